"""``check``: a robot's prediction (the physical equilibrium under the commanded lengths, through
the drums of a robot with winches) against measured samples, position and, for a 6-DoF platform,
orientation. ``check_motor``: a spool robot's positions solved from its motor angles
(``predict_samples``, ``cdpr.analyses.calibration.motor``) against the measured ones."""

from __future__ import annotations

import numpy as np

from cdpr.analyses.calibration.model import (
    DRUM_RANGE,
    drum_or_standard,
    equilibria,
    realised_lengths,
)
from cdpr.analyses.calibration.motor import (
    SpoolModel,
    reference_forces,
    solve_positions,
    stretch_factors,
)
from cdpr.analyses.calibration.problem import (
    orientation_residual,
)
from cdpr.errors import CdprError
from cdpr.models.platform import rotation_matrix
from cdpr.parameters import (
    is_spatial,
)


def check(robot, data, engine=None):
    """The robot's prediction (physical equilibrium under the commanded lengths, through the drums
    of a robot with winches, started at the measured pose) against every sample: the 6-DoF
    equilibrium (``equilibria``) of every robot.

    Parameters
    ----------
    robot : Robot
    data : Data
        Commanded lengths (not encoder readings: their offsets are unknown) and measured poses.
    engine : {"compiled", "numpy"} or None
        Engine of the solves (None: ``equilibrium_engine``'s default, ``solve.check_engine``'s:
        compiled).

    Returns
    -------
    dict
        n (samples compared), rms_m (RMS over samples of |P* - y|), max_m, median_m, rms_rad and
        max_rad (None for a point mass; for a 6-DoF platform the RMS and largest angle of
        R_meas R*ᵀ), samples: list of {sample, status, error_m} (error None where the equilibrium is
        not ok; with error_rad for a 6-DoF platform).
    """
    if data.encoder:
        raise CdprError(f"{data.source}: check needs commanded lengths L1..L{robot.m}, not encoder readings")
    spatial = is_spatial(robot)
    L0 = realised_lengths(robot, data.L)
    drum = np.isfinite(L0).all(axis=1)
    if spatial:
        L0 = drum_or_standard(robot, L0, drum, data.pose, np.nan_to_num(data.rotvec))
    else:
        L0 = np.where(drum[:, None], L0, data.L)
    res = equilibria(robot, data.pose, L0, rotvec=data.rotvec if spatial else None, engine=engine)
    res["status"] = np.where(drum, res["status"], DRUM_RANGE)
    ok = res["status"] == "ok"
    err = np.linalg.norm(res["P_s"] - data.pose, axis=1)
    e = err[ok]
    out = {
        "n": int(ok.sum()),
        "rms_m": float(np.sqrt(np.mean(e**2))) if len(e) else None,
        "max_m": float(e.max()) if len(e) else None,
        "median_m": float(np.median(e)) if len(e) else None,
        "rms_rad": None,
        "max_rad": None,
        "samples": [
            {"sample": str(s), "status": str(st), "error_m": float(x) if o else None}
            for s, st, x, o in zip(data.sample, res["status"], err, ok)
        ],
    }
    if spatial:  # the orientation error angle |log(R_meas R*ᵀ)|
        ang = np.linalg.norm(orientation_residual(rotation_matrix(data.rotvec), res["R_s"]), axis=1)
        a = ang[ok]
        out["rms_rad"] = float(np.sqrt(np.mean(a**2))) if len(a) else None
        out["max_rad"] = float(a.max()) if len(a) else None
        for sample, y, o in zip(out["samples"], ang, ok):
            sample["error_rad"] = float(y) if o else None
    return out


def predict_samples(sm, data, model, t_ref):
    """Positions solved from each sample's readings (and forces in the exact model), their line RMS
    and, where measured, the position error.

    Parameters
    ----------
    sm : SpoolModel
    data : MotorData
    model : {"exact", "standard"}
    t_ref : ndarray (m,) [N]
        ``reference_forces``.

    Returns
    -------
    list of dict
        One per sample: sample, x_m, y_m, z_m (solved from the anchors' centroid, never from the
        measured position), error_m (None without a measured position), line_rms_m, status.
    """
    f, g = stretch_factors(model, data, t_ref, sm.K)
    # from the anchors' centroid, never from the measured position (a held-out sample's is the answer)
    P, rms = solve_positions(sm, data, f, g)
    out = []
    for k in range(len(data.sample)):
        ok = bool(np.isfinite(P[k]).all() and np.isfinite(rms[k]))
        err = float(np.linalg.norm(P[k] - data.pose[k])) if (ok and data.has_pose[k]) else None
        st = "ok" if ok else "no solution"
        if ok and model == "exact" and not data.has_force[k]:
            st = "no forces: rigid lines"
        out.append(
            {
                "sample": str(data.sample[k]),
                "x_m": float(P[k, 0]) if ok else None,
                "y_m": float(P[k, 1]) if ok else None,
                "z_m": float(P[k, 2]) if ok else None,
                "error_m": err,
                "line_rms_m": float(rms[k]) if ok else None,
                "status": st,
            }
        )
    return out


def check_motor(robot, data, model="exact"):
    """``cdpr calibrate check`` on motor-angle data: each sample's position solved from its readings
    against the measured one.

    Parameters
    ----------
    robot : Robot
    data : MotorData
    model : {"exact", "standard"}

    Returns
    -------
    dict
        n (samples with a measured position and a solution), rms_m, max_m, median_m, line_rms_m,
        model, samples (``predict_samples``).
    """
    t_ref, warn = reference_forces(data, model)
    rows = predict_samples(SpoolModel.of(robot), data, model, t_ref)
    e = np.array([r["error_m"] for r in rows if r["error_m"] is not None])
    lr = np.array([r["line_rms_m"] for r in rows if r["line_rms_m"] is not None])
    return {
        "n": len(e),
        "rms_m": float(np.sqrt(np.mean(e**2))) if len(e) else None,
        "max_m": float(e.max()) if len(e) else None,
        "median_m": float(np.median(e)) if len(e) else None,
        "line_rms_m": float(np.sqrt(np.mean(lr**2))) if len(lr) else None,
        "model": model,
        "samples": rows,
        **({"data_warnings": [warn]} if warn else {}),
    }
