"""The uncertainty study's experiments (the ``uncertainty:`` section of a study file): DataFrames in
and out, no files. The mathematics (distributions, drivers, seeded samples, ``PoseErrorModel``,
the linearisation, Sobol indices) is ``cdpr.analyses.uncertainty``; this module applies it to the
designs of a study (``pipeline.study.design_robot``) for the pipeline's tasks.

Every table has ‖δp‖'s columns (``index_m``, ``index_full_m``, ``q05_m``, ``rms_m``, ``dominant``, ...)
and, for a robot solved as a pose (``PoseErrorModel.responses``: a rigid platform, or pulleys at
other axes than +z; physical mode), δφ's beside them, named by ``column`` (``index_phi_rad``,
``index_phi_full_rad``, ``q05_phi_rad``, ``rms_phi_rad``, ``dominant_phi``, ...).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (section 5).
"""

from __future__ import annotations

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
    nanquantile,
    parameter_samples,
    sample_stats,
    sobol_analysis,
)
from cdpr.analyses.workspace import grid_points, shard_range
from cdpr.parameters import parameter_values
from cdpr.pipeline.study import design_robot, rotvec, uq_redundancy

#: The tag and unit suffix of each response's columns (``column``).
_TAGS = {"dp": ("", "_m"), "dphi": ("_phi", "_rad")}
#: ``sample_stats``'s columns of ‖δp‖.
_STATS = ("index", "median", "p95")


def column(response, stem, kind="", unit=True):
    """The table column of ``stem`` for a response: ‖δp‖'s ``{stem}[_{kind}]_m``, δφ's
    ``{stem}_phi[_{kind}]_rad`` (``index_full_m``, ``index_phi_full_rad``, ``q05_phi_rad``, ...);
    ``unit`` False leaves the unit out (``dominant``, ``dominant_phi``, the Sobol output ``index_phi``).

    Parameters
    ----------
    response : {"dp", "dphi"}
        ``analyses.uncertainty.RESPONSES``.
    stem : str
    kind : str
        "full", "lin" or "" (none).
    unit : bool

    Returns
    -------
    str
    """
    tag, u = _TAGS[response]
    return f"{stem}{tag}{'_' + kind if kind else ''}{u if unit else ''}"


def _nominal(response):
    """The nominal value's column: dp_nominal_m, dphi_nominal_rad."""
    return f"{response}_nominal{_TAGS[response][1]}"


def _stats(values, ok, response, kind="", keep=None):
    """``sample_stats`` of a response over the points ``keep`` (default all: the points not left
    out, ``_left_out``) with its columns named (``column``); not_ok for ‖δp‖ only."""
    if keep is not None and not keep.all():  # C order: the sums over the points as without keep
        values, ok = np.ascontiguousarray(values[:, keep]), np.ascontiguousarray(ok[:, keep])
    s = sample_stats(values, ok)
    if response != "dp":
        s = s.drop(columns="not_ok")
    return s.rename(columns={f"{k}_m": column(response, k, kind) for k in _STATS})


def _rigid(m_):
    """A model whose robot can interfere (not a point mass): its tables get the interference counts."""
    return not m_.robot.point_mass


def _left_out(m_):
    """The points kept (N,) bool: all but those where the nominal robot's cables interfere at its
    solved pose (``PoseErrorModel.interfering``), which every statistic leaves out."""
    return ~m_.interfering()


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
    dr = drivers(u["parameters"], robot)
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
    theta : ndarray, shape (stop - start, len(parameter_names(robot)))
    """
    u = st["uncertainty"]
    dr, active = study_drivers(st, robot)
    U = mc_uniforms(u["seed"], start, stop, len(dr))
    th = parameter_samples(robot, dr, U, active if varied else None)
    check_samples(robot, th, st.path)
    return th


def model(st, design, case, points, threads=None):
    """The ``PoseErrorModel`` of a design and case at ``points`` with the study's settings (and its
    ``rotvec_rad`` for a robot solved as a pose).

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
        rotvec=rotvec(st),
    )


def _active_columns(st, robot):
    """The θ columns of the drivers Monte Carlo varies (``monte_carlo.vary``)."""
    dr, active = study_drivers(st, robot)
    return driver_columns([d for d, a in zip(dr, active, strict=True) if a])


def _max_diff(full, lin, both, axis):
    """|full - lin| where both are ok, and its largest value along ``axis`` (NaN where none)."""
    with np.errstate(all="ignore"):
        diff = np.where(both, np.abs(full - lin), np.nan)
        out = np.nanmax(np.where(both, diff, -np.inf), axis=axis) if diff.size else np.nan
    return diff, np.where(np.isfinite(out), out, np.nan)


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
        largest point difference [m], the share of points differing by more than ``agree_tol_m``;
        for a pose the same of δφ [rad] after them (index_phi_full_rad, ..., max_diff_phi_rad);
        for a rigid platform, last, interfering_points (the points left out of every statistic:
        the nominal robot's cables interfere at its solved pose, ``PoseErrorModel.interfering``)
        and interfering_full (of the points kept and ok, those where the sample's own robot
        interferes at its solved pose: flagged, kept in the statistics).
    points : DataFrame
        x, y, z, smooth (the nominal answer's flag), dp_nominal_m, max_diff_m over the shard's
        samples, n_disagree (samples where the difference exceeds ``agree_tol_m``); for a pose
        dphi_nominal_rad and max_diff_phi_rad [rad]; for a rigid platform, last, interfering (the
        point is left out; its max_diff NaN, n_disagree 0) and n_interfering (the shard's samples
        whose solved pose interferes there).
    """
    mc = st["uncertainty"]["monte_carlo"]
    start, stop = shard_range(mc["full_samples"], shard, mc["shards"])
    m_ = model(st, design, case, grid_points(box, mc["index_n"]), threads)
    th = mc_parameters(st, m_.robot, start, stop)
    full, ok_f, hit = m_.solve(th, interference=True)
    keep = _left_out(m_)
    lins = m_.linearisations(_active_columns(st, m_.robot))
    lin = {r: lins[r].dp(th) for r in m_.responses}
    ok_l = np.isfinite(lin["dp"])
    both = ok_f & ok_l & keep
    tol = mc["agree_tol_m"]
    samples = {"sample": np.arange(start, stop)}
    points = {"x": m_.p[:, 0], "y": m_.p[:, 1], "z": m_.p[:, 2], "smooth": lins["dp"].smooth}
    for r in m_.responses:
        diff, max_s = _max_diff(full[r], lin[r], both, 1)
        _, max_p = _max_diff(full[r], lin[r], both, 0)
        sf, sl = _stats(full[r], ok_f, r, "full", keep), _stats(lin[r], ok_l, r, "lin", keep)
        for k in _STATS:
            samples[column(r, k, "full")] = sf[column(r, k, "full")]
            samples[column(r, k, "lin")] = sl[column(r, k, "lin")]
        if r == "dp":
            samples.update(not_ok_full=sf.not_ok, not_ok_lin=sl.not_ok)
        samples[column(r, "max_diff")] = max_s
        with np.errstate(all="ignore"):
            points[_nominal(r)] = np.where(lins[r].ok, np.linalg.norm(lins[r].nominal()[0], axis=1), np.nan)
        points[column(r, "max_diff")] = max_p if len(th) else np.nan
        if r == "dp":  # the tolerance is in metres: the points and samples where ‖δp‖ disagrees
            samples["share_disagree"] = (diff > tol).sum(axis=1) / np.maximum(both.sum(axis=1), 1)
            points["n_disagree"] = (diff > tol).sum(axis=0)
    if _rigid(m_):  # the interference counts (docs/interference.md), last
        samples["interfering_points"] = np.full(len(th), int((~keep).sum()))
        samples["interfering_full"] = (hit & keep & ok_f).sum(axis=1)
        points.update(interfering=~keep, n_interfering=hit.sum(axis=0))
    return pd.DataFrame(samples), pd.DataFrame(points)


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
        sample, index_m, median_m, p95_m [m], not_ok; for a pose index_phi_rad, median_phi_rad,
        p95_phi_rad [rad]; for a rigid platform, last, interfering_points (the points left out of
        every row: the nominal robot's cables interfere at its solved pose; a linearised sample's
        own interference is not tested).
    """
    mc = st["uncertainty"]["monte_carlo"]
    m_ = model(st, design, case, grid_points(box, mc["index_n"]), threads)
    keep = _left_out(m_)
    lins = m_.linearisations(_active_columns(st, m_.robot))
    th = np.vstack([parameter_values(m_.robot), mc_parameters(st, m_.robot, 0, mc["samples"])])
    out = linear_stats(lins["dp"], th, threads=threads, keep=keep)
    for r in m_.responses[1:]:
        s = linear_stats(lins[r], th, threads=threads, keep=keep).drop(columns="not_ok")
        out = pd.concat([out, s.rename(columns={f"{k}_m": column(r, k) for k in _STATS})], axis=1)
    out.insert(0, "sample", np.arange(-1, mc["samples"]))
    if _rigid(m_):
        out["interfering_points"] = int((~keep).sum())
    return out


def _quantiles(values, ok):
    with np.errstate(all="ignore"):  # nanquantile warns of no all-NaN slice (numpy's did)
        return nanquantile(np.where(ok, values, np.nan), QUANTILES, axis=0)


def path_bands(st, design, case, threads=None):
    """‖δp‖ quantiles (5, 50, 95 %) along the section 5.2 path (``elasticity.path``) over every
    Monte Carlo sample, by full solves; and δφ's for a pose.

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
        point is ok); for a pose dphi_nominal_rad, q05_phi_rad, q50_phi_rad, q95_phi_rad [rad]; for
        a rigid platform, last, interfering (the nominal robot's cables interfere at its solved pose)
        and interfering_share (share of samples whose solved pose interferes): a path's points are
        flagged, not left out (as the study's paths).

    References
    ----------
    Paty et al. 2021, section 5.2, Fig. 19.
    """
    path = st["elasticity"]["path"]
    P, s = trajectory_points(path["start_m"], path["end_m"], path["points"])
    m_ = model(st, design, case, P, threads)
    mc = st["uncertainty"]["monte_carlo"]
    th = mc_parameters(st, m_.robot, 0, mc["samples"])
    values, ok, hit = m_.solve(th, interference=True)
    nominal, ok0, hit0 = m_.solve(parameter_values(m_.robot)[None], interference=True)
    out = {"s": s, "x": P[:, 0], "y": P[:, 1], "z": P[:, 2]}
    for r in m_.responses:
        q = _quantiles(values[r], ok)
        out[_nominal(r)] = np.where(ok0[0], nominal[r][0], np.nan)
        out.update({column(r, f"q{k:02d}"): q[j] for j, k in enumerate((5, 50, 95))})
        if r == "dp":
            out["ok_share"] = ok.mean(axis=0)
    if _rigid(m_):
        out.update(interfering=hit0[0], interfering_share=hit.mean(axis=0))
    return pd.DataFrame(out)


def sobol(st, design, case, box, threads=None):
    """Sobol first-order and total indices (SALib) of the global index over the RW_C grid
    (``sobol.index_n``) and of ‖δp‖ at ``sobol.points_m``, for every declared parameter (per driver
    and per group), by full solves; for a pose also of δφ's global index (output ``index_phi``) and
    of δφ at the points (``dphi@(x, y, z)``).

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
        output, level, name, S1, S1_conf, ST, ST_conf (the half-widths of SALib's 95 % bootstrap
        confidence intervals), base_samples (N).
    rows : DataFrame
        The evaluations of the independent rows A and B of Saltelli's scheme (2 base_samples draws
        of every parameter): index_m, median_m, p95_m, not_ok over the RW_C grid (and index_phi_rad,
        median_phi_rad, p95_phi_rad for a pose); for a rigid platform, last, interfering_points
        (grid points left out of every row: the nominal robot's cables interfere at its solved
        pose) and interfering_full (of the points kept and ok, those where the row's robot
        interferes at its solved pose: flagged, kept; these rows are solved again for it).

    Notes
    -----
    A point of ``points_m`` where the nominal robot interferes is left out too: its outputs are
    NaN, as at a point that is not ok.
    """
    u = st["uncertainty"]
    so = u["sobol"]
    grid = grid_points(box, so["index_n"])
    pts = np.asarray(so["points_m"], dtype=float).reshape(-1, 3)
    m_ = model(st, design, case, np.vstack([grid, pts]), threads)
    keep = _left_out(m_)
    dr, _ = study_drivers(st, m_.robot)
    n = len(grid)
    at = [f"({x:g}, {y:g}, {z:g})" for x, y, z in pts]
    outputs = [column(r, "index", unit=False) for r in m_.responses]
    outputs += [f"{r}@{a}" for r in m_.responses for a in at]
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
            values, ok = m_.solve(theta[list(todo.values())])
            parts = [_stats(values[r][:, :n], ok[:, :n], r, keep=keep[:n]) for r in m_.responses]
            s = parts[0] if len(parts) == 1 else pd.concat(parts, axis=1)
            done_stats.append(s)
            done_Y.append(
                np.column_stack(
                    [s[column(r, "index")].to_numpy() for r in m_.responses]
                    + [np.where(ok[:, n:] & keep[n:], values[r][:, n:], np.nan) for r in m_.responses]
                )
            )
            base = len(seen)
            seen.update((k, base + j) for j, k in enumerate(todo))
        at = np.array([seen[k] for k in keys], dtype=np.intp)
        stats.append(pd.concat(done_stats, ignore_index=True).iloc[at].reset_index(drop=True))
        return np.vstack(done_Y)[at]

    per, _, theta = sobol_analysis(
        evaluate, dr, m_.robot, so["base_samples"], u["seed"], outputs, source=st.path
    )
    D = len(dr)
    ab = np.r_[0 : len(stats[0]) : D + 2, D + 1 : len(stats[0]) : D + 2]  # the A and B rows
    rows = stats[0].iloc[ab].reset_index(drop=True)
    if _rigid(m_):  # the A and B rows' own interference (flagged): tested on these rows only, whose
        # few solves are repeated; every row of Saltelli's scheme would cost ~10 ms each
        _, ok_ab, hit = m_.solve(theta[ab], interference=True)
        rows["interfering_points"] = int((~keep[:n]).sum())
        rows["interfering_full"] = (hit[:, :n] & keep[:n] & ok_ab[:, :n]).sum(axis=1)
    grp, _, _ = sobol_analysis(
        evaluate, dr, m_.robot, so["base_samples"], u["seed"], outputs, groups=True, source=st.path
    )
    indices = pd.concat([per, grp], ignore_index=True)
    indices["base_samples"] = int(so["base_samples"])  # N of Saltelli's scheme: what the intervals rest on
    return indices, rows


def _dominant(lin, dr, projected):
    """The nominal value, the dominant driver and its group, its share and the RMS of the
    first-order contributions (``local_contributions``) at every point."""
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
    """The parameter that dominates the spread of ‖δp‖ (and of δφ for a pose) on the plane
    z = ``plane.z_m`` (``map_n`` points per side), from the first-order contributions of every
    declared driver (``local_contributions``).

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
        contributions), rms_m (the square root of that sum) [m]; for a pose dphi_nominal_rad,
        dominant_phi, group_phi, share_phi and rms_phi_rad [rad]; for a rigid platform, last,
        interfering: the nominal robot's cables interfere at its solved pose, and the point is left
        out (NaN values and empty names, as a point that is not ok).
    """
    u = st["uncertainty"]
    robot = design_robot(st, st["doe"]["robot"], st["optimal"][design])
    P = plane_points(robot, st["plane"]["z_m"], u["map_n"])
    m_ = model(st, design, case, P, threads)
    dr, _ = study_drivers(st, robot)
    lins = m_.linearisations(driver_columns(dr))
    out = {"x": P[:, 0], "y": P[:, 1], "z": P[:, 2]}
    keep = _left_out(m_)
    for r in m_.responses:
        keys = (_nominal(r), column(r, "dominant", unit=False), column(r, "group", unit=False))
        keys += (column(r, "share", unit=False), column(r, "rms"))
        cols = _dominant(lins[r], dr, projected=case == "uncompensated")
        cols = [np.where(keep, c, "" if c.dtype == object else np.nan) for c in cols]
        out.update(zip(keys, cols, strict=True))
    if _rigid(m_):
        out["interfering"] = ~keep
    return pd.DataFrame(out)


def bands(linear, full, nominal_common=None, rows=None):
    """The global-index band of the Monte Carlo samples of one design and case.

    Parameters
    ----------
    linear : DataFrame
        ``linear_samples`` (sample -1 nominal, then every sample).
    full : DataFrame
        The concatenated ``mc_shard`` samples.
    nominal_common : float [m], optional
        Our index at the nominal common E, default the linear nominal row.
    rows : DataFrame, optional
        ``sobol``'s Saltelli rows (every declared parameter): a third row, ``all_parameters``.

    Returns
    -------
    DataFrame
        One row per method (linearised over every sample, full over the full-solve samples, and
        all_parameters with ``rows``): method, n, index_nominal_m, index_q05_m, index_q50_m,
        index_q95_m, index_min_m, index_max_m, plus_m = max - nominal, minus_m = nominal - min (the
        paper's band definition), median_q50_m / p95_q50_m (median over samples of each sample's
        median and 95 % of ‖δp‖ over the points) and p95_q95_m [m]; for a pose (``index_phi_rad``
        in ``linear``; needs ``rows``) δφ's band beside: index_phi_nominal_rad, index_phi_q05_rad,
        index_phi_q50_rad, index_phi_q95_rad, index_phi_min_rad, index_phi_max_rad [rad]; for a
        rigid platform (``interfering_points`` in ``linear``), last, interfering_points (the grid's
        points left out of the row's statistics: the nominal robot's cables interfere at its
        solved pose; the Saltelli rows' grid for all_parameters) and interfering_full (over the
        row's samples, the sample points kept whose own robot interferes at its solved pose;
        missing for the linearised row, whose samples are not solved).

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
        out.append(
            {
                "method": method,
                "n": int(len(idx)),
                **_spread(idx, nom, "index", "m"),
                "plus_m": float(np.max(idx)) - nom if len(idx) else np.nan,
                "minus_m": nom - float(np.min(idx)) if len(idx) else np.nan,
                "median_q50_m": float(np.median(med)) if len(med) else np.nan,
                "p95_q50_m": float(np.median(p95)) if len(p95) else np.nan,
                "p95_q95_m": float(np.quantile(p95, 0.95)) if len(p95) else np.nan,
            }
        )
    b = pd.DataFrame(out)
    if rows is None:
        return _interference_counts(b, linear, full, None)
    q = np.quantile(rows.index_m, QUANTILES)
    nom = float(b.index_nominal_m.iloc[0])
    every = {
        "method": "all_parameters",
        "n": len(rows),
        "index_nominal_m": nom,
        "index_q05_m": q[0],
        "index_q50_m": q[1],
        "index_q95_m": q[2],
        "index_min_m": rows.index_m.min(),
        "index_max_m": rows.index_m.max(),
        "plus_m": rows.index_m.max() - nom,
        "minus_m": nom - rows.index_m.min(),
        "median_q50_m": rows.median_m.median(),
        "p95_q50_m": rows.p95_m.median(),
        "p95_q95_m": rows.p95_m.quantile(0.95),
    }
    b = pd.concat([b, pd.DataFrame([every])], ignore_index=True)
    if "index_phi_rad" in linear:  # a pose: δφ's band beside
        b = pd.concat([b, _phi_bands(linear, full, rows)], axis=1)
    return _interference_counts(b, linear, full, rows)


def _interference_counts(b, linear, full, rows):
    """``bands``'s interference columns (a rigid platform: ``interfering_points`` in ``linear``):
    the points each row leaves out and the flagged sample points of its full solves."""
    if "interfering_points" not in linear:
        return b
    tables = [linear, full] + ([] if rows is None else [rows])
    b["interfering_points"] = pd.array(
        [
            int(t["interfering_points"].max()) if "interfering_points" in t and len(t) else pd.NA
            for t in tables
        ],
        dtype="Int64",
    )
    flagged = [pd.NA] + [
        int(t["interfering_full"].sum()) if "interfering_full" in t else pd.NA for t in tables[1:]
    ]
    b["interfering_full"] = pd.array(flagged, dtype="Int64")
    return b


def _phi_bands(linear, full, rows):
    """δφ's global-index band for ``bands``'s three rows (linearised, full, all_parameters) [rad]."""
    nom = float(linear.loc[linear["sample"] == -1, "index_phi_rad"].iloc[0])
    out = []
    for idx in (
        linear.loc[linear["sample"] >= 0, "index_phi_rad"],
        full["index_phi_full_rad"],
        rows["index_phi_rad"],
    ):
        out.append(_spread(idx.to_numpy(dtype=float), nom, "index_phi", "rad"))
    return pd.DataFrame(out)


def _spread(idx, nom, stem, unit):
    """One band's global-index spread (``bands``, ``_phi_bands``): the columns
    {stem}_nominal_{unit}, the QUANTILES q05, q50, q95, min and max of the samples ``idx`` (NaN
    when there are none), with ``nom`` the nominal robot's index [unit]."""
    q = np.quantile(idx, QUANTILES) if len(idx) else [np.nan] * 3
    return {
        f"{stem}_nominal_{unit}": nom,
        f"{stem}_q05_{unit}": q[0],
        f"{stem}_q50_{unit}": q[1],
        f"{stem}_q95_{unit}": q[2],
        f"{stem}_min_{unit}": float(np.min(idx)) if len(idx) else np.nan,
        f"{stem}_max_{unit}": float(np.max(idx)) if len(idx) else np.nan,
    }


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
        sensitivities flag as not smooth), z_disagree_min_m / z_disagree_max_m (where they are);
        for a pose (``index_phi_full_rad`` in ``full``) max_index_phi_diff_rad (largest difference
        of the δφ global index) and max_point_phi_diff_rad (of δφ at a point) [rad].
    """
    d = (full["index_lin_m"] - full["index_full_m"]).abs()
    if "interfering" in points:  # a rigid platform: the points left out of every statistic
        points = points[~points["interfering"].astype(bool)]
    # one row per point: the shards' tables repeat every point (its samples split between them),
    # so a point disagrees when some shard's samples do, whatever the shard count
    phi = float(points["max_diff_phi_rad"].max()) if "max_diff_phi_rad" in points else np.nan
    points = points.groupby(["x", "y", "z"], sort=False).agg(
        smooth=("smooth", "first"), max_diff_m=("max_diff_m", "max"), n_disagree=("n_disagree", "sum")
    )
    points = points.reset_index()
    bad = points["n_disagree"] > 0
    with np.errstate(all="ignore"):
        out = {
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
    if "index_phi_full_rad" in full:  # a pose: how far the linearised δφ agrees
        d = (full["index_phi_lin_rad"] - full["index_phi_full_rad"]).abs()
        out["max_index_phi_diff_rad"] = float(d.max()) if len(d) else np.nan
        out["max_point_phi_diff_rad"] = phi
    return out
