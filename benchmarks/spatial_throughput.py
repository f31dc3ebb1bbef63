"""Spatial (6-DoF) equilibria per second, compiled and numpy, beside the point-mass compiled kernel,
in one run.

CoGiRo (config/robots/cogiro_massless.yaml) commanded with L_TS at N random poses in a box round the centre
(|rotation| up to 10 deg), solved by the compiled engine ``cdpr.compiled.equilibrium.solve``
(warm: compiled before the clock starts) and by the numpy reference ``models.equilibrium.solve``
(on the first ``--n-numpy`` of them, it is slow), both with the restarts; the ratio; the compiled
Newton kernel alone (``newton6_fast``, without the numpy set-up and result); the 6-DoF sensitivities
dp*/dθ, dφ*/dθ of all 84 parameters at those equilibria (``sensitivities_at``: compiled
``cdpr.compiled.sensitivity`` on N, numpy ``cdpr.models.sensitivity`` on ``--n-numpy``, same
solve result) and end to end (``pose_sensitivities``: the solve plus the sensitivities, compiled
on N, numpy on a tenth of ``--n-numpy``); CDPR4 SR physical mode
at N random points by the point-mass compiled kernel and its numpy reference. The machine's load
(``os.getloadavg``) and the CPU model (``lscpu``) are printed: on a shared machine the figures are a lower bound. Wall-clock
rates, best of ``--repeat``; "cpu" is the process's CPU time per solve (all threads).

    .venv/bin/python benchmarks/spatial_throughput.py [--n 20000] [--n-numpy 2000] [--repeat 3]
"""

import argparse
import os
import subprocess
import time
from pathlib import Path

import numba
import numpy as np

from cdpr.compiled.equilibrium import CompiledCables as Compiled6
from cdpr.compiled.equilibrium import newton as newton6_fast
from cdpr.compiled.equilibrium import solve as solve_spatial_fast
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.compiled.sensitivity import pose_sensitivities as spatial_sensitivities_fast
from cdpr.compiled.sensitivity import sensitivities_at as sensitivities_at_fast
from cdpr.models.equilibrium import PHYSICAL_DEFAULTS
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays
from cdpr.models.results import point_keys
from cdpr.models.sensitivity import pose_sensitivities, sensitivities_at
from cdpr.robot import load_robot

ROOT = Path(__file__).resolve().parents[1]


def best(fn, repeat):
    """(wall [s], cpu [s], result) of the fastest of ``repeat`` runs."""
    times, out = [], None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        times.append((time.perf_counter() - t0, time.process_time() - c0))
    wall, cpu = min(times)
    return wall, cpu, out


def cpu_model():
    """The CPU's model name (``lscpu``), or "unknown"."""
    try:
        text = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return next(
        (ln.split(":", 1)[1].strip() for ln in text.splitlines() if ln.startswith("Model name")), "unknown"
    )


def sensitivity_rates(cog, p, rv, res, n, nn, repeat):
    """Prints the 6-DoF sensitivities per second, compiled and numpy, at the same equilibria ``res``
    (``sensitivities_at``) and end to end (``pose_sensitivities``)."""
    sub = {k: v[:nn] for k, v in res.items() if k != "alternatives"}
    sensitivities_at_fast(cog, {k: v[:10] for k, v in sub.items()})  # compile (or load the cache)
    ts, cs, a = best(lambda: sensitivities_at_fast(cog, res), repeat)
    tsn, _, b = best(lambda: sensitivities_at(cog, sub), max(1, repeat - 1))
    sm = b["smooth"]
    same = (a["smooth"][:nn] == sm).all()
    dev = np.abs(a["S"][:nn][sm] - b["S"][sm]).max(axis=1) / np.abs(b["S"][sm]).max(axis=1).clip(1e-300)
    print(
        f"CoGiRo 6-DoF sensitivities (84 parameters) at the equilibria: compiled {n / ts:,.0f} poses/s "
        f"({cs / n * 1e6:.1f} us cpu per pose, N = {n}), numpy {nn / tsn:,.0f} poses/s (N = {nn}): "
        f"ratio {(n / ts) / (nn / tsn):,.0f}; flags {'same' if same else 'DIFFERENT'}, max column-relative "
        f"|dS| {dev.max():.1e} (the numpy finite differences' round-off)"
    )
    n3 = max(1, nn // 10)
    te, ce, _ = best(lambda: spatial_sensitivities_fast(cog, p, rv), repeat)
    ten, _, _ = best(lambda: pose_sensitivities(cog, p[:n3], rv[:n3]), max(1, repeat - 1))
    print(
        f"  solve + sensitivities (pose_sensitivities): compiled {n / te:,.0f} poses/s "
        f"({ce / n * 1e6:.1f} us cpu per pose), numpy {n3 / ten:,.0f} poses/s (N = {n3}): "
        f"ratio {(n / te) / (n3 / ten):,.0f}"
    )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20000)
    ap.add_argument("--n-numpy", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    n, nn = args.n, min(args.n_numpy, args.n)
    g = np.random.default_rng(0)
    cog = load_robot(ROOT / "config/robots/cogiro_massless.yaml")
    p = np.column_stack([g.uniform(-3, 3, n), g.uniform(-2, 2, n), g.uniform(1.0, 3.0, n)])
    rv = g.normal(size=(n, 3))
    rv *= (np.radians(10) * g.uniform(0, 1, (n, 1))) / np.linalg.norm(rv, axis=1, keepdims=True)
    print(
        f"CPU {cpu_model()}, cores {os.cpu_count()}, numba threads {numba.get_num_threads()}, "
        f"load before {os.getloadavg()}"
    )
    solve_spatial_fast(cog, p[:10], rv[:10])  # compile (or load the cache)
    tc, cc, res = best(lambda: solve_spatial_fast(cog, p, rv), args.repeat)
    tn, _, ref = best(lambda: solve_spatial(cog, p[:nn], rv[:nn]), max(1, args.repeat - 1))
    same = (ref["status"] == res["status"][:nn]).all() and (ref["taut"] == res["taut"][:nn]).all()
    dev = np.abs(ref["P_s"] - res["P_s"][:nn]).max()
    print(
        f"CoGiRo 6-DoF with restarts: compiled {n / tc:,.0f} /s ({cc / n * 1e6:.1f} us cpu per solve, "
        f"N = {n}), numpy {nn / tn:,.0f} /s (N = {nn}): ratio {(n / tc) / (nn / tn):,.0f}"
    )
    print(
        f"  status ok: {(res['status'] == 'ok').mean():.1%}; not unique: {(~res['unique']).sum()}; "
        f"median iterations {np.median(res['iterations']):g}; compiled = numpy on the first {nn}: "
        f"{'same statuses and taut sets' if same else 'DIFFERENT'}, max |dP| {dev:.1e} m"
    )
    sensitivity_rates(cog, p, rv, res, n, nn, args.repeat)
    cab = Compiled6(cog)
    pp, R = pose_arrays(p, rv)
    L0 = L_TS(cog, pp, R=R)
    o = PHYSICAL_DEFAULTS
    tk, ck, _ = best(
        lambda: newton6_fast(cab, pp, R, L0, pp, o["tol"], o["maxiter"], o["max_step"]), args.repeat
    )
    print(f"  the compiled Newton kernel alone: {n / tk:,.0f} /s ({ck / n * 1e6:.1f} us cpu per solve)")
    r4 = load_robot(ROOT / "config/robots/cdpr4.yaml")
    P = np.column_stack([g.uniform(-2.3, 2.3, n), g.uniform(-2.3, 2.3, n), g.uniform(0.2, 3.7, n)])
    solve_physical_fast(r4, P[:10])  # compile
    t4, c4, _ = best(lambda: solve_physical_fast(r4, P), args.repeat)
    t4n, _, _ = best(lambda: point_keys(solve_spatial(r4, P[:nn])), max(1, args.repeat - 1))
    solve_spatial_fast(r4, P[:10])  # the pose kernel on the point mass (compiled above for CoGiRo)
    t4p, c4p, viap = best(lambda: solve_spatial_fast(r4, P), args.repeat)
    fast = solve_physical_fast(r4, P)
    same4 = (fast["status"] == viap["status"]).all()
    both = (fast["status"] == "ok") & (fast["n_taut"] >= 2)
    dev4 = np.abs(fast["P_s"] - viap["P_s"])[both].max(initial=0.0)
    print(
        f"CDPR4 SR point mass: compiled 3-DoF kernel {n / t4:,.0f} /s ({c4 / n * 1e6:.1f} us cpu per solve), "
        f"numpy {nn / t4n:,.0f} /s"
    )
    print(
        f"  CDPR4 through the pose kernel (cdpr.compiled.equilibrium.solve): {n / t4p:,.0f} /s "
        f"({c4p / n * 1e6:.1f} us cpu per solve): the 3-DoF kernel is {t4p / t4:.2f}x faster "
        f"(kept as the fast path where > 1.3x); statuses {'same' if same4 else 'DIFFERENT'}, "
        f"max |dP| {dev4:.1e} m on the ok points held by 2 or more cables"
    )
    print(f"load after {os.getloadavg()}")


if __name__ == "__main__":
    main()
