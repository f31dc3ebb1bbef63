"""The scalar cable kernel of the compiled engines, written once: the pulley geometry of Paty 2021
eq. (3)-(7) for one cable at one point P (``pulley_geometry``), what the direct solvers need of it
(``cable``, the scalar twin of ``pulleys.total_length_and_direction``) and its partial derivatives
(``cable_partials``, the scalar twin of ``sensitivity.cable_partials``), both built on
``pulley_geometry``. Also the constants and the argument records every compiled kernel takes
(``Cables`` from ``cable_arrays(robot)``, ``Newton`` from ``newton_options``).

A private module of ``cdpr.compiled``: the engines (``subsets`` paper mode, ``equilibrium`` physical
mode, ``sensitivity``) import its public names; nothing outside ``cdpr.compiled`` should.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np
from numba import njit

from cdpr.models.direct import NEWTON_DEFAULTS
from cdpr.models.pulleys import RHO_EPS, SWIVEL_RHO_MIN, TWO_PI
from cdpr.models.statics import DET_EPS

__all__ = [
    "CHUNK",
    "DET_EPS",
    "NEWTON_DEFAULTS",
    "RHO_EPS",
    "SWIVEL_RHO_MIN",
    "TWO_PI",
    "C_DLD",
    "C_DLDP",
    "C_DLH",
    "C_DLR",
    "C_DUDP",
    "C_DUH",
    "C_DUR",
    "C_INSIDE",
    "C_L",
    "C_LE",
    "C_U",
    "NCOL",
    "Cables",
    "Newton",
    "PulleyGeometry",
    "cable",
    "cable_arrays",
    "cable_axis",
    "cable_derivatives",
    "cable_of",
    "cable_params",
    "cable_partials",
    "cable_partials_at",
    "cable_partials_axis",
    "commanded_input",
    "entry_angle",
    "in_frame",
    "mod_two_pi",
    "newton_options",
    "pulley_frames",
    "pulley_geometry",
    "set_threads",
]

#: Points per parallel work item of every compiled kernel: per-point scratch arrays are allocated
#: once per chunk.
CHUNK = 256

#: Layout of one cable's row written by ``cable_partials``: L_TE, u (3), |l_E|, dL_TE/dP (3),
#: du/dP (9, row-major du_a/dP_b), dL_TE/dh, du/dh (3), dL_TE/dr_p, du/dr_p (3), dL_TE/dd, inside.
C_L, C_U, C_LE, C_DLDP, C_DUDP, C_DLH, C_DUH, C_DLR, C_DUR, C_DLD, C_INSIDE = (
    0,
    1,
    4,
    5,
    8,
    17,
    18,
    21,
    22,
    25,
    26,
)
NCOL = 27


class Cables(NamedTuple):
    """The per-cable arrays every compiled kernel takes (``cable_arrays``), over the m cables.

    A (m, 3) [m]; kind (m,) int64 codes (0 fixed, 1 SR, 2 DR); h, rp, d (m,) [m]; inward (m, 2) [-];
    ES (m,) [N]; E (m,) [Pa]; T_a (m,) [N] (``robot.CableArrays``)."""

    A: np.ndarray
    kind: np.ndarray
    h: np.ndarray
    rp: np.ndarray
    d: np.ndarray
    inward: np.ndarray
    ES: np.ndarray
    E: np.ndarray
    T_a: np.ndarray


def cable_arrays(robot):
    """The ``Cables`` record of ``robot`` (contiguous float64 arrays, kind as int64).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    Cables
    """
    a = robot.arrays
    f = np.ascontiguousarray
    return Cables(
        f(a.A, dtype=float),
        f(a.kind, dtype=np.int64),
        f(a.h, dtype=float),
        f(a.r_p, dtype=float),
        f(a.d, dtype=float),
        f(a.inward, dtype=float),
        f(a.ES, dtype=float),
        f(a.E, dtype=float),
        f(a.T_a, dtype=float),
    )


def pulley_frames(robot):
    """The pulley frames as the kernels take them: frame (m, 3, 3) [-] contiguous (rows i_i, j_i,
    k_i, ``robot.CableArrays.frame``) and ident (m,) bool, the frame is the identity (axis +z
    without ``zero``: ``cable_axis`` then runs the scalar kernel on B and A themselves).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    tuple of ndarray
        (frame (m, 3, 3), ident (m,)).
    """
    frame = np.ascontiguousarray(robot.arrays.frame, dtype=float)
    return frame, np.array([(f == np.eye(3)).all() for f in frame], dtype=np.bool_)


class Newton(NamedTuple):
    """Stop rule of the compiled Newton solvers: tol [m] on the step, maxiter, max_step [m]."""

    tol: float
    maxiter: int
    max_step: float


def newton_options(defaults, tol=None, maxiter=None, max_step=None):
    """The ``Newton`` record: each of tol, maxiter, max_step, or its value in ``defaults`` (a dict,
    ``direct.NEWTON_DEFAULTS`` or ``equilibrium.PHYSICAL_DEFAULTS``) when None."""
    return Newton(
        float(defaults["tol"] if tol is None else tol),
        int(defaults["maxiter"] if maxiter is None else maxiter),
        float(defaults["max_step"] if max_step is None else max_step),
    )


def commanded_input(L, n, m):
    """The kernels' commanded lengths: L broadcast to (n, m) [m], or an empty (0, m) array for
    "L_TS at each point" (eq. 2) when L is None."""
    if L is None:
        return np.empty((0, m))
    return np.ascontiguousarray(np.broadcast_to(np.asarray(L, dtype=float), (n, m)))


def set_threads(threads):
    """Cap numba's threads at ``threads`` (None or 0: leave them as they are)."""
    if threads:
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))


class PulleyGeometry(NamedTuple):
    """One cable's pulley geometry at P (``pulley_geometry``), scalars.

    esx, esy [-] horizontal unit vector e_s of the cable plane; rho [m] horizontal distance A -> P;
    arm [-] = h / (2 |AP|) for DR, else 0; bhs, bhw [-] the unit bisector (DR, else 0); ens, enw [-]
    the in-plane normal of the strand A -> P (DR, else 0); Hs, Hw [m] the sheave centre H; cD, sD,
    cK, sK [-] cos and sin of theta_D and theta_K (the tangent points D = H + r_p (cD, sD) and
    K = H + r_p (cK, sK)); ld [m] = |l_d|; lE [m] = sqrt(|H - P|^2 - r_p^2) the
    tangent length; gamma [rad] the wrap angle in [0, 2 pi); L [m] = L_TE (eq. 5); Ds [m] the in-plane s of D;
    vx, vy, vz [m] = D - P; n [m] = |D - P| (1 where 0); inside: P or C inside the sheave circle."""

    esx: float
    esy: float
    rho: float
    arm: float
    bhs: float
    bhw: float
    ens: float
    enw: float
    Hs: float
    Hw: float
    cD: float
    sD: float
    cK: float
    sK: float
    ld: float
    lE: float
    gamma: float
    L: float
    Ds: float
    vx: float
    vy: float
    vz: float
    n: float
    inside: bool


@njit(cache=True, inline="always", error_model="numpy")
def pulley_geometry(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny):
    """Extended inverse geometric model of one cable at one point P, Paty 2021 eq. (3)-(7):
    the scalar form of ``pulleys.pulley_state``.

    In the cable plane through A and P (in-plane coordinates s horizontal toward P, w = z - z_A),
    with the sheave centre H = (H_s, H_w) (SR and fixed: (h, 0); DR: h times the unit bisector of
    the vertical and the strand A -> P), the tangent points D (toward P) and K (toward the winch
    exit C = (0, -d)) on the circle of radius r_p, and the wrap angle gamma from D to K over the
    top (eq. 5)::

        L_TE = |l_d| + r_p gamma + |l_E|,   |l_E| = sqrt(|H - P|^2 - r_p^2),
        |l_d| = sqrt(|H - C|^2 - r_p^2),    gamma = theta_K - theta_D (mod 2 pi)

    With cos(delta) = r_p / R and sin(delta) = l / R the tangent directions follow from angle-sum
    identities (no acos), and gamma needs a single atan2.

    Parameters
    ----------
    px, py, pz : float [m]
        The point P.
    Ax, Ay, Az : float [m]
        The pulley joint point A.
    kind : int
        0 fixed, 1 SR, 2 DR.
    h, rp, d : float [m]
        Lever arm, sheave radius, dead length.
    inx, iny : float [-]
        The cable plane's horizontal direction used where P lies on the vertical through A.

    Returns
    -------
    PulleyGeometry

    References
    ----------
    Paty et al. 2021, eq. (3)-(7), section 2.2.
    """
    dx, dy = px - Ax, py - Ay
    rho = math.sqrt(dx * dx + dy * dy)
    if rho < RHO_EPS:
        esx, esy = inx, iny
    else:
        esx, esy = dx / rho, dy / rho
    wP = pz - Az
    arm = bhs = bhw = ens = enw = 0.0
    if kind == 2:
        nP = math.sqrt(rho * rho + wP * wP)
        okP = nP > 0.0
        if not okP:
            nP = 1.0
        bs, bw = rho / nP, wP / nP - 1.0
        nb = math.sqrt(bs * bs + bw * bw)
        if okP and nb > 0.0:
            arm = h / (2.0 * nP)
        if nb == 0.0:
            nb = 1.0
        bhs, bhw = bs / nb, bw / nb
        Hs, Hw = h * bhs, h * bhw
        ens, enw = -wP / nP, rho / nP  # in-plane normal of the strand A -> P
    else:
        Hs, Hw = h, 0.0
    rp2 = rp * rp
    # P side: theta_D = phi_P + delta_P
    rs, rw = rho - Hs, wP - Hw
    R2 = rs * rs + rw * rw
    inside = R2 <= rp2 and rp > 0.0
    lE = math.sqrt(max(R2 - rp2, 0.0))
    if R2 > 0.0:
        iR2 = 1.0 / R2
        cD, sD = (rs * rp - rw * lE) * iR2, (rw * rp + rs * lE) * iR2
    else:
        cD, sD = 0.0, 1.0
    # C side (C = (0, -d)): theta_K = phi_C - delta_C
    cs, cw = -Hs, -d - Hw
    RC2 = cs * cs + cw * cw
    inside = inside or (RC2 <= rp2 and rp > 0.0)
    ld = math.sqrt(max(RC2 - rp2, 0.0))
    if RC2 > 0.0:
        iRC2 = 1.0 / RC2
        cK, sK = (cs * rp + cw * ld) * iRC2, (cw * rp - cs * ld) * iRC2
    else:
        cK, sK = 0.0, -1.0
    gamma = math.atan2(sK * cD - cK * sD, cK * cD + sK * sD)  # in (-pi, pi]; gamma mod 2 pi:
    if gamma < 0.0:
        gamma += TWO_PI
    L = ld + rp * gamma + lE
    Ds, Dw = Hs + rp * cD, Hw + rp * sD
    vx, vy, vz = Ax + Ds * esx - px, Ay + Ds * esy - py, Az + Dw - pz
    n = math.sqrt(vx * vx + vy * vy + vz * vz)
    if n <= 0.0:
        n = 1.0
    return PulleyGeometry(
        esx,
        esy,
        rho,
        arm,
        bhs,
        bhw,
        ens,
        enw,
        Hs,
        Hw,
        cD,
        sD,
        cK,
        sK,
        ld,
        lE,
        gamma,
        L,
        Ds,
        vx,
        vy,
        vz,
        n,
        inside,
    )


@njit(cache=True, inline="always", error_model="numpy")
def cable(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny):
    """What the direct solvers need of one cable at P (``pulleys.CableGeometry``, scalar form):
    L_TE (eq. 5) and u = (D - P)/|D - P| (a column of M, eq. 12) from ``pulley_geometry``, and the
    pulley-motion terms of ``statics.length_gradient`` / ``tension_gradient``.

    Parameters
    ----------
    px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny
        As ``pulley_geometry``.

    Returns
    -------
    tuple
        (L [m]; ux, uy, uz [-]; l_E = |D - P| [m]; inside; swivel [-] = D_s / rho (0 on the axis);
        e_perp x, y [-]; arm [-]; beta x, y, z [-]; eps x, y, z [-]; uC_beta [-]; gamma [rad], the
        wrap angle of eq. (5)).

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (12).
    """
    g = pulley_geometry(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny)
    esx, esy, bhs, bhw, ens, enw, n = g.esx, g.esy, g.bhs, g.bhw, g.ens, g.enw, g.n
    swivel = g.Ds / g.rho if g.rho > SWIVEL_RHO_MIN else 0.0  # pulleys.total_length_and_direction
    # u_C . beta, u_C = (K - C)/l_d in the plane, beta = (-bhw, bhs) the arm's in-plane normal
    uCb = ((g.Hs + rp * g.cK) * -bhw + (g.Hw + rp * g.sK + d) * bhs) / (g.ld if g.ld > 0.0 else 1.0)
    i_n = 1.0 / n
    return (
        g.L,
        g.vx * i_n,
        g.vy * i_n,
        g.vz * i_n,
        n,
        g.inside,
        swivel,
        -esy,
        esx,
        g.arm,
        -bhw * esx,
        -bhw * esy,
        bhs,
        ens * esx,
        ens * esy,
        enw,
        uCb,
        g.gamma,
    )


@njit(cache=True, inline="always", error_model="numpy")
def in_frame(px, py, pz, Ax, Ay, Az, ident, f):
    """The point B and the joint A as the scalar kernels take them for a pulley with frame F (rows
    i_i, j_i, k_i): the components of B - A in the pulley frame and A' = 0, or, for the identity
    frame (``ident``), B and A themselves (the kernels' arithmetic bit for bit)::

        w' = F (B - A)

    Parameters
    ----------
    px, py, pz : float [m]
        B (base frame).
    Ax, Ay, Az : float [m]
        A (base frame).
    ident : bool
        F is the identity.
    f : ndarray (3, 3) [-]
        The pulley frame F.

    Returns
    -------
    tuple
        (w'x, w'y, w'z, A'x, A'y, A'z) [m].

    References
    ----------
    Paty et al. 2021, section 2.1 (the cable plane through the pulley's axis).
    """
    if ident:
        return px, py, pz, Ax, Ay, Az
    wx, wy, wz = px - Ax, py - Ay, pz - Az
    return (
        f[0, 0] * wx + f[0, 1] * wy + f[0, 2] * wz,
        f[1, 0] * wx + f[1, 1] * wy + f[1, 2] * wz,
        f[2, 0] * wx + f[2, 1] * wy + f[2, 2] * wz,
        0.0,
        0.0,
        0.0,
    )


@njit(cache=True, inline="always", error_model="numpy")
def cable_axis(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny, ident, f):
    """``cable`` for a pulley whose swivel axis k_i is any unit vector: the pulley frame F (rows
    i_i, j_i, k_i) is a rotation, so the cable is evaluated by the same scalar kernel at the
    components of B - A in that frame, and the vectors come back to the base frame by F^T::

        w' = F (B - A),   (L, u', e_perp', beta', eps', ...) = cable(w', A' = 0),
        u = F^T u',   e_perp = F^T e_perp',   beta = F^T beta',   eps = F^T eps'

    The scalars (L_TE, |l_E|, swivel, arm, u_C . beta) are invariant. The gradients built from the
    vectors (``cable_derivatives``) then rotate as dL/dB = F^T dL'/dB', du/dB = F^T du'/dB' F.
    ``inward`` is already in the pulley frame (``robot.CableArrays``). With ``ident`` (F = I) the
    scalar kernel runs on B and A themselves: bit for bit ``cable``.

    Parameters
    ----------
    px, py, pz : float [m]
        The attachment point B_i (base frame).
    Ax, Ay, Az, kind, h, rp, d, inx, iny
        As ``pulley_geometry`` (A in the base frame, inward in the pulley frame).
    ident : bool
        F is the identity (axis +z without ``zero``).
    f : ndarray (3, 3) [-]
        The pulley frame, rows i_i, j_i, k_i (``robot.CableArrays.frame``).

    Returns
    -------
    tuple
        (L [m]; ux, uy, uz [-]; l_E [m]; inside; swivel [-]; e_perp x, y, z [-]; arm [-]; beta x, y, z
        [-]; eps x, y, z [-]; uC_beta [-]; gamma [rad]), vectors in the base frame.

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (12).
    """
    qx, qy, qz, ax, ay, az = in_frame(px, py, pz, Ax, Ay, Az, ident, f)
    (L, ux, uy, uz, lE, ins, sw, epx, epy, arm, btx, bty, btz, ex, ey, ez, uCb, gam) = cable(
        qx, qy, qz, ax, ay, az, kind, h, rp, d, inx, iny
    )
    if ident:
        return (L, ux, uy, uz, lE, ins, sw, epx, epy, 0.0, arm, btx, bty, btz, ex, ey, ez, uCb, gam)
    return (
        L,
        f[0, 0] * ux + f[1, 0] * uy + f[2, 0] * uz,
        f[0, 1] * ux + f[1, 1] * uy + f[2, 1] * uz,
        f[0, 2] * ux + f[1, 2] * uy + f[2, 2] * uz,
        lE,
        ins,
        sw,
        f[0, 0] * epx + f[1, 0] * epy,
        f[0, 1] * epx + f[1, 1] * epy,
        f[0, 2] * epx + f[1, 2] * epy,
        arm,
        f[0, 0] * btx + f[1, 0] * bty + f[2, 0] * btz,
        f[0, 1] * btx + f[1, 1] * bty + f[2, 1] * btz,
        f[0, 2] * btx + f[1, 2] * bty + f[2, 2] * btz,
        f[0, 0] * ex + f[1, 0] * ey + f[2, 0] * ez,
        f[0, 1] * ex + f[1, 1] * ey + f[2, 1] * ez,
        f[0, 2] * ex + f[1, 2] * ey + f[2, 2] * ez,
        uCb,
        gam,
    )


@njit(cache=True, inline="always", error_model="numpy")
def cable_derivatives(ux, uy, uz, lE, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb):
    """The gradients of one cable's length and direction with respect to its attachment point B
    (``statics.length_gradient``, ``statics.direction_gradient``, scalar form), from the vectors of
    ``cable_axis`` (any frame: they are built from vectors only)::

        dL_TE/dB = -u + arm ((u + u_C) . beta) eps
        du/dB = -[(I - u u^T) - swivel e_perp e_perp^T - arm v eps^T] / |l_E|,  v = beta - (u . beta) u

    Parameters
    ----------
    ux, uy, uz, lE, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb
        As returned by ``cable_axis`` (after L and inside) [-] or [m].

    Returns
    -------
    tuple
        (dL_TE/dB x, y, z [-]; du/dB row-major, du_a/dB_b, 9 values [1/m]).

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (12).
    """
    ub = ux * btx + uy * bty + uz * btz
    q = arm * (ub + uCb)
    i_n = 1.0 / lE
    vx, vy, vz = btx - ub * ux, bty - ub * uy, btz - ub * uz
    # -M / |l_E|, M = (I - u u^T) - sw e_perp e_perp^T - arm v eps^T
    d00 = (1.0 - ux * ux - sw * epx * epx - arm * vx * ex) * -i_n
    d01 = (-ux * uy - sw * epx * epy - arm * vx * ey) * -i_n
    d02 = (-ux * uz - sw * epx * epz - arm * vx * ez) * -i_n
    d10 = (-uy * ux - sw * epy * epx - arm * vy * ex) * -i_n
    d11 = (1.0 - uy * uy - sw * epy * epy - arm * vy * ey) * -i_n
    d12 = (-uy * uz - sw * epy * epz - arm * vy * ez) * -i_n
    d20 = (-uz * ux - sw * epz * epx - arm * vz * ex) * -i_n
    d21 = (-uz * uy - sw * epz * epy - arm * vz * ey) * -i_n
    d22 = (1.0 - uz * uz - sw * epz * epz - arm * vz * ez) * -i_n
    return (-ux + q * ex, -uy + q * ey, -uz + q * ez, d00, d01, d02, d10, d11, d12, d20, d21, d22)


@njit(cache=True, inline="always")
def cable_params(cab, c):
    """The scalars ``cable`` takes after P for cable c of the ``Cables`` record ``cab``: (Ax, Ay, Az
    [m], kind, h, rp, d [m], inx, iny [-]) for ``cable_of``. Hoisted out of a solver's loop, they
    are read once per solve."""
    return (
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


@njit(cache=True, inline="always", error_model="numpy")
def cable_of(px, py, pz, cp):
    """``cable`` at P = (px, py, pz) [m] for the cable whose parameters are ``cp = cable_params(cab, c)``."""
    return cable(px, py, pz, cp[0], cp[1], cp[2], cp[3], cp[4], cp[5], cp[6], cp[7], cp[8])


@njit(cache=True, error_model="numpy")
def cable_partials(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny, out):
    """One cable at P and its partial derivatives (scalar form of ``sensitivity.cable_partials``),
    from the same ``pulley_geometry``::

        dL_TE/dP = -u + arm ((u + u_C) . beta) eps
        du/dP = -[(I - u u^T) - swivel e_perp e_perp^T - arm v eps^T] / |l_E|,  v = beta - (u . beta) u
        dL_TE/dh = (u + u_C) . b,      du/dh = (I - u u^T) b / |l_E|
        dL_TE/dr_p = gamma,            du/dr_p = n_D / |l_E|
        dL_TE/dd = u_C . z

    with b the arm direction (SR and fixed: e_s; DR: the bisector), u_C the unit vector from the
    winch exit C toward K, n_D the sheave's outward normal at D.

    Parameters
    ----------
    px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny
        As ``pulley_geometry``.
    out : ndarray, shape (NCOL,)
        Written with the layout ``C_*``: L_TE [m], u [-], |l_E| [m], dL_TE/dP [-], du/dP [1/m],
        dL_TE/dh [-], du/dh [1/m], dL_TE/dr_p [rad], du/dr_p [1/m], dL_TE/dd [-], inside (1.0 / 0.0).

    References
    ----------
    Paty et al. 2021, eq. (3)-(5).
    """
    g = pulley_geometry(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny)
    esx, esy, bhs, bhw, ens, enw, n = g.esx, g.esy, g.bhs, g.bhw, g.ens, g.enw, g.n
    arm, cD, sD = g.arm, g.cD, g.sD
    sw = g.Ds / g.rho if g.rho > SWIVEL_RHO_MIN else 0.0
    ldd = g.ld if g.ld > 0.0 else 1.0
    ucs, ucw = (g.Hs + rp * g.cK) / ldd, (g.Hw + rp * g.sK + d) / ldd  # u_C in the plane (C toward K)
    uCb = ucs * -bhw + ucw * bhs
    i_n = 1.0 / n
    ux, uy, uz = g.vx * i_n, g.vy * i_n, g.vz * i_n
    btx, bty, btz = -bhw * esx, -bhw * esy, bhs  # beta, the arm's normal (DR)
    epx, epy, epz = ens * esx, ens * esy, enw  # eps, the strand's normal (DR)
    ub = ux * btx + uy * bty + uz * btz
    q = arm * (ub + uCb)
    out[C_L] = g.L
    out[C_U], out[C_U + 1], out[C_U + 2] = ux, uy, uz
    out[C_LE] = n
    out[C_DLDP], out[C_DLDP + 1], out[C_DLDP + 2] = -ux + q * epx, -uy + q * epy, -uz + q * epz
    # du/dP = -[(I - u u^T) - sw e_perp e_perp^T - arm v eps^T] / |l_E|, v = beta - (u . beta) u
    vx_, vy_, vz_ = btx - ub * ux, bty - ub * uy, btz - ub * uz
    u3 = (ux, uy, uz)
    pe = (-esy, esx, 0.0)
    v3 = (vx_, vy_, vz_)
    e3 = (epx, epy, epz)
    for a in range(3):
        for b in range(3):
            m_ab = (1.0 if a == b else 0.0) - u3[a] * u3[b] - sw * pe[a] * pe[b] - arm * v3[a] * e3[b]
            out[C_DUDP + 3 * a + b] = -m_ab * i_n
    # arm direction b: DR the bisector, else e_s; u_C in 3D
    if kind == 2:
        bx_, by_, bz_ = bhs * esx, bhs * esy, bhw
    else:
        bx_, by_, bz_ = esx, esy, 0.0
    ucx, ucy, ucz = ucs * esx, ucs * esy, ucw
    ubb = ux * bx_ + uy * by_ + uz * bz_
    out[C_DLH] = (ux + ucx) * bx_ + (uy + ucy) * by_ + (uz + ucz) * bz_
    out[C_DUH], out[C_DUH + 1], out[C_DUH + 2] = (
        (bx_ - ubb * ux) * i_n,
        (by_ - ubb * uy) * i_n,
        (bz_ - ubb * uz) * i_n,
    )
    out[C_DLR] = g.gamma
    out[C_DUR], out[C_DUR + 1], out[C_DUR + 2] = cD * esx * i_n, cD * esy * i_n, sD * i_n
    out[C_DLD] = ucw
    out[C_INSIDE] = 1.0 if g.inside else 0.0


@njit(cache=True, inline="always", error_model="numpy")
def cable_partials_at(px, py, pz, cab, c, out):
    """``cable_partials`` for cable c of the ``Cables`` record ``cab`` at P, into ``out`` (NCOL,)."""
    cable_partials(
        px,
        py,
        pz,
        cab.A[c, 0],
        cab.A[c, 1],
        cab.A[c, 2],
        cab.kind[c],
        cab.h[c],
        cab.rp[c],
        cab.d[c],
        cab.inward[c, 0],
        cab.inward[c, 1],
        out,
    )


@njit(cache=True, error_model="numpy")
def cable_partials_axis(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny, ident, f, out):
    """``cable_partials`` for a pulley whose swivel axis k_i is any unit vector (the frame rule of
    ``cable_axis``): the same scalar kernel at w' = F (B - A), A' = 0, and the vectors back to the
    base frame::

        u = F^T u',  dL_TE/dB = F^T dL'/dB',  du/dB = F^T (du'/dB') F,
        du/dh = F^T du'/dh,  du/dr_p = F^T du'/dr_p

    (L_TE, |l_E|, dL_TE/dh, dL_TE/dr_p, dL_TE/dd are invariant). With ``ident`` bit for bit
    ``cable_partials`` at B and A.

    Parameters
    ----------
    px, py, pz : float [m]
        The attachment point B_i (base frame).
    Ax, Ay, Az, kind, h, rp, d, inx, iny
        As ``pulley_geometry`` (A in the base frame, inward in the pulley frame).
    ident : bool
        F is the identity.
    f : ndarray (3, 3) [-]
        The pulley frame, rows i_i, j_i, k_i.
    out : ndarray, shape (NCOL,)
        Written with the layout ``C_*`` (``cable_partials``), vectors in the base frame.

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (12).
    """
    qx, qy, qz, ax, ay, az = in_frame(px, py, pz, Ax, Ay, Az, ident, f)
    cable_partials(qx, qy, qz, ax, ay, az, kind, h, rp, d, inx, iny, out)
    if ident:
        return
    for c0 in (C_U, C_DLDP, C_DUH, C_DUR):
        v0, v1, v2 = out[c0], out[c0 + 1], out[c0 + 2]
        for a in range(3):
            out[c0 + a] = f[0, a] * v0 + f[1, a] * v1 + f[2, a] * v2
    o = C_DUDP
    dp = (
        out[o],
        out[o + 1],
        out[o + 2],
        out[o + 3],
        out[o + 4],
        out[o + 5],
        out[o + 6],
        out[o + 7],
        out[o + 8],
    )
    for a in range(3):  # du/dB = F^T (du'/dB') F
        for b in range(3):
            s = 0.0
            for k in range(3):
                for q in range(3):
                    s += f[k, a] * dp[3 * k + q] * f[q, b]
            out[o + 3 * a + b] = s


@njit(cache=True, inline="always", error_model="numpy")
def sheave(
    Px, Py, Pz, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12, F20, F21, F22, kind, h, rp, d, inx, iny
):
    """The massless pulley geometry of one cable at the point P (``pulley_geometry`` in the
    pulley frame F, ``ident``: the identity) and its plane's horizontal unit vector e_s in the base
    frame: (geometry, e_s (3) [-])."""
    if ident:
        qx, qy, qz, ax, ay, az = Px, Py, Pz, Ax, Ay, Az
    else:
        wx, wy, wz = Px - Ax, Py - Ay, Pz - Az
        qx, qy, qz = (
            F00 * wx + F01 * wy + F02 * wz,
            F10 * wx + F11 * wy + F12 * wz,
            F20 * wx + F21 * wy + F22 * wz,
        )
        ax = ay = az = 0.0
    g = pulley_geometry(qx, qy, qz, ax, ay, az, kind, h, rp, d, inx, iny)
    if ident:
        return g, g.esx, g.esy, 0.0
    return g, g.esx * F00 + g.esy * F10, g.esx * F01 + g.esy * F11, g.esx * F02 + g.esy * F12


@njit(cache=True, error_model="numpy")
def entry_angle(kind, h, rp, d):
    """The angle [rad] on the sheave (in its plane, from e_s toward the axis) of the entry point K,
    where the cable from the winch exit C = (0, -d) meets the sheave of centre (h, 0): the massless
    pulley geometry's (``pulley_geometry``, whose arithmetic this is) atan2(sin, cos) of
    theta_K, the same wherever the platform is for a fixed or SR pulley (a DR arm moves the centre);
    0 without a sheave (r_p = 0)."""
    if not rp > 0.0:
        return 0.0
    g = pulley_geometry(1.0, 0.0, -1.0, 0.0, 0.0, 0.0, kind, h, rp, d, 1.0, 0.0)
    return math.atan2(g.sK, g.cK)


@njit(cache=True, inline="always", error_model="numpy")
def mod_two_pi(x):
    """x % (2 pi), Python's modulo into [0, 2 pi), without the library's fmod where x lies within a
    turn of that range (an angle on the sheave moved by a step): the same floating-point result,
    fmod being exact there (a zero goes to ``%``, whose signed zero is +0)."""
    if 0.0 < x < TWO_PI:
        return x
    if -TWO_PI < x < 0.0:
        return x + TWO_PI
    return x % TWO_PI
