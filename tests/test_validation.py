"""Configuration files (cdpr.validation): reading refuses what is not a UTF-8 text file of sensible
size before parsing, YAML refuses a key given twice naming both lines, and schema validation turns
each violation into one sentence naming the file, the most precise key and what is allowed (every
distinct violation in one error)."""

import copy
from collections import deque
from pathlib import Path

import pytest

from cdpr.errors import ConfigError
from cdpr.validation import key_path, read_text_file, read_yaml, schema, unit_of_key, validate
from tests.conftest import ROBOTS, ROOT


def _refused(call, path):
    with pytest.raises(ConfigError) as exc:
        call(path)
    msg = str(exc.value)
    assert msg.startswith(f"{path}: ") and "\n" not in msg and exc.value.key is None
    return msg


@pytest.mark.parametrize(
    "content,words",
    [
        ("é ok\n".encode("utf-16"), "is UTF-16 text; save it as UTF-8"),
        (b"a: 1\n\x00\x01", "is a binary file, not a text file"),
        (b"a: 1\nname: caf\xe9\n", "is not UTF-8 text (byte 0xe9 on line 2; Latin-1?); save it as UTF-8"),
    ],
)
def test_text_that_is_not_utf8_is_refused_saying_what_it_is(tmp_path, content, words):
    p = tmp_path / "r.yaml"
    p.write_bytes(content)
    assert words in _refused(read_text_file, p)


def test_what_is_not_a_regular_file_is_refused_before_reading(tmp_path):
    assert "cannot read the file (No such file or directory)" in _refused(
        read_text_file, tmp_path / "absent.yaml"
    )
    (tmp_path / "d.yaml").mkdir()
    assert "is a folder, not a file" in _refused(read_text_file, tmp_path / "d.yaml")
    assert "is not a regular file (a device or a pipe?)" in _refused(read_text_file, Path("/dev/null"))


def test_a_file_larger_than_the_limit_is_refused_with_both_sizes(tmp_path):
    p = tmp_path / "big.yaml"
    p.write_text("x" * (3 * 2**20))
    msg = str(pytest.raises(ConfigError, read_text_file, p, "robot file", 2 * 2**20).value)
    assert msg == f"{p}: is 3.0 MiB; a robot file is at most 2 MiB"
    assert read_text_file(p, max_bytes=4 * 2**20) == "x" * (3 * 2**20)


def test_read_yaml_reads_utf8_and_refuses_a_key_given_twice_naming_both_lines(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text("name: Café\nsolver:\n  tol: 1\n  maxiter: 3\n  tol: 2\n", encoding="utf-8")
    with pytest.raises(ConfigError) as exc:
        read_yaml(p)
    assert str(exc.value) == f"{p}: key 'tol': given twice (lines 3 and 5); keep one"
    p.write_text("name: Café\nsolver: {tol: 1}\n", encoding="utf-8")
    assert read_yaml(p) == {"name": "Café", "solver": {"tol": 1}}


def test_a_yaml_syntax_error_is_one_line(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text("a: [1, 2\nb: 3\n")
    assert "not valid YAML: " in _refused(read_yaml, p)


def test_key_paths_and_their_units():
    assert key_path(deque(["cables", 2, "pulley", "h_m"])) == "cables[2].pulley.h_m"
    assert key_path([0, "a"]) == "[0].a" and key_path([]) == ""
    assert [
        unit_of_key(["cables", 1, k]) for k in ("A_m", "young_modulus_Pa", "mass_kg", "gravity_m_per_s2")
    ] == [
        "m",
        "Pa",
        "kg",
        "m/s^2",
    ]
    assert unit_of_key(["max_tension_N"]) == "N" and unit_of_key(["zero_rad"]) == "rad"
    assert unit_of_key(["kind"]) is None and unit_of_key([3]) is None


@pytest.mark.parametrize(
    "name,path", [("robot", ROBOTS / "cogiro.yaml"), ("study", ROOT / "config" / "studies" / "quick.yaml")]
)
def test_the_shipped_files_are_valid(name, path):
    data = read_yaml(path)
    assert validate(data, name, path) is data
    assert schema(name) is schema(name)  # parsed once


@pytest.fixture
def robot():
    return read_yaml(ROBOTS / "cdpr4.yaml")


@pytest.mark.parametrize(
    "change,message",
    [
        (
            lambda d: d["cables"][1].update(A_m=[1, 2]),
            "key 'cables[1].A_m': expected a list of 3 coordinates [x, y, z] in m, got [1, 2]",
        ),
        (
            lambda d: d["pulley"].update(h_m=[1]),
            "key 'pulley.h_m': expected a number in m (or a string with one of the units m, cm, mm), got [1]",
        ),
        (
            lambda d: d["pulley"].update(kind="XR"),
            "key 'pulley.kind': unknown kind 'XR'; allowed: fixed | SR | DR",
        ),
        (lambda d: d.pop("cables"), "key 'cables': missing required key"),
    ],
)
def test_a_violation_is_one_sentence_naming_the_most_precise_key(robot, change, message):
    change(robot)
    with pytest.raises(ConfigError) as exc:
        validate(robot, "robot", "r.yaml")
    assert str(exc.value) == f"r.yaml: {message}"


def test_every_distinct_violation_is_reported_at_once(robot):
    bad = copy.deepcopy(robot)
    bad["colour"] = "red"
    bad["pulley"]["kind"] = "XR"
    with pytest.raises(ConfigError) as exc:
        validate(bad, "robot", "r.yaml")
    msg = str(exc.value)
    assert msg.startswith("r.yaml: 2 problems: key 'colour': unknown key; allowed keys here: cable, cables,")
    assert (
        msg.endswith("; key 'pulley.kind': unknown kind 'XR'; allowed: fixed | SR | DR") and "\n" not in msg
    )
