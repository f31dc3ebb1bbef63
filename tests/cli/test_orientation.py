"""Issue 41: ``--euler-xyz-deg A B C`` beside ``--rotvec`` on every command that takes an orientation:
CASPR's Euler XYZ convention (intrinsic, R = Rx(A) Ry(B) Rz(C), ``SphericalEulerXYZ`` of CASPR's
joints), mutually exclusive with --rotvec, and the same results as the equivalent rotation vector."""

import argparse
import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from cdpr.cli.main import main
from cdpr.cli.parser import build_parser
from tests.conftest import ROBOTS

COGIRO = str(ROBOTS / "cogiro.yaml")
R4 = str(ROBOTS / "cdpr4.yaml")
ANGLES = ["5", "-10", "15"]


def _rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rotvec_of(angles_deg):
    return [
        float(x) for x in Rotation.from_euler("XYZ", [float(a) for a in angles_deg], degrees=True).as_rotvec()
    ]


def test_the_convention_is_caspr_intrinsic_xyz():
    """CASPR's R_pe = R_x(alpha) R_y(beta) R_z(gamma) (each an active rotation about its axis): the
    rotation vector used is exactly it, and not the extrinsic product R_z R_y R_x."""
    a, b, c = np.radians([float(x) for x in ANGLES])
    R = Rotation.from_rotvec(rotvec_of(ANGLES)).as_matrix()
    np.testing.assert_allclose(R, _rx(a) @ _ry(b) @ _rz(c), atol=1e-15)
    assert np.abs(R - _rz(c) @ _ry(b) @ _rx(a)).max() > 1e-3


def _leaves(parser):
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield parser
        return
    for sp in subs[0].choices.values():
        yield from _leaves(sp)


def test_every_command_with_rotvec_takes_euler_xyz_deg_and_not_both():
    with_rotvec = [
        p for p in _leaves(build_parser()) if any("--rotvec" in a.option_strings for a in p._actions)
    ]
    assert {p.prog.split()[1] for p in with_rotvec} >= {
        "inverse",
        "point",
        "compensate",
        "grid",
        "plane",
        "trajectory",
        "view",
    }
    for p in with_rotvec:
        assert any("--euler-xyz-deg" in a.option_strings for a in p._actions), p.prog
    with pytest.raises(SystemExit) as exc:
        main(
            [
                "point",
                "--robot",
                COGIRO,
                "--at",
                "0",
                "0",
                "2",
                "--rotvec",
                "0",
                "0",
                "0",
                "--euler-xyz-deg",
                *ANGLES,
            ]
        )
    assert exc.value.code == 2


@pytest.mark.parametrize(
    "argv",
    [
        ["inverse", "--robot", COGIRO, "--at", "0.3", "0.2", "2"],
        ["point", "--robot", COGIRO, "--at", "0.3", "0.2", "2", "--redundancy", "physical"],
        ["point", "--robot", R4, "--at", "0.3", "0.2", "2"],
        ["compensate", "--robot", COGIRO, "--at", "0.3", "0.2", "2"],
    ],
)
def test_euler_angles_give_what_the_equivalent_rotvec_gives(capsys, argv):
    assert main([*argv, "--euler-xyz-deg", *ANGLES, "--json"]) == 0
    euler = json.loads(capsys.readouterr().out)
    rv = [repr(x) for x in rotvec_of(ANGLES)]
    assert main([*argv, "--rotvec", *rv, "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == euler


def test_euler_angles_in_a_trajectory_table(tmp_path, capsys):
    base = ["trajectory", "--robot", COGIRO, "--start", "0", "0", "1.5", "--end", "0.5", "0", "2", "--n", "3"]
    base += ["--redundancy", "physical", "--engine", "numpy"]
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    assert main([*base, "--euler-xyz-deg", *ANGLES, "--out", str(a)]) == 0
    assert main([*base, "--rotvec", *[repr(x) for x in rotvec_of(ANGLES)], "--out", str(b)]) == 0
    assert a.read_bytes() == b.read_bytes()
