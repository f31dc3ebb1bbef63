"""Statics of a point mass on cables (cdpr.models.statics, Paty 2021 eq. 10-13) tested by physics and
by numbers that do not come from the module: the batched 3x3 inverse against numpy, the tensions of
a symmetric tripod in closed form and unchanged by a rotation of the whole problem, the equilibrium
residual zero at those tensions, Hooke's law in its limits, and every gradient against central
finite differences."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.models import statics
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.statics import direction_gradient, length_gradient
from cdpr.robot import with_pulleys
from tests.models.test_equilibrium import KINDS, PTS, central_fd, robots


@pytest.mark.parametrize("name", KINDS + ["mixed"])
def test_direction_gradient_matches_finite_differences(cdpr4, name):
    r = robots(cdpr4)[name]
    args = (r.A, r.kind, r.h, r.r_p, r.d, r.inward)
    g = total_length_and_direction(PTS, *args)
    fd = central_fd(lambda P: total_length_and_direction(P, *args).u, PTS, 1e-6)
    assert np.abs(direction_gradient(g) - fd).max() < 1e-7  # |du/dP| ~ 1/|l_E| ~ 0.2-1 /m
    fdL = central_fd(lambda P: total_length_and_direction(P, *args).L_TE, PTS, 1e-6)
    assert np.abs(length_gradient(g) - fdL).max() < 1e-8


def test_inverse3_and_solve3_agree_with_numpy_and_flag_a_singular_member():
    rng = np.random.default_rng(5)
    M = rng.normal(size=(50, 3, 3))
    M[7] = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]]  # rank 2
    inv, det = statics.inverse3(M)
    good = np.arange(50) != 7
    np.testing.assert_allclose(inv[good], np.linalg.inv(M[good]), rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(det, np.linalg.det(M), rtol=1e-10, atol=1e-14)
    assert np.isnan(inv[7]).all() and np.isfinite(inv[good]).all()
    b = rng.normal(size=(50, 3))
    x, det2 = statics.solve3(M, b)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", M[good], x[good]), b[good], atol=1e-9)
    assert np.isnan(x[7]).all() and np.array_equal(det, det2)


def _tripod(elevation, azimuth0=0.0):
    """Unit vectors from the platform up to three anchors 120 degrees apart at ``elevation``."""
    az = azimuth0 + np.deg2rad([0.0, 120.0, 240.0])
    c, s = np.cos(elevation), np.sin(elevation)
    return np.column_stack([c * np.cos(az), c * np.sin(az), np.full(3, s)])


@pytest.mark.parametrize("elevation_deg", [20.0, 45.0, 80.0])
def test_a_symmetric_tripod_shares_the_weight_equally(elevation_deg):
    """Each of three cables at elevation a, 120 degrees apart, carries m g / (3 sin a); the residual
    of the force balance is zero there and the whole weight without tensions."""
    weight = 300.0 * 9.81
    w_ext = np.array([0.0, 0.0, -weight])
    u = _tripod(np.deg2rad(elevation_deg), azimuth0=0.3)
    t, M_inv = statics.tensions(u, w_ext)
    np.testing.assert_allclose(t, weight / (3 * np.sin(np.deg2rad(elevation_deg))), rtol=1e-12)
    np.testing.assert_allclose(M_inv @ u.T, np.eye(3), atol=1e-12)
    assert statics.equilibrium_residual(u, t, w_ext) < 1e-9
    assert statics.equilibrium_residual(u, np.zeros(3), w_ext) == pytest.approx(weight)


def test_tensions_do_not_depend_on_the_frame_and_scale_with_the_load():
    """Rotate cables and load together: the same tensions; double the load: double tensions; a load
    the cables cannot pull against (upward) needs pushing cables (negative tensions)."""
    rng = np.random.default_rng(2)
    u = rng.normal(size=(3, 3)) + [0, 0, 2.0]
    u /= np.linalg.norm(u, axis=1)[:, None]
    w_ext = np.array([120.0, -40.0, -2900.0])
    t, _ = statics.tensions(u, w_ext)
    Q = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix()
    t_rot, _ = statics.tensions(u @ Q.T, Q @ w_ext)
    np.testing.assert_allclose(t_rot, t, rtol=1e-11)
    np.testing.assert_allclose(statics.tensions(u, 2 * w_ext)[0], 2 * t, rtol=1e-12)
    up, _ = statics.tensions(_tripod(0.6), [0.0, 0.0, 1000.0])
    assert (up < 0).all()


def test_coplanar_cables_give_nan_tensions():
    flat = _tripod(0.0)  # all three horizontal: they cannot hold a weight
    t, M_inv = statics.tensions(flat, [0.0, 0.0, -100.0])
    assert np.isnan(t).all() and np.isnan(M_inv).all()


def test_hookes_law_limits_and_linearity():
    L0 = np.array([[3.0, 4.0, 5.0]])
    t = np.array([[1000.0, 0.0, 2500.0]])
    ES = np.array([1.2e6, 1.3e6, 1.4e6])
    L = statics.stretched_length(L0, t, ES)
    np.testing.assert_allclose(L - L0, t * L0 / ES, rtol=1e-12)  # Delta L = t L0 / (E S)
    assert L[0, 1] == L0[0, 1]  # no tension, no stretch
    assert (statics.stretched_length(L0, t, np.full(3, np.inf)) == L0).all()  # rigid cables
    np.testing.assert_allclose(statics.stretched_length(L0, ES[None], ES), 2 * L0)  # t = E S doubles it


@pytest.mark.parametrize("name", KINDS + ["mixed"])
def test_tension_gradient_matches_finite_differences(cdpr4, name):
    """dt/dP of three cables holding CDPR4's platform against central differences of ``tensions``
    at the geometry of each P (every pulley kind: the DR arm's term included)."""
    r = robots(cdpr4)[name]
    sub = [0, 1, 2]
    args = (r.A[sub], r.kind[sub], r.h[sub], r.r_p[sub], r.d[sub], r.inward[sub])
    w_ext = r.platform.w_ext

    def t_of(P):
        return statics.tensions(total_length_and_direction(P, *args).u, w_ext)[0]

    g = total_length_and_direction(PTS, *args)
    t, M_inv = statics.tensions(g.u, w_ext)
    fd = central_fd(t_of, PTS, 1e-6)
    scale = np.abs(fd).max()
    assert scale > 100.0  # N/m: a real gradient, not zeros
    assert np.abs(statics.tension_gradient(t, M_inv, g) - fd).max() < 1e-6 * scale


def test_point_pulleys_make_the_length_gradient_minus_u(cdpr4):
    """r_p = h = 0: the cable is the straight line A_i P, dL/dP = -u exactly."""
    r = with_pulleys(cdpr4, kind="SR", h=0.0, r_p=0.0)
    g = total_length_and_direction(PTS, r.A, r.kind, r.h, r.r_p, r.d, r.inward)
    np.testing.assert_allclose(length_gradient(g), -g.u, atol=1e-15)
    np.testing.assert_allclose(
        g.u, (r.A - PTS[:, None]) / np.linalg.norm(r.A - PTS[:, None], axis=2)[..., None]
    )
