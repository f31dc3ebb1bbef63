"""The compiled twin of the heavy cable (cdpr.compiled.catenary) equals the numpy reference
(cdpr.models.catenary) to round-off: the same statuses and Newton iterations, the same end forces,
and every scalar function equal on the solved spans (weightless, vertical, U-shaped, inextensible
and infeasible cables included)."""

import numpy as np
import pytest

from cdpr.compiled import catenary as ccat
from cdpr.models import catenary as cat


def _spans(n=3000, seed=7):
    rng = np.random.default_rng(seed)
    l_h = rng.uniform(0.0, 30.0, n)
    l_v = rng.uniform(-30.0, 30.0, n)
    c = np.hypot(l_h, l_v)
    L0 = c * rng.uniform(0.995, 1.3, n)
    w = np.where(np.arange(n) % 5 == 0, 0.0, rng.uniform(0.0, 2.0, n))  # every fifth massless: taut or slack
    EA = rng.choice([1.2e6, 5e3, np.inf], n)
    w[::7] = 0.0  # weightless: taut or slack
    w[1::11] = 1e-8
    l_h[::13] = 0.0  # vertical
    L0[::17] = c[::17] * 0.99  # inextensible ones infeasible, elastic ones taut
    return l_h, l_v, L0, w, EA


def test_compiled_span_states_equal_the_reference():
    l_h, l_v, L0, w, EA = _spans()
    ref = cat.span_state(l_h, l_v, L0, w, EA)
    H, V, code, iters, conv = ccat.span_states(l_h, l_v, L0, w, EA)
    np.testing.assert_array_equal(code, ref.status_code)
    assert set(np.unique(ref.status)) == set(cat.SPAN_STATUSES)  # every status is exercised
    np.testing.assert_array_equal(conv, ref.converged)
    ok = ref.status_code != cat.INFEASIBLE
    assert np.isnan(H[~ok]).all() and np.isnan(V[~ok]).all()
    scale = ref.T_B[ok] + 1e-300
    assert (np.abs(H[ok] - ref.H[ok]) <= 1e-11 * scale).all()
    assert (np.abs(V[ok] - ref.V_B[ok]) <= 1e-11 * scale).all()
    # the same iterations (a last step can differ where the residual sits at the tolerance)
    assert (np.abs(iters - ref.iterations) <= 1).all() and (iters == ref.iterations).mean() > 0.99


def test_compiled_scalar_functions_equal_the_reference():
    l_h, l_v, L0, w, EA = _spans(600, seed=11)
    s = cat.span_state(l_h, l_v, L0, w, EA)
    ok = (s.status_code != cat.INFEASIBLE) & (s.T_B > 0)
    H, V = s.H[ok], s.V_B[ok]
    a = (L0[ok], w[ok], EA[ok])
    lh, lv = cat.span_equations(H, V, *a)
    F = cat.flexibility(H, V, *a)
    K = cat.stiffness(H, V, *a)
    phi = cat.complementary_energy(H, V, *a, l_h[ok], l_v[ok])
    arc = cat.arc_length(H, V, *a)
    sg = cat.sag(H, V, *a, l_h[ok], l_v[ok])
    ang = cat.angle_f_deg(H, V, l_h[ok], l_v[ok])
    TD = cat.tension_at(H, V, L0[ok], w[ok])
    for i in range(ok.sum()):
        args = (H[i], V[i], a[0][i], a[1][i], a[2][i])
        assert ccat.span_equations(*args) == pytest.approx((lh[i], lv[i]), rel=1e-13, abs=1e-13 * a[0][i])
        f = ccat.flexibility(*args)
        assert f == pytest.approx(
            (F[i, 0, 0], F[i, 0, 1], F[i, 1, 1]), rel=1e-12, abs=1e-13 * np.abs(F[i]).max()
        )
        k = ccat.stiffness(*args)
        assert k == pytest.approx(
            (K[i, 0, 0], K[i, 0, 1], K[i, 1, 1]), rel=1e-9, abs=1e-11 * np.abs(K[i]).max(), nan_ok=True
        )
        assert ccat.complementary_energy(*args, l_h[ok][i], l_v[ok][i]) == pytest.approx(
            phi[i], rel=1e-12, abs=1e-12 * s.T_B[ok][i] * a[0][i]
        )
        assert ccat.arc_length(*args) == pytest.approx(arc[i], rel=1e-14)
        assert ccat.sag(*args, l_h[ok][i], l_v[ok][i]) == pytest.approx(sg[i], rel=1e-9, abs=1e-13 * a[0][i])
        assert ccat.angle_f_deg(H[i], V[i], l_h[ok][i], l_v[ok][i]) == pytest.approx(
            ang[i], rel=1e-12, abs=1e-12
        )
        assert ccat.tension_at(H[i], V[i], a[0][i], a[1][i]) == pytest.approx(TD[i], rel=1e-15)
        assert ccat.end_forces(l_h[ok][i], l_v[ok][i], *[x[i] for x in a]) == pytest.approx(
            (H[i], V[i]), rel=1e-11, abs=1e-11 * s.T_B[ok][i]
        )


def test_a_start_given_to_the_compiled_kernel_gives_the_same_answer():
    l_h, l_v, L0, w, EA = 10.0, 2.0, 10.5, 0.6, 1.2e6
    ref = cat.span_state(l_h, l_v, L0, w, EA)
    for H0, V0 in [(1e-3, 0.0), (1e5, -1e3), (1.0, 50.0)]:
        H, V, code, _, conv = ccat.span_state(l_h, l_v, L0, w, EA, H0, V0)
        assert conv and code == ref.status_code
        assert H == pytest.approx(float(ref.H), rel=1e-10) and V == pytest.approx(float(ref.V_B), rel=1e-10)


def test_compiled_whole_cable_equals_the_reference():
    """cable_state (the free span and the dead part, the split of L0 at the tension at D), its
    stiffness and its energy: compiled = numpy, from the reference's start and from a warm one."""
    rng = np.random.default_rng(5)
    n = 400
    l_h = rng.uniform(0.5, 30.0, n)
    l_v = rng.uniform(-10.0, 30.0, n)
    l_dead = rng.choice([0.0, 2.0, 4.5], n)
    L0 = (np.hypot(l_h, l_v) + l_dead) * rng.uniform(0.998, 1.05, n)
    w = np.where(np.arange(n) % 5 == 0, 0.0, rng.uniform(0.0, 2.0, n))  # every fifth massless: taut or slack
    EA = rng.choice([1.28e6, 5e4, np.inf], n)
    ref = cat.cable_state(l_h, l_v, L0, l_dead, w, EA)
    sp = ref.span
    K = cat.cable_stiffness(ref, l_dead, w, EA)
    U = cat.cable_energy(ref, l_h, l_v, l_dead, w, EA)
    seen = set()
    for i in range(n):
        args = (l_h[i], l_v[i], L0[i], l_dead[i], w[i], EA[i])
        H, V, code, it, conv, L0f = ccat.cable_state(*args)
        assert code == sp.status_code[i]
        seen.add(int(code))
        if code == cat.INFEASIBLE:
            assert np.isnan(H) and np.isnan(sp.H[i])
            continue
        T = sp.T_B[i] + 1e-300
        assert abs(H - sp.H[i]) <= 1e-11 * T and abs(V - sp.V_B[i]) <= 1e-11 * T
        assert L0f == pytest.approx(ref.L0_free[i], rel=1e-14)
        # a warm start (the answer perturbed) reaches the same cable
        H2, V2, code2, _, _, L0f2 = ccat.cable_state(*args, 1.01 * H + 1.0, V - 1.0, 0.999 * L0f)
        assert code2 == code and abs(H2 - H) <= 1e-11 * T and abs(V2 - V) <= 1e-11 * T
        assert L0f2 == pytest.approx(L0f, rel=1e-14)
        k = ccat.cable_stiffness(sp.H[i], sp.V_B[i], ref.L0_free[i], l_dead[i], w[i], EA[i])
        kr = K[i].ravel()
        assert np.allclose(k, kr, rtol=1e-9, atol=1e-9 * np.abs(kr).max())
        e = ccat.cable_energy(sp.H[i], sp.V_B[i], ref.L0_free[i], l_h[i], l_v[i], l_dead[i], w[i], EA[i])
        assert e == pytest.approx(U[i], rel=1e-10, abs=1e-10 * T * L0[i])
    assert {cat.CATENARY, cat.TAUT}.issubset(seen)
