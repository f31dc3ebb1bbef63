"""The uncertainty study's experiments on a spatial robot (rigid 6-DoF platform, physical mode):
the ``uq`` experiments with ``uncertainty6.PoseErrorModel6``, whose responses are ‖δp‖ [m] and δφ
[rad]. The tables keep ``uq``'s columns (so ``uq.bands`` and ``uq.agreement`` read them) and add the
orientation's beside them (``*_phi_*_rad``). Samples, drivers and checks are ``uq``'s (point-mass
parameter vectors, mapped to 6-DoF ones by ``uncertainty6.spatial_theta``: the attachments b and the
centre of mass c stay nominal)."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from cdpr.analyses.scans import plane_points, trajectory_points
from cdpr.analyses.uncertainty import (
    QUANTILES,
    driver_columns,
    linear_stats,
    local_contributions,
    nominal_theta,
    sample_stats,
    sobol_analysis,
)
from cdpr.analyses.uncertainty6 import PoseErrorModel6, spatial_theta
from cdpr.analyses.workspace import grid_points, shard_range
from cdpr.pipeline.study import design_robot, rotvec
from cdpr.pipeline.uq import mc_parameters, study_drivers

#: sample_stats columns -> their orientation names.
_PHI = {"index_m": "index_phi_rad", "median_m": "median_phi_rad", "p95_m": "p95_phi_rad"}


def model(st, design, case, points, threads=None):
    """The ``PoseErrorModel6`` of a design and case at ``points`` and the study's ``rotvec_rad``.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    points : array_like, shape (N, 3) [m]
    threads : int, optional

    Returns
    -------
    PoseErrorModel6
    """
    robot = design_robot(st, st["doe"]["robot"], st["optimal"][design])
    return PoseErrorModel6(
        robot, points, rotvec(st), case, st["uncertainty"]["compensation"], threads=threads
    )


def _phi_stats(dphi, ok):
    """``sample_stats`` of δφ, columns renamed (``_PHI``)."""
    return sample_stats(dphi, ok).drop(columns="not_ok").rename(columns=_PHI)


def _active_columns(st, robot):
    dr, active = study_drivers(st, robot)
    return driver_columns([d for d, a in zip(dr, active, strict=True) if a])


def _max_diff(full, lin, both, axis):
    with np.errstate(all="ignore"):
        diff = np.where(both, np.abs(full - lin), np.nan)
        out = np.nanmax(np.where(both, diff, -np.inf), axis=axis) if diff.size else np.nan
    return diff, np.where(np.isfinite(out), out, np.nan)


def mc_shard(st, design, case, box, shard, threads=None):
    """``uq.mc_shard`` on a spatial robot: the same columns, plus the orientation's.

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
        ``uq.mc_shard``'s columns plus index/median/p95_phi_full_rad and _lin_rad [rad] and
        max_diff_phi_rad (the largest point difference of δφ).
    points : DataFrame
        ``uq.mc_shard``'s columns plus dphi_nominal_rad and max_diff_phi_rad [rad].
    """
    mc = st["uncertainty"]["monte_carlo"]
    start, stop = shard_range(mc["full_samples"], shard, mc["shards"])
    m_ = model(st, design, case, grid_points(box, mc["index_n"]), threads)
    th = mc_parameters(st, m_.robot, start, stop)
    dp_f, phi_f, ok_f = m_.solve(spatial_theta(m_.robot, th))
    lin_p, lin_r = m_.linearisations(_active_columns(st, m_.robot))
    dp_l, phi_l = lin_p.dp(th), lin_r.dp(th)
    ok_l = np.isfinite(dp_l)
    both = ok_f & ok_l
    diff, max_s = _max_diff(dp_f, dp_l, both, 1)
    _, max_phi_s = _max_diff(phi_f, phi_l, both, 1)
    _, max_p = _max_diff(dp_f, dp_l, both, 0)
    _, max_phi_p = _max_diff(phi_f, phi_l, both, 0)
    tol = mc["agree_tol_m"]
    sf, sl = sample_stats(dp_f, ok_f), sample_stats(dp_l, ok_l)
    pf, pl = _phi_stats(phi_f, ok_f), _phi_stats(phi_l, ok_l)
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
                "max_diff_m": max_s,
                "share_disagree": (diff > tol).sum(axis=1) / np.maximum(both.sum(axis=1), 1),
                "index_phi_full_rad": pf.index_phi_rad,
                "index_phi_lin_rad": pl.index_phi_rad,
                "median_phi_full_rad": pf.median_phi_rad,
                "median_phi_lin_rad": pl.median_phi_rad,
                "p95_phi_full_rad": pf.p95_phi_rad,
                "p95_phi_lin_rad": pl.p95_phi_rad,
                "max_diff_phi_rad": max_phi_s,
            }
        )
        points = pd.DataFrame(
            {
                "x": m_.p[:, 0],
                "y": m_.p[:, 1],
                "z": m_.p[:, 2],
                "smooth": lin_p.smooth,
                "dp_nominal_m": np.where(lin_p.ok, np.linalg.norm(lin_p.nominal()[0], axis=1), np.nan),
                "max_diff_m": max_p if len(th) else np.nan,
                "n_disagree": (diff > tol).sum(axis=0),
                "dphi_nominal_rad": np.where(lin_r.ok, np.linalg.norm(lin_r.nominal()[0], axis=1), np.nan),
                "max_diff_phi_rad": max_phi_p if len(th) else np.nan,
            }
        )
    return samples, points


def linear_samples(st, design, case, box, threads=None):
    """``uq.linear_samples`` on a spatial robot: every Monte Carlo sample by the linearised
    propagation of ‖δp‖ and δφ over the RW_C grid (sample -1 the nominal robot).

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
        sample, index_m, median_m, p95_m [m], not_ok, index_phi_rad, median_phi_rad, p95_phi_rad [rad].
    """
    mc = st["uncertainty"]["monte_carlo"]
    m_ = model(st, design, case, grid_points(box, mc["index_n"]), threads)
    lin_p, lin_r = m_.linearisations(_active_columns(st, m_.robot))
    th = np.vstack(
        [
            nominal_theta(m_.robot, study_drivers(st, m_.robot)[0]),
            mc_parameters(st, m_.robot, 0, mc["samples"]),
        ]
    )
    out = linear_stats(lin_p, th, threads=threads)
    phi = linear_stats(lin_r, th, threads=threads).drop(columns="not_ok").rename(columns=_PHI)
    out = pd.concat([out, phi], axis=1)
    out.insert(0, "sample", np.arange(-1, mc["samples"]))
    return out


def _quantiles(d, ok):
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanquantile(np.where(ok, d, np.nan), QUANTILES, axis=0)


def path_bands(st, design, case, threads=None):
    """``uq.path_bands`` on a spatial robot: the 5, 50, 95 % quantiles of ‖δp‖ and δφ along the
    section 5.2 path over every Monte Carlo sample, by full solves.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    threads : int, optional

    Returns
    -------
    DataFrame
        ``uq.path_bands``'s columns plus dphi_nominal_rad, q05_phi_rad, q50_phi_rad, q95_phi_rad [rad].
    """
    path = st["elasticity"]["path"]
    P, s = trajectory_points(path["start_m"], path["end_m"], path["points"])
    m_ = model(st, design, case, P, threads)
    mc = st["uncertainty"]["monte_carlo"]
    th = mc_parameters(st, m_.robot, 0, mc["samples"])
    dp, phi, ok = m_.solve(spatial_theta(m_.robot, th))
    dp0, phi0, ok0 = m_.solve(spatial_theta(m_.robot, nominal_theta(m_.robot)))
    q, qp = _quantiles(dp, ok), _quantiles(phi, ok)
    return pd.DataFrame(
        {
            "s": s,
            "x": P[:, 0],
            "y": P[:, 1],
            "z": P[:, 2],
            "dp_nominal_m": np.where(ok0[0], dp0[0], np.nan),
            "q05_m": q[0],
            "q50_m": q[1],
            "q95_m": q[2],
            "ok_share": ok.mean(axis=0),
            "dphi_nominal_rad": np.where(ok0[0], phi0[0], np.nan),
            "q05_phi_rad": qp[0],
            "q50_phi_rad": qp[1],
            "q95_phi_rad": qp[2],
        }
    )


def sobol(st, design, case, box, threads=None):
    """``uq.sobol`` on a spatial robot: Sobol first-order and total indices (SALib) of the global
    indices of ‖δp‖ (output ``index``) and of δφ (``index_phi``) over the RW_C grid, and of ‖δp‖
    (``dp@(x, y, z)``) and δφ (``dphi@(x, y, z)``) at ``sobol.points_m``, per driver and per group,
    by full solves.

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
        Saltelli's A and B rows: index_m, median_m, p95_m, not_ok, index_phi_rad, median_phi_rad,
        p95_phi_rad over the RW_C grid.
    """
    u = st["uncertainty"]
    so = u["sobol"]
    grid = grid_points(box, so["index_n"])
    pts = np.asarray(so["points_m"], dtype=float).reshape(-1, 3)
    m_ = model(st, design, case, np.vstack([grid, pts]), threads)
    dr, _ = study_drivers(st, m_.robot)
    n = len(grid)
    at = [f"({x:g}, {y:g}, {z:g})" for x, y, z in pts]
    outputs = ["index", "index_phi"] + [f"dp@{a}" for a in at] + [f"dphi@{a}" for a in at]
    stats = []

    def evaluate(theta):
        dp, phi, ok = m_.solve(spatial_theta(m_.robot, theta))
        s = pd.concat([sample_stats(dp[:, :n], ok[:, :n]), _phi_stats(phi[:, :n], ok[:, :n])], axis=1)
        stats.append(s)
        return np.column_stack(
            [
                s.index_m.to_numpy(),
                s.index_phi_rad.to_numpy(),
                np.where(ok[:, n:], dp[:, n:], np.nan),
                np.where(ok[:, n:], phi[:, n:], np.nan),
            ]
        )

    per, _, _ = sobol_analysis(evaluate, dr, m_.robot, so["base_samples"], u["seed"], outputs, source=st.path)
    D = len(dr)
    rows = stats[0].iloc[np.r_[0 : len(stats[0]) : D + 2, D + 1 : len(stats[0]) : D + 2]]  # A and B rows
    grp, _, _ = sobol_analysis(
        evaluate, dr, m_.robot, so["base_samples"], u["seed"], outputs, groups=True, source=st.path
    )
    return pd.concat([per, grp], ignore_index=True), rows.reset_index(drop=True)


def _dominant(lin, dr, projected):
    c = local_contributions(lin, dr, projected=projected)
    total = c.sum(axis=1)
    ok = lin.ok & (total > 0)
    k = np.argmax(np.where(ok[:, None], c, -1.0), axis=1)
    names = np.array([d.name for d in dr], dtype=object)
    groups = np.array([d.group for d in dr], dtype=object)
    with np.errstate(all="ignore"):
        return (
            np.where(lin.ok, np.linalg.norm(lin.nominal()[0], axis=1), np.nan),
            np.where(ok, names[k], ""),
            np.where(ok, groups[k], ""),
            np.where(ok, c[np.arange(len(c)), k] / total, np.nan),
            np.where(ok, np.sqrt(total), np.nan),
        )


def dominant_map(st, design, case, threads=None):
    """``uq.dominant_map`` on a spatial robot: the driver that dominates the first-order spread of
    ‖δp‖, and the one of δφ, on the plane z = ``plane.z_m``.

    Parameters
    ----------
    st : Study
    design : str
    case : {"uncompensated", "compensated"}
    threads : int, optional

    Returns
    -------
    DataFrame
        ``uq.dominant_map``'s columns plus dphi_nominal_rad, dominant_phi, group_phi, share_phi and
        rms_phi_rad [rad].
    """
    u = st["uncertainty"]
    robot = design_robot(st, st["doe"]["robot"], st["optimal"][design])
    P = plane_points(robot, st["plane"]["z_m"], u["map_n"])
    m_ = model(st, design, case, P, threads)
    dr, _ = study_drivers(st, robot)
    lin_p, lin_r = m_.linearisations(driver_columns(dr))
    projected = case == "uncompensated"
    out = {"x": P[:, 0], "y": P[:, 1], "z": P[:, 2]}
    keys = ("dp_nominal_m", "dominant", "group", "share", "rms_m")
    out.update(zip(keys, _dominant(lin_p, dr, projected), strict=True))
    keys = ("dphi_nominal_rad", "dominant_phi", "group_phi", "share_phi", "rms_phi_rad")
    out.update(zip(keys, _dominant(lin_r, dr, projected), strict=True))
    return pd.DataFrame(out)


def phi_bands(linear, full, rows):
    """The δφ global-index band of one design and case, for ``uq.bands``'s three rows (linearised,
    full, all_parameters).

    Parameters
    ----------
    linear : DataFrame
        ``linear_samples``.
    full : DataFrame
        The concatenated ``mc_shard`` samples.
    rows : DataFrame
        ``sobol``'s Saltelli rows (every declared parameter).

    Returns
    -------
    DataFrame
        Three rows: index_phi_nominal_rad, index_phi_q05_rad, index_phi_q50_rad, index_phi_q95_rad,
        index_phi_min_rad, index_phi_max_rad [rad].
    """
    nom = float(linear.loc[linear["sample"] == -1, "index_phi_rad"].iloc[0])
    out = []
    for idx in (
        linear.loc[linear["sample"] >= 0, "index_phi_rad"],
        full["index_phi_full_rad"],
        rows["index_phi_rad"],
    ):
        idx = idx.to_numpy(dtype=float)
        q = np.quantile(idx, QUANTILES) if len(idx) else [np.nan] * 3
        out.append(
            {
                "index_phi_nominal_rad": nom,
                "index_phi_q05_rad": q[0],
                "index_phi_q50_rad": q[1],
                "index_phi_q95_rad": q[2],
                "index_phi_min_rad": float(np.min(idx)) if len(idx) else np.nan,
                "index_phi_max_rad": float(np.max(idx)) if len(idx) else np.nan,
            }
        )
    return pd.DataFrame(out)


def phi_agreement(full, points):
    """How far the linearised δφ agrees with the full solves (one design and case).

    Parameters
    ----------
    full, points : DataFrame
        The concatenated ``mc_shard`` samples and points.

    Returns
    -------
    dict
        max_index_phi_diff_rad (largest difference of the δφ global index) and
        max_point_phi_diff_rad (of δφ at a point) [rad].
    """
    d = (full["index_phi_lin_rad"] - full["index_phi_full_rad"]).abs()
    return {
        "max_index_phi_diff_rad": float(d.max()) if len(d) else np.nan,
        "max_point_phi_diff_rad": float(points["max_diff_phi_rad"].max()),
    }
