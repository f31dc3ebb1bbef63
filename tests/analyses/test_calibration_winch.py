"""Calibration of a robot with winches (cdpr.analyses.calibration on a robot file with ``winch:``): the
commanded lengths go through the drums' map (cdpr.models.drive.realised_rest_lengths) before the
equilibrium; the Jacobian carries its chain rule; a model without the drums cannot reach the noise
floor, the model with them recovers the truth. The numpy engine throughout (the compiled one's
first call costs a JIT compile of about a minute on the 2-core machine; the engines are twins)."""

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.analyses.compensation import compensated_pose
from cdpr.models.drive import realised_rest_lengths
from cdpr.models.inverse import L_TS
from cdpr.parameters import calibration_names, select_groups
from cdpr.pipeline.calibration_files import write_robot
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

BOX = [-1.8, 1.8, -1.8, 1.8, 0.8, 3.5]
NP = "numpy"


@pytest.fixture(scope="module")
def cdpr4w():
    return load_robot(ROBOTS / "cdpr4_winch.yaml")


def _poses(rng, n):
    return rng.uniform(np.array(BOX[::2]), np.array(BOX[1::2]), (n, 3))


def test_jacobian_through_the_winch_equals_central_differences(cdpr4w):
    """Problem.jacobian with the winch map (dP/do_i = -dP/dL0_i dL0_i/dL_cmd,i, dP/dd_i gains
    dP/dL0_i dL0_i/dd_i, and the same on the tension rows) against central differences of
    Problem.residual, which re-maps the commands and re-solves every equilibrium."""
    groups = ["anchors", "dead_lengths", "offsets", "pulleys", "moduli", "mass"]
    rng = np.random.default_rng(6)
    data = cal.simulate(cdpr4w, cdpr4w, _poses(rng, 6), offsets=np.zeros(4), tensions=True, engine=NP)
    data.pose[::2] = np.nan  # half with tensions only
    idx = select_groups(cdpr4w, groups)
    sd = cal.prior_sd(cdpr4w, idx, cal.parse_priors(None))
    prob = cal.Problem(cdpr4w, data, idx, sd, solver={"tol": 1e-14}, engine=NP)
    assert prob.winch
    z = 0.3 * rng.standard_normal(len(idx))
    ev = prob.evaluate(z)
    assert ((ev["status"] == "ok") & ev["smooth"]).all()
    J = prob.jacobian(z)
    fd = np.empty_like(J)
    for j in range(len(idx)):
        e = np.zeros(len(idx))
        e[j] = 1e-5
        fd[:, j] = (prob.residual(z + e) - prob.residual(z - e)) / 2e-5
    scale = np.abs(fd).max(axis=0)
    err = np.abs(J - fd).max(axis=0) / scale
    assert err.max() < 1e-5, (calibration_names(prob.robot)[idx[int(np.argmax(err))]], err.max())
    # the chain rule matters: without it the offset and dead-length columns would be off by more
    no_winch = cal.Problem(cal.without_winches(cdpr4w), data, idx, sd, solver={"tol": 1e-14}, engine=NP)
    J0 = no_winch.jacobian(z)
    assert (np.abs(J0 - fd).max(axis=0) / scale).max() > 1e-4


def test_the_winch_model_recovers_the_truth_the_drumless_model_cannot(cdpr4w):
    """Noise-free data of a perturbed robot with drums: the exact model with the drums recovers every
    parameter to 1e-6 relative; the same model without them (the drums' length error, millimetres,
    unmodelled) leaves a residual far above the 1 nm data."""
    groups = ["anchors", "dead_lengths", "pulleys", "moduli"]
    rng = np.random.default_rng(3)
    idx = select_groups(cdpr4w, groups)
    sd = cal.prior_sd(cdpr4w, idx, cal.parse_priors(None))
    truth, th = cal.perturbed(cdpr4w, idx, sd, rng)
    assert truth.winches == cdpr4w.winches
    data = cal.simulate(truth, cdpr4w, _poses(rng, 40), sigma=1e-9, engine=NP)
    c = cal.fit(cdpr4w, data, groups, solver={"tol": 1e-13}, engine=NP)
    rel = np.abs(c.estimate - th[idx]) / np.abs(th[idx])
    assert rel.max() < 1e-6, (c.names[int(np.argmax(rel))], rel.max())
    assert c.summary()["residual_rms_m"] < 1e-9
    blind = cal.fit(cal.without_winches(cdpr4w), data, groups, solver={"tol": 1e-13}, engine=NP)
    assert blind.summary()["residual_rms_m"] > 1e-5


def test_simulate_and_check_go_through_the_drums(cdpr4w):
    """The data keep the commands L_TS; the true robot settles under the realised lengths; check
    with the robot file's winch predicts them exactly, the drumless robot is off by the winch error."""
    rng = np.random.default_rng(8)
    P = _poses(rng, 20)
    data = cal.simulate(cdpr4w, cdpr4w, P, sigma=1e-9, engine=NP)
    np.testing.assert_array_equal(data.L, L_TS(cdpr4w, P)[: len(data.L)])
    assert cal.check(cdpr4w, data, engine=NP)["max_m"] < 1e-7
    off = cal.check(cal.without_winches(cdpr4w), data, engine=NP)
    assert off["median_m"] > 1e-4
    L0, _, _ = realised_rest_lengths(cdpr4w, data.L)
    assert np.abs(L0 - data.L).max() > 5e-4


def test_compensation_through_the_drums(cdpr4w):
    """A model that knows the drums commands commanded_for its wanted lengths: the true robot reaches
    the target; a drumless model's commands leave the winch error."""
    p = np.array([[0.3, -0.4, 1.5], [-1.0, 0.8, 2.5]])
    ex = cal.executed_lengths(cdpr4w, cdpr4w)
    good = compensated_pose(cdpr4w, p, actual=cdpr4w, realise=ex, engine=NP)
    assert (good["status"] == "ok").all() and good["dp"].max() < 1e-8
    blind = cal.without_winches(cdpr4w)
    bad = compensated_pose(blind, p, actual=cdpr4w, realise=cal.executed_lengths(blind, cdpr4w), engine=NP)
    assert bad["dp"].min() > 1e-4
    assert cal.executed_lengths(blind, blind) is None


def test_write_robot_keeps_the_winch(cdpr4w, tmp_path):
    rng = np.random.default_rng(9)
    data = cal.simulate(cdpr4w, cdpr4w, _poses(rng, 10), sigma=1e-9, engine=NP)
    c = cal.fit(cdpr4w, data, ["dead_lengths"], engine=NP)
    write_robot(tmp_path / "r.yaml", c, "x.csv")
    back = load_robot(tmp_path / "r.yaml")
    assert back.winches == cdpr4w.winches


def test_standard_model_and_spatial_winches(cdpr4w):
    assert all(w is None for w in cal.model_robot(cdpr4w, "standard").winches)
    assert cal.model_robot(cdpr4w, "rigid").winches == cdpr4w.winches
    import dataclasses

    cog = load_robot(ROBOTS / "cogiro.yaml")
    cogw = dataclasses.replace(
        cog, cables=tuple(dataclasses.replace(c, winch=cdpr4w.winches[0]) for c in cog.cables)
    )
    data = cal.Data(
        sample=np.array(["s1"]),
        L=np.full((1, cog.m), 30.0),
        pose=np.zeros((1, 3)),
        sigma=np.ones(1),
        encoder=False,
        source="d.csv",
        rotvec=np.zeros((1, 3)),
    )
    # a spatial robot with winches maps its commands through the drums (no longer refused): 30 m is
    # more than the drum holds, outside its range, flagged (the drum map of a 6-DoF platform is
    # tested in test_calibration_platform_tensions.py)
    prob = cal.Problem(cogw, data, np.arange(8), np.ones(8))
    assert prob.winch and list(prob.evaluate(np.zeros(8))["status"]) == [cal.DRUM_RANGE]
    assert cal.check(cogw, data)["samples"][0]["status"] == cal.DRUM_RANGE
