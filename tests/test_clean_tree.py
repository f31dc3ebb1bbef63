"""The test suite writes only under temporary folders, nothing into the working tree.

tests/conftest.py fails a session that leaves a new file or folder in the tree (``tree_paths`` before
and after the session). The tests below show that this check fails when a test writes into the tree,
and that the writers an audit found stay configured away: Hypothesis' storage (.hypothesis/), grimp's
cache (.grimp_cache/), Snakemake's .snakemake/ of a dry run from the repository, and the copies of the
figures a baseline comparison makes (tests/output/ before): each of them, reverted, fails a test here.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import ROOT, copy_sources, new_paths, tree_paths

#: A test module that writes one file into the tree of the repository it belongs to, and one
#: property-based test (Hypothesis caches constants in its storage folder when it runs one).
PROBE = """
from pathlib import Path

from hypothesis import given, strategies as st


@given(st.integers())
def test_hypothesis_runs(x):
    assert isinstance(x, int)


def test_writes_into_the_tree():
    (Path(__file__).resolve().parents[1] / "written-by-a-test.txt").write_text("x")
"""

#: Tests that wrote into the tree before (grimp's cache; .snakemake/ of a Snakemake dry run).
REPRESENTATIVE = (
    "tests/test_layers.py::test_no_import_cycle_between_modules",
    "tests/pipeline/test_results.py::test_layout_is_the_dag",
)


def test_new_paths_names_new_files_and_folders_once(tmp_path):
    (tmp_path / "kept").mkdir()
    (tmp_path / "kept" / "a.txt").write_text("a")
    before = tree_paths(tmp_path)
    assert new_paths(before, tree_paths(tmp_path)) == []
    (tmp_path / "kept" / "b.txt").write_text("b")
    (tmp_path / "new" / "deep").mkdir(parents=True)
    (tmp_path / "new" / "deep" / "c.txt").write_text("c")
    (tmp_path / "__pycache__").mkdir()  # Python's bytecode caches do not count
    (tmp_path / "__pycache__" / "m.pyc").write_text("")
    (tmp_path / "kept" / ".a.txt.swp").write_text("")  # nor an editor's swap file
    assert new_paths(before, tree_paths(tmp_path)) == ["kept/b.txt", "new/"]


def test_a_session_that_writes_into_the_tree_fails(tmp_path):
    """A few representative tests and a probe that writes one file, run by pytest in a copy of the
    repository (from its root, as ``make test`` runs): the session fails and names exactly the probe's
    file. Hypothesis' storage folder is left to the copy's conftest.py (not inherited from this
    session), so a .hypothesis/, .grimp_cache/ or .snakemake/ in the copy is named too."""
    repo = copy_sources(tmp_path / "repo")
    (repo / "tests" / "test_probe_writes.py").write_text(PROBE)
    env = {k: v for k, v in os.environ.items() if k != "HYPOTHESIS_STORAGE_DIRECTORY"}
    env["PYTHONPATH"] = str(repo)
    p = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist"]
        + ["tests/test_probe_writes.py", *REPRESENTATIVE],
        cwd=repo,
        env=env,
        capture_output=True,
        text=True,
    )
    out = p.stdout + p.stderr
    assert "4 passed" in out, out[-3000:]
    assert p.returncode == pytest.ExitCode.TESTS_FAILED, out[-3000:]
    summary = out.split("files written into the working tree", 1)[-1]
    written = [ln.strip() for ln in summary.splitlines() if ln.startswith("  ")]
    assert written == ["written-by-a-test.txt"], out[-3000:]


def test_hypothesis_storage_is_a_temporary_folder():
    from hypothesis.configuration import storage_directory

    home = storage_directory(intent_to_write=False).home_directory.resolve()
    assert Path(os.environ["HYPOTHESIS_STORAGE_DIRECTORY"]).resolve() == home
    assert not home.is_relative_to(ROOT.resolve()), home


def test_the_import_graph_leaves_no_grimp_cache(tmp_path, monkeypatch):
    from tests.test_layers import test_no_import_cycle_between_modules

    monkeypatch.chdir(tmp_path)  # grimp's cache goes to .grimp_cache/ in the current folder
    test_no_import_cycle_between_modules()
    assert list(tmp_path.iterdir()) == []


def _wrong_copy(baseline, dest):
    """``baseline``'s PNG with its colours inverted, at ``dest``: the same size, far from it."""
    import matplotlib.image as mpimg

    img = mpimg.imread(baseline)
    img[..., :3] = 1.0 - img[..., :3]
    dest.parent.mkdir(parents=True, exist_ok=True)
    mpimg.imsave(dest, img)


@pytest.mark.parametrize("module", ["test_figures", "test_workflow_spatial"])
def test_a_failing_figure_comparison_writes_only_under_tmp(tmp_path, monkeypatch, module):
    """The figure tests' baseline comparison, on a wrong figure: it fails, and leaves the figure and
    its difference image in the test's temporary folder, nowhere in the tree; with CDPR_TEST_OUTPUT
    it copies both to the folder named."""
    if module == "test_figures":
        from tests.pipeline import test_figures as mod

        run, figure = mod.FIGURES[0]
        name = f"{run}/{figure}"
        _wrong_copy(mod.BASELINE / run / figure, tmp_path / "runs" / run / figure)

        def compare(out):
            mod.test_figure_matches_its_baseline(tmp_path / "runs", run, figure, out)

    else:
        from tests import test_workflow_spatial as mod

        figure = mod.FIGURES[0]
        name = f"{mod.SPATIAL_STUDY}/{figure}"
        _wrong_copy(mod.BASELINE / figure, tmp_path / "spatial" / figure)

        def compare(out):
            mod.test_figure_matches_its_baseline(tmp_path / "spatial", figure, out)

    before = tree_paths()
    monkeypatch.delenv("CDPR_TEST_OUTPUT", raising=False)
    (tmp_path / "t").mkdir()
    with pytest.raises(pytest.fail.Exception, match="RMS"):
        compare(tmp_path / "t")
    stem = Path(figure).stem
    assert sorted(p.name for p in (tmp_path / "t").iterdir()) == [f"{stem}-failed-diff.png", f"{stem}.png"]

    monkeypatch.setenv("CDPR_TEST_OUTPUT", str(tmp_path / "kept"))
    (tmp_path / "t2").mkdir()
    with pytest.raises(pytest.fail.Exception, match="kept"):
        compare(tmp_path / "t2")
    kept = tmp_path / "kept" / name
    assert kept.is_file() and kept.with_name(f"{stem}-failed-diff.png").is_file()
    assert new_paths(before, tree_paths()) == []
