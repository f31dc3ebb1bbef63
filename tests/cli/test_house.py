"""The command line's house: the rules' commands and options exist (the job registry itself:
tests/cli/test_job.py; the parser's choices against their owners: tests/cli/test_options.py), every
import inside a function says why, and start-up loads only what a command needs."""

import argparse
import ast
import re
import subprocess
import sys

import pytest

from cdpr.cli import job
from cdpr.cli.parser import build_parser
from tests.conftest import ROBOTS, ROOT

RULES = sorted((ROOT / "workflow" / "rules").glob("*.smk")) + [ROOT / "Snakefile"]
CLI = sorted((ROOT / "cdpr" / "cli").glob("*.py")) + [
    ROOT / "cdpr" / "__main__.py",
    ROOT / "cdpr" / "__init__.py",
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


def test_no_rule_passes_a_study_value_as_command_line_text():
    """The study's solver options and a job's design reach the library as values of the study
    (``cdpr job NAME --study``, ``SolverOptions``, ``study.design_robot``), not as command-line text
    parsed back; every solver-table rule declares the study keys its job reads, so that Snakemake
    reruns it when one changes."""
    rules = sorted((ROOT / "workflow" / "rules").glob("*.smk"))
    text = "\n".join(f.read_text() for f in rules)
    for flag in (
        "--redundancy",
        "--method",
        "--dead-length",
        "--pulley kind",
        "--h ",
        "--rp",
        "--rotvec",
        "--E {params",
    ):
        assert flag not in text, flag
    for rule in ("plane_table", "trajectory_table", "volume_shard", "workspace_grid", "elasticity_path"):
        body = re.search(rf"rule {rule}:\n(.*?)\n\n\n", text + "\n\n\n", re.S).group(1)
        for key in ("dead_length_m", "solver", "redundancy", "rotvec_rad"):
            assert f'"{key}"' in body, (rule, key)
        assert f"job {rule.replace('_', '-')}" in body, rule


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
        assert not {"numpy", "pandas", "numba", "tqdm", "cdpr.robot", "importlib.metadata"} & mods, argv


def test_one_point_loads_no_pandas_and_no_scipy_spatial():
    code, mods = imported(
        "point", "--robot", str(ROBOTS / "cdpr4.yaml"), "--at", "0.5", "0.2", "2.5", "--json"
    )
    assert code == 0 and "cdpr.compiled.subsets" in mods
    assert not {m for m in mods if m == "pandas" or m.startswith("pandas.")}
    # scipy.spatial (0.2-0.4 s with scipy.sparse) is imported where a hull or a rotation is built
    assert "scipy.spatial" not in mods and "scipy.sparse" not in mods
    # the engine switch (cdpr.solve) imports every compiled twin; numba loads a kernel's cached
    # machine code on its first call only, so the other twins cost their module's import (~20 ms)
    assert "cdpr.pipeline.tasks" not in mods and "cdpr.tables" not in mods and "cdpr.table_io" not in mods
    assert "tqdm" not in mods  # the progress bar: tables on a terminal only
