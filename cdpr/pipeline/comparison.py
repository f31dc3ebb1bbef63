"""Paper rule versus physics: the paper's conclusions in both redundancy modes, with a verdict each.

A comparison file (``config/comparisons/*.yaml``, schema ``comparison.schema.yaml``) names a study
run twice, in paper mode (Paty 2021's rule: the best admissible 3-cable subset) and in physical
mode (``equilibrium``: the platform settles where all cables balance, each free to go slack), the
two study files differing only in ``name`` and ``redundancy``. ``conclusions`` reads both results
folders and returns one row per number behind each of the paper's conclusions, with both values,
the paper's printed value where there is one, a tolerance and a verdict (``verdict``):

* ``reverses``: the row's statement (e.g. "DR gives a smaller plane error than SR") is true in one
  mode and false in the other;
* ``changes``: the statement keeps its truth value (or the row has none) but the value moves by
  more than the tolerance, or a categorical value (a test number, a term) differs;
* ``holds``: same truth value, and the value moves by at most the tolerance (same category);
* ``undetermined``: a value is missing in a mode (e.g. no interior valley point on a coarse map).

Tolerances are those ``cdpr/data/paper_values.yaml`` uses to call the paper's printed number
reproduced (the precision the paper states it with), else ``DEFAULT_REL`` of the paper-mode value.

The page (``write_page``) gives the headline table (one statement per conclusion), every row, the
difference maps ‖δp‖_physical - ‖δp‖_paper on the plane (``difference_table``) and the error budget
(``budget``) with one sentence per design.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from cdpr import io, table_io
from cdpr.analyses import scans
from cdpr.errors import ConfigError
from cdpr.pipeline.results import rel_path
from cdpr.pipeline.study import load_study, redundancy
from cdpr.pipeline.summary import paper_values
from cdpr.validation import read_yaml, validate

#: Tolerance of a row without a paper value: this fraction of the paper-mode value.
DEFAULT_REL = 0.10
#: Tolerance of the plane extremes [mm] (cdpr/data/paper_values.yaml's for most printed ones).
PLANE_TOL_MM = 10.0
VERDICTS = ("holds", "changes", "reverses", "undetermined")
COLUMNS = [
    "group",
    "quantity",
    "statement",
    "unit",
    "paper_mode",
    "physical",
    "printed",
    "tolerance",
    "claim_paper_mode",
    "claim_physical",
    "verdict",
    "headline",
    "note",
]


class Comparison(dict):
    """A validated comparison file: its keys, plus ``path`` and the two loaded studies
    (``paper_study``, ``physical_study``)."""

    path: str = "<dict>"


def load_comparison(path):
    """Read and validate a comparison file: the schema, both study files, their modes, and that they
    differ only in ``name`` and ``redundancy`` (and ``uncertainty.redundancy``: each study's uncertainty
    runs in its own mode). Raises ConfigError naming the file and the key."""
    data = read_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(path, None, f"expected a mapping of comparison keys, got {type(data).__name__}")
    validate(data, "comparison", path)
    cmp = Comparison(data)
    cmp.path = str(path)
    studies = {}
    for mode in ("paper", "physical"):
        try:
            studies[mode] = load_study(data[mode]["study"])
        except ConfigError as exc:
            raise ConfigError(path, f"{mode}.study", f"the study is invalid: {exc}") from None
        if redundancy(studies[mode]) != mode:
            raise ConfigError(
                path,
                f"{mode}.study",
                f"expected a study with redundancy: {mode}, got {redundancy(studies[mode])!r}",
            )
    a, b = studies["paper"], studies["physical"]
    ua, ub = ({k: v for k, v in (s.get("uncertainty") or {}).items() if k != "redundancy"} for s in (a, b))
    differ = sorted(
        k for k in set(a) | set(b) if k not in ("name", "redundancy", "uncertainty") and a.get(k) != b.get(k)
    ) + (["uncertainty"] if ua != ub else [])
    if differ:
        raise ConfigError(
            path,
            "physical.study",
            "the two studies must differ only in name and redundancy (and uncertainty.redundancy);"
            f" they differ in {', '.join(differ)}",
        )
    cmp.paper_study, cmp.physical_study = a, b
    return cmp


# ------------------------------------------------------------------------------------------------
# Verdicts
# ------------------------------------------------------------------------------------------------
def is_missing(v):
    """True for a value a verdict cannot use: None or a non-finite float."""
    return v is None or (isinstance(v, float) and not math.isfinite(v))


def verdict(paper_mode, physical, tolerance=None, claim=None):
    """Verdict of one row (module docstring).

    Parameters
    ----------
    paper_mode, physical : float or str
        The row's value in each mode (a string is categorical: equal or not).
    tolerance : float, optional
        Largest |physical - paper_mode| that still ``holds`` (numbers only).
    claim : (bool, bool), optional
        Truth of the row's statement in paper mode and in physical mode.

    Returns
    -------
    str, one of ``VERDICTS``.
    """
    if is_missing(paper_mode) or is_missing(physical):
        return "undetermined"
    if claim is not None and bool(claim[0]) != bool(claim[1]):
        return "reverses"
    if isinstance(paper_mode, str) or isinstance(physical, str):
        return "holds" if str(paper_mode) == str(physical) else "changes"
    return "holds" if abs(float(physical) - float(paper_mode)) <= tolerance else "changes"


# ------------------------------------------------------------------------------------------------
# Numbers from a results folder
# ------------------------------------------------------------------------------------------------


def _read(res, rel):
    p = Path(res) / rel
    return table_io.read_table(p) if p.exists() else None


def printed_values():
    """The paper's printed numbers by quantity (``cdpr/data/paper_values.yaml``) in SI units: quantity ->
    (value, tolerance); values in mm are converted to m."""
    out = {}
    for v in paper_values():
        scale = 1e-3 if v["unit"] == "mm" else 1.0
        val = None if v["value"] is None else v["value"] * scale
        out[v["quantity"]] = (val, v["tolerance"] * scale)
    return out


def first_designs(st):
    """The study's first pulley design of each kind: kind -> design key (e.g. {'SR': 'SR', 'DR': 'DR'})."""
    out = {}
    for key, spec in st["pulleys"].items():
        out.setdefault(spec["kind"], key)
    return out


def plane_extremes(res, robot, pulley):
    """(min, max) ‖δp‖ [m] over the ok points of a plane table, NaN when absent."""
    df = _read(res, rel_path("plane_table", robot=robot, pulley=pulley))
    return (np.nan, np.nan) if df is None else scans.ok_extremes(df)


def regular_volume(res, robot, pulley, limit):
    """R_V [m^3] of ``robot`` with ``pulley`` at the pose-error limit ``limit`` [m] in the results
    folder ``res`` (``volumes`` table), NaN when absent."""
    v = _read(res, rel_path("volumes"))
    if v is None:
        return np.nan
    r = v[(v.robot == robot) & (v.pulley == pulley) & np.isclose(v.limit_m, limit)]
    return float(r.R_V.iloc[0]) if len(r) else np.nan


def doe_tables(res):
    """(DOE table, effects indexed by term without the mean) of the results folder ``res``; None
    for a table that is absent."""
    d = _read(res, rel_path("doe"))
    e = _read(res, rel_path("doe", "effects"))
    return d, (None if e is None else e[e.term != "mean"].set_index("term"))


def line_value(res, kind, col):
    """Column ``col`` of the optimal line of pulley ``kind`` (``maps/lines``) in ``res``, NaN when absent."""
    li = _read(res, rel_path("maps", "lines"))
    r = None if li is None else li[li.kind == kind]
    return np.nan if r is None or r.empty else float(r[col].iloc[0])


def band_value(res, design, col):
    """Column ``col`` of ``design``'s Young's-modulus band (``elasticity/bands``) in ``res``, NaN when absent."""
    b = _read(res, rel_path("elasticity", "bands"))
    r = None if b is None else b[b.design == design]
    return np.nan if r is None or r.empty else float(r[col].iloc[0])


def _crossing(res, design, near):
    c = _read(res, rel_path("elasticity", "crossings"))
    s = [] if c is None else c[c.design == design].s_m.tolist()
    if not s:
        return np.nan
    return float(min(s, key=lambda x: abs(x - near))) if near is not None else float(s[0])


# ------------------------------------------------------------------------------------------------
# The conclusions
# ------------------------------------------------------------------------------------------------
def conclusions(st, paper_res, physical_res):
    """Every row behind the paper's conclusions, in both modes (module docstring).

    Parameters
    ----------
    st : Study
        The study (either mode's file: they differ only in name and redundancy).
    paper_res, physical_res : path
        Results folders of the paper-mode and physical-mode runs.

    Returns
    -------
    DataFrame with ``COLUMNS``: values in the row's unit (mm for errors and indices, m for path
    positions, '-' for ratios and counts), the paper's printed value where there is one.
    """
    printed = printed_values()
    rows = []
    res = {"paper": paper_res, "physical": physical_res}

    def add(group, quantity, statement, unit, a, b, tol=None, claim=None, pq=None, headline=False, note=""):
        pv, ptol = printed.get(pq, (None, None)) if pq else (None, None)
        scale = 1e3 if unit == "mm" else 1.0
        if tol is None:
            tol = ptol * scale if ptol is not None else None
        if tol is None and not isinstance(a, str) and not is_missing(a):
            tol = DEFAULT_REL * abs(a)
        rows.append(
            {
                "group": group,
                "quantity": quantity,
                "statement": statement,
                "unit": unit,
                "paper_mode": a,
                "physical": b,
                "printed": None if pv is None else pv * scale,
                "tolerance": tol,
                "claim_paper_mode": None if claim is None else bool(claim[0]),
                "claim_physical": None if claim is None else bool(claim[1]),
                "verdict": verdict(a, b, tol, claim),
                "headline": headline,
                "note": note,
            }
        )

    kinds = first_designs(st)
    pair = "SR" in kinds and "DR" in kinds
    # -- plane z (section 3.3.2, Fig. 12)
    z = st["plane"]["z_m"]
    ext = {
        (m, rk, pk): plane_extremes(res[m], rk, pk)
        for m in res
        for rk in st["robots"]
        for pk in st["pulleys"]
    }
    for rk in st["robots"]:
        for pk in st["pulleys"]:
            for i, stat in enumerate(("min", "max")):
                a, b = ext["paper", rk, pk][i] * 1e3, ext["physical", rk, pk][i] * 1e3
                add(
                    "plane",
                    f"{rk}_{pk} plane {stat} ‖δp‖",
                    f"iso-contour extreme at z = {z:g} m",
                    "mm",
                    a,
                    b,
                    tol=None if f"{rk}_{pk} plane {stat}" in printed else PLANE_TOL_MM,
                    pq=f"{rk}_{pk} plane {stat}",
                )
        if pair:
            r = [ext[m, rk, kinds["DR"]][1] / ext[m, rk, kinds["SR"]][1] for m in res]
            add(
                "plane",
                f"{rk} plane max ‖δp‖ DR / SR",
                f"DR pulleys give smaller errors than SR on the plane z = {z:g} m ({rk}, largest ‖δp‖)",
                "-",
                r[0],
                r[1],
                tol=0.1,
                claim=(r[0] < 1, r[1] < 1),
                headline=True,
            )
    # -- error-limited volumes (section 3.3.3, Fig. 13)
    for lim in st["volumes"]["limits_m"]:
        for rk in st["robots"]:
            for pk in st["pulleys"]:
                add(
                    "volumes",
                    f"{rk}_{pk} R_V at {lim:g} m",
                    f"share of the frame with ‖δp‖ <= {lim:g} m",
                    "-",
                    regular_volume(paper_res, rk, pk, lim),
                    regular_volume(physical_res, rk, pk, lim),
                    tol=0.05,
                    pq=f"{rk}_{pk} R_V at {lim:g} m",
                )
            if pair:
                d = [
                    regular_volume(res[m], rk, kinds["DR"], lim)
                    - regular_volume(res[m], rk, kinds["SR"], lim)
                    for m in res
                ]
                add(
                    "volumes",
                    f"{rk} R_V(DR) - R_V(SR) at {lim:g} m",
                    f"DR pulleys give a larger error-limited volume than SR ({rk}, limit {lim:g} m)",
                    "-",
                    d[0],
                    d[1],
                    tol=0.05,
                    claim=(d[0] > 0, d[1] > 0),
                    headline=True,
                )
    # -- DOE (section 4.2, Fig. 15-16)
    doe_ = {m: doe_tables(res[m]) for m in res}
    if all(d is not None for d, _ in doe_.values()):
        rank = {m: " < ".join(str(t) for t in d.sort_values("index_m").test) for m, (d, _) in doe_.items()}
        add(
            "doe",
            "DOE ranking (best first)",
            "order of the 8 tests by global index",
            "-",
            rank["paper"],
            rank["physical"],
        )
        best = {m: int(d.loc[d.index_m.idxmin(), "test"]) for m, (d, _) in doe_.items()}
        worst = {m: int(d.loc[d.index_m.idxmax(), "test"]) for m, (d, _) in doe_.items()}
        add(
            "doe",
            "DOE best and worst tests",
            "test 1 (SR, small h, small r_p) is the best design and test 7 (DR, large h, small r_p) the worst",
            "-",
            f"best {best['paper']}, worst {worst['paper']}",
            f"best {best['physical']}, worst {worst['physical']}",
            claim=tuple(best[m] == 1 and worst[m] == 7 for m in res),
            headline=True,
        )
        for stat, pq in (("min", "DOE minimum (test 1)"), ("max", "DOE maximum (test 7)")):
            v = [getattr(d.index_m, stat)() * 1e3 for d, _ in doe_.values()]
            add("doe", f"DOE {stat} index", f"global index of the {stat}imal test", "mm", v[0], v[1], pq=pq)
        eff = {m: e for m, (_, e) in doe_.items()}
        top = {m: str(e.effect.abs().idxmax()) for m, e in eff.items()}
        add(
            "doe",
            "largest DOE effect",
            "the joint × r_p interaction is the largest effect on the index (Fig. 16)",
            "-",
            top["paper"],
            top["physical"],
            claim=tuple(top[m] == "joint:r_p" for m in res),
            headline=True,
        )
        for term in eff["paper"].index:
            a, b = (float(eff[m].effect.get(term, np.nan)) * 1e3 for m in res)
            add(
                "doe",
                f"effect {term}",
                f"effect of {term} on the index (sign kept)",
                "mm",
                a,
                b,
                claim=(a > 0, b > 0),
            )
    # -- optimal lines and designs (section 4.3, Fig. 17, Table 3)
    slopes = {}
    for kind, pq in (("SR", "D_SR slope h/r_p"), ("DR", "D_DR slope h/r_p")):
        slopes[kind] = [line_value(res[m], kind, "slope_k") for m in res]
        add(
            "maps",
            f"D_{kind} slope h / r_p",
            f"the optimal line D_{kind}: h = k r_p (paper: {'40/13' if kind == 'SR' else '5/4'})",
            "-",
            *slopes[kind],
            pq=pq,
            headline=True,
        )
        for col, what, unit, scale, q in (
            ("h_opt_m", "h", "mm", 1e3, f"I_{kind} h"),
            ("r_p_opt_m", "r_p", "mm", 1e3, f"I_{kind} r_p"),
            ("index_opt_m", "index", "mm", 1e3, f"index at our I_{kind}"),
        ):
            a, b = (line_value(res[m], kind, col) * scale for m in res)
            add(
                "maps",
                f"I_{kind} {what}",
                f"the optimal design I_{kind} (Table 3): {what}",
                unit,
                a,
                b,
                pq=q,
                headline=what != "index",
            )
    if pair:
        k = slopes
        add(
            "maps",
            "slope D_SR - slope D_DR",
            "D_SR is steeper than D_DR",
            "-",
            k["SR"][0] - k["DR"][0],
            k["SR"][1] - k["DR"][1],
            claim=(k["SR"][0] > k["DR"][0], k["SR"][1] > k["DR"][1]),
        )
        ix = [
            (line_value(res[m], "DR", "index_opt_m") - line_value(res[m], "SR", "index_opt_m")) * 1e3
            for m in res
        ]
        add(
            "maps",
            "index at I_DR - index at I_SR",
            "DR pulleys beat SR: the optimal DR design has the smaller global index (Table 3)",
            "mm",
            ix[0],
            ix[1],
            claim=(ix[0] < 0, ix[1] < 0),
            headline=True,
        )
    # -- Young's modulus (section 5, Fig. 18-19)
    opt = list(st["optimal"])
    totals = {}
    for dk in opt:
        kind = st["optimal"][dk]["kind"]
        star = f"{kind}*"
        totals[dk] = [band_value(res[m], dk, "total_m") * 1e3 for m in res]
        add(
            "elasticity",
            f"{dk} E band total",
            f"spread of {star}'s index over E = {st['elasticity']['E_Pa']['from'] / 1e9:g}"
            f"-{st['elasticity']['E_Pa']['to'] / 1e9:g} GPa",
            "mm",
            *totals[dk],
            pq=f"{star} band total",
            headline=True,
        )
        for col in ("minus_m", "plus_m"):
            a, b = (band_value(res[m], dk, col) * 1e3 for m in res)
            add(
                "elasticity",
                f"{dk} E band {col[:-2]}",
                f"{star}'s band {col[:-2]}",
                "mm",
                a,
                b,
                pq=f"{star} band {col[:-2]}",
            )
        pq = f"{star} E_max/E_min crossing"
        near = printed.get(pq, (None, None))[0]
        a, b = (_crossing(res[m], dk, near) for m in res)
        add(
            "elasticity",
            f"{dk} E_max/E_min crossing",
            f"where {star}'s ‖δp‖ curves at E_max and E_min cross on the section 5.2 path (Fig. 19)",
            "m",
            a,
            b,
            pq=pq,
            headline=True,
        )
    sr = [dk for dk in opt if st["optimal"][dk]["kind"] == "SR"]
    dr = [dk for dk in opt if st["optimal"][dk]["kind"] == "DR"]
    if sr and dr:
        r = [totals[sr[0]][i] / totals[dr[0]][i] for i in range(2)]
        add(
            "elasticity",
            "E band total SR* / DR*",
            "SR* is more robust to E than DR* (smaller band of the index over E)",
            "-",
            r[0],
            r[1],
            tol=0.1,
            claim=(r[0] < 1, r[1] < 1),
            headline=True,
        )
    # -- per-cable moduli (beyond the paper: results/<study>/uncertainty/bands.csv, when both ran it)
    uq = {m: _uq_bands(res[m]) for m in res}
    if all(u is not None for u in uq.values()):
        designs = [d for d in dict.fromkeys(uq["paper"].design) if d in set(uq["physical"].design)]
        spread = {m: {d: _uq_spread(uq[m], d, "uncompensated") for d in designs} for m in res}
        for d in designs:
            add(
                "uncertainty",
                f"{d} index 5-95 % spread, per-cable E",
                "spread of the global index when each cable has its own modulus (linearised Monte Carlo)",
                "mm",
                spread["paper"][d] * 1e3,
                spread["physical"][d] * 1e3,
            )
        sr = [d for d in designs if d.upper().startswith("SR")]
        dr = [d for d in designs if d.upper().startswith("DR")]
        if sr and dr:
            r = [spread[m][sr[0]] / spread[m][dr[0]] for m in res]
            add(
                "uncertainty",
                f"{sr[0]} / {dr[0]} index spread under per-cable E",
                f"{sr[0]} is more robust than {dr[0]} to per-cable moduli (narrower 5-95 % band of the index)",
                "-",
                r[0],
                r[1],
                tol=0.1,
                claim=(r[0] < 1, r[1] < 1),
                headline=True,
                note="uncompensated robot, each study's uncertainty.redundancy",
            )
        # The compensated robot is physical in both studies: only the physical study writes it
        # (study.uq_cases), so these rows have no paper-mode value; their question is whether
        # compensation keeps the uncompensated conclusions, read from the physical column.
        once = "compensated robot: physical in both studies, computed once (the physical study)"
        for d in designs:
            add(
                "uncertainty",
                f"{d} index median after compensation, per-cable E",
                "what compensating the nominal robot's lengths leaves under per-cable moduli",
                "mm",
                _uq_value(uq["paper"], d, "compensated", "index_q50_m") * 1e3,
                _uq_value(uq["physical"], d, "compensated", "index_q50_m") * 1e3,
                note=once,
            )
        if sr and dr:
            ratio = {
                case: _uq_spread(uq["physical"], sr[0], case) / _uq_spread(uq["physical"], dr[0], case)
                for case in ("uncompensated", "compensated")
            }
            holds = {case: bool(r < 1) for case, r in ratio.items()}
            add(
                "uncertainty",
                f"{sr[0]} / {dr[0]} index spread under per-cable E, compensated",
                f"{sr[0]} stays more robust than {dr[0]} to per-cable moduli after compensation",
                "-",
                _uq_spread(uq["paper"], sr[0], "compensated") / _uq_spread(uq["paper"], dr[0], "compensated"),
                ratio["compensated"],
                tol=0.1,
                headline=True,
                note=f"{once}; physically: {'yes' if holds['compensated'] else 'no'} after compensation,"
                f" {'yes' if holds['uncompensated'] else 'no'} before",
            )
    return pd.DataFrame(rows, columns=COLUMNS)


def _uq_bands(res):
    """The uncertainty bands table of a results folder, or None without it."""
    p = Path(res) / "uncertainty" / "bands.csv"
    return table_io.read_table(p) if p.exists() else None


def _uq_value(tab, design, case, column, method="linearised"):
    g = tab[(tab.design == design) & (tab.case == case) & (tab.method == method)]
    return float(g[column].iloc[0]) if len(g) else float("nan")


def _uq_spread(tab, design, case):
    """5-95 % spread [m] of the global index under per-cable moduli (linearised samples)."""
    return _uq_value(tab, design, case, "index_q95_m") - _uq_value(tab, design, case, "index_q05_m")


def difference_table(paper_res, physical_res, robot, pulley):
    """‖δp‖_physical - ‖δp‖_paper [m] on the plane of one design, per point (x, y), NaN where either
    mode is not ok; also both statuses. Returns a DataFrame x, y, dp_paper, dp_physical, diff,
    status_paper, status_physical."""
    a = table_io.read_table(Path(paper_res) / rel_path("plane_table", robot=robot, pulley=pulley))
    b = table_io.read_table(Path(physical_res) / rel_path("plane_table", robot=robot, pulley=pulley))
    if len(a) != len(b) or not (np.allclose(a.x, b.x) and np.allclose(a.y, b.y)):
        raise ValueError(f"plane tables of {robot}_{pulley} are not on the same grid")
    ok = (a.status == "ok").to_numpy() & (b.status == "ok").to_numpy()
    return pd.DataFrame(
        {
            "x": a.x,
            "y": a.y,
            "dp_paper": a.dp,
            "dp_physical": b.dp,
            "diff": np.where(ok, b.dp - a.dp, np.nan),
            "status_paper": a.status.astype(str),
            "status_physical": b.status.astype(str),
        }
    )


def difference_stats(tables):
    """One row per design of ``difference_table`` results: points ok in both modes, the min, mean
    and max of the difference [m], and the points ok in one mode only (e.g. where the paper's rule
    finds no admissible subset but the platform hangs on the cables that stay taut)."""
    rows = []
    for label, t in tables.items():
        d = t["diff"].dropna()
        a, b = t.status_paper == "ok", t.status_physical == "ok"
        rows.append(
            {
                "design": label,
                "ok_both": int(len(d)),
                "diff_min_m": float(d.min()) if len(d) else np.nan,
                "diff_mean_m": float(d.mean()) if len(d) else np.nan,
                "diff_max_m": float(d.max()) if len(d) else np.nan,
                "ok_paper_only": int((a & ~b).sum()),
                "ok_physical_only": int((~a & b).sum()),
            }
        )
    return pd.DataFrame(rows)


# ------------------------------------------------------------------------------------------------
# The page
# ------------------------------------------------------------------------------------------------
def _fmt(v, unit=""):
    if isinstance(v, str):  # a number read back from the CSV (mixed columns are text there)
        try:
            v = float(v)
        except ValueError:
            return v
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, str):
        return v
    return f"{v:.4g}"


def _md_table(df, cols, headers):
    lines = [io.md_row(headers), "|" + "---|" * len(headers)]
    for r in df.itertuples():
        lines.append(io.md_row(_fmt(getattr(r, c)) for c in cols))
    return lines


def headline_table(rows):
    """The headline rows of ``conclusions`` (one statement per conclusion) as Markdown lines."""
    h = rows[rows.headline.astype(bool)].copy()
    for col in ("paper_mode", "physical"):
        h[f"{col}_u"] = [
            _fmt(v) + ("" if u == "-" or _fmt(v) == "–" else f" {u}") for v, u in zip(h[col], h.unit)
        ]
    return _md_table(
        h,
        ["statement", "quantity", "paper_mode_u", "physical_u", "verdict"],
        ["conclusion of the paper", "quantity", "paper rule", "physical", "verdict"],
    )


def write_page(cmp, rows, diff_stats, budget_table, sentences, figures, out_md):
    """The comparison page: headline table, every row, difference maps, error budget.

    Parameters
    ----------
    cmp : Comparison
    rows : DataFrame of ``conclusions``
    diff_stats : DataFrame of ``difference_stats``
    budget_table : DataFrame (design, region, entry, mean_m, ...) or None
    sentences : list of str, one per design
    figures : dict name -> path of a figure (written relative to the page)
    out_md : path
    """
    page = Path(out_md)
    rel = {k: Path(v).resolve().relative_to(page.resolve().parent).as_posix() for k, v in figures.items()}
    counts = rows.verdict.value_counts().to_dict()
    st = cmp.paper_study
    lines = [
        "# Does the paper survive physics? Paper rule versus physical equilibrium",
        "",
        f"Study `{st.path}` run twice: with Paty et al. 2021's rule (each 4-cable point held by its best "
        f"admissible 3-cable subset; results `{cmp['paper']['results']}`) and in physical mode (the platform "
        f"settles where the forces of all cables balance, each free to go slack; commanded rest lengths "
        f"L_TS as in the paper; results `{cmp['physical']['results']}`). Comparison file `{cmp.path}`.",
        "",
        "Verdicts (computed by `cdpr.pipeline.comparison.verdict`): **reverses** = the statement is true in one mode "
        "and false in the other; **changes** = same truth value but the number moves by more than the "
        "tolerance (the one `cdpr/data/paper_values.yaml` uses to call the paper's printed value reproduced, "
        f"else {DEFAULT_REL:.0%} of the paper-mode value), or a categorical value differs; **holds** = "
        "within the tolerance. Rows: " + ", ".join(f"{k} {v}" for k, v in counts.items()) + ".",
        "",
        "## Headline: the paper's conclusions under physics",
        "",
        *headline_table(rows),
        "",
        "## Every number",
        "",
        *_md_table(
            rows,
            ["group", "quantity", "unit", "paper_mode", "physical", "printed", "tolerance", "verdict"],
            ["group", "quantity", "unit", "paper rule", "physical", "paper printed", "tolerance", "verdict"],
        ),
        "",
        f"## Difference maps ‖δp‖_physical − ‖δp‖_paper at z = {st['plane']['z_m']:g} m",
        "",
        f"![difference maps]({rel['difference']})",
        "",
        *(
            [
                "Fig. 10, 14, 18 and 19 of both modes over each other (solid: paper rule, dashed: physical):",
                "",
                f"![paper rule and physical overlaid]({rel['overlays']})",
                "",
            ]
            if "overlays" in rel
            else []
        ),
        *(
            [
                "‖δp‖ over the plane in both modes, one colour scale per design (Fig. 12):",
                "",
                f"![the plane in both modes]({rel['planes']})",
                "",
            ]
            if "planes" in rel
            else []
        ),
        *_md_table(
            diff_stats.assign(
                **{c: diff_stats[c] * 1e3 for c in ("diff_min_m", "diff_mean_m", "diff_max_m")}
            ),
            [
                "design",
                "ok_both",
                "diff_min_m",
                "diff_mean_m",
                "diff_max_m",
                "ok_paper_only",
                "ok_physical_only",
            ],
            [
                "design",
                "points ok in both",
                "min [mm]",
                "mean [mm]",
                "max [mm]",
                "ok only with the paper rule",
                "ok only in physics",
            ],
        ),
    ]
    if budget_table is not None:
        bt = budget_table[budget_table.region == "RW_C"]
        wide = bt.pivot(index="design", columns="entry", values="mean_m").reindex(bt.design.unique()) * 1e3
        cols = [
            c
            for c in (
                "pulley",
                "elasticity",
                "winch",
                "sag",  # heavy cables only (``budget.effects_of``), as the two sag entries below
                "interaction",
                "all",
                "compensated_pulley",
                "compensated_elasticity",
                "compensated_winch",
                "compensated_sag",
                "neglected_sag",
                "compensated_all",
            )
            if c in wide.columns
        ]
        wide = wide[cols]
        ok = bt[bt.entry == "all"].set_index("design")
        wide["ok_points"] = [f"{ok.ok_points[d]:,} of {ok.points[d]:,}" for d in wide.index]
        cols.append("ok_points")
        wide = wide.reset_index()
        lines += [
            "",
            "## Error budget: what each effect the standard model neglects costs (cdpr.analyses.budget)",
            "",
            "Mean ‖δp‖ [mm] over the RW_C grid (the points ok in every variant: for a robot whose "
            "frame does not contain RW_C, e.g. CDPR3, the part inside its workspace), the physical equilibrium "
            "of the robot with only that effect, commanded by the standard model (pulley = pulleys with "
            "rigid cables; elasticity = fixed exit points with Hooke cables; winch = fixed points, rigid "
            "cables, drum angles of the no-winch model q_nw); all = the three together; interaction = "
            "δp_all − Σ δp_k; compensated_k = all effects on, the model includes k; compensated_all = 0 "
            "by construction.",
            "",
            *_md_table(wide, ["design", *cols], ["design", *cols]),
            "",
            *[f"* {s}" for s in sentences],
            "",
            f"![budget bars]({rel['budget']})",
            "",
            f"![budget paths]({rel['budget_paths']})",
        ]
    io.write_text("\n".join(lines) + "\n", out_md)
