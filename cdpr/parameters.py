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
