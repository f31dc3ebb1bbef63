"""Physical equilibrium on all cables (cdpr.models.equilibrium): derivatives against finite differences,
energy and force, uniqueness, limits, symmetry, agreement with paper mode on CDPR3, statuses."""

import dataclasses

import numpy as np
import pytest

from cdpr.models.cables import FTOL_REL, Cables
from cdpr.models.equilibrium import solve as solve_pose
from cdpr.models.inverse import L_TS
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.results import point_keys, taut_labels
from cdpr.models.subsets import solve_points
from cdpr.robot import read_yaml, robot_from_dict, with_pulleys, with_values
from cdpr.tables import to_frame
from tests.conftest import ROBOTS

rng = np.random.default_rng(11)
# points well inside CDPR4 (|x|, |y| < 2.2, 0.3 < z < 4.3)
PTS = np.column_stack([rng.uniform(-2.2, 2.2, 60), rng.uniform(-2.2, 2.2, 60), rng.uniform(0.3, 4.3, 60)])
KINDS = ["fixed", "SR", "DR"]


def mixed_robot():
    """CDPR4 with one cable of each kind and different materials, dead lengths and pulleys."""
    data = read_yaml(ROBOTS / "cdpr4.yaml")
    data["cables"][0]["pulley"] = {"kind": "fixed", "h_m": 0.0, "r_p_m": 0.0}
    data["cables"][1]["pulley"] = {"kind": "DR", "h_m": 0.12, "r_p_m": 0.05}
    data["cables"][2]["dead_length_m"] = 3.0
    data["cables"][3]["pulley"] = {"kind": "DR", "h_m": 0.08, "r_p_m": 0.04}
    return with_values(robot_from_dict(data), E_cables=[80e9, 120e9, 95e9, 130e9])


def robots(cdpr4):
    return {k: with_pulleys(cdpr4, kind=k) for k in KINDS} | {"mixed": mixed_robot()}


def central_fd(f, P, step):
    """Central differences of f (N, 3) -> (N, ...) along x, y, z: (N, ..., 3)."""
    cols = []
    for a in range(3):
        dP = np.zeros(3)
        dP[a] = step
        cols.append((f(P + dP) - f(P - dP)) / (2 * step))
    return np.stack(cols, axis=-1)


def _near(cab, n=60, seed=3):
    """Points P near desired points p (rest lengths L_TS(p)) with every cable away from its kink."""
    r = np.random.default_rng(seed)
    p = PTS[:n]
    P = p + r.normal(0, 0.03, p.shape) - [0, 0, 0.05]
    L0 = L_TS(cab.robot, p)
    e = total_length_and_direction(P, *cab.args).L_TE - L0
    keep = (np.abs(e) > 1e-4).all(axis=1)
    return p[keep], P[keep], L0[keep]


class _PointCables:
    """The pose model's ``Cables`` at the identity orientation, seen as a point mass's: F, J = dF/dP
    (3 x 3), grad = dV/dP (3,) and the taut cables."""

    def __init__(self, robot):
        self.cables, self.robot, self.args = Cables(robot), robot, Cables(robot).args

    def evaluate(self, P, L0, p, jacobian=True):
        ev = self.cables.evaluate(P, np.broadcast_to(np.eye(3), (len(P), 3, 3)), L0, p, jacobian)
        ev["taut"] = ev["t"] > 0.0
        if jacobian:
            ev["J"], ev["grad"] = ev["J"][:, :3, :3], ev["grad"][:, :3]
        return ev


def solve_physical(robot, p, **options):
    """The numpy equilibrium of a point mass with the point-mass keys (what ``cdpr.solve`` returns)."""
    return point_keys(solve_pose(robot, p, **options))


def _cab(r):
    return _PointCables(r)


@pytest.mark.parametrize("name", ["fixed", "SR"])
def test_energy_gradient_is_minus_the_force_for_fixed_and_SR(cdpr4, name):
    """V(P) = -w_ext . (P - p) + sum E S / (2 L0) max(0, L_TE - L0)^2: grad V = -(sum t u + w_ext)."""
    cab = _cab(robots(cdpr4)[name])
    p, P, L0 = _near(cab)
    assert len(p) > 30
    ev = cab.evaluate(P, L0, p)
    assert ev["taut"].any(axis=1).all() and (~ev["taut"]).any()  # slack and taut cables both occur
    fd = central_fd(lambda Q: cab.evaluate(Q, L0, p, jacobian=False)["merit"], P, 1e-6)
    scale = np.linalg.norm(ev["F"], axis=1, keepdims=True)
    assert (np.abs(fd + ev["F"]) / scale).max() < 1e-6
    assert np.allclose(ev["grad"], -ev["F"], rtol=0, atol=1e-9)


@pytest.mark.parametrize("name", ["DR", "mixed"])
def test_DR_energy_gradient_has_the_arm_term(cdpr4, name):
    """With the bisector reading of the DR arm, dV/dP (checked by finite differences) differs from
    -F by sum t arm ((u + u_C) . beta) eps: small but not zero (why Newton solves the force balance)."""
    cab = _cab(robots(cdpr4)[name])
    p, P, L0 = _near(cab)
    ev = cab.evaluate(P, L0, p)
    fd = central_fd(lambda Q: cab.evaluate(Q, L0, p, jacobian=False)["merit"], P, 1e-6)
    scale = np.linalg.norm(ev["F"], axis=1)
    assert (np.linalg.norm(fd - ev["grad"], axis=1) / scale).max() < 1e-6
    pull = ev["taut"].any(axis=1)
    assert pull.sum() > 20
    gap = np.linalg.norm(ev["grad"] + ev["F"], axis=1)[pull] / np.linalg.norm(ev["t"], axis=1)[pull]
    assert 1e-8 < gap.max() < 1e-2


@pytest.mark.parametrize("name", KINDS + ["mixed"])
def test_force_jacobian_matches_finite_differences(cdpr4, name):
    cab = _cab(robots(cdpr4)[name])
    p, P, L0 = _near(cab)
    ev = cab.evaluate(P, L0, p)
    pull = ev["taut"].any(axis=1)  # (with every cable slack F is constant; J is then Hooke's extension)
    assert pull.sum() > 20
    fd = central_fd(lambda Q: cab.evaluate(Q, L0, p, jacobian=False)["F"], P, 1e-6)
    scale = np.abs(ev["J"]).max(axis=(1, 2))[:, None, None]
    assert (np.abs(ev["J"] - fd) / scale)[pull].max() < 1e-6


@pytest.mark.parametrize("name", KINDS + ["mixed"])
def test_equilibrium_is_balanced_and_hooke_holds(cdpr4, name):
    r = robots(cdpr4)[name]
    res = solve_physical(r, PTS)
    ok = res["status"] == "ok"
    assert ok.sum() > 50
    P = res["P_s"]
    g = total_length_and_direction(P, r.A, r.kind, r.h, r.r_p, r.d, r.inward)
    t = np.nan_to_num(res["t"])
    F = np.einsum("nj,nja->na", t, g.u) + r.platform.w_ext
    assert np.linalg.norm(F[ok], axis=1).max() <= FTOL_REL * r.platform.mass * r.platform.g * 1.0001
    L0 = L_TS(r, PTS)
    taut = res["taut"]
    assert np.allclose(t[taut], (r.ES * (g.L_TE - L0) / L0)[taut], rtol=1e-12, atol=1e-9)
    assert (g.L_TE[~taut] <= L0[~taut]).all()  # slack cables are not stretched
    assert np.isnan(res["t"][~taut]).all() and (res["t"][taut] > 0).all()


@pytest.mark.parametrize("name", ["fixed", "SR", "mixed"])
def test_several_starts_reach_the_same_equilibrium(cdpr4, name):
    """The potential is (nearly) convex: starts around, above and below the desired point give one P*."""
    r = robots(cdpr4)[name]
    p = PTS[:20]
    ref = solve_physical(r, p)
    assert (ref["status"] == "ok").all()
    for off in ([0.3, -0.2, 0.1], [-0.25, 0.25, -0.4], [0.0, 0.0, 0.45], [0.1, 0.1, -0.8]):
        res = solve_physical(r, p, P0=p + np.array(off))
        same = res["status"] == "ok"
        assert same.all()
        assert np.linalg.norm(res["P_s"] - ref["P_s"], axis=1).max() < 1e-9


def test_rigid_cables_and_point_pulleys_give_no_error(cdpr4):
    for kind in ("SR", "DR"):
        # (beyond E ~ 1e18 Pa the stretch sinks below the round-off of P)
        res = [
            solve_physical(with_pulleys(cdpr4, kind=kind, h=0.0, r_p=0.0, E=E), PTS)
            for E in (1e12, 1e13, 1e16)
        ]
        for x in res:
            assert np.isin(x["status"], ["ok", "over_tension"]).all()
        # elasticity alone: |dp| ~ 1/E
        ratio = res[0]["dp"] / res[1]["dp"]
        assert np.allclose(ratio, 10.0, rtol=1e-2)
        assert res[2]["dp"].max() < 1e-6


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_centre_of_cdpr4_holds_on_four_equal_tensions(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    p = np.column_stack([np.zeros(5), np.zeros(5), [0.2, 1.0, 2.5, 3.5, 4.2]])
    res = solve_physical(r, p)
    assert (res["status"] == "ok").all() and (res["n_taut"] == 4).all()
    assert np.abs(res["P_s"][:, :2]).max() < 1e-12
    t = res["t"]
    assert (np.ptp(t, axis=1) / t.mean(axis=1)).max() < 1e-9


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_cdpr3_physical_equals_paper_mode(cdpr3, kind):
    """Three cables: one subset, and where it is admissible all three are taut, so both modes solve
    the same equations."""
    r = with_pulleys(cdpr3, kind=kind)
    u = rng.uniform(0.05, 0.95, (200, 2))
    A = r.A[:, :2]
    xy = A[0] + u[:, :1] * (A[1] - A[0]) + (u[:, :1] * u[:, 1:]) * (A[2] - A[1])  # inside the triangle
    p = np.column_stack([xy, rng.uniform(0.0, 4.2, 200)])
    phys, paper = solve_physical(r, p), solve_points(r, p)
    ok = paper["status"] == "ok"
    assert ok.sum() > 150
    assert (phys["status"][ok] == "ok").all() and (phys["n_taut"][ok] == 3).all()
    assert np.linalg.norm(phys["P_s"][ok] - paper["P_s"][ok], axis=1).max() < 1e-9
    assert np.abs(phys["t"][ok] - paper["t"][ok]).max() < 1e-5


def test_per_cable_modulus_equal_to_the_robot_modulus_changes_nothing(cdpr4):
    data = read_yaml(ROBOTS / "cdpr4.yaml")
    E = data["cable"]["young_modulus_Pa"]
    per_cable = with_values(robot_from_dict(data), E_cables=[E] * 4)
    for kind in ("SR", "DR"):
        a = solve_physical(with_pulleys(cdpr4, kind=kind), PTS)
        b = solve_physical(with_pulleys(per_cable, kind=kind), PTS)
        for key in ("P_s", "t", "taut", "iterations", "status"):
            np.testing.assert_array_equal(a[key], b[key])


def test_per_cable_moduli_follow_their_cables(cdpr4):
    """Mirror x -> -x swaps cables 1<->2 and 3<->4: swapping their moduli mirrors the solution."""
    data = read_yaml(ROBOTS / "cdpr4.yaml")
    a_r = with_values(robot_from_dict(data), E_cables=[80e9, 120e9, 95e9, 130e9])
    b_r = with_values(robot_from_dict(data), E_cables=[120e9, 80e9, 130e9, 95e9])
    mirror = np.array([-1.0, 1.0, 1.0])
    a, b = solve_physical(a_r, PTS), solve_physical(b_r, PTS * mirror)
    assert np.linalg.norm(a["P_s"] * mirror - b["P_s"], axis=1).max() < 1e-9
    assert np.nanmax(np.abs(a["t"][:, [1, 0, 3, 2]] - b["t"])) < 1e-6
    uniform = solve_physical(cdpr4, PTS)
    assert np.abs(a["dp"] - uniform["dp"]).max() > 1e-3  # the moduli matter


def test_pendulum_on_two_cables_is_ok(cdpr4):
    """Cables 3 and 4 paid out by 2 m go slack: the platform hangs on cables 1 and 2 in the vertical
    plane through their exit points, a physical equilibrium (status ok, two taut cables). With SR
    pulleys that plane is the frame's face y = -2.5 m (the sheaves turn into it)."""
    r = with_pulleys(cdpr4, kind="SR")
    p = np.array([[0.0, -1.5, 2.5], [0.0, -1.0, 3.5], [1.0, -2.0, 3.0]])
    L0 = L_TS(r, p) + [0.0, 0.0, 2.0, 2.0]
    res = solve_physical(r, p, L0=L0)
    assert (res["status"] == "ok").all()
    assert (res["taut"] == [True, True, False, False]).all()
    assert np.abs(res["P_s"][:2, 0]).max() < 1e-12  # symmetric about x = 0
    g = total_length_and_direction(res["P_s"], r.A, r.kind, r.h, r.r_p, r.d, r.inward)
    normal = np.cross(g.u[:, 0], g.u[:, 1])
    assert (
        np.abs(normal[:, 2]).max() < 1e-9 * np.linalg.norm(normal, axis=1).min()
    )  # the cable plane is vertical


def test_statuses(cdpr3, cdpr4):
    r = with_pulleys(cdpr4, kind="SR")
    p = np.array(
        [
            [0.0, 0.0, 5.2],  # above the pulleys
            [0.0, 0.0, 4.99],  # just under: tensions far above T_a
            [2.6, 0.0, 2.0],  # outside the frame
            [0.5, 0.3, 2.0],
        ]
    )
    res = solve_physical(r, p)
    assert list(res["status"]) == ["inaccessible", "over_tension", "inaccessible", "ok"]
    assert list(solve_physical(r, p[3:], maxiter=1)["status"]) == ["not_converged"]
    # CDPR3: a corner of the anchors' bounding box is outside the triangle
    assert solve_physical(cdpr3, [[2.4, 2.8, 2.0]])["status"][0] == "inaccessible"


def test_frame_and_labels(cdpr4):
    p = np.array([[0.0, 0.0, 2.5], [0.0, -1.5, 2.5]])
    res = solve_physical(
        with_pulleys(cdpr4, kind="SR"), p, L0=L_TS(cdpr4, p) + [[0.0] * 4, [0.0, 0.0, 0.0, 0.5]]
    )
    df = to_frame(cdpr4, res, "physical")
    assert list(df.columns) == [
        "x",
        "y",
        "z",
        "x_s",
        "y_s",
        "z_s",
        "dp",
        "t1",
        "t2",
        "t3",
        "t4",
        "taut",
        "n_taut",
        "iterations",
        "status",
    ]
    assert list(df["taut"]) == ["1-2-3-4", "1-2-3"]
    codes, labels = taut_labels(np.array([[False] * 4, [True, False, True, True]]))
    assert [labels[c] for c in codes] == ["", "1-3-4"] and len(labels) == 16
    assert df["t4"].isna().tolist() == [False, True]


def test_robot_dataclass_is_not_mutated(cdpr4):
    before = dataclasses.asdict(cdpr4)
    solve_physical(cdpr4, PTS[:3])
    assert dataclasses.asdict(cdpr4) == before


# ---- compiled engine ------------------------------------------------------------------------
def _grid_with_edges(robot, n=9):
    """A grid over the anchors' bounding box from the floor to above the pulleys (every status)."""
    from cdpr.analyses.workspace import frame_box, grid_points

    x0, x1, y0, y1, _, z1 = frame_box(robot)
    return grid_points([x0 - 0.6, x1 + 0.6, y0 - 0.6, y1 + 0.6, -0.2, z1 + 0.8], n)


@pytest.mark.parametrize("name", KINDS + ["mixed", "cdpr3_SR", "cdpr3_DR"])
def test_compiled_equals_numpy_reference(cdpr3, cdpr4, name):
    """Same statuses and convergence everywhere; where the equilibrium is unique (converged, two or
    more taut cables) the same taut sets, P* to 1e-9 m and tensions to 1e-8 relative. A lone SR or
    DR cable has a circle of equilibria (neutral swivel), where P* depends on round-off."""
    from cdpr.compiled.equilibrium import solve_points as solve_physical_fast

    r = with_pulleys(cdpr3, kind=name[6:]) if name.startswith("cdpr3") else robots(cdpr4)[name]
    p = np.vstack([PTS, _grid_with_edges(r)])
    for kw in (
        {},
        {"maxiter": 2},
        {"L0": L_TS(r, p) + rng.uniform(-0.02, 0.3, (len(p), r.m))},
        {"P0": p + rng.normal(0, 0.1, p.shape)},
    ):
        a, b = solve_physical(r, p, **kw), solve_physical_fast(r, p, **kw)
        assert set(a) == set(b)
        np.testing.assert_array_equal(a["status"], b["status"])
        np.testing.assert_array_equal(a["converged"], b["converged"])
        unique = a["converged"] & (a["n_taut"] >= 2)
        np.testing.assert_array_equal(a["taut"][unique], b["taut"][unique])
        assert np.abs(a["P_s"] - b["P_s"])[unique].max(initial=0.0) < 1e-9
        assert (np.abs(a["t"] - b["t"]) / np.fmax(1.0, np.abs(a["t"])))[a["taut"] & unique[:, None]].max(
            initial=0.0
        ) < 1e-8
        lone = a["converged"] & (a["n_taut"] == 1)
        assert (a["residual"][lone] <= 1e-9 * 2943.0).all() and (b["residual"][lone] <= 1e-9 * 2943.0).all()
    if kw.get("maxiter") is None:
        assert {"ok", "inaccessible"} <= set(a["status"]) and unique.sum() > 300


def test_statuses_of_a_batch_equal_each_robots_and_the_frame_is_the_anchors_hull():
    """statuses_batch groups robots by their hulls' number of edges: a square robot (4 edges) and
    the same robot with one anchor pulled inside the triangle of the others (3 edges) give, in one
    batch, each robot's own statuses; outside_frame is the anchors' horizontal hull (scipy's
    Delaunay, away from the edges) and the height of the lowest anchor."""
    from scipy.spatial import Delaunay

    from cdpr.models.results import TAUT_MIN, hull_halfplanes, outside_frame, statuses, statuses_batch
    from cdpr.parameters import parameter_values, robot_with_parameters

    square = with_pulleys(robot_from_dict(read_yaml(ROBOTS / "cdpr4.yaml")), kind="SR")
    th = parameter_values(square)
    m = square.m
    th[4 * m : 4 * m + 2] = 0.3 * th[4 * m : 4 * m + 2]  # anchor 1 inside the others' triangle
    dent = robot_with_parameters(square, th)
    robots = [square, dent, square]
    rng = np.random.default_rng(11)
    p = rng.uniform([-3.0, -3.0, -0.5], [3.0, 3.0, 5.5], (400, 3))
    P = p[None] + rng.normal(0.0, 0.05, (3, 400, 3))
    P[0, :5] = np.nan
    t = rng.uniform(-50.0, 1.2 * square.T_a.max(), (3, 400, m))
    t[:, 7] = 0.0  # no cable pulls
    conv = rng.uniform(size=(3, 400)) > 0.05
    inside = rng.uniform(size=(3, 400, 1)) > 0.97
    batch = statuses_batch(robots, p, P, t, conv, inside)
    for k, r in enumerate(robots):
        np.testing.assert_array_equal(batch[k], statuses(r, p, P[k], t[k], conv[k], inside[k]))
        np.testing.assert_array_equal(batch[k], statuses(r, p, P[k], t[k], conv[k], inside[k][:, 0]))  # (N,)
        hull = Delaunay(r.A[:, :2])
        out = outside_frame(r, p)
        hp = hull_halfplanes(r)
        clear = np.abs(p[:, :2] @ hp[:, :2].T + hp[:, 2]).min(axis=1) > 1e-6  # not on an edge's line
        expect = (hull.find_simplex(p[:, :2]) < 0) | (p[:, 2] >= r.A[:, 2].min())
        np.testing.assert_array_equal(out[clear], expect[clear])
        assert outside_frame(r, p[0]).shape == () and outside_frame(r, p[None]).shape == (1, 400)
    assert len({len(batch[0]), len(batch[1])}) == 1 and not np.array_equal(batch[0], batch[1])
    codes = set(np.unique(batch))
    assert len(codes) == 4, codes  # ok, over_tension, inaccessible, not_converged all occur
    assert (batch[:, 7] != 0).all() and TAUT_MIN > 0
