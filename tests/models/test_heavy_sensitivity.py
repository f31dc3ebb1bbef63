"""Heavy-cable pose sensitivities (issue 38): the linear densities rho_i join θ, and dp*/dθ and
dφ*/dθ of the heavy equilibrium (``cdpr.models.heavy_sensitivity``, implicit-function theorem on the
catenaries' balance) agree with central differences of full heavy direct solves, on a point mass
(CDPR4 with heavy cables, SR pulleys) and on a rigid platform (CoGiRo with its 4 mm cable's density).
A massless robot's θ is unchanged."""

from pathlib import Path

import numpy as np
import pytest

from cdpr import solve as door
from cdpr.errors import CdprError
from cdpr.models import heavy_sensitivity as hs
from cdpr.models.platform import rotvec_of
from cdpr.parameters import (
    calibration_names,
    parameter_names,
    parameter_units,
    parameter_values,
    robot_size,
    robot_with_parameters,
    select_groups,
)
from cdpr.robot import load_robot, with_pulleys, with_values
from tests.models import heavy_fd_reference as fdr

ROBOTS = Path(__file__).resolve().parents[2] / "config" / "robots"


def _robot(name, rho):
    return with_values(load_robot(ROBOTS / f"{name}.yaml"), linear_density=rho)


def test_theta_has_rho_before_mass_only_with_heavy_cables():
    light = _robot("cdpr4", 0.0)
    heavy = _robot("cdpr4", 0.5)
    m = heavy.m
    assert parameter_names(heavy)[: 7 * m] == parameter_names(light)[:-1]
    assert parameter_names(heavy)[7 * m :] == ["rho_1", "rho_2", "rho_3", "rho_4", "M"]
    assert parameter_units(heavy)[7 * m : 8 * m] == ["kg/m"] * m
    assert robot_size(heavy) == 8 * m + 1 and robot_size(light) == 7 * m + 1
    assert not any(n.startswith("rho") for n in calibration_names(light))
    th = parameter_values(heavy)
    np.testing.assert_allclose(th[7 * m : 8 * m], 0.5)
    th[7 * m + 2] = 0.7
    th[-1] = 3.0
    r = robot_with_parameters(heavy, th)
    np.testing.assert_allclose(r.arrays.rho, [0.5, 0.5, 0.7, 0.5])
    assert r.platform.mass == 3.0
    np.testing.assert_array_equal(parameter_values(r), th)
    idx = select_groups(heavy, ["linear_densities"])
    assert [calibration_names(heavy)[k] for k in idx] == ["rho_1", "rho_2", "rho_3", "rho_4"]
    with pytest.raises(CdprError, match="linear_densities"):
        select_groups(light, ["linear_densities"])


def _central(robot, p, rv, L0, name, h):
    """dx*/dθ by central differences of full heavy direct solves (numpy reference, tight tol)."""
    out = []
    for s in (h, -h):
        q = door.solve(
            fdr.perturbed_robot(robot, name, s),
            p,
            rv,
            redundancy="physical",
            engine="numpy",
            L0=L0,
            tol=1e-14,
        )
        out.append(q)
    dp = (out[0]["P_s"][0] - out[1]["P_s"][0]) / (2 * h)
    dphi = rotvec_of(out[0]["R_s"][:1] @ np.swapaxes(out[1]["R_s"][:1], 1, 2))[0] / (2 * h)
    return np.concatenate([dp, dphi])


def _fd_step(robot, name):
    if name == "M":
        return 1e-4 * robot.platform.mass
    if name.startswith("E_"):
        return 1e-4 * robot.cables[0].material.E
    if name.startswith("rho_"):
        return 1e-3 * robot.cables[0].material.rho
    return 1e-5


@pytest.mark.slow
@pytest.mark.parametrize(
    ("name", "rho", "names"),
    [
        (
            "cdpr4",
            0.5,
            ["E_1", "h_2", "r_p_3", "d_4", "A_1_x", "A_3_z", "rho_1", "rho_2", "rho_3", "rho_4", "M"],
        ),
        (
            "cogiro",
            0.063,
            ["E_1", "h_2", "r_p_3", "d_4", "A_5_x", "b_6_y", "b_2_z", "c_z", "rho_1", "rho_7", "M"],
        ),
    ],
)
def test_heavy_sensitivities_match_central_differences(name, rho, names):
    robot = _robot(name, rho)
    assert robot.heavy
    A = robot.A
    p = np.array([[A[:, 0].mean() + 0.1, A[:, 1].mean() - 0.05, 0.5 * A[:, 2].min()]])
    rv = np.zeros((1, 3)) if robot.point_mass else np.array([[0.02, -0.01, 0.03]])
    L0 = door.solve(robot, p, rv, redundancy="physical", engine="numpy")["L0"]
    res = door.sensitivities(robot, p, rv, redundancy="physical", L=L0, names=names)
    assert res["status"][0] == "ok" and res["smooth"][0]
    assert res["S"].shape == (1, 6, len(names))
    for k, nm in enumerate(names):
        fd = _central(robot, p, rv, L0, nm, _fd_step(robot, nm))
        an = res["S"][0, :, k]
        scale = np.abs(an).max()
        assert scale > 0, nm
        np.testing.assert_allclose(an, fd, rtol=0, atol=2e-6 * scale, err_msg=nm)
    if robot.point_mass:  # a point mass does not turn
        assert not res["S"][0, 3:].any()


def test_heavy_rest_length_sensitivities_match_central_differences():
    robot = _robot("cdpr4", 0.5)
    p = np.array([[0.2, -0.1, 1.5]])
    rv = np.zeros((1, 3))
    res = door.solve(robot, p, rv, redundancy="physical", engine="numpy", tol=1e-14)
    L0 = res["L0"]
    S, t, cond = hs.rest_length_sensitivities(robot, res["P_s"], res["R_s"], L0)
    assert (t > 0).all() and np.isfinite(cond).all()
    for i in range(robot.m):
        e = np.zeros(robot.m)
        e[i] = 1e-5
        up = door.solve(robot, p, rv, redundancy="physical", engine="numpy", L0=L0 + e, tol=1e-14)["P_s"][0]
        dn = door.solve(robot, p, rv, redundancy="physical", engine="numpy", L0=L0 - e, tol=1e-14)["P_s"][0]
        fd = (up - dn) / 2e-5
        np.testing.assert_allclose(S[0, :3, i], fd, rtol=0, atol=1e-6 * np.abs(fd).max())


def test_heavy_sensitivities_refuse_paper_mode():
    with pytest.raises(CdprError, match="physical mode only"):
        door.sensitivities(_robot("cdpr4", 0.5), [[0.0, 0.0, 1.5]], redundancy="paper")


@pytest.mark.slow
def test_heavy_sensitivities_on_dr_pulleys_match_full_solves():
    """DR pulleys (the arm turns with the strand's direction, the exit point slides on the sheave):
    the exact partials give dp*/dθ equal to central differences of full heavy direct solves."""
    robot = with_pulleys(_robot("cdpr4", 0.5), kind="DR")
    p, rv = np.array([[0.6, -0.4, 1.2]]), np.zeros((1, 3))
    names = ["r_p_1", "h_2", "A_3_z", "d_4", "rho_2"]
    L0 = door.solve(robot, p, rv, redundancy="physical", engine="numpy")["L0"]
    res = door.sensitivities(robot, p, rv, redundancy="physical", L=L0, names=names)
    assert res["status"][0] == "ok" and res["smooth"][0]
    for k, nm in enumerate(names):
        fd = _central(robot, p, rv, L0, nm, _fd_step(robot, nm))
        an = res["S"][0, :, k]
        np.testing.assert_allclose(an, fd, rtol=0, atol=2e-6 * np.abs(an).max(), err_msg=nm)


def test_heavy_sensitivities_of_either_engine_agree():
    """The door's heavy sensitivities solve the equilibria by the chosen engine (the derivatives are
    the numpy reference's either way): on CoGiRo with DR pulleys at two tilted poses the compiled
    and numpy engines give the same statuses and smooth flags, poses within 1e-12 m and dx*/dθ
    within 1e-8 of each column's largest entry."""
    robot = with_pulleys(_robot("cogiro", 0.0631), kind="DR", h=0.075, r_p=0.05)
    p = np.array([[0.0, 0.0, 2.0], [1.0, -0.5, 1.6]])
    rv = np.array([[0.02, -0.01, 0.03], [0.0, 0.05, 0.0]])
    names = ["E_1", "d_4", "A_5_x", "rho_2", "M"]
    L0 = door.solve(robot, p, rv, redundancy="physical")["L0"]
    a = door.sensitivities(robot, p, rv, redundancy="physical", L=L0, names=names)
    b = door.sensitivities(robot, p, rv, redundancy="physical", L=L0, names=names, engine="numpy")
    np.testing.assert_array_equal(a["status"], b["status"])
    np.testing.assert_array_equal(a["smooth"], b["smooth"])
    assert (a["status"] == "ok").all()
    np.testing.assert_allclose(a["P_s"], b["P_s"], rtol=0, atol=1e-12)
    scale = np.abs(b["S"]).max(axis=1, keepdims=True)
    assert (np.abs(a["S"] - b["S"]) <= 1e-8 * scale).all()
