"""cdpr.analyses.scans.pose_geometry and view_position: the points a picture of a robot draws, checked
by geometry (rigid-body placement, tangency of the cables to the sheaves, the winch exit points)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.analyses import scans, workspace
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

SPATIAL = ["cogiro.yaml", "wall_pulleys.yaml", "hang4_6dof.yaml"]


@pytest.mark.parametrize("name", SPATIAL + ["cdpr4.yaml"])
def test_the_cables_are_tangent_to_their_sheaves_at_both_tangent_points(name):
    """K_i and D_i lie on the sheave circle (radius r_p about H_i); the free cable D_i -> B_i and the
    dead length C_i -> K_i are perpendicular to the radius at their tangent point; the drawn circle is
    that circle, in the plane of the swivel axis and the cable."""
    robot = load_robot(ROBOTS / name)
    g = scans.pose_geometry(robot, [0.4, -0.3, 1.8], None if robot.point_mass else [0.1, -0.2, 0.3])
    r_p = np.asarray(robot.r_p, dtype=float)
    for T in (g["K"], g["D"]):
        np.testing.assert_allclose(np.linalg.norm(T - g["H"], axis=1), r_p, rtol=1e-12)
    radial = (g["D"] - g["H"]) / r_p[:, None]
    free = (g["B"] - g["D"]) / np.linalg.norm(g["B"] - g["D"], axis=1)[:, None]
    assert np.abs((radial * free).sum(axis=1)).max() < 1e-9
    radial_k = (g["K"] - g["H"]) / r_p[:, None]
    dead = (g["K"] - g["C"]) / np.linalg.norm(g["K"] - g["C"], axis=1)[:, None]
    assert np.abs((radial_k * dead).sum(axis=1)).max() < 1e-9
    rel = g["sheave"] - g["H"][:, None, :]
    np.testing.assert_allclose(
        np.linalg.norm(rel, axis=2), np.broadcast_to(r_p[:, None], rel.shape[:2]), rtol=1e-12
    )
    normal = np.cross(g["axis"], g["D"] - g["H"])
    assert np.abs(np.einsum("mkc,mc->mk", rel, normal)).max() < 1e-12
    np.testing.assert_allclose(g["C"], robot.A - robot.arrays.d[:, None] * g["axis"], rtol=0, atol=1e-15)


def test_the_platform_is_placed_as_a_rigid_body():
    """B_i - p = R b_i with R the rotation of the rotation vector (scipy's, an independent
    implementation), the centre of mass likewise; distances between attachments are kept."""
    robot = load_robot(ROBOTS / "cogiro.yaml")
    p, rv = np.array([1.0, -0.5, 2.0]), np.array([0.2, -0.1, 0.4])
    g = scans.pose_geometry(robot, p, rv)
    R = Rotation.from_rotvec(rv).as_matrix()
    np.testing.assert_allclose(g["R"], R, atol=1e-12)
    np.testing.assert_allclose(g["B"] - p, robot.arrays.b @ R.T, atol=1e-12)
    np.testing.assert_allclose(g["com"] - p, R @ robot.arrays.com, atol=1e-12)
    d0 = np.linalg.norm(robot.arrays.b[:, None] - robot.arrays.b[None], axis=2)
    np.testing.assert_allclose(np.linalg.norm(g["B"][:, None] - g["B"][None], axis=2), d0, atol=1e-12)
    assert g["rotvec"].tolist() == rv.tolist() and not g["point_mass"] and g["name"] == robot.name
    # identity by default: the attachments are the platform's own points shifted to p
    np.testing.assert_allclose(scans.pose_geometry(robot, p)["B"], robot.arrays.b + p, atol=1e-15)


def test_a_fixed_pulley_has_no_sheave_circle():
    robot = load_robot(ROBOTS / "cdpr4.yaml", pulley="fixed")
    g = scans.pose_geometry(robot, [0.0, 0.0, 2.0])
    assert np.isnan(g["sheave"]).all() and g["point_mass"]
    np.testing.assert_allclose(g["B"], np.tile([0.0, 0.0, 2.0], (4, 1)))


@pytest.mark.parametrize("name", SPATIAL + ["cdpr4.yaml", "cdpr3.yaml"])
def test_the_default_position_is_inside_the_frame_box(name):
    robot = load_robot(ROBOTS / name)
    p = scans.view_position(robot)
    b = workspace.frame_box(robot)
    assert all(b[2 * a] < p[a] < b[2 * a + 1] for a in range(3))
    A = robot.A
    np.testing.assert_allclose(p[:2], A[:, :2].mean(axis=0))
    if robot.suspended_point_mass:  # 60 % of the anchors' mid-height: CDPR4's 5 m anchors give 3 m
        assert p[2] == pytest.approx(0.3 * (A[:, 2].min() + A[:, 2].max()))
    else:  # the frame's mid-height (CoGiRo: 0 to 5.42 m)
        assert p[2] == pytest.approx(0.5 * (b[4] + b[5]))
