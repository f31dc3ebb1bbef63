"""Robot descriptions: frame anchors, pulleys, cables and platform, read from YAML.

A robot file looks like this (all values SI; a string with a unit such as ``"100 mm"`` is accepted)::

    name: CDPR4
    platform: {mass_kg: 300, gravity_m_per_s2: 9.81}
    cable: {young_modulus_Pa: 102.2e9, diameter_m: 0.004, max_tension_N: 5140}
    pulley: {kind: SR, h_m: 0.100, r_p_m: 0.0665}      # default for every cable
    dead_length_m: 4.0                                  # default for every cable
    cables:
      - {A_m: [-2.5, -2.5, 5.0]}
      - {A_m: [2.5, -2.5, 5.0], pulley: {kind: DR}, dead_length_m: 3.5}
      ...

``A_m`` is the pulley joint point A_i (the swivel axis of an SR pulley, the U-joint of a DR pulley,
the fixed point of the standard model). The winch exit C_i lies ``dead_length_m`` below A_i.
"""
from __future__ import annotations

import dataclasses
import itertools
import math
from functools import cached_property
from pathlib import Path

import numpy as np
import yaml

from .errors import ConfigError
from .units import quantity

PULLEY_KINDS = ("fixed", "SR", "DR")
#: Integer codes used in the vectorised kernels.
KIND_CODE = {"fixed": 0, "SR": 1, "DR": 2}

_TOP_KEYS = {"name", "description", "platform", "cable", "pulley", "dead_length_m", "cables"}
_PLATFORM_KEYS = {"mass_kg", "gravity_m_per_s2"}
_CABLE_MATERIAL_KEYS = {"young_modulus_Pa", "diameter_m", "max_tension_N"}
_PULLEY_KEYS = {"kind", "h_m", "r_p_m"}
_CABLE_KEYS = {"A_m", "pulley", "dead_length_m"}

#: Standard gravity [m/s^2], the default of ``platform.gravity_m_per_s2``.
G_STANDARD = 9.81


@dataclasses.dataclass(frozen=True)
class Pulley:
    """Pulley of one cable: kind fixed | SR | DR, lever arm h [m] and sheave radius r_p [m]."""

    kind: str
    h: float = 0.0
    r_p: float = 0.0


@dataclasses.dataclass(frozen=True)
class Cable:
    """One cable: joint point A [m], its pulley and its dead length d [m] (winch exit C = A - d z)."""

    A: tuple
    pulley: Pulley
    dead_length: float


@dataclasses.dataclass(frozen=True)
class CableMaterial:
    """Cable material: Young's modulus E [Pa], diameter d_c [m], admissible tension T_a [N]."""

    E: float
    diameter: float
    T_a: float

    @property
    def S(self):
        """Cross-section S = pi d_c^2 / 4 [m^2]."""
        return math.pi * self.diameter**2 / 4.0


@dataclasses.dataclass(frozen=True)
class Platform:
    """Point-mass moving platform: mass M [kg] and gravity g [m/s^2]."""

    mass: float
    g: float = G_STANDARD

    @property
    def w_ext(self):
        """External wrench (force part) on the platform, (0, 0, -M g) [N]."""
        return np.array([0.0, 0.0, -self.mass * self.g])


@dataclasses.dataclass(frozen=True)
class Robot:
    """A suspended point-mass CDPR with m >= 3 cables."""

    name: str
    cables: tuple
    platform: Platform
    material: CableMaterial
    source: str = "<dict>"

    @property
    def m(self):
        return len(self.cables)

    @cached_property
    def A(self):
        """Pulley joint points A_i, shape (m, 3) [m]."""
        return np.array([c.A for c in self.cables], dtype=float)

    @cached_property
    def h(self):
        return np.array([c.pulley.h for c in self.cables], dtype=float)

    @cached_property
    def r_p(self):
        return np.array([c.pulley.r_p for c in self.cables], dtype=float)

    @cached_property
    def kind(self):
        """Pulley kind codes (0 fixed, 1 SR, 2 DR), shape (m,)."""
        return np.array([KIND_CODE[c.pulley.kind] for c in self.cables], dtype=np.int8)

    @cached_property
    def d(self):
        """Dead lengths d_i [m], shape (m,)."""
        return np.array([c.dead_length for c in self.cables], dtype=float)

    @cached_property
    def inward(self):
        """Horizontal unit vector from each A_i toward the anchors' centroid, shape (m, 2).

        Used as the pulley plane direction when P lies exactly on the vertical through A_i.
        """
        c = self.A[:, :2].mean(axis=0)
        v = c - self.A[:, :2]
        n = np.linalg.norm(v, axis=1, keepdims=True)
        v = np.where(n > 0, v / np.where(n > 0, n, 1.0), np.array([1.0, 0.0]))
        return v

    @property
    def ES(self):
        """Axial stiffness E S [N] (same for every cable)."""
        return self.material.E * self.material.S

    @cached_property
    def subsets(self):
        """All 3-cable subsets as an int array (n_subsets, 3), lexicographic order (0-based)."""
        return np.array(list(itertools.combinations(range(self.m), 3)), dtype=np.intp)

    @cached_property
    def envelope_volume(self):
        """Volume V_T of the outer envelope [m^3]: the anchors' horizontal convex hull from z = 0 to
        the lowest anchor height (a 5 m cube for CDPR4, a 54.13 m^3 prism for CDPR3)."""
        from scipy.spatial import ConvexHull

        hull = ConvexHull(self.A[:, :2])
        return float(hull.volume * self.A[:, 2].min())

    def pulley_summary(self):
        """Short text such as 'SR h=100 mm r_p=66.5 mm' when all pulleys are alike, else 'mixed'."""
        ps = {c.pulley for c in self.cables}
        if len(ps) != 1:
            return "mixed"
        p = ps.pop()
        if p.kind == "fixed":
            return "fixed"
        return f"{p.kind} h={p.h * 1e3:g} mm r_p={p.r_p * 1e3:g} mm"


# --------------------------------------------------------------------------------------------
# Reading and validating
# --------------------------------------------------------------------------------------------
def _mapping(value, source, key):
    if not isinstance(value, dict):
        raise ConfigError(source, key, f"expected a mapping of keys to values, got {type(value).__name__}")
    return value


def _check_keys(d, allowed, required, source, prefix):
    for k in d:
        if k not in allowed:
            raise ConfigError(source, f"{prefix}{k}", f"unknown key; allowed keys here: {', '.join(sorted(allowed))}")
    for k in required:
        if k not in d:
            raise ConfigError(source, f"{prefix}{k}", "missing required key")


def _positive(value, dimension, source, key, allow_zero=False):
    v = quantity(value, dimension, source, key)
    if v < 0 or (v == 0 and not allow_zero):
        word = "non-negative" if allow_zero else "strictly positive"
        raise ConfigError(source, key, f"must be {word} ({dimension}), got {value!r}")
    return v


def _pulley(d, default, source, key):
    d = _mapping(d, source, key)
    _check_keys(d, _PULLEY_KEYS, (), source, key + ".")
    merged = dict(default or {})
    merged.update(d)
    if "kind" not in merged:
        raise ConfigError(source, key + ".kind", f"missing required key; allowed values: {' | '.join(PULLEY_KINDS)}")
    kind = merged["kind"]
    if kind not in PULLEY_KINDS:
        raise ConfigError(source, key + ".kind", f"unknown pulley kind {kind!r}; allowed: {' | '.join(PULLEY_KINDS)}")
    h = _positive(merged.get("h_m", 0.0), "m", source, key + ".h_m", allow_zero=True)
    r_p = _positive(merged.get("r_p_m", 0.0), "m", source, key + ".r_p_m", allow_zero=True)
    if kind == "fixed":
        if h != 0.0 or r_p != 0.0:
            raise ConfigError(source, key, "a 'fixed' pulley is a point of passage: h_m and r_p_m must be 0 or absent")
    elif not (h == 0.0 and r_p == 0.0) and h <= r_p:
        raise ConfigError(
            source, key,
            f"{kind} pulley needs lever arm h_m > sheave radius r_p_m (the sheave would hit its joint), "
            f"got h_m={h:g} m, r_p_m={r_p:g} m; h_m = r_p_m = 0 is allowed as the fixed-point limit")
    return Pulley(kind=kind, h=h, r_p=r_p)


def robot_from_dict(data, source="<dict>"):
    """Build and validate a Robot from the parsed YAML mapping ``data``; errors name ``source``."""
    data = _mapping(data, source, "")
    _check_keys(data, _TOP_KEYS, ("platform", "cable", "pulley", "cables"), source, "")
    plat = _mapping(data["platform"], source, "platform")
    _check_keys(plat, _PLATFORM_KEYS, ("mass_kg",), source, "platform.")
    platform = Platform(
        mass=_positive(plat["mass_kg"], "kg", source, "platform.mass_kg"),
        g=_positive(plat.get("gravity_m_per_s2", G_STANDARD), "m/s^2", source, "platform.gravity_m_per_s2"),
    )
    mat = _mapping(data["cable"], source, "cable")
    _check_keys(mat, _CABLE_MATERIAL_KEYS, sorted(_CABLE_MATERIAL_KEYS), source, "cable.")
    material = CableMaterial(
        E=_positive(mat["young_modulus_Pa"], "Pa", source, "cable.young_modulus_Pa"),
        diameter=_positive(mat["diameter_m"], "m", source, "cable.diameter_m"),
        T_a=_positive(mat["max_tension_N"], "N", source, "cable.max_tension_N"),
    )
    default_pulley = _mapping(data["pulley"], source, "pulley")
    _pulley(default_pulley, None, source, "pulley")  # validate the default on its own
    default_dead = data.get("dead_length_m", 0.0)
    cables_raw = data["cables"]
    if not isinstance(cables_raw, list):
        raise ConfigError(source, "cables", f"expected a list of cables, got {type(cables_raw).__name__}")
    if len(cables_raw) < 3:
        raise ConfigError(source, "cables", f"a spatial point-mass CDPR needs at least 3 cables, got {len(cables_raw)}")
    cables = []
    for i, c in enumerate(cables_raw):
        key = f"cables[{i}]"
        c = _mapping(c, source, key)
        _check_keys(c, _CABLE_KEYS, ("A_m",), source, key + ".")
        A = c["A_m"]
        if not (isinstance(A, list) and len(A) == 3):
            raise ConfigError(source, key + ".A_m", f"expected a list of 3 coordinates [x, y, z] in m, got {A!r}")
        A = tuple(quantity(v, "m", source, f"{key}.A_m[{j}]") for j, v in enumerate(A))
        pulley = _pulley(c.get("pulley", {}), default_pulley, source, key + ".pulley" if "pulley" in c else "pulley")
        dk = key + ".dead_length_m" if "dead_length_m" in c else "dead_length_m"
        dead = _positive(c.get("dead_length_m", default_dead), "m", source, dk, allow_zero=True)
        cables.append(Cable(A=A, pulley=pulley, dead_length=dead))
    for (i, a), (j, b) in itertools.combinations(enumerate(cables), 2):
        if np.allclose(a.A, b.A, atol=1e-9):
            raise ConfigError(source, f"cables[{j}].A_m", f"duplicate anchor point {list(b.A)}: same as cables[{i}].A_m; anchors must be distinct")
    xy = np.array([c.A[:2] for c in cables])
    centred = xy - xy.mean(axis=0)
    if np.linalg.matrix_rank(centred, tol=1e-9) < 2:
        raise ConfigError(source, "cables", "the anchor points are collinear seen from above; a suspended CDPR needs anchors spanning an area")
    name = data.get("name", Path(str(source)).stem)
    if not isinstance(name, str):
        raise ConfigError(source, "name", f"expected a string, got {name!r}")
    return Robot(name=name, cables=tuple(cables), platform=platform, material=material, source=str(source))


def apply_overrides(data, pulley=None, h=None, r_p=None, dead_length=None, E=None, mass=None):
    """Return a copy of the robot mapping with the given values set for every cable, exactly as if
    the file had been edited (``pulley`` kind, ``h``, ``r_p``, ``dead_length`` in m, ``E`` in Pa,
    ``mass`` in kg). ``None`` leaves the file's value."""
    import copy

    data = copy.deepcopy(data)
    pul_over = {}
    if pulley is not None:
        pul_over["kind"] = pulley
        if pulley == "fixed":
            pul_over.update(h_m=0.0, r_p_m=0.0)
    if h is not None:
        pul_over["h_m"] = h
    if r_p is not None:
        pul_over["r_p_m"] = r_p
    if pul_over and isinstance(data.get("pulley"), dict):
        data["pulley"].update(pul_over)
        for c in data.get("cables") or []:
            if isinstance(c, dict) and isinstance(c.get("pulley"), dict):
                c["pulley"].update(pul_over)
    if dead_length is not None:
        data["dead_length_m"] = dead_length
        for c in data.get("cables") or []:
            if isinstance(c, dict):
                c.pop("dead_length_m", None)
    if E is not None and isinstance(data.get("cable"), dict):
        data["cable"]["young_modulus_Pa"] = E
    if mass is not None and isinstance(data.get("platform"), dict):
        data["platform"]["mass_kg"] = mass
    return data


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
        raise ConfigError(path, None, f"not valid YAML: {exc}") from None


def load_robot(path, **overrides):
    """Read a robot YAML file into a validated Robot; keyword overrides as in ``apply_overrides``."""
    data = read_yaml(path)
    given = {k: v for k, v in overrides.items() if v is not None}
    source = str(path)
    if given:
        data = apply_overrides(_mapping(data, source, ""), **given)
        source = f"{path} (with command-line overrides: {', '.join(sorted(given))})"
    return robot_from_dict(data, source=source)


def with_pulleys(robot, kind=None, h=None, r_p=None, dead_length=None, E=None):
    """A copy of ``robot`` with every cable's pulley / dead length / E replaced (validated)."""
    cables = []
    for c in robot.cables:
        k = c.pulley.kind if kind is None else kind
        hh = c.pulley.h if h is None else h
        rr = c.pulley.r_p if r_p is None else r_p
        if k == "fixed":
            hh = rr = 0.0
        pd = {"kind": k, "h_m": hh, "r_p_m": rr}
        pulley = _pulley(pd, None, robot.source, "pulley")
        cables.append(Cable(A=c.A, pulley=pulley, dead_length=c.dead_length if dead_length is None else float(dead_length)))
    material = robot.material if E is None else dataclasses.replace(robot.material, E=float(E))
    if material.E <= 0:
        raise ConfigError(robot.source, "cable.young_modulus_Pa", f"must be strictly positive, got {E!r}")
    return dataclasses.replace(robot, cables=tuple(cables), material=material)
