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
  * the heavy inverse on CoGiRo (SR and DR): the catenaries that carry given tensions at B_i and
    their rest lengths (the inner step of the sag-consistent compensation), compiled
    (cdpr.compiled.cables.inverse) over the grid and the numpy reference
    (cdpr.models.cables.HeavyCables.inverse) on a slice: inverses/s and their ratio;
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
from cdpr.compiled import cables as ccables
from cdpr.compiled import catenary as ccat
from cdpr.compiled import equilibrium as cequilibrium
from cdpr.models import equilibrium
from cdpr.models.cables import HeavyCables
from cdpr.models.platform import pose_arrays
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


def cogiro_rows(label, massless, Q, slq, repeat):
    """The massless pose kernel, the heavy kernel (0.0631 kg/m) over the grid Q and the heavy numpy
    reference on the slice slq of one CoGiRo design, and the compiled-vs-numpy check on the slice;
    returns the equilibria/s of the two kernels."""
    heavy = with_values(massless, linear_density=RHO)
    key = label.lower()
    figures = {}
    t, res = best_of(lambda: cequilibrium.solve(massless, Q), repeat)
    figures[f"{key} massless pose"] = row(f"{label} massless, pose kernel", len(Q), t, res)
    t, res = best_of(lambda: cequilibrium.solve(heavy, Q), repeat)
    figures[f"{key} heavy"] = row(f"{label} heavy 0.0631 kg/m, compiled", len(Q), t, res)
    t, ref = best_of(lambda: equilibrium.solve(heavy, slq), 1)
    row(f"{label} heavy 0.0631 kg/m, numpy reference", len(slq), t, ref)
    sub = cequilibrium.solve(heavy, slq)
    print(
        f"  compiled vs numpy on the slice: same statuses {bool((sub['status'] == ref['status']).all())}, "
        f"max |dP*| {np.abs(sub['P_s'] - ref['P_s']).max():.1e} m, "
        f"max |dphi*| {np.abs(sub['rotvec_s'] - ref['rotvec_s']).max():.1e} rad, largest sag "
        f"{1e3 * sub['sag_max'].max():.1f} mm"
    )
    return figures


def inverse_rows(label, heavy, Q, slq, repeat):
    """The heavy inverse (``HeavyCables.inverse``: the catenaries that carry given tensions at B_i
    and their rest lengths, the inner step of the sag-consistent compensation) at the identity
    orientation over the grid Q, compiled (``compiled.cables.inverse``), and the numpy reference on
    the slice slq: inverses/s (poses; each is m cables), the ratio of the two per pose and their
    largest difference on the slice. Tensions at B: 200-3000 N, seeded."""
    rng = np.random.default_rng(7)
    t = rng.uniform(200.0, 3000.0, (len(Q), heavy.m))
    ts = t[:: max(1, len(Q) // len(slq))][: len(slq)]
    p, R = pose_arrays(Q)
    ps, Rs = pose_arrays(slq)
    cab, ref = cequilibrium.CompiledHeavyCables(heavy), HeavyCables(heavy)
    tc, _ = best_of(lambda: ccables.inverse(cab, p, R, t), repeat)
    cpu_c = CPU_TIME["last"]
    tn, a = best_of(lambda: ref.inverse(ps, Rs, ts), 1)
    cpu_n = CPU_TIME["last"]
    b = ccables.inverse(cab, ps, Rs, ts)
    diff = max(float(np.nanmax(np.abs(a[k] - b[k]))) for k in ("D", "L0", "L0_free", "l_dead"))
    print(
        f"{label} heavy inverse, compiled: {len(Q) / tc:,.0f} inverses/s ({len(Q) * heavy.m / tc:,.0f} "
        f"cables/s, {len(Q) / cpu_c:,.0f} per CPU-s); numpy reference: {len(slq) / tn:,.0f} inverses/s "
        f"({len(slq) / cpu_n:,.0f} per CPU-s); ratio {len(Q) / tc / (len(slq) / tn):.0f} (wall), "
        f"{len(Q) / cpu_c / (len(slq) / cpu_n):.0f} (CPU); same converged "
        f"{bool((a['converged'] == b['converged']).all())}, max |dD|, |dL0| {diff:.1e} m"
    )


def cpu_name():
    """The CPU's model name (/proc/cpuinfo), else ``platform.processor()`` or the machine."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20, help="points per axis of the grids (n^3 poses)")
    ap.add_argument("--repeat", type=int, default=3, help="best of this many runs")
    ap.add_argument("--numpy", type=int, default=500, help="poses of the numpy reference's slice")
    args = ap.parse_args()
    print(
        f"machine: {cpu_name()}, {os.cpu_count()} cores, "
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

    cogiro = load_robot(ROOT / "config" / "robots" / "cogiro_massless.yaml")
    Q = grid_points(COGIRO_BOX, args.n)
    slq = Q[:: max(1, len(Q) // args.numpy)][: args.numpy]
    # CoGiRo's SR pulleys, and its DR design (the study's DRopt: h 75 mm, r_p 50 mm): the general
    # pulley coupling (compiled.cables._general_at, the reference's fixed point on P*)
    dr = with_pulleys(cogiro, kind="DR", h=0.075, r_p=0.05)
    for label, massless in (("CoGiRo", cogiro), ("CoGiRo DR", dr)):
        figures.update(cogiro_rows(label, massless, Q, slq, args.repeat))
    for label, massless in (("CoGiRo", cogiro), ("CoGiRo DR", dr)):
        inverse_rows(label, with_values(massless, linear_density=RHO), Q, slq, args.repeat)

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
