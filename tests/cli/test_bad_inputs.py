"""Bad and edge inputs, as a new user meets them: each row is a command and what must come out
(exit code and a fragment of the one-line message). No traceback, no silent NaN, no work first."""

import json
import subprocess
import sys

import pandas as pd
import pytest
import yaml

from cdpr import table_io
from cdpr.cli.main import main
from cdpr.errors import ConfigError
from cdpr.pipeline.study import load_study
from tests.conftest import ROBOTS, ROOT

R4 = str(ROBOTS / "cdpr4.yaml")
QUICK = ROOT / "config" / "studies" / "quick.yaml"


def run(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse
        code = exc.code
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def files(tmp_path):
    """Helper files some rows refer to as {name}."""
    f = {}
    robot = yaml.safe_load(open(R4))
    robot["frame"] = {"floor_z_m": "2 kg"}
    contents = {
        "floor.yaml": yaml.safe_dump(robot),
        "bad.yaml": "cables: [\n",
        "box.json": "{not json",
        "box2.json": '{"other": 1}',
        "w1.yaml": "l_E1E2_m: 100\n",
        "w2.yaml": "alpha_E1_rad: -1e9\n",
        "p.csv": "x,y,z\n0,0,2\nnan,0,2\n",
        "p2.csv": "x,y,z\n0,0,2\n0.5,0.2,2.5\n",
        "p3.csv": "a,b\n1,2\n",
        "p4.csv": "x,y,z,rx,ry,rz\n0,0,2,abc,0,0\n",
        "p5.csv": "x,y,z\n",
        "p6.csv": "x,y,z,x\n0,0,2,1\n",
        "p7.csv": "x,y,z\n0,0,2\n1e300,0,2\n",
    }
    names = {
        "floor": "floor.yaml",
        "malformed": "bad.yaml",
        "box_bad": "box.json",
        "box_nokey": "box2.json",
        "winch_long": "w1.yaml",
        "winch_alpha": "w2.yaml",
        "pts_nan": "p.csv",
        "pts": "p2.csv",
        "pts_cols": "p3.csv",
        "pts_rot_text": "p4.csv",
        "pts_no_rows": "p5.csv",
        "pts_twice": "p6.csv",
        "pts_far": "p7.csv",
    }
    for key, name in names.items():
        f[key] = tmp_path / name
        f[key].write_text(contents[name])
    f["out"] = tmp_path / "out.parquet"
    f["missing"] = tmp_path / "nope.yaml"
    # parquet tables: a column of text, and no rows
    f["pts_text_pq"] = tmp_path / "text.parquet"
    table_io.write_table(pd.DataFrame({"x": [0.0], "y": ["a"], "z": [2.0]}), f["pts_text_pq"])
    f["pts_empty_pq"] = tmp_path / "empty.parquet"
    table_io.write_table(pd.DataFrame({"x": [], "y": [], "z": []}, dtype=float), f["pts_empty_pq"])
    return {k: str(v) for k, v in f.items()}


CASES = [  # (argv with {file} placeholders, exit code, fragment of stderr)
    ("point --robot {R4} --at nan 0 2", 2, "not a finite number"),
    ("point --robot {R4} --at inf 0 2", 2, "not a finite number"),
    ("inverse --robot {R4} --at nan 0 2", 2, "not a finite number"),
    ("point --robot {R4} --at 0 0 abc", 2, "is not a number"),
    ("point --robot {R4} --at -1e-1 0 2.5", 0, ""),
    ("point --robot {R4} --E -1e9 --at 0 0 2", 2, "must be > 0"),
    ("point --robot {R4} --E 0 --at 0 0 2", 2, "must be > 0"),
    ("point --robot {R4} --mass -3 --at 0 0 2", 2, "must be > 0"),
    ("point --robot {R4} --h -0.1 --at 0 0 2", 2, "must be >= 0"),
    ("point --robot {R4} --pulley triple --at 0 0 2", 2, "invalid choice"),
    ("point --robot {R4} --pulley SR --h 0.05 --rp 0.05 --at 0 0 2", 0, ""),
    (
        "point --robot {R4} --pulley DR --h 0.05 --rp 0.05 --at 0 0 2",
        2,
        "DR pulley needs lever arm h_m > sheave radius",
    ),
    (
        "point --robot {R4} --pulley SR --h 0.04 --rp 0.05 --at 0 0 2",
        2,
        "SR pulley needs lever arm h_m >= sheave radius",
    ),
    (
        "point --robot {R4} --engine compiled --method fixed_point --at 0 0 2",
        2,
        "has no 'fixed_point' solver",
    ),
    ("point --robot {missing} --at 0 0 2", 2, "cannot read the file"),
    ("point --robot {malformed} --at 0 0 2", 2, "not valid YAML"),
    ("point --robot {floor} --at 0 0 2", 2, "'frame.floor_z_m'"),
    ("point --robot {R4} --points {pts}", 2, "--points needs --out"),
    ("point --robot {R4} --points {pts_nan} --out {out}", 2, "non-finite coordinate"),
    ("point --robot {R4} --points {pts_cols} --out {out}", 2, "missing column(s) x, y, z"),
    ("point --robot {R4} --points {missing}.csv --out {out}", 2, "does not exist"),
    ("point --robot {R4} --points {pts} --out {out}", 0, ""),
    ("point --robot {R4} --points {pts_rot_text} --out {out}", 2, "row 1, column rx: 'abc' is not a number"),
    ("inverse --robot {R4} --points {pts_text_pq} --out {out}", 2, "column y holds"),
    ("point --robot {R4} --points {pts_no_rows} --out {out}", 2, "the table has no rows"),
    ("compensate --robot {R4} --points {pts_empty_pq} --out {out}", 2, "the table has no rows"),
    ("point --robot {R4} --points {pts_twice} --out {out}", 2, "column x appears 2 times"),
    ("inverse --robot {R4} --points {pts_far} --out {out}", 2, "row 2 has a coordinate beyond"),
    ("inverse --robot {R4} --at 1e300 0 2", 2, "is beyond ±1e+06 m"),
    ("view --robot {R4} --at 0 1e7 2 --out {out}.png", 2, "is beyond ±1e+06 m"),
    ("inverse --robot {R4} --points {pts} --out {out}", 0, ""),
    ("point --robot {R4} --at 0 0 2 --threads 0", 2, "outside the allowed range"),
    ("point --robot {R4} --at 0 0 2 --threads 1000", 2, "outside the allowed range"),
    ("grid --robot {R4} --frame --n 100000 --out {out}", 2, "GiB of memory"),
    ("grid --robot {R4} --frame --n 0 --out {out}", 2, "outside the allowed range"),
    ("grid --robot {R4} --frame --n 2 --out /proc/cdpr/x.parquet", 2, "cannot"),
    ("grid --robot {R4} --frame --n 2 --out {out}.txt", 2, "unknown output format"),
    ("grid --robot {R4} --box-file {missing}.json --n 2 --out {out}", 2, "does not exist"),
    ("grid --robot {R4} --box-file {box_bad} --n 2 --out {out}", 2, "six numbers"),
    ("grid --robot {R4} --box-file {box_nokey} --n 2 --out {out}", 2, "six numbers"),
    ("grid --robot {R4} --box 1 0 0 1 0 1 --n 2 --out {out}", 2, "XMIN < XMAX"),
    ("grid --robot {R4} --box 0 1 0 1 0 nan --n 2 --out {out}", 2, "not a finite number"),
    ("grid --robot {R4} --frame --n 2 --shard 3 --shards 2 --out {out}", 2, "0 <= shard < shards"),
    ("grid --robot {R4} --n 2 --out {out}", 2, "give the grid box"),
    ("plane --robot {R4} --z 6 --n 5 --out {out}", 2, "lowest pulley"),
    ("plane --robot {R4} --z -1 --n 5 --out {out}", 2, "lowest pulley"),
    ("trajectory --robot {R4} --start 0 0 0 --end 0 0 nan --n 5 --out {out}", 2, "not a finite number"),
    ("winch --lpm-to 1000", 2, "leaves [0, q_max"),
    ("winch --lpm-from nan", 2, "not a finite number"),
    ("winch --lpm-from 3 --lpm-to 1", 2, "below --lpm-to"),
    ("winch --steps 1e8", 2, "is not an integer"),
    ("winch --steps 100000000", 2, "outside the allowed range"),
    ("winch --steps 1", 2, "outside the allowed range"),
    ("winch --params {winch_long}", 2, "l_pm0"),
    ("winch --params {winch_alpha}", 2, "lies in [0, pi]"),
    ("winch --params {missing}", 2, "cannot read the file"),
    ("winch --out {out}.txt", 2, "unknown output format"),
    ("job volumes --study {QUICK}", 2, "needs --tables"),
    ("job volumes --study {missing} --tables x", 2, "cannot read the file"),
    (
        "plane --robot {R4} --z 2.5 --n 3 --out {out} --redundancy physical --method fixed_point",
        2,
        "one solver",
    ),
    (
        "trajectory --robot {R4} --start 0 0 1 --end 0 0 2 --n 3 --out {out} --redundancy magic",
        2,
        "invalid choice",
    ),
    (
        "job comparison --study {QUICK} --comparison {missing} --tables x --table t.csv --figure f.png --markdown m.md",
        2,
        "cannot read the file",
    ),
    (
        "job budget-design --study {QUICK} --comparison {missing} --label CDPR4_SR --box-file x --table t.csv",
        2,
        "needs --path-table",
    ),
]


@pytest.mark.parametrize("argv,code,fragment", CASES, ids=[c[0][:60] for c in CASES])
def test_bad_input_table(tmp_path, capsys, argv, code, fragment):
    f = files(tmp_path)
    args = argv.format(R4=R4, QUICK=QUICK, **f).split()
    got, out, err = run(args, capsys)
    assert got == code, (argv, err)
    if code:
        assert fragment in err, (argv, err)
        assert (
            err.startswith("cdpr: error:") and len(err.strip().splitlines()) == 1 and "Traceback" not in err
        )


@pytest.mark.parametrize("json_out", [False, True])
def test_compensate_at_a_point_with_no_tension_distribution_is_flagged(capsys, json_out):
    """CDPR4 at a point outside its anchors' hull (and at the centre with a 200 N ceiling): no
    tension distribution exists, so nothing is solved; the point is reported ``infeasible``, exit 0,
    not a traceback from a solve of zero points."""
    for at, extra in ((["3", "0", "2"], []), (["0", "0", "2"], ["--t-max", "200"])):
        argv = ["compensate", "--robot", R4, "--at", *at, *extra] + (["--json"] if json_out else [])
        code, out, err = run(argv, capsys)
        assert code == 0 and err == ""
        if json_out:
            got = json.loads(out)
            assert got["status"] == "infeasible" and got["dp_norm"] is None and got["lengths"] == [None] * 4
        else:
            assert out.splitlines()[-1].startswith("status: infeasible (no tension distribution")


def test_broken_pipe_ends_quietly():
    p = subprocess.run(
        f"{sys.executable} -m cdpr winch --steps 100000 | head -1", shell=True, capture_output=True, text=True
    )
    assert p.returncode == 0 and "Traceback" not in p.stderr and p.stdout.startswith("winch")


def test_truncated_parquet_names_the_file(tmp_path):
    from cdpr.errors import CdprError

    bad = tmp_path / "shard.parquet"
    bad.write_bytes(b"PAR1" + b"\0" * 20)
    with pytest.raises(CdprError, match="shard.parquet.*delete it"):
        table_io.read_table(bad)


STUDY_CASES = [  # (edit of the quick study's text, key named in the message)
    ("SR: {kind: SR, h_m: 0.100, r_p_m: 0.0665}", "SR: {kind: SR, h_m: 0.05, r_p_m: 0.0665}", "pulleys.SR"),
    ("DR: {kind: DR, h_m: 0.100, r_p_m: 0.0665}", "DR: {kind: DR, h_m: 0.0665, r_p_m: 0.0665}", "pulleys.DR"),
    ("h_m: [0.100, 0.150]", "h_m: [0.050, 0.150]", "doe.levels"),
    ("E_Pa: {from: 67.2e+9", "E_Pa: {from: 0.0", "elasticity.E_Pa.from"),
    ("h_m: {from: 0.050, to: 0.150, step: 0.050}", "h_m: {from: 0.150, to: 0.050, step: 0.050}", "maps.h_m"),
    ("paper_rw_c_m: [-2.32, 2.32,", "paper_rw_c_m: [2.32, -2.32,", "doe.paper_rw_c_m"),
    ("z_m: 2.5", "z_m: 5.5", "plane.z_m"),
    ("lpm_to_m: 5.0", "lpm_to_m: .nan", "winch.lpm_to_m"),
    ("CDPR4: config/robots/cdpr4.yaml", "CDPR4: config/robots/none.yaml", "robots.CDPR4"),
    ("solver: newton", "solver: magic", "solver"),
    ("sweep_m: {from: 0.0, to: 0.30", "sweep_m: {from: 0.30, to: 0.0", "volumes.sweep_m"),
    ("robot: CDPR4", "robot: CDPR9", "doe.robot"),
    ("redundancy: paper ", "redundancy: magic ", "redundancy"),
    (
        "solver: newton                # newton | fixed_point\nredundancy: paper ",
        "solver: fixed_point\nredundancy: physical ",
        "solver",
    ),
]


@pytest.mark.parametrize("old,new,key", STUDY_CASES, ids=[c[2] for c in STUDY_CASES])
def test_bad_study_values_name_file_and_key(tmp_path, monkeypatch, old, new, key):
    monkeypatch.chdir(ROOT)  # robot paths in studies are relative to the repository
    text = QUICK.read_text()
    assert old in text
    bad = tmp_path / "study.yaml"
    bad.write_text(text.replace(old, new, 1))
    with pytest.raises(ConfigError) as exc:
        load_study(bad)
    assert str(exc.value).startswith(f"{bad}: key '{key}") and len(str(exc.value).splitlines()) == 1, str(
        exc.value
    )


def test_missing_and_malformed_study_files(tmp_path):
    with pytest.raises(ConfigError, match="cannot read the file"):
        load_study(tmp_path / "none.yaml")
    (tmp_path / "m.yaml").write_text("robots: [\n")
    with pytest.raises(ConfigError, match="not valid YAML"):
        load_study(tmp_path / "m.yaml")
