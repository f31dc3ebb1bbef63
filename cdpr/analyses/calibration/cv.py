"""K-fold cross-validation of a motor-angle calibration (``cross_validate``, ``cdpr calibrate cv``):
fold k holds the samples whose 0-based row index i has i mod K = k (``fold_of``); each fold is
fitted on the others (``estimator.fit_motor``) and its held-out positions solved from their readings
(``prediction.predict_samples``) against the measured ones."""

from __future__ import annotations

import dataclasses

import numpy as np

from cdpr.analyses.calibration.estimator import fit_motor
from cdpr.analyses.calibration.motor import (
    SIGMA_LINE_DEFAULT,
    SpoolModel,
    line_residuals,
    reference_forces,
    solve_positions,
    stretch_factors,
)
from cdpr.analyses.calibration.prediction import predict_samples
from cdpr.errors import CdprError


def fold_of(n, folds):
    """Fold of each sample: the 0-based row index i is in fold i mod K.

    Parameters
    ----------
    n : int
        Samples.
    folds : int
        K, 2 <= K <= n (K = n: leave-one-out).

    Returns
    -------
    ndarray (n,) of int
    """
    if not (2 <= folds <= n):
        raise CdprError(
            f"--folds {folds}: needs 2 <= K <= {n} (the number of samples; K = {n} is leave-one-out)"
        )
    return np.arange(n) % folds


def cross_validate(
    robot, data, groups=(), priors=None, model="exact", folds=5, fixed=False, sigma_line=SIGMA_LINE_DEFAULT
):
    """K-fold cross-validation of a motor-angle calibration (``cdpr calibrate cv``).

    Fold k holds the samples whose 0-based row index i has i mod K = k. For each fold: fit on the
    other folds (``fit_motor``; with ``fixed`` the robot as given), solve each held-out sample's
    position from its readings (``predict_samples``) and compare it with the measured one where
    measured; the held-out line RMS is that of the redundant line equations at the solved position.

    Parameters
    ----------
    robot : Robot
    data : MotorData
    groups : list of str
        Estimated groups (ignored with ``fixed``).
    priors : dict, optional
    model : {"exact", "standard"}
    folds : int
    fixed : bool
        Score ``robot`` without fitting.
    sigma_line : float [m]

    Returns
    -------
    dict
        folds (list: fold, samples, heldout_position_rms_m, heldout_position_median_m,
        heldout_line_rms_m, train_rms_m), the same four overall, per_sample (each held-out
        sample's ``predict_samples`` row with its fold and its m line residuals
        ``line_residual_m``), n_folds, model, estimate, fixed, gauge, warnings.
    """
    n = len(data.sample)
    fold = fold_of(n, folds)
    t_ref, warn = reference_forces(data, model)  # the session's reference, from all samples
    per_sample, out_folds, train_sq = [], [], []
    gauge = None
    for kf in range(folds):
        held = np.flatnonzero(fold == kf)
        train = np.flatnonzero(fold != kf)
        tdata = data.subset(train)
        if fixed:
            sm = SpoolModel.of(robot)
            f, g = stretch_factors(model, tdata, t_ref, sm.K)
            _, trms = solve_positions(sm, tdata, f, g)
            tres = trms[np.isfinite(trms)]
            train_rms = float(np.sqrt(np.mean(tres**2)))
            train_sq.append(tres**2)
        else:
            cal = fit_motor(robot, tdata, groups, priors, model, sigma_line)
            sm = dataclasses.replace(cal.spool_model)
            train_rms = float(np.sqrt(np.mean(cal.line_residual**2)))
            train_sq.append(np.mean(cal.line_residual**2, axis=1))
            gauge = cal.gauge
        hdata = data.subset(held)
        rows = predict_samples(sm, hdata, model, t_ref)
        lres = _line_residuals(sm, hdata, rows, model, t_ref)
        for r, lr in zip(rows, lres):
            r["fold"] = kf
            r["line_residual_m"] = lr
        per_sample += rows
        out_folds.append(
            {
                "fold": kf,
                "samples": [str(s) for s in data.sample[held]],
                **_scores(rows),
                "train_rms_m": train_rms,
            }
        )
    order = np.argsort(np.concatenate([np.flatnonzero(fold == kf) for kf in range(folds)]), kind="stable")
    per_sample = [per_sample[i] for i in order]
    tsq = np.concatenate(train_sq)
    return {
        "folds": out_folds,
        **_scores(per_sample),
        "train_rms_m": float(np.sqrt(np.mean(tsq))),
        "per_sample": per_sample,
        "n_folds": folds,
        "model": model,
        "estimate": [] if fixed else list(groups),
        "fixed": bool(fixed),
        "gauge": gauge,
        "data_warnings": [w for w in (warn,) if w],
    }


def _line_residuals(sm, data, rows, model, t_ref):
    """Each held-out sample's m line residuals [m] at its solved position (``motor.line_residuals``;
    None where it has no solution)."""
    f, g = stretch_factors(model, data, t_ref, sm.K)
    ok = np.array([r["x_m"] is not None for r in rows])
    P = np.array(
        [[r["x_m"], r["y_m"], r["z_m"]] if o else [np.nan] * 3 for r, o in zip(rows, ok)], dtype=float
    )
    res = line_residuals(sm, data, P, f, g)
    return [[float(x) for x in res[k]] if ok[k] else None for k in range(len(rows))]


def _scores(rows):
    e = np.array([r["error_m"] for r in rows if r["error_m"] is not None])
    lr = np.array([r["line_rms_m"] for r in rows if r["line_rms_m"] is not None])
    return {
        "heldout_position_rms_m": float(np.sqrt(np.mean(e**2))) if len(e) else None,
        "heldout_position_median_m": float(np.median(e)) if len(e) else None,
        "heldout_line_rms_m": float(np.sqrt(np.mean(lr**2))) if len(lr) else None,
        "heldout_with_position": len(e),
    }
