"""The command-line cases of the trust issue's second round, each a row: command -> exit code ->
fragment of the one-line message (or of the output). Points below a suspended robot's floor are
inaccessible by one rule in every command and engine; a full disk ends in one line, exit 1."""

import json
import subprocess
import sys

import numpy as np
import pytest

from cdpr.cli.main import main
from cdpr.robot import load_robot
from cdpr.solve import solve
from cdpr.tables import solve_table
from tests.conftest import ROBOTS, ROOT

R4 = str(ROBOTS / "cdpr4.yaml")


def run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse
        code = exc.code
    cap = capsys.readouterr()
    return code, cap.out, cap.err


TABLES = {
    "wide.csv": "x,y,z\n0,0,2.5,9\n",
    "short.csv": "x,y,z\n0,0\n",
    "comma.csv": 'x,y,z\n"0,5",0,2.5\n',
    "underscore.csv": "x,y,z\n1_0,0,2.5\n",
    "word.csv": "x,y,z\nzero,0,2.5\n",
}

ROWS = [
    (["point", "--robot", R4, "--at", "1_0", "0", "2.5"], 2, "'1_0' is not a number"),
    (["point", "--robot", R4, "--at", "0,5", "0", "2.5"], 2, "use a decimal point"),
    (["inverse", "--robot", R4, "--at", "0x10", "0", "2.5"], 2, "'0x10' is not a number"),
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
            "0",
            "1",
            "--frame",
            "--n",
            "3",
            "--out",
            "{tmp}/g.parquet",
        ],
        2,
        "--frame: not allowed with argument --box",
    ),
    (
        [
            "grid",
            "--robot",
            R4,
            "--box-file",
            "{tmp}/b.json",
            "--frame",
            "--n",
            "3",
            "--out",
            "{tmp}/g.parquet",
        ],
        2,
        "not allowed with argument --box-file",
    ),
    (
        ["point", "--robot", R4, "--points", "{tmp}/wide.csv", "--out", "{tmp}/o.csv"],
        2,
        "row 1 has 4 fields, the header has 3",
    ),
    (
        ["point", "--robot", R4, "--points", "{tmp}/short.csv", "--out", "{tmp}/o.csv"],
        2,
        "row 1 has 2 fields, the header has 3",
    ),
    (
        ["point", "--robot", R4, "--points", "{tmp}/comma.csv", "--out", "{tmp}/o.csv"],
        2,
        "row 1, column x: '0,5' is not a number (use a decimal point",
    ),
    (
        ["inverse", "--robot", R4, "--points", "{tmp}/underscore.csv", "--out", "{tmp}/o.csv"],
        2,
        "row 1, column x: '1_0' is not a number",
    ),
    (
        ["compensate", "--robot", R4, "--points", "{tmp}/word.csv", "--out", "{tmp}/o.csv"],
        2,
        "row 1, column x: 'zero' is not a number",
    ),
]


@pytest.mark.parametrize(
    "argv, code, fragment", ROWS, ids=lambda x: " ".join(x)[:60] if isinstance(x, list) else None
)
def test_bad_command_lines(tmp_path, capsys, argv, code, fragment):
    for name, text in TABLES.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    got, out, err = run(argv, capsys)
    assert got == code, err
    assert err.startswith("cdpr: error: ") and err.count("\n") == 1, err
    assert fragment in err, err
    assert not (tmp_path / "o.csv").exists() and not (tmp_path / "g.parquet").exists()


@pytest.mark.parametrize("redundancy", ["paper", "physical"])
@pytest.mark.parametrize("engine", ["compiled", "numpy"])
def test_below_the_floor_is_inaccessible_everywhere(redundancy, engine):
    """(0, 0, -3) on CDPR4, 3 m under the floor: the cable model has an equilibrium there, but the
    point cannot be reached: inaccessible in both modes, both engines, tables and arrays alike; the
    points above the floor keep their status."""
    robot = load_robot(R4)
    P = np.array([[0.0, 0.0, -3.0], [0.0, 0.0, 2.5], [0.5, 0.2, -1e-6]])
    res = solve(robot, P, engine=engine, redundancy=redundancy)
    assert list(res["status"]) == ["inaccessible", "ok", "inaccessible"]
    df = solve_table(robot, P, engine=engine, redundancy=redundancy)
    assert list(df.status) == ["inaccessible", "ok", "inaccessible"]


@pytest.mark.parametrize("redundancy", ["paper", "physical"])
def test_point_command_below_the_floor(capsys, redundancy):
    code, out, err = run(
        ["point", "--robot", R4, "--at", "0", "0", "-3", "--redundancy", redundancy, "--json"], capsys
    )
    assert code == 0, err
    assert json.loads(out)["status"] == "inaccessible"


@pytest.mark.parametrize(
    "argv",
    [
        ["winch", "--json"],
        ["inverse", "--robot", R4, "--at", "0", "0", "2", "--json"],
        ["point", "--robot", R4, "--at", "0", "0", "2"],
    ],
)
def test_full_disk_is_one_line(argv):
    with open("/dev/full", "w") as full:
        p = subprocess.run(
            [sys.executable, "-m", "cdpr", *argv], stdout=full, stderr=subprocess.PIPE, cwd=ROOT
        )
    err = p.stderr.decode()
    assert p.returncode == 1, err
    assert err.count("\n") == 1 and "No space left on device" in err and "Traceback" not in err, err


def test_closed_pipe_ends_quietly():
    p = subprocess.run(
        f"{sys.executable} -m cdpr winch --steps 100000 | head -n 1",
        shell=True,
        capture_output=True,
        cwd=ROOT,
    )
    assert p.returncode == 0 and p.stderr == b"", p.stderr


def test_a_renamed_robot_is_one_report(tmp_path):
    """Renaming a robot in `robots:` only: every key that still names the old robot is listed in
    one error (it took one run per key before)."""
    import re

    from cdpr.errors import ConfigError
    from cdpr.pipeline.study import load_study

    text = (ROOT / "config" / "studies" / "quick.yaml").read_text(encoding="utf-8")
    p = tmp_path / "renamed.yaml"
    p.write_text(re.sub(r"^(\s*)CDPR4:", r"\1ROBOT4:", text, count=1, flags=re.M), encoding="utf-8")
    with pytest.raises(ConfigError) as err:
        load_study(p)
    msg = str(err.value)
    assert "2 problems" in msg and "\n" not in msg, msg
    assert "key 'doe.robot': unknown robot 'CDPR4'; allowed: CDPR3, ROBOT4" in msg
    assert "key 'trajectories.paths.CDPR4': unknown robot" in msg


def test_several_physical_mistakes_in_a_robot_file_are_one_report(tmp_path, capsys):
    import yaml

    robot = yaml.safe_load((ROBOTS / "cdpr4.yaml").read_text(encoding="utf-8"))
    robot["platform"]["mass_kg"] = -3
    robot["cables"][1]["pulley"] = {"kind": "SR", "h_m": 0.01, "r_p_m": 0.05}
    robot["cables"][2]["dead_length_m"] = -1
    p = tmp_path / "r.yaml"
    p.write_text(yaml.safe_dump(robot), encoding="utf-8")
    code, out, err = run(["point", "--robot", str(p), "--at", "0", "0", "2.5"], capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert "3 problems" in err
    for key in ("platform.mass_kg", "cables[1].pulley", "cables[2].dead_length_m"):
        assert f"key '{key}'" in err, err
