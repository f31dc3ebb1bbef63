"""Kinematics of one pulley per cable (Paty et al. 2021, eq. 3-7, as read in docs/models.md).

Everything of cable i happens in the vertical plane through A_i that contains P: the swivel of an
SR pulley and the U-joint of a DR pulley both turn the sheave into that plane. In-plane coordinates
(s, w): origin A_i, s horizontal toward P, w = z. Then the winch exit is C = (0, -d) and
P = (rho, z_P - z_A). The cable runs C -> entry point K (on the side of the sheave facing the
swivel axis) -> over the top -> exit point D -> P.

All functions broadcast: P has shape (..., 3), per-cable parameters have shape (m,) or broadcast
against (..., m). Results have shape (..., m) or (..., m, 3).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

TWO_PI = 2.0 * np.pi
#: Horizontal distance [m] under which P counts as lying on the vertical through A_i.
RHO_EPS = 1e-12


@dataclass(frozen=True)
class PulleyState:
    """Extended inverse model of every cable at P; arrays of shape (..., m) unless stated.

    Attributes: H, K, D (points, shape (..., m, 3)) [m]; gamma wrap angle [rad]; l_d = |K - C| [m];
    l_E = |D - P| [m]; L_TE = l_d + r_p gamma + l_E [m] (eq. 5); alpha swivel angle [rad] (eq. 4);
    beta angle of the arm A->H below the horizontal [rad] (DR); inside: P or C inside the sheave
    circle (no tangent exists, lengths clipped); e_s (..., m, 2) horizontal unit vector of the cable
    plane and rho (..., m) horizontal distance A_i -> P [m].
    """

    H: np.ndarray
    K: np.ndarray
    D: np.ndarray
    gamma: np.ndarray
    l_d: np.ndarray
    l_E: np.ndarray
    L_TE: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    inside: np.ndarray
    e_s: np.ndarray
    rho: np.ndarray


def plane_frame(P, A, inward):
    """Horizontal unit vector e_s from A_i toward P and in-plane coordinates of P.

    Returns (e_s (..., m, 2), rho (..., m), w_P (..., m)). When P is on the vertical through A_i
    (rho < RHO_EPS) the plane direction is ``inward`` (deterministic, and every length is
    independent of it there by symmetry about the vertical).
    """
    dxy = P[..., None, :2] - A[:, :2]
    rho = np.hypot(dxy[..., 0], dxy[..., 1])
    on_axis = rho < RHO_EPS
    safe = np.where(on_axis, 1.0, rho)
    e_s = np.where(on_axis[..., None], inward, dxy / safe[..., None])
    w_P = P[..., None, 2] - A[:, 2]
    return e_s, rho, w_P


def sheave_centre(kind, h, rho, w_P, d):
    """In-plane sheave centre H = (H_s, H_w).

    SR (eq. 4): H = (h, 0). DR: H = h (e_C + e_P)/|e_C + e_P|, the bisector of the strand toward the
    winch e_C = (0, -1) and the strand toward P (erratum: the paper's a_i points C -> A; the strand
    toward the winch is -a_i). fixed: H = A (h = 0).
    """
    n_P = np.hypot(rho, w_P)
    n_P = np.where(n_P > 0, n_P, 1.0)
    bs = rho / n_P
    bw = w_P / n_P - 1.0
    nb = np.hypot(bs, bw)
    nb = np.where(nb > 0, nb, 1.0)
    is_dr = kind == 2
    H_s = np.where(is_dr, h * bs / nb, h)
    H_w = np.where(is_dr, h * bw / nb, 0.0)
    return H_s, H_w


def _tangent(Xs, Xw, H_s, H_w, r_p):
    """Polar angle phi of X about H, distance R, tangent offset delta = arccos(r_p / R)."""
    rs, rw = Xs - H_s, Xw - H_w
    R = np.hypot(rs, rw)
    phi = np.arctan2(rw, rs)
    ratio = np.divide(r_p, R, out=np.zeros_like(R), where=R > 0)
    inside = ratio > 1.0
    delta = np.arccos(np.minimum(ratio, 1.0))
    return phi, R, delta, inside


def pulley_state(P, A, kind, h, r_p, d, inward):
    """Extended inverse geometric model IGM_E of every cable at points P, eq. (3)-(7).

    Parameters: P (..., 3) [m]; A (m, 3) joint points [m]; kind (m,) codes 0 fixed / 1 SR / 2 DR;
    h (m,) lever arms [m]; r_p (m,) sheave radii [m]; d (m,) dead lengths [m]; inward (m, 2).
    """
    P = np.asarray(P, dtype=float)
    e_s, rho, w_P = plane_frame(P, A, inward)
    H_s, H_w = sheave_centre(kind, h, rho, w_P, d)
    phi_P, R_P, delta_P, in_P = _tangent(rho, w_P, H_s, H_w, r_p)
    phi_C, R_C, delta_C, in_C = _tangent(0.0, -d, H_s, H_w, r_p)
    theta_D = phi_P + delta_P
    theta_K = phi_C - delta_C
    gamma = np.mod(theta_K - theta_D, TWO_PI)
    l_E = np.sqrt(np.maximum(R_P**2 - r_p**2, 0.0))
    l_d = np.sqrt(np.maximum(R_C**2 - r_p**2, 0.0))
    L_TE = l_d + r_p * gamma + l_E

    def lift(s, w):
        return (
            A
            + s[..., None] * np.concatenate([e_s, np.zeros(e_s.shape[:-1] + (1,))], axis=-1)
            + w[..., None] * np.array([0.0, 0.0, 1.0])
        )

    H = lift(H_s, H_w)
    D = lift(H_s + r_p * np.cos(theta_D), H_w + r_p * np.sin(theta_D))
    K = lift(H_s + r_p * np.cos(theta_K), H_w + r_p * np.sin(theta_K))
    alpha = np.arctan2(-e_s[..., 1], e_s[..., 0])
    beta = np.arctan2(H_w, np.where((H_s == 0) & (H_w == 0), 1.0, H_s))
    return PulleyState(
        H=H,
        K=K,
        D=D,
        gamma=gamma,
        l_d=l_d,
        l_E=l_E,
        L_TE=L_TE,
        alpha=alpha,
        beta=beta,
        inside=in_P | in_C,
        e_s=e_s,
        rho=rho,
    )


#: Horizontal distance [m] under which the swivel term of du/dP is left out (it is singular on the axis).
SWIVEL_RHO_MIN = 1e-9


class CableGeometry(NamedTuple):
    """What the direct solvers need of every cable at P (``total_length_and_direction``); shapes
    (..., m) or (..., m, 3).

    L_TE [m]; u = (D - P)/|D - P| unit vector from P toward the exit point (eq. 12); l_E = |D - P|
    [m]; inside flag; swivel = D_s / rho and e_perp, the horizontal normal of the cable plane (the
    swivel carries D round the joint axis when P leaves the plane); and, for DR pulleys, the arm's
    rotation: P's in-plane motion dP turns the strand direction A -> P by (eps . dP)/|AP| and the
    arm (the bisector) by half of it, so dH/dP = arm beta eps^T with arm = h / (2 |AP|), beta the
    arm's in-plane normal and eps the strand's (0 for SR and fixed pulleys); u_beta = u . beta and
    uC_beta = u_C . beta with u_C the unit vector from the winch exit C toward K.
    """

    L_TE: np.ndarray
    u: np.ndarray
    l_E: np.ndarray
    inside: np.ndarray
    swivel: np.ndarray
    e_perp: np.ndarray
    arm: np.ndarray
    beta: np.ndarray
    eps: np.ndarray
    u_beta: np.ndarray
    uC_beta: np.ndarray


def total_length_and_direction(P, A, kind, h, r_p, d, inward):
    """The extended inverse model reduced to what the direct solvers need: a CableGeometry."""
    P = np.asarray(P, dtype=float)
    st = pulley_state(P, A, kind, h, r_p, d, inward)
    v = st.D - P[..., None, :]
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    n = np.where(n > 0, n, 1.0)
    D_s = np.einsum("...i,...i->...", (st.D - A)[..., :2], st.e_s)
    swivel = np.divide(D_s, st.rho, out=np.zeros_like(D_s), where=st.rho > SWIVEL_RHO_MIN)
    zero = np.zeros_like(st.rho)
    e_perp = np.stack([-st.e_s[..., 1], st.e_s[..., 0], zero], axis=-1)
    # DR arm: in-plane unit normals of the strand A -> P (eps) and of the bisector (beta), lifted to 3D
    w_P = P[..., None, 2] - A[:, 2]
    n_P = np.hypot(st.rho, w_P)
    ok_P = n_P > 0
    n_P = np.where(ok_P, n_P, 1.0)
    b_s, b_w = st.rho / n_P, w_P / n_P - 1.0
    n_b = np.hypot(b_s, b_w)
    arm = np.where((kind == 2) & ok_P & (n_b > 0), h / (2.0 * n_P), 0.0)
    n_b = np.where(n_b > 0, n_b, 1.0)

    def lift(s, w):
        return np.stack([s * st.e_s[..., 0], s * st.e_s[..., 1], w], axis=-1)

    beta = lift(-b_w / n_b, b_s / n_b)
    eps = lift(-w_P / n_P, st.rho / n_P)
    l_d = np.where(st.l_d > 0, st.l_d, 1.0)
    uC_beta = (np.einsum("...i,...i->...", st.K - A, beta) + d * beta[..., 2]) / l_d  # C = A - d z
    u = v / n
    u_beta = np.einsum("...i,...i->...", u, beta)
    return CableGeometry(st.L_TE, u, n[..., 0], st.inside, swivel, e_perp, arm, beta, eps, u_beta, uC_beta)
