"""``cdpr inverse``: the extended inverse model at given poses (lengths, exit points, swivel and
wrap angles), and with heavy cables the catenaries under given tensions at B."""

from __future__ import annotations

import numpy as np

from cdpr.cli import heavy
from cdpr.cli.commands import emit_json, read_points, robot_from_args, text_table, write_chunks


def _vec(v):
    return "(" + ", ".join(f"{x:.4f}" for x in v) + ")"


def cmd_inverse(args):
    # lazy: the inverse model, for this command only
    from cdpr.models.inverse import L_TS, igm_e, pose_state
    from cdpr.models.platform import pose_arrays
    from cdpr.models.pulleys import swivel

    robot = robot_from_args(args)
    points = read_points(args)
    a = robot.arrays
    spools = any(p is not None for p in robot.spools)
    if spools:
        from cdpr.models.drive import spool_motor_angles  # lazy: robots with spools only

    def state(P, rv):
        """The extended inverse model at P: lengths L_TS, the pulley states, swivel, wrap > 270°."""
        if robot.point_mass:
            st = igm_e(robot, P)
            lts = L_TS(robot, P)
            B = np.repeat(P[:, None, :], robot.m, axis=1)
        else:
            p_, R = pose_arrays(P, rv)
            B, st = pose_state(robot, p_, R)
            lts = L_TS(robot, p_, R=R)
        sw = swivel(B, a.A, None if robot.suspended_point_mass else a.frame, a.inward, per_cable=True)
        # a fixed anchor is a point of passage: no sheave to wrap, no swivel joint (no angle to report)
        pulley = robot.kind != 0
        over = (st.gamma > 1.5 * np.pi) & pulley
        gamma, alpha = np.where(pulley, st.gamma, np.nan), np.where(pulley, st.alpha, np.nan)
        return lts, st, np.where(pulley, sw, np.nan), over, gamma, alpha

    done = heavy.inverse_heavy(args, robot, points) if args.tensions is not None or robot.heavy else None
    if done is not None:  # --tensions: the cables under those tensions
        out, title, table = done
        emit_json(out, args) if args.json else print(title + "\n" + text_table(*table))
        return
    if args.points or args.out:
        import pandas as pd  # lazy: a table of points only

        inside = [0]

        def table(P, rv):
            lts, st, sw, over, gamma, alpha = state(P, rv)
            motor = spool_motor_angles(robot, lts) if spools else None  # the encoder angles of L_TS
            inside[0] += int(st.inside.any(axis=1).sum())
            cols = {"x": P[:, 0], "y": P[:, 1], "z": P[:, 2]}
            if rv is not None:  # the orientation it was given (--rotvec or the table's), any robot
                cols.update({"rx": rv[:, 0], "ry": rv[:, 1], "rz": rv[:, 2]})
            for i in range(robot.m):
                c = i + 1
                cols.update(
                    {
                        f"L_TS{c}": lts[:, i],
                        f"L_TE{c}": st.L_TE[:, i],
                        f"gamma{c}": gamma[:, i],
                        f"alpha{c}": alpha[:, i],
                        f"beta{c}": st.beta[:, i] if robot.kind[i] == 2 else np.full(len(P), np.nan),
                        f"inside{c}": st.inside[:, i],
                    }
                )
                if not robot.suspended_point_mass:
                    cols.update({f"swivel{c}": sw[:, i], f"wrap_over_270{c}": over[:, i]})
                if motor is not None:
                    cols[f"motor_deg{c}"] = motor[:, i]
            return pd.DataFrame(cols)

        write_chunks(args, points, table, "inverse")
        print(f"wrote {points.n} points to {args.out}; {inside[0]} inside a sheave (lengths clipped there)")
        return
    lts, st, sw, over, gamma, alpha = state(*points.first())
    motor = spool_motor_angles(robot, lts) if spools else None  # the encoder angles that command L_TS
    out = [
        {
            "cable": i + 1,
            "L_TS": float(lts[0, i]),
            "L_TE": float(st.L_TE[0, i]),
            "gamma": float(gamma[0, i]),
            "l_d": float(st.l_d[0, i]),
            "l_E": float(st.l_E[0, i]),
            "alpha": float(alpha[0, i]),
            "beta": float(st.beta[0, i]) if robot.kind[i] == 2 else None,
            "H": st.H[0, i].tolist(),
            "K": st.K[0, i].tolist(),
            "D": st.D[0, i].tolist(),
            "inside": bool(st.inside[0, i]),
            "swivel": float(sw[0, i]),
            "wrap": float(gamma[0, i]),
            "wrap_over_270": bool(over[0, i]),
            **({} if motor is None else {"motor_deg": float(motor[0, i])}),
        }
        for i in range(robot.m)
    ]
    if args.json:
        emit_json(out, args)
        return
    print(f"{robot.name} ({robot.pulley_summary()}, {robot.dead_length_summary()}) at P = {args.at} m")
    rows = [
        [
            str(o["cable"]),
            f"{o['L_TS']:.6f}",
            f"{o['L_TE']:.6f}",
            "-" if o["gamma"] != o["gamma"] else f"{o['gamma']:.6f}",
            "-" if o["alpha"] != o["alpha"] else f"{o['alpha']:.6f}",
            "-" if o["beta"] is None else f"{o['beta']:.6f}",
            f"{o['l_d']:.6f}",
            f"{o['l_E']:.6f}",
            _vec(o["H"]),
            _vec(o["K"]),
            _vec(o["D"]),
            "INSIDE" if o["inside"] else "",
        ]
        + ([] if motor is None else [f"{o['motor_deg']:.2f}"])
        for o in out
    ]
    print(
        text_table(
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
            ]
            + ([] if motor is None else ["motor [deg] for L_TS (spool)"]),
        )
    )
    if any(o["inside"] for o in out):
        print(
            "warning: P (or the winch exit) lies inside a sheave circle for the cables marked INSIDE: no tangent exists, their lengths are clipped"
        )
