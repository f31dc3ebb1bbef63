"""The compiled heavy inverse (``cdpr.compiled.cables.inverse``, issue 38) equals the numpy reference
(``cdpr.models.cables.HeavyCables.inverse``): the exit points, the catenaries that carry the
tensions at B_i and the rest lengths within 1e-9 m (forces within 1e-9 of the tensions), the same
convergence flags, including cables whose tension at B no catenary carries (the reference does not
converge there), over 64 poses of CDPR4 (point mass, SR), CoGiRo (SR and its DR design), the 8-cable
rigid platform with swivel axes and gravity turned off the vertical, fixed pulleys and w -> 0; and
the sag-consistent distribution (``compensation.heavy_distribution``) and the compensation by either
engine: the same tensions (1e-9 relative) and feasibility, and the compiled compensation's round
trip through the heavy direct model within 1e-9 m and 1e-9 rad."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.analyses.compensation import compensate, compensated_pose, heavy_distribution
from cdpr.analyses.workspace import grid_points
from cdpr.compiled import cables as ccables
from cdpr.compiled import equilibrium as cequilibrium
from cdpr.models.cables import HeavyCables
from cdpr.models.platform import pose_arrays
from cdpr.robot import load_robot, with_pulleys, with_values
from tests.models.test_equilibrium_heavy import Q_TILT, tilted
from tests.models.test_equilibrium_heavy import heavy as heavy_robot

RHO = 0.0631  # [kg/m] a 4 mm steel cable
RW_C = [-2.32, 2.32, -2.32, 2.32, 0.0, 3.73]  # CDPR4's regular workspace (the paper's)
COGIRO_BOX = [-4.0, 4.0, -3.0, 3.0, 1.0, 3.5]
#: lengths [m] and angles [rad] within these, forces [N] within this times the largest tension
TOL = 1e-9
LENGTHS = ("D", "l_h", "l_v", "L0_free", "L0", "l_dead")
FORCES = ("H", "V_B", "V_D", "T_D")
UNITLESS = ("e_h", "f", "gamma")


def _cogiro(kind=None, rho=RHO):
    r = load_robot("config/robots/cogiro.yaml")
    if kind == "DR":  # the study's DRopt design
        r = with_pulleys(r, kind="DR", h=0.075, r_p=0.05)
    return with_values(r, linear_density=rho)


def _poses(box, rigid, seed=5):
    """64 poses on the 4^3 grid of ``box``, turned by up to 0.1 rad about random axes when ``rigid``."""
    P = grid_points(box, 4)
    rng = np.random.default_rng(seed)
    rv = rng.uniform(-0.1, 0.1, P.shape) if rigid else None
    return pose_arrays(P, rv)


def _tensions(n, m, seed=6):
    """Tensions at B [N] from 30 to 3000 N, and two cables no catenary can hold: zero tension, and
    0.5 N at B, a fraction of one cable's weight (the reference does not converge there)."""
    t = np.random.default_rng(seed).uniform(30.0, 3000.0, (n, m))
    t[3, 0] = 0.0
    t[7, 1] = 0.5
    return t


def _case(name):
    """(robot, p (64, 3), R (64, 3, 3)) of each robot the test runs."""
    cdpr4 = load_robot("config/robots/cdpr4.yaml")
    if name == "cdpr4 SR":
        return (with_values(cdpr4, linear_density=RHO), *_poses(RW_C, False))
    if name == "cdpr4 fixed":
        return (with_values(with_pulleys(cdpr4, kind="fixed"), linear_density=RHO), *_poses(RW_C, False))
    if name == "cdpr4 SR w->0":
        return (with_values(cdpr4, linear_density=1e-12), *_poses(RW_C, False))
    if name == "cdpr4 SR w=0":
        return (cdpr4, *_poses(RW_C, False))
    if name == "cogiro SR":
        return (_cogiro(), *_poses(COGIRO_BOX, True))
    if name == "cogiro DR":
        return (_cogiro("DR"), *_poses(COGIRO_BOX, True))
    # the 8-cable rigid platform, its swivel axes off the gravity's line and the gravity turned
    G = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix()
    r = heavy_robot(tilted("SR", Q_TILT, G))
    P, R = _poses([-0.4, 0.4, -0.3, 0.3, 1.3, 1.8], True)
    Gq = G @ Q_TILT
    return r, P @ Gq.T, np.einsum("ab,nbc->nac", G, R)


CASES = ("cdpr4 SR", "cdpr4 fixed", "cdpr4 SR w->0", "cdpr4 SR w=0", "cogiro SR", "cogiro DR", "tilted SR")


def largest_difference(a, b, t):
    """The largest difference of the twins' lengths [m] and angles, and of their forces relative to
    the largest tension."""
    worst = 0.0
    for k in (*LENGTHS, *UNITLESS):
        worst = max(worst, float(np.nanmax(np.abs(a[k] - b[k]), initial=0.0)))
    for k in FORCES:
        worst = max(worst, float(np.nanmax(np.abs(a[k] - b[k]), initial=0.0)) / t.max())
    return worst


@pytest.mark.parametrize("name", CASES)
def test_compiled_inverse_equals_the_reference(name):
    robot, p, R = _case(name)
    t = _tensions(len(p), robot.m)
    a = HeavyCables(robot).inverse(p, R, t)
    cab = cequilibrium.CompiledHeavyCables(robot)
    b = ccables.inverse(cab, p, R, t)
    assert set(a) == set(b)
    np.testing.assert_array_equal(b["converged"], a["converged"])
    # zero tension; 0.5 N at B held by no catenary of that weight (a weightless cable carries it)
    weightless = "w" in name
    assert not a["converged"][3, 0] and a["converged"][7, 1] == weightless
    assert a["converged"].sum() == a["converged"].size - (1 if weightless else 2)  # every other cable
    for k in (*LENGTHS, *FORCES, *UNITLESS):
        np.testing.assert_array_equal(np.isnan(b[k]), np.isnan(a[k]), err_msg=k)
    assert largest_difference(a, b, t) <= TOL
    np.testing.assert_array_equal(b["r"], a["r"])
    # the count of the fixed point's passes: the reference's global stop rule against one per cable
    assert isinstance(b["iterations"], int) and abs(b["iterations"] - a["iterations"]) <= 2
    if name == "cdpr4 fixed":  # no pulley: one pass, D = A
        assert a["iterations"] == b["iterations"] == 1
        np.testing.assert_array_equal(b["D"], np.broadcast_to(robot.arrays.A, b["D"].shape))
    if name.startswith("cogiro"):  # the catenaries are there to see: the force leaves the chord
        assert (np.abs(a["V_B"] - a["H"] * a["l_v"] / a["l_h"])[a["converged"]] > 1e-3).all()


def test_compiled_inverse_of_weightless_cables_is_the_chord():
    """w = 0: the force at B lies along the chord to D (Hooke's spring), in both engines."""
    robot, p, R = _case("cdpr4 SR w=0")
    t = np.full((len(p), robot.m), 800.0)
    b = ccables.inverse(cequilibrium.CompiledHeavyCables(robot), p, R, t)
    assert b["converged"].all() and b["iterations"] <= 2
    np.testing.assert_allclose(b["V_B"] * b["l_h"], b["H"] * b["l_v"], rtol=0, atol=1e-9 * 800.0 * 5.0)


@pytest.mark.parametrize("name", ["cdpr4 SR", "cogiro DR"])
def test_heavy_distribution_by_either_engine(name):
    robot, p, R = _case(name)
    p, R = p[::3], R[::3]  # 22 poses
    if name == "cogiro DR":  # and one in the top corner of the frame, where no distribution exists
        p, R = np.vstack([p, [[7.0, 5.0, 5.3]]]), np.concatenate([R, np.eye(3)[None]])
    a = heavy_distribution(robot, p, R, t_min=100.0, engine="numpy")
    b = heavy_distribution(robot, p, R, t_min=100.0, engine="compiled")
    np.testing.assert_array_equal(b["feasible"], a["feasible"])
    assert a["feasible"][:22].all()
    if name == "cogiro DR":
        assert not a["feasible"][-1]
    ok = a["feasible"]
    scale = np.abs(a["t"][ok]).max(axis=1, keepdims=True)
    assert (np.abs(b["t"][ok] - a["t"][ok]) / scale).max() <= 1e-9
    assert np.abs(b["L0"][ok] - a["L0"][ok]).max() <= TOL
    assert np.isnan(b["t"][~ok]).all() and np.isnan(b["L0"][~ok]).all()
    # the default engine is the compiled one
    d = heavy_distribution(robot, p, R, t_min=100.0)
    np.testing.assert_array_equal(d["t"], b["t"])


def test_compensation_by_either_engine_and_its_round_trip():
    """CoGiRo DR: compensate by either engine (tensions, lengths and the planned cables alike), and
    the compiled compensation's lengths hold the platform at the desired poses in the heavy direct
    model (the compiled equilibrium started away from them) within 1e-9 m and 1e-9 rad."""
    robot, p, R = _case("cogiro DR")
    p6 = np.concatenate([p[::4], Rotation.from_matrix(R[::4]).as_rotvec()], axis=1)  # 16 poses
    a = compensate(robot, p6, t_min=100.0, engine="numpy")
    b = compensate(robot, p6, t_min=100.0, engine="compiled")
    assert a["feasible"].all() and b["feasible"].all()
    np.testing.assert_allclose(b["t"], a["t"], rtol=1e-9)
    assert np.abs(b["L0"] - a["L0"]).max() <= TOL
    np.testing.assert_array_equal(b["cables"]["cable_status"], a["cables"]["cable_status"])
    for k in ("sag", "arc_minus_chord", "D", "gamma"):
        assert np.abs(b["cables"][k] - a["cables"][k]).max() <= TOL, k
    np.testing.assert_allclose(b["cables"]["t_B"], a["cables"]["t_B"], rtol=1e-9)
    o = compensated_pose(robot, p6, t_min=100.0, engine="compiled", solver={"P0": p6[:, :3] + 0.02})
    assert (o["status"] == "ok").all()
    assert o["dp"].max() <= 1e-9 and o["dphi"].max() <= 1e-9
    # the tensions there: the planned ones to the stiffest cable's EA / L0 times 1e-9 m
    k = (robot.ES / b["L0"]).max()
    assert np.abs(o["t"] - b["t"]).max() <= k * 1e-9
