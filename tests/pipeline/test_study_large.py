"""The large study (issue 38, config/studies/large.yaml): cube50 with heavy cables beside its
massless twin. Its file validates, its `sag` section is checked before any work, its two robot
files differ only in the cable's weight, and a dry run of `large_study` (what `make reproduce` asks
of it) lists the plane maps, the paths and the two sag rules, nothing of the DOE."""

import subprocess
import sys
from pathlib import Path

import pytest

from cdpr.errors import ConfigError
from cdpr.pipeline.results import Layout
from cdpr.pipeline.study import load_study
from tests.conftest import ROOT
from tests.quick_runs import make_workdir, rule_jobs

LARGE = ROOT / "config" / "studies" / "large.yaml"


@pytest.fixture
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)


def test_large_study_validates(at_root):
    st = load_study(LARGE)
    assert st["redundancy"] == "physical"
    models = st.robot_models
    assert models[st["sag"]["robot"]].heavy and not models[st["sag"]["massless"]].heavy
    # the section 3.3.1 path of CDPR4 scaled x10, on both robots
    for key in (st["sag"]["robot"], st["sag"]["massless"]):
        assert st["trajectories"]["paths"][key] == {"start_m": [-25.0, 0.0, 0.0], "end_m": [25.0, 0.0, 50.0]}
    rules = {Path(p).parent.name for p in Layout(st, "results/large").large_targets()}
    assert rules == {"plane", "trajectories", "sag", "budget"}


@pytest.mark.parametrize(
    "old, new, key",
    [
        ("  robot: Cube50               # the heavy robot", "  robot: Cube50w0", "sag.robot"),
        ("  massless: Cube50w0          # its massless twin", "  massless: Cube50", "sag.massless"),
        ("  robot: Cube50               # the heavy robot", "  robot: Nope", "sag.robot"),
    ],
)
def test_bad_sag_section_is_one_line_naming_the_key(at_root, tmp_path, old, new, key):
    text = LARGE.read_text()
    assert old in text
    bad = tmp_path / "large.yaml"
    bad.write_text(text.replace(old, new))
    with pytest.raises(ConfigError) as exc:
        load_study(bad)
    assert f"'{key}'" in str(exc.value) and "\n" not in str(exc.value)


def test_dry_run_lists_the_large_rules(tmp_path):
    work = make_workdir(tmp_path / "work", studies=("large",))
    exe = Path(sys.executable).with_name("snakemake")
    p = subprocess.run(
        [str(exe), "--snakefile", str(ROOT / "Snakefile"), "large_study", "-n", "--quiet", "rules", "--cores", "1",
         "--config", "study=studies/large.yaml", "results=results/large"],
        cwd=work, capture_output=True, text=True,
    )  # fmt: skip
    jobs = rule_jobs(p)
    assert jobs == {
        "plane_table": 2, "plane_figure": 2, "trajectory_table": 2, "trajectory_figure": 1,
        "sag_path": 1, "sag_corner": 1, "large_study": 1,
        # the error budget on RW_C (doe.rw_c: paper) and the DOE workspace grids its box job reads
        "study_budget_design": 1, "study_budget": 1, "regular_workspace": 1, "workspace_grid": 8,
    }  # fmt: skip
