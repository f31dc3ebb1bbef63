"""The ``out_of_frame`` status (issue 41): a solved pose whose reference point P* lies more than
``FRAME_TOL`` outside the frame box (the anchors' bounding box extended down to the floor) is not
``ok``, in physical mode (paper mode follows the paper, which has no frame: docs/models.md), every
engine, table and JSON output."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from cdpr import solve, tables
from cdpr.models.results import FRAME_TOL, STATUSES, frame_bounds, mark_out_of_frame
from cdpr.robot import robot_from_dict

ROOT = Path(__file__).resolve().parents[2]


def three_cables():
    """CoGiRo's rigid platform hung on its first 3 cables only (issue 41's "rigid platform on 3
    cables"): at a desired pose in the middle of the frame it swings, tilts and sinks below the floor."""
    data = yaml.safe_load((ROOT / "config" / "robots" / "cogiro.yaml").read_text())
    data["cables"] = data["cables"][:3]
    return data


@pytest.fixture(scope="module")
def three():
    return robot_from_dict(three_cables())


def test_status_is_listed_last():
    """New status appended: the codes of the older ones are unchanged."""
    assert STATUSES[-1] == "out_of_frame"
    assert STATUSES[:5] == ("ok", "slack", "over_tension", "inaccessible", "not_converged")


def test_frame_bounds_extend_down_to_the_floor(three, cdpr4):
    lo, hi = frame_bounds(three)
    A = three.A
    np.testing.assert_array_equal(lo, [*A[:, :2].min(axis=0), 0.0])  # the floor z = 0 lies below every anchor
    np.testing.assert_array_equal(hi, A.max(axis=0))
    lo4, hi4 = frame_bounds(cdpr4)
    assert lo4[2] == cdpr4.floor_z and hi4[2] == cdpr4.A[:, 2].max()


def test_mark_out_of_frame_changes_only_solved_poses_beyond_the_tolerance(three):
    lo, hi = frame_bounds(three)
    x, y = (lo[:2] + hi[:2]) / 2  # the box's centre seen from above
    P = np.array(
        [
            [x, y, -0.5 * FRAME_TOL],  # inside the tolerance: stays ok
            [x, y, -2.0 * FRAME_TOL],  # below the floor: out_of_frame
            [hi[0] + 0.1, y, 0.5],  # beyond the x range, over tension: out_of_frame
            [x, y, -1.0],  # far out but not converged: stays
            [np.nan, np.nan, np.nan],  # no pose: stays
        ]
    )
    status = np.array(["ok", "ok", "over_tension", "not_converged", "ok"])
    res = {"P_s": P, "status": status, "status_code": np.array([STATUSES.index(s) for s in status], np.int8)}
    mark_out_of_frame(res, three)
    assert list(res["status"]) == ["ok", "out_of_frame", "out_of_frame", "not_converged", "ok"]
    assert [STATUSES[c] for c in res["status_code"]] == list(res["status"])


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
def test_rigid_platform_on_three_cables_below_the_floor_is_out_of_frame(three, engine):
    """The issue's case: the solve converges to a pose below the floor, which was reported ok."""
    res = solve.solve(three, [[0.0, 0.0, 2.0]], rotvec=[0.0, 0.0, 0.0], engine=engine)
    assert res["P_s"][0, 2] < -1.0, res["P_s"]  # the physics: it does hang below the floor
    assert res["status"][0] == "out_of_frame"
    assert STATUSES[res["status_code"][0]] == "out_of_frame"
    df = tables.solve_table(three, [[0.0, 0.0, 2.0]], rotvec=[0.0, 0.0, 0.0], engine=engine)
    assert df["status"].tolist() == ["out_of_frame"] and "n_taut" in df.columns


def test_the_same_pose_on_all_eight_cables_stays_ok():
    """The rule does not fire on a pose the robot holds inside its frame."""
    cogiro = robot_from_dict(yaml.safe_load((ROOT / "config" / "robots" / "cogiro.yaml").read_text()))
    res = solve.solve(cogiro, [[0.0, 0.0, 2.0]], rotvec=[0.0, 0.0, 0.0], engine="numpy")
    assert res["status"][0] == "ok"


def test_point_json_says_out_of_frame(three, tmp_path):
    """``cdpr point --json`` carries the status (every mode, every output)."""
    path = tmp_path / "three.yaml"
    path.write_text(yaml.safe_dump(three_cables()))
    out = subprocess.run(
        [sys.executable, "-m", "cdpr", "point", "--robot", str(path), "--at", "0", "0", "2", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(out.stdout)["status"] == "out_of_frame"
    assert "RuntimeWarning" not in out.stderr


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
def test_anchors_in_the_origin_plane_hang_the_platform_below(engine):
    """A frame written with its origin in the anchors' plane (every anchor at z = 0, the platform
    hanging at negative z, as cdpyr writes robots) without ``frame.floor_z_m``: the default floor
    lies the anchors' horizontal extent below them, so the robot is the suspended point mass it is,
    and physical mode gives CDPR4's answer shifted down, ``ok`` (it was ``out_of_frame`` at every
    hanging pose: a frame box of no height)."""
    data = yaml.safe_load((ROOT / "config" / "robots" / "cdpr4.yaml").read_text())
    shifted = yaml.safe_load((ROOT / "config" / "robots" / "cdpr4.yaml").read_text())
    top = max(c["A_m"][2] for c in data["cables"])
    for c in shifted["cables"]:
        c["A_m"][2] -= top
    assert all(c["A_m"][2] == 0.0 for c in shifted["cables"])
    a, b = robot_from_dict(data), robot_from_dict(shifted)
    A = b.A
    assert b.floor_z == -float((A[:, :2].max(axis=0) - A[:, :2].min(axis=0)).max())
    assert b.suspended_point_mass
    P = np.array([[0.5, -0.3, 1.2], [-1.0, 0.8, 2.5], [0.0, 0.0, 0.6]])
    ra = solve.solve(a, P, redundancy="physical", engine=engine)
    rb = solve.solve(b, P - [0.0, 0.0, top], redundancy="physical", engine=engine)
    assert list(rb["status"]) == ["ok"] * 3 == list(ra["status"])
    np.testing.assert_allclose(rb["P_s"], ra["P_s"] - [0.0, 0.0, top], atol=1e-9)
    # a Hangprinter-like frame (some anchors above z = 0, some not) keeps the lowest anchor's height
    mixed = yaml.safe_load((ROOT / "config" / "robots" / "cdpr4.yaml").read_text())
    mixed["cables"][0]["A_m"][2] = -0.1
    assert robot_from_dict(mixed).floor_z == -0.1
