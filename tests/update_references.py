"""Copy the quick runs' tables (results/quick, results/quick_physical, results/quick_comparison) over
the regression references (tests/reference/<run>).

Run by `make update-references`, after it recomputed the quick study in both modes and their
comparison from scratch."""

import shutil
from pathlib import Path

from tests.test_workflow import CASES, RUNS

ROOT = Path(__file__).resolve().parents[1]

for run, table in CASES:
    dst = ROOT / "tests" / "reference" / run / table
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(ROOT / "results" / RUNS[run] / table, dst)
    print(f"updated {dst.relative_to(ROOT)}")
