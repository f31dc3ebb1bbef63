"""``cdpr import caspr``: a robot file from CASPR's bodies and cables XML (``cdpr.robot_import``)."""

from __future__ import annotations

import yaml

from cdpr import io


def add_parser(sub, parser_class, positive, non_negative):
    """Register ``import caspr`` on the command line's subparsers ``sub``."""
    sp = sub.add_parser("import", help="write a robot file from another tool's model (CASPR)")
    tools = sp.add_subparsers(dest="tool", required=True, parser_class=parser_class)
    c = tools.add_parser("caspr", help="single-link spatial CASPR model: X_bodies.xml + X_cables.xml")
    c.add_argument("--bodies", required=True, metavar="FILE", help="CASPR bodies file (X_bodies.xml)")
    c.add_argument("--cables", required=True, metavar="FILE", help="CASPR cables file (X_cables.xml)")
    c.add_argument("--cable-set", metavar="ID", help="cable set id (default: the file's default_cable_set)")
    c.add_argument("--out", required=True, metavar="FILE", help="robot YAML file to write")
    c.add_argument("--E", type=positive, default=102.2e9, metavar="PA", help="Young's modulus (not in CASPR)")
    c.add_argument(
        "--diameter", type=positive, default=0.004, metavar="M", help="cable diameter (not in CASPR)"
    )
    c.add_argument(
        "--dead-length", type=non_negative, default=0.0, metavar="M", help="dead length d (not in CASPR)"
    )
    c.set_defaults(func=cmd_import_caspr)


def cmd_import_caspr(args):
    """Read, validate as a robot file, write."""
    from cdpr.robot import robot_from_dict
    from cdpr.robot_import import robot_dict_from_caspr

    data = robot_dict_from_caspr(
        args.bodies,
        args.cables,
        args.cable_set,
        E=args.E,
        diameter=args.diameter,
        dead_length=args.dead_length,
    )
    robot = robot_from_dict(data, source=f"{args.cables} (imported)")
    io.check_output(args.out, (".yaml", ".yml"))
    header = (
        f"# Imported by `cdpr import caspr` from {args.bodies} and {args.cables}"
        f" (cable set {args.cable_set or 'default'}).\n"
        "# E, the cable diameter and the dead length are not part of CASPR models: given on the command line.\n"
    )
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(header + yaml.safe_dump(data, sort_keys=False))
    print(f"wrote {args.out}: {robot.m} cables, platform {robot.platform.mass:g} kg")
