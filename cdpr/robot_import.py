"""Robot files from CASPR's XML models (single-link spatial robots).

CASPR (Lau et al., the Cable-robot Analysis and Simulation Platform for Research) describes a robot
by a bodies file (links, joints, mass, centre of mass) and a cables file (cable sets; each cable a
chain of attachments). This reader accepts what maps onto a cdpr robot file exactly:

* bodies: one ``link_rigid`` (the platform) with a spatial joint; its ``mass`` [kg] and
  ``com_location`` [m] become ``platform.mass_kg`` and ``platform.com_m``;
* cables: ``cable_ideal`` with two attachments, the base one (``link`` 0: the anchor A_i, a fixed
  pulley) and the platform one (``link`` 1: B_i; with ``attachment_reference="com"`` the location is
  taken from the centre of mass and moved to the platform frame); or a first attachment
  ``base_rotating_pulley`` (``fixed_location``, ``pulley_radius``, ``cable_entry_vector``), which is
  an SR pulley with h = r_p = pulley_radius, A_i = fixed_location and ``axis`` = cable_entry_vector
  (the cable enters at the fixed point along that vector, as in our convention); ``force_max``
  [N] becomes the cable's ``max_tension_N``.

``force_min`` [N] becomes ``min_tension_N`` (a ``force_min`` above ``force_max`` is refused). A
translational model (joint ``T_XYZ``: the platform does not turn) whose cables all attach at the
platform's reference point becomes a point-mass robot (its ``com_location`` plays no part then).

Anything else is refused with one line naming the file and the element. CASPR models carry no
cable stiffness, diameter or dead length: the caller gives them (``cdpr import caspr --E ...``) or
the defaults ``ASSUMED`` are taken, and ``import_caspr`` lists every value that did not come from
the XML (``CasprImport.assumed``), so that the robot file's header and the command say so.

References
----------
Lau, D., Eden, J., Tan, Y., Oetomo, D. (2016). CASPR: A comprehensive cable-robot analysis and
simulation platform for the research community. IEEE/RSJ IROS, 3004-3011.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import NamedTuple

import numpy as np

from cdpr.errors import ConfigError

#: Elements of a cable's ``attachments`` list that the reader understands.
ATTACHMENTS = ("attachment", "base_rotating_pulley")

#: What CASPR models do not hold, and the value taken when the caller gives none: key of the robot
#: file -> (value, unit, command-line option). E, diameter: CDPR4's steel cable (Paty et al. 2021,
#: Table 1); the dead length 0 (the winch exit at the anchor); the admissible tension where a cable
#: has no ``force_max``.
ASSUMED = {
    "cable.young_modulus_Pa": (102.2e9, "Pa", "--E"),
    "cable.diameter_m": (0.004, "m", "--diameter"),
    "dead_length_m": (0.0, "m", "--dead-length"),
    "cable.max_tension_N": (5000.0, "N", None),
}

#: An anchor that breaks a mirror symmetry of the others by less than this fraction of the frame
#: (the anchors' bounding-box diagonal) is reported as a possible typo.
SYMMETRY_TYPO_FRACTION = 0.01


class CasprImport(NamedTuple):
    """What ``import_caspr`` makes of CASPR's two files.

    data: the robot file's mapping; assumed: one phrase per value that did not come from the XML
    (``"cable.diameter_m = 0.004 m (assumed; ...)"``); notes: sanity lines about the model (a
    near-symmetry, an ignored centre of mass), reported, never acted on; cable_set: the id read."""

    data: dict
    assumed: list
    notes: list
    cable_set: str


def _parse(path, root_tag):
    """The root element of the XML file ``path``, which must be ``<root_tag>``."""
    try:
        root = ET.parse(path).getroot()
    except OSError as exc:
        raise ConfigError(str(path), None, f"cannot read the file ({exc.strerror})") from None
    except ET.ParseError as exc:
        raise ConfigError(str(path), None, f"not valid XML ({exc})") from None
    if root.tag != root_tag:
        raise ConfigError(
            str(path), None, f"the root element is <{root.tag}>; a CASPR file of this kind has <{root_tag}>"
        )
    return root


def _vector(el, path, where):
    """The 3 finite numbers of element ``el`` (``where`` names it in an error)."""
    if el is None or el.text is None:
        raise ConfigError(str(path), where, "missing; expected 3 numbers")
    try:
        v = [float(x) for x in el.text.split()]
    except ValueError:
        raise ConfigError(str(path), where, f"expected 3 numbers, got {el.text.strip()!r}") from None
    if len(v) != 3 or not all(math.isfinite(x) for x in v):
        raise ConfigError(str(path), where, f"expected 3 finite numbers, got {el.text.strip()!r}")
    return v


def _number(el, path, where, low=None, strict=False):
    """The finite number of element ``el``, at least ``low`` (above it when ``strict``) when given."""
    if el is None or el.text is None:
        raise ConfigError(str(path), where, "missing; expected a number")
    try:
        v = float(el.text)
    except ValueError:
        raise ConfigError(str(path), where, f"expected a number, got {el.text.strip()!r}") from None
    if not math.isfinite(v):
        raise ConfigError(str(path), where, f"expected a finite number, got {el.text.strip()!r}")
    if low is not None and (v <= low if strict else v < low):
        raise ConfigError(
            str(path), where, f"must be {'>' if strict else '>='} {low:g}, got {el.text.strip()!r}"
        )
    return v


def read_caspr_bodies(path):
    """The platform of a CASPR bodies file: mass [kg] and centre of mass [m] (platform frame).

    Parameters
    ----------
    path : str or Path
        ``X_bodies.xml``.

    Returns
    -------
    dict
        ``{"mass_kg": M, "com_m": [x, y, z], "name": link name, "translational": bool}``
        (``translational``: joint ``T_XYZ``, the platform does not turn).
    """
    root = _parse(path, "bodies_system")
    links = root.find("links")
    if links is None:
        raise ConfigError(str(path), "links", "missing element <links>")
    bodies = list(links)
    if len(bodies) != 1 or bodies[0].tag != "link_rigid":
        tags = ", ".join(f"<{b.tag}>" for b in bodies) or "none"
        raise ConfigError(
            str(path), "links", f"only single-link models are read (one <link_rigid>), got {tags}"
        )
    link = bodies[0]
    joint = link.find("joint")
    jtype = "" if joint is None else joint.get("type", "")
    if not (jtype.startswith("SPATIAL") or jtype == "T_XYZ"):
        raise ConfigError(
            str(path),
            "link_rigid.joint",
            f"a spatial (SPATIAL...) or translational (T_XYZ) joint is needed, got type {jtype!r}",
        )
    phys = link.find("physical")
    if phys is None:
        raise ConfigError(str(path), "link_rigid.physical", "missing element <physical>")
    mass = _number(phys.find("mass"), path, "link_rigid.physical.mass", low=0.0, strict=True)
    com = _vector(phys.find("com_location"), path, "link_rigid.physical.com_location")
    return {"mass_kg": mass, "com_m": com, "name": link.get("name", ""), "translational": jtype == "T_XYZ"}


def read_caspr_cables(path, cable_set=None, com=(0.0, 0.0, 0.0)):
    """The cables of one cable set of a CASPR cables file, as robot-file cable entries.

    Parameters
    ----------
    path : str or Path
        ``X_cables.xml``.
    cable_set : str, optional
        The ``cable_set`` id; default the file's ``default_cable_set``.
    com : sequence of 3 floats [m]
        Centre of mass in the platform frame (for ``attachment_reference="com"``).

    Returns
    -------
    list of dict
        One entry per cable: ``A_m``, ``B_m``, ``pulley`` and ``cable: {max_tension_N, min_tension_N}``
        from ``force_max`` and ``force_min`` when given.
    """
    root = _parse(path, "cables")
    wanted = cable_set or root.get("default_cable_set")
    ids = [s.get("id") for s in root.findall("cable_set")]
    twice = sorted({i for i in ids if ids.count(i) > 1}, key=str)
    if twice:
        raise ConfigError(
            str(path),
            "cable_set",
            f"the id {twice[0]!r} names {ids.count(twice[0])} cable sets; each id must be unique",
        )
    sets = {s.get("id"): s for s in root.findall("cable_set")}
    if wanted is None:
        raise ConfigError(
            str(path),
            "cables.default_cable_set",
            f"the file names no default cable set; give --cable-set ID (the file has: {', '.join(map(str, sets)) or 'none'})",
        )
    if wanted not in sets:
        raise ConfigError(
            str(path),
            "cable_set",
            f"no cable set {wanted!r}; the file has: {', '.join(map(str, sets)) or 'none'}",
        )
    out = []
    for k, cab in enumerate(sets[wanted]):
        where = f"cable_set[{wanted}].{cab.tag}[{k}]"
        if cab.tag != "cable_ideal":
            raise ConfigError(
                str(path), where, f"element <{cab.tag}> is not read; only <cable_ideal> cables are"
            )
        ref = cab.get("attachment_reference", "joint")
        if ref not in ("joint", "com"):
            raise ConfigError(
                str(path), where, f"attachment_reference {ref!r} is not read; allowed: joint | com"
            )
        atts = cab.find("attachments")
        items = [] if atts is None else list(atts)
        for a in items:
            if a.tag not in ATTACHMENTS:
                raise ConfigError(
                    str(path),
                    f"{where}.attachments",
                    f"element <{a.tag}> is not read; allowed: {' | '.join(ATTACHMENTS)}",
                )
        if len(items) != 2:
            raise ConfigError(str(path), f"{where}.attachments", f"expected 2 attachments, got {len(items)}")
        base, plat = items
        entry = {}
        if base.tag == "base_rotating_pulley":
            entry["A_m"] = _vector(
                base.find("fixed_location"), path, f"{where}.base_rotating_pulley.fixed_location"
            )
            r = _number(
                base.find("pulley_radius"), path, f"{where}.base_rotating_pulley.pulley_radius", low=0.0
            )
            axis = _vector(
                base.find("cable_entry_vector"), path, f"{where}.base_rotating_pulley.cable_entry_vector"
            )
            entry["pulley"] = {"kind": "SR", "h_m": r, "r_p_m": r, "axis": axis}
        else:
            if (base.findtext("link") or "").strip() != "0":
                raise ConfigError(
                    str(path), f"{where}.attachments", "the first attachment must be on link 0 (the base)"
                )
            entry["A_m"] = _vector(base.find("location"), path, f"{where}.attachment[0].location")
            entry["pulley"] = {"kind": "fixed"}
        if plat.tag != "attachment" or (plat.findtext("link") or "").strip() != "1":
            raise ConfigError(
                str(path), f"{where}.attachments", "the second attachment must be on link 1 (the platform)"
            )
        b = _vector(plat.find("location"), path, f"{where}.attachment[1].location")
        if ref == "com":
            b = [x + c for x, c in zip(b, com)]
        entry["B_m"] = b
        fmax = cab.find("properties/force_max")
        if fmax is not None:
            entry["cable"] = {
                "max_tension_N": _number(fmax, path, f"{where}.properties.force_max", low=0.0, strict=True)
            }
        fmin = cab.find("properties/force_min")
        if fmin is not None:
            t_min = _number(fmin, path, f"{where}.properties.force_min", low=0.0)
            if fmax is not None and t_min > entry["cable"]["max_tension_N"]:
                raise ConfigError(
                    str(path),
                    f"{where}.properties.force_min",
                    f"force_min {t_min:g} N exceeds force_max {entry['cable']['max_tension_N']:g} N; "
                    "the least tension must not exceed the largest",
                )
            if t_min > 0:
                entry.setdefault("cable", {})["min_tension_N"] = t_min
        out.append(entry)
    if not out:
        raise ConfigError(str(path), f"cable_set[{wanted}]", "no cables")
    return out


def model_name(bodies):
    """The default name of an imported robot: the bodies file's stem without CASPR's ``_bodies``
    suffix (``CoGiRo_bodies.xml`` -> ``CoGiRo``), or its folder's name when nothing is left.

    Parameters
    ----------
    bodies : str or Path
        CASPR's ``X_bodies.xml``.

    Returns
    -------
    str
    """
    p = Path(bodies)
    stem = p.stem.removesuffix("_bodies")
    if stem and stem != "bodies":
        return stem
    return p.resolve().parent.name or "caspr"


def symmetry_notes(A):
    """Anchors that break a mirror symmetry of the others by less than ``SYMMETRY_TYPO_FRACTION`` of
    the frame: a possible typo, reported and never changed.

    For each axis x, y, the mirror plane through the anchors' median coordinate; every anchor's
    mirror image is matched to the nearest anchor. When every mismatch is below the fraction of the
    frame (a near-symmetric robot) and some exceed 1e-9 of it, each such pair is one note.

    Parameters
    ----------
    A : array_like (m, 3) [m]
        Anchor points.

    Returns
    -------
    list of str
        One sentence per anchor pair that breaks a near-symmetry (empty when none).
    """
    A = np.asarray(A, dtype=float)
    frame = float(np.linalg.norm(np.ptp(A, axis=0)))
    if not frame > 0:
        return []
    out = []
    for k, axis in enumerate("xy"):
        c = float(np.median(A[:, k]))
        M = A.copy()
        M[:, k] = 2 * c - M[:, k]
        D = np.linalg.norm(M[:, None, :] - A[None, :, :], axis=2)
        j = D.argmin(axis=1)
        miss = D[np.arange(len(A)), j]
        if miss.max() >= SYMMETRY_TYPO_FRACTION * frame or miss.max() <= 1e-9 * frame:
            continue
        seen = set()
        for i in np.flatnonzero(miss > 1e-9 * frame):
            pair = tuple(sorted((int(i), int(j[i]))))
            if pair in seen:
                continue
            seen.add(pair)
            a, b = pair
            out.append(
                f"anchors {a + 1} and {b + 1} (cables[{a}], cables[{b}]) are mirror images about {axis} = {c:g} m "
                f"but for {miss[i] * 1e3:.3g} mm ({miss[i] / frame:.2%} of the {frame:.3g} m frame): a typo? (kept as read)"
            )
    return out


def import_caspr(bodies, cables, cable_set=None, E=None, diameter=None, dead_length=None, name=None):
    """A robot-file mapping from CASPR's two files, with every value that did not come from them named.

    Parameters
    ----------
    bodies, cables : str or Path
        CASPR's ``X_bodies.xml`` and ``X_cables.xml``.
    cable_set : str, optional
        Cable set id (default: the file's default).
    E : float [Pa], optional
        Young's modulus of every cable (not in CASPR models); None: ``ASSUMED``.
    diameter : float [m], optional
        Cable diameter (not in CASPR models); None: ``ASSUMED``.
    dead_length : float [m], optional
        Dead length d of every cable (not in CASPR models); None: ``ASSUMED``.
    name : str, optional
        The robot's name; default ``model_name(bodies)`` (not CASPR's link name).

    Returns
    -------
    CasprImport
        The mapping (its ``description`` names the files, not their folders), the values not from
        the XML and the sanity notes.
    """
    body = read_caspr_bodies(bodies)
    cabs = read_caspr_cables(cables, cable_set, body["com_m"])
    wanted = cable_set or _parse(cables, "cables").get("default_cable_set")
    assumed, notes = [], []
    given = {"cable.young_modulus_Pa": E, "cable.diameter_m": diameter, "dead_length_m": dead_length}
    values = {}
    for key, (default, unit, option) in ASSUMED.items():
        if key == "cable.max_tension_N":
            continue
        if given[key] is None:
            values[key] = default
            assumed.append(
                f"{key} = {default:g} {unit} (assumed; CASPR models hold none; set it with {option})"
            )
        else:
            values[key] = float(given[key])
            assumed.append(
                f"{key} = {given[key]:g} {unit} (given on the command line, {option}; CASPR models hold none)"
            )
    T_a = ASSUMED["cable.max_tension_N"][0]
    no_fmax = [i for i, c in enumerate(cabs) if "max_tension_N" not in c.get("cable", {})]
    if no_fmax:
        which = (
            "every cable" if len(no_fmax) == len(cabs) else "cables " + ", ".join(str(i + 1) for i in no_fmax)
        )
        assumed.append(f"cable.max_tension_N = {T_a:g} N for {which} (assumed: no force_max)")
    assumed.append("platform.gravity_m_per_s2 = 9.81 m/s^2 (assumed: standard gravity along -z)")
    for c in cabs:  # the default pulley is fixed; rotating pulleys keep their own entry
        if c["pulley"] == {"kind": "fixed"}:
            c.pop("pulley")
    platform = {"mass_kg": body["mass_kg"], "com_m": body["com_m"]}
    if body["translational"]:  # T_XYZ: a point mass when every cable attaches at the reference point
        off = [i for i, c in enumerate(cabs) if any(c["B_m"])]
        if off:
            raise ConfigError(
                str(cables),
                f"cable_set[{wanted}]",
                f"a translational (T_XYZ) model is read as a point mass, whose cables attach at its reference "
                f"point; cable {off[0] + 1} attaches at {cabs[off[0]]['B_m']}",
            )
        for c in cabs:
            c.pop("B_m")
        platform.pop("com_m")
        if any(body["com_m"]):
            notes.append(
                f"com_location {body['com_m']} left out: a translational (T_XYZ) platform does not turn, "
                "so its centre of mass plays no part (a point-mass robot)"
            )
    notes += symmetry_notes([c["A_m"] for c in cabs])
    data = {
        "name": name or model_name(bodies),
        "description": f"imported from CASPR model files {Path(bodies).name} and {Path(cables).name} "
        f"(cable set {wanted})",
        "platform": platform,
        "cable": {
            "young_modulus_Pa": values["cable.young_modulus_Pa"],
            "diameter_m": values["cable.diameter_m"],
            "max_tension_N": T_a,
        },
        "pulley": {"kind": "fixed"},
        "dead_length_m": values["dead_length_m"],
        "cables": cabs,
    }
    return CasprImport(data=data, assumed=assumed, notes=notes, cable_set=wanted)


def robot_dict_from_caspr(bodies, cables, cable_set=None, E=None, diameter=None, dead_length=None, name=None):
    """The robot-file mapping of ``import_caspr`` (without its list of assumed values and notes).

    Parameters
    ----------
    bodies, cables : str or Path
        CASPR's ``X_bodies.xml`` and ``X_cables.xml``.
    cable_set : str, optional
        Cable set id (default: the file's default).
    E : float [Pa], optional
        Young's modulus of every cable; None: ``ASSUMED``.
    diameter : float [m], optional
        Cable diameter; None: ``ASSUMED``.
    dead_length : float [m], optional
        Dead length d of every cable; None: ``ASSUMED``.
    name : str, optional
        The robot's name (default ``model_name(bodies)``).

    Returns
    -------
    dict
        The robot file's mapping.
    """
    return import_caspr(bodies, cables, cable_set, E, diameter, dead_length, name).data
