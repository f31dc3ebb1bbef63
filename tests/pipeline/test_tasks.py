"""The pipeline jobs of cdpr.pipeline.tasks on small hand-made inputs.

The global-index jobs of the DOE and of the E sweep (``index_shard``, ``elasticity_shard``): one
process per slice of the tests or moduli, one solve per orbit of the grid's symmetries. The jobs of
the 3-D figures and the volumes on δφ (``robot_view``, ``volumes_dphi``) on a RW_C file and
frame-grid shards of the quick spatial study. ``concat``, the tasks' helper that joins shards."""

import json

import numpy as np
import pandas as pd
import pytest

from cdpr import table_io
from cdpr.analyses import doe, scans, workspace
from cdpr.analyses.workspace import grid_points
from cdpr.errors import CdprError
from cdpr.pipeline import study, tasks
from cdpr.pipeline.plots import robot as robot_plots
from cdpr.solve import solve
from tests.conftest import ROOT

BOX = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


@pytest.fixture()
def quick(monkeypatch, tmp_path):
    monkeypatch.chdir(ROOT)
    st = study.load_study(ROOT / "config" / "studies" / "quick_physical.yaml")
    box = tmp_path / "rw_c.json"
    box.write_text(json.dumps({"box": BOX}))
    return st, box


def _full_grid_index(st, robot, n):
    """eq. 15 over every point of the n^3 grid, each solved (no symmetry)."""
    res = solve(robot, grid_points(BOX, n), method=st["solver"], redundancy=study.redundancy(st))
    return doe.global_index(res["dp"], np.asarray(res["status"]).astype(str))


def test_the_doe_shards_share_the_tests_and_give_the_full_grids_index(quick, tmp_path):
    st, box = quick
    shards = [tmp_path / f"tests_{k}.parquet" for k in range(st["doe"]["shards"])]
    for k, p in enumerate(shards):
        tasks.index_shard(st, str(k), str(box), str(p))
    rows = pd.concat([pd.read_parquet(p) for p in shards], ignore_index=True)
    assert list(rows.test) == list(range(1, 9))  # every test once, in order, over 2 shards
    assert len(pd.read_parquet(shards[0])) == 4
    tests = study.doe_tests(st)
    for t in (1, 8):  # SR and DR, both levels of h and r_p
        spec = tests.set_index("test").loc[t, ["kind", "h_m", "r_p_m"]].to_dict()
        robot = study.design_robot(st, st["doe"]["robot"], spec)
        ix, bad = _full_grid_index(st, robot, st["doe"]["index_n"])
        row = rows[rows.test == t].iloc[0]
        assert row.not_ok_points == bad
        assert row.index_m == pytest.approx(ix, rel=1e-9)  # solver tolerance, not the same solves
    assert "index_phi_rad" not in rows  # a point mass has no orientation


def test_the_elasticity_shards_share_the_moduli_of_each_design(quick, tmp_path):
    st, box = quick
    moduli = study.E_values(st)
    paths = [tmp_path / f"SRopt_{k}.parquet" for k in range(st["elasticity"]["shards"])]
    for k, p in enumerate(paths):
        tasks.elasticity_shard(st, "SRopt", str(k), str(box), str(p))
    rows = pd.concat([pd.read_parquet(p) for p in paths], ignore_index=True)
    assert list(rows.E_Pa) == moduli and set(rows.design) == {"SRopt"}
    robot = study.design_robot(st, st["doe"]["robot"], st["optimal"]["SRopt"], E=moduli[0])
    ix, bad = _full_grid_index(st, robot, st["elasticity"]["index_n"])
    assert rows.index_m.iloc[0] == pytest.approx(ix, rel=1e-9) and rows.not_ok_points.iloc[0] == bad
    assert rows.index_m.nunique() == len(moduli)  # each modulus its own solve


def test_a_missing_doe_test_is_named(quick, tmp_path):
    st, box = quick
    p = tmp_path / "tests_0.parquet"
    tasks.index_shard(st, "0", str(box), str(p))
    out = {k: str(tmp_path / f"o.{k}") for k in ("csv", "e.csv", "png", "f.png")}
    with pytest.raises(CdprError, match=r"no shard of DOE test\(s\) 5, 6, 7, 8"):
        tasks.doe_results(st, [str(p)], out["csv"], out["e.csv"], out["png"], out["f.png"])


# ---- the 3-D figures and the volumes on δφ (formerly test_tasks_view.py) ----
QUICK_SPATIAL = ROOT / "config" / "studies" / "quick_spatial.yaml"


@pytest.fixture
def st(monkeypatch):
    monkeypatch.chdir(ROOT)  # robot paths of the study files are relative to the repository
    return study.load_study(QUICK_SPATIAL)


def _record_views(tmp_path, box, monkeypatch):
    """Write ``box`` as tmp_path/rw_c.json and record every ``plots.robot.robot_view`` call (geometry,
    keywords) while it still draws: the list it appends to."""
    (tmp_path / "rw_c.json").write_text(json.dumps({"box": box}), encoding="utf-8")
    seen = []
    real = robot_plots.robot_view
    monkeypatch.setattr(
        robot_plots, "robot_view", lambda geom, out, **kw: seen.append((geom, kw)) or real(geom, out, **kw)
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


def test_concat_joins_shards_in_the_order_given_with_a_fresh_index(tmp_path):
    """Shards of either table format, given in shard order, come back one after the other with the
    index 0..N-1 (the shards' own indexes restart at 0); a missing shard is an error, not a gap."""
    parts = [pd.DataFrame({"x": [3.0 * k, 3.0 * k + 1], "status": ["ok", "slack"]}) for k in range(3)]
    paths = []
    for k, (part, ext) in enumerate(zip(parts, ("parquet", "csv", "parquet"))):
        p = tmp_path / f"plane_{k}.{ext}"
        table_io.write_table(part, p)
        paths.append(str(p))
    df = tasks.concat(paths)
    assert df["x"].tolist() == [0.0, 1.0, 3.0, 4.0, 6.0, 7.0]
    assert df.index.tolist() == list(range(6)) and df["status"].tolist() == ["ok", "slack"] * 3
    assert tasks.concat(paths[::-1])["x"].tolist() == [6.0, 7.0, 3.0, 4.0, 0.0, 1.0]
    with pytest.raises(FileNotFoundError):
        tasks.concat([*paths, str(tmp_path / "plane_3.csv")])
