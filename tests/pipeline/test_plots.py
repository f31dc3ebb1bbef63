"""Figures are deterministic: the same data gives the same PNG and PDF bytes (no embedded date)."""

import time

import matplotlib.pyplot as plt
import numpy as np
import pytest

from cdpr import table_io
from cdpr.pipeline import figure_checks
from cdpr.pipeline.plots import comparison as comparison_plots
from cdpr.pipeline.plots import doe as doe_plots
from cdpr.pipeline.plots import planes as planes_plots
from cdpr.pipeline.plots import style as style_plots
from cdpr.pipeline.plots import trajectories as trajectories_plots
from cdpr.pipeline.plots import uq as uq_plots

#: The figure modules drawn here: each calls its own ``save`` (``plots.style.save``).
FIGURE_MODULES = (comparison_plots, doe_plots, planes_plots, trajectories_plots, uq_plots)


def test_same_figure_gives_same_bytes(tmp_path):
    blobs = []
    for i in range(2):
        fig, ax = plt.subplots()
        ax.plot([0.0, 1.0, 2.0], [0.0, 1.0, 4.0])
        out = tmp_path / f"f{i}.png"
        paths = style_plots.save(fig, out)
        assert [p.suffix for p in paths] == [".png", ".pdf"]
        blobs.append([p.read_bytes() for p in paths])
        time.sleep(1.1)  # a creation date in seconds would differ
    assert blobs[0] == blobs[1]


@pytest.fixture(autouse=True)
def _close_kept_figures():
    """``_captured`` keeps figures open for inspection: close them after each test (pyplot warned
    once more than 20 were open)."""
    yield
    plt.close("all")


def _captured(monkeypatch):
    """Figures handed to ``plots.style.save`` by the figure modules, kept open for inspection (the
    files are still written)."""
    figs = []
    real = style_plots.save

    def keep(fig, out):
        figs.append(fig)
        fig.savefig(str(out), dpi=40)
        return [out]

    for module in FIGURE_MODULES:
        monkeypatch.setattr(module, "save", keep)
    return figs, real


def _plane_table(kind, scale):
    import numpy as np
    import pandas as pd

    x, y = np.meshgrid(np.linspace(-2, 2, 9), np.linspace(-2, 2, 9))
    dp = scale * (0.05 + 0.01 * (x**2 + y**2)).ravel()
    status = np.where(np.abs(x.ravel()) + np.abs(y.ravel()) > 3.9, "slack", "ok")
    return pd.DataFrame({"x": x.ravel(), "y": y.ravel(), "dp": dp, "status": status, "subset": "1-2-3"})


def test_plane_figure_has_levels_per_panel_the_paper_iso_values_and_names_the_height(tmp_path, monkeypatch):
    """Fig. 12 (issue 21): each panel on levels fine enough for its own range (a shared scale painted
    a panel with half the range in two or three bands), the paper's iso-values drawn as red dashed
    contours, the mode in the title, and the points outside the anchors' footprint counted apart."""
    import numpy as np

    figs, _ = _captured(monkeypatch)
    A = np.array([[-2.5, -2.5, 5], [2.5, -2.5, 5], [2.5, 2.5, 5], [-2.5, 2.5, 5]])
    planes_plots.fig12_plane(
        {"SR": _plane_table("SR", 2.0), "DR": _plane_table("DR", 1.0)},
        A,
        2.5,
        "CDPR4",
        tmp_path / "p.png",
        mode="paper",
        paper={"SR": [0.15], "DR": [None]},
    )
    planes_plots.fig9_subsets(
        {"SR": _plane_table("SR", 2.0)}, A, 2.5, "CDPR4", tmp_path / "s.png", mode="paper"
    )
    plane, subsets = figs
    panels = [ax for ax in plane.axes if ax.get_title()]
    assert len(panels) == 2 and all("z = 2.5 m" in ax.get_title() for ax in panels)
    assert "paper rule" in plane._suptitle.get_text()
    for ax, scale in zip(panels, (2.0, 1.0)):
        t = _plane_table("SR", scale)
        lo, hi = (f(t.dp[t.status == "ok"]) * 1e3 for f in (np.min, np.max))
        filled = [c for c in ax.collections if hasattr(c, "levels") and c.filled]
        levels = filled[0].levels
        assert len(levels) >= 6 and levels[0] <= lo + 1e-9 and levels[-1] >= hi - 1e-9, levels
        assert np.diff(levels).max() <= (hi - lo) / 4  # at least four bands inside the panel's own range
    red = [
        c
        for c in panels[0].collections
        if hasattr(c, "levels") and not c.filled and list(c.levels) == [150.0]
    ]
    assert len(red) == 1  # the paper's iso-value on the SR panel
    texts = [t.get_text() for t in panels[0].get_legend().get_texts()]
    assert all(ax.get_legend() is not None for ax in panels) and "slack" in texts[0]  # slack cells explained
    assert "z = 2.5 m" in [ax for ax in subsets.axes if ax.get_title()][0].get_title()
    assert (tmp_path / "p.png").exists() and (tmp_path / "s.png").exists()


def test_not_ok_counts_put_points_outside_the_footprint_apart():
    import numpy as np
    import pandas as pd

    A = np.array([[-1.0, -1.0, 5], [1.0, -1.0, 5], [1.0, 1.0, 5], [-1.0, 1.0, 5]])
    df = pd.DataFrame(
        {
            "x": [0.0, 0.5, 2.0, -3.0, 0.2],
            "y": [0.0, 0.5, 0.0, 0.0, 0.1],
            "status": ["ok", "slack", "inaccessible", "slack", "inaccessible"],
        }
    )
    assert planes_plots._not_ok_counts(df, A) == {"outside the footprint": 2, "slack": 1, "inaccessible": 1}
    assert planes_plots._not_ok_counts(df) == {"slack": 2, "inaccessible": 2}


def test_taut_set_map_and_difference_maps(tmp_path, monkeypatch):
    """Fig. 9 of the physical study colours the taut sets (four-cable sets first); the difference
    maps share one colour scale centred on zero."""
    import numpy as np

    figs, _ = _captured(monkeypatch)
    A = np.array([[-2.5, -2.5, 5], [2.5, -2.5, 5], [2.5, 2.5, 5], [-2.5, 2.5, 5]])
    t = _plane_table("SR", 1.0).drop(columns="subset")
    t["taut"] = np.where(np.abs(t.x) > 1.5, "1-2-3", "1-2-3-4")
    planes_plots.fig9_taut({"SR": t}, A, 2.5, "CDPR4", tmp_path / "t.png")
    labels = [lab.get_text() for lab in figs[0].axes[-1].get_yticklabels()]
    assert labels == ["taut 1-2-3-4", "taut 1-2-3"]
    d = {(r, p): t.assign(diff=s * (t.x - 0.5) * 1e-3) for r in ("A", "B") for p, s in (("SR", 1), ("DR", 3))}
    comparison_plots.comparison_difference_maps(d, {"A": A, "B": A}, 2.5, tmp_path / "d.png")
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


def _spatial(df, phi_scale):
    """A plane or path table of a rigid platform: the point-mass columns plus dphi [rad] and tensions."""
    out = df.copy()
    out["dphi"] = phi_scale * (1e-3 + out.dp)
    for i in range(1, 5):
        out[f"t{i}"] = 100.0 * i
    return out


def test_spatial_tables_get_dphi_panels_with_their_unit(tmp_path, monkeypatch):
    """Issue 19: where a table has dphi (a rigid platform), the plane, path, DOE, effects and
    index-versus-E figures add δφ panels, labelled δφ [mrad]; every axis names its unit."""
    import numpy as np
    import pandas as pd

    figs, _ = _captured(monkeypatch)
    A = np.array([[-2.5, -2.5, 5], [2.5, -2.5, 5], [2.5, 2.5, 5], [-2.5, 2.5, 5]])
    plane = {"SR": _spatial(_plane_table("SR", 2.0), 0.1), "DR": _spatial(_plane_table("DR", 1.0), 0.2)}
    planes_plots.fig12_plane(plane, A, 2.0, "CoGiRo", tmp_path / "plane.png", mode="physical")
    s = np.linspace(0, 3, 7)
    path = pd.DataFrame({"s": s, "dp": 0.1 + 0.01 * s, "status": "ok", "x": s, "y": 0.0, "z": 1.0})
    tables = {"diagonal_SR": _spatial(path, 0.1), "diagonal_DR": _spatial(path, 0.2)}
    mm = pd.DataFrame(
        {
            "design": list(tables),
            "dp_min_m": [0.1, 0.1],
            "dp_max_m": [0.13, 0.13],
            "dphi_min_rad": [0.01, 0.02],
            "dphi_max_rad": [0.02, 0.03],
            "ok_until_s_m": [3.0, 3.0],
            "path_length_m": [3.0, 3.0],
        }
    )
    trajectories_plots.fig10_trajectories(tables, mm, tmp_path / "paths.png", mode="physical")
    trajectories_plots.fig11_minmax(mm, tmp_path / "minmax.png", mode="physical")
    tests = pd.DataFrame(
        {
            "test": range(1, 9),
            "kind": ["SR"] * 4 + ["DR"] * 4,
            "h_m": [0.05] * 8,
            "r_p_m": [0.025] * 8,
            "index_m": np.linspace(0.05, 0.2, 8),
            "index_phi_rad": np.linspace(0.003, 0.03, 8),
        }
    )
    doe_plots.fig15_doe(tests, tmp_path / "doe.png", mode="physical", paper=False)
    eff = pd.DataFrame(
        {
            "response": ["index_m"] * 3 + ["index_phi_rad"] * 3,
            "term": ["mean", "joint", "h"] * 2,
            "effect": [0.1, 0.02, -0.01, 0.01, 0.002, -0.001],
        }
    )
    doe_plots.fig16_effects(eff, tmp_path / "effects.png", mode="physical")
    ylabels = [[ax.get_ylabel() for ax in f.axes] for f in figs]
    assert sum(y == "δφ [mrad]" for y in ylabels[0]) == 2  # the plane: a δφ colour bar per design
    assert all(any("[mrad]" in y for y in ys) for ys in ylabels)  # every figure has its δφ panel
    for f in figs:
        assert "physical" in f.get_suptitle() or any("physical" in ax.get_title() for ax in f.axes)
        for ax in f.axes:
            for lab in (ax.get_xlabel(), ax.get_ylabel()):
                assert not lab or "[" in lab, lab
    ax_doe = figs[3].axes
    assert not any("paper" in t.get_text() for ax in ax_doe for t in ax.texts)  # no paper markers


def test_colliding_contour_labels_are_hidden_and_others_kept():
    x = np.linspace(0, 1, 60)
    X, Y = np.meshgrid(x, x)
    # a steep rim: forty levels crowd into the last few percent of the panel
    Z = np.exp(40 * (X - 1))
    fig, ax = plt.subplots(figsize=(4, 4))
    ax.set(xlabel="x [m]", ylabel="y [m]")
    cs = ax.contour(X, Y, Z, levels=np.linspace(0.02, 0.98, 40))
    labels = ax.clabel(cs, fmt="%.2f", fontsize=8)
    before = figure_checks.layout_problems(fig)
    assert any("overlap" in p for p in before)
    rec = style_plots.audit(fig)
    assert not [p for p in rec["problems"] if "overlap" in p], rec["problems"]
    shown = [t for t in labels if t.get_visible()]
    assert 0 < len(shown) < len(labels)
    plt.close(fig)
    # well separated labels are all kept
    fig, ax = plt.subplots(figsize=(4, 4))
    ax.set(xlabel="x [m]", ylabel="y [m]")
    cs = ax.contour(X, Y, X, levels=[0.25, 0.5, 0.75])
    labels = ax.clabel(cs, fmt="%.2f")
    style_plots.audit(fig)
    assert all(t.get_visible() for t in labels)
    plt.close(fig)


#: The responses of a robot solved as a pose (``analyses.uncertainty.RESPONSES``).
POSE = ("dp", "dphi")


def test_spatial_uncertainty_figures_have_dphi_panels_with_their_unit(tmp_path, monkeypatch):
    """Issue 19: the uncertainty figures of a rigid platform (``plots.uq.uq_*`` with responses ‖δp‖ and δφ, drawn from the quick
    spatial study's reference tables) have a δφ panel beside each ‖δp‖ one, in mrad, the mode in the
    title and a unit in every axis label; and the mechanical layout check finds nothing."""
    import pandas as pd

    from tests.conftest import ROOT

    ref = ROOT / "tests" / "reference" / "quick_spatial" / "uncertainty"
    figs, _ = _captured(monkeypatch)
    A = np.array([[-7.0, -5.0, 5.4], [7.0, -5.0, 5.4], [7.0, 5.0, 5.4], [-7.0, 5.0, 5.4]])
    path = {("SRopt", "uncompensated"): pd.read_csv(ref / "SRopt_uncompensated_path.csv")}
    maps = {("SRopt", "compensated"): pd.read_csv(ref / "SRopt_compensated_map.csv")}
    uq_plots.uq_path_bands(path, {}, tmp_path / "path.png", mode="physical", responses=POSE)
    uq_plots.uq_sobol(pd.read_csv(ref / "sobol.csv"), tmp_path / "sobol.png", mode="physical", responses=POSE)
    uq_plots.uq_dominant_map(maps, A, 2.0, tmp_path / "dominant.png", mode="physical", responses=POSE)
    uq_plots.uq_residual_map(maps, A, 2.0, tmp_path / "residual.png", mode="physical", responses=POSE)
    titles = [[ax.get_title() for ax in f.axes] for f in figs]
    ylabels = [[ax.get_ylabel() for ax in f.axes] for f in figs]
    assert ylabels[0] == ["‖δp‖ [mm]", "δφ [mrad]"]
    assert sum("δφ" in t for t in titles[1]) == sum("‖δp‖" in t for t in titles[1]) == 4  # 2 cases x 2 levels
    assert any("δφ" in t for t in titles[2]) and any("δφ [mrad]" == y for y in ylabels[3])
    for f in figs:
        assert "physical" in f.get_suptitle()
        for ax in f.axes:
            for lab in (ax.get_xlabel(), ax.get_ylabel()):
                assert not lab or "[" in lab, lab
        assert figure_checks.mode_problems([f.get_suptitle()], "physical") == []


def test_a_three_cable_difference_panel_counts_the_points_where_the_modes_differ(tmp_path, monkeypatch):
    """Without redundancy both modes solve the same equations, but they can land on different
    solutions: the panel must not call them equal then."""
    import numpy as np

    figs, _ = _captured(monkeypatch)
    A3 = np.array([[-2.5, -1.44, 5], [2.5, -1.44, 5], [0.0, 2.89, 5]])
    t = _plane_table("SR", 1.0).drop(columns="subset")
    same = t.assign(diff=1e-12 * np.sign(t.x - 0.5))
    one = same.copy()
    one.loc[one.index[0], "diff"] = 0.004
    comparison_plots.comparison_difference_maps(
        {("C", "SR"): same, ("C", "DR"): one}, {"C": A3}, 2.5, tmp_path / "d.png"
    )
    titles = [ax.get_title() for ax in figs[0].axes if ax.get_title()]
    assert "both modes equal (|diff| ≤ 1e-09 mm)" in titles[0]
    assert "equal at" not in titles[0]
    assert f"modes equal at {len(t) - 1} points" in titles[1] and "1 differ by up to 4 mm" in titles[1]
    assert "both modes equal" not in titles[1]


def test_sobol_panels_show_the_upper_whiskers_up_to_1_5(tmp_path, monkeypatch):
    """The Sobol figures' y axis reaches the top of every interval (an estimate plus its 95 % interval
    can pass 1 with few base samples: CoGiRo's compensated d group, 0.99 + 0.28), from 1.05 up to 1.5,
    and stays at 1.05 where every whisker is below 1."""
    import pandas as pd
    import pytest

    from tests.conftest import ROOT

    tab = pd.read_csv(ROOT / "tests" / "reference" / "quick_spatial" / "uncertainty" / "sobol.csv")
    figs, _ = _captured(monkeypatch)
    low = tab.assign(ST=0.3, ST_conf=0.1, S1=0.2, S1_conf=0.1)
    high = low.copy()
    high.loc[high.index[0], ["ST", "ST_conf"]] = (0.99, 0.28)  # the first design and case's panels
    huge = low.assign(ST_conf=5.0)
    for t, name in ((low, "low"), (high, "high"), (huge, "huge")):
        uq_plots.uq_sobol(t, tmp_path / f"{name}.png", mode="physical", responses=POSE)
    tops = [
        sorted({round(ax.get_ylim()[1], 6) for ax in f.axes if ax.get_ylabel() or ax.get_xlabel()})
        for f in figs
    ]
    assert tops[0] == [1.05]
    assert max(tops[1]) == pytest.approx(0.99 + 0.28 + 0.05) and min(tops[1]) == 1.05
    assert tops[2] == [1.5]


def test_close_anchors_share_one_label_that_covers_no_marker():
    """CoGiRo's crossed cables leave their pulleys in pairs: one label per pair ("3,4"), none of
    them over an anchor's marker; a point-mass robot keeps one number per anchor."""
    from cdpr.robot import load_robot
    from tests.conftest import ROOT

    for name, labels in (("cogiro", ["1,2", "3,4", "5,6", "7,8"]), ("cdpr4", ["1", "2", "3", "4"])):
        A = load_robot(ROOT / "config" / "robots" / f"{name}.yaml").A
        fig, ax = plt.subplots(figsize=(6, 5))
        style_plots.draw_anchors(ax, A)
        fig.canvas.draw()
        texts = sorted(t.get_text() for t in ax.texts)
        assert texts == labels, name
        pix = ax.transData.transform(A[:, :2])
        for t in ax.texts:
            box = t.get_window_extent().expanded(1.0, 1.0)
            inside = (
                (box.x0 <= pix[:, 0]) & (pix[:, 0] <= box.x1) & (box.y0 <= pix[:, 1]) & (pix[:, 1] <= box.y1)
            )
            assert not inside.any(), (name, t.get_text())
        plt.close(fig)


def test_uq_maps_draw_and_count_the_interfering_points(tmp_path, monkeypatch):
    """Issue 39: the dominant-parameter and residual maps draw the points left out because the
    nominal robot's cables interfere (column ``interfering``) pink, crossed, and count them in the
    panel's title; without such points the titles say nothing of them."""
    import pandas as pd

    from tests.conftest import ROOT

    ref = ROOT / "tests" / "reference" / "quick_spatial" / "uncertainty"
    A = np.array([[-7.0, -5.0, 5.4], [7.0, -5.0, 5.4], [7.0, 5.0, 5.4], [-7.0, 5.0, 5.4]])
    clean = pd.read_csv(ref / "SRopt_compensated_map.csv")
    assert not clean["interfering"].any()
    bad = clean.copy()
    left = bad.index[:3]
    bad.loc[left, "interfering"] = True
    for c in ("dominant", "group", "dominant_phi", "group_phi"):
        bad.loc[left, c] = ""
    for c in ("share", "rms_m", "dp_nominal_m", "share_phi", "rms_phi_rad", "dphi_nominal_rad"):
        bad.loc[left, c] = np.nan
    for maps, n in (({("SRopt", "compensated"): clean}, 0), ({("SRopt", "compensated"): bad}, 3)):
        figs, _ = _captured(monkeypatch)
        uq_plots.uq_dominant_map(maps, A, 2.0, tmp_path / "dominant.png", mode="physical", responses=POSE)
        uq_plots.uq_residual_map(maps, A, 2.0, tmp_path / "residual.png", mode="physical", responses=POSE)
        panels = [ax for f in figs for ax in f.axes if ax.get_title()]
        counted = [ax.get_title() for ax in panels if f"pink crossed: {n} points" in ax.get_title()]
        assert len(counted) == (0 if n == 0 else len(panels)), [ax.get_title() for ax in panels]
        assert not any("pink crossed" in ax.get_title() for ax in panels) or n
