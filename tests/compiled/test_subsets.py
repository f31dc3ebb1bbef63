"""The compiled engine (cdpr.compiled.subsets) gives the same table as the numpy reference implementation,
and its subset pruning changes nothing."""

import numpy as np
import pandas as pd
import pytest

from cdpr.analyses.workspace import grid_points
from cdpr.compiled.subsets import solve_points_batch, solve_points_fast
from cdpr.errors import CdprError
from cdpr.models.direct import degm_e
from cdpr.models.inverse import L_TS
from cdpr.models.subsets import solve_points
from cdpr.parameters import parameter_values, robot_with_parameters
from cdpr.robot import with_pulleys
from cdpr.tables import solve_table

# a box larger than the frames: includes slack, over-tension and inaccessible points
BOX = [-2.7, 2.7, -2.7, 2.7, -0.2, 5.3]


@pytest.mark.parametrize("name", ["cdpr3", "cdpr4"])
@pytest.mark.parametrize("kind", ["SR", "DR", "fixed"])
def test_compiled_equals_numpy_reference(request, name, kind):
    r = with_pulleys(request.getfixturevalue(name), kind=kind)
    P = grid_points(BOX, 14)
    a, b = solve_points(r, P), solve_points_fast(r, P)
    assert set(a["status"]) >= {"ok", "slack"}
    assert (a["status"] == b["status"]).all()
    assert (a["subset"] == b["subset"]).all()
    assert (a["iterations"] == b["iterations"]).all()
    assert np.array_equal(np.isnan(a["dp"]), np.isnan(b["dp"]))
    np.testing.assert_allclose(b["dp"], a["dp"], rtol=0, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(b["P_s"], a["P_s"], rtol=0, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(b["t"], a["t"], rtol=1e-9, atol=1e-6, equal_nan=True)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_iteration_cap_equals_numpy_reference(cdpr4, kind):
    """With an iteration cap that some points need more than, both engines flag the same points
    not_converged and agree on the others."""
    r = with_pulleys(cdpr4, kind=kind)
    P = grid_points([-2.0, 2.0, -2.0, 2.0, 0.5, 4.0], 8)
    a, b = solve_points(r, P, maxiter=3), solve_points_fast(r, P, maxiter=3)
    assert (a["status"] == "not_converged").any() and (a["status"] == "ok").any()
    assert (a["status"] == b["status"]).all() and (a["iterations"] == b["iterations"]).all()
    assert (a["subset"] == b["subset"]).all()
    np.testing.assert_allclose(b["t"], a["t"], rtol=1e-9, atol=1e-6, equal_nan=True)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_pruning_changes_nothing(cdpr4, kind):
    r = with_pulleys(cdpr4, kind=kind)
    P = grid_points(BOX, 18)
    full, pruned = solve_points_fast(r, P, prune=False), solve_points_fast(r, P)
    for key in ("P_s", "dp", "t", "subset", "iterations", "status"):
        assert np.array_equal(full[key], pruned[key], equal_nan=key in ("P_s", "dp", "t")), key
    assert (full["subset_solves"] == 4).all()
    assert pruned["subset_solves"].mean() < 3.2  # pruning does remove work


def test_thread_count_does_not_change_results(cdpr4):
    P = grid_points(BOX, 10)
    a = solve_table(cdpr4, P, threads=1)
    b = solve_table(cdpr4, P, threads=2)
    pd.testing.assert_frame_equal(a, b)
    c = solve_table(cdpr4, P, engine="numpy")
    assert (a.status == c.status).all() and (a.subset == c.subset).all()
    np.testing.assert_allclose(a.dp, c.dp, atol=1e-9)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_batch_equals_one_solve_per_robot(cdpr4, kind):
    """Every (robot, point) pair of the batched paper-mode kernel gives exactly the numbers of one
    solve_points_fast per robot at the same commanded lengths (same kernel, same inputs), with
    robots that differ in every parameter and several chunks of points per robot."""
    r = with_pulleys(cdpr4, kind=kind)
    P = grid_points(BOX, 10)
    L = L_TS(r, P)
    rng = np.random.default_rng(5)
    th = parameter_values(r)
    robots = [robot_with_parameters(r, th * (1.0 + rng.uniform(-0.01, 0.01, th.shape))) for _ in range(4)]
    batch = solve_points_batch(robots, P, L, threads=2)
    assert len(P) > 2 * 256
    for k, rk in enumerate(robots):
        one = solve_points_fast(rk, P, L=L)
        assert set(one) == set(batch[k])
        for key in one:
            np.testing.assert_array_equal(batch[k][key], one[key], err_msg=key)
    assert set(batch[0]["status"]) >= {"ok", "slack"}
    assert not np.array_equal(batch[0]["dp"], batch[1]["dp"], equal_nan=True)


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_batch_from_given_starts_finds_the_same_solutions(cdpr4, kind):
    """Starts per robot, point and subset (P0 (K, N, ns, 3)) near each subset's solution: the
    same statuses, subsets and P* (to 1e-9 m) as the start at p in fewer iterations, and the numpy
    reference from the same starts agrees; a start of the wrong shape is one CdprError."""
    r = with_pulleys(cdpr4, kind=kind)
    P = grid_points(BOX, 10)
    L = L_TS(r, P)
    rng = np.random.default_rng(8)
    th = parameter_values(r)
    robots = [robot_with_parameters(r, th * (1.0 + rng.uniform(-0.01, 0.01, th.shape))) for _ in range(3)]
    ns = len(r.subsets)
    # every subset's own solution (the numpy reference solves them all) moved by up to 0.1 mm
    ref = [solve_points(rk, P, L=L) for rk in robots]
    P0 = np.empty((len(robots), len(P), ns, 3))
    for k, rk in enumerate(robots):
        for c, sub in enumerate(rk.subsets):
            d = degm_e(rk, P, subset=sub, L=L[:, sub])
            P0[k, :, c] = np.where(d.converged[:, None], d.P, P) + rng.uniform(-1e-4, 1e-4, P.shape)
    cold = solve_points_batch(robots, P, L, threads=2)
    warm = solve_points_batch(robots, P, L, threads=2, P0=P0)
    for k in range(len(robots)):
        ok = cold[k]["status"] == "ok"
        assert ok.sum() > 100
        np.testing.assert_array_equal(warm[k]["status"], cold[k]["status"])
        np.testing.assert_array_equal(warm[k]["subset"][ok], cold[k]["subset"][ok])
        assert np.abs(warm[k]["P_s"] - cold[k]["P_s"])[ok].max() < 1e-9
        assert warm[k]["iterations"][ok].sum() < 0.8 * cold[k]["iterations"][ok].sum()
    numpy_warm = solve_points(robots[0], P, L=L, P0=P0[0])
    np.testing.assert_array_equal(numpy_warm["status"], warm[0]["status"])
    ok = warm[0]["status"] == "ok"
    assert np.abs(numpy_warm["P_s"] - warm[0]["P_s"])[ok].max() < 1e-9
    assert np.abs(numpy_warm["P_s"] - ref[0]["P_s"])[ok].max() < 1e-9
    with pytest.raises(CdprError, match=r"P0 has shape \(3, 1000, 3\); allowed"):
        solve_points_batch(robots, P, L, P0=np.zeros((3, len(P), 3)))
    with pytest.raises(CdprError, match=r"P0 has shape \(1000, 3\); allowed"):
        solve_points(robots[0], P, L=L, P0=np.zeros((len(P), 3)))


def test_batch_rejects_robots_with_different_cables(cdpr3, cdpr4):
    P = grid_points(BOX, 3)
    with pytest.raises(ValueError, match="same cables"):
        solve_points_batch([cdpr4, cdpr3], P, L_TS(cdpr4, P))
