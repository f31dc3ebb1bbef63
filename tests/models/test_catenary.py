"""One heavy elastic cable (cdpr.models.catenary, Irvine 1981 ch. 2) tested by physics and by numbers
that do not come from the module: w = 0 is the straight Hooke spring, EA -> inf the inextensible
catenary a cosh(x/a) solved independently, the vertical cable's closed form against the limit
l_h -> 0 and its stretched length, the flexibility matrix against central differences (w = 1e-8,
U-shaped spans, D below B), the arc length against a fine polyline of the shape, the shallow level
span's sag w L^2/(8H), and Newton's answer independent of its start."""

import numpy as np
import pytest
from scipy.optimize import brentq

from cdpr.errors import CdprError
from cdpr.models import catenary as cat

EA = 1.2e6  # [N] a 4 mm steel cable, roughly
# spans (l_h, l_v, L0, w): taut, nearly straight, U-shaped, D below B, long slack, tiny weight
CASES = [
    (3.0, 4.0, 5.001, 0.6),
    (10.0, 2.0, 10.19, 0.6),
    (10.0, 0.0, 10.5, 0.6),
    (8.0, -3.0, 9.5, 2.0),
    (5.0, 5.0, 12.0, 0.6),
    (6.0, 1.5, 6.1, 1e-8),
    (25.0, 30.0, 39.0, 0.619),
    (4.0, -6.0, 7.3, 0.619),
]


def _cases(ea=EA):
    a = np.array(CASES)
    return a[:, 0], a[:, 1], a[:, 2], a[:, 3], np.full(len(a), ea)


def test_spans_are_reached_and_statuses_follow_the_issue():
    l_h, l_v, L0, w, ea = _cases()
    s = cat.span_state(l_h, l_v, L0, w, ea)
    assert s.converged.all()
    lh, lv = cat.span_equations(s.H, s.V_B, L0, w, ea)
    np.testing.assert_allclose(lh, l_h, rtol=0, atol=1e-12)
    np.testing.assert_allclose(lv, l_v, rtol=0, atol=1e-12)
    assert (s.H > 0).all()
    U = (s.V_B < 0) & (s.V_D > 0)
    assert U[2] and U[4] and not U[0]  # the level slack span and the long cable are U-shaped
    assert list(s.status) == ["U" if u else "catenary" for u in U]
    np.testing.assert_array_equal(s.V_D, s.V_B + w * L0)
    np.testing.assert_allclose(s.T_D, cat.tension_at(s.H, s.V_B, L0, w), rtol=1e-15)
    assert s.iterations.max() <= 15, s.iterations


def test_weightless_cable_is_the_straight_hooke_spring():
    """w = 0: T = EA (c/L0 - 1) along the chord, or slack; w = 1e-9 differs from it by O(w)."""
    rng = np.random.default_rng(3)
    l_h = rng.uniform(0.0, 5.0, 40)
    l_v = rng.uniform(-5.0, 5.0, 40)
    c = np.hypot(l_h, l_v)
    L0 = c * rng.uniform(0.995, 1.0005, 40)
    s = cat.span_state(l_h, l_v, L0, 0.0, EA)
    T = np.maximum(EA * (c - L0) / L0, 0.0)
    np.testing.assert_allclose(s.H, T * l_h / c, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(s.V_B, T * l_v / c, rtol=1e-12, atol=1e-12)
    assert list(s.status) == ["taut" if t > 0 else "slack" for t in T]
    taut = T > 0
    # the span equations at w = 0 are Hooke's stretched chord, to round-off
    lh, lv = cat.span_equations(s.H[taut], s.V_B[taut], L0[taut], 0.0, EA)
    np.testing.assert_allclose(lh, l_h[taut], rtol=0, atol=1e-12)
    np.testing.assert_allclose(lv, l_v[taut], rtol=0, atol=1e-12)
    # its flexibility is the straight spring's: L0/EA I + (L0/T)(I - e e^T), e = (H, V)/T
    e = np.stack([s.H[taut], s.V_B[taut]], axis=-1) / T[taut, None]
    F0 = (L0[taut] / EA)[:, None, None] * np.eye(2) + (L0[taut] / T[taut])[:, None, None] * (
        np.eye(2) - e[:, :, None] * e[:, None, :]
    )
    F = cat.flexibility(s.H[taut], s.V_B[taut], L0[taut], 0.0, EA)
    scale = np.abs(F0).max(axis=(1, 2))[:, None, None]  # (I - e e^T) cancels in F0's small entries
    np.testing.assert_allclose(F / scale, F0 / scale, rtol=0, atol=1e-12)
    # the weightless cable's shape is its chord, the sag and the force angle zero
    assert cat.sag(s.H, s.V_B, L0, 0.0, EA, l_h, l_v).max() == 0.0
    np.testing.assert_allclose(cat.angle_f_deg(s.H[taut], s.V_B[taut], l_h[taut], l_v[taut]), 0.0, atol=1e-6)
    # w -> 0 is continuous: the tension at mid-span (V_B + w L0/2) tends to Hooke's
    w = 1e-9
    sw = cat.span_state(l_h[taut], l_v[taut], L0[taut], w, EA)
    np.testing.assert_allclose(sw.H, s.H[taut], rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(sw.V_B + 0.5 * w * L0[taut], s.V_B[taut], rtol=1e-8, atol=1e-8)


@pytest.mark.parametrize("ea", [np.inf, 1e16])
def test_inextensible_limit_is_the_catenary_a_cosh_x_over_a(ea):
    """EA -> inf: H from sinh(lam)/lam = sqrt(L^2 - l_v^2)/l_h solved by bisection, the shape on
    z = a (cosh((x + x_B)/a) - cosh(x_B/a)), a = H/w, and the arc length L0."""
    for l_h, l_v, L0, w in [(10.0, 0.0, 10.5, 0.6), (10.0, 3.0, 12.0, 2.0), (6.0, -4.0, 7.5, 1.0)]:
        rho = np.sqrt(L0**2 - l_v**2) / l_h
        lam = brentq(lambda x: np.sinh(x) / x - rho, 1e-9, 50.0, xtol=1e-15)
        H_ref = w * l_h / (2 * lam)
        V_ref = 0.5 * w * (l_v / np.tanh(lam) - L0)
        s = cat.span_state(l_h, l_v, L0, w, ea)
        np.testing.assert_allclose([s.H, s.V_B], [H_ref, V_ref], rtol=1e-9)
        a = s.H / w
        xB = a * np.arcsinh(s.V_B / s.H)
        x, z = cat.shape(s.H, s.V_B, L0, w, ea, n=201)
        np.testing.assert_allclose(z, a * (np.cosh((x + xB) / a) - np.cosh(xB / a)), atol=1e-10)
        assert x[-1] == pytest.approx(l_h, abs=1e-11) and z[-1] == pytest.approx(l_v, abs=1e-11)
        assert cat.arc_length(s.H, s.V_B, L0, w, ea) == pytest.approx(L0, abs=1e-14 * L0 + L0 / ea * 1e3)
        # the catenary's tension difference is w times the height difference
        assert s.T_D - s.T_B == pytest.approx(w * l_v, abs=1e-9 * s.T_D + 1e-3 * L0 * s.T_D / ea)


def test_inextensible_cable_too_short_for_its_chord_is_infeasible():
    s = cat.span_state(
        [3.0, 3.0, 0.0, 3.0], [4.0, 4.0, 6.0, 4.0], [4.9, 5.0, 5.0, 5.0], [0.6, 0.6, 0.6, 0.0], np.inf
    )
    assert list(s.status) == ["infeasible", "infeasible", "infeasible", "slack"]
    assert np.isnan(s.H[:3]).all() and not s.converged[:3].any()


def test_vertical_cable_closed_form():
    """l_h = 0: hanging from D (V_B >= 0), folded (V_B < 0 < V_D), hanging from B (V_D <= 0):
    the stretched lengths match the span and the closed form is the limit l_h -> 0 of Newton's."""
    L0, w = 5.0, 0.8
    for ea in (EA, 3e3, np.inf):
        for l_v in (6.0 if np.isfinite(ea) else 4.99, 2.0, -1.0, -4.5, -6.0 if np.isfinite(ea) else -4.99):
            s = cat.span_state(0.0, l_v, L0, w, ea)
            assert s.H == 0.0 and s.converged
            near = cat.span_state(1e-7, l_v, L0, w, ea)
            assert near.V_B == pytest.approx(s.V_B, rel=1e-5, abs=1e-5)
            if s.V_B >= 0:  # stretched length of a cable hanging from D up to B
                assert L0 + L0 * (s.V_B + 0.5 * w * L0) / ea == pytest.approx(l_v, rel=1e-12)
                assert s.status == "catenary"
            elif s.V_D <= 0:  # hanging below B down to D
                assert -(L0 - L0 * (s.V_B + 0.5 * w * L0) / ea) == pytest.approx(l_v, rel=1e-12)
                assert s.status == "catenary"
            else:  # folded: two hanging legs of lengths -V_B/w and V_D/w
                a, b = -s.V_B / w, s.V_D / w
                assert a + b == pytest.approx(L0, rel=1e-12)
                legs = (b + 0.5 * w * b * b / ea) - (a + 0.5 * w * a * a / ea)
                assert legs == pytest.approx(l_v, rel=1e-12, abs=1e-12)
                assert s.status == "U"
            lh, lv = cat.span_equations(s.H, s.V_B, L0, w, ea)
            assert lh == 0.0 and lv == pytest.approx(l_v, rel=1e-12, abs=1e-12)


def _fd_flexibility(H, V, L0, w, ea, step):
    F = np.empty(np.shape(H) + (2, 2))
    for j, (dh, dv) in enumerate([(step, 0.0), (0.0, step)]):
        hp = np.stack(cat.span_equations(H + dh, V + dv, L0, w, ea), axis=-1)
        hm = np.stack(cat.span_equations(H - dh, V - dv, L0, w, ea), axis=-1)
        F[..., :, j] = (hp - hm) / (2 * step[..., None])
    return F


@pytest.mark.parametrize("ea", [EA, np.inf])
def test_flexibility_matches_central_differences(ea):
    l_h, l_v, L0, w, _ = _cases()
    s = cat.span_state(l_h, l_v, L0, w, ea if np.isfinite(ea) else EA)
    if np.isinf(ea):  # inextensible spans: slacken the cables a little so they stay feasible
        s = cat.span_state(l_h, l_v, L0 * 1.02, w, ea)
        L0 = L0 * 1.02
    assert (s.V_B < 0).sum() >= 3  # U-shaped spans and spans descending to D are included
    F = cat.flexibility(s.H, s.V_B, L0, w, ea)
    step = 1e-5 * s.T_B
    fd = _fd_flexibility(s.H, s.V_B, L0, w, ea, step)
    scale = np.abs(F).max(axis=(1, 2))[:, None, None]
    np.testing.assert_allclose(F / scale, fd / scale, atol=1e-8)
    np.testing.assert_allclose(F, np.swapaxes(F, 1, 2), rtol=0, atol=0)
    assert (np.linalg.eigvalsh(F) > 0).all()
    # the stiffness is its inverse, and the derivative of the end forces along a change of span
    K = cat.stiffness(s.H, s.V_B, L0, w, ea)
    np.testing.assert_allclose(K @ F, np.broadcast_to(np.eye(2), F.shape), atol=1e-9)


def test_flexibility_at_tiny_weight_and_in_u_spans_against_differences_of_end_forces():
    """K = d(H, V_B)/d(l_h, l_v) against central differences of the solver's end forces."""
    l_h, l_v, L0, w, ea = _cases()
    s = cat.span_state(l_h, l_v, L0, w, ea)
    K = cat.stiffness(s.H, s.V_B, L0, w, ea)
    d = 1e-6
    for j, (dh, dv) in enumerate([(d, 0.0), (0.0, d)]):
        p = np.stack(cat.end_forces(l_h + dh, l_v + dv, L0, w, ea), axis=-1)
        m = np.stack(cat.end_forces(l_h - dh, l_v - dv, L0, w, ea), axis=-1)
        fd = (p - m) / (2 * d)
        scale = np.abs(K).max(axis=(1, 2))[:, None]
        np.testing.assert_allclose(K[:, :, j] / scale, fd / scale, atol=1e-6)


def test_arc_length_is_the_integral_of_the_stretch_along_a_fine_polyline():
    """L = int (1 + T/EA) ds against the length of polylines through 10001 and 20001 points of the
    shape (Richardson-extrapolated: a polyline's error falls as the square of its segments)."""
    l_h, l_v, L0, w, _ = _cases()
    ea = np.full(len(l_h), 5e3)  # soft cables, so the stretch matters
    s = cat.span_state(l_h, l_v, L0, w, ea)
    x, z = cat.shape(s.H, s.V_B, L0, w, ea, n=10001)
    coarse = np.hypot(np.diff(x, axis=-1), np.diff(z, axis=-1)).sum(axis=-1)
    x, z = cat.shape(s.H, s.V_B, L0, w, ea, n=20001)
    poly = np.hypot(np.diff(x, axis=-1), np.diff(z, axis=-1)).sum(axis=-1)
    np.testing.assert_allclose(cat.arc_length(s.H, s.V_B, L0, w, ea), (4 * poly - coarse) / 3, rtol=1e-12)
    arc = cat.arc_length(s.H, s.V_B, L0, w, ea)
    assert (arc > L0).all()
    np.testing.assert_allclose(x[:, -1], l_h, atol=1e-11)
    np.testing.assert_allclose(z[:, -1], l_v, atol=1e-11)
    excess = cat.arc_minus_chord(s.H, s.V_B, L0, w, ea, l_h, l_v)
    np.testing.assert_allclose(excess, (4 * poly - coarse) / 3 - np.hypot(l_h, l_v), rtol=1e-9, atol=1e-12)
    # the sag is the largest distance of the polyline's points from the chord
    c = np.hypot(l_h, l_v)
    dist = np.abs(x * l_v[:, None] - z * l_h[:, None]) / c[:, None]
    sag = cat.sag(s.H, s.V_B, L0, w, ea, l_h, l_v)
    np.testing.assert_allclose(sag, dist.max(axis=-1), rtol=1e-7, atol=1e-12)
    # the force at B is along the tangent at B: its angle to the chord is the polyline's first segment's
    seg = np.degrees(np.arctan2(np.abs((x[:, 1] * l_v - z[:, 1] * l_h)), x[:, 1] * l_h + z[:, 1] * l_v))
    np.testing.assert_allclose(cat.angle_f_deg(s.H, s.V_B, l_h, l_v), seg, rtol=1e-3, atol=1e-9)


@pytest.mark.parametrize("tension", [1e3, 1e4])
def test_shallow_level_span_sags_w_l2_over_8h(tension):
    """The parabola: sag = W l_h/(8H) with W = w L0 the cable's weight (w per unstrained metre,
    so w l_h^2/(8H) holds up to the strain T/EA), to O((sag/l_h)^2)."""
    l_h, w = 20.0, 0.619
    L0 = l_h / (1 + tension / EA) * 1.0000001  # a little longer than the straight stretched cable
    s = cat.span_state(l_h, 0.0, L0, w, EA)
    sag = cat.sag(s.H, s.V_B, L0, w, EA, l_h, 0.0)
    ratio = sag / l_h
    assert ratio < 2e-3
    assert sag == pytest.approx(w * L0 * l_h / (8 * s.H), rel=10 * ratio**2 + 1e-9)
    assert sag == pytest.approx(w * l_h**2 / (8 * s.H), rel=2 * tension / EA)
    assert s.V_B == pytest.approx(-0.5 * w * L0, rel=1e-12)  # the level span shares the weight


def test_starting_guesses_do_not_change_the_answer():
    l_h, l_v, L0, w, ea = _cases()
    ref = cat.span_state(l_h, l_v, L0, w, ea)
    for H0, V0 in [(1e-3, 0.0), (1e5, -1e3), (1.0, 50.0), (ref.H * 3, ref.V_B - 10)]:
        s = cat.span_state(l_h, l_v, L0, w, ea, start=(H0, V0))
        assert s.converged.all()
        np.testing.assert_allclose(s.H, ref.H, rtol=1e-10)
        assert (np.abs(s.V_B - ref.V_B) <= 1e-10 * ref.T_B).all()


def test_end_forces_is_vectorised_and_agrees_with_span_state():
    l_h, l_v, L0, w, ea = _cases()
    H, V = cat.end_forces(l_h.reshape(2, 4), l_v.reshape(2, 4), L0.reshape(2, 4), w.reshape(2, 4), EA)
    s = cat.span_state(l_h, l_v, L0, w, ea)
    np.testing.assert_array_equal(H.ravel(), s.H)
    np.testing.assert_array_equal(V.ravel(), s.V_B)
    assert np.shape(cat.end_forces(3.0, 4.0, 5.1, 0.6, EA)[0]) == ()


@pytest.mark.parametrize(
    "args, name",
    [
        ((-1.0, 1.0, 2.0, 0.5, EA), "l_h"),
        ((1.0, np.nan, 2.0, 0.5, EA), "l_v"),
        ((1.0, 1.0, 0.0, 0.5, EA), "L0"),
        ((1.0, 1.0, 2.0, -0.5, EA), "w"),
        ((1.0, 1.0, 2.0, np.inf, EA), "w"),
        ((1.0, 1.0, 2.0, 0.5, 0.0), "EA"),
    ],
)
def test_bad_input_is_one_line_naming_it(args, name):
    with pytest.raises(CdprError, match=rf"^catenary: {name} = .* is not allowed; allowed: "):
        cat.span_state(*args)


DEAD = 4.0  # [m] a dead length carrying the tension at D


def test_whole_cable_splits_its_rest_length_at_the_tension_at_d():
    """cable_state: L0 = L0_free + l_dead/(1 + T_D/EA); l_dead = 0 is span_state; w = 0 is Hooke's
    law on the whole length (Paty 2021 eq. 10, 13)."""
    l_h, l_v, L0, w, ea = _cases()
    L0 = L0 + DEAD
    st = cat.cable_state(l_h, l_v, L0, DEAD, w, ea)
    assert st.span.converged.all()
    assert (np.abs(st.L0_free + DEAD / (1 + st.span.T_D / ea) - L0) <= 1e-14 * L0).all()
    lh, lv = cat.span_equations(st.span.H, st.span.V_B, st.L0_free, w, ea)
    np.testing.assert_allclose(lh, l_h, atol=1e-12)
    np.testing.assert_allclose(lv, l_v, atol=1e-12)
    s0 = cat.cable_state(l_h, l_v, L0 - DEAD, 0.0, w, ea).span
    ref = cat.span_state(l_h, l_v, L0 - DEAD, w, ea)
    assert (np.abs(s0.H - ref.H) <= 1e-11 * ref.T_B).all()  # the same solution (warm restarts: round-off)
    assert (np.abs(s0.V_B - ref.V_B) <= 1e-11 * ref.T_B).all()
    c = np.hypot(l_h, l_v)
    Lh = (c + DEAD) / (1 + np.array([0.0, 1e-4, 2e-3, 5e-3, 0.0, 1e-3, 3e-4, 1e-3]))
    hk = cat.cable_state(l_h, l_v, Lh, DEAD, 0.0, ea).span
    np.testing.assert_allclose(hk.T_B, np.maximum(ea * ((c + DEAD) / Lh - 1), 0), rtol=1e-12, atol=1e-9)


def test_whole_cable_stiffness_and_energy_against_central_differences():
    """d(H, V_B)/d(l_h, l_v) with the split following T_D, and dU/d(l_h, l_v) = (H, V_B)."""
    l_h, l_v, L0, w, ea = _cases()
    L0 = L0 + DEAD
    st = cat.cable_state(l_h, l_v, L0, DEAD, w, ea)
    K = cat.cable_stiffness(st, DEAD, w, ea)
    d = 1e-6
    for j, (dh, dv) in enumerate([(d, 0.0), (0.0, d)]):
        p = cat.cable_state(l_h + dh, l_v + dv, L0, DEAD, w, ea).span
        m = cat.cable_state(l_h - dh, l_v - dv, L0, DEAD, w, ea).span
        fd = np.stack([p.H - m.H, p.V_B - m.V_B], axis=-1) / (2 * d)
        scale = np.abs(K).max(axis=(1, 2))[:, None]
        np.testing.assert_allclose(K[:, :, j] / scale, fd / scale, atol=1e-6)

    def U(a, b):
        return cat.cable_energy(cat.cable_state(a, b, L0, DEAD, w, ea), a, b, DEAD, w, ea)

    d = 1e-5
    gh = (U(l_h + d, l_v) - U(l_h - d, l_v)) / (2 * d)
    gv = (U(l_h, l_v + d) - U(l_h, l_v - d)) / (2 * d)
    np.testing.assert_allclose(gh, st.span.H, rtol=0, atol=1e-6 * st.span.T_B.max())
    np.testing.assert_allclose(gv, st.span.V_B, rtol=0, atol=1e-6 * st.span.T_B.max())
