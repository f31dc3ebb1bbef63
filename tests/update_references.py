"""Copy the quick runs' tables and figures (results/quick, results/quick_physical, results/quick_comparison) over
the regression references (tests/reference/<run>) and the figure baselines (tests/baseline/<run>).

Run by `make update-references`, after it recomputed the quick study in both modes and their
comparison from scratch."""

import shutil
from pathlib import Path

from tests.pipeline.test_figures import BASELINE
from tests.pipeline.test_figures import RUNS as FIGURE_RUNS
from tests.test_workflow import CASES, RUNS

ROOT = Path(__file__).resolve().parents[1]

for run, table in CASES:
    dst = ROOT / "tests" / "reference" / run / table
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(ROOT / "results" / RUNS[run] / table, dst)
    print(f"updated {dst.relative_to(ROOT)}")

# Baseline PNGs of every figure of the quick runs (tests/pipeline/test_figures.py compares with them).

shutil.rmtree(BASELINE, ignore_errors=True)
for run in FIGURE_RUNS:
    src = ROOT / "results" / run
    for png in sorted(src.rglob("*.png")):
        dst = BASELINE / run / png.relative_to(src)
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(png, dst)
        print(f"updated {dst.relative_to(ROOT)}")
