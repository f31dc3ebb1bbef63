"""The whole DAG on the quick study of a spatial robot (issue 19): config/studies/quick_spatial.yaml,
CoGiRo with its rigid 6-DoF platform in physical mode, against committed reference tables
(tests/reference/quick_spatial/) and figure baselines (tests/baseline_spatial/quick_spatial/).
Regenerate both with `make update-references` (tests/update_references.py runs the study exactly as
the fixture below does).

The study runs once per run of this module, in a working folder of its own under pytest's
temporary folder (``make_workdir`` with the spatial study only; its path has a space and a non-ASCII
letter), with the figure audit on (tests/quick_runs.py). It does not read the session's quick runs
(``quick_results``): make test's scheduler (tests/conftest.py) gives this module a work unit of its
own, so it runs on another worker, in parallel with them. The tables are compared as
tests/test_workflow.py compares the quick study's, with the same tolerances; every declared output
must exist, and every figure pass the layout checks of tests/pipeline/test_figures.py and match its
baseline at the same RMS tolerance."""

import json
from pathlib import Path

import pytest

from cdpr.pipeline import figure_checks
from cdpr.pipeline.results import Layout
from cdpr.pipeline.study import load_study
from tests.conftest import ROOT
from tests.pipeline.test_figures import compare_with_baseline
from tests.quick_runs import SPATIAL_STUDY, make_workdir, run_quick_spatial
from tests.test_workflow import assert_table_matches

STUDY = ROOT / "config" / "studies" / f"{SPATIAL_STUDY}.yaml"
REF = ROOT / "tests" / "reference" / SPATIAL_STUDY
BASELINE = ROOT / "tests" / "baseline_spatial" / SPATIAL_STUDY
#: The redundancy mode the figures' titles must name (a spatial robot has the physical mode only).
MODE = "physical"


def declared(study=STUDY):
    """Every output the study declares (``Layout.targets``), relative to its results folder."""
    return [p.removeprefix("R/") for p in Layout(load_study(study), "R").targets()]


#: The tables of tests/test_workflow.py's TABLES the spatial study writes (its uncertainty section runs
#: in physical mode, pipeline.uq: the tables carry δφ columns beside ‖δp‖'s), then its per-path and
#: per-plane tables (paths under results/quick_spatial/).
#: The plane tables are compared here (not for the point-mass quick study): the per-point pose of
#: the 6-DoF equilibrium, of which the summary keeps only the extremes.
TABLES = [
    "summary.csv",
    "doe/doe.csv",
    "doe/effects.csv",
    "doe/rw_max.csv",
    "volumes/volumes.csv",
    "volumes/volumes_dphi.csv",
    "maps/map.csv",
    "maps/lines.csv",
    "trajectories/trajectories_minmax.csv",
    "elasticity/index_vs_E.csv",
    "elasticity/bands.csv",
    "elasticity/crossings.csv",
    "dead_length/dead_length.csv",
    "winch/winch.csv",
    "uncertainty/bands.csv",
    "uncertainty/agreement.csv",
    "uncertainty/sobol.csv",
    "uncertainty/SRopt_uncompensated_path.csv",
    "uncertainty/SRopt_compensated_map.csv",
] + [
    p
    for p in declared()
    if p.endswith(".csv") and p.startswith(("trajectories/", "plane/")) and "minmax" not in p
]
#: Every figure the study declares (a PNG and its PDF each).
FIGURES = sorted(p for p in declared() if p.endswith(".png"))


@pytest.fixture(scope="module")
def spatial(tmp_path_factory):
    """results/quick_spatial of one run of the spatial study in a working folder of its own."""
    work = make_workdir(tmp_path_factory.mktemp("spatial work dir é") / "w", studies=(SPATIAL_STUDY,))
    return run_quick_spatial(work)


def test_the_references_are_the_compared_tables():
    refs = sorted(p.relative_to(REF).as_posix() for p in REF.rglob("*") if p.is_file())
    assert refs == sorted(TABLES), "run `make update-references` to write tests/reference/quick_spatial/"
    assert {"trajectories/diagonal_SR.csv", "trajectories/vertical_DR.csv", "plane/CoGiRo_DR.csv"} <= set(
        TABLES
    )


@pytest.mark.parametrize("table", TABLES)
def test_quick_spatial_study_matches_references(spatial, table):
    assert_table_matches(spatial / table, REF / table, table)


def test_every_declared_output_is_written_and_every_figure_declared(spatial):
    work = spatial.parents[1]
    targets = Layout(load_study(work / "studies" / f"{SPATIAL_STUDY}.yaml"), spatial).targets()
    assert len(targets) == len(declared())
    empty = [t for t in targets if not Path(t).is_file() or Path(t).stat().st_size == 0]
    assert empty == [], f"declared but not written (or empty): {empty}"
    written = sorted(p.relative_to(spatial).as_posix() for p in spatial.rglob("*.png"))
    assert written == FIGURES, {"undeclared": set(written) - set(FIGURES)}
    assert all((spatial / f).with_suffix(".pdf").stat().st_size > 0 for f in FIGURES)
    text = (spatial / "summary.md").read_text(encoding="utf-8")
    assert "redundancy physical" in text and "rotvec_rad = [0.0, 0.0, 0.0] rad" in text


@pytest.mark.parametrize("figure", FIGURES)
def test_figure_layout(spatial, figure):
    rec = json.loads((spatial / (figure + ".layout.json")).read_text(encoding="utf-8"))
    problems = list(rec["problems"]) + figure_checks.mode_problems(rec["titles"], MODE)
    assert problems == [], f"{SPATIAL_STUDY}/{figure}:\n" + "\n".join(problems)


def test_every_figure_has_a_baseline():
    baselines = sorted(p.relative_to(BASELINE).as_posix() for p in BASELINE.rglob("*.png"))
    assert baselines == FIGURES, "run `make update-references` to write tests/baseline_spatial/"


@pytest.mark.parametrize("figure", FIGURES)
def test_figure_matches_its_baseline(spatial, figure, tmp_path):
    """A failing comparison leaves the figure and its difference image in the test's temporary
    folder, and copies them to ``$CDPR_TEST_OUTPUT/quick_spatial/`` when that variable names a folder,
    as tests/pipeline/test_figures.py does (``compare_with_baseline``); nothing goes into the tree."""
    failure = compare_with_baseline(
        spatial / figure, BASELINE / figure, tmp_path, f"{SPATIAL_STUDY}/{figure}"
    )
    if failure:
        pytest.fail(failure)
