"""The compiled pose kernel with an external wrench on a rigid platform (issue 41; ``Platform.wrench``:
a constant world-frame force at p and moment about p): the compiled engine equals the numpy
reference (same statuses, taut sets, ``unique``, alternatives; poses within 1e-9 m and 1e-9 rad)
on CDPR4's frame with a rigid platform (hang4_6dof, under-constrained: restarts at every pose),
CoGiRo and wall_pulleys (several equilibria), under forces, moments and both, with massless and heavy cables, in a
single solve and in the batched solve of many robots; and the solution balances the wrench."""

import numpy as np
import pytest

from cdpr.compiled.equilibrium import solve as solve_fast
from cdpr.compiled.equilibrium import solve_batch as solve_fast_batch
from cdpr.models.equilibrium import solve as solve_ref
from cdpr.models.equilibrium import solve_batch as solve_ref_batch
from cdpr.robot import load_robot, with_values, with_wrench
from tests.compiled.test_equilibrium_pose import BOXES, _poses, _same
from tests.conftest import ROBOTS
from tests.models.test_wrench import balance

#: Forces [N] and moments [N m] beside gravity (hang4_6dof weighs 490 N, CoGiRo's platform 1.5 kN).
WRENCHES = [
    (40.0, -25.0, 30.0, 6.0, -4.0, 3.0),  # force and moment
    (0.0, 0.0, 0.0, 0.0, 0.0, 15.0),  # a moment alone (no potential: its work in the line search)
    (-120.0, 0.0, -300.0, 0.0, 0.0, 0.0),  # a force alone
    (0.0, 80.0, 0.0, -10.0, 0.0, 0.0),
]
ROBOT_NAMES = ["hang4_6dof.yaml", "cogiro_massless.yaml"]


@pytest.mark.parametrize("name", ROBOT_NAMES)
@pytest.mark.parametrize("k", range(len(WRENCHES)))
def test_compiled_equals_numpy_with_a_wrench(name, k):
    r = with_wrench(load_robot(ROBOTS / name), WRENCHES[k])
    p, rv, L0 = _poses(r, BOXES[name], 120, seed=11 + k)
    a, b = solve_ref(r, p, rv, L0=L0), solve_fast(r, p, rv, L0=L0)
    _same(a, b)
    ok = a["status"] == "ok"
    assert ok.sum() > 100
    assert np.abs(balance(r, b)[ok]).max() < 1e-6
    plain = solve_fast(load_robot(ROBOTS / name), p, rv, L0=L0)
    assert np.abs(plain["P_s"] - b["P_s"]).max() > 1e-4  # the wrench moved the platform
    _same(solve_ref(r, p, rv, L0=L0, restarts=False), solve_fast(r, p, rv, L0=L0, restarts=False))


def test_several_equilibria_with_a_moment_are_the_same():
    """wall_pulleys with rest lengths 1 % long under a force and a moment: several equilibria at
    about half of the poses; both engines pick the same lowest-energy one (the energy leaves the
    moment out) and list the same alternatives."""
    r = with_wrench(load_robot(ROBOTS / "wall_pulleys.yaml"), (10.0, 0.0, 0.0, 0.0, 0.0, 8.0))
    p, rv, L0 = _poses(r, BOXES["wall_pulleys.yaml"], 120, seed=3)
    a, b = solve_ref(r, p, rv, L0=L0 * 1.01), solve_fast(r, p, rv, L0=L0 * 1.01)
    _same(a, b)
    assert (~a["unique"]).sum() > 30
    np.testing.assert_allclose(a["energy"], b["energy"], rtol=1e-9, atol=1e-9)
    for x, y in zip(a["alternatives"], b["alternatives"]):
        for u, v in zip(x, y):
            assert u["taut"] == v["taut"]
            assert np.abs(np.subtract(u["P_s"], v["P_s"])).max() < 1e-9
            assert np.abs(np.subtract(u["rotvec_s"], v["rotvec_s"])).max() < 1e-9


@pytest.mark.parametrize(
    "name, n, restarts", [("hang4_6dof.yaml", 3, False), ("cogiro_massless.yaml", 6, True)]
)
def test_compiled_equals_numpy_with_a_wrench_and_heavy_cables(name, n, restarts):
    """Heavy cables (a linear density: Irvine's catenary, ``compiled.cables``) under a force and a
    moment, and a moment alone (few poses: the numpy heavy reference takes ~3 s a solve on hang4,
    whose 4 cables restart every pose 6 times: its first pass only)."""
    base = with_values(load_robot(ROBOTS / name), linear_density=0.0631)
    for k in (0, 1):
        r = with_wrench(base, WRENCHES[k])
        p, rv, L0 = _poses(r, BOXES[name], n, seed=21 + k)
        a = solve_ref(r, p, rv, L0=L0, restarts=restarts)
        b = solve_fast(r, p, rv, L0=L0, restarts=restarts)
        _same(a, b)
        assert (a["status"] == "ok").all()
        assert (b["residual"][b["status"] == "ok"] < 1e-6).all()


def test_the_batched_solve_takes_each_robots_wrench():
    """``solve_batch`` of robots with different wrenches (one without): each robot's result equals
    the numpy reference's and the single compiled solve of that robot."""
    base = load_robot(ROBOTS / "cogiro_massless.yaml")
    robots = [with_wrench(base, w) for w in WRENCHES[:3]] + [base]
    p, rv, L0 = _poses(base, BOXES["cogiro_massless.yaml"], 40, seed=9)
    fast = solve_fast_batch(robots, p, rv, L0=L0)
    for r, a, b in zip(robots, solve_ref_batch(robots, p, rv, L0=L0), fast):
        _same(a, b)
        one = solve_fast(r, p, rv, L0=L0)
        assert np.array_equal(one["P_s"], b["P_s"]) and np.array_equal(one["R_s"], b["R_s"])
    assert np.abs(fast[0]["P_s"] - fast[3]["P_s"]).max() > 1e-4
