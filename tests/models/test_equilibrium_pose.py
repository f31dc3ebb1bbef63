"""Physical equilibrium of a rigid 6-DoF platform (issue 17): the point-mass mode as its special
case, symmetry, rotation invariance, a pendulum, the analytic Jacobian, several equilibria."""

import dataclasses

import numpy as np
import pytest

from cdpr.models.cables import Cables as Cables6
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.inverse import pose_state
from cdpr.models.platform import external_wrench, pose_arrays, rotation_matrix, wrench_matrix
from cdpr.models.tension_distribution import compensated_lengths
from cdpr.robot import robot_from_dict, with_pulleys
from cdpr.solve import solve as solve_any
from tests.point_mass import solve_physical

rng = np.random.default_rng(2024)
PTS = np.column_stack([rng.uniform(-2.4, 2.4, 200), rng.uniform(-2.4, 2.4, 200), rng.uniform(0.2, 4.8, 200)])
PTS = np.vstack([PTS, [[0.0, 0.0, 9.0], [7.0, 7.0, 1.0], [0.0, 0.0, 2.5]]])


def robot8(kind="fixed", mass=50.0, com=(0.0, 0.0, 0.0), turn=0.0):
    """8 crossed cables on a 6 x 4 x 3 m frame, symmetric about the x-z, y-z and z = 1.5 m planes; the whole
    robot (anchors, axes) turned by ``turn`` [rad] about z."""
    c, s = np.cos(turn), np.sin(turn)
    Q = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    cables = []
    for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
        cables.append({"A_m": (Q @ [3 * sx, 2 * sy, 3.0]).tolist(), "B_m": [-0.3 * sx, 0.2 * sy, 0.15]})
        cables.append(
            {
                "A_m": (Q @ [3 * sx, 2 * sy, 0.0]).tolist(),
                "B_m": [-0.3 * sx, 0.2 * sy, -0.15],
                "pulley": {"axis": [0, 0, -1]},
            }
        )
    pulley = {"kind": kind} | ({} if kind == "fixed" else {"h_m": 0.06, "r_p_m": 0.05})
    return robot_from_dict(
        {
            "platform": {"mass_kg": mass, "com_m": list(com)},
            "cable": {"young_modulus_Pa": 1e11, "diameter_m": 0.004, "max_tension_N": 5000},
            "pulley": pulley,
            "dead_length_m": 2.0,
            "cables": cables,
        }
    )


def pretensioned(r, p, rv, t0=1000.0):
    """Rest lengths that stretch every cable by t0 [N] at the desired pose."""
    p_, R = pose_arrays(p, rv)
    _, st = pose_state(r, p_, R)
    return st.L_TE / (1.0 + t0 / r.ES)


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_point_mass_robots_give_todays_physical_mode(cdpr4, cdpr3, kind):
    """b = 0, c = 0: the spatial solver (its 6-DoF code, moment rows reduced) reproduces the
    point-mass physical mode to 1e-9 m, with the same statuses and taut sets."""
    for robot in (cdpr4, cdpr3):
        r = with_pulleys(robot, kind=kind)
        a, b = solve_physical(r, PTS), solve_spatial(r, PTS)
        assert np.abs(a["P_s"] - b["P_s"]).max() < 1e-9
        assert (a["status"] == b["status"]).all() and (a["taut"] == b["taut"]).all()
        assert (b["dphi"] == 0).all() and (b["rotvec_s"] == 0).all()
    assert (b["status"][-3:-1] == "inaccessible").all()  # CDPR3 at (0, 0, 9) and (7, 7, 1)


@pytest.mark.parametrize("kind", ["fixed", "SR"])
def test_symmetric_platform_on_equal_tensions(kind):
    r = robot8(kind)
    p, rv = [[0.0, 0.0, 1.5]], [[0.0, 0.0, 0.0]]
    res = solve_spatial(r, p, rv, L0=pretensioned(r, p, rv))
    assert res["status"][0] == "ok" and res["n_taut"][0] == 8
    t = res["t"][0]
    upper, lower = t[0::2], t[1::2]
    assert np.ptp(upper) < 1e-6 * upper.mean() and np.ptp(lower) < 1e-6 * lower.mean()
    assert upper.mean() > lower.mean()  # the upper cables carry the weight
    assert np.abs(res["P_s"][0, :2]).max() < 1e-9 and res["dphi"][0] < 1e-9
    # weightless: all eight equal
    light = robot8(kind, mass=1e-6)
    t = solve_spatial(light, p, rv, L0=pretensioned(light, p, rv))["t"][0]
    assert np.ptp(t) < 1e-6 * t.mean()


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_wrench_balance_holds_at_the_solution(kind):
    r = robot8(kind, com=(0.02, -0.01, 0.05))
    p = [[0.3, -0.2, 1.4], [0.0, 0.1, 1.6]]
    rv = [[0.05, -0.1, 0.2], [np.radians(15), 0, 0]]
    res = solve_spatial(r, p, rv, L0=pretensioned(r, p, rv))
    assert (res["status"] == "ok").all()
    R = res["R_s"]
    B, st = pose_state(r, res["P_s"], R)
    u = st.D - B
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    W = wrench_matrix(u, B - res["P_s"][:, None, :])
    w = np.einsum("nam,nm->na", W, np.nan_to_num(res["t"])) + external_wrench(50.0, 9.81, r.arrays.com, R)
    assert np.abs(w).max() < 1e-6  # N and N m, under a 490 N weight


def central_jacobian(cab, p, R, L0, h):
    """d(F, M)/d(dp, dphi) (6, 6) of ``cab.evaluate`` at the first pose (p, R) by central
    differences of step h (dphi a base-frame rotation: R <- exp([dphi]) R)."""
    fd = np.empty((6, 6))
    for k in range(6):
        dx = np.zeros(6)
        dx[k] = h
        ev = [
            cab.evaluate(p + s * dx[:3], rotation_matrix(s * dx[3:]) @ R, L0, p, jacobian=False)
            for s in (1, -1)
        ]
        fd[:, k] = (
            np.concatenate([ev[0]["F"], ev[0]["M"]], 1) - np.concatenate([ev[1]["F"], ev[1]["M"]], 1)
        )[0] / (2 * h)
    return fd


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_analytic_jacobian_equals_finite_differences(kind):
    r = robot8(kind, com=(0.02, -0.01, 0.05))
    p, rv = np.array([[0.3, -0.2, 1.4]]), np.array([[0.05, -0.1, 0.2]])
    L0 = pretensioned(r, p, rv)
    cab = Cables6(r)
    _, R = pose_arrays(p, rv)
    J = cab.evaluate(p, R, L0, p)["J"][0]
    fd = central_jacobian(cab, p, R, L0, 1e-7)
    assert np.abs(J - fd).max() < 1e-5 * np.abs(J).max()


def test_rotating_the_whole_robot_about_gravity_rotates_the_solution():
    turn = 0.7
    c, s = np.cos(turn), np.sin(turn)
    Q = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    a, b = robot8("SR", com=(0.02, -0.01, 0.05)), robot8("SR", com=(0.02, -0.01, 0.05), turn=turn)
    p, rv = np.array([[0.3, -0.2, 1.4]]), np.array([[0.05, -0.1, 0.2]])
    from scipy.spatial.transform import Rotation

    rv_b = (Rotation.from_matrix(Q) * Rotation.from_rotvec(rv)).as_rotvec()
    ra = solve_spatial(a, p, rv, L0=pretensioned(a, p, rv))
    rb = solve_spatial(b, p @ Q.T, rv_b, L0=pretensioned(a, p, rv))
    assert np.abs(ra["P_s"] @ Q.T - rb["P_s"]).max() < 1e-9
    assert np.abs(Q @ ra["R_s"][0] - rb["R_s"][0]).max() < 1e-9
    assert np.abs(ra["t"] - rb["t"]).max() < 1e-6


def test_under_constrained_platform_hangs_its_centre_of_mass_below_the_cables_meeting_point():
    """Four cables to one attachment point b0: the platform is a pendulum on that point; it tilts
    until the centre of mass is straight below B0 (analytic), whatever the commanded tilt."""
    b0 = [0.1, 0.2, 0.3]
    cables = [{"A_m": [x, y, 4.0], "B_m": b0} for x, y in ((2, 2), (-2, 2), (-2, -2), (2, -2))]
    r = robot_from_dict(
        {
            "platform": {"mass_kg": 20.0, "com_m": [0.0, 0.0, -0.1]},
            "cable": {"young_modulus_Pa": 1e11, "diameter_m": 0.004, "max_tension_N": 5000},
            "pulley": {"kind": "SR", "h_m": 0.05, "r_p_m": 0.05},
            "dead_length_m": 1.0,
            "cables": cables,
        }
    )
    p, rv = [[0.0, 0.0, 2.0], [0.5, 0.3, 2.0]], [[0.0, 0.0, 0.0], [0.3, 0.0, 0.0]]
    res = solve_spatial(r, p, rv, L0=pretensioned(r, p, rv, 50.0))
    assert (res["status"] == "ok").all()
    R = res["R_s"]
    B0 = res["P_s"] + R @ np.array(b0)
    com = res["P_s"] + R @ np.array([0.0, 0.0, -0.1])
    assert np.abs((com - B0)[:, :2]).max() < 1e-9 and ((com - B0)[:, 2] < 0).all()
    assert (res["dphi"] > 0.1).all()  # it did tilt


def test_several_equilibria_are_found_and_the_lowest_is_returned():
    """Commanded with L_TS (no pretension) the crossed 8-cable robot at a tilt has slack cables;
    restarts look for other equilibria; the one returned has the lowest energy."""
    r = robot8("fixed")
    p = np.array([[0.0, 0.0, 1.5], [0.5, 0.3, 1.2], [0.0, 0.0, 1.5]])
    rv = np.array([[0, 0, 0], [0.1, 0, 0.2], [np.radians(15), 0, 0]])
    res = solve_spatial(r, p, rv)
    assert (res["status"] == "ok").all()
    for i in range(len(p)):
        assert res["unique"][i] == (len(res["alternatives"][i]) == 0)
        assert all(a["energy"] >= res["energy"][i] for a in res["alternatives"][i])


def robot8_turned(kind, Q, com=(0.02, -0.01, 0.05)):
    """``robot8`` with every pulley's ``zero`` given (so that the pulley frames turn with the robot)
    and the whole robot — anchors, swivel axes, zeros and gravity — turned by the rotation Q."""
    Q = np.asarray(Q, dtype=float)
    cables = []
    for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
        for z, bz, axis in ((3.0, 0.15, [0, 0, 1]), (0.0, -0.15, [0, 0, -1])):
            cables.append(
                {
                    "A_m": (Q @ [3 * sx, 2 * sy, z]).tolist(),
                    "B_m": [-0.3 * sx, 0.2 * sy, bz],
                    "pulley": {"axis": (Q @ axis).tolist(), "zero": (Q @ [1.0, 0.0, 0.0]).tolist()},
                }
            )
    pulley = {"kind": kind} | ({} if kind == "fixed" else {"h_m": 0.06, "r_p_m": 0.05})
    r = robot_from_dict(
        {
            "platform": {"mass_kg": 50.0, "com_m": list(com)},
            "cable": {"young_modulus_Pa": 1e11, "diameter_m": 0.004, "max_tension_N": 5000},
            "pulley": pulley,
            "dead_length_m": 2.0,
            "cables": cables,
        }
    )
    down = tuple(float(v) for v in Q @ [0.0, 0.0, -1.0])
    return dataclasses.replace(r, platform=dataclasses.replace(r.platform, down=down))


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_rotating_the_whole_robot_and_gravity_rotates_the_solution(kind):
    """Any rotation Q of the whole robot together with its gravity: the equilibrium under the same
    rest lengths is Q times the old one (positions Q p*, orientations Q R*), with the same tensions,
    taut sets and statuses; the compensated lengths at the turned poses are the same numbers."""
    from scipy.spatial.transform import Rotation

    Q = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix()
    a, b = robot8_turned(kind, np.eye(3)), robot8_turned(kind, Q)
    assert np.allclose(b.platform.w_ext, Q @ a.platform.w_ext, rtol=0, atol=1e-12)
    p = np.array([[0.3, -0.2, 1.4], [-0.5, 0.4, 1.7], [0.0, 0.0, 1.5]])
    rv = np.array([[0.05, -0.1, 0.2], [0.2, 0.1, -0.1], [0.0, 0.0, 0.0]])
    rv_b = (Rotation.from_matrix(Q) * Rotation.from_rotvec(rv)).as_rotvec()
    L0 = pretensioned(a, p, rv)
    assert np.abs(pretensioned(b, p @ Q.T, rv_b) - L0).max() < 1e-9  # the lengths do not see Q
    ra = solve_spatial(a, p, rv, L0=L0)
    rb = solve_spatial(b, p @ Q.T, rv_b, L0=L0)
    assert (ra["status"] == "ok").all() and (ra["status"] == rb["status"]).all()
    assert (ra["taut"] == rb["taut"]).all()
    assert np.abs(ra["P_s"] @ Q.T - rb["P_s"]).max() < 1e-9
    assert np.abs(Q @ ra["R_s"] - rb["R_s"]).max() < 1e-9
    assert np.abs(ra["t"] - rb["t"]).max() < 1e-6
    assert np.abs(ra["dp"] - rb["dp"]).max() < 1e-9 and np.abs(ra["dphi"] - rb["dphi"]).max() < 1e-9
    assert ra["dp"].max() > 1e-4  # the pulleys and the weight do move the platform
    fast = solve_any(
        b, p @ Q.T, rv_b, redundancy="physical", engine="compiled", L0=L0
    )  # the kernel sees the turned gravity too
    assert (fast["status"] == rb["status"]).all() and np.abs(fast["P_s"] - rb["P_s"]).max() < 1e-9
    ca, cb = compensated_lengths(a, p, rv), compensated_lengths(b, p @ Q.T, rv_b)
    ok = ca[
        "feasible"
    ]  # (the symmetric pose's wrench matrix has rank 5: no distribution holds the offset com)
    assert (ok == cb["feasible"]).all()
    assert np.allclose(ca["L0"][ok], cb["L0"][ok], rtol=0, atol=1e-9)
