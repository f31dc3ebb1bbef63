"""The winches of a robot file: the Métillon drum (``winch:`` with Table 1's keys, ``kind: drum`` or no
kind) and the Hangprinter spool (``kind: spool``, RepRapFirmware's M666 constants), read and checked
as the robot file's other keys are (one line naming the file and the key). The equations are in
``cdpr.models.winch`` and ``cdpr.models.drive``; ``cdpr.robot`` attaches a winch to each cable.
"""

from __future__ import annotations

import dataclasses
import math

from cdpr.errors import ConfigError
from cdpr.units import DIMENSIONLESS, quantity
from cdpr.validation import read_yaml


@dataclasses.dataclass(frozen=True)
class WinchParams:
    """Description of one winch: the parameters of its quadratic (Métillon 2022, Table 1), SI units
    (the equations are in ``cdpr.models.winch``).

    k_w coiling coefficient [m/rad]; l_u0 initial uncoiled length [m]; q0 initial joint angle [rad];
    q_max drum angle at full coiling [rad]; l_AE1 |A E1| [m]; l_E1E2 coiling length [m];
    alpha_E1 angle between AE1 and E1E2 [rad].
    """

    k_w: float
    l_u0: float
    q0: float
    q_max: float
    l_AE1: float
    l_E1E2: float
    alpha_E1: float


#: Table 1 of the winch seed.
TABLE1 = WinchParams(
    k_w=0.07460068, l_u0=5.9261, q0=94.2478, q_max=188.4956, l_AE1=2.6848, l_E1E2=0.06, alpha_E1=1.6906
)

#: A winch mapping's keys (robot files, winch files) -> (WinchParams field, unit).
WINCH_KEYS = {
    "k_w_m": ("k_w", "m"),
    "l_u0_m": ("l_u0", "m"),
    "q0_rad": ("q0", "rad"),
    "q_max_rad": ("q_max", "rad"),
    "l_AE1_m": ("l_AE1", "m"),
    "l_E1E2_m": ("l_E1E2", "m"),
    "alpha_E1_rad": ("alpha_E1", "rad"),
}


def params_from_mapping(data, source, key=""):
    """WinchParams from a mapping of the keys of ``WINCH_KEYS`` (k_w_m, l_u0_m, q0_rad, q_max_rad,
    l_AE1_m, l_E1E2_m, alpha_E1_rad; SI values or strings with units); missing keys take Table 1's
    values. Errors name ``source`` and ``key`` (the mapping's place in its file).

    Parameters
    ----------
    data : dict
        Winch parameters by key: lengths [m], angles [rad], as numbers or strings with units
        (``"60 mm"``). Every value but alpha_E1_rad must be > 0; alpha_E1_rad lies in [0, pi];
        q0_rad must lie in [0, q_max_rad].
    source : str
        Name of the file (or other origin) for error messages.
    key : str
        Dotted place of the mapping in that file, for error messages ('' at the top level).

    Returns
    -------
    WinchParams
        The parameters of Métillon 2022 Table 1 with the given values, SI units.

    Raises
    ------
    ConfigError
        For an unknown key, a value with the wrong unit or out of range.
    """
    if not isinstance(data, dict):
        raise ConfigError(source, key or None, "expected a mapping of winch parameters")
    prefix = f"{key}." if key else ""
    values = dataclasses.asdict(TABLE1)
    for k, val in data.items():
        if k not in WINCH_KEYS:
            raise ConfigError(source, prefix + str(k), f"unknown key; allowed: {', '.join(WINCH_KEYS)}")
        field, dim = WINCH_KEYS[k]
        v = quantity(val, dim, source, prefix + k)
        if field != "alpha_E1" and (v < 0 or (v == 0 and field != "q0")):
            raise ConfigError(
                source, prefix + k, f"must be {'>= 0' if field == 'q0' else 'strictly positive'}, got {val!r}"
            )
        if field == "alpha_E1" and not 0 <= v <= math.pi:
            raise ConfigError(
                source, prefix + k, f"an angle between two segments lies in [0, pi] rad, got {val!r}"
            )
        values[field] = v
    p = WinchParams(**values)
    if not 0 <= p.q0 <= p.q_max:
        raise ConfigError(
            source, prefix + "q0_rad", f"must lie in [0, q_max_rad] = [0, {p.q_max:g}], got {p.q0:g}"
        )
    return p


def load_winch_params(path):
    """Read WinchParams from a YAML file (keys as ``params_from_mapping``).

    Parameters
    ----------
    path : str or Path
        YAML file holding one mapping of winch parameters.

    Returns
    -------
    WinchParams
        SI units; missing keys take Table 1's values.
    """
    return params_from_mapping(read_yaml(path), path)


#: The keys of a spool winch (``winch: {kind: spool, ...}``) -> (SpoolParams field, unit, default);
#: None: required. The M666 letter of RepRapFirmware's Hangprinter kinematics in the comment.
SPOOL_KEYS = {
    "spool_radius_m": ("r0", "m", None),  # R (mm there): the spool radius with the mover at the origin
    "buildup_factor_m": ("Q", "m", 0.0),  # Q (mm there): r^2 = r0^2 - O Q s
    "mechanical_advantage": ("U", DIMENSIONLESS, 1),  # U: strands between anchor and mover
    "lines_per_spool": ("lines_per_spool", DIMENSIONLESS, 1),  # O
    "motor_gear_teeth": ("motor_teeth", DIMENSIONLESS, 1),  # L
    "spool_gear_teeth": ("spool_teeth", DIMENSIONLESS, 1),  # H
}
#: The integer keys of a spool (counts of strands, lines and teeth).
SPOOL_INTEGER_KEYS = ("mechanical_advantage", "lines_per_spool", "motor_gear_teeth", "spool_gear_teeth")


@dataclasses.dataclass(frozen=True)
class SpoolParams:
    """A spool winch (RepRapFirmware's Hangprinter kinematics, M666 R Q U O L H; the equations are in
    ``cdpr.models.winch``): r0 spool radius with the mover at the origin [m]; Q buildup factor [m]
    (the squared radius drops by O Q per metre of released line); U mechanical advantage (the line
    runs U times between anchor and mover: U strands, so the cable's axial stiffness is U E S and the
    spool releases U times the change of the rest length); lines_per_spool O; motor_teeth L and
    spool_teeth H of the gears (the motor turns H / L times per spool turn)."""

    r0: float
    Q: float = 0.0
    U: int = 1
    lines_per_spool: int = 1
    motor_teeth: int = 1
    spool_teeth: int = 1


def spool_from_mapping(data, source, key="", partial=False):
    """SpoolParams from a robot file's ``winch: {kind: spool, ...}`` mapping (keys of ``SPOOL_KEYS``:
    spool_radius_m required, buildup_factor_m default 0, mechanical_advantage, lines_per_spool,
    motor_gear_teeth, spool_gear_teeth default 1). Errors name ``source`` and ``key``.

    Parameters
    ----------
    data : dict
        The mapping, ``kind: spool`` included; lengths [m] as numbers or strings with units.
    source : str
        Name of the file for error messages.
    key : str
        Dotted place of the mapping in that file.
    partial : bool
        A robot's default ``winch:`` that its cables complete: spool_radius_m may be absent (the
        radius is then 1 m, a placeholder; each cable's merged mapping is checked in full).

    Returns
    -------
    SpoolParams

    Raises
    ------
    ConfigError
        For an unknown or missing key, a wrong unit, a radius <= 0, a buildup < 0 or a count that is
        not a positive integer.
    """
    prefix = f"{key}." if key else ""
    values = {}
    for k, val in data.items():
        if k == "kind":
            continue
        if k not in SPOOL_KEYS:
            raise ConfigError(
                source,
                prefix + str(k),
                f"unknown key of a spool winch; allowed: kind, {', '.join(SPOOL_KEYS)}",
            )
        field, dim, _ = SPOOL_KEYS[k]
        if k in SPOOL_INTEGER_KEYS:
            if isinstance(val, bool) or not isinstance(val, (int, float)) or val != int(val) or val < 1:
                raise ConfigError(source, prefix + k, f"must be a positive integer (a count), got {val!r}")
            values[field] = int(val)
            continue
        v = quantity(val, dim, source, prefix + k)
        if not math.isfinite(v) or v < 0 or (v == 0 and field == "r0"):
            word = "strictly positive" if field == "r0" else "non-negative"
            raise ConfigError(source, prefix + k, f"must be {word} ({dim}), got {val!r}")
        values[field] = v
    if "r0" not in values and partial:
        values["r0"] = 1.0
    if "r0" not in values:
        raise ConfigError(source, prefix + "spool_radius_m", "missing required key of a spool winch")
    return SpoolParams(**values)


def spool_mapping(p):
    """A SpoolParams as the robot file's ``winch:`` mapping (``kind: spool`` and plain SI numbers),
    the inverse of ``spool_from_mapping``.

    Parameters
    ----------
    p : SpoolParams

    Returns
    -------
    dict
    """
    out = {"kind": "spool"}
    for k, (field, _, _) in SPOOL_KEYS.items():
        v = getattr(p, field)
        out[k] = int(v) if k in SPOOL_INTEGER_KEYS else float(v)
    return out


def winch_of(w, default, source, key, partial=False):
    """A cable's winch from its ``winch:`` mapping ``w`` merged over the robot's ``default``: a
    WinchParams (the Métillon drum, ``kind: drum`` or no kind) or a SpoolParams (``kind: spool``).
    A cable whose kind differs from the default's takes none of the default's keys."""
    if not isinstance(w, dict):
        raise ConfigError(source, key, "expected a mapping of winch parameters")
    kind = w.get("kind", (default or {}).get("kind", "drum"))
    merged = dict(w)
    if (default or {}).get("kind", "drum") == kind:
        merged = {**(default or {}), **w}
    if kind not in WINCH_KINDS:
        raise ConfigError(
            source, key + ".kind", f"unknown winch kind {kind!r}; allowed: {' | '.join(WINCH_KINDS)}"
        )
    if kind == "spool":
        return spool_from_mapping(merged, source, key, partial=partial)
    merged.pop("kind", None)
    return params_from_mapping(merged, source, key)


#: The kinds of winch a robot file may give (``winch: {kind: ...}``; default drum).
WINCH_KINDS = ("drum", "spool")
