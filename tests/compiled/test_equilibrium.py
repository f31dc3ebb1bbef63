"""The compiled physical equilibrium (cdpr.compiled.equilibrium) equals the numpy reference
(cdpr.models.equilibrium) on a grid with slack cables, over-tension and inaccessible points, and its
answers are equilibria of the numpy pulley model (force balance, Hooke)."""

import numpy as np
import pytest

from cdpr.analyses.workspace import frame_box, grid_points
from cdpr.compiled.equilibrium import solve_points as solve_physical_fast
from cdpr.compiled.equilibrium import solve_points_batch as solve_physical_batch
from cdpr.errors import CdprError
from cdpr.models.cables import FTOL_REL
from cdpr.models.inverse import L_TS
from cdpr.models.pulleys import total_length_and_direction
from cdpr.parameters import parameter_values, robot_with_parameters
from cdpr.robot import load_robot, with_pulleys
from tests.conftest import ROBOTS
from tests.point_mass import solve_physical
from tests.point_mass import solve_physical_batch as solve_physical_batch_numpy

#: a platform heavy enough that the tensions exceed T_a = 5140 N over part of the frame
HEAVY_KG = 600.0


def _case(kind, seed=0):
    """CDPR4 with a heavy platform, a grid from the floor to above the pulleys and beyond the frame,
    and rest lengths L_TS + U(-2 cm, 30 cm): some cables slack at equilibrium."""
    r = with_pulleys(load_robot(ROBOTS / "cdpr4.yaml", mass=HEAVY_KG), kind=kind)
    x0, x1, y0, y1, _, z1 = frame_box(r)
    p = grid_points([x0 - 0.6, x1 + 0.6, y0 - 0.6, y1 + 0.6, -0.2, z1 + 0.8], 8)
    rng = np.random.default_rng(seed)
    L0 = L_TS(r, p) + rng.uniform(-0.02, 0.3, (len(p), r.m))
    return r, p, L0


@pytest.mark.parametrize("kind", ["SR", "DR", "fixed"])
def test_compiled_equals_numpy_reference_with_slack_and_over_tension(kind):
    r, p, L0 = _case(kind)
    a, b = solve_physical(r, p, L0=L0), solve_physical_fast(r, p, L0=L0)
    assert set(a) == set(b)
    assert {"ok", "over_tension", "inaccessible"} <= set(a["status"])
    np.testing.assert_array_equal(a["status"], b["status"])
    np.testing.assert_array_equal(a["converged"], b["converged"])
    unique = a["converged"] & (a["n_taut"] >= 2)  # a lone cable has a circle of equilibria
    assert (a["n_taut"][unique] < r.m).sum() > 50  # slack cables at equilibrium
    np.testing.assert_array_equal(a["taut"][unique], b["taut"][unique])
    assert np.abs(a["P_s"] - b["P_s"])[unique].max() < 1e-9
    rel = np.abs(a["t"] - b["t"]) / np.fmax(1.0, np.abs(a["t"]))
    assert rel[a["taut"] & unique[:, None]].max() < 1e-8


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_compiled_answers_are_equilibria_of_the_numpy_pulley_model(kind):
    """At every converged point: t_i = E S_i / L0_i max(L_TE,i(P*) - L0_i, 0) (Hooke) and
    sum_i t_i u_i(P*) + w_ext = 0 to the solver's force tolerance, with L_TE and u from
    ``pulleys.total_length_and_direction`` (numpy)."""
    r, p, L0 = _case(kind, seed=1)
    b = solve_physical_fast(r, p, L0=L0)
    conv = b["converged"] & np.isfinite(b["P_s"]).all(axis=1)
    assert conv.sum() > 200
    a = r.arrays
    g = total_length_and_direction(b["P_s"][conv], a.A, a.kind, a.h, a.r_p, a.d, a.inward)
    hooke = a.ES / L0[conv] * np.maximum(g.L_TE - L0[conv], 0.0)
    t = np.nan_to_num(b["t"][conv])
    np.testing.assert_allclose(t, hooke, rtol=1e-9, atol=1e-6)
    w = r.platform.w_ext
    F = np.einsum("ni,nij->nj", hooke, g.u) + w
    assert np.linalg.norm(F, axis=1).max() <= 1.01 * FTOL_REL * np.linalg.norm(w) + 1e-6


def _perturbed(r, n, seed=2):
    """n copies of r with every parameter (anchors, pulleys, dead lengths, moduli, mass) scaled by
    1 + U(-1 %, 1 %): the robots of a batch differ everywhere."""
    rng = np.random.default_rng(seed)
    th = parameter_values(r)
    return [robot_with_parameters(r, th * (1.0 + rng.uniform(-0.01, 0.01, th.shape))) for _ in range(n)]


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_batch_equals_one_solve_per_robot(kind):
    """Every (robot, point) pair of the batched kernel gives exactly the numbers of one
    solve_physical_fast per robot (same kernel, same inputs), several chunks of points per robot,
    and the numpy batch reference agrees with it as solve_physical does."""
    r, p, L0 = _case(kind, seed=3)
    robots = _perturbed(r, 5)
    batch = solve_physical_batch(robots, p, L0=L0, threads=2)
    ref = solve_physical_batch_numpy(robots[:2], p, L0=L0)
    assert len(batch) == len(robots) and len(p) >= 2 * 256  # two chunks per robot
    for k, rk in enumerate(robots):
        one = solve_physical_fast(rk, p, L0=L0)
        assert set(one) == set(batch[k])
        for key in one:
            np.testing.assert_array_equal(batch[k][key], one[key], err_msg=key)
    assert {"ok", "inaccessible"} <= set(batch[0]["status"])
    assert not np.array_equal(batch[0]["P_s"], batch[1]["P_s"], equal_nan=True)  # the robots differ
    for k in range(2):
        np.testing.assert_array_equal(ref[k]["status"], batch[k]["status"])
        unique = ref[k]["converged"] & (ref[k]["n_taut"] >= 2)
        assert np.abs(ref[k]["P_s"] - batch[k]["P_s"])[unique].max() < 1e-9


def test_batch_without_rest_lengths_commands_each_robots_L_TS():
    r, p, _ = _case("SR", seed=4)
    robots = _perturbed(r, 2)
    for rk, b in zip(robots, solve_physical_batch(robots, p)):
        np.testing.assert_array_equal(b["status"], solve_physical_fast(rk, p)["status"])
        np.testing.assert_array_equal(b["P_s"], solve_physical_fast(rk, p)["P_s"])


@pytest.mark.parametrize("kind", ["SR", "DR"])
def test_batch_from_given_starts_equals_one_solve_per_robot_from_them(kind):
    """Starting points per robot (P0 (K, N, 3)): each robot's rows are solve_physical_fast from its
    own P0[k], the numpy batch reference agrees as solve_physical does, and a start near the
    equilibrium reaches the same equilibrium as the start at p in fewer iterations."""
    r, p, L0 = _case(kind, seed=5)
    robots = _perturbed(r, 3)
    cold = solve_physical_batch(robots, p, L0=L0)
    # a start 0.1 mm from each robot's equilibrium where it converged, p elsewhere
    rng = np.random.default_rng(6)
    near = [np.where(c["converged"][:, None], c["P_s"], p) + rng.uniform(-1e-4, 1e-4, p.shape) for c in cold]
    P0 = np.stack(near)
    warm = solve_physical_batch(robots, p, L0=L0, P0=P0, threads=2)
    ref = solve_physical_batch_numpy(robots[:1], p, L0=L0, P0=P0[:1])
    for k, rk in enumerate(robots):
        one = solve_physical_fast(rk, p, L0=L0, P0=P0[k])
        for key in one:
            np.testing.assert_array_equal(warm[k][key], one[key], err_msg=key)
        unique = cold[k]["converged"] & (cold[k]["n_taut"] >= 3) & (cold[k]["status"] == "ok")
        assert unique.sum() > 100
        np.testing.assert_array_equal(warm[k]["status"][unique], cold[k]["status"][unique])
        assert np.abs(warm[k]["P_s"] - cold[k]["P_s"])[unique].max() < 1e-9
        assert warm[k]["iterations"][unique].sum() < 0.8 * cold[k]["iterations"][unique].sum()
    np.testing.assert_array_equal(ref[0]["status"], warm[0]["status"])
    both = ref[0]["converged"] & (ref[0]["n_taut"] >= 2)
    assert np.abs(ref[0]["P_s"] - warm[0]["P_s"])[both].max() < 1e-9
    # one start for every robot, and a start of the wrong shape
    same = solve_physical_batch(robots[:2], p, L0=L0, P0=P0[0])
    np.testing.assert_array_equal(same[1]["P_s"], solve_physical_fast(robots[1], p, L0=L0, P0=P0[0])["P_s"])
    with pytest.raises(CdprError, match=r"P0 has shape \(2, 3\); allowed"):
        solve_physical_batch(robots, p, L0=L0, P0=np.zeros((2, 3)))
