"""``cdpr calibrate fit | check | cv | plan``: a real robot's parameters from measurements (issue 18).

``fit`` estimates the parameter groups ``--estimate`` from a data table (docs/calibration.md) and
writes the calibrated robot file; ``check`` compares a robot's prediction with measured samples;
``plan`` picks D-optimal poses to measure; ``cv`` cross-validates a calibration from motor-angle data
(a spool robot such as the Hangprinter; ``fit`` and ``check`` take those data too). JSON with ``--json`` (SI units), a readable table
without; every bad input is one line on stderr and exit code 2 (``cdpr.cli.main.main``).

``--wrench`` (fit, check, plan) is the external wrench on the platform while the data were taken (a
tool's weight): it acts on the nominal and on the fitted robot, is echoed under ``wrench`` in the
JSON and named in the text and in the written robot file's header, and is not written into that
file (a calibrated robot is the robot without its temporary load). Motor-angle data refuse it: their
model takes the measured line forces, not the platform's balance.

Its options are defined in ``cdpr.cli.parser`` (``calibrate_parser``), which loads this module only
to run a command.
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np

from cdpr import io
from cdpr.analyses import calibration as cal
from cdpr.cli.commands import checked, emit_json
from cdpr.errors import CdprError
from cdpr.pipeline.calibration_files import write_robot
from cdpr.robot import load_robot, with_wrench


def _table(rows, headers):
    cols = [[h] + [r[i] for r in rows] for i, h in enumerate(headers)]
    widths = [max(len(x) for x in c) for c in cols]
    lines = ["  ".join(x.rjust(w) for x, w in zip(r, widths)) for r in [headers] + rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def nominal_robot(args, motor=False):
    """The nominal robot of ``--robot``, checked for plausibility (``checked``), with ``--wrench`` on
    its platform (``robot.with_wrench``: a moment on a point mass refused in one line); on
    motor-angle data (``motor``) a wrench is refused in one line: that model takes the measured line
    forces, not the platform's balance, so a wrench would change nothing."""
    robot = checked(load_robot(args.robot), args)
    wrench = getattr(args, "wrench", None)
    if motor and wrench is not None:
        raise CdprError(
            f"--wrench: {args.data} holds motor angles (motor_deg_1..); their model takes the measured line "
            "forces, not the platform's balance, so it takes no wrench; leave --wrench out"
        )
    return with_wrench(robot, wrench)


def _wrench_line(args, when="while the data were taken"):
    """The text line naming ``--wrench`` and ``when`` it acts (None when not given)."""
    if getattr(args, "wrench", None) is None:
        return None
    w = ", ".join(f"{x:g}" for x in args.wrench)
    return f"external wrench ({w}) [N, N m] on the platform {when}"


def cmd_fit(args):
    """``cdpr calibrate fit``: estimate, report, write the calibrated robot."""
    io.check_output(args.out, (".yaml", ".yml"))
    motor = cal.is_motor_table(args.data)
    robot = nominal_robot(args, motor)
    if motor:
        _fit_motor(args, robot)
        return
    priors = cal.parse_priors(args.prior, estimate=args.estimate)
    data = cal.read_data(args.data, robot)
    result = cal.fit(robot, data, args.estimate, priors=priors, model=args.model, loss=args.loss)
    write_robot(args.out, result, args.data)
    if args.model == "standard":
        print(
            "cdpr: warning: the standard model ignores pulley kinematics and cable stretch; its estimates are biased",
            file=sys.stderr,
        )
    summary = result.summary()
    if args.report:
        write_report(result, Path(args.report))
    if args.json:
        emit_json(summary, args)
        return
    _print_fit(result, summary)
    if _wrench_line(args):
        print(f"{_wrench_line(args)}: on the nominal and the fitted robot; not written into {args.out}")


def _fit_motor(args, robot):
    """``cdpr calibrate fit`` on motor-angle data: the self-calibration with every position a nuisance."""
    priors = cal.parse_motor_priors(args.prior, args.estimate)
    if args.loss != "linear":
        raise CdprError(f"--loss {args.loss}: the motor-angle calibration takes the linear loss only")
    if args.report:
        raise CdprError("--report: not written for motor-angle data (the JSON has every number)")
    data = cal.read_motor_data(args.data, robot)
    result = cal.fit_motor(robot, data, args.estimate, priors=priors, model=args.model)
    write_robot(args.out, result, args.data)
    s = result.summary()
    for w in result.warnings:
        print(f"cdpr: warning: {w}", file=sys.stderr)
    if args.json:
        emit_json({**s, "data_warnings": result.warnings}, args)
        return
    cond = _print_parameters(s)
    pos = "no position measured" if s["residual_rms_m"] is None else f"{s['residual_rms_m'] * 1e3:.4g} mm"
    print(
        f"{s['n_parameters']} parameters, rank {s['rank']}, condition {cond}; {s['samples_used']} samples "
        f"({s['samples_with_position']} with a measured position); line RMS {s['line_rms_m'] * 1e3:.4g} mm, "
        f"position residual RMS {pos} ({result.model} model)"
    )
    print(f"gauge: {s['gauge']}")
    for w in s["unidentified"]:
        print(f"weak: {w}")
    if "linear_densities" in s:
        print(s["linear_densities"])


def _print_parameters(s):
    """Print the parameter table of a fit's summary ``s``; return its condition number as text."""
    rows = [
        [
            p["name"],
            f"{p['nominal']:.6g}",
            f"{p['estimate']:.6g}",
            f"{p['sd']:.3g}",
            f"{p['prior_sd']:.3g}",
            p["identified"],
        ]
        for p in s["parameters"]
    ]
    print(_table(rows, ["parameter", "nominal", "estimate", "sd", "prior sd", "identified"]))
    cond = "inf" if s["condition"] is None else f"{s['condition']:.3g}"
    return cond


def _print_fit(result, s):
    cond = _print_parameters(s)
    rms = "no pose measured" if s["residual_rms_m"] is None else f"{s['residual_rms_m'] * 1e3:.4g} mm"
    print(
        f"{s['n_parameters']} parameters, rank {s['rank']}, condition {cond}; samples used {s['samples_used']}, "
        f"left out {s['samples_left_out']}; residual RMS {rms} ({result.model} model)"
        + (
            f", orientation {s['residual_rms_rad'] * 1e3:.4g} mrad"
            if s["residual_rms_rad"] is not None
            else ""
        )
    )
    for w in s["unidentified"]:
        print(f"weak: {w}")
    if "linear_densities" in s:
        print(s["linear_densities"])
    t = result.table
    if t["outlier"].any():
        print("outliers down-weighted by the robust loss: " + ", ".join(t.loc[t["outlier"], "sample"]))
    left = t[t["status"] != "used"]
    for r in left.itertuples():
        print(f"left out: sample {r.sample} ({r.status})")
    if result.model == "standard":
        print(
            "warning: the standard model ignores pulley kinematics and elasticity; its estimates are biased"
        )


def write_report(result, folder):
    """Per-sample table, per-parameter table, correlation matrix and three figures in ``folder``
    (each file written atomically, ``cdpr.io.atomic``)."""
    folder.mkdir(parents=True, exist_ok=True)
    samples, pt = result.table, result.parameter_table()
    io.atomic(folder / "samples.csv", lambda tmp: samples.to_csv(tmp, index=False, float_format="%.9g"))
    io.atomic(folder / "parameters.csv", lambda tmp: pt.to_csv(tmp, index=False, float_format="%.9g"))
    import pandas as pd  # lazy: the report's tables only

    corr = pd.DataFrame(result.correlation, index=result.names, columns=result.names)
    io.atomic(folder / "correlation.csv", lambda tmp: corr.to_csv(tmp, float_format="%.6f"))
    from cdpr.pipeline.plots import calibration as figures  # lazy: matplotlib, --report only

    figures.calibration_figures(result, folder)


def cmd_check(args):
    """``cdpr calibrate check``: the robot's prediction against every measured sample."""
    motor = cal.is_motor_table(args.data)
    robot = nominal_robot(args, motor)
    if motor:
        _check_motor(args, robot)
        return
    if args.model != "exact":
        raise CdprError(
            f"--model {args.model}: check on commanded lengths uses the robot file as it is; "
            "--model is for motor-angle data (motor_deg_1..)"
        )
    data = cal.read_data(args.data, robot)
    out = cal.check(robot, data)
    if args.json:
        emit_json(out, args)
        return
    if _wrench_line(args):
        print(_wrench_line(args))
    if out["n"] == 0:
        counts = Counter(s["status"] for s in out["samples"])
        what = ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
        print(f"no sample has an ok equilibrium ({len(out['samples'])} samples: {what})")
        return
    print(
        f"{out['n']} samples: RMS {out['rms_m'] * 1e3:.4g} mm, median {out['median_m'] * 1e3:.4g} mm, "
        f"max {out['max_m'] * 1e3:.4g} mm"
        + (
            f"; orientation RMS {out['rms_rad'] * 1e3:.4g} mrad, max {out['max_rad'] * 1e3:.4g} mrad"
            if out["rms_rad"] is not None
            else ""
        )
    )
    bad = [s for s in out["samples"] if s["error_m"] is None]
    if bad:
        print(
            f"{len(bad)} samples without equilibrium: "
            + ", ".join(f"{s['sample']} ({s['status']})" for s in bad)
        )


def _check_motor(args, robot):
    """``cdpr calibrate check`` on motor-angle data: positions solved from the readings vs measured."""
    data = cal.read_motor_data(args.data, robot)
    out = cal.check_motor(robot, data, args.model)
    if args.json:
        emit_json(out, args)
        return
    if out["n"] == 0:
        print(
            f"no sample has a measured position ({len(out['samples'])} samples); line RMS {_mm(out['line_rms_m'])}"
        )
        return
    print(
        f"{out['n']} samples with a measured position: RMS {_mm(out['rms_m'])}, median {_mm(out['median_m'])}, "
        f"max {_mm(out['max_m'])}; line RMS {_mm(out['line_rms_m'])} over {len(out['samples'])} samples "
        f"({out['model']} model)"
    )


def _mm(x):
    return "n/a" if x is None else f"{x * 1e3:.4g} mm"


def cmd_cv(args):
    """``cdpr calibrate cv``: K-fold cross-validation of a motor-angle calibration (or of a given robot, --fixed)."""
    robot = checked(load_robot(args.robot), args)
    if args.fixed and args.estimate:
        raise CdprError("--fixed scores the robot file as given: give no --estimate")
    if args.fixed and args.prior:
        raise CdprError("--fixed scores the robot file as given: give no --prior")
    if not args.fixed and not args.estimate:
        raise CdprError(f"--estimate: give the groups to fit ({', '.join(cal.MOTOR_GROUPS)}), or --fixed")
    priors = None if args.fixed else cal.parse_motor_priors(args.prior, args.estimate)
    data = cal.read_motor_data(args.data, robot)
    out = cal.cross_validate(
        robot, data, args.estimate or [], priors, model=args.model, folds=args.folds, fixed=args.fixed
    )
    for w in out["data_warnings"]:
        print(f"cdpr: warning: {w}", file=sys.stderr)
    if args.json:
        emit_json(out, args)
        return
    rows = [_cv_row(str(f["fold"]), len(f["samples"]), f) for f in out["folds"]]
    rows.append(_cv_row("all", len(out["per_sample"]), out))
    print(
        _table(
            rows,
            [
                "fold",
                "held out",
                "with position",
                "position RMS",
                "position median",
                "line RMS",
                "train line RMS",
            ],
        )
    )
    what = "the robot file as given (--fixed)" if args.fixed else f"fit of {','.join(args.estimate)}"
    print(f"{args.folds} folds (row i in fold i mod {args.folds}); {what}; {args.model} model")
    if out["gauge"]:
        print(f"gauge: {out['gauge']}")


def _cv_row(label, n, scores):
    """A row of the cross-validation table: ``label``, ``n`` held-out samples and the ``scores`` of a
    fold or of all folds (``calibration.cross_validate``)."""
    return [
        label,
        str(n),
        str(scores["heldout_with_position"]),
        _mm(scores["heldout_position_rms_m"]),
        _mm(scores["heldout_position_median_m"]),
        _mm(scores["heldout_line_rms_m"]),
        _mm(scores["train_rms_m"]),
    ]


def cmd_plan(args):
    """``cdpr calibrate plan``: D-optimal poses and their expected standard errors versus random ones."""
    if args.out:
        io.check_output(args.out, (".csv",))
    robot = nominal_robot(args)
    priors = cal.parse_priors(args.prior, estimate=args.estimate)
    res = cal.plan(
        robot,
        args.estimate,
        args.n,
        box=args.box,
        priors=priors,
        sigma=args.sigma,
        n_axis=args.grid,
        command=args.command,
    )
    if args.out:
        import pandas as pd  # lazy: the plan's table only

        df = pd.DataFrame({"sample": np.arange(1, args.n + 1)})
        for i in range(robot.m):
            df[f"L{i + 1}"] = res["lengths"][:, i]
        cols = (
            "x_expected_m",
            "y_expected_m",
            "z_expected_m",
            "rx_expected_rad",
            "ry_expected_rad",
            "rz_expected_rad",
        )
        for j in range(res["poses"].shape[1]):  # 6 columns for a 6-DoF platform
            df[cols[j]] = res["poses"][:, j]
        io.atomic(args.out, lambda tmp: df.to_csv(tmp, index=False, float_format="%.12g"))
    out = {
        "n": args.n,
        "n_candidates": res["n_candidates"],
        "poses": res["poses"].tolist(),
        "lengths": res["lengths"].tolist(),
        "expected_sd": [
            {"name": nm, "prior_sd": float(p), "d_optimal": float(d), "random_median": float(r)}
            for nm, p, d, r in zip(
                res["names"], res["prior_sd"], res["sd_d_optimal"], res["sd_random_median"]
            )
        ],
        "logdet_d_optimal": res["logdet_d_optimal"],
        "logdet_random_median": res["logdet_random_median"],
    }
    for w in res.get("warnings", []):  # a group the plan cannot see: one line each on stderr, and in --json
        print(f"cdpr: warning: {w}", file=sys.stderr)
        args.warnings = [*getattr(args, "warnings", []), w]
    if args.json:
        emit_json(out, args)
        return
    rows = [
        [e["name"], f"{e['prior_sd']:.3g}", f"{e['d_optimal']:.3g}", f"{e['random_median']:.3g}"]
        for e in out["expected_sd"]
    ]
    print(
        _table(rows, ["parameter", "prior sd", f"sd D-optimal ({args.n})", f"sd random ({args.n}, median)"])
    )
    print(
        f"{args.n} poses chosen among {res['n_candidates']} admissible candidates; log det information "
        f"{res['logdet_d_optimal']:.4g} (random plans: median {res['logdet_random_median']:.4g})"
        + (f"; written to {args.out}" if args.out else "")
    )
    if _wrench_line(args):
        print(_wrench_line(args, "while the plan is measured"))


def cmd_study(args):
    """``cdpr calibrate study``: run the calibration study and print the headline table (a study
    with ``data_sets`` is the Hangprinter study, ``cdpr.pipeline.hangprinter``)."""
    from cdpr.pipeline import hangprinter  # lazy: the study only

    if hangprinter.is_hangprinter_study(args.study):
        res = hangprinter.run_hangprinter_study(args.study, args.out)
        print(Path(res["summary"]).read_text(encoding="utf-8"))
        print(f"Hangprinter study: {res['elapsed_s']:.1f} s")
        return
    from cdpr.pipeline.calibration import run_calibration_study  # lazy: the study only

    res = run_calibration_study(args.study, args.out)
    print(Path(res["summary"]).read_text(encoding="utf-8"))
    print(f"calibration study: {res['elapsed_s']:.1f} s")
