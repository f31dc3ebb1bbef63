"""The engine registry: every choice between a numba kernel (``cdpr.compiled``) and its numpy
reference (``cdpr.models``) is made here, through ``check_engine``, and nowhere else.

``solve_points_any`` (per-point arrays) and ``solve_table`` (a DataFrame) solve the pose;
``sensitivities`` and ``subset_sensitivities`` add dP*/dθ; ``linear_dp`` propagates them. Each takes
``engine`` in ``ENGINES`` or None for the default (compiled for Newton, numpy for the fixed point);
an unknown engine or an engine/method pair that does not exist raises CdprError naming the allowed
values, never a silent fall-back. ``to_frame`` gives one row per point with stable column names.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from cdpr.compiled import equilibrium as compiled_equilibrium
from cdpr.compiled import sensitivity as compiled_sensitivity
from cdpr.compiled import subsets as compiled_subsets
from cdpr.errors import CdprError
from cdpr.models import equilibrium, sensitivity
from cdpr.models.results import STATUSES, pose_columns, subset_codes, taut_labels
from cdpr.models.subsets import solve_points


def to_frame(robot, res, redundancy="paper"):
    """One row per point of a ``solve_points_any`` (or ``sensitivities``, or
    ``compensation.compensated_pose``) result, with stable column names (SI units).

    Parameters
    ----------
    robot : Robot
        Supplies m and the subsets.
    res : dict
        The per-point arrays (``models.results``).
    redundancy : {"paper", "physical"}
        The mode that produced ``res``.

    Returns
    -------
    DataFrame
        ``results.pose_columns`` (x, y, z, x_s, y_s, z_s, dp [m], t1..tm [N]); paper mode: subset
        (label '1-2-3', '' when none), iterations, status; physical mode: taut (label of the taut
        cables, '1-2-3-4'), n_taut, iterations, status. The status categories are
        ``res["statuses"]`` when given (``compensation.COMP_STATUSES``), else ``results.STATUSES``.
        When ``res`` holds sensitivities (key ``S``): then dx_d<θ>, dy_d<θ>, dz_d<θ> per parameter
        [m per unit of θ] (``sensitivity.sensitivity_columns``) and smooth.
    """
    df = pd.DataFrame(pose_columns(robot, res))
    if check_redundancy(redundancy) == "paper":
        codes, labels = subset_codes(robot, res["subset"])
        df["subset"] = pd.Categorical.from_codes(codes, categories=labels)
    else:
        codes, labels = taut_labels(res["taut"])
        df["taut"] = pd.Categorical.from_codes(codes, categories=labels)
        df["n_taut"] = res["n_taut"]
    df["iterations"] = res["iterations"]
    statuses = list(res.get("statuses", STATUSES))
    codes = (
        res["status_code"]
        if "status_code" in res
        else pd.Categorical(res["status"], categories=statuses).codes
    )
    df["status"] = pd.Categorical.from_codes(codes, categories=statuses)
    if "S" in res:
        S = res["S"]
        flat = np.swapaxes(S, 1, 2).reshape(len(S), -1)
        sens = pd.DataFrame(flat, columns=sensitivity.sensitivity_columns(res["names"]))
        sens["smooth"] = res["smooth"]
        df = pd.concat([df, sens], axis=1)
    return df


#: Points solved per batch: bounds memory (about 2 kB per point and subset) and keeps arrays in cache.
CHUNK = 20000


#: The (engine, method) pairs that exist: the compiled kernel implements Newton only.
ENGINES = {"compiled": ("newton",), "numpy": ("newton", "fixed_point")}


def check_engine(engine, method):
    """The engine to use: ``engine``, or when None the default for ``method`` (compiled for Newton,
    numpy for the fixed point). Raises CdprError for a pair that does not exist (never falls back
    silently)."""
    if engine is None:
        return "compiled" if method == "newton" else "numpy"
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


def solve_points_any(
    robot, p, method="newton", engine=None, threads=None, redundancy="paper", L0=None, L=None, **options
):
    """Per-point results as a dict of arrays from the chosen model and engine.

    ``redundancy="paper"``: DEGM_E on every 3-cable subset and the paper's choice
    (``redundancy.solve_points`` keys), commanded total lengths ``L`` (N, m) [m] or L_TS at p.
    ``redundancy="physical"``: the equilibrium on all cables (``equilibrium.solve_physical`` keys),
    commanded rest lengths ``L0`` (N, m) [m] or L_TS at p. An engine/method/model combination that
    does not exist raises CdprError."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    check_redundancy(redundancy)
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
            return compiled_equilibrium.solve_physical_fast(robot, p, L0=L0, threads=threads, **options)
        return equilibrium.solve_physical(robot, p, L0=L0, **options)
    if L0 is not None:
        raise CdprError(
            "commanded lengths need physical mode (--redundancy physical); paper mode commands L_TS at the desired point"
        )
    engine = check_engine(engine, method)
    if L is not None:
        options["L"] = L
    if engine == "compiled":
        return compiled_subsets.solve_points_fast(robot, p, threads=threads, **options)
    return solve_points(robot, p, method=method, **options)


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
    p = np.atleast_2d(np.asarray(p, dtype=float))
    check_redundancy(redundancy)
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.sensitivities_fast(
            robot, p, redundancy=redundancy, L=L, threads=threads, gap_tol=gap_tol, t_tol=t_tol, **solver
        )
    return sensitivity.sensitivities(
        robot, p, redundancy=redundancy, L=L, gap_tol=gap_tol, t_tol=t_tol, **solver
    )


def subset_sensitivities(robot, p, L=None, columns=None, engine=None, threads=None, **solver):
    """Every 3-cable subset of paper mode at every point with dP*/dθ and dt/dθ, by the chosen engine
    (``"compiled"`` default: ``cdpr.compiled.sensitivity.subset_sensitivities``; ``"numpy"``: the
    reference ``cdpr.models.sensitivity.subset_sensitivities``, whose docstring gives the result);
    another engine raises CdprError."""
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.subset_sensitivities(
            robot, p, L=L, columns=columns, threads=threads, **solver
        )
    return sensitivity.subset_sensitivities(robot, p, L=L, columns=columns, **solver)


def linear_dp(dp0, S, valid, delta, t0=None, St=None, T_a=None, engine=None, threads=None):
    """The linearised ‖dp‖ (n, N) [m] of every parameter change (``models.sensitivity.linear_dp``,
    the reference, whose docstring gives the equation), by the chosen engine (``"compiled"``
    default: ``cdpr.compiled.sensitivity.linear_dp``, points in parallel); another engine raises
    CdprError."""
    if check_engine(engine, "newton") == "compiled":
        return compiled_sensitivity.linear_dp(dp0, S, valid, delta, t0, St, T_a, threads=threads)
    return sensitivity.linear_dp(dp0, S, valid, delta, t0, St, T_a)


def solve_table(
    robot, p, method="newton", chunk=CHUNK, engine=None, threads=None, redundancy="paper", L0=None, **options
):
    """Solve DEGM_E at points p with the paper-mode subset choice, as a DataFrame (``to_frame``).

    Parameters
    ----------
    robot : Robot
    p : array (N, 3) [m]
        Desired platform positions.
    method : {"newton", "fixed_point"}
        DEGM_E solver (``direct.degm_e``).
    engine : {"compiled", "numpy", None}
        None (default): compiled for Newton, numpy for the fixed point. ``"compiled"`` runs the numba kernel of ``cdpr.compiled.subsets`` over all points in parallel
        (``threads`` caps the threads); Newton only. ``"numpy"`` runs ``redundancy.solve_points`` in
        chunks of ``chunk`` points: the reference implementation, and the only one for the fixed
        point. Both give the same table (tested). Another pair raises CdprError.

    redundancy : {"paper", "physical"}
        The paper's 3-cable subset rule, or the physical equilibrium on all cables
        (``solve_points_any``); ``L0`` (N, m) [m] commanded rest lengths, physical mode only.

    Returns
    -------
    DataFrame, one row per point (``to_frame``)."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if redundancy != "paper" or L0 is not None:
        return to_frame(
            robot, solve_points_any(robot, p, method, engine, threads, redundancy, L0, **options), redundancy
        )
    engine = check_engine(engine, method)
    if engine == "compiled":
        return to_frame(robot, compiled_subsets.solve_points_fast(robot, p, threads=threads, **options))
    starts = range(0, len(p), chunk) if len(p) else [0]
    frames = [
        to_frame(robot, solve_points(robot, p[i : i + chunk], method=method, **options)) for i in starts
    ]
    return pd.concat(frames, ignore_index=True)
