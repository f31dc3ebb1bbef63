"""The parameter vector θ of a robot: names, groups, units, nominal values, and the robot they describe.

θ is what the sensitivities differentiate by (``cdpr.models.sensitivity``), what the uncertainty
study samples (``cdpr.analyses.uncertainty``) and what calibration estimates. One vector for every
robot, built from the robot, cables numbered from 1:

=========  ==================  =====  ==========================================
group      names               unit   what
=========  ==================  =====  ==========================================
``E``      ``E_1`` .. ``E_m``  Pa     Young's modulus of each cable
``h``      ``h_1`` .. ``h_m``  m      pulley arm length (joint axis to sheave centre)
``r_p``    ``r_p_1`` ..        m      sheave radius
``d``      ``d_1`` .. ``d_m``  m      dead length (winch exit to the pulley's joint point)
``A``      ``A_1_x`` ..        m      pulley joint points (anchors), base frame
``b``      ``b_1_x`` ..        m      attachment points, platform frame (rigid platform only)
``c``      ``c_x`` .. ``c_z``  m      centre of mass, platform frame (rigid platform only)
``rho``    ``rho_1`` ..        kg/m   linear density of each cable (heavy cables only)
``M``      ``M``               kg     platform (and payload) mass
=========  ==================  =====  ==========================================

A point mass (``Robot.point_mass``) has 7 m + 1 parameters (E, h, r_p, d, A, M); a rigid platform
10 m + 4 (E, h, r_p, d, A, b, c, M): the groups b and c only where the platform rotates. A robot
with heavy cables (``Robot.heavy``, some ``cable.linear_density_kg_m`` > 0) has m more, the linear
densities ``rho_1`` .. ``rho_m`` just before M (M stays last; a massless robot's θ is unchanged). The order
of ``parameter_names(robot)`` is the order of the sensitivity columns and of every θ array;
``group_columns`` maps each group to its columns (the uncertainty sampler's drivers set them).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cdpr.errors import CdprError

#: Parameter groups, in the order of θ; ``RIGID_GROUPS`` only on a rigid platform.
GROUPS = ("E", "h", "r_p", "d", "A", "b", "c", "rho", "M")
#: Groups of a rigid platform only (attachments and centre of mass, platform frame).
RIGID_GROUPS = ("b", "c")
#: Groups of a robot with heavy cables only (``Robot.heavy``: the linear densities).
HEAVY_GROUPS = ("rho",)
#: Units of the groups (a sensitivity of group g is in m or rad per this unit).
UNITS = {"E": "Pa", "h": "m", "r_p": "m", "d": "m", "A": "m", "b": "m", "c": "m", "rho": "kg/m", "M": "kg"}


def _groups_of(m, rigid, heavy=False):
    return [g for g in GROUPS if (rigid or g not in RIGID_GROUPS) and (heavy or g not in HEAVY_GROUPS)]


def _names(m, rigid, heavy=False):
    """Names of θ for m cables, with b and c when ``rigid``, the linear densities when ``heavy``."""
    names = []
    for g in _groups_of(m, rigid, heavy):
        if g in ("A", "b"):
            names += [f"{g}_{i}_{a}" for i in range(1, m + 1) for a in "xyz"]
        elif g == "c":
            names += [f"c_{a}" for a in "xyz"]
        elif g == "M":
            names.append("M")
        else:
            names += [f"{g}_{i}" for i in range(1, m + 1)]
    return names


def _group_list(m, rigid, heavy=False):
    size = {"A": 3 * m, "b": 3 * m, "c": 3, "M": 1}
    return [g for g in _groups_of(m, rigid, heavy) for _ in range(size.get(g, m))]


def has_rigid_parameters(robot):
    """Whether θ of ``robot`` has the attachments b and the centre of mass c: a rigid platform
    (``not Robot.point_mass``: some b_i or c off the reference point).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    bool
    """
    return not robot.point_mass


def parameter_names(robot, rigid=None):
    """Names of θ, in the order of the sensitivity columns (cables from 1).

    Parameters
    ----------
    robot : Robot
    rigid : bool, optional
        With b and c (True: the pose kernels' full set of columns, whatever the platform) or
        without (False); default ``has_rigid_parameters(robot)``.

    Returns
    -------
    names : list of str, length 7 m + 1 (10 m + 4 on a rigid platform; m more with heavy cables)
        E_1..E_m, h_1..h_m, r_p_1..r_p_m, d_1..d_m, A_1_x, A_1_y, A_1_z, ..., A_m_z, then on a
        rigid platform b_1_x .. b_m_z and c_x, c_y, c_z, with heavy cables rho_1 .. rho_m, and M last.
    """
    return _names(robot.m, has_rigid_parameters(robot) if rigid is None else rigid, robot.heavy)


def parameter_groups(robot, rigid=None):
    """The group (``GROUPS``) of each entry of ``parameter_names(robot, rigid)``.

    Parameters
    ----------
    robot : Robot
    rigid : bool, optional
        As ``parameter_names``.

    Returns
    -------
    groups : list of str, length ``len(parameter_names(robot, rigid))``
        "E", "h", "r_p", "d", "A", ("b", "c"), ("rho") or "M".
    """
    return _group_list(robot.m, has_rigid_parameters(robot) if rigid is None else rigid, robot.heavy)


def parameter_units(robot, rigid=None):
    """Units of the entries of ``parameter_names(robot, rigid)`` (a sensitivity is in m or rad per unit).

    Parameters
    ----------
    robot : Robot
    rigid : bool, optional
        As ``parameter_names``.

    Returns
    -------
    units : list of str
        'Pa' for E_i, 'kg' for M, 'kg/m' for rho_i, 'm' for every length and coordinate.
    """
    return [UNITS[g] for g in parameter_groups(robot, rigid)]


def group_columns(robot):
    """The columns of θ (``parameter_names(robot)``) of each group: the one mapping from a group
    (and cable, axis) to θ that the uncertainty sampler's drivers use.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    columns : dict of str -> ndarray of int
        Group -> its columns in θ order: m for E, h, r_p, d; 3 m for A and b (cable by cable,
        x y z); 3 for c; m for rho; 1 for M. Only the groups of the robot's θ.
    """
    groups = np.array(parameter_groups(robot), dtype=object)
    return {g: np.flatnonzero(groups == g) for g in dict.fromkeys(groups)}


def parameter_values(robot):
    """Nominal values of ``parameter_names(robot)``.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    theta : ndarray, shape (len(parameter_names(robot)),) [Pa, m, kg/m, kg]
        E_i [Pa], h_i, r_p_i, d_i, A_i [m], (b_i, c [m], platform frame), (rho_i [kg/m], heavy
        cables), M [kg].
    """
    a = robot.arrays
    rigid = [a.b.ravel(), a.com] if has_rigid_parameters(robot) else []
    heavy = [a.rho] if robot.heavy else []
    return np.concatenate([a.E, a.h, a.r_p, a.d, a.A.ravel(), *rigid, *heavy, [robot.platform.mass]])


def robot_with_parameters(robot, values):
    """A copy of ``robot`` whose parameters are ``values``; pulley kinds and axes, cable
    diameters and admissible tensions unchanged. Not validated (the caller checks physical ranges): a sampled or
    perturbed robot.

    Parameters
    ----------
    robot : Robot
    values : array_like, shape (len(parameter_names(robot)),) [Pa, m, kg/m, kg]
        In the order of ``parameter_names(robot)``: 7 m + 1, or 10 m + 4 on a rigid platform, m
        more (the linear densities) with heavy cables.

    Returns
    -------
    Robot
    """
    m = robot.m
    rigid = has_rigid_parameters(robot)
    heavy = robot.heavy
    n = robot_size(robot)
    v = np.asarray(values, dtype=float)
    if v.shape != (n,):
        what = "a rigid platform" if rigid else "a point mass"
        what += " with heavy cables" if heavy else ""
        raise CdprError(f"expected {n} parameter values for {what} on {m} cables, got shape {v.shape}")
    rho = v[n - 1 - m : n - 1] if heavy else None
    E, h, r_p, d = v[:m], v[m : 2 * m], v[2 * m : 3 * m], v[3 * m : 4 * m]
    A = v[4 * m : 7 * m].reshape(m, 3)
    b = v[7 * m : 10 * m].reshape(m, 3) if rigid else None
    cables = tuple(
        dataclasses.replace(
            c,
            A=tuple(float(x) for x in A[i]),
            pulley=dataclasses.replace(c.pulley, h=float(h[i]), r_p=float(r_p[i])),
            dead_length=float(d[i]),
            material=dataclasses.replace(
                c.material, E=float(E[i]), **({"rho": float(rho[i])} if heavy else {})
            ),
            **({"B": tuple(float(x) for x in b[i])} if rigid else {}),
        )
        for i, c in enumerate(robot.cables)
    )
    com = {"com": tuple(float(x) for x in v[10 * m : 10 * m + 3])} if rigid else {}
    platform = dataclasses.replace(robot.platform, mass=float(v[-1]), **com)
    return dataclasses.replace(robot, cables=cables, platform=platform)


# --- calibration groups -------------------------------------------------------------------------
#: The groups a calibration estimates (``cdpr calibrate fit --estimate``), in the order of
#: ``calibration_names``; ``attachments`` (b_i of a 6-DoF platform) only for spatial robots.
CALIBRATION_GROUPS = (
    "moduli",
    "pulleys",
    "dead_lengths",
    "anchors",
    "mass",
    "linear_densities",
    "offsets",
    "attachments",
)
#: The θ group (``GROUPS``) behind each parameter-vector group; ``offsets`` are per-cable encoder
#: offsets [m] (reading = rest length + offset), which belong to the measurement, not the robot.
_CALIBRATION_OF = {
    "E": "moduli",
    "h": "pulleys",
    "r_p": "pulleys",
    "d": "dead_lengths",
    "A": "anchors",
    "M": "mass",
    "b": "attachments",
    "c": "centre_of_mass",
    "rho": "linear_densities",
}
#: The calibration group of the centre of mass c (spatial vector): part of θ, not estimated.
CENTRE_OF_MASS = "centre_of_mass"


def calibration_names(robot):
    """Names of the calibration vector: ``parameter_names(robot)`` followed by the encoder offsets
    ``offset_1`` .. ``offset_m`` [m].

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    names : list of str, length 8 m + 1 (11 m + 4 on a rigid platform; m more with heavy cables)
    """
    return parameter_names(robot) + [f"offset_{i}" for i in range(1, robot.m + 1)]


def robot_size(robot):
    """Length of the robot part of the calibration vector (before the offsets): ``len(parameter_names(robot))``,
    7 m + 1, or 10 m + 4 on a rigid platform, m more with heavy cables (the linear densities).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    int
    """
    n = 10 * robot.m + 4 if has_rigid_parameters(robot) else 7 * robot.m + 1
    return n + robot.m if robot.heavy else n


def is_spatial(robot):
    """Whether ``robot`` calibrates with the spatial vector: a rigid platform (some b_i or c nonzero,
    ``has_rigid_parameters``).

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    bool
    """
    return has_rigid_parameters(robot)


def calibrated_robot(robot, values):
    """The robot of the robot part of a calibration vector (``robot_with_parameters``).

    Parameters
    ----------
    robot : Robot
    values : array_like, shape (robot_size,) or longer (offsets ignored) [Pa, m, kg/m, kg]

    Returns
    -------
    Robot
    """
    return robot_with_parameters(robot, np.asarray(values, dtype=float)[: robot_size(robot)])


def calibration_groups(robot):
    """The calibration group (``CALIBRATION_GROUPS``; ``CENTRE_OF_MASS`` for c, never estimated) and
    the 1-based cable (None for the mass and c) of every entry of ``calibration_names(robot)``.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    groups : list of str, length ``len(calibration_names(robot))``
    cables : list of int or None, same length
    """
    m = robot.m
    c = list(range(1, m + 1))
    triple = [i for i in c for _ in range(3)]
    per = {"A": triple, "b": triple, "c": [None] * 3, "M": [None]}
    groups = [_CALIBRATION_OF[g] for g in parameter_groups(robot)] + ["offsets"] * m
    cables = [k for g in _groups_of(m, has_rigid_parameters(robot), robot.heavy) for k in per.get(g, c)] + c
    return groups, cables


def calibration_values(robot, offsets=None):
    """Nominal calibration vector: ``parameter_values(robot)`` then the offsets (default 0).

    Parameters
    ----------
    robot : Robot
    offsets : array_like, shape (m,) [m], optional

    Returns
    -------
    theta : ndarray, shape (len(calibration_names(robot)),) [Pa, m, kg/m, kg]
    """
    off = np.zeros(robot.m) if offsets is None else np.asarray(offsets, dtype=float)
    return np.concatenate([parameter_values(robot), off])


def select_groups(robot, groups, source="--estimate"):
    """Indices into ``calibration_names(robot)`` of the parameters of ``groups``.

    Parameters
    ----------
    robot : Robot
    groups : iterable of str
        Names of ``CALIBRATION_GROUPS``.
    source : str
        Where the names come from, for the error message.

    Returns
    -------
    index : ndarray of int, sorted

    Raises
    ------
    CdprError
        An unknown group, ``attachments`` on a point-mass robot (no attachment points b_i), or
        ``linear_densities`` on a robot with massless cables (no rho_i in its θ).
    """
    groups = list(groups)
    for g in groups:
        if g not in CALIBRATION_GROUPS:
            raise CdprError(f"{source}: unknown group {g!r}; allowed: {', '.join(CALIBRATION_GROUPS)}")
        if g == "attachments" and not is_spatial(robot):
            raise CdprError(
                f"{source}: 'attachments' (b_i) are for a 6-DoF platform; robot {robot.name} is a point mass"
            )
        if g == "linear_densities" and not robot.heavy:
            raise CdprError(
                f"{source}: 'linear_densities' (rho_i) are for heavy cables; robot {robot.name} has massless cables "
                "(set cable.linear_density_kg_m > 0 or --linear-density)"
            )
    if not groups:
        raise CdprError(f"{source}: no group given; allowed: {', '.join(CALIBRATION_GROUPS[:-1])}")
    of, _ = calibration_groups(robot)
    return np.array([k for k, g in enumerate(of) if g in groups], dtype=np.intp)
