"""The compiled 6-DoF physical equilibrium (cdpr.compiled.equilibrium) equals the numpy reference
(cdpr.models.equilibrium) on the shipped spatial robots at random tilted poses, slack cables and
several equilibria included; its general-axis cable kernel (``_kernels.cable_axis``) equals the
numpy pulley model with random axes and its derivatives equal finite differences; point-mass
robots give the compiled point-mass physical mode."""

import numpy as np
import pytest
from numba import njit

from cdpr.compiled import equilibrium as compiled6
from cdpr.compiled._kernels import cable, cable_axis, cable_derivatives
from cdpr.compiled._linalg import lu_solve, pinv_solve, positive_definite, rotvec_of_matrix
from cdpr.compiled.equilibrium import solve as solve_fast
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.models.equilibrium import RCOND
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.inverse import L_TS, pose_state
from cdpr.models.platform import pose_arrays, rotation_error, rotation_matrix, rotvec_of
from cdpr.models.pulleys import total_length_and_direction
from cdpr.models.statics import direction_gradient, length_gradient
from cdpr.parameters import parameter_values, robot_with_parameters
from cdpr.robot import load_robot, pulley_frame, with_pulleys
from cdpr.solve import solve_batch
from tests.conftest import ROBOTS

#: Per robot: the box [x0, x1, y0, y1, z0, z1] [m] of the random desired positions.
BOXES = {
    "cogiro_massless.yaml": (-3.0, 3.0, -2.0, 2.0, 1.0, 3.0),
    "ipanema_like.yaml": (-1.0, 1.0, -0.7, 0.7, 1.0, 2.0),
    "wall_pulleys.yaml": (-1.5, 1.5, -1.0, 1.0, 1.0, 2.5),
    "hang4_6dof.yaml": (-1.0, 1.0, -1.0, 1.0, 1.5, 3.5),
}
N_POSES = 300
MAX_TILT = np.radians(25.0)


def _poses(robot, box, n, seed):
    """n random positions in ``box``, rotation vectors of random axes and angles up to MAX_TILT, and
    rest lengths: L_TS at the desired pose for a third, L_TS (1 + U(-0.3 %, 0.5 %)) for the rest
    (slack cables, over-tension, pretension)."""
    g = np.random.default_rng(seed)
    x0, x1, y0, y1, z0, z1 = box
    p = np.column_stack([g.uniform(x0, x1, n), g.uniform(y0, y1, n), g.uniform(z0, z1, n)])
    rv = g.normal(size=(n, 3))
    rv *= MAX_TILT * g.uniform(0, 1, (n, 1)) / np.linalg.norm(rv, axis=1, keepdims=True)
    p_, R = pose_arrays(p, rv)
    L0 = L_TS(robot, p_, R=R)
    L_TE = pose_state(robot, p_, R)[1].L_TE
    L0[n // 3 :] = L_TE[n // 3 :] * (1.0 - g.uniform(-0.001, 0.003, (n - n // 3, robot.m)))
    return p, rv, L0


def _same(a, b):
    """Same statuses, taut sets, unique flags, alternatives count; poses within 1e-9 m and 1e-9 rad;
    returns the largest position and orientation deviations."""
    assert set(a) == set(b)
    np.testing.assert_array_equal(a["status"], b["status"])
    np.testing.assert_array_equal(a["converged"], b["converged"])
    np.testing.assert_array_equal(a["taut"], b["taut"])
    np.testing.assert_array_equal(a["unique"], b["unique"])
    np.testing.assert_array_equal(a["wrap_over_270"], b["wrap_over_270"])
    assert [len(x) for x in a["alternatives"]] == [len(x) for x in b["alternatives"]]
    fin = np.isfinite(a["P_s"]).all(axis=1)
    np.testing.assert_array_equal(fin, np.isfinite(b["P_s"]).all(axis=1))
    dp = np.abs(a["P_s"] - b["P_s"])[fin].max(initial=0.0)
    dphi = rotation_error(a["R_s"], b["R_s"])[fin].max(initial=0.0)
    assert np.abs(a["rotvec_s"] - b["rotvec_s"])[fin].max(initial=0.0) < 1e-9
    np.testing.assert_allclose(a["L0"], b["L0"], rtol=1e-15, atol=0)
    assert dp < 1e-9 and dphi < 1e-9, (dp, dphi)
    rel = np.abs(a["t"] - b["t"]) / np.fmax(1.0, np.abs(a["t"]))
    assert np.nan_to_num(rel).max() < 1e-6
    return dp, dphi


@pytest.mark.parametrize("name", list(BOXES))
def test_compiled_equals_numpy_on_the_spatial_robots(name):
    r = load_robot(ROBOTS / name)
    p, rv, L0 = _poses(r, BOXES[name], N_POSES, seed=len(name))
    a, b = solve_spatial(r, p, rv, L0=L0), solve_fast(r, p, rv, L0=L0)
    _same(a, b)
    assert (a["n_taut"] < r.m).sum() > 20  # slack cables at equilibrium
    c = solve_fast(r, p, rv, L0=L0, restarts=False)
    _same(solve_spatial(r, p, rv, L0=L0, restarts=False), c)


def test_the_compiled_solver_finds_the_same_several_equilibria():
    """wall_pulleys with rest lengths 1 % long: many slack cables and, at about half of the poses,
    several equilibria; the restarts run on the compiled Newton and select the same equilibrium,
    with the same alternatives."""
    r = load_robot(ROBOTS / "wall_pulleys.yaml")
    p, rv, L0 = _poses(r, BOXES["wall_pulleys.yaml"], N_POSES, seed=3)
    a, b = solve_spatial(r, p, rv, L0=L0 * 1.01), solve_fast(r, p, rv, L0=L0 * 1.01)
    _same(a, b)
    assert (~a["unique"]).sum() > 50
    for x, y in zip(a["alternatives"], b["alternatives"]):
        for u, v in zip(x, y):
            assert u["taut"] == v["taut"]
            assert np.abs(np.subtract(u["P_s"], v["P_s"])).max() < 1e-9
            assert np.abs(np.subtract(u["rotvec_s"], v["rotvec_s"])).max() < 1e-9
            assert abs(u["energy"] - v["energy"]) <= 1e-9 * max(1.0, abs(u["energy"]))


@pytest.mark.parametrize("kind", ["fixed", "SR", "DR"])
def test_point_mass_robots_give_the_compiled_point_mass_mode(cdpr4, cdpr3, kind):
    """b = 0, c = 0: the compiled 6-DoF kernel (3 x 3 step, rotation rows reduced) reproduces the
    compiled point-mass physical mode to 1e-9 m, with the same statuses and taut sets."""
    g = np.random.default_rng(5)
    P = np.column_stack([g.uniform(-2.4, 2.4, 300), g.uniform(-2.4, 2.4, 300), g.uniform(0.2, 4.8, 300)])
    P = np.vstack([P, [[0.0, 0.0, 9.0], [7.0, 7.0, 1.0]]])
    for robot in (cdpr4, cdpr3):
        r = with_pulleys(robot, kind=kind)
        L0 = L_TS(r, *pose_arrays(P)[:1], R=pose_arrays(P)[1]) * (1.0 + g.uniform(-1e-3, 3e-3, (len(P), r.m)))
        a, b = solve_physical_fast(r, P, L0=L0), solve_fast(r, P, L0=L0)
        assert np.abs(a["P_s"] - b["P_s"]).max() < 1e-9
        np.testing.assert_array_equal(a["status"], b["status"])
        np.testing.assert_array_equal(a["taut"], b["taut"])
        assert (b["dphi"] == 0).all() and (b["rotvec_s"] == 0).all()
        assert {"ok", "inaccessible"} <= set(b["status"])


@njit(cache=True)
def _cables(B, A, kind, h, rp, d, inward, frame, ident):
    """cable_axis and cable_derivatives at B (N, m, 3): L (N, m), u (N, m, 3), dL (N, m, 3),
    du (N, m, 3, 3), inside (N, m) and the 19 outputs of cable_axis (N, m, 19)."""
    n, m = B.shape[0], B.shape[1]
    L, ins = np.empty((n, m)), np.empty((n, m), dtype=np.bool_)
    u, dL, du = np.empty((n, m, 3)), np.empty((n, m, 3)), np.empty((n, m, 3, 3))
    raw = np.empty((n, m, 19))
    for i in range(n):
        for c in range(m):
            (L_, ux, uy, uz, lE, ins_, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb, gam) = cable_axis(
                B[i, c, 0], B[i, c, 1], B[i, c, 2], A[c, 0], A[c, 1], A[c, 2],
                kind[c], h[c], rp[c], d[c], inward[c, 0], inward[c, 1], ident[c], frame[c],
            )  # fmt: skip
            L[i, c], ins[i, c] = L_, ins_
            u[i, c, 0], u[i, c, 1], u[i, c, 2] = ux, uy, uz
            dv = cable_derivatives(ux, uy, uz, lE, sw, epx, epy, epz, arm, btx, bty, btz, ex, ey, ez, uCb)
            dL[i, c, 0], dL[i, c, 1], dL[i, c, 2] = dv[0], dv[1], dv[2]
            du[i, c, 0, 0], du[i, c, 0, 1], du[i, c, 0, 2] = dv[3], dv[4], dv[5]
            du[i, c, 1, 0], du[i, c, 1, 1], du[i, c, 1, 2] = dv[6], dv[7], dv[8]
            du[i, c, 2, 0], du[i, c, 2, 1], du[i, c, 2, 2] = dv[9], dv[10], dv[11]
            vals = (
                L_,
                ux,
                uy,
                uz,
                lE,
                1.0 if ins_ else 0.0,
                sw,
                epx,
                epy,
                epz,
                arm,
                btx,
                bty,
                btz,
                ex,
                ey,
                ez,
                uCb,
                gam,
            )
            for k in range(19):
                raw[i, c, k] = vals[k]
    return L, u, dL, du, ins, raw


@njit(cache=True)
def _point_mass_cables(B, A, kind, h, rp, d, inward):
    """The scalar kernel ``cable`` itself at B (N, m, 3): its 18 outputs (N, m, 18)."""
    n, m = B.shape[0], B.shape[1]
    out = np.empty((n, m, 18))
    for i in range(n):
        for c in range(m):
            (L, ux, uy, uz, lE, ins, sw, epx, epy, arm, btx, bty, btz, ex, ey, ez, uCb, gam) = cable(
                B[i, c, 0], B[i, c, 1], B[i, c, 2], A[c, 0], A[c, 1], A[c, 2],
                kind[c], h[c], rp[c], d[c], inward[c, 0], inward[c, 1],
            )  # fmt: skip
            vals = (
                L,
                ux,
                uy,
                uz,
                lE,
                1.0 if ins else 0.0,
                sw,
                epx,
                epy,
                arm,
                btx,
                bty,
                btz,
                ex,
                ey,
                ez,
                uCb,
                gam,
            )
            for k in range(18):
                out[i, c, k] = vals[k]
    return out


def _random_pulleys(seed, m=9):
    """m pulleys (3 of each kind) at random points with random axes (and random ``zero``), and 200
    random attachment points per cable within 3 m of them."""
    g = np.random.default_rng(seed)
    A = g.uniform(-3, 3, (m, 3))
    kind = np.array([0, 1, 2] * (m // 3), dtype=np.int64)
    h = np.where(kind == 0, 0.0, g.uniform(0.03, 0.12, m))
    rp = np.where(kind == 0, 0.0, g.uniform(0.02, 0.08, m))
    d = g.uniform(0.5, 3.0, m)
    axes = g.normal(size=(m, 3))
    frame = np.array([pulley_frame(k) for k in axes])
    ang = g.uniform(0, 2 * np.pi, m)
    inward = np.column_stack([np.cos(ang), np.sin(ang)])
    B = A + g.uniform(-3, 3, (200, m, 3))
    return B, A, kind, h, rp, d, inward, frame


def test_general_axis_cable_kernel_equals_the_numpy_pulley_model():
    B, A, kind, h, rp, d, inward, frame = _random_pulleys(11)
    ident = np.zeros(len(A), dtype=np.bool_)
    L, u, dL, du, ins, _ = _cables(B, A, kind, h, rp, d, inward, frame, ident)
    g = total_length_and_direction(B, A, kind, h, rp, d, inward, frame, per_cable=True)
    ok = ~g.inside
    assert ok.mean() > 0.9
    np.testing.assert_array_equal(ins, g.inside)
    np.testing.assert_allclose(L[ok], g.L_TE[ok], rtol=0, atol=1e-12)
    np.testing.assert_allclose(u[ok], g.u[ok], rtol=0, atol=1e-12)
    np.testing.assert_allclose(dL[ok], length_gradient(g)[ok], rtol=0, atol=1e-10)
    np.testing.assert_allclose(du[ok], direction_gradient(g)[ok], rtol=1e-9, atol=1e-9)


def test_general_axis_cable_derivatives_equal_finite_differences():
    B, A, kind, h, rp, d, inward, frame = _random_pulleys(12)
    B = B[:50]
    ident = np.zeros(len(A), dtype=np.bool_)
    L, u, dL, du, ins, _ = _cables(B, A, kind, h, rp, d, inward, frame, ident)
    eps = 1e-6
    for b in range(3):
        e = np.zeros(3)
        e[b] = eps
        Lp, up = _cables(B + e, A, kind, h, rp, d, inward, frame, ident)[:2]
        Lm, um = _cables(B - e, A, kind, h, rp, d, inward, frame, ident)[:2]
        ok = ~ins
        np.testing.assert_allclose(((Lp - Lm) / (2 * eps))[ok], dL[..., b][ok], atol=1e-6)
        np.testing.assert_allclose(((up - um) / (2 * eps))[ok], du[..., b][ok], atol=1e-5 * np.abs(du).max())


def test_identity_frame_is_bit_identical_to_the_point_mass_kernel(cdpr4):
    """For an identity frame the general-axis kernel runs the scalar kernel on B and A themselves:
    every output bit for bit (e_perp's z is 0)."""
    r = load_robot(ROBOTS / "cogiro_massless.yaml")
    for robot in (r, with_pulleys(cdpr4, kind="DR")):
        a = robot.arrays
        g = np.random.default_rng(3)
        B = a.A + g.uniform(-4, 4, (300, robot.m, 3))
        B[0, :, :2] = a.A[:, :2]  # on the axis: the fallback plane
        ident = np.ones(robot.m, dtype=np.bool_)
        args = (a.A, a.kind.astype(np.int64), a.h, a.r_p, a.d, a.inward)
        raw = _cables(B, *args, np.ascontiguousarray(a.frame), ident)[5]
        ref = _point_mass_cables(B, *args)
        np.testing.assert_array_equal(raw[..., [*range(9), *range(10, 19)]], ref)
        assert (raw[..., 9] == 0).all()
        # and the frame arithmetic with F = I agrees to round-off
        raw2 = _cables(B, *args, np.ascontiguousarray(a.frame), ~ident)[5]
        assert np.abs(raw2 - raw).max() < 1e-9


def test_lu_step_equals_the_pseudo_inverse_step_and_the_cholesky_test_eigvalsh():
    g = np.random.default_rng(4)
    A, V, x, y = np.empty((6, 6)), np.empty((6, 6)), np.empty(6), np.empty(6)
    piv = np.empty(6, dtype=np.int64)
    for k in range(200):
        J = g.normal(size=(6, 6)) * np.array([1e5, 1e5, 1e5, 1e4, 1e4, 1e4])
        if k % 4 == 0:  # rank deficient: the LU step declines, the SVD step is pinv's
            J[:, 5] = J[:, :5] @ g.normal(size=5)
        rhs = g.normal(size=6)
        ref = np.linalg.pinv(J, rcond=RCOND) @ rhs
        pinv_solve(J, rhs, A, V, y, RCOND)
        assert np.abs(y - ref).max() <= 1e-8 * np.abs(ref).max()
        if lu_solve(J, rhs, A, V, piv, x, RCOND):
            assert k % 4 != 0
            assert np.abs(x - ref).max() <= 1e-8 * np.abs(ref).max()
        H = -0.5 * (J + J.T) if k % 2 else J @ J.T
        assert positive_definite(-H, A) <= (np.linalg.eigvalsh(H)[0] > 0)
        if k % 2 == 0 and k % 4 != 0:
            assert positive_definite(-H, A)


@njit(cache=True)
def _rotvecs(R):
    out = np.empty((len(R), 3))
    for i in range(len(R)):
        rotvec_of_matrix(R[i], out[i])
    return out


def test_rotation_vector_of_a_matrix_equals_scipys():
    g = np.random.default_rng(6)
    rv = g.normal(size=(2000, 3))
    rv *= g.uniform(0, np.pi * (1 - 1e-6), (2000, 1)) / np.linalg.norm(rv, axis=1, keepdims=True)
    rv[:10] *= 1e-9  # the series near 0
    R = rotation_matrix(rv)
    assert np.abs(_rotvecs(R) - rotvec_of(R)).max() < 1e-12
    assert np.abs(_rotvecs(R) - rv).max() < 1e-9


def _equal_results(a, b):
    """Two ``solve_spatial`` results element for element (arrays equal, alternatives equal)."""
    assert set(a) == set(b)
    for key in a:
        if key == "alternatives":
            assert [[sorted(u) for u in x] for x in a[key]] == [[sorted(u) for u in x] for x in b[key]]
            for x, y in zip(a[key], b[key]):
                for u, v in zip(x, y):
                    for k in u:
                        np.testing.assert_array_equal(np.asarray(u[k]), np.asarray(v[k]))
        else:
            np.testing.assert_array_equal(np.asarray(a[key]), np.asarray(b[key]), err_msg=key)


@pytest.mark.parametrize("name, scale", [("cogiro_massless.yaml", 1.0), ("wall_pulleys.yaml", 1.01)])
def test_the_batched_solve_equals_one_solve_per_robot(name, scale, monkeypatch):
    """``solve_spatial_batch`` (the uncertainty samples' solver) of robots with perturbed anchors,
    dead lengths, moduli and mass gives each robot's ``solve_spatial`` exactly, restarts and several
    equilibria included (wall_pulleys, 1 % long), also when the robots are split into several passes."""
    r = load_robot(ROBOTS / name)
    p, rv, L0 = _poses(r, BOXES[name], 60, seed=7)
    theta0 = parameter_values(r)
    g = np.random.default_rng(11)
    robots = [
        robot_with_parameters(r, theta0 * (1.0 + 1e-3 * g.standard_normal(theta0.shape))) for _ in range(5)
    ]
    monkeypatch.setattr(compiled6, "BATCH_POSES", 2 * 60)  # three passes of two, two and one robot
    batch = compiled6.solve_batch(robots, p, rv, L0=L0 * scale)
    assert len(batch) == len(robots)
    for robot, res in zip(robots, batch):
        _equal_results(solve_fast(robot, p, rv, L0=L0 * scale), res)
    if scale > 1.0:
        assert sum((~res["unique"]).sum() for res in batch) > 20  # restarts found several equilibria
    ref = solve_batch(robots[:2], p[:20], rv[:20], engine="numpy", L0=L0[:20] * scale)
    for a, b in zip(ref, batch[:2]):
        _same(a, {k: v[:20] for k, v in b.items()})
