"""The calibration studies (issue 18): a seeded true robot, synthetic tracker data, calibrations
with models of increasing fidelity, and their errors on a validation set. One door,
``run_calibration_study``, for every robot; the kind of robot the study file names
(``study_kind``) sets what is measured and validated:

- a point mass (CDPR4, config/studies/calibration.yaml, rule ``calibration_study``): a true robot
  with the study's ``winch`` on every cable, positions tracked, validation and compensation over
  RW_C, learning curves (random and D-optimal poses), encoder data with and without tensions;
- a rigid 6-DoF platform (CoGiRo, config/studies/calibration_cogiro.yaml, rule
  ``calibration_cogiro``): position and orientation tracked, validation poses in the workspace
  (those where the true robot holds fewer than 6 taut cables or has a second equilibrium flagged,
  never dropped), the pose reached when each calibrated model computes the compensated commands,
  and a pretensioned validation.

The figures (residuals before/after per sample, estimates with their 95 % intervals against the
prior, the posterior correlation matrix, the learning curve, the validation errors) are drawn by
``cdpr.pipeline.plots.calibration``.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np
import pandas as pd

from cdpr import io, table_io
from cdpr.analyses import calibration as cal
from cdpr.analyses.compensation import compensated_pose
from cdpr.errors import CdprError, ConfigError
from cdpr.models.platform import rotation_matrix
from cdpr.parameters import calibration_values, is_spatial, select_groups
from cdpr.pipeline.calibration_files import read_study_file
from cdpr.pipeline.plots import calibration as figures
from cdpr.pipeline.results import rel_path
from cdpr.robot import TABLE1, check_wrench, load_robot, params_from_mapping, with_wrench

#: The kinds of robot a calibration study knows (``study_kind``).
POINT_MASS, PLATFORM = "point-mass robot", "rigid platform"
#: The study's rule by kind (its outputs ``cdpr.pipeline.results.CALIBRATION_OUTPUTS[rule]``).
RULES = {POINT_MASS: "calibration_study", PLATFORM: "calibration_cogiro"}
#: The study's models by kind: label -> (fit model, groups); in order of fidelity.
STUDY_MODELS = {
    POINT_MASS: {
        "standard": ("standard", ["anchors", "dead_lengths"]),
        "pulleys": ("rigid", ["anchors", "dead_lengths", "pulleys"]),
        "pulleys + elasticity": ("exact", ["anchors", "dead_lengths", "pulleys", "moduli"]),
        "pulleys + elasticity + winch": ("exact", ["anchors", "dead_lengths", "pulleys", "moduli"]),
    },
    PLATFORM: {
        "standard": ("standard", ["anchors", "attachments", "dead_lengths"]),
        "pulleys": ("rigid", ["anchors", "attachments", "dead_lengths"]),
        "pulleys + elasticity": ("exact", ["anchors", "attachments", "dead_lengths", "moduli"]),
    },
}
#: The exact model: its fit is written under exact/ (without winches) and its compensated commands
#: drive the rigid platform's pretensioned validation.
EXACT = "pulleys + elasticity"
#: Floats of the fitted parameters and per-sample tables: six significant digits. The fit ends
#: where least_squares' xtol holds: the estimates are fixed to ~1e-8 relative on CDPR4 and ~1e-6 on
#: CoGiRo (whose fit ends at a kink of the residual: slack cables), and the last bits differ between
#: CPUs, so more digits would not be the same on another machine.
FIT_FORMAT = "%.6g"

#: The model that knows the drums (the nominal robot with the study's winch on every cable); the
#: others take the commanded lengths as rest lengths.
WINCH_MODEL = "pulleys + elasticity + winch"
_KEYS = {"name", "robot", "seed", "truth_deviations", "tracker_sigma_m", "n_train", "n_validation"}
#: Keys of a study file by kind (config/studies/calibration.yaml, calibration_cogiro.yaml).
STUDY_KEYS = {
    POINT_MASS: _KEYS
    | {
        "tension_sigma_N",
        "encoder_offset_sd_m",
        "calibration_box_m",
        "validation_box_m",
        "learning_curve",
        "plan_grid",
    },
    PLATFORM: _KEYS | {"tracker_sigma_rad", "command", "pose_box_m", "tilt_rad", "tension_margin_N"},
}
#: Optional keys by kind: ``winch``, the drum on every cable of a point mass's true robot (Métillon
#: 2022 Table 1 keys, ``{}`` is Table 1; without it the true robot has no winch and the study has
#: no winch model); ``wrench``, the external wrench [FX, FY, FZ, MX, MY, MZ] [N, N m] on the
#: platform during every measurement (``robot.with_wrench``; a moment refused on a point mass),
#: on the true robot and known to every model (``study_robot``).
STUDY_OPTIONAL = {POINT_MASS: {"winch", "wrench"}, PLATFORM: {"wrench"}}
#: Groups the true robot may deviate in, by kind.
DEVIATION_GROUPS = {
    POINT_MASS: ("anchors", "dead_lengths", "pulleys", "moduli"),
    PLATFORM: ("anchors", "attachments", "dead_lengths", "moduli"),
}
#: Study keys by type: boxes [xmin, xmax, ymin, ymax, zmin, zmax] [m], positive integers, numbers > 0.
_BOXES = ("calibration_box_m", "validation_box_m", "pose_box_m")
_COUNTS = ("n_train", "n_validation", "plan_grid", "seed")
_POSITIVE = ("tracker_sigma_m", "tension_sigma_N", "encoder_offset_sd_m", "tracker_sigma_rad", "tilt_rad")


def study_kind(robot):
    """The kind of calibration study a robot gets: ``PLATFORM`` for a rigid 6-DoF platform
    (``parameters.is_spatial``), else ``POINT_MASS``.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    str
    """
    return PLATFORM if is_spatial(robot) else POINT_MASS


def load_calibration_study(path):
    """Read and check a calibration study file (one-line ConfigError per bad key); its robot's kind
    (``study_kind``) fixes the keys (``STUDY_KEYS``, ``STUDY_OPTIONAL``).

    Parameters
    ----------
    path : str or Path
        config/studies/calibration.yaml or calibration_cogiro.yaml.

    Returns
    -------
    dict
        The study's keys; truth_deviations as ``calibration.parse_priors`` values, deviation_groups
        the groups given, winch (when given) the drum's parameters, kind the ``study_kind``.
    """
    data = read_study_file(path)
    if "robot" not in data:
        raise ConfigError(path, "robot", "missing; a calibration study needs its robot file")
    nominal = load_robot(data["robot"])
    kind = study_kind(nominal)
    keys, optional = STUDY_KEYS[kind], STUDY_OPTIONAL[kind]
    missing = sorted(keys - set(data))
    if missing:
        raise ConfigError(
            path, missing[0], f"missing; a calibration study of a {kind} needs {', '.join(sorted(keys))}"
        )
    extra = sorted(set(data) - keys - optional)
    if extra:
        raise ConfigError(path, extra[0], f"unknown key; allowed: {', '.join(sorted(keys | optional))}")
    if "winch" in data:
        out_w = data["winch"] if data["winch"] is not None else {}
        if not isinstance(out_w, dict):
            raise ConfigError(path, "winch", "expected a mapping of winch parameters ({} is Table 1's drum)")
        data = dict(data, winch=params_from_mapping(out_w, str(path), "winch"))
    out = dict(data, kind=kind)
    dev = data["truth_deviations"]
    if not isinstance(dev, dict) or not dev:
        raise ConfigError(path, "truth_deviations", "expected a mapping group: sd, e.g. anchors: 5mm")
    out["truth_deviations"] = cal.parse_priors(
        ",".join(f"{k}={v}" for k, v in dev.items()), f"{path}: truth_deviations"
    )
    bad = sorted(set(dev) - set(DEVIATION_GROUPS[kind]))
    if bad:
        raise ConfigError(
            path, "truth_deviations", f"group {bad[0]!r}; allowed: {', '.join(DEVIATION_GROUPS[kind])}"
        )
    out["deviation_groups"] = list(dev)
    for key in (k for k in _BOXES if k in keys):
        box = data[key]
        if not (isinstance(box, list) and len(box) == 6 and all(isinstance(v, (int, float)) for v in box)):
            raise ConfigError(path, key, "expected 6 numbers [xmin, xmax, ymin, ymax, zmin, zmax] in m")
    for key in (k for k in _COUNTS if k in keys):
        if not (isinstance(data[key], int) and not isinstance(data[key], bool) and data[key] > 0):
            raise ConfigError(path, key, f"expected a positive integer, got {data[key]!r}")
    if "learning_curve" in keys:
        lc = data["learning_curve"]
        if not (isinstance(lc, list) and lc and all(isinstance(v, int) and v > 0 for v in lc)):
            raise ConfigError(path, "learning_curve", "expected a list of positive sample counts")
    for key in (k for k in _POSITIVE if k in keys):
        if not (isinstance(data[key], (int, float)) and data[key] > 0):
            raise ConfigError(path, key, f"expected a number > 0, got {data[key]!r}")
    if "tension_margin_N" in keys and not (
        isinstance(data["tension_margin_N"], (int, float)) and data["tension_margin_N"] >= 0
    ):
        raise ConfigError(
            path, "tension_margin_N", f"expected a number >= 0, got {data['tension_margin_N']!r}"
        )
    if "command" in keys and data["command"] not in cal.COMMANDS:
        raise ConfigError(path, "command", f"{data['command']!r}; allowed: {', '.join(cal.COMMANDS)}")
    if "wrench" in data:
        try:
            out["wrench"] = None if data["wrench"] is None else check_wrench(data["wrench"], "wrench")
            with_wrench(nominal, out["wrench"], "wrench")  # a moment on a point mass: refused
        except CdprError as exc:
            raise ConfigError(path, "wrench", str(exc).removeprefix("wrench: ")) from None
    return out


def study_robot(st):
    """The nominal robot of a loaded calibration study (``load_calibration_study``) with the study's
    ``wrench`` on its platform (``robot.with_wrench``): the true robot drawn from it carries the wrench
    during every measurement, and every model fitted to the data knows it.

    Parameters
    ----------
    st : dict

    Returns
    -------
    Robot
    """
    return with_wrench(load_robot(st["robot"]), st.get("wrench"), "wrench")


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


def _predict_columns(err):
    """The headline's prediction columns of position errors [m]: median, 95 %, max, RMS [mm]."""
    out = {f"predict_{k}": v for k, v in error_stats(err).items()}
    out["predict_rms_mm"] = 1e3 * float(np.sqrt(np.nanmean(err**2)))
    return out


def _uniform(rng, box, n):
    lo, hi = np.array(box[::2], dtype=float), np.array(box[1::2], dtype=float)
    return rng.uniform(lo, hi, (n, 3))


def run_calibration_study(study_path, out):
    """The calibration study of issue 18 that ``study_path`` describes (module docstring): a seeded
    true robot, synthetic tracker data, calibrations with the study's models (``STUDY_MODELS`` of
    its kind), their validation errors. A point mass writes headline.csv, summary.md,
    learning_curve.csv/.png, encoder.csv, parameters.csv; a rigid platform headline.csv,
    validation.csv, parameters.csv, summary.md, validation_errors.png; both the exact fit's samples
    and figures (exact/): the files of ``cdpr.pipeline.results.CALIBRATION_OUTPUTS[RULES[kind]]``
    under ``out``.

    Parameters
    ----------
    study_path : str or Path
        config/studies/calibration.yaml (CDPR4) or calibration_cogiro.yaml (CoGiRo).
    out : str or Path
        Results folder (results/calibration, results/calibration/cogiro).

    Returns
    -------
    dict
        headline (DataFrame), elapsed_s, summary (the path of summary.md).
    """
    t0 = time.perf_counter()
    st = load_calibration_study(study_path)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    robot = study_robot(st)
    rng = np.random.default_rng(st["seed"])
    study = _platform_study if st["kind"] == PLATFORM else _point_mass_study
    headline, text = study(st, robot, rng, out)
    elapsed = time.perf_counter() - t0
    summary = out / rel_path(RULES[st["kind"]], "summary")
    io.write_text("\n".join(text), summary)
    return {"headline": headline, "elapsed_s": elapsed, "summary": summary}


def _truth(robot, st, rng, winched=None):
    """The true robot: every deviation group of the study drawn from its tolerance (on ``winched``,
    the robot with the study's drums, when given)."""
    idx = select_groups(robot, st["deviation_groups"])
    sd = cal.prior_sd(robot, idx, st["truth_deviations"])
    return cal.perturbed(robot if winched is None else winched, idx, sd, rng)[0]


def _fit_models(st, robot, train, winched=None):
    """The fits of the study's models (``STUDY_MODELS`` of its kind; the winch model, on
    ``winched``, only when the true robot has winches) and a line of identifiability per model
    (a point mass's names its weak directions, a platform's the samples its fits used)."""
    fits, lines = {}, []
    for label, (model, groups) in STUDY_MODELS[st["kind"]].items():
        if label == WINCH_MODEL and winched is None:
            continue
        c = cal.fit(
            winched if label == WINCH_MODEL else robot,
            train,
            groups,
            priors=st["truth_deviations"],
            model=model,
        )
        fits[label] = c
        s = c.summary()
        labels = pd.Series([p["identified"] for p in s["parameters"]]).value_counts().to_dict()
        cond = "inf" if s["condition"] is None else f"{s['condition']:.3g}"
        used = ""
        if st["kind"] == PLATFORM:
            used = f", {int((c.table['status'] == 'used').sum())} of {len(train.sample)} samples used"
        line = (
            f"- **{label}** ({model} model, {s['n_parameters']} parameters{used}): rank {s['rank']}, condition {cond}; "
            + ", ".join(f"{v} {k}" for k, v in sorted(labels.items()))
        )
        if st["kind"] == POINT_MASS:
            line += "; weak: " + ("; ".join(s["unidentified"]) if s["unidentified"] else "none")
        lines.append(line)
    return fits, lines


def _write_fit(out, rule, rows, exact, truth):
    """headline.csv (``rows``), and the exact fit's parameters.csv (with the truth), exact/samples.csv
    and figures; returns the headline."""
    headline = pd.DataFrame(rows)
    headline["rank"] = headline["rank"].astype("Int64")
    table_io.write_table(headline, out / rel_path(rule, "headline"), float_format="%.4f")
    pt = exact.parameter_table()
    pt["truth"] = calibration_values(truth)[exact.index]
    table_io.write_table(pt, out / rel_path(rule, "parameters"), float_format=FIT_FORMAT)
    figures.calibration_figures(exact, out, {k: rel_path(rule, k) for k in figures.FIT_FIGURES})
    table_io.write_table(exact.table, out / rel_path(rule, "samples"), float_format=FIT_FORMAT)
    return headline


def _point_mass_study(st, robot, rng, out):
    """The study of a point mass (CDPR4): the true robot with the study's ``winch`` on every cable,
    commanded through a controller that neglects the exit point's motion; the standard, pulley,
    pulley + elasticity and (with a winch) pulley + elasticity + winch models, each predicting and
    compensating a validation set over RW_C; learning curves (random and D-optimal poses); encoder
    data with and without tensions. Writes its tables and figures; returns the headline and the
    lines of summary.md."""
    rule = RULES[POINT_MASS]
    # with a winch, the true robot and the winch model have the study's drum on every cable
    winched = None
    if st.get("winch") is not None:
        winched = dataclasses.replace(
            robot, cables=tuple(dataclasses.replace(c, winch=st["winch"]) for c in robot.cables)
        )
    sigma = float(st["tracker_sigma_m"])
    truth = _truth(robot, st, rng, winched)
    train = cal.simulate(truth, robot, _uniform(rng, st["calibration_box_m"], st["n_train"]), sigma, rng)
    p_val = _uniform(rng, st["validation_box_m"], st["n_validation"])
    val = cal.simulate(truth, robot, p_val, sigma, rng)
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

    def row(label, rob, n_par=0, rank=None):
        err_pred, err_comp = validate(rob)
        r = {"model": label, "parameters": n_par, **_predict_columns(err_pred)}
        r.update({f"compensated_{k}": v for k, v in error_stats(err_comp).items()})
        r["compensated_points"] = int(np.isfinite(err_comp).sum())
        return r if rank is None else dict(r, rank=rank)

    fits, ident_lines = _fit_models(st, robot, train, winched)
    rows = [row("nominal (uncalibrated)", robot)]
    rows += [row(label, c.fitted_model(), len(c.index), c.ident["rank"]) for label, c in fits.items()]
    rows.append(row("truth robot (noise floor)", truth))
    best = EXACT if winched is None else WINCH_MODEL
    headline = _write_fit(out, rule, rows, fits[best], truth)

    # learning curves, exact model: random poses vs D-optimal poses among the admissible candidates
    # (the best model: with a winch the one that knows the drums)
    winched = robot if winched is None else winched
    groups = STUDY_MODELS[POINT_MASS][best][1]
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
    table_io.write_table(curve, out / rel_path(rule, "curve"), float_format="%.4f")
    figures.learning_curve(
        curve, float(headline.iloc[-1]["predict_rms_mm"]), out / rel_path(rule, "figure"), best
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
    enc = pd.DataFrame(enc_rows)
    table_io.write_table(enc, out / rel_path(rule, "encoder"), float_format="%.4f")
    left_out = st["n_validation"] - len(val.sample)
    return headline, _point_mass_summary(
        st, headline, curve, enc, ident_lines, left_out, len(val.sample), best
    )


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


def _platform_study(st, robot, rng, out):
    """The study of a rigid 6-DoF platform (CoGiRo): position and orientation tracked, the
    standard, rigid and exact models, validation poses in the workspace (flagged where the true
    robot holds fewer than 6 taut cables or has a second equilibrium), the pose reached under each
    model's compensated commands, and the pretensioned validation. Writes its tables and figures;
    returns the headline and the lines of summary.md."""
    rule = RULES[PLATFORM]
    sigma, sigma_rad, command = float(st["tracker_sigma_m"]), float(st["tracker_sigma_rad"]), st["command"]
    truth = _truth(robot, st, rng)

    def poses(n):
        return cal.random_poses(
            robot, rng, n, st["pose_box_m"], st["tilt_rad"], float(st["tension_margin_N"]), command
        )

    kw = dict(sigma=sigma, rng=rng, sigma_rad=sigma_rad, command=command)
    train = cal.simulate(truth, robot, poses(st["n_train"]), **kw)
    P_val = poses(st["n_validation"])
    val = cal.simulate(truth, robot, P_val, **kw)
    n_taut, second = cal.equilibrium_flags(truth, val)
    flagged = (n_taut < 6) | second
    truth_taut = cal.equilibria(truth, val.pose, val.L, rotvec=val.rotvec)["holding"]

    vt = pd.DataFrame(
        {"sample": val.sample, "truth_taut_cables": n_taut, "second_equilibrium": second, "flagged": flagged}
    )

    def row(label, rob, n_par=0, rank=None):
        pos, ang, status = _errors(rob, val)
        # the model's taut set against the truth's at the measured pose
        differs = (cal.equilibria(rob, val.pose, val.L, rotvec=val.rotvec)["holding"] != truth_taut).any(
            axis=1
        )
        key = _key(label)
        vt[f"{key}_taut_set_differs"] = differs
        vt[f"{key}_status"] = status
        vt[f"{key}_position_mm"] = 1e3 * pos
        vt[f"{key}_orientation_mrad"] = 1e3 * ang
        # the calibrated model computes compensated commands for the validation targets; the truth executes
        p, R = P_val[:, :3], rotation_matrix(P_val[:, 3:])
        L = cal.commanded_lengths(rob, p, R, "compensated")
        fin = np.isfinite(L).all(axis=1)
        reach = cal.equilibria(truth, p[fin], L[fin], rotvec=P_val[fin, 3:])
        ok = reach["status"] == "ok"
        dp = np.where(ok, np.linalg.norm(reach["P_s"] - p[fin], axis=1), np.nan)
        r = {"model": label, "parameters": n_par, "rank": rank, **_predict_columns(pos)}
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
        return r

    fits, ident_lines = _fit_models(st, robot, train)
    # pretensioned validation: the same targets commanded with the exact model's compensated lengths
    # (every cable of the true robot taut when the model is close enough to it)
    val_pt = cal.simulate(truth, fits[EXACT].fitted_model(), P_val, **dict(kw, command="compensated"))
    pretensioned = cal.equilibrium_flags(truth, val_pt)
    models = {"nominal (uncalibrated)": (robot, 0, None)}
    models.update({k: (c.fitted_model(), len(c.index), c.ident["rank"]) for k, c in fits.items()})
    models["truth robot (noise floor)"] = (truth, 0, None)
    rows, pt_err = [], {}
    for label, (rob, n_par, rank) in models.items():
        rows.append(row(label, rob, n_par, rank))
        pos, ang, _ = _errors(rob, val_pt)
        pt_err[label] = (pos, ang)
        rows[-1].update(
            {f"pretensioned_{k}": v for k, v in error_stats(pos).items()},
            pretensioned_rms_mm=1e3 * float(np.sqrt(np.nanmean(pos**2))),
            pretensioned_orient_rms_mrad=1e3 * float(np.sqrt(np.nanmean(ang**2))),
            pretensioned_points=int(np.isfinite(pos).sum()),
        )
    headline = _write_fit(out, rule, rows, fits[EXACT], truth)
    table_io.write_table(vt, out / rel_path(rule, "validation"), float_format="%.6g")
    figures.validation_errors(
        vt,
        {label: _key(label) for label in headline["model"]},
        {label: pt_err[label] for label in (EXACT, "truth robot (noise floor)")},
        out / rel_path(rule, "figure"),
        robot.name,
        command,
    )
    return headline, _platform_summary(st, robot, headline, ident_lines, vt, len(train.sample), pretensioned)


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


def _truth_words(st):
    """The start of a summary's sentence on the true robot: its file, seed, deviations and tracker
    noise."""
    return (
        f"True robot: {st['robot']} with deviations drawn (seed {st['seed']}) from "
        + ", ".join(f"{g} {v:g}" for g, v in st["truth_deviations"].items() if g in st["deviation_groups"])
        + (
            " (lengths in m, moduli relative), carrying the external wrench ("
            + ", ".join(f"{x:g}" for x in st["wrench"])
            + ") [N, N m] during every measurement, known to every model"
            if st.get("wrench") is not None and any(st["wrench"])
            else " (lengths in m, moduli relative)"
        )
        + f"; tracker sigma {st['tracker_sigma_m'] * 1e3:g} mm"
    )


def _headline_table(headline, columns):
    """The summary's headline section: its title and the table of the model, its parameter count,
    its prediction errors and ``columns``."""
    predict = ["predict_median_mm", "predict_p95_mm", "predict_max_mm", "predict_rms_mm"]
    return [
        "## Headline: validation error per model",
        "",
        md_table(headline, ["model", "parameters", *predict, *columns]),
    ]


def _point_mass_summary(st, headline, curve, enc, ident_lines, left_out, n_val, best):
    """The lines of a point mass's summary.md: the headline table, identifiability, learning curve,
    encoder."""
    return [
        "# Calibration study: a robot's parameters from simulated measurements",
        "",
        _truth_words(st)
        + f"; {st['n_train']} training samples in {st['calibration_box_m']}; validation: {n_val} poses over RW_C "
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
        *_headline_table(
            headline,
            [
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


def _platform_summary(st, robot, headline, ident_lines, vt, n_train, pretensioned):
    """The lines of a rigid platform's summary.md: the headline tables, identifiability, flagged
    poses."""
    fl = vt[vt["flagged"]]
    counts = vt["truth_taut_cables"].value_counts().sort_index()
    # heavy cables all pull: those hanging at about their own weight are not counted (equilibria's holding)
    held, short = (
        ("holding cables (taut, not hanging at about their own weight)", "holding")
        if robot.heavy
        else ("taut cables", "taut")
    )
    return [
        f"# Calibration study of a 6-DoF platform, {robot.name}: its parameters from simulated measurements",
        "",
        _truth_words(st)
        + f", {st['tracker_sigma_rad'] * 1e3:g} mrad; {n_train} training samples and {len(vt)} validation poses in "
        f"{st['pose_box_m']} m, tilted up to {st['tilt_rad']:g} rad, {st['command']} commands (every cable of the "
        f"nominal robot above {st['tension_margin_N']:g} N). Errors in mm and mrad.",
        "",
        *_headline_table(
            headline,
            [
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
        f"{EXACT} model (a second measurement campaign after the calibration): |predicted - measured| [mm] "
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
        f"True robot's {held} under the validation commands: "
        + ", ".join(f"{k}: {v}" for k, v in counts.items())
        + f"; second equilibrium found: {int(vt['second_equilibrium'].sum())}. Flagged (fewer than 6 {short} or a "
        f"second equilibrium): {len(fl)}"
        + (f" ({', '.join(fl['sample'])})" if len(fl) else "")
        + "; kept in every "
        "statistic but `unflagged_rms_mm`.",
        "",
    ]
