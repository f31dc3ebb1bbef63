"""The figures of the horizontal plane (Paty 2021 section 3.3.2, the study's ``plane`` part): the
3-cable subset or taut set at each point (Fig. 9), ‖δp‖ (and δφ) over the plane (Fig. 12), and the
minimum cable tension over it (beyond the paper).

A rigid platform's plane tables carry the interference columns (``analyses.interference
.add_interference``): an ok point whose cables interfere at its solved pose is left out of every
map, as of the study's numbers, and drawn in ``INTERFERING_COLOUR`` (pink), counted under the panel
(docs/interference.md).
"""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

from cdpr.analyses.workspace import interference_free_rows
from cdpr.pipeline.plots.robot import INTERFERING_COLOUR
from cdpr.pipeline.plots.style import (
    DPHI_LABEL,
    DPHI_SCALE,
    DPHI_UNIT,
    NOT_OK_COLOUR,
    draw_anchors,
    footprint,
    mode_suffix,
    plane_grid,
    round_levels,
    save,
)


def interfering_points(df):
    """Mask (N,) of the ok points whose cables interfere at their solved pose (a rigid platform's
    plane table, column ``interference_free``); none for a table without the column (a point mass).

    Parameters
    ----------
    df : DataFrame
        A plane table (status, and interference_free when the robot is a rigid platform).

    Returns
    -------
    ndarray (N,) bool
    """
    return (df.status == "ok").to_numpy() & ~interference_free_rows(df)


def _drawn(df):
    """Mask (N,) of the points a map draws: ok and free of interference."""
    return (df.status == "ok").to_numpy() & ~interfering_points(df)


def _draw_interfering(ax, df):
    """The interfering ok points of ``df`` (``interfering_points``) as cells of ``INTERFERING_COLOUR``."""
    bad = interfering_points(df)
    if bad.any():
        xs, ys, Z = plane_grid(df, np.where(bad, 1.0, np.nan))
        ax.pcolormesh(xs, ys, Z, cmap=ListedColormap([INTERFERING_COLOUR]), shading="nearest")


def _interference_note(tables):
    """The suptitle's words on the interfering points when some table has them, else ""."""
    n = sum(int(interfering_points(df).sum()) for df in tables.values())
    return f"; pink: {n} ok points with interfering cables, left out" if n else ""


def _not_ok_counts(df, A=None):
    """Counts of the points that are not ok by status; with anchors ``A``, the points outside the
    anchors' footprint are counted apart (``outside the footprint``) from the statuses inside."""
    bad = df[df.status != "ok"]
    counts = {}
    if A is not None and len(bad):
        inside = footprint(A).contains_points(bad[["x", "y"]].to_numpy(), radius=1e-9)
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
    handles = []
    if counts:
        handles.append(
            Patch(
                color=NOT_OK_COLOUR, label="grey, not ok: " + ", ".join(f"{k} {v}" for k, v in counts.items())
            )
        )
    n_bad = int(interfering_points(df).sum())
    if n_bad:
        handles.append(Patch(color=INTERFERING_COLOUR, label=f"pink, ok but interfering (left out): {n_bad}"))
    if handles:
        ax.legend(
            handles=handles,
            fontsize=7,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.14),
            frameon=False,
        )


#: Categories (subsets, taut sets) a map colours apart at most; the rarer ones are one "other" colour.
MAX_CATEGORIES = 9
#: The colour of the rare categories grouped as "other" (darker than the grey of the points not ok).
OTHER_COLOUR = "0.45"


def category_colours(tables, column, order=None, keep=MAX_CATEGORIES):
    """The categories of a map (``column`` of the plane tables, counted over their ok points) that
    get a colour of their own: the ``keep`` most frequent, the rest grouped as one "other" entry
    drawn in ``OTHER_COLOUR``, so that no colour is repeated and the legend fits.

    Parameters
    ----------
    tables : dict
        Design label -> plane table (``column``, ``status``).
    column : str
        ``subset`` or ``taut``.
    order : callable, optional
        Sort key of the kept categories in the legend (default: by name).
    keep : int
        Categories with a colour of their own at most (one more when that avoids an "other" of one).

    Returns
    -------
    labels : list of str
        The kept categories, then "other (N sets)" when some are grouped.
    code : dict
        Category -> index into ``labels`` (every category of the tables).
    cmap : matplotlib.colors.ListedColormap
        One distinct colour per entry of ``labels`` (Okabe-Ito / tab10; "other" grey).
    """
    counts = {}
    for df in tables.values():
        ok = _drawn(df)
        for cat, n in df.loc[ok, column].astype(str).value_counts().items():
            if cat:
                counts[cat] = counts.get(cat, 0) + int(n)
    ranked = sorted(counts, key=lambda c: (-counts[c], c))
    if len(ranked) > keep + 1:
        kept, rare = ranked[:keep], ranked[keep:]
    else:
        kept, rare = ranked, []
    kept = sorted(kept, key=order)
    labels = kept + ([f"other ({len(rare)} sets)"] if rare else [])
    code = {c: i for i, c in enumerate(kept)} | {c: len(kept) for c in rare}
    # tab10 without its grey (the colour of "other" and, lighter, of the points not ok), then a
    # tenth distinct colour for the case of keep + 1 categories
    palette = [plt.get_cmap("tab10")(i) for i in range(10) if i != 7] + [plt.get_cmap("tab20")(1)]
    colours = palette[: len(kept)] + ([OTHER_COLOUR] if rare else [])
    return labels, code, ListedColormap(colours or ["w"])


def _category_panels(axes, tables, column, labels, cmap, A, z, robot_name, code=None):
    """One panel per design (``tables``: label -> plane table) of the category in ``column`` at each
    point (one colour per entry of ``labels``; the points that are not ok grey, counted under the
    panel), with the anchors ``A``, titled with the robot's name, the design and the height ``z``.
    Returns the last panel's mesh (for the colour bar), None without tables."""
    im = None
    code = code or {s: i for i, s in enumerate(labels)}
    for ax, (label, df) in zip(axes, tables.items()):
        c = df[column].astype(str).map(code).astype(float)
        c[~_drawn(df)] = np.nan
        xs, ys, Z = plane_grid(df, c.to_numpy())
        ax.set_facecolor(NOT_OK_COLOUR)
        im = ax.pcolormesh(xs, ys, Z, cmap=cmap, vmin=-0.5, vmax=len(labels) - 0.5, shading="nearest")
        _draw_interfering(ax, df)
        draw_anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df, A)
    return im


def fig9_subsets(tables, A, z, robot_name, out, mode=None):
    """Paty 2021 Fig. 9: the 3-cable subset that minimises ‖δp‖ at each point of the plane, one
    panel per pulley design. ``tables`` maps a design label to its plane table."""
    labels, code, cmap = category_colours(tables, "subset")
    fig, axes = plt.subplots(
        1, len(tables), figsize=(5.2 * len(tables) + 1.5, 5.2), squeeze=False, layout="constrained"
    )
    im = _category_panels(axes[0], tables, "subset", labels, cmap, A, z, robot_name, code)
    cb = fig.colorbar(im, ax=axes[0].tolist(), ticks=range(len(labels)))
    cb.ax.set_yticklabels([s if s.startswith("other") else f"cables {s}" for s in labels])
    cb.set_label("subset kept [cable numbers]")
    fig.suptitle(
        f"Subset of 3 cables that minimises ‖δp‖ (Fig. 9){_interference_note(tables)}{mode_suffix(mode)}",
        fontsize=10,
    )
    return save(fig, out)


def fig9_taut(tables, A, z, robot_name, out, mode="physical"):
    """Fig. 9 of the physical study: the set of taut cables of the equilibrium at each point of the
    plane (``redundancy: physical``: every cable may go slack; the paper's Fig. 9 shows instead the
    3-cable subset its rule keeps), one panel per pulley design. ``tables`` maps a design label to
    its plane table (column ``taut``, e.g. '1-2-3-4'); points that are not ok are grey. At most
    ``MAX_CATEGORIES`` sets get a colour of their own, the rarer ones one "other" colour
    (``category_colours``)."""
    labels, code, cmap = category_colours(tables, "taut", order=lambda s: (-len(s.split("-")), s))
    # 5.4 in high: at 5.2 the colour bar of ten sets outgrows the square panels and constrained
    # layout leaves their x labels a pixel below the canvas
    fig, axes = plt.subplots(
        1, len(tables), figsize=(5.2 * len(tables) + 1.5, 5.4), squeeze=False, layout="constrained"
    )
    im = _category_panels(axes[0], tables, "taut", labels, cmap, A, z, robot_name, code)
    if im is not None:
        cb = fig.colorbar(im, ax=axes[0].tolist(), ticks=range(len(labels)))
        cb.ax.set_yticklabels([s if s.startswith("other") else f"taut {s}" for s in labels])
        cb.set_label("taut-set map [cable numbers]")
    fig.suptitle(
        f"Taut cables at each point (Fig. 9 as a taut-set map){_interference_note(tables)}{mode_suffix(mode)}",
        fontsize=10,
    )
    return save(fig, out)


def _labelled_contours(fig, ax, xs, ys, Z, cmap, label, skip=(), top=None):
    """Filled contours of Z at about ten round levels (``round_levels``) with every level a black
    line, every other line labelled (but values in ``skip``, whose own labels are drawn elsewhere),
    and the panel's own colour bar titled ``label``. ``top``: the levels stop there and the values
    above it take the top colour (the colour bar's triangle), for a field whose few largest values
    would flatten the rest. Nothing is drawn where Z has under two levels."""
    high = np.nanmax(Z) if top is None else min(top, np.nanmax(Z))
    levels = round_levels(np.nanmin(Z), high, 10)
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
    ten filled levels, every level a labelled line; its own colour bar: the title says "colour
    scale per panel", the designs' errors differ by up to an order of magnitude). ``paper`` maps a design
    label to the paper's iso-values [m] (e.g. the min and max it quotes), drawn as red dashed
    labelled contours. Cells that are not ok are grey, counted by status under the panel with the
    points outside the anchors' footprint counted apart; the dashed line is the footprint. A rigid
    platform's ok points whose cables interfere at the solved pose are left out of the contours and
    drawn pink (``interfering_points``), counted under the panel and in the title.

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
        ok = _drawn(df)
        xs, ys, Z = plane_grid(df, np.where(ok, df.dp * 1e3, np.nan))
        ax.set_facecolor(NOT_OK_COLOUR)
        _draw_interfering(ax, df)
        if np.isfinite(Z).any():
            iso = [v * 1e3 for v in paper.get(label, []) if v is not None]
            _labelled_contours(fig, ax, xs, ys, Z, "viridis", "‖δp‖ [mm]", skip=iso)  # paper's own label wins
            if iso and np.nanmin(Z) < max(iso) and np.nanmax(Z) > min(iso):
                cp = ax.contour(xs, ys, Z, levels=sorted(iso), colors="r", linewidths=1.2, linestyles="--")
                ax.clabel(cp, fmt=lambda v: f"paper {v:g}", fontsize=6)
        draw_anchors(ax, A)
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
    scale = ", colour scale per panel" if len(tables) > 1 else ""
    fig.suptitle(
        f"{what} over the plane (Fig. 12{scale}){_interference_note(tables)}{mode_suffix(mode)}", fontsize=10
    )
    return save(fig, out)


#: A δφ plane whose largest value exceeds this many times its 75th percentile is drawn to the percentile.
DPHI_TAIL = 3.0


def _plane_dphi_panel(fig, ax, df, A, title):
    """One panel of the orientation error δφ [mrad] over a plane table (column ``dphi`` [rad]):
    filled round levels with their own colour bar; cells that are not ok grey, counted below. Where
    the largest values (near the frame's edges, where the platform hangs on few taut cables) exceed
    DPHI_TAIL times the 75th percentile, the levels stop at that percentile and the title says so:
    else the interior, where the platform works, is one colour."""
    ok = _drawn(df)
    xs, ys, Z = plane_grid(df, np.where(ok, df["dphi"] * DPHI_SCALE, np.nan))
    ax.set_facecolor(NOT_OK_COLOUR)
    _draw_interfering(ax, df)
    if np.isfinite(Z).any():
        q75 = float(np.nanpercentile(Z, 75))
        top = q75 if np.nanmax(Z) > DPHI_TAIL * q75 else None
        _labelled_contours(fig, ax, xs, ys, Z, "magma", DPHI_LABEL, top=top)
        if top is not None:
            title += f"\nlevels to the 75th percentile; max {np.nanmax(Z):.3g} {DPHI_UNIT}"
    draw_anchors(ax, A)
    ax.set(xlabel="x [m]", ylabel="y [m]", title=title, aspect="equal")
    ax.title.set_fontsize(9)
    _not_ok_legend(ax, df, A)


def fig12_tension(tables, A, z, robot_name, t_min, out, mode=None):
    """Minimum cable tension over the plane at height z (beyond the paper): min_i t_i at each ok
    point (physical mode: over every cable, a slack one at 0 N; paper mode: over the 3-cable subset
    the rule keeps, the others carry no modelled tension), one panel per pulley design, with the tension limit ``t_min`` [N] drawn as a red line
    (the slack margin is the distance to it) where the plane crosses it; the title names the red
    line only when some panel draws it. ``tables`` maps a design label to its plane table
    (columns x, y, status, t1..tm [N])."""
    fig, axes = plt.subplots(
        1, len(tables), figsize=(5.6 * len(tables), 5.6), squeeze=False, layout="constrained"
    )
    drawn = False  # the red line of t_min, in some panel
    for ax, (label, df) in zip(axes[0], tables.items()):
        tcols = sorted((c for c in df.columns if re.fullmatch(r"t\d+", c)), key=lambda c: int(c[1:]))
        ok = _drawn(df)
        tt = df[tcols]
        if "taut" in df.columns:  # physical mode: a slack cable's tension is written NaN, and is 0 N
            tt = tt.fillna(0.0)
        tmin = tt.min(axis=1).to_numpy() if tcols else np.full(len(df), np.nan)
        xs, ys, Z = plane_grid(df, np.where(ok, tmin, np.nan))
        ax.set_facecolor(NOT_OK_COLOUR)
        _draw_interfering(ax, df)
        if np.isfinite(Z).any():
            _labelled_contours(fig, ax, xs, ys, Z, "cividis", "minimum cable tension min t_i [N]")
            if t_min is not None and np.nanmin(Z) < t_min < np.nanmax(Z):
                ax.contour(xs, ys, Z, levels=[t_min], colors="r", linewidths=1.2)
                drawn = True
        draw_anchors(ax, A)
        ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{robot_name} {label} at z = {z:g} m", aspect="equal")
        _not_ok_legend(ax, df, A)
    lim = f"; red: min t_i = {t_min:g} N" if drawn else ""  # promised only where the plane crosses it
    over = "slack cables count as 0 N" if mode == "physical" else "over the 3 cables the rule keeps"
    fig.suptitle(
        f"Minimum cable tension over the plane ({over}){lim}{_interference_note(tables)}{mode_suffix(mode)}",
        fontsize=10,
    )
    return save(fig, out)
