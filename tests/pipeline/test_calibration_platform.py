"""The 6-DoF part of the calibration study (cdpr.pipeline.calibration on a rigid platform, CoGiRo) at tiny sizes: its
wiring (outputs, rows, flags), the physics its rows must obey (the truth commanding its own
compensated lengths reaches every target with every cable taut; the calibrated exact model beats the
nominal one), the new analysis helpers (random_poses, equilibrium_flags) and bad study files."""

import numpy as np
import pandas as pd
import pytest
import yaml

from cdpr.analyses import calibration as cal
from cdpr.errors import CdprError, ConfigError
from cdpr.models.inverse import L_TS
from cdpr.models.platform import rotation_matrix
from cdpr.pipeline import calibration as study
from cdpr.pipeline.results import CALIBRATION_OUTPUTS
from cdpr.robot import load_robot
from tests.conftest import ROBOTS, ROOT

STUDY = ROOT / "config" / "studies" / "calibration_cogiro.yaml"
BOX = [-3.0, 3.0, -2.0, 2.0, 1.0, 2.5]


@pytest.fixture(scope="module")
def cogiro():
    return load_robot(ROBOTS / "cogiro_massless.yaml")


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """The study at tiny sizes: 12 training samples (72 equations for at most 64 parameters), 8
    validation poses."""
    folder = tmp_path_factory.mktemp("cal6")
    base = yaml.safe_load(STUDY.read_text())
    base.update(n_train=12, n_validation=8)
    path = folder / "study.yaml"
    path.write_text(yaml.safe_dump(base))
    res = study.run_calibration_study(path, folder / "out")
    return folder / "out", res


def test_study_wiring(tiny):
    out, res = tiny
    for name in ("headline.csv", "validation.csv", "parameters.csv", "summary.md", "validation_errors.png"):
        assert (out / name).is_file(), name
    assert (out / "exact" / "samples.csv").is_file()
    # the study writes the files cdpr.pipeline.results describes (the rule's outputs), no other
    written = {f.relative_to(out).as_posix() for f in out.rglob("*") if f.is_file()}
    assert written == set(CALIBRATION_OUTPUTS["calibration_cogiro"].values())
    assert res["summary"] == out / "summary.md"
    h = pd.read_csv(out / "headline.csv")
    assert list(h["model"]) == [
        "nominal (uncalibrated)",
        *study.STUDY_MODELS[study.PLATFORM],
        "truth robot (noise floor)",
    ]
    assert list(h["parameters"]) == [0, 56, 56, 64, 0]
    v = pd.read_csv(out / "validation.csv")
    assert len(v) == 8  # every validation pose kept, flagged or not
    assert (v["flagged"] == ((v["truth_taut_cables"] < 6) | v["second_equilibrium"])).all()
    p = pd.read_csv(out / "parameters.csv")
    assert len(p) == 64 and np.isfinite(p["truth"]).all()


def test_study_rows_obey_the_physics(tiny):
    out, _ = tiny
    h = pd.read_csv(out / "headline.csv").set_index("model")
    truth, nominal, exact = (
        h.loc["truth robot (noise floor)"],
        h.loc["nominal (uncalibrated)"],
        h.loc[study.EXACT],
    )
    # the truth computing its own compensated lengths reaches every target, every cable taut
    assert truth["compensated_max_mm"] < 1e-3
    assert truth["compensated_all_taut"] == truth["compensated_points"] == 8
    # the truth's prediction error is the tracker noise alone: |N(0, 0.2 mm I3)| is below 1.5 mm
    assert truth["predict_max_mm"] < 1.5
    # 12 samples already bring the exact model far below the nominal robot's 20-60 mm
    assert exact["predict_rms_mm"] < 0.2 * nominal["predict_rms_mm"]
    assert exact["compensated_median_mm"] < 0.2 * nominal["compensated_median_mm"]


def test_random_poses_hold_every_cable_taut(cogiro):
    rng = np.random.default_rng(3)
    for command in cal.COMMANDS:
        P = cal.random_poses(cogiro, rng, 10, BOX, tilt=0.1, margin=150.0, command=command)
        assert P.shape == (10, 6)
        lo, hi = np.array(BOX[::2]), np.array(BOX[1::2])
        assert ((P[:, :3] >= lo) & (P[:, :3] <= hi)).all() and (np.abs(P[:, 3:]) <= 0.1).all()
        L = cal.commanded_lengths(cogiro, P[:, :3], rotation_matrix(P[:, 3:]), command)
        res = cal.equilibria(cogiro, P[:, :3], L, rotvec=P[:, 3:])
        assert (res["status"] == "ok").all() and (res["t"] > 150.0).all()
    with pytest.raises(CdprError, match="admissible poses"):
        cal.random_poses(cogiro, rng, 5, BOX, margin=1e5)  # above the cables' 5000 N


def test_equilibrium_flags_count_taut_cables(cogiro):
    """On the nominal robot under its own L_TS every cable is taut (8) at the drawn poses; a cable
    made 0.5 m longer leaves 6 or 7 taut (it or a crossed partner goes slack as the platform moves; as
    the solver counts them); no second equilibrium near these well-posed poses."""
    P = cal.random_poses(cogiro, np.random.default_rng(4), 6, BOX)
    data = cal.simulate(cogiro, cogiro, P)
    n_taut, second = cal.equilibrium_flags(cogiro, data)
    assert (n_taut == 8).all() and not second.any()
    L = L_TS(cogiro, P[:, :3], R=rotation_matrix(P[:, 3:]))
    L[:, 0] += 0.5
    data = cal.Data(
        sample=data.sample,
        L=L,
        pose=data.pose,
        sigma=data.sigma,
        encoder=False,
        source="<test>",
        rotvec=data.rotvec,
        sigma_rad=data.sigma_rad,
    )
    n_taut, _ = cal.equilibrium_flags(cogiro, data)
    res = cal.equilibria(cogiro, data.pose, L, rotvec=data.rotvec)
    assert (res["status"] == "ok").all()
    assert (n_taut == res["taut"].sum(axis=1)).all() and (n_taut < 8).all() and (n_taut >= 6).all()


@pytest.mark.parametrize(
    "change, key",
    [
        ({"n_train": 0}, "n_train"),
        ({"command": "pretension"}, "command"),
        ({"truth_deviations": {"pulleys": "1mm"}}, "truth_deviations"),
        ({"extra": 1}, "extra"),
        ({"tracker_sigma_rad": -1.0}, "tracker_sigma_rad"),
        ({"pose_box_m": [0, 1]}, "pose_box_m"),
    ],
)
def test_bad_study_files(tmp_path, change, key):
    base = dict(yaml.safe_load(STUDY.read_text()), **change)
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(base))
    with pytest.raises(ConfigError, match=key):
        study.load_calibration_study(path)


def test_missing_key_and_point_mass_robot(tmp_path):
    base = yaml.safe_load(STUDY.read_text())
    base.pop("tilt_rad")
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(base))
    with pytest.raises(ConfigError, match="tilt_rad"):
        study.load_calibration_study(path)
    base = dict(yaml.safe_load(STUDY.read_text()), robot=str(ROBOTS / "cdpr4.yaml"))
    path.write_text(yaml.safe_dump(base))
    with pytest.raises(ConfigError, match="point-mass"):
        study.run_calibration_study(path, tmp_path / "out")
