"""Figures are deterministic: the same data gives the same PNG and PDF bytes (no embedded date)."""

import time

import matplotlib.pyplot as plt

from cdpr import table_io
from cdpr.pipeline import plots


def test_same_figure_gives_same_bytes(tmp_path):
    blobs = []
    for i in range(2):
        fig, ax = plt.subplots()
        ax.plot([0.0, 1.0, 2.0], [0.0, 1.0, 4.0])
        out = tmp_path / f"f{i}.png"
        paths = plots.save(fig, out)
        assert [p.suffix for p in paths] == [".png", ".pdf"]
        blobs.append([p.read_bytes() for p in paths])
        time.sleep(1.1)  # a creation date in seconds would differ
    assert blobs[0] == blobs[1]


def _captured(monkeypatch):
    """Figures handed to plots.save, kept open for inspection (the files are still written)."""
    figs = []
    real = plots.save

    def keep(fig, out):
        figs.append(fig)
        fig.savefig(str(out), dpi=40)
        return [out]

    monkeypatch.setattr(plots, "save", keep)
    return figs, real


def _plane_table(kind, scale):
    import numpy as np
    import pandas as pd

    x, y = np.meshgrid(np.linspace(-2, 2, 9), np.linspace(-2, 2, 9))
    dp = scale * (0.05 + 0.01 * (x**2 + y**2)).ravel()
    status = np.where(np.abs(x.ravel()) + np.abs(y.ravel()) > 3.9, "slack", "ok")
    return pd.DataFrame({"x": x.ravel(), "y": y.ravel(), "dp": dp, "status": status, "subset": "1-2-3"})


def test_plane_figure_shares_one_colour_scale_and_names_the_height(tmp_path, monkeypatch):
    import numpy as np

    figs, _ = _captured(monkeypatch)
    A = np.array([[-2.5, -2.5, 5], [2.5, -2.5, 5], [2.5, 2.5, 5], [-2.5, 2.5, 5]])
    plots.fig12_plane(
        {"SR": _plane_table("SR", 2.0), "DR": _plane_table("DR", 1.0)}, A, 2.5, "CDPR4", tmp_path / "p.png"
    )
    plots.fig9_subsets({"SR": _plane_table("SR", 2.0)}, A, 2.5, "CDPR4", tmp_path / "s.png")
    plane, subsets = figs
    panels = [ax for ax in plane.axes if ax.get_title()]
    assert len(panels) == 2 and all("z = 2.5 m" in ax.get_title() for ax in panels)
    limits = {
        (round(c.norm.vmin, 12), round(c.norm.vmax, 12))
        for ax in panels
        for c in ax.collections
        if hasattr(c, "norm") and c.get_array() is not None
    }
    assert len(limits) == 1  # SR and DR on one colour scale although their ranges differ by 2x
    assert all(ax.get_legend() is not None for ax in panels)  # the slack cells are explained
    assert "z = 2.5 m" in [ax for ax in subsets.axes if ax.get_title()][0].get_title()
    assert (tmp_path / "p.png").exists() and (tmp_path / "s.png").exists()


def test_taut_set_map_and_difference_maps(tmp_path, monkeypatch):
    """Fig. 9 of the physical study colours the taut sets (four-cable sets first); the difference
    maps share one colour scale centred on zero."""
    import numpy as np

    figs, _ = _captured(monkeypatch)
    A = np.array([[-2.5, -2.5, 5], [2.5, -2.5, 5], [2.5, 2.5, 5], [-2.5, 2.5, 5]])
    t = _plane_table("SR", 1.0).drop(columns="subset")
    t["taut"] = np.where(np.abs(t.x) > 1.5, "1-2-3", "1-2-3-4")
    plots.fig9_taut({"SR": t}, A, 2.5, "CDPR4", tmp_path / "t.png")
    labels = [lab.get_text() for lab in figs[0].axes[-1].get_yticklabels()]
    assert labels == ["taut 1-2-3-4", "taut 1-2-3"]
    d = {(r, p): t.assign(diff=s * (t.x - 0.5) * 1e-3) for r in ("A", "B") for p, s in (("SR", 1), ("DR", 3))}
    plots.comparison_difference_maps(d, {"A": A, "B": A}, 2.5, tmp_path / "d.png")
    panels = [ax for ax in figs[1].axes if ax.get_title()]
    meshes = [c for ax in panels for c in ax.collections if hasattr(c, "norm") and c.get_array() is not None]
    assert len(meshes) == 4 and {(c.norm.vmin, c.norm.vmax) for c in meshes} == {(-7.5, 7.5)}


def test_outputs_follow_the_umask(tmp_path):
    """Atomic writes must not keep the temporary file's 0600: under umask 022 a table is 0644."""
    import os

    import pandas as pd

    from cdpr import io

    old = os.umask(0o022)
    try:
        table_io.write_table(pd.DataFrame({"a": [1.0]}), tmp_path / "t.csv")
        io.write_text("x", tmp_path / "t.md")
        os.umask(0o077)
        io.write_text("x", tmp_path / "private.md")
    finally:
        os.umask(old)
    assert (tmp_path / "t.csv").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "t.md").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "private.md").stat().st_mode & 0o777 == 0o600
