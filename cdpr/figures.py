"""``cdpr plot KIND``: draw a figure from the table(s) a rule produced (the table stays beside it)."""
from __future__ import annotations

from .io import read_table
from . import plots


def _plot_plane(args):
    df = read_table(args.table[0])
    plots.plane_contours(df, args.title or "", args.out)


def _plot_subsets(args):
    df = read_table(args.table[0])
    plots.subset_map(df, args.title or "", args.out)


def _plot_winch(args):
    df = read_table(args.table[0])
    base = args.out
    plots.curves([(df.l_pm, df.q1, "q1 (physical root)"), (df.l_pm, df.q2, "q2"), (df.l_pm, df.q_nw, "q_nw (winch neglected)")],
                 "l_pm [m]", "q [rad]", args.title or "Winch joint angle (winch seed Fig. 7a)", base)
    plots.curves([(df.l_pm, df.dl * 1e3, "dl = k_w (q1 - q_nw)")], "l_pm [m]", "dl [mm]",
                 "Uncoiled length error (winch seed Fig. 7b)", base.replace(".png", "_dl.png"))


def _plot_trajectories(args):
    """Fig. 10 (|dp| along the paths) and Fig. 11 (its min and max per design, with a CSV table)."""
    import pandas as pd

    from . import io, study

    series, rows = [], []
    labels = args.labels or args.table
    for path, label in zip(args.table, labels):
        df = read_table(path)
        ok = df.status == "ok"
        series.append((df.s.where(ok), df.dp.where(ok), label))
        lo, hi = study.ok_extremes(df)
        last = df.s[ok].max() if ok.any() else float("nan")
        rows.append({"design": label, "dp_min_m": lo, "dp_max_m": hi, "ok_until_s_m": last, "path_length_m": float(df.s.max())})
    plots.curves(series, "position along the path s [m]", "|dp| [m]", args.title or "", args.out)
    base = args.out.replace(".png", "_minmax")
    table = pd.DataFrame(rows)
    io.write_table(table, base + ".csv")
    plots.bars(labels, None, "|dp| [m]", "Min and max of |dp| along the paths (Fig. 11)", base + ".png",
               groups=[("min", table.dp_min_m), ("max", table.dp_max_m)])


KINDS = {"plane": _plot_plane, "subsets": _plot_subsets, "winch": _plot_winch, "trajectories": _plot_trajectories}
