"""The result of a calibration (``Calibration``): estimate, posterior, identifiability, the
per-sample table, the JSON summary, and the calibrated robot as robot-file text
(``robot_file_text``; ``cdpr.pipeline.calibration_files.robot_file_text`` writes it)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
import yaml

from cdpr.analyses.calibration.model import (
    STANDARD_STIFFENING,
)
from cdpr.parameters import (
    calibrated_robot,
    calibration_groups,
    is_spatial,
    robot_size,
)
from cdpr.robot import WINCH_KEYS


@dataclasses.dataclass
class Calibration:
    """The result of ``fit``: estimate, posterior, identifiability and the per-sample table."""

    robot: object
    base: object
    model: str
    index: np.ndarray
    names: list
    nominal: np.ndarray
    estimate: np.ndarray
    prior_sd: np.ndarray
    ident: dict
    theta: np.ndarray
    table: pd.DataFrame
    source: str
    cost: float
    nfev: int

    @property
    def sd(self):
        """Posterior sd [Pa, m, kg] (Gauss-Newton at the MAP)."""
        return self.ident["ratio"] * self.prior_sd

    @property
    def covariance(self):
        return self.ident["cov_scaled"] * np.outer(self.prior_sd, self.prior_sd)

    @property
    def correlation(self):
        c = self.ident["cov_scaled"]
        d = np.sqrt(np.diag(c))
        return c / np.outer(d, d)

    def calibrated_robot(self):
        """The robot at the estimate (the model's pulleys; the standard model's E back to the file's)."""
        m = self.robot.m
        th = self.theta[: robot_size(self.base)].copy()
        if self.model in ("standard", "rigid"):
            th[:m] /= STANDARD_STIFFENING
        return calibrated_robot(self.base, th)

    def fitted_model(self):
        """The model at the estimate, as the fit saw it (rigid models keep their stiff cables): what
        predicts and compensates."""
        return calibrated_robot(self.base, self.theta)

    @property
    def offsets(self):
        return self.theta[robot_size(self.base) :]

    def parameter_table(self):
        """nominal, estimate, sd, 95 % interval, prior sd, ratio and label per parameter (SI)."""
        groups, cables = calibration_groups(self.base)
        return pd.DataFrame(
            {
                "name": self.names,
                "group": [groups[k] for k in self.index],
                "cable": pd.array([cables[k] for k in self.index], dtype="Int64"),
                "nominal": self.nominal,
                "estimate": self.estimate,
                "sd": self.sd,
                "lo95": self.estimate - 1.959964 * self.sd,
                "hi95": self.estimate + 1.959964 * self.sd,
                "prior_sd": self.prior_sd,
                "ratio": self.ident["ratio"],
                "identified": self.ident["labels"],
            }
        )

    def summary(self):
        """The JSON of ``cdpr calibrate fit --json`` (issue 18's keys; SI units)."""
        pt = self.parameter_table()
        used = self.table["status"] == "used"
        res = self.table.loc[used, "residual_after_m"].to_numpy()
        res = res[np.isfinite(res)]
        rad = None
        if "residual_after_rad" in self.table:
            ang = self.table.loc[used, "residual_after_rad"].to_numpy()
            ang = ang[np.isfinite(ang)]
            rad = float(np.sqrt(np.mean(ang**2))) if len(ang) else None
        return {
            "parameters": [
                {
                    "name": r.name,
                    "group": r.group,
                    "cable": None if pd.isna(r.cable) else int(r.cable),
                    "nominal": float(r.nominal),
                    "estimate": float(r.estimate),
                    "sd": float(r.sd),
                    "prior_sd": float(r.prior_sd),
                    "identified": str(r.identified),
                }
                for r in pt.itertuples()
            ],
            "n_parameters": len(self.index),
            "rank": self.ident["rank"],
            "condition": _json_float(self.ident["condition"]),
            "singular_values": [float(s) for s in self.ident["singular_values"]],
            "unidentified": list(self.ident["unidentified"]),
            "residual_rms_m": float(np.sqrt(np.mean(res**2))) if len(res) else None,
            "residual_rms_rad": rad,
            "samples_used": int(used.sum()),
            "samples_left_out": int((~used).sum()),
        }


def _winch_mapping(w):
    """A cable's WinchParams as the robot file's ``winch:`` keys (plain SI numbers)."""
    return {key: float(getattr(w, attr)) for key, (attr, _unit) in WINCH_KEYS.items()}


def _json_float(x):
    return float(x) if math.isfinite(x) else None


def robot_file_text(cal, data_source, when):
    """The calibrated robot as robot-file text (``cdpr.pipeline.calibration_files.robot_file_text``
    writes it): the input's schema, per-cable plain SI values, and a header saying from which
    data, with which model, and when (offsets, which are not robot parameters, in the header).

    Parameters
    ----------
    cal : Calibration
    data_source : str
        The data file, named in the header.
    when : datetime.datetime
        The time of the calibration, named in the header (ISO 8601, to the second).

    Returns
    -------
    str
        YAML with a comment header, ending in a newline.
    """

    rob = cal.calibrated_robot()
    header = [
        f"# {rob.name} calibrated by cdpr calibrate fit ({cal.model} model) from {data_source}",
        f"# on {when.isoformat(timespec='seconds')}; nominal robot: {cal.robot.source}",
        f"# estimated: {', '.join(cal.names)}",
    ]
    spatial = is_spatial(rob)
    if "offsets" in {calibration_groups(rob)[0][k] for k in cal.index}:
        header.append("# encoder offsets [m]: " + ", ".join(f"{o:.9g}" for o in cal.offsets))
    cables = []
    for c in rob.cables:
        pul = {"kind": c.pulley.kind, "h_m": float(c.pulley.h), "r_p_m": float(c.pulley.r_p)}
        # the pulley's swivel axis and zero (defaults left out), a point mass's as a platform's
        if tuple(c.pulley.axis) != (0.0, 0.0, 1.0):
            pul["axis"] = [float(x) for x in c.pulley.axis]
        if c.pulley.zero is not None:
            pul["zero"] = [float(x) for x in c.pulley.zero]
        mat = {
            "young_modulus_Pa": float(c.material.E),
            "diameter_m": float(c.material.diameter),
            "max_tension_N": float(c.material.T_a),
            **({"min_tension_N": float(c.material.T_min)} if c.material.T_min else {}),
            **({"linear_density_kg_m": float(c.material.rho)} if c.material.rho else {}),
        }
        cables.append(
            {
                "A_m": [float(x) for x in c.A],
                **({"B_m": [float(x) for x in c.B]} if spatial else {}),
                "pulley": pul,
                "cable": mat,
                "dead_length_m": float(c.dead_length),
                **({"winch": _winch_mapping(c.winch)} if c.winch is not None else {}),
            }
        )
    first = rob.cables[0]
    doc = {
        "name": f"{rob.name} (calibrated)",
        "platform": {
            "mass_kg": float(rob.platform.mass),
            **({"com_m": [float(x) for x in rob.platform.com]} if spatial else {}),
            "gravity_m_per_s2": float(rob.platform.g),
        },
        "cable": {
            "young_modulus_Pa": float(first.material.E),
            "diameter_m": float(first.material.diameter),
            "max_tension_N": float(first.material.T_a),
        },
        "pulley": {"kind": first.pulley.kind, "h_m": float(first.pulley.h), "r_p_m": float(first.pulley.r_p)},
        "cables": cables,
    }
    return "\n".join(header) + "\n" + yaml.safe_dump(doc, sort_keys=False)
