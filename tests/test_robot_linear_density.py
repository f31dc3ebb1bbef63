"""The cable's linear density (``cable.linear_density_kg_m``, issue 38): read from robot files (robot
default and per cable, SI number or a string in kg/m or g/m), bad values refused in one line naming
the key, the ``--linear-density`` override equal to editing the file, its default 0 changing nothing,
and heavy robots refused in one line by the commands that do not model them yet."""

import copy
import json

import numpy as np
import pytest
import yaml

from cdpr.cli.main import main
from cdpr.errors import ConfigError
from cdpr.robot import load_robot
from tests.conftest import ROBOTS
from tests.test_robot import base, write  # the cdpr4 mapping and its writer

R4 = str(ROBOTS / "cdpr4.yaml")


def test_default_is_massless_and_an_explicit_zero_changes_nothing(tmp_path, cdpr4):
    a = cdpr4.arrays
    assert (a.rho == 0).all() and (a.w == 0).all() and not cdpr4.heavy
    d = base()
    d["cable"]["linear_density_kg_m"] = 0
    r = load_robot(write(tmp_path, d))
    assert r.cables == cdpr4.cables and not r.heavy


def test_robot_default_per_cable_and_units(tmp_path):
    d = base()
    d["cable"]["linear_density_kg_m"] = "63.1 g/m"
    d["cables"][2]["cable"] = {"linear_density_kg_m": "0.1 kg/m"}
    r = load_robot(write(tmp_path, d))
    np.testing.assert_allclose(r.arrays.rho, [0.0631, 0.0631, 0.1, 0.0631], rtol=1e-15)
    np.testing.assert_allclose(r.arrays.w, r.arrays.rho * r.platform.g, rtol=1e-15)
    assert r.heavy and r.cables[2].material.E == r.cables[0].material.E  # the rest inherited


@pytest.mark.parametrize(
    "value, where, message",
    [
        (-0.06, "cable", "key 'cable.linear_density_kg_m': must be non-negative (kg/m), got -0.06"),
        (float("inf"), "cable", "key 'cable.linear_density_kg_m': must be finite"),
        (float("nan"), "cable", "key 'cable.linear_density_kg_m': must be finite"),
        (
            "63 g",
            "cable",
            "key 'cable.linear_density_kg_m': unit 'g' is not a unit of kg/m; allowed units: kg/m, g/m",
        ),
        (
            "0.06 kg",
            "cables[1]",
            "key 'cables[1].cable.linear_density_kg_m': unit 'kg' is not a unit of kg/m",
        ),
        ("heavy", "cable", "key 'cable.linear_density_kg_m': cannot read 'heavy' as a quantity"),
        ([0.06], "cable", "key 'cable.linear_density_kg_m'"),
    ],
)
def test_bad_linear_density_is_one_line_naming_the_key(tmp_path, value, where, message):
    d = base()
    if where == "cable":
        d["cable"]["linear_density_kg_m"] = value
    else:
        d["cables"][1]["cable"] = {"linear_density_kg_m": value}
    path = write(tmp_path, d)
    with pytest.raises(ConfigError) as exc:
        load_robot(path)
    text = str(exc.value)
    assert message in text and str(path) in text and "\n" not in text


def test_override_equals_editing_the_file(tmp_path):
    d = base()
    d["cables"][0]["cable"] = {"linear_density_kg_m": 0.2}
    edited = copy.deepcopy(d)
    edited["cable"]["linear_density_kg_m"] = 0.05
    edited["cables"][0]["cable"].pop("linear_density_kg_m")
    a = load_robot(write(tmp_path, edited, "edited.yaml"))
    b = load_robot(write(tmp_path, d), linear_density=0.05)
    assert a.cables == b.cables
    assert (b.arrays.rho == 0.05).all()


COMMANDS = [
    ["point", "--robot", R4, "--at", "0.5", "0.2", "2.5"],
    ["point", "--robot", R4, "--at", "0.5", "0.2", "2.5", "--redundancy", "physical"],
    ["compensate", "--robot", R4, "--at", "0.5", "0.2", "2.5"],
]


@pytest.mark.parametrize("args", COMMANDS)
def test_linear_density_zero_gives_byte_identical_output(capsys, args):
    assert main([*args, "--json"]) == 0
    plain = capsys.readouterr().out
    assert main([*args, "--json", "--linear-density", "0"]) == 0
    assert capsys.readouterr().out == plain
    json.loads(plain)


@pytest.mark.parametrize(
    "args, words",
    [
        (
            [
                "grid",
                "--robot",
                R4,
                "--box",
                "-1",
                "1",
                "-1",
                "1",
                "1",
                "2",
                "--n",
                "2",
                "--out",
                "x.parquet",
                "--interference",
            ],
            "physical mode only",
        ),
        (["point", "--robot", R4, "--at", "0.5", "0.2", "2.5"], "physical mode only"),
    ],
)
def test_heavy_cables_are_refused_in_one_line_where_not_modelled(capsys, args, words):
    """Paper mode asked for on heavy cables (left out, a heavy robot's default is physical mode:
    tests/cli/test_heavy_scans.py)."""
    assert main([*args, "--linear-density", "0.0631", "--redundancy", "paper"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and words in err


@pytest.mark.parametrize("command", ["point", "compensate", "grid", "plane", "trajectory"])
@pytest.mark.parametrize("value, words", [("-1", "'-1' must be >= 0"), ("inf", "is not a finite number")])
def test_every_command_with_E_takes_linear_density(capsys, command, value, words):
    with pytest.raises(SystemExit) as exc:
        main([command, "--robot", R4, "--linear-density", value, "--json"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "argument --linear-density" in err and words in err


def test_import_caspr_writes_the_given_linear_density(tmp_path, capsys):
    from tests.test_robot_import import files

    b, c = files(tmp_path)
    base_args = ["import", "caspr", "--bodies", str(b), "--cables", str(c)]
    assert main([*base_args, "--out", str(tmp_path / "d.yaml")]) == 0
    assert "linear_density" not in (tmp_path / "d.yaml").read_text()  # not given: massless, not written
    assert main([*base_args, "--linear-density", "0.0631", "--out", str(tmp_path / "g.yaml")]) == 0
    text = (tmp_path / "g.yaml").read_text()
    assert "cable.linear_density_kg_m = 0.0631 kg/m (given on the command line" in text
    assert (load_robot(tmp_path / "g.yaml").arrays.rho == 0.0631).all()


@pytest.mark.parametrize(
    "heavy_file, twin", [("cube50.yaml", "cube50_massless.yaml"), ("cogiro.yaml", "cogiro_massless.yaml")]
)
def test_massless_twin_differs_only_in_the_cable_weight(heavy_file, twin):
    """A shipped heavy robot and its w = 0 twin (the studies and tests of massless behaviour use
    the twin) are the same file but for name, description and the linear density."""
    heavy, light = (yaml.safe_load((ROBOTS / f).read_text()) for f in (heavy_file, twin))
    assert (
        heavy["cable"].pop("linear_density_kg_m") == 0.0631
        and light["cable"].pop("linear_density_kg_m") == 0.0
    )
    for d in (heavy, light):
        del d["name"], d["description"]
    assert heavy == light
    assert load_robot(ROBOTS / heavy_file).heavy and not load_robot(ROBOTS / twin).heavy
