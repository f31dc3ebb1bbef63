"""Paper mode (Paty 2021: every 3-cable subset solved with DEGM_E, the admissible one with the lowest
|dp| chosen) on point-mass robots whose pulley swivel axes are not +z.

The key check is physical: a whole robot turned by a rotation R (anchors A_i, swivel axes k_i, the
zero of each swivel angle and gravity) is the same machine, so at R p it must give R times the
solution at p, with the same tensions, subsets and statuses. The suspended robots' own rules (points
at or above the lowest pulley inaccessible, the floor, the fixed point's "smaller z" sphere
intersection, which becomes "on gravity's side") must not apply to a turned robot; the large
rotation below turns the workspace upside down and under the floor to make sure of it."""

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.analyses.workspace import grid_points
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.compiled.sensitivity import sensitivities_fast
from cdpr.compiled.subsets import solve_points_fast
from cdpr.errors import CdprError
from cdpr.models.direct import _Subset, degm_e
from cdpr.models.inverse import L_TS
from cdpr.models.subsets import solve_points
from cdpr.parameters import parameter_names, parameter_values, robot_with_parameters
from cdpr.robot import load_robot, with_pulleys
from cdpr.solve import sensitivities, subset_sensitivities
from cdpr.solve import solve as solve_any
from cdpr.tables import solve_table
from tests.conftest import ROBOTS

CDPR4 = ROBOTS / "cdpr4.yaml"

#: Rotations of the whole robot: none (the general path on an unturned robot, see ``turned``), a
#: small generic one (not about z alone) and a large one (about 172 deg) that turns the robot nearly
#: upside down: gravity nearly +z, the workspace box below the floor z = 0 and above every pulley in z.
ROTVECS = {
    "identity": (0.0, 0.0, 0.0),
    "small": (0.3, -0.2, 0.1),
    "large": (3.0, 0.3, 0.15),
}


def rotation(name):
    return Rotation.from_rotvec(ROTVECS[name]).as_matrix()


def _vec(v):
    return tuple(float(x) for x in v)


def turned(robot, R, zero=True):
    """``robot`` (a suspended point mass) turned as a whole by the rotation matrix R: every anchor
    A_i -> R A_i, swivel axis k_i -> R k_i, gravity ``down`` -> R down. With ``zero`` each pulley's
    zero of the swivel angle is the turned i-axis of the robot's own pulley frame (R i_i), so the
    pulley frames turn exactly (frame rows R i_i, R j_i, R k_i). Giving ``zero`` makes the robot
    not suspended even for R = I (the general path). Without ``zero`` the default frame is used
    (+x projected): a different swivel-angle zero, the same physics."""
    frame = robot.arrays.frame
    cables = tuple(
        dataclasses.replace(
            c,
            A=_vec(R @ c.A),
            pulley=dataclasses.replace(
                c.pulley, axis=_vec(R @ c.pulley.axis), zero=_vec(R @ frame[i, 0]) if zero else None
            ),
        )
        for i, c in enumerate(robot.cables)
    )
    platform = dataclasses.replace(robot.platform, down=_vec(R @ np.asarray(robot.platform.down)))
    return dataclasses.replace(robot, cables=cables, platform=platform)


def workspace_points(n=150, seed=7):
    """Points of CDPR4 (anchors at z = 5, x, y = +-2.5): ``n`` random ones in the box x, y in
    [-1.5, 1.5], z in [0.5, 3] (held by some subset: ok) and a few outside the footprint, below the
    pulleys (every subset needs a pushing cable: slack)."""
    rng = np.random.default_rng(seed)
    inside = np.column_stack([rng.uniform(-1.5, 1.5, n), rng.uniform(-1.5, 1.5, n), rng.uniform(0.5, 3.0, n)])
    outside = np.array([[3.5, 0.0, 2.0], [0.3, -3.4, 1.5], [-3.2, 2.9, 2.5], [3.1, 3.3, 1.0]])
    return np.vstack([inside, outside])


@pytest.fixture(scope="module", params=["SR", "DR"])
def pair(request):
    """(original CDPR4, its pulley kind) for each kind; CDPR4 is a suspended point mass."""
    r = load_robot(CDPR4, pulley=request.param)
    assert r.suspended_point_mass
    return r, request.param


def solve(robot, p, engine):
    return solve_any(robot, p, redundancy="paper", engine=engine)


# ---- the turned robot itself -------------------------------------------------------------------
@pytest.mark.parametrize("name", ["small", "large"])
def test_the_turned_robot_is_the_rotated_image(pair, name):
    """Checks of the construction the other tests rely on: a point mass that is not suspended,
    pulley frames, anchors and gravity turned exactly, and the same commanded lengths L_TS."""
    a, _ = pair
    R = rotation(name)
    b = turned(a, R)
    assert b.point_mass and not b.suspended_point_mass
    np.testing.assert_allclose(b.arrays.frame, a.arrays.frame @ R.T, rtol=0, atol=1e-15)
    np.testing.assert_allclose(b.A, a.A @ R.T, rtol=0, atol=1e-14)
    np.testing.assert_allclose(b.platform.w_ext, R @ a.platform.w_ext, rtol=1e-15, atol=1e-12)
    p = workspace_points()
    np.testing.assert_allclose(L_TS(b, p @ R.T), L_TS(a, p), rtol=0, atol=1e-12)


# ---- 1. rotation invariance --------------------------------------------------------------------
@pytest.mark.parametrize("engine", ["numpy", "compiled"])
@pytest.mark.parametrize("name", ["identity", "small", "large"])
def test_turning_the_whole_robot_turns_the_paper_mode_solution(pair, name, engine):
    """At R p the turned robot gives R P_s(p) (1e-9 m), the same status, chosen subset and |dp|
    (1e-9 m) and the same tensions (1e-6 relative) as the original at p. For R = I it is the
    general (tilted-axis) path against the suspended one on the same machine."""
    a, _ = pair
    R = rotation(name)
    b = turned(a, R)
    p = workspace_points()
    ra, rb = solve(a, p, engine), solve(b, p @ R.T, engine)
    assert (ra["status"][:-4] == "ok").all() and (ra["status"][-4:] == "slack").all()  # the points' design
    np.testing.assert_array_equal(rb["status"], ra["status"])
    np.testing.assert_array_equal(rb["subset"], ra["subset"])
    assert np.isfinite(ra["P_s"]).all()
    np.testing.assert_allclose(rb["P_s"], ra["P_s"] @ R.T, rtol=0, atol=1e-9)
    np.testing.assert_allclose(rb["dp"], ra["dp"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(rb["t"], ra["t"], rtol=1e-6, atol=1e-9, equal_nan=True)
    np.testing.assert_array_equal(np.isnan(rb["t"]), np.isnan(ra["t"]))  # the same slack cable
    assert ra["dp"][:-4].max() > 1e-3  # pulleys and elasticity do move the platform (mm)
    if name == "large":
        # the suspended robots' rules would refuse every turned point of the box: below the floor
        # z = 0 and above every pulley in z
        q = p[:-4] @ R.T
        assert (q[:, 2] < 0).all() and (q[:, 2] > b.A[:, 2].max()).all()


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
def test_the_default_swivel_zero_gives_the_same_solution(pair, engine):
    """Without ``zero`` the turned pulleys take the default frame (+x projected on the plane normal
    to each axis): only the zero of the swivel angle differs, so the solution is the same."""
    a, _ = pair
    R = rotation("small")
    b = turned(a, R, zero=False)
    assert all(c.pulley.zero is None for c in b.cables) and not b.suspended_point_mass
    p = workspace_points(60)
    ra, rb = solve(a, p, engine), solve(b, p @ R.T, engine)
    np.testing.assert_array_equal(rb["status"], ra["status"])
    np.testing.assert_array_equal(rb["subset"], ra["subset"])
    np.testing.assert_allclose(rb["P_s"], ra["P_s"] @ R.T, rtol=0, atol=1e-9)
    np.testing.assert_allclose(rb["t"], ra["t"], rtol=1e-6, atol=1e-9, equal_nan=True)


def test_degm_e_of_one_subset_turns_with_the_robot(pair):
    """``degm_e`` itself (one subset, Newton) on the turned robot: R P, the same tensions,
    convergence and existence."""
    a, _ = pair
    R = rotation("small")
    b = turned(a, R)
    p = workspace_points(40)[:40]
    for s in ((0, 1, 2), (1, 2, 3), (0, 2, 3)):
        da, db = degm_e(a, p, subset=s), degm_e(b, p @ R.T, subset=s)
        np.testing.assert_array_equal(db.converged, da.converged)
        np.testing.assert_array_equal(db.exists, da.exists)
        assert da.converged.any()
        np.testing.assert_allclose(db.P, da.P @ R.T, rtol=0, atol=1e-9)
        np.testing.assert_allclose(db.t, da.t, rtol=1e-6, atol=1e-9)


def test_solve_table_on_the_turned_robot(pair):
    """``cdpr.tables.solve_table`` in paper mode on the turned robot: one row per point, the
    columns of paper mode, the same numbers as ``solve.solve``."""
    a, _ = pair
    R = rotation("small")
    b = turned(a, R)
    q = workspace_points(30) @ R.T
    df = solve_table(b, q, redundancy="paper", engine="numpy")
    res = solve(b, q, "numpy")
    assert len(df) == len(q)
    assert list(df["status"]) == list(res["status"])
    np.testing.assert_allclose(df["dp"].to_numpy(), res["dp"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(df[["x_s", "y_s", "z_s"]].to_numpy(), res["P_s"], rtol=0, atol=1e-12)


# ---- 2. compiled = numpy on turned robots ------------------------------------------------------
@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
@pytest.mark.parametrize("name", ["small", "large"])
def test_compiled_equals_numpy_on_the_turned_robot(name, kind):
    b = turned(load_robot(CDPR4, pulley=kind), rotation(name))
    q = workspace_points(120, seed=11) @ rotation(name).T
    a, c = solve_points(b, q), solve_points_fast(b, q)
    assert set(a["status"]) == {"ok", "slack"}
    np.testing.assert_array_equal(c["status"], a["status"])
    np.testing.assert_array_equal(c["subset"], a["subset"])
    np.testing.assert_array_equal(c["iterations"], a["iterations"])
    np.testing.assert_allclose(c["P_s"], a["P_s"], rtol=0, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(c["dp"], a["dp"], rtol=0, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(c["t"], a["t"], rtol=1e-9, atol=1e-6, equal_nan=True)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_iteration_cap_equals_numpy_on_the_turned_robot(kind):
    """With an iteration cap that some points need more than, both engines flag the same points
    not_converged on the turned robot and agree on the others."""
    b = turned(load_robot(CDPR4, pulley=kind), rotation("small"))
    q = grid_points([-2.0, 2.0, -2.0, 2.0, 0.5, 4.0], 5) @ rotation("small").T  # up near the pulleys
    a, c = solve_points(b, q, maxiter=3), solve_points_fast(b, q, maxiter=3)
    assert (a["status"] == "not_converged").any() and (a["status"] == "ok").any()
    np.testing.assert_array_equal(c["status"], a["status"])
    np.testing.assert_array_equal(c["iterations"], a["iterations"])
    np.testing.assert_array_equal(c["subset"], a["subset"])
    np.testing.assert_allclose(c["t"], a["t"], rtol=1e-9, atol=1e-6, equal_nan=True)


def test_every_subset_is_solved_on_the_turned_robot():
    """No pruning by the anchor triangles seen from above (a suspended robot's shortcut): the
    compiled kernel solves all four subsets of every point of a turned CDPR4."""
    b = turned(load_robot(CDPR4, pulley="SR"), rotation("small"))
    q = workspace_points(50) @ rotation("small").T
    res = solve_points_fast(b, q)
    assert (res["subset_solves"] == len(b.subsets)).all()


# ---- 3. analytic limit -------------------------------------------------------------------------
@pytest.mark.parametrize("engine", ["numpy", "compiled"])
@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
@pytest.mark.parametrize("name", ["small", "large"])
def test_point_pulleys_and_rigid_cables_reach_the_desired_point(name, kind, engine):
    """h = r_p = 0 (the pulley is a point: L_TE = |P - A| + d = L_TS) and a huge Young's modulus:
    DEGM_E's solution is the desired point, |dp| < 1e-6 m at every ok point of the turned robot.
    With the real modulus the same robot sags by millimetres (the assertion can fail)."""
    R = rotation(name)
    over = {"pulley": kind} if kind == "fixed" else {"pulley": kind, "h": 0.0, "r_p": 0.0}
    stiff = turned(load_robot(CDPR4, E=1e20, **over), R)
    soft = turned(load_robot(CDPR4, **over), R)
    q = workspace_points(100, seed=3) @ R.T
    res = solve(stiff, q, engine)
    ok = res["status"] == "ok"
    assert ok.sum() >= 100
    assert res["dp"][ok].max() < 1e-6
    np.testing.assert_allclose(res["P_s"][ok], q[ok], rtol=0, atol=1e-6)
    sag = solve(soft, q, engine)
    assert sag["dp"][sag["status"] == "ok"].max() > 1e-3


# ---- 5. what stays refused ---------------------------------------------------------------------
def _one_line(exc):
    msg = str(exc.value)
    assert msg and "\n" not in msg, msg
    return msg


@pytest.fixture(scope="module")
def tilted():
    return turned(load_robot(CDPR4, pulley="SR"), rotation("small"))


@pytest.mark.parametrize("name", ["small", "large"])
def test_the_fixed_point_turns_with_the_robot(pair, name):
    """The paper's fixed point (sphere intersections, eq. 8-9) on the turned robot: each pulley in
    its frame and the intersection kept on gravity's side of the sheave centres' plane. It gives R
    times the suspended robot's answer (same statuses, subsets and sphere intersections), and the
    same P* as Newton at a tight tolerance. The large rotation turns gravity nearly to +z: the
    paper's "smaller z" rule would pick the mirror point there."""
    a, _ = pair
    R = rotation(name)
    b = turned(a, R)
    p = workspace_points(40)
    ra = solve_any(a, p, method="fixed_point", engine="numpy", tol=1e-10)
    rb = solve_any(b, p @ R.T, method="fixed_point", engine="numpy", tol=1e-10)
    assert (ra["status"] == rb["status"]).all() and (ra["subset"] == rb["subset"]).all()
    assert (ra["iterations"] == rb["iterations"]).all()
    ok = ra["status"] == "ok"
    assert ok.sum() > 30 and {"slack"} <= set(ra["status"])
    assert np.abs(rb["P_s"][ok] - ra["P_s"][ok] @ R.T).max() < 1e-9
    rn = solve_any(b, p @ R.T, engine="numpy")
    assert (rn["status"] == rb["status"]).all() and (rn["subset"] == rb["subset"]).all()
    assert np.abs(rn["P_s"][ok] - rb["P_s"][ok]).max() < 1e-9


def test_the_fixed_point_at_the_papers_tolerance_on_the_turned_robot(tilted):
    """At the paper's stop criterion (1e-5 m) the fixed point stays within a few tolerances of
    Newton, through every entry (solve_points, degm_e, solve_table)."""
    q = workspace_points(20) @ rotation("small").T
    n = solve_points(tilted, q)
    f = solve_points(tilted, q, method="fixed_point")
    ok = n["status"] == "ok"
    assert (n["status"] == f["status"]).all() and ok.sum() > 15
    assert np.abs(n["P_s"][ok] - f["P_s"][ok]).max() < 5e-5
    assert 5 < f["iterations"][ok].mean() < 200
    d = degm_e(tilted, q[ok], subset=(0, 1, 2), method="fixed_point")
    assert d.exists.any()
    df = solve_table(tilted, q, method="fixed_point", engine="numpy")
    assert list(df["status"]) == list(f["status"])


def test_the_fixed_point_still_runs_on_suspended_robots(pair):
    a, _ = pair
    res = solve_any(a, np.array([[0.5, 0.2, 2.5]]), method="fixed_point", engine="numpy")
    assert list(res["status"]) == ["ok"]


# ---- paper-mode sensitivities dP*/dθ on the turned robot ----------------------------------------
#: Points of CDPR4 away from its diagonals and axes (where two subsets tie and a point is not smooth).
SENS_POINTS = np.array(
    [[0.7, -1.3, 0.4], [-1.6, 0.5, 1.9], [1.1, 1.9, 3.1], [-0.4, -2.0, 2.6], [2.1, 0.3, 1.2]]
)


def _full_solve(robot, q, L):
    return solve_points_fast(robot, q, L=L, tol=1e-13)["P_s"]


@pytest.mark.parametrize("kind", ["SR", "DR", "fixed"])
def test_sensitivities_on_the_turned_robot_equal_central_differences(kind):
    """dP*/dθ by the implicit-function theorem, each cable's partials taken in its pulley frame,
    against central differences of full paper-mode solves (every subset and the paper's choice) of
    the turned robot with each parameter moved (relative step 1e-4 for E and M, 1e-6 m otherwise);
    the compiled engine equals the numpy reference."""
    h, r_p = {"SR": (0.1077, 0.035), "DR": (0.1, 0.08), "fixed": (0.0, 0.0)}[kind]
    R = rotation("small")
    robot = turned(with_pulleys(load_robot(CDPR4), kind=kind, h=h, r_p=r_p), R)
    q = SENS_POINTS @ R.T
    a = sensitivities(robot, q, engine="numpy")
    b = sensitivities(robot, q, engine="compiled")
    assert a["smooth"].all() and b["smooth"].all()
    assert np.abs(a["S"] - b["S"]).max() <= 1e-9 * np.abs(a["S"]).max()
    L = L_TS(robot, q)
    th = parameter_values(robot)
    names = parameter_names(robot)
    for k, name in enumerate(names):
        step = 1e-4 * th[k] if name[0] in "EM" else 1e-6
        up, down = th.copy(), th.copy()
        up[k] += step
        down[k] -= step
        fd = (_full_solve(robot_with_parameters(robot, up), q, L) - _full_solve(
            robot_with_parameters(robot, down), q, L)) / (2 * step)  # fmt: skip
        err = np.linalg.norm(a["S"][:, :, k] - fd, axis=1)
        bound = 1e-5 * np.linalg.norm(fd, axis=1) + 1e-13 / step
        assert (err <= bound).all(), (name, a["S"][:, :, k], fd)
        if name[0] != "E" and not (kind == "fixed" and name[:2] in ("h_", "r_")):
            # the parameters of the three taut cables move the point: the test compares no zeros
            assert np.abs(fd).max() > 1e-6 or np.abs(a["S"][:, :, k]).max() == 0.0, name


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
@pytest.mark.parametrize("name", ["identity", "small", "large"])
def test_sensitivities_turn_with_the_robot(pair, name, engine):
    """Turning the whole robot by R turns dP*/dθ: R S for the scalar parameters (E, h, r_p, d, M)
    and R S_A Rᵀ for the joint points A_i; the same smoothness flags and gaps. The suspended robot's
    sensitivities (frame-free arithmetic) are the reference."""
    a, _ = pair
    R = rotation(name)
    b = turned(a, R)
    p = SENS_POINTS
    ra = sensitivities(a, p, engine=engine)
    rb = sensitivities(b, p @ R.T, engine=engine)
    assert (ra["status"] == rb["status"]).all() and (ra["smooth"] == rb["smooth"]).all()
    assert ra["smooth"].all()
    names = ra["names"]
    scale = np.abs(ra["S"]).max(axis=(0, 1))
    for k, nm in enumerate(names):
        if nm.startswith("A_"):
            continue
        assert np.abs(rb["S"][:, :, k] - ra["S"][:, :, k] @ R.T).max() <= 1e-9 * scale[k] + 1e-300, nm
    for c in range(a.m):
        cols = [names.index(f"A_{c + 1}_{x}") for x in "xyz"]
        want = R @ ra["S"][:, :, cols] @ R.T
        assert np.abs(rb["S"][:, :, cols] - want).max() <= 1e-9 * np.abs(want).max() + 1e-12, c
    assert np.allclose(rb["dp_gap"], ra["dp_gap"], rtol=0, atol=1e-9)
    assert np.allclose(rb["margin_t"], ra["margin_t"], rtol=1e-9, atol=1e-6)


def test_compiled_sensitivities_equal_numpy_on_the_turned_robot(tilted):
    """Over ok, slack and lone-cable points: the same statuses and smoothness flags, NaN at the same
    places, dP*/dθ within 1e-9 of each column's scale; and every subset's (``subset_sensitivities``)."""
    q = workspace_points(60) @ rotation("small").T
    a = sensitivities(tilted, q, engine="numpy")
    b = sensitivities(tilted, q, engine="compiled")
    assert (a["status"] == b["status"]).all() and (a["smooth"] == b["smooth"]).all()
    assert {"ok", "slack"} <= set(a["status"])
    assert np.array_equal(np.isnan(a["S"]), np.isnan(b["S"]))
    ok = a["status"] == "ok"
    scale = np.nanmax(np.abs(a["S"][ok]), axis=0)
    assert (np.abs(a["S"][ok] - b["S"][ok]) <= 1e-9 * scale).all()
    c = subset_sensitivities(tilted, q[:12], engine="numpy")
    d = subset_sensitivities(tilted, q[:12], engine="compiled")
    assert (c["converged"] == d["converged"]).all() and (c["admissible"] == d["admissible"]).all()
    cv = c["converged"]
    assert cv.sum() > 20
    for key in ("S", "St"):
        sc = np.abs(c[key][cv]).max(axis=0)
        assert (np.abs(c[key][cv] - d[key][cv]) <= 1e-9 * sc + 1e-12).all(), key


@pytest.mark.parametrize("engine", ["numpy", "compiled"])
def test_physical_point_mass_sensitivities_on_the_turned_robot_go_through_the_pose_model(tilted, engine):
    """One door: physical-mode sensitivities of a point mass on leaning pulleys are the pose model's
    (``sensitivity.pose_sensitivities``: dp*/dθ and dφ*/dθ rows), not a refusal; the point's
    position rows equal the reference's and the rotation rows of a point mass are 0."""
    from cdpr.models.sensitivity import pose_sensitivities

    q = workspace_points(5) @ rotation("small").T
    res = sensitivities(tilted, q, redundancy="physical", engine=engine)
    ref = pose_sensitivities(tilted, q)
    assert res["S"].shape[1] == 6 and list(res["names"]) == list(ref["names"])
    np.testing.assert_array_equal(res["status"], ref["status"])
    ok = res["status"] == "ok"
    assert ok.sum() >= 3
    scale = np.abs(ref["S"][ok, :3]).max(axis=0, keepdims=True) + 1e-30
    assert (np.abs(res["S"][ok, :3] - ref["S"][ok, :3]) / scale).max() < 1e-4


@pytest.mark.parametrize(
    "call",
    [
        lambda r, q: sensitivities_fast(r, q, redundancy="physical"),
        lambda r, q: solve_physical_fast(r, q),
    ],
    ids=["sensitivities_fast", "solve_physical_fast"],
)
def test_compiled_point_mass_physical_entries_refuse_leaning_pulleys(tilted, call):
    """Called directly, the compiled point-mass physical kernels refuse pulleys at other axes (their
    cable kernel takes +z axes) as their numpy twins do, instead of ignoring the axes."""
    q = workspace_points(5) @ rotation("small").T
    with pytest.raises(CdprError) as exc:
        call(tilted, q)
    _one_line(exc)


@pytest.fixture(scope="module")
def cogiro():
    r = load_robot(ROBOTS / "cogiro.yaml")
    assert not r.point_mass
    return r


@pytest.mark.parametrize(
    "call",
    [
        lambda r, p: solve_any(r, p, redundancy="paper", engine="numpy"),
        lambda r, p: solve_any(r, p, redundancy="paper", engine="compiled"),
        lambda r, p: solve_any(r, p, redundancy="paper"),
        lambda r, p: solve_table(r, p, redundancy="paper"),
        lambda r, p: solve_points(r, p),
        lambda r, p: degm_e(r, p),
        lambda r, p: solve_points_fast(r, p),
        lambda r, p: sensitivities(r, p, redundancy="paper", engine="numpy"),
        lambda r, p: sensitivities(r, p, redundancy="paper"),
        lambda r, p: subset_sensitivities(r, p),
        lambda r, p: sensitivities_fast(r, p),
    ],
    ids=[
        "any-numpy",
        "any-compiled",
        "any-default",
        "solve_table",
        "solve_points",
        "degm_e",
        "solve_points_fast",
        "sensitivities-numpy",
        "sensitivities",
        "subset_sensitivities",
        "sensitivities_fast",
    ],
)
def test_paper_mode_still_refuses_a_rigid_platform(cogiro, call):
    with pytest.raises(CdprError) as exc:
        call(cogiro, np.array([[0.0, 0.0, 2.0], [0.5, -0.3, 1.5]]))
    assert "physical" in _one_line(exc)


# ---- 6. the residual and its Jacobian ----------------------------------------------------------
def _residual_points():
    """A few desired points p of CDPR4 and points P near them where the residual is evaluated."""
    p = np.array([[0.4, -0.3, 2.2], [-1.1, 0.8, 1.0], [0.9, 1.2, 2.9], [-0.2, -1.3, 0.6]])
    P = p + np.array([[0.01, -0.02, -0.03], [-0.005, 0.01, -0.02], [0.02, 0.0, -0.01], [0.0, 0.015, -0.025]])
    return p, P


@pytest.mark.parametrize("kind", ["SR", "DR"])
@pytest.mark.parametrize("subset", [(0, 1, 2), (1, 2, 3)])
def test_residual_turns_with_the_robot(kind, subset):
    """F = L_TE(P) - L (1 + t/(E S)) and t of the turned robot at R P equal the original's at P
    (1e-12 m, 1e-9 relative); the Jacobians turn: J_b = J_a R^T, dt_b = dt_a R^T."""
    a = load_robot(CDPR4, pulley=kind)
    R = rotation("small")
    b = turned(a, R)
    p, P = _residual_points()
    L = L_TS(a, p)[:, list(subset)]
    Fa, ta, va, Ja, dta = _Subset(a, subset).residual(P, L, jacobian=True)
    Fb, tb, vb, Jb, dtb = _Subset(b, subset).residual(P @ R.T, L, jacobian=True)
    assert va.all() and vb.all()
    np.testing.assert_allclose(Fb, Fa, rtol=0, atol=1e-12)
    np.testing.assert_allclose(tb, ta, rtol=1e-9, atol=0)
    np.testing.assert_allclose(Jb, Ja @ R.T, rtol=0, atol=1e-9 * np.abs(Ja).max())
    np.testing.assert_allclose(dtb, dta @ R.T, rtol=0, atol=1e-9 * np.abs(dta).max())


@pytest.mark.parametrize("kind", ["SR", "DR"])
@pytest.mark.parametrize("name", ["small", "large"])
@pytest.mark.parametrize("subset", [(0, 1, 2), (0, 2, 3)])
def test_analytic_jacobian_equals_central_differences_on_the_turned_robot(kind, name, subset):
    """J = dF/dP and dt/dP of ``_Subset.residual`` against central differences (step 1e-6 m) at
    points of the turned robot, to 1e-6 of their largest entry."""
    R = rotation(name)
    b = turned(load_robot(CDPR4, pulley=kind), R)
    p, P = _residual_points()
    q, Q = p @ R.T, P @ R.T
    sub = _Subset(b, subset)
    L = L_TS(b, q)[:, list(subset)]
    F, t, valid, J, dt = sub.residual(Q, L, jacobian=True)
    assert valid.all() and np.isfinite(J).all() and np.isfinite(dt).all()
    step = 1e-6
    J_fd, dt_fd = np.empty_like(J), np.empty_like(dt)
    for k in range(3):
        e = np.zeros(3)
        e[k] = step
        Fp, tp, _ = sub.residual(Q + e, L)
        Fm, tm, _ = sub.residual(Q - e, L)
        J_fd[..., k] = (Fp - Fm) / (2 * step)
        dt_fd[..., k] = (tp - tm) / (2 * step)
    for n in range(len(Q)):
        assert np.abs(J[n] - J_fd[n]).max() < 1e-6 * np.abs(J[n]).max(), n
        assert np.abs(dt[n] - dt_fd[n]).max() < 1e-6 * np.abs(dt[n]).max(), n
    # the pulley terms are there: J differs from the straight-cable Jacobian -u by far more than the tolerance
    assert np.abs(J).max() > 0.5


def test_suspended_robot_is_still_suspended_and_unchanged(pair):
    """CDPR4 keeps today's model: suspended, the z rule of the residual (a point above the pulleys
    is not a valid evaluation) and the floor rule in ``solve.solve``."""
    a, _ = pair
    sub = _Subset(a, (0, 1, 2))
    P = np.array([[0.0, 0.0, 2.0], [0.0, 0.0, 5.5]])
    _, _, valid = sub.residual(P, L_TS(a, P)[:, :3])
    assert list(valid) == [True, False]
    res = solve_any(a, np.array([[0.0, 0.0, -0.5], [0.0, 0.0, 2.0]]), engine="numpy")
    assert list(res["status"]) == ["inaccessible", "ok"]


def test_with_pulleys_keeps_the_turned_axes(pair):
    """``with_pulleys`` on a turned robot keeps its axes and zeros (so the studies that vary the
    pulley design keep the tilt) and paper mode still runs on it."""
    a, _ = pair
    b = turned(a, rotation("small"))
    c = with_pulleys(b, kind="DR", h=0.12, r_p=0.05)
    assert [x.pulley.axis for x in c.cables] == [x.pulley.axis for x in b.cables]
    assert [x.pulley.zero for x in c.cables] == [x.pulley.zero for x in b.cables]
    res = solve(c, workspace_points(10)[:10] @ rotation("small").T, "numpy")
    assert (res["status"] == "ok").all()
