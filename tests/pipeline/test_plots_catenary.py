"""Heavy cables drawn as catenaries (issue 38): ``cdpr view`` and the study's robot view
(``plots.robot.robot_view`` on ``scans.pose_geometry``) draw each heavy cable as the polyline of its
elastic catenary from B_i to its exit point D_i, and the large study's corner figure
(``plots.sag.sag_corner``) the same polylines. The drawn points are checked against the model
computed on its own path (``compensation.compensate``'s planned cables, what ``cdpr compensate``
reports as ``sag_m``), not against the drawing's own numbers."""

import importlib.util

import matplotlib.pyplot as plt
import numpy as np
import pytest

from cdpr.analyses import compensation, scans
from cdpr.pipeline.plots import robot as robot_plots
from cdpr.pipeline.plots import sag as sag_plots
from cdpr.pipeline.plots import style as style_plots
from cdpr.robot import load_robot
from tests.conftest import ROBOTS, ROOT

CORNER = [-20.0, -20.0, 10.0]  # the large study's corner pose (config/studies/large.yaml)


def _captured(monkeypatch, *modules):
    figs = []

    def keep(fig, out):
        figs.append((fig, style_plots.audit(fig)))
        return [out]

    for module in modules:
        monkeypatch.setattr(module, "save", keep)
    return figs


def _drawn_cables(fig, m):
    """The 3-D points of each cable line of the robot view (their gid ``cable i``)."""
    lines = {ln.get_gid(): ln for ln in fig.axes[0].get_lines() if (ln.get_gid() or "").startswith("cable ")}
    assert sorted(lines) == [f"cable {i + 1}" for i in range(m)]
    return [np.column_stack(lines[f"cable {i + 1}"].get_data_3d()) for i in range(m)]


def _deflection(P):
    """Largest distance of the polyline's points from its chord (first to last point) [m]."""
    c = P[-1] - P[0]
    c = c / np.linalg.norm(c)
    Q = P - P[0]
    return float(np.linalg.norm(Q - np.outer(Q @ c, c), axis=1).max())


def test_view_draws_heavy_cables_on_their_catenaries(tmp_path, monkeypatch):
    figs = _captured(monkeypatch, robot_plots)
    robot = load_robot(ROBOTS / "cube50.yaml")
    geom = scans.pose_geometry(robot, CORNER)
    robot_plots.robot_view(geom, tmp_path / "v.png")
    ((fig, rec),) = figs
    assert rec["problems"] == []
    drawn = _drawn_cables(fig, robot.m)
    # the model on its own path: the compensated pose's planned cables (cdpr compensate's cables)
    comp = compensation.compensate(robot, np.array([CORNER]))
    planned = comp["cables"]
    assert comp["feasible"].all()
    for i, P in enumerate(drawn):
        assert len(P) == scans.CATENARY_POINTS
        assert P[0] == pytest.approx(geom["B"][i], abs=1e-9)  # from B_i ...
        assert P[-1] == pytest.approx(planned["D"][0, i], abs=1e-6)  # ... to the heavy exit point D_i
        # in the vertical plane through B_i and D_i
        h = P[-1, :2] - P[0, :2]
        normal = np.array([-h[1], h[0]]) / np.linalg.norm(h)
        assert np.abs((P[:, :2] - P[0, :2]) @ normal).max() < 1e-9
        # below the chord (a hanging cable) by the model's sag at the widest point
        sag_m = float(planned["sag"][0, i])
        assert sag_m > 0.005
        assert _deflection(P) == pytest.approx(sag_m, rel=2e-3)
        chord_z = P[0, 2] + (P[-1, 2] - P[0, 2]) * np.linalg.norm(
            P[:, :2] - P[0, :2], axis=1
        ) / np.linalg.norm(h)
        assert (P[1:-1, 2] < chord_z[1:-1]).all()
    # cable 3 (the far, slackest one) sags by metres on this 50 m robot: visibly not a line
    assert planned["sag"][0].max() > 1.0
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any(t.startswith("cables: catenaries") for t in legend)
    plt.close(fig)


def test_view_of_massless_cables_draws_straight_lines(tmp_path, monkeypatch):
    """w = 0: no catenary key, each cable the two points D_i, B_i (the drawing as before)."""
    figs = _captured(monkeypatch, robot_plots)
    robot = load_robot(ROBOTS / "cube50_massless.yaml")
    geom = scans.pose_geometry(robot, CORNER)
    assert "catenary" not in geom
    robot_plots.robot_view(geom, tmp_path / "v.png")
    ((fig, _),) = figs
    for i, P in enumerate(_drawn_cables(fig, robot.m)):
        assert np.array_equal(P, np.stack([geom["D"][i], geom["B"][i]]))
    plt.close(fig)


def test_corner_figure_draws_the_catenaries(tmp_path, monkeypatch):
    """The large study's corner figure: axes in m, the mode in the title, each cable's deflection
    from its chord peaking at the model's sag."""
    figs = _captured(monkeypatch, sag_plots)
    robot = load_robot(ROBOTS / "cube50.yaml")
    geom = scans.pose_geometry(robot, CORNER)
    sag_plots.sag_corner(geom, tmp_path / "c.png", mode="physical")
    ((fig, rec),) = figs
    assert rec["problems"] == []
    assert "physical" in fig._suptitle.get_text()
    a1, a2 = fig.axes
    assert a1.get_xlabel().endswith("[m]") and a1.get_ylabel() == "z [m]" and a2.get_ylabel().endswith("[m]")
    sags = [float(np.max(ln.get_ydata())) for ln in a2.get_lines()]
    assert sags == pytest.approx(list(geom["catenary_sag"]), rel=2e-3)
    plt.close(fig)


def test_the_docs_build_adds_the_corner_figure_without_writing_into_docs():
    """docs/hooks/catenary_figure.py's on_files adds figures/catenary_corner.png (PNG bytes) to the
    site, drawn from the large study's `sag` section; nothing is written under docs/."""
    from types import SimpleNamespace

    from mkdocs.structure.files import Files

    spec = importlib.util.spec_from_file_location(
        "catenary_figure_hook", ROOT / "docs" / "hooks" / "catenary_figure.py"
    )
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    assert hook.URI in (ROOT / "docs" / "heavy_cables.md").read_text(encoding="utf-8")
    before = sorted((ROOT / "docs").rglob("*"))
    config = SimpleNamespace(
        site_dir="/nonexistent-site", use_directory_urls=True, plugins=SimpleNamespace(_current_plugin=None)
    )
    files = hook.on_files(Files([]), config)
    f = files.get_file_from_path(hook.URI)
    assert f is not None and f.generated_by is not None
    assert f.content_bytes[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted((ROOT / "docs").rglob("*")) == before
