"""The calibration data: the measured samples (``Data``), the CSV table they come from
(``read_data``, every bad input one ``ConfigError`` line naming the file, the column and what is
allowed) and the table they go back to (``data_frame``; ``cdpr.pipeline.calibration_files.data_frame``
writes it).

Columns (docs/calibration.md): sample, L1..Lm (commanded rest lengths) or L_enc1..L_encm (encoder
readings = rest length + an unknown offset), x_m, y_m, z_m, and for a 6-DoF platform rx_rad, ry_rad,
rz_rad; optional sigma_m (and sigma_rad), tensions t1_N..tm_N and sigma_N.

Motor-angle data of a spool robot (a Hangprinter; ``MotorData``, ``read_motor_data``; a contract,
docs/calibration.md and docs/hangprinter.md): ``sample``, ``motor_deg_1..m`` (the motor shaft angle
from the encoder [deg], relative to the reference taken with the mover at the origin; positive =
line paid out), optional ``force_N_1..m`` (the line force the drivers report [N], the force of the
cable on the mover), optional ``x_m, y_m, z_m`` (measured position, all three or none per sample)
and optional ``sigma_m``. ``cdpr.analyses.calibration.motor`` turns a motor angle into line.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from cdpr.errors import ConfigError
from cdpr.parameters import (
    is_spatial,
)

#: Default tracker noise [m] when the data have no ``sigma_m`` column.
SIGMA_DEFAULT = 0.2e-3
#: Default orientation noise [rad] of a 6-DoF tracker when the data have no ``sigma_rad`` column.
SIGMA_RAD_DEFAULT = 1e-3
#: Default tension-sensor noise [N] when the data have tensions but no ``sigma_N`` column.
SIGMA_T_DEFAULT = 5.0
#: Default sd of a measured position [m] of motor-angle data without a ``sigma_m`` column.
SIGMA_POSITION_DEFAULT = 1e-3

POSE = ["x_m", "y_m", "z_m"]
ORIENTATION = ["rx_rad", "ry_rad", "rz_rad"]


class _Samples:
    """What every table of samples has: ``has_pose`` and ``subset`` (a dataclass whose per-sample
    fields are arrays with one row per sample, ``pose`` among them)."""

    @property
    def has_pose(self):
        return np.isfinite(self.pose).all(axis=1)

    def subset(self, idx):
        """The samples ``idx`` (every per-sample array field indexed, the rest kept)."""
        rows = {
            f.name: getattr(self, f.name)[idx]
            for f in dataclasses.fields(self)
            if isinstance(getattr(self, f.name), np.ndarray)
        }
        return dataclasses.replace(self, **rows)


@dataclasses.dataclass
class Data(_Samples):
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
    def has_tension(self):
        return np.isfinite(self.tension).all(axis=1)


@dataclasses.dataclass
class MotorData(_Samples):
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
    def has_force(self):
        return np.isfinite(self.force).all(axis=1)


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
    src, df = str(path), _read_csv(path)
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
    need = data_columns(m, enc, spatial)
    missing = [c for c in need if c not in cols]
    if missing:
        platform = f"robot {robot.name} has a 6-DoF platform, " if spatial else ""
        raise ConfigError(
            src, missing[0], f"missing column; {platform}a calibration table needs {', '.join(need)}"
        )
    sigmas = ["sigma_m", "sigma_rad"] if spatial else ["sigma_m"]
    Tcols = [f"t{i}_N" for i in range(1, m + 1)]
    extra = [c for c in cols if c not in set(need) | set(sigmas) | {"sigma_N"} | set(Tcols)]
    if extra:
        raise ConfigError(
            src,
            extra[0],
            f"unknown column; allowed: {', '.join(need)}, {', '.join(sigmas)}, t1_N..t{m}_N, sigma_N",
        )
    given = _tension_names(cols, src, m)
    if len(df) == 0:
        raise ConfigError(src, None, "no samples")
    L = _lengths(df, [f"{prefix}{i}" for i in range(1, m + 1)], src)
    pose_cols = POSE + ORIENTATION if spatial else POSE
    pose = _numbers(df, pose_cols, src)
    fin = np.isfinite(pose)
    bad = (fin.any(axis=1) & ~fin.all(axis=1)) | np.isinf(pose).any(axis=1)
    if bad.any():
        r = int(np.flatnonzero(bad)[0])
        if spatial:
            col = pose_cols[int(np.flatnonzero(~fin[r])[0])]
            raise ConfigError(
                src, col, f"row {r + 1}: a 6-DoF pose needs all six finite values x_m..rz_rad (or none)"
            )
        raise ConfigError(
            src, "x_m,y_m,z_m", f"row {r + 1}: a pose needs all three finite coordinates (or none)"
        )
    if not fin.all(axis=1).all() and not enc and not given:
        r = int(np.flatnonzero(~fin.all(axis=1))[0])
        raise ConfigError(
            src,
            "x_m" if spatial else "x_m,y_m,z_m",
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
    orientation = {"rotvec": pose[:, 3:], "sigma_rad": sig["sigma_rad"]} if spatial else {}
    return Data(
        sample=df["sample"].astype(str).to_numpy(),
        L=L,
        pose=pose[:, :3],
        sigma=sig["sigma_m"],
        encoder=enc,
        source=src,
        tension=tension,
        sigma_t=sigma_t,
        **orientation,
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
    """Read and check a motor-angle table (the module docstring) for ``robot``.

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
    src, df = str(path), _read_csv(path)
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


def _read_csv(path):
    """The CSV at ``path`` as a DataFrame; ConfigError naming the file when it does not exist or is
    not CSV."""
    try:
        return pd.read_csv(path)
    except FileNotFoundError:
        raise ConfigError(str(path), None, "the data file does not exist") from None
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ConfigError(str(path), None, f"cannot read it as CSV ({str(exc).splitlines()[0]})") from None


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


def data_frame(data, robot):
    """The calibration table of ``data`` (the columns ``read_data`` reads), as
    ``cdpr.pipeline.calibration_files.data_frame`` writes it: sample, L1..Lm (L_enc1..L_encm for
    encoder data), x_m, y_m, z_m, for a 6-DoF platform rx_rad, ry_rad, rz_rad, sigma_m (and
    sigma_rad), and where any tension is measured t1_N..tm_N and sigma_N.

    Parameters
    ----------
    data : Data
    robot : Robot
        Its cable count and kind (point mass or 6-DoF platform) fix the columns.

    Returns
    -------
    DataFrame
        One row per sample [m, rad, N].
    """
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
    return df
