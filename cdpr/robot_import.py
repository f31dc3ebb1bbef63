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

Anything else is refused with one line naming the file and the element. CASPR models carry no
cable stiffness, diameter or dead length: the caller gives them (``cdpr import caspr --E ...``).

References
----------
Lau, D., Eden, J., Tan, Y., Oetomo, D. (2016). CASPR: A comprehensive cable-robot analysis and
simulation platform for the research community. IEEE/RSJ IROS, 3004-3011.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

from cdpr.errors import ConfigError

#: Elements of a cable's ``attachments`` list that the reader understands.
ATTACHMENTS = ("attachment", "base_rotating_pulley")


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
        ``{"mass_kg": M, "com_m": [x, y, z], "name": link name}``.
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
    if not jtype.startswith("SPATIAL"):
        raise ConfigError(str(path), "link_rigid.joint", f"a spatial joint is needed, got type {jtype!r}")
    phys = link.find("physical")
    if phys is None:
        raise ConfigError(str(path), "link_rigid.physical", "missing element <physical>")
    mass = _number(phys.find("mass"), path, "link_rigid.physical.mass", low=0.0, strict=True)
    com = _vector(phys.find("com_location"), path, "link_rigid.physical.com_location")
    return {"mass_kg": mass, "com_m": com, "name": link.get("name", "")}


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
        One entry per cable: ``A_m``, ``B_m``, ``pulley`` and ``cable: {max_tension_N}`` when given.
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
        out.append(entry)
    if not out:
        raise ConfigError(str(path), f"cable_set[{wanted}]", "no cables")
    return out


def robot_dict_from_caspr(
    bodies, cables, cable_set=None, E=102.2e9, diameter=0.004, dead_length=0.0, T_a=5000.0
):
    """A robot-file mapping (``robot.robot_from_dict`` reads it) from CASPR's two files.

    Parameters
    ----------
    bodies, cables : str or Path
        CASPR's ``X_bodies.xml`` and ``X_cables.xml``.
    cable_set : str, optional
        Cable set id (default: the file's default).
    E : float [Pa]
        Young's modulus of every cable (not in CASPR models).
    diameter : float [m]
        Cable diameter (not in CASPR models).
    dead_length : float [m]
        Dead length d of every cable (not in CASPR models).
    T_a : float [N]
        Admissible tension where the file gives no ``force_max``.

    Returns
    -------
    dict
        The robot file's mapping.
    """
    body = read_caspr_bodies(bodies)
    cabs = read_caspr_cables(cables, cable_set, body["com_m"])
    for c in cabs:  # the default pulley is fixed; rotating pulleys keep their own entry
        if c["pulley"] == {"kind": "fixed"}:
            c.pop("pulley")
    return {
        "name": body["name"] or "caspr",
        "description": f"imported from CASPR models {bodies} and {cables}",
        "platform": {"mass_kg": body["mass_kg"], "com_m": body["com_m"]},
        "cable": {"young_modulus_Pa": E, "diameter_m": diameter, "max_tension_N": T_a},
        "pulley": {"kind": "fixed"},
        "dead_length_m": dead_length,
        "cables": cabs,
    }
