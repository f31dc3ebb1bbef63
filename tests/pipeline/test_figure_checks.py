"""cdpr.pipeline.figure_checks on 3-D axes: a text of a 3-D axes (``Text3D``) is measured where it is
drawn, checked against the drawn pixels, so the layout audit neither reports it off the canvas
nor misses (or invents) an overlap."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from cdpr.pipeline import figure_checks


def _ink_box(fig):
    """The bounding box [px, origin bottom left] of the pixels that are not white."""
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3]
    rows, cols = np.nonzero((rgb < 200).any(axis=2))
    h = rgb.shape[0]
    return cols.min(), h - 1 - rows.max(), cols.max() + 1, h - rows.min()


def _bare_3d(limits=(0.0, 10.0)):
    fig = plt.figure(figsize=(4, 4), dpi=100)
    ax = fig.add_subplot(projection="3d")
    ax.set(xlim=limits, ylim=limits, zlim=limits)
    ax.set_axis_off()
    return fig, ax


@pytest.mark.parametrize("xyz", [(8.0, 2.0, 9.0), (1.0, 9.0, 0.5), (5.0, 5.0, 5.0)])
def test_a_3d_text_is_measured_where_its_pixels_are(xyz):
    fig, ax = _bare_3d()
    t = ax.text(*xyz, "Wg", fontsize=20)
    ink = _ink_box(fig)
    bb = figure_checks.text_extent(t, fig.canvas.get_renderer())
    # the text's box holds its ink (the box also holds the font's ascent and descent)
    assert bb.x0 - 1 <= ink[0] and ink[2] <= bb.x1 + 1 and bb.y0 - 1 <= ink[1] and ink[3] <= bb.y1 + 1
    assert bb.width < 2.0 * (ink[2] - ink[0]) and bb.height < 2.5 * (ink[3] - ink[1])
    # matplotlib's own extent reads (x, y) as 2-D data coordinates: far from the ink
    raw = t.get_window_extent(fig.canvas.get_renderer())
    assert abs(raw.x0 - bb.x0) > 50 or abs(raw.y0 - bb.y0) > 50
    plt.close(fig)


def test_the_audit_of_3d_texts_finds_real_overlaps_only():
    """Two texts far apart in 3-D whose (x, y) agree (matplotlib's own extents would overlap, and
    leave the canvas) pass; two texts at nearly the same 3-D point are reported."""
    fig, ax = _bare_3d()
    ax.text(5.0, 5.0, 0.0, "low")
    ax.text(5.0, 5.0, 10.0, "high")
    assert figure_checks.layout_problems(fig) == []
    ax.text(5.0, 5.05, 10.0, "high too")
    problems = figure_checks.layout_problems(fig)
    assert problems == ["texts 'high' and 'high too' overlap"], problems
    plt.close(fig)


def test_a_3d_text_outside_the_view_leaves_the_canvas():
    fig, ax = _bare_3d()
    ax.text(60.0, -50.0, 5.0, "far away")
    assert figure_checks.layout_problems(fig) == ["text 'far away' leaves the canvas"]
    plt.close(fig)


def test_a_2d_text_is_measured_by_matplotlib():
    fig, ax = plt.subplots()
    t = ax.text(0.5, 0.5, "plain")
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    assert figure_checks.text_extent(t, r).bounds == t.get_window_extent(r).bounds
    plt.close(fig)
