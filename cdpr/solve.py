"""One door per concept for every robot, and the engine registry: every choice between a model
(paper mode's 3-cable subsets, the physical equilibrium) and between a numba kernel
(``cdpr.compiled``) and its numpy reference (``cdpr.models``) is made here, and nowhere else.

``solve`` solves poses of any robot (per-point arrays; ``cdpr.tables.solve_table`` gives a
DataFrame) and ``solve_batch`` the same poses for many robots (the uncertainty samples);
``sensitivities`` adds dp*/dθ (and dφ*/dθ on a rigid platform), ``sensitivities_at`` at the
equilibria of a result, ``subset_sensitivities`` every 3-cable subset of paper mode;
``linear_dp`` and ``linear_positions`` propagate them; ``solve_stiff`` solves a robot with
stiffened cables (E x factor, the error budget's rigid cables) by a continuation in E from the
cables' own E. A point mass is the rigid platform with b = 0 and c = 0: physical mode solves both with ``models.equilibrium``; a suspended point mass
(pulley axes +z) solved without an orientation takes the 3-DoF fast path of the compiled engine
and answers with the point-mass keys (``results.POINT_KEYS``) from either engine. Paper mode is the
point-mass rule (refused in one line on a rigid platform).

Each door takes ``engine`` in ``ENGINES`` or None for the default (compiled for Newton, numpy for
the fixed point); an unknown engine or an engine/method pair that does not exist raises CdprError
naming the allowed values, never a silent fall-back. No pandas here: ``cdpr point`` solves one
point without it.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cdpr.compiled import cables as compiled_cables
from cdpr.compiled import equilibrium as compiled_equilibrium
from cdpr.compiled import sensitivity as compiled_sensitivity
from cdpr.compiled import subsets as compiled_subsets
from cdpr.errors import CdprError
from cdpr.models import continuation, equilibrium, heavy_sensitivity, sensitivity
from cdpr.models.cables import Cables, HeavyCables, heavy_cables
from cdpr.models.results import mark_below_floor, mark_out_of_frame, point_keys
from cdpr.models.subsets import solve_points
from cdpr.robot import require_point_mass

#: The (engine, method) pairs that exist: the compiled kernel implements Newton only.
ENGINES = {"compiled": ("newton",), "numpy": ("newton", "fixed_point")}


#: A process that solves fewer poses than this and then exits (``cdpr point``, ``cdpr compensate``)
#: is answered by the numpy reference unless an engine is named: the compiled engine's first call
#: in a process costs about 0.3 s on the 2-core machine (numba loads its implementation modules
#: and, through its BLAS check, scipy.linalg), more than the numpy reference needs for 500 poses in
#: any mode (17-430 µs per pose, point-mass physical to 6-DoF sensitivities; ``benchmarks/startup.py``).
ONE_SHOT_POSES = 500


def check_engine(engine, method, one_shot=None):
    """The engine to use: ``engine``, or when None the default for ``method``: compiled for Newton,
    numpy for the fixed point, and numpy for Newton too when ``one_shot`` (the number of poses of
    a process that solves them and exits: the command line's ``point``) is below
    ``ONE_SHOT_POSES``. The two engines give the same statuses and poses to 1e-9 m (tests/compiled).
    Raises CdprError for a pair that does not exist (never falls back silently)."""
    if engine is None:
        if method != "newton" or (one_shot is not None and one_shot < ONE_SHOT_POSES):
            return "numpy"
        return "compiled"
    if engine not in ENGINES:
        raise CdprError(f"unknown engine {engine!r}; allowed: {', '.join(ENGINES)}")
    if method not in ENGINES[engine]:
        ok = [f"{e}/{m}" for e, ms in ENGINES.items() for m in ms]
        raise CdprError(
            f"the {engine} engine has no {method!r} solver; allowed engine/method pairs: {', '.join(ok)}"
        )
    return engine


#: How a robot with more cables than needed is held: the paper's best 3-cable subset, or physics.
REDUNDANCY = ("paper", "physical")


def check_redundancy(redundancy, robot=None):
    """``redundancy`` if it is one of ``REDUNDANCY``, else CdprError naming the allowed values. None
    with a ``robot``: the robot's default (``Robot.default_redundancy``), paper mode for a point
    mass on massless cables and physical mode for a rigid platform or heavy cables (their only
    mode)."""
    if redundancy is None and robot is not None:
        return robot.default_redundancy
    if redundancy not in REDUNDANCY:
        raise CdprError(f"unknown redundancy {redundancy!r}; allowed: {', '.join(REDUNDANCY)}")
    return redundancy


def _check_physical(method, L):
    """Physical mode has one method and commands rest lengths: CdprError otherwise."""
    if method != "newton":
        raise CdprError(
            "physical mode has one solver (Newton on the force balance); --method fixed_point applies to paper mode"
        )
    if L is not None:
        raise CdprError("physical mode commands rest lengths L0, not total lengths L")


def _check_paper(robot):
    """Paper mode (3 of m) is the point-mass rule: CdprError in one line on a rigid platform."""
    if not robot.point_mass:
        raise CdprError(
            f"{robot.source}: paper mode (3-cable subsets) is the point-mass rule; this robot has platform "
            "attachments or a centre of mass off its reference point: use redundancy: physical (--redundancy physical)"
        )


#: The per-cable and per-point keys a heavy-cable solve adds (``cables.heavy_cables``).
HEAVY_KEYS = ("t_B", "t_D", "H", "sag", "arc_minus_chord", "angle_f_deg", "cable_status", "sag_max")


def heavy_cables_at(robot, P, R, L0, engine=None):
    """What each heavy cable does at poses (P, R) under rest lengths L0 (``cables.heavy_cables``:
    the pulley coupling and each catenary solved afresh), by the chosen engine (``check_engine``'s
    Newton default, compiled: ``cdpr.compiled.cables.heavy_cables``).

    Parameters
    ----------
    robot : Robot
    P : ndarray (N, 3) [m]
        Platform positions.
    R : ndarray (N, 3, 3) [-]
        Platform orientations.
    L0 : ndarray (N, m) [m]
        Rest lengths of the whole cables.
    engine : {"compiled", "numpy"}, optional

    Returns
    -------
    dict
        As ``models.cables.heavy_cables``.
    """
    P, R, L0 = (np.asarray(a, dtype=float) for a in (P, R, L0))
    if check_engine(engine, "newton") == "compiled":  # (its kernel makes its arrays contiguous)
        return compiled_cables.heavy_cables(compiled_equilibrium.CompiledHeavyCables(robot), P, R, L0)
    return heavy_cables(HeavyCables(robot), P, R, L0)


def _solve_heavy(robot, p, rotvec, redundancy, engine, L0, L, threads, options):
    """A robot with heavy cables (issue 38): physical mode, by the compiled kernel
    (``cdpr.compiled.equilibrium.solve`` with ``cdpr.compiled.cables``) or the numpy reference
    (``cables.HeavyCables``), ``check_engine``'s default (compiled: it models every pulley); CdprError in one
    line for anything else."""
    if redundancy != "physical":
        raise CdprError(
            f"{robot.source}: heavy cables (cable.linear_density_kg_m > 0) are modelled in physical mode only "
            "(--redundancy physical)"
        )
    _check_physical("newton", L)
    if check_engine(engine, "newton") == "compiled":
        res = compiled_equilibrium.solve(robot, p, rotvec, L0=L0, threads=threads, **options)
    else:
        res = equilibrium.solve(robot, p, rotvec, L0=L0, **options)
    if _fast_point(robot, p, rotvec):
        res = {**point_keys(res), **{k: res[k] for k in HEAVY_KEYS}}
    return _mark(res, p, robot)


def _mark(res, p, robot, floor=None, frame=True):
    """The statuses every door gives whatever the engine: a desired point below the floor of a
    suspended point mass is ``inaccessible`` (``mark_below_floor``; ``floor`` True/False forces it
    on or off, None: when the robot is a suspended point mass), and with ``frame`` (physical mode) a
    solved pose whose reference point leaves the frame box is ``out_of_frame``
    (``mark_out_of_frame``). Paper mode passes ``frame=False``: the paper evaluates every point of
    its volume with its own rule and has no floor or frame."""
    if robot.suspended_point_mass if floor is None else floor:
        res = mark_below_floor(res, p, robot.floor_z)
    return mark_out_of_frame(res, robot) if frame else res


def _fast_point(robot, p, rotvec):
    """True where the 3-DoF paths apply: a suspended point mass at positions (N, 3), no orientation."""
    return robot.suspended_point_mass and rotvec is None and p.shape[1] == 3


def solve(
    robot, p, rotvec=None, *, redundancy=None, method="newton", engine=None, threads=None, L0=None, L=None, **options
):  # fmt: skip
    """Poses of any robot from the chosen model and engine, as per-point arrays.

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses (x, y, z, rx, ry, rz).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientations (rotation vectors); ignored by paper mode (a point mass).
    redundancy : {"paper", "physical"}, optional
        The paper's 3-cable subsets (DEGM_E on every subset, point masses only) or the physical
        equilibrium on all cables (``models.equilibrium``); default paper for a point mass,
        physical for a rigid platform (``check_redundancy``).
    method : {"newton", "fixed_point"}
        Paper mode's DEGM_E solver; physical mode has Newton only.
    engine : {"compiled", "numpy"}, optional
        ``check_engine``'s default when None.
    threads : int, optional
        Caps the compiled engine's threads.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths (physical mode), default L_TS at the desired pose.
    L : array_like (N, m) [m], optional
        Commanded total lengths (paper mode), default L_TS at p.
    **options
        The solver's stop rules (tol, maxiter, max_step) and starts (P0).

    Returns
    -------
    dict
        Paper mode: ``models.subsets.solve_points``'s keys. Physical mode: a suspended point mass
        solved without an orientation gets ``results.POINT_KEYS``; every other robot, or a given
        orientation, ``models.equilibrium.solve``'s keys (rotvec_s, dphi, unique, ...). The desired
        points below the floor of a suspended robot are ``inaccessible`` (``mark_below_floor``); in
        physical mode a solved pose whose reference point leaves the frame box is ``out_of_frame``
        (``mark_out_of_frame``; paper mode follows the paper, which evaluates every point of its
        volume and has no floor or frame). A robot with heavy cables (``Robot.heavy``, issue 38) is
        solved in physical mode by either engine (``cables.HeavyCables`` and its compiled twin
        ``cdpr.compiled.cables``; the same statuses and poses to 1e-9 m, tests/compiled) and its
        result adds ``HEAVY_KEYS``; paper mode refuses it in one line.

    Raises
    ------
    CdprError
        An engine/method/model combination that does not exist, paper mode on a rigid platform.
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    redundancy = check_redundancy(redundancy, robot)
    if robot.heavy:
        return _solve_heavy(robot, p, rotvec, redundancy, engine, L0, L, threads, options)
    if redundancy == "paper":
        _check_paper(robot)
        if L0 is not None:
            raise CdprError(
                "commanded lengths need physical mode (--redundancy physical); paper mode commands L_TS at the desired point"
            )
        engine = check_engine(engine, method)
        if L is not None:
            options["L"] = L
        p = p[:, :3]  # a point mass: the orientation plays no part
        if engine == "compiled":
            res = compiled_subsets.solve_points_fast(robot, p, threads=threads, **options)
        else:
            res = solve_points(robot, p, method=method, **options)
        return _mark(res, p, robot, frame=False)
    _check_physical(method, L)
    engine = check_engine(engine, "newton")
    if _fast_point(robot, p, rotvec):
        if L0 is not None:
            L0 = np.broadcast_to(np.asarray(L0, dtype=float), (len(p), robot.m))
        if engine == "compiled":  # the 3-DoF fast path of a suspended point mass
            res = compiled_equilibrium.solve_points(robot, p, L0=L0, threads=threads, **options)
        else:
            res = point_keys(equilibrium.solve(robot, p, L0=L0, **options))
        return _mark(res, p, robot, floor=True)
    if engine == "compiled":
        res = compiled_equilibrium.solve(robot, p, rotvec, L0=L0, threads=threads, **options)
    else:
        res = equilibrium.solve(robot, p, rotvec, L0=L0, **options)
    return _mark(res, p, robot)


#: Ratio of E between two stages of the continuation in stiffness (``solve_stiff``).
STIFF_RATIO = 10.0


def stiffened(robot, factor):
    """``robot`` with every cable's Young's modulus E multiplied by ``factor`` (the rest unchanged).

    Parameters
    ----------
    robot : Robot
    factor : float [-]

    Returns
    -------
    Robot
    """
    cables = tuple(
        dataclasses.replace(c, material=dataclasses.replace(c.material, E=c.material.E * factor))
        for c in robot.cables
    )
    return dataclasses.replace(robot, cables=cables)


def solve_stiff(robot, p, factor, rotvec=None, *, L0=None, engine=None, threads=None, ratio=STIFF_RATIO):
    """The physical equilibrium of ``stiffened(robot, factor)`` (nearly inextensible cables for a
    large ``factor``, the error budget's ``RIGID``) by a continuation in stiffness: the robot with
    its own cables' E first (from the desired pose, as ``solve``), then E x ratio, E x ratio^2, ...
    and last E x ``factor`` exactly, each Newton pass (the chosen engine's local solver) started
    from the pose (position and orientation) where the previous one stopped; the last stage alone
    also gets ``solve``'s restarts and statuses. Newton on the stiff problem from the desired pose
    can stall (its line search follows an energy whose curvature grows with E while cables go slack
    and taut); each stage here starts within the basin of the stiffer one. The answer is an
    equilibrium of the stiff robot in the same sense as ``solve``'s (the same Newton, tolerance and
    statuses: ``not_converged`` where the last stage did not converge), only its start differs, and
    ``iterations`` counts every stage. Every robot (a point mass is the rigid platform with b = 0),
    massless or heavy cables, physical mode.

    Parameters
    ----------
    robot : Robot
        The robot with its cables' own E (the continuation's first stage).
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    factor : float [-]
        The factor on E of the robot solved (>= 1).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientations.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths, default L_TS at the desired pose.
    engine : {"compiled", "numpy"}, optional
        ``check_engine``'s default for Newton (compiled) when None.
    threads : int, optional
        Caps the compiled engine's threads.
    ratio : float [-]
        Factor on E between two stages (> 1).

    Returns
    -------
    dict
        ``solve``'s result for ``stiffened(robot, factor)`` in physical mode (the point-mass keys
        for a suspended point mass solved without an orientation).

    Raises
    ------
    CdprError
        An unknown engine, factor < 1 or ratio <= 1.
    """
    if not (factor >= 1.0 and ratio > 1.0):
        raise CdprError(f"solve_stiff: factor must be >= 1 and ratio > 1; got factor={factor}, ratio={ratio}")
    engine = check_engine(engine, "newton")
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if engine == "compiled":
        compiled_equilibrium.set_threads(threads)
        kind = (
            compiled_equilibrium.CompiledHeavyCables if robot.heavy else compiled_equilibrium.CompiledCables
        )
        newton, standard = compiled_equilibrium.newton, compiled_equilibrium.L_TS
    else:
        kind, newton, standard = (HeavyCables if robot.heavy else Cables), equilibrium.local_newton, None
    tol, maxiter, max_step = equilibrium.stop_rules()
    pose = equilibrium.set_up(robot, p, rotvec, L0, None, standard)
    stages = [1.0]
    while stages[-1] * ratio < factor:
        stages.append(stages[-1] * ratio)
    if factor > 1.0:
        stages.append(factor)
    P, R, iters = pose.p0, pose.R_d.copy(), np.zeros(len(p), dtype=np.int32)
    for f in stages:
        stiff = robot if f == 1.0 else stiffened(robot, f)
        cab = kind(stiff)
        P, R, cur, it, conv = newton(cab, P, R, pose.L0, pose.p, tol, maxiter, max_step)
        iters = iters + it
        P, R = np.array(P), np.array(R)
    res = equilibrium.finish(stiff, cab, newton, pose, (P, R, cur, iters, conv), tol, maxiter, max_step, True)
    if stiff.heavy:
        res.update(heavy_cables(cab, res["P_s"], res["R_s"], res["L0"]))
    if _fast_point(stiff, p, rotvec):
        res = point_keys(res) if not stiff.heavy else {**point_keys(res), **{k: res[k] for k in HEAVY_KEYS}}
    return _mark(res, p[:, :3], stiff)


#: Which equilibrium physical mode answers with: the one reached by continuation (the default), or
#: the lowest energy over restarts.
EQUILIBRIA = ("reached", "global")


def check_equilibrium(choice):
    """``choice`` if it is one of ``EQUILIBRIA`` (None: "reached"), else CdprError naming them."""
    if choice is None:
        return "reached"
    if choice not in EQUILIBRIA:
        raise CdprError(f"unknown equilibrium {choice!r}; allowed: {', '.join(EQUILIBRIA)}")
    return choice


def reach(robot, p, rotvec=None, *, L0=None, engine=None, threads=None, **start):
    """The equilibrium reached by continuation (``models.continuation.reach``, whose docstring gives
    the path, the steps, the folds and the starts), by the chosen engine's local Newton solver:
    compiled (``compiled.equilibrium.newton``, the default as for ``solve``; heavy cables too,
    ``compiled.equilibrium.CompiledHeavyCables``: every pulley) or numpy (``equilibrium.local_newton``);
    the two reach the same equilibria, statuses and starts to 1e-9 m and rad (tests/models/test_continuation.py).

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientations.
    L0 : array_like (N, m) or (m,) [m], optional
        Target rest lengths, default L_TS at the desired pose.
    engine : {"compiled", "numpy"}, optional
        ``check_engine``'s default for Newton (compiled) when None.
    threads : int, optional
        Caps the compiled engine's threads.
    **start
        ``continuation.reach``'s start and path options (start, t_min, t_max, from_p,
        from_rotvec, from_lengths, schedule).

    Returns
    -------
    dict
        ``continuation.reach``'s result (the points below the floor of a suspended robot marked
        ``inaccessible``, the poses out of the frame box ``out_of_frame``).

    Raises
    ------
    CdprError
        An unknown engine, a start that does not exist.
    """
    engine = check_engine(engine, "newton")
    if engine == "compiled":
        compiled_equilibrium.set_threads(threads)
        kind = (
            compiled_equilibrium.CompiledHeavyCables if robot.heavy else compiled_equilibrium.CompiledCables
        )
        cab, newton = kind(robot), compiled_equilibrium.newton
        standard = None if robot.heavy else compiled_equilibrium.L_TS
    elif robot.heavy:
        cab, newton, standard = HeavyCables(robot), equilibrium.local_newton, None
    else:
        cab, newton, standard = Cables(robot), equilibrium.local_newton, None
    p = np.atleast_2d(np.asarray(p, dtype=float))
    res = continuation.reach(robot, cab, newton, p, rotvec, L0, standard=standard, **start)
    if robot.heavy:
        from_heavy = heavy_cables(cab, res["P_s"], res["R_s"], res["L0"])
        res.update(from_heavy)
    return _mark(res, p[:, :3], robot)


#: The per-point keys of a physical-mode result that ``reach_where_multiple`` replaces.
REACHED_KEYS = (
    "P_s", "dp", "rotvec_s", "R_s", "dphi", "t", "taut", "n_taut", "residual", "iterations",
    "converged", "status_code", "status", "energy", "wrap_over_270",
)  # fmt: skip


def reach_where_multiple(robot, res, engine=None, threads=None, **start):
    """A physical-mode result (``solve`` of a rigid platform or at given orientations, with its
    keys p, rotvec, L0, unique) answered with the reached equilibrium (``reach``) where the restarts
    found more than one equilibrium (``unique`` False); elsewhere the unique equilibrium is the
    reached one and the result is kept as it is (the studies' rule, issue 39).

    Parameters
    ----------
    robot : Robot
    res : dict
        ``solve``'s result (not modified).
    engine : {"compiled", "numpy"}, optional
        The engine of the continuation (``reach``).
    threads : int, optional
    **start
        ``reach``'s start options.

    Returns
    -------
    dict
        ``res`` with ``REACHED_KEYS`` of the reached equilibrium at the points not unique, and
        n_folds (N,) int (folds crossed on the way), reached_is_global (N,) bool (within
        ``equilibrium.DISTINCT`` of the lowest energy found), folds (N lists of dicts) and
        continued (N,) bool (the points continued).
    """
    out = dict(res)
    n = len(res["P_s"])
    multiple = ~np.asarray(res.get("unique", np.ones(n, dtype=bool)), dtype=bool)
    out["n_folds"] = np.zeros(n, dtype=np.int32)
    out["reached_is_global"] = np.ones(n, dtype=bool)
    out["folds"] = [[] for _ in range(n)]
    out["continued"] = multiple.copy()
    idx = np.flatnonzero(multiple)
    if idx.size == 0:
        return out
    r = reach(
        robot, res["p"][idx], res["rotvec"][idx], L0=res["L0"][idx], engine=engine, threads=threads, **start
    )
    for key in REACHED_KEYS:
        if key in res:
            out[key] = np.array(res[key], copy=True)
            out[key][idx] = r[key]
    out["n_folds"][idx] = r["n_folds"]
    out["reached_is_global"][idx] = (
        continuation.pose_distance(r["P_s"], r["R_s"], res["P_s"][idx], res["R_s"][idx])
        <= equilibrium.DISTINCT
    )
    for k, i in enumerate(idx):
        out["folds"][i] = r["folds"][k]
    return out


def reached_answer(robot, res, equilibrium="reached", engine=None, threads=None):
    """Physical mode's answer (issue 39): where the restarts found more than one equilibrium
    (``unique`` False) the one reached by continuation (``reach_where_multiple``), unless
    ``equilibrium`` is "global"; ``res`` itself, unchanged, where every equilibrium is unique or the
    result has no ``unique`` (paper mode, a suspended point mass solved without an orientation).
    The door of every table and study solve (the point tables, the global index, the error budget,
    the uncertainty study).

    Parameters
    ----------
    robot : Robot
    res : dict
        ``solve``'s result (not modified).
    equilibrium : {"reached", "global"}
        Where the equilibrium is not unique: the reached one or the lowest energy found.
    engine : {"compiled", "numpy"}, optional
        The continuation's engine (``check_engine``'s default for Newton when None).
    threads : int, optional

    Returns
    -------
    dict
        ``res``, or ``reach_where_multiple``'s result.
    """
    if check_equilibrium(equilibrium) != "reached" or "unique" not in res or np.all(res["unique"]):
        return res
    return reach_where_multiple(robot, res, engine=check_engine(engine, "newton"), threads=threads)


def solve_batch(
    robots, p, rotvec=None, *, redundancy="physical", L0=None, L=None, engine=None, threads=None, P0=None, **options
):  # fmt: skip
    """``solve`` of every robot at the same poses (the Monte Carlo and Sobol samples of one design),
    by the chosen engine. Compiled (default): one parallel pass over every (robot, point) pair, the
    same kernel and results as one solve per robot; numpy: the references per robot.

    Parameters
    ----------
    robots : sequence of Robot
        Robots with the same number of cables m (all point masses or all rigid platforms).
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientations.
    redundancy : {"paper", "physical"}
        Paper mode (suspended point masses, commanded total lengths ``L``) or physical mode.
    L0 : array_like (N, m) [m], optional
        Commanded rest lengths (physical mode).
    L : array_like (N, m) [m], optional
        Commanded total lengths (paper mode; required there).
    engine : {"compiled", "numpy"}, optional
    threads : int, optional
    P0 : array_like, optional
        Newton's starting points (default p): (N, 3) or (K, N, 3) [m] in physical mode on suspended
        point masses, (K, N, n_subsets, 3) [m] (every subset of every robot) in paper mode.
    **options
        Stop rules of the pose solver (tol, maxiter, max_step, restarts), rigid platforms.

    Returns
    -------
    list of dict
        ``solve`` of each robot (the points below the floor marked, ``mark_below_floor``). Robots
        with heavy cables (issue 38) are solved one by one by ``solve`` (physical mode).
    """
    robots = list(robots)
    p = np.atleast_2d(np.asarray(p, dtype=float))
    check_redundancy(redundancy)
    if any(r.heavy for r in robots):  # heavy cables: one solve per robot, by either engine
        if L is not None:
            raise CdprError("physical mode commands rest lengths L0, not total lengths L")
        starts = [None] * len(robots)
        if P0 is not None:
            P0 = np.asarray(P0, dtype=float)
            starts = list(P0) if P0.ndim == 3 else [P0] * len(robots)
        return [
            solve(r, p, rotvec, redundancy=redundancy, engine=engine, threads=threads, L0=L0, P0=P, **options)
            for r, P in zip(robots, starts)
        ]
    compiled = check_engine(engine, "newton") == "compiled"
    if not all(_fast_point(r, p, rotvec) for r in robots):
        if redundancy != "physical" or P0 is not None or L is not None:
            raise CdprError(
                "batched solves of rigid platforms or at given orientations are physical mode, from the desired poses"
            )
        if compiled:
            res = compiled_equilibrium.solve_batch(robots, p, rotvec, L0=L0, threads=threads, **options)
        else:
            res = equilibrium.solve_batch(robots, p, rotvec, L0=L0, **options)
        return [_mark(r, p, rk) for r, rk in zip(res, robots)]
    if redundancy == "physical":
        if L is not None:
            raise CdprError("physical mode commands rest lengths L0, not total lengths L")
        if compiled:
            res = compiled_equilibrium.solve_points_batch(robots, p, L0=L0, threads=threads, P0=P0)
        else:
            res = [point_keys(r) for r in equilibrium.solve_batch(robots, p, L0=L0, P0=P0)]
    else:
        if L0 is not None or L is None:
            raise CdprError("batched paper-mode solves command total lengths L, not rest lengths L0")
        starts = [None] * len(robots) if P0 is None else P0
        if compiled:
            res = compiled_subsets.solve_points_batch(robots, p, L, threads=threads, P0=P0)
        else:
            res = [solve_points(r, p, method="newton", L=L, P0=P) for r, P in zip(robots, starts)]
    return [_mark(r, p, rk, floor=True, frame=redundancy == "physical") for r, rk in zip(res, robots)]


def sensitivities(
    robot,
    p,
    rotvec=None,
    *,
    redundancy=None,
    L=None,
    engine=None,
    threads=None,
    gap_tol=sensitivity.GAP_TOL,
    t_tol=sensitivity.T_TOL,
    **solver,
):
    """The solve plus dp*/dθ of every parameter θ (and dφ*/dθ on a rigid platform or at a given
    orientation), by the chosen engine (Newton only).

    A point mass in paper mode, or a suspended point mass in physical mode without an orientation:
    ``models.sensitivity.sensitivities`` (compiled twin ``cdpr.compiled.sensitivity``), S (N, 3, n).
    Every other robot in physical mode (a rigid platform, pulleys at any axis, a given orientation):
    the pose sensitivities ``models.sensitivity.pose_sensitivities`` (compiled twin
    ``cdpr.compiled.sensitivity``), S (N, 6, n) with the rows dφ*/dθ. The references' docstrings
    give the equations and the result.

    Parameters
    ----------
    robot : Robot
    p : array_like (N, 3) or (N, 6) [m, rad]
        Desired positions, or poses.
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientations (physical mode).
    redundancy : {"paper", "physical"}, optional
        Default as ``solve``.
    L : array_like (N, m) [m], optional
        Commanded lengths held fixed (total lengths in paper mode, rest lengths in physical mode),
        default L_TS at the desired pose.
    engine : {"compiled", "numpy"}, optional
    threads : int, optional
    gap_tol : float [m]
        Paper mode's subset-switch tolerance (point masses).
    t_tol : float [N]
        Tension margin below which a cable is near its slack switch.
    **solver
        The solver's stop rules.

    Returns
    -------
    dict
        The solve's result with names (n,), S (N, 3, n) or (N, 6, n) and smooth (N,).

    Notes
    -----
    Heavy cables (``Robot.heavy``): physical mode; the equilibria by the chosen engine, dp*/dθ and
    dφ*/dθ by the numpy reference whatever the engine (``heavy_sensitivity.sensitivities_at``: the
    compiled heavy kernel has no sensitivities).
    """
    redundancy = check_redundancy(redundancy, robot)
    p = np.atleast_2d(np.asarray(p, dtype=float))
    engine = check_engine(engine, "newton")
    if robot.heavy:
        return _heavy_sensitivities(robot, p, rotvec, redundancy, L, t_tol, solver, engine, threads)
    if redundancy == "paper":
        _check_paper(robot)
        p = p[:, :3]
    elif not _fast_point(robot, p, rotvec):
        if engine == "compiled":
            res = compiled_sensitivity.pose_sensitivities(
                robot, p, rotvec, L0=L, threads=threads, t_tol=t_tol, **solver
            )
        else:
            res = sensitivity.pose_sensitivities(robot, p, rotvec, L0=L, t_tol=t_tol, **solver)
        return _mark(res, p, robot, floor=False)
    if engine == "compiled":
        res = compiled_sensitivity.sensitivities_fast(
            robot, p, redundancy=redundancy, L=L, threads=threads, gap_tol=gap_tol, t_tol=t_tol, **solver
        )
    else:
        res = sensitivity.sensitivities(
            robot, p, redundancy=redundancy, L=L, gap_tol=gap_tol, t_tol=t_tol, **solver
        )
    return _mark(res, p, robot, floor=False, frame=redundancy == "physical")


def _heavy_sensitivities(robot, p, rotvec, redundancy, L, t_tol, solver, engine, threads):
    """``sensitivities`` of a robot with heavy cables: physical mode; the equilibria by ``engine``
    (the compiled kernel, or the numpy reference), then ``heavy_sensitivity.sensitivities_at`` (the
    numpy reference: ``heavy_sensitivity.pose_sensitivities`` with the solve by either engine); S
    (N, 3, n) and the point keys for a suspended point mass at positions, as the massless door."""
    if redundancy != "physical":
        raise CdprError(
            f"{robot.source}: heavy cables (cable.linear_density_kg_m > 0) are modelled in physical mode only "
            "(--redundancy physical)"
        )
    if engine == "compiled":
        options = dict(solver)
        names = options.pop("names", None)
        res = compiled_equilibrium.solve(robot, p, rotvec, L0=L, threads=threads, **options)
        res.update(heavy_sensitivity.sensitivities_at(robot, res, names, t_tol))
    else:
        res = heavy_sensitivity.pose_sensitivities(robot, p, rotvec, L0=L, t_tol=t_tol, **solver)
    if _fast_point(robot, p, rotvec):
        extra = {k: res[k] for k in ("names", "smooth", "margin_t", "cond", "sag_max")}
        res = {**point_keys(res), **extra, "S": res["S"][:, :3]}
    return _mark(res, p, robot, floor=False)


def sensitivities_at(robot, res, names=None, t_tol=sensitivity.T_TOL, engine=None, threads=None):
    """dp*/dθ and dφ*/dθ at the equilibria of a physical-mode pose result (``solve`` with all keys:
    P_s, R_s, L0, status) of either engine (``sensitivity.sensitivities_at``, whose docstring gives
    the equations and the result), by the chosen engine: ``"compiled"`` (default:
    ``cdpr.compiled.sensitivity.sensitivities_at``) or ``"numpy"``; another engine raises CdprError
    naming the allowed values. Heavy cables: always numpy (the compiled heavy kernel has no
    sensitivities; ``heavy_sensitivity.sensitivities_at``)."""
    if robot.heavy:
        check_engine(engine, "newton")
        return heavy_sensitivity.sensitivities_at(robot, res, names, t_tol)
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.sensitivities_at(robot, res, names, t_tol, threads=threads)
    return sensitivity.sensitivities_at(robot, res, names, t_tol)


def subset_sensitivities(robot, p, L=None, columns=None, engine=None, threads=None, **solver):
    """Every 3-cable subset of paper mode at every point with dP*/dθ and dt/dθ, by the chosen engine
    (``"compiled"`` default: ``cdpr.compiled.sensitivity.subset_sensitivities``; ``"numpy"``: the
    reference ``cdpr.models.sensitivity.subset_sensitivities``, whose docstring gives the result);
    another engine raises CdprError."""
    require_point_mass(
        robot,
        "subset_sensitivities (paper mode)",
        "cdpr.solve.sensitivities (redundancy: physical, the pose equilibrium)",
        P=p,
    )
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.subset_sensitivities(
            robot, p, L=L, columns=columns, threads=threads, **solver
        )
    return sensitivity.subset_sensitivities(robot, p, L=L, columns=columns, **solver)


def linear_positions(dp0, S, delta, engine=None, threads=None):
    """The linearised P*(θ) - p (n, N, 3) [m] of one slot for every parameter change
    (``models.sensitivity.linear_positions``, the reference, whose docstring gives the equation), by
    the chosen engine (``"compiled"`` default: ``cdpr.compiled.sensitivity.linear_positions``, points
    in parallel); another engine raises CdprError."""
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.linear_positions(dp0, S, delta, threads=threads)
    return sensitivity.linear_positions(dp0, S, delta)


def linear_dp(dp0, S, valid, delta, t0=None, St=None, T_a=None, engine=None, threads=None):
    """The linearised ‖dp‖ (n, N) [m] of every parameter change (``models.sensitivity.linear_dp``,
    the reference, whose docstring gives the equation), by the chosen engine (``"compiled"``
    default: ``cdpr.compiled.sensitivity.linear_dp``, points in parallel); another engine raises
    CdprError."""
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.linear_dp(dp0, S, valid, delta, t0, St, T_a, threads=threads)
    return sensitivity.linear_dp(dp0, S, valid, delta, t0, St, T_a)
