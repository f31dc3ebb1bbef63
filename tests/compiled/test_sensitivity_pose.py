"""The compiled 6-DoF sensitivities (cdpr.compiled.sensitivity) equal the numpy reference
(cdpr.models.sensitivity) on the spatial robots (CoGiRo, wall pulleys with horizontal axes, ...) at
random tilted poses with slack cables, and on point-mass robots; the engine registry chooses them.

Both take dF6/dθ exactly by the same formulas (the numpy one vectorised): dF6/dθ agrees to 1e-11 of
a column (measured 1.1e-12), dx*/dθ to ``ROUNDOFF`` (measured 6.3e-11: the Jacobian's conditioning
on the round-off). CDPR4 and CoGiRo with SR, DR and fixed pulleys: the engines agree, and both
equal central differences of the full solve of the perturbed robot. The flags, the tension margins
and the condition numbers agree to 1e-9."""

import numpy as np
import pytest
from numba import njit

from cdpr.compiled import sensitivity as fast
from cdpr.compiled._kernels import (
    C_DLD,
    C_DLDP,
    C_DLH,
    C_DLR,
    C_DUDP,
    C_DUH,
    C_DUR,
    C_L,
    C_U,
    NCOL,
    cable_partials_axis,
)
from cdpr.compiled._pose_sensitivity import wrench_partials
from cdpr.compiled.equilibrium import CompiledCables
from cdpr.compiled.equilibrium import solve as solve_fast
from cdpr.errors import CdprError
from cdpr.models import sensitivity as ref
from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays, rotvec_of
from cdpr.parameters import parameter_names, parameter_values, robot_with_parameters
from cdpr.robot import load_robot, with_pulleys
from cdpr.solve import sensitivities, sensitivities_at
from tests.compiled.test_equilibrium_pose import BOXES, _cables, _poses, _random_pulleys
from tests.conftest import ROBOTS

#: The engines' round-off bound, relative to a column of S (measured 6.3e-11).
ROUNDOFF = 1e-10
N = 60


def _errors(x, y, smooth, rigid):
    """max |x - y| per (pose, column) over the rows, relative to the column's max |y|, at the
    smooth poses; a column that is 0 in y must be 0 in x."""
    x, y = x[smooth], y[smooth]
    if not rigid:
        x, y = x[:, :3], y[:, :3]
    cm = np.abs(y).max(axis=1)
    zero = cm == 0
    assert (np.abs(x).max(axis=1)[zero] == 0).all()
    return np.where(zero, 0.0, np.abs(x - y).max(axis=1) / np.where(zero, 1.0, cm))


def _cases():
    out = {}
    for name in BOXES:  # cogiro, ipanema_like, wall_pulleys (horizontal axes), hang4_6dof
        r = load_robot(ROBOTS / name)
        p, rv, L0 = _poses(r, BOXES[name], N, seed=len(name))
        out[name] = (r, p, rv, L0)
    r = with_pulleys(load_robot(ROBOTS / "cdpr4.yaml"), kind="DR")
    g = np.random.default_rng(5)
    P = np.column_stack([g.uniform(-2.4, 2.4, N), g.uniform(-2.4, 2.4, N), g.uniform(0.2, 4.8, N)])
    L0 = L_TS(r, *pose_arrays(P)[:1], R=pose_arrays(P)[1]) * (1.0 + g.uniform(-1e-3, 3e-3, (N, r.m)))
    out["cdpr4 DR (point mass)"] = (r, P, None, L0)
    return out


CASES = _cases()


@pytest.mark.parametrize("name", list(CASES))
def test_compiled_equals_numpy_reference_at_the_same_equilibria(name):
    r, p, rv, L0 = CASES[name]
    res = solve_spatial(r, p, rv, L0=L0)
    a, b = ref.sensitivities_at(r, res), fast.sensitivities_at(r, res)
    assert a["names"] == b["names"] == parameter_names(r, rigid=True)
    ok = res["status"] == "ok"
    assert ok.sum() > N // 2 and ((res["n_taut"] < r.m) & ok).sum() > 10  # slack cables (taut subsets)
    np.testing.assert_array_equal(a["smooth"], b["smooth"])
    np.testing.assert_array_equal(np.isnan(a["S"]), np.isnan(b["S"]))
    assert np.isnan(b["S"][~ok]).all() and np.isfinite(b["S"][ok]).all()
    np.testing.assert_allclose(b["margin_t"], a["margin_t"], rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(b["cond"], a["cond"], rtol=1e-9)
    if r.point_mass:
        assert (b["S"][ok][:, 3:] == 0).all() and (a["S"][ok][:, 3:] == 0).all()
    sm = a["smooth"]
    assert sm.sum() > N // 2
    e = _errors(b["S"], a["S"], sm, not r.point_mass).max()
    assert e < ROUNDOFF, e


def _compiled_wrench_partials(r, P, R, L0):
    """The compiled ``wrench_partials`` at every pose: dF6/dθ (n, 6, 10 m + 4)."""
    cc = CompiledCables(r)
    rows, dF = np.empty((r.m, NCOL)), np.empty((6, 10 * r.m + 4))
    out = np.empty((len(P), 6, 10 * r.m + 4))
    f = np.ascontiguousarray
    for i in range(len(P)):
        wrench_partials(f(P), f(R), f(L0), i, cc.cables, cc.body, float(r.platform.mass), rows, dF)
        out[i] = dF
    return out


@pytest.mark.parametrize("name", list(CASES))
def test_the_wrench_partials_are_the_same_formulas(name):
    """dF6/dθ of the numpy reference = the compiled kernel's, column by column, to round-off (both
    exact; measured 1.1e-12 of a column's largest entry), zeros where the kernel has zeros."""
    r, p, rv, L0 = CASES[name]
    res = solve_spatial(r, p, rv, L0=L0)
    ok = res["status"] == "ok"
    P, R, L = res["P_s"][ok], res["R_s"][ok], np.asarray(res["L0"])[ok]
    a, t = ref._wrench_partials(ref._cables(r), P, R, L)
    b = _compiled_wrench_partials(r, P, R, L)
    scale = np.abs(b).max(axis=(0, 1))
    assert (scale > 0).sum() >= 7 * r.m  # every cable's E, h or r_p, d, A and b columns move the balance
    assert (np.abs(a - b).max(axis=(0, 1)) <= 1e-11 * scale).all()
    assert (t >= 0).all() and (t == 0).any()  # slack cables: their partials vanish
    slack = t == 0
    for c in range(r.m):
        cols = [c, r.m + c, 2 * r.m + c, 3 * r.m + c]
        assert (a[slack[:, c]][:, :, cols] == 0).all()


KINDS = ("SR", "DR", "fixed")


def _kind_case(robot_file, kind, n=20):
    """The robot with every pulley of ``kind`` (a DR arm twice the sheave radius where it was
    shorter), n equilibria (tilted on CoGiRo) under rest lengths around L_TS (slack cables,
    pretension): (robot, solve result)."""
    r = load_robot(ROBOTS / robot_file)
    h = max(r.arrays.h.max(), 2.0 * r.arrays.r_p.max()) if kind == "DR" else None
    r = with_pulleys(r, kind=kind, h=h)
    if r.point_mass:
        g = np.random.default_rng(7)
        p = np.column_stack([g.uniform(-2.0, 2.0, n), g.uniform(-2.0, 2.0, n), g.uniform(0.5, 4.5, n)])
        L0 = L_TS(r, p) * (1.0 + g.uniform(-1e-3, 3e-3, (n, r.m)))
        return r, solve_spatial(r, p, L0=L0)
    p, rv, L0 = _poses(r, BOXES[robot_file], n, seed=7)
    return r, solve_spatial(r, p, rv, L0=L0)


def _fd_of_the_solve(r, res, i, name):
    """Central difference of the full solve (the numpy reference's, restarts off) of the robot with
    parameter ``name`` moved (``robot_with_parameters``) at equilibrium i: (dp, dφ) per unit and
    the step."""
    every = parameter_names(r)
    k = every.index(name)
    theta = parameter_values(r)
    h = 1e-6 * theta[k] if name.startswith("E_") else 1e-4 if name == "M" else 1e-6
    out = []
    for s in (1.0, -1.0):
        v = theta.copy()
        v[k] += s * h
        q = solve_spatial(
            robot_with_parameters(r, v), res["P_s"][i : i + 1], rotvec_of(res["R_s"][i : i + 1]),
            L0=res["L0"][i : i + 1], restarts=False,
        )  # fmt: skip
        assert q["status"][0] == "ok"
        out.append((q["P_s"][0], q["R_s"][0]))
    return np.concatenate(
        [(out[0][0] - out[1][0]) / (2 * h), rotvec_of(out[0][1] @ out[1][1].T) / (2 * h)]
    ), h


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("robot_file", ["cdpr4.yaml", "cogiro_massless.yaml"])
def test_engines_agree_and_equal_finite_differences_of_the_solve(robot_file, kind):
    """A point mass (CDPR4) and a rigid platform (CoGiRo) with SR, DR and fixed pulleys: the numpy
    and compiled dp*/dθ, dφ*/dθ agree to ``ROUNDOFF`` at the same equilibria, and at three smooth
    ones equal central differences of the full solve of the perturbed robot (an independent check:
    the robot's data perturbed, not the evaluator): within 1e-6 of the largest entry plus the
    solved pose's round-off, 1e-13 m over the step (measured 4e-7 relative, the round-off)."""
    r, res = _kind_case(robot_file, kind)
    a, b = ref.sensitivities_at(r, res), fast.sensitivities_at(r, res)
    sm = a["smooth"]
    np.testing.assert_array_equal(sm, b["smooth"])
    assert sm.sum() >= 10
    assert _errors(b["S"], a["S"], sm, not r.point_mass).max() < ROUNDOFF
    names = ["E_1", "d_4", "A_1_x", "A_3_z", "M"]
    if kind != "fixed":
        names += ["h_2", "r_p_3"]
    if not r.point_mass:
        names += ["b_2_y", "b_5_z", "c_x", "c_z"]
    every = parameter_names(r, rigid=True)
    rows = 3 if r.point_mass else 6
    moved = 0
    for i in np.flatnonzero(sm)[:3]:
        for name in names:
            fd, h = _fd_of_the_solve(r, res, i, name)
            fd = fd[:rows]
            for S in (a["S"], b["S"]):
                x = S[i, :rows, every.index(name)]
                if not fd.any():  # a slack cable's own parameters do not move the platform
                    assert not x.any(), (name, x)
                    continue
                moved += 1
                assert np.abs(x - fd).max() <= 1e-6 * np.abs(fd).max() + 1e-13 / h, (name, x, fd)
    assert moved >= 2 * 3 * (len(names) - 2)


def test_names_subset_and_order():
    r, p, rv, L0 = CASES["cogiro_massless.yaml"]
    res = solve_fast(r, p[:10], rv[:10], L0=L0[:10])
    names = ["M", "b_3_y", "E_1", "c_z", "A_8_x"]
    full = fast.sensitivities_at(r, res)
    part = fast.sensitivities_at(r, res, names)
    idx = [parameter_names(r, rigid=True).index(nm) for nm in names]
    assert part["names"] == names
    np.testing.assert_array_equal(part["S"], full["S"][:, :, idx])
    with pytest.raises(CdprError, match="unknown 6-DoF parameter.*'r_p_9'.*allowed: parameter_names"):
        fast.sensitivities_at(r, res, ["E_1", "r_p_9"])


@pytest.mark.parametrize(
    "pose",
    [
        [0, 0, 2.0, 0, 0, 0],
        [1, 1, 1.5, 0, 0, 0],
        [0, 0, 2.0, np.radians(15), 0, 0],
        [-1.5, 0.8, 2.5, 0.1, -0.2, 0.15],
    ],
)
def test_spatial_sensitivities_compiled_equal_numpy_on_cogiro(pose):
    """End to end (each engine its own solve): same statuses and flags, S within the reference's
    round-off, poses within 1e-9."""
    r = load_robot(ROBOTS / "cogiro_massless.yaml")
    a = sensitivities(r, [pose], redundancy="physical", engine="numpy")
    b = sensitivities(r, [pose], redundancy="physical")  # the default: compiled
    np.testing.assert_array_equal(a["status"], b["status"])
    np.testing.assert_array_equal(a["smooth"], b["smooth"])
    assert a["smooth"].all()
    assert np.abs(a["P_s"] - b["P_s"]).max() < 1e-9
    assert _errors(b["S"], a["S"], a["smooth"], True).max() < ROUNDOFF


def test_compiled_equals_finite_differences_of_the_compiled_solve():
    """Physics: dx*/dθ of the kernel = central differences of the compiled solve of the perturbed
    robot (attachments, anchors, mass, centre of mass) on a tilted CoGiRo pose."""
    from tests.models.test_sensitivity_pose import changed

    r = load_robot(ROBOTS / "cogiro_massless.yaml")
    pose = [[0.3, -0.2, 2.0, 0.1, -0.05, 0.2]]
    res = fast.pose_sensitivities(r, pose, names=["b_1_x", "b_4_z", "A_2_y", "h_3", "c_z", "M"])
    assert res["smooth"][0]
    for k, name in enumerate(res["names"]):
        h = 1e-4 if name == "M" else 1e-6
        out = []
        for s in (1, -1):
            q = solve_fast(
                changed(r, name, s * h), res["P_s"], rotvec_of(res["R_s"]), L0=res["L0"], restarts=False
            )
            out.append((q["P_s"][0], q["R_s"][0]))
        fd = np.concatenate([(out[0][0] - out[1][0]) / (2 * h), rotvec_of(out[0][1] @ out[1][1].T) / (2 * h)])
        assert np.abs(res["S"][0, :, k] - fd).max() <= 1e-4 * np.abs(fd).max() + 1e-12, name


def test_engine_registry():
    r = load_robot(ROBOTS / "cogiro_massless.yaml")
    res = solve_fast(r, [[0, 0, 2.0]])
    a = sensitivities_at(r, res, ["E_1", "M"])
    b = fast.sensitivities_at(r, res, ["E_1", "M"])
    np.testing.assert_array_equal(a["S"], b["S"])  # compiled by default
    c = sensitivities_at(r, res, ["E_1", "M"], engine="numpy")
    np.testing.assert_array_equal(c["S"], ref.sensitivities_at(r, res, ["E_1", "M"])["S"])
    for call in (
        lambda: sensitivities_at(r, res, engine="numba"),
        lambda: sensitivities(r, [[0, 0, 2.0]], redundancy="physical", engine="numba"),
    ):
        with pytest.raises(CdprError, match="unknown engine 'numba'; allowed: compiled, numpy"):
            call()


@njit(cache=True)
def _rows(B, A, kind, h, rp, d, inward, frame, ident):
    """cable_partials_axis at B (N, m, 3): rows (N, m, NCOL)."""
    n, m = B.shape[0], B.shape[1]
    out = np.empty((n, m, NCOL))
    for i in range(n):
        for c in range(m):
            cable_partials_axis(
                B[i, c, 0], B[i, c, 1], B[i, c, 2], A[c, 0], A[c, 1], A[c, 2],
                kind[c], h[c], rp[c], d[c], inward[c, 0], inward[c, 1], ident[c], frame[c], out[i, c],
            )  # fmt: skip
    return out


def test_general_axis_cable_partials_equal_the_kernel_and_finite_differences():
    """``_kernels.cable_partials_axis`` with random pulley axes: L, u, dL/dB, du/dB those of
    ``cable_axis`` + ``cable_derivatives``; dL/dh, du/dh, dL/dr_p, du/dr_p, dL/dd central differences
    of the kernel in h, r_p, d."""
    B, A, kind, h, rp, d, inward, frame = _random_pulleys(21)
    B = B[:60]
    ident = np.zeros(len(A), dtype=np.bool_)
    rows = _rows(B, A, kind, h, rp, d, inward, frame, ident)
    L, u, dL, du, ins, _ = _cables(B, A, kind, h, rp, d, inward, frame, ident)
    ok = ~ins
    assert ok.mean() > 0.9
    np.testing.assert_allclose(rows[..., C_L][ok], L[ok], rtol=0, atol=1e-12)
    np.testing.assert_allclose(rows[..., C_U : C_U + 3][ok], u[ok], rtol=0, atol=1e-12)
    np.testing.assert_allclose(rows[..., C_DLDP : C_DLDP + 3][ok], dL[ok], rtol=0, atol=1e-10)
    np.testing.assert_allclose(rows[..., C_DUDP : C_DUDP + 9][ok], du[ok].reshape(-1, 9), rtol=0, atol=1e-9)
    eps = 1e-7
    for key, cl, cu in (("h", C_DLH, C_DUH), ("rp", C_DLR, C_DUR), ("d", C_DLD, None)):
        pulley = kind > 0 if key != "d" else np.ones(len(A), dtype=bool)
        vals = {"h": h, "rp": rp, "d": d}
        out = []
        for s in (1.0, -1.0):
            v = dict(vals)
            v[key] = vals[key] + s * eps * pulley
            out.append(_cables(B, A, kind, v["h"], v["rp"], v["d"], inward, frame, ident)[:2])
        fdL = (out[0][0] - out[1][0]) / (2 * eps)
        good = ok & pulley[None, :]
        np.testing.assert_allclose(rows[..., cl][good], fdL[good], rtol=0, atol=1e-6)
        if cu is not None:
            fdu = (out[0][1] - out[1][1]) / (2 * eps)
            scale = np.abs(fdu[good]).max()
            np.testing.assert_allclose(rows[..., cu : cu + 3][good], fdu[good], rtol=0, atol=1e-5 * scale)
