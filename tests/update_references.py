"""Recompute the quick runs from scratch and copy their tables and figures over the regression
references (tests/reference/<run>) and the figure baselines (tests/baseline/<run>).

Run by `make update-references`. The runs are made exactly as the test suite makes them
(tests/quick_runs.py: a working folder outside the tree, the figure audit on), in a temporary
folder that is removed afterwards, so the baselines are what the tests will compare with."""

import shutil
import tempfile
from pathlib import Path

from tests.pipeline.test_figures import BASELINE
from tests.pipeline.test_figures import RUNS as FIGURE_RUNS
from tests.quick_runs import make_workdir, run_quick
from tests.test_workflow import CASES, RUNS

ROOT = Path(__file__).resolve().parents[1]

with tempfile.TemporaryDirectory(prefix="cdpr-references-") as tmp:
    results = run_quick(make_workdir(Path(tmp) / "work dir é"))
    for run, table in CASES:
        dst = ROOT / "tests" / "reference" / run / table
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(results / RUNS[run] / table, dst)
        print(f"updated {dst.relative_to(ROOT)}")

    # Baseline PNGs of every figure of the quick runs (tests/pipeline/test_figures.py compares with them).
    shutil.rmtree(BASELINE, ignore_errors=True)
    for run in FIGURE_RUNS:
        src = results / run
        for png in sorted(src.rglob("*.png")):
            dst = BASELINE / run / png.relative_to(src)
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(png, dst)
            print(f"updated {dst.relative_to(ROOT)}")
