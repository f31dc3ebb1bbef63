"""Interference in the studies (issue 39): a rigid platform's study tables carry the interference
columns at the solved poses (``analyses.interference.add_interference``), an interfering point is left out of the
volumes, RW_C and the plane's numbers and counted in the summary (``summary_rows.interference_rows``),
and ``cdpr view`` draws the interfering cables in their own colour (``plots.robot.cable_colours``)."""

import numpy as np
import pandas as pd
import pytest
from matplotlib.colors import to_rgba

from cdpr import table_io
from cdpr.analyses import scans, workspace
from cdpr.analyses.interference import add_interference
from cdpr.analyses.workspace import interference_free_rows
from cdpr.models.interference import COLUMNS, columns, interference
from cdpr.pipeline import solver_tables, study, summary, summary_rows
from cdpr.pipeline.plots import robot as robot_plots
from cdpr.pipeline.plots import style as style_plots
from cdpr.pipeline.results import rel_path
from cdpr.robot import load_robot
from cdpr.tables import solve_table
from tests.conftest import ROBOTS, ROOT

WALL = ROOT / "tests" / "data" / "wall_crossed.yaml"
#: The wall robot's flipped equilibrium of docs/interference.md: cables 5-6 and 7-8 touch there.
FLIPPED = [0.2942680209348096, 0.07308079308461758, 0.6383801136561223]
FLIPPED_RV = [-2.439405217117418, 0.0010651427941656395, -0.008637515319062455]


def test_a_rigid_platform_table_gets_the_columns_at_its_solved_poses():
    robot = load_robot(ROBOTS / "cogiro_massless.yaml")
    P = np.array([[0.0, 0.0, 1.5], [6.45, 4.69, 2.71], [-6.39, -4.75, 1.94], [2.0, 1.0, 2.5]])
    rv = [0.0, 0.0, np.radians(15)]
    df = add_interference(robot, solve_table(robot, P, rotvec=rv))
    assert list(df.columns[-6:]) == list(COLUMNS)
    solved = df[["x_s", "y_s", "z_s"]].to_numpy(), df[["rx_s", "ry_s", "rz_s"]].to_numpy()
    want = columns(interference(robot, *solved))
    for c in COLUMNS:
        np.testing.assert_array_equal(np.asarray(df[c], dtype=want[c].dtype), want[c])
    # at 15 degrees about z the poses near the frame's corners have a cable through the platform
    # (12.8 cm deep at the desired pose), the centre none
    assert df["interference_free"].tolist() == [True, False, False, True] and (df["n_cp"][1:3] > 0).all()
    assert (df["cp_cables"] != "").to_numpy().tolist() == (df["n_cp"] > 0).to_numpy().tolist()


def test_an_unsolved_row_has_no_interference_answer_and_a_point_mass_no_columns():
    robot = load_robot(ROBOTS / "cogiro_massless.yaml")
    df = solve_table(robot, [[0.0, 0.0, 1.5], [0.5, 0.0, 2.0]])
    df.loc[1, ["x_s", "y_s", "z_s"]] = np.nan  # as an unsolved point's
    df = add_interference(robot, df)
    assert df["interference_free"].isna().tolist() == [False, True]
    assert df["n_cc"].isna().tolist() == [False, True] and np.isnan(df["dmin_m"][1])
    assert interference_free_rows(df)[1] == False  # noqa: E712 (a missing answer is not free)
    pm = load_robot(ROBOTS / "cdpr4.yaml")
    t = solve_table(pm, [[0.0, 0.0, 1.0]])
    before = t.copy()
    assert add_interference(pm, t).equals(before) and interference_free_rows(t).all()


def test_the_study_jobs_write_the_columns_for_a_rigid_platform(tmp_path):
    st = study.load_study(ROOT / "config" / "studies" / "quick_spatial.yaml")
    solver_tables.plane_table(st, "CoGiRo", "SR", tmp_path / "plane.csv", threads=1)
    df = table_io.read_table(tmp_path / "plane.csv")
    assert set(COLUMNS) <= set(df.columns) and len(df) == st["plane"]["n"] ** 2
    # a point-mass study's tables keep their columns (the paper's results keep their bytes)
    pm = study.load_study(ROOT / "config" / "studies" / "quick_physical.yaml")
    solver_tables.plane_table(pm, next(iter(pm["robots"])), "DR", tmp_path / "pm.csv", threads=1)
    assert not set(COLUMNS) & set(table_io.read_table(tmp_path / "pm.csv").columns)


def _grid(n=3, bad=(4,)):
    """A cell-centred n^3 grid table, every point ok with |dp| = 1 mm, interfering at rows ``bad``."""
    df = pd.DataFrame({"status": ["ok"] * n**3, "dp": np.full(n**3, 1e-3), "dphi": np.full(n**3, 1e-3)})
    free = np.ones(n**3, dtype=bool)
    free[list(bad)] = False
    df["interference_free"] = pd.array(free, dtype="boolean")
    return df


def test_an_interfering_point_is_left_out_of_the_volumes_and_the_box():
    n, box = 3, [0.0, 3.0, 0.0, 3.0, 0.0, 3.0]
    df = _grid(n, bad=(13,))  # the centre voxel
    v = workspace.error_limited_volume(df, n, box, 0.01, 27.0)
    assert v["V_L"] == pytest.approx(26.0)  # 27 voxels of 1 m^3, one interfering
    count, _ = workspace.largest_box(workspace.voxel_mask(df, n))
    assert count == 9  # a 3 x 3 x 1 slab: every box through the centre is cut
    v = workspace.error_limited_volume(df.drop(columns="interference_free"), n, box, 0.01, 27.0)
    assert v["V_L"] == pytest.approx(27.0)  # without the column every ok point counts


def test_the_summary_counts_the_interfering_points_it_leaves_out(tmp_path):
    st = study.load_study(ROOT / "config" / "studies" / "quick_spatial.yaml")
    n = 2
    plane = _grid(n, bad=(1, 5))
    plane = plane.assign(
        x=[0.0, 1, 2, 3, 4, 5, 6, 7], y=0.0, dp=[1e-3, 9e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3, 7e-3]
    )
    plane["n_cc"] = pd.array([0, 1, 0, 0, 0, 0, 0, 0], dtype="Int64")
    plane["n_cp"] = pd.array([0, 0, 0, 0, 0, 2, 0, 0], dtype="Int64")
    plane["status"] = ["ok"] * 7 + ["slack"]
    for pk in st["pulleys"]:
        p = tmp_path / rel_path("plane_table", robot="CoGiRo", pulley=pk)
        p.parent.mkdir(parents=True, exist_ok=True)
        table_io.write_table(plane, p)
    rows = {r["quantity"]: r for r in summary_rows.interference_rows(st, tmp_path)}
    r = rows["CoGiRo SR plane: interfering points left out"]
    assert r["ours"] == 2 and r["note"] == "2 of 7 ok points; cable-cable at 1, cable-platform at 1"
    head = summary.headline_rows(st, tmp_path).set_index("quantity")
    assert head.loc["CoGiRo SR plane ‖δp‖ max", "ours"] == pytest.approx(6.0)  # 9 mm interferes, 7 mm slack
    assert "CoGiRo SR plane: interfering points left out" in head.index
    # the reached equilibrium's rows: 1 point not the global one, 1 fold
    plane = plane.assign(
        unique=[True, False, True, True, True, False, True, True],
        n_folds=np.array([0, 0, 0, 0, 0, 1, 0, 0], dtype=np.int32),
        reached_is_global=[True, False, True, True, True, True, True, True],
    )
    table_io.write_table(plane, tmp_path / rel_path("plane_table", robot="CoGiRo", pulley="SR"))
    rows = {r["quantity"]: r for r in summary_rows.reached_rows(st, tmp_path)}
    assert rows["points where the reached equilibrium is not the global one"]["ours"] == 1
    assert rows["points whose continuation crossed a fold"]["ours"] == 1
    assert "continued at the 2 points" in rows["points whose continuation crossed a fold"]["note"]


def _is_segment(line, seg, three_d):
    """Whether a drawn line is the segment ``seg`` (2, 3) [m] (in plan: its x and y)."""
    xyz = np.asarray(line.get_data_3d() if three_d else line.get_data(), dtype=float)
    want = seg.T if three_d else seg[:, :2].T
    return xyz.shape == want.shape and np.allclose(xyz, want)


def test_view_draws_the_interfering_cables_in_their_colour(monkeypatch, tmp_path):
    robot = load_robot(WALL)
    geom = scans.pose_geometry(robot, FLIPPED, FLIPPED_RV)
    assert geom["interfering"].tolist() == [False] * 4 + [True] * 4  # pairs 5-6 and 7-8
    figs = []

    def keep(fig, out):
        figs.append(fig)
        style_plots.audit(fig)
        return [out]

    monkeypatch.setattr(robot_plots, "save", keep)
    robot_plots.robot_view(geom, tmp_path / "v.png", plan=True)
    fig = figs[0]
    for ax in fig.axes[:2]:  # the 3-D view and the plan
        for i in range(robot.m):
            seg = np.stack([geom["D"][i], geom["B"][i]])
            drawn = [ln for ln in ax.lines if _is_segment(ln, seg, three_d=ax.name == "3d")]
            want = robot_plots.INTERFERING_COLOUR if geom["interfering"][i] else robot_plots.CABLE_COLOUR
            assert drawn and all(to_rgba(ln.get_color()) == to_rgba(want) for ln in drawn)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "interfering cables (cable or platform)" in labels
    # a pose free of interference: every cable in the cable colour, no legend entry
    free = scans.pose_geometry(load_robot(ROBOTS / "cogiro_massless.yaml"), [0.0, 0.0, 2.0])
    assert not free["interfering"].any()
    assert robot_plots.cable_colours(free) == [robot_plots.CABLE_COLOUR] * 8


def test_the_docs_workspace_figure_draws_the_column_counts(monkeypatch, tmp_path):
    """``plots.interference.workspace_plan_figure`` (docs/hooks/interference_figure.py): each panel's
    image is the count of free (and free and feasible) voxels per (x, y) column; the layout passes
    the audit."""
    from cdpr.pipeline.plots import interference as interference_plots

    figs = []

    def keep(fig, out):
        figs.append((fig, style_plots.audit(fig)))
        return [out]

    monkeypatch.setattr(interference_plots, "save", keep)
    shape, box = (3, 2, 4), [0.0, 3.0, 0.0, 2.0, 0.0, 4.0]
    rng = np.random.default_rng(1)
    free, feasible = rng.random(24) < 0.7, rng.random(24) < 0.5
    w = {
        "free": free,
        "feasible": feasible,
        "fraction": free.mean(),
        "volume_m3": 1.0,
        "free_feasible_m3": 0.5,
    }
    interference_plots.workspace_plan_figure(
        "R", box, shape, [("identity", w), ("15° about z", w)], tmp_path / "f.png"
    )
    fig = figs[0][0]
    images = [ax.get_images()[0].get_array() for ax in fig.axes if ax.get_images()]
    assert len(images) == 4  # row by row: the free counts, then the free and feasible counts
    np.testing.assert_array_equal(images[0], free.reshape(shape).sum(axis=2).T)
    np.testing.assert_array_equal(images[2], (free & feasible).reshape(shape).sum(axis=2).T)


def test_the_docs_page_is_named_as_the_issue_names_it_and_shows_the_cogiro_figure():
    """Issue 39's Done-when: a docs page "Interference and reached equilibria" with the CoGiRo
    figure (the hook draws it at the identity and at 15 degrees about x, y and z)."""
    import importlib.util

    page = (ROOT / "docs" / "interference.md").read_text()
    assert page.splitlines()[0] == "# Interference and reached equilibria"
    assert "## The reached equilibrium" in page and "(figures/interference_workspace.png)" in page
    mkdocs = (ROOT / "mkdocs.yml").read_text()
    assert "  - Interference and reached equilibria: interference.md\n" in mkdocs
    assert "  - docs/hooks/interference_figure.py\n" in mkdocs
    spec = importlib.util.spec_from_file_location("hook", ROOT / "docs" / "hooks" / "interference_figure.py")
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    assert hook.URI == "figures/interference_workspace.png" and hook.ROBOT.name == "cogiro_massless.yaml"
    assert dict(hook.ORIENTATIONS) == {
        "identity": (0.0, 0.0, 0.0),
        "15° about x": (15.0, 0.0, 0.0),
        "15° about y": (0.0, 15.0, 0.0),
        "15° about z": (0.0, 0.0, 15.0),
    }


# ---- the plane figures, the global index, the budget and the summary (issue 39) ----------------
def _rotated_study(tmp_path, rz=np.radians(15)):
    """quick_spatial.yaml with the platform turned ``rz`` about z (CoGiRo's corners then interfere)."""
    import yaml

    data = yaml.safe_load((ROOT / "config" / "studies" / "quick_spatial.yaml").read_text())
    data["rotvec_rad"] = [0.0, 0.0, float(rz)]
    path = tmp_path / "rotated.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return study.load_study(path)


def test_the_global_index_leaves_out_the_interfering_points(tmp_path):
    """``tasks._grid_index`` of CoGiRo at 15° about z over its frame: the index is the mean ‖δp‖
    over the points that are ok and free of interference in the study's own table of the same grid
    (``add_interference``), and interfering_points counts the others."""
    from cdpr.pipeline import tasks

    st = _rotated_study(tmp_path)
    robot = study.design_robot(st, "CoGiRo", st["pulleys"]["SR"])
    box, n = workspace.check_box(workspace.frame_box(robot)), 3
    g = tasks._grid_index(st, robot, box, n, threads=1)
    P = workspace.grid_points(box, n)
    df = add_interference(robot, solve_table(robot, P, **study.solve_kwargs(st, 1)))
    ok = (df.status == "ok").to_numpy()
    free = interference_free_rows(df)
    assert g["interfering_points"] == int((ok & ~free).sum()) > 0
    assert g["not_ok_points"] == int((~ok).sum())
    assert g["index_m"] == pytest.approx(df.dp[ok & free].mean(), rel=1e-12)
    assert g["index_m"] != pytest.approx(df.dp[ok].mean(), rel=1e-6)  # leaving them out matters
    assert g["index_phi_rad"] == pytest.approx(df.dphi[ok & free].mean(), rel=1e-12)
    row = tasks._index_row(st, robot, box, n, threads=1)
    assert list(row) == ["index_m", "index_phi_rad", "not_ok_points", "interfering_points"]


def test_the_budget_tests_the_robots_own_solved_pose():
    """``tasks._budget_interfering``: from the budget's ``all`` entry (δp, δφ = rotvec of R* R_dᵀ)
    the solved poses are rebuilt and tested; the mask is ``add_interference``'s on a solved table."""
    from scipy.spatial.transform import Rotation

    from cdpr.pipeline import tasks

    robot = load_robot(ROBOTS / "cogiro_massless.yaml")
    P = np.array([[0.0, 0.0, 1.5], [6.45, 4.69, 2.71], [-6.39, -4.75, 1.94], [2.0, 1.0, 2.5]])
    rv = np.array([0.0, 0.0, np.radians(15)])
    df = add_interference(robot, solve_table(robot, P, rotvec=rv))
    R_s = Rotation.from_rotvec(df[["rx_s", "ry_s", "rz_s"]].to_numpy())
    dphi = (R_s * Rotation.from_rotvec(np.tile(rv, (4, 1))).inv()).as_rotvec()
    status = np.array(["ok", "ok", "ok", "slack"])
    all_effects = {"dp": df[["x_s", "y_s", "z_s"]].to_numpy() - P, "dphi": dphi, "status": status}
    bad = tasks._budget_interfering(robot, P, all_effects, rv)
    want = ~interference_free_rows(df) & (status == "ok")
    assert bad.tolist() == want.tolist() == [False, True, True, False]


def test_the_summary_says_what_the_index_budget_and_dead_length_runs_left_out(tmp_path):
    for rule, name, t in (
        ("doe", "table", pd.DataFrame({"test": [1, 2], "index_m": [0.1, 0.2], "interfering_points": [3, 0]})),
        (
            "dead_length",
            "table",
            pd.DataFrame(
                {"d_m": [1.0, 2.0], "plane_SR_min_m": [0.1, 0.1], "interfering_points_plane_SR": [2, 1]}
                | {"interfering_points_SRopt_Emean": [4, 0]}
            ),
        ),
        (
            "study_budget",
            "table",
            pd.DataFrame(
                {"design": ["SRopt", "SRopt", "DRopt"], "points": [64] * 3, "interfering_points": [5, 5, 7]}
            ),
        ),
    ):
        p = tmp_path / rel_path(rule, name)
        p.parent.mkdir(parents=True, exist_ok=True)
        table_io.write_table(t, p)
    rows = {r["quantity"]: r for r in summary_rows.left_out_rows(tmp_path)}
    r = rows["DOE global index over RW_C: interfering points left out"]
    assert r["ours"] == 3 and r["note"] == "over 2 runs; test 1: 3"
    r = rows["dead-length sweep: interfering points left out"]
    assert r["ours"] == 7 and r["note"] == "over 2 dead lengths; plane_SR: 3; SRopt_Emean: 4"
    r = rows["error budget over RW_C: interfering points left out"]
    assert r["ours"] == 12 and r["note"] == "SRopt: 5 of 64; DRopt: 7 of 64"
    assert summary_rows.left_out_rows(tmp_path / "none") == []


def _plane_tables(bad):
    """A 5 x 5 plane of a rigid platform: ‖δp‖ 1-3 mm, 1 m where ``bad`` (interfering) rows are."""
    x, y = np.meshgrid(np.arange(5.0), np.arange(5.0), indexing="ij")
    n = 25
    df = pd.DataFrame({"x": x.ravel(), "y": y.ravel(), "status": ["ok"] * n})
    df["dp"] = 1e-3 + 2e-3 * df.x / 4
    df["dphi"] = 1e-3 + 1e-3 * df.y / 4
    df["t1"], df["t2"] = 50.0 + df.x, 60.0 + df.y
    df["taut"] = "1-2"
    free = np.ones(n, dtype=bool)
    free[list(bad)] = False
    df.loc[list(bad), "dp"] = 1.0
    df["interference_free"] = pd.array(free, dtype="boolean")
    df.loc[24, "status"] = "slack"
    return {"SR": df}


def test_the_plane_figures_draw_interfering_points_pink_and_leave_them_out(monkeypatch, tmp_path):
    """Fig. 12 (‖δp‖ and δφ), the tension map and the taut-set map: the interfering ok points are
    one pink cell each, counted under the panel and in the title, and no contour level reaches
    their 1 m (they are left out of the maps)."""
    from matplotlib.collections import QuadMesh
    from matplotlib.colors import to_rgba

    from cdpr.pipeline.plots import planes

    figs = []

    def keep(fig, out):
        figs.append(fig)
        style_plots.audit(fig)
        return [out]

    monkeypatch.setattr(planes, "save", keep)
    bad = (6, 12, 18)
    tables = _plane_tables(bad)
    assert planes.interfering_points(tables["SR"]).sum() == 3
    A = np.array([[-1.0, -1, 5], [6, -1, 5], [6, 6, 5], [-1, 6, 5]])
    planes.fig12_plane(tables, A, 2.0, "R", tmp_path / "p.png", mode="physical")
    planes.fig12_tension(tables, A, 2.0, "R", 55.0, tmp_path / "t.png", mode="physical")
    planes.fig9_taut(tables, A, 2.0, "R", tmp_path / "s.png", mode="physical")
    pink = to_rgba(robot_plots.INTERFERING_COLOUR)
    for fig in figs:
        assert "pink: 3 ok points with interfering cables, left out" in fig._suptitle.get_text()
        panels = [ax for ax in fig.axes if ax.get_xlabel() == "x [m]"]
        for ax in panels:
            meshes = [c for c in ax.collections if isinstance(c, QuadMesh) and to_rgba(c.cmap(0.0)) == pink]
            assert len(meshes) == 1 and int(np.isfinite(meshes[0].get_array()).sum()) == 3
            texts = [t.get_text() for t in ax.get_legend().get_texts()]
            assert "pink, ok but interfering (left out): 3" in texts
            levels = [lv for c in ax.collections if hasattr(c, "levels") for lv in c.levels]
            assert not levels or max(levels) < 100.0  # mm or mrad or N: the 1 m points are not drawn


def test_the_dead_length_sweep_leaves_out_and_counts_the_interfering_points(tmp_path, monkeypatch):
    """``tasks.dead_length_point`` of the quick spatial study, its plane solved at four poses of
    CoGiRo at 15° about z (two of them interfere; the largest ‖δp‖ is set on one of those) and its
    indices stubbed: the plane extremes leave the interfering points out and the row counts them."""
    import json

    from cdpr.pipeline import tasks

    st = study.load_study(ROOT / "config" / "studies" / "quick_spatial.yaml")
    P = np.array([[0.0, 0.0, 1.5], [6.45, 4.69, 2.71], [-6.39, -4.75, 1.94], [2.0, 1.0, 2.5]])
    rv = [0.0, 0.0, np.radians(15)]

    def plane(robot, z, n, **solver):
        df = solve_table(robot, P, rotvec=rv)
        df.loc[1, "dp"] = 9.0  # an interfering point: must not be the plane's maximum
        return df

    monkeypatch.setattr(tasks.scans, "plane", plane)
    monkeypatch.setattr(
        tasks,
        "_grid_index",
        lambda *a, **k: {"index_m": 0.1, "index_phi_rad": 0.01, "not_ok_points": 0, "interfering_points": 2},
    )
    box = tmp_path / "rw_c.json"
    box.write_text(json.dumps({"box": [-0.4, 0.4, -0.4, 0.4, 2.4, 3.0]}), encoding="utf-8")
    tasks.dead_length_point(st, box, tmp_path / "d.csv", d=1.0)
    row = table_io.read_table(tmp_path / "d.csv").iloc[0]
    free = solve_table(load_robot(ROBOTS / "cogiro_massless.yaml"), P[[0, 3]], rotvec=rv)
    assert free.dp.max() < 1.0
    for pk in st["pulleys"]:
        assert row[f"interfering_points_plane_{pk}"] == 2
        assert row[f"plane_{pk}_max_m"] < 1.0  # the 9 m point is left out
    designs = [f"interfering_points_{dk}_{tag}" for dk in st["optimal"] for tag in ("Emin", "Emean", "Emax")]
    assert all(row[c] == 2 for c in designs)
    assert not any(c.startswith("plane_") and "interfering" in c for c in row.index)  # the figure's columns
