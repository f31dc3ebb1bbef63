"""Tension distribution (cdpr.models.tension_distribution): equilibrium, bounds, optimality, agreement of methods."""

import numpy as np
import pytest

from cdpr.models.statics import tensions
from cdpr.models.tension_distribution import (
    active_set_candidates,
    closed_form,
    closed_form_improved,
    distribute,
    min_norm,
    null_vector,
    wrench_matrix,
)
from cdpr.robot import robot_from_dict, with_pulleys

rng = np.random.default_rng(5)
PTS = np.column_stack([rng.uniform(-2.4, 2.4, 300), rng.uniform(-2.4, 2.4, 300), rng.uniform(0.0, 4.5, 300)])
T_MIN = 100.0


def hexagon(kind="SR"):
    """A 6-cable suspended robot (regular hexagon of radius 3 m at 5 m) for the general-m methods."""
    ang = np.arange(6) * np.pi / 3
    cables = [{"A_m": [3 * np.cos(a), 3 * np.sin(a), 5.0]} for a in ang]
    return robot_from_dict(
        {
            "name": "HEX6",
            "platform": {"mass_kg": 300.0},
            "cable": {"young_modulus_Pa": 102.2e9, "diameter_m": 0.004, "max_tension_N": 5140.0},
            "pulley": {"kind": kind, "h_m": 0.1, "r_p_m": 0.0665},
            "dead_length_m": 4.0,
            "cables": cables,
        }
    )


@pytest.fixture(params=["SR", "DR"])
def robot(request, cdpr4):
    return with_pulleys(cdpr4, kind=request.param)


@pytest.mark.parametrize("method", ["closed_form", "closed_form_improved", "min_norm"])
def test_feasible_tensions_hold_the_platform_within_bounds(robot, method):
    d = distribute(robot, PTS, method, t_min=T_MIN)
    ok = d["feasible"]
    assert 100 < ok.sum() < len(PTS)
    t = d["t"][ok]
    assert np.abs(np.einsum("nam,nm->na", d["W"][ok], t) + robot.platform.w_ext).max() < 1e-8
    assert (t >= T_MIN - 1e-6).all() and (t <= robot.T_a + 1e-6).all()
    assert (d["status"] == np.where(ok, "ok", "infeasible")).all()


def test_min_norm_is_the_minimum(robot):
    """Exactness for m = 4: no feasible point of the 1-D null-space line has a lower 2-norm."""
    W = wrench_matrix(robot, PTS)
    w = -robot.platform.w_ext
    t, ok = min_norm(W, w, T_MIN, robot.T_a)
    n = null_vector(W)
    assert np.abs(np.einsum("nam,nm->na", W, n)).max() < 1e-12
    lam = np.linspace(-5000, 5000, 20001)[None, :, None] / np.linalg.norm(n, axis=1)[:, None, None]
    cand = t[:, None, :] + lam * n[:, None, :]
    feas = ((cand >= T_MIN - 1e-9) & (cand <= robot.T_a + 1e-9)).all(axis=2)
    best = np.where(feas, (cand**2).sum(axis=2), np.inf).min(axis=1)
    assert (((t**2).sum(axis=1) <= best + 1e-6)[ok]).all()
    assert not feas[~ok].any()  # nothing feasible where it reports infeasible (on this line: none exists)


def test_null_space_and_enumeration_agree_for_four_cables(robot):
    W = wrench_matrix(robot, PTS)
    w = -robot.platform.w_ext
    a, fa = min_norm(W, w, T_MIN, robot.T_a, method="null_space")
    b, fb = min_norm(W, w, T_MIN, robot.T_a, method="enumerate")
    assert (fa == fb).all() and fa.sum() > 100
    assert np.abs(a[fa] - b[fa]).max() < 1e-8
    # with a reference: the bounded closed form
    tm = 0.5 * (T_MIN + robot.T_a)
    a, fa = min_norm(W, w, T_MIN, robot.T_a, t_ref=tm, method="null_space")
    b, fb = min_norm(W, w, T_MIN, robot.T_a, t_ref=tm, method="enumerate")
    assert (fa == fb).all() and np.abs(a[fa] - b[fa]).max() < 1e-8


def test_closed_form_is_min_norm_about_the_middle_where_interior(robot):
    """Case: both feasible and no bound active. The closed form minimises |t - t_m| with the bounds
    ignored, so where that minimum lies strictly inside the bounds it is min_norm with t_ref = t_m;
    with symmetric bounds (T_min = -T_max, t_m = 0) it is the plain minimum 2-norm."""
    W = wrench_matrix(robot, PTS)
    w = -robot.platform.w_ext
    T = robot.T_a
    tm = 0.5 * (T_MIN + T)
    c, fc = closed_form(W, w, T_MIN, T)
    m, fm = min_norm(W, w, T_MIN, T, t_ref=tm)
    interior = fc & fm & (m > T_MIN + 1e-3).all(axis=1) & (m < T - 1e-3).all(axis=1)
    assert interior.sum() > 100
    assert np.abs(c[interior] - m[interior]).max() < 1e-8
    c0, f0 = closed_form(W, w, -T, T)
    m0, g0 = min_norm(W, w, -T, T)
    inner = f0 & g0 & (np.abs(m0) < T - 1e-3).all(axis=1)
    assert inner.sum() > 100 and np.abs(c0[inner] - m0[inner]).max() < 1e-8
    # where the bounded minimum pins a cable, the closed form is infeasible or differs
    pinned = fm & ~interior
    assert pinned.any() and (~fc[pinned] | (np.abs(c[pinned] - m[pinned]).max(axis=1) > 1e-3)).all()


def test_under_the_centre_closed_form_and_min_norm_agree(cdpr4):
    """By symmetry the null vector is (1, -1, 1, -1), orthogonal to t_m: both give 4 equal tensions."""
    p = np.array([[0.0, 0.0, z] for z in (0.5, 2.5, 4.0)])
    for kind in ("SR", "DR"):
        r = with_pulleys(cdpr4, kind=kind)
        a, b = distribute(r, p, "closed_form"), distribute(r, p, "min_norm")
        assert a["feasible"].all() and b["feasible"].all()
        assert np.abs(a["t"] - b["t"]).max() < 1e-9
        assert (np.ptp(b["t"], axis=1) < 1e-9).all()


def test_improved_closed_form(robot):
    W = wrench_matrix(robot, PTS)
    w = -robot.platform.w_ext
    c, fc = closed_form(W, w, T_MIN, robot.T_a)
    i, fi = closed_form_improved(W, w, T_MIN, robot.T_a)
    assert (fi >= fc).all() and fi.sum() > fc.sum()  # it rescues points the closed form loses
    assert np.abs(c[fc] - i[fc]).max() == 0.0
    m, fm = min_norm(W, w, T_MIN, robot.T_a)
    assert (fi <= fm).all()  # never feasible where no feasible distribution exists
    # a rescued point has one cable on a bound
    resc = fi & ~fc
    on_bound = (np.abs(i[resc] - T_MIN) < 1e-9) | (np.abs(i[resc] - robot.T_a) < 1e-9)
    assert on_bound.any(axis=1).all()


def test_infeasible_is_flagged_not_clipped(cdpr4):
    p = np.array([[0.0, 0.0, 2.5], [3.0, 0.0, 2.0], [0.0, 0.0, 5.5]])  # inside / outside the frame / above
    for method in ("closed_form", "closed_form_improved", "min_norm"):
        d = distribute(cdpr4, p, method)
        assert list(d["status"]) == ["ok", "infeasible", "infeasible"]
        d = distribute(cdpr4, p[:1], method, t_max=500.0)  # 4 x 500 N < M g
        assert list(d["status"]) == ["infeasible"]
        if method == "min_norm":
            assert np.isnan(d["t"]).all()
        else:
            assert (d["t"] > 500.0 + 1.0).any()  # reported as computed, not clipped


def test_three_cables_give_the_unique_solution(cdpr3):
    W = wrench_matrix(cdpr3, PTS)
    t3, _ = tensions(np.swapaxes(W, 1, 2), cdpr3.platform.w_ext)
    for method in ("closed_form", "closed_form_improved", "min_norm"):
        d = distribute(cdpr3, PTS, method, t_min=0.0)
        inside = ((t3 >= 0) & (t3 <= cdpr3.T_a)).all(axis=1)
        assert (d["feasible"] == inside).all() and inside.sum() > 50
        assert np.abs(d["t"][inside] - t3[inside]).max() < 1e-8


def test_six_cables_enumeration_against_a_generic_solver():
    from scipy.optimize import minimize

    r = hexagon()
    p = np.column_stack([rng.uniform(-1.5, 1.5, 12), rng.uniform(-1.5, 1.5, 12), rng.uniform(0.5, 4.0, 12)])
    W = wrench_matrix(r, p)
    w = -r.platform.w_ext
    t, ok = min_norm(W, w, T_MIN, 1500.0)
    assert ok.all()
    for k in range(len(p)):
        res = minimize(
            lambda x: x @ x,
            np.full(6, 0.8),
            jac=lambda x: 2 * x,
            method="SLSQP",  # in kN
            bounds=[(T_MIN / 1e3, 1.5)] * 6,
            constraints={"type": "eq", "fun": lambda x, k=k: W[k] @ x - w / 1e3},
            options={"ftol": 1e-15, "maxiter": 500},
        )
        assert res.success
        assert t[k] @ t[k] <= res.fun * 1e6 * (1 + 1e-9)
        assert np.abs(t[k] - 1e3 * res.x).max() < 1e-3
    assert (np.abs(t - 1500.0) < 1e-9).any()  # some bound active: the enumeration was exercised
    assert len(active_set_candidates(6)[0]) == 1 + 12 + 60 + 160


def test_unknown_method(cdpr4):
    with pytest.raises(ValueError, match="allowed"):
        distribute(cdpr4, PTS[:2], "magic")
    with pytest.raises(ValueError, match="m = 4"):
        min_norm(wrench_matrix(hexagon(), PTS[:2]), [0, 0, 2943.0], 0.0, 1e4, method="null_space")
