"""The parameter vector θ (cdpr.parameters): a robot rebuilt from its own θ is the same robot,
pulley axes included (a wall pulley's horizontal axis must survive a calibration)."""

import numpy as np

from cdpr.parameters import parameter_values6, robot_with_parameters6
from cdpr.robot import load_robot
from tests.conftest import ROBOTS


def test_a_spatial_robot_rebuilt_from_its_parameters_keeps_its_pulleys():
    robot = load_robot(ROBOTS / "wall_pulleys.yaml")
    assert any(tuple(c.pulley.axis) != (0.0, 0.0, 1.0) for c in robot.cables)
    theta = parameter_values6(robot)
    again = robot_with_parameters6(robot, theta)
    assert [c.pulley for c in again.cables] == [c.pulley for c in robot.cables]
    np.testing.assert_array_equal(parameter_values6(again), theta)
    theta2 = theta.copy()
    theta2[robot.m] += 1e-3  # h_1
    moved = robot_with_parameters6(robot, theta2)
    assert moved.cables[0].pulley.h == robot.cables[0].pulley.h + 1e-3
    assert moved.cables[0].pulley.axis == robot.cables[0].pulley.axis
