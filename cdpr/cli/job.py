"""``cdpr job NAME --study FILE --opt ...``: the pipeline tasks of ``cdpr.pipeline.tasks`` (run by Snakemake).

The registry is read from the tasks themselves: every public function of ``cdpr.pipeline.tasks``
(but the helpers in ``HELPERS``) is a job, named after the function with ``_`` → ``-`` unless
``ALIASES`` says otherwise; its parameters after the study ``st`` are the job's options
(``--box-file`` for ``box_file``), required unless the parameter has a default. What an option
means (its help, whether it takes many files, whether it names a file the job writes) is said once,
in ``OPTIONS``, keyed by parameter name. workflow/rules/*.smk and users call these names and
options: tests/cli/test_house.py checks that every one the rules use exists.

This module imports the pipeline (pandas and the analyses): ``cdpr.cli.parser`` imports it only when
the command is ``job``.
"""

from __future__ import annotations

import inspect
from typing import Callable, NamedTuple

from cdpr import io
from cdpr.cli.options import non_negative, threads
from cdpr.errors import CdprError
from cdpr.pipeline import sag, solver_tables, tasks
from cdpr.pipeline.study import load_study

#: Job names that are not the task's name with ``_`` → ``-`` (kept as the rules and users spell them).
ALIASES = {
    "regular_workspace": "rw",
    "doe_results": "doe",
    "map_rows": "map",
    "budget_tables": "budget",
}
#: Public functions of ``cdpr.pipeline.tasks`` that are helpers of the tasks, not jobs.
HELPERS = ("concat",)
#: The modules whose public functions are the jobs: the tasks, the solver tables of a study's
#: designs (``cdpr.pipeline.solver_tables``) and what sag adds (``cdpr.pipeline.sag``).
TASK_MODULES = (tasks, solver_tables, sag)


class Option(NamedTuple):
    """What one task parameter is on the command line."""

    help: str
    #: "value": one value; "files": one or more input files; "out": a file the job writes (its
    #: folder and extension are checked before the job starts).
    kind: str = "value"
    #: argparse type of a "value" (None: the text as given).
    type: Callable | None = None


#: Every task parameter (but ``st``), keyed by its name: help text, kind and type.
OPTIONS = {
    "tables": Option("input tables (matched by file name)", "files"),
    "paths": Option("path tables (matched by file name)", "files"),
    "table": Option("output table", "out"),
    "figure": Option("output figure (.png; a .pdf is written beside it)", "out"),
    "json": Option("output JSON", "out"),
    "effects": Option("output effects table", "out"),
    "effects_figure": Option("output effects figure", "out"),
    "minmax_figure": Option("output min/max figure", "out"),
    "map": Option("output map table", "out"),
    "lines": Option("output lines table", "out"),
    "bands": Option("output bands table", "out"),
    "crossings": Option("output crossings table", "out"),
    "paths_figure": Option("output figure of the paths", "out"),
    "markdown": Option("output summary.md", "out"),
    "results": Option("results folder of the study"),
    "box_file": Option("JSON with the RW_C box"),
    "robot_key": Option("robot label of the study"),
    "pulley": Option("pulley design label of the study (a key of pulleys)"),
    "path_label": Option("path label of the study (a key of trajectories.paths)"),
    "test": Option("DOE test number (Table 2)", type=int),
    "modulus": Option("label of a Young's modulus of elasticity.E_path_Pa (as in the file name)"),
    "label": Option("robot_pulley label"),
    "kind": Option("pulley kind"),
    "d": Option("dead length [m]", type=non_negative),
    "threads": Option("solver threads", type=threads),
    "comparison": Option("comparison file (config/comparisons/*.yaml)"),
    "path_table": Option("output table along the path", "out"),
    "design": Option("design label of the study's optimal designs"),
    "case": Option("uncompensated | compensated"),
    "shard": Option("0-based shard index"),
    "points": Option("output per-point table", "out"),
    "path": Option("output path table", "out"),
    "sobol": Option("output Sobol table", "out"),
    "tolerances": Option("output table of the all-parameter samples", "out"),
    "agreement": Option("output agreement table", "out"),
    "sobol_figure": Option("output Sobol figure", "out"),
    "map_figure": Option("output map figure", "out"),
    "agreement_figure": Option("output agreement figure", "out"),
    "residual_figure": Option("output figure of what compensation leaves", "out"),
}


class Job(NamedTuple):
    """One ``cdpr job NAME``: the task function, its option names in signature order, the required ones."""

    func: Callable
    params: tuple
    required: tuple


def task_functions():
    """{name: function}: the public functions defined in the ``TASK_MODULES`` but ``HELPERS``, in
    source order."""
    return {
        name: f
        for module in TASK_MODULES
        for name, f in vars(module).items()
        if inspect.isfunction(f)
        and f.__module__ == module.__name__
        and not name.startswith("_")
        and name not in HELPERS
    }


def job_name(func_name):
    """The job name of a task: ``ALIASES`` or the function name with ``_`` → ``-``."""
    return ALIASES.get(func_name, func_name.replace("_", "-"))


def option(param):
    """The command-line spelling of a task parameter (``box_file`` → ``--box-file``)."""
    return "--" + param.replace("_", "-")


def registry():
    """{job name: Job} from the signatures of the tasks (first parameter ``st``, the study)."""
    out = {}
    for name, f in task_functions().items():
        params = list(inspect.signature(f).parameters.values())
        if not params or params[0].name != "st":
            raise TypeError(f"{f.__module__}.{name}: a task's first parameter is the study `st`")
        unknown = [p.name for p in params[1:] if p.name not in OPTIONS]
        if unknown:
            raise TypeError(
                f"{f.__module__}.{name}: parameter(s) {', '.join(unknown)} have no entry in cdpr.cli.job.OPTIONS"
            )
        out[job_name(name)] = Job(
            f,
            tuple(p.name for p in params[1:]),
            tuple(p.name for p in params[1:] if p.default is inspect.Parameter.empty),
        )
    return out


#: name -> Job, every task of cdpr.pipeline.tasks.
JOBS = registry()


def add_arguments(sp):
    """The job subparser's arguments: NAME, --study and every task parameter as an option (sorted)."""
    sp.add_argument("name", choices=list(JOBS))
    sp.add_argument(
        "--study", required=True, metavar="FILE", help="the study file (validated as by the pipeline)"
    )
    for n in sorted({n for job in JOBS.values() for n in job.params}):
        o = OPTIONS[n]
        if o.kind == "files":
            sp.add_argument(option(n), nargs="+", metavar="FILE", help=o.help)
        elif o.type is not None:
            sp.add_argument(option(n), type=o.type, help=o.help)
        else:
            sp.add_argument(option(n), help=o.help)


def run(args):
    """Run job ``args.name``: validate the study, refuse a missing option or an output file that
    cannot be written, then call the task with the named files."""
    st = load_study(args.study)
    job = JOBS[args.name]
    given = {n: getattr(args, n) for n in job.params}
    missing = [option(n) for n in job.required if given[n] is None]
    if missing:
        raise CdprError(f"job {args.name} needs {', '.join(missing)}")
    for n in job.params:
        if OPTIONS[n].kind == "out" and given[n] is not None:
            io.check_output(given[n])
    job.func(st, **given)
