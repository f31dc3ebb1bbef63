"""cdpr.analyses.scans: the points a picture of a robot draws (pose_geometry, view_position), checked
by geometry (rigid-body placement, tangency of the cables to the sheaves, the winch exit points); the
paths and planes of points (by construction and by the robot's symmetry), the extremes and
crossings of curves (on curves whose answer is known), and the winch table (round trips through the
drum models)."""

import numpy as np
import pandas as pd
import pytest
from scipy.spatial.transform import Rotation

from cdpr.analyses import scans, workspace
from cdpr.models import winch
from cdpr.robot import TABLE1, load_robot, with_pulleys
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


# ---- paths and planes of points --------------------------------------------------------------
def test_trajectory_points_are_evenly_spaced_on_the_segment_with_their_arc_length():
    start, end = np.array([-1.0, 0.5, 1.0]), np.array([2.0, -1.5, 3.5])
    P, s = scans.trajectory_points(start, end, 7)
    assert P.shape == (7, 3) and s.shape == (7,)
    np.testing.assert_allclose(P[[0, -1]], [start, end], atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(P - start, axis=1), s, rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(np.diff(s), np.linalg.norm(end - start) / 6, rtol=1e-13)
    # every point on the line: no component across the direction of the segment
    u = (end - start) / np.linalg.norm(end - start)
    across = (P - start) - ((P - start) @ u)[:, None] * u
    assert np.abs(across).max() < 1e-14


@pytest.mark.parametrize("redundancy", ["paper", "physical"])
def test_a_path_through_the_centre_of_cdpr4_has_a_mirrored_error_curve(cdpr4, redundancy):
    """CDPR4 is invariant under the half turn about its vertical centre line (anchors at (+-2.5,
    +-2.5)): a path symmetric under it, walked backwards, is the same path, so |dp|(s) = |dp|(L - s)
    and the solved points are the half-turned ones read backwards. Paper mode holds the centre on
    three of the four cables (a subset the half turn does not map to itself), so there the check
    leaves the middle point out; physical mode holds it on all four, so it keeps it."""
    for kind in ("SR", "DR"):
        robot = with_pulleys(cdpr4, kind=kind)
        df = scans.trajectory(
            robot, [-1.2, -0.7, 2.2], [1.2, 0.7, 2.2], 9, redundancy=redundancy, engine="numpy"
        )
        assert list(df.columns[:4]) == ["s", "x", "y", "z"] and len(df) == 9
        assert (df["status"] == "ok").all() and (df["dp"] > 1e-5).all()
        np.testing.assert_allclose(df["s"], np.linspace(0, np.hypot(2.4, 1.4), 9), rtol=1e-14)
        np.testing.assert_allclose(df["dp"].to_numpy(), df["dp"].to_numpy()[::-1], rtol=1e-7, atol=0)
        sol = df[["x_s", "y_s", "z_s"]].to_numpy()
        turned = sol[::-1] * [-1.0, -1.0, 1.0]
        rows = np.arange(9) if redundancy == "physical" else np.r_[0:4, 5:9]
        np.testing.assert_allclose(sol[rows], turned[rows], atol=1e-9)


def test_plane_points_are_cell_centres_at_height_z(cdpr4):
    n, z = 4, 1.7
    P = scans.plane_points(cdpr4, z, n)
    assert P.shape == (n * n, 3) and (P[:, 2] == z).all()
    # 5 m between anchors (x, y in [-2.5, 2.5]): cells of 1.25 m, centres 0.625 m from the edges
    centres = [-1.875, -0.625, 0.625, 1.875]
    np.testing.assert_allclose(np.unique(P[:, 0]), centres)
    np.testing.assert_allclose(np.unique(P[:, 1]), centres)
    assert (np.diff(P[:, 0]) >= 0).all() and P[1, 1] > P[0, 1]  # x slowest, then y
    df = scans.plane(cdpr4, z, n, engine="numpy")
    np.testing.assert_allclose(df[["x", "y", "z"]].to_numpy(), P)


# ---- extremes and crossings ------------------------------------------------------------------
def test_ok_extremes_read_only_the_ok_rows():
    df = pd.DataFrame(
        {"dp": [5.0, 1.0, 0.2, 3.0, 9.0], "dphi": [0.1, 0.4, 0.2, 0.3, 7.0]}
        | {"status": ["ok", "ok", "slack", "ok", "inaccessible"]}
    )
    assert scans.ok_extremes(df) == (1.0, 5.0)
    assert scans.ok_extremes(df, "dphi") == (0.1, 0.4)
    none = df.assign(status="slack")
    assert all(np.isnan(v) for v in scans.ok_extremes(none))


def test_crossings_of_two_lines_are_found_exactly():
    """a - b linear in s between samples: the interpolated crossing is the exact one."""
    s = np.linspace(0.0, 3.0, 7)
    a = 2.0 * s - 1.0  # crosses b = 0.5 at s = 0.75, between samples 0.5 and 1.0
    assert scans.crossings(s, a, np.full_like(s, 0.5)) == pytest.approx([0.75], abs=1e-15)
    # two crossings of a parabola sampled finely enough; the curves' order does not matter
    s = np.linspace(0.0, 4.0, 4001)
    got = scans.crossings(s, (s - 1.0) * (s - 3.0), np.zeros_like(s))
    assert got == pytest.approx([1.0, 3.0], abs=1e-6)
    assert scans.crossings(s, np.zeros_like(s), (s - 1.0) * (s - 3.0)) == pytest.approx(got)


def test_crossings_skip_nan_points_and_count_a_touch_on_a_sample_once():
    s = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    a = np.array([-1.0, np.nan, 1.0, 0.0, -2.0])  # NaN dropped: -1 -> 1 between s = 0 and 2
    got = scans.crossings(s, a, np.zeros(5))
    assert got == pytest.approx([1.0, 3.0])  # s = 3 lands on a sample: counted once
    assert scans.crossings(s, np.ones(5), np.zeros(5)) == []


# ---- winch table (Métillon 2022, Fig. 7) ------------------------------------------------------
def test_winch_table_roots_realise_their_lengths():
    """q1 is the drum angle that realises l_pm (eq. 15-17 give l_pm back), q_nw the angle of the
    no-winch model (its own inverse gives l_pm back), dl = k_w (q1 - q_nw) the length error."""
    df = scans.winch_table(TABLE1, 0.5, 4.5, 9)
    assert list(df.columns) == ["l_pm", "q1", "q2", "q_nw", "dl"] and len(df) == 9
    np.testing.assert_allclose(df["l_pm"], np.linspace(0.5, 4.5, 9))
    np.testing.assert_allclose(winch.l_pm_of_q(TABLE1, df["q1"].to_numpy()), df["l_pm"], atol=1e-10)
    np.testing.assert_allclose(
        winch.l_pm_of_q_no_winch(TABLE1, df["q_nw"].to_numpy()), df["l_pm"], atol=1e-12
    )
    np.testing.assert_allclose(df["dl"], winch.length_error(TABLE1, df["l_pm"].to_numpy()), rtol=1e-12)
    assert (df["q1"] != df["q2"]).all() and (np.abs(df["dl"]) < 2e-3).all()
