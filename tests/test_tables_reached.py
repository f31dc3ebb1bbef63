"""``solve_table``'s physical mode answers with the reached equilibrium where the restarts find
more than one (issue 39, ``solve.reach_where_multiple``) and is unchanged where every equilibrium
is unique (the studies' rule: byte-identical tables there)."""

from pathlib import Path

import numpy as np
import pandas as pd

from cdpr.robot import load_robot
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
