"""File-level tasks of the study pipeline (``cdpr job NAME``): read tables, call the library,
write tables and figures atomically. Physics lives in the library; this is plumbing."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from . import doe, io, plots, study, workspace
from .errors import ConfigError
from .robot import load_robot, read_yaml
from .redundancy import solve_table


# ---- study access -----------------------------------------------------------------------------
def load_study(path):
    data = read_yaml(path)
    if not isinstance(data, dict):
        raise ConfigError(path, None, "expected a mapping")
    data["_path"] = str(path)
    return data


def design_robot(st, robot_key, pulley, E=None, dead_length=None):
    """Robot of the study with a pulley design {kind, h_m, r_p_m} applied to every cable."""
    return load_robot(st["robots"][robot_key], pulley=pulley["kind"], h=pulley.get("h_m", 0.0) if pulley["kind"] != "fixed" else None,
                      r_p=pulley.get("r_p_m", 0.0) if pulley["kind"] != "fixed" else None,
                      dead_length=st["dead_length_m"] if dead_length is None else dead_length, E=E)


def doe_tests(st):
    """The 2^3 tests of Table 2: number, coded levels and actual design."""
    lv = st["doe"]["levels"]
    X = doe.full_factorial(3)
    rows = []
    for i, (cj, ch, cr) in enumerate(X, start=1):
        rows.append({"test": i, "joint_c": cj, "h_c": ch, "r_p_c": cr,
                     "kind": lv["joint"][int(cj > 0)], "h_m": lv["h_m"][int(ch > 0)], "r_p_m": lv["r_p_m"][int(cr > 0)]})
    return pd.DataFrame(rows)


def read_box(path):
    return json.loads(Path(path).read_text())["box"]


def concat(paths):
    return pd.concat([io.read_table(p) for p in paths], ignore_index=True)


def global_index(df):
    """Eq. (15): mean |dp| over the ok points; also the count of points that are not ok."""
    ok = df["status"] == "ok"
    return float(df.loc[ok, "dp"].mean()), int((~ok).sum())


def arange_incl(spec):
    n = int(round((spec["to"] - spec["from"]) / spec["step"])) + 1
    return np.round(spec["from"] + spec["step"] * np.arange(n), 10)


# ---- volumes (Fig. 13-14) ---------------------------------------------------------------------
def volumes(st, labels, shard_lists, out_csv, out_fig):
    """V_L and R_V per robot x pulley at the limits and over the sweep."""
    n = st["volumes"]["n"]
    sw = st["volumes"]["sweep_m"]
    lims = sorted(set(np.round(np.linspace(sw["from"], sw["to"], sw["steps"]), 10)) | set(st["volumes"]["limits_m"]))
    rows, series = [], []
    for label, paths in zip(labels, shard_lists):
        rk, pk = label.split("_", 1)
        robot = design_robot(st, rk, st["pulleys"][pk])
        df = concat(paths)
        box = workspace.frame_box(robot)
        mine = []
        for lim in lims:
            v = workspace.error_limited_volume(df, n, box, lim, robot.envelope_volume)
            mine.append({"robot": rk, "pulley": pk, "limit_m": lim, "V_T_m3": robot.envelope_volume, **{k + ("_m3" if k != "R_V" else ""): val for k, val in v.items()},
                         "paper_limit": lim in st["volumes"]["limits_m"]})
        rows += mine
        series.append(([r["limit_m"] for r in mine], [r["R_V"] for r in mine], label))
    tab = pd.DataFrame(rows)
    io.write_table(tab, out_csv)
    plots.curves(series, "error limit |dp|_lim [m]", "R_V = V_L / V_T", "Error-limited volume ratio (Fig. 14)", out_fig)


def volume_views(st, label, paths, out_fig):
    """Fig. 13: the voxels of V_L at each paper limit, as 3-D scatter (one panel per limit)."""
    import matplotlib.pyplot as plt

    n = st["volumes"]["n"]
    df = concat(paths)
    rk, pk = label.split("_", 1)
    robot = design_robot(st, rk, st["pulleys"][pk])
    lims = st["volumes"]["limits_m"]
    fig = plt.figure(figsize=(5 * len(lims), 4.5))
    for k, lim in enumerate(lims):
        ax = fig.add_subplot(1, len(lims), k + 1, projection="3d")
        sel = (df.status == "ok") & (df.dp <= lim)
        stride = max(1, int(sel.sum() // 6000))
        d = df[sel].iloc[::stride]
        v = workspace.error_limited_volume(df, n, workspace.frame_box(robot), lim, robot.envelope_volume)
        ax.scatter(d.x, d.y, d.z, c=d.dp, s=2, cmap="viridis", vmin=0, vmax=max(lims))
        ax.set(xlabel="x [m]", ylabel="y [m]", zlabel="z [m]", title=f"{label}, |dp| <= {lim} m: R_V = {v['R_V']:.2f}")
    plots.save(fig, out_fig)


# ---- regular workspaces (section 4.1.1) --------------------------------------------------------
def regular_workspace(st, grid_paths, out_csv, out_json):
    """RW_max of each DOE design (largest axis-aligned box of ok voxels) and RW_C, their intersection."""
    n = st["doe"]["workspace_n"]
    tests = doe_tests(st)
    rows, boxes = [], []
    for (_, t), path in zip(tests.iterrows(), grid_paths):
        robot = design_robot(st, st["doe"]["robot"], {"kind": t.kind, "h_m": t.h_m, "r_p_m": t.r_p_m})
        fbox = workspace.frame_box(robot)
        df = io.read_table(path)
        count, cells = workspace.largest_box(workspace.voxel_mask(df, n))
        box = workspace.box_from_cells(fbox, n, cells)
        boxes.append(box)
        rows.append({"test": int(t.test), "kind": t.kind, "h_m": t.h_m, "r_p_m": t.r_p_m, "xmin": box[0], "xmax": box[1], "ymin": box[2],
                     "ymax": box[3], "zmin": box[4], "zmax": box[5], "volume_m3": workspace.box_volume(box)})
    tab = pd.DataFrame(rows)
    rwc = workspace.intersect_boxes(boxes)
    smallest = int(tab.loc[tab.volume_m3.idxmin(), "test"])
    contained = all(all(b[2 * a] <= boxes[smallest - 1][2 * a] + 1e-12 and boxes[smallest - 1][2 * a + 1] <= b[2 * a + 1] + 1e-12 for a in range(3)) for b in boxes)
    paper = st["doe"]["paper_rw_c_m"]
    used = paper if st["doe"]["rw_c"] == "paper" else rwc
    io.write_table(tab, out_csv)
    io.write_json({"computed": rwc, "computed_volume_m3": workspace.box_volume(rwc), "paper": paper,
                   "paper_volume_m3": workspace.box_volume(paper), "smallest_rw_max_test": smallest,
                   "smallest_contained_in_all": contained, "grid_n": n, "use": st["doe"]["rw_c"], "box": used}, out_json)


# ---- DOE (Fig. 15-16) --------------------------------------------------------------------------
def doe_results(st, shard_lists, out_csv, out_effects, out_fig15, out_fig16):
    tests = doe_tests(st)
    idx = [global_index(concat(p)) for p in shard_lists]
    tests["index_m"] = [i for i, _ in idx]
    tests["not_ok_points"] = [k for _, k in idx]
    tests["N"] = st["doe"]["index_n"] ** 3
    io.write_table(tests, out_csv)
    eff = doe.effects(tests[["joint_c", "h_c", "r_p_c"]].to_numpy(), tests["index_m"].to_numpy(), ["joint", "h", "r_p"])
    io.write_table(eff, out_effects)
    plots.bars([f"{t}: {k} h={h * 1e3:g} r_p={r * 1e3:g}" for t, k, h, r in zip(tests.test, tests.kind, tests.h_m, tests.r_p_m)],
               tests.index_m, "global index mean |dp| [m]", "DOE responses (Fig. 15)", out_fig15)
    e = eff[eff.term != "mean"]
    plots.bars(list(e.term), e.effect, "effect on mean |dp| [m]", "Effects and interactions (Fig. 16)", out_fig16)


# ---- h-r_p maps (Fig. 17, Table 3) -------------------------------------------------------------
def map_rows(st, kind, box_file, out_csv, threads=None):
    """Index over every map cell (r_p, h) with r_p < h for one pulley kind (Fig. 17)."""
    box = read_box(box_file)
    n = st["maps"]["index_n"]
    P = workspace.grid_points(box, n)
    rows = []
    cells = [(h, r_p) for h in arange_incl(st["maps"]["h_m"]) for r_p in arange_incl(st["maps"]["r_p_m"]) if r_p < h - 1e-12]
    for h, r_p in cells:
        robot = design_robot(st, st["doe"]["robot"], {"kind": kind, "h_m": float(h), "r_p_m": float(r_p)})
        ix, bad = global_index(solve_table(robot, P, method=st["solver"], threads=threads))
        rows.append({"kind": kind, "h_m": float(h), "r_p_m": float(r_p), "index_m": ix, "not_ok_points": bad, "N": n**3})
    io.write_table(pd.DataFrame(rows, columns=["kind", "h_m", "r_p_m", "index_m", "not_ok_points", "N"]), out_csv)


def maps(st, row_paths, box_file, out_map, out_lines, out_fig):
    import matplotlib.pyplot as plt

    tab = concat(row_paths)
    io.write_table(tab, out_map)
    box = read_box(box_file)
    lv = st["doe"]["levels"]
    n = st["doe"]["index_n"]
    P = workspace.grid_points(box, n)
    lines = []
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, kind in zip(axes, ("SR", "DR")):
        g = tab[tab.kind == kind]
        if g.empty:
            continue
        v = doe.valley(g.r_p_m, g.h_m, g.index_m)
        use = v[v.interior]
        k = doe.line_through_origin(use.r_p_star, use.h) if len(use) else float("nan")
        pt = doe.line_field_point(k, lv["r_p_m"], lv["h_m"]) if np.isfinite(k) else None
        ix = float("nan")
        if pt is not None:
            robot = design_robot(st, st["doe"]["robot"], {"kind": kind, "h_m": pt[1], "r_p_m": pt[0]})
            ix, _ = global_index(solve_table(robot, P, method=st["solver"]))
        lines.append({"kind": kind, "slope_k": k, "valley_points": int(len(use)), "r_p_opt_m": pt[0] if pt else None,
                      "h_opt_m": pt[1] if pt else None, "index_opt_m": ix, "N": n**3})
        piv = g.pivot(index="h_m", columns="r_p_m", values="index_m")
        cf = ax.contourf(piv.columns * 1e3, piv.index * 1e3, piv.values, levels=20, cmap="viridis")
        fig.colorbar(cf, ax=ax, label="mean |dp| [m]")
        ax.plot(v.r_p_star * 1e3, v.h * 1e3, "w.", ms=4, label="valley r_p*(h)")
        rr = np.linspace(0, g.r_p_m.max(), 10)
        ax.plot(rr * 1e3, k * rr * 1e3, "r-", label=f"h = {k:.2f} r_p")
        ax.add_patch(plt.Rectangle((lv["r_p_m"][0] * 1e3, lv["h_m"][0] * 1e3), (lv["r_p_m"][1] - lv["r_p_m"][0]) * 1e3,
                                   (lv["h_m"][1] - lv["h_m"][0]) * 1e3, fill=False, ec="w", ls="--"))
        if pt:
            ax.plot(pt[0] * 1e3, pt[1] * 1e3, "r*", ms=12, label=f"I_{kind}")
        ax.set(xlabel="r_p [mm]", ylabel="h [mm]", title=f"CDPR4_{kind} (Fig. 17)", xlim=(0, g.r_p_m.max() * 1e3), ylim=(0, g.h_m.max() * 1e3))
        ax.legend(fontsize=7, loc="lower right")
    io.write_table(pd.DataFrame(lines), out_lines)
    plots.save(fig, out_fig)


# ---- elasticity (Fig. 18-19) -------------------------------------------------------------------
def elasticity(st, designs, E_values, shard_lists, path_tables, out_csv, out_bands, out_fig18, out_fig19, out_cross):
    rows = []
    for (dk, E), paths in zip([(d, E) for d in designs for E in E_values], shard_lists):
        ix, bad = global_index(concat(paths))
        rows.append({"design": dk, "E_Pa": E, "index_m": ix, "not_ok_points": bad})
    tab = pd.DataFrame(rows)
    io.write_table(tab, out_csv)
    E_mean = 102.2e9
    bands = []
    for dk, g in tab.groupby("design", sort=False):
        mean_row = g.iloc[np.argmin(np.abs(g.E_Pa - E_mean))]
        bands.append({"design": dk, "index_mean_m": mean_row.index_m, "index_min_m": g.index_m.min(), "index_max_m": g.index_m.max(),
                      "minus_m": mean_row.index_m - g.index_m.min(), "plus_m": g.index_m.max() - mean_row.index_m,
                      "total_m": g.index_m.max() - g.index_m.min(), "relative": (g.index_m.max() - g.index_m.min()) / mean_row.index_m})
    io.write_table(pd.DataFrame(bands), out_bands)
    plots.curves([(g.E_Pa / 1e9, g.index_m * 1e3, dk) for dk, g in tab.groupby("design", sort=False)], "E [GPa]", "mean |dp| [mm]",
                 "Index versus Young's modulus (Fig. 18)", out_fig18)
    series, cross = [], []
    E_path = st["elasticity"]["E_path_Pa"]
    for i, dk in enumerate(designs):
        curves = {}
        for j, E in enumerate(E_path):
            df = io.read_table(path_tables[i * len(E_path) + j])
            ok = df.status == "ok"
            curves[E] = df.dp.where(ok)
            series.append((df.s.where(ok), df.dp.where(ok) * 1e3, f"{dk} E = {E / 1e9:g} GPa"))
        s = df.s
        for c in study.crossings(s, curves[max(E_path)], curves[min(E_path)]):
            cross.append({"design": dk, "s_m": c})
    io.write_table(pd.DataFrame(cross, columns=["design", "s_m"]), out_cross)
    plots.curves(series, "position along the path s [m]", "|dp| [mm]", "|dp| along the section 5.2 path (Fig. 19)", out_fig19)


# ---- dead-length calibration -------------------------------------------------------------------
def dead_length_point(st, d, box_file, out_csv, threads=None):
    """Paper-comparable numbers at dead length d: CDPR4 plane extremes and SR*/DR* index at E_min, E_mean, E_max."""
    box = read_box(box_file)
    P = workspace.grid_points(box, st["dead_length"]["index_n"])
    row = {"d_m": d}
    for pk in st["pulleys"]:
        robot = design_robot(st, st["doe"]["robot"], st["pulleys"][pk], dead_length=d)
        lo, hi = study.ok_extremes(study.plane(robot, st["plane"]["z_m"], st["dead_length"]["plane_n"], method=st["solver"], threads=threads))
        row[f"plane_{pk}_min_m"], row[f"plane_{pk}_max_m"] = lo, hi
    E_path = st["elasticity"]["E_path_Pa"]
    for dk, spec in st["optimal"].items():
        for tag, E in zip(("Emin", "Emean", "Emax"), E_path):
            robot = design_robot(st, st["doe"]["robot"], spec, E=E, dead_length=d)
            row[f"{dk}_{tag}_index_m"], _ = global_index(solve_table(robot, P, method=st["solver"], threads=threads))
    io.write_table(pd.DataFrame([row]), out_csv)


def dead_length(st, paths, out_csv, out_fig):
    tab = concat(paths).sort_values("d_m")
    io.write_table(tab, out_csv)
    series = [(tab.d_m, tab[c] * 1e3, c.replace("_m", "")) for c in tab.columns if c.endswith("_index_m") and "Emean" in c]
    series += [(tab.d_m, tab[c] * 1e3, c.replace("_m", "")) for c in tab.columns if c.startswith("plane_")]
    plots.curves(series, "dead length d [m]", "[mm]", "Sensitivity of paper-comparable numbers to the dead length d", out_fig)
