"""Inverse geometric models: standard IGM_S (eq. 1-2) and extended IGM_E (eq. 3-7)."""

from __future__ import annotations

import numpy as np

from .pulleys import pulley_state


def l_S(robot, P):
    """Standard useful length |A_i - P| (eq. 1 with b_i = 0), shape (..., m) [m]."""
    P = np.asarray(P, dtype=float)
    return np.linalg.norm(P[..., None, :] - robot.A, axis=-1)


def L_TS(robot, P):
    """Standard total length L_TS = |P - A_i| + d_i (eq. 2), shape (..., m) [m]."""
    return l_S(robot, P) + robot.d


def igm_e(robot, P):
    """Extended inverse model of every cable at P (eq. 3-7): a PulleyState of arrays (..., m)."""
    return pulley_state(P, robot.A, robot.kind, robot.h, robot.r_p, robot.d, robot.inward)
