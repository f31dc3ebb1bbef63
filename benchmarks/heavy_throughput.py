"""Heavy cables (issue 38): equilibria per second of the compiled heavy-cable kernel beside the
massless kernels, measured in one run on this machine, and the cost of one catenary solve.

  * CDPR4, point mass, over the n^3 cell-centred grid of the paper's RW_C box, rest lengths L_TS
    at the desired point (physical mode): the massless 3-DoF fast path (cdpr.solve's default for a
    suspended point mass), the massless pose kernel (cdpr.compiled.equilibrium.solve), the heavy
    kernel (0.0631 kg/m, the 4 mm steel cable; cdpr.compiled.equilibrium.solve with
    cdpr.compiled.cables) and the heavy numpy reference on a slice;
  * CoGiRo, rigid 6-DoF platform, over an n^3 grid of its central box at the identity orientation:
    the massless pose kernel, the heavy kernel (0.0631 kg/m) and the heavy numpy reference, with its
    SR pulleys and with the study's DR design (h 75 mm, r_p 50 mm: the general pulley coupling);
  * one catenary (cdpr.compiled.catenary.span_states over random taut spans of CoGiRo's size, and
    cable_state, the whole cable with its dead part): the time per solve beside the hand count of
    the floating-point operations of one Newton iteration (README, "Heavy cables").

Each figure is the best of --repeat runs after one warm-up (numba compiled and loaded), both
cores, in wall time and in CPU time (equilibria per CPU-second: less sensitive to the other
processes on a shared machine); the load average is printed before and after. The catenary's
cost is set against the hand count of the flops of one Newton iteration and the machine's peak.

    .venv/bin/python benchmarks/heavy_throughput.py [--n 20] [--repeat 3]
"""

import argparse
import os
import platform
import time
from pathlib import Path

import numba
import numpy as np

from cdpr import solve as door
from cdpr.analyses.workspace import grid_points
from cdpr.compiled import catenary as ccat
from cdpr.compiled import equilibrium as cequilibrium
from cdpr.models import equilibrium
from cdpr.robot import load_robot, with_pulleys, with_values

ROOT = Path(__file__).resolve().parents[1]
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]
COGIRO_BOX = [-4.0, 4.0, -3.0, 3.0, 1.0, 3.5]
RHO = 0.0631  # [kg/m]


#: Hand count of one Newton iteration of ``catenary.span_state`` (end_forces), in flop-equivalents:
#: ``_terms`` about 31 additions, multiplications and divisions, 2 hypot and 1 asinh; spans and
#: flexibility 15; the 2 x 2 step, its Armijo slope and the stop tests about 30 with 3 hypot; a hypot
#: counted as 5, an asinh (a logarithm and a square root) as 25 (README, "Heavy cables").
FLOPS_PER_ITERATION = 31 + 15 + 30 + 5 * 5 + 25
#: Peak double-precision rate of one core of this machine's CPU class: 2 AVX-512 FMA units, 8 doubles
#: each, 2 flops per FMA, at the clock /proc/cpuinfo reports (flops per cycle).
PEAK_FLOPS_PER_CYCLE = 32
CPU_TIME = {}


def best_of(fn, repeat):
    fn()  # warm-up: numba compiled (or loaded from its cache) and its threads started
    times = []
    cpu = []
    out = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    CPU_TIME["last"] = min(cpu)
    return min(times), out


def row(name, n, seconds, res):
    ok = float(np.mean(res["status"] == "ok")) if res is not None else float("nan")
    it = float(np.mean(res["iterations"])) if res is not None and "iterations" in res else float("nan")
    cpu = CPU_TIME.get("last", float("nan"))
    print(
        f"{name:<44} {n:>7} {n / seconds:>12,.0f} {1e6 * seconds / n:>9.1f} {n / cpu:>12,.0f} {it:>6.2f} {ok:>6.3f}"
    )
    return n / seconds


def _mhz():
    """The clock [MHz] /proc/cpuinfo reports (NaN where there is none)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("cpu MHz"):
                return float(line.split(":")[1])
    except OSError:
        pass
    return float("nan")


def spans(n, seed=3):
    """Random taut heavy spans of CoGiRo's size (l_h 1-12 m, l_v 0.5-5 m, 4 mm steel cable)."""
    rng = np.random.default_rng(seed)
    l_h = rng.uniform(1.0, 12.0, n)
    l_v = rng.uniform(0.5, 5.0, n)
    L0 = np.hypot(l_h, l_v) * rng.uniform(0.9995, 1.0005, n)
    w = np.full(n, RHO * 9.81)
    EA = np.full(n, 102.2e9 * np.pi * 0.004**2 / 4)
    return l_h, l_v, L0, w, EA


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20, help="points per axis of the grids (n^3 poses)")
    ap.add_argument("--repeat", type=int, default=3, help="best of this many runs")
    ap.add_argument("--numpy", type=int, default=500, help="poses of the numpy reference's slice")
    args = ap.parse_args()
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"numba threads {numba.get_num_threads()}, Python {platform.python_version()}"
    )
    print("load average before: {:.2f} {:.2f} {:.2f}".format(*os.getloadavg()))
    print(
        f"{'solver':<44} {'poses':>7} {'equilibria/s':>12} {'us/pose':>9} {'per CPU-s':>12} {'iters':>6} {'ok':>6}"
    )

    cdpr4 = load_robot(ROOT / "config" / "robots" / "cdpr4.yaml")
    heavy4 = with_values(cdpr4, linear_density=RHO)
    P = grid_points(RW_C, args.n)
    sl = P[:: max(1, len(P) // args.numpy)][: args.numpy]
    figures = {}
    t, res = best_of(lambda: door.solve(cdpr4, P, redundancy="physical"), args.repeat)
    figures["cdpr4 massless 3-DoF"] = row("CDPR4 massless, 3-DoF fast path", len(P), t, res)
    t, res = best_of(lambda: cequilibrium.solve(cdpr4, P), args.repeat)
    figures["cdpr4 massless pose"] = row("CDPR4 massless, pose kernel", len(P), t, res)
    t, res = best_of(lambda: cequilibrium.solve(heavy4, P), args.repeat)
    figures["cdpr4 heavy"] = row("CDPR4 heavy 0.0631 kg/m, compiled", len(P), t, res)
    t, ref = best_of(lambda: equilibrium.solve(heavy4, sl), 1)
    row("CDPR4 heavy 0.0631 kg/m, numpy reference", len(sl), t, ref)
    sub = cequilibrium.solve(heavy4, sl)
    print(
        f"  compiled vs numpy on the slice: same statuses {bool((sub['status'] == ref['status']).all())}, "
        f"max |dP*| {np.abs(sub['P_s'] - ref['P_s']).max():.1e} m, largest sag "
        f"{1e3 * sub['sag_max'].max():.1f} mm"
    )

    cogiro = load_robot(ROOT / "config" / "robots" / "cogiro.yaml")
    heavyc = with_values(cogiro, linear_density=RHO)
    Q = grid_points(COGIRO_BOX, args.n)
    slq = Q[:: max(1, len(Q) // args.numpy)][: args.numpy]
    t, res = best_of(lambda: cequilibrium.solve(cogiro, Q), args.repeat)
    figures["cogiro massless pose"] = row("CoGiRo massless, pose kernel", len(Q), t, res)
    t, res = best_of(lambda: cequilibrium.solve(heavyc, Q), args.repeat)
    figures["cogiro heavy"] = row("CoGiRo heavy 0.0631 kg/m, compiled", len(Q), t, res)
    t, ref = best_of(lambda: equilibrium.solve(heavyc, slq), 1)
    row("CoGiRo heavy 0.0631 kg/m, numpy reference", len(slq), t, ref)
    sub = cequilibrium.solve(heavyc, slq)
    print(
        f"  compiled vs numpy on the slice: same statuses {bool((sub['status'] == ref['status']).all())}, "
        f"max |dP*| {np.abs(sub['P_s'] - ref['P_s']).max():.1e} m, "
        f"max |dphi*| {np.abs(sub['rotvec_s'] - ref['rotvec_s']).max():.1e} rad, largest sag "
        f"{1e3 * sub['sag_max'].max():.1f} mm"
    )

    # CoGiRo's DR design (the study's DRopt: h 75 mm, r_p 50 mm): the general pulley coupling
    # (compiled.cables._general_at, the reference's fixed point on P*) beside the numpy reference
    dr = with_pulleys(cogiro, kind="DR", h=0.075, r_p=0.05)
    heavyd = with_values(dr, linear_density=RHO)
    t, res = best_of(lambda: cequilibrium.solve(dr, Q), args.repeat)
    figures["cogiro dr massless pose"] = row("CoGiRo DR massless, pose kernel", len(Q), t, res)
    t, res = best_of(lambda: cequilibrium.solve(heavyd, Q), args.repeat)
    figures["cogiro dr heavy"] = row("CoGiRo DR heavy 0.0631 kg/m, compiled", len(Q), t, res)
    t, ref = best_of(lambda: equilibrium.solve(heavyd, slq), 1)
    row("CoGiRo DR heavy 0.0631 kg/m, numpy reference", len(slq), t, ref)
    sub = cequilibrium.solve(heavyd, slq)
    print(
        f"  compiled vs numpy on the slice: same statuses {bool((sub['status'] == ref['status']).all())}, "
        f"max |dP*| {np.abs(sub['P_s'] - ref['P_s']).max():.1e} m, "
        f"max |dphi*| {np.abs(sub['rotvec_s'] - ref['rotvec_s']).max():.1e} rad, largest sag "
        f"{1e3 * sub['sag_max'].max():.1f} mm"
    )

    n = 200_000
    l_h, l_v, L0, w, EA = spans(n)
    t, out = best_of(lambda: ccat.span_states(l_h, l_v, L0, w, EA), args.repeat)
    iters = float(out[3].mean())
    threads = numba.get_num_threads()
    print(
        f"catenary span_state (cold start), {n} taut CoGiRo-size spans: {n / t:,.0f} solves/s, "
        f"{1e9 * t * threads / n:.0f} ns per solve per core, {iters:.2f} Newton iterations, "
        f"{1e9 * t * threads / n / iters:.0f} ns per iteration per core"
    )
    ns_cpu = 1e9 * CPU_TIME["last"] / n / iters
    mhz = _mhz()
    peak = PEAK_FLOPS_PER_CYCLE * mhz / 1e3  # [GFLOP/s per core]
    print(
        f"  by CPU time {ns_cpu:.0f} ns per iteration; {FLOPS_PER_ITERATION} flop-equivalents per iteration "
        f"(hand count): {FLOPS_PER_ITERATION / ns_cpu:.2f} GFLOP/s per core against a peak of {peak:.0f} "
        f"({PEAK_FLOPS_PER_CYCLE} flops/cycle at {mhz:.0f} MHz): {FLOPS_PER_ITERATION / ns_cpu / peak:.1%}"
    )
    print(
        "load average after: {:.2f} {:.2f} {:.2f}; targets: CDPR4 heavy >= 100,000/s ({:.1%} of it), "
        "CoGiRo heavy >= 25,000/s ({:.1%})".format(
            *os.getloadavg(), figures["cdpr4 heavy"] / 1e5, figures["cogiro heavy"] / 2.5e4
        )
    )


if __name__ == "__main__":
    main()
