"""The MAP problem of one data set: residuals and their exact Jacobians.

The robot is commanded rest lengths L0 and settles at the equilibrium P*(θ, L0); a tracker measures
the pose y. The residual (``map_residual``, ``map_residual6`` for a 6-DoF platform) is the measured
minus predicted pose over the tracker noise, then (t_meas - t(θ, L0)) / σ_t for measured tensions,
then the prior rows (θ - θ_0) / σ_prior. Its Jacobian is exact, from the implicit-function
sensitivities dP*/dθ (``cdpr.models.sensitivity``; ``cdpr.models.sensitivity`` on the 6-DoF
equilibrium, for a rigid platform and for a point mass under a tilted pulley axis), with the encoder offsets' column
dP*/do = J^-1 dF/dL0 (``offset_sensitivities``) and the tensions' total derivatives
(``tension_sensitivities``, ``tension_sensitivities6``); no finite differences inside the fit.
``map_problem`` builds the problem of the robot's kind (``Problem`` or ``Problem6``).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 3-5, 10-14).
Tarantola, A. (2005). Inverse Problem Theory and Methods for Model Parameter Estimation, SIAM,
section 3.2 (least squares with a Gaussian prior).
Sola, J., Deray, J., Atchuthan, D. (2018). A micro Lie theory for state estimation in robotics,
arXiv:1812.01537 (the orientation error and its Jacobian).
"""

from __future__ import annotations

import numpy as np

from cdpr.analyses.calibration.model import (
    DRUM_RANGE,
    default_start,
    drum_or_standard,
    engine6,
    smooth6,
)
from cdpr.models.drive import has_winches, realised_rest_lengths
from cdpr.models.platform import rotation_matrix, rotvec_of, skew
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.sensitivity import (
    cable_partials,
    implicit_solve,
    physical_jacobian_terms,
    rest_length_sensitivities,
    tension_partials,
)
from cdpr.parameters import (
    calibrated_robot,
    calibration_names,
    calibration_values,
    is_spatial,
    robot_size,
    robot_with_parameters,
)
from cdpr.solve import check_engine, sensitivities


def offset_sensitivities(robot, P, L0):
    """dP*/do_i of the encoder offsets: rest length L0_i = reading - o_i, so

    .. math:: \\frac{dP^*}{do_i} = -\\frac{dP^*}{dL0_i} = J^{-1} \\frac{\\partial F}{\\partial L0_i},
              \\quad \\frac{\\partial F}{\\partial L0_i} = -a_i \\frac{E_i S_i}{L0_i} \\frac{L_{TE,i}}{L0_i} u_i

    (t_i = E_i S_i (L_TE,i - L0_i) / L0_i, a_i = 1 on a taut cable).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibria.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.

    Returns
    -------
    S : ndarray, shape (n, 3, m) [m/m]

    References
    ----------
    Paty et al. 2021, eq. (10)-(13); implicit-function theorem.
    """

    a = robot.arrays
    J, _, hooke = physical_jacobian_terms(robot, P, L0)
    g = total_length_and_direction(P, a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    k = a.ES / L0
    dF = -((hooke >= 0) * k * g.L_TE / L0)[:, None, :] * np.swapaxes(g.u, 1, 2)  # (n, 3, m)
    S, _ = implicit_solve(J, dF)
    return -S


def map_residual(y, P, sigma, z):
    """The MAP residual: measured minus predicted pose over the tracker noise, then the prior rows.

    .. math:: r = \\left[\\frac{y_k - P^*_k(\\theta)}{\\sigma_k}\\right]_{k} \\oplus
              \\frac{\\theta - \\theta_0}{\\sigma_{prior}}

    so that ½|r|² is the negative log posterior under Gaussian noise and prior.

    Parameters
    ----------
    y : ndarray, shape (n, 3) [m]
        Measured positions.
    P : ndarray, shape (n, 3) [m]
        Predicted equilibria.
    sigma : ndarray, shape (n,) [m]
        Tracker noise sd.
    z : ndarray, shape (k,) [-]
        (θ - θ_0) / σ_prior of the estimated parameters.

    Returns
    -------
    r : ndarray, shape (3 n + k,) [-]

    References
    ----------
    Tarantola 2005, eq. (3.46).
    """
    return np.concatenate([((y - P) / sigma[:, None]).ravel(), np.asarray(z, dtype=float)])


class Problem:
    """The MAP problem of one data set: residual and exact Jacobian in prior-scaled variables.

    z = (θ_free - θ_nominal) / σ_prior; residual r(z) = [(y - P*(θ, L0)) / σ ; (t_meas - t(θ, L0)) / σ_t ;
    z] (``map_residual``), pose rows for the samples with a measured pose, tension rows for those with
    measured tensions.

    Parameters
    ----------
    robot : Robot
        Nominal robot (the prior mean), already in the chosen model (``model_robot``).
    data : Data
        Samples with a measured pose or measured tensions.
    index : ndarray of int
        Estimated parameters, into ``calibration_names(robot)``.
    sd : ndarray, shape (len(index),)
        Prior sd [Pa, m, kg].
    engine : {"compiled", "numpy"} or None
        Engine of the solves and sensitivities (None: ``solve.check_engine``'s default, compiled).
    solver : dict
        tol, maxiter, max_step of the physical solve.
    """

    def __init__(self, robot, data, index, sd, engine=None, solver=None):
        self.robot, self.data, self.index, self.sd = robot, data, np.asarray(index), np.asarray(sd, float)
        self.engine = engine
        self.solver = dict(solver or {})
        self.m = robot.m
        self.theta0 = calibration_values(robot)
        #: a robot file with ``winch:``: the commanded lengths are mapped through the drums
        self.winch = has_winches(robot)
        self._cache = None
        pose, tens = np.flatnonzero(data.has_pose), np.flatnonzero(data.has_tension)
        #: the sample of every measurement row
        self.row_sample = np.concatenate([np.repeat(pose, 3), np.repeat(tens, self.m)]).astype(np.intp)
        self._pose, self._tens = pose, tens

    def theta(self, z):
        th = self.theta0.copy()
        th[self.index] += self.sd * np.asarray(z, dtype=float)
        return th

    def evaluate(self, z):
        """Solve at z: P* (n, 3), status (n,), smooth (n,), dP*/dθ_free (n, 3, k); with tension data
        also the tensions t (n, m) [N] and dt/dθ_free (n, m, k)."""
        key = np.asarray(z, float).tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        data = self.data
        th = self.theta(z)
        m = self.m
        rob = robot_with_parameters(self.robot, th[: 7 * m + 1])
        L0 = data.L - th[7 * m + 1 :]
        if self.winch:  # the commanded lengths go through the drums (drive.realised_rest_lengths)
            L0, w_L, w_d = realised_rest_lengths(rob, L0)
        start = np.where(data.has_pose[:, None], data.pose, default_start(rob))
        drum = np.isfinite(L0).all(axis=1)
        res = sensitivities(
            rob,
            start,
            redundancy="physical",
            L=np.where(drum[:, None], L0, data.L),
            engine=self.engine,
            **self.solver,
        )
        if not drum.all():  # a command the drum cannot pay out: no equilibrium, flagged by the fit
            res["status"] = np.where(drum, res["status"], DRUM_RANGE)
            res["P_s"][~drum] = np.nan
        S = np.zeros((len(start), 3, len(th)))
        S[:, :, : 7 * m + 1] = res["S"]
        ok = res["status"] == "ok"
        need_off = (self.index >= 7 * m + 1).any() or len(self._tens) or self.winch
        if need_off and ok.any():
            S[ok, :, 7 * m + 1 :] = offset_sensitivities(rob, res["P_s"][ok], L0[ok])
        if self.winch:  # chain rule: dP/do_i = -dP/dL0_i dL0_i/dL_cmd,i, dP/dd_i += dP/dL0_i dL0_i/dd_i
            SL0 = -S[:, :, 7 * m + 1 :].copy()
            S[:, :, 7 * m + 1 :] = -SL0 * w_L[:, None, :]
            S[:, :, 3 * m : 4 * m] += SL0 * w_d[:, None, :]
        out = {"P": res["P_s"], "status": res["status"], "smooth": res["smooth"], "S": S[:, :, self.index]}
        if len(self._tens):
            t = np.full((len(start), m), np.nan)
            St = np.full((len(start), m, len(th)), np.nan)
            if ok.any():
                w = (w_L[ok], w_d[ok]) if self.winch else (None, None)
                t[ok], St[ok] = tension_sensitivities(rob, res["P_s"][ok], L0[ok], S[ok], *w)
            out["t"], out["St"] = t, St[:, :, self.index]
        self._cache = (key, out)
        return out

    def residual(self, z):
        """r(z) = [pose rows ; tension rows ; z] (``map_residual``)."""
        ev = self.evaluate(z)
        d, p, t = self.data, self._pose, self._tens
        r = map_residual(d.pose[p], ev["P"][p], d.sigma[p], z)
        if len(t):
            rt = ((d.tension[t] - ev["t"][t]) / d.sigma_t[t, None]).ravel()
            r = np.concatenate([r[: 3 * len(p)], rt, r[3 * len(p) :]])
        return r

    def jacobian(self, z):
        """dr/dz: [-dP*/dθ σ_prior / σ ; -dt/dθ σ_prior / σ_t ; I]."""
        ev = self.evaluate(z)
        d, p, t = self.data, self._pose, self._tens
        k = len(self.index)
        blocks = [(-(np.nan_to_num(ev["S"][p]) * self.sd) / d.sigma[p, None, None]).reshape(-1, k)]
        if len(t):
            blocks.append((-(np.nan_to_num(ev["St"][t]) * self.sd) / d.sigma_t[t, None, None]).reshape(-1, k))
        return np.vstack([*blocks, np.eye(k)])


def orientation_residual(R_meas, R_pred):
    r"""The orientation error as a rotation vector: e = log(R_meas R_predᵀ), the base-frame rotation
    that takes the predicted orientation onto the measured one (its norm is the error angle).

    .. math:: e = \log\left(R_{meas} R_{pred}^T\right)^\vee

    Parameters
    ----------
    R_meas, R_pred : ndarray, shape (n, 3, 3) [-]
        Measured and predicted orientations (active, base frame).

    Returns
    -------
    e : ndarray, shape (n, 3) [rad]

    References
    ----------
    Sola, J., Deray, J., Atchuthan, D. (2018). A micro Lie theory for state estimation in robotics,
    arXiv:1812.01537, eq. (10), (26) (the logarithm of SO(3) and the left minus).
    """
    return rotvec_of(np.einsum("nab,ncb->nac", R_meas, R_pred))


def log_right_jacobian_inverse(e):
    r"""The inverse right Jacobian of SO(3): log(exp([e]) exp([w])) = e + J_r⁻¹(e) w + O(w²).

    .. math:: J_r^{-1}(e) = I + \tfrac12 [e]_\times +
              \left(\frac{1}{\theta^2} - \frac{1 + \cos\theta}{2\theta\sin\theta}\right) [e]_\times^2,
              \quad \theta = |e|

    With the prediction turned by a base-frame dφ (R_pred ← exp([dφ]) R_pred) the residual
    e = log(R_meas R_predᵀ) moves by de = -J_r⁻¹(e) dφ.

    Parameters
    ----------
    e : ndarray, shape (n, 3) [rad]

    Returns
    -------
    Jinv : ndarray, shape (n, 3, 3) [-]

    References
    ----------
    Sola et al. 2018, eq. (144).
    """
    th = np.linalg.norm(e, axis=1)
    small = th < 1e-4
    ts = np.where(small, 1.0, th)
    c = np.where(
        small, 1.0 / 12.0 + th**2 / 720.0, 1.0 / ts**2 - (1.0 + np.cos(ts)) / (2.0 * ts * np.sin(ts))
    )
    K = skew(e)
    return np.eye(3) + 0.5 * K + c[:, None, None] * (K @ K)


def map_residual6(y, P, R_meas, R_pred, sigma, sigma_rad, z):
    r"""The MAP residual of a 6-DoF platform: per sample the position rows then the orientation rows,
    then the prior rows.

    .. math:: r = \left[\frac{y_k - p^*_k(\theta)}{\sigma_k},\;
              \frac{\log(R_{meas,k} R^*_k(\theta)^T)^\vee}{\sigma_{rad,k}}\right]_{k} \oplus
              \frac{\theta - \theta_0}{\sigma_{prior}}

    Parameters
    ----------
    y, P : ndarray, shape (n, 3) [m]
        Measured and predicted positions.
    R_meas, R_pred : ndarray, shape (n, 3, 3) [-]
        Measured and predicted orientations.
    sigma : ndarray, shape (n,) [m]
    sigma_rad : ndarray, shape (n,) [rad]
    z : ndarray, shape (k,) [-]
        (θ - θ_0) / σ_prior.

    Returns
    -------
    r : ndarray, shape (6 n + k,) [-]

    References
    ----------
    Tarantola 2005, eq. (3.46); Sola et al. 2018 (the orientation error).
    """
    rp = (y - P) / sigma[:, None]
    rr = orientation_residual(R_meas, R_pred) / sigma_rad[:, None]
    return np.concatenate([np.concatenate([rp, rr], axis=1).ravel(), np.asarray(z, dtype=float)])


class Problem6:
    """``Problem`` on the 6-DoF equilibrium (``cdpr.models.equilibrium``): a rigid 6-DoF platform,
    or a point mass whose pulleys are not all at +z axes (a tilted axis or a ``zero``), which the
    point-mass physical solver does not model.

    A rigid platform has six rows per sample with a measured pose (position / σ_m, orientation
    error / σ_rad, ``map_residual6``); a point mass three (position / σ_m, ``map_residual``: its
    orientation plays no part, and its calibration vector is the point mass's,
    ``calibration_names(robot)``). Then m tension rows (t_meas - t(θ, L0)) / σ_t per sample with
    measured tensions (``tension_sensitivities6``), then the prior rows; the exact Jacobian from
    ``sensitivity.pose_sensitivities`` (implicit function) and, for the encoder offsets,
    ``sensitivity.rest_length_sensitivities`` (dx*/do_i = -dx*/dL0_i). A sample without a
    measured pose is solved from ``default_start`` at the identity orientation. On a robot file with
    ``winch:`` the commanded lengths go through the drums (``drive.realised_rest_lengths``) with
    the chain rule of ``Problem.evaluate`` on the offsets and dead lengths. The solve and the
    sensitivities by ``engine`` (``solve.sensitivities``), the numpy reference by default:
    the compiled twin (analytic dF6/dθ) changes the tracked CoGiRo tables (the misfit models' fits
    move; the exact model's in the 4th digit), so the study stays on numpy. A sample is smooth
    where ``smooth6`` says so (a rigid platform) or, for a point mass (whose moment rows vanish, so
    that the 6 × 6 Jacobian is singular), where ``sensitivity.sensitivities_at`` says so (the
    point-mass physical mode's rule on the 3 × 3 translation block).

    Parameters
    ----------
    robot : Robot
        Nominal robot (the prior mean), in the chosen model.
    data : Data
        Samples with a measured pose (position, and orientation on a rigid platform) or measured
        tensions.
    index : ndarray of int
        Into ``calibration_names(robot)``.
    sd : ndarray, shape (len(index),)
        Prior sd [Pa, m, kg].
    engine : {"numpy", "compiled"}
        Engine of the solve and the sensitivities.
    solver : dict
        tol, maxiter, max_step of ``solve_spatial``.
    """

    def __init__(self, robot, data, index, sd, engine="numpy", solver=None):
        self.robot, self.data, self.index, self.sd = robot, data, np.asarray(index), np.asarray(sd, float)
        self.engine = engine
        self.solver = dict(solver or {})
        self.m = robot.m
        #: a rigid platform (False: a point mass under pulleys at other axes than +z)
        self.spatial = is_spatial(robot)
        self.nr = robot_size(robot)
        self.theta0 = calibration_values(robot)
        #: a robot file with ``winch:``: the commanded lengths are mapped through the drums
        self.winch = has_winches(robot)
        names = calibration_names(robot)
        self._cols6 = self.index[self.index < self.nr]
        self._names6 = [names[k] for k in self._cols6]
        self._cache = None
        pose = np.flatnonzero(self._measured(data))
        tens = np.flatnonzero(data.has_tension)
        #: pose rows per sample: position and orientation, or the position of a point mass
        self.dof = 6 if self.spatial else 3
        #: the sample of every measurement row
        self.row_sample = np.concatenate([np.repeat(pose, self.dof), np.repeat(tens, self.m)]).astype(np.intp)
        self._pose, self._tens = pose, tens
        self._R = rotation_matrix(np.nan_to_num(data.rotvec))

    def _measured(self, data):
        """Where a sample's pose is measured: position and orientation (rigid platform), position
        (point mass)."""
        return data.has_pose & data.has_orientation if self.spatial else data.has_pose

    def theta(self, z):
        th = self.theta0.copy()
        th[self.index] += self.sd * np.asarray(z, dtype=float)
        return th

    def evaluate(self, z):
        """Solve at z: P* (n, 3), R* (n, 3, 3), status, smooth (n,), dx*/dθ_free (n, 6, k) (rows
        dp, dφ; dφ = 0 on a point mass); with tension data also the tensions t (n, m) [N] and
        dt/dθ_free (n, m, k)."""
        key = np.asarray(z, float).tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        data, nr, m = self.data, self.nr, self.m
        th = self.theta(z)
        rob = calibrated_robot(self.robot, th[:nr])
        L0 = data.L - th[nr:]
        w_L = w_d = None
        if self.winch:  # the commanded lengths go through the drums (drive.realised_rest_lengths)
            L0, w_L, w_d = realised_rest_lengths(rob, L0)
        hp = self._measured(data)
        start = np.where(hp[:, None], data.pose, default_start(rob))
        rv = np.where(hp[:, None], data.rotvec, 0.0) if self.spatial else np.zeros_like(start)
        drum = np.isfinite(L0).all(axis=1)
        L0 = drum_or_standard(rob, L0, drum, start, rv)
        res = sensitivities(
            rob, start, rv, redundancy="physical", L=L0, engine=self.engine, names=self._names6, **self.solver
        )
        SL, hooke, cond = rest_length_sensitivities(rob, res["P_s"], res["R_s"], L0)
        # a point mass's 6 x 6 Jacobian is singular (no moment rows): sensitivities_at judges its
        # 3 x 3 translation block as the point-mass physical mode does
        smooth = smooth6(hooke, cond) if self.spatial else res["smooth"]
        if not drum.all():  # a command the drum cannot pay out: no equilibrium, flagged by the fit
            res["status"] = np.where(drum, res["status"], DRUM_RANGE)
            res["P_s"][~drum] = np.nan
        S = np.zeros((len(start), 6, len(th)))
        S[:, :, self._cols6] = res["S"]
        S[:, :, nr:] = -SL if w_L is None else -SL * w_L[:, None, :]
        if self.winch:  # chain rule: dx/dd_i += dx/dL0_i dL0_i/dd_i (dx/do_i above: -dx/dL0_i dL0_i/dL_cmd,i)
            S[:, :, 3 * m : 4 * m] += SL * w_d[:, None, :]
        out = {
            "P": res["P_s"],
            "R": res["R_s"],
            "status": res["status"],
            "smooth": smooth,
            "S": S[:, :, self.index],
        }
        if len(self._tens):
            ok = res["status"] == "ok"
            t = np.full((len(start), m), np.nan)
            St = np.full((len(start), m, len(th)), np.nan)
            if ok.any():
                w = (w_L[ok], w_d[ok]) if self.winch else (None, None)
                t[ok], St[ok] = tension_sensitivities6(
                    rob, res["P_s"][ok], res["R_s"][ok], L0[ok], S[ok], self._cols6, *w
                )
            out["t"], out["St"] = t, St[:, :, self.index]
        self._cache = (key, out)
        return out

    def residual(self, z):
        """r(z) = [position and orientation rows ; tension rows ; z] (``map_residual6``; the
        position rows of ``map_residual`` on a point mass)."""
        ev = self.evaluate(z)
        d, p, t = self.data, self._pose, self._tens
        if self.spatial:
            r = map_residual6(d.pose[p], ev["P"][p], self._R[p], ev["R"][p], d.sigma[p], d.sigma_rad[p], z)
        else:
            r = map_residual(d.pose[p], ev["P"][p], d.sigma[p], z)
        if len(t):
            n = self.dof * len(p)
            rt = ((d.tension[t] - ev["t"][t]) / d.sigma_t[t, None]).ravel()
            r = np.concatenate([r[:n], rt, r[n:]])
        return r

    def jacobian(self, z):
        """dr/dz: per sample [-dp*/dθ σ_prior / σ_m ; -J_r⁻¹(e) dφ*/dθ σ_prior / σ_rad] (the
        position rows alone on a point mass), then -dt/dθ σ_prior / σ_t, then I."""
        ev = self.evaluate(z)
        d, p, t = self.data, self._pose, self._tens
        k = len(self.index)
        S = np.nan_to_num(ev["S"][p]) * self.sd
        Jp = -S[:, :3] / d.sigma[p, None, None]
        if self.spatial:
            e = orientation_residual(self._R[p], ev["R"][p])
            Jr = -np.einsum("nab,nbk->nak", log_right_jacobian_inverse(np.nan_to_num(e)), S[:, 3:])
            Jr /= d.sigma_rad[p, None, None]
            Jp = np.concatenate([Jp, Jr], axis=1)
        blocks = [Jp.reshape(-1, k)]
        if len(t):
            blocks.append((-(np.nan_to_num(ev["St"][t]) * self.sd) / d.sigma_t[t, None, None]).reshape(-1, k))
        return np.vstack([*blocks, np.eye(k)])

    def angles(self, ev):
        """The orientation error angle |log(R_meas R*ᵀ)| (n,) [rad] of every sample (NaN without
        one; a rigid platform's)."""
        out = np.full(len(self.data.sample), np.nan)
        p = self._pose
        out[p] = np.linalg.norm(orientation_residual(self._R[p], ev["R"][p]), axis=1)
        return out


def tension_sensitivities(robot, P, L0, S, w_L=None, w_d=None):
    r"""Cable tensions at the equilibrium and their total derivatives by the calibration parameters.

    .. math:: t_i = k_i\,a_i\,(L_{TE,i}(P^*) - L0_i),\quad k_i = \frac{E_i S_i}{L0_i},\quad
              \frac{dt_i}{d\theta} = a_i\left[k_i\left(\frac{\partial L_{TE,i}}{\partial P}
              \frac{dP^*}{d\theta} + \frac{\partial L_{TE,i}}{\partial \theta}\right)
              + \frac{\partial k_i}{\partial \theta}(L_{TE,i} - L0_i)\right]

    with ∂k_i/∂E_i = k_i / E_i, and for the encoder offset o_i (L0_i = reading - o_i)
    ∂(L_TE,i - L0_i)/∂o_i = 1, ∂k_i/∂o_i = k_i / L0_i. Through a winch (L0_i = W(reading - o_i, d_i),
    ``drive.realised_rest_lengths``) the offset terms are multiplied by ∂W/∂L_cmd and the dead length
    gets ∂t_i/∂L0_i ∂W/∂d_i, ∂t_i/∂L0_i = -(k_i + k_i (L_TE,i - L0_i) / L0_i).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibria.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.
    S : ndarray, shape (n, 3, 8 m + 1)
        dP*/dθ of every calibration parameter (``calibration_names``).
    w_L, w_d : ndarray, shape (n, m) [m/m], optional
        dL0/dL_cmd and dL0/dd of the winch map (None: no winch).

    Returns
    -------
    t : ndarray, shape (n, m) [N]
        0 on slack cables.
    dt : ndarray, shape (n, m, 8 m + 1) [N per unit of θ]

    References
    ----------
    Paty et al. 2021, eq. (10), (13).
    """

    a = robot.arrays
    m = robot.m
    cp = cable_partials(P, a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    k = a.ES / L0
    e = cp.L_TE - L0
    taut = e >= 0
    t = np.where(taut, k * e, 0.0)
    dt = k[..., None] * np.einsum("nia,nak->nik", cp.dL_dP, S)
    for c in range(m):
        geo = [m + c, 2 * m + c, 3 * m + c, 4 * m + 3 * c, 4 * m + 3 * c + 1, 4 * m + 3 * c + 2]
        dt[:, c, geo] += k[:, c, None] * cp.dL[:, c]
        dt[:, c, c] += k[:, c] * e[:, c] / a.E[c]
        dt_dL0 = -(k[:, c] + k[:, c] * e[:, c] / L0[:, c])
        if w_L is None:
            dt[:, c, 7 * m + 1 + c] -= dt_dL0
        else:
            dt[:, c, 7 * m + 1 + c] -= dt_dL0 * w_L[:, c]
            dt[:, c, 3 * m + c] += dt_dL0 * w_d[:, c]
    return t, dt * taut[..., None]


def tension_sensitivities6(robot, P, R, L0, S, cols6, w_L=None, w_d=None):
    r"""Cable tensions at a 6-DoF equilibrium (a rigid platform, or a point mass under pulleys at
    any axis) and their total derivatives by the calibration parameters.

    .. math:: t_i = a_i k_i (L_{TE,i}(x^*) - L0_i),\quad k_i = \frac{E_i S_i}{L0_i},\quad
              \frac{dt_i}{d\theta} = \frac{\partial t_i}{\partial x}\frac{dx^*}{d\theta}
              + a_i\left[k_i \frac{\partial L_{TE,i}}{\partial \theta}
              + \frac{\partial k_i}{\partial \theta}(L_{TE,i} - L0_i)\right]
              + \frac{\partial t_i}{\partial L0_i}\frac{dL0_i}{d\theta}

    x* = (p*, R*) with the attachment B_i = p + R b_i (``sensitivity.tension_partials``: ∂t_i/∂x,
    ∂t_i/∂L0_i = -a_i k_i L_TE,i / L0_i and the fixed-pose partials); L0_i = reading - o_i, so
    dL0_i/do_i = -1, or through a winch (L0_i = W(reading - o_i, d_i), ``drive.realised_rest_lengths``)
    dL0_i/do_i = -∂W/∂L_cmd and dL0_i/dd_i = ∂W/∂d_i. The calibration vector is the robot's
    (``calibration_names(robot)``: 11 m + 4 entries on a rigid platform, 8 m + 1 on a
    point mass, whose b_i = 0 make ∂t_i/∂φ = 0).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibrium positions.
    R : ndarray, shape (n, 3, 3) [-]
        Equilibrium orientations.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.
    S : ndarray, shape (n, 6, K)
        dx*/dθ of the calibration parameters (``calibration_names(robot)``, K of
        them), the chain rule of the winch included; only the columns ``cols6`` and the offsets
        need to be filled.
    cols6 : ndarray of int
        Robot parameters (before the offsets) whose fixed-pose partials count.
    w_L, w_d : ndarray, shape (n, m) [m/m], optional
        dL0/dL_cmd and dL0/dd of the winch map (None: no winch).

    Returns
    -------
    t : ndarray, shape (n, m) [N]
        0 on slack cables.
    dt : ndarray, shape (n, m, K) [N per unit of θ]

    References
    ----------
    Paty et al. 2021, eq. (5), (10), (13); implicit-function theorem.
    """
    m = robot.m
    nr = robot_size(robot)
    names = calibration_names(robot)
    tp = tension_partials(robot, P, R, L0, [names[k] for k in cols6])
    dt = np.einsum("nia,nak->nik", tp["dt_dx"], S)
    dt[:, :, cols6] += tp["dt_dtheta"]
    cab = np.arange(m)
    dt[:, cab, nr + cab] -= tp["dt_dL0"] if w_L is None else tp["dt_dL0"] * w_L
    if w_d is not None:
        dt[:, cab, 3 * m + cab] += tp["dt_dL0"] * w_d
    return tp["t"], dt


def map_problem(base, data, index, sd, engine=None, solver=None):
    """The MAP problem of the robot's kind: ``Problem`` for a suspended point mass (pulley axes +z,
    the point-mass physical solver), ``Problem6`` on the 6-DoF equilibrium for every other robot (a
    rigid platform, or a point mass under a tilted pulley axis). A named ``engine`` is checked
    (``solve.check_engine``) and used by either; None is each problem's default (``Problem``:
    ``check_engine``'s, compiled; ``Problem6``: the numpy reference, ``engine6``).

    Parameters
    ----------
    base : Robot
        Nominal robot (the prior mean), in the chosen model (``model_robot``).
    data : Data
    index : ndarray of int
        Estimated parameters, into ``calibration_names(base)``.
    sd : ndarray, shape (len(index),)
        Prior sd [Pa, m, kg].
    engine : {"compiled", "numpy"} or None
    solver : dict, optional
        tol, maxiter, max_step of the physical solve.

    Returns
    -------
    Problem or Problem6
    """
    if engine is not None:
        engine = check_engine(engine, "newton")
    if not base.suspended_point_mass:
        return Problem6(base, data, index, sd, engine=engine6(engine), solver=solver)
    return Problem(base, data, index, sd, engine=engine, solver=solver)
