"""Compiled twin of ``cdpr.models.catenary`` (Irvine's elastic catenary, one heavy cable): the same
functions under the same names as numba scalar kernels, to be called inside the compiled engines'
per-cable loops, and ``span_states``, the batch of ``span_state`` in parallel over cables (the test
of this twin against the numpy reference, and the benchmark).

The arithmetic is the reference's, branch by branch (the cancellation-free forms, the closed forms
of the weightless and the vertical cable, Newton's start, its Armijo search on the complementary
energy and its stop rule), so the two agree to round-off, with the same statuses and iteration
counts. Inputs are not checked here (the numpy reference refuses bad ones).

References
----------
Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from cdpr.models.catenary import (
    ARMIJO_C,
    CATENARY,
    CATENARY_DEFAULTS,
    INFEASIBLE,
    MAX_HALVINGS,
    SLACK,
    TAUT,
    U_SHAPED,
    WHOLE_STEP,
)

__all__ = [
    "angle_f_deg",
    "arc_length",
    "cable_energy",
    "cable_energy_stiffness",
    "cable_state",
    "cable_stiffness",
    "complementary_energy",
    "end_forces",
    "flexibility",
    "sag",
    "span_equations",
    "span_state",
    "spans_and_flexibility",
    "span_states",
    "stiffness",
    "tension_at",
]

_RTOL = CATENARY_DEFAULTS["rtol"]
_MAXITER = CATENARY_DEFAULTS["maxiter"]


@njit(cache=True, inline="always", error_model="numpy")
def _asinh(x):
    """asinh(x) as log1p(|x| + x^2 / (1 + sqrt(1 + x^2))) with x's sign: within an ulp of
    ``math.asinh`` and a third of its time (no cancellation for either sign)."""
    a = abs(x)
    r = math.asinh(a) if a > 1e150 else math.log1p(a + a * a / (1.0 + math.sqrt(1.0 + a * a)))
    return r if x >= 0.0 else -r


@njit(cache=True, inline="always", error_model="numpy")
def _asinhc_series(y):
    """asinh(x) / x from y = x^2 by its series (to x^14: the next term is below 2e-18 for y < 0.01)."""
    return 1.0 - y * (
        1.0 / 6.0
        - y
        * (
            3.0 / 40.0
            - y
            * (
                5.0 / 112.0
                - y * (35.0 / 1152.0 - y * (63.0 / 2816.0 - y * (231.0 / 13312.0 - y * (143.0 / 10240.0))))
            )
        )
    )


@njit(cache=True, inline="always", error_model="numpy")
def _terms_of(H, V_B, L0, w, fast):
    """(V_D, T_B, T_D, S, Qh, Qv, Qd, Qx, Qe) of ``models.catenary._terms``, one cable: the forms
    written once for ``_terms`` (``fast`` False: the reference's arithmetic, hypot and asinh) and
    ``terms_fast`` (True: sqrt(a^2 + b^2), ``_asinh`` and asinh(x)/x by its series for |x| < 0.1).
    Both callers pass a constant ``fast``, so the inlined branch folds away."""
    aH = abs(H)
    V_D = V_B + w * L0
    if fast:
        T_B = math.sqrt(H * H + V_B * V_B)
        T_D = math.sqrt(H * H + V_D * V_D)
    else:
        T_B = math.hypot(H, V_B)
        T_D = math.hypot(H, V_D)
    S = V_B + V_D
    wL = w * L0
    if V_B < 0.0 and V_D > 0.0:
        if fast:
            Qh = (_asinh(V_D / aH) - _asinh(V_B / aH)) / wL
        else:
            Qh = (math.asinh(V_D / aH) - math.asinh(V_B / aH)) / wL
        Qd = (V_D / T_D - V_B / T_B) / wL
        Qe = (V_D * T_D - V_B * T_B) / wL
    else:
        P = V_D * T_B + V_B * T_D
        r = S / P if P != 0.0 else 1.0 / aH
        x = wL * r
        if fast:
            y = x * x
            asinhc = _asinhc_series(y) if y < 0.01 else _asinh(x) / x
        else:
            asinhc = math.asinh(x) / x if x != 0.0 else 1.0
        Qh = r * asinhc
        Qd = H * H * r / (T_B * T_D)
        PE = V_D * T_D + V_B * T_B
        Qe = S * (H * H + V_D * V_D + V_B * V_B) / PE if PE != 0.0 else aH
    TT = T_B + T_D
    if TT > 0.0:
        Qv = S / TT
        Qx = -H * S / (TT * T_B * T_D)
    else:
        Qv = 0.0
        Qx = 0.0
    return V_D, T_B, T_D, S, Qh, Qv, Qd, Qx, Qe


@njit(cache=True, inline="always", error_model="numpy")
def _terms(H, V_B, L0, w):
    """(V_D, T_B, T_D, S, Qh, Qv, Qd, Qx, Qe) of ``models.catenary._terms``, one cable (the
    reference's arithmetic: ``_terms_of``)."""
    return _terms_of(H, V_B, L0, w, False)


@njit(cache=True, inline="always", error_model="numpy")
def terms_fast(H, V_B, L0, w):
    """``_terms`` with sqrt(a^2 + b^2) for hypot and ``_asinh`` for asinh (asinh(x)/x by its series
    for |x| < 0.1, the usual sag): the same forms (``_terms_of``), a few ulp apart and a third of the
    time, for the pose kernel's joint iteration of a cable (``cables._joint``) and its energy and
    stiffness (``cable_energy_stiffness``); the twin functions keep the reference's arithmetic."""
    return _terms_of(H, V_B, L0, w, True)


@njit(cache=True, error_model="numpy")
def span_equations(H, V_B, L0, w, EA):
    """(l_h, l_v) [m] of one cable from its end forces H, V_B [N], unstrained length L0 [m], weight
    w [N/m] and stiffness EA [N] (``models.catenary.span_equations``)."""
    _, _, _, S, Qh, Qv, _, _, _ = _terms(H, V_B, L0, w)
    l_h = 0.0 if (H == 0.0 or L0 == 0.0) else H * L0 * (1.0 / EA + Qh)
    return l_h, L0 * (0.5 * S / EA + Qv)


@njit(cache=True, error_model="numpy")
def flexibility(H, V_B, L0, w, EA):
    """(f11, f12, f22) [m/N] of the symmetric flexibility matrix of one cable
    (``models.catenary.flexibility``)."""
    _, _, _, _, Qh, _, Qd, Qx, _ = _terms(H, V_B, L0, w)
    e = L0 / EA
    return e + L0 * (Qh - Qd), L0 * Qx, e + L0 * Qd


@njit(cache=True, inline="always", error_model="numpy")
def spans_and_flexibility(H, V_B, L0, w, EA):
    """``span_equations`` and ``flexibility`` of one cable from one ``_terms`` (the same arithmetic
    as the two: the Newton iterations of ``span_state`` and ``cables.span_for_tension`` need both
    at every step): (l_h, l_v [m], f11, f12, f22 [m/N])."""
    _, _, _, S, Qh, Qv, Qd, Qx, _ = _terms(H, V_B, L0, w)
    l_h = 0.0 if (H == 0.0 or L0 == 0.0) else H * L0 * (1.0 / EA + Qh)
    e = L0 / EA
    return l_h, L0 * (0.5 * S / EA + Qv), e + L0 * (Qh - Qd), L0 * Qx, e + L0 * Qd


@njit(cache=True, error_model="numpy")
def stiffness(H, V_B, L0, w, EA):
    """(k11, k12, k22) [N/m], the inverse of ``flexibility`` (``models.catenary.stiffness``); zero
    for a slack weightless cable."""
    if w == 0.0 and H == 0.0 and V_B == 0.0:
        return 0.0, 0.0, 0.0
    f11, f12, f22 = flexibility(H, V_B, L0, w, EA)
    return _inverse(f11, f12, f22)


@njit(cache=True, inline="always", error_model="numpy")
def _inverse(f11, f12, f22):
    """The inverse of the symmetric 2 x 2 (f11, f12, f22)."""
    det = f11 * f22 - f12 * f12
    return f22 / det, -f12 / det, f11 / det


@njit(cache=True, inline="always", error_model="numpy")
def _phi(H, V_B, L0, EA, l_h, l_v, V_D, Qh, Qe):
    """``complementary_energy`` from ``_terms``' V_D, Qh, Qe."""
    intT = 0.5 * L0 * (Qe + (0.0 if H == 0.0 else H * H * Qh))
    intT2 = L0 * (H * H + (V_B * V_B + V_B * V_D + V_D * V_D) / 3.0)
    return intT + 0.5 * intT2 / EA - H * l_h - V_B * l_v


@njit(cache=True, error_model="numpy")
def complementary_energy(H, V_B, L0, w, EA, l_h, l_v):
    """Phi [J] of one cable (``models.catenary.complementary_energy``)."""
    V_D, _, _, _, Qh, _, _, _, Qe = _terms(H, V_B, L0, w)
    return _phi(H, V_B, L0, EA, l_h, l_v, V_D, Qh, Qe)


@njit(cache=True, error_model="numpy")
def tension_at(H, V_B, s, w):
    """Tension [N] at unstrained arc length s [m] from B (``models.catenary.tension_at``)."""
    return math.hypot(H, V_B + w * s)


@njit(cache=True, error_model="numpy")
def arc_length(H, V_B, L0, w, EA):
    """Stretched length [m] of one cable (``models.catenary.arc_length``)."""
    if L0 == 0.0:
        return L0
    _, _, _, _, Qh, _, _, _, Qe = _terms(H, V_B, L0, w)
    return L0 + 0.5 * L0 * (Qe + (0.0 if H == 0.0 else H * H * Qh)) / EA


@njit(cache=True, error_model="numpy")
def sag(H, V_B, L0, w, EA, l_h, l_v):
    """Largest deflection [m] of one cable from its chord (``models.catenary.sag``)."""
    if not (w > 0.0 and l_h > 0.0 and H > 0.0):
        return 0.0
    s = min(max((H * l_v / l_h - V_B) / w, 0.0), L0)
    x, z = span_equations(H, V_B, s, w, EA)
    return abs(x * l_v - z * l_h) / math.hypot(l_h, l_v)


@njit(cache=True, error_model="numpy")
def angle_f_deg(H, V_B, l_h, l_v):
    """Angle [deg] of the force at B to the chord (``models.catenary.angle_f_deg``)."""
    return math.degrees(math.atan2(abs(H * l_v - V_B * l_h), H * l_h + V_B * l_v))


@njit(cache=True, error_model="numpy")
def _vertical(l_v, L0, w, EA):
    """(V_B, status code) of a vertical heavy cable (``models.catenary._vertical``)."""
    k = 1.0 + 0.5 * w * L0 / EA
    wL = w * L0
    if math.isinf(EA) and (l_v >= L0 or l_v <= -L0):
        return np.nan, INFEASIBLE
    if l_v >= L0 * k:
        return EA * (l_v / L0 - 1.0) - 0.5 * wL, CATENARY
    if l_v <= -L0 * k:
        return EA * (l_v / L0 + 1.0) - 0.5 * wL, CATENARY
    return 0.5 * (l_v * w / k - wL), U_SHAPED


@njit(cache=True, error_model="numpy")
def _start(l_h, l_v, L0, w, EA):
    """Newton's start (``models.catenary._start``)."""
    c = math.hypot(l_h, l_v)
    Le = max(L0, 1.001 * c)
    rho = math.sqrt(Le * Le - l_v * l_v) / l_h
    if rho < 3.0:
        lam = math.sqrt(6.0 * (rho - 1.0))
    else:
        lam = math.log(2.0 * rho) + math.log(math.log(2.0 * rho) + 1.0)
    for _ in range(6):
        g = math.log(math.sinh(lam) / lam) - math.log(rho)
        lam = max(lam - g / (1.0 / math.tanh(lam) - 1.0 / lam), 1e-3)
    H_cat = w * l_h / (2.0 * lam)
    V_cat = 0.5 * w * (l_v / math.tanh(lam) - Le)
    T = EA * (c / L0 - 1.0) if c > L0 else 0.0
    if not math.isfinite(T):
        T = 0.0
    H_h = T * l_h / c
    if H_h > H_cat:
        return H_h, T * l_v / c - 0.5 * w * L0
    return H_cat, V_cat


@njit(cache=True, error_model="numpy")
def span_state(l_h, l_v, L0, w, EA, H0=np.nan, V0=np.nan, rtol=_RTOL, maxiter=_MAXITER):
    """One cable's (H, V_B [N], status code, iterations, converged) (``models.catenary.span_state``;
    H0, V0 a start, NaN: the default)."""
    c = math.hypot(l_h, l_v)
    if w == 0.0:
        if math.isinf(EA) and c > L0:
            return np.nan, np.nan, INFEASIBLE, 0, False
        if c > L0:
            T = EA * (c / L0 - 1.0)
            return T * l_h / c, T * l_v / c, TAUT, 0, True
        return 0.0, 0.0, SLACK, 0, True
    if l_h == 0.0:
        V, code = _vertical(l_v, L0, w, EA)
        if code == INFEASIBLE:
            return np.nan, np.nan, INFEASIBLE, 0, False
        return 0.0, V, code, 0, True
    if math.isinf(EA) and c >= L0:
        return np.nan, np.nan, INFEASIBLE, 0, False
    if math.isnan(H0):
        H, V = _start(l_h, l_v, L0, w, EA)
    else:
        H, V = H0, V0
    tol = rtol * (L0 + c)
    it = 0
    conv = False
    for _ in range(maxiter):
        lh, lv, f11, f12, f22 = spans_and_flexibility(H, V, L0, w, EA)
        r1 = lh - l_h
        r2 = lv - l_v
        small = math.hypot(r1, r2) <= tol
        det = f11 * f22 - f12 * f12
        dH = -(f22 * r1 - f12 * r2) / det
        dV = -(-f12 * r1 + f11 * r2) / det
        slope = r1 * dH + r2 * dV
        alpha = 1.0 if H + dH > 0.0 else 0.5 * H / max(-dH, 1e-300)
        scale = math.hypot(H, V + 0.5 * w * L0) * L0
        if not (small or -slope <= WHOLE_STEP * scale):
            phi0 = complementary_energy(H, V, L0, w, EA, l_h, l_v)
            for _h in range(MAX_HALVINGS):
                phi = complementary_energy(H + alpha * dH, V + alpha * dV, L0, w, EA, l_h, l_v)
                if phi <= phi0 + ARMIJO_C * alpha * slope:
                    break
                alpha *= 0.5
        H += alpha * dH
        V += alpha * dV
        it += 1
        if small or math.hypot(alpha * dH, alpha * dV) <= 1e-15 * scale / L0:
            conv = True
            break
    code = U_SHAPED if (V < 0.0 and V + w * L0 > 0.0) else CATENARY
    return H, V, code, it, conv


@njit(cache=True, error_model="numpy")
def end_forces(l_h, l_v, L0, w, EA):
    """(H, V_B) [N] of one cable from its spans (``models.catenary.end_forces``)."""
    H, V, _, _, _ = span_state(l_h, l_v, L0, w, EA)
    return H, V


@njit(cache=True, parallel=True, error_model="numpy")
def span_states(l_h, l_v, L0, w, EA):
    """``span_state`` of n cables in parallel: 1-D float arrays (n,) in; H, V_B (n,) [N], status
    codes (n,) int8, iterations (n,) int64 and converged (n,) bool out."""
    n = l_h.shape[0]
    H = np.empty(n)
    V = np.empty(n)
    code = np.empty(n, dtype=np.int8)
    iters = np.empty(n, dtype=np.int64)
    conv = np.empty(n, dtype=np.bool_)
    for i in prange(n):
        h, v, k, it, ok = span_state(l_h[i], l_v[i], L0[i], w[i], EA[i])
        H[i] = h
        V[i] = v
        code[i] = k
        iters[i] = it
        conv[i] = ok
    return H, V, code, iters, conv


@njit(cache=True, inline="always", error_model="numpy")
def _ratio(EA, T):
    """1 / (1 + T/EA) (``models.catenary._ratio``), 1 for EA = inf."""
    return 1.0 if math.isinf(EA) else EA / (EA + T)


@njit(cache=True, inline="always", error_model="numpy")
def _usable(H, V):
    """A start of ``span_state`` where usable (H > 0, both finite, as the reference's), else NaN."""
    if H > 0.0 and math.isfinite(H) and math.isfinite(V):
        return H, V
    return np.nan, np.nan


@njit(cache=True, inline="always", error_model="numpy")
def _dTD_dL0(H, V_B, T_D, L0f, w, EA):
    """dT_D/dL0 of a span at fixed spans (``models.catenary._dTD_dL0``)."""
    if not T_D > 0.0:
        return 0.0
    k11, k12, k22 = stiffness(H, V_B, L0f, w, EA)
    V_D = V_B + w * L0f
    k = 1.0 / EA + 1.0 / T_D
    gh, gv = k * H, k * V_D
    dH = -(k11 * gh + k12 * gv)
    dV = -(k12 * gh + k22 * gv)
    return (H * dH + V_D * (dV + w)) / T_D


@njit(cache=True, error_model="numpy")
def cable_state(l_h, l_v, L0, l_dead, w, EA, H0=np.nan, V0=np.nan, L0f0=np.nan, maxiter=30):
    """One whole heavy cable (``models.catenary.cable_state``): the free span's (H, V_B [N], status
    code, iterations (outer), converged) and L0_free [m], by Newton's method on the split
    L0 = L0_free + l_dead / (1 + T_D/EA), each free span by ``span_state`` warm-started from the
    last. H0, V0 [N] a start of the first span solve and L0f0 [m] one of the split (NaN: the
    reference's, from Hooke's law on the whole length; ignored where the split is fixed, l_dead = 0
    or EA = inf, and replaced by the reference's where its span is infeasible); the converged answer
    does not depend on them (a convex span problem, a split function increasing with slope >= 1)."""
    c = math.hypot(l_h, l_v)
    T0 = EA * ((c + l_dead) / L0 - 1.0) if c + l_dead > L0 else 0.0
    if not math.isfinite(T0):
        T0 = 0.0
    L0f = L0 - l_dead * _ratio(EA, T0)
    if not L0f > 0.0:
        return np.nan, np.nan, INFEASIBLE, 0, False, np.nan
    fixed = l_dead == 0.0 or math.isinf(EA)  # the split does not depend on the tension: L0f is known
    cold = L0f
    warm = not fixed and L0f0 > 0.0 and L0f0 < L0
    if warm:
        L0f = L0f0
    it = 0
    done = False
    hs, vs = _usable(H0, V0)
    H = V = np.nan
    code = INFEASIBLE
    for _ in range(maxiter):
        H, V, code, _, _ = span_state(l_h, l_v, L0f, w, EA, hs, vs)
        if code == INFEASIBLE and warm:  # a warm split too short for the span: the reference's start
            warm = False
            L0f = cold
            continue
        hs, vs = _usable(H, V)
        T_D = math.hypot(H, V + w * L0f)
        phi = L0f + l_dead * _ratio(EA, T_D) - L0
        slope = 1.0
        if not fixed:
            dT = _dTD_dL0(H, V, T_D, L0f, w, EA)
            slope = 1.0 - l_dead * EA / (EA + T_D) ** 2 * dT
            if not math.isfinite(slope):
                slope = 1.0
        step = 0.0 if code == INFEASIBLE else -phi / slope
        new = L0f + step
        if not new > 0.0:
            new = 0.5 * L0f
        it += 1
        done = abs(new - L0f) <= 4e-16 * L0
        L0f = new
        if done:
            break
    H, V, code, _, conv = span_state(l_h, l_v, L0f, w, EA, hs, vs)
    return H, V, code, it, conv and done, L0f


@njit(cache=True, error_model="numpy")
def cable_stiffness(H, V_B, L0f, l_dead, w, EA):
    """(k11, k12, k21, k22) [N/m], d(H, V_B)/d(l_h, l_v) of a whole cable with the split following
    the tension at D (``models.catenary.cable_stiffness``; not symmetric in general)."""
    k11, k12, k22 = stiffness(H, V_B, L0f, w, EA)
    return _whole_stiffness(k11, k12, k22, H, V_B, L0f, l_dead, w, EA, math.hypot(H, V_B + w * L0f))


@njit(cache=True, inline="always", error_model="numpy")
def _whole_stiffness(k11, k12, k22, H, V_B, L0f, l_dead, w, EA, T_D):
    """``cable_stiffness`` from the free span's ``stiffness`` (k11, k12, k22) and T_D [N]."""
    V_D = V_B + w * L0f
    gk = 1.0 / EA + 1.0 / T_D if T_D > 0.0 else 0.0
    gh, gv = gk * H, gk * V_D
    Kg0 = k11 * gh + k12 * gv
    Kg1 = k12 * gh + k22 * gv
    inv = 1.0 / T_D if T_D > 0.0 else 0.0
    cpr = 0.0 if math.isinf(EA) else l_dead * EA / (EA + T_D) ** 2
    dT0 = (H * k11 + V_D * k12) * inv
    dT1 = (H * k12 + V_D * k22) * inv
    dTL = (H * -Kg0 + V_D * (-Kg1 + w)) * inv
    q = 1.0 - cpr * dTL
    dL0 = cpr * dT0 / q
    dL1 = cpr * dT1 / q
    return k11 - Kg0 * dL0, k12 - Kg0 * dL1, k12 - Kg1 * dL0, k22 - Kg1 * dL1


@njit(cache=True, error_model="numpy")
def cable_energy(H, V_B, L0f, l_h, l_v, l_dead, w, EA):
    """Potential energy [J] of a whole cable up to a constant (``models.catenary.cable_energy``)."""
    phi = complementary_energy(H, V_B, L0f, w, EA, l_h, l_v)
    return _whole_energy(phi, l_dead, EA, math.hypot(H, V_B + w * L0f))


@njit(cache=True, inline="always", error_model="numpy")
def _whole_energy(phi, l_dead, EA, T_D):
    """``cable_energy`` from the free span's ``complementary_energy`` phi and T_D [N]."""
    if math.isinf(EA):
        return -phi
    return l_dead * _ratio(EA, T_D) * T_D * T_D / (2.0 * EA) - phi


@njit(cache=True, error_model="numpy")
def cable_energy_stiffness(H, V_B, L0f, l_h, l_v, l_dead, w, EA):
    """``cable_energy`` [J] and ``cable_stiffness`` (k11, k12, k21, k22) [N/m] of a whole cable from
    one ``terms_fast`` (the pose kernel needs both at every cable; the two's forms, a few ulp
    apart)."""
    V_D, _, T_D, _, Qh, _, Qd, Qx, Qe = terms_fast(H, V_B, L0f, w)
    energy = _whole_energy(_phi(H, V_B, L0f, EA, l_h, l_v, V_D, Qh, Qe), l_dead, EA, T_D)
    if w == 0.0 and H == 0.0 and V_B == 0.0:
        k11 = k12 = k22 = 0.0
    else:
        e = L0f / EA
        k11, k12, k22 = _inverse(e + L0f * (Qh - Qd), L0f * Qx, e + L0f * Qd)
    k11, k12, k21, k22 = _whole_stiffness(k11, k12, k22, H, V_B, L0f, l_dead, w, EA, T_D)
    return energy, k11, k12, k21, k22
