"""Statics of a point-mass platform held by three cables and Hooke elasticity (eq. 10-13)."""
from __future__ import annotations

import numpy as np

#: |det| of the three unit cable vectors under which the three cables count as coplanar.
DET_EPS = 1e-12


def solve3(M, b):
    """Batched solve of M x = b for 3x3 systems by cofactors; M (..., 3, 3), b (..., 3).

    Returns (x, det). Where |det| < DET_EPS, x is NaN (the caller flags it); no exception is
    raised for a singular member of the batch.
    """
    c0, c1, c2 = M[..., :, 0], M[..., :, 1], M[..., :, 2]
    r0 = np.cross(c1, c2)
    r1 = np.cross(c2, c0)
    r2 = np.cross(c0, c1)
    det = np.einsum("...i,...i->...", c0, r0)
    ok = np.abs(det) >= DET_EPS
    inv_det = np.divide(1.0, det, out=np.full_like(det, np.nan), where=ok)
    x = np.stack([np.einsum("...i,...i->...", r, b) for r in (r0, r1, r2)], axis=-1) * inv_det[..., None]
    return x, det


def tensions(u, w_ext):
    """Cable tensions t from the equilibrium sum_j t_j u_j + w_ext = 0 (eq. 11-12).

    u (..., 3, 3): unit vectors along the three cables, from P toward their exit points, one per
    row; w_ext (3,) [N]. Returns (t (..., 3) [N], det): t is NaN where the cables are coplanar.
    """
    M = np.swapaxes(u, -1, -2)  # columns u_j
    b = np.broadcast_to(-np.asarray(w_ext, dtype=float), u.shape[:-1])
    return solve3(M, b)


def stretched_length(L0, t, ES):
    """Hooke's law (eq. 10, 13): a cable of rest length L0 under tension t [N] is L0 (1 + t / (E S))."""
    return L0 * (1.0 + t / ES)


def equilibrium_residual(u, t, w_ext):
    """|sum_j t_j u_j + w_ext| [N], shape (...)."""
    return np.linalg.norm(np.einsum("...j,...jk->...k", t, u) + w_ext, axis=-1)
