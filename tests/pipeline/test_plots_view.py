"""The 3-D figures of spatial studies (issue 19): the robot view (``plots.robot_view``, what ``cdpr
view`` and the study's robot_view rule draw) and the error-limited volumes on δφ (a δφ row in Fig. 13,
Fig. 14 on δφ). Every figure passes the layout audit (``plots.audit``: no overlapping text, none off
the canvas, labelled axes with units) and names the mode."""

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from mpl_toolkits.mplot3d.art3d import Text3D

from cdpr.analyses import scans, workspace
from cdpr.pipeline import plots
from cdpr.robot import load_robot
from tests.conftest import ROBOTS


def _captured(monkeypatch):
    """Figures handed to plots.save, audited and kept open for inspection (files still written)."""
    figs = []

    def keep(fig, out):
        figs.append((fig, plots.audit(fig)))
        fig.savefig(str(out), dpi=40)
        return [out]

    monkeypatch.setattr(plots, "save", keep)
    return figs


def test_box_edges_are_the_twelve_edges_of_the_box():
    box = [-1.0, 2.0, 0.0, 4.0, 0.5, 1.0]
    edges = plots._box_edges(box)
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
    plots.robot_view(geom, tmp_path / "robot.png", boxes=boxes, mode="physical")
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
    paths = plots.robot_view(scans.pose_geometry(robot, scans.view_position(robot)), tmp_path / "w.png")
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
    plots.fig13_volume_view(*args, A=robot.A, mode="physical", dphi_limits=[0.005, 0.01], dphi_R_V=[0.1, 0.3])
    plots.fig13_volume_view(*args, A=robot.A, mode="physical")
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
    plots.fig14_rv_dphi(tab, tmp_path / "rv.png", mode="physical")
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
