"""An external wrench beside gravity (issue 41, ``Platform.wrench``, ``robot.with_wrench``): a constant
force [N] in the world frame at the platform's reference point p and a constant moment [N m] about
p in the world frame, in every model that balances the platform (the equilibrium, the tension
distribution and the compensation, the wrench feasibility, the reached continuation).

Checked by physics: the balance at the solution, a vertical force -dM g that equals a heavier
platform (point mass and a rigid platform whose centre of mass is its reference point), the whole
robot turned with its gravity and its wrench, the compensate -> solve round trip, and the wrench
feasibility of a force along an axis."""

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.analyses.compensation import compensated_pose
from cdpr.errors import CdprError
from cdpr.models.inverse import pose_state
from cdpr.models.platform import external_wrench, pose_arrays, wrench_matrix
from cdpr.models.tension_distribution import distribute_pose
from cdpr.robot import G_STANDARD, check_wrench, with_values, with_wrench
from cdpr.solve import reach
from cdpr.solve import solve as solve_any
from tests.models.test_equilibrium_pose import pretensioned, robot8, robot8_turned

WRENCH = (40.0, -25.0, 30.0, 6.0, -4.0, 3.0)  # N and N m, beside a 490 N weight
P = np.array([[0.3, -0.2, 1.4], [0.0, 0.1, 1.6]])
RV = np.array([[0.05, -0.1, 0.2], [np.radians(15), 0.0, 0.0]])


def balance(robot, res):
    """W t + gravity + wrench at the solved poses (N, 6) [N, N m], recomputed from the geometry."""
    R = res["R_s"]
    B, st = pose_state(robot, res["P_s"], R)
    u = st.D - B
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    W = wrench_matrix(u, B - res["P_s"][:, None, :])
    pl = robot.platform
    return np.einsum("nam,nm->na", W, np.nan_to_num(res["t"])) + external_wrench(
        pl.mass, pl.g, robot.arrays.com, R, pl.down, pl.wrench
    )


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_balance_with_a_wrench_holds_at_the_solution(kind):
    """Force and moment balance with gravity at c and the wrench at p: ~0; the wrench moved the
    platform (the answer is not gravity's alone)."""
    r = robot8(kind, com=(0.02, -0.01, 0.05))
    rw = with_wrench(r, WRENCH)
    L0 = pretensioned(r, P, RV)
    res = solve_any(rw, P, RV, redundancy="physical", engine="numpy", L0=L0)
    assert (res["status"] == "ok").all()
    assert np.abs(balance(rw, res)).max() < 1e-6
    plain = solve_any(r, P, RV, redundancy="physical", engine="numpy", L0=L0)
    assert np.abs(plain["P_s"] - res["P_s"]).max() > 1e-5


def test_a_vertical_force_equals_a_heavier_point_mass(cdpr4):
    """Point mass: the force -dM g at p is the weight of dM more mass, same pose to 1e-12 m, in
    both modes and both engines."""
    dM = 7.0
    p = np.array([[0.3, 0.2, 2.0], [-1.0, 0.5, 3.0], [1.2, -0.8, 1.0]])
    heavier = with_values(cdpr4, mass=cdpr4.platform.mass + dM)
    pushed = with_wrench(cdpr4, [0.0, 0.0, -dM * G_STANDARD, 0.0, 0.0, 0.0])
    for mode in ("physical", "paper"):
        for engine in ("numpy", "compiled"):
            a = solve_any(heavier, p, redundancy=mode, engine=engine)
            b = solve_any(pushed, p, redundancy=mode, engine=engine)
            assert (a["status"] == "ok").all() and (a["status"] == b["status"]).all()
            assert np.abs(a["P_s"] - b["P_s"]).max() <= 1e-12
            assert np.abs(np.nan_to_num(a["t"]) - np.nan_to_num(b["t"])).max() <= 1e-9


@pytest.mark.parametrize("kind", ["fixed", "SR"])
def test_a_vertical_force_equals_a_heavier_rigid_platform(kind):
    """Rigid platform with its centre of mass at p (c = 0, b_i != 0): -dM g at p is dM more mass."""
    dM = 5.0
    r = robot8(kind)
    L0 = pretensioned(r, P, RV)
    a = solve_any(with_values(r, mass=50.0 + dM), P, RV, redundancy="physical", engine="numpy", L0=L0)
    b = solve_any(
        with_wrench(r, [0.0, 0.0, -dM * G_STANDARD, 0.0, 0.0, 0.0]),
        P,
        RV,
        redundancy="physical",
        engine="numpy",
        L0=L0,
    )
    assert (a["status"] == "ok").all() and (a["status"] == b["status"]).all()
    assert np.abs(a["P_s"] - b["P_s"]).max() <= 1e-12
    assert np.abs(a["R_s"] - b["R_s"]).max() <= 1e-12


@pytest.mark.parametrize("kind", ["fixed", "DR"])
def test_turning_the_robot_gravity_and_wrench_turns_the_answer(kind):
    """The whole robot, its gravity and its wrench (force and moment) turned by Q: the equilibrium
    under the same rest lengths is Q times the old one, with the same tensions."""
    Q = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix()
    a = with_wrench(robot8_turned(kind, np.eye(3)), WRENCH)
    wq = np.concatenate([Q @ WRENCH[:3], Q @ WRENCH[3:]])
    b = with_wrench(robot8_turned(kind, Q), wq)
    rv_b = (Rotation.from_matrix(Q) * Rotation.from_rotvec(RV)).as_rotvec()
    L0 = pretensioned(a, P, RV)
    ra = solve_any(a, P, RV, redundancy="physical", engine="numpy", L0=L0)
    rb = solve_any(b, P @ Q.T, rv_b, redundancy="physical", engine="numpy", L0=L0)
    assert (ra["status"] == "ok").all() and (ra["status"] == rb["status"]).all()
    assert np.abs(ra["P_s"] @ Q.T - rb["P_s"]).max() < 1e-9
    assert np.abs(Q @ ra["R_s"] - rb["R_s"]).max() < 1e-9
    assert (ra["taut"] == rb["taut"]).all()
    assert np.abs(np.nan_to_num(ra["t"]) - np.nan_to_num(rb["t"])).max() < 1e-6


def test_compensate_then_solve_reaches_the_pose_under_the_wrench():
    """Compensated rest lengths under the wrench, commanded to the same robot with the wrench and
    solved from a start 5 cm away: the platform reaches the desired pose (round trip); without the
    wrench it does not."""
    r = robot8("SR", com=(0.02, -0.01, 0.05))
    rw = with_wrench(r, WRENCH)
    p = np.array([[0.0, 0.0, 1.5], [0.2, -0.1, 1.5], [-0.3, 0.2, 1.6]])
    rv = np.array([[0.0, 0.0, 0.0], [0.02, -0.01, 0.03], [0.0, 0.03, -0.02]])
    comp = compensated_pose(rw, p, rotvec=rv, t_min=10.0)
    assert (comp["status"] == "ok").all()
    res = solve_any(rw, p, rv, redundancy="physical", engine="numpy", L0=comp["L0"], P0=p + 0.05)
    assert (res["status"] == "ok").all()
    assert res["dp"].max() < 1e-8 and res["dphi"].max() < 1e-8
    assert np.abs(balance(rw, res)).max() < 1e-6
    off = solve_any(r, p, rv, redundancy="physical", engine="numpy", L0=comp["L0"])
    assert off["dp"].max() > 1e-5


def test_the_reached_equilibrium_with_a_wrench_is_balanced():
    """The continuation (Newton on the balance, the moment's work in the line search) ends on a
    balanced pose, the same as the direct solve where that one is unique."""
    r = robot8("fixed", com=(0.02, -0.01, 0.05))
    rw = with_wrench(r, WRENCH)
    L0 = pretensioned(r, P, RV)
    res = reach(rw, P, RV, L0=L0)
    assert (res["status"] == "ok").all()
    assert np.abs(balance(rw, res)).max() < 1e-6
    direct = solve_any(rw, P, RV, redundancy="physical", engine="numpy", L0=L0)
    assert np.abs(res["P_s"] - direct["P_s"]).max() < 1e-8


def test_wrench_feasibility_follows_a_force_along_an_axis(cdpr4):
    """Point mass under 4 cables from above, bounds 0 <= t (no upper bound): the feasible set is the
    cone condition, so a vertical force that scales the load by k > 0 leaves it unchanged and
    scales the least-norm tensions by k; an upward force beyond the weight leaves nothing feasible
    (cables cannot push); a force along +x moves the feasible points toward +x (the cables on the -x
    side must pull sideways, which they do from far away), and the upper bound T_a shrinks the set
    under a large downward force."""
    g = np.linspace(-3.0, 3.0, 11)  # the anchors at x, y = +-2.5: some points outside the footprint
    pts = np.array([[x, y, z] for x in g for y in g for z in (0.5, 2.0, 4.0)])
    W = cdpr4.platform.mass * G_STANDARD
    free = {"t_min": 0.0, "t_max": np.inf}
    base = distribute_pose(cdpr4, pts, **free)
    assert 0 < base["feasible"].sum() < len(pts)
    for k in (0.25, 3.0):
        d = distribute_pose(with_wrench(cdpr4, [0.0, 0.0, -(k - 1.0) * W, 0, 0, 0]), pts, **free)
        assert (d["feasible"] == base["feasible"]).all()
        ok = base["feasible"]
        assert np.abs(d["t"][ok] - k * base["t"][ok]).max() <= 1e-9 * k * W
    lift = distribute_pose(with_wrench(cdpr4, [0.0, 0.0, 1.5 * W, 0, 0, 0]), pts, **free)
    assert not lift["feasible"].any()
    side = distribute_pose(with_wrench(cdpr4, [0.6 * W, 0, 0, 0, 0, 0]), pts, **free)["feasible"]
    assert 0 < side.sum() and pts[side, 0].mean() > pts[base["feasible"], 0].mean()
    bounded = distribute_pose(cdpr4, pts, t_min=0.0)["feasible"]
    heavy = distribute_pose(with_wrench(cdpr4, [0.0, 0.0, -20.0 * W, 0, 0, 0]), pts, t_min=0.0)["feasible"]
    assert heavy.sum() < bounded.sum() and not (heavy & ~bounded).any()


def test_a_zero_wrench_is_the_robot_itself(cdpr4):
    assert with_wrench(cdpr4, None) is cdpr4 and with_wrench(cdpr4, [0] * 6) is cdpr4
    r = robot8("fixed")
    assert with_wrench(r, (0.0,) * 6) is r
    assert dataclasses.replace(r.platform).wrench == (0.0,) * 6


@pytest.mark.parametrize(
    "values, words",
    [
        ([1, 2, 3, 4, 5], "expected 6 numbers"),
        ([1, 2, 3, 4, 5, 6, 7], "expected 6 numbers"),
        ([1, 2, float("nan"), 0, 0, 0], "FZ = nan"),
        ([1, 2, 3, float("inf"), 0, 0], "MX = inf"),
        (["a", 0, 0, 0, 0, 0], "expected 6 numbers"),
    ],
)
def test_bad_wrenches_are_refused_in_one_line(values, words):
    with pytest.raises(CdprError) as exc:
        check_wrench(values, "--wrench")
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("--wrench: ") and words in msg


def test_a_moment_on_a_point_mass_is_refused(cdpr4):
    with pytest.raises(CdprError) as exc:
        with_wrench(cdpr4, [0, 0, 0, 1.0, 0, 0])
    msg = str(exc.value)
    assert "\n" not in msg and "--wrench" in msg and "point mass" in msg and "MX MY MZ must be 0" in msg


def test_the_default_engine_with_a_rigid_platform_wrench_is_the_compiled_one():
    """No engine named: a rigid platform with a wrench is solved by the compiled kernel, as without
    one (the result is the compiled engine's, bit for bit, not the numpy reference's)."""
    rw = with_wrench(robot8("fixed"), WRENCH)
    a = solve_any(rw, P, RV, redundancy="physical")
    b = solve_any(rw, P, RV, redundancy="physical", engine="compiled")
    assert (a["status"] == "ok").all()
    assert np.array_equal(a["P_s"], b["P_s"]) and np.array_equal(a["R_s"], b["R_s"])
    assert pose_arrays(P, RV)[0].shape == (2, 3)


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
def test_heavy_cables_a_vertical_force_equals_more_mass(cdpr4, engine):
    """Heavy cables (a point mass): -dM g at p is dM more platform mass, same pose to 1e-12 m."""
    dM = 7.0
    r = with_values(cdpr4, linear_density=0.0631, pulley="fixed")
    p = np.array([[0.3, -0.5, 2.0], [-1.0, 0.5, 3.0]])
    a = solve_any(with_values(r, mass=r.platform.mass + dM), p, redundancy="physical", engine=engine)
    b = solve_any(
        with_wrench(r, [0.0, 0.0, -dM * G_STANDARD, 0, 0, 0]), p, redundancy="physical", engine=engine
    )
    assert (a["status"] == "ok").all() and (a["status"] == b["status"]).all()
    assert np.abs(a["P_s"] - b["P_s"]).max() <= 1e-12


def test_heavy_cables_balance_with_a_wrench_on_a_rigid_platform():
    """Heavy cables on a rigid platform with a force and a moment: the solve converges (Newton on the
    balance, the moment's work in the line search) and the wrench moved the platform."""
    r = with_values(robot8("fixed", com=(0.02, -0.01, 0.05)), linear_density=0.05)
    L0 = pretensioned(r, P, RV)
    res = solve_any(with_wrench(r, WRENCH), P, RV, redundancy="physical", L0=L0)
    plain = solve_any(r, P, RV, redundancy="physical", engine="numpy", L0=L0)
    assert (res["status"] == "ok").all() and (res["residual"] < 1e-6).all()
    assert np.abs(plain["P_s"] - res["P_s"]).max() > 1e-5
