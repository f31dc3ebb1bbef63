"""Command line: ``cdpr inverse | point | grid | plane | trajectory | winch | job`` (also ``python -m cdpr``).

JSON with ``--json``, a readable table without. Options given on the command line override the
robot file exactly as if it had been edited. SI units throughout. Every bad input is refused with
one sentence on stderr and exit code 2, before any work starts.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import time

import numpy as np

from cdpr import io
from cdpr.analyses import scans
from cdpr.analyses.workspace import check_box, frame_box, grid_points, shard_range
from cdpr.errors import CdprError
from cdpr.models import winch
from cdpr.robot import PULLEY_KINDS, load_robot

#: Bytes of memory per grid point while solving and writing (measured peak RSS / points, rounded up).
BYTES_PER_POINT = 600
#: Largest winch table a command writes.
MAX_STEPS = 10_000_000
#: A number, also in exponent notation and negative ("-1e-1"): argparse must not take it for an option.
_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-inf(inity)?$", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``cdpr: error: ...``, exit 2) and negative numbers in exponent
    notation read as numbers."""

    def __init__(self, *a, **k):
        super().__init__(*a, **k)
        self._negative_number_matcher = _NUMBER

    def error(self, message):
        self.exit(2, f"cdpr: error: {self.prog.removeprefix('cdpr ')}: {message}\n")


def finite(text):
    """argparse type: a finite float."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return v


def positive(text):
    """argparse type: a finite float > 0."""
    v = finite(text)
    if v <= 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be > 0")
    return v


def non_negative(text):
    """argparse type: a finite float >= 0."""
    v = finite(text)
    if v < 0:
        raise argparse.ArgumentTypeError(f"{text!r} must be >= 0")
    return v


def count(low, high=None):
    """argparse type: an integer in [low, high]."""

    def parse(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if v < low or (high is not None and v > high):
            raise argparse.ArgumentTypeError(
                f"{v} is outside the allowed range [{low}, {high if high is not None else 'inf'}]"
            )
        return v

    return parse


def _threads(text):
    return count(1, os.cpu_count() or 1)(text)


def _robot_options(sp):
    sp.add_argument("--robot", required=True, metavar="FILE", help="robot YAML file (config/robots/*.yaml)")
    sp.add_argument("--pulley", choices=PULLEY_KINDS, help="pulley kind for every cable")
    sp.add_argument("--h", type=non_negative, metavar="M", help="lever arm h [m] for every cable")
    sp.add_argument("--rp", type=non_negative, metavar="M", help="sheave radius r_p [m] for every cable")
    sp.add_argument("--dead-length", type=non_negative, metavar="M", help="dead length d [m] for every cable")
    sp.add_argument("--json", action="store_true", help="print JSON")


def _solver_options(sp):
    sp.add_argument("--E", type=positive, metavar="PA", help="Young's modulus E [Pa] of every cable")
    sp.add_argument("--mass", type=positive, metavar="KG", help="platform mass M [kg]")
    sp.add_argument(
        "--method", choices=("newton", "fixed_point"), default="newton", help="DEGM_E solver (default newton)"
    )
    sp.add_argument(
        "--engine",
        choices=("compiled", "numpy"),
        default=None,
        help="compiled numba kernel (default for newton; Newton only) or the numpy reference (default for fixed_point)",
    )
    sp.add_argument(
        "--threads",
        type=_threads,
        help="threads of the compiled engine (1 to the number of cores; default: all)",
    )


def _physics_options(sp):
    sp.add_argument(
        "--redundancy",
        choices=("paper", "physical"),
        default="paper",
        help="paper: the best admissible 3-cable subset (the paper's rule, default); physical: the platform settles where "
        "the forces of all cables balance, each free to go slack",
    )
    sp.add_argument(
        "--E-cables",
        nargs="+",
        type=positive,
        metavar="PA",
        help="Young's modulus of each cable [Pa], cable 1 first",
    )


def _rotvec_argument(sp):
    sp.add_argument(
        "--rotvec",
        nargs=3,
        type=finite,
        metavar=("RX", "RY", "RZ"),
        help="platform orientation: rotation vector [rad] (active, base frame; default identity)",
    )


def _points_options(sp, what):
    g = sp.add_mutually_exclusive_group(required=True)
    g.add_argument("--at", nargs=3, type=finite, metavar=("X", "Y", "Z"), help=f"{what} [m]")
    g.add_argument(
        "--points",
        metavar="FILE",
        help="many points at once: a .csv or .parquet table with columns x, y, z [m] (and rx, ry, rz [rad])",
    )
    sp.add_argument(
        "--out", metavar="FILE", help="write the result table (.csv or .parquet); needed with --points"
    )
    sp.add_argument(
        "--rotvec",
        nargs=3,
        type=finite,
        metavar=("RX", "RY", "RZ"),
        help="platform orientation: rotation vector [rad] (active, base frame; default identity)",
    )


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
    try:
        df = io.read_table(args.points)
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
    rot = [c for c in ("rx", "ry", "rz") if c in df.columns]
    if rot:
        if len(rot) != 3:
            raise CdprError(
                f"{args.points}: an orientation needs all three columns rx, ry, rz [rad], got {', '.join(rot)}"
            )
        rv = df[["rx", "ry", "rz"]].to_numpy(dtype=float)
        bad = ~np.isfinite(rv).all(axis=1)
        if bad.any():
            raise CdprError(
                f"{args.points}: row {int(np.flatnonzero(bad)[0]) + 1} has a non-finite rx, ry or rz"
            )
        args.table_rotvec = rv
    return P


def _rotvec(args, n):
    """(N, 3) orientations [rad] of --rotvec or the points table's rx, ry, rz; None when neither."""
    table = getattr(args, "table_rotvec", None)
    if table is not None:
        return table
    if getattr(args, "rotvec", None) is None:
        return None
    return np.tile(np.asarray(args.rotvec, dtype=float), (n, 1))


def _table(rows, headers):
    cols = [[h] + [r[i] for r in rows] for i, h in enumerate(headers)]
    widths = [max(len(x) for x in c) for c in cols]
    lines = ["  ".join(x.rjust(w) for x, w in zip(r, widths)) for r in [headers] + rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _vec(v):
    return "(" + ", ".join(f"{x:.4f}" for x in v) + ")"


def cmd_inverse(args):
    from cdpr.models.inverse import L_TS, igm_e
    from cdpr.models.pulleys import swivel

    robot = _load(args)
    P = _points(args)
    rv = _rotvec(args, len(P))
    if robot.point_mass:
        st = igm_e(robot, P)
        lts = L_TS(robot, P)
        B = np.repeat(P[:, None, :], robot.m, axis=1)
    else:
        from cdpr.models.equilibrium6 import L_TS_pose, pose_arrays, pose_state

        p_, R = pose_arrays(robot, P, rv)
        B, st = pose_state(robot, p_, R)
        lts = L_TS_pose(robot, p_, R)
    a = robot.arrays
    sw = swivel(B, a.A, None if robot.suspended_point_mass else a.frame, a.inward, per_cable=True)
    over = st.gamma > 1.5 * np.pi
    if args.points or args.out:
        import pandas as pd

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
            if not robot.suspended_point_mass:
                cols.update({f"swivel{c}": sw[:, i], f"wrap_over_270{c}": over[:, i]})
        df = pd.DataFrame(cols)
        io.write_table(df, args.out)
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
            "swivel": float(sw[0, i]),
            "wrap": float(st.gamma[0, i]),
            "wrap_over_270": bool(over[0, i]),
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


def _sensitivity_options(sp):
    sp.add_argument(
        "--sensitivities",
        action="store_true",
        help="also dP*/dθ for every parameter (E_i [Pa], h_i, r_p_i, d_i, A_i_x/y/z [m], M [kg]; cables from 1) "
        "at fixed commanded lengths, by the implicit-function theorem; Newton only",
    )


def _solve_sensitivities(robot, P, args, L0=None):
    """The solve plus dP*/dθ (``sensitivity.sensitivities``) for --sensitivities."""
    from cdpr.models.sensitivity import sensitivities

    if not robot.suspended_point_mass or getattr(args, "rotvec", None) is not None:
        raise CdprError(
            "--sensitivities is not available yet for a rigid platform or an orientation (--rotvec); "
            "the library has cdpr.models.sensitivity6.spatial_sensitivities"
        )
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


def _with_sensitivities(df, res):
    """The point table with the sensitivity columns (dx_dE_1, ..., dz_dM) and ``smooth`` appended."""
    import pandas as pd

    from cdpr.models.sensitivity import sensitivity_frame

    return pd.concat([df, sensitivity_frame(res)], axis=1)


def cmd_point(args):
    from cdpr.solve import results_frame, solve_points_any

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
        from cdpr.models.drive import rest_lengths_from_angles

        if len(args.q) != robot.m:
            raise CdprError(f"--q needs one drum angle per cable ({robot.m}), got {len(args.q)}")
        L0 = rest_lengths_from_angles(robot, np.array([args.q]), model="winch")[0]
    rv = _rotvec(args, len(P))
    if args.sensitivities and (rv is not None or not robot.suspended_point_mass):
        raise CdprError(
            "--sensitivities is not available yet for a rigid platform or an orientation (--rotvec)"
        )
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
            rotvec=rv,
        )
    if args.points or args.out:
        df = results_frame(robot, res, args.redundancy)
        if args.sensitivities:
            df = _with_sensitivities(df, res)
        io.write_table(df, args.out)
        _report(df, args.out, args, float("nan"))
        return
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
    if args.redundancy == "physical":
        out["taut"] = [int(i) + 1 for i in np.flatnonzero(res["taut"][0])]
    else:
        out["subset"] = [int(i) + 1 for i in res["subset"][0] if i >= 0]
    out.update(status=str(res["status"][0]), iterations=int(res["iterations"][0]))
    if "unique" in res:
        out.update(unique=bool(res["unique"][0]), alternatives=res["alternatives"][0])
    if args.sensitivities:
        S = res["S"][0]
        out["sensitivities"] = {
            name: [None if np.isnan(v) else float(v) for v in S[:, k]] for k, name in enumerate(res["names"])
        }
        out["sensitivities_smooth"] = bool(res["smooth"][0])
    if args.json:
        print(json.dumps(io.clean_json(out), indent=2))
        return
    from cdpr.models.subsets import subset_label

    mode = "physical equilibrium" if args.redundancy == "physical" else f"paper mode, solver {args.method}"
    print(
        f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}, {robot.dead_length_summary()}), {mode}"
    )
    fmt = lambda v: "(" + ", ".join("nan" if v is None or v != v else f"{x:.6f}" for x in v) + ")"  # noqa: E731
    print(f"  desired P  [m] : {fmt(out['desired'])}")
    print(f"  solved P*  [m] : {fmt(out['solved'])}")
    print(f"  |dp|       [m] : {out['dp_norm']:.6f}")
    if "dphi" in out:
        print(f"  rotvec*  [rad] : {fmt(out['solved_rotvec'])}   dphi [rad]: {out['dphi']:.6g}")
    print("  tensions   [N] : " + ", ".join("slack" if v is None else f"{v:.2f}" for v in out["tensions"]))
    if args.redundancy == "physical":
        print(f"  taut cables    : {'-'.join(map(str, out['taut'])) or '-'}")
    else:
        print(f"  subset         : {subset_label(res['subset'][0]) or '-'}")
    print(f"  status         : {out['status']}  ({out['iterations']} iterations)")
    if args.sensitivities:
        from cdpr.parameters import UNITS, parameter_groups

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
    import dataclasses

    from cdpr.analyses.compensation import compensated_pose
    from cdpr.models.equilibrium import to_frame as physical_frame

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
    rv = _rotvec(args, len(P))
    if rv is not None or not robot.suspended_point_mass:
        return _compensate_spatial(args, robot, actual, P, rv, t_max)
    engine = args.engine or "compiled"
    res = compensated_pose(
        robot, P, actual=actual, method=args.distribution, engine=engine, t_min=args.t_min, t_max=t_max
    )
    if args.points or args.out:
        df = physical_frame(robot, res)
        for i in range(robot.m):
            df[f"L0_{i + 1}"] = res["L0"][:, i]
        for i in range(robot.m):
            df[f"t_planned{i + 1}"] = res["t_planned"][:, i]
        io.write_table(df, args.out)
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
        from cdpr.models.drive import drum_angles

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


def _compensate_spatial(args, robot, actual, P, rv, t_max):
    """``compensate`` at poses (rigid platform or --rotvec): minimum-norm distribution in the bounds
    at the pose (``distribution6``), compensated rest lengths, and the check solve (6-DoF numpy)."""
    from cdpr.models.distribution6 import compensated_lengths
    from cdpr.models.equilibrium6 import solve_spatial, to_frame6

    if args.distribution != "min_norm":
        raise CdprError(
            f"--distribution {args.distribution} is not available at a pose (rigid platform or --rotvec); use min_norm"
        )
    if args.engine == "compiled":
        raise CdprError("the compiled engine has no 6-DoF solver yet; use --engine numpy")
    c = compensated_lengths(robot, P, rv, t_min=args.t_min, t_max=t_max)
    ok = c["feasible"]
    res = solve_spatial(actual or robot, P, rv, L0=np.where(ok[:, None], c["L0"], 1.0))
    status = np.where(ok, res["status"], "infeasible")
    if args.points or args.out:
        df = to_frame6(robot, res)
        df["status"] = status
        for i in range(robot.m):
            df[f"L0_{i + 1}"] = c["L0"][:, i]
        for i in range(robot.m):
            df[f"t_planned{i + 1}"] = c["t"][:, i]
        io.write_table(df, args.out)
        print(f"wrote {len(df)} poses to {args.out}; {int((~ok).sum())} infeasible (no tension distribution)")
        return
    out = {
        "desired": list(map(float, args.at)),
        "rotvec": res["rotvec"][0].tolist(),
        "lengths": c["L0"][0].tolist(),
        "tensions": c["t"][0].tolist(),
        "status": str(status[0]),
        "solved": res["P_s"][0].tolist() if ok[0] else None,
        "solved_rotvec": res["rotvec_s"][0].tolist() if ok[0] else None,
        "dp_norm": float(res["dp"][0]) if ok[0] else None,
        "dphi": float(res["dphi"][0]) if ok[0] else None,
    }
    if args.json:
        print(json.dumps(io.clean_json(out), indent=2))
        return
    print(
        f"{robot.name} ({robot.pulley_summary()}, {robot.material_summary()}), distribution min_norm at a pose"
    )
    if not ok[0]:
        print(
            "status: infeasible (no tension distribution within the bounds holds the platform at this pose)"
        )
        return
    rows = [
        [str(i + 1), f"{L:.6f}", f"{t:.2f}"] for i, (L, t) in enumerate(zip(out["lengths"], out["tensions"]))
    ]
    print(_table(rows, ["cable", "rest length L0 [m]", "planned tension [N]"]))
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
    from cdpr.solve import solve_table

    robot = _load(args)
    io.check_output(args.out)
    if args.box_file:
        from cdpr.pipeline.study import read_box

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
        from cdpr.solve import results_frame

        res = _solve_sensitivities(robot, P, args)
        df = _with_sensitivities(results_frame(robot, res, args.redundancy), res)
    else:
        extra = {} if args.rotvec is None else {"rotvec": np.asarray(args.rotvec, dtype=float)}
        df = solve_table(
            robot,
            P,
            method=args.method,
            engine=args.engine,
            threads=args.threads,
            redundancy=args.redundancy,
            **extra,
        )
    if args.wrench_feasible:
        from cdpr.models.distribution6 import distribute_pose

        df["feasible"] = distribute_pose(robot, P, args.rotvec, t_min=args.t_min)["feasible"]
        cell = np.prod([(box[2 * k + 1] - box[2 * k]) / args.n for k in range(3)])
        print(
            f"wrench-feasible: {int(df['feasible'].sum())} of {len(df)} grid points, {df['feasible'].sum() * cell:.4g} m^3"
        )
    io.write_table(df, args.out)
    dt = time.perf_counter() - t0
    _report(df, args.out, args, dt)


def cmd_winch(args):
    p = winch.load_params(args.params) if args.params else winch.TABLE1
    if args.out:
        io.check_output(args.out)
    if not args.lpm_from < args.lpm_to:
        raise CdprError(f"--lpm-from must be below --lpm-to, got {args.lpm_from:g} and {args.lpm_to:g}")
    winch.check_range(p, args.lpm_from, args.lpm_to)
    df = winch.winch_table(p, args.lpm_from, args.lpm_to, args.steps)
    if args.out:
        io.write_table(df, args.out)
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
    robot = _load(args)
    io.check_output(args.out)
    top = float(robot.A[:, 2].min())
    if not robot.suspended_point_mass:
        from cdpr.analyses.workspace import frame_box

        lo, hi = frame_box(robot)[4:]
        if not lo <= args.z <= hi:
            raise CdprError(
                f"--z must lie within the frame's height ({lo:g} <= z <= {hi:g} m), got {args.z:g}"
            )
    elif not 0.0 <= args.z < top:
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
        **_rotvec_option(args),
    )
    io.write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)


def _rotvec_option(args):
    """``{"rotvec": (3,)}`` for the solvers when --rotvec is given, else nothing."""
    return {} if args.rotvec is None else {"rotvec": np.asarray(args.rotvec, dtype=float)}


def cmd_trajectory(args):
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
        **_rotvec_option(args),
    )
    io.write_table(df, args.out)
    _report(df, args.out, args, time.perf_counter() - t0)


#: Pipeline tasks: name -> (function of cdpr.pipeline.tasks, its named options). Options named ``tables``
#: and ``paths`` take many files; the rest one value. Files are matched by name, not position.
JOBS = {
    "winch-figure": ("winch_figure", ["table", "figure"]),
    "plane-figure": ("plane_figure", ["robot_key", "tables", "figure"]),
    "subsets-figure": ("subsets_figure", ["robot_key", "tables", "figure"]),
    "trajectories": ("trajectories", ["tables", "table", "figure", "minmax_figure"]),
    "volumes": ("volumes", ["tables", "table", "figure"]),
    "volume-view": ("volume_view", ["label", "tables", "figure"]),
    "rw": ("regular_workspace", ["tables", "table", "json"]),
    "doe": ("doe_results", ["tables", "table", "effects", "figure", "effects_figure"]),
    "map": ("map_rows", ["kind", "box_file", "table", "threads"]),
    "maps": ("maps", ["tables", "box_file", "map", "lines", "figure", "threads"]),
    "elasticity": (
        "elasticity",
        ["tables", "paths", "table", "bands", "crossings", "figure", "paths_figure"],
    ),
    "dead-length-point": ("dead_length_point", ["d", "box_file", "table", "threads"]),
    "dead-length": ("dead_length", ["tables", "table", "figure"]),
    "summary": ("summary", ["results", "table", "markdown"]),
    "budget-design": (
        "budget_design",
        ["comparison", "label", "box_file", "table", "path_table", "threads"],
    ),
    "budget": ("budget_tables", ["comparison", "tables", "paths", "table", "figure", "paths_figure"]),
    "comparison": ("comparison", ["comparison", "tables", "table", "figure", "markdown"]),
    "uq-shard": ("uq_shard", ["design", "case", "shard", "box_file", "table", "points", "threads"]),
    "uq-design": (
        "uq_design",
        ["design", "case", "box_file", "table", "path", "sobol", "tolerances", "map", "threads"],
    ),
    "uncertainty": (
        "uncertainty",
        [
            "tables",
            "paths",
            "bands",
            "agreement",
            "sobol",
            "figure",
            "paths_figure",
            "sobol_figure",
            "map_figure",
            "agreement_figure",
        ],
    ),
}
_JOB_OPTION_HELP = {
    "tables": "input tables (matched by file name)",
    "paths": "path tables (matched by file name)",
    "table": "output table",
    "figure": "output figure (.png; a .pdf is written beside it)",
    "json": "output JSON",
    "effects": "output effects table",
    "effects_figure": "output effects figure",
    "minmax_figure": "output min/max figure",
    "map": "output map table",
    "lines": "output lines table",
    "bands": "output bands table",
    "crossings": "output crossings table",
    "paths_figure": "output figure of the paths",
    "markdown": "output summary.md",
    "results": "results folder of the study",
    "box_file": "JSON with the RW_C box",
    "robot_key": "robot label of the study",
    "label": "robot_pulley label",
    "kind": "pulley kind",
    "d": "dead length [m]",
    "threads": "solver threads",
    "comparison": "comparison file (config/comparisons/*.yaml)",
    "path_table": "output table along the path",
    "design": "design label of the study's optimal designs",
    "case": "uncompensated | compensated",
    "shard": "0-based shard index",
    "points": "output per-point table",
    "path": "output path table",
    "sobol": "output Sobol table",
    "tolerances": "output table of the all-parameter samples",
    "agreement": "output agreement table",
    "sobol_figure": "output Sobol figure",
    "map_figure": "output map figure",
    "agreement_figure": "output agreement figure",
}


def cmd_job(args):
    from cdpr.pipeline import tasks
    from cdpr.pipeline.study import load_study

    st = load_study(args.study)
    func, names = JOBS[args.name]
    given = {n: getattr(args, n) for n in names}
    missing = [f"--{n.replace('_', '-')}" for n, v in given.items() if v is None and n != "threads"]
    if missing:
        raise CdprError(f"job {args.name} needs {', '.join(missing)}")
    for n in names:
        if n in (
            "table",
            "figure",
            "json",
            "effects",
            "effects_figure",
            "minmax_figure",
            "map",
            "lines",
            "bands",
            "crossings",
            "paths_figure",
            "markdown",
            "path_table",
            "points",
            "path",
            "sobol",
            "tolerances",
            "agreement",
            "sobol_figure",
            "map_figure",
            "agreement_figure",
        ):
            io.check_output(given[n])
    getattr(tasks, func)(st, **given)


def build_parser():
    ap = _Parser(
        prog="cdpr",
        description="Pose errors of cable-driven parallel robots from pulleys, cable elasticity and winch geometry.",
    )
    sub = ap.add_subparsers(dest="command", required=True, parser_class=_Parser)
    sp = sub.add_parser(
        "inverse", help="extended inverse model of every cable at a point (or a table of points)"
    )
    _robot_options(sp)
    _points_options(sp, "platform position")
    sp.set_defaults(func=cmd_inverse)
    sp = sub.add_parser(
        "point", help="DEGM_E at a point (or a table of points): solved pose, |dp|, tensions, subset, status"
    )
    _robot_options(sp)
    _solver_options(sp)
    _points_options(sp, "desired position")
    _physics_options(sp)
    sp.add_argument(
        "--lengths",
        nargs="+",
        type=positive,
        metavar="M",
        help="commanded rest lengths L0 per cable [m] (winch exit to platform; physical mode), instead of L_TS at --at",
    )
    sp.add_argument(
        "--q",
        nargs="+",
        type=finite,
        metavar="RAD",
        help="commanded drum angles per cable [rad] (robot with winches; physical mode): mapped to rest lengths by the winch model",
    )
    _sensitivity_options(sp)
    sp.set_defaults(func=cmd_point)
    sp = sub.add_parser(
        "compensate", help="compensated rest lengths: what to command so that the platform reaches --at"
    )
    _robot_options(sp)
    sp.add_argument("--E", type=positive, metavar="PA", help="Young's modulus E [Pa] of every cable")
    sp.add_argument(
        "--E-cables",
        nargs="+",
        type=positive,
        metavar="PA",
        help="Young's modulus of each cable [Pa] (the model)",
    )
    sp.add_argument("--mass", type=positive, metavar="KG", help="platform mass M [kg]")
    _points_options(sp, "desired position")
    sp.add_argument(
        "--distribution",
        choices=("min_norm", "closed_form", "closed_form_improved", "subset"),
        default="min_norm",
        help="tension distribution (default min_norm: least 2-norm within [t-min, t-max]); subset: the paper's 3-cable subset",
    )
    sp.add_argument(
        "--t-min", type=non_negative, default=100.0, metavar="N", help="least cable tension [N] (default 100)"
    )
    sp.add_argument(
        "--t-max",
        type=positive,
        metavar="N",
        help="largest cable tension [N] (default: each cable's admissible tension)",
    )
    sp.add_argument(
        "--actual-E-cables",
        nargs="+",
        type=positive,
        metavar="PA",
        help="check: command the lengths to a robot whose cables have these moduli [Pa] and report where it settles",
    )
    sp.add_argument(
        "--engine",
        choices=("compiled", "numpy"),
        default=None,
        help="engine of the check solve (default compiled)",
    )
    sp.add_argument("--threads", type=_threads, help="threads of the compiled engine")
    sp.set_defaults(func=cmd_compensate)
    sp = sub.add_parser("grid", help="DEGM_E over the n^3 cell-centred grid of a box; writes parquet or CSV")
    _robot_options(sp)
    _solver_options(sp)
    sp.add_argument("--box", nargs=6, type=finite, metavar=("XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"))
    sp.add_argument(
        "--box-file", metavar="FILE", help="JSON file whose key 'box' holds the six numbers (e.g. rw_c.json)"
    )
    sp.add_argument(
        "--frame",
        action="store_true",
        help="the frame's bounding box (anchors' extent, z from 0 to the pulleys)",
    )
    sp.add_argument("--n", type=count(1), required=True, help="points per axis")
    sp.add_argument(
        "--rotvec", nargs=3, type=finite, metavar=("RX", "RY", "RZ"), help="fixed platform orientation [rad]"
    )
    sp.add_argument(
        "--wrench-feasible",
        action="store_true",
        help="add a 'feasible' column: a tension distribution in [--t-min, T_a] holds the platform at the pose",
    )
    sp.add_argument(
        "--t-min", type=non_negative, default=100.0, metavar="N", help="least tension of --wrench-feasible"
    )
    sp.add_argument("--out", required=True, metavar="FILE", help="output .parquet or .csv")
    sp.add_argument("--shard", type=count(0), default=0, help="0-based shard index (default 0)")
    sp.add_argument("--shards", type=count(1), default=1, help="number of shards (default 1)")
    _physics_options(sp)
    _sensitivity_options(sp)
    sp.set_defaults(func=cmd_grid)
    sp = sub.add_parser("winch", help="winch joint angles and length error versus l_pm (winch seed Fig. 7)")
    sp.add_argument(
        "--params", metavar="FILE", help="YAML of winch parameters (default: Table 1 of the winch seed)"
    )
    sp.add_argument(
        "--lpm-from", type=non_negative, default=0.0, metavar="M", help="first l_pm [m] (default 0)"
    )
    sp.add_argument("--lpm-to", type=non_negative, default=5.0, metavar="M", help="last l_pm [m] (default 5)")
    sp.add_argument(
        "--steps", type=count(2, MAX_STEPS), default=101, help="points of the table (default 101)"
    )
    sp.add_argument("--out", metavar="FILE", help="also write the table (.csv or .parquet)")
    sp.add_argument("--json", action="store_true")
    sp.set_defaults(func=cmd_winch)
    sp = sub.add_parser("plane", help="DEGM_E over a horizontal plane (Fig. 9, 12); writes a table")
    _robot_options(sp)
    _solver_options(sp)
    sp.add_argument("--z", type=finite, required=True, metavar="M", help="plane height [m]")
    sp.add_argument(
        "--n", type=count(2, 20000), required=True, help="points per side over the anchors' bounding box"
    )
    sp.add_argument("--out", required=True, metavar="FILE")
    _rotvec_argument(sp)
    _physics_options(sp)
    sp.set_defaults(func=cmd_plane)
    sp = sub.add_parser(
        "trajectory", help="DEGM_E along a straight path (Fig. 10, 19); writes a table with arc length s"
    )
    _robot_options(sp)
    _solver_options(sp)
    sp.add_argument("--start", nargs=3, type=finite, required=True, metavar=("X", "Y", "Z"))
    sp.add_argument("--end", nargs=3, type=finite, required=True, metavar=("X", "Y", "Z"))
    sp.add_argument("--n", type=count(2, 100_000_000), required=True, help="points along the path")
    sp.add_argument("--out", required=True, metavar="FILE")
    _rotvec_argument(sp)
    _physics_options(sp)
    sp.set_defaults(func=cmd_trajectory)
    sp = sub.add_parser("job", help="a pipeline task: tables in, tables and figures out (run by Snakemake)")
    sp.add_argument("name", choices=list(JOBS))
    sp.add_argument(
        "--study", required=True, metavar="FILE", help="the study file (validated as by the pipeline)"
    )
    for n in sorted({n for _, names in JOBS.values() for n in names}):
        opt = "--" + n.replace("_", "-")
        if n in ("tables", "paths"):
            sp.add_argument(opt, nargs="+", metavar="FILE", help=_JOB_OPTION_HELP[n])
        elif n == "threads":
            sp.add_argument(opt, type=_threads, help=_JOB_OPTION_HELP[n])
        elif n == "d":
            sp.add_argument(opt, type=non_negative, help=_JOB_OPTION_HELP[n])
        else:
            sp.add_argument(opt, help=_JOB_OPTION_HELP[n])
    sp.set_defaults(func=cmd_job)
    from cdpr.cli import caspr

    caspr.add_parser(sub, _Parser, positive, non_negative)
    from cdpr.cli import view

    view.add_parser(sub, finite)
    return ap


def main(argv=None):
    try:
        args = build_parser().parse_args(argv)
        args.func(args)
    except CdprError as exc:
        print(f"cdpr: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. `cdpr ... | head`: the reader left; stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    return 0
