"""The parameter vector θ (cdpr.parameters): one vector for every robot, built from the robot (E, h,
r_p, d, A, then b and c when the platform is rigid, M last); a robot rebuilt from its own θ is the
same robot, pulley axes included (a wall pulley's horizontal axis must survive a calibration)."""

import numpy as np
import pytest

from cdpr.errors import CdprError
from cdpr.parameters import (
    calibration_groups,
    calibration_names,
    group_columns,
    parameter_groups,
    parameter_names,
    parameter_units,
    parameter_values,
    robot_with_parameters,
)
from cdpr.robot import load_robot
from tests.conftest import ROBOTS


def test_a_spatial_robot_rebuilt_from_its_parameters_keeps_its_pulleys():
    robot = load_robot(ROBOTS / "wall_pulleys.yaml")
    assert any(tuple(c.pulley.axis) != (0.0, 0.0, 1.0) for c in robot.cables)
    theta = parameter_values(robot)
    again = robot_with_parameters(robot, theta)
    assert [c.pulley for c in again.cables] == [c.pulley for c in robot.cables]
    np.testing.assert_array_equal(parameter_values(again), theta)
    theta2 = theta.copy()
    theta2[robot.m] += 1e-3  # h_1
    moved = robot_with_parameters(robot, theta2)
    assert moved.cables[0].pulley.h == robot.cables[0].pulley.h + 1e-3
    assert moved.cables[0].pulley.axis == robot.cables[0].pulley.axis


@pytest.mark.parametrize("name, rigid", [("cdpr4.yaml", False), ("cogiro_massless.yaml", True)])
def test_one_vector_built_from_the_robot(name, rigid):
    """A point mass has E, h, r_p, d, A, M (7 m + 1); a rigid platform adds b and c before M
    (10 m + 4); names, groups, units, values and the columns of each group agree."""
    robot = load_robot(ROBOTS / name)
    m = robot.m
    names, groups, units = parameter_names(robot), parameter_groups(robot), parameter_units(robot)
    theta = parameter_values(robot)
    n = 10 * m + 4 if rigid else 7 * m + 1
    assert len(names) == len(groups) == len(units) == len(theta) == n
    assert names[0] == "E_1" and names[-1] == "M" and groups[-1] == "M" and units[-1] == "kg"
    assert ("b_1_x" in names and "c_z" in names) is rigid and (names[-2] == "c_z") is rigid
    assert all(u == ("Pa" if g == "E" else "kg" if g == "M" else "m") for g, u in zip(groups, units))
    cols = group_columns(robot)
    assert sorted(int(k) for c in cols.values() for k in c) == list(range(n))
    a = robot.arrays
    np.testing.assert_array_equal(theta[cols["A"]], a.A.ravel())
    assert theta[cols["M"][0]] == robot.platform.mass
    if rigid:
        np.testing.assert_array_equal(theta[cols["b"]], a.b.ravel())
        np.testing.assert_array_equal(theta[cols["c"]], a.com)
        # the pose kernels' full set of columns of a point mass is the rigid platform's order
    assert parameter_names(robot, rigid=True)[-4:] == ["c_x", "c_y", "c_z", "M"]
    assert parameter_names(robot, rigid=False) == [
        x for x in parameter_names(robot, rigid=True) if x[0] not in "bc"
    ]
    # calibration: θ then the encoder offsets
    cal = calibration_names(robot)
    assert cal[:n] == names and cal[n:] == [f"offset_{i}" for i in range(1, m + 1)]
    g, cables = calibration_groups(robot)
    assert len(g) == len(cables) == n + m and g[-1] == "offsets" and cables[n - 1] is None


def test_a_changed_parameter_reaches_the_robot_and_a_wrong_length_is_refused():
    robot = load_robot(ROBOTS / "cogiro_massless.yaml")
    names, theta = parameter_names(robot), parameter_values(robot).copy()
    theta[names.index("b_2_y")] += 0.01
    theta[names.index("c_z")] = 0.05
    theta[names.index("M")] = 90.0
    moved = robot_with_parameters(robot, theta)
    assert moved.cables[1].B[1] == robot.cables[1].B[1] + 0.01
    assert moved.platform.com[2] == 0.05 and moved.platform.mass == 90.0
    with pytest.raises(CdprError, match="expected 84 parameter values for a rigid platform on 8 cables"):
        robot_with_parameters(robot, theta[:-1])
