"""Speed of the uncertainty study on this machine, measured in one run (issue 11).

1. Cost of the compiled sensitivities: solve alone vs solve + dP*/dθ of every parameter in the same
   pass (``sensitivity.sensitivities``), paper and physical mode, SR* and DR*, over the 63^3 grid of
   the paper's RW_C (best of ``--repeat``).
2. The speed target: 1,000 per-cable-E samples of the global index (63^3 points each) for SR* and
   DR*, uncompensated (the paper's question):
   * full solves: ``--full`` samples timed, the 1,000 extrapolated (or all of them with --full 1000);
   * linearised: the per-subset sensitivities once (``PoseErrorModel.linearise``) and the 1,000
     samples, timed end to end; validated against the full-solve samples (same seeds).

    .venv/bin/python benchmarks/uncertainty_speed.py [--n 63] [--samples 1000] [--full 8] [--repeat 3]
"""

import argparse
import platform
import subprocess
import time

import numpy as np

from cdpr.analyses import uncertainty as uq
from cdpr.analyses.workspace import grid_points
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.compiled.subsets import solve_points_fast
from cdpr.robot import load_robot, with_pulleys
from cdpr.solve import sensitivities

RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]
DESIGNS = {"SR*": ("SR", 0.1077, 0.035), "DR*": ("DR", 0.100, 0.080)}
E_RANGE = {"dist": "uniform", "low": 67.2e9, "high": 137.2e9, "per_cable": True}
SEED = 20210304


def cpu_model():
    out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    name = next((ln.split(":", 1)[1].strip() for ln in out.splitlines() if ln.startswith("Model name")), "?")
    cpus = next((ln.split(":", 1)[1].strip() for ln in out.splitlines() if ln.startswith("CPU(s)")), "?")
    return f"{name}, {cpus} CPUs"


def best_of(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times), float(np.median(times))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=63, help="points per axis of the RW_C grid")
    ap.add_argument("--samples", type=int, default=1000, help="per-cable-E samples of the target")
    ap.add_argument("--full", type=int, default=8, help="samples solved in full (timed and compared)")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(
        f"# uncertainty speed: {cpu_model()}; Python {platform.python_version()}; {args.n}^3 = {args.n**3:,} points"
    )
    load = open("/proc/loadavg").read().split()[:3]
    print(f"load average at start: {' '.join(load)}\n")
    P = grid_points(RW_C, args.n)
    r0 = load_robot("config/robots/cdpr4.yaml")
    robots = {k: with_pulleys(r0, kind=kd, h=h, r_p=rp) for k, (kd, h, rp) in DESIGNS.items()}
    for r in robots.values():  # load the compiled kernels
        solve_points_fast(r, P[:10])
        solve_physical_fast(r, P[:10])
        sensitivities(r, P[:10])
        sensitivities(r, P[:10], redundancy="physical")
        uq.PoseErrorModel(r, P[:10]).linearise([0, 1, 2, 3])
    print("## 1. Compiled sensitivities: solve vs solve + dP*/dθ (29 parameters), same pass\n")
    print("| design | mode | solve [s] | solve + sensitivities [s] | ratio (best) | ratio (median) |")
    print("|---|---|---|---|---|---|")
    for name, r in robots.items():
        for mode, solve in (
            ("paper", lambda r=r: solve_points_fast(r, P)),
            ("physical", lambda r=r: solve_physical_fast(r, P)),
        ):
            tb, tm = best_of(solve, args.repeat)
            sb, sm = best_of(lambda r=r, mode=mode: sensitivities(r, P, redundancy=mode), args.repeat)
            print(f"| {name} | {mode} | {tb:.3f} | {sb:.3f} | {sb / tb:.2f} | {sm / tm:.2f} |")
    print(f"\n## 2. {args.samples} per-cable-E samples of the global index, uncompensated (paper mode)\n")
    print(
        "| design | full: s/sample | full: extrapolated to all samples [s] | linearise once [s] | "
        "linearised samples [s] | linearised total [s] | max abs index diff lin - full [mm] | max rel | index 5-50-95 % [mm] |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    total_lin = total_full = 0.0
    for name, r in robots.items():
        dr = uq.drivers({"young_modulus_Pa": E_RANGE}, r)
        U = uq.mc_uniforms(SEED, 0, args.samples, len(dr))
        th = uq.parameter_samples(r, dr, U)
        m = uq.PoseErrorModel(r, P)
        t0 = time.perf_counter()
        values, ok = m.solve(th[: args.full])
        dp = values["dp"]
        t_full = (time.perf_counter() - t0) / max(args.full, 1)
        full = uq.sample_stats(dp, ok)
        t0 = time.perf_counter()
        lin = m.linearise(uq.driver_columns(dr))
        t_once = time.perf_counter() - t0
        t0 = time.perf_counter()
        stats = uq.linear_stats(lin, th)
        t_samples = time.perf_counter() - t0
        d = np.abs(stats.index_m[: args.full].to_numpy() - full.index_m.to_numpy())
        q = np.quantile(stats.index_m, uq.QUANTILES) * 1e3
        total_lin += t_once + t_samples
        total_full += t_full * args.samples
        print(
            f"| {name} | {t_full:.3f} | {t_full * args.samples:.0f} | {t_once:.2f} | {t_samples:.1f} | "
            f"{t_once + t_samples:.1f} | {d.max() * 1e3:.4f} | {(d / full.index_m).max():.1e} | "
            f"{q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} |"
        )
    print(
        f"\nSR* + DR*: linearised {total_lin:.0f} s, full solves {total_full:.0f} s (extrapolated from {args.full} "
        f"samples each); target <= 600 s."
    )
    print(f"load average at end: {' '.join(open('/proc/loadavg').read().split()[:3])}")


if __name__ == "__main__":
    main()
