"""Compiled sensitivities dP*/dθ: ``sensitivity.sensitivities`` in the compiled engines' kernels.

Each point is solved by the compiled solver (``fast._solve_one`` for paper mode,
``fast_physical._solve_one`` for the physical equilibrium) and, in the same pass, its cables are
evaluated once more at P* with their partial derivatives (``_cable_sens``): the Jacobian J and
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

import numba
import numpy as np
from numba import njit, prange

from cdpr.compiled import equilibrium as fast_physical
from cdpr.compiled import subsets as fast
from cdpr.models.direct import NEWTON_DEFAULTS
from cdpr.models.equilibrium import (
    FTOL_REL,
    PHYSICAL_DEFAULTS,
    hull_halfplanes,
    physical_result,
    start_points,
)
from cdpr.models.inverse import L_TS
from cdpr.models.pulleys import RHO_EPS, SWIVEL_RHO_MIN
from cdpr.models.results import STATUSES
from cdpr.models.sensitivity import COND_MAX, GAP_TOL, T_TOL
from cdpr.models.statics import DET_EPS
from cdpr.parameters import parameter_names

TWO_PI = 2.0 * math.pi
#: Layout of one cable's row in the scratch array of ``_cable_sens``.
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
CHUNK = 256
ST_OK = STATUSES.index("ok")


@njit(cache=True, error_model="numpy")
def _cable_sens(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny, out):
    """One cable at P: L_TE, u, |l_E|, dL_TE/dP, du/dP (row-major, du_a/dP_b), and the partials with
    respect to h, r_p, d (``sensitivity.cable_partials``), written to ``out`` (layout ``C_*``).
    The geometry is ``fast._cable``'s, line for line."""
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
        ens, enw = -wP / nP, rho / nP
    else:
        Hs, Hw = h, 0.0
    rp2 = rp * rp
    rs, rw = rho - Hs, wP - Hw
    R2 = rs * rs + rw * rw
    inside = R2 <= rp2 and rp > 0.0
    lE = math.sqrt(max(R2 - rp2, 0.0))
    if R2 > 0.0:
        iR2 = 1.0 / R2
        cD, sD = (rs * rp - rw * lE) * iR2, (rw * rp + rs * lE) * iR2
    else:
        cD, sD = 0.0, 1.0
    cs, cw = -Hs, -d - Hw
    RC2 = cs * cs + cw * cw
    inside = inside or (RC2 <= rp2 and rp > 0.0)
    ld = math.sqrt(max(RC2 - rp2, 0.0))
    if RC2 > 0.0:
        iRC2 = 1.0 / RC2
        cK, sK = (cs * rp + cw * ld) * iRC2, (cw * rp - cs * ld) * iRC2
    else:
        cK, sK = 0.0, -1.0
    gamma = math.atan2(sK * cD - cK * sD, cK * cD + sK * sD)
    if gamma < 0.0:
        gamma += TWO_PI
    L = ld + rp * gamma + lE
    Ds, Dw = Hs + rp * cD, Hw + rp * sD
    vx, vy, vz = Ax + Ds * esx - px, Ay + Ds * esy - py, Az + Dw - pz
    n = math.sqrt(vx * vx + vy * vy + vz * vz)
    if n <= 0.0:
        n = 1.0
    sw = Ds / rho if rho > SWIVEL_RHO_MIN else 0.0
    ldd = ld if ld > 0.0 else 1.0
    ucs, ucw = (Hs + rp * cK) / ldd, (Hw + rp * sK + d) / ldd  # u_C in the plane (C toward K)
    uCb = ucs * -bhw + ucw * bhs
    i_n = 1.0 / n
    ux, uy, uz = vx * i_n, vy * i_n, vz * i_n
    btx, bty, btz = -bhw * esx, -bhw * esy, bhs  # beta, the arm's normal (DR)
    epx, epy, epz = ens * esx, ens * esy, enw  # eps, the strand's normal (DR)
    ub = ux * btx + uy * bty + uz * btz
    q = arm * (ub + uCb)
    out[C_L] = L
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
    out[C_DLR] = gamma
    out[C_DUR], out[C_DUR + 1], out[C_DUR + 2] = cD * esx * i_n, cD * esy * i_n, sD * i_n
    out[C_DLD] = ucw
    out[C_INSIDE] = 1.0 if inside else 0.0


@njit(cache=True, inline="always")
def _geo(cab, j, g, du):
    """Partial g (0 h, 1 r_p, 2 d, 3..5 A_x..A_z) of cable row j of ``cab``: writes du (3), returns dL."""
    if g == 0:
        for a in range(3):
            du[a] = cab[j, C_DUH + a]
        return cab[j, C_DLH]
    if g == 1:
        for a in range(3):
            du[a] = cab[j, C_DUR + a]
        return cab[j, C_DLR]
    if g == 2:
        for a in range(3):
            du[a] = 0.0
        return cab[j, C_DLD]
    b = g - 3  # d/dA_b = -d/dP_b
    for a in range(3):
        du[a] = -cab[j, C_DUDP + 3 * a + b]
    return -cab[j, C_DLDP + b]


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
def _paper_sens(i, Px, Py, Pz, cs, Lc, A, kind, h, rp, d, inward, ES, E, bz, mass, m, cab, S, w, St, want_t):
    """dP*/dθ of paper mode at P* for the subset cs (3 cables) with commanded lengths Lc (3), written
    to S[i] (``sensitivity.paper_jacobian_terms`` and ``implicit_solve``); returns the subset's
    tensions at P* and the condition number of J (inf where singular). ``w`` (8, 3, 3): scratch.
    With ``want_t``, also the total dt/dθ = dt/dP dP*/dθ + dt/dθ|_P into St[i]."""
    for j in range(3):
        c = cs[j]
        _cable_sens(
            Px,
            Py,
            Pz,
            A[c, 0],
            A[c, 1],
            A[c, 2],
            kind[c],
            h[c],
            rp[c],
            d[c],
            inward[c, 0],
            inward[c, 1],
            cab[j],
        )
    # M_u = [u_0 u_1 u_2] (columns); M_u^-1 rows r_j / det
    u, r, G, J, Jinv, T = w[0], w[1], w[2], w[3], w[4], w[7]
    t, kL, du, f, pt = w[5, 0], w[5, 1], w[5, 2], w[6, 0], w[6, 1]
    for j in range(3):
        for a in range(3):
            u[j, a] = cab[j, C_U + a]
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
        t[j] = r[j, 2] * bz * idet
        kL[j] = Lc[j] / ES[cs[j]]
    for a in range(3):
        for b in range(3):
            G[a, b] = 0.0
    for j in range(3):
        for a in range(3):
            for b in range(3):
                G[a, b] += t[j] * cab[j, C_DUDP + 3 * a + b]
    for j in range(3):
        for b in range(3):
            T[j, b] = -(r[j, 0] * G[0, b] + r[j, 1] * G[1, b] + r[j, 2] * G[2, b]) * idet
            J[j, b] = cab[j, C_DLDP + b] - kL[j] * T[j, b]
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
            dL = _geo(cab, j, g, du)
            for k in range(3):
                pt[k] = -(r[k, 0] * du[0] + r[k, 1] * du[1] + r[k, 2] * du[2]) * t[j] * idet
                f[k] = (dL if k == j else 0.0) - kL[k] * pt[k]
            col = (g + 1) * m + c if g < 3 else 4 * m + 3 * c + (g - 3)
            _put(S, i, col, Jinv, f[0], f[1], f[2])
            if want_t:
                _put_t(St, S, i, col, T, pt)
    for k in range(3):
        f[k] = -kL[k] * t[k] / mass
        pt[k] = t[k] / mass
    _put(S, i, 7 * m, Jinv, f[0], f[1], f[2])
    if want_t:
        _put_t(St, S, i, 7 * m, T, pt)
    return t[0], t[1], t[2], _cond(J, Jinv)


@njit(cache=True, parallel=True, error_model="numpy")
def _paper_points(
    p,
    Lin,
    A,
    kind,
    h,
    rp,
    d,
    inward,
    subsets,
    edges,
    margin,
    ES,
    E,
    b,
    mass,
    T_a,
    tol,
    maxiter,
    max_step,
    gap_tol,
    P_s,
    dp_out,
    t_out,
    sub_out,
    it_out,
    st_out,
    work,
    S,
    gap_out,
    tm_out,
    cond_out,
):
    n = p.shape[0]
    ns = subsets.shape[0]
    m = A.shape[0]
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        Lall = np.empty(m)
        Ps = np.empty((ns, 3))
        ts = np.empty((ns, 3))
        its = np.empty(ns, np.int32)
        conv = np.empty(ns, np.bool_)
        exi = np.empty(ns, np.bool_)
        dps = np.empty(ns)
        solved = np.empty(ns, np.bool_)
        adm = np.empty(ns, np.bool_)
        gap = np.empty(ns)
        cab = np.empty((3, NCOL))
        cs = np.empty(3, np.int64)
        Lc = np.empty(3)
        w = np.empty((8, 3, 3))
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            fast._solve_one(
                i, p, Lin, A, kind, h, rp, d, inward, subsets, edges, margin, ES, b, T_a, tol, maxiter,
                max_step, True, P_s, dp_out, t_out, sub_out, it_out, st_out, work, Lall, Ps, ts, its, conv,
                exi, dps, solved, adm, gap,
            )  # fmt: skip
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
                    fast._solve_subset(
                        k, i, p, A, kind, h, rp, d, inward, subsets, Lall, ES, b, tol, maxiter, max_step, Ps,
                        ts, its, conv, exi, dps,
                    )  # fmt: skip
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
                i, Ps[choice, 0], Ps[choice, 1], Ps[choice, 2], cs, Lc, A, kind, h, rp, d, inward, ES, E, b[2],
                mass, m, cab, S, w, S, False,
            )  # fmt: skip
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
def _physical_points(
    p,
    P0,
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
    wx,
    wy,
    wz,
    mass,
    ztop,
    ftol,
    tol,
    maxiter,
    max_step,
    P_out,
    t_out,
    res_out,
    it_out,
    conv_out,
    ins_out,
    S,
    tm_out,
    cond_out,
):
    n = p.shape[0]
    m = A.shape[0]
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        tcur = np.empty(m)
        ttry = np.empty(m)
        cab = np.empty((m, NCOL))
        hooke = np.empty(m)
        J = np.empty((3, 3))
        Jinv = np.empty((3, 3))
        du = np.empty(3)
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            fast_physical._solve_one(
                i, p, P0, L0, A, kind, h, rp, d, inward, ES, wx, wy, wz, ztop, ftol, tol, maxiter, max_step,
                P_out, t_out, res_out, it_out, conv_out, ins_out, tcur, ttry,
            )  # fmt: skip
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
                _cable_sens(
                    Px, Py, Pz, A[c, 0], A[c, 1], A[c, 2], kind[c], h[c], rp[c], d[c], inward[c, 0], inward[c, 1],
                    cab[c],
                )  # fmt: skip
                k_ = ES[c] / L0[i, c]
                hooke[c] = k_ * (cab[c, C_L] - L0[i, c])
                t = hooke[c] if hooke[c] > 0.0 else 0.0
                ka = k_ if hooke[c] >= 0.0 else 0.0
                tm = min(tm, abs(hooke[c]))
                if hooke[c] > 0.0:
                    tm = min(tm, T_a[c] - t)
                for a in range(3):
                    for b in range(3):
                        J[a, b] += t * cab[c, C_DUDP + 3 * a + b] + ka * cab[c, C_U + a] * cab[c, C_DLDP + b]
            tm_out[i] = tm
            if not _inv3(J, Jinv):
                continue
            cond_out[i] = _cond(J, Jinv)
            for c in range(m):
                k_ = ES[c] / L0[i, c]
                t = hooke[c] if hooke[c] > 0.0 else 0.0
                ka = k_ if hooke[c] >= 0.0 else 0.0
                w = t / E[c]
                _put(S, i, c, Jinv, w * cab[c, C_U], w * cab[c, C_U + 1], w * cab[c, C_U + 2])
                for g in range(6):
                    dL = _geo(cab, c, g, du)
                    col = (g + 1) * m + c if g < 3 else 4 * m + 3 * c + (g - 3)
                    _put(
                        S,
                        i,
                        col,
                        Jinv,
                        ka * dL * cab[c, C_U] + t * du[0],
                        ka * dL * cab[c, C_U + 1] + t * du[1],
                        ka * dL * cab[c, C_U + 2] + t * du[2],
                    )
            _put(S, i, 7 * m, Jinv, wx / mass, wy / mass, wz / mass)


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
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    n, m = len(p), robot.m
    K = 7 * m + 1
    if threads:
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    a = robot.arrays
    kind = a.kind.astype(np.int64)
    inward = np.ascontiguousarray(a.inward)
    S = np.empty((n, 3, K))
    tm = np.empty(n)
    cond = np.empty(n)
    if redundancy == "paper":
        o = {**NEWTON_DEFAULTS, **solver}
        Lin = (
            np.empty((0, m))
            if L is None
            else np.ascontiguousarray(np.broadcast_to(np.asarray(L, dtype=float), (n, m)))
        )
        P_s, dp, t = np.empty((n, 3)), np.empty(n), np.empty((n, m))
        sub = np.empty((n, 3), dtype=np.intp)
        it = np.empty(n, dtype=np.int32)
        st = np.empty(n, dtype=np.int8)
        work = np.empty(n, dtype=np.int32)
        gap = np.empty(n)
        if n:
            edges, margin = fast.subset_edges(robot)
            _paper_points(
                p, Lin, a.A, kind, a.h, a.r_p, a.d, inward, robot.subsets.astype(np.int64), edges, margin,
                a.ES, a.E, -robot.platform.w_ext, robot.platform.mass, a.T_a, o["tol"], o["maxiter"],
                o["max_step"], gap_tol, P_s, dp, t, sub, it, st, work, S, gap, tm, cond,
            )  # fmt: skip
        res = {
            "p": p,
            "P_s": P_s,
            "dp": dp,
            "t": t,
            "subset": sub,
            "iterations": it,
            "status_code": st,
            "status": np.asarray(STATUSES)[st],
            "subset_solves": work,
            "dp_gap": gap,
        }
        smooth = (st == ST_OK) & (gap > gap_tol) & (tm > t_tol) & (cond < COND_MAX)
    elif redundancy == "physical":
        o = {**PHYSICAL_DEFAULTS, **solver}
        L0 = L_TS(robot, p) if L is None else np.broadcast_to(np.asarray(L, dtype=float), (n, m))
        L0 = np.ascontiguousarray(L0, dtype=float)
        P0 = start_points(robot, p)
        w = robot.platform.w_ext
        P, t = np.empty((n, 3)), np.empty((n, m))
        resid = np.empty(n)
        it = np.empty(n, dtype=np.int32)
        conv = np.empty(n, dtype=np.bool_)
        ins = np.empty(n, dtype=np.bool_)
        if n:
            _physical_points(
                p, P0, L0, a.A, kind, a.h, a.r_p, a.d, inward, a.ES, a.E, a.T_a, float(w[0]), float(w[1]),
                float(w[2]), robot.platform.mass, float(a.A[:, 2].min()), FTOL_REL * float(np.linalg.norm(w)),
                o["tol"], o["maxiter"], o["max_step"], P, t, resid, it, conv, ins, S, tm, cond,
            )  # fmt: skip
        res = physical_result(
            robot, p, P, t, resid, it, conv, ins[:, None], halfplanes=hull_halfplanes(robot)
        )
        ok = res["status"] == "ok"
        S[~ok] = np.nan
        tm = np.where(ok, tm, np.nan)
        cond = np.where(ok, cond, np.inf)
        smooth = ok & (tm > t_tol) & (cond < COND_MAX)
    else:
        raise ValueError(f"unknown redundancy {redundancy!r}; allowed: 'paper', 'physical'")
    res.update(S=S, names=parameter_names(m), smooth=smooth, margin_t=tm, cond=cond)
    return res


@njit(cache=True, parallel=True, error_model="numpy")
def _subsets_points(
    p, Lin, A, kind, h, rp, d, inward, subsets, ES, E, b, mass, tol, maxiter, max_step, cols, P_out, t_out,
    conv_out, S_out, St_out,
):  # fmt: skip
    n = p.shape[0]
    ns = subsets.shape[0]
    m = A.shape[0]
    K = 7 * m + 1
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        Lall = np.empty(m)
        Ps = np.empty((ns, 3))
        ts = np.empty((ns, 3))
        its = np.empty(ns, np.int32)
        conv = np.empty(ns, np.bool_)
        exi = np.empty(ns, np.bool_)
        dps = np.empty(ns)
        cab = np.empty((3, NCOL))
        cs = np.empty(3, np.int64)
        Lc = np.empty(3)
        w = np.empty((8, 3, 3))
        S1 = np.empty((1, 3, K))
        St1 = np.empty((1, 3, K))
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            for c in range(m):
                if Lin.shape[0] > 0:
                    Lall[c] = Lin[i, c]
                else:
                    Lall[c] = (
                        math.sqrt(
                            (p[i, 0] - A[c, 0]) ** 2 + (p[i, 1] - A[c, 1]) ** 2 + (p[i, 2] - A[c, 2]) ** 2
                        )
                        + d[c]
                    )
            for k in range(ns):
                fast._solve_subset(
                    k, i, p, A, kind, h, rp, d, inward, subsets, Lall, ES, b, tol, maxiter, max_step, Ps, ts, its,
                    conv, exi, dps,
                )  # fmt: skip
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
                    0, Ps[k, 0], Ps[k, 1], Ps[k, 2], cs, Lc, A, kind, h, rp, d, inward, ES, E, b[2], mass, m, cab,
                    S1, w, St1, True,
                )  # fmt: skip
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
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    n, m = len(p), robot.m
    cols = np.arange(7 * m + 1) if columns is None else np.asarray(columns, dtype=np.int64)
    if threads:
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    o = {**NEWTON_DEFAULTS, **solver}
    a = robot.arrays
    Lin = (
        np.empty((0, m))
        if L is None
        else np.ascontiguousarray(np.broadcast_to(np.asarray(L, dtype=float), (n, m)))
    )
    ns = len(robot.subsets)
    P = np.empty((n, ns, 3))
    t = np.empty((n, ns, 3))
    conv = np.empty((n, ns), dtype=np.bool_)
    S = np.empty((n, ns, 3, len(cols)))
    St = np.empty((n, ns, 3, len(cols)))
    if n:
        _subsets_points(
            p, Lin, a.A, a.kind.astype(np.int64), a.h, a.r_p, a.d, np.ascontiguousarray(a.inward),
            robot.subsets.astype(np.int64), a.ES, a.E, -robot.platform.w_ext, robot.platform.mass, o["tol"],
            o["maxiter"], o["max_step"], cols.astype(np.int64), P, t, conv, S, St,
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
    if threads:
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
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
