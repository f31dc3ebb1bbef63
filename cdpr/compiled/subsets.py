"""Compiled DEGM_E over many points: the batched-Newton solver and the paper-mode subset choice
of ``cdpr.models.subsets.solve_points``, fused into one numba kernel that runs in parallel over
points.

Same equations, same analytic-Jacobian Newton and stop rule, same tolerances, tie-break and
status rules as the numpy path (``cdpr.models.direct._newton`` +
``cdpr.models.subsets.solve_points``); a test checks that both give the same table. The numpy path
stays the reference; this one is what the CLI and pipeline use.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from cdpr.compiled._kernels import (
    CHUNK,
    DET_EPS,
    NEWTON_DEFAULTS,
    Cables,
    cable_arrays,
    cable_axis,
    cable_derivatives,
    cable_of,
    cable_params,
    commanded_input,
    newton_options,
    pulley_frames,
    set_threads,
)
from cdpr.errors import CdprError
from cdpr.models.results import STATUSES
from cdpr.models.subsets import TIE_TOL
from cdpr.robot import require_point_mass

ST_OK, ST_SLACK, ST_OVER, ST_INACC, ST_NOCONV = (
    STATUSES.index(s) for s in ("ok", "slack", "over_tension", "inaccessible", "not_converged")
)


class Subsets(NamedTuple):
    """The 3-cable subsets of paper mode for the kernels (``subset_arrays``): idx (ns, 3) int64 cable
    indices; edges (ns, 3, 3) and margin (ns,) [m] as ``subset_edges``; and how the robot's
    pulleys are evaluated: suspended (bool, ``Robot.suspended_point_mass``: axes +z, ``_residual``
    and the rule that P lies below the pulleys), else every cable in its pulley frame
    (``_residual_axis``) with frame (m, 3, 3) [-] (rows i_i, j_i, k_i) and ident (m,) bool (the
    frame is the identity)."""

    idx: np.ndarray
    edges: np.ndarray
    margin: np.ndarray
    suspended: bool
    frame: np.ndarray
    ident: np.ndarray


class PaperOut(NamedTuple):
    """Per-point results of the paper-mode kernel (``paper_outputs``): P_s (N, 3) [m], dp (N,) [m],
    t (N, m) [N], subset (N, 3), iterations (N,), status codes (N,) int8, subset solves (N,)."""

    P_s: np.ndarray
    dp: np.ndarray
    t: np.ndarray
    sub: np.ndarray
    it: np.ndarray
    st: np.ndarray
    work: np.ndarray


class PaperScratch(NamedTuple):
    """Per-point scratch of ``solve_point`` (``paper_scratch``, one per chunk): the commanded lengths
    Lall (m,) [m] and, per subset (ns), its solution Ps (ns, 3) [m], tensions ts (ns, 3) [N],
    iterations, converged, exists, |dp| [m], solved, admissible and the pruning bound gap [m]."""

    Lall: np.ndarray
    Ps: np.ndarray
    ts: np.ndarray
    its: np.ndarray
    conv: np.ndarray
    exi: np.ndarray
    dps: np.ndarray
    solved: np.ndarray
    adm: np.ndarray
    gap: np.ndarray


@njit(cache=True)
def paper_scratch(m, ns):
    """A ``PaperScratch`` for m cables and ns subsets (allocated, not initialised)."""
    return PaperScratch(
        np.empty(m),
        np.empty((ns, 3)),
        np.empty((ns, 3)),
        np.empty(ns, np.int32),
        np.empty(ns, np.bool_),
        np.empty(ns, np.bool_),
        np.empty(ns),
        np.empty(ns, np.bool_),
        np.empty(ns, np.bool_),
        np.empty(ns),
    )


def paper_outputs(n, m):
    """An uninitialised ``PaperOut`` for n points and m cables."""
    return PaperOut(
        np.empty((n, 3)),
        np.empty(n),
        np.empty((n, m)),
        np.empty((n, 3), dtype=np.intp),
        np.empty(n, dtype=np.int32),
        np.empty(n, dtype=np.int8),
        np.empty(n, dtype=np.int32),
    )


@njit(cache=True, inline="always")
def _no_residual():
    """What ``_residual`` returns where M = [u_a u_b u_c] is singular: NaN everywhere, not valid."""
    nan = np.nan
    return (
        nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan,
        nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan,
        False,
    )  # fmt: skip


@njit(cache=True, inline="always", error_model="numpy")
def _tensions3(ax, ay, az, bx_, by_, bz_, cx, cy, cz, bx, by, bz):
    """t = M^-1 b for M = [u_a u_b u_c] (statics.tensions, scalar form) by cofactors.

    Returns (cofactor rows r0, r1, r2 (9 values: M^-1 = [r0; r1; r2] / det), 1/det, t0, t1, t2,
    solvable = |det| >= DET_EPS)."""
    r0x, r0y, r0z = by_ * cz - bz_ * cy, bz_ * cx - bx_ * cz, bx_ * cy - by_ * cx
    r1x, r1y, r1z = cy * az - cz * ay, cz * ax - cx * az, cx * ay - cy * ax
    r2x, r2y, r2z = ay * bz_ - az * by_, az * bx_ - ax * bz_, ax * by_ - ay * bx_
    det = ax * r0x + ay * r0y + az * r0z
    if abs(det) < DET_EPS:
        return r0x, r0y, r0z, r1x, r1y, r1z, r2x, r2y, r2z, 0.0, 0.0, 0.0, 0.0, False
    idet = 1.0 / det
    t0 = (r0x * bx + r0y * by + r0z * bz) * idet
    t1 = (r1x * bx + r1y * by + r1z * bz) * idet
    t2 = (r2x * bx + r2y * by + r2z * bz) * idet
    return r0x, r0y, r0z, r1x, r1y, r1z, r2x, r2y, r2z, idet, t0, t1, t2, True


@njit(cache=True, inline="always", error_model="numpy")
def _close(r, idet, t0, t1, t2, G, dL, La, Lb, Lg, L0, L1, L2, Ea, Eb, Eg, valid):
    """The end of both residuals: F = L_TE - L (1 + t/(E S)), dt/dP = -M^-1 G (row j: -(r_j G)/det)
    and J = dL_TE/dP - diag(L/ES) dt/dP, from the cofactor rows r (9) and 1/det of ``_tensions3``,
    G = sum_j t_j du_j/dP (9, row-major) and dL_TE/dP of the three cables (9, row j cable j).

    Returns (F (3), t (3), J (9, row-major), dt/dP (9, row-major), valid and F finite)."""
    r0x, r0y, r0z, r1x, r1y, r1z, r2x, r2y, r2z = r
    Gxx, Gxy, Gxz, Gyx, Gyy, Gyz, Gzx, Gzy, Gzz = G
    F0 = La - L0 * (1.0 + t0 / Ea)
    F1 = Lb - L1 * (1.0 + t1 / Eb)
    F2 = Lg - L2 * (1.0 + t2 / Eg)
    valid = valid and math.isfinite(F0) and math.isfinite(F1) and math.isfinite(F2)
    T00 = -(r0x * Gxx + r0y * Gyx + r0z * Gzx) * idet
    T01 = -(r0x * Gxy + r0y * Gyy + r0z * Gzy) * idet
    T02 = -(r0x * Gxz + r0y * Gyz + r0z * Gzz) * idet
    T10 = -(r1x * Gxx + r1y * Gyx + r1z * Gzx) * idet
    T11 = -(r1x * Gxy + r1y * Gyy + r1z * Gzy) * idet
    T12 = -(r1x * Gxz + r1y * Gyz + r1z * Gzz) * idet
    T20 = -(r2x * Gxx + r2y * Gyx + r2z * Gzx) * idet
    T21 = -(r2x * Gxy + r2y * Gyy + r2z * Gzy) * idet
    T22 = -(r2x * Gxz + r2y * Gyz + r2z * Gzz) * idet
    k0, k1, k2 = L0 / Ea, L1 / Eb, L2 / Eg
    return (
        F0, F1, F2, t0, t1, t2,
        dL[0] - k0 * T00, dL[1] - k0 * T01, dL[2] - k0 * T02,
        dL[3] - k1 * T10, dL[4] - k1 * T11, dL[5] - k1 * T12,
        dL[6] - k2 * T20, dL[7] - k2 * T21, dL[8] - k2 * T22,
        T00, T01, T02, T10, T11, T12, T20, T21, T22,
        valid,
    )  # fmt: skip


@njit(cache=True, inline="always", error_model="numpy")
def _residual(px, py, pz, c0, c1, c2, Ea, Eb, Eg, L0, L1, L2, bx, by, bz):
    """F = L_TE(P) - Lc (1 + t/(E S)) (E S per cable) for the subset of cables with parameters
    c0, c1, c2 (``cable_params``) and axial stiffnesses Ea, Eb, Eg [N], t from equilibrium
    (statics.tensions), the Jacobian dF/dP and dt/dP (direct._Subset.residual), for pulleys with +z
    axes: G and dL_TE/dP written with the vertical cable plane's terms. Scalars only: no
    allocation in the hot loop.

    Returns (F (3), t (3), J (9, row-major), dt/dP (9, row-major), valid)."""
    (La, ax, ay, az, la, ia, sa, pax, pay, qa, bax, bay, baz, eax, eay, eaz, ca, _) = cable_of(px, py, pz, c0)
    (Lb, bx_, by_, bz_, lb, ib, sb, pbx, pby, qb, bbx, bby, bbz, ebx, eby, ebz, cb, _) = cable_of(
        px, py, pz, c1
    )
    (Lg, cx, cy, cz, lg, ig, sg, pgx, pgy, qg, bgx, bgy, bgz, egx, egy, egz, cg, _) = cable_of(px, py, pz, c2)
    valid = not (ia or ib or ig) and pz < c0[2] and pz < c1[2] and pz < c2[2]
    r0x, r0y, r0z, r1x, r1y, r1z, r2x, r2y, r2z, idet, t0, t1, t2, ok = _tensions3(
        ax, ay, az, bx_, by_, bz_, cx, cy, cz, bx, by, bz
    )
    if not ok:
        return _no_residual()
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
    G = (
        Sxx + vax * eax + vbx * ebx + vgx * egx,
        Sxy + vax * eay + vbx * eby + vgx * egy,
        Sxz + vax * eaz + vbx * ebz + vgx * egz,
        Sxy + vay * eax + vby * ebx + vgy * egx,
        Syy + vay * eay + vby * eby + vgy * egy,
        Syz + vay * eaz + vby * ebz + vgy * egz,
        Sxz + vaz * eax + vbz * ebx + vgz * egx,
        Syz + vaz * eay + vbz * eby + vgz * egy,
        Szz + vaz * eaz + vbz * ebz + vgz * egz,
    )
    # dL_TE/dP = -u + arm ((u + u_C) . beta) eps (statics.length_gradient)
    ma, mb, mg = qa * (uba + ca), qb * (ubb + cb), qg * (ubg + cg)
    dL = (
        -ax + ma * eax, -ay + ma * eay, -az + ma * eaz,
        -bx_ + mb * ebx, -by_ + mb * eby, -bz_ + mb * ebz,
        -cx + mg * egx, -cy + mg * egy, -cz + mg * egz,
    )  # fmt: skip
    r = (r0x, r0y, r0z, r1x, r1y, r1z, r2x, r2y, r2z)
    return _close(r, idet, t0, t1, t2, G, dL, La, Lb, Lg, L0, L1, L2, Ea, Eb, Eg, valid)


@njit(cache=True, inline="always", error_model="numpy")
def _cable_rows(px, py, pz, cp, ident, f):
    """One cable at P for ``_residual_axis``: (L_TE [m], u (3) [-], dL_TE/dP (3) [-], du/dP (9,
    row-major) [1/m], inside) from ``cable_axis`` (the pulley's frame) and ``cable_derivatives``."""
    (L, ux, uy, uz, lE, ins, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb, _) = cable_axis(
        px, py, pz, cp[0], cp[1], cp[2], cp[3], cp[4], cp[5], cp[6], cp[7], cp[8], ident, f
    )
    dv = cable_derivatives(ux, uy, uz, lE, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb)
    return L, ux, uy, uz, dv, ins


@njit(cache=True, inline="always", error_model="numpy")
def _residual_axis(px, py, pz, c0, c1, c2, i0, i1, i2, f0, f1, f2, Ea, Eb, Eg, L0, L1, L2, bx, by, bz):
    """``_residual`` for pulleys at any axis (each cable in its frame: ``cable_axis``, with ident
    i0, i1, i2 and frames f0, f1, f2 (3, 3)): the same equations written with each cable's full
    gradients (``cable_derivatives``)::

        t = M^-1 b,  G = sum_j t_j du_j/dP,  dt/dP = -M^-1 G,
        J = dL_TE/dP - diag(L / E S) dt/dP

    (``direct._Subset.residual`` with the pulley frames). No accessibility rule: P may lie at any
    side of the pulleys (``Robot.suspended_point_mass`` false).

    Returns (F (3), t (3), J (9, row-major), dt/dP (9, row-major), valid) as ``_residual``."""
    La, ax, ay, az, da, ia = _cable_rows(px, py, pz, c0, i0, f0)
    Lb, bx_, by_, bz_, db, ib = _cable_rows(px, py, pz, c1, i1, f1)
    Lg, cx, cy, cz, dg, ig = _cable_rows(px, py, pz, c2, i2, f2)
    r0x, r0y, r0z, r1x, r1y, r1z, r2x, r2y, r2z, idet, t0, t1, t2, ok = _tensions3(
        ax, ay, az, bx_, by_, bz_, cx, cy, cz, bx, by, bz
    )
    if not ok:
        return _no_residual()
    # G = sum_j t_j du_j/dP (du_j/dP row-major: items 3..11 of cable_derivatives)
    G = (
        t0 * da[3] + t1 * db[3] + t2 * dg[3],
        t0 * da[4] + t1 * db[4] + t2 * dg[4],
        t0 * da[5] + t1 * db[5] + t2 * dg[5],
        t0 * da[6] + t1 * db[6] + t2 * dg[6],
        t0 * da[7] + t1 * db[7] + t2 * dg[7],
        t0 * da[8] + t1 * db[8] + t2 * dg[8],
        t0 * da[9] + t1 * db[9] + t2 * dg[9],
        t0 * da[10] + t1 * db[10] + t2 * dg[10],
        t0 * da[11] + t1 * db[11] + t2 * dg[11],
    )
    dL = (da[0], da[1], da[2], db[0], db[1], db[2], dg[0], dg[1], dg[2])
    r = (r0x, r0y, r0z, r1x, r1y, r1z, r2x, r2y, r2z)
    valid = not (ia or ib or ig)
    return _close(r, idet, t0, t1, t2, G, dL, La, Lb, Lg, L0, L1, L2, Ea, Eb, Eg, valid)


@njit(cache=True, inline="always", error_model="numpy")
def _subset_residual(px, py, pz, c0, c1, c2, s0, s1, s2, subs, Ea, Eb, Eg, L0, L1, L2, bx, by, bz):
    """``_residual`` (suspended robots: today's arithmetic) or ``_residual_axis`` (pulleys at any
    axis) of cables s0, s1, s2 as ``subs.suspended`` says."""
    if subs.suspended:
        return _residual(px, py, pz, c0, c1, c2, Ea, Eb, Eg, L0, L1, L2, bx, by, bz)
    fr, idn = subs.frame, subs.ident
    return _residual_axis(
        px,
        py,
        pz,
        c0,
        c1,
        c2,
        idn[s0],
        idn[s1],
        idn[s2],
        fr[s0],
        fr[s1],
        fr[s2],
        Ea,
        Eb,
        Eg,
        L0,
        L1,
        L2,
        bx,
        by,
        bz,
    )


@njit(cache=True, error_model="numpy")
def _newton(p0x, p0y, p0z, s0, s1, s2, cab, subs, L0, L1, L2, bx, by, bz, opts):
    """direct._newton (analytic Jacobian, same stop rule) for one point and one subset; ``cab`` the
    ``Cables`` record, ``subs`` the ``Subsets`` record (how the pulleys are evaluated), ``opts``
    the ``Newton`` record.

    Returns (Px, Py, Pz, t0, t1, t2, iterations, converged, exists)."""
    tol, maxiter, max_step = opts.tol, opts.maxiter, opts.max_step
    c0, c1, c2 = cable_params(cab, s0), cable_params(cab, s1), cable_params(cab, s2)
    Ea, Eb, Eg = cab.ES[s0], cab.ES[s1], cab.ES[s2]
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
        ) = _subset_residual(px, py, pz, c0, c1, c2, s0, s1, s2, subs, Ea, Eb, Eg, L0, L1, L2, bx, by, bz)
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
        out = _subset_residual(px, py, pz, c0, c1, c2, s0, s1, s2, subs, Ea, Eb, Eg, L0, L1, L2, bx, by, bz)
        t0, t1, t2, valid = out[3], out[4], out[5], out[-1]
    exists = exists and valid
    return px, py, pz, t0, t1, t2, it, conv and exists, exists


@njit(cache=True, inline="always", error_model="numpy")
def commanded_lengths(i, p, Lin, cab, Lall):
    """Lall (m,) [m] = the commanded total lengths of point i: Lin[i] when Lin (N, m) has rows,
    else L_TS at p[i] (eq. 2: |A_j - p| + d_j)."""
    A, d = cab.A, cab.d
    for c in range(A.shape[0]):
        if Lin.shape[0] > 0:
            Lall[c] = Lin[i, c]
        else:
            Lall[c] = (
                math.sqrt((p[i, 0] - A[c, 0]) ** 2 + (p[i, 1] - A[c, 1]) ** 2 + (p[i, 2] - A[c, 2]) ** 2)
                + d[c]
            )


@njit(cache=True, error_model="numpy")
def solve_subset(k, i, p, cab, subs, Lall, b, opts, scr):
    """Subset k (row k of ``subs.idx`` (ns, 3), ``subs`` the ``Subsets`` record) at point i from
    P = p[i] with commanded lengths Lall (m,) [m] and force b (3,) [N] (``_newton``): writes row k of
    scr.Ps, ts, its, conv, exi, dps (``PaperScratch``)."""
    solve_subset_from(k, i, p, p[i, 0], p[i, 1], p[i, 2], cab, subs, Lall, b, opts, scr)


@njit(cache=True, error_model="numpy")
def solve_subset_from(k, i, p, sx, sy, sz, cab, subs, Lall, b, opts, scr):
    """``solve_subset`` with Newton started at (sx, sy, sz) [m] instead of p[i]."""
    subsets = subs.idx
    s0, s1, s2 = subsets[k, 0], subsets[k, 1], subsets[k, 2]
    px, py, pz, t0, t1, t2, it, cv, ex = _newton(
        sx, sy, sz, s0, s1, s2, cab, subs, Lall[s0], Lall[s1], Lall[s2], b[0], b[1], b[2], opts
    )
    Ps, ts = scr.Ps, scr.ts
    Ps[k, 0], Ps[k, 1], Ps[k, 2] = px, py, pz
    ts[k, 0], ts[k, 1], ts[k, 2] = t0, t1, t2
    scr.its[k], scr.conv[k], scr.exi[k] = it, cv, ex
    scr.dps[k] = math.sqrt((px - p[i, 0]) ** 2 + (py - p[i, 1]) ** 2 + (pz - p[i, 2]) ** 2)


@njit(cache=True, parallel=True, error_model="numpy")
def _solve_points(p, Lin, cab, subs, b, opts, prune, out):
    n = p.shape[0]
    ns = subs.idx.shape[0]
    m = cab.A.shape[0]
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        scr = paper_scratch(m, ns)
        P0 = np.empty((0, ns, 3))
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            solve_point(i, p, Lin, cab, subs, b, opts, prune, out, scr, P0)


@njit(cache=True, error_model="numpy")
def solve_point(i, p, Lin, cab, subs, b, opts, prune, out, scr, P0):
    """Point i: solve the subsets (pruned, see solve_points_fast) and choose as
    cdpr.models.subsets.solve_points.

    p (N, 3) [m]; Lin (N, m) or (0, m) [m] the commanded lengths (none: L_TS at p[i], eq. 2); cab
    ``Cables``; subs ``Subsets``; b (3,) [N] = -w_ext; opts ``Newton``; prune bool; writes row i
    of out (``PaperOut``); scr a ``PaperScratch`` (left holding every subset's result at point i);
    P0 (N, ns, 3) [m] Newton's start of every subset at every point, or (0, ns, 3): start at p[i]."""
    subsets, edges, margin = subs.idx, subs.edges, subs.margin
    A, T_a = cab.A, cab.T_a
    P_s, dp_out, t_out, sub_out, it_out, st_out, work = out
    Lall, Ps, ts, its, conv, exi, dps, solved, adm, gap = scr
    ns = subsets.shape[0]
    m = A.shape[0]
    commanded_lengths(i, p, Lin, cab, Lall)
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
            if P0.shape[0] > 0:
                solve_subset_from(
                    k, i, p, P0[i, k, 0], P0[i, k, 1], P0[i, k, 2], cab, subs, Lall, b, opts, scr
                )
            else:
                solve_subset(k, i, p, cab, subs, Lall, b, opts, scr)
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
    # paper-mode choice, as cdpr.models.subsets.solve_points
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
    n . p - c is the signed distance of p outside that edge; and the margin max(h + r_p). Every
    subset at once (a Sobol job builds this for each of its ~18,000 sampled robots)."""
    subs = np.asarray(robot.subsets, dtype=np.intp).reshape(-1, 3)
    xy = robot.A[:, :2][subs]  # (subsets, 3 corners, 2)
    e1, e2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
    area2 = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    v = xy[:, [1, 2, 0]] - xy  # corner e to corner e + 1
    sign = np.where(area2 > 0, 1.0, -1.0)[:, None]
    nx, ny = v[..., 1] * sign, -v[..., 0] * sign
    ln = np.sqrt(nx * nx + ny * ny)
    scale = np.where(ln > 0, ln, 1.0)
    nx, ny = nx / scale, ny / scale
    edges = np.stack([nx, ny, nx * xy[..., 0] + ny * xy[..., 1]], axis=2)
    flat = np.abs(area2) < 1e-12  # degenerate triangle: never prune it on geometry
    edges[flat, :, :2] = 0.0
    edges[flat, :, 2] = np.inf
    margin = (robot.h + robot.r_p)[subs].max(axis=1)
    return edges, margin


def subset_arrays(robot):
    """The ``Subsets`` record of ``robot``: its paper-mode subsets, their ``subset_edges`` and its
    pulley frames. A robot that is not suspended (pulleys at other axes than +z) is never pruned:
    the anchor triangles seen from above bound nothing there (every edge is made degenerate)."""
    edges, margin = subset_edges(robot)
    suspended = robot.suspended_point_mass
    frame, ident = pulley_frames(robot)
    if not suspended:
        edges[:, :, :2] = 0.0
        edges[:, :, 2] = np.inf
    return Subsets(
        np.ascontiguousarray(robot.subsets, dtype=np.int64), edges, margin, suspended, frame, ident
    )


def solve_points_fast(robot, p, tol=None, maxiter=None, threads=None, prune=True, L=None):
    """Fast equivalent of ``cdpr.models.subsets.solve_points(robot, p, method="newton", L=L)``
    (same keys except the per-subset arrays). ``threads`` caps numba's threads (default: all
    cores). ``L`` (N, m) [m]: commanded total lengths of every cable, default L_TS(p) of ``robot``
    (eq. 2); give them to command a robot whose parameters differ from the model that computed the
    lengths."""
    require_point_mass(
        robot, "paper mode (solve_points_fast)", 'cdpr.solve.solve(robot, p, redundancy="physical")', P=p
    )
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    n, m = len(p), robot.m
    Lin = commanded_input(L, n, m)
    set_threads(threads)
    out = paper_outputs(n, m)
    if n:
        opts = newton_options(NEWTON_DEFAULTS, tol, maxiter)
        _solve_points(
            p, Lin, cable_arrays(robot), subset_arrays(robot), -robot.platform.w_ext, opts, prune, out
        )
    return {
        "p": p,
        "P_s": out.P_s,
        "dp": out.dp,
        "t": out.t,
        "subset": out.sub,
        "iterations": out.it,
        "status_code": out.st,
        "status": np.asarray(STATUSES)[out.st],
        "subset_solves": out.work,
    }


@njit(cache=True, parallel=True, error_model="numpy")
def _solve_batch(p, Lin, A, kind, h, rp, d, inward, ES, E, T_a, idx, edges, margin, b, opts, prune, P0, out):
    # robot k's solve_point over the chunks of points: every (robot, chunk) pair is one parallel job;
    # P0 (K, N, ns, 3) the starts of every robot, or (0, N, ns, 3): start at p
    K, n = b.shape[0], p.shape[0]
    ns, m = idx.shape[0], A.shape[1]
    P_s, dp, t, sub, it, st, work = out
    nchunks = (n + CHUNK - 1) // CHUNK
    frame = np.zeros((m, 3, 3))  # suspended robots only (solve_points_batch): identity frames
    for c in range(m):
        for a in range(3):
            frame[c, a, a] = 1.0
    ident = np.ones(m, np.bool_)
    for job in prange(K * nchunks):
        k, ch = job // nchunks, job % nchunks
        cab = Cables(A[k], kind[k], h[k], rp[k], d[k], inward[k], ES[k], E[k], T_a[k])
        subs = Subsets(idx, edges[k], margin[k], True, frame, ident)
        o = PaperOut(P_s[k], dp[k], t[k], sub[k], it[k], st[k], work[k])
        scr = paper_scratch(m, ns)
        P0k = P0[k] if P0.shape[0] > 0 else np.empty((0, ns, 3))
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            solve_point(i, p, Lin, cab, subs, b[k], opts, prune, o, scr, P0k)


def solve_points_batch(robots, p, L, tol=None, maxiter=None, threads=None, prune=True, P0=None):
    """``solve_points_fast`` of every robot at the same points and commanded total lengths in one
    parallel pass over (robot, chunk of points) pairs, so that many small solves (Monte Carlo and
    Sobol samples) do not each start and stop numba's threads. Each point runs the same kernel on
    the same inputs as ``solve_points_fast`` (equal results); the numpy reference is
    ``cdpr.models.subsets.solve_points`` of each robot.

    Parameters
    ----------
    robots : sequence of Robot
        Robots with the same number of cables m and the same subsets.
    p : array_like, shape (N, 3) [m]
    L : array_like, shape (N, m) [m]
        Commanded total lengths of every robot.
    tol, maxiter : optional, defaults ``direct.NEWTON_DEFAULTS``.
    threads : int, optional
    prune : bool
    P0 : array_like, shape (K, N, ns, 3) [m], optional
        Newton's start of every robot's subsets at every point (a warm start near each solution,
        ``uncertainty.PoseErrorModel``); default p.

    Returns
    -------
    list of dict
        ``solve_points_fast`` of each robot.
    """
    robots = list(robots)
    p = np.ascontiguousarray(np.atleast_2d(np.asarray(p, dtype=float)))
    if not robots:
        return []
    if any(not r.suspended_point_mass for r in robots):
        raise CdprError("solve_points_batch takes suspended point-mass robots (pulley axes +z) only")
    n, m, K = len(p), robots[0].m, len(robots)
    subs = [subset_arrays(r) for r in robots]
    if any(r.m != m for r in robots) or any(not np.array_equal(s.idx, subs[0].idx) for s in subs):
        raise ValueError("solve_points_batch: every robot needs the same cables and subsets")
    Lin = commanded_input(L, n, m)
    cabs = [cable_arrays(r) for r in robots]
    stack = [np.ascontiguousarray(np.stack([c[j] for c in cabs])) for j in range(len(Cables._fields))]
    edges = np.ascontiguousarray(np.stack([s.edges for s in subs]))
    margin = np.ascontiguousarray(np.stack([s.margin for s in subs]))
    b = np.ascontiguousarray(np.stack([-r.platform.w_ext for r in robots]), dtype=float)
    out = PaperOut(
        np.empty((K, n, 3)),
        np.empty((K, n)),
        np.empty((K, n, m)),
        np.empty((K, n, 3), dtype=np.intp),
        np.empty((K, n), dtype=np.int32),
        np.empty((K, n), dtype=np.int8),
        np.empty((K, n), dtype=np.int32),
    )
    ns = len(subs[0].idx)
    if P0 is None:
        P0 = np.empty((0, n, ns, 3))
    else:
        P0 = np.ascontiguousarray(P0, dtype=float)
        if P0.shape != (K, n, ns, 3):
            raise CdprError(f"P0 has shape {P0.shape}; allowed: (K, N, subsets, 3) = ({K}, {n}, {ns}, 3)")
    set_threads(threads)
    if n:
        opts = newton_options(NEWTON_DEFAULTS, tol, maxiter)
        _solve_batch(p, Lin, *stack, subs[0].idx, edges, margin, b, opts, prune, P0, out)
    return [
        {
            "p": p,
            "P_s": out.P_s[k],
            "dp": out.dp[k],
            "t": out.t[k],
            "subset": out.sub[k],
            "iterations": out.it[k],
            "status_code": out.st[k],
            "status": np.asarray(STATUSES)[out.st[k]],
            "subset_solves": out.work[k],
        }
        for k in range(K)
    ]
