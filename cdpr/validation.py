"""JSON-schema validation of configuration files (robots, studies, winches).

The schemas live in ``cdpr/schemas/*.schema.yaml`` and ship with the library, so a robot or study
file is checked the same way by the command line, the library and the Snakemake pipeline. A
violation becomes one :class:`~cdpr.errors.ConfigError` sentence that names the file, the key and
what is allowed.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import jsonschema
import yaml

from cdpr.errors import ConfigError
from cdpr.units import UNITS

SCHEMA_DIR = Path(__file__).parent / "schemas"


@lru_cache(maxsize=None)
def schema(name):
    """The parsed schema ``cdpr/schemas/<name>.schema.yaml`` (``name`` e.g. "robot", "study")."""
    return yaml.safe_load((SCHEMA_DIR / f"{name}.schema.yaml").read_text())


def read_yaml(path):
    """Parse a YAML file; a missing file or a syntax error becomes a ConfigError naming the file."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise ConfigError(path, None, f"cannot read the file ({exc.strerror})") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ConfigError(path, None, f"not valid YAML: {' '.join(str(exc).split())}") from None


def key_path(path):
    """'cables[2].pulley.h_m' from a jsonschema error path deque(['cables', 2, 'pulley', 'h_m'])."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


#: Key suffix -> dimension of ``units.UNITS`` (keys name their unit: ``h_m``, ``mass_kg``, ...).
_SUFFIX = {"_m_per_s2": "m/s^2", "_Pa": "Pa", "_kg": "kg", "_N": "N", "_rad": "rad", "_m": "m"}


def unit_of_key(path):
    """The dimension named by the last key of ``path`` ('A_m' -> 'm'), or None."""
    keys = [p for p in path if isinstance(p, str)]
    if not keys:
        return None
    return next((dim for suf, dim in _SUFFIX.items() if keys[-1].endswith(suf)), None)


def _explain(err):
    """One sentence for a jsonschema ValidationError."""
    v = err.validator
    if "x-message" in err.schema and v != "additionalProperties":  # the schema's own sentence for this key
        count = len(err.instance) if isinstance(err.instance, (list, dict)) else None
        return [], err.schema["x-message"].format(got=repr(err.instance), count=count)
    if v == "additionalProperties":
        allowed = sorted(err.schema.get("properties", {}))
        extra = sorted(set(err.instance) - set(allowed)) if isinstance(err.instance, dict) else []
        return extra, f"unknown key; allowed keys here: {', '.join(allowed)}"
    if v == "required":
        missing = err.message.split("'")[1] if "'" in err.message else ""
        return [missing], "missing required key"
    if v == "enum":
        keys = [p for p in err.absolute_path if isinstance(p, str)]
        what = f"{keys[-1]} " if keys else "value "
        return [], f"unknown {what}{err.instance!r}; allowed: {' | '.join(map(str, err.validator_value))}"
    if v == "type" and err.validator_value == ["number", "string"]:
        dim = unit_of_key(err.absolute_path)
        if dim:
            return (
                [],
                f"expected a number in {dim} (or a string with one of the units {', '.join(UNITS[dim])}), got {err.instance!r}",
            )
    if v == "type":
        t = err.validator_value
        t = " or ".join(t) if isinstance(t, list) else t
        return [], f"expected {t}, got {type(err.instance).__name__} {err.instance!r}"
    if v in ("minItems", "maxItems"):
        return (
            [],
            f"expected {'at least' if v == 'minItems' else 'at most'} {err.validator_value} items, got {len(err.instance)}",
        )
    if v in ("minimum", "exclusiveMinimum", "maximum", "exclusiveMaximum"):
        op = {"minimum": ">=", "exclusiveMinimum": ">", "maximum": "<=", "exclusiveMaximum": "<"}[v]
        return [], f"must be {op} {err.validator_value}, got {err.instance!r}"
    if v == "pattern":
        return [], f"{err.instance!r} does not match the allowed pattern {err.validator_value}"
    return [], err.message


def validate(data, name, source):
    """Validate ``data`` against schema ``name``; raise ConfigError naming ``source`` and the key.

    Of several violations the one deepest in the file is reported (it names the most precise key)."""
    validator = jsonschema.Draft202012Validator(schema(name))
    errors = list(validator.iter_errors(data))
    if not errors:
        return data
    err = max(errors, key=lambda e: len(e.absolute_path))
    if err.context:  # allOf/anyOf: take the most precise sub-error
        err = max(err.context, key=lambda e: len(e.absolute_path))
    extra, message = _explain(err)
    path = list(err.absolute_path) + extra[:1]
    raise ConfigError(source, key_path(path) or None, message)
