"""Copy the quick study's tables (results/quick) over the regression references (tests/reference/quick).

Run by `make update-references`, after it recomputed the quick study from scratch."""

import shutil
from pathlib import Path

from tests.test_workflow import TABLES

ROOT = Path(__file__).resolve().parents[1]

for table in TABLES:
    dst = ROOT / "tests" / "reference" / "quick" / table
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(ROOT / "results" / "quick" / table, dst)
    print(f"updated {dst.relative_to(ROOT)}")
