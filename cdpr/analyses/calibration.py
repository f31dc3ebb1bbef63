"""Calibration: a real robot's parameters θ from measured poses, what the data cannot identify, and
where to measure.

The robot is commanded rest lengths L0 (winch exit to platform, the ``physical`` mode of
``cdpr.models.equilibrium``) and settles at the equilibrium P*(θ, L0); a tracker measures the pose
y. The estimate is the maximum a posteriori (MAP) of θ under a Gaussian prior around the nominal
robot (``map_residual``): a weakly identified parameter stays near its prior instead of running away.
The Jacobian of the residual is exact, from the implicit-function sensitivities dP*/dθ
(``cdpr.models.sensitivity``), with the encoder offsets' column dP*/do = J^-1 dF/dL0
(``offset_sensitivities``); no finite differences inside the fit.

Models (``MODELS``): ``exact`` is the robot file as it is (pulley kinematics and Hooke elasticity);
``standard`` is the straight-line model, every pulley a fixed point (h = r_p = 0) and the cables
rigid, realised as the physical equilibrium with E multiplied by ``STANDARD_STIFFENING`` (the
stretch drops below a micrometre; the redundant robot still settles on its taut cables).

Winches: on a robot file with ``winch:`` (every cable) the data's lengths are the rest lengths the
controller was asked for; it turns each drum to the angle of the model that neglects the exit
point's motion (Métillon 2022 eq. 32), so the drum realises L0 = W(L_cmd) =
``drive.realised_rest_lengths`` (the length error δl of eq. 31). The exact model maps every
command through W before the equilibrium and its Jacobian carries the chain rule (dL0/dL_cmd on the
offsets, dL0/dd on the dead lengths); the standard model knows no drum (``without_winches``).

Encoder data (``L_enc1..L_encm`` = rest length + an unknown offset per cable): with elastic cables
and no measured tension every set of lengths has an equilibrium for every θ, so a sample without a
measured pose gives no equation in the exact model; such samples are counted and left out, and
with none left the fit refuses with one line naming the way out (measure poses, or ``--model
standard`` for a rigid self-calibration of a point mass, ``self_calibrate_standard``, whose gauge
it reports). Measured tensions (``t1_N..tm_N``, point mass and 6-DoF platform alike) add m rows
(t_meas - t(θ, L0)) / σ_t per sample, which make encoder-only samples equations: the tensions fix
the pose through the balance, Hooke's law then the rest lengths (``tension_sensitivities``,
``tension_sensitivities6``).

Identifiability (``identifiability``): singular values of the measurement rows scaled by the
prior (rows / σ, columns × prior sd), the rank (> 1e-9 s_max), the condition number, the weakest
directions in words, and each parameter's posterior-to-prior sd ratio: identified (≤ 0.3), partly
(≤ 0.8) or prior-dominated (> 0.8).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 3-5, 10-14).
Tarantola, A. (2005). Inverse Problem Theory and Methods for Model Parameter Estimation, SIAM,
section 3.2 (least squares with a Gaussian prior, posterior covariance).
Atkinson, A. C., Donev, A. N. (1992). Optimum Experimental Designs, Oxford, ch. 11 (D-optimality)
and 15 (exchange algorithms).
"""

from __future__ import annotations

import dataclasses
import datetime
import math
from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from scipy.optimize import least_squares

from cdpr.analyses.workspace import check_box, grid_points
from cdpr.errors import CdprError, ConfigError
from cdpr.models.distribution6 import compensated_lengths
from cdpr.models.drive import commanded_for, has_winches, realised_rest_lengths
from cdpr.models.equilibrium6 import L_TS_pose, pose_arrays
from cdpr.models.inverse import L_TS
from cdpr.models.platform import rotation_matrix, rotvec_of, skew
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.sensitivity import (
    COND_MAX,
    T_TOL,
    cable_partials,
    implicit_solve,
    physical_jacobian_terms,
)
from cdpr.models.sensitivity6 import rest_length_sensitivities, tension_partials6
from cdpr.parameters import (
    CALIBRATION_GROUPS,
    calibrated_robot,
    calibration_groups,
    calibration_names,
    calibration_values,
    is_spatial,
    parameter_values,
    robot_size,
    robot_with_parameters,
    robot_with_parameters6,
    select_groups,
)
from cdpr.robot import WINCH_KEYS, with_pulleys
from cdpr.solve import check_engine, sensitivities, solve_spatial_any
from cdpr.solve import spatial_sensitivities as solve_spatial_sensitivities
from cdpr.units import quantity

#: How the candidate and simulated poses are commanded: standard lengths L_TS (the point mass's only
#: choice) or, for a 6-DoF platform, the compensated rest lengths of the minimum-norm tension
#: distribution (``distribution6.compensated_lengths``; a fully constrained robot needs them).
COMMANDS = ("standard", "compensated")
#: Model of the robot during the fit (the command line's choices).
MODELS = ("exact", "standard")
#: Also ``rigid``: pulley kinematics with rigid cables (the calibration study's middle model).
ALL_MODELS = ("standard", "rigid", "exact")
#: Factor on E that makes the standard model's cables rigid (stretch of a few micrometres).
STANDARD_STIFFENING = 1e3
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
#: Default tracker noise [m] when the data have no ``sigma_m`` column.
SIGMA_DEFAULT = 0.2e-3
#: Default orientation noise [rad] of a 6-DoF tracker when the data have no ``sigma_rad`` column.
SIGMA_RAD_DEFAULT = 1e-3
#: Default tension-sensor noise [N] when the data have tensions but no ``sigma_N`` column.
SIGMA_T_DEFAULT = 5.0
#: Rank threshold: singular values > RANK_TOL s_max count.
RANK_TOL = 1e-9
#: Posterior-to-prior sd ratios of "identified" and "partly".
IDENTIFIED, PARTLY = 0.3, 0.8
#: Normalised residual above which a sample counts as an outlier of the robust loss.
OUTLIER = 3.0
#: Status of a sample whose commanded length the drum cannot pay out (a robot with winches).
DRUM_RANGE = "outside the drum's range"


# --- priors ---------------------------------------------------------------------------------------
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
    out = dict(DEFAULT_PRIORS)
    if not text:
        return out
    for item in str(text).split(","):
        if "=" not in item:
            raise CdprError(f"{source}: expected GROUP=SD, got {item!r}; e.g. anchors=5mm,moduli=20%")
        g, v = (s.strip() for s in item.split("=", 1))
        if g not in CALIBRATION_GROUPS:
            raise CdprError(f"{source}: unknown group {g!r}; allowed: {', '.join(CALIBRATION_GROUPS)}")
        if g in RELATIVE:
            try:
                sd = float(v[:-1]) / 100.0 if v.endswith("%") else float(v)
            except ValueError:
                raise CdprError(f"{source}: {g}={v!r} is not a percentage (e.g. {g}=20%)") from None
        else:
            sd = quantity(v, "m", source, g)
        if not (math.isfinite(sd) and sd > 0):
            raise CdprError(f"{source}: the prior sd of {g} must be > 0, got {v!r}")
        if g in RELATIVE and sd >= 1.0:
            raise CdprError(
                f"{source}: the prior sd of {g} is relative and must be below 100 %, got {v!r} "
                f"({sd:.0%}); give a percentage, e.g. {g}=20%"
            )
        if estimate is not None and g not in estimate:
            raise CdprError(
                f"{source}: a prior for {g}, which is not estimated (--estimate {','.join(estimate)}); "
                f"remove it or add {g} to --estimate"
            )
        out[g] = sd
    return out


def prior_sd(robot, index, priors):
    """Absolute prior sd of the calibration parameters ``index`` (relative groups × |nominal|).

    Parameters
    ----------
    robot : Robot
    index : ndarray of int
        Into ``calibration_names(robot.m)``.
    priors : dict
        ``parse_priors``.

    Returns
    -------
    sd : ndarray, shape (len(index),) [Pa, m, kg]
    """
    groups, _ = calibration_groups(robot.m, is_spatial(robot))
    nominal = calibration_values(robot)
    return np.array(
        [priors[groups[k]] * abs(nominal[k]) if groups[k] in RELATIVE else priors[groups[k]] for k in index]
    )


# --- data -----------------------------------------------------------------------------------------
@dataclasses.dataclass
class Data:
    """Calibration samples (``read_data``).

    sample (N,) labels; L (N, m) [m] commanded rest lengths, or encoder readings when ``encoder``;
    pose (N, 3) [m], NaN where not measured; sigma (N,) [m]; tension (N, m) [N], NaN where not
    measured, and sigma_t (N,) [N]; source: the file. A 6-DoF platform's samples also carry rotvec
    (N, 3) [rad], the measured orientation's rotation vector (active, base frame), NaN where not
    measured, and sigma_rad (N,) [rad]; a point mass's rotvec stays NaN."""

    sample: np.ndarray
    L: np.ndarray
    pose: np.ndarray
    sigma: np.ndarray
    encoder: bool
    source: str
    tension: np.ndarray = None
    sigma_t: np.ndarray = None
    rotvec: np.ndarray = None
    sigma_rad: np.ndarray = None

    def __post_init__(self):
        n, m = self.L.shape
        if self.tension is None:
            self.tension = np.full((n, m), np.nan)
        if self.sigma_t is None:
            self.sigma_t = np.full(n, SIGMA_T_DEFAULT)
        if self.rotvec is None:
            self.rotvec = np.full((n, 3), np.nan)
        if self.sigma_rad is None:
            self.sigma_rad = np.full(n, SIGMA_RAD_DEFAULT)

    @property
    def has_orientation(self):
        return np.isfinite(self.rotvec).all(axis=1)

    @property
    def has_pose(self):
        return np.isfinite(self.pose).all(axis=1)

    @property
    def has_tension(self):
        return np.isfinite(self.tension).all(axis=1)

    def subset(self, idx):
        return dataclasses.replace(
            self,
            sample=self.sample[idx],
            L=self.L[idx],
            pose=self.pose[idx],
            sigma=self.sigma[idx],
            tension=self.tension[idx],
            sigma_t=self.sigma_t[idx],
            rotvec=self.rotvec[idx],
            sigma_rad=self.sigma_rad[idx],
        )


POSE = ["x_m", "y_m", "z_m"]
ORIENTATION = ["rx_rad", "ry_rad", "rz_rad"]


def data_columns(m, encoder=False, spatial=False):
    """Columns of a calibration table for m cables: sample, L1..Lm (or L_enc1..L_encm), x_m, y_m,
    z_m, and for a 6-DoF platform (``spatial``) rx_rad, ry_rad, rz_rad; optional sigma_m (and
    sigma_rad), tensions t1_N..tm_N and sigma_N."""
    lengths = [f"L_enc{i}" for i in range(1, m + 1)] if encoder else [f"L{i}" for i in range(1, m + 1)]
    return ["sample", *lengths, *POSE, *(ORIENTATION if spatial else [])]


def read_data(path, robot):
    """Read and check a calibration CSV (docs/calibration.md) for ``robot``.

    Parameters
    ----------
    path : str or Path
    robot : Robot
        Its cable count fixes the length columns.

    Returns
    -------
    Data

    Raises
    ------
    ConfigError
        One line naming the file, the column and what is allowed: missing or extra columns, a
        length column count that does not match the robot, NaN, non-finite or non-positive
        lengths, half-measured poses, sigma <= 0, orientation columns on a point-mass robot; on a
        6-DoF platform a pose needs all six of x_m, y_m, z_m, rx_rad, ry_rad, rz_rad; tensions
        t1_N..tm_N all or none, finite and >= 0, sigma_N > 0 (every robot).
    """
    src = str(path)
    try:
        df = pd.read_csv(path)
    except FileNotFoundError:
        raise ConfigError(src, None, "the data file does not exist") from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ConfigError(src, None, f"cannot read it as CSV ({str(exc).splitlines()[0]})") from None
    m = robot.m
    cols = list(df.columns)
    enc = any(c.startswith("L_enc") for c in cols)
    plain = [c for c in cols if c.startswith("L") and not c.startswith("L_enc")]
    if enc and plain:
        raise ConfigError(
            src, plain[0], "give commanded lengths L1..Lm or encoder readings L_enc1..L_encm, not both"
        )
    prefix = "L_enc" if enc else "L"
    lengths = [c for c in cols if c.startswith(prefix) and c[len(prefix) :].isdigit()]
    if len(lengths) != m and lengths:
        raise ConfigError(
            src,
            ",".join(lengths),
            f"{len(lengths)} length columns but robot {robot.name} has {m} cables; allowed: {prefix}1..{prefix}{m}",
        )
    spatial = is_spatial(robot)
    for c in (o for o in ORIENTATION if o in cols and not spatial):
        raise ConfigError(
            src, c, f"orientation columns are for a 6-DoF platform; robot {robot.name} is a point mass"
        )
    if spatial:
        return _read_data6(df, src, robot, enc, cols)
    need = data_columns(m, enc)
    missing = [c for c in need if c not in cols]
    if missing:
        raise ConfigError(src, missing[0], f"missing column; a calibration table needs {', '.join(need)}")
    Tcols = [f"t{i}_N" for i in range(1, m + 1)]
    allowed = set(need) | {"sigma_m", "sigma_N"} | set(Tcols)
    extra = [c for c in cols if c not in allowed]
    if extra:
        raise ConfigError(
            src, extra[0], f"unknown column; allowed: {', '.join(need)}, sigma_m, t1_N..t{m}_N, sigma_N"
        )
    given = _tension_names(cols, src, m)
    if len(df) == 0:
        raise ConfigError(src, None, "no samples")
    Lcols = [f"{prefix}{i}" for i in range(1, m + 1)]
    L = _lengths(df, Lcols, src)
    pose = _numbers(df, POSE, src)
    half = np.isfinite(pose).any(axis=1) & ~np.isfinite(pose).all(axis=1)
    if half.any() or np.isinf(pose).any():
        r = int(np.flatnonzero(half | np.isinf(pose).any(axis=1))[0])
        raise ConfigError(
            src, "x_m,y_m,z_m", f"row {r + 1}: a pose needs all three finite coordinates (or none)"
        )
    nan_pose = ~np.isfinite(pose).all(axis=1)
    if nan_pose.any() and not enc and not given:
        r = int(np.flatnonzero(nan_pose)[0])
        raise ConfigError(
            src,
            "x_m,y_m,z_m",
            f"row {r + 1}: no pose; only encoder data (L_enc1..) or tension data (t1_N..) may leave the pose empty",
        )
    if "sigma_m" in cols:
        sigma = _numbers(df, ["sigma_m"], src)[:, 0]
        bad = ~(np.isfinite(sigma) & (sigma > 0))
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise ConfigError(
                src, "sigma_m", f"row {r + 1}: {float(sigma[r])!r}; sigma_m must be finite and > 0 [m]"
            )
    else:
        sigma = np.full(len(df), SIGMA_DEFAULT)
    tension, sigma_t = _tensions(df, src, m, given)
    sample = df["sample"].astype(str).to_numpy()
    return Data(
        sample=sample, L=L, pose=pose, sigma=sigma, encoder=enc, source=src, tension=tension, sigma_t=sigma_t
    )


def _read_data6(df, src, robot, enc, cols):
    """``read_data`` for a 6-DoF platform: positions and orientations (rotation vectors) measured
    together, optional sigma_m [m] and sigma_rad [rad]."""
    m = robot.m
    need = data_columns(m, enc, spatial=True)
    missing = [c for c in need if c not in cols]
    if missing:
        raise ConfigError(
            src,
            missing[0],
            f"missing column; robot {robot.name} has a 6-DoF platform, a calibration table needs {', '.join(need)}",
        )
    Tcols = [f"t{i}_N" for i in range(1, m + 1)]
    extra = [c for c in cols if c not in set(need) | {"sigma_m", "sigma_rad", "sigma_N"} | set(Tcols)]
    if extra:
        raise ConfigError(
            src,
            extra[0],
            f"unknown column; allowed: {', '.join(need)}, sigma_m, sigma_rad, t1_N..t{m}_N, sigma_N",
        )
    given = _tension_names(cols, src, m)
    if len(df) == 0:
        raise ConfigError(src, None, "no samples")
    Lcols = [f"{'L_enc' if enc else 'L'}{i}" for i in range(1, m + 1)]
    L = _lengths(df, Lcols, src)
    six = _numbers(df, POSE + ORIENTATION, src)
    fin = np.isfinite(six)
    bad = (fin.any(axis=1) & ~fin.all(axis=1)) | np.isinf(six).any(axis=1)
    if bad.any():
        r = int(np.flatnonzero(bad)[0])
        col = (POSE + ORIENTATION)[int(np.flatnonzero(~fin[r])[0])]
        raise ConfigError(
            src, col, f"row {r + 1}: a 6-DoF pose needs all six finite values x_m..rz_rad (or none)"
        )
    if not fin.all(axis=1).all() and not enc and not given:
        r = int(np.flatnonzero(~fin.all(axis=1))[0])
        raise ConfigError(
            src,
            "x_m",
            f"row {r + 1}: no pose; only encoder data (L_enc1..) or tension data (t1_N..) may leave the pose empty",
        )
    sig = {}
    for c, default, unit in (("sigma_m", SIGMA_DEFAULT, "m"), ("sigma_rad", SIGMA_RAD_DEFAULT, "rad")):
        if c in cols:
            v = _numbers(df, [c], src)[:, 0]
            bad = ~(np.isfinite(v) & (v > 0))
            if bad.any():
                r = int(np.flatnonzero(bad)[0])
                raise ConfigError(
                    src, c, f"row {r + 1}: {float(v[r])!r}; {c} must be finite and > 0 [{unit}]"
                )
            sig[c] = v
        else:
            sig[c] = np.full(len(df), default)
    tension, sigma_t = _tensions(df, src, m, given)
    return Data(
        sample=df["sample"].astype(str).to_numpy(),
        L=L,
        pose=six[:, :3],
        sigma=sig["sigma_m"],
        encoder=enc,
        source=src,
        tension=tension,
        sigma_t=sigma_t,
        rotvec=six[:, 3:],
        sigma_rad=sig["sigma_rad"],
    )


def _tension_names(cols, src, m):
    """The tension columns t1_N..tm_N of a calibration table, all of them or none (an empty list);
    ConfigError when only some are there or sigma_N comes without them."""
    Tcols = [f"t{i}_N" for i in range(1, m + 1)]
    given = [c for c in Tcols if c in cols]
    if given and len(given) != m:
        missing_t = [c for c in Tcols if c not in cols]
        raise ConfigError(src, missing_t[0], f"tensions need all of t1_N..t{m}_N")
    if "sigma_N" in cols and not given:
        raise ConfigError(src, "sigma_N", f"the tension noise needs the tension columns t1_N..t{m}_N")
    return given


def _tensions(df, src, m, given):
    """The measured tensions (n, m) [N] (NaN rows where not measured) and their noise sd sigma_N
    (n,) [N] (``SIGMA_T_DEFAULT`` without the column) of the tension columns ``given``
    (``_tension_names``); ConfigError naming the row where the tensions are half given, negative or
    not finite, or sigma_N is not finite and > 0."""
    tension = np.full((len(df), m), np.nan)
    sigma_t = np.full(len(df), SIGMA_T_DEFAULT)
    if not given:
        return tension, sigma_t
    tension = _numbers(df, given, src)
    fin = np.isfinite(tension)
    half = fin.any(axis=1) & ~fin.all(axis=1)
    neg = (tension < 0).any(axis=1) | np.isinf(tension).any(axis=1)
    if (half | neg).any():
        r = int(np.flatnonzero(half | neg)[0])
        raise ConfigError(
            src, ",".join(given), f"row {r + 1}: tensions must be all finite and >= 0 [N] (or all empty)"
        )
    if "sigma_N" in df.columns:
        sigma_t = _numbers(df, ["sigma_N"], src)[:, 0]
        bad = fin.all(axis=1) & ~(np.isfinite(sigma_t) & (sigma_t > 0))
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise ConfigError(src, "sigma_N", f"row {r + 1}: sigma_N must be finite and > 0 [N]")
    return tension, sigma_t


def _lengths(df, cols, src):
    """The length columns ``cols`` of a calibration table as floats (n, m) [m]; ConfigError naming
    the column and the first row whose value is not finite and > 0."""
    L = _numbers(df, cols, src)
    for j, c in enumerate(cols):
        bad = ~np.isfinite(L[:, j]) | (L[:, j] <= 0)
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise ConfigError(src, c, f"row {r + 1}: {float(L[r, j])!r}; lengths must be finite and > 0 [m]")
    return L


def _numbers(df, cols, src):
    out = np.empty((len(df), len(cols)))
    for j, c in enumerate(cols):
        v = pd.to_numeric(df[c], errors="coerce").to_numpy(dtype=float)
        text = df[c].notna().to_numpy() & np.isnan(v)
        if text.any():
            r = int(np.flatnonzero(text)[0])
            raise ConfigError(src, c, f"row {r + 1}: {df[c].iloc[r]!r} is not a number")
        out[:, j] = v
    return out


def write_data(path, data, robot):
    """Write ``data`` as a calibration CSV (the format ``read_data`` reads)."""
    m = robot.m
    prefix = "L_enc" if data.encoder else "L"
    df = pd.DataFrame({"sample": data.sample})
    for i in range(m):
        df[f"{prefix}{i + 1}"] = data.L[:, i]
    for j, c in enumerate(POSE):
        df[c] = data.pose[:, j]
    if is_spatial(robot):
        for j, c in enumerate(ORIENTATION):
            df[c] = data.rotvec[:, j]
    df["sigma_m"] = data.sigma
    if is_spatial(robot):
        df["sigma_rad"] = data.sigma_rad
    if np.isfinite(data.tension).any():
        for i in range(m):
            df[f"t{i + 1}_N"] = data.tension[:, i]
        df["sigma_N"] = data.sigma_t
    df.to_csv(path, index=False, float_format="%.17g")


# --- the model ------------------------------------------------------------------------------------
def model_robot(robot, model):
    """The robot the fit moves: ``exact`` the robot itself, ``standard`` fixed pulleys and rigid cables.

    Parameters
    ----------
    robot : Robot
    model : {"exact", "standard", "rigid"}
        ``rigid``: the robot's pulleys, rigid cables.

    Returns
    -------
    Robot
    """
    if model not in ALL_MODELS:
        raise CdprError(f"unknown model {model!r}; allowed: {', '.join(MODELS)}")
    if model == "exact":
        return robot
    rigid = robot if model == "rigid" else without_winches(with_pulleys(robot, kind="fixed", h=0.0, r_p=0.0))
    th = parameter_values(rigid)
    th[: robot.m] *= STANDARD_STIFFENING
    return robot_with_parameters(rigid, th)


def without_winches(robot):
    """The robot with its winches removed: the commanded lengths are then the rest lengths (the
    standard model knows no drum)."""
    if all(w is None for w in robot.winches):
        return robot
    return dataclasses.replace(robot, cables=tuple(dataclasses.replace(c, winch=None) for c in robot.cables))


def realised_lengths(robot, L_cmd):
    """The rest lengths ``robot`` realises under the commanded lengths L_cmd (N, m) [m]: L_cmd itself
    without winches, ``drive.realised_rest_lengths`` with them (the robot file's ``winch:``; NaN
    where the drum cannot pay the length out)."""
    if not has_winches(robot):
        return np.asarray(L_cmd, dtype=float)
    return realised_rest_lengths(robot, L_cmd)[0]


def executed_lengths(model, actual):
    """The map from the rest lengths a compensating ``model`` wants to those the ``actual`` robot
    realises: a model with winches asks the no-winch controller for ``drive.commanded_for`` its
    wanted lengths (it knows the drums), a model without takes its rest lengths as the commands;
    the actual robot's drums then pay out ``realised_lengths``. None when neither has winches (the
    identity)."""
    if not (has_winches(model) or has_winches(actual)):
        return None

    def execute(L0):
        L_cmd = commanded_for(model, L0) if has_winches(model) else L0
        return realised_lengths(actual, L_cmd)

    return execute


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
        Estimated parameters, into ``calibration_names(robot.m)``.
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
        start = np.where(data.has_pose[:, None], data.pose, _centre(rob))
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


# --- 6-DoF platforms ------------------------------------------------------------------------------
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


def smooth6(hooke, cond):
    """Where a 6-DoF equilibrium is differentiable: no cable's Hooke tension within ``T_TOL`` of 0
    (the taut set would change) and a condition number of dF6/dx below ``COND_MAX``."""
    return (np.abs(hooke) > T_TOL).all(axis=1) & (cond < COND_MAX)


class Problem6:
    """``Problem`` for a rigid 6-DoF platform: six rows per sample with a measured pose (position /
    σ_m, orientation error / σ_rad, ``map_residual6``), m tension rows (t_meas - t(θ, L0)) / σ_t per
    sample with measured tensions (``tension_sensitivities6``), then the prior rows; the exact
    Jacobian from ``sensitivity6.spatial_sensitivities`` (implicit function) and, for the encoder
    offsets, ``sensitivity6.rest_length_sensitivities`` (dx*/do_i = -dx*/dL0_i). A sample without a
    measured pose is solved from ``_centre`` at the identity orientation. On a robot file with
    ``winch:`` the commanded lengths go through the drums (``drive.realised_rest_lengths``) with
    the chain rule of ``Problem.evaluate`` on the offsets and dead lengths. The solve and the
    sensitivities by ``engine`` (``solve.spatial_sensitivities``), the numpy reference by default:
    the compiled twin (analytic dF6/dθ) changes the tracked CoGiRo tables (the misfit models' fits
    move; the exact model's in the 4th digit), so the study stays on numpy.

    Parameters
    ----------
    robot : Robot
        Nominal robot (the prior mean), in the chosen model.
    data : Data
        Samples with a measured pose (position and orientation) or measured tensions.
    index : ndarray of int
        Into ``calibration_names(robot.m, spatial=True)``.
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
        self.nr = robot_size(self.m, True)
        self.theta0 = calibration_values(robot)
        #: a robot file with ``winch:``: the commanded lengths are mapped through the drums
        self.winch = has_winches(robot)
        names = calibration_names(self.m, True)
        self._cols6 = self.index[self.index < self.nr]
        self._names6 = [names[k] for k in self._cols6]
        self._cache = None
        pose = np.flatnonzero(data.has_pose & data.has_orientation)
        tens = np.flatnonzero(data.has_tension)
        #: the sample of every measurement row
        self.row_sample = np.concatenate([np.repeat(pose, 6), np.repeat(tens, self.m)]).astype(np.intp)
        self._pose, self._tens = pose, tens
        self._R = rotation_matrix(np.nan_to_num(data.rotvec))

    def theta(self, z):
        th = self.theta0.copy()
        th[self.index] += self.sd * np.asarray(z, dtype=float)
        return th

    def evaluate(self, z):
        """Solve at z: P* (n, 3), R* (n, 3, 3), status, smooth (n,), dx*/dθ_free (n, 6, k); with
        tension data also the tensions t (n, m) [N] and dt/dθ_free (n, m, k)."""
        key = np.asarray(z, float).tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        data, nr, m = self.data, self.nr, self.m
        th = self.theta(z)
        rob = robot_with_parameters6(self.robot, th[:nr])
        L0 = data.L - th[nr:]
        w_L = w_d = None
        if self.winch:  # the commanded lengths go through the drums (drive.realised_rest_lengths)
            L0, w_L, w_d = realised_rest_lengths(rob, L0)
        hp = data.has_pose & data.has_orientation
        start = np.where(hp[:, None], data.pose, _centre(rob))
        rv = np.where(hp[:, None], data.rotvec, 0.0)
        drum = np.isfinite(L0).all(axis=1)
        L0 = _drum_or_standard(rob, L0, drum, start, rv)
        res = solve_spatial_sensitivities(
            rob, start, rv, L0=L0, engine=self.engine, names=self._names6, **self.solver
        )
        SL, hooke, cond = rest_length_sensitivities(rob, res["P_s"], res["R_s"], L0)
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
            "smooth": smooth6(hooke, cond),
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
        """r(z) = [position and orientation rows ; tension rows ; z] (``map_residual6``)."""
        ev = self.evaluate(z)
        d, p, t = self.data, self._pose, self._tens
        r = map_residual6(d.pose[p], ev["P"][p], self._R[p], ev["R"][p], d.sigma[p], d.sigma_rad[p], z)
        if len(t):
            rt = ((d.tension[t] - ev["t"][t]) / d.sigma_t[t, None]).ravel()
            r = np.concatenate([r[: 6 * len(p)], rt, r[6 * len(p) :]])
        return r

    def jacobian(self, z):
        """dr/dz: per sample [-dp*/dθ σ_prior / σ_m ; -J_r⁻¹(e) dφ*/dθ σ_prior / σ_rad], then
        -dt/dθ σ_prior / σ_t, then I."""
        ev = self.evaluate(z)
        d, p, t = self.data, self._pose, self._tens
        k = len(self.index)
        S = np.nan_to_num(ev["S"][p]) * self.sd
        e = orientation_residual(self._R[p], ev["R"][p])
        Jp = -S[:, :3] / d.sigma[p, None, None]
        Jr = -np.einsum("nab,nbk->nak", log_right_jacobian_inverse(np.nan_to_num(e)), S[:, 3:])
        Jr /= d.sigma_rad[p, None, None]
        blocks = [np.concatenate([Jp, Jr], axis=1).reshape(-1, k)]
        if len(t):
            blocks.append((-(np.nan_to_num(ev["St"][t]) * self.sd) / d.sigma_t[t, None, None]).reshape(-1, k))
        return np.vstack([*blocks, np.eye(k)])

    def angles(self, ev):
        """The orientation error angle |log(R_meas R*ᵀ)| (n,) [rad] of every sample (NaN without one)."""
        out = np.full(len(self.data.sample), np.nan)
        p = self._pose
        out[p] = np.linalg.norm(orientation_residual(self._R[p], ev["R"][p]), axis=1)
        return out


def _drum_or_standard(robot, L0, drum, p, rv):
    """The rest lengths L0 (n, m) [m] where the drums can pay them out (``drum``), elsewhere the
    standard lengths at the start poses (p, rv): a harmless solve for the samples flagged
    ``DRUM_RANGE`` afterwards."""
    if drum.all():
        return L0
    return np.where(drum[:, None], L0, L_TS_pose(robot, p, rotation_matrix(rv)))


def tension_sensitivities6(robot, P, R, L0, S, cols6, w_L=None, w_d=None):
    r"""Cable tensions at a rigid platform's equilibrium and their total derivatives by the
    calibration parameters.

    .. math:: t_i = a_i k_i (L_{TE,i}(x^*) - L0_i),\quad k_i = \frac{E_i S_i}{L0_i},\quad
              \frac{dt_i}{d\theta} = \frac{\partial t_i}{\partial x}\frac{dx^*}{d\theta}
              + a_i\left[k_i \frac{\partial L_{TE,i}}{\partial \theta}
              + \frac{\partial k_i}{\partial \theta}(L_{TE,i} - L0_i)\right]
              + \frac{\partial t_i}{\partial L0_i}\frac{dL0_i}{d\theta}

    x* = (p*, R*) with the attachment B_i = p + R b_i (``sensitivity6.tension_partials6``: ∂t_i/∂x,
    ∂t_i/∂L0_i = -a_i k_i L_TE,i / L0_i and the fixed-pose partials); L0_i = reading - o_i, so
    dL0_i/do_i = -1, or through a winch (L0_i = W(reading - o_i, d_i), ``drive.realised_rest_lengths``)
    dL0_i/do_i = -∂W/∂L_cmd and dL0_i/dd_i = ∂W/∂d_i.

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) [m]
        Equilibrium positions.
    R : ndarray, shape (n, 3, 3) [-]
        Equilibrium orientations.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.
    S : ndarray, shape (n, 6, 11 m + 4)
        dx*/dθ of the calibration parameters (``calibration_names(m, spatial=True)``), the chain
        rule of the winch included; only the columns ``cols6`` and the offsets need to be filled.
    cols6 : ndarray of int
        Robot parameters (< 10 m + 4) whose fixed-pose partials count.
    w_L, w_d : ndarray, shape (n, m) [m/m], optional
        dL0/dL_cmd and dL0/dd of the winch map (None: no winch).

    Returns
    -------
    t : ndarray, shape (n, m) [N]
        0 on slack cables.
    dt : ndarray, shape (n, m, 11 m + 4) [N per unit of θ]

    References
    ----------
    Paty et al. 2021, eq. (5), (10), (13); implicit-function theorem.
    """
    m = robot.m
    nr = robot_size(m, True)
    names = calibration_names(m, True)
    tp = tension_partials6(robot, P, R, L0, [names[k] for k in cols6])
    dt = np.einsum("nia,nak->nik", tp["dt_dx"], S)
    dt[:, :, cols6] += tp["dt_dtheta"]
    cab = np.arange(m)
    dt[:, cab, nr + cab] -= tp["dt_dL0"] if w_L is None else tp["dt_dL0"] * w_L
    if w_d is not None:
        dt[:, cab, 3 * m + cab] += tp["dt_dL0"] * w_d
    return tp["t"], dt


def _problem(base, data, index, sd, engine=None, solver=None):
    """The MAP problem of the robot's kind: ``Problem`` (point mass) or ``Problem6``. A named
    ``engine`` is checked (``solve.check_engine``) and used by either; None is each problem's
    default (``Problem``: ``check_engine``'s, compiled; ``Problem6``: the numpy reference)."""
    if engine is not None:
        engine = check_engine(engine, "newton")
    if is_spatial(base):
        return Problem6(base, data, index, sd, engine=engine6(engine), solver=solver)
    return Problem(base, data, index, sd, engine=engine, solver=solver)


def engine6(engine):
    """The engine of the 6-DoF calibration (fits, plans, checks, simulations): a named engine,
    checked by ``solve.check_engine``, or for None the numpy reference: the tracked CoGiRo
    calibration tables were computed with it, and the compiled twin (analytic dF6/dθ) moves the
    misfit models' fits (the exact model's in the 4th digit).

    Parameters
    ----------
    engine : {"compiled", "numpy"} or None

    Returns
    -------
    str
    """
    return "numpy" if engine is None else check_engine(engine, "newton")


def solve6(robot, P, L0, rotvec=None, solver=None, engine=None):
    """The 6-DoF equilibria under commanded rest lengths L0 started at poses (P, rotvec): the
    ``solve_spatial`` result (``solve.solve_spatial_any`` by ``engine6(engine)``) with ``smooth``
    (``smooth6``) added.

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) or (n, 6) [m, rad]
    L0 : ndarray, shape (n, m) [m]
    rotvec : ndarray, shape (n, 3) [rad], optional
    solver : dict, optional
    engine : {"compiled", "numpy"} or None
        ``engine6``.

    Returns
    -------
    dict
    """
    res = solve_spatial_any(robot, P, rotvec, engine6(engine), L0=L0, **dict(solver or {}))
    _, hooke, cond = rest_length_sensitivities(robot, res["P_s"], res["R_s"], res["L0"])
    res["smooth"] = smooth6(hooke, cond)
    return res


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


def _centre(robot):
    """A start point for samples without a pose: below the anchors' centroid at half height."""
    A = robot.A
    return np.array([A[:, 0].mean(), A[:, 1].mean(), 0.5 * A[:, 2].min()])


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


# --- identifiability ------------------------------------------------------------------------------
def identifiability(Jm, names, rank_tol=RANK_TOL):
    """Singular values, rank, condition, posterior covariance and the weak directions in words.

    The posterior covariance in prior-scaled variables is (Jmᵀ Jm + I)^-1 (Gauss-Newton at the
    MAP); the posterior-to-prior sd ratio of parameter j is sqrt of its diagonal.

    Parameters
    ----------
    Jm : ndarray, shape (rows, k)
        Measurement rows / σ, columns × prior sd.
    names : list of str, length k
    rank_tol : float
        Singular values > rank_tol s_max count in the rank.

    Returns
    -------
    dict
        singular_values (k,) (0 where rows < k), rank, condition (inf when rank deficient),
        cov_scaled (k, k), ratio (k,), labels (k,) identified / partly / prior-dominated,
        unidentified: list of str, one per direction whose singular value is below 1 (the data
        see it less than the prior does), weakest first.
    """
    k = Jm.shape[1]
    s = np.zeros(k)
    if Jm.shape[0]:
        _, sv, Vt = np.linalg.svd(Jm, full_matrices=True)
        s[: len(sv)] = sv
    else:
        Vt = np.eye(k)
    smax = s.max() if k else 0.0
    rank = int((s > rank_tol * smax).sum()) if smax > 0 else 0
    cond = float(s[0] / s[-1]) if rank == k and k else math.inf
    cov = np.linalg.inv(Jm.T @ Jm + np.eye(k))
    ratio = np.sqrt(np.diag(cov))
    labels = np.where(
        ratio <= IDENTIFIED, "identified", np.where(ratio <= PARTLY, "partly", "prior-dominated")
    )
    words = []
    null = s <= rank_tol * smax if smax > 0 else np.ones(k, dtype=bool)
    if null.any():  # a degenerate null space: a sparse basis (reduced row echelon form) reads best
        words += [direction_words(v, names, 0.0, True) for v in sparse_basis(Vt[null])]
    for i in np.argsort(s, kind="stable"):
        if s[i] >= 1.0:
            break
        if not null[i]:
            words.append(direction_words(Vt[i], names, s[i], False))
    return {
        "singular_values": s,
        "rank": rank,
        "condition": cond,
        "cov_scaled": cov,
        "ratio": ratio,
        "labels": labels,
        "unidentified": words,
    }


def sparse_basis(B):
    """A basis of the row space of B (r, k) with one pivot parameter per vector (reduced row echelon
    form), each row normalised: e.g. the directions d_i - offset_i one by one instead of an
    arbitrary rotation of them.

    The pivots are chosen greedily, each the parameter whose column has the largest norm left after
    projecting out the pivots already chosen (column-pivoted Gram-Schmidt). The norms are rounded
    to ``TIE_DIGITS`` significant digits relative to the largest before ranking and ties go to the
    first parameter, so that equal loadings (a symmetric robot's d_1 - offset_1, d_2 - offset_2,
    ...) give the same basis, in the same order, on every machine. The result depends only on the
    row space of B, not on which orthonormal basis of it B holds.

    Parameters
    ----------
    B : ndarray, shape (r, k)
        Orthonormal rows spanning a subspace.

    Returns
    -------
    V : ndarray, shape (r, k)
    """

    r = B.shape[0]
    Q = np.array(B, dtype=float)  # columns of B, orthogonalised against the chosen pivots
    piv = []
    for _ in range(r):
        norms = np.linalg.norm(Q, axis=0)
        norms[piv] = 0.0
        j = _first_max(norms)
        piv.append(j)
        q = Q[:, j] / norms[j]
        Q -= np.outer(q, q @ Q)
    V = np.linalg.solve(B[:, piv], B)
    V[:, piv] = np.eye(r)  # exact zeros and ones at the pivots (no round-off left to rank on)
    return V / np.linalg.norm(V, axis=1, keepdims=True)


#: Significant digits kept when ranking loadings: closer values are a tie, broken by parameter order.
TIE_DIGITS = 6


def _first_max(values):
    """Index of the largest of ``values`` (>= 0) after rounding to ``TIE_DIGITS`` significant digits
    relative to the largest; ties go to the lowest index."""
    top = float(np.max(values))
    if top <= 0:
        return 0
    return int(np.argmax(np.round(np.asarray(values) / top, TIE_DIGITS)))


def _ranked(v):
    """Parameter indices by decreasing |v|, rounded to ``TIE_DIGITS`` significant digits relative to
    the largest; ties in parameter order."""
    a = np.abs(np.asarray(v, dtype=float))
    top = a.max() if len(a) else 0.0
    key = np.round(a / top, TIE_DIGITS) if top > 0 else a
    return np.lexsort((np.arange(len(a)), -key))


def direction_words(v, names, s, null):
    """A direction of parameter space in words: the leading parameter, then 'against' those that
    move against it along the unseen direction (opposite sign), 'with' those that move with it.

    Parameters
    ----------
    v : ndarray, shape (k,)
        Unit singular vector (prior-scaled).
    names : list of str
    s : float
        Its singular value.
    null : bool
        Below the rank threshold.

    Returns
    -------
    str, e.g. "d_1 against offset_1 (not seen by the data)".
    """
    order = _ranked(v)  # ties: the first parameter leads
    lead = order[0]
    big = [j for j in order[1:5] if abs(v[j]) >= 0.2 * abs(v[lead])]
    # along v the data do not change: opposite signs move against each other, equal signs together
    against = [names[j] for j in big if v[j] * v[lead] < 0]
    withs = [names[j] for j in big if v[j] * v[lead] > 0]
    text = names[lead]
    if against:
        text += " against " + " and ".join(against)
    if withs:
        text += (";" if against else "") + " with " + " and ".join(withs)
    if not big:
        text += " alone"
    tail = "not seen by the data" if null else f"weak: s = {s:.2g} < 1, the prior decides"
    return f"{text} ({tail})"


# --- the fit --------------------------------------------------------------------------------------
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
        None: ``solve.check_engine``'s default (compiled) on a point mass, the numpy reference on a
        6-DoF platform (``Problem6``); a named engine is used by either.
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
    names = [calibration_names(robot.m, spatial)[k] for k in index]
    keep = used
    for _attempt in range(3):
        sub = data.subset(keep)
        prob = _problem(base, sub, index, sd, engine=engine, solver=solver)
        ev0 = prob.evaluate(np.zeros(len(index)))
        good = (ev0["status"] == "ok") & ev0["smooth"]
        if not good.all():
            status[keep[~good]] = [f"left out at nominal: {s}" for s in _why(ev0, ~good)]
            keep = keep[good]
            continue
        break
    sub = data.subset(keep)
    n_eq = (6 if spatial else 3) * int(sub.has_pose.sum()) + robot.m * int(sub.has_tension.sum())
    if n_eq < len(index):
        raise CdprError(
            f"{data.source}: {len(keep)} usable samples give {n_eq} equations for {len(index)} "
            "parameters; give at least as many equations as parameters"
        )
    prob = _problem(base, sub, index, sd, engine=engine, solver=solver)
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
    groups, _ = calibration_groups(base.m, is_spatial(base))
    names = calibration_names(base.m, is_spatial(base))
    th0 = calibration_values(base)
    lo = np.full(len(index), -np.inf)
    for j, k in enumerate(index):
        g = groups[k]
        if g in RELATIVE:
            lo[j] = (0.01 * th0[k] - th0[k]) / sd[j]
        elif g in ("pulleys", "dead_lengths") or names[k].startswith(("h_", "r_p_", "d_")):
            lo[j] = -th0[k] / sd[j]
    return lo, np.full(len(index), np.inf)


@dataclasses.dataclass
class Calibration:
    """The result of ``fit``: estimate, posterior, identifiability and the per-sample table."""

    robot: object
    base: object
    model: str
    index: np.ndarray
    names: list
    nominal: np.ndarray
    estimate: np.ndarray
    prior_sd: np.ndarray
    ident: dict
    theta: np.ndarray
    table: pd.DataFrame
    source: str
    cost: float
    nfev: int

    @property
    def sd(self):
        """Posterior sd [Pa, m, kg] (Gauss-Newton at the MAP)."""
        return self.ident["ratio"] * self.prior_sd

    @property
    def covariance(self):
        return self.ident["cov_scaled"] * np.outer(self.prior_sd, self.prior_sd)

    @property
    def correlation(self):
        c = self.ident["cov_scaled"]
        d = np.sqrt(np.diag(c))
        return c / np.outer(d, d)

    def calibrated_robot(self):
        """The robot at the estimate (the model's pulleys; the standard model's E back to the file's)."""
        m = self.robot.m
        th = self.theta[: robot_size(m, is_spatial(self.base))].copy()
        if self.model in ("standard", "rigid"):
            th[:m] /= STANDARD_STIFFENING
        return calibrated_robot(self.base, th)

    def fitted_model(self):
        """The model at the estimate, as the fit saw it (rigid models keep their stiff cables): what
        predicts and compensates."""
        return calibrated_robot(self.base, self.theta)

    @property
    def offsets(self):
        return self.theta[robot_size(self.robot.m, is_spatial(self.base)) :]

    def parameter_table(self):
        """nominal, estimate, sd, 95 % interval, prior sd, ratio and label per parameter (SI)."""
        groups, cables = calibration_groups(self.robot.m, is_spatial(self.base))
        return pd.DataFrame(
            {
                "name": self.names,
                "group": [groups[k] for k in self.index],
                "cable": pd.array([cables[k] for k in self.index], dtype="Int64"),
                "nominal": self.nominal,
                "estimate": self.estimate,
                "sd": self.sd,
                "lo95": self.estimate - 1.959964 * self.sd,
                "hi95": self.estimate + 1.959964 * self.sd,
                "prior_sd": self.prior_sd,
                "ratio": self.ident["ratio"],
                "identified": self.ident["labels"],
            }
        )

    def summary(self):
        """The JSON of ``cdpr calibrate fit --json`` (issue 18's keys; SI units)."""
        pt = self.parameter_table()
        used = self.table["status"] == "used"
        res = self.table.loc[used, "residual_after_m"].to_numpy()
        res = res[np.isfinite(res)]
        rad = None
        if "residual_after_rad" in self.table:
            ang = self.table.loc[used, "residual_after_rad"].to_numpy()
            ang = ang[np.isfinite(ang)]
            rad = float(np.sqrt(np.mean(ang**2))) if len(ang) else None
        return {
            "parameters": [
                {
                    "name": r.name,
                    "group": r.group,
                    "cable": None if pd.isna(r.cable) else int(r.cable),
                    "nominal": float(r.nominal),
                    "estimate": float(r.estimate),
                    "sd": float(r.sd),
                    "prior_sd": float(r.prior_sd),
                    "identified": str(r.identified),
                }
                for r in pt.itertuples()
            ],
            "n_parameters": len(self.index),
            "rank": self.ident["rank"],
            "condition": _json_float(self.ident["condition"]),
            "singular_values": [float(s) for s in self.ident["singular_values"]],
            "unidentified": list(self.ident["unidentified"]),
            "residual_rms_m": float(np.sqrt(np.mean(res**2))) if len(res) else None,
            "residual_rms_rad": rad,
            "samples_used": int(used.sum()),
            "samples_left_out": int((~used).sum()),
        }


def _winch_mapping(w):
    """A cable's WinchParams as the robot file's ``winch:`` keys (plain SI numbers)."""
    return {key: float(getattr(w, attr)) for key, (attr, _unit) in WINCH_KEYS.items()}


def _json_float(x):
    return float(x) if math.isfinite(x) else None


def write_robot(path, cal, data_source):
    """Write the calibrated robot: the input's schema, per-cable plain SI values, and a header saying
    from which data, with which model, and when (offsets, which are not robot parameters, in the header).
    """

    rob = cal.calibrated_robot()
    header = [
        f"# {rob.name} calibrated by cdpr calibrate fit ({cal.model} model) from {data_source}",
        f"# on {datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds')}; nominal robot: {cal.robot.source}",
        f"# estimated: {', '.join(cal.names)}",
    ]
    spatial = is_spatial(rob)
    if "offsets" in {calibration_groups(rob.m, spatial)[0][k] for k in cal.index}:
        header.append("# encoder offsets [m]: " + ", ".join(f"{o:.9g}" for o in cal.offsets))
    cables = []
    for c in rob.cables:
        pul = {"kind": c.pulley.kind, "h_m": float(c.pulley.h), "r_p_m": float(c.pulley.r_p)}
        if spatial:  # the swivel axis and zero of a spatial robot's pulley (defaults left out)
            if tuple(c.pulley.axis) != (0.0, 0.0, 1.0):
                pul["axis"] = [float(x) for x in c.pulley.axis]
            if c.pulley.zero is not None:
                pul["zero"] = [float(x) for x in c.pulley.zero]
        mat = {
            "young_modulus_Pa": float(c.material.E),
            "diameter_m": float(c.material.diameter),
            "max_tension_N": float(c.material.T_a),
            **({"min_tension_N": float(c.material.T_min)} if c.material.T_min else {}),
        }
        cables.append(
            {
                "A_m": [float(x) for x in c.A],
                **({"B_m": [float(x) for x in c.B]} if spatial else {}),
                "pulley": pul,
                "cable": mat,
                "dead_length_m": float(c.dead_length),
                **({"winch": _winch_mapping(c.winch)} if c.winch is not None else {}),
            }
        )
    first = rob.cables[0]
    doc = {
        "name": f"{rob.name} (calibrated)",
        "platform": {
            "mass_kg": float(rob.platform.mass),
            **({"com_m": [float(x) for x in rob.platform.com]} if spatial else {}),
            "gravity_m_per_s2": float(rob.platform.g),
        },
        "cable": {
            "young_modulus_Pa": float(first.material.E),
            "diameter_m": float(first.material.diameter),
            "max_tension_N": float(first.material.T_a),
        },
        "pulley": {"kind": first.pulley.kind, "h_m": float(first.pulley.h), "r_p_m": float(first.pulley.r_p)},
        "cables": cables,
    }
    Path(path).write_text("\n".join(header) + "\n" + yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")


# --- check ----------------------------------------------------------------------------------------
def check(robot, data, engine=None):
    """The robot's prediction (physical equilibrium under the commanded lengths) against every sample.

    Parameters
    ----------
    robot : Robot
    data : Data
        Commanded lengths (not encoder readings: their offsets are unknown) and measured poses.

    Returns
    -------
    dict
        n (samples compared), rms_m (RMS over samples of |P* - y|), max_m, median_m, rms_rad and
        max_rad (None for a point mass; for a 6-DoF platform the RMS and largest angle of
        R_meas R*ᵀ), samples: list of {sample, status, error_m} (error None where the equilibrium is
        not ok; with error_rad for a 6-DoF platform).
    """
    if data.encoder:
        raise CdprError(f"{data.source}: check needs commanded lengths L1..L{robot.m}, not encoder readings")
    if is_spatial(robot):
        return _check6(robot, data, engine)
    L0 = realised_lengths(robot, data.L)
    drum = np.isfinite(L0).all(axis=1)
    res = sensitivities(
        robot, data.pose, redundancy="physical", L=np.where(drum[:, None], L0, data.L), engine=engine
    )
    res["status"] = np.where(drum, res["status"], DRUM_RANGE)
    ok = res["status"] == "ok"
    err = np.linalg.norm(res["P_s"] - data.pose, axis=1)
    e = err[ok]
    return {
        "n": int(ok.sum()),
        "rms_m": float(np.sqrt(np.mean(e**2))) if len(e) else None,
        "max_m": float(e.max()) if len(e) else None,
        "median_m": float(np.median(e)) if len(e) else None,
        "rms_rad": None,
        "max_rad": None,
        "samples": [
            {"sample": str(s), "status": str(st), "error_m": float(x) if o else None}
            for s, st, x, o in zip(data.sample, res["status"], err, ok)
        ],
    }


def _check6(robot, data, engine=None):
    """``check`` for a 6-DoF platform: the equilibrium under the commanded lengths (through the
    drums of a robot with winches, ``realised_lengths``) started at the measured pose."""
    L0 = realised_lengths(robot, data.L)
    drum = np.isfinite(L0).all(axis=1)
    L0 = _drum_or_standard(robot, L0, drum, data.pose, np.nan_to_num(data.rotvec))
    res = solve6(robot, data.pose, L0, rotvec=data.rotvec, engine=engine)
    res["status"] = np.where(drum, res["status"], DRUM_RANGE)
    ok = res["status"] == "ok"
    err = np.linalg.norm(res["P_s"] - data.pose, axis=1)
    ang = np.linalg.norm(orientation_residual(rotation_matrix(data.rotvec), res["R_s"]), axis=1)
    e, a = err[ok], ang[ok]
    return {
        "n": int(ok.sum()),
        "rms_m": float(np.sqrt(np.mean(e**2))) if len(e) else None,
        "max_m": float(e.max()) if len(e) else None,
        "median_m": float(np.median(e)) if len(e) else None,
        "rms_rad": float(np.sqrt(np.mean(a**2))) if len(a) else None,
        "max_rad": float(a.max()) if len(a) else None,
        "samples": [
            {
                "sample": str(s),
                "status": str(st),
                "error_m": float(x) if o else None,
                "error_rad": float(y) if o else None,
            }
            for s, st, x, y, o in zip(data.sample, res["status"], err, ang, ok)
        ],
    }


# --- synthetic data -------------------------------------------------------------------------------
def simulate(
    truth,
    nominal,
    P,
    sigma=SIGMA_DEFAULT,
    rng=None,
    offsets=None,
    engine=None,
    tensions=False,
    sigma_t=SIGMA_T_DEFAULT,
    rotvec=None,
    sigma_rad=SIGMA_RAD_DEFAULT,
    command="standard",
):
    """Synthetic tracker data: the lengths the nominal robot would command to reach P (L_TS, eq. 2),
    the pose where the true robot settles under them, plus Gaussian noise. A true robot with
    winches realises the commands through its drums (``realised_lengths``: a controller that
    neglects the exit point's motion, Métillon 2022 eq. 31-32); the data keep the commands.

    Parameters
    ----------
    truth : Robot
        The real robot.
    nominal : Robot
        The model that computes the commands.
    P : ndarray, shape (n, 3) [m]
        Targets.
    sigma : float [m]
        Tracker noise sd.
    rng : numpy Generator, optional
        Noise source (None: noise-free).
    offsets : ndarray, shape (m,) [m], optional
        Encoder offsets: the data are then readings L0 + offsets.
    tensions : bool
        Also measure the cable tensions (noise sd ``sigma_t`` [N]).
    rotvec : ndarray, shape (n, 3) or (3,) [rad], optional
        Target orientations of a 6-DoF platform (default identity; or P of shape (n, 6)): the
        commands are then L_TS,i = |p + R b_i - A_i| + d_i and the tracker also measures the
        orientation, R_meas = exp([w]) R*, w ~ N(0, ``sigma_rad``² I) [rad].
    command : {"standard", "compensated"}
        ``COMMANDS``; "compensated" only for a 6-DoF platform.

    Returns
    -------
    Data
        With status "ok" samples only (the others are dropped here: this is the simulator, not the fit).
    """
    if is_spatial(truth):
        return _simulate6(
            truth,
            nominal,
            P,
            rotvec,
            sigma,
            sigma_rad,
            rng,
            offsets,
            command,
            tensions=tensions,
            sigma_t=sigma_t,
            engine=engine,
        )
    _check_command(command, truth)
    L0 = L_TS(nominal, P)
    L_real = realised_lengths(truth, L0)  # through the true robot's drums when it has winches
    drum = np.isfinite(L_real).all(axis=1)
    res = sensitivities(truth, P, redundancy="physical", L=np.where(drum[:, None], L_real, L0), engine=engine)
    ok = (res["status"] == "ok") & res["smooth"] & drum
    y = res["P_s"][ok]
    if rng is not None:
        y = y + rng.normal(0.0, sigma, y.shape)
    L = L0[ok] if offsets is None else L0[ok] + np.asarray(offsets)
    t = np.full(L.shape, np.nan)
    if tensions:
        t = _measured_tensions(res["t"][ok], sigma_t, rng)
    return Data(
        tension=t,
        sigma_t=np.full(int(ok.sum()), float(sigma_t)),
        sample=np.array([f"s{i + 1}" for i in range(int(ok.sum()))]),
        L=L,
        pose=y,
        sigma=np.full(int(ok.sum()), float(sigma)),
        encoder=offsets is not None,
        source="<simulated>",
    )


def _measured_tensions(t, sigma_t, rng):
    """Tension-sensor readings of the equilibrium tensions t (n, m) [N] (NaN on a slack cable, read
    as 0 N): plus N(0, sigma_t²) noise with ``rng``, clipped at 0 N."""
    t = np.nan_to_num(t)
    if rng is not None:
        t = np.maximum(t + rng.normal(0.0, sigma_t, t.shape), 0.0)
    return t


def _check_command(command, robot):
    if command not in COMMANDS or (command != "standard" and not is_spatial(robot)):
        allowed = COMMANDS if is_spatial(robot) else COMMANDS[:1]
        raise CdprError(f"command {command!r}: allowed for robot {robot.name}: {', '.join(allowed)}")


def commanded_lengths(robot, p, R, command="standard"):
    """Rest lengths commanded at 6-DoF poses: ``L_TS_pose`` (standard) or the compensated rest
    lengths of the minimum-norm tensions (``distribution6.compensated_lengths``, NaN where no
    admissible distribution exists).

    Parameters
    ----------
    robot : Robot
    p : ndarray, shape (n, 3) [m]
    R : ndarray, shape (n, 3, 3) [-]
    command : {"standard", "compensated"}

    Returns
    -------
    L0 : ndarray, shape (n, m) [m]
    """
    _check_command(command, robot)
    if command == "standard":
        return L_TS_pose(robot, p, R)
    return compensated_lengths(robot, p, rotvec_of(R))["L0"]


def _simulate6(
    truth,
    nominal,
    P,
    rotvec,
    sigma,
    sigma_rad,
    rng,
    offsets,
    command="standard",
    tensions=False,
    sigma_t=SIGMA_T_DEFAULT,
    engine=None,
):
    """``simulate`` for a 6-DoF platform (its docstring; the solves by ``engine6(engine)``)."""
    p, R = pose_arrays(nominal, P, rotvec)
    rv = rotvec_of(R)
    L0 = commanded_lengths(nominal, p, R, command)
    fin = np.isfinite(L0).all(axis=1)
    p, R, rv, L0 = p[fin], R[fin], rv[fin], L0[fin]
    L_real = realised_lengths(truth, L0)  # through the true robot's drums when it has winches
    drum = np.isfinite(L_real).all(axis=1)
    res = solve6(truth, p, np.where(drum[:, None], L_real, L0), rotvec=rv, engine=engine)
    ok = (res["status"] == "ok") & res["smooth"] & drum
    y, Rs = res["P_s"][ok], res["R_s"][ok]
    if rng is not None:
        y = y + rng.normal(0.0, sigma, y.shape)
        Rs = rotation_matrix(rng.normal(0.0, sigma_rad, (len(y), 3))) @ Rs
    n = int(ok.sum())
    t = np.full((n, truth.m), np.nan)
    if tensions:
        t = _measured_tensions(res["t"][ok], sigma_t, rng)
    return Data(
        tension=t,
        sigma_t=np.full(n, float(sigma_t)),
        sample=np.array([f"s{i + 1}" for i in range(n)]),
        L=L0[ok] if offsets is None else L0[ok] + np.asarray(offsets),
        pose=y,
        sigma=np.full(n, float(sigma)),
        encoder=offsets is not None,
        source="<simulated>",
        rotvec=rotvec_of(Rs),
        sigma_rad=np.full(n, float(sigma_rad)),
    )


def perturbed(robot, index, sd, rng):
    """A robot whose parameters ``index`` are drawn from the prior N(nominal, sd²); returns (robot, θ)."""
    th = calibration_values(robot)
    th[index] += sd * rng.standard_normal(len(index))
    return calibrated_robot(robot, th), th


def random_poses6(robot, rng, n, box, tilt=0.1, margin=100.0, command="standard"):
    """n random poses of a 6-DoF platform where the robot under the ``command`` lengths
    (``commanded_lengths``) settles ``ok`` with every cable taut by more than ``margin``.

    Positions are uniform in ``box`` (x, then y, then z drawn), rotation vectors uniform in
    [-tilt, tilt]³; 4n candidates are drawn and the first n admissible kept (the others are
    rejected: this draws targets, it is not the fit).

    Parameters
    ----------
    robot : Robot
        6-DoF platform that computes the commands and judges admissibility (the nominal robot).
    rng : numpy Generator
    n : int
        Number of poses.
    box : list of 6 float [m]
        [xmin, xmax, ymin, ymax, zmin, zmax] of the positions.
    tilt : float [rad]
        Largest rotation-vector component.
    margin : float [N]
        Least tension of every cable at an admissible pose.
    command : {"standard", "compensated"}
        ``COMMANDS``.

    Returns
    -------
    P6 : ndarray, shape (n, 6) [m, rad]
        Target positions and rotation vectors.

    Raises
    ------
    CdprError
        Fewer than n admissible poses among the 4n drawn.
    """
    p = np.column_stack([rng.uniform(box[2 * k], box[2 * k + 1], 4 * n) for k in range(3)])
    P6 = np.concatenate([p, rng.uniform(-tilt, tilt, (4 * n, 3))], axis=1)
    L = commanded_lengths(robot, P6[:, :3], rotation_matrix(P6[:, 3:]), command)
    fin = np.isfinite(L).all(axis=1)
    P6, L = P6[fin], L[fin]
    res = solve6(robot, P6[:, :3], L, rotvec=P6[:, 3:])
    good = (res["status"] == "ok") & (np.nan_to_num(res["t"]) > margin).all(axis=1)
    if good.sum() < n:
        raise CdprError(
            f"only {int(good.sum())} admissible poses of {4 * n} drawn in {list(box)} (tilt {tilt} rad, "
            f"every cable above {margin} N, {command} commands); ask for fewer or widen the box"
        )
    return P6[good][:n]


def equilibrium_flags(robot, data, kick=(0.05, 0.05), tol=1e-3):
    """Per sample: the number of taut cables of ``robot``'s equilibrium under the data's lengths
    (started at the measured pose), and whether a second equilibrium exists (``robot`` settles
    more than ``tol`` away when started from the measured pose moved by ±kick[0] along each axis or
    turned by ±kick[1] about each axis: 12 starts, a heuristic, not a proof of uniqueness).

    A 6-DoF platform on fewer than 6 taut cables has a soft mode (it swings until gravity
    balances), where a small parameter error moves the pose far.

    Parameters
    ----------
    robot : Robot
        6-DoF platform (the true robot of a simulation).
    data : Data
        Samples with poses and orientations.
    kick : tuple of 2 float [m, rad]
        Start offsets.
    tol : float [m]
        Distance beyond which an equilibrium counts as another one.

    Returns
    -------
    n_taut : ndarray, shape (N,) of int
        0 where the equilibrium is not ``ok``.
    second : ndarray, shape (N,) of bool
    """
    ref = solve6(robot, data.pose, data.L, rotvec=data.rotvec)
    ok_ref = ref["status"] == "ok"
    second = np.zeros(len(data.sample), dtype=bool)
    for k in range(6):
        for s in (-1.0, 1.0):
            P, rv = data.pose.copy(), data.rotvec.copy()
            if k < 3:
                P[:, k] += s * kick[0]
            else:
                rv[:, k - 3] += s * kick[1]
            r = solve6(robot, P, data.L, rotvec=rv)
            ok = (r["status"] == "ok") & ok_ref
            second |= ok & (np.linalg.norm(r["P_s"] - ref["P_s"], axis=1) > tol)
    n_taut = np.where(ok_ref, ref["taut"].sum(axis=1), 0).astype(int)
    return n_taut, second


# --- plan -----------------------------------------------------------------------------------------
def default_box(robot):
    """Candidate box: the middle 80 % of the anchors' horizontal extent, z from 10 % to 70 % of
    the lowest anchor height [m]; for a 6-DoF robot whose anchors spread in height (some low, some
    high), z from 20 % to 80 % of the anchors' vertical span."""
    A = robot.A
    lo, hi = A[:, :2].min(axis=0), A[:, :2].max(axis=0)
    c, w = (lo + hi) / 2, (hi - lo) / 2 * 0.8
    top = A[:, 2].min()
    zlo, zhi = 0.1 * top, 0.7 * top
    span = A[:, 2].max() - top
    if is_spatial(robot) and (top <= 0 or span > 0.1 * abs(top)):  # anchors low and high (IPAnema-like)
        zlo, zhi = top + 0.2 * span, top + 0.8 * span
    return [c[0] - w[0], c[0] + w[0], c[1] - w[1], c[1] + w[1], zlo, zhi]


def candidates(robot, box, n_axis=7, model="exact", engine=None, targets=False, command="standard"):
    """Admissible candidate poses of a box and their scaled measurement rows.

    A candidate is the grid point p commanded with L_TS(p); admissible when the nominal equilibrium
    is ``ok`` and smooth there. A 6-DoF platform's candidates are at the identity orientation
    (L_TS,i = |p + b_i - A_i| + d_i, or with ``command="compensated"`` the compensated rest lengths,
    ``commanded_lengths``), admissible with at least min(6, m) taut cables.

    Returns
    -------
    P : ndarray (c, 3) [m], or (c, 6) [m, rad] for a 6-DoF platform
        The equilibria (where the tracker would measure).
    L0 : ndarray (c, m) [m]
        Commanded lengths.
    p : ndarray (c, 3) [m]
        The grid points commanded (only with ``targets=True``).
    """

    base = model_robot(robot, model)
    p = grid_points(box, n_axis)
    if is_spatial(robot):
        L0 = commanded_lengths(robot, p, rotation_matrix(np.zeros_like(p)), command)
        fin = np.isfinite(L0).all(axis=1)
        p, L0 = p[fin], L0[fin]
        L_real = realised_lengths(base, L0)  # through the drums of a robot with winches
        drum = np.isfinite(L_real).all(axis=1)
        res = solve6(base, p, np.where(drum[:, None], L_real, L0), engine=engine)
        ok = (res["status"] == "ok") & res["smooth"] & (res["n_taut"] >= min(6, robot.m)) & drum
        P6 = np.concatenate([res["P_s"], res["rotvec_s"]], axis=1)
        return (P6[ok], L0[ok], p[ok]) if targets else (P6[ok], L0[ok])
    L0 = L_TS(robot, p)
    L_real = realised_lengths(base, L0)  # through the drums of a robot with winches
    drum = np.isfinite(L_real).all(axis=1)
    res = sensitivities(base, p, redundancy="physical", L=np.where(drum[:, None], L_real, L0), engine=engine)
    ok = (res["status"] == "ok") & res["smooth"] & (res["n_taut"] >= 3) & drum
    if targets:
        return res["P_s"][ok], L0[ok], p[ok]
    return res["P_s"][ok], L0[ok]


def info_rows(robot, P, L0, index, sd, sigma=SIGMA_DEFAULT, model="exact", engine=None):
    """Scaled measurement rows per candidate: -dP*/dθ σ_prior / σ, shape (c, 3, k); for a 6-DoF
    platform (P (c, 6)) also the orientation rows -dφ*/dθ σ_prior / σ_rad (``SIGMA_RAD_DEFAULT``),
    shape (c, 6, k)."""
    base = model_robot(robot, model)
    if is_spatial(robot):
        data = Data(
            sample=np.arange(len(P)).astype(str),
            L=L0,
            pose=P[:, :3],
            sigma=np.full(len(P), sigma),
            encoder=False,
            source="<plan>",
            rotvec=P[:, 3:],
        )
        prob = _problem(base, data, index, sd, engine=engine)
        return prob.jacobian(np.zeros(len(index)))[: 6 * len(P)].reshape(len(P), 6, len(index))
    data = Data(
        sample=np.arange(len(P)).astype(str),
        L=L0,
        pose=P,
        sigma=np.full(len(P), sigma),
        encoder=False,
        source="<plan>",
    )
    prob = _problem(base, data, index, sd, engine=engine)
    return prob.jacobian(np.zeros(len(index)))[: 3 * len(P)].reshape(len(P), 3, len(index))


#: log det differences [-] below which two D-optimal candidates tie (broken by candidate order): a
#: symmetric robot on a symmetric candidate grid has exact ties, which round-off would otherwise break
#: differently on different CPUs (1e-9 in log det is a relative 1e-9 in the determinant).
LOGDET_TIE = 1e-9


def _first_within(values, tol):
    """Lowest index whose value lies within ``tol`` of the largest of ``values``."""
    values = np.asarray(values, dtype=float)
    return int(np.flatnonzero(values >= values.max() - tol)[0])


def d_optimal(rows, n, exchange=True):
    """Greedy D-optimal choice of n candidates maximising det(Σ J_kᵀ J_k + I), then one exchange pass.

    Each greedy step adds the candidate with the largest det(I + J_k C J_kᵀ), C the current
    posterior covariance (matrix determinant lemma); the exchange pass swaps a chosen candidate for
    an unchosen one whenever the determinant grows. Candidates within ``LOGDET_TIE`` of the best tie
    and the first in candidate order is taken, so the plan does not depend on the last bits.

    Parameters
    ----------
    rows : ndarray, shape (c, r, k)
        Scaled measurement rows of the candidates (``info_rows``; r = 3, or 6 for a 6-DoF platform).
    n : int
        Plan size (repeats allowed: a pose may be measured twice).
    exchange : bool

    Returns
    -------
    chosen : ndarray of int, shape (n,)
    logdet : float
        log det of the information matrix of the plan (prior included).

    References
    ----------
    Atkinson & Donev 1992, ch. 11 and 15.
    """
    c, nr, k = rows.shape
    info = np.eye(k)
    chosen = []
    for _ in range(n):
        C = np.linalg.inv(info)
        M = np.eye(nr) + np.einsum("cik,kl,cjl->cij", rows, C, rows)
        j = _first_within(np.linalg.slogdet(M)[1], LOGDET_TIE)
        chosen.append(j)
        info += rows[j].T @ rows[j]
    chosen = np.array(chosen)
    if exchange:
        for pos in range(n):
            rest = info - rows[chosen[pos]].T @ rows[chosen[pos]]
            C = np.linalg.inv(rest)
            M = np.eye(nr) + np.einsum("cik,kl,cjl->cij", rows, C, rows)
            j = _first_within(np.linalg.slogdet(M)[1], LOGDET_TIE)
            chosen[pos] = j
            info = rest + rows[j].T @ rows[j]
    return chosen, float(np.linalg.slogdet(info)[1])


def plan_sd(rows, chosen):
    """Posterior-to-prior sd ratios of a plan: sqrt diag (Σ_chosen J_kᵀ J_k + I)^-1."""
    k = rows.shape[2]
    info = np.eye(k) + np.einsum("cik,cil->kl", rows[chosen], rows[chosen])
    return np.sqrt(np.diag(np.linalg.inv(info))), float(np.linalg.slogdet(info)[1])


def plan(
    robot,
    groups,
    n,
    box=None,
    priors=None,
    sigma=SIGMA_DEFAULT,
    n_random=50,
    seed=0,
    n_axis=7,
    command="standard",
):
    """Pick n poses among admissible candidates maximising det(JᵀJ + prior) and compare with random.

    Returns
    -------
    dict
        poses (n, 3) [m] (n, 6 [m, rad] for a 6-DoF platform: position and rotation vector of the
        expected equilibrium), lengths (n, m) [m], names, sd_d_optimal, sd_random_median (k,) [SI],
        prior_sd (k,), logdet_d_optimal, logdet_random_median, n_candidates.
    """
    priors = parse_priors(None) if priors is None else priors
    index = select_groups(robot, groups)
    sd = prior_sd(robot, index, priors)

    box = default_box(robot) if box is None else check_box(box).tolist()
    _check_command(command, robot)
    P, L0 = candidates(robot, box, n_axis, command=command)
    if len(P) == 0:
        raise CdprError(f"no admissible candidate pose in the box {box}")
    rows = info_rows(robot, P, L0, index, sd, sigma)
    chosen, logdet = d_optimal(rows, n)
    rng = np.random.default_rng(seed)
    rand = [plan_sd(rows, rng.choice(len(P), n, replace=len(P) < n)) for _ in range(n_random)]
    ratio, _ = plan_sd(rows, chosen)
    return {
        "poses": P[chosen],
        "lengths": L0[chosen],
        "names": [calibration_names(robot.m, is_spatial(robot))[k] for k in index],
        "sd_d_optimal": ratio * sd,
        "sd_random_median": np.median([r[0] for r in rand], axis=0) * sd,
        "prior_sd": sd,
        "logdet_d_optimal": logdet,
        "logdet_random_median": float(np.median([r[1] for r in rand])),
        "n_candidates": len(P),
    }


# --- rigid self-calibration (standard model, poses unknown) ---------------------------------------
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
    if n * m < 3 * n + k:
        raise CdprError(
            f"{data.source}: {n} samples give {n * m} equations for {3 * n + k} unknowns (poses and parameters)"
        )

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
    P = np.tile(_centre(base), (n, 1))
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
    Q, _ = np.linalg.qr(J[:, : 3 * n])
    Jth = J[:, 3 * n :]
    names = [calibration_names(m)[c] for c in index]
    ident = identifiability(Jth - Q @ (Q.T @ Jth), names)
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
