"""The winch in the chain: drum angles <-> rest lengths (Métillon 2022 on each cable)."""

import json

import numpy as np
import pytest

from cdpr.cli.main import main
from cdpr.errors import CdprError
from cdpr.models import drive, winch
from cdpr.robot import TABLE1, load_robot, with_pulleys
from tests.conftest import ROBOTS

RW = str(ROBOTS / "cdpr4_winch.yaml")


def test_round_trip_q_to_lengths_to_q():
    r = load_robot(RW)
    rng = np.random.default_rng(1)
    q = rng.uniform(60.0, 120.0, (50, r.m))
    L0 = drive.rest_lengths_from_angles(r, q)
    q_back, q_nw = drive.drum_angles(r, L0)
    np.testing.assert_allclose(q_back, q, atol=1e-9)
    # the model that neglects the winch is exact at q0 only; elsewhere it differs by dl / k_w (eq. 31)
    p = TABLE1
    np.testing.assert_allclose((q_back - q_nw) * p.k_w, winch.length_error(p, L0 - r.d), atol=1e-12)
    at_q0 = drive.rest_lengths_from_angles(r, np.full((1, r.m), p.q0))
    np.testing.assert_allclose(
        drive.rest_lengths_from_angles(r, np.full((1, r.m), p.q0), model="no_winch"), at_q0, atol=1e-12
    )


def test_no_winch_is_an_error(cdpr4):
    with pytest.raises(CdprError, match="no winch"):
        drive.drum_angles(cdpr4, np.ones((1, 4)))


def run(capsys, *args):
    assert main(list(args) + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_commanding_drum_angles_includes_the_winch_error(capsys):
    at = ["--at", "0.5", "0.2", "2.5"]
    comp = run(capsys, "compensate", "--robot", RW, *at)
    assert len(comp["q"]) == len(comp["q_no_winch"]) == 4
    exact = run(capsys, "point", "--robot", RW, *at, "--redundancy", "physical", "--q", *map(str, comp["q"]))
    assert exact["dp_norm"] < 1e-9
    naive = run(
        capsys, "point", "--robot", RW, *at, "--redundancy", "physical", "--q", *map(str, comp["q_no_winch"])
    )
    assert 1e-4 < naive["dp_norm"] < 5e-3  # the drum's exit point moves by less than l_E1E2 = 60 mm


def test_realised_rest_lengths_are_the_drum_angle_q_nw_paid_out_by_the_true_drum():
    """realised_rest_lengths = rest_lengths_from_angles(drum_angles(...)[1]) (the independent route:
    the no-winch controller's angle, then the drum's true geometry); L0 - L_cmd equals eq. (31)'s
    δl to first order (the difference is δl l_AE'/k_w, below 2 µm); commanded_for inverts it."""
    r = load_robot(RW)
    rng = np.random.default_rng(2)
    L_cmd = r.d + rng.uniform(0.0, 9.5, (200, r.m))
    L0, dL, dd = drive.realised_rest_lengths(r, L_cmd)
    _, q_nw = drive.drum_angles(r, L_cmd)
    np.testing.assert_allclose(L0, drive.rest_lengths_from_angles(r, q_nw), rtol=0, atol=1e-12)
    dl = winch.length_error(TABLE1, L_cmd - r.d)
    assert np.abs(L0 - L_cmd).max() > 1e-3  # millimetres: the effect is there
    np.testing.assert_allclose(L0 - L_cmd, dl, rtol=0, atol=2e-6)
    back = drive.commanded_for(r, L0)
    np.testing.assert_allclose(back, L_cmd, rtol=0, atol=1e-12)
    np.testing.assert_allclose(dL + dd, 1.0, rtol=0, atol=1e-15)


def test_realised_rest_length_derivatives_equal_central_differences():
    r = load_robot(RW)
    rng = np.random.default_rng(3)
    L_cmd = r.d + rng.uniform(0.5, 9.0, (40, r.m))
    _, dL, dd = drive.realised_rest_lengths(r, L_cmd)
    h = 1e-4
    fd = (drive.realised_rest_lengths(r, L_cmd + h)[0] - drive.realised_rest_lengths(r, L_cmd - h)[0]) / (
        2 * h
    )
    np.testing.assert_allclose(dL, fd, rtol=0, atol=1e-9)
    assert np.abs(dL - 1.0).max() > 1e-4  # the slope is not the identity's
    up, down = with_pulleys(r, dead_length=r.d[0] + h), with_pulleys(r, dead_length=r.d[0] - h)
    fd_d = (drive.realised_rest_lengths(up, L_cmd)[0] - drive.realised_rest_lengths(down, L_cmd)[0]) / (2 * h)
    np.testing.assert_allclose(dd, fd_d, rtol=0, atol=1e-9)


def test_realised_rest_lengths_outside_the_drum_are_nan():
    r = load_robot(RW)
    L_cmd = r.d + np.array([[1.0, 11.0, 1.0, -3.8]])  # 11 m: more than the drum holds; l_pm < 0
    L0, _, _ = drive.realised_rest_lengths(r, L_cmd)
    assert np.isfinite(L0[0, [0, 2]]).all() and np.isnan(L0[0, [1, 3]]).all()
