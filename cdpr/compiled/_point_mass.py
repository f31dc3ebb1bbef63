"""The compiled physical equilibrium's fast path for a suspended point mass (b_i = 0, c = 0,
pulley axes +z): ``models.equilibrium.solve`` on its 3 force rows as a numba kernel that runs in
parallel over points, scalars only in the hot loop (one cable at a time through the shared kernel
``_kernels.cable``). ``cdpr.solve`` chooses it for such robots (``benchmarks/`` measures it
against the pose kernel ``cdpr.compiled.equilibrium`` on the same points).

Same equations, Jacobian, merit, line search, stop rules and statuses as the numpy reference
(``models.equilibrium``, whose point-mass case is this 3 x 3 Newton); a test checks that both give
the same statuses, taut sets and P* (1e-9 m). The result holds the point-mass keys
(``results.physical_result``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from cdpr.compiled._kernels import CHUNK, DET_EPS, Cables, cable, cable_arrays, newton_options, set_threads
from cdpr.models.cables import FTOL_REL
from cdpr.models.equilibrium import (
    ARMIJO_C,
    LS_SKIP,
    MAX_HALVINGS,
    PHYSICAL_DEFAULTS,
    batch_starts,
    start_points,
)
from cdpr.models.inverse import L_TS
from cdpr.models.results import hull_halfplanes, physical_result, physical_results
from cdpr.robot import require_point_mass


class Load(NamedTuple):
    """The platform's load for the physical kernels (``physical_load``): wx, wy, wz the external
    force w_ext [N], ztop [m] the lowest pulley joint height (P must stay below it), ftol [N] the
    force tolerance FTOL_REL |w_ext|."""

    wx: float
    wy: float
    wz: float
    ztop: float
    ftol: float


class PhysicalOut(NamedTuple):
    """Per-point results of the physical kernel (``physical_outputs``): P (N, 3) [m], t (N, m) [N],
    resid (N,) [N], it (N,), conv (N,) bool, ins (N,) bool (a cable's P or C inside its sheave)."""

    P: np.ndarray
    t: np.ndarray
    resid: np.ndarray
    it: np.ndarray
    conv: np.ndarray
    ins: np.ndarray


def physical_load(robot):
    """The ``Load`` record of ``robot``."""
    w = robot.platform.w_ext
    return Load(
        float(w[0]),
        float(w[1]),
        float(w[2]),
        float(robot.arrays.A[:, 2].min()),
        FTOL_REL * float(np.linalg.norm(w)),
    )


def physical_outputs(n, m):
    """An uninitialised ``PhysicalOut`` for n points and m cables."""
    return PhysicalOut(
        np.empty((n, 3)),
        np.empty((n, m)),
        np.empty(n),
        np.empty(n, dtype=np.int32),
        np.empty(n, dtype=np.bool_),
        np.empty(n, dtype=np.bool_),
    )


@njit(cache=True, inline="always", error_model="numpy")
def _eval(px, py, pz, rx, ry, rz, cab, L0, i, load, tbuf):
    """``models.cables.Cables.evaluate`` of a point mass at one point P with rest lengths L0[i] (``Cables`` cab, ``Load``
    load): writes the tensions in tbuf and returns (F (3), Newton's F (3), merit, J (9, row-major),
    grad (3), kappa, inside)."""
    A, kind, h, rp, d, inward, ES = cab.A, cab.kind, cab.h, cab.rp, cab.d, cab.inward, cab.ES
    wx, wy, wz, ztop = load.wx, load.wy, load.wz, load.ztop
    m = A.shape[0]
    Fx, Fy, Fz = wx, wy, wz
    elastic = 0.0
    gx = gy = gz = 0.0
    J00 = J01 = J02 = J10 = J11 = J12 = J20 = J21 = J22 = 0.0
    K00 = K01 = K02 = K10 = K11 = K12 = K20 = K21 = K22 = 0.0  # every cable's stiffness term
    kact = ksum = geo = 0.0
    Ex = Ey = Ez = 0.0  # sum k e u over every cable (Hooke extended to compression)
    nact = 0
    inside_any = False
    for c in range(m):
        (L, ux, uy, uz, lE, ins, sw, epx, epy, arm, bx, by, bz, ex, ey, ez, uCb, _gam) = cable(
            px, py, pz, A[c, 0], A[c, 1], A[c, 2], kind[c], h[c], rp[c], d[c], inward[c, 0], inward[c, 1]
        )
        inside_any = inside_any or ins
        L0c = L0[i, c]
        e = L - L0c
        k = ES[c] / L0c
        t = k * e if e > 0.0 else 0.0
        tbuf[c] = t
        Fx += t * ux
        Fy += t * uy
        Fz += t * uz
        if e > 0.0:
            elastic += 0.5 * k * e * e
        # dL/dP = -u + arm (u . beta + u_C . beta) eps (statics.length_gradient)
        ub = ux * bx + uy * by + uz * bz
        q = arm * (ub + uCb)
        dLx, dLy, dLz = -ux + q * ex, -uy + q * ey, -uz + q * ez
        gx += t * dLx
        gy += t * dLy
        gz += t * dLz
        # t du/dP = -(t/lE) [(I - u u^T) - sw ep ep^T - arm v eps^T], v = beta - (u . beta) u
        w = t / lE
        geo += w
        ws = w * sw
        wa = w * arm
        vx, vy, vz = bx - ub * ux, by - ub * uy, bz - ub * uz
        J00 += -w * (1.0 - ux * ux) + ws * epx * epx + wa * vx * ex
        J01 += w * ux * uy + ws * epx * epy + wa * vx * ey
        J02 += w * ux * uz + wa * vx * ez
        J10 += w * uy * ux + ws * epy * epx + wa * vy * ex
        J11 += -w * (1.0 - uy * uy) + ws * epy * epy + wa * vy * ey
        J12 += w * uy * uz + wa * vy * ez
        J20 += w * uz * ux + wa * vz * ex
        J21 += w * uz * uy + wa * vz * ey
        J22 += -w * (1.0 - uz * uz) + wa * vz * ez
        # stiffness term k u dL^T, on active cables (L >= L0) and, apart, on all of them
        kx, ky, kz = k * ux, k * uy, k * uz
        K00 += kx * dLx
        K01 += kx * dLy
        K02 += kx * dLz
        K10 += ky * dLx
        K11 += ky * dLy
        K12 += ky * dLz
        K20 += kz * dLx
        K21 += kz * dLy
        K22 += kz * dLz
        ksum += k
        Ex += k * e * ux
        Ey += k * e * uy
        Ez += k * e * uz
        if e >= 0.0:
            nact += 1
            kact += k
            J00 += kx * dLx
            J01 += kx * dLy
            J02 += kx * dLz
            J10 += ky * dLx
            J11 += ky * dLy
            J12 += ky * dLz
            J20 += kz * dLx
            J21 += kz * dLy
            J22 += kz * dLz
    if nact == 0:  # no cable taut: Hooke extended to compression
        J00 += K00
        J01 += K01
        J02 += K02
        J10 += K10
        J11 += K11
        J12 += K12
        J20 += K20
        J21 += K21
        J22 += K22
        kact = ksum
        Nx, Ny, Nz = Fx + Ex, Fy + Ey, Fz + Ez
    else:
        Nx, Ny, Nz = Fx, Fy, Fz
    merit = -(wx * (px - rx) + wy * (py - ry) + wz * (pz - rz)) + elastic
    if not pz < ztop:
        merit = np.inf
    return (
        Fx,
        Fy,
        Fz,
        Nx,
        Ny,
        Nz,
        merit,
        J00,
        J01,
        J02,
        J10,
        J11,
        J12,
        J20,
        J21,
        J22,
        gx - wx,
        gy - wy,
        gz - wz,
        kact + geo,
        inside_any,
    )


@njit(cache=True, error_model="numpy")
def solve_point(i, p, P0, L0, cab, load, opts, out, tcur, ttry):
    """``models.equilibrium._newton`` of a point mass for point i: p (N, 3) [m] the nominal points, P0 (N, 3) [m] the start
    points, L0 (N, m) [m] the rest lengths, cab ``Cables``, load ``Load``, opts ``Newton``; writes
    row i of out (``PhysicalOut``); tcur, ttry (m,): scratch (tcur is left holding the tensions)."""
    tol, maxiter, max_step, ftol = opts.tol, opts.maxiter, opts.max_step, load.ftol
    P_out, t_out, res_out, it_out, conv_out, ins_out = out
    m = cab.A.shape[0]
    rx, ry, rz = p[i, 0], p[i, 1], p[i, 2]
    px, py, pz = P0[i, 0], P0[i, 1], P0[i, 2]
    (Fx, Fy, Fz, Nx, Ny, Nz, merit, J00, J01, J02, J10, J11, J12, J20, J21, J22, gx, gy, gz, kappa, ins) = (
        _eval(px, py, pz, rx, ry, rz, cab, L0, i, load, tcur)
    )
    conv = False
    it = 0
    prev = 0.0
    prev_full = False
    for _ in range(maxiter):
        if Fx * Fx + Fy * Fy + Fz * Fz <= ftol * ftol:
            conv = True
            break
        # Newton step J s = -F by cofactors (statics.solve3)
        c00, c01, c02 = J11 * J22 - J12 * J21, J12 * J20 - J10 * J22, J10 * J21 - J11 * J20
        c10, c11, c12 = J21 * J02 - J22 * J01, J22 * J00 - J20 * J02, J20 * J01 - J21 * J00
        c20, c21, c22 = J01 * J12 - J02 * J11, J02 * J10 - J00 * J12, J00 * J11 - J01 * J10
        det = J00 * c00 + J01 * c01 + J02 * c02
        newton = abs(det) >= DET_EPS
        sx = sy = sz = 0.0
        if newton:
            idet = 1.0 / det
            sx = -(c00 * Nx + c10 * Ny + c20 * Nz) * idet
            sy = -(c01 * Nx + c11 * Ny + c21 * Nz) * idet
            sz = -(c02 * Nx + c12 * Ny + c22 * Nz) * idet
            newton = math.isfinite(sx) and math.isfinite(sy) and math.isfinite(sz)
        if newton:
            slope = gx * sx + gy * sy + gz * sz
            newton = slope < 0.0 or sx * sx + sy * sy + sz * sz <= LS_SKIP * LS_SKIP
        if not newton:
            kk = kappa if kappa > 0 else 1.0
            sx, sy, sz = -gx / kk, -gy / kk, -gz / kk
        slope = gx * sx + gy * sy + gz * sz
        norm = math.sqrt(sx * sx + sy * sy + sz * sz)
        done = newton and (norm < tol or (prev_full and norm * norm < tol * prev))
        scale = 1.0 if done else min(1.0, max_step / max(norm, 1e-300))
        sx, sy, sz = sx * scale, sy * scale, sz * scale
        slope *= scale
        whole = done or norm * scale <= LS_SKIP
        alpha = 1.0
        for hv in range(MAX_HALVINGS + 1):
            qx, qy, qz = px + alpha * sx, py + alpha * sy, pz + alpha * sz
            (
                tFx,
                tFy,
                tFz,
                tNx,
                tNy,
                tNz,
                tmerit,
                t00,
                t01,
                t02,
                t10,
                t11,
                t12,
                t20,
                t21,
                t22,
                tgx,
                tgy,
                tgz,
                tkappa,
                tins,
            ) = _eval(qx, qy, qz, rx, ry, rz, cab, L0, i, load, ttry)
            if whole or tmerit <= merit + ARMIJO_C * alpha * slope or hv == MAX_HALVINGS:
                px, py, pz = qx, qy, qz
                Fx, Fy, Fz, Nx, Ny, Nz, merit = tFx, tFy, tFz, tNx, tNy, tNz, tmerit
                J00, J01, J02, J10, J11, J12, J20, J21, J22 = t00, t01, t02, t10, t11, t12, t20, t21, t22
                gx, gy, gz, kappa, ins = tgx, tgy, tgz, tkappa, tins
                for c in range(m):
                    tcur[c] = ttry[c]
                break
            alpha *= 0.5
        it += 1
        prev = alpha * norm * scale
        prev_full = newton and alpha == 1.0 and scale == 1.0
        if done:
            conv = True
            break
    P_out[i, 0], P_out[i, 1], P_out[i, 2] = px, py, pz
    for c in range(m):
        t_out[i, c] = tcur[c]
    res_out[i] = math.sqrt(Fx * Fx + Fy * Fy + Fz * Fz)
    it_out[i] = it
    conv_out[i] = conv
    ins_out[i] = ins


@njit(cache=True, parallel=True, error_model="numpy")
def _solve_points(p, P0, L0, cab, load, opts, out):
    n = p.shape[0]
    m = cab.A.shape[0]
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        tcur = np.empty(m)
        ttry = np.empty(m)
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            solve_point(i, p, P0, L0, cab, load, opts, out, tcur, ttry)


def solve(robot, p, L0=None, P0=None, tol=None, maxiter=None, max_step=None, threads=None):
    """Compiled ``models.equilibrium.solve`` (same parameters and result; ``threads`` caps numba's
    threads, default all cores).

    Parameters
    ----------
    robot : Robot
    p : array_like, shape (N, 3) [m]
    L0 : array_like, shape (N, m) [m], optional
        Rest lengths, default L_TS(p) (eq. 2).
    P0 : array_like, shape (N, 3) [m], optional
    tol, maxiter, max_step : optional, defaults ``equilibrium.PHYSICAL_DEFAULTS``.
    threads : int, optional

    Returns
    -------
    dict
        The point-mass keys of ``models.equilibrium.solve`` (``results.physical_result``).
    """
    require_point_mass(  # as the numpy twin: the kernel evaluates pulleys with +z axes only
        robot, "solve", 'cdpr.solve.solve(robot, p, redundancy="physical")', True, p
    )
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    n, m = len(p), robot.m
    L0 = L_TS(robot, p) if L0 is None else np.broadcast_to(np.asarray(L0, dtype=float), (n, m))
    L0 = np.ascontiguousarray(L0, dtype=float)
    P0 = start_points(robot, p if P0 is None else P0)
    set_threads(threads)
    out = physical_outputs(n, m)
    if n:
        opts = newton_options(PHYSICAL_DEFAULTS, tol, maxiter, max_step)
        _solve_points(p, P0, L0, cable_arrays(robot), physical_load(robot), opts, out)
    P, t, resid, it, conv, ins = out
    return physical_result(robot, p, P, t, resid, it, conv, ins[:, None], halfplanes=hull_halfplanes(robot))


@njit(cache=True, parallel=True, error_model="numpy")
def _solve_batch(p, P0, L0, A, kind, h, rp, d, inward, ES, E, T_a, loads, opts, P, t, resid, it, conv, ins):
    # robot k's solve_point over the chunks of points: every (robot, chunk) pair is one parallel job
    K, n = P0.shape[0], p.shape[0]
    m = A.shape[1]
    nchunks = (n + CHUNK - 1) // CHUNK
    for job in prange(K * nchunks):
        k, ch = job // nchunks, job % nchunks
        cab = Cables(A[k], kind[k], h[k], rp[k], d[k], inward[k], ES[k], E[k], T_a[k])
        load = Load(loads[k, 0], loads[k, 1], loads[k, 2], loads[k, 3], loads[k, 4])
        out = PhysicalOut(P[k], t[k], resid[k], it[k], conv[k], ins[k])
        tcur = np.empty(m)
        ttry = np.empty(m)
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            solve_point(i, p, P0[k], L0, cab, load, opts, out, tcur, ttry)


def solve_batch(robots, p, L0=None, tol=None, maxiter=None, max_step=None, threads=None, P0=None):
    """Compiled ``equilibrium.solve_batch``: ``solve`` of every robot at the
    same points and rest lengths in one parallel pass over (robot, chunk of points) pairs, so that
    many small solves (Monte Carlo and Sobol samples) do not each start and stop numba's threads.
    Each point runs the same kernel on the same inputs as ``solve`` (equal results).

    Parameters
    ----------
    robots : sequence of Robot
        Robots with the same number of cables m.
    p : array_like, shape (N, 3) [m]
    L0 : array_like, shape (N, m) [m], optional
        Rest lengths of every robot, default L_TS(p) (eq. 2) of each robot.
    tol, maxiter, max_step : optional, defaults ``equilibrium.PHYSICAL_DEFAULTS``.
    threads : int, optional
    P0 : array_like, shape (N, 3) or (K, N, 3) [m], optional
        Newton's starting points, as ``equilibrium.solve_batch`` (default p).

    Returns
    -------
    list of dict
        ``models.equilibrium.solve`` of each robot.
    """
    robots = list(robots)
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    if not robots:
        return []
    n, m = len(p), robots[0].m
    if any(r.m != m for r in robots):
        raise ValueError("solve_batch: every robot needs the same number of cables")
    if L0 is None:
        L0s = [np.ascontiguousarray(L_TS(r, p), dtype=float) for r in robots]
    else:
        L0s = [np.ascontiguousarray(np.broadcast_to(np.asarray(L0, dtype=float), (n, m)), dtype=float)] * len(
            robots
        )
    starts = batch_starts(robots, p, P0)
    if n == 0 or L0 is None:  # rest lengths per robot: one solve each
        return [solve(r, p, L, P, tol, maxiter, max_step, threads) for r, L, P in zip(robots, L0s, starts)]
    K = len(robots)
    cabs = [cable_arrays(r) for r in robots]
    stack = [np.ascontiguousarray(np.stack([c[j] for c in cabs])) for j in range(len(Cables._fields))]
    loads = np.array([tuple(physical_load(r)) for r in robots], dtype=float)
    P0 = np.ascontiguousarray(np.stack(starts))
    P = np.empty((K, n, 3))
    t = np.empty((K, n, m))
    resid = np.empty((K, n))
    it = np.empty((K, n), dtype=np.int32)
    conv = np.empty((K, n), dtype=np.bool_)
    ins = np.empty((K, n), dtype=np.bool_)
    set_threads(threads)
    opts = newton_options(PHYSICAL_DEFAULTS, tol, maxiter, max_step)
    _solve_batch(p, P0, L0s[0], *stack, loads, opts, P, t, resid, it, conv, ins)
    return physical_results(robots, p, P, t, resid, it, conv, ins[..., None])
