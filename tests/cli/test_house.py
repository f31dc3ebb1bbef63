"""The command line's house: the job registry read from the tasks, the rules' commands and options
exist, the parser's choices agree with their owners, and start-up loads only what a command needs."""

import argparse
import ast
import inspect
import re
import subprocess
import sys

import pytest

from cdpr.cli import job, options
from cdpr.cli.main import main
from cdpr.cli.parser import build_parser
from cdpr.pipeline import tasks
from tests.conftest import ROBOTS, ROOT

RULES = sorted((ROOT / "workflow" / "rules").glob("*.smk")) + [ROOT / "Snakefile"]
CLI = sorted((ROOT / "cdpr" / "cli").glob("*.py")) + [
    ROOT / "cdpr" / "__main__.py",
    ROOT / "cdpr" / "__init__.py",
]
#: The job names users and the rules know (issue 16: every one kept exactly).
KNOWN_JOBS = [
    "winch-figure",
    "plane-figure",
    "subsets-figure",
    "trajectories",
    "volumes",
    "volume-view",
    "volumes-dphi",
    "rw",
    "robot-view",
    "doe",
    "map",
    "maps",
    "elasticity",
    "dead-length-point",
    "dead-length",
    "summary",
    "budget-design",
    "budget",
    "comparison",
    "uq-shard",
    "uq-design",
    "uncertainty",
]


def shell_commands():
    """Every ``{params.cdpr} ...`` command of the rules: (file, the concatenated shell string)."""
    out = []
    for f in RULES:
        text = f.read_text()
        for block in re.finditer(r"shell:\s*\n((?:[ \t]*f?\"[^\"\n]*\"[ \t]*\n)+)", text):
            cmd = "".join(re.findall(r"\"([^\"\n]*)\"", block.group(1)))
            if "{params.cdpr}" in cmd:
                out.append((f.name, cmd))
    return out


def subparser(name):
    ap = build_parser()
    sub = next(a for a in ap._actions if a.dest == "command")
    return sub.choices[name]


def option_strings(parser):
    return {s for a in parser._actions for s in a.option_strings}


def test_the_rules_are_found():
    cmds = shell_commands()
    jobs = {re.search(r"\{params\.cdpr\} job ([a-z-]+)", c).group(1) for _, c in cmds if " job " in c}
    assert len(cmds) >= 25 and len(jobs) >= 18, (len(cmds), jobs)


@pytest.mark.parametrize("where,cmd", shell_commands(), ids=lambda x: x if len(x) < 40 else x[14:50])
def test_every_command_and_option_of_the_rules_exists(where, cmd):
    m = re.search(r"\{params\.cdpr\} ([a-z-]+)(?: ([a-z-]+))?", cmd)
    command = m.group(1)
    parser = subparser(command)
    if command == "job":
        assert m.group(2) in job.JOBS, (where, m.group(2))
        allowed = {"--study"} | {job.option(n) for n in job.JOBS[m.group(2)].params}
    else:
        nested = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        if nested:  # a command with commands of its own (cdpr calibrate study ...)
            assert m.group(2) in nested[0].choices, (where, m.group(2))
            parser = nested[0].choices[m.group(2)]
        allowed = option_strings(parser)
    used = set(re.findall(r"(?<![\w-])(--[a-z][a-z-]*)", cmd.split(">")[0]))
    assert used and used <= allowed, (where, sorted(used - allowed))


def test_the_design_options_of_common_smk_exist():
    text = (ROOT / "workflow" / "rules" / "common.smk").read_text()
    used = set(re.findall(r"(--[a-z][a-z-]*) \{", text))
    assert {"--pulley", "--dead-length", "--method", "--redundancy", "--h", "--rp"} <= used
    for command in ("grid", "plane", "trajectory"):
        assert used <= option_strings(subparser(command)), command


def test_every_public_task_has_a_job_and_every_known_name_stays():
    public = {
        n
        for n, f in vars(tasks).items()
        if inspect.isfunction(f) and f.__module__ == tasks.__name__ and not n.startswith("_")
    }
    assert public - set(job.HELPERS) == set(job.task_functions())
    assert {job.JOBS[j].func.__name__ for j in job.JOBS} == public - set(job.HELPERS)
    # every known name stays, in its order (the order of tasks.py, shown by --help); new jobs may join
    assert [j for j in job.JOBS if j in KNOWN_JOBS] == KNOWN_JOBS
    assert set(job.HELPERS) <= public  # a helper that disappears from tasks.py is dropped from HELPERS too


def test_job_options_follow_the_signatures():
    for name, j in job.JOBS.items():
        sig = inspect.signature(j.func).parameters
        assert list(sig)[0] == "st" and j.params == tuple(list(sig)[1:]), name
        assert j.required == tuple(p for p in j.params if sig[p].default is inspect.Parameter.empty), name
    assert job.JOBS["map"].required == ("kind", "box_file", "table")  # threads has a default
    ap = subparser("job")
    helps = {a.option_strings[0]: a.help for a in ap._actions if a.option_strings}
    for n in {n for j in job.JOBS.values() for n in j.params}:
        assert helps[job.option(n)] == job.OPTIONS[n].help, n
    assert set(job.OPTIONS) == {n for j in job.JOBS.values() for n in j.params}  # no stale entry


def test_a_task_parameter_without_an_option_entry_is_refused(monkeypatch):
    def new_task(st, table, colour):
        """A task with a parameter OPTIONS does not know."""

    monkeypatch.setattr(tasks, "new_task", new_task, raising=False)
    new_task.__module__ = tasks.__name__
    with pytest.raises(TypeError, match="new_task: parameter.*colour"):
        job.registry()


def test_job_missing_options_and_outputs_are_named(tmp_path, capsys):
    study = str(ROOT / "config" / "studies" / "quick.yaml")
    assert main(["job", "maps", "--study", study, "--tables", "a.csv", "--box-file", "b.json"]) == 2
    assert capsys.readouterr().err == "cdpr: error: job maps needs --map, --lines, --figure\n"
    code = main(
        ["job", "dead-length", "--study", study, "--tables", "a.csv", "--table", str(tmp_path / "t.txt")]
        + ["--figure", str(tmp_path / "f.png")]
    )
    err = capsys.readouterr().err
    assert code == 2 and "t.txt" in err and err.count("\n") == 1


def test_choices_agree_with_their_owners():
    from cdpr.robot import PULLEY_KINDS
    from cdpr.solve import ENGINES, REDUNDANCY

    assert options.PULLEY_KINDS == PULLEY_KINDS
    assert options.ENGINES == tuple(ENGINES)
    assert set(options.METHODS) == {m for ms in ENGINES.values() for m in ms}
    assert options.REDUNDANCY == REDUNDANCY
    from cdpr.analyses import calibration

    assert options.CALIBRATION_MODELS == calibration.MODELS
    assert options.CALIBRATION_SIGMA == calibration.SIGMA_DEFAULT


def test_every_import_inside_a_function_says_why():
    bad = []
    for f in CLI:
        lines = f.read_text().splitlines()
        tree = ast.parse("\n".join(lines))
        top = {id(n) for n in tree.body}
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)) and id(node) not in top:
                here = lines[node.lineno - 1]
                above = lines[node.lineno - 2].strip()
                # a block of lazy imports may share one comment on the line above the first
                k = node.lineno - 2
                while (
                    not above.startswith("# lazy:")
                    and k > 0
                    and lines[k].strip().startswith(("from ", "import "))
                ):
                    k -= 1
                    above = lines[k].strip()
                if "# lazy:" not in here and not above.startswith("# lazy:"):
                    bad.append(f"{f.name}:{node.lineno}")
    assert not bad, bad


def imported(*argv):
    """The modules a ``python -m cdpr ...`` process imports (from -X importtime)."""
    p = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "cdpr", *argv], capture_output=True, text=True, cwd=ROOT
    )
    mods = {
        line.rsplit("|", 1)[1].strip() for line in p.stderr.splitlines() if line.startswith("import time:")
    }
    return p.returncode, mods


def test_help_and_usage_errors_load_no_numpy():
    for argv in (["--help"], ["point", "--help"], ["point", "--robot", "x.yaml"], ["grid", "--n", "0"]):
        code, mods = imported(*argv)
        assert code in (0, 2) and mods, argv
        assert not {"numpy", "pandas", "numba", "cdpr.robot", "importlib.metadata"} & mods, argv


def test_one_point_loads_no_pandas():
    code, mods = imported(
        "point", "--robot", str(ROBOTS / "cdpr4.yaml"), "--at", "0.5", "0.2", "2.5", "--json"
    )
    assert code == 0 and "cdpr.compiled.subsets" in mods
    assert not {m for m in mods if m == "pandas" or m.startswith("pandas.")}
    # the engine switch (cdpr.solve) imports every compiled twin; numba loads a kernel's cached
    # machine code on its first call only, so the other twins cost their module's import (~20 ms)
    assert "cdpr.pipeline.tasks" not in mods and "cdpr.tables" not in mods and "cdpr.table_io" not in mods


def test_job_help_lists_every_job_and_option(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["job", "--help"])
    out = capsys.readouterr().out
    assert exc.value.code == 0
    assert all(j in out for j in KNOWN_JOBS)
    assert all(job.option(n) in out for n in job.OPTIONS)
