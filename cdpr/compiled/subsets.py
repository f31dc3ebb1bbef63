"""Compiled DEGM_E over many points: the batched-Newton solver and the paper-mode subset choice
of ``redundancy.solve_points``, fused into one numba kernel that runs in parallel over points.

Same equations, same analytic-Jacobian Newton and stop rule, same tolerances, tie-break and
status rules as the numpy path (``direct._newton`` + ``redundancy.solve_points``); a test checks
that both give the same table. The numpy path stays the reference; this one is what the CLI and
pipeline use.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import njit, prange

from cdpr.models.direct import NEWTON_DEFAULTS
from cdpr.models.pulleys import RHO_EPS, SWIVEL_RHO_MIN
from cdpr.models.results import STATUSES
from cdpr.models.statics import DET_EPS
from cdpr.models.subsets import TIE_TOL

TWO_PI = 2.0 * math.pi
ST_OK, ST_SLACK, ST_OVER, ST_INACC, ST_NOCONV = (
    STATUSES.index(s) for s in ("ok", "slack", "over_tension", "inaccessible", "not_converged")
)


@njit(cache=True, inline="always", error_model="numpy")
def _cable(px, py, pz, Ax, Ay, Az, kind, h, rp, d, inx, iny):
    """One cable's pulleys.CableGeometry at P: L_TE, u = (D - P)/|D - P|, |D - P|, inside,
    swivel, e_perp (x, y), and the DR arm terms arm, beta, eps, uC_beta (zero for SR and fixed).

    Same geometry as pulleys.pulley_state without its angles: with cos(delta) = r_p/R and
    sin(delta) = l/R, the tangent directions follow from angle-sum identities, and the wrap angle
    gamma = theta_K - theta_D (mod 2 pi) needs a single atan2."""
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
    swivel = Ds / rho if rho > SWIVEL_RHO_MIN else 0.0  # pulleys.total_length_and_direction
    # u_C . beta, u_C = (K - C)/l_d in the plane, beta = (-bhw, bhs) the arm's in-plane normal
    uCb = ((Hs + rp * cK) * -bhw + (Hw + rp * sK + d) * bhs) / (ld if ld > 0.0 else 1.0)
    i_n = 1.0 / n
    return (
        L,
        vx * i_n,
        vy * i_n,
        vz * i_n,
        n,
        inside,
        swivel,
        -esy,
        esx,
        arm,
        -bhw * esx,
        -bhw * esy,
        bhs,
        ens * esx,
        ens * esy,
        enw,
        uCb,
    )


@njit(cache=True, inline="always", error_model="numpy")
def _residual(px, py, pz, s0, s1, s2, A, kind, h, rp, d, inward, L0, L1, L2, ES, bx, by, bz):
    """F = L_TE(P) - Lc (1 + t/(E S)) (E S per cable) for subset (s0, s1, s2), t from equilibrium (statics.tensions),
    the Jacobian dF/dP and dt/dP (direct._Subset.residual). Scalars only: no allocation in the hot loop.

    Returns (F (3), t (3), J (9, row-major), dt/dP (9, row-major), valid)."""
    (La, ax, ay, az, la, ia, sa, pax, pay, qa, bax, bay, baz, eax, eay, eaz, ca) = _cable(
        px, py, pz, A[s0, 0], A[s0, 1], A[s0, 2], kind[s0], h[s0], rp[s0], d[s0], inward[s0, 0], inward[s0, 1]
    )
    (Lb, bx_, by_, bz_, lb, ib, sb, pbx, pby, qb, bbx, bby, bbz, ebx, eby, ebz, cb) = _cable(
        px, py, pz, A[s1, 0], A[s1, 1], A[s1, 2], kind[s1], h[s1], rp[s1], d[s1], inward[s1, 0], inward[s1, 1]
    )
    (Lg, cx, cy, cz, lg, ig, sg, pgx, pgy, qg, bgx, bgy, bgz, egx, egy, egz, cg) = _cable(
        px, py, pz, A[s2, 0], A[s2, 1], A[s2, 2], kind[s2], h[s2], rp[s2], d[s2], inward[s2, 0], inward[s2, 1]
    )
    valid = not (ia or ib or ig) and pz < A[s0, 2] and pz < A[s1, 2] and pz < A[s2, 2]
    # cofactor rows of M = [u_a u_b u_c]: M^{-1} = [r0; r1; r2] / det
    r0x, r0y, r0z = by_ * cz - bz_ * cy, bz_ * cx - bx_ * cz, bx_ * cy - by_ * cx
    r1x, r1y, r1z = cy * az - cz * ay, cz * ax - cx * az, cx * ay - cy * ax
    r2x, r2y, r2z = ay * bz_ - az * by_, az * bx_ - ax * bz_, ax * by_ - ay * bx_
    det = ax * r0x + ay * r0y + az * r0z
    if abs(det) < DET_EPS:
        nan = np.nan
        return (
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            nan,
            False,
        )
    idet = 1.0 / det
    t0 = (r0x * bx + r0y * by + r0z * bz) * idet
    t1 = (r1x * bx + r1y * by + r1z * bz) * idet
    t2 = (r2x * bx + r2y * by + r2z * bz) * idet
    Ea, Eb, Eg = ES[s0], ES[s1], ES[s2]
    F0 = La - L0 * (1.0 + t0 / Ea)
    F1 = Lb - L1 * (1.0 + t1 / Eb)
    F2 = Lg - L2 * (1.0 + t2 / Eg)
    valid = valid and math.isfinite(F0) and math.isfinite(F1) and math.isfinite(F2)
    # G = sum_j t_j du_j/dP (statics.tension_gradient): the symmetric part, the swivel term in the
    # horizontal normal e_perp of each cable plane, and the DR arm term v_j eps_j^T
    wa, wb, wg = t0 / la, t1 / lb, t2 / lg
    ws = wa + wb + wg
    qsa, qsb, qsg = wa * sa, wb * sb, wg * sg
    uba, ubb, ubg = (
        ax * bax + ay * bay + az * baz,
        bx_ * bbx + by_ * bby + bz_ * bbz,
        cx * bgx + cy * bgy + cz * bgz,
    )
    ka, kb, kg = wa * qa, wb * qb, wg * qg
    vax, vay, vaz = ka * (bax - uba * ax), ka * (bay - uba * ay), ka * (baz - uba * az)
    vbx, vby, vbz = kb * (bbx - ubb * bx_), kb * (bby - ubb * by_), kb * (bbz - ubb * bz_)
    vgx, vgy, vgz = kg * (bgx - ubg * cx), kg * (bgy - ubg * cy), kg * (bgz - ubg * cz)
    Sxx = (
        -ws
        + wa * ax * ax
        + wb * bx_ * bx_
        + wg * cx * cx
        + qsa * pax * pax
        + qsb * pbx * pbx
        + qsg * pgx * pgx
    )
    Sxy = wa * ax * ay + wb * bx_ * by_ + wg * cx * cy + qsa * pax * pay + qsb * pbx * pby + qsg * pgx * pgy
    Sxz = wa * ax * az + wb * bx_ * bz_ + wg * cx * cz
    Syy = (
        -ws
        + wa * ay * ay
        + wb * by_ * by_
        + wg * cy * cy
        + qsa * pay * pay
        + qsb * pby * pby
        + qsg * pgy * pgy
    )
    Syz = wa * ay * az + wb * by_ * bz_ + wg * cy * cz
    Szz = -ws + wa * az * az + wb * bz_ * bz_ + wg * cz * cz
    Gxx = Sxx + vax * eax + vbx * ebx + vgx * egx
    Gxy = Sxy + vax * eay + vbx * eby + vgx * egy
    Gxz = Sxz + vax * eaz + vbx * ebz + vgx * egz
    Gyx = Sxy + vay * eax + vby * ebx + vgy * egx
    Gyy = Syy + vay * eay + vby * eby + vgy * egy
    Gyz = Syz + vay * eaz + vby * ebz + vgy * egz
    Gzx = Sxz + vaz * eax + vbz * ebx + vgz * egx
    Gzy = Syz + vaz * eay + vbz * eby + vgz * egy
    Gzz = Szz + vaz * eaz + vbz * ebz + vgz * egz
    # dt/dP = -M^{-1} G (row j: -(r_j G)/det)
    T00 = -(r0x * Gxx + r0y * Gyx + r0z * Gzx) * idet
    T01 = -(r0x * Gxy + r0y * Gyy + r0z * Gzy) * idet
    T02 = -(r0x * Gxz + r0y * Gyz + r0z * Gzz) * idet
    T10 = -(r1x * Gxx + r1y * Gyx + r1z * Gzx) * idet
    T11 = -(r1x * Gxy + r1y * Gyy + r1z * Gzy) * idet
    T12 = -(r1x * Gxz + r1y * Gyz + r1z * Gzz) * idet
    T20 = -(r2x * Gxx + r2y * Gyx + r2z * Gzx) * idet
    T21 = -(r2x * Gxy + r2y * Gyy + r2z * Gzy) * idet
    T22 = -(r2x * Gxz + r2y * Gyz + r2z * Gzz) * idet
    # J = dL_TE/dP - diag(L/ES) dt/dP, dL_TE/dP = -u + arm ((u + u_C) . beta) eps (statics.length_gradient)
    k0, k1, k2 = L0 / Ea, L1 / Eb, L2 / Eg
    ma, mb, mg = qa * (uba + ca), qb * (ubb + cb), qg * (ubg + cg)
    J00, J01, J02 = -ax + ma * eax - k0 * T00, -ay + ma * eay - k0 * T01, -az + ma * eaz - k0 * T02
    J10, J11, J12 = -bx_ + mb * ebx - k1 * T10, -by_ + mb * eby - k1 * T11, -bz_ + mb * ebz - k1 * T12
    J20, J21, J22 = -cx + mg * egx - k2 * T20, -cy + mg * egy - k2 * T21, -cz + mg * egz - k2 * T22
    return (
        F0,
        F1,
        F2,
        t0,
        t1,
        t2,
        J00,
        J01,
        J02,
        J10,
        J11,
        J12,
        J20,
        J21,
        J22,
        T00,
        T01,
        T02,
        T10,
        T11,
        T12,
        T20,
        T21,
        T22,
        valid,
    )


@njit(cache=True, error_model="numpy")
def _newton(
    p0x, p0y, p0z, s0, s1, s2, A, kind, h, rp, d, inward, L0, L1, L2, ES, bx, by, bz, tol, maxiter, max_step
):
    """direct._newton (analytic Jacobian, same stop rule) for one point and one subset.

    Returns (Px, Py, Pz, t0, t1, t2, iterations, converged, exists)."""
    px, py, pz = p0x, p0y, p0z
    conv = False
    exists = True
    it = 0
    prev = 0.0
    for _ in range(maxiter):
        (
            F0,
            F1,
            F2,
            t0,
            t1,
            t2,
            jx0,
            jy0,
            jz0,
            jx1,
            jy1,
            jz1,
            jx2,
            jy2,
            jz2,
            T00,
            T01,
            T02,
            T10,
            T11,
            T12,
            T20,
            T21,
            T22,
            valid,
        ) = _residual(px, py, pz, s0, s1, s2, A, kind, h, rp, d, inward, L0, L1, L2, ES, bx, by, bz)
        # solve J step = -F by cofactors (statics.solve3); columns (jx., jy., jz.)
        q0x, q0y, q0z = jy1 * jz2 - jy2 * jz1, jy2 * jz0 - jy0 * jz2, jy0 * jz1 - jy1 * jz0
        q1x, q1y, q1z = jz1 * jx2 - jz2 * jx1, jz2 * jx0 - jz0 * jx2, jz0 * jx1 - jz1 * jx0
        q2x, q2y, q2z = jx1 * jy2 - jx2 * jy1, jx2 * jy0 - jx0 * jy2, jx0 * jy1 - jx1 * jy0
        det = jx0 * q0x + jx1 * q0y + jx2 * q0z
        it += 1
        ok = abs(det) >= DET_EPS
        sx = sy = sz = 0.0
        if ok:
            idet = -1.0 / det
            sx = (q0x * F0 + q0y * F1 + q0z * F2) * idet
            sy = (q1x * F0 + q1y * F1 + q1z * F2) * idet
            sz = (q2x * F0 + q2y * F1 + q2z * F2) * idet
            ok = math.isfinite(sx) and math.isfinite(sy) and math.isfinite(sz)
        if not valid or not ok:
            exists = False
            break
        norm = math.sqrt(sx * sx + sy * sy + sz * sz)
        if norm < tol or norm * norm < tol * prev:  # converged: take this last step (direct._newton)
            px += sx
            py += sy
            pz += sz
            t0 += T00 * sx + T01 * sy + T02 * sz
            t1 += T10 * sx + T11 * sy + T12 * sz
            t2 += T20 * sx + T21 * sy + T22 * sz
            conv = True
            break
        scale = min(1.0, max_step / max(norm, 1e-300))
        px += sx * scale
        py += sy * scale
        pz += sz * scale
        prev = norm * scale
    else:  # iteration cap: evaluate at the last P
        out = _residual(px, py, pz, s0, s1, s2, A, kind, h, rp, d, inward, L0, L1, L2, ES, bx, by, bz)
        t0, t1, t2, valid = out[3], out[4], out[5], out[-1]
    exists = exists and valid
    return px, py, pz, t0, t1, t2, it, conv and exists, exists


@njit(cache=True, error_model="numpy")
def _solve_subset(
    k,
    i,
    p,
    A,
    kind,
    h,
    rp,
    d,
    inward,
    subsets,
    Lall,
    ES,
    b,
    tol,
    maxiter,
    max_step,
    Ps,
    ts,
    its,
    conv,
    exi,
    dps,
):
    s0, s1, s2 = subsets[k, 0], subsets[k, 1], subsets[k, 2]
    px, py, pz, t0, t1, t2, it, cv, ex = _newton(
        p[i, 0],
        p[i, 1],
        p[i, 2],
        s0,
        s1,
        s2,
        A,
        kind,
        h,
        rp,
        d,
        inward,
        Lall[s0],
        Lall[s1],
        Lall[s2],
        ES,
        b[0],
        b[1],
        b[2],
        tol,
        maxiter,
        max_step,
    )
    Ps[k, 0], Ps[k, 1], Ps[k, 2] = px, py, pz
    ts[k, 0], ts[k, 1], ts[k, 2] = t0, t1, t2
    its[k], conv[k], exi[k] = it, cv, ex
    dps[k] = math.sqrt((px - p[i, 0]) ** 2 + (py - p[i, 1]) ** 2 + (pz - p[i, 2]) ** 2)


#: Points per parallel work item: per-point scratch arrays are allocated once per chunk.
CHUNK = 256


@njit(cache=True, parallel=True, error_model="numpy")
def _solve_points(
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
    b,
    T_a,
    tol,
    maxiter,
    max_step,
    prune,
    P_s,
    dp_out,
    t_out,
    sub_out,
    it_out,
    st_out,
    work,
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
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            _solve_one(
                i,
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
                b,
                T_a,
                tol,
                maxiter,
                max_step,
                prune,
                P_s,
                dp_out,
                t_out,
                sub_out,
                it_out,
                st_out,
                work,
                Lall,
                Ps,
                ts,
                its,
                conv,
                exi,
                dps,
                solved,
                adm,
                gap,
            )


@njit(cache=True, error_model="numpy")
def _solve_one(
    i,
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
    b,
    T_a,
    tol,
    maxiter,
    max_step,
    prune,
    P_s,
    dp_out,
    t_out,
    sub_out,
    it_out,
    st_out,
    work,
    Lall,
    Ps,
    ts,
    its,
    conv,
    exi,
    dps,
    solved,
    adm,
    gap,
):
    """Point i: solve the subsets (pruned, see solve_points_fast) and choose as redundancy.solve_points.
    The commanded lengths are Lin[i] when Lin has rows, else L_TS at p[i] (eq. 2)."""
    ns = subsets.shape[0]
    m = A.shape[0]
    for c in range(m):
        if Lin.shape[0] > 0:
            Lall[c] = Lin[i, c]
        else:
            Lall[c] = (
                math.sqrt((p[i, 0] - A[c, 0]) ** 2 + (p[i, 1] - A[c, 1]) ** 2 + (p[i, 2] - A[c, 2]) ** 2)
                + d[c]
            )
    for k in range(ns):
        Ps[k, 0] = Ps[k, 1] = Ps[k, 2] = np.nan
        ts[k, 0] = ts[k, 1] = ts[k, 2] = np.nan
        its[k] = 0
        conv[k] = exi[k] = solved[k] = adm[k] = False
        dps[k] = np.inf
        g = -np.inf
        for e in range(3):
            g = max(g, edges[k, e, 0] * p[i, 0] + edges[k, e, 1] * p[i, 1] - edges[k, e, 2])
        gap[k] = g - margin[k]  # lower bound of |dp| of any admissible solution of subset k
    best = np.inf
    # pass 0: subsets whose (widened) triangle holds the point; pass 1: the others, unless their bound
    # already exceeds the best admissible |dp|; pass 2: everything, when nothing is admissible
    for pss in range(3):
        for k in range(ns):
            if solved[k]:
                continue
            if pss == 0 and gap[k] > 0.0:
                continue
            if pss == 1 and prune and gap[k] > best + TIE_TOL:
                continue
            if pss == 2 and best < np.inf:
                break
            _solve_subset(
                k,
                i,
                p,
                A,
                kind,
                h,
                rp,
                d,
                inward,
                subsets,
                Lall,
                ES,
                b,
                tol,
                maxiter,
                max_step,
                Ps,
                ts,
                its,
                conv,
                exi,
                dps,
            )
            solved[k] = True
            if (
                conv[k]
                and ts[k, 0] >= 0
                and ts[k, 1] >= 0
                and ts[k, 2] >= 0
                and ts[k, 0] <= T_a[subsets[k, 0]]
                and ts[k, 1] <= T_a[subsets[k, 1]]
                and ts[k, 2] <= T_a[subsets[k, 2]]
            ):
                best = min(best, dps[k])
    nsolved = 0
    for k in range(ns):
        nsolved += solved[k]
    work[i] = nsolved
    # paper-mode choice, as redundancy.solve_points
    any_adm, any_conv, any_low, any_nc = False, False, False, False
    for k in range(ns):
        if not solved[k]:
            continue
        low = ts[k, 0] >= 0 and ts[k, 1] >= 0 and ts[k, 2] >= 0
        high = (
            ts[k, 0] <= T_a[subsets[k, 0]]
            and ts[k, 1] <= T_a[subsets[k, 1]]
            and ts[k, 2] <= T_a[subsets[k, 2]]
        )
        adm[k] = conv[k] and low and high
        any_adm = any_adm or adm[k]
        any_conv = any_conv or conv[k]
        any_low = any_low or (conv[k] and low)
        any_nc = any_nc or ((not conv[k]) and exi[k])
    best = np.inf
    for k in range(ns):
        key = dps[k] if (adm[k] if any_adm else conv[k]) else np.inf
        if key < best:
            best = key
    choice = -1
    if best < np.inf:
        for k in range(ns):
            key = dps[k] if (adm[k] if any_adm else conv[k]) else np.inf
            if key <= best + TIE_TOL:
                choice = k
                break
    if any_adm:
        st_out[i] = ST_OK
    elif any_low:
        st_out[i] = ST_OVER
    elif any_conv:
        st_out[i] = ST_SLACK
    elif any_nc:
        st_out[i] = ST_NOCONV
    else:
        st_out[i] = ST_INACC
    for c in range(m):
        t_out[i, c] = np.nan
    if choice >= 0:
        P_s[i, 0], P_s[i, 1], P_s[i, 2] = Ps[choice, 0], Ps[choice, 1], Ps[choice, 2]
        dp_out[i] = dps[choice]
        for j in range(3):
            t_out[i, subsets[choice, j]] = ts[choice, j]
            sub_out[i, j] = subsets[choice, j]
        it_out[i] = its[choice]
    else:
        P_s[i, 0] = P_s[i, 1] = P_s[i, 2] = np.nan
        dp_out[i] = np.nan
        sub_out[i, 0] = sub_out[i, 1] = sub_out[i, 2] = -1
        it_out[i] = its[0]


def subset_edges(robot):
    """Outward edge lines (n_x, n_y, c) of each subset's anchor triangle seen from above, so that
    n . p - c is the signed distance of p outside that edge; and the margin max(h + r_p)."""
    subs = robot.subsets
    edges = np.empty((len(subs), 3, 3))
    margin = np.empty(len(subs))
    for k, s in enumerate(subs):
        xy = robot.A[s, :2]
        e1, e2 = xy[1] - xy[0], xy[2] - xy[0]
        area2 = e1[0] * e2[1] - e1[1] * e2[0]
        for e in range(3):
            a, b = xy[e], xy[(e + 1) % 3]
            v = b - a
            nrm = np.array([v[1], -v[0]]) * (1.0 if area2 > 0 else -1.0)
            ln = np.linalg.norm(nrm)
            nrm = nrm / ln if ln > 0 else nrm
            edges[k, e] = (nrm[0], nrm[1], nrm @ a)
        if abs(area2) < 1e-12:  # degenerate triangle: never prune it on geometry
            edges[k, :, :] = 0.0
            edges[k, :, 2] = np.inf
        margin[k] = float(np.max(robot.h[s] + robot.r_p[s]))
    return edges, margin


def solve_points_fast(robot, p, tol=None, maxiter=None, threads=None, prune=True, L=None):
    """Fast equivalent of ``redundancy.solve_points(robot, p, method="newton", L=L)`` (same keys
    except the per-subset arrays). ``threads`` caps numba's threads (default: all cores). ``L``
    (N, m) [m]: commanded total lengths of every cable, default L_TS(p) of ``robot`` (eq. 2); give
    them to command a robot whose parameters differ from the model that computed the lengths."""
    o = NEWTON_DEFAULTS
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    n, m = len(p), robot.m
    Lin = (
        np.empty((0, m))
        if L is None
        else np.ascontiguousarray(np.broadcast_to(np.asarray(L, dtype=float), (n, m)))
    )
    if threads:
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    P_s = np.empty((n, 3))
    dp = np.empty(n)
    t = np.empty((n, m))
    sub = np.empty((n, 3), dtype=np.intp)
    it = np.empty(n, dtype=np.int32)
    st = np.empty(n, dtype=np.int8)
    work = np.empty(n, dtype=np.int32)
    if n:
        edges, margin = subset_edges(robot)
        _solve_points(
            p,
            Lin,
            robot.A,
            robot.kind.astype(np.int64),
            robot.h,
            robot.r_p,
            robot.d,
            np.ascontiguousarray(robot.inward),
            robot.subsets.astype(np.int64),
            edges,
            margin,
            robot.ES,
            -robot.platform.w_ext,
            robot.T_a,
            o["tol"] if tol is None else tol,
            o["maxiter"] if maxiter is None else maxiter,
            o["max_step"],
            prune,
            P_s,
            dp,
            t,
            sub,
            it,
            st,
            work,
        )
    return {
        "p": p,
        "P_s": P_s,
        "dp": dp,
        "t": t,
        "subset": sub,
        "iterations": it,
        "status_code": st,
        "status": np.asarray(STATUSES)[st],
        "subset_solves": work,
    }
