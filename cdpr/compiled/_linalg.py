"""Small dense linear algebra of the compiled pose kernels (numba, scalar loops, no allocation in
the hot loop): the 6 x 6 least-squares step by a one-sided Jacobi SVD, its LU short cut with a
bound that guarantees the same cut, a Cholesky test of positive definiteness, the 3 x 3 solve of a
point mass, and the rotation vector <-> matrix maps. Each is the scalar twin of a numpy call of the
reference (``numpy.linalg.pinv``, ``numpy.linalg.eigvalsh``, ``statics.solve3``,
``platform.rotation_matrix``, ``platform.rotvec_of``), tested against it.

References
----------
Golub, G. H., Van Loan, C. F. (2013). Matrix Computations, 4th ed. Johns Hopkins (one-sided Jacobi
SVD 8.6.3, LU with partial pivoting 3.4, Cholesky 4.2).

Murray, R. M., Li, Z., Sastry, S. S. (1994). A Mathematical Introduction to Robotic Manipulation.
CRC Press (Rodrigues' formula, eq. 2.14).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from cdpr.compiled._kernels import DET_EPS

#: Sweeps of the one-sided Jacobi SVD (``pinv_solve``) at most; it stops when every column pair
#: is orthogonal to ``JACOBI_EPS`` (relative).
JACOBI_SWEEPS = 30
JACOBI_EPS = 1e-15
#: The LU step stands for the pseudo-inverse one where |J|_F |L^-1|_F |U^-1|_F <= LU_SAFE / RCOND:
#: then s_min(J) / s_max(J) >= RCOND / LU_SAFE, so the RCOND cut leaves out no singular value.
LU_SAFE = 1e-3
#: The Cholesky shift, relative to |H|_F, of the compiled positive-definiteness test: a Hessian that
#: passes it has lambda_min >= STABLE_REL |H|_F, far beyond eigvalsh's round-off.
STABLE_REL = 1e-10


@njit(cache=True, inline="always", error_model="numpy")
def rodrigues(sx, sy, sz, Q):
    """Rodrigues' formula Q = I + sin(a)/a [s]x + (1 - cos a)/a^2 [s]x^2, a = |s|, into Q (3, 3)
    (``platform.rotation_matrix``, scalar form, with its series under a = 1e-8).

    .. math:: Q = \\exp([s]_\\times)

    Parameters
    ----------
    sx, sy, sz : float [rad]
        Rotation vector (base frame).
    Q : ndarray (3, 3)
        Written with the rotation matrix [-].

    References
    ----------
    Murray, Li, Sastry (1994), A Mathematical Introduction to Robotic Manipulation, eq. (2.14).
    """
    a = math.sqrt(sx * sx + sy * sy + sz * sz)
    if a < 1e-8:
        s = 1.0 - a * a / 6.0
        c = 0.5 - a * a / 24.0
    else:
        s = math.sin(a) / a
        c = (1.0 - math.cos(a)) / (a * a)
    K = ((0.0, -sz, sy), (sz, 0.0, -sx), (-sy, sx, 0.0))
    for i in range(3):
        for j in range(3):
            k2 = K[i][0] * K[0][j] + K[i][1] * K[1][j] + K[i][2] * K[2][j]
            Q[i, j] = (1.0 if i == j else 0.0) + s * K[i][j] + c * k2


@njit(cache=True, error_model="numpy")
def pinv_solve(J, rhs, A, V, x, rcond):
    """The least-squares step x = pinv(J) rhs of a 6 x 6 system (``numpy.linalg.pinv`` with
    ``rcond``: singular values s <= rcond max(s) left out), by a one-sided Jacobi SVD: plane
    rotations V make the columns of A = J V orthogonal, then s_k = |A_k| and

    .. math:: x = \\sum_{s_k > r \\max s} V_k \\, (A_k \\cdot rhs) / s_k^2

    Parameters
    ----------
    J : ndarray (6, 6)
        The system matrix (not changed).
    rhs : ndarray (6,)
        The right-hand side.
    A, V : ndarray (6, 6)
        Work arrays.
    x : ndarray (6,)
        Written with the step.
    rcond : float [-]
        Relative singular-value cut.

    References
    ----------
    Hestenes, M. R. (1958). Inversion of matrices by biorthogonalization. J. SIAM 6, 51-90.
    """
    n = 6
    for a in range(n):
        for c in range(n):
            A[a, c] = J[a, c]
            V[a, c] = 1.0 if a == c else 0.0
    for _ in range(JACOBI_SWEEPS):
        rotated = False
        for p in range(n - 1):
            for q in range(p + 1, n):
                alpha = beta = gamma = 0.0
                for a in range(n):
                    alpha += A[a, p] * A[a, p]
                    beta += A[a, q] * A[a, q]
                    gamma += A[a, p] * A[a, q]
                if gamma == 0.0 or abs(gamma) <= JACOBI_EPS * math.sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                tt = math.copysign(1.0, zeta) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                cs = 1.0 / math.sqrt(1.0 + tt * tt)
                sn = cs * tt
                for a in range(n):
                    ap, aq = A[a, p], A[a, q]
                    A[a, p] = cs * ap - sn * aq
                    A[a, q] = sn * ap + cs * aq
                    vp, vq = V[a, p], V[a, q]
                    V[a, p] = cs * vp - sn * vq
                    V[a, q] = sn * vp + cs * vq
        if not rotated:
            break
    smax = 0.0
    for c in range(n):
        s2 = 0.0
        for a in range(n):
            s2 += A[a, c] * A[a, c]
        smax = max(smax, math.sqrt(s2))
    for a in range(n):
        x[a] = 0.0
    cut = rcond * smax
    for c in range(n):
        s2 = 0.0
        dot = 0.0
        for a in range(n):
            s2 += A[a, c] * A[a, c]
            dot += A[a, c] * rhs[a]
        if math.sqrt(s2) > cut:
            coef = dot / s2
            for a in range(n):
                x[a] += V[a, c] * coef


@njit(cache=True, error_model="numpy")
def lu_solve(J, rhs, A, Linv, piv, x, rcond):
    """x = J^-1 rhs by LU with partial pivoting (P J = L U), where it equals the least-squares step
    of ``pinv_solve``: returns False (x undefined) unless the bound

        s_min(J) / s_max(J) >= 1 / (|J|_F |L^-1|_F |U^-1|_F) >= r / LU_SAFE

    shows that the pseudo-inverse's cut r keeps every singular value.

    Parameters
    ----------
    J : ndarray (6, 6)
        The system matrix (not changed).
    rhs : ndarray (6,)
        The right-hand side.
    A, Linv : ndarray (6, 6)
        Work arrays (A holds L and U).
    piv : ndarray (6,) int64
        Work array.
    x : ndarray (6,)
        Written with the step.
    rcond : float [-]
        The pseudo-inverse's relative cut.

    Returns
    -------
    ok : bool

    References
    ----------
    Golub, G. H., Van Loan, C. F. (2013). Matrix Computations, 4th ed., section 3.4.
    """
    n = 6
    nJ = 0.0
    for a in range(n):
        piv[a] = a
        for c in range(n):
            A[a, c] = J[a, c]
            nJ += J[a, c] * J[a, c]
    for k in range(n):
        best, at = abs(A[k, k]), k
        for a in range(k + 1, n):
            if abs(A[a, k]) > best:
                best, at = abs(A[a, k]), a
        if best == 0.0:
            return False
        if at != k:
            for c in range(n):
                A[k, c], A[at, c] = A[at, c], A[k, c]
            piv[k], piv[at] = piv[at], piv[k]
        inv = 1.0 / A[k, k]
        for a in range(k + 1, n):
            A[a, k] *= inv
            l_ak = A[a, k]
            for c in range(k + 1, n):
                A[a, c] -= l_ak * A[k, c]
    # |L^-1|_F (unit lower) and |U^-1|_F by substitution on the identity
    nL = 0.0
    for c in range(n):
        for a in range(n):
            v = 1.0 if a == c else 0.0
            for q in range(c, a):
                v -= A[a, q] * Linv[q, c]
            Linv[a, c] = v
            nL += v * v
    for a in range(n):  # Linv is free: its first row holds 1 / U_aa
        Linv[0, a] = 1.0 / A[a, a]
    nU = 0.0
    for c in range(n):
        for a in range(c, -1, -1):
            v = 1.0 if a == c else 0.0
            for q in range(a + 1, c + 1):
                v -= A[a, q] * x[q]
            x[a] = v * Linv[0, a]
            nU += x[a] * x[a]
    if not math.sqrt(nJ * nL * nU) * rcond <= LU_SAFE:
        return False
    for a in range(n):  # forward: L y = P rhs
        v = rhs[piv[a]]
        for q in range(a):
            v -= A[a, q] * x[q]
        x[a] = v
    for a in range(n - 1, -1, -1):  # back: U x = y
        v = x[a]
        for q in range(a + 1, n):
            v -= A[a, q] * x[q]
        x[a] = v * Linv[0, a]
    return True


@njit(cache=True, error_model="numpy")
def positive_definite(J, A):
    """Whether H = -(J + J^T)/2 is positive definite by a margin: the Cholesky factorisation of
    H - STABLE_REL |H|_F I succeeds (then lambda_min(H) > 0 beyond any round-off of
    ``numpy.linalg.eigvalsh``, the test of ``models.equilibrium._needs_restart``).

        H - delta I = C C^T,   delta = STABLE_REL |H|_F

    Parameters
    ----------
    J : ndarray (6, 6)
        d(F, M)/d(dp, dphi) [N/m, N, N m].
    A : ndarray (6, 6)
        Work array.

    Returns
    -------
    ok : bool

    References
    ----------
    Golub, G. H., Van Loan, C. F. (2013). Matrix Computations, 4th ed., section 4.2.
    """
    n = 6
    nH = 0.0
    for a in range(n):
        for c in range(n):
            A[a, c] = -0.5 * (J[a, c] + J[c, a])
            nH += A[a, c] * A[a, c]
    if not math.isfinite(nH):
        return False
    delta = STABLE_REL * math.sqrt(nH)
    for a in range(n):
        A[a, a] -= delta
    for k in range(n):
        v = A[k, k]
        for q in range(k):
            v -= A[k, q] * A[k, q]
        if not v > 0.0:
            return False
        d = math.sqrt(v)
        A[k, k] = d
        for a in range(k + 1, n):
            v = A[a, k]
            for q in range(k):
                v -= A[a, q] * A[k, q]
            A[a, k] = v / d
    return True


@njit(cache=True, inline="always", error_model="numpy")
def rotvec_of_matrix(R, out):
    """The rotation vector of a rotation matrix (``platform.rotvec_of``, scipy's from_matrix then
    as_rotvec, scalar form): the unit quaternion q = (x, y, z, w) from the largest of R00, R11, R22
    and tr R (Shepperd's method), w >= 0, then

        theta = 2 atan2(|(x, y, z)|, w),   rotvec = theta / sin(theta / 2) (x, y, z)

    (the series 2 + theta^2 / 12 + 7 theta^4 / 2880 for theta <= 1e-3).

    Parameters
    ----------
    R : ndarray (3, 3) [-]
        Rotation matrix.
    out : ndarray (3,)
        Written with the rotation vector [rad], |rotvec| in [0, pi].

    References
    ----------
    Shepperd, S. W. (1978). Quaternion from rotation matrix. J. Guidance and Control 1(3), 223-224.
    """
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    big, at = tr, 3
    for a in range(3):
        if R[a, a] > big:
            big, at = R[a, a], a
    if at == 3:
        x, y, z, w = R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1], 1.0 + tr
    else:
        i = at
        j = (i + 1) % 3
        k = (j + 1) % 3
        qi, qj, qk = 1.0 - tr + 2.0 * R[i, i], R[j, i] + R[i, j], R[k, i] + R[i, k]
        if i == 0:
            x, y, z = qi, qj, qk
        elif i == 1:
            x, y, z = qk, qi, qj
        else:
            x, y, z = qj, qk, qi
        w = R[k, j] - R[j, k]
    nq = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / nq, y / nq, z / nq, w / nq
    if w < 0.0:
        x, y, z, w = -x, -y, -z, -w
    theta = 2.0 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
    if theta <= 1e-3:
        t2 = theta * theta
        scale = 2.0 + t2 / 12.0 + 7.0 * t2 * t2 / 2880.0
    else:
        scale = theta / math.sin(theta / 2.0)
    out[0], out[1], out[2] = scale * x, scale * y, scale * z


@njit(cache=True, inline="always", error_model="numpy")
def solve3(J, nx, ny, nz, x):
    """x = J[:3, :3]^-1 (-n) by cofactors (``statics.solve3``); NaN where |det| < DET_EPS."""
    c00, c01, c02 = (
        J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1],
        J[1, 2] * J[2, 0] - J[1, 0] * J[2, 2],
        J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0],
    )
    c10, c11, c12 = (
        J[2, 1] * J[0, 2] - J[2, 2] * J[0, 1],
        J[2, 2] * J[0, 0] - J[2, 0] * J[0, 2],
        J[2, 0] * J[0, 1] - J[2, 1] * J[0, 0],
    )
    c20, c21, c22 = (
        J[0, 1] * J[1, 2] - J[0, 2] * J[1, 1],
        J[0, 2] * J[1, 0] - J[0, 0] * J[1, 2],
        J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0],
    )
    det = J[0, 0] * c00 + J[0, 1] * c01 + J[0, 2] * c02
    if abs(det) < DET_EPS:
        x[0] = x[1] = x[2] = np.nan
        return
    idet = 1.0 / det
    x[0] = -(c00 * nx + c10 * ny + c20 * nz) * idet
    x[1] = -(c01 * nx + c11 * ny + c21 * nz) * idet
    x[2] = -(c02 * nx + c12 * ny + c22 * nz) * idet


@njit(cache=True, inline="always", error_model="numpy")
def add_cable_jacobian(J, g00, g01, g02, g10, g11, g12, g20, g21, g22, rx, ry, rz, t, ux, uy, uz):
    """Adds one cable (or, with t = 1 and u = its force, one heavy cable)'s terms of ``models.cables._jacobian`` to J (6, 6), with G = t du/dB + ka u dL^T
    (3 x 3, g_ab) and S = [r]x: J[:3, :3] += G, J[:3, 3:] -= G S, J[3:, :3] += S G,
    J[3:, 3:] += -S G S + t (r u^T - (u . r) I)."""
    s00, s01, s02 = g01 * rz - g02 * ry, g02 * rx - g00 * rz, g00 * ry - g01 * rx  # (G S)[0]
    s10, s11, s12 = g11 * rz - g12 * ry, g12 * rx - g10 * rz, g10 * ry - g11 * rx  # (G S)[1]
    s20, s21, s22 = g21 * rz - g22 * ry, g22 * rx - g20 * rz, g20 * ry - g21 * rx  # (G S)[2]
    ur = ux * rx + uy * ry + uz * rz
    J[0, 0] += g00
    J[0, 1] += g01
    J[0, 2] += g02
    J[1, 0] += g10
    J[1, 1] += g11
    J[1, 2] += g12
    J[2, 0] += g20
    J[2, 1] += g21
    J[2, 2] += g22
    J[0, 3] -= s00
    J[0, 4] -= s01
    J[0, 5] -= s02
    J[1, 3] -= s10
    J[1, 4] -= s11
    J[1, 5] -= s12
    J[2, 3] -= s20
    J[2, 4] -= s21
    J[2, 5] -= s22
    J[3, 0] += ry * g20 - rz * g10
    J[4, 0] += rz * g00 - rx * g20
    J[5, 0] += rx * g10 - ry * g00
    J[3, 1] += ry * g21 - rz * g11
    J[4, 1] += rz * g01 - rx * g21
    J[5, 1] += rx * g11 - ry * g01
    J[3, 2] += ry * g22 - rz * g12
    J[4, 2] += rz * g02 - rx * g22
    J[5, 2] += rx * g12 - ry * g02
    J[3, 3] += -(ry * s20 - rz * s10) + t * (rx * ux - ur)
    J[4, 3] += -(rz * s00 - rx * s20) + t * ry * ux
    J[5, 3] += -(rx * s10 - ry * s00) + t * rz * ux
    J[3, 4] += -(ry * s21 - rz * s11) + t * rx * uy
    J[4, 4] += -(rz * s01 - rx * s21) + t * (ry * uy - ur)
    J[5, 4] += -(rx * s11 - ry * s01) + t * rz * uy
    J[3, 5] += -(ry * s22 - rz * s12) + t * rx * uz
    J[4, 5] += -(rz * s02 - rx * s22) + t * ry * uz
    J[5, 5] += -(rx * s12 - ry * s02) + t * (rz * uz - ur)


@njit(cache=True, inline="always", error_model="numpy")
def add_gravity(J, Fx, Fy, Fz, Mx, My, Mz, fx, fy, fz, rcx, rcy, rcz):
    """Adds the platform's weight f at its centre of mass rc (base frame) to the balance and its
    Jacobian, the last terms of ``models.cables._jacobian``: F += f, M += rc × f and
    J[3:, 3:] += rc f^T - (rc . f) I (the weight's moment turns with the platform).

    Returns the updated (Fx, Fy, Fz, Mx, My, Mz) and the weight's moment rc × f (3 floats)."""
    cfx, cfy, cfz = rcy * fz - rcz * fy, rcz * fx - rcx * fz, rcx * fy - rcy * fx
    rc3 = (rcx, rcy, rcz)
    f3 = (fx, fy, fz)
    rcf = rcx * fx + rcy * fy + rcz * fz
    for a in range(3):
        for q in range(3):
            J[3 + a, 3 + q] += rc3[a] * f3[q] - (rcf if a == q else 0.0)
    return Fx + fx, Fy + fy, Fz + fz, Mx + cfx, My + cfy, Mz + cfz, cfx, cfy, cfz


@njit(cache=True, inline="always", error_model="numpy")
def add_wrench(e6, g6, px, py, pz, rfx, rfy, rfz, wrench):
    """Adds a rigid platform's external wrench (``Platform.wrench``: a constant world-frame force fe
    at p and moment me about p) to one evaluation of the pose kernel, as ``models.cables.Cables``
    does: F += fe, M += me (also in the Newton residual Fn), the merit gains the force's potential
    -fe . (p - p_ref) and its gradient minus the generalised force (fe, me). The Jacobian does not
    change (a constant world wrench does not depend on the pose); a constant moment has no
    potential, its work along a line-search step is ``moment_work``'s. Nothing is added when the
    wrench is zero (the default path stays bit for bit what it was).

    .. math:: F \\mathrel{+}= f_e,\\quad M \\mathrel{+}= m_e,\\quad V \\mathrel{-}= f_e \\cdot (p - p_{ref}),
        \\quad \\nabla V \\mathrel{-}= (f_e, m_e)

    Parameters
    ----------
    e6 : ndarray (14,)
        The evaluation: F (3) [N], M (3) [N m], Fn (6), merit [J], inside; updated.
    g6 : ndarray (8,)
        The merit's gradient (6) [N, N m] and the stiffness bounds (2); updated.
    px, py, pz : float [m]
        The pose's reference point p.
    rfx, rfy, rfz : float [m]
        The energy's origin p_ref.
    wrench : ndarray (6,) [N, N m]
        (fe, me); zeros on a point mass (its force is folded into gravity's).

    References
    ----------
    Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer, section 3.3.
    """
    if not (
        wrench[0] != 0.0
        or wrench[1] != 0.0
        or wrench[2] != 0.0
        or wrench[3] != 0.0
        or wrench[4] != 0.0
        or wrench[5] != 0.0
    ):
        return
    for a in range(6):
        e6[a] += wrench[a]
        e6[6 + a] += wrench[a]
        g6[a] -= wrench[a]
    e6[12] -= (px - rfx) * wrench[0] + (py - rfy) * wrench[1] + (pz - rfz) * wrench[2]


@njit(cache=True, inline="always", error_model="numpy")
def moment_work(sx, sy, sz, wrench):
    """The work of a constant world-frame moment me (``wrench[3:]``) along a rotation step s [rad]
    (base frame: R_t = exp([s]x) R, whose base-frame angular displacement is s exactly): me . s [J].
    The line search of the pose kernel subtracts it from the trial merit, as
    ``models.equilibrium._newton`` does.

    .. math:: W = m_e \\cdot s

    Parameters
    ----------
    sx, sy, sz : float [rad]
        The step's rotation vector.
    wrench : ndarray (6,) [N, N m]
        (fe, me).

    Returns
    -------
    work : float [J]
    """
    return sx * wrench[3] + sy * wrench[4] + sz * wrench[5]
