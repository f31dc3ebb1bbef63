"""Long work over ``--points`` tables (docs/cli.md, "Large tables"): the table is read, solved and
written ``--chunk-rows`` rows at a time with the bytes of the table written at once, a progress bar
shows on a terminal only and never with ``--quiet``, a long table says its expected time, Ctrl-C
ends with one line and exit 130 leaving no output, memory does not grow with the table, and
``grid``'s kernel compile is announced instead of being counted in its rate."""

import fcntl
import io as stdio
import json
import os
import pty
import signal
import struct
import subprocess
import sys
import termios
import time

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from cdpr import table_io
from cdpr.cli import stream
from cdpr.cli.main import INTERRUPTED, main
from cdpr.robot import load_robot
from cdpr.solve import solve
from cdpr.tables import to_frame
from tests.conftest import ROBOTS, ROOT

CDPR4 = str(ROBOTS / "cdpr4.yaml")


def points_table(path, n, seed=0, spread=1.5):
    """n positions in CDPR4's box (``spread`` beyond 2.5 m puts some out of reach), as .csv or .parquet."""
    rng = np.random.default_rng(seed)
    P = np.column_stack(
        [rng.uniform(-spread, spread, n), rng.uniform(-spread, spread, n), rng.uniform(0.3, 4.0, n)]
    )
    df = pd.DataFrame(P, columns=["x", "y", "z"])
    if str(path).endswith(".csv"):
        df.to_csv(path, index=False)
    else:
        df.to_parquet(path, index=False)
    return P


def cdpr(*argv, **kw):
    """``python -m cdpr argv`` in a subprocess (stdout and stderr captured as text)."""
    return subprocess.run(
        [sys.executable, "-m", "cdpr", *map(str, argv)], capture_output=True, text=True, cwd=ROOT, **kw
    )


# --- chunks: the same bytes -----------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
@pytest.mark.parametrize(
    "command",
    [
        ["point"],
        ["point", "--redundancy", "physical"],
        ["point", "--method", "fixed_point"],
        ["compensate"],
        ["inverse"],
    ],
    ids=lambda c: "-".join(c),
)
def test_chunked_output_has_the_bytes_of_one_chunk(tmp_path, capsys, suffix, command):
    """61 points (some out of reach: several statuses) in chunks of 7 rows, against one chunk."""
    table = tmp_path / f"p{suffix}"
    points_table(table, 61, spread=3.2)
    outs = []
    for rows in ("7", "100000"):
        out = tmp_path / f"out_{rows}{suffix}"
        argv = command + ["--robot", CDPR4, "--points", str(table), "--out", str(out), "--chunk-rows", rows]
        assert main(argv) == 0
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    assert len(pd.read_parquet(out) if suffix == ".parquet" else pd.read_csv(out)) == 61
    text = capsys.readouterr().out
    assert text.count("wrote 61 points") == 2 or text.count("wrote 61 poses") == 2


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_chunked_point_table_is_todays_table(tmp_path, suffix):
    """The chunked command writes what the one-shot code wrote: ``to_frame`` of the solve of every
    point at once, through ``table_io.write_table``."""
    table = tmp_path / f"p{suffix}"
    P = points_table(table, 45, seed=3, spread=3.2)
    out = tmp_path / f"chunked{suffix}"
    assert (
        main(["point", "--robot", CDPR4, "--points", str(table), "--out", str(out), "--chunk-rows", "4"]) == 0
    )
    robot = load_robot(CDPR4)
    today = tmp_path / f"today{suffix}"
    table_io.write_table(to_frame(robot, solve(robot, P, engine="numpy")), today)
    assert out.read_bytes() == today.read_bytes()
    statuses = set(pd.read_parquet(out)["status"] if suffix == ".parquet" else pd.read_csv(out)["status"])
    assert len(statuses) > 1, statuses  # the table covers more than ok rows


def test_parquet_row_groups_as_pyarrow_cuts_them(tmp_path, monkeypatch):
    """A table longer than a row group: the chunks are cut into the row groups ``pq.write_table``
    makes (``ROW_GROUP_ROWS`` made small here), so that the bytes stay the same."""
    monkeypatch.setattr(table_io, "ROW_GROUP_ROWS", 50)
    rng = np.random.default_rng(1)
    df = pd.DataFrame({"a": rng.normal(size=233), "b": np.arange(233)})
    df["c"] = pd.Categorical.from_codes(rng.integers(0, 3, 233), categories=["ok", "slack", ""])
    whole = tmp_path / "whole.parquet"
    pq.write_table(
        pa.Table.from_pandas(df, preserve_index=False),
        whole,
        compression=None,
        use_dictionary=["c"],
        row_group_size=50,
    )
    chunked = tmp_path / "chunked.parquet"
    n = table_io.write_table_chunks((df.iloc[i : i + 17] for i in range(0, 233, 17)), chunked)
    assert n == 233 and pq.ParquetFile(chunked).metadata.num_row_groups == 5
    assert chunked.read_bytes() == whole.read_bytes()


def test_a_bad_row_in_a_later_chunk_is_refused_before_any_work(tmp_path, capsys):
    table = tmp_path / "p.csv"
    points_table(table, 30)
    lines = table.read_text().splitlines()
    lines[26] = "0,nan,1"  # row 26 of the table, in the fourth chunk of 7 rows
    table.write_text("\n".join(lines) + "\n")
    out = tmp_path / "out.csv"
    argv = ["point", "--robot", CDPR4, "--points", str(table), "--out", str(out), "--chunk-rows", "7"]
    assert main(argv) == 2
    assert "row 26 has a non-finite coordinate" in capsys.readouterr().err
    assert not out.exists() and os.listdir(tmp_path) == ["p.csv"]


# --- progress bar, quiet mode, expected time ------------------------------------------------------


def test_not_a_terminal_no_bar_and_quiet_nothing(tmp_path):
    """stderr is a pipe: no bar (stderr empty); --quiet: stderr empty, stdout as without it."""
    table = tmp_path / "p.parquet"
    points_table(table, 40)
    plain = cdpr("compensate", "--robot", CDPR4, "--points", table, "--out", tmp_path / "a.csv")
    quiet = cdpr("compensate", "--robot", CDPR4, "--points", table, "--out", tmp_path / "b.csv", "--quiet")
    assert plain.returncode == quiet.returncode == 0
    assert plain.stderr == "" and quiet.stderr == ""
    assert plain.stdout.replace("a.csv", "b.csv") == quiet.stdout


def run_on_terminal(*argv):
    """``cdpr argv`` with stderr on a pseudo-terminal; returns (exit code, what stderr got)."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))  # a terminal's size
    p = subprocess.Popen(
        [sys.executable, "-m", "cdpr", *map(str, argv)], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=slave
    )
    os.close(slave)
    got = b""
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:  # the terminal closed with the process
            break
        if not data:
            break
        got += data
    os.close(master)
    return p.wait(), got.decode(errors="replace")


def test_on_a_terminal_a_bar_and_with_quiet_nothing(tmp_path):
    table = tmp_path / "p.parquet"
    points_table(table, 40)
    code, err = run_on_terminal(
        "point", "--robot", CDPR4, "--points", table, "--out", tmp_path / "a.csv", "--chunk-rows", "10"
    )
    assert code == 0 and "point: " in err and "/40 [" in err and " points/s" in err, err
    code, err = run_on_terminal(
        "point", "--robot", CDPR4, "--points", table, "--out", tmp_path / "b.csv", "--quiet"
    )
    assert code == 0 and err == "", err


def test_progress_draws_on_a_terminal_only():
    class Terminal(stdio.StringIO):
        def isatty(self):
            return True

    for stream_, quiet, bar in (
        (stdio.StringIO(), False, False),
        (Terminal(), False, True),
        (Terminal(), True, False),
    ):
        p = stream.Progress(10, "point", quiet=quiet, stream=stream_)
        p.update(10)
        p.say("a line")
        p.close()
        text = stream_.getvalue()
        assert ("10/10" in text) is bar, text
        assert ("a line" in text) is not quiet


def test_the_expected_time_is_said_when_over_a_minute(monkeypatch, capsys):
    """At the first chunk's rate (0.05 s per 10 points), 100 points take 0.5 s: said when the limit
    is below that, not when above, never with --quiet."""

    def slow(P):
        time.sleep(0.05)
        return P

    chunks = [(np.zeros((10, 3)),)] * 10
    for limit, quiet, said in ((0.2, False, True), (5.0, False, False), (0.2, True, False)):
        monkeypatch.setattr(stream, "ETA_SECONDS", limit)
        assert len(list(stream.solve_chunks(chunks, slow, 100, "compensate", quiet=quiet))) == 10
        err = capsys.readouterr().err
        assert ("compensate: 100 points, expected to take about " in err) is said, err
        assert err.count("\n") == int(said)


def test_a_compile_is_announced_and_a_quick_load_is_not(monkeypatch):
    monkeypatch.setattr(stream, "COMPILE_NOTICE_SECONDS", 0.05)
    for wait, quiet, said in ((0.3, False, True), (0.0, False, False), (0.3, True, False)):
        out = stdio.StringIO()
        dt = stream.warm_up(lambda wait=wait: time.sleep(wait), quiet=quiet, stream=out)
        assert dt >= wait
        assert ("compiling the solver kernels" in out.getvalue()) is said, out.getvalue()
        assert ("compiled in" in out.getvalue()) is said


@pytest.mark.parametrize("command", ["point", "compensate"])
def test_one_heavy_pose_announces_a_compile(monkeypatch, capsys, command):
    """One pose of a heavy-cable robot runs on the compiled engine (``heavy.one_shot``): it goes
    through ``stream.warm_up`` first (the notice above on a cold cache), with the same answer; one
    pose of a massless robot (the numpy reference) does not."""
    calls = []

    def recorder(solve, quiet=False, stream=None):
        calls.append(solve())
        return 0.0

    monkeypatch.setattr(stream, "warm_up", recorder)
    heavy = ["--robot", ROBOTS / "cube50.yaml", "--at", "3", "-2", "20", "--json"]
    extra = ["--redundancy", "physical"] if command == "point" else []
    assert main([command, *map(str, heavy), *extra]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(calls) == 1 and out["status"] == "ok"
    first = calls[0]
    key = "P_s" if command == "point" else "L0"
    # compensate: the same lengths to the bit; point answers with the equilibrium reached from the
    # desired pose (issue 39), the same one here
    assert np.allclose(
        first[key][0], out["solved"] if command == "point" else out["lengths"], rtol=0, atol=1e-9
    )
    if command == "compensate":
        assert first[key][0].tolist() == out["lengths"]
    assert main([command, "--robot", CDPR4, "--at", "0.3", "-0.2", "1.4", "--json", *extra]) == 0
    capsys.readouterr()
    assert len(calls) == 1  # the massless pose: numpy reference, no kernel to load


# --- Ctrl-C ---------------------------------------------------------------------------------------


def test_ctrl_c_ends_with_one_line_exit_130_and_no_output(tmp_path):
    """``compensate --points`` on 60,000 rows with the numpy engine (several seconds of work; no numba
    compile, so no compile notice can reach stderr) gets SIGINT once it writes its output."""
    table = tmp_path / "p.parquet"
    points_table(table, 60_000)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    out = out_dir / "comp.csv"
    p = subprocess.Popen(
        [sys.executable, "-m", "cdpr", "compensate", "--robot", CDPR4, "--points", str(table)]
        + ["--out", str(out), "--engine", "numpy", "--chunk-rows", "2000"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 120
    while not os.listdir(out_dir) and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)  # the temporary output appears once the first chunk is being solved
    assert os.listdir(out_dir) and p.poll() is None, "the command did not start writing"
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=120)
    assert p.returncode == 130
    assert stderr.splitlines() == [INTERRUPTED], stderr
    assert "Traceback" not in stderr and stdout == ""
    assert os.listdir(out_dir) == []


def test_ctrl_c_in_any_command_is_one_line(monkeypatch, capsys):
    from cdpr.cli import inverse

    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(inverse, "cmd_inverse", interrupted)
    assert main(["inverse", "--robot", CDPR4, "--at", "0", "0", "2"]) == 130
    assert capsys.readouterr().err == INTERRUPTED + "\n"


# --- memory ---------------------------------------------------------------------------------------

#: What a 50x longer table may add to the peak memory of ``point --points`` [MiB] with a CSV output,
#: which holds one chunk's work and rows whatever the table's length. Measured on the 2-core
#: machine: 365 MB at 20,000 rows, 367 MB at 10^6 (and ``compensate``: +30 to +45 MiB from 20,000
#: to 200,000 rows); before chunks the whole table was solved at once (1.5 kB per row).
EXTRA_MIB = 100


def peak_rss_mib(*argv):
    """Peak resident memory [MiB] of ``cdpr argv``, measured by a fresh parent process (whose only
    child it is)."""
    code = (
        "import resource, subprocess, sys; "
        "r = subprocess.run([sys.executable, '-m', 'cdpr'] + sys.argv[1:], capture_output=True); "
        "assert r.returncode == 0, r.stderr; "
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
    )
    p = subprocess.run(
        [sys.executable, "-c", code, *map(str, argv)], capture_output=True, text=True, cwd=ROOT
    )
    assert p.returncode == 0, p.stderr
    return int(p.stdout) / 1024


def test_memory_does_not_grow_with_the_table(tmp_path):
    """The issue's 10^6 rows: ``point --points`` (paper mode, compiled engine, CDPR4) on 20,000 rows
    (one chunk) and on 1,000,000 rows (fifty chunks of 20,000), CSV output: the peak grows by less
    than EXTRA_MIB (before chunks a table cost about 1.5 kB per row: +1.4 GiB here;
    benchmarks/README.md has the figures of ``compensate``). About 35 s of CPU in all, most of it
    writing the million CSV rows."""
    small, large = tmp_path / "small.parquet", tmp_path / "large.parquet"
    points_table(small, 20_000, seed=1)
    points_table(large, 1_000_000, seed=2)
    # numba's kernels loaded (compiled, when the cache is cold) once before: a compile's memory
    # would raise the first peak and hide growth
    peak_rss_mib("point", "--robot", CDPR4, "--points", small, "--out", tmp_path / "o.csv", "--quiet")
    peaks = [
        peak_rss_mib("point", "--robot", CDPR4, "--points", t, "--out", tmp_path / "o.csv", "--quiet")
        for t in (small, large)
    ]
    assert peaks[1] < peaks[0] + EXTRA_MIB, peaks
    assert sum(1 for _ in open(tmp_path / "o.csv")) == 1_000_001  # every row written


def test_grid_loads_its_kernels_before_the_clock_starts(monkeypatch, capsys, tmp_path):
    """``grid`` warms the compiled engine up on one point (``stream.warm_up``, which announces a
    compile) before it times the solve: a warm-up made 2 s slower here is not in its seconds."""
    calls = []

    def slow_warm_up(solve, quiet=False, stream=None):
        solve()
        time.sleep(2.0)
        calls.append(quiet)
        return 2.0

    monkeypatch.setattr(stream, "warm_up", slow_warm_up)
    for extra in ([], ["--quiet"]):
        out = tmp_path / "g.parquet"
        argv = ["grid", "--robot", CDPR4, "--frame", "--n", "5", "--out", str(out), "--json", *extra]
        assert main(argv) == 0
        summary = json.loads(capsys.readouterr().out)
        assert summary["points"] == 125 and summary["seconds"] < 2.0, summary
    assert calls == [False, True]
    assert (
        main(["grid", "--robot", CDPR4, "--frame", "--n", "5", "--out", str(out), "--engine", "numpy"]) == 0
    )
    assert calls == [False, True]  # the numpy reference has nothing to compile


@pytest.mark.parametrize("command", [["point", "--redundancy", "physical"], ["compensate"], ["inverse"]])
def test_chunked_poses_of_a_rigid_platform_have_the_bytes_of_one_chunk(tmp_path, command):
    """A rigid platform (hang4_6dof) over a table with rx, ry, rz columns: the 6-DoF paths (numpy
    reference below 500 poses), in chunks of 5 rows against one chunk."""
    rng = np.random.default_rng(5)
    n = 23
    table = tmp_path / "poses.csv"
    pd.DataFrame(
        {
            "x": rng.uniform(-0.5, 0.5, n),
            "y": rng.uniform(-0.5, 0.5, n),
            "z": rng.uniform(1.5, 3.0, n),
            "rx": 0.0,
            "ry": 0.0,
            "rz": rng.uniform(-0.05, 0.05, n),
        }
    ).to_csv(table, index=False)
    outs = []
    for rows in ("5", "1000"):
        out = tmp_path / f"out_{rows}.parquet"
        argv = command + ["--robot", str(ROBOTS / "hang4_6dof.yaml"), "--points", str(table)]
        assert main(argv + ["--out", str(out), "--chunk-rows", rows]) == 0
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
    assert {"rx", "ry", "rz"} <= set(pd.read_parquet(out).columns)


def test_durations_in_words():
    assert [stream._duration(s) for s in (0.4, 45, 960, 9000)] == ["0 s", "45 s", "16 min", "2.5 h"]
