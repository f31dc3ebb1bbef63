"""Argument types and the option groups the commands share (standard library only).

This module is imported to build the parser, also for ``cdpr --help``: it must not import numpy, pandas or
any layer of cdpr above the ground floor (``cdpr.io`` is standard library only). The choices that belong to those layers are spelled here and a
test (tests/cli/test_options.py) checks them against their owners (``cdpr.robot.PULLEY_KINDS``,
``cdpr.solve.ENGINES``, ``cdpr.solve.REDUNDANCY``).
"""

from __future__ import annotations

import argparse
import math
import os
import re

from cdpr.io import is_plain_number

#: Pulley kinds of ``--pulley`` (the same as ``cdpr.robot.PULLEY_KINDS``).
PULLEY_KINDS = ("fixed", "SR", "DR")
#: DEGM_E solvers of ``--method`` (the methods of ``cdpr.solve.ENGINES``).
METHODS = ("newton", "fixed_point")
#: Engines of ``--engine`` (the keys of ``cdpr.solve.ENGINES``).
ENGINES = ("compiled", "numpy")
#: Redundancy modes of ``--redundancy`` (``cdpr.solve.REDUNDANCY``).
REDUNDANCY = ("paper", "physical")
#: Tension distributions of ``cdpr compensate --distribution``.
DISTRIBUTIONS = ("min_norm", "closed_form", "closed_form_improved", "subset")
#: Largest winch table a command writes.
MAX_STEPS = 10_000_000
#: Rows of a ``--points`` table solved and written at a time (``--chunk-rows``): bounds the memory of
#: a large table (docs/cli.md, "Large tables").
CHUNK_ROWS = 20_000
#: ``cdpr calibrate fit --model`` (``cdpr.analyses.calibration.MODELS``).
CALIBRATION_MODELS = ("exact", "standard")
#: ``cdpr calibrate plan --sigma`` default [m] (``cdpr.analyses.calibration.SIGMA_DEFAULT``).
CALIBRATION_SIGMA = 0.2e-3
#: A number, also in exponent notation and negative ("-1e-1"): argparse must not take it for an option.
_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-inf(inity)?$", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``cdpr: error: ...``, exit 2) and negative numbers in exponent
    notation read as numbers."""

    def __init__(self, *a, **k):
        super().__init__(*a, **k)
        self._negative_number_matcher = _NUMBER

    def error(self, message):
        self.exit(2, f"cdpr: error: {self.prog.removeprefix('cdpr ')}: {message}\n")


def finite(text):
    """argparse type: a finite float in plain decimal or exponent notation (``2.5``, ``-1e-3``); Python's
    other float spellings (``1_0`` read as 10, ``0x1p3``) and decimal commas are refused."""
    if not is_plain_number(text):
        hint = " (use a decimal point, not a comma)" if "," in text else ""
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a number{hint}; allowed: plain decimal or exponent notation, e.g. 2.5 or 2.5e-3"
        )
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return v


#: The largest coordinate of a position [m] the commands take (1000 km): beyond it squared distances
#: lose every digit of a robot's size, and near 1e154 they overflow to inf.
MAX_COORDINATE_M = 1e6


def coordinate(text):
    """argparse type: a position coordinate [m], a finite float within ±``MAX_COORDINATE_M``."""
    v = finite(text)
    if abs(v) > MAX_COORDINATE_M:
        raise argparse.ArgumentTypeError(
            f"{text!r} is beyond ±{MAX_COORDINATE_M:g} m; a position must be within it"
        )
    return v


class BoxAction(argparse.Action):
    """argparse action of ``--box XMIN XMAX YMIN YMAX ZMIN ZMAX``: each minimum below its maximum, so
    that a reversed box is refused by the parser, naming the option, before any work."""

    def __call__(self, parser, namespace, values, option_string=None):
        if not (values[0] < values[1] and values[2] < values[3] and values[4] < values[5]):
            raise argparse.ArgumentError(
                self, f"a box needs XMIN < XMAX, YMIN < YMAX and ZMIN < ZMAX, got {values}"
            )
        setattr(namespace, self.dest, values)


def box_option(parser, help=None):
    """Adds ``--box XMIN XMAX YMIN YMAX ZMIN ZMAX`` [m] to ``parser`` (a parser or a group): six finite
    numbers, a reversed box refused by ``BoxAction``."""
    parser.add_argument(
        "--box",
        nargs=6,
        type=finite,
        action=BoxAction,
        metavar=("XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"),
        help=help,
    )


def wrench_option(sp, help=None):
    """Adds ``--wrench FX FY FZ MX MY MZ``: an external wrench beside gravity, force [N] in the world
    frame at the platform's reference point and moment [N m] about it in the world frame (six finite
    numbers; a moment on a point mass is refused by ``robot.with_wrench``); ``help`` replaces the
    default help text."""
    sp.add_argument(
        "--wrench",
        nargs=6,
        type=finite,
        metavar=("FX", "FY", "FZ", "MX", "MY", "MZ"),
        help=help
        or "external wrench beside gravity: force [N] (world frame, at the platform's reference point) and "
        "moment [N m] about that point (world frame; 0 on a point mass); default none",
    )


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


def threads(text):
    """argparse type: a thread count, 1 to the number of cores."""
    return count(1, os.cpu_count() or 1)(text)


def robot_options(sp):
    """--robot FILE and the per-cable overrides every robot command takes, and --json."""
    sp.add_argument("--robot", required=True, metavar="FILE", help="robot YAML file (config/robots/*.yaml)")
    sp.add_argument("--pulley", choices=PULLEY_KINDS, help="pulley kind for every cable")
    sp.add_argument("--h", type=non_negative, metavar="M", help="lever arm h [m] for every cable")
    sp.add_argument("--rp", type=non_negative, metavar="M", help="sheave radius r_p [m] for every cable")
    sp.add_argument("--dead-length", type=non_negative, metavar="M", help="dead length d [m] for every cable")
    sp.add_argument("--json", action="store_true", help="print JSON")


def linear_density_option(sp):
    """--linear-density KG_PER_M: every cable's mass per unstrained metre [kg/m] (heavy cables)."""
    sp.add_argument(
        "--linear-density",
        type=non_negative,
        metavar="KG_PER_M",
        help="mass per unstrained metre [kg/m] of every cable (heavy cables; default the robot file's, 0: massless)",
    )


def solver_options(sp):
    """--E, --linear-density, --mass and the solver switch (--method, --engine, --threads)."""
    sp.add_argument("--E", type=positive, metavar="PA", help="Young's modulus E [Pa] of every cable")
    linear_density_option(sp)
    sp.add_argument("--mass", type=positive, metavar="KG", help="platform mass M [kg]")
    sp.add_argument("--method", choices=METHODS, default="newton", help="DEGM_E solver (default newton)")
    sp.add_argument(
        "--engine",
        choices=ENGINES,
        default=None,
        help="compiled numba kernel (default for newton; Newton only) or the numpy reference (default for fixed_point, and for `point` below 500 poses of massless cables)",
    )
    sp.add_argument(
        "--threads",
        type=threads,
        help="threads of the compiled engine (1 to the number of cores; default: all)",
    )


def physics_options(sp):
    """--redundancy and --E-cables."""
    sp.add_argument(
        "--redundancy",
        choices=REDUNDANCY,
        default=None,
        help="paper: the best admissible 3-cable subset (the paper's rule; the default for a point mass on massless "
        "cables); physical: the platform settles where the forces of all cables balance, each free to go slack (the "
        "default, and the only mode, for a rigid platform or heavy cables)",
    )
    sp.add_argument(
        "--E-cables",
        nargs="+",
        type=positive,
        metavar="PA",
        help="Young's modulus of each cable [Pa], cable 1 first",
    )


def rotvec_option(
    sp, help="platform orientation: rotation vector [rad] (active, base frame; default identity)"
):
    """--rotvec RX RY RZ: the platform's orientation [rad] (spatial robots, docs/spatial.md), or
    --euler-xyz-deg A B C, the same orientation as CASPR's Euler XYZ angles in degrees (intrinsic
    x, then y', then z'': R = Rx(A) Ry(B) Rz(C)); one or the other. ``cdpr.cli.main`` turns the
    angles into ``args.rotvec`` before the command runs."""
    g = sp.add_mutually_exclusive_group()
    g.add_argument("--rotvec", nargs=3, type=finite, metavar=("RX", "RY", "RZ"), help=help)
    g.add_argument(
        "--euler-xyz-deg",
        nargs=3,
        type=finite,
        metavar=("A", "B", "C"),
        help="platform orientation as CASPR's Euler XYZ angles [deg] (intrinsic: R = Rx(A) Ry(B) Rz(C)), "
        "instead of --rotvec",
    )


def points_options(sp, what):
    """--at X Y Z or --points FILE, --out FILE and --rotvec."""
    g = sp.add_mutually_exclusive_group(required=True)
    g.add_argument("--at", nargs=3, type=coordinate, metavar=("X", "Y", "Z"), help=f"{what} [m]")
    g.add_argument(
        "--points",
        metavar="FILE",
        help="many points at once: a .csv or .parquet table with columns x, y, z [m] (and rx, ry, rz [rad])",
    )
    sp.add_argument(
        "--out", metavar="FILE", help="write the result table (.csv or .parquet); needed with --points"
    )
    rotvec_option(sp)
    sp.add_argument(
        "--chunk-rows",
        type=count(1, 10_000_000),
        default=CHUNK_ROWS,
        metavar="N",
        help=f"rows of --points read, solved and written at a time (default {CHUNK_ROWS}); bounds the memory",
    )
    quiet_option(sp)


def quiet_option(sp):
    """--quiet: nothing on stderr but errors (no progress bar, expected time or compile notice)."""
    sp.add_argument(
        "--quiet",
        action="store_true",
        help="nothing on stderr but errors (no progress bar, expected time or compile notice)",
    )


def sensitivity_options(sp):
    """--sensitivities."""
    sp.add_argument(
        "--sensitivities",
        action="store_true",
        help="also dP*/dθ for every parameter (E_i [Pa], h_i, r_p_i, d_i, A_i_x/y/z [m], M [kg]; cables from 1) "
        "at fixed commanded lengths, by the implicit-function theorem; Newton only. A spatial robot (rigid "
        "platform, tilted pulleys) also gets dφ*/dθ [rad per unit] and θ gains b_i_x/y/z and c_x/y/z [m]; "
        "there the compiled 6-DoF kernel runs (--engine numpy: the numpy reference)",
    )


def groups(text):
    """argparse type: comma-separated parameter group names (checked by the calibration itself)."""
    return [g.strip() for g in text.split(",") if g.strip()]


def reached_options(sp):
    """--equilibrium and the start of the reached equilibrium (physical mode; docs/interference.md):
    --t-min/--t-max of the compensated start, or --from X Y Z [--from-rotvec] --from-lengths."""
    sp.add_argument(
        "--equilibrium",
        choices=("reached", "global"),
        default="reached",
        help="physical mode's answer: reached (default), the equilibrium the robot reaches when its rest lengths move "
        "continuously from a known equilibrium to the commanded ones; global: the lowest energy over restarts",
    )
    sp.add_argument(
        "--t-min",
        type=non_negative,
        metavar="N",
        help="least tension of the start's compensated lengths [N] (default: the robot's min_tension_N, 100 where it is 0)",
    )
    sp.add_argument(
        "--t-max",
        type=positive,
        metavar="N",
        help="largest tension of the start's compensated lengths [N] (default: each cable's admissible tension)",
    )
    sp.add_argument(
        "--from",
        dest="from_p",
        nargs=3,
        type=finite,
        metavar=("X", "Y", "Z"),
        help="start of the continuation: the robot at equilibrium near this position [m] under --from-lengths",
    )
    sp.add_argument(
        "--from-rotvec",
        nargs=3,
        type=finite,
        metavar=("RX", "RY", "RZ"),
        help="the start's orientation, a rotation vector [rad] (default identity)",
    )
    sp.add_argument(
        "--from-lengths",
        nargs="+",
        type=positive,
        metavar="L",
        help="the start's rest lengths per cable [m] (with --from)",
    )
