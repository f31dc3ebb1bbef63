"""What a solved point is (cdpr.models.results): the floor rule of a suspended robot, the subset and
taut-cable labels (codes into categories, checked against labels written out by hand and against a
per-point loop), and the leading columns of every point table."""

import itertools

import numpy as np
import pytest

from cdpr.models import results
from cdpr.models.results import STATUSES


def test_points_below_the_floor_become_inaccessible_and_nothing_else_changes():
    p = np.array([[0.0, 0.0, 1.0], [0.1, 0.0, -1e-9], [0.0, 0.2, 0.0], [0.0, 0.0, -3.0]])
    status = np.array(["ok", "ok", "slack", "over_tension"])
    codes = np.array([STATUSES.index(s) for s in status], dtype=np.int8)
    res = {"status": status.copy(), "status_code": codes.copy(), "dp": np.arange(4.0)}
    out = results.mark_below_floor(res, p)
    assert out is res
    assert list(res["status"]) == ["ok", "inaccessible", "slack", "inaccessible"]  # z = 0 is on the floor
    assert [STATUSES[c] for c in res["status_code"]] == list(res["status"])
    assert res["status_code"].dtype == np.int8 and list(res["dp"]) == [0.0, 1.0, 2.0, 3.0]
    # no point below: the result is left as it was (no status_code needed)
    above = {"status": ["ok", "slack"]}
    assert results.mark_below_floor(above, [[0, 0, 1], [0, 0, 2]])["status"] == ["ok", "slack"]


def test_subset_labels_are_one_based_cable_numbers():
    assert results.subset_label([0, 1, 3]) == "1-2-4"
    assert results.subset_label(np.array([5, 6, 7])) == "6-7-8"
    assert results.subset_label([-1, -1, -1]) == ""


class _Robot:
    """What ``subset_codes`` reads of a robot: m and the lexicographic 3-cable subsets."""

    def __init__(self, m):
        self.m = m
        self.subsets = np.array(list(itertools.combinations(range(m), 3)))


@pytest.mark.parametrize("m", [3, 4, 8])
def test_subset_codes_equal_a_per_point_lookup(m):
    robot = _Robot(m)
    rng = np.random.default_rng(m)
    rows = robot.subsets[rng.integers(0, len(robot.subsets), 200)].copy()
    rows[::7] = -1  # no subset
    codes, labels = results.subset_codes(robot, rows)
    assert labels[-1] == "" and len(labels) == len(robot.subsets) + 1 and len(set(labels)) == len(labels)
    assert [labels[c] for c in codes] == [results.subset_label(r) for r in rows]


def test_a_subset_the_robot_does_not_list_has_no_label(cdpr4):
    codes, labels = results.subset_codes(cdpr4, [[0, 1, 2], [2, 1, 0], [0, 1, 9], [1, 2, 3]])
    assert [labels[c] for c in codes] == ["1-2-3", "", "", "2-3-4"]
    assert labels == ["1-2-3", "1-2-4", "1-3-4", "2-3-4", ""]


def test_taut_labels_follow_the_bit_pattern():
    taut = np.array(
        [[True, True, True, True], [False] * 4, [True, False, True, True], [False, True, False, False]]
    )
    codes, labels = results.taut_labels(taut)
    assert [labels[c] for c in codes] == ["1-2-3-4", "", "1-3-4", "2"]
    assert list(codes) == [15, 0, 13, 2] and len(labels) == 16 == len(set(labels))
    rng = np.random.default_rng(0)
    many = rng.random((300, 6)) < 0.5
    codes, labels = results.taut_labels(many)
    expected = ["-".join(str(i + 1) for i in np.flatnonzero(row)) for row in many]
    assert [labels[c] for c in codes] == expected and codes.dtype == np.int64


def test_pose_columns_are_the_tables_leading_columns(cdpr4):
    rng = np.random.default_rng(4)
    res = {"p": rng.normal(size=(5, 3)), "P_s": rng.normal(size=(5, 3)), "t": rng.normal(size=(5, 4))}
    res["dp"] = np.linalg.norm(res["P_s"] - res["p"], axis=1)
    cols = results.pose_columns(cdpr4, res)
    assert list(cols) == ["x", "y", "z", "x_s", "y_s", "z_s", "dp", "t1", "t2", "t3", "t4"]
    np.testing.assert_array_equal(np.column_stack([cols[k] for k in ("x", "y", "z")]), res["p"])
    np.testing.assert_array_equal(np.column_stack([cols[k] for k in ("x_s", "y_s", "z_s")]), res["P_s"])
    np.testing.assert_array_equal(np.column_stack([cols[f"t{i}"] for i in range(1, 5)]), res["t"])
