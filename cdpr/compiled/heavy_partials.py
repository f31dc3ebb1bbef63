"""The compiled twin of ``cdpr.models.heavy_partials`` used by the heavy Newton: the exact dF/dB of one
heavy cable's end force (the exit point's slide on the sheave, the swivel and a DR arm's turn
included), ``exact_force_gradient``, called by ``cables.evaluate`` near the solution."""

from __future__ import annotations

import math

from numba import njit

from cdpr.compiled._kernels import SWIVEL_RHO_MIN, sheave
from cdpr.compiled.catenary import terms_fast


@njit(cache=True, error_model="numpy")
def _left(ax, ay, az, D00, D01, D02, D10, D11, D12, D20, D21, D22):
    """a^T D of a 3-vector a and a 3 x 3 matrix D given as scalars (row-major): 3 floats."""
    return (
        ax * D00 + ay * D10 + az * D20,
        ax * D01 + ay * D11 + az * D21,
        ax * D02 + ay * D12 + az * D22,
    )


@njit(cache=True, error_model="numpy")
def _mul(a00, a01, a02, a10, a11, a12, a20, a21, a22, b00, b01, b02, b10, b11, b12, b20, b21, b22):
    """The product a b of two 3 x 3 matrices given as scalars (row-major): 9 floats."""
    return (
        a00 * b00 + a01 * b10 + a02 * b20,
        a00 * b01 + a01 * b11 + a02 * b21,
        a00 * b02 + a01 * b12 + a02 * b22,
        a10 * b00 + a11 * b10 + a12 * b20,
        a10 * b01 + a11 * b11 + a12 * b21,
        a10 * b02 + a11 * b12 + a12 * b22,
        a20 * b00 + a21 * b10 + a22 * b20,
        a20 * b01 + a21 * b11 + a22 * b21,
        a20 * b02 + a21 * b12 + a22 * b22,
    )


@njit(cache=True, error_model="numpy")
def _adjugate(M00, M01, M02, M10, M11, M12, M20, M21, M22):
    """The adjugate (row-major, 9 floats) and the determinant of a 3 x 3 matrix given as scalars."""
    a00, a01, a02 = M11 * M22 - M12 * M21, M02 * M21 - M01 * M22, M01 * M12 - M02 * M11
    a10, a11, a12 = M12 * M20 - M10 * M22, M00 * M22 - M02 * M20, M02 * M10 - M00 * M12
    a20, a21, a22 = M10 * M21 - M11 * M20, M01 * M20 - M00 * M21, M00 * M11 - M01 * M10
    return a00, a01, a02, a10, a11, a12, a20, a21, a22, M00 * a00 + M01 * a10 + M02 * a20


@njit(cache=True, error_model="numpy")
def exact_force_gradient(
    Bx, By, Bz, Dx, Dy, Dz, H, V, L0f, ell, ehx, ehy, ehz, l_h, Ax, Ay, Az, ident, F00, F01, F02, F10, F11, F12,
    F20, F21, F22, kind, h, rp, d, inx, iny, EA, w, ux, uy, uz, kx, ky, kz, G,
):  # fmt: skip
    """The exact dF/dB (3 x 3, written into G) [N/m] of one heavy cable's end force F = H e_h + V_B up
    at its solution (``_cable_at``'s D, H, V_B, L0f, l_dead, e_h, l_h), the exit point's slide on the
    sheave, the swivel and a DR arm's turn included: the compiled twin of
    ``models.heavy_partials.cable_force_partials`` (its B columns), by the implicit-function theorem on
    the same per-cable system in z = (P*, H, V_B, L0f) (that module's docstring: P* on the end
    tangent, the span equations, the split of the rest length), with D(P*) and l_dead(P*)
    differentiated in closed form in the sheave plane (Paty 2021 eq. 3-7: the tangent points
    theta_D = atan2(r) + acos(r_p/|r|), theta_K, the DR arm's centre h times the unit bisector, the
    plane's turn about the axis (D_s/rho) e_perp e_perp^T). The 6 x 6 system [A B; C E] in
    (P*, H, V_B, L0f) is solved by blocks in scalars: A (the end-tangent rows in P*, I minus D's
    small slide) by its cofactors, then the Schur complement E - C A^-1 B; the span equations'
    flexibility from ``catenary.terms_fast`` (the pose kernel's arithmetic). Returns False
    (G untouched) where the system is not finite or singular (a slack weightless cable, a vertical
    span, a point on the swivel axis): the caller keeps its approximate G there."""
    V_D = V + w * L0f
    T_D = math.sqrt(H * H + V_D * V_D)
    vx, vy, vz = Dx - Bx, Dy - By, Dz - Bz
    n = math.sqrt(vx * vx + vy * vy + vz * vz)
    if not (T_D > 0.0 and l_h > 0.0 and n > 0.0 and rp > 0.0 and kind != 0):
        return False
    iT = 1.0 / T_D
    uvx, uvy, uvz = -(H * ehx + V_D * ux) * iT, -(H * ehy + V_D * uy) * iT, -(H * ehz + V_D * uz) * iT
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
    tK0 = tK1 = dl0 = dl1 = 0.0
    if kind == 2:  # the entry side moves with the arm: c = C - Hc
        cs, cw = -g.Hs, -d - g.Hw
        RC2 = cs * cs + cw * cw
        ld = g.ld
        gK0, gK1 = (-cw - rp * cs / ld) / RC2, (cs - rp * cw / ld) / RC2
        tK0, tK1 = -(gK0 * q00 + gK1 * q10), -(gK0 * q01 + gK1 * q11)
        dl0, dl1 = -(cs * q00 + cw * q10) / ld, -(cs * q01 + cw * q11) / ld
    # D's in-plane coordinates (D_s, D_w) = Hc + r_p (cos, sin) theta_D and l_dead = l_d + r_p gamma
    i00, i01 = q00 - rp * g.sD * tD0, q01 - rp * g.sD * tD1
    i10, i11 = q10 + rp * g.cD * tD0, q11 + rp * g.cD * tD1
    e0, e1 = dl0 + rp * (tK0 - tD0), dl1 + rp * (tK1 - tD1)
    sw = (g.Hs + rp * g.cD) / rho
    epx, epy, epz = ky * esz - kz * esy, kz * esx - kx * esz, kx * esy - ky * esx
    # Dp = dD/dP* = es (i00 es + i01 k)^T + k (i10 es + i11 k)^T + sw ep ep^T; a = i00 es + i01 k, b = i10 es + i11 k
    ax_, ay_, az_ = i00 * esx + i01 * kx, i00 * esy + i01 * ky, i00 * esz + i01 * kz
    bx_, by_, bz_ = i10 * esx + i11 * kx, i10 * esy + i11 * ky, i10 * esz + i11 * kz
    D00 = esx * ax_ + kx * bx_ + sw * epx * epx
    D01 = esx * ay_ + kx * by_ + sw * epx * epy
    D02 = esx * az_ + kx * bz_ + sw * epx * epz
    D10 = esy * ax_ + ky * bx_ + sw * epy * epx
    D11 = esy * ay_ + ky * by_ + sw * epy * epy
    D12 = esy * az_ + ky * bz_ + sw * epy * epz
    D20 = esz * ax_ + kz * bx_ + sw * epz * epx
    D21 = esz * ay_ + kz * by_ + sw * epz * epy
    D22 = esz * az_ + kz * bz_ + sw * epz * epz
    lp0, lp1, lp2 = e0 * esx + e1 * kx, e0 * esy + e1 * ky, e0 * esz + e1 * kz
    if not (
        math.isfinite(D00 + D01 + D02 + D10 + D11 + D12 + D20 + D21 + D22) and math.isfinite(lp0 + lp1 + lp2)
    ):
        return False
    # flat = (I - eh eh^T - up up^T) / l_h = q q^T / l_h, q = up x eh (eh horizontal: q unit)
    qx, qy, qz = uy * ehz - uz * ehy, uz * ehx - ux * ehz, ux * ehy - uy * ehx
    il = 1.0 / l_h
    nvx, nvy, nvz = vx / n, vy / n, vz / n
    # row vectors over P* columns: nv^T Dp, q^T Dp, eh^T Dp, up^T Dp
    Dp = (D00, D01, D02, D10, D11, D12, D20, D21, D22)
    nD0, nD1, nD2 = _left(nvx, nvy, nvz, *Dp)
    qD0, qD1, qD2 = _left(qx, qy, qz, *Dp)
    hD0, hD1, hD2 = _left(ehx, ehy, ehz, *Dp)
    uD0, uD1, uD2 = _left(ux, uy, uz, *Dp)
    c = n * H * iT
    cl = c * il
    # A (R1 rows, P* cols): I - Dp - uv nD^T + cl q qD^T
    A00 = 1.0 - D00 - uvx * nD0 + cl * qx * qD0
    A01 = -D01 - uvx * nD1 + cl * qx * qD1
    A02 = -D02 - uvx * nD2 + cl * qx * qD2
    A10 = -D10 - uvy * nD0 + cl * qy * qD0
    A11 = 1.0 - D11 - uvy * nD1 + cl * qy * qD1
    A12 = -D12 - uvy * nD2 + cl * qy * qD2
    A20 = -D20 - uvz * nD0 + cl * qz * qD0
    A21 = -D21 - uvz * nD1 + cl * qz * qD1
    A22 = 1.0 - D22 - uvz * nD2 + cl * qz * qD2
    # Bm (R1 rows; cols H T_D, V_B T_D, L0f): n (eh + uv H/T_D), n (up + uv V_D/T_D), w n/T_D (...)
    hT, vT = H * iT, V_D * iT
    B00, B10, B20 = n * (ehx + uvx * hT), n * (ehy + uvy * hT), n * (ehz + uvz * hT)
    B01, B11, B21 = n * (ux + uvx * vT), n * (uy + uvy * vT), n * (uz + uvz * vT)
    wi = w * iT
    B02, B12, B22 = wi * B01, wi * B11, wi * B21
    # right-hand side of R1: -(uv nv^T - cl q q^T)
    r00, r01, r02 = -(uvx * nvx - cl * qx * qx), -(uvx * nvy - cl * qx * qy), -(uvx * nvz - cl * qx * qz)
    r10, r11, r12 = -(uvy * nvx - cl * qy * qx), -(uvy * nvy - cl * qy * qy), -(uvy * nvz - cl * qy * qz)
    r20, r21, r22 = -(uvz * nvx - cl * qz * qx), -(uvz * nvy - cl * qz * qy), -(uvz * nvz - cl * qz * qz)
    # Cm (R2, R3 rows; P* cols) and Dm (cols H T_D, V_B T_D, L0f), their right-hand side s
    _, _, _, _, Qh, _, Qd, Qx, _ = terms_fast(H, V, L0f, w)
    e = L0f / EA
    f11, f12, f22 = e + L0f * (Qh - Qd), L0f * Qx, e + L0f * Qd
    kq = 1.0 / EA + iT
    if math.isinf(EA):
        rs_, rT = 1.0, 0.0
    else:
        rs_ = EA / (EA + T_D)
        rT = -rs_ / (EA + T_D)
    C00, C01, C02 = -hD0, -hD1, -hD2
    C10, C11, C12 = -uD0, -uD1, -uD2
    C20, C21, C22 = rs_ * lp0, rs_ * lp1, rs_ * lp2
    E00, E01, E02 = f11 * T_D, f12 * T_D, kq * H
    E10, E11, E12 = f12 * T_D, f22 * T_D, kq * V_D
    m53 = ell * rT * H * iT
    m54 = ell * rT * V_D * iT
    E20, E21, E22 = m53 * T_D, m54 * T_D, 1.0 + w * m54
    s00, s01, s02 = -ehx, -ehy, -ehz
    s10, s11, s12 = -ux, -uy, -uz
    # A^-1 by its adjugate
    a00, a01, a02, a10, a11, a12, a20, a21, a22, det = _adjugate(A00, A01, A02, A10, A11, A12, A20, A21, A22)
    if not (abs(det) > 0.0 and math.isfinite(det)):
        return False
    idt = 1.0 / det
    a00 *= idt
    a01 *= idt
    a02 *= idt
    a10 *= idt
    a11 *= idt
    a12 *= idt
    a20 *= idt
    a21 *= idt
    a22 *= idt
    # X = A^-1 Bm, Y = A^-1 r
    Ai = (a00, a01, a02, a10, a11, a12, a20, a21, a22)
    X = _mul(*Ai, B00, B01, B02, B10, B11, B12, B20, B21, B22)
    Y = _mul(*Ai, r00, r01, r02, r10, r11, r12, r20, r21, r22)
    # Schur complement S = Dm - Cm X, right-hand side t = s - Cm Y (s's third row 0)
    Cm = (C00, C01, C02, C10, C11, C12, C20, C21, C22)
    CX00, CX01, CX02, CX10, CX11, CX12, CX20, CX21, CX22 = _mul(*Cm, *X)
    CY00, CY01, CY02, CY10, CY11, CY12, CY20, CY21, CY22 = _mul(*Cm, *Y)
    S = (
        E00 - CX00, E01 - CX01, E02 - CX02, E10 - CX10, E11 - CX11, E12 - CX12, E20 - CX20, E21 - CX21, E22 - CX22,
    )  # fmt: skip
    t = (s00 - CY00, s01 - CY01, s02 - CY02, s10 - CY10, s11 - CY11, s12 - CY12, -CY20, -CY21, -CY22)
    # Z = S^-1 t (rows H T_D, V_B T_D, L0f) by S's adjugate
    b00, b01, b02, b10, b11, b12, b20, b21, b22, ds = _adjugate(*S)
    if not (abs(ds) > 0.0 and math.isfinite(ds)):
        return False
    ids = 1.0 / ds
    bt00, bt01, bt02, bt10, bt11, bt12, bt20, bt21, bt22 = _mul(
        b00, b01, b02, b10, b11, b12, b20, b21, b22, *t
    )
    Z00, Z01, Z02 = bt00 * ids, bt01 * ids, bt02 * ids
    Z10, Z11, Z12 = bt10 * ids, bt11 * ids, bt12 * ids
    Z20, Z21, Z22 = bt20 * ids, bt21 * ids, bt22 * ids
    # dP*/dB = Y - X Z
    XZ00, XZ01, XZ02, XZ10, XZ11, XZ12, XZ20, XZ21, XZ22 = _mul(
        *X, Z00, Z01, Z02, Z10, Z11, Z12, Z20, Z21, Z22
    )
    Y00, Y01, Y02, Y10, Y11, Y12, Y20, Y21, Y22 = Y
    P00, P01, P02 = Y00 - XZ00, Y01 - XZ01, Y02 - XZ02
    P10, P11, P12 = Y10 - XZ10, Y11 - XZ11, Y12 - XZ12
    P20, P21, P22 = Y20 - XZ20, Y21 - XZ21, Y22 - XZ22
    # dv = Dp dP*/dB - I; dF/dB = eh (T_D dH) + H flat dv + up (T_D dV_B), flat dv = q (q^T dv) / l_h
    qv0 = qD0 * P00 + qD1 * P10 + qD2 * P20 - qx
    qv1 = qD0 * P01 + qD1 * P11 + qD2 * P21 - qy
    qv2 = qD0 * P02 + qD1 * P12 + qD2 * P22 - qz
    hl = H * il
    g00 = ehx * T_D * Z00 + hl * qx * qv0 + ux * T_D * Z10
    g01 = ehx * T_D * Z01 + hl * qx * qv1 + ux * T_D * Z11
    g02 = ehx * T_D * Z02 + hl * qx * qv2 + ux * T_D * Z12
    g10 = ehy * T_D * Z00 + hl * qy * qv0 + uy * T_D * Z10
    g11 = ehy * T_D * Z01 + hl * qy * qv1 + uy * T_D * Z11
    g12 = ehy * T_D * Z02 + hl * qy * qv2 + uy * T_D * Z12
    g20 = ehz * T_D * Z00 + hl * qz * qv0 + uz * T_D * Z10
    g21 = ehz * T_D * Z01 + hl * qz * qv1 + uz * T_D * Z11
    g22 = ehz * T_D * Z02 + hl * qz * qv2 + uz * T_D * Z12
    if not math.isfinite(g00 + g01 + g02 + g10 + g11 + g12 + g20 + g21 + g22):
        return False
    G[0, 0], G[0, 1], G[0, 2] = g00, g01, g02
    G[1, 0], G[1, 1], G[1, 2] = g10, g11, g12
    G[2, 0], G[2, 1], G[2, 2] = g20, g21, g22
    return True
