"""Tension distribution and compensation of a rigid platform at a pose (issue 17), on the shipped
spatial robots."""

import numpy as np
import pytest

from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.tension_distribution import compensated_lengths, distribute, distribute_pose, min_norm_rows
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

E_COGIRO = [80e9, 120e9, 95e9, 130e9, 110e9, 90e9, 105e9, 115e9]
POSES = np.array([[0, 0, 2.0, 0, 0, 0], [1, 1, 1.5, 0, 0, 0], [0, 0, 2.0, np.radians(15), 0, 0]])


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro_massless.yaml", E_cables=E_COGIRO)


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


def _random_poses(n=200, seed=0):
    """Poses over CoGiRo's frame, tilted by up to about 0.3 rad."""
    rng = np.random.default_rng(seed)
    return np.column_stack(
        [rng.uniform(-6, 6, n), rng.uniform(-4, 4, n), rng.uniform(0.5, 4.5, n), rng.normal(0, 0.15, (n, 3))]
    )


def _wrench(robot, poses):
    from cdpr.models.platform import pose_arrays
    from cdpr.models.tension_distribution import pose_wrench

    p, R = pose_arrays(poses)
    W, w, _ = pose_wrench(robot, p, R)
    return W, w


@pytest.mark.parametrize("method", ["closed_form", "closed_form_improved"])
def test_closed_forms_at_a_pose_balance_the_platform_within_the_bounds(cogiro, method):
    """Pott's closed forms on the 6 x 8 wrench matrix: where they report feasible, W t = -w_ext to
    1e-9 N (and N m) and 100 <= t <= 5000 N; the closed form is the minimum of |t - t_m| over W t = w
    (the exact bounded solver with t_ref = t_m gives the same tensions where it is feasible)."""
    poses = np.vstack([POSES, _random_poses()])
    d = distribute_pose(cogiro, poses, t_min=100.0, t_max=5000.0, method=method)
    ok = d["feasible"]
    assert ok.sum() > 100 and d["W"].shape[1] == 6
    W, w = _wrench(cogiro, poses)
    assert np.abs(np.einsum("nam,nm->na", W, d["t"]) - w)[ok].max() < 1e-9
    assert (d["t"][ok] >= 100.0 - 1e-6).all() and (d["t"][ok] <= 5000.0 + 1e-6).all()
    assert ok[:3].all()
    if method == "closed_form":
        t, good = min_norm_rows(W[ok], w[ok], 100.0, 5000.0, t_ref=np.full(8, 2550.0))
        assert good.all() and np.abs(t - d["t"][ok]).max() < 1e-6


def test_improved_closed_form_is_feasible_wherever_the_closed_form_is(cogiro):
    poses = _random_poses(300, seed=1)
    a = distribute_pose(cogiro, poses, t_min=100.0, t_max=5000.0, method="closed_form")
    b = distribute_pose(cogiro, poses, t_min=100.0, t_max=5000.0, method="closed_form_improved")
    c = distribute_pose(cogiro, poses, t_min=100.0, t_max=5000.0)
    assert (b["feasible"] | ~a["feasible"]).all()
    assert b["feasible"].sum() > a["feasible"].sum()  # it pins cables where the closed form leaves the bounds
    assert (c["feasible"] | ~b["feasible"]).all()  # and never finds a distribution where none exists
    assert np.array_equal(a["t"][a["feasible"]], b["t"][a["feasible"]])  # nothing to pin there


@pytest.mark.parametrize("method", ["closed_form", "closed_form_improved"])
def test_closed_forms_reduce_to_the_point_mass_ones_for_b_0(cdpr4, method):
    """b_i = 0 (CDPR4): the rows reduced to rank 3, the same tensions as tension_distribution's
    functions on the point-mass wrench matrix; the 6 unreduced rows have rank 3 and no W^+."""
    from cdpr.models.tension_distribution import closed_form, pseudo_inverse

    p = np.array([[0.3, -0.4, 2.0], [1.0, 1.0, 1.0], [-2.0, 1.5, 3.5], [0.0, 0.0, 2.5], [2.2, -2.2, 4.5]])
    a = distribute(cdpr4, p, method=method, t_min=100.0, t_max=3000.0)
    b = distribute_pose(cdpr4, p, t_min=100.0, t_max=3000.0, method=method)
    assert b["W"].shape == (5, 3, 4) and np.allclose(a["W"], b["W"], atol=1e-12)
    assert (a["feasible"] == b["feasible"]).all() and a["feasible"].any() and not a["feasible"].all()
    assert np.allclose(a["t"], b["t"], atol=1e-6)
    W6, w6 = _wrench(cdpr4, p)
    assert np.isnan(pseudo_inverse(W6)).all() and not closed_form(W6, w6, 100.0, 3000.0)[1].any()


def test_closed_forms_find_nothing_on_an_under_constrained_robot():
    r = load_robot(ROBOTS / "hang4_6dof.yaml")
    for method in ("closed_form", "closed_form_improved"):
        c = compensated_lengths(r, [[0.3, 0.2, 2.5]], [[0.2, 0.0, 0.0]], method=method)
        assert not c["feasible"][0] and c["status"][0] == "infeasible" and np.isnan(c["L0"]).all()


def test_compensation_round_trip_with_the_improved_closed_form(cogiro):
    """Lengths compensated with Pott's improved closed form, commanded to the robot they were computed
    for, starting 5 cm away: the platform reaches the pose to 1e-9 m and 1e-9 rad, with the planned
    tensions."""
    c = compensated_lengths(cogiro, POSES, t_min=100.0, t_max=5000.0, method="closed_form_improved")
    assert c["feasible"].all()
    chk = solve_spatial(cogiro, POSES, L0=c["L0"], P0=POSES[:, :3] + [0.05, -0.03, 0.04])
    assert (chk["status"] == "ok").all() and (chk["n_taut"] == 8).all()
    assert chk["dp"].max() < 1e-9 and chk["dphi"].max() < 1e-9
    assert np.abs(chk["t"] - c["t"]).max() < 1e-5


def _kkt_residual(W, t, t_ref, lo, hi, tol=1e-6):
    """The first-order optimality of t for min |t - t_ref|^2, W t = w, lo <= t <= hi: t - t_ref =
    -W^T mu + nu_lo - nu_hi with nu >= 0 on the active bounds only (least squares for the
    multipliers); returns (stationarity residual [N], most negative bound multiplier [N])."""
    m = len(t)
    at_lo, at_hi = np.abs(t - lo) <= tol, np.abs(t - hi) <= tol
    A = np.column_stack([-W.T, np.eye(m)[:, at_lo], -np.eye(m)[:, at_hi]])
    x, *_ = np.linalg.lstsq(A, t - t_ref, rcond=None)
    nu = x[W.shape[0] :]
    return np.abs(A @ x - (t - t_ref)).max(), nu.min(initial=0.0)


@pytest.mark.parametrize("rows,m", [(6, 8), (6, 7), (3, 5), (3, 6), (6, 6)])
def test_min_norm_rows_meets_kkt_and_linprog_feasibility(rows, m):
    """On random wrench matrices (one in ten of rank rows - 1, with a consistent right-hand side)
    and a reference t_ref: every returned t is optimal by the KKT conditions (stationarity with
    nonnegative multipliers of the active bounds, to 1e-6 of the tensions' scale), and a point is
    feasible exactly where scipy's linprog finds a t with W t = w in the bounds."""
    from scipy.optimize import linprog

    rng = np.random.default_rng(rows * 10 + m)
    n = 120
    W = rng.normal(size=(n, rows, m))
    W[::10, -1] = W[::10, 0]  # rank-deficient rows
    t_true = rng.uniform(50.0, 450.0, (n, m))
    w = np.einsum("nam,nm->na", W, t_true)
    t_ref = rng.uniform(0.0, 300.0, m)
    t, ok = min_norm_rows(W, w, 100.0, 400.0, t_ref=t_ref)
    assert 0 < ok.sum() < n  # both outcomes occur
    assert np.isnan(t[~ok]).all()
    for i in range(n):
        lp = linprog(np.zeros(m), A_eq=W[i], b_eq=w[i], bounds=[(100.0, 400.0)] * m, method="highs")
        assert ok[i] == (lp.status == 0), i
        if ok[i]:
            assert np.abs(W[i] @ t[i] - w[i]).max() < 1e-8 * max(1.0, np.abs(w[i]).max())
            assert (t[i] >= 100.0 - 1e-6).all() and (t[i] <= 400.0 + 1e-6).all()
            stat, nu_min = _kkt_residual(W[i], t[i], t_ref, 100.0, 400.0)
            assert stat < 1e-6 * 400.0 and nu_min > -1e-6 * 400.0, (i, stat, nu_min)
