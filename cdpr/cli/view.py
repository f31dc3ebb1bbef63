"""``cdpr view``: a 3-D picture of a robot (frame, pulleys with their axes, platform, cables) so a
user checks a robot file by looking at it."""

from __future__ import annotations

import numpy as np

from cdpr import io


def add_parser(sub, finite):
    """Register ``view`` on the command line's subparsers ``sub``."""
    sp = sub.add_parser(
        "view", help="3-D picture of a robot file at a pose (frame, pulleys and axes, platform, cables)"
    )
    sp.add_argument("--robot", required=True, metavar="FILE", help="robot YAML file")
    sp.add_argument(
        "--at", nargs=3, type=finite, metavar=("X", "Y", "Z"), help="platform position [m] (default: centre)"
    )
    sp.add_argument("--rotvec", nargs=3, type=finite, metavar=("RX", "RY", "RZ"), help="orientation [rad]")
    sp.add_argument("--out", required=True, metavar="FILE", help="output .png")
    sp.set_defaults(func=cmd_view)


def default_position(robot):
    """The anchors' centroid, lowered to the middle of their height range."""
    A = robot.A
    return np.array(
        [
            A[:, 0].mean(),
            A[:, 1].mean(),
            0.5 * (A[:, 2].min() + A[:, 2].max()) * (0.6 if robot.suspended_point_mass else 1.0),
        ]
    )


def draw_robot(robot, p, rotvec, path):
    """Write the picture of ``robot`` with its platform at (p, rotvec) to ``path`` (.png)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from cdpr.models.equilibrium6 import pose_arrays, pose_state

    p_, R = pose_arrays(robot, [p], None if rotvec is None else [rotvec])
    B, st = pose_state(robot, p_, R)
    B, D, K, H = B[0], st.D[0], st.K[0], st.H[0]
    a = robot.arrays
    C = a.A - a.d[:, None] * a.axis
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    span = float(np.ptp(np.vstack([a.A, B]), axis=0).max())
    ax.scatter(*a.A.T, color="k", s=12, label="joint points A_i")
    for i in range(robot.m):
        ax.plot(*np.stack([C[i], K[i]]).T, color="0.6", lw=0.8)  # dead length
        ax.plot(*np.stack([D[i], B[i]]).T, color="tab:blue", lw=1.2)  # cable
        ax.quiver(*a.A[i], *(0.08 * span * a.axis[i]), color="tab:red", lw=1.0)
        if robot.r_p[i] > 0:
            t = np.linspace(0, 2 * np.pi, 40)
            e_s = (D[i] - H[i]) / max(np.linalg.norm(D[i] - H[i]), 1e-12)
            n = np.cross(e_s, a.axis[i])
            n /= max(np.linalg.norm(n), 1e-12)
            w = np.cross(n, e_s)
            circ = H[i] + robot.r_p[i] * (np.cos(t)[:, None] * e_s + np.sin(t)[:, None] * w)
            ax.plot(*circ.T, color="tab:orange", lw=0.8)
        ax.text(*a.A[i], f" {i + 1}", fontsize=8)
    if not robot.point_mass:
        from scipy.spatial import ConvexHull

        pts = np.vstack([B, p_[0] + R[0] @ a.com])
        try:
            hull = ConvexHull(B)
            for s in hull.simplices:
                ax.plot(*B[np.append(s, s[0])].T, color="tab:green", lw=0.5)
        except Exception:  # coplanar attachments: outline them
            ax.plot(*np.vstack([B, B[:1]]).T, color="tab:green", lw=0.8)
        ax.scatter(*pts[-1], color="tab:green", marker="x", s=30, label="centre of mass")
    ax.scatter(*p_[0], color="tab:green", s=20, label="platform point p")
    ax.plot([], [], color="tab:red", label="pulley axes k_i")
    ax.plot([], [], color="tab:blue", label="cables D_i -> B_i")
    lo, hi = np.vstack([a.A, B, C]).min(axis=0), np.vstack([a.A, B, C]).max(axis=0)
    mid, half = (lo + hi) / 2, (hi - lo).max() / 2
    for set_lim, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid):
        set_lim(c - half, c + half)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(f"{robot.name} at p = {np.round(p_[0], 3).tolist()} m")
    ax.legend(fontsize=7, loc="upper left")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def cmd_view(args):
    """Load, draw, report."""
    from cdpr.robot import load_robot

    robot = load_robot(args.robot)
    io.check_output(args.out, (".png",))
    p = default_position(robot) if args.at is None else np.asarray(args.at, dtype=float)
    draw_robot(robot, p, args.rotvec, args.out)
    print(f"wrote {args.out}")
