"""Calibration of a rigid 6-DoF platform, measured (issue 18): a seeded CoGiRo whose anchors (5 mm),
attachments (3 mm), dead lengths (50 mm) and moduli (20 %) deviate from the drawing by the default
priors, tracker samples (σ = 0.2 mm, 1 mrad) at poses tilted up to 0.1 rad, calibrated with the
exact model; the nominal, calibrated and true robots then predict held-out noisy samples.

    .venv/bin/python benchmarks/calibration_cogiro.py [--seed 2026] [--n 40] [--n-val 200]
        [--command standard|compensated] [--design random|d-optimal] [--validate nominal|calibrated]
        [--two-stage]

``--command compensated`` commands the rest lengths that hold the nominal robot at the pose under
the minimum-norm tension distribution (pretension, every cable taut) instead of L_TS;
``--design d-optimal`` takes the training poses from ``calibrate plan`` (identity orientation);
``--validate calibrated`` commands the held-out poses with the calibrated robot's compensated
lengths; ``--two-stage`` refits on a second campaign commanded that way.

Prints the held-out RMS (position [mm], orientation [mrad]) of each robot, the fit's rank,
condition and identification counts, the fit's wall and CPU time, and the held-out samples flagged
(the truth holds fewer than 6 taut cables, or a second equilibrium exists under the same lengths)
with the errors with and without them: flagged, never dropped.
"""

import argparse
import time

import numpy as np

from cdpr.analyses import calibration as cal
from cdpr.errors import CdprError
from cdpr.parameters import select_groups
from cdpr.robot import load_robot

GROUPS = ["anchors", "attachments", "dead_lengths", "moduli"]


BOX = [-3.0, 3.0, -2.0, 2.0, 1.0, 2.5]


def poses(robot, rng, n, tilt=0.1, margin=100.0, command="standard"):
    """n poses in CoGiRo's workspace (``calibration.random_poses``); exits when too few admissible."""
    try:
        return cal.random_poses(robot, rng, n, BOX, tilt, margin, command)
    except CdprError as exc:
        raise SystemExit(str(exc)) from None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--n-val", type=int, default=200)
    ap.add_argument("--command", choices=cal.COMMANDS, default="standard")
    ap.add_argument("--design", choices=("random", "d-optimal"), default="random")
    ap.add_argument("--plan-grid", type=int, default=5)
    ap.add_argument(
        "--two-stage",
        action="store_true",
        help="a second training set (--n poses) commanded with the compensated lengths of the first "
        "calibrated robot (every cable of the truth taut), fitted alone; the held-out commands are then "
        "the second calibrated robot's compensated lengths",
    )
    ap.add_argument(
        "--validate",
        choices=("nominal", "calibrated"),
        default="nominal",
        help="which robot computes the held-out commands: the nominal one (the --command lengths) or the "
        "calibrated one (its compensated lengths: pretension that keeps the truth's cables taut)",
    )
    a = ap.parse_args()
    robot = load_robot("config/robots/cogiro_massless.yaml")
    rng = np.random.default_rng(a.seed)
    idx = select_groups(robot, GROUPS)
    sd = cal.prior_sd(robot, idx, cal.parse_priors(None))
    truth, _ = cal.perturbed(robot, idx, sd, rng)
    kw = dict(sigma=2e-4, rng=rng, sigma_rad=1e-3, command=a.command)
    # draw order: training poses, their data, validation poses, their data (as the study does)
    P_train = poses(robot, rng, a.n, command=a.command)
    if a.design == "d-optimal":
        pl = cal.plan(robot, GROUPS, a.n, box=BOX, n_axis=a.plan_grid, command=a.command)
        P_train = pl["poses"]
    train = cal.simulate(truth, robot, P_train, **kw)
    P_val = poses(robot, rng, a.n_val, command=a.command)
    if not a.two_stage and a.validate == "nominal":
        val = cal.simulate(truth, robot, P_val, **kw)
    t0, c0 = time.perf_counter(), time.process_time()
    fit = cal.fit(robot, train, GROUPS)
    if a.two_stage:
        first = fit.calibrated_robot()
        kw["command"] = "compensated"
        train = cal.simulate(truth, first, poses(robot, rng, a.n, command="compensated"), **kw)
        taut1 = cal.equilibria(truth, train.pose, train.L, rotvec=train.rotvec)["taut"].sum(axis=1)
        print(
            f"stage 2: {len(train.sample)} samples, truth taut cables: {np.bincount(taut1, minlength=9)[5:]} (5..8)"
        )
        fit = cal.fit(robot, train, GROUPS)
        # held-out commands: the second calibrated robot's compensated lengths
        val = cal.simulate(truth, fit.calibrated_robot(), P_val, **kw)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    if not a.two_stage and a.validate == "calibrated":
        val = cal.simulate(truth, fit.calibrated_robot(), P_val, **dict(kw, command="compensated"))
    marks = fit.ident.get("labels")
    print(
        f"CoGiRo, seed {a.seed}: {len(idx)} parameters ({', '.join(GROUPS)}), {len(train.sample)} training "
        f"samples ({a.design}), command {a.command}"
    )
    print(
        f"fit: rank {fit.ident['rank']} of {len(idx)}, condition {fit.ident['condition']:.3g}, {fit.nfev} evaluations"
    )
    if marks is not None:
        kinds, counts = np.unique(np.asarray(marks), return_counts=True)
        print("identification: " + ", ".join(f"{k} {n}" for k, n in zip(kinds, counts)))
    print(f"fit time: {wall:.1f} s wall, {cpu:.1f} s CPU")
    tr = cal.check(fit.calibrated_robot(), train)
    print(
        f"training residual: {tr['rms_m'] * 1e3:.3f} mm, {tr['rms_rad'] * 1e3:.3f} mrad RMS (max {tr['max_m'] * 1e3:.3f} mm)"
    )
    # A cable of the true robot may be slack under the nominal L_TS (a dead length 50 mm long): on
    # fewer than six taut cables the platform has a soft mode (it swings until gravity balances), where
    # a small parameter error moves the pose far. The held-out samples are flagged (taut count, second
    # equilibrium) and the errors given with and without the flagged ones.
    ntaut, other = cal.equilibrium_flags(truth, val)
    flag = (ntaut < 6) | other
    counts = ", ".join(f"{k} taut: {int((ntaut == k).sum())}" for k in sorted(set(ntaut.tolist())))
    print(
        f"\nheld-out samples: {len(val.sample)} ({counts}, on the true robot; second equilibrium: "
        f"{int(other.sum())}; flagged: {int(flag.sum())})"
    )
    print(
        "| robot | position RMS [mm] | position max [mm] | orientation RMS [mrad] | unflagged: RMS [mm] | max [mm] |"
    )
    print("|---|---|---|---|---|---|")
    for name, r in (
        ("nominal", robot),
        ("calibrated", fit.calibrated_robot()),
        ("truth (noise floor)", truth),
    ):
        ch = cal.check(r, val)
        e = np.array([np.nan if s["error_m"] is None else s["error_m"] for s in ch["samples"]])
        ok = ~flag
        print(
            f"| {name} | {ch['rms_m'] * 1e3:.3f} | {ch['max_m'] * 1e3:.3f} | {ch['rms_rad'] * 1e3:.3f} | "
            f"{np.sqrt(np.nanmean(e[ok] ** 2)) * 1e3:.3f} | {np.nanmax(e[ok]) * 1e3:.3f} |"
        )
        if name == "calibrated":
            worst = np.argsort(-np.nan_to_num(e))[:3]
            print(
                "|   worst: "
                + "; ".join(f"{val.sample[i]} {e[i] * 1e3:.2f} mm, {ntaut[i]} taut" for i in worst)
                + " | | | | | |"
            )


if __name__ == "__main__":
    main()
