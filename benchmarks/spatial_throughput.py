"""Spatial (6-DoF) equilibrium solves per second beside the point-mass physical kernel, in one run.

CoGiRo (config/robots/cogiro.yaml) commanded with L_TS at N random poses in a box round the centre
(|rotation| up to 10 deg), solved by the numpy reference ``equilibrium6.solve_spatial`` (with and
without the restarts); CDPR4 SR physical mode at N random points by the compiled kernel and the
numpy reference. The compiled 6-DoF engine does not exist yet (issue 17: it waits for the shared
scalar cable kernel), so there is no compiled spatial figure.

    .venv/bin/python benchmarks/spatial_throughput.py [--n 2000] [--repeat 2]
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

from cdpr.models.equilibrium import solve_physical
from cdpr.models.equilibrium6 import solve_spatial
from cdpr.robot import load_robot

ROOT = Path(__file__).resolve().parents[1]


def best(fn, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    g = np.random.default_rng(0)
    cog = load_robot(ROOT / "config/robots/cogiro.yaml")
    p = np.column_stack([g.uniform(-3, 3, args.n), g.uniform(-2, 2, args.n), g.uniform(1.0, 3.0, args.n)])
    rv = g.normal(size=(args.n, 3))
    rv *= (np.radians(10) * g.uniform(0, 1, (args.n, 1))) / np.linalg.norm(rv, axis=1, keepdims=True)
    t, res = best(lambda: solve_spatial(cog, p, rv), args.repeat)
    t_nr, _ = best(lambda: solve_spatial(cog, p, rv, restarts=False), args.repeat)
    ok = (res["status"] == "ok").mean()
    print(
        f"CoGiRo 6-DoF numpy reference: {args.n / t:,.0f} solves/s with restarts, {args.n / t_nr:,.0f} without"
    )
    print(
        f"  status ok: {ok:.1%}; not unique: {(~res['unique']).sum()}; median iterations {np.median(res['iterations']):g}"
    )
    r4 = load_robot(ROOT / "config/robots/cdpr4.yaml")
    P = np.column_stack(
        [g.uniform(-2.3, 2.3, args.n), g.uniform(-2.3, 2.3, args.n), g.uniform(0.2, 3.7, args.n)]
    )
    from cdpr.compiled.equilibrium import solve_physical_fast

    solve_physical_fast(r4, P[:10])  # compile
    tc, _ = best(lambda: solve_physical_fast(r4, P), args.repeat)
    tn, _ = best(lambda: solve_physical(r4, P), args.repeat)
    print(
        f"CDPR4 SR point mass: compiled {args.n / tc:,.0f} /s, numpy {args.n / tn:,.0f} /s (cores: {os.cpu_count()})"
    )


if __name__ == "__main__":
    main()
