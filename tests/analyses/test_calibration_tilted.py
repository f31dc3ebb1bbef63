"""Calibration of a point mass under a tilted pulley axis (issue 37: it used to be refused with "use
cdpr.solve.pose_sensitivities"): such a robot goes to the 6-DoF equilibrium, which contains the
point mass. The point-mass problem on that path equals the point-mass physical one on a suspended
CDPR4 (same residual and Jacobian), its exact Jacobian (pose and tension rows, offsets, every
group) equals central differences of the full residual, and noise-free data recover the truth."""

import numpy as np
import pytest

import cdpr.models.cables as cables
from cdpr.analyses import calibration as cal
from cdpr.parameters import calibration_names, select_groups
from cdpr.robot import load_robot
from tests.analyses.test_calibration import _poses, evaluated_problem, recovered_noise_free
from tests.analyses.test_calibration_platform_tensions import assert_columns_match_central_differences
from tests.conftest import ROBOTS

#: Every group a point mass calibrates.
GROUPS = ["moduli", "pulleys", "dead_lengths", "anchors", "offsets", "mass"]


def tilted_robot_file(folder, axis="[0.2, 0.0, 1.0]"):
    """config/robots/cdpr4.yaml with the second cable's pulley axis tilted (default 11.3° toward +x)."""
    text = (ROBOTS / "cdpr4.yaml").read_text(encoding="utf-8")
    old = "  - {A_m: [2.5, -2.5, 5.0]}\n"
    assert text.count(old) == 1
    path = folder / "cdpr4_tilted.yaml"
    path.write_text(text.replace(old, f"  - {{A_m: [2.5, -2.5, 5.0], pulley: {{axis: {axis}}}}}\n"), "utf-8")
    return path


@pytest.fixture(scope="module")
def tilted(tmp_path_factory):
    robot = load_robot(tilted_robot_file(tmp_path_factory.mktemp("tilted")))
    assert robot.point_mass and not robot.suspended_point_mass
    return robot


def test_the_tilted_point_mass_goes_to_the_6dof_problem(tilted, cdpr4):
    rng = np.random.default_rng(1)
    data = cal.simulate(tilted, tilted, _poses(rng, 5))
    assert len(data.sample) == 5 and not np.isfinite(data.rotvec).any()  # a point mass's data
    idx = select_groups(tilted, ["anchors"])
    sd = cal.prior_sd(tilted, idx, cal.parse_priors(None))
    prob = cal.Problem(tilted, data, idx, sd)
    assert isinstance(prob, cal.Problem) and prob.pose_model and not prob.spatial and prob.engine is None
    p3 = cal.Problem(cdpr4, data, idx, sd)
    assert isinstance(p3, cal.Problem) and not p3.pose_model
    assert prob.residual(np.zeros(len(idx))).shape == (3 * 5 + len(idx),)


def test_the_6dof_path_equals_the_point_mass_path_on_a_suspended_point_mass(cdpr4, monkeypatch):
    """The pose model (Problem, pose_model=True) forced on the suspended CDPR4 (the 6-DoF equilibrium with b = 0, c = 0) against
    Problem (the point-mass physical solver): same equilibria, residual and exact Jacobian, pose and
    tension rows, to the solvers' tolerance."""
    monkeypatch.setattr(cables, "FTOL_REL", 1e-15)
    rng = np.random.default_rng(2)
    data = cal.simulate(cdpr4, cdpr4, _poses(rng, 6), offsets=np.zeros(4), tensions=True)
    data.pose[::3] = np.nan  # two samples with tensions only
    idx = select_groups(cdpr4, GROUPS)
    sd = cal.prior_sd(cdpr4, idx, cal.parse_priors(None))
    z = 0.3 * rng.standard_normal(len(idx))
    p3 = cal.Problem(cdpr4, data, idx, sd, engine="numpy", solver={"tol": 1e-14})
    p6 = cal.Problem(cdpr4, data, idx, sd, solver={"tol": 1e-14}, pose_model=True)
    e3, e6 = p3.evaluate(z), p6.evaluate(z)
    assert (e3["status"] == "ok").all() and (e6["status"] == "ok").all()
    np.testing.assert_array_equal(e3["smooth"], e6["smooth"])
    np.testing.assert_allclose(e6["P"], e3["P"], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(p3.row_sample, p6.row_sample)
    r3, r6 = p3.residual(z), p6.residual(z)
    np.testing.assert_allclose(r6, r3, rtol=0, atol=1e-9 / 0.2e-3 * 10)  # 1e-9 m over σ = 0.2 mm
    J3, J6 = p3.jacobian(z), p6.jacobian(z)
    scale = np.abs(J3).max(axis=0)
    assert (np.abs(J6 - J3).max(axis=0) / scale).max() < 1e-6


def test_analytic_jacobian_equals_central_differences_of_the_full_residual(tilted, monkeypatch):
    """The pose model's point-mass rows (positions, tensions) against central differences of its residual,
    which re-solves every equilibrium; every group, encoder offsets, two samples without a pose.
    The tension rows are a small difference of large terms, so the equilibria are re-solved to
    round-off (FTOL_REL 1e-15)."""
    monkeypatch.setattr(cables, "FTOL_REL", 1e-15)
    rng = np.random.default_rng(4)
    data = cal.simulate(tilted, tilted, _poses(rng, 40), offsets=np.zeros(4), tensions=True)
    data = data.subset(np.flatnonzero(data.tension.min(axis=1) > 300.0)[:6])  # every cable taut
    assert len(data.sample) == 6
    data.pose[:2] = np.nan
    prob, idx, z, ev, J = evaluated_problem(
        tilted, data, GROUPS, "dead_lengths=5mm,offsets=5mm", 1e-15, 0.1, rng
    )
    assert ev["t"].min() > 50.0
    n_pose, n_t = 3 * 4, 4 * 6
    assert J.shape == (n_pose + n_t + len(idx), len(idx))
    names = [calibration_names(prob.robot)[k] for k in idx]
    assert_columns_match_central_differences(prob, z, J, names, names, n_pose, n_t)


def test_noise_free_data_recover_the_truth(tilted):
    """A tilted CDPR4 perturbed in anchors, dead lengths, pulleys and moduli (28 parameters),
    noise-free poses: every parameter back to 1e-6 relative, the axis kept."""
    c, truth = recovered_noise_free(tilted, ["anchors", "dead_lengths", "pulleys", "moduli"])
    assert len(c.index) == 28
    assert truth.cables[1].pulley.axis == tilted.cables[1].pulley.axis != (0.0, 0.0, 1.0)
    assert c.calibrated_robot().cables[1].pulley.axis == tilted.cables[1].pulley.axis


def test_check_and_plan_on_the_tilted_point_mass(tilted):
    rng = np.random.default_rng(5)
    data = cal.simulate(tilted, tilted, _poses(rng, 10))  # noise-free: the robot predicts itself
    out = cal.check(tilted, data)
    assert out["n"] == 10 and out["max_m"] < 1e-9 and out["rms_rad"] is None
    assert "error_rad" not in out["samples"][0]
    res = cal.plan(tilted, ["anchors"], 6, n_axis=4, n_random=5)
    assert res["poses"].shape == (6, 3) and res["lengths"].shape == (6, 4)
    assert (res["sd_d_optimal"] < res["prior_sd"]).all()
