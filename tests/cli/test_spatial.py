"""The command line on spatial robots (issue 17): --rotvec, the JSON keys, tables with rx, ry, rz."""

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from cdpr.cli.main import main
from tests.conftest import ROBOTS

COGIRO = str(ROBOTS / "cogiro_massless.yaml")
R4 = str(ROBOTS / "cdpr4.yaml")
TILT = str(np.radians(15))


def run_json(capsys, *args):
    assert main(list(args) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_point_json_on_cogiro(capsys):
    out = run_json(
        capsys,
        "point",
        "--robot",
        COGIRO,
        "--at",
        "0",
        "0",
        "2",
        "--rotvec",
        TILT,
        "0",
        "0",
        "--redundancy",
        "physical",
    )
    assert set(out) >= {
        "solved",
        "solved_rotvec",
        "dp_norm",
        "dphi",
        "tensions",
        "taut",
        "status",
        "unique",
        "alternatives",
    }
    assert out["status"] == "ok" and out["taut"] == sorted(out["taut"]) and min(out["taut"]) >= 1
    assert out["dp_norm"] == pytest.approx(np.linalg.norm(np.subtract(out["solved"], [0, 0, 2])))
    from scipy.spatial.transform import Rotation

    dphi = (
        Rotation.from_rotvec(out["solved_rotvec"]) * Rotation.from_rotvec([float(TILT), 0, 0]).inv()
    ).magnitude()
    assert out["dphi"] == pytest.approx(dphi, abs=1e-12)


def test_rotvec_is_carried_through_on_a_point_mass_robot(capsys):
    base = ["point", "--robot", R4, "--at", "0.5", "0.2", "2.5", "--redundancy", "physical"]
    a = run_json(capsys, *base)
    b = run_json(capsys, *base, "--rotvec", "0.1", "-0.2", "0.3")
    assert b["solved_rotvec"] == [0.1, -0.2, 0.3] and b["dphi"] == 0.0
    assert np.abs(np.subtract(a["solved"], b["solved"])).max() < 1e-9 and a["taut"] == b["taut"]
    c = run_json(capsys, "point", "--robot", R4, "--at", "0.5", "0.2", "2.5", "--rotvec", "0.1", "0", "0")
    assert c["solved_rotvec"] == [0.1, 0.0, 0.0] and c["dphi"] == 0.0 and "subset" in c


def test_inverse_json_keys_and_rotation(capsys):
    out = run_json(capsys, "inverse", "--robot", COGIRO, "--at", "0", "0", "2", "--rotvec", "0", "0", "0.3")
    assert len(out) == 8 and {"L_TE", "swivel", "wrap", "wrap_over_270"} <= set(out[0])
    flat = run_json(capsys, "inverse", "--robot", COGIRO, "--at", "0", "0", "2")
    assert any(abs(a["L_TE"] - b["L_TE"]) > 1e-3 for a, b in zip(out, flat))  # the orientation matters
    r4 = run_json(capsys, "inverse", "--robot", R4, "--at", "0.5", "0.2", "2.5")
    assert all(abs(c["swivel"] + c["alpha"]) < 1e-15 for c in r4)


def test_points_table_with_orientations(tmp_path, capsys):
    pts = tmp_path / "p.csv"
    pd.DataFrame(
        {"x": [0, 1], "y": [0, 1], "z": [2, 1.5], "rx": [float(TILT), 0], "ry": [0, 0], "rz": [0, 0.1]}
    ).to_csv(pts, index=False)
    out = tmp_path / "o.csv"
    assert (
        main(
            ["point", "--robot", COGIRO, "--points", str(pts), "--out", str(out), "--redundancy", "physical"]
        )
        == 0
    )
    capsys.readouterr()
    df = pd.read_csv(out)
    assert {"rx", "ry", "rz", "rx_s", "ry_s", "rz_s", "dphi", "unique", "taut", "status"} <= set(df.columns)
    assert df["rx"][0] == pytest.approx(float(TILT)) and (df["status"] == "ok").all()
    single = run_json(
        capsys,
        "point",
        "--robot",
        COGIRO,
        "--at",
        "1",
        "1",
        "1.5",
        "--rotvec",
        "0",
        "0",
        "0.1",
        "--redundancy",
        "physical",
    )
    assert df["dphi"][1] == pytest.approx(single["dphi"], abs=1e-12)


@pytest.mark.parametrize(
    "extra,message",
    [
        (["--redundancy", "paper"], "paper mode (3-cable subsets) is the point-mass rule"),
        (["--redundancy", "physical", "--method", "fixed_point"], "physical mode has one solver"),
    ],
)
def test_spatial_refusals_are_one_line(capsys, extra, message):
    assert main(["point", "--robot", COGIRO, "--at", "0", "0", "2", *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_a_rigid_platform_defaults_to_physical_mode(capsys):
    """Without --redundancy a rigid platform is solved in physical mode (its only mode), as if it had
    been given, and a point mass keeps paper mode (issue 41, 'Defaults a newcomer expects')."""
    at = ["--robot", COGIRO, "--at", "0", "0", "2", "--json"]
    assert main(["point", *at]) == 0
    default = json.loads(capsys.readouterr().out)
    assert main(["point", *at, "--redundancy", "physical"]) == 0
    assert default == json.loads(capsys.readouterr().out)
    assert default["status"] == "ok" and "taut" in default and "subset" not in default
    assert main(["point", "--robot", str(ROBOTS / "cdpr4.yaml"), "--at", "0", "0", "2.5", "--json"]) == 0
    assert "subset" in json.loads(capsys.readouterr().out)  # a point mass: paper mode, as before


def test_the_compiled_engine_solves_spatial_poses_as_the_numpy_one(capsys):
    """--engine compiled: the compiled 6-DoF twin, the same pose as the numpy default (1e-9)."""
    base = ["point", "--robot", COGIRO, "--at", "1", "1", "1.5", "--rotvec", "0", "0.2", "0.1"]
    a = run_json(capsys, *base, "--redundancy", "physical")
    b = run_json(capsys, *base, "--redundancy", "physical", "--engine", "compiled")
    assert a["status"] == b["status"] == "ok" and a["taut"] == b["taut"] and a["unique"] == b["unique"]
    assert np.abs(np.subtract(a["solved"], b["solved"])).max() < 1e-9
    assert np.abs(np.subtract(a["solved_rotvec"], b["solved_rotvec"])).max() < 1e-9


def test_compensate_at_a_pose_round_trips(capsys):
    E = ["80e9", "120e9", "95e9", "130e9", "110e9", "90e9", "105e9", "115e9"]
    base = ["compensate", "--robot", COGIRO, "--E-cables", *E, "--t-min", "100", "--t-max", "5000"]
    out = run_json(capsys, *base, "--at", "0", "0", "2", "--rotvec", TILT, "0", "0")
    assert out["status"] == "ok" and len(out["lengths"]) == 8
    assert out["dp_norm"] < 1e-9 and out["dphi"] < 1e-9
    hang = run_json(
        capsys,
        "compensate",
        "--robot",
        str(ROBOTS / "hang4_6dof.yaml"),
        "--at",
        "0.3",
        "0.2",
        "2.5",
        "--rotvec",
        "0.2",
        "0",
        "0",
    )
    assert hang["status"] == "infeasible" and hang["lengths"] == [None] * 4


def test_compensate_table_leaves_infeasible_poses_unsolved(tmp_path, capsys):
    """A pose with no tension distribution is ``infeasible`` and never solved: its solved columns
    are empty (no equilibrium of placeholder lengths), its feasible neighbours are solved and hold
    the pose; the table equals the library's ``compensated_pose`` row for row."""
    from cdpr.analyses.compensation import compensated_pose
    from cdpr.robot import load_robot

    pts = tmp_path / "p.csv"
    pts.write_text("x,y,z,rx,ry,rz\n0,0,2,0,0,0\n0,0,2,0.8,0,0\n0.5,-0.3,1.0,0,0.1,0\n0,0,2,0.2618,0,0\n")
    wall = str(ROBOTS / "wall_pulleys.yaml")
    out = tmp_path / "c.csv"
    assert (
        main(["compensate", "--robot", wall, "--points", str(pts), "--out", str(out), "--t-min", "10"]) == 0
    )
    df = pd.read_csv(out)
    bad = df["status"] == "infeasible"
    assert bad.any() and (~bad).any()
    solved = ["x_s", "y_s", "z_s", "dp", "rx_s", "ry_s", "rz_s", "dphi", "t1", "L0_1"]
    assert df.loc[bad, solved].isna().all().all() and (df.loc[bad, "iterations"] == 0).all()
    assert (df.loc[~bad, "status"] == "ok").all()
    assert df.loc[~bad, "dp"].max() < 1e-9 and df.loc[~bad, "dphi"].max() < 1e-9
    P = pd.read_csv(pts).to_numpy()
    lib = compensated_pose(load_robot(wall), P, t_min=10.0)
    assert list(lib["status"]) == list(df["status"])
    np.testing.assert_allclose(df[["x_s", "y_s", "z_s"]].to_numpy(), lib["P_s"], rtol=0, atol=1e-12)


def test_view_writes_a_picture(tmp_path, capsys):
    out = tmp_path / "robot.png"
    assert (
        main(
            ["view", "--robot", COGIRO, "--at", "0", "0", "2", "--rotvec", TILT, "0", "0", "--out", str(out)]
        )
        == 0
    )
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 20_000
    assert main(["view", "--robot", COGIRO, "--out", str(tmp_path / "robot.jpg")]) == 2
    assert "unknown output format '.jpg'" in capsys.readouterr().err


def test_grid_at_a_fixed_orientation_with_wrench_feasibility(tmp_path, capsys):
    out = tmp_path / "g.csv"
    base = [
        "grid",
        "--box",
        "-2",
        "2",
        "-2",
        "2",
        "1",
        "3",
        "--n",
        "2",
        "--redundancy",
        "physical",
        "--wrench-feasible",
    ]
    assert main([*base, "--robot", COGIRO, "--rotvec", "0.1", "0", "0", "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert len(df) == 8 and df["feasible"].all() and (df["rx"] == 0.1).all() and (df["status"] == "ok").all()
    text = capsys.readouterr().out
    assert "wrench-feasible: 8 of 8 grid points, 32 m^3" in text
    assert "largest wrench-feasible box: x [-2, 2] y [-2, 2] z [1, 3] m, 32 m^3 (8 grid points" in text
    hang = str(ROBOTS / "hang4_6dof.yaml")
    assert main([*base, "--robot", hang, "--rotvec", "0.1", "0", "0", "--out", str(out)]) == 0
    assert not pd.read_csv(out)["feasible"].any()  # 4 cables, 6 DoF: no distribution at a fixed orientation
    capsys.readouterr()
    assert main([*base[:-1], "--robot", COGIRO, "--sensitivities", "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert {"dx_db_1_x", "dphiz_db_1_x", "dphix_dc_z", "dz_dM", "smooth"} <= set(df.columns)
    assert df["smooth"].all() and np.isfinite(df["dphiy_dA_3_z"]).all()


def test_frame_extent_of_a_robot_that_is_not_a_suspended_point_mass(cdpr4):
    from cdpr.analyses.workspace import envelope_volume, frame_box
    from cdpr.robot import load_robot

    cog = load_robot(COGIRO)
    box = frame_box(cog)
    assert box[4] == 0.0 and box[5] == pytest.approx(5.42) and box[0] == pytest.approx(-7.4594)
    assert frame_box(cdpr4) == [-2.5, 2.5, -2.5, 2.5, 0.0, 5.0] and envelope_volume(cdpr4) == pytest.approx(
        125.0
    )
    ip = load_robot(ROBOTS / "ipanema_like.yaml")
    assert envelope_volume(ip) == pytest.approx(4 * 3 * 3)


def test_plane_and_trajectory_take_an_orientation(tmp_path, capsys):
    out = tmp_path / "t.csv"
    base = ["--robot", COGIRO, "--rotvec", "0", "0.1", "0", "--redundancy", "physical", "--out", str(out)]
    assert main(["trajectory", "--start", "-1", "0", "1.5", "--end", "1", "0", "2", "--n", "3", *base]) == 0
    df = pd.read_csv(out)
    assert len(df) == 3 and (df["ry"] == 0.1).all() and "s" in df.columns and (df["status"] == "ok").all()
    assert main(["plane", "--z", "2", "--n", "2", *base]) == 0
    assert len(pd.read_csv(out)) == 4
    capsys.readouterr()
    assert main(["plane", "--z", "7", "--n", "2", *base]) == 2
    assert "--z must lie within the frame's height (0 <= z <= 5.42 m)" in capsys.readouterr().err


DATA = Path(__file__).parent / "data"
SENS = ["--redundancy", "physical", "--sensitivities"]


@pytest.mark.parametrize("engine", [None, "numpy", "compiled"])
def test_point_sensitivities_on_cogiro_equal_the_library(capsys, engine):
    """--sensitivities on a rigid platform: the JSON's dp*/dθ and dφ*/dθ are the library's numbers,
    the numpy reference's by default (one pose, solve.ONE_SHOT_POSES) and with --engine numpy, the
    compiled engine's with --engine compiled."""
    from cdpr.parameters import parameter_names
    from cdpr.robot import load_robot
    from cdpr.solve import sensitivities

    rv = [0.05, -0.03, 0.02]
    extra = [] if engine is None else ["--engine", engine]
    out = run_json(
        capsys,
        "point",
        "--robot",
        COGIRO,
        "--at",
        "0.2",
        "0.1",
        "2",
        "--rotvec",
        *map(str, rv),
        *SENS,
        *extra,
    )
    assert out["engine"] == (engine or "numpy")  # one pose: the numpy reference by default
    lib = sensitivities(
        load_robot(COGIRO), [[0.2, 0.1, 2.0]], rv, redundancy="physical", engine=out["engine"]
    )
    names = parameter_names(load_robot(COGIRO))
    assert list(out["sensitivities"]) == names == list(out["sensitivities_phi"]) and len(names) == 8 * 10 + 4
    S = lib["S"][0]
    assert all(out["sensitivities"][n] == S[:3, k].tolist() for k, n in enumerate(names))
    assert all(out["sensitivities_phi"][n] == S[3:, k].tolist() for k, n in enumerate(names))
    assert out["sensitivities_smooth"] is bool(lib["smooth"][0]) is True
    assert out["solved"] == lib["P_s"][0].tolist()


def test_point_sensitivities_table_on_cogiro(capsys):
    assert main(["point", "--robot", COGIRO, "--at", "0", "0", "2", *SENS]) == 0
    text = capsys.readouterr().out
    assert "sensitivities dp*/dθ and dφ*/dθ at fixed commanded lengths (numpy reference):" in text
    row = next(line for line in text.splitlines() if line.strip().startswith("E_1 "))
    assert row.split()[1] == "m/Pa" and row.split()[5] == "rad/Pa"
    assert "b_8_z   m/m" in text and "    M  m/kg" in text
    assert main(["point", "--robot", COGIRO, "--at", "0", "0", "2", *SENS, "--engine", "compiled"]) == 0
    assert "at fixed commanded lengths (compiled engine):" in capsys.readouterr().out
    assert (
        main(["point", "--robot", COGIRO, "--at", "0", "0", "2", "--sensitivities", "--redundancy", "paper"])
        == 2
    )
    assert "paper mode (3-cable subsets) is the point-mass rule" in capsys.readouterr().err
    # without --redundancy a rigid platform takes physical mode, its only one
    assert main(["point", "--robot", COGIRO, "--at", "0", "0", "2", "--sensitivities"]) == 0
    assert "sensitivities dp*/dθ and dφ*/dθ at fixed commanded lengths" in capsys.readouterr().out


@pytest.mark.parametrize("mode", ["paper", "physical"])
def test_point_mass_sensitivities_json_is_unchanged(capsys, mode):
    """CDPR4's --sensitivities output, byte for byte as before the spatial sensitivities (files written
    by the previous version of the command with the compiled engine, its default then; the JSON has
    gained the keys "engine", "warnings" and "interference_free", and in physical mode the reached
    equilibrium's "equilibrium", "reached", "global" and "reached_is_global"); with --rotvec the orientation is carried through. One pose now defaults
    to the numpy reference: the same subset or taut set, pose to 1e-9 m, sensitivities to 1e-6."""
    args = ["point", "--robot", R4, "--pulley", "DR", "--at", "0.5", "0.2", "2.5", "--redundancy", mode]
    ref = json.loads((DATA / f"point_sensitivities_cdpr4_{mode}.json").read_text())
    fast = run_json(capsys, *args, "--sensitivities", "--engine", "compiled")
    assert fast.pop("engine") == "compiled" and fast.pop("warnings") == [] and fast.pop("interference_free")
    if mode == "physical":  # issue 39: the reached equilibrium beside the global one, the same here
        assert fast.pop("equilibrium") == "reached" and fast.pop("reached_is_global") is True
        assert fast.pop("reached")["solved"] == pytest.approx(fast.pop("global")["solved"], abs=1e-9)
    assert fast == ref
    default = run_json(capsys, *args, "--sensitivities")
    assert default.pop("engine") == "numpy"
    assert default.get("subset") == ref.get("subset") and default.get("taut") == ref.get("taut")
    assert np.allclose(default["solved"], ref["solved"], rtol=0, atol=1e-9)
    for name, vec in ref["sensitivities"].items():
        assert np.allclose(default["sensitivities"][name], vec, rtol=1e-6, atol=1e-12), name
    args = [*args, "--engine", "compiled"]
    if mode == "paper":
        assert main([*args, "--sensitivities"]) == 0
        assert capsys.readouterr().out == (DATA / "point_sensitivities_cdpr4_paper.txt").read_text()
    rot = run_json(capsys, *args, "--rotvec", "0.1", "0", "0", "--sensitivities")
    ref = json.loads((DATA / f"point_sensitivities_cdpr4_{mode}.json").read_text())
    assert rot["solved_rotvec"] == [0.1, 0.0, 0.0] and rot["dphi"] == 0.0 and "sensitivities_phi" not in rot
    assert rot["sensitivities"] == ref["sensitivities"]


@pytest.mark.parametrize("method", ["closed_form", "closed_form_improved"])
def test_compensate_at_a_pose_with_the_closed_forms(capsys, method):
    """--distribution closed_form / closed_form_improved at a pose: the library's lengths, and the check
    solve returns the pose; the paper's subset is refused in one line."""
    from cdpr.models.tension_distribution import compensated_lengths
    from cdpr.robot import load_robot

    base = ["compensate", "--robot", COGIRO, "--at", "0", "0", "2", "--rotvec", TILT, "0", "0"]
    out = run_json(capsys, *base, "--t-max", "5000", "--distribution", method)
    lib = compensated_lengths(
        load_robot(COGIRO), [[0, 0, 2.0]], [float(TILT), 0, 0], t_max=5000.0, method=method
    )
    assert out["status"] == "ok" and out["lengths"] == lib["L0"][0].tolist()
    assert out["dp_norm"] < 1e-9 and out["dphi"] < 1e-9
    assert main([*base, "--distribution", method]) == 0
    assert f"distribution {method} at a pose" in capsys.readouterr().out
    assert main([*base, "--distribution", "subset"]) == 2
    err = capsys.readouterr().err
    assert "--distribution subset (the paper's 3-cable subset) is not available at a pose" in err
    assert err.count("\n") == 1


def test_largest_wrench_feasible_box_of_a_spatial_grid(tmp_path, capsys):
    """CoGiRo tilted, a 4^3 grid over the frame: the JSON's box lies on the grid, every grid point
    inside it is ok and wrench-feasible, its volume is its bounds' and at most the feasible volume."""
    out = tmp_path / "g.parquet"
    args = ["grid", "--robot", COGIRO, "--frame", "--n", "4", "--rotvec", "0.05", "0", "0"]
    s = run_json(capsys, *args, "--redundancy", "physical", "--wrench-feasible", "--out", str(out))
    df = pd.read_parquet(out)
    b = [s[f"wf_box_{k}_m"] for k in ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")]
    assert s["wrench_feasible_box_m3"] == pytest.approx((b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]))
    assert 0 < s["wrench_feasible_box_m3"] <= s["wrench_feasible_m3"] + 1e-9
    inside = (
        df["x"].between(b[0], b[1]) & df["y"].between(b[2], b[3]) & df["z"].between(b[4], b[5])
    ).to_numpy()
    cell = s["wrench_feasible_m3"] / s["wrench_feasible_points"]
    assert inside.sum() * cell == pytest.approx(s["wrench_feasible_box_m3"])
    assert df["feasible"][inside].all() and (df["status"][inside] == "ok").all()
    assert not (df["feasible"] & (df["status"] == "ok")).all()  # the box is a real restriction here
    assert (
        main([*args, "--redundancy", "physical", "--wrench-feasible", "--out", str(out), "--shards", "2"])
        == 0
    )
    assert "needs the whole grid (--shards 1)" in capsys.readouterr().out


def test_point_text_says_when_the_equilibrium_is_not_unique(capsys):
    """The readable output names a non-unique equilibrium (the JSON's unique: false) in one extra
    line; every other line is the same, and a unique equilibrium prints no such line."""
    base = ["point", "--robot", COGIRO, "--redundancy", "physical", "--engine", "numpy"]
    js = run_json(capsys, *base, "--at", "0", "0", "9")
    assert js["unique"] is False and js["alternatives"]
    assert main([*base, "--at", "0", "0", "9"]) == 0
    lines = capsys.readouterr().out.splitlines()
    n = len(js["alternatives"])
    assert lines[-1] == f"  equilibrium    : not unique ({n} alternative{'s' * (n != 1)}; --json lists them)"
    assert lines[-2].startswith("  status         : ok  (")
    assert main([*base, "--at", "0", "0", "2"]) == 0
    assert (
        "equilibrium    :" not in capsys.readouterr().out
        and run_json(capsys, *base, "--at", "0", "0", "2")["unique"]
    )


@pytest.mark.parametrize("robot", [R4, COGIRO])
@pytest.mark.parametrize("command", ["inverse", "point", "compensate"])
def test_rotvec_and_orientation_columns_together_are_refused_before_any_solve(
    tmp_path, capsys, monkeypatch, command, robot
):
    """--rotvec was silently ignored when the --points table had rx, ry, rz: now one line naming
    both sources, exit code 2, nothing solved and no table written."""
    import cdpr.analyses.compensation
    import cdpr.models.inverse
    import cdpr.models.tension_distribution
    import cdpr.solve

    def no_solve(*args, **kwargs):
        raise AssertionError("solved before refusing")

    for module, name in [
        (cdpr.solve, "solve"),
        (cdpr.models.inverse, "igm_e"),
        (cdpr.models.inverse, "pose_state"),
        (cdpr.analyses.compensation, "compensated_pose"),
        (cdpr.models.tension_distribution, "compensated_lengths"),
    ]:
        monkeypatch.setattr(module, name, no_solve)
    pts, out = tmp_path / "poses.csv", tmp_path / "out.csv"
    pd.DataFrame({"x": [0.0], "y": [0.0], "z": [2.0], "rx": [0.1], "ry": [0.0], "rz": [0.0]}).to_csv(
        pts, index=False
    )
    args = [command, "--robot", robot, "--points", str(pts), "--out", str(out), "--rotvec", "0", "0", "0.2"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err == (
        f"cdpr: error: give the orientation either as --rotvec (or --euler-xyz-deg) or as rx, ry, rz columns of --points ({pts}), not both\n"
    )
    assert not out.exists()


ORIENTATION = ["rx", "ry", "rz", "rx_s", "ry_s", "rz_s", "dphi"]


BOX = ["--box", "-1", "1", "-1", "1", "1", "3", "--n", "2"]
GIVEN_ORIENTATION = [  # (command and its points, where the orientation comes from)
    (["point", "--points", "{p}"], "--rotvec"),
    (["point"], "columns"),
    (["grid", *BOX], "--rotvec"),
    (["grid", *BOX, "--sensitivities"], "--rotvec"),
    (["plane", "--z", "2.5", "--n", "2"], "--rotvec"),
    (["trajectory", "--start", "-1", "0", "1.5", "--end", "1", "0", "2", "--n", "3"], "--rotvec"),
]


@pytest.mark.parametrize("mode", ["paper", "physical"])
@pytest.mark.parametrize("command,source", GIVEN_ORIENTATION, ids=lambda v: v if isinstance(v, str) else v[0])
def test_point_mass_tables_carry_a_given_orientation(tmp_path, capsys, command, source, mode):
    """A point-mass robot given an orientation writes it as the spatial tables do: rx, ry, rz and
    rx_s, ry_s, rz_s (the same: carried through), dphi = 0 after dp, unique where the JSON has it
    (physical mode, not with --sensitivities); every other column equals the table solved without
    the orientation (the same P*). Without one, no orientation column (the tables as before)."""
    rv = [0.1, -0.2, 0.3]
    P = {"x": [0.0, 0.5], "y": [0.0, 0.2], "z": [2.5, 2.5]}
    pd.DataFrame(P).to_csv(tmp_path / "p.csv", index=False)
    R = {"rx": [rv[0]] * 2, "ry": [rv[1]] * 2, "rz": [rv[2]] * 2}
    pd.DataFrame({**P, **R}).to_csv(tmp_path / "pr.csv", index=False)
    command = [c.format(p=tmp_path / "p.csv") for c in command]
    base = ["--robot", R4, "--redundancy", mode, "--engine", "numpy"]
    plain, rot = tmp_path / "plain.csv", tmp_path / "rot.csv"
    if source == "columns":
        assert main([*command, *base, "--points", str(tmp_path / "p.csv"), "--out", str(plain)]) == 0
        assert main([*command, *base, "--points", str(tmp_path / "pr.csv"), "--out", str(rot)]) == 0
    else:
        assert main([*command, *base, "--out", str(plain)]) == 0
        assert main([*command, *base, "--rotvec", *map(str, rv), "--out", str(rot)]) == 0
    capsys.readouterr()
    a, b = pd.read_csv(plain), pd.read_csv(rot)
    assert not set(ORIENTATION + ["unique"]) & set(a.columns)  # no orientation given: no such columns
    at = list(a.columns).index("dp") + 1
    extra = ["unique"] if mode == "physical" and "--sensitivities" not in command else []
    assert list(b.columns) == list(a.columns)[:at] + ORIENTATION + list(a.columns)[at:] + extra
    for k, c in enumerate(("rx", "ry", "rz")):
        assert (b[c] == rv[k]).all() and (b[c + "_s"] == rv[k]).all()
    assert (b["dphi"] == 0).all() and (not extra or b["unique"].all())
    pd.testing.assert_frame_equal(b[a.columns], a, atol=1e-9)


@pytest.mark.parametrize("robot", [R4, COGIRO])
def test_inverse_tables_write_the_orientation_they_were_given(tmp_path, capsys, robot):
    P = {"x": [0.0, 0.5], "y": [0.0, 0.2], "z": [2.0, 2.5]}
    R = {"rx": [0.01, 0.0], "ry": [0.0, 0.02], "rz": [0.0, -0.03]}
    pd.DataFrame(P).to_csv(tmp_path / "p.csv", index=False)
    pd.DataFrame({**P, **R}).to_csv(tmp_path / "pr.csv", index=False)
    out = tmp_path / "o.csv"
    assert main(["inverse", "--robot", robot, "--points", str(tmp_path / "p.csv"), "--out", str(out)]) == 0
    assert list(pd.read_csv(out).columns[:4]) == ["x", "y", "z", "L_TS1"]  # none given: none written
    assert main(["inverse", "--robot", robot, "--points", str(tmp_path / "pr.csv"), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert list(df.columns[:7]) == ["x", "y", "z", "rx", "ry", "rz", "L_TS1"]
    assert df[["rx", "ry", "rz"]].to_dict("list") == R
    rotvec = ["--rotvec", "0.01", "0", "0"]
    assert (
        main(["inverse", "--robot", robot, "--points", str(tmp_path / "p.csv"), *rotvec, "--out", str(out)])
        == 0
    )
    capsys.readouterr()
    df = pd.read_csv(out)
    assert (df["rx"] == 0.01).all() and (df["ry"] == 0).all() and (df["rz"] == 0).all()


def _leaning_cdpr4(tmp_path):
    """CDPR4's file with every pulley axis leaning 20° toward the frame's centre (a point mass whose
    pulleys are not +z: not suspended)."""
    import yaml

    d = yaml.safe_load(Path(R4).read_text())
    s, c = np.sin(np.radians(20)), np.cos(np.radians(20))
    for cab in d["cables"]:
        a = np.asarray(cab["A_m"][:2], dtype=float)
        a /= np.linalg.norm(a)
        cab["pulley"] = {"axis": [float(-s * a[0]), float(-s * a[1]), float(c)]}
    path = tmp_path / "leaning.yaml"
    path.write_text(yaml.safe_dump(d))
    return str(path)


def test_paper_mode_on_a_point_mass_with_leaning_pulleys(capsys, tmp_path):
    """Paper mode takes a point mass whose pulley axes lean: both engines give the same subset,
    status and P* (1e-9 m), and the paper's fixed point the same within its tolerance."""
    robot = _leaning_cdpr4(tmp_path)
    at = ["--at", "0.5", "0.2", "2.5"]
    a = run_json(capsys, "point", "--robot", robot, *at, "--engine", "numpy")
    b = run_json(capsys, "point", "--robot", robot, *at, "--engine", "compiled")
    assert a["status"] == b["status"] == "ok" and a["subset"] == b["subset"]
    assert len(a["subset"]) == 3 and a["dp_norm"] > 1e-3
    assert np.allclose(a["solved"], b["solved"], rtol=0, atol=1e-9)
    # the pulleys lean, so the answer is not the suspended robot's
    c = run_json(capsys, "point", "--robot", R4, *at, "--engine", "numpy")
    assert abs(c["dp_norm"] - a["dp_norm"]) > 1e-4
    # the paper's fixed point, each pulley in its frame: the same subset, within its 1e-5 m tolerance
    f = run_json(capsys, "point", "--robot", robot, *at, "--method", "fixed_point")
    assert f["status"] == "ok" and f["subset"] == a["subset"]
    assert np.allclose(f["solved"], a["solved"], rtol=0, atol=5e-5)


def test_paper_mode_sensitivities_on_a_point_mass_with_leaning_pulleys(capsys, tmp_path):
    """--sensitivities in paper mode on a point mass whose pulley axes lean: dP*/dθ of the chosen
    subset (both engines equal), zero for the slack cable's parameters, different from the
    suspended robot's; in a grid table too."""
    robot = _leaning_cdpr4(tmp_path)
    at = ["--at", "0.5", "0.2", "2.5", "--sensitivities"]
    a = run_json(capsys, "point", "--robot", robot, *at, "--engine", "numpy")
    b = run_json(capsys, "point", "--robot", robot, *at, "--engine", "compiled")
    assert a["status"] == "ok" and a["sensitivities_smooth"] and a["subset"] == [1, 2, 3]
    assert a["sensitivities"].keys() == b["sensitivities"].keys()
    for name, vec in a["sensitivities"].items():
        assert np.allclose(vec, b["sensitivities"][name], rtol=1e-9, atol=1e-15), name
    assert np.abs(a["sensitivities"]["h_1"]).max() > 0.1
    assert not np.any(a["sensitivities"]["h_4"])  # cable 4 is slack: its pulley plays no part
    c = run_json(capsys, "point", "--robot", R4, *at)
    assert np.abs(np.subtract(c["sensitivities"]["h_1"], a["sensitivities"]["h_1"])).max() > 1e-3
    out = tmp_path / "g.parquet"
    assert main(["grid", "--robot", robot, "--box", "-1", "1", "-1", "1", "1", "3", "--n", "3",
                 "--sensitivities", "--out", str(out)]) == 0  # fmt: skip
    df = pd.read_parquet(out)
    assert len(df) == 27 and (df["status"] == "ok").all() and "dx_dh_1" in df.columns
