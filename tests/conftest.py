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


#: The session fixtures of the quick runs (tests/quick_runs.py).
QUICK_FIXTURES = ("quick_work", "quick_results")


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Work units for ``pytest -n auto --dist loadgroup`` (make test): the tests that read the
    session's quick runs (about half the suite's time) form one unit, scheduled first so that the
    runs start at once and other tests share the second core; every other module is a unit of its
    own, so a module's fixtures are built once. This hook runs before xdist's own, which turns the
    marks into work units; without xdist it only puts the quick tests first."""
    quick = [i for i in items if any(f in i.fixturenames for f in QUICK_FIXTURES)]
    chosen = set(quick)
    rest = [i for i in items if i not in chosen]
    for item in quick:
        item.add_marker(pytest.mark.xdist_group("quick"))
    for item in rest:
        item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::")[0]))
    items[:] = quick + rest


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
