"""A weightless cable (linear density 0) in a robot with heavy cables, slack at the equilibrium: it pulls
with no force and, strictly slack, with none under a small change, so its partials are 0
(``heavy_partials.cable_force_partials``; they were NaN, divided by its zero tension, and
``cdpr.solve.sensitivities`` ended in numpy's "SVD did not converge"). CoGiRo with 0.063 kg/m cables but
cable 1 weightless and paid out 5 cm, under a tool's wrench: the sensitivities are finite and equal
central differences of full heavy re-solves of the perturbed robot (the bound of
``test_heavy_sensitivity``); the slack cable's anchor moves nothing."""

import dataclasses

import numpy as np

from cdpr.models.platform import rotvec_of
from cdpr.robot import load_robot, with_values, with_wrench
from cdpr.solve import sensitivities
from cdpr.solve import solve as solve_any
from tests.conftest import ROBOTS
from tests.models.test_wrench_sensitivity import pose_central_difference

F_TOOL = np.array([0.0, 0.0, -20 * 9.81])
WRENCH = (*F_TOOL, *np.cross([0.2, 0.1, 0.0], F_TOOL))


def test_a_slack_weightless_cable_among_heavy_ones_has_zero_partials():
    r = with_wrench(with_values(load_robot(ROBOTS / "cogiro.yaml"), linear_density=0.063), WRENCH)
    c0 = r.cables[0]
    r = dataclasses.replace(
        r,
        cables=(dataclasses.replace(c0, material=dataclasses.replace(c0.material, rho=0.0)),) + r.cables[1:],
    )
    assert r.heavy and list(r.arrays.rho) == [0.0] + [0.063] * 7
    p, rv = np.array([[0.4, -0.3, 2.0]]), np.array([[0.02, -0.01, 0.03]])
    L0 = solve_any(r, p, rv, redundancy="physical", engine="numpy")["L0"].copy()
    L0[0, 0] += 0.05  # cable 1 paid out: slack
    eq = solve_any(r, p, rv, redundancy="physical", engine="numpy", L0=L0, tol=1e-14)
    assert eq["status"][0] == "ok" and eq["cable_status"][0, 0] == "slack"
    assert (eq["cable_status"][0, 1:] == "catenary").all()
    P, RV = eq["P_s"], rotvec_of(eq["R_s"])
    names = ["A_1_x", "A_3_y", "b_2_z", "rho_4", "M"]
    res = sensitivities(r, P, RV, redundancy="physical", L=L0, names=names)
    assert res["status"][0] == "ok" and np.isfinite(res["S"]).all()
    for k, name in enumerate(names):
        fd = pose_central_difference(r, P, RV, L0, name, relative=("rho_4", "M"))
        an = res["S"][0, :, k]
        if name == "A_1_x":  # the slack cable's anchor: nothing moves
            assert (an == 0.0).all() and np.abs(fd).max() < 1e-8, fd
            continue
        assert np.abs(an).max() > 1e-5, name
        np.testing.assert_allclose(an, fd, rtol=0, atol=2e-6 * np.abs(an).max(), err_msg=name)
