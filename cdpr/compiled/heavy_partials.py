"""The compiled twin of ``cdpr.models.heavy_partials`` used by the heavy Newton: the exact dF/dB of one
heavy cable's end force (the exit point's slide on the sheave, the swivel and a DR arm's turn
included), ``exact_force_gradient``, called by ``cables.evaluate`` near the solution."""

from __future__ import annotations

import math

from numba import njit

from cdpr.compiled._kernels import SWIVEL_RHO_MIN, sheave
from cdpr.compiled.catenary import flexibility


@njit(cache=True, error_model="numpy")
def exact_force_gradient(
    Bx, By, Bz, Dx, Dy, Dz, H, V, L0f, ell, ehx, ehy, ehz, l_h, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12,
    F20, F21, F22, kind, h, rp, d, inx, iny, EA, w, ux, uy, uz, kx, ky, kz, G, M,
):  # fmt: skip
    """The exact dF/dB (3 x 3, written into G) [N/m] of one heavy cable's end force F = H e_h + V_B up
    at its solution (``_cable_at``'s D, H, V_B, L0f, l_dead, e_h, l_h), the exit point's slide on the
    sheave, the swivel and a DR arm's turn included: the compiled twin of
    ``models.heavy_partials.cable_force_partials`` (its B columns), by the implicit-function theorem on
    the same per-cable system in z = (P*, H, V_B, L0f) (that module's docstring: P* on the end
    tangent, the span equations, the split of the rest length), with D(P*) and l_dead(P*)
    differentiated in closed form in the sheave plane (Paty 2021 eq. 3-7: the tangent points
    theta_D = atan2(r) + acos(r_p/|r|), theta_K, the DR arm's centre h times the unit bisector, the
    plane's turn about the axis (D_s/rho) e_perp e_perp^T). ``M`` (13, 9) scratch (rows 0-5 the
    system, 6-12 D's and l_dead's derivatives and the result). Returns False
    (G untouched) where the system is not finite or singular (a slack weightless cable, a vertical
    span, a point on the swivel axis): the caller keeps its approximate G there."""
    V_D = V + w * L0f
    T_D = math.sqrt(H * H + V_D * V_D)
    vx, vy, vz = Dx - Bx, Dy - By, Dz - Bz
    n = math.sqrt(vx * vx + vy * vy + vz * vz)
    if not (T_D > 0.0 and l_h > 0.0 and n > 0.0 and rp > 0.0 and kind != 0):
        return False
    uvx, uvy, uvz = -(H * ehx + V_D * ux) / T_D, -(H * ehy + V_D * uy) / T_D, -(H * ehz + V_D * uz) / T_D
    Px, Py, Pz = Dx + n * uvx, Dy + n * uvy, Dz + n * uvz  # the virtual point P*
    g, esx, esy, esz = sheave(
        Px, Py, Pz, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12, F20, F21, F22, kind, h, rp, d, inx, iny
    )  # fmt: skip
    rho = g.rho
    if not rho > SWIVEL_RHO_MIN:
        return False
    wP = (Px - Ax) * kx + (Py - Ay) * ky + (Pz - Az) * kz
    # in the sheave plane, q = (rho, w_P): the centre's derivative Hq (DR: h times the bisector)
    q00 = q01 = q10 = q11 = 0.0
    if kind == 2:
        nP = math.sqrt(rho * rho + wP * wP)
        a0, a1 = rho / nP, wP / nP
        b0, b1 = a0, a1 - 1.0
        nb = math.sqrt(b0 * b0 + b1 * b1)
        c0, c1 = b0 / nb, b1 / nb
        f = h / (nb * nP)
        m00, m01, m11 = 1.0 - c0 * c0, -c0 * c1, 1.0 - c1 * c1  # (I - bh bh^T)
        n00, n01, n11 = 1.0 - a0 * a0, -a0 * a1, 1.0 - a1 * a1  # (I - a a^T)
        q00, q01 = f * (m00 * n00 + m01 * n01), f * (m00 * n01 + m01 * n11)
        q10, q11 = f * (m01 * n00 + m11 * n01), f * (m01 * n01 + m11 * n11)
    rs, rw = rho - g.Hs, wP - g.Hw
    R2 = rs * rs + rw * rw
    lE = math.sqrt(max(R2 - rp * rp, 0.0))
    gD0, gD1 = (-rw + rp * rs / lE) / R2, (rs + rp * rw / lE) / R2  # dtheta_D/dr
    tD0 = gD0 * (1.0 - q00) - gD1 * q10  # dtheta_D/dq, r = q - Hc
    tD1 = -gD0 * q01 + gD1 * (1.0 - q11)
    cs, cw = -g.Hs, -d - g.Hw
    RC2 = cs * cs + cw * cw
    ld = g.ld
    tK0 = tK1 = dl0 = dl1 = 0.0
    if kind == 2:  # the entry side moves with the arm: c = C - Hc
        gK0, gK1 = (-cw - rp * cs / ld) / RC2, (cs - rp * cw / ld) / RC2
        tK0, tK1 = -(gK0 * q00 + gK1 * q10), -(gK0 * q01 + gK1 * q11)
        dl0, dl1 = -(cs * q00 + cw * q10) / ld, -(cs * q01 + cw * q11) / ld
    # D's in-plane coordinates (D_s, D_w) = Hc + r_p (cos, sin) theta_D and l_dead = l_d + r_p gamma
    i00, i01 = q00 - rp * g.sD * tD0, q01 - rp * g.sD * tD1
    i10, i11 = q10 + rp * g.cD * tD0, q11 + rp * g.cD * tD1
    e0, e1 = dl0 + rp * (tK0 - tD0), dl1 + rp * (tK1 - tD1)
    Ds = g.Hs + rp * g.cD
    sw = Ds / rho
    es = (esx, esy, esz)
    kk = (kx, ky, kz)
    ep = (ky * esz - kz * esy, kz * esx - kx * esz, kx * esy - ky * esx)
    eh = (ehx, ehy, ehz)
    up = (ux, uy, uz)
    uv = (uvx, uvy, uvz)
    nv = (vx / n, vy / n, vz / n)
    Dp, flat, lp = M[6:9, 0:3], M[6:9, 3:6], M[9, 0:3]
    for a in range(3):
        for b in range(3):
            Dp[a, b] = (
                es[a] * (i00 * es[b] + i01 * kk[b]) + kk[a] * (i10 * es[b] + i11 * kk[b]) + sw * ep[a] * ep[b]
            )
        lp[a] = e0 * es[a] + e1 * kk[a]
    for a in range(3):
        if not (math.isfinite(lp[a]) and math.isfinite(Dp[a, 0] + Dp[a, 1] + Dp[a, 2])):
            return False
    for a in range(3):
        for b in range(3):
            flat[a, b] = ((1.0 if a == b else 0.0) - eh[a] * eh[b] - up[a] * up[b]) / l_h
    f11, f12, f22 = flexibility(H, V, L0f, w, EA)
    kq = 1.0 / EA + 1.0 / T_D
    if math.isinf(EA):
        rs_, rT = 1.0, 0.0
    else:
        rs_ = EA / (EA + T_D)
        rT = -rs_ / (EA + T_D)
    c = n * H / T_D
    # rows: R1 (3), R2 (2), R3; columns: P* (3), H, V_B, L0f | the right-hand side -dR/dB (3)
    for a in range(3):
        for b in range(3):
            nD = nv[0] * Dp[0, b] + nv[1] * Dp[1, b] + nv[2] * Dp[2, b]
            fD = flat[a, 0] * Dp[0, b] + flat[a, 1] * Dp[1, b] + flat[a, 2] * Dp[2, b]
            M[a, b] = (1.0 if a == b else 0.0) - Dp[a, b] - uv[a] * nD + c * fD
            M[a, 6 + b] = -(uv[a] * nv[b] - c * flat[a, b])
        M[a, 3] = n / T_D * (eh[a] + uv[a] * H / T_D)
        M[a, 4] = n / T_D * (up[a] + uv[a] * V_D / T_D)
        M[a, 5] = w * M[a, 4]
    for b in range(3):
        M[3, b] = -(eh[0] * Dp[0, b] + eh[1] * Dp[1, b] + eh[2] * Dp[2, b])
        M[4, b] = -(up[0] * Dp[0, b] + up[1] * Dp[1, b] + up[2] * Dp[2, b])
        M[5, b] = rs_ * lp[b]
        M[3, 6 + b] = -eh[b]
        M[4, 6 + b] = -up[b]
        M[5, 6 + b] = 0.0
    M[3, 3], M[3, 4], M[3, 5] = f11, f12, kq * H
    M[4, 3], M[4, 4], M[4, 5] = f12, f22, kq * V_D
    M[5, 3] = ell * rT * H / T_D
    M[5, 4] = ell * rT * V_D / T_D
    M[5, 5] = 1.0 + w * M[5, 4]
    # Gaussian elimination with partial pivoting, columns scaled to comparable sizes by T_D
    for r in range(6):
        M[r, 3] *= T_D
        M[r, 4] *= T_D
    for col in range(6):
        piv = col
        for r in range(col + 1, 6):
            if abs(M[r, col]) > abs(M[piv, col]):
                piv = r
        if not abs(M[piv, col]) > 0.0:
            return False
        if piv != col:
            for b in range(9):
                M[col, b], M[piv, b] = M[piv, b], M[col, b]
        for r in range(col + 1, 6):
            fr = M[r, col] / M[col, col]
            for b in range(col, 9):
                M[r, b] -= fr * M[col, b]
    for col in range(5, -1, -1):
        for b in range(6, 9):
            acc = M[col, b]
            for k in range(col + 1, 6):
                acc -= M[col, k] * M[k, b]
            M[col, b] = acc / M[col, col]
    # dz/dB in M[:6, 6:9] (H, V_B scaled by T_D); dF/dB = e_h dH + H flat (Dp dP* - I) + up dV_B
    dv = M[10:13, 0:3]
    for a in range(3):
        for b in range(3):
            dv[a, b] = (
                -(1.0 if a == b else 0.0)
                + Dp[a, 0] * M[0, 6 + b]
                + Dp[a, 1] * M[1, 6 + b]
                + Dp[a, 2] * M[2, 6 + b]
            )
    ok = True
    out = M[10:13, 3:6]
    for a in range(3):
        for b in range(3):
            fdv = flat[a, 0] * dv[0, b] + flat[a, 1] * dv[1, b] + flat[a, 2] * dv[2, b]
            out[a, b] = eh[a] * T_D * M[3, 6 + b] + H * fdv + up[a] * T_D * M[4, 6 + b]
            ok = ok and math.isfinite(out[a, b])
    if ok:
        for a in range(3):
            for b in range(3):
                G[a, b] = out[a, b]
    return ok
