"""Exact partial derivatives of one elastic catenary (``catenary``): the spans at fixed end forces
with respect to every argument, and the end forces at fixed spans by the implicit-function theorem
on the two span equations (Irvine 1981, ch. 2). The analytic twins of what the heavy-cable
sensitivities used to difference (``heavy_partials``).

With the span equations (l_h, l_v) = s(H, V_B, L0, w, EA) (``catenary.span_equations``)::

    ds = F d(H, V_B) + g dL0 + s_w dw + s_EA dEA,
    F = flexibility,  g = (1/EA + 1/T_D)(H, V_D),
    s_w = (-∫ H V s/T^3 ds,  L0^2/(2 EA) + ∫ s H^2/T^3 ds),   s_EA = -(H L0, L0 (V_B + V_D)/2)/EA^2,

and at fixed spans d(H, V_B) = K (d(l_h, l_v) - g dL0 - s_w dw - s_EA dEA), K = F^-1 (``stiffness``).
The two integrals of s_w have closed forms (``_span_w_derivative``) written, like the span equations,
free of cancellation as w -> 0 (the horizontal one by Gauss-Legendre quadrature of its smooth
integrand where w L0 <= ``QUAD_MAX`` H, where the closed form would cancel).

References
----------
Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2 (the elastic catenary, its span equations
and flexibility).
"""

from __future__ import annotations

import numpy as np

from cdpr.models.catenary import flexibility, span_equations

#: Where w L0 <= QUAD_MAX H the horizontal span's w-derivative is integrated by Gauss-Legendre
#: (its integrand's singularities are then >= 1/QUAD_MAX span lengths off the interval).
QUAD_MAX = 0.1
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(10)


def _broadcast(*xs):
    return np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in xs))


def _span_w_derivative(H, V_B, L0, w, EA):
    """d(l_h, l_v)/dw at fixed (H, V_B, L0, EA), cancellation-free (module docstring)::

    dl_h/dw = -(l_h,cat - H L0/T_D)/w = -∫_0^L0 H V(s) s / T(s)^3 ds,
    dl_v/dw = L0^2/(2 EA) + H^2 L0^2 / (T_D (T_B T_D + H^2 + V_B V_D))

    (l_h,cat = (H/w)(asinh(V_D/H) - asinh(V_B/H)), the inextensible part of l_h; the second from
    T_B T_D - H^2 - V_B V_D = H^2 w^2 L0^2 / (T_B T_D + H^2 + V_B V_D))."""
    V_D = V_B + w * L0
    T_B, T_D = np.hypot(H, V_B), np.hypot(H, V_D)
    l_cat = span_equations(H, V_B, L0, w, np.inf)[0]  # the catenary's part of l_h, H L0 Qh
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        den = T_D * (T_B * T_D + H * H + V_B * V_D)
        dlv = L0 * L0 / (2.0 * EA) + np.where(den > 0.0, H * H * L0 * L0 / den, 0.0)
        closed = -(l_cat - H * L0 / T_D) / w
        s = 0.5 * L0[..., None] * (1.0 + _NODES)
        V = V_B[..., None] + w[..., None] * s
        T = np.hypot(H[..., None], V)
        quad = -0.5 * L0 * np.sum(_WEIGHTS * H[..., None] * V * s / T**3, axis=-1)
        dlh = np.where(w * L0 <= QUAD_MAX * np.abs(H), quad, closed)
    return np.where(np.isfinite(dlh), dlh, 0.0), dlv


def span_partials(H, V_B, L0, w, EA):
    """Partial derivatives of the spans (l_h, l_v) of an elastic catenary (``catenary.span_equations``)
    with respect to (H, V_B, L0, w, EA) at fixed other arguments (Irvine 1981, ch. 2).

    .. math::

        \\frac{\\partial(l_h, l_v)}{\\partial(H, V_B)} = F, \\quad
        \\frac{\\partial(l_h, l_v)}{\\partial L_0} = \\left(\\frac{1}{EA} + \\frac{1}{T_D}\\right)(H, V_D),
        \\quad \\frac{\\partial(l_h, l_v)}{\\partial EA} = -\\frac{L_0}{EA^2}\\left(H, \\frac{V_B + V_D}{2}\\right),

        \\frac{\\partial l_h}{\\partial w} = -\\int_0^{L_0} \\frac{H V s}{T^3} ds, \\quad
        \\frac{\\partial l_v}{\\partial w} = \\frac{L_0^2}{2 EA} + \\int_0^{L_0} \\frac{H^2 s}{T^3} ds

    with F the ``catenary.flexibility``, V(s) = V_B + w s, T(s) = sqrt(H^2 + V(s)^2), in forms free of
    cancellation (w = 0: the straight Hooke spring's derivatives; module docstring).

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
        Axial stiffness (inf: inextensible, its column 0).

    Returns
    -------
    P : ndarray (..., 2, 5) [m/N, m/N, m/m, m/(N/m), m/N]
        Rows l_h, l_v; columns H, V_B, L0, w, EA.

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA = (np.array(x) for x in _broadcast(H, V_B, L0, w, EA))
    F = flexibility(H, V_B, L0, w, EA)
    V_D = V_B + w * L0
    T_D = np.hypot(H, V_D)
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(T_D > 0.0, 1.0 / EA + 1.0 / T_D, 0.0)
        ea = np.where(np.isinf(EA), 0.0, -L0 / (EA * EA))
    dlh_w, dlv_w = _span_w_derivative(H, V_B, L0, w, EA)
    out = np.empty(H.shape + (2, 5))
    out[..., :, :2] = F
    out[..., 0, 2], out[..., 1, 2] = k * H, k * V_D
    out[..., 0, 3], out[..., 1, 3] = dlh_w, dlv_w
    out[..., 0, 4], out[..., 1, 4] = ea * H, ea * 0.5 * (V_B + V_D)
    return out


def end_force_partials(H, V_B, L0, w, EA):
    """Derivatives of the end forces (H, V_B) of an elastic catenary (``catenary.end_forces``) with
    respect to (l_h, l_v, L0, w, EA): the implicit-function theorem on the two span equations with
    the analytic flexibility matrix F (Irvine 1981, ch. 2).

    .. math::

        \\frac{d(H, V_B)}{d(l_h, l_v, L_0, w, EA)} = F^{-1}\\left[\\, I_2 \\;\\middle|\\;
            -\\frac{\\partial(l_h, l_v)}{\\partial(L_0, w, EA)} \\right]

    (``span_partials``), at the solved end forces.

    Parameters
    ----------
    H : array_like (...) [N]
        Horizontal end force at the solution.
    V_B : array_like (...) [N]
        Vertical end force at B at the solution.
    L0 : array_like (...) [m]
        Unstrained length of the span.
    w : array_like (...) [N/m]
        Weight per unstrained metre.
    EA : array_like (...) [N]
        Axial stiffness (inf allowed).

    Returns
    -------
    D : ndarray (..., 2, 5) [N/m, N/m, N/m, N/(N/m), N/N]
        Rows H, V_B; columns l_h, l_v, L0, w, EA. Zero for a slack weightless span (no force).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.
    """
    H, V_B, L0, w, EA = (np.array(x) for x in _broadcast(H, V_B, L0, w, EA))
    P = span_partials(H, V_B, L0, w, EA)
    rhs = np.concatenate([np.broadcast_to(np.eye(2), H.shape + (2, 2)), -P[..., 2:]], axis=-1)
    slack = (w == 0.0) & (H == 0.0) & (V_B == 0.0)
    F = np.where(slack[..., None, None], np.eye(2), P[..., :2])
    out = np.linalg.solve(F, rhs)
    return np.where(slack[..., None, None], 0.0, out)
