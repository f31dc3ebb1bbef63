"""Pipeline tasks (``cdpr job NAME``): read tables, call the library, write tables and figures.

Each task takes the validated study and named files (the command line's ``--tables``,
``--table``, ``--figure``, ...). Input files are matched by their names, never by their position,
so the order in a Snakemake rule does not matter. Physics lives in the model modules and drawing in
``cdpr.pipeline.plots``; a task only moves data between them.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from cdpr import io, table_io
from cdpr.analyses import budget, doe, scans, workspace
from cdpr.analyses.interference import add_interference, interfering_at
from cdpr.analyses.symmetry import solve_grid_columns
from cdpr.analyses.uncertainty import RESPONSES
from cdpr.analyses.workspace import interference_free_rows
from cdpr.errors import CdprError
from cdpr.models import winch
from cdpr.models.platform import rotation_matrix
from cdpr.pipeline import comparison as cm
from cdpr.pipeline import conclusions as robot_conclusions
from cdpr.pipeline import study, uq
from cdpr.pipeline import summary as sm
from cdpr.pipeline.plots import budget as budget_plots
from cdpr.pipeline.plots import comparison as comparison_plots
from cdpr.pipeline.plots import dead_length as dead_length_plots
from cdpr.pipeline.plots import doe as doe_plots
from cdpr.pipeline.plots import elasticity as elasticity_plots
from cdpr.pipeline.plots import maps as maps_plots
from cdpr.pipeline.plots import parity as parity_plots
from cdpr.pipeline.plots import planes as planes_plots
from cdpr.pipeline.plots import robot as robot_plots
from cdpr.pipeline.plots import trajectories as trajectories_plots
from cdpr.pipeline.plots import uq as uq_plots
from cdpr.pipeline.plots import volumes as volumes_plots
from cdpr.pipeline.plots import winch as winch_plots
from cdpr.pipeline.plots.style import paper_value
from cdpr.pipeline.results import ComparisonLayout, rel_path
from cdpr.pipeline.study import budget_designs
from cdpr.robot import TABLE1, with_values


def _by_stem(paths, pattern, what):
    """Map each file to the groups of ``pattern`` (a regex on the file stem); error on a stranger."""
    out = []
    for p in paths:
        m = re.fullmatch(pattern, Path(p).stem)
        if not m:
            raise CdprError(f"{p}: not a {what} file (expected a name matching {pattern})")
        out.append((m.groupdict(), p))
    return out


def concat(paths):
    """The tables ``paths`` one after the other (shards in shard order)."""
    return pd.concat([table_io.read_table(p) for p in paths], ignore_index=True)


def _shards(paths, pattern, what, key):
    """{key value: [paths in shard order]} from files named <key>_<shard>."""
    groups = {}
    for g, p in _by_stem(paths, pattern, what):
        groups.setdefault(g[key] if isinstance(key, str) else tuple(g[k] for k in key), []).append(
            (int(g["shard"]), p)
        )
    return {k: [p for _, p in sorted(v)] for k, v in groups.items()}


def _grid_index(st, robot, box, n, threads=None):
    """Global index (eq. 15) of ``robot`` over the n^3 grid of ``box`` in the study's redundancy
    mode, one solve per orbit of the symmetries robot and grid share (``symmetry.solve_grid_columns``):
    a dict with index_m [m], not_ok_points, index_phi_rad (the orientation index [rad],
    ``doe.orientation_index``; NaN for a point mass) and, for a rigid platform, interfering_points:
    the ok points whose cables interfere at their solved pose (``interference.interfering_at``),
    left out of both indices as the volumes and RW_C leave them out (docs/interference.md)."""
    rigid = not robot.point_mass
    keys = ("dp", "status", "dphi") + (("P_s", "rotvec_s") if rigid else ())
    c, _ = solve_grid_columns(robot, box, n, keys, **study.solve_kwargs(st, threads))
    status = c["status"].astype(str)
    out = {"not_ok_points": int((status != "ok").sum())}
    if rigid:
        P = workspace.grid_points(box, n)
        rv = study.rotvec(st)
        desired = np.column_stack(
            [P, np.broadcast_to(np.zeros(3) if rv is None else np.asarray(rv), P.shape)]
        )
        bad = (status == "ok") & interfering_at(robot, c["P_s"], c["rotvec_s"], desired=desired)
        status = np.where(bad, "interfering", status)
        out["interfering_points"] = int(bad.sum())
    out["index_m"] = doe.global_index(c["dp"], status)[0]
    out["index_phi_rad"] = (
        doe.orientation_index(c["dphi"], status)[0] if not robot.suspended_point_mass else float("nan")
    )
    return out


def _index_row(st, robot, box, n, threads=None):
    """The columns of one design in an index table (``index_shard``, ``elasticity_shard``): index_m
    (eq. 15) over the n^3 grid of ``box``, index_phi_rad (the orientation index, a rigid platform
    only), not_ok_points and, for a rigid platform, interfering_points (ok points left out of both
    indices: their cables interfere), one solve per orbit of the grid's symmetries (``_grid_index``)."""
    g = _grid_index(st, robot, box, n, threads)
    row = {"index_m": g["index_m"]}
    if not robot.suspended_point_mass:
        row["index_phi_rad"] = g["index_phi_rad"]
    row["not_ok_points"] = g["not_ok_points"]
    if "interfering_points" in g:
        row["interfering_points"] = g["interfering_points"]
    return row


# ---- winch (Métillon Fig. 7) -------------------------------------------------------------------
def winch_figure(st, table, figure):
    """Fig. 7 of the winch seed from ``winch.csv``."""
    p = TABLE1
    winch_plots.fig7_winch(table_io.read_table(table), winch.l_pm0(p), p.q0, figure)


# ---- planes (Fig. 9, 12) -----------------------------------------------------------------------
def _plane_tables(st, tables, robot_key):
    found = dict(
        (g["pulley"], p)
        for g, p in _by_stem(tables, rf"{re.escape(robot_key)}_(?P<pulley>[A-Za-z0-9]+)", "plane table")
    )
    return {pk: table_io.read_table(found[pk]) for pk in st["pulleys"] if pk in found}


def plane_figure(st, robot_key, tables, figure):
    """Fig. 12 for one robot: one panel per pulley design, each on its own colour scale."""
    robot = study.robot_of(st, robot_key)
    data, z, mode = _plane_tables(st, tables, robot_key), st["plane"]["z_m"], study.redundancy(st)
    paper = {
        pk: [paper_value(f"{robot_key}_{pk} plane {stat}") for stat in ("min", "centre", "max")]
        for pk in data
    }
    planes_plots.fig12_plane(data, robot.A, z, robot_key, figure, mode=mode, paper=paper)
    # the minimum-tension (slack margin) map beside it (declared by the rule)
    planes_plots.fig12_tension(
        data, robot.A, z, robot_key, 0.0, Path(figure).with_name(f"{robot_key}_tension.png"), mode=mode
    )


def subsets_figure(st, robot_key, tables, figure):
    """Fig. 9 for one robot: the subset minimising ‖δp‖ (paper mode) or the taut cables (physical
    mode), one panel per pulley design."""
    robot = study.robot_of(st, robot_key)
    draw = planes_plots.fig9_taut if study.redundancy(st) == "physical" else planes_plots.fig9_subsets
    draw(
        _plane_tables(st, tables, robot_key),
        robot.A,
        st["plane"]["z_m"],
        robot_key,
        figure,
        mode=study.redundancy(st),
    )


# ---- trajectories (Fig. 10-11) -----------------------------------------------------------------
def trajectories(st, tables, table, figure, minmax_figure):
    """Fig. 10 (‖δp‖ along the paths) and Fig. 11 (min, max per design) with their table."""
    files = dict(
        (f"{g['robot']}_{g['pulley']}", p)
        for g, p in _by_stem(tables, r"(?P<robot>[A-Za-z0-9]+)_(?P<pulley>[A-Za-z0-9]+)", "path table")
    )
    labels = [
        f"{rk}_{pk}" for rk in st["trajectories"]["paths"] for pk in st["pulleys"] if f"{rk}_{pk}" in files
    ]
    data = {lab: table_io.read_table(files[lab]) for lab in labels}
    rows = []
    for lab, df in data.items():
        ok = df.status == "ok"
        lo, hi = scans.ok_extremes(df)
        row = {"design": lab, "dp_min_m": lo, "dp_max_m": hi}
        if "dphi" in df:  # a rigid platform: the orientation error's extremes beside them
            row["dphi_min_rad"], row["dphi_max_rad"] = scans.ok_extremes(df, "dphi")
        row["ok_until_s_m"] = float(df.s[ok].max()) if ok.any() else float("nan")
        row["path_length_m"] = float(df.s.max())
        rows.append(row)
    mm = pd.DataFrame(rows)
    table_io.write_table(mm, table)
    trajectories_plots.fig10_trajectories(data, mm, figure, mode=study.redundancy(st))
    trajectories_plots.fig11_minmax(mm, minmax_figure, mode=study.redundancy(st))


# ---- volumes (Fig. 13-14) ----------------------------------------------------------------------
def _volume_rows(st, tables, what, column, limits, limit_col, flag_col, flagged):
    """One row per robot x pulley design x limit: V_L and R_V of the frame grids' shards on the
    error ``column`` ("dp" [m] or "dphi" [rad]) at each of ``limits``, the limit under ``limit_col``
    and ``flag_col`` true for the limits in ``flagged``; ``what`` names the job in errors."""
    n = st["volumes"]["n"]
    groups = _shards(tables, r"(?P<label>[A-Za-z0-9]+_[A-Za-z0-9]+)_(?P<shard>\d+)", "volume shard", "label")
    rows = []
    for rk in st["robots"]:
        for pk in st["pulleys"]:
            label = f"{rk}_{pk}"
            if label not in groups:
                raise CdprError(f"{what}: no shard of {label} among the inputs")
            robot = study.design_robot(st, rk, st["pulleys"][pk])
            df, box, V_T = concat(groups[label]), workspace.frame_box(robot), workspace.envelope_volume(robot)
            for lim in limits:
                v = workspace.error_limited_volume(df, n, box, lim, V_T, column=column)
                rows.append(
                    {
                        "robot": rk,
                        "pulley": pk,
                        limit_col: lim,
                        "V_T_m3": V_T,
                        "V_L_m3": v["V_L"],
                        "R_V": v["R_V"],
                        "V_L_err_m3": v["V_L_err"],
                        flag_col: lim in flagged,
                    }
                )
    return pd.DataFrame(rows)


def volumes(st, tables, table, figure):
    """V_L and R_V per robot x pulley design at the paper's limits and over the sweep (Fig. 14)."""
    lims = study.volume_limits(st)
    tab = _volume_rows(st, tables, "volumes", "dp", lims, "limit_m", "paper_limit", st["volumes"]["limits_m"])
    table_io.write_table(tab, table)
    volumes_plots.fig14_rv(tab, _paper_rv(st), figure, mode=study.redundancy(st))


def _paper_rv(st):
    """The paper's R_V values (cdpr/data/paper_values.yaml) for the paper's study, else none."""
    rows = (
        []
        if not st.get("paper_comparison")
        else [
            {
                "robot": v["ours"]["robot"],
                "pulley": v["ours"]["pulley"],
                "limit_m": v["ours"]["limit_m"],
                "R_V": v["value"],
            }
            for v in sm.paper_values()
            if v["ours"].get("kind") == "R_V"
        ]
    )
    return pd.DataFrame(rows, columns=["robot", "pulley", "limit_m", "R_V"])


def volume_view(st, label, tables, figure):
    """Fig. 13: the error-limited regions of one design at the paper's limits (and at the study's
    δφ limits, ``volumes.dphi_limits_rad``, in a second row)."""
    rk, pk = label.split("_", 1)
    robot = study.design_robot(st, rk, st["pulleys"][pk])
    df = concat(sorted(tables, key=lambda p: int(Path(p).stem.rsplit("_", 1)[1])))
    n = st["volumes"]["n"]
    lims = st["volumes"]["limits_m"]
    rv = [
        workspace.error_limited_volume(
            df, n, workspace.frame_box(robot), lim, workspace.envelope_volume(robot)
        )["R_V"]
        for lim in lims
    ]
    phi_lims = st["volumes"].get("dphi_limits_rad") or []
    phi_rv = [
        workspace.error_limited_volume(
            df, n, workspace.frame_box(robot), lim, workspace.envelope_volume(robot), column="dphi"
        )["R_V"]
        for lim in phi_lims
    ]
    volumes_plots.fig13_volume_view(
        df,
        lims,
        rv,
        float(robot.A[:, 2].min()),
        f"{rk} {pk}: error-limited volume V_L (Fig. 13)",
        figure,
        A=robot.A,
        mode=study.redundancy(st),
        dphi_limits=phi_lims,
        dphi_R_V=phi_rv,
    )


def volumes_dphi(st, tables, table, figure):
    """V_L and R_V on the orientation error δφ (beyond the paper) per robot x pulley design at the
    study's limits and over its sweep (``volumes.dphi_limits_rad``, ``volumes.dphi_sweep_rad``), from
    the same frame grids as ``volumes``."""
    tab = _volume_rows(
        st,
        tables,
        "volumes-dphi",
        "dphi",
        study.dphi_volume_limits(st),
        "limit_rad",
        "study_limit",
        st["volumes"]["dphi_limits_rad"],
    )
    table_io.write_table(tab, table)
    volumes_plots.fig14_rv_dphi(tab, figure, mode=study.redundancy(st))


# ---- regular workspaces (section 4.1.1) --------------------------------------------------------
def regular_workspace(st, tables, table, json):
    """RW_max of each DOE design (largest axis-aligned box of ok voxels) and RW_C, their intersection."""
    n = st["doe"]["workspace_n"]
    tests = study.doe_tests(st)
    files = {int(g["test"]): p for g, p in _by_stem(tables, r"test(?P<test>\d+)", "workspace grid")}
    rows, boxes = [], []
    for t in tests.itertuples():
        robot = study.design_robot(st, st["doe"]["robot"], {"kind": t.kind, "h_m": t.h_m, "r_p_m": t.r_p_m})
        grid = table_io.read_table(files[t.test])
        # a spatial robot's grid carries `feasible` (a tension distribution in [t_min, T_a] holds the
        # platform at the pose): its workspace is the wrench-feasible one, where also the solve is ok
        feasible = grid["feasible"].to_numpy(dtype=bool) if "feasible" in grid else None
        count, cells = workspace.largest_box(workspace.voxel_mask(grid, n, feasible))
        if cells is None:
            raise CdprError(
                f"DOE test {t.test}: no admissible voxel on the {n}^3 frame grid; the design has no workspace"
            )
        box = workspace.box_from_cells(workspace.frame_box(robot), n, cells)
        boxes.append(box)
        extra = {}
        if feasible is not None:  # the wrench-feasible (and ok) workspace's volume by voxel counting
            voxel = workspace.box_volume(workspace.frame_box(robot)) / n**3
            ok = workspace.voxel_mask(grid, n, feasible)
            extra["wrench_feasible_m3"] = float(ok.sum() * voxel)
        rows.append(
            {
                "test": int(t.test),
                "kind": t.kind,
                "h_m": t.h_m,
                "r_p_m": t.r_p_m,
                "xmin": box[0],
                "xmax": box[1],
                "ymin": box[2],
                "ymax": box[3],
                "zmin": box[4],
                "zmax": box[5],
                "volume_m3": workspace.box_volume(box),
                **extra,
            }
        )
    tab = pd.DataFrame(rows)
    rwc = workspace.intersect_boxes(boxes)
    smallest = int(tab.loc[tab.volume_m3.idxmin(), "test"])
    contained = all(
        all(
            b[2 * a] <= boxes[smallest - 1][2 * a] + 1e-12
            and boxes[smallest - 1][2 * a + 1] <= b[2 * a + 1] + 1e-12
            for a in range(3)
        )
        for b in boxes
    )
    paper = st["doe"]["paper_rw_c_m"]
    used = paper if st["doe"]["rw_c"] == "paper" else rwc
    table_io.write_table(tab, table)
    io.write_json(
        {
            "computed": rwc,
            "computed_volume_m3": workspace.box_volume(rwc),
            "paper": paper,
            "paper_volume_m3": workspace.box_volume(paper),
            "smallest_rw_max_test": smallest,
            "smallest_contained_in_all": contained,
            "grid_n": n,
            "use": st["doe"]["rw_c"],
            "box": used,
        },
        json,
    )


# ---- the robot in 3-D --------------------------------------------------------------------------
def robot_view(st, robot_key, box_file, figure):
    """A 3-D picture of the study's robot ``robot_key`` (its file with the study's dead length) at
    the study's platform orientation: the frame box of the volumes' grid and, for the DOE robot, the
    RW_C box of ``box_file`` (doe/rw_c.json) drawn as wireframes, the platform at RW_C's centre
    (elsewhere the default position of ``scans.view_position``)."""
    robot = study.robot_of(st, robot_key, dead_length=st["dead_length_m"])
    boxes = {"frame box (the volumes' grid)": workspace.frame_box(robot)}
    p = scans.view_position(robot)
    if robot_key == st["doe"]["robot"]:
        rwc = workspace.read_box(box_file)
        boxes[f"RW_C ({Path(box_file).name}, {st['doe']['rw_c']})"] = rwc
        p = np.array([0.5 * (rwc[2 * a] + rwc[2 * a + 1]) for a in range(3)])
    robot_plots.robot_view(
        scans.pose_geometry(robot, p, study.rotvec(st)), figure, boxes=boxes, mode=study.redundancy(st)
    )


# ---- DOE (Fig. 15-16) --------------------------------------------------------------------------
def index_shard(st, shard, box_file, table, threads=None):
    """Global index (eq. 15) of the DOE tests of shard ``shard`` (Table 2's tests cut into
    ``doe.shards`` contiguous slices) over the RW_C grid (``doe.index_n``), one row per test: test,
    index_m, index_phi_rad (the orientation index, a rigid platform only), not_ok_points. One
    process solves every test of its slice, one solve per orbit of the
    grid's symmetries (``_grid_index``). Written as parquet: the indices keep every bit for the
    effects."""
    box, n = workspace.read_box(box_file), st["doe"]["index_n"]
    tests = study.doe_tests(st)
    start, stop = workspace.shard_range(len(tests), int(shard), st["doe"]["shards"])
    rows = []
    for t in tests.iloc[start:stop].itertuples():
        spec = {"kind": t.kind, "h_m": t.h_m, "r_p_m": t.r_p_m}
        robot = study.design_robot(st, st["doe"]["robot"], spec)
        rows.append({"test": int(t.test), **_index_row(st, robot, box, n, threads)})
    table_io.write_table(pd.DataFrame(rows), table)


def doe_results(st, tables, table, effects, figure, effects_figure):
    """Global index of every DOE test (eq. 15) from the ``index_shard`` tables, the effects and
    interactions, Fig. 15-16."""
    tests = study.doe_tests(st)
    _by_stem(tables, r"tests_\d+", "DOE shard")  # a stranger among the inputs: error
    rows = concat(tables).drop_duplicates("test").set_index("test")
    missing = sorted(set(tests.test.astype(int)) - set(rows.index))
    if missing:
        raise CdprError(f"doe: no shard of DOE test(s) {', '.join(map(str, missing))} among the inputs")
    rows = rows.loc[tests.test.astype(int)]
    tests["index_m"] = rows.index_m.to_numpy()
    spatial = "index_phi_rad" in rows
    if spatial:  # a rigid platform: the orientation index beside the position index
        tests["index_phi_rad"] = rows.index_phi_rad.to_numpy()
    tests["not_ok_points"] = rows.not_ok_points.to_numpy()
    if "interfering_points" in rows:  # a rigid platform: ok points left out of the indices
        tests["interfering_points"] = rows.interfering_points.to_numpy()
    tests["N"] = st["doe"]["index_n"] ** 3
    table_io.write_table(tests, table)
    X = tests[["joint_c", "h_c", "r_p_c"]].to_numpy()
    eff = doe.effects(X, tests["index_m"].to_numpy(), ["joint", "h", "r_p"])
    if spatial:  # the effects on the orientation index, one response per row block
        eff.insert(0, "response", "index_m")
        phi = doe.effects(X, tests["index_phi_rad"].to_numpy(), ["joint", "h", "r_p"])
        phi.insert(0, "response", "index_phi_rad")
        eff = pd.concat([eff, phi], ignore_index=True)
    table_io.write_table(eff, effects)
    doe_plots.fig15_doe(tests, figure, mode=study.redundancy(st), paper=not study.spatial_robots(st))
    doe_plots.fig16_effects(eff, effects_figure, mode=study.redundancy(st))


# ---- h-r_p maps (Fig. 17, Table 3) -------------------------------------------------------------
def map_rows(st, kind, box_file, table, threads=None):
    """Global index over every map cell (h, r_p), r_p < h, for one pulley kind (Fig. 17)."""
    n = st["maps"]["index_n"]
    box = workspace.read_box(box_file)
    rows = []
    for h, r_p in study.map_cells(st):
        robot = study.design_robot(st, st["doe"]["robot"], {"kind": kind, "h_m": h, "r_p_m": r_p})
        g = _grid_index(st, robot, box, n, threads)
        row = {"kind": kind, "h_m": h, "r_p_m": r_p, "index_m": g["index_m"]}
        if not robot.suspended_point_mass:  # a rigid platform: the orientation index beside it
            row["index_phi_rad"] = g["index_phi_rad"]
        row.update(not_ok_points=g["not_ok_points"], N=n**3)
        if "interfering_points" in g:  # a rigid platform: ok points left out of the index
            row["interfering_points"] = g["interfering_points"]
        rows.append(row)
    cols = ["kind", "h_m", "r_p_m", "index_m", "not_ok_points", "N"]
    if rows and "index_phi_rad" in rows[0]:
        cols.insert(4, "index_phi_rad")
    if rows and "interfering_points" in rows[0]:
        cols.append("interfering_points")
    table_io.write_table(pd.DataFrame(rows, columns=cols), table)


def maps(st, tables, box_file, map, lines, figure, threads=None):
    """The valley, the line h = k r_p (eq. 17-18) and its crossing with the DOE field (Table 3)."""
    tab = concat(tables)
    tab = pd.concat([tab[tab.kind == k] for k in study.map_kinds(st)], ignore_index=True)
    table_io.write_table(tab, map)
    lv = st["doe"]["levels"]
    n = st["doe"]["index_n"]
    box = workspace.read_box(box_file)
    out, valleys = [], {}
    for kind in study.map_kinds(st):
        g = tab[tab.kind == kind]
        v = doe.valley(g.r_p_m, g.h_m, g.index_m)
        valleys[kind] = v
        use = v[v.interior]
        k = doe.line_through_origin(use.r_p_star, use.h) if len(use) else float("nan")
        pt = doe.line_field_point(k, lv["r_p_m"], lv["h_m"]) if np.isfinite(k) else None
        ix = float("nan")
        if pt is not None:
            robot = study.design_robot(st, st["doe"]["robot"], {"kind": kind, "h_m": pt[1], "r_p_m": pt[0]})
            ix = _grid_index(st, robot, box, n, threads)["index_m"]
        out.append(
            {
                "kind": kind,
                "slope_k": k,
                "valley_points": int(len(use)),
                "r_p_opt_m": pt[0] if pt else np.nan,
                "h_opt_m": pt[1] if pt else np.nan,
                "index_opt_m": ix,
                "N": n**3,
            }
        )
    lines_tab = pd.DataFrame(out)
    table_io.write_table(lines_tab, lines)
    maps_plots.fig17_maps(
        tab,
        valleys,
        lines_tab,
        study.doe_tests(st),
        lv,
        figure,
        mode=study.redundancy(st),
        paper=not study.spatial_robots(st),
    )


# ---- elasticity (Fig. 18-19) -------------------------------------------------------------------
def elasticity_shard(st, design, shard, box_file, table, threads=None):
    """Global index (eq. 15) of optimal design ``design`` over the RW_C grid (``elasticity.index_n``)
    at each Young's modulus of shard ``shard`` (the sweep ``study.E_values`` cut into
    ``elasticity.shards`` contiguous slices), one row per modulus: design, E_Pa, index_m,
    index_phi_rad (the orientation index, a rigid platform only), not_ok_points. One process solves
    every modulus of its slice, one solve per orbit of the grid's
    symmetries (``_grid_index``). Written as parquet: the indices keep every bit for the bands."""
    box, n, e = workspace.read_box(box_file), st["elasticity"]["index_n"], st["elasticity"]
    moduli = study.E_values(st)
    start, stop = workspace.shard_range(len(moduli), int(shard), e["shards"])
    rows = []
    for E in moduli[start:stop]:
        robot = study.design_robot(st, st["doe"]["robot"], st["optimal"][design], E=E)
        rows.append({"design": design, "E_Pa": E, **_index_row(st, robot, box, n, threads)})
    table_io.write_table(pd.DataFrame(rows), table)


def elasticity(st, tables, paths, table, bands, crossings, figure, paths_figure):
    """Index versus E (Fig. 18) from the ``elasticity_shard`` tables, its band around the nominal
    modulus, ‖δp‖ along the section 5.2 path at E_min, E_mean, E_max (Fig. 19) and where the E_max
    and E_min curves cross."""
    _by_stem(tables, r"[A-Za-z0-9]+_\d+", "elasticity shard")  # a stranger among the inputs: error
    rows = concat(tables)
    parts = []
    for dk in st["optimal"]:
        for E in study.E_values(st):
            at = rows[(rows.design == dk) & np.isclose(rows.E_Pa, E, rtol=1e-5, atol=0)]
            if at.empty:
                raise CdprError(f"elasticity: no shard of design {dk} at E = {E:g} Pa among the inputs")
            parts.append(at.iloc[:1])
    tab = pd.concat(parts, ignore_index=True)
    table_io.write_table(tab, table)
    E_min, E_mean, E_max = st["elasticity"]["E_path_Pa"]
    out = []
    for dk, g in tab.groupby("design", sort=False):
        # the sweep's row nearest E_mean (the middle of E_path_Pa, the cable's nominal modulus)
        at_mean = float(g.index_m.iloc[np.argmin(np.abs(g.E_Pa.to_numpy() - E_mean))])
        lo, hi = g.index_m.min(), g.index_m.max()
        band = {
            "design": dk,
            "index_mean_m": at_mean,
            "index_min_m": lo,
            "index_max_m": hi,
            "minus_m": at_mean - lo,
            "plus_m": hi - at_mean,
            "total_m": hi - lo,
            "relative": (hi - lo) / at_mean,
        }
        if "index_phi_rad" in g:  # the same band of the orientation index (a rigid platform)
            i_mean = int(np.argmin(np.abs(g.E_Pa.to_numpy() - E_mean)))
            phi_mean = float(g.index_phi_rad.iloc[i_mean])
            band.update(
                index_phi_mean_rad=phi_mean,
                phi_minus_rad=phi_mean - g.index_phi_rad.min(),
                phi_plus_rad=g.index_phi_rad.max() - phi_mean,
            )
        out.append(band)
    bands_tab = pd.DataFrame(out)
    table_io.write_table(bands_tab, bands)
    files = {
        (g["design"], float(g["E"])): p
        for g, p in _by_stem(paths, r"path_(?P<design>[A-Za-z0-9]+)_E(?P<E>[0-9.e+-]+)", "path table")
    }
    curves, cross, phi = [], [], []
    for dk in st["optimal"]:
        at = {}
        for E in (E_min, E_mean, E_max):
            key = next(k for k in files if k[0] == dk and np.isclose(k[1], E, rtol=1e-5))
            df = table_io.read_table(files[key])
            at[E] = df.dp.where(df.status == "ok")
            curves.append((dk, E, df.s.to_numpy(), at[E].to_numpy()))
            if "dphi" in df:  # a rigid platform: δφ along the path too
                phi.append((dk, E, df.s.to_numpy(), df.dphi.where(df.status == "ok").to_numpy()))
        cross += [{"design": dk, "s_m": c} for c in scans.crossings(df.s, at[E_max], at[E_min])]
    cross_tab = pd.DataFrame(cross, columns=["design", "s_m"])
    table_io.write_table(cross_tab, crossings)
    mode = study.redundancy(st)
    paper_cross = {dk: paper_value(f"{dk.replace('opt', '*')} E_max/E_min crossing") for dk in st["optimal"]}
    paper_cross = {dk: v for dk, v in paper_cross.items() if v is not None and st.get("paper_comparison")}
    elasticity_plots.fig18_index_vs_E(tab, E_mean, bands_tab, figure, mode=mode, paper=_paper_uq_bands(st))
    elasticity_plots.fig19_paths(
        curves, cross_tab, paths_figure, mode=mode, paper=paper_cross, phi=phi or None
    )


# ---- dead-length calibration -------------------------------------------------------------------
def dead_length_point(st, box_file, table, d=None, threads=None):
    """Paper-comparable numbers at dead length ``d`` [m] (default: every value of
    ``dead_length.values_m``, one row each, in one process): the plane extremes of each pulley design
    on the DOE robot, and each optimal design's index at E_min, E_mean, E_max. A rigid platform's
    ok points whose cables interfere at the solved pose are left out of both (``_grid_index``,
    ``add_interference``) and counted, last, in interfering_points_plane_<pulley> and
    interfering_points_<design>_<Emin|Emean|Emax>."""
    box, n = workspace.read_box(box_file), st["dead_length"]["index_n"]
    rows = []
    for dv in st["dead_length"]["values_m"] if d is None else [d]:
        row, left = {"d_m": dv}, {}
        for pk in st["pulleys"]:
            robot = study.design_robot(st, st["doe"]["robot"], st["pulleys"][pk], dead_length=dv)
            plane = scans.plane(
                robot, st["plane"]["z_m"], st["dead_length"]["plane_n"], **study.solve_kwargs(st, threads)
            )
            if not robot.point_mass:  # a rigid platform: its interfering points left out (issue 39)
                plane = add_interference(robot, plane)
                left[f"interfering_points_plane_{pk}"] = int(
                    ((plane.status == "ok").to_numpy() & ~interference_free_rows(plane)).sum()
                )
                plane = plane[interference_free_rows(plane)]
            lo, hi = scans.ok_extremes(plane)
            row[f"plane_{pk}_min_m"], row[f"plane_{pk}_max_m"] = lo, hi
        for dk, spec in st["optimal"].items():
            for tag, E in zip(("Emin", "Emean", "Emax"), st["elasticity"]["E_path_Pa"]):
                robot = study.design_robot(st, st["doe"]["robot"], spec, E=E, dead_length=dv)
                g = _grid_index(st, robot, box, n, threads)
                row[f"{dk}_{tag}_index_m"] = g["index_m"]
                if "interfering_points" in g:
                    left[f"interfering_points_{dk}_{tag}"] = g["interfering_points"]
        rows.append({**row, **left})
    table_io.write_table(pd.DataFrame(rows), table)


def dead_length(st, tables, table, figure):
    """The dead-length sweep as one table and its figure."""
    tab = concat(tables).sort_values("d_m", ignore_index=True)
    table_io.write_table(tab, table)
    dead_length_plots.dead_length_figure(
        tab, st["dead_length_m"], figure, mode=study.redundancy(st), paper=bool(st.get("paper_comparison"))
    )


# ---- summary -----------------------------------------------------------------------------------
def summary(st, results, table, markdown):
    """results/<study>/summary.md and .csv (``cdpr.pipeline.summary``)."""
    sm.write_summary(st, results, markdown, table)


def parity_figure(st, table, figure):
    """The parity chart of every paper number against ours from ``summary.csv``."""

    parity_plots.parity_chart(table_io.read_table(table), figure, mode=study.redundancy(st))


def conclusions(st, results, table, markdown):
    """results/<study>/conclusions.md and .csv: the paper's conclusions on this study's robot against
    its reference study (``cdpr.pipeline.conclusions``)."""
    robot_conclusions.write_conclusions(st, results, table, markdown)


# ---- error budget and the paper-rule-versus-physics comparison ---------------------------------
#: The leading columns of a budget table, before the optional p95 (and orientation) ones.
_BUDGET_COLUMNS = [
    "design",
    "region",
    "entry",
    "mean_m",
    "max_m",
    "share_m",
    "largest_fraction",
    "points",
    "ok_points",
]


def _budget_rows(label, region, summary):
    cols = _BUDGET_COLUMNS + [c for c in ("p95_m",) if c in summary]
    return summary.assign(design=label, region=region)[cols]


def budget_design(st, comparison, label, box_file, table, path_table, threads=None):
    """Error budget (``cdpr.analyses.budget``) of one design over the n^3 grid of RW_C and along its robot's
    section 3.3.1 path: summary rows per region and entry, and ‖δp‖ per entry along the path."""
    cmp = cm.load_comparison(comparison)
    designs = budget_designs(st)
    if label not in designs:
        raise CdprError(f"budget: unknown design {label!r}; allowed: {', '.join(designs)}")
    rk, spec = designs[label]
    robot = study.design_robot(st, rk, spec)
    b = cmp["budget"]
    P = workspace.grid_points(workspace.read_box(box_file), b["index_n"])
    rows = [
        _budget_rows(label, "RW_C", budget.summarise(budget.error_budget(robot, P, b["t_min_N"], threads)))
    ]
    path = st["trajectories"]["paths"].get(rk)
    cols = ["s", *budget.variants(budget.effects_of(robot)), "interaction"]
    out = pd.DataFrame(columns=cols)
    if path is not None:
        Pp, s = scans.trajectory_points(path["start_m"], path["end_m"], st["trajectories"]["points"])
        bp = budget.error_budget(robot, Pp, b["t_min_N"], threads)
        rows.append(_budget_rows(label, "path", budget.summarise(bp)))
        nm, _ = budget.norms(bp)
        for k, r in bp.items():
            nm.loc[r["status"] != "ok", k] = np.nan
        out = nm.assign(s=s)[cols]
    table_io.write_table(pd.concat(rows, ignore_index=True), table)
    table_io.write_table(out, path_table)


def budget_tables(st, comparison, tables, paths, table, figure, paths_figure):
    """The error budget of every design as one table (design, region, entry, ...), its stacked bars
    and its curves along the paths."""
    found = {
        g["label"]: p for g, p in _by_stem(tables, r"(?P<label>[A-Za-z0-9]+_[A-Za-z0-9]+)", "budget table")
    }
    order = [lab for lab in budget_designs(st) if lab in found]
    tab = pd.concat([table_io.read_table(found[lab]) for lab in order], ignore_index=True)
    table_io.write_table(tab, table)
    pfiles = {
        g["label"]: p for g, p in _by_stem(paths, r"path_(?P<label>[A-Za-z0-9]+_[A-Za-z0-9]+)", "budget path")
    }
    curves = {lab: table_io.read_table(pfiles[lab]) for lab in order if lab in pfiles}
    budget_plots.budget_bars(tab, figure)
    budget_plots.budget_paths({k: v for k, v in curves.items() if len(v)}, paths_figure)


def study_budget_design(st, design, box_file, table, threads=None):
    """The error budget (``cdpr.analyses.budget``) of one optimal design on the DOE robot of a
    spatial study, over the index_n^3 grid of RW_C at the study's orientation (``rotvec_rad``): one
    row per entry (``budget.summarise``: ‖δp‖ and ‖δφ‖ over the points ok in every entry) with the
    design, the region and entry_ok_points (points ok in that entry alone; the winch entries flag
    points whose drum angle leaves [0, q_max] as infeasible). Every cable without a winch of its own
    gets the study's drum (``study.budget_drum``: ``budget.drum``, Table 1 by default), and the
    cables the study's ``budget.linear_density_kg_m`` when given (``study.budget_linear_density``;
    > 0: the ``sag`` entries and the p95 columns, ``budget.effects_of``). A rigid platform's points
    whose cables interfere at the robot's solved pose (``_budget_interfering``) are left out of every
    entry and counted in interfering_points, last (docs/interference.md)."""
    if design not in st["optimal"]:
        raise CdprError(f"budget: unknown design {design!r}; allowed: {', '.join(st['optimal'])}")
    b = st["budget"]
    robot = study.design_robot(st, st["doe"]["robot"], st["optimal"][design])
    rho = study.budget_linear_density(st)
    if rho is not None:
        robot = with_values(robot, linear_density=rho)
    robot = budget.with_drums(robot, study.budget_drum(st))
    P = workspace.grid_points(workspace.read_box(box_file), b["index_n"])
    res = budget.error_budget(robot, P, b["t_min_N"], threads, rotvec=study.rotvec(st))
    last = []
    if not robot.point_mass:  # the points where the robot's cables interfere are left out (issue 39)
        bad = _budget_interfering(robot, P, res["all"], study.rotvec(st))
        res = {k: {**r, "status": np.where(bad, "interfering", r["status"])} for k, r in res.items()}
        last = ["interfering_points"]
    tab = budget.summarise(res).assign(design=design, region="RW_C")
    tab["entry_ok_points"] = [int((res[k]["status"] == "ok").sum()) for k in tab.entry]
    if last:
        tab["interfering_points"] = int(bad.sum())
    extra = [c for c in ("mean_rad", "max_rad", "p95_m", "p95_rad") if c in tab]
    table_io.write_table(tab[_BUDGET_COLUMNS + extra + ["entry_ok_points"] + last], table)


def _budget_interfering(robot, P, all_effects, rotvec):
    """Mask (N,) of the budget's points where the robot itself (the ``all`` entry: every effect, the
    study's robot) has interfering cables at its solved pose P + δp, R = exp([δφ]) R_d
    (``interference.interfering_at``; heavy cables under L_TS at the desired pose); only points ok
    in that entry are tested."""
    ok = np.asarray(all_effects["status"]) == "ok"
    rv = (
        np.zeros((len(P), 3)) if rotvec is None else np.broadcast_to(np.asarray(rotvec, dtype=float), P.shape)
    )
    P_s = np.where(ok[:, None], P + np.asarray(all_effects["dp"]), np.nan)
    R_s = rotation_matrix(np.asarray(all_effects["dphi"])) @ rotation_matrix(rv)
    return ok & interfering_at(robot, P_s, R_s=R_s, desired=np.column_stack([P, rv]))


def study_budget(st, tables, table, figure):
    """The study's error budget of every optimal design as one table and its stacked bars
    (``plots.budget.budget_bars``, with the orientation panel when the table has ‖δφ‖)."""
    found = {g["design"]: p for g, p in _by_stem(tables, r"(?P<design>[A-Za-z0-9_-]+)", "budget table")}
    order = [d for d in st["optimal"] if d in found]
    tab = pd.concat([table_io.read_table(found[d]) for d in order], ignore_index=True)
    table_io.write_table(tab, table)
    budget_plots.budget_bars(tab, figure, xlabel=f"design [{st['doe']['robot']} optimal]")


def comparison(st, comparison, tables, table, figure, markdown):
    """The comparison page (``cdpr.pipeline.comparison``): every conclusion in both modes with its verdict,
    the difference maps on the plane, and the error budget (``tables``: the budget table) with one
    sentence per design. Figures sit beside ``table``; ``figure`` is the difference maps."""
    cmp = cm.load_comparison(comparison)
    pres, fres = cmp["paper"]["results"], cmp["physical"]["results"]
    rows = cm.conclusions(st, pres, fres)
    table_io.write_table(rows, table)
    diffs = {(rk, pk): cm.difference_table(pres, fres, rk, pk) for rk in st["robots"] for pk in st["pulleys"]}
    anchors = {rk: study.robot_of(st, rk).A for rk in st["robots"]}
    comparison_plots.comparison_difference_maps(diffs, anchors, st["plane"]["z_m"], figure)
    comparison_plots.comparison_planes(
        diffs, anchors, st["plane"]["z_m"], Path(figure).with_name("planes.png")
    )
    comparison_plots.comparison_overlays(
        {m: _overlay_data(st, cmp[m]["results"]) for m in ("paper", "physical")},
        Path(figure).with_name("overlays.png"),
    )
    stats = cm.difference_stats({f"{rk}_{pk}": t for (rk, pk), t in diffs.items()})
    layout = ComparisonLayout(cmp)  # where the stats and the budget figures are (beside ``figure``)
    table_io.write_table(stats, layout.paths("comparison", "stats")[0])
    bt = table_io.read_table(tables[0]) if tables else None
    sentences = []
    if bt is not None:
        for label in dict.fromkeys(bt.design):
            g = bt[bt.design == label]
            rw = g[g.region == "RW_C"].drop(columns=["design", "region"])
            pa = g[g.region == "path"].drop(columns=["design", "region"])
            sentences.append(budget.sentence(label, rw, pa if len(pa) else None))
    cm.write_page(
        cmp,
        rows,
        stats,
        bt,
        sentences,
        {
            "difference": figure,
            "budget": layout.paths("budget", "figure")[0],
            "budget_paths": layout.paths("budget", "paths_figure")[0],
            "overlays": layout.paths("comparison", "overlays")[0],
            "planes": layout.paths("comparison", "planes")[0],
        },
        markdown,
    )


def _overlay_data(st, res):
    """The tables of one study's results folder that the paper-versus-physics overlays draw (the
    CDPR4 paths, R_V, index versus E and the section 5.2 paths at E_mean); missing files are left out."""
    res = Path(res)
    out = {"paths": {}, "paths_E": []}
    for pk in st["pulleys"]:
        p = res / rel_path("trajectory_table", path="CDPR4", pulley=pk)
        if p.exists():
            out["paths"][f"CDPR4_{pk}"] = table_io.read_table(p)
    for key, rel in (("volumes", rel_path("volumes")), ("index_vs_E", rel_path("elasticity"))):
        if (res / rel).exists():
            out[key] = table_io.read_table(res / rel)
    E_mean = float(st["elasticity"]["E_path_Pa"][1])
    for dk in st["optimal"]:
        p = res / rel_path("elasticity_path", design=dk, E=f"{E_mean:.6g}")
        if p.exists():
            df = table_io.read_table(p)
            out["paths_E"].append((dk, df.s.to_numpy(), df.dp.where(df.status == "ok").to_numpy()))
    return out


# ---- uncertainty and sensitivity (beyond the paper: cdpr.analyses.uncertainty) ---------------------------
def uq_shard(st, design, case, shard, box_file, table, points, threads=None):
    """One Monte Carlo shard by full solves with the linearised propagation of the same samples."""
    samples, pts = uq.mc_shard(st, design, case, workspace.read_box(box_file), int(shard), threads)
    table_io.write_table(samples, table)
    table_io.write_table(pts, points)


def uq_design(st, design, case, box_file, table, path, sobol, tolerances, map, threads=None):
    """Every sample linearised over RW_C, the path bands, the Sobol indices and the dominant-parameter
    map of one design and case."""
    box = workspace.read_box(box_file)
    table_io.write_table(uq.linear_samples(st, design, case, box, threads), table)
    table_io.write_table(uq.path_bands(st, design, case, threads), path)
    indices, rows = uq.sobol(st, design, case, box, threads)
    table_io.write_table(indices, sobol)
    table_io.write_table(rows, tolerances)
    table_io.write_table(uq.dominant_map(st, design, case, threads), map)


_UQ = r"(?P<design>[A-Za-z0-9]+)_(?P<case>uncompensated|compensated)"


def uncertainty(
    st,
    tables,
    paths,
    bands,
    agreement,
    sobol,
    figure,
    paths_figure,
    sobol_figure,
    map_figure,
    agreement_figure,
    residual_figure=None,
):
    """Aggregate the uncertainty jobs: index bands (per-cable Monte Carlo, linearised and full, and
    every declared parameter from Saltelli's rows), the agreement of the linearisation with the full
    solves, the Sobol indices; and the figures. ``tables``: the uncertainty jobs' files; ``paths``:
    the elasticity tables (common-E index sweep and paths) the figures compare with."""
    u = st["uncertainty"]
    kinds = {
        "mc": rf"mc_{_UQ}_(?P<shard>\d+)",
        "points": rf"points_{_UQ}_(?P<shard>\d+)",
        "linear": rf"{_UQ}_linear",
        "path": rf"{_UQ}_path",
        "sobol": rf"{_UQ}_sobol",
        "tolerances": rf"{_UQ}_tolerances",
        "map": rf"{_UQ}_map",
    }
    found = {k: {} for k in kinds}
    for p in tables:
        stem = Path(p).stem
        kind = next((k for k, pat in kinds.items() if re.fullmatch(pat, stem)), None)
        if kind is None:
            raise CdprError(
                f"{p}: not an uncertainty file (expected mc_, points_, _linear, _path, _sobol, _tolerances, _map)"
            )
        g = re.fullmatch(kinds[kind], stem).groupdict()
        found[kind].setdefault((g["design"], g["case"]), []).append((int(g.get("shard", 0)), p))
    read = {k: {key: concat([p for _, p in sorted(v)]) for key, v in d.items()} for k, d in found.items()}
    common = {}
    for p in paths:
        stem = Path(p).stem
        if stem == "index_vs_E":
            common["index_vs_E"] = table_io.read_table(p)
        elif stem == "bands":
            common["bands"] = table_io.read_table(p)
        elif (m := re.fullmatch(r"path_(?P<design>[A-Za-z0-9]+)_E(?P<E>[0-9.e+-]+)", stem)) is not None:
            df = table_io.read_table(p)
            common.setdefault("paths", []).append(
                (m["design"], float(m["E"]), df.s.to_numpy(), df.dp.where(df.status == "ok").to_numpy())
            )
            if "dphi" in df:  # a rigid platform: δφ along the path too
                common.setdefault("phi_paths", []).append(
                    (m["design"], float(m["E"]), df.s.to_numpy(), df.dphi.where(df.status == "ok").to_numpy())
                )
    rows, agree = [], []
    for design in u["designs"]:
        for case in study.uq_cases(st):
            key = (design, case)
            for name in ("mc", "points", "linear", "tolerances"):
                if key not in read[name]:
                    raise CdprError(f"uncertainty: no {name} table of {design} {case} among the inputs")
            # the per-cable Monte Carlo (linearised, full) and every declared parameter (Saltelli's rows)
            b = uq.bands(read["linear"][key], read["mc"][key], rows=read["tolerances"][key])
            b.insert(0, "case", case)
            b.insert(0, "design", design)
            b["index_n"] = [u["monte_carlo"]["index_n"]] * 2 + [u["sobol"]["index_n"]]
            rows.append(b)
            a = uq.agreement(read["mc"][key], read["points"][key], u["monte_carlo"]["agree_tol_m"])
            agree.append({"design": design, "case": case, **a})
    bands_tab = pd.concat(rows, ignore_index=True)
    agree_tab = pd.DataFrame(agree)
    sob = []
    for (design, case), df in read["sobol"].items():
        df = df.copy()
        df.insert(0, "case", case)
        df.insert(0, "design", design)
        sob.append(df)
    sobol_tab = pd.concat(sob, ignore_index=True)
    table_io.write_table(bands_tab, bands)
    table_io.write_table(agree_tab, agreement)
    table_io.write_table(sobol_tab, sobol)
    paper_bands = _paper_uq_bands(st)
    robot = study.robot_of(st, st["doe"]["robot"])
    mode = study.uq_redundancy(st)  # the model of the uncompensated robot
    # a robot solved as a pose: a ‖δp‖ and a δφ panel in every figure
    responses = RESPONSES if study.uq_spatial(st) else RESPONSES[:1]
    z = st["plane"]["z_m"]
    common_paths = {"dp": common.get("paths", []), "dphi": common.get("phi_paths", [])}
    uq_plots.uq_index_distribution(
        read["linear"], read["tolerances"], common.get("index_vs_E"), paper_bands, figure, mode, responses
    )
    uq_plots.uq_path_bands(read["path"], common_paths, paths_figure, mode, study.redundancy(st), responses)
    uq_plots.uq_sobol(sobol_tab, sobol_figure, mode=mode, responses=responses)
    uq_plots.uq_dominant_map(read["map"], robot.A, z, map_figure, mode=mode, responses=responses)
    uq_plots.uq_agreement(read["mc"], agreement_figure, mode=mode, responses=responses)
    if residual_figure:
        uq_plots.uq_residual_map(read["map"], robot.A, z, residual_figure, mode=mode, responses=responses)


def _paper_uq_bands(st):
    """The paper's common-E band per design {design: (index, minus, plus)} [m] from
    cdpr/data/paper_values.yaml, for the paper's study only."""
    if not st.get("paper_comparison"):
        return {}
    out = {}
    for v in sm.paper_values():
        o = v["ours"]
        if o.get("kind") == "band" and o.get("column") in ("index_mean_m", "minus_m", "plus_m"):
            out.setdefault(o["design"], {})[o["column"]] = v["value"] / 1000.0
    return {d: (c["index_mean_m"], c["minus_m"], c["plus_m"]) for d, c in out.items() if len(c) == 3}
