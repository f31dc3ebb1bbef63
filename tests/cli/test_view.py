"""``cdpr view`` (cdpr.cli.view, drawn by cdpr.pipeline.plots.robot.robot_view) on a point-mass and a
spatial robot, with a box; a bad box is refused in one line."""

import pytest

from cdpr.cli.main import main
from tests.conftest import ROBOTS

PNG = b"\x89PNG\r\n\x1a\n"


def test_view_of_a_point_mass_robot_at_its_default_position(tmp_path, capsys):
    out = tmp_path / "cdpr4.png"
    assert main(["view", "--robot", str(ROBOTS / "cdpr4.yaml"), "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == PNG and out.with_suffix(".pdf").read_bytes()[:4] == b"%PDF"
    assert f"wrote {out}" in capsys.readouterr().out


def test_view_of_a_spatial_robot_with_a_box(tmp_path):
    plain, boxed = tmp_path / "plain.png", tmp_path / "boxed.png"
    base = [
        "view",
        "--robot",
        str(ROBOTS / "cogiro.yaml"),
        "--at",
        "1",
        "0.5",
        "2",
        "--rotvec",
        "0",
        "0",
        "0.3",
    ]
    assert main(base + ["--out", str(plain)]) == 0
    assert main(base + ["--box", "-3", "3", "-2", "2", "0.5", "3.5", "--out", str(boxed)]) == 0
    assert boxed.read_bytes()[:8] == PNG and boxed.read_bytes() != plain.read_bytes()  # the box is drawn


def test_a_bad_box_is_refused_in_one_line(tmp_path, capsys):
    args = ["view", "--robot", str(ROBOTS / "cogiro.yaml"), "--box", "3", "-3", "-2", "2", "0.5", "3.5"]
    with pytest.raises(SystemExit) as exc:  # the parser refuses it, before the robot is read
        main(args + ["--out", str(tmp_path / "r.png")])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith("cdpr: error: view: argument --box:") and "XMIN < XMAX" in err
    assert not (tmp_path / "r.png").exists()
