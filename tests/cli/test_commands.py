"""The four commands on the shipped robot files, JSON keys, overrides, clean errors."""

import json

import numpy as np
import pandas as pd
import pytest

from cdpr.cli.main import main
from tests.conftest import ROBOTS

R4 = str(ROBOTS / "cdpr4.yaml")
R3 = str(ROBOTS / "cdpr3.yaml")


def run_json(capsys, *args):
    assert main(list(args) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_inverse_json(capsys):
    out = run_json(capsys, "inverse", "--robot", R4, "--at", "0.5", "0.2", "2.5")
    assert len(out) == 4
    assert set(out[0]) >= {"L_TS", "L_TE", "gamma", "l_d", "l_E", "D", "H", "K", "alpha", "beta", "inside"}
    assert len(out[0]["D"]) == 3
    fixed = run_json(capsys, "inverse", "--robot", R4, "--pulley", "fixed", "--at", "0.5", "0.2", "2.5")
    assert all(abs(c["L_TE"] - c["L_TS"]) < 1e-12 for c in fixed)


def test_point_json(capsys):
    out = run_json(capsys, "point", "--robot", R4, "--pulley", "DR", "--at", "0.5", "0.2", "2.5")
    assert set(out) == {
        "desired",
        "solved",
        "dp_norm",
        "tensions",
        "subset",
        "status",
        "iterations",
        "engine",
        "interference_free",
        "warnings",
    }
    assert out["warnings"] == []  # CDPR4 is plausible (cdpr.plausibility.plausibility_warnings)
    assert out["engine"] == "numpy"  # one pose: the numpy reference unless --engine names one
    assert out["status"] == "ok" and len(out["subset"]) == 3 and min(out["subset"]) >= 1
    assert sum(t is None for t in out["tensions"]) == 1
    assert out["dp_norm"] == pytest.approx(np.linalg.norm(np.subtract(out["solved"], out["desired"])))
    fp = run_json(
        capsys,
        "point",
        "--robot",
        R4,
        "--pulley",
        "DR",
        "--method",
        "fixed_point",
        "--at",
        "0.5",
        "0.2",
        "2.5",
    )
    assert abs(fp["dp_norm"] - out["dp_norm"]) < 5e-5


@pytest.mark.parametrize("extra", [[], ["--redundancy", "physical"]])
def test_point_one_pose_engines_agree(capsys, extra):
    """One pose defaults to the numpy reference (solve.ONE_SHOT_POSES); --engine compiled gives the
    same status, subset or taut set, and pose to 1e-9 m."""
    args = ["point", "--robot", R4, "--at", "0.5", "0.2", "2.5", *extra]
    ref = run_json(capsys, *args)
    fast = run_json(capsys, *args, "--engine", "compiled")
    assert (ref["engine"], fast["engine"]) == ("numpy", "compiled")
    assert ref["status"] == fast["status"] == "ok"
    assert ref.get("subset") == fast.get("subset") and ref.get("taut") == fast.get("taut")
    assert np.allclose(ref["solved"], fast["solved"], rtol=0, atol=1e-9)
    assert ref["solved"] != ref["desired"]


def test_point_overrides_change_the_answer(capsys):
    base = run_json(capsys, "point", "--robot", R3, "--at", "0", "0", "2")
    stiff = run_json(
        capsys, "point", "--robot", R3, "--pulley", "fixed", "--E", "1e20", "--at", "0", "0", "2"
    )
    assert stiff["dp_norm"] < 1e-9 < base["dp_norm"]


@pytest.mark.parametrize("ext", ["parquet", "csv"])
def test_grid_writes_one_row_per_point(tmp_path, capsys, ext):
    out = tmp_path / f"g.{ext}"
    summary = run_json(
        capsys,
        "grid",
        "--robot",
        R4,
        "--box",
        "-2",
        "2",
        "-2",
        "2",
        "0.5",
        "4",
        "--n",
        "4",
        "--out",
        str(out),
    )
    df = pd.read_parquet(out) if ext == "parquet" else pd.read_csv(out)
    assert len(df) == 64 == summary["points"]
    assert list(df.columns) == [
        "x",
        "y",
        "z",
        "x_s",
        "y_s",
        "z_s",
        "dp",
        "t1",
        "t2",
        "t3",
        "t4",
        "subset",
        "n_taut",
        "iterations",
        "status",
    ]
    assert sorted(set(df.x)) == pytest.approx([-1.5, -0.5, 0.5, 1.5])  # cell centres


def test_grid_shards_concatenate_to_the_whole(tmp_path, capsys):
    args = ["grid", "--robot", R4, "--box", "-2", "2", "-2", "2", "0.5", "4", "--n", "5"]
    whole = tmp_path / "w.parquet"
    run_json(capsys, *args, "--out", str(whole))
    parts = []
    for k in range(3):
        f = tmp_path / f"s{k}.parquet"
        run_json(capsys, *args, "--out", str(f), "--shard", str(k), "--shards", "3")
        parts.append(pd.read_parquet(f))
    pd.testing.assert_frame_equal(pd.concat(parts, ignore_index=True), pd.read_parquet(whole))


def test_winch_json(capsys):
    out = run_json(capsys, "winch", "--steps", "3")
    assert [set(r) for r in out] == [{"l_pm", "q1", "q2", "q_nw", "dl"}] * 3
    assert out[0]["dl"] == pytest.approx(1.46e-3, abs=1e-5)


def test_point_physical_json_and_commanded_lengths(capsys):
    out = run_json(
        capsys,
        "point",
        "--robot",
        R4,
        "--pulley",
        "DR",
        "--at",
        "0.5",
        "0.2",
        "2.5",
        "--redundancy",
        "physical",
    )
    assert set(out) == {
        "desired",
        "solved",
        "dp_norm",
        "tensions",
        "taut",
        "status",
        "iterations",
        "engine",
        "interference_free",
        "equilibrium",
        "reached",
        "global",
        "reached_is_global",
        "warnings",
    }
    assert out["status"] == "ok" and out["taut"] == [1, 2, 3, 4] and all(t > 0 for t in out["tensions"])
    # the lengths of `compensate` commanded explicitly bring the platform to the desired point
    compensate = ["compensate", "--robot", R4, "--pulley", "DR", "--at", "0.5", "0.2", "2.5"]
    comp = run_json(capsys, *compensate)
    assert (
        set(comp)
        == {
            "desired",
            "lengths",
            "tensions",
            "status",
            "solved",
            "dp_norm",
            "engine",
            "interference_free",
            "warnings",
        }
        and comp["status"] == "ok"
    )
    assert comp["dp_norm"] < 1e-9 and comp["engine"] == "numpy"  # one pose: solve.ONE_SHOT_POSES
    fast = run_json(capsys, *compensate, "--engine", "compiled")
    assert fast["engine"] == "compiled" and fast["status"] == "ok" and fast["dp_norm"] < 1e-9
    assert np.allclose(fast["lengths"], comp["lengths"], rtol=0, atol=1e-9)
    back = run_json(
        capsys,
        "point",
        "--robot",
        R4,
        "--pulley",
        "DR",
        "--at",
        "0.5",
        "0.2",
        "2.5",
        "--redundancy",
        "physical",
        "--lengths",
        *map(str, comp["lengths"]),
    )
    assert back["dp_norm"] < 1e-9
    np.testing.assert_allclose(back["tensions"], comp["tensions"], atol=1e-6)


def test_per_cable_moduli_equal_to_the_robot_s_give_the_same_numbers(capsys):
    a = run_json(capsys, "point", "--robot", R4, "--at", "0.3", "-0.4", "2.0", "--redundancy", "physical")
    b = run_json(
        capsys,
        "point",
        "--robot",
        R4,
        "--at",
        "0.3",
        "-0.4",
        "2.0",
        "--redundancy",
        "physical",
        "--E-cables",
        *["102.2e9"] * 4,
    )
    assert a == b
    c = run_json(
        capsys,
        "point",
        "--robot",
        R4,
        "--at",
        "0.3",
        "-0.4",
        "2.0",
        "--redundancy",
        "physical",
        "--E-cables",
        "80e9",
        "120e9",
        "95e9",
        "130e9",
    )
    assert c["dp_norm"] != a["dp_norm"]


def test_grid_physical_writes_taut_sets(tmp_path, capsys):
    out = tmp_path / "g.parquet"
    run_json(
        capsys,
        "grid",
        "--robot",
        R4,
        "--box",
        "-2",
        "2",
        "-2",
        "2",
        "0.5",
        "4",
        "--n",
        "4",
        "--out",
        str(out),
        "--redundancy",
        "physical",
    )
    df = pd.read_parquet(out)
    assert {"taut", "n_taut", "status"} <= set(df.columns) and len(df) == 64
    assert (df.n_taut >= 2).all() and set(df.status.astype(str)) <= {
        "ok",
        "inaccessible",
        "over_tension",
        "not_converged",
    }


def test_inverse_reports_no_wrap_or_swivel_on_fixed_anchors(capsys, tmp_path):
    """Issue 41: a fixed anchor has no sheave and no swivel joint: inverse gives no wrap (gamma) and
    no swivel angle (alpha, swivel) there, in JSON (null), text ('-') and tables (NaN), and keeps
    them on a pulley."""
    fixed = run_json(capsys, "inverse", "--robot", R4, "--pulley", "fixed", "--at", "0.5", "0.2", "2.5")
    for c in fixed:
        assert c["gamma"] is c["wrap"] is c["alpha"] is c["swivel"] is None and c["wrap_over_270"] is False
    sr = run_json(capsys, "inverse", "--robot", R4, "--at", "0.5", "0.2", "2.5")
    assert all(0 < c["wrap"] < np.pi and c["swivel"] is not None for c in sr)
    assert main(["inverse", "--robot", R4, "--pulley", "fixed", "--at", "0.5", "0.2", "2.5"]) == 0
    rows = capsys.readouterr().out.splitlines()[3:]
    assert len(rows) == 4 and all(r.split()[3:5] == ["-", "-"] for r in rows)
    pts = tmp_path / "p.csv"
    pts.write_text("x,y,z\n0.5,0.2,2.5\n")
    out = tmp_path / "o.csv"
    assert main(["inverse", "--robot", R4, "--pulley", "fixed", "--points", str(pts), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert df[[f"gamma{i}" for i in range(1, 5)]].isna().all().all()
