"""`cdpr calibrate fit | check | plan --wrench` (cdpr.cli.calibrate): the external wrench on the platform
while the data were taken (a tool's weight) acts on the nominal and the fitted robot. Data simulated
under a wrench are recovered with it and biased without it; the JSON echoes it; the written robot file
names it in its header and does not carry it; bad requests are one line."""

import json

import numpy as np
import pytest

from cdpr.analyses import calibration as cal
from cdpr.parameters import select_groups
from cdpr.pipeline.calibration_files import write_data
from cdpr.robot import load_robot, with_wrench
from tests.cli.test_wrench import run
from tests.conftest import ROBOTS

R4 = str(ROBOTS / "cdpr4.yaml")
GROUPS = ["anchors", "dead_lengths", "pulleys"]
#: A load on CDPR4's 300 kg point mass while it was measured: 30 kg more weight and a side pull [N].
WRENCH = (60.0, -40.0, -300.0, 0.0, 0.0, 0.0)


@pytest.fixture(scope="module")
def loaded(tmp_path_factory):
    """A perturbed CDPR4 (anchors, dead lengths, pulleys) carrying ``WRENCH``, commanded the nominal
    robot's standard lengths at 40 poses (σ = 0.2 mm) and 60 held-out ones."""
    robot = load_robot(R4)
    rng = np.random.default_rng(17)
    idx = select_groups(robot, GROUPS)
    truth, th = cal.perturbed(robot, idx, cal.prior_sd(robot, idx, cal.parse_priors(None)), rng)
    truth = with_wrench(truth, WRENCH)
    box = np.array([[-1.8, -1.8, 0.8], [1.8, 1.8, 3.5]])
    d = tmp_path_factory.mktemp("calw")
    write_data(d / "m.csv", cal.simulate(truth, robot, rng.uniform(box[0], box[1], (40, 3)), rng=rng), robot)
    write_data(d / "v.csv", cal.simulate(truth, robot, rng.uniform(box[0], box[1], (60, 3)), rng=rng), robot)
    return d, th[idx]


def _fit(capsys, d, out, *extra):
    code, text, err = run(
        capsys,
        *("calibrate", "fit", "--robot", R4, "--data", d / "m.csv", "--estimate", ",".join(GROUPS)),
        *("--out", out, "--json", *extra),
    )
    assert code == 0, err
    return json.loads(text)


def test_fit_with_the_wrench_recovers_the_truth_and_without_it_is_biased(loaded, capsys):
    d, truth = loaded
    w = [str(x) for x in WRENCH]
    s = _fit(capsys, d, d / "with.yaml", "--wrench", *w)
    assert s["wrench"] == list(WRENCH) and s["warnings"] == []  # the JSON echo
    est = np.array([p["estimate"] for p in s["parameters"]])
    sd = np.array([p["sd"] for p in s["parameters"]])
    assert s["samples_used"] == 40 and 2e-4 < s["residual_rms_m"] < 4.5e-4  # the noise floor
    assert (np.abs(est - truth) < 5 * sd).all()
    # the same data fitted as if the platform carried nothing: the residual and the estimates show it
    s0 = _fit(capsys, d, d / "without.yaml")
    assert "wrench" not in s0
    est0 = np.array([p["estimate"] for p in s0["parameters"]])
    assert s0["residual_rms_m"] > 3 * s["residual_rms_m"]
    sd0 = np.array([p["sd"] for p in s0["parameters"]])
    assert (np.abs(est0 - truth) / sd0).max() > 6  # some estimate many posterior sd off (9.3 here)
    # the calibrated robot under the wrench predicts held-out poses at the noise floor; the robot
    # file itself is the robot without the load (check needs --wrench again)
    checks = {}
    for name, extra in (("with", ["--wrench", *w]), ("without", [])):
        code, text, err = run(
            capsys, "calibrate", "check", "--robot", d / "with.yaml", "--data", d / "v.csv", "--json", *extra
        )
        assert code == 0, err
        checks[name] = json.loads(text)
    assert checks["with"]["wrench"] == list(WRENCH) and "wrench" not in checks["without"]
    assert (
        checks["with"]["n"] == 60
        and checks["with"]["rms_m"] < 4.5e-4
        and checks["without"]["rms_m"] > 5 * checks["with"]["rms_m"]
    )


def test_the_written_robot_names_the_wrench_and_does_not_carry_it(loaded, capsys):
    d, _ = loaded
    out = d / "text.yaml"
    code, text, err = run(
        capsys,
        *("calibrate", "fit", "--robot", R4, "--data", d / "m.csv", "--estimate", "dead_lengths"),
        *("--out", out, "--wrench", *WRENCH),
    )
    assert code == 0, err
    assert (
        "external wrench (60, -40, -300, 0, 0, 0) [N, N m] on the platform while the data were taken" in text
    )
    assert f"not written into {out}" in text
    header = [ln for ln in out.read_text().splitlines() if ln.startswith("#")]
    assert any("(60, -40, -300, 0, 0, 0) [N, N m]" in ln and "not part of this robot" in ln for ln in header)
    back = load_robot(out)
    assert not back.platform.has_wrench and back.platform.mass == load_robot(R4).platform.mass
    # without --wrench the header says nothing of one
    run(
        capsys,
        "calibrate",
        "fit",
        "--robot",
        R4,
        "--data",
        d / "m.csv",
        "--estimate",
        "dead_lengths",
        "--out",
        d / "plain.yaml",
    )
    assert "external wrench" not in (d / "plain.yaml").read_text()


def test_plan_solves_its_candidates_under_the_wrench(capsys):
    """One candidate (a 1-point grid): its expected pose moves along the force, and the JSON echoes it."""
    argv = [
        "calibrate",
        "plan",
        "--robot",
        R4,
        "--estimate",
        "dead_lengths",
        "--n",
        "1",
        "--grid",
        "1",
        "--json",
    ]
    argv += ["--box", "-0.5", "0.5", "-0.5", "0.5", "1.5", "2.5"]
    code, text, err = run(capsys, *argv)
    assert code == 0, err
    free = json.loads(text)
    code, text, err = run(capsys, *argv, "--wrench", "200", "0", "0", "0", "0", "0")
    assert code == 0, err
    pushed = json.loads(text)
    assert pushed["wrench"] == [200.0, 0, 0, 0, 0, 0] and "wrench" not in free
    (x0, y0, _), (x1, y1, _) = free["poses"][0], pushed["poses"][0]
    assert pushed["lengths"] == free["lengths"]  # the same commands (L_TS)
    assert x1 - x0 > 1e-3 and abs(y1 - y0) < 1e-3 * (x1 - x0) + 1e-9  # along the force


@pytest.mark.parametrize(
    "cmd,wrench,words",
    [
        (
            ["fit", "--estimate", "anchors", "--out", "{d}/x.yaml"],
            ["0", "0", "-10", "1", "0", "0"],
            "cannot carry a moment",
        ),
        (["check"], ["0", "0", "-10", "0", "0", "2"], "cannot carry a moment"),
        (["plan", "--estimate", "anchors"], ["0", "0", "-10", "0", "3", "0"], "cannot carry a moment"),
        (
            ["fit", "--estimate", "anchors", "--out", "{d}/x.yaml"],
            ["0", "0", "nan", "0", "0", "0"],
            "--wrench",
        ),
        (["check"], ["0", "0", "-10", "0"], "--wrench"),
    ],
)
def test_bad_wrenches_are_one_line(loaded, capsys, cmd, wrench, words):
    d, _ = loaded
    argv = ["calibrate", cmd[0], "--robot", R4, *[a.format(d=d) for a in cmd[1:]]]
    if cmd[0] != "plan":
        argv += ["--data", str(d / "m.csv")]
    code, out, err = run(capsys, *argv, "--wrench", *wrench)
    assert code == 2 and out == "" and len(err.splitlines()) == 1, err
    assert err.startswith("cdpr: error: ") and words in err and "--wrench" in err


def test_motor_angle_data_refuse_a_wrench(tmp_path, capsys):
    """The motor-angle model takes the measured line forces, not the platform's balance: fit and check
    on such data refuse --wrench in one line naming the file (cv has no --wrench)."""
    hp = ROBOTS / "hangprinter_hp4.yaml"
    data = tmp_path / "motor.csv"
    data.write_text("sample,motor_deg_1,motor_deg_2,motor_deg_3,motor_deg_4\ns1,0,0,0,0\ns2,10,-5,3,2\n")
    hanging = ["--wrench", "0", "0", "-5", "0", "0", "0"]
    for argv in (
        ["fit", "--estimate", "anchors", "--out", str(tmp_path / "x.yaml")],
        ["check"],
    ):
        code, out, err = run(
            capsys,
            "calibrate",
            *argv,
            "--robot",
            hp,
            "--data",
            data,
            *hanging,
        )
        assert code == 2 and out == "" and len(err.splitlines()) == 1, err
        assert "--wrench" in err and str(data) in err and "motor angles" in err
    code, out, err = run(
        capsys,
        "calibrate",
        "cv",
        "--robot",
        hp,
        "--data",
        data,
        "--fixed",
        "--folds",
        "2",
        *hanging,
    )
    assert code == 2 and "unrecognized arguments: --wrench" in err
