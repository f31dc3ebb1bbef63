import atexit
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

# The test suite writes only under temporary folders: numba's cache of compiled kernels (by default
# __pycache__/ beside cdpr/compiled/) goes to one for the session, shared by the processes the tests
# start (set before anything imports numba; a fresh clone compiles once either way).
if "NUMBA_CACHE_DIR" not in os.environ:
    os.environ["NUMBA_CACHE_DIR"] = tempfile.mkdtemp(prefix="cdpr-tests-numba-")
    atexit.register(shutil.rmtree, os.environ["NUMBA_CACHE_DIR"], True)

import pytest
from hypothesis import settings

from cdpr.robot import load_robot
from tests.quick_runs import make_workdir, run_quick

ROOT = Path(__file__).resolve().parents[1]
ROBOTS = ROOT / "config" / "robots"

# The test suite writes only under pytest's temporary folders: no hypothesis example database
# (.hypothesis/) and no bytecode caches (__pycache__/), here or in the processes the tests start.
settings.register_profile("cdpr", database=None)
settings.load_profile("cdpr")
sys.dont_write_bytecode = True
os.environ["PYTHONDONTWRITEBYTECODE"] = "1"


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
