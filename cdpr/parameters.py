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
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cdpr.errors import CdprError
from cdpr.robot import Pulley

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


def robot_with_parameters(robot, values):
    """A copy of ``robot`` whose parameters are ``values``; pulley kinds, cable diameters and
    admissible tensions unchanged. Not validated (the caller checks physical ranges): a sampled or
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
            pulley=Pulley(kind=c.pulley.kind, h=float(h[i]), r_p=float(r_p[i])),
            dead_length=float(d[i]),
            material=dataclasses.replace(c.material, E=float(E[i])),
        )
        for i, c in enumerate(robot.cables)
    )
    platform = dataclasses.replace(robot.platform, mass=float(v[7 * m]))
    return dataclasses.replace(robot, cables=cables, platform=platform)


# --- calibration groups -------------------------------------------------------------------------
#: The groups a calibration estimates (``cdpr calibrate fit --estimate``), in the order of
#: ``calibration_names``; ``attachments`` (b_i of a 6-DoF platform) is reserved for spatial robots.
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
}


def calibration_names(m):
    """Names of the calibration vector: ``parameter_names(m)`` followed by the encoder offsets
    ``offset_1`` .. ``offset_m`` [m].

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    names : list of str, length 8 m + 1
    """
    return parameter_names(m) + [f"offset_{i}" for i in range(1, m + 1)]


def calibration_groups(m):
    """The calibration group (``CALIBRATION_GROUPS``) and the 1-based cable (None for the mass) of
    every entry of ``calibration_names(m)``.

    Parameters
    ----------
    m : int
        Number of cables.

    Returns
    -------
    groups : list of str, length 8 m + 1
    cables : list of int or None, length 8 m + 1
    """
    groups = [_CALIBRATION_OF[g] for g in parameter_groups(m)] + ["offsets"] * m
    c = list(range(1, m + 1))
    cables = c * 4 + [i for i in c for _ in range(3)] + [None] + c
    return groups, cables


def calibration_values(robot, offsets=None):
    """Nominal calibration vector: ``parameter_values(robot)`` then the offsets (default 0).

    Parameters
    ----------
    robot : Robot
    offsets : array_like, shape (m,) [m], optional

    Returns
    -------
    theta : ndarray, shape (8 m + 1,) [Pa, m, kg]
    """
    off = np.zeros(robot.m) if offsets is None else np.asarray(offsets, dtype=float)
    return np.concatenate([parameter_values(robot), off])


def select_groups(robot, groups, source="--estimate"):
    """Indices into ``calibration_names(robot.m)`` of the parameters of ``groups``.

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
        if g == "attachments":
            raise CdprError(
                f"{source}: 'attachments' (b_i) are for a 6-DoF platform; robot {robot.name} is a point mass"
            )
    if not groups:
        raise CdprError(f"{source}: no group given; allowed: {', '.join(CALIBRATION_GROUPS[:-1])}")
    of, _ = calibration_groups(robot.m)
    return np.array([k for k, g in enumerate(of) if g in groups], dtype=np.intp)
