"""``check``: a robot's prediction (the physical equilibrium under the commanded lengths, through
the drums of a robot with winches) against measured samples, position and, for a 6-DoF platform,
orientation."""

from __future__ import annotations

import numpy as np

from cdpr.analyses.calibration.model import (
    DRUM_RANGE,
    drum_or_standard,
    point_mass_equilibria,
    realised_lengths,
    solve6,
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
    equilibrium (``solve6``) of a rigid platform, a point mass's ``point_mass_equilibria`` (the
    6-DoF equilibrium too when a pulley axis is not +z).

    Parameters
    ----------
    robot : Robot
    data : Data
        Commanded lengths (not encoder readings: their offsets are unknown) and measured poses.
    engine : {"compiled", "numpy"} or None
        Engine of the solves (None: ``solve.check_engine``'s default for a suspended point mass,
        ``engine6``'s for the 6-DoF equilibrium).

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
        res = solve6(robot, data.pose, L0, rotvec=data.rotvec, engine=engine)
    else:
        res = point_mass_equilibria(robot, data.pose, np.where(drum[:, None], L0, data.L), engine=engine)
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
