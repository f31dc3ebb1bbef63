"""results/<study>/summary.md and summary.csv: every number the papers state beside ours.

The papers' numbers live in ``cdpr/data/paper_values.yaml`` (quantity, source, value, unit,
tolerance, reason, and where our number comes from). This module loops over that file: for each
entry it runs the named extractor (``EXTRACTORS``) on the study's result tables and writes one row
with columns quantity, source, paper, ours, unit, tolerance, verdict, note. A row is
``reproduced`` when |ours - paper| <= tolerance, else ``not reproduced`` followed by the known
reason. A study that is not the paper's (``paper_comparison: false``) is not scored: its summary
lists our numbers only. Nothing here is tuned: the paper's values are read for comparison only.
"""

from __future__ import annotations

import importlib.resources
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from cdpr import io, table_io
from cdpr.analyses import scans
from cdpr.analyses.workspace import interference_free_rows
from cdpr.models import winch
from cdpr.pipeline.results import Layout, check_complete, rel_path
from cdpr.pipeline.study import robot_of, spatial_robots
from cdpr.pipeline.summary_rows import headline, interference_rows, reached_rows, read_result
from cdpr.robot import TABLE1

#: The papers' numbers (package data of the library).
PAPER_VALUES = importlib.resources.files("cdpr") / "data" / "paper_values.yaml"
COLUMNS = ["quantity", "source", "paper", "ours", "unit", "tolerance", "verdict", "note"]


def paper_values(path=PAPER_VALUES):
    """The entries of ``cdpr/data/paper_values.yaml`` as a list of dicts."""
    return yaml.safe_load(Path(path).read_text(encoding="utf-8"))


# Each extractor returns (our value in SI units or a count, note) or None when its table is absent.
def _path_length(st, res, robot):
    path = st["trajectories"]["paths"].get(robot)
    return None if path is None else (float(np.linalg.norm(np.subtract(path["end_m"], path["start_m"]))), "")


def _path(st, res, robot, pulley, stat):
    df = read_result(res, rel_path("trajectory_table", path=robot, pulley=pulley))
    return None if df is None else (scans.ok_extremes(df)[stat == "max"], "")


def _path_reach(st, res, robot, pulley):
    mm = read_result(res, rel_path("trajectory_figure"))
    r = None if mm is None else mm[mm.design == f"{robot}_{pulley}"]
    return (
        None
        if r is None or r.empty
        else (float(r.ok_until_s_m.iloc[0]), f"path length {float(r.path_length_m.iloc[0]):.3f} m")
    )


def _path_reach_order(st, res, robot, first, second):
    a, b = _path_reach(st, res, robot, first), _path_reach(st, res, robot, second)
    return (
        None
        if a is None or b is None
        else (int(a[0] > b[0]), f"last ok s: {first} {a[0]:.3f} m, {second} {b[0]:.3f} m")
    )


def _plane(st, res, robot, pulley, stat):
    df = read_result(res, rel_path("plane_table", robot=robot, pulley=pulley))
    if df is None:
        return None
    if stat == "centre":
        ok = df[df.status == "ok"]
        return float(ok.loc[(ok.x**2 + ok.y**2).idxmin(), "dp"]), ""
    return scans.ok_extremes(df)[stat == "max"], ""


def _volumes_row(res, robot, pulley=None, limit_m=None):
    vol = read_result(res, rel_path("volumes"))
    if vol is None:
        return None
    sel = vol.robot == robot
    if pulley is not None:
        sel &= (vol.pulley == pulley) & np.isclose(vol.limit_m, limit_m)
    r = vol[sel]
    return None if r.empty else r.iloc[0]


def _R_V(st, res, robot, pulley, limit_m):
    r = _volumes_row(res, robot, pulley, limit_m)
    return None if r is None else (float(r.R_V), f"voxel error +/- {r.V_L_err_m3 / r.V_T_m3:.3f}")


def _V_T(st, res, robot):
    r = _volumes_row(res, robot)
    return None if r is None else (float(r.V_T_m3), "")


def _rw_c(res):
    p = Path(res) / rel_path("regular_workspace", "json")
    return json.loads(p.read_text(encoding="utf-8")) if p.exists() else None


def _rw_c_volume(st, res):
    rw = _rw_c(res)
    return (
        None
        if rw is None
        else (
            rw["computed_volume_m3"],
            f"computed box {np.round(rw['computed'], 3).tolist()} on a {rw['grid_n']}^3 grid; "
            "the index uses "
            + ("the study's doe.paper_rw_c_m box" if rw["use"] == "paper" else "this computed box"),
        )
    )


def _smallest_rw_max_test(st, res):
    rw = _rw_c(res)
    return None if rw is None else (rw["smallest_rw_max_test"], "")


def _doe_index(st, res, stat):
    d = read_result(res, rel_path("doe"))
    if d is None:
        return None
    i = d.index_m.idxmin() if stat == "min" else d.index_m.idxmax()
    return float(d.index_m[i]), f"arg{stat} = test {int(d.test[i])}"


def _doe_test(st, res, stat):
    d = read_result(res, rel_path("doe"))
    return (
        None
        if d is None
        else (int(d.loc[d.index_m.idxmin() if stat == "argmin" else d.index_m.idxmax(), "test"]), "")
    )


def _doe_two_best(st, res, tests):
    d = read_result(res, rel_path("doe"))
    if d is None:
        return None
    two = sorted(d.nsmallest(2, "index_m").test.astype(int).tolist())
    return int(two == sorted(tests)), f"two best: {two}"


def _doe_worst(st, res, joint):
    d = read_result(res, rel_path("doe"))
    return (
        None
        if d is None or not (d.kind == joint).any()
        else (int(d[d.kind == joint].nlargest(1, "index_m").test.iloc[0]), "")
    )


def _effects(res, response="index_m"):
    """The effects of one response (``index_m``, or ``index_phi_rad`` of a spatial study) without the mean."""
    e = read_result(res, rel_path("doe", "effects"))
    if e is None:
        return None
    if "response" in e:
        e = e[e.response == response]
    return e[e.term != "mean"].set_index("term")


def _largest_effect(st, res, term):
    e = _effects(res)
    if e is None:
        return None
    top = e.effect.abs().idxmax()
    return int(top == term), f"largest: {top}"


def _third_order_smallest(st, res):
    e = _effects(res)
    if e is None:
        return None
    return int(abs(e.effect["joint:h:r_p"]) <= e.effect[["joint:h", "joint:r_p", "h:r_p"]].abs().min()), ""


def _line(st, res, pulley, column, scale=1.0):
    lines = read_result(res, rel_path("maps", "lines"))
    r = None if lines is None else lines[lines.kind == pulley]
    if r is None or r.empty:
        return None
    r = r.iloc[0]
    note = {
        "slope_k": f"{int(r.valley_points)} valley points, fixed-h valley",
        "index_opt_m": f"N = {int(r.N)}",
    }.get(column, "")
    return float(r[column]) * scale, note


def _band(st, res, design, column, scale=1.0):
    b = read_result(res, rel_path("elasticity", "bands"))
    r = None if b is None else b[b.design == design]
    if r is None or r.empty:
        return None
    return float(
        r[column].iloc[0]
    ) * scale, "at the paper's Table 3 geometry" if column == "index_mean_m" else ""


def _crossing(st, res, design, near=None):
    cr = read_result(res, rel_path("elasticity", "crossings"))
    if cr is None:
        return None
    c = cr[cr.design == design].s_m.tolist()
    return (
        float(min(c, key=lambda x: abs(x - near))) if c else float("nan")
    ), f"all crossings: {np.round(c, 3).tolist()}"


def _uq_band(st, res, design, case, column, method="linearised", scale=1.0):
    """A column of uncertainty/bands.csv (one design, case and method); the note gives the 5-95 %
    range of the index, the sample count and grid, and our common-E band for comparison."""
    b = read_result(res, rel_path("uncertainty", "bands"))
    r = None if b is None else b[(b.design == design) & (b.case == case) & (b.method == method)]
    if r is None or r.empty:
        return None
    r = r.iloc[0]
    note = (
        f"{method}, n = {int(r.n)} samples on {int(r.index_n)}^3 RW_C points; index 5-95 %: "
        f"{r.index_q05_m * 1e3:.2f}-{r.index_q95_m * 1e3:.2f} mm"
    )
    common = read_result(res, rel_path("elasticity", "bands"))
    c = None if common is None else common[common.design == design]
    if case == "uncompensated" and c is not None and not c.empty:
        c = c.iloc[0]
        note += (
            f"; our common-E band {c.index_mean_m * 1e3:.2f} +{c.plus_m * 1e3:.2f}/-{c.minus_m * 1e3:.2f} mm"
        )
    return float(r[column]) * scale, note


def _uq_sobol_top(st, res, design, case, rank=1, output="index"):
    """The rank-th largest Sobol total index of one output (parameters, not groups); the note names
    the three largest with their 95 % confidence half-widths."""
    t = read_result(res, rel_path("uncertainty", "sobol"))
    if t is None:
        return None
    g = t[(t.design == design) & (t.case == case) & (t.level == "parameter") & (t.output == output)]
    if g.empty:
        return None
    g = g.sort_values("ST", ascending=False)
    top = ", ".join(f"{r.name} {r.ST:.2f}±{r.ST_conf:.2f}" for r in g.head(3).itertuples())
    return float(g.ST.iloc[rank - 1]), f"largest ST: {top}{_sobol_basis(g)}"


#: Base samples N under which the Sobol indices get a caveat line in the summary (``sobol_caveat``):
#: at N = 512 the paper study's 95 % intervals are about ±0.03; at 128 CoGiRo's reach ±0.28.
SOBOL_SMALL_N = 512
#: A 95 % bootstrap half-width above this also gets the caveat, whatever N.
SOBOL_WIDE_CONF = 0.1


def _sobol_basis(t):
    """What a Sobol note's ± rests on: " (±: 95 % bootstrap, N = 128)", from the rows of a Sobol
    table (``base_samples``; tables written before that column: the interval only)."""
    if "base_samples" in t and len(t):
        return f" (±: 95 % bootstrap, N = {int(t.base_samples.iloc[0])})"
    return " (±: 95 % bootstrap)"


def sobol_caveat(st, res):
    """The caveat line of a summary whose Sobol indices rest on few samples: N (the study's
    ``uncertainty.sobol.base_samples``) below ``SOBOL_SMALL_N`` or a 95 % bootstrap half-width of a
    total or first-order index above ``SOBOL_WIDE_CONF``; None otherwise or without a Sobol table.

    Parameters
    ----------
    st : Study
    res : path
        The study's results folder.

    Returns
    -------
    str or None
    """
    t = read_result(res, rel_path("uncertainty", "sobol"))
    so = (st.get("uncertainty") or {}).get("sobol") or {}
    if t is None or t.empty or "base_samples" not in so:
        return None
    n = int(so["base_samples"])
    wide = float(np.nanmax(t[["S1_conf", "ST_conf"]].to_numpy()))
    outside = int(((t.ST > 1) | (t.ST < 0) | (t.S1 > 1) | (t.S1 < 0)).sum())
    if n >= SOBOL_SMALL_N and wide <= SOBOL_WIDE_CONF:
        return None
    return (
        f"Caveat: the Sobol indices rest on N = {n} base samples (Saltelli's scheme, SALib); their 95 % "
        f"bootstrap intervals (the ± in the notes, S1_conf and ST_conf in uncertainty/sobol.csv) reach "
        f"±{wide:.2g}, and {outside} of the {len(t)} indices lie outside [0, 1], which only sampling error "
        "can do. Read them as a ranking within their intervals; more base samples "
        "(`uncertainty.sobol.base_samples`) narrow the intervals."
    )


def _winch_dl(st, res, l_pm_m, scale=1000.0):
    w = read_result(res, rel_path("winch_table"))
    return None if w is None else (float(np.interp(l_pm_m, w.l_pm, w.dl)) * scale, "")


def _winch_q1_at_l_pm0(st, res):
    p = TABLE1
    return float(winch.roots(p, winch.l_pm0(p))[0]), ""


EXTRACTORS = {
    "path_length": _path_length,
    "path": _path,
    "path_reach": _path_reach,
    "path_reach_order": _path_reach_order,
    "plane": _plane,
    "R_V": _R_V,
    "V_T": _V_T,
    "rw_c_volume": _rw_c_volume,
    "smallest_rw_max_test": _smallest_rw_max_test,
    "doe_index": _doe_index,
    "doe_test": _doe_test,
    "doe_two_best": _doe_two_best,
    "doe_worst": _doe_worst,
    "largest_effect": _largest_effect,
    "third_order_smallest": _third_order_smallest,
    "line": _line,
    "band": _band,
    "crossing": _crossing,
    "uq_band": _uq_band,
    "uq_sobol_top": _uq_sobol_top,
    "winch_dl": _winch_dl,
    "winch_q1_at_l_pm0": _winch_q1_at_l_pm0,
}


def verdict(paper, ours, tolerance, reason=None, scored=True):
    """'reproduced' when |ours - paper| <= tolerance, 'not reproduced (reason)' otherwise, and
    'no paper value' when the paper prints none; 'beside the paper (reason)' for a number of ours
    shown beside a different experiment of the paper's (``scored: false`` in paper_values.yaml)."""
    if paper is None:
        return "no paper value"
    if not scored:
        return "beside the paper, not scored" + (f" ({reason})" if reason else "")
    if ours is not None and np.isfinite(ours) and abs(ours - paper) <= tolerance:
        return "reproduced"
    return "not reproduced" + (f" ({reason})" if reason else "")


def build_rows(st, res, values=None):
    """One row per entry of ``cdpr/data/paper_values.yaml`` whose result table exists."""
    scored = bool(st.get("paper_comparison"))
    rows = []
    for v in values if values is not None else paper_values():
        args = dict(v["ours"])
        kind = args.pop("kind")
        if kind == "crossing":
            args["near"] = v["value"]
        got = EXTRACTORS[kind](st, res, **args)
        if got is None:
            continue
        ours, note = got
        paper = v["value"] if scored else None
        rows.append(
            {
                "quantity": v["quantity"],
                "source": v["source"],
                "paper": paper,
                "ours": ours,
                "unit": v["unit"],
                "tolerance": v["tolerance"] if scored else None,
                "verdict": verdict(paper, ours, v["tolerance"], v.get("reason"), v.get("scored", True))
                if scored
                else "not scored (not the paper's study)",
                "note": note,
            }
        )
    return pd.DataFrame(rows, columns=COLUMNS)


def _line_note(r):
    """The note of a ``line D_<kind>`` headline row: its slope and optimum, or in words what is
    missing (no valley point on the fixed-h line: no slope, no optimum), never ``nan``."""
    parts = []
    if math.isfinite(r.slope_k):  # a line through the origin: one valley point fixes it
        parts.append(f"slope k = {r.slope_k:.4g} from {int(r.valley_points)} valley points")
    else:
        parts.append(
            "no slope k: no interior valley point on the map (the line D runs through the origin and one)"
        )
    if math.isfinite(r.h_opt_m) and math.isfinite(r.r_p_opt_m):
        parts.append(f"h = {r.h_opt_m * 1e3:.4g} mm, r_p = {r.r_p_opt_m * 1e3:.4g} mm")
    else:
        parts.append("no optimal h, r_p (no ok point on the line)")
    return "; ".join(parts)


def _ok_range(df, column, scale):
    """(min, max) of ``column`` times ``scale`` over the ok rows of a point table (NaN when none)."""
    ok = df.loc[df["status"] == "ok", column]
    return (float(ok.min()) * scale, float(ok.max()) * scale) if len(ok) else (math.nan, math.nan)


def hold_note(df, dof):
    """The note of a plane's headline row: how many points are ok and, beyond "N of N ok", how the
    platform holds: the ok points that hang on fewer cables than the platform has degrees of freedom
    (it tilts or swings until it balances), the largest δφ over the ok points, and the count of every
    other status (``out_of_frame``: a pose that left the frame box).

    Parameters
    ----------
    df : DataFrame
        A point table (``status``; ``n_taut`` or, heavy cables, ``n_holding``, and ``dphi`` [rad]
        when it has them).
    dof : int
        Degrees of freedom of the platform: 6 for a rigid platform, 3 for a point mass.

    Returns
    -------
    str
    """
    ok = df["status"].astype(str) == "ok"
    parts = [f"{int(ok.sum())} of {len(df)} points ok"]
    if "n_holding" in df:  # heavy cables: every one pulls; count those that hold (tables.to_frame)
        few = int((ok & (df["n_holding"] < dof)).sum())
        parts.append(
            f"{few} of the ok points hang on fewer than {dof} holding cables (the platform's degrees of "
            "freedom; a heavy cable hanging at about its own weight does not hold)"
        )
    elif "n_taut" in df:
        few = int((ok & (df["n_taut"] < dof)).sum())
        parts.append(
            f"{few} of the ok points hang on fewer than {dof} cables (the platform's degrees of freedom)"
        )
    if "dphi" in df and ok.any():
        parts.append(f"largest δφ {float(df.loc[ok, 'dphi'].max()) * 1e3:.4g} mrad")
    others = df.loc[~ok, "status"].astype(str).value_counts()
    if len(others):
        parts.append("not ok: " + ", ".join(f"{n} {s}" for s, n in sorted(others.items())))
    return "; ".join(parts)


def headline_rows(st, res):
    """The headline numbers of a study of spatial robots (``paper_comparison: false``, no paper
    values): per design the plane's and the paths' ‖δp‖ [mm] and δφ [mrad] ranges over the ok points
    and the paths' largest tension [N]; R_V at the study's limits (on ‖δp‖, and on δφ where the study
    sets ``volumes.dphi_limits_rad``); RW_C's volume; the DOE's best and
    worst test and largest effect on both indices; the optimal lines; the common-E band of each
    optimal design. Columns ``COLUMNS`` (paper and tolerance empty)."""
    rows = []
    for rk in st["robots"]:
        for pk in st["pulleys"]:
            df = read_result(res, rel_path("plane_table", robot=rk, pulley=pk))
            if df is None:
                continue
            dof = 3 if robot_of(st, rk).point_mass else 6
            src = f"plane z = {st['plane']['z_m']:g} m"
            counted = df[interference_free_rows(df)]  # a rigid platform's: interfering points left out
            lo, hi = _ok_range(counted, "dp", 1e3)
            rows.append(headline(f"{rk} {pk} plane ‖δp‖ min", src, lo, "mm", hold_note(df, dof)))
            rows.append(headline(f"{rk} {pk} plane ‖δp‖ max", src, hi, "mm"))
            if "dphi" in df:
                lo, hi = _ok_range(counted, "dphi", 1e3)
                rows.append(headline(f"{rk} {pk} plane δφ min", src, lo, "mrad"))
                rows.append(headline(f"{rk} {pk} plane δφ max", src, hi, "mrad"))
    for path in st["trajectories"]["paths"]:
        for pk in st["pulleys"]:
            df = read_result(res, rel_path("trajectory_table", path=path, pulley=pk))
            if df is None:
                continue
            src = f"path {path}"
            lo, hi = _ok_range(df, "dp", 1e3)
            rows.append(headline(f"{path} {pk} ‖δp‖ min / max", src, lo, "mm", f"max {hi:.4g} mm"))
            if "dphi" in df:
                lo, hi = _ok_range(df, "dphi", 1e3)
                rows.append(headline(f"{path} {pk} δφ max", src, hi, "mrad", f"min {lo:.4g} mrad"))
            t = df.loc[df.status == "ok", [c for c in df.columns if c[:1] == "t" and c[1:].isdigit()]]
            if len(t):
                rows.append(
                    headline(f"{path} {pk} largest tension", src, float(np.nanmax(t.to_numpy())), "N")
                )
    vol = read_result(res, rel_path("volumes"))
    if vol is not None:
        for r in vol[vol.paper_limit].itertuples():
            rows.append(
                headline(
                    f"{r.robot} {r.pulley} R_V at ‖δp‖ < {r.limit_m * 1e3:g} mm",
                    "volumes",
                    float(r.R_V),
                    "-",
                    f"V_L = {r.V_L_m3:.4g} m^3 of V_T = {r.V_T_m3:.4g} m^3",
                )
            )
    vol = read_result(res, rel_path("volumes_dphi")) if st["volumes"].get("dphi_limits_rad") else None
    if vol is not None:
        for r in vol[vol.study_limit].itertuples():
            rows.append(
                headline(
                    f"{r.robot} {r.pulley} R_V at δφ < {r.limit_rad * 1e3:g} mrad",
                    "volumes",
                    float(r.R_V),
                    "-",
                    f"V_L = {r.V_L_m3:.4g} m^3 of V_T = {r.V_T_m3:.4g} m^3",
                )
            )
    rw = _rw_c(res)
    if rw is not None:
        rows.append(
            headline(
                "RW_C volume",
                rel_path("regular_workspace", "json"),
                float(rw["computed_volume_m3"]),
                "m^3",
                f"box {np.round(rw['computed'], 3).tolist()} on a {rw['grid_n']}^3 grid; the index uses the "
                + ("study's doe.paper_rw_c_m box" if rw["use"] == "paper" else "computed box"),
            )
        )
    rwm = read_result(res, rel_path("regular_workspace"))
    if rwm is not None and "wrench_feasible_m3" in rwm:
        for r in rwm.itertuples():
            rows.append(
                headline(
                    f"DOE test {int(r.test)} wrench-feasible workspace",
                    rel_path("regular_workspace"),
                    float(r.wrench_feasible_m3),
                    "m^3",
                    f"{r.kind}, h = {r.h_m * 1e3:g} mm, r_p = {r.r_p_m * 1e3:g} mm; RW_max {r.volume_m3:.4g} m^3",
                )
            )
    d = read_result(res, rel_path("doe"))
    if d is not None:
        for col, unit, scale, what in (("index_m", "mm", 1e3, "I"), ("index_phi_rad", "mrad", 1e3, "I_φ")):
            if col not in d:
                continue
            lo, hi = d[col].idxmin(), d[col].idxmax()
            rows.append(
                headline(
                    f"DOE lowest {what}",
                    rel_path("doe"),
                    float(d[col][lo]) * scale,
                    unit,
                    f"test {int(d.test[lo])} ({d.kind[lo]}, h = {d.h_m[lo] * 1e3:g} mm, r_p = {d.r_p_m[lo] * 1e3:g} mm)",
                )
            )
            rows.append(
                headline(
                    f"DOE highest {what}",
                    rel_path("doe"),
                    float(d[col][hi]) * scale,
                    unit,
                    f"test {int(d.test[hi])}",
                )
            )
            e = _effects(res, col)
            if e is not None and len(e):
                top = e.effect.abs().idxmax()
                rows.append(
                    headline(
                        f"DOE largest effect on {what}",
                        rel_path("doe", "effects"),
                        float(e.effect[top]) * scale,
                        unit,
                        f"term {top}",
                    )
                )
    lines = read_result(res, rel_path("maps", "lines"))
    if lines is not None:
        for r in lines.itertuples():
            rows.append(
                headline(
                    f"line D_{r.kind}: optimal index",
                    rel_path("maps", "lines"),
                    float(r.index_opt_m) * 1e3,
                    "mm",
                    _line_note(r),
                )
            )
    b = read_result(res, rel_path("elasticity", "bands"))
    if b is not None:
        for r in b.itertuples():
            rows.append(
                headline(
                    f"{r.design} index at E_mean",
                    rel_path("elasticity", "bands"),
                    float(r.index_mean_m) * 1e3,
                    "mm",
                    f"common-E band +{r.plus_m * 1e3:.3g} / -{r.minus_m * 1e3:.3g} mm",
                )
            )
            if "index_phi_mean_rad" in b:
                rows.append(
                    headline(
                        f"{r.design} orientation index at E_mean",
                        rel_path("elasticity", "bands"),
                        float(r.index_phi_mean_rad) * 1e3,
                        "mrad",
                        f"common-E band +{r.phi_plus_rad * 1e3:.3g} / -{r.phi_minus_rad * 1e3:.3g} mrad",
                    )
                )
    rows += _budget_rows(res)
    rows += _uq_spatial_rows(st, res)
    rows += interference_rows(st, res)
    rows += reached_rows(st, res)
    return pd.DataFrame(rows, columns=COLUMNS)


def _uq_spatial_rows(st, res):
    """The uncertainty study of a spatial robot (``uncertainty/bands.csv`` and ``sobol.csv``, written by
    ``pipeline.uq``): per design and case the per-cable-E Monte Carlo median of the global index of
    ‖δp‖ [mm] and of δφ [mrad] (linearised; the note gives the 5-95 % range and the full solves'
    median), and the largest total Sobol index of each response per parameter group and per
    parameter (the note names the three largest with their 95 % half-widths); no rows when the
    tables are absent."""
    b, t = (
        read_result(res, rel_path("uncertainty", "bands")),
        read_result(res, rel_path("uncertainty", "sobol")),
    )
    rows = []
    if b is not None and "index_phi_q50_rad" in b:
        for (design, case), g in b.groupby(["design", "case"], sort=False):
            lin, full = g[g.method == "linearised"].iloc[0], g[g.method == "full"].iloc[0]
            for what, col, unit in (("‖δp‖", "index", "mm"), ("δφ", "index_phi", "mrad")):
                u = "_m" if col == "index" else "_rad"
                rows.append(
                    headline(
                        f"{design} {case} index of {what} under per-cable E (median)",
                        rel_path("uncertainty", "bands"),
                        float(lin[f"{col}_q50{u}"]) * 1e3,
                        unit,
                        f"linearised, n = {int(lin.n)}; 5-95 %: {lin[f'{col}_q05{u}'] * 1e3:.3g}-"
                        f"{lin[f'{col}_q95{u}'] * 1e3:.3g} {unit}; full solves (n = {int(full.n)}) median "
                        f"{full[f'{col}_q50{u}'] * 1e3:.3g} {unit}; nominal {lin[f'{col}_nominal{u}'] * 1e3:.3g} {unit}",
                    )
                )
    if t is not None and "index_phi" in set(t.output):
        for (design, case), g in t.groupby(["design", "case"], sort=False):
            for what, out in (("‖δp‖", "index"), ("δφ", "index_phi")):
                for level, word in (("group", "group"), ("parameter", "parameter")):
                    h = g[(g.output == out) & (g.level == level)].sort_values("ST", ascending=False)
                    if h.empty:
                        continue
                    top = ", ".join(f"{r.name} {r.ST:.2f}±{r.ST_conf:.2f}" for r in h.head(3).itertuples())
                    rows.append(
                        headline(
                            f"{design} {case} largest total Sobol index on the index of {what} ({word})",
                            rel_path("uncertainty", "sobol"),
                            float(h.ST.iloc[0]),
                            "-",
                            f"{h.name.iloc[0]}; largest ST: {top}{_sobol_basis(h)}",
                        )
                    )
    return rows


#: The error budget's entries in the summary (``cdpr.analyses.budget``), with their words.
BUDGET_TERMS = {
    "pulley": "pulley geometry alone",
    "elasticity": "elasticity alone",
    "winch": "winch exit point alone",
    "all": "all three",
}


def _budget_rows(res):
    """The study's error budget (``budget/budget.csv``, a spatial study with a ``budget`` key): per
    design the mean ‖δp‖ [mm] of the three terms alone and together, with the mean ‖δφ‖ and the
    points the means are over (ok in every entry); no rows when the table is absent. A heavy budget
    (a ``sag`` entry) adds sag alone, all four together and per design what sag adds (``_sag_row``)."""
    t = read_result(res, rel_path("study_budget"))
    if t is None:
        return []
    rows = []
    heavy = (t.entry == "sag").any()
    terms = {**BUDGET_TERMS, "sag": "cable sag alone", "all": "all four"} if heavy else BUDGET_TERMS
    for r in t[t.entry.isin(list(terms))].itertuples():
        rows.append(
            headline(
                f"{r.design} budget: {terms[r.entry]}",
                rel_path("study_budget"),
                float(r.mean_m) * 1e3,
                "mm",
                f"mean ‖δφ‖ {r.mean_rad * 1e3:.3g} mrad; over the {int(r.ok_points)} of {int(r.points)} RW_C points "
                f"ok in every entry ({int(r.entry_ok_points)} ok in this one)",
            )
        )
    if heavy:
        rows += [_sag_row(t[t.design == d]) for d in dict.fromkeys(t.design)]
    return rows


def _sag_row(t):
    """What sag adds over RW_C (a heavy budget, ``analyses.budget``'s ``neglected_sag``: the robot
    with heavy cables commanded with the massless compensated lengths): mean, 95 % and max of ‖δp‖
    [mm] and ‖δφ‖ [mrad], and what the heavy compensation leaves (``compensated_all``)."""
    e = t.set_index("entry")
    r, c = e.loc["neglected_sag"], e.loc["compensated_all"]
    return headline(
        f"{r.design} budget: what cable sag adds (massless compensated lengths)",
        rel_path("study_budget"),
        float(r.mean_m) * 1e3,
        "mm",
        f"over RW_C ‖δp‖ mean {r.mean_m * 1e3:.3g}, 95 % {r.p95_m * 1e3:.3g}, max {r.max_m * 1e3:.3g} mm; "
        f"‖δφ‖ mean {r.mean_rad * 1e3:.3g}, 95 % {r.p95_rad * 1e3:.3g}, max {r.max_rad * 1e3:.3g} mrad; "
        f"compensating with the heavy model leaves at most {c.max_m * 1e3:.2g} mm, {c.max_rad * 1e3:.2g} mrad "
        f"(over the {int(r.ok_points)} of {int(r.points)} points ok in every entry)",
    )


def _fmt(v):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return ""
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def write_summary(st, res, out_md, out_csv):
    """Write the summary table (CSV) and its Markdown page. A results folder that does not exist or
    lacks a table the summary reads (``Layout.summary_inputs``) is refused with a CdprError naming
    what is missing, rather than summarised from what happens to be there."""
    check_complete(res, Layout(st, res).summary_inputs(), "the summary")
    spatial = bool(spatial_robots(st))
    # a study of spatial robots: the papers' quantities are about CDPR3 and CDPR4; its headline numbers
    df = headline_rows(st, res) if spatial else build_rows(st, res)
    table_io.write_table(df, out_csv)
    counts = df.verdict.str.split(" \\(").str[0].value_counts().to_dict()
    scored = bool(st.get("paper_comparison"))
    lines = [
        f"# Summary of study `{st['name']}`"
        + (": the papers' numbers beside ours" if scored else ": our numbers"),
        "",
        f"Study file `{st.path}`; dead length d = {st['dead_length_m']} m; solver {st['solver']}; "
        f"redundancy {st.options.redundancy}; "
        f"global index over N = {st['doe']['index_n']}^3 = {st['doe']['index_n'] ** 3:,} cell-centred points (paper: 250,000); "
        f"h-r_p maps with {st['maps']['index_n']}^3 = {st['maps']['index_n'] ** 3:,} points per cell.",
        "",
        (
            "Verdicts: "
            + ", ".join(f"{k}: {v}" for k, v in counts.items())
            + ". The paper's values are targets; nothing is tuned to them."
        )
        if scored
        else (
            "A study of spatial robots (6-DoF platform at the orientation rotvec_rad = "
            f"{st.get('rotvec_rad', [0.0, 0.0, 0.0])} rad, physical mode): its headline numbers, no paper values."
            if spatial
            else "This study is not the paper's (`paper_comparison: false`), so its numbers are not scored against the paper's."
        ),
        "",
        *([caveat, ""] if (caveat := sobol_caveat(st, res)) else []),
        *summary_table(df),
    ]
    io.write_text("\n".join(lines) + "\n", out_md)


def summary_table(df):
    """The Markdown table of the summary's rows ``df`` (columns quantity, source, paper, ours, unit,
    tolerance, verdict, note): a header and one row each, every cell escaped (``io.md_row``: a
    quantity such as ``||dp||`` keeps the row's 8 columns).

    Parameters
    ----------
    df : pandas.DataFrame
        The summary's rows (``build_rows`` or ``headline_rows``).

    Returns
    -------
    list of str
        The table's lines.
    """
    lines = [
        "| quantity | source | paper | ours | unit | tolerance | verdict | note |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in df.itertuples():
        cells = [
            r.quantity,
            r.source,
            _fmt(r.paper),
            _fmt(r.ours),
            r.unit,
            _fmt(r.tolerance),
            r.verdict,
            r.note,
        ]
        lines.append(io.md_row(cells))
    return lines
