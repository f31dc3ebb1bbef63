"""cdpr.models.platform: rotations, attachment points, the wrench matrix, the orientation error."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.models.platform import (
    attachment_points,
    external_wrench,
    rotation_error,
    rotation_matrix,
    rotvec_of,
    skew,
    wrench_matrix,
)

RNG = np.random.default_rng(17)
ROTVECS = np.vstack([RNG.normal(size=(50, 3)), 1e-10 * RNG.normal(size=(5, 3)), np.zeros((1, 3))])


def test_rodrigues_equals_scipy_from_rotvec_and_round_trips():
    R = rotation_matrix(ROTVECS)
    np.testing.assert_allclose(R, Rotation.from_rotvec(ROTVECS).as_matrix(), atol=1e-14)
    np.testing.assert_allclose(R @ np.swapaxes(R, 1, 2), np.broadcast_to(np.eye(3), R.shape), atol=1e-14)
    back = rotvec_of(R)
    small = np.linalg.norm(ROTVECS, axis=1) < np.pi
    np.testing.assert_allclose(back[small], ROTVECS[small], atol=1e-12)


def test_a_rotation_that_is_not_finite_gives_nan_not_an_error():
    R = rotation_matrix(ROTVECS[:3])
    R[1] = np.nan
    out = rotvec_of(R)
    assert np.isnan(out[1]).all() and np.isfinite(out[[0, 2]]).all()


def test_skew_is_the_cross_product():
    v, w = RNG.normal(size=(2, 20, 3))
    np.testing.assert_allclose(np.einsum("nab,nb->na", skew(v), w), np.cross(v, w), atol=1e-15)


@pytest.mark.parametrize("angle", [0.0, 1e-9, 0.3, 2.0, np.pi - 1e-6])
def test_rotation_error_is_the_angle_of_the_relative_rotation(angle):
    axis = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
    R_d = rotation_matrix(RNG.normal(size=3))
    R_s = rotation_matrix(angle * axis) @ R_d
    assert rotation_error(R_s, R_d) == pytest.approx(angle, abs=1e-12, rel=1e-9)


def test_wrench_columns_are_force_and_moment_about_p():
    """W t equals the sum of the cable forces and of their moments r_i x f_i about p."""
    p = np.array([0.2, -0.1, 1.0])
    R = rotation_matrix(np.array([0.1, 0.2, -0.3]))
    b = RNG.normal(size=(6, 3))
    B = attachment_points(p, R, b)
    np.testing.assert_allclose(B, p + b @ R.T, atol=1e-15)
    u = RNG.normal(size=(6, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    t = RNG.uniform(10, 100, 6)
    W = wrench_matrix(u, B - p)
    f = t[:, None] * u
    np.testing.assert_allclose(W @ t, np.concatenate([f.sum(0), np.cross(B - p, f).sum(0)]), atol=1e-12)


def test_gravity_wrench_acts_at_the_centre_of_mass():
    R = rotation_matrix(np.array([0.0, 0.4, 0.0]))
    c = np.array([0.1, 0.0, 0.3])
    w = external_wrench(10.0, 9.81, c, R)
    np.testing.assert_allclose(w[:3], [0.0, 0.0, -98.1])
    np.testing.assert_allclose(w[3:], np.cross(R @ c, [0.0, 0.0, -98.1]), atol=1e-12)
