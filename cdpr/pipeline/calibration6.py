"""The calibration study of a rigid 6-DoF platform (issue 18, CoGiRo): a seeded true robot, synthetic
tracker data (position and orientation), calibrations with the standard, rigid and exact models,
their prediction errors on validation poses in the workspace (validation poses where the true robot
holds fewer than 6 taut cables or has a second equilibrium flagged, never dropped), and the pose
reached when each calibrated model computes the compensated commands.

``run_study`` runs the study a file describes: this one for a 6-DoF robot, the CDPR4 study of
``cdpr.pipeline.calibration`` for a point-mass robot.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from cdpr import io, table_io
from cdpr.analyses import calibration as cal
from cdpr.errors import ConfigError
from cdpr.models.platform import rotation_matrix
from cdpr.parameters import calibration_values, is_spatial, select_groups
from cdpr.pipeline.calibration import (
    FIT_FORMAT,
    error_stats,
    md_table,
    run_calibration_study,
)
from cdpr.pipeline.plots import calibration as figures
from cdpr.pipeline.results import rel_path
from cdpr.robot import load_robot

#: The study's outputs under its folder: ``cdpr.pipeline.results.CALIBRATION_OUTPUTS[RULE6]``.
RULE6 = "calibration_cogiro"
#: The study's models on a 6-DoF platform: label -> (fit model, groups); in order of fidelity.
STUDY_MODELS6 = {
    "standard": ("standard", ["anchors", "attachments", "dead_lengths"]),
    "pulleys": ("rigid", ["anchors", "attachments", "dead_lengths"]),
    "pulleys + elasticity": ("exact", ["anchors", "attachments", "dead_lengths", "moduli"]),
}
#: The model whose compensated commands drive the pretensioned validation.
EXACT6 = "pulleys + elasticity"
#: Keys of config/studies/calibration_cogiro.yaml.
STUDY_KEYS6 = {
    "name",
    "robot",
    "seed",
    "truth_deviations",
    "tracker_sigma_m",
    "tracker_sigma_rad",
    "command",
    "pose_box_m",
    "tilt_rad",
    "tension_margin_N",
    "n_train",
    "n_validation",
}
#: Groups a 6-DoF study's true robot may deviate in.
DEVIATION_GROUPS6 = ("anchors", "attachments", "dead_lengths", "moduli")


def _read(path):
    try:
        data = yaml.safe_load(open(path, encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(path, None, "the study file does not exist") from None
    if not isinstance(data, dict):
        raise ConfigError(path, None, "expected a mapping of keys to values")
    if "robot" not in data:
        raise ConfigError(path, "robot", "missing; a calibration study needs its robot file")
    return data


def run_study(study_path, out):
    """The calibration study of ``study_path``: ``run_calibration_study6`` when its robot is a 6-DoF
    platform, else ``calibration.run_calibration_study`` (CDPR4)."""
    data = _read(study_path)
    if is_spatial(load_robot(data["robot"])):
        return run_calibration_study6(study_path, out)
    return run_calibration_study(study_path, out)


def load_calibration_study6(path):
    """Read and check config/studies/calibration_cogiro.yaml (one-line ConfigError per bad key).

    Returns
    -------
    dict
        The keys of ``STUDY_KEYS6``; truth_deviations as ``calibration.parse_priors`` values,
        deviation_groups the groups given.
    """
    data = _read(path)
    missing = sorted(STUDY_KEYS6 - set(data))
    if missing:
        raise ConfigError(
            path, missing[0], f"missing; a 6-DoF calibration study needs {', '.join(sorted(STUDY_KEYS6))}"
        )
    extra = sorted(set(data) - STUDY_KEYS6)
    if extra:
        raise ConfigError(path, extra[0], f"unknown key; allowed: {', '.join(sorted(STUDY_KEYS6))}")
    out = dict(data)
    dev = data["truth_deviations"]
    if not isinstance(dev, dict) or not dev:
        raise ConfigError(path, "truth_deviations", "expected a mapping group: sd, e.g. anchors: 5mm")
    bad = sorted(set(dev) - set(DEVIATION_GROUPS6))
    if bad:
        raise ConfigError(
            path, "truth_deviations", f"group {bad[0]!r}; allowed: {', '.join(DEVIATION_GROUPS6)}"
        )
    out["truth_deviations"] = cal.parse_priors(
        ",".join(f"{k}={v}" for k, v in dev.items()), f"{path}: truth_deviations"
    )
    out["deviation_groups"] = list(dev)
    box = data["pose_box_m"]
    if not (isinstance(box, list) and len(box) == 6 and all(isinstance(v, (int, float)) for v in box)):
        raise ConfigError(path, "pose_box_m", "expected 6 numbers [xmin, xmax, ymin, ymax, zmin, zmax] in m")
    for key in ("n_train", "n_validation", "seed"):
        if not (isinstance(data[key], int) and not isinstance(data[key], bool) and data[key] > 0):
            raise ConfigError(path, key, f"expected a positive integer, got {data[key]!r}")
    for key in ("tracker_sigma_m", "tracker_sigma_rad", "tilt_rad"):
        if not (isinstance(data[key], (int, float)) and data[key] > 0):
            raise ConfigError(path, key, f"expected a number > 0, got {data[key]!r}")
    if not (isinstance(data["tension_margin_N"], (int, float)) and data["tension_margin_N"] >= 0):
        raise ConfigError(
            path, "tension_margin_N", f"expected a number >= 0, got {data['tension_margin_N']!r}"
        )
    if data["command"] not in cal.COMMANDS:
        raise ConfigError(path, "command", f"{data['command']!r}; allowed: {', '.join(cal.COMMANDS)}")
    return out


def _key(label):
    """Column prefix of a model label in validation.csv ("pulleys + elasticity" -> "pulleys_and_elasticity")."""
    return label.replace(" ", "_").replace("(", "").replace(")", "").replace("+", "and")


def _errors(robot, data):
    """Position [m] and orientation [rad] errors of ``robot``'s prediction per sample (NaN where its
    equilibrium is not ok) and the statuses."""
    ch = cal.check(robot, data)
    pos = np.array([np.nan if s["error_m"] is None else s["error_m"] for s in ch["samples"]])
    ang = np.array([np.nan if s["error_rad"] is None else s["error_rad"] for s in ch["samples"]])
    return pos, ang, np.array([s["status"] for s in ch["samples"]])


def run_calibration_study6(study_path, out):
    """The calibration study of a 6-DoF platform (module docstring). Writes headline.csv,
    validation.csv, parameters.csv, summary.md, validation_errors.png and the exact fit's samples
    and figures (exact/) under ``out``: the files of
    ``cdpr.pipeline.results.CALIBRATION_OUTPUTS["calibration_cogiro"]``.

    Parameters
    ----------
    study_path : str or Path
        config/studies/calibration_cogiro.yaml.
    out : str or Path
        Results folder (results/calibration/cogiro).

    Returns
    -------
    dict
        headline (DataFrame), elapsed_s, summary (the path of summary.md).
    """
    t0 = time.perf_counter()
    st = load_calibration_study6(study_path)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    robot = load_robot(st["robot"])
    if not is_spatial(robot):
        raise ConfigError(
            study_path, "robot", f"{st['robot']} is a point-mass robot; this study needs a 6-DoF platform"
        )
    rng = np.random.default_rng(st["seed"])
    sigma, sigma_rad, command = float(st["tracker_sigma_m"]), float(st["tracker_sigma_rad"]), st["command"]
    dev_idx = select_groups(robot, st["deviation_groups"])
    truth, _ = cal.perturbed(robot, dev_idx, cal.prior_sd(robot, dev_idx, st["truth_deviations"]), rng)

    def poses(n):
        return cal.random_poses6(
            robot, rng, n, st["pose_box_m"], st["tilt_rad"], float(st["tension_margin_N"]), command
        )

    kw = dict(sigma=sigma, rng=rng, sigma_rad=sigma_rad, command=command)
    train = cal.simulate(truth, robot, poses(st["n_train"]), **kw)
    P_val = poses(st["n_validation"])
    val = cal.simulate(truth, robot, P_val, **kw)
    n_taut, second = cal.equilibrium_flags(truth, val)
    flagged = (n_taut < 6) | second
    truth_taut = cal.solve6(truth, val.pose, val.L, rotvec=val.rotvec)["taut"]
    priors = st["truth_deviations"]

    vt = pd.DataFrame(
        {"sample": val.sample, "truth_taut_cables": n_taut, "second_equilibrium": second, "flagged": flagged}
    )
    rows, fits, ident_lines = [], {}, []

    def row(label, rob, n_par=0, rank=None):
        pos, ang, status = _errors(rob, val)
        # the model's taut set against the truth's at the measured pose
        differs = (cal.solve6(rob, val.pose, val.L, rotvec=val.rotvec)["taut"] != truth_taut).any(axis=1)
        key = _key(label)
        vt[f"{key}_taut_set_differs"] = differs
        vt[f"{key}_status"] = status
        vt[f"{key}_position_mm"] = 1e3 * pos
        vt[f"{key}_orientation_mrad"] = 1e3 * ang
        # the calibrated model computes compensated commands for the validation targets; the truth executes
        p, R = P_val[:, :3], rotation_matrix(P_val[:, 3:])
        L = cal.commanded_lengths(rob, p, R, "compensated")
        fin = np.isfinite(L).all(axis=1)
        reach = cal.solve6(truth, p[fin], L[fin], rotvec=P_val[fin, 3:])
        ok = reach["status"] == "ok"
        dp = np.where(ok, np.linalg.norm(reach["P_s"] - p[fin], axis=1), np.nan)
        r = {"model": label, "parameters": n_par, "rank": rank}
        r.update({f"predict_{k}": v for k, v in error_stats(pos).items()})
        r["predict_rms_mm"] = 1e3 * float(np.sqrt(np.nanmean(pos**2)))
        r.update({f"orient_{k.replace('mm', 'mrad')}": v for k, v in error_stats(ang).items()})
        r["orient_rms_mrad"] = 1e3 * float(np.sqrt(np.nanmean(ang**2)))
        r["unflagged_rms_mm"] = 1e3 * float(np.sqrt(np.nanmean(pos[~flagged] ** 2)))
        r["unflagged_max_mm"] = 1e3 * float(np.nanmax(pos[~flagged])) if (~flagged).any() else np.nan
        r["predicted_points"] = int(np.isfinite(pos).sum())
        r["taut_set_differs"] = int(differs.sum())
        r["same_taut_set_rms_mm"] = (
            1e3 * float(np.sqrt(np.nanmean(pos[~differs] ** 2))) if (~differs).any() else np.nan
        )
        r.update({f"compensated_{k}": v for k, v in error_stats(dp).items()})
        r["compensated_all_taut"] = int((ok & (reach["n_taut"] == robot.m)).sum())
        r["compensated_points"] = int(np.isfinite(dp).sum())
        rows.append(r)

    for label, (model, groups) in STUDY_MODELS6.items():
        c = cal.fit(robot, train, groups, priors=priors, model=model)
        fits[label] = c
        s = c.summary()
        labels = pd.Series([p["identified"] for p in s["parameters"]]).value_counts().to_dict()
        cond = "inf" if s["condition"] is None else f"{s['condition']:.3g}"
        used = int((c.table["status"] == "used").sum())
        ident_lines.append(
            f"- **{label}** ({model} model, {s['n_parameters']} parameters, {used} of {len(train.sample)} samples "
            f"used): rank {s['rank']}, condition {cond}; "
            + ", ".join(f"{v} {k}" for k, v in sorted(labels.items()))
        )
    # pretensioned validation: the same targets commanded with the exact model's compensated lengths
    # (every cable of the true robot taut when the model is close enough to it)
    val_pt = cal.simulate(truth, fits[EXACT6].fitted_model(), P_val, **dict(kw, command="compensated"))
    taut_pt, second_pt = cal.equilibrium_flags(truth, val_pt)
    models = {"nominal (uncalibrated)": (robot, 0, None)}
    models.update({k: (c.fitted_model(), len(c.index), c.ident["rank"]) for k, c in fits.items()})
    models["truth robot (noise floor)"] = (truth, 0, None)
    pt_err = {}
    for label, (rob, n_par, rank) in models.items():
        row(label, rob, n_par, rank)
        pos, ang, _ = _errors(rob, val_pt)
        pt_err[label] = (pos, ang)
        rows[-1].update(
            {f"pretensioned_{k}": v for k, v in error_stats(pos).items()},
            pretensioned_rms_mm=1e3 * float(np.sqrt(np.nanmean(pos**2))),
            pretensioned_orient_rms_mrad=1e3 * float(np.sqrt(np.nanmean(ang**2))),
            pretensioned_points=int(np.isfinite(pos).sum()),
        )
    headline = pd.DataFrame(rows)
    headline["rank"] = headline["rank"].astype("Int64")
    table_io.write_table(headline, out / rel_path(RULE6, "headline"), float_format="%.4f")
    table_io.write_table(vt, out / rel_path(RULE6, "validation"), float_format="%.6g")

    exact = fits[EXACT6]
    pt = exact.parameter_table()
    pt["truth"] = calibration_values(truth)[exact.index]
    table_io.write_table(pt, out / rel_path(RULE6, "parameters"), float_format=FIT_FORMAT)
    figures.calibration_figures(exact, out, {k: rel_path(RULE6, k) for k in figures.FIT_FIGURES})
    table_io.write_table(exact.table, out / rel_path(RULE6, "samples"), float_format=FIT_FORMAT)
    figures.validation_errors(
        vt,
        {label: _key(label) for label in headline["model"]},
        {label: pt_err[label] for label in (EXACT6, "truth robot (noise floor)")},
        out / rel_path(RULE6, "figure"),
        robot.name,
        command,
    )
    elapsed = time.perf_counter() - t0
    _write_markdown6(out, st, robot, headline, ident_lines, vt, len(train.sample), (taut_pt, second_pt))
    return {"headline": headline, "elapsed_s": elapsed, "summary": out / rel_path(RULE6, "summary")}


def _write_markdown6(out, st, robot, headline, ident_lines, vt, n_train, pretensioned):
    """results/calibration/cogiro/summary.md: the headline tables, identifiability, flagged poses."""
    fl = vt[vt["flagged"]]
    counts = vt["truth_taut_cables"].value_counts().sort_index()
    text = [
        f"# Calibration study of a 6-DoF platform, {robot.name}: its parameters from simulated measurements",
        "",
        f"True robot: {st['robot']} with deviations drawn (seed {st['seed']}) from "
        + ", ".join(f"{g} {v:g}" for g, v in st["truth_deviations"].items() if g in st["deviation_groups"])
        + f" (lengths in m, moduli relative); tracker sigma {st['tracker_sigma_m'] * 1e3:g} mm, "
        f"{st['tracker_sigma_rad'] * 1e3:g} mrad; {n_train} training samples and {len(vt)} validation poses in "
        f"{st['pose_box_m']} m, tilted up to {st['tilt_rad']:g} rad, {st['command']} commands (every cable of the "
        f"nominal robot above {st['tension_margin_N']:g} N). Errors in mm and mrad.",
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
                "orient_median_mrad",
                "orient_p95_mrad",
                "orient_max_mrad",
                "unflagged_rms_mm",
                "taut_set_differs",
                "same_taut_set_rms_mm",
            ],
        ),
        "predict: |predicted - measured| under the validation commands (includes the tracker noise); "
        "unflagged: the same without the flagged poses (below); taut_set_differs: validation poses where the model's "
        "equilibrium at the measured pose has other taut cables than the truth's (the truth is known here, not on a real "
        "robot), same_taut_set: the RMS over the others.",
        "",
        "## Compensated commands of each model",
        "",
        md_table(
            headline,
            [
                "model",
                "compensated_median_mm",
                "compensated_p95_mm",
                "compensated_max_mm",
                "compensated_all_taut",
                "compensated_points",
            ],
        ),
        f"compensated: |reached - target| [mm] of the true robot when the model computes the rest lengths of the "
        f"minimum-norm tensions for the validation targets (true error, no noise); all_taut: poses where the true "
        f"robot then holds all {robot.m} cables taut.",
        "",
        "## Pretensioned validation",
        "",
        md_table(
            headline,
            [
                "model",
                "pretensioned_median_mm",
                "pretensioned_p95_mm",
                "pretensioned_max_mm",
                "pretensioned_rms_mm",
                "pretensioned_orient_rms_mrad",
                "pretensioned_points",
            ],
        ),
        f"The same {len(vt)} targets commanded with the compensated rest lengths of the calibrated "
        f"{EXACT6} model (a second measurement campaign after the calibration): |predicted - measured| [mm] "
        "(includes the tracker noise). True robot's taut cables: "
        + ", ".join(f"{k}: {v}" for k, v in zip(*np.unique(pretensioned[0], return_counts=True)))
        + f"; second equilibrium found: {int(pretensioned[1].sum())}.",
        "",
        "## Identifiability",
        "",
        *ident_lines,
        "",
        "## Flagged validation poses",
        "",
        "True robot's taut cables under the validation commands: "
        + ", ".join(f"{k}: {v}" for k, v in counts.items())
        + f"; second equilibrium found: {int(vt['second_equilibrium'].sum())}. Flagged (fewer than 6 taut or a "
        f"second equilibrium): {len(fl)}"
        + (f" ({', '.join(fl['sample'])})" if len(fl) else "")
        + "; kept in every "
        "statistic but `unflagged_rms_mm`.",
        "",
    ]
    io.write_text("\n".join(text), out / rel_path(RULE6, "summary"))
