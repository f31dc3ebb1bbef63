"""The MAP problem of one data set: residuals and their exact Jacobians.

The robot is commanded rest lengths L0 and settles at the equilibrium P*(θ, L0); a tracker measures
the pose y. The residual (``map_residual``: the position, and the orientation of a rigid platform) is the
measured minus predicted pose over the tracker noise, then (t_meas - t(θ, L0)) / σ_t for measured tensions,
then the prior rows (θ - θ_0) / σ_prior. Its Jacobian is exact, from the implicit-function
sensitivities dP*/dθ (``cdpr.models.sensitivity``; ``cdpr.models.sensitivity`` on the 6-DoF
equilibrium, for a rigid platform and for a point mass under a tilted pulley axis), with the encoder offsets' column
dP*/do = J^-1 dF/dL0 (``offset_sensitivities``) and the tensions' total derivatives
(``tension_sensitivities``); no finite differences inside the fit. ``Problem`` is the problem of
every robot (the point-mass physical solver for a suspended point mass, the pose model for every
other robot).

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
    differentiable,
    drum_or_standard,
    equilibrium_engine,
)
from cdpr.errors import CdprError
from cdpr.models import heavy_sensitivity
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
)
from cdpr.solve import sensitivities


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


def map_residual(y, P, sigma, z, R_meas=None, R_pred=None, sigma_rad=None):
    r"""The MAP residual: per sample the measured minus predicted position over the tracker noise
    (then, given orientations, the orientation error over its noise), then the prior rows.

    .. math:: r = \left[\frac{y_k - p^*_k(\theta)}{\sigma_k},\;
              \frac{\log(R_{meas,k} R^*_k(\theta)^T)^\vee}{\sigma_{rad,k}}\right]_{k} \oplus
              \frac{\theta - \theta_0}{\sigma_{prior}}

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
    R_meas, R_pred : ndarray, shape (n, 3, 3) [-], optional
        Measured and predicted orientations (a rigid platform; None: positions only).
    sigma_rad : ndarray, shape (n,) [rad], optional
        Orientation noise sd (with R_meas).

    Returns
    -------
    r : ndarray, shape (3 n + k,), or (6 n + k,) with orientations [-]

    References
    ----------
    Tarantola 2005, eq. (3.46); Sola et al. 2018 (the orientation error).
    """
    rows = (y - P) / sigma[:, None]
    if R_meas is not None:
        rows = np.concatenate([rows, orientation_residual(R_meas, R_pred) / sigma_rad[:, None]], axis=1)
    return np.concatenate([rows.ravel(), np.asarray(z, dtype=float)])


class Problem:
    """The MAP problem of one data set: residual and exact Jacobian in prior-scaled variables.

    z = (θ_free - θ_nominal) / σ_prior; residual r(z) = [pose rows ; (t_meas - t(θ, L0)) / σ_t ; z]
    (``map_residual``): pose rows for the samples with a measured pose (position / σ_m, and on a
    rigid platform the orientation error / σ_rad), m tension rows for those with measured tensions
    (``tension_sensitivities``), then the prior rows. The calibration vector is the robot's
    (``calibration_names(robot)``). A sample without a measured pose is solved from
    ``default_start`` (at the identity orientation). On a robot file with ``winch:`` the commanded
    lengths go through the drums (``drive.realised_rest_lengths``) with the chain rule on the
    offsets (dx/do_i = -dx/dL0_i dL0_i/dL_cmd,i) and dead lengths (dx/dd_i += dx/dL0_i dL0_i/dd_i).

    The equilibrium: a suspended point mass by the point-mass physical solver
    (``solve.sensitivities``, encoder offsets by ``offset_sensitivities``); every other robot (a
    rigid platform, or a point mass whose pulleys are not all at +z axes) by the pose model, the
    exact Jacobian from ``sensitivity.pose_sensitivities`` (implicit function) and
    ``sensitivity.rest_length_sensitivities`` for the offsets (heavy cables: always the pose model,
    with ``heavy_sensitivity``'s twins; measured tensions refused); a point mass's moment rows vanish
    (its 6 × 6 Jacobian is singular), so its samples are smooth where ``sensitivities_at`` says
    so (the 3 × 3 translation block), a rigid platform's where ``differentiable`` says so. The
    engine is ``equilibrium_engine``'s (the solvers' default, compiled, unless one is named).

    Parameters
    ----------
    robot : Robot
        Nominal robot (the prior mean), already in the chosen model (``model_robot``).
    data : Data
        Samples with a measured pose (position, and orientation on a rigid platform) or measured
        tensions.
    index : ndarray of int
        Estimated parameters, into ``calibration_names(robot)``.
    sd : ndarray, shape (len(index),)
        Prior sd [Pa, m, kg].
    engine : {"compiled", "numpy"} or None
        Engine of the solves and sensitivities (``equilibrium_engine``).
    solver : dict
        tol, maxiter, max_step of the physical solve.
    pose_model : bool, optional
        True: the pose model on a suspended point mass too (b = 0 is a platform; the tests compare
        the two); default the robot's.
    """

    def __init__(self, robot, data, index, sd, engine=None, solver=None, pose_model=None):
        self.robot, self.data, self.index, self.sd = robot, data, np.asarray(index), np.asarray(sd, float)
        #: the pose model (False: the point-mass physical solver of a suspended point mass)
        self.pose_model = not robot.suspended_point_mass if pose_model is None else bool(pose_model)
        # heavy cables: the pose model (``heavy_sensitivity``), positions and orientations only
        if robot.heavy:
            self.pose_model = True
            if data.has_tension.any():
                raise CdprError(
                    f"{data.source}: measured tensions (t1_N..) on heavy cables (cable.linear_density_kg_m > 0) "
                    "are not modelled yet; calibrate from measured poses"
                )
        self.engine = equilibrium_engine(robot, engine)
        self.solver = dict(solver or {})
        self.m = robot.m
        #: a rigid platform (its orientation is measured and fitted)
        self.spatial = is_spatial(robot)
        self.nr = robot_size(robot)
        self.theta0 = calibration_values(robot)
        #: a robot file with ``winch:``: the commanded lengths are mapped through the drums
        self.winch = has_winches(robot)
        names = calibration_names(robot)
        self._cols = self.index[self.index < self.nr]
        self._names = [names[k] for k in self._cols]
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
        """Solve at z: P* (n, 3), status, smooth (n,), dx*/dθ_free (n, 3, k) (the point-mass solver)
        or (n, 6, k) with R* (n, 3, 3) (the pose model: rows dp, dφ; dφ = 0 on a point mass); with
        tension data also the tensions t (n, m) [N] and dt/dθ_free (n, m, k)."""
        key = np.asarray(z, float).tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        data, nr = self.data, self.nr
        th = self.theta(z)
        rob = calibrated_robot(self.robot, th[:nr])
        L0 = data.L - th[nr:]
        w_L = w_d = None
        if self.winch:  # the commanded lengths go through the drums (drive.realised_rest_lengths)
            L0, w_L, w_d = realised_rest_lengths(rob, L0)
        hp = self._measured(data)
        start = np.where(hp[:, None], data.pose, default_start(rob))
        drum = np.isfinite(L0).all(axis=1)
        solve = self._pose_solve if self.pose_model else self._point_mass_solve
        res, L0, S, smooth = solve(rob, th, start, L0, drum, w_L, w_d)
        out = {"P": res["P_s"], "status": res["status"], "smooth": smooth, "S": S[:, :, self.index]}
        if self.pose_model:
            out["R"] = res["R_s"]
        if len(self._tens):
            ok = res["status"] == "ok"
            t = np.full((len(start), self.m), np.nan)
            St = np.full((len(start), self.m, len(th)), np.nan)
            if ok.any():
                w = (w_L[ok], w_d[ok]) if self.winch else (None, None)
                pose = {"R": res["R_s"][ok], "cols": self._cols} if self.pose_model else {}
                t[ok], St[ok] = tension_sensitivities(rob, res["P_s"][ok], L0[ok], S[ok], *w, **pose)
            out["t"], out["St"] = t, St[:, :, self.index]
        self._cache = (key, out)
        return out

    def _point_mass_solve(self, rob, th, start, L0, drum, w_L, w_d):
        """The point-mass physical solve and dP*/dθ (n, 3, len(θ)) of ``evaluate``."""
        m, nr, data = self.m, self.nr, self.data
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
        S[:, :, :nr] = res["S"]
        ok = res["status"] == "ok"
        need_off = (self.index >= nr).any() or len(self._tens) or self.winch
        if need_off and ok.any():
            S[ok, :, nr:] = offset_sensitivities(rob, res["P_s"][ok], L0[ok])
        if self.winch:  # chain rule: dP/do_i = -dP/dL0_i dL0_i/dL_cmd,i, dP/dd_i += dP/dL0_i dL0_i/dd_i
            SL0 = -S[:, :, nr:].copy()
            S[:, :, nr:] = -SL0 * w_L[:, None, :]
            S[:, :, 3 * m : 4 * m] += SL0 * w_d[:, None, :]
        return res, L0, S, res["smooth"]

    def _pose_solve(self, rob, th, start, L0, drum, w_L, w_d):
        """The pose model's solve and dx*/dθ (n, 6, len(θ)) of ``evaluate``."""
        m, nr, data = self.m, self.nr, self.data
        rv = (
            np.where(self._measured(data)[:, None], data.rotvec, 0.0)
            if self.spatial
            else np.zeros_like(start)
        )
        L0 = drum_or_standard(rob, L0, drum, start, rv)
        res = sensitivities(
            rob, start, rv, redundancy="physical", L=L0, engine=self.engine, names=self._names, **self.solver
        )
        rls = heavy_sensitivity.rest_length_sensitivities if rob.heavy else rest_length_sensitivities
        SL, hooke, cond = rls(rob, res["P_s"], res["R_s"], L0)
        # a point mass's 6 x 6 Jacobian is singular (no moment rows): sensitivities_at judges its
        # 3 x 3 translation block as the point-mass physical mode does
        smooth = differentiable(hooke, cond) if self.spatial else res["smooth"]
        if not drum.all():  # a command the drum cannot pay out: no equilibrium, flagged by the fit
            res["status"] = np.where(drum, res["status"], DRUM_RANGE)
            res["P_s"][~drum] = np.nan
        S = np.zeros((len(start), 6, len(th)))
        S[:, :, self._cols] = res["S"]
        S[:, :, nr:] = -SL if w_L is None else -SL * w_L[:, None, :]
        if self.winch:  # chain rule: dx/dd_i += dx/dL0_i dL0_i/dd_i (dx/do_i above: -dx/dL0_i dL0_i/dL_cmd,i)
            S[:, :, 3 * m : 4 * m] += SL * w_d[:, None, :]
        return res, L0, S, smooth

    def residual(self, z):
        """r(z) = [pose rows ; tension rows ; z] (``map_residual``)."""
        ev = self.evaluate(z)
        d, p, t = self.data, self._pose, self._tens
        orientation = {}
        if self.spatial:
            orientation = {"R_meas": self._R[p], "R_pred": ev["R"][p], "sigma_rad": d.sigma_rad[p]}
        r = map_residual(d.pose[p], ev["P"][p], d.sigma[p], z, **orientation)
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


def tension_sensitivities(robot, P, L0, S, w_L=None, w_d=None, R=None, cols=None):
    r"""Cable tensions at the equilibrium and their total derivatives by the calibration parameters.

    The point-mass physical solver's equilibrium (``R`` None; x* = P*):

    .. math:: t_i = k_i\,a_i\,(L_{TE,i}(P^*) - L0_i),\quad k_i = \frac{E_i S_i}{L0_i},\quad
              \frac{dt_i}{d\theta} = a_i\left[k_i\left(\frac{\partial L_{TE,i}}{\partial P}
              \frac{dP^*}{d\theta} + \frac{\partial L_{TE,i}}{\partial \theta}\right)
              + \frac{\partial k_i}{\partial \theta}(L_{TE,i} - L0_i)\right]

    with ∂k_i/∂E_i = k_i / E_i, and for the encoder offset o_i (L0_i = reading - o_i)
    ∂(L_TE,i - L0_i)/∂o_i = 1, ∂k_i/∂o_i = k_i / L0_i. Through a winch (L0_i = W(reading - o_i, d_i),
    ``drive.realised_rest_lengths``) the offset terms are multiplied by ∂W/∂L_cmd and the dead length
    gets ∂t_i/∂L0_i ∂W/∂d_i, ∂t_i/∂L0_i = -(k_i + k_i (L_TE,i - L0_i) / L0_i).

    The pose model's equilibrium (``R`` given: a rigid platform, or a point mass under pulleys at
    any axis, whose b_i = 0 make ∂t_i/∂φ = 0):

    .. math:: \frac{dt_i}{d\theta} = \frac{\partial t_i}{\partial x}\frac{dx^*}{d\theta}
              + a_i\left[k_i \frac{\partial L_{TE,i}}{\partial \theta}
              + \frac{\partial k_i}{\partial \theta}(L_{TE,i} - L0_i)\right]
              + \frac{\partial t_i}{\partial L0_i}\frac{dL0_i}{d\theta}

    x* = (p*, R*) with the attachment B_i = p + R b_i (``sensitivity.tension_partials``: ∂t_i/∂x,
    ∂t_i/∂L0_i = -a_i k_i L_TE,i / L0_i and the fixed-pose partials of the columns ``cols``);
    dL0_i/do_i = -1, or through a winch -∂W/∂L_cmd, and dL0_i/dd_i = ∂W/∂d_i.

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibria.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.
    S : ndarray, shape (n, 3, K), or (n, 6, K) with ``R``
        dx*/dθ of every calibration parameter (``calibration_names(robot)``, K of them: 8 m + 1,
        11 m + 4 on a rigid platform), the chain rule of the winch included; with ``R`` only the
        columns ``cols`` and the offsets need to be filled.
    w_L, w_d : ndarray, shape (n, m) [m/m], optional
        dL0/dL_cmd and dL0/dd of the winch map (None: no winch).
    R : ndarray, shape (n, 3, 3) [-], optional
        Equilibrium orientations of the pose model.
    cols : ndarray of int, optional
        With ``R``: the robot parameters (before the offsets) whose fixed-pose partials count.

    Returns
    -------
    t : ndarray, shape (n, m) [N]
        0 on slack cables.
    dt : ndarray, shape (n, m, K) [N per unit of θ]

    References
    ----------
    Paty et al. 2021, eq. (5), (10), (13); implicit-function theorem.
    """
    if R is not None:
        return _pose_tension_sensitivities(robot, P, R, L0, S, cols, w_L, w_d)

    a = robot.arrays
    m = robot.m
    nr = robot_size(robot)
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
            dt[:, c, nr + c] -= dt_dL0
        else:
            dt[:, c, nr + c] -= dt_dL0 * w_L[:, c]
            dt[:, c, 3 * m + c] += dt_dL0 * w_d[:, c]
    return t, dt * taut[..., None]


def _pose_tension_sensitivities(robot, P, R, L0, S, cols, w_L, w_d):
    """``tension_sensitivities`` on the pose model (its docstring)."""
    m = robot.m
    nr = robot_size(robot)
    names = calibration_names(robot)
    tp = tension_partials(robot, P, R, L0, [names[k] for k in cols])
    dt = np.einsum("nia,nak->nik", tp["dt_dx"], S)
    dt[:, :, cols] += tp["dt_dtheta"]
    cab = np.arange(m)
    dt[:, cab, nr + cab] -= tp["dt_dL0"] if w_L is None else tp["dt_dL0"] * w_L
    if w_d is not None:
        dt[:, cab, 3 * m + cab] += tp["dt_dL0"] * w_d
    return tp["t"], dt
