"""The 3-D figures of spatial studies (issue 19): the robot view (``plots.robot.robot_view``, what
``cdpr view`` and the study's robot_view rule draw) and the error-limited volumes on δφ (a δφ row in
Fig. 13, Fig. 14 on δφ), and the pulley-axis figure of docs/spatial.md
(``plots.robot.pulley_axis_figure``, drawn at the docs' build by docs/hooks/pulley_figure.py). Every
figure passes the layout audit (``plots.style.audit``: no overlapping text, none off the canvas,
labelled axes with units) and the study figures name the mode."""

import importlib.util

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from mpl_toolkits.mplot3d.art3d import Text3D

from cdpr.analyses import scans, workspace
from cdpr.pipeline.plots import robot as robot_plots
from cdpr.pipeline.plots import style as style_plots
from cdpr.pipeline.plots import volumes as volumes_plots
from cdpr.robot import load_robot, with_pulleys
from tests.conftest import ROBOTS, ROOT


def _captured(monkeypatch):
    """Figures handed to ``plots.style.save`` by the figure modules, audited and kept open for
    inspection (files still written)."""
    figs = []

    def keep(fig, out):
        figs.append((fig, style_plots.audit(fig)))
        fig.savefig(str(out), dpi=40)
        return [out]

    for module in (robot_plots, volumes_plots):
        monkeypatch.setattr(module, "save", keep)
    return figs


def test_box_edges_are_the_twelve_edges_of_the_box():
    box = [-1.0, 2.0, 0.0, 4.0, 0.5, 1.0]
    edges = robot_plots._box_edges(box)
    assert len(edges) == 12
    lengths = sorted(float(np.linalg.norm(e[1] - e[0])) for e in edges)
    assert lengths == pytest.approx([0.5] * 4 + [3.0] * 4 + [4.0] * 4)
    for e in edges:  # axis-aligned, between corners of the box
        assert (np.abs(e[1] - e[0]) > 0).sum() == 1
        for c in e:
            assert all(c[a] in (box[2 * a], box[2 * a + 1]) for a in range(3))


@pytest.mark.parametrize(
    "name, rotvec, labels",
    [
        ("cogiro.yaml", [0.0, 0.0, 0.2], ["1,2", "3,4", "5,6", "7,8"]),  # crossed cables leave in pairs
        ("cdpr4.yaml", None, ["1", "2", "3", "4"]),
    ],
)
def test_robot_view_of_a_spatial_and_a_point_mass_robot(tmp_path, monkeypatch, name, rotvec, labels):
    figs = _captured(monkeypatch)
    robot = load_robot(ROBOTS / name)
    geom = scans.pose_geometry(robot, scans.view_position(robot), rotvec)
    boxes = {"frame box": workspace.frame_box(robot), "RW_C": [-1.0, 1.0, -1.0, 1.0, 1.0, 3.0]}
    robot_plots.robot_view(geom, tmp_path / "robot.png", boxes=boxes, mode="physical")
    ((fig, rec),) = figs
    assert rec["problems"] == [] and "physical" in rec["titles"][0] and robot.name in rec["titles"][0]
    ax = fig.axes[0]
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()) == ("x [m]", "y [m]", "z [m]")
    assert sorted(t.get_text() for t in ax.texts if isinstance(t, Text3D)) == labels
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend[:2] == ["frame box", "RW_C"] and "swivel axes k_i" in legend
    assert ("centre of mass" in legend) == (not robot.point_mass)
    # every box's edges are drawn (12 lines each) and the view holds them all
    lo = np.array([ax.get_xlim()[0], ax.get_ylim()[0], ax.get_zlim()[0]])
    hi = np.array([ax.get_xlim()[1], ax.get_ylim()[1], ax.get_zlim()[1]])
    for b in boxes.values():
        assert (lo <= np.asarray(b)[0::2]).all() and (np.asarray(b)[1::2] <= hi).all()
    # equal scale: the box aspect is the data ranges'
    aspect = ax.get_box_aspect()
    assert aspect / aspect[0] == pytest.approx((hi - lo) / (hi - lo)[0], rel=1e-6)
    plt.close(fig)


def test_robot_view_without_a_mode_or_boxes(tmp_path):
    """``cdpr view``'s call: no mode, no box; a PNG and a PDF."""
    robot = load_robot(ROBOTS / "wall_pulleys.yaml")
    paths = robot_plots.robot_view(scans.pose_geometry(robot, scans.view_position(robot)), tmp_path / "w.png")
    assert [p.suffix for p in paths] == [".png", ".pdf"] and all(p.stat().st_size > 10_000 for p in paths)


def _grid(n=6):
    robot = load_robot(ROBOTS / "cogiro.yaml")
    box = workspace.frame_box(robot)
    P = workspace.grid_points(box, n)
    r = np.linalg.norm((P - P.mean(axis=0)) / (np.asarray(box)[1::2] - np.asarray(box)[0::2]), axis=1)
    df = pd.DataFrame(
        {
            "x": P[:, 0],
            "y": P[:, 1],
            "z": P[:, 2],
            "dp": 0.1 + 0.2 * r,
            "dphi": 0.002 + 0.02 * r,
            "status": "ok",
        }
    )
    return robot, df


def test_volume_view_draws_a_dphi_row_under_the_dp_row(tmp_path, monkeypatch):
    figs = _captured(monkeypatch)
    robot, df = _grid()
    z = float(robot.A[:, 2].min())
    args = (df, [0.15, 0.2], [0.4, 0.6], z, "CoGiRo SR: V_L", tmp_path / "vl.png")
    volumes_plots.fig13_volume_view(
        *args, A=robot.A, mode="physical", dphi_limits=[0.005, 0.01], dphi_R_V=[0.1, 0.3]
    )
    volumes_plots.fig13_volume_view(*args, A=robot.A, mode="physical")
    (two, rec2), (one, rec1) = figs
    assert rec2["problems"] == [] and rec1["problems"] == []
    titles = [ax.get_title() for ax in two.axes if hasattr(ax, "zaxis")]
    assert titles == [
        "‖δp‖ ≤ 150 mm: R_V = 0.40",
        "‖δp‖ ≤ 200 mm: R_V = 0.60",
        "δφ ≤ 5 mrad: R_V = 0.10",
        "δφ ≤ 10 mrad: R_V = 0.30",
    ]
    bars = [ax.get_xlabel() for ax in two.axes if not hasattr(ax, "zaxis")]
    assert bars == ["‖δp‖ [mm]", "δφ [mrad]"]
    assert [ax.get_xlabel() for ax in one.axes if not hasattr(ax, "zaxis")] == ["‖δp‖ [mm]"]
    assert len(one.axes) == 3 and len(two.axes) == 6
    plt.close(one)
    plt.close(two)


def test_rv_on_dphi_figure_marks_the_study_limits(tmp_path, monkeypatch):
    figs = _captured(monkeypatch)
    lims = [0.0025, 0.005, 0.0075, 0.01]
    tab = pd.DataFrame(
        {
            "robot": ["CoGiRo"] * 8,
            "pulley": ["SR"] * 4 + ["DR"] * 4,
            "limit_rad": lims * 2,
            "R_V": [0.1, 0.3, 0.45, 0.5, 0.05, 0.2, 0.4, 0.55],
            "study_limit": [False, True, False, True] * 2,
        }
    )
    volumes_plots.fig14_rv_dphi(tab, tmp_path / "rv.png", mode="physical")
    ((fig, rec),) = figs
    assert rec["problems"] == [] and "physical" in rec["titles"][0]
    ax = fig.axes[0]
    assert ax.get_xlabel() == "orientation error limit δφ_lim [mrad]" and ax.get_ylabel().endswith("[-]")
    vertical = [
        ln.get_xdata()[0] for ln in ax.lines if ln.get_linestyle() == ":" and len(ln.get_xdata()) == 2
    ]
    assert sorted(vertical) == pytest.approx([5.0, 10.0])
    sr = [ln for ln in ax.lines if ln.get_label() == "CoGiRo SR"][0]
    assert list(sr.get_xdata()) == pytest.approx([2.5, 5.0, 7.5, 10.0]) and list(sr.get_ydata()) == [
        0.1,
        0.3,
        0.45,
        0.5,
    ]
    plt.close(fig)


# ---- the pulley-axis figure of docs/spatial.md (plots.robot.pulley_axis_figure, docs/hooks/pulley_figure.py) ----
def _pulley_hook():
    """docs/hooks/pulley_figure.py, the MkDocs hook that draws the figure at build time, as a module."""
    spec = importlib.util.spec_from_file_location(
        "pulley_figure_hook", ROOT / "docs" / "hooks" / "pulley_figure.py"
    )
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    return hook


def _hook_geometries(hook):
    robot = load_robot(hook.ROBOT)
    i = hook.CABLE - 1
    B = robot.A[i] + np.asarray(hook.B_MINUS_A)
    return [
        scans.pulley_plane_geometry(
            with_pulleys(robot, kind=k, h=h, r_p=r, dead_length=hook.DEAD_LENGTH), i, B
        )
        for k, h, r in hook.DESIGNS
    ]


def test_pulley_plane_geometry_is_the_pulley_model():
    """SR with h = r_p: K on the axis at A; D on the sheave and |B - D| = l_E tangent; L_TE = d + r_p γ +
    l_E; the in-plane coordinates keep every 3-D distance (all points lie in the plane through k_i and
    B); the arc runs from K to D and is r_p γ long. DR: the arm |A H| = h and K a tangent point from C."""
    sr, dr = _hook_geometries(_pulley_hook())
    for g in (sr, dr):
        X, P, r = g["points"], g["plane"], g["r_p"]
        k = g["frame"][2]
        assert (
            abs(np.linalg.norm(X["D"] - X["H"]) - r) < 1e-12
            and abs(np.linalg.norm(X["K"] - X["H"]) - r) < 1e-12
        )
        assert abs(np.linalg.norm(X["B"] - X["D"]) - g["l_E"]) < 1e-12
        assert abs((X["D"] - X["H"]) @ (X["B"] - X["D"])) < 1e-12
        assert abs((X["K"] - X["H"]) @ (X["K"] - X["C"])) < 1e-12
        assert abs(g["L_TE"] - (g["l_d"] + r * g["gamma"] + g["l_E"])) < 1e-12
        assert abs(np.linalg.norm(X["H"] - X["A"]) - g["h"]) < 1e-12
        assert (
            np.abs(X["C"] - (X["A"] - g["d"] * k)).max() < 1e-12
            and np.abs(P["C"] - [0.0, -g["d"]]).max() < 1e-12
        )
        names = list(X)
        for a in names:
            for b in names:
                assert abs(np.linalg.norm(P[a] - P[b]) - np.linalg.norm(X[a] - X[b])) < 1e-12
        assert np.abs(g["arc"][0] - P["K"]).max() < 1e-12 and np.abs(g["arc"][-1] - P["D"]).max() < 1e-12
        seg = np.linalg.norm(np.diff(g["arc"], axis=0), axis=1).sum()
        assert seg == pytest.approx(r * g["gamma"], rel=1e-4)
        assert P["B"][0] > 0  # s points toward B
    assert sr["kind"] == "SR" and sr["h"] == sr["r_p"]
    assert np.linalg.norm(sr["points"]["K"] - sr["points"]["A"]) < 1e-12 and abs(sr["l_d"] - sr["d"]) < 1e-12
    assert dr["kind"] == "DR" and np.linalg.norm(dr["points"]["K"] - dr["points"]["A"]) > 0.05
    # the swivel angle drawn is atan2(w . j_i, w . i_i), w = B - A
    w = sr["points"]["B"] - sr["points"]["A"]
    assert sr["swivel"] == pytest.approx(np.arctan2(w @ sr["frame"][1], w @ sr["frame"][0]), abs=1e-12)


def test_pulley_axis_figure_draws_the_models_points(tmp_path, monkeypatch):
    figs = _captured(monkeypatch)
    hook = _pulley_hook()
    hook.draw(tmp_path / "pulley_axis.png")
    ((fig, rec),) = figs
    assert rec["problems"] == []
    geoms = _hook_geometries(hook)
    for ax, g in zip(fig.axes[:2], geoms):
        P = g["plane"]
        same = np.linalg.norm(P["K"] - P["A"]) < 1e-9
        dots = sorted(tuple(ln.get_xydata()[0]) for ln in ax.lines if ln.get_marker() == "o")
        want = sorted(tuple(xy) for n, xy in P.items() if not (same and n == "K"))
        assert np.allclose(dots, want, atol=1e-12)
        cable = [ln.get_xydata() for ln in ax.lines if ln.get_color() == "tab:blue"]
        assert np.allclose(cable[0], [P["C"], P["K"]]) and np.allclose(cable[1], g["arc"])
        assert np.allclose(cable[2], [P["D"], P["B"]])
        texts = {t.get_text() for t in ax.texts}
        assert {"$C_i$", "$H_i$", "$D_i$", "$B_i$", "$h$", r"$\mathbf{k}_i$"} <= texts
        assert ("$A_i = K_i$" in texts) == same and ("$K_i$" in texts) == (not same)
        assert "[m]" in ax.get_xlabel() and "[m]" in ax.get_ylabel()
    assert [g["kind"] for g in geoms] == ["SR", "DR"]
    assert any("swivel" in t.get_text() for t in fig.axes[2].texts)
    plt.close(fig)


def test_the_docs_build_adds_the_pulley_figure_without_writing_into_docs():
    """The hook's on_files adds figures/pulley_axis.png to the site as a generated file (PNG bytes);
    nothing is written under docs/."""
    from types import SimpleNamespace

    from mkdocs.structure.files import Files

    hook = _pulley_hook()
    before = sorted((ROOT / "docs").rglob("*"))
    plugins = SimpleNamespace(_current_plugin=None)
    config = SimpleNamespace(site_dir="/nonexistent-site", use_directory_urls=True, plugins=plugins)
    files = hook.on_files(Files([]), config)
    f = files.get_file_from_path(hook.URI)
    assert f is not None and f.generated_by is not None
    assert f.content_bytes[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted((ROOT / "docs").rglob("*")) == before


def test_robot_view_title_shows_no_round_off(tmp_path, monkeypatch):
    """A pose computed through a rotation carries round-off (1.11e-16 m, -0): the title says 0."""
    figs = _captured(monkeypatch)
    robot = load_robot(ROBOTS / "cogiro.yaml")
    p = np.asarray(scans.view_position(robot), dtype=float) + [1.11e-16, -2e-17, 0.0]
    geom = scans.pose_geometry(robot, p, [-1e-17, 0.0, 0.2])
    robot_plots.robot_view(geom, tmp_path / "robot.png")
    ((_, rec),) = figs
    title = rec["titles"][0]
    assert "e-1" not in title and "-0," not in title and "rotvec = [0, 0, 0.2] rad" in title
