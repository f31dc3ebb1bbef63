"""The commands that read and write robot files rather than solve: ``cdpr import caspr | rrf``,
``cdpr export rrf | klipper``, ``cdpr view`` (a picture of a robot), ``cdpr study check`` and
``cdpr compile`` (the kernels into numba's cache)."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

from cdpr import io
from cdpr.cli.commands import checked
from cdpr.errors import CdprError
from cdpr.robot import load_robot


def cmd_import_caspr(args):
    """``cdpr import caspr``: read CASPR's bodies and cables XML (``cdpr.robot_import``), validate the
    result as a robot file, write it. Every value that did not come from the XML (E, diameter, dead
    length, ...) is named in the file's header and in one line on stderr, assumed or given; sanity
    notes (a near-symmetry broken by a possible typo) are lines on stderr, the values kept."""
    from pathlib import Path  # lazy: this command only

    import yaml  # lazy: yaml, for this command only

    # lazy: the importer, for this command only
    from cdpr.robot import robot_from_dict
    from cdpr.robot_import import import_caspr

    got = import_caspr(
        args.bodies,
        args.cables,
        args.cable_set,
        E=args.E,
        diameter=args.diameter,
        dead_length=args.dead_length,
        name=args.name,
    )
    data = got.data
    if args.linear_density is not None:  # not in CASPR; written only when given (else massless, the default)
        data["cable"]["linear_density_kg_m"] = args.linear_density
        got.assumed.append(
            f"cable.linear_density_kg_m = {args.linear_density:g} kg/m (given on the command line, "
            "--linear-density; CASPR models hold none)"
        )
    default_set = "" if args.cable_set else ", the file's default"
    robot = checked(robot_from_dict(data, source=f"{args.cables} (imported)"), args)
    io.check_output(args.out, (".yaml", ".yml"))
    header = (
        f"# Imported by `cdpr import caspr` from {Path(args.bodies).name} and {Path(args.cables).name}"
        f" (cable set {got.cable_set}{default_set}).\n"
        "# Not from the CASPR files (CASPR models hold no cable stiffness, diameter or dead length):\n"
        + "".join(f"#   {a}\n" for a in got.assumed)
    )
    print(f"cdpr: note: not from the CASPR files: {'; '.join(got.assumed)}", file=sys.stderr)
    for n in got.notes:
        print(f"cdpr: note: {args.cables}: {n}", file=sys.stderr)
    io.write_text(header + yaml.safe_dump(data, sort_keys=False), args.out)
    print(f"wrote {args.out}: {robot.name}, {robot.m} cables, platform {robot.platform.mass:g} kg")


def cmd_import_rrf(args):
    """``cdpr import rrf``: a Hangprinter robot file from a RepRapFirmware configuration's M669 K6 and
    M666 lines (``cdpr.robot_rrf``), validated; the header and one stderr line name every value
    that did not come from the configuration."""
    import yaml  # lazy: yaml, for this command only

    # lazy: the importer, for this command only
    from cdpr.robot import robot_from_dict
    from cdpr.robot_rrf import robot_dict_from_rrf

    io.check_output(args.out, (".yaml", ".yml"))
    data, assumed = robot_dict_from_rrf(args.config, name=args.name)
    robot = robot_from_dict(data, source=f"{args.config} (imported)")
    header = [
        f"# Imported by `cdpr import rrf` from {os.path.basename(args.config)} (RepRapFirmware, Hangprinter: M669 K6, M666).",
        "# A point mass on one cable per anchor through fixed pulleys; a spool winch per cable (M666 R Q U O L H);",
        "# the cable is the U strands of the line (axial stiffness U E S, E S = M666 S); dead length = guy wire / U.",
    ]
    if assumed:
        header.append("# Assumed (not in the configuration): " + "; ".join(assumed) + ".")
        print("cdpr import rrf: assumed (not in the configuration): " + "; ".join(assumed), file=sys.stderr)
    io.write_text("\n".join(header) + "\n" + yaml.safe_dump(data, sort_keys=False), args.out)
    print(f"wrote {args.out}: {robot.m} cables, platform {robot.platform.mass:g} kg")


def _export(args, make):
    """Run an export (``make(robot)`` -> (text, warnings)): warnings on stderr, the text to --out or
    standard output."""
    robot = load_robot(args.robot)
    if args.out:
        io.check_output(args.out, (os.path.splitext(args.out)[1],))  # any name: the folder is checked
    text, warnings = make(robot)
    for w in warnings:
        print(f"warning: {w}", file=sys.stderr)
    if args.out:
        io.write_text(text, args.out)
        print(f"wrote {args.out}")
    else:
        print(text, end="")


def cmd_export_rrf(args):
    """``cdpr export rrf``: RepRapFirmware's M669 and M666 lines of a Hangprinter robot
    (``cdpr.robot_rrf.rrf_lines``; a per-cable buildup factor is exported as its mean, with a
    warning)."""
    from cdpr.robot_rrf import rrf_lines  # lazy: this command only

    def make(robot):
        lines, warnings = rrf_lines(robot)
        head = (
            f"; Hangprinter {robot.name} written by `cdpr export rrf` from {os.path.basename(args.robot)}\n"
        )
        return head + "\n".join(lines) + "\n", warnings

    _export(args, make)


def cmd_export_klipper(args):
    """``cdpr export klipper``: Klipper's ``[printer] kinematics: winch`` and ``[stepper_a..]``
    anchors of a Hangprinter robot (``cdpr.robot_rrf.klipper_text``; Klipper has no buildup model,
    said on stderr)."""
    from cdpr.robot_rrf import klipper_text  # lazy: this command only

    _export(args, klipper_text)


def cmd_view(args):
    """``cdpr view``: a 3-D picture of a robot file at a desired pose (frame box, pulleys with their
    swivel axes and sheaves, platform, cables; ``--box``: a box drawn as a wireframe; ``--plan``: the
    plan (top) view beside it), drawn by
    ``cdpr.pipeline.plots.robot.robot_view`` (a .pdf beside the .png)."""
    # lazy: the pose geometry, the workspace boxes and matplotlib, for `cdpr view` only
    from cdpr.analyses import scans, workspace
    from cdpr.pipeline.plots import robot as robot_plots

    robot = checked(load_robot(args.robot), args)
    io.check_output(args.out, (".png",))
    boxes = {"frame box": workspace.frame_box(robot)}
    if args.box is not None:
        try:
            boxes["--box"] = workspace.check_box(args.box).tolist()
        except CdprError as exc:
            raise CdprError(f"--box: {exc}") from None
    p = scans.view_position(robot) if args.at is None else np.asarray(args.at, dtype=float)
    robot_plots.robot_view(scans.pose_geometry(robot, p, args.rotvec), args.out, boxes=boxes, plan=args.plan)
    print(f"wrote {args.out}")


def cmd_compile(args):
    """``cdpr compile [--part ...]``: compile (or load from numba's cache) the kernels of the
    families asked for on a few poses of the shipped robots (``cdpr.pipeline.kernels.warm``), and
    say how long it took on stderr. ``make reproduce`` runs two of these side by side before its
    two studies, so that the kernels are compiled once, not by both studies at once."""
    from cdpr.pipeline import kernels  # lazy: the pipeline (pandas), for this command only

    folder = Path(args.robots)
    for name in ("cdpr4.yaml", "cogiro.yaml", "cogiro_massless.yaml", "cube50.yaml"):
        if not (folder / name).is_file():
            raise CdprError(
                f"--robots {folder}: no {name} there (the shipped config/robots folder is needed)"
            )
    t = time.perf_counter()
    done = kernels.warm(folder, args.part, threads=1)
    print(f"cdpr: compiled {', '.join(done)} in {time.perf_counter() - t:.0f} s", file=sys.stderr)
    return 0


def cmd_study_check(args):
    """``cdpr study check FILE``: the validation the pipeline makes before any job
    (``cdpr.pipeline.study.check_file``), without Snakemake. Each problem is one line on stderr and
    the exit code is 2; a valid study prints ``ok`` (exit 0)."""
    from cdpr.pipeline.study import check_file  # lazy: the pipeline (pandas), for this command only

    problems = check_file(args.file, args.results)
    for p in problems:
        print(f"cdpr: error: {p}", file=sys.stderr)
    if problems:
        return 2
    print("ok")
    return 0
