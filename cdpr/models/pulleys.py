"""Kinematics of one pulley per cable (Paty et al. 2021, eq. 3-7, as read in docs/models.md).

Everything of cable i happens in the plane through the pulley's swivel axis k_i (through A_i) that
contains the cable's attachment point B_i (the platform point P for a point-mass platform; the
paper's axis is vertical, k_i = +z, and that plane is "the vertical plane through A_i that contains
P"): the swivel of an SR pulley and the U-joint of a DR pulley both turn the sheave into that plane.
In-plane coordinates (s, w): origin A_i, s perpendicular to k_i toward B_i, w along k_i. Then the
winch exit is C = A - d k = (0, -d) and B = (rho, (B - A) . k). The cable runs C -> entry point K (on
the side of the sheave facing the swivel axis) -> over the sheave's +k side -> exit point D -> B.
Each pulley has a frame (i_i, j_i, k_i) (``robot.pulley_frame``; the identity for k = +z); with the
identity frame the arithmetic is today's, bit for bit (the code takes the components directly).

All functions broadcast: P has shape (..., 3) (one platform point for every cable) or, with
``per_cable=True``, (..., m, 3) (each cable's own attachment point B_i of a rigid platform);
per-cable parameters have shape (m,) or broadcast against (..., m). Results have shape (..., m) or
(..., m, 3).

Equation numbers are those of Paty 2021: eq. (3) the extended useful length l_E = P - D, eq. (4)
the SR sheave position with the swivel angle alpha_i, eq. (5) the extended total length
L_TE = |l_E| + |l_d| + gamma r_p; the DR pulley (U-joint, sheave centre on a bisector) is section
2.2.2 and Fig. 5 (eq. 6-7), with the erratum on the bisector's strand in ``sheave_centre``.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
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
    beta angle of the arm A->H below the horizontal [rad] (DR; computed as atan2(H_w, H_s), so it
    is negative when the arm points down, 0 for SR and fixed pulleys); inside: P or C inside the
    sheave circle (no tangent exists, lengths clipped); e_s (..., m, 2) horizontal unit vector of
    the cable plane and rho (..., m) horizontal distance A_i -> P [m].
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
    e_s3: np.ndarray = None  #: (..., m, 3) e_s in the base frame
    w_P: np.ndarray = None  #: (..., m) [m] coordinate of B_i along k_i relative to A_i


def _points(P, A, per_cable):
    """B - A for every cable, shape (..., m, 3) [m]."""
    return (P if per_cable else P[..., None, :]) - A


def _components(W, frame):
    """Components (along i_i, j_i, k_i) of the per-cable vectors W (..., m, 3); identity frame: the
    coordinates themselves (no arithmetic)."""
    if frame is None:
        return W[..., 0], W[..., 1], W[..., 2]
    return tuple(np.einsum("...ma,ma->...m", W, frame[:, r]) for r in range(3))


def _lift(A, e_s2, s, w, frame):
    """The point A + s e_s + w k in the base frame, shape (..., m, 3) [m]."""
    if frame is None:
        return (
            A
            + s[..., None] * np.concatenate([e_s2, np.zeros(e_s2.shape[:-1] + (1,))], axis=-1)
            + w[..., None] * np.array([0.0, 0.0, 1.0])
        )
    return A + s[..., None] * _e_s3(e_s2, frame) + w[..., None] * frame[:, 2]


def _e_s3(e_s2, frame):
    """e_s (..., m, 2) in the pulley frame (i_i, j_i) as a base-frame vector (..., m, 3)."""
    if frame is None:
        return np.concatenate([e_s2, np.zeros(e_s2.shape[:-1] + (1,))], axis=-1)
    return e_s2[..., 0, None] * frame[:, 0] + e_s2[..., 1, None] * frame[:, 1]


def plane_frame(P, A, inward, frame=None, per_cable=False):
    """Unit vector e_s from A_i toward P perpendicular to the swivel axis, and in-plane coordinates of P.

    The cable plane of cable i is the plane through the axis k_i (through A_i) and P (vertical for
    k_i = +z): its azimuth is the swivel angle alpha_i of Paty 2021 eq. (4),
    e_s = (cos alpha_i, -sin alpha_i) in the pulley frame (i_i, j_i). When P is on the axis
    (rho < RHO_EPS) the plane direction is ``inward`` (deterministic, and every length is
    independent of it there by symmetry about the axis).

    Parameters
    ----------
    P : ndarray (..., 3) or, with ``per_cable``, (..., m, 3) [m]
        Platform positions, or each cable's attachment point B_i (an ndarray).
    A : ndarray (m, 3) [m]
        Pulley joint points A_i.
    inward : ndarray (m, 2) [-]
        Unit vector (in the pulley frame i_i, j_i) taken as e_s where P lies on the axis through
        A_i (``Robot.inward``: toward the anchors' centroid, or the pulley's ``zero``).
    frame : ndarray (m, 3, 3) [-], optional
        Rows i_i, j_i, k_i of each pulley frame (``Robot.arrays.frame``); None: the identity (k = +z).
    per_cable : bool
        P holds one point per cable.

    Returns
    -------
    e_s : ndarray (..., m, 2) [-]
        Unit vector of each cable plane perpendicular to k_i, from A_i toward P, in (i_i, j_i).
    rho : ndarray (..., m) [m]
        Distance from the axis to P (in-plane coordinate s of P).
    w_P : ndarray (..., m) [m]
        (P - A_i) . k_i (in-plane coordinate w of P; negative below A_i for k = +z).
    """
    ws, wt, w_P = _components(_points(P, A, per_cable), frame)
    rho = np.hypot(ws, wt)
    on_axis = rho < RHO_EPS
    safe = np.where(on_axis, 1.0, rho)
    dxy = np.stack([ws, wt], axis=-1)
    e_s = np.where(on_axis[..., None], inward, dxy / safe[..., None])
    return e_s, rho, w_P


def sheave_centre(kind, h, rho, w_P, d):
    """In-plane sheave centre H = (H_s, H_w).

    SR (Paty 2021 eq. 4, the arm h_i horizontal along the swivel direction): H = (h, 0).
    DR (section 2.2.2, Fig. 5): H = h (e_C + e_P)/|e_C + e_P|, the bisector of the strand toward
    the winch e_C = (0, -1) and the strand toward P, e_P = (rho, w_P)/|(rho, w_P)| (erratum: the
    paper's a_i points C -> A; the strand toward the winch is -a_i). fixed: H = A (h = 0).

    Parameters
    ----------
    kind : array (m,) int
        Pulley kind codes: 0 fixed, 1 SR, 2 DR (``robot.KIND_CODE``).
    h : array (m,) [m]
        Lever arms |A_i H_i|.
    rho : array (..., m) [m]
        Horizontal distance from A_i to P (``plane_frame``).
    w_P : array (..., m) [m]
        Height of P relative to A_i (``plane_frame``).
    d : array (m,) [m]
        Dead lengths |C_i A_i|; not used (the winch exit C lies straight below A_i, so e_C does not
        depend on d), kept for a signature parallel to ``pulley_state``.

    Returns
    -------
    H_s : array (..., m) [m]
        Horizontal in-plane coordinate of the sheave centre H_i relative to A_i (along e_s).
    H_w : array (..., m) [m]
        Vertical in-plane coordinate of H_i relative to A_i (0 for SR and fixed pulleys).
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


def pulley_state(P, A, kind, h, r_p, d, inward, frame=None, per_cable=False):
    """Extended inverse geometric model IGM_E of every cable at points P, Paty 2021 eq. (3)-(7).

    In the cable plane (``plane_frame``), with the sheave centre H (``sheave_centre``), the cable
    leaves the sheave at the tangent point D toward P and enters it at the tangent point K from the
    winch exit C = (0, -d); gamma is the wrap angle from D to K over the top, and (eq. 5)

    .. math:: L_{TE} = \\lVert l_d \\rVert + r_p \\gamma + \\lVert l_E \\rVert,
        \\quad \\lVert l_E \\rVert = \\sqrt{\\lVert H - P \\rVert^2 - r_p^2},
        \\quad \\lVert l_d \\rVert = \\sqrt{\\lVert H - C \\rVert^2 - r_p^2}

    Parameters
    ----------
    P : array_like (..., 3) [m]
        Platform positions.
    A : ndarray (m, 3) [m]
        Pulley joint points A_i.
    kind : ndarray (m,) int
        Pulley kind codes: 0 fixed, 1 SR, 2 DR.
    h : ndarray (m,) [m]
        Lever arms.
    r_p : ndarray (m,) [m]
        Sheave radii.
    d : ndarray (m,) [m]
        Dead lengths |C_i A_i| (winch exit C_i = A_i - d_i k_i).
    inward : ndarray (m, 2) [-]
        Fallback plane direction on the axis through A_i (``plane_frame``).
    frame : ndarray (m, 3, 3) [-], optional
        Pulley frames (rows i, j, k); None: the identity (k = +z, today's model).
    per_cable : bool
        P is (..., m, 3), one attachment point B_i per cable (rigid platform).

    Returns
    -------
    PulleyState
        Arrays (..., m), points (..., m, 3) [m]: H, K, D, gamma [rad], l_d [m], l_E [m], L_TE [m]
        (eq. 5), alpha [rad] (eq. 4), beta [rad], inside, e_s (..., m, 2) and rho [m].
    """
    P = np.asarray(P, dtype=float)
    e_s, rho, w_P = plane_frame(P, A, inward, frame, per_cable)
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
        return _lift(A, e_s, s, w, frame)

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
        e_s3=_e_s3(e_s, frame),
        w_P=w_P,
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


def total_length_and_direction(P, A, kind, h, r_p, d, inward, frame=None, per_cable=False):
    """The extended inverse model reduced to what the direct solvers need: a CableGeometry.

    L_TE is Paty 2021 eq. (5); u = (D - P)/|D - P| = -l_E/|l_E| is a column of the matrix M of
    eq. (12) (l_E of eq. 3); the remaining fields carry the pulley motion that the gradients of
    ``statics`` need (see ``CableGeometry``).

    Parameters
    ----------
    P : array_like (..., 3) [m]
        Platform positions.
    A : ndarray (m, 3) [m]
        Pulley joint points A_i.
    kind : ndarray (m,) int
        Pulley kind codes: 0 fixed, 1 SR, 2 DR.
    h : ndarray (m,) [m]
        Lever arms.
    r_p : ndarray (m,) [m]
        Sheave radii.
    d : ndarray (m,) [m]
        Dead lengths.
    inward : ndarray (m, 2) [-]
        Fallback plane direction on the axis through A_i.
    frame : ndarray (m, 3, 3) [-], optional
        Pulley frames (rows i, j, k); None: the identity (k = +z, today's model).
    per_cable : bool
        P is (..., m, 3), one attachment point B_i per cable; u then points from B_i toward D_i.

    Returns
    -------
    CableGeometry
        L_TE (..., m) [m]; u (..., m, 3) [-]; l_E (..., m) [m]; inside (..., m) bool;
        swivel (..., m) [-]; e_perp (..., m, 3) [-]; arm (..., m) [-]; beta, eps (..., m, 3) [-];
        u_beta, uC_beta (..., m) [-].
    """
    P = np.asarray(P, dtype=float)
    st = pulley_state(P, A, kind, h, r_p, d, inward, frame, per_cable)
    v = st.D - (P if per_cable else P[..., None, :])
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    n = np.where(n > 0, n, 1.0)
    if frame is None:
        D_s = np.einsum("...i,...i->...", (st.D - A)[..., :2], st.e_s)
        zero = np.zeros_like(st.rho)
        e_perp = np.stack([-st.e_s[..., 1], st.e_s[..., 0], zero], axis=-1)
    else:
        D_s = np.einsum("...i,...i->...", st.D - A, st.e_s3)
        e_perp = st.e_s[..., 0, None] * frame[:, 1] - st.e_s[..., 1, None] * frame[:, 0]  # k x e_s
    swivel = np.divide(D_s, st.rho, out=np.zeros_like(D_s), where=st.rho > SWIVEL_RHO_MIN)
    # DR arm: in-plane unit normals of the strand A -> P (eps) and of the bisector (beta), lifted to 3D
    w_P = st.w_P
    n_P = np.hypot(st.rho, w_P)
    ok_P = n_P > 0
    n_P = np.where(ok_P, n_P, 1.0)
    b_s, b_w = st.rho / n_P, w_P / n_P - 1.0
    n_b = np.hypot(b_s, b_w)
    arm = np.where((kind == 2) & ok_P & (n_b > 0), h / (2.0 * n_P), 0.0)
    n_b = np.where(n_b > 0, n_b, 1.0)

    def lift(s, w):
        if frame is None:
            return np.stack([s * st.e_s[..., 0], s * st.e_s[..., 1], w], axis=-1)
        return s[..., None] * st.e_s3 + w[..., None] * frame[:, 2]

    beta = lift(-b_w / n_b, b_s / n_b)
    eps = lift(-w_P / n_P, st.rho / n_P)
    l_d = np.where(st.l_d > 0, st.l_d, 1.0)
    beta_k = beta[..., 2] if frame is None else np.einsum("...ma,ma->...m", beta, frame[:, 2])
    uC_beta = (np.einsum("...i,...i->...", st.K - A, beta) + d * beta_k) / l_d  # C = A - d k
    u = v / n
    u_beta = np.einsum("...i,...i->...", u, beta)
    return CableGeometry(st.L_TE, u, n[..., 0], st.inside, swivel, e_perp, arm, beta, eps, u_beta, uC_beta)


#: Wrap angle [rad] beyond which a cable is flagged ``wrap_over_270``.
WRAP_LIMIT = 1.5 * np.pi


def swivel(P, A, frame, inward, per_cable=False):
    """Reported swivel angle of every pulley, atan2(w . j_i, w . i_i) with w = B_i - A_i [rad].

    The angle of the cable plane about the axis k_i measured from the pulley's ``zero`` i_i (the
    generalisation of Paty 2021 eq. (4): for k = +z and i = +x it is -alpha_i). On the axis it is
    the angle of the fallback plane ``inward``.

    Parameters
    ----------
    P : ndarray (..., 3) or (..., m, 3) with ``per_cable`` [m]
        Platform point or attachment points B_i.
    A : ndarray (m, 3) [m]
        Pulley joint points A_i.
    frame : ndarray (m, 3, 3) [-] or None
        Pulley frames (rows i, j, k); None: the identity.
    inward : ndarray (m, 2) [-]
        Fallback plane direction in (i_i, j_i).
    per_cable : bool
        P holds one point per cable.

    Returns
    -------
    swivel : ndarray (..., m) [rad]
        In (-pi, pi].

    References
    ----------
    Paty et al. 2021, eq. (4).
    """
    e_s, _, _ = plane_frame(np.asarray(P, dtype=float), A, inward, frame, per_cable)
    return np.arctan2(e_s[..., 1], e_s[..., 0])


def wrap(state):
    """Wrap angle of the cable on its sheave, gamma (eq. 5's arc r_p gamma) [rad], (..., m).

    Parameters
    ----------
    state : PulleyState
        ``pulley_state`` of the cables.

    Returns
    -------
    gamma : ndarray (..., m) [rad]
        In [0, 2 pi).

    References
    ----------
    Paty et al. 2021, eq. (5).
    """
    return state.gamma


def wrap_over_270(state):
    """True where a cable wraps more than 270 deg round its sheave (``WRAP_LIMIT``), (..., m): the
    attachment is in front of a wall pulley, inside its rim. The model length is still the literal
    one of eq. (5); this is a flag, not a refusal.

    Parameters
    ----------
    state : PulleyState
        ``pulley_state`` of the cables.

    Returns
    -------
    flag : ndarray (..., m) bool

    References
    ----------
    Paty et al. 2021, eq. (5).
    """
    return state.gamma > WRAP_LIMIT
