"""``solve_table``'s physical mode answers with the reached equilibrium where the restarts find
more than one (issue 39, ``solve.reach_where_multiple``) and is unchanged where every equilibrium
is unique (the studies' rule: byte-identical tables there); so do the global index's grids, the
error budget and the uncertainty study (``solve.reached_answer``)."""

from pathlib import Path

import numpy as np
import pandas as pd

from cdpr.analyses import budget, uncertainty
from cdpr.analyses.symmetry import solve_grid_columns
from cdpr.parameters import parameter_values
from cdpr.robot import load_robot
from cdpr.solve import reached_answer, solve
from cdpr.tables import solve_table

ROOT = Path(__file__).resolve().parents[1]
L0 = [6.52907908125, 6.14882031715, 5.85918529262, 6.26397544351, 6.06888687927, 5.63634727396, 5.23674973794, 5.70862689323]  # fmt: skip


def test_the_wall_example_is_continued_in_a_table():
    robot = load_robot(ROOT / "tests" / "data" / "wall_crossed.yaml")
    p = np.array([[0.3, 0.3, 0.7, 0.12, 0.12, 0.0]] * 2)
    p[1, :3] = [0.31, 0.3, 0.7]
    for engine in ("numpy", "compiled"):
        reached = solve_table(robot, p, L0=np.array([L0, L0]), engine=engine)
        glob = solve_table(robot, p, L0=np.array([L0, L0]), engine=engine, equilibrium="global")
        assert glob["unique"].tolist() == [False, True] and "n_folds" not in glob
        assert reached["n_folds"].tolist() == [0, 0] and reached["reached_is_global"].tolist() == [
            False,
            True,
        ]
        assert reached["dphi"][0] < 0.2 and glob["dphi"][0] > 2.5
        # the unique point is the global solve's row, unchanged
        pd.testing.assert_frame_equal(reached.iloc[1:][glob.columns], glob.iloc[1:])
        assert (reached["status"] == "ok").all()


def test_unique_equilibria_give_the_same_table():
    robot = load_robot(ROOT / "config" / "robots" / "cogiro.yaml")
    p = np.array([[0.5, 0.3, 1.5, 0, 0, 0.1], [0.0, 0.0, 1.2, 0, 0, 0], [1.0, -0.5, 2.0, 0.05, 0, 0]])
    a = solve_table(robot, p)
    assert a["unique"].all() and "n_folds" not in a
    pd.testing.assert_frame_equal(a, solve_table(robot, p, equilibrium="global"))


# the studies' doors (issue 39, "the studies use the reached equilibrium"): at the issue's wall pose
# commanded with L_TS, the restarts find the flipped platform (delta phi 2.55 rad) beside the one
# the robot reaches (0.13 rad); every study solve answers with the reached one
WALL = ROOT / "tests" / "data" / "wall_crossed.yaml"
P_WALL, RV_WALL = [0.3, 0.3, 0.7], [0.12, 0.12, 0.0]


def test_reached_answer_continues_only_where_not_unique():
    robot = load_robot(WALL)
    glob = solve(robot, [P_WALL, [0.31, 0.3, 0.7]], [RV_WALL, RV_WALL])
    assert glob["unique"].tolist() == [False, True] and glob["dphi"][0] > 2.5
    got = reached_answer(robot, glob)
    assert got["dphi"][0] < 0.2 and got["continued"].tolist() == [True, False]
    assert got["dphi"][1] == glob["dphi"][1]
    assert reached_answer(robot, glob, equilibrium="global") is glob
    unique = solve(robot, [[0.31, 0.3, 0.7]], [RV_WALL])
    assert reached_answer(robot, unique) is unique  # unchanged, no new keys


def test_the_global_index_grid_answers_with_the_reached_equilibrium():
    robot = load_robot(WALL)
    box = [0.29, 0.31, 0.29, 0.31, 0.69, 0.71]  # n = 1: the one cell centre is the wall pose
    out, solved = solve_grid_columns(robot, box, 1, ["dphi", "status"], rotvec=RV_WALL, redundancy="physical")
    table = solve_table(robot, np.array([[*P_WALL, *RV_WALL]]))
    assert solved == 1 and out["dphi"][0] < 0.2
    np.testing.assert_allclose(out["dphi"], table["dphi"], rtol=0, atol=1e-12)


def test_the_budget_and_the_uncertainty_model_answer_with_the_reached_equilibrium():
    robot = load_robot(WALL)
    rv = np.array([RV_WALL])
    b = budget.variant(robot, [P_WALL], ["pulley", "elasticity"], [], rotvec=rv)
    assert np.linalg.norm(b["dphi"][0]) < 0.2  # uncompensated: L_TS at the pose, as above
    model = uncertainty.PoseErrorModel(robot, np.array([P_WALL]), "uncompensated", "physical", rotvec=rv)
    values, ok = model.solve(parameter_values(robot))
    assert ok.all() and values["dphi"][0, 0] < 0.2
