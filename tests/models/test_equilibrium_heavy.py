"""The physical equilibrium with heavy cables (cdpr.models.cables.HeavyCables, issue 38; fixed
pulleys so far) tested by physics: w = 0 through the catenary reproduces today's massless answers
(1e-12 m, 1e-12 rad), the energy's gradient is minus the net force (a point mass hung from fixed
points, d = 0, and with dead lengths), the solution balances the catenaries' end forces computed
independently, the analytic Jacobian equals central differences, w -> 0 is continuous, rotating the
whole robot with its gravity rotates the answer (also with swivel axes off the gravity's line and
DR pulleys: the general pulley coupling), and the end tangent lies in the sheave plane."""

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.errors import CdprError
from cdpr.models import catenary as cat
from cdpr.models.cables import Cables, HeavyCables
from cdpr.models.equilibrium import SLACK_STIFFNESS, hanging_cables, local_newton, solve
from cdpr.models.platform import pose_arrays
from cdpr.robot import load_robot, with_pulleys, with_values
from cdpr.solve import solve as door
from tests.conftest import ROBOTS
from tests.models.test_equilibrium_pose import central_jacobian, pretensioned, robot8_turned

RHO = 0.0631  # [kg/m] a 4 mm steel cable
PTS = np.array([[0.0, 0.0, 2.5], [1.0, 0.5, 3.0], [-2.0, 1.5, 1.0], [1.2, -1.1, 4.2], [0.3, 0.2, 0.5]])


def heavy(robot, rho=RHO, dead_length=None):
    cables = tuple(
        dataclasses.replace(
            c,
            material=dataclasses.replace(c.material, rho=rho),
            dead_length=c.dead_length if dead_length is None else dead_length,
        )
        for c in robot.cables
    )
    return dataclasses.replace(robot, cables=cables)


@pytest.mark.parametrize("kind", ["fixed", "SR"])
def test_weightless_cables_through_the_catenary_give_todays_point_mass(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    a, b = solve(r, PTS), solve(r, PTS, heavy=True)
    assert (a["status"] == "ok").all() and (a["status"] == b["status"]).all()
    assert np.abs(a["P_s"] - b["P_s"]).max() < 1e-12
    assert (a["taut"] == b["taut"]).all()
    np.testing.assert_allclose(b["t"], a["t"], rtol=1e-9)
    assert (b["sag"] == 0).all() and np.abs(b["angle_f_deg"]).max() < 1e-6


def assert_weightless_is_massless(r, p, rv):
    """The rigid platform of ``r`` (weightless cables) at the pretensioned rest lengths of poses
    (p, rv): the heavy solve through the catenary gives the massless one's status, pose (1e-12 m,
    1e-12 rad) and tensions (1e-9 relative)."""
    L0 = pretensioned(r, p, rv)
    a, b = solve(r, p, rv, L0=L0), solve(r, p, rv, L0=L0, heavy=True)
    assert (a["status"] == "ok").all() and (a["status"] == b["status"]).all()
    assert np.abs(a["P_s"] - b["P_s"]).max() < 1e-12
    assert np.abs(a["rotvec_s"] - b["rotvec_s"]).max() < 1e-12
    np.testing.assert_allclose(b["t"], a["t"], rtol=1e-9)


@pytest.mark.parametrize("kind", ["fixed", "SR"])
def test_weightless_cables_through_the_catenary_give_todays_rigid_platform(kind):
    r = robot8_turned(kind, np.eye(3))
    p = np.array([[0.3, -0.2, 1.4], [-0.5, 0.4, 1.7], [0.0, 0.0, 1.5]])
    rv = np.array([[0.05, -0.1, 0.2], [0.2, 0.1, -0.1], [0.0, 0.0, 0.0]])
    assert_weightless_is_massless(r, p, rv)


@pytest.mark.parametrize("kind, dead_length", [("fixed", 0.0), ("fixed", 4.0), ("SR", 4.0)])
def test_energy_gradient_is_minus_the_net_force(cdpr4, kind, dead_length):
    """A point mass hung from fixed points (d = 0, then d = 4 m, then SR pulleys): -dU/dp by central
    differences of the merit (the cables' energy plus the weight's) equals the net force, off the
    equilibrium."""
    r = heavy(with_pulleys(cdpr4, kind=kind), rho=0.5, dead_length=dead_length)
    cab = HeavyCables(r)
    p = PTS[:4]
    L0 = solve(r, p)["L0"] * 1.002  # a little longer: sagging, U-shaped spans among them
    R = np.broadcast_to(np.eye(3), (len(p), 3, 3)).copy()
    F = cab.evaluate(p, R, L0, p)["F"]
    h = 1e-6
    grad = np.empty_like(p)
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        up = cab.evaluate(p + e, R, L0, p, jacobian=False)["merit"]
        dn = cab.evaluate(p - e, R, L0, p, jacobian=False)["merit"]
        grad[:, k] = (up - dn) / (2 * h)
    assert np.abs(F).max() > 10.0  # off the equilibrium
    np.testing.assert_allclose(-grad, F, rtol=0, atol=2e-5 * np.abs(F).max())


def test_heavy_point_mass_balances_the_catenaries_end_forces(cdpr4):
    """At the solution, the end forces of the four catenaries from B = P* to D = A_i, computed by
    ``catenary.end_forces`` (d = 0: the whole rest length is the free span), balance the weight."""
    r = heavy(with_pulleys(cdpr4, kind="fixed"), dead_length=0.0)
    res = solve(r, PTS)
    assert (res["status"] == "ok").all() and res["converged"].all()
    v = r.A[None] - res["P_s"][:, None]
    l_h, l_v = np.hypot(v[..., 0], v[..., 1]), v[..., 2]
    H, V = cat.end_forces(l_h, l_v, res["L0"], r.arrays.w, r.ES)
    F = (H / l_h)[..., None] * np.concatenate([v[..., :2], np.zeros_like(l_h)[..., None]], -1)
    F[..., 2] = V
    net = F.sum(axis=1) + r.platform.w_ext
    assert np.abs(net).max() < 1e-6 * r.platform.mass * r.platform.g
    # the cables carry their own weight: the exit points pull harder than the platform feels
    assert (res["t_D"] > res["t_B"]).all() and (res["sag"] > 0).all()
    np.testing.assert_allclose(res["sag_max"], res["sag"].max(axis=1))
    assert (np.abs(res["angle_f_deg"]) > 0).all()


def test_weight_to_zero_is_continuous(cdpr4):
    r = with_pulleys(cdpr4, kind="fixed")
    a = solve(r, PTS)
    b = solve(heavy(r, rho=1e-9), PTS)
    assert np.abs(a["P_s"] - b["P_s"]).max() < 1e-8
    c = solve(heavy(r), PTS)
    assert np.abs(a["P_s"] - c["P_s"]).max() > 1e-5  # a real cable's weight does move the platform


@pytest.mark.parametrize("case", ["point mass", "rigid", "point mass DR", "tilted SR", "tilted DR"])
def test_analytic_jacobian_equals_finite_differences(cdpr4, case):
    """The whole Jacobian d(F, M)/d(dp, dphi), exact also on DR pulleys and swivel axes off the
    gravity's line (the exit point's slide on the sheave, the swivel and a DR arm's turn:
    ``heavy_partials``), against central differences to 1e-7 of its largest entry (1e-9 seen; the
    Jacobian without the slide and the arm's turn was off by 2e-3 to 2e-2)."""
    if case.startswith("point mass"):
        r = heavy(with_pulleys(cdpr4, kind="DR" if case.endswith("DR") else "fixed"), rho=0.5)
        p, rv = np.array([[0.4, -0.3, 2.0]]), np.zeros((1, 3))
        L0 = solve(r, p)["L0"] * 1.001
    elif case == "rigid":
        r = heavy(robot8_turned("fixed", np.eye(3)), rho=0.5)
        p, rv = np.array([[0.3, -0.2, 1.4]]), np.array([[0.05, -0.1, 0.2]])
        L0 = pretensioned(r, p, rv, t0=200.0)
    else:
        r = heavy(tilted(case[-2:], Q_TILT), rho=0.5)
        p, rv = np.array([[0.3, -0.2, 1.4]]) @ Q_TILT.T, np.array([[0.05, -0.1, 0.2]])
        L0 = pretensioned(r, p, rv, t0=200.0)
    cab = HeavyCables(r)
    _, R = pose_arrays(p, rv)
    J = cab.evaluate(p, R, L0, p)["J"][0]
    n = 6 if cab.rigid else 3
    fd = central_jacobian(cab, p, R, L0, 1e-6)
    assert np.abs(J - fd)[:n, :n].max() < 1e-7 * np.abs(J).max()


@pytest.mark.parametrize("kind", ["fixed", "SR"])
def test_rotating_the_whole_robot_and_gravity_rotates_the_heavy_solution(kind):
    """Gravity not along -z: the catenaries' planes follow it (this exercises "up" = -down, and SR
    axes along gravity both up and down)."""
    Q = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix()
    a, b = heavy(robot8_turned(kind, np.eye(3))), heavy(robot8_turned(kind, Q))
    p = np.array([[0.3, -0.2, 1.4], [-0.5, 0.4, 1.7], [0.0, 0.0, 1.5]])
    rv = np.array([[0.05, -0.1, 0.2], [0.2, 0.1, -0.1], [0.0, 0.0, 0.0]])
    rv_b = (Rotation.from_matrix(Q) * Rotation.from_rotvec(rv)).as_rotvec()
    L0 = pretensioned(a, p, rv, t0=300.0)
    ra = solve(a, p, rv, L0=L0)
    rb = solve(b, p @ Q.T, rv_b, L0=L0)
    assert (ra["status"] == "ok").all() and (ra["status"] == rb["status"]).all()
    assert np.abs(ra["P_s"] @ Q.T - rb["P_s"]).max() < 1e-9
    assert np.abs(Q @ ra["R_s"] - rb["R_s"]).max() < 1e-9
    assert np.abs(ra["t"] - rb["t"]).max() < 1e-6 and np.abs(ra["sag"] - rb["sag"]).max() < 1e-9
    assert ra["sag"].max() > 1e-4


def tilted(kind, Q=np.eye(3), G=np.eye(3)):
    """``robot8_turned(kind, G Q)`` whose gravity is turned by G only: its swivel axes are off the
    gravity's line (by Q) wherever Q is not the identity."""
    r = robot8_turned(kind, G @ Q)
    return dataclasses.replace(r, platform=dataclasses.replace(r.platform, down=tuple(G @ [0.0, 0.0, -1.0])))


Q_TILT = Rotation.from_rotvec([0.25, -0.15, 0.1]).as_matrix()
P8 = np.array([[0.3, -0.2, 1.4], [-0.5, 0.4, 1.7], [0.0, 0.0, 1.5]])
RV8 = np.array([[0.05, -0.1, 0.2], [0.2, 0.1, -0.1], [0.0, 0.0, 0.0]])


def massless_equilibrium(robot, res):
    """The massless model's equilibrium near ``solve``'s answer ``res``, to round-off: three more
    Newton steps (``local_newton``) with no force-balance stop. ``solve`` stops where |F| <= 1e-10
    |w_ext| (``cables.FTOL_REL``), which on CDPR4's DR pulleys leaves up to 1.8e-12 m."""
    cab = Cables(robot)
    cab.ftol = 0.0
    P, R, _, _, _ = local_newton(cab, res["P_s"], res["R_s"], res["L0"], res["p"], 0.0, 3, 0.5)
    return P, R


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_weightless_cables_on_tilted_axes_and_dr_pulleys_give_todays_answers(cdpr4, kind):
    r = tilted(kind, Q_TILT)
    p, rv = P8 @ Q_TILT.T, RV8
    # the heavy Jacobian is exact (the DR arm's turn, D's slide on the sheave): Newton's paths agree
    assert_weightless_is_massless(r, p, rv)
    if kind == "DR":  # the point mass: the heavy Newton starts from slack cables (the massless one
        # from Hooke extended to compression), so the two paths differ; both converge quadratically
        # and the heavy one lands on the massless equilibrium (2.6e-11 m off with the old Jacobian)
        d = with_pulleys(cdpr4, kind="DR")
        a, b = solve(d, PTS), solve(d, PTS, heavy=True)
        P, _ = massless_equilibrium(d, a)
        assert (a["status"] == "ok").all() and (b["status"] == "ok").all()
        assert np.abs(b["P_s"] - P).max() < 1e-12
        assert np.abs(a["P_s"] - P).max() < 1e-11  # the massless solve's own force-balance stop


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_rotating_a_tilted_robot_and_gravity_rotates_the_heavy_solution(kind):
    """Swivel axes off the gravity's line (the general path: the swivel angle that puts the
    catenary's end tangent in the sheave plane), the whole robot and its gravity turned by G."""
    G = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix()
    a, b = heavy(tilted(kind, Q_TILT)), heavy(tilted(kind, Q_TILT, G))
    p = P8 @ Q_TILT.T
    rv_b = (Rotation.from_matrix(G) * Rotation.from_rotvec(RV8)).as_rotvec()
    L0 = pretensioned(a, p, RV8, t0=300.0)
    ra, rb = solve(a, p, RV8, L0=L0), solve(b, p @ G.T, rv_b, L0=L0)
    assert (ra["status"] == "ok").all() and (ra["status"] == rb["status"]).all()
    assert np.abs(ra["P_s"] @ G.T - rb["P_s"]).max() < 1e-9
    assert np.abs(G @ ra["R_s"] - rb["R_s"]).max() < 1e-9
    assert np.abs(ra["t"] - rb["t"]).max() < 1e-6 and np.abs(ra["sag"] - rb["sag"]).max() < 1e-9
    assert ra["sag"].max() > 1e-4


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_end_tangent_lies_in_the_sheave_plane_and_touches_the_circle(kind):
    """Tilted axes and DR arms: at the equilibrium the catenary's end tangent at D_i lies in the
    sheave plane (the plane of the swivel axis and the arm) and is perpendicular to the radius."""
    from cdpr.models.inverse import pose_state
    from cdpr.models.pulleys import pulley_state

    r = heavy(tilted(kind, Q_TILT), rho=0.5)
    p = P8 @ Q_TILT.T
    res = solve(r, p, RV8, L0=pretensioned(r, p, RV8, t0=300.0))
    assert (res["status"] == "ok").all()
    cab = HeavyCables(r)
    R = res["R_s"]
    x = cab.exit_points(res["P_s"], R, res["L0"])
    st = x["state"].span
    tangent = (st.H[..., None] * x["e_h"] + st.V_D[..., None] * cab.up) / st.T_D[..., None]
    Pv = x["D"] - np.linalg.norm(x["v"], axis=-1)[..., None] * tangent  # on the end tangent
    ps = pulley_state(Pv, *cab.args, per_cable=True)
    np.testing.assert_allclose(ps.D, x["D"], rtol=0, atol=1e-12)
    radius = x["D"] - ps.H
    np.testing.assert_allclose(np.linalg.norm(radius, axis=-1), r.r_p[0], rtol=1e-12)
    assert np.abs(np.einsum("nma,nma->nm", tangent, radius)).max() < 1e-12 * r.r_p[0]
    normal = np.cross(cab.axis, ps.e_s3)  # the sheave plane's normal
    assert np.abs(np.einsum("nma,nma->nm", tangent, normal)).max() < 1e-12
    # the heavy cable's plane is not the massless one: the swivel turned
    _, ps0 = pose_state(r, res["P_s"], R)
    assert np.abs(ps.alpha - ps0.alpha).max() > 1e-6


def test_sr_exit_point_is_where_the_catenary_leaves_the_sheave_tangentially(cdpr4):
    """SR pulleys: D_i lies on the sheave circle (|D - H| = r_p, in the cable's vertical plane), and
    the catenary's end tangent at D_i is perpendicular to the radius H -> D_i."""
    r = heavy(with_pulleys(cdpr4, kind="SR"), rho=0.5)
    res = solve(r, PTS)
    assert (res["status"] == "ok").all()
    cab = HeavyCables(r)
    R = np.broadcast_to(np.eye(3), (len(PTS), 3, 3))
    x = cab.exit_points(res["P_s"], R, res["L0"])
    st = x["state"].span
    D = res["D"]
    from cdpr.models.inverse import pose_state

    _, ps = pose_state(r, res["P_s"], R)
    radius = D - ps.H
    np.testing.assert_allclose(np.linalg.norm(radius, axis=-1), r.r_p[0], rtol=1e-12)
    tangent = st.H[..., None] * x["e_h"] + st.V_D[..., None] * cab.up  # along the cable at D
    cos = np.einsum("nma,nma->nm", tangent, radius) / (st.T_D * r.r_p[0])
    assert np.abs(cos).max() < 1e-12
    # the heavy cable leaves the sheave lower than the straight one would (its tangent at D is steeper)
    assert (np.abs(res["gamma"] - ps.gamma) > 0).all()


def test_the_one_door_solves_heavy_robots_with_the_numpy_reference_and_refuses_the_rest(cdpr4):
    from cdpr import solve as door

    r = heavy(cdpr4)  # SR pulleys, vertical axes
    res = door.solve(r, PTS[:2], redundancy="physical", engine="numpy")
    ref = solve(r, PTS[:2])
    assert set(door.HEAVY_KEYS) <= set(res) and (res["status"] == ref["status"]).all()
    assert np.abs(res["P_s"] - ref["P_s"]).max() == 0.0
    np.testing.assert_array_equal(res["sag"], ref["sag"])
    with pytest.raises(CdprError, match="physical mode only"):
        door.solve(r, PTS[:1], redundancy="paper")
    with pytest.raises(
        CdprError, match="physical mode only"
    ):  # the sensitivities: tests/models/test_heavy_sensitivity.py
        door.sensitivities(r, PTS[:1], redundancy="paper")


def test_dr_pulleys_take_the_compiled_kernel_by_default(cdpr4):
    """The compiled kernel models every pulley (issue 38): a DR robot's default solve is the
    compiled one (to the bit), equal to the numpy reference to 1e-9 m."""
    from cdpr import solve as door

    r = heavy(with_pulleys(cdpr4, kind="DR"))
    got = door.solve(r, PTS[:2], redundancy="physical")
    np.testing.assert_array_equal(
        got["P_s"], door.solve(r, PTS[:2], redundancy="physical", engine="compiled")["P_s"]
    )
    ref = door.solve(r, PTS[:2], redundancy="physical", engine="numpy")
    assert (got["status"] == ref["status"]).all()
    np.testing.assert_allclose(got["P_s"], ref["P_s"], rtol=0, atol=1e-9)


def test_hanging_cables_is_ernsts_equivalent_modulus():
    """``hanging_cables``: a heavy cable hangs when Ernst's E_eq / E = 1 / (1 + (w l)^2 EA / (12 T^3))
    is below SLACK_STIFFNESS; at the threshold tension T* = ((w l)^2 EA / (12 (1/s - 1)))^(1/3) it
    switches; a massless cable never hangs, whatever its tension."""
    w, EA, L0 = np.array([0.619, 0.0]), np.array([1.284e6, 1.284e6]), np.array([[16.0, 16.0]])
    T_star = ((w[0] * L0[0, 0]) ** 2 * EA[0] / (12.0 * (1.0 / SLACK_STIFFNESS - 1.0))) ** (1.0 / 3.0)
    assert 40.0 < T_star < 55.0  # CoGiRo's 4 mm cable: about 47 N
    for T, want in ((0.99 * T_star, True), (1.01 * T_star, False), (1e-3, True), (5000.0, False)):
        e_ratio = 1.0 / (1.0 + (w[0] * L0[0, 0]) ** 2 * EA[0] / (12.0 * T**3))
        assert (e_ratio < SLACK_STIFFNESS) == want
        np.testing.assert_array_equal(hanging_cables(np.array([[T, T]]), w, EA, L0), [[want, False]])


@pytest.mark.parametrize("engine", ["compiled", "numpy"])
def test_heavy_cables_hanging_at_their_own_weight_trigger_the_restarts(engine):
    """CoGiRo at the plane's edge (z = 2 m), where the massless model leaves cables slack and finds
    two equilibria: with heavy cables every cable pulls (7-19 N on the hanging ones), but those hang
    (``hanging_cables``), so the restarts run and find the second, higher-energy equilibrium; the
    answer is the lowest-energy one, as the restarts forced everywhere give it."""
    robot = load_robot(ROBOTS / "cogiro.yaml")
    p = np.array([[-2.466, -5.5342, 2.0], [1.903225, 5.4753, 2.0]])
    res = door(robot, p, redundancy="physical", rotvec=np.zeros(3), engine=engine)
    assert (res["status"] == "ok").all() and (res["n_taut"] == 8).all()  # every heavy cable pulls
    assert not res["unique"].any()
    for alts, e in zip(res["alternatives"], res["energy"]):
        assert alts and all(a["energy"] > e + 1.0 for a in alts)
    massless = door(with_values(robot, linear_density=0.0), p, redundancy="physical", rotvec=np.zeros(3))
    assert not massless["unique"].any() and (massless["n_taut"] < 8).all()
    hanging = hanging_cables(res["t"], robot.arrays.w, robot.arrays.ES, res["L0"])
    # the massless model's slack cables hang (one taut there at 4 N hangs too with its weight)
    assert hanging[~massless["taut"]].all() and (8 - hanging.sum(axis=1) < 6).all()  # fewer than 6 hold it
