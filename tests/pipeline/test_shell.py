"""The pipeline's shell commands (workflow/rules/*.smk, common.smk): they run from a copy of the
repository whose path has spaces and non-ASCII letters, with an interpreter whose path has them
too; an edit of a library file in a subpackage reruns the jobs (the code version CODE); a failed
job's reason reaches the console, not only its log."""

import os
import subprocess
import sys

import pytest

from tests.conftest import copy_sources
from tests.quick_runs import rule_jobs

TARGET = "winch_figure"  # two jobs: winch_table (cdpr winch) and winch_figure (cdpr job winch-figure)


@pytest.fixture(scope="module")
def repo(tmp_path_factory):
    """A copy of the repository under a path with a space and 'é', a link to this environment under
    such a path (its interpreter is what the rules run), and the winch jobs run once there."""
    if sys.prefix == sys.base_prefix:
        pytest.skip("needs a virtual environment to link under a path with spaces")
    tmp = tmp_path_factory.mktemp("dépôt à espaces")
    src = copy_sources(tmp / "the repo é")
    venv = tmp / "env é x"
    venv.symlink_to(sys.prefix, target_is_directory=True)
    py = venv / "bin" / "python"
    res = tmp / "résultats x" / "quick"
    run = _runner(src, py, res)
    p = run(TARGET)
    assert p.returncode == 0, p.stderr[-3000:]
    return src, run, res


def _runner(src, py, res):
    env = {**os.environ, "PYTHONPATH": str(src)}

    def run(*args):
        return subprocess.run(
            [str(py), "-m", "snakemake", *args, "--cores", "1"]
            + ["--config", "study=config/studies/quick.yaml", f"results={res}"],
            cwd=src,
            env=env,
            capture_output=True,
            text=True,
        )

    return run


def _scheduled(p):
    return set(rule_jobs(p))


def test_jobs_run_from_paths_with_spaces_and_accents(repo):
    src, run, res = repo
    assert " " in str(res) and "é" in str(src)
    table, fig = res / "winch" / "winch.csv", res / "winch" / "winch.png"
    assert table.stat().st_size > 0 and fig.stat().st_size > 0 and fig.with_suffix(".pdf").stat().st_size > 0
    assert table.read_text().splitlines()[0].startswith("l_pm")
    # the interpreter's path has a space: it reached the shell quoted
    log = (res / "logs" / "winch_figure.log").read_text()
    assert "Traceback" not in log


def test_editing_a_subpackage_file_reruns_its_jobs(repo):
    src, run, res = repo
    assert _scheduled(run(TARGET, "-n", "--quiet", "rules")) == set()
    winch_py = src / "cdpr" / "models" / "winch.py"
    original = winch_py.read_bytes()
    try:
        winch_py.write_bytes(original + b"\n# an edit of the library\n")
        assert {"winch_table", "winch_figure"} <= _scheduled(run(TARGET, "-n", "--quiet", "rules"))
    finally:
        winch_py.write_bytes(original)
    assert _scheduled(run(TARGET, "-n", "--quiet", "rules")) == set()  # the same code again: nothing


def test_a_failed_job_prints_its_reason_on_the_console(repo):
    src, run, res = repo
    table = res / "winch" / "winch.csv"
    original = table.read_bytes()
    try:
        table.write_bytes(b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR" + bytes(range(256)))  # not a table
        p = run(TARGET, "--forcerun", "winch_figure")
    finally:
        table.write_bytes(original)
    assert p.returncode != 0
    # the library's one-line error, from the job's log, on the console with the exit status
    assert "job failed (exit status 2): cdpr: error:" in p.stderr, p.stderr[-3000:]
    assert (
        "winch.csv: cannot read this table" in p.stderr and "it holds binary data, not CSV text" in p.stderr
    )
    assert "truncated" not in p.stderr.split("job failed", 1)[1].splitlines()[0]
