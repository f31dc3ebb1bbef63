"""The engine registry: every choice between a numba kernel (``cdpr.compiled``) and its numpy
reference (``cdpr.models``) is made here, through ``check_engine``, and nowhere else.

``solve_points_any`` solves the pose (per-point arrays; ``cdpr.tables.solve_table`` gives a DataFrame);
``sensitivities`` and ``subset_sensitivities`` add dP*/dθ (``spatial_sensitivities`` and
``spatial_sensitivities_at`` dp*/dθ and dφ*/dθ of a rigid platform); ``linear_dp`` propagates them. Each takes
``engine`` in ``ENGINES`` or None for the default (compiled for Newton, numpy for the fixed point);
an unknown engine or an engine/method pair that does not exist raises CdprError naming the allowed
values, never a silent fall-back. No pandas here: ``cdpr point`` solves one point without it.
"""

from __future__ import annotations

import numpy as np

from cdpr.compiled import equilibrium as compiled_equilibrium
from cdpr.compiled import equilibrium6 as compiled_equilibrium6
from cdpr.compiled import sensitivity as compiled_sensitivity
from cdpr.compiled import sensitivity6 as compiled_sensitivity6
from cdpr.compiled import subsets as compiled_subsets
from cdpr.errors import CdprError
from cdpr.models import equilibrium, sensitivity, sensitivity6
from cdpr.models.equilibrium6 import solve_spatial, solve_spatial_batch
from cdpr.models.results import mark_below_floor
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


def check_redundancy(redundancy):
    """``redundancy`` if it is one of ``REDUNDANCY``, else CdprError naming the allowed values."""
    if redundancy not in REDUNDANCY:
        raise CdprError(f"unknown redundancy {redundancy!r}; allowed: {', '.join(REDUNDANCY)}")
    return redundancy


def check_spatial(robot, engine, redundancy):
    """The engine for a rigid platform (``Robot.point_mass`` false: attachments b_i or a centre of
    mass off the reference point): such robots have the 6-DoF physical mode only
    (``cdpr.models.equilibrium6``); paper mode (3 of m) raises CdprError in one line. The engine is
    ``engine`` or, when None, the one default of ``check_engine`` (``spatial_engine``)."""
    if redundancy != "physical":
        raise CdprError(
            f"{robot.source}: paper mode (3-cable subsets) is the point-mass rule; this robot has platform "
            "attachments or a centre of mass off its reference point: use redundancy: physical (--redundancy physical)"
        )
    return spatial_engine(engine)


def spatial_engine(engine):
    """The engine of the 6-DoF solver (a Newton method): ``engine`` ("compiled" or "numpy"), or when
    None the default of ``check_engine`` (compiled: ``cdpr.compiled.equilibrium6``, tested equal to
    the numpy reference to 1e-9 m and rad); an unknown engine raises CdprError naming the allowed
    values."""
    return check_engine(engine, "newton")


def solve_spatial_any(robot, p, rotvec=None, engine=None, threads=None, **options):
    """``equilibrium6.solve_spatial`` by the chosen engine (``spatial_engine``): the numpy reference
    or the compiled twin ``cdpr.compiled.equilibrium6.solve_spatial`` (``threads`` caps its
    threads); same parameters and result."""
    if spatial_engine(engine) == "compiled":
        return compiled_equilibrium6.solve_spatial(robot, p, rotvec, threads=threads, **options)
    return solve_spatial(robot, p, rotvec, **options)


def solve_spatial_batch_any(robots, p, rotvec=None, engine=None, threads=None, **options):
    """``solve_spatial_any`` of every robot at the same poses (the samples of one design) by the
    chosen engine: compiled (default), one parallel pass over every (robot, pose) pair for the
    first Newton pass, the same kernel and results as one solve per robot
    (``cdpr.compiled.equilibrium6.solve_spatial_batch``); numpy, the reference per robot
    (``equilibrium6.solve_spatial_batch``). Returns one result dict per robot."""
    if spatial_engine(engine) == "compiled":
        return compiled_equilibrium6.solve_spatial_batch(robots, p, rotvec, threads=threads, **options)
    return solve_spatial_batch(robots, p, rotvec, **options)


def solve_points_any(
    robot,
    p,
    method="newton",
    engine=None,
    threads=None,
    redundancy="paper",
    L0=None,
    L=None,
    rotvec=None,
    **options,
):
    """Per-point results as a dict of arrays from the chosen model and engine.

    ``redundancy="paper"``: DEGM_E on every 3-cable subset and the paper's choice
    (``cdpr.models.subsets.solve_points`` keys), commanded total lengths ``L`` (N, m) [m] or L_TS
    at p.
    ``redundancy="physical"``: the equilibrium on all cables (``equilibrium.solve_physical`` keys),
    commanded rest lengths ``L0`` (N, m) [m] or L_TS at p. In physical mode a robot that is not a
    suspended point mass, an orientation ``rotvec`` ((3,) or (N, 3) [rad]) or poses p (N, 6) go to
    the 6-DoF solver (``equilibrium6.solve_spatial``), compiled by default and the numpy reference
    with ``engine="numpy"`` (``solve_spatial_any``). Paper mode takes every point-mass robot, pulleys
    at any axis (the suspended robots' accessibility and floor rules for suspended ones only),
    Newton or the paper's fixed point, ignores the orientation, and refuses a rigid platform
    (``check_spatial``). An engine/method/model combination that does not exist raises CdprError."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    check_redundancy(redundancy)
    if not robot.suspended_point_mass or rotvec is not None or p.shape[1] == 6:
        if not robot.point_mass:
            check_spatial(robot, engine, redundancy)
        if redundancy == "physical" or not robot.point_mass:
            if method != "newton":
                raise CdprError(
                    "physical mode has one solver (Newton on the force balance); --method fixed_point applies to paper mode"
                )
            if L is not None:
                raise CdprError("physical mode commands rest lengths L0, not total lengths L")
            res = solve_spatial_any(robot, p, rotvec, engine, threads, L0=L0, **options)
            return mark_below_floor(res, p, robot.floor_z) if robot.suspended_point_mass else res
        p = p[:, :3]  # paper mode on a point mass: the orientation plays no part
    if redundancy == "physical":
        if method != "newton":
            raise CdprError(
                "physical mode has one solver (Newton on the force balance); --method fixed_point applies to paper mode"
            )
        if L is not None:
            raise CdprError("physical mode commands rest lengths L0, not total lengths L")
        engine = check_engine(engine, "newton")
        if L0 is not None:
            L0 = np.broadcast_to(np.asarray(L0, dtype=float), (len(p), robot.m))
        if engine == "compiled":
            res = compiled_equilibrium.solve_physical_fast(robot, p, L0=L0, threads=threads, **options)
        else:
            res = equilibrium.solve_physical(robot, p, L0=L0, **options)
        return mark_below_floor(res, p, robot.floor_z)
    if L0 is not None:
        raise CdprError(
            "commanded lengths need physical mode (--redundancy physical); paper mode commands L_TS at the desired point"
        )
    engine = check_engine(engine, method)
    if L is not None:
        options["L"] = L
    if engine == "compiled":
        res = compiled_subsets.solve_points_fast(robot, p, threads=threads, **options)
    else:
        res = solve_points(robot, p, method=method, **options)
    return mark_below_floor(res, p, robot.floor_z) if robot.suspended_point_mass else res


def solve_points_batch_any(
    robots, p, redundancy="physical", L0=None, L=None, engine=None, threads=None, P0=None
):
    """``solve_points_any(robot, p, redundancy=redundancy, L0=L0, L=L)`` of every robot (suspended
    point masses with the same cables, no orientation) by the chosen engine. Compiled (default): one
    parallel pass over every (robot, point) pair, the same per-point kernel and results as one solve
    per robot (``cdpr.compiled.equilibrium.solve_physical_batch``, physical mode, commanded rest
    lengths ``L0`` (N, m) [m]; ``cdpr.compiled.subsets.solve_points_batch``, paper mode, commanded
    total lengths ``L`` (N, m) [m]); numpy: the references (``equilibrium.solve_physical_batch``,
    ``subsets.solve_points`` per robot). The points below the floor are marked inaccessible
    (``mark_below_floor``). ``P0``: Newton's starting points (default p), (N, 3) or (K, N, 3) [m]
    in physical mode, (K, N, n_subsets, 3) [m] (every subset of every robot) in paper mode. Returns
    one result dict per robot."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    check_redundancy(redundancy)
    if any(not r.suspended_point_mass for r in robots) or p.shape[1] != 3:
        raise CdprError("batched solves take suspended point-mass robots and positions (N, 3)")
    compiled = check_engine(engine, "newton") == "compiled"
    if redundancy == "physical":
        if L is not None:
            raise CdprError("physical mode commands rest lengths L0, not total lengths L")
        if compiled:
            res = compiled_equilibrium.solve_physical_batch(robots, p, L0=L0, threads=threads, P0=P0)
        else:
            res = equilibrium.solve_physical_batch(robots, p, L0=L0, P0=P0)
    else:
        if L0 is not None or L is None:
            raise CdprError("batched paper-mode solves command total lengths L, not rest lengths L0")
        starts = [None] * len(robots) if P0 is None else P0
        if compiled:
            res = compiled_subsets.solve_points_batch(robots, p, L, threads=threads, P0=P0)
        else:
            res = [solve_points(r, p, method="newton", L=L, P0=P) for r, P in zip(robots, starts)]
    return [mark_below_floor(r, p, rob.floor_z) for r, rob in zip(res, robots)]


def sensitivities(
    robot,
    p,
    redundancy="paper",
    L=None,
    engine=None,
    threads=None,
    gap_tol=sensitivity.GAP_TOL,
    t_tol=sensitivity.T_TOL,
    **solver,
):
    """The solve plus dP*/dθ of every parameter, by the chosen engine: ``"compiled"`` (default,
    ``cdpr.compiled.sensitivity.sensitivities_fast``: the solve and the sensitivities in one compiled
    pass, ``threads`` caps the threads) or ``"numpy"`` (the reference
    ``cdpr.models.sensitivity.sensitivities``). Newton only; same parameters and result as the
    reference, whose docstring gives the equations; another engine raises CdprError."""
    check_redundancy(redundancy)
    # paper mode takes any point mass (pulleys at any axis); the point-mass physical solver takes
    # suspended ones (axes +z), the others go to the 6-DoF equilibrium
    require_point_mass(
        robot, f"sensitivities ({redundancy} mode)", "cdpr.solve.spatial_sensitivities (redundancy: physical, the 6-DoF equilibrium)",
        redundancy == "physical", p,
    )  # fmt: skip
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.sensitivities_fast(
            robot, p, redundancy=redundancy, L=L, threads=threads, gap_tol=gap_tol, t_tol=t_tol, **solver
        )
    return sensitivity.sensitivities(
        robot, p, redundancy=redundancy, L=L, gap_tol=gap_tol, t_tol=t_tol, **solver
    )


def spatial_sensitivities(robot, p, rotvec=None, L0=None, engine=None, threads=None, **solver):
    """The 6-DoF solve plus dp*/dθ and dφ*/dθ (``sensitivity6.spatial_sensitivities``, whose docstring
    gives the equations and the result), by the chosen engine: ``"compiled"`` (default, as for the
    point-mass sensitivities: ``cdpr.compiled.sensitivity6.spatial_sensitivities``, the compiled
    solve and analytic dF6/dθ in parallel over poses, ``threads`` caps the threads) or ``"numpy"``
    (the reference); another engine raises CdprError naming the allowed values."""
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity6.spatial_sensitivities(robot, p, rotvec, L0=L0, threads=threads, **solver)
    return sensitivity6.spatial_sensitivities(robot, p, rotvec, L0=L0, **solver)


def spatial_sensitivities_at(robot, res, names=None, t_tol=sensitivity.T_TOL, engine=None, threads=None):
    """dp*/dθ and dφ*/dθ at the equilibria of a ``solve_spatial`` result of either engine
    (``sensitivity6.sensitivities_at``, whose docstring gives the equations and the result), by the
    chosen engine: ``"compiled"`` (default: ``cdpr.compiled.sensitivity6.sensitivities_at``) or
    ``"numpy"``; another engine raises CdprError naming the allowed values."""
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity6.sensitivities_at(robot, res, names, t_tol, threads=threads)
    return sensitivity6.sensitivities_at(robot, res, names, t_tol)


def subset_sensitivities(robot, p, L=None, columns=None, engine=None, threads=None, **solver):
    """Every 3-cable subset of paper mode at every point with dP*/dθ and dt/dθ, by the chosen engine
    (``"compiled"`` default: ``cdpr.compiled.sensitivity.subset_sensitivities``; ``"numpy"``: the
    reference ``cdpr.models.sensitivity.subset_sensitivities``, whose docstring gives the result);
    another engine raises CdprError."""
    require_point_mass(
        robot,
        "subset_sensitivities (paper mode)",
        "cdpr.solve.spatial_sensitivities (redundancy: physical, the 6-DoF equilibrium)",
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
