"""A whole calibration study with the study key ``wrench`` (issue 41): config/studies/calibration.yaml
(CDPR4, point mass) cut down (15 training poses, 20 validation poses, one learning-curve size, a 3^3
candidate grid, no drums) and run by the command of the rule ``calibration_study``
(``cdpr calibrate study --study FILE --out DIR``, workflow/rules/calibration.smk) with no wrench, a zero
wrench and a load of 30 kg more weight and a side pull. The zero wrench writes the wrench-free files
byte for byte; the load changes every file, the summary names it, and the exact model fitted under it
recovers the true robot (every estimate within 4 posterior sd of the truth, the prediction at the
tracker's noise floor, the truth's compensated error 0: the true robot and the models carry the same
load)."""

import numpy as np
import pytest
import yaml

from cdpr import table_io
from cdpr.cli.main import main
from cdpr.pipeline.results import CALIBRATION_OUTPUTS
from tests.conftest import ROOT

STUDY = ROOT / "config" / "studies" / "calibration.yaml"
#: A load on CDPR4's 300 kg point mass during every measurement [N, N m] (no moment: a point mass).
LOAD = [60.0, -40.0, -300.0, 0.0, 0.0, 0.0]
WRENCHES = {"none": None, "zero": [0.0] * 6, "load": LOAD}


def _study(path, wrench):
    """The calibration study cut down to ~10 s, with ``wrench`` (None: no key)."""
    data = yaml.safe_load(STUDY.read_text(encoding="utf-8"))
    data["robot"] = str(ROOT / data["robot"])
    del data["winch"]  # no drums: the exact model is then the best one (parameters.csv is its fit)
    data.update(name="calibration_wrench", n_train=15, n_validation=20, learning_curve=[8], plan_grid=3)
    if wrench is not None:
        data["wrench"] = wrench
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    root = tmp_path_factory.mktemp("calibration_wrench")
    out = {}
    for key, wrench in WRENCHES.items():
        study = _study(root / f"{key}.yaml", wrench)
        out[key] = root / key
        assert main(["calibrate", "study", "--study", str(study), "--out", str(out[key])]) == 0
    return out


def _files(folder):
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


def test_a_zero_wrench_writes_the_wrench_free_files_byte_for_byte(runs):
    names = _files(runs["none"])
    # every output the rule declares, and nothing else
    assert names == sorted(CALIBRATION_OUTPUTS["calibration_study"].values()) == _files(runs["zero"])
    for n in names:
        assert (runs["zero"] / n).read_bytes() == (runs["none"] / n).read_bytes(), n


def test_the_load_reaches_every_output(runs):
    for n in _files(runs["none"]):
        assert (runs["load"] / n).read_bytes() != (runs["none"] / n).read_bytes(), n
    summary = (runs["load"] / "summary.md").read_text(encoding="utf-8")
    assert (
        "carrying the external wrench (60, -40, -300, 0, 0, 0) [N, N m] during every measurement" in summary
    )
    assert "external wrench" not in (runs["none"] / "summary.md").read_text(encoding="utf-8")


def test_the_exact_model_fitted_under_the_load_recovers_the_truth(runs):
    """parameters.csv (the pulleys + elasticity model's 28 parameters, with the truth): every estimate
    within 4 posterior sd of the truth and their squared z-scores near 1 on average, while the nominal
    is tens of sd away; the headline: that model predicts the validation poses within twice the true
    robot's (the noise floor, ~0.3 mm), and the true robot's compensated error is 0 (the compensation
    and the solves under the same load)."""
    p = table_io.read_table(runs["load"] / "parameters.csv")
    assert len(p) == 28
    z = (p["estimate"] - p["truth"]) / p["sd"]
    assert np.abs(z).max() < 4 and (z**2).mean() < 2, z.abs().max()
    assert (np.abs(p["nominal"] - p["truth"]) / p["sd"]).max() > 10
    h = table_io.read_table(runs["load"] / "headline.csv").set_index("model")
    floor = h.loc["truth robot (noise floor)"]
    exact = h.loc["pulleys + elasticity"]
    assert 0.1 < floor["predict_rms_mm"] < 0.6 and exact["predict_rms_mm"] < 2.5 * floor["predict_rms_mm"]
    assert floor["compensated_max_mm"] < 1e-3 and floor["compensated_points"] == exact["compensated_points"]
    assert h.loc["nominal (uncalibrated)", "predict_rms_mm"] > 10 * exact["predict_rms_mm"]
