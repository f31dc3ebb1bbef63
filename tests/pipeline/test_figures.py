"""Every figure the pipeline declares, rendered from the quick studies and checked as a reviewer would
(issue 21): no two texts overlap, no text leaves the canvas, every axis has a label with a unit in
brackets, the title names the redundancy mode of the study that drew it; and each PNG matches its
tracked baseline (tests/baseline/<run>/...) at a small RMS tolerance.

The quick studies (both modes) and their comparison run ONCE per session (tests/quick_runs.py, shared
with tests/test_workflow.py), with ``CDPR_FIGURE_AUDIT`` set so that ``plots.style.save`` writes each
figure's layout audit beside it.
``CDPR_FIGURE_RUNS=<folder>`` reuses a folder such a run wrote (same layout: quick/,
quick_physical/, quick_comparison/). ``make update-references`` refreshes the baselines.

Nothing is written into the working tree: each baseline comparison copies the figure into the test's
own temporary folder (``tmp_path``), where a failing one leaves the figure and its difference image
(``*-failed-diff.png``; pytest keeps the temporary folders of its last three sessions, the failure
message names the files). To keep them elsewhere for inspection, name a folder explicitly:
``CDPR_TEST_OUTPUT=<folder>`` copies a failing comparison's figure and difference image to
``<folder>/<run>/<figure>`` (``compare_with_baseline``; tests/test_workflow_spatial.py does the same).
"""

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from cdpr.pipeline import figure_checks
from cdpr.pipeline.plots import style as style_plots

ROOT = Path(__file__).resolve().parents[2]
BASELINE = ROOT / "tests" / "baseline"
#: The environment variable naming a folder that keeps failing comparisons' figures (none by default).
OUTPUT_ENV = "CDPR_TEST_OUTPUT"
#: run folder -> (study file, redundancy mode named in its figures' titles; None: both modes drawn)
RUNS = {
    "quick": ("config/studies/quick.yaml", "paper"),
    "quick_physical": ("config/studies/quick_physical.yaml", "physical"),
    "quick_comparison": (None, None),
}
#: RMS tolerance of the baseline comparison (matplotlib.testing.compare.compare_images, 0-255 scale)
RMS_TOL = 2.0


@pytest.fixture(scope="session")
def runs(request):
    given = os.environ.get("CDPR_FIGURE_RUNS")
    if given:
        return Path(given)
    return request.getfixturevalue("quick_results")  # the session's quick runs (tests/quick_runs.py)


def declared(root):
    """(run, path relative to the run folder) of every PNG the runs wrote."""
    return sorted(
        (run, p.relative_to(root / run).as_posix()) for run in RUNS for p in (root / run).rglob("*.png")
    )


def _baselines():
    return sorted(
        (p.relative_to(BASELINE).parts[0], Path(*p.relative_to(BASELINE).parts[1:]).as_posix())
        for p in BASELINE.rglob("*.png")
    )


FIGURES = _baselines()


def test_baselines_exist_for_the_quick_studies():
    runs_with_figures = {r for r, _ in FIGURES}
    assert runs_with_figures == set(RUNS), "run `make update-references` to write tests/baseline/"


def test_every_declared_figure_has_a_baseline_and_an_audit(runs):
    ours = declared(runs)
    assert ours == FIGURES, {"new (no baseline)": set(ours) - set(FIGURES), "lost": set(FIGURES) - set(ours)}
    for run, rel in ours:
        assert (runs / run / (rel + ".layout.json")).exists(), f"{run}/{rel}: not written by plots.style.save"


@pytest.mark.parametrize("run,figure", FIGURES, ids=[f"{r}/{f}" for r, f in FIGURES])
def test_figure_layout(runs, run, figure):
    rec = json.loads((runs / run / (figure + ".layout.json")).read_text(encoding="utf-8"))
    problems = list(rec["problems"])
    mode = RUNS[run][1]
    if mode is not None:
        problems += figure_checks.mode_problems(rec["titles"], mode)
    assert problems == [], f"{run}/{figure}:\n" + "\n".join(problems)


def compare_with_baseline(image, baseline, tmp_path, name):
    """Compare a copy of the PNG ``image``, made in the test's temporary folder ``tmp_path``, with the
    PNG ``baseline`` at ``RMS_TOL``: None when they match, else the failure message. A failing
    comparison leaves the copy and its difference image in ``tmp_path`` and, when ``CDPR_TEST_OUTPUT``
    names a folder, copies both to ``<folder>/<name>`` (``name``: the figure's path, e.g.
    ``quick/plane/x.png``); nothing is written anywhere else."""
    from matplotlib.testing.compare import compare_images

    ours = tmp_path / Path(name).name
    shutil.copy(image, ours)
    err = compare_images(str(baseline), str(ours), tol=RMS_TOL, in_decorator=True)
    if err is None:
        return None
    kept = [ours, Path(err["diff"])]
    folder = os.environ.get(OUTPUT_ENV)
    if folder:
        out = Path(folder) / name
        out.parent.mkdir(parents=True, exist_ok=True)
        kept = [Path(shutil.copy(f, out.with_name(f.name))) for f in kept]
    return f"{name}: RMS {err['rms']:.2f} > {RMS_TOL}; figure and difference image: {kept[0]}, {kept[1]}"


@pytest.mark.parametrize("run,figure", FIGURES, ids=[f"{r}/{f}" for r, f in FIGURES])
def test_figure_matches_its_baseline(runs, run, figure, tmp_path):
    failure = compare_with_baseline(runs / run / figure, BASELINE / run / figure, tmp_path, f"{run}/{figure}")
    if failure:
        pytest.fail(failure)


# ---- the checks themselves can fail -------------------------------------------------------------------


def test_layout_checks_catch_overlap_offcanvas_missing_unit_and_mode():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(3, 2))
    ax.plot([0, 1], [0, 1])
    ax.set(xlabel="x", ylabel="")
    ax.text(0.5, 0.5, "first label", transform=ax.transAxes)
    ax.text(0.52, 0.5, "second label", transform=ax.transAxes)
    fig.text(1.2, 0.5, "outside")
    problems = figure_checks.layout_problems(fig, mode="physical")
    plt.close(fig)
    text = "\n".join(problems)
    assert "overlap" in text and "leaves the canvas" in text
    assert "label 'x' has no unit" in text and "y axis" in text and "no label" in text
    assert "names the mode" in text


def test_layout_checks_pass_a_clean_figure():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4, 3), layout="constrained")
    ax.plot([0, 1], [0, 1])
    ax.set(xlabel="x [m]", ylabel="‖δp‖ [mm]", title="physical equilibrium")
    assert figure_checks.layout_problems(fig, mode="physical") == []
    plt.close(fig)


def test_a_figure_has_the_same_pixels_with_and_without_its_audit(tmp_path, monkeypatch):
    """The figure test's runs keep the audit, make reproduce and make update-references do not:
    both must draw the same image (drawing for the audit once moved constrained layouts by a pixel)."""
    import matplotlib.pyplot as plt

    def draw(out):
        fig, axes = plt.subplots(1, 2, figsize=(6, 3), layout="constrained")
        for ax in axes:
            cf = ax.contourf(np.random.default_rng(0).random((5, 5)))
            fig.colorbar(cf, ax=ax, label="‖δp‖ [mm]")
            ax.set(xlabel="x [m]", ylabel="y [m]", title="a title\nover two lines")
        fig.suptitle("physical equilibrium")
        style_plots.save(fig, out)

    monkeypatch.delenv("CDPR_FIGURE_AUDIT", raising=False)
    draw(tmp_path / "plain.png")
    monkeypatch.setenv("CDPR_FIGURE_AUDIT", "1")
    draw(tmp_path / "audited.png")
    assert (tmp_path / "audited.png.layout.json").exists()
    assert (tmp_path / "plain.png").read_bytes() == (tmp_path / "audited.png").read_bytes()
