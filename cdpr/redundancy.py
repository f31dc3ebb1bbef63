"""Choice of the cables that hold the platform and the per-point status (paper mode, section 3.2).

Every 3-cable subset is solved with DEGM_E. A subset is admissible at a point when its solution
exists, converged, and 0 <= t_j <= T_a at P*. The point's answer is the admissible subset with the
lowest |dp| (Fig. 8-9). Ties (e.g. on the diagonals of CDPR4, where two subsets give the same
|dp| mathematically) are broken deterministically: among subsets within ``TIE_TOL`` of the
minimum, the first in lexicographic order of cable numbers wins.

Status of a point (``STATUSES``):
  ok             an admissible subset exists;
  over_tension   some subset converged with all tensions >= 0 but one above T_a, none admissible;
  slack          subsets converged but each needs a negative (pushing) tension;
  not_converged  a subset's solver hit its iteration cap and no subset converged;
  inaccessible   no subset has a geometric solution (spheres do not meet, point above the
                 pulleys, point inside a sheave, coplanar cables).
For a point that is not ``ok``, the solved position and tensions of the converged subset with the
lowest |dp| are still reported, so that the reason can be inspected; aggregations keep ``ok`` rows.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from .direct import degm_e
from .inverse import L_TS

STATUSES = ("ok", "slack", "over_tension", "inaccessible", "not_converged")
#: |dp| difference [m] under which two admissible subsets count as tied.
TIE_TOL = 1e-9


def solve_points(robot, p, method="newton", **options):
    """Solve DEGM_E at desired points p (N, 3) over all 3-cable subsets; choose per point.

    Returns a dict of arrays: P_s (N, 3), dp (N,), t (N, m) with NaN for slack cables,
    subset (N, 3) 0-based (-1 when none), iterations (N,), status (N,) strings, and the per-subset
    dp (N, n_subsets) and admissible (N, n_subsets) for maps such as Fig. 9.
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    n = p.shape[0]
    subsets = robot.subsets
    ns = len(subsets)
    L_all = L_TS(robot, p)
    T_a = robot.T_a[subsets][:, None, :]  # (n_subsets, 1, 3) per-cable admissible tension
    Ps = np.full((ns, n, 3), np.nan)
    ts = np.full((ns, n, 3), np.nan)
    its = np.zeros((ns, n), dtype=np.int32)
    conv = np.zeros((ns, n), dtype=bool)
    exists = np.zeros((ns, n), dtype=bool)
    for k, s in enumerate(subsets):
        r = degm_e(robot, p, subset=s, L=L_all[:, s], method=method, **options)
        Ps[k], ts[k], its[k], conv[k], exists[k] = r.P, r.t, r.iterations, r.converged, r.exists
    dp = np.linalg.norm(Ps - p, axis=2)
    t_ok_low = (ts >= 0).all(axis=2)
    t_ok_high = (ts <= T_a).all(axis=2)
    admissible = conv & t_ok_low & t_ok_high
    # choose: admissible with min dp, else converged with min dp (for reporting only)
    dp_adm = np.where(admissible, dp, np.inf)
    dp_conv = np.where(conv, dp, np.inf)
    any_adm = admissible.any(axis=0)
    key = np.where(any_adm, dp_adm, dp_conv)
    best = key.min(axis=0)
    tied = key <= best + TIE_TOL
    choice = np.argmax(tied, axis=0)  # first (lexicographic) subset among the tied ones
    has = np.isfinite(best)
    cols = np.arange(n)
    status = np.full(n, "inaccessible", dtype=object)
    status[(~conv & exists).any(axis=0)] = "not_converged"
    status[conv.any(axis=0)] = "slack"
    status[(conv & t_ok_low).any(axis=0)] = "over_tension"
    status[any_adm] = "ok"
    t_full = np.full((n, robot.m), np.nan)
    chosen = np.where(has[:, None], subsets[choice], -1)
    for j in range(3):
        t_full[cols[has], chosen[has, j]] = ts[choice[has], cols[has], j]
    P_s = np.where(has[:, None], Ps[choice, cols], np.nan)
    return {
        "p": p,
        "P_s": P_s,
        "dp": np.where(has, dp[choice, cols], np.nan),
        "t": t_full,
        "subset": chosen,
        "iterations": its[choice, cols],
        "status": status.astype(str),
        "dp_subsets": dp.T,
        "admissible_subsets": admissible.T,
    }


def subset_label(subset_row):
    """1-based cable numbers joined by '-', e.g. '1-2-3'; '' when no subset."""
    if subset_row[0] < 0:
        return ""
    return "-".join(str(int(i) + 1) for i in subset_row)


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
    df = pd.DataFrame({
        "x": res["p"][:, 0], "y": res["p"][:, 1], "z": res["p"][:, 2],
        "x_s": res["P_s"][:, 0], "y_s": res["P_s"][:, 1], "z_s": res["P_s"][:, 2],
        "dp": res["dp"],
    })
    for i in range(robot.m):
        df[f"t{i + 1}"] = res["t"][:, i]
    df["subset"] = subset_labels(robot, res["subset"])
    df["iterations"] = res["iterations"]
    codes = res["status_code"] if "status_code" in res else pd.Categorical(res["status"], categories=list(STATUSES)).codes
    df["status"] = pd.Categorical.from_codes(codes, categories=list(STATUSES))
    return df


#: Points solved per batch: bounds memory (about 2 kB per point and subset) and keeps arrays in cache.
CHUNK = 20000


def solve_table(robot, p, method="newton", chunk=CHUNK, engine="compiled", threads=None, **options):
    """Solve DEGM_E at points p with the paper-mode subset choice, as a DataFrame (``to_frame``).

    ``engine="compiled"`` (default, Newton only) runs the numba kernel of ``cdpr.fast`` over all
    points in parallel (``threads`` caps the threads); ``engine="numpy"`` runs ``solve_points`` in
    chunks of ``chunk`` points: the reference implementation, and the only one for the fixed point.
    Both give the same table (tested)."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    if engine == "compiled" and method == "newton":
        from .fast import solve_points_fast

        return to_frame(robot, solve_points_fast(robot, p, threads=threads, **options))
    if engine not in ("compiled", "numpy"):
        raise ValueError(f"unknown engine {engine!r}; allowed: 'compiled', 'numpy'")
    starts = range(0, len(p), chunk) if len(p) else [0]
    frames = [to_frame(robot, solve_points(robot, p[i:i + chunk], method=method, **options)) for i in starts]
    return pd.concat(frames, ignore_index=True)
