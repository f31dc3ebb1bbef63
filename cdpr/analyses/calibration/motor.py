"""Calibration from motor angles: a spool robot's (Hangprinter's) encoder data, poses unknown or measured.

Data (a contract, docs/calibration.md and docs/hangprinter.md): ``sample``, ``motor_deg_1..m`` (the
motor shaft angle from the encoder [deg], relative to the reference taken with the mover at the
origin; positive = line paid out), optional ``force_N_1..m`` (the line force the drivers report [N],
the force of the cable on the mover), optional ``x_m, y_m, z_m`` (measured position, all three or
none per sample) and optional ``sigma_m``. A motor angle becomes line through the robot's spool
(``cdpr.models.winch.released_line``: phi = theta L / H, s = r0 phi - O Q phi^2 / 4, the U strands
between anchor and mover lengthen by s / U).

Every sample's position P_k is an unknown (three nuisance parameters); a measured position adds the
three rows (P_k - y_k) / sigma_k. Each sample gives m line rows, (l_i(P_k) - l_pred,ki) / sigma_L with
l_i(P) = |A_i - P| + d_i the line from the spool exit over the fixed anchor to the mover and

- ``standard`` (rigid lines, the Hangprinter tool's model): l_pred = l_i(0) + s_ki / U_i, i.e.
  |A_i - P_k| - |A_i| = s_ki / U_i;
- ``exact`` (the robot's model for a point mass on fixed anchors: straight lines, Hooke elasticity
  of the U strands K_i = U E S, the spool): the rest length is L0_ki = L0_ref,i + s_ki / U_i and the
  line under the measured force t_ki is l_pred = L0_ki (1 + t_ki / K_i); the encoder reference is
  the mover at the origin under the reference sample's forces t_ref (the first sample whose motor
  angles are all within ``REFERENCE_DEG`` of 0 and that has forces; none: t_ref = 0, said in the
  warnings), so L0_ref,i = l_i(0) / (1 + t_ref,i / K_i). A sample without forces is taken with rigid
  lines (status ``no forces: rigid lines``).

The parameters θ: ``anchors`` (A_i, names ``A_1_x`` ..) and ``spools`` (``r0_1`` .. the spool radius
at the origin, ``Q_1`` .. the buildup factor), each with a Gaussian prior around the robot file
(``DEFAULT_PRIORS``; ``spools=SD`` sets the radius' sd, the buildup factor's is
``BUILDUP_PRIOR_SD``). The MAP is proper whenever every estimated parameter has a prior, however few
the equations: nothing is refused for counting. The poses carry no prior; with m >= 3 lines each is
fixed by its own rows.

Gauge: the encoder reference puts the mover at the origin at zero motor angle, which fixes the
frame's translation; with no measured position the frame's rotation about the origin (3 directions)
is not seen by the data, and with ``spools`` also its scale (anchors, positions and spool radii
scaled together), so those are fixed by the priors alone (the Hangprinter tool fixes A_x = D_x =
D_y = 0 instead). Measured positions fix the frame (theirs).

The Jacobian is analytic; identifiability is that of θ with the poses eliminated (measurement rows
projected on the orthogonal complement of the pose columns), as in ``self_calibrate_standard``.

References
----------
RepRapFirmware, HangprinterKinematics (M666 Q R U O L H), as derived in ``cdpr.models.winch``.
Tarantola, A. (2005). Inverse Problem Theory and Methods for Model Parameter Estimation, SIAM,
section 3.2 (least squares with a Gaussian prior, posterior covariance).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
import yaml
from scipy.optimize import least_squares

from cdpr.analyses.calibration.identify import identifiability
from cdpr.errors import CdprError, ConfigError
from cdpr.models import winch
from cdpr.units import quantity

#: Default line noise sd [m] of the motor-angle rows (one line, after the spool model).
SIGMA_LINE_DEFAULT = 1e-3
#: Default sd of a measured position [m] when the data have no ``sigma_m`` column.
SIGMA_POSITION_DEFAULT = 1e-3
#: Prior sd by default: anchors [m]; spools: the spool radius at the origin [m].
DEFAULT_PRIORS = {"anchors": 5e-3, "spools": 1e-3}
#: Prior sd of the buildup factor Q [m] (M666 Q 0.05 mm).
BUILDUP_PRIOR_SD = 5e-5
#: The groups a motor-angle calibration estimates.
MOTOR_GROUPS = ("anchors", "spools")
#: A sample whose motor angles are all within this of 0 [deg] (and that has forces) is the reference.
REFERENCE_DEG = 1.0
#: The models of a motor-angle calibration.
MOTOR_MODELS = ("exact", "standard")

POSE = ["x_m", "y_m", "z_m"]


@dataclasses.dataclass
class MotorData:
    """Motor-angle samples (``read_motor_data``): sample (n,) labels; motor_deg (n, m) [deg]; force
    (n, m) [N], NaN rows where not measured; pose (n, 3) [m], NaN rows where not measured; sigma (n,)
    [m] the position sd; source: the file."""

    sample: np.ndarray
    motor_deg: np.ndarray
    force: np.ndarray
    pose: np.ndarray
    sigma: np.ndarray
    source: str

    @property
    def has_pose(self):
        return np.isfinite(self.pose).all(axis=1)

    @property
    def has_force(self):
        return np.isfinite(self.force).all(axis=1)

    def subset(self, idx):
        return dataclasses.replace(
            self,
            sample=self.sample[idx],
            motor_deg=self.motor_deg[idx],
            force=self.force[idx],
            pose=self.pose[idx],
            sigma=self.sigma[idx],
        )


def is_motor_table(path):
    """True when the CSV at ``path`` has a ``motor_deg_1`` column (a motor-angle table).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    bool
    """
    try:
        cols = pd.read_csv(path, nrows=0).columns
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError):
        return False  # read_data says what is wrong with it
    return any(str(c).startswith("motor_deg_") for c in cols)


def read_motor_data(path, robot):
    """Read and check a motor-angle table (module docstring) for ``robot``.

    Parameters
    ----------
    path : str or Path
    robot : Robot
        Every cable needs a spool winch; its cable count fixes the columns.

    Returns
    -------
    MotorData

    Raises
    ------
    ConfigError
        One line naming the file, the column and what is allowed: missing, unknown or extra columns,
        a column count that does not match the robot, non-numbers, non-finite angles, forces half
        given or negative, half-given positions, sigma_m <= 0.
    """
    src = str(path)
    try:
        df = pd.read_csv(path)
    except FileNotFoundError:
        raise ConfigError(src, None, "the data file does not exist") from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ConfigError(src, None, f"cannot read it as CSV ({str(exc).splitlines()[0]})") from None
    if any(s is None for s in robot.spools):
        raise ConfigError(
            src, "motor_deg_1", f"motor angles need a spool winch on every cable; robot {robot.name} has none"
        )
    m = robot.m
    cols = [str(c) for c in df.columns]
    mcols = [f"motor_deg_{i}" for i in range(1, m + 1)]
    fcols = [f"force_N_{i}" for i in range(1, m + 1)]
    allowed = ["sample", *mcols, *fcols, *POSE, "sigma_m"]
    for c in cols:
        if c not in allowed:
            raise ConfigError(
                src,
                c,
                f"unknown column; allowed: sample, motor_deg_1..motor_deg_{m}, force_N_1..force_N_{m}, "
                "x_m, y_m, z_m, sigma_m (robot "
                f"{robot.name} has {m} cables)",
            )
    for c in ["sample", *mcols]:
        if c not in cols:
            raise ConfigError(
                src, c, f"missing column; a motor-angle table needs sample, motor_deg_1..motor_deg_{m}"
            )
    for group, what in (
        (fcols, "forces need all of force_N_1..force_N_%d" % m),
        (POSE, "positions need all of x_m, y_m, z_m"),
    ):
        given = [c for c in group if c in cols]
        if given and len(given) != len(group):
            raise ConfigError(src, next(c for c in group if c not in cols), what + " (or none)")
    if len(df) == 0:
        raise ConfigError(src, None, "no samples")
    deg = _numbers(df, mcols, src)
    for j, c in enumerate(mcols):
        bad = ~np.isfinite(deg[:, j])
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise ConfigError(src, c, f"row {r + 1}: {float(deg[r, j])!r}; motor angles must be finite [deg]")
    n = len(df)
    force = np.full((n, m), np.nan)
    if fcols[0] in cols:
        force = _numbers(df, fcols, src)
        fin = np.isfinite(force)
        bad = (fin.any(axis=1) & ~fin.all(axis=1)) | (force < 0).any(axis=1) | np.isinf(force).any(axis=1)
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            c = fcols[int(np.flatnonzero(~fin[r] | (force[r] < 0) | np.isinf(force[r]))[0])]
            raise ConfigError(src, c, f"row {r + 1}: forces must be all finite and >= 0 [N] (or all empty)")
    pose = np.full((n, 3), np.nan)
    if "x_m" in cols:
        pose = _numbers(df, POSE, src)
        fin = np.isfinite(pose)
        bad = (fin.any(axis=1) & ~fin.all(axis=1)) | np.isinf(pose).any(axis=1)
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            c = POSE[int(np.flatnonzero(~fin[r])[0])]
            raise ConfigError(
                src, c, f"row {r + 1}: a position needs all three finite x_m, y_m, z_m (or none)"
            )
    sigma = np.full(n, SIGMA_POSITION_DEFAULT)
    if "sigma_m" in cols:
        sigma = _numbers(df, ["sigma_m"], src)[:, 0]
        bad = np.isfinite(pose).all(axis=1) & ~(np.isfinite(sigma) & (sigma > 0))
        if bad.any():
            r = int(np.flatnonzero(bad)[0])
            raise ConfigError(
                src, "sigma_m", f"row {r + 1}: {float(sigma[r])!r}; sigma_m must be finite and > 0 [m]"
            )
    return MotorData(
        sample=df["sample"].astype(str).to_numpy(),
        motor_deg=deg,
        force=force,
        pose=pose,
        sigma=sigma,
        source=src,
    )


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


# ---- priors and parameters ------------------------------------------------------------------
def parse_motor_priors(text, estimate, source="--prior"):
    """Prior sd of a motor-angle calibration from ``G=SD,...`` (``anchors=150mm,spools=1mm``).

    Parameters
    ----------
    text : str or None
    estimate : sequence of str
        The groups estimated (``MOTOR_GROUPS``); a prior for another group is refused.
    source : str
        Named in the error message.

    Returns
    -------
    priors : dict group -> float [m]
    """
    out = dict(DEFAULT_PRIORS)
    for g in estimate:
        if g not in MOTOR_GROUPS:
            raise CdprError(
                f"--estimate {g}: a motor-angle calibration estimates {', '.join(MOTOR_GROUPS)} only"
            )
    if not text:
        return out
    for item in str(text).split(","):
        if "=" not in item:
            raise CdprError(f"{source}: expected GROUP=SD, got {item!r}; e.g. anchors=150mm,spools=1mm")
        g, v = (s.strip() for s in item.split("=", 1))
        if g not in MOTOR_GROUPS:
            raise CdprError(
                f"{source}: unknown group {g!r} for motor-angle data; allowed: {', '.join(MOTOR_GROUPS)}"
            )
        sd = quantity(v, "m", source, g)
        if not (math.isfinite(sd) and sd > 0):
            raise CdprError(f"{source}: the prior sd of {g} must be > 0, got {v!r}")
        if g not in estimate:
            raise CdprError(
                f"{source}: a prior for {g}, which is not estimated (--estimate {','.join(estimate)}); "
                f"remove it or add {g} to --estimate"
            )
        out[g] = sd
    return out


@dataclasses.dataclass
class SpoolModel:
    """What the motor-angle model needs of a robot: anchors A (m, 3) [m], dead lengths d (m,) [m],
    spool radii r0 (m,) [m], buildup factors Q (m,) [m], U, lines per spool O (``lines``), the gear ratio L/H (m,), the
    strands' axial stiffness K = U E S (m,) [N]."""

    A: np.ndarray
    d: np.ndarray
    r0: np.ndarray
    Q: np.ndarray
    U: np.ndarray
    lines: np.ndarray
    ratio: np.ndarray
    K: np.ndarray

    @classmethod
    def of(cls, robot):
        sp = robot.spools
        if any(s is None for s in sp):
            raise CdprError(f"{robot.source}: motor angles need a spool winch on every cable")
        if (robot.arrays.kind != 0).any():
            raise CdprError(
                f"{robot.source}: the motor-angle calibration knows fixed anchors only (pulley.kind: fixed)"
            )
        if any(np.any(np.asarray(c.B) != 0) for c in robot.cables):
            raise CdprError(f"{robot.source}: the motor-angle calibration is for a point mass")
        return cls(
            A=np.array([c.A for c in robot.cables], dtype=float),
            d=np.asarray(robot.arrays.d, dtype=float).copy(),
            r0=np.array([s.r0 for s in sp], dtype=float),
            Q=np.array([s.Q for s in sp], dtype=float),
            U=np.array([s.U for s in sp], dtype=float),
            lines=np.array([s.lines_per_spool for s in sp], dtype=float),
            ratio=np.array([s.motor_teeth / s.spool_teeth for s in sp], dtype=float),
            K=np.asarray(robot.arrays.ES, dtype=float).copy(),
        )

    def theta(self):
        return np.concatenate([self.A.ravel(), self.r0, self.Q])

    def with_theta(self, th):
        m = len(self.r0)
        return dataclasses.replace(
            self, A=th[: 3 * m].reshape(m, 3), r0=th[3 * m : 4 * m], Q=th[4 * m : 5 * m]
        )


def motor_names(m):
    """Names of the motor-angle parameter vector: A_1_x .. A_m_z, r0_1 .. r0_m, Q_1 .. Q_m."""
    return (
        [f"A_{i + 1}_{a}" for i in range(m) for a in "xyz"]
        + [f"r0_{i + 1}" for i in range(m)]
        + [f"Q_{i + 1}" for i in range(m)]
    )


def _index(m, groups):
    idx = []
    if "anchors" in groups:
        idx += list(range(3 * m))
    if "spools" in groups:
        idx += list(range(3 * m, 5 * m))
    return np.array(idx, dtype=int)


def _prior_sd(m, index, priors):
    sd = np.empty(len(index))
    for j, k in enumerate(index):
        sd[j] = priors["anchors"] if k < 3 * m else (priors["spools"] if k < 4 * m else BUILDUP_PRIOR_SD)
    return sd


def reference_forces(data, model):
    """The forces at the encoder reference t_ref (m,) [N] and a warning (or None): the first sample
    whose motor angles are all within ``REFERENCE_DEG`` of 0 and that has forces (the exact model
    only; zero for ``standard``).

    Parameters
    ----------
    data : MotorData
    model : {"exact", "standard"}

    Returns
    -------
    t_ref : ndarray (m,) [N]
    warning : str or None
    """
    m = data.motor_deg.shape[1]
    if model == "standard" or not data.has_force.any():
        return np.zeros(m), None
    ref = np.flatnonzero((np.abs(data.motor_deg) <= REFERENCE_DEG).all(axis=1) & data.has_force)
    if not len(ref):
        return np.zeros(m), (
            f"{data.source}: no sample at the encoder reference (motor angles within {REFERENCE_DEG:g} deg of 0) "
            "has forces; the line stretch at the reference is taken as zero"
        )
    return data.force[ref[0]].copy(), None


def _stretch(model, data, t_ref, K):
    """f (n, m) = 1 + t / K where the exact model has forces (1 elsewhere), g (m,) = 1 / (1 + t_ref / K)."""
    n, m = data.motor_deg.shape
    f = np.ones((n, m))
    if model == "exact":
        hf = data.has_force
        f[hf] = 1.0 + data.force[hf] / K
    return f, 1.0 / (1.0 + t_ref / K)


def line_terms(sm, motor_deg, f, g):
    """The predicted line l_pred (n, m) [m] minus d (so it compares with |A_i - P|) and the spool
    angle phi (n, m) [rad]."""
    phi = np.deg2rad(motor_deg) * sm.ratio
    s = winch.released_line(phi, sm.r0, sm.Q, sm.lines)
    l0 = np.linalg.norm(sm.A, axis=1) + sm.d
    return (l0 * g + s / sm.U) * f - sm.d, phi


def line_residuals(sm, data, P, f, g):
    """Line residuals |A_i - P_k| + d_i - l_pred,ki (n, m) [m] of the motor-angle model.

    Parameters
    ----------
    sm : SpoolModel
    data : MotorData
    P : ndarray (n, 3) [m]
        Mover positions.
    f, g : ndarray
        ``_stretch``.

    Returns
    -------
    r : ndarray (n, m) [m]
    """
    pred, _ = line_terms(sm, data.motor_deg, f, g)
    return np.linalg.norm(P[:, None, :] - sm.A, axis=-1) - pred


# ---- solving positions -------------------------------------------------------------------------
def solve_positions(sm, data, f, g, start=None, iterations=60):
    """Each sample's position from its readings alone: Gauss-Newton on its m line residuals
    (least squares, 3 unknowns), vectorised over samples.

    Parameters
    ----------
    sm : SpoolModel
    data : MotorData
    f, g : ndarray
        ``_stretch``.
    start : ndarray (n, 3), optional
        Start positions [m] (default: the anchors' centroid).
    iterations : int

    Returns
    -------
    P : ndarray (n, 3) [m]
    line_rms : ndarray (n,) [m]
        RMS of the m line residuals at P (NaN where not converged).
    """
    n = len(data.sample)
    pred, _ = line_terms(sm, data.motor_deg, f, g)
    P = np.tile(sm.A.mean(axis=0), (n, 1)) if start is None else np.array(start, dtype=float)
    for _ in range(iterations):
        diff = P[:, None, :] - sm.A
        dist = np.linalg.norm(diff, axis=-1)
        r = dist - pred
        u = diff / dist[..., None]
        JtJ = np.einsum("nia,nib->nab", u, u) + 1e-12 * np.eye(3)
        step = np.linalg.solve(JtJ, np.einsum("nia,ni->na", u, r)[..., None])[..., 0]
        P = P - step
        if np.nanmax(np.abs(step)) < 1e-13:
            break
    r = np.linalg.norm(P[:, None, :] - sm.A, axis=-1) - pred
    rms = np.sqrt(np.mean(r**2, axis=1))
    return P, np.where(np.isfinite(rms), rms, np.nan)


# ---- the fit -------------------------------------------------------------------------------------
@dataclasses.dataclass
class MotorCalibration:
    """The result of ``fit_motor``: the estimate, its posterior and identifiability, the positions."""

    robot: object
    model: str
    groups: list
    index: np.ndarray
    names: list
    nominal: np.ndarray
    estimate: np.ndarray
    prior_sd: np.ndarray
    ident: dict
    spool_model: SpoolModel
    positions: np.ndarray
    line_residual: np.ndarray
    table: pd.DataFrame
    source: str
    gauge: str
    warnings: list
    cost: float
    nfev: int

    @property
    def sd(self):
        """Posterior sd [m] (Gauss-Newton at the MAP, the positions marginalised)."""
        return self.ident["ratio"] * self.prior_sd

    @property
    def covariance(self):
        """Posterior covariance of the estimated parameters [m^2] (the positions marginalised)."""
        return self.ident["cov_scaled"] * np.outer(self.prior_sd, self.prior_sd)

    def summary(self):
        """The JSON of ``cdpr calibrate fit --json`` on motor-angle data (SI units)."""
        m = self.robot.m
        out = {
            "parameters": [
                {
                    "name": nm,
                    "group": "anchors" if k < 3 * m else "spools",
                    "cable": int(k // 3 + 1) if k < 3 * m else int((k - 3 * m) % m + 1),
                    "nominal": float(a),
                    "estimate": float(b),
                    "sd": float(s),
                    "prior_sd": float(p),
                    "identified": str(lab),
                }
                for nm, k, a, b, s, p, lab in zip(
                    self.names,
                    self.index,
                    self.nominal,
                    self.estimate,
                    self.sd,
                    self.prior_sd,
                    self.ident["labels"],
                )
            ],
            "n_parameters": len(self.index),
            "rank": self.ident["rank"],
            "condition": float(self.ident["condition"]) if math.isfinite(self.ident["condition"]) else None,
            "singular_values": [float(s) for s in self.ident["singular_values"]],
            "unidentified": list(self.ident["unidentified"]),
            "gauge": self.gauge,
            "model": self.model,
            "line_rms_m": float(np.sqrt(np.mean(self.line_residual**2))),
            "residual_rms_m": _rms(self.table["position_residual_m"].to_numpy()),
            "samples_used": len(self.table),
            "samples_with_position": int(np.isfinite(self.table["position_residual_m"]).sum()),
            "samples_left_out": 0,
        }
        return out


def _rms(x):
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(np.sqrt(np.mean(x**2))) if len(x) else None


def gauge_words(data, groups):
    """The gauge of a motor-angle calibration in words (module docstring)."""
    if data.has_pose.any():
        return (
            "the encoder reference fixes the origin (mover at the origin at zero motor angle); "
            f"{int(data.has_pose.sum())} measured positions fix the frame's orientation"
            + (" and scale" if "spools" in groups else "")
        )
    return (
        "no measured position: the encoder reference fixes the origin (mover at the origin at zero motor "
        "angle); the frame's rotation about the origin"
        + (" and its scale (anchors, positions and spool radii together)" if "spools" in groups else "")
        + " are not seen by the data and are fixed by the priors alone"
    )


def motor_problem(sm0, data, index, sd, f, g, sigma_line=SIGMA_LINE_DEFAULT):
    """The MAP residual of a motor-angle calibration and its exact Jacobian, in the variables
    x = [(θ_index - θ0_index) / sd, P_1, .., P_n] (module docstring).

    Rows: the n m line rows (``line_residuals`` / sigma_line), 3 rows (P_k - y_k) / sigma_k per
    measured position, the k prior rows.

    Parameters
    ----------
    sm0 : SpoolModel
        The nominal robot (the prior mean).
    data : MotorData
    index : ndarray of int
        Estimated entries of ``motor_names``.
    sd : ndarray [m]
        Their prior sd.
    f, g : ndarray
        The stretch factors (``_stretch``).
    sigma_line : float [m]

    Returns
    -------
    residual, jacobian, unpack : callables of x
        unpack(x) gives (SpoolModel, P (n, 3) [m]).
    """
    m, n, k = len(sm0.r0), len(data.sample), len(index)
    th0 = sm0.theta()
    hp = data.has_pose
    ip = np.flatnonzero(hp)

    def unpack(x):
        th = th0.copy()
        th[index] += sd * x[:k]
        return sm0.with_theta(th), x[k:].reshape(n, 3)

    def residual(x):
        sm, P = unpack(x)
        r = line_residuals(sm, data, P, f, g) / sigma_line
        rp = (P[ip] - data.pose[ip]) / data.sigma[ip, None]
        return np.concatenate([r.ravel(), rp.ravel(), x[:k]])

    def jacobian(x):
        sm, P = unpack(x)
        diff = P[:, None, :] - sm.A
        u = diff / np.linalg.norm(diff, axis=-1, keepdims=True)  # (n, m, 3)
        phi = np.deg2rad(data.motor_deg) * sm.ratio
        nA = sm.A / np.linalg.norm(sm.A, axis=1, keepdims=True)
        J = np.zeros((n * m + 3 * len(ip) + k, k + 3 * n))
        for kk in range(n):
            J[kk * m : (kk + 1) * m, k + 3 * kk : k + 3 * kk + 3] = u[kk] / sigma_line
        for j, col in enumerate(index):
            dr = np.zeros((n, m))
            if col < 3 * m:
                c, ax = divmod(col, 3)
                dr[:, c] = -u[:, c, ax] - f[:, c] * g[c] * nA[c, ax]
            elif col < 4 * m:
                c = col - 3 * m
                dr[:, c] = -f[:, c] * phi[:, c] / sm.U[c]
            else:
                c = col - 4 * m
                dr[:, c] = f[:, c] * sm.lines[c] * phi[:, c] ** 2 / (4 * sm.U[c])
            J[: n * m, j] = (dr * sd[j] / sigma_line).ravel()
        for q, kk in enumerate(ip):
            J[n * m + 3 * q : n * m + 3 * q + 3, k + 3 * kk : k + 3 * kk + 3] = np.eye(3) / data.sigma[kk]
        J[n * m + 3 * len(ip) :, :k] = np.eye(k)
        return J

    return residual, jacobian, unpack


def fit_motor(robot, data, groups, priors=None, model="exact", sigma_line=SIGMA_LINE_DEFAULT):
    """MAP self-calibration from motor angles with every position a nuisance (module docstring).

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
    index = _index(m, groups)
    k = len(index)
    sd = _prior_sd(m, index, priors)
    th0 = sm0.theta()
    t_ref, warn = reference_forces(data, model)
    f, g = _stretch(model, data, t_ref, sm0.K)
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
    Q, _ = np.linalg.qr(J[:, k:])
    Jth = J[:, :k]
    names_all = motor_names(m)
    names = [names_all[c] for c in index]
    ident = identifiability(Jth - Q @ (Q.T @ Jth), names)
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


# ---- prediction: check and cross-validation -----------------------------------------------------
def predict_samples(sm, data, model, t_ref):
    """Positions solved from each sample's readings (and forces in the exact model), their line RMS
    and, where measured, the position error.

    Parameters
    ----------
    sm : SpoolModel
    data : MotorData
    model : {"exact", "standard"}
    t_ref : ndarray (m,) [N]
        ``reference_forces``.

    Returns
    -------
    list of dict
        One per sample: sample, x_m, y_m, z_m (solved from the anchors' centroid, never from the
        measured position), error_m (None without a measured position), line_rms_m, status.
    """
    f, g = _stretch(model, data, t_ref, sm.K)
    # from the anchors' centroid, never from the measured position (a held-out sample's is the answer)
    P, rms = solve_positions(sm, data, f, g)
    out = []
    for k in range(len(data.sample)):
        ok = bool(np.isfinite(P[k]).all() and np.isfinite(rms[k]))
        err = float(np.linalg.norm(P[k] - data.pose[k])) if (ok and data.has_pose[k]) else None
        st = "ok" if ok else "no solution"
        if ok and model == "exact" and not data.has_force[k]:
            st = "no forces: rigid lines"
        out.append(
            {
                "sample": str(data.sample[k]),
                "x_m": float(P[k, 0]) if ok else None,
                "y_m": float(P[k, 1]) if ok else None,
                "z_m": float(P[k, 2]) if ok else None,
                "error_m": err,
                "line_rms_m": float(rms[k]) if ok else None,
                "status": st,
            }
        )
    return out


def check_motor(robot, data, model="exact"):
    """``cdpr calibrate check`` on motor-angle data: each sample's position solved from its readings
    against the measured one.

    Parameters
    ----------
    robot : Robot
    data : MotorData
    model : {"exact", "standard"}

    Returns
    -------
    dict
        n (samples with a measured position and a solution), rms_m, max_m, median_m, line_rms_m,
        model, samples (``predict_samples``).
    """
    t_ref, warn = reference_forces(data, model)
    rows = predict_samples(SpoolModel.of(robot), data, model, t_ref)
    e = np.array([r["error_m"] for r in rows if r["error_m"] is not None])
    lr = np.array([r["line_rms_m"] for r in rows if r["line_rms_m"] is not None])
    return {
        "n": len(e),
        "rms_m": float(np.sqrt(np.mean(e**2))) if len(e) else None,
        "max_m": float(e.max()) if len(e) else None,
        "median_m": float(np.median(e)) if len(e) else None,
        "line_rms_m": float(np.sqrt(np.mean(lr**2))) if len(lr) else None,
        "model": model,
        "samples": rows,
        **({"data_warnings": [warn]} if warn else {}),
    }


def fold_of(n, folds):
    """Fold of each sample: the 0-based row index i is in fold i mod K.

    Parameters
    ----------
    n : int
        Samples.
    folds : int
        K, 2 <= K <= n (K = n: leave-one-out).

    Returns
    -------
    ndarray (n,) of int
    """
    if not (2 <= folds <= n):
        raise CdprError(
            f"--folds {folds}: needs 2 <= K <= {n} (the number of samples; K = {n} is leave-one-out)"
        )
    return np.arange(n) % folds


def cross_validate(
    robot, data, groups=(), priors=None, model="exact", folds=5, fixed=False, sigma_line=SIGMA_LINE_DEFAULT
):
    """K-fold cross-validation of a motor-angle calibration (``cdpr calibrate cv``).

    Fold k holds the samples whose 0-based row index i has i mod K = k. For each fold: fit on the
    other folds (``fit_motor``; with ``fixed`` the robot as given), solve each held-out sample's
    position from its readings (``predict_samples``) and compare it with the measured one where
    measured; the held-out line RMS is that of the redundant line equations at the solved position.

    Parameters
    ----------
    robot : Robot
    data : MotorData
    groups : list of str
        Estimated groups (ignored with ``fixed``).
    priors : dict, optional
    model : {"exact", "standard"}
    folds : int
    fixed : bool
        Score ``robot`` without fitting.
    sigma_line : float [m]

    Returns
    -------
    dict
        folds (list: fold, samples, heldout_position_rms_m, heldout_position_median_m,
        heldout_line_rms_m, train_rms_m), the same four overall, per_sample, n_folds, model,
        estimate, fixed, gauge, warnings.
    """
    n = len(data.sample)
    fold = fold_of(n, folds)
    t_ref, warn = reference_forces(data, model)  # the session's reference, from all samples
    per_sample, out_folds, train_sq = [], [], []
    gauge = None
    for kf in range(folds):
        held = np.flatnonzero(fold == kf)
        train = np.flatnonzero(fold != kf)
        tdata = data.subset(train)
        if fixed:
            sm = SpoolModel.of(robot)
            f, g = _stretch(model, tdata, t_ref, sm.K)
            _, trms = solve_positions(sm, tdata, f, g)
            tres = trms[np.isfinite(trms)]
            train_rms = float(np.sqrt(np.mean(tres**2)))
            train_sq.append(tres**2)
        else:
            cal = fit_motor(robot, tdata, groups, priors, model, sigma_line)
            sm = dataclasses.replace(cal.spool_model)
            train_rms = float(np.sqrt(np.mean(cal.line_residual**2)))
            train_sq.append(np.mean(cal.line_residual**2, axis=1))
            gauge = cal.gauge
        rows = predict_samples(sm, data.subset(held), model, t_ref)
        for r in rows:
            r["fold"] = kf
        per_sample += rows
        out_folds.append(
            {
                "fold": kf,
                "samples": [str(s) for s in data.sample[held]],
                **_scores(rows),
                "train_rms_m": train_rms,
            }
        )
    order = np.argsort(np.concatenate([np.flatnonzero(fold == kf) for kf in range(folds)]), kind="stable")
    per_sample = [per_sample[i] for i in order]
    tsq = np.concatenate(train_sq)
    return {
        "folds": out_folds,
        **_scores(per_sample),
        "train_rms_m": float(np.sqrt(np.mean(tsq))),
        "per_sample": per_sample,
        "n_folds": folds,
        "model": model,
        "estimate": [] if fixed else list(groups),
        "fixed": bool(fixed),
        "gauge": gauge,
        "data_warnings": [w for w in (warn,) if w],
    }


def _scores(rows):
    e = np.array([r["error_m"] for r in rows if r["error_m"] is not None])
    lr = np.array([r["line_rms_m"] for r in rows if r["line_rms_m"] is not None])
    return {
        "heldout_position_rms_m": float(np.sqrt(np.mean(e**2))) if len(e) else None,
        "heldout_position_median_m": float(np.median(e)) if len(e) else None,
        "heldout_line_rms_m": float(np.sqrt(np.mean(lr**2))) if len(lr) else None,
        "heldout_with_position": len(e),
    }


# ---- the calibrated robot file ----------------------------------------------------------------------
def motor_robot_mapping(robot_mapping, sm):
    """A robot file's mapping with the anchors and every cable's spool radius and buildup factor of
    ``sm`` (plain SI numbers, per cable).

    Parameters
    ----------
    robot_mapping : dict
        The robot file as loaded by YAML.
    sm : SpoolModel

    Returns
    -------
    dict
    """
    doc = dict(robot_mapping)
    cables = []
    for i, c in enumerate(doc["cables"]):
        c = dict(c)
        c["A_m"] = [float(x) for x in sm.A[i]]
        w = dict(c.get("winch") or {})
        w["spool_radius_m"] = float(sm.r0[i])
        w["buildup_factor_m"] = float(sm.Q[i])
        c["winch"] = w
        cables.append(c)
    doc["cables"] = cables
    return doc


def motor_robot_text(cal, data_source, when):
    """The calibrated robot file of a motor-angle fit: the nominal robot file with the estimated
    anchors and spools per cable, and a header naming the data, the model, the gauge and the time.

    Parameters
    ----------
    cal : MotorCalibration
    data_source : str
        The data file, named in the header.
    when : datetime.datetime
        The time of the calibration (ISO 8601, to the second).

    Returns
    -------
    str
        YAML with a comment header, ending in a newline.
    """
    try:
        with open(cal.robot.source, encoding="utf-8") as fh:
            doc = yaml.safe_load(fh)
    except OSError as exc:
        raise CdprError(f"{cal.robot.source}: cannot read the nominal robot file ({exc})") from None
    doc = motor_robot_mapping(doc, cal.spool_model)
    doc["name"] = f"{doc.get('name', cal.robot.name)} (calibrated)"
    header = [
        f"# {cal.robot.name} calibrated by cdpr calibrate fit ({cal.model} model, motor angles) from {data_source}",
        f"# on {when.isoformat(timespec='seconds')}; nominal robot: {cal.robot.source}",
        f"# estimated: {', '.join(cal.names)}",
        f"# gauge: {cal.gauge}",
    ]
    return "\n".join(header) + "\n" + yaml.safe_dump(doc, sort_keys=False)


def simulate_motor(
    truth, P, force=None, sigma_line=0.0, rng=None, measured=None, sigma=SIGMA_POSITION_DEFAULT
):
    """Motor-angle samples of a robot ``truth`` at positions P, the inverse of the model (module
    docstring): the line l_i(P) = |A_i - P| + d_i under the force t stretches from the rest length
    L0 = l / (1 + t / K); the spool released s = U (L0 - L0_ref) with L0_ref = l_i(0) / (1 + t_ref / K),
    t_ref the forces of the first sample (put it at the origin: the encoders are zeroed there, so it
    reads 0 without noise); the motor angle releasing s
    (``winch.spool_angle_of_line``, ``winch.motor_degrees``). Without forces, rigid lines.

    Parameters
    ----------
    truth : Robot
    P : ndarray (n, 3) [m]
        True positions.
    force : ndarray (n, m) [N], optional
        Line forces (recorded in the data); None: rigid lines, no force columns.
    sigma_line : float [m]
        Noise sd added to each line (through its motor angle).
    rng : numpy Generator, optional
    measured : ndarray of bool (n,), optional
        Samples whose position is recorded (with noise ``sigma``); default none.
    sigma : float [m]
        Position noise sd.

    Returns
    -------
    MotorData
    """
    sm = SpoolModel.of(truth)
    P = np.asarray(P, dtype=float)
    n, m = len(P), len(sm.r0)
    rng = np.random.default_rng(0) if rng is None else rng
    ell = np.linalg.norm(P[:, None, :] - sm.A, axis=-1) + sm.d
    ell0 = np.linalg.norm(sm.A, axis=1) + sm.d
    if force is None:
        L0, L0_ref, F = ell, ell0, np.full((n, m), np.nan)
    else:
        F = np.asarray(force, dtype=float)
        L0, L0_ref = ell / (1.0 + F / sm.K), ell0 / (1.0 + F[0] / sm.K)
    noise = sigma_line * rng.standard_normal((n, m))
    noise[0] = 0.0  # the encoders are zeroed at the first sample: it reads 0 exactly
    L0 = L0 + noise
    s = sm.U * (L0 - L0_ref)
    phi = winch.spool_angle_of_line(s, sm.r0, sm.Q, sm.lines)
    deg = np.rad2deg(phi) / sm.ratio
    meas = np.zeros(n, dtype=bool) if measured is None else np.asarray(measured, dtype=bool)
    pose = np.full((n, 3), np.nan)
    pose[meas] = P[meas] + sigma * rng.standard_normal((int(meas.sum()), 3))
    return MotorData(
        sample=np.array([str(i) for i in range(n)]),
        motor_deg=deg,
        force=F,
        pose=pose,
        sigma=np.full(n, sigma),
        source="simulated",
    )
