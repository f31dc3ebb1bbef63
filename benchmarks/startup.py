"""Start-up of the command line, whole processes, measured from outside (issue 16).

  * ``cdpr --help``;
  * ``cdpr point --robot config/robots/cdpr4.yaml --at 0.5 0.2 2.5`` (one point: its default engine,
    the numpy reference below ``cdpr.solve.ONE_SHOT_POSES`` poses), and the same with
    ``--engine compiled`` (the numba kernel's load counted);
  * ``cdpr grid`` over the n^3 (default 63^3 = 250,047) cell-centred grid of the paper's RW_C box, CDPR4
    with DR pulleys, compiled engine, parquet written;
  * a bare process (``BARE``: no command line, no table, no file) that loads the robot and the compiled
    kernel and solves the same grid: the floor of any command built on numba;
  * the numpy reference (``engine="numpy"``, Newton, the same points' solver) on a smaller grid, timed
    inside this process (solve and table only, no start-up: its best case), as seconds per point;

each ``--runs`` times (wall clock and the child's user + system CPU from ``resource``), printed as
median and min; then the ratio of the numpy reference's time per point to the whole ``cdpr grid``
process's time per point, and the ``-X importtime`` top ten (cumulative) of ``cdpr --help`` and
``cdpr point``. Run from the project root:

    .venv/bin/python benchmarks/startup.py [--runs 7] [--n 63] [--n-ref 16] [--threads T]

``cdpr grid`` runs with the command's default threads (all cores) unless ``--threads`` is given;
``--threads 1`` compares engines on one core each (the numpy reference is single-threaded). The
row ``point --engine compiled`` is for information: it shows what the compiled engine's load costs.
On a machine shared with other jobs every figure is an upper bound (the minimum is the nearest to the
unloaded machine).
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]
ROBOT = "config/robots/cdpr4.yaml"
POINT = ["point", "--robot", ROBOT, "--at", "0.5", "0.2", "2.5"]


#: The floor of any command built on the compiled engine: a bare process that imports the robot
#: loader and the paper-mode kernel, solves the same grid as ``cdpr grid`` and exits (no command
#: line, no table, no file written; argv: n, then threads or nothing).
BARE = """
import sys
from cdpr.analyses.workspace import grid_points
from cdpr.compiled.subsets import solve_points_fast
from cdpr.robot import load_robot
robot = load_robot("%s", pulley="DR")
threads = int(sys.argv[2]) if len(sys.argv) > 2 else None
solve_points_fast(robot, grid_points(%r, int(sys.argv[1])), threads=threads)
""" % (ROBOT, RW_C)


def run_once(argv, env):
    """(wall seconds, CPU seconds) of one ``python -m cdpr argv`` process (``python -c BARE argv``
    when argv starts with "-c")."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    cmd = ["-c", BARE, *argv[1:]] if argv[:1] == ["-c"] else ["-m", "cdpr", *argv]
    p = subprocess.run(
        [sys.executable, *cmd],
        cwd=ROOT,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit(f"cdpr {' '.join(argv)} failed ({p.returncode}): {p.stderr.decode().strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def measure(argv, runs, env):
    """{"wall": [...], "cpu": [...]} of ``runs`` processes after one warm-up (caches warm)."""
    run_once(argv, env)
    out = {"wall": [], "cpu": []}
    for _ in range(runs):
        w, c = run_once(argv, env)
        out["wall"].append(w)
        out["cpu"].append(c)
    return out


def line(name, m, per=1):
    """One row: median and min of wall and CPU seconds (divided by ``per``)."""
    med = {k: statistics.median(v) / per for k, v in m.items()}
    low = {k: min(v) / per for k, v in m.items()}
    unit = "s" if per == 1 else "us/point"
    scale = 1 if per == 1 else 1e6
    print(
        f"{name:38s} wall median {med['wall'] * scale:9.3f}  min {low['wall'] * scale:9.3f}   "
        f"cpu median {med['cpu'] * scale:9.3f}  min {low['cpu'] * scale:9.3f}  [{unit}]"
    )
    return med, low


def numpy_reference(n, runs, method):
    """Seconds per point of the numpy reference (``method``: newton or the paper's fixed point; all
    subsets, paper mode) over the n^3 grid of RW_C, CDPR4 DR, inside this process (solve and table
    only): {"wall": [...], "cpu": [...]} of ``runs`` timings."""
    from cdpr.analyses.workspace import grid_points
    from cdpr.robot import load_robot
    from cdpr.tables import solve_table

    robot = load_robot(ROOT / ROBOT, pulley="DR")
    P = grid_points(RW_C, n)
    solve_table(robot, P[:10], method=method, engine="numpy")  # warm-up
    out = []
    for _ in range(runs):
        c0, t0 = time.process_time(), time.perf_counter()
        solve_table(robot, P, method=method, engine="numpy")
        out.append((time.perf_counter() - t0, time.process_time() - c0))
    return {"wall": [w / len(P) for w, _ in out], "cpu": [c / len(P) for _, c in out]}


def importtime_top(argv, env, k=10):
    """The k imports of largest cumulative time of ``python -X importtime -m cdpr argv``."""
    p = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "cdpr", *argv],
        cwd=ROOT,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    rows = []
    for ln in p.stderr.splitlines():
        if ln.startswith("import time:") and "cumulative" not in ln:
            _, self_us, cum_us, name = (x.strip() for x in ln.replace("import time:", "|").split("|"))
            rows.append((int(cum_us), int(self_us), name))
    rows.sort(reverse=True)
    total = sum(s for _, s, _ in rows)
    print(
        f"\n-X importtime, cdpr {' '.join(argv)}: {len(rows)} modules, {total / 1e3:.0f} ms of imports in all"
    )
    print(f"  {'cumulative ms':>13s} {'self ms':>8s}  module")
    for cum, self_, name in rows[:k]:
        print(f"  {cum / 1e3:13.1f} {self_ / 1e3:8.1f}  {name}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=7, help="processes per command (after one warm-up)")
    ap.add_argument("--n", type=int, default=63, help="points per axis of the cdpr grid run")
    ap.add_argument("--n-ref", type=int, default=16, help="points per axis of the numpy reference")
    ap.add_argument(
        "--threads",
        type=int,
        help="threads of the compiled engine in cdpr grid (default: the command's, all cores)",
    )
    args = ap.parse_args()
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    print(
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}, Python {platform.python_version()}"
    )
    help_m = measure(["--help"], args.runs, env)
    point_m = measure(POINT, args.runs, env)
    point_c = measure(POINT + ["--engine", "compiled"], args.runs, env)
    with tempfile.TemporaryDirectory() as tmp:
        grid = ["grid", "--robot", ROBOT, "--pulley", "DR", "--box", *map(str, RW_C), "--n", str(args.n)]
        grid += ["--out", str(Path(tmp) / "g.parquet")] + (
            [] if args.threads is None else ["--threads", str(args.threads)]
        )
        grid_m = measure(grid, args.runs, env)
    bare_m = measure(
        ["-c", str(args.n)] + ([] if args.threads is None else [str(args.threads)]), args.runs, env
    )
    refs = {m: numpy_reference(args.n_ref, max(3, args.runs // 2), m) for m in ("newton", "fixed_point")}
    n_pts = args.n**3
    print()
    line("cdpr --help", help_m)
    line("cdpr point --at (default: numpy)", point_m)
    line("cdpr point --at --engine compiled", point_c)
    line(f"cdpr grid --n {args.n} (whole process)", grid_m)
    g_med, g_min = line(f"cdpr grid --n {args.n}, per point", grid_m, per=n_pts)
    b_med, b_min = line("bare solve process, per point", bare_m, per=n_pts)
    for m, ref in refs.items():
        r_med = {k: statistics.median(v) for k, v in ref.items()}
        r_min = {k: min(v) for k, v in ref.items()}
        print(
            f"{f'numpy {m} {args.n_ref}^3, per point':38s} wall median {r_med['wall'] * 1e6:9.3f}  "
            f"min {r_min['wall'] * 1e6:9.3f}   cpu median {r_med['cpu'] * 1e6:9.3f}  min {r_min['cpu'] * 1e6:9.3f}"
            "  [us/point]"
        )
        print(
            f"  ratio numpy {m} / whole cdpr grid process, per point: wall median "
            f"{r_med['wall'] / g_med['wall']:.1f}x (min/min {r_min['wall'] / g_min['wall']:.1f}x), "
            f"cpu median {r_med['cpu'] / g_med['cpu']:.1f}x (min/min {r_min['cpu'] / g_min['cpu']:.1f}x)"
        )
        print(
            f"  ratio numpy {m} / bare solve process (the floor of any numba command), per point: wall "
            f"median {r_med['wall'] / b_med['wall']:.1f}x (min/min {r_min['wall'] / b_min['wall']:.1f}x)"
        )
    importtime_top(["--help"], env)
    importtime_top(POINT, env)


if __name__ == "__main__":
    main()
