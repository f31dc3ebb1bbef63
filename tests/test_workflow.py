"""The whole DAG on small studies: the quick study against committed reference tables, and an
end-to-end run of a user's own design. Regenerate the references with `make update-references`."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tests.conftest import ROOT

REF = ROOT / "tests" / "reference" / "quick"
#: The quick study runs in both redundancy modes, then their comparison: reference folder -> results
#: folder under results/ (the physical run has the same tables as the paper run).
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
    "uncertainty/SRopt_compensated_map.csv",
]
#: Tables of the comparison of the two quick runs (results/quick_comparison/).
COMPARISON_TABLES = ["conclusions.csv", "budget.csv", "difference_stats.csv"]
#: (run, table) pairs compared with tests/reference/<run>/<table>.
CASES = (
    [("quick", t) for t in TABLES]
    + [("quick_physical", t) for t in TABLES]
    + [("quick_comparison", t) for t in COMPARISON_TABLES]
)
RTOL, ATOL = 1e-6, 1e-9


def snakemake(target, *config, cwd=ROOT, quiet=True, force=True):
    """Run the workflow on `target` with `--config key=value ...` (option order matters: both take
    lists). ``force``: recompute every job, since Snakemake does not see changes of the library; a
    list of rule names forces only those (and what depends on them)."""
    exe = Path(sys.executable).with_name("snakemake")
    q = ["--quiet", "all"] if quiet else []
    f = ["--forceall"] if force is True else (["--forcerun", *force] if force else [])
    return subprocess.run(
        [str(exe), target, "--cores", "2", *q, *f, "--config", *config],
        cwd=cwd,
        capture_output=True,
        text=True,
    )


#: The rules of the comparison step (forced: their inputs come from the two runs before).
COMPARISON_RULES = ["budget_design", "budget", "comparison"]


@pytest.fixture(scope="module")
def quick():
    """The quick study in paper mode, in physical mode, then their comparison (as `make reproduce`
    does with the paper study)."""
    for study in ("quick", "quick_physical"):
        p = snakemake("reproduce_paper", f"study=config/studies/{study}.yaml", f"results=results/{study}")
        assert p.returncode == 0, p.stderr[-3000:]
    p = snakemake(
        "reproduce_comparison",
        "study=config/studies/quick.yaml",
        "results=results/quick",
        "comparison=config/comparisons/quick.yaml",
        force=COMPARISON_RULES,
    )
    assert p.returncode == 0, p.stderr[-3000:]
    return ROOT / "results" / "quick"


@pytest.mark.parametrize("run,table", CASES, ids=[f"{r}/{t}" for r, t in CASES])
def test_quick_study_matches_references(quick, run, table):
    ours = pd.read_csv(quick.parent / RUNS[run] / table)
    ref = pd.read_csv(ROOT / "tests" / "reference" / run / table)
    assert list(ours.columns) == list(ref.columns) and len(ours) == len(ref), (
        f"{table}: shape or columns changed"
    )
    for col in ref.columns:
        if pd.api.types.is_numeric_dtype(ref[col]) and pd.api.types.is_numeric_dtype(ours[col]):
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


def test_own_design_end_to_end(tmp_path):
    out = tmp_path / "example"
    p = snakemake("reproduce_paper", "study=config/studies/example.yaml", f"results={out}")
    assert p.returncode == 0, p.stderr[-3000:]
    doe = pd.read_csv(out / "doe" / "doe.csv")
    assert len(doe) == 8 and doe.index_m.notna().all() and (doe.index_m > 0).all()
    plane = pd.read_csv(out / "plane" / "FRAME_DR50.csv")
    assert (plane.status == "ok").mean() > 0.8
    text = (out / "summary.md").read_text()
    assert (
        "not scored" in text and "not reproduced" not in text
    )  # an own design is not scored against the paper


def test_bad_study_value_stops_before_any_job(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(
        (ROOT / "config" / "studies" / "quick.yaml").read_text().replace("solver: newton", "solver: magic")
    )
    p = snakemake("reproduce_paper", f"study={bad}", f"results={tmp_path / 'r'}", quiet=False)
    assert p.returncode != 0
    assert (
        "invalid study configuration" in p.stdout + p.stderr
        and "bad.yaml: key 'solver'" in p.stdout + p.stderr
    )
    assert not (tmp_path / "r").exists()


def _dry_run_rules(quick_study_text):
    """Rules a dry run of the quick study would run after its study file is replaced by
    ``quick_study_text`` (the file is restored afterwards)."""
    path = ROOT / "config" / "studies" / "quick.yaml"
    original = path.read_bytes()
    try:
        path.write_text(quick_study_text)
        exe = Path(sys.executable).with_name("snakemake")
        p = subprocess.run(
            [
                str(exe),
                "reproduce_paper",
                "-n",
                "--quiet",
                "rules",
                "--cores",
                "1",
                "--config",
                "study=config/studies/quick.yaml",
                "results=results/quick",
            ],
            cwd=ROOT,
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


def test_editing_a_study_key_reruns_exactly_the_affected_jobs(quick):
    text = (ROOT / "config" / "studies" / "quick.yaml").read_text()
    assert _dry_run_rules(text) == set()  # the fixture just ran everything: nothing to do
    rules = _dry_run_rules(text.replace("limits_m: [0.05, 0.15]", "limits_m: [0.05, 0.10]"))
    assert rules == {"volumes", "volume_view", "summary", "reproduce_paper"}, rules
    rules = _dry_run_rules(
        text.replace(
            "paper_rw_c_m: [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]",
            "paper_rw_c_m: [-2.3, 2.3, -2.3, 2.3, 0.0, 3.7]",
        )
    )
    assert {"regular_workspace", "index_shard", "doe", "summary"} <= rules and not rules & {
        "winch_table",
        "plane_table",
        "volume_shard",
    }, rules
