"""``cdpr grid``, ``plane`` and ``trajectory`` with heavy cables (issue 38): the tables are the
library's physical-mode solve under L_TS at each desired pose (the large study's maps and paths),
with ``sag_max_m``; they agree with the numpy reference and with ``cdpr point`` at the same points;
w -> 0 is the massless table; w = 0 is byte-identical; what still refuses heavy cables does so in
one line."""

import json

import numpy as np
import pandas as pd
import pytest
import yaml

from cdpr.analyses.compensation import heavy_distribution
from cdpr.cli.main import main
from cdpr.models.platform import pose_arrays
from cdpr.robot import load_robot
from cdpr.solve import solve
from tests.conftest import ROBOTS

CUBE = str(ROBOTS / "cube50.yaml")  # heavy 4 mm cables, 0.0631 kg/m
RC = str(ROBOTS / "cogiro_massless.yaml")  # massless in its file; heavy with --linear-density
R4 = str(ROBOTS / "cdpr4.yaml")
RHO = ["--linear-density", "0.0631"]
PHYS = ["--redundancy", "physical"]

#: (robot file, extra options, command arguments): heavy scans of a point mass and a rigid platform.
SCANS = {
    "plane-cube50": (CUBE, PHYS, ["plane", "--z", "25", "--n", "3"]),
    "trajectory-cube50": (CUBE, PHYS, ["trajectory", "--start", "-20", "0", "5", "--end", "20", "0", "40", "--n", "3"]),
    "grid-cube50": (CUBE, PHYS, ["grid", "--box", "-20", "20", "-20", "20", "5", "40", "--n", "2"]),
    "plane-cogiro": (RC, RHO, ["plane", "--z", "1.5", "--n", "2"]),
    "trajectory-cogiro": (RC, RHO, ["trajectory", "--start", "-2", "0", "1", "--end", "2", "1", "2.5", "--n", "3"]),
    "grid-cogiro": (RC, RHO, ["grid", "--box", "-2", "2", "-1", "1", "1", "2.5", "--n", "2"]),
}  # fmt: skip


def run(tmp_path, capsys, robot, extra, args, name="t.csv"):
    out = tmp_path / name
    assert main([args[0], "--robot", robot, *args[1:], *extra, "--out", str(out)]) == 0
    capsys.readouterr()
    return pd.read_csv(out)


@pytest.mark.parametrize("key", SCANS)
def test_heavy_table_is_the_library_solve(tmp_path, capsys, key):
    """Each row is the physical equilibrium of the heavy robot under L_TS at its desired pose: the
    numpy reference's (``solve.solve``, engine numpy) to 1e-9 m and rad, the same statuses, and the
    sag_max_m of the reference's catenaries; every cable sags (w > 0)."""
    robot_file, extra, args = SCANS[key]
    df = run(tmp_path, capsys, robot_file, extra, args)
    robot = load_robot(robot_file, linear_density=0.0631)
    assert (
        robot.heavy
        and "sag_max_m" in df
        and list(df.columns).index("sag_max_m") == list(df.columns).index("status") + 1
    )
    P = df[["x", "y", "z"]].to_numpy()
    ref = solve(robot, P, redundancy="physical", engine="numpy")
    assert df["status"].tolist() == list(ref["status"])
    ok = (df["status"] == "ok").to_numpy()
    assert ok.sum() >= 2
    np.testing.assert_allclose(df[["x_s", "y_s", "z_s"]].to_numpy()[ok], ref["P_s"][ok], rtol=0, atol=1e-9)
    np.testing.assert_allclose(df["sag_max_m"].to_numpy()[ok], ref["sag_max"][ok], rtol=1e-6, atol=1e-12)
    assert (df["sag_max_m"][ok] > 1e-4).all()
    t = df[[f"t{i + 1}" for i in range(robot.m)]].to_numpy()
    np.testing.assert_allclose(t[ok], ref["t"][ok], rtol=1e-7)
    if not robot.point_mass:
        np.testing.assert_allclose(
            df[["rx_s", "ry_s", "rz_s"]].to_numpy()[ok], ref["rotvec_s"][ok], rtol=0, atol=1e-9
        )


@pytest.mark.parametrize("key", ["plane-cube50", "trajectory-cogiro"])
def test_heavy_table_agrees_with_point(tmp_path, capsys, key):
    """``cdpr point --at`` at a table's point (physical mode, L_TS) gives the table's pose, |dp| and
    the largest of its cables' sags."""
    robot_file, extra, args = SCANS[key]
    df = run(tmp_path, capsys, robot_file, extra, args)
    row = df[df["status"] == "ok"].iloc[-1]
    at = [repr(float(row[k])) for k in ("x", "y", "z")]
    assert main(["point", "--robot", robot_file, *extra, *PHYS, "--at", *at, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "ok" and out["engine"] == "compiled"
    np.testing.assert_allclose(out["solved"], row[["x_s", "y_s", "z_s"]].to_numpy(float), rtol=0, atol=1e-9)
    assert out["dp_norm"] == pytest.approx(row["dp"], abs=1e-9)
    assert max(out["sag_m"]) == pytest.approx(row["sag_max_m"], rel=1e-6)


@pytest.mark.parametrize("key", ["plane-cube50", "trajectory-cube50", "grid-cogiro"])
def test_vanishing_density_is_the_massless_table(tmp_path, capsys, key):
    """w = 1e-9 kg/m through the catenary: the massless table (w = 0) to 1e-9 m and rad, the same
    statuses and taut sets, the tensions to 1e-7, and sags below a micrometre."""
    robot_file, _, args = SCANS[key]
    tiny = run(tmp_path, capsys, robot_file, [*PHYS, "--linear-density", "1e-9"], args, "tiny.csv")
    zero = run(tmp_path, capsys, robot_file, [*PHYS, "--linear-density", "0"], args, "zero.csv")
    assert [c for c in tiny.columns if c not in ("sag_max_m", "n_holding")] == list(zero.columns)
    assert "sag_max_m" not in zero and (tiny["sag_max_m"] < 1e-6).all()
    if "rx_s" in zero:  # a rigid platform's heavy table counts the holding cables: at 1e-9 kg/m none hangs
        assert "n_holding" not in zero and (tiny["n_holding"] == tiny["n_taut"]).all()
    assert (
        tiny["status"].tolist() == zero["status"].tolist() and tiny["taut"].tolist() == zero["taut"].tolist()
    )
    ok = (zero["status"] == "ok").to_numpy()
    cols = ["x_s", "y_s", "z_s", "dp"] + ([] if "rx_s" not in zero else ["rx_s", "ry_s", "rz_s", "dphi"])
    np.testing.assert_allclose(tiny[cols].to_numpy()[ok], zero[cols].to_numpy()[ok], rtol=0, atol=1e-9)
    t = [c for c in zero.columns if c[0] == "t" and c[1:].isdigit()]
    np.testing.assert_allclose(tiny[t].to_numpy()[ok], zero[t].to_numpy()[ok], rtol=1e-7)


def _zero_file(tmp_path, robot):
    d = yaml.safe_load(open(robot).read())
    d["cable"]["linear_density_kg_m"] = 0.0
    p = tmp_path / "w0.yaml"
    p.write_text(yaml.safe_dump(d))
    return str(p)


@pytest.mark.parametrize(
    "robot, args",
    [
        (R4, ["grid", "--box", "-1", "1", "-1", "1", "0.5", "2.5", "--n", "3"]),
        (R4, ["plane", "--z", "2.5", "--n", "4", *PHYS]),
        (R4, ["trajectory", "--start", "-2.5", "0", "0", "--end", "2.5", "0", "5", "--n", "7"]),
        (RC, ["grid", "--frame", "--n", "2", "--wrench-feasible"]),
        (RC, ["plane", "--z", "1.5", "--n", "3"]),
        (RC, ["trajectory", "--start", "-3", "0", "0.5", "--end", "3", "0", "2.5", "--n", "4"]),
    ],
)
def test_zero_density_is_byte_identical(tmp_path, capsys, robot, args):
    """cable.linear_density_kg_m: 0 writes the same bytes as the file without the key."""
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    assert main([args[0], "--robot", robot, *args[1:], "--out", str(a)]) == 0
    assert main([args[0], "--robot", _zero_file(tmp_path, robot), *args[1:], "--out", str(b)]) == 0
    capsys.readouterr()
    assert a.read_bytes() == b.read_bytes()


def test_heavy_wrench_feasible_is_the_sag_consistent_distribution(tmp_path, capsys):
    """grid --wrench-feasible with heavy cables: a sag-consistent distribution (tensions at B in
    [--t-min, T_a]) holds the platform (``compensation.heavy_distribution``); with w -> 0 the massless
    distribution's feasibility."""
    box = ["grid", "--frame", "--n", "3", "--wrench-feasible", "--t-min", "100"]
    df = run(tmp_path, capsys, RC, RHO, box)
    robot = load_robot(RC, linear_density=0.0631)
    p, R = pose_arrays(df[["x", "y", "z"]].to_numpy(), None)
    want = heavy_distribution(robot, p, R, t_min=100.0)["feasible"]
    assert df["feasible"].tolist() == list(want) and 0 < df["feasible"].sum() < len(df)
    tiny = run(tmp_path, capsys, RC, ["--linear-density", "1e-9"], box, "tiny.csv")
    zero = run(tmp_path, capsys, RC, [], box, "zero.csv")
    assert tiny["feasible"].tolist() == zero["feasible"].tolist()


@pytest.mark.parametrize(
    "args, words",
    [
        (["grid", "--robot", CUBE, "--frame", "--n", "2"], "physical mode only"),
        (["plane", "--robot", CUBE, "--z", "25", "--n", "2"], "physical mode only"),
        (
            ["trajectory", "--robot", CUBE, "--start", "0", "0", "5", "--end", "0", "0", "9", "--n", "2"],
            "physical mode only",
        ),
    ],
)
def test_what_is_not_modelled_is_refused_in_one_line(tmp_path, capsys, args, words):
    """Paper mode asked for refuses heavy cables in one line, before writing anything; left out,
    a heavy robot's mode is physical (``Robot.default_redundancy``), and the command runs."""
    out = tmp_path / "x.csv"
    assert main([*args, *RHO, "--redundancy", "paper", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and words in err and not out.exists()
    assert main([*args, *RHO, "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert len(df) > 0 and "sag_max_m" in df.columns and (df["sag_max_m"] > 0).any()  # heavy, physical
