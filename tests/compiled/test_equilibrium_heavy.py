"""The compiled physical equilibrium with heavy cables (cdpr.compiled.cables in the pose kernel of
cdpr.compiled.equilibrium, issue 38) equals the numpy reference (cdpr.models.equilibrium with
cdpr.models.cables.HeavyCables): the same statuses, taut sets and per-cable catenary statuses,
poses within 1e-9 m and 1e-9 rad, on CDPR4 with a linear density (fixed, SR, DR pulleys, swivel axes
off the gravity's line), on the 8-cable rigid platform with tilted axes and on CoGiRo (SR, and its
DR design) with its 4 mm cable's, at several poses, with cables lengthened until they hang in a U
(the heavy model's "slack": a cable that carries little more than its own weight); and
cdpr.solve routes heavy robots to it (its default engine) in solve and solve_batch."""

import dataclasses

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr import solve as door
from cdpr.compiled import cables as ccables
from cdpr.compiled import equilibrium as cequilibrium
from cdpr.models import equilibrium
from cdpr.models.cables import HeavyCables
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays
from cdpr.robot import load_robot, with_pulleys, with_values
from tests.models.test_equilibrium_heavy import P8, Q_TILT, RV8, massless_equilibrium, tilted
from tests.models.test_equilibrium_heavy import heavy as heavy_robot
from tests.models.test_equilibrium_pose import pretensioned

RHO = 0.0631  # [kg/m] a 4 mm steel cable (the cube50 robot's, issue 38)
CDPR4_PTS = np.array(
    [[0.0, 0.0, 2.5], [1.0, 0.5, 3.0], [-2.0, 1.5, 1.0], [1.2, -1.1, 4.2], [0.3, 0.2, 0.5], [2.2, 2.2, 0.4]]
)
COGIRO_POSES = np.array(
    [
        [0.0, 0.0, 2.0, 0.0, 0.0, 0.0],
        [1.0, 1.0, 1.5, 0.0, 0.0, 0.0],
        [0.0, 0.0, 2.0, np.radians(15.0), 0.0, 0.0],
        [-3.0, 2.0, 1.0, 0.05, -0.1, 0.2],
        [4.0, -2.5, 3.0, -0.1, 0.05, -0.3],
    ]
)
KEYS = ("t_B", "t_D", "H", "sag", "arc_minus_chord", "angle_f_deg")


def _lengthened(robot, p, rotvec=None, factor=1.003):
    """L_TS at the desired poses, the first cable of every other pose lengthened by ``factor``
    (it then hangs in a deeper sag, or a U, and carries little)."""
    P, R = pose_arrays(p, rotvec)
    L0 = L_TS(robot, P, R=R)
    L0[::2, 0] *= factor
    return L0


def _same(a, b, pose=True):
    np.testing.assert_array_equal(a["status"], b["status"])
    np.testing.assert_array_equal(a["taut"], b["taut"])
    np.testing.assert_array_equal(a["cable_status"], b["cable_status"])
    assert np.abs(a["P_s"] - b["P_s"]).max() <= 1e-9
    if pose:
        assert np.abs(a["rotvec_s"] - b["rotvec_s"]).max() <= 1e-9
        np.testing.assert_array_equal(a["unique"], b["unique"])
    scale = np.nanmax(a["t_B"])
    for k in KEYS:  # per-cable outputs: to round-off of the equilibrium (forces relative to the largest)
        tol = 1e-9 * scale if k in ("t_B", "t_D", "H") else 1e-9
        np.testing.assert_allclose(b[k], a[k], rtol=0, atol=tol, err_msg=k)
    np.testing.assert_allclose(b["t"], a["t"], rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize("kind, L0_factor", [("SR", None), ("SR", 1.003), ("fixed", 1.003)])
def test_compiled_heavy_point_mass_equals_the_reference(cdpr4, kind, L0_factor):
    r = with_values(with_pulleys(cdpr4, kind=kind), linear_density=RHO * 5)
    L0 = None if L0_factor is None else _lengthened(r, CDPR4_PTS, factor=L0_factor)
    a = equilibrium.solve(r, CDPR4_PTS, L0=L0)
    b = cequilibrium.solve(r, CDPR4_PTS, L0=L0)
    _same(a, b, pose=False)
    assert (a["status"] == "ok").all()
    assert (a["sag_max"] > 1e-3).all()  # the sag is there to see (mm to dm)
    if L0_factor is not None:  # the lengthened cables sag more and pull less than at L_TS
        std = equilibrium.solve(r, CDPR4_PTS)
        assert (a["sag"][::2, 0] > std["sag"][::2, 0]).all()
        assert (a["t_B"][::2, 0] < std["t_B"][::2, 0]).all()


def test_compiled_heavy_point_mass_with_its_density(cdpr4):
    """CDPR4 with the 4 mm cable's density (0.0631 kg/m): equal statuses and poses, and the sag
    moves the point by less than a millimetre on a 5 m robot."""
    r = with_values(cdpr4, linear_density=RHO)
    a = equilibrium.solve(r, CDPR4_PTS)
    b = cequilibrium.solve(r, CDPR4_PTS)
    _same(a, b, pose=False)
    massless = equilibrium.solve(cdpr4, CDPR4_PTS)
    moved = np.linalg.norm(a["P_s"] - massless["P_s"], axis=1)
    assert (moved > 0).all() and moved.max() < 1e-3


def test_compiled_heavy_rigid_platform_equals_the_reference_on_cogiro():
    r = load_robot("config/robots/cogiro.yaml", linear_density=RHO)
    assert r.heavy and not r.point_mass
    L0 = _lengthened(r, COGIRO_POSES[:, :3], COGIRO_POSES[:, 3:], factor=1.002)
    for lengths in (None, L0):
        a = equilibrium.solve(r, COGIRO_POSES, L0=lengths)
        b = cequilibrium.solve(r, COGIRO_POSES, L0=lengths)
        _same(a, b)
        assert (a["status"] != "not_converged").all()
        assert (a["sag_max"] > 5e-3).all()  # centimetres of sag on a 15 m robot


def test_the_door_routes_heavy_robots_to_the_compiled_kernel(cdpr4):
    r = with_values(cdpr4, linear_density=RHO)
    p = CDPR4_PTS[:3]
    res = door.solve(r, p, redundancy="physical")  # the default engine: compiled
    comp = door.solve(r, p, redundancy="physical", engine="compiled")
    ref = door.solve(r, p, redundancy="physical", engine="numpy")
    assert set(res) == set(ref) and set(door.HEAVY_KEYS) <= set(res)
    for k in ("P_s", "t", "sag", "t_D"):
        np.testing.assert_array_equal(res[k], comp[k])
    np.testing.assert_array_equal(res["status"], ref["status"])
    assert np.abs(res["P_s"] - ref["P_s"]).max() <= 1e-9
    # solve_batch: heavy robots one by one, by either engine, equal to their solves
    r2 = with_values(cdpr4, linear_density=2 * RHO)
    for engine in ("compiled", "numpy"):
        batch = door.solve_batch([r, r2], p, engine=engine)
        for rk, got in zip((r, r2), batch):
            one = door.solve(rk, p, redundancy="physical", engine=engine)
            np.testing.assert_array_equal(got["P_s"], one["P_s"])
            np.testing.assert_array_equal(got["sag_max"], one["sag_max"])
    assert (batch[1]["sag_max"] < batch[0]["sag_max"] * 2.5).all()
    assert (batch[1]["sag_max"] > batch[0]["sag_max"]).all()


# --- every pulley: DR pulleys and SR swivel axes off gravity (compiled.cables._general_at) ---------

#: A small tilt of every swivel axis (and its zero) off the vertical.
TILT = Rotation.from_rotvec([0.2, -0.1, 0.05]).as_matrix()


def _tilted_axes(robot, Q=TILT):
    """``robot`` with every pulley's swivel axis and zero turned by Q (gravity kept along -z)."""
    cables = []
    for c in robot.cables:
        axis = tuple(float(v) for v in Q @ np.asarray(c.pulley.axis, dtype=float))
        zero = tuple(float(v) for v in Q @ [1.0, 0.0, 0.0])
        cables.append(dataclasses.replace(c, pulley=dataclasses.replace(c.pulley, axis=axis, zero=zero)))
    return dataclasses.replace(robot, cables=tuple(cables))


def _same_heavy_keys(a, b):
    """The twins' per-cable outputs (``solve.HEAVY_KEYS``) to 1e-9 relative to each key's largest."""
    np.testing.assert_array_equal(a["cable_status"], b["cable_status"])
    for k in door.HEAVY_KEYS:
        if k != "cable_status":
            x, y = np.asarray(a[k], dtype=float), np.asarray(b[k], dtype=float)
            np.testing.assert_allclose(y, x, rtol=0, atol=1e-9 * np.nanmax(np.abs(x)), err_msg=k)


@pytest.mark.parametrize("kind, tilt", [("DR", False), ("SR", True), ("DR", True)])
def test_compiled_heavy_point_mass_on_dr_and_tilted_pulleys_equals_the_reference(cdpr4, kind, tilt):
    r = with_pulleys(cdpr4, kind=kind)
    r = with_values(_tilted_axes(r) if tilt else r, linear_density=RHO * 5)
    heavy = cequilibrium.CompiledHeavyCables(r).heavy
    assert heavy.general.all()  # heavy_arrays takes DR and tilted pulleys: every cable on the general path
    for L0 in (None, _lengthened(r, CDPR4_PTS, factor=1.003)):
        a = equilibrium.solve(r, CDPR4_PTS, L0=L0)
        b = cequilibrium.solve(r, CDPR4_PTS, L0=L0)
        _same(a, b, pose=False)
        _same_heavy_keys(a, b)
        assert (a["status"] == "ok").all() and (a["sag_max"] > 1e-3).all()


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_compiled_heavy_rigid_platform_on_tilted_axes_equals_the_reference(kind):
    """The 8-cable rigid platform of tests/models with swivel axes off the gravity's line, and the
    same robot with its gravity turned too (``tilted``): rotvec and pose to 1e-9, same statuses."""
    G = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix()
    for g in (np.eye(3), G):
        r = heavy_robot(tilted(kind, Q_TILT, g))
        p = P8 @ Q_TILT.T @ g.T
        rv = (Rotation.from_matrix(g) * Rotation.from_rotvec(RV8)).as_rotvec()
        assert cequilibrium.CompiledHeavyCables(r).heavy.general.all()
        L0 = pretensioned(r, p, rv, t0=300.0)
        a = equilibrium.solve(r, p, rv, L0=L0)
        b = cequilibrium.solve(r, p, rv, L0=L0)
        _same(a, b)
        _same_heavy_keys(a, b)
        assert (a["status"] == "ok").all() and a["sag_max"].max() > 1e-4


def test_compiled_heavy_rigid_platform_equals_the_reference_on_cogiro_dr():
    """CoGiRo's DR design (the study's DRopt: h 75 mm, r_p 50 mm) with its 4 mm cable's density, at
    the poses above, at L_TS and with cables lengthened into deep sags."""
    r = with_values(
        with_pulleys(load_robot("config/robots/cogiro.yaml"), kind="DR", h=0.075, r_p=0.05),
        linear_density=RHO,
    )
    # the default engine is the compiled one, which models it
    np.testing.assert_array_equal(
        door.solve(r, COGIRO_POSES)["P_s"], cequilibrium.solve(r, COGIRO_POSES)["P_s"]
    )
    L0 = _lengthened(r, COGIRO_POSES[:, :3], COGIRO_POSES[:, 3:], factor=1.002)
    for lengths in (None, L0):
        a = equilibrium.solve(r, COGIRO_POSES, L0=lengths)
        b = cequilibrium.solve(r, COGIRO_POSES, L0=lengths)
        _same(a, b)
        _same_heavy_keys(a, b)
        assert (a["status"] != "not_converged").all() and (a["sag_max"] > 5e-3).all()


@pytest.mark.parametrize("kind", ["DR", "SR_tilted"])
def test_weightless_heavy_dr_and_tilted_cables_give_the_massless_answer(cdpr4, kind):
    """w = 0 through the general coupling: the compiled heavy kernel (P* = B to round-off) lands on
    the massless equilibrium to 1e-12 m (its Jacobian is exact: a DR arm's turn and D's slide on the
    sheave; 2.6e-11 m without them). The compiled massless kernel's answer is that equilibrium to
    its force-balance stop (1e-10 of the weight: 1.8e-12 m on DR), along another Newton path (the
    massless one starts from Hooke extended to compression, the heavy one from slack cables); the
    numpy twins likewise (tests/models/test_equilibrium_heavy.py)."""
    r = with_pulleys(cdpr4, kind="DR") if kind == "DR" else _tilted_axes(with_pulleys(cdpr4, kind="SR"))
    a = cequilibrium.solve(r, CDPR4_PTS)
    b = cequilibrium.solve(r, CDPR4_PTS, heavy=True)
    assert (a["status"] == "ok").all() and (b["status"] == a["status"]).all()
    P, _ = massless_equilibrium(r, a)
    assert np.abs(b["P_s"] - P).max() < 1e-12
    assert np.abs(a["P_s"] - P).max() < 1e-11
    np.testing.assert_allclose(b["t"], a["t"], rtol=1e-9)
    assert (b["sag"] == 0).all()


@pytest.mark.parametrize("case", ["point mass SR", "point mass DR", "tilted SR", "tilted DR"])
def test_compiled_heavy_jacobian_equals_the_reference(cdpr4, case):
    """The kernel's exact Jacobian (``heavy_partials.exact_force_gradient``: the slide of D on the sheave,
    the swivel and a DR arm's turn) equals the numpy reference's (``heavy_partials``, itself checked
    against central differences) to 1e-11 of its largest entry, at a pose off the equilibrium."""
    if case.startswith("point mass"):
        r = heavy_robot(with_pulleys(cdpr4, kind=case[-2:]), rho=0.5)
        p, rv = np.array([[0.4, -0.3, 2.0]]), np.zeros((1, 3))
        L0 = equilibrium.solve(r, p)["L0"] * 1.001
    else:
        r = heavy_robot(tilted(case[-2:], Q_TILT), rho=0.5)
        p, rv = np.array([[0.3, -0.2, 1.4]]) @ Q_TILT.T, np.array([[0.05, -0.1, 0.2]])
        L0 = pretensioned(r, p, rv, t0=200.0)
    _, R = pose_arrays(p, rv)
    cab = cequilibrium.CompiledHeavyCables(r)
    n = 6 if cab.rigid else 3
    x, q = p[0], np.ascontiguousarray(R[0])
    Js = {}
    for exact in (True, False):  # the exact one, and the cheaper one of Newton's longer steps
        J = HeavyCables(r).evaluate(p, R, L0, p, exact=exact)["J"][0]
        w = cequilibrium.scratch(r.m)
        Jc, t, e6, g6 = np.empty((6, 6)), np.empty(r.m), np.empty(14), np.empty(8)
        ccables.evaluate(
            *x, q, *x, cab.cables, cab.body, cab.heavy, L0, 0, t, Jc, e6, g6, w.hg, w.cab_inside, w.cab_gamma,
            w.hc, w.hc, exact,
        )  # fmt: skip
        assert np.abs(Jc - J)[:n, :n].max() < 1e-11 * np.abs(J).max()
        Js[exact] = Jc
    slide = np.abs(Js[True] - Js[False])[:n, :n].max() / np.abs(J).max()
    if case == "point mass SR":  # a vertical swivel axis: D's slide on the sheave is all that differs
        assert 0.0 < slide < 1e-4
    else:  # the slide, the swivel off gravity and the arm matter
        assert slide > 1e-4
