"""Where the compiled 6-DoF Newton's time goes (issue 17): one ``eval6`` (the energy, gradient,
tensions and 6 x 6 Jacobian at one pose, every cable through the shared ``_kernels.cable_axis``)
timed alone on one thread, beside the whole compiled Newton ``newton6_fast`` on one thread, on the
same CoGiRo poses as ``spatial_throughput.py``. Prints the cost of one evaluation, of one solve,
the evaluations per solve (iterations + 1) and the evaluations' share of the solve; then the numpy
reference (``models.equilibrium.solve``, with its restarts, as ``spatial_throughput.py``) on the
first ``--n-numpy`` poses and the largest compiled/numpy ratio a Newton with these evaluations could
reach on all cores: a solve that did nothing but its evaluations, with perfect scaling over the cores.

    .venv/bin/python benchmarks/spatial_profile.py [--n 20000] [--n-numpy 2000]
"""

import argparse
import os
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit

from cdpr.compiled.equilibrium import CompiledCables as Compiled6
from cdpr.compiled.equilibrium import evaluate as eval6
from cdpr.compiled.equilibrium import newton as newton6_fast
from cdpr.compiled.equilibrium import scratch as scratch6
from cdpr.models.equilibrium import PHYSICAL_DEFAULTS
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays
from cdpr.robot import load_robot

ROOT = Path(__file__).resolve().parents[1]


@njit
def _evals(pp, R, L0, cab, body):
    """One ``eval6`` at each pose (pose i, rest lengths L0[i]); returns the summed merit."""
    w = scratch6(cab.A.shape[0])
    s = 0.0
    for i in range(pp.shape[0]):
        Ri = R[i].copy()
        x, y, z = pp[i, 0], pp[i, 1], pp[i, 2]
        eval6(x, y, z, Ri, x, y, z, cab, body, L0, i, w.t, w.J, w.e6, w.g6, w)
        s += w.e6[12]
    return s


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20000)
    ap.add_argument("--n-numpy", type=int, default=2000)
    args = ap.parse_args()
    n, nn = args.n, args.n_numpy
    g = np.random.default_rng(0)
    cog = load_robot(ROOT / "config/robots/cogiro_massless.yaml")
    p = np.column_stack([g.uniform(-3, 3, n), g.uniform(-2, 2, n), g.uniform(1.0, 3.0, n)])
    rv = g.normal(size=(n, 3))
    rv *= (np.radians(10) * g.uniform(0, 1, (n, 1))) / np.linalg.norm(rv, axis=1, keepdims=True)
    cab = Compiled6(cog)
    pp, R = pose_arrays(p, rv)
    L0 = L_TS(cog, pp, R=R)
    o = PHYSICAL_DEFAULTS
    print(f"load before {os.getloadavg()}")
    _evals(pp[:10], R[:10], L0[:10], cab.cables, cab.body)
    t0 = time.perf_counter()
    _evals(pp, R, L0, cab.cables, cab.body)
    te = (time.perf_counter() - t0) / n
    numba.set_num_threads(1)
    newton6_fast(cab, pp[:10], R[:10], L0[:10], pp[:10], o["tol"], o["maxiter"], o["max_step"])
    t0 = time.perf_counter()
    it = newton6_fast(cab, pp, R, L0, pp, o["tol"], o["maxiter"], o["max_step"])[3]
    tk = (time.perf_counter() - t0) / n
    ev = it.mean() + 1
    print(
        f"CoGiRo (m = {cog.m}), one thread: one eval6 {te * 1e6:.2f} us ({te / cog.m * 1e9:.0f} ns per "
        f"cable); one Newton solve {tk * 1e6:.2f} us; {ev:.2f} evaluations per solve, "
        f"{ev * te * 1e6:.2f} us = {ev * te / tk:.0%} of the solve"
    )
    solve_spatial(cog, p[:5], rv[:5])
    t0 = time.perf_counter()
    solve_spatial(cog, p[:nn], rv[:nn])
    tn = (time.perf_counter() - t0) / nn
    cores = numba.config.NUMBA_NUM_THREADS
    print(
        f"numpy reference {tn * 1e6:.0f} us per solve (N = {nn}); evaluations only, {cores} cores, perfect "
        f"scaling: {ev * te / cores * 1e6:.2f} us per solve, a ratio of at most {tn / (ev * te / cores):.0f}"
    )
    print(f"load after {os.getloadavg()}")


if __name__ == "__main__":
    main()
