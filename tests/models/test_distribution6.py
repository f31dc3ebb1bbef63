"""Tension distribution and compensation of a rigid platform at a pose (issue 17), on the shipped
spatial robots."""

import numpy as np
import pytest

from cdpr.models.distribution6 import compensated_lengths, distribute_pose, min_norm_rows
from cdpr.models.equilibrium6 import solve_spatial
from cdpr.models.tension_distribution import distribute
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

E_COGIRO = [80e9, 120e9, 95e9, 130e9, 110e9, 90e9, 105e9, 115e9]
POSES = np.array([[0, 0, 2.0, 0, 0, 0], [1, 1, 1.5, 0, 0, 0], [0, 0, 2.0, np.radians(15), 0, 0]])


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro.yaml", E_cables=E_COGIRO)


def test_cogiro_holds_caspr_data(cogiro):
    assert cogiro.m == 8 and cogiro.platform.mass == 91.058
    assert cogiro.A[0] == pytest.approx([-7.1775, -5.4361, 5.3911]) and cogiro.arrays.b[6, 2] == -0.0007
    assert cogiro.arrays.com == pytest.approx([-0.034, -0.013, 0.264]) and set(cogiro.h) == {0.05}


def test_compensation_round_trip_on_cogiro(cogiro):
    """Compensated lengths (minimum norm in [100, 5000] N), commanded to the robot they were computed
    for, starting 5 cm away: the platform reaches the pose to 1e-9 m and 1e-9 rad."""
    c = compensated_lengths(cogiro, POSES, t_min=100.0)
    assert c["feasible"].all()
    chk = solve_spatial(cogiro, POSES, L0=c["L0"], P0=POSES[:, :3] + [0.05, -0.03, 0.04])
    assert (chk["status"] == "ok").all() and (chk["n_taut"] == 8).all()
    assert chk["dp"].max() < 1e-9 and chk["dphi"].max() < 1e-9
    assert np.abs(chk["t"] - c["t"]).max() < 1e-5


def test_min_norm_rows_is_the_minimum(cogiro):
    """W t = w, the bounds, and no lower 2-norm found by an independent solver (SLSQP)."""
    from scipy.optimize import minimize

    d = distribute_pose(cogiro, POSES, t_min=100.0)
    for W, t in zip(d["W"], d["t"]):
        w = W @ t
        res = minimize(
            lambda x: x @ x,
            np.full(8, 1000.0),
            jac=lambda x: 2 * x,
            constraints=[{"type": "eq", "fun": lambda x: W @ x - w, "jac": lambda x: W}],
            bounds=[(100.0, 5000.0)] * 8,
            method="SLSQP",
            options={"ftol": 1e-12, "maxiter": 500},
        )
        assert res.success and np.abs(W @ res.x - w).max() < 1e-6
        assert t @ t <= res.x @ res.x * (1 + 1e-9)
        assert (t >= 100.0 - 1e-6).all() and (t <= 5000.0 + 1e-6).all()


def test_point_mass_rows_reduce_to_todays_distribution(cdpr4):
    p = np.array([[0.3, -0.4, 2.0], [1.0, 1.0, 1.0], [-2.0, 1.5, 3.5]])
    a = distribute(cdpr4, p, method="min_norm", t_min=100.0)
    b = distribute_pose(cdpr4, p, t_min=100.0)
    assert b["W"].shape == (3, 3, 4)
    assert (a["feasible"] == b["feasible"]).all()
    assert np.allclose(a["t"], b["t"], atol=1e-6, equal_nan=True)
    t, ok = min_norm_rows(a["W"], -cdpr4.platform.w_ext[None].repeat(3, 0), 100.0, cdpr4.T_a)
    assert np.allclose(a["t"], t, atol=1e-6, equal_nan=True)


def test_under_constrained_robot_has_no_distribution_but_hangs():
    r = load_robot(ROBOTS / "hang4_6dof.yaml")
    c = compensated_lengths(r, [[0.3, 0.2, 2.5]], [[0.2, 0.0, 0.0]])
    assert not c["feasible"][0] and c["status"][0] == "infeasible" and np.isnan(c["L0"]).all()
    res = solve_spatial(r, [[0.3, 0.2, 2.5]], [[0.2, 0.0, 0.0]])
    assert res["status"][0] == "ok" and res["n_taut"][0] == 4


@pytest.mark.parametrize("name", ["ipanema_like", "wall_pulleys"])
def test_shipped_spatial_robots_round_trip(name):
    r = load_robot(ROBOTS / f"{name}.yaml")
    c = compensated_lengths(r, [[0.0, 0.0, 1.5]], t_min=100.0)
    assert c["feasible"].all()
    chk = solve_spatial(r, [[0.0, 0.0, 1.5]], L0=c["L0"], P0=[[0.05, -0.03, 1.54]])
    assert chk["dp"][0] < 1e-9 and chk["dphi"][0] < 1e-9 and chk["status"][0] == "ok"
