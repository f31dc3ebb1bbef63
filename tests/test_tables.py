"""Tables of solved points (cdpr.tables): the same leading columns in both modes, the labels and the
sensitivity columns, the orientation columns of a rigid platform and of a point mass given one, and
solve_table's chunks (any chunk size, no point, the same table)."""

import numpy as np
import pandas as pd
import pytest

from cdpr import solve, tables
from cdpr.errors import CdprError
from cdpr.robot import load_robot, with_pulleys
from tests.conftest import ROBOTS

PTS = np.array([[0.7, -1.3, 0.4], [-1.6, 0.5, 1.9], [1.1, 1.9, 3.1], [0.0, 0.0, 4.95]])
LEAD = ["x", "y", "z", "x_s", "y_s", "z_s", "dp", "t1", "t2", "t3", "t4"]
ORIENTATION = ["rx", "ry", "rz", "rx_s", "ry_s", "rz_s", "dphi"]


@pytest.fixture(scope="module")
def robot(cdpr4):
    return with_pulleys(cdpr4, kind="SR", h=0.1077, r_p=0.035)


def test_one_to_frame_for_both_modes_and_the_sensitivities(robot):
    """The same leading columns in both modes; paper mode labels the subset, physical mode the taut
    cables; the sensitivity columns follow when the result has them and equal S. (The numpy engine:
    the table does not depend on it, tests/test_solve.py; no kernel to compile here.)"""
    lead = ["x", "y", "z", "x_s", "y_s", "z_s", "dp", "t1", "t2", "t3", "t4"]
    paper = tables.to_frame(robot, solve.solve(robot, PTS, engine="numpy"))
    assert list(paper.columns) == [*lead, "subset", "n_taut", "iterations", "status"]
    res = solve.solve(robot, PTS, engine="numpy", redundancy="physical")
    phys = tables.to_frame(robot, res, "physical")
    assert list(phys.columns) == [*lead, "taut", "n_taut", "iterations", "status"]
    assert list(phys["status"].astype(str)) == list(res["status"])
    assert set(paper["subset"].astype(str)[paper["status"] == "ok"]) <= {"1-2-3", "1-2-4", "1-3-4", "2-3-4"}
    sens = solve.sensitivities(robot, PTS, engine="numpy")
    df = tables.to_frame(robot, sens)
    names = sens["names"]
    assert list(df.columns[: len(paper.columns)]) == list(paper.columns)
    assert list(df.columns[len(paper.columns) :]) == [f"d{a}_d{n}" for n in names for a in "xyz"] + ["smooth"]
    k = names.index("M")
    np.testing.assert_array_equal(df["dz_dM"].to_numpy(), sens["S"][:, 2, k])
    with pytest.raises(CdprError, match="allowed: paper, physical"):
        tables.to_frame(robot, res, "both")


def test_the_columns_hold_the_solver_s_numbers(robot):
    res = solve.solve(robot, PTS, engine="numpy")
    df = tables.to_frame(robot, res)
    np.testing.assert_array_equal(df[["x_s", "y_s", "z_s"]].to_numpy(), res["P_s"])
    np.testing.assert_array_equal(df[[f"t{i}" for i in range(1, 5)]].to_numpy(), res["t"])
    assert list(df["status"].astype(str)) == list(res["status"]) and list(df["iterations"]) == list(
        res["iterations"]
    )
    assert list(df["status"].cat.categories) == list(tables.STATUSES)
    # a result that names its own statuses (compensation's) gets those categories
    own = dict(
        res, statuses=("ok", "no_distribution", "slack", "over_tension", "inaccessible", "not_converged")
    )
    own.pop("status_code", None)
    assert list(tables.to_frame(robot, own)["status"].cat.categories)[1] == "no_distribution"


def test_a_point_mass_given_an_orientation_carries_it_through(robot):
    rv = np.array([0.1, -0.2, 0.3])
    res = solve.solve(robot, PTS, engine="numpy")
    df = tables.to_frame(robot, res, rotvec=rv)
    assert list(df.columns) == [
        *LEAD[:7],
        *ORIENTATION,
        *LEAD[7:],
        "subset",
        "n_taut",
        "iterations",
        "status",
    ]
    np.testing.assert_array_equal(df[["rx", "ry", "rz"]].to_numpy(), np.tile(rv, (4, 1)))
    np.testing.assert_array_equal(df[["rx_s", "ry_s", "rz_s"]].to_numpy(), np.tile(rv, (4, 1)))
    assert (df["dphi"] == 0).all()
    pd.testing.assert_frame_equal(df.drop(columns=ORIENTATION), tables.to_frame(robot, res))


def test_a_rigid_platform_s_table_has_its_orientation_columns():
    cogiro = load_robot(ROBOTS / "cogiro_massless.yaml")
    P, rv = np.array([[0.5, -0.3, 2.0], [0.0, 0.0, 2.5]]), np.array([0.05, 0.0, 0.1])
    res = solve.solve(cogiro, P, engine="numpy", redundancy="physical", rotvec=rv)
    df = tables.to_frame(cogiro, res, "physical")
    t = [f"t{i}" for i in range(1, cogiro.m + 1)]
    assert list(df.columns) == [
        *LEAD[:7],
        *ORIENTATION,
        *t,
        "taut",
        "n_taut",
        "iterations",
        "status",
        "unique",
    ]
    pd.testing.assert_frame_equal(df, tables.to_frame(cogiro, res, "physical"))
    np.testing.assert_array_equal(df[["rx_s", "ry_s", "rz_s"]].to_numpy(), res["rotvec_s"])
    np.testing.assert_array_equal(df["dphi"].to_numpy(), res["dphi"])
    assert (df["status"] == "ok").all() and (df["dphi"] > 0).all()
    pd.testing.assert_frame_equal(
        tables.solve_table(cogiro, P, engine="numpy", redundancy="physical", rotvec=rv), df
    )


def test_solve_table_gives_the_same_table_whatever_the_chunk(robot):
    P = np.vstack([PTS, PTS[:3] * [0.5, 0.5, 1.0]])
    whole = tables.solve_table(robot, P, engine="numpy")
    for chunk in (1, 3, 100):
        pd.testing.assert_frame_equal(tables.solve_table(robot, P, engine="numpy", chunk=chunk), whole)
    one = tables.solve_table(robot, P[2], engine="numpy")  # one point: one row
    pd.testing.assert_frame_equal(one, whole.iloc[[2]].reset_index(drop=True))


def test_solve_table_of_no_point_has_the_columns_and_no_row(robot):
    empty = tables.solve_table(robot, np.empty((0, 3)), engine="numpy")
    assert len(empty) == 0 and list(empty.columns) == [*LEAD, "subset", "n_taut", "iterations", "status"]


def test_solve_table_refuses_an_engine_pair_that_does_not_exist(robot):
    with pytest.raises(CdprError, match="allowed"):
        tables.solve_table(robot, PTS, method="fixed_point", engine="compiled")


def test_a_heavy_rigid_platform_s_table_counts_the_cables_that_hold():
    """Heavy CoGiRo at two plane-edge points where the massless robot leaves cables slack: every
    heavy cable pulls (n_taut 8), n_holding leaves out those hanging at about their own weight, and
    the summary's plane note counts both points as hanging on fewer than 6 holding cables."""
    from cdpr.pipeline.summary import hold_note

    robot = load_robot(ROBOTS / "cogiro.yaml")
    P = np.array([[-2.466, -5.5342, 2.0], [1.903225, 5.4753, 2.0], [0.0, 0.0, 2.0]])
    df = tables.solve_table(robot, P, redundancy="physical", rotvec=np.zeros(3))
    assert (df["n_taut"] == 8).all()
    assert (df["n_holding"].iloc[:2] < 6).all() and df["n_holding"].iloc[2] == 8
    assert "2 of the ok points hang on fewer than 6 holding cables" in hold_note(df, 6)
    massless = tables.solve_table(
        load_robot(ROBOTS / "cogiro_massless.yaml"), P, redundancy="physical", rotvec=np.zeros(3)
    )
    assert "n_holding" not in massless and "2 of the ok points hang on fewer than 6 cables" in hold_note(
        massless, 6
    )
