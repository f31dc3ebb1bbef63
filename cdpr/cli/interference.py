"""``cdpr interference``: cable-cable and cable-platform interference at a pose (``--at``) or at the
poses of a table (``--points``) (``cdpr.models.interference``; docs/interference.md)."""

from __future__ import annotations

from cdpr.cli.commands import checked, emit_json, read_points
from cdpr.models import interference as itf
from cdpr.robot import BoxBody, load_robot


def _table(rows, headers):
    """A right-aligned text table with a rule under its headers."""
    cols = [[h] + [r[i] for r in rows] for i, h in enumerate(headers)]
    widths = [max(len(x) for x in c) for c in cols]
    lines = ["  ".join(x.rjust(w) for x, w in zip(r, widths)) for r in [headers] + rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join("  " + line for line in lines)


def _body_label(robot, res):
    """A few words on the platform body that was tested."""
    body = robot.platform.body
    if isinstance(body, BoxBody):
        return f"box centre {list(body.centre)} m, half-sizes {list(body.half)} m"
    if body == "none":
        return "none (platform.body: none)"
    return "convex hull of the attachments" if res.has_body else "none (the attachments span no volume)"


def cmd_interference(args):
    """``cdpr interference``: the JSON object of ``models.interference.report`` (or a readable
    report) at --at [--rotvec]; with --points, a table of the interference columns per pose
    (``models.interference.COLUMNS``) written to --out."""
    robot = checked(
        load_robot(args.robot, pulley=args.pulley, h=args.h, r_p=args.rp, dead_length=args.dead_length), args
    )
    points = read_points(args)
    if args.points:
        import pandas as pd  # lazy: a table of points only

        from cdpr import table_io  # lazy: pandas and pyarrow, for a table of points only
        from cdpr.cli.stream import solve_chunks  # lazy: tqdm, for a table of points only

        count = [0, 0]

        def table(P, rv):
            res = itf.interference(robot, P, rv)
            count[0] += len(P)
            count[1] += int(res.free.sum())
            cols = {"x": P[:, 0], "y": P[:, 1], "z": P[:, 2]}
            if rv is not None:
                cols.update({"rx": rv[:, 0], "ry": rv[:, 1], "rz": rv[:, 2]})
            return pd.DataFrame({**cols, **itf.columns(res)})

        frames = solve_chunks(points.chunks(), table, points.n, "interference", quiet=args.quiet)
        table_io.write_table_chunks(frames, args.out)
        summary = {"out": args.out, "points": count[0], "interference_free_points": count[1]}
        if args.json:
            emit_json(summary, args)
        else:
            print(f"wrote {count[0]} poses to {args.out}; {count[1]} interference-free")
        return
    P, rv = points.first()
    res = itf.interference(robot, P, rv)
    out = itf.report(res)
    if args.json:
        emit_json(out, args)
        return
    rot = [0.0, 0.0, 0.0] if rv is None else rv[0].tolist()
    print(f"{robot.name} ({robot.pulley_summary()}) at p = {list(map(float, args.at))} m, rotvec {rot} rad")
    print(f"  platform body  : {_body_label(robot, res)}")
    verdict = "yes" if out["interference_free"] else "no"
    print(
        f"  interference-free: {verdict} ({len(out['cable_cable'])} cable-cable, "
        f"{len(out['cable_platform'])} cable-platform)"
    )
    if out["dmin_pair"] is not None:
        i, j = out["dmin_pair"]
        print(f"  closest tested pair: {i}-{j} at {out['dmin_m']:.6g} m")
    if out["shared"]:
        print(
            "  not tested (a shared end point): "
            + ", ".join(f"{a}-{b} at {s['at']}" for s in out["shared"] for a, b in [s["cables"]])
        )
    if out["cable_cable"]:
        r = [c.material.diameter / 2 for c in robot.cables]
        rows = [
            [
                f"{i}-{j}",
                f"{c['distance_m']:.6g}",
                f"{r[i - 1] + r[j - 1]:.6g}",
                f"{c['s'][0]:.6f}",
                f"{c['s'][1]:.6f}",
            ]
            for c in out["cable_cable"]
            for i, j in [c["cables"]]
        ]
        print(_table(rows, ["pair", "distance [m]", "r_i + r_j [m]", "s_i", "s_j"]))
    if out["cable_platform"]:
        rows = [
            [
                str(c["cable"]),
                f"{c['length_m']:.6g}",
                f"{c['depth_m']:.6g}",
                f"{c['s_in']:.6f}",
                f"{c['s_out']:.6f}",
            ]
            for c in out["cable_platform"]
        ]
        print(_table(rows, ["cable", "chord inside [m]", "depth [m]", "s_in", "s_out"]))
