"""``cdpr interference``: cable-cable and cable-platform interference at a pose (``--at``) or at the
poses of a table (``--points``) (``cdpr.models.interference``; docs/interference.md). Heavy cables
sag under their tensions: a rigid platform's are tested under the sag-consistent compensated lengths
of the desired pose (``analyses.interference.desired_lengths``), or, with ``--lengths``, at the pose
the platform settles at under those lengths."""

from __future__ import annotations

import numpy as np

from cdpr.cli import heavy
from cdpr.cli.commands import checked, emit_json, read_points
from cdpr.errors import CdprError
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


def _settled(robot, P, rv, L0):
    """The pose the platform settles at under the rest lengths L0 (physical mode; heavy cables by
    the heavy direct model): the equilibrium reached where the restarts find more than one, as
    ``cdpr point --points`` answers (``solve.reach_where_multiple``). Returns (P_s (1, 3),
    rotvec_s (1, 3) or None, status); CdprError in one line where the platform finds none."""
    from cdpr.solve import check_engine, reach_where_multiple, solve  # lazy: --lengths only

    engine = check_engine(None, "newton", one_shot=heavy.one_shot(robot, 1))
    res = solve(robot, P, rv, engine=engine, redundancy="physical", L0=L0)
    if "unique" in res and "rotvec" in res and not np.all(res["unique"]):
        res = reach_where_multiple(robot, res, engine=engine)
    status = str(res["status"][0])
    if status != "ok":
        raise CdprError(
            f"--lengths: the platform finds no equilibrium under these rest lengths (status {status}); "
            "there is no pose to test"
        )
    return res["P_s"][:1], (res["rotvec_s"][:1] if "rotvec_s" in res else rv), status


def _lengths(args, robot, P, rv):
    """The rest lengths the cables are tested under and where the test is made: (P, rv, L0 (m,) or
    None, the JSON's extra keys). --lengths: at the settled pose; heavy cables of a rigid platform
    without: the desired pose under the sag-consistent compensated lengths; else the desired pose
    with straight spans. The extra keys always hold ``status``: the settled pose's with --lengths,
    else ``ok`` (the desired pose is tested as given: nothing is solved that could fail)."""
    if args.lengths is not None:
        if len(args.lengths) != robot.m:
            raise CdprError(f"--lengths needs one rest length per cable ({robot.m}), got {len(args.lengths)}")
        L0 = np.array(args.lengths, dtype=float)
        P, rv, status = _settled(robot, P, rv, L0)
        extra = {"lengths": L0.tolist(), "lengths_from": "given", "solved": P[0].tolist()}
        if rv is not None:
            extra["solved_rotvec"] = rv[0].tolist()
        return P, rv, L0, {**extra, "status": status}
    if robot.heavy and not robot.point_mass:
        from cdpr.analyses.interference import desired_lengths  # lazy: heavy cables only

        L0 = desired_lengths(robot, P, rv)[0]
        if not np.isfinite(L0).all():
            raise CdprError(
                "heavy cables: no sag-consistent tension distribution in [100 N, T_a] holds the platform at this "
                "pose, so it has no rest lengths to test the catenaries under; give them with --lengths L1 ... Lm"
            )
        return P, rv, L0, {"lengths": L0.tolist(), "lengths_from": "compensated", "status": "ok"}
    return P, rv, None, {"status": "ok"}


def cmd_interference(args):
    """``cdpr interference``: the JSON object of ``models.interference.report`` (or a readable
    report) at --at [--rotvec]; with --points, a table of the interference columns per pose
    (``analyses.interference.desired_columns``) written to --out. Heavy cables of a rigid platform
    are tested under rest lengths (``_lengths``): the JSON then adds lengths and lengths_from
    (``compensated`` or ``given``), and with --lengths solved and solved_rotvec; every JSON object
    has ``status`` (issue 41: scripts read it)."""
    robot = checked(
        load_robot(
            args.robot,
            pulley=args.pulley,
            h=args.h,
            r_p=args.rp,
            dead_length=args.dead_length,
            linear_density=args.linear_density,
        ),
        args,
    )
    if args.lengths is not None and args.points:
        raise CdprError("--lengths takes one pose (--at), not a table of points (--points)")
    points = read_points(args)
    if args.points:
        import pandas as pd  # lazy: a table of points only

        from cdpr import table_io  # lazy: pandas and pyarrow, for a table of points only
        from cdpr.analyses.interference import desired_columns  # lazy: a table of points only
        from cdpr.cli.stream import solve_chunks  # lazy: tqdm, for a table of points only

        count = [0, 0]

        def table(P, rv):
            c = desired_columns(robot, P, rv)
            count[0] += len(P)
            count[1] += int(pd.array(c["interference_free"], dtype="boolean").sum())
            cols = {"x": P[:, 0], "y": P[:, 1], "z": P[:, 2]}
            if rv is not None:
                cols.update({"rx": rv[:, 0], "ry": rv[:, 1], "rz": rv[:, 2]})
            return pd.DataFrame({**cols, **c})

        frames = solve_chunks(points.chunks(), table, points.n, "interference", quiet=args.quiet)
        table_io.write_table_chunks(frames, args.out)
        summary = {"out": args.out, "points": count[0], "interference_free_points": count[1]}
        if args.json:
            emit_json(summary, args)
        else:
            print(f"wrote {count[0]} poses to {args.out}; {count[1]} interference-free")
        return
    P, rv = points.first()
    P, rv, L0, extra = _lengths(args, robot, P, rv)
    res = itf.interference(robot, P, rv, L0=None if L0 is None else L0[None])
    out = itf.report(res)
    out.update(extra)
    if args.json:
        emit_json(out, args)
        return
    rot = [0.0, 0.0, 0.0] if rv is None else rv[0].tolist()
    where = list(map(float, args.at)) if "solved" not in extra else extra["solved"]
    print(f"{robot.name} ({robot.pulley_summary()}) at p = {where} m, rotvec {rot} rad")
    if extra.get("lengths_from") == "given":
        print(
            f"  pose           : where the platform settles under --lengths (desired p = {list(map(float, args.at))} m)"
        )
    if "lengths" in extra and robot.heavy:
        how = (
            "--lengths"
            if extra["lengths_from"] == "given"
            else "sag-consistent compensated lengths of the pose"
        )
        print(
            f"  heavy cables   : catenaries under the {how}: "
            + ", ".join(f"{x:.6f}" for x in extra["lengths"])
            + " m"
        )
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
