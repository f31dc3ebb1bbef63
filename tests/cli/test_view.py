"""``cdpr view`` (cdpr.cli.view, drawn by cdpr.pipeline.plots.robot.robot_view) on a point-mass and a
spatial robot, with a box, and on heavy cables; a bad box is refused in one line."""

import numpy as np
import pytest
import yaml

from cdpr.analyses import scans
from cdpr.cli.main import main
from cdpr.models.interference import interference
from cdpr.robot import load_robot
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


def test_view_of_a_heavy_rigid_platform(tmp_path, capsys):
    """A rigid platform on heavy cables (CoGiRo at 0.0631 kg/m) is drawn with its catenaries, and
    its interfering cables (1 and 7 at this turned pose near the frame's edge) are those of
    ``interference`` under the drawn distribution's rest lengths (the view failed: heavy cables'
    interference needs their rest lengths)."""
    data = yaml.safe_load((ROBOTS / "cogiro.yaml").read_text())
    data["cable"]["linear_density_kg_m"] = 0.0631
    path = tmp_path / "heavy.yaml"
    path.write_text(yaml.safe_dump(data))
    out = tmp_path / "heavy.png"
    args = ["view", "--robot", str(path), "--at", "5.5", "0", "4.2", "--rotvec", "0", "0", "0.6"]
    assert main(args + ["--out", str(out)]) == 0, capsys.readouterr().err
    assert out.read_bytes()[:8] == PNG
    robot = load_robot(path)
    geom = scans.pose_geometry(robot, [5.5, 0.0, 4.2], [0.0, 0.0, 0.6])
    assert np.isfinite(geom["catenary_L0"]).all() and (geom["catenary_sag"] > 0).all()
    res = interference(robot, [[5.5, 0.0, 4.2]], [[0.0, 0.0, 0.6]], L0=geom["catenary_L0"])
    want = res.cp[0].copy()
    for q in np.flatnonzero(res.cc[0]):
        want[res.pairs[q]] = True
    np.testing.assert_array_equal(geom["interfering"], want)
    assert np.flatnonzero(want).tolist() == [0, 6]
