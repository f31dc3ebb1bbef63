"""Sensitivities under an external wrench (issue 41, ``Platform.wrench``): a constant world-frame force
at p and moment about p depends neither on the pose nor on a parameter, so dx*/dθ follows from the
same balance with the wrench in it (its Jacobian unchanged; the mass's column moves the weight
only). Checked against central differences of full re-solves of the perturbed robot carrying the
same wrench, on both engines: a rigid platform (CoGiRo, and CDPR4's frame with a rigid platform,
hang4_6dof) under a force and a moment, and the point mass CDPR4 under a force in paper mode and in
physical mode, where the mass column is the one that changes (a force beside the weight does not
scale with M)."""

import numpy as np
import pytest

from cdpr.compiled import sensitivity as fast
from cdpr.models import sensitivity as ref
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.platform import rotvec_of
from cdpr.parameters import parameter_names, parameter_values, robot_with_parameters
from cdpr.robot import load_robot, with_values, with_wrench
from cdpr.solve import sensitivities, subset_sensitivities
from cdpr.solve import solve as solve_any
from tests.analyses.test_uncertainty_pose import SMALL, linearised_against_full
from tests.compiled.test_equilibrium_pose import BOXES
from tests.compiled.test_sensitivity_pose import ROUNDOFF, _errors, _fd_of_the_solve, _poses
from tests.conftest import ROBOTS
from tests.models.test_sensitivity import _finite_differences, _robot

WRENCH = (60.0, -40.0, 25.0, 8.0, -5.0, 3.0)  # N, N m


@pytest.mark.parametrize("robot_file", ["cogiro_massless.yaml", "hang4_6dof.yaml"])
def test_rigid_platform_sensitivities_with_a_wrench_equal_finite_differences(robot_file):
    """Both engines agree to ``ROUNDOFF`` at the same equilibria under the wrench, and at three smooth
    ones equal central differences of the full solve of the perturbed robot with the same wrench
    (the bound of ``test_sensitivity_pose``); the wrench moved the sensitivities."""
    base = load_robot(ROBOTS / robot_file)
    r = with_wrench(base, WRENCH)
    p, rv, L0 = _poses(r, BOXES[robot_file], 20, seed=7)
    res = solve_spatial(r, p, rv, L0=L0)
    a, b = ref.sensitivities_at(r, res), fast.sensitivities_at(r, res)
    sm = a["smooth"]
    np.testing.assert_array_equal(sm, b["smooth"])
    assert sm.sum() >= 10
    assert _errors(b["S"], a["S"], sm, True).max() < ROUNDOFF
    every = parameter_names(r, rigid=True)
    names = ["E_1", "d_4", "h_2", "r_p_3", "A_1_x", "A_3_z", "b_2_y", "b_4_z", "c_x", "c_z", "M"]
    assert robot_with_parameters(r, parameter_values(r)).platform.wrench == WRENCH
    moved = 0
    for i in np.flatnonzero(sm)[:3]:
        for name in names:
            fd, h = _fd_of_the_solve(r, res, i, name)
            for S in (a["S"], b["S"]):
                x = S[i, :, every.index(name)]
                if not fd.any():  # a slack cable's own parameters do not move the platform
                    assert not x.any(), (name, x)
                    continue
                moved += 1
                assert np.abs(x - fd).max() <= 1e-6 * np.abs(fd).max() + 1e-13 / h, (name, x, fd)
    assert moved >= 2 * 3 * (len(names) - 3)
    plain = ref.sensitivities_at(base, solve_spatial(base, p, rv, L0=L0))
    assert np.abs(plain["S"][sm] - a["S"][sm]).max() > 1e-3 * np.abs(a["S"][sm]).max()


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
@pytest.mark.parametrize("mode", ["paper", "physical"])
def test_point_mass_sensitivities_with_a_force_equal_finite_differences(cdpr4, mode, engine):
    """CDPR4 (SR) under a side and downward force: ``cdpr.solve.sensitivities`` (paper mode's subsets,
    the physical fast path) equals central differences of full solves of the perturbed robot
    with the same force, every parameter (the mass's column included: the weight alone moves with
    M); the bound of ``test_sensitivity``."""
    robot = with_wrench(_robot(cdpr4, "SR"), (300.0, -200.0, -500.0, 0.0, 0.0, 0.0))
    p = np.array([[0.7, -1.3, 0.4], [-1.6, 0.5, 1.9], [1.1, 1.9, 3.1]])
    res = sensitivities(robot, p, redundancy=mode, engine=engine)
    assert res["smooth"].all(), res["smooth"]
    fd, floor = _finite_differences(robot, p, mode)
    err = np.linalg.norm(res["S"] - fd, axis=1)
    assert (err <= 1e-5 * np.linalg.norm(fd, axis=1) + floor).all()
    M = parameter_names(robot).index("M")
    assert np.abs(fd[:, :, M]).max() > 1e-6
    # the mass column is not (w_ext / M)'s: with the force counted as weight it would differ
    plain = sensitivities(_robot(cdpr4, "SR"), p, redundancy=mode, engine=engine)
    assert np.abs(plain["S"][:, :, M] - res["S"][:, :, M]).max() > 1e-7


def test_subset_sensitivities_with_a_force_agree_across_engines(cdpr4):
    """Every 3-cable subset under a force: the compiled dP*/dθ and dt/dθ equal the numpy reference's."""
    robot = with_wrench(_robot(cdpr4, "DR"), (300.0, -200.0, -500.0, 0.0, 0.0, 0.0))
    p = np.array([[0.7, -1.3, 0.4], [-1.6, 0.5, 1.9], [1.1, 1.9, 3.1]])
    a = subset_sensitivities(robot, p, engine="numpy")
    b = subset_sensitivities(robot, p, engine="compiled")
    ok = a["converged"]
    assert ok.sum() >= 6 and (ok == b["converged"]).all()
    for key in ("S", "St"):
        scale = np.abs(a[key][ok]).max(axis=(0, 1))
        assert (np.abs(a[key][ok] - b[key][ok]) <= 1e-9 * np.where(scale > 0, scale, 1.0)).all(), key


def pose_central_difference(r, p, rv, L0, name, relative=()):
    """(dp*/dθ, dφ*/dθ) of parameter ``name`` at the first pose by central differences of full
    numpy re-solves (tolerance 1e-14) of the perturbed robot under the same rest lengths ``L0``:
    step 1e-4 θ for the names in ``relative``, else 1e-5 (m)."""
    every, theta = parameter_names(r), parameter_values(r)
    i = every.index(name)
    h = 1e-4 * theta[i] if name in relative else 1e-5
    out = []
    for s in (h, -h):
        v = theta.copy()
        v[i] += s
        out.append(
            solve_any(
                robot_with_parameters(r, v), p, rv, redundancy="physical", engine="numpy", L0=L0, tol=1e-14
            )
        )
    return np.concatenate(
        [
            (out[0]["P_s"][0] - out[1]["P_s"][0]) / (2 * h),
            rotvec_of(out[0]["R_s"][:1] @ np.swapaxes(out[1]["R_s"][:1], 1, 2))[0] / (2 * h),
        ]
    )


def test_heavy_cable_sensitivities_with_a_wrench_equal_finite_differences():
    """CoGiRo with heavy cables under a force and a moment (``heavy_sensitivity``, numpy): the
    closed-form columns of the centre of mass and the mass take the weight alone, the differenced
    ones the balance with the wrench; each equals central differences of full heavy re-solves of
    the perturbed robot with the same wrench (the bound of ``test_heavy_sensitivity``)."""
    r = with_wrench(with_values(load_robot(ROBOTS / "cogiro_massless.yaml"), linear_density=0.063), WRENCH)
    p, rv = np.array([[0.4, -0.3, 2.0]]), np.array([[0.02, -0.01, 0.03]])
    L0 = solve_any(r, p, rv, redundancy="physical", engine="numpy")["L0"]
    names = ["E_1", "b_2_z", "c_x", "c_z", "M"]
    res = sensitivities(r, p, rv, redundancy="physical", L=L0, names=names)
    assert res["status"][0] == "ok" and res["smooth"][0]
    for k, name in enumerate(names):
        fd = pose_central_difference(r, p, rv, L0, name, relative=("E_1", "M"))
        an = res["S"][0, :, k]
        assert np.abs(an).max() > 0, name
        np.testing.assert_allclose(an, fd, rtol=0, atol=2e-6 * np.abs(an).max(), err_msg=name)


def test_the_pose_uncertainty_model_takes_the_wrench():
    """The uncertainty study's pose model (``PoseErrorModel``: full solves and the first-order
    propagation of the sensitivities) on CoGiRo under the wrench, compensated (the compensated
    lengths under the wrench), per-cable E and dead lengths uncertain: the nominal robot holds the
    pose (a round trip) and the linearised ‖δp‖ and δφ of each sample are within 5 % of its full
    solve's (``test_uncertainty_pose``). (The uncompensated case's rule, 5 % of the change from the
    nominal, fails at one sample whose δφ change nearly cancels under the wrench, 1.5e-5 rad, while
    the second-order term is 1.7e-6 rad with and without the wrench.)"""
    r = with_wrench(load_robot(ROBOTS / "cogiro_massless.yaml"), WRENCH)
    dp0, phi0 = linearised_against_full(r, SMALL, 11, "compensated", min_change=0.0)
    assert np.all(dp0 < 1e-8) and np.all(phi0 < 1e-8)
