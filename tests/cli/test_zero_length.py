"""Issue 41: a zero-length cable (the platform's attachment at its anchor) in ``compensate``,
``grid`` and ``plane``, as ``point`` already does (tests/cli/test_status.py): the point is flagged
with a reason, no numpy warning and no traceback reaches the user (any warning is an error here)."""

import json
import warnings

import pandas as pd
import yaml

from cdpr.cli.main import main
from cdpr.models.tension_distribution import defined_rows, distribute_pose
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

HANG = str(ROBOTS / "hang4_6dof.yaml")
#: The pose that puts cable 1's attachment B_1 = (-0.2, -0.2, 0) at its anchor A_1 = (-2.5, -2.5, 5).
AT = ["-2.3", "-2.3", "5"]
FIXED = ["--robot", HANG, "--pulley", "fixed", "--dead-length", "0", "--engine", "numpy"]


def run(argv):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(argv) == 0


def test_the_distribution_is_infeasible_where_a_cable_has_no_direction():
    """W is 0/0 in cable 1's column there: infeasible, finite elsewhere (no LAPACK failure)."""
    robot = load_robot(HANG, pulley="fixed", dead_length=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        import numpy as np

        with np.errstate(all="ignore"):  # the wrench matrix itself divides 0 by 0 at that pose
            d = distribute_pose(robot, [[-2.3, -2.3, 5.0], [0.0, 0.0, 2.0]], [0.0, 0.0, 0.0])
    assert d["feasible"].tolist() == [False, True]
    assert np.isnan(d["t"][0]).all() and np.isfinite(d["t"][1]).all()
    W, defined = defined_rows(np.array([np.full((6, 4), np.nan), np.ones((6, 4))]))
    assert defined.tolist() == [False, True] and np.isfinite(W).all()


def test_compensate_at_the_pose_is_infeasible_with_a_reason(capsys):
    run(["compensate", *FIXED, "--at", *AT, "--rotvec", "0", "0", "0", "--json"])
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert out["status"] == "infeasible" and cap.err == ""
    assert out["reason"].startswith("cable 1 has zero length (the attachment at its anchor)")
    run(["compensate", *FIXED, "--at", *AT, "--rotvec", "0", "0", "0"])
    assert "reason: cable 1 has zero length" in capsys.readouterr().out


def test_compensate_points_flags_the_row_and_says_why(capsys, tmp_path):
    pts = tmp_path / "p.csv"
    pts.write_text("x,y,z\n-2.3,-2.3,5\n0,0,2\n")
    out = tmp_path / "c.csv"
    run(["compensate", *FIXED, "--points", str(pts), "--rotvec", "0", "0", "0", "--out", str(out)])
    assert pd.read_csv(out)["status"].tolist() == ["infeasible", "ok"]
    err = capsys.readouterr().err
    assert "1 point(s) have a cable of zero length" in err and "Traceback" not in err


def test_grid_wrench_feasible_flags_the_point_and_says_why(capsys, tmp_path):
    out = tmp_path / "g.csv"
    box = ["-2.5", "-2.1", "-2.5", "-2.1", "4.8", "5.2"]  # one cell, centred at the pose
    run(
        [
            "grid",
            *FIXED,
            "--box",
            *box,
            "--n",
            "1",
            "--rotvec",
            "0",
            "0",
            "0",
            "--wrench-feasible",
            "--out",
            str(out),
        ]
    )
    df = pd.read_csv(out)
    assert df["status"].tolist() == ["not_converged"] and df["feasible"].tolist() == [False]
    err = capsys.readouterr().err
    assert "1 point(s) have a cable of zero rest length" in err
    assert "1 point(s) have a cable of zero length" in err and "not wrench-feasible" in err


def test_plane_says_why(capsys, tmp_path):
    """A plane whose first cell centre puts B_1 at A_1: B_1 moved to (-0.25, -0.25, 0) so that the
    pose (-2.25, -2.25, 5) is the first centre of a 10 x 10 plane at z = 5."""
    data = yaml.safe_load(open(HANG))
    data["cables"][0]["B_m"] = [-0.25, -0.25, 0.0]
    robot = tmp_path / "hang.yaml"
    robot.write_text(yaml.safe_dump(data))
    out = tmp_path / "plane.csv"
    argv = ["plane", "--robot", str(robot), "--pulley", "fixed", "--dead-length", "0", "--engine", "numpy"]
    run([*argv, "--z", "5", "--n", "10", "--rotvec", "0", "0", "0", "--out", str(out)])
    df = pd.read_csv(out)
    row = df[(df.x == -2.25) & (df.y == -2.25)]
    assert len(row) == 1 and row["status"].iloc[0] != "ok"
    assert "1 point(s) have a cable of zero rest length" in capsys.readouterr().err
