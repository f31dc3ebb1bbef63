"""The quick studies run once per test session, shared by the workflow tests (tests/test_workflow.py)
and the figure tests (tests/pipeline/test_figures.py): the quick study in paper mode, in physical
mode, then their comparison, as `make reproduce` does with the paper study, in a working folder
outside the tree (``make_workdir``) with ``CDPR_FIGURE_AUDIT`` set, so that every figure's layout
audit is written beside it (the audit does not change the pixels: ``plots.save``)."""

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


def make_workdir(folder):
    """A working folder for Snakemake outside the tree: ``config/`` linked to the repository's,
    the studies copied to ``studies/``, and the quick comparison file naming them."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "config").symlink_to(ROOT / "config", target_is_directory=True)
    (folder / "studies").mkdir()
    for name in ("quick", "quick_physical", "example"):
        shutil.copy(ROOT / "config" / "studies" / f"{name}.yaml", folder / "studies" / f"{name}.yaml")
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
