"""The command line's heavy-cable outputs (issue 38, docs/heavy_cables.md): ``compensate``'s
per-cable ``cables`` JSON and text columns, and ``inverse --tensions``."""

from __future__ import annotations

import sys

import numpy as np

from cdpr.errors import CdprError

#: ``compensate --json``'s per-cable keys with heavy cables and the keys of ``cables.heavy_cables``.
HEAVY_CABLE_JSON = (
    ("tension_B_N", "t_B"),
    ("tension_D_N", "t_D"),
    ("H_N", "H"),
    ("sag_m", "sag"),
    ("arc_minus_chord_m", "arc_minus_chord"),
    ("angle_f_deg", "angle_f_deg"),
    ("status", "cable_status"),
)


def compensate_columns(out, rows, headers):
    """``compensate``'s text table with heavy cables: the tension at D, the sag and the angle of the
    force at B to the chord per cable, and a note on the distribution's fixed point."""
    if "cables" not in out:
        return rows, headers
    c = out["cables"]
    rows = [
        r + [f"{o['tension_D_N']:.2f}", f"{1e3 * o['sag_m']:.2f}", f"{o['angle_f_deg']:.3f}", o["status"]]
        for r, o in zip(rows, c)
    ]
    print(
        f"heavy cables: sag-consistent tension distribution (tensions at B), "
        f"{out['distribution_iterations']} fixed-point iterations"
    )
    return rows, headers + ["tension at D [N]", "sag [mm]", "force vs chord [deg]", "cable"]


def compensate_json(out, res):
    """With heavy cables (``res`` of ``compensation.compensated_pose`` with planned_cables), add to
    ``out`` (in place) ``cables``: one object per cable at the desired pose under the compensated
    lengths (``HEAVY_CABLE_JSON``, issue 38's keys) and ``distribution_iterations``, the sag-consistent
    distribution's fixed-point iterations."""
    if "planned_cables" not in res:
        return
    h = res["planned_cables"]
    num = lambda v: None if v != v else float(v)  # noqa: E731
    out["cables"] = [
        {key: (str(h[k][0, i]) if k == "cable_status" else num(h[k][0, i])) for key, k in HEAVY_CABLE_JSON}
        for i in range(h["t_B"].shape[1])
    ]
    out["distribution_iterations"] = int(res["iterations_distribution"][0])


def _inverse_tensions(args, robot, P, rv):
    """``inverse --tensions``: each cable under its tension at the platform B_i
    (``cables.HeavyCables.inverse``): the catenary from B_i to the exit point D_i, the wrap and the
    rest length that stretches to it (a massless robot: the straight cable and Hooke's rest length);
    returns (out, title, (rows, headers)) for ``inverse`` to print."""
    from cdpr.models.cables import HeavyCables, heavy_cables  # lazy: --tensions only
    from cdpr.models.platform import pose_arrays  # lazy: --tensions only

    p, R = pose_arrays(P, None if robot.point_mass else rv)
    cab = HeavyCables(robot)
    t = np.array([args.tensions], dtype=float)
    inv = cab.inverse(p, R, t)
    if not inv["converged"].all():
        bad = [int(i) + 1 for i in np.flatnonzero(~inv["converged"][0])]
        raise CdprError(f"--tensions: no catenary carries the tension given for cables {bad} at this pose")
    h = heavy_cables(cab, p, R, inv["L0"])
    out = [
        {
            "cable": i + 1,
            "L0": float(inv["L0"][0, i]),
            "L0_free": float(inv["L0_free"][0, i]),
            "D": inv["D"][0, i].tolist(),
            "wrap": float(inv["gamma"][0, i]) if robot.kind[i] != 0 else None,
            **{
                key: (str(h[k][0, i]) if k == "cable_status" else float(h[k][0, i]))
                for key, k in HEAVY_CABLE_JSON
            },
        }
        for i in range(robot.m)
    ]
    title = f"{robot.name} ({robot.pulley_summary()}, {robot.dead_length_summary()}) at P = {args.at} m, cables under --tensions"
    rows = [
        [
            str(o["cable"]),
            f"{o['L0']:.6f}",
            f"{o['tension_B_N']:.2f}",
            f"{o['tension_D_N']:.2f}",
            f"{1e3 * o['sag_m']:.2f}",
            f"{o['angle_f_deg']:.3f}",
            "(" + ", ".join(f"{x:.4f}" for x in o["D"]) + ")",
            o["status"],
        ]
        for o in out
    ]
    headers = ["cable", "rest length L0 [m]", "T at B [N]", "T at D [N]", "sag [mm]", "force vs chord [deg]"]
    return out, title, (rows, headers + ["D [m]", "status"])


def inverse_heavy(args, robot, points):
    """``inverse`` with --tensions: the cables under those tensions at B, as (the JSON list, the
    text's title, (rows, headers) of its table); on a robot with heavy cables without them, one line
    on stderr (the massless geometry follows) and None."""
    if args.tensions is not None:
        if args.points or args.out:
            raise CdprError("--tensions takes one pose (--at), not a table of points (--points/--out)")
        if len(args.tensions) != robot.m:
            raise CdprError(f"--tensions needs one tension per cable ({robot.m}), got {len(args.tensions)}")
        return _inverse_tensions(args, robot, *points.first())
    if robot.heavy:
        print(
            "cdpr: note: heavy cables (cable.linear_density_kg_m > 0): this is the massless geometry (straight "
            "cables); give --tensions T1 ... Tm (at the platform) for the catenaries",
            file=sys.stderr,
        )
    return None


def one_shot(robot, n):
    """``solve.check_engine``'s ``one_shot`` for a process that solves ``n`` poses and exits
    (``point``, ``compensate``): ``n`` for massless cables (below ``solve.ONE_SHOT_POSES`` the numpy
    reference is cheaper than loading the compiled engine), None with heavy cables: the compiled
    engine for any number of poses, as in the library. The heavy numpy reference costs seconds per
    pose (CoGiRo at 0.0631 kg/m, ``point --at 1 1 1.5``: 14.5 s CPU numpy, 2.2 s compiled with the
    kernels' load; docs/heavy_cables.md)."""
    return None if robot.heavy else n


def feasible(robot, P, rotvec, t_min):
    """``grid --wrench-feasible``: a tension distribution in [t_min, T_a] holds the platform at each
    pose. Massless cables: ``tension_distribution.distribute_pose``; heavy cables: the sag-consistent
    distribution (``compensation.heavy_distribution``, the bounds on the tensions at B_i, as
    ``compensate``'s), whose W has the catenaries' end forces for columns."""
    if not robot.heavy:
        from cdpr.models.tension_distribution import distribute_pose  # lazy: --wrench-feasible only

        return distribute_pose(robot, P, rotvec, t_min=t_min)["feasible"]
    from cdpr.analyses.compensation import heavy_distribution  # lazy: --wrench-feasible, heavy only
    from cdpr.models.platform import pose_arrays  # lazy: --wrench-feasible, heavy only

    p, R = pose_arrays(P, rotvec)
    return heavy_distribution(robot, p, R, t_min=t_min)["feasible"]


def _nan_none(x):
    return [None if np.isnan(v) else float(v) for v in x]


def point_json(out, res):
    """``point``'s JSON with heavy cables (in place): tensions_D and sag_m per cable."""
    if "t_D" in res:
        out.update(tensions_D=_nan_none(res["t_D"][0]), sag_m=_nan_none(res["sag"][0]))


def point_text(out):
    """``point``'s text with heavy cables: the tensions at D and the sags."""
    if "sag_m" in out:
        print(
            "  tensions at D  : " + ", ".join("nan" if v is None else f"{v:.2f}" for v in out["tensions_D"])
        )
        print(
            "  sag       [mm] : " + ", ".join("nan" if v is None else f"{1e3 * v:.2f}" for v in out["sag_m"])
        )
