"""``cdpr calibrate plan`` on a rigid platform (issue 41): candidates at one orientation cannot
separate an anchor A_i from an attachment b_i (the D-optimal plan then left every b_i near its
prior sd), so the candidates are also tilted by ±10° about x, y and z; a group the plan still cannot
see is named in a warning (JSON ``warnings`` and one stderr line)."""

import json

import numpy as np

from cdpr.analyses.calibration import design
from cdpr.cli.main import main
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

COGIRO = ROBOTS / "cogiro.yaml"
ARGS = dict(groups=["anchors", "attachments"], n=30, n_axis=3)


def _ratios(res):
    """max sd / prior sd of each group's parameters (A_..., b_...)."""
    r = res["sd_d_optimal"] / res["prior_sd"]
    return {g: float(max(v for v, nm in zip(r, res["names"]) if nm[0] == g)) for g in ("A", "b")}


def test_candidate_orientations():
    t = design.TILT_RAD
    assert np.isclose(t, np.deg2rad(10.0))
    rv = design.candidate_orientations(load_robot(COGIRO))
    assert rv.shape == (7, 3) and (rv[0] == 0).all()
    assert sorted(map(tuple, rv[1:])) == sorted(
        tuple(s * t * np.eye(3)[k]) for k in range(3) for s in (1.0, -1.0)
    )
    assert design.candidate_orientations(load_robot(ROBOTS / "cdpr4.yaml")).shape == (1, 3)  # a point mass


def test_tilted_candidates_let_the_plan_see_the_attachments(monkeypatch):
    robot = load_robot(COGIRO)
    tilted = design.plan(robot, **ARGS)
    assert tilted["warnings"] == []
    assert _ratios(tilted)["b"] < 0.7  # every b_i's sd at most 70 % of its prior
    monkeypatch.setattr(design, "candidate_orientations", lambda robot: np.zeros((1, 3)))  # the old plan
    flat = design.plan(robot, **ARGS)
    assert _ratios(flat)["b"] >= design.BLIND_RATIO > _ratios(tilted)["b"]
    assert len(flat["warnings"]) == 1 and flat["warnings"][0].startswith(
        "the plan cannot see group 'attachments'"
    )
    assert flat["n_candidates"] < tilted["n_candidates"]


def test_cli_plan_warns_on_stderr_and_in_json(monkeypatch, capsys):
    monkeypatch.setattr(design, "candidate_orientations", lambda robot: np.zeros((1, 3)))
    argv = ["calibrate", "plan", "--robot", str(COGIRO), "--estimate", "anchors,attachments", "--n", "30"]
    assert main([*argv, "--grid", "3", "--json"]) == 0
    cap = capsys.readouterr()
    assert json.loads(cap.out)["warnings"][0].startswith("the plan cannot see group 'attachments'")
    assert cap.err.startswith("cdpr: warning: the plan cannot see group 'attachments'")
