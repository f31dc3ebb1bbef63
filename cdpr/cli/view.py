"""``cdpr view``: its options (the command is ``cdpr.cli.robot_files.cmd_view``: a 3-D picture of a
robot (frame box, pulleys with their swivel axes and sheaves, platform, cables, optionally a box) so a
user checks a robot file by looking at it; drawn by ``cdpr.pipeline.plots.robot.robot_view``).

Standard library and ``cdpr.cli.options`` only: ``cdpr.cli.parser`` registers it for ``cdpr --help``.
"""

from __future__ import annotations

from cdpr.cli.options import box_option, coordinate, rotvec_option


def add_parser(sub):
    """Register ``view`` on the command line's subparsers ``sub``."""
    sp = sub.add_parser(
        "view", help="3-D picture of a robot file at a pose (frame, pulleys and axes, platform, cables)"
    )
    sp.add_argument("--robot", required=True, metavar="FILE", help="robot YAML file")
    sp.add_argument(
        "--at",
        nargs=3,
        type=coordinate,
        metavar=("X", "Y", "Z"),
        help="platform position [m] (default: centre)",
    )
    rotvec_option(sp, help="orientation [rad]")
    box_option(sp, "a box [m] drawn as a wireframe (e.g. the RW_C box of doe/rw_c.json)")
    sp.add_argument(
        "--plan", action="store_true", help="also draw the plan (top) view, seen from +z, beside the 3-D one"
    )
    sp.add_argument("--out", required=True, metavar="FILE", help="output .png (a .pdf is written beside it)")
    sp.set_defaults(run=("cdpr.cli.robot_files", "cmd_view"))
