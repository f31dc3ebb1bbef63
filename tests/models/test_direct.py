"""DEGM_E: analytic limits, equilibrium, round trip, agreement of the two solvers."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.models.direct import degm_e, trilaterate_low
from cdpr.models.inverse import L_TS, igm_e
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.statics import equilibrium_residual
from cdpr.robot import with_pulleys

rng = np.random.default_rng(7)
# points inside the triangle A1 A2 A3 of CDPR4 (x > y), where subset (1,2,3) holds the platform
_u = rng.uniform(0.05, 0.95, (400, 2))
PTS = np.column_stack([-2.2 + 4.4 * _u[:, 0], -2.2 + 4.4 * _u[:, 0] * _u[:, 1], rng.uniform(0.0, 4.0, 400)])
SUB = (0, 1, 2)


@pytest.mark.parametrize("kind", ["SR", "DR"])
@pytest.mark.parametrize("method", ["newton", "fixed_point"])
def test_zero_pulley_and_rigid_cable_give_zero_error(cdpr4, kind, method):
    r = with_pulleys(cdpr4, kind=kind, h=0.0, r_p=0.0, E=1e30)
    opts = {"tol": 1e-12} if method == "fixed_point" else {}
    res = degm_e(r, PTS, SUB, method=method, **opts)
    assert res.converged.all()
    assert np.linalg.norm(res.P - PTS, axis=1).max() < 1e-9


def test_elasticity_alone_lowers_the_platform(cdpr4):
    r = with_pulleys(cdpr4, kind="fixed")
    res = degm_e(r, PTS, SUB)
    dp = res.P - PTS
    assert res.converged.all() and (dp[:, 2] < 0).all()
    # small-strain check: the drop is of the order of the stretch t L / (E S)
    stretch = (res.t * L_TS(r, PTS)[:, SUB] / r.ES[list(SUB)]).max(axis=1)
    assert (np.linalg.norm(dp, axis=1) > 0.3 * stretch).all()


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_equilibrium_and_round_trip(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    res = degm_e(r, PTS, SUB)
    assert res.converged.all()
    A, kd, h, rp, d, inward = (
        r.A[list(SUB)],
        r.kind[list(SUB)],
        r.h[list(SUB)],
        r.r_p[list(SUB)],
        r.d[list(SUB)],
        r.inward[list(SUB)],
    )
    L_TE, u = total_length_and_direction(res.P, A, kd, h, rp, d, inward)[:2]
    assert equilibrium_residual(u, res.t, r.platform.w_ext).max() < 1e-6  # N
    stretched = L_TS(r, PTS)[:, SUB] * (1 + res.t / r.ES[list(SUB)])
    assert np.abs(L_TE - stretched).max() < 1e-9  # L_TE(P*) = stretched L_TS
    # the IGM_E at P* gives back the same lengths
    assert np.allclose(igm_e(r, res.P).L_TE[:, SUB], L_TE)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_newton_and_fixed_point_agree(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    a = degm_e(r, PTS, SUB, method="newton")
    b = degm_e(r, PTS, SUB, method="fixed_point", tol=1e-10)
    assert a.converged.all() and b.converged.all()
    assert np.linalg.norm(a.P - b.P, axis=1).max() < 1e-6
    # at the paper's stop criterion (1e-5 m) the fixed point stays within a few eps_P
    c = degm_e(r, PTS, SUB, method="fixed_point")
    assert np.linalg.norm(a.P - c.P, axis=1).max() < 5e-5
    assert 5 < c.iterations.mean() < 40  # models.md: ~12 sphere intersections per subset


def test_trilateration_takes_the_low_solution():
    c = np.array([[[0, 0, 5.0], [4, 0, 5.0], [0, 4, 5.0]]])
    P = np.array([[1.0, 1.5, 2.0]])
    R = np.linalg.norm(c - P[:, None, :], axis=2)
    sol, ok = trilaterate_low(c, R)
    assert ok.all() and np.allclose(sol, P)
    _, ok = trilaterate_low(c, R * 0.1)
    assert not ok.any()


def test_trilateration_keeps_the_solution_on_gravitys_side():
    """With ``down`` the kept intersection is the one on gravity's side of the centres' plane:
    down = -z gives the paper's (smaller z) solution bit for bit, down = +z the mirror one, and a
    rotated configuration (centres, point and gravity) gives the rotated point."""
    rng = np.random.default_rng(3)
    c = rng.uniform(-3, 3, (50, 3, 3)) + [0.0, 0.0, 5.0]
    P = rng.uniform(-1, 1, (50, 3))
    R = np.linalg.norm(c - P[:, None, :], axis=2)
    low, ok = trilaterate_low(c, R)
    assert ok.all()
    same, _ = trilaterate_low(c, R, np.array([0.0, 0.0, -1.0]))
    assert np.array_equal(same, low)
    up, _ = trilaterate_low(c, R, np.array([0.0, 0.0, 1.0]))
    assert (up[:, 2] >= low[:, 2]).all() and np.abs(up - low).max() > 0.1
    # each solution lies on the spheres
    for sol in (low, up):
        assert np.abs(np.linalg.norm(c - sol[:, None, :], axis=2) - R).max() < 1e-9
    Q = Rotation.from_rotvec([2.5, -0.4, 0.7]).as_matrix()
    turned, _ = trilaterate_low(c @ Q.T, R, Q @ [0.0, 0.0, -1.0])
    assert np.abs(turned - low @ Q.T).max() < 1e-9


def test_unknown_method(cdpr4):
    with pytest.raises(ValueError, match="allowed: 'newton', 'fixed_point'"):
        degm_e(cdpr4, PTS[:2], SUB, method="magic")


@pytest.mark.parametrize("kind", ["SR", "fixed", "DR"])
def test_analytic_jacobian_against_finite_differences(cdpr4, kind):
    """dF/dP = dL_TE/dP - diag(L/ES) dt/dP and dt/dP, exact for every pulley kind (for DR with the
    arm's rotation)."""
    rel = 1e-6
    from cdpr.models.direct import _Subset

    r = with_pulleys(cdpr4, kind=kind)
    sub = _Subset(r, SUB)
    L = L_TS(r, PTS)[:, SUB]
    P = PTS + np.array([0.01, -0.02, -0.05])
    _, _, _, J, dt = sub.residual(P, L, jacobian=True)
    fd, fd_t = np.empty_like(J), np.empty_like(dt)
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1e-6
        hi, lo = sub.residual(P + e, L), sub.residual(P - e, L)
        fd[..., k] = (hi[0] - lo[0]) / 2e-6
        fd_t[..., k] = (hi[1] - lo[1]) / 2e-6
    assert np.abs(J - fd).max() < rel * np.abs(fd).max()
    assert np.abs(dt - fd_t).max() < rel * np.abs(fd_t).max()


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_newton_stop_rule_keeps_root_and_tensions_at_returned_point(cdpr4, kind):
    """The default stop takes the last step and carries t to first order: the root equals a much
    tighter solve, and the reported tensions equal a fresh evaluation at the returned P."""
    from cdpr.models.direct import _Subset

    r = with_pulleys(cdpr4, kind=kind)
    a = degm_e(r, PTS, SUB)
    b = degm_e(r, PTS, SUB, tol=1e-14)
    ok = a.converged & b.converged
    assert ok.sum() >= len(PTS) - 1
    assert np.abs(a.P[ok] - b.P[ok]).max() < 1e-12
    assert (a.iterations[ok] < b.iterations[ok]).any()
    L = L_TS(r, PTS)[:, SUB]
    _, t_fresh, _ = _Subset(r, SUB).residual(a.P[ok], L[ok])
    np.testing.assert_allclose(a.t[ok], t_fresh, rtol=0, atol=1e-8)  # N; without the carry ~1e-3
