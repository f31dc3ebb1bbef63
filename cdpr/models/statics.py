"""Statics of a point-mass platform held by three cables and Hooke elasticity (Paty 2021 eq. 10-13).

Eq. (11) is the force balance W t + w_ext = 0, eq. (12) the matrix of unit cable vectors
M = -[l_E,1/|l_E,1| ... l_E,m/|l_E,m|] (columns u_i from P toward the exit point D_i), eq. (10) and
(13) Hooke's law, Delta L_T,i = t_i L_T,i / (E S_i). The gradients with respect to P are this
project's derivatives of those equations (no paper equation), used by the Newton solvers.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import numpy as np

#: |det| of the three unit cable vectors under which the three cables count as coplanar.
DET_EPS = 1e-12


def inverse3(M):
    """Batched inverse of 3x3 matrices by cofactors (linear algebra, no paper equation).

    Parameters
    ----------
    M : ndarray (..., 3, 3) [any unit]
        Matrices to invert.

    Returns
    -------
    M_inv : ndarray (..., 3, 3) [1 / unit of M]
        The inverses; NaN where |det| < DET_EPS (the caller flags it); no exception for a singular
        member of the batch.
    det : ndarray (...) [unit of M cubed]
        The determinants.
    """
    c0, c1, c2 = M[..., :, 0], M[..., :, 1], M[..., :, 2]
    rows = np.stack([np.cross(c1, c2), np.cross(c2, c0), np.cross(c0, c1)], axis=-2)
    det = np.einsum("...i,...i->...", c0, rows[..., 0, :])
    ok = np.abs(det) >= DET_EPS
    inv_det = np.divide(1.0, det, out=np.full_like(det, np.nan), where=ok)
    return rows * inv_det[..., None, None], det


def solve3(M, b):
    """Batched solve of M x = b for 3x3 systems (``inverse3`` applied to b; no paper equation).

    Parameters
    ----------
    M : ndarray (..., 3, 3) [any unit]
        System matrices.
    b : ndarray (..., 3) [any unit]
        Right-hand sides.

    Returns
    -------
    x : ndarray (..., 3) [unit of b / unit of M]
        Solutions; NaN where |det| < DET_EPS.
    det : ndarray (...) [unit of M cubed]
        The determinants of M.
    """
    inv, det = inverse3(M)
    return np.einsum("...ij,...j->...i", inv, b), det


def tensions(u, w_ext):
    """Cable tensions t from the equilibrium sum_j t_j u_j + w_ext = 0 (Paty 2021 eq. 11-12).

    .. math:: M t + w_{ext} = 0, \\quad M = [u_1 \\; u_2 \\; u_3], \\quad t = -M^{-1} w_{ext}

    Parameters
    ----------
    u : ndarray (..., 3, 3) [-]
        Unit vectors along the three cables, from P toward their exit points, one per row
        (``CableGeometry.u`` of a 3-cable subset); the matrix M of eq. (12) has them as columns.
    w_ext : array_like (3,) [N]
        External force on the platform (``Platform.w_ext`` = (0, 0, -mass g)).

    Returns
    -------
    t : ndarray (..., 3) [N]
        Tensions of the three cables; NaN where the cables are coplanar (|det M| < DET_EPS).
        Negative entries are pushing cables (the caller rejects them).
    M_inv : ndarray (..., 3, 3) [-]
        M^-1, reused by ``tension_gradient``.
    """
    inv, _ = inverse3(np.swapaxes(u, -1, -2))
    return np.einsum("...ij,j->...i", inv, -np.asarray(w_ext, dtype=float)), inv


def tension_gradient(t, M_inv, g):
    """dt/dP (..., 3, 3) from differentiating M t = -w_ext (Paty 2021 eq. 11-12), with g the
    CableGeometry at P and

        du_j/dP = -[(I - u_j u_j^T) - (D_s/rho)_j e_perp,j e_perp,j^T - arm_j (I - u_j u_j^T) beta_j eps_j^T] / |l_E,j|

    In the cable plane the exit point slides along the cable, so u turns only as D's pulley
    centre moves (the DR arm's rotation); out of the plane the swivel carries D round the joint
    axis by D_s/rho of P's displacement. Then dt/dP = -M^-1 sum_j t_j du_j/dP.

    Parameters
    ----------
    t : ndarray (..., 3) [N]
        Tensions at P (``tensions``).
    M_inv : ndarray (..., 3, 3) [-]
        Inverse of M = [u_1 u_2 u_3] (``tensions``).
    g : CableGeometry
        ``pulleys.total_length_and_direction`` of the three cables at P, arrays (..., 3) and
        (..., 3, 3).

    Returns
    -------
    dt_dP : ndarray (..., 3, 3) [N/m]
        ``dt_dP[..., j, b]`` = d t_j / d P_b.
    """
    w, u = t / g.l_E, g.u
    lever = (w * g.arm)[..., None] * (g.beta - g.u_beta[..., None] * u)
    G = (
        np.einsum("...j,...ja,...jb->...ab", w, u, u)
        - w.sum(axis=-1)[..., None, None] * np.eye(3)
        + np.einsum("...j,...ja,...jb->...ab", w * g.swivel, g.e_perp, g.e_perp)
        + np.einsum("...ja,...jb->...ab", lever, g.eps)
    )
    return -M_inv @ G


def length_gradient(g):
    """dL_TE/dP (..., m, 3) = -u + arm ((u + u_C) . beta) eps: moving P shortens the cable along u
    (eq. 5 is a tangent length plus an arc), and the DR arm's rotation moves the sheave by dH, which
    lengthens it by (u + u_C) . dH.

    The gradient of Paty 2021 eq. (5) with respect to the platform position.

    Parameters
    ----------
    g : CableGeometry
        ``pulleys.total_length_and_direction`` at P, arrays (..., m) and (..., m, 3).

    Returns
    -------
    dL_dP : ndarray (..., m, 3) [m/m]
        ``dL_dP[..., i, b]`` = d L_TE,i / d P_b.
    """
    return -g.u + (g.arm * (g.u_beta + g.uC_beta))[..., None] * g.eps


def stretched_length(L0, t, ES):
    """Hooke's law (Paty 2021 eq. 10, 13): a cable of rest length L0 under tension t [N] is
    L0 (1 + t / (E S)).

    .. math:: L = L_0 + \\Delta L_T, \\quad \\Delta L_T = \\frac{t L_0}{E S}

    Parameters
    ----------
    L0 : array_like (..., k) [m]
        Rest (unstretched) lengths.
    t : array_like (..., k) [N]
        Tensions.
    ES : array_like (k,) [N]
        Axial stiffness E_i S_i of each cable.

    Returns
    -------
    L : ndarray (..., k) [m]
        Stretched lengths.
    """
    return L0 * (1.0 + t / ES)


def equilibrium_residual(u, t, w_ext):
    """Residual of the force balance of Paty 2021 eq. (11), |sum_j t_j u_j + w_ext|.

    Parameters
    ----------
    u : ndarray (..., k, 3) [-]
        Unit cable vectors from P toward the exit points, one per row.
    t : ndarray (..., k) [N]
        Cable tensions.
    w_ext : array_like (3,) [N]
        External force on the platform.

    Returns
    -------
    residual : ndarray (...) [N]
        Norm of the unbalanced force.
    """
    return np.linalg.norm(np.einsum("...j,...jk->...k", t, u) + w_ext, axis=-1)


def direction_gradient(g):
    """Derivative of every cable's unit vector with respect to the platform position,

        du_i/dP = -[(I - u_i u_i^T) - (D_s/rho)_i e_perp,i e_perp,i^T - arm_i (I - u_i u_i^T) beta_i eps_i^T] / |l_E,i|

    the per-cable term that ``tension_gradient`` sums with the weights t_i (same reading: in the
    cable plane the exit point D slides along the cable, so u turns only as the sheave centre moves
    with the DR arm; out of the plane the swivel carries D round the joint axis by D_s/rho of P's
    displacement).

    Parameters
    ----------
    g : CableGeometry
        ``pulleys.total_length_and_direction`` at P, arrays (..., m) and (..., m, 3).

    Returns
    -------
    du_dP : ndarray, shape (..., m, 3, 3) [1/m]
        ``du_dP[..., i, a, b]`` = d u_i,a / d P_b.

    References
    ----------
    Paty et al. 2021, eq. (3)-(5) and (12).
    """
    u = g.u
    eye = np.eye(3)
    proj = eye - u[..., :, None] * u[..., None, :]
    arm_v = g.arm[..., None] * (g.beta - g.u_beta[..., None] * u)  # arm (I - u u^T) beta
    M = (
        proj
        - g.swivel[..., None, None] * g.e_perp[..., :, None] * g.e_perp[..., None, :]
        - arm_v[..., :, None] * g.eps[..., None, :]
    )
    return -M / g.l_E[..., None, None]
