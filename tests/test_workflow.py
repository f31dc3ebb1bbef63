"""The whole DAG on small studies: the quick study against committed reference tables (the
end-to-end run of a user's own design is tests/test_own_design.py). Regenerate the references with `make update-references`.

Snakemake runs in a working folder under pytest's temporary folder (``work``): the repository's
``config/`` is linked there (robot files), the study and comparison files are copies (a test may
edit them), and the results, Snakemake's ``.snakemake/`` and the logs stay there, so the test
suite writes nothing into the working tree. Its path has a space and a non-ASCII letter: every
path that reaches a shell command is quoted."""

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tests.conftest import ROOT
from tests.quick_runs import make_workdir, snakemake

REF = ROOT / "tests" / "reference" / "quick"
#: The quick study runs in both redundancy modes, then their comparison: reference folder -> results
#: folder under the working folder's results/ (the physical run has the same tables as the paper run).
RUNS = {"quick": "quick", "quick_physical": "quick_physical", "quick_comparison": "quick_comparison"}
#: Tables compared with the references (paths under results/quick/).
TABLES = [
    "summary.csv",
    "doe/doe.csv",
    "doe/effects.csv",
    "doe/rw_max.csv",
    "volumes/volumes.csv",
    "maps/map.csv",
    "maps/lines.csv",
    "trajectories/trajectories_minmax.csv",
    "elasticity/index_vs_E.csv",
    "elasticity/bands.csv",
    "elasticity/crossings.csv",
    "dead_length/dead_length.csv",
    "trajectories/CDPR4_SR.csv",
    "trajectories/CDPR3_DR.csv",
    "winch/winch.csv",
    "uncertainty/bands.csv",
    "uncertainty/agreement.csv",
    "uncertainty/sobol.csv",
    "uncertainty/DRopt_uncompensated_path.csv",
]
#: Tables only the physical run writes (the compensated robot is physical in both modes: computed once).
PHYSICAL_TABLES = ["uncertainty/SRopt_compensated_map.csv"]
#: Tables of the comparison of the two quick runs (results/quick_comparison/).
COMPARISON_TABLES = ["conclusions.csv", "budget.csv", "difference_stats.csv"]
#: (run, table) pairs compared with tests/reference/<run>/<table>.
CASES = (
    [("quick", t) for t in TABLES]
    + [("quick_physical", t) for t in TABLES + PHYSICAL_TABLES]
    + [("quick_comparison", t) for t in COMPARISON_TABLES]
)
RTOL, ATOL = 1e-6, 1e-9


@pytest.fixture
def work(quick_work):
    """The session's working folder of the quick runs (tests/quick_runs.py)."""
    return quick_work


@pytest.fixture
def quick(quick_results):
    """results/quick of the session's quick runs (paper mode, physical mode, their comparison)."""
    return quick_results / "quick"


@pytest.mark.parametrize("run,table", CASES, ids=[f"{r}/{t}" for r, t in CASES])
def test_quick_study_matches_references(quick, run, table):
    assert_table_matches(quick.parent / RUNS[run] / table, ROOT / "tests" / "reference" / run / table, table)


#: Columns that count the solver's work rather than give a result: the Newton iterations of a 6-DoF
#: point include those of its restarts, which start where the Hessian test (LAPACK's eigvalsh) or the
#: taut-set count sits at a threshold, and the last bits of the arithmetic differ between CPUs (AVX-512
#: or not). Measured: CoGiRo DR at two corners of the quick spatial plane takes 27 and 32 iterations
#: on one machine, 18 and 15 on another, and reaches the same pose to the last bit (|Δ dp| = 0). They
#: are compared as counts (positive where the other is), not as numbers.
WORK_COLUMNS = {"iterations"}


def assert_table_matches(ours_path, ref_path, table):
    """A results table against its reference: same columns and rows, numbers within RTOL/ATOL
    (``WORK_COLUMNS``: both positive or both not), every other column's text equal (``table``
    names it in the message)."""
    ours, ref = pd.read_csv(ours_path), pd.read_csv(ref_path)
    assert list(ours.columns) == list(ref.columns) and len(ours) == len(ref), (
        f"{table}: shape or columns changed"
    )
    for col in ref.columns:
        if col in WORK_COLUMNS:
            assert ((ours[col] > 0) == (ref[col] > 0)).all(), f"{table}: column {col}"
        elif pd.api.types.is_numeric_dtype(ref[col]) and pd.api.types.is_numeric_dtype(ours[col]):
            np.testing.assert_allclose(
                ours[col], ref[col], rtol=RTOL, atol=ATOL, err_msg=f"{table}: column {col}"
            )
        else:
            assert ours[col].fillna("").astype(str).tolist() == ref[col].fillna("").astype(str).tolist(), (
                f"{table}: column {col}"
            )


def test_quick_study_writes_every_figure_and_the_summary(quick):
    for fig in [
        "winch/winch.png",
        "plane/CDPR4.png",
        "plane/CDPR3.png",
        "plane/CDPR4_subsets.png",
        "trajectories/trajectories.png",
        "trajectories/trajectories_minmax.png",
        "volumes/R_V.png",
        "volumes/CDPR3_SR_VL.png",
        "doe/responses.png",
        "doe/effects.png",
        "maps/maps.png",
        "elasticity/index_vs_E.png",
        "elasticity/paths.png",
        "dead_length/dead_length.png",
        "uncertainty/index.png",
        "uncertainty/path.png",
        "uncertainty/sobol.png",
        "uncertainty/dominant.png",
        "uncertainty/agreement.png",
    ]:
        assert (quick / fig).stat().st_size > 0 and (quick / fig).with_suffix(".pdf").stat().st_size > 0, fig
    text = (quick / "summary.md").read_text()
    assert "| winch dl at l_pm = 0 | Metillon Fig. 7b | 1.46 |" in text


def test_quick_physical_run_and_comparison_write_their_figures_and_page(quick):
    phys = quick.parent / "quick_physical"
    assert "redundancy physical" in (phys / "summary.md").read_text()
    plane = pd.read_csv(phys / "plane" / "CDPR4_DR.csv")
    assert {"taut", "n_taut"} <= set(plane.columns) and "subset" not in plane.columns
    assert (phys / "plane" / "CDPR4_subsets.png").stat().st_size > 0  # Fig. 9: the taut sets
    folder = quick.parent / "quick_comparison"
    for fig in ("difference.png", "budget.png", "budget_paths.png"):
        assert (folder / fig).stat().st_size > 0 and (folder / fig).with_suffix(".pdf").stat().st_size > 0
    page = (quick.parent / "quick_comparison.md").read_text()
    assert (
        "## Headline: the paper's conclusions under physics" in page
        and "](quick_comparison/budget.png)" in page
    )
    rows = pd.read_csv(folder / "conclusions.csv")
    assert set(rows.verdict) <= {"holds", "changes", "reverses", "undetermined"}
    assert rows.headline.any() and all(st in page for st in rows[rows.headline].statement)
    b = pd.read_csv(folder / "budget.csv").set_index(["design", "region", "entry"]).mean_m
    assert (b.xs("none", level="entry") < 1e-7).all() and (
        b.xs("compensated_all", level="entry") < 1e-9
    ).all()


def test_bad_study_value_stops_before_any_job(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(
        (ROOT / "config" / "studies" / "quick.yaml").read_text().replace("solver: newton", "solver: magic")
    )
    work = make_workdir(tmp_path / "w")
    p = snakemake("reproduce_paper", f"study={bad}", f"results={tmp_path / 'r'}", quiet=False, cwd=work)
    assert p.returncode != 0
    assert (
        "invalid study configuration" in p.stdout + p.stderr
        and "bad.yaml: key 'solver'" in p.stdout + p.stderr
    )
    assert not (tmp_path / "r").exists()


def _dry_run_rules(work, quick_study_text=None):
    """Rules a dry run of the quick study (in the working folder ``work``) would run, after its
    study file is replaced by ``quick_study_text`` (the file is restored afterwards)."""
    path = work / "studies" / "quick.yaml"
    original = path.read_bytes()
    try:
        if quick_study_text is not None:
            path.write_text(quick_study_text)
        exe = Path(sys.executable).with_name("snakemake")
        p = subprocess.run(
            [str(exe), "reproduce_paper", "--snakefile", str(ROOT / "Snakefile"), "-n", "--quiet", "rules"]
            + ["--cores", "1", "--config", "study=studies/quick.yaml", "results=results/quick"],
            cwd=work,
            capture_output=True,
            text=True,
        )
    finally:
        path.write_bytes(original)
    assert p.returncode == 0, p.stderr[-2000:]
    text = p.stdout + p.stderr
    return {
        line.split()[0]
        for line in text.splitlines()
        if len(line.split()) == 2 and line.split()[1].isdigit() and line.split()[0] not in ("total", "job")
    }


#: Documented results of the quick study, intermediate ones included, and the rule that writes each.
DELETED = [
    ("doe/rw_c.json", "regular_workspace"),
    ("plane/CDPR4_SR.csv", "plane_table"),
    ("shards/volume/CDPR3_DR_1.parquet", "volume_shard"),
    ("elasticity/path_DRopt_E1.022e+11.csv", "elasticity_path"),
    ("uncertainty/SRopt_uncompensated_map.csv", "uq_design"),
    ("volumes/CDPR3_SR_VL.pdf", "volume_view"),
]


@pytest.mark.parametrize("rel,rule", DELETED, ids=[r for r, _ in DELETED])
def test_a_deleted_result_is_rebuilt(quick, work, rel, rule):
    """Issue 20: every documented output is a target, so a missing one is scheduled again (the
    file is put back, with its time stamp, afterwards)."""
    f, backup = quick / rel, work / "deleted.bak"
    shutil.copy2(f, backup)
    f.unlink()
    try:
        rules = _dry_run_rules(work)
    finally:
        shutil.copy2(backup, f)
    assert rule in rules and "reproduce_paper" in rules, rules
    assert not rules & {"winch_table", "winch_figure"}, rules  # unrelated jobs stay done


def test_editing_a_study_key_reruns_exactly_the_affected_jobs(quick, work):
    text = (work / "studies" / "quick.yaml").read_text()
    assert _dry_run_rules(work) == set()  # the fixture just ran everything: nothing to do
    rules = _dry_run_rules(work, text.replace("limits_m: [0.05, 0.15]", "limits_m: [0.05, 0.10]"))
    # parity draws summary.csv: a changed summary redraws it
    assert rules == {"volumes", "volume_view", "summary", "parity", "reproduce_paper"}, rules
    rules = _dry_run_rules(
        work,
        text.replace(
            "paper_rw_c_m: [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]",
            "paper_rw_c_m: [-2.3, 2.3, -2.3, 2.3, 0.0, 3.7]",
        ),
    )
    assert {"regular_workspace", "index_shard", "doe", "summary"} <= rules and not rules & {
        "winch_table",
        "plane_table",
        "volume_shard",
    }, rules
