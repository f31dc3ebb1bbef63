"""The pipeline jobs of the 3-D figures and the volumes on δφ (cdpr.pipeline.tasks.robot_view,
volumes_dphi) on hand-made inputs: a RW_C file and frame-grid shards of the quick spatial study."""

import json

import numpy as np
import pandas as pd
import pytest

from cdpr import table_io
from cdpr.analyses import scans, workspace
from cdpr.pipeline import plots, study, tasks
from tests.conftest import ROOT

QUICK_SPATIAL = ROOT / "config" / "studies" / "quick_spatial.yaml"


@pytest.fixture
def st(monkeypatch):
    monkeypatch.chdir(ROOT)  # robot paths of the study files are relative to the repository
    return study.load_study(QUICK_SPATIAL)


def _record_views(tmp_path, box, monkeypatch):
    """Write ``box`` as tmp_path/rw_c.json and record every ``plots.robot_view`` call (geometry,
    keywords) while it still draws: the list it appends to."""
    (tmp_path / "rw_c.json").write_text(json.dumps({"box": box}), encoding="utf-8")
    seen = []
    real = plots.robot_view
    monkeypatch.setattr(
        plots, "robot_view", lambda geom, out, **kw: seen.append((geom, kw)) or real(geom, out, **kw)
    )
    return seen


def test_robot_view_puts_the_platform_at_the_centre_of_rw_c(st, tmp_path, monkeypatch):
    box = [-3.0, 3.0, -2.0, 1.0, 0.5, 3.5]
    seen = _record_views(tmp_path, box, monkeypatch)
    out = tmp_path / "robot" / "CoGiRo.png"
    tasks.robot_view(st, "CoGiRo", str(tmp_path / "rw_c.json"), str(out))
    ((geom, kw),) = seen
    assert geom["p"].tolist() == [0.0, -0.5, 2.0] and geom["rotvec"].tolist() == st["rotvec_rad"]
    assert kw["mode"] == "physical"
    assert list(kw["boxes"].values())[1] == box and "RW_C (rw_c.json, computed)" in kw["boxes"]
    robot = study.robot_of(st, "CoGiRo")
    assert list(kw["boxes"].values())[0] == workspace.frame_box(robot)
    assert out.stat().st_size > 10_000 and out.with_suffix(".pdf").stat().st_size > 0


def test_robot_view_of_a_point_mass_study_draws_each_robot(tmp_path, monkeypatch):
    """The paper's robots (point masses) get their view too: the DOE robot (CDPR4) at RW_C's centre
    with its box, the other (CDPR3) at ``scans.view_position`` with the frame box alone."""
    monkeypatch.chdir(ROOT)
    st = study.load_study(ROOT / "config" / "studies" / "quick.yaml")
    box = [-0.6, 0.6, -0.4, 0.8, 1.0, 2.2]
    seen = _record_views(tmp_path, box, monkeypatch)
    doe_robot = st["doe"]["robot"]
    other = next(k for k in st["robots"] if k != doe_robot)
    for key in (doe_robot, other):
        tasks.robot_view(st, key, str(tmp_path / "rw_c.json"), str(tmp_path / "robot" / f"{key}.png"))
    (g1, kw1), (g2, kw2) = seen
    assert g1["point_mass"] and g2["point_mass"]
    assert g1["p"].tolist() == pytest.approx([0.0, 0.2, 1.6]) and list(kw1["boxes"].values())[1] == box
    assert len(kw2["boxes"]) == 1 and kw1["mode"] == kw2["mode"] == study.redundancy(st)
    robot = study.robot_of(st, other)
    assert g2["p"].tolist() == pytest.approx(scans.view_position(robot).tolist())
    for key in (doe_robot, other):
        assert (tmp_path / "robot" / f"{key}.png").stat().st_size > 10_000


def test_volumes_dphi_counts_the_voxels_of_each_design(st, tmp_path):
    """Shards with δφ a known field (SR: 2 mrad + 1 mrad per m from the centre, DR twice that) and
    a few points not ok: V_L = (ok points with δφ <= limit) x the voxel's volume, R_V = V_L / V_T."""
    n = st["volumes"]["n"]
    paths, fields = [], {}
    for k, pk in enumerate(st["pulleys"]):
        robot = study.design_robot(st, "CoGiRo", st["pulleys"][pk])
        box = workspace.frame_box(robot)
        P = workspace.grid_points(box, n)
        dphi = (k + 1) * (0.002 + 0.001 * np.linalg.norm(P - P.mean(axis=0), axis=1))
        status = np.where(np.arange(len(P)) % 7 == 0, "over_tension", "ok")
        df = pd.DataFrame(
            {"x": P[:, 0], "y": P[:, 1], "z": P[:, 2], "dp": 0.1, "dphi": dphi, "status": status}
        )
        half = len(df) // 2  # two shards, given out of order
        for s, part in ((1, df.iloc[half:]), (0, df.iloc[:half])):
            p = tmp_path / f"CoGiRo_{pk}_{s}.parquet"
            table_io.write_table(part, p)
            paths.append(str(p))
        voxel = workspace.box_volume(box) / n**3
        fields[pk] = (dphi, status == "ok", voxel, workspace.envelope_volume(robot))
    out = tmp_path / "volumes_dphi.csv"
    tasks.volumes_dphi(st, paths, str(out), str(tmp_path / "R_V_dphi.png"))
    tab = pd.read_csv(out)
    lims = study.dphi_volume_limits(st)
    assert len(tab) == len(lims) * 2 and list(tab.columns[:3]) == ["robot", "pulley", "limit_rad"]
    for row in tab.itertuples():
        dphi, ok, voxel, V_T = fields[row.pulley]
        expected = int((ok & (dphi <= row.limit_rad)).sum()) * voxel
        assert row.V_L_m3 == pytest.approx(expected) and row.R_V == pytest.approx(expected / V_T)
        assert row.study_limit == (row.limit_rad in st["volumes"]["dphi_limits_rad"])
    sr, dr = (tab[tab.pulley == p].R_V.to_numpy() for p in ("SR", "DR"))
    assert (np.diff(sr) >= 0).all() and (dr <= sr).all() and sr[-1] > dr[-1]  # DR's δφ is twice SR's
    assert (tmp_path / "R_V_dphi.png").stat().st_size > 0
