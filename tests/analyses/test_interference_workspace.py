"""The interference-free workspace of a grid at a fixed orientation (issue 39,
``cdpr.analyses.interference``): its counts, volume and largest box agree with the per-pose
interference, and the cable-platform depth of CoGiRo's grid agrees with dense sampling."""

from __future__ import annotations

import numpy as np
import pytest

from cdpr.analyses.interference import grid_of, interference_workspace
from cdpr.analyses.workspace import frame_box, grid_points
from cdpr.errors import CdprError
from cdpr.models.interference import cable_segments, interference, platform_faces
from cdpr.models.platform import rotation_matrix
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

COGIRO = ROBOTS / "cogiro_massless.yaml"


def test_grid_of_is_the_cell_centred_grid_in_c_order():
    box = [-1.0, 1.0, -2.0, 2.0, 0.0, 3.0]
    P, shape = grid_of(box, 4)
    np.testing.assert_array_equal(P, grid_points(box, 4))
    P, shape = grid_of(box, (3, 2, 5))
    assert shape == (3, 2, 5) and P.shape == (30, 3)
    assert P[1, 2] > P[0, 2] and P[5, 1] > P[0, 1] and P[10, 0] > P[0, 0]  # z fastest, x slowest
    with pytest.raises(CdprError, match="three counts"):
        grid_of(box, (3, 0, 2))


def test_cogiro_workspace_is_its_poses_interference():
    """A 7 x 7 x 5 grid over CoGiRo's frame, turned 15 degrees about z: the free voxels are the
    free poses, the volume their count times the voxel, every voxel of the largest box is free,
    and the intersection with the wrench-feasible workspace is within both."""
    robot = load_robot(COGIRO)
    box = frame_box(robot)
    rv = [0.0, 0.0, np.radians(15)]
    w = interference_workspace(robot, box, (7, 7, 5), rv, wrench_feasible=True)
    P, shape = grid_of(box, (7, 7, 5))
    free = interference(robot, P, rv).free
    np.testing.assert_array_equal(w["free"], free)
    voxel = np.prod([(box[2 * a + 1] - box[2 * a]) / n for a, n in enumerate(shape)])
    assert w["free_points"] == free.sum() and w["fraction"] == pytest.approx(free.mean())
    assert w["volume_m3"] == pytest.approx(free.sum() * voxel)
    assert 0 < w["free_points"] < w["points"] == 245 and w["cp_points"] > 0  # a real restriction
    b = w["box"]
    inside = (
        (P[:, 0] > b[0])
        & (P[:, 0] < b[1])
        & (P[:, 1] > b[2])
        & (P[:, 1] < b[3])
        & (P[:, 2] > b[4])
        & (P[:, 2] < b[5])
    )
    assert free[inside].all() and w["box_m3"] == pytest.approx(inside.sum() * voxel)
    assert w["box_m3"] == pytest.approx((b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]))
    both = w["free"] & w["feasible"]
    assert w["free_feasible_points"] == both.sum() <= min(w["free_points"], w["feasible_points"])
    assert w["free_feasible_box_m3"] <= w["box_m3"] + 1e-9


def test_cable_platform_depth_against_dense_sampling():
    """CoGiRo's hull over a 9 x 9 x 5 grid of its frame at a tilt: the exact depth of every cable's
    chord is never below the depth of 2001 points sampled on the segment and above it by at most
    the sampling's resolution; the cables found inside are those the sampling finds inside."""
    robot = load_robot(COGIRO)
    P, _ = grid_of(frame_box(robot), (9, 9, 5))
    rv = np.array([0.1, -0.05, 0.2])
    res = interference(robot, P, rv)
    faces = platform_faces(robot)
    R = np.broadcast_to(rotation_matrix(rv), (len(P), 3, 3))
    B, D = cable_segments(robot, P, R)
    u = np.linspace(0.0, 1.0, 2001)
    X = B[:, :, None, :] + u[None, None, :, None] * (D - B)[:, :, None, :] - P[:, None, None, :]
    x = np.einsum("ba,nmub->nmua", R[0], X)  # R^T (X - p) in the platform frame
    sampled = np.max(np.min(-(np.einsum("nmua,fa->nmuf", x, faces[:, :3]) + faces[:, 3]), axis=-1), axis=-1)
    sampled = np.maximum(sampled, 0.0)
    step = np.linalg.norm(D - B, axis=-1) / 2000
    assert (res.depth >= sampled - 1e-12).all()
    assert (res.depth <= sampled + step).all()
    clear = (res.depth > 1e-3) | (res.depth < 1e-12)  # away from the sampling's resolution
    np.testing.assert_array_equal(res.cp[clear], (sampled > 1e-9)[clear])
    assert res.cp.any() and not res.cp.all()
