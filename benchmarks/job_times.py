"""Where the time of a Snakemake run goes, rule by rule, from Snakemake's own log (issue 19).

Snakemake writes one log per invocation under ``.snakemake/log/`` with a time stamp (1 s resolution)
before every job's start (``rule X:`` / ``localrule X:`` with its ``jobid``) and before every
``Finished jobid: N``. This script pairs them and prints, per rule, the number of jobs, the sum of
their wall seconds, the longest job and the rule's share of the summed job time, largest first, and
the run's own wall time (first to last stamp). Jobs run side by side on several cores, so the sum of
job times exceeds the wall time; a job's wall time also grows with the machine's load. Run from the
project root after ``make reproduce`` (each of its snakemake commands leaves one log):

    .venv/bin/python benchmarks/job_times.py .snakemake/log/*.snakemake.log        # every run, one table each
    .venv/bin/python benchmarks/job_times.py --top 8 LOG [LOG ...]
"""

from __future__ import annotations

import argparse
import datetime as dt
import re
import sys
from pathlib import Path

STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]$")
START = re.compile(r"^(?:local)?(?:rule|checkpoint) (\S+):$")
JOBID = re.compile(r"^\s+jobid: (\d+)$")
DONE = re.compile(r"^Finished jobid: (\d+)")
COMMAND = re.compile(r"^\s+Command: (.*)$")


def parse(path):
    """Jobs of one Snakemake log: list of (rule, start, end) with datetimes, the command line and the
    first and last time stamps."""
    now = first = last = None
    pending = None  # (rule, start) until its jobid line
    started, jobs, command = {}, [], ""
    for line in Path(path).read_text(encoding="utf-8", errors="replace").splitlines():
        if m := STAMP.match(line):
            now = dt.datetime.strptime(m.group(1), "%a %b %d %H:%M:%S %Y")
            first = first or now
            last = now
        elif m := COMMAND.match(line):
            command = command or m.group(1)
        elif m := START.match(line):
            pending = (m.group(1), now)
        elif (m := JOBID.match(line)) and pending is not None:
            started[int(m.group(1))] = pending
            pending = None
        elif (m := DONE.match(line)) and int(m.group(1)) in started:
            rule, start = started.pop(int(m.group(1)))
            jobs.append((rule, start, now))
    return jobs, command, first, last


def table(jobs):
    """Per rule: (rule, jobs, summed seconds, longest seconds), largest sum first."""
    out = {}
    for rule, start, end in jobs:
        s = (end - start).total_seconds()
        n, tot, top = out.get(rule, (0, 0.0, 0.0))
        out[rule] = (n + 1, tot + s, max(top, s))
    return sorted(((r, *v) for r, v in out.items()), key=lambda row: (-row[2], row[0]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("logs", nargs="+", help="Snakemake log files (.snakemake/log/*.snakemake.log)")
    ap.add_argument("--top", type=int, default=10, help="rules listed per run (default 10)")
    args = ap.parse_args(argv)
    for path in args.logs:
        jobs, command, first, last = parse(path)
        if not jobs:
            print(f"{path}: no finished job")
            continue
        rows = table(jobs)
        total = sum(r[2] for r in rows)
        wall = (last - first).total_seconds()
        print(
            f"\n{path}\n  {command}\n  wall {wall:.0f} s (first to last stamp), {len(jobs)} jobs, job time summed {total:.0f} s"
        )
        print("| rule | jobs | summed job wall [s] | longest job [s] | share |")
        print("|---|---|---|---|---|")
        for rule, n, tot, top in rows[: args.top]:
            print(f"| {rule} | {n} | {tot:.0f} | {top:.0f} | {tot / total:.0%} |")
        if len(rows) > args.top:
            rest = sum(r[2] for r in rows[args.top :])
            print(
                f"| ({len(rows) - args.top} other rules) | {sum(r[1] for r in rows[args.top :])} | {rest:.0f} | | {rest / total:.0%} |"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
