"""The figures of the study: one function per figure of the papers, each drawing from tables.

Every function takes the tables (DataFrames) a pipeline job wrote beside the figure, draws, and
writes a PNG and a PDF (``save``). Nothing here computes physics: the numbers drawn are the numbers
in the tables. Figure numbers are those of Paty et al. 2021 (Fig. 9-19) and Métillon et al. 2022
(Fig. 7).
"""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import json

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd
from matplotlib.colors import ListedColormap
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from matplotlib.path import Path as MPath
from scipy.spatial import ConvexHull  # noqa: E402

from cdpr.analyses.uncertainty import CASES  # noqa: E402
from cdpr.io import atomic  # noqa: E402
from cdpr.pipeline import figure_checks, summary

#: Colours of the pulley kinds and designs, used by every figure that compares them.
KIND_COLOURS = {"SR": "tab:blue", "DR": "tab:orange", "fixed": "tab:gray"}
#: Colour of the cells that are not ``ok`` in the maps.
NOT_OK_COLOUR = "0.85"


def audit(fig, out=None):
    """The layout audit of ``fig``: the problems ``figure_checks`` finds (overlapping texts, texts
    off the canvas, axes without a unit) and the titles (for the mode); written to
    ``<out>.layout.json`` when ``out`` is given. Auditing draws the figure, then hides the contour
    labels that collide (``_drop_colliding_contour_labels``)."""

    fig.canvas.draw()
    _drop_colliding_contour_labels(fig)
    rec = {"problems": figure_checks.layout_problems(fig, draw=False), "titles": figure_checks.titles(fig)}
    if out is not None:
        atomic(
            Path(str(out) + ".layout.json"),
            lambda tmp: Path(tmp).write_text(json.dumps(rec, indent=1, ensure_ascii=False), encoding="utf-8"),
        )
    return rec


def _drop_colliding_contour_labels(fig):
    """Hide every contour label (``clabel``) that would overlap a text drawn before it: the other
    texts first (titles, tick and anchor labels), then the contour labels in the order they were
    placed. matplotlib places contour labels without looking at each other; where a field's levels
    crowd (a steep rim near the frame's edge) their labels pile up. Figures whose labels do not
    collide are untouched. ``fig`` must have been drawn (``audit`` draws it once: a second draw would
    move a constrained layout by a pixel)."""
    labels = [t for ax in fig.axes for c in ax.collections if hasattr(c, "labelTexts") for t in c.labelTexts]
    if not labels:
        return
    renderer = fig.canvas.get_renderer()
    ids = {id(t) for t in labels}
    kept = [
        figure_checks.text_extent(t, renderer) for t in figure_checks.visible_texts(fig) if id(t) not in ids
    ]
    slack = figure_checks.SLACK_PX
    for t in labels:
        if not t.get_visible():
            continue
        bb = t.get_window_extent(renderer)
        if any(
            min(bb.x1, k.x1) - max(bb.x0, k.x0) > slack and min(bb.y1, k.y1) - max(bb.y0, k.y0) > slack
            for k in kept
        ):
            t.set_visible(False)
        else:
            kept.append(bb)


def save(fig, out):
    """Write ``out`` (.png) and its .pdf sibling atomically; returns both paths. The PDF carries no
    creation date, so the same table gives the same bytes. Every figure is audited (``audit``)
    before it is written, so that the pixels do not depend on whether the audit is kept: drawing
    the figure for the audit moves a constrained layout by a pixel. With the environment variable
    ``CDPR_FIGURE_AUDIT`` set, the audit is written beside the figure."""
    out = Path(out)
    audit(fig, out if os.environ.get("CDPR_FIGURE_AUDIT") else None)
    paths = [out, out.with_suffix(".pdf")]
    meta = {".png": None, ".pdf": {"CreationDate": None}}
    for p in paths:
        atomic(
            p,
            lambda tmp, p=p: fig.savefig(
                tmp, format=p.suffix[1:], dpi=150, bbox_inches="tight", metadata=meta[p.suffix]
            ),
        )
    plt.close(fig)
    return paths


def _grid(df, value):
    xs, ys = np.sort(df.x.unique()), np.sort(df.y.unique())
    Z = np.full((len(ys), len(xs)), np.nan)
    ix, iy = np.searchsorted(xs, df.x), np.searchsorted(ys, df.y)
    Z[iy, ix] = value
    return xs, ys, Z


def _round_levels(lo, hi, target=8):
    """Contour levels at round values covering [lo, hi]."""
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi <= lo:
        return None
    raw = (hi - lo) / target
    mag = 10 ** np.floor(np.log10(raw))
    step = min((m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw), default=10 * mag)
    return np.arange(np.floor(lo / step) * step, hi + step, step)


def _anchors(ax, A):
    """Draw the anchors' footprint (the frame's outline seen from above) with cable numbers (1-based).
    Anchors closer than 4 % of the footprint's span seen from above share one label ("3,4": the
    crossed cables of a spatial robot leave their pulleys in pairs), written above and right of the
    group's outermost marker so that it covers none of them (``_anchor_groups``)."""
    hull = A[ConvexHull(A[:, :2]).vertices, :2]
    ax.plot(*np.vstack([hull, hull[:1]]).T, color="k", lw=0.6, ls="--")
    xy = A[:, :2]
    span = float((xy.max(axis=0) - xy.min(axis=0)).max())
    first = {g[0]: g for g in _anchor_groups(xy, span)}
    for i, (x, y) in enumerate(xy):
        ax.plot(x, y, "k^", ms=6)
        if i in first:
            g = first[i]
            # the group's top-right corner (the anchor itself when alone)
            at = (xy[g, 0].max(), xy[g, 1].max())
            label = ",".join(str(k + 1) for k in g)
            ax.annotate(label, at, textcoords="offset points", xytext=(4, 4), fontsize=8)
    # the anchors and their numbers inside the axes (a number above the top edge met the title)
    lo, hi = A[:, :2].min(axis=0), A[:, :2].max(axis=0)
    pad = 0.08 * (hi - lo).max()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    ax.set_xlim(min(x0, lo[0] - pad), max(x1, hi[0] + pad))
    ax.set_ylim(min(y0, lo[1] - pad), max(y1, hi[1] + pad))


#: How a figure's title names the redundancy mode of the study that drew it.
MODE_TITLES = {
    "paper": "paper rule (best 3-cable subset)",
    "physical": "physical equilibrium (all cables)",
}
#: A colour-blind-safe palette (Okabe & Ito 2008) for signs and categories.
OKABE_ITO = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442", "#000000"]


def _mode(mode):
    """' — <mode>' for a title, '' when the figure has no mode."""
    return f" — {MODE_TITLES[mode]}" if mode in MODE_TITLES else ""


def paper_value(quantity):
    """The paper's number for ``quantity`` of cdpr/data/paper_values.yaml (its unit), or None."""

    for v in summary.paper_values():
        if v["quantity"] == quantity:
            return v["value"]
    return None


def _footprint(A):
    """The anchors' outline seen from above as a matplotlib Path (convex hull of their x, y)."""

    hull = A[ConvexHull(A[:, :2]).vertices, :2]
    return MPath(np.vstack([hull, hull[:1]]))


def _not_ok_counts(df, A=None):
    """Counts of the points that are not ok by status; with anchors ``A``, the points outside the
    anchors' footprint are counted apart (``outside the footprint``) from the statuses inside."""
    bad = df[df.status != "ok"]
    counts = {}
    if A is not None and len(bad):
        inside = _footprint(A).contains_points(bad[["x", "y"]].to_numpy(), radius=1e-9)
        if (~inside).any():
            counts["outside the footprint"] = int((~inside).sum())
        bad = bad[inside]
    for k, v in bad.status.value_counts().items():
        if v > 0:
            counts[k] = int(v)
    return counts


def _not_ok_legend(ax, df, A=None):
    """A legend under ``ax`` counting the points that are not ok (grey), by status, with the points
    outside the anchors' footprint counted apart when ``A`` is given."""

    counts = _not_ok_counts(df, A)
    if counts:
        ax.legend(
            handles=[
                Patch(
                    color=NOT_OK_COLOUR,
                    label="grey, not ok: " + ", ".join(f"{k} {v}" for k, v in counts.items()),
                )
            ],
            fontsize=7,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.14),
            frameon=False,
        )


def fig7_winch(df, l_pm0, q0, out, mode=None):
    """Métillon 2022 Fig. 7: (a) the two roots q1, q2 of the drum angle versus the length l_pm and
    the angle without the winch model, and (b) the length error δl = k_w (q1 - q_nw). The figure's
    point: q1, not q2, passes through the initial point (l_pm0, q0). ``df`` has columns l_pm, q1,
    q2, q_nw, dl. One cable: the same in both redundancy modes (the title says so)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.4), layout="constrained")
    a.plot(df.l_pm, df.q1, color=OKABE_ITO[0], label="q1 (winch model, physical root)")
    a.plot(df.l_pm, df.q2, color=OKABE_ITO[1], ls="-.", label="q2 (winch model, other root)")
    a.plot(df.l_pm, df.q_nw, "--", color="0.3", label="q_nw (winch neglected)")
    a.plot([l_pm0], [q0], "ko", label=f"initial point (l_pm0 = {l_pm0:.3f} m, q0 = {q0:g} rad)")
    a.set(xlabel="cable length l_pm [m]", ylabel="drum angle q [rad]", title="(a) drum angle (Fig. 7a)")
    a.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    a.grid(alpha=0.3)
    b.plot(df.l_pm, df.dl * 1e3, "k-", label="δl = k_w (q1 - q_nw)")
    b.axvline(l_pm0, color="0.5", ls=":", label=f"l_pm0 = {l_pm0:.3f} m")
    b.axhline(0.0, color="0.7", lw=0.8)
    b.set(xlabel="cable length l_pm [m]", ylabel="length error δl [mm]", title="(b) length error (Fig. 7b)")
    b.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    b.grid(alpha=0.3)
    fig.suptitle(
        "Winch exit point (Métillon 2022): one cable, the same in paper rule and physical modes", fontsize=10
    )
    return save(fig, out)


def fig9_subsets(tables, A, z, robot_name, out, mode=None):
    """Paty 2021 Fig. 9: the 3-cable subset that minimises ‖δp‖ at each point of the plane, one
    panel per pulley design. ``tables`` maps a design label to its plane table."""
    labels = sorted({s for df in tables.values() for s in df.subset.astype(str).unique() if s})
    cmap = plt.get_cmap("tab10", max(len(labels), 1))
    fig, axes = plt.subplots(
        1, len(tables), figsize=(5.2 * len(tables) + 1.5, 5.2), squeeze=False, layout="constrained"
    )
    for ax, (label, df) in zip(axes[0], tables.items()):
        code = df.subset.astype(str).map({s: i for i, s in enumerate(labels)}).astype(float)
        code[(df.status != "ok").to_numpy()] = np.nan
        xs, ys, Z = _grid(df, code.to_numpy())
        ax.set_facecolor(NOT_OK_COLOUR)
        im = ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(labels) - 0.5, shading="nearest")
        _anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df, A)
    cb = fig.colorbar(im, ax=axes[0].tolist(), ticks=range(len(labels)))
    cb.ax.set_yticklabels([f"cables {s}" for s in labels])
    cb.set_label("subset kept [cable numbers]")
    fig.suptitle(f"Subset of 3 cables that minimises ‖δp‖ (Fig. 9){_mode(mode)}", fontsize=10)
    return save(fig, out)


def fig9_taut(tables, A, z, robot_name, out, mode="physical"):
    """Fig. 9 of the physical study: the set of taut cables of the equilibrium at each point of the
    plane (``redundancy: physical``: every cable may go slack; the paper's Fig. 9 shows instead the
    3-cable subset its rule keeps), one panel per pulley design. ``tables`` maps a design label to
    its plane table (column ``taut``, e.g. '1-2-3-4'); points that are not ok are grey."""
    labels = sorted(
        {s for df in tables.values() for s in df.taut.astype(str).unique() if s},
        key=lambda s: (-len(s.split("-")), s),
    )
    cmap = plt.get_cmap("tab20" if len(labels) > 10 else "tab10", max(len(labels), 1))
    fig, axes = plt.subplots(
        1, len(tables), figsize=(5.2 * len(tables) + 1.5, 5.2), squeeze=False, layout="constrained"
    )
    im = None
    for ax, (label, df) in zip(axes[0], tables.items()):
        code = df.taut.astype(str).map({s: i for i, s in enumerate(labels)}).astype(float)
        code[(df.status != "ok").to_numpy()] = np.nan
        xs, ys, Z = _grid(df, code.to_numpy())
        ax.set_facecolor(NOT_OK_COLOUR)
        im = ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(labels) - 0.5, shading="nearest")
        _anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df, A)
    if im is not None:
        cb = fig.colorbar(im, ax=axes[0].tolist(), ticks=range(len(labels)))
        cb.ax.set_yticklabels([f"taut {s}" for s in labels])
        cb.set_label("taut-set map [cable numbers]")
    fig.suptitle(f"Taut cables at each point (Fig. 9 as a taut-set map){_mode(mode)}", fontsize=10)
    return save(fig, out)


#: Colours of the point statuses in the status strips (ok is not drawn).
STATUS_COLOURS = {
    "ok": "white",
    "slack": OKABE_ITO[1],
    "over_tension": OKABE_ITO[3],
    "inaccessible": "0.35",
    "not_converged": OKABE_ITO[4],
}


def fig10_trajectories(tables, minmax, out, mode=None):
    """Paty 2021 Fig. 10: ‖δp‖ along the section 3.3.1 paths, one panel per robot (colour: pulley
    kind). ``tables`` maps a design label (robot_pulley) to its path table (s, dp, status);
    ``minmax`` has ok_until_s_m and path_length_m per design. Points that are not ok are not drawn
    as curves (no ‖δp‖ = 0 that reads as no error): a status strip under each panel shows, per
    design, where the points are ok or why they are not, and the legend gives each design's reach
    (the last ok point over the path length)."""

    robots = list(dict.fromkeys(lab.split("_", 1)[0] for lab in tables))
    per = {rk: [lab for lab in tables if lab.split("_", 1)[0] == rk] for rk in robots}
    n_strip = max(len(v) for v in per.values())
    # a rigid platform (tables with dphi): δφ and the cable tensions in panels under ‖δp‖
    spatial = any("dphi" in df for df in tables.values())
    extra = [2.6, 2.6] if spatial else []
    fig = plt.figure(figsize=(6.2 * len(robots), 5.4 + 2.6 * len(extra)), layout="constrained")
    outer = fig.add_gridspec(2 + len(extra), len(robots), height_ratios=[4, *extra, 0.35 * n_strip + 0.4])
    states = list(STATUS_COLOURS)
    cmap = ListedColormap([STATUS_COLOURS[s] for s in states])
    mm = minmax.set_index("design")
    seen = set()
    for j, rk in enumerate(robots):
        ax = fig.add_subplot(outer[0, j])
        strip = fig.add_subplot(outer[1 + len(extra), j], sharex=ax)
        if spatial:
            _path_dphi_tensions(
                fig.add_subplot(outer[1, j], sharex=ax),
                fig.add_subplot(outer[2, j], sharex=ax),
                {lab: tables[lab] for lab in per[rk]},
                rk,
            )
        for lab in per[rk]:
            df = tables[lab]
            ok = df.status == "ok"
            kind = lab.split("_", 1)[1] if "_" in lab else lab
            row = mm.loc[lab]
            reach = f"last ok point at s = {row.ok_until_s_m:.2f} of {row.path_length_m:.2f} m"
            ax.plot(
                df.s.where(ok), df.dp.where(ok) * 1e3, color=KIND_COLOURS.get(kind), label=f"{lab}: {reach}"
            )
            seen |= set(df.status.unique())
        codes = np.array(
            [[states.index(s) if s in states else 0 for s in tables[lab].status] for lab in per[rk]], float
        )
        s0 = tables[per[rk][0]].s.to_numpy()
        strip.pcolormesh(
            s0,
            np.arange(len(per[rk])),
            codes,
            cmap=cmap,
            vmin=-0.5,
            vmax=len(states) - 0.5,
            shading="nearest",
        )
        strip.set_yticks(np.arange(len(per[rk])), [lab.split("_", 1)[1] for lab in per[rk]], fontsize=7)
        strip.set(xlabel="position along the path s [m]", ylabel="status [-]")
        ax.tick_params(labelbottom=False)
        ax.set(
            ylabel="‖δp‖ [mm]", title=f"{rk}: ‖δp‖ along the {'path' if spatial else 'section 3.3.1 path'}"
        )
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.02 - 0.09 * n_strip), frameon=False)
        ax.set_ylim(bottom=0)
    handles = [Patch(facecolor=STATUS_COLOURS[s], edgecolor="0.5", label=s) for s in states if s in seen]
    fig.legend(
        handles=handles,
        loc="outside lower center",
        ncol=len(handles),
        fontsize=7,
        title="status strip",
        title_fontsize=7,
    )
    what = "‖δp‖, δφ and the tensions" if spatial else "‖δp‖"
    fig.suptitle(f"{what} along the paths (Fig. 10){_mode(mode)}", fontsize=10)
    return save(fig, out)


def _tension_columns(df):
    """The tension columns t1..tm of a point table, in cable order."""
    return sorted((c for c in df.columns if re.fullmatch(r"t\d+", c)), key=lambda c: int(c[1:]))


def _path_dphi_tensions(ax_phi, ax_t, tables, name):
    """δφ [mrad] (``ax_phi``) and the least and largest cable tension [N] (``ax_t``, a slack cable
    at 0 N) along the path tables ``tables`` (label -> table with s, dphi, t1..tm, status), ok
    points only, one colour per pulley kind."""
    for lab, df in tables.items():
        ok = df.status == "ok"
        kind = lab.split("_", 1)[1] if "_" in lab else lab
        c = KIND_COLOURS.get(kind)
        if "dphi" in df:
            ax_phi.plot(df.s.where(ok), df["dphi"].where(ok) * DPHI_SCALE, color=c, label=lab)
        tt = df[_tension_columns(df)].fillna(0.0)
        ax_t.plot(df.s.where(ok), tt.max(axis=1).where(ok), color=c, label=f"{lab}: largest t_i")
        ax_t.plot(df.s.where(ok), tt.min(axis=1).where(ok), color=c, ls="--", label=f"{lab}: least t_i")
    ax_phi.set(ylabel=DPHI_LABEL, title=f"{name}: orientation error δφ")
    ax_phi.set_ylim(bottom=0)
    ax_t.set(ylabel="cable tension [N]", title=f"{name}: largest and least cable tension (slack: 0 N)")
    for a in (ax_phi, ax_t):
        a.tick_params(labelbottom=False)
        a.grid(alpha=0.3)
        a.title.set_fontsize(9)
    ax_phi.legend(fontsize=7)
    ax_t.legend(fontsize=6, ncol=2)


def fig11_minmax(minmax, out, mode=None):
    """Paty 2021 Fig. 11: min and max ‖δp‖ along each path, per design (table ``minmax``); with
    columns dphi_min_rad, dphi_max_rad (a rigid platform) the same for δφ in a second panel."""
    spatial = "dphi_max_rad" in minmax
    fig, axes = plt.subplots(
        1, 2 if spatial else 1, figsize=(13 if spatial else 6.5, 4.4), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    x = np.arange(len(minmax))
    if spatial:
        a = axes[0, 1]
        a.bar(
            x - 0.2, minmax.dphi_min_rad * DPHI_SCALE, 0.4, color=OKABE_ITO[0], label="min over the ok points"
        )
        a.bar(
            x + 0.2, minmax.dphi_max_rad * DPHI_SCALE, 0.4, color=OKABE_ITO[1], label="max over the ok points"
        )
        a.set_xticks(x, minmax.design, rotation=30, ha="right")
        a.set(
            xlabel="design [path_pulley]",
            ylabel=DPHI_LABEL,
            title=f"Min and max of δφ along the paths{_mode(mode)}",
        )
        a.title.set_fontsize(9)
        a.grid(axis="y", alpha=0.3)
        a.legend(fontsize=8)
    ax.bar(x - 0.2, minmax.dp_min_m * 1e3, 0.4, color=OKABE_ITO[0], label="min over the ok points")
    ax.bar(x + 0.2, minmax.dp_max_m * 1e3, 0.4, color=OKABE_ITO[1], label="max over the ok points")
    ax.set_xticks(x, minmax.design, rotation=30, ha="right")
    ax.set(
        xlabel="design [robot_pulley]",
        ylabel="‖δp‖ [mm]",
        title=f"Min and max of ‖δp‖ along the paths (Fig. 11){_mode(mode)}",
    )
    ax.title.set_fontsize(9)
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out)


def _labelled_contours(fig, ax, xs, ys, Z, cmap, label, skip=(), top=None):
    """Filled contours of Z at about ten round levels (``_round_levels``) with every level a black
    line, every other line labelled (but values in ``skip``, whose own labels are drawn elsewhere),
    and the panel's own colour bar titled ``label``. ``top``: the levels stop there and the values
    above it take the top colour (the colour bar's triangle), for a field whose few largest values
    would flatten the rest. Nothing is drawn where Z has under two levels."""
    high = np.nanmax(Z) if top is None else min(top, np.nanmax(Z))
    levels = _round_levels(np.nanmin(Z), high, 10)
    if levels is None or len(levels) < 2:
        return
    extend = "max" if np.nanmax(Z) > levels[-1] else "neither"
    cf = ax.contourf(xs, ys, Z, levels=levels, cmap=cmap, extend=extend)
    cs = ax.contour(xs, ys, Z, levels=levels, colors="k", linewidths=0.4)
    ax.clabel(cs, [v for v in levels[1:-1:2] if not np.isclose(skip, v).any()], fmt="%g", fontsize=6)
    fig.colorbar(cf, ax=ax, label=label, shrink=0.8)


def fig12_plane(tables, A, z, robot_name, out, mode=None, paper=None):
    """Paty 2021 Fig. 12: iso-contours of ‖δp‖ over the horizontal plane at height z, one panel per
    pulley design of the same robot, each on levels fine enough to show its own structure (about
    ten filled levels, every level a labelled line; its own colour bar). ``paper`` maps a design
    label to the paper's iso-values [m] (e.g. the min and max it quotes), drawn as red dashed
    labelled contours. Cells that are not ok are grey, counted by status under the panel with the
    points outside the anchors' footprint counted apart; the dashed line is the footprint.

    The small closed contour at the centre of CDPR4 with DR pulleys is in the data, not the
    contouring: the paper's rule takes the least ‖δp‖ of the four 3-cable subsets, which are equal
    at the centre by symmetry and each fall away from it, so ‖δp‖ has a cusp maximum there."""
    paper = paper or {}
    spatial = any("dphi" in df for df in tables.values())
    fig, axes = plt.subplots(
        2 if spatial else 1,
        len(tables),
        figsize=(5.6 * len(tables), 11.2 if spatial else 5.6),
        squeeze=False,
        layout="constrained",
    )
    if spatial:  # a rigid platform: the orientation error δφ under the position error
        for ax, (label, df) in zip(axes[1], tables.items()):
            _plane_dphi_panel(fig, ax, df, A, f"{robot_name} {label} at z = {z:g} m: δφ")
    for ax, (label, df) in zip(axes[0], tables.items()):
        ok = (df.status == "ok").to_numpy()
        xs, ys, Z = _grid(df, np.where(ok, df.dp * 1e3, np.nan))
        ax.set_facecolor(NOT_OK_COLOUR)
        if np.isfinite(Z).any():
            iso = [v * 1e3 for v in paper.get(label, []) if v is not None]
            _labelled_contours(fig, ax, xs, ys, Z, "viridis", "‖δp‖ [mm]", skip=iso)  # paper's own label wins
            if iso and np.nanmin(Z) < max(iso) and np.nanmax(Z) > min(iso):
                cp = ax.contour(xs, ys, Z, levels=sorted(iso), colors="r", linewidths=1.2, linestyles="--")
                ax.clabel(cp, fmt=lambda v: f"paper {v:g}", fontsize=6)
        _anchors(ax, A)
        iso_txt = " / ".join(f"{v * 1e3:g}" for v in paper.get(label, []) if v is not None)
        extra = f"\nred dashed: paper's {iso_txt} mm" if iso_txt else ""
        ax.set(
            xlabel="x [m]",
            ylabel="y [m]",
            title=f"{robot_name} {label} at z = {z:g} m{extra}",
            aspect="equal",
        )
        ax.title.set_fontsize(9)
        _not_ok_legend(ax, df, A)
    what = "‖δp‖ and δφ" if spatial else "‖δp‖"
    fig.suptitle(f"{what} over the plane (Fig. 12){_mode(mode)}", fontsize=10)
    return save(fig, out)


#: The orientation error's display unit: δφ [rad] is drawn in mrad (the error is a few mrad).
DPHI_SCALE, DPHI_UNIT = 1e3, "mrad"
DPHI_LABEL = f"δφ [{DPHI_UNIT}]"
#: A δφ plane whose largest value exceeds this many times its 75th percentile is drawn to the percentile.
DPHI_TAIL = 3.0


def _plane_dphi_panel(fig, ax, df, A, title):
    """One panel of the orientation error δφ [mrad] over a plane table (column ``dphi`` [rad]):
    filled round levels with their own colour bar; cells that are not ok grey, counted below. Where
    the largest values (near the frame's edges, where the platform hangs on few taut cables) exceed
    DPHI_TAIL times the 75th percentile, the levels stop at that percentile and the title says so:
    else the interior, where the platform works, is one colour."""
    ok = (df.status == "ok").to_numpy()
    xs, ys, Z = _grid(df, np.where(ok, df["dphi"] * DPHI_SCALE, np.nan))
    ax.set_facecolor(NOT_OK_COLOUR)
    if np.isfinite(Z).any():
        q75 = float(np.nanpercentile(Z, 75))
        top = q75 if np.nanmax(Z) > DPHI_TAIL * q75 else None
        _labelled_contours(fig, ax, xs, ys, Z, "magma", DPHI_LABEL, top=top)
        if top is not None:
            title += f"\nlevels to the 75th percentile; max {np.nanmax(Z):.3g} {DPHI_UNIT}"
    _anchors(ax, A)
    ax.set(xlabel="x [m]", ylabel="y [m]", title=title, aspect="equal")
    ax.title.set_fontsize(9)
    _not_ok_legend(ax, df, A)


def fig12_tension(tables, A, z, robot_name, t_min, out, mode=None):
    """Minimum cable tension over the plane at height z (beyond the paper): min_i t_i at each ok
    point (physical mode: over every cable, a slack one at 0 N; paper mode: over the 3-cable subset
    the rule keeps, the others carry no modelled tension), one panel per pulley design, with the tension limit ``t_min`` [N] drawn as a red line
    (the slack margin is the distance to it). ``tables`` maps a design label to its plane table
    (columns x, y, status, t1..tm [N])."""
    fig, axes = plt.subplots(
        1, len(tables), figsize=(5.6 * len(tables), 5.6), squeeze=False, layout="constrained"
    )
    for ax, (label, df) in zip(axes[0], tables.items()):
        tcols = sorted((c for c in df.columns if re.fullmatch(r"t\d+", c)), key=lambda c: int(c[1:]))
        ok = (df.status == "ok").to_numpy()
        tt = df[tcols]
        if "taut" in df.columns:  # physical mode: a slack cable's tension is written NaN, and is 0 N
            tt = tt.fillna(0.0)
        tmin = tt.min(axis=1).to_numpy() if tcols else np.full(len(df), np.nan)
        xs, ys, Z = _grid(df, np.where(ok, tmin, np.nan))
        ax.set_facecolor(NOT_OK_COLOUR)
        if np.isfinite(Z).any():
            _labelled_contours(fig, ax, xs, ys, Z, "cividis", "minimum cable tension min t_i [N]")
            if t_min is not None and np.nanmin(Z) < t_min < np.nanmax(Z):
                ax.contour(xs, ys, Z, levels=[t_min], colors="r", linewidths=1.2)
        _anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df, A)
    lim = f"; red: t = {t_min:g} N" if t_min is not None else ""
    over = "slack cables count as 0 N" if mode == "physical" else "over the 3 cables the rule keeps"
    fig.suptitle(f"Minimum cable tension over the plane ({over}){lim}{_mode(mode)}", fontsize=10)
    return save(fig, out)


#: Largest number of voxels per axis drawn in Fig. 13 (matplotlib's voxel rendering is slow).
VOXELS_DRAWN = 24


def _coarsen(a, k, how):
    """Block-reduce a (n, n, n) array by k per axis (n padded with NaN to a multiple of k)."""
    n = np.array(a.shape)
    m = -(-n // k)
    pad = np.full(tuple(m * k), np.nan)
    pad[: n[0], : n[1], : n[2]] = a
    blocks = pad.reshape(m[0], k, m[1], k, m[2], k)
    with warnings.catch_warnings():  # a block with no ok cell has no mean: NaN, as wanted
        warnings.simplefilter("ignore", RuntimeWarning)
        return how(blocks, axis=(1, 3, 5))


def _frame(ax, A):
    """The frame of anchors ``A`` (m, 3) in a 3-D axes: the anchors (pulleys, triangles), the
    footprint at the floor and at the anchors' height, and the vertical posts."""
    path = _footprint(A).vertices
    top = float(A[:, 2].max())
    for zz in (0.0, top):
        ax.plot(path[:, 0], path[:, 1], zz, color="k", lw=0.7)
    for x, y in path[:-1]:
        ax.plot([x, x], [y, y], [0.0, top], color="k", lw=0.7)
    ax.scatter(A[:, 0], A[:, 1], A[:, 2], marker="^", color="k", s=20, depthshade=False)


def fig13_volume_view(df, limits, R_V, z_top, title, out, A=None, mode=None, dphi_limits=None, dphi_R_V=None):
    """Paty 2021 Fig. 13: the error-limited region ‖δp‖ <= limit, one panel per limit, drawn as
    opaque voxels (cell-centred grid table ``df`` in C order) inside the frame of anchors ``A``
    (drawn, with the pulleys), every panel on the same limits (the frame's box, z from 0 to
    ``z_top``). Grids finer than ``VOXELS_DRAWN`` per axis are drawn on coarser blocks (a block is
    filled when most of its cells are); R_V is computed on the full grid by the caller. With
    ``dphi_limits`` [rad] and their ``dphi_R_V`` (a rigid platform: ``df`` has ``dphi`` [rad]), a
    second row draws the region δφ <= limit the same way (beyond the paper)."""
    xs, ys, zs = (np.sort(df[c].unique()) for c in ("x", "y", "z"))
    n = (len(xs), len(ys), len(zs))
    k = max(1, -(-max(n) // VOXELS_DRAWN))
    ok = (df.status == "ok").to_numpy().reshape(n)
    lo = np.array([xs[0], ys[0], zs[0]]) - np.array([xs[1] - xs[0], ys[1] - ys[0], zs[1] - zs[0]]) / 2
    step = np.array([xs[1] - xs[0], ys[1] - ys[0], zs[1] - zs[0]]) * k
    m = tuple(-(-np.array(n) // k))
    edges = [lo[a] + step[a] * np.arange(m[a] + 1) for a in range(3)]
    if A is not None:
        box = [(float(A[:, a].min()), float(A[:, a].max())) for a in range(2)] + [
            (0.0, max(z_top, float(A[:, 2].max())))
        ]
    else:
        box = [(edges[0][0], edges[0][-1]), (edges[1][0], edges[1][-1]), (0.0, z_top)]
    rows = [("dp", limits, R_V, 1e3, "‖δp‖", "mm")]
    if dphi_limits:
        rows.append(("dphi", dphi_limits, dphi_R_V, DPHI_SCALE, "δφ", DPHI_UNIT))
    ncols = max(len(r[1]) for r in rows)
    fig = plt.figure(figsize=(5.2 * ncols, 5.6 * len(rows)), layout="constrained")
    for r, (column, lims, rvs, scale, name, unit) in enumerate(rows):
        err = np.where(ok, df[column].to_numpy().reshape(n), np.nan)
        axes = _volume_row(fig, (len(rows), ncols, r), err, lims, rvs, (scale, name, unit), k, edges, box, A)
        fig.colorbar(
            matplotlib.cm.ScalarMappable(
                norm=matplotlib.colors.Normalize(0.0, max(lims) * scale), cmap="viridis"
            ),
            ax=axes,
            location="bottom",
            shrink=0.5,
            label=f"{name} [{unit}]",
        )
    drawn = f" (drawn on {m[0]}x{m[1]}x{m[2]} blocks of the {n[0]}^3 grid)" if k > 1 else ""
    fig.suptitle(title + drawn + _mode(mode), fontsize=10)
    return save(fig, out)


def _volume_row(fig, grid, err, limits, R_V, what, k, edges, box, A):
    """One row of Fig. 13: a 3-D panel per limit of the voxels whose error ``err`` (n, n, n; NaN
    where not ok) is at most the limit, coloured by the error. ``grid`` = (rows, columns, row);
    ``what`` = (display scale, name, unit). Returns the row's axes."""
    rows, ncols, r = grid
    scale, name, unit = what
    norm = matplotlib.colors.Normalize(0.0, max(limits) * scale)
    err_c = _coarsen(err, k, np.nanmean) if k > 1 else err
    X, Y, Z = np.meshgrid(*edges, indexing="ij")
    axes = []
    for j, (lim, rv) in enumerate(zip(limits, R_V)):
        ax = fig.add_subplot(rows, ncols, r * ncols + j + 1, projection="3d")
        axes.append(ax)
        inside = np.where(np.isnan(err), 0.0, (err <= lim).astype(float))
        filled = (_coarsen(inside, k, np.nanmean) >= 0.5) if k > 1 else inside > 0
        colour = plt.get_cmap("viridis")(norm(np.nan_to_num(err_c, nan=0.0) * scale))
        # the limits are set below: without autoscaling after each of the voxels (matplotlib adds one
        # collection per voxel and rescales the view each time: half of the drawing time)
        ax.set_autoscale_on(False)
        ax.voxels(X, Y, Z, filled, facecolors=colour, edgecolor=None, linewidth=0)
        if A is not None:
            _frame(ax, A)
        ax.set(
            xlim=box[0], ylim=box[1], zlim=box[2], title=f"{name} ≤ {lim * scale:g} {unit}: R_V = {rv:.2f}"
        )
        ax.set_xlabel("x [m]", labelpad=6)
        ax.set_ylabel("y [m]", labelpad=6)
        ax.set_zlabel("z [m]", labelpad=6)
        ax.tick_params(labelsize=6, pad=0)
        ax.set_box_aspect([box[a][1] - box[a][0] for a in range(3)], zoom=0.85)
    return axes


def fig14_rv(tab, paper, out, mode=None):
    """Paty 2021 Fig. 14: R_V = V_L / V_T versus the error limit, per robot and pulley design;
    ``paper`` rows (robot, pulley, limit_m, R_V) are the paper's values, drawn as markers."""
    fig, ax = plt.subplots(figsize=(7.5, 4.6), layout="constrained")
    robots = list(dict.fromkeys(tab.robot))
    for (rk, pk), g in tab.groupby(["robot", "pulley"], sort=False):
        k = robots.index(rk)
        (line,) = ax.plot(
            g.limit_m * 1e3, g.R_V, ["-", "--", ":"][k % 3], color=KIND_COLOURS.get(pk), label=f"{rk} {pk}"
        )
        p = paper[(paper.robot == rk) & (paper.pulley == pk)]
        if len(p):
            ax.plot(
                p.limit_m * 1e3,
                p.R_V,
                "os^"[k % 3],
                mfc="none",
                ms=7,
                color=line.get_color(),
                label=f"{rk} {pk}: paper",
            )
    for lim in sorted(set(paper.limit_m)):
        ax.axvline(lim * 1e3, color="0.6", ls=":", lw=0.8)
    ax.set(
        xlabel=r"error limit $\|\delta p\|_{lim}$ [mm]",
        ylabel=r"$R_V = V_L / V_T$ [-]",
        title=f"Error-limited volume ratio (Fig. 14){_mode(mode)}",
    )
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=1, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return save(fig, out)


def fig14_rv_dphi(tab, out, mode=None):
    """Fig. 14 on the orientation error (beyond the paper): R_V = V_L / V_T of the region δφ <= limit
    versus the limit [rad, drawn in mrad], per robot and pulley design (``tab``: robot, pulley,
    limit_rad, R_V, study_limit); the study's limits (``volumes.dphi_limits_rad``) are marked."""
    fig, ax = plt.subplots(figsize=(7.5, 4.6), layout="constrained")
    robots = list(dict.fromkeys(tab.robot))
    for (rk, pk), g in tab.groupby(["robot", "pulley"], sort=False):
        k = robots.index(rk)
        ax.plot(
            g.limit_rad * DPHI_SCALE,
            g.R_V,
            ["-", "--", ":"][k % 3],
            marker="o",
            ms=3,
            color=KIND_COLOURS.get(pk),
            label=f"{rk} {pk}",
        )
    for lim in sorted(set(tab.limit_rad[tab.study_limit.astype(bool)])):
        ax.axvline(lim * DPHI_SCALE, color="0.6", ls=":", lw=0.8)
    ax.set(
        xlabel=f"orientation error limit δφ_lim [{DPHI_UNIT}]",
        ylabel=r"$R_V = V_L / V_T$ [-]",
        title=f"Error-limited volume ratio on δφ (Fig. 14 on the orientation){_mode(mode)}",
    )
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=1, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return save(fig, out)


def fig15_doe(tests, out, mode=None, paper=True):
    """Paty 2021 Fig. 15: the global index of each DOE test (Table 2), the factor levels of each
    test in a table under the bars, the paper's best and worst index (0.05 / 0.29 m) as markers
    (``paper``: False for a robot the paper did not study). With a column ``index_phi_rad`` (a rigid
    platform) the orientation index of each test in a second panel."""
    spatial = "index_phi_rad" in tests
    fig, axes = plt.subplots(
        1, 2 if spatial else 1, figsize=(15 if spatial else 8, 4.8), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    x = np.arange(len(tests))
    colours = [KIND_COLOURS.get(k) for k in tests.kind]
    ax.bar(x, tests.index_m * 1e3, color=colours)
    ax.set_xticks(x, [f"T{t}" for t in tests.test])
    if spatial:
        a = axes[0, 1]
        a.bar(x, tests.index_phi_rad * DPHI_SCALE, color=colours)
        a.set_xticks(x, [f"T{t}" for t in tests.test])
        a.set(
            xlabel="DOE test [Table 2]",
            ylabel=f"orientation index mean δφ [{DPHI_UNIT}]",
            title=f"DOE responses: orientation{_mode(mode)}",
        )
        a.grid(axis="y", alpha=0.3)
    for name, q in (("paper's best", "DOE minimum (test 1)"), ("paper's worst", "DOE maximum (test 7)")):
        if not paper:
            break
        v = paper_value(q)
        if v is not None:
            ax.axhline(v * 1e3, color="r", ls="--", lw=0.9)
            ax.annotate(
                f"{name} {v:g} m",
                (1.0, v * 1e3),
                xycoords=("axes fraction", "data"),
                xytext=(3, 0),
                textcoords="offset points",
                fontsize=7,
                color="r",
                va="center",
            )
    cells = [
        list(tests.kind),
        [f"{h * 1e3:g}" for h in tests.h_m],
        [f"{r * 1e3:g}" for r in tests.r_p_m],
    ]
    tb = ax.table(
        cellText=cells,
        rowLabels=["joint", "h [mm]", "r_p [mm]"],
        loc="bottom",
        cellLoc="center",
        bbox=[0, -0.32, 1, 0.22],
    )
    tb.set_fontsize(7)
    ax.set(
        xlabel="DOE test [Table 2]",
        ylabel="global index mean ‖δp‖ [mm]",
        title=f"DOE responses (Fig. 15){_mode(mode)}",
    )
    ax.xaxis.set_label_position("top")
    ax.grid(axis="y", alpha=0.3)
    return save(fig, out)


def fig16_effects(eff, out, mode=None):
    """Paty 2021 Fig. 16: effects and interactions of the coded factors on the global index; the
    effect of a term is 2 × its regression coefficient (the change from its -1 to its +1 level).
    Colour-blind-safe signs (blue: lowers the index, vermillion: raises it). A table with a column
    ``response`` (a rigid platform: ``index_m`` and ``index_phi_rad``) gets one panel per response,
    the orientation's in mrad."""
    responses = list(dict.fromkeys(eff.response)) if "response" in eff else ["index_m"]
    fig, axes = plt.subplots(
        1, len(responses), figsize=(7 * len(responses), 4.4), squeeze=False, layout="constrained"
    )
    for ax, resp in zip(axes[0], responses):
        e = eff[eff.term != "mean"]
        if "response" in eff:
            e = e[e.response == resp]
        phi = resp == "index_phi_rad"
        ax.bar(
            np.arange(len(e)),
            e.effect * (DPHI_SCALE if phi else 1e3),
            color=[OKABE_ITO[0] if v < 0 else OKABE_ITO[1] for v in e.effect],
        )
        ax.set_xticks(np.arange(len(e)), e.term, rotation=30, ha="right")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set(
            xlabel="term [coded factors -1/+1: joint SR/DR, h and r_p low/high of Table 2]",
            ylabel=f"effect = 2 × coefficient [{DPHI_UNIT if phi else 'mm'}]",
            title=f"Effects and interactions on mean {'δφ' if phi else '‖δp‖'} (Fig. 16){_mode(mode)}",
        )
        ax.title.set_fontsize(9)
        ax.grid(axis="y", alpha=0.3)
    return save(fig, out)


#: The paper's lines h = k r_p (Paty 2021 section 4.3: D_SR h = 40/13 r_p, D_DR h = 5/4 r_p) and
#: optimal designs (Table 3: SR* h = 107.7 mm, r_p = 35 mm; DR* h = 100 mm, r_p = 80 mm) [m].
PAPER_LINES = {"SR": 40.0 / 13.0, "DR": 5.0 / 4.0}
PAPER_OPTIMA = {"SR": (0.1077, 0.035), "DR": (0.100, 0.080)}


def fig17_maps(tab, valleys, lines, tests, levels, out, mode=None, paper=True):
    """Paty 2021 Fig. 17: the global index over the (r_p, h) plane for each pulley kind on one
    colour range with labelled contour lines, the valley r_p*(h), the fitted line h = k r_p and
    our optimum I, the paper's line D and its optimum (SR*, DR*) (``paper``: False for a robot the
    paper did not study), the DOE field and tests T1-T8. ``valleys`` maps a kind to its valley
    table; ``lines`` has one row per kind. With a column ``index_phi_rad`` (a rigid platform) a
    second row maps the orientation index [mrad] with the DOE field."""
    kinds = list(dict.fromkeys(tab.kind))
    lo, hi = float(tab.index_m.min()) * 1e3, float(tab.index_m.max()) * 1e3
    lv = _round_levels(lo, hi, 20)
    spatial = "index_phi_rad" in tab
    fig, axes = plt.subplots(
        2 if spatial else 1,
        len(kinds),
        figsize=(6.0 * len(kinds) + 1.2, 11.6 if spatial else 5.8),
        squeeze=False,
        layout="constrained",
    )
    if spatial:
        _maps_dphi_row(fig, axes[1], tab, kinds, levels)
    cf = None
    for ax, kind in zip(axes[0], kinds):
        g = tab[tab.kind == kind]
        piv = g.pivot(index="h_m", columns="r_p_m", values="index_m")
        if piv.shape[0] > 1 and piv.shape[1] > 1 and lv is not None:
            cf = ax.contourf(piv.columns * 1e3, piv.index * 1e3, piv.values * 1e3, levels=lv, cmap="viridis")
            ax.contour(
                piv.columns * 1e3,
                piv.index * 1e3,
                piv.values * 1e3,
                levels=lv[::4],
                colors="k",
                linewidths=0.4,
            )  # unlabelled: the colour bar's ticks are these levels (labels would sit on T1-T8)
        v = valleys[kind]
        ax.plot(v.r_p_star * 1e3, v.h * 1e3, "wo", ms=3, mec="k", mew=0.4, label="valley r_p*(h)")
        line = lines[lines.kind == kind].iloc[0]
        rmax = g.r_p_m.max()
        rr = np.linspace(0, rmax, 10)
        if np.isfinite(line.slope_k):
            ax.plot(rr * 1e3, line.slope_k * rr * 1e3, "r-", label=f"ours: h = {line.slope_k:.2f} r_p")
        if paper and kind in PAPER_LINES:
            k = PAPER_LINES[kind]
            ax.plot(rr * 1e3, k * rr * 1e3, color="m", ls="--", label=f"paper D_{kind}: h = {k:.3g} r_p")
            h_p, r_p = PAPER_OPTIMA[kind]
            ax.plot(r_p * 1e3, h_p * 1e3, "D", color="m", mec="w", ms=8, zorder=6, label=f"paper {kind}*")
        r0, r1 = levels["r_p_m"]
        h0, h1 = levels["h_m"]
        ax.add_patch(
            plt.Rectangle((r0 * 1e3, h0 * 1e3), (r1 - r0) * 1e3, (h1 - h0) * 1e3, fill=False, ec="w", ls="--")
        )
        for t in tests[tests.kind == kind].itertuples():
            ax.plot(t.r_p_m * 1e3, t.h_m * 1e3, "w+", ms=6, mew=1.2)  # the test's point; its name beside it
            ax.annotate(
                f"T{t.test}",
                (t.r_p_m * 1e3, t.h_m * 1e3),
                xytext=(-9, -9),
                textcoords="offset points",
                color="w",
                fontsize=7,
                ha="center",
                va="center",
                bbox=dict(boxstyle="round,pad=0.15", fc="k", alpha=0.6),
            )
        if line.r_p_opt_m == line.r_p_opt_m and line.r_p_opt_m is not None:
            ax.plot(
                line.r_p_opt_m * 1e3,
                line.h_opt_m * 1e3,
                "r*",
                ms=13,
                mec="w",
                zorder=7,
                label=f"ours: I_{kind}",
            )
        hmax = max(g.h_m.max(), h1) * 1e3
        ax.set(
            xlabel="sheave radius r_p [mm]",
            ylabel="lever arm h [mm]",
            title=f"{kind} pulleys (Fig. 17)",
            xlim=(0, rmax * 1e3),
            ylim=(0, hmax * 1.08),
        )
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, frameon=False)
    if cf is not None:
        cb = fig.colorbar(
            cf, ax=axes[0].tolist(), label="global index mean ‖δp‖ [mm] (black lines at the ticks)"
        )
        cb.set_ticks(lv[::4])
    fig.suptitle(f"Global index over the (r_p, h) plane{_mode(mode)}", fontsize=10)
    return save(fig, out)


def _maps_dphi_row(fig, axes, tab, kinds, levels):
    """The orientation index [mrad] over the (r_p, h) plane, one panel per kind on one colour range,
    with the DOE field (dashed): the second row of ``fig17_maps`` for a rigid platform."""
    v = tab.index_phi_rad * DPHI_SCALE
    lv = _round_levels(float(v.min()), float(v.max()), 16)
    cf = None
    for ax, kind in zip(axes, kinds):
        g = tab[tab.kind == kind]
        piv = g.pivot(index="h_m", columns="r_p_m", values="index_phi_rad")
        if piv.shape[0] > 1 and piv.shape[1] > 1 and lv is not None and len(lv) > 1:
            cf = ax.contourf(
                piv.columns * 1e3, piv.index * 1e3, piv.values * DPHI_SCALE, levels=lv, cmap="magma"
            )
        ax.plot(g.r_p_m * 1e3, g.h_m * 1e3, "k.", ms=3)
        r0, r1 = levels["r_p_m"]
        h0, h1 = levels["h_m"]
        ax.add_patch(
            plt.Rectangle((r0 * 1e3, h0 * 1e3), (r1 - r0) * 1e3, (h1 - h0) * 1e3, fill=False, ec="c", ls="--")
        )
        ax.set(
            xlabel="sheave radius r_p [mm]",
            ylabel="lever arm h [mm]",
            title=f"{kind} pulleys: orientation index mean δφ",
            xlim=(0, g.r_p_m.max() * 1e3),
            ylim=(0, max(g.h_m.max(), h1) * 1e3 * 1.08),
        )
    if cf is not None:
        fig.colorbar(cf, ax=list(axes), label=f"orientation index mean δφ [{DPHI_UNIT}]")


def fig18_index_vs_E(tab, E_mean, bands, out, mode=None, paper=None):
    """Paty 2021 Fig. 18: the global index of each optimal design versus Young's modulus, with the
    nominal modulus E_mean and our band [min, max] over the range shaded; ``paper`` {design:
    (index, minus, plus)} [m] draws the paper's band as an error bar at E_mean."""
    paper = paper or {}
    spatial = "index_phi_rad" in tab
    fig, axes = plt.subplots(
        1, 2 if spatial else 1, figsize=(15 if spatial else 7.5, 4.6), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    if spatial:  # a rigid platform: the orientation index versus E beside it
        a = axes[0, 1]
        for i, (dk, g) in enumerate(tab.groupby("design", sort=False)):
            c = OKABE_ITO[i % len(OKABE_ITO)]
            a.plot(g.E_Pa / 1e9, g.index_phi_rad * DPHI_SCALE, "o-", ms=3, color=c, label=f"{dk} (ours)")
            a.axhspan(
                g.index_phi_rad.min() * DPHI_SCALE, g.index_phi_rad.max() * DPHI_SCALE, color=c, alpha=0.12
            )
        a.axvline(E_mean / 1e9, color="k", ls=":", label=f"E_mean = {E_mean / 1e9:g} GPa")
        a.set(
            xlabel="Young's modulus E [GPa]",
            ylabel=f"orientation index mean δφ [{DPHI_UNIT}]",
            title=f"Orientation index versus E, shaded: our band{_mode(mode)}",
        )
        a.title.set_fontsize(9)
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    for i, (dk, g) in enumerate(tab.groupby("design", sort=False)):
        c = OKABE_ITO[i % len(OKABE_ITO)]
        ax.plot(g.E_Pa / 1e9, g.index_m * 1e3, "o-", ms=3, color=c, label=f"{dk} (ours)")
        b = bands[bands.design == dk].iloc[0]
        ax.axhspan(b.index_min_m * 1e3, b.index_max_m * 1e3, color=c, alpha=0.12)
        if dk in paper:
            mid, minus, plus = (v * 1e3 for v in paper[dk])
            ax.errorbar(
                [E_mean / 1e9 + 1.5],
                [mid],
                yerr=[[minus], [plus]],
                fmt="s",
                color=c,
                mfc="w",
                capsize=4,
                label=f"{dk}: paper {mid:g} +{plus:g}/-{minus:g} mm",
            )
    ax.axvline(E_mean / 1e9, color="k", ls=":", label=f"E_mean = {E_mean / 1e9:g} GPa")
    ax.set(
        xlabel="Young's modulus E [GPa]",
        ylabel="global index mean ‖δp‖ [mm]",
        title=f"Index versus E (Fig. 18), shaded: our band{_mode(mode)}",
    )
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return save(fig, out)


def fig19_paths(curves, crossings, out, mode=None, paper=None, phi=None):
    """Paty 2021 Fig. 19: ‖δp‖ along the section 5.2 path for each design (colour) at E_min,
    E_mean, E_max (line style), with our crossings of the E_max and E_min curves (solid vertical
    lines) and the paper's (``paper`` {design: s [m]}, dashed). ``curves`` is a list of (design, E
    [Pa], s [m], dp [m]); ``crossings`` a table design, s_m. ``phi``: the same list with δφ [rad]
    (a rigid platform), drawn in a second panel [mrad]."""
    paper = paper or {}
    fig, axes = plt.subplots(
        2 if phi else 1, 1, figsize=(7.5, 8.6 if phi else 4.6), squeeze=False, layout="constrained"
    )
    ax = axes[0, 0]
    designs = list(dict.fromkeys(c[0] for c in curves))
    Es = sorted({c[1] for c in curves})
    styles = dict(zip(Es, [":", "-", "--"] if len(Es) == 3 else ["-"] * len(Es)))
    colours = dict(zip(designs, OKABE_ITO))
    if phi:
        a = axes[1, 0]
        for dk, E, s, v in phi:
            a.plot(
                s,
                v * DPHI_SCALE,
                styles.get(E, "-"),
                color=colours.get(dk),
                label=f"{dk} E = {E / 1e9:g} GPa",
            )
        a.set(
            xlabel="position along the path s [m]",
            ylabel=DPHI_LABEL,
            title=f"δφ along the path at E_min, E_mean, E_max{_mode(mode)}",
        )
        a.title.set_fontsize(9)
        a.grid(alpha=0.3)
        a.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    for dk, E, s, dp in curves:
        ax.plot(s, dp * 1e3, styles[E], color=colours[dk], label=f"{dk} E = {E / 1e9:g} GPa")
    for r in crossings.itertuples():
        ax.axvline(r.s_m, color=colours.get(r.design, "k"), lw=1.0, alpha=0.8)
    for dk, s in paper.items():
        if dk in colours and s is not None:
            ax.axvline(s, color=colours[dk], lw=1.0, ls=(0, (5, 3)))
    ours = ", ".join(f"{r.design} {r.s_m:.2f} m" for r in crossings.itertuples()) or "none"
    theirs = ", ".join(f"{d} {s:g} m" for d, s in paper.items()) or "not given"
    ax.set(
        xlabel=f"position along the path s [m]\ncrossings E_max/E_min, solid: ours ({ours}); dashed: paper ({theirs})",
        ylabel="‖δp‖ [mm]",
        title=f"‖δp‖ along the section 5.2 path (Fig. 19){_mode(mode)}",
    )
    ax.xaxis.label.set_fontsize(8)
    ax.title.set_fontsize(9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return save(fig, out)


def dead_length_figure(tab, d_default, out, mode=None):
    """Sensitivity of the paper-comparable numbers to the dead length d (not given by the paper):
    the CDPR4 plane extremes (left) and the optimal designs' index at E_mean (right), with the
    paper's values as horizontal lines of the same colour (dash-dot)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
    for c in [c for c in tab.columns if c.startswith("plane_")]:
        _, pk, stat, _ = c.split("_")
        col = KIND_COLOURS.get(pk)
        a.plot(
            tab.d_m,
            tab[c] * 1e3,
            "-" if stat == "max" else "--",
            marker="o",
            ms=3,
            color=col,
            label=f"{pk} plane {stat}",
        )
        v = paper_value(f"CDPR4_{pk} plane {stat}")
        if v is not None:
            a.axhline(v * 1e3, color=col, ls="-.", lw=0.8, label=f"paper {pk} plane {stat} {v * 1e3:g} mm")
    for i, c in enumerate([c for c in tab.columns if c.endswith("_index_m") and "_Emean_" in c]):
        dk = c.split("_")[0]
        col = OKABE_ITO[i % len(OKABE_ITO)]
        b.plot(tab.d_m, tab[c] * 1e3, marker="o", ms=3, color=col, label=f"{dk} index at E_mean")
        v = paper_value(f"{dk.replace('opt', '*')} index (Table 3)")
        if v is not None:
            b.axhline(v, color=col, ls="-.", lw=0.8, label=f"paper {dk.replace('opt', '*')} {v:g} mm")
    for ax, yl in ((a, "‖δp‖ on the plane [mm]"), (b, "global index mean ‖δp‖ [mm]")):
        ax.axvline(d_default, color="k", ls=":", label=f"default d = {d_default:g} m")
        ax.set(xlabel="dead length d [m]", ylabel=yl)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    fig.suptitle(f"Sensitivity of paper-comparable numbers to the dead length d{_mode(mode)}", fontsize=10)
    return save(fig, out)


#: |‖δp‖ physical − ‖δp‖ paper| [mm] below which a 3-cable point counts as the same solution in both modes.
SAME_MM = 1e-3


def comparison_difference_maps(tables, anchors, z, out):
    """Paper rule versus physics: ‖δp‖_physical − ‖δp‖_paper over the plane at height z, one panel
    per design (rows: robots, columns: pulley designs) on one diverging colour scale centred on 0.
    ``tables`` maps (robot, pulley) to a ``comparison.difference_table``; ``anchors`` maps a robot
    to its anchors A (m, 3). Grey: not ok in either mode; each panel's title counts the points ok
    in only one mode (left out of the difference). A robot with as many cables as degrees of
    freedom has no redundancy: both modes solve the same equations, the panel says so, and counts
    the points where they still found different solutions (more than ``SAME_MM`` apart: the same
    equations can have two; CDPR3 DR at (0, 2.87, 2.5) m hangs from cable 3 alone in physical mode,
    while the paper rule's three taut cables put P* 2 cm outside the anchors' footprint)."""
    robots = list(dict.fromkeys(r for r, _ in tables))
    pulleys = list(dict.fromkeys(p for _, p in tables))
    vmax = max(
        (np.nanmax(np.abs(t["diff"])) for t in tables.values() if t["diff"].notna().any()), default=1.0
    )
    vmax = vmax * 1e3 if vmax > 0 else 1.0
    fig, axes = plt.subplots(
        len(robots),
        len(pulleys),
        figsize=(5.2 * len(pulleys) + 1.2, 5.0 * len(robots)),
        squeeze=False,
        layout="constrained",
    )
    im = None
    for i, rk in enumerate(robots):
        for j, pk in enumerate(pulleys):
            ax = axes[i, j]
            t = tables.get((rk, pk))
            if t is None:
                ax.set_axis_off()
                continue
            A = anchors[rk]
            xs, ys, Z = _grid(t, t["diff"].to_numpy() * 1e3)
            ax.set_facecolor(NOT_OK_COLOUR)
            im = ax.pcolormesh(xs, ys, Z, cmap="RdBu_r", vmin=-vmax, vmax=vmax, shading="nearest")
            _anchors(ax, A)
            d = t["diff"].dropna() * 1e3
            one = _ok_in_one_mode(t)
            if len(A) <= 3:
                span = "3 cables: no redundancy, both modes equal"
                same = np.abs(d) <= SAME_MM
                if len(d) and same.all():
                    span += f" (|diff| ≤ {np.abs(d).max():.1g} mm)"
                elif len(d):  # the same equations can have two solutions: say so, not "equal"
                    span = (
                        f"3 cables: no redundancy, modes equal at {int(same.sum())} points;\n"
                        f"{int((~same).sum())} differ by up to {np.abs(d).max():.2g} mm (different equilibria)"
                    )
            else:
                span = f"{d.min():+.1f} to {d.max():+.1f} mm" if len(d) else "no common ok point"
            ok1 = f"\nok in one mode only (left out): {one}" if one is not None else ""
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{rk} {pk}: {span}{ok1}", aspect="equal")
            ax.title.set_fontsize(8)
    if im is not None:
        fig.colorbar(im, ax=axes.ravel().tolist(), label="‖δp‖ physical − ‖δp‖ paper rule [mm]")
    fig.suptitle(
        f"Physical equilibrium minus the paper rule (best 3-cable subset) at z = {z:g} m", fontsize=10
    )
    return save(fig, out)


def comparison_planes(tables, anchors, z, out):
    """Paty 2021 Fig. 12 in both modes on one scale: ‖δp‖ over the plane at height z, one column
    per design (robot and pulley), the paper rule (top) above the physical equilibrium (bottom); the
    two panels of a column share their filled levels (fine enough for the column's structure,
    labelled lines at every other level) and one colour bar, so a colour means the same error in
    both modes. Grey: not ok in that mode. ``tables`` maps (robot, pulley) to a
    ``comparison.difference_table``; ``anchors`` maps a robot to its anchors A (m, 3)."""
    keys = list(tables)
    fig, axes = plt.subplots(
        2, len(keys), figsize=(4.6 * len(keys), 9.8), squeeze=False, layout="constrained"
    )
    modes = (("paper", "paper rule (best 3-cable subset)"), ("physical", "physical equilibrium"))
    for j, (rk, pk) in enumerate(keys):
        t = tables[(rk, pk)]
        Zs = []
        for mode, _ in modes:
            ok = (t[f"status_{mode}"] == "ok").to_numpy()
            xs, ys, Z = _grid(t, np.where(ok, t[f"dp_{mode}"] * 1e3, np.nan))
            Zs.append(Z)
        finite = np.concatenate([Z[np.isfinite(Z)] for Z in Zs])
        levels = _round_levels(finite.min(), finite.max(), 10) if finite.size else None
        cf = None
        for i, ((mode, name), Z) in enumerate(zip(modes, Zs)):
            ax = axes[i, j]
            ax.set_facecolor(NOT_OK_COLOUR)
            if levels is not None and len(levels) > 1 and np.isfinite(Z).any():
                cf = ax.contourf(xs, ys, Z, levels=levels, cmap="viridis")
                cs = ax.contour(xs, ys, Z, levels=levels, colors="k", linewidths=0.4)
                ax.clabel(cs, levels[1:-1:2], fmt="%g", fontsize=6)
            _anchors(ax, anchors[rk])
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{rk} {pk}: {name}", aspect="equal")
            ax.title.set_fontsize(8)
        if cf is not None:
            fig.colorbar(cf, ax=axes[:, j].tolist(), location="bottom", label="‖δp‖ [mm]", shrink=0.8)
    fig.suptitle(
        f"‖δp‖ over the plane at z = {z:g} m in both modes, one scale per design (Fig. 12)", fontsize=10
    )
    return save(fig, out)


def _ok_in_one_mode(t):
    """Number of points of a difference table ok in exactly one mode, or None without the columns."""
    cols = [c for c in t.columns if c.startswith("status")]
    if len(cols) >= 2:
        a, b = (t[c] == "ok" for c in cols[:2])
        return int((a ^ b).sum())
    oks = [c for c in t.columns if c.startswith("dp_")]
    if len(oks) >= 2:
        a, b = (t[c].notna() for c in oks[:2])
        return int((a ^ b).sum())
    return None


#: Colours of the error budget's effects (Okabe & Ito, colour-blind safe).
EFFECT_COLOURS = {
    "pulley": OKABE_ITO[0],
    "elasticity": OKABE_ITO[2],
    "winch": OKABE_ITO[1],
    "interaction": "0.6",
    "all": "k",
}


def budget_bars(tab, out, xlabel="design [robot_pulley]"):
    """Error budget per design over RW_C: (a) stacked bars of each effect's share of the mean
    all-effects error (projection on its direction, so the stack sums to the mean ‖δp_all‖, marked
    by a black tick; negative shares go below zero), beside the mean ‖δp‖ of each effect alone;
    (b) the mean error left after compensating each effect, and all of them (exactly zero: written
    as text over its place, a log axis cannot draw it); (c), when the table has ``mean_rad`` (a
    rigid platform), the mean orientation error ‖δφ‖ of each effect alone, all together, the
    interaction and after compensating each. ``tab`` is the budget table (design, region, entry,
    mean_m, share_m, ...); rows of region RW_C are drawn. Legends sit outside."""
    t = tab[tab.region == "RW_C"]
    designs = list(dict.fromkeys(t.design))
    x = np.arange(len(designs))
    get = lambda d, e, c: float(t[(t.design == d) & (t.entry == e)][c].iloc[0]) * 1e3  # noqa: E731
    if "mean_rad" in t:
        fig, (a, b, c) = plt.subplots(1, 3, figsize=(max(16, 3.6 * len(designs)), 5.6), layout="constrained")
    else:
        fig, (a, b) = plt.subplots(1, 2, figsize=(max(11, 2.6 * len(designs)), 5.6), layout="constrained")
    pos, neg = np.zeros(len(designs)), np.zeros(len(designs))
    for e in ("pulley", "elasticity", "winch", "interaction"):
        v = np.array([get(d, e, "share_m") for d in designs])
        base = np.where(v >= 0, pos, neg)
        a.bar(x - 0.2, v, 0.38, bottom=base, color=EFFECT_COLOURS[e], label=f"{e} (share)")
        pos, neg = np.where(v >= 0, pos + v, pos), np.where(v < 0, neg + v, neg)
    tot = np.array([get(d, "all", "mean_m") for d in designs])
    a.scatter(x - 0.2, tot, marker="_", s=400, color="k", zorder=3, label="mean ‖δp_all‖")
    bottom = np.zeros(len(designs))
    for e in ("pulley", "elasticity", "winch"):
        v = np.array([get(d, e, "mean_m") for d in designs])
        a.bar(
            x + 0.2,
            v,
            0.38,
            bottom=bottom,
            color=EFFECT_COLOURS[e],
            alpha=0.45,
            hatch="//",
            label=f"{e} alone (hatched)",
        )
        bottom += v
    a.axhline(0, color="0.5", lw=0.8)
    a.set_xticks(x, designs, rotation=20)
    a.set(
        xlabel=xlabel,
        ylabel="mean ‖δp‖ [mm]",
        title="(a) shares of ‖δp_all‖ (left bar), each effect alone (right)",
    )
    a.title.set_fontsize(9)
    a.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    entries = ["all", "compensated_pulley", "compensated_elasticity", "compensated_winch", "compensated_all"]
    w = 0.8 / len(entries)
    zero_label = False
    for i, e in enumerate(entries):
        v = np.array([get(d, e, "mean_m") for d in designs])
        xe = x - 0.4 + (i + 0.5) * w
        b.bar(xe, v, w, color=OKABE_ITO[i], label=e.replace("compensated_", "compensating "))
        for xx, vv in zip(xe, v):
            if vv == 0.0:
                b.annotate("0", (xx, 1e-3), ha="center", va="bottom", fontsize=7, color=OKABE_ITO[i])
                zero_label = True
    b.set_xticks(x, designs, rotation=20)
    b.set_yscale("symlog", linthresh=1e-3)
    b.set(
        xlabel=xlabel,
        ylabel="mean ‖δp‖ [mm]",
        title="(b) error left after compensating" + (" ('0': exactly zero)" if zero_label else ""),
    )
    b.title.set_fontsize(9)
    b.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    if "mean_rad" in t:
        phi = ["pulley", "elasticity", "winch", "interaction", "all", *entries[1:]]
        w = 0.8 / len(phi)
        for i, e in enumerate(phi):
            v = np.array([get(d, e, "mean_rad") for d in designs])
            colour = EFFECT_COLOURS.get(e) or OKABE_ITO[entries.index(e)]  # as in (b)
            hatch = "//" if e.startswith("compensated_") else None  # (b)'s colours: tell them from (a)'s
            c.bar(
                x - 0.4 + (i + 0.5) * w,
                v,
                w,
                color=colour,
                hatch=hatch,
                edgecolor="w" if hatch else None,
                label=e.replace("compensated_", "compensating "),
            )
        c.set_xticks(x, designs, rotation=20)
        c.set_yscale("symlog", linthresh=1e-3)
        c.set(xlabel=xlabel, ylabel="mean ‖δφ‖ [mrad]", title="(c) orientation error of each entry")
        c.title.set_fontsize(9)
        c.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3, frameon=False)
    fig.suptitle(
        "Error budget over RW_C: pulley geometry, cable elasticity, winch exit point (physical equilibrium)",
        fontsize=10,
    )
    return save(fig, out)


def budget_paths(paths, out):
    """Error budget along the section 3.3.1 paths: ‖δp‖ of each effect alone, all together, the
    interaction and the error left after compensating pulley geometry, versus the arc length s; one
    panel per design, one legend for all under the panels. ``paths`` maps a design label to its
    budget path table (s and one column of ‖δp‖ [m] per budget entry, NaN where a variant is not ok)."""
    labels = list(paths)
    cols = 2 if len(labels) > 1 else 1
    rows = int(np.ceil(len(labels) / cols))
    fig, axes = plt.subplots(
        rows, cols, figsize=(6.5 * cols, 3.8 * rows + 0.8), squeeze=False, layout="constrained"
    )
    for ax, label in zip(axes.ravel(), labels):
        df = paths[label]
        for e in ("pulley", "elasticity", "winch", "interaction", "all"):
            ax.plot(df.s, df[e] * 1e3, color=EFFECT_COLOURS[e], lw=1.8 if e == "all" else 1.1, label=e)
        ax.plot(df.s, df["compensated_pulley"] * 1e3, "k:", lw=1, label="after compensating pulleys")
        ax.set_yscale("log")
        ax.set(xlabel="position along the path s [m]", ylabel="‖δp‖ [mm]", title=label)
        ax.grid(alpha=0.3, which="both")
    handles, names = axes.ravel()[0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncol=6, fontsize=7)
    for ax in axes.ravel()[len(labels) :]:
        ax.set_axis_off()
    fig.suptitle("Error budget along the section 3.3.1 paths (physical equilibrium)", fontsize=10)
    return save(fig, out)


# ---- uncertainty and sensitivity (beyond the paper: cdpr.analyses.uncertainty) ---------------------------
UQ_CASES = CASES  # the compensated case only where the study ran it (``study.uq_cases``)


def _uq_designs(tables):
    return list(dict.fromkeys(d for d, _ in tables))


def _uq_cases(tables):
    """The cases present among {(design, case): table}, in ``UQ_CASES`` order (a paper-mode study
    has no compensated case: ``study.uq_cases``)."""
    cases = {c for _, c in tables}
    return [c for c in UQ_CASES if c in cases]


def _colour_violin(parts, colour, alpha):
    """Bodies, whiskers (extrema bars) and medians of a violin in one colour."""
    for b in parts["bodies"]:
        b.set_facecolor(colour)
        b.set_edgecolor(colour)
        b.set_alpha(alpha)
    for key in ("cbars", "cmins", "cmaxes", "cmedians"):
        if key in parts:
            parts[key].set_color(colour)


def uq_index_distribution(linear, tolerances, index_vs_E, paper, out, mode=None):
    """The global index of each optimal design under per-cable moduli (Monte Carlo, one violin per
    design) beside the common-E band of the paper's section 5.1 (our sweep, and the paper's numbers
    when given), and under every declared parameter (Saltelli's independent rows); uncompensated
    (left) and compensated (right). Each design has one colour (violins, whiskers, bars); the key
    under the panels says what each mark is. A study without the compensated case (``study.uq_cases``)
    gets the left panel only.

    ``linear``, ``tolerances``: {(design, case): table} of ``uq.linear_samples`` and of
    ``uq.sobol``'s rows; ``index_vs_E``: the elasticity sweep (design, E_Pa, index_m) or
    None; ``paper``: {design: (index, minus, plus)} [m]."""

    designs = _uq_designs(linear)
    cases = _uq_cases(linear)
    fig, axes = plt.subplots(
        1,
        len(cases),
        figsize=(5 + 10 * len(cases) / 2, 5.8),
        gridspec_kw={"width_ratios": [2, 1][: len(cases)]},
        squeeze=False,
        layout="constrained",
    )
    colours = dict(zip(designs, OKABE_ITO))
    for ax, case in zip(axes[0], cases):
        ticks, labels, x = [], [], 0.0
        for dk in designs:
            lin = linear.get((dk, case))
            if lin is None:
                continue
            nominal = lin.loc[lin["sample"] == -1, "index_m"].iloc[0] * 1e3
            vals = lin.loc[lin["sample"] >= 0, "index_m"].dropna().to_numpy() * 1e3
            parts = ax.violinplot([vals], positions=[x], widths=0.7, showextrema=True, showmedians=True)
            _colour_violin(parts, colours[dk], 0.45)
            ax.plot([x - 0.35, x + 0.35], [nominal, nominal], "k:", lw=1)
            ticks.append(x)
            labels.append(f"{dk}\nper-cable E\nn = {len(vals)}")
            x += 1.0
            if case == "uncompensated" and index_vs_E is not None:
                g = index_vs_E[index_vs_E.design == dk]
                if len(g):
                    lo, hi = g.index_m.min() * 1e3, g.index_m.max() * 1e3
                    ax.vlines(x, lo, hi, color=colours[dk], lw=6, alpha=0.7)
                    ax.plot(x, nominal, "k_", ms=14)
                    ticks.append(x)
                    labels.append(f"{dk}\ncommon E\nours")
                    x += 1.0
                if dk in paper:
                    mid, minus, plus = (v * 1e3 for v in paper[dk])
                    ax.vlines(x, mid - minus, mid + plus, color=colours[dk], lw=6, alpha=0.35, hatch="//")
                    ax.plot(x, mid, "k_", ms=14)
                    ticks.append(x)
                    labels.append(f"{dk}\ncommon E\npaper")
                    x += 1.0
            tol = tolerances.get((dk, case))
            if tol is not None and len(tol):
                parts = ax.violinplot(
                    [tol.index_m.to_numpy() * 1e3], positions=[x], widths=0.7, showextrema=True
                )
                _colour_violin(parts, colours[dk], 0.2)
                ticks.append(x)
                labels.append(f"{dk}\nall param.\nn = {len(tol)}")
                x += 1.5
        ax.set_xticks(ticks, labels, fontsize=7)
        ax.set(xlabel="design and sampling [-]", ylabel="global index mean ‖δp‖ over RW_C [mm]", title=case)
        ax.grid(alpha=0.3, axis="y")
    key = [Patch(color=colours[d], alpha=0.6, label=d) for d in designs] + [
        Line2D([], [], color="k", ls=":", label="nominal robot (dotted)"),
        Line2D([], [], color="0.4", lw=6, alpha=0.7, label="common-E band [min, max] (bar)"),
        Line2D([], [], color="k", marker="_", ls="", ms=14, label="index at E_mean (tick)"),
        Patch(color="0.4", alpha=0.45, label="violin: samples; whiskers: min, median, max"),
    ]
    fig.legend(handles=key, loc="outside lower center", ncol=len(key), fontsize=7)
    fig.suptitle(
        f"Global index under per-cable moduli beside the common-E band (section 5.1){_mode(mode)}",
        fontsize=10,
    )
    return save(fig, out)


def uq_path_bands(bands, common, out, mode=None, common_mode=None):
    """‖δp‖ along the section 5.2 path: 5-50-95 % band under per-cable moduli for each design
    (columns), uncompensated beside the three common-E curves of the elasticity section (top) and
    compensated (bottom). ``bands``: {(design, case): ``uncertainty.path_bands`` table}; ``common``:
    list of (design, E [Pa], s [m], dp [m]) of the common-E paths (Fig. 19), computed in
    ``common_mode`` (named in the legend when it differs from ``mode``)."""
    designs, cases = _uq_designs(bands), _uq_cases(bands)
    fig, axes = plt.subplots(
        len(cases),
        len(designs),
        figsize=(5.5 * len(designs), 3.8 * len(cases)),
        squeeze=False,
        layout="constrained",
    )
    Es = sorted({c[1] for c in common})
    styles = dict(zip(Es, [":", "-", "--"] if len(Es) == 3 else ["-"] * len(Es)))
    other = f" ({MODE_TITLES[common_mode].split(' (')[0]})" if common_mode and common_mode != mode else ""
    for j, dk in enumerate(designs):
        for i, case in enumerate(cases):
            ax = axes[i, j]
            b = bands.get((dk, case))
            if b is None:
                ax.set_visible(False)
                continue
            ax.fill_between(
                b.s, b.q05_m * 1e3, b.q95_m * 1e3, color=OKABE_ITO[0], alpha=0.3, label="5-95 % per-cable E"
            )
            ax.plot(b.s, b.q50_m * 1e3, color=OKABE_ITO[0], label="median per-cable E")
            ax.plot(b.s, b.dp_nominal_m * 1e3, "k", lw=0.8, alpha=0.6, label="nominal")
            if case == "uncompensated":
                for d, E, s, dp in common:
                    if d == dk:
                        ax.plot(
                            s,
                            dp * 1e3,
                            styles[E],
                            color=OKABE_ITO[1],
                            lw=1,
                            label=f"common E = {E / 1e9:g} GPa{other}",
                        )
            ax.set(xlabel="position along the path s [m]", ylabel="‖δp‖ [mm]", title=f"{dk} {case}")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False)
    fig.suptitle(
        f"‖δp‖ along the section 5.2 path under per-cable moduli (Fig. 19 extended){_mode(mode)}", fontsize=10
    )
    return save(fig, out)


def _sobol_top(tab):
    """Top of a Sobol panel's y axis: 1.05, raised to show the upper whiskers (index + 95 %
    interval) of the estimates that pass it, up to 1.5 (few base samples give wider intervals)."""
    if not len(tab):
        return 1.05
    whisker = max(float((tab.ST + tab.ST_conf).max()), float((tab.S1 + tab.get("S1_conf", 0)).max()))
    return float(min(1.5, max(1.05, whisker + 0.05)))


def uq_sobol(tab, out, mode=None):
    """Sobol total (bars) and first-order (dots) indices of the global index, both with their 95 %
    confidence intervals, per parameter group (left of each pair) and per parameter (right: each
    cable's E_i, d_i, h_i, r_p_i, anchor coordinates and the mass), for each design before and after
    compensation (rows)."""
    g = tab[tab.output == "index"]
    designs = list(dict.fromkeys(g.design))
    cases = [c for c in UQ_CASES if c in set(g.case)]
    fig, axes = plt.subplots(
        len(cases),
        2 * len(designs),
        figsize=(6.5 * len(designs) + 1, 3.75 * len(cases) + 0.5 * (len(cases) == 1)),
        squeeze=False,
        layout="constrained",
        gridspec_kw={"width_ratios": [1, 3] * len(designs)},
    )
    for j, dk in enumerate(designs):
        for i, case in enumerate(cases):
            for k, level in enumerate(("group", "parameter")):
                ax = axes[i, 2 * j + k]
                d = g[(g.design == dk) & (g.case == case) & (g.level == level)]
                x = np.arange(len(d))
                ax.bar(
                    x, d.ST, yerr=d.ST_conf, color=OKABE_ITO[0], alpha=0.7, capsize=2, label="total ST ± 95 %"
                )
                ax.errorbar(
                    x,
                    d.S1,
                    yerr=d.S1_conf if "S1_conf" in d else None,
                    fmt="o",
                    color="k",
                    ms=3,
                    capsize=2,
                    label="first order S1 ± 95 %",
                )
                ax.axhline(0, color="0.5", lw=0.6)
                ax.set_xticks(
                    x,
                    d.name,
                    rotation=90 if level == "parameter" else 0,
                    fontsize=6 if level == "parameter" else 8,
                )
                # one y range per design and case (groups and parameters), intervals below -1 clipped
                pair = g[(g.design == dk) & (g.case == case)]
                lo = (
                    max(-1.0, min(0.0, float((pair.S1 - pair.get("S1_conf", 0)).min()) - 0.05))
                    if len(pair)
                    else 0.0
                )
                ax.set(
                    xlabel=f"{level} [-]",
                    ylabel="Sobol index [-]" if k == 0 else "",
                    title=f"{dk} {case}: {'groups' if k == 0 else 'per parameter'}",
                    ylim=(lo, _sobol_top(pair)),
                )
                ax.title.set_fontsize(8)
                ax.grid(alpha=0.3, axis="y")
                if k == 1:
                    ax.tick_params(labelleft=False)
    handles, names = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncol=2, fontsize=7)
    fig.suptitle(
        f"Which uncertainty drives the global index (SALib, Saltelli sampling){_mode(mode)}", fontsize=10
    )
    return save(fig, out)


def uq_dominant_map(maps, A, z, out, mode=None):
    """The parameter whose first-order contribution to the spread of ‖δp‖ is the largest, on the
    plane z (columns: designs; rows: before and after compensation); hatched where it explains less
    than half of the spread. ``maps``: {(design, case): ``uq.dominant_map`` table}."""
    designs = _uq_designs(maps)
    names = sorted({n for df in maps.values() for n in df.dominant.dropna().unique() if n})
    cmap = plt.get_cmap("tab20", max(len(names), 1))
    code = {n: k for k, n in enumerate(names)}
    cases = _uq_cases(maps)
    fig, axes = plt.subplots(
        len(cases),
        len(designs),
        figsize=(5 * len(designs) + 2, 4.75 * len(cases)),
        squeeze=False,
        layout="constrained",
    )
    for j, dk in enumerate(designs):
        for i, case in enumerate(cases):
            ax = axes[i, j]
            df = maps.get((dk, case))
            if df is None:
                ax.set_visible(False)
                continue
            val = df.dominant.map(lambda n: code.get(n, np.nan)).astype(float)
            xs, ys, Z = _grid(df, val.to_numpy())
            _, _, share = _grid(df, df.share.to_numpy())
            ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5, shading="nearest")
            ax.contourf(
                xs, ys, np.where(share < 0.5, 1.0, np.nan), levels=[0.5, 1.5], colors="none", hatches=["///"]
            )
            _anchors(ax, A)
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{dk} {case}", aspect="equal")
    handles = [Patch(color=cmap(code[n]), label=n) for n in names]
    fig.legend(handles=handles, loc="outside right center", fontsize=7, title="dominant")
    fig.suptitle(f"Dominant uncertain parameter at z = {z:g} m (hatched: < 50 %){_mode(mode)}", fontsize=10)
    return save(fig, out)


def uq_residual_map(maps, A, z, out, mode=None):
    """What compensation leaves, on the plane z (beyond the paper): for each design (columns) and
    case the study ran, the nominal robot's ‖δp‖ (uncompensated: the pose error the paper studies;
    compensated: the round-trip residual of the compensated lengths, 0 up to rounding) and the
    first-order spread of ‖δp‖ under the declared parameters (RMS of the per-parameter
    contributions, ``uq.dominant_map``'s ``rms_m``). Rows: nominal then spread, per case; grey:
    not ok. ``maps``: {(design, case): ``uq.dominant_map`` table}."""
    designs, cases = _uq_designs(maps), _uq_cases(maps)
    rows = [(case, col) for case in cases for col in ("dp_nominal_m", "rms_m")]
    fig, axes = plt.subplots(
        len(rows),
        len(designs),
        figsize=(5 * len(designs) + 1.5, 4.4 * len(rows)),
        squeeze=False,
        layout="constrained",
    )
    what = {"dp_nominal_m": "nominal robot ‖δp‖", "rms_m": "spread of ‖δp‖ (RMS, declared parameters)"}
    for i, (case, col) in enumerate(rows):
        for j, dk in enumerate(designs):
            ax = axes[i, j]
            df = maps.get((dk, case))
            if df is None:
                ax.set_visible(False)
                continue
            xs, ys, Z = _grid(df, df[col].to_numpy() * 1e3)
            ax.set_facecolor(NOT_OK_COLOUR)
            finite = Z[np.isfinite(Z)]
            top = float(np.abs(finite).max()) if finite.size else 0.0
            if top < 1e-6:  # the compensated nominal residual: zero up to rounding, stated
                ax.pcolormesh(
                    xs,
                    ys,
                    np.where(np.isfinite(Z), 0.0, np.nan),
                    cmap="Greys",
                    vmin=0,
                    vmax=1,
                    shading="nearest",
                )
                label = f"max {top:.1g} mm (round trip)"
            else:
                levels = _round_levels(float(finite.min()), float(finite.max()), 10)
                cf = ax.contourf(xs, ys, Z, levels=levels, cmap="viridis")
                fig.colorbar(cf, ax=ax, label=f"{what[col].split(' (')[0]} [mm]", shrink=0.8)
                label = f"{finite.min():.3g} to {finite.max():.3g} mm"
            _anchors(ax, A)
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{dk} {case}: {what[col]}\n{label}", aspect="equal")
            ax.title.set_fontsize(8)
    fig.suptitle(f"What compensation leaves at z = {z:g} m (beyond the paper){_mode(mode)}", fontsize=10)
    return save(fig, out)


def uq_agreement(mc, out, mode=None):
    """The global index of each full-solve Monte Carlo sample against its linearised value, one
    panel per design and case, with the line of equality."""
    keys = sorted(mc)
    fig, axes = plt.subplots(
        1, len(keys), figsize=(3.8 * len(keys), 4.2), squeeze=False, layout="constrained"
    )
    for ax, key in zip(axes[0], keys):
        df = mc[key]
        ax.plot(df.index_full_m * 1e3, df.index_lin_m * 1e3, "o", ms=3, color=OKABE_ITO[0])
        lo = np.nanmin([df.index_full_m.min(), df.index_lin_m.min()]) * 1e3
        hi = np.nanmax([df.index_full_m.max(), df.index_lin_m.max()]) * 1e3
        ax.plot([lo, hi], [lo, hi], "k:", lw=1)
        ax.set(xlabel="full solves [mm]", ylabel="linearised [mm]", title=f"{key[0]}\n{key[1]}")
        ax.title.set_fontsize(9)
        ax.tick_params(axis="x", labelrotation=30, labelsize=7)
        ax.grid(alpha=0.3)
    fig.suptitle(f"Global index per sample: linearised against full solves{_mode(mode)}", fontsize=10)
    return save(fig, out)


def parity_chart(summary_tab, out, mode=None):
    """Every paper number against ours (``summary.csv`` rows with a paper value), one panel per
    unit, with the line of equality and each number's tolerance band (|ours − paper| ≤ tolerance:
    reproduced, filled marker; else open marker)."""
    t = summary_tab[summary_tab.paper.notna() & summary_tab.ours.notna()].copy()
    t = t[pd_numeric(t.paper) & pd_numeric(t.ours)]
    units = list(dict.fromkeys(t.unit.astype(str)))
    fig, axes = plt.subplots(
        1, max(len(units), 1), figsize=(4.2 * max(len(units), 1), 4.6), squeeze=False, layout="constrained"
    )
    for ax, unit in zip(axes[0], units):
        g = t[t.unit.astype(str) == unit]
        p, o, tol = (g[c].astype(float).to_numpy() for c in ("paper", "ours", "tolerance"))
        ok = np.abs(o - p) <= tol + 1e-12
        ax.errorbar(p, p, yerr=tol, fmt="none", ecolor="0.6", capsize=3, lw=4, alpha=0.5)
        ax.plot(p[ok], o[ok], "o", color=OKABE_ITO[2], ms=5, label=f"within tolerance ({ok.sum()})")
        ax.plot(p[~ok], o[~ok], "o", mfc="none", color=OKABE_ITO[1], ms=5, label=f"outside ({(~ok).sum()})")
        lo, hi = float(min(p.min(), o.min())), float(max(p.max(), o.max()))
        pad = 0.05 * (hi - lo if hi > lo else 1.0)
        ax.plot([lo - pad, hi + pad], [lo - pad, hi + pad], "k:", lw=0.8)
        ax.set(xlabel=f"paper [{unit}]", ylabel=f"ours [{unit}]", title=f"{len(g)} numbers in {unit}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    fig.suptitle(f"Paper numbers against ours (grey bar: tolerance){_mode(mode)}", fontsize=10)
    return save(fig, out)


def pd_numeric(col):
    """Whether each entry of ``col`` reads as a finite number."""

    v = pd.to_numeric(col, errors="coerce")
    return np.isfinite(v.to_numpy(dtype=float))


#: Line styles of the two redundancy modes in the overlays.
MODE_STYLES = {"paper": "-", "physical": "--"}


def comparison_overlays(data, out):
    """Paper rule and physical equilibrium drawn over each other for Fig. 10 (‖δp‖ along the
    CDPR4 path), Fig. 14 (R_V versus the limit), Fig. 18 (index versus E) and Fig. 19 (the section
    5.2 path at E_mean); solid: paper rule (best 3-cable subset), dashed: physical equilibrium.
    ``data`` maps a mode to {"paths": {label: path table}, "volumes": volumes table,
    "index_vs_E": table, "paths_E": [(design, s, dp)]} (any key may be missing)."""
    fig, axes = plt.subplots(2, 2, figsize=(13, 9), layout="constrained")
    (a, b), (c, d) = axes
    for mode, dd in data.items():
        ls = MODE_STYLES.get(mode, "-")
        tag = "paper rule" if mode == "paper" else "physical"
        for label, df in dd.get("paths", {}).items():
            kind = label.split("_", 1)[-1]
            a.plot(
                df.s,
                df.dp.where(df.status == "ok") * 1e3,
                ls,
                color=KIND_COLOURS.get(kind),
                label=f"{label}, {tag}",
            )
        v = dd.get("volumes")
        if v is not None:
            for (rk, pk), g in v.groupby(["robot", "pulley"], sort=False):
                if rk == "CDPR4":
                    b.plot(g.limit_m * 1e3, g.R_V, ls, color=KIND_COLOURS.get(pk), label=f"{rk} {pk}, {tag}")
        e = dd.get("index_vs_E")
        if e is not None:
            for i, (dk, g) in enumerate(e.groupby("design", sort=False)):
                c.plot(
                    g.E_Pa / 1e9,
                    g.index_m * 1e3,
                    ls,
                    marker="o",
                    ms=3,
                    color=OKABE_ITO[i],
                    label=f"{dk}, {tag}",
                )
        for i, (dk, s, dp) in enumerate(dd.get("paths_E", [])):
            d.plot(s, dp * 1e3, ls, color=OKABE_ITO[i % len(OKABE_ITO)], label=f"{dk} at E_mean, {tag}")
    a.set(
        xlabel="position along the path s [m]", ylabel="‖δp‖ [mm]", title="Fig. 10: CDPR4 section 3.3.1 path"
    )
    b.set(
        xlabel="error limit [mm]",
        ylabel="R_V = V_L / V_T [-]",
        title="Fig. 14: CDPR4 error-limited volume ratio",
    )
    c.set(
        xlabel="Young's modulus E [GPa]",
        ylabel="global index mean ‖δp‖ [mm]",
        title="Fig. 18: index versus E",
    )
    d.set(
        xlabel="position along the path s [m]",
        ylabel="‖δp‖ [mm]",
        title="Fig. 19: section 5.2 path at E_mean",
    )
    for ax in axes.ravel():
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    fig.suptitle(
        "Paper rule (solid) against physical equilibrium (dashed): Fig. 10, 14, 18, 19 overlaid", fontsize=10
    )
    return save(fig, out)


# ---- the robot in 3-D (``cdpr view``, the study's robot figure) --------------------------------
#: Colours and line styles of the boxes ``robot_view`` draws, in the order given.
BOX_STYLES = [("0.45", "--"), ("tab:purple", "-"), ("tab:brown", "-."), ("tab:olive", ":")]


def _box_edges(box):
    """The 12 edges of the axis-aligned box (xmin, xmax, ymin, ymax, zmin, zmax) [m], each (2, 3)."""
    b = np.asarray(box, dtype=float)
    corners = np.array([[b[i], b[2 + j], b[4 + k]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    # corners differ in one coordinate along an edge: index bits (x, y, z) = (4, 2, 1)
    return [corners[[c, c | bit]] for c in range(8) for bit in (4, 2, 1) if not c & bit]


def _anchor_groups(A, span):
    """Indices (0-based) of the anchors grouped by distance below 4 % of ``span`` [m]: one label per group
    (the crossed cables of a robot leave their pulleys in pairs, whose numbers would overlap)."""
    groups = []
    for i, a in enumerate(A):
        for g in groups:
            if np.linalg.norm(A[g[0]] - a) < 0.04 * span:
                g.append(i)
                break
        else:
            groups.append([i])
    return groups


def robot_view(geom, out, boxes=None, mode=None):
    """A 3-D picture of a robot at a pose: the joint points A_i with their cable numbers, the swivel
    axes k_i, the sheaves, the dead lengths C_i → K_i, the cables D_i → B_i, the platform (the
    attachment points' hull, its centre of mass and reference point) and the given boxes as
    wireframes. Nothing is solved: ``geom`` is ``cdpr.analyses.scans.pose_geometry`` (the desired
    pose). Drawn to equal scale on every axis.

    Parameters
    ----------
    geom : dict
        ``scans.pose_geometry`` of the robot at the pose.
    out : str or Path
        The .png written (a .pdf beside it, ``save``).
    boxes : dict, optional
        Label -> box (xmin, xmax, ymin, ymax, zmin, zmax) [m] drawn as a wireframe (e.g. the frame
        box of the volumes' grid, the study's RW_C), in the styles of ``BOX_STYLES``.
    mode : {"paper", "physical", None}
        The study's redundancy mode, named in the title (``cdpr view`` has none).
    """
    boxes = dict(boxes or {})
    A, B, axis = geom["A"], geom["B"], geom["axis"]
    allp = np.vstack([A, B, geom["C"], geom["H"]] + [e for b in boxes.values() for e in _box_edges(b)])
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    span = float((hi - lo).max())
    lo, hi = lo - 0.03 * span, hi + 0.03 * span
    fig = plt.figure(figsize=(8.0, 7.0), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    handles = []
    for (label, box), (colour, ls) in zip(boxes.items(), BOX_STYLES * 4):
        for e in _box_edges(box):
            ax.plot(*e.T, color=colour, ls=ls, lw=0.9)
        handles.append(Line2D([], [], color=colour, ls=ls, label=label))
    ax.scatter(*A.T, color="k", marker="^", s=18, depthshade=False)
    for i in range(len(A)):
        ax.plot(*np.stack([geom["C"][i], geom["K"][i]]).T, color="0.6", lw=0.8)
        ax.plot(*np.stack([geom["D"][i], B[i]]).T, color="tab:blue", lw=1.1)
        ax.plot(*np.stack([A[i], A[i] + 0.06 * span * axis[i]]).T, color="tab:red", lw=1.2)
        if np.isfinite(geom["sheave"][i]).all():
            ax.plot(*geom["sheave"][i].T, color="tab:orange", lw=0.9)
    for g in _anchor_groups(A, span):
        c = A[g].mean(axis=0)
        ax.text(*(c + 0.04 * span * np.array([0, 0, 1])), ",".join(str(i + 1) for i in g), fontsize=7)
    if not geom["point_mass"]:
        try:
            for s in ConvexHull(B).simplices:
                ax.plot(*B[np.append(s, s[0])].T, color="tab:green", lw=0.5)
        except Exception:  # coplanar attachment points: their outline
            ax.plot(*np.vstack([B, B[:1]]).T, color="tab:green", lw=0.8)
        ax.scatter(*geom["com"], color="tab:green", marker="x", s=30, depthshade=False)
        handles += [
            Line2D([], [], color="tab:green", lw=0.5, label="platform: attachment points B_i (hull)"),
            Line2D([], [], color="tab:green", marker="x", ls="none", label="centre of mass"),
        ]
    ax.scatter(*geom["p"], color="tab:green", s=20, depthshade=False)
    handles += [
        Line2D([], [], color="tab:green", marker="o", ls="none", label="platform point p"),
        Line2D([], [], color="k", marker="^", ls="none", label="joint points A_i (cable numbers)"),
        Line2D([], [], color="tab:red", label="swivel axes k_i"),
        Line2D([], [], color="tab:orange", label="sheaves (radius r_p)"),
        Line2D([], [], color="0.6", label="dead length C_i → K_i"),
        Line2D([], [], color="tab:blue", label="cables D_i → B_i"),
    ]
    ax.set(xlim=(lo[0], hi[0]), ylim=(lo[1], hi[1]), zlim=(lo[2], hi[2]))
    ax.set_box_aspect(hi - lo, zoom=0.9)
    ax.set_xlabel("x [m]", labelpad=4)
    ax.set_ylabel("y [m]", labelpad=4)
    ax.set_zlabel("z [m]", labelpad=2)
    ax.tick_params(labelsize=7, pad=0)
    rv = geom["rotvec"]
    pose = f"p = [{', '.join(f'{x:.3g}' for x in geom['p'])}] m, rotvec = [{', '.join(f'{x:.3g}' for x in rv)}] rad"
    ax.set_title(f"{geom['name']} at the desired pose {pose}{_mode(mode)}", fontsize=9, wrap=True)
    fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=7, frameon=False)
    return save(fig, out)


# ---- the pulley axis convention (docs/spatial.md, "The pulley axis") ------------------------------------
#: Where each point's label sits, as a direction of its offset (s, w) from the point when no other
#: rule applies (K and D are labelled radially outward from the sheave centre).
_PLANE_LABEL_DIR = {"C": (1.0, 0.0), "A": (-1.0, 0.6), "H": (0.7, 0.7), "B": (0.6, 0.8)}


def _label(ax, text, xy, direction, colour="k", pt=9.0):
    """``text`` next to the data point ``xy``, ``pt`` points away along ``direction``, aligned so
    that it grows away from the point."""
    u = np.asarray(direction, dtype=float)
    u = u / max(float(np.linalg.norm(u)), 1e-12)
    ha = "left" if u[0] > 0.3 else ("right" if u[0] < -0.3 else "center")
    va = "bottom" if u[1] > 0.3 else ("top" if u[1] < -0.3 else "center")
    ax.annotate(
        text,
        xy,
        xytext=(pt * u[0], pt * u[1]),
        textcoords="offset points",
        ha=ha,
        va=va,
        fontsize=9,
        color=colour,
    )


def _pulley_plane_panel(ax, g, lim):
    """One pulley drawn in its cable plane (``scans.pulley_plane_geometry`` ``g``) on ``ax`` with the
    data limits ``lim`` = (s0, s1, w0, w1) [m]."""
    P = g["plane"]
    s0, s1, w0, w1 = lim
    ax.plot([0.0, 0.0], [w0, w1 - 0.02 * (w1 - w0)], color="k", ls=(0, (4, 3)), lw=0.8, zorder=1)
    ax.annotate(
        "",
        (0.0, w1 - 0.02 * (w1 - w0)),
        xytext=(0.0, w1 - 0.12 * (w1 - w0)),
        arrowprops={"arrowstyle": "-|>", "color": "k", "lw": 1.0},
    )
    ax.annotate(
        r"$\mathbf{k}_i$",
        (0.0, w1 - 0.04 * (w1 - w0)),
        xytext=(6, 0),
        textcoords="offset points",
        ha="left",
        va="center",
        fontsize=10,
    )
    if np.isfinite(g["sheave"]).all():
        ax.plot(*g["sheave"].T, color="tab:orange", lw=1.0, zorder=2)
    cable = {"color": "tab:blue", "lw": 2.0, "zorder": 3, "solid_capstyle": "butt"}
    ax.plot(*np.stack([P["C"], P["K"]]).T, **cable)
    ax.plot(*g["arc"].T, **cable)
    ax.plot(*np.stack([P["D"], P["B"]]).T, **cable)
    ax.plot(*np.stack([P["A"], P["H"]]).T, color="tab:red", lw=1.6, zorder=4)
    arm = P["H"] - P["A"]
    if np.linalg.norm(arm) > 0:
        # h beside the arm, 30 % of the way from A: on the side of +s (below a horizontal SR arm,
        # inside the sheave; right of a DR arm, between it and the arc)
        n = np.array([arm[1], -arm[0]]) / np.linalg.norm(arm)
        if n[0] < -1e-9 or (abs(n[0]) <= 1e-9 and n[1] > 0):
            n = -n
        _label(ax, "$h$", P["A"] + 0.3 * arm, n, colour="tab:red", pt=4.0)
    names = {"C": "$C_i$", "A": "$A_i$", "H": "$H_i$", "K": "$K_i$", "D": "$D_i$", "B": "$B_i$"}
    same = np.linalg.norm(P["K"] - P["A"]) < 1e-3 * (s1 - s0)
    for n, xy in P.items():
        if same and n == "K":
            continue
        text = "$A_i = K_i$" if same and n == "A" else names[n]
        if n in ("K", "D"):
            d = xy - P["H"]
        else:
            d = _PLANE_LABEL_DIR[n]
        ax.plot(*xy, "o", color="k", ms=3.5, zorder=5)
        _label(ax, text, xy, d)
    ax.set(xlim=(s0, s1), ylim=(w0, w1), aspect="equal")
    ax.set_xlabel(r"s [m]  (perpendicular to $\mathbf{k}_i$, toward $B_i$)")
    ax.set_ylabel(r"w [m]  (along $\mathbf{k}_i$)")
    h, r = g["h"] * 1e3, g["r_p"] * 1e3
    arms = f"h = r_p = {h:.0f} mm" if abs(h - r) < 1e-9 else f"h = {h:.0f} mm, r_p = {r:.0f} mm"
    ax.set_title(
        f"{g['kind']}, {arms}\nwrap γ = {np.degrees(g['gamma']):.1f}°, |B−D| = l_E = {g['l_E']:.3f} m, "
        f"L_TE = {g['L_TE']:.3f} m",
        fontsize=9,
    )


def _swivel_panel(ax, g):
    """The pulley seen from the tip of k_i (``g`` of ``scans.pulley_plane_geometry``): i_i (the
    swivel angle's zero), j_i, the trace of the cable plane toward B and the swivel angle."""
    top = g["top"]
    b = top["B"]
    L = 0.45 * float(np.linalg.norm(b))
    arrow = {"arrowstyle": "-|>", "color": "k", "lw": 1.0}
    ax.annotate("", (L, 0.0), xytext=(0.0, 0.0), arrowprops=arrow)
    ax.annotate("", (0.0, L), xytext=(0.0, 0.0), arrowprops=arrow)
    _label(ax, r"$\mathbf{i}_i$ (zero)", (L, 0.0), (0.0, -1.0))
    _label(ax, r"$\mathbf{j}_i$", (0.0, L), (-1.0, 0.0))
    e = g["e_s"]
    ax.plot([0.0, b[0]], [0.0, b[1]], color="tab:blue", ls=(0, (4, 3)), lw=1.0)
    H, r = top["H"], g["r_p"]
    if r > 0:
        ax.plot(*np.stack([H - r * e, H + r * e]).T, color="tab:orange", lw=3.0, solid_capstyle="butt")
    ax.plot(0.0, 0.0, "o", color="k", ms=3.5)
    ax.plot(*b, "o", color="k", ms=3.5)
    _label(ax, "$A_i$", (0.0, 0.0), (-1.0, -1.0))
    _label(ax, "$B_i$ (projected)", b, (0.0, 1.0))
    sw = g["swivel"]
    t = np.linspace(0.0, sw, 60)
    rad = 0.6 * L
    ax.plot(rad * np.cos(t), rad * np.sin(t), color="tab:green", lw=1.2)
    mid = 0.5 * sw
    _label(
        ax,
        f"swivel {np.degrees(sw):.1f}°",
        (rad * np.cos(mid), rad * np.sin(mid)),
        (1.0, 0.35),
        colour="tab:green",
    )
    pad = 0.25 * float(np.linalg.norm(b))
    xs = [0.0, b[0], L]
    ys = [0.0, b[1], L]
    ax.set(xlim=(min(xs) - pad, max(xs) + pad), ylim=(min(ys) - pad, max(ys) + pad), aspect="equal")
    ax.set_xlabel(r"along $\mathbf{i}_i$ [m]")
    ax.set_ylabel(r"along $\mathbf{j}_i$ [m]")
    ax.set_title("seen from the tip of $\\mathbf{k}_i$:\nthe swivel angle", fontsize=9)


def pulley_axis_figure(geoms, out):
    """The pulley-axis convention drawn from the model (docs/spatial.md, "The pulley axis"): each
    pulley of ``geoms`` in the plane through its swivel axis k_i that contains the attachment point
    B_i (in-plane coordinates s ⟂ k_i toward B_i, w along k_i, origin the joint point A_i): the axis
    with its direction, the sheave, the points C_i = A_i - d_i k_i (winch exit), A_i, H_i (sheave
    centre), K_i (entry tangent point), D_i (exit tangent point) and B_i, the cable C→K (along
    +k_i), the wrapped arc K→D over the +k_i side, the straight part D→B and the lever arm h = |A H|;
    then the first pulley seen from the tip of k_i with i_i (the swivel angle's zero), j_i and the
    swivel angle atan2(w·j_i, w·i_i), w = B_i - A_i. Nothing is solved here: the points are those of
    ``cdpr.analyses.scans.pulley_plane_geometry`` (``models.pulleys.pulley_state``).

    Parameters
    ----------
    geoms : list of dict
        ``scans.pulley_plane_geometry`` of one or more pulleys (e.g. an SR and a DR pulley at the
        same joint point and attachment), drawn side by side to the same scale.
    out : str or Path
        The .png written (a .pdf beside it, ``save``).

    References
    ----------
    Paty et al. 2021, eq. (3)-(7) (the plane of the cable, the SR and DR sheave centres).
    """
    allp = np.vstack(
        [
            np.vstack(list(g["plane"].values()) + [g["sheave"][np.isfinite(g["sheave"]).all(axis=1)]])
            for g in geoms
        ]
    )
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    span = float((hi - lo).max())
    lim = (lo[0] - 0.22 * span, hi[0] + 0.12 * span, lo[1] - 0.06 * span, hi[1] + 0.22 * span)
    n = len(geoms)
    fig = plt.figure(figsize=(4.2 * n + 3.4, 4.6), layout="constrained")
    axes = fig.subplots(1, n + 1, width_ratios=[1.0] * n + [0.8])
    for ax, g in zip(axes, geoms):
        _pulley_plane_panel(ax, g, lim)
    _swivel_panel(axes[-1], geoms[0])
    g = geoms[0]
    k = g["frame"][2]
    w = g["points"]["B"] - g["points"]["A"]
    fig.suptitle(
        f"{g['name']}, pulley of cable {g['cable']}: k_i = [{', '.join(f'{x:.3g}' for x in k)}], "
        f"d = {g['d']:.3g} m, B_i − A_i = [{', '.join(f'{x:.3g}' for x in w)}] m\n"
        "drawn in the plane through the swivel axis k_i that contains B_i",
        fontsize=10,
    )
    handles = [
        Line2D([], [], color="tab:blue", lw=2.0, label="cable: C→K along +k_i, arc K→D, straight D→B"),
        Line2D([], [], color="tab:orange", lw=1.0, label="sheave (radius r_p)"),
        Line2D([], [], color="tab:red", lw=1.6, label="lever arm h = |A_i H_i|"),
        Line2D([], [], color="k", ls=(0, (4, 3)), lw=0.8, label="swivel axis k_i through A_i"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncol=4, fontsize=8, frameon=False)
    return save(fig, out)


# ---- uncertainty of a spatial robot (cdpr.pipeline.uq6): a ‖δp‖ and a δφ panel for each ------------------
#: The two responses of a rigid platform: name -> (label, unit, scale to it, the columns of each table:
#: global index, full/linearised index, path quantile suffix, path nominal, Sobol output, map columns).
UQ6_RESPONSES = {
    "dp": {
        "label": "‖δp‖",
        "unit": "mm",
        "scale": 1e3,
        "index": "index_m",
        "full": "index_full_m",
        "lin": "index_lin_m",
        "q": "_m",
        "nominal": "dp_nominal_m",
        "output": "index",
        "dominant": "dominant",
        "share": "share",
        "rms": "rms_m",
    },
    "phi": {
        "label": "δφ",
        "unit": "mrad",
        "scale": 1e3,
        "index": "index_phi_rad",
        "full": "index_phi_full_rad",
        "lin": "index_phi_lin_rad",
        "q": "_phi_rad",
        "nominal": "dphi_nominal_rad",
        "output": "index_phi",
        "dominant": "dominant_phi",
        "share": "share_phi",
        "rms": "rms_phi_rad",
    },
}


def uq6_index_distribution(linear, tolerances, index_vs_E, out, mode=None):
    """``uq_index_distribution`` of a rigid platform: the global index of ‖δp‖ (top) and of δφ
    (bottom) of each optimal design under per-cable moduli (violins), beside the common-E band of
    the elasticity sweep (bar, uncompensated) and under every declared parameter (Saltelli's rows);
    columns: the cases. ``linear``, ``tolerances``: {(design, case): ``uq6.linear_samples`` table, resp.
    ``uq6.sobol``'s rows}; ``index_vs_E``: the elasticity sweep (design, E_Pa, index_m,
    index_phi_rad) or None."""
    designs, cases = _uq_designs(linear), _uq_cases(linear)
    fig, axes = plt.subplots(
        2, len(cases), figsize=(4.5 + 3.5 * len(cases), 8.5), squeeze=False, layout="constrained"
    )
    colours = dict(zip(designs, OKABE_ITO))
    for i, r in enumerate(UQ6_RESPONSES.values()):
        col, k = r["index"], r["scale"]
        for ax, case in zip(axes[i], cases):
            ticks, labels, x = [], [], 0.0
            for dk in designs:
                lin = linear.get((dk, case))
                if lin is None:
                    continue
                nominal = lin.loc[lin["sample"] == -1, col].iloc[0] * k
                vals = lin.loc[lin["sample"] >= 0, col].dropna().to_numpy() * k
                parts = ax.violinplot([vals], positions=[x], widths=0.7, showextrema=True, showmedians=True)
                _colour_violin(parts, colours[dk], 0.45)
                ax.plot([x - 0.35, x + 0.35], [nominal, nominal], "k:", lw=1)
                ticks.append(x)
                labels.append(f"{dk}\nper-cable E\nn = {len(vals)}")
                x += 1.0
                g = index_vs_E[index_vs_E.design == dk] if index_vs_E is not None else []
                if case == "uncompensated" and len(g) and col in g:
                    ax.vlines(x, g[col].min() * k, g[col].max() * k, color=colours[dk], lw=6, alpha=0.7)
                    ax.plot(x, nominal, "k_", ms=14)
                    ticks.append(x)
                    labels.append(f"{dk}\ncommon E")
                    x += 1.0
                tol = tolerances.get((dk, case))
                if tol is not None and len(tol) and col in tol:
                    parts = ax.violinplot([tol[col].dropna().to_numpy() * k], positions=[x], widths=0.7)
                    _colour_violin(parts, colours[dk], 0.2)
                    ticks.append(x)
                    labels.append(f"{dk}\nall param.\nn = {len(tol)}")
                    x += 1.5
            ax.set_xticks(ticks, labels, fontsize=7)
            ax.set(
                xlabel="design and sampling [-]",
                ylabel=f"global index mean {r['label']} over RW_C [{r['unit']}]",
                title=f"{case}: {r['label']}",
            )
            ax.grid(alpha=0.3, axis="y")
    key = [Patch(color=colours[d], alpha=0.6, label=d) for d in designs] + [
        Line2D([], [], color="k", ls=":", label="nominal robot (dotted)"),
        Line2D([], [], color="0.4", lw=6, alpha=0.7, label="common-E band [min, max] (bar)"),
        Patch(color="0.4", alpha=0.45, label="violin: samples; whiskers: min, median, max"),
    ]
    fig.legend(handles=key, loc="outside lower center", ncol=2, fontsize=7)
    fig.suptitle(f"Global indices of ‖δp‖ and δφ under per-cable moduli\n{_mode(mode)[3:]}", fontsize=10)
    return save(fig, out)


def uq6_path_bands(bands, common, out, mode=None):
    """``uq_path_bands`` of a rigid platform: the 5-50-95 % band of ‖δp‖ and of δφ along the section
    5.2 path under per-cable moduli, per design (columns) and case x response (rows), uncompensated
    beside the common-E curves of the elasticity section. ``bands``: {(design, case):
    ``uq6.path_bands`` table}; ``common``: {"dp": [...], "phi": [...]} of (design, E [Pa], s [m],
    value [m or rad]) along the common-E paths."""
    designs, cases = _uq_designs(bands), _uq_cases(bands)
    rows = [(case, key) for case in cases for key in UQ6_RESPONSES]
    fig, axes = plt.subplots(
        len(rows),
        len(designs),
        figsize=(6.5 * len(designs), 3.6 * len(rows)),
        squeeze=False,
        layout="constrained",
    )
    Es = sorted({c[1] for c in common.get("dp", [])})
    styles = dict(zip(Es, [":", "-", "--"] if len(Es) == 3 else ["-"] * len(Es)))
    for j, dk in enumerate(designs):
        for i, (case, key) in enumerate(rows):
            r, ax = UQ6_RESPONSES[key], axes[i, j]
            b = bands.get((dk, case))
            if b is None:
                ax.set_visible(False)
                continue
            k, q = r["scale"], r["q"]
            ax.fill_between(
                b.s,
                b[f"q05{q}"] * k,
                b[f"q95{q}"] * k,
                color=OKABE_ITO[0],
                alpha=0.3,
                label="5-95 % per-cable E",
            )
            ax.plot(b.s, b[f"q50{q}"] * k, color=OKABE_ITO[0], label="median per-cable E")
            ax.plot(b.s, b[r["nominal"]] * k, "k", lw=0.8, alpha=0.6, label="nominal")
            if case == "uncompensated":
                for d, E, s, v in common.get(key, []):
                    if d == dk:
                        ax.plot(
                            s,
                            v * k,
                            styles.get(E, "-"),
                            color=OKABE_ITO[1],
                            lw=1,
                            label=f"common E = {E / 1e9:g} GPa",
                        )
            ax.set(
                xlabel="position along the path s [m]",
                ylabel=f"{r['label']} [{r['unit']}]",
                title=f"{dk} {case}: {r['label']}",
            )
            ax.grid(alpha=0.3)
            ax.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.25), ncol=2, frameon=False)
    fig.suptitle(
        f"‖δp‖ and δφ along the section 5.2 path under per-cable moduli\n{_mode(mode)[3:]}", fontsize=10
    )
    return save(fig, out)


def uq6_sobol(tab, out, mode=None):
    """``uq_sobol`` of a rigid platform: Sobol total (bars) and first-order (dots) indices with their
    95 % intervals of the global index of ‖δp‖ and of δφ (rows, per case), per parameter group (left)
    and per parameter (right), per design."""
    designs = list(dict.fromkeys(tab.design))
    cases = [c for c in UQ_CASES if c in set(tab.case)]
    rows = [(case, key) for case in cases for key in UQ6_RESPONSES]
    fig, axes = plt.subplots(
        len(rows),
        2 * len(designs),
        figsize=(7.5 * len(designs) + 1, 3.4 * len(rows)),
        squeeze=False,
        layout="constrained",
        gridspec_kw={"width_ratios": [1, 3] * len(designs)},
    )
    for j, dk in enumerate(designs):
        for i, (case, key) in enumerate(rows):
            r = UQ6_RESPONSES[key]
            g = tab[(tab.output == r["output"]) & (tab.design == dk) & (tab.case == case)]
            lo = max(-1.0, min(0.0, float((g.S1 - g.S1_conf).min()) - 0.05)) if len(g) else 0.0
            for k, level in enumerate(("group", "parameter")):
                ax = axes[i, 2 * j + k]
                d = g[g.level == level]
                x = np.arange(len(d))
                ax.bar(
                    x, d.ST, yerr=d.ST_conf, color=OKABE_ITO[0], alpha=0.7, capsize=2, label="total ST ± 95 %"
                )
                ax.errorbar(
                    x,
                    d.S1,
                    yerr=d.S1_conf,
                    fmt="o",
                    color="k",
                    ms=3,
                    capsize=2,
                    label="first order S1 ± 95 %",
                )
                ax.axhline(0, color="0.5", lw=0.6)
                ax.set_xticks(
                    x,
                    d.name,
                    rotation=90 if level == "parameter" else 0,
                    fontsize=6 if level == "parameter" else 8,
                )
                ax.set(
                    xlabel=f"{level} [-]",
                    ylabel="Sobol index [-]" if k == 0 else "",
                    title=f"{dk} {case}, index of {r['label']}: {'groups' if k == 0 else 'per parameter'}",
                    ylim=(lo, _sobol_top(g)),
                )
                ax.title.set_fontsize(8)
                ax.grid(alpha=0.3, axis="y")
                if k == 1:
                    ax.tick_params(labelleft=False)
    handles, names = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncol=2, fontsize=7)
    fig.suptitle(
        f"Which uncertainty drives the global indices of ‖δp‖ and δφ (SALib){_mode(mode)}", fontsize=10
    )
    return save(fig, out)


def uq6_dominant_map(maps, A, z, out, mode=None):
    """``uq_dominant_map`` of a rigid platform: the parameter with the largest first-order
    contribution to the spread of ‖δp‖ and, below it, of δφ on the plane z (columns: designs; rows:
    case x response); hatched where it explains less than half of the spread."""
    designs, cases = _uq_designs(maps), _uq_cases(maps)
    rows = [(case, key) for case in cases for key in UQ6_RESPONSES]
    names = sorted(
        {
            n
            for df in maps.values()
            for r in UQ6_RESPONSES.values()
            for n in df[r["dominant"]].dropna().unique()
            if n
        }
    )
    cmap = plt.get_cmap("tab20", max(len(names), 1))
    code = {n: k for k, n in enumerate(names)}
    fig, axes = plt.subplots(
        len(rows),
        len(designs),
        figsize=(5 * len(designs) + 2, 4.0 * len(rows)),
        squeeze=False,
        layout="constrained",
    )
    for j, dk in enumerate(designs):
        for i, (case, key) in enumerate(rows):
            r, ax = UQ6_RESPONSES[key], axes[i, j]
            df = maps.get((dk, case))
            if df is None:
                ax.set_visible(False)
                continue
            ax.set_facecolor(NOT_OK_COLOUR)
            val = df[r["dominant"]].map(lambda n: code.get(n, np.nan)).astype(float)
            xs, ys, Z = _grid(df, val.to_numpy())
            _, _, share = _grid(df, df[r["share"]].to_numpy())
            ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(names) - 0.5, shading="nearest")
            if np.nanmin(np.where(np.isfinite(share), share, 1.0)) < 0.5:
                ax.contourf(
                    xs,
                    ys,
                    np.where(share < 0.5, 1.0, np.nan),
                    levels=[0.5, 1.5],
                    colors="none",
                    hatches=["///"],
                )
            _anchors(ax, A)
            ax.set(
                xlabel="x [m]", ylabel="y [m]", title=f"{dk} {case}: spread of {r['label']}", aspect="equal"
            )
            ax.title.set_fontsize(9)
    handles = [Patch(color=cmap(code[n]), label=n) for n in names]
    fig.legend(handles=handles, loc="outside right center", fontsize=7, title="dominant")
    fig.suptitle(
        f"Dominant uncertain parameter at z = {z:g} m (hatched: < 50 %)\n{_mode(mode)[3:]}", fontsize=10
    )
    return save(fig, out)


def uq6_residual_map(maps, A, z, out, mode=None):
    """``uq_residual_map`` of a rigid platform: on the plane z, per design (columns) and case, the
    nominal robot's ‖δp‖ and δφ and their first-order spreads under the declared parameters (RMS of
    the per-parameter contributions, ``uq6.dominant_map``); grey: not ok."""
    designs, cases = _uq_designs(maps), _uq_cases(maps)
    cols = [(key, c) for key in UQ6_RESPONSES for c in ("nominal", "rms")]
    rows = [(case, key, c) for case in cases for key, c in cols]
    fig, axes = plt.subplots(
        len(rows),
        len(designs),
        figsize=(6 * len(designs) + 1.5, 3.9 * len(rows)),
        squeeze=False,
        layout="constrained",
    )
    for i, (case, key, c) in enumerate(rows):
        r = UQ6_RESPONSES[key]
        what = f"nominal robot {r['label']}" if c == "nominal" else f"spread of {r['label']} (RMS)"
        for j, dk in enumerate(designs):
            ax = axes[i, j]
            df = maps.get((dk, case))
            if df is None:
                ax.set_visible(False)
                continue
            xs, ys, Z = _grid(df, df[r[c]].to_numpy() * r["scale"])
            ax.set_facecolor(NOT_OK_COLOUR)
            finite = Z[np.isfinite(Z)]
            top = float(np.abs(finite).max()) if finite.size else 0.0
            if top < 1e-6:  # the compensated nominal residual: zero up to rounding, stated
                grey = np.where(np.isfinite(Z), 0.0, np.nan)
                ax.pcolormesh(xs, ys, grey, cmap="Greys", vmin=0, vmax=1, shading="nearest")
                label = f"max {top:.1g} {r['unit']} (round trip)"
            else:
                levels = _round_levels(float(finite.min()), float(finite.max()), 10)
                cf = ax.contourf(xs, ys, Z, levels=levels, cmap="viridis")
                fig.colorbar(cf, ax=ax, label=f"{r['label']} [{r['unit']}]", shrink=0.8)
                label = f"{finite.min():.3g} to {finite.max():.3g} {r['unit']}"
            _anchors(ax, A)
            ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{dk} {case}: {what}\n{label}", aspect="equal")
            ax.title.set_fontsize(8)
    fig.suptitle(f"What compensation leaves at z = {z:g} m\n{_mode(mode)[3:]}", fontsize=10)
    return save(fig, out)


def uq6_agreement(mc, out, mode=None):
    """``uq_agreement`` of a rigid platform: the global index of ‖δp‖ (top) and of δφ (bottom) of
    each full-solve Monte Carlo sample against its linearised value, per design and case, with the
    line of equality."""
    keys = sorted(mc)
    fig, axes = plt.subplots(
        2, len(keys), figsize=(max(3.8 * len(keys), 7.0), 7.6), squeeze=False, layout="constrained"
    )
    for i, r in enumerate(UQ6_RESPONSES.values()):
        for ax, key in zip(axes[i], keys):
            df, k = mc[key], r["scale"]
            ax.plot(df[r["full"]] * k, df[r["lin"]] * k, "o", ms=3, color=OKABE_ITO[0])
            lo = np.nanmin([df[r["full"]].min(), df[r["lin"]].min()]) * k
            hi = np.nanmax([df[r["full"]].max(), df[r["lin"]].max()]) * k
            ax.plot([lo, hi], [lo, hi], "k:", lw=1)
            ax.set(
                xlabel=f"full solves [{r['unit']}]",
                ylabel=f"linearised [{r['unit']}]",
                title=f"{key[0]} {key[1]}: index of {r['label']}",
            )
            ax.title.set_fontsize(9)
            ax.tick_params(axis="x", labelrotation=30, labelsize=7)
            ax.grid(alpha=0.3)
    fig.suptitle(f"Global indices per sample: linearised against full solves\n{_mode(mode)[3:]}", fontsize=10)
    return save(fig, out)
