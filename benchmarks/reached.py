"""The cost of a reached equilibrium (issue 39): one continued point (``cdpr.solve.reach``, the
adaptive continuation from the compensated start) against a plain solve of the same point
(``cdpr.solve.solve``, the local Newton solve with the restarts), both on the same engine (the
compiled one, the default of both, and the numpy reference), on the issue's wall robot example
(tests/data/wall_crossed.yaml) and on CoGiRo at a unique equilibrium.
Each figure is the median and the minimum of ``--runs`` runs, in one process after a warm-up.
Run from the project root:

    .venv/bin/python benchmarks/reached.py [--runs 5]

On a machine shared with other jobs every figure is an upper bound (the minimum is the nearest to the
unloaded machine).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from cdpr.robot import load_robot
from cdpr.solve import reach, solve

ROOT = Path(__file__).resolve().parents[1]
L0 = [6.52907908125, 6.14882031715, 5.85918529262, 6.26397544351, 6.06888687927, 5.63634727396, 5.23674973794, 5.70862689323]  # fmt: skip
CASES = [
    ("wall_crossed, the issue's example", ROOT / "tests/data/wall_crossed.yaml", [0.3, 0.3, 0.7], [0.12, 0.12, 0.0], L0),
    ("CoGiRo, unique equilibrium", ROOT / "config/robots/cogiro_massless.yaml", [0.5, 0.3, 1.5], [0.0, 0.0, 0.1], None),
]  # fmt: skip


def timed(f, runs):
    """Median and minimum wall time [s] of ``runs`` calls of f, and f's last result."""
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
    return statistics.median(times), min(times), out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    head = f"{'case':38s} {'engine':8s} {'plain solve [ms]':>18s} {'continued [ms]':>16s} {'ratio':>6s} {'steps':>6s}"
    print(head)
    for name, path, p, rv, L in CASES:
        robot = load_robot(path)
        P, RV = np.array([p]), np.array(rv)
        for engine in ("compiled", "numpy"):
            plain = lambda: solve(robot, P, RV, L0=L, engine=engine)  # noqa: E731
            cont = lambda: reach(robot, P, RV, L0=L, engine=engine)  # noqa: E731
            plain(), cont()  # warm-up (and the compiled kernels' first compile)
            m0, n0, _ = timed(plain, args.runs)
            m1, n1, res = timed(cont, args.runs)
            steps = len(res["lambdas"][0]) - 1
            print(
                f"{name:38s} {engine:8s} {1e3 * m0:8.1f} (min {1e3 * n0:5.1f}) "
                f"{1e3 * m1:7.1f} (min {1e3 * n1:5.1f}) {m1 / m0:6.1f} {steps:6d}"
            )


if __name__ == "__main__":
    main()
