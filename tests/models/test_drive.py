"""The winch in the chain: drum angles <-> rest lengths (Métillon 2022 on each cable)."""

import json

import numpy as np
import pytest

from cdpr.cli.main import main
from cdpr.errors import CdprError
from cdpr.models import drive, winch
from cdpr.robot import TABLE1, load_robot
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
