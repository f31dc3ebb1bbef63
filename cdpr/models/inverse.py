"""Inverse geometric models: standard IGM_S (Paty 2021 eq. 1-2) and extended IGM_E (eq. 3-7).

The platform is a point mass (b_i = 0) and the winch exit C_i lies the dead length d_i straight below
the pulley joint point A_i (the paper's a_i collinear with z_b, |a_i| = d_i).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import numpy as np

from cdpr.models.pulleys import pulley_state


def l_S(robot, P):
    """Standard useful length l_S,i = |P - A_i| (Paty 2021 eq. 1 with b_i = 0).

    .. math:: l_{S,i} = \\lVert p - a_i - c_i \\rVert = \\lVert P - A_i \\rVert

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m].
    P : array_like (..., 3) [m]
        Platform positions.

    Returns
    -------
    l_S : ndarray (..., m) [m]
        Distance from each joint point A_i to P.
    """
    P = np.asarray(P, dtype=float)
    return np.linalg.norm(P[..., None, :] - robot.A, axis=-1)


def L_TS(robot, P):
    """Standard total length L_TS,i = |P - A_i| + d_i (Paty 2021 eq. 2).

    .. math:: L_{TS,i} = \\lVert l_{S,i} \\rVert + \\lVert l_{d,i} \\rVert, \\quad \\lVert l_{d,i} \\rVert = d_i

    This is the length a controller using the standard model commands (the default commanded
    length of DEGM_E and of the physical mode).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m] and the dead lengths d (m,) [m].
    P : array_like (..., 3) [m]
        Platform positions.

    Returns
    -------
    L_TS : ndarray (..., m) [m]
        Standard total cable lengths, winch exit C_i to P.
    """
    return l_S(robot, P) + robot.d


def igm_e(robot, P):
    """Extended inverse model IGM_E of every cable at P (Paty 2021 eq. 3-7), ``pulleys.pulley_state``.

    Parameters
    ----------
    robot : Robot
        Supplies A (m, 3) [m], kind (m,), h, r_p, d (m,) [m] and inward (m, 2).
    P : array_like (..., 3) [m]
        Platform positions.

    Returns
    -------
    PulleyState
        Arrays (..., m) and points (..., m, 3) [m]; ``L_TE`` (..., m) [m] is the extended total
        length of eq. (5).
    """
    frame = None if robot.suspended_point_mass else robot.arrays.frame
    return pulley_state(P, robot.A, robot.kind, robot.h, robot.r_p, robot.d, robot.inward, frame)
