"""The study's sweeps contain the values the summary reads at (issue 21: E_mean in the E sweep)."""

from pathlib import Path

import numpy as np
import pytest

from cdpr.pipeline import study
from cdpr.pipeline.results import Layout

ROOT = Path(__file__).resolve().parents[2]
# config/studies/calibration.yaml is a calibration study (cdpr calibrate study), not a pipeline one
STUDIES = sorted(p for p in (ROOT / "config" / "studies").glob("*.yaml") if p.stem != "calibration")


@pytest.mark.parametrize("path", STUDIES, ids=[p.stem for p in STUDIES])
def test_every_modulus_sweep_contains_E_min_E_mean_E_max(path):
    st = study.load_study(path)
    Es = np.array(study.E_values(st))
    for E in st["elasticity"]["E_path_Pa"]:
        assert np.isclose(Es, E, rtol=1e-9, atol=0).sum() == 1, (path.name, E, Es)
    assert (np.diff(Es) > 0).all()  # sorted, no duplicate


def test_paper_sweep_keeps_its_ten_GPa_steps_and_adds_E_mean():
    st = study.load_study(ROOT / "config" / "studies" / "paper.yaml")
    Es = np.array(study.E_values(st)) / 1e9
    assert np.allclose(Es, [67.2, 77.2, 87.2, 97.2, 102.2, 107.2, 117.2, 127.2, 137.2])


def test_a_path_modulus_on_a_step_is_not_added_twice():
    st = study.load_study(ROOT / "config" / "studies" / "quick.yaml")
    # 3 steps from 67.2 to 137.2 GPa: the middle step is E_mean up to rounding
    assert len(study.E_values(st)) == 3


def test_the_calibration_study_is_refused_as_a_pipeline_study_in_one_line():
    path = ROOT / "config" / "studies" / "calibration.yaml"
    with pytest.raises(study.ConfigError) as err:
        study.load_study(path)
    message = str(err.value)
    assert "\n" not in message and "cdpr calibrate study" in message and "calibration.yaml" in message


def test_the_compensated_case_is_computed_once_by_the_physical_study():
    """Issue 21: the compensated robot is physical in both modes; the paper-mode study does not copy it."""
    paper = study.load_study(ROOT / "config" / "studies" / "quick.yaml")
    physical = study.load_study(ROOT / "config" / "studies" / "quick_physical.yaml")
    assert study.uq_cases(paper) == ("uncompensated",)
    assert study.uq_cases(physical) == ("uncompensated", "compensated")
    cases = {w["case"] for w in Layout(paper, "results/quick").wildcards("uq_design")}
    assert cases == {"uncompensated"}
    cases = {w["case"] for w in Layout(physical, "results/quick_physical").wildcards("uq_shard")}
    assert cases == {"uncompensated", "compensated"}
