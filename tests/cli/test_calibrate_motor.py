"""``cdpr calibrate fit | check | cv`` on motor-angle data: the shipped Hangprinter sessions (issue 40)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cdpr.analyses import calibration as cal
from cdpr.cli.main import main
from cdpr.robot import load_robot

ROOT = Path(__file__).resolve().parents[2]
HP4 = str(ROOT / "config/robots/hangprinter_hp4.yaml")
SERIES2 = str(ROOT / "data/hangprinter/hp4_2022_force_series2_cdpr.csv")
GRID = str(ROOT / "data/hangprinter/hp4_2021_12_grid_cdpr.csv")
TOOL2 = str(ROOT / "data/hangprinter/tool_hp4_2022_force_series2.yaml")

KEYS = (
    "folds",
    "heldout_position_rms_m",
    "heldout_position_median_m",
    "heldout_line_rms_m",
    "train_rms_m",
    "per_sample",
)


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_cv_on_the_shipped_data_runs(capsys):
    argv = ["calibrate", "cv", "--robot", HP4, "--data", SERIES2, "--folds", "5", "--json"]
    out = _json(capsys, [*argv, "--estimate", "anchors,spools", "--prior", "anchors=150mm"])
    for k in KEYS:
        assert k in out
    assert len(out["folds"]) == 5 and len(out["per_sample"]) == 44
    assert sum(r["error_m"] is not None for r in out["per_sample"]) == 9
    assert 0 < out["heldout_position_median_m"] < 0.02  # millimetres, not the nominal robot's centimetres
    again = _json(capsys, [*argv, "--estimate", "anchors,spools", "--prior", "anchors=150mm"])
    assert json.dumps(again) == json.dumps(out)  # deterministic
    tool = _json(
        capsys, ["calibrate", "cv", "--robot", TOOL2, "--data", SERIES2, "--folds", "5", "--fixed", "--json"]
    )
    assert tool["fixed"] and [f["samples"] for f in tool["folds"]] == [f["samples"] for f in out["folds"]]
    grid = _json(
        capsys,
        [
            "calibrate",
            "cv",
            "--robot",
            HP4,
            "--data",
            GRID,
            "--folds",
            "25",
            "--estimate",
            "anchors",
            "--model",
            "standard",
            "--json",
        ],
    )
    assert len(grid["folds"]) == 25 and all(len(f["samples"]) == 1 for f in grid["folds"])


def test_fit_writes_a_robot_that_check_reads(capsys, tmp_path):
    out = tmp_path / "hp.yaml"
    argv = [
        "calibrate",
        "fit",
        "--robot",
        HP4,
        "--data",
        SERIES2,
        "--estimate",
        "anchors,spools",
        "--out",
        str(out),
    ]
    s = _json(capsys, [*argv, "--prior", "anchors=150mm", "--json"])
    assert s["n_parameters"] == 20 and "9 measured positions fix the frame" in s["gauge"]
    rob = load_robot(out)
    est = {p["name"]: p["estimate"] for p in s["parameters"]}
    assert rob.cables[1].A[2] == pytest.approx(est["A_2_z"]) and rob.spools[3].r0 == pytest.approx(
        est["r0_4"]
    )
    assert rob.spools[2].Q == pytest.approx(est["Q_3"])
    chk = _json(capsys, ["calibrate", "check", "--robot", str(out), "--data", SERIES2, "--json"])
    assert chk["n"] == 9 and chk["rms_m"] < 0.01
    # the fit's positions are the nuisance parameters; check solves each from its readings alone
    assert chk["line_rms_m"] == pytest.approx(s["line_rms_m"], rel=0.3)
    assert main([*argv, "--prior", "anchors=150mm"]) == 0
    text = capsys.readouterr().out
    assert "gauge:" in text and "rank 20" in text


@pytest.mark.parametrize(
    "argv, words",
    [
        (["cv", "--folds", "5", "--fixed", "--estimate", "anchors"], "give no --estimate"),
        (["cv", "--folds", "5"], "--estimate: give the groups"),
        (["cv", "--folds", "45", "--estimate", "anchors"], "--folds 45: needs 2 <= K <= 44"),
        (["cv", "--folds", "5", "--estimate", "anchors,moduli"], "estimates anchors, spools only"),
        (["fit", "--estimate", "anchors", "--out", "{d}/x.yaml", "--loss", "huber"], "linear loss only"),
    ],
)
def test_bad_requests_are_one_line(capsys, tmp_path, argv, words):
    argv = [a.format(d=tmp_path) for a in argv]
    assert main(["calibrate", argv[0], "--robot", HP4, "--data", SERIES2, *argv[1:]]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err


def test_bad_data_through_the_command_line(capsys, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("sample,motor_deg_1,motor_deg_2,motor_deg_3,motor_deg_4,force_N_1\n0,0,0,0,0,1\n")
    assert main(["calibrate", "cv", "--robot", HP4, "--data", str(bad), "--folds", "2", "--fixed"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(bad) in err and "force_N_2" in err


def test_check_on_encoder_data_solves_each_position(capsys):
    out = _json(
        capsys, ["calibrate", "check", "--robot", TOOL2, "--data", SERIES2, "--model", "standard", "--json"]
    )
    assert out["n"] == 9 and len(out["samples"]) == 44
    measured = cal.read_motor_data(SERIES2, load_robot(HP4))
    for r, has in zip(out["samples"], measured.has_pose):
        assert (r["error_m"] is not None) == bool(has)
    assert out["rms_m"] < 0.005  # the tool's own solution puts its trusted positions within millimetres
