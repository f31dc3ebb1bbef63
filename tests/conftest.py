import atexit
import os
import shutil
import subprocess
import sys
import tempfile
from fnmatch import fnmatch
from pathlib import Path

# The test suite writes only under temporary folders: numba's cache of compiled kernels (by default
# __pycache__/ beside cdpr/compiled/) goes to one for the session, shared by the processes the tests
# start (set before anything imports numba; a fresh clone compiles once either way).
if "NUMBA_CACHE_DIR" not in os.environ:
    os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="cdpr-tests-numba-")
    atexit.register(shutil.rmtree, os.environ["NUMBA_CACHE_DIR"], True)
# Hypothesis' storage (.hypothesis/ in the current folder by default; with database=None below it
# still caches the constants it collects from the tested modules there) goes to one for the session
# too. Hypothesis reads the variable when it first writes, after this (its pytest plugin is loaded
# before this file but writes nothing at import).
if "HYPOTHESIS_STORAGE_DIRECTORY" not in os.environ:
    os.environ["HYPOTHESIS_STORAGE_DIRECTORY"] = tempfile.mkdtemp(prefix="cdpr-tests-hypothesis-")
    atexit.register(shutil.rmtree, os.environ["HYPOTHESIS_STORAGE_DIRECTORY"], True)

import pytest
from hypothesis import settings

from cdpr.robot import load_robot
from tests.quick_runs import make_workdir, run_quick

ROOT = Path(__file__).resolve().parents[1]
ROBOTS = ROOT / "config" / "robots"
_TREE_BEFORE = pytest.StashKey[set]()
_TREE_WRITES = pytest.StashKey[list]()

# The test suite writes only under pytest's temporary folders: no hypothesis example database
# (.hypothesis/) and no bytecode caches (__pycache__/), here or in the processes the tests start.
settings.register_profile("cdpr", database=None)
settings.load_profile("cdpr")
sys.dont_write_bytecode = True
os.environ["PYTHONDONTWRITEBYTECODE"] = "1"


#: Names a file or folder may have in the tree without counting as a write of the test session:
#: Python's bytecode caches (none are written: PYTHONDONTWRITEBYTECODE above; a developer's own runs
#: leave them) and what an editor creates beside a file it opens while the tests run.
NOT_WRITES = ("__pycache__", "*.swp", "*.swo", "*~", ".#*", "#*#")


def tree_paths(root=ROOT):
    """Every file and folder under ``root`` (relative POSIX paths, folders with a trailing slash),
    without .git/ and the names of ``NOT_WRITES`` (and what is under them)."""
    paths = set()
    for folder, dirs, files in os.walk(root):
        rel = Path(folder).relative_to(root)
        dirs[:] = [d for d in dirs if d != ".git" and not any(fnmatch(d, pat) for pat in NOT_WRITES)]
        paths.update((rel / d).as_posix() + "/" for d in dirs)
        paths.update((rel / f).as_posix() for f in files if not any(fnmatch(f, pat) for pat in NOT_WRITES))
    return paths


def new_paths(before, after):
    """The paths of ``after`` not in ``before``, without those under a new folder (the folder names
    them), sorted."""
    new = sorted(set(after) - set(before))
    return [p for p in new if not any(p != q and p.startswith(q) for q in new if q.endswith("/"))]


def pytest_sessionstart(session):
    """The tree's files and folders before the session (in the process that runs the session: not in
    a pytest-xdist worker, whose tests the controller's session covers)."""
    if not hasattr(session.config, "workerinput"):
        session.config.stash[_TREE_BEFORE] = tree_paths()


def pytest_sessionfinish(session, exitstatus):
    """The test suite writes only under temporary folders: a session that leaves a new file or
    folder in the working tree fails, naming them (ignored by git or not; see ``NOT_WRITES``). A file
    rewritten in place is not seen, nor a path created and removed again."""
    before = session.config.stash.get(_TREE_BEFORE, None)
    if before is None:
        return
    written = new_paths(before, tree_paths())
    if written:
        session.config.stash[_TREE_WRITES] = written
        if session.exitstatus == pytest.ExitCode.OK:
            session.exitstatus = pytest.ExitCode.TESTS_FAILED


def pytest_terminal_summary(terminalreporter, config):
    written = config.stash.get(_TREE_WRITES, None)
    if written:
        terminalreporter.section("files written into the working tree", red=True)
        terminalreporter.line(
            f"the test session left {len(written)} new path(s) under {ROOT} (tests must write under "
            "tmp_path or another temporary folder; something else that created a file there meanwhile "
            "is listed too):"
        )
        for p in written:
            terminalreporter.line(f"  {p}")


def copy_sources(dest):
    """The repository's files (tracked, and new ones not ignored) copied to ``dest``."""
    files = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, capture_output=True, check=True
    ).stdout.split(b"\0")
    for f in filter(None, files):
        src = ROOT / f.decode()
        if src.is_file():
            (dest / f.decode()).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / f.decode())
    return dest


#: The modules whose tests read the session's quick runs (``quick_results``, tests/quick_runs.py).
QUICK_MODULES = ("tests/pipeline/test_figures.py", "tests/test_workflow.py")


def _work_unit(nodeid):
    """The pytest-xdist work unit of a test: "quick" for the modules of the quick runs (one worker
    makes the runs once and runs every test that reads them), else the test's module (or class),
    as ``--dist loadscope`` has it, so a module's fixtures are built once."""
    module = nodeid.split("::")[0]
    return "quick" if module in QUICK_MODULES else nodeid.rsplit("::", 1)[0]


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``make test`` runs ``pytest -n auto --dist loadscope``: the scheduling of loadscope with the
    work units of ``_work_unit``. (xdist's own ``loadgroup`` marks do not group with pytest 9:
    they rename ``Node._nodeid``, which pytest 9 no longer reads.)"""
    if config.getvalue("dist") != "loadscope":
        return None
    from xdist.scheduler import LoadScopeScheduling  # only under xdist: a plain pytest needs none

    class QuickFirst(LoadScopeScheduling):
        def _split_scope(self, nodeid):
            return _work_unit(nodeid)

    return QuickFirst(config, log)


def pytest_collection_modifyitems(config, items):
    """The tests of the quick runs first (``--no-loadscope-reorder`` keeps this order): their
    unit, about half the suite's time, starts at once on the first worker."""
    items.sort(key=lambda item: _work_unit(item.nodeid) != "quick")


@pytest.fixture(scope="session")
def quick_work(tmp_path_factory):
    """The working folder of the session's quick runs: outside the tree, its path with a space and
    a non-ASCII letter (every path that reaches a shell command is quoted)."""
    return make_workdir(tmp_path_factory.mktemp("work dir é") / "w")


@pytest.fixture(scope="session")
def quick_results(quick_work):
    """The quick study in both modes and their comparison, run once per session (tests/quick_runs.py):
    the workflow regression and the figure tests read the same runs."""
    return run_quick(quick_work)


@pytest.fixture(scope="session")
def cdpr4():
    return load_robot(ROBOTS / "cdpr4.yaml")


@pytest.fixture(scope="session")
def cdpr3():
    return load_robot(ROBOTS / "cdpr3.yaml")
