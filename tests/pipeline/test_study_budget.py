"""The error budget of a spatial study (study key ``budget``; rules study_budget_design, study_budget):
the key is refused for a paper-mode point-mass study in one line (a physical-mode point-mass study,
e.g. the large study, has it), gates the rules' jobs, and its two jobs write
the per-design table (position and orientation, every entry) and the stacked bars."""

import functools
import json

import numpy as np
import pytest
import yaml

from cdpr import table_io
from cdpr.analyses import budget
from cdpr.pipeline import study, summary, tasks
from cdpr.pipeline.results import Layout
from tests.conftest import ROOT

QUICK = ROOT / "config" / "studies" / "quick.yaml"
QUICK_SPATIAL = ROOT / "config" / "studies" / "quick_spatial.yaml"
QUICK_PHYSICAL = ROOT / "config" / "studies" / "quick_physical.yaml"
LARGE = ROOT / "config" / "studies" / "large.yaml"
KEY = {"index_n": 2, "t_min_N": 100.0}


def _variant(src, tmp_path, **changes):
    data = yaml.safe_load(src.read_text(encoding="utf-8"))
    data["robots"] = {k: str(ROOT / v) for k, v in data["robots"].items()}
    data.update(changes)
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def test_a_point_mass_study_refuses_the_key_in_one_line(tmp_path):
    path = _variant(QUICK, tmp_path, budget=KEY)
    with pytest.raises(study.ConfigError) as err:
        study.load_study(path)
    message = str(err.value)
    assert "\n" not in message and str(path) in message and "key 'budget'" in message
    assert "point mass" in message and "comparison" in message


def test_a_physical_point_mass_study_has_the_budget_in_position_only(tmp_path):
    """A point mass in physical mode (the large study's case): the key is accepted, and the job
    writes every entry in position only (no orientation columns); the compensation of all the
    effects leaves the physical equilibrium's round trip (<= 1e-9 m)."""
    st = study.load_study(_variant(QUICK_PHYSICAL, tmp_path, budget=KEY))
    assert st.robot_models[st["doe"]["robot"]].suspended_point_mass
    box = tmp_path / "rw_c.json"
    box.write_text(json.dumps({"box": [-0.5, 0.5, -0.5, 0.5, 1.5, 2.5]}), encoding="utf-8")
    d = next(iter(st["optimal"]))
    tasks.study_budget_design(st, d, box, tmp_path / f"{d}.csv")
    t = table_io.read_table(tmp_path / f"{d}.csv").set_index("entry")
    assert list(t.index) == [*budget.variants(), "interaction"]
    assert not any(c.endswith("_rad") for c in t.columns)
    assert (t.ok_points == 8).all() and t.loc["compensated_all", "max_m"] < 1e-9
    assert t.loc["pulley", "mean_m"] > 0 and t.loc["elasticity", "mean_m"] > 0


def test_the_large_study_asks_for_its_budget():
    """config/studies/large.yaml (heavy point mass, physical mode): make reproduce's target
    ``large_study`` includes the budget's table and figure."""
    lay = Layout(study.load_study(LARGE), "r")
    assert {"r/budget/budget.csv", "r/budget/budget.png"} <= set(lay.large_targets())
    assert lay.wildcards("study_budget_design") == [{"design": "SR"}]


def test_the_key_is_checked_by_the_schema(tmp_path):
    with pytest.raises(study.ConfigError, match="budget"):
        study.load_study(_variant(QUICK_SPATIAL, tmp_path, budget={"index_n": 1, "t_min_N": 100.0}))


def test_the_key_gates_the_jobs(tmp_path):
    plain = Layout(study.load_study(QUICK_SPATIAL), "r")
    assert plain.wildcards("study_budget_design") == [] and plain.wildcards("study_budget") == []
    assert "budget" not in plain.summary_inputs()
    st = study.load_study(_variant(QUICK_SPATIAL, tmp_path, budget=KEY))
    lay = Layout(st, "r")
    assert lay.wildcards("study_budget_design") == [{"design": d} for d in st["optimal"]]
    targets = lay.targets()
    assert {f"r/budget/{d}.csv" for d in st["optimal"]} | {
        "r/budget/budget.csv",
        "r/budget/budget.png",
    } <= set(targets)
    assert lay.summary_inputs()["budget"] == "r/budget/budget.csv"


def test_the_jobs_write_the_budget_of_every_design(tmp_path, monkeypatch):
    # the numpy reference of the 6-DoF solve: no kernel compilation in this file (the compiled twin
    # is tested equal to it to 1e-9 m and rad, tests/compiled/test_equilibrium_pose.py)
    monkeypatch.setattr(tasks.budget, "error_budget", functools.partial(budget.error_budget, engine="numpy"))
    st = study.load_study(_variant(QUICK_SPATIAL, tmp_path, budget=KEY))
    box = tmp_path / "rw_c.json"
    box.write_text(json.dumps({"box": [-0.4, 0.4, -0.4, 0.4, 2.4, 3.0]}), encoding="utf-8")
    tables = []
    for d in st["optimal"]:
        tables.append(tmp_path / f"{d}.csv")
        tasks.study_budget_design(st, d, box, tables[-1])
    t = table_io.read_table(tables[0]).set_index("entry")
    assert list(t.index) == [*budget.variants(), "interaction"]
    assert (t.points == 8).all() and (t.ok_points == 8).all() and (t.entry_ok_points == 8).all()
    assert (t.interfering_points == 0).all()  # RW_C at the identity: no cable interferes
    assert t.loc["compensated_all", "mean_m"] < 1e-9 and t.loc["compensated_all", "mean_rad"] < 1e-9
    assert t.loc["pulley", "mean_m"] > t.loc["winch", "mean_m"] > 0 and t.loc["pulley", "mean_rad"] > 0
    shares = t.loc[[*budget.EFFECTS, "interaction"], "share_m"].sum()
    assert shares == pytest.approx(t.loc["all", "mean_m"], rel=1e-9)
    out = tmp_path / "budget" / "budget.csv"
    out.parent.mkdir()
    tasks.study_budget(st, list(reversed(tables)), out, out.with_suffix(".png"))
    tab = table_io.read_table(out)
    assert list(dict.fromkeys(tab.design)) == list(st["optimal"])  # in the study's order
    assert out.with_suffix(".png").stat().st_size > 0 and out.with_suffix(".pdf").is_file()
    rows = summary._budget_rows(tmp_path)
    assert [r["quantity"] for r in rows[:4]] == [
        f"{next(iter(st['optimal']))} budget: {w}" for w in summary.BUDGET_TERMS.values()
    ]


def test_the_drum_key_defaults_to_table_1_and_is_checked_in_one_line(tmp_path):
    st = study.load_study(_variant(QUICK_SPATIAL, tmp_path, budget=KEY))
    assert study.budget_drum(st) == budget.TABLE1
    st = study.load_study(_variant(QUICK_SPATIAL, tmp_path, budget={**KEY, "drum": {"l_u0_m": 12.0}}))
    drum = study.budget_drum(st)
    assert drum.l_u0 == 12.0 and drum.k_w == budget.TABLE1.k_w and drum.q_max == budget.TABLE1.q_max
    for bad in ({"l_u0_m": -1.0}, {"radius_m": 0.1}):
        path = _variant(QUICK_SPATIAL, tmp_path, budget={**KEY, "drum": bad})
        with pytest.raises(study.ConfigError) as err:
            study.load_study(path)
        message = str(err.value)
        assert "\n" not in message and str(path) in message and "budget.drum" in message


def test_the_drum_goes_on_cables_without_a_winch_of_their_own():
    robot = study.load_study(QUICK_SPATIAL).robot_models["CoGiRo"]
    drum = study.params_from_mapping({"l_u0_m": 12.0}, "test")
    own = study.params_from_mapping({"l_u0_m": 7.0}, "test")
    mixed = budget.dataclasses.replace(
        robot, cables=(budget.dataclasses.replace(robot.cables[0], winch=own), *robot.cables[1:])
    )
    out = budget.with_drums(mixed, drum)
    assert out.cables[0].winch == own and all(c.winch == drum for c in out.cables[1:])
    # the drum decides the winch entries only: a longer uncoiled length at q0 moves the drum's
    # range of l_pm up by the same amount (l_pm = l_u0 + k_w (q0 - q) - |e(q) - a|, Métillon eq. 17)
    q = np.linspace(0.0, drum.q_max, 5)
    shift = budget.winch_model.l_pm_of_q(drum, q) - budget.winch_model.l_pm_of_q(budget.TABLE1, q)
    assert np.allclose(shift, 12.0 - budget.TABLE1.l_u0, atol=1e-12)


def test_the_linear_density_key_adds_the_sag_entries_and_the_summary_line(tmp_path, monkeypatch):
    """``budget.linear_density_kg_m`` > 0 (heavy cables, issue 38): the job's table gets the sag
    entries and the 95th percentiles, the heavy compensation leaves <= 1e-9 m, and the summary says
    what sag adds (mean, 95 %, max in mm and mrad); without the key nothing reads a density."""
    monkeypatch.setattr(tasks.budget, "error_budget", functools.partial(budget.error_budget, engine="numpy"))
    assert (
        study.budget_linear_density(study.load_study(_variant(QUICK_SPATIAL, tmp_path, budget=KEY))) is None
    )
    st = study.load_study(_variant(QUICK_SPATIAL, tmp_path, budget={**KEY, "linear_density_kg_m": 0.0631}))
    assert study.budget_linear_density(st) == 0.0631
    assert not st.robot_models["CoGiRo"].heavy  # the other analyses: the robot file's massless cables
    box = tmp_path / "rw_c.json"
    box.write_text(json.dumps({"box": [-0.4, 0.4, -0.4, 0.4, 2.4, 3.0]}), encoding="utf-8")
    d = next(iter(st["optimal"]))
    tasks.study_budget_design(st, d, box, tmp_path / f"{d}.csv")
    t = table_io.read_table(tmp_path / f"{d}.csv").set_index("entry")
    assert list(t.index) == [*budget.variants((*budget.EFFECTS, "sag")), "interaction"]
    assert list(t.columns[-4:]) == ["p95_m", "p95_rad", "entry_ok_points", "interfering_points"]
    assert (t.ok_points == 8).all()
    assert (
        0
        < t.loc["neglected_sag", "mean_m"]
        <= t.loc["neglected_sag", "p95_m"]
        <= t.loc["neglected_sag", "max_m"]
    )
    assert t.loc["neglected_sag", "mean_rad"] > 0
    assert t.loc["compensated_all", "max_m"] <= 1e-9 and t.loc["compensated_all", "max_rad"] <= 1e-9
    out = tmp_path / "budget" / "budget.csv"
    out.parent.mkdir()
    tasks.study_budget(st, [tmp_path / f"{d}.csv"], out, out.with_suffix(".png"))
    rows = {r["quantity"]: r for r in summary._budget_rows(tmp_path)}
    assert f"{d} budget: all four" in rows and f"{d} budget: cable sag alone" in rows
    line = rows[f"{d} budget: what cable sag adds (massless compensated lengths)"]
    assert line["ours"] == pytest.approx(t.loc["neglected_sag", "mean_m"] * 1e3)
    note = line["note"]
    for word in ("mean", "95 %", "max", " mm", " mrad", "heavy model leaves"):
        assert word in note
    assert f"{t.loc['neglected_sag', 'p95_m'] * 1e3:.3g}" in note


@pytest.mark.parametrize("bad", [-0.1, "63 g/m"])
def test_a_bad_linear_density_is_refused_in_one_line(tmp_path, bad):
    path = _variant(QUICK_SPATIAL, tmp_path, budget={**KEY, "linear_density_kg_m": bad})
    with pytest.raises(study.ConfigError) as err:
        study.load_study(path)
    message = str(err.value)
    assert "\n" not in message and str(path) in message and "linear_density_kg_m" in message
