"""Paper rule versus physics (cdpr.pipeline.comparison): the verdict rules and the comparison file checks.
The comparison of the quick study in both modes runs in tests/test_workflow.py."""

import pytest

from cdpr.errors import ConfigError
from cdpr.pipeline.comparison import load_comparison, verdict
from tests.conftest import ROOT

QUICK = ROOT / "config" / "comparisons" / "quick.yaml"


@pytest.mark.parametrize(
    "a,b,tol,claim,expected",
    [
        (1.0, 1.05, 0.1, None, "holds"),
        (1.0, 1.2, 0.1, None, "changes"),
        (0.5, 1.5, 0.1, (True, False), "reverses"),  # a DR/SR ratio crossing 1
        (0.5, 0.55, 0.1, (True, True), "holds"),
        (0.5, 0.9, 0.1, (True, True), "changes"),
        (-0.1, 0.01, 1.0, (True, False), "reverses"),  # within tolerance, but the statement flips
        ("joint:r_p", "joint:r_p", None, (True, True), "holds"),
        ("joint:r_p", "h", None, (True, False), "reverses"),
        ("1 < 6 < 3", "6 < 1 < 3", None, None, "changes"),
        (float("nan"), 1.0, 0.1, None, "undetermined"),
        (None, "x", None, None, "undetermined"),
    ],
)
def test_verdict_rules(a, b, tol, claim, expected):
    assert verdict(a, b, tol, claim) == expected


def test_quick_comparison_file_loads(monkeypatch):
    monkeypatch.chdir(ROOT)
    cmp = load_comparison(QUICK)
    assert cmp.paper_study["redundancy"] == "paper" and cmp.physical_study["redundancy"] == "physical"


@pytest.mark.parametrize(
    "edit,key,fragment",
    [
        (
            "config/studies/quick_physical.yaml",
            "physical.study",
            "expected a study with redundancy: physical",
        ),
        ("config/studies/physical.yaml", "physical.study", "differ only in name and redundancy"),
        ("config/studies/none.yaml", "physical.study", "cannot read the file"),
    ],
)
def test_bad_comparison_files_name_file_and_key(tmp_path, monkeypatch, edit, key, fragment):
    monkeypatch.chdir(ROOT)
    text = QUICK.read_text()
    if "quick_physical" in edit and "redundancy" in fragment:
        text = text.replace("study: config/studies/quick_physical.yaml", "study: config/studies/quick.yaml")
    else:
        text = text.replace("config/studies/quick_physical.yaml", edit)
    bad = tmp_path / "cmp.yaml"
    bad.write_text(text)
    with pytest.raises(ConfigError) as exc:
        load_comparison(bad)
    msg = str(exc.value)
    assert msg.startswith(f"{bad}: key '{key}'") and fragment in msg and len(msg.splitlines()) == 1, msg


def test_schema_errors_name_the_key(tmp_path):
    bad = tmp_path / "cmp.yaml"
    bad.write_text(QUICK.read_text().replace("index_n: 6", "index_n: 1"))
    with pytest.raises(ConfigError, match="key 'budget.index_n': must be >= 2"):
        load_comparison(bad)


def test_each_study_runs_its_uncertainty_in_its_own_mode_but_nothing_else_may_differ(tmp_path, monkeypatch):
    """uncertainty.redundancy may differ between the two studies (issue 21: the physical study is
    physical throughout); any other uncertainty key may not."""
    monkeypatch.chdir(ROOT)
    cmp = load_comparison(QUICK)
    assert cmp.physical_study["uncertainty"]["redundancy"] == "physical"
    assert cmp.paper_study["uncertainty"]["redundancy"] == "paper"
    text = (ROOT / "config/studies/quick_physical.yaml").read_text()
    bad_study = tmp_path / "qp.yaml"
    bad_study.write_text(text.replace("seed: 20210304", "seed: 1"))
    bad = tmp_path / "cmp.yaml"
    bad.write_text(QUICK.read_text().replace("config/studies/quick_physical.yaml", str(bad_study)))
    with pytest.raises(ConfigError) as exc:
        load_comparison(bad)
    assert "they differ in uncertainty" in str(exc.value)
