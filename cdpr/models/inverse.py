"""Inverse geometric models: standard IGM_S (Paty 2021 eq. 1-2) and extended IGM_E (eq. 3-7).

The paper's platform is a point mass (b_i = 0): the models take its positions P, and on a rigid
platform (attachments b_i) poses, each cable at its attachment point B_i = p + R b_i. The winch exit
C_i lies the dead length d_i from the pulley joint point A_i along the swivel axis (straight below
for the paper's vertical axes: a_i collinear with z_b, |a_i| = d_i).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import numpy as np

from cdpr.errors import CdprError
from cdpr.models.platform import attachment_points, rotation_matrix
from cdpr.models.pulleys import pulley_state


def attachments(robot, P, rotvec=None, R=None):
    """The points the inverse models take: P itself on a point-mass platform, else the attachment
    points B_i = p + R b_i of each cable at poses (no paper equation; Paty 2021 section 2.1).

    Parameters
    ----------
    robot : Robot
    P : array_like (..., 3) [m] or (N, 6) [m, rad]
        Positions, or poses (x, y, z, rx, ry, rz). On a point-mass robot an orientation plays no
        part (B_i = p).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Orientation of positions P (default identity; ignored when P holds poses).
    R : array_like (N, 3, 3) [-], optional
        Orientation matrices of positions P, in place of ``rotvec``.

    Returns
    -------
    B : ndarray (..., 3) or (N, m, 3) [m]
    per_cable : bool
        True when B holds one point per cable (a rigid platform).
    """
    P = np.asarray(P, dtype=float)
    if P.shape[-1:] not in ((3,), (6,)):
        raise CdprError(f"positions (..., 3) [m] or poses (N, 6) [m, rad] expected, got shape {P.shape}")
    if robot.point_mass:
        return (P[..., :3] if P.shape[-1] == 6 else P), False
    P = np.atleast_2d(P)
    if P.ndim != 2:
        raise CdprError(f"poses of a rigid platform are (N, 3) or (N, 6), got shape {P.shape}")
    p, rv = (P[:, :3], P[:, 3:]) if P.shape[1] == 6 else (P, rotvec)
    if R is None or P.shape[1] == 6:
        rv = np.zeros_like(p) if rv is None else np.broadcast_to(np.asarray(rv, dtype=float), p.shape)
        R = rotation_matrix(rv)
    return attachment_points(p, R, robot.arrays.b), True


def l_S(robot, P, rotvec=None, R=None):
    """Standard useful length l_S,i = |B_i - A_i| (Paty 2021 eq. 1), B_i = P on a point mass.

    .. math:: l_{S,i} = \\lVert p + R\\,b_i - a_i - c_i \\rVert = \\lVert B_i - A_i \\rVert

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m] (and the attachments b_i of a rigid platform).
    P : array_like (..., 3) [m] or (N, 6) [m, rad]
        Platform positions or poses (``attachments``).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Orientation of a rigid platform at positions P (default identity).
    R : array_like (N, 3, 3) [-], optional
        Orientation matrices at positions P, in place of ``rotvec`` (``attachments``).

    Returns
    -------
    l_S : ndarray (..., m) [m]
        Distance from each joint point A_i to its attachment point.
    """
    B, per_cable = attachments(robot, P, rotvec, R)
    return np.linalg.norm((B if per_cable else B[..., None, :]) - robot.A, axis=-1)


def L_TS(robot, P, rotvec=None, R=None):
    """Standard total length L_TS,i = |B_i - A_i| + d_i (Paty 2021 eq. 2), B_i = P on a point mass.

    .. math:: L_{TS,i} = \\lVert l_{S,i} \\rVert + \\lVert l_{d,i} \\rVert, \\quad \\lVert l_{d,i} \\rVert = d_i

    This is the length a controller using the standard model commands (the default commanded
    length of DEGM_E and of the physical mode).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m] and the dead lengths d (m,) [m].
    P : array_like (..., 3) [m] or (N, 6) [m, rad]
        Platform positions or poses (``attachments``).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Orientation of a rigid platform at positions P (default identity).
    R : array_like (N, 3, 3) [-], optional
        Orientation matrices at positions P, in place of ``rotvec`` (``attachments``).

    Returns
    -------
    L_TS : ndarray (..., m) [m]
        Standard total cable lengths, winch exit C_i to B_i.
    """
    return l_S(robot, P, rotvec, R) + robot.d


def igm_e(robot, P, rotvec=None, R=None):
    """Extended inverse model IGM_E of every cable at its attachment point (Paty 2021 eq. 3-7),
    ``pulleys.pulley_state``; B_i = P on a point mass, p + R b_i at poses of a rigid platform.

    Parameters
    ----------
    robot : Robot
        Supplies A (m, 3) [m], kind (m,), h, r_p, d (m,) [m] and inward (m, 2).
    P : array_like (..., 3) [m] or (N, 6) [m, rad]
        Platform positions or poses (``attachments``).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Orientation of a rigid platform at positions P (default identity).
    R : array_like (N, 3, 3) [-], optional
        Orientation matrices at positions P, in place of ``rotvec`` (``attachments``).

    Returns
    -------
    PulleyState
        Arrays (..., m) and points (..., m, 3) [m]; ``L_TE`` (..., m) [m] is the extended total
        length of eq. (5).
    """
    B, per_cable = attachments(robot, P, rotvec, R)
    return pulley_state(B, *pulley_args(robot), per_cable=per_cable)


def pulley_args(robot):
    """The per-cable arrays every pulley model takes, in ``pulleys.pulley_state``'s order: joint
    points A (m, 3) [m], kind (m,), h, r_p, d (m,) [m], inward (m, 2) and the pulley frames
    (m, 3, 3), None for a suspended point-mass robot (vertical axes: the identity frames).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    tuple
        (A, kind, h, r_p, d, inward, frame).
    """
    a = robot.arrays
    frame = None if robot.suspended_point_mass else a.frame
    return a.A, a.kind, a.h, a.r_p, a.d, a.inward, frame


def pose_state(robot, p, R):
    """The extended inverse model (``pulleys.pulley_state``, Paty 2021 eq. 3-7) of every cable at
    poses (p, R): the attachment points B_i = p + R b_i (N, m, 3) [m] and the PulleyState at them.

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) [m]
        Reference points.
    R : ndarray (N, 3, 3) [-]
        Orientations.

    Returns
    -------
    B : ndarray (N, m, 3) [m]
    state : PulleyState
        Arrays (N, m); L_TE is Paty 2021 eq. (5) at B_i.
    """
    B = attachment_points(p, R, robot.arrays.b)
    return B, pulley_state(B, *pulley_args(robot), per_cable=True)
