"""``cdpr compile``: the kernels of a family are in numba's cache afterwards, so that a command of
that family run next in another process compiles nothing (numba's own cache log, NUMBA_DEBUG_CACHE,
says "data saved" for every kernel it compiles and writes); a wrong robots folder is one line."""

import os
import subprocess
import sys

from tests.conftest import ROBOTS, ROOT


def cdpr(*argv, env=None):
    return subprocess.run(
        [sys.executable, "-m", "cdpr", *map(str, argv)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={**os.environ, **(env or {})},
    )


def compiled_anew(result):
    """The kernels a process compiled and wrote to the cache (numba's cache log on stdout)."""
    return [line for line in (result.stdout + result.stderr).splitlines() if "data saved" in line]


def test_after_compile_a_physical_grid_compiles_nothing(tmp_path):
    """The physical family covers ``grid --redundancy physical`` (the studies' workspace grids) on
    CDPR4 with SR and DR pulleys, at another grid size than the warm-up's poses (the kernels
    specialise on types, not sizes)."""
    done = cdpr("compile", "--part", "physical")
    assert done.returncode == 0, done.stderr
    assert "compiled physical in" in done.stderr
    for kind in ("SR", "DR"):
        r = cdpr(
            "grid", "--robot", ROBOTS / "cdpr4.yaml", "--pulley", kind, "--redundancy", "physical", "--n", "5", "--box", "-1", "1", "-1", "1", "1", "3",
            "--out", tmp_path / f"{kind}.parquet", env={"NUMBA_DEBUG_CACHE": "1"},
        )  # fmt: skip
        assert r.returncode == 0, r.stderr
        assert "data loaded" in r.stdout + r.stderr  # the log is on: kernels came from the cache
        assert compiled_anew(r) == []


def test_after_compile_a_heavy_compensation_compiles_nothing():
    done = cdpr("compile", "--part", "heavy")
    assert done.returncode == 0, done.stderr
    r = cdpr(
        "compensate",
        "--robot",
        ROBOTS / "cube50.yaml",
        "--at",
        "3",
        "-2",
        "20",
        "--json",
        env={"NUMBA_DEBUG_CACHE": "1"},
    )
    assert r.returncode == 0, r.stderr
    assert compiled_anew(r) == []


def test_a_folder_without_the_shipped_robots_is_one_line(tmp_path):
    r = cdpr("compile", "--robots", tmp_path)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "--robots" in lines[0] and "cdpr4.yaml" in lines[0]
