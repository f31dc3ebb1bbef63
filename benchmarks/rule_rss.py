"""Peak memory (max RSS) and wall time of every job of a study, by rule, measured with GNU time.

    python benchmarks/rule_rss.py --study config/studies/quick.yaml --results results/rss_quick [--cores 2]

1. Runs the study locally (``snakemake --cores N``) so that every job's inputs exist.
2. Lists every job's shell command (``snakemake -n -p --forceall``, with the same ``--cores``, so
   ``--threads`` is what a run gives) and runs them one after the other under ``/usr/bin/time -v``
   on an otherwise idle machine (outputs are rewritten with the same content).
3. Prints, per rule: jobs, peak RSS [MiB] (the largest over the rule's jobs) and wall time [s]
   (median and max). ``workflow/profiles/slurm/config.yaml`` takes its ``mem_mb`` from these peaks.

Needs GNU time (Debian package ``time``).
"""

import argparse
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def snakemake(*args, capture=False):
    cmd = [sys.executable, "-m", "snakemake", "reproduce_paper", *args]
    return subprocess.run(cmd, cwd=ROOT, check=True, text=True, capture_output=capture)


def shell_commands(dry_run: str):
    """(rule, shell command) of every job in a ``snakemake -n -p`` listing."""
    rule = None
    for line in dry_run.splitlines():
        m = re.match(r"^(?:local)?rule (\w+):$", line.strip())
        if m:
            rule = m.group(1)
        elif line.startswith("Shell command: ") and rule and line != "Shell command: None":
            yield rule, line[len("Shell command: ") :]


def measure(command: str):
    with tempfile.NamedTemporaryFile("r", suffix=".time") as out:
        subprocess.run(["/usr/bin/time", "-v", "-o", out.name, "bash", "-c", command], cwd=ROOT, check=True)
        text = out.read()
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", text)
    wall = int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3))
    return rss_kb / 1024, wall


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--study", required=True)
    ap.add_argument("--results", required=True)
    ap.add_argument("--cores", type=int, default=2)
    a = ap.parse_args()
    cfg = ["--config", f"study={a.study}", f"results={a.results}"]
    snakemake("--cores", str(a.cores), "--quiet", "all", *cfg)
    listing = snakemake("-n", "-p", "--forceall", "--cores", str(a.cores), *cfg, capture=True).stdout
    by_rule = {}
    for rule, cmd in shell_commands(listing):
        by_rule.setdefault(rule, []).append(measure(cmd))
    print(f"study {a.study}, --cores {a.cores}")
    print(f"{'rule':<20} {'jobs':>4} {'peak RSS MiB':>13} {'wall s median':>14} {'wall s max':>11}")
    for rule, runs in sorted(by_rule.items(), key=lambda kv: -max(r for r, _ in kv[1])):
        rss = max(r for r, _ in runs)
        walls = [w for _, w in runs]
        print(f"{rule:<20} {len(runs):>4} {rss:>13.0f} {statistics.median(walls):>14.2f} {max(walls):>11.2f}")


if __name__ == "__main__":
    main()
