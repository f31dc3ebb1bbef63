"""Issue 41: every single-pose ``--json`` object carries ``status``, and every computed result exits
with code 0 whatever its status, so scripts read ``status``, not the exit code (said in ``cdpr
--help``, in the help of the commands that report a status and in docs/cli.md)."""

import json

import pytest

from cdpr.cli.main import main
from cdpr.cli.parser import STATUS_EPILOG, build_parser
from tests.conftest import ROBOTS, ROOT

R4 = str(ROBOTS / "cdpr4.yaml")
HANG = str(ROBOTS / "hang4_6dof.yaml")
COGIRO = str(ROBOTS / "cogiro.yaml")


@pytest.mark.parametrize(
    "argv,status",
    [
        (["point", "--robot", R4, "--at", "0.5", "0.2", "2.5"], "ok"),
        (["point", "--robot", R4, "--at", "0", "0", "-1"], "inaccessible"),
        (["point", "--robot", R4, "--at", "0", "0", "2", "--redundancy", "physical"], "ok"),
        (["point", "--robot", HANG, "--at", "0", "0", "2", "--redundancy", "physical"], "ok"),
        (["point", "--robot", R4, "--at", "0.5", "0.2", "2.5", "--sensitivities"], "ok"),
        (["compensate", "--robot", R4, "--at", "0", "0", "2"], "ok"),
        (["compensate", "--robot", R4, "--at", "0", "0", "2", "--t-min", "5000"], "infeasible"),
        (["compensate", "--robot", COGIRO, "--at", "0", "0", "2"], "ok"),
        (["compensate", "--robot", COGIRO, "--at", "0", "0", "2", "--t-min", "5000"], "infeasible"),
        (["interference", "--robot", COGIRO, "--at", "0", "0", "2"], "ok"),
        (["interference", "--robot", R4, "--at", "0", "0", "2"], "ok"),
        (["interference", "--robot", COGIRO, "--at", "0", "0", "2", "--linear-density", "0.0631"], "ok"),
    ],
)
def test_single_pose_json_has_status_and_exit_code_0(capsys, argv, status):
    assert main([*argv, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["status"] == status


def test_help_and_docs_say_scripts_read_status():
    assert "scripts read the 'status' key of --json, not the exit code" in STATUS_EPILOG
    top = build_parser(jobs=False)
    assert STATUS_EPILOG.split(":")[0] in " ".join(top.format_help().split())
    sub = next(a for a in top._actions if a.__class__.__name__ == "_SubParsersAction")
    for cmd in ("point", "compensate"):
        assert "not the exit code" in " ".join(sub.choices[cmd].format_help().split())
    page = " ".join((ROOT / "docs" / "cli.md").read_text().split())
    assert "scripts read the `status` key of `--json`, not the exit code" in page


def test_a_zero_length_cable_is_flagged_with_a_reason_and_no_numpy_warning(capsys):
    """Issue 41: the platform's attachment at its anchor with no dead length gives a cable of zero
    rest length; physical mode has no stiffness ES/L0 there. No numpy RuntimeWarning reaches the user
    (any warning is an error here) and the point carries a reason; it is not ok."""
    import warnings

    argv = ["point", "--robot", HANG, "--pulley", "fixed", "--dead-length", "0", "--at", "-2.3", "-2.3", "5"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main([*argv, "--redundancy", "physical", "--json"]) == 0
    cap = capsys.readouterr()
    out = json.loads(cap.out)
    assert cap.err == "" and out["status"] != "ok"
    assert out["reason"].startswith("cable 1 has zero rest length") and out["unique"] is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main([*argv, "--redundancy", "physical"]) == 0
    cap = capsys.readouterr()
    assert "reason         : cable 1 has zero rest length" in cap.out and "not unique" not in cap.out
    assert cap.err == ""


def test_a_table_with_no_ok_point_says_so_in_words(tmp_path, capsys):
    """Issue 41 'no nan': the summary line of a --points command whose points are all not ok said
    '|dp| over ok points: min nan m, max nan m'; it says there is none (JSON: null)."""
    points = tmp_path / "below.csv"
    points.write_text("x,y,z\n0,0,-1\n0.5,0,-2\n")  # below CDPR4's floor: inaccessible
    argv = ["point", "--robot", R4, "--points", str(points), "--out", str(tmp_path / "o.csv")]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "status: inaccessible 2; |dp| over ok points: none (no point is ok)" in out and "nan" not in out
    assert main([*argv, "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["status"] == {"inaccessible": 2} and got["dp_min"] is None and got["dp_max"] is None
