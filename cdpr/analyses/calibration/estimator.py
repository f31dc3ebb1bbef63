"""The estimator: priors, the MAP fit, the rigid self-calibration and the motor-angle fit.

``fit`` is the maximum a posteriori (MAP) estimate of θ under a Gaussian prior around the nominal
robot (``parse_priors``, ``prior_sd``): a weakly identified parameter stays near its prior instead
of running away. ``scipy.optimize.least_squares`` on the residual of ``problem.Problem`` with
its exact Jacobian; the result is a ``result.Calibration``. ``fit_motor`` is the self-calibration
from a spool robot's motor angles with every position a nuisance (``cdpr.analyses.calibration.motor``,
its priors ``parse_motor_priors``); its result is a ``result.MotorCalibration``.

Encoder data (``L_enc1..L_encm``): with elastic cables and no measured tension every set of lengths
has an equilibrium for every θ, so a sample without a measured pose gives no equation in the exact
model; such samples are counted and left out, and with none left the fit refuses with one line
naming the way out (measure poses, or ``--model standard`` for a rigid self-calibration of a point
mass, ``self_calibrate_standard``, whose gauge it reports).

References
----------
Tarantola, A. (2005). Inverse Problem Theory and Methods for Model Parameter Estimation, SIAM,
section 3.2 (least squares with a Gaussian prior, posterior covariance).
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Mechanism and Machine Theory 159, 104263,
eq. (1)-(2) (the standard model of the self-calibration).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from cdpr.analyses.calibration import motor
from cdpr.analyses.calibration.identify import (
    identifiability,
    identifiability_without,
)
from cdpr.analyses.calibration.model import (
    default_start,
    model_robot,
)
from cdpr.analyses.calibration.motor import (
    MOTOR_GROUPS,
    MOTOR_MODELS,
    SIGMA_LINE_DEFAULT,
    SpoolModel,
    gauge_words,
    line_residuals,
    motor_index,
    motor_names,
    motor_prior_sd,
    motor_problem,
    reference_forces,
    solve_positions,
    stretch_factors,
)
from cdpr.analyses.calibration.problem import (
    Problem,
)
from cdpr.analyses.calibration.result import Calibration, MotorCalibration
from cdpr.errors import CdprError
from cdpr.parameters import (
    CALIBRATION_GROUPS,
    calibration_groups,
    calibration_names,
    calibration_values,
    is_spatial,
    select_groups,
)
from cdpr.units import quantity

#: Prior standard deviations by default: lengths [m], moduli and mass relative to the nominal.
DEFAULT_PRIORS = {
    "anchors": 5e-3,
    "dead_lengths": 50e-3,
    "moduli": 0.20,
    "pulleys": 1e-3,
    "attachments": 3e-3,
    "offsets": 50e-3,
    "mass": 0.05,
}
#: Groups whose prior sd is relative to the nominal value.
RELATIVE = ("moduli", "mass")
#: Normalised residual above which a sample counts as an outlier of the robust loss.
OUTLIER = 3.0


def parse_priors(text, source="--prior", estimate=None):
    """Prior standard deviations from ``G=SD,...`` (``anchors=5mm,moduli=20%``).

    Length groups take a length with its unit (or a bare number in m), ``moduli`` and ``mass`` a
    percentage (or a bare fraction), below 100 % (a bare ``moduli=20`` would be 2000 %). Missing
    groups keep ``DEFAULT_PRIORS``.

    Parameters
    ----------
    text : str or None
    source : str
        Named in the error message.
    estimate : sequence of str, optional
        The groups estimated: a prior given for another group is refused (it would do nothing).

    Returns
    -------
    priors : dict group -> float [m, or relative]
    """

    def value(g, v):
        if g not in RELATIVE:
            return quantity(v, "m", source, g)
        try:
            sd = float(v[:-1]) / 100.0 if v.endswith("%") else float(v)
        except ValueError:
            raise CdprError(f"{source}: {g}={v!r} is not a percentage (e.g. {g}=20%)") from None
        if math.isfinite(sd) and 1.0 <= sd:
            raise CdprError(
                f"{source}: the prior sd of {g} is relative and must be below 100 %, got {v!r} "
                f"({sd:.0%}); give a percentage, e.g. {g}=20%"
            )
        return sd

    priors = _prior_items(text, source, CALIBRATION_GROUPS, "anchors=5mm,moduli=20%", "", value, estimate)
    return {**DEFAULT_PRIORS, **priors}


def _prior_items(text, source, allowed, example, unknown, value, estimate):
    """The prior sd of each ``G=SD`` item of ``text`` (dict group -> sd, in the order given, empty
    without text): ``value(group, text)`` reads an sd; CdprError naming ``source`` on an item
    without ``=``, a group not ``allowed`` (``unknown`` completes that message), an sd not finite
    and > 0, or a group not in ``estimate`` (None: any)."""
    out = {}
    for item in str(text).split(",") if text else []:
        if "=" not in item:
            raise CdprError(f"{source}: expected GROUP=SD, got {item!r}; e.g. {example}")
        g, v = (s.strip() for s in item.split("=", 1))
        if g not in allowed:
            raise CdprError(f"{source}: unknown group {g!r}{unknown}; allowed: {', '.join(allowed)}")
        sd = value(g, v)
        if not (math.isfinite(sd) and sd > 0):
            raise CdprError(f"{source}: the prior sd of {g} must be > 0, got {v!r}")
        if estimate is not None and g not in estimate:
            raise CdprError(
                f"{source}: a prior for {g}, which is not estimated (--estimate {','.join(estimate)}); "
                f"remove it or add {g} to --estimate"
            )
        out[g] = sd
    return out


def parse_motor_priors(text, estimate, source="--prior"):
    """Prior sd of a motor-angle calibration from ``G=SD,...`` (``anchors=150mm,spools=1mm``).

    Parameters
    ----------
    text : str or None
    estimate : sequence of str
        The groups estimated (``motor.MOTOR_GROUPS``); a prior for another group is refused.
    source : str
        Named in the error message.

    Returns
    -------
    priors : dict group -> float [m]
    """
    for g in estimate:
        if g not in MOTOR_GROUPS:
            raise CdprError(
                f"--estimate {g}: a motor-angle calibration estimates {', '.join(MOTOR_GROUPS)} only"
            )
    priors = _prior_items(
        text,
        source,
        MOTOR_GROUPS,
        "anchors=150mm,spools=1mm",
        " for motor-angle data",
        lambda g, v: quantity(v, "m", source, g),
        estimate,
    )
    return {**motor.DEFAULT_PRIORS, **priors}


def prior_sd(robot, index, priors):
    """Absolute prior sd of the calibration parameters ``index`` (relative groups × |nominal|).

    Parameters
    ----------
    robot : Robot
    index : ndarray of int
        Into ``calibration_names(robot)``.
    priors : dict
        ``parse_priors``.

    Returns
    -------
    sd : ndarray, shape (len(index),) [Pa, m, kg]
    """
    groups, _ = calibration_groups(robot)
    nominal = calibration_values(robot)
    return np.array(
        [priors[groups[k]] * abs(nominal[k]) if groups[k] in RELATIVE else priors[groups[k]] for k in index]
    )


def check_model_groups(robot, model, groups, data):
    """Refuse group/model/data combinations that mean nothing (one line each)."""
    if model == "standard" and ({"pulleys", "moduli"} & set(groups)):
        bad = sorted({"pulleys", "moduli"} & set(groups))[0]
        raise CdprError(
            f"--estimate {bad}: the standard model has no {bad} (straight lines to fixed points, rigid cables)"
        )
    if model == "rigid" and "moduli" in groups:
        raise CdprError("--estimate moduli: the rigid model's cables do not stretch")
    if "offsets" in groups and not data.encoder:
        raise CdprError(f"{data.source}: --estimate offsets needs encoder readings L_enc1..L_enc{robot.m}")
    if "pulleys" in groups and (robot.arrays.kind == 0).any():
        raise CdprError("--estimate pulleys: the robot has fixed pulleys (h = r_p = 0); nothing to estimate")


def usable(data, robot):
    """Split the samples: those with a measured pose or measured tensions are equations, the others
    (encoder readings alone) are not.

    Raises CdprError when no sample is usable: in the exact model encoder-only samples give no
    equation (every set of lengths has an equilibrium for every θ)."""
    has = data.has_pose | data.has_tension
    if not has.any():
        raise CdprError(
            f"{data.source}: no sample has a measured pose or tensions; with elastic cables and no measured tension every "
            "set of lengths has an equilibrium for every θ, so encoder-only samples give no equation "
            "(d_i and offset_i enter only as their sum); measure poses or tensions (t1_N..), or, for a point mass, "
            "use --model standard for a rigid self-calibration (biased)"
        )
    return np.flatnonzero(has), np.flatnonzero(~has)


def fit(robot, data, groups, priors=None, model="exact", loss="linear", engine=None, solver=None):
    """MAP estimate of the parameters of ``groups`` from ``data`` (module docstring).

    Encoder-only data with ``model="standard"`` go to the rigid self-calibration with unknown poses
    (``self_calibrate_standard``).

    ``scipy.optimize.least_squares`` (trust-region reflective, bounds from the robot checks: E, M > 0,
    h, r_p, d >= 0) on ``map_residual`` with the exact Jacobian. Samples whose equilibrium is not
    ``ok`` or not smooth (a taut set about to change, a singular Jacobian) at the nominal or at the
    estimate are flagged and left out, never silently.

    Parameters
    ----------
    robot : Robot
        Nominal robot (the prior mean).
    data : Data
    groups : list of str
        ``CALIBRATION_GROUPS``.
    priors : dict, optional
        ``parse_priors`` (default ``DEFAULT_PRIORS``).
    model : {"exact", "standard"}
    loss : str
        ``least_squares`` loss: "linear" (default) or a robust one ("soft_l1", "huber", "cauchy").
    engine : {"compiled", "numpy"} or None
        None: ``equilibrium_engine``'s default (compiled, on the point-mass solver and on the pose
        model alike); a named engine is checked and used by either.
    solver : dict, optional
        tol, maxiter, max_step of the physical solve.

    Returns
    -------
    Calibration
    """

    priors = parse_priors(None) if priors is None else priors
    if model == "standard" and data.encoder and not (data.has_pose | data.has_tension).any():
        return self_calibrate_standard(robot, data, groups, priors)
    base = model_robot(robot, model)
    index = select_groups(robot, groups)
    check_model_groups(base, model, groups, data)
    sd = prior_sd(base, index, priors)
    used, no_pose = usable(data, robot)
    status = np.full(len(data.sample), "no pose or tension", dtype=object)
    spatial = is_spatial(robot)
    names = [calibration_names(robot)[k] for k in index]
    keep = used
    for _attempt in range(3):
        sub = data.subset(keep)
        prob = Problem(base, sub, index, sd, engine=engine, solver=solver)
        ev0 = prob.evaluate(np.zeros(len(index)))
        good = (ev0["status"] == "ok") & ev0["smooth"]
        if not good.all():
            status[keep[~good]] = [f"left out at nominal: {s}" for s in _why(ev0, ~good)]
            keep = keep[good]
            continue
        break
    # fewer equations than parameters is no reason to refuse: every estimated parameter has a prior,
    # so the MAP is proper; what the data do not see stays at its prior (identifiability says which)
    sub = data.subset(keep)
    prob = Problem(base, sub, index, sd, engine=engine, solver=solver)
    lo, hi = _bounds(base, index, sd)
    sol = least_squares(
        prob.residual,
        np.zeros(len(index)),
        jac=prob.jacobian,
        bounds=(lo, hi),
        method="trf",
        loss=loss,
        f_scale=OUTLIER if loss != "linear" else 1.0,
        x_scale=1.0,
        ftol=1e-15,
        xtol=1e-15,
        gtol=1e-15,
        max_nfev=200,
    )
    ev = prob.evaluate(sol.x)
    bad = ~((ev["status"] == "ok") & ev["smooth"])
    status[keep] = "used"
    if bad.any():
        status[keep[bad]] = [f"left out at estimate: {s}" for s in _why(ev, bad)]
    J = prob.jacobian(sol.x)[: -len(index)]
    Jm = J[~bad[prob.row_sample]]
    ident = identifiability(Jm, names)
    theta = prob.theta(sol.x)
    before = np.full(len(data.sample), np.nan)
    after = np.full(len(data.sample), np.nan)
    before[keep] = np.linalg.norm(sub.pose - ev0_positions(prob), axis=1)  # NaN without a pose
    after[keep] = np.linalg.norm(sub.pose - ev["P"], axis=1)
    after[keep[bad]] = np.nan
    norm = after / data.sigma
    extra = {}
    if spatial:
        for col, evk in (
            ("residual_before_rad", prob.evaluate(np.zeros(len(index)))),
            ("residual_after_rad", ev),
        ):
            extra[col] = np.full(len(data.sample), np.nan)
            extra[col][keep] = prob.angles(evk)
        extra["residual_after_rad"][keep[bad]] = np.nan
        norm = np.maximum(norm, extra["residual_after_rad"] / data.sigma_rad)
    outlier = (norm > OUTLIER) if loss != "linear" else np.zeros(len(norm), dtype=bool)
    return Calibration(
        robot=robot,
        base=base,
        model=model,
        index=index,
        names=names,
        nominal=prob.theta0[index],
        estimate=theta[index],
        prior_sd=sd,
        ident=ident,
        theta=theta,
        table=pd.DataFrame(
            {
                "sample": data.sample,
                "status": status.astype(str),
                "residual_before_m": before,
                "residual_after_m": after,
                **extra,
                "outlier": outlier,
            }
        ),
        source=data.source,
        cost=float(sol.cost),
        nfev=int(sol.nfev),
    )


def ev0_positions(prob):
    """P* of the nominal robot at the problem's samples."""
    return prob.evaluate(np.zeros(len(prob.index)))["P"]


def _why(ev, mask):
    return [st if st != "ok" else "taut set about to change or singular" for st in ev["status"][mask]]


def _bounds(base, index, sd):
    """Box bounds in prior-scaled variables: E, M > 1 % of nominal; h, r_p, d >= 0; A and offsets free."""
    groups, _ = calibration_groups(base)
    names = calibration_names(base)
    th0 = calibration_values(base)
    lo = np.full(len(index), -np.inf)
    for j, k in enumerate(index):
        g = groups[k]
        if g in RELATIVE:
            lo[j] = (0.01 * th0[k] - th0[k]) / sd[j]
        elif g in ("pulleys", "dead_lengths") or names[k].startswith(("h_", "r_p_", "d_")):
            lo[j] = -th0[k] / sd[j]
    return lo, np.full(len(index), np.inf)


#: Encoder noise sd [m] of the rigid self-calibration.
SIGMA_L_DEFAULT = 1e-3


def standard_lengths(A, d, o, P):
    """Encoder readings of the standard model: straight lines to fixed points, rigid cables,

    .. math:: L_{enc,ki} = o_i + d_i + |P_k - A_i|

    (the winch exit C_i = A_i - d_i z, so the cable runs C_i → A_i → P_k).

    Parameters
    ----------
    A : ndarray, shape (m, 3) [m]
        Joint points.
    d, o : ndarray, shape (m,) [m]
        Dead lengths and encoder offsets.
    P : ndarray, shape (n, 3) [m]
        Platform positions.

    Returns
    -------
    L : ndarray, shape (n, m) [m]

    References
    ----------
    Paty et al. 2021, eq. (1)-(2) (the standard geometric model).
    """
    return o + d + np.linalg.norm(P[:, None, :] - A, axis=-1)


def self_calibrate_standard(robot, data, groups, priors=None, sigma_L=SIGMA_L_DEFAULT):
    """Hangprinter-style rigid self-calibration: encoder readings only, poses unknown, redundant cables.

    Least squares on (L_enc - ``standard_lengths``) / σ_L over the unknown poses P_k and the
    parameters of ``groups`` (anchors, dead_lengths, offsets; MAP with their prior rows), exact
    Jacobian. The identifiability is that of θ with the poses eliminated (measurement rows projected
    on the orthogonal complement of the pose columns): d_i and offset_i enter only as their sum, and
    with every anchor free the frame may move rigidly. Biased on a real robot: it ignores the
    pulleys and the cables' stretch.

    Parameters
    ----------
    robot : Robot
        Nominal robot; its pulleys and moduli are ignored (standard model).
    data : Data
        Encoder readings (``data.encoder``); measured poses, if any, are not used.
    groups : list of str
        Among anchors, dead_lengths, offsets.
    priors : dict, optional
    sigma_L : float [m]
        Encoder noise sd.

    Returns
    -------
    Calibration
        ``model == "standard"``; residual_after_m per sample is its RMS length residual [m].
    """

    if not data.encoder:
        raise CdprError(
            f"{data.source}: rigid self-calibration needs encoder readings L_enc1..L_enc{robot.m}"
        )
    if is_spatial(robot):
        raise CdprError(
            f"{data.source}: the rigid self-calibration (encoder readings alone, --model standard) is for "
            f"point-mass robots; robot {robot.name} has a 6-DoF platform: give tensions t1_N..t{robot.m}_N "
            "or measured poses"
        )
    bad = set(groups) - {"anchors", "dead_lengths", "offsets"}
    if bad:
        raise CdprError(
            f"--estimate {sorted(bad)[0]}: the rigid self-calibration estimates anchors, dead_lengths, offsets only"
        )
    priors = parse_priors(None) if priors is None else priors
    base = model_robot(robot, "standard")
    index = select_groups(robot, groups)
    sd = prior_sd(base, index, priors)
    th0 = calibration_values(base)
    m, n, k = robot.m, len(data.sample), len(index)
    if m < 3:
        raise CdprError(f"{data.source}: the rigid self-calibration needs at least 3 cables to locate a pose")

    def unpack(x):
        th = th0.copy()
        th[index] += sd * x[3 * n :]
        A = th[4 * m : 7 * m].reshape(m, 3)
        return th, A, th[3 * m : 4 * m], th[7 * m + 1 :], x[: 3 * n].reshape(n, 3)

    def residual(x):
        th, A, d, o, P = unpack(x)
        return np.concatenate([((data.L - standard_lengths(A, d, o, P)) / sigma_L).ravel(), x[3 * n :]])

    def jacobian(x):
        th, A, d, o, P = unpack(x)
        diff = P[:, None, :] - A
        u = diff / np.linalg.norm(diff, axis=-1, keepdims=True)  # (n, m, 3): dL/dP, -dL/dA
        J = np.zeros((n * m + k, 3 * n + k))
        for kk in range(n):
            J[kk * m : (kk + 1) * m, 3 * kk : 3 * kk + 3] = -u[kk] / sigma_L
        for j, col in enumerate(index):
            dL = np.zeros((n, m))
            if 4 * m <= col < 7 * m:
                c, ax = divmod(col - 4 * m, 3)
                dL[:, c] = -u[:, c, ax]
            else:  # d_i or offset_i
                dL[:, (col - 3 * m) if col < 4 * m else (col - 7 * m - 1)] = 1.0
            J[: n * m, 3 * n + j] = -(dL * sd[j] / sigma_L).ravel()
        J[n * m :, 3 * n :] = np.eye(k)
        return J

    # first guess of the poses: multilateration with the nominal robot (Gauss-Newton per sample)
    A0, d0, o0 = base.A, th0[3 * m : 4 * m], np.zeros(m)
    P = np.tile(default_start(base), (n, 1))
    for _ in range(30):
        diff = P[:, None, :] - A0
        dist = np.linalg.norm(diff, axis=-1)
        r = data.L - o0 - d0 - dist
        u = diff / dist[..., None]
        step = np.linalg.solve(np.einsum("nia,nib->nab", u, u), np.einsum("nia,ni->na", u, r)[..., None])[
            ..., 0
        ]
        P = P + step  # Gauss-Newton: dr/dP = -u
    x0 = np.concatenate([P.ravel(), np.zeros(k)])
    sol = least_squares(
        residual, x0, jac=jacobian, method="trf", ftol=1e-15, xtol=1e-15, gtol=1e-15, max_nfev=200
    )
    J = jacobian(sol.x)[: n * m]
    names = [calibration_names(robot)[c] for c in index]
    ident = identifiability_without(J[:, 3 * n :], J[:, : 3 * n], names)
    th = unpack(sol.x)[0]
    res = residual(sol.x)[: n * m].reshape(n, m) * sigma_L
    table = pd.DataFrame(
        {
            "sample": data.sample,
            "status": "used",
            "residual_before_m": np.nan,
            "residual_after_m": np.sqrt(np.mean(res**2, axis=1)),
            "outlier": False,
        }
    )
    return Calibration(
        robot=robot,
        base=base,
        model="standard",
        index=index,
        names=names,
        nominal=th0[index],
        estimate=th[index],
        prior_sd=sd,
        ident=ident,
        theta=th,
        table=table,
        source=data.source,
        cost=float(sol.cost),
        nfev=int(sol.nfev),
    )


def fit_motor(robot, data, groups, priors=None, model="exact", sigma_line=SIGMA_LINE_DEFAULT):
    """MAP self-calibration from motor angles with every position a nuisance (``cdpr.analyses.calibration.motor``).

    Parameters
    ----------
    robot : Robot
        Nominal robot (the prior mean), a point mass on fixed anchors with a spool on every cable.
    data : MotorData
    groups : list of str
        Among ``MOTOR_GROUPS``.
    priors : dict, optional
        ``parse_motor_priors`` (default ``DEFAULT_PRIORS``).
    model : {"exact", "standard"}
    sigma_line : float [m]
        Line noise sd.

    Returns
    -------
    MotorCalibration
    """
    if model not in MOTOR_MODELS:
        raise CdprError(f"--model {model}: motor-angle data take {', '.join(MOTOR_MODELS)}")
    bad = [g for g in groups if g not in MOTOR_GROUPS]
    if bad or not groups:
        raise CdprError(
            f"--estimate {bad[0] if bad else ''}: a motor-angle calibration estimates {', '.join(MOTOR_GROUPS)}"
        )
    priors = parse_motor_priors(None, groups) if priors is None else priors
    sm0 = SpoolModel.of(robot)
    m, n = robot.m, len(data.sample)
    index = motor_index(m, groups)
    k = len(index)
    sd = motor_prior_sd(m, index, priors)
    th0 = sm0.theta()
    t_ref, warn = reference_forces(data, model)
    f, g = stretch_factors(model, data, t_ref, sm0.K)
    hp = data.has_pose
    ip = np.flatnonzero(hp)
    residual, jacobian, unpack = motor_problem(sm0, data, index, sd, f, g, sigma_line)
    start = np.where(hp[:, None], data.pose, np.nan)
    P0, _ = solve_positions(sm0, data, f, g, start=np.where(np.isfinite(start), start, sm0.A.mean(axis=0)))
    x0 = np.concatenate([np.zeros(k), P0.ravel()])
    sol = least_squares(
        residual,
        x0,
        jac=jacobian,
        method="trf",
        x_scale="jac",
        ftol=1e-12,
        xtol=1e-12,
        gtol=1e-12,
        max_nfev=200,
    )
    sm, P = unpack(sol.x)
    J = jacobian(sol.x)[: n * m + 3 * len(ip)]
    names_all = motor_names(m)
    names = [names_all[c] for c in index]
    ident = identifiability_without(J[:, :k], J[:, k:], names)
    res = line_residuals(sm, data, P, f, g)
    perr = np.full(n, np.nan)
    perr[ip] = np.linalg.norm(P[ip] - data.pose[ip], axis=1)
    status = np.where((model == "exact") & ~data.has_force, "no forces: rigid lines", "used")
    table = pd.DataFrame(
        {
            "sample": data.sample,
            "status": status,
            "x_m": P[:, 0],
            "y_m": P[:, 1],
            "z_m": P[:, 2],
            "line_rms_m": np.sqrt(np.mean(res**2, axis=1)),
            "position_residual_m": perr,
        }
    )
    return MotorCalibration(
        robot=robot,
        model=model,
        groups=list(groups),
        index=index,
        names=names,
        nominal=th0[index],
        estimate=sm.theta()[index],
        prior_sd=sd,
        ident=ident,
        spool_model=sm,
        positions=P,
        line_residual=res,
        table=table,
        source=data.source,
        gauge=gauge_words(data, groups),
        warnings=[w for w in (warn,) if w],
        cost=float(sol.cost),
        nfev=int(sol.nfev),
    )
