"""Sensitivities of a rigid platform's equilibrium = finite differences of the full solve (issue 17)."""

import dataclasses

import numpy as np
import pytest

from cdpr.models.equilibrium6 import solve_spatial
from cdpr.models.platform import rotvec_of
from cdpr.models.sensitivity6 import spatial_sensitivities
from cdpr.robot import load_robot
from tests.conftest import ROBOTS


def changed(robot, name, delta):
    """The robot with one parameter moved by delta (through its dataclasses, independent of the
    evaluator the sensitivities perturb)."""
    parts = name.split("_")
    if name == "M":
        return dataclasses.replace(
            robot, platform=dataclasses.replace(robot.platform, mass=robot.platform.mass + delta)
        )
    if parts[0] == "c":
        com = list(robot.platform.com)
        com["xyz".index(parts[1])] += delta
        return dataclasses.replace(robot, platform=dataclasses.replace(robot.platform, com=tuple(com)))
    i = int(parts[1]) - 1
    c = robot.cables[i]
    if parts[0] in ("A", "b"):
        key = "A" if parts[0] == "A" else "B"
        v = list(getattr(c, key))
        v["xyz".index(parts[2])] += delta
        c = dataclasses.replace(c, **{key: tuple(v)})
    elif parts[0] == "E":
        c = dataclasses.replace(c, material=dataclasses.replace(c.material, E=c.material.E + delta))
    elif parts[0] == "d":
        c = dataclasses.replace(c, dead_length=c.dead_length + delta)
    else:
        c = dataclasses.replace(c, pulley=dataclasses.replace(c.pulley, h=c.pulley.h + delta))
    cables = list(robot.cables)
    cables[i] = c
    return dataclasses.replace(robot, cables=tuple(cables))


NAMES = ["E_3", "h_1", "d_2", "A_2_y", "b_1_x", "b_4_z", "c_z", "c_x", "M"]
STEPS = {"E_3": 1e5, "M": 1e-4}


@pytest.mark.parametrize(
    "pose", [[0, 0, 2.0, 0, 0, 0], [1, 1, 1.5, 0, 0, 0], [0, 0, 2.0, np.radians(15), 0, 0]]
)
def test_sensitivities_equal_finite_differences_on_cogiro(pose):
    r = load_robot(ROBOTS / "cogiro.yaml")
    res = spatial_sensitivities(r, [pose], names=NAMES)
    L0 = res["L0"]
    for k, name in enumerate(NAMES):
        h = STEPS.get(name, 1e-6)
        out = []
        for s in (1, -1):
            q = solve_spatial(
                changed(r, name, s * h), res["P_s"], rotvec_of(res["R_s"]), L0=L0, restarts=False
            )
            out.append((q["P_s"][0], q["R_s"][0]))
        dp = (out[0][0] - out[1][0]) / (2 * h)
        dphi = rotvec_of(out[0][1] @ out[1][1].T) / (2 * h)
        fd = np.concatenate([dp, dphi])
        S = res["S"][0, :, k]
        assert np.abs(S - fd).max() <= 1e-4 * np.abs(fd).max() + 1e-12, name
