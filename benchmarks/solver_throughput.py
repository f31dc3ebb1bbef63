"""Throughput of the DEGM_E solvers, measured in one run on this machine.

For each robot x pulley kind, over the cell-centred grid of the paper's RW_C box:
  * fast:  the compiled engine (cdpr.fast: numba kernel, analytic-Jacobian Newton, subset pruning,
           both cores), the default of `cdpr grid` and of the pipeline;
  * fixed: the project's own implementation of the paper's nested fixed-point scheme
           (cdpr.direct, numpy, vectorised over points, eps_P = 1e-5 m, every subset);
points/s, subset-solves/s, their ratio, and the largest |dp| difference between the two on ok points.
Then `cdpr grid` end to end (grid, solve, statuses, parquet) on CDPR4_DR at 63^3.

    .venv/bin/python benchmarks/solver_throughput.py [--n 30] [--repeat 3]
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from cdpr.fast import solve_points_fast
from cdpr.redundancy import solve_points
from cdpr.robot import load_robot, with_pulleys
from cdpr.workspace import grid_points

ROOT = Path(__file__).resolve().parents[1]
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument(
        "--n", type=int, default=30, help="points per axis for the solver comparison (n^3 points)"
    )
    ap.add_argument("--repeat", type=int, default=3, help="best of this many runs")
    args = ap.parse_args()
    P = grid_points(RW_C, args.n)
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    )
    print(f"{len(P)} points per design ({args.n}^3 cell centres of RW_C); best of {args.repeat}")
    hdr = f"{'design':<9} {'fast pts/s':>11} {'fast solves/s':>14} {'fixed pts/s':>12} {'fixed solves/s':>15} {'ratio':>6} {'max|ddp| m':>11}"
    print(hdr)
    for name in ("cdpr3", "cdpr4"):
        base = load_robot(ROOT / "config" / "robots" / f"{name}.yaml")
        for kind in ("SR", "DR"):
            r = with_pulleys(base, kind=kind)
            solve_points_fast(r, P[:10])  # load the compiled kernel
            tf, a = best_of(lambda r=r: solve_points_fast(r, P), args.repeat)
            tx, b = best_of(lambda r=r: solve_points(r, P, method="fixed_point"), 1)
            ok = (a["status"] == "ok") & (b["status"] == "ok")
            diff = np.abs(a["dp"][ok] - b["dp"][ok]).max()
            print(
                f"{base.name + '_' + kind:<9} {len(P) / tf:>11.0f} {a['subset_solves'].sum() / tf:>14.0f} {len(P) / tx:>12.0f} "
                f"{len(P) * len(r.subsets) / tx:>15.0f} {tx / tf:>6.0f} {diff:>11.1e}"
            )
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [
            sys.executable,
            "-m",
            "cdpr",
            "grid",
            "--robot",
            str(ROOT / "config/robots/cdpr4.yaml"),
            "--pulley",
            "DR",
            "--box",
            *map(str, RW_C),
            "--n",
            "63",
            "--out",
            f"{tmp}/g.parquet",
        ]
        walls, own = [], []
        for _ in range(max(args.repeat, 11)):
            t0 = time.perf_counter()
            out = subprocess.run(cmd + ["--json"], capture_output=True, text=True, check=True).stdout
            walls.append(time.perf_counter() - t0)
            own.append(json.loads(out)["seconds"])
        n = 250047
        print(
            f"cdpr grid CDPR4_DR 63^3 = {n:,} points, {len(own)} runs; command's own timer (grid, numba start-up, solve, "
            f"statuses, parquet): best {min(own):.2f} s = {n / min(own):,.0f} points/s, median {np.median(own):.2f} s = "
            f"{n / np.median(own):,.0f} points/s; whole process incl. Python start-up: best {min(walls):.2f} s = "
            f"{n / min(walls):,.0f} points/s, median {np.median(walls):.2f} s"
        )


if __name__ == "__main__":
    main()
