"""The commands: ``cdpr inverse | point | compensate | grid | winch | plane | trajectory``.

JSON with ``--json``, a readable table without. Options given on the command line override the
robot file exactly as if it had been edited. SI units throughout. Every bad input is refused with
one sentence on stderr and exit code 2, before any work starts.

``cdpr.cli.main`` imports this module only once the command line has been parsed (``cdpr --help`` and a
usage error never load numpy). Its module-level imports are what every command needs (numpy, the robot
file reader); each command imports the rest of what it uses (the solvers, pandas, numba) itself.
"""

from __future__ import annotations

import json
import os
import time

import numpy as np

from cdpr import io
from cdpr.errors import CdprError
from cdpr.models import winch
from cdpr.robot import TABLE1, load_robot, load_winch_params

#: Bytes of memory per grid point while solving and writing (measured peak RSS / points, rounded up).
BYTES_PER_POINT = 600


def _read_table(path):
    from cdpr import table_io  # lazy: pandas and pyarrow, for the commands that read a table only

    return table_io.read_table(path)


def _write_table(df, path):
    from cdpr import table_io  # lazy: pandas and pyarrow, for the commands that write a table only

    table_io.write_table(df, path)


def _load(args):
    return load_robot(
        args.robot,
        E_cables=getattr(args, "E_cables", None),
        pulley=args.pulley,
        h=args.h,
        r_p=args.rp,
        dead_length=args.dead_length,
        E=getattr(args, "E", None),
        mass=getattr(args, "mass", None),
    )


def _points(args):
    """(N, 3) points of --at or --points; refuses non-finite coordinates and a missing --out."""
    if args.at is not None:
        if args.out:
            io.check_output(args.out)
        return np.array([args.at], dtype=float)
    if not args.out:
        raise CdprError("--points needs --out FILE for the result table")
    io.check_output(args.out)
    if str(args.points).endswith(".csv") and os.path.isfile(args.points):
        io.check_csv_rows(args.points, "xyz")  # rows as wide as the header, plain numbers
    try:
        df = _read_table(args.points)
    except FileNotFoundError:
        raise CdprError(f"{args.points}: the points file does not exist") from None
    missing = [c for c in "xyz" if c not in df.columns]
    if missing:
        raise CdprError(
            f"{args.points}: missing column(s) {', '.join(missing)}; a points table needs columns x, y, z [m]"
        )
    P = df[["x", "y", "z"]].to_numpy(dtype=float)
    bad = ~np.isfinite(P).all(axis=1)
    if bad.any():
        raise CdprError(
            f"{args.points}: row {int(np.flatnonzero(bad)[0]) + 1} has a non-finite coordinate; every x, y, z must be a finite number"
        )
    return P


def _table(rows, headers):
    cols = [[h] + [r[i] for r in rows] for i, h in enumerate(headers)]
    widths = [max(len(x) for x in c) for c in cols]
    lines = ["  ".join(x.rjust(w) for x, w in zip(r, widths)) for r in [headers] + rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _vec(v):
    return "(" + ", ".join(f"{x:.4f}" for x in v) + ")"


def cmd_inverse(args):
    from cdpr.models.inverse import L_TS, igm_e  # lazy: the inverse model, for this command only

    robot = _load(args)
    P = _points(args)
    st = igm_e(robot, P)
    lts = L_TS(robot, P)
    if args.points or args.out:
        import pandas as pd  # lazy: a table of points only

        cols = {"x": P[:, 0], "y": P[:, 1], "z": P[:, 2]}
        for i in range(robot.m):
            c = i + 1
            cols.update(
                {
                    f"L_TS{c}": lts[:, i],
                    f"L_TE{c}": st.L_TE[:, i],
                    f"gamma{c}": st.gamma[:, i],
                    f"alpha{c}": st.alpha[:, i],
                    f"beta{c}": st.beta[:, i] if robot.kind[i] == 2 else np.full(len(P), np.nan),
                    f"inside{c}": st.inside[:, i],
                }
            )
        df = pd.DataFrame(cols)
        _write_table(df, args.out)
        print(
            f"wrote {len(df)} points to {args.out}; {int(st.inside.any(axis=1).sum())} inside a sheave (lengths clipped there)"
        )
        return
    out = [
        {
            "cable": i + 1,
            "L_TS": float(lts[0, i]),
            "L_TE": float(st.L_TE[0, i]),
            "gamma": float(st.gamma[0, i]),
            "l_d": float(st.l_d[0, i]),
            "l_E": float(st.l_E[0, i]),
            "alpha": float(st.alpha[0, i]),
            "beta": float(st.beta[0, i]) if robot.kind[i] == 2 else None,
            "H": st.H[0, i].tolist(),
            "K": st.K[0, i].tolist(),
            "D": st.D[0, i].tolist(),
            "inside": bool(st.inside[0, i]),
        }
        for i in range(robot.m)
    ]
    if args.json:
        print(json.dumps(io.clean_json(out), indent=2))
        return
    print(f"{robot.name} ({robot.pulley_summary()}, {robot.dead_length_summary()}) at P = {args.at} m")
    rows = [
        [
            str(o["cable"]),
            f"{o['L_TS']:.6f}",
            f"{o['L_TE']:.6f}",
            f"{o['gamma']:.6f}",
            f"{o['alpha']:.6f}",
            "-" if o["beta"] is None else f"{o['beta']:.6f}",
            f"{o['l_d']:.6f}",
            f"{o['l_E']:.6f}",
            _vec(o["H"]),
            _vec(o["K"]),
            _vec(o["D"]),
            "INSIDE" if o["inside"] else "",
        ]
        for o in out
    ]
    print(
        _table(
            rows,
            [
                "cable",
                "L_TS [m]",
                "L_TE [m]",
                "gamma [rad]",
                "alpha [rad]",
                "beta [rad]",
                "|l_d| [m]",
                "|l_E| [m]",
                "H [m]",
                "K [m]",
                "D [m]",
                "sheave",
            ],
        )
    )
    if any(o["inside"] for o in out):
        print(
            "warning: P (or the winch exit) lies inside a sheave circle for the cables marked INSIDE: no tangent exists, their lengths are clipped"
        )


def _solve_sensitivities(robot, P, args, L0=None):
    """The solve plus dP*/dθ (``sensitivity.sensitivities``) for --sensitivities."""
    from cdpr.solve import sensitivities  # lazy: --sensitivities only

    if args.method != "newton":
        raise CdprError(
            "--sensitivities needs --method newton (the implicit-function theorem uses its Jacobian at the solution)"
        )
    return sensitivities(
        robot,
        P,
        redundancy=args.redundancy,
        L=L0,
        engine=args.engine or "compiled",
        threads=args.threads,
    )


def cmd_point(args):
    from cdpr.solve import solve_points_any  # lazy: the solvers, for the solver commands only

    robot = _load(args)
    P = _points(args)
    L0 = None
    if args.lengths is not None and args.q is not None:
        raise CdprError("give the commanded cables either as --lengths or as drum angles --q, not both")
    if args.lengths is not None:
        if len(args.lengths) != robot.m:
            raise CdprError(f"--lengths needs one rest length per cable ({robot.m}), got {len(args.lengths)}")
        L0 = np.array(args.lengths, dtype=float)
    if args.q is not None:
        from cdpr.models.drive import rest_lengths_from_angles  # lazy: --q only

        if len(args.q) != robot.m:
            raise CdprError(f"--q needs one drum angle per cable ({robot.m}), got {len(args.q)}")
        L0 = rest_lengths_from_angles(robot, np.array([args.q]), model="winch")[0]
    if args.sensitivities:
        if L0 is not None and args.redundancy != "physical":
            raise CdprError(
                "commanded lengths need physical mode (--redundancy physical); paper mode commands L_TS at the desired point"
            )
        res = _solve_sensitivities(robot, P, args, L0)
    else:
        res = solve_points_any(
            robot,
            P,
            method=args.method,
            engine=args.engine,
            threads=args.threads,
            redundancy=args.redundancy,
            L0=L0,
        )
    if args.points or args.out:
        from cdpr.tables import to_frame  # lazy: a table of points only (pandas)

        df = to_frame(robot, res, args.redundancy)
        _write_table(df, args.out)
        _report(df, args.out, args, float("nan"))
        return
    t = res["t"][0]
    out = {
        "desired": list(map(float, args.at)),
        "solved": res["P_s"][0].tolist(),
        "dp_norm": float(res["dp"][0]),
        "tensions": [None if np.isnan(v) else float(v) for v in t],
    }
    if args.redundancy == "physical":
        out["taut"] = [int(i) + 1 for i in np.flatnonzero(res["taut"][0])]
    else:
        out["subset"] = [int(i) + 1 for i in res["subset"][0] if i >= 0]
    out.update(status=str(res["status"][0]), iterations=int(res["iterations"][0]))
    if args.sensitivities:
        S = res["S"][0]
        out["sensitivities"] = {
            name: [None if np.isnan(v) else float(v) for v in S[:, k]] for k, name in enumerate(res["names"])
        }
        out["sensitivities_smooth"] = bool(res["smooth"][0])
    if args.json:
        print(json.dumps(io.clean_json(out), indent=2))
        return
    from cdpr.models.results import subset_label  # lazy: the readable output only

    mode = "physical equilibrium" if args.redundancy == "physical" else f"paper mode, solver {args.method}"
    print(
        f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}, {robot.dead_length_summary()}), {mode}"
    )
    fmt = lambda v: "(" + ", ".join("nan" if v is None or v != v else f"{x:.6f}" for x in v) + ")"  # noqa: E731
    print(f"  desired P  [m] : {fmt(out['desired'])}")
    print(f"  solved P*  [m] : {fmt(out['solved'])}")
    print(f"  |dp|       [m] : {out['dp_norm']:.6f}")
    print("  tensions   [N] : " + ", ".join("slack" if v is None else f"{v:.2f}" for v in out["tensions"]))
    if args.redundancy == "physical":
        print(f"  taut cables    : {'-'.join(map(str, out['taut'])) or '-'}")
    else:
        print(f"  subset         : {subset_label(res['subset'][0]) or '-'}")
    print(f"  status         : {out['status']}  ({out['iterations']} iterations)")
    if args.sensitivities:
        from cdpr.parameters import UNITS, parameter_groups  # lazy: --sensitivities only

        units = [UNITS[g] for g in parameter_groups(robot.m)]
        rows = [
            [name, f"m/{unit}"] + ["nan" if v is None else f"{v:.6g}" for v in vec]
            for (name, vec), unit in zip(out["sensitivities"].items(), units)
        ]
        smooth = (
            "" if out["sensitivities_smooth"] else " (not smooth here: the subset or taut set may switch)"
        )
        print(f"sensitivities dP*/dθ at fixed commanded lengths{smooth}:")
        print(_table(rows, ["θ", "unit", "dx", "dy", "dz"]))


def cmd_compensate(args):
    """Compensated rest lengths (inverse elasto-geometric model) and, as a check, the pose the
    platform takes when they are commanded (to the same robot, or to one with --actual-E-cables)."""
    import dataclasses  # lazy: --actual-E-cables only

    from cdpr.analyses.compensation import compensated_pose  # lazy: this command only

    robot = _load(args)
    P = _points(args)
    actual = None
    if args.actual_E_cables is not None:
        if len(args.actual_E_cables) != robot.m:
            raise CdprError(
                f"--actual-E-cables needs one modulus per cable ({robot.m}), got {len(args.actual_E_cables)}"
            )
        cables = tuple(
            dataclasses.replace(c, material=dataclasses.replace(c.material, E=float(e)))
            for c, e in zip(robot.cables, args.actual_E_cables)
        )
        actual = dataclasses.replace(robot, cables=cables)
    t_max = args.t_max if args.t_max is not None else None
    if t_max is not None and not args.t_min < t_max:
        raise CdprError(f"--t-min must be below --t-max, got {args.t_min:g} N and {t_max:g} N")
    engine = args.engine or "compiled"
    res = compensated_pose(
        robot, P, actual=actual, method=args.distribution, engine=engine, t_min=args.t_min, t_max=t_max
    )
    if args.points or args.out:
        from cdpr.tables import to_frame  # lazy: tables only (pandas)

        df = to_frame(robot, res, "physical")
        for i in range(robot.m):
            df[f"L0_{i + 1}"] = res["L0"][:, i]
        for i in range(robot.m):
            df[f"t_planned{i + 1}"] = res["t_planned"][:, i]
        _write_table(df, args.out)
        _report(df, args.out, args, float("nan"))
        return
    status = str(res["status"][0])
    out = {
        "desired": list(map(float, args.at)),
        "lengths": res["L0"][0].tolist(),
        "tensions": res["t_planned"][0].tolist(),
        "status": status,
        "solved": res["P_s"][0].tolist(),
        "dp_norm": float(res["dp"][0]),
    }
    if all(w is not None for w in robot.winches):
        from cdpr.models.drive import drum_angles  # lazy: robots with winches only

        q, q_nw = drum_angles(robot, res["L0"][:1])
        out["q"], out["q_no_winch"] = q[0].tolist(), q_nw[0].tolist()
    if args.json:
        print(json.dumps(io.clean_json(out), indent=2))
        return
    print(
        f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}, {robot.dead_length_summary()}), distribution {args.distribution}"
    )
    rows = [
        [str(i + 1), f"{L:.6f}", f"{t:.2f}"] for i, (L, t) in enumerate(zip(out["lengths"], out["tensions"]))
    ]
    headers = ["cable", "rest length L0 [m]", "planned tension [N]"]
    if "q" in out:
        rows = [r + [f"{a:.6f}", f"{b:.6f}"] for r, a, b in zip(rows, out["q"], out["q_no_winch"])]
        headers += ["drum angle q [rad]", "q neglecting the winch [rad]"]
    print(_table(rows, headers))
    check = "the robot with --actual-E-cables" if actual is not None else "the same robot"
    print(
        f"status: {status}; commanded to {check}, the platform settles {out['dp_norm']:.3g} m from the desired point"
    )


def _check_size(n_points, what):
    """Refuse a job whose tables cannot fit in memory, naming the size it would need."""
    need = n_points * BYTES_PER_POINT
    avail = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    if need > avail:
        raise CdprError(
            f"{what}: {n_points:,} points would need about {need / 2**30:,.1f} GiB of memory, "
            f"more than this machine's {avail / 2**30:.1f} GiB; use fewer points or --shards"
        )


def cmd_grid(args):
    # lazy: the grid, the solvers and pandas, for this command only
    from cdpr.analyses.workspace import check_box, frame_box, grid_points, shard_range
    from cdpr.tables import solve_table

    robot = _load(args)
    io.check_output(args.out)
    if args.box_file:
        from cdpr.pipeline.study import read_box  # lazy: --box-file only

        box = read_box(args.box_file)
    elif args.frame:
        box = check_box(frame_box(robot))
    elif args.box:
        box = check_box(args.box)
    else:
        raise CdprError("give the grid box with --box, --box-file or --frame")
    start, stop = shard_range(args.n**3, args.shard, args.shards)
    _check_size(stop - start, f"--n {args.n}")
    t0 = time.perf_counter()
    P = grid_points(box, args.n, start, stop)
    if args.sensitivities:
        from cdpr.tables import to_frame  # lazy: --sensitivities only

        res = _solve_sensitivities(robot, P, args)
        df = to_frame(robot, res, args.redundancy)
    else:
        df = solve_table(
            robot, P, method=args.method, engine=args.engine, threads=args.threads, redundancy=args.redundancy
        )
    _write_table(df, args.out)
    dt = time.perf_counter() - t0
    _report(df, args.out, args, dt)


def cmd_winch(args):
    p = load_winch_params(args.params) if args.params else TABLE1
    if args.out:
        io.check_output(args.out)
    if not args.lpm_from < args.lpm_to:
        raise CdprError(f"--lpm-from must be below --lpm-to, got {args.lpm_from:g} and {args.lpm_to:g}")
    winch.check_range(p, args.lpm_from, args.lpm_to)
    from cdpr.analyses import scans  # lazy: pandas, for this command only

    df = scans.winch_table(p, args.lpm_from, args.lpm_to, args.steps)
    if args.out:
        _write_table(df, args.out)
    if args.json:
        print(json.dumps(io.clean_json(df.to_dict(orient="records")), indent=2))
        return
    print(f"winch (l_pm0 = {winch.l_pm0(p):.6f} m, q0 = {p.q0:g} rad)")
    rows = [
        [f"{r.l_pm:.4f}", f"{r.q1:.6f}", f"{r.q2:.6f}", f"{r.q_nw:.6f}", f"{r.dl * 1e3:.4f}"]
        for r in df.itertuples()
    ]
    print(_table(rows, ["l_pm [m]", "q1 [rad]", "q2 [rad]", "q_nw [rad]", "dl [mm]"]))


def _report(df, out, args, dt):
    """What a solver command wrote: points, time, statuses and the |dp| range of the ok points."""
    from cdpr.analyses import scans  # lazy: the solver commands only

    counts = {k: int(v) for k, v in df["status"].value_counts().items() if v}
    lo, hi = scans.ok_extremes(df)
    rate = len(df) / dt if dt > 0 else None
    summary = {
        "out": out,
        "points": int(len(df)),
        "seconds": dt,
        "points_per_second": rate,
        "status": counts,
        "dp_min": lo,
        "dp_max": hi,
    }
    if args.json:
        print(json.dumps(io.clean_json(summary), indent=2))
    else:
        timing = f" in {dt:.2f} s ({rate:.0f} points/s)" if rate else ""
        print(f"wrote {len(df)} points to {out}{timing}")
        print(
            "status: "
            + ", ".join(f"{k} {v}" for k, v in counts.items())
            + f"; |dp| over ok points: min {lo:.6f} m, max {hi:.6f} m"
        )


def cmd_plane(args):
    from cdpr.analyses import scans  # lazy: this command only

    robot = _load(args)
    io.check_output(args.out)
    top = float(robot.A[:, 2].min())
    if not 0.0 <= args.z < top:
        raise CdprError(
            f"--z must lie between the floor and the lowest pulley (0 <= z < {top:g} m), got {args.z:g}"
        )
    t0 = time.perf_counter()
    df = scans.plane(
        robot,
        args.z,
        args.n,
        method=args.method,
        engine=args.engine,
        threads=args.threads,
        redundancy=args.redundancy,
    )
    _write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)


def cmd_trajectory(args):
    from cdpr.analyses import scans  # lazy: this command only

    robot = _load(args)
    io.check_output(args.out)
    t0 = time.perf_counter()
    df = scans.trajectory(
        robot,
        args.start,
        args.end,
        args.n,
        method=args.method,
        engine=args.engine,
        threads=args.threads,
        redundancy=args.redundancy,
    )
    _write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)
