"""Throughput of the DEGM_E solvers, measured in one run on this machine.

For each robot x pulley kind, over the cell-centred grid of the paper's RW_C box:
  * fast:  the compiled engine (cdpr.compiled.subsets: numba kernel, analytic-Jacobian Newton, subset pruning,
           both cores), the default of `cdpr grid` and of the pipeline;
  * fixed: the project's own implementation of the paper's nested fixed-point scheme
           (cdpr.models.direct, numpy, vectorised over points, eps_P = 1e-5 m, every subset);
points/s, subset-solves/s, their ratio, and the largest |dp| difference between the two on ok points.
Then `cdpr grid` end to end (grid, solve, statuses, parquet) on CDPR4_DR at 63^3.

Then, side by side in the same run on CDPR4_SR and CDPR4_DR over the 63^3 grid of RW_C (``--nphys``):
  * paper:        the compiled paper-mode kernel (cdpr.compiled.subsets.solve_points_fast);
  * physical:     the compiled physical equilibrium on all four cables (cdpr.compiled.equilibrium);
  * comp lengths: compensated rest lengths (cdpr.analyses.compensation.compensate, min_norm, t_min 100 N,
                  numpy, vectorised);
  * comp + solve: those lengths and the physical equilibrium they give (compensated_pose, compiled).

    .venv/bin/python benchmarks/solver_throughput.py [--n 30] [--repeat 3] [--physical-only] [--nphys 63]
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

from cdpr.analyses.compensation import compensate, compensated_pose
from cdpr.analyses.workspace import grid_points
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.compiled.subsets import solve_points_fast
from cdpr.models.subsets import solve_points
from cdpr.robot import load_robot, with_pulleys

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
    ap.add_argument(
        "--physical-only", action="store_true", help="only the paper / physical / compensation table"
    )
    ap.add_argument(
        "--nphys", type=int, default=63, help="points per axis of the physical table (n^3 points)"
    )
    args = ap.parse_args()
    if args.physical_only:
        physical_table(args)
        return
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


def cpu_model():
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        return next(
            line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Model name")
        )
    except (OSError, subprocess.CalledProcessError, StopIteration):
        return platform.processor() or platform.machine()


def physical_table(args):
    """Paper mode, physical mode and compensation side by side (points/s, same run, same grid)."""
    P = grid_points(RW_C, args.nphys)
    base = load_robot(ROOT / "config" / "robots" / "cdpr4.yaml")
    print(
        f"{cpu_model()}, {os.cpu_count()} cores; {len(P):,} points ({args.nphys}^3 cell centres of RW_C); best of {args.repeat}"
    )
    print(
        f"{'design':<9} {'paper pts/s':>12} {'physical pts/s':>15} {'phys/paper':>11} {'comp lengths pts/s':>19} "
        f"{'comp+solve pts/s':>17} {'phys iters':>11}"
    )
    for kind in ("SR", "DR"):
        r = with_pulleys(base, kind=kind)
        solve_points_fast(r, P[:10])  # load the compiled kernels
        solve_physical_fast(r, P[:10])
        ta, _ = best_of(lambda r=r: solve_points_fast(r, P), args.repeat)
        tb, b = best_of(lambda r=r: solve_physical_fast(r, P), args.repeat)
        tc, _ = best_of(lambda r=r: compensate(r, P), args.repeat)
        td, _ = best_of(lambda r=r: compensated_pose(r, P), args.repeat)
        print(
            f"{base.name + '_' + kind:<9} {len(P) / ta:>12,.0f} {len(P) / tb:>15,.0f} {ta / tb:>11.2f} {len(P) / tc:>19,.0f} "
            f"{len(P) / td:>17,.0f} {b['iterations'].mean():>11.2f}"
        )


if __name__ == "__main__":
    main()
