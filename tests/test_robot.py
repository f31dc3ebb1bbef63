"""Robot files: the shipped ones load with the paper's data; bad files give one clear sentence."""

import copy
import math

import numpy as np
import pytest
import yaml

from cdpr.analyses.workspace import envelope_volume
from cdpr.errors import ConfigError
from cdpr.robot import load_robot, robot_from_dict, with_pulleys
from tests.conftest import ROBOTS


def test_shipped_robots_hold_the_paper_data(cdpr3, cdpr4):
    assert cdpr4.m == 4 and cdpr3.m == 3
    assert envelope_volume(cdpr4) == pytest.approx(125.0)
    assert envelope_volume(cdpr3) == pytest.approx(54.13, abs=0.005)  # V_T, section 3.3.3
    # trajectory lengths of section 3.3.1 follow from the geometry
    assert np.linalg.norm(np.subtract((1.25, 0.72, 5), (-2.5, -1.44, 0))) == pytest.approx(6.61, abs=0.005)
    assert np.linalg.norm(np.subtract((2.5, 0, 5), (-2.5, 0, 0))) == pytest.approx(7.07, abs=0.005)
    for r in (cdpr3, cdpr4):
        assert r.platform.mass == 300 and (r.arrays.E == 102.2e9).all() and (r.T_a == 5140).all()
        assert r.arrays.S == pytest.approx(math.pi * 0.004**2 / 4)
        assert set(r.h) == {0.1} and set(r.r_p) == {0.0665} and set(r.d) == {4.0}


def base():
    return yaml.safe_load((ROBOTS / "cdpr4.yaml").read_text())


def write(tmp_path, data, name="robot.yaml"):
    p = tmp_path / name
    p.write_text(yaml.safe_dump(data))
    return p


def test_units_as_strings_equal_si_numbers(tmp_path):
    d = base()
    d["pulley"] = {"kind": "DR", "h_m": "100 mm", "r_p_m": "6.65 cm"}
    d["cable"]["young_modulus_Pa"] = "102.2 GPa"
    d["cable"]["max_tension_N"] = "5.14 kN"
    r = load_robot(write(tmp_path, d))
    assert r.h[0] == pytest.approx(0.1) and r.r_p[0] == pytest.approx(0.0665)
    assert r.arrays.E == pytest.approx(102.2e9) and r.T_a == pytest.approx(5140)


def test_per_cable_overrides(tmp_path):
    d = base()
    d["cables"][1]["pulley"] = {"kind": "DR", "h_m": 0.15}
    d["cables"][2]["dead_length_m"] = 2.0
    r = load_robot(write(tmp_path, d))
    assert list(r.kind) == [1, 2, 1, 1]
    assert r.h[1] == 0.15 and r.r_p[1] == 0.0665  # r_p inherited from the default pulley
    assert list(r.d) == [4.0, 4.0, 2.0, 4.0]


def test_command_line_overrides_equal_editing_the_file(tmp_path):
    d = base()
    edited = copy.deepcopy(d)
    edited["pulley"] = {"kind": "DR", "h_m": 0.15, "r_p_m": 0.098}
    edited["dead_length_m"] = 3.0
    edited["cable"]["young_modulus_Pa"] = 80e9
    a = load_robot(write(tmp_path, edited, "edited.yaml"))
    b = load_robot(write(tmp_path, d), pulley="DR", h=0.15, r_p=0.098, dead_length=3.0, E=80e9)
    assert a.cables == b.cables and a.platform == b.platform


BAD = [
    (lambda d: d.update(colour="red"), "key 'colour': unknown key"),
    (lambda d: d["platform"].pop("mass_kg"), "key 'platform.mass_kg': missing required key"),
    (lambda d: d.pop("cables"), "key 'cables': missing required key"),
    (lambda d: d["pulley"].update(r_p_m=-0.01), "key 'pulley.r_p_m': must be non-negative"),
    (lambda d: d["pulley"].update(h_m="100 kg"), "unit 'kg' is not a unit of m"),
    (lambda d: d["platform"].update(mass_kg="heavy"), "cannot read 'heavy' as a quantity"),
    (lambda d: d["platform"].update(mass_kg=[300]), "expected a number in kg"),
    (
        lambda d: d["pulley"].update(kind="DR", h_m=0.05, r_p_m=0.0665),
        "DR pulley needs lever arm h_m > sheave radius r_p_m",
    ),
    (
        lambda d: d["pulley"].update(kind="DR", h_m=0.0665, r_p_m=0.0665),
        "DR pulley needs lever arm h_m > sheave radius r_p_m",
    ),
    (lambda d: d["pulley"].update(kind="triple"), "unknown kind 'triple'; allowed: fixed | SR | DR"),
    (lambda d: d.update(cables=d["cables"][:2]), "needs at least 3 cables, got 2"),
    (lambda d: d["cables"][3].update(A_m=[-2.5, -2.5, 5.0]), "key 'cables[3].A_m': duplicate anchor point"),
    (lambda d: d["cables"][0].update(A_m=[1, 2]), "key 'cables[0].A_m': expected a list of 3 coordinates"),
    (lambda d: d["cable"].update(diameter_m=0), "key 'cable.diameter_m': must be strictly positive"),
    (lambda d: d["cables"][0].update(pulley={"radius": 1}), "key 'cables[0].pulley.radius': unknown key"),
    (lambda d: d.update(cables=[{"A_m": [x, 0, 5]} for x in (0, 1, 2)]), "collinear"),
]


@pytest.mark.parametrize("mutate,message", BAD)
def test_bad_robot_files_name_file_key_and_what_is_allowed(tmp_path, mutate, message):
    d = base()
    mutate(d)
    path = write(tmp_path, d)
    with pytest.raises(ConfigError) as exc:
        load_robot(path)
    assert message in str(exc.value)
    assert str(path) in str(exc.value)


def test_unreadable_and_invalid_yaml(tmp_path):
    with pytest.raises(ConfigError, match="cannot read the file"):
        load_robot(tmp_path / "nope.yaml")
    p = tmp_path / "broken.yaml"
    p.write_text("platform: {mass_kg: 300\n")
    with pytest.raises(ConfigError, match="broken.yaml: not valid YAML"):
        load_robot(p)


def test_fixed_point_limit_allowed_for_every_kind(cdpr4):
    for kind in ("SR", "DR"):
        r = with_pulleys(cdpr4, kind=kind, h=0.0, r_p=0.0)
        assert (r.h == 0).all() and (r.r_p == 0).all()
    with pytest.raises(ConfigError):
        robot_from_dict({**base(), "pulley": {"kind": "fixed", "h_m": 0.1}}, "x.yaml")


# ---------------------------------------------------------------------------------------------
# Spatial robot files (issue 17): B_m, pulley.axis, pulley.zero, platform.com_m
# ---------------------------------------------------------------------------------------------
def spatial_base():
    d = base()
    d["cables"] = [
        {"A_m": [-2.5, -2.5, 5.0], "B_m": [-0.2, -0.2, 0.1]},
        {"A_m": [2.5, -2.5, 5.0], "B_m": [0.2, -0.2, 0.1]},
        {"A_m": [2.5, 2.5, 0.0], "B_m": [0.2, 0.2, -0.1], "pulley": {"axis": [0, 0, -1]}},
        {"A_m": [-2.5, 2.5, -1.0], "B_m": [-0.2, 0.2, -0.1], "pulley": {"axis": [1, 0, 0]}},
    ]
    d["platform"]["com_m"] = [0.0, 0.01, 0.02]
    return d


def test_spatial_keys_are_read_and_defaults_are_todays_model(tmp_path, cdpr4):
    r = load_robot(write(tmp_path, spatial_base()))
    a = r.arrays
    assert a.b[0] == pytest.approx([-0.2, -0.2, 0.1]) and a.com == pytest.approx([0.0, 0.01, 0.02])
    assert a.axis[2] == pytest.approx([0, 0, -1]) and a.axis[3] == pytest.approx([1, 0, 0])
    assert not r.point_mass and not r.suspended_point_mass
    for f in a.frame:  # orthonormal, right-handed, k = axis
        assert f @ f.T == pytest.approx(np.eye(3), abs=1e-15) and np.linalg.det(f) == pytest.approx(1.0)
    assert a.frame[3, 0] == pytest.approx([0, 1, 0])  # axis within 25 deg of +x: the zero is +y
    # today's robots: identity frames, zero attachments, the same inward vectors as before
    c = cdpr4.arrays
    assert cdpr4.suspended_point_mass and (c.frame == np.eye(3)).all() and not c.b.any()
    assert c.inward == pytest.approx(np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]]) / math.sqrt(2))


def test_anchors_anywhere_and_shared_anchors_for_spatial_robots(tmp_path):
    d = spatial_base()
    d["cables"][1]["A_m"] = [-2.5, -2.5, 5.0]  # shared anchor, different attachment: allowed
    r = load_robot(write(tmp_path, d))
    assert r.m == 4
    d["cables"] = [{"A_m": [x, 0, 0.0], "B_m": [0.1 * x, 0, 0]} for x in (0, 1, 2)]  # collinear, z = 0
    assert load_robot(write(tmp_path, d)).m == 3


SPATIAL_BAD = [
    (lambda d: d["cables"][1].update(A_m=[-2.5, -2.5, 5.0], B_m=[-0.2, -0.2, 0.1]), "duplicate anchor point"),
    (lambda d: d["pulley"].update(axis=[0, 0, 0]), "key 'pulley.axis': the swivel axis must be a non-zero"),
    (lambda d: d["pulley"].update(axis=[0, 0, float("nan")]), "key 'pulley.axis[2]': must be finite"),
    (
        lambda d: d["pulley"].update(zero=[0, 0, 1]),
        "key 'pulley.zero': must be a non-zero vector perpendicular",
    ),
    (lambda d: d["cables"][0].update(B_m=[1, 2]), "key 'cables[0].B_m': expected a list of 3 coordinates"),
    (lambda d: d["platform"].update(com_m=[0, 0]), "key 'platform.com_m': expected a list of 3 coordinates"),
]


@pytest.mark.parametrize("mutate,message", SPATIAL_BAD)
def test_bad_spatial_keys_give_one_sentence(tmp_path, mutate, message):
    d = spatial_base()
    mutate(d)
    path = write(tmp_path, d)
    with pytest.raises(ConfigError) as exc:
        load_robot(path)
    assert message in str(exc.value) and str(path) in str(exc.value)


AXIS_ZERO_BAD = [  # (pulley keys of cable 0, key, the whole detail of the message)
    ({"axis": [0, 0, 0]}, "axis", "the swivel axis must be a non-zero vector, got [0.0, 0.0, 0.0]"),
    (
        {"axis": [0, 0, 1], "zero": [0, 0.5, 1]},
        "zero",
        "must be a non-zero vector perpendicular to the pulley axis [0.0, 0.0, 1.0], got [0.0, 0.5, 1.0]",
    ),
    (
        {"axis": [0, 0, 1], "zero": [0, 0, 0]},
        "zero",
        "must be a non-zero vector perpendicular to the pulley axis [0.0, 0.0, 1.0], got [0.0, 0.0, 0.0]",
    ),
    (
        {"axis": ["nan", 0, 1]},
        "axis[0]",
        "cannot read 'nan' as a number; expected a plain number (dimensionless, no unit)",
    ),
    (
        {"axis": ["5 mm", 0, 1]},
        "axis[0]",
        "expected a plain number (dimensionless, no unit), got '5 mm' with the unit 'mm'",
    ),
    (
        {"axis": [0, 0, 1], "zero": [1, "1 cm", 0]},
        "zero[1]",
        "expected a plain number (dimensionless, no unit), got '1 cm' with the unit 'cm'",
    ),
]


@pytest.mark.parametrize("pulley,key,detail", AXIS_ZERO_BAD)
def test_axis_and_zero_messages_are_plain_and_dimensionless(tmp_path, pulley, key, detail):
    """Plain numbers (no numpy reprs), no length units for a direction, one line naming file and key."""
    d = spatial_base()
    d["cables"][0]["pulley"] = pulley
    path = write(tmp_path, d, "zeroaxis.yaml")
    with pytest.raises(ConfigError) as exc:
        load_robot(path)
    assert str(exc.value) == f"{path}: key 'cables[0].pulley.{key}': {detail}"


def test_axis_and_zero_take_plain_numbers_written_as_strings(tmp_path):
    d = spatial_base()
    d["cables"][0]["pulley"] = {"axis": ["0", 0, "2"], "zero": ["1e0", 0, 0]}
    p = load_robot(write(tmp_path, d)).cables[0].pulley
    assert (p.axis, p.zero) == ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0))


def test_suspended_point_mass_rules_only_for_anchors_above_the_floor(tmp_path):
    """An anchor at or below the floor (default z = 0) no longer refuses the file: the robot is not a
    suspended one (issue 40/41: the Hangprinter). With the floor below it, the same robot is
    suspended again, and a suspended robot's anchors collinear seen from above are still refused."""
    d = base()
    d["cables"][0]["A_m"] = [-2.5, -2.5, 0.0]
    r = load_robot(write(tmp_path, d))
    assert r.floor_z == 0.0 and not r.suspended_point_mass
    d["frame"] = {"floor_z_m": -1.0}
    r = load_robot(write(tmp_path, d))
    assert r.floor_z == -1.0 and r.suspended_point_mass
    for i, c in enumerate(d["cables"]):
        c["A_m"] = [float(i), float(i), 5.0]
    with pytest.raises(ConfigError, match="collinear seen from above"):
        load_robot(write(tmp_path, d))


def test_with_pulleys_keeps_axis_zero_attachment_and_winch(tmp_path):
    d = spatial_base()
    d["cables"][3]["pulley"]["zero"] = [0, 0, 1]
    d["winch"] = {}
    r = load_robot(write(tmp_path, d))
    s = with_pulleys(r, kind="DR", h=0.15)
    for a, b in zip(r.cables, s.cables):
        assert (a.pulley.axis, a.pulley.zero, a.B, a.winch) == (b.pulley.axis, b.pulley.zero, b.B, b.winch)
        assert b.pulley.kind == "DR" and b.pulley.h == 0.15
