"""Compiled physical equilibrium, the pose kernel: ``models.equilibrium.solve`` with its Newton iteration as a
numba kernel that runs in parallel over poses (chunks of ``CHUNK``), scalars and 3 x 3 / 6 x 6
scratch arrays in the hot loop, one cable at a time through the shared kernel
(``_kernels.cable_axis``: the scalar ``cable`` in each pulley's frame).

Same equations, Jacobian (``models.cables._jacobian``), energy, least-squares step (a 6 x 6
pseudo-inverse with the reference's ``RCOND`` cut, by a one-sided Jacobi SVD), modified-Newton
fallback (``SHIFT_REL``), line search, stop rules and constants as the numpy reference; the pose
set-up, the restarts (``_needs_restart``, the candidates' selection, ``unique``, ``alternatives``)
and the result are the reference's own functions (``models.equilibrium.solve_with``), run round the
compiled Newton. A test checks that both give the same statuses, taut sets, ``unique``, poses
(1e-9 m, 1e-9 rad).

An external wrench on a rigid platform (``Platform.wrench``: a constant world-frame force fe at p and
moment me about p; ``Body.wrench``) enters as in the reference (``models.cables.Cables``): F += fe,
M += me, the merit gains -fe . (p - p_d) and its gradient -(fe, me) (``_linalg.add_wrench``, after
each evaluation, massless or heavy), the Jacobian is unchanged, and the line search's test adds the
moment's work me . (alpha s_phi) along each trial step while the merit kept leaves it out
(``_linalg.moment_work``). A point mass's force is in its weight (``Platform.w_ext``).

``solve_points`` and ``solve_points_batch`` are the fast path of a suspended point mass (a 3-DoF
kernel, ``_point_mass``), which ``cdpr.solve`` chooses for such robots; they return the point-mass
keys (``results.physical_result``).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 2-5, 10-14).

Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer, ch. 3.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from cdpr.compiled._kernels import (
    CHUNK,
    cable_arrays,
    cable_axis,
    cable_derivatives,
    newton_options,
    pulley_frames,
    set_threads,
)
from cdpr.compiled._kernels import Cables as CableArrays
from cdpr.compiled._linalg import (
    add_cable_jacobian,
    add_gravity,
    add_wrench,
    lu_solve,
    moment_work,
    pinv_solve,
    positive_definite,
    rodrigues,
    rotvec_of_matrix,
    solve3,
)
from cdpr.compiled._point_mass import solve as solve_points  # noqa: F401  (the fast path, cdpr.solve)
from cdpr.compiled._point_mass import solve_batch as solve_points_batch  # noqa: F401
from cdpr.compiled.cables import NSTATE, STATE, Heavy, heavy_arrays, heavy_cables
from cdpr.compiled.cables import evaluate as evaluate_heavy
from cdpr.models.equilibrium import (
    ARMIJO_C,
    LS_SKIP,
    MAX_HALVINGS,
    PHYSICAL_DEFAULTS,
    RCOND,
    SHIFT_REL,
    Cables,
    HeavyCables,
    finish,
    set_up,
    solve_with,
    stop_rules,
)
from cdpr.models.results import TAUT_MIN

READY = STATE["ready"]


class Body(NamedTuple):
    """The platform and pulley frames for the 6-DoF kernel (``body_arrays``): b (m, 3) [m]
    attachments in the platform frame; frame (m, 3, 3) [-] pulley frames (rows i, j, k); ident (m,)
    bool (frame is the identity); com (3,) [m]; f (3,) [N] gravity force; wrench (6,) [N, N m] a
    rigid platform's external wrench (fe at p, me about p, world frame; ``Cables.fe``, ``Cables.me``;
    zeros on a point mass, whose force is in f); ftol [N]; size [m] the platform's size l; ztop [m]
    the lowest joint height; rigid, suspended (``Cables``)."""

    b: np.ndarray
    frame: np.ndarray
    ident: np.ndarray
    com: np.ndarray
    f: np.ndarray
    wrench: np.ndarray
    ftol: float
    size: float
    ztop: float
    rigid: bool
    suspended: bool


class Out(NamedTuple):
    """Per-pose results of the kernel (``outputs``): P (N, 3) [m], R (N, 3, 3), F, M (N, 3) [N, N m],
    t (N, m) [N], merit (N,) [J], J (N, 6, 6), it (N,), conv (N,) bool, inside (N, m) bool, gamma
    (N, m) [rad] the pulleys' state at P, R (``pulleys.pulley_state``), stable (N,) bool: converged
    with 6 or more taut cables and a positive definite -J (``STABLE_REL``), rotvec (N, 3) [rad] of R;
    cat (N, m, ``cables.NSTATE``) heavy cables' state at the result (``cables.STATE``; (0, m, ...)
    for massless cables)."""

    P: np.ndarray
    R: np.ndarray
    F: np.ndarray
    M: np.ndarray
    t: np.ndarray
    merit: np.ndarray
    J: np.ndarray
    it: np.ndarray
    conv: np.ndarray
    inside: np.ndarray
    gamma: np.ndarray
    stable: np.ndarray
    rotvec: np.ndarray
    cat: np.ndarray


def body_arrays(cab):
    """The ``Body`` record of a ``Cables`` (the reference's evaluation record)."""
    a = cab.robot.arrays
    frame, ident = pulley_frames(cab.robot)
    if cab.suspended:  # the reference takes the identity frame (models.equilibrium._args)
        frame = np.ascontiguousarray(np.broadcast_to(np.eye(3), frame.shape))
        ident[:] = True
    return Body(
        np.ascontiguousarray(a.b, dtype=float),
        frame,
        ident,
        np.ascontiguousarray(a.com, dtype=float),
        np.ascontiguousarray(cab.f, dtype=float),
        np.ascontiguousarray(np.concatenate([cab.fe, cab.me]), dtype=float),
        float(cab.ftol),
        float(cab.size),
        float(cab.z_top),
        bool(cab.rigid),
        bool(cab.suspended),
    )


def outputs(n, m, heavy=False):
    """An uninitialised ``Out`` for n poses and m cables (``heavy``: with the cables' state)."""
    return Out(
        np.empty((n, 3)),
        np.empty((n, 3, 3)),
        np.empty((n, 3)),
        np.empty((n, 3)),
        np.empty((n, m)),
        np.empty(n),
        np.empty((n, 6, 6)),
        np.empty(n, dtype=np.int32),
        np.empty(n, dtype=np.bool_),
        np.empty((n, m), dtype=np.bool_),
        np.empty((n, m)),
        np.empty(n, dtype=np.bool_),
        np.empty((n, 3)),
        np.zeros((n if heavy else 0, m, NSTATE)),
    )


class _Scratch(NamedTuple):
    """Per-chunk work arrays of ``solve_pose`` (allocated once per chunk)."""

    t: np.ndarray  # (m,) tensions of the current pose
    tt: np.ndarray  # (m,) tensions of the trial pose
    J: np.ndarray  # (6, 6) current Jacobian
    Jt: np.ndarray  # (6, 6) trial Jacobian
    e6: np.ndarray  # (14,) current F (3), M (3), Fn (6), merit, kappa... see evaluate
    et: np.ndarray  # (14,) trial
    g6: np.ndarray  # (8,) current grad (6), kappa (2)
    gt: np.ndarray  # (8,) trial
    R: np.ndarray  # (3, 3) current orientation
    Rt: np.ndarray  # (3, 3) trial orientation
    Q: np.ndarray  # (3, 3) step rotation
    cab_u: np.ndarray  # (m, 3) per-cable u (for the all-slack Jacobian)
    cab_dL: np.ndarray  # (m, 3)
    cab_r: np.ndarray  # (m, 3)
    cab_k: np.ndarray  # (m,)
    cab_inside: np.ndarray  # (m,) bool: the pulleys' state at the last evaluated pose (the result's
    cab_gamma: np.ndarray  # (m,) [rad]   inside and gamma: a solve ends on its last evaluation)
    A6: np.ndarray  # (6, 6) SVD / eigen work
    V6: np.ndarray  # (6, 6)
    s6: np.ndarray  # (6,) step
    w6: np.ndarray  # (6,) work
    fb: np.ndarray  # (6,) fallback step
    piv: np.ndarray  # (6,) int64 LU pivots
    hc: np.ndarray  # (m, NSTATE) heavy cables: the state of the current pose (``cables.STATE``)
    ht: np.ndarray  # (m, NSTATE) heavy cables: the state of the trial pose
    hg: np.ndarray  # (3, 3) heavy cables: one cable's dF/dB


@njit(cache=True)
def scratch(m):
    return _Scratch(
        np.empty(m),
        np.empty(m),
        np.empty((6, 6)),
        np.empty((6, 6)),
        np.empty(14),
        np.empty(14),
        np.empty(8),
        np.empty(8),
        np.empty((3, 3)),
        np.empty((3, 3)),
        np.empty((3, 3)),
        np.empty((m, 3)),
        np.empty((m, 3)),
        np.empty((m, 3)),
        np.empty(m),
        np.empty(m, dtype=np.bool_),
        np.empty(m),
        np.empty((6, 6)),
        np.empty((6, 6)),
        np.empty(6),
        np.empty(6),
        np.empty(6),
        np.empty(6, dtype=np.int64),
        np.zeros((m, NSTATE)),
        np.zeros((m, NSTATE)),
        np.empty((3, 3)),
    )


@njit(cache=True, error_model="numpy")
def evaluate(px, py, pz, R, rfx, rfy, rfz, cab, body, L0, i, t, J, e6, g6, w):
    """``models.cables.Cables.evaluate`` at one pose (p, R) with rest lengths L0[i], merit relative
    to p_ref = (rfx, rfy, rfz): writes the tensions t (m,), J (6, 6), e6 = (F (3), M (3), Fn (6),
    merit, inside), g6 = (grad (6), kappa (2)); ``w`` the scratch record."""
    A, kind, h, rp, d, inward, ES = cab.A, cab.kind, cab.h, cab.rp, cab.d, cab.inward, cab.ES
    b, frame, ident, f = body.b, body.frame, body.ident, body.f
    m = A.shape[0]
    fx, fy, fz = f[0], f[1], f[2]
    rcx = R[0, 0] * body.com[0] + R[0, 1] * body.com[1] + R[0, 2] * body.com[2]
    rcy = R[1, 0] * body.com[0] + R[1, 1] * body.com[1] + R[1, 2] * body.com[2]
    rcz = R[2, 0] * body.com[0] + R[2, 1] * body.com[1] + R[2, 2] * body.com[2]
    Fx, Fy, Fz = 0.0, 0.0, 0.0
    Mx, My, Mz = 0.0, 0.0, 0.0
    Ex = Ey = Ez = Emx = Emy = Emz = 0.0  # sum k e u, sum k e (r x u): Hooke extended to compression
    gx = gy = gz = gmx = gmy = gmz = 0.0
    elastic = 0.0
    kact0 = kact1 = kall0 = kall1 = geo0 = geo1 = 0.0
    nact = 0
    inside = False
    for a in range(6):
        for c in range(6):
            J[a, c] = 0.0
    for c in range(m):
        rx = R[0, 0] * b[c, 0] + R[0, 1] * b[c, 1] + R[0, 2] * b[c, 2]
        ry = R[1, 0] * b[c, 0] + R[1, 1] * b[c, 1] + R[1, 2] * b[c, 2]
        rz = R[2, 0] * b[c, 0] + R[2, 1] * b[c, 1] + R[2, 2] * b[c, 2]
        (L, ux, uy, uz, lE, ins, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb, gam) = cable_axis(
            px + rx,
            py + ry,
            pz + rz,
            A[c, 0],
            A[c, 1],
            A[c, 2],
            kind[c],
            h[c],
            rp[c],
            d[c],
            inward[c, 0],
            inward[c, 1],
            ident[c],
            frame[c],
        )
        inside = inside or ins
        L0c = L0[i, c]
        e = L - L0c
        k = ES[c] / L0c
        tc = k * e if e > 0.0 else 0.0
        t[c] = tc
        mux, muy, muz = ry * uz - rz * uy, rz * ux - rx * uz, rx * uy - ry * ux  # r x u
        Fx += tc * ux
        Fy += tc * uy
        Fz += tc * uz
        Mx += tc * mux
        My += tc * muy
        Mz += tc * muz
        ke = k * e
        Ex += ke * ux
        Ey += ke * uy
        Ez += ke * uz
        Emx += ke * mux
        Emy += ke * muy
        Emz += ke * muz
        if e > 0.0:
            elastic += 0.5 * k * e * e
        (dLx, dLy, dLz, d00, d01, d02, d10, d11, d12, d20, d21, d22) = cable_derivatives(
            ux, uy, uz, lE, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb
        )
        gx += tc * dLx
        gy += tc * dLy
        gz += tc * dLz
        gmx += tc * (ry * dLz - rz * dLy)
        gmy += tc * (rz * dLx - rx * dLz)
        gmz += tc * (rx * dLy - ry * dLx)
        rr = rx * rx + ry * ry + rz * rz
        geo0 += tc / lE
        geo1 += tc / lE * rr + tc * math.sqrt(rr)
        kall0 += k
        kall1 += k * rr
        act = e >= 0.0
        ka = k if act else 0.0
        if act:
            nact += 1
            kact0 += k
            kact1 += k * rr
        kx, ky, kz = ka * ux, ka * uy, ka * uz
        add_cable_jacobian(
            J,
            tc * d00 + kx * dLx,
            tc * d01 + kx * dLy,
            tc * d02 + kx * dLz,
            tc * d10 + ky * dLx,
            tc * d11 + ky * dLy,
            tc * d12 + ky * dLz,
            tc * d20 + kz * dLx,
            tc * d21 + kz * dLy,
            tc * d22 + kz * dLz,
            rx,
            ry,
            rz,
            tc,
            ux,
            uy,
            uz,
        )
        w.cab_u[c, 0], w.cab_u[c, 1], w.cab_u[c, 2] = ux, uy, uz
        w.cab_dL[c, 0], w.cab_dL[c, 1], w.cab_dL[c, 2] = dLx, dLy, dLz
        w.cab_r[c, 0], w.cab_r[c, 1], w.cab_r[c, 2] = rx, ry, rz
        w.cab_k[c] = k
        w.cab_inside[c] = ins
        w.cab_gamma[c] = gam
    Fx, Fy, Fz, Mx, My, Mz, cfx, cfy, cfz = add_gravity(J, Fx, Fy, Fz, Mx, My, Mz, fx, fy, fz, rcx, rcy, rcz)
    if nact == 0:  # no cable taut: Hooke extended to compression (ka = k on every cable)
        for c in range(m):
            k = w.cab_k[c]
            kx, ky, kz = k * w.cab_u[c, 0], k * w.cab_u[c, 1], k * w.cab_u[c, 2]
            lx, ly, lz = w.cab_dL[c, 0], w.cab_dL[c, 1], w.cab_dL[c, 2]
            add_cable_jacobian(
                J,
                kx * lx,
                kx * ly,
                kx * lz,
                ky * lx,
                ky * ly,
                ky * lz,
                kz * lx,
                kz * ly,
                kz * lz,
                w.cab_r[c, 0],
                w.cab_r[c, 1],
                w.cab_r[c, 2],
                0.0,
                0.0,
                0.0,
                0.0,
            )
        e6[6], e6[7], e6[8] = Fx + Ex, Fy + Ey, Fz + Ez
        e6[9], e6[10], e6[11] = Mx + Emx, My + Emy, Mz + Emz
        ka0, ka1 = kall0, kall1
    else:
        e6[6], e6[7], e6[8], e6[9], e6[10], e6[11] = Fx, Fy, Fz, Mx, My, Mz
        ka0, ka1 = kact0, kact1
    e6[0], e6[1], e6[2], e6[3], e6[4], e6[5] = Fx, Fy, Fz, Mx, My, Mz
    merit = -((px - rfx + rcx) * fx + (py - rfy + rcy) * fy + (pz - rfz + rcz) * fz) + elastic
    if body.suspended and not pz < body.ztop:
        merit = np.inf
    e6[12] = merit
    e6[13] = 1.0 if inside else 0.0
    g6[0], g6[1], g6[2] = gx - fx, gy - fy, gz - fz
    g6[3], g6[4], g6[5] = gmx - cfx, gmy - cfy, gmz - cfz
    g6[6] = ka0 + geo0
    g6[7] = (
        ka1 * 1.0
        + geo1
        + math.sqrt(fx * fx + fy * fy + fz * fz) * math.sqrt(rcx * rcx + rcy * rcy + rcz * rcz)
    )
    # kappa_1 = sum (ka + t/lE) rr + t |r| + |f| |rc|; ka1 = sum ka rr, geo1 = sum (t/lE rr + t |r|)


@njit(cache=True, error_model="numpy")
def modified_newton(J, grad, ell, fallback, x):
    """``models.equilibrium._modified_newton`` at one pose: x = -(H + mu I)^-1 grad in scaled coordinates
    (D = (1, 1, 1, l, l, l), H the symmetric part of -J / D D^T, mu = max(0, -lambda_min) +
    ``SHIFT_REL`` max |lambda|), or ``fallback`` where H or grad is not finite.

    .. math:: x = -D^{-1} (H + \\mu I)^{-1} D^{-1} \\nabla V

    Parameters
    ----------
    J : ndarray (6, 6)
        d(F, M)/d(dp, dphi) [N/m, N, N m].
    grad : ndarray (6,)
        Energy gradient [N, N m].
    ell : float [m]
        The platform's size l.
    fallback : ndarray (6,)
        The scaled gradient step [m, rad].
    x : ndarray (6,)
        Written with the step [m, rad].

    References
    ----------
    Nocedal, J., Wright, S. J. (2006). Numerical Optimization, 2nd ed., Springer, section 3.4.
    """
    D = (1.0, 1.0, 1.0, ell, ell, ell)
    H = np.empty((6, 6))
    g = np.empty(6)
    ok = True
    for a in range(6):
        g[a] = grad[a] / D[a]
        ok = ok and math.isfinite(g[a])
        for c in range(6):
            H[a, c] = -0.5 * (J[a, c] + J[c, a]) / D[a] / D[c]
            ok = ok and math.isfinite(H[a, c])
    if not ok:
        for a in range(6):
            x[a] = fallback[a]
        return
    lam, V = np.linalg.eigh(H)
    top = 0.0
    for a in range(6):
        top = max(top, abs(lam[a]))
    mu = max(0.0, -lam[0]) + SHIFT_REL * (top if top > 0 else 1.0)
    for a in range(6):
        x[a] = 0.0
    for c in range(6):
        coef = 0.0
        for a in range(6):
            coef += V[a, c] * g[a]
        coef /= lam[c] + mu
        for a in range(6):
            x[a] += V[a, c] * coef
    for a in range(6):
        x[a] = -x[a] / D[a]


@njit(cache=True, error_model="numpy")
def solve_pose(i, p_ref, P0, R0, L0, cab, body, opts, out, w, heavy):
    """``models.equilibrium._newton`` for pose i: p_ref (N, 3) [m] the desired positions (the energy's
    origin), P0 (N, 3) [m] and R0 (N, 3, 3) the start, L0 (N, m) [m] the rest lengths, cab
    ``_kernels.Cables``, body ``Body``, opts ``Newton``; writes row i of out (``Out``); w the scratch;
    heavy a ``cables.Heavy`` record (``heavy.on``: the heavy cables' ``cables.evaluate``, each
    evaluation started from the cables' state at the current pose, reset at the start of the pose)."""
    tol, maxiter, max_step = opts.tol, opts.maxiter, opts.max_step
    m = cab.A.shape[0]
    rigid = body.rigid
    ell = body.size if rigid else 0.0
    ftol2, mtol2 = body.ftol * body.ftol, (body.ftol * body.size) ** 2
    moment = rigid and (body.wrench[3] != 0.0 or body.wrench[4] != 0.0 or body.wrench[5] != 0.0)
    rfx, rfy, rfz = p_ref[i, 0], p_ref[i, 1], p_ref[i, 2]
    px, py, pz = P0[i, 0], P0[i, 1], P0[i, 2]
    R, Rt, Q, s, x = w.R, w.Rt, w.Q, w.s6, w.w6
    for a in range(3):
        for c in range(3):
            R[a, c] = R0[i, a, c]
    t, J, e6, g6 = w.t, w.J, w.e6, w.g6
    if heavy.on:
        for c in range(m):
            w.hc[c, READY] = 0.0
        evaluate_heavy(
            px, py, pz, R, rfx, rfy, rfz, cab, body, heavy, L0, i, t, J, e6, g6, w.hg, w.cab_inside, w.cab_gamma,
            w.hc, w.hc, False,
        )  # fmt: skip
    else:
        evaluate(px, py, pz, R, rfx, rfy, rfz, cab, body, L0, i, t, J, e6, g6, w)
    add_wrench(e6, g6, px, py, pz, rfx, rfy, rfz, body.wrench)
    conv = False
    it = 0
    prev = 0.0
    prev_full = False
    fb = w.fb
    for _ in range(maxiter):
        if e6[0] ** 2 + e6[1] ** 2 + e6[2] ** 2 <= ftol2 and e6[3] ** 2 + e6[4] ** 2 + e6[5] ** 2 <= mtol2:
            conv = True
            break
        # the Newton step J s = -Fn: 3 x 3 (point mass) or least squares 6 x 6
        finite = True
        for a in range(6):
            for c in range(6):
                finite = finite and math.isfinite(J[a, c])
        if not rigid:
            solve3(J, e6[6], e6[7], e6[8], s)
            s[3] = s[4] = s[5] = 0.0
        elif finite:
            for a in range(6):
                x[a] = -e6[6 + a]
            if not lu_solve(J, x, w.A6, w.V6, w.piv, s, RCOND):
                pinv_solve(J, x, w.A6, w.V6, s, RCOND)
        else:
            for a in range(6):
                s[a] = np.nan
        newton = True
        for a in range(6):
            newton = newton and math.isfinite(s[a])
        if not newton:
            for a in range(6):
                s[a] = 0.0
        norm = math.sqrt(s[0] ** 2 + s[1] ** 2 + s[2] ** 2 + ell * ell * (s[3] ** 2 + s[4] ** 2 + s[5] ** 2))
        slope = 0.0
        for a in range(6):
            slope += g6[a] * s[a]
        newton = newton and (slope < 0.0 or norm <= LS_SKIP)
        if not newton:
            kp = g6[6] if g6[6] > 0 else 1.0
            kr = g6[7] if g6[7] > 0 else 1.0
            for a in range(3):
                fb[a] = -g6[a] / kp
                fb[3 + a] = -g6[3 + a] / kr * (1.0 if rigid else 0.0)
            if rigid:
                modified_newton(J, g6, body.size, fb, s)
            else:
                for a in range(6):
                    s[a] = fb[a]
        slope = 0.0
        for a in range(6):
            slope += g6[a] * s[a]
        norm = math.sqrt(s[0] ** 2 + s[1] ** 2 + s[2] ** 2 + ell * ell * (s[3] ** 2 + s[4] ** 2 + s[5] ** 2))
        done = newton and (norm < tol or (prev_full and norm * norm < tol * prev))
        scale = 1.0 if done else min(1.0, max_step / max(norm, 1e-300))
        for a in range(6):
            s[a] *= scale
        slope *= scale
        whole = done or norm * scale <= LS_SKIP
        # heavy cables: the exact Jacobian at the trial of a whole step (near the answer, where the
        # approximate one would make Newton's convergence linear), the cheaper one before
        alpha = 1.0
        merit = e6[12]
        for hv in range(MAX_HALVINGS + 1):
            qx, qy, qz = px + alpha * s[0], py + alpha * s[1], pz + alpha * s[2]
            if rigid:
                rodrigues(alpha * s[3], alpha * s[4], alpha * s[5], Q)
                for a in range(3):
                    for c in range(3):
                        Rt[a, c] = Q[a, 0] * R[0, c] + Q[a, 1] * R[1, c] + Q[a, 2] * R[2, c]
            else:
                for a in range(3):
                    for c in range(3):
                        Rt[a, c] = R[a, c]
            if heavy.on:
                evaluate_heavy(
                    qx,
                    qy,
                    qz,
                    Rt,
                    rfx,
                    rfy,
                    rfz,
                    cab,
                    body,
                    heavy,
                    L0,
                    i,
                    w.tt,
                    w.Jt,
                    w.et,
                    w.gt,
                    w.hg,
                    w.cab_inside,
                    w.cab_gamma,
                    w.hc,
                    w.ht,
                    whole,
                )
            else:
                evaluate(qx, qy, qz, Rt, rfx, rfy, rfz, cab, body, L0, i, w.tt, w.Jt, w.et, w.gt, w)
            add_wrench(w.et, w.gt, qx, qy, qz, rfx, rfy, rfz, body.wrench)
            # an external moment's work along the trial step (``models.equilibrium._newton``): the
            # test's merit adds it, the merit kept is the potential
            trial = w.et[12]
            if moment:
                trial -= moment_work(alpha * s[3], alpha * s[4], alpha * s[5], body.wrench)
            if whole or trial <= merit + ARMIJO_C * alpha * slope or hv == MAX_HALVINGS:
                px, py, pz = qx, qy, qz
                for a in range(3):
                    for c in range(3):
                        R[a, c] = Rt[a, c]
                for c in range(m):
                    t[c] = w.tt[c]
                for a in range(6):
                    for c in range(6):
                        J[a, c] = w.Jt[a, c]
                for a in range(14):
                    e6[a] = w.et[a]
                for a in range(8):
                    g6[a] = w.gt[a]
                if heavy.on:
                    for c in range(m):
                        for a in range(NSTATE):
                            w.hc[c, a] = w.ht[c, a]
                break
            alpha *= 0.5
        it += 1
        prev = alpha * norm * scale
        prev_full = newton and alpha == 1.0 and scale == 1.0
        if done:
            conv = True
            break
    out.P[i, 0], out.P[i, 1], out.P[i, 2] = px, py, pz
    for a in range(3):
        out.F[i, a] = e6[a]
        out.M[i, a] = e6[3 + a]
        for c in range(3):
            out.R[i, a, c] = R[a, c]
    for c in range(m):
        out.t[i, c] = t[c]
    for a in range(6):
        for c in range(6):
            out.J[i, a, c] = J[a, c]
    out.merit[i] = e6[12]
    out.it[i] = it
    out.conv[i] = conv
    n_taut = 0
    for c in range(m):
        n_taut += t[c] > TAUT_MIN
    out.stable[i] = rigid and conv and n_taut >= 6 and positive_definite(J, w.A6)
    for c in range(m):  # the pulleys' state at the result: the last evaluation was at (p, R)
        out.inside[i, c] = w.cab_inside[c]
        out.gamma[i, c] = w.cab_gamma[c]
    rotvec_of_matrix(R, out.rotvec[i])
    if heavy.on:  # the cables' state at the result (``cables.heavy_cables`` starts from it)
        for c in range(m):
            for a in range(NSTATE):
                out.cat[i, c, a] = w.hc[c, a]


@njit(cache=True, parallel=True, error_model="numpy")
def _solve_poses(p_ref, P0, R0, L0, cab, body, opts, out, heavy):
    n = p_ref.shape[0]
    m = cab.A.shape[0]
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        w = scratch(m)
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            solve_pose(i, p_ref, P0, R0, L0, cab, body, opts, out, w, heavy)


class CompiledCables(Cables):
    """The reference's evaluation record (``models.cables.Cables``: the robot, its load and
    tolerances, read by the restarts and the result) with the kernel's ``CableArrays`` (``_kernels.Cables``) and ``Body``."""

    def __init__(self, robot):
        super().__init__(robot)
        self.cables = cable_arrays(robot)
        self.body = body_arrays(self)
        self.heavy = heavy_arrays(None, robot.m)


class CompiledHeavyCables(HeavyCables):
    """The reference's heavy-cable record (``models.cables.HeavyCables``) with the kernel's
    ``CableArrays``, ``Body`` and ``cables.Heavy`` (every pulley: fixed, SR with any axis, DR)."""

    def __init__(self, robot):
        super().__init__(robot)
        self.cables = cable_arrays(robot)
        self.body = body_arrays(self)
        self.heavy = heavy_arrays(self)


def _first_pass(out):
    """``newton``'s result from the kernel's ``Out``: (P, R, the evaluation dict that
    ``models.equilibrium.finish`` reads, iterations, converged)."""
    cur = {
        "F": out.F,
        "M": out.M,
        "t": out.t,
        "merit": out.merit,
        "J": out.J,
        "inside": out.inside,
        "gamma": out.gamma,
        "stable": out.stable,
        "rotvec": out.rotvec,
    }
    if len(out.cat):
        cur["cat"] = out.cat
    return out.P, out.R, cur, out.it, out.conv


def newton(cab, p0, R0, L0, p_ref, tol, maxiter, max_step):
    """The compiled ``models.equilibrium._newton`` (same parameters and results) over N poses.

    Parameters
    ----------
    cab : CompiledCables
    p0 : ndarray (N, 3) [m]
        Start positions.
    R0 : ndarray (N, 3, 3) [-]
        Start orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths.
    p_ref : ndarray (N, 3) [m]
        The energy's origin (the desired positions).
    tol, maxiter, max_step : float [m], int, float [m]
        Stop rules (``equilibrium.PHYSICAL_DEFAULTS``).

    Returns
    -------
    p : ndarray (N, 3) [m]
    R : ndarray (N, 3, 3) [-]
    cur : dict
        F, M (N, 3) [N, N m], t (N, m) [N], merit (N,) [J], J (N, 6, 6) at the last pose.
    iters : ndarray (N,) int32
    conv : ndarray (N,) bool
    """
    n, m = len(p0), cab.robot.m
    f = np.ascontiguousarray
    out = outputs(n, m, cab.heavy.on)
    if n:
        opts = newton_options(PHYSICAL_DEFAULTS, tol, maxiter, max_step)
        _solve_poses(
            f(p_ref, dtype=float),
            f(p0, dtype=float),
            f(R0, dtype=float),
            f(L0, dtype=float),
            cab.cables,
            cab.body,
            opts,
            out,
            cab.heavy,
        )
    return _first_pass(out)


def solve(
    robot,
    p,
    rotvec=None,
    L0=None,
    P0=None,
    tol=None,
    maxiter=None,
    max_step=None,
    restarts=True,
    threads=None,
    heavy=None,
):
    """Compiled ``models.equilibrium.solve`` (same parameters and result; ``threads`` caps numba's
    threads, default all cores): the reference's pose set-up, restarts and result
    (``models.equilibrium.solve_with``) round the compiled Newton ``newton``; heavy cables
    (``robot.heavy``, issue 38) through ``cables.evaluate`` and their outputs by
    ``cables.heavy_cables``, as the reference's.

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses (x, y, z, rx, ry, rz).
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Desired orientations, default identity.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths; default L_TS at the desired pose.
    P0 : array_like (N, 3) [m], optional
        Newton's starting positions (default p).
    tol, maxiter, max_step : float [m], int, float [m], optional
        As ``equilibrium.PHYSICAL_DEFAULTS``.
    restarts : bool
        Look for other equilibria where the solution may not be unique.
    threads : int, optional
    heavy : bool, optional
        Model the cables as heavy (default ``robot.heavy``), as the reference's ``heavy``.

    Returns
    -------
    dict
        As ``models.equilibrium.solve``.

    References
    ----------
    Paty et al. 2021, eq. (2)-(5), (10)-(14); Pott 2018, ch. 3.
    """
    set_threads(threads)
    heavy = robot.heavy if heavy is None else heavy
    cab = CompiledHeavyCables(robot) if heavy else CompiledCables(robot)
    passes = []

    def recorded(*args):
        passes.append(newton(*args))
        return passes[-1]

    res = solve_with(robot, cab, recorded, p, rotvec, L0, P0, tol, maxiter, max_step, restarts, L_TS)
    if heavy:  # the outputs at the result, each cable started from its state there (the first
        # pass's, into which the restarts' winners are copied: a start only, the answer does not
        # depend on it)
        start = passes[0][2]["cat"] if passes and "cat" in passes[0][2] else None
        res.update(heavy_cables(cab, res["P_s"], res["R_s"], res["L0"], start=start))
    return res


@njit(cache=True, parallel=True, error_model="numpy")
def _solve_poses_batch(
    p_ref,
    P0,
    R0,
    L0,
    A,
    kind,
    h,
    rp,
    d,
    inward,
    ES,
    E,
    T_a,
    b,
    frame,
    ident,
    com,
    f,
    wrench,
    scal,
    flags,
    opts,
    out,
):
    # robot k's solve_pose over the chunks of poses: every (robot, chunk) pair is one parallel job
    K, n = P0.shape[0], P0.shape[1]
    m = A.shape[1]
    nchunks = (n + CHUNK - 1) // CHUNK
    for job in prange(K * nchunks):
        k, ch = job // nchunks, job % nchunks
        cab = CableArrays(A[k], kind[k], h[k], rp[k], d[k], inward[k], ES[k], E[k], T_a[k])
        body = Body(
            b[k],
            frame[k],
            ident[k],
            com[k],
            f[k],
            wrench[k],
            scal[k, 0],
            scal[k, 1],
            scal[k, 2],
            flags[k, 0],
            flags[k, 1],
        )
        o = Out(
            out.P[k],
            out.R[k],
            out.F[k],
            out.M[k],
            out.t[k],
            out.merit[k],
            out.J[k],
            out.it[k],
            out.conv[k],
            out.inside[k],
            out.gamma[k],
            out.stable[k],
            out.rotvec[k],
            out.cat[k],
        )
        w = scratch(m)
        massless = Heavy(
            False, np.zeros(m), np.zeros(3), np.zeros((m, 3)), np.zeros(m, dtype=np.bool_), np.zeros(m)
        )
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            solve_pose(i, p_ref[k], P0[k], R0[k], L0[k], cab, body, opts, o, w, massless)


#: Sample-pose pairs of one batched pass (``solve_batch``): about 50 MB of outputs.
BATCH_POSES = 1 << 16


def _stack(records, n, m):
    """The kernel's arrays of K robots: Cables and Body arrays (b to wrench) stacked (K, ...), their scalars as
    (K, 3) floats (ftol, size, ztop) and (K, 2) flags (rigid, suspended), and an ``Out`` (K, n, ...)."""
    cabs = [
        np.ascontiguousarray(np.stack([r.cables[j] for r in records]))
        for j in range(len(CableArrays._fields))
    ]
    bodies = [np.ascontiguousarray(np.stack([r.body[j] for r in records])) for j in range(6)]
    scal = np.array([(r.body.ftol, r.body.size, r.body.ztop) for r in records], dtype=float)
    flags = np.array([(r.body.rigid, r.body.suspended) for r in records], dtype=np.bool_)
    one = outputs(n, m)
    out = Out(*(np.empty((len(records),) + a.shape, dtype=a.dtype) for a in one))
    return cabs, bodies, scal, flags, out


def solve_batch(
    robots, p, rotvec=None, L0=None, tol=None, maxiter=None, max_step=None, restarts=True, threads=None
):
    """Compiled ``models.equilibrium.solve_batch``: ``solve`` of every robot at the same
    poses and rest lengths, the first Newton pass of all of them in one parallel pass over (robot,
    chunk of poses) pairs (``BATCH_POSES`` pairs at a time), so that many small solves (the Monte
    Carlo and Sobol samples of a design) neither start numba's threads nor set up the engine one by
    one. Each pose runs ``solve_pose`` on the same inputs as ``solve``'s, and the restarts
    and the result are ``solve_with``'s (``models.equilibrium.finish``): the results are equal.

    Parameters
    ----------
    robots : sequence of Robot
        Robots with the same number of cables m.
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
    L0 : array_like (N, m) [m], optional
        Rest lengths of every robot, default L_TS at the desired pose of each robot.
    tol, maxiter, max_step, restarts
        As ``solve``.
    threads : int, optional

    Returns
    -------
    list of dict
        ``solve`` of each robot.
    """
    robots = list(robots)
    if not robots:
        return []
    m = robots[0].m
    if any(r.m != m for r in robots):
        raise ValueError("solve_batch: every robot needs the same number of cables")
    tol, maxiter, max_step = stop_rules(tol, maxiter, max_step)
    set_threads(threads)
    opts = newton_options(PHYSICAL_DEFAULTS, tol, maxiter, max_step)
    n = len(np.atleast_2d(np.asarray(p, dtype=float)))
    per = max(1, BATCH_POSES // max(n, 1))
    results = []
    for start in range(0, len(robots), per):
        group = robots[start : start + per]
        records = [CompiledCables(r) for r in group]
        poses = [set_up(r, p, rotvec, L0, None, L_TS) for r in group]
        cabs, bodies, scal, flags, out = _stack(records, n, m)
        if n:
            f = np.ascontiguousarray
            _solve_poses_batch(
                f(np.stack([q.p for q in poses]), dtype=float),
                f(np.stack([q.p0 for q in poses]), dtype=float),
                f(np.stack([q.R_d for q in poses]), dtype=float),
                f(np.stack([q.L0 for q in poses]), dtype=float),
                *cabs,
                *bodies,
                scal,
                flags,
                opts,
                out,
            )
        for k, (robot, rec, pose) in enumerate(zip(group, records, poses)):
            first = _first_pass(Out(*(a[k].copy() for a in out)))
            results.append(finish(robot, rec, newton, pose, first, tol, maxiter, max_step, restarts))
    return results


@njit(cache=True, parallel=True, error_model="numpy")
def _L_TS(p, R, b, A, d, out):
    n, m = p.shape[0], A.shape[0]
    for i in prange(n):
        for c in range(m):
            Bx = p[i, 0] + R[i, 0, 0] * b[c, 0] + R[i, 0, 1] * b[c, 1] + R[i, 0, 2] * b[c, 2]
            By = p[i, 1] + R[i, 1, 0] * b[c, 0] + R[i, 1, 1] * b[c, 1] + R[i, 1, 2] * b[c, 2]
            Bz = p[i, 2] + R[i, 2, 0] * b[c, 0] + R[i, 2, 1] * b[c, 1] + R[i, 2, 2] * b[c, 2]
            dx, dy, dz = Bx - A[c, 0], By - A[c, 1], Bz - A[c, 2]
            out[i, c] = math.sqrt(dx * dx + dy * dy + dz * dz) + d[c]


def L_TS(robot, p, R):
    """Compiled ``models.inverse.L_TS`` at poses: L_TS,i = |B_i - A_i| + d_i at poses (p, R), B_i = p + R b_i
    (Paty 2021 eq. 2 with B_i in place of P), in parallel over the poses.

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Reference points.
    R : ndarray (N, 3, 3) [-]
        Orientations.

    Returns
    -------
    L_TS : ndarray (N, m) [m]

    References
    ----------
    Paty et al. 2021, eq. (2).
    """
    a = robot.arrays
    f = np.ascontiguousarray
    out = np.empty((len(p), robot.m))
    _L_TS(
        f(p, dtype=float),
        f(R, dtype=float),
        f(a.b, dtype=float),
        f(a.A, dtype=float),
        f(a.d, dtype=float),
        out,
    )
    return out
