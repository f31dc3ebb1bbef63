"""Calibration from motor angles (a spool robot, the Hangprinter; issue 40): the data contract, the
self-calibration with unknown poses, a prior-only MAP, check and the K-fold cross-validation."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.analyses.calibration import motor
from cdpr.errors import CdprError, ConfigError
from cdpr.robot import load_robot
from tests.analyses.one_line import assert_refused_in_one_line

ROOT = Path(__file__).resolve().parents[2]
HP4 = ROOT / "config/robots/hangprinter_hp4.yaml"
SERIES2 = ROOT / "data/hangprinter/hp4_2022_force_series2_cdpr.csv"
GRID = ROOT / "data/hangprinter/hp4_2021_12_grid_cdpr.csv"


@pytest.fixture(scope="module")
def hp4():
    return load_robot(HP4)


def _truth(robot, rng, anchors=0.08, radius=0.6e-3, buildup=3e-5):
    """The robot with its anchors, spool radii and buildup factors moved by seeded amounts."""
    sm = motor.SpoolModel.of(robot)
    cables = []
    for i, c in enumerate(robot.cables):
        sp = dataclasses.replace(
            c.spool,
            r0=c.spool.r0 + radius * rng.standard_normal(),
            Q=c.spool.Q + buildup * rng.standard_normal(),
        )
        cables.append(dataclasses.replace(c, A=tuple(sm.A[i] + anchors * rng.standard_normal(3)), spool=sp))
    return dataclasses.replace(robot, cables=tuple(cables))


def _positions(rng, n):
    """n positions in the HP4's print volume, the first at the origin (the encoder reference)."""
    P = np.column_stack([rng.uniform(-0.4, 0.4, n), rng.uniform(-0.4, 0.4, n), rng.uniform(0.0, 1.2, n)])
    P[0] = 0.0
    return P


# ---- the data contract -----------------------------------------------------------------------------
def test_reads_the_shipped_tables(hp4):
    d = cal.read_motor_data(SERIES2, hp4)
    assert d.motor_deg.shape == (44, 4)
    assert int(d.has_pose.sum()) == 9 and int(d.has_force.sum()) == 41
    assert list(d.sample[d.has_pose]) == ["0", "1", "2", "3", "4", "5", "6", "7", "40"]
    g = cal.read_motor_data(GRID, hp4)
    assert g.has_pose.all() and not g.has_force.any()
    assert cal.is_motor_table(SERIES2) and not cal.is_motor_table(
        ROOT / "data/hangprinter/hp3_2018_samples.csv"
    )


GOOD = "sample,motor_deg_1,motor_deg_2,motor_deg_3,motor_deg_4"


@pytest.mark.parametrize(
    "text, column, words",
    [
        (GOOD + ",L1\n0,0,0,0,0,1\n", "L1", "unknown column; allowed: sample, motor_deg_1..motor_deg_4"),
        ("sample,motor_deg_1,motor_deg_2,motor_deg_4\n0,0,0,0\n", "motor_deg_3", "missing column"),
        ("sample,motor_deg_1,motor_deg_2,motor_deg_3\n0,0,0,0\n", "motor_deg_4", "missing column"),
        (GOOD + ",motor_deg_5\n0,0,0,0,0,0\n", "motor_deg_5", "unknown column"),
        (
            GOOD + ",force_N_1,force_N_2\n0,0,0,0,0,1,1\n",
            "force_N_3",
            "forces need all of force_N_1..force_N_4",
        ),
        (GOOD + ",x_m,y_m\n0,0,0,0,0,0,0\n", "z_m", "positions need all of x_m, y_m, z_m"),
        (GOOD + ",x_m,y_m,z_m\n0,0,0,0,0,0.1,,0.2\n", "y_m", "a position needs all three"),
        (GOOD + "\n0,0,abc,0,0\n", "motor_deg_2", "'abc' is not a number"),
        (GOOD + "\n0,0,,0,0\n", "motor_deg_2", "motor angles must be finite"),
        (GOOD + ",force_N_1,force_N_2,force_N_3,force_N_4\n0,0,0,0,0,1,-2,1,1\n", "force_N_2", ">= 0"),
        (GOOD + ",force_N_1,force_N_2,force_N_3,force_N_4\n0,0,0,0,0,1,,1,1\n", "force_N_2", "all empty"),
        (GOOD + ",x_m,y_m,z_m,sigma_m\n0,0,0,0,0,0,0,0,0\n", "sigma_m", "must be finite and > 0"),
        (GOOD + "\n", None, "no samples"),
    ],
)
def test_bad_data_is_one_line_naming_file_and_column(hp4, tmp_path, text, column, words):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    assert_refused_in_one_line(cal.read_motor_data, path, hp4, column, words)


def test_motor_angles_need_spools(tmp_path):
    path = tmp_path / "m.csv"
    path.write_text("sample,motor_deg_1,motor_deg_2,motor_deg_3\n0,0,0,0\n")
    with pytest.raises(ConfigError, match="need a spool winch on every cable"):
        cal.read_motor_data(path, load_robot(ROOT / "config/robots/cdpr3.yaml"))


def test_bad_groups_and_priors():
    with pytest.raises(CdprError, match="estimates anchors, spools only"):
        cal.parse_motor_priors(None, ["anchors", "moduli"])
    with pytest.raises(CdprError, match="a prior for spools, which is not estimated"):
        cal.parse_motor_priors("spools=1mm", ["anchors"])
    assert cal.parse_motor_priors("anchors=150mm", ["anchors"])["anchors"] == pytest.approx(0.15)
    data = cal.simulate_motor(load_robot(HP4), np.zeros((1, 3)))
    for groups in (["moduli"], []):
        with pytest.raises(CdprError, match="estimates anchors, spools"):
            cal.fit_motor(load_robot(HP4), data, groups, cal.parse_motor_priors(None, []))


# ---- the model -----------------------------------------------------------------------------------
@pytest.mark.parametrize("model, forces", [("standard", False), ("exact", True)])
def test_jacobian_matches_central_differences(hp4, model, forces):
    rng = np.random.default_rng(3)
    P = _positions(rng, 6)
    F = rng.uniform(5, 30, (6, 4)) if forces else None
    data = cal.simulate_motor(hp4, P, F, measured=[True, False, True, False, False, False])
    sm0 = motor.SpoolModel.of(hp4)
    index = np.arange(20)
    sd = motor.motor_prior_sd(4, index, motor.DEFAULT_PRIORS)
    f, g = motor.stretch_factors(model, data, motor.reference_forces(data, model)[0], sm0.K)
    res, jac, _ = motor.motor_problem(sm0, data, index, sd, f, g)
    x = np.concatenate([0.3 * rng.standard_normal(20), (P + 0.01 * rng.standard_normal(P.shape)).ravel()])
    J = jac(x)
    h = 1e-6
    Jn = np.column_stack([(res(x + h * e) - res(x - h * e)) / (2 * h) for e in np.eye(len(x))])
    assert np.abs(J - Jn).max() < 1e-5 * np.abs(J).max()


def test_simulated_readings_put_the_true_robot_at_its_positions(hp4):
    """The model inverts the simulation: the true robot solves every sample to its position."""
    rng = np.random.default_rng(4)
    P = _positions(rng, 12)
    F = rng.uniform(5, 30, (12, 4))
    truth = _truth(hp4, rng)
    for model, force in (("exact", F), ("standard", None)):
        data = cal.simulate_motor(truth, P, force, measured=np.ones(12, dtype=bool), sigma=1e-12)
        out = cal.check_motor(truth, data, model)
        assert out["max_m"] < 1e-8 and out["line_rms_m"] < 1e-9
    # the stretch matters: the rigid model reads the stretched lines a few tenths of a millimetre off
    data = cal.simulate_motor(truth, P, F, measured=np.ones(12, dtype=bool), sigma=1e-12)
    assert cal.check_motor(truth, data, "standard")["rms_m"] > 1e-4


# ---- self-calibration with unknown poses ------------------------------------------------------------
@pytest.mark.parametrize("model", ["exact", "standard"])
def test_self_calibration_recovers_a_seeded_machine_to_its_noise(hp4, model):
    """40 samples, 6 with a measured position (sd 0.2 mm), lines with 0.1 mm noise; anchors off by
    8 cm, spool radii by 0.6 mm: the fit recovers every parameter within 4 posterior sd, the line
    chi-square is that of the noise, and every position comes back within 3 mm."""
    rng = np.random.default_rng(2026)
    truth = _truth(hp4, rng)
    n = 40
    P = _positions(rng, n)
    F = rng.uniform(5, 30, (n, 4)) if model == "exact" else None
    meas = np.zeros(n, dtype=bool)
    meas[[0, 5, 11, 17, 23, 31]] = True
    sig_l = 1e-4
    data = cal.simulate_motor(truth, P, F, sigma_line=sig_l, rng=rng, measured=meas, sigma=2e-4)
    priors = cal.parse_motor_priors("anchors=150mm", ["anchors", "spools"])
    res = cal.fit_motor(hp4, data, ["anchors", "spools"], priors, model, sigma_line=sig_l)
    true_theta = motor.SpoolModel.of(truth).theta()
    z = (res.estimate - true_theta) / res.sd
    assert np.abs(z).max() < 4.0, dict(zip(res.names, np.round(z, 2)))
    nominal_err = np.abs(res.nominal - true_theta)[:12].max()
    assert nominal_err > 0.05 and np.abs(res.estimate - true_theta)[:12].max() < 0.1 * nominal_err
    # at the noise: the MAP's chi-square is that of its degrees of freedom (n m line rows and 3 per
    # measured position, less 3 n pose unknowns; the prior rows and parameters cancel)
    dof = n * 4 + 3 * int(meas.sum()) - 3 * n
    assert abs(2 * res.cost - dof) < 4 * np.sqrt(2 * dof)
    assert np.sqrt(np.mean(np.sum((res.positions - P) ** 2, axis=1))) < 3e-3
    assert res.ident["rank"] == 20
    assert np.sqrt(np.diag(res.covariance)) == pytest.approx(res.sd, rel=1e-12)
    assert "6 measured positions fix the frame" in res.gauge


def test_without_positions_the_gauge_is_named_and_left_to_the_priors(hp4):
    """No measured position: the frame's rotation about the origin and its scale are not seen; the
    fit still runs (MAP), the lines fit to their noise, and the identifiability names weak directions."""
    rng = np.random.default_rng(11)
    truth = _truth(hp4, rng, anchors=0.02)
    P = _positions(rng, 30)
    data = cal.simulate_motor(truth, P, None, sigma_line=1e-4, rng=rng)
    res = cal.fit_motor(
        hp4, data, ["anchors", "spools"], cal.parse_motor_priors(None, ["anchors"]), "standard", 1e-4
    )
    assert (
        "no measured position" in res.gauge
        and "rotation about the origin" in res.gauge
        and "scale" in res.gauge
    )
    assert res.summary()["residual_rms_m"] is None
    assert np.sqrt(np.mean(res.line_residual**2)) < 1.2e-4
    assert res.ident["unidentified"]  # at least the rotations: seen less than the prior sees them
    sv = np.sort(res.ident["singular_values"])
    assert (sv[:4] < 1.0).sum() >= 3  # three rotations (and the scale) are weak directions


def test_prior_only_map_with_fewer_equations_than_parameters(hp4):
    """2 samples, no position: 8 line equations, 6 pose unknowns, 20 parameters. Not refused: the
    MAP is proper; at least 18 directions keep their prior variance exactly."""
    rng = np.random.default_rng(5)
    data = cal.simulate_motor(_truth(hp4, rng), _positions(rng, 2), None, sigma_line=1e-4, rng=rng)
    res = cal.fit_motor(hp4, data, ["anchors", "spools"], None, "standard")
    assert res.ident["rank"] <= 2
    eig = np.linalg.eigvalsh(res.ident["cov_scaled"])
    assert (eig > 1 - 1e-9).sum() >= 18 and eig.max() <= 1 + 1e-9
    assert np.all(res.sd <= res.prior_sd * (1 + 1e-12))
    assert np.isfinite(res.estimate).all()


# ---- cross-validation ------------------------------------------------------------------------------------
def test_folds_are_row_index_mod_k():
    assert cal.fold_of(7, 3).tolist() == [0, 1, 2, 0, 1, 2, 0]
    assert cal.fold_of(5, 5).tolist() == [0, 1, 2, 3, 4]  # leave-one-out
    for k in (1, 8):
        with pytest.raises(CdprError, match="--folds"):
            cal.fold_of(7, k)


def test_cv_is_deterministic_and_leave_one_out_holds_out_each_sample_once(hp4):
    rng = np.random.default_rng(9)
    truth = _truth(hp4, rng, anchors=0.03)
    n = 12
    meas = np.zeros(n, dtype=bool)
    meas[::2] = True
    data = cal.simulate_motor(truth, _positions(rng, n), None, sigma_line=1e-4, rng=rng, measured=meas)
    pri = cal.parse_motor_priors("anchors=150mm", ["anchors"])
    a = cal.cross_validate(hp4, data, ["anchors"], pri, "standard", folds=n)
    b = cal.cross_validate(hp4, data, ["anchors"], pri, "standard", folds=n)
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)
    assert [f["samples"] for f in a["folds"]] == [[str(i)] for i in range(n)]
    assert [r["sample"] for r in a["per_sample"]] == [str(i) for i in range(n)]
    assert [r["fold"] for r in a["per_sample"]] == list(range(n))
    errs = [r["error_m"] for r in a["per_sample"]]
    assert sum(e is not None for e in errs) == 6
    # calibrated on the other samples, the held-out ones come back far better than with the nominal robot
    fixed = cal.cross_validate(hp4, data, model="standard", folds=n, fixed=True)
    assert a["heldout_position_rms_m"] < 0.5 * fixed["heldout_position_rms_m"]
    k3 = cal.cross_validate(hp4, data, ["anchors"], pri, "standard", folds=3)
    assert [f["samples"] for f in k3["folds"]][0] == ["0", "3", "6", "9"]
    for key in (
        "folds",
        "heldout_position_rms_m",
        "heldout_position_median_m",
        "heldout_line_rms_m",
        "train_rms_m",
    ):
        assert key in k3
