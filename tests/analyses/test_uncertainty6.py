"""Spatial pose-error model (cdpr.analyses.uncertainty6) on CoGiRo: without pulleys the error of
the commanded L_TS is the elastic one alone, so it scales as 1/E and vanishes as E → ∞ (position
and orientation); the implicit-function linearisation predicts a small modulus change."""

import numpy as np
import pytest

from cdpr.analyses.uncertainty import drivers, mc_uniforms, parameter_samples, sobol_analysis
from cdpr.analyses.uncertainty6 import PoseErrorModel6, spatial_theta
from cdpr.models.equilibrium6 import solve_spatial
from cdpr.models.platform import rotation_error
from cdpr.parameters import parameter_names6, parameter_values6, robot_with_parameters6
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

P = np.array([[0.0, 0.0, 2.0], [0.5, -0.5, 2.5]])


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro.yaml")


def test_pulleyless_error_is_elastic_and_vanishes_as_E_grows(cogiro):
    m = cogiro.m
    th = parameter_values6(cogiro).copy()
    th[m : 3 * m] = 0.0  # h_i = r_p_i = 0: L_TS is the exact geometric length
    model = PoseErrorModel6(robot_with_parameters6(cogiro, th), P)
    out = {}
    for s in (1.0, 1e3, 1e6):
        t = th.copy()
        t[:m] *= s
        dp, dphi, ok = model.solve(t)
        assert ok.all()
        out[s] = (dp[0], dphi[0])
    assert np.all(out[1e6][0] < 1e-7) and np.all(out[1e6][1] < 1e-8)
    assert np.all(out[1.0][0] > 1e-3)  # the nominal elastic error is not zero
    # first order in 1/E: a 1000 times stiffer cable set gives a 1000 times smaller error
    np.testing.assert_allclose(out[1.0][0] / out[1e3][0], 1e3, rtol=0.02)
    np.testing.assert_allclose(out[1.0][1] / out[1e3][1], 1e3, rtol=0.02)


@pytest.mark.parametrize(
    ("name", "rel", "absolute"), [("E_1", 0.01, 0.0), ("d_3", 0.0, 1e-3), ("M", 0.01, 0.0)]
)
def test_linearisation_predicts_small_change(cogiro, name, rel, absolute):
    model = PoseErrorModel6(cogiro, P)
    th0 = parameter_values6(cogiro)
    lin = model.linearise()
    k = parameter_names6(cogiro.m).index(name)
    th = th0.copy()
    th[k] += rel * th0[k] + absolute  # 1 % of E or M, 1 mm of a dead length
    full = solve_spatial(robot_with_parameters6(cogiro, th), model.p, model.rotvec, L0=model.L0)
    d = th[k] - th0[k]
    pred = lin["P_s"] + lin["S"][:, :3, k] * d
    step = np.linalg.norm(full["P_s"] - lin["P_s"], axis=1)
    assert np.all(step > 0)
    assert np.all(np.linalg.norm(full["P_s"] - pred, axis=1) < 0.05 * step)
    # orientation: the predicted rotation vector change agrees with the full solve's rotation
    ang = rotation_error(full["R_s"], lin["R_s"])
    np.testing.assert_allclose(np.linalg.norm(lin["S"][:, 3:, k] * d, axis=1), ang, rtol=0.05, atol=1e-9)


def test_monte_carlo_linear_agrees_with_full_solves_for_small_spreads(cogiro):
    """Per-cable E within ±1 % and dead lengths within ±1 mm (the study's drivers): the first-order
    pose of every sample is within 5 % of its full-solve displacement from the nominal pose."""
    spec = {
        "young_modulus_Pa": {
            "dist": "uniform",
            "low": 0.99 * cogiro.arrays.E[0],
            "high": 1.01 * cogiro.arrays.E[0],
        },
        "dead_length_offset_m": {"dist": "uniform", "low": -1e-3, "high": 1e-3},
    }
    drs = drivers(spec, cogiro.m)
    assert len(drs) == 2 * cogiro.m
    th6 = spatial_theta(cogiro, parameter_samples(cogiro, drs, mc_uniforms(7, 0, 6, len(drs))))
    model = PoseErrorModel6(cogiro, P[:1])
    lin = model.linearise()
    d = th6 - lin["theta0"]
    for t, dt in zip(th6, d, strict=True):
        full = solve_spatial(robot_with_parameters6(cogiro, t), model.p, model.rotvec, L0=model.L0)
        pred = lin["P_s"] + np.einsum("nak,k->na", lin["S"][:, :3], dt)
        step = np.linalg.norm(full["P_s"] - lin["P_s"], axis=1)
        assert np.all(step > 0)
        assert np.all(np.linalg.norm(full["P_s"] - pred, axis=1) < 0.05 * step)


def test_sobol_indices_of_spatial_responses_are_bounded(cogiro):
    """SALib Sobol indices of ‖δp‖ and δφ under common E (±10 %) and dead lengths (±1 mm): every
    index within [-conf, 1 + conf] and the first-order indices sum to at most 1 + conf."""
    E = cogiro.arrays.E[0]
    spec = {
        "young_modulus_Pa": {"dist": "uniform", "low": 0.9 * E, "high": 1.1 * E, "per_cable": False},
        "dead_length_offset_m": {"dist": "uniform", "low": -1e-3, "high": 1e-3, "per_cable": False},
    }
    drs = drivers(spec, cogiro.m)
    model = PoseErrorModel6(cogiro, P[:1])

    def evaluate(theta):
        dp, dphi, ok = model.solve(spatial_theta(cogiro, theta))
        assert ok.all()
        return np.column_stack([dp[:, 0], dphi[:, 0]])

    idx, Y, _ = sobol_analysis(evaluate, drs, cogiro, 32, 3, ["dp_norm_m", "dphi_rad"])
    assert len(idx) == 4 and np.all(np.isfinite(idx[["S1", "ST"]].to_numpy()))
    assert np.all(idx["ST"] <= 1 + idx["ST_conf"]) and np.all(idx["ST"] >= -idx["ST_conf"])
    for _, g in idx.groupby("output"):
        assert g["S1"].sum() <= 1 + g["S1_conf"].sum()
