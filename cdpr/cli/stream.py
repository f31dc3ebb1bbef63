"""Long work on the command line: a progress bar, the expected time, the one-time kernel compile.

The commands over ``--points`` tables (``inverse``, ``point``, ``compensate``) solve and write a
table ``--chunk-rows`` rows at a time (``cdpr.table_io.write_table_chunks``); ``solve_chunks`` runs
that loop: a progress bar on a terminal (tqdm, on stderr; none when stderr is not a terminal or with
``--quiet``), and, when the whole table is expected to take more than ``ETA_SECONDS``, one line with
the expected time measured on the first chunk. ``warm_up`` runs a one-point solve before the timed
work, so that numba's one-time compile (a cold cache, e.g. a fresh clone: about a minute) is
announced on stderr instead of being counted in a rate. ``--quiet``: nothing on stderr but errors.
"""

from __future__ import annotations

import sys
import threading
import time

#: A table whose work is expected to last longer than this [s] gets a line with the expected time.
ETA_SECONDS = 60.0
#: A warm-up (one point) still running after this [s] is compiling numba's kernels (a warm cache
#: loads them in 1-2 s on the 2-core machine, a compile takes 15 s to minutes): ``warm_up`` says so.
COMPILE_NOTICE_SECONDS = 5.0


def _duration(seconds):
    """``seconds`` in words: '45 s', '16 min', '2.1 h'."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


class Progress:
    """What a long command says on stderr: a tqdm bar on a terminal, and lines (``say``), nothing
    with ``quiet``."""

    def __init__(self, total, what, quiet=False, stream=None):
        """
        Parameters
        ----------
        total : int
            Points of the work.
        what : str
            The command's name, the bar's label.
        quiet : bool
            ``--quiet``: no bar and no lines.
        stream : file, optional
            Where to write (default ``sys.stderr``); the bar is drawn only when it is a terminal.
        """
        self.stream = sys.stderr if stream is None else stream
        self.quiet = quiet
        self.bar = None
        if not quiet and self.stream.isatty():
            from tqdm import tqdm  # lazy: only a command over a table on a terminal draws a bar

            self.bar = tqdm(total=total, desc=what, unit=" points", file=self.stream, leave=False)

    def update(self, n):
        """Advance the bar by n points."""
        if self.bar is not None:
            self.bar.update(n)

    def say(self, line):
        """One line on stderr (above the bar), unless quiet."""
        if self.quiet:
            return
        if self.bar is not None:
            self.bar.write(line, file=self.stream)
        else:
            print(line, file=self.stream, flush=True)

    def close(self):
        """Remove the bar."""
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def warm_up(solve, quiet=False, stream=None):
    """Run ``solve()`` (one point through the compiled engine) before timed work: numba loads its
    cached kernels, or compiles them when its cache is cold. A compile (the call still running after
    ``COMPILE_NOTICE_SECONDS``) is announced on stderr while it runs, and its time said when done.

    Parameters
    ----------
    solve : callable
        No arguments; its result is discarded.
    quiet : bool
        ``--quiet``: say nothing.
    stream : file, optional
        Where to write (default ``sys.stderr``).

    Returns
    -------
    float
        The seconds it took [s].
    """
    stream = sys.stderr if stream is None else stream
    said = threading.Event()

    def notice():
        said.set()
        print(
            "cdpr: compiling the solver kernels (once: numba caches them for the next runs; about a minute)...",
            file=stream,
            flush=True,
        )

    timer = threading.Timer(COMPILE_NOTICE_SECONDS, notice)
    timer.daemon = True
    t0 = time.perf_counter()
    if not quiet:
        timer.start()
    try:
        solve()
    finally:
        timer.cancel()
    dt = time.perf_counter() - t0
    if said.is_set():
        print(f"cdpr: solver kernels compiled in {_duration(dt)}", file=stream, flush=True)
    return dt


def solve_chunks(chunks, solve, total, what, quiet=False):
    """The frames of ``solve(*chunk)`` for each chunk, one at a time (a generator for
    ``table_io.write_table_chunks``), with a progress bar and, when the whole is expected to last
    longer than ``ETA_SECONDS`` at the rate of the first chunk, one line with the expected time.

    Parameters
    ----------
    chunks : iterable of tuple
        The arguments of ``solve`` per chunk, the first one an array of the chunk's points.
    solve : callable
        Returns the chunk's DataFrame.
    total : int
        Points in all chunks.
    what : str
        The command's name (the bar's label and the line's start).
    quiet : bool
        ``--quiet``: no bar, no line.

    Yields
    ------
    DataFrame
        One per chunk, in order.
    """
    progress = Progress(total, what, quiet)
    try:
        done = 0
        for chunk in chunks:
            t0 = time.perf_counter()
            df = solve(*chunk)
            dt = time.perf_counter() - t0
            first = done == 0
            done += len(chunk[0])
            progress.update(len(chunk[0]))
            if first and done < total and dt > 0:
                expected = dt * total / done
                if expected > ETA_SECONDS:
                    progress.say(
                        f"cdpr: {what}: {total:,} points, expected to take about {_duration(expected)} "
                        f"({done / dt:,.0f} points/s on the first {done:,}); Ctrl-C stops it, leaving no output"
                    )
            yield df
    finally:
        progress.close()
