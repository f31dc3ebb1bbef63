"""Robot descriptions: frame anchors, pulleys, cables and platform, read from YAML.

A robot file looks like this (all values SI; a string with a unit such as ``"100 mm"`` is accepted)::

    name: CDPR4
    platform: {mass_kg: 300, gravity_m_per_s2: 9.81}
    cable: {young_modulus_Pa: 102.2e9, diameter_m: 0.004, max_tension_N: 5140}   # default for every cable
    pulley: {kind: SR, h_m: 0.100, r_p_m: 0.0665}                               # default for every cable
    dead_length_m: 4.0                                                           # default for every cable
    cables:
      - {A_m: [-2.5, -2.5, 5.0]}
      - {A_m: [2.5, -2.5, 5.0], pulley: {kind: DR}, dead_length_m: 3.5, cable: {young_modulus_Pa: 95e9}}
      ...

``A_m`` is the pulley joint point A_i (the swivel axis of an SR pulley, the U-joint of a DR pulley,
the fixed point of the standard model). The winch exit C_i lies ``dead_length_m`` before A_i along
the pulley's swivel axis ``pulley.axis`` (unit k_i, default [0, 0, 1]: C_i = A_i - d_i k_i, straight
below A_i). A cable's ``pulley``, ``cable`` (material) and ``dead_length_m`` override the robot's
defaults key by key. The file is checked against ``cdpr/schemas/robot.schema.yaml`` first, then for
the physics a schema cannot express (h >= r_p, distinct anchors, ...).

Spatial robots (docs/spatial.md): ``B_m`` per cable is the attachment point b_i in the platform
frame (default [0, 0, 0]), ``platform.com_m`` the centre of mass c in the platform frame (default
[0, 0, 0]), ``pulley.zero`` (perpendicular to ``axis``) the zero of the reported swivel angle. A
robot with every b_i = 0, c = 0, every axis +z and every anchor above the floor is a *suspended
point-mass* robot, today's model: only there are anchors required not collinear seen from above.
The floor is ``frame: {floor_z_m: ...}`` (default: 0 when every anchor lies above z = 0, the
lowest anchor's height when only some do, and with no anchor above z = 0 the lowest anchor's height
less the anchors' horizontal extent, ``Robot.floor_z``); a point mass with anchors at or below it (a Hangprinter: three low
anchors, one on the ceiling) is solved as the rigid platforms are.

Winches: ``winch:`` (per robot, or per cable over the robot's keys) is the Métillon drum (Table 1
keys, ``kind: drum`` or no kind) or a spool (``kind: spool``: ``spool_radius_m``,
``buildup_factor_m``, ``mechanical_advantage``, ``lines_per_spool``, ``motor_gear_teeth``,
``spool_gear_teeth``; RepRapFirmware's Hangprinter M666 R Q U O L H, ``cdpr.models.winch``). A
spool's line runs U times between anchor and platform: the cable is U strands of the line whose
material ``cable:`` describes (axial stiffness U E S), and its tension (the force on the platform,
``max_tension_N`` included) is U times the line's.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from functools import cached_property, lru_cache
from pathlib import Path
from typing import NamedTuple

import numpy as np

from cdpr.errors import CdprError, ConfigError, raise_problems
from cdpr.units import DIMENSIONLESS, quantity
from cdpr.validation import read_yaml, validate  # noqa: F401  (read_yaml re-exported)
from cdpr.winch_params import (  # noqa: F401  (the winch descriptions, re-exported: cdpr.robot.TABLE1 ... stay importable)
    SPOOL_INTEGER_KEYS,
    SPOOL_KEYS,
    TABLE1,
    WINCH_KEYS,
    WINCH_KINDS,
    SpoolParams,
    WinchParams,
    load_winch_params,
    params_from_mapping,
    spool_from_mapping,
    spool_mapping,
    winch_of,
)

PULLEY_KINDS = ("fixed", "SR", "DR")
#: Integer codes used in the vectorised kernels.
KIND_CODE = {"fixed": 0, "SR": 1, "DR": 2}

#: Standard gravity [m/s^2], the default of ``platform.gravity_m_per_s2``.
G_STANDARD = 9.81


@dataclasses.dataclass(frozen=True)
class Pulley:
    """Pulley of one cable: kind fixed | SR | DR, lever arm h [m], sheave radius r_p [m], swivel axis
    k_i (unit, base frame) and the optional zero direction of its swivel angle."""

    kind: str
    h: float = 0.0
    r_p: float = 0.0
    axis: tuple = (0.0, 0.0, 1.0)  #: unit swivel axis k_i (base frame) [-]; the cable arrives along +k_i
    zero: tuple | None = None  #: unit vector ⟂ axis, zero of the reported swivel angle [-]; None: default


@dataclasses.dataclass(frozen=True)
class CableMaterial:
    """Cable material: Young's modulus E [Pa], diameter d_c [m], admissible tension T_a [N], the
    least tension T_min [N] the robot's controller keeps (``min_tension_N``, default 0; e.g. CASPR's
    ``force_min``) and the linear density rho [kg/m], mass per unstrained metre
    (``linear_density_kg_m``, default 0: a massless cable; docs/heavy_cables.md)."""

    E: float
    diameter: float
    T_a: float
    T_min: float = 0.0
    rho: float = 0.0

    @property
    def S(self):
        """Cross-section S = pi d_c^2 / 4 [m^2]."""
        return math.pi * self.diameter**2 / 4.0


@dataclasses.dataclass(frozen=True)
class Cable:
    """One cable: joint point A [m], its pulley, its dead length d [m] (winch exit C = A - d z) and
    its material, and optionally its winch (Métillon 2022 drum model)."""

    A: tuple
    pulley: Pulley
    dead_length: float
    material: CableMaterial
    winch: object = None  #: WinchParams of the drum that pays the cable out, or None (no winch model)
    B: tuple = (0.0, 0.0, 0.0)  #: attachment point b_i in the platform frame [m]
    spool: object = (
        None  #: SpoolParams of the spool that pays the cable out (``winch: {kind: spool}``), or None
    )

    @property
    def strands(self):
        """Strands of line between anchor and platform: the spool's mechanical advantage U, else 1."""
        return 1 if self.spool is None else self.spool.U


class BoxBody(NamedTuple):
    """A box-shaped platform body (``platform.body: {box: ...}``): centre and half-sizes in the
    platform frame [m] (the half-sizes > 0)."""

    centre: tuple
    half: tuple


#: The platform bodies a robot file names (``platform.body``) besides a box (``BoxBody``).
BODY_KINDS = ("hull", "none")


@dataclasses.dataclass(frozen=True)
class Platform:
    """Moving platform: mass M [kg], gravity g [m/s^2] along the unit vector ``down`` (-z; robot files
    do not set it: it lets a test turn a whole robot together with its gravity) and centre of mass c
    in the platform frame [m] (0 for a point mass). ``body`` is the solid the cable-platform
    interference test uses (``cdpr.models.interference``): "hull" (the convex hull of the
    attachments, the default; none when they span no volume), "none", or a ``BoxBody``.
    ``wrench`` (FX, FY, FZ, MX, MY, MZ) [N, N m] is an external wrench beside gravity (``with_wrench``;
    robot files do not set it): a constant force in the world frame applied at the reference point p
    and a constant moment about p in the world frame (0 on a point mass)."""

    mass: float
    g: float = G_STANDARD
    com: tuple = (0.0, 0.0, 0.0)
    down: tuple = (0.0, 0.0, -1.0)
    body: object = "hull"
    wrench: tuple = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

    @property
    def gravity_force(self):
        """Gravity on the platform, M g ``down`` = (0, 0, -M g) [N], acting at the centre of mass."""
        return self.mass * self.g * np.asarray(self.down, dtype=float)

    @property
    def w_ext(self):
        """External force on a point-mass platform: gravity plus the external wrench's force,
        M g ``down`` + (FX, FY, FZ) [N] (both act at p = the centre of mass there; a rigid platform's
        models take ``gravity_force`` at c and ``wrench`` at p apart)."""
        if not any(self.wrench[:3]):
            return self.gravity_force
        return self.gravity_force + np.asarray(self.wrench[:3], dtype=float)

    @property
    def has_wrench(self):
        """True when an external wrench beside gravity is set (``wrench`` not all zero)."""
        return any(self.wrench)


class CableArrays(NamedTuple):
    """Per-cable parameters of a robot as arrays over the m cables (what the models and kernels take).

    A (m, 3) [m]; kind (m,) int8 codes (0 fixed, 1 SR, 2 DR); h, r_p, d (m,) [m]; inward (m, 2)
    horizontal unit vector from A_i toward the anchors' centroid (the pulley plane used when P is
    on the vertical through A_i); E (m,) [Pa]; S (m,) [m^2] (U S for the U strands of a spool,
    ``Cable.strands``); ES (m,) [N]; T_a (m,) [N]; rho (m,) [kg/m] mass per unstrained metre of the
    line (U rho for the U strands of a spool) and w (m,) [N/m] = rho g its weight per unstrained
    metre (0: massless, the default).

    Spatial fields: axis (m, 3) unit swivel axes k_i; frame (m, 3, 3) rows i_i, j_i, k_i of each
    pulley's frame (i_i = ``zero``, j_i = k_i x i_i; the identity for axis +z without ``zero``);
    b (m, 3) [m] attachments in the platform frame; com (3,) [m] centre of mass in the platform
    frame. ``inward`` is expressed in the pulley frame (i_i, j_i): for axis +z it is today's
    horizontal vector."""

    A: np.ndarray
    kind: np.ndarray
    h: np.ndarray
    r_p: np.ndarray
    d: np.ndarray
    inward: np.ndarray
    E: np.ndarray
    S: np.ndarray
    ES: np.ndarray
    T_a: np.ndarray
    axis: np.ndarray = None
    frame: np.ndarray = None
    b: np.ndarray = None
    com: np.ndarray = None
    rho: np.ndarray = None
    w: np.ndarray = None


def require_point_mass(robot, what, instead, suspended=False, P=None):
    """Refuse, in one line, a robot or points that the point-mass model function ``what`` does not
    model, naming ``instead`` (the function that takes them): a rigid platform (attachments b_i or a
    centre of mass off the reference point, ``Robot.point_mass``), with ``suspended`` also pulleys
    whose swivel axes are not +z (``Robot.suspended_point_mass``: paper mode and the point-mass
    physical solver), and points ``P`` whose last axis is not 3 (poses (N, 6)).

    Parameters
    ----------
    robot : Robot
    what, instead : str
        The refusing function's name and what to call instead.
    suspended : bool
        Also require axes +z.
    P : array_like, optional
        The points given to ``what``.

    Raises
    ------
    CdprError
    """
    if P is not None and np.shape(P)[-1:] != (3,):
        raise CdprError(
            f"{what} takes positions (..., 3) [m], got shape {np.shape(P)}; poses (N, 6) go to {instead}"
        )
    if not robot.point_mass:
        raise CdprError(
            f"{robot.source}: {what} is the point-mass model and this robot is a rigid platform (attachments "
            f"or centre of mass off its reference point); use {instead}"
        )
    if suspended and not robot.suspended_point_mass:
        raise CdprError(
            f"{robot.source}: {what} is the model of a point mass under pulleys with +z axes and this robot's "
            f"pulleys have other axes; use {instead}"
        )


@dataclasses.dataclass(frozen=True)
class Robot:
    """A CDPR: m cables from pulleys to a platform (a suspended point mass when every b_i = 0, c = 0
    and every pulley axis is +z, see ``suspended_point_mass``)."""

    name: str
    cables: tuple
    platform: Platform
    source: str = "<dict>"
    floor_z_m: float | None = (
        None  #: the robot file's ``frame.floor_z_m`` [m]; None: the default (``floor_z``)
    )

    @cached_property
    def floor_z(self):
        """Height of the floor [m]: the robot file's ``frame.floor_z_m``; by default 0 when every
        anchor lies above z = 0; the lowest anchor's height when some anchors lie above z = 0 and
        some not (a Hangprinter: low anchors at the bed, one on the ceiling); and when no anchor
        lies above z = 0 (the frame's origin in the anchors' plane, the platform hanging below
        them, as cdpyr writes its robots) the lowest anchor's height less the anchors' largest
        horizontal extent (a frame as tall as it is wide: set ``frame.floor_z_m`` for the real one).
        """
        if self.floor_z_m is not None:
            return float(self.floor_z_m)
        A = self.A
        if (A[:, 2] > 0.0).all():
            return 0.0
        if (A[:, 2] > 0.0).any():
            return float(A[:, 2].min())
        extent = float((A[:, :2].max(axis=0) - A[:, :2].min(axis=0)).max())
        return float(A[:, 2].min()) - extent

    @property
    def m(self):
        """Number of cables."""
        return len(self.cables)

    @cached_property
    def arrays(self):
        """The per-cable parameters as a :class:`CableArrays` (computed once per robot)."""
        A = np.array([c.A for c in self.cables], dtype=float)
        centre = A[:, :2].mean(axis=0)
        v = centre - A[:, :2]
        n = np.linalg.norm(v, axis=1, keepdims=True)
        inward = np.where(n > 0, v / np.where(n > 0, n, 1.0), np.array([1.0, 0.0]))
        axis = np.array([c.pulley.axis for c in self.cables], dtype=float)
        frame = np.array([_pulley_frame_of(c.pulley.axis, c.pulley.zero) for c in self.cables])
        vertical = np.array([c.pulley.axis == (0.0, 0.0, 1.0) and c.pulley.zero is None for c in self.cables])
        # the fallback pulley plane (B_i on the axis): `zero` if given, else toward the anchors'
        # centroid perpendicular to k_i (today's `inward` for axis +z), else i_i; in the frame (i_i, j_i)
        v3 = A.mean(axis=0) - A
        v3 = v3 - np.einsum("ma,ma->m", v3, axis)[:, None] * axis
        f2 = np.stack(
            [np.einsum("ma,ma->m", v3, frame[:, 0]), np.einsum("ma,ma->m", v3, frame[:, 1])], axis=1
        )
        nf = np.linalg.norm(f2, axis=1, keepdims=True)
        f2 = np.where(nf > 1e-12, f2 / np.where(nf > 1e-12, nf, 1.0), np.array([1.0, 0.0]))
        has_zero = np.array([c.pulley.zero is not None for c in self.cables])
        f2[has_zero] = (1.0, 0.0)
        inward = np.where(vertical[:, None], inward, f2)
        E = np.array([c.material.E for c in self.cables], dtype=float)
        # U strands of a spool's line share the load: the cable's cross-section is U S (``Cable.strands``)
        S = np.array([c.material.S * c.strands for c in self.cables], dtype=float)
        rho = np.array([c.material.rho * c.strands for c in self.cables], dtype=float)
        return CableArrays(
            A=A,
            kind=np.array([KIND_CODE[c.pulley.kind] for c in self.cables], dtype=np.int8),
            h=np.array([c.pulley.h for c in self.cables], dtype=float),
            r_p=np.array([c.pulley.r_p for c in self.cables], dtype=float),
            d=np.array([c.dead_length for c in self.cables], dtype=float),
            inward=np.ascontiguousarray(inward),
            E=E,
            S=S,
            ES=E * S,
            T_a=np.array([c.material.T_a for c in self.cables], dtype=float),
            axis=axis,
            frame=frame,
            b=np.array([c.B for c in self.cables], dtype=float),
            com=np.array(self.platform.com, dtype=float),
            rho=rho,
            w=rho * self.platform.g,
        )

    @property
    def heavy(self):
        """True when some cable has a linear density > 0 (``linear_density_kg_m``): heavy cables."""
        return bool(self.arrays.rho.any())

    @cached_property
    def point_mass(self):
        """True when every attachment b_i and the centre of mass c are 0 (the platform is a point)."""
        a = self.arrays
        return bool(not a.b.any() and not a.com.any())

    @property
    def default_redundancy(self):
        """The redundancy mode when none is given: "paper" (the paper's 3-cable subsets) for a point
        mass on massless cables, "physical" for a rigid platform or heavy cables (their only mode)."""
        return "paper" if self.point_mass and not self.heavy else "physical"

    @cached_property
    def suspended_point_mass(self):
        """True for today's model: a point-mass platform under pulleys whose swivel axes are +z (and
        no ``zero`` given), every anchor above the floor (``floor_z``): the platform hangs below its
        anchors. Accessibility (hull, lowest anchor), the floor and collinearity checks and paper
        mode (3 of m) apply to these robots only; a point mass with anchors at or below the floor
        (a Hangprinter) is solved as the rigid platforms are (a pose is inaccessible only where no
        equilibrium exists)."""
        return (
            self.point_mass
            and all(c.pulley.axis == (0.0, 0.0, 1.0) and c.pulley.zero is None for c in self.cables)
            and all(c.A[2] > self.floor_z for c in self.cables)
        )

    # Short names for the arrays most models use.
    A = property(lambda self: self.arrays.A, doc="Pulley joint points A_i, shape (m, 3) [m].")
    kind = property(lambda self: self.arrays.kind, doc="Pulley kind codes (0 fixed, 1 SR, 2 DR), shape (m,).")
    h = property(lambda self: self.arrays.h, doc="Lever arms h_i, shape (m,) [m].")
    r_p = property(lambda self: self.arrays.r_p, doc="Sheave radii r_p,i, shape (m,) [m].")
    d = property(lambda self: self.arrays.d, doc="Dead lengths d_i, shape (m,) [m].")
    inward = property(lambda self: self.arrays.inward, doc="Fallback pulley-plane directions, shape (m, 2).")
    ES = property(lambda self: self.arrays.ES, doc="Axial stiffness E_i S_i per cable, shape (m,) [N].")
    T_a = property(lambda self: self.arrays.T_a, doc="Admissible tension per cable, shape (m,) [N].")

    @cached_property
    def subsets(self):
        """All 3-cable subsets as an int array (n_subsets, 3), lexicographic order (0-based)."""
        return np.array(list(itertools.combinations(range(self.m), 3)), dtype=np.intp)

    def pulley_summary(self):
        """Short text such as 'SR h=100 mm r_p=66.5 mm' when all pulleys are alike, else 'mixed'."""
        ps = {c.pulley for c in self.cables}
        if len(ps) != 1:
            return "mixed"
        p = ps.pop()
        if p.kind == "fixed":
            return "fixed"
        return f"{p.kind} h={p.h * 1e3:g} mm r_p={p.r_p * 1e3:g} mm"

    @property
    def winches(self):
        """Each cable's WinchParams (a Métillon drum), or None where the robot file gives no drum."""
        return tuple(c.winch for c in self.cables)

    @property
    def spools(self):
        """Each cable's SpoolParams (``winch: {kind: spool}``), or None where it has no spool."""
        return tuple(c.spool for c in self.cables)

    def material_summary(self):
        """'E = 102.2 GPa' when every cable has the same modulus, else the list per cable."""
        E = self.arrays.E
        if np.all(E == E[0]):
            return f"E = {E[0] / 1e9:g} GPa"
        return "E = " + "/".join(f"{e / 1e9:g}" for e in E) + " GPa"

    def dead_length_summary(self):
        """'d = 4 m' when every cable has the same dead length, else the list per cable."""
        d = self.arrays.d
        if np.all(d == d[0]):
            return f"d = {d[0]:g} m"
        return "d = " + "/".join(f"{x:g}" for x in d) + " m"


# --------------------------------------------------------------------------------------------
# Reading and validating
# --------------------------------------------------------------------------------------------
def _positive(value, dimension, source, key, allow_zero=False):
    v = quantity(value, dimension, source, key)
    if v < 0 or (v == 0 and not allow_zero):
        word = "non-negative" if allow_zero else "strictly positive"
        raise ConfigError(source, key, f"must be {word} ({dimension}), got {value!r}")
    return v


#: How far [m] an SR pulley's lever arm may lie below its sheave radius (calibrated swivel pulleys).
SR_SLACK = 1e-3


def check_pulley(kind, h, r_p, source, key):
    """The physical rule of a pulley design; raises ConfigError naming ``source`` and ``key``.

    fixed: h = r_p = 0. SR: h >= r_p - ``SR_SLACK`` (h = r_p is the common swivel pulley whose cable
    enters on the swivel axis; a calibrated SR pulley may come out with h slightly below r_p, where the
    model is still defined: the incoming strand leaves the axis at a small angle). DR: h > r_p, as the paper states (the sheave hangs from its U-joint and must
    clear it). h = r_p = 0 is the fixed-point limit of either kind."""
    if kind == "fixed":
        if h != 0.0 or r_p != 0.0:
            raise ConfigError(
                source, key, "a 'fixed' pulley is a point of passage: h_m and r_p_m must be 0 or absent"
            )
    elif h == 0.0 and r_p == 0.0:
        return
    elif kind == "SR" and h < r_p - SR_SLACK:
        raise ConfigError(
            source,
            key,
            f"SR pulley needs lever arm h_m >= sheave radius r_p_m - 1 mm (the sheave would cross its swivel axis), "
            f"got h_m={h:g} m, r_p_m={r_p:g} m; h_m = r_p_m = 0 is allowed as the fixed-point limit",
        )
    elif kind == "DR" and h <= r_p:
        raise ConfigError(
            source,
            key,
            f"DR pulley needs lever arm h_m > sheave radius r_p_m (the sheave would hit its joint), "
            f"got h_m={h:g} m, r_p_m={r_p:g} m; h_m = r_p_m = 0 is allowed as the fixed-point limit",
        )


#: Within this angle [deg] of +-x, the default zero of the swivel angle is +y projected (not +x).
ZERO_X_CONE_DEG = 25.0


def pulley_frame(axis, zero=None):
    """The frame (i_i, j_i, k_i) of a pulley, rows of a (3, 3) array (no paper equation).

    k_i = ``axis`` normalised; i_i = ``zero`` normalised, or by default +x projected onto the plane
    perpendicular to k_i (+y projected when k_i lies within ``ZERO_X_CONE_DEG`` of +-x);
    j_i = k_i x i_i. For axis +z without ``zero`` this is exactly the identity.

    Parameters
    ----------
    axis : array_like (3,) [-]
        Swivel axis (non-zero).
    zero : array_like (3,) [-], optional
        Direction perpendicular to ``axis`` of the swivel angle's zero.

    Returns
    -------
    frame : ndarray (3, 3) [-]
        Rows i_i, j_i, k_i (orthonormal, right-handed).
    """
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    if zero is None:
        e = np.array([1.0, 0.0, 0.0])
        if abs(k[0]) > math.cos(math.radians(ZERO_X_CONE_DEG)):
            e = np.array([0.0, 1.0, 0.0])
        i = e - (e @ k) * k
    else:
        i = np.asarray(zero, dtype=float)
    i = i / np.linalg.norm(i)
    return np.array([i, np.cross(k, i), k])


@lru_cache(maxsize=1024)
def _pulley_frame_of(axis, zero):
    """``pulley_frame`` of the tuples (axis, zero) of a ``Pulley``, computed once per distinct pulley
    orientation (read-only): the sample robots of an uncertainty study rebuild their arrays by the
    thousand with unchanged pulley axes."""
    frame = pulley_frame(axis, zero)
    frame.flags.writeable = False
    return frame


def _vector(value, source, key, dimension="m"):
    """A list of 3 quantities of ``dimension`` (``DIMENSIONLESS``: plain numbers) as a tuple of
    floats; ConfigError when not finite."""
    v = tuple(quantity(x, dimension, source, f"{key}[{j}]") for j, x in enumerate(value))
    if not all(math.isfinite(x) for x in v):
        raise ConfigError(source, key, f"must be 3 finite numbers, got {list(value)!r}")
    return v


def _body(value, source, key):
    """The platform body of ``platform.body`` (after the schema): "hull", "none" or a ``BoxBody``
    whose half-sizes are > 0."""
    if isinstance(value, str):
        return value
    box = value["box"]
    centre = _vector(box["centre_m"], source, f"{key}.box.centre_m")
    half = _vector(box["half_m"], source, f"{key}.box.half_m")
    if not all(h > 0 for h in half):
        raise ConfigError(source, f"{key}.box.half_m", f"every half-size must be > 0 m, got {list(half)}")
    return BoxBody(centre=centre, half=half)


def _plain(v):
    """A vector as a list of plain floats, for messages ('[0.0, 0.0, 1.0]', no numpy reprs)."""
    return [float(x) for x in v]


def _axis_zero(merged, source, key):
    """The pulley's ``axis`` (unit) and ``zero`` (unit, ⟂ axis, or None), checked."""
    axis = (0.0, 0.0, 1.0)
    if merged.get("axis") is not None:
        a = np.array(_vector(merged["axis"], source, key + ".axis", DIMENSIONLESS))
        n = float(np.linalg.norm(a))
        if not n > 1e-12:
            raise ConfigError(
                source, key + ".axis", f"the swivel axis must be a non-zero vector, got {_plain(a)}"
            )
        axis = tuple(float(x) for x in a / n)
    zero = None
    if merged.get("zero") is not None:
        z = np.array(_vector(merged["zero"], source, key + ".zero", DIMENSIONLESS))
        nz = float(np.linalg.norm(z))
        if not nz > 1e-12 or abs(z @ np.array(axis)) > 1e-9 * nz:
            raise ConfigError(
                source,
                key + ".zero",
                f"must be a non-zero vector perpendicular to the pulley axis {_plain(axis)}, got {_plain(z)}",
            )
        zero = tuple(float(x) for x in z / nz)
    return axis, zero


def _pulley(d, default, source, key):
    merged = dict(default or {})
    merged.update(d or {})
    if "kind" not in merged:
        raise ConfigError(
            source, key + ".kind", f"missing required key; allowed values: {' | '.join(PULLEY_KINDS)}"
        )
    kind = merged["kind"]
    h = _positive(merged.get("h_m", 0.0), "m", source, key + ".h_m", allow_zero=True)
    r_p = _positive(merged.get("r_p_m", 0.0), "m", source, key + ".r_p_m", allow_zero=True)
    check_pulley(kind, h, r_p, source, key)
    axis, zero = _axis_zero(merged, source, key)
    return Pulley(kind=kind, h=h, r_p=r_p, axis=axis, zero=zero)


def _material(d, default, source, key):
    merged = dict(default or {})
    merged.update(d or {})
    T_a = _positive(merged["max_tension_N"], "N", source, key + ".max_tension_N")
    T_min = _positive(merged.get("min_tension_N", 0.0), "N", source, key + ".min_tension_N", allow_zero=True)
    if T_min > T_a:
        raise ConfigError(
            source,
            key + ".min_tension_N",
            f"the least tension must not exceed max_tension_N = {T_a:g} N, got {T_min:g} N",
        )
    rho = _positive(
        merged.get("linear_density_kg_m", 0.0), "kg/m", source, key + ".linear_density_kg_m", allow_zero=True
    )
    return CableMaterial(
        E=_positive(merged["young_modulus_Pa"], "Pa", source, key + ".young_modulus_Pa"),
        diameter=_positive(merged["diameter_m"], "m", source, key + ".diameter_m"),
        T_a=T_a,
        T_min=T_min,
        rho=rho,
    )


def robot_from_dict(data, source="<dict>"):
    """Build and validate a Robot from the parsed YAML mapping ``data``; errors name ``source``.

    The schema ``cdpr/schemas/robot.schema.yaml`` is applied first (keys, types, counts), then the
    physical checks: positive quantities, the pulley rule (``check_pulley``), a non-zero pulley axis
    and a ``zero`` perpendicular to it, no two cables sharing both anchor and attachment; for a
    suspended point-mass robot (``Robot.suspended_point_mass``) also anchors above the floor and not
    collinear seen from above."""
    if not isinstance(data, dict):
        raise ConfigError(source, None, f"expected a mapping of keys to values, got {type(data).__name__}")
    validate(data, "robot", source)
    problems = []  # every physical check runs; all the problems are reported at once (``errors.raise_problems``)

    def ok(fn, *args, default=None, **kwargs):
        try:
            return fn(*args, **kwargs)
        except ConfigError as exc:
            problems.append(exc)
            return default

    plat = data["platform"]
    platform = Platform(
        mass=ok(_positive, plat["mass_kg"], "kg", source, "platform.mass_kg", default=1.0),
        g=ok(
            _positive, plat.get("gravity_m_per_s2", G_STANDARD), "m/s^2", source, "platform.gravity_m_per_s2",
            default=G_STANDARD,
        ),
        com=ok(_vector, plat.get("com_m", (0.0, 0.0, 0.0)), source, "platform.com_m", default=(0.0, 0.0, 0.0)),
        body=ok(_body, plat.get("body", "hull"), source, "platform.body", default="hull"),
    )  # fmt: skip
    default_material = data["cable"]
    ok(_material, default_material, None, source, "cable")  # the default on its own
    default_pulley = data["pulley"]
    ok(_pulley, default_pulley, None, source, "pulley")
    default_dead = data.get("dead_length_m", 0.0)
    default_winch = data.get("winch")
    if default_winch is not None:
        ok(winch_of, default_winch, None, source, "winch", partial=True)
    cables = []
    for i, c in enumerate(data["cables"]):
        key = f"cables[{i}]"
        A = ok(_vector, c["A_m"], source, f"{key}.A_m", default=(0.0, 0.0, float(i)))
        B = ok(_vector, c.get("B_m", (0.0, 0.0, 0.0)), source, f"{key}.B_m", default=(0.0, 0.0, 0.0))
        pulley = ok(
            _pulley, c.get("pulley"), default_pulley, source, key + ".pulley" if "pulley" in c else "pulley"
        )
        material = ok(
            _material, c.get("cable"), default_material, source, key + ".cable" if "cable" in c else "cable"
        )
        dk = key + ".dead_length_m" if "dead_length_m" in c else "dead_length_m"
        dead = ok(
            _positive, c.get("dead_length_m", default_dead), "m", source, dk, allow_zero=True, default=0.0
        )
        w = c.get("winch", default_winch)
        winch = (
            None
            if w is None
            else ok(winch_of, w, default_winch, source, key + ".winch" if "winch" in c else "winch")
        )
        spool = winch if isinstance(winch, SpoolParams) else None
        winch = None if spool is not None else winch
        if pulley is not None and material is not None:
            cables.append(
                Cable(A=A, pulley=pulley, dead_length=dead, material=material, winch=winch, B=B, spool=spool)
            )
    for (i, a), (j, b) in itertools.combinations(enumerate(cables), 2):
        if np.allclose(a.A, b.A, atol=1e-9) and np.allclose(a.B, b.B, atol=1e-9):
            problems.append(
                ConfigError(
                    source,
                    f"cables[{j}].A_m",
                    f"duplicate anchor point {list(b.A)}: same as cables[{i}].A_m with the same attachment B_m; "
                    "two cables may share an anchor only with different attachments",
                )
            )
    raise_problems(source, problems)
    name = data.get("name", Path(str(source)).stem)
    floor = (data.get("frame") or {}).get("floor_z_m")
    if floor is not None:
        floor = quantity(floor, "m", source, "frame.floor_z_m")
        if not math.isfinite(floor):
            raise ConfigError(source, "frame.floor_z_m", f"must be a finite height [m], got {floor!r}")
    robot = Robot(name=name, cables=tuple(cables), platform=platform, source=str(source), floor_z_m=floor)
    if (
        robot.suspended_point_mass
    ):  # every anchor above the floor (a point mass with one at or below is not suspended)
        xy = np.array([c.A[:2] for c in cables])
        centred = xy - xy.mean(axis=0)
        if np.linalg.matrix_rank(centred, tol=1e-9) < 2:
            raise ConfigError(
                source,
                "cables",
                "the anchor points are collinear seen from above; a suspended CDPR needs anchors spanning an area",
            )
    return robot


def load_robot(path, **overrides):
    """Read a robot YAML file into a validated Robot, then set the keyword overrides on it as values
    (``with_values``: ``pulley``, ``h``, ``r_p``, ``dead_length``, ``E``, ``E_cables``, ``mass``,
    ``linear_density``; None leaves the file's value); the robot's ``source`` then names them, for the messages."""
    robot = robot_from_dict(read_yaml(path), source=str(path))
    given = {k: v for k, v in overrides.items() if v is not None}
    if not given:
        return robot
    robot = dataclasses.replace(
        robot, source=f"{path} (with command-line overrides: {', '.join(sorted(given))})"
    )
    return with_values(robot, **given)


def with_values(
    robot,
    pulley=None,
    h=None,
    r_p=None,
    dead_length=None,
    E=None,
    E_cables=None,
    mass=None,
    linear_density=None,
):
    """A copy of ``robot`` with values set as if its file had been edited, checked as the file's
    values are (one line naming the robot's source and the key): every cable's pulley ``pulley``
    (kind), ``h`` and ``r_p`` [m] (``with_pulleys``), ``dead_length`` [m] and Young's modulus ``E``
    [Pa]; ``E_cables`` (m,) [Pa] each cable's modulus; ``mass`` [kg] the platform's;
    ``linear_density`` [kg/m] every cable's mass per unstrained metre. None leaves a
    value as it is. Typed values on the loaded robot (``dataclasses.replace``): the YAML mapping is
    neither rewritten nor validated again, so a study's many designs of one robot cost no reading.

    Parameters
    ----------
    robot : Robot
        The robot to copy.
    pulley : str or None
        Pulley kind for every cable, fixed | SR | DR (fixed sets h = r_p = 0).
    h, r_p, dead_length : float or str or None
        Lever arm, sheave radius and dead length of every cable [m] (a string may carry a unit).
    E : float or str or None
        Young's modulus of every cable [Pa].
    E_cables : sequence of float or None
        (m,) Young's modulus of each cable [Pa].
    mass : float or str or None
        Platform mass [kg].
    linear_density : float or str or None
        Mass per unstrained metre of every cable [kg/m] (``cable.linear_density_kg_m``; 0: massless).

    Returns
    -------
    Robot
    """
    src = robot.source
    if pulley is not None and pulley not in PULLEY_KINDS:
        raise ConfigError(src, "pulley.kind", f"must be one of {' | '.join(PULLEY_KINDS)}, got {pulley!r}")
    if dead_length is not None:
        dead_length = _positive(dead_length, "m", src, "dead_length_m", allow_zero=True)
    if any(v is not None for v in (pulley, h, r_p, dead_length, E)):
        robot = with_pulleys(robot, kind=pulley, h=h, r_p=r_p, dead_length=dead_length, E=E)
    if E_cables is not None:
        if len(E_cables) != robot.m:
            raise ConfigError(
                src, "cables", f"{len(E_cables)} per-cable Young's moduli given for {robot.m} cables"
            )
        moduli = [
            _positive(e, "Pa", src, f"cables[{i}].cable.young_modulus_Pa") for i, e in enumerate(E_cables)
        ]
        robot = dataclasses.replace(
            robot,
            cables=tuple(
                dataclasses.replace(c, material=dataclasses.replace(c.material, E=e))
                for c, e in zip(robot.cables, moduli)
            ),
        )
    if linear_density is not None:
        rho = _positive(linear_density, "kg/m", src, "cable.linear_density_kg_m", allow_zero=True)
        robot = dataclasses.replace(
            robot,
            cables=tuple(
                dataclasses.replace(c, material=dataclasses.replace(c.material, rho=rho))
                for c in robot.cables
            ),
        )
    if mass is not None:
        mass = _positive(mass, "kg", src, "platform.mass_kg")
        robot = dataclasses.replace(robot, platform=dataclasses.replace(robot.platform, mass=mass))
    return robot


def with_pulleys(robot, kind=None, h=None, r_p=None, dead_length=None, E=None):
    """A copy of ``robot`` with every cable's pulley / dead length / Young's modulus E [Pa] replaced
    (validated as a robot file would be); everything else of a cable (axis, zero, attachment B,
    winch) is kept (``dataclasses.replace``)."""
    cables = []
    for c in robot.cables:
        k = c.pulley.kind if kind is None else kind
        hh = c.pulley.h if h is None else h
        rr = c.pulley.r_p if r_p is None else r_p
        if k == "fixed":
            hh = rr = 0.0
        pulley = _pulley({"kind": k, "h_m": hh, "r_p_m": rr}, None, robot.source, "pulley")
        pulley = dataclasses.replace(pulley, axis=c.pulley.axis, zero=c.pulley.zero)
        material = c.material
        if E is not None:
            material = dataclasses.replace(
                material, E=_positive(E, "Pa", robot.source, "cable.young_modulus_Pa")
            )
        cables.append(
            dataclasses.replace(
                c,
                pulley=pulley,
                dead_length=c.dead_length if dead_length is None else float(dead_length),
                material=material,
            )
        )
    return dataclasses.replace(robot, cables=tuple(cables))


#: The components of an external wrench, in the order of ``--wrench`` and the study key ``wrench``.
WRENCH_KEYS = ("FX", "FY", "FZ", "MX", "MY", "MZ")


def check_wrench(values, where="--wrench"):
    """An external wrench as 6 finite floats (FX, FY, FZ [N], MX, MY, MZ [N m]), else CdprError in
    one line naming ``where``.

    Parameters
    ----------
    values : sequence of float or str
        The six components.
    where : str
        What the user typed them into (an option or a study file's key), for the message.

    Returns
    -------
    tuple of float
        (FX, FY, FZ, MX, MY, MZ) [N, N m].
    """
    try:
        vals = [float(v) for v in values]
    except (TypeError, ValueError):
        raise CdprError(f"{where}: expected 6 numbers FX FY FZ [N] MX MY MZ [N m], got {values!r}") from None
    if len(vals) != 6:
        raise CdprError(f"{where}: expected 6 numbers FX FY FZ [N] MX MY MZ [N m], got {len(vals)}: {vals}")
    bad = [k for k, v in zip(WRENCH_KEYS, vals) if not math.isfinite(v)]
    if bad:
        raise CdprError(
            f"{where}: every component must be finite, got {bad[0]} = {vals[WRENCH_KEYS.index(bad[0])]}"
        )
    return tuple(vals)


def with_wrench(robot, wrench, where="--wrench"):
    """A copy of ``robot`` whose platform carries the external wrench ``wrench`` beside gravity
    (``Platform.wrench``: force in the world frame at the reference point p, moment about p in the
    world frame). A point mass (``Robot.point_mass``) takes a force only: a moment is refused in one
    line naming ``where``. A zero wrench (or None) returns ``robot`` itself.

    Parameters
    ----------
    robot : Robot
    wrench : sequence of 6 float or None
        (FX, FY, FZ) [N], (MX, MY, MZ) [N m].
    where : str
        The option or study key the wrench came from, for the messages.

    Returns
    -------
    Robot
    """
    if wrench is None:
        return robot
    w = check_wrench(wrench, where)
    if not any(w):
        return robot
    if robot.point_mass and any(w[3:]):
        raise CdprError(
            f"{where}: {robot.source} is a point mass (no attachments, centre of mass at p), which cannot carry "
            f"a moment; MX MY MZ must be 0, got {list(w[3:])}"
        )
    return dataclasses.replace(robot, platform=dataclasses.replace(robot.platform, wrench=w))
