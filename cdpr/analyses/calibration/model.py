"""The robot the calibration moves and how it is commanded.

Models (``MODELS``): ``exact`` is the robot file as it is (pulley kinematics and Hooke elasticity);
``standard`` is the straight-line model, every pulley a fixed point (h = r_p = 0) and the cables
rigid, realised as the physical equilibrium with E multiplied by ``STANDARD_STIFFENING``; ``rigid``
(the study's middle model) keeps the pulleys with rigid cables (``model_robot``).

Winches: on a robot file with ``winch:`` the commanded lengths go through the drums
(``realised_lengths``, ``drive.realised_rest_lengths``; NaN, flagged ``DRUM_RANGE``, where a drum
cannot pay a length out). Commands (``COMMANDS``): the standard lengths L_TS or, for a 6-DoF
platform, the compensated rest lengths (``commanded_lengths``). The equilibria of every robot by
``equilibria`` (engine ``equilibrium_engine``).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 1-5).
Métillon, M. et al. (2022), eq. 31-32 (the winch's length error; ``cdpr.models.drive``).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cdpr.analyses.compensation import compensate
from cdpr.errors import CdprError
from cdpr.models.drive import commanded_for, has_winches, realised_rest_lengths
from cdpr.models.equilibrium import hanging_cables
from cdpr.models.inverse import L_TS
from cdpr.models.platform import rotation_matrix, rotvec_of
from cdpr.models.sensitivity import (
    COND_MAX,
    T_TOL,
    rest_length_sensitivities,
)
from cdpr.parameters import (
    is_spatial,
    parameter_values,
    robot_with_parameters,
)
from cdpr.robot import with_pulleys
from cdpr.solve import check_engine, sensitivities, sensitivities_at, solve

#: How the candidate and simulated poses are commanded: standard lengths L_TS (the point mass's only
#: choice) or, for a 6-DoF platform, the compensated rest lengths of the minimum-norm tension
#: distribution (``compensation.compensate``, sag-consistent with heavy cables; a fully constrained robot needs them).
COMMANDS = ("standard", "compensated")
#: Model of the robot during the fit (the command line's choices).
MODELS = ("exact", "standard")
#: Also ``rigid``: pulley kinematics with rigid cables (the calibration study's middle model).
ALL_MODELS = ("standard", "rigid", "exact")
#: Factor on E that makes the standard model's cables rigid (stretch of a few micrometres).
STANDARD_STIFFENING = 1e3
#: Status of a sample whose commanded length the drum cannot pay out (a robot with winches).
DRUM_RANGE = "outside the drum's range"


def model_robot(robot, model):
    """The robot the fit moves: ``exact`` the robot itself, ``standard`` fixed pulleys and rigid cables.

    Parameters
    ----------
    robot : Robot
    model : {"exact", "standard", "rigid"}
        ``rigid``: the robot's pulleys, rigid cables.

    Returns
    -------
    Robot
    """
    if model not in ALL_MODELS:
        raise CdprError(f"unknown model {model!r}; allowed: {', '.join(MODELS)}")
    if model == "exact":
        return robot
    rigid = robot if model == "rigid" else without_winches(with_pulleys(robot, kind="fixed", h=0.0, r_p=0.0))
    th = parameter_values(rigid)
    th[: robot.m] *= STANDARD_STIFFENING
    return robot_with_parameters(rigid, th)


def without_winches(robot):
    """The robot with its winches removed: the commanded lengths are then the rest lengths (the
    standard model knows no drum)."""
    if all(w is None for w in robot.winches):
        return robot
    return dataclasses.replace(robot, cables=tuple(dataclasses.replace(c, winch=None) for c in robot.cables))


def realised_lengths(robot, L_cmd):
    """The rest lengths ``robot`` realises under the commanded lengths L_cmd (N, m) [m]: L_cmd itself
    without winches, ``drive.realised_rest_lengths`` with them (the robot file's ``winch:``; NaN
    where the drum cannot pay the length out)."""
    if not has_winches(robot):
        return np.asarray(L_cmd, dtype=float)
    return realised_rest_lengths(robot, L_cmd)[0]


def executed_lengths(model, actual):
    """The map from the rest lengths a compensating ``model`` wants to those the ``actual`` robot
    realises: a model with winches asks the no-winch controller for ``drive.commanded_for`` its
    wanted lengths (it knows the drums), a model without takes its rest lengths as the commands;
    the actual robot's drums then pay out ``realised_lengths``. None when neither has winches (the
    identity)."""
    if not (has_winches(model) or has_winches(actual)):
        return None

    def execute(L0):
        L_cmd = commanded_for(model, L0) if has_winches(model) else L0
        return realised_lengths(actual, L_cmd)

    return execute


def default_start(robot):
    """A start point for samples without a pose: below the anchors' centroid at half the lowest
    anchor's height.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    p : ndarray, shape (3,) [m]
    """
    A = robot.A
    return np.array([A[:, 0].mean(), A[:, 1].mean(), 0.5 * A[:, 2].min()])


def check_command(command, robot):
    """Refuse a command the robot cannot take, in one line naming the allowed ones: ``COMMANDS``
    for a 6-DoF platform, "standard" only for a point mass.

    Parameters
    ----------
    command : str
    robot : Robot

    Returns
    -------
    None

    Raises
    ------
    CdprError
    """
    if command not in COMMANDS or (command != "standard" and not is_spatial(robot)):
        allowed = COMMANDS if is_spatial(robot) else COMMANDS[:1]
        raise CdprError(f"command {command!r}: allowed for robot {robot.name}: {', '.join(allowed)}")


def commanded_lengths(robot, p, R, command="standard"):
    """Rest lengths commanded at 6-DoF poses: ``inverse.L_TS`` (standard) or the compensated rest
    lengths of the minimum-norm tensions (``compensation.compensate``, NaN where no admissible
    distribution exists; with heavy cables the sag-consistent distribution and rest lengths, so that
    a model computing its own commands reaches its targets).

    Parameters
    ----------
    robot : Robot
    p : ndarray, shape (n, 3) [m]
    R : ndarray, shape (n, 3, 3) [-]
    command : {"standard", "compensated"}

    Returns
    -------
    L0 : ndarray, shape (n, m) [m]
    """
    check_command(command, robot)
    if command == "standard":
        return L_TS(robot, p, R=R)
    return compensate(robot, p, rotvec=rotvec_of(R))["L0"]


def differentiable(hooke, cond):
    """Where an equilibrium of the pose model is differentiable: no cable's Hooke tension within
    ``T_TOL`` of 0 (the taut set would change) and a condition number of dF/dx below ``COND_MAX``.

    Parameters
    ----------
    hooke : ndarray, shape (n, m) [N]
        Hooke tensions (negative on a slack cable).
    cond : ndarray, shape (n,) [-]
        Scaled condition numbers of dF/dx.

    Returns
    -------
    ndarray, shape (n,) of bool
    """
    return (np.abs(hooke) > T_TOL).all(axis=1) & (cond < COND_MAX)


def drum_or_standard(robot, L0, drum, p, rv):
    """The rest lengths L0 where the drums can pay them out (``drum``), elsewhere the standard
    lengths at the start poses (p, rv): a harmless solve for the samples flagged ``DRUM_RANGE``
    afterwards.

    Parameters
    ----------
    robot : Robot
    L0 : ndarray, shape (n, m) [m]
        Realised rest lengths (NaN rows where a drum cannot pay out).
    drum : ndarray, shape (n,) of bool
        Where every drum can.
    p : ndarray, shape (n, 3) [m]
        Start positions.
    rv : ndarray, shape (n, 3) [rad]
        Start orientations (rotation vectors).

    Returns
    -------
    L0 : ndarray, shape (n, m) [m]
    """
    if drum.all():
        return L0
    return np.where(drum[:, None], L0, L_TS(robot, p, R=rotation_matrix(rv)))


def equilibrium_engine(robot, engine=None):
    """The engine of the calibration's equilibria (fits, plans, checks, simulations): a named engine,
    checked by ``solve.check_engine``; None keeps the solvers' default (compiled) for every robot:
    the numpy and compiled pose sensitivities take dF/dθ by the same exact formulas and agree to
    round-off (``sensitivity.sensitivities_at``).

    Parameters
    ----------
    robot : Robot
        The robot (every robot has the same default).
    engine : {"compiled", "numpy"} or None

    Returns
    -------
    str or None
    """
    return None if engine is None else check_engine(engine, "newton")


def equilibria(robot, P, L0, rotvec=None, solver=None, engine=None):
    """The physical equilibria under commanded rest lengths L0 started at poses (P, rotvec), with
    the ``smooth`` flag, by ``equilibrium_engine(robot, engine)``: a suspended point mass (pulley
    axes +z) by the point-mass physical solve (``solve.sensitivities``); every other robot by the
    pose model (``solve.solve``), smooth where ``differentiable`` says so on a rigid platform and,
    on a point mass under a tilted pulley axis (whose 6 × 6 Jacobian has no moment rows), where
    ``solve.sensitivities_at`` says so (the point-mass physical mode's rule on the translation
    block).

    Parameters
    ----------
    robot : Robot
    P : ndarray, shape (n, 3) or (n, 6) [m, rad]
        Start poses.
    L0 : ndarray, shape (n, m) [m]
        Rest lengths.
    rotvec : ndarray, shape (n, 3) [rad], optional
        Start orientations (default identity).
    solver : dict, optional
        tol, maxiter, max_step of the physical solve.
    engine : {"compiled", "numpy"} or None
        ``equilibrium_engine``.

    Returns
    -------
    dict
        P_s (n, 3) [m], status, smooth, n_taut (n,), t (n, m) [N] and the rest of the solver's
        result (R_s, rotvec_s, taut on the pose model); on the pose model also holding (n, m) bool,
        the taut cables less the heavy ones that hang at about their own weight
        (``equilibrium.hanging_cables``; = taut with massless cables).
    """
    engine = equilibrium_engine(robot, engine)
    if robot.suspended_point_mass:
        return sensitivities(robot, P, redundancy="physical", L=L0, engine=engine, **dict(solver or {}))
    rv = np.zeros((len(np.atleast_2d(P)), 3)) if rotvec is None else rotvec  # the pose keys (R_s)
    res = solve(robot, P, rv, redundancy="physical", engine=engine, L0=L0, **dict(solver or {}))
    if robot.point_mass:
        res["smooth"] = sensitivities_at(robot, res, names=[], engine=engine)["smooth"]
        return res
    _, hooke, cond = rest_length_sensitivities(robot, res["P_s"], res["R_s"], res["L0"])
    res["smooth"] = differentiable(hooke, cond)
    res["holding"] = res["taut"].copy()  # heavy cables hanging at about their own weight do not hold
    if robot.heavy:
        res["holding"] &= ~hanging_cables(res["t"], robot.arrays.w, robot.arrays.ES, res["L0"])
    return res
