"""Issue 41: ``--wrench FX FY FZ MX MY MZ`` (an external wrench beside gravity) on ``point``,
``compensate`` and ``grid --wrench-feasible``, echoed in the JSON, and the study key ``wrench``
reaching the study's robots as a typed value; bad input in one line."""

import json

import numpy as np
import pandas as pd
import pytest
import yaml

from cdpr.cli.main import main
from cdpr.errors import ConfigError
from cdpr.pipeline.study import load_study
from cdpr.robot import G_STANDARD
from tests.conftest import ROBOTS, ROOT

R4 = str(ROBOTS / "cdpr4.yaml")
RC = str(ROBOTS / "cogiro_massless.yaml")


def run(capsys, *args):
    try:
        code = main([str(a) for a in args])
    except SystemExit as exc:  # the parser's one-line refusals
        code = exc.code
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def run_json(capsys, *args):
    code, out, err = run(capsys, *args, "--json")
    assert code == 0, err
    return json.loads(out)


def test_point_echoes_the_wrench_and_a_vertical_force_is_more_mass(capsys, tmp_path):
    """CDPR4 (a point mass): --wrench 0 0 -dM g 0 0 0 solves to the pose of a robot file with dM
    more mass (physical mode, 1e-12 m); the JSON echoes the six numbers; without --wrench no key."""
    d = yaml.safe_load(open(R4).read())
    dM = 12.0
    d["platform"]["mass_kg"] = float(d["platform"]["mass_kg"]) + dM
    heavier = tmp_path / "heavier.yaml"
    heavier.write_text(yaml.safe_dump(d))
    at = ["--at", "0.3", "-0.5", "2.0", "--redundancy", "physical"]
    w = [0.0, 0.0, -dM * G_STANDARD, 0.0, 0.0, 0.0]
    a = run_json(capsys, "point", "--robot", R4, *at, "--wrench", *w)
    b = run_json(capsys, "point", "--robot", heavier, *at)
    assert a["wrench"] == w and "wrench" not in b
    assert a["status"] == b["status"] == "ok"
    assert np.abs(np.subtract(a["solved"], b["solved"])).max() <= 1e-12
    plain = run_json(capsys, "point", "--robot", R4, *at)
    assert plain["solved"][2] > a["solved"][2] + 1e-4  # the push down lowered it


def test_a_zero_wrench_changes_nothing_but_the_echo(capsys):
    at = ["--at", "0.3", "-0.5", "2.0"]
    a = run_json(capsys, "point", "--robot", R4, *at, "--wrench", 0, 0, 0, 0, 0, 0)
    b = run_json(capsys, "point", "--robot", R4, *at)
    assert a.pop("wrench") == [0.0] * 6 and a == b
    _, ta, _ = run(capsys, "point", "--robot", R4, *at)
    _, tb, _ = run(capsys, "point", "--robot", R4, *at, "--wrench", 0, 0, 0, 0, 0, 0)
    assert tb.splitlines()[1:] == ta.splitlines()[1:]


def test_compensate_then_point_round_trip_with_a_wrench_on_a_rigid_platform(capsys):
    """CoGiRo under a side force and a moment: compensate's lengths, commanded by point with the same
    wrench, bring the platform back to the desired pose; without the wrench they do not."""
    w = [60.0, -40.0, 25.0, 8.0, -5.0, 3.0]
    at = ["--at", "0.5", "-0.3", "2.5"]
    comp = run_json(capsys, "compensate", "--robot", RC, *at, "--wrench", *w)
    assert comp["status"] == "ok" and comp["wrench"] == w
    lengths = [str(v) for v in comp["lengths"]]
    back = run_json(capsys, "point", "--robot", RC, *at, "--lengths", *lengths, "--wrench", *w)
    assert back["status"] == "ok" and back["engine"] == "numpy"
    assert back["dp_norm"] < 1e-7 and back["dphi"] < 1e-7
    off = run_json(capsys, "point", "--robot", RC, *at, "--lengths", *lengths)
    assert off["dp_norm"] > 1e-4


def test_grid_wrench_feasible_under_a_force_along_x(capsys, tmp_path):
    """A force along +x must be balanced by the cables pulling toward -x: the wrench-feasible points
    move to +x (the largest box's x-minimum rises) and there are fewer of them."""
    box = ["--box", "-2", "2", "-2", "2", "0.5", "4", "--n", "6", "--wrench-feasible"]
    a = run_json(capsys, "grid", "--robot", R4, *box, "--out", tmp_path / "a.csv")
    b = run_json(
        capsys, "grid", "--robot", R4, *box, "--out", tmp_path / "b.csv", "--wrench", 3000, 0, 0, 0, 0, 0
    )
    assert b["wrench"] == [3000.0, 0, 0, 0, 0, 0]
    assert 0 < b["wrench_feasible_points"] < a["wrench_feasible_points"]
    assert b["wf_box_xmin_m"] > a["wf_box_xmin_m"] and b["wf_box_xmax_m"] == a["wf_box_xmax_m"]


@pytest.mark.parametrize(
    "wrench, words",
    [
        (["1", "2", "3", "4", "5"], "argument --wrench: expected 6 arguments"),
        (["0", "0", "nan", "0", "0", "0"], "'nan' is not a finite number"),
        (["0", "0", "0", "0", "inf", "0"], "'inf' is not a finite number"),
        (["0", "0", "-10", "1", "0", "0"], "point mass"),
    ],
)
def test_bad_wrenches_are_one_line(capsys, wrench, words):
    for cmd in (["point", "--at", "0", "0", "2"], ["compensate", "--at", "0", "0", "2"]):
        code, out, err = run(capsys, *cmd, "--robot", R4, "--wrench", *wrench)
        assert code == 2 and out == "" and len(err.splitlines()) == 1
        assert err.startswith("cdpr: error: ") and words in err and "--wrench" in err


def test_both_engines_take_a_rigid_wrench(capsys):
    """CoGiRo with a force and a moment: ``--engine compiled`` solves it (no refusal) and agrees with
    the numpy reference to 1e-9 m and 1e-9 rad, same status and taut set; the wrench moved it."""
    at = ["--robot", RC, "--at", "0.5", "-0.3", "2.5", "--rotvec", "0.05", "-0.02", "0.1"]
    w = [60.0, -40.0, 25.0, 8.0, -5.0, 3.0]
    a = run_json(capsys, "point", *at, "--engine", "compiled", "--wrench", *w)
    b = run_json(capsys, "point", *at, "--engine", "numpy", "--wrench", *w)
    assert a["engine"] == "compiled" and b["engine"] == "numpy"
    assert a["status"] == b["status"] == "ok" and a["taut"] == b["taut"]
    assert np.abs(np.subtract(a["solved"], b["solved"])).max() <= 1e-9
    assert np.abs(np.subtract(a["solved_rotvec"], b["solved_rotvec"])).max() <= 1e-9
    plain = run_json(capsys, "point", *at, "--engine", "compiled")
    assert np.abs(np.subtract(a["solved"], plain["solved"])).max() > 1e-4


def study_with(tmp_path, text, wrench):
    f = tmp_path / "study.yaml"
    f.write_text(text + f"\nwrench: {wrench}\n")
    return f


def test_the_study_key_reaches_every_robot(tmp_path):
    text = (ROOT / "config" / "studies" / "template_spatial.yaml").read_text()
    st = load_study(study_with(tmp_path, text, [10.0, 0, -5, 1, 2, 0]))
    assert st.options.wrench == (10.0, 0.0, -5.0, 1.0, 2.0, 0.0)
    assert all(r.platform.wrench == (10.0, 0.0, -5.0, 1.0, 2.0, 0.0) for r in st.robot_models.values())
    plain = load_study(ROOT / "config" / "studies" / "template_spatial.yaml")
    assert plain.options.wrench is None
    assert all(not r.platform.has_wrench for r in plain.robot_models.values())


def test_bad_study_wrenches_name_the_key(tmp_path):
    quick = (ROOT / "config" / "studies" / "quick.yaml").read_text()
    with pytest.raises(ConfigError) as exc:
        load_study(study_with(tmp_path, quick, [0, 0, -5, 1, 0, 0]))  # a moment on point masses
    msg = str(exc.value)
    assert "key 'wrench'" in msg and "point mass" in msg and "\n" not in msg
    with pytest.raises(ConfigError) as exc:
        load_study(study_with(tmp_path, quick, [0, 0, -5, 0, 0]))
    assert "wrench" in str(exc.value)
    st = load_study(study_with(tmp_path, quick, [0, 0, -5, 0, 0, 0]))  # a force is fine
    assert all(r.platform.wrench[2] == -5.0 for r in st.robot_models.values())


def test_plane_and_trajectory_take_the_wrench(capsys, tmp_path):
    """``plane`` and ``trajectory`` with --wrench: the JSON echoes it and the text's first line names
    it; on CDPR4 (a point mass) a vertical force -dM g is dM more mass along the path (the table of a
    robot file with that mass, 1e-12 m); on CoGiRo a force and a moment move the plane's poses."""
    d = yaml.safe_load(open(R4).read())
    dM = 12.0
    d["platform"]["mass_kg"] = float(d["platform"]["mass_kg"]) + dM
    heavier = tmp_path / "heavier.yaml"
    heavier.write_text(yaml.safe_dump(d))
    w = [0.0, 0.0, -dM * G_STANDARD, 0.0, 0.0, 0.0]
    path = ["--start", "-1", "-1", "1", "--end", "1", "1", "3", "--n", "7", "--redundancy", "physical"]
    a = run_json(capsys, "trajectory", "--robot", R4, *path, "--out", tmp_path / "a.parquet", "--wrench", *w)
    b = run_json(capsys, "trajectory", "--robot", heavier, *path, "--out", tmp_path / "b.parquet")
    assert a["wrench"] == w and "wrench" not in b
    ta, tb = (pd.read_parquet(tmp_path / f) for f in ("a.parquet", "b.parquet"))
    assert (ta["status"] == "ok").all() and (ta["status"] == tb["status"]).all()
    assert np.abs(ta[["x_s", "y_s", "z_s"]].to_numpy() - tb[["x_s", "y_s", "z_s"]].to_numpy()).max() <= 1e-12
    wc = [60.0, -40.0, 25.0, 8.0, -5.0, 3.0]
    plane = ["plane", "--robot", RC, "--z", "2", "--n", "3"]
    code, out, err = run(capsys, *plane, "--out", tmp_path / "c.parquet", "--wrench", *wc)
    assert code == 0, err
    assert "wrench (60, -40, 25, 8, -5, 3) [N, N m]" in out.splitlines()[0]
    c = run_json(capsys, *plane, "--out", tmp_path / "d.parquet")
    assert "wrench" not in c
    tc, td = (pd.read_parquet(tmp_path / f) for f in ("c.parquet", "d.parquet"))
    assert (tc["status"] == "ok").all()
    assert np.abs(tc[["x_s", "y_s", "z_s"]].to_numpy() - td[["x_s", "y_s", "z_s"]].to_numpy()).max() > 1e-4
