"""The compiled engines' one scalar cable kernel (cdpr.compiled._kernels) equals the numpy reference
of the pulley model (cdpr.models.pulleys, cdpr.models.sensitivity.cable_partials) point by point, and
its partial derivatives equal central finite differences of the kernel itself."""

import numpy as np
import pytest

from cdpr.compiled._kernels import (
    C_DLD,
    C_DLDP,
    C_DLH,
    C_DLR,
    C_DUDP,
    C_DUH,
    C_DUR,
    C_INSIDE,
    C_L,
    C_LE,
    C_U,
    NCOL,
    cable,
    cable_arrays,
    cable_partials,
    pulley_geometry,
)
from cdpr.models.pulleys import pulley_state, total_length_and_direction
from cdpr.models.sensitivity import cable_partials as cable_partials_reference
from cdpr.robot import with_pulleys

#: pulley designs: (kind, h [m], r_p [m]); fixed is the h = r_p = 0 limit
DESIGNS = {"fixed": ("fixed", 0.0, 0.0), "SR": ("SR", 0.1, 0.0665), "DR": ("DR", 0.1, 0.08)}


def _points(robot, n=40, seed=1):
    """Random points in and around the frame, below the pulleys, plus one on the vertical through
    A_1 (rho = 0, the fallback plane) and one inside the first sheave's circle."""
    rng = np.random.default_rng(seed)
    A = robot.A
    lo, hi = A.min(axis=0), A.max(axis=0)
    P = rng.uniform([lo[0] - 0.5, lo[1] - 0.5, 0.0], [hi[0] + 0.5, hi[1] + 0.5, hi[2] - 0.3], (n, 3))
    on_axis = A[0] - [0.0, 0.0, 2.0]
    return np.vstack([P, on_axis])


def _args(cab, c, P):
    return (
        P[0],
        P[1],
        P[2],
        cab.A[c, 0],
        cab.A[c, 1],
        cab.A[c, 2],
        cab.kind[c],
        cab.h[c],
        cab.rp[c],
        cab.d[c],
        cab.inward[c, 0],
        cab.inward[c, 1],
    )


def _robot(cdpr4, design):
    kind, h, r_p = DESIGNS[design]
    return with_pulleys(cdpr4, kind=kind, h=h, r_p=r_p)


@pytest.mark.parametrize("design", list(DESIGNS))
def test_cable_equals_vectorised_pulley_model(cdpr4, design):
    """L_TE, u, |l_E|, the wrap angle, H, D, K and every solver term of ``cable`` equal
    ``pulleys.pulley_state`` / ``total_length_and_direction`` at random points."""
    r = _robot(cdpr4, design)
    cab = cable_arrays(r)
    a = r.arrays
    P = _points(r)
    st = pulley_state(P, a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    g = total_length_and_direction(P, a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    z = np.array([0.0, 0.0, 1.0])
    close = dict(rtol=1e-12, atol=1e-12)
    for i, p in enumerate(P):
        for c in range(r.m):
            (L, ux, uy, uz, lE, ins, sw, epx, epy, arm, bx, by, bz, ex, ey, ez, uCb, gam) = cable(
                *_args(cab, c, p)
            )
            np.testing.assert_allclose(gam, st.gamma[i, c], **close)
            np.testing.assert_allclose(L, g.L_TE[i, c], **close)
            np.testing.assert_allclose([ux, uy, uz], g.u[i, c], **close)
            np.testing.assert_allclose(lE, g.l_E[i, c], **close)
            assert ins == g.inside[i, c]
            np.testing.assert_allclose(sw, g.swivel[i, c], **close)
            np.testing.assert_allclose([epx, epy, 0.0], g.e_perp[i, c], **close)
            np.testing.assert_allclose(arm, g.arm[i, c], **close)
            if design == "DR":  # the arm's rotation; SR and fixed: arm = 0 and the kernel skips beta, eps
                assert arm > 0.0
                np.testing.assert_allclose([bx, by, bz], g.beta[i, c], **close)
                np.testing.assert_allclose([ex, ey, ez], g.eps[i, c], **close)
                np.testing.assert_allclose(uCb, g.uC_beta[i, c], **close)
            else:
                assert arm == 0.0
            geo = pulley_geometry(*_args(cab, c, p))
            np.testing.assert_allclose(geo.gamma, st.gamma[i, c], **close)
            np.testing.assert_allclose(geo.ld, st.l_d[i, c], **close)
            np.testing.assert_allclose(geo.lE, st.l_E[i, c], **close)
            e3 = np.array([geo.esx, geo.esy, 0.0])
            np.testing.assert_allclose(e3[:2], st.e_s[i, c], **close)
            np.testing.assert_allclose(a.A[c] + geo.Hs * e3 + geo.Hw * z, st.H[i, c], **close)
            np.testing.assert_allclose(p + [geo.vx, geo.vy, geo.vz], st.D[i, c], **close)
            K = a.A[c] + (geo.Hs + r.r_p[c] * geo.cK) * e3 + (geo.Hw + r.r_p[c] * geo.sK) * z
            np.testing.assert_allclose(K, st.K[i, c], **close)
            # eq. (5) holds for the kernel's own pieces
            np.testing.assert_allclose(geo.L, geo.ld + r.r_p[c] * geo.gamma + geo.lE, rtol=1e-15, atol=0)
    # the points do exercise the pulley: wrap angles other than the fixed-pulley zero, and the plane
    # fallback on the axis
    if design != "fixed":
        assert np.ptp(st.gamma) > 0.5
    assert np.isclose(st.rho[-1, 0], 0.0)


def test_inside_the_sheave_is_flagged(cdpr4):
    """A point inside the sheave circle (no tangent) is flagged inside, as by the numpy model."""
    r = _robot(cdpr4, "SR")
    cab = cable_arrays(r)
    a = r.arrays
    e_s = -a.inward[0]  # from A_1 away from the centre: the sheave centre H = A_1 + h e_s (SR)
    P = a.A[0] + r.h[0] * np.array([e_s[0], e_s[1], 0.0]) + [0.0, 0.0, 0.5 * r.r_p[0]]
    g = total_length_and_direction(P[None], a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    assert g.inside[0, 0]
    assert cable(*_args(cab, 0, P))[5]
    out = np.empty(NCOL)
    cable_partials(*_args(cab, 0, P), out)
    assert out[C_INSIDE] == 1.0


@pytest.mark.parametrize("design", list(DESIGNS))
def test_cable_partials_equal_vectorised_reference(cdpr4, design):
    """Every entry of the kernel's row equals ``sensitivity.cable_partials`` (numpy)."""
    r = _robot(cdpr4, design)
    cab = cable_arrays(r)
    a = r.arrays
    P = _points(r, seed=2)
    ref = cable_partials_reference(P, a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    out = np.empty(NCOL)
    close = dict(rtol=1e-11, atol=1e-12)
    for i, p in enumerate(P):
        for c in range(r.m):
            cable_partials(*_args(cab, c, p), out)
            np.testing.assert_allclose(out[C_L], ref.L_TE[i, c], **close)
            np.testing.assert_allclose(out[C_U : C_U + 3], ref.u[i, c], **close)
            np.testing.assert_allclose(out[C_LE], ref.l_E[i, c], **close)
            np.testing.assert_allclose(out[C_DLDP : C_DLDP + 3], ref.dL_dP[i, c], **close)
            np.testing.assert_allclose(out[C_DUDP : C_DUDP + 9].reshape(3, 3), ref.du_dP[i, c], **close)
            np.testing.assert_allclose(
                [out[C_DLH], out[C_DLR], out[C_DLD]], ref.dL[i, c, :3], **close
            )  # h, r_p, d
            np.testing.assert_allclose(out[C_DUH : C_DUH + 3], ref.du[i, c, :, 0], **close)
            np.testing.assert_allclose(out[C_DUR : C_DUR + 3], ref.du[i, c, :, 1], **close)
            np.testing.assert_allclose(ref.du[i, c, :, 2], 0.0, atol=0)
            # and its L_TE, u are the solver kernel's, bit for bit (one geometry)
            k = cable(*_args(cab, c, p))
            assert out[C_L] == k[0] and out[C_LE] == k[4]
            assert out[C_U] == k[1] and out[C_U + 1] == k[2] and out[C_U + 2] == k[3]


def _lu(args):
    k = cable(*args)
    return k[0], np.array(k[1:4])


@pytest.mark.parametrize("design", list(DESIGNS))
def test_cable_partials_equal_central_differences(cdpr4, design):
    """dL_TE/dP, du/dP and the partials in h, r_p, d equal central differences of ``cable``
    (step 1e-6 m). The fixed pulley (r_p = 0) has no r_p derivative to compare: r_p < 0 is not a
    pulley."""
    r = _robot(cdpr4, design)
    cab = cable_arrays(r)
    P = _points(r, n=25, seed=3)[:-1]  # off the axis: du/dP is singular on it (swivel)
    step = 1e-6
    out = np.empty(NCOL)
    # slots of (P_x, P_y, P_z, h, r_p, d) in the argument tuple
    slots = {"Px": 0, "Py": 1, "Pz": 2, "h": 7, "r_p": 8, "d": 9}
    checked = 0
    for p in P:
        for c in range(r.m):
            args = _args(cab, c, p)
            cable_partials(*args, out)
            analytic = {
                "Px": (out[C_DLDP], out[C_DUDP : C_DUDP + 9 : 3]),
                "Py": (out[C_DLDP + 1], out[C_DUDP + 1 : C_DUDP + 9 : 3]),
                "Pz": (out[C_DLDP + 2], out[C_DUDP + 2 : C_DUDP + 9 : 3]),
                "h": (out[C_DLH], out[C_DUH : C_DUH + 3]),
                "r_p": (out[C_DLR], out[C_DUR : C_DUR + 3]),
                "d": (out[C_DLD], np.zeros(3)),
            }
            for name, slot in slots.items():
                if name == "r_p" and design == "fixed":
                    continue
                up, down = list(args), list(args)
                up[slot] += step
                down[slot] -= step
                (Lu, uu), (Ld, ud) = _lu(tuple(up)), _lu(tuple(down))
                dL, du = analytic[name]
                np.testing.assert_allclose(dL, (Lu - Ld) / (2 * step), rtol=1e-6, atol=1e-8, err_msg=name)
                np.testing.assert_allclose(du, (uu - ud) / (2 * step), rtol=1e-6, atol=1e-8, err_msg=name)
                checked += 1
    assert checked == len(P) * r.m * (5 if design == "fixed" else 6)
