"""Recompute the quick runs from scratch and copy their tables and figures over the regression
references (tests/reference/<run>) and the figure baselines (tests/baseline/<run>); then the same
for the quick study of a spatial robot (tests/reference/quick_spatial, tests/baseline_spatial/).

Run by `make update-references` (``python -m tests.update_references``; ``--only quick`` or
``--only quick_spatial`` recomputes one of the two). The runs are made exactly as the test suite makes
them (tests/quick_runs.py: a working folder outside the tree, the figure audit on), in a temporary
folder that is removed afterwards, so the references and baselines are what the tests will compare
with."""

import argparse
import shutil
import tempfile
from pathlib import Path

from tests.pipeline.test_figures import BASELINE
from tests.pipeline.test_figures import RUNS as FIGURE_RUNS
from tests.quick_runs import SPATIAL_STUDY, make_workdir, run_quick, run_quick_spatial
from tests.test_workflow import CASES, RUNS
from tests.test_workflow_spatial import BASELINE as SPATIAL_BASELINE
from tests.test_workflow_spatial import REF as SPATIAL_REF
from tests.test_workflow_spatial import TABLES as SPATIAL_TABLES

ROOT = Path(__file__).resolve().parents[1]


def _copy(src, dst):
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(src, dst)
    print(f"updated {dst.relative_to(ROOT)}")


def update_quick(tmp):
    """The quick study in both modes and their comparison (tests/test_workflow.py, test_figures.py)."""
    results = run_quick(make_workdir(Path(tmp) / "work dir é"))
    for run, table in CASES:
        _copy(results / RUNS[run] / table, ROOT / "tests" / "reference" / run / table)

    # Baseline PNGs of every figure of the quick runs (tests/pipeline/test_figures.py compares with them).
    shutil.rmtree(BASELINE, ignore_errors=True)
    for run in FIGURE_RUNS:
        src = results / run
        for png in sorted(src.rglob("*.png")):
            _copy(png, BASELINE / run / png.relative_to(src))


def update_quick_spatial(tmp):
    """The quick spatial study (tests/test_workflow_spatial.py): its own working folder, as its fixture."""
    results = run_quick_spatial(make_workdir(Path(tmp) / "spatial work dir é", studies=(SPATIAL_STUDY,)))
    shutil.rmtree(SPATIAL_REF, ignore_errors=True)
    for table in SPATIAL_TABLES:
        _copy(results / table, SPATIAL_REF / table)
    shutil.rmtree(SPATIAL_BASELINE, ignore_errors=True)
    for png in sorted(results.rglob("*.png")):
        _copy(png, SPATIAL_BASELINE / png.relative_to(results))


UPDATES = {"quick": update_quick, SPATIAL_STUDY: update_quick_spatial}

if __name__ == "__main__":
    parser = argparse.ArgumentParser(prog="python -m tests.update_references", description=__doc__)
    parser.add_argument("--only", choices=list(UPDATES), help="recompute only these references")
    args = parser.parse_args()
    for name, update in UPDATES.items():
        if args.only in (None, name):
            with tempfile.TemporaryDirectory(prefix="cdpr-references-") as tmp:
                update(tmp)
