"""`cdpr calibrate fit | check` on a robot file with `winch:` (cdpr4_winch.yaml): the commanded
lengths go through the drums (the controller neglects the exit point's motion), so the exact model
of that file reaches the noise floor where the same robot without `winch:` cannot."""

import json

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.cli.main import main
from cdpr.parameters import select_groups
from cdpr.pipeline.calibration_files import write_data
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

RW = str(ROBOTS / "cdpr4_winch.yaml")
R4 = str(ROBOTS / "cdpr4.yaml")


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """A CDPR4 with drums, dead lengths perturbed, measured at 30 poses with σ = 10 µm."""
    robot = load_robot(RW)
    rng = np.random.default_rng(21)
    idx = select_groups(robot, ["dead_lengths"])
    truth, th = cal.perturbed(robot, idx, cal.prior_sd(robot, idx, cal.parse_priors(None)), rng)
    box = np.array([[-1.8, -1.8, 0.8], [1.8, 1.8, 3.5]])
    data = cal.simulate(truth, robot, rng.uniform(box[0], box[1], (30, 3)), sigma=1e-5, rng=rng)
    d = tmp_path_factory.mktemp("calw")
    write_data(d / "m.csv", data, robot)
    return d, th[idx]


def _fit(capsys, robot, d, out):
    argv = ["calibrate", "fit", "--robot", robot, "--data", str(d / "m.csv"), "--estimate", "dead_lengths"]
    assert main(argv + ["--model", "exact", "--out", str(out), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_fit_exact_on_a_winch_robot_uses_the_drums(measured, capsys):
    d, truth = measured
    s = _fit(capsys, RW, d, d / "w.yaml")
    assert s["residual_rms_m"] < 2e-5  # the noise floor: sqrt(3) * 10 µm
    est = np.array([p["estimate"] for p in s["parameters"]])
    sd = np.array([p["sd"] for p in s["parameters"]])
    assert (np.abs(est - truth) < 4 * sd).all()
    assert load_robot(d / "w.yaml").winches == load_robot(RW).winches  # the calibrated file keeps them
    blind = _fit(capsys, R4, d, d / "b.yaml")  # same robot, no winch: the drums' error is left over
    assert blind["residual_rms_m"] > 5 * s["residual_rms_m"]


def test_check_on_a_winch_robot_uses_the_drums(measured, capsys):
    d, _ = measured
    assert (
        main(["calibrate", "check", "--robot", str(d / "w.yaml"), "--data", str(d / "m.csv"), "--json"]) == 0
    )
    with_drums = json.loads(capsys.readouterr().out)
    assert (
        main(["calibrate", "check", "--robot", str(d / "b.yaml"), "--data", str(d / "m.csv"), "--json"]) == 0
    )
    without = json.loads(capsys.readouterr().out)
    assert with_drums["rms_m"] < 2e-5 and without["rms_m"] > 5 * with_drums["rms_m"]
