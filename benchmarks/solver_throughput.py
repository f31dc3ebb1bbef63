"""Throughput of the DEGM_E solvers, measured in one run on this machine.

For each robot x pulley kind: points/s and subset-solves/s of the default (Newton) solver and of
the project's own fixed-point solver (the paper's scheme, eps_P = 1e-5 m), over the cell-centred
grid of the paper's RW_C box, single process, and their ratio.

    .venv/bin/python benchmarks/solver_throughput.py [--n 30]
"""
import argparse
import time
from pathlib import Path

from cdpr.redundancy import solve_table
from cdpr.robot import load_robot, with_pulleys
from cdpr.workspace import grid_points

ROOT = Path(__file__).resolve().parents[1]
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]


def rate(robot, P, method):
    t0 = time.perf_counter()
    df = solve_table(robot, P, method=method)
    dt = time.perf_counter() - t0
    return len(P) / dt, len(P) * len(robot.subsets) / dt, df


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=30, help="points per axis (n^3 points)")
    args = ap.parse_args()
    P = grid_points(RW_C, args.n)
    print(f"{len(P)} points per design (RW_C box, {args.n}^3 cell centres), one process")
    print(f"{'design':<10} {'newton pts/s':>13} {'subset-solves/s':>16} {'fixed-pt pts/s':>15} {'subset-solves/s':>16} {'ratio':>6} {'max |diff| [m]':>15}")
    for name in ("cdpr3", "cdpr4"):
        base = load_robot(ROOT / "config" / "robots" / f"{name}.yaml")
        for kind in ("SR", "DR"):
            r = with_pulleys(base, kind=kind)
            pn, sn, a = rate(r, P, "newton")
            pf, sf, b = rate(r, P, "fixed_point")
            ok = (a.status == "ok") & (b.status == "ok")
            diff = (a.dp[ok] - b.dp[ok]).abs().max()
            print(f"{base.name + '_' + kind:<10} {pn:>13.0f} {sn:>16.0f} {pf:>15.0f} {sf:>16.0f} {pn / pf:>6.2f} {diff:>15.2e}")


if __name__ == "__main__":
    main()
