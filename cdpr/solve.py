"""Solving many points into a table: the engine/method dispatch and the per-point columns.

``solve_table`` is what the command line and the pipeline call. It chooses the compiled kernel
(``cdpr.compiled.subsets``) or the numpy reference (``cdpr.models.subsets``), refuses engine/method pairs that do
not exist, and returns one row per point with stable column names (``to_frame``).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from cdpr.errors import CdprError
from cdpr.models.subsets import STATUSES, pose_columns, solve_points, subset_label


def subset_labels(robot, subset):
    """Categorical labels ('1-2-3', ..., '' when none) of an (N, 3) array of 0-based subsets, built
    from integer codes (no Python loop per point; parquet stores it dictionary-encoded)."""
    subs = robot.subsets
    labels = [subset_label(s) for s in subs] + [""]
    weights = np.array([robot.m * robot.m, robot.m, 1])
    skey = subs @ weights  # lexicographic order -> sorted keys
    key = np.asarray(subset).reshape(-1, 3) @ weights
    pos = np.minimum(np.searchsorted(skey, key), len(subs) - 1)
    code = np.where((np.asarray(subset).reshape(-1, 3)[:, 0] >= 0) & (skey[pos] == key), pos, len(subs))
    return pd.Categorical.from_codes(code, categories=labels)


def to_frame(robot, res):
    """One row per point with stable column names: x, y, z, x_s, y_s, z_s, dp, t1..tm, subset,
    iterations, status (SI units)."""
    df = pose_columns(robot, res)
    df["subset"] = subset_labels(robot, res["subset"])
    df["iterations"] = res["iterations"]
    codes = (
        res["status_code"]
        if "status_code" in res
        else pd.Categorical(res["status"], categories=list(STATUSES)).codes
    )
    df["status"] = pd.Categorical.from_codes(codes, categories=list(STATUSES))
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


def check_spatial(robot, engine, redundancy):
    """The engine for a robot that is not a suspended point mass (``Robot.suspended_point_mass``):
    such robots have the numpy 6-DoF physical mode only (``cdpr.models.equilibrium6``); paper mode
    (3 of m) and the compiled engine raise CdprError in one line."""
    if redundancy != "physical":
        raise CdprError(
            f"{robot.source}: paper mode (3-cable subsets) is the point-mass rule; this robot has platform "
            "attachments or pulley axes other than +z: use redundancy: physical (--redundancy physical)"
        )
    if engine == "compiled":
        raise CdprError(
            f"{robot.source}: the compiled engine has no 6-DoF solver yet; use --engine numpy (the default for this robot)"
        )
    return "numpy"


def solve_points_any(
    robot, p, method="newton", engine=None, threads=None, redundancy="paper", L0=None, rotvec=None, **options
):
    """Per-point results as a dict of arrays from the chosen model and engine.

    ``redundancy="paper"``: DEGM_E on every 3-cable subset and the paper's choice
    (``redundancy.solve_points`` keys), commanded lengths L_TS at p. ``redundancy="physical"``:
    the equilibrium on all cables (``equilibrium.solve_physical`` keys), commanded rest lengths
    ``L0`` (N, m) [m] or L_TS at p. An engine/method/model combination that does not exist raises
    CdprError."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if redundancy not in REDUNDANCY:
        raise CdprError(f"unknown redundancy {redundancy!r}; allowed: {', '.join(REDUNDANCY)}")
    if not robot.suspended_point_mass or rotvec is not None or p.shape[1] == 6:
        if not robot.suspended_point_mass:
            check_spatial(robot, engine, redundancy)
        if redundancy == "physical" or not robot.suspended_point_mass:
            from cdpr.models.equilibrium6 import solve_spatial

            if method != "newton":
                raise CdprError(
                    "physical mode has one solver (Newton on the force balance); --method fixed_point applies to paper mode"
                )

            return solve_spatial(robot, p, rotvec, L0=L0, **options)
        p = p[:, :3]  # paper mode on a point mass: the orientation plays no part
    if redundancy == "physical":
        if method != "newton":
            raise CdprError(
                "physical mode has one solver (Newton on the force balance); --method fixed_point applies to paper mode"
            )
        engine = check_engine(engine, "newton")
        if L0 is not None:
            L0 = np.broadcast_to(np.asarray(L0, dtype=float), (len(p), robot.m))
        if engine == "compiled":
            from cdpr.compiled.equilibrium import solve_physical_fast

            return solve_physical_fast(robot, p, L0=L0, threads=threads, **options)
        from cdpr.models.equilibrium import solve_physical

        return solve_physical(robot, p, L0=L0, **options)
    if L0 is not None:
        raise CdprError(
            "commanded lengths need physical mode (--redundancy physical); paper mode commands L_TS at the desired point"
        )
    engine = check_engine(engine, method)
    if engine == "compiled":
        from cdpr.compiled.subsets import solve_points_fast

        return solve_points_fast(robot, p, threads=threads, **options)
    return solve_points(robot, p, method=method, **options)


def results_frame(robot, res, redundancy="paper"):
    """One row per point of a ``solve_points_any`` result (paper: ``to_frame``; physical:
    ``equilibrium.to_frame`` with the taut cables instead of the subset)."""
    if redundancy == "physical":
        from cdpr.models.equilibrium import to_frame as physical_frame

        if "rotvec_s" in res and not robot.point_mass:
            from cdpr.models.equilibrium6 import to_frame6

            return to_frame6(robot, res)
        return physical_frame(robot, res)
    return to_frame(robot, res)


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
    DataFrame, one row per point (``results_frame``)."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if redundancy != "paper" or L0 is not None or not robot.suspended_point_mass or "rotvec" in options:
        return results_frame(
            robot, solve_points_any(robot, p, method, engine, threads, redundancy, L0, **options), redundancy
        )
    engine = check_engine(engine, method)
    if engine == "compiled":
        from cdpr.compiled.subsets import solve_points_fast

        return to_frame(robot, solve_points_fast(robot, p, threads=threads, **options))
    starts = range(0, len(p), chunk) if len(p) else [0]
    frames = [
        to_frame(robot, solve_points(robot, p[i : i + chunk], method=method, **options)) for i in starts
    ]
    return pd.concat(frames, ignore_index=True)
