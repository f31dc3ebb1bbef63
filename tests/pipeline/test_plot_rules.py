"""Issue 41's figure rules, each checked on the figure's own data (the artists matplotlib holds):
the paper's values only in a study that compares with the paper, the plane's colour scale said per
panel, no legend or title promising a line that is not drawn, taut-set maps with distinct colours
and a legend that fits, one colour per effect across the budget's panels."""

import itertools

import matplotlib.colors as mcolors
import numpy as np
import pandas as pd
import pytest

from cdpr.pipeline.plots import budget as budget_plots
from cdpr.pipeline.plots import dead_length as dead_length_plots
from cdpr.pipeline.plots import planes as planes_plots
from tests.conftest import ROOT

A = np.array([[-2.5, -2.5, 5], [2.5, -2.5, 5], [2.5, 2.5, 5], [-2.5, 2.5, 5]])


@pytest.fixture
def figs(monkeypatch):
    """The figures the modules hand to ``save``, kept open (nothing written)."""
    kept = []
    for module in (budget_plots, dead_length_plots, planes_plots):
        monkeypatch.setattr(module, "save", lambda fig, out: kept.append(fig) or [out])
    return kept


def _plane(scale, t_lo=100.0):
    x, y = np.meshgrid(np.linspace(-2, 2, 9), np.linspace(-2, 2, 9))
    x, y = x.ravel(), y.ravel()
    return pd.DataFrame(
        {
            "x": x,
            "y": y,
            "dp": scale * (0.05 + 0.01 * (x**2 + y**2)),
            "status": "ok",
            "t1": t_lo + 50 * (x + 2),
            "t2": 900.0,
            "t3": 900.0,
            "t4": 900.0,
            "taut": "1-2-3",
        }
    )


def _lines(fig):
    return [ln for ax in fig.axes for ln in ax.get_lines()]


@pytest.mark.parametrize("paper", [True, False])
def test_dead_length_draws_the_paper_values_only_when_the_study_compares_with_the_paper(
    figs, paper, tmp_path
):
    d = np.array([2.0, 4.0, 6.0])
    tab = pd.DataFrame(
        {
            "d_m": d,
            "plane_SR_min_m": 0.08 + 0 * d,
            "plane_SR_max_m": 0.2 + 0 * d,
            "SRopt_Emean_index_m": 0.05 + 0 * d,
        }
    )
    dead_length_plots.dead_length_figure(tab, 4.0, tmp_path / "d.png", paper=paper)
    labels = [ln.get_label() for ln in _lines(figs[0])]
    assert any(lab.startswith("paper ") for lab in labels) == paper, labels


def test_plane_figure_says_its_colour_scale_is_per_panel(figs, tmp_path):
    planes_plots.fig12_plane({"SR": _plane(1.0), "DR": _plane(0.3)}, A, 2.5, "R", tmp_path / "p.png")
    fig = figs[0]
    assert "colour scale per panel" in fig._suptitle.get_text()
    bars = [ax for ax in fig.axes if ax.get_ylabel() == "‖δp‖ [mm]"]
    assert len(bars) == 2 and bars[0].get_ylim() != bars[1].get_ylim()  # the scales do differ
    planes_plots.fig12_plane({"SR": _plane(1.0)}, A, 2.5, "R", tmp_path / "q.png")
    assert "per panel" not in figs[1]._suptitle.get_text()  # one panel: nothing to say
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:  # nor do the docs promise one
        assert "shared colour scale" not in " ".join(page.read_text().split()), page


def _red_contours(fig):
    return [
        c
        for ax in fig.axes
        for c in ax.collections
        if len(c.get_edgecolor()) and np.allclose(c.get_edgecolor()[0][:3], mcolors.to_rgb("r"))
    ]


def test_tension_figure_promises_the_red_line_only_where_it_is_drawn(figs, tmp_path):
    tables = {"SR": _plane(1.0), "DR": _plane(1.0)}
    planes_plots.fig12_tension(tables, A, 2.5, "R", 0.0, tmp_path / "t.png", mode="physical")
    assert "red" not in figs[0]._suptitle.get_text() and not _red_contours(figs[0])  # t >= 100 N > 0 N
    planes_plots.fig12_tension(tables, A, 2.5, "R", 200.0, tmp_path / "u.png", mode="physical")
    assert "red: min t_i = 200 N" in figs[1]._suptitle.get_text() and _red_contours(figs[1])


def test_taut_set_map_groups_rare_sets_as_other_with_distinct_colours(figs, tmp_path):
    """36 taut sets (issue 41's CoGiRo plane): 9 colours of their own, the rest one "other"."""
    sets = ["-".join(map(str, c)) for k in (4, 5) for c in itertools.combinations(range(1, 9), k)][:36]
    df = _plane(1.0)
    df["taut"] = [sets[i % 36] if i < 45 else sets[0] for i in range(len(df))]  # set 1 most frequent
    labels, code, cmap = planes_plots.category_colours({"SR": df}, "taut")
    assert len(labels) == 10 and labels[-1] == "other (27 sets)"
    assert set(code) == set(sets) and set(code.values()) == set(range(10))
    colours = [tuple(c) for c in cmap.colors]
    assert len(set(colours)) == len(colours) == 10
    planes_plots.fig9_taut({"SR": df}, A, 2.5, "R", tmp_path / "s.png")
    ticks = [t.get_text() for t in figs[0].axes[-1].get_yticklabels()]
    assert len(ticks) == 10 and ticks[-1] == "other (27 sets)" and ticks[0].startswith("taut ")
    few = df.assign(taut=np.where(df.x > 0, "1-2-3", "1-2-3-4"))
    assert planes_plots.category_colours({"SR": few}, "taut")[0] == ["1-2-3", "1-2-3-4"]  # no grouping


@pytest.mark.parametrize("heavy", [False, True])
def test_budget_gives_each_effect_one_colour_in_every_panel(figs, tmp_path, heavy):
    effects = ("pulley", "elasticity", "winch", "sag") if heavy else ("pulley", "elasticity", "winch")
    entries = [*effects, "interaction", "all"]
    entries += [f"compensated_{e}" for e in (*effects, "all")] + (["neglected_sag"] if heavy else [])
    rows = [
        {
            "design": d,
            "region": "RW_C",
            "entry": e,
            "mean_m": 1e-3 * (i + 1),
            "share_m": 1e-4,
            "mean_rad": 1e-3,
        }
        for d in ("R_SR", "R_DR")
        for i, e in enumerate(entries)
    ]
    budget_plots.budget_bars(pd.DataFrame(rows), tmp_path / "b.png")
    seen = {}
    for ax in figs[0].axes:
        for patch, label in _bars(ax):
            effect = label.split()[-1] if label.startswith("compensating") else label.split()[0]
            colour = mcolors.to_hex(patch.get_facecolor(), keep_alpha=False)
            seen.setdefault(effect, set()).add(colour)
    assert {*effects, "all"} <= set(seen)
    assert all(len(c) == 1 for c in seen.values()), seen
    assert len({next(iter(c)) for c in seen.values()}) == len(seen)  # and no two effects share one


def _bars(ax):
    """(first patch, legend label) of each bar container of ``ax``."""
    return [(c.patches[0], c.get_label()) for c in ax.containers if c.patches]


def test_cdpr_view_plan_adds_a_top_view_of_every_anchor(tmp_path, monkeypatch):
    """``cdpr view --plan``: a 2-D panel beside the 3-D one, x and y to equal scale, every anchor
    seen from above, its cable numbers labelled (crossed pairs share one label)."""
    from cdpr.cli.main import main
    from cdpr.pipeline.plots import robot as robot_plots
    from cdpr.robot import load_robot
    from tests.conftest import ROBOTS

    kept = []
    monkeypatch.setattr(robot_plots, "save", lambda fig, out: kept.append(fig) or [out])
    assert (
        main(["view", "--robot", str(ROBOTS / "cogiro.yaml"), "--plan", "--out", str(tmp_path / "v.png")])
        == 0
    )
    fig = kept[0]
    plan = [ax for ax in fig.axes if ax.name != "3d"]
    assert len(fig.axes) == 2 and len(plan) == 1 and plan[0].get_title().startswith("plan (top) view")
    ax = plan[0]
    assert ax.get_aspect() == 1.0 and ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    A = load_robot(ROBOTS / "cogiro.yaml").A
    anchors = ax.collections[0].get_offsets()  # the first scatter: the anchors' x, y
    np.testing.assert_allclose(np.asarray(anchors), A[:, :2])
    numbers = sorted(int(n) for t in ax.texts for n in t.get_text().split(","))
    assert numbers == list(range(1, len(A) + 1))
    assert main(["view", "--robot", str(ROBOTS / "cogiro.yaml"), "--out", str(tmp_path / "w.png")]) == 0
    assert len(kept[1].axes) == 1  # without --plan: the 3-D view alone, as before
