"""Pose error of a rigid 6-DoF platform under parameter vectors θ (``parameter_names6``): the
spatial counterpart of ``uncertainty.PoseErrorModel`` (physical mode, the only mode of a spatial
robot). Responses: ‖δp‖ [m] and δφ [rad] (angle of R*ᵀR_d). Cases (issue 19): ``uncompensated``
(the nominal robot's L_TS at the desired pose) and ``compensated`` (the nominal robot's rest lengths
under its minimum-norm tension distribution, ``tension_distribution.compensated_lengths``); full solves and
the linearisation by the implicit-function theorem (``sensitivity.sensitivities_at``), also as
two ``uncertainty.Linearisation`` objects (position and rotation vector) in the point-mass
parameter columns the study's drivers set (``linearisations``)."""

import numpy as np

from cdpr.analyses.uncertainty import CASES, Linearisation, nominal_theta
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays, rotvec_of
from cdpr.models.tension_distribution import compensated_lengths
from cdpr.parameters import parameter_names6, parameter_values6, robot_with_parameters6
from cdpr.solve import sensitivities_at, solve, solve_batch


def spatial_theta(robot, theta):
    """6-DoF parameter vectors of the drivers' ones (``uncertainty.drivers``, ``parameter_samples``):
    E, h, r_p, d and A keep their columns, M moves to the last column; the attachments b and the
    centre of mass c come from the columns after M where θ has them (10 m + 4 columns,
    ``uncertainty.nominal_theta``), else keep their nominal values.

    Parameters
    ----------
    robot : Robot
        The nominal spatial robot.
    theta : array_like (n, 7 m + 1) or (n, 10 m + 4) [Pa, m, kg]
        (E, h, r_p, d, A, M) or (E, h, r_p, d, A, M, b, c).

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
    if th.shape[1] == 10 * m + 4:
        out[:, 7 * m : 10 * m + 3] = th[:, 7 * m + 1 :]
    return out


def spatial_columns(m, columns):
    """The ``parameter_names6`` columns of the drivers' parameter columns (``spatial_theta``'s map).

    Parameters
    ----------
    m : int
        Number of cables.
    columns : array_like (k,) of int
        Columns of (E, h, r_p, d, A, M, b, c): ``parameter_names(m)`` and, after it, b and c.

    Returns
    -------
    columns6 : ndarray (k,) of int
    """
    c = np.asarray(columns, dtype=np.intp)
    return np.where(c < 7 * m, c, np.where(c == 7 * m, 10 * m + 3, c - 1))


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
    case : {"uncompensated", "compensated"}
        The commanded rest lengths: the nominal L_TS, or the nominal robot's compensated lengths
        (``compensation``: method and t_min_N of ``tension_distribution.compensated_lengths``, default
        min_norm, 100 N; poses without a feasible distribution are not solved, never ok).
    engine : {"compiled", "numpy", None}
        Engine of the full solves (``solve.solve``; None is compiled).
    threads : int, optional
    """

    def __init__(
        self, robot, p, rotvec=None, case="uncompensated", compensation=None, engine=None, threads=None
    ):
        self.robot = robot
        self.case = case
        self.engine = engine
        self.threads = threads
        self.p, self.R = pose_arrays(p, rotvec)
        self.rotvec = (
            np.zeros((len(self.p), 3)) if rotvec is None else np.broadcast_to(rotvec, (len(self.p), 3))
        )
        if case == "uncompensated":
            self.L0 = L_TS(robot, self.p, R=self.R)
            self.feasible = np.ones(len(self.p), dtype=bool)
        elif case == "compensated":
            c = compensation or {}
            comp = compensated_lengths(
                robot, self.p, self.rotvec, t_min=c.get("t_min_N", 100.0), method=c.get("method", "min_norm")
            )
            self.L0, self.feasible = comp["L0"], np.asarray(comp["feasible"], dtype=bool)
        else:
            raise ValueError(f"unknown case {case!r}; allowed: {', '.join(CASES)}")

    def _solve(self, robot):
        f = self.feasible
        return solve(
            robot,
            self.p[f],
            self.rotvec[f],
            redundancy="physical",
            engine=self.engine,
            threads=self.threads,
            L0=self.L0[f],
        )

    def solve(self, theta):
        """Full solves: ‖δp‖ (n, N) [m], δφ (n, N) [rad], ok (n, N) for θ (n, 10 m + 4)."""
        th = np.atleast_2d(theta)
        n, N = len(th), len(self.p)
        dp, dphi = np.full((n, N), np.nan), np.full((n, N), np.nan)
        ok = np.zeros((n, N), dtype=bool)
        f = self.feasible
        robots = [robot_with_parameters6(self.robot, t) for t in th]
        results = solve_batch(
            robots, self.p[f], self.rotvec[f], engine=self.engine, threads=self.threads, L0=self.L0[f]
        )  # every sample in one parallel pass (the same results as one solve per sample)
        for i, res in enumerate(results):
            ok[i, f] = res["status"] == "ok"
            dp[i, f], dphi[i, f] = res["dp"], res["dphi"]
        return dp, dphi, ok

    def linearise(self):
        """Nominal pose (P_s (N, 3) [m], R_s (N, 3, 3)) and S = dx*/dθ (N, 6, 10 m + 4), x = (p, φ)
        (``sensitivity.sensitivities_at``; NaN rows where the pose is infeasible or not ok)."""
        N, f = len(self.p), self.feasible
        res = self._solve(self.robot)
        # the numpy reference (central differences of the balance), through the engine switch: the
        # tracked CoGiRo uncertainty tables were computed with it; the compiled twin's analytic
        # dF6/dθ agrees to 1.4e-6 of a column (benchmarks/README.md) but not to the digits written
        sens = sensitivities_at(self.robot, res, parameter_names6(self.robot.m), engine="numpy")
        P_s, R_s = np.full((N, 3), np.nan), np.full((N, 3, 3), np.nan)
        S = np.full((N, 6, sens["S"].shape[2]), np.nan)
        smooth, status = np.zeros(N, dtype=bool), np.full(N, "infeasible", dtype=object)
        P_s[f], R_s[f], S[f], smooth[f], status[f] = (
            res["P_s"],
            res["R_s"],
            sens["S"],
            sens["smooth"],
            res["status"],
        )
        return {
            "P_s": P_s,
            "R_s": R_s,
            "S": S,
            "smooth": smooth,
            "theta0": parameter_values6(self.robot),
            "status": status,
        }

    def linearisations(self, columns):
        """The first-order propagation of ‖δp‖ and of δφ in point-mass parameter columns.

        Position: δp(θ) = δp_0 + S_p (τ(θ) - τ(θ_0)); orientation: the rotation vector of R* R_dᵀ,
        φ(θ) = φ_0 + S_φ (τ(θ) - τ(θ_0)) (first order in the base-frame rotation increment, for a
        small φ_0), δφ = ‖φ‖; τ as ``uncertainty.Linearisation`` (1/E for the moduli).

        Parameters
        ----------
        columns : array_like (k,) of int
            Columns of ``parameter_names(m)`` and, after it, b and c (the study's drivers,
            ``uncertainty.driver_columns``).

        Returns
        -------
        position, orientation : Linearisation
            Over θ (n, 7 m + 1) or, with b and c, (n, 10 m + 4) [Pa, m, kg]: ``dp`` gives ‖δp‖
            [m], resp. δφ [rad].
        """
        m = self.robot.m
        cols = np.asarray(columns, dtype=np.intp)
        lin = self.linearise()
        ok = (lin["status"] == "ok")[:, None]
        S = lin["S"][..., spatial_columns(m, cols)]
        R_d = self.R
        with np.errstate(invalid="ignore"):
            phi0 = np.where(
                ok, rotvec_of(np.where(ok[..., None], lin["R_s"], np.eye(3)) @ np.swapaxes(R_d, 1, 2)), 0.0
            )
        th0 = nominal_theta(self.robot, rigid=True)  # takes θ with or without b and c
        dp0 = np.where(ok, lin["P_s"] - self.p, 0.0)
        pos = Linearisation(dp0[:, None], S[:, None, :3], ok, lin["smooth"], th0, m, cols)
        rot = Linearisation(phi0[:, None], S[:, None, 3:], ok, lin["smooth"], th0, m, cols)
        return pos, rot
