"""``cdpr import caspr | rrf`` and ``cdpr export rrf | klipper``: their options (the commands are
``cdpr.cli.robot_files.cmd_import_caspr``, which builds a robot file from CASPR's bodies and cables XML
with ``cdpr.robot_import``, and ``cmd_import_rrf``, ``cmd_export_rrf``, ``cmd_export_klipper`` with
``cdpr.robot_rrf``: a Hangprinter from and to RepRapFirmware's M669/M666 lines, and to Klipper).

Standard library and ``cdpr.cli.options`` only: ``cdpr.cli.parser`` registers it for ``cdpr --help``.
"""

from __future__ import annotations

from cdpr.cli.options import Parser, linear_density_option, non_negative, positive


def add_parser(sub):
    """Register ``import caspr``, ``import rrf``, ``export rrf`` and ``export klipper`` on the command
    line's subparsers ``sub``."""
    sp = sub.add_parser(
        "import",
        help="write a robot file from another tool's model (CASPR) or a firmware's configuration (RepRapFirmware)",
    )
    tools = sp.add_subparsers(dest="tool", required=True, parser_class=Parser)
    c = tools.add_parser("caspr", help="single-link spatial CASPR model: X_bodies.xml + X_cables.xml")
    c.add_argument("--bodies", required=True, metavar="FILE", help="CASPR bodies file (X_bodies.xml)")
    c.add_argument("--cables", required=True, metavar="FILE", help="CASPR cables file (X_cables.xml)")
    c.add_argument("--cable-set", metavar="ID", help="cable set id (default: the file's default_cable_set)")
    c.add_argument("--out", required=True, metavar="FILE", help="robot YAML file to write")
    c.add_argument(
        "--name",
        metavar="NAME",
        help="the robot's name (default: the model's file stem, CoGiRo_bodies.xml -> CoGiRo)",
    )
    c.add_argument(
        "--E",
        type=positive,
        metavar="PA",
        help="Young's modulus [Pa] (not in CASPR; default 102.2e9, assumed and said so)",
    )
    c.add_argument(
        "--diameter",
        type=positive,
        metavar="M",
        help="cable diameter [m] (not in CASPR; default 0.004, assumed and said so)",
    )
    c.add_argument(
        "--dead-length",
        type=non_negative,
        metavar="M",
        help="dead length d [m] (not in CASPR; default 0, assumed and said so)",
    )
    linear_density_option(c)
    c.set_defaults(run=("cdpr.cli.robot_files", "cmd_import_caspr"))
    r = tools.add_parser(
        "rrf", help="Hangprinter robot from a RepRapFirmware configuration (M669 K6 anchors, M666 spools)"
    )
    r.add_argument("--config", required=True, metavar="FILE", help="RepRapFirmware configuration (config.g)")
    r.add_argument("--out", required=True, metavar="FILE", help="robot YAML file to write")
    r.add_argument("--name", metavar="NAME", help="the robot's name (default: the configuration's file stem)")
    r.set_defaults(run=("cdpr.cli.robot_files", "cmd_import_rrf"))
    sp = sub.add_parser("export", help="a robot file as a firmware's configuration (RepRapFirmware, Klipper)")
    tools = sp.add_subparsers(dest="tool", required=True, parser_class=Parser)
    for tool, what in (
        ("rrf", "RepRapFirmware's M669 K6 and M666 lines of a Hangprinter robot"),
        (
            "klipper",
            "Klipper's [printer] kinematics: winch and [stepper_a..] anchor_x/y/z of a Hangprinter robot",
        ),
    ):
        e = tools.add_parser(tool, help=what)
        e.add_argument(
            "--robot",
            required=True,
            metavar="FILE",
            help="robot YAML file (a Hangprinter: spools, fixed pulleys)",
        )
        e.add_argument("--out", metavar="FILE", help="file to write (default: standard output)")
        e.set_defaults(run=("cdpr.cli.robot_files", f"cmd_export_{tool}"))
