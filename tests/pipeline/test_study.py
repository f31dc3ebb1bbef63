"""The study's sweeps contain the values the summary reads at (issue 21: E_mean in the E sweep)."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
import yaml

from cdpr.pipeline import study
from cdpr.pipeline.results import Layout
from cdpr.robot import load_robot, read_yaml

ROOT = Path(__file__).resolve().parents[2]
# config/studies/calibration.yaml, calibration_cogiro.yaml and hangprinter.yaml are calibration studies
# (cdpr calibrate study), not pipeline ones
CALIBRATION_STUDIES = ("calibration", "calibration_cogiro", "hangprinter")
STUDIES = sorted(p for p in (ROOT / "config" / "studies").glob("*.yaml") if p.stem not in CALIBRATION_STUDIES)


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


@pytest.mark.parametrize("name", CALIBRATION_STUDIES)
def test_the_calibration_study_is_refused_as_a_pipeline_study_in_one_line(name):
    path = ROOT / "config" / "studies" / f"{name}.yaml"
    with pytest.raises(study.ConfigError) as err:
        study.load_study(path)
    message = str(err.value)
    assert "\n" not in message and "cdpr calibrate study" in message and f"{name}.yaml" in message


# ---- spatial robots (issue 19): what a study of a rigid 6-DoF platform refuses, in one line --------
QUICK_SPATIAL = ROOT / "config" / "studies" / "quick_spatial.yaml"


def _spatial_variant(tmp_path, **changes):
    """quick_spatial.yaml with top-level keys changed (None removes a key), written to tmp_path."""
    data = yaml.safe_load(QUICK_SPATIAL.read_text(encoding="utf-8"))
    data["robots"] = {k: str(ROOT / v) for k, v in data["robots"].items()}
    for k, v in changes.items():
        if v is None:
            data.pop(k, None)
        else:
            data[k] = v
    path = tmp_path / "spatial.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def _refusal(path):
    with pytest.raises(study.ConfigError) as err:
        study.load_study(path)
    message = str(err.value)
    assert "\n" not in message and str(path) in message
    return message


def test_the_quick_spatial_study_loads_with_its_orientation():
    st = study.load_study(QUICK_SPATIAL)
    assert study.spatial_robots(st) == ["CoGiRo"]
    assert study.rotvec(st) == [0.0, 0.0, 0.0]
    assert study.path_robot(st, "diagonal") == "CoGiRo"


def test_paper_mode_on_a_spatial_robot_is_refused_naming_redundancy_physical(tmp_path):
    message = _refusal(_spatial_variant(tmp_path, redundancy="paper"))
    assert "key 'redundancy'" in message and "redundancy: physical" in message and "3 of m" in message


def test_a_spatial_study_without_redundancy_is_physical(tmp_path):
    """Issue 41 'Defaults': left out, the mode of a spatial robot's study is physical (its only
    mode), not a refusal of the point-mass default paper; paper given is refused (test above)."""
    st = study.load_study(_spatial_variant(tmp_path, redundancy=None))
    assert study.redundancy(st) == "physical"


def test_paper_comparison_on_a_spatial_robot_is_refused(tmp_path):
    message = _refusal(_spatial_variant(tmp_path, paper_comparison=True))
    assert "key 'paper_comparison'" in message and "paper_comparison: false" in message


def test_uncertainty_in_paper_mode_on_a_spatial_robot_is_refused(tmp_path):
    u = yaml.safe_load((ROOT / "config" / "studies" / "quick_physical.yaml").read_text())["uncertainty"]
    u["redundancy"] = "paper"
    message = _refusal(_spatial_variant(tmp_path, uncertainty=u))
    assert "key 'uncertainty.redundancy'" in message and "uncertainty.redundancy: physical" in message


def test_the_uncertainty_study_of_a_spatial_robot_loads_in_physical_mode(tmp_path):
    """Issue 19: a spatial robot runs the uncertainty study (pipeline.uq, ‖δp‖ and δφ) in physical mode, both
    cases; its experiments are the 6-DoF ones (``uq_spatial``), a point-mass study's are not."""
    u = yaml.safe_load((ROOT / "config" / "studies" / "quick_physical.yaml").read_text())["uncertainty"]
    u["designs"] = ["SRopt", "DRopt"]
    for key in ("h_offset_m", "r_p_offset_m"):  # CoGiRo's SR pulley has h = r_p: no room for offsets
        u["parameters"].pop(key)
    st = study.load_study(_spatial_variant(tmp_path, uncertainty=u))
    assert study.uq_spatial(st) and study.uq_cases(st) == ("uncompensated", "compensated")
    assert not study.uq_spatial(study.load_study(ROOT / "config" / "studies" / "quick_physical.yaml"))


def test_lever_arm_offsets_that_break_the_pulley_rule_of_a_spatial_design_are_refused(tmp_path):
    u = yaml.safe_load((ROOT / "config" / "studies" / "quick_physical.yaml").read_text())["uncertainty"]
    u["designs"] = ["SRopt"]  # h = r_p = 50 mm: a lower h and a larger r_p break h >= r_p - 1 mm
    message = _refusal(_spatial_variant(tmp_path, uncertainty=u))
    assert "key 'uncertainty.parameters.h_offset_m'" in message and "pulley rule" in message


def test_an_orientation_on_a_point_mass_study_is_refused(tmp_path):
    data = yaml.safe_load((ROOT / "config" / "studies" / "quick_physical.yaml").read_text())
    data["robots"] = {k: str(ROOT / v) for k, v in data["robots"].items()}
    data["rotvec_rad"] = [0.0, 0.0, 0.1]
    path = tmp_path / "pm.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    message = _refusal(path)
    assert "key 'rotvec_rad'" in message and "spatial robots only" in message


def test_several_spatial_refusals_are_listed_in_one_line(tmp_path):
    message = _refusal(_spatial_variant(tmp_path, redundancy="paper", paper_comparison=True))
    assert "2 problems" in message and "'redundancy'" in message and "'paper_comparison'" in message


def test_a_path_naming_an_unknown_robot_is_refused(tmp_path):
    data = yaml.safe_load(QUICK_SPATIAL.read_text(encoding="utf-8"))
    paths = data["trajectories"]["paths"]
    paths["diagonal"]["robot"] = "Nope"
    message = _refusal(_spatial_variant(tmp_path, trajectories=data["trajectories"]))
    assert "trajectories.paths.diagonal.robot" in message and "allowed: CoGiRo" in message


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


# ---- error-limited volumes on δφ (spatial studies only) ---------------------------------------------
def _with_volumes(tmp_path, base, **keys):
    data = yaml.safe_load(base.read_text(encoding="utf-8"))
    data["robots"] = {k: str(ROOT / v) for k, v in data["robots"].items()}
    data["volumes"].update(keys)
    path = tmp_path / f"v_{base.name}"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def test_the_dphi_limits_of_the_spatial_studies_are_their_sweep_and_their_limits():
    st = study.load_study(QUICK_SPATIAL)
    lims = study.dphi_volume_limits(st)
    assert lims == pytest.approx([0.0025, 0.005, 0.0075, 0.01, 0.0125, 0.015])
    assert set(st["volumes"]["dphi_limits_rad"]) <= set(lims) and all(isinstance(x, float) for x in lims)
    assert study.dphi_volume_limits(study.load_study(ROOT / "config" / "studies" / "quick.yaml")) == []


@pytest.mark.parametrize("key", ["dphi_limits_rad", "dphi_sweep_rad"])
def test_dphi_volumes_on_a_point_mass_study_are_refused_in_one_line(tmp_path, key):
    value = [0.01] if key == "dphi_limits_rad" else {"from": 0.001, "to": 0.01, "steps": 3}
    extra = {} if key == "dphi_limits_rad" else {"dphi_limits_rad": [0.005]}
    message = _refusal(
        _with_volumes(tmp_path, ROOT / "config" / "studies" / "quick_physical.yaml", **{key: value}, **extra)
    )
    assert f"key 'volumes.{key}'" in message and "point mass (no δφ)" in message and "CDPR" in message


def test_a_reversed_dphi_sweep_and_a_sweep_without_limits_are_refused(tmp_path):
    bad = _with_volumes(tmp_path, QUICK_SPATIAL, dphi_sweep_rad={"from": 0.02, "to": 0.01, "steps": 3})
    assert "key 'volumes.dphi_sweep_rad'" in _refusal(bad) and "'from' must be below 'to'" in _refusal(bad)
    data = yaml.safe_load(QUICK_SPATIAL.read_text(encoding="utf-8"))
    data["robots"] = {k: str(ROOT / v) for k, v in data["robots"].items()}
    del data["volumes"]["dphi_limits_rad"]
    path = tmp_path / "nolimits.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    assert "dphi_limits_rad" in _refusal(path)


def _edited_file_robot(path, tmp_path, spec, E=None, dead_length=None):
    """The robot of ``path`` with the design written into its YAML mapping, as a user editing the
    file would: every cable's pulley kind, h, r_p (the robot's and each cable's), the dead length and
    the modulus (per-cable values dropped), then read back from a file."""
    data = read_yaml(path)
    pulley = {"kind": spec["kind"]}
    if spec["kind"] == "fixed":
        pulley.update(h_m=0.0, r_p_m=0.0)
    else:
        pulley.update(h_m=spec["h_m"], r_p_m=spec["r_p_m"])
    data["pulley"].update(pulley)
    for c in data["cables"]:
        if isinstance(c.get("pulley"), dict):
            c["pulley"].update(pulley)
        if dead_length is not None:
            c.pop("dead_length_m", None)
        if E is not None and isinstance(c.get("cable"), dict):
            c["cable"].pop("young_modulus_Pa", None)
    if dead_length is not None:
        data["dead_length_m"] = dead_length
    if E is not None:
        data["cable"]["young_modulus_Pa"] = E
    out = tmp_path / "edited.yaml"
    out.write_text(yaml.safe_dump(data), encoding="utf-8")
    return load_robot(out)


@pytest.mark.parametrize("name", ["paper.yaml", "quick_spatial.yaml"])
def test_a_design_set_as_values_is_the_robot_file_edited(name, tmp_path):
    """design_robot sets a pulley design, the dead length and E as values on the study's Robot
    (``with_values``: the YAML mapping is neither rewritten nor validated again); the robot is the
    one a user gets by editing the robot file (pulley axes and zeros, attachments, winches kept)."""
    st = study.load_study(Path("config/studies") / name)
    key = st["doe"]["robot"]
    for spec, kw in (
        ({"kind": "SR", "h_m": 0.035, "r_p_m": 0.02}, {}),
        ({"kind": "DR", "h_m": 0.15, "r_p_m": 0.145}, {"E": 9.0e10, "dead_length": 1.5}),
        ({"kind": "fixed"}, {}),
    ):
        typed = study.design_robot(st, key, spec, **kw)
        edited = _edited_file_robot(st["robots"][key], tmp_path, spec, **kw)
        assert dataclasses.replace(typed, source="") == dataclasses.replace(edited, source="")
        for a, b in zip(typed.arrays, edited.arrays):
            np.testing.assert_array_equal(a, b)


def test_a_design_builds_on_the_study_robot_without_reading_its_file(monkeypatch):
    """The study's Robot (built once by load_study's checks) is the base of every design: reading a
    robot file during design_robot fails the test."""
    st = study.load_study(Path("config/studies") / "paper.yaml")

    def no_reading(*args, **kwargs):
        raise AssertionError("the robot file was read again")

    monkeypatch.setattr(study, "load_robot", no_reading)
    monkeypatch.setattr("cdpr.robot.read_yaml", no_reading)
    robot = study.design_robot(st, st["doe"]["robot"], {"kind": "DR", "h_m": 0.15, "r_p_m": 0.1}, E=9e10)
    assert robot.cables[0].pulley.kind == "DR" and robot.cables[0].material.E == 9e10
