"""Command line: ``cdpr inverse | point | grid | winch`` (also ``python -m cdpr``).

JSON with ``--json``, a readable table without. Options given on the command line override the
robot file exactly as if it had been edited. SI units throughout.
"""
from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from . import io, study, winch
from .errors import CdprError
from .inverse import L_TS, igm_e
from .redundancy import solve_points, solve_table, subset_label
from .robot import PULLEY_KINDS, load_robot
from .workspace import check_box, frame_box, grid_points, shard_range


def _robot_options(sp):
    sp.add_argument("--robot", required=True, metavar="FILE", help="robot YAML file (config/robots/*.yaml)")
    sp.add_argument("--pulley", choices=PULLEY_KINDS, help="pulley kind for every cable")
    sp.add_argument("--h", type=float, metavar="M", help="lever arm h [m] for every cable")
    sp.add_argument("--rp", type=float, metavar="M", help="sheave radius r_p [m] for every cable")
    sp.add_argument("--dead-length", type=float, metavar="M", help="dead length d [m] for every cable")
    sp.add_argument("--json", action="store_true", help="print JSON")


def _solver_options(sp):
    sp.add_argument("--E", type=float, metavar="PA", help="Young's modulus E [Pa]")
    sp.add_argument("--mass", type=float, metavar="KG", help="platform mass M [kg]")
    sp.add_argument("--method", choices=("newton", "fixed_point"), default="newton", help="DEGM_E solver (default newton)")
    sp.add_argument("--engine", choices=("compiled", "numpy"), default="compiled",
                    help="compiled numba kernel (default, Newton only) or the numpy reference implementation")
    sp.add_argument("--threads", type=int, help="threads of the compiled engine (default: all cores)")


def _load(args):
    return load_robot(args.robot, pulley=args.pulley, h=args.h, r_p=args.rp, dead_length=args.dead_length,
                      E=getattr(args, "E", None), mass=getattr(args, "mass", None))


def _table(rows, headers):
    cols = [[h] + [r[i] for r in rows] for i, h in enumerate(headers)]
    widths = [max(len(x) for x in c) for c in cols]
    lines = ["  ".join(x.rjust(w) for x, w in zip(r, widths)) for r in [headers] + rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def cmd_inverse(args):
    robot = _load(args)
    P = np.array([args.at], dtype=float)
    st = igm_e(robot, P)
    lts = L_TS(robot, P)[0]
    out = [{"cable": i + 1, "L_TS": float(lts[i]), "L_TE": float(st.L_TE[0, i]), "gamma": float(st.gamma[0, i]),
            "l_d": float(st.l_d[0, i]), "l_E": float(st.l_E[0, i]), "D": st.D[0, i].tolist()} for i in range(robot.m)]
    if args.json:
        print(json.dumps(io.clean_json(out), indent=2))
        return
    print(f"{robot.name} ({robot.pulley_summary()}, {robot.dead_length_summary()}) at P = {args.at} m")
    rows = [[str(o["cable"]), f"{o['L_TS']:.6f}", f"{o['L_TE']:.6f}", f"{o['gamma']:.6f}", f"{o['l_d']:.6f}",
             f"{o['l_E']:.6f}", "(" + ", ".join(f"{v:.4f}" for v in o["D"]) + ")"] for o in out]
    print(_table(rows, ["cable", "L_TS [m]", "L_TE [m]", "gamma [rad]", "|l_d| [m]", "|l_E| [m]", "D [m]"]))


def cmd_point(args):
    robot = _load(args)
    P = np.array([args.at], dtype=float)
    if args.engine == "compiled" and args.method == "newton":
        from .fast import solve_points_fast

        res = solve_points_fast(robot, P, threads=args.threads)
    else:
        res = solve_points(robot, P, method=args.method)
    t = res["t"][0]
    out = {
        "desired": list(map(float, args.at)),
        "solved": res["P_s"][0].tolist(),
        "dp_norm": float(res["dp"][0]),
        "tensions": [None if np.isnan(v) else float(v) for v in t],
        "subset": [int(i) + 1 for i in res["subset"][0] if i >= 0],
        "status": str(res["status"][0]),
        "iterations": int(res["iterations"][0]),
    }
    if args.json:
        print(json.dumps(io.clean_json(out), indent=2))
        return
    print(f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}, {robot.dead_length_summary()}), solver {args.method}")
    fmt = lambda v: "(" + ", ".join("nan" if v is None or v != v else f"{x:.6f}" for x in v) + ")"  # noqa: E731
    print(f"  desired P  [m] : {fmt(out['desired'])}")
    print(f"  solved P*  [m] : {fmt(out['solved'])}")
    print(f"  |dp|       [m] : {out['dp_norm']:.6f}")
    print("  tensions   [N] : " + ", ".join("slack" if v is None else f"{v:.2f}" for v in out["tensions"]))
    print(f"  subset         : {subset_label(res['subset'][0]) or '-'}")
    print(f"  status         : {out['status']}  ({out['iterations']} iterations)")


def cmd_grid(args):
    robot = _load(args)
    if args.box_file:
        from .jobs import read_box

        box = check_box(read_box(args.box_file))
    elif args.frame:
        box = check_box(frame_box(robot))
    elif args.box:
        box = check_box(args.box)
    else:
        raise CdprError("give the grid box with --box, --box-file or --frame")
    if args.n < 1:
        raise CdprError(f"--n must be a positive integer, got {args.n}")
    start, stop = shard_range(args.n**3, args.shard, args.shards)
    t0 = time.perf_counter()
    P = grid_points(box, args.n, start, stop)
    df = solve_table(robot, P, method=args.method, engine=args.engine, threads=args.threads)
    io.write_table(df, args.out)
    dt = time.perf_counter() - t0
    _report(df, args.out, args, dt)


def cmd_winch(args):
    p = winch.load_params(args.params) if args.params else winch.TABLE1
    if args.steps < 2:
        raise CdprError(f"--steps must be at least 2, got {args.steps}")
    df = winch.winch_table(p, args.lpm_from, args.lpm_to, args.steps)
    if args.out:
        io.write_table(df, args.out)
    if args.json:
        print(json.dumps(io.clean_json(df.to_dict(orient="records")), indent=2))
        return
    print(f"winch (l_pm0 = {winch.l_pm0(p):.6f} m, q0 = {p.q0:g} rad)")
    rows = [[f"{r.l_pm:.4f}", f"{r.q1:.6f}", f"{r.q2:.6f}", f"{r.q_nw:.6f}", f"{r.dl * 1e3:.4f}"] for r in df.itertuples()]
    print(_table(rows, ["l_pm [m]", "q1 [rad]", "q2 [rad]", "q_nw [rad]", "dl [mm]"]))


def _report(df, out, args, dt):
    """What a solver command wrote: points, time, statuses and the |dp| range of the ok points."""
    counts = {k: int(v) for k, v in df["status"].value_counts().items() if v}
    lo, hi = study.ok_extremes(df)
    rate = len(df) / dt if dt > 0 else None
    summary = {"out": out, "points": int(len(df)), "seconds": dt, "points_per_second": rate, "status": counts, "dp_min": lo, "dp_max": hi}
    if args.json:
        print(json.dumps(io.clean_json(summary), indent=2))
    else:
        print(f"wrote {len(df)} points to {out} in {dt:.2f} s ({rate:.0f} points/s)")
        print("status: " + ", ".join(f"{k} {v}" for k, v in counts.items()) + f"; |dp| over ok points: min {lo:.6f} m, max {hi:.6f} m")


def cmd_plane(args):
    robot = _load(args)
    if args.n < 2:
        raise CdprError(f"--n must be at least 2, got {args.n}")
    t0 = time.perf_counter()
    df = study.plane(robot, args.z, args.n, method=args.method, engine=args.engine, threads=args.threads)
    io.write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)


def cmd_trajectory(args):
    robot = _load(args)
    if args.n < 2:
        raise CdprError(f"--n must be at least 2, got {args.n}")
    t0 = time.perf_counter()
    df = study.trajectory(robot, args.start, args.end, args.n, method=args.method, engine=args.engine, threads=args.threads)
    io.write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)


def cmd_plot(args):
    from .figures import KINDS  # matplotlib is imported only by the commands that draw

    KINDS[args.kind](args)


def _groups(items, size):
    return [items[i:i + size] for i in range(0, len(items), size)]


def cmd_job(args):
    from . import jobs

    st = jobs.load_study(args.study)
    i, o = args.inputs or [], args.outputs or []
    name = args.name
    if name == "volumes":
        jobs.volumes(st, args.labels, _groups(i, args.shards), *o)
    elif name == "volume-view":
        jobs.volume_views(st, args.labels[0], i, *o)
    elif name == "rw":
        jobs.regular_workspace(st, i, *o)
    elif name == "doe":
        jobs.doe_results(st, _groups(i, args.shards), *o)
    elif name == "map":
        jobs.map_rows(st, args.kind, args.box_file, *o, threads=args.threads)
    elif name == "maps":
        jobs.maps(st, i, args.box_file, *o)
    elif name == "elasticity":
        designs = list(st["optimal"])
        E_values = [float(e) for e in args.E_values]
        n_idx = len(designs) * len(E_values) * args.shards
        jobs.elasticity(st, designs, E_values, _groups(i[:n_idx], args.shards), i[n_idx:], *o)
    elif name == "dead-length-point":
        jobs.dead_length_point(st, args.d, args.box_file, *o, threads=args.threads)
    elif name == "dead-length":
        jobs.dead_length(st, i, *o)
    elif name == "summary":
        from . import summary

        summary.write_summary(st, args.results, *o)
    else:
        raise CdprError(f"unknown job {name!r}")


JOBS = ("volumes", "volume-view", "rw", "doe", "map", "maps", "elasticity", "dead-length-point", "dead-length", "summary")


def build_parser():
    ap = argparse.ArgumentParser(prog="cdpr", description="Pose errors of cable-driven parallel robots from pulleys, cable elasticity and winch geometry.")
    sub = ap.add_subparsers(dest="command", required=True)
    sp = sub.add_parser("inverse", help="extended inverse model of every cable at a point")
    _robot_options(sp)
    sp.add_argument("--at", nargs=3, type=float, required=True, metavar=("X", "Y", "Z"), help="platform position [m]")
    sp.set_defaults(func=cmd_inverse)
    sp = sub.add_parser("point", help="DEGM_E at one point: solved pose, |dp|, tensions, subset, status")
    _robot_options(sp)
    _solver_options(sp)
    sp.add_argument("--at", nargs=3, type=float, required=True, metavar=("X", "Y", "Z"), help="desired position [m]")
    sp.set_defaults(func=cmd_point)
    sp = sub.add_parser("grid", help="DEGM_E over the n^3 cell-centred grid of a box; writes parquet or CSV")
    _robot_options(sp)
    _solver_options(sp)
    sp.add_argument("--box", nargs=6, type=float, metavar=("XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"))
    sp.add_argument("--box-file", metavar="FILE", help="JSON file whose key 'box' holds the six numbers (e.g. rw_c.json)")
    sp.add_argument("--frame", action="store_true", help="the frame's bounding box (anchors' extent, z from 0 to the pulleys)")
    sp.add_argument("--n", type=int, required=True, help="points per axis")
    sp.add_argument("--out", required=True, metavar="FILE", help="output .parquet or .csv")
    sp.add_argument("--shard", type=int, default=0, help="0-based shard index (default 0)")
    sp.add_argument("--shards", type=int, default=1, help="number of shards (default 1)")
    sp.set_defaults(func=cmd_grid)
    sp = sub.add_parser("winch", help="winch joint angles and length error versus l_pm (winch seed Fig. 7)")
    sp.add_argument("--params", metavar="FILE", help="YAML of winch parameters (default: Table 1 of the winch seed)")
    sp.add_argument("--lpm-from", type=float, default=0.0)
    sp.add_argument("--lpm-to", type=float, default=5.0)
    sp.add_argument("--steps", type=int, default=101)
    sp.add_argument("--out", metavar="FILE", help="also write the table (.csv or .parquet)")
    sp.add_argument("--json", action="store_true")
    sp.set_defaults(func=cmd_winch)
    sp = sub.add_parser("plane", help="DEGM_E over a horizontal plane (Fig. 9, 12); writes a table")
    _robot_options(sp)
    _solver_options(sp)
    sp.add_argument("--z", type=float, required=True, metavar="M", help="plane height [m]")
    sp.add_argument("--n", type=int, required=True, help="points per side over the anchors' bounding box")
    sp.add_argument("--out", required=True, metavar="FILE")
    sp.set_defaults(func=cmd_plane)
    sp = sub.add_parser("trajectory", help="DEGM_E along a straight path (Fig. 10, 19); writes a table with arc length s")
    _robot_options(sp)
    _solver_options(sp)
    sp.add_argument("--start", nargs=3, type=float, required=True, metavar=("X", "Y", "Z"))
    sp.add_argument("--end", nargs=3, type=float, required=True, metavar=("X", "Y", "Z"))
    sp.add_argument("--n", type=int, required=True, help="points along the path")
    sp.add_argument("--out", required=True, metavar="FILE")
    sp.set_defaults(func=cmd_trajectory)
    sp = sub.add_parser("job", help="a pipeline task: aggregate tables into tables and figures")
    sp.add_argument("name", choices=JOBS)
    sp.add_argument("--study", required=True, metavar="FILE")
    sp.add_argument("--inputs", nargs="*", metavar="FILE")
    sp.add_argument("--outputs", nargs="*", metavar="FILE")
    sp.add_argument("--labels", nargs="*")
    sp.add_argument("--shards", type=int, default=1)
    sp.add_argument("--kind", choices=("SR", "DR"))
    sp.add_argument("--d", type=float)
    sp.add_argument("--E-values", nargs="*")
    sp.add_argument("--box-file")
    sp.add_argument("--results", help="results folder (summary)")
    sp.add_argument("--threads", type=int, help="threads of the compiled solver")
    sp.set_defaults(func=cmd_job)
    sp = sub.add_parser("plot", help="draw a figure (PNG + PDF) from result tables")
    sp.add_argument("kind", choices=("plane", "subsets", "trajectories", "winch"))
    sp.add_argument("--table", nargs="+", required=True, metavar="FILE")
    sp.add_argument("--labels", nargs="+")
    sp.add_argument("--title")
    sp.add_argument("--out", required=True, metavar="FILE.png")
    sp.set_defaults(func=cmd_plot)
    return ap


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        args.func(args)
    except CdprError as exc:
        print(f"cdpr: error: {exc}", file=sys.stderr)
        return 2
    return 0

