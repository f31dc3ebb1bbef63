"""The SLURM profile against the workflow, without SLURM: every rule it names exists, every rule with
a command is either a solver rule the profile groups or one of the `localrules` of
workflow/rules/cluster.smk (never both, never neither), and its groups form a valid DAG with the
expected number of group jobs. `make test-slurm` runs the profile on a real SLURM cluster."""

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tests.conftest import ROOT
from tests.quick_runs import make_workdir

PROFILE = yaml.safe_load((ROOT / "workflow" / "profiles" / "slurm" / "config.yaml").read_text())
CLUSTER_SMK = (ROOT / "workflow" / "rules" / "cluster.smk").read_text()


def localrules():
    block = re.search(r"^localrules:\n((?:[ \t]+\w+,?\n)+)", CLUSTER_SMK, re.M).group(1)
    return set(re.findall(r"\w+", block))


def profile_args():
    """The profile's grouping and resource keys as command-line options (the rest of the profile
    needs the SLURM plugin)."""
    p = PROFILE
    args = ["--groups", *(f"{r}={g}" for r, g in p["groups"].items())]
    args += ["--group-components", *(f"{g}={n}" for g, n in p["group-components"].items())]
    args += ["--resources", *(f"{k}={v}" for k, v in p["resources"].items())]
    args += ["--set-resource-scopes", *(f"{k}={v}" for k, v in p["set-resource-scopes"].items())]
    args += ["--default-resources", *(f"{k}={v}" for k, v in p["default-resources"].items())]
    args += [
        "--set-resources",
        *(f"{r}:{k}={v}" for r, res in p["set-resources"].items() for k, v in res.items()),
    ]
    return args


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    """Snakemake's working folder: outside the tree (Snakemake writes .snakemake/ there, even for a dry
    run), with ``config/`` linked to the repository's, so that config/studies/... and the study files'
    robot paths resolve as from the repository (``make_workdir``)."""
    return make_workdir(tmp_path_factory.mktemp("snakemake") / "work", studies=())


@pytest.fixture(scope="module", params=["quick", "paper", "quick_spatial"])
def dry_run(request, work):
    """(study, rule -> has a shell command, number of group jobs) of a dry run with the profile's groups."""
    exe = Path(sys.executable).with_name("snakemake")
    p = subprocess.run(
        [
            str(exe),
            "reproduce_paper",
            "--snakefile",
            str(ROOT / "Snakefile"),
            "-n",
            "-p",
            "--forceall",
            "--cores",
            "2",
            *profile_args(),
            "--config",
            f"study=config/studies/{request.param}.yaml",
            f"results=results/dry_{request.param}",
        ],
        cwd=work,
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    rules, rule = {}, None
    for line in p.stdout.splitlines():
        m = re.match(r"^\s*(?:local)?rule (\w+):$", line)
        if m:
            rule = m.group(1)
            rules.setdefault(rule, False)
        elif line.startswith("Shell command: ") and line != "Shell command: None":
            rules[rule] = True
    return request.param, rules, len(re.findall(r"^\[.*\] Group job ", p.stdout, re.M))


def test_every_rule_is_either_local_or_grouped(dry_run):
    _, rules, _ = dry_run
    grouped, local = set(PROFILE["groups"]), localrules()
    assert not grouped & local, f"both local and grouped: {grouped & local}"
    with_command = {r for r, shell in rules.items() if shell}
    assert with_command - grouped - local == set(), (
        "rules that would be single SLURM jobs: add to groups or localrules"
    )


def defined_rules(work):
    """Every rule the workflow defines (``snakemake --list-rules`` in the working folder ``work``),
    whether a study's DAG has it or not (``conclusions`` runs only in a study that names a reference)."""
    exe = Path(sys.executable).with_name("snakemake")
    p = subprocess.run(
        [
            str(exe),
            "--list-rules",
            "--snakefile",
            str(ROOT / "Snakefile"),
            "--config",
            "study=config/studies/quick.yaml",
            "results=results/dry_quick",
        ],
        cwd=work,
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    return set(p.stdout.split())


def test_profile_and_cluster_name_only_defined_rules(work):
    grouped, local = set(PROFILE["groups"]), localrules()
    assert (grouped | local) - defined_rules(work) == set(), (
        "rules named in the profile or cluster.smk that the workflow lacks"
    )


def test_profile_names_only_existing_rules(dry_run, work):
    """Every rule the profile gives resources is defined (``defined_rules``: a rule need not be in
    the quick or paper DAG, as ``study_budget_design`` of a spatial study)."""
    _, rules, _ = dry_run
    assert set(PROFILE["set-resources"]) - defined_rules(work) == set()
    assert set(PROFILE["set-resources"]) == set(PROFILE["groups"]), (
        "every solver rule needs measured resources"
    )


def test_no_partition_account_or_cpu_override():
    defaults = PROFILE["default-resources"]
    assert not {"slurm_partition", "slurm_account", "cpus_per_task"} & set(defaults)
    assert all("cpus_per_task" not in r for r in PROFILE["set-resources"].values())
    assert PROFILE["slurm-status-command"] == "squeue"


def test_group_job_count(dry_run):
    """The number of SLURM jobs docs/pipeline.md states (solver jobs / group-components, per group)."""
    study, _, groups = dry_run
    assert groups == {"quick": 3, "paper": 3, "quick_spatial": 3}[study]
