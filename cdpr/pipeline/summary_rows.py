"""Rows of the study summary (``cdpr.pipeline.summary``) that are counts, not comparisons with the
paper: the row constructor and the table reader the summary shares, and the rows of a rigid
platform's interference and reached equilibria (issue 39, docs/interference.md): the interfering
points each table flags or leaves out, the runs over RW_C that leave them out, and the points where
the reached equilibrium is not the lowest-energy one."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from cdpr import table_io
from cdpr.analyses.workspace import interference_free_rows
from cdpr.pipeline.results import Layout, rel_path


def read_result(res, rel):
    """The table at ``rel`` under the results folder ``res`` (``table_io.read_table``), None when
    it does not exist.

    Parameters
    ----------
    res : str or Path
        The results folder.
    rel : str
        Its path inside ``res``.

    Returns
    -------
    DataFrame or None
    """
    p = Path(res) / rel
    return table_io.read_table(p) if p.exists() else None


def headline(quantity, source, ours, unit, note=""):
    """A summary row of ``summary.COLUMNS`` with no paper value (not scored).

    Parameters
    ----------
    quantity, source : str
        What the row counts or measures, and the table it comes from.
    ours : float or int
        The value.
    unit : str
    note : str, optional

    Returns
    -------
    dict
    """
    return {
        "quantity": quantity,
        "source": source,
        "paper": None,
        "ours": ours,
        "unit": unit,
        "tolerance": None,
        "verdict": "not scored (no paper value)",
        "note": note,
    }


def point_tables(st, res):
    """The study's point tables a rigid platform's summary counts in (``interference_rows``,
    ``reached_rows``): (what, label, table) for each plane, path, volume grid (its shards joined) and
    DOE workspace grid that exists under ``res``."""
    lay = Layout(st, res)
    out = []
    for rk in st["robots"]:
        for pk in st["pulleys"]:
            df = read_result(res, rel_path("plane_table", robot=rk, pulley=pk))
            if df is not None:
                out.append(("plane", f"{rk} {pk}", df))
    for path in st["trajectories"]["paths"]:
        for pk in st["pulleys"]:
            df = read_result(res, rel_path("trajectory_table", path=path, pulley=pk))
            if df is not None:
                out.append(("path", f"{path} {pk}", df))
    for rk in st["robots"]:
        for pk in st["pulleys"]:
            shards = [p for p in lay.volume_shards(f"{rk}_{pk}") if Path(p).exists()]
            if shards:
                frame = pd.concat([table_io.read_table(p) for p in shards], ignore_index=True)
                out.append(("volume grid", f"{rk} {pk}", frame))
    for t in lay.tests():
        p = Path(lay.path("workspace_grid", "table", test=t))
        if p.exists():
            out.append(("DOE workspace grid", f"test {t}", table_io.read_table(p)))
    return out


def interference_rows(st, res):
    """The interference rows of a study of rigid platforms (issue 39, docs/interference.md): per
    plane and volume grid, and over the DOE's workspace grids (RW_max, RW_C), how many ok points
    interfere at their solved pose and so are left out of the plane's numbers, the volumes and RW_C;
    the paths' interfering ok points are counted (flagged in their tables, not left out). No rows
    when no table has the ``interference_free`` column (point masses).

    Parameters
    ----------
    st : Study
    res : str or Path
        The results folder.

    Returns
    -------
    list of dict
        Rows of ``COLUMNS``.
    """
    rows, doe = [], []
    for what, label, df in point_tables(st, res):
        if "interference_free" not in df:
            continue
        ok = (df["status"].astype(str) == "ok").to_numpy()
        bad = ok & ~interference_free_rows(df)
        cc = int((bad & (df["n_cc"].fillna(0).to_numpy() > 0)).sum())
        cp = int((bad & (df["n_cp"].fillna(0).to_numpy() > 0)).sum())
        note = f"{int(bad.sum())} of {int(ok.sum())} ok points; cable-cable at {cc}, cable-platform at {cp}"
        if what == "DOE workspace grid":
            doe.append((label, int(bad.sum()), int(ok.sum())))
            continue
        verb = "flagged" if what == "path" else "left out"
        rows.append(
            headline(f"{label} {what}: interfering points {verb}", what, int(bad.sum()), "points", note)
        )
    if doe:
        rows.append(
            headline(
                "DOE workspace grids: interfering points left out of RW_max and RW_C",
                rel_path("regular_workspace"),
                sum(b for _, b, _ in doe),
                "points",
                "; ".join(f"{lab}: {b} of {n} ok" for lab, b, n in doe),
            )
        )
    return rows + left_out_rows(res)


def left_out_rows(res):
    """The ok points a rigid platform's runs over RW_C leave out because their cables interfere at
    the solved pose (issue 39): the DOE's global indices (``doe/doe.csv``), the h-r_p maps, the
    index versus E, the dead-length sweep, the error budget and the uncertainty study (its Monte
    Carlo and Sobol grids; the note adds the sample points flagged because the sample's own robot
    interferes), each one row with the total and, in the note, where they are; none for tables
    without the ``interfering_points`` columns (point masses, or results written before them).

    Parameters
    ----------
    res : str or Path
        The results folder.

    Returns
    -------
    list of dict
        Rows of ``COLUMNS``.
    """
    rows = []
    for rule, name, what, label in (
        ("doe", "table", "DOE global index over RW_C", lambda r: f"test {int(r.test)}"),
        (
            "maps",
            "map",
            "h-r_p maps' index over RW_C",
            lambda r: f"{r.kind} h {r.h_m * 1e3:g} r_p {r.r_p_m * 1e3:g} mm",
        ),
        ("elasticity", "table", "index versus E over RW_C", lambda r: f"{r.design} E {r.E_Pa:.4g} Pa"),
    ):
        t = read_result(res, rel_path(rule, name))
        if t is None or "interfering_points" not in t:
            continue
        n = t["interfering_points"].fillna(0).astype(int)
        where = "; ".join(f"{label(r)}: {k}" for r, k in zip(t.itertuples(), n) if k)
        note = f"over {len(t)} runs; " + (where or "none in any run")
        rows.append(
            headline(
                f"{what}: interfering points left out", rel_path(rule, name), int(n.sum()), "points", note
            )
        )
    t = read_result(res, rel_path("dead_length"))
    cols = [] if t is None else [c for c in t.columns if c.startswith("interfering_points_")]
    if cols:
        per = {c.removeprefix("interfering_points_"): int(t[c].fillna(0).sum()) for c in cols}
        note = f"over {len(t)} dead lengths; " + "; ".join(f"{k}: {v}" for k, v in per.items())
        rows.append(
            headline(
                "dead-length sweep: interfering points left out",
                rel_path("dead_length"),
                sum(per.values()),
                "points",
                note,
            )
        )
    t = read_result(res, rel_path("study_budget"))
    if t is not None and "interfering_points" in t:
        per = t.drop_duplicates("design").set_index("design")["interfering_points"].astype(int)
        rows.append(
            headline(
                "error budget over RW_C: interfering points left out",
                rel_path("study_budget"),
                int(per.sum()),
                "points",
                "; ".join(f"{d}: {k} of {int(t[t.design == d].points.iloc[0])}" for d, k in per.items()),
            )
        )
    return rows + uq_left_out(res)


def uq_left_out(res):
    """``left_out_rows``'s row of the uncertainty study (``uncertainty/bands.csv``): the points its
    Monte Carlo (the linearised row's grid) and Sobol (all_parameters) grids leave out, and the
    sample points flagged (full solves)."""
    t = read_result(res, rel_path("uncertainty", "bands"))
    if t is None or "interfering_points" not in t:
        return []
    g = t[t.method.isin(["linearised", "all_parameters"])]
    n = g["interfering_points"].fillna(0).astype(int)
    grid = {"linearised": "Monte Carlo", "all_parameters": "Sobol"}
    where = "; ".join(
        f"{r.design} {r.case} {grid[r.method]}: {k} of {int(r.index_n) ** 3}"
        for r, k in zip(g.itertuples(), n)
    )
    flagged = int(t["interfering_full"].fillna(0).astype(int).sum())
    note = f"{where}; sample points where the sample's robot interferes (flagged, kept): {flagged}"
    return [
        headline(
            "uncertainty over RW_C: interfering points left out",
            rel_path("uncertainty", "bands"),
            int(n.sum()),
            "points",
            note,
        )
    ]


def reached_rows(st, res):
    """The reached-equilibrium rows of a study (issue 39): over every point table the summary counts
    in (planes, paths, volume grids, DOE workspace grids), the points where the equilibrium reached
    by continuation is not the lowest-energy one (``reached_is_global`` false) and those whose
    continuation crossed a fold (``n_folds`` > 0). The columns exist only where the restarts found
    more than one equilibrium (``solve.reach_where_multiple``); elsewhere the equilibrium is unique,
    so the reached one is the global one. No rows for a study without rigid platforms.

    Parameters
    ----------
    st : Study
    res : str or Path
        The results folder.

    Returns
    -------
    list of dict
        Rows of ``COLUMNS``.
    """
    tables = point_tables(st, res)
    if not tables or not any("interference_free" in df for _, _, df in tables):
        return []
    total = sum(len(df) for _, _, df in tables)
    continued = differ = folds = 0
    where = []
    for what, label, df in tables:
        if "reached_is_global" not in df:
            continue
        g = df["reached_is_global"].astype("boolean").fillna(True).to_numpy(dtype=bool)
        f = df["n_folds"].fillna(0).to_numpy() > 0
        if "unique" in df:
            continued += int((~df["unique"].astype("boolean").fillna(True).to_numpy(dtype=bool)).sum())
        differ += int((~g).sum())
        folds += int(f.sum())
        if (~g).any() or f.any():
            where.append(f"{label} {what}: {int((~g).sum())} / {int(f.sum())}")
    note = (
        f"of {total} points in the planes, paths, volume and workspace grids; continued at the "
        f"{continued} points where the restarts find more than one equilibrium (elsewhere it is unique)"
        + (f"; reached ≠ global / folds by table: {', '.join(where)}" if where else "")
    )
    return [
        headline(
            "points where the reached equilibrium is not the global one",
            "point tables",
            differ,
            "points",
            note,
        ),
        headline("points whose continuation crossed a fold", "point tables", folds, "points", note),
    ]
