"""Solving many points into a table: the engine/method dispatch and the per-point columns.

``solve_table`` is what the command line and the pipeline call. It chooses the compiled kernel
(``cdpr.fast``) or the numpy reference (``cdpr.redundancy``), refuses engine/method pairs that do
not exist, and returns one row per point with stable column names (``to_frame``).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .errors import CdprError
from .redundancy import STATUSES, solve_points, subset_label


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
    df = pd.DataFrame(
        {
            "x": res["p"][:, 0],
            "y": res["p"][:, 1],
            "z": res["p"][:, 2],
            "x_s": res["P_s"][:, 0],
            "y_s": res["P_s"][:, 1],
            "z_s": res["P_s"][:, 2],
            "dp": res["dp"],
        }
    )
    for i in range(robot.m):
        df[f"t{i + 1}"] = res["t"][:, i]
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


def solve_points_any(robot, p, method="newton", engine=None, threads=None, **options):
    """Per-point results as a dict of arrays (``redundancy.solve_points`` keys) from the chosen
    engine; an engine/method pair that does not exist raises CdprError."""
    engine = check_engine(engine, method)
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if engine == "compiled":
        from .fast import solve_points_fast

        return solve_points_fast(robot, p, threads=threads, **options)
    return solve_points(robot, p, method=method, **options)


def solve_table(robot, p, method="newton", chunk=CHUNK, engine=None, threads=None, **options):
    """Solve DEGM_E at points p with the paper-mode subset choice, as a DataFrame (``to_frame``).

    Parameters
    ----------
    robot : Robot
    p : array (N, 3) [m]
        Desired platform positions.
    method : {"newton", "fixed_point"}
        DEGM_E solver (``direct.degm_e``).
    engine : {"compiled", "numpy", None}
        None (default): compiled for Newton, numpy for the fixed point. ``"compiled"`` runs the numba kernel of ``cdpr.fast`` over all points in parallel
        (``threads`` caps the threads); Newton only. ``"numpy"`` runs ``redundancy.solve_points`` in
        chunks of ``chunk`` points: the reference implementation, and the only one for the fixed
        point. Both give the same table (tested). Another pair raises CdprError.

    Returns
    -------
    DataFrame, one row per point (``to_frame``)."""
    engine = check_engine(engine, method)
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if engine == "compiled":
        from .fast import solve_points_fast

        return to_frame(robot, solve_points_fast(robot, p, threads=threads, **options))
    starts = range(0, len(p), chunk) if len(p) else [0]
    frames = [
        to_frame(robot, solve_points(robot, p[i : i + chunk], method=method, **options)) for i in starts
    ]
    return pd.concat(frames, ignore_index=True)
