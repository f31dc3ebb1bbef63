"""The paper's conclusions on another robot (cdpr.pipeline.conclusions): the statements evaluated
on the committed results of the paper's study in physical mode (CDPR4) and of CoGiRo's study."""

import json
import shutil

import numpy as np
import pandas as pd
import pytest

from cdpr.errors import ConfigError
from cdpr.pipeline import conclusions as cc
from cdpr.pipeline.results import Layout
from cdpr.pipeline.study import load_study
from cdpr.validation import read_yaml
from tests.conftest import ROOT
from tests.quick_runs import make_workdir, snakemake

TABLES = ("doe/doe.csv", "doe/effects.csv", "maps/lines.csv", "elasticity/bands.csv", "volumes/volumes.csv")


def _folder(tmp_path, name, st, scale_dr=1.0):
    """The committed tables of results/<name> copied to tmp_path, with plane tables written from the
    study's plane: ‖δp‖ = 0.1 m + 0.05 m x (SR) and, for DR, that times ``scale_dr``."""
    out = tmp_path / name
    for rel in TABLES:
        (out / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / "results" / name / rel, out / rel)
    x = np.linspace(0.0, 1.0, 5)
    kinds = {spec["kind"]: key for key, spec in st["pulleys"].items()}
    for kind, key in kinds.items():
        dp = (0.1 + 0.05 * x) * (scale_dr if kind == "DR" else 1.0)
        path = out / Layout(st, out).relative("plane_table", "table", robot=st["doe"]["robot"], pulley=key)
        path.parent.mkdir(parents=True, exist_ok=True)
        pd.DataFrame({"status": "ok", "dp": dp}).to_csv(path, index=False)
    return out


@pytest.fixture(scope="module")
def studies():
    return load_study(ROOT / "config/studies/physical.yaml"), load_study(ROOT / "config/studies/cogiro.yaml")


def test_a_robot_against_itself_never_reverses(tmp_path, studies):
    ref, _ = studies
    res = _folder(tmp_path, "physical", ref, scale_dr=0.5)
    rows = cc.robot_conclusions(ref, res, ref, res)
    assert set(rows.verdict) <= {"holds", "undetermined"}, rows[["quantity", "verdict"]]
    claimed = rows.dropna(subset=["claim_reference"])
    assert (claimed.claim_reference == claimed.claim_robot).all()
    assert (rows.verdict == "holds").sum() >= 10


def test_verdicts_follow_the_tables(tmp_path, studies):
    ref_st, st = studies
    ref = _folder(tmp_path, "physical", ref_st, scale_dr=0.5)
    rob = _folder(tmp_path, "cogiro", st, scale_dr=2.0)  # DR worse than SR on CoGiRo's plane
    rows = cc.robot_conclusions(ref_st, ref, st, rob).set_index("quantity")
    plane = rows.loc["plane max ‖δp‖ DR / SR"]
    assert plane.reference == pytest.approx(0.5) and plane.robot == pytest.approx(2.0)
    assert (plane.claim_reference, plane.claim_robot, plane.verdict) == (True, False, "reverses")
    assert plane.verdict_paper == "reverses"
    # the DOE rows read the tables: best and worst test by the global index
    for name, res, col in ((ref_st, ref, "reference"), (st, rob, "robot")):
        d = pd.read_csv(res / "doe/doe.csv")
        best, worst = int(d.loc[d.index_m.idxmin(), "test"]), int(d.loc[d.index_m.idxmax(), "test"])
        assert rows.loc["DOE best and worst tests", col] == f"best {best}, worst {worst}"
    # the spatial effects table has the δφ index's rows too: the ‖δp‖ ones are read
    e = pd.read_csv(rob / "doe/effects.csv")
    e = e[(e.response == "index_m") & (e.term != "mean")].set_index("term").effect
    assert rows.loc["largest DOE effect", "robot"] == e.abs().idxmax()
    assert rows.loc["effect joint", "robot"] == pytest.approx(e["joint"] * 1e3)
    # a missing optimal line gives undetermined, not a verdict
    lines = pd.read_csv(rob / "maps/lines.csv").set_index("kind")
    slope = rows.loc["D_DR slope h / r_p"]
    assert np.isnan(lines.loc["DR", "slope_k"]) == (slope.verdict == "undetermined")


def test_the_page_lists_every_headline_statement(tmp_path, studies):
    ref_st, st = studies
    ref = _folder(tmp_path, "physical", ref_st)
    rob = _folder(tmp_path, "cogiro", st)
    rows = cc.robot_conclusions(ref_st, ref, st, rob)
    page = cc.conclusions_page(ref_st, st, rows)
    head = page.split("## Headline")[1].split("## Every row")[0]
    for statement in rows[rows.headline].statement:
        assert statement in head
    assert "nan" not in page and "None" not in page
    assert page.count("\n| ") == int(rows.headline.sum()) + len(rows) + 2  # two header rows


def test_only_a_study_that_names_a_reference_has_the_rule(studies):
    ref_st, st = studies
    assert "conclusions" in Layout(st, "results/cogiro").rules()
    assert "conclusions" not in Layout(ref_st, "results/physical").rules()


def test_bad_reference_is_one_line(tmp_path):
    data = read_yaml(ROOT / "config/studies/cogiro.yaml")
    bad = tmp_path / "cogiro.yaml"
    for ref, words in (
        ("config/studies/nope.yaml", "conclusions.study"),
        (str(bad), "the reference study is this study"),
    ):
        data["conclusions"] = {"study": ref, "results": "results/physical"}
        bad.write_text(json.dumps(data))  # JSON is YAML
        with pytest.raises(ConfigError, match=words) as exc:
            load_study(bad)
        assert "\n" not in str(exc.value)


def test_an_unrun_reference_stops_the_workflow_in_one_line(tmp_path):
    work = make_workdir(tmp_path / "w")
    text = (ROOT / "config/studies/cogiro.yaml").read_text()
    (work / "studies" / "cogiro.yaml").write_text(
        text.replace("results: results/physical", "results: results/nowhere")
    )
    p = snakemake(
        "reproduce_paper", "study=studies/cogiro.yaml", "results=results/cogiro", cwd=work, extra=("-n",)
    )
    assert p.returncode != 0
    line = next(li for li in (p.stdout + p.stderr).splitlines() if "invalid study configuration" in li)
    assert (
        "studies/cogiro.yaml: conclusions.results: results/nowhere" in line and "run the study first" in line
    )
