"""Sensitivities of a rigid platform's equilibrium = finite differences of the full solve (issue 17)."""

import dataclasses

import numpy as np
import pytest

from cdpr.models.equilibrium import solve as solve_spatial
from cdpr.models.platform import rotvec_of
from cdpr.models.sensitivity import COND_MAX, pose_sensitivities
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
    r = load_robot(ROBOTS / "cogiro_massless.yaml")
    res = pose_sensitivities(r, [pose], names=NAMES)
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


def test_sensitivities_under_compensated_lengths_at_a_tilted_pose():
    """dp*/dθ and dφ*/dθ of an anchor, an attachment, a modulus and the centre of mass = central
    differences of the re-solved equilibrium, CoGiRo slightly tilted under compensated lengths (every
    cable taut at >= 100 N); the point is smooth and its tension margin is the least of t_i, T_a - t_i."""
    from cdpr.models.tension_distribution import compensated_lengths

    r = load_robot(ROBOTS / "cogiro_massless.yaml")
    pose = [[0.3, -0.2, 2.1, 0.04, -0.03, 0.05]]
    comp = compensated_lengths(r, pose, t_min=100.0, t_max=5000.0)
    assert comp["feasible"].all()
    names = ["A_3_x", "b_2_y", "E_5", "c_z"]
    res = pose_sensitivities(r, pose, L0=comp["L0"], names=names)
    assert res["status"][0] == "ok" and res["taut"].all()
    assert np.abs(res["P_s"][0] - pose[0][:3]).max() < 1e-9  # compensated: the platform is at the pose
    assert res["smooth"][0] and np.isfinite(res["cond"][0])
    t = res["t"][0]
    assert res["margin_t"][0] == pytest.approx(np.minimum(t, r.T_a - t).min(), rel=1e-9)
    assert res["margin_t"][0] >= 100.0 - 1e-6
    steps = {"E_5": 1e5}
    for k, name in enumerate(names):
        h = steps.get(name, 1e-6)
        out = []
        for s in (1, -1):
            q = solve_spatial(
                changed(r, name, s * h), res["P_s"], rotvec_of(res["R_s"]), L0=comp["L0"], restarts=False
            )
            out.append((q["P_s"][0], q["R_s"][0]))
        fd = np.concatenate([(out[0][0] - out[1][0]) / (2 * h), rotvec_of(out[0][1] @ out[1][1].T) / (2 * h)])
        S = res["S"][0, :, k]
        assert np.abs(fd).max() > 0
        assert np.abs(S - fd).max() <= 1e-4 * np.abs(fd).max() + 1e-12, name
    tight = pose_sensitivities(r, pose, L0=comp["L0"], names=names, t_tol=res["margin_t"][0] + 1.0)
    assert not tight["smooth"][0]  # a tension within t_tol of a bound: the taut set may change


def test_scaled_condition_flags_a_singular_jacobian():
    from cdpr.models.sensitivity import scaled_condition

    rng = np.random.default_rng(3)
    J = rng.normal(size=(2, 6, 6))
    J[1, :, 5] = J[1, :, 4]  # rank 5: a neutral mode
    c = scaled_condition(J, 0.5)
    assert np.isfinite(c[0]) and 6.0 <= c[0] < COND_MAX  # ||A||_F ||A^-1||_F >= n
    assert c[1] > COND_MAX  # not smooth there
    J[0, 0, 0] = np.nan
    assert scaled_condition(J, 0.5)[0] == np.inf


def test_failed_points_get_nan_and_are_not_smooth():
    r = load_robot(ROBOTS / "cogiro_massless.yaml")
    res = pose_sensitivities(r, [[0, 0, 2.0, 0, 0, 0], [0, 0, 20.0, 0, 0, 0]], names=["c_z"])
    bad = res["status"] != "ok"
    assert list(bad) == [False, True] and res["smooth"][0]  # 20 m is above the frame: not converged
    assert np.isnan(res["S"][bad]).all() and not res["smooth"][bad].any()
