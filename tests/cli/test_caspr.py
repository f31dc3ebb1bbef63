"""``cdpr import caspr`` (cdpr.cli.caspr, run by cdpr.cli.robot_files.cmd_import_caspr): CASPR's XML
files become a robot file that loads, with the options CASPR does not hold (E, diameter, dead
length) given on the command line or defaulted, and bad options refused in one line before a file
is written. The XML reading itself: tests/test_robot_import.py."""

import numpy as np
import pytest
import yaml

from cdpr.cli.main import main
from cdpr.robot import load_robot
from tests.test_robot_import import files


def test_command_line_writes_a_robot_file_that_loads(tmp_path, capsys):
    b, c = files(tmp_path)
    out = tmp_path / "robot.yaml"
    args = [
        "import",
        "caspr",
        "--bodies",
        str(b),
        "--cables",
        str(c),
        "--cable-set",
        "other",
        "--out",
        str(out),
    ]
    assert main(args) == 0
    assert "6 cables" in capsys.readouterr().out
    r = load_robot(out)
    assert r.m == 6 and not r.point_mass
    assert yaml.safe_load(out.read_text())["cables"][0]["pulley"]["axis"] == [0.0, 0.0, 1.0]


def test_what_caspr_does_not_hold_is_defaulted_or_given(tmp_path, capsys):
    b, c = files(tmp_path)
    base = ["import", "caspr", "--bodies", str(b), "--cables", str(c)]
    assert main([*base, "--out", str(tmp_path / "d.yaml")]) == 0
    d = load_robot(tmp_path / "d.yaml")
    assert (d.arrays.E == 102.2e9).all() and (d.d == 0.0).all()
    np.testing.assert_allclose(d.ES, 102.2e9 * np.pi * 0.004**2 / 4, rtol=1e-12)
    given = ["--E", "80e9", "--diameter", "0.006", "--dead-length", "1.5", "--out", str(tmp_path / "g.yaml")]
    assert main([*base, *given]) == 0
    g = load_robot(tmp_path / "g.yaml")
    assert (g.arrays.E == 80e9).all() and (g.d == 1.5).all()
    np.testing.assert_allclose(g.ES, 80e9 * np.pi * 0.006**2 / 4, rtol=1e-12)
    np.testing.assert_array_equal(g.A, d.A)  # the geometry is CASPR's either way
    header = (tmp_path / "g.yaml").read_text().splitlines()[0]
    assert (
        header.startswith("# Imported by `cdpr import caspr`")
        and "cable set main, the file's default" in header
    )


@pytest.mark.parametrize(
    "extra,words",
    [
        (["--out", "robot.txt"], "unknown output format '.txt'; allowed: .yaml, .yml"),
        (["--out", "r.yaml", "--dead-length", "-1"], "argument --dead-length: '-1' must be >= 0"),
        (["--out", "r.yaml", "--E", "0"], "argument --E: '0' must be > 0"),
        ([], "the following arguments are required: --out"),
    ],
)
def test_bad_options_are_one_line_and_write_nothing(tmp_path, capsys, monkeypatch, extra, words):
    monkeypatch.chdir(tmp_path)
    b, c = files(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    try:
        code = main(["import", "caspr", "--bodies", str(b), "--cables", str(c), *extra])
    except SystemExit as exc:  # argparse's refusals
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and words in err and err.count("\n") == 1, err
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_the_header_and_one_stderr_line_name_what_was_assumed(tmp_path, capsys):
    """Issue 41: nothing the XML does not hold is passed off as given: the file's header and one
    stderr line name E, the diameter and the dead length (assumed, or given on the command line); the
    description names the files without the importing machine's folders; --name names the robot."""
    b, c = files(tmp_path)
    out = tmp_path / "robot.yaml"
    args = ["import", "caspr", "--bodies", str(b), "--cables", str(c), "--out", str(out)]
    assert main([*args, "--diameter", "0.006"]) == 0
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if line.startswith("cdpr: note: not from the CASPR files:")]
    assert len(notes) == 1, err
    text = out.read_text()
    header = "\n".join(line for line in text.splitlines() if line.startswith("#"))
    for where in (notes[0], header):
        assert "cable.young_modulus_Pa = 1.022e+11 Pa (assumed" in where
        assert "dead_length_m = 0 m (assumed" in where
        assert "cable.diameter_m = 0.006 m (given on the command line" in where
    assert str(tmp_path) not in text
    data = yaml.safe_load(text)
    assert data["name"] == "X" and data["cables"][0]["cable"]["min_tension_N"] == 10.0
    assert main([*args, "--name", "my robot"]) == 0
    assert load_robot(out).name == "my robot"
