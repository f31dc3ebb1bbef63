"""The reached equilibrium (issue 39, ``cdpr.models.continuation`` through ``cdpr.solve.reach``):
the wall robot example of the issue, K vs 2K steps, a unique equilibrium reached = global, the
three starts."""

from pathlib import Path

import numpy as np
import pytest

from cdpr.errors import CdprError
from cdpr.models.interference import interference_free
from cdpr.models.platform import rotation_error
from cdpr.models.tension_distribution import compensated_lengths
from cdpr.robot import load_robot, with_values
from cdpr.solve import reach, solve

ROOT = Path(__file__).resolve().parents[2]
WALL = ROOT / "tests" / "data" / "wall_crossed.yaml"
#: The issue's example: rest lengths commanded at the desired pose p, rotvec.
L0 = np.array([6.52907908125, 6.14882031715, 5.85918529262, 6.26397544351, 6.06888687927, 5.63634727396, 5.23674973794, 5.70862689323])  # fmt: skip
P = np.array([[0.3, 0.3, 0.7]])
RV = np.array([0.12, 0.12, 0.0])


@pytest.fixture(scope="module")
def wall():
    return load_robot(WALL)


@pytest.fixture(scope="module")
def example(wall):
    return reach(wall, P, RV, L0=L0), solve(wall, P, RV, L0=L0, engine="numpy")


def test_wall_example_reached_is_not_the_global_one(wall, example):
    """The issue's numbers: the lowest energy flips the platform by 2.56 rad with interfering cables;
    the robot moved there continuously from the pose held with pretension stays at 0.13 rad, free."""
    a, g = example
    assert a["start"][0] == "compensated" and a["status"][0] == "ok" and a["n_folds"][0] == 0
    assert g["dphi"][0] == pytest.approx(2.56, abs=0.01)
    assert a["dphi"][0] == pytest.approx(0.13, abs=0.01)
    assert a["energy"][0] - g["energy"][0] == pytest.approx(21.0, abs=0.5)
    assert interference_free(wall, a["P_s"][0], a["rotvec_s"][0])
    assert not interference_free(wall, g["P_s"][0], g["rotvec_s"][0])
    # the reached equilibrium is one the restarts know too (an alternative of the global solve)
    alt = [np.linalg.norm(np.subtract(x["P_s"], a["P_s"][0])) for x in g["alternatives"][0]]
    assert min(alt) < 1e-8
    # the start: the desired pose, balanced under the compensated lengths, every cable taut
    assert np.allclose(a["P_start"], P, atol=1e-9) and np.allclose(a["rotvec_start"], RV, atol=1e-9)


def test_k_and_2k_steps_agree(wall, example):
    """Halving every accepted step changes nothing: the path on the adaptive λ grid (K steps) and
    on the grid with every step halved (2K) end at the same pose to 1e-9."""
    a, _ = example
    lam = np.array(a["lambdas"][0])
    assert len(lam) > 3 and lam[0] == 0.0 and lam[-1] == 1.0
    fine = np.sort(np.concatenate([lam, 0.5 * (lam[1:] + lam[:-1])]))
    k = reach(wall, P, RV, L0=L0, schedule=lam)
    k2 = reach(wall, P, RV, L0=L0, schedule=fine)
    for b in (k, k2):
        assert np.abs(b["P_s"] - a["P_s"]).max() < 1e-9
        assert np.abs(b["R_s"] - a["R_s"]).max() < 1e-9
        assert b["n_folds"][0] == 0
    # one step of the whole λ range jumps: the continuation is what keeps the platform on its branch
    one = reach(wall, P, RV, L0=L0, schedule=[0.0, 1.0])
    assert one["folds"][0] and one["folds"][0][0]["jump_m"] > 0.02


@pytest.mark.parametrize(
    "path, p, rv",
    [
        (WALL, [0.1, -0.1, 1.4], [0.05, 0.0, 0.02]),
        (ROOT / "config" / "robots" / "cogiro.yaml", [0.5, 0.3, 1.5], [0, 0, 0.1]),
    ],
)
def test_unique_equilibrium_reached_is_global(path, p, rv):
    """Where the restarts find one equilibrium, continuation reaches it."""
    robot = load_robot(path)
    g = solve(robot, np.array([p]), np.array(rv), engine="numpy")
    a = reach(robot, np.array([p]), np.array(rv))
    assert g["unique"][0] and g["status"][0] == "ok" == a["status"][0]
    assert np.abs(a["P_s"] - g["P_s"]).max() < 1e-9
    assert rotation_error(a["R_s"], g["R_s"])[0] < 1e-6
    assert a["energy"][0] == pytest.approx(g["energy"][0], abs=1e-9)


def test_given_start_equals_the_compensated_one(wall, example):
    """--from at the desired pose with its compensated lengths is the default start."""
    a, _ = example
    Ls = compensated_lengths(wall, P, RV, 100.0)["L0"][0]
    b = reach(wall, P, RV, L0=L0, start="given", from_p=P[0], from_rotvec=RV, from_lengths=Ls)
    assert b["start"][0] == "given"
    assert np.abs(b["P_s"] - a["P_s"]).max() < 1e-9


def test_search_start_where_no_distribution_exists(wall, example):
    """Tension bounds no distribution meets: the start is the restarts' equilibrium nearest to the
    desired pose (here the reached one, 0.13 rad, not the flipped lowest one)."""
    a, g = example
    b = reach(wall, P, RV, L0=L0, t_min=2900.0, t_max=3000.0)
    assert b["start"][0] == "search"
    assert np.abs(b["P_s"] - a["P_s"]).max() < 1e-8


def test_bad_starts(wall):
    with pytest.raises(CdprError, match="--from-lengths"):
        reach(wall, P, RV, L0=L0, start="given", from_p=P[0])
    with pytest.raises(CdprError, match="one rest length per cable"):
        reach(wall, P, RV, L0=L0, start="given", from_p=P[0], from_lengths=[5.0, 5.0])
    with pytest.raises(CdprError, match="allowed"):
        reach(wall, P, RV, L0=L0, start="lowest")


def test_reach_where_multiple_continues_only_points_with_several_equilibria(wall, example):
    """The studies' rule: continuation only where the restarts found more than one equilibrium."""
    from cdpr.solve import reach_where_multiple

    a, _ = example
    p = np.array([[0.3, 0.3, 0.7], [0.1, -0.1, 1.4]])
    rv = np.array([RV, [0.05, 0.0, 0.02]])
    L = np.array([L0, compensated_lengths(wall, p[1:], rv[1:], 100.0)["L0"][0]])
    g = solve(wall, p, rv, L0=L, engine="numpy")
    assert g["unique"].tolist() == [False, True]
    out = reach_where_multiple(wall, g)
    assert out["continued"].tolist() == [True, False]
    assert out["reached_is_global"].tolist() == [False, True] and out["n_folds"].tolist() == [0, 0]
    assert np.abs(out["P_s"][0] - a["P_s"][0]).max() < 1e-9
    assert np.array_equal(out["P_s"][1], g["P_s"][1]) and out["status"][1] == g["status"][1]
    assert np.abs(g["P_s"][0] - a["P_s"][0]).max() > 0.1  # the input is not modified


def test_a_fold_is_reported_and_the_point_stays_ok(wall):
    """A path of the wall robot across a fold (found among random commanded lengths): the tracked
    equilibrium ceases to exist near λ = 0.94 and the platform snaps by more than 0.02 m + rad; the
    fold is reported with λ, the jump and the taut sets, and the point's status stays ok."""
    p = np.array([[0.020155929528785976, 0.1478999746670242, 0.5790885638375065]])
    rv = np.array([-0.4387665183814998, -0.24645732048736985, 0.28936617471305015])
    L = np.array([6.333482321341457, 6.421385277887961, 5.929557081913589, 6.258898991375651, 5.618117964579822, 5.664101186167743, 5.529752668850362, 5.649836611489017])  # fmt: skip
    a = reach(wall, p, rv, L0=L)
    assert a["status"][0] == "ok" and a["n_folds"][0] == 1
    (fold,) = a["folds"][0]
    assert set(fold) == {"lambda", "jump_m", "jump_rad", "taut_before", "taut_after"}
    assert 0.9 < fold["lambda"] < 0.97 and fold["jump_m"] + fold["jump_rad"] > 0.02
    assert fold["jump_m"] == pytest.approx(0.147, abs=0.01) and fold["jump_rad"] == pytest.approx(
        1.02, abs=0.05
    )
    # the step that crossed it is the least one: the λ grid closes in on the fold
    lam = np.array(a["lambdas"][0])
    k = int(np.flatnonzero(np.isclose(lam, fold["lambda"], rtol=0, atol=1e-15))[0])
    assert lam[k] - lam[k - 1] <= 1e-7
    # the global solve knows the equilibrium the platform snapped to or a lower one
    g = solve(wall, p, rv, L0=L, engine="numpy")
    assert g["energy"][0] <= a["energy"][0] + 1e-9


def test_heavy_cables_are_continued_by_either_engine():
    """The compiled kernel continues heavy cables (every pulley, issue 38): the same reached
    equilibria, statuses and starts as the numpy reference, to 1e-9 m and rad."""
    robot = with_values(load_robot(ROOT / "config" / "robots" / "hang4_6dof.yaml"), linear_density=0.3)
    assert robot.heavy
    p = np.array([[0.2, -0.3, 1.5], [0.5, 0.5, 2.5]])
    ref = reach(robot, p, rotvec=[0.05, 0.0, 0.1], engine="numpy")
    got = reach(robot, p, rotvec=[0.05, 0.0, 0.1], engine="compiled")
    assert list(got["status"]) == list(ref["status"]) == ["ok", "ok"]
    assert list(got["start"]) == list(ref["start"])
    np.testing.assert_allclose(got["P_s"], ref["P_s"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(got["R_s"], ref["R_s"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(got["sag"], ref["sag"], rtol=1e-9, atol=1e-12)


def test_the_default_engine_is_the_compiled_one(wall, example):
    """reach's default engine is solve's (compiled for Newton): the default answer is the compiled
    engine's, and the numpy reference reaches the same equilibrium, status and start to 1e-9."""
    a, _ = example
    got = reach(wall, P, RV, L0=L0, engine="compiled")
    ref = reach(wall, P, RV, L0=L0, engine="numpy")
    assert np.array_equal(a["P_s"], got["P_s"]) and np.array_equal(a["R_s"], got["R_s"])
    assert list(ref["status"]) == list(a["status"]) and list(ref["start"]) == list(a["start"])
    assert ref["n_folds"].tolist() == a["n_folds"].tolist()
    np.testing.assert_allclose(ref["P_s"], a["P_s"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(ref["R_s"], a["R_s"], rtol=0, atol=1e-9)
