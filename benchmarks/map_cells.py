"""Throughput of the h-r_p map job (Fig. 17) at the paper's N per cell, before and after the
symmetric-orbit solve, in one run on this machine.

For a few map cells (h, r_p) of each pulley kind on CDPR4 over the paper's RW_C box at n^3 points
per cell (default 63^3 = 250,047, the DOE's N), in paper and physical mode:
  * full:      every grid point solved (the map job before: solve_table on the whole grid);
  * symmetric: one point per orbit of the D4 symmetries robot and grid share (cdpr.analyses.symmetry,
               33,264 solved points per cell at n = 63), copied to the whole grid.
Reported: seconds per cell, kernel points/s (points actually solved / s), effective cell points/s
(n^3 / s), the largest |index difference| between the two, and the CPU model.

    .venv/bin/python benchmarks/map_cells.py [--n 63] [--repeat 2] [--cells 3]
"""

import argparse
import subprocess
import time
from pathlib import Path

from cdpr.analyses import doe
from cdpr.analyses.symmetry import solve_grid
from cdpr.analyses.workspace import grid_points
from cdpr.robot import load_robot, with_pulleys
from cdpr.solve import solve

ROOT = Path(__file__).resolve().parents[1]
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


def cpu_model():
    out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    return next(
        (line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Model name")), "?"
    )


def best(fn, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=63)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--cells", type=int, default=3, help="map cells per pulley kind")
    args = ap.parse_args()
    base = load_robot(ROOT / "config" / "robots" / "cdpr4.yaml")
    cells = {
        "SR": [(0.1077, 0.035), (0.10, 0.0665), (0.15, 0.098)],
        "DR": [(0.10, 0.08), (0.10, 0.0665), (0.15, 0.035)],
    }
    P = grid_points(RW_C, args.n)
    print(f"CPU {cpu_model()}; {args.n}^3 = {len(P):,} points per cell over RW_C; best of {args.repeat}")
    print(
        f"{'mode':<9} {'kind':<4} {'full s/cell':>11} {'full pts/s':>11} {'sym s/cell':>10} {'sym solved pts/s':>16} {'sym cell pts/s':>14} {'speed-up':>8} {'max|dI| m':>10}"
    )
    for mode in ("paper", "physical"):
        for kind, hr in cells.items():
            hr = hr[: args.cells]
            robots = [with_pulleys(base, kind=kind, h=h, r_p=r) for h, r in hr]
            solve(robots[0], P[:10], redundancy=mode)  # load the kernel
            tf, full = best(lambda: [solve(r, P, redundancy=mode) for r in robots], args.repeat)
            ts, sym = best(
                lambda: [solve_grid(r, RW_C, args.n, redundancy=mode) for r in robots], args.repeat
            )
            dI = max(
                abs(doe.global_index(f["dp"], f["status"])[0] - doe.global_index(s[0], s[1])[0])
                for f, s in zip(full, sym)
            )
            k = len(robots)
            solved = sym[0][2]
            print(
                f"{mode:<9} {kind:<4} {tf / k:11.3f} {len(P) * k / tf:11,.0f} {ts / k:10.3f} {solved * k / ts:16,.0f}"
                f" {len(P) * k / ts:14,.0f} {tf / ts:8.1f} {dI:10.1e}"
            )


if __name__ == "__main__":
    main()
