"""Issue 41: Markdown tables that do not break. A ``|`` inside a cell (``||dp||``) is escaped by the
writers (``cdpr.io.md_row``), so every row keeps its header's column count; a missing number is
said in words, never ``nan``; no row names the project's development history ("issue 11")."""

import re
import subprocess
import types

import numpy as np
import pandas as pd
import pytest

from cdpr import io
from cdpr.pipeline import calibration, comparison, conclusions, summary
from tests.conftest import ROOT

#: A cell boundary: a ``|`` not escaped by a backslash.
BOUNDARY = re.compile(r"(?<!\\)\|")


def table_problems(text):
    """(line number, cells, header's cells) of every table row whose column count differs from its
    table's header (a table: consecutive lines starting with ``|``)."""
    out, header = [], None
    for n, line in enumerate(text.splitlines(), 1):
        if not line.startswith("|"):
            header = None
            continue
        cells = len(BOUNDARY.split(line.strip())) - 2
        if header is None:
            header = cells
        elif cells != header:
            out.append((n, cells, header))
    return out


def test_the_check_can_fail():
    assert table_problems("| a | b |\n|---|---|\n| ||dp|| | 1 |\n") == [(3, 6, 2)]
    assert table_problems("| a | b |\n|---|---|\n" + io.md_row(["||dp||", 1]) + "\n") == []


def _rows():
    return pd.DataFrame(
        {
            "quantity": ["SR* residual, median of ||dp|| over RW_C", "plain"],
            "source": ["beyond the paper (uncertainty study)", "Paty 3.3.1"],
            "paper": [np.nan, 1.0],
            "ours": [2.5, np.nan],
            "unit": ["mm", "m"],
            "tolerance": [0.0, 0.1],
            "verdict": ["no paper value", "reproduced"],
            "note": ["a | b, line\nbreak", ""],
        }
    )


def test_summary_writer_keeps_the_column_count():
    text = "\n".join(summary.summary_table(_rows()))
    assert table_problems(text) == [] and "\\|\\|dp\\|\\|" in text and "nan" not in text


def test_comparison_and_calibration_writers_keep_the_column_count():
    df = pd.DataFrame({"what": ["median ||dp||", "x"], "value": [1.5, float("nan")]})
    assert table_problems("\n".join(comparison._md_table(df, ["what", "value"], ["what", "value"]))) == []
    text = calibration.md_table(df, ["what", "value"])
    assert table_problems(text) == [] and "nan" not in text


def test_conclusions_writer_keeps_the_column_count():
    st = {"name": "s", "doe": {"robot": "R"}}
    rows = pd.DataFrame(
        {
            "group": ["g"],
            "quantity": ["median ||dp||"],
            "statement": ["a | b"],
            "paper": [np.nan],
            "reference": [1.0],
            "robot": [2.0],
            "unit": ["mm"],
            "claim_reference": [True],
            "claim_robot": [False],
            "verdict": ["reverses"],
            "verdict_paper": [np.nan],
            "note": ["n"],
            "headline": [True],
        }
    )
    text = conclusions.conclusions_page(st, st, rows)
    assert table_problems(text) == [] and "median \\|\\|dp\\|\\|" in text


def test_a_line_without_valley_points_is_said_in_words():
    r = types.SimpleNamespace(
        valley_points=0, slope_k=float("nan"), h_opt_m=float("nan"), r_p_opt_m=float("nan")
    )
    note = summary._line_note(r)
    assert "nan" not in note and "no slope k" in note and "no optimal h, r_p" in note
    r = types.SimpleNamespace(valley_points=5, slope_k=0.5, h_opt_m=0.1, r_p_opt_m=0.05)
    assert summary._line_note(r) == "slope k = 0.5 from 5 valley points; h = 100 mm, r_p = 50 mm"


def test_no_summary_source_names_an_issue():
    assert not [v for v in summary.paper_values() if re.search(r"issue \d", str(v.get("source", "")))]


TRACKED = subprocess.run(
    ["git", "ls-files", "results/*.md", "results/**/*.md"], cwd=ROOT, capture_output=True, text=True
).stdout.split()
#: Tracked summaries written before the writers escaped cells (none: `make reproduce` rewrote them
#: on 2026-12-06; a name here is expected to fail, strictly, until the next `make reproduce`).
STALE = set()


@pytest.mark.parametrize(
    "path",
    [
        pytest.param(
            p, marks=pytest.mark.xfail(strict=True, reason="written before escaping; needs make reproduce")
        )
        if p in STALE
        else p
        for p in TRACKED
    ],
)
def test_every_tracked_markdown_table_row_has_its_headers_column_count(path):
    assert table_problems((ROOT / path).read_text()) == []


def test_no_tracked_results_page_prints_nan_or_names_an_issue():
    """Issue 41: a missing number is said in words, and a reader has no 'issue 11': every tracked
    results/**/*.md, as written by the pipeline."""
    assert TRACKED  # the check reads something
    bad = []
    for path in TRACKED:
        text = (ROOT / path).read_text()
        bad += [(path, m.group(0)) for m in re.finditer(r"\bnan\b|\bissue \d+", text, flags=re.I)]
    assert not bad, bad[:10]
    assert re.search(r"\bnan\b", "slope k = nan from 0 valley points") and re.search(
        r"\bissue \d+", "beyond (issue 11)"
    )
