"""The result of a calibration (``Calibration``; ``MotorCalibration`` from motor angles): estimate,
posterior, identifiability, the per-sample table, the JSON summary, and the calibrated robot as
robot-file text (``robot_file_text``; ``cdpr.pipeline.calibration_files.write_robot`` writes
it)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd
import yaml

from cdpr.analyses.calibration.model import (
    STANDARD_STIFFENING,
)
from cdpr.errors import CdprError
from cdpr.parameters import (
    calibrated_robot,
    calibration_groups,
    is_spatial,
    robot_size,
)
from cdpr.robot import WINCH_KEYS, BoxBody


@dataclasses.dataclass
class _Posterior:
    """What every fit returns: the nominal robot, the model, the estimated parameters (``index``
    into the fit's parameter vector, their ``names``, ``nominal`` and ``estimate`` values, prior sd
    ``prior_sd``), the identifiability ``ident`` (the prior-scaled posterior, Gauss-Newton at the
    MAP, Tarantola 2005 section 3.2), the per-sample table, the data file and the optimiser's cost
    and evaluation count."""

    robot: object
    model: str
    index: np.ndarray
    names: list
    nominal: np.ndarray
    estimate: np.ndarray
    prior_sd: np.ndarray
    ident: dict
    table: pd.DataFrame
    source: str
    cost: float
    nfev: int

    @property
    def sd(self):
        """Posterior sd, in the parameters' units [Pa, m, kg] (nuisance positions marginalised)."""
        return self.ident["ratio"] * self.prior_sd

    @property
    def covariance(self):
        """Posterior covariance of the estimated parameters (their units squared)."""
        return self.ident["cov_scaled"] * np.outer(self.prior_sd, self.prior_sd)

    def _summary(self, groups, cables):
        """The JSON keys every fit's summary starts with: parameters (with ``groups`` and
        ``cables``, None where a parameter has no cable), n_parameters, rank, condition,
        singular_values, unidentified."""
        return {
            "parameters": [
                {
                    "name": nm,
                    "group": grp,
                    "cable": cab,
                    "nominal": float(a),
                    "estimate": float(b),
                    "sd": float(s),
                    "prior_sd": float(p),
                    "identified": str(lab),
                }
                for nm, grp, cab, a, b, s, p, lab in zip(
                    self.names,
                    groups,
                    cables,
                    self.nominal,
                    self.estimate,
                    self.sd,
                    self.prior_sd,
                    self.ident["labels"],
                )
            ],
            "n_parameters": len(self.index),
            "rank": self.ident["rank"],
            "condition": _json_float(self.ident["condition"]),
            "singular_values": [float(s) for s in self.ident["singular_values"]],
            "unidentified": list(self.ident["unidentified"]),
        }


@dataclasses.dataclass
class Calibration(_Posterior):
    """The result of ``fit``: estimate, posterior, identifiability and the per-sample table; ``base``
    is the robot the model moves, ``theta`` its whole parameter vector at the estimate."""

    base: object
    theta: np.ndarray

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
        out = {
            **self._summary(pt["group"], [None if pd.isna(c) else int(c) for c in pt["cable"]]),
            "residual_rms_m": float(np.sqrt(np.mean(res**2))) if len(res) else None,
            "residual_rms_rad": rad,
            "samples_used": int(used.sum()),
            "samples_left_out": int((~used).sum()),
        }
        if "linear_densities" in set(pt["group"]):  # heavy cables: how well the data see rho_i
            out["linear_densities"] = linear_density_words(out)
        return out


@dataclasses.dataclass
class MotorCalibration(_Posterior):
    """The result of ``fit_motor``: the estimate, its posterior and identifiability, the positions;
    ``spool_model`` is the ``motor.SpoolModel`` at the estimate."""

    groups: list
    spool_model: object
    positions: np.ndarray
    line_residual: np.ndarray
    gauge: str
    warnings: list

    def summary(self):
        """The JSON of ``cdpr calibrate fit --json`` on motor-angle data (SI units)."""
        m = self.robot.m
        groups = ["anchors" if k < 3 * m else "spools" for k in self.index]
        cables = [int(k // 3 + 1) if k < 3 * m else int((k - 3 * m) % m + 1) for k in self.index]
        out = {
            **self._summary(groups, cables),
            "gauge": self.gauge,
            "model": self.model,
            "line_rms_m": float(np.sqrt(np.mean(self.line_residual**2))),
            "residual_rms_m": _rms(self.table["position_residual_m"].to_numpy()),
            "samples_used": len(self.table),
            "samples_with_position": int(np.isfinite(self.table["position_residual_m"]).sum()),
            "samples_left_out": 0,
        }
        return out


def linear_density_words(summary):
    """One sentence on how well a fit's data see the linear densities rho_i (heavy cables): their
    posterior sd against the prior sd, the identifiability labels, the rank and condition of the fit.

    Parameters
    ----------
    summary : dict
        A fit's summary (``Calibration.summary``'s keys parameters, n_parameters, rank, condition).

    Returns
    -------
    str
    """
    rho = [p for p in summary["parameters"] if p["group"] == "linear_densities"]
    sd = np.array([p["sd"] for p in rho])
    ratio = sd / np.array([p["prior_sd"] for p in rho])
    labels = [p["identified"] for p in rho]
    worst = float(ratio.max())
    how = "well" if worst <= 0.3 else ("weakly" if worst <= 0.8 else "hardly (the prior decides)")
    count = ", ".join(f"{labels.count(lab)} {lab}" for lab in dict.fromkeys(labels))
    cond = summary["condition"]
    cond = "inf" if cond is None else f"{cond:.3g}"
    return (
        f"linear densities {rho[0]['name']}..{rho[-1]['name']}: the data see them {how}: posterior sd "
        f"{sd.min():.3g}-{sd.max():.3g} kg/m, {100 * ratio.min():.0f}-{100 * worst:.0f} % of the prior sd "
        f"({count}); the fit has rank {summary['rank']} of {summary['n_parameters']}, condition {cond}"
    )


def _rms(x):
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(np.sqrt(np.mean(x**2))) if len(x) else None


def _winch_mapping(w):
    """A cable's WinchParams as the robot file's ``winch:`` keys (plain SI numbers)."""
    return {key: float(getattr(w, attr)) for key, (attr, _unit) in WINCH_KEYS.items()}


def _json_float(x):
    return float(x) if math.isfinite(x) else None


def robot_file_text(cal, data_source, when):
    """The calibrated robot as robot-file text (``cdpr.pipeline.calibration_files.write_robot``
    writes it): the input's schema, per-cable plain SI values, and a header saying from which
    data, with which model, and when (offsets, which are not robot parameters, in the header; so is
    an external wrench the data were taken under, ``Platform.wrench``, which the file does not carry:
    a calibrated robot is the robot without its temporary load). A
    motor-angle fit's is the nominal robot file with the estimated anchors and spools per cable
    (``motor_robot_mapping``), its header naming the gauge too.

    Parameters
    ----------
    cal : Calibration or MotorCalibration
    data_source : str
        The data file, named in the header.
    when : datetime.datetime
        The time of the calibration, named in the header (ISO 8601, to the second).

    Returns
    -------
    str
        YAML with a comment header, ending in a newline.
    """
    if isinstance(cal, MotorCalibration):
        return _motor_robot_text(cal, data_source, when)
    rob = cal.calibrated_robot()
    header = _header(rob.name, f"{cal.model} model", cal, data_source, when)
    spatial = is_spatial(rob)
    if "offsets" in {calibration_groups(rob)[0][k] for k in cal.index}:
        header.append("# encoder offsets [m]: " + ", ".join(f"{o:.9g}" for o in cal.offsets))
    if rob.platform.has_wrench:  # the load of the measurements (--wrench): named, not part of the robot
        header.append(
            "# fitted under the external wrench (FX, FY, FZ, MX, MY, MZ) = ("
            + ", ".join(f"{x:.9g}" for x in rob.platform.wrench)
            + ") [N, N m] on the platform while the data were taken; not part of this robot (--wrench)"
        )
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
            **({"body": _body_mapping(rob.platform.body)} if rob.platform.body != "hull" else {}),
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


def _body_mapping(body):
    """A platform body (``Platform.body``) as the robot file's ``platform.body`` value."""
    if isinstance(body, BoxBody):
        return {"box": {"centre_m": [float(x) for x in body.centre], "half_m": [float(x) for x in body.half]}}
    return str(body)


def motor_robot_mapping(robot_mapping, sm):
    """A robot file's mapping with the anchors and every cable's spool radius and buildup factor of
    ``sm`` (plain SI numbers, per cable).

    Parameters
    ----------
    robot_mapping : dict
        The robot file as loaded by YAML.
    sm : SpoolModel

    Returns
    -------
    dict
    """
    doc = dict(robot_mapping)
    cables = []
    for i, c in enumerate(doc["cables"]):
        c = dict(c)
        c["A_m"] = [float(x) for x in sm.A[i]]
        w = dict(c.get("winch") or {})
        w["spool_radius_m"] = float(sm.r0[i])
        w["buildup_factor_m"] = float(sm.Q[i])
        c["winch"] = w
        cables.append(c)
    doc["cables"] = cables
    return doc


def _motor_robot_text(cal, data_source, when):
    """``robot_file_text`` of a ``MotorCalibration``."""
    try:
        with open(cal.robot.source, encoding="utf-8") as fh:
            doc = yaml.safe_load(fh)
    except OSError as exc:
        raise CdprError(f"{cal.robot.source}: cannot read the nominal robot file ({exc})") from None
    doc = motor_robot_mapping(doc, cal.spool_model)
    doc["name"] = f"{doc.get('name', cal.robot.name)} (calibrated)"
    header = _header(cal.robot.name, f"{cal.model} model, motor angles", cal, data_source, when)
    header.append(f"# gauge: {cal.gauge}")
    return "\n".join(header) + "\n" + yaml.safe_dump(doc, sort_keys=False)


def _header(name, what, cal, data_source, when):
    """The first comment lines of a calibrated robot file: robot ``name`` calibrated (``what``:
    the model) from the data, when, from which nominal robot, and the estimated parameters."""
    return [
        f"# {name} calibrated by cdpr calibrate fit ({what}) from {data_source}",
        f"# on {when.isoformat(timespec='seconds')}; nominal robot: {cal.robot.source}",
        f"# estimated: {', '.join(cal.names)}",
    ]
