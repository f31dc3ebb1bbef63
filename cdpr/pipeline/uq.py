"""The uncertainty study's experiments (the ``uncertainty:`` section of a study file): DataFrames in
and out, no files. The mathematics (distributions, drivers, seeded samples, ``PoseErrorModel``,
the linearisation, Sobol indices) is ``cdpr.analyses.uncertainty``; this module applies it to the
designs of a study (``pipeline.study.design_robot``) for the pipeline's tasks.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (section 5).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from cdpr.analyses.scans import plane_points, trajectory_points
from cdpr.analyses.uncertainty import (
    QUANTILES,
    PoseErrorModel,
    check_samples,
    driver_columns,
    drivers,
    linear_stats,
    local_contributions,
    mc_uniforms,
    parameter_samples,
    sample_stats,
    sobol_analysis,
)
from cdpr.analyses.workspace import grid_points, shard_range
from cdpr.parameters import parameter_values
from cdpr.pipeline.study import design_robot, uq_redundancy


def study_drivers(st, robot):
    """The drivers of a study's ``uncertainty.parameters`` and which of them Monte Carlo varies.

    Parameters
    ----------
    st : Study
    robot : Robot

    Returns
    -------
    drivers : list of Driver
    active : ndarray of bool
        The drivers of ``monte_carlo.vary``.
    """
    u = st["uncertainty"]
    dr = drivers(u["parameters"], robot.m)
    vary = u["monte_carlo"]["vary"]
    return dr, np.array([d.key in vary for d in dr], dtype=bool)


def mc_parameters(st, robot, start, stop, varied=True):
    """Checked parameter vectors of Monte Carlo samples start .. stop - 1 of a study.

    Parameters
    ----------
    st : Study
    robot : Robot
    start, stop : int
    varied : bool
        Only the drivers of ``monte_carlo.vary`` move (the others stay nominal); else all.

    Returns
    -------
    theta : ndarray, shape (stop - start, 7 m + 1)
    """
    u = st["uncertainty"]
    dr, active = study_drivers(st, robot)
    U = mc_uniforms(u["seed"], start, stop, len(dr))
    th = parameter_samples(robot, dr, U, active if varied else None)
    check_samples(robot, th, st.path)
    return th


def model(st, design, case, points, threads=None):
    """The ``PoseErrorModel`` of a design and case at ``points`` with the study's settings.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    points : array_like, shape (N, 3) [m]
    threads : int, optional

    Returns
    -------
    PoseErrorModel
    """
    u = st["uncertainty"]
    return PoseErrorModel(
        design_robot(st, st["doe"]["robot"], st["optimal"][design]),
        points,
        case,
        redundancy=uq_redundancy(st),
        compensation=u["compensation"],
        threads=threads,
    )


def mc_shard(st, design, case, box, shard, threads=None):
    """Monte Carlo shard by full solves over the RW_C grid, and the linearised propagation of the
    same samples: how far the two agree.

    Samples ``shard_range(full_samples, shard, shards)`` of ``monte_carlo``.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    box : array_like, shape (6,) [m]
        RW_C.
    shard : int
    threads : int, optional

    Returns
    -------
    samples : DataFrame
        sample, index/median/p95 of ‖δp‖ [m] by full solves and linearised, not-ok points, the
        largest point difference [m], the share of points differing by more than ``agree_tol_m``.
    points : DataFrame
        x, y, z, smooth (the nominal answer's flag), dp_nominal_m, max_diff_m over the shard's
        samples, n_disagree (samples where the difference exceeds ``agree_tol_m``).
    """
    mc = st["uncertainty"]["monte_carlo"]
    start, stop = shard_range(mc["full_samples"], shard, mc["shards"])
    m_ = model(st, design, case, grid_points(box, mc["index_n"]), threads)
    th = mc_parameters(st, m_.robot, start, stop)
    dr, active = study_drivers(st, m_.robot)
    dp_f, ok_f = m_.solve(th)
    lin = m_.linearise(driver_columns([d for d, a in zip(dr, active) if a]))
    dp_l = lin.dp(th)
    ok_l = np.isfinite(dp_l)
    both = ok_f & ok_l
    diff = np.where(both, np.abs(dp_f - dp_l), np.nan)
    tol = mc["agree_tol_m"]
    sf, sl = sample_stats(dp_f, ok_f), sample_stats(dp_l, ok_l)
    with np.errstate(all="ignore"):
        samples = pd.DataFrame(
            {
                "sample": np.arange(start, stop),
                "index_full_m": sf.index_m,
                "index_lin_m": sl.index_m,
                "median_full_m": sf.median_m,
                "median_lin_m": sl.median_m,
                "p95_full_m": sf.p95_m,
                "p95_lin_m": sl.p95_m,
                "not_ok_full": sf.not_ok,
                "not_ok_lin": sl.not_ok,
                "max_diff_m": np.nanmax(np.where(both, diff, -np.inf), axis=1),
                "share_disagree": (diff > tol).sum(axis=1) / np.maximum(both.sum(axis=1), 1),
            }
        )
        dp0 = np.where(lin.ok, np.linalg.norm(lin.nominal()[0], axis=1), np.nan)
        points = pd.DataFrame(
            {
                "x": m_.p[:, 0],
                "y": m_.p[:, 1],
                "z": m_.p[:, 2],
                "smooth": lin.smooth,
                "dp_nominal_m": dp0,
                "max_diff_m": np.nanmax(np.where(both, diff, -np.inf), axis=0) if len(th) else np.nan,
                "n_disagree": (diff > tol).sum(axis=0),
            }
        )
    samples["max_diff_m"] = samples["max_diff_m"].where(np.isfinite(samples["max_diff_m"]))
    points["max_diff_m"] = points["max_diff_m"].where(np.isfinite(points["max_diff_m"]))
    return samples, points


def linear_samples(st, design, case, box, threads=None):
    """Every Monte Carlo sample (``monte_carlo.samples``) by the linearised propagation over the
    RW_C grid; the first row (sample -1) is the nominal robot.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    box : array_like, shape (6,) [m]
    threads : int, optional

    Returns
    -------
    DataFrame
        sample, index_m, median_m, p95_m [m], not_ok.
    """
    mc = st["uncertainty"]["monte_carlo"]
    m_ = model(st, design, case, grid_points(box, mc["index_n"]), threads)
    dr, active = study_drivers(st, m_.robot)
    lin = m_.linearise(driver_columns([d for d, a in zip(dr, active) if a]))
    th = np.vstack([parameter_values(m_.robot), mc_parameters(st, m_.robot, 0, mc["samples"])])
    out = linear_stats(lin, th, threads=threads)
    out.insert(0, "sample", np.arange(-1, mc["samples"]))
    return out


def path_bands(st, design, case, threads=None):
    """‖δp‖ quantiles (5, 50, 95 %) along the section 5.2 path (``elasticity.path``) over every
    Monte Carlo sample, by full solves.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    threads : int, optional

    Returns
    -------
    DataFrame
        s, x, y, z [m], dp_nominal_m, q05_m, q50_m, q95_m [m], ok_share (share of samples where the
        point is ok).

    References
    ----------
    Paty et al. 2021, section 5.2, Fig. 19.
    """
    path = st["elasticity"]["path"]
    P, s = trajectory_points(path["start_m"], path["end_m"], path["points"])
    m_ = model(st, design, case, P, threads)
    mc = st["uncertainty"]["monte_carlo"]
    th = mc_parameters(st, m_.robot, 0, mc["samples"])
    dp, ok = m_.solve(th)
    nominal, ok0 = m_.solve(parameter_values(m_.robot)[None])
    d = np.where(ok, dp, np.nan)
    with np.errstate(all="ignore"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            q = np.nanquantile(d, QUANTILES, axis=0)
    return pd.DataFrame(
        {
            "s": s,
            "x": P[:, 0],
            "y": P[:, 1],
            "z": P[:, 2],
            "dp_nominal_m": np.where(ok0[0], nominal[0], np.nan),
            "q05_m": q[0],
            "q50_m": q[1],
            "q95_m": q[2],
            "ok_share": ok.mean(axis=0),
        }
    )


def sobol(st, design, case, box, threads=None):
    """Sobol first-order and total indices (SALib) of the global index over the RW_C grid
    (``sobol.index_n``) and of ‖δp‖ at ``sobol.points_m``, for every declared parameter (per driver
    and per group), by full solves.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    box : array_like, shape (6,) [m]
    threads : int, optional

    Returns
    -------
    indices : DataFrame
        output, level, name, S1, S1_conf, ST, ST_conf.
    rows : DataFrame
        The evaluations of the independent rows A and B of Saltelli's scheme (2 base_samples draws
        of every parameter): index_m, median_m, p95_m, not_ok over the RW_C grid.
    """
    u = st["uncertainty"]
    so = u["sobol"]
    grid = grid_points(box, so["index_n"])
    pts = np.asarray(so["points_m"], dtype=float).reshape(-1, 3)
    m_ = model(st, design, case, np.vstack([grid, pts]), threads)
    dr, _ = study_drivers(st, m_.robot)
    n = len(grid)
    outputs = ["index"] + [f"dp@({x:g}, {y:g}, {z:g})" for x, y, z in pts]
    stats = []
    # the group analysis repeats rows of the per-parameter one (the A and B matrices, the groups of one
    # driver): each distinct θ row is solved once (row by row the same numbers as solving it again)
    seen, done_stats, done_Y = {}, [], []

    def evaluate(theta):
        keys = [t.tobytes() for t in theta]
        todo = {}
        for i, k in enumerate(keys):
            if k not in seen and k not in todo:
                todo[k] = i
        if todo:
            dp, ok = m_.solve(theta[list(todo.values())])
            s = sample_stats(dp[:, :n], ok[:, :n])
            done_stats.append(s)
            done_Y.append(np.column_stack([s.index_m.to_numpy(), np.where(ok[:, n:], dp[:, n:], np.nan)]))
            base = len(seen)
            seen.update((k, base + j) for j, k in enumerate(todo))
        at = np.array([seen[k] for k in keys], dtype=np.intp)
        stats.append(pd.concat(done_stats, ignore_index=True).iloc[at].reset_index(drop=True))
        return np.vstack(done_Y)[at]

    per, _, _ = sobol_analysis(evaluate, dr, m_.robot, so["base_samples"], u["seed"], outputs, source=st.path)
    D = len(dr)
    rows = stats[0].iloc[np.r_[0 : len(stats[0]) : D + 2, D + 1 : len(stats[0]) : D + 2]]  # A and B rows
    grp, _, _ = sobol_analysis(
        evaluate, dr, m_.robot, so["base_samples"], u["seed"], outputs, groups=True, source=st.path
    )
    return pd.concat([per, grp], ignore_index=True), rows.reset_index(drop=True)


def dominant_map(st, design, case, threads=None):
    """The parameter that dominates the spread of ‖δp‖ on the plane z = ``plane.z_m`` (``map_n``
    points per side), from the first-order contributions of every declared driver
    (``local_contributions``).

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    threads : int, optional

    Returns
    -------
    DataFrame
        x, y, z [m], dp_nominal_m, dominant (driver name), group, share (its part of the sum of
        contributions), rms_m (the square root of that sum) [m].
    """
    u = st["uncertainty"]
    robot = design_robot(st, st["doe"]["robot"], st["optimal"][design])
    P = plane_points(robot, st["plane"]["z_m"], u["map_n"])
    m_ = model(st, design, case, P, threads)
    dr, _ = study_drivers(st, robot)
    lin = m_.linearise(driver_columns(dr))
    c = local_contributions(lin, dr, projected=case == "uncompensated")
    total = c.sum(axis=1)
    ok = lin.ok & (total > 0)
    k = np.argmax(np.where(ok[:, None], c, -1.0), axis=1)
    names = np.array([d.name for d in dr], dtype=object)
    groups = np.array([d.group for d in dr], dtype=object)
    dp0 = np.linalg.norm(lin.nominal()[0], axis=1)
    with np.errstate(all="ignore"):
        return pd.DataFrame(
            {
                "x": P[:, 0],
                "y": P[:, 1],
                "z": P[:, 2],
                "dp_nominal_m": np.where(lin.ok, dp0, np.nan),
                "dominant": np.where(ok, names[k], ""),
                "group": np.where(ok, groups[k], ""),
                "share": np.where(ok, c[np.arange(len(c)), k] / total, np.nan),
                "rms_m": np.where(ok, np.sqrt(total), np.nan),
            }
        )


def bands(linear, full, nominal_common=None):
    """The global-index band of the Monte Carlo samples of one design and case.

    Parameters
    ----------
    linear : DataFrame
        ``linear_samples`` (sample -1 nominal, then every sample).
    full : DataFrame
        The concatenated ``mc_shard`` samples.
    nominal_common : float [m], optional
        Our index at the nominal common E, default the linear nominal row.

    Returns
    -------
    DataFrame
        One row per method (linearised over every sample, full over the full-solve samples):
        method, n, index_nominal_m, index_q05_m, index_q50_m, index_q95_m, index_min_m,
        index_max_m, plus_m = max - nominal, minus_m = nominal - min (the paper's band definition),
        median_q50_m / p95_q50_m (median over samples of each sample's median and 95 % of ‖δp‖ over
        the points) and p95_q95_m [m].

    References
    ----------
    Paty et al. 2021, section 5.1.
    """
    nom = linear.loc[linear["sample"] == -1, "index_m"].iloc[0]
    nom = nom if nominal_common is None else nominal_common
    out = []
    for method, idx, med, p95 in (
        ("linearised", *(linear.loc[linear["sample"] >= 0, c] for c in ("index_m", "median_m", "p95_m"))),
        ("full", full["index_full_m"], full["median_full_m"], full["p95_full_m"]),
    ):
        q = np.quantile(idx, QUANTILES) if len(idx) else [np.nan] * 3
        out.append(
            {
                "method": method,
                "n": int(len(idx)),
                "index_nominal_m": nom,
                "index_q05_m": q[0],
                "index_q50_m": q[1],
                "index_q95_m": q[2],
                "index_min_m": float(np.min(idx)) if len(idx) else np.nan,
                "index_max_m": float(np.max(idx)) if len(idx) else np.nan,
                "plus_m": float(np.max(idx)) - nom if len(idx) else np.nan,
                "minus_m": nom - float(np.min(idx)) if len(idx) else np.nan,
                "median_q50_m": float(np.median(med)) if len(med) else np.nan,
                "p95_q50_m": float(np.median(p95)) if len(p95) else np.nan,
                "p95_q95_m": float(np.quantile(p95, 0.95)) if len(p95) else np.nan,
            }
        )
    return pd.DataFrame(out)


def agreement(full, points, agree_tol):
    """How far the linearised propagation agrees with the full solves (one design and case).

    Parameters
    ----------
    full : DataFrame
        The concatenated ``mc_shard`` samples.
    points : DataFrame
        The concatenated ``mc_shard`` points.
    agree_tol : float [m]

    Returns
    -------
    dict
        n (samples compared), agree_tol_m, max_index_diff_m and max_index_rel (largest difference of
        the global index), max_p95_diff_m, max_point_diff_m, share_points_disagree (points where some
        sample differs by more than ``agree_tol``), share_disagree_flagged (the part of those the
        sensitivities flag as not smooth), z_disagree_min_m / z_disagree_max_m (where they are).
    """
    d = (full["index_lin_m"] - full["index_full_m"]).abs()
    # one row per point: the shards' tables repeat every point (its samples split between them),
    # so a point disagrees when some shard's samples do, whatever the shard count
    points = points.groupby(["x", "y", "z"], sort=False).agg(
        smooth=("smooth", "first"), max_diff_m=("max_diff_m", "max"), n_disagree=("n_disagree", "sum")
    )
    points = points.reset_index()
    bad = points["n_disagree"] > 0
    with np.errstate(all="ignore"):
        return {
            "n": int(len(full)),
            "agree_tol_m": agree_tol,
            "max_index_diff_m": float(d.max()) if len(d) else np.nan,
            "max_index_rel": float((d / full["index_full_m"]).max()) if len(d) else np.nan,
            "max_p95_diff_m": float((full["p95_lin_m"] - full["p95_full_m"]).abs().max())
            if len(d)
            else np.nan,
            "max_point_diff_m": float(points["max_diff_m"].max()),
            "share_points_disagree": float(bad.mean()),
            "share_disagree_flagged": float((~points.loc[bad, "smooth"]).mean()) if bad.any() else np.nan,
            "z_disagree_min_m": float(points.loc[bad, "z"].min()) if bad.any() else np.nan,
            "z_disagree_max_m": float(points.loc[bad, "z"].max()) if bad.any() else np.nan,
        }
