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
    return yaml.safe_load((SCHEMA_DIR / f"{name}.schema.yaml").read_text(encoding="utf-8"))


#: Largest configuration file read [bytes]: robot and study files are a few kB; a larger "file" is a
#: mistake (a data file, a device), refused before it is read.
MAX_CONFIG_BYTES = 4 * 1024 * 1024


class _UniqueKeyLoader(yaml.SafeLoader):
    """yaml.SafeLoader that refuses a key given twice in one mapping (YAML's default keeps the last)."""

    def construct_mapping(self, node, deep=False):
        seen = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            try:
                first = seen.get(key)
            except TypeError:  # an unhashable key: let the base class say so
                break
            if first is not None:
                raise _DuplicateKey(key, first, key_node.start_mark.line + 1)
            seen[key] = key_node.start_mark.line + 1
        return super().construct_mapping(node, deep=deep)


class _DuplicateKey(Exception):
    def __init__(self, key, first, second):
        self.key, self.first, self.second = key, first, second


def read_text_file(path, what="file", max_bytes=MAX_CONFIG_BYTES):
    """The text of a UTF-8 file; ConfigError naming the file when it is missing, not a regular file
    (a folder, a device such as /dev/zero, a pipe), larger than ``max_bytes``, binary or not UTF-8."""
    path = Path(path)
    try:
        st = path.stat()
    except OSError as exc:
        raise ConfigError(path, None, f"cannot read the file ({exc.strerror})") from None
    if path.is_dir():
        raise ConfigError(path, None, f"is a folder, not a {what}")
    if not path.is_file():
        raise ConfigError(path, None, f"is not a regular file (a device or a pipe?); give a {what}")
    if st.st_size > max_bytes:
        raise ConfigError(
            path, None, f"is {st.st_size / 2**20:.1f} MiB; a {what} is at most {max_bytes / 2**20:.0f} MiB"
        )
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ConfigError(path, None, f"cannot read the file ({exc.strerror})") from None
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise ConfigError(path, None, "is UTF-16 text; save it as UTF-8")
    if b"\x00" in data:
        raise ConfigError(path, None, f"is a binary file, not a text {what}")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ConfigError(
            path,
            None,
            f"is not UTF-8 text (byte 0x{data[exc.start]:02x} on line {line}; Latin-1?); save it as UTF-8",
        ) from None


def read_yaml(path):
    """Parse a YAML file (``read_text_file``); a syntax error or a key given twice in one mapping
    becomes a ConfigError naming the file (and the key with both lines)."""
    path = Path(path)
    text = read_text_file(path, "YAML file")
    try:
        return yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 (a SafeLoader subclass)
    except _DuplicateKey as exc:
        raise ConfigError(
            path, str(exc.key), f"given twice (lines {exc.first} and {exc.second}); keep one"
        ) from None
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


def problems(errors):
    """(key, sentence) of each distinct violation: per error its most precise sub-error, then of
    errors on the same branch of the file only the deepest (a parent's "not valid" adds nothing)."""
    found = []
    for err in errors:
        if err.context:  # allOf/anyOf/oneOf: take the most precise sub-error
            err = max(err.context, key=lambda e: len(e.absolute_path))
        extra, message = _explain(err)
        found.append((list(err.absolute_path) + extra[:1], message))
    found.sort(key=lambda pm: -len(pm[0]))
    kept = []
    for path, message in found:
        if any(k[: len(path)] == path for k, _ in kept):
            continue
        if (path, message) not in kept:
            kept.append((path, message))
    kept.sort(key=lambda pm: [str(x) for x in pm[0]])
    return [(key_path(path) or None, message) for path, message in kept]


def validate(data, name, source):
    """Validate ``data`` against schema ``name``; raise ConfigError naming ``source`` and the key.

    Every distinct violation is reported at once (``problems``): a file with several mistakes is
    corrected in one go, one per key, the most precise key of each."""
    validator = jsonschema.Draft202012Validator(schema(name))
    errors = list(validator.iter_errors(data))
    if not errors:
        return data
    found = problems(errors)
    if len(found) == 1:
        raise ConfigError(source, *found[0])
    listed = "; ".join(f"key '{k}': {m}" if k else m for k, m in found)
    exc = ConfigError(source, None, f"{len(found)} problems: {listed}")
    exc.problems = [ConfigError(source, k, m) for k, m in found]  # each on its own (cdpr study check)
    raise exc
