"""Compensated cable lengths: the inverse elasto-geometric model, and the error left when the real
robot differs from the model used to compensate.

To hold the platform at p with planned tensions t (``distribution``), cable i must be stretched to
its extended-model length at p, so its commanded rest length is

    L0_i = L_TE,i(p) / (1 + t_i / (E_i S_i))

(Hooke, eq. 10 and 13, solved for the rest length; L_TE from eq. 3-5). With these lengths the
physical equilibrium (``equilibrium``) of the same robot is p itself, with the planned tensions:
the force balance holds at p by construction, and each taut cable's Hooke tension is t_i. A cable
planned at t_i = 0 gets L0_i = L_TE,i(p), slack at the limit.

Methods (``method``): the distributions of ``distribution`` (``min_norm``, ``closed_form``,
``closed_form_improved``), or ``subset``: the paper's choice, the 3-cable subset that paper mode
(``redundancy``) keeps at p, with the tensions that subset needs at p (eq. 11-12) and the other
cables slack at the limit (L0 = L_TE(p), zero tension at p). That keeps the paper's actuation
scheme exactly (the extra cable carries nothing at p) while leaving it ready: if the platform sags
below p (a softer cable than modelled) the extra cable tightens and takes load.

References
----------
Paty et al. 2021, eq. (3)-(5), (10)-(13):
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.

A. Pott, Cable-Driven Parallel Robots: Theory and Application, Springer 2018 (force distribution and
elastic cable models).
"""

from __future__ import annotations

import numpy as np

from cdpr.errors import CdprError
from cdpr.models.inverse import igm_e
from cdpr.models.results import STATUSES
from cdpr.models.statics import tensions
from cdpr.models.tension_distribution import (
    METHODS,
    T_MIN_DEFAULT,
    compensated_lengths,
    distribute,
    wrench_matrix,
)
from cdpr.solve import check_engine, solve

COMP_METHODS = (*METHODS, "subset")
#: Statuses of a compensated pose: the physical ones, and ``infeasible`` where no tension
#: distribution exists at p (nothing is commanded there).
COMP_STATUSES = (*STATUSES, "infeasible")


def rest_lengths(L_TE, t, ES):
    """Rest length that stretches to L_TE under tension t: L0 = L_TE / (1 + t / (E S)).

    Parameters
    ----------
    L_TE : array_like, shape (..., m) [m]
    t : array_like, shape (..., m) [N]
    ES : array_like, shape (m,) [N]

    Returns
    -------
    L0 : ndarray, shape (..., m) [m]

    References
    ----------
    Paty et al. 2021, eq. (10), (13).
    """
    return np.asarray(L_TE, dtype=float) / (1.0 + np.asarray(t, dtype=float) / ES)


def _subset_tensions(robot, p, engine):
    """Paper mode's subset at p and the tensions it needs at p; the other cables at zero."""
    res = solve(robot, p, redundancy="paper", engine=engine)
    sub = res["subset"]
    has = sub[:, 0] >= 0
    n = len(p)
    safe = np.where(has[:, None], sub, np.arange(3))
    W = wrench_matrix(robot, p)
    u = np.take_along_axis(np.swapaxes(W, 1, 2), safe[:, :, None], axis=1)  # (N, 3 cables, 3)
    ts, _ = tensions(u, robot.platform.w_ext)
    t = np.zeros((n, robot.m))
    np.put_along_axis(t, safe, ts, axis=1)
    ok = has & (res["status"] == "ok") & np.isfinite(ts).all(axis=1) & (ts >= 0).all(axis=1)
    ok &= (t <= robot.T_a).all(axis=1)
    return t, ok, np.where(has[:, None], sub, -1)


def at_poses(robot, p, rotvec=None):
    """True when ``compensate`` and ``compensated_pose`` take the 6-DoF path: a robot that is not a
    suspended point mass (``Robot.suspended_point_mass``), poses p (N, 6) or an orientation
    ``rotvec`` given (the command line's rule for ``compensate``).

    Parameters
    ----------
    robot : Robot
    p : ndarray (N, 3) or (N, 6) [m, rad]
    rotvec : array_like (3,) or (N, 3) [rad], optional

    Returns
    -------
    bool
    """
    return rotvec is not None or p.shape[1] == 6 or not robot.suspended_point_mass


def _compensate6(robot, p, rotvec, method, t_min, t_max, options):
    """``compensate`` at poses: ``tension_distribution.compensated_lengths`` (Paty 2021 eq. (10), (13) with
    the 6 x m wrench matrix)."""
    if method not in METHODS:
        raise CdprError(
            f"compensation at a pose (rigid platform, poses or rotvec) takes method {', '.join(METHODS)}, "
            f"got {method!r} (the 3-cable subset is the point-mass rule)"
        )
    if options:
        raise CdprError(f"compensation at a pose takes no distribution options, got {', '.join(options)}")
    c = compensated_lengths(robot, p, rotvec, t_min, t_max, method)  # poses (N, 6) carry their rotvec
    return {key: c[key] for key in ("p", "R", "L0", "t", "L_TE", "feasible")}


def compensate(
    robot, p, method="min_norm", t_min=T_MIN_DEFAULT, t_max=None, engine=None, rotvec=None, **options
):
    """Compensated rest lengths that hold the platform of ``robot`` at p with planned tensions.

    Parameters
    ----------
    robot : Robot
        The model used to compensate (its geometry and E_i S_i).
    p : array_like, shape (N, 3) [m] or (N, 6) [m, rad]
        Desired positions, or poses of a rigid platform.
    method : {"min_norm", "closed_form", "closed_form_improved", "subset"}
    t_min, t_max : float or array_like (m,) [N]
        Tension bounds of the distribution (``t_max`` default T_a,i); not used by ``subset``
        (0 <= t <= T_a there, as in paper mode).
    engine : {"compiled", "numpy", None}
        Paper-mode engine for ``subset`` (``solve.check_engine``: None is compiled; another value
        raises CdprError).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientation (default identity). With it, with poses p (N, 6) or on a robot that is
        not a suspended point mass (``at_poses``) the compensation is the 6-DoF one
        (``tension_distribution.compensated_lengths``: no ``subset`` method, no options).
    options : passed to ``cdpr.models.tension_distribution.distribute``.

    Returns
    -------
    dict
        p (N, 3) [m]; L0 (N, m) [m], NaN where infeasible; t (N, m) [N] planned tensions;
        L_TE (N, m) [m] at p; feasible (N,) bool; subset (N, 3) 0-based for ``subset`` (else
        absent); at poses also R (N, 3, 3), the desired orientations.

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10)-(13).
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    engine = check_engine(engine, "newton")
    if at_poses(robot, p, rotvec):
        return _compensate6(robot, p, rotvec, method, t_min, t_max, options)
    L_TE = igm_e(robot, p).L_TE
    out = {"p": p}
    if method == "subset":
        t, ok, out["subset"] = _subset_tensions(robot, p, engine)
    elif method in METHODS:
        d = distribute(robot, p, method, t_min=t_min, t_max=t_max, **options)
        t, ok = d["t"], d["feasible"]
    else:
        raise ValueError(f"unknown compensation method {method!r}; allowed: {', '.join(COMP_METHODS)}")
    L0 = np.where(ok[:, None], rest_lengths(L_TE, t, robot.ES), np.nan)
    out.update(L0=L0, t=t, L_TE=L_TE, feasible=ok)
    return out


def compensated_pose(
    robot,
    p,
    actual=None,
    method="min_norm",
    engine=None,
    t_min=T_MIN_DEFAULT,
    t_max=None,
    solver=None,
    realise=None,
    rotvec=None,
    threads=None,
    **options,
):
    """Compensate with ``robot``, then let the platform settle on the ``actual`` robot.

    The rest lengths of ``compensate(robot, p, ...)`` are commanded to ``actual`` (default: the same
    robot, which returns p itself); its physical equilibrium P* (``solve.solve`` in
    physical mode) gives the residual error |dp| = |P* - p|,
    e.g. for cables whose real moduli differ from the modelled one.

    Parameters
    ----------
    robot : Robot
        The model used to compensate.
    p : array_like, shape (N, 3) [m] or (N, 6) [m, rad]
        Desired positions, or poses (``compensate``).
    actual : Robot, optional
        The robot that executes the lengths (same anchors, pulleys and cables, other values).
    method, t_min, t_max, options : as ``compensate``.
    engine : {"compiled", "numpy", None}
        ``solve.check_engine``: None is compiled; another value raises CdprError.
    solver : dict, optional
        Options of the physical solve (tol, maxiter, max_step).
    realise : callable, optional
        L0 (k, m) [m] -> the rest lengths the actual robot realises (k, m) [m] under those commands,
        NaN where it cannot (e.g. through its drums, ``calibration.executed_lengths``); default the
        identity. Points it cannot realise are ``infeasible``.
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientation: at poses (``at_poses``) the 6-DoF compensation and the 6-DoF
        equilibrium of ``actual`` (``solve.solve``).
    threads : int, optional
        Threads of the compiled engine.

    Returns
    -------
    dict
        As ``solve.solve`` in physical mode, plus L0 (N, m) [m],
        t_planned (N, m) [N] and ``statuses`` (``COMP_STATUSES``): status ``infeasible`` (P_s, dp,
        t NaN; at poses also rotvec_s and dphi) where no distribution exists.
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    actual = robot if actual is None else actual
    if actual.m != robot.m:
        raise ValueError(f"the actual robot has {actual.m} cables, the model {robot.m}")
    six = at_poses(robot, p, rotvec)
    comp = compensate(
        robot, p, method=method, t_min=t_min, t_max=t_max, engine=engine, rotvec=rotvec, **options
    )
    ok = comp["feasible"]
    L_act = comp["L0"]
    if realise is not None:
        L_act = np.full(comp["L0"].shape, np.nan)
        L_act[ok] = realise(comp["L0"][ok])
        ok = ok & np.isfinite(L_act).all(axis=1)
    if six:
        rv = p[:, 3:].copy() if p.shape[1] == 6 else _rotvecs(p, rotvec)
        p6 = np.concatenate([comp["p"], rv], axis=1)
        res = solve(
            actual,
            p6[ok],
            redundancy="physical",
            engine=engine,
            threads=threads,
            L0=L_act[ok],
            **(solver or {}),
        )
    else:
        res = solve(
            actual,
            p[ok],
            engine=engine,
            threads=threads,
            redundancy="physical",
            L0=L_act[ok],
            **(solver or {}),
        )
    p = comp["p"]
    n, m = len(p), robot.m
    out = {"p": p}
    fill = {
        "P_s": (np.nan, (n, 3)),
        "dp": (np.nan, (n,)),
        "t": (np.nan, (n, m)),
        "taut": (False, (n, m)),
        "n_taut": (0, (n,)),
        "residual": (np.nan, (n,)),
        "iterations": (0, (n,)),
    }
    if six:
        fill.update(rotvec_s=(np.nan, (n, 3)), dphi=(np.nan, (n,)), unique=(True, (n,)))
    for key, (value, shape) in fill.items():
        arr = np.full(shape, value, dtype=res[key].dtype)
        arr[ok] = res[key]
        out[key] = arr
    code = np.full(n, COMP_STATUSES.index("infeasible"), dtype=np.int8)
    code[ok] = res["status_code"]
    out.update(
        status_code=code,
        status=np.asarray(COMP_STATUSES)[code],
        statuses=COMP_STATUSES,
        L0=comp["L0"],
        t_planned=comp["t"],
    )
    if "subset" in comp:
        out["subset"] = comp["subset"]
    if six:
        out["rotvec"] = rv
        alternatives = [[] for _ in range(n)]
        for k, alt in zip(np.flatnonzero(ok), res["alternatives"]):
            alternatives[k] = alt
        out["alternatives"] = alternatives
    return out


def _rotvecs(p, rotvec):
    """The desired rotation vectors (N, 3) [rad] of positions p with ``rotvec`` (default identity)."""
    n = len(p)
    return (
        np.zeros((n, 3))
        if rotvec is None
        else np.broadcast_to(np.asarray(rotvec, dtype=float), (n, 3)).copy()
    )
