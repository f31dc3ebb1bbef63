"""The Hangprinter study (issue 40; ``cdpr calibrate study --study config/studies/hangprinter.yaml``):
a real machine's published auto-calibration sessions calibrated with models of increasing fidelity,
every model scored by K-fold cross-validation on identical folds beside the Hangprinter tool's own
published solution, and the firmware lines of the best model.

Per data set (``data_sets``: a motor-angle table, the tool's solution as a robot file and the
session's JSON with the hand-measured line lengths) and per model (``models``: a fit of ``estimate``
with ``model``, or a robot file scored as given, ``fixed: nominal | tool``), for every fold count of
``folds`` (an integer, or ``leave-one-out``): ``cdpr.analyses.calibration.cross_validate``. Each
fitted model is also fitted on all samples (``fit_motor``): its parameters, identifiability and the
anchor-to-origin line lengths against the taped ones. The best model of a session is the fitted one
with the lowest held-out position RMS at the last fold count; its robot goes to RepRapFirmware's
M669/M666 lines (``cdpr.robot_rrf.rrf_lines``).

Outputs (``cdpr.pipeline.results.CALIBRATION_OUTPUTS["hangprinter_study"]``), written atomically
through ``cdpr.io``: cv.csv, per_sample.csv, parameters.csv, fits.csv, line_lengths.csv,
firmware.g, summary.md and three figures (``cdpr.pipeline.plots.hangprinter``). Deterministic: the
same inputs give the same bytes (floats to six significant digits, no time stamps).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from cdpr import io
from cdpr.analyses import calibration as cal
from cdpr.analyses.calibration.motor import BUILDUP_PRIOR_SD
from cdpr.errors import CdprError, ConfigError
from cdpr.pipeline.calibration_files import read_study_file
from cdpr.pipeline.plots import hangprinter as figures
from cdpr.pipeline.results import rel_path
from cdpr.robot import load_robot, robot_from_dict
from cdpr.robot_rrf import rrf_lines
from cdpr.units import quantity

#: The study's outputs under its folder: ``cdpr.pipeline.results.CALIBRATION_OUTPUTS[RULE]``.
RULE = "hangprinter_study"
#: Keys of config/studies/hangprinter.yaml.
STUDY_KEYS = {"name", "robot", "priors", "folds", "data_sets", "models"}
#: Keys of one data set and of one model.
DATA_SET_KEYS = {"data", "source"}
#: Optional keys of a data set: the tool's solution, its own nominal robot (default the study's),
#: the models it runs (default all).
DATA_SET_OPTIONAL = {"tool", "robot", "models"}
MODEL_KEYS = {"label", "model", "estimate", "fixed", "buildup", "priors", "reference"}
#: What ``fixed`` names: the study's robot, or the data set's tool solution.
FIXED = ("nominal", "tool")
#: Floats of the tables: six significant digits (the fit ends where least_squares' tolerances hold;
#: the last bits differ between CPUs).
FORMAT = "%.6g"
#: The 2-D 95 % ellipse of a projected Gaussian: sqrt of the chi-square quantile, 2 degrees of freedom.
CHI2_95_2D = float(np.sqrt(-2.0 * np.log(0.05)))


def is_hangprinter_study(path):
    """True when the study file at ``path`` is a Hangprinter study (it has ``data_sets``).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    bool
    """
    try:
        data = read_study_file(path)  # a mapping, or ConfigError
    except (OSError, ConfigError):
        return False
    return "data_sets" in data


def load_hangprinter_study(path, check_files=True):
    """Read and check config/studies/hangprinter.yaml (one-line ConfigError per bad key).

    Parameters
    ----------
    path : str or Path
    check_files : bool
        Refuse a data set whose files do not exist (the Snakefile reads the study without it: a
        missing input is then the Hangprinter job's error, not every workflow's).

    Returns
    -------
    dict
        name, robot, priors (``parse_motor_priors`` values [m]), folds (list of int, or
        "leave-one-out"), data_sets (name -> data, tool, source), models (name -> label, model,
        estimate, fixed, buildup [m] or None, priors: the model's own prior sd by group [m]).
    """
    data = read_study_file(path)
    missing = sorted(STUDY_KEYS - set(data))
    if missing:
        raise ConfigError(
            path, missing[0], f"missing; a Hangprinter study needs {', '.join(sorted(STUDY_KEYS))}"
        )
    extra = sorted(set(data) - STUDY_KEYS)
    if extra:
        raise ConfigError(path, extra[0], f"unknown key; allowed: {', '.join(sorted(STUDY_KEYS))}")
    out = dict(data)
    pri = data["priors"]
    if not isinstance(pri, dict):
        raise ConfigError(path, "priors", "expected a mapping group: sd, e.g. anchors: 150mm")
    out["priors"] = cal.parse_motor_priors(
        ",".join(f"{k}={v}" for k, v in pri.items()), list(cal.MOTOR_GROUPS), f"{path}: priors"
    )
    folds = data["folds"]
    if not (isinstance(folds, list) and folds):
        raise ConfigError(path, "folds", "expected a list of fold counts (integers >= 2, or leave-one-out)")
    for k in folds:
        if not (k == "leave-one-out" or (isinstance(k, int) and not isinstance(k, bool) and k >= 2)):
            raise ConfigError(path, "folds", f"{k!r}: a fold count is an integer >= 2 or leave-one-out")
    sets = data["data_sets"]
    if not (isinstance(sets, dict) and sets):
        raise ConfigError(path, "data_sets", "expected a mapping name: {data, tool, source}")
    models = data["models"]
    if not (isinstance(models, dict) and models):
        raise ConfigError(path, "models", "expected a mapping name: {label, model, estimate | fixed}")
    out["models"] = {name: _model(path, name, m) for name, m in models.items()}
    if not any(m["fixed"] is None for m in out["models"].values()):
        raise ConfigError(path, "models", "no fitted model (every model is fixed): nothing to calibrate")
    out["data_sets"] = {name: _data_set(path, name, d, out, check_files) for name, d in sets.items()}
    return out


def _data_set(path, name, d, st, check_files):
    """One checked entry of ``data_sets``: data, source, tool (or None), robot, models (names)."""
    key = f"data_sets.{name}"
    allowed = DATA_SET_KEYS | DATA_SET_OPTIONAL
    if not isinstance(d, dict) or not DATA_SET_KEYS <= set(d) or set(d) - allowed:
        raise ConfigError(
            path,
            key,
            f"expected the keys {', '.join(sorted(DATA_SET_KEYS))} (and {', '.join(sorted(DATA_SET_OPTIONAL))})",
        )
    out = {
        "data": d["data"],
        "source": d["source"],
        "tool": d.get("tool"),
        "robot": d.get("robot", st["robot"]),
    }
    for k in ("data", "source", "tool", "robot"):
        if check_files and out[k] is not None and not Path(out[k]).is_file():
            raise ConfigError(path, f"{key}.{k}", f"{out[k]}: no such file")
    models = d.get("models", list(st["models"]))
    if not (isinstance(models, list) and models and all(m in st["models"] for m in models)):
        raise ConfigError(path, f"{key}.models", f"expected a list among {', '.join(st['models'])}")
    for m in models:
        if st["models"][m]["fixed"] == "tool" and out["tool"] is None:
            raise ConfigError(path, f"{key}.models", f"{m} scores the tool's solution: give {key}.tool")
    out["models"] = list(models)
    return out


def _model(path, name, m):
    """One checked entry of ``models``."""
    key = f"models.{name}"
    if not isinstance(m, dict):
        raise ConfigError(path, key, "expected a mapping {label, model, estimate | fixed}")
    extra = sorted(set(m) - MODEL_KEYS)
    if extra:
        raise ConfigError(path, f"{key}.{extra[0]}", f"unknown key; allowed: {', '.join(sorted(MODEL_KEYS))}")
    if m.get("model") not in cal.MOTOR_MODELS:
        raise ConfigError(path, f"{key}.model", f"{m.get('model')!r}; allowed: {', '.join(cal.MOTOR_MODELS)}")
    fixed, est = m.get("fixed"), m.get("estimate")
    if (fixed is None) == (est is None):
        raise ConfigError(path, key, "give either estimate (a fit) or fixed (a robot file scored as given)")
    if fixed is not None and fixed not in FIXED:
        raise ConfigError(path, f"{key}.fixed", f"{fixed!r}; allowed: {', '.join(FIXED)}")
    if est is not None:
        if not (isinstance(est, list) and est and all(g in cal.MOTOR_GROUPS for g in est)):
            raise ConfigError(path, f"{key}.estimate", f"expected a list among {', '.join(cal.MOTOR_GROUPS)}")
    buildup = m.get("buildup")
    if buildup is not None:
        if est is None or "spools" not in est:
            raise ConfigError(
                path, f"{key}.buildup", "the buildup factor's prior needs estimate: [.., spools]"
            )
        buildup = quantity(buildup, "m", path, f"{key}.buildup")
        if not buildup > 0:
            raise ConfigError(path, f"{key}.buildup", "the prior sd must be > 0")
    priors = m.get("priors")
    if priors is not None:
        if est is None or not isinstance(priors, dict):
            raise ConfigError(path, f"{key}.priors", "expected a mapping group: sd for a fitted model")
        priors = cal.parse_motor_priors(
            ",".join(f"{k}={v}" for k, v in priors.items()), list(est), f"{path}: {key}.priors"
        )
        priors = {g: v for g, v in priors.items() if g in m["priors"]}
    return {
        "label": str(m.get("label", name)),
        "model": m["model"],
        "estimate": list(est) if est else None,
        "fixed": fixed,
        "buildup": buildup,
        "priors": priors or {},
        # a comparison (another tool's solution or model), not a candidate for the best model
        "reference": bool(m.get("reference", fixed == "tool")),
    }


def _fold_count(k, n):
    return n if k == "leave-one-out" else int(k)


def _mm(x):
    return np.nan if x is None else 1e3 * float(x)


def run_hangprinter_study(study_path, out):
    """Run the Hangprinter study of ``study_path`` into the folder ``out`` (module docstring).

    Parameters
    ----------
    study_path : str or Path
        config/studies/hangprinter.yaml.
    out : str or Path
        The results folder (results/hangprinter).

    Returns
    -------
    dict
        cv (the cross-validation table), best (data set -> model name), elapsed_s, summary (the
        path of summary.md).
    """
    t0 = time.time()
    st = load_hangprinter_study(study_path)
    out = Path(out)
    cv_rows, sample_rows, par_rows, fit_rows, len_rows, ellipses = [], [], [], [], [], []
    sessions = {}
    for ds, spec in st["data_sets"].items():
        robot = load_robot(spec["robot"])
        data = cal.read_motor_data(spec["data"], robot)
        tool = None if spec["tool"] is None else load_robot(spec["tool"])
        taped = _taped(spec["source"], robot.m)
        sessions[ds] = {
            "n": len(data.sample),
            "with_position": int(data.has_pose.sum()),
            "with_forces": int(data.has_force.sum()),
            "exact": any(st["models"][n]["model"] == "exact" for n in spec["models"]),
            "taped": bool(np.isfinite(taped).any()),
        }
        for name in spec["models"]:
            mod = st["models"][name]
            fixed_robot = {"nominal": robot, "tool": tool}.get(mod["fixed"])
            priors = None if fixed_robot is not None else _priors(st, mod)
            for k in st["folds"]:
                K = _fold_count(k, len(data.sample))
                if fixed_robot is not None:
                    res = cal.cross_validate(
                        fixed_robot, data, [], None, model=mod["model"], folds=K, fixed=True
                    )
                else:
                    res = cross_validate_model(st, name, robot, data, K)
                cv_rows.append(_cv_row(ds, name, mod, K, k, res))
                sample_rows += _sample_rows(ds, name, K, res, data)
            if fixed_robot is not None:
                sm = cal.SpoolModel.of(fixed_robot)
                len_rows += _lengths(ds, name, sm.A, None, None, taped)
                ellipses.append({"data_set": ds, "model": name, "A": sm.A, "cov": None})
                continue
            fit = cal.fit_motor(robot, data, mod["estimate"], priors, mod["model"])
            par_rows += _parameter_rows(ds, name, fit)
            s = fit.summary()
            fit_rows.append(
                {
                    "data_set": ds,
                    "model": name,
                    "parameters": s["n_parameters"],
                    "rank": s["rank"],
                    "line_rms_mm": _mm(s["line_rms_m"]),
                    "position_residual_rms_mm": _mm(s["residual_rms_m"]),
                    "unidentified": "; ".join(s["unidentified"]),
                    "gauge": s["gauge"],
                }
            )
            covA = _anchor_covariance(fit, robot.m)
            len_rows += _lengths(ds, name, fit.spool_model.A, covA, fit, taped)
            ellipses.append({"data_set": ds, "model": name, "A": fit.spool_model.A, "cov": covA, "fit": fit})
    cv = pd.DataFrame(cv_rows)
    samples = pd.DataFrame(sample_rows)
    best = _best(cv, st)
    firmware = _firmware(st, best, ellipses, cv)
    _write_csv(cv, out / rel_path(RULE, "cv"))
    _write_csv(samples, out / rel_path(RULE, "per_sample"))
    _write_csv(pd.DataFrame(par_rows), out / rel_path(RULE, "parameters"))
    _write_csv(pd.DataFrame(fit_rows), out / rel_path(RULE, "fits"))
    _write_csv(pd.DataFrame(len_rows), out / rel_path(RULE, "line_lengths"))
    io.write_text(firmware, out / rel_path(RULE, "firmware"))
    nominal = {ds: cal.SpoolModel.of(load_robot(spec["robot"])).A for ds, spec in st["data_sets"].items()}
    figures.heldout_errors(cv, samples, st, out / rel_path(RULE, "errors_figure"))
    figures.anchor_ellipses(ellipses, nominal, st, CHI2_95_2D, out / rel_path(RULE, "anchors_figure"))
    figures.residuals_against_force(samples, st, out / rel_path(RULE, "force_figure"))
    _write_summary(
        out, st, study_path, cv, pd.DataFrame(fit_rows), pd.DataFrame(len_rows), best, firmware, sessions
    )
    return {
        "cv": cv,
        "best": best,
        "elapsed_s": time.time() - t0,
        "summary": out / rel_path(RULE, "summary"),
    }


def cross_validate_model(st, name, robot, data, folds):
    """K-fold cross-validation of the study's fitted model ``name`` from ``robot`` (its groups,
    model and priors: the study's with the model's own), as the study runs it; reused by
    benchmarks/hangprinter_rough_start.py to re-fit a model from another start.

    Parameters
    ----------
    st : dict
        ``load_hangprinter_study``.
    name : str
        A fitted model of ``st["models"]`` (not ``fixed``).
    robot : Robot
        The nominal robot: the prior mean and the fit's start.
    data : MotorData
    folds : int
        K.

    Returns
    -------
    dict
        ``cdpr.analyses.calibration.cross_validate``'s.
    """
    mod = st["models"][name]
    if mod["fixed"] is not None:
        raise CdprError(f"models.{name}: a fixed model ({mod['fixed']}) is scored as given, not re-fitted")
    return cal.cross_validate(robot, data, mod["estimate"], _priors(st, mod), model=mod["model"], folds=folds)


def _priors(st, mod):
    """The prior sd of a fitted model: the study's, with the model's own (``priors``, ``buildup``)."""
    p = {**st["priors"], **mod["priors"]}
    if mod["buildup"] is not None:
        p["buildup"] = mod["buildup"]
    return p


def _taped(source, m):
    """The hand-measured line lengths at the origin [mm] of a session's JSON (NaN where absent)."""
    try:
        doc = json.loads(Path(source).read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise CdprError(f"{source}: cannot read the data set's JSON ({exc})") from None
    v = doc.get("hand_line_lengths_at_origin_mm")
    if v is None:
        return np.full(m, np.nan)
    if not (isinstance(v, list) and len(v) == m):
        raise CdprError(f"{source}: hand_line_lengths_at_origin_mm: expected {m} lengths in mm")
    return np.array(v, dtype=float)


def _cv_row(ds, name, mod, K, k, res):
    errs = [r["error_m"] for r in res["per_sample"] if r["error_m"] is not None]
    return {
        "data_set": ds,
        "model": name,
        "label": mod["label"],
        "fit": "fixed" if mod["fixed"] else f"{mod['model']}: {','.join(mod['estimate'])}",
        "folds": K,
        "leave_one_out": k == "leave-one-out",
        "heldout_with_position": res["heldout_with_position"],
        "heldout_position_rms_mm": _mm(res["heldout_position_rms_m"]),
        "heldout_position_median_mm": _mm(res["heldout_position_median_m"]),
        "heldout_position_max_mm": 1e3 * max(errs) if errs else np.nan,
        "heldout_line_rms_mm": _mm(res["heldout_line_rms_m"]),
        "train_line_rms_mm": _mm(res["train_rms_m"]),
    }


def _sample_rows(ds, name, K, res, data):
    rows = []
    m = data.motor_deg.shape[1]
    for k, r in enumerate(res["per_sample"]):
        row = {
            "data_set": ds,
            "model": name,
            "folds": K,
            "sample": r["sample"],
            "fold": r["fold"],
            "status": r["status"],
            "x_m": np.nan if r["x_m"] is None else r["x_m"],
            "y_m": np.nan if r["y_m"] is None else r["y_m"],
            "z_m": np.nan if r["z_m"] is None else r["z_m"],
            "error_mm": _mm(r["error_m"]),
            "line_rms_mm": _mm(r["line_rms_m"]),
        }
        lr = r["line_residual_m"]
        for i in range(m):
            row[f"line_residual_mm_{i + 1}"] = np.nan if lr is None else 1e3 * lr[i]
        for i in range(m):
            row[f"force_N_{i + 1}"] = data.force[k, i] if data.has_force[k] else np.nan
        rows.append(row)
    return rows


def _parameter_rows(ds, name, fit):
    return [
        {
            "data_set": ds,
            "model": name,
            "name": p["name"],
            "nominal": p["nominal"],
            "estimate": p["estimate"],
            "sd": p["sd"],
            "prior_sd": p["prior_sd"],
            "identified": p["identified"],
        }
        for p in fit.summary()["parameters"]
    ]


def _anchor_covariance(fit, m):
    """The posterior covariance of each anchor (m, 3, 3) [m^2], or None without the anchors group."""
    names = list(fit.names)
    if "A_1_x" not in names:
        return None
    C = fit.covariance
    out = np.empty((m, 3, 3))
    for i in range(m):
        ix = [names.index(f"A_{i + 1}_{a}") for a in "xyz"]
        out[i] = C[np.ix_(ix, ix)]
    return out


def _lengths(ds, name, A, covA, fit, taped):
    rows = []
    for i in range(len(A)):
        L = float(np.linalg.norm(A[i]))
        sd = np.nan
        if covA is not None:
            u = A[i] / L
            sd = float(np.sqrt(u @ covA[i] @ u))
        rows.append(
            {
                "data_set": ds,
                "model": name,
                "cable": i + 1,
                "anchor": "ABCDEFGH"[i] if i < 8 else str(i + 1),
                "length_mm": 1e3 * L,
                "taped_mm": taped[i],
                "difference_mm": 1e3 * L - taped[i],
                "sd_mm": 1e3 * sd,
            }
        )
    return rows


def _best(cv, st):
    """Data set -> the fitted model (not a ``reference``) with the lowest held-out position RMS at the
    last fold count; a data set without a held-out measured position has none (no firmware lines)."""
    fitted = [n for n, m in st["models"].items() if m["fixed"] is None and not m["reference"]]
    out = {}
    for ds in st["data_sets"]:
        last = cv[(cv.data_set == ds) & cv.model.isin(fitted)]
        last = last[last.folds == last.folds.iloc[-1]] if len(last) else last
        scored = last.dropna(subset=["heldout_position_rms_mm"])
        if not len(scored):
            continue
        out[ds] = str(scored.sort_values(["heldout_position_rms_mm", "model"], kind="stable").model.iloc[0])
    return out


def _firmware(st, best, ellipses, cv):
    """RepRapFirmware's M669/M666 lines of each session's best model (``rrf_lines``), commented."""
    text = [
        "; RepRapFirmware lines (config.g) of the best model of each session of the Hangprinter study",
        f"; ({st['name']}; written by cdpr calibrate study, cdpr.pipeline.hangprinter; nominal robot {st['robot']})",
    ]
    for ds, name in best.items():
        fit = next(e["fit"] for e in ellipses if e["data_set"] == ds and e["model"] == name)
        doc = yaml.safe_load(Path(st["data_sets"][ds]["robot"]).read_text(encoding="utf-8"))
        robot = robot_from_dict(cal.motor_robot_mapping(doc, fit.spool_model), source=f"{ds}: {name}")
        lines, warnings = rrf_lines(robot)
        row = cv[(cv.data_set == ds) & (cv.model == name)].iloc[-1]
        text += [
            "",
            f"; {ds}: {st['models'][name]['label']} ({name}), fitted on all samples; held-out position RMS "
            f"{row.heldout_position_rms_mm:.3g} mm with {int(row.folds)} folds",
            *[f"; warning: {w}" for w in warnings],
            *lines,
        ]
    for ds in st["data_sets"]:
        if ds not in best:
            text += ["", f"; {ds}: no held-out measured position, so no best model: no firmware lines"]
    return "\n".join(text) + "\n"


def _write_csv(df, path):
    io.atomic(path, lambda tmp: df.to_csv(tmp, index=False, float_format=FORMAT, lineterminator="\n"))


def _f(x, fmt="{:.3g}"):
    return "–" if x is None or x != x else fmt.format(x)


def headline_table(cv, ds, folds):
    """The markdown table of one session: per model the held-out position RMS and median at each
    fold count, the max, the held-out and training line RMS at the last fold count [mm].

    Parameters
    ----------
    cv : DataFrame
        cv.csv.
    ds : str
        Data set.
    folds : list
        The study's fold counts (as given: integers, leave-one-out).

    Returns
    -------
    str
    """
    d = cv[cv.data_set == ds]
    ks = list(dict.fromkeys(d.folds))
    head = ["model"]
    for K, k in zip(ks, folds):
        tag = f"K = {K}" + (" (LOO)" if k == "leave-one-out" else "")
        head += [f"{tag}: RMS", "median"]
    head += ["max", "held-out line RMS", "train line RMS"]
    lines = [io.md_row(head), "|" + "---|" * len(head)]
    for name in dict.fromkeys(d.model):
        rows = d[d.model == name]
        cells = [str(rows.label.iloc[0])]
        for K in ks:
            r = rows[rows.folds == K].iloc[0]
            cells += [_f(r.heldout_position_rms_mm), _f(r.heldout_position_median_mm)]
        r = rows[rows.folds == ks[-1]].iloc[0]
        cells += [_f(r.heldout_position_max_mm), _f(r.heldout_line_rms_mm), _f(r.train_line_rms_mm)]
        lines.append(io.md_row(cells))
    return "\n".join(lines) + "\n"


def _verdict(cv, ds, best, st):
    """Sentences comparing the best cdpr model with the tool's solution on one session, from the numbers."""
    refs = [n for n in st["data_sets"][ds]["models"] if st["models"][n]["reference"]]
    if best is None:
        return []
    d = cv[cv.data_set == ds]
    K = d.folds.iloc[-1]
    b = d[(d.model == best) & (d.folds == K)].iloc[0]
    out = []
    for ref in refs:
        t = d[(d.model == ref) & (d.folds == K)].iloc[0]
        for what, col in (("RMS", "heldout_position_rms_mm"), ("median", "heldout_position_median_mm")):
            x, y = b[col], t[col]
            word = "lower (better) than" if x < y else ("equal to" if x == y else "**higher (worse) than**")
            out.append(
                f"- {ds}, {K} folds: the best cdpr model ({best}) has a held-out position {what} of {x:.3g} mm, "
                f"{word} the {y:.3g} mm of {st['models'][ref]['label']} ({ref})."
            )
    return out


def _write_summary(out, st, study_path, cv, fits, lengths, best, firmware, sessions):
    """results/hangprinter/summary.md."""
    text = [
        "# Hangprinter study: a real machine calibrated from its own published sessions",
        "",
        f"Study {study_path}; nominal robot {st['robot']} (the rough tape measurement: the prior mean); "
        "priors "
        + ", ".join(f"{g} {v * 1e3:g} mm" for g, v in st["priors"].items())
        + " (the buildup factor "
        f"{BUILDUP_PRIOR_SD * 1e3:g} mm unless a model says otherwise). Every model is scored by K-fold "
        "cross-validation on identical folds (row i in fold i mod K): fitted on the other folds, each held-out "
        "sample's position solved from its readings (and forces in the exact model) against the measured one. "
        "Errors in mm.",
        "",
    ]
    for ds, info in sessions.items():
        text += [
            f"## {ds}",
            "",
            f"{info['n']} samples, {info['with_position']} with a measured position, {info['with_forces']} with "
            "line forces"
            + (
                " (no forces: the exact model is the rigid one, the same numbers)"
                if not info["with_forces"] and info["exact"]
                else ""
            )
            + "."
            + (
                " No measured position: only the line residuals are held out, and the frame's rotation about "
                "the origin is not seen by the data (fixed by the prior alone; see the weak directions below)."
                if not info["with_position"]
                else ""
            ),
            "",
            headline_table(cv, ds, st["folds"]),
            *_verdict(cv, ds, best.get(ds), st),
            "",
            *(
                [
                    "Line lengths at the origin |A_i| against the taped ones (difference [mm], posterior sd "
                    "in brackets):",
                    "",
                    _lengths_table(lengths[lengths.data_set == ds], st),
                ]
                if info["taped"]
                else ["No taped line lengths in this session (the anchors: anchors.png, parameters.csv).", ""]
            ),
            "Identifiability of each fit on all samples:",
            "",
            *[
                f"- {r.model}: {r.parameters} parameters, rank {r.rank}; line RMS {_f(r.line_rms_mm)} mm, "
                f"position residual RMS {_f(r.position_residual_rms_mm)} mm"
                + (f"; weak: {r.unidentified}" if r.unidentified else "")
                for r in fits[fits.data_set == ds].itertuples()
            ],
            "",
        ]
    text += [
        "## What this shows, and what it does not",
        "",
        "- The tool's solution was fitted by the tool to *all* samples of its session, held-out ones "
        "included: its numbers are training errors, cdpr's are held-out. The fair comparison is the tool's "
        "model re-fitted on each fold's training samples (a reference model of the study where it has one: "
        "cdpr's re-implementation of that model, rigid lines, anchors and spool radii with the one buildup "
        "factor fixed; not the tool's own code, SLSQP and gauge A_x = D_x = D_y = 0).",
        "- The gear ratio (`gear`) is not a group: a motor angle enters the spool model only through "
        "phi = theta L / H in s = r0 phi - O Q phi^2 / 4, so L / H scaled by c with r0 by 1 / c and Q by "
        "1 / c^2 gives the same line: motor angles cannot see it.",
        "- Other sessions of these machines (the issue's held-out target) are not in the repository.",
        "",
        "## Firmware lines of the best model (firmware.g)",
        "",
        "```",
        firmware.rstrip("\n"),
        "```",
        "",
    ]
    io.write_text("\n".join(text), out / rel_path(RULE, "summary"))


def _lengths_table(d, st):
    anchors = list(dict.fromkeys(d.anchor))
    head = ["model", *anchors]
    lines = [io.md_row(head), "|" + "---|" * len(head)]
    for name in dict.fromkeys(d.model):
        r = d[d.model == name]
        cells = [st["models"][name]["label"]]
        for a in anchors:
            x = r[r.anchor == a].iloc[0]
            cells.append(_f(x.difference_mm, "{:.1f}") + ("" if x.sd_mm != x.sd_mm else f" ({x.sd_mm:.0f})"))
        lines.append(io.md_row(cells))
    return "\n".join(lines) + "\n"
