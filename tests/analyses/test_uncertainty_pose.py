"""The pose error model of a robot solved as a pose (cdpr.analyses.uncertainty.PoseErrorModel,
responses ‖δp‖ and δφ) on CoGiRo: without pulleys the error of
the commanded L_TS is the elastic one alone, so it scales as 1/E and vanishes as E → ∞ (position
and orientation); the implicit-function linearisation predicts a small modulus change."""

import numpy as np
import pytest

from cdpr.analyses.uncertainty import (
    PoseErrorModel,
    driver_columns,
    drivers,
    mc_uniforms,
    parameter_samples,
    sobol_analysis,
)
from cdpr.errors import CdprError
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.platform import rotation_error
from cdpr.parameters import group_columns, parameter_names, parameter_values, robot_with_parameters
from cdpr.robot import load_robot, with_pulleys, with_values
from tests.conftest import ROBOTS

P = np.array([[0.0, 0.0, 2.0], [0.5, -0.5, 2.5]])


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro_massless.yaml")


def test_pulleyless_error_is_elastic_and_vanishes_as_E_grows(cogiro):
    m = cogiro.m
    th = parameter_values(cogiro).copy()
    th[m : 3 * m] = 0.0  # h_i = r_p_i = 0: L_TS is the exact geometric length
    model = PoseErrorModel(robot_with_parameters(cogiro, th), P)
    out = {}
    for s in (1.0, 1e3, 1e6):
        t = th.copy()
        t[:m] *= s
        y, ok = model.solve(t)
        dp, dphi = y["dp"], y["dphi"]
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
    model = PoseErrorModel(cogiro, P)
    th0 = parameter_values(cogiro)
    lin = model.nominal_pose()
    k = parameter_names(cogiro).index(name)
    th = th0.copy()
    th[k] += rel * th0[k] + absolute  # 1 % of E or M, 1 mm of a dead length
    full = solve_spatial(robot_with_parameters(cogiro, th), model.p, model.rotvec, L0=model.L)
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
    drs = drivers(spec, cogiro)
    assert len(drs) == 2 * cogiro.m
    th6 = parameter_samples(cogiro, drs, mc_uniforms(7, 0, 6, len(drs)))
    model = PoseErrorModel(cogiro, P[:1])
    lin = model.nominal_pose()
    d = th6 - lin["theta0"]
    for t, dt in zip(th6, d, strict=True):
        full = solve_spatial(robot_with_parameters(cogiro, t), model.p, model.rotvec, L0=model.L)
        pred = lin["P_s"] + np.einsum("nak,k->na", lin["S"][:, :3], dt)
        step = np.linalg.norm(full["P_s"] - lin["P_s"], axis=1)
        assert np.all(step > 0)
        assert np.all(np.linalg.norm(full["P_s"] - pred, axis=1) < 0.05 * step)


def first_pose_errors(model, robot):
    """The Sobol evaluator of ``model`` (a pose ``PoseErrorModel`` at one pose): θ samples (k, ·) ->
    (k, 2) = (‖δp‖, δφ), every solve ``ok``."""

    def evaluate(theta):
        y, ok = model.solve(theta)
        assert ok.all()
        return np.column_stack([y["dp"][:, 0], y["dphi"][:, 0]])

    return evaluate


def linearised_against_full(robot, spec, seed, case, min_change):
    """Five samples of ``spec`` on ``robot`` at the poses P: asserts that every sample moves ‖δp‖
    and δφ from the nominal by more than ``min_change`` and that the first-order propagation
    (``linearisations``) predicts the full solves' change within 5 % (uncompensated), or the
    compensated error itself within 5 %. Returns the nominal (‖δp‖, δφ)."""
    drs = drivers(spec, robot)
    th = parameter_samples(robot, drs, mc_uniforms(seed, 0, 5, len(drs)))
    model = PoseErrorModel(robot, P, case=case)
    lins = model.linearisations(driver_columns(drs))
    pos, rot = lins["dp"], lins["dphi"]
    (y, ok), (y0, _) = model.solve(th), model.solve(parameter_values(robot))
    assert ok.all() and pos.ok.all()
    dp_f, phi_f, dp0, phi0 = y["dp"], y["dphi"], y0["dp"], y0["dphi"]
    for full, lin, nominal in ((dp_f, pos.dp(th), dp0), (phi_f, rot.dp(th), phi0)):
        change = np.abs(full - nominal)
        assert np.all(change > min_change)
        scale = change if case == "uncompensated" else full
        assert np.all(np.abs(lin - full) < 0.05 * scale)
    return dp0, phi0


def test_sobol_indices_of_spatial_responses_are_bounded(cogiro):
    """SALib Sobol indices of ‖δp‖ and δφ under common E (±10 %) and dead lengths (±1 mm): every
    index within [-conf, 1 + conf] and the first-order indices sum to at most 1 + conf."""
    E = cogiro.arrays.E[0]
    spec = {
        "young_modulus_Pa": {"dist": "uniform", "low": 0.9 * E, "high": 1.1 * E, "per_cable": False},
        "dead_length_offset_m": {"dist": "uniform", "low": -1e-3, "high": 1e-3, "per_cable": False},
    }
    drs = drivers(spec, cogiro)
    model = PoseErrorModel(cogiro, P[:1])
    evaluate = first_pose_errors(model, cogiro)

    idx, Y, _ = sobol_analysis(evaluate, drs, cogiro, 32, 3, ["dp_norm_m", "dphi_rad"])
    assert len(idx) == 4 and np.all(np.isfinite(idx[["S1", "ST"]].to_numpy()))
    assert np.all(idx["ST"] <= 1 + idx["ST_conf"]) and np.all(idx["ST"] >= -idx["ST_conf"])
    for _, g in idx.groupby("output"):
        assert g["S1"].sum() <= 1 + g["S1_conf"].sum()


# ---- the study's model (issue 19): both cases, the linearisations in the drivers' columns ---------
SMALL = {  # per-cable E within ±1 % and dead lengths within ±1 mm (first order must hold)
    "young_modulus_Pa": {"dist": "uniform", "low": 0.99 * 102.2e9, "high": 1.01 * 102.2e9, "per_cable": True},
    "dead_length_offset_m": {"dist": "uniform", "low": -1e-3, "high": 1e-3, "per_cable": True},
}


@pytest.mark.parametrize("case", ["uncompensated", "compensated"])
def test_linearised_norms_agree_with_full_solves_for_small_tolerances(cogiro, case):
    """‖δp‖ and δφ of the first-order propagation (``linearisations``: 1/E columns, rotation vector)
    against full solves of each sample: the change from the nominal pose error is predicted within
    5 % (uncompensated), and the compensated error itself (nominal 0) within 5 %."""
    dp0, phi0 = linearised_against_full(cogiro, SMALL, 11, case, min_change=0.0)
    if case == "compensated":  # the nominal robot holds the pose: a round trip
        assert np.all(dp0 < 1e-8) and np.all(phi0 < 1e-8)


def test_a_parameter_without_variance_has_zero_sobol_indices(cogiro):
    """A mass drawn from a degenerate uniform (low = high = the nominal mass) never moves the pose:
    its first-order and total Sobol indices on ‖δp‖ and δφ are exactly 0; the dead lengths' not."""
    M = cogiro.platform.mass
    spec = {
        "dead_length_offset_m": {"dist": "uniform", "low": -1e-3, "high": 1e-3, "per_cable": False},
        "mass_kg": {"dist": "uniform", "low": M, "high": M},
    }
    drs = drivers(spec, cogiro)
    model = PoseErrorModel(cogiro, P[:1])
    evaluate = first_pose_errors(model, cogiro)

    idx, _, _ = sobol_analysis(evaluate, drs, cogiro, 16, 5, ["dp", "dphi"])
    m_rows, d_rows = idx[idx.name == "M"], idx[idx.name == "d_all"]
    assert len(m_rows) == 2 and np.all(m_rows[["S1", "ST"]].to_numpy() == 0.0)
    assert np.all(d_rows["ST"] > 0.5)


def test_on_a_point_mass_robot_dphi_is_zero_and_dp_is_the_point_mass_model(cdpr4):
    """The 6-DoF model of a suspended point mass: δφ = 0 (no orientation), and ‖δp‖ and its
    linearisation agree with the point-mass physical model (``uncertainty.PoseErrorModel``, an
    independent solver) for per-cable moduli."""
    p = np.array([[0.0, 0.0, 1.5], [0.8, -0.6, 1.0]])
    spec = {"young_modulus_Pa": {"dist": "uniform", "low": 67.2e9, "high": 137.2e9, "per_cable": True}}
    drs = drivers(spec, cdpr4)
    th = parameter_samples(cdpr4, drs, mc_uniforms(3, 0, 4, len(drs)))
    six = PoseErrorModel(cdpr4, p, pose=True)
    point = PoseErrorModel(cdpr4, p, redundancy="physical")
    assert six.responses == ("dp", "dphi") and point.responses == ("dp",)
    (y6, ok6), (y3, ok3) = six.solve(th), point.solve(th)
    assert ok6.all() and ok3.all()
    assert np.all(y6["dphi"] == 0.0)
    np.testing.assert_allclose(y6["dp"], y3["dp"], rtol=1e-6, atol=1e-9)
    lins = six.linearisations(driver_columns(drs))
    np.testing.assert_allclose(
        lins["dp"].dp(th), point.linearise(driver_columns(drs)).dp(th), rtol=1e-5, atol=1e-9
    )
    assert np.all(lins["dphi"].dp(th) == 0.0)


def test_the_mass_driver_sets_the_last_column_on_both_kinds_of_robot(cogiro, cdpr4):
    """One θ per robot: M is its last column on a rigid platform (10 m + 4) and on a point mass
    (7 m + 1), and the drivers keep their draw order (the study's keys, then cables)."""
    spec = {"mass_kg": {"dist": "uniform", "low": 80.0, "high": 100.0}}
    for robot in (cogiro, cdpr4):
        (dr,) = drivers(spec, robot)
        assert dr.columns == (len(parameter_names(robot)) - 1,) and parameter_names(robot)[-1] == "M"


# ---- a rigid platform's attachments b_i and centre of mass c as uncertain parameters -------------
RIGID = {
    "young_modulus_Pa": {
        "dist": "uniform",
        "low": 0.99 * 102.2e9,
        "high": 1.01 * 102.2e9,
        "per_cable": False,
    },
    "attachment_offset_m": {"dist": "uniform", "low": -1e-3, "high": 1e-3, "per_cable": True},
    "com_offset_m": {"dist": "uniform", "low": -5e-3, "high": 5e-3},
}


def test_attachment_and_com_drivers_set_the_b_and_c_columns(cogiro, cdpr4):
    """The drivers of attachment_offset_m (b_i_x/y/z per cable) and com_offset_m (c_x, c_y, c_z)
    come after every point-mass driver (a study without them keeps its drivers' numbers) and set the
    b and c columns of the robot's θ (E, h, r_p, d, A, b, c, M): the sampled robot has the drawn
    attachments and centre of mass; a point mass refuses them in one line."""
    m = cogiro.m
    drs = drivers(RIGID, cogiro)
    names = [d.name for d in drs]
    assert names[0] == "E_all" and names[1:4] == ["b_1_x", "b_1_y", "b_1_z"]
    assert names[-3:] == ["c_x", "c_y", "c_z"] and len(drs) == 1 + 3 * m + 3
    assert [d.name for d in drivers({k: RIGID[k] for k in ("young_modulus_Pa",)}, cogiro)] == ["E_all"]
    th = parameter_samples(cogiro, drs, mc_uniforms(4, 0, 6, len(drs)))
    assert th.shape == (6, 10 * m + 4)
    cols = group_columns(cogiro)
    E = th[:, :m]
    assert np.all(E == E[:, :1]) and np.ptp(E[:, 0]) > 0  # one shared modulus
    fixed = np.r_[m : 7 * m, 10 * m + 3]  # h, r_p, d, A and M stay nominal
    np.testing.assert_array_equal(th[:, fixed], np.tile(parameter_values(cogiro)[fixed], (6, 1)))
    b0, c0 = cogiro.arrays.b.ravel(), cogiro.arrays.com
    db, dc = th[:, cols["b"]] - b0, th[:, cols["c"]] - c0
    assert np.abs(db).max() <= 1e-3 and db.std() > 2e-4 and np.abs(dc).max() <= 5e-3 and dc.std() > 1e-3
    for k in (0, 5):
        r = robot_with_parameters(cogiro, th[k])
        np.testing.assert_array_equal(r.arrays.b.ravel(), th[k, cols["b"]])
        np.testing.assert_array_equal(r.arrays.com, th[k, cols["c"]])
        assert r.platform.mass == th[k, -1] == cogiro.platform.mass
    with pytest.raises(
        CdprError, match=r"uncertainty.parameters.attachment_offset_m: robot .* is a point mass"
    ):
        drivers(RIGID, cdpr4)


@pytest.mark.parametrize("case", ["uncompensated", "compensated"])
def test_attachment_and_com_tolerances_linearised_against_full_solves(cogiro, case):
    """Millimetre attachment and centre-of-mass tolerances on CoGiRo: the first-order propagation
    (dp*/dθ and dφ*/dθ of b_i and c by the implicit-function theorem) predicts the full solves'
    change of ‖δp‖ and δφ within 5 % (uncompensated) and the compensated error itself within 5 %;
    the tolerances do move the pose."""
    linearised_against_full(cogiro, RIGID, 12, case, min_change=1e-6)


def test_com_offset_alone_tilts_the_platform_and_has_sobol_weight(cogiro):
    """The centre of mass off the reference point turns the platform under gravity (a moment): with
    the moduli held, δφ moves with c, and c's total Sobol index on δφ is large."""
    spec = {"com_offset_m": {"dist": "uniform", "low": -0.02, "high": 0.02}}
    drs = drivers(spec, cogiro)
    model = PoseErrorModel(cogiro, P[:1])
    evaluate = first_pose_errors(model, cogiro)

    idx, _, _ = sobol_analysis(evaluate, drs, cogiro, 16, 5, ["dp", "dphi"])
    phi = idx[idx.output == "dphi"]
    assert set(phi.name) == {"c_x", "c_y", "c_z"}
    assert phi[phi.name.isin(["c_x", "c_y"])]["ST"].sum() > 0.5  # horizontal offsets tilt it


def test_heavy_samples_from_the_linear_start_reach_the_desired_starts_answers():
    """A heavy CoGiRo (0.0631 kg/m) with DR pulleys (the general coupling): the full solves of
    perturbed samples started from the linear shift of the nominal equilibria (the default) give
    the answers of the solves started at the desired poses, to the solver's tolerance, and the
    same statuses."""
    robot = with_pulleys(
        with_values(load_robot(ROBOTS / "cogiro_massless.yaml"), linear_density=0.0631), "DR", 0.075, 0.05
    )
    n = parameter_names(robot)
    th = np.repeat(parameter_values(robot)[None], 3, axis=0)
    th[:, n.index("M")] *= [0.97, 1.0, 1.04]
    th[:, n.index("E_1")] *= [1.2, 0.8, 1.0]
    th[:, n.index("d_3")] += [0.004, -0.003, 0.0]
    lin, desired = PoseErrorModel(robot, P), PoseErrorModel(robot, P, start="desired")
    a, ok_a = lin.solve(th)
    b, ok_b = desired.solve(th)
    np.testing.assert_array_equal(ok_a, ok_b)
    assert ok_a.all()
    np.testing.assert_allclose(a["dp"], b["dp"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(a["dphi"], b["dphi"], rtol=0, atol=1e-9)
