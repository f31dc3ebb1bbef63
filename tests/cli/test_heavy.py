"""The command line with heavy cables (issue 38): ``compensate --json``'s lengths, tensions (at B)
and per-cable ``cables`` objects; ``point --redundancy physical --lengths`` reaching the
compensated pose from elsewhere with tensions at B and D and sags; the result tables' sag_max_m;
``inverse`` keeping the massless geometry with one line on stderr, or the catenaries under
``--tensions``; and w = 0 byte-identical to the massless robot's output."""

import contextlib
import io
import json

import numpy as np
import pandas as pd
import pytest
import yaml

from cdpr.cli.main import main
from tests.conftest import ROBOTS

R4 = str(ROBOTS / "cdpr4.yaml")
RC = str(ROBOTS / "cogiro_massless.yaml")
HEAVY = ["--linear-density", "0.0631"]
CABLE_KEYS = ["tension_B_N", "tension_D_N", "H_N", "sag_m", "arc_minus_chord_m", "angle_f_deg", "status"]
AT = ["0.3", "-0.5", "2.0"]


def run_json(capsys, *args):
    assert main(list(args) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def heavy_file(tmp_path, robot=R4, rho=0.0631):
    d = yaml.safe_load(open(robot).read())
    d["cable"]["linear_density_kg_m"] = rho
    p = tmp_path / f"heavy_{rho}.yaml"
    p.write_text(yaml.safe_dump(d))
    return str(p)


@pytest.fixture(scope="module")
def comp4():

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["compensate", "--robot", R4, *HEAVY, "--at", *AT, "--json"]) == 0
    return json.loads(buf.getvalue())


def test_compensate_json_keys_point_mass(comp4):
    assert list(comp4["cables"][0]) == CABLE_KEYS and len(comp4["cables"]) == 4
    assert len(comp4["lengths"]) == 4 and comp4["status"] == "ok"
    np.testing.assert_allclose([c["tension_B_N"] for c in comp4["cables"]], comp4["tensions"], rtol=1e-10)
    for c in comp4["cables"]:
        assert c["status"] == "catenary" and c["sag_m"] > 1e-4 and c["tension_D_N"] > c["tension_B_N"]
        assert 0 < c["H_N"] < c["tension_B_N"] and c["angle_f_deg"] > 0 and c["arc_minus_chord_m"] > 0
    assert comp4["distribution_iterations"] >= 2


def test_point_reaches_the_compensated_pose_from_elsewhere(capsys, comp4):
    lengths = [str(v) for v in comp4["lengths"]]
    out = run_json(
        capsys, "point", "--robot", R4, *HEAVY, "--at", "0.33", "-0.46", "2.04",
        "--redundancy", "physical", "--lengths", *lengths,
    )  # fmt: skip
    assert out["status"] == "ok"
    assert np.abs(np.array(out["solved"]) - [0.3, -0.5, 2.0]).max() <= 1e-9
    np.testing.assert_allclose(out["tensions"], comp4["tensions"], rtol=1e-8)
    np.testing.assert_allclose(out["tensions_D"], [c["tension_D_N"] for c in comp4["cables"]], rtol=1e-8)
    np.testing.assert_allclose(out["sag_m"], [c["sag_m"] for c in comp4["cables"]], rtol=1e-6)


def test_compensate_json_keys_rigid_platform_cogiro(capsys):
    out = run_json(capsys, "compensate", "--robot", RC, *HEAVY, "--at", "1", "1", "1.5")
    assert len(out["cables"]) == 8 and all(list(c) == CABLE_KEYS for c in out["cables"])
    assert out["status"] == "ok" and out["dp_norm"] <= 1e-9 and out["dphi"] <= 1e-9
    assert 0.02 < max(c["sag_m"] for c in out["cables"]) < 0.06  # CoGiRo's cables sag by centimetres
    massless = run_json(capsys, "compensate", "--robot", RC, "--at", "1", "1", "1.5")
    assert "cables" not in massless
    assert np.abs(np.array(out["lengths"]) - massless["lengths"]).max() > 1e-6


def test_heavy_cables_default_to_the_compiled_engine(capsys):
    """One heavy pose is solved by the compiled engine unless --engine names one (the numpy
    reference costs seconds per heavy pose: ``cli.heavy.one_shot``); the numpy reference gives the
    same equilibrium, reached and global, to 1e-9 m and rad."""
    args = ["point", "--robot", RC, *HEAVY, "--at", "1", "1", "1.5"]
    got = run_json(capsys, *args)
    ref = run_json(capsys, *args, "--engine", "numpy")
    assert (got["engine"], ref["engine"]) == ("compiled", "numpy")
    assert got["status"] == ref["status"] == "ok" and got["taut"] == ref["taut"]
    for key in ("solved", "solved_rotvec"):
        np.testing.assert_allclose(got[key], ref[key], rtol=0, atol=1e-9)
        np.testing.assert_allclose(got["reached"][key], ref["reached"][key], rtol=0, atol=1e-9)
    np.testing.assert_allclose(got["tensions"], ref["tensions"], rtol=1e-8)
    np.testing.assert_allclose(got["sag_m"], ref["sag_m"], rtol=1e-8)
    comp = run_json(capsys, "compensate", "--robot", RC, *HEAVY, "--at", "1", "1", "1.5")
    assert comp["engine"] == "compiled" and comp["dp_norm"] <= 1e-9
    # heavy sensitivities are the numpy reference's whatever the engine: the JSON says so
    sens = run_json(capsys, *args, "--sensitivities")
    assert sens["engine"] == "numpy" and "rho_1" in sens["sensitivities"]


def test_point_table_has_sag_max(tmp_path, capsys):
    pts = tmp_path / "p.csv"
    pd.DataFrame({"x": [0.3, 1.0], "y": [-0.5, 0.5], "z": [2.0, 3.0]}).to_csv(pts, index=False)
    base = ["point", "--robot", R4, "--points", str(pts), "--redundancy", "physical"]
    assert main([*base, *HEAVY, "--out", str(tmp_path / "h.csv")]) == 0
    assert main([*base, "--out", str(tmp_path / "m.csv")]) == 0
    capsys.readouterr()
    h, m = pd.read_csv(tmp_path / "h.csv"), pd.read_csv(tmp_path / "m.csv")
    assert "sag_max_m" in h and "sag_max_m" not in m
    assert (h["sag_max_m"] > 1e-4).all() and list(h.columns[:-1]) == list(m.columns)


def test_inverse_keeps_the_massless_geometry_with_one_line(tmp_path, capsys):
    heavy = heavy_file(tmp_path)
    assert main(["inverse", "--robot", R4, "--at", *AT, "--json"]) == 0
    plain = capsys.readouterr().out
    assert main(["inverse", "--robot", heavy, "--at", *AT, "--json"]) == 0
    cap = capsys.readouterr()
    assert cap.out == plain and isinstance(json.loads(cap.out), list)
    err = cap.err.strip()
    assert "\n" not in err and "massless geometry" in err and "--tensions" in err


def test_inverse_tensions_gives_the_compensated_lengths(tmp_path, capsys, comp4):
    heavy = heavy_file(tmp_path)
    out = run_json(
        capsys, "inverse", "--robot", heavy, "--at", *AT, "--tensions", *map(str, comp4["tensions"])
    )
    assert isinstance(out, list) and len(out) == 4
    np.testing.assert_allclose([c["L0"] for c in out], comp4["lengths"], rtol=0, atol=1e-9)
    np.testing.assert_allclose([c["sag_m"] for c in out], [c["sag_m"] for c in comp4["cables"]], rtol=1e-6)


def test_inverse_tensions_refuses_a_wrong_count(capsys):
    assert main(["inverse", "--robot", R4, "--at", *AT, "--tensions", "100", "200"]) == 2
    assert "one tension per cable (4)" in capsys.readouterr().err


@pytest.mark.parametrize(
    "args",
    [
        ["inverse", "--at", *AT],
        ["point", "--at", *AT, "--redundancy", "physical", "--lengths", "8.6", "8.3", "8.8", "9.1"],
        ["compensate", "--at", *AT],
        ["compensate", "--at", "1", "1", "1.5"],
    ],
)
def test_zero_density_is_byte_identical(tmp_path, capsys, args):
    robot = RC if args[-1] == "1.5" else R4
    cmd = [args[0], "--robot"]
    assert main([*cmd, robot, *args[1:], "--json"]) == 0
    plain = capsys.readouterr().out
    assert main([*cmd, heavy_file(tmp_path, robot, 0.0), *args[1:], "--json"]) == 0
    assert capsys.readouterr().out == plain
