"""``cdpr interference`` and the interference keys and columns of ``point``, ``compensate`` and
``grid --interference`` (issue 39): the JSON keys and table columns the issue names, spelled as
it spells them."""

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from cdpr.cli.main import main
from cdpr.models.interference import COLUMNS
from tests.conftest import ROBOTS

ROOT = Path(__file__).resolve().parents[2]
WALL = str(ROOT / "tests" / "data" / "wall_crossed.yaml")
COGIRO = str(ROBOTS / "cogiro_massless.yaml")
R4 = str(ROBOTS / "cdpr4.yaml")
KEYS = {
    "interference_free",
    "cable_cable",
    "shared",
    "cable_platform",
    "dmin_m",
    "dmin_pair",
    "warnings",
    "status",
}


def run_json(capsys, *args):
    assert main(list(args) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_json_of_the_wall_robot_at_home_with_fixed_pulleys(capsys):
    out = run_json(capsys, "interference", "--robot", WALL, "--pulley", "fixed", "--at", "0", "0", "1.5")
    assert set(out) == KEYS
    assert out["interference_free"] is False
    pairs = [c["cables"] for c in out["cable_cable"]]
    assert pairs == [[1, 4], [2, 3], [5, 6], [5, 8], [6, 7], [7, 8]]
    for c in out["cable_cable"]:
        assert set(c) == {"cables", "distance_m", "s"} and c["distance_m"] < 1e-12 and len(c["s"]) == 2
    assert out["shared"] == [] and out["cable_platform"] == []
    assert out["dmin_m"] < 1e-12 and out["dmin_pair"] in pairs


def test_text_of_a_point_mass_lists_the_shared_pairs(capsys):
    assert main(["interference", "--robot", R4, "--at", "0", "0", "1"]) == 0
    text = capsys.readouterr().out
    assert "interference-free: yes" in text and "1-2 at B" in text and "3-4 at B" in text
    out = run_json(capsys, "interference", "--robot", R4, "--at", "0", "0", "1")
    assert out["shared"][0] == {"cables": [1, 2], "at": "B"} and len(out["shared"]) == 6
    assert out["dmin_m"] is None and out["dmin_pair"] is None


def test_cable_platform_keys(capsys):
    """The wall robot at the issue's desired pose: cable 6, from a bottom corner almost
    horizontally across the tilted box of the attachments, runs through the platform."""
    out = run_json(
        capsys, "interference", "--robot", WALL, "--at", "0.3", "0.3", "0.7", "--rotvec", "0.12", "0.12", "0"
    )
    assert [c["cable"] for c in out["cable_platform"]] == [6]
    c = out["cable_platform"][0]
    assert set(c) == {"cable", "length_m", "depth_m", "s_in", "s_out"}
    assert c["s_in"] == 0.0 and 0 < c["s_out"] < 1 and c["length_m"] > 0 and c["depth_m"] > 1e-9


def test_table_of_poses(tmp_path, capsys):
    points = tmp_path / "p.csv"
    pd.DataFrame(
        {
            "x": [0, 0.3, 1],
            "y": [0, 0.3, 1],
            "z": [1.5, 0.7, 2],
            "rx": [0, 0.12, 0],
            "ry": [0, 0.12, 0],
            "rz": [0, 0, 0.3],
        }
    ).to_csv(points, index=False)
    out = tmp_path / "o.csv"
    assert main(["interference", "--robot", WALL, "--points", str(points), "--out", str(out)]) == 0
    assert "wrote 3 poses" in capsys.readouterr().out
    df = pd.read_csv(out, keep_default_na=False)
    assert list(df.columns) == ["x", "y", "z", "rx", "ry", "rz", *COLUMNS]
    assert list(COLUMNS) == ["interference_free", "n_cc", "n_cp", "dmin_m", "cc_pairs", "cp_cables"]
    assert df["cc_pairs"][0] == "1-4;2-3;5-6;5-8;6-7;7-8" and df["n_cc"][0] == 6
    assert df["cp_cables"][1] == "6" and df["n_cp"][1] == 1 and df["cc_pairs"][1] == ""
    assert df["interference_free"].tolist() == [False, False, True] and df["cp_cables"][2] == ""
    # the same poses one at a time agree with the table
    for k in range(3):
        row = df.iloc[k]
        args = ["--at", *map(str, row[["x", "y", "z"]]), "--rotvec", *map(str, row[["rx", "ry", "rz"]])]
        one = run_json(capsys, "interference", "--robot", WALL, *args)
        assert one["interference_free"] == row["interference_free"]
        assert one["dmin_m"] == pytest.approx(row["dmin_m"], rel=1e-9)


def test_points_need_out(tmp_path, capsys):
    points = tmp_path / "p.csv"
    points.write_text("x,y,z\n0,0,1\n")
    assert main(["interference", "--robot", WALL, "--points", str(points)]) == 2
    assert "--points needs --out" in capsys.readouterr().err


def test_point_and_compensate_report_interference_free(capsys):
    """point: at the solved pose (the flipped equilibrium of the issue's example has cables 5-6 and
    7-8 closer than their diameter); compensate: at the desired pose."""
    lengths = "6.52907908125 6.14882031715 5.85918529262 6.26397544351 6.06888687927 5.63634727396 5.23674973794 5.70862689323"
    args = ["--robot", WALL, "--at", "0.3", "0.3", "0.7", "--rotvec", "0.12", "0.12", "0"]
    out = run_json(capsys, "point", *args, "--lengths", *lengths.split())
    assert out["interference_free"] is True  # the reached equilibrium (issue 39) interferes nowhere
    out = run_json(capsys, "point", *args, "--lengths", *lengths.split(), "--equilibrium", "global")
    assert out["interference_free"] is False
    solved = run_json(
        capsys,
        "interference",
        "--robot",
        WALL,
        "--at",
        *map(str, out["solved"]),
        "--rotvec",
        *map(str, out["solved_rotvec"]),
    )
    assert solved["interference_free"] is False
    comp = run_json(capsys, "compensate", "--robot", COGIRO, "--at", "0", "0", "2")
    assert comp["interference_free"] is True
    comp = run_json(capsys, "compensate", "--robot", R4, "--at", "0", "0", "2")
    assert comp["interference_free"] is True  # a point mass never interferes


def test_grid_interference_columns(tmp_path, capsys):
    out = tmp_path / "g.csv"
    args = ["grid", "--robot", COGIRO, "--frame", "--n", "3", "--rotvec", "0", "0", "0.5", "--interference"]
    s = run_json(capsys, *args, "--out", str(out))
    df = pd.read_csv(out, keep_default_na=False)
    assert list(df.columns[-6:]) == list(COLUMNS)
    assert s["interference_free_points"] == int(df["interference_free"].sum())
    assert ((df["n_cc"] > 0) == (df["cc_pairs"] != "")).all()
    assert ((df["n_cp"] > 0) == (df["cp_cables"] != "")).all()
    assert (df["interference_free"] == ((df["n_cc"] == 0) & (df["n_cp"] == 0))).all()
    assert np.isfinite(df["dmin_m"]).all()
    assert main([*args, "--out", str(out)]) == 0
    assert f"interference-free: {s['interference_free_points']} of 27 grid points" in capsys.readouterr().out


@pytest.mark.parametrize("name", sorted(p.name for p in ROBOTS.glob("*.yaml")))
def test_every_shipped_robot(capsys, name):
    """The command runs on every shipped robot at its view position; a point mass lists every pair
    as shared at B and tests none; a rigid platform tests the pairs it does not list as shared."""
    from cdpr.analyses.scans import view_position
    from cdpr.robot import load_robot

    robot = load_robot(ROBOTS / name)
    p = view_position(robot)
    out = run_json(capsys, "interference", "--robot", str(ROBOTS / name), "--at", *map(str, p))
    # heavy cables of a rigid platform are drawn under rest lengths: the JSON says which (docs/cli.md)
    heavy = robot.heavy and not robot.point_mass
    assert set(out) == KEYS | ({"lengths", "lengths_from"} if heavy else set())
    if heavy:
        assert out["lengths_from"] == "compensated" and len(out["lengths"]) == robot.m
    m = robot.m
    if robot.point_mass:
        assert (
            len(out["shared"]) == m * (m - 1) // 2 and out["dmin_pair"] is None and out["interference_free"]
        )
    else:
        assert out["dmin_m"] >= 0 and out["dmin_pair"][0] < out["dmin_pair"][1]


@pytest.mark.parametrize("name", sorted(p.name for p in ROBOTS.glob("*.yaml")))
def test_point_compensate_and_grid_on_every_shipped_robot(tmp_path, capsys, name):
    """Issue 39's Done-when, "the commands work on every shipped robot": at its view position,
    physical mode's ``point --json`` answers with the reached equilibrium beside the global one
    (the issue's keys), ``compensate --json`` says ``interference_free``, and ``grid --interference``
    ends with the six columns, each an answer (no blank) where the pose is solved."""
    from cdpr.analyses.scans import view_position
    from cdpr.robot import load_robot

    path = str(ROBOTS / name)
    robot = load_robot(path)
    at = [str(float(v)) for v in view_position(robot)]
    pt = run_json(capsys, "point", "--robot", path, "--at", *at, "--redundancy", "physical", "--quiet")
    obj = {"solved", "energy_J", "taut", "tensions", "interference_free", "status"}
    obj |= set() if robot.point_mass else {"solved_rotvec"}
    assert obj <= set(pt["global"]) and obj | {"folds", "start"} <= set(pt["reached"])
    assert pt["equilibrium"] == "reached" and pt["solved"] == pt["reached"]["solved"]
    assert isinstance(pt["reached_is_global"], bool) and isinstance(pt["interference_free"], bool)
    comp = run_json(capsys, "compensate", "--robot", path, "--at", *at, "--quiet")
    assert isinstance(comp["interference_free"], bool)
    out = tmp_path / "g.csv"
    grid = ["grid", "--robot", path, "--frame", "--n", "2", "--interference", "--out", str(out), "--quiet"]
    assert main(grid + ["--redundancy", "physical"]) == 0
    df = pd.read_csv(out, keep_default_na=False)
    assert list(df.columns[-6:]) == list(COLUMNS) and len(df) == 8
    assert (df["interference_free"].astype(str) != "").all()


def test_unsolved_point_has_no_interference_answer(capsys):
    out = run_json(capsys, "point", "--robot", R4, "--at", "0", "0", "9")  # above the pulleys
    assert out["status"] == "inaccessible" and out["interference_free"] is None


def _points(tmp_path, rows):
    path = tmp_path / "p.csv"
    pd.DataFrame(rows, columns=["x", "y", "z", "rx", "ry", "rz"]).to_csv(path, index=False)
    return str(path)


def _check_at_solved_poses(capsys, robot, df, *extra):
    """Each row's interference columns are ``cdpr interference``'s at the row's solved pose."""
    assert list(df.columns[-6:]) == list(COLUMNS)
    for _, row in df.iterrows():
        at = [
            "--at",
            *(repr(float(v)) for v in row[["x_s", "y_s", "z_s"]]),
            "--rotvec",
            *(repr(float(v)) for v in row[["rx_s", "ry_s", "rz_s"]]),
        ]
        one = run_json(capsys, "interference", "--robot", robot, *extra, *at)
        assert one["interference_free"] == bool(row["interference_free"])
        assert row["n_cc"] == len(one["cable_cable"]) and row["n_cp"] == len(one["cable_platform"])
        assert row["cc_pairs"] == ";".join(f"{i}-{j}" for i, j in (c["cables"] for c in one["cable_cable"]))
        assert row["cp_cables"] == ";".join(str(c["cable"]) for c in one["cable_platform"])
        assert row["dmin_m"] == pytest.approx(one["dmin_m"], rel=1e-12, abs=1e-15)


def test_point_table_has_the_columns_at_the_solved_poses(tmp_path, capsys):
    """The wall robot at home (crossing pairs) and at the issue's tilted pose (cable 6 through the
    platform): ``point --points`` carries the columns of ``interference`` at the solved poses."""
    pts = _points(
        tmp_path, [[0, 0, 1.5, 0, 0, 0], [0.3, 0.3, 0.7, 0.12, 0.12, 0], [0.5, -0.4, 1.2, 0, 0, 0.2]]
    )
    out = tmp_path / "o.parquet"
    assert main(["point", "--robot", WALL, "--pulley", "fixed", "--points", pts, "--out", str(out)]) == 0
    capsys.readouterr()
    df = pd.read_parquet(out)
    assert (df["status"] == "ok").all()
    assert (df[["x_s", "y_s", "z_s"]].to_numpy() != df[["x", "y", "z"]].to_numpy()).any(axis=1).all()
    _check_at_solved_poses(capsys, WALL, df, "--pulley", "fixed")
    assert not df["interference_free"][0] and df["n_cc"][0] > 0


def test_point_table_tests_the_equilibrium_it_reports(tmp_path, capsys):
    """The issue's example in a table: the reached equilibrium interferes nowhere, the global one
    (the flipped platform) has cables 5-6 and 7-8 closer than their diameter."""
    lengths = "6.52907908125 6.14882031715 5.85918529262 6.26397544351 6.06888687927 5.63634727396 5.23674973794 5.70862689323"
    pts = _points(tmp_path, [[0.3, 0.3, 0.7, 0.12, 0.12, 0]])
    got = {}
    for eq in ("reached", "global"):
        out = tmp_path / f"{eq}.parquet"
        args = ["point", "--robot", WALL, "--points", pts, "--out", str(out), "--lengths", *lengths.split()]
        assert main([*args, "--equilibrium", eq]) == 0
        got[eq] = pd.read_parquet(out).iloc[0]
    assert bool(got["reached"]["interference_free"]) is True and got["reached"]["cc_pairs"] == ""
    assert bool(got["global"]["interference_free"]) is False
    assert {"5-6", "7-8"} <= set(got["global"]["cc_pairs"].split(";"))


def test_compensate_table_has_the_columns_and_no_answer_where_infeasible(tmp_path, capsys):
    """CoGiRo: two feasible poses (one rotated 0.5 rad about z, where a cable runs through the platform) and
    one far outside the frame (infeasible: no pose solved, the columns empty)."""
    pts = _points(tmp_path, [[0, 0, 2, 0, 0, 0], [-3, 2, 1.5, 0, 0, 0.5], [40, 0, 2, 0, 0, 0]])
    out = tmp_path / "c.parquet"
    assert main(["compensate", "--robot", COGIRO, "--points", pts, "--out", str(out)]) == 0
    capsys.readouterr()
    df = pd.read_parquet(out)
    assert df["status"].tolist()[2] == "infeasible" and df["status"].tolist()[:2] == ["ok", "ok"]
    assert pd.isna(df["interference_free"][2]) and pd.isna(df["n_cc"][2]) and pd.isna(df["dmin_m"][2])
    assert df["cc_pairs"][2] == "" and not df["interference_free"][1]
    _check_at_solved_poses(capsys, COGIRO, df.iloc[:2])


def _heavy_wall(tmp_path):
    import yaml

    data = yaml.safe_load(Path(WALL).read_text())
    data["cable"]["linear_density_kg_m"] = 0.5
    path = tmp_path / "wall_heavy.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


def test_heavy_compensate_table_tests_the_catenaries(tmp_path, capsys):
    """Heavy cables: the columns are the catenaries' polylines' under the compensated lengths at the
    solved poses; ``cdpr interference`` tests the desired pose under the same compensated lengths
    (tests/cli/test_interference_heavy.py)."""
    from cdpr.models.interference import columns, interference
    from cdpr.robot import load_robot

    heavy = _heavy_wall(tmp_path)
    pts = _points(tmp_path, [[0, 0, 1.5, 0, 0, 0], [0.3, 0.3, 0.7, 0.12, 0.12, 0]])
    out = tmp_path / "c.parquet"
    assert main(["compensate", "--robot", heavy, "--points", pts, "--out", str(out)]) == 0
    df = pd.read_parquet(out)
    assert list(df.columns[-6:]) == list(COLUMNS) and (df["status"] == "ok").all()
    robot = load_robot(heavy)
    L0 = df[[f"L0_{i + 1}" for i in range(robot.m)]].to_numpy()
    res = interference(
        robot, df[["x_s", "y_s", "z_s"]].to_numpy(), df[["rx_s", "ry_s", "rz_s"]].to_numpy(), L0=L0
    )
    assert res.pieces > 1
    want = columns(res)
    assert df["interference_free"].tolist() == want["interference_free"].tolist() == [False, False]
    assert df["cc_pairs"].tolist() == list(want["cc_pairs"]) and df["cp_cables"].tolist() == list(
        want["cp_cables"]
    )
    np.testing.assert_allclose(df["dmin_m"], want["dmin_m"], rtol=1e-12, atol=1e-15)
    capsys.readouterr()
    out = run_json(capsys, "interference", "--robot", heavy, "--at", "0", "0", "1.5")
    assert out["lengths_from"] == "compensated" and out["lengths"] == L0[0].tolist()
