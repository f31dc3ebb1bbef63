"""Reading physical quantities from configuration values.

A value is either a plain number, taken in the SI unit named by its key (``h_m: 0.1``), or a
string with a unit (``h_m: "100 mm"``, ``young_modulus_Pa: "102.2 GPa"``). Everything inside the
library is SI (m, N, Pa, kg, rad). A dimensionless value (``DIMENSIONLESS``: a pulley's ``axis``,
its ``zero``) is a plain number, or a string holding one; it takes no unit.
"""

import math
import re

from cdpr.errors import ConfigError

#: Accepted unit spellings for each dimension, with their factor to SI.
UNITS = {
    "m": {"m": 1.0, "cm": 1e-2, "mm": 1e-3},
    "Pa": {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9, "N/mm^2": 1e6},
    "N": {"N": 1.0, "kN": 1e3},
    "kg": {"kg": 1.0, "g": 1e-3, "t": 1e3},
    "kg/m": {"kg/m": 1.0, "g/m": 1e-3},
    "m/s^2": {"m/s^2": 1.0, "m/s2": 1.0},
    "rad": {"rad": 1.0, "deg": math.pi / 180.0},
}

#: The dimension of a pure number (a direction's components): no unit is accepted.
DIMENSIONLESS = "-"

_QUANTITY = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z/^0-9]*)\s*$")


def quantity(value, dimension, source, key):
    """Convert a configuration value to a float in the SI unit of ``dimension``.

    Raises ConfigError naming ``source`` and ``key`` when the value is not a number, has a unit of
    another dimension, or is not finite. ``dimension`` ``DIMENSIONLESS`` accepts a plain number only.
    """
    if dimension == DIMENSIONLESS:
        return _pure_number(value, source, key)
    allowed = ", ".join(UNITS[dimension])
    if isinstance(value, bool):
        raise ConfigError(
            source,
            key,
            f"expected a number in {dimension} (or a string with one of the units {allowed}), got {value!r}",
        )
    if isinstance(value, (int, float)):
        out = float(value)
    elif isinstance(value, str):
        match = _QUANTITY.match(value)
        if not match:
            raise ConfigError(
                source,
                key,
                f"cannot read {value!r} as a quantity; write a number in {dimension} or a number with one of the units {allowed}",
            )
        number, unit = match.groups()
        unit = unit or dimension  # a bare number written as a string (PyYAML reads 102.2e9 so)
        if unit not in UNITS[dimension]:
            raise ConfigError(
                source, key, f"unit '{unit}' is not a unit of {dimension}; allowed units: {allowed}"
            )
        out = float(number) * UNITS[dimension][unit]
    else:
        raise ConfigError(
            source,
            key,
            f"expected a number in {dimension} (or a string with one of the units {allowed}), got {type(value).__name__} {value!r}",
        )
    if not math.isfinite(out):
        raise ConfigError(source, key, f"must be finite, got {value!r}")
    return out


def _pure_number(value, source, key):
    """A dimensionless configuration value as a float: a number, or a string holding one, no unit."""
    expected = "expected a plain number (dimensionless, no unit)"
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ConfigError(source, key, f"{expected}, got {type(value).__name__} {value!r}")
    if isinstance(value, str):
        match = _QUANTITY.match(value)
        if not match:
            raise ConfigError(source, key, f"cannot read {value!r} as a number; {expected}")
        number, unit = match.groups()
        if unit:
            raise ConfigError(source, key, f"{expected}, got {value!r} with the unit '{unit}'")
        value = number
    out = float(value)
    if not math.isfinite(out):
        raise ConfigError(source, key, f"must be finite, got {value!r}")
    return out
