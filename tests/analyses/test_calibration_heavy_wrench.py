"""Calibration of a robot with heavy cables under an external wrench (issues 38 and 41): CoGiRo with 4 mm
steel cables (0.063 kg/m) and a 20 kg tool hung 0.22 m off its reference point (a force and a moment).
The fit's exact Jacobian (``Problem.jacobian``: ``heavy_sensitivity`` under the wrench, the linear
densities, the mass and the encoder offsets among the columns) equals central differences of its full
residual, every heavy equilibrium re-solved under the same wrench; and as the linear density goes to
0 the heavy calibration under the wrench becomes the massless calibration under that wrench (residual
and Jacobian), while the same calibration without the wrench is another one. The fit itself, with and
without ``--wrench``, on heavy data: tests/cli/test_calibrate_heavy_wrench.py."""

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.parameters import calibration_names, select_groups
from cdpr.robot import load_robot, with_values, with_wrench
from tests.analyses.test_calibration_wrench import assert_jacobian_columns
from tests.conftest import ROBOTS

#: The tool: 20 kg at (0.2, 0.1, 0) m from p, its weight at p and the moment r x F [N, N m].
F_TOOL = np.array([0.0, 0.0, -20 * 9.81])
WRENCH = (*F_TOOL, *np.cross([0.2, 0.1, 0.0], F_TOOL))
RHO = 0.063  # [kg/m] a 4 mm steel cable
GROUPS = ["anchors", "attachments", "dead_lengths", "moduli", "mass", "offsets"]


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro_massless.yaml")


def _data(robot, seed, n):
    """``n`` poses of ``robot`` (its standard lengths, tilted by up to 0.1 rad, 100 N of margin),
    noise-free positions and orientations."""
    rng = np.random.default_rng(seed)
    P = cal.random_poses(robot, rng, n, [-3, 3, -2, 2, 1.0, 2.5], 0.1, 100.0)
    data = cal.simulate(robot, robot, P, offsets=np.zeros(robot.m), sigma_rad=0.1)
    assert len(data.sample) == n
    return data, rng


def _problem(robot, data, groups):
    idx = select_groups(robot, groups)
    sd = cal.prior_sd(robot, idx, cal.parse_priors(None))
    prob = cal.Problem(robot, data, idx, sd, solver={"tol": 1e-14})
    return prob, [calibration_names(robot)[k] for k in idx]


def test_heavy_jacobian_under_a_wrench_equals_central_differences(cogiro):
    """Problem.jacobian of heavy CoGiRo under the tool's wrench against central differences of
    Problem.residual; the columns of every kind: the mass (it moves the weight, not the wrench), an
    anchor, an attachment, a dead length, a modulus, a linear density and an encoder offset. The
    step is 1e-3 prior sd: the differences are then round-off free to ~1e-7 (the linear density's
    column: 1.7e-7 at 1e-3, 1.2e-6 at 1e-4, 1.9e-5 at 1e-5, the heavy re-solves' round-off over
    the step; 1.6e-8 at 1e-2, the truncation error)."""
    heavy = with_wrench(with_values(cogiro, linear_density=RHO), WRENCH)
    assert heavy.heavy and heavy.platform.has_wrench
    data, rng = _data(heavy, 4, 2)
    prob, names = _problem(heavy, data, GROUPS + ["linear_densities"])
    z = 0.3 * rng.standard_normal(len(names))
    ev = prob.evaluate(z)
    assert ((ev["status"] == "ok") & ev["smooth"]).all()
    J = prob.jacobian(z)
    n = 6 * len(data.sample)
    columns = ("M", "A_1_x", "b_2_y", "d_3", "E_4", "rho_5", "offset_6")
    assert_jacobian_columns(prob, z, J, names, columns, n, step=1e-3)


def test_heavy_calibration_under_a_wrench_tends_to_the_massless_one_as_w_goes_to_zero(cogiro):
    """A linear density of 1e-12 kg/m (w ~ 1e-11 N/m: the catenary's sag and its moment arms are
    O(w L^2 / T) ~ 1e-13 m) sends the calibration through the heavy equilibrium and
    ``heavy_sensitivity``; under the tool's wrench its residual and Jacobian equal the massless
    calibration's under that wrench to round-off, at a z away from the nominal; at 1e-6 kg/m they
    differ by ~1e-6 relative (the heavy model is in play: its difference is O(w)). The same z on the
    robots without the wrench gives residuals that differ by more than one sd: the comparison sees
    the wrench."""
    loaded = with_wrench(cogiro, WRENCH)
    data, rng = _data(loaded, 5, 3)
    massless, names = _problem(loaded, data, GROUPS)
    thin = with_wrench(with_values(cogiro, linear_density=1e-12), WRENCH)
    assert thin.heavy and not loaded.heavy
    heavy, names_h = _problem(thin, data, GROUPS)
    assert names_h == names  # the same parameters (the thin robot's rho_i are not estimated)
    z = 0.3 * rng.standard_normal(len(names))
    r, J = massless.residual(z), massless.jacobian(z)
    assert ((massless.evaluate(z)["status"] == "ok") & massless.evaluate(z)["smooth"]).all()
    r_h, J_h = heavy.residual(z), heavy.jacobian(z)
    assert np.abs(r_h - r).max() < 1e-9 * np.abs(r).max()
    assert np.abs(J_h - J).max() < 1e-9 * np.abs(J).max()
    light, _ = _problem(with_wrench(with_values(cogiro, linear_density=1e-6), WRENCH), data, GROUPS)
    d_r = np.abs(light.residual(z) - r).max() / np.abs(r).max()
    d_J = np.abs(light.jacobian(z) - J).max() / np.abs(J).max()
    assert 1e-7 < d_r < 1e-5 and 1e-7 < d_J < 1e-4, (d_r, d_J)
    n = 6 * len(data.sample)
    for robot in (cogiro, with_values(cogiro, linear_density=1e-12)):
        bare, _ = _problem(robot, data, GROUPS)
        assert np.abs(bare.residual(z)[:n] - r[:n]).max() > 1.0
