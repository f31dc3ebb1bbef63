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

from cdpr.compiled import cables as compiled_cables
from cdpr.compiled.equilibrium import CompiledHeavyCables
from cdpr.errors import CdprError
from cdpr.models.cables import HeavyCables
from cdpr.models.inverse import pose_state
from cdpr.models.platform import external_wrench, pose_arrays
from cdpr.models.platform import wrench_matrix as pose_wrench_matrix
from cdpr.models.results import STATUSES
from cdpr.models.statics import tensions
from cdpr.models.tension_distribution import (
    METHODS,
    T_MIN_DEFAULT,
    closed_form,
    closed_form_improved,
    defined_rows,
    min_norm,
    min_norm_rows,
    rank_rows,
    wrench_matrix,
)
from cdpr.solve import HEAVY_KEYS, check_engine, heavy_cables_at, solve

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


#: The sag-consistent distribution's fixed point stops when no tension moves by more than this
#: fraction of the largest tension (``heavy_distribution``), or after ``HEAVY_MAXITER`` iterations.
HEAVY_RTOL = 1e-13
HEAVY_MAXITER = 100


def _distribution(W, w, method, t_min, t_max, options):
    """The tension distribution of wrench matrices W (N, r, m) reduced to their rank
    (``tension_distribution.rank_rows``) for the wrench w (N, r): Pott's closed forms, or the exact
    bounded minimum norm (``min_norm`` on 3 rows, a point mass: null space for m = 4, with its
    options; ``min_norm_rows`` on 6). Returns t (N, m) [N] and feasible (N,). A point where W is not
    finite (a zero-length cable has no direction: ``defined_rows``) is infeasible, its t NaN."""
    W, defined = defined_rows(W)
    if method == "closed_form":
        t, ok = closed_form(W, w, t_min, t_max)
    elif method == "closed_form_improved":
        t, ok = closed_form_improved(W, w, t_min, t_max)
    elif W.shape[1] == 3:
        opts = dict(options)
        solver = opts.pop("solver", "auto")
        t, ok = min_norm(W, w, t_min, t_max, method=solver, **opts)
    else:
        t, ok = min_norm_rows(W, w, t_min, t_max, **options)
    if defined.all():
        return t, ok
    return np.where(defined[:, None], t, np.nan), ok & defined


def _wrench(robot, R, u, r):
    """The wrench matrix of unit cable forces u (N, m, 3) at r_i = R b_i and the wrench -w_ext, both
    reduced to the rows their rank keeps (``rank_rows``: the 3 force rows of a point mass)."""
    W = pose_wrench_matrix(u, r)
    pl = robot.platform
    w = -external_wrench(pl.mass, pl.g, robot.arrays.com, R, pl.down, pl.wrench)
    return rank_rows(robot, W, w)


def heavy_distribution(
    robot, p, R, t_min=T_MIN_DEFAULT, t_max=None, method="min_norm", t0=None, engine=None, **options
):
    """The sag-consistent tension distribution of a robot with heavy cables (issue 38): the
    distribution (``method``, bounds on the tensions at B_i) of the wrench matrix whose columns are
    the unit end forces at B_i of the catenaries that carry those tensions
    (``cables.HeavyCables.inverse``), found by the fixed point t_(k+1) = distribution(W(t_k))
    started from t0 (default: the massless distribution, W of the chords' directions at the exit
    points of the massless model).

    .. math:: \\mathbf t = \\arg\\min_{\\mathbf W(\\mathbf t)\\,\\mathbf s = -\\mathbf w_{ext},\\;
        T_{min} \\le \\mathbf s \\le T_{max}} |\\mathbf s|_2

    Parameters
    ----------
    robot : Robot
        With heavy cables (w = 0 is allowed: the massless distribution, the chords' directions).
    p : ndarray (N, 3) [m]
        Positions.
    R : ndarray (N, 3, 3) [-]
        Orientations.
    t_min : float or array_like (m,) [N]
        Least tension at B_i.
    t_max : float or array_like (m,) [N], optional
        Largest tension at B_i (default T_a).
    method : {"min_norm", "closed_form", "closed_form_improved"}
        The distribution.
    t0 : ndarray (N, m) [N], optional
        Start of the fixed point (default the massless distribution).
    engine : {"compiled", "numpy", None}
        The heavy inverse's engine (``solve.check_engine``: None is compiled,
        ``compiled.cables.inverse``; numpy: ``cables.HeavyCables.inverse``); another value raises
        CdprError.
    options : passed to ``tension_distribution.min_norm`` (``t_ref``, ``solver``).

    Returns
    -------
    dict
        t (N, m) [N] tensions at B_i (NaN where infeasible); feasible (N,); iterations (N,) of the
        fixed point (distributions computed after the start); inverse (``HeavyCables.inverse`` at
        t: D, H, V_B, T_D, L0, ...); L0 (N, m) [m] the rest lengths that hold the platform at
        (p, R) under t in the heavy direct model.

    References
    ----------
    Irvine 1981, ch. 2; Pott 2018, ch. 3; Paty et al. 2021, eq. (11)-(13).
    """
    inverse = _heavy_inverse(robot, engine)
    t_max = robot.T_a if t_max is None else t_max
    n = len(p)
    if t0 is None:
        B, st = pose_state(robot, p, R)
        u = st.D - B
        u = u / np.linalg.norm(u, axis=-1, keepdims=True)
        t0, _ = _distribution(*_wrench(robot, R, u, B - p[:, None, :]), method, t_min, t_max, options)
    t = np.array(t0, dtype=float)
    ok = np.isfinite(t).all(axis=1)
    iters = np.zeros(n, dtype=np.int64)
    todo = ok.copy()
    for _ in range(HEAVY_MAXITER):
        if not todo.any():
            break
        idx = np.flatnonzero(todo)
        inv = inverse(p[idx], R[idx], t[idx])
        good = inv["converged"].all(axis=1)
        u = np.where(good[:, None, None], inv["f"], 0.0)
        W, w = _wrench(robot, R[idx], u, inv["r"])
        t_new, feas = _distribution(W, w, method, t_min, t_max, options)
        feas &= good
        with np.errstate(invalid="ignore"):
            moved = np.abs(t_new - t[idx]).max(axis=1)
            scale = np.abs(t_new).max(axis=1)
        iters[idx] += 1
        t[idx] = t_new
        ok[idx] = feas
        done = ~feas | (moved <= HEAVY_RTOL * scale)
        todo[idx[done]] = False
    ok &= ~todo  # no fixed point within HEAVY_MAXITER: infeasible, never a half-converged answer
    inv = inverse(p, R, np.where(ok[:, None], t, 1.0))
    ok &= inv["converged"].all(axis=1)
    t = np.where(ok[:, None], t, np.nan)
    L0 = np.where(ok[:, None], inv["L0"], np.nan)
    return {"t": t, "feasible": ok, "iterations": iters, "inverse": inv, "L0": L0}


def _heavy_inverse(robot, engine):
    """``HeavyCables.inverse`` of ``robot`` (p, R, t) -> dict by the engine ``engine``
    (``solve.check_engine``: None is compiled, ``compiled.cables.inverse``)."""
    if check_engine(engine, "newton") == "compiled":
        cab = CompiledHeavyCables(robot)
        return lambda p, R, t: compiled_cables.inverse(cab, p, R, t)
    return HeavyCables(robot).inverse


def _planned_cables(robot, p, R, L0, ok, engine=None):
    """The heavy cables at the desired poses under the compensated rest lengths
    (``solve.heavy_cables_at`` by ``engine``), NaN (status ``infeasible``) where no distribution exists."""
    h = heavy_cables_at(robot, p, R, L0, engine)
    for key, value in h.items():
        if key == "cable_status":
            h[key] = np.where(ok[:, None], value, "infeasible")
        elif value.dtype.kind == "f":
            h[key] = np.where(ok.reshape((-1,) + (1,) * (value.ndim - 1)), value, np.nan)
    return h


def compensate(
    robot, p, method="min_norm", t_min=T_MIN_DEFAULT, t_max=None, engine=None, rotvec=None, **options
):
    """Compensated rest lengths that hold the platform of ``robot`` at p with planned tensions.

    One path for the point mass and the rigid platform (the point mass is the platform with b = 0,
    its wrench matrix reduced to the 3 force rows, ``tension_distribution.rank_rows``): the
    distribution of the wrench matrix of the extended model at the pose, and the rest lengths of
    Hooke's law L0_i = L_TE,i / (1 + t_i / (E_i S_i)). With heavy cables (``Robot.heavy``) the
    distribution is the sag-consistent one (``heavy_distribution``) and L0_i the rest length that
    puts B_i on the catenary carrying t_i at B_i (``cables.HeavyCables.inverse``).

    Parameters
    ----------
    robot : Robot
        The model used to compensate (its geometry and E_i S_i).
    p : array_like, shape (N, 3) [m] or (N, 6) [m, rad]
        Desired positions, or poses of a rigid platform.
    method : {"min_norm", "closed_form", "closed_form_improved", "subset"}
    t_min, t_max : float or array_like (m,) [N]
        Tension bounds of the distribution (``t_max`` default T_a,i; at B_i for heavy cables); not
        used by ``subset`` (0 <= t <= T_a there, as in paper mode).
    engine : {"compiled", "numpy", None}
        Paper-mode engine for ``subset`` and the heavy cables' inverse and cables
        (``heavy_distribution``) (``solve.check_engine``: None is compiled; another value raises
        CdprError).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientation (default identity); poses p (N, 6) carry theirs. ``subset`` is the
        point-mass rule at positions only (``at_poses`` false).
    options : passed to ``cdpr.models.tension_distribution.min_norm`` (a point mass) or
        ``min_norm_rows`` (``t_ref``).

    Returns
    -------
    dict
        p (N, 3) [m]; L0 (N, m) [m], NaN where infeasible; t (N, m) [N] planned tensions;
        L_TE (N, m) [m] at p; feasible (N,) bool; subset (N, 3) 0-based for ``subset`` (else
        absent); at poses also R (N, 3, 3), the desired orientations; with heavy cables also
        iterations (N,) (``heavy_distribution``'s fixed point) and cables (``cables.heavy_cables``'s
        dict at the desired poses under L0: t_B, t_D, H, sag, ..., NaN where infeasible).

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10)-(13); Irvine 1981, ch. 2.
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    engine = check_engine(engine, "newton")
    six = at_poses(robot, p, rotvec)
    if method not in COMP_METHODS:
        raise ValueError(f"unknown compensation method {method!r}; allowed: {', '.join(COMP_METHODS)}")
    if method == "subset" and (six or robot.heavy):
        raise CdprError(
            "the 3-cable subset (compensation method 'subset') is the paper's point-mass rule at positions with "
            f"massless cables; use {', '.join(METHODS)}"
        )
    pp, R = pose_arrays(p, rotvec)
    B, st = pose_state(robot, pp, R)
    out = {"p": pp}
    if six:
        out["R"] = R
    if method == "subset":
        t, ok, out["subset"] = _subset_tensions(robot, pp, engine)
        L0 = rest_lengths(st.L_TE, t, robot.ES)
    elif robot.heavy:
        h = heavy_distribution(robot, pp, R, t_min, t_max, method, engine=engine, **options)
        t, ok, L0 = h["t"], h["feasible"], h["L0"]
        out["iterations"] = h["iterations"]
        out["cables"] = _planned_cables(robot, pp, R, np.where(ok[:, None], L0, st.L_TE), ok, engine)
    else:
        u = st.D - B
        u = u / np.linalg.norm(u, axis=-1, keepdims=True)
        W, w = _wrench(robot, R, u, B - pp[:, None, :])
        t_max = robot.T_a if t_max is None else t_max
        t, ok = _distribution(W, w, method, t_min, t_max, options)
        L0 = rest_lengths(st.L_TE, t, robot.ES)
    out.update(L0=np.where(ok[:, None], L0, np.nan), t=t, L_TE=st.L_TE, feasible=ok)
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
        ``solve.check_engine``: None is compiled (heavy cables too: it models every pulley);
        another value raises CdprError.
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
        t NaN; at poses also rotvec_s and dphi) where no distribution exists. With heavy cables
        also ``solve.HEAVY_KEYS`` at the equilibria (NaN, status ``infeasible``, where not solved),
        planned_cables (``compensate``'s cables, at the desired poses) and iterations_distribution.
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
    if "cables" in comp:
        out["planned_cables"], out["iterations_distribution"] = comp["cables"], comp["iterations"]
    if actual.heavy:
        for key in HEAVY_KEYS:
            dims = res[key].shape[1:]
            text = key == "cable_status"
            arr = np.full((n, *dims), "infeasible" if text else np.nan, dtype="<U10" if text else float)
            arr[ok] = res[key]
            out[key] = arr
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
