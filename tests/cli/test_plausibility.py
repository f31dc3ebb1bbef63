"""Plausibility warnings (issue 41): a value far outside what a real CDPR has — a unit slip, most
likely — gives one warning line on stderr naming the key, the value and the likely slip, and a
``warnings`` list in the command's JSON object; the command still runs (exit 0). The checks are one
library function, ``cdpr.plausibility.plausibility_warnings``; the command line calls it once per robot."""

import json

import pytest
import yaml

from cdpr.cli.main import main
from cdpr.plausibility import plausibility_warnings
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

R4 = ROBOTS / "cdpr4.yaml"
HANG = ROBOTS / "hang4_6dof.yaml"


def run(argv, capsys):
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def edited(tmp_path, base, edit):
    """A copy of robot file ``base`` with ``edit(data)`` applied."""
    data = yaml.safe_load(base.read_text())
    edit(data)
    path = tmp_path / "robot.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.mark.parametrize("robot", sorted(ROBOTS.glob("*.yaml")), ids=lambda p: p.stem)
def test_shipped_robots_are_plausible(robot):
    assert plausibility_warnings(load_robot(robot)) == []


def _anchor_in_mm(d):
    d["cables"][1]["A_m"] = [2500.0, -2500.0, 5000.0]


def _all_in_mm(d):
    for c in d["cables"]:
        c["A_m"] = [1000 * x for x in c["A_m"]]


def _attachments_20x(d):
    for c in d["cables"]:  # the frame's diagonal is 7.07 m; these attachments span 20 times it
        c["B_m"] = [x * 20 * 7.07 / 0.5657 for x in c["B_m"]]


def _diameter(d):
    d["cable"]["diameter_m"] = 4


@pytest.mark.parametrize(
    "base,edit,args,words",
    [
        (R4, None, ["--E", "102.2"], ["cable.young_modulus_Pa = 102.2 Pa", "GPa typed as Pa?"]),
        (R4, None, ["--E", "102200"], ["cable.young_modulus_Pa = 102200 Pa", "MPa typed as Pa?"]),
        (R4, _diameter, [], ["cable.diameter_m = 4 m", "millimetres typed as metres? (4 mm = 0.004 m)"]),
        (R4, None, ["--h", "100", "--rp", "66.5"], ["pulley.h_m = 100 m", "(100 mm = 0.1 m)"]),
        (R4, None, ["--h", "100", "--rp", "66.5"], ["pulley.r_p_m = 66.5 m", "(66.5 mm = 0.0665 m)"]),
        (R4, _anchor_in_mm, [], ["cables[1].A_m = [2500.0, -2500.0, 5000.0] m", "millimetres among metres?"]),
        (R4, _all_in_mm, [], ["the anchors span 7071 m", "every location in millimetres?"]),
        (
            HANG,
            _attachments_20x,
            [],
            ["cables[*].B_m: the platform's attachments span 141.4 m", "frame's 7.071 m"],
        ),
    ],
)
def test_an_implausible_value_is_one_warning_and_the_command_runs(tmp_path, capsys, base, edit, args, words):
    robot = base if edit is None else edited(tmp_path, base, edit)
    code, out, err = run(["compensate", "--robot", robot, "--at", "0", "0", "2", *args, "--json"], capsys)
    assert code == 0
    lines = [line for line in err.splitlines() if all(w in line for w in words)]
    assert len(lines) == 1 and lines[0].startswith("cdpr: warning: "), err
    got = json.loads(out)["warnings"]  # the same sentences in the JSON object
    assert err == "".join(f"cdpr: warning: {load_robot_source(robot, args)}: {w}\n" for w in got)
    if "--E" not in args:  # `inverse` has no --E
        code, out, err2 = run(["inverse", "--robot", robot, "--at", "0", "0", "2", *args, "--json"], capsys)
        assert code == 0 and err2 == err
        assert isinstance(json.loads(out), list)  # a JSON list keeps its shape: warnings on stderr only


def load_robot_source(robot, args):
    """The source a robot loaded with command-line overrides names in its messages."""
    over = {"--E": "E", "--h": "h", "--rp": "r_p"}
    given = sorted(over[a] for a in args if a in over)
    return f"{robot} (with command-line overrides: {', '.join(given)})" if given else str(robot)


def test_plausible_robot_json_has_an_empty_warnings_list(capsys):
    code, out, err = run(["compensate", "--robot", R4, "--at", "0", "0", "2", "--json"], capsys)
    assert code == 0 and err == "" and json.loads(out)["warnings"] == []


def test_the_library_names_each_cable_when_they_differ(tmp_path):
    def edit(d):
        d["cables"][2]["cable"] = {"diameter_m": 0.5}

    w = plausibility_warnings(load_robot(edited(tmp_path, R4, edit)))
    assert len(w) == 1 and w[0].startswith("cables[2].cable.diameter_m = 0.5 m")


def test_an_import_with_a_unit_slip_warns_and_still_writes(tmp_path, capsys):
    """The issue's import cases: ``cdpr import caspr --diameter 4`` (mm meant) and a CASPR
    ``pulley_radius`` of 45 (mm typed as m) each give their warning line; the file is written."""
    from tests.test_robot_import import files

    b, c = files(tmp_path)
    base = ["import", "caspr", "--bodies", b, "--cables", c]
    code, _, err = run([*base, "--diameter", "4", "--out", tmp_path / "d.yaml"], capsys)
    warned = [line for line in err.splitlines() if line.startswith("cdpr: warning: ")]
    assert code == 0 and (tmp_path / "d.yaml").is_file()
    assert len(warned) == 1 and "cable.diameter_m = 4 m" in warned[0] and "(4 mm = 0.004 m)" in warned[0]
    c.write_text(
        c.read_text().replace("<pulley_radius>0.05</pulley_radius>", "<pulley_radius>45</pulley_radius>")
    )
    code, _, err = run([*base, "--out", tmp_path / "r.yaml"], capsys)
    warned = [line for line in err.splitlines() if line.startswith("cdpr: warning: ")]
    assert code == 0 and (tmp_path / "r.yaml").is_file()
    assert warned and all("= 45 m" in w and "(45 mm = 0.045 m)" in w for w in warned)
    assert any("pulley.r_p_m = 45 m" in w for w in warned)
