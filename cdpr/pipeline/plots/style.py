"""The figures' shared style: colours, the redundancy mode in a title, the orientation error's
display unit, the grid and contour-level helpers, the anchors drawn from above, the paper's values,
and ``save`` (the layout audit, then the PNG and its PDF written atomically). Every figure module of
``cdpr.pipeline.plots`` draws through these.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.path import Path as MPath
from scipy.spatial import ConvexHull

from cdpr.io import atomic
from cdpr.pipeline import figure_checks, summary

#: Colours of the pulley kinds and designs, used by every figure that compares them.
KIND_COLOURS = {"SR": "tab:blue", "DR": "tab:orange", "fixed": "tab:gray"}
#: Colour of the cells that are not ``ok`` in the maps.
NOT_OK_COLOUR = "0.85"
#: How a figure's title names the redundancy mode of the study that drew it.
MODE_TITLES = {
    "paper": "paper rule (best 3-cable subset)",
    "physical": "physical equilibrium (all cables)",
}
#: A colour-blind-safe palette (Okabe & Ito 2008) for signs and categories.
OKABE_ITO = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442", "#000000"]
#: The orientation error's display unit: δφ [rad] is drawn in mrad (the error is a few mrad).
DPHI_SCALE, DPHI_UNIT = 1e3, "mrad"
DPHI_LABEL = f"δφ [{DPHI_UNIT}]"


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


def plane_grid(df, value):
    xs, ys = np.sort(df.x.unique()), np.sort(df.y.unique())
    Z = np.full((len(ys), len(xs)), np.nan)
    ix, iy = np.searchsorted(xs, df.x), np.searchsorted(ys, df.y)
    Z[iy, ix] = value
    return xs, ys, Z


def round_levels(lo, hi, target=8):
    """Contour levels at round values covering [lo, hi]."""
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi <= lo:
        return None
    raw = (hi - lo) / target
    mag = 10 ** np.floor(np.log10(raw))
    step = min((m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw), default=10 * mag)
    return np.arange(np.floor(lo / step) * step, hi + step, step)


def draw_anchors(ax, A):
    """Draw the anchors' footprint (the frame's outline seen from above) with cable numbers (1-based).
    Anchors closer than 4 % of the footprint's span seen from above share one label ("3,4": the
    crossed cables of a spatial robot leave their pulleys in pairs), written above and right of the
    group's outermost marker so that it covers none of them (``anchor_groups``)."""
    hull = A[ConvexHull(A[:, :2]).vertices, :2]
    ax.plot(*np.vstack([hull, hull[:1]]).T, color="k", lw=0.6, ls="--")
    xy = A[:, :2]
    span = float((xy.max(axis=0) - xy.min(axis=0)).max())
    first = {g[0]: g for g in anchor_groups(xy, span)}
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


def anchor_groups(A, span):
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


def mode_suffix(mode):
    """' — <mode>' for a title, '' when the figure has no mode."""
    return f" — {MODE_TITLES[mode]}" if mode in MODE_TITLES else ""


def paper_value(quantity):
    """The paper's number for ``quantity`` of cdpr/data/paper_values.yaml (its unit), or None."""

    for v in summary.paper_values():
        if v["quantity"] == quantity:
            return v["value"]
    return None


def footprint(A):
    """The anchors' outline seen from above as a matplotlib Path (convex hull of their x, y)."""

    hull = A[ConvexHull(A[:, :2]).vertices, :2]
    return MPath(np.vstack([hull, hull[:1]]))
