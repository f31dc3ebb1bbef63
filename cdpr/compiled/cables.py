"""Compiled twin of ``cdpr.models.cables``' heavy cables (issue 38): ``HeavyCables.exit_points``
(one cable: the sheave exit point D_i and the elastic catenary from B_i to D_i solved together),
``HeavyCables.evaluate`` (a pose: force and moment balance, energy, Jacobian, written in the
compiled pose kernel's layout, ``equilibrium.evaluate``) and ``heavy_cables`` (the per-cable
outputs at the equilibria), as numba kernels run inside ``cdpr.compiled.equilibrium``'s Newton;
and ``HeavyCables.inverse`` (``inverse``, with ``span_for_tension``: the catenaries that carry given
tensions at B_i, the inner step of ``analyses.compensation.heavy_distribution``), which follows the
reference's algorithm step by step, in parallel over poses.

Same equations, pulley coupling, energy and Jacobian as the numpy reference (whose docstrings give
them), cable by cable: the fixed point on the exit point, the Newton iteration on the split of the
unstrained length between the free span and the dead part (``catenary.cable_state``) and the
span's Newton iteration (``catenary.span_state``). What differs is where they start: the reference
starts every evaluation from the massless exit point and Hooke's law, the kernel from the state of
the last accepted evaluation of the same pose (the tangent angle of D on the sheave, the end forces
and the split; ``STATE``), so that the Newton iterations of the equilibrium, whose poses move
little, cost one or two catenary steps per cable. Every one of these sub-problems has one
solution, reached from any start, so the two engines agree to round-off (tests/compiled).

References
----------
Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2.

Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 3-5, 10-14).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from cdpr.compiled._kernels import SWIVEL_RHO_MIN, TWO_PI, entry_angle, mod_two_pi, set_threads, sheave
from cdpr.compiled._linalg import add_cable_jacobian, add_gravity
from cdpr.compiled.catenary import (
    angle_f_deg,
    arc_length,
    cable_energy_stiffness,
    cable_state,
    sag,
    spans_and_flexibility,
    terms_fast,
)
from cdpr.compiled.heavy_partials import exact_force_gradient
from cdpr.models.catenary import CATENARY, INFEASIBLE, SPAN_STATUSES, U_SHAPED

__all__ = [
    "NSTATE",
    "STATE",
    "INVERSE",
    "Heavy",
    "evaluate",
    "exit_points",
    "heavy_arrays",
    "heavy_cables",
    "inverse",
    "span_for_tension",
]

#: Columns of one cable's state (``exit_points``): what the next evaluation starts from and what the
#: outputs read. H, V_B [N]; L0f [m] the free span's unstrained length; theta [rad] the angle of D on
#: the sheave (in the sheave plane, from e_s toward k); ready (1: a start is there); T_B, T_D [N];
#: l_h, l_v [m]; Dx, Dy, Dz [m]; gamma [rad] the wrap to D; code (``catenary.SPAN_STATUSES``);
#: l_dead [m]; iterations of the exit point's fixed point.
STATE = {
    k: i
    for i, k in enumerate(
        (
            "H",
            "V_B",
            "L0f",
            "theta",
            "ready",
            "T_B",
            "T_D",
            "l_h",
            "l_v",
            "Dx",
            "Dy",
            "Dz",
            "gamma",
            "code",
            "l_dead",
            "it",
        )
    )
}
NSTATE = len(STATE)
_H, _V, _L0F, _TH, _READY, _TB, _TD, _LH, _LV, _DX, _DY, _DZ, _GAM, _CODE, _ELL, _IT = range(NSTATE)
#: Cap of the exit point's fixed point (``HeavyCables.exit_points``' maxiter).
EXIT_MAXITER = 60


class Heavy(NamedTuple):
    """What the pose kernel needs of heavy cables (``heavy_arrays``): on (the robot's cables are
    heavy: ``HeavyCables.evaluate``, else the massless ``Cables.evaluate``); w (m,) [N/m] the weight
    per unstrained metre; up (3,) [-] the unit vector against gravity; axis (m, 3) [-] the swivel
    axes k_i (base frame); general (m,) bool: the cable's sheave plane follows the catenary's end
    tangent (a DR pulley, an SR swivel axis off gravity: ``_general_at``), else it is the plane
    through B (fixed pulleys, SR pulleys with axes along gravity: ``_joint``); thK (m,) [rad] the
    angle on the sheave of the entry point K (toward the winch) of the cables that are not general,
    which the sheave's fixed centre makes constant (``entry_angle``; 0 without a sheave, NaN for
    general cables, whose K moves)."""

    on: bool
    w: np.ndarray
    up: np.ndarray
    axis: np.ndarray
    general: np.ndarray
    thK: np.ndarray


def heavy_arrays(cab=None, m=0):
    """The ``Heavy`` record of a ``models.cables.HeavyCables`` ``cab``, or of a massless robot of m
    cables when ``cab`` is None (``on`` False).

    Parameters
    ----------
    cab : HeavyCables, optional
    m : int
        Number of cables (massless record).

    Returns
    -------
    Heavy
    """
    f = np.ascontiguousarray
    if cab is None:
        z = np.zeros(m)
        return Heavy(False, z, f([0.0, 0.0, 1.0]), np.zeros((m, 3)), np.zeros(m, dtype=np.bool_), z)
    a = cab.robot.arrays
    kind, r_p = a.kind, a.r_p
    general = (r_p > 0.0) & ((kind == 2) | ((kind == 1) & (np.abs(cab.axis @ cab.up) < 1.0 - 1e-12)))
    thK = np.array(
        [entry_angle(int(k), float(hh), float(r), float(dd)) for k, hh, r, dd in zip(kind, a.h, r_p, a.d)]
    )
    return Heavy(
        True,
        f(cab.w, dtype=float),
        f(cab.up, dtype=float),
        f(cab.axis, dtype=float),
        f(general, dtype=np.bool_),
        f(np.where(general, np.nan, thK)),
    )


#: Cap of the joint Newton iteration of one cable (``_joint``); past it, the nested iterations.
JOINT_MAXITER = 12
#: The joint iteration stops after the step taken from residuals below this fraction of the
#: lengths (the span iteration's ``rtol``: the step's own error is of its square).
JOINT_RTOL = 1e-13
#: ... or after a whole step of at most this fraction of the forces and lengths (Newton's error after
#: it is of its square, relative, below the round-off of the spans' residuals).
JOINT_STEP = 1e-8
#: Damped steps (a force or length kept positive) after which the joint iteration gives up.
JOINT_DAMPED = 1


@njit(cache=True, inline="always", error_model="numpy")
def _spans_at(Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ct, st):
    """The exit point D = H + r_p (cos theta e_s + sin theta k) on the sheave (centre H, plane
    (e_s, k)) and the spans from B: (r (3) [-] the sheave's radius direction at D, D (3) [m],
    v = D - B (3) [m], l_v, l_h [m], e_h (3) [-] the horizontal unit vector from B toward D; e_h is
    the horizontal part of v unscaled where l_h = 0, a vertical cable)."""
    rx, ry, rz = ct * esx + st * kx, ct * esy + st * ky, ct * esz + st * kz
    Dx, Dy, Dz = Hx + rp * rx, Hy + rp * ry, Hz + rp * rz
    vx, vy, vz, l_v, l_h, ehx, ehy, ehz = _span(Dx, Dy, Dz, Bx, By, Bz, ux, uy, uz)
    return rx, ry, rz, Dx, Dy, Dz, vx, vy, vz, l_v, l_h, ehx, ehy, ehz


@njit(cache=True, inline="always", error_model="numpy")
def _span(Dx, Dy, Dz, Bx, By, Bz, ux, uy, uz):
    """The span from B to D along the unit up (u_x, u_y, u_z): v = D - B (3) [m], l_v = v . up,
    l_h = |v - l_v up| [m] and e_h (3) [-] the horizontal unit vector from B toward D (the
    horizontal part of v unscaled where l_h = 0, a vertical cable)."""
    vx, vy, vz = Dx - Bx, Dy - By, Dz - Bz
    l_v = vx * ux + vy * uy + vz * uz
    hx, hy, hz = vx - l_v * ux, vy - l_v * uy, vz - l_v * uz
    l_h = math.sqrt(hx * hx + hy * hy + hz * hz)
    n = l_h if l_h > 0.0 else 1.0
    return vx, vy, vz, l_v, l_h, hx / n, hy / n, hz / n


@njit(cache=True, error_model="numpy")
def _joint(
    Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ld, thK, sr, L0c, w, EA, H, V, L0f, th
):
    """One heavy cable at its attachment point B by one Newton iteration on all its unknowns at
    once, (H, V_B [N], L0f [m], theta [rad]) (theta fixed where ``sr`` is False), from a start near
    the answer (the cable's state at a nearby pose): the span equations (``catenary.span_equations``
    = the spans from B to D(theta)), the split L0f + l_dead(theta) / (1 + T_D/EA) = L0c and, on an
    SR pulley, the tangency of the catenary's end direction to the sheave at D(theta),
    (H e_h + V_D up) . r(theta) = 0 with r the sheave's radius direction. The answer is the one of
    the nested iterations of ``exit_points`` (each equation is theirs; the tangency root is
    checked to be the fixed point's, not the opposite tangent point). Each step eliminates (dH, dV)
    by the 2 x 2 flexibility and solves the 2 x 2 left in (dL0f, dtheta) in closed form.

    Returns
    -------
    tuple
        (ok, H, V_B, L0f, theta, iterations, cos theta, sin theta, gamma); ok False (no convergence in ``JOINT_MAXITER``, a
        non-positive force or length, a vertical span, the other tangent point): use the nested
        iterations.
    """
    iEA = 1.0 / EA
    c_scale = L0c
    damped = 0
    ct, st = math.cos(th), math.sin(th)
    gam = mod_two_pi(thK - th)
    for it in range(1, JOINT_MAXITER + 1):
        rx, ry, rz, _, _, _, _, _, _, l_v, l_h, ehx, ehy, ehz = _spans_at(
            Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ct, st
        )
        if not (l_h > 0.0 and H > 0.0 and L0f > 0.0):
            return False, H, V, L0f, th, it, ct, st, gam
        ell = ld + rp * gam
        V_D, _, T_D, S, Qh, Qv, Qd, Qx, _ = terms_fast(H, V, L0f, w)
        e = L0f * iEA
        E1 = H * L0f * (iEA + Qh) - l_h
        E2 = L0f * (0.5 * S * iEA + Qv) - l_v
        f11, f12, f22 = e + L0f * (Qh - Qd), L0f * Qx, e + L0f * Qd
        det = f11 * f22 - f12 * f12
        kk = iEA + 1.0 / T_D
        gh, gv = kk * H, kk * V_D
        if math.isinf(EA):
            rho, drho = 1.0, 0.0
        else:
            rho = EA / (EA + T_D)
            drho = -rho / (EA + T_D)
        E3 = L0f + ell * rho - L0c
        q = ell * drho / T_D
        c3H, c3V, c3L = q * H, q * V_D, 1.0 + q * w * V_D
        # (dH, dV) = p0 + pL dL0f + pt dtheta from the span equations
        p0H, p0V = -(f22 * E1 - f12 * E2) / det, -(f11 * E2 - f12 * E1) / det
        pLH, pLV = -(f22 * gh - f12 * gv) / det, -(f11 * gv - f12 * gh) / det
        A11 = c3H * pLH + c3V * pLV + c3L
        b1 = -E3 - c3H * p0H - c3V * p0V
        small = (
            math.sqrt(E1 * E1 + E2 * E2) <= JOINT_RTOL * (L0f + l_h + abs(l_v))
            and abs(E3) <= JOINT_RTOL * c_scale
        )
        if sr:
            dx, dy, dz = -st * esx + ct * kx, -st * esy + ct * ky, -st * esz + ct * kz  # dr/dtheta
            dlv = rp * (dx * ux + dy * uy + dz * uz)
            dlh = rp * (dx * ehx + dy * ehy + dz * ehz)
            ptH, ptV = (f22 * dlh - f12 * dlv) / det, (f11 * dlv - f12 * dlh) / det
            ehr = ehx * rx + ehy * ry + ehz * rz
            ur = ux * rx + uy * ry + uz * rz
            E4 = H * ehr + V_D * ur
            # d(e_h . r)/dtheta = (de_h/dtheta) . r + e_h . dr/dtheta
            drr = rp * (dx * rx + dy * ry + dz * rz)
            dehr = (drr - dlv * ur - dlh * ehr) / l_h + ehx * dx + ehy * dy + ehz * dz
            c4H, c4V, c4L, c4t = ehr, ur, w * ur, H * dehr + V_D * (ux * dx + uy * dy + uz * dz)
            A12 = c3H * ptH + c3V * ptV - rp * rho
            A21 = c4H * pLH + c4V * pLV + c4L
            A22 = c4H * ptH + c4V * ptV + c4t
            b2 = -E4 - c4H * p0H - c4V * p0V
            dd = A11 * A22 - A12 * A21
            dL = (b1 * A22 - A12 * b2) / dd
            dt = (A11 * b2 - A21 * b1) / dd
            small = small and abs(E4) <= JOINT_RTOL * T_D
        else:
            dL = b1 / A11
            dt = ptH = ptV = 0.0
        dH = p0H + pLH * dL + ptH * dt
        dV = p0V + pLV * dL + ptV * dt
        if not (math.isfinite(dH) and math.isfinite(dV) and math.isfinite(dL) and math.isfinite(dt)):
            return False, H, V, L0f, th, it, ct, st, gam
        alpha = 1.0
        if H + dH <= 0.0:
            alpha = 0.5 * H / -dH
        if L0f + alpha * dL <= 0.0:
            alpha = 0.5 * L0f / -dL
        if alpha * abs(dt) > 0.5:
            alpha = 0.5 / abs(dt)
        if alpha < 1.0:
            damped += 1
            if damped > JOINT_DAMPED:  # far from the answer: the nested iterations' line searches
                return False, H, V, L0f, th, it, ct, st, gam
        H += alpha * dH
        V += alpha * dV
        L0f += alpha * dL
        da = alpha * dt
        th += da
        gam -= da
        if not 0.0 <= gam < TWO_PI:
            gam = mod_two_pi(thK - th)
        if abs(da) < 1e-3:  # cos and sin of theta turned by da (Taylor's series: to round-off)
            a2 = da * da
            cd = 1.0 - a2 * (0.5 - a2 * (1.0 / 24.0 - a2 / 720.0))
            sd = da * (1.0 - a2 * (1.0 / 6.0 - a2 * (1.0 / 120.0 - a2 / 5040.0)))
            ct, st = ct * cd - st * sd, st * cd + ct * sd
        else:
            ct, st = math.cos(th), math.sin(th)
        step = max(abs(dH) + abs(dV), T_D * (abs(dL) + rp * abs(dt)) / c_scale)
        if alpha == 1.0 and (small or step <= JOINT_STEP * T_D):
            if sr:  # the fixed point's root: the end direction toward the sheave gives back theta
                V_D = V + w * L0f
                n_s = H * (ehx * kx + ehy * ky + ehz * kz) + V_D * (ux * kx + uy * ky + uz * kz)
                n_w = -(H * (ehx * esx + ehy * esy + ehz * esz) + V_D * (ux * esx + uy * esy + uz * esz))
                if n_s * ct + n_w * st <= 0.0:
                    return False, H, V, L0f, th, it, ct, st, gam
            return True, H, V, L0f, th, it, ct, st, gam
    return False, H, V, L0f, th, JOINT_MAXITER, ct, st, gam


@njit(cache=True, error_model="numpy")
def _cold_start(
    Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ld, thK, sr, L0c, w, EA, th
):
    """A start of ``_joint`` with D at theta (the massless exit point): the split of Hooke's law on
    the whole length (``catenary.cable_state``'s) and the span's start (``catenary._start``'s
    first guess);
    (H, V_B [N], L0f [m]), H NaN where there is none (a vertical span, an infeasible one)."""
    ct, st = math.cos(th), math.sin(th)
    _, _, _, _, _, _, _, _, _, l_v, l_h, _, _, _ = _spans_at(
        Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ct, st
    )
    ell = ld + rp * mod_two_pi(thK - th)
    c = math.hypot(l_h, l_v)
    T0 = EA * ((c + ell) / L0c - 1.0) if c + ell > L0c else 0.0
    if not math.isfinite(T0):
        T0 = 0.0
    L0f = L0c - ell * (1.0 if math.isinf(EA) else EA / (EA + T0))
    if not (l_h > 0.0 and L0f > 0.0) or (math.isinf(EA) and c >= L0f):
        return np.nan, np.nan, np.nan
    # catenary._start without its refinement of lambda (a start only: the joint iteration solves)
    Le = max(L0f, 1.001 * c)
    rho = math.sqrt(Le * Le - l_v * l_v) / l_h
    lam = (
        math.sqrt(6.0 * (rho - 1.0))
        if rho < 3.0
        else math.log(2.0 * rho) + math.log(math.log(2.0 * rho) + 1.0)
    )
    H_cat = w * l_h / (2.0 * lam)
    T = EA * (c / L0f - 1.0) if c > L0f else 0.0
    if not math.isfinite(T):
        T = 0.0
    H_h = T * l_h / c
    if H_h > H_cat:
        return H_h, T * l_v / c - 0.5 * w * L0f, L0f
    return H_cat, 0.5 * w * (l_v / math.tanh(lam) - Le), L0f


@njit(cache=True, inline="always", error_model="numpy")
def _joint_or_cold(
    Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ld, thK, sr, L0c, w, EA, warm, H0, V0, L0f, th,
    tc, sD, cD,
):  # fmt: skip
    """``_joint`` from the start (H0, V0 [N], L0f [m], theta th [rad]) where ``warm``, else, or where
    it fails, from ``_cold_start`` at the angle tc [rad] (NaN: atan2(sD, cD), the massless exit
    point's angle, computed only where the cold start is needed): ``_joint``'s tuple (ok False, NaN
    forces, where neither converges)."""
    args = (Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ld, thK, sr, L0c, w, EA)
    ok, H, V, L, t, it, ct, st, gam = False, np.nan, np.nan, np.nan, np.nan, 0, 1.0, 0.0, 0.0
    if warm:
        ok, H, V, L, t, it, ct, st, gam = _joint(*args, H0, V0, L0f, th)
    if not ok:
        if tc != tc:
            tc = math.atan2(sD, cD)
        Hc, Vc, Lc = _cold_start(*args, tc)
        if Hc > 0.0:
            ok, H, V, L, t, it, ct, st, gam = _joint(*args, Hc, Vc, Lc, tc)
    return ok, H, V, L, t, it, ct, st, gam


@njit(cache=True, error_model="numpy")
def _result(
    H, V, L0f, th, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it, ehx, ehy, ehz, Ds, rho, esx, esy, esz, kx, ky, kz, Ax,
    Ay, Az, ux, uy, uz, w, inside, gam0,
):  # fmt: skip
    """``_cable_at``'s tuple from one cable's solution: T_B, T_D [N], the swivel term D_s / rho (D_s
    [m] D's in-plane s, rho [m] B's distance to the axis; 0 on the axis), e_perp = k x e_s and
    (D - A) . up [m] added."""
    T_B = math.sqrt(H * H + V * V)
    V_D = V + w * L0f
    T_D = math.sqrt(H * H + V_D * V_D)
    swivel = Ds / rho if rho > SWIVEL_RHO_MIN else 0.0
    epx, epy, epz = ky * esz - kz * esy, kz * esx - kx * esz, kx * esy - ky * esx
    zD = (Dx - Ax) * ux + (Dy - Ay) * uy + (Dz - Az) * uz
    return (
        H, V, L0f, th, T_B, T_D, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it, ehx, ehy, ehz, swivel, epx, epy, epz,
        zD, inside, gam0,
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def _general_at(
    Bx, By, Bz, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12, F20, F21, F22, kind, h, rp, d, inx, iny, EA, w,
    ux, uy, uz, kx, ky, kz, L0c, ready, H0, V0, L0f, th0, D0x, D0y, D0z, gB,
):  # fmt: skip
    """``_cable_at`` for any pulley (a DR pulley, an SR swivel axis off gravity): the numpy
    reference's coupling (``models.cables.HeavyCables._couple``), the fixed point on the virtual
    point P* = D + |B - D| u (u the catenary's unit end tangent at D toward the platform), D the
    tangent point of the massless pulley model at P* (so the sheave plane contains the swivel axis
    and u, and a DR arm bisects the strand to the winch and the direction of P*), the catenary from
    B to D. Each pass holds the sheave (plane, centre, entry point K) of the last P* and solves D's
    angle on it with the catenary at once (``_joint``: its tangency (H e_h + V_D up) . r = 0 in that
    plane), warm-started from the last pass, else D the tangent point from P* and the nested
    ``catenary.cable_state``; at the fixed point both are the reference's D. Its contraction is of
    the order r_p / |B - D|. It starts from P* = B (ready 0: the reference's start) or from the stored
    state's D0 and end forces (the P* they give at this B). Stops when P* moves by at most 1e-15
    (1 + max |v|) (the reference's rule) or, within 1e-12 (1 + max |v|), stops shrinking (round-off),
    then solves the cable once more at the last P*. ``gB`` the massless geometry at B (its inside,
    gamma and distance to the axis); th0 [rad] D's angle on the sheave in the stored state. Returns
    ``_cable_at``'s tuple (theta: D's angle on the sheave)."""
    Px, Py, Pz = Bx, By, Bz
    L0f0 = L0f
    if ready > 0.0:
        vx, vy, vz = D0x - Bx, D0y - By, D0z - Bz
        l_v = vx * ux + vy * uy + vz * uz
        hx, hy, hz = vx - l_v * ux, vy - l_v * uy, vz - l_v * uz
        l_h = math.sqrt(hx * hx + hy * hy + hz * hz)
        V_D = V0 + w * L0f
        T_D = math.sqrt(H0 * H0 + V_D * V_D)
        if l_h > 0.0 and T_D > 0.0 and math.isfinite(T_D):
            n = math.sqrt(vx * vx + vy * vy + vz * vz) / T_D
            Px = D0x - n * (H0 * hx / l_h + V_D * ux)
            Py = D0y - n * (H0 * hy / l_h + V_D * uy)
            Pz = D0z - n * (H0 * hz / l_h + V_D * uz)
    else:
        H0 = V0 = L0f0 = np.nan
    moved_prev = np.inf
    last = False
    H = V = L0f = np.nan
    code = INFEASIBLE
    it = 0
    th = th0 if ready > 0.0 else np.nan
    for it in range(1, EXIT_MAXITER + 2):
        g, esx, esy, esz = sheave(
            Px, Py, Pz, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12, F20, F21, F22, kind, h, rp, d, inx, iny
        )  # fmt: skip
        joint = False
        if w > 0.0:  # in this pass's sheave plane, D's angle with the catenary at once (``_joint``)
            Hx, Hy, Hz = Ax + g.Hs * esx + g.Hw * kx, Ay + g.Hs * esy + g.Hw * ky, Az + g.Hs * esz + g.Hw * kz
            thK = math.atan2(g.sK, g.cK)
            tj = th if th == th else math.atan2(g.sD, g.cD)
            warm = H0 > 0.0 and L0f0 > 0.0 and math.isfinite(V0)
            joint, Hj, Vj, Lj, tj2, _, ct, st, gam = _joint_or_cold(
                Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, g.ld, thK, True, L0c, w, EA, warm,
                H0, V0, L0f0, tj, tj, g.sD, g.cD,
            )  # fmt: skip
        if joint:
            H, V, L0f, th, gamma = Hj, Vj, Lj, tj2, gam
            _, _, _, Dx, Dy, Dz, vx, vy, vz, l_v, l_h, ehx, ehy, ehz = _spans_at(
                Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ct, st
            )
            code = U_SHAPED if (V < 0.0 and V + w * L0f > 0.0) else CATENARY
        else:  # D the tangent point from P* and the whole cable by the nested iterations
            th, gamma = math.atan2(g.sD, g.cD), g.gamma
            Dw = g.Hw + rp * g.sD
            Dx, Dy, Dz = Ax + g.Ds * esx + Dw * kx, Ay + g.Ds * esy + Dw * ky, Az + g.Ds * esz + Dw * kz
            vx, vy, vz, l_v, l_h, ehx, ehy, ehz = _span(Dx, Dy, Dz, Bx, By, Bz, ux, uy, uz)
            H, V, code, _, _, L0f = cable_state(l_h, l_v, L0c, g.ld + rp * gamma, w, EA, H0, V0, L0f0)
        ell = g.ld + rp * gamma
        H0, V0, L0f0 = H, V, L0f
        if last or rp == 0.0 or it > EXIT_MAXITER:
            break
        V_D = V + w * L0f
        T_D = math.sqrt(H * H + V_D * V_D)
        n = math.sqrt(vx * vx + vy * vy + vz * vz) / T_D
        Qx = Dx - n * (H * ehx + V_D * ux)
        Qy = Dy - n * (H * ehy + V_D * uy)
        Qz = Dz - n * (H * ehz + V_D * uz)
        if not (T_D > 0.0 and math.isfinite(Qx) and math.isfinite(Qy) and math.isfinite(Qz)):
            Qx, Qy, Qz = Bx, By, Bz
        moved = math.sqrt((Qx - Px) ** 2 + (Qy - Py) ** 2 + (Qz - Pz) ** 2)
        Px, Py, Pz = Qx, Qy, Qz
        scale = 1.0 + max(abs(vx), abs(vy), abs(vz))
        last = moved <= 1e-15 * scale or (moved >= moved_prev and moved <= 1e-12 * scale)
        moved_prev = moved
    Ds = (Dx - Ax) * esx + (Dy - Ay) * esy + (Dz - Az) * esz
    return _result(
        H, V, L0f, th, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it, ehx, ehy, ehz, Ds, gB.rho, esx, esy, esz, kx, ky,
        kz, Ax, Ay, Az, ux, uy, uz, w, gB.inside, gB.gamma,
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def _cable_at(
    Bx, By, Bz, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12, F20, F21, F22, kind, h, rp, d, inx, iny, EA, w,
    ux, uy, uz, kx, ky, kz, L0c, ready, H0, V0, L0f, th0, D0x, D0y, D0z, general, thK,
):  # fmt: skip
    """``exit_points`` of one cable on scalars only (no arrays: no reference counts in the pose
    kernel's loop over cables): the attachment point B, the joint A, the pulley frame F (``ident``:
    the identity) and the cable's data (``_kernels.Cables``, ``Heavy``), rest length L0c [m] and the
    start (ready > 0: H0, V0 [N], L0f [m], theta [rad], the exit point D0 [m]; else the reference's
    start). ``general`` (``Heavy.general``): a DR pulley or an SR swivel axis off gravity, solved by
    ``_general_at``; else the sheave plane is the one through B (a vertical axis: the catenary's
    vertical plane contains the axis) and D's angle theta on it is solved with the catenary
    (``_joint``, else the nested iterations); thK [rad] the angle of its entry point K on the sheave
    (``Heavy.thK``: fixed on such a sheave, so computed once).

    Returns
    -------
    tuple
        (H, V_B [N], L0f [m], theta [rad], T_B, T_D [N], l_h, l_v [m], D (3) [m], gamma [rad], code,
        l_dead [m], iterations, e_h (3) [-], swivel [-], e_perp (3) [-], (D - A) . up [m], inside,
        gamma of the massless model [rad]).
    """
    g, esx, esy, esz = sheave(
        Bx, By, Bz, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12, F20, F21, F22, kind, h, rp, d, inx, iny
    )
    if general:  # the swivel angle (any axis) and a DR arm follow the catenary's end tangent
        return _general_at(
            Bx, By, Bz, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12, F20, F21, F22, kind, h, rp, d, inx, iny,
            EA, w, ux, uy, uz, kx, ky, kz, L0c, ready, H0, V0, L0f, th0, D0x, D0y, D0z, g,
        )  # fmt: skip
    Hx, Hy, Hz = Ax + g.Hs * esx + g.Hw * kx, Ay + g.Hs * esy + g.Hw * ky, Az + g.Hs * esz + g.Hw * kz
    if ready > 0.0:
        th = th0
    else:
        th, H0, V0, L0f = math.atan2(g.sD, g.cD), np.nan, np.nan, np.nan
    sr = kind == 1 and rp > 0.0
    gamma = ell = np.nan
    H = V = np.nan
    code = 0
    l_h = l_v = 0.0
    ehx = ehy = ehz = 0.0
    Dx = Dy = Dz = 0.0
    it = 0
    last = not sr
    th_prev = f_prev = np.nan
    joint = False
    if w > 0.0:  # all the cable's unknowns at once: from the start given, else from a cold one
        joint, Hj, Vj, Lj, tj, it, ct, st, gamma_j = _joint_or_cold(
            Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, g.ld, thK, sr, L0c, w, EA, ready > 0.0,
            H0, V0, L0f, th, np.nan if ready > 0.0 else th, g.sD, g.cD,
        )  # fmt: skip
        if joint:
            H, V, L0f, th, gamma = Hj, Vj, Lj, tj, gamma_j
            _, _, _, Dx, Dy, Dz, _, _, _, l_v, l_h, ehx, ehy, ehz = _spans_at(
                Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ct, st
            )
            ell = g.ld + rp * gamma
            code = U_SHAPED if (V < 0.0 and V + w * L0f > 0.0) else CATENARY
    if not joint:  # the nested iterations, from the given start (or the reference's)
        gamma = mod_two_pi(thK - th) if ready > 0.0 else g.gamma
        ell = g.ld + rp * gamma
        for it in range(1, EXIT_MAXITER + 2):
            ct, st = math.cos(th), math.sin(th)
            _, _, _, Dx, Dy, Dz, vx, vy, vz, l_v, l_h, ehx, ehy, ehz = _spans_at(
                Bx, By, Bz, Hx, Hy, Hz, esx, esy, esz, kx, ky, kz, ux, uy, uz, rp, ct, st
            )
            H, V, code, _, _, L0f = cable_state(l_h, l_v, L0c, ell, w, EA, H0, V0, L0f)
            H0, V0 = H, V
            if last or it > EXIT_MAXITER or code == INFEASIBLE:
                break
            V_D = V + w * L0f
            T_D = math.hypot(H, V_D)
            # the cable's direction at D toward the sheave, in the sheave plane: (n_s, n_w)
            cx = -(H * ehx + V_D * ux) / T_D
            cy = -(H * ehy + V_D * uy) / T_D
            cz = -(H * ehz + V_D * uz) / T_D
            n_s = -(cx * kx + cy * ky + cz * kz)
            n_w = cx * esx + cy * esy + cz * esz
            if not (T_D > 0.0 and math.isfinite(n_s) and math.isfinite(n_w)):
                break
            g_th = math.atan2(n_w, n_s)  # the fixed point's map: theta <- g(theta)
            f = mod_two_pi(g_th - th + math.pi) - math.pi
            vmax = max(abs(vx), abs(vy), abs(vz))
            # converged: one more pass solves the whole cable at D = g(theta) (the loop's last)
            last = rp * abs(f) <= 1e-15 * (1.0 + vmax)
            th_new = g_th
            if not last and f_prev == f_prev and th != th_prev:
                # the secant step on f(theta) = g(theta) - theta where its slope is that of a
                # contraction (g' = slope + 1 in (-0.5, 0.5)); else the plain fixed-point step
                slope = (f - f_prev) / (th - th_prev)
                if -1.5 < slope < -0.5:
                    th_new = th - f / slope
            th_prev, f_prev = th, f
            th = th_new
            gamma = mod_two_pi(thK - th)
            ell = g.ld + rp * gamma
    Ds = g.Hs + rp * (ct if joint else math.cos(th))
    return _result(
        H, V, L0f, th, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it, ehx, ehy, ehz, Ds, g.rho, esx, esy, esz, kx, ky,
        kz, Ax, Ay, Az, ux, uy, uz, w, g.inside, g.gamma,
    )  # fmt: skip


@njit(cache=True, inline="always", error_model="numpy")
def _store(out, c, H, V, L0f, th, T_B, T_D, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it):
    """Row c of a cables' state (``STATE``) from ``_cable_at``'s results."""
    out[c, _H], out[c, _V], out[c, _L0F], out[c, _TH] = H, V, L0f, th
    out[c, _READY] = 1.0 if math.isfinite(H) else 0.0
    out[c, _TB], out[c, _TD], out[c, _LH], out[c, _LV] = T_B, T_D, l_h, l_v
    out[c, _DX], out[c, _DY], out[c, _DZ], out[c, _GAM] = Dx, Dy, Dz, gamma
    out[c, _CODE], out[c, _ELL], out[c, _IT] = code, ell, it


@njit(cache=True, error_model="numpy")
def exit_points(Bx, By, Bz, c, L0c, cab, frame, ident, heavy, start, out):
    """``HeavyCables.exit_points`` of cable c at its attachment point B (base frame) with rest
    length L0c [m]: the exit point D on the sheave where the catenary's end tangent leaves it, the
    wrap gamma from the entry point K to D, the dead part l_dead = |l_d| + r_p gamma and the
    catenary (``catenary.cable_state``) from B to D, by a fixed point on D (fixed pulleys: D = A);
    ``start`` (NSTATE,) the state to start from (``STATE``; ready 0: the reference's start, the
    massless exit point and Hooke's law), ``out`` (NSTATE,) written (it may be ``start``).

    Returns
    -------
    tuple
        (H, V_B [N], L0f [m], l_h, l_v [m], e_h (3) [-], l_dead [m], swivel [-], e_perp (3) [-],
        T_B [N], (D - A) . up [m], inside, gamma of the massless model [rad]).
    """
    A, F, k = cab.A, frame[c], heavy.axis
    (H, V, L0f, th, T_B, T_D, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it, ehx, ehy, ehz, sw, epx, epy, epz, zD, ins,
     gam) = _cable_at(
        Bx, By, Bz, A[c, 0], A[c, 1], A[c, 2], ident[c], F[0, 0], F[0, 1], F[0, 2], F[1, 0], F[1, 1], F[1, 2],
        F[2, 0], F[2, 1], F[2, 2], cab.kind[c], cab.h[c], cab.rp[c], cab.d[c], cab.inward[c, 0], cab.inward[c, 1],
        cab.ES[c], heavy.w[c], heavy.up[0], heavy.up[1], heavy.up[2], k[c, 0], k[c, 1], k[c, 2], L0c, start[_READY],
        start[_H], start[_V], start[_L0F], start[_TH], start[_DX], start[_DY], start[_DZ], heavy.general[c],
        heavy.thK[c],
    )  # fmt: skip
    _store(out.reshape((1, NSTATE)), 0, H, V, L0f, th, T_B, T_D, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it)
    return H, V, L0f, l_h, l_v, ehx, ehy, ehz, ell, sw, epx, epy, epz, T_B, zD, ins, gam


@njit(cache=True, error_model="numpy")
def evaluate(
    px, py, pz, R, rfx, rfy, rfz, cab, body, heavy, L0, i, t, J, e6, g6, G, ins_out, gam_out, start, state, exact
):  # fmt: skip
    """``HeavyCables.evaluate`` at one pose (p, R) with rest lengths L0[i], merit relative to p_ref =
    (rfx, rfy, rfz), in the layout of ``equilibrium.evaluate``: writes the tensions at B t (m,),
    J (6, 6), e6 = (F (3), M (3), Fn = (F, M) (6), merit, inside), g6 = (grad = -Fn (6), kappa (2))
    and the cables' state (m, NSTATE) (``exit_points``, started from ``start``, which may be the
    same array); G (3, 3) scratch (one cable's dF/dB); ins_out (m,) bool, gam_out (m,) [rad] written:
    the massless pulley state at B, which the result reports (the pose kernel's scratch arrays,
    passed alone: the whole scratch record would cost a reference count per member and call);
    ``exact``: each pulley cable's dF/dB exact (``exact_force_gradient``,
    ``models.cables.HeavyCables.evaluate``'s ``exact``), else without D's slide on the sheave and a
    DR arm's turn."""
    b, frame, ident, f = body.b, body.frame, body.ident, body.f
    m = cab.A.shape[0]
    ux, uy, uz = heavy.up[0], heavy.up[1], heavy.up[2]
    fx, fy, fz = f[0], f[1], f[2]
    rcx = R[0, 0] * body.com[0] + R[0, 1] * body.com[1] + R[0, 2] * body.com[2]
    rcy = R[1, 0] * body.com[0] + R[1, 1] * body.com[1] + R[1, 2] * body.com[2]
    rcz = R[2, 0] * body.com[0] + R[2, 1] * body.com[1] + R[2, 2] * body.com[2]
    Fx = Fy = Fz = Mx = My = Mz = 0.0
    energy = 0.0
    kap0 = kap1 = 0.0
    inside = False
    for a in range(6):
        for q in range(6):
            J[a, q] = 0.0
    A, kind, h, rp, d, inward, ES, k, wd, gen = (
        cab.A,
        cab.kind,
        cab.h,
        cab.rp,
        cab.d,
        cab.inward,
        cab.ES,
        heavy.axis,
        heavy.w,
        heavy.general,
    )
    thk = heavy.thK
    for c in range(m):
        rx = R[0, 0] * b[c, 0] + R[0, 1] * b[c, 1] + R[0, 2] * b[c, 2]
        ry = R[1, 0] * b[c, 0] + R[1, 1] * b[c, 1] + R[1, 2] * b[c, 2]
        rz = R[2, 0] * b[c, 0] + R[2, 1] * b[c, 1] + R[2, 2] * b[c, 2]
        (H, V, L0f, th, T_B, T_D, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it, ehx, ehy, ehz, sw, epx, epy, epz, zD, ins,
         gam) = _cable_at(
            px + rx, py + ry, pz + rz, A[c, 0], A[c, 1], A[c, 2], ident[c], frame[c, 0, 0], frame[c, 0, 1],
            frame[c, 0, 2], frame[c, 1, 0], frame[c, 1, 1], frame[c, 1, 2], frame[c, 2, 0], frame[c, 2, 1],
            frame[c, 2, 2], kind[c], h[c], rp[c], d[c], inward[c, 0], inward[c, 1], ES[c], wd[c], ux, uy, uz, k[c, 0],
            k[c, 1], k[c, 2], L0[i, c], start[c, _READY], start[c, _H], start[c, _V], start[c, _L0F], start[c, _TH],
            start[c, _DX], start[c, _DY], start[c, _DZ], gen[c], thk[c],
        )  # fmt: skip
        _store(state, c, H, V, L0f, th, T_B, T_D, l_h, l_v, Dx, Dy, Dz, gamma, code, ell, it)
        inside = inside or ins
        ins_out[c] = ins
        gam_out[c] = gam
        t[c] = T_B
        wc, EA = wd[c], ES[c]
        Fix, Fiy, Fiz = H * ehx + V * ux, H * ehy + V * uy, H * ehz + V * uz
        Fx += Fix
        Fy += Fiy
        Fz += Fiz
        Mx += ry * Fiz - rz * Fiy
        My += rz * Fix - rx * Fiz
        Mz += rx * Fiy - ry * Fix
        energy_c, k11, k12, k21, k22 = cable_energy_stiffness(H, V, L0f, l_h, l_v, ell, wc, EA)
        energy += energy_c + wc * L0f * zD
        turn = H / l_h if l_h > 1e-12 * (1.0 + abs(l_v)) else k11
        # dF/dv = e_h (k11 e_h + k12 up)^T + up (k21 e_h + k22 up)^T + turn (I - e_h e_h^T - up up^T)
        ah = (k11 * ehx + k12 * ux, k11 * ehy + k12 * uy, k11 * ehz + k12 * uz)
        av = (k21 * ehx + k22 * ux, k21 * ehy + k22 * uy, k21 * ehz + k22 * uz)
        a0, a1, a2 = ah
        v0, v1, v2 = av
        d00 = ehx * a0 + ux * v0 + turn * (1.0 - ehx * ehx - ux * ux)
        d01 = ehx * a1 + ux * v1 + turn * (-ehx * ehy - ux * uy)
        d02 = ehx * a2 + ux * v2 + turn * (-ehx * ehz - ux * uz)
        d10 = ehy * a0 + uy * v0 + turn * (-ehy * ehx - uy * ux)
        d11 = ehy * a1 + uy * v1 + turn * (1.0 - ehy * ehy - uy * uy)
        d12 = ehy * a2 + uy * v2 + turn * (-ehy * ehz - uy * uz)
        d20 = ehz * a0 + uz * v0 + turn * (-ehz * ehx - uz * ux)
        d21 = ehz * a1 + uz * v1 + turn * (-ehz * ehy - uz * uy)
        d22 = ehz * a2 + uz * v2 + turn * (1.0 - ehz * ehz - uz * uz)
        # G = dF/dB = dF/dv (-I + swivel e_perp e_perp^T)
        de0 = sw * (d00 * epx + d01 * epy + d02 * epz)
        de1 = sw * (d10 * epx + d11 * epy + d12 * epz)
        de2 = sw * (d20 * epx + d21 * epy + d22 * epz)
        G[0, 0], G[0, 1], G[0, 2] = de0 * epx - d00, de0 * epy - d01, de0 * epz - d02
        G[1, 0], G[1, 1], G[1, 2] = de1 * epx - d10, de1 * epy - d11, de1 * epz - d12
        G[2, 0], G[2, 1], G[2, 2] = de2 * epx - d20, de2 * epy - d21, de2 * epz - d22
        if exact and kind[c] != 0 and rp[c] > 0.0:  # exact: D's slide on the sheave, a DR arm's turn
            exact_force_gradient(
                px + rx, py + ry, pz + rz, Dx, Dy, Dz, H, V, L0f, ell, ehx, ehy, ehz, l_h, A[c, 0], A[c, 1], A[c, 2],
                ident[c], frame[c, 0, 0], frame[c, 0, 1], frame[c, 0, 2], frame[c, 1, 0], frame[c, 1, 1],
                frame[c, 1, 2], frame[c, 2, 0], frame[c, 2, 1], frame[c, 2, 2], kind[c], h[c], rp[c], d[c],
                inward[c, 0], inward[c, 1], EA, wc, ux, uy, uz, k[c, 0], k[c, 1], k[c, 2], G,
            )  # fmt: skip
        add_cable_jacobian(
            J, G[0, 0], G[0, 1], G[0, 2], G[1, 0], G[1, 1], G[1, 2], G[2, 0], G[2, 1], G[2, 2],
            rx, ry, rz, 1.0, Fix, Fiy, Fiz,
        )  # fmt: skip
        kc = abs(k11) + abs(k22) + abs(turn)
        rr = rx * rx + ry * ry + rz * rz
        kap0 += kc
        kap1 += kc * rr + T_B * math.sqrt(rr)
    Fx, Fy, Fz, Mx, My, Mz, _, _, _ = add_gravity(J, Fx, Fy, Fz, Mx, My, Mz, fx, fy, fz, rcx, rcy, rcz)
    e6[0], e6[1], e6[2], e6[3], e6[4], e6[5] = Fx, Fy, Fz, Mx, My, Mz
    e6[6], e6[7], e6[8], e6[9], e6[10], e6[11] = Fx, Fy, Fz, Mx, My, Mz
    merit = -((px - rfx + rcx) * fx + (py - rfy + rcy) * fy + (pz - rfz + rcz) * fz) + energy
    if not math.isfinite(merit):
        merit = np.inf
    if body.suspended and not pz < body.ztop:
        merit = np.inf
    e6[12] = merit
    e6[13] = 1.0 if inside else 0.0
    for a in range(6):
        g6[a] = -e6[6 + a]
    g6[6] = kap0
    g6[7] = kap1 + math.sqrt(fx * fx + fy * fy + fz * fz) * math.sqrt(rcx * rcx + rcy * rcy + rcz * rcz)


@njit(cache=True, parallel=True, error_model="numpy")
def _heavy_cables(P, R, L0, cab, frame, ident, heavy, b, start, out):
    n, m = P.shape[0], cab.A.shape[0]
    warm = start.shape[0] == n
    for i in prange(n):
        st = np.zeros(NSTATE)
        for c in range(m):
            Bx = P[i, 0] + R[i, 0, 0] * b[c, 0] + R[i, 0, 1] * b[c, 1] + R[i, 0, 2] * b[c, 2]
            By = P[i, 1] + R[i, 1, 0] * b[c, 0] + R[i, 1, 1] * b[c, 1] + R[i, 1, 2] * b[c, 2]
            Bz = P[i, 2] + R[i, 2, 0] * b[c, 0] + R[i, 2, 1] * b[c, 1] + R[i, 2, 2] * b[c, 2]
            st[_READY] = 0.0
            if warm:
                for a in range(NSTATE):
                    st[a] = start[i, c, a]
            (H, V, L0f, l_h, l_v, _, _, _, _, _, _, _, _, T_B, _, _, _) = exit_points(
                Bx, By, Bz, c, L0[i, c], cab, frame, ident, heavy, st, st
            )
            wc, EA = heavy.w[c], cab.ES[c]
            o = out[i, c]
            o[0], o[1], o[2] = T_B, st[_TD], H
            o[3] = sag(H, V, L0f, wc, EA, l_h, l_v)
            o[4] = arc_length(H, V, L0f, wc, EA) - math.hypot(l_h, l_v)
            o[5] = angle_f_deg(H, V, l_h, l_v)
            o[6] = st[_CODE]
            o[7], o[8], o[9] = st[_DX], st[_DY], st[_DZ]
            o[10] = st[_GAM]
            o[11], o[12] = V, L0f


def heavy_cables(cab, P, R, L0, start=None):
    """Compiled ``models.cables.heavy_cables``: what each heavy cable does at the equilibria, each
    cable solved afresh at (P, R) by ``exit_points`` (from ``start``, or the reference's start),
    points in parallel.

    Parameters
    ----------
    cab : CompiledHeavyCables
        The robot's cables (``equilibrium.CompiledHeavyCables``: the kernel's records).
    P : ndarray (N, 3) [m]
        Platform positions.
    R : ndarray (N, 3, 3) [-]
        Platform orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths of the whole cables.
    start : ndarray (N, m, NSTATE), optional
        The cables' state to start from (``STATE``; the pose kernel's at the result).

    Returns
    -------
    dict
        As ``models.cables.heavy_cables``: t_B, t_D, H [N], sag, arc_minus_chord [m], angle_f_deg
        [deg], cable_status (str), all (N, m), sag_max (N,) [m], D (N, m, 3) [m], gamma (N, m) [rad],
        V_B (N, m) [N] and L0_free (N, m) [m].

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2; Paty et al. 2021, eq. (10)-(13).
    """
    f = np.ascontiguousarray
    n, m = len(P), cab.robot.m
    out = np.empty((n, m, 13))
    if n:
        _heavy_cables(
            f(P, dtype=float), f(R, dtype=float), f(L0, dtype=float), cab.cables, cab.body.frame,
            cab.body.ident, cab.heavy, cab.body.b, np.zeros((0, m, NSTATE)) if start is None else f(start), out,
        )  # fmt: skip
    code = out[..., 6].astype(np.int8)
    sag_ = out[..., 3]
    return {
        "t_B": out[..., 0],
        "t_D": out[..., 1],
        "H": out[..., 2],
        "sag": sag_,
        "arc_minus_chord": out[..., 4],
        "angle_f_deg": out[..., 5],
        "cable_status": np.asarray(SPAN_STATUSES)[code],
        "sag_max": sag_.max(axis=1) if m else np.zeros(n),
        "D": out[..., 7:10],
        "gamma": out[..., 10],
        "V_B": out[..., 11],
        "L0_free": out[..., 12],
    }


@njit(cache=True, error_model="numpy")
def span_for_tension(l_h, l_v, T_B, w, EA, rtol=1e-15, maxiter=50):
    """One span of ``models.cables.span_for_tension`` (its defaults): the elastic catenary of spans
    l_h, l_v [m] that carries the tension T_B [N] at B, by the reference's Newton iteration on
    (psi, L0) from the straight Hooke spring along the chord, step by step (the same Jacobian,
    clips and stop rule). Returns (H, V_B [N], L0 [m], converged, iterations), NaN forces and length
    where not converged (T_B <= 0, l_h <= 0, no convergence in maxiter)."""
    c = math.hypot(l_h, l_v)
    ok = T_B > 0.0 and l_h > 0.0 and math.isfinite(T_B)
    psi = math.atan2(l_v, l_h)
    L0 = c * (1.0 if math.isinf(EA) else EA / (EA + (T_B if ok else 0.0)))
    it = 0
    done = (not ok) or w == 0.0
    for _ in range(maxiter):
        if done:
            break
        H, V = T_B * math.cos(psi), T_B * math.sin(psi)
        xh, xv, f11, f12, f22 = spans_and_flexibility(H, V, L0, w, EA)
        rh, rv = xh - l_h, xv - l_v
        if math.hypot(rh, rv) <= rtol * c:
            done = True
            break
        V_D = V + w * L0
        T_D = math.hypot(H, V_D)
        g = 1.0 / EA + 1.0 / T_D if T_D > 0.0 else 0.0  # the stretched tangent at D
        gh, gv = g * H, g * V_D
        j11 = -f11 * V + f12 * H
        j21 = -f12 * V + f22 * H
        det = j11 * gv - gh * j21
        dpsi = -(gv * rh - gh * rv) / det
        dL = -(-j21 * rh + j11 * rv) / det
        psi += min(max(dpsi if math.isfinite(dpsi) else 0.0, -0.5), 0.5)
        L0 += max(dL if math.isfinite(dL) else 0.0, -0.5 * L0)
        it += 1
    if not (done and ok):
        return np.nan, np.nan, np.nan, False, it
    return T_B * math.cos(psi), T_B * math.sin(psi), L0, True, it


#: Columns of one cable's result of ``inverse`` (``_inverse_cable``).
INVERSE = ("Dx", "Dy", "Dz", "l_h", "l_v", "ehx", "ehy", "ehz", "H", "V_B", "V_D", "T_D", "L0_free", "L0")
INVERSE += ("l_dead", "gamma", "converged", "iterations")


@njit(cache=True, error_model="numpy")
def _inverse_cable(Bx, By, Bz, c, t, cab, frame, ident, heavy, pulleys, maxiter, o):
    """``models.cables.HeavyCables.inverse`` of cable c at its attachment point B (base frame) under
    the tension t [N] at B, the reference's algorithm (``HeavyCables._couple``): the fixed point on
    the virtual point P* = D + |B - D| u from P* = B, D the tangent point of the massless pulley
    model at P* (``_sheave``), the catenary from B to D that carries t (``span_for_tension``), u its
    unit end tangent at D toward the platform; one pass without pulleys, else until P* moves by at
    most 1e-15 (1 + max |v|) or, within 1e-12 (1 + max |v|), stops shrinking (then the cable solved
    once more at the last P*), or ``maxiter`` passes. Writes ``INVERSE``'s columns into o."""
    A, F, rp, EA, w = cab.A[c], frame[c], cab.rp[c], cab.ES[c], heavy.w[c]
    ux, uy, uz = heavy.up[0], heavy.up[1], heavy.up[2]
    kx, ky, kz = heavy.axis[c, 0], heavy.axis[c, 1], heavy.axis[c, 2]
    Px, Py, Pz = Bx, By, Bz
    moved_prev = np.inf
    it = 0
    final = False
    while True:
        it += 1
        g, esx, esy, esz = sheave(
            Px, Py, Pz, A[0], A[1], A[2], ident[c], F[0, 0], F[0, 1], F[0, 2], F[1, 0], F[1, 1], F[1, 2], F[2, 0],
            F[2, 1], F[2, 2], cab.kind[c], cab.h[c], rp, cab.d[c], cab.inward[c, 0], cab.inward[c, 1],
        )  # fmt: skip
        Dw = g.Hw + rp * g.sD
        Dx, Dy, Dz = A[0] + g.Ds * esx + Dw * kx, A[1] + g.Ds * esy + Dw * ky, A[2] + g.Ds * esz + Dw * kz
        ell = g.ld + rp * g.gamma
        vx, vy, vz, l_v, l_h, ehx, ehy, ehz = _span(Dx, Dy, Dz, Bx, By, Bz, ux, uy, uz)
        H, V, L0f, conv, _ = span_for_tension(l_h, l_v, t, w, EA)
        V_D = V + w * L0f
        T_D = math.hypot(H, V_D)
        if final or not pulleys:
            break
        cx, cy, cz = -(H * ehx + V_D * ux) / T_D, -(H * ehy + V_D * uy) / T_D, -(H * ehz + V_D * uz) / T_D
        Qx, Qy, Qz = Bx, By, Bz
        if T_D > 0.0 and math.isfinite(cx) and math.isfinite(cy) and math.isfinite(cz):
            n = math.sqrt(vx * vx + vy * vy + vz * vz)
            Qx, Qy, Qz = Dx + n * cx, Dy + n * cy, Dz + n * cz
        moved = math.sqrt((Qx - Px) ** 2 + (Qy - Py) ** 2 + (Qz - Pz) ** 2)
        Px, Py, Pz = Qx, Qy, Qz
        scale = 1.0 + max(abs(vx), abs(vy), abs(vz))
        final = moved <= 1e-15 * scale or (moved >= moved_prev and moved <= 1e-12 * scale)
        if not final and it >= maxiter:
            break
        moved_prev = moved
    o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[7] = Dx, Dy, Dz, l_h, l_v, ehx, ehy, ehz
    o[8], o[9], o[10], o[11], o[12] = H, V, V_D, T_D, L0f
    o[13] = L0f + ell * (1.0 if math.isinf(EA) else EA / (EA + T_D))
    o[14], o[15], o[16], o[17] = ell, g.gamma, 1.0 if conv else 0.0, it - 1 if final else it


@njit(cache=True, parallel=True, error_model="numpy")
def _inverse(B, t, cab, frame, ident, heavy, pulleys, maxiter, out):
    for i in prange(B.shape[0]):
        for c in range(B.shape[1]):
            _inverse_cable(
                B[i, c, 0],
                B[i, c, 1],
                B[i, c, 2],
                c,
                t[i, c],
                cab,
                frame,
                ident,
                heavy,
                pulleys,
                maxiter,
                out[i, c],
            )


def inverse(cab, p, R, t, maxiter=EXIT_MAXITER, threads=None):
    """Compiled ``models.cables.HeavyCables.inverse``: the heavy inverse of every cable at poses (the
    exit points D_i, the catenaries that carry the tensions t_i at B_i, the whole cables' rest
    lengths), each cable by the reference's algorithm (``_inverse_cable``), points in parallel.
    The fixed point on P* stops cable by cable (the reference's when the largest move of all the
    cables of all the poses is small): the two agree to round-off; ``iterations`` is the largest
    number of passes of a cable.

    Parameters
    ----------
    cab : CompiledHeavyCables
        The robot's cables (``equilibrium.CompiledHeavyCables``: the kernel's records).
    p : ndarray (N, 3) [m]
        Platform positions.
    R : ndarray (N, 3, 3) [-]
        Platform orientations.
    t : ndarray (N, m) [N]
        Tensions at B_i (> 0).
    maxiter : int
        Cap of the fixed point's passes (pulleys).
    threads : int, optional
        Caps numba's threads.

    Returns
    -------
    dict
        As ``models.cables.HeavyCables.inverse``: r (N, m, 3) [m] = R b_i; D (N, m, 3) [m]; l_h,
        l_v (N, m) [m]; e_h (N, m, 3); H, V_B, V_D, T_D (N, m) [N]; f (N, m, 3) [-] the unit force
        on the platform at B_i; L0_free, L0, l_dead (N, m) [m]; gamma (N, m) [rad]; converged
        (N, m) bool; iterations (int).

    References
    ----------
    Irvine, H. M. (1981). Cable Structures. MIT Press, ch. 2; Paty et al. 2021, eq. (3)-(5).
    """
    set_threads(threads)
    t = np.asarray(t, dtype=float)
    r = np.einsum("nab,mb->nma", np.asarray(R, dtype=float), cab.b)
    B = np.asarray(p, dtype=float)[:, None, :] + r
    out = np.zeros(B.shape[:2] + (len(INVERSE),))
    if out.size:
        tt = np.ascontiguousarray(np.broadcast_to(t, B.shape[:2]))
        _inverse(
            B, tt, cab.cables, cab.body.frame, cab.body.ident, cab.heavy, bool(cab.pulleys), int(maxiter), out
        )
    res = {k: out[..., i] for i, k in enumerate(INVERSE) if k not in ("Dx", "Dy", "Dz", "ehx", "ehy", "ehz")}
    res.update(r=r, D=out[..., 0:3], e_h=out[..., 5:8], converged=res["converged"] > 0.0)
    res["iterations"] = int(res["iterations"].max(initial=0))
    with np.errstate(invalid="ignore", divide="ignore"):
        res["f"] = (res["H"][..., None] * res["e_h"] + res["V_B"][..., None] * cab.up) / t[..., None]
    return res
