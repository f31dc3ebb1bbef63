"""The quick studies run once per test session, shared by the workflow tests (tests/test_workflow.py)
and the figure tests (tests/pipeline/test_figures.py): the quick study in paper mode, in physical
mode, then their comparison, as `make reproduce` does with the paper study, in a working folder
outside the tree (``make_workdir``) with ``CDPR_FIGURE_AUDIT`` set, so that every figure's layout
audit is written beside it (the audit does not change the pixels: ``cdpr.pipeline.plots.style.save``).

The quick study of a spatial robot (``run_quick_spatial``) runs the same way in a working folder
of its own, once per run of tests/test_workflow_spatial.py (not with the quick runs: make test
runs that module on another pytest-xdist worker, in parallel with them)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def snakemake(target, *config, cwd, quiet=True, force=True, extra=()):
    """Run the workflow (the repository's Snakefile) on `target` in the working folder `cwd` with
    `--config key=value ...` (option order matters: both take lists). ``force``: recompute every
    job; a list of rule names forces only those (and what depends on them)."""
    exe = Path(sys.executable).with_name("snakemake")
    q = ["--quiet", "all"] if quiet else []
    f = ["--forceall"] if force is True else (["--forcerun", *force] if force else [])
    return subprocess.run(
        [str(exe), target, "--snakefile", str(ROOT / "Snakefile"), "--cores", "2", *q, *f, *extra]
        + ["--config", *config],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=dict(os.environ, CDPR_FIGURE_AUDIT="1"),
    )


def rule_jobs(p):
    """Jobs per rule {rule: count} of a finished Snakemake dry run ``p`` (``-n --quiet rules``: its
    table of rule and count), which must have succeeded."""
    assert p.returncode == 0, p.stderr[-2000:]
    jobs = {}
    for line in (p.stdout + p.stderr).splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[1].isdigit() and parts[0] not in ("total", "job"):
            jobs[parts[0]] = int(parts[1])
    return jobs


#: The study files a working folder gets by default (``make_workdir``): the quick study in both
#: modes (their comparison file names them) and the example of a user's own design.
QUICK_STUDIES = ("quick", "quick_physical", "example")


def make_workdir(folder, studies=QUICK_STUDIES):
    """A working folder for Snakemake outside the tree: ``config/`` and ``data/`` linked to the repository's,
    the ``studies`` (names of config/studies/*.yaml) copied to ``studies/``, and, when both quick
    studies are among them, the quick comparison file naming them."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "config").symlink_to(ROOT / "config", target_is_directory=True)
    # the Hangprinter study's sessions (data/hangprinter/), inputs of its rule
    (folder / "data").symlink_to(ROOT / "data", target_is_directory=True)
    (folder / "studies").mkdir()
    for name in studies:
        shutil.copy(ROOT / "config" / "studies" / f"{name}.yaml", folder / "studies" / f"{name}.yaml")
    if {"quick", "quick_physical"} <= set(studies):
        (folder / "comparison.yaml").write_text(
            "paper: {study: studies/quick.yaml, results: results/quick}\n"
            "physical: {study: studies/quick_physical.yaml, results: results/quick_physical}\n"
            "page: results/quick_comparison.md\nfolder: results/quick_comparison\n"
            "budget: {index_n: 6, t_min_N: 100.0}\n"
        )
    return folder


#: The rules of the comparison step (forced: their inputs come from the two runs before).
COMPARISON_RULES = ["budget_design", "budget", "comparison"]


def run_quick(work):
    """Run the quick study in both modes and their comparison in the working folder ``work``;
    returns ``work/results`` (folders quick/, quick_physical/, quick_comparison/)."""
    for study in ("quick", "quick_physical"):
        p = snakemake("reproduce_paper", f"study=studies/{study}.yaml", f"results=results/{study}", cwd=work)
        assert p.returncode == 0, p.stderr[-3000:]
    p = snakemake(
        "reproduce_comparison",
        "study=studies/quick.yaml",
        "results=results/quick",
        "comparison=comparison.yaml",
        force=COMPARISON_RULES,
        cwd=work,
    )
    assert p.returncode == 0, p.stderr[-3000:]
    return work / "results"


#: The quick study of a spatial robot (config/studies/quick_spatial.yaml: CoGiRo, rigid platform,
#: physical mode), run by tests/test_workflow_spatial.py on its own, beside the quick runs.
SPATIAL_STUDY = "quick_spatial"


#: The first job of the spatial run, run alone (a plane of CoGiRo, a couple of seconds once
#: compiled): it compiles the 6-DoF kernels (cdpr/compiled/equilibrium.py, about 100 s of one core)
#: into the numba cache, which every later job loads. Started together, the first two solver jobs
#: each compiled them: twice the CPU on a shared machine.
SPATIAL_FIRST = "plane/CoGiRo_SR.csv"


def run_quick_spatial(work):
    """Run the quick spatial study in the working folder ``work`` (``make_workdir(folder,
    studies=(SPATIAL_STUDY,))``), its first job alone (``SPATIAL_FIRST``), then the whole study;
    returns its results folder ``work/results/quick_spatial``."""
    config = (f"study=studies/{SPATIAL_STUDY}.yaml", f"results=results/{SPATIAL_STUDY}")
    for target in (f"results/{SPATIAL_STUDY}/{SPATIAL_FIRST}", "reproduce_paper"):
        p = snakemake(target, *config, cwd=work)
        assert p.returncode == 0, p.stderr[-3000:]
    return work / "results" / SPATIAL_STUDY
