"""Uncertainty of the pose error: parameter distributions, seeded Monte Carlo by full solves, the
first-order (linearised) propagation of the exact sensitivities, and Sobol indices (SALib).

The study file's ``uncertainty.parameters`` declares a distribution per parameter group (keys
``PARAMETER_KEYS``)::

    young_modulus_Pa: {dist: uniform, low: 67.2e9, high: 137.2e9, per_cable: true}    # E_i [Pa]
    anchor_offset_m:  {dist: normal, mean: 0, sd: 0.002, per_cable: true}           # A_i + offset [m]
    mass_kg:          {dist: normal, mean: 300, sd: 10, low: 270, high: 330}        # M [kg], truncated
    attachment_offset_m: {dist: normal, mean: 0, sd: 0.001, per_cable: true}        # b_i + offset [m]
    com_offset_m:     {dist: uniform, low: -0.01, high: 0.01}                      # c + offset [m]

The last two are a rigid platform's (a spatial study): the attachments b_i (platform frame, x, y,
z of each cable drawn independently with ``per_cable: true``, one draw per axis for all cables
otherwise) and the centre of mass c (one draw per axis). Every driver sets columns of the robot's
own θ (``parameters.parameter_names``: E, h, r_p, d, A, then b and c on a rigid platform, M last)
through ``parameters.group_columns``; a point mass has no b and c, and refuses their keys.

``uniform`` takes low and high; ``normal`` takes mean and sd, and optional low/high that truncate
it. Keys ending in ``_offset_m`` are deviations added to each cable's nominal value (the designs
differ in h and r_p, the anchors in position); the others are the values themselves. ``per_cable:
true`` draws each cable's value independently; ``false`` draws one value for every cable (fully
correlated, the paper's common E). Each independent draw is a *driver* (``Driver``): E_2, A_3_z, M,
or E_all for a shared modulus. A driver's value is its distribution's inverse CDF at a uniform
number u in (0, 1), so Monte Carlo (``mc_uniforms``) and Saltelli's design (``sobol_analysis``)
only generate u.

Reproducibility: sample s of seed S uses ``numpy.random.default_rng([S, s])`` and nothing else, so
the same seed gives the same numbers whatever the shards (ranges of s) are; drivers are numbered in
the fixed order of ``PARAMETER_KEYS`` and the cables, whatever the order of the study's keys.

The pose error of a design (``PoseErrorModel``), for sampled parameters θ:

* ``uncompensated`` (the paper's question): the winches command the standard model's lengths
  L_TS(p) of the *nominal* robot; the robot with parameters θ settles at P*(θ) (paper mode: DEGM_E
  on the best admissible 3-cable subset; or the physical equilibrium);
* ``compensated``: the lengths are compensated with the nominal parameters (``compensation``:
  rest lengths that hold the nominal robot exactly at p) and the robot with θ settles where its
  forces balance (physical equilibrium): the residual error a real robot would have.

Its responses (``RESPONSES``) are ‖δp‖ [m] and, when the robot is solved as a pose (every robot
but a suspended point mass: a rigid platform, or pulleys at other axes than +z; physical mode, at
the study's orientation), δφ [rad], the angle of R*ᵀR_d. ``solve`` does full solves;
``linearisations`` gives the first-order propagation of the sensitivities at the nominal parameters
(``sensitivity``) of each response, dp(θ) = dp_0 + S (τ(θ) - τ(θ_0)), with τ the identity except
for the moduli, linearised in the compliance 1/E_i (the cable stretch t L / (E S) is linear in it, so
the elastic error is nearly linear in 1/E over the paper's ±35 GPa, not in E).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (section 5).
Saltelli, A. et al. (2010), Variance based sensitivity analysis of
model output, Computer Physics Communications 181, 259-270. Herman, J., Usher, W. (2017), SALib:
an open-source Python library for sensitivity analysis, JOSS 2(9).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from cdpr.analyses.compensation import compensate
from cdpr.analyses.interference import interfering_at
from cdpr.errors import CdprError, ConfigError
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays, rotvec_of
from cdpr.parameters import (
    RIGID_GROUPS,
    group_columns,
    parameter_names,
    parameter_values,
    robot_with_parameters,
)
from cdpr.solve import (
    check_engine,
    linear_dp,
    linear_positions,
    reached_answer,
    sensitivities,
    sensitivities_at,
    solve,
    solve_batch,
    subset_sensitivities,
)

#: Study keys of ``uncertainty.parameters``: key -> (parameter group, "value" or "offset"), in the
#: order drivers are numbered.
PARAMETER_KEYS = {
    "young_modulus_Pa": ("E", "value"),
    "h_offset_m": ("h", "offset"),
    "r_p_offset_m": ("r_p", "offset"),
    "dead_length_offset_m": ("d", "offset"),
    "anchor_offset_m": ("A", "offset"),
    "mass_kg": ("M", "value"),
    # a rigid platform's (``Robot.point_mass`` false; spatial studies): after every point-mass key,
    # so that the drivers of a study without them keep their numbers
    "attachment_offset_m": ("b", "offset"),
    "com_offset_m": ("c", "offset"),
}
CASES = ("uncompensated", "compensated")
#: The responses of ``PoseErrorModel``: ‖δp‖ [m] of every robot, δφ [rad] of a robot solved as a pose.
RESPONSES = ("dp", "dphi")
#: Where ``PoseErrorModel``'s physical full solves start Newton.
STARTS = ("linear", "desired")
#: Quantiles of the bands (5, 50, 95 %).
QUANTILES = (0.05, 0.5, 0.95)
#: u is kept in [U_EPS, 1 - U_EPS] so that an unbounded normal's inverse CDF stays finite.
U_EPS = 1e-12


@dataclasses.dataclass(frozen=True)
class Distribution:
    """A univariate distribution: ``uniform`` (low, high) or ``normal`` (mean, sd, optional low and
    high truncating it)."""

    dist: str
    low: float | None = None
    high: float | None = None
    mean: float | None = None
    sd: float | None = None

    @classmethod
    def from_spec(cls, spec):
        return cls(
            dist=spec["dist"],
            low=spec.get("low"),
            high=spec.get("high"),
            mean=spec.get("mean"),
            sd=spec.get("sd"),
        )

    def _trunc(self):
        from scipy.stats import truncnorm  # lazy: scipy.stats is 0.4 s of every job's start-up

        a = -np.inf if self.low is None else (self.low - self.mean) / self.sd
        b = np.inf if self.high is None else (self.high - self.mean) / self.sd
        return truncnorm(a, b, loc=self.mean, scale=self.sd)

    def ppf(self, u):
        """Inverse CDF at u (any shape) in (0, 1)."""
        u = np.clip(np.asarray(u, dtype=float), U_EPS, 1.0 - U_EPS)
        if self.dist == "uniform":
            return self.low + u * (self.high - self.low)
        if self.low is None and self.high is None:
            from scipy.stats import norm  # lazy: scipy.stats is 0.4 s of every job's start-up

            return norm.ppf(u, loc=self.mean, scale=self.sd)
        return self._trunc().ppf(u)

    def moments(self):
        """(mean, variance) of the distribution."""
        if self.dist == "uniform":
            return 0.5 * (self.low + self.high), (self.high - self.low) ** 2 / 12.0
        if self.low is None and self.high is None:
            return float(self.mean), float(self.sd) ** 2
        mu, var = self._trunc().stats("mv")
        return float(mu), float(var)

    def support(self):
        """(lowest, highest) value that can be drawn (infinite for an untruncated normal)."""
        lo = self.low if self.low is not None else -np.inf
        hi = self.high if self.high is not None else np.inf
        return lo, hi


@dataclasses.dataclass(frozen=True)
class Driver:
    """One independent draw: its name (E_2, E_all, A_3_z, A_all_z, M), the study key, the parameter
    group, the columns of the robot's θ (``parameters.parameter_names``) it sets, whether it
    is an offset added to the nominal values, and its distribution."""

    name: str
    key: str
    group: str
    columns: tuple
    offset: bool
    dist: Distribution


def drivers(parameters, robot):
    """The drivers (independent draws) of ``uncertainty.parameters``, in the fixed order of
    ``PARAMETER_KEYS`` and cables, whatever the order of the study's keys (the draw order: the
    columns they set are the robot's θ's, ``parameters.group_columns``).

    Parameters
    ----------
    parameters : dict
        ``PARAMETER_KEYS`` -> distribution spec {dist, low, high, mean, sd, per_cable}.
    robot : Robot
        The nominal robot (its θ: b and c on a rigid platform only).

    Returns
    -------
    list of Driver

    Raises
    ------
    CdprError
        A key of a rigid platform's group (b, c) on a point mass.
    """
    m = robot.m
    columns = group_columns(robot)
    out = []
    for key, (group, kind) in PARAMETER_KEYS.items():
        if key not in parameters:
            continue
        if group not in columns:
            raise CdprError(
                f"uncertainty.parameters.{key}: robot {robot.name} is a point mass (no attachments b_i or "
                f"centre of mass c); allowed for it: {', '.join(k for k, (g, _) in PARAMETER_KEYS.items() if g not in RIGID_GROUPS)}"
            )
        spec = parameters[key]
        dist = Distribution.from_spec(spec)
        offset = kind == "offset"
        per_cable = spec.get("per_cable", True) and group != "M"
        col = [int(c) for c in columns[group]]
        if group == "M":
            out.append(Driver("M", key, group, (col[0],), offset, dist))
        elif group == "c":
            out += [Driver(f"c_{ax}", key, group, (col[a],), offset, dist) for a, ax in enumerate("xyz")]
        elif group in ("A", "b"):  # per-cable 3-vectors: cable by cable, x y z
            for a, ax in enumerate("xyz"):
                if per_cable:
                    out += [
                        Driver(f"{group}_{c + 1}_{ax}", key, group, (col[3 * c + a],), offset, dist)
                        for c in range(m)
                    ]
                else:
                    cols = tuple(col[3 * c + a] for c in range(m))
                    out.append(Driver(f"{group}_all_{ax}", key, group, cols, offset, dist))
        elif per_cable:
            out += [Driver(f"{group}_{c + 1}", key, group, (col[c],), offset, dist) for c in range(m)]
        else:
            out.append(Driver(f"{group}_all", key, group, tuple(col), offset, dist))
    # anchors and attachments: per cable x, y, z together (A_1_x, A_1_y, A_1_z, A_2_x, ...)
    return sorted(out, key=lambda d: (list(PARAMETER_KEYS).index(d.key), d.columns))


def mc_uniforms(seed, start, stop, n_drivers):
    """Uniform numbers of Monte Carlo samples start .. stop - 1.

    Sample s draws from ``numpy.random.default_rng([seed, s])`` only: the same seed gives the same
    numbers for a sample whatever range (shard) it is computed in.

    Parameters
    ----------
    seed : int
    start, stop : int
        Sample range [start, stop).
    n_drivers : int

    Returns
    -------
    U : ndarray, shape (stop - start, n_drivers)
        In [0, 1).
    """
    return np.array(
        [np.random.default_rng([int(seed), int(s)]).random(n_drivers) for s in range(start, stop)]
    ).reshape(stop - start, n_drivers)


def parameter_samples(robot, drivers_, U, active=None):
    """Parameter vectors of uniform numbers: each active driver's inverse CDF sets its columns
    (offsets are added to the nominal values); inactive drivers leave the nominal values.

    Parameters
    ----------
    robot : Robot
        The nominal robot.
    drivers_ : list of Driver
    U : array_like, shape (n, n_drivers)
        Uniform numbers in (0, 1).
    active : array_like of bool, shape (n_drivers,), optional
        Drivers that move (default all).

    Returns
    -------
    theta : ndarray, shape (n, len(parameter_names(robot))) [Pa, m, kg]
        In the order of ``parameters.parameter_names``.
    """
    U = np.atleast_2d(np.asarray(U, dtype=float))
    th0 = parameter_values(robot)
    th = np.tile(th0, (len(U), 1))
    for k, dr in enumerate(drivers_):
        if active is not None and not active[k]:
            continue
        x = dr.dist.ppf(U[:, k])
        cols = list(dr.columns)
        th[:, cols] = th0[cols] + x[:, None] if dr.offset else x[:, None]
    return th


def check_samples(robot, theta, source="<study>", key="uncertainty.parameters"):
    """Refuse parameter vectors a robot cannot have (E, M, r_p > 0 or >= 0, h >= r_p for SR and
    h > r_p for DR, d >= 0, and, for a suspended point mass, anchors above the floor: every other
    robot has its anchors anywhere, e.g. IPAnema's at z = 0), naming the first bad sample.

    Parameters
    ----------
    robot : Robot
    theta : array_like, shape (n, len(parameter_names(robot)))
    source : str
        File named in the error.
    key : str
        Key named in the error.

    Returns
    -------
    None
        Raises ConfigError for a bad sample.
    """
    m = robot.m
    th = np.atleast_2d(theta)
    E, h, r_p, d = th[:, :m], th[:, m : 2 * m], th[:, 2 * m : 3 * m], th[:, 3 * m : 4 * m]
    Az = th[:, 4 * m + 2 : 7 * m : 3]
    kind = robot.arrays.kind
    sized = robot.arrays.h > 0
    checks = [
        (E <= 0, "a Young's modulus <= 0"),
        (th[:, [-1]] <= 0, "a payload mass <= 0"),
        (d < 0, "a negative dead length"),
        ((Az <= robot.floor_z) & robot.suspended_point_mass, "an anchor at or below the floor"),
        ((r_p < 0) | (h < 0), "a negative lever arm or sheave radius"),
        ((kind == 1) & sized & (h < r_p), "an SR pulley with h < r_p"),
        ((kind == 2) & sized & (h <= r_p), "a DR pulley with h <= r_p"),
    ]
    for bad, what in checks:
        bad = np.asarray(bad).reshape(len(th), -1).any(axis=1)
        if bad.any():
            raise ConfigError(
                source,
                key,
                f"sample {int(np.flatnonzero(bad)[0])} gives {what}; narrow the distribution or bound it with low/high",
            )


def nanquantile(a, q, axis):
    """``np.nanquantile(a, q, axis=axis)`` (linear interpolation, NaN ignored, NaN for a slice of
    NaN only, without warnings), to the bit, computed per group of slices that have their NaN at
    the same places: each group is one vectorised ``np.quantile`` over its valid entries instead
    of numpy's one call per slice (``apply_along_axis``; a Monte Carlo's samples usually share
    their infeasible points, so the groups are few).

    Parameters
    ----------
    a : ndarray, shape (..., n, ...) [any unit]
    q : sequence of float, shape (k,)
        Quantiles in [0, 1].
    axis : int
        The axis reduced.

    Returns
    -------
    ndarray, shape (k, ...) [a's unit]
        ``a``'s shape without ``axis``, behind the quantile's axis.
    """
    moved = np.moveaxis(np.asarray(a, dtype=float), axis, -1)
    flat = moved.reshape(int(np.prod(moved.shape[:-1])), moved.shape[-1])
    out = np.full((len(q), len(flat)), np.nan)
    nan = np.isnan(flat)
    groups = {}
    for i, key in enumerate(np.packbits(nan, axis=1) if flat.size else []):
        groups.setdefault(key.tobytes(), []).append(i)
    for rows in groups.values():
        cols = ~nan[rows[0]]
        if cols.any():
            out[:, rows] = np.quantile(flat[np.ix_(rows, cols)], q, axis=1)
    return out.reshape((len(q),) + moved.shape[:-1])


def sample_stats(dp, ok):
    """Per sample: the global index (eq. 15: mean of ‖δp‖ over the ok points), the median and the
    95 % quantile of ‖δp‖ over the ok points, and the number of points that are not ok.

    Parameters
    ----------
    dp : ndarray, shape (n, N) [m]
    ok : ndarray, shape (n, N) bool

    Returns
    -------
    DataFrame
        Columns index_m, median_m, p95_m [m], not_ok; one row per sample.

    References
    ----------
    Paty et al. 2021, eq. (14)-(15).
    """
    d = np.where(ok, dp, np.nan)
    with np.errstate(all="ignore"):
        q = nanquantile(d, [0.5, 0.95], axis=1)
        return pd.DataFrame(
            {
                "index_m": np.nanmean(d, axis=1),
                "median_m": q[0],
                "p95_m": q[1],
                "not_ok": (~ok).sum(axis=1),
            }
        )


class Linearisation:
    """First-order propagation of the sensitivities at the nominal parameters θ_0,
    dp(θ) = dp_0 + S (τ(θ) - τ(θ_0)), τ(θ) = θ except 1/E for the moduli, for each candidate
    solution ("slot") of a point: in paper mode every converged 3-cable subset, whose tensions are
    propagated too (t(θ) = t_0 + S_t (τ(θ) - τ(θ_0))) so that the paper's rule (the smallest ‖dp‖
    among the subsets with 0 <= t <= T_a) is applied to the linearised answers: the best subset may
    switch with θ; in physical mode the one equilibrium.

    Parameters
    ----------
    dp0 : array (N, C, 3) [m]
        P*(θ_0) - p of each slot.
    S : array (N, C, 3, k)
        dP*/dθ at θ_0 of each slot for the parameter columns ``columns``.
    valid : array (N, C) bool
        Slots with a regular solution (S finite).
    smooth : array (N,) bool
        The sensitivity module's flag of the nominal answer.
    theta0 : array (len(parameter_names(robot)),)
    m : int
    columns : array (k,) of int
        Columns of θ (``parameters.parameter_names``) that S covers; the others must stay nominal.
    t0, St : arrays (N, C, 3) [N] and (N, C, 3, k), optional
        Tensions of each slot and their sensitivities (paper mode).
    T_a : array (C, 3) [N], optional
        Admissible tensions of each slot's cables.
    """

    def __init__(self, dp0, S, valid, smooth, theta0, m, columns, t0=None, St=None, T_a=None):
        self.theta0 = np.asarray(theta0, dtype=float)
        self.columns = np.asarray(columns, dtype=np.intp)
        self.valid = np.asarray(valid, dtype=bool) & np.isfinite(S).all(axis=(2, 3))
        self.smooth = np.asarray(smooth, dtype=bool)
        self.dp0 = np.where(self.valid[..., None], dp0, 0.0)
        self.is_E = self.columns < m
        # dP/d(1/E) = -E^2 dP/dE (and the same for the tensions)
        self._scale = np.where(self.is_E, -(self.theta0[self.columns] ** 2), 1.0)
        self.S = np.where(self.valid[..., None, None], S * self._scale, 0.0)
        self.has_t = t0 is not None
        if self.has_t:
            self.t0 = np.where(self.valid[..., None], t0, 0.0)
            self.St = np.where(self.valid[..., None, None], St * self._scale, 0.0)
            self.T_a = np.asarray(T_a, dtype=float)
            adm0 = self.valid & (self.t0 >= 0).all(axis=2) & (self.t0 <= self.T_a).all(axis=2)
        else:
            adm0 = self.valid
        self.admissible0 = adm0
        self.ok = adm0.any(axis=1)
        # the nominal answer: the admissible slot of smallest |dp_0| (paper mode's choice)
        self.best = np.argmin(np.where(adm0, np.linalg.norm(self.dp0, axis=2), np.inf), axis=1)

    def tau(self, theta):
        """τ(θ) on the covered columns, shape (n, k)."""
        th = np.atleast_2d(np.asarray(theta, dtype=float))[:, self.columns]
        # 1/θ on the moduli only (an attachment or anchor coordinate may be 0)
        return np.where(self.is_E, 1.0 / np.where(self.is_E, th, 1.0), th)

    def _delta(self, theta):
        th = np.atleast_2d(np.asarray(theta, dtype=float))
        other = np.setdiff1d(np.arange(th.shape[1]), self.columns)
        if other.size and np.abs(th[:, other] - self.theta0[other]).max() > 0:
            raise ValueError("the linearisation does not cover every parameter that varies")
        return self.tau(th) - self.tau(self.theta0)

    def dp(self, theta, engine=None, threads=None):
        """‖dp(θ)‖ (n, N) [m] of the linearised answer; NaN where no slot is admissible
        (``solve.linear_dp``: ``engine`` None or ``"compiled"`` runs the compiled kernel, points in
        parallel; ``"numpy"`` the reference ``models.sensitivity.linear_dp``, same numbers)."""
        delta = self._delta(theta)
        t = (self.t0, self.St, self.T_a) if self.has_t else (None, None, None)
        return linear_dp(self.dp0, self.S, self.valid, delta, *t, engine=engine, threads=threads)

    def shift(self, theta, every_slot=False, engine=None, threads=None):
        """The linearised P*(θ) - p [m] of each point's nominal slot (``best``), (n, N, 3), zero
        where no slot is admissible; with ``every_slot`` that of every slot, (n, N, C, 3), zero
        where the slot is not valid (``solve.linear_positions``; the same engines as ``dp``)."""
        delta = self._delta(theta)
        if every_slot:
            N, C, _, k = self.S.shape
            out = linear_positions(
                self.dp0.reshape(N * C, 3), self.S.reshape(N * C, 3, k), delta, engine=engine, threads=threads
            )
            return out.reshape(len(delta), N, C, 3)
        idx = np.arange(len(self.best))
        dp0 = np.where(self.ok[:, None], self.dp0[idx, self.best], 0.0)
        S = np.where(self.ok[:, None, None], self.S[idx, self.best], 0.0)
        return linear_positions(dp0, S, delta, engine=engine, threads=threads)

    def nominal(self):
        """(dp_0 (N, 3), S (N, 3, k)) of the nominal answer, with S in dP/dθ (not compliance)."""
        idx = np.arange(len(self.best))
        return self.dp0[idx, self.best], self.S[idx, self.best] / self._scale


def linear_stats(lin, theta, batch=64, threads=None, keep=None):
    """``sample_stats`` of the linearised ‖dp‖ for every row of θ, ``batch`` samples at a time (the
    (samples, points) array of 1,000 samples over 63^3 points would take 2 GB).

    Parameters
    ----------
    lin : Linearisation
    theta : array_like, shape (n, len(parameter_names(robot)))
    batch : int
    threads : int, optional
    keep : array_like (N,) bool, optional
        The points the statistics are over (default all; the others, e.g. where the nominal
        robot's cables interfere, ``PoseErrorModel.interfering``, are left out and not counted in
        not_ok).

    Returns
    -------
    DataFrame
        As ``sample_stats``.
    """
    theta = np.atleast_2d(theta)
    parts = []
    for i in range(0, len(theta), batch):
        dp = lin.dp(theta[i : i + batch], threads=threads)
        if keep is not None and not np.all(keep):  # C order: the sums over the points as without keep
            dp = np.ascontiguousarray(dp[:, np.asarray(keep, dtype=bool)])
        parts.append(sample_stats(dp, np.isfinite(dp)))
    return (
        pd.concat(parts, ignore_index=True)
        if parts
        else sample_stats(np.empty((0, 0)), np.empty((0, 0), bool))
    )


#: (sample, point) pairs per batched physical solve of ``PoseErrorModel.solve`` of a suspended point
#: mass (memory ~100 bytes each).
BATCH_POINTS = 2**20


class PoseErrorModel:
    """The pose error of one design at points p when the robot's parameters are θ (module
    docstring): ‖δp‖ of every robot and δφ of a robot solved as a pose (``pose``).

    Parameters
    ----------
    robot : Robot
        The nominal robot (the model that computes the commanded lengths).
    p : array (N, 3) [m]
        Desired positions.
    case : {"uncompensated", "compensated"}
    redundancy : {"paper", "physical"}
        Model of the uncompensated suspended point mass (paper: DEGM_E on the best subset); the
        compensated robot, and every robot solved as a pose, is the physical equilibrium.
    compensation : dict, optional
        ``method`` and ``t_min_N`` of ``compensation.compensate`` (sag-consistent with heavy cables;
        default min_norm, 100 N).
    threads : int, optional
    engine : {"compiled", "numpy", None}
        Engine of every solve (``solve.check_engine``: None is compiled; another value raises
        CdprError); the sensitivities of a pose are the numpy reference's.
    start : {"linear", "desired"}
        Where the full solves of a suspended point mass start Newton: at each sample's linearised
        solution, p + dp_0 + S (τ(θ) - τ(θ_0)) (``Linearisation.shift``: the equilibrium in
        physical mode, every subset's solution in paper mode; the desired point where the nominal
        one is not valid), or at the desired point p. Both converge to the same solutions within
        the solver's tolerance; the linear start takes about half the Newton iterations
        (benchmarks/README.md). A pose starts at the desired pose.
    rotvec : array (N, 3) or (3,) [rad], optional
        Desired orientations of a pose (default identity).
    pose : bool, optional
        Solve as a pose; default every robot but a suspended point mass (True on a suspended point
        mass: the 6-DoF model, whose δφ is 0, a cross-check of the point-mass model).

    Attributes
    ----------
    pose : bool
        Solved as a pose (every robot but a suspended point mass): responses ‖δp‖ and δφ.
    responses : tuple of str
        ``RESPONSES`` of this robot: ("dp",) or ("dp", "dphi").
    """

    def __init__(
        self,
        robot,
        p,
        case="uncompensated",
        redundancy="paper",
        compensation=None,
        threads=None,
        engine=None,
        start="linear",
        rotvec=None,
        pose=None,
    ):
        if start not in STARTS:
            raise CdprError(f"unknown start {start!r}; allowed: {', '.join(STARTS)}")
        if case not in CASES:
            raise ValueError(f"unknown case {case!r}; allowed: {', '.join(CASES)}")
        self.robot = robot
        self.start = start
        self._nominal_sens = self._pose_lin = self._interfering = None
        self._linearisations, self._start_slots = {}, {}
        self.case = case
        self.threads = threads
        self.pose = not robot.suspended_point_mass if pose is None else bool(pose)
        self.responses = RESPONSES if self.pose else RESPONSES[:1]
        c = compensation or {}
        if self.pose:
            self.engine = engine
            self.mode = "physical"
            self.p, self.R = pose_arrays(p, rotvec)
            n = len(self.p)
            self.rotvec = np.zeros((n, 3)) if rotvec is None else np.broadcast_to(rotvec, (n, 3))
            if case == "uncompensated":
                self.L, self.feasible = L_TS(robot, self.p, R=self.R), np.ones(n, dtype=bool)
            else:
                comp = compensate(  # sag-consistent with heavy cables
                    robot,
                    self.p,
                    rotvec=self.rotvec,
                    t_min=c.get("t_min_N", 100.0),
                    method=c.get("method", "min_norm"),
                )
                self.L, self.feasible = comp["L0"], np.asarray(comp["feasible"], dtype=bool)
            return
        self.engine = check_engine(engine, "newton")
        self.p = np.atleast_2d(np.asarray(p, dtype=float))
        n = len(self.p)
        if case == "uncompensated":
            self.mode = redundancy
            self.L = L_TS(robot, self.p)
            self.feasible = np.ones(n, dtype=bool)
        else:
            comp = compensate(
                robot,
                self.p,
                method=c.get("method", "min_norm"),
                t_min=c.get("t_min_N", 100.0),
                engine=self.engine,
            )
            self.mode = "physical"
            self.L = comp["L0"]
            self.feasible = comp["feasible"]
        self._pv = np.ascontiguousarray(self.p[self.feasible])
        self._Lv = np.ascontiguousarray(self.L[self.feasible])

    def _nominal(self):
        """``solve.sensitivities`` of the nominal robot at the feasible points (computed once)."""
        if self._nominal_sens is None:
            run = {"engine": self.engine, "threads": self.threads}
            self._nominal_sens = sensitivities(self.robot, self._pv, redundancy=self.mode, L=self._Lv, **run)
        return self._nominal_sens

    def _starts(self, theta, columns):
        """Newton's starting points [m] of the full solves of θ: (n, N_feasible, 3) in physical
        mode, (n, N_feasible, n_subsets, 3) in paper mode; None (start at p) for ``start``
        "desired" or where no column varies. p + ``Linearisation.shift`` over the varying
        ``columns`` of θ, computed in one pass from the slots' p + dp_0 and S, which are kept."""
        if self.start != "linear" or len(columns) == 0:
            return None
        key = tuple(columns)
        if key not in self._start_slots:
            lin = self.linearise(columns)
            f = self.feasible
            if self.mode == "physical":
                idx = np.arange(len(lin.best))
                dp0 = np.where(lin.ok[:, None], lin.dp0[idx, lin.best], 0.0)[f][:, None]
                S = np.where(lin.ok[:, None, None], lin.S[idx, lin.best], 0.0)[f][:, None]
            else:
                dp0, S = lin.dp0[f], lin.S[f]
            N, C, _, k = S.shape
            base = (self.p[f][:, None] + dp0).reshape(N * C, 3)
            self._start_slots[key] = (lin, base, np.ascontiguousarray(S.reshape(N * C, 3, k)), C)
        lin, base, S, C = self._start_slots[key]
        P0 = linear_positions(base, S, lin._delta(theta), engine=self.engine, threads=self.threads)
        return P0.reshape(len(P0), -1, 3) if self.mode == "physical" else P0.reshape(len(P0), -1, C, 3)

    def solve(self, theta, interference=False):
        """Full solves for parameter vectors θ (n, len(parameter_names(robot))).

        Parameters
        ----------
        theta : array_like, shape (n, len(parameter_names(robot))) [Pa, m, kg]
        interference : bool
            Also say where each sample's robot (its own attachments, anchors, ...) has cables that
            interfere at its solved pose (``analyses.interference.interfering_at``, under the
            commanded lengths for heavy cables): a third array.

        Returns
        -------
        values : dict
            Response (``responses``) -> (n, N): ‖δp‖ [m] under "dp", δφ [rad] under "dphi"; NaN
            where the point is infeasible.
        ok : ndarray, shape (n, N), bool
        interfering : ndarray, shape (n, N), bool
            With ``interference`` only: ok points whose cables interfere at the sample's solved
            pose (all False for a robot not solved as a pose, or a point mass: no interference).
        """
        th = np.atleast_2d(theta)
        n, N = len(th), len(self.p)
        values = {r: np.full((n, N), np.nan) for r in self.responses}
        ok = np.zeros((n, N), dtype=bool)
        hit = np.zeros((n, N), dtype=bool)
        f = self.feasible
        varying = np.flatnonzero((th != parameter_values(self.robot)).any(axis=0))
        if self.pose:  # heavy cables from the linear shift (fewer Newton steps: benchmarks/README.md)
            robots = [robot_with_parameters(self.robot, t) for t in th]
            P0 = self._starts(th, varying) if self.robot.heavy else None
            run = {"engine": self.engine, "threads": self.threads, "L0": self.L[f], "P0": P0}
            results = solve_batch(robots, self.p[f], self.rotvec[f], **run)
            for i, res in enumerate(results):
                res = reached_answer(robots[i], res, engine=self.engine, threads=self.threads)
                ok[i, f] = res["status"] == "ok"
                values["dp"][i, f], values["dphi"][i, f] = res["dp"], res["dphi"]
                if interference and not self.robot.point_mass:
                    P_s = np.where(ok[i, f][:, None], res["P_s"], np.nan)
                    bad = interfering_at(robots[i], P_s, res["rotvec_s"], L0=self.L[f], engine=self.engine)
                    hit[i, f] = ok[i, f] & bad
            return (values, ok, hit) if interference else (values, ok)
        # a suspended point mass: BATCH_POINTS (sample, point) pairs per batched solve (= one by one)
        dp = values["dp"]
        k = max(1, BATCH_POINTS // max(len(self._pv), 1))
        run = {"engine": self.engine, "threads": self.threads, "redundancy": self.mode}
        lengths = {"L": self._Lv} if self.mode == "paper" else {"L0": self._Lv}
        # the linear start covers the columns that vary over θ (Saltelli's rows: all), linearised once per set
        for i in range(0, n, k):
            robots = [robot_with_parameters(self.robot, t) for t in th[i : i + k]]
            P0 = self._starts(th[i : i + k], varying)
            for j, res in enumerate(solve_batch(robots, self._pv, **lengths, **run, P0=P0)):
                dp[i + j, f] = res["dp"]
                ok[i + j, f] = res["status"] == "ok"
        return (values, ok, hit) if interference else (values, ok)

    def interfering(self):
        """The points left out of the statistics (docs/interference.md): where the nominal robot,
        commanded with ``L``, settles at a pose at which its cables interfere (``solve`` of the
        nominal θ with ``interference``; the pose the robot is designed to reach there is not one it
        can be at). Computed once; all False for a robot not solved as a pose or a point mass.

        Returns
        -------
        ndarray, shape (N,), bool
        """
        if self._interfering is None:
            if self.pose and not self.robot.point_mass:
                self._interfering = self.solve(parameter_values(self.robot)[None], interference=True)[2][0]
            else:
                self._interfering = np.zeros(len(self.p), dtype=bool)
        return self._interfering

    def linearise(self, columns=None):
        """The ``Linearisation`` of ‖δp‖ at the nominal parameters for the θ columns ``columns``
        (default all): ``linearisations(columns)["dp"]``.

        Parameters
        ----------
        columns : array_like (k,) of int, optional
            Columns of ``parameters.parameter_names(robot)``.

        Returns
        -------
        Linearisation
        """
        return self.linearisations(columns)["dp"]

    def linearisations(self, columns=None):
        """The first-order propagation of every response at the nominal parameters, computed once
        per set of columns (the full solves' linear start uses the same one).

        A suspended point mass: paper mode every subset (``solve.subset_sensitivities``), physical
        mode the equilibrium (``solve.sensitivities``), by the model's engine. A pose: position
        δp(θ) = δp_0 + S_p (τ(θ) - τ(θ_0)); orientation, the rotation vector of R* R_dᵀ,
        φ(θ) = φ_0 + S_φ (τ(θ) - τ(θ_0)) (first order in the base-frame rotation increment, for a
        small φ_0), δφ = ‖φ‖ (``sensitivity.sensitivities_at``, by the model's engine).

        Parameters
        ----------
        columns : array_like (k,) of int, optional
            Columns of ``parameters.parameter_names(robot)`` (default all; the study's drivers,
            ``driver_columns``).

        Returns
        -------
        dict
            Response (``responses``) -> Linearisation over θ (n, len(parameter_names(robot)))
            [Pa, m, kg]: its ``dp`` gives ‖δp‖ [m], resp. δφ [rad].
        """
        n_theta = len(parameter_names(self.robot))
        cols = np.arange(n_theta) if columns is None else np.asarray(columns, dtype=np.intp)
        key = tuple(int(c) for c in cols)
        if key not in self._linearisations:
            if self.pose:
                self._linearisations[key] = self._linearise_pose(cols)
            else:
                self._linearisations[key] = {"dp": self._linearise(cols)}
        return self._linearisations[key]

    def _linearise(self, cols):
        m = self.robot.m
        N = len(self.p)
        run = {"engine": self.engine, "threads": self.threads}
        nom = self._nominal()
        smooth = np.zeros(N, dtype=bool)
        smooth[self.feasible] = nom["smooth"]
        extra = {}
        if self.mode == "paper":
            sub = subset_sensitivities(self.robot, self._pv, L=self._Lv, columns=cols, **run)
            C = sub["P"].shape[1]
            P, valid, S = sub["P"], sub["converged"], sub["S"]
            t0 = np.zeros((N, C, 3))
            St = np.full((N, C, 3, len(cols)), np.nan)
            t0[self.feasible], St[self.feasible] = sub["t"], sub["St"]
            extra = {"t0": t0, "St": St, "T_a": sub["T_a"]}
        else:
            C = 1
            P = nom["P_s"][:, None]
            valid = (nom["status"] == "ok")[:, None]
            S = nom["S"][:, None][..., cols]
        dp0 = np.zeros((N, C, 3))
        Sall = np.full((N, C, 3, len(cols)), np.nan)
        ok = np.zeros((N, C), dtype=bool)
        dp0[self.feasible] = P - self._pv[:, None]
        Sall[self.feasible] = S
        ok[self.feasible] = valid
        return Linearisation(dp0, Sall, ok, smooth, parameter_values(self.robot), m, cols, **extra)

    def nominal_pose(self):
        """The nominal robot's equilibria at the desired poses and their sensitivities (a pose
        model only; computed once).

        Returns
        -------
        dict
            P_s (N, 3) [m], R_s (N, 3, 3) [-]; S = dx*/dθ (N, 6, len(parameter_names(robot))),
            x = (p, φ) [m, rad per unit of θ]; smooth (N,) bool; status (N,) ("infeasible" where the
            compensated lengths do not exist); theta0 (len(θ),) the nominal θ [Pa, m, kg]. NaN rows
            where the pose is infeasible or not ok.
        """
        if self._pose_lin is None:
            N, f = len(self.p), self.feasible
            run = {"engine": self.engine, "threads": self.threads}
            res = solve(self.robot, self.p[f], self.rotvec[f], redundancy="physical", **run, L0=self.L[f])
            # the model's engine: the numpy and compiled twins take dF/dθ by the same exact formulas
            sens = sensitivities_at(self.robot, res, parameter_names(self.robot), **run)
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
            th0 = parameter_values(self.robot)
            self._pose_lin = {
                "P_s": P_s,
                "R_s": R_s,
                "S": S,
                "smooth": smooth,
                "status": status,
                "theta0": th0,
            }
        return self._pose_lin

    def _linearise_pose(self, cols):
        m = self.robot.m
        lin = self.nominal_pose()
        ok = (lin["status"] == "ok")[:, None]
        S = lin["S"][..., cols]
        with np.errstate(invalid="ignore"):
            phi0 = np.where(
                ok, rotvec_of(np.where(ok[..., None], lin["R_s"], np.eye(3)) @ np.swapaxes(self.R, 1, 2)), 0.0
            )
        th0 = lin["theta0"]
        dp0 = np.where(ok, lin["P_s"] - self.p, 0.0)
        pos = Linearisation(dp0[:, None], S[:, None, :3], ok, lin["smooth"], th0, m, cols)
        rot = Linearisation(phi0[:, None], S[:, None, 3:], ok, lin["smooth"], th0, m, cols)
        return {"dp": pos, "dphi": rot}


def sobol_analysis(evaluate, drivers_, robot, base_samples, seed, outputs, groups=False, source="<study>"):
    """First-order and total Sobol indices of the model outputs with SALib (Saltelli's sampling
    scheme on a scrambled Sobol' sequence, Sobol analysis with bootstrap confidence intervals).

    Parameters
    ----------
    evaluate : callable
        θ (n, len(parameter_names(robot))) -> Y (n, len(outputs)).
    drivers_ : list of Driver
    robot : Robot
    base_samples : int
        N of Saltelli's scheme (a power of 2); the model runs N (D + 2) times, D the number of
        drivers (or of groups).
    seed : int
        Seed of the scrambling and of the bootstrap.
    outputs : list of str
        Names of Y's columns.
    groups : bool
        Indices per parameter group (``Driver.group``) instead of per driver.
    source : str
        File named by ``check_samples``.

    Returns
    -------
    indices : DataFrame
        Columns output, level, name, S1, S1_conf, ST, ST_conf.
    Y : ndarray, shape (N (D + 2), len(outputs))
    theta : ndarray, shape (N (D + 2), len(parameter_names(robot)))

    References
    ----------
    Saltelli et al. 2010; SALib (Herman and Usher 2017).
    """
    from SALib.analyze import sobol as sobol_analyze  # lazy: SALib loads scipy.stats, 0.4 s of start-up
    from SALib.sample import sobol as sobol_sample  # lazy: the Sobol jobs only

    D = len(drivers_)
    problem = {"num_vars": D, "names": [d.name for d in drivers_], "bounds": [[0.0, 1.0]] * D}
    if groups:
        problem["groups"] = [d.group for d in drivers_]
    U = sobol_sample.sample(problem, base_samples, calc_second_order=False, scramble=True, seed=seed)
    theta = parameter_samples(robot, drivers_, U)
    check_samples(robot, theta, source)
    Y = np.asarray(evaluate(theta), dtype=float).reshape(len(theta), len(outputs))
    names = list(dict.fromkeys(problem["groups"])) if groups else problem["names"]
    rows = []
    for j, out in enumerate(outputs):
        Si = sobol_analyze.analyze(
            problem, Y[:, j], calc_second_order=False, conf_level=0.95, seed=seed, print_to_console=False
        )
        for k, name in enumerate(names):
            rows.append(
                {
                    "output": out,
                    "level": "group" if groups else "parameter",
                    "name": name,
                    "S1": float(Si["S1"][k]),
                    "S1_conf": float(Si["S1_conf"][k]),
                    "ST": float(Si["ST"][k]),
                    "ST_conf": float(Si["ST_conf"][k]),
                }
            )
    return pd.DataFrame(rows), Y, theta


def local_contributions(lin, drivers_, projected):
    """First-order share of each driver in the spread of the pose error at every point.

    Driver k moves the pose by δ_k = sum over its columns c of S_c (x_c - θ_0,c), x its value, so
    its contribution is E[(n . δ_k)^2] with n = dp_0/|dp_0| (``projected``: the variance of ‖δp‖
    to first order, where dp_0 is not small) or E[|δ_k|^2] (the mean square error, for the
    compensated robot whose dp_0 = 0). Moments about the nominal values; S of the nominal answer.

    Parameters
    ----------
    lin : Linearisation
        Covering every driver's columns.
    drivers_ : list of Driver
    projected : bool

    Returns
    -------
    contributions : ndarray, shape (N, n_drivers) [m^2]
        NaN where the point is not ok.
    """
    dp0, S = lin.nominal()
    th0 = lin.theta0
    pos = {int(c): j for j, c in enumerate(lin.columns)}
    if projected:
        n = dp0 / np.linalg.norm(dp0, axis=1, keepdims=True)
        S = np.einsum("na,nak->nk", n, S)[:, None, :]
    out = np.empty((len(S), len(drivers_)))
    for k, dr in enumerate(drivers_):
        mean, var = dr.dist.moments()
        cols = [pos[c] for c in dr.columns]
        a = S[:, :, cols].sum(axis=2)  # dδ/dx
        if dr.offset:
            # δ = a x: E[δ^2] = |a|^2 (var + mean^2)
            out[:, k] = (a**2).sum(axis=1) * (var + mean**2)
        else:
            # δ = a x - b, b = sum_c S_c θ_0,c: E|δ|^2 = |a|^2 E[x^2] - 2 a.b mean + |b|^2
            b = (S[:, :, cols] * th0[list(dr.columns)]).sum(axis=2)
            out[:, k] = (
                (a**2).sum(axis=1) * (var + mean**2) - 2 * (a * b).sum(axis=1) * mean + (b**2).sum(axis=1)
            )
    return np.where(lin.ok[:, None], np.maximum(out, 0.0), np.nan)


def driver_columns(drivers_):
    """The parameter columns the drivers set, sorted.

    Parameters
    ----------
    drivers_ : list of Driver

    Returns
    -------
    columns : ndarray of int
    """
    return np.array(sorted({c for d in drivers_ for c in d.columns}), dtype=np.intp)
