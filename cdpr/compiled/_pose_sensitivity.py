"""Compiled pose sensitivities dp*/dθ, dφ*/dθ (physical mode of any robot):
``models.sensitivity.sensitivities_at`` and ``pose_sensitivities`` as a numba kernel in parallel over
poses (chunks of ``CHUNK``); ``cdpr.compiled.sensitivity`` exposes them beside the point-mass
kernels.

At each equilibrium (p*, R*) of a ``models.equilibrium.solve`` result (either engine; ``pose_sensitivities``
runs the compiled one) the balance's 6 x 6 Jacobian dF6/dx is the solver's own
(``compiled.equilibrium.evaluate``, the compiled ``models.cables._jacobian``) and dF6/dθ at fixed pose is
analytic, cable by cable, from the shared cable kernel (``_kernels.cable_partials_axis``: the
scalar ``cable_partials`` in each pulley's frame). With w_i = t_i (u_i, r_i × u_i), t_i = a_i k_i
(L_TE,i - L0_i), k_i = E_i S_i / L0_i, r_i = R b_i, B_i = p + r_i::

    dw_i/dq = dt_i (u_i, r_i × u_i) + t_i (du_i, dr_i × u_i + r_i × du_i),  dt_i = a_i k_i dL_TE,i
    q = h_i, r_p,i, d_i:  (dL_TE, du) of ``cable_partials``, dr_i = 0
    q = A_i,a:            dL_TE = -dL_TE/dB_a, du = -du/dB_a, dr_i = 0
    q = b_i,a:            dB = dr_i = R e_a (dL_TE = dL_TE/dB . R e_a, du = du/dB R e_a)
    dw_i/dE_i = (t_i / E_i) (u_i, r_i × u_i)
    dF6/dc_a = (0, R e_a × f),   dF6/dM = (f, R c × f) / M     (f = -M g e_z)

(the moment rows zero on a point mass), then S = -pinv(dF6/dx) dF6/dθ with the reference's rcond:
J^-1 by LU where ``_linalg.lu_solve``'s bound shows that the cut keeps every singular value
(then pinv = J^-1), ``numpy.linalg.pinv`` otherwise (a point mass: the rotation rows are zero). The
numpy reference (``models.sensitivity._wrench_partials``) takes dF6/dθ by the same formulas,
vectorised: the two agree to round-off, tested. Same flags (smooth, margin_t, cond) as the
reference.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.

Pott, A. (2018). Cable-Driven Parallel Robots: Theory and Application. Springer, ch. 3.
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
    NCOL,
    cable_partials_axis,
    set_threads,
)
from cdpr.compiled._linalg import lu_solve
from cdpr.compiled.equilibrium import CompiledCables, evaluate, scratch
from cdpr.compiled.equilibrium import solve as solve_spatial
from cdpr.models.sensitivity import COND_MAX, T_TOL, pose_columns

__all__ = ["pose_sensitivities", "sensitivities_at"]

#: rcond of the pseudo-inverse of dF6/dx (``models.sensitivity.sensitivities_at``).
PINV_RCOND = 1e-12


@njit(cache=True, inline="always", error_model="numpy")
def _wrench_col(dF, col, dt, t, ux, uy, uz, dux, duy, duz, rx, ry, rz, qx, qy, qz):
    """dF[:, col] = dt (u, r × u) + t (du, q × u + r × du): one cable's wrench partial (q = dr)."""
    dF[0, col] = dt * ux + t * dux
    dF[1, col] = dt * uy + t * duy
    dF[2, col] = dt * uz + t * duz
    dF[3, col] = dt * (ry * uz - rz * uy) + t * (qy * uz - qz * uy + ry * duz - rz * duy)
    dF[4, col] = dt * (rz * ux - rx * uz) + t * (qz * ux - qx * uz + rz * dux - rx * duz)
    dF[5, col] = dt * (rx * uy - ry * ux) + t * (qx * uy - qy * ux + rx * duy - ry * dux)


@njit(cache=True, error_model="numpy")
def wrench_partials(P, R, L0, i, cab, body, mass, rows, dF):
    """dF6/dθ (6, 10 m + 4) at the fixed pose (P[i], R[i]) with rest lengths L0[i], columns in the
    order of ``parameter_names(robot, rigid=True)`` (module docstring), into dF; ``rows`` (m, NCOL) the cables'
    ``cable_partials_axis``. Returns the tension margin of ``models.sensitivity.sensitivities_at``
    (min over cables of |Hooke tension| and of T_a minus a positive one) [N].

    .. math:: \\frac{\\partial w_i}{\\partial q} = dt_i \\begin{bmatrix} u_i \\\\ r_i \\times u_i
              \\end{bmatrix} + t_i \\begin{bmatrix} du_i \\\\ dr_i \\times u_i + r_i \\times du_i
              \\end{bmatrix}

    Parameters
    ----------
    P : ndarray (N, 3) [m]
        Equilibrium positions.
    R : ndarray (N, 3, 3) [-]
        Equilibrium orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths.
    i : int
        The pose.
    cab : Cables
    body : Body
    mass : float [kg]
        The platform's mass M.
    rows : ndarray (m, NCOL)
        Work array (written with the cables' partials in the base frame).
    dF : ndarray (6, 10 m + 4)
        Written with d(F, M)/dθ [N, N m per unit of θ].

    Returns
    -------
    margin : float [N]

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10)-(13).
    """
    A, kind, h, rp, d, inward, ES, E, T_a = (
        cab.A,
        cab.kind,
        cab.h,
        cab.rp,
        cab.d,
        cab.inward,
        cab.ES,
        cab.E,
        cab.T_a,
    )
    b, frame, ident, f = body.b, body.frame, body.ident, body.f
    m = A.shape[0]
    px, py, pz = P[i, 0], P[i, 1], P[i, 2]
    tm = np.inf
    for c in range(m):
        rx = R[i, 0, 0] * b[c, 0] + R[i, 0, 1] * b[c, 1] + R[i, 0, 2] * b[c, 2]
        ry = R[i, 1, 0] * b[c, 0] + R[i, 1, 1] * b[c, 1] + R[i, 1, 2] * b[c, 2]
        rz = R[i, 2, 0] * b[c, 0] + R[i, 2, 1] * b[c, 1] + R[i, 2, 2] * b[c, 2]
        row = rows[c]
        cable_partials_axis(
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
            row,
        )
        k = ES[c] / L0[i, c]
        e = row[C_L] - L0[i, c]
        hooke = k * e
        tm = min(tm, abs(hooke))
        if hooke > 0.0:
            tm = min(tm, T_a[c] - hooke)
        t = hooke if e > 0.0 else 0.0
        ka = k if e > 0.0 else 0.0
        ux, uy, uz = row[C_U], row[C_U + 1], row[C_U + 2]
        _wrench_col(dF, c, t / E[c], 0.0, ux, uy, uz, 0.0, 0.0, 0.0, rx, ry, rz, 0.0, 0.0, 0.0)
        _wrench_col(
            dF,
            m + c,
            ka * row[C_DLH],
            t,
            ux,
            uy,
            uz,
            row[C_DUH],
            row[C_DUH + 1],
            row[C_DUH + 2],
            rx,
            ry,
            rz,
            0.0,
            0.0,
            0.0,
        )
        _wrench_col(
            dF,
            2 * m + c,
            ka * row[C_DLR],
            t,
            ux,
            uy,
            uz,
            row[C_DUR],
            row[C_DUR + 1],
            row[C_DUR + 2],
            rx,
            ry,
            rz,
            0.0,
            0.0,
            0.0,
        )
        _wrench_col(dF, 3 * m + c, ka * row[C_DLD], t, ux, uy, uz, 0.0, 0.0, 0.0, rx, ry, rz, 0.0, 0.0, 0.0)
        for a in range(3):
            # the anchor: the geometry depends on B - A
            _wrench_col(
                dF,
                4 * m + 3 * c + a,
                -ka * row[C_DLDP + a],
                t,
                ux,
                uy,
                uz,
                -row[C_DUDP + a],
                -row[C_DUDP + 3 + a],
                -row[C_DUDP + 6 + a],
                rx,
                ry,
                rz,
                0.0,
                0.0,
                0.0,
            )
            # the attachment: dB = dr = R e_a
            qx, qy, qz = R[i, 0, a], R[i, 1, a], R[i, 2, a]
            dL = row[C_DLDP] * qx + row[C_DLDP + 1] * qy + row[C_DLDP + 2] * qz
            _wrench_col(
                dF,
                7 * m + 3 * c + a,
                ka * dL,
                t,
                ux,
                uy,
                uz,
                row[C_DUDP] * qx + row[C_DUDP + 1] * qy + row[C_DUDP + 2] * qz,
                row[C_DUDP + 3] * qx + row[C_DUDP + 4] * qy + row[C_DUDP + 5] * qz,
                row[C_DUDP + 6] * qx + row[C_DUDP + 7] * qy + row[C_DUDP + 8] * qz,
                rx,
                ry,
                rz,
                qx,
                qy,
                qz,
            )
    fx, fy, fz = f[0], f[1], f[2]
    com = body.com
    rcx = R[i, 0, 0] * com[0] + R[i, 0, 1] * com[1] + R[i, 0, 2] * com[2]
    rcy = R[i, 1, 0] * com[0] + R[i, 1, 1] * com[1] + R[i, 1, 2] * com[2]
    rcz = R[i, 2, 0] * com[0] + R[i, 2, 1] * com[1] + R[i, 2, 2] * com[2]
    for a in range(3):  # the centre of mass: dM = R e_a x f
        col = 10 * m + a
        qx, qy, qz = R[i, 0, a], R[i, 1, a], R[i, 2, a]
        dF[0, col] = dF[1, col] = dF[2, col] = 0.0
        dF[3, col] = qy * fz - qz * fy
        dF[4, col] = qz * fx - qx * fz
        dF[5, col] = qx * fy - qy * fx
    col = 10 * m + 3  # the mass: f / M and (R c x f) / M
    dF[0, col], dF[1, col], dF[2, col] = fx / mass, fy / mass, fz / mass
    dF[3, col] = (rcy * fz - rcz * fy) / mass
    dF[4, col] = (rcz * fx - rcx * fz) / mass
    dF[5, col] = (rcx * fy - rcy * fx) / mass
    if not body.rigid:
        for a in range(3, 6):
            for col in range(dF.shape[1]):
                dF[a, col] = 0.0
    return tm


@njit(cache=True, error_model="numpy")
def scaled_condition(J, ell, rigid, Js):
    """``models.sensitivity.scaled_condition`` of one Jacobian: ||J_s||_F ||J_s^-1||_F of
    J_s = D^-1 J D^-1, D = diag(1, 1, 1, ell, ell, ell) (the 3 x 3 translation block unless
    ``rigid``), from its singular values; inf where J is singular or not finite.

    .. math:: \\kappa = \\sqrt{\\textstyle\\sum_k s_k^2} \\sqrt{\\textstyle\\sum_k s_k^{-2}}

    Parameters
    ----------
    J : ndarray (6, 6) [N/m, N/rad, N m/m, N m/rad]
        d(F, M)/d(dp, dphi).
    ell : float [m]
        The platform's size.
    rigid : bool
        Whether the moment rows count.
    Js : ndarray (6, 6)
        Work array.

    Returns
    -------
    cond : float [-]

    References
    ----------
    Golub, G. H., Van Loan, C. F. (2013). Matrix Computations, 4th ed., section 2.6.
    """
    n = 6 if rigid else 3
    ok = True
    for a in range(n):
        for c in range(n):
            v = J[a, c] / (ell if a >= 3 else 1.0) / (ell if c >= 3 else 1.0)
            ok = ok and math.isfinite(v)
            Js[a, c] = v
    if not ok:
        return np.inf
    s = np.linalg.svd(np.ascontiguousarray(Js[:n, :n]))[1]
    if not s[n - 1] > 0.0:
        return np.inf
    a2 = b2 = 0.0
    for k in range(n):
        a2 += s[k] * s[k]
        b2 += 1.0 / (s[k] * s[k])
    return math.sqrt(a2) * math.sqrt(b2)


@njit(cache=True, error_model="numpy")
def _sens_pose(i, P, R, L0, ok, cab, body, mass, cols, rcond, S, margin, cond, w, rows, dF, Js, Jp):
    """dx*/dθ at pose i into S[i], margin[i], cond[i] (``sensitivities_at``); w the ``scratch``
    record, rows (m, NCOL), dF (6, 10 m + 4), Js, Jp (6, 6) work arrays."""
    K = cols.shape[0]
    for a in range(6):
        for k in range(K):
            S[i, a, k] = np.nan
    margin[i] = np.nan
    cond[i] = np.inf
    if not ok[i]:
        return
    evaluate(
        P[i, 0],
        P[i, 1],
        P[i, 2],
        R[i],
        P[i, 0],
        P[i, 1],
        P[i, 2],
        cab,
        body,
        L0,
        i,
        w.t,
        w.J,
        w.e6,
        w.g6,
        w,
    )
    J = w.J
    margin[i] = wrench_partials(P, R, L0, i, cab, body, mass, rows, dF)
    finite = True
    for a in range(6):
        for c in range(6):
            finite = finite and math.isfinite(J[a, c])
    if not finite:
        return
    lu = body.rigid  # J^-1 by LU where it equals the pseudo-inverse (``lu_solve``'s bound)
    for c in range(6):
        if not lu:
            break
        for a in range(6):
            w.w6[a] = 1.0 if a == c else 0.0
        lu = lu_solve(J, w.w6, w.A6, w.V6, w.piv, w.s6, rcond)
        for a in range(6):
            Jp[a, c] = w.s6[a]
    if lu:  # ||J_s||_F ||J_s^-1||_F with J_s^-1 = D J^-1 D
        a2 = b2 = 0.0
        for a in range(6):
            for c in range(6):
                da = body.size if a >= 3 else 1.0
                dc = body.size if c >= 3 else 1.0
                a2 += (J[a, c] / da / dc) ** 2
                b2 += (Jp[a, c] * da * dc) ** 2
        cond[i] = math.sqrt(a2) * math.sqrt(b2)
    else:
        cond[i] = scaled_condition(J, body.size, body.rigid, Js)
        Jp[:, :] = np.linalg.pinv(J, rcond)
    for k in range(K):
        col = cols[k]
        for a in range(6):
            s = 0.0
            for c in range(6):
                s += Jp[a, c] * dF[c, col]
            S[i, a, k] = -s


@njit(cache=True, parallel=True, error_model="numpy")
def _sens_poses(P, R, L0, ok, cab, body, mass, cols, rcond, S, margin, cond):
    n = P.shape[0]
    m = cab.A.shape[0]
    nchunks = (n + CHUNK - 1) // CHUNK
    for ch in prange(nchunks):
        w = scratch(m)
        rows = np.empty((m, NCOL))
        dF = np.empty((6, 10 * m + 4))
        Js = np.empty((6, 6))
        Jp = np.empty((6, 6))
        for i in range(ch * CHUNK, min(n, (ch + 1) * CHUNK)):
            _sens_pose(i, P, R, L0, ok, cab, body, mass, cols, rcond, S, margin, cond, w, rows, dF, Js, Jp)


def sensitivities_at(robot, res, names=None, t_tol=T_TOL, threads=None):
    """Compiled ``models.sensitivity.sensitivities_at`` (same parameters and result; ``threads`` caps
    numba's threads): dp*/dθ and dφ*/dθ at the equilibria of a ``models.equilibrium.solve`` result.

    .. math:: \\frac{dx^*}{d\\theta} = -\\left(\\frac{\\partial F_6}{\\partial x}\\right)^{+}
        \\frac{\\partial F_6}{\\partial \\theta}, \\qquad x = (\\mathbf p, \\boldsymbol\\varphi)

    Parameters
    ----------
    robot : Robot
        The model at its nominal parameters.
    res : dict
        A ``solve_spatial`` result (P_s (N, 3) [m], R_s (N, 3, 3), L0 (N, m) [m], status (N,)), from
        either engine.
    names : list of str, optional
        Parameters (default ``parameter_names(robot, rigid=True)``); another name raises CdprError
        (``models.sensitivity.pose_columns``).
    t_tol : float [N]
        Tension margin under which a point is not smooth (``sensitivity.T_TOL``).
    threads : int, optional

    Returns
    -------
    dict
        names (n,); S (N, 6, n) [m or rad per unit of θ], NaN where the status is not ok; smooth
        (N,) bool; margin_t (N,) [N]; cond (N,) (as ``models.sensitivity.sensitivities_at``).

    References
    ----------
    Paty et al. 2021 (parameters); implicit-function theorem on Pott 2018's elastic equilibrium.
    """
    names, cols = pose_columns(robot, names)
    set_threads(threads)
    f = np.ascontiguousarray
    P = f(res["P_s"], dtype=float)
    n = len(P)
    ok = f(np.asarray(res["status"]) == "ok")
    S = np.empty((n, 6, len(names)))
    margin = np.empty(n)
    cond = np.empty(n)
    if n:
        cab = CompiledCables(robot)
        # the load whose partials by c and M are taken: the weight (a point mass's body.f adds an
        # external force, ``Platform.wrench``, which depends on no parameter; the Jacobian is the
        # same, its weight term vanishing there with c = 0)
        body = cab.body._replace(f=f(robot.platform.gravity_force, dtype=float))
        _sens_poses(
            P,
            f(res["R_s"], dtype=float),
            f(np.broadcast_to(np.asarray(res["L0"], dtype=float), (n, robot.m))),
            ok,
            cab.cables,
            body,
            float(robot.platform.mass),
            cols.astype(np.int64),
            PINV_RCOND,
            S,
            margin,
            cond,
        )
    smooth = ok & (margin > t_tol) & (cond < COND_MAX)
    return {"names": names, "S": S, "smooth": smooth, "margin_t": margin, "cond": cond}


def pose_sensitivities(robot, p, rotvec=None, L0=None, names=None, t_tol=T_TOL, threads=None, **solver):
    """Compiled ``models.sensitivity.pose_sensitivities``: the compiled ``solve_spatial`` then the
    compiled ``sensitivities_at`` (same parameters and result; ``threads`` caps numba's threads).

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Desired orientations.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths (default L_TS at the desired pose), held fixed.
    names : list of str, optional
        Parameters (default ``parameter_names(robot, rigid=True)``).
    t_tol : float [N]
        Tension margin of the smoothness flag.
    threads : int, optional
    solver : options of ``solve_spatial`` (tol, maxiter, max_step, restarts, P0).

    Returns
    -------
    dict
        As ``models.sensitivity.pose_sensitivities``.

    References
    ----------
    Paty et al. 2021 (parameters); implicit-function theorem on Pott 2018's elastic equilibrium.
    """
    res = solve_spatial(robot, p, rotvec, L0=L0, threads=threads, **solver)
    res.update(sensitivities_at(robot, res, names, t_tol))
    return res
