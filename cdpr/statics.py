"""Statics of a point-mass platform held by three cables and Hooke elasticity (eq. 10-13)."""
from __future__ import annotations

import numpy as np

#: |det| of the three unit cable vectors under which the three cables count as coplanar.
DET_EPS = 1e-12


def inverse3(M):
    """Batched inverse of 3x3 matrices by cofactors; M (..., 3, 3). Returns (M^-1, det); NaN where
    |det| < DET_EPS (the caller flags it); no exception for a singular member of the batch."""
    c0, c1, c2 = M[..., :, 0], M[..., :, 1], M[..., :, 2]
    rows = np.stack([np.cross(c1, c2), np.cross(c2, c0), np.cross(c0, c1)], axis=-2)
    det = np.einsum("...i,...i->...", c0, rows[..., 0, :])
    ok = np.abs(det) >= DET_EPS
    inv_det = np.divide(1.0, det, out=np.full_like(det, np.nan), where=ok)
    return rows * inv_det[..., None, None], det


def solve3(M, b):
    """Batched solve of M x = b for 3x3 systems; M (..., 3, 3), b (..., 3). Returns (x, det);
    x is NaN where |det| < DET_EPS."""
    inv, det = inverse3(M)
    return np.einsum("...ij,...j->...i", inv, b), det


def tensions(u, w_ext):
    """Cable tensions t from the equilibrium sum_j t_j u_j + w_ext = 0 (eq. 11-12).

    u (..., 3, 3): unit vectors along the three cables, from P toward their exit points, one per
    row; w_ext (3,) [N]. Returns (t (..., 3) [N], M^-1 (..., 3, 3)): t is NaN where the cables are
    coplanar. M = [u_1 u_2 u_3] (columns)."""
    inv, _ = inverse3(np.swapaxes(u, -1, -2))
    return np.einsum("...ij,j->...i", inv, -np.asarray(w_ext, dtype=float)), inv


def tension_gradient(u, l_E, t, M_inv, swivel, e_perp):
    """dt/dP (..., 3, 3) from differentiating M t = -w_ext with
    du_j/dP = -[(I - u_j u_j^T) - (D_s/rho)_j e_perp,j e_perp,j^T] / |l_E,j|.

    In the cable plane the exit point slides along the cable, so u turns as if D were fixed; out of
    the plane the swivel carries D round the joint axis by D_s/rho of P's displacement (exact for
    SR pulleys; for DR the arm's own rotation is left out, ~2 % of du/dP)."""
    w = t / l_E
    G = (np.einsum("...j,...ja,...jb->...ab", w, u, u) - w.sum(axis=-1)[..., None, None] * np.eye(3)
         + np.einsum("...j,...ja,...jb->...ab", w * swivel, e_perp, e_perp))
    return -M_inv @ G


def stretched_length(L0, t, ES):
    """Hooke's law (eq. 10, 13): a cable of rest length L0 under tension t [N] is L0 (1 + t / (E S))."""
    return L0 * (1.0 + t / ES)


def equilibrium_residual(u, t, w_ext):
    """|sum_j t_j u_j + w_ext| [N], shape (...)."""
    return np.linalg.norm(np.einsum("...j,...jk->...k", t, u) + w_ext, axis=-1)
