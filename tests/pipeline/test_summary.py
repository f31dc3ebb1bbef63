"""The papers' numbers beside ours (cdpr.pipeline.summary): the verdict rule at its boundaries, the
paper-values file well formed (every extractor known, a number or none where the paper prints none,
each quantity once), and build_rows on a results folder holding only what a test writes: the rows
whose tables exist, our numbers from the models (the winch's physical root passes through
(l_pm0, q0); its length error at both ends of Métillon's Fig. 7b), and no score for a study that is
not the paper's."""

import math

import numpy as np
import pytest

from cdpr import table_io
from cdpr.analyses import scans
from cdpr.models import winch
from cdpr.pipeline import study, summary
from cdpr.pipeline.results import rel_path
from cdpr.robot import TABLE1
from tests.conftest import ROOT


@pytest.fixture
def st(monkeypatch):
    monkeypatch.chdir(ROOT)  # robot paths of the study files are relative to the repository
    return study.load_study(ROOT / "config" / "studies" / "quick.yaml")


def test_verdict_at_the_boundaries():
    assert summary.verdict(1.0, 1.25, 0.25) == "reproduced"  # |ours - paper| = tolerance, exactly
    assert summary.verdict(1.0, 0.75, 0.25) == "reproduced"
    assert summary.verdict(1.0, 1.2500001, 0.25) == "not reproduced"
    assert (
        summary.verdict(1.0, 2.0, 0.25, "the figure is read by eye")
        == "not reproduced (the figure is read by eye)"
    )
    for ours in (None, math.nan, math.inf):
        assert summary.verdict(1.0, ours, 10.0).startswith("not reproduced")
    assert summary.verdict(None, 1.0, 0.1) == "no paper value"
    assert summary.verdict(1.0, 1.0, 0.1, "another experiment", scored=False) == (
        "beside the paper, not scored (another experiment)"
    )


def test_the_paper_values_are_well_formed():
    values = summary.paper_values()
    assert len(values) > 50
    for v in values:
        assert {"quantity", "source", "value", "unit", "tolerance", "ours"} <= set(v), v
        assert v["ours"]["kind"] in summary.EXTRACTORS, v
        assert v["tolerance"] >= 0 and (v["value"] is None or isinstance(v["value"], (int, float))), v
        assert v.get("scored", True) or v.get("reason"), v  # an unscored row says why
    keys = [(v["quantity"], v["source"]) for v in values]
    assert len(set(keys)) == len(keys)


def test_rows_come_only_from_tables_that_exist_and_from_the_models(st, tmp_path):
    """An empty results folder: the path lengths of the study file and the winch root, no more."""
    df = summary.build_rows(st, tmp_path)
    assert list(df.columns) == summary.COLUMNS
    assert list(df["quantity"]) == ["CDPR3 path length", "CDPR4 path length", "winch q1 at l_pm0"]
    paths = st["trajectories"]["paths"]
    for robot in ("CDPR3", "CDPR4"):
        row = df[df["quantity"] == f"{robot} path length"].iloc[0]
        length = np.linalg.norm(np.subtract(paths[robot]["end_m"], paths[robot]["start_m"]))
        assert row["ours"] == pytest.approx(length, rel=1e-15) and row["verdict"] == "reproduced"
    # the physical root passes through (l_pm0, q0): Métillon's drum starts there
    q1 = df[df["quantity"] == "winch q1 at l_pm0"].iloc[0]
    assert q1["ours"] == pytest.approx(TABLE1.q0, abs=1e-9) and q1["verdict"] == "reproduced"


def test_the_winch_rows_read_the_winch_table(st, tmp_path):
    path = tmp_path / rel_path("winch_table")
    table_io.write_table(scans.winch_table(TABLE1, 0.0, 5.0, 501), path)
    df = summary.build_rows(st, tmp_path).set_index("quantity")
    for l_pm, name in ((0.0, "winch dl at l_pm = 0"), (5.0, "winch dl at l_pm = 5 m")):
        assert df.loc[name, "ours"] == pytest.approx(1e3 * winch.length_error(TABLE1, l_pm), abs=1e-9)
        assert df.loc[name, "unit"] == "mm" and df.loc[name, "verdict"] == "reproduced"
    # a drum whose length error is off by 0.1 mm: not reproduced
    table = scans.winch_table(TABLE1, 0.0, 5.0, 501)
    table_io.write_table(table.assign(dl=table["dl"] + 1e-4), path)
    assert summary.build_rows(st, tmp_path).set_index("quantity").loc["winch dl at l_pm = 0", "verdict"] == (
        "not reproduced"
    )


def test_a_study_that_is_not_the_paper_s_is_not_scored(st, tmp_path):
    df = summary.build_rows(dict(st, paper_comparison=False), tmp_path)
    assert len(df) == 3 and df["paper"].isna().all() and df["tolerance"].isna().all()
    assert set(df["verdict"]) == {"not scored (not the paper's study)"}


def test_hold_note_says_how_the_platform_holds_not_only_how_many_are_ok():
    """Issue 41: "121 of 121 ok" on a platform hanging on 4-5 of 8 cables tilted 38 degrees hid both
    facts; the note counts the ok points on fewer cables than the degrees of freedom, the largest
    δφ and every other status."""
    import pandas as pd

    from cdpr.pipeline.summary import hold_note

    df = pd.DataFrame(
        {
            "status": ["ok", "ok", "ok", "out_of_frame"],
            "n_taut": [8, 5, 4, 3],
            "dphi": [0.001, 0.2, 0.66, 1.36],
        }
    )
    note = hold_note(df, 6)
    assert note.startswith("3 of 4 points ok; 2 of the ok points hang on fewer than 6 cables")
    assert "largest δφ 660 mrad" in note  # the ok points only
    assert note.endswith("not ok: 1 out_of_frame")
    assert hold_note(df.assign(status="ok"), 3).startswith("4 of 4 points ok; 0 of the ok")


def _sobol_table(res, conf, ST=0.5, n=4):
    import pandas as pd

    t = pd.DataFrame(
        {
            "design": "SRopt",
            "case": "uncompensated",
            "output": "index",
            "level": "parameter",
            "name": ["E_1", "d_1", "A_1"],
            "S1": [0.2, 0.1, -0.05],
            "S1_conf": [conf / 2, conf / 2, conf / 2],
            "ST": [ST, 0.3, 0.1],
            "ST_conf": [conf, conf / 2, conf / 3],
            "base_samples": n,
        }
    )
    path = res / rel_path("uncertainty", "sobol")
    path.parent.mkdir(parents=True, exist_ok=True)
    table_io.write_table(t, path)


def test_sobol_indices_get_their_bootstrap_basis_and_a_caveat_when_few(st, tmp_path):
    """Issue 41: "a total index of 1.06 > 1 with 16 base samples" was quoted without its interval:
    the note gives the 95 % bootstrap half-widths and N; a caveat line when N is small or an
    interval is wide, none for a well-sampled study."""
    _sobol_table(tmp_path, conf=0.3, ST=1.06, n=st["uncertainty"]["sobol"]["base_samples"])
    value, note = summary._uq_sobol_top(st, tmp_path, "SRopt", "uncompensated")
    assert value == 1.06 and note.startswith("largest ST: E_1 1.06±0.30, d_1 0.30±0.15")
    assert note.endswith(f"(±: 95 % bootstrap, N = {st['uncertainty']['sobol']['base_samples']})")
    caveat = summary.sobol_caveat(st, tmp_path)
    assert caveat.startswith(
        f"Caveat: the Sobol indices rest on N = {st['uncertainty']['sobol']['base_samples']}"
    )
    assert "reach ±0.3" in caveat and "2 of the 3 indices lie outside [0, 1]" in caveat
    big = dict(st["uncertainty"]["sobol"], base_samples=summary.SOBOL_SMALL_N)
    st["uncertainty"]["sobol"] = big
    _sobol_table(tmp_path, conf=0.03, n=summary.SOBOL_SMALL_N)
    assert summary.sobol_caveat(st, tmp_path) is None  # enough samples, narrow intervals
    _sobol_table(tmp_path, conf=0.3, n=summary.SOBOL_SMALL_N)
    assert summary.sobol_caveat(st, tmp_path) is not None  # an interval too wide, whatever N
