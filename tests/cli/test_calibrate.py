"""`cdpr calibrate fit | check | plan` (cdpr.cli.calibrate): the issue-18 names and JSON keys, on the
shipped robots, and one-line errors."""

import json

import numpy as np
import pandas as pd
import pytest

from cdpr.analyses import calibration as cal
from cdpr.cli.main import main
from cdpr.parameters import select_groups
from cdpr.pipeline.calibration_files import write_data
from cdpr.robot import load_robot
from tests.conftest import ROBOTS

R4 = str(ROBOTS / "cdpr4.yaml")
FIT_KEYS = {
    "parameters",
    "n_parameters",
    "rank",
    "condition",
    "singular_values",
    "unidentified",
    "residual_rms_m",
    "residual_rms_rad",
    "samples_used",
    "samples_left_out",
}
PARAM_KEYS = {"name", "group", "cable", "nominal", "estimate", "sd", "prior_sd", "identified"}


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """A perturbed CDPR4 (anchors, dead lengths, pulleys) measured at 40 poses (σ = 0.2 mm), and 100
    held-out poses."""
    robot = load_robot(R4)
    rng = np.random.default_rng(17)
    groups = ["anchors", "dead_lengths", "pulleys"]
    idx = select_groups(robot, groups)
    truth, th = cal.perturbed(robot, idx, cal.prior_sd(robot, idx, cal.parse_priors(None)), rng)
    box = np.array([[-1.8, -1.8, 0.8], [1.8, 1.8, 3.5]])
    d = tmp_path_factory.mktemp("cal")
    train = cal.simulate(truth, robot, rng.uniform(box[0], box[1], (40, 3)), rng=rng)
    test = cal.simulate(truth, robot, rng.uniform(box[0], box[1], (100, 3)), rng=rng)
    write_data(d / "m.csv", train, robot)
    write_data(d / "v.csv", test, robot)
    return d, th[idx], idx


def test_fit_json_keys_and_the_written_robot(measured, capsys):
    d, truth, idx = measured
    out = d / "calibrated.yaml"
    args = [
        "calibrate",
        "fit",
        "--robot",
        R4,
        "--data",
        str(d / "m.csv"),
        "--estimate",
        "anchors,dead_lengths,pulleys",
    ]
    assert main([*args, "--out", str(out), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert set(s) == FIT_KEYS | {"warnings"} and s["warnings"] == []
    assert all(set(p) == PARAM_KEYS for p in s["parameters"])
    names = [p["name"] for p in s["parameters"]]
    assert names[:2] == ["h_1", "h_2"] and "r_p_4" in names and "d_1" in names and names[-1] == "A_4_z"
    assert s["n_parameters"] == 24 == s["rank"] and s["samples_used"] == 40 and s["samples_left_out"] == 0
    assert s["residual_rms_rad"] is None and 2e-4 < s["residual_rms_m"] < 4.5e-4
    p = {q["name"]: q for q in s["parameters"]}
    assert p["A_1_x"]["group"] == "anchors" and p["A_1_x"]["cable"] == 1 and p["r_p_3"]["group"] == "pulleys"
    est = np.array([p[n]["estimate"] for n in names])
    sd = np.array([p[n]["sd"] for n in names])
    assert (np.abs(est - truth) < 5 * sd).all()
    # the written robot: same schema, per-cable SI values, header naming the data
    text = out.read_text()
    assert text.splitlines()[0].endswith(f"from {d / 'm.csv'}")
    back = load_robot(out)
    assert back.cables[2].dead_length == pytest.approx(p["d_3"]["estimate"], rel=1e-12)
    assert back.cables[0].A[0] == pytest.approx(p["A_1_x"]["estimate"], rel=1e-12)
    # check: the calibrated robot on held-out poses is at the noise floor, the nominal one is not
    assert main(["calibrate", "check", "--robot", str(out), "--data", str(d / "v.csv"), "--json"]) == 0
    after = json.loads(capsys.readouterr().out)
    assert main(["calibrate", "check", "--robot", R4, "--data", str(d / "v.csv"), "--json"]) == 0
    before = json.loads(capsys.readouterr().out)
    assert set(after) == {"n", "rms_m", "max_m", "median_m", "rms_rad", "max_rad", "samples", "warnings"}
    assert after["n"] == 100 and after["rms_m"] < 4.5e-4 < 10 * 4.5e-4 < before["rms_m"]


def test_fit_text_report_and_figures(measured, capsys):
    d, _, _ = measured
    rep = d / "report"
    assert (
        main(
            [
                "calibrate",
                "fit",
                "--robot",
                R4,
                "--data",
                str(d / "m.csv"),
                "--estimate",
                "dead_lengths,mass,moduli",
                "--prior",
                "dead_lengths=20mm,moduli=10%",
                "--out",
                str(d / "c2.yaml"),
                "--report",
                str(rep),
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    assert "rank 8" in text and "weak: M with E_" in text  # E and M enter only as E/M
    for f in (
        "samples.csv",
        "parameters.csv",
        "correlation.csv",
        "residuals.png",
        "estimates.png",
        "correlation.png",
    ):
        assert (rep / f).stat().st_size > 0, f


def test_plan_beats_random_and_writes_the_poses(tmp_path, capsys):
    out = tmp_path / "plan.csv"
    args = [
        "calibrate",
        "plan",
        "--robot",
        R4,
        "--estimate",
        "anchors,dead_lengths",
        "--n",
        "12",
        "--grid",
        "5",
    ]
    assert main([*args, "--out", str(out), "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert len(s["poses"]) == 12 and s["logdet_d_optimal"] > s["logdet_random_median"]
    assert np.median([e["d_optimal"] / e["random_median"] for e in s["expected_sd"]]) < 1
    import pandas as pd

    df = pd.read_csv(out)
    assert list(df.columns) == [
        "sample",
        "L1",
        "L2",
        "L3",
        "L4",
        "x_expected_m",
        "y_expected_m",
        "z_expected_m",
    ]


@pytest.mark.parametrize(
    "argv,words",
    [
        (["fit", "--estimate", "wheels", "--out", "{d}/x.yaml"], "unknown group 'wheels'"),
        (["fit", "--estimate", "attachments", "--out", "{d}/x.yaml"], "'attachments' (b_i) are for a 6-DoF"),
        (["fit", "--estimate", "anchors", "--prior", "anchors=0mm", "--out", "{d}/x.yaml"], "must be > 0"),
        (
            ["fit", "--estimate", "pulleys", "--model", "standard", "--out", "{d}/x.yaml"],
            "standard model has no",
        ),
        (["fit", "--estimate", "anchors", "--out", "{d}/x.txt"], "unknown output format"),
        (["check", "--data", "{d}/missing.csv"], "the data file does not exist"),
    ],
)
def test_bad_requests_are_one_line(measured, capsys, argv, words):
    d, _, _ = measured
    argv = [a.format(d=d) for a in argv]
    if "--data" not in argv:
        argv += ["--data", str(d / "m.csv")]
    assert main(["calibrate", argv[0], "--robot", R4, *argv[1:]]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err


def test_encoder_only_data_exact_refuses_standard_self_calibrates(tmp_path, capsys):
    """Encoder readings without poses: the exact model refuses in one line naming the gauge; the
    standard model runs the rigid self-calibration, warns of its bias and reports d_i against offset_i."""
    robot = load_robot(R4)
    rng = np.random.default_rng(5)
    data = cal.simulate(
        robot, robot, rng.uniform([-1.5, -1.5, 1.0], [1.5, 1.5, 3.0], (20, 3)), offsets=[0.01] * 4
    )
    data.pose[:] = np.nan
    write_data(tmp_path / "enc.csv", data, robot)
    args = [
        "calibrate",
        "fit",
        "--robot",
        R4,
        "--data",
        str(tmp_path / "enc.csv"),
        "--out",
        str(tmp_path / "c.yaml"),
    ]
    assert main([*args, "--estimate", "dead_lengths,offsets", "--json"]) == 2
    err = capsys.readouterr().err
    assert (
        err.count("\n") == 1
        and "d_i and offset_i enter only as their sum" in err
        and "--model standard" in err
    )
    assert main([*args, "--estimate", "dead_lengths,offsets", "--model", "standard", "--json"]) == 0
    cap = capsys.readouterr()
    s = json.loads(cap.out)
    assert "biased" in cap.err
    assert s["rank"] == 4 and s["n_parameters"] == 8
    assert "d_1 against offset_1 (not seen by the data)" in s["unidentified"]


def test_check_where_no_sample_is_ok_counts_the_statuses(measured, tmp_path, capsys):
    """Every measured pose moved far outside the anchors' hull (the lengths unchanged): a suspended
    point mass's status is judged there, so no sample is ok; the text says so with the count of each
    status, not a bare "no equilibrium"."""

    d, _, _ = measured
    df = pd.read_csv(d / "v.csv")
    df["x_m"] = df["y_m"] = 100.0
    df.to_csv(tmp_path / "far.csv", index=False)
    assert main(["calibrate", "check", "--robot", R4, "--data", str(tmp_path / "far.csv")]) == 0
    assert (
        capsys.readouterr().out.strip()
        == f"no sample has an ok equilibrium ({len(df)} samples: inaccessible {len(df)})"
    )
