"""The calibration study (issue 18): a seeded true CDPR4 (with winches), synthetic tracker data,
calibrations with models of increasing fidelity, and their errors on a validation set.

The figures (residuals before/after per sample, estimates with their 95 % intervals against the
prior, the posterior correlation matrix, the learning curve) are drawn by
``cdpr.pipeline.plots.calibration``.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from cdpr import io, table_io
from cdpr.analyses import calibration as cal
from cdpr.analyses.compensation import compensated_pose
from cdpr.errors import CdprError, ConfigError
from cdpr.parameters import calibration_values, select_groups
from cdpr.pipeline.plots import calibration as figures
from cdpr.pipeline.results import rel_path
from cdpr.robot import TABLE1, load_robot, params_from_mapping

# --- the calibration study ------------------------------------------------------------------------
#: The study's models: label -> (fit model, groups); in order of fidelity.
STUDY_MODELS = {
    "standard": ("standard", ["anchors", "dead_lengths"]),
    "pulleys": ("rigid", ["anchors", "dead_lengths", "pulleys"]),
    "pulleys + elasticity": ("exact", ["anchors", "dead_lengths", "pulleys", "moduli"]),
    "pulleys + elasticity + winch": ("exact", ["anchors", "dead_lengths", "pulleys", "moduli"]),
}
#: Floats of the fitted parameters and per-sample tables: six significant digits. The fit ends
#: where least_squares' xtol holds: the estimates are fixed to ~1e-8 relative on CDPR4 and ~1e-6 on
#: CoGiRo (whose fit ends at a kink of the residual: slack cables), and the last bits differ between
#: CPUs, so more digits would not be the same on another machine.
FIT_FORMAT = "%.6g"

#: The model that knows the drums (the nominal robot with the study's winch on every cable); the
#: others take the commanded lengths as rest lengths.
WINCH_MODEL = "pulleys + elasticity + winch"
#: The study's outputs under its folder: ``cdpr.pipeline.results.CALIBRATION_OUTPUTS[RULE]``.
RULE = "calibration_study"
#: Keys of config/studies/calibration.yaml.
STUDY_KEYS = {
    "name",
    "robot",
    "seed",
    "truth_deviations",
    "tracker_sigma_m",
    "tension_sigma_N",
    "encoder_offset_sd_m",
    "calibration_box_m",
    "validation_box_m",
    "n_train",
    "n_validation",
    "learning_curve",
    "plan_grid",
}
#: Optional keys: ``winch``, the drum on every cable of the true robot (Métillon 2022 Table 1 keys,
#: ``{}`` is Table 1; without it the true robot has no winch and the study has no winch model).
STUDY_OPTIONAL = {"winch"}


def load_calibration_study(path):
    """Read and check config/studies/calibration.yaml (one-line ConfigError per bad key).

    Returns
    -------
    dict
        The keys of ``STUDY_KEYS``; truth_deviations as ``calibration.parse_priors`` values.
    """

    try:
        data = yaml.safe_load(open(path, encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(path, None, "the study file does not exist") from None
    if not isinstance(data, dict):
        raise ConfigError(path, None, "expected a mapping of keys to values")
    missing = sorted(STUDY_KEYS - set(data))
    if missing:
        raise ConfigError(
            path, missing[0], f"missing; a calibration study needs {', '.join(sorted(STUDY_KEYS))}"
        )
    extra = sorted(set(data) - STUDY_KEYS - STUDY_OPTIONAL)
    if extra:
        raise ConfigError(
            path, extra[0], f"unknown key; allowed: {', '.join(sorted(STUDY_KEYS | STUDY_OPTIONAL))}"
        )
    if "winch" in data:
        out_w = data["winch"] if data["winch"] is not None else {}
        if not isinstance(out_w, dict):
            raise ConfigError(path, "winch", "expected a mapping of winch parameters ({} is Table 1's drum)")
        data = dict(data, winch=params_from_mapping(out_w, str(path), "winch"))
    out = dict(data)
    dev = data["truth_deviations"]
    if not isinstance(dev, dict):
        raise ConfigError(path, "truth_deviations", "expected a mapping group: sd, e.g. anchors: 5mm")
    out["truth_deviations"] = cal.parse_priors(
        ",".join(f"{k}={v}" for k, v in dev.items()), f"{path}: truth_deviations"
    )
    out["deviation_groups"] = list(dev)
    for key in ("calibration_box_m", "validation_box_m"):
        box = data[key]
        if not (isinstance(box, list) and len(box) == 6 and all(isinstance(v, (int, float)) for v in box)):
            raise ConfigError(path, key, "expected 6 numbers [xmin, xmax, ymin, ymax, zmin, zmax] in m")
    for key in ("n_train", "n_validation", "plan_grid", "seed"):
        if not (isinstance(data[key], int) and data[key] > 0):
            raise ConfigError(path, key, f"expected a positive integer, got {data[key]!r}")
    lc = data["learning_curve"]
    if not (isinstance(lc, list) and lc and all(isinstance(v, int) and v > 0 for v in lc)):
        raise ConfigError(path, "learning_curve", "expected a list of positive sample counts")
    for key in ("tracker_sigma_m", "tension_sigma_N", "encoder_offset_sd_m"):
        if not (isinstance(data[key], (int, float)) and data[key] > 0):
            raise ConfigError(path, key, f"expected a number > 0, got {data[key]!r}")
    return out


def error_stats(err):
    """median, 95 % and max of an error array [m] -> [mm], NaN-free."""
    e = np.asarray(err)[np.isfinite(err)]
    if not len(e):
        return {"median_mm": np.nan, "p95_mm": np.nan, "max_mm": np.nan}
    return {
        "median_mm": 1e3 * float(np.median(e)),
        "p95_mm": 1e3 * float(np.percentile(e, 95)),
        "max_mm": 1e3 * float(e.max()),
    }


def _uniform(rng, box, n):
    lo, hi = np.array(box[::2], dtype=float), np.array(box[1::2], dtype=float)
    return rng.uniform(lo, hi, (n, 3))


def run_calibration_study(study_path, out):
    """The calibration study of issue 18: a seeded true CDPR4 (with the study's ``winch`` on every
    cable, commanded through a controller that neglects the exit point's motion), synthetic tracker
    data, calibrations with the standard, pulley, pulley + elasticity and (with a winch) pulley +
    elasticity + winch models, each predicting and compensating a validation set over RW_C; learning curves (random and D-optimal poses); encoder data with and
    without tensions. Writes headline.csv, summary.md, learning_curve.csv/.png, encoder.csv,
    parameters.csv and the exact fit's samples and figures (exact/) under ``out``: the files of
    ``cdpr.pipeline.results.CALIBRATION_OUTPUTS["calibration_study"]``.

    Parameters
    ----------
    study_path : str or Path
        config/studies/calibration.yaml.
    out : str or Path
        Results folder (results/calibration).

    Returns
    -------
    dict
        headline (DataFrame), elapsed_s, summary (the path of summary.md).
    """

    t0 = time.perf_counter()
    st = load_calibration_study(study_path)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    robot = load_robot(st["robot"])
    # with a winch, the true robot and the winch model have the study's drum on every cable
    winched = robot
    if st.get("winch") is not None:
        winched = dataclasses.replace(
            robot, cables=tuple(dataclasses.replace(c, winch=st["winch"]) for c in robot.cables)
        )
    rng = np.random.default_rng(st["seed"])
    sigma = float(st["tracker_sigma_m"])
    # the true robot: every deviation group drawn from its tolerance
    dev_idx = select_groups(robot, st["deviation_groups"])
    dev_sd = cal.prior_sd(robot, dev_idx, st["truth_deviations"])
    truth, theta_true = cal.perturbed(winched, dev_idx, dev_sd, rng)
    train = cal.simulate(truth, robot, _uniform(rng, st["calibration_box_m"], st["n_train"]), sigma, rng)
    p_val = _uniform(rng, st["validation_box_m"], st["n_validation"])
    val = cal.simulate(truth, robot, p_val, sigma, rng)
    n_val_left_out = st["n_validation"] - len(val.sample)
    priors = st["truth_deviations"]

    def validate(model_robot, offsets=None):
        """Prediction errors on the validation samples and compensated errors over RW_C; with
        ``offsets`` the validation lengths are encoder readings (true rest length + the true
        offset) turned into rest lengths with the estimated offsets."""
        v = val if offsets is None else dataclasses.replace(val, L=val.L + off - offsets)
        pred = cal.check(model_robot, v)
        err_pred = np.array([s["error_m"] if s["error_m"] is not None else np.nan for s in pred["samples"]])
        comp = compensated_pose(
            model_robot, p_val, actual=truth, realise=cal.executed_lengths(model_robot, truth)
        )
        err_comp = np.where(comp["status"] == "ok", comp["dp"], np.nan)
        return err_pred, err_comp

    rows, ident_lines, fits = [], [], {}

    def row(label, n_par, err_pred, err_comp, extra=None):
        r = {"model": label, "parameters": n_par}
        r.update({f"predict_{k}": v for k, v in error_stats(err_pred).items()})
        r["predict_rms_mm"] = 1e3 * float(np.sqrt(np.nanmean(err_pred**2)))
        r.update({f"compensated_{k}": v for k, v in error_stats(err_comp).items()})
        r["compensated_points"] = int(np.isfinite(err_comp).sum())
        r.update(extra or {})
        rows.append(r)

    row("nominal (uncalibrated)", 0, *validate(robot))
    models = {k: v for k, v in STUDY_MODELS.items() if k != WINCH_MODEL or winched is not robot}
    best = WINCH_MODEL if winched is not robot else "pulleys + elasticity"
    for label, (model, groups) in models.items():
        c = cal.fit(winched if label == WINCH_MODEL else robot, train, groups, priors=priors, model=model)
        fits[label] = c
        row(label, len(c.index), *validate(c.fitted_model()), {"rank": c.ident["rank"]})
        s = c.summary()
        labels = pd.Series([p["identified"] for p in s["parameters"]]).value_counts().to_dict()
        cond = "inf" if s["condition"] is None else f"{s['condition']:.3g}"
        ident_lines.append(
            f"- **{label}** ({model} model, {s['n_parameters']} parameters): rank {s['rank']}, condition {cond}; "
            + ", ".join(f"{v} {k}" for k, v in sorted(labels.items()))
            + "; weak: "
            + ("; ".join(s["unidentified"]) if s["unidentified"] else "none")
        )
    row("truth robot (noise floor)", 0, *validate(truth))
    headline = pd.DataFrame(rows)
    headline["rank"] = headline["rank"].astype("Int64")
    table_io.write_table(headline, out / rel_path(RULE, "headline"), float_format="%.4f")

    exact = fits[best]
    pt = exact.parameter_table()
    pt["truth"] = calibration_values(truth)[exact.index]
    table_io.write_table(pt, out / rel_path(RULE, "parameters"), float_format=FIT_FORMAT)
    figures.calibration_figures(exact, out, {k: rel_path(RULE, k) for k in figures.FIT_FIGURES})
    table_io.write_table(exact.table, out / rel_path(RULE, "samples"), float_format=FIT_FORMAT)

    # learning curves, exact model: random poses vs D-optimal poses among the admissible candidates
    # (the best model: with a winch the one that knows the drums)
    groups = STUDY_MODELS[best][1]
    idx = select_groups(robot, groups)
    sd = cal.prior_sd(robot, idx, priors)
    P_c, L_c, p_c = cal.candidates(winched, st["calibration_box_m"], st["plan_grid"], targets=True)
    rows_c = cal.info_rows(winched, P_c, L_c, idx, sd, sigma)
    pool = cal.simulate(
        truth, robot, _uniform(rng, st["calibration_box_m"], max(st["learning_curve"])), sigma, rng
    )
    curve = []
    for n in st["learning_curve"]:
        chosen, _ = cal.d_optimal(rows_c, n)
        designs = {"random": pool.subset(np.arange(min(n, len(pool.sample)))), "D-optimal": None}
        designs["D-optimal"] = cal.simulate(truth, robot, p_c[chosen], sigma, rng)
        for design, data in designs.items():
            try:
                c = cal.fit(winched, data, groups, priors=priors)
            except CdprError as exc:
                curve.append({"n": n, "design": design, "error": str(exc)})
                continue
            err, _ = validate(c.fitted_model())
            curve.append(
                {
                    "n": n,
                    "design": design,
                    "predict_rms_mm": 1e3 * float(np.sqrt(np.nanmean(err**2))),
                    **{f"predict_{k}": v for k, v in error_stats(err).items()},
                    "median_sd_ratio": float(np.median(c.ident["ratio"])),
                }
            )
    curve = pd.DataFrame(curve)
    table_io.write_table(curve, out / rel_path(RULE, "curve"), float_format="%.4f")
    figures.learning_curve(
        curve, float(headline.iloc[-1]["predict_rms_mm"]), out / rel_path(RULE, "figure"), best
    )

    # encoder data: offsets unknown; with poses, with tensions only, alone; validated on encoder
    # readings of the validation commands
    off = rng.normal(0.0, st["encoder_offset_sd_m"], robot.m)
    priors_enc = dict(priors, offsets=float(st["encoder_offset_sd_m"]))
    p_enc = _uniform(rng, st["calibration_box_m"], st["n_train"])
    enc_rows = []
    cases = {
        "encoder + poses": (False, True, "exact", groups + ["offsets"]),
        "encoder + tensions, no poses": (True, False, "exact", ["dead_lengths", "moduli", "offsets"]),
        "encoder only, exact model": (False, False, "exact", ["dead_lengths", "offsets"]),
        "encoder only, rigid self-calibration": (
            False,
            False,
            "standard",
            ["anchors", "dead_lengths", "offsets"],
        ),
    }
    for case, (tens, poses, model, gr) in cases.items():
        data = cal.simulate(
            truth, robot, p_enc, sigma, rng, offsets=off, tensions=tens, sigma_t=float(st["tension_sigma_N"])
        )
        if not poses:
            data.pose[:] = np.nan
        try:
            c = cal.fit(winched, data, gr, priors=priors_enc, model=model)
        except CdprError as exc:
            enc_rows.append({"case": case, "groups": ",".join(gr), "result": str(exc).split(";")[0]})
            continue
        err, _ = validate(c.fitted_model(), offsets=c.offsets)
        s = c.summary()
        enc_rows.append(
            {
                "case": case,
                "groups": ",".join(gr),
                "n_parameters": s["n_parameters"],
                "rank": s["rank"],
                "identified": int((c.ident["labels"] == "identified").sum()),
                "predict_rms_mm": 1e3 * float(np.sqrt(np.nanmean(err**2))),
                "result": "; ".join(s["unidentified"][:4]) or "all directions seen",
            }
        )
    table_io.write_table(pd.DataFrame(enc_rows), out / rel_path(RULE, "encoder"), float_format="%.4f")

    elapsed = time.perf_counter() - t0
    _write_markdown(
        out, st, headline, curve, pd.DataFrame(enc_rows), ident_lines, n_val_left_out, len(val.sample), best
    )
    return {"headline": headline, "elapsed_s": elapsed, "summary": out / rel_path(RULE, "summary")}


def md_table(df, cols, fmt="{:.3g}"):
    """A markdown table of the columns ``cols`` of ``df``, floats written with ``fmt`` (a missing
    value, NaN, as "–": the row's note says why), cells escaped by ``io.md_row``."""
    head = io.md_row(cols) + "\n|" + "---|" * len(cols) + "\n"
    lines = []
    for _, r in df.iterrows():
        cells = [
            ("–" if r[c] != r[c] else fmt.format(r[c])) if isinstance(r[c], float) else str(r[c])
            for c in cols
        ]
        lines.append(io.md_row(cells))
    return head + "\n".join(lines) + "\n"


def _write_markdown(out, st, headline, curve, enc, ident_lines, left_out, n_val, best="pulleys + elasticity"):
    """results/calibration/summary.md: the headline table, identifiability, learning curve, encoder."""
    text = [
        "# Calibration study: a robot's parameters from simulated measurements",
        "",
        f"True robot: {st['robot']} with deviations drawn (seed {st['seed']}) from "
        + ", ".join(f"{g} {v:g}" for g, v in st["truth_deviations"].items() if g in st["deviation_groups"])
        + f" (lengths in m, moduli relative); tracker sigma {st['tracker_sigma_m'] * 1e3:g} mm; "
        f"{st['n_train']} training samples in {st['calibration_box_m']}; validation: {n_val} poses over RW_C "
        f"{st['validation_box_m']} ({left_out} without equilibrium left out). Errors in mm.",
        *(
            [
                "",
                "Winch: the true robot has the drum of Metillon et al. 2022 (Table 1 values"
                + (" as given in the study file" if st["winch"] != TABLE1 else "")
                + ") on every cable, nominal geometry on all four (no per-cable drum deviation). Its controller "
                "turns each drum to the angle of the model that neglects the exit point's motion (q_nw, eq. 32), "
                "so the realised rest lengths differ from the commanded ones by the winch error (eq. 31, about "
                "-0.8 to +1.5 mm). The data's L1..Lm are the commanded lengths; the first three models take them "
                "as rest lengths, the winch model maps them through the drums.",
            ]
            if st.get("winch") is not None
            else []
        ),
        "",
        "## Headline: validation error per model",
        "",
        md_table(
            headline,
            [
                "model",
                "parameters",
                "predict_median_mm",
                "predict_p95_mm",
                "predict_max_mm",
                "predict_rms_mm",
                "compensated_median_mm",
                "compensated_p95_mm",
                "compensated_max_mm",
            ],
        ),
        "predict: |predicted - measured| under the validation commands (includes the tracker noise); "
        "compensated: |reached - target| when the calibrated model computes the commands (true error, no noise).",
        "",
        "## Identifiability",
        "",
        *ident_lines,
        "",
        f"## Learning curve ({best} model)",
        "",
        md_table(
            curve,
            [c for c in ("n", "design", "predict_rms_mm", "predict_p95_mm", "median_sd_ratio") if c in curve],
        ),
        "## Encoder data (unknown offsets)",
        "",
        md_table(enc, list(enc.columns)),
    ]
    io.write_text("\n".join(text), out / rel_path(RULE, "summary"))
