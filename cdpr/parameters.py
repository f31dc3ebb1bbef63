"""The parameter vector θ of a robot: names, groups, units, nominal values, and the robot they describe.

θ is what the sensitivities differentiate by (``cdpr.models.sensitivity``), what the uncertainty
study samples (``cdpr.analyses.uncertainty``) and what calibration estimates. One naming for all of
them, cables numbered from 1:

=========  ==================  =====  ==========================================
group      names               unit   what
=========  ==================  =====  ==========================================
``E``      ``E_1`` .. ``E_m``  Pa     Young's modulus of each cable
``h``      ``h_1`` .. ``h_m``  m      pulley arm length (joint axis to sheave centre)
``r_p``    ``r_p_1`` ..        m      sheave radius
``d``      ``d_1`` .. ``d_m``  m      dead length (winch exit to the pulley's joint point)
``A``      ``A_1_x`` ..        m      pulley joint points (anchors), base frame
``M``      ``M``               kg     platform (and payload) mass
=========  ==================  =====  ==========================================

The order of ``parameter_names`` is the order of the sensitivity columns and of every θ array.

A rigid 6-DoF platform (``Robot.point_mass`` False) has more: ``parameter_names6`` adds the
attachment points ``b_1_x`` .. ``b_m_z`` [m] (platform frame, group ``b``) after the anchors and the
centre of mass ``c_x``, ``c_y``, ``c_z`` [m] (platform frame, group ``c``) before M; the sensitivities
dp*/dθ, dφ*/dθ (``cdpr.models.sensitivity``) and the spatial calibration use that one naming.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cdpr.errors import CdprError

#: Parameter groups, in the order of the sensitivity columns.
GROUPS = ("E", "h", "r_p", "d", "A", "M")
#: Units of the groups (a sensitivity of group g is in m per this unit).
UNITS = {"E": "Pa", "h": "m", "r_p": "m", "d": "m", "A": "m", "M": "kg"}


def parameter_names(m):
    """Names of the 7 m + 1 parameters, in the order of the sensitivity columns.

    E_1..E_m, h_1..h_m, r_p_1..r_p_m, d_1..d_m, A_1_x, A_1_y, A_1_z, ..., A_m_z, M (cables numbered
    from 1).

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    names : list of str, length 7 m + 1
    """
    c = range(1, m + 1)
    return (
        [f"E_{i}" for i in c]
        + [f"h_{i}" for i in c]
        + [f"r_p_{i}" for i in c]
        + [f"d_{i}" for i in c]
        + [f"A_{i}_{a}" for i in c for a in "xyz"]
        + ["M"]
    )


def parameter_groups(m):
    """The group (``GROUPS``) of each parameter of ``parameter_names(m)``.

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    groups : list of str, length 7 m + 1
        "E", "h", "r_p", "d", "A" or "M".
    """
    return ["E"] * m + ["h"] * m + ["r_p"] * m + ["d"] * m + ["A"] * (3 * m) + ["M"]


def parameter_values(robot):
    """Nominal values of the parameters of ``parameter_names(robot.m)``.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    theta : ndarray, shape (7 m + 1,) [Pa, m, kg]
        E_i [Pa], h_i, r_p_i, d_i, A_i [m], M [kg].
    """
    a = robot.arrays
    return np.concatenate([a.E, a.h, a.r_p, a.d, a.A.ravel(), [robot.platform.mass]])


#: Parameter groups of a rigid 6-DoF platform, in the order of ``parameter_names6``.
GROUPS6 = ("E", "h", "r_p", "d", "A", "b", "c", "M")


def parameter_names6(m):
    """Names of θ for a rigid platform on m cables (cables from 1), the order of the columns of
    ``cdpr.models.sensitivity.pose_sensitivities``.

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    names : list of str, length 10 m + 4
        E_i, h_i, r_p_i, d_i, A_i_x/y/z, b_i_x/y/z for every cable, then c_x, c_y, c_z and M.
    """
    names = []
    for key in ("E", "h", "r_p", "d"):
        names += [f"{key}_{i + 1}" for i in range(m)]
    for key in ("A", "b"):
        names += [f"{key}_{i + 1}_{a}" for i in range(m) for a in "xyz"]
    return names + ["c_x", "c_y", "c_z", "M"]


def parameter_units6(m):
    """Units of the parameters of ``parameter_names6(m)`` (a sensitivity is in m or rad per unit).

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    units : list of str
        'Pa' for E_i, 'kg' for M, 'm' for every length and coordinate (h_i, r_p_i, d_i, A_i, b_i, c).
    """
    return ["Pa" if n.startswith("E_") else "kg" if n == "M" else "m" for n in parameter_names6(m)]


def parameter_groups6(m):
    """The group (``GROUPS6``) of each parameter of ``parameter_names6(m)``.

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    groups : list of str, length 10 m + 4
    """
    return (
        ["E"] * m
        + ["h"] * m
        + ["r_p"] * m
        + ["d"] * m
        + ["A"] * (3 * m)
        + ["b"] * (3 * m)
        + ["c"] * 3
        + ["M"]
    )


def parameter_values6(robot):
    """Nominal values of ``parameter_names6(robot.m)``.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    theta : ndarray, shape (10 m + 4,) [Pa, m, kg]
        E_i [Pa], h_i, r_p_i, d_i, A_i, b_i (platform frame), c (platform frame) [m], M [kg].
    """
    a = robot.arrays
    return np.concatenate([a.E, a.h, a.r_p, a.d, a.A.ravel(), a.b.ravel(), a.com, [robot.platform.mass]])


def robot_with_parameters6(robot, values):
    """``robot_with_parameters`` for the spatial vector ``parameter_names6``: also the attachment
    points b_i and the centre of mass c. Not validated (a sampled or perturbed robot).

    Parameters
    ----------
    robot : Robot
    values : array_like, shape (10 m + 4,) [Pa, m, kg]
        In the order of ``parameter_names6``.

    Returns
    -------
    Robot
    """
    m = robot.m
    v = np.asarray(values, dtype=float)
    if v.shape != (10 * m + 4,):
        raise CdprError(f"expected {10 * m + 4} spatial parameter values for {m} cables, got shape {v.shape}")
    out = robot_with_parameters(robot, np.concatenate([v[: 7 * m], v[-1:]]))
    b = v[7 * m : 10 * m].reshape(m, 3)
    cables = tuple(dataclasses.replace(c, B=tuple(float(x) for x in b[i])) for i, c in enumerate(out.cables))
    platform = dataclasses.replace(out.platform, com=tuple(float(x) for x in v[10 * m : 10 * m + 3]))
    return dataclasses.replace(out, cables=cables, platform=platform)


def robot_with_parameters(robot, values):
    """A copy of ``robot`` whose parameters are ``values``; pulley kinds and axes, cable
    diameters and admissible tensions unchanged. Not validated (the caller checks physical ranges): a sampled or
    perturbed robot.

    Parameters
    ----------
    robot : Robot
    values : array_like, shape (7 m + 1,) [Pa, m, kg]
        In the order of ``parameter_names``.

    Returns
    -------
    Robot
    """
    m = robot.m
    v = np.asarray(values, dtype=float)
    if v.shape != (7 * m + 1,):
        raise CdprError(f"expected {7 * m + 1} parameter values for {m} cables, got shape {v.shape}")
    E, h, r_p, d = v[:m], v[m : 2 * m], v[2 * m : 3 * m], v[3 * m : 4 * m]
    A = v[4 * m : 7 * m].reshape(m, 3)
    cables = tuple(
        dataclasses.replace(
            c,
            A=tuple(float(x) for x in A[i]),
            pulley=dataclasses.replace(c.pulley, h=float(h[i]), r_p=float(r_p[i])),
            dead_length=float(d[i]),
            material=dataclasses.replace(c.material, E=float(E[i])),
        )
        for i, c in enumerate(robot.cables)
    )
    platform = dataclasses.replace(robot.platform, mass=float(v[7 * m]))
    return dataclasses.replace(robot, cables=cables, platform=platform)


# --- calibration groups -------------------------------------------------------------------------
#: The groups a calibration estimates (``cdpr calibrate fit --estimate``), in the order of
#: ``calibration_names``; ``attachments`` (b_i of a 6-DoF platform) only for spatial robots.
CALIBRATION_GROUPS = ("moduli", "pulleys", "dead_lengths", "anchors", "mass", "offsets", "attachments")
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
}
#: The calibration group of the centre of mass c (spatial vector): part of θ, not estimated.
CENTRE_OF_MASS = "centre_of_mass"


def calibration_names(m, spatial=False):
    """Names of the calibration vector: ``parameter_names(m)`` (``parameter_names6(m)`` for a
    spatial robot) followed by the encoder offsets ``offset_1`` .. ``offset_m`` [m].

    Parameters
    ----------
    m : int
        Number of cables.
    spatial : bool
        A rigid 6-DoF platform (``not Robot.point_mass``).

    Returns
    -------
    names : list of str, length 8 m + 1 (11 m + 4 spatial)
    """
    return (parameter_names6(m) if spatial else parameter_names(m)) + [f"offset_{i}" for i in range(1, m + 1)]


def robot_size(m, spatial=False):
    """Length of the robot part of the calibration vector (before the offsets): 7 m + 1, or
    10 m + 4 for a spatial robot."""
    return 10 * m + 4 if spatial else 7 * m + 1


def is_spatial(robot):
    """Whether ``robot`` calibrates with the spatial vector: a rigid platform (some b_i or c nonzero)."""
    return not robot.point_mass


def calibrated_robot(robot, values):
    """The robot of the robot part of a calibration vector (``robot_with_parameters`` or
    ``robot_with_parameters6`` by ``is_spatial``).

    Parameters
    ----------
    robot : Robot
    values : array_like, shape (robot_size,) or longer (offsets ignored) [Pa, m, kg]

    Returns
    -------
    Robot
    """
    sp = is_spatial(robot)
    v = np.asarray(values, dtype=float)[: robot_size(robot.m, sp)]
    return robot_with_parameters6(robot, v) if sp else robot_with_parameters(robot, v)


def calibration_groups(m, spatial=False):
    """The calibration group (``CALIBRATION_GROUPS``; ``CENTRE_OF_MASS`` for c, never estimated) and
    the 1-based cable (None for the mass and c) of every entry of ``calibration_names(m, spatial)``.

    Parameters
    ----------
    m : int
        Number of cables.
    spatial : bool
        A rigid 6-DoF platform.

    Returns
    -------
    groups : list of str, length 8 m + 1 (11 m + 4 spatial)
    cables : list of int or None, same length
    """
    c = list(range(1, m + 1))
    triple = [i for i in c for _ in range(3)]
    if spatial:
        groups = [_CALIBRATION_OF[g] for g in parameter_groups6(m)] + ["offsets"] * m
        return groups, c * 4 + triple * 2 + [None] * 4 + c
    groups = [_CALIBRATION_OF[g] for g in parameter_groups(m)] + ["offsets"] * m
    cables = c * 4 + triple + [None] + c
    return groups, cables


def calibration_values(robot, offsets=None):
    """Nominal calibration vector: ``parameter_values(robot)`` (``parameter_values6`` for a spatial
    robot, ``is_spatial``) then the offsets (default 0).

    Parameters
    ----------
    robot : Robot
    offsets : array_like, shape (m,) [m], optional

    Returns
    -------
    theta : ndarray, shape (8 m + 1,) (11 m + 4 spatial) [Pa, m, kg]
    """
    off = np.zeros(robot.m) if offsets is None else np.asarray(offsets, dtype=float)
    values = parameter_values6(robot) if is_spatial(robot) else parameter_values(robot)
    return np.concatenate([values, off])


def select_groups(robot, groups, source="--estimate"):
    """Indices into ``calibration_names(robot.m, is_spatial(robot))`` of the parameters of ``groups``.

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
        An unknown group, or ``attachments`` on a point-mass robot (no attachment points b_i).
    """
    groups = list(groups)
    for g in groups:
        if g not in CALIBRATION_GROUPS:
            raise CdprError(f"{source}: unknown group {g!r}; allowed: {', '.join(CALIBRATION_GROUPS)}")
        if g == "attachments" and not is_spatial(robot):
            raise CdprError(
                f"{source}: 'attachments' (b_i) are for a 6-DoF platform; robot {robot.name} is a point mass"
            )
    if not groups:
        raise CdprError(f"{source}: no group given; allowed: {', '.join(CALIBRATION_GROUPS[:-1])}")
    of, _ = calibration_groups(robot.m, is_spatial(robot))
    return np.array([k for k, g in enumerate(of) if g in groups], dtype=np.intp)
