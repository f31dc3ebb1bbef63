"""Compiled sensitivities dP*/dθ: ``sensitivity.sensitivities`` in the compiled engines' kernels.

Each point is solved by the compiled solver (``subsets.solve_point`` for paper mode,
``equilibrium.solve_point`` for the physical equilibrium) and, in the same pass, its cables are
evaluated once more at P* with their partial derivatives (``_kernels.cable_partials``): the Jacobian J and
dF/dθ follow, and dP*/dθ = -J^-1 dF/dθ by cofactors. Paper mode also solves the subsets the
solver's pruning skipped whose |dp| could lie within ``gap_tol`` of the chosen one, so that the
smoothness flag sees every subset the answer could switch to. Same equations, flags and results as
the numpy reference (``sensitivity``), tested equal.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from cdpr.compiled._kernels import (
    C_DLD,
    C_DLDP,
    C_DLH,
    C_DLR,
    C_DUDP,
    C_DUH,
    C_DUR,
    C_L,
    C_U,
    CHUNK,
    DET_EPS,
    NCOL,
    NEWTON_DEFAULTS,
    cable_arrays,
    cable_partials_at,
    cable_partials_axis,
    commanded_input,
    newton_options,
    set_threads,
)
from cdpr.compiled._point_mass import physical_load, physical_outputs
from cdpr.compiled._point_mass import solve_point as physical_point
from cdpr.compiled._pose_sensitivity import pose_sensitivities, sensitivities_at  # noqa: F401  (the pose path)
from cdpr.compiled.subsets import (
    ST_OK,
    commanded_lengths,
    paper_outputs,
    paper_scratch,
    solve_subset,
    subset_arrays,
)
from cdpr.compiled.subsets import solve_point as paper_point
from cdpr.errors import CdprError
from cdpr.models.equilibrium import PHYSICAL_DEFAULTS, start_points
from cdpr.models.inverse import L_TS
from cdpr.models.results import STATUSES, hull_halfplanes, physical_result
from cdpr.models.sensitivity import COND_MAX, GAP_TOL, T_TOL
from cdpr.parameters import parameter_names
from cdpr.robot import require_point_mass


@njit(cache=True, inline="always")
def _geo(rows, j, g, du):
    """Partial g (0 h, 1 r_p, 2 d, 3..5 A_x..A_z) of cable row j of ``rows``: writes du (3), returns dL."""
    if g == 0:
        for a in range(3):
            du[a] = rows[j, C_DUH + a]
        return rows[j, C_DLH]
    if g == 1:
        for a in range(3):
            du[a] = rows[j, C_DUR + a]
        return rows[j, C_DLR]
    if g == 2:
        for a in range(3):
            du[a] = 0.0
        return rows[j, C_DLD]
    b = g - 3  # d/dA_b = -d/dP_b
    for a in range(3):
        du[a] = -rows[j, C_DUDP + 3 * a + b]
    return -rows[j, C_DLDP + b]


@njit(cache=True, inline="always")
def _inv3(J, Jinv):
    """Jinv = J^-1 (3x3, by cofactors); returns False where |det| < DET_EPS."""
    c00 = J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]
    c01 = J[1, 2] * J[2, 0] - J[1, 0] * J[2, 2]
    c02 = J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0]
    det = J[0, 0] * c00 + J[0, 1] * c01 + J[0, 2] * c02
    if not abs(det) >= DET_EPS:
        return False
    idet = 1.0 / det
    Jinv[0, 0] = c00 * idet
    Jinv[1, 0] = c01 * idet
    Jinv[2, 0] = c02 * idet
    Jinv[0, 1] = (J[2, 1] * J[0, 2] - J[2, 2] * J[0, 1]) * idet
    Jinv[1, 1] = (J[2, 2] * J[0, 0] - J[2, 0] * J[0, 2]) * idet
    Jinv[2, 1] = (J[2, 0] * J[0, 1] - J[2, 1] * J[0, 0]) * idet
    Jinv[0, 2] = (J[0, 1] * J[1, 2] - J[0, 2] * J[1, 1]) * idet
    Jinv[1, 2] = (J[0, 2] * J[1, 0] - J[0, 0] * J[1, 2]) * idet
    Jinv[2, 2] = (J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]) * idet
    return True


@njit(cache=True, inline="always")
def _cond(J, Jinv):
    """||J||_F ||J^-1||_F."""
    a = b = 0.0
    for i in range(3):
        for j in range(3):
            a += J[i, j] * J[i, j]
            b += Jinv[i, j] * Jinv[i, j]
    return math.sqrt(a * b)


@njit(cache=True, inline="always")
def _put(S, i, col, Jinv, f0, f1, f2):
    """S[i, :, col] = -Jinv (f0, f1, f2)."""
    for a in range(3):
        S[i, a, col] = -(Jinv[a, 0] * f0 + Jinv[a, 1] * f1 + Jinv[a, 2] * f2)


@njit(cache=True, inline="always")
def _put_t(St, S, i, col, T, pt):
    """St[i, :, col] = dt/dP S[i, :, col] + pt (the partial at fixed P)."""
    for k in range(3):
        St[i, k, col] = T[k, 0] * S[i, 0, col] + T[k, 1] * S[i, 1, col] + T[k, 2] * S[i, 2, col] + pt[k]


@njit(cache=True, error_model="numpy")
def _paper_sens(i, Px, Py, Pz, cs, Lc, cables, subs, b, bg, mass, rows, S, w, St, want_t):
    """dP*/dθ of paper mode at P* for the subset cs (3 cables) with commanded lengths Lc (3), written
    to S[i] (``sensitivity.paper_jacobian_terms`` and ``implicit_solve``); returns the subset's
    tensions at P* and the condition number of J (inf where singular). ``cables`` the ``Cables``
    record, ``subs`` the ``Subsets`` record (a robot that is not suspended has each cable evaluated
    in its pulley frame, ``cable_partials_axis``), b (3,) [N] = -w_ext, bg (3,) [N] = -M g the weight
    alone (the mass's column: an external force does not scale with M), ``rows`` (3, NCOL) and ``w``
    (8, 3, 3): scratch. With ``want_t``, also the total dt/dθ = dt/dP dP*/dθ + dt/dθ|_P into St[i]."""
    ES, E = cables.ES, cables.E
    m = cables.A.shape[0]
    for j in range(3):
        c = cs[j]
        if subs.suspended:
            cable_partials_at(Px, Py, Pz, cables, c, rows[j])
        else:
            A, inward = cables.A, cables.inward
            cable_partials_axis(
                Px, Py, Pz, A[c, 0], A[c, 1], A[c, 2], cables.kind[c], cables.h[c], cables.rp[c],
                cables.d[c], inward[c, 0], inward[c, 1], subs.ident[c], subs.frame[c], rows[j],
            )  # fmt: skip
    # M_u = [u_0 u_1 u_2] (columns); M_u^-1 rows r_j / det
    u, r, G, J, Jinv, T = w[0], w[1], w[2], w[3], w[4], w[7]
    t, kL, du, f, pt = w[5, 0], w[5, 1], w[5, 2], w[6, 0], w[6, 1]
    for j in range(3):
        for a in range(3):
            u[j, a] = rows[j, C_U + a]
    for j in range(3):
        p_, q_ = (j + 1) % 3, (j + 2) % 3
        r[j, 0] = u[p_, 1] * u[q_, 2] - u[p_, 2] * u[q_, 1]
        r[j, 1] = u[p_, 2] * u[q_, 0] - u[p_, 0] * u[q_, 2]
        r[j, 2] = u[p_, 0] * u[q_, 1] - u[p_, 1] * u[q_, 0]
    det = u[0, 0] * r[0, 0] + u[0, 1] * r[0, 1] + u[0, 2] * r[0, 2]
    if not abs(det) >= DET_EPS:
        return np.nan, np.nan, np.nan, np.inf
    idet = 1.0 / det
    for j in range(3):
        t[j] = (r[j, 0] * b[0] + r[j, 1] * b[1] + r[j, 2] * b[2]) * idet
        kL[j] = Lc[j] / ES[cs[j]]
    # the weight's share of the tensions (t itself without an external force: the same bits)
    tg0 = (r[0, 0] * bg[0] + r[0, 1] * bg[1] + r[0, 2] * bg[2]) * idet
    tg1 = (r[1, 0] * bg[0] + r[1, 1] * bg[1] + r[1, 2] * bg[2]) * idet
    tg2 = (r[2, 0] * bg[0] + r[2, 1] * bg[1] + r[2, 2] * bg[2]) * idet
    for a in range(3):
        for b in range(3):
            G[a, b] = 0.0
    for j in range(3):
        for a in range(3):
            for b in range(3):
                G[a, b] += t[j] * rows[j, C_DUDP + 3 * a + b]
    for j in range(3):
        for b in range(3):
            T[j, b] = -(r[j, 0] * G[0, b] + r[j, 1] * G[1, b] + r[j, 2] * G[2, b]) * idet
            J[j, b] = rows[j, C_DLDP + b] - kL[j] * T[j, b]
    if not _inv3(J, Jinv):
        return t[0], t[1], t[2], np.inf
    for j in range(3):
        c = cs[j]
        for k in range(3):
            f[k] = 0.0
        f[j] = kL[j] * t[j] / E[c]
        _put(S, i, c, Jinv, f[0], f[1], f[2])
        if want_t:
            pt[0] = pt[1] = pt[2] = 0.0
            _put_t(St, S, i, c, T, pt)
        for g in range(6):
            dL = _geo(rows, j, g, du)
            for k in range(3):
                pt[k] = -(r[k, 0] * du[0] + r[k, 1] * du[1] + r[k, 2] * du[2]) * t[j] * idet
                f[k] = (dL if k == j else 0.0) - kL[k] * pt[k]
            col = (g + 1) * m + c if g < 3 else 4 * m + 3 * c + (g - 3)
            _put(S, i, col, Jinv, f[0], f[1], f[2])
            if want_t:
                _put_t(St, S, i, col, T, pt)
    for k, tg in enumerate((tg0, tg1, tg2)):
        f[k] = -kL[k] * tg / mass
        pt[k] = tg / mass
    _put(S, i, 7 * m, Jinv, f[0], f[1], f[2])
    if want_t:
        _put_t(St, S, i, 7 * m, T, pt)
    return t[0], t[1], t[2], _cond(J, Jinv)


@njit(cache=True, parallel=True, error_model="numpy")
def _paper_points(p, Lin, cables, subs, b, bg, mass, opts, gap_tol, out, S, gap_out, tm_out, cond_out):
    n = p.shape[0]
    subsets = subs.idx
    ns = subsets.shape[0]
    m = cables.A.shape[0]
    T_a = cables.T_a
    st_out, sub_out = out.st, out.sub
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        scr = paper_scratch(m, ns)
        Lall, Ps, ts, its, conv, exi, dps, solved, adm, gap = scr
        rows = np.empty((3, NCOL))
        cs = np.empty(3, np.int64)
        Lc = np.empty(3)
        w = np.empty((8, 3, 3))
        P0 = np.empty((0, ns, 3))  # every subset starts at p
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            paper_point(i, p, Lin, cables, subs, b, opts, True, out, scr, P0)
            gap_out[i] = np.nan
            tm_out[i] = np.nan
            cond_out[i] = np.inf
            if st_out[i] != ST_OK:
                for a in range(3):
                    for k in range(S.shape[2]):
                        S[i, a, k] = np.nan
                continue
            choice = -1
            for k in range(ns):
                if (
                    subsets[k, 0] == sub_out[i, 0]
                    and subsets[k, 1] == sub_out[i, 1]
                    and subsets[k, 2] == sub_out[i, 2]
                ):
                    choice = k
            best = dps[choice]
            runner = np.inf
            for k in range(ns):
                if k == choice:
                    continue
                if not solved[k] and gap[k] <= best + gap_tol:  # skipped by the pruning, could be close
                    solve_subset(k, i, p, cables, subs, Lall, b, opts, scr)
                    solved[k] = True
                    adm[k] = conv[k]
                    for j in range(3):
                        adm[k] = adm[k] and 0.0 <= ts[k, j] <= T_a[subsets[k, j]]
                if solved[k] and adm[k] and dps[k] < runner:
                    runner = dps[k]
            gap_out[i] = runner - best
            for a in range(3):
                for k in range(S.shape[2]):
                    S[i, a, k] = 0.0
            for j in range(3):
                cs[j] = subsets[choice, j]
                Lc[j] = Lall[cs[j]]
            t0, t1, t2, cond = _paper_sens(
                i,
                Ps[choice, 0],
                Ps[choice, 1],
                Ps[choice, 2],
                cs,
                Lc,
                cables,
                subs,
                b,
                bg,
                mass,
                rows,
                S,
                w,
                S,
                False,
            )
            cond_out[i] = cond
            if not cond < np.inf:
                for a in range(3):
                    for k in range(S.shape[2]):
                        S[i, a, k] = np.nan
            tm = np.inf
            for j, tj in enumerate((t0, t1, t2)):
                tm = min(tm, tj, T_a[cs[j]] - tj)
            tm_out[i] = tm


@njit(cache=True, parallel=True, error_model="numpy")
def _physical_points(p, P0, L0, cables, load, gravity, mass, opts, out, S, tm_out, cond_out):
    n = p.shape[0]
    m = cables.A.shape[0]
    ES, E, T_a = cables.ES, cables.E, cables.T_a
    P_out, conv_out = out.P, out.conv
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        tcur = np.empty(m)
        ttry = np.empty(m)
        rows = np.empty((m, NCOL))
        hooke = np.empty(m)
        J = np.empty((3, 3))
        Jinv = np.empty((3, 3))
        du = np.empty(3)
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            physical_point(i, p, P0, L0, cables, load, opts, out, tcur, ttry)
            for a in range(3):
                for k in range(S.shape[2]):
                    S[i, a, k] = np.nan
            tm_out[i] = np.nan
            cond_out[i] = np.inf
            if not conv_out[i]:
                continue
            Px, Py, Pz = P_out[i, 0], P_out[i, 1], P_out[i, 2]
            for a in range(3):
                for b in range(3):
                    J[a, b] = 0.0
            tm = np.inf
            for c in range(m):
                cable_partials_at(Px, Py, Pz, cables, c, rows[c])
                k_ = ES[c] / L0[i, c]
                hooke[c] = k_ * (rows[c, C_L] - L0[i, c])
                t = hooke[c] if hooke[c] > 0.0 else 0.0
                ka = k_ if hooke[c] >= 0.0 else 0.0
                tm = min(tm, abs(hooke[c]))
                if hooke[c] > 0.0:
                    tm = min(tm, T_a[c] - t)
                for a in range(3):
                    for b in range(3):
                        J[a, b] += (
                            t * rows[c, C_DUDP + 3 * a + b] + ka * rows[c, C_U + a] * rows[c, C_DLDP + b]
                        )
            tm_out[i] = tm
            if not _inv3(J, Jinv):
                continue
            cond_out[i] = _cond(J, Jinv)
            for c in range(m):
                k_ = ES[c] / L0[i, c]
                t = hooke[c] if hooke[c] > 0.0 else 0.0
                ka = k_ if hooke[c] >= 0.0 else 0.0
                w = t / E[c]
                _put(S, i, c, Jinv, w * rows[c, C_U], w * rows[c, C_U + 1], w * rows[c, C_U + 2])
                for g in range(6):
                    dL = _geo(rows, c, g, du)
                    col = (g + 1) * m + c if g < 3 else 4 * m + 3 * c + (g - 3)
                    _put(
                        S,
                        i,
                        col,
                        Jinv,
                        ka * dL * rows[c, C_U] + t * du[0],
                        ka * dL * rows[c, C_U + 1] + t * du[1],
                        ka * dL * rows[c, C_U + 2] + t * du[2],
                    )
            # the mass moves the weight only (not an external force): M g / M
            _put(S, i, 7 * m, Jinv, gravity[0] / mass, gravity[1] / mass, gravity[2] / mass)


def sensitivities_fast(
    robot, p, redundancy="paper", L=None, threads=None, gap_tol=GAP_TOL, t_tol=T_TOL, **solver
):
    """Compiled ``sensitivity.sensitivities`` (same parameters, except the engine, and same result).

    Parameters
    ----------
    robot : Robot
    p : array_like, shape (N, 3) [m]
    redundancy : {"paper", "physical"}
    L : array_like, shape (N, m) [m], optional
        Commanded lengths (held fixed), default L_TS(p).
    threads : int, optional
    gap_tol : float [m]
    t_tol : float [N]
    solver : tol, maxiter (and max_step, physical mode).

    Returns
    -------
    dict
        As ``sensitivity.sensitivities``.

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10)-(14).
    """
    if redundancy not in ("paper", "physical"):
        raise CdprError(f"unknown redundancy {redundancy!r}; allowed: paper, physical")
    require_point_mass(
        robot, f"sensitivities_fast ({redundancy} mode)", "cdpr.solve.sensitivities (redundancy: physical, the pose equilibrium)",
        redundancy == "physical", p,
    )  # fmt: skip
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    n, m = len(p), robot.m
    K = 7 * m + 1
    set_threads(threads)
    cables = cable_arrays(robot)
    S = np.empty((n, 3, K))
    tm = np.empty(n)
    cond = np.empty(n)
    if redundancy == "paper":
        opts = newton_options({**NEWTON_DEFAULTS, **solver})
        Lin = commanded_input(L, n, m)
        out = paper_outputs(n, m)
        gap = np.empty(n)
        if n:
            b = -robot.platform.w_ext
            _paper_points(
                p,
                Lin,
                cables,
                subset_arrays(robot),
                b,
                -robot.platform.gravity_force,
                robot.platform.mass,
                opts,
                gap_tol,
                out,
                S,
                gap,
                tm,
                cond,
            )
        st = out.st
        res = {
            "p": p,
            "P_s": out.P_s,
            "dp": out.dp,
            "t": out.t,
            "subset": out.sub,
            "iterations": out.it,
            "status_code": st,
            "status": np.asarray(STATUSES)[st],
            "subset_solves": out.work,
            "dp_gap": gap,
        }
        smooth = (st == ST_OK) & (gap > gap_tol) & (tm > t_tol) & (cond < COND_MAX)
    else:
        opts = newton_options({**PHYSICAL_DEFAULTS, **solver})
        L0 = L_TS(robot, p) if L is None else np.broadcast_to(np.asarray(L, dtype=float), (n, m))
        L0 = np.ascontiguousarray(L0, dtype=float)
        P0 = start_points(robot, p)
        out = physical_outputs(n, m)
        if n:
            _physical_points(
                p,
                P0,
                L0,
                cables,
                physical_load(robot),
                robot.platform.gravity_force,
                robot.platform.mass,
                opts,
                out,
                S,
                tm,
                cond,
            )
        P, t, resid, it, conv, ins = out
        res = physical_result(
            robot, p, P, t, resid, it, conv, ins[:, None], halfplanes=hull_halfplanes(robot)
        )
        ok = res["status"] == "ok"
        S[~ok] = np.nan
        tm = np.where(ok, tm, np.nan)
        cond = np.where(ok, cond, np.inf)
        smooth = ok & (tm > t_tol) & (cond < COND_MAX)
    res.update(S=S, names=parameter_names(robot, rigid=False), smooth=smooth, margin_t=tm, cond=cond)
    return res


@njit(cache=True, parallel=True, error_model="numpy")
def _subsets_points(p, Lin, cables, subs, b, bg, mass, opts, cols, P_out, t_out, conv_out, S_out, St_out):
    subsets = subs.idx
    n = p.shape[0]
    ns = subsets.shape[0]
    m = cables.A.shape[0]
    K = 7 * m + 1
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        scr = paper_scratch(m, ns)
        Lall, Ps, conv = scr.Lall, scr.Ps, scr.conv
        rows = np.empty((3, NCOL))
        cs = np.empty(3, np.int64)
        Lc = np.empty(3)
        w = np.empty((8, 3, 3))
        S1 = np.empty((1, 3, K))
        St1 = np.empty((1, 3, K))
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            commanded_lengths(i, p, Lin, cables, Lall)
            for k in range(ns):
                solve_subset(k, i, p, cables, subs, Lall, b, opts, scr)
                conv_out[i, k] = False
                for a in range(3):
                    P_out[i, k, a] = Ps[k, a]
                    t_out[i, k, a] = np.nan
                    for q in range(cols.shape[0]):
                        S_out[i, k, a, q] = np.nan
                        St_out[i, k, a, q] = np.nan
                if not conv[k]:
                    continue
                for j in range(3):
                    cs[j] = subsets[k, j]
                    Lc[j] = Lall[cs[j]]
                for a in range(3):
                    for q in range(K):
                        S1[0, a, q] = 0.0
                        St1[0, a, q] = 0.0
                t0, t1, t2, cond = _paper_sens(
                    0, Ps[k, 0], Ps[k, 1], Ps[k, 2], cs, Lc, cables, subs, b, bg, mass, rows, S1, w, St1, True
                )
                if not cond < np.inf:
                    continue
                conv_out[i, k] = True
                t_out[i, k, 0], t_out[i, k, 1], t_out[i, k, 2] = t0, t1, t2
                for a in range(3):
                    for q in range(cols.shape[0]):
                        S_out[i, k, a, q] = S1[0, a, cols[q]]
                        St_out[i, k, a, q] = St1[0, a, cols[q]]


def subset_sensitivities(robot, p, L=None, columns=None, threads=None, **solver):
    """Compiled ``sensitivity.subset_sensitivities``: every 3-cable subset of paper mode at every
    point, its P*, tensions, dP*/dθ and dt/dθ.

    Parameters
    ----------
    robot : Robot
    p : array_like, shape (N, 3) [m]
    L : array_like, shape (N, m) [m], optional
    columns : sequence of int, optional
    threads : int, optional
    solver : tol, maxiter.

    Returns
    -------
    dict
        As ``sensitivity.subset_sensitivities``.
    """
    require_point_mass(
        robot,
        "subset_sensitivities (paper mode)",
        "cdpr.solve.sensitivities (redundancy: physical, the pose equilibrium)",
        P=p,
    )
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    n, m = len(p), robot.m
    cols = np.arange(7 * m + 1) if columns is None else np.asarray(columns, dtype=np.int64)
    set_threads(threads)
    opts = newton_options({**NEWTON_DEFAULTS, **solver})
    Lin = commanded_input(L, n, m)
    ns = len(robot.subsets)
    P = np.empty((n, ns, 3))
    t = np.empty((n, ns, 3))
    conv = np.empty((n, ns), dtype=np.bool_)
    S = np.empty((n, ns, 3, len(cols)))
    St = np.empty((n, ns, 3, len(cols)))
    if n:
        _subsets_points(
            p, Lin, cable_arrays(robot), subset_arrays(robot), -robot.platform.w_ext,
            -robot.platform.gravity_force, robot.platform.mass,
            opts, cols.astype(np.int64), P, t, conv, S, St,
        )  # fmt: skip
    T_a = robot.T_a[robot.subsets]
    with np.errstate(invalid="ignore"):
        adm = conv & (t >= 0).all(axis=2) & (t <= T_a).all(axis=2)
    return {
        "P": P,
        "t": t,
        "converged": conv,
        "admissible": adm,
        "S": S,
        "St": St,
        "T_a": T_a,
        "columns": cols,
    }


@njit(cache=True, parallel=True, error_model="numpy")
def _linear_dp(dp0, S, valid, has_t, t0, St, T_a, delta, out):
    """out[s, i] = min over the valid slots c of point i whose linearised tensions lie in [0, T_a]
    (when ``has_t``) of |dp0[i, c] + S[i, c] delta[s]|; NaN where none (``uncertainty.Linearisation``)."""
    N, C = valid.shape
    k = S.shape[3]
    ns = delta.shape[0]
    for i in prange(N):
        for s in range(ns):
            best = np.inf
            for c in range(C):
                if not valid[i, c]:
                    continue
                if has_t:
                    adm = True
                    for a in range(3):
                        t = t0[i, c, a]
                        for q in range(k):
                            t += St[i, c, a, q] * delta[s, q]
                        if t < 0.0 or t > T_a[c, a]:
                            adm = False
                            break
                    if not adm:
                        continue
                v2 = 0.0
                for a in range(3):
                    v = dp0[i, c, a]
                    for q in range(k):
                        v += S[i, c, a, q] * delta[s, q]
                    v2 += v * v
                best = min(best, math.sqrt(v2))
            out[s, i] = best if best < np.inf else np.nan


def linear_dp(dp0, S, valid, delta, t0=None, St=None, T_a=None, threads=None):
    """Compiled ``uncertainty.Linearisation.dp``: the smallest ‖dp‖ over the admissible linearised
    slots of every point, for every parameter change.

    Parameters
    ----------
    dp0 : ndarray, shape (N, C, 3) [m]
    S : ndarray, shape (N, C, 3, k)
        Sensitivities of the slots (in τ, see ``uncertainty.Linearisation``).
    valid : ndarray, shape (N, C) bool
    delta : ndarray, shape (n, k)
        τ(θ) - τ(θ_0) per sample.
    t0 : ndarray, shape (N, C, 3) [N], optional
    St : ndarray, shape (N, C, 3, k), optional
    T_a : ndarray, shape (C, 3) [N], optional
        Tensions, their sensitivities and the admissible tensions (paper mode).
    threads : int, optional

    Returns
    -------
    dp : ndarray, shape (n, N) [m]
        NaN where no slot is admissible.
    """
    set_threads(threads)
    N, C = valid.shape
    has_t = t0 is not None
    if not has_t:
        t0 = np.zeros((N, C, 3))
        St = np.zeros((N, C, 3, S.shape[3]))
        T_a = np.zeros((C, 3))
    out = np.empty((len(delta), N))
    _linear_dp(
        np.ascontiguousarray(dp0),
        np.ascontiguousarray(S),
        np.ascontiguousarray(valid),
        has_t,
        np.ascontiguousarray(t0),
        np.ascontiguousarray(St),
        np.ascontiguousarray(T_a, dtype=float),
        np.ascontiguousarray(delta, dtype=float),
        out,
    )
    return out


@njit(cache=True, parallel=True, error_model="numpy")
def _linear_positions(dp0, S, delta, out):
    """out[s, i] = dp0[i] + S[i] delta[s] (``models.sensitivity.linear_positions``)."""
    N, k = S.shape[0], S.shape[2]
    for i in prange(N):
        for s in range(delta.shape[0]):
            for a in range(3):
                v = dp0[i, a]
                for q in range(k):
                    v += S[i, a, q] * delta[s, q]
                out[s, i, a] = v


def linear_positions(dp0, S, delta, threads=None):
    """Compiled ``models.sensitivity.linear_positions``: dp0 + S δ of one slot for every parameter
    change, points in parallel.

    Parameters
    ----------
    dp0 : ndarray, shape (N, 3) [m]
    S : ndarray, shape (N, 3, k) [m per unit of τ]
    delta : ndarray, shape (n, k) [unit of τ]
    threads : int, optional

    Returns
    -------
    ndarray, shape (n, N, 3) [m]
    """
    set_threads(threads)
    delta = np.ascontiguousarray(np.atleast_2d(delta), dtype=float)
    out = np.empty((len(delta), len(dp0), 3))
    _linear_positions(
        np.ascontiguousarray(dp0, dtype=float), np.ascontiguousarray(S, dtype=float), delta, out
    )
    return out
