"""The ``cdpr`` command line's parser: ``build_parser()``.

Standard library and ``cdpr.cli.options`` only, so that ``cdpr --help`` and a usage error answer
without loading numpy; each subcommand names the function that runs it (``run``: module, function),
imported by ``cdpr.cli.main`` once the arguments are read.
"""

from __future__ import annotations

from cdpr.cli import caspr, view
from cdpr.cli.options import (
    CALIBRATION_MODELS,
    CALIBRATION_SIGMA,
    DISTRIBUTIONS,
    ENGINES,
    MAX_STEPS,
    Parser,
    box_option,
    count,
    finite,
    groups,
    linear_density_option,
    non_negative,
    physics_options,
    points_options,
    positive,
    quiet_option,
    reached_options,
    robot_options,
    rotvec_option,
    sensitivity_options,
    solver_options,
    threads,
    wrench_option,
)

#: The exit-code contract, in ``cdpr --help`` and in the commands that report a status.
STATUS_EPILOG = (
    "Exit code 0 for every computed result whatever its status (ok, slack, infeasible, not_converged, "
    "inaccessible, ...): scripts read the 'status' key of --json, not the exit code. Exit code 2: a refused "
    "input (one line on stderr); 1: an output that could not be written."
)


def build_parser(jobs=True):
    """The ``cdpr`` parser. ``jobs=False`` leaves out the options of ``cdpr job`` (their registry imports the
    pipeline): ``cdpr.cli.main`` asks for them only when the command is ``job``."""
    ap = Parser(
        prog="cdpr",
        description="Pose errors of cable-driven parallel robots from pulleys, cable elasticity and winch geometry.",
        epilog=STATUS_EPILOG,
    )
    sub = ap.add_subparsers(dest="command", required=True, parser_class=Parser)
    sp = sub.add_parser(
        "inverse", help="extended inverse model of every cable at a point (or a table of points)"
    )
    robot_options(sp)
    points_options(sp, "platform position")
    sp.add_argument(
        "--tensions",
        nargs="+",
        type=positive,
        metavar="N",
        help="tensions at the platform per cable [N] (one pose, --at): the heavy cables' catenaries, exit points "
        "and rest lengths under them (docs/heavy_cables.md)",
    )
    sp.set_defaults(run=("cdpr.cli.inverse", "cmd_inverse"))
    sp = sub.add_parser(
        "point",
        help="DEGM_E at a point (or a table of points): solved pose, |dp|, tensions, subset, status",
        epilog=STATUS_EPILOG,
    )
    robot_options(sp)
    solver_options(sp)
    points_options(sp, "desired position")
    physics_options(sp)
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
    sp.add_argument(
        "--motor-deg",
        nargs="+",
        type=finite,
        metavar="DEG",
        help="motor angles per cable [deg] from the reference at the origin (robot with spool winches; physical mode): "
        "mapped to rest lengths by the spool model",
    )
    wrench_option(sp)
    sensitivity_options(sp)
    reached_options(sp)
    sp.set_defaults(run=("cdpr.cli.commands", "cmd_point"))
    sp = sub.add_parser(
        "compensate",
        help="compensated rest lengths: what to command so that the platform reaches --at",
        epilog=STATUS_EPILOG,
    )
    robot_options(sp)
    sp.add_argument("--E", type=positive, metavar="PA", help="Young's modulus E [Pa] of every cable")
    linear_density_option(sp)
    sp.add_argument(
        "--E-cables",
        nargs="+",
        type=positive,
        metavar="PA",
        help="Young's modulus of each cable [Pa] (the model)",
    )
    sp.add_argument("--mass", type=positive, metavar="KG", help="platform mass M [kg]")
    wrench_option(sp)
    points_options(sp, "desired position")
    sp.add_argument(
        "--distribution",
        choices=DISTRIBUTIONS,
        default="min_norm",
        help="tension distribution (default min_norm: least 2-norm within [t-min, t-max]; closed_form, "
        "closed_form_improved: Pott's; subset: the paper's 3-cable subset, point-mass robots only)",
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
        choices=ENGINES,
        default=None,
        help="engine of the check solve (default: numpy below 500 poses of massless cables, else compiled; cdpr.solve.check_engine)",
    )
    sp.add_argument("--threads", type=threads, help="threads of the compiled engine")
    sp.set_defaults(run=("cdpr.cli.commands", "cmd_compensate"))
    sp = sub.add_parser("grid", help="DEGM_E over the n^3 cell-centred grid of a box; writes parquet or CSV")
    robot_options(sp)
    solver_options(sp)
    box = sp.add_mutually_exclusive_group()  # one box: giving two would silently ignore one
    box_option(box)
    box.add_argument(
        "--box-file", metavar="FILE", help="JSON file whose key 'box' holds the six numbers (e.g. rw_c.json)"
    )
    box.add_argument(
        "--frame",
        action="store_true",
        help="the frame's bounding box (anchors' extent, z from 0 to the pulleys)",
    )
    sp.add_argument("--n", type=count(1), required=True, help="points per axis")
    rotvec_option(sp, help="fixed platform orientation [rad]")
    sp.add_argument(
        "--wrench-feasible",
        action="store_true",
        help="add a 'feasible' column: a tension distribution in [--t-min, T_a] holds the platform at the pose; "
        "prints the feasible volume and the largest axis-aligned box of ok and feasible points (whole grids)",
    )
    sp.add_argument(
        "--t-min", type=non_negative, default=100.0, metavar="N", help="least tension of --wrench-feasible"
    )
    wrench_option(sp)
    sp.add_argument(
        "--interference",
        action="store_true",
        help="add the interference columns at each grid pose (interference_free, n_cc, n_cp, dmin_m, cc_pairs, "
        "cp_cables; docs/interference.md) and print the count of interference-free points",
    )
    sp.add_argument("--out", required=True, metavar="FILE", help="output .parquet or .csv")
    sp.add_argument("--shard", type=count(0), default=0, help="0-based shard index (default 0)")
    sp.add_argument("--shards", type=count(1), default=1, help="number of shards (default 1)")
    physics_options(sp)
    sensitivity_options(sp)
    quiet_option(sp)
    sp.set_defaults(run=("cdpr.cli.commands", "cmd_grid"))
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
    sp.set_defaults(run=("cdpr.cli.winch", "cmd_winch"))
    sp = sub.add_parser("plane", help="DEGM_E over a horizontal plane (Fig. 9, 12); writes a table")
    robot_options(sp)
    solver_options(sp)
    sp.add_argument("--z", type=finite, required=True, metavar="M", help="plane height [m]")
    sp.add_argument(
        "--n", type=count(2, 20000), required=True, help="points per side over the anchors' bounding box"
    )
    sp.add_argument("--out", required=True, metavar="FILE")
    rotvec_option(sp)
    physics_options(sp)
    wrench_option(sp)
    sp.set_defaults(run=("cdpr.cli.commands", "cmd_plane"))
    sp = sub.add_parser(
        "trajectory", help="DEGM_E along a straight path (Fig. 10, 19); writes a table with arc length s"
    )
    robot_options(sp)
    solver_options(sp)
    sp.add_argument("--start", nargs=3, type=finite, required=True, metavar=("X", "Y", "Z"))
    sp.add_argument("--end", nargs=3, type=finite, required=True, metavar=("X", "Y", "Z"))
    sp.add_argument("--n", type=count(2, 100_000_000), required=True, help="points along the path")
    sp.add_argument("--out", required=True, metavar="FILE")
    rotvec_option(sp)
    physics_options(sp)
    wrench_option(sp)
    sp.set_defaults(run=("cdpr.cli.commands", "cmd_trajectory"))
    sp = sub.add_parser(
        "interference",
        help="cable-cable and cable-platform interference at a pose (or a table of poses)",
    )
    robot_options(sp)
    points_options(sp, "platform position (reference point)")
    linear_density_option(sp)
    sp.add_argument(
        "--lengths",
        nargs="+",
        type=positive,
        metavar="M",
        help="rest lengths L0 per cable [m] (with --at): test the pose the platform settles at under them "
        "(heavy cables: their catenaries); default: the desired pose itself, heavy cables under their "
        "sag-consistent compensated lengths",
    )
    sp.set_defaults(run=("cdpr.cli.interference", "cmd_interference"))
    sp = sub.add_parser("job", help="a pipeline task: tables in, tables and figures out (run by Snakemake)")
    if jobs:
        from cdpr.cli import job  # lazy: the job registry imports the pipeline (pandas); for `cdpr job` only

        job.add_arguments(sp)
    sp.set_defaults(run=("cdpr.cli.job", "run"))
    sp = sub.add_parser("study", help="study files: check one without running Snakemake")
    studies = sp.add_subparsers(dest="study_command", required=True, parser_class=Parser)
    c = studies.add_parser(
        "check",
        help="the pipeline's validation of a study file, without Snakemake: one line per problem (exit 2) or 'ok'",
    )
    c.add_argument("file", metavar="FILE", help="study YAML file (config/studies/*.yaml)")
    c.add_argument("--results", metavar="DIR", help="also check the results folder the study would write")
    c.set_defaults(run=("cdpr.cli.robot_files", "cmd_study_check"))
    sp = sub.add_parser(
        "compile",
        help="compile the numba kernels into their cache now (once, before studies run side by side)",
    )
    sp.add_argument(
        "--part",
        nargs="+",
        choices=("paper", "physical", "platform", "heavy"),
        default=["paper", "physical", "platform", "heavy"],
        help="kernel families (default: every one); split them over processes to compile in parallel",
    )
    sp.add_argument(
        "--robots",
        metavar="DIR",
        default="config/robots",
        help="the shipped robot files (default config/robots)",
    )
    sp.set_defaults(run=("cdpr.cli.robot_files", "cmd_compile"))
    calibrate_parser(sub)
    caspr.add_parser(sub)
    view.add_parser(sub)
    return ap


_GROUPS_HELP = (
    "comma-separated groups: anchors (A_i), dead_lengths (d_i), moduli (E_i), pulleys (h_i, r_p_i), "
    "offsets (encoder offsets), mass (M); attachments (b_i) for 6-DoF platforms; linear_densities "
    "(rho_i) for heavy cables; on motor-angle data "
    "(motor_deg_1..m) anchors and spools (r0_i, Q_i)"
)
_PRIOR_HELP = (
    "prior sd per group, e.g. anchors=5mm,dead_lengths=50mm,moduli=20%%,pulleys=1mm,offsets=50mm,mass=5%%,"
    "attachments=3mm,linear_densities=20%% "
    "(these are the defaults; moduli, mass and linear_densities relative); on motor-angle data anchors=5mm,spools=1mm"
)


def calibration_wrench_option(sp):
    """Adds ``--wrench`` to a ``calibrate`` command: the external wrench on the platform while the data
    were taken (a tool's weight), on the nominal and the fitted robot alike, not written into the robot."""
    wrench_option(
        sp,
        "external wrench on the platform while the data were taken (e.g. a tool's weight), beside gravity: "
        "force [N] (world frame, at the platform's reference point) and moment [N m] about that point (world "
        "frame; 0 on a point mass); acts on the nominal and the fitted robot, not written into a robot file; "
        "default none",
    )


def calibrate_parser(subparsers):
    """Add ``calibrate`` with its commands ``fit``, ``check``, ``cv``, ``plan`` and ``study`` (``cdpr.cli.calibrate``)."""
    cp = subparsers.add_parser("calibrate", help="identify a robot's parameters from measurements")
    sub = cp.add_subparsers(dest="calibrate_command", required=True, parser_class=Parser)

    sp = sub.add_parser("fit", help="MAP estimate of parameter groups from measured poses; writes the robot")
    sp.add_argument("--robot", required=True, metavar="FILE", help="nominal robot YAML (the prior mean)")
    sp.add_argument("--data", required=True, metavar="FILE", help="measurements CSV (docs/calibration.md)")
    sp.add_argument("--estimate", required=True, type=groups, metavar="GROUPS", help=_GROUPS_HELP)
    sp.add_argument("--prior", metavar="G=SD,...", help=_PRIOR_HELP)
    sp.add_argument(
        "--model",
        choices=CALIBRATION_MODELS,
        default="exact",
        help="exact: pulleys and elastic cables (default), and on a robot file with winch: the drums (the lengths "
        "are the controller's commands, realised through the no-winch drum model); standard: straight lines to "
        "fixed points, rigid cables, no drums",
    )
    sp.add_argument(
        "--loss",
        choices=("linear", "soft_l1", "huber", "cauchy"),
        default="linear",
        help="least-squares loss (default linear); a robust one down-weights and lists outliers",
    )
    sp.add_argument("--out", required=True, metavar="FILE", help="calibrated robot YAML to write")
    sp.add_argument(
        "--report", metavar="DIR", help="write per-sample and per-parameter tables and figures here"
    )
    calibration_wrench_option(sp)
    sp.add_argument("--json", action="store_true", help="print JSON")
    sp.set_defaults(run=("cdpr.cli.calibrate", "cmd_fit"))

    sp = sub.add_parser("check", help="a robot's predictions against measured samples")
    sp.add_argument("--robot", required=True, metavar="FILE")
    sp.add_argument(
        "--data",
        required=True,
        metavar="FILE",
        help="CSV with commanded lengths L1..Lm and poses, or motor angles motor_deg_1..m (positions solved from them)",
    )
    sp.add_argument(
        "--model",
        choices=CALIBRATION_MODELS,
        default="exact",
        help="motor-angle data: exact (line stretch from force_N_i where given, default) or standard (rigid lines)",
    )
    calibration_wrench_option(sp)
    sp.add_argument("--json", action="store_true", help="print JSON")
    sp.set_defaults(run=("cdpr.cli.calibrate", "cmd_check"))

    sp = sub.add_parser("cv", help="K-fold cross-validation of a calibration from motor-angle data")
    sp.add_argument("--robot", required=True, metavar="FILE", help="nominal robot YAML (the prior mean)")
    sp.add_argument(
        "--data",
        required=True,
        metavar="FILE",
        help="motor-angle CSV: sample, motor_deg_1..m, optional force_N_1..m, x_m, y_m, z_m",
    )
    sp.add_argument(
        "--estimate",
        type=groups,
        metavar="GROUPS",
        help="anchors, spools (comma-separated); not with --fixed",
    )
    sp.add_argument(
        "--prior", metavar="G=SD,...", help="prior sd, e.g. anchors=150mm,spools=1mm (defaults 5mm, 1mm)"
    )
    sp.add_argument(
        "--model",
        choices=CALIBRATION_MODELS,
        default="exact",
        help="exact: line stretch from the measured forces (default); standard: rigid lines",
    )
    sp.add_argument(
        "--folds",
        required=True,
        type=count(2, 100000),
        metavar="K",
        help="fold k holds the rows i with i mod K = k; K = number of samples is leave-one-out",
    )
    sp.add_argument("--fixed", action="store_true", help="score the robot file as given, without fitting")
    sp.add_argument("--json", action="store_true", help="print JSON")
    sp.set_defaults(run=("cdpr.cli.calibrate", "cmd_cv"))

    sp = sub.add_parser("plan", help="D-optimal poses to measure for a calibration")
    sp.add_argument("--robot", required=True, metavar="FILE")
    sp.add_argument("--estimate", required=True, type=groups, metavar="GROUPS", help=_GROUPS_HELP)
    sp.add_argument("--prior", metavar="G=SD,...", help=_PRIOR_HELP)
    sp.add_argument("--n", type=count(1, 10000), default=30, help="poses in the plan (default 30)")
    box_option(
        sp, "candidate box [m] (default: middle 80 %% of the anchors' extent, z 10-70 %% of their height)"
    )
    sp.add_argument(
        "--grid", type=count(1, 10000), default=7, help="candidates per axis of the box (default 7)"
    )
    sp.add_argument(
        "--sigma",
        type=positive,
        default=CALIBRATION_SIGMA,
        metavar="M",
        help="tracker noise sd [m] (default 2e-4)",
    )
    sp.add_argument(
        "--command",
        choices=("standard", "compensated"),
        default="standard",
        help="commanded lengths of the candidates: standard L_TS (default) or, for a 6-DoF platform, "
        "compensated (minimum-norm tensions; a fully constrained robot needs them)",
    )
    sp.add_argument("--out", metavar="FILE", help="write the plan (CSV: sample, L1..Lm, expected pose)")
    calibration_wrench_option(sp)
    sp.add_argument("--json", action="store_true", help="print JSON")
    sp.set_defaults(run=("cdpr.cli.calibrate", "cmd_plan"))

    sp = sub.add_parser(
        "study",
        help="a calibration study (config/studies/calibration*.yaml; hangprinter.yaml: the real Hangprinter sessions)",
    )
    sp.add_argument("--study", required=True, metavar="FILE", help="calibration study YAML")
    sp.add_argument("--out", required=True, metavar="DIR", help="results folder (results/calibration)")
    sp.set_defaults(run=("cdpr.cli.calibrate", "cmd_study"))
    return cp
