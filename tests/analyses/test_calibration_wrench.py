"""Calibration under an external wrench (``Platform.wrench``, ``robot.with_wrench``; ``cdpr calibrate
--wrench``): a tool of 20 kg hung 0.22 m off CoGiRo's reference point while the data were taken.
Noise-free poses of a perturbed CoGiRo under that load are recovered to round-off when the nominal
robot carries the wrench too, and not without it; the fit's exact Jacobian under the wrench equals
central differences of its full residual (the mass column moves the weight only)."""

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.parameters import calibration_names
from cdpr.robot import load_robot, with_wrench
from tests.analyses.test_calibration import _truth, evaluated_problem
from tests.conftest import ROBOTS

COGIRO = str(ROBOTS / "cogiro.yaml")
#: The tool: 20 kg at (0.2, 0.1, 0) m from p, its weight at p and the moment r x F [N, N m].
F_TOOL = np.array([0.0, 0.0, -20 * 9.81])
WRENCH = (*F_TOOL, *np.cross([0.2, 0.1, 0.0], F_TOOL))


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(COGIRO)


def _poses(robot, rng, n):
    return cal.random_poses(robot, rng, n, [-3, 3, -2, 2, 1.0, 2.5], 0.1, 100.0)


def assert_jacobian_columns(prob, z, J, names, columns, n, step):
    """Each named column of the fit's Jacobian J at z equals central differences of the residual's
    first n rows (step ``step`` on that column) to 1e-5 of the column's largest entry."""
    for name in columns:
        j = names.index(name)
        e = np.zeros(len(names))
        e[j] = step
        fd = (prob.residual(z + e) - prob.residual(z - e))[:n] / (2 * step)
        scale = np.abs(fd).max()
        assert scale > 1e-3, name
        assert np.abs(J[:n, j] - fd).max() / scale < 1e-5, name


def test_a_tool_wrench_is_recovered_with_it_and_biases_the_fit_without_it(cogiro):
    groups = ["anchors", "attachments", "dead_lengths"]
    rng, idx, sd, truth, th = _truth(cogiro, groups, 1)
    data = cal.simulate(
        with_wrench(truth, WRENCH), cogiro, _poses(cogiro, rng, 30), sigma=1e-9, sigma_rad=1e-9
    )
    n = len(data.sample)
    assert n == 30  # every pose reached by the loaded truth
    scale = np.maximum(np.abs(th[idx]), sd)
    fits = {}
    for label, nominal in (("with", with_wrench(cogiro, WRENCH)), ("without", cogiro)):
        c = cal.fit(nominal, data, groups, solver={"tol": 1e-13})
        fits[label] = (c, c.summary(), np.abs(c.estimate - th[idx]) / scale)
    c, s, rel = fits["with"]
    assert s["samples_used"] == n and s["residual_rms_m"] < 1e-9 and s["residual_rms_rad"] < 1e-9
    assert rel.max() < 1e-6
    # the fitted robot carries the load of the data (it predicts under it); the file written from it
    # does not (tests/cli/test_calibrate_wrench.py)
    assert c.calibrated_robot().platform.wrench == with_wrench(cogiro, WRENCH).platform.wrench
    _, s0, rel0 = fits["without"]
    # the load the fit does not know of: millimetres of residual, parameters off by more than their tolerance
    assert s0["samples_used"] == n and s0["residual_rms_m"] > 1e-4 and s0["residual_rms_rad"] > 1e-4
    assert rel0.max() > 1.0


def test_exact_jacobian_under_a_wrench_equals_central_differences(cogiro):
    """Problem.jacobian with the wrench on the platform against central differences of
    Problem.residual (every equilibrium re-solved under the same wrench)."""
    groups = ["anchors", "attachments", "dead_lengths", "mass", "offsets"]
    rng = np.random.default_rng(4)
    loaded = with_wrench(cogiro, WRENCH)
    data = cal.simulate(loaded, loaded, _poses(cogiro, rng, 4), offsets=np.zeros(8), sigma_rad=0.1, rng=rng)
    prob, idx, z, ev, J = evaluated_problem(loaded, data, groups, None, 1e-14, 0.3, rng)
    names = [calibration_names(cogiro)[k] for k in idx]
    n = 6 * len(data.sample)
    assert_jacobian_columns(prob, z, J, names, ("M", "A_1_x", "b_2_y", "d_3", "offset_4"), n, step=1e-5)
    # the wrench reaches the residual: the same z on the unloaded robot gives other poses
    bare = cal.Problem(cogiro, data, idx, prob.sd, solver={"tol": 1e-14})
    assert np.abs(bare.residual(z)[:n] - prob.residual(z)[:n]).max() > 1.0
