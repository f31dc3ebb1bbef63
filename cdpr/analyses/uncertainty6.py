"""Pose error of a rigid 6-DoF platform under parameter vectors θ (``parameter_names6``): the
spatial counterpart of ``uncertainty.PoseErrorModel`` (physical mode, the only mode of a spatial
robot). Responses: ‖δp‖ [m] and δφ [rad] (angle of R*ᵀR_d). First step of issues 17/19: the
uncompensated case (nominal L_TS at the desired pose), full solves and the linearisation by the
implicit-function theorem (``sensitivity6.sensitivities_at``). Not yet wired into the study."""

import numpy as np

from cdpr.models.equilibrium6 import L_TS_pose, pose_arrays, solve_spatial
from cdpr.models.sensitivity6 import sensitivities_at
from cdpr.parameters import parameter_names6, parameter_values6, robot_with_parameters6


def spatial_theta(robot, theta):
    """6-DoF parameter vectors of point-mass ones (``parameter_names``, as ``uncertainty.drivers``
    and ``parameter_samples`` build them): E, h, r_p, d and A keep their columns, M moves to the
    last column, the attachments b and the centre of mass c keep their nominal values.

    Parameters
    ----------
    robot : Robot
        The nominal spatial robot.
    theta : array_like (n, 7 m + 1) [Pa, m, kg]

    Returns
    -------
    theta6 : ndarray (n, 10 m + 4) [Pa, m, kg]
        In the order of ``parameter_names6``.
    """
    th = np.atleast_2d(np.asarray(theta, dtype=float))
    m = robot.m
    out = np.tile(parameter_values6(robot), (len(th), 1))
    out[:, : 7 * m] = th[:, : 7 * m]
    out[:, -1] = th[:, 7 * m]
    return out


class PoseErrorModel6:
    """‖δp‖ and δφ of a spatial robot at desired poses when its parameters are θ.

    Parameters
    ----------
    robot : Robot
        The nominal robot (computes the commanded rest lengths).
    p : array (N, 3) [m]
        Desired positions.
    rotvec : array (N, 3) or (3,) [rad], optional
        Desired orientations (default identity).
    """

    def __init__(self, robot, p, rotvec=None):
        self.robot = robot
        self.p, self.R = pose_arrays(robot, p, rotvec)
        self.rotvec = (
            np.zeros((len(self.p), 3)) if rotvec is None else np.broadcast_to(rotvec, (len(self.p), 3))
        )
        self.L0 = L_TS_pose(robot, self.p, self.R)

    def solve(self, theta):
        """Full solves: ‖δp‖ (n, N) [m], δφ (n, N) [rad], ok (n, N) for θ (n, 10 m + 4)."""
        th = np.atleast_2d(theta)
        n, N = len(th), len(self.p)
        dp, dphi = np.full((n, N), np.nan), np.full((n, N), np.nan)
        ok = np.zeros((n, N), dtype=bool)
        for i, t in enumerate(th):
            res = solve_spatial(robot_with_parameters6(self.robot, t), self.p, self.rotvec, L0=self.L0)
            ok[i] = res["status"] == "ok"
            dp[i], dphi[i] = res["dp"], res["dphi"]
        return dp, dphi, ok

    def linearise(self):
        """Nominal pose error x0 = (δp, δφ) (N, 6) [m, rad] and S = dx*/dθ (N, 6, 10 m + 4)."""
        res = solve_spatial(self.robot, self.p, self.rotvec, L0=self.L0)
        sens = sensitivities_at(self.robot, res, parameter_names6(self.robot.m))
        return {
            "P_s": res["P_s"],
            "R_s": res["R_s"],
            "S": sens["S"],
            "smooth": sens["smooth"],
            "theta0": parameter_values6(self.robot),
            "status": res["status"],
        }
