"""One heavy elastic cable: Irvine's elastic catenary between the platform attachment B and the
exit point D, in their vertical plane (Irvine 1981, ch. 2).

Conventions (issue 38). In the cable's vertical plane, x is horizontal from B toward D and z points
up; B is the origin. The cable has unstrained length L0 (the free span only: not the dead length
nor the wrap), weight w per *unstrained* metre [N/m] (w = rho A g) and axial stiffness EA [N]
(EA = inf: inextensible). The spans are l_h >= 0 (horizontal, B to D) and l_v = z_D - z_B
(positive when D is above B). The end forces on the platform at B are H >= 0 (horizontal, toward
D) and V_B (vertical, positive upward). With s the unstrained arc length from B, the tension
vector is (H, V(s)), V(s) = V_B + w s, so V_D = V_B + w L0, and T(s) = sqrt(H^2 + V(s)^2).

The two span equations (``span_equations``) are the integrals of the stretched tangent
(1 + T/EA) (H, V)/T ds over the cable. They are written in forms free of cancellation (no
difference of nearly equal numbers, no division by w), so that w = 0 is exactly the straight
Hooke spring and w -> 0 is continuous; ``flexibility`` is their analytic Jacobian with respect to
(H, V_B), symmetric and positive definite (it is the Hessian of the complementary energy
``complementary_energy``, which ``end_forces`` minimises by Newton's method with an Armijo line
search: a convex problem, so every start reaches the one solution).

Statuses (``SPAN_STATUSES``): ``taut`` (w = 0, stretched), ``slack`` (w = 0, chord <= L0, no
force), ``catenary`` (w > 0, the lowest point of the cable at an end: V_B >= 0, or V_D <= 0 for a
cable that descends from B all the way to D), ``U`` (w > 0, the lowest point inside the span,
V_B < 0 < V_D), ``infeasible`` (EA = inf and a chord the inextensible cable cannot span: no
equilibrium; forces NaN).

References
----------
Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2 (the elastic catenary: Lagrangian
coordinates, the span equations, the flexibility of the cable's end).

Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (section 2.2.3
neglects the cable mass; this module is the heavy cable that section leaves out).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from cdpr.errors import CdprError

#: Per-cable statuses of a span, by code.
SPAN_STATUSES = ("taut", "slack", "catenary", "U", "infeasible")
TAUT, SLACK, CATENARY, U_SHAPED, INFEASIBLE = range(5)
#: Newton's defaults: relative residual (of the spans, against L0 + chord), iteration cap.
CATENARY_DEFAULTS = {"rtol": 1e-13, "maxiter": 100}
#: Armijo constant and the largest number of halvings of the line search.
ARMIJO_C = 1e-4
MAX_HALVINGS = 60
#: Newton decrements below this fraction of T L0 are taken whole (no line search: round-off).
WHOLE_STEP = 1e-9


class Span(NamedTuple):
    """A solved span, arrays of the broadcast shape of the inputs.

    H, V_B, V_D [N] (V_D = V_B + w L0), T_B, T_D [N] tensions at B and D; status_code (int8) and
    status (str, ``SPAN_STATUSES``); iterations (Newton's, 0 in closed form); converged (bool).
    """

    H: np.ndarray
    V_B: np.ndarray
    V_D: np.ndarray
    T_B: np.ndarray
    T_D: np.ndarray
    status_code: np.ndarray
    status: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray


def _arrays(*xs):
    return np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in xs))


def _terms(H, V_B, L0, w):
    """The per-unstrained-metre quantities of the span equations and their Jacobian, free of
    cancellation. Returns V_D, T_B, T_D, S = V_B + V_D, U (V_B < 0 < V_D), and

    Qh = (asinh(V_D/H) - asinh(V_B/H)) / (w L0)     (-> 1/T as w -> 0)
    Qv = (T_D - T_B) / (w L0) = S / (T_B + T_D)
    Qd = (V_D/T_D - V_B/T_B) / (w L0)                (-> H^2/T^3)
    Qx = H (1/T_D - 1/T_B) / (w L0) = -H S / ((T_B + T_D) T_B T_D)
    Qe = (V_D T_D - V_B T_B) / (w L0)                (-> (H^2 + 2 V^2)/T)

    Where V_B and V_D have the same sign the differences are rewritten as quotients (e.g.
    asinh a - asinh b = asinh((a - b)(a + b) / (a sqrt(1 + b^2) + b sqrt(1 + a^2)))), where they
    have opposite signs (U) the differences are sums of terms of one sign.
    """
    aH = np.abs(H)
    V_D = V_B + w * L0
    T_B, T_D = np.hypot(H, V_B), np.hypot(H, V_D)
    S = V_B + V_D
    U = (V_B < 0.0) & (V_D > 0.0)
    wL = w * L0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        P = V_D * T_B + V_B * T_D
        r = np.where(P != 0.0, S / P, 1.0 / aH)  # same sign: (asinh a - asinh b) = asinh(wL0 r)
        x = wL * r
        asinhc = np.where(x != 0.0, np.arcsinh(x) / x, 1.0)
        Qh_same = r * asinhc
        Qd_same = H * H * r / (T_B * T_D)
        PE = V_D * T_D + V_B * T_B
        Qe_same = np.where(PE != 0.0, S * (H * H + V_D * V_D + V_B * V_B) / PE, aH)
        Qh_U = (np.arcsinh(V_D / aH) - np.arcsinh(V_B / aH)) / wL
        Qd_U = (V_D / T_D - V_B / T_B) / wL
        Qe_U = (V_D * T_D - V_B * T_B) / wL
        Qh = np.where(U, Qh_U, Qh_same)
        Qd = np.where(U, Qd_U, Qd_same)
        Qe = np.where(U, Qe_U, Qe_same)
        TT = T_B + T_D
        Qv = np.where(TT > 0.0, S / TT, 0.0)
        Qx = np.where(TT > 0.0, -H * S / (TT * T_B * T_D), 0.0)
    return V_D, T_B, T_D, S, U, Qh, Qv, Qd, Qx, Qe


def span_equations(H, V_B, L0, w, EA):
    """Horizontal and vertical spans of an elastic catenary from its end forces (Irvine 1981, ch. 2).

    .. math::

        l_h = \\frac{H L_0}{EA} + \\frac{H}{w}\\left[\\operatorname{asinh}\\frac{V_D}{H}
              - \\operatorname{asinh}\\frac{V_B}{H}\\right], \\qquad
        l_v = \\frac{L_0 (V_B + V_D)}{2 EA} + \\frac{T_D - T_B}{w},

    with V_D = V_B + w L_0 and T = sqrt(H^2 + V^2), evaluated in cancellation-free forms (module
    docstring; ``_terms``): at w = 0 they are the straight Hooke spring, l = L0 (1 + T/EA) along
    (H, V_B)/T. With L0 replaced by s in [0, L0] they give the cable's shape (``shape``).

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force (on the platform, toward D).
    V_B : array_like (...) [N]
        Vertical end force on the platform at B (positive upward).
    L0 : array_like (...) [m]
        Unstrained length of the span.
    w : array_like (...) [N/m]
        Weight per unstrained metre (>= 0).
    EA : array_like (...) [N]
        Axial stiffness (inf: inextensible).

    Returns
    -------
    l_h : ndarray (...) [m]
        Horizontal span from B to D.
    l_v : ndarray (...) [m]
        Vertical span z_D - z_B.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2 (the elastic catenary).
    """
    H, V_B, L0, w, EA = _arrays(H, V_B, L0, w, EA)
    _, _, _, S, _, Qh, Qv, _, _, _ = _terms(H, V_B, L0, w)
    with np.errstate(invalid="ignore"):
        l_h = np.where((H == 0.0) | (L0 == 0.0), 0.0, H * L0 * (1.0 / EA + Qh))
    l_v = L0 * (0.5 * S / EA + Qv)
    return l_h, l_v


def flexibility(H, V_B, L0, w, EA):
    """Flexibility matrix of the span: the Jacobian of (l_h, l_v) with respect to (H, V_B)
    (Irvine 1981, ch. 2), symmetric, positive definite for w > 0 or finite EA.

    .. math::

        \\frac{\\partial l_h}{\\partial H} = \\frac{L_0}{EA} + \\frac{1}{w}\\left[
            \\operatorname{asinh}\\frac{V_D}{H} - \\operatorname{asinh}\\frac{V_B}{H}\\right]
            - \\frac{1}{w}\\left[\\frac{V_D}{T_D} - \\frac{V_B}{T_B}\\right], \\quad
        \\frac{\\partial l_h}{\\partial V_B} = \\frac{\\partial l_v}{\\partial H}
            = \\frac{H}{w}\\left[\\frac{1}{T_D} - \\frac{1}{T_B}\\right], \\quad
        \\frac{\\partial l_v}{\\partial V_B} = \\frac{L_0}{EA}
            + \\frac{1}{w}\\left[\\frac{V_D}{T_D} - \\frac{V_B}{T_B}\\right],

    in the cancellation-free forms of ``_terms`` (w = 0: the straight spring's L0/EA I +
    L0 H^2/T^3 ... , i.e. L0/EA I + (L0/T)(I - e e^T) in (H, V) with e = (H, V)/T).

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B (positive upward).
    L0 : array_like (...) [m]
        Unstrained length.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).

    Returns
    -------
    F : ndarray (..., 2, 2) [m/N]
        [[dl_h/dH, dl_h/dV_B], [dl_v/dH, dl_v/dV_B]].

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA = _arrays(H, V_B, L0, w, EA)
    _, _, _, _, _, Qh, _, Qd, Qx, _ = _terms(H, V_B, L0, w)
    e = L0 / EA
    f11 = e + L0 * (Qh - Qd)
    f12 = L0 * Qx
    f22 = e + L0 * Qd
    return np.stack([np.stack([f11, f12], axis=-1), np.stack([f12, f22], axis=-1)], axis=-2)


def complementary_energy(H, V_B, L0, w, EA, l_h, l_v):
    """The span's complementary energy less the work of the end forces on the spans; its gradient
    in (H, V_B) is the span residual (l_h(H, V_B) - l_h, l_v(H, V_B) - l_v), its Hessian the
    flexibility, so the end forces are its minimum (convex; Irvine 1981, ch. 2, energy methods).

    .. math::

        \\Phi = \\int_0^{L_0} \\left(T + \\frac{T^2}{2 EA}\\right) ds - H l_h - V_B l_v,
        \\quad \\int_0^{L_0} T\\,ds = \\frac{1}{2w}\\left[V T + H^2 \\operatorname{asinh}
            \\frac{V}{H}\\right]_{V_B}^{V_D}

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    L0 : array_like (...) [m]
        Unstrained length.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).
    l_h : array_like (...) [m]
        Horizontal span to reach.
    l_v : array_like (...) [m]
        Vertical span to reach.

    Returns
    -------
    Phi : ndarray (...) [J]
        The energy.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA, l_h, l_v = _arrays(H, V_B, L0, w, EA, l_h, l_v)
    V_D, _, _, _, _, Qh, _, _, _, Qe = _terms(H, V_B, L0, w)
    with np.errstate(invalid="ignore"):
        intT = 0.5 * L0 * (Qe + np.where(H == 0.0, 0.0, H * H * Qh))
    intT2 = L0 * (H * H + (V_B * V_B + V_B * V_D + V_D * V_D) / 3.0)
    return intT + 0.5 * intT2 / EA - H * l_h - V_B * l_v


def _check(l_h, l_v, L0, w, EA):
    for name, x, ok in (
        ("l_h", l_h, np.isfinite(l_h) & (l_h >= 0.0)),
        ("l_v", l_v, np.isfinite(l_v)),
        ("L0", L0, np.isfinite(L0) & (L0 > 0.0)),
        ("w", w, np.isfinite(w) & (w >= 0.0)),
        ("EA", EA, (EA > 0.0) & ~np.isnan(EA)),
    ):
        if not np.all(ok):
            bad = np.asarray(x)[~ok].flat[0]
            allowed = {"l_h": ">= 0", "l_v": "finite", "L0": "> 0", "w": ">= 0", "EA": "> 0 (inf allowed)"}
            raise CdprError(f"catenary: {name} = {bad!r} is not allowed; allowed: {allowed[name]}")


def _vertical(l_v, L0, w, EA):
    """V_B and status of a vertical span (l_h = 0, w > 0) in closed form (three regimes)."""
    k = 1.0 + 0.5 * w * L0 / EA  # stretched length of a cable that hangs from one end, over L0
    wL = w * L0
    up = l_v >= L0 * k  # V_B >= 0: hangs from D, pulls B up
    down = l_v <= -L0 * k  # V_D <= 0: hangs from B, D below it
    with np.errstate(invalid="ignore"):
        V_up = EA * (l_v / L0 - 1.0) - 0.5 * wL
        V_down = EA * (l_v / L0 + 1.0) - 0.5 * wL
    V_fold = 0.5 * (l_v * w / k - wL)  # folded: V_B < 0 < V_D
    V = np.where(up, V_up, np.where(down, V_down, V_fold))
    code = np.where(up | down, CATENARY, U_SHAPED)
    infeasible = np.isinf(EA) & ((l_v >= L0) | (l_v <= -L0))
    code = np.where(infeasible, INFEASIBLE, code)
    V = np.where(infeasible, np.nan, V)
    return V, code


def _start(l_h, l_v, L0, w, EA):
    """Newton's start: the larger-tension of the inextensible catenary spanning (l_h, l_v) with
    length max(L0, 1.001 chord) and the straight Hooke spring (module docstring)."""
    c = np.hypot(l_h, l_v)
    Le = np.maximum(L0, 1.001 * c)
    rho = np.sqrt(Le * Le - l_v * l_v) / l_h  # sinh(lam)/lam = rho >= 1
    lam = np.where(rho < 3.0, np.sqrt(6.0 * (rho - 1.0)), np.log(2.0 * rho) + np.log(np.log(2.0 * rho) + 1.0))
    for _ in range(6):  # Newton on log(sinh lam / lam) = log rho
        g = np.log(np.sinh(lam) / lam) - np.log(rho)
        lam = np.maximum(lam - g / (1.0 / np.tanh(lam) - 1.0 / lam), 1e-3)
    H_cat = w * l_h / (2.0 * lam)
    V_cat = 0.5 * w * (l_v / np.tanh(lam) - Le)
    with np.errstate(invalid="ignore"):
        T = np.where(c > L0, EA * (c / L0 - 1.0), 0.0)
    T = np.where(np.isfinite(T), T, 0.0)
    H_h, V_h = T * l_h / c, T * l_v / c - 0.5 * w * L0
    hooke = H_h > H_cat
    return np.where(hooke, H_h, H_cat), np.where(hooke, V_h, V_cat)


def span_state(l_h, l_v, L0, w, EA, start=None, rtol=None, maxiter=None):
    """End forces, tensions and status of elastic catenaries from their spans (Irvine 1981, ch. 2):
    the solution (H, V_B) of ``span_equations`` = (l_h, l_v).

    w = 0: the straight Hooke spring in closed form (T = EA (chord/L0 - 1) along the chord, or
    slack). l_h = 0: the vertical cable in closed form (hanging from D; folded, V_B < 0 < V_D;
    hanging from B). Otherwise Newton's method on the span equations with the analytic
    ``flexibility``, globalised by an Armijo line search on ``complementary_energy`` (convex) and
    kept at H > 0 (fraction to the boundary); U-shaped spans are solved like the others.

    Parameters
    ----------
    l_h : array_like (...) [m]
        Horizontal span from B to D (>= 0).
    l_v : array_like (...) [m]
        Vertical span z_D - z_B.
    L0 : array_like (...) [m]
        Unstrained length of the free span (> 0).
    w : array_like (...) [N/m]
        Weight per unstrained metre (>= 0).
    EA : array_like (...) [N]
        Axial stiffness (> 0; inf: inextensible).
    start : tuple of array_like (...), optional
        Newton's starting (H, V_B) [N]; ``_start`` where not given or not usable (H <= 0, NaN).
    rtol : float, optional
        Residual tolerance relative to L0 + chord (``CATENARY_DEFAULTS``).
    maxiter : int, optional
        Newton's iteration cap (``CATENARY_DEFAULTS``).

    Returns
    -------
    Span
        H, V_B, V_D, T_B, T_D [N], status_code, status, iterations, converged.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    l_h, l_v, L0, w, EA = (np.array(x) for x in _arrays(l_h, l_v, L0, w, EA))
    _check(l_h, l_v, L0, w, EA)
    rtol = CATENARY_DEFAULTS["rtol"] if rtol is None else rtol
    maxiter = CATENARY_DEFAULTS["maxiter"] if maxiter is None else maxiter
    shape = l_h.shape
    l_h, l_v, L0, w, EA = (x.ravel() for x in (l_h, l_v, L0, w, EA))
    n = l_h.size
    c = np.hypot(l_h, l_v)
    H, V = np.zeros(n), np.zeros(n)
    code = np.zeros(n, dtype=np.int8)
    iters = np.zeros(n, dtype=np.int64)
    conv = np.ones(n, dtype=bool)

    # w = 0: the straight Hooke spring
    m0 = w == 0.0
    taut = m0 & (c > L0)
    with np.errstate(invalid="ignore", divide="ignore"):
        T = EA * (c / L0 - 1.0)
        H = np.where(taut, T * l_h / c, H)
        V = np.where(taut, T * l_v / c, V)
    code[m0] = np.where(taut[m0], TAUT, SLACK)
    # inextensible and too short a cable for its chord: no equilibrium
    bad = np.isinf(EA) & (c > L0) | (np.isinf(EA) & ~m0 & (c >= L0) & (l_h > 0.0))
    # vertical heavy cables
    vert = ~m0 & (l_h == 0.0)
    Vv, cv = _vertical(l_v[vert], L0[vert], w[vert], EA[vert])
    H[vert], V[vert], code[vert] = 0.0, Vv, cv
    bad |= vert & (code == INFEASIBLE)
    # Newton on the others
    todo = np.flatnonzero(~m0 & ~vert & ~bad)
    if todo.size:
        args = (L0[todo], w[todo], EA[todo])
        tgt = (l_h[todo], l_v[todo])
        h, v = _start(tgt[0], tgt[1], *args)
        if start is not None:  # a given start where it is usable (H > 0, finite), else the default
            h1, v1 = (np.broadcast_to(np.asarray(x, dtype=float), shape).ravel()[todo] for x in start)
            use = (h1 > 0.0) & np.isfinite(h1) & np.isfinite(v1)
            h, v = np.where(use, h1, h), np.where(use, v1, v)
        h, v, it, ok = _newton(h, v, args, tgt, c[todo], rtol, maxiter)
        H[todo], V[todo], iters[todo], conv[todo] = h, v, it, ok
        VD = v + args[1] * args[0]
        code[todo] = np.where((v < 0.0) & (VD > 0.0), U_SHAPED, CATENARY)
    H[bad], V[bad], code[bad], conv[bad] = np.nan, np.nan, INFEASIBLE, False
    V_D = V + w * L0
    out = [x.reshape(shape) for x in (H, V, V_D, np.hypot(H, V), np.hypot(H, V_D))]
    code = code.reshape(shape)
    return Span(*out, code, np.asarray(SPAN_STATUSES)[code], iters.reshape(shape), conv.reshape(shape))


def _newton(H, V, args, tgt, c, rtol, maxiter):
    """Newton's iteration of ``span_state`` over the points given (1-D arrays)."""
    L0, w, EA = args
    n = H.size
    iters = np.zeros(n, dtype=np.int64)
    conv = np.zeros(n, dtype=bool)
    act = np.arange(n)
    tol = rtol * (L0 + c)
    for _ in range(maxiter):
        if act.size == 0:
            break
        a = (L0[act], w[act], EA[act])
        lh, lv = span_equations(H[act], V[act], *a)
        r1, r2 = lh - tgt[0][act], lv - tgt[1][act]
        small = np.hypot(r1, r2) <= tol[act]  # converged: this last (polishing) step is taken whole
        F = flexibility(H[act], V[act], *a)
        det = F[:, 0, 0] * F[:, 1, 1] - F[:, 0, 1] * F[:, 1, 0]
        dH = -(F[:, 1, 1] * r1 - F[:, 0, 1] * r2) / det
        dV = -(-F[:, 1, 0] * r1 + F[:, 0, 0] * r2) / det
        slope = r1 * dH + r2 * dV  # dPhi along the step (< 0)
        h0, v0 = H[act], V[act]
        keep = h0 + dH > 0.0  # else halve the way to H = 0 (the divisor only where it is used)
        alpha = np.where(keep, 1.0, 0.5 * h0 / np.maximum(np.where(keep, 1.0, -dH), 1e-300))
        scale = np.hypot(h0, v0 + 0.5 * a[1] * a[0]) * a[0]
        whole = small | (-slope <= WHOLE_STEP * scale)
        phi0 = complementary_energy(h0, v0, *a, tgt[0][act], tgt[1][act])
        pend = np.flatnonzero(~whole)
        for _h in range(MAX_HALVINGS):
            if pend.size == 0:
                break
            k = act[pend]
            phi = complementary_energy(
                h0[pend] + alpha[pend] * dH[pend],
                v0[pend] + alpha[pend] * dV[pend],
                L0[k],
                w[k],
                EA[k],
                tgt[0][k],
                tgt[1][k],
            )
            ok = phi <= phi0[pend] + ARMIJO_C * alpha[pend] * slope[pend]
            pend = pend[~ok]
            alpha[pend] *= 0.5
        H[act] = h0 + alpha * dH
        V[act] = v0 + alpha * dV
        iters[act] += 1
        done = small | (np.hypot(alpha * dH, alpha * dV) <= 1e-15 * scale / a[0])
        conv[act[done]] = True
        act = act[~done]
    return H, V, iters, conv


def end_forces(l_h, l_v, L0, w, EA):
    """End forces on the platform of elastic catenaries from their spans (Irvine 1981, ch. 2):
    ``span_state``'s (H, V_B); its ``status`` gives the per-cable status.

    .. math::

        l_h(H, V_B) = l_h, \\quad l_v(H, V_B) = l_v \\quad (\\text{``span\\_equations``})

    Parameters
    ----------
    l_h : array_like (...) [m]
        Horizontal span from B to D (>= 0).
    l_v : array_like (...) [m]
        Vertical span z_D - z_B (positive when D is above B).
    L0 : array_like (...) [m]
        Unstrained length of the free span only (not the dead length and the wrap).
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).

    Returns
    -------
    H : ndarray (...) [N]
        Horizontal force on the platform toward D (>= 0).
    V_B : ndarray (...) [N]
        Vertical force on the platform at B (positive upward).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    s = span_state(l_h, l_v, L0, w, EA)
    return s.H, s.V_B


def stiffness(H, V_B, L0, w, EA):
    """Stiffness matrix of the span: the inverse of ``flexibility``, d(H, V_B)/d(l_h, l_v), for the
    equilibrium's Newton (Irvine 1981, ch. 2).

    .. math:: K = F^{-1}

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    L0 : array_like (...) [m]
        Unstrained length.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).

    Returns
    -------
    K : ndarray (..., 2, 2) [N/m]
        d(H, V_B)/d(l_h, l_v); zero for a slack weightless cable (H = V_B = w = 0).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA = _arrays(H, V_B, L0, w, EA)
    F = flexibility(H, V_B, L0, w, EA)
    det = F[..., 0, 0] * F[..., 1, 1] - F[..., 0, 1] * F[..., 1, 0]
    slack = (w == 0.0) & (H == 0.0) & (V_B == 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        K = (
            np.stack(
                [
                    np.stack([F[..., 1, 1], -F[..., 0, 1]], axis=-1),
                    np.stack([-F[..., 1, 0], F[..., 0, 0]], axis=-1),
                ],
                axis=-2,
            )
            / det[..., None, None]
        )
    return np.where(slack[..., None, None], 0.0, K)


def tension_at(H, V_B, s, w):
    """Tension at unstrained arc length s from B (Irvine 1981, ch. 2).

    .. math:: T(s) = \\sqrt{H^2 + (V_B + w s)^2}

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    s : array_like (...) [m]
        Unstrained arc length from B (L0: the tension at D).
    w : array_like (...) [N/m]
        Weight per unstrained metre.

    Returns
    -------
    T : ndarray (...) [N]
        The tension.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    return np.hypot(H, np.asarray(V_B) + np.asarray(w) * np.asarray(s))


def shape(H, V_B, L0, w, EA, n=101):
    """Points along the cable, from B to D, in the cable's plane (x horizontal toward D, z up, from
    B): ``span_equations`` with L0 replaced by s = L0 k/(n-1), k = 0..n-1 (Irvine 1981, ch. 2).

    .. math:: x(s) = \\frac{H s}{EA} + \\frac{H}{w}\\left[\\operatorname{asinh}\\frac{V_B + w s}{H}
        - \\operatorname{asinh}\\frac{V_B}{H}\\right], \\quad
        z(s) = \\frac{V_B s + w s^2/2}{EA} + \\frac{T(s) - T_B}{w}

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    L0 : array_like (...) [m]
        Unstrained length.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).
    n : int
        Number of points (>= 2).

    Returns
    -------
    x : ndarray (..., n) [m]
        Horizontal coordinates from B.
    z : ndarray (..., n) [m]
        Vertical coordinates from B.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA = (x[..., None] for x in _arrays(H, V_B, L0, w, EA))
    s = L0 * np.linspace(0.0, 1.0, n)
    return span_equations(H, V_B, s, w, EA)


def arc_length(H, V_B, L0, w, EA):
    """Stretched length of the cable (Irvine 1981, ch. 2).

    .. math:: L = \\int_0^{L_0} \\left(1 + \\frac{T}{EA}\\right) ds
        = L_0 + \\frac{1}{2 w EA}\\left[V T + H^2 \\operatorname{asinh}\\frac{V}{H}\\right]_{V_B}^{V_D}

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    L0 : array_like (...) [m]
        Unstrained length.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).

    Returns
    -------
    L : ndarray (...) [m]
        The stretched arc length.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA = _arrays(H, V_B, L0, w, EA)
    _, _, _, _, _, Qh, _, _, _, Qe = _terms(H, V_B, L0, w)
    with np.errstate(invalid="ignore"):
        intT = np.where(L0 == 0.0, 0.0, 0.5 * L0 * (Qe + np.where(H == 0.0, 0.0, H * H * Qh)))
    return L0 + intT / EA


def sag(H, V_B, L0, w, EA, l_h, l_v):
    """Largest perpendicular deflection of the cable from its chord B-D: at the point where the
    tangent, along (H, V(s)), is parallel to the chord, s* = (H l_v/l_h - V_B)/w (Irvine 1981,
    ch. 2; the shallow level span's w l_h^2/(8H) in the limit).

    .. math:: \\text{sag} = \\frac{|x(s^*) l_v - z(s^*) l_h|}{\\sqrt{l_h^2 + l_v^2}}

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    L0 : array_like (...) [m]
        Unstrained length.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).
    l_h : array_like (...) [m]
        Horizontal span.
    l_v : array_like (...) [m]
        Vertical span.

    Returns
    -------
    sag : ndarray (...) [m]
        The deflection (0 for a straight or vertical cable).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA, l_h, l_v = _arrays(H, V_B, L0, w, EA, l_h, l_v)
    curved = (w > 0.0) & (l_h > 0.0) & (H > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.clip(np.where(curved, (H * l_v / l_h - V_B) / w, 0.0), 0.0, L0)
    x, z = span_equations(H, V_B, s, w, EA)
    c = np.hypot(l_h, l_v)
    with np.errstate(invalid="ignore"):
        return np.where(curved, np.abs(x * l_v - z * l_h) / c, 0.0)


def arc_minus_chord(H, V_B, L0, w, EA, l_h, l_v):
    """Stretched arc length less the chord |D - B| (Irvine 1981, ch. 2; ``arc_length``).

    .. math:: L - \\sqrt{l_h^2 + l_v^2}

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    L0 : array_like (...) [m]
        Unstrained length.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).
    l_h : array_like (...) [m]
        Horizontal span.
    l_v : array_like (...) [m]
        Vertical span.

    Returns
    -------
    excess : ndarray (...) [m]
        Arc minus chord (>= 0 up to round-off; the slack cable's excess length).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    return arc_length(H, V_B, L0, w, EA) - np.hypot(l_h, l_v)


def angle_f_deg(H, V_B, l_h, l_v):
    """Angle between the cable's force on the platform at B, (H, V_B), and the chord from B to D
    (l_h, l_v): how far the heavy cable's wrench is from the massless model's direction.

    .. math:: \\angle = \\operatorname{atan2}(|H l_v - V_B l_h|, H l_h + V_B l_v)

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force.
    V_B : array_like (...) [N]
        Vertical end force at B.
    l_h : array_like (...) [m]
        Horizontal span.
    l_v : array_like (...) [m]
        Vertical span.

    Returns
    -------
    angle : ndarray (...) [deg]
        In [0, 180]; 0 for a straight cable (and for a slack one, no force).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, l_h, l_v = _arrays(H, V_B, l_h, l_v)
    return np.degrees(np.arctan2(np.abs(H * l_v - V_B * l_h), H * l_h + V_B * l_v))


class CableState(NamedTuple):
    """A whole cable solved (``cable_state``): the free span's ``Span`` (H, V_B, V_D, T_B, T_D [N],
    status_code, status, iterations (outer, over the split), converged) and L0_free [m], the
    unstrained length of the free span."""

    span: Span
    L0_free: np.ndarray


def cable_state(l_h, l_v, L0, l_dead, w, EA, start=None, maxiter=30):
    """A whole heavy cable: the free span B-D (an elastic catenary) and a straight weightless part of
    stretched length l_dead (the dead length and the arc wrapped on the sheave, issue 38's pulley
    coupling) that carries the tension at D over a frictionless sheave; L0 is the whole cable's
    unstrained length, split as

    .. math:: L_0 = L_{0,free} + \\frac{l_{dead}}{1 + T_D / EA}

    solved by Newton's method on the split (the function of L0_free above is increasing with slope
    >= 1), each free span by ``span_state`` warm-started from the last. w = 0 is Hooke's law on
    the whole length, T = EA ((chord + l_dead)/L0 - 1) (Paty 2021 eq. 10, 13).

    Parameters
    ----------
    l_h : array_like (...) [m]
        Horizontal span from B to D.
    l_v : array_like (...) [m]
        Vertical span z_D - z_B.
    L0 : array_like (...) [m]
        Unstrained length of the whole cable (C to B: dead length, wrap and free span).
    l_dead : array_like (...) [m]
        Stretched length of the part from the winch exit C to D (|l_d| + r_p gamma), >= 0.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).
    start : tuple of array_like (...), optional
        (H, V_B) [N] to start the first free-span solve from.
    maxiter : int
        Cap of the Newton iterations on the split.

    Returns
    -------
    CableState
        The free span's ``Span`` and its unstrained length L0_free [m]; an inextensible cable whose
        dead part leaves no free length, or too short for its chord, is ``infeasible``.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    l_h, l_v, L0, l_dead, w, EA = (np.array(x) for x in _arrays(l_h, l_v, L0, l_dead, w, EA))
    shape = l_h.shape
    l_h, l_v, L0, l_dead, w, EA = (x.ravel() for x in (l_h, l_v, L0, l_dead, w, EA))
    c = np.hypot(l_h, l_v)
    with np.errstate(invalid="ignore", divide="ignore"):
        T0 = np.where(c + l_dead > L0, EA * ((c + l_dead) / L0 - 1.0), 0.0)
        T0 = np.where(np.isfinite(T0), T0, 0.0)
        L0f = L0 - l_dead * _ratio(EA, T0)
    bad = ~(L0f > 0.0)
    L0f = np.where(bad, L0, L0f)  # placeholder; flagged infeasible below
    if start is None:
        H0, V0 = np.full(l_h.size, np.nan), np.full(l_h.size, np.nan)
    else:
        H0, V0 = (np.broadcast_to(np.asarray(x, dtype=float), shape).ravel().copy() for x in start)
    fixed = (l_dead == 0.0) | np.isinf(EA)  # the split does not depend on the tension
    it = np.zeros(l_h.size, dtype=np.int64)
    for k in range(maxiter):
        s = span_state(l_h, l_v, L0f, w, EA, start=(H0, V0))
        H0, V0 = s.H, s.V_B
        phi = L0f + l_dead * _ratio(EA, s.T_D) - L0
        dT = _dTD_dL0(s, L0f, w, EA)
        with np.errstate(invalid="ignore", divide="ignore"):
            slope = 1.0 - l_dead * EA / (EA + s.T_D) ** 2 * dT
        slope = np.where(fixed | ~np.isfinite(slope), 1.0, slope)
        step = np.where(bad | (s.status_code == INFEASIBLE), 0.0, -phi / slope)
        new = L0f + step
        new = np.where(new > 0.0, new, 0.5 * L0f)
        it += 1
        done = np.abs(new - L0f) <= 4e-16 * L0
        L0f = new
        if done.all():
            break
    s = span_state(l_h, l_v, L0f, w, EA, start=(H0, V0))
    code = np.where(bad, INFEASIBLE, s.status_code).astype(np.int8)
    nan = np.where(bad, np.nan, 1.0)
    span = Span(
        *(np.reshape(x * nan, shape) for x in (s.H, s.V_B, s.V_D, s.T_B, s.T_D)),
        code.reshape(shape),
        np.asarray(SPAN_STATUSES)[code].reshape(shape),
        it.reshape(shape),
        (s.converged & ~bad & done).reshape(shape),
    )
    return CableState(span, np.where(bad, np.nan, L0f).reshape(shape))


def _ratio(EA, T):
    """1 / (1 + T/EA) = EA / (EA + T), 1 for EA = inf."""
    with np.errstate(invalid="ignore"):
        return np.where(np.isinf(EA), 1.0, EA / (EA + T))


def _span_L0_derivative(H, V_D, T_D, EA):
    """d(l_h, l_v)/dL0 of a span at fixed end forces: the stretched tangent at D, (1/EA + 1/T_D)(H, V_D)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(T_D > 0.0, 1.0 / EA + 1.0 / T_D, 0.0)
    return k * H, k * V_D


def _dTD_dL0(s, L0f, w, EA):
    """dT_D/dL0 of a span at fixed spans (the cable lengthened at D): (H dH + V_D (dV + w))/T_D with
    (dH, dV) = -K (d(l_h, l_v)/dL0)."""
    K = stiffness(s.H, s.V_B, L0f, w, EA)
    gh, gv = _span_L0_derivative(s.H, s.V_D, s.T_D, EA)
    dH = -(K[..., 0, 0] * gh + K[..., 0, 1] * gv)
    dV = -(K[..., 1, 0] * gh + K[..., 1, 1] * gv)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(s.T_D > 0.0, (s.H * dH + s.V_D * (dV + w)) / s.T_D, 0.0)


def cable_stiffness(state, l_dead, w, EA):
    """Stiffness of a whole cable (``cable_state``), d(H, V_B)/d(l_h, l_v) with the split between
    the free span and the dead part following the tension at D (implicit differentiation of the
    split equation of ``cable_state``; Irvine 1981, ch. 2, for the span).

    .. math:: K_{eff} = K - K g \\, \\frac{dL_{0,free}}{d l}, \\quad
        g = \\left(\\frac{1}{EA} + \\frac{1}{T_D}\\right)(H, V_D)

    Parameters
    ----------
    state : CableState
        The solved cables.
    l_dead : array_like (...) [m]
        Stretched length of the dead part.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).

    Returns
    -------
    K : ndarray (..., 2, 2) [N/m]
        d(H, V_B)/d(l_h, l_v).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    s, L0f = state.span, state.L0_free
    l_dead, w, EA = (np.broadcast_to(np.asarray(x, dtype=float), L0f.shape) for x in (l_dead, w, EA))
    K = stiffness(s.H, s.V_B, L0f, w, EA)
    gh, gv = _span_L0_derivative(s.H, s.V_D, s.T_D, EA)
    Kg = np.stack([K[..., 0, 0] * gh + K[..., 0, 1] * gv, K[..., 1, 0] * gh + K[..., 1, 1] * gv], axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(s.T_D > 0.0, 1.0 / s.T_D, 0.0)
        cpr = np.where(np.isinf(EA), 0.0, l_dead * EA / (EA + s.T_D) ** 2)
    # T_D at fixed split: dT_D/dl = (H K[0, :] + V_D K[1, :]) / T_D; along the split: _dTD_dL0
    dT_dl = (s.H[..., None] * K[..., 0, :] + s.V_D[..., None] * K[..., 1, :]) * inv[..., None]
    dT_dL = (s.H * -Kg[..., 0] + s.V_D * (-Kg[..., 1] + w)) * inv
    dL_dl = cpr[..., None] * dT_dl / (1.0 - cpr * dT_dL)[..., None]
    return K - Kg[..., :, None] * dL_dl[..., None, :]


def cable_energy(state, l_h, l_v, l_dead, w, EA):
    """Potential energy of a whole cable (``cable_state``) up to a constant: the free span's
    -min Phi (``complementary_energy``: strain and weight, by Legendre duality) plus the dead part's
    strain energy l0_dead T_D^2/(2 EA); its gradient with respect to the attachment B is minus the
    cable's force on the platform, so the equilibrium minimises it plus the platform's weight.

    .. math:: U = H l_h + V_B l_v - \\int_0^{L_{0,free}}\\left(T + \\frac{T^2}{2EA}\\right) ds
        + \\frac{l_{dead}}{1 + T_D/EA}\\,\\frac{T_D^2}{2 EA}

    Parameters
    ----------
    state : CableState
        The solved cables.
    l_h : array_like (...) [m]
        Horizontal span.
    l_v : array_like (...) [m]
        Vertical span.
    l_dead : array_like (...) [m]
        Stretched length of the dead part.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).

    Returns
    -------
    U : ndarray (...) [J]
        The energy (w = 0: EA (chord + l_dead - L0)^2 / (2 L0), Hooke's).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    s = state.span
    phi = complementary_energy(s.H, s.V_B, state.L0_free, w, EA, l_h, l_v)
    with np.errstate(invalid="ignore"):
        dead = np.where(np.isinf(EA), 0.0, l_dead * _ratio(EA, s.T_D) * s.T_D**2 / (2.0 * EA))
    return dead - phi
