"""Mechanical checks of a figure's layout, from matplotlib's text extents (issue 21).

A reviewer's first reading of a figure: can every text be read (no two texts overlap, none leaves the
canvas), does every axis say what it measures and in which unit, and does the title say which model
(the paper's 3-of-m rule or the physical equilibrium) drew it. :func:`layout_problems` returns one
sentence per violation; :func:`cdpr.pipeline.plots.style.save` writes them beside the figure when the
environment variable ``CDPR_FIGURE_AUDIT`` is set (the figure test, tests/pipeline/test_figures.py).
"""

from __future__ import annotations

import math
import re

import numpy as np
from matplotlib.text import Text
from mpl_toolkits.mplot3d import proj3d
from mpl_toolkits.mplot3d.art3d import Text3D

#: A unit in brackets at the end of an axis label: "x [m]", "R_V [-]", "‖δp‖ [mm]".
UNIT = re.compile(r"\[[^\]]+\]\s*\)?\s*$|\[[^\]]+\]")
#: Words of a title that name the redundancy mode.
MODE_WORDS = {"paper": ("paper rule", "paper mode"), "physical": ("physical",)}
#: Overlaps smaller than this [px] on either side are antialiasing, not a collision.
SLACK_PX = 1.0


def _hidden_tick_labels(fig):
    """Tick labels matplotlib keeps but does not draw (ticks outside the view limits)."""
    hidden = set()
    for ax in fig.axes:
        for axis in getattr(ax, "_axis_map", {}).values():
            lo, hi = sorted(axis.get_view_interval())
            eps = 1e-9 * abs(hi - lo)
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                loc = tick.get_loc()
                if loc is None or not lo - eps <= loc <= hi + eps:
                    hidden.update((id(tick.label1), id(tick.label2)))
    return hidden


def visible_texts(fig):
    """Every visible, drawn, non-empty text of ``fig`` (titles, labels, tick labels, legends,
    annotations, contour labels)."""

    hidden = _hidden_tick_labels(fig)
    out = []
    for t in fig.findobj(Text):
        if not t.get_visible() or not t.get_text().strip() or id(t) in hidden:
            continue
        if t.axes is not None and not t.axes.get_visible():
            continue
        out.append(t)
    return out


def text_extent(t, renderer):
    """The window extent [px] of text ``t`` where it is drawn.

    A 2-D text's ``get_window_extent``. A text of a 3-D axes (``ax.text(x, y, z, s)``, a
    ``Text3D``) keeps its data coordinates (x, y, z) and is moved to their projection only while it is
    drawn, so its own ``get_window_extent`` measures it at (x, y) read as 2-D data coordinates of
    the 3-D axes (far off the canvas for x, y of metres). Here it is measured at the projection of
    (x, y, z) through the axes' last projection matrix (``ax.M``, set when the figure was drawn) and
    at the angle of its projected direction, as ``Text3D.draw`` places it.
    """
    if not isinstance(t, Text3D) or t.axes is None or getattr(t.axes, "M", None) is None:
        return t.get_window_extent(renderer)
    ax = t.axes
    x, y, z = t.get_position_3d()
    ends = np.array([[x, y, z], np.add([x, y, z], t._dir_vec)], dtype=float)
    scaled = [a.get_transform().transform(ends[:, i]) for i, a in enumerate((ax.xaxis, ax.yaxis, ax.zaxis))]
    px, py, _ = proj3d.proj_transform(*scaled, ax.M)
    angle = (math.degrees(math.atan2(py[1] - py[0], px[1] - px[0])) + 180) % 180
    saved = (t._x, t._y, t._rotation)
    try:
        t._x, t._y, t._rotation = px[0], py[0], angle - 180 if angle > 90 else angle
        return t.get_window_extent(renderer)
    finally:
        t._x, t._y, t._rotation = saved


def _name(t):
    s = t.get_text().replace("\n", " ")
    return repr(s[:40] + ("..." if len(s) > 40 else ""))


def _axis_labels(ax):
    """(axis name, label text, whether the axis shows tick labels) of a 2-D or 3-D axes."""
    names = ["x", "y"] + (["z"] if hasattr(ax, "zaxis") else [])
    out = []
    for n in names:
        axis = getattr(ax, f"{n}axis")
        shown = axis.get_visible() and any(
            tl.get_visible() and tl.get_text().strip() for tl in axis.get_ticklabels()
        )
        out.append((n, axis.get_label().get_text(), shown))
    return out


def layout_problems(fig, mode=None, draw=True):
    """The layout problems of ``fig``, one sentence each (empty when the figure passes).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A drawn or undrawn figure (it is drawn here, with its final size).
    mode : {"paper", "physical", None}
        The redundancy mode of the study that drew it; when given, a title (the figure's suptitle
        or an axes title) must name it ("paper rule" / "physical").
    draw : bool
        Draw the figure first (False: it has just been drawn with its final size).

    Returns
    -------
    list of str
        Text pairs that overlap, texts that leave the canvas, axes without a label or without a
        unit in brackets (colour bars included), and a missing mode.
    """
    if draw:
        fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    W, H = fig.bbox.width, fig.bbox.height
    problems = []
    texts = visible_texts(fig)
    boxes = []
    for t in texts:
        bb = text_extent(t, renderer)
        if bb.width <= 0 or bb.height <= 0:
            continue
        if bb.x0 < -SLACK_PX or bb.y0 < -SLACK_PX or bb.x1 > W + SLACK_PX or bb.y1 > H + SLACK_PX:
            problems.append(f"text {_name(t)} leaves the canvas")
        boxes.append((t, bb))
    for i in range(len(boxes)):
        ti, bi = boxes[i]
        for j in range(i + 1, len(boxes)):
            tj, bj = boxes[j]
            dx = min(bi.x1, bj.x1) - max(bi.x0, bj.x0)
            dy = min(bi.y1, bj.y1) - max(bi.y0, bj.y0)
            if dx > SLACK_PX and dy > SLACK_PX:
                problems.append(f"texts {_name(ti)} and {_name(tj)} overlap")
    for ax in fig.axes:
        if not ax.get_visible() or not ax.axison:
            continue
        for n, label, shown in _axis_labels(ax):
            if not shown:
                continue
            where = ax.get_title() or ax.get_label() or "an axes"
            if not label.strip():
                problems.append(f"{n} axis of {where!r} has no label")
            elif not UNIT.search(label):
                problems.append(f"{n} axis label {label!r} has no unit in brackets")
    if mode is not None:
        problems += mode_problems(titles(fig), mode)
    return problems


def titles(fig):
    """The figure's suptitle and every axes title (left, centre, right), non-empty."""
    out = [fig._suptitle.get_text()] if fig._suptitle is not None else []
    out += [ax.get_title(loc) for ax in fig.axes for loc in ("left", "center", "right")]
    return [t for t in out if t.strip()]


def mode_problems(title_texts, mode):
    """[] when one of ``title_texts`` names ``mode`` ("paper" or "physical"), else one sentence."""
    words = MODE_WORDS[mode]
    if any(w in t.lower() for t in title_texts for w in words):
        return []
    return [f"no title names the mode ({' / '.join(words)})"]
