"""The reached equilibrium: the pose a robot settles in when its commanded rest lengths move
continuously from a known equilibrium to the target, tracked by continuation (issue 39).

A robot whose winches change the rest lengths slowly follows its current equilibrium; it does not
jump over an energy barrier to the lowest one. The robot starts at a known equilibrium (P_0, R_0)
under rest lengths L_start, and the commanded lengths move linearly to the target,

    L0(λ) = L_start + λ (L_target - L_start),   λ from 0 to 1,

each step solved from the previous equilibrium by the local solver of the force and moment balance
(``equilibrium``'s Newton iteration: a descent of the energy where one exists, Newton on the
balance for DR pulleys, heavy cables and external wrenches), without restarts.

Steps (``reach``)
-----------------
A step λ -> λ + h is accepted when solving it whole and as two halves gives the same equilibrium
(to ``AGREE`` in m + rad, the rotation measured as |R_a - R_b|_F / sqrt 2) and the platform moves
by at most ``JUMP`` (m + rad) across it; otherwise h is halved. An accepted step doubles h (at most
``H_MAX``). Halving every accepted step therefore changes nothing beyond the solver's tolerance
(tests/models/test_continuation.py: K and 2K steps agree to 1e-9).

Folds
-----
A fold is a step across which the tracked equilibrium ceases to exist (it merges with an unstable
one, typically when a cable goes slack and the others cannot hold the platform where it was) and
the platform snaps: the motion across the step exceeds ``JUMP`` = 0.02 (m + rad) and still does
when the step in λ is refined down to ``H_MIN`` = 1e-7. The path then goes on from the equilibrium
the platform snapped to (the two-half-step solution), and the fold is reported with its λ, the jump
(position [m], rotation [rad]) and the taut sets before and after.

Where the local solver converges to no equilibrium even at the least step (the model's force is
not continuous there, e.g. a pulley's wrap angle switching), or a path takes more than
``MAX_STEPS`` steps, the tracking ends and the point is reported ``not_converged``.

Starts (``start``)
------------------
* ``compensated`` (default): the desired pose held by its minimum-norm compensated rest lengths
  with tensions in [t_min, t_max] (``tension_distribution.compensated_lengths``); the start is the
  local equilibrium under those lengths from the desired pose (the desired pose itself, to the
  solver's tolerance, for massless cables).
* ``search``: where no such distribution exists, the equilibrium of the multi-start search
  (``equilibrium.solve`` with restarts) under the target lengths nearest to the desired pose
  (|P - p| + δφ); the path is then the single pose under constant lengths.
* ``given``: the robot at equilibrium near a given pose under given lengths (``from_p``,
  ``from_rotvec``, ``from_lengths``).

References
----------
Allgower, E. L., Georg, K. (2003). Introduction to Numerical Continuation Methods. SIAM, ch. 1-2
(natural-parameter continuation, turning points).

Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (eq. 2-5, 10-14).
"""

from __future__ import annotations

import numpy as np

from cdpr.errors import CdprError
from cdpr.models import equilibrium
from cdpr.models.platform import pose_arrays, rotation_error, rotation_matrix, rotvec_of
from cdpr.models.results import ST, STATUSES, TAUT_MIN
from cdpr.models.tension_distribution import T_MIN_DEFAULT, compensated_lengths

#: Two solutions of one step agree when they differ by at most this [m + rad].
AGREE = 1e-9
#: A step that moves the platform by more than this [m + rad] is refined; at ``H_MIN`` it is a fold.
JUMP = 0.02
#: The smallest and the largest step in λ, and the first step.
H_MIN = 1e-7
H_MAX = 0.25
H_FIRST = 0.0625
#: Newton's iteration cap along the path (a snap may need many line-searched steps).
MAXITER = 200
#: The most steps of one path (then the point is reported not converged).
MAX_STEPS = 5000
#: The starts of a continuation.
STARTS = ("compensated", "search", "given")


def pose_distance(P_a, R_a, P_b, R_b):
    """Distance of poses [m + rad]: |P_a - P_b| + |R_a - R_b|_F / sqrt 2 (the rotation angle to
    first order, exact to round-off near zero where arccos is not).

    Parameters
    ----------
    P_a, P_b : ndarray (N, 3) [m]
    R_a, R_b : ndarray (N, 3, 3) [-]

    Returns
    -------
    ndarray (N,) [m + rad]
    """
    return np.linalg.norm(P_a - P_b, axis=1) + np.linalg.norm(R_a - R_b, axis=(1, 2)) / np.sqrt(2.0)


def least_tensions(robot):
    """The least tensions of the compensated start: each cable's ``min_tension_N`` (the robot
    file's bound), ``tension_distribution.T_MIN_DEFAULT`` (100 N, ``cdpr compensate``'s default)
    where the file sets none (0): a start held with pretension, every cable taut.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    ndarray (m,) [N]
    """
    t = np.array([c.material.T_min for c in robot.cables], dtype=float)
    return np.where(t > 0, t, T_MIN_DEFAULT)


def _taut(t):
    return [int(i) + 1 for i in np.flatnonzero(t > TAUT_MIN)]


def _solve(cab, newton, P, R, L0, p_ref, tol, maxiter, max_step):
    """One local Newton solve of every row from (P, R): P, R, t, converged."""
    P2, R2, cur, _, conv = newton(cab, P, R.copy(), L0, p_ref, tol, maxiter, max_step)
    return P2, R2, cur["t"], conv


def _track(cab, newton, P, R, L_start, L_target, p_ref, stop, schedule):
    """The continuation of N rows from (P, R) at λ = 0 to λ = 1 (module docstring); with
    ``schedule`` (an increasing λ grid from 0 to 1) one Newton solve per grid step instead."""
    n = len(P)
    lam = np.zeros(n)
    h = np.full(n, H_FIRST)
    dL = L_target - L_start
    P, R = P.copy(), R.copy()
    folds = [[] for _ in range(n)]
    lams = [[0.0] for _ in range(n)]
    stuck = np.zeros(n, dtype=bool)
    steps = np.zeros(n, dtype=np.int64)
    at = lambda rows, x: L_start[rows] + x[:, None] * dL[rows]  # noqa: E731
    # t at the start (the taut set before a first-step fold)
    _, _, t, conv = _solve(cab, newton, P, R, at(np.arange(n), lam), p_ref, *stop)
    if schedule is not None:
        grid = np.asarray(schedule, dtype=float)
        if grid[0] != 0.0 or grid[-1] != 1.0 or np.any(np.diff(grid) <= 0):
            raise CdprError("a continuation schedule runs from 0 to 1 in increasing steps")
        rows = np.arange(n)
        for x in grid[1:]:
            lx = np.full(n, x)
            P2, R2, t2, c2 = _solve(cab, newton, P, R, at(rows, lx), p_ref, *stop)
            jump = pose_distance(P, R, P2, R2)
            for i in np.flatnonzero(jump > JUMP):
                folds[i].append(_fold(x, P[i], R[i], P2[i], R2[i], t[i], t2[i]))
            P, R, t, conv = P2, R2, t2, c2
            for i in rows:
                lams[i].append(float(x))
        return P, R, t, conv & ~stuck, folds, lams, stuck
    still = np.flatnonzero(~(dL != 0).any(axis=1))  # the lengths do not move: the start is the end
    lam[still] = 1.0
    for i in still:
        lams[i].append(1.0)
    active = np.flatnonzero(lam < 1.0)
    while active.size:
        x0, hh = lam[active], h[active]
        x1 = np.minimum(x0 + hh, 1.0)
        xm = 0.5 * (x0 + x1)
        Pa, Ra, _, ca = _solve(cab, newton, P[active], R[active], at(active, x1), p_ref[active], *stop)
        Pm, Rm, _, cm = _solve(cab, newton, P[active], R[active], at(active, xm), p_ref[active], *stop)
        Pb, Rb, tb, cb = _solve(cab, newton, Pm, Rm, at(active, x1), p_ref[active], *stop)
        jump = pose_distance(P[active], R[active], Pb, Rb)
        agree = ca & cm & cb & (pose_distance(Pa, Ra, Pb, Rb) <= AGREE)
        smooth = agree & (jump <= JUMP)
        floor = (x1 - x0) <= H_MIN
        take = smooth | floor
        lost = floor & ~(ca & cm & cb)  # the local solver finds no equilibrium even at the least step
        lost |= ~take & (steps[active] >= MAX_STEPS)
        take |= lost
        stuck[active[lost]] = True
        for k in np.flatnonzero(take & ~smooth & (jump > JUMP)):
            i = active[k]
            folds[i].append(_fold(x1[k], P[i], R[i], Pb[k], Rb[k], t[i], tb[k]))
        rows = active[take]
        P[rows], R[rows], t[rows], conv[rows] = Pb[take], Rb[take], tb[take], cb[take]
        lam[rows] = x1[take]
        lam[active[lost]] = 1.0  # tracking ends there: reported not converged
        steps[active] += 1
        for i, x in zip(rows, x1[take]):
            lams[i].append(float(x))
        # the next step: doubled, but aimed at half the jump limit where the path moves fast
        grow = np.minimum(2.0, 0.5 * JUMP / np.maximum(jump[take], 1e-300))
        h[rows] = np.minimum(np.maximum(grow, 1.0) * (x1[take] - x0[take]), H_MAX)
        h[rows[~smooth[take]]] = H_MIN * 2.0  # after a fold or an unresolved step: grow again from small
        h[active[~take]] = 0.5 * (x1[~take] - x0[~take])
        active = active[lam[active] < 1.0]
    return P, R, t, conv & ~stuck, folds, lams, stuck


def _fold(lam, P0, R0, P1, R1, t0, t1):
    """The report of a fold at λ: the jump of position [m] and rotation [rad], the taut sets."""
    return {
        "lambda": float(lam),
        "jump_m": float(np.linalg.norm(P1 - P0)),
        "jump_rad": float(rotation_error(R1[None], R0[None])[0]),
        "taut_before": _taut(t0),
        "taut_after": _taut(t1),
    }


def reach(
    robot,
    cab,
    newton,
    p,
    rotvec=None,
    L0=None,
    start="compensated",
    t_min=None,
    t_max=None,
    from_p=None,
    from_rotvec=None,
    from_lengths=None,
    schedule=None,
    standard=None,
):
    """The equilibrium reached by continuation from a known one (module docstring), at N poses.

    Parameters
    ----------
    robot : Robot
    cab : Cables
        The cables the given ``newton`` reads (``equilibrium``'s ``Cables`` or a subclass, or the
        compiled engine's).
    newton : callable
        ``newton(cab, p0, R0, L0, p_ref, tol, maxiter, max_step)`` as ``equilibrium.local_newton``.
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    rotvec : array_like (N, 3) or (3,) [rad], optional
        Desired orientations, default identity.
    L0 : array_like (N, m) or (m,) [m], optional
        Target rest lengths, default ``standard`` (L_TS) at the desired pose.
    start : {"compensated", "given"}
        The start (module docstring); "compensated" falls back to "search" per pose where the
        tension distribution does not exist. "given" needs ``from_p`` and ``from_lengths``.
    t_min, t_max : float or array_like (m,) [N], optional
        Tension bounds of the compensated start: default ``least_tensions`` and each cable's T_a.
    from_p : array_like (3,) or (N, 3) [m], optional
        The given start's position (near its equilibrium).
    from_rotvec : array_like (3,) or (N, 3) [rad], optional
        The given start's orientation, default identity.
    from_lengths : array_like (m,) or (N, m) [m], optional
        The given start's rest lengths.
    schedule : array_like, optional
        A fixed λ grid from 0 to 1 (one Newton solve per step, no refinement) instead of the
        adaptive steps: the K vs 2K check.
    standard : callable, optional
        Default rest lengths ``standard(robot, p, R)`` (L_TS when None).

    Returns
    -------
    dict
        ``equilibrium.solve``'s keys at the reached equilibrium (energy relative to the desired
        pose, so comparable with the global one; unique True and no alternatives: none were
        sought), and start (N,) str, folds (N lists of dicts with lambda, jump_m, jump_rad,
        taut_before, taut_after), n_folds (N,) int, lambdas (N lists of the accepted λ), P_start
        (N, 3) [m], rotvec_start (N, 3) [rad], L_start (N, m) [m].

    Raises
    ------
    CdprError
        An unknown start, or a given start without its pose or lengths or with the wrong number of
        lengths.
    """
    if start not in ("compensated", "given"):
        raise CdprError(f"unknown continuation start {start!r}; allowed: compensated, given")
    tol, _, max_step = equilibrium.stop_rules()
    stop = (tol, MAXITER, max_step)
    pose = equilibrium.set_up(robot, p, rotvec, L0, None, standard)
    n, m = len(pose.p), robot.m
    kind = np.full(n, start, dtype=object)
    if start == "given":
        if from_p is None or from_lengths is None:
            raise CdprError(
                "a given start needs its pose (--from X Y Z) and its rest lengths (--from-lengths)"
            )
        L_start = np.asarray(from_lengths, dtype=float)
        if L_start.shape[-1] != m:
            raise CdprError(f"--from-lengths needs one rest length per cable ({m}), got {L_start.shape[-1]}")
        P0, R0 = pose_arrays(np.broadcast_to(np.asarray(from_p, dtype=float), (n, 3)), from_rotvec)
        R0 = np.broadcast_to(R0, (n, 3, 3)).copy()
        L_start = np.broadcast_to(L_start, (n, m)).copy()
        P0, R0, _, _ = _solve(cab, newton, P0, R0, L_start, pose.p, *stop)
    else:
        t_min = least_tensions(robot) if t_min is None else t_min
        comp = compensated_lengths(robot, pose.p, pose.rv_d, t_min, t_max)
        L_start = np.where(comp["feasible"][:, None], comp["L0"], pose.L0)
        P0, R0 = pose.p.copy(), pose.R_d.copy()
        ok = comp["feasible"]
        if ok.any():
            P0[ok], R0[ok], _, _ = _solve(cab, newton, P0[ok], R0[ok], L_start[ok], pose.p[ok], *stop)
        bad = np.flatnonzero(~ok)
        if bad.size:
            kind[bad] = "search"
            P0[bad], R0[bad] = _nearest(robot, cab, newton, pose, bad)
    P, R, t, conv, folds, lams, stuck = _track(cab, newton, P0, R0, L_start, pose.L0, pose.p, stop, schedule)
    first = newton(cab, P, R.copy(), pose.L0, pose.p, *stop)
    res = equilibrium.finish(robot, cab, newton, pose, first, *stop, restarts=False)
    res["converged"] &= ~stuck
    res["status_code"][stuck] = ST["not_converged"]
    res["status"] = np.asarray(STATUSES)[res["status_code"]]
    res.update(
        start=kind.astype(str),
        folds=folds,
        n_folds=np.array([len(f) for f in folds], dtype=np.int32),
        lambdas=lams,
        P_start=P0,
        rotvec_start=rotvec_of(R0),
        L_start=L_start,
    )
    return res


def _nearest(robot, cab, newton, pose, rows):
    """The equilibrium of the multi-start search under the target lengths nearest to the desired
    pose (|P - p| + δφ) at the poses ``rows``: P (k, 3) [m], R (k, 3, 3). Candidates that no cable
    holds (a Newton stop with every cable slack) are not equilibria and are passed over."""
    sub = equilibrium.Setup(pose.p[rows], pose.R_d[rows], pose.rv_d[rows], pose.L0[rows], pose.p[rows])
    tol, maxiter, max_step = equilibrium.stop_rules()
    first = newton(cab, sub.p0, sub.R_d.copy(), sub.L0, sub.p, tol, maxiter, max_step)
    res = equilibrium.finish(robot, cab, newton, sub, first, tol, maxiter, max_step, restarts=True)
    P, R = res["P_s"].copy(), res["R_s"].copy()
    for k in range(len(rows)):
        best = np.linalg.norm(P[k] - sub.p[k]) + rotation_error(R[k][None], sub.R_d[k][None])[0]
        if res["status"][k] == "not_converged":
            best = np.inf
        for alt in (a for a in res["alternatives"][k] if a["taut"]):  # a platform no cable holds is none
            Ra = rotation_matrix(np.asarray(alt["rotvec_s"]))
            d = (
                np.linalg.norm(np.asarray(alt["P_s"]) - sub.p[k])
                + rotation_error(Ra[None], sub.R_d[k][None])[0]
            )
            if d < best:
                best, P[k], R[k] = d, alt["P_s"], Ra
    return P, R
