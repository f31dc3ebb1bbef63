"""The commands: ``cdpr inverse | point | compensate | grid | winch | plane | trajectory | import caspr |
view | study check``.

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
import sys
import time

import numpy as np

from cdpr import io
from cdpr.analyses.workspace import BYTES_PER_POINT
from cdpr.cli import heavy
from cdpr.cli.options import MAX_COORDINATE_M
from cdpr.errors import CdprError
from cdpr.plausibility import plausibility_warnings
from cdpr.robot import load_robot, with_wrench

#: The columns of a ``--points`` table: the position [m] and, optional, the orientation [rad].
POINT_COLUMNS = ("x", "y", "z", "rx", "ry", "rz")


def _write_table(df, path):
    from cdpr import table_io  # lazy: pandas and pyarrow, for the commands that write a table only

    table_io.write_table(df, path)


def checked(robot, args):
    """The one plausibility check of the command line: every command that reads or writes a robot
    passes it here once. Each implausible value (``plausibility.plausibility_warnings``: a unit slip, most
    likely) is one line on stderr; the list goes to ``args.warnings`` for the ``warnings`` key of the
    command's JSON object (``emit_json``). The command still runs: a user may mean the value."""
    warnings = plausibility_warnings(robot)
    for w in warnings:
        print(f"cdpr: warning: {robot.source}: {w}", file=sys.stderr)
    args.warnings = warnings
    return robot


def emit_json(out, args):
    """Print a command's JSON: an object gets the ``warnings`` list of ``checked`` (empty when the
    robot is plausible or the command reads none); a list keeps its shape (its warnings are on
    stderr only)."""
    if isinstance(out, dict):
        if getattr(args, "wrench", None) is not None:  # --wrench given: echoed [N, N m]
            out = {**out, "wrench": [float(x) for x in args.wrench]}
        out = {**out, "warnings": list(getattr(args, "warnings", []))}
    print(json.dumps(io.clean_json(out), indent=2, allow_nan=False))


def _wrench_text(args):
    """``, wrench (FX, ..., MZ) [N, N m]`` for a header line when --wrench is given, else ""."""
    w = getattr(args, "wrench", None)
    return "" if w is None else ", wrench (" + ", ".join(f"{x:g}" for x in w) + ") [N, N m]"


def robot_from_args(args):
    """The robot of --robot with the command line's overrides, checked for plausibility; a
    --redundancy left out becomes the robot's default (``Robot.default_redundancy``: paper mode for
    a point mass on massless cables, physical mode for a rigid platform or heavy cables, their only
    mode)."""
    robot = checked(
        load_robot(
            args.robot,
            E_cables=getattr(args, "E_cables", None),
            pulley=args.pulley,
            h=args.h,
            r_p=args.rp,
            dead_length=args.dead_length,
            E=getattr(args, "E", None),
            mass=getattr(args, "mass", None),
            linear_density=getattr(args, "linear_density", None),
        ),
        args,
    )
    robot = with_wrench(robot, getattr(args, "wrench", None))  # --wrench: beside gravity
    if hasattr(args, "redundancy") and args.redundancy is None:
        args.redundancy = robot.default_redundancy
    return robot


class Points:
    """The points of --at or --points: ``n`` of them, read ``--chunk-rows`` at a time by ``chunks()``.

    ``chunks()`` yields (P (k, 3) [m], rotvec (k, 3) [rad] or None) per chunk: the orientation of the
    table's rx, ry, rz columns, else of --rotvec, else None. --at is one chunk of one point."""

    def __init__(self, args, n, columns=None):
        self.args, self.n, self.columns = args, n, columns
        self.table = args.at is None
        self.has_rot = columns is not None and "rx" in columns

    def chunks(self):
        args = self.args
        if not self.table:
            P = np.array([args.at], dtype=float)
            yield P, _rotvec(args, len(P))
            return
        from cdpr import table_io  # lazy: pandas and pyarrow, for the commands that read a table only

        for df in table_io.iter_table(args.points, self.columns, args.chunk_rows):
            P = df[["x", "y", "z"]].to_numpy(dtype=float)
            if self.has_rot:
                yield P, df[["rx", "ry", "rz"]].to_numpy(dtype=float)
            else:
                yield P, _rotvec(args, len(P))

    def first(self):
        """The first chunk (P, rotvec): all of --at; a table's first ``--chunk-rows`` rows (the
        reader is closed at once: no open file left to the garbage collector)."""
        gen = self.chunks()
        try:
            return next(gen)
        finally:
            gen.close()


def read_points(args):
    """The ``Points`` of --at or --points; refuses non-finite coordinates, a missing --out and an
    orientation given twice (--rotvec and rx, ry, rz columns). A table is checked in one pass over
    its chunks, so that a bad row is refused before any solve (inverse, point, compensate)."""
    if args.at is not None:
        if args.out:
            io.check_output(args.out)
        return Points(args, 1)
    if not args.out:
        raise CdprError("--points needs --out FILE for the result table")
    io.check_output(args.out)
    if str(args.points).endswith(".csv") and os.path.isfile(args.points):
        io.check_csv_rows(args.points, POINT_COLUMNS)  # rows as wide as the header, plain numbers
    from cdpr import table_io  # lazy: pandas and pyarrow, for the commands that read a table only

    try:
        columns = table_io.table_columns(args.points)
    except FileNotFoundError:
        raise CdprError(f"{args.points}: the points file does not exist") from None
    missing = [c for c in "xyz" if c not in columns]
    if missing:
        raise CdprError(
            f"{args.points}: missing column(s) {', '.join(missing)}; a points table needs columns x, y, z [m]"
        )
    present = [c for c in POINT_COLUMNS if c in columns]
    rot = [c for c in ("rx", "ry", "rz") if c in columns]
    n, bad_xyz, far_xyz, bad_rot = 0, None, None, None
    for df in table_io.iter_table(args.points, present, args.chunk_rows):
        for c in present:  # a parquet or CSV column of text (a CSV's cells are checked above)
            if df[c].dtype.kind not in "iuf":
                raise CdprError(f"{args.points}: column {c} holds {df[c].dtype} values; it must hold numbers")
        P = df[["x", "y", "z"]].to_numpy(dtype=float)
        bad = ~np.isfinite(P).all(axis=1)
        if bad_xyz is None and bad.any():
            bad_xyz = n + int(np.flatnonzero(bad)[0]) + 1
        far = (np.abs(P) > MAX_COORDINATE_M).any(axis=1)
        if far_xyz is None and far.any():
            far_xyz = n + int(np.flatnonzero(far)[0]) + 1
        if len(rot) == 3:
            bad = ~np.isfinite(df[["rx", "ry", "rz"]].to_numpy(dtype=float)).all(axis=1)
            if bad_rot is None and bad.any():
                bad_rot = n + int(np.flatnonzero(bad)[0]) + 1
        n += len(df)
    if n == 0:
        raise CdprError(
            f"{args.points}: the table has no rows; a points table needs at least one row of x, y, z [m]"
        )
    if bad_xyz is not None:
        raise CdprError(
            f"{args.points}: row {bad_xyz} has a non-finite coordinate; every x, y, z must be a finite number"
        )
    if far_xyz is not None:
        raise CdprError(
            f"{args.points}: row {far_xyz} has a coordinate beyond ±{MAX_COORDINATE_M:g} m; "
            "a position must be within it"
        )
    if rot:
        if len(rot) != 3:
            raise CdprError(
                f"{args.points}: an orientation needs all three columns rx, ry, rz [rad], got {', '.join(rot)}"
            )
        if getattr(args, "rotvec", None) is not None:  # two orientations: neither may win silently
            raise CdprError(
                f"give the orientation either as --rotvec (or --euler-xyz-deg) or as rx, ry, rz columns of --points ({args.points}), not both"
            )
        if bad_rot is not None:
            raise CdprError(f"{args.points}: row {bad_rot} has a non-finite rx, ry or rz")
    return Points(args, n, present)


def _rotvec(args, n):
    """(N, 3) orientations [rad] of --rotvec; None when not given."""
    if getattr(args, "rotvec", None) is None:
        return None
    return np.tile(np.asarray(args.rotvec, dtype=float), (n, 1))


def write_chunks(args, points, solve, what):
    """Solve ``points`` chunk by chunk with ``solve(P, rotvec)`` (a DataFrame per chunk) and write the
    frames as one table to --out (``table_io.write_table_chunks``: atomic, the bytes of the table
    written at once), with a progress bar and the expected time (``stream.solve_chunks``)."""
    from cdpr import table_io  # lazy: pandas and pyarrow, for the commands that write a table only
    from cdpr.cli.stream import solve_chunks  # lazy: tqdm, for the commands over a table only

    frames = solve_chunks(points.chunks(), solve, points.n, what, quiet=getattr(args, "quiet", False))
    table_io.write_table_chunks(frames, args.out)


def _warm_up(args, solve):
    """``stream.warm_up``: one point through the compiled engine before the timed work, so that a
    cold numba cache's compile is announced on stderr (not with --quiet) and not counted in a rate."""
    from cdpr.cli.stream import warm_up  # lazy: the compiled solver commands only

    return warm_up(solve, quiet=getattr(args, "quiet", False))


def _solve_announced(args, solve):
    """``solve()`` (one pose on the compiled engine: heavy cables take it at one pose) run as
    ``_warm_up``'s call, so that a cold numba cache's compile is announced, and its result kept (the
    pose is solved once)."""
    got = []

    def run():
        got.append(solve())
        return got[-1]

    _warm_up(args, run)
    return got[0]


class Tally:
    """The summary of a table written chunk by chunk: points, status counts, the |dp| range of the
    ok points (what ``_report`` prints)."""

    def __init__(self):
        self.n, self.counts, self.lo, self.hi = 0, None, float("nan"), float("nan")

    def add(self, df):
        """Count the frame ``df`` (columns status and dp); returns it."""
        from cdpr.analyses import scans  # lazy: the solver commands only

        self.n += len(df)
        counts = df["status"].value_counts(sort=False)
        self.counts = counts if self.counts is None else self.counts.add(counts, fill_value=0)
        lo, hi = scans.ok_extremes(df)
        self.lo, self.hi = float(np.fmin(self.lo, lo)), float(np.fmax(self.hi, hi))
        return df

    def status(self):
        """{status: count} of the counted statuses, most frequent first (as ``value_counts``)."""
        counts = self.counts.sort_values(ascending=False, kind="stable")
        return {k: int(v) for k, v in counts.items() if v}


def _rotvec_option(args):
    """``{"rotvec": (3,)}`` for the solvers when --rotvec is given, else nothing."""
    return {} if args.rotvec is None else {"rotvec": np.asarray(args.rotvec, dtype=float)}


def text_table(rows, headers):
    cols = [[h] + [r[i] for r in rows] for i, h in enumerate(headers)]
    widths = [max(len(x) for x in c) for c in cols]
    lines = ["  ".join(x.rjust(w) for x, w in zip(r, widths)) for r in [headers] + rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _solve_sensitivities(robot, P, args, L0=None, rv=None, engine=None):
    """The solve plus the sensitivities for --sensitivities by ``engine`` (``solve.sensitivities``):
    dP*/dθ on a suspended point mass and, in paper mode, on any point mass (an orientation plays no
    part there and is carried through), dp*/dθ and dφ*/dθ on any other robot."""
    from cdpr.solve import sensitivities  # lazy: --sensitivities only

    if args.method != "newton":
        raise CdprError(
            "--sensitivities needs --method newton (the implicit-function theorem uses its Jacobian at the solution)"
        )
    return sensitivities(
        robot,
        P,
        None if robot.suspended_point_mass else rv,
        redundancy=args.redundancy,
        L=L0,
        engine=engine,
        threads=args.threads,
    )


#: A commanded rest length at or below this [m] is a zero-length cable: no stiffness ES/L0 exists.
ZERO_LENGTH_M = 1e-9


def _zero_length(robot, P, rv, L0, redundancy):
    """(N, m) mask of the cables whose commanded rest length is zero in physical mode (L0, or the
    standard length L_TS at the desired pose: an attachment at its anchor with no dead length); the
    physical model has no stiffness ES/L0 there, and the point is flagged with this reason."""
    from cdpr.models.inverse import L_TS  # lazy: the physical-mode check only

    if redundancy != "physical":
        return np.zeros((len(P), robot.m), dtype=bool)
    if L0 is None:
        L0 = L_TS(robot, P, rv)
    return np.broadcast_to(np.asarray(L0, dtype=float) <= ZERO_LENGTH_M, (len(P), robot.m))


def _zero_segment(robot, P, rv):
    """(N, m) mask of the cables of zero length |B_i - A_i| at the desired poses (the attachment at
    its anchor): the cable has no direction there, so no tension distribution exists (``compensate``,
    ``grid --wrench-feasible``; ``tension_distribution.defined_rows`` makes such a point infeasible)."""
    from cdpr.models.inverse import l_S  # lazy: the zero-length check only

    return np.asarray(l_S(robot, P, rv), dtype=float).reshape(len(P), robot.m) <= ZERO_LENGTH_M


def _zero_length_reason(zero_row, what="rest length"):
    """The reason of a point with zero-length cables (one row of ``_zero_length``, or with ``what``
    "length" of ``_zero_segment``), or None."""
    cables = [int(i) + 1 for i in np.flatnonzero(zero_row)]
    if not cables:
        return None
    which = ", ".join(map(str, cables))
    has = f"cable{'s' * (len(cables) > 1)} {which} {'has' if len(cables) == 1 else 'have'} zero {what}"
    if what != "rest length":
        return f"{has} (the attachment at its anchor): its direction does not exist, no tension distribution"
    return f"{has} (the attachment at its anchor, no dead length): its stiffness ES/L0 does not exist, no equilibrium"


def _zero_length_note(n, what="rest length", status="status as solved (not ok)"):
    """One stderr line for the ``n`` points of a table that have a cable of zero length (nothing
    when none): the table's statuses say not ok, this line says why."""
    if n:
        print(
            f"cdpr: note: {n} point(s) have a cable of zero {what} (the attachment at its anchor): "
            f"no {'equilibrium' if what == 'rest length' else 'tension distribution'} exists there, {status}",
            file=sys.stderr,
        )


def cmd_point(args):
    """One pose (--at) or a table of poses (--points): the solved pose, tensions and status. Without
    --engine, fewer than ``solve.ONE_SHOT_POSES`` poses are answered by the numpy reference (the
    compiled engine's load would be most of the process), more by the compiled engine; heavy cables
    by the compiled engine (``heavy.one_shot``)."""
    from cdpr.models.interference import interference_free  # lazy: the solver commands only
    from cdpr.solve import check_engine  # lazy: the solvers, for the solver commands only
    from cdpr.solve import solve as solve_poses  # lazy: the solvers, for the solver commands only

    robot = robot_from_args(args)
    points = read_points(args)
    engine = check_engine(args.engine, args.method, one_shot=heavy.one_shot(robot, points.n))
    if robot.heavy and args.sensitivities and args.engine is None:
        engine = "numpy"  # heavy sensitivities: the numpy reference whatever the engine (solve.sensitivities)
    L0 = None
    given = [
        o
        for o, v in (("--lengths", args.lengths), ("--q", args.q), ("--motor-deg", args.motor_deg))
        if v is not None
    ]
    if len(given) > 1:
        raise CdprError(
            f"give the commanded cables one way: rest lengths --lengths, drum angles --q or motor angles --motor-deg, not {' and '.join(given)}"
        )
    if args.lengths is not None:
        if len(args.lengths) != robot.m:
            raise CdprError(f"--lengths needs one rest length per cable ({robot.m}), got {len(args.lengths)}")
        L0 = np.array(args.lengths, dtype=float)
    if args.q is not None:
        from cdpr.models.drive import rest_lengths_from_angles  # lazy: --q only

        if len(args.q) != robot.m:
            raise CdprError(f"--q needs one drum angle per cable ({robot.m}), got {len(args.q)}")
        L0 = rest_lengths_from_angles(robot, np.array([args.q]), model="winch")[0]
    if args.motor_deg is not None:
        from cdpr.models.drive import spool_rest_lengths  # lazy: --motor-deg only

        if len(args.motor_deg) != robot.m:
            raise CdprError(
                f"--motor-deg needs one motor angle per cable ({robot.m}), got {len(args.motor_deg)}"
            )
        L0 = spool_rest_lengths(robot, np.array([args.motor_deg]))[0]
        if not np.isfinite(L0).all():
            bad = [i + 1 for i in np.flatnonzero(~np.isfinite(L0))]
            raise CdprError(
                f"--motor-deg: the spools of cables {bad} cannot pay out that much line (the spool would be empty)"
            )
    if args.sensitivities:
        if L0 is not None and args.redundancy != "physical":
            raise CdprError(
                "commanded lengths need physical mode (--redundancy physical); paper mode commands L_TS at the desired point"
            )

    def solve(P, rv):
        if args.sensitivities:
            return _solve_sensitivities(robot, P, args, L0, rv, engine)
        return solve_poses(
            robot,
            P,
            method=args.method,
            engine=engine,
            threads=args.threads,
            redundancy=args.redundancy,
            L0=L0,
            rotvec=rv,
        )

    if args.points or args.out:
        from cdpr.analyses.interference import add_interference  # lazy: a table of points only (pandas)
        from cdpr.cli import reached  # lazy: a table of points only
        from cdpr.tables import to_frame  # lazy: a table of points only (pandas)

        tally = Tally()
        if engine == "compiled":
            P, rv = points.first()
            _warm_up(args, lambda: solve(P[:1], None if rv is None else rv[:1]))
        n_zero = [0]

        def chunk(P, rv):
            n_zero[0] += int(_zero_length(robot, P, rv, L0, args.redundancy).any(axis=1).sum())
            res = reached.table_answer(robot, args, solve(P, rv), engine)  # issue 39
            df = to_frame(robot, res, args.redundancy, rotvec=rv)
            # a rigid platform's interference columns at the solved poses (docs/interference.md)
            return tally.add(add_interference(robot, df, L0=res.get("L0", L0)))

        write_chunks(args, points, chunk, "point")
        _report(tally, args.out, args, float("nan"))
        _zero_length_note(n_zero[0])
        return
    P, rv = points.first()
    zero = _zero_length(robot, P, rv, L0, args.redundancy)
    res = _solve_announced(args, lambda: solve(P, rv)) if engine == "compiled" else solve(P, rv)
    two = None
    if args.redundancy == "physical" and not zero.any():  # issue 39: reached
        from cdpr.cli import reached  # lazy: physical mode at one pose only

        res_reached = reached.reach_point(robot, args, P, rv, L0, engine)
        two = reached.both(robot, res_reached, res, rigid="rotvec_s" in res)
        if args.equilibrium == "reached" and not (args.sensitivities and two["reached_is_global"]):
            # (--sensitivities where the two are one equilibrium: the solve's pose they are taken at)
            res = reached.answer(res, res_reached)
            if args.sensitivities:  # dP*/dθ where the robot is
                res = reached.with_sensitivities(robot, res, res_reached, [0], engine, args.threads)
    t = res["t"][0]
    out = {
        "desired": list(map(float, args.at)),
        "solved": res["P_s"][0].tolist(),
        "dp_norm": float(res["dp"][0]),
        "tensions": [None if np.isnan(v) else float(v) for v in t],
    }
    if "rotvec_s" in res or rv is not None:
        out["solved_rotvec"] = (res["rotvec_s"][0] if "rotvec_s" in res else rv[0]).tolist()
        out["dphi"] = float(res["dphi"][0]) if "dphi" in res else 0.0
    heavy.point_json(out, res)  # heavy cables: tensions at the exit points D and sags
    if args.redundancy == "physical":
        out["taut"] = [int(i) + 1 for i in np.flatnonzero(res["taut"][0])]
    else:
        out["subset"] = [int(i) + 1 for i in res["subset"][0] if i >= 0]
    out.update(status=str(res["status"][0]), iterations=int(res["iterations"][0]), engine=engine)
    out["interference_free"] = interference_free(
        robot, out["solved"], out.get("solved_rotvec"), L0=res["L0"][0] if "L0" in res else L0
    )
    if "unique" in res:
        out.update(unique=bool(res["unique"][0]), alternatives=res["alternatives"][0])
    if two is not None:
        out.update(equilibrium=args.equilibrium, **two)
    reason = _zero_length_reason(zero[0])
    if reason is not None:  # no equilibrium model there: no uniqueness to claim either
        out["reason"] = reason
        if "unique" in out:
            out.update(unique=None, alternatives=[])
    if args.sensitivities:
        S = res["S"][0]
        out["sensitivities"] = {
            name: [None if np.isnan(v) else float(v) for v in S[:3, k]] for k, name in enumerate(res["names"])
        }
        if len(S) == 6:  # a rigid platform: dφ*/dθ, base-frame rotation vector [rad per unit]
            out["sensitivities_phi"] = {
                name: [None if np.isnan(v) else float(v) for v in S[3:, k]]
                for k, name in enumerate(res["names"])
            }
        out["sensitivities_smooth"] = bool(res["smooth"][0])
    if args.json:
        emit_json(out, args)
        return
    from cdpr.models.results import subset_label  # lazy: the readable output only

    mode = "physical equilibrium" if args.redundancy == "physical" else f"paper mode, solver {args.method}"
    print(
        f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}, {robot.dead_length_summary()}), {mode}"
        f"{_wrench_text(args)}"
    )
    fmt = lambda v: "(" + ", ".join("nan" if v is None or v != v else f"{x:.6f}" for x in v) + ")"  # noqa: E731
    print(f"  desired P  [m] : {fmt(out['desired'])}")
    print(f"  solved P*  [m] : {fmt(out['solved'])}")
    print(f"  |dp|       [m] : {out['dp_norm']:.6f}")
    if "dphi" in out:
        print(f"  rotvec*  [rad] : {fmt(out['solved_rotvec'])}   dphi [rad]: {out['dphi']:.6g}")
    print("  tensions   [N] : " + ", ".join("slack" if v is None else f"{v:.2f}" for v in out["tensions"]))
    heavy.point_text(out)
    if args.redundancy == "physical":
        print(f"  taut cables    : {'-'.join(map(str, out['taut'])) or '-'}")
        if two is not None:  # the reached equilibrium and the global one (issue 39)
            from cdpr.cli.reached import text  # lazy: physical mode at one pose only

            print(f"  answer         : the {args.equilibrium} equilibrium")
            print("\n".join(text(out)))
    else:
        print(f"  subset         : {subset_label(res['subset'][0]) or '-'}")
    print(f"  status         : {out['status']}  ({out['iterations']} iterations)")
    if "reason" in out:
        print(f"  reason         : {out['reason']}")
    if out.get("unique") is False:  # another equilibrium holds the same lengths (equilibrium: restarts)
        n = len(out["alternatives"])
        print(f"  equilibrium    : not unique ({n} alternative{'s' * (n != 1)}; --json lists them)")
    if args.sensitivities:
        num = lambda v: "nan" if v is None else f"{v:.6g}"  # noqa: E731
        smooth = (
            "" if out["sensitivities_smooth"] else " (not smooth here: the subset or taut set may switch)"
        )
        if "sensitivities_phi" in out:
            from cdpr.parameters import parameter_units  # lazy: --sensitivities only

            rows = [
                [name, f"m/{unit}"]
                + [num(v) for v in vec]
                + [f"rad/{unit}"]
                + [num(v) for v in out["sensitivities_phi"][name]]
                for (name, vec), unit in zip(out["sensitivities"].items(), parameter_units(robot, rigid=True))
            ]
            smooth = smooth.replace("subset or taut set may switch", "taut set may switch or J is singular")
            label = "numpy reference" if engine == "numpy" else "compiled engine"
            print(f"sensitivities dp*/dθ and dφ*/dθ at fixed commanded lengths ({label}){smooth}:")
            headers = ["θ", "unit", "dx", "dy", "dz", "unit", "dφx", "dφy", "dφz"]
            print(text_table(rows, headers))
            return
        from cdpr.parameters import parameter_units  # lazy: --sensitivities only

        units = parameter_units(robot, rigid=False)
        rows = [
            [name, f"m/{unit}"] + [num(v) for v in vec]
            for (name, vec), unit in zip(out["sensitivities"].items(), units)
        ]
        print(f"sensitivities dP*/dθ at fixed commanded lengths{smooth}:")
        print(text_table(rows, ["θ", "unit", "dx", "dy", "dz"]))


def cmd_compensate(args):
    """Compensated rest lengths (inverse elasto-geometric model) and, as a check, the pose the
    platform takes when they are commanded (to the same robot, or to one with --actual-E-cables).
    The engine's default is ``point``'s (``solve.check_engine`` with ``heavy.one_shot``)."""
    import dataclasses  # lazy: --actual-E-cables only

    from cdpr.analyses.compensation import at_poses, compensated_pose  # lazy: this command only
    from cdpr.models.interference import interference_free  # lazy: this command only
    from cdpr.solve import check_engine  # lazy: the solvers, for the solver commands only

    robot = robot_from_args(args)
    points = read_points(args)
    engine = check_engine(args.engine, "newton", one_shot=heavy.one_shot(robot, points.n))
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
    P, rv = points.first()
    six = at_poses(robot, P, rv)  # a rigid platform or --rotvec: the 6-DoF compensation
    if six and args.distribution == "subset":
        raise CdprError(
            "--distribution subset (the paper's 3-cable subset) is not available at a pose (rigid platform or "
            "--rotvec); use min_norm, closed_form or closed_form_improved"
        )

    def solve(P, rv):
        # a pose with no tension distribution is infeasible and not solved (its solved columns are empty)
        return compensated_pose(
            robot,
            P,
            actual=actual,
            method=args.distribution,
            engine=engine,
            t_min=args.t_min,
            t_max=t_max,
            rotvec=rv,
            threads=args.threads,
        )

    if args.points or args.out:
        from cdpr.analyses.interference import add_interference  # lazy: tables only (pandas)
        from cdpr.tables import to_frame  # lazy: tables only (pandas)

        def table(P, rv):
            n_zero[0] += int(_zero_segment(robot, P, rv).any(axis=1).sum())
            res = solve(P, rv)
            # at a pose (``six``) the orientation columns, a point mass's too
            df = to_frame(robot, res, "physical", res["rotvec"] if six else None)
            for i in range(robot.m):
                df[f"L0_{i + 1}"] = res["L0"][:, i]
            for i in range(robot.m):
                df[f"t_planned{i + 1}"] = res["t_planned"][:, i]
            # a rigid platform's interference columns at the solved poses (the robot they were
            # solved on, under the compensated lengths: docs/interference.md)
            return tally.add(add_interference(robot if actual is None else actual, df, L0=res["L0"]))

        tally = Tally()
        n_zero = [0]
        if engine == "compiled":
            _warm_up(args, lambda: solve(P[:1], None if rv is None else rv[:1]))
        write_chunks(args, points, table, "compensate")
        _zero_length_note(n_zero[0], "length", "status infeasible")
        if six:
            n_bad = tally.status().get("infeasible", 0)
            print(f"wrote {tally.n} poses to {args.out}; {n_bad} infeasible (no tension distribution)")
        else:
            _report(tally, args.out, args, float("nan"))
        return
    res = _solve_announced(args, lambda: solve(P, rv)) if engine == "compiled" else solve(P, rv)
    # at the desired pose (heavy cables: the planned catenaries, under the compensated lengths)
    free = interference_free(robot, args.at, None if rv is None else rv[0], L0=res["L0"][0])
    reason = _zero_length_reason(_zero_segment(robot, P, rv)[0], "length")
    if six:
        return _compensate_pose_report(args, robot, res, engine, free, reason)
    status = str(res["status"][0])
    out = {
        "desired": list(map(float, args.at)),
        "lengths": res["L0"][0].tolist(),
        "tensions": res["t_planned"][0].tolist(),
        "status": status,
        "solved": res["P_s"][0].tolist(),
        "dp_norm": float(res["dp"][0]),
        "engine": engine,
        "interference_free": free,
    }
    if reason is not None:
        out["reason"] = reason
    heavy.compensate_json(out, res)
    if all(w is not None for w in robot.winches):
        from cdpr.models.drive import drum_angles  # lazy: robots with winches only

        q, q_nw = drum_angles(robot, res["L0"][:1])
        out["q"], out["q_no_winch"] = q[0].tolist(), q_nw[0].tolist()
    if any(p is not None for p in robot.spools):
        from cdpr.models.drive import spool_motor_angles  # lazy: robots with spools only

        out["motor_deg"] = spool_motor_angles(robot, res["L0"][:1])[0].tolist()
    if args.json:
        emit_json(out, args)
        return
    print(
        f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}, {robot.dead_length_summary()}), distribution {args.distribution}{_wrench_text(args)}"
    )
    if status == "infeasible":
        print(INFEASIBLE_LINE)
        if reason is not None:
            print(f"reason: {reason}")
        return
    rows = [
        [str(i + 1), f"{L:.6f}", f"{t:.2f}"] for i, (L, t) in enumerate(zip(out["lengths"], out["tensions"]))
    ]
    headers = ["cable", "rest length L0 [m]", "planned tension [N]"]
    rows, headers = heavy.compensate_columns(out, rows, headers)
    if "q" in out:
        rows = [r + [f"{a:.6f}", f"{b:.6f}"] for r, a, b in zip(rows, out["q"], out["q_no_winch"])]
        headers += ["drum angle q [rad]", "q neglecting the winch [rad]"]
    if "motor_deg" in out:
        rows = [r + [f"{a:.2f}"] for r, a in zip(rows, out["motor_deg"])]
        headers += ["motor angle [deg] (spool)"]
    print(text_table(rows, headers))
    check = "the robot with --actual-E-cables" if actual is not None else "the same robot"
    print(
        f"status: {status}; commanded to {check}, the platform settles {out['dp_norm']:.3g} m from the desired point"
    )


#: The text report of ``compensate --at`` where no tension distribution exists (nothing is solved).
INFEASIBLE_LINE = (
    "status: infeasible (no tension distribution within the bounds holds the platform at this pose)"
)


def _compensate_pose_report(args, robot, res, engine, free, reason=None):
    """``compensate --at`` at a pose (rigid platform or --rotvec): the JSON or the text of the one
    pose of ``res`` (``compensation.compensated_pose``) and ``free``, its interference_free; ``reason``
    (a zero-length cable) added when given."""
    ok = res["status"][0] != "infeasible"
    out = {
        "desired": list(map(float, args.at)),
        "rotvec": res["rotvec"][0].tolist(),
        "lengths": res["L0"][0].tolist(),
        "tensions": res["t_planned"][0].tolist(),
        "status": str(res["status"][0]),
        "solved": res["P_s"][0].tolist() if ok else None,
        "solved_rotvec": res["rotvec_s"][0].tolist() if ok else None,
        "dp_norm": float(res["dp"][0]) if ok else None,
        "dphi": float(res["dphi"][0]) if ok else None,
        "engine": engine,
        "interference_free": free,
    }
    if reason is not None:
        out["reason"] = reason
    heavy.compensate_json(out, res)
    if ok and any(p is not None for p in robot.spools):
        from cdpr.models.drive import spool_motor_angles  # lazy: robots with spools only

        out["motor_deg"] = spool_motor_angles(robot, res["L0"][:1])[0].tolist()
    if args.json:
        emit_json(out, args)
        return
    print(
        f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}), distribution {args.distribution} at a pose{_wrench_text(args)}"
    )
    if not ok:
        print(INFEASIBLE_LINE)
        if reason is not None:
            print(f"reason: {reason}")
        return
    rows = [
        [str(i + 1), f"{L:.6f}", f"{t:.2f}"] for i, (L, t) in enumerate(zip(out["lengths"], out["tensions"]))
    ]
    headers = ["cable", "rest length L0 [m]", "planned tension [N]"]
    rows, headers = heavy.compensate_columns(out, rows, headers)
    if "motor_deg" in out:
        rows = [r + [f"{a:.2f}"] for r, a in zip(rows, out["motor_deg"])]
        headers += ["motor angle [deg] (spool)"]
    print(text_table(rows, headers))
    print(
        f"status: {out['status']}; the platform settles {out['dp_norm']:.3g} m and {out['dphi']:.3g} rad from the pose"
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
    from cdpr.analyses.interference import desired_columns
    from cdpr.analyses.workspace import check_box, frame_box, grid_points, read_box, shard_range
    from cdpr.solve import check_engine
    from cdpr.tables import solve_table

    robot = robot_from_args(args)
    io.check_output(args.out)
    if args.box_file:
        box = read_box(args.box_file)
    elif args.frame:
        box = check_box(frame_box(robot))
    elif args.box:
        box = check_box(args.box)
    else:
        raise CdprError("give the grid box with --box, --box-file or --frame")
    start, stop = shard_range(args.n**3, args.shard, args.shards)
    _check_size(stop - start, f"--n {args.n}")
    P = grid_points(box, args.n, start, stop)
    rv = None if args.rotvec is None else np.asarray(args.rotvec, dtype=float)

    def solve(P):
        if args.sensitivities:
            from cdpr.tables import to_frame  # lazy: --sensitivities only

            res = _solve_sensitivities(robot, P, args, rv=rv, engine=args.engine)
            return to_frame(robot, res, args.redundancy, rotvec=rv)
        return solve_table(
            robot,
            P,
            method=args.method,
            engine=args.engine,
            threads=args.threads,
            redundancy=args.redundancy,
            **_rotvec_option(args),
        )

    if len(P) and check_engine(args.engine, args.method) == "compiled":
        # numba loads (or, with a cold cache, compiles: announced) its kernels here, outside the rate
        _warm_up(args, lambda: solve(P[:1]))
    t0 = time.perf_counter()
    df = solve(P)
    extra = {}
    _zero_length_note(int(_zero_length(robot, P, rv, None, args.redundancy).any(axis=1).sum()))
    if args.wrench_feasible:
        _zero_length_note(int(_zero_segment(robot, P, rv).any(axis=1).sum()), "length", "not wrench-feasible")
        df["feasible"] = heavy.feasible(robot, P, args.rotvec, args.t_min)  # heavy: sag-consistent
        extra = _wrench_feasible_summary(df, box, args)
    if args.interference:  # the interference columns at the grid's poses (docs/interference.md;
        # heavy cables: under the sag-consistent compensated lengths of each pose)
        df = df.assign(**desired_columns(robot, P, rv))
        extra["interference_free_points"] = int(df["interference_free"].sum())
        if not args.json:
            print(f"interference-free: {extra['interference_free_points']} of {len(df)} grid points")
    _write_table(df, args.out)
    dt = time.perf_counter() - t0
    _report(df, args.out, args, dt, extra)


def _wrench_feasible_summary(df, box, args):
    """--wrench-feasible: the feasible points' volume and, on a whole grid, the largest axis-aligned
    box of points both ok and feasible (``workspace.largest_box_in``); printed, or returned for --json."""
    from cdpr.analyses.workspace import largest_box_in  # lazy: --wrench-feasible only

    cell = np.prod([(box[2 * k + 1] - box[2 * k]) / args.n for k in range(3)])
    out = {
        "wrench_feasible_points": int(df["feasible"].sum()),
        "wrench_feasible_m3": float(df["feasible"].sum() * cell),
    }
    lines = [
        f"wrench-feasible: {out['wrench_feasible_points']} of {len(df)} grid points, {out['wrench_feasible_m3']:.4g} m^3"
    ]
    if args.shards == 1:
        wf = largest_box_in(df, args.n, box, df["feasible"].to_numpy(dtype=bool))
        out["wrench_feasible_box_m3"] = wf["volume_m3"]
        for k, name in enumerate(("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")):
            out[f"wf_box_{name}_m"] = None if wf["box"] is None else wf["box"][k]
        if wf["box"] is None:
            lines.append("largest wrench-feasible box: none (no grid point is both ok and wrench-feasible)")
        else:
            b = wf["box"]
            lines.append(
                f"largest wrench-feasible box: x [{b[0]:.4g}, {b[1]:.4g}] y [{b[2]:.4g}, {b[3]:.4g}] "
                f"z [{b[4]:.4g}, {b[5]:.4g}] m, {wf['volume_m3']:.4g} m^3 ({wf['count']} grid points, ok and feasible)"
            )
    else:
        lines.append(
            "largest wrench-feasible box: needs the whole grid (--shards 1); not computed for a shard"
        )
    if not args.json:
        print("\n".join(lines))
    return out


def _report(df, out, args, dt, extra=None):
    """What a solver command wrote: points, time, statuses and the |dp| range of the ok points (and
    ``extra`` keys in the JSON, e.g. the wrench-feasible volume and box of ``grid``). ``df``: the
    table, or the ``Tally`` of a table written in chunks."""
    if isinstance(df, Tally):
        tally = df
    else:
        tally = Tally()
        tally.add(df)
    counts = tally.status()
    lo, hi = tally.lo, tally.hi
    n = tally.n
    rate = n / dt if dt > 0 else None
    summary = {
        "out": out,
        "points": int(n),
        "seconds": dt,
        "points_per_second": rate,
        "status": counts,
        "dp_min": lo,
        "dp_max": hi,
        **(extra or {}),
    }
    if args.json:
        emit_json(summary, args)
    else:
        timing = f" in {dt:.2f} s ({rate:.0f} points/s)" if rate else ""
        print(f"wrote {n} points to {out}{timing}{_wrench_text(args)}")
        dp = f"min {lo:.6f} m, max {hi:.6f} m" if np.isfinite(lo) else "none (no point is ok)"
        print("status: " + ", ".join(f"{k} {v}" for k, v in counts.items()) + f"; |dp| over ok points: {dp}")


def cmd_plane(args):
    # lazy: this command only
    from cdpr.analyses import scans
    from cdpr.analyses.workspace import frame_box

    robot = robot_from_args(args)
    io.check_output(args.out)
    top = float(robot.A[:, 2].min())
    if not robot.suspended_point_mass:
        lo, hi = frame_box(robot)[4:]
        if not lo <= args.z <= hi:
            raise CdprError(
                f"--z must lie within the frame's height ({lo:g} <= z <= {hi:g} m), got {args.z:g}"
            )
    elif not robot.floor_z <= args.z < top:
        raise CdprError(
            f"--z must lie between the floor and the lowest pulley ({robot.floor_z:g} <= z < {top:g} m), got {args.z:g}"
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
        **_rotvec_option(args),
    )
    _write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)
    P, rv = (
        df[["x", "y", "z"]].to_numpy(),
        None if args.rotvec is None else np.asarray(args.rotvec, dtype=float),
    )
    _zero_length_note(int(_zero_length(robot, P, rv, None, args.redundancy).any(axis=1).sum()))


def cmd_trajectory(args):
    from cdpr.analyses import scans  # lazy: this command only

    robot = robot_from_args(args)
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
        **_rotvec_option(args),
    )
    _write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)
