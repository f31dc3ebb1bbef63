"""Inverse geometric models (cdpr.models.inverse, Paty 2021 eq. 1-7): the attachment points of a point
mass and of a rigid platform (against scipy's rotations), the standard lengths as distances plus the
dead length, the extended model's limits (point pulleys: the standard model), the robot's mirror
symmetry (the mirrored point gives the mirrored cables' lengths), and a rigid motion of the whole
robot (same lengths). The pulley geometry itself: tests/models/test_pulleys.py."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.errors import CdprError
from cdpr.models.inverse import L_TS, attachments, igm_e, l_S
from cdpr.robot import load_robot, read_yaml, robot_from_dict, with_pulleys
from tests.conftest import ROBOTS

rng = np.random.default_rng(21)
PTS = np.column_stack([rng.uniform(-2.2, 2.2, 40), rng.uniform(-2.2, 2.2, 40), rng.uniform(0.3, 4.5, 40)])
ROTVECS = rng.uniform(-0.3, 0.3, (40, 3))


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro.yaml")


def test_a_point_mass_is_attached_at_its_position_whatever_the_orientation(cdpr4):
    B, per_cable = attachments(cdpr4, PTS)
    assert not per_cable and np.array_equal(B, PTS)
    poses = np.column_stack([PTS, ROTVECS])
    B6, per_cable = attachments(cdpr4, poses)
    assert not per_cable and np.array_equal(B6, PTS)
    np.testing.assert_array_equal(l_S(cdpr4, poses), l_S(cdpr4, PTS))


def test_a_rigid_platform_is_attached_at_p_plus_R_b(cogiro):
    B, per_cable = attachments(cogiro, PTS, ROTVECS)
    R = Rotation.from_rotvec(ROTVECS).as_matrix()  # an independent implementation
    assert per_cable and B.shape == (40, cogiro.m, 3)
    np.testing.assert_allclose(B, PTS[:, None] + np.einsum("nab,mb->nma", R, cogiro.arrays.b), atol=1e-12)
    # poses (N, 6) and positions with rotvec say the same; no rotvec is the identity
    np.testing.assert_array_equal(attachments(cogiro, np.column_stack([PTS, ROTVECS]))[0], B)
    np.testing.assert_allclose(attachments(cogiro, PTS)[0], PTS[:, None] + cogiro.arrays.b, atol=1e-15)
    # one orientation for every position broadcasts
    one = attachments(cogiro, PTS, ROTVECS[0])[0]
    np.testing.assert_allclose(one[5], attachments(cogiro, PTS[5:6], ROTVECS[0])[0][0], atol=1e-15)


@pytest.mark.parametrize("shape", [(4,), (10, 2), (3, 5)])
def test_a_point_of_the_wrong_shape_is_refused_naming_the_shape(cdpr4, cogiro, shape):
    for robot in (cdpr4, cogiro):
        with pytest.raises(
            CdprError, match=rf"positions \(\.\.\., 3\) \[m\] or poses \(N, 6\).*got shape \({shape[0]},"
        ):
            l_S(robot, np.zeros(shape))
    with pytest.raises(
        CdprError, match=r"poses of a rigid platform are \(N, 3\) or \(N, 6\), got shape \(2, 2, 3\)"
    ):
        l_S(cogiro, np.zeros((2, 2, 3)))


def test_standard_lengths_are_distances_plus_the_dead_length(cdpr4, cogiro):
    np.testing.assert_allclose(l_S(cdpr4, PTS), np.linalg.norm(PTS[:, None] - cdpr4.A, axis=2), rtol=1e-15)
    np.testing.assert_allclose(L_TS(cdpr4, PTS), l_S(cdpr4, PTS) + cdpr4.d, rtol=1e-15)
    B, _ = attachments(cogiro, PTS, ROTVECS)
    np.testing.assert_allclose(l_S(cogiro, PTS, ROTVECS), np.linalg.norm(B - cogiro.A, axis=2), rtol=1e-15)
    # a single point keeps its shape: (m,) lengths
    assert l_S(cdpr4, PTS[0]).shape == (cdpr4.m,)


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_point_pulleys_give_the_standard_model_on_a_rigid_platform(cogiro, kind):
    """h = r_p = 0: the extended length is the standard one at poses too (eq. 5 -> eq. 2)."""
    r = with_pulleys(cogiro, kind=kind, h=0.0, r_p=0.0)
    np.testing.assert_allclose(igm_e(r, PTS, ROTVECS).L_TE, L_TS(r, PTS, ROTVECS), rtol=0, atol=1e-12)
    assert np.abs(igm_e(cogiro, PTS, ROTVECS).L_TE - L_TS(cogiro, PTS, ROTVECS)).max() > 1e-4


#: CDPR4's cables under the mirror x -> -x (anchors at (-2.5, -2.5), (2.5, -2.5), (2.5, 2.5), (-2.5, 2.5)).
MIRROR_X = [1, 0, 3, 2]


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_the_mirrored_point_gives_the_mirrored_cables_lengths(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    st, mirrored = igm_e(r, PTS), igm_e(r, PTS * [-1.0, 1.0, 1.0])
    np.testing.assert_allclose(mirrored.L_TE, st.L_TE[:, MIRROR_X], rtol=1e-13)
    np.testing.assert_allclose(mirrored.D, st.D[:, MIRROR_X] * [-1.0, 1.0, 1.0], atol=1e-12)
    if kind != "fixed":
        assert np.abs(st.L_TE[:, 0] - st.L_TE[:, 1]).max() > 1e-2  # the check compares different numbers


def test_moving_the_whole_robot_and_the_point_together_changes_no_length(cdpr4):
    data = read_yaml(ROBOTS / "cdpr4.yaml")
    shift = np.array([10.0, -3.0, 0.0])  # horizontal: the floor (z = 0) stays under the robot
    for cable in data["cables"]:
        cable["A_m"] = (np.asarray(cable["A_m"]) + shift).tolist()
    moved = robot_from_dict(data)
    for kind in ("SR", "DR"):
        a, b = with_pulleys(cdpr4, kind=kind), with_pulleys(moved, kind=kind)
        np.testing.assert_allclose(igm_e(b, PTS + shift).L_TE, igm_e(a, PTS).L_TE, rtol=1e-12)
        np.testing.assert_allclose(igm_e(b, PTS + shift).D, igm_e(a, PTS).D + shift, atol=1e-12)
