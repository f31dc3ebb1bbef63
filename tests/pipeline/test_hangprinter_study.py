"""The Hangprinter study (config/studies/hangprinter.yaml, cdpr.pipeline.hangprinter,
workflow/rules/hangprinter.smk): it dry-runs in Snakemake, a small study writes every file of its
layout, deterministically, the tracked table has every data set × model × fold count and the
columns the docs quote, docs/hangprinter.md quotes the pipeline's table, and a bad study file is
refused in one line."""

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from cdpr.analyses import calibration as cal
from cdpr.analyses.calibration.motor import BUILDUP_PRIOR_SD, line_terms, motor_index, motor_prior_sd
from cdpr.errors import CdprError, ConfigError
from cdpr.pipeline import hangprinter as hp
from cdpr.pipeline.results import CALIBRATION_OUTPUTS, calibration_outputs
from cdpr.robot import load_robot
from tests.conftest import ROOT
from tests.quick_runs import make_workdir

STUDY = ROOT / "config" / "studies" / "hangprinter.yaml"
#: The columns of cv.csv that docs/hangprinter.md and summary.md quote.
CV_COLUMNS = [
    "data_set",
    "model",
    "label",
    "fit",
    "folds",
    "leave_one_out",
    "heldout_with_position",
    "heldout_position_rms_mm",
    "heldout_position_median_mm",
    "heldout_position_max_mm",
    "heldout_line_rms_mm",
    "train_line_rms_mm",
]
SMALL = """name: small
robot: config/robots/hangprinter_hp4.yaml
priors: {anchors: 150mm}
folds: [3]
data_sets:
  grid:
    data: data/hangprinter/hp4_2021_12_grid_cdpr.csv
    tool: data/hangprinter/tool_hp4_2021_12_grid.yaml
    source: data/hangprinter/hp4_2021_12_grid.json
models:
  nominal: {label: nominal, fixed: nominal, model: standard}
  rigid_spools: {label: "rigid, anchors + spools", model: standard, estimate: [anchors, spools]}
  tool: {label: tool, fixed: tool, model: standard}
"""


@pytest.fixture
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)  # the study's paths are relative to the repository


def test_the_study_dry_runs(tmp_path):
    """Snakemake schedules the study's one job from a working folder outside the tree."""
    work = make_workdir(tmp_path / "work", studies=())
    exe = Path(sys.executable).with_name("snakemake")
    p = subprocess.run(
        [str(exe), "--snakefile", str(ROOT / "Snakefile"), "hangprinter_study", "-n", "--cores", "1"]
        + ["--config", "study=config/studies/quick.yaml", f"results={tmp_path / 'r'}"],
        cwd=work,
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stderr[-2000:]
    out = p.stdout + p.stderr
    assert "hangprinter_study        1" in out, out[-2000:]
    for path in calibration_outputs("hangprinter_study").values():
        assert path in out, path


def test_a_small_study_writes_its_layout_deterministically(at_root, tmp_path):
    study = tmp_path / "small.yaml"
    study.write_text(SMALL)
    a, b = tmp_path / "a", tmp_path / "b"
    res = hp.run_hangprinter_study(study, a)
    hp.run_hangprinter_study(study, b)
    for rel in CALIBRATION_OUTPUTS["hangprinter_study"].values():
        assert (a / rel).is_file(), rel
        if not rel.endswith((".png", ".pdf")):
            assert (a / rel).read_bytes() == (b / rel).read_bytes(), rel
    cv = pd.read_csv(a / "cv.csv")
    assert list(cv.columns) == CV_COLUMNS
    assert list(cv.model) == ["nominal", "rigid_spools", "tool"] and set(cv.folds) == {3}
    rms = dict(zip(cv.model, cv.heldout_position_rms_mm))
    # the fit moves the rough tape-measured robot towards the data: held out, it predicts better
    assert rms["rigid_spools"] < 0.5 * rms["nominal"]
    assert res["best"] == {"grid": "rigid_spools"}
    fw = (a / "firmware.g").read_text()
    assert "\nM669 K6 A" in fw and "\nM666 Q" in fw
    summary = (a / "summary.md").read_text()
    assert hp.headline_table(cv, "grid", [3]) in summary
    per = pd.read_csv(a / "per_sample.csv")
    assert len(per) == 3 * 25
    # each held-out sample's line residuals have the RMS cross_validate reports for it
    r = per[[f"line_residual_mm_{i}" for i in range(1, 5)]].to_numpy()
    assert np.allclose(np.sqrt(np.mean(r**2, axis=1)), per.line_rms_mm, rtol=1e-5)


def test_the_tracked_table_has_every_row_and_column():
    """results/hangprinter/cv.csv (make reproduce) has every data set × model × fold count of the
    study, its columns, and a finite held-out position RMS in every row."""
    st = hp.load_hangprinter_study(STUDY, check_files=False)
    cv = pd.read_csv(ROOT / "results" / "hangprinter" / "cv.csv")
    assert list(cv.columns) == CV_COLUMNS
    n = {ds: len(pd.read_csv(ROOT / d["data"])) for ds, d in st["data_sets"].items()}
    expected = [
        (ds, name, n[ds] if k == "leave-one-out" else k)
        for ds, d in st["data_sets"].items()
        for name in d["models"]
        for k in st["folds"]
    ]
    assert list(zip(cv.data_set, cv.model, cv.folds)) == expected
    assert np.isfinite(cv.heldout_line_rms_mm).all()
    # a finite held-out position RMS exactly where the session has measured positions
    measured = {ds: pd.read_csv(ROOT / d["data"]).x_m.notna().any() for ds, d in st["data_sets"].items()}
    assert (np.isfinite(cv.heldout_position_rms_mm) == cv.data_set.map(measured)).all()
    assert set(measured.values()) == {True, False}  # HP3 has none


def test_the_docs_quote_the_pipeline_table():
    """docs/hangprinter.md carries the study's table of each session as the pipeline writes it."""
    st = hp.load_hangprinter_study(STUDY, check_files=False)
    cv = pd.read_csv(ROOT / "results" / "hangprinter" / "cv.csv")
    docs = (ROOT / "docs" / "hangprinter.md").read_text()
    for ds in st["data_sets"]:
        assert hp.headline_table(cv, ds, st["folds"]) in docs, ds


@pytest.mark.parametrize(
    "old, new, key",
    [
        ("folds: [3]", "folds: [1]", "folds"),
        ("folds: [3]", "folds: [3]\nextra: 1", "extra"),
        ("fixed: tool,", "fixed: other,", "models.tool.fixed"),
        ("estimate: [anchors, spools]}", "estimate: [anchors, gear]}", "models.rigid_spools.estimate"),
        ("model: standard, estimate", "model: stiff, estimate", "models.rigid_spools.model"),
        ("hp4_2021_12_grid.json", "missing.json", "data_sets.grid.source"),
        ("    tool: data/hangprinter/tool_hp4_2021_12_grid.yaml\n", "", "data_sets.grid.models"),
        (
            "    source: data/hangprinter/hp4_2021_12_grid.json\n",
            "    source: data/hangprinter/hp4_2021_12_grid.json\n    models: [other]\n",
            "data_sets.grid.models",
        ),
    ],
)
def test_a_bad_study_is_refused_in_one_line(at_root, tmp_path, old, new, key):
    assert old in SMALL
    study = tmp_path / "bad.yaml"
    study.write_text(SMALL.replace(old, new))
    with pytest.raises(ConfigError) as exc:
        hp.load_hangprinter_study(study)
    assert exc.value.key == key and "\n" not in str(exc.value)


def test_the_buildup_prior_of_a_study(at_root):
    """A study's ``buildup`` prior sd reaches the buildup factors only; without it the default."""
    idx = motor_index(4, ["anchors", "spools"])
    sd = motor_prior_sd(4, idx, {"anchors": 0.15, "spools": 1e-3})
    wide = motor_prior_sd(4, idx, {"anchors": 0.15, "spools": 1e-3, "buildup": 5e-4})
    assert np.all(sd[16:] == BUILDUP_PRIOR_SD) and np.all(wide[16:] == 5e-4)
    assert np.array_equal(sd[:16], wide[:16])
    with pytest.raises(CdprError, match="buildup factor"):
        motor_prior_sd(4, idx, {"anchors": 0.15, "spools": 1e-3, "buildup": 0.0})
    robot = load_robot("config/robots/hangprinter_hp4.yaml")
    assert hp.is_hangprinter_study(STUDY) and not hp.is_hangprinter_study(
        ROOT / "config/studies/calibration.yaml"
    )
    assert cal.SpoolModel.of(robot).Q.shape == (4,)


def test_the_gear_ratio_is_not_seen_by_motor_angles():
    """Why there is no ``gear`` group: L/H scaled by c with r0 by 1/c and Q by 1/c^2 gives the same
    line for every motor angle (s = r0 phi - O Q phi^2 / 4, phi = theta L / H), to round-off."""
    robot = load_robot(ROOT / "config" / "robots" / "hangprinter_hp4.yaml")
    sm = cal.SpoolModel.of(robot)
    data = cal.read_motor_data(ROOT / "data" / "hangprinter" / "hp4_2022_force_series2_cdpr.csv", robot)
    f, g = np.ones(data.motor_deg.shape), np.ones(robot.m)
    c = 1.37
    other = dataclasses.replace(sm, ratio=sm.ratio * c, r0=sm.r0 / c, Q=sm.Q / c**2)
    a, _ = line_terms(sm, data.motor_deg, f, g)
    b, _ = line_terms(other, data.motor_deg, f, g)
    assert np.abs(a - b).max() < 1e-12
    changed = dataclasses.replace(sm, ratio=sm.ratio * c)  # the ratio alone does change the lines
    assert np.abs(line_terms(changed, data.motor_deg, f, g)[0] - a).max() > 0.1
