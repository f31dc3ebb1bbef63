"""Robot files with spool winches and a floor: the shipped Hangprinter, per-robot and per-cable
spools, the U strands' stiffness, the floor rule (suspended only when every anchor is above the
floor), and the robot-level encoder map (cdpr.models.drive spool functions)."""

import copy

import numpy as np
import pytest
import yaml

from cdpr.analyses.workspace import frame_box
from cdpr.errors import CdprError, ConfigError
from cdpr.models import drive
from cdpr.robot import SpoolParams, load_robot, robot_from_dict, spool_from_mapping, spool_mapping
from cdpr.solve import solve
from tests.conftest import ROBOTS

HP4 = ROBOTS / "hangprinter_hp4.yaml"
EA = 20000.0  # the HP4 line's E A [N] (M666 S)


def hp4_data():
    return yaml.safe_load(HP4.read_text())


def test_shipped_hangprinter_holds_the_hp4_constants():
    r = load_robot(HP4)
    assert r.m == 4 and r.point_mass and r.platform.mass == 2.0
    assert [c.pulley.kind for c in r.cables] == ["fixed"] * 4
    assert [p.U for p in r.spools] == [2, 2, 2, 4]
    assert {(p.r0, p.Q, p.lines_per_spool, p.motor_teeth, p.spool_teeth) for p in r.spools} == {
        (0.075, 0.06875e-3, 1, 20, 255)
    }
    assert all(w is None for w in r.winches)  # spools are not Métillon drums
    # U strands of a 20 kN line between anchor and mover
    assert r.ES == pytest.approx(EA * np.array([2, 2, 2, 4]), rel=1e-12)
    assert r.A[:, 2] == pytest.approx([-0.15, -0.15, -0.15, 2.35])


def test_hangprinter_is_not_suspended_and_its_floor_is_its_lowest_anchor():
    r = load_robot(HP4)
    assert r.floor_z == -0.15 and not r.suspended_point_mass
    assert frame_box(r)[4:] == [-0.15, 2.35]


def test_a_pose_above_the_low_anchors_is_solved_not_inaccessible():
    """Before: every pose above the lowest anchor was inaccessible. Now a pose inside the anchors'
    tetrahedron is held by the lines, in both engines, within a few millimetres (stiff lines, 2 kg)."""
    r = load_robot(HP4)
    P = np.array([[0.0, 0.0, 0.0], [0.1, -0.2, 0.5], [0.0, 0.0, 1.2], [-0.2, 0.1, 0.05]])
    for engine in ("numpy", "compiled"):
        res = solve(r, P, redundancy="physical", engine=engine)
        assert list(res["status"]) == ["ok"] * 4, engine
        assert (res["dp"] < 5e-3).all(), res["dp"]
        assert (res["t"][:, 3] > 19.0).all()  # the top line carries the weight (2 kg * 9.81 m/s^2)


def test_floor_key_makes_a_suspended_robot_with_anchors_at_z0():
    """cdpyr's convention: anchors at z = 0, the platform below. Without a floor the default floor
    lies the anchors' horizontal extent (5 m) below them: a suspended robot (its frame box had no
    height before, and every hanging pose was out_of_frame); with ``frame.floor_z_m: -3`` it is a
    suspended robot whose points below -3 m are inaccessible."""
    d = yaml.safe_load((ROBOTS / "cdpr4.yaml").read_text())
    for c in d["cables"]:
        c["A_m"][2] = 0.0
    r = robot_from_dict(copy.deepcopy(d), "flat.yaml")
    assert r.floor_z == -5.0 and r.suspended_point_mass and frame_box(r)[4:] == [-5.0, 0.0]
    d["frame"] = {"floor_z_m": "-3000 mm"}
    r = robot_from_dict(d, "flat.yaml")
    assert r.floor_z == -3.0 and r.suspended_point_mass
    assert frame_box(r)[4:] == [-3.0, 0.0]
    res = solve(r, np.array([[0.0, 0.0, -2.0], [0.0, 0.0, -3.5]]), redundancy="physical")
    assert list(res["status"]) == ["ok", "inaccessible"]


def test_cdpr4_keeps_its_suspended_rules():
    r = load_robot(ROBOTS / "cdpr4.yaml")
    assert r.floor_z == 0.0 and r.suspended_point_mass
    res = solve(r, np.array([[0.0, 0.0, -0.5], [0.0, 0.0, 2.5]]), redundancy="physical")
    assert list(res["status"]) == ["inaccessible", "ok"]


@pytest.mark.parametrize(
    "change, key, words",
    [
        ({"frame": {"floor_z_m": "2 kg"}}, "frame.floor_z_m", "m"),
        ({"frame": {"floor": 0}}, "frame", "floor"),
        ({"winch": {"kind": "spool", "spool_radius_m": -0.07}}, "winch.spool_radius_m", "strictly positive"),
        (
            {"winch": {"kind": "spool", "spool_radius_m": 0.07, "mechanical_advantage": 1.5}},
            "mechanical_advantage",
            "expected integer",
        ),
        (
            {"winch": {"kind": "spool", "spool_radius_m": 0.07, "k_w_m": 0.07}},
            "k_w_m",
            "unknown key of a spool winch",
        ),
        ({"winch": {"kind": "spool"}}, "spool_radius_m", "missing required key"),
        ({"winch": {"kind": "capstan"}}, "winch.kind", "drum | spool"),
    ],
)
def test_bad_spool_and_floor_keys_are_named(change, key, words):
    d = hp4_data()
    d.pop("winch")
    for c in d["cables"]:
        c.pop("winch")
    d.update(change)
    with pytest.raises(ConfigError) as exc:
        robot_from_dict(d, "hp.yaml")
    msg = str(exc.value)
    assert msg.startswith("hp.yaml") and key in msg and words in msg and "\n" not in msg


def test_spool_per_robot_per_cable_and_beside_a_drum():
    d = hp4_data()
    d["winch"] = {"kind": "spool", "spool_radius_m": 0.07, "buildup_factor_m": 1e-5}
    for c in d["cables"]:
        c.pop("winch")
    d["cables"][3]["winch"] = {"mechanical_advantage": 4}  # merged over the robot's spool
    r = robot_from_dict(d, "hp.yaml")
    assert [p.U for p in r.spools] == [1, 1, 1, 4] and {p.r0 for p in r.spools} == {0.07}
    d["cables"][3]["winch"] = {"kind": "drum"}  # another kind takes none of the robot's keys
    r = robot_from_dict(d, "hp.yaml")
    assert r.spools[3] is None and r.winches[3] is not None and r.spools[0].Q == 1e-5
    with pytest.raises(CdprError, match=r"cables \[4\] have no spool"):
        drive.spool_rest_lengths(r, np.zeros((1, 4)))


def test_spool_mapping_round_trip():
    p = SpoolParams(r0=0.0757, Q=6.875e-5, U=4, lines_per_spool=2, motor_teeth=20, spool_teeth=255)
    assert spool_from_mapping(spool_mapping(p), "x") == p


def test_robot_encoder_map_round_trip_and_reference():
    """Motor angle 0 is the standard model's length at the origin (|A_i| + d_i for fixed pulleys);
    motor angles -> rest lengths -> motor angles is exact; the direction: paying out lengthens."""
    r = load_robot(HP4)
    ref = drive.spool_reference_lengths(r)
    assert ref == pytest.approx(np.linalg.norm(r.A, axis=1) + r.d, rel=1e-15)
    assert drive.spool_rest_lengths(r, np.zeros((2, 4))) == pytest.approx(np.tile(ref, (2, 1)), rel=1e-15)
    deg = np.random.default_rng(3).uniform(-40000, 40000, size=(20, 4))
    L0 = drive.spool_rest_lengths(r, deg)
    assert drive.spool_motor_angles(r, L0) == pytest.approx(deg, rel=1e-11, abs=1e-7)
    assert (np.sign(L0 - ref) == np.sign(deg)).all()
    with pytest.raises(CdprError, match="4 motor angles needed"):
        drive.spool_rest_lengths(r, np.zeros((1, 3)))
    with pytest.raises(CdprError, match="need spool winches"):
        drive.spool_rest_lengths(load_robot(ROBOTS / "cdpr4.yaml"), np.zeros((1, 4)))
