"""A whole spatial study with the study key ``wrench`` (``SolverOptions.wrench``): the quick spatial study
(CoGiRo) run through the jobs Snakemake's rules call (``tasks.uq_shard``, ``tasks.uq_design``,
``tasks.study_budget_design``, ``tasks.study_budget``) on a tiny grid, with no wrench, a zero wrench and
a downward force of half the platform's weight. The zero wrench writes the wrench-free files byte for
byte; the force reaches every solve: the compensated nominal robot still reaches its poses (the
compensation and the solves see the same load), the linearised propagation still agrees with the full
solves, the budget's elasticity entry grows with the load as Hooke's law says; and Snakemake reruns
every job that solves a robot of the study when the wrench changes (the key is among their params)."""

import json
import os
from pathlib import Path

import numpy as np
import pytest
import yaml

from cdpr import table_io
from cdpr.pipeline import study, tasks
from cdpr.pipeline.results import Layout
from tests.conftest import ROOT
from tests.pipeline.test_shell import _scheduled
from tests.quick_runs import make_workdir, snakemake

QUICK_SPATIAL = ROOT / "config" / "studies" / "quick_spatial.yaml"
BOX = [-3.0, 3.0, -2.0, 2.0, 1.0, 3.5]  # inside CoGiRo's RW_C
#: The budget's box: its 2^3 points are ok in every entry of both designs (tests/pipeline/test_study_budget.py).
BUDGET_BOX = [-0.4, 0.4, -0.4, 0.4, 2.4, 3.0]
#: CoGiRo's weight [N] (config/robots/cogiro.yaml: 91.058 kg, g = 9.81 m/s^2) and the study's loads.
WEIGHT = 91.058 * 9.81
WRENCHES = {"none": None, "zero": [0.0] * 6, "down": [0.0, 0.0, -0.5 * WEIGHT, 0.0, 0.0, 0.0]}
CASES = ("uncompensated", "compensated")
#: The files of one design and case of the uncertainty jobs, and of the budget jobs.
UQ_FILES = ("samples", "points", "table", "path", "sobol", "tolerances", "map")


def _variant(tmp_path, wrench):
    """The quick spatial study with the uncertainty study cut down, a budget, and ``wrench``."""
    data = yaml.safe_load(QUICK_SPATIAL.read_text(encoding="utf-8"))
    data["robots"] = {k: str(ROOT / v) for k, v in data["robots"].items()}
    data["budget"] = {"index_n": 2, "t_min_N": 100.0}
    uq = data["uncertainty"]
    uq["monte_carlo"].update(samples=6, full_samples=2, index_n=2)
    uq["sobol"].update(base_samples=2, index_n=2)
    uq["map_n"] = 3
    if wrench is not None:
        data["wrench"] = wrench
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return study.load_study(path)


def _run(tmp_path, wrench):
    """Every uncertainty and budget job of the study with ``wrench``; the folder of their files."""
    tmp_path.mkdir()
    st = _variant(tmp_path, wrench)
    box = tmp_path / "rw_c.json"
    box.write_text(json.dumps({"box": BOX}), encoding="utf-8")
    for case in CASES:
        f = {k: tmp_path / f"{case}_{k}.csv" for k in UQ_FILES}
        tasks.uq_shard(st, "SRopt", case, 0, box, f["samples"], f["points"])
        tasks.uq_design(st, "SRopt", case, box, f["table"], f["path"], f["sobol"], f["tolerances"], f["map"])
    designs = [tmp_path / f"{d}.csv" for d in st["optimal"]]  # the stem is the design (tasks.study_budget)
    budget_box = tmp_path / "budget_box.json"
    budget_box.write_text(json.dumps({"box": BUDGET_BOX}), encoding="utf-8")
    for d, t in zip(st["optimal"], designs):
        tasks.study_budget_design(st, d, budget_box, t)
    tasks.study_budget(st, designs, tmp_path / "budget.csv", tmp_path / "budget.png")
    return tmp_path


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    root = tmp_path_factory.mktemp("wrench_study")
    return {k: _run(root / k, w) for k, w in WRENCHES.items()}


def _tables(folder):
    return sorted(p.name for p in folder.glob("*.csv"))


def test_a_zero_wrench_writes_the_wrench_free_files_byte_for_byte(runs):
    names = _tables(runs["none"])
    assert len(names) == 2 * len(UQ_FILES) + 3 and names == _tables(runs["zero"])
    for n in names:
        assert (runs["zero"] / n).read_bytes() == (runs["none"] / n).read_bytes(), n


def test_the_force_reaches_every_job(runs):
    for n in _tables(runs["none"]):
        assert (runs["down"] / n).read_bytes() != (runs["none"] / n).read_bytes(), n


def _read(runs, key, name):
    return table_io.read_table(runs[key] / name)


def test_compensation_and_solves_see_the_same_load(runs):
    """Lengths compensated with the nominal parameters under the wrench hold the nominal robot at its
    poses under that wrench (had either ignored it the nominal error would be the load's sag); the
    uncompensated nominal error moves by millimetres (down: 0.1501 -> 0.1427 m: CoGiRo's L_TS error is
    not the cables' sag alone, so its norm need not grow; the budget's elasticity entry does, below)."""
    for key in ("none", "down"):
        lin = _read(runs, key, "compensated_table.csv")
        nom = lin[lin["sample"] == -1].iloc[0]
        assert nom.index_m < 1e-8 and nom.index_phi_rad < 1e-8, key
    free, down = (_read(runs, k, "uncompensated_table.csv") for k in ("none", "down"))
    nom_free, nom_down = (t[t["sample"] == -1].iloc[0] for t in (free, down))
    assert abs(nom_down.index_m - nom_free.index_m) > 1e-3
    # the full solves of the first samples and their linearised propagation agree under the load
    pts = _read(runs, "down", "uncompensated_points.csv")
    samples = _read(runs, "down", "uncompensated_samples.csv")
    lin = down[down["sample"] >= 0].reset_index(drop=True)
    np.testing.assert_allclose(lin.index_m[: len(samples)], samples.index_full_m, rtol=2e-2)
    assert (pts["max_diff_m"] < 1e-3).all()


def test_the_budget_elasticity_grows_with_the_load_as_hooke_says(runs):
    """The cables' stretch is their tension over their stiffness and a vertical force on a platform whose
    centre of mass is near p scales every tension by (M g + F) / (M g): so does the elasticity entry
    (to first order: the tensions move with the pose by a few per mille). The budget's means are over the
    points ok in every entry, so the ratio is taken where both runs have the same points: DRopt's 8
    (SRopt's pulley entry, rigid cables, does not converge at 2 of its 8 points without a load and at
    1 with it, by the default engine). The compensated budget stays at round-off: its model knows the
    load."""
    free, down = (_read(runs, k, "budget.csv").set_index(["design", "entry"]) for k in ("none", "down"))
    for design in free.index.unique("design"):
        assert (
            free.loc[(design, "elasticity"), "entry_ok_points"]
            == 8
            == down.loc[(design, "elasticity"), "entry_ok_points"]
        )
        assert down.loc[(design, "compensated_all"), "mean_m"] < 1e-9
    assert (free.xs("DRopt").ok_points == 8).all() and (down.xs("DRopt").ok_points == 8).all()
    ratio = down.loc[("DRopt", "elasticity"), "mean_m"] / free.loc[("DRopt", "elasticity"), "mean_m"]
    assert ratio == pytest.approx(1.5, rel=0.02)


#: The rules of the quick spatial study (with a budget) whose jobs solve a robot of the study, each with
#: ``"wrench"`` among its ``uses`` params (workflow/rules/*.smk).
SOLVING_RULES = {
    "workspace_grid",
    "regular_workspace",
    "index_shard",
    "map_kind",
    "maps",
    "plane_table",
    "trajectory_table",
    "volume_shard",
    "elasticity_shard",
    "elasticity_path",
    "dead_length_point",
    "uq_shard",
    "uq_design",
    "study_budget_design",
}


def _dry_run_rules(work, config):
    p = snakemake(
        "reproduce_paper", *config, cwd=work, quiet=False, force=False, extra=["-n", "--quiet", "rules"]
    )
    return _scheduled(p)


def test_snakemake_reruns_every_solving_job_when_the_wrench_changes(tmp_path):
    """Every output of the study is put in place empty and recorded by ``--touch`` (no job runs), so
    Snakemake holds each job's params; adding a wrench to the study file then schedules every job
    that solves a robot (and what follows from them), and not the winch seed's, which has no robot."""
    work = make_workdir(tmp_path / "work", studies=())
    data = yaml.safe_load(QUICK_SPATIAL.read_text(encoding="utf-8"))
    data["budget"] = {"index_n": 2, "t_min_N": 100.0}
    path = work / "studies" / "study.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    config = ["study=studies/study.yaml", "results=results/s"]
    cwd = os.getcwd()
    os.chdir(work)
    try:
        for f in Layout(study.load_study(path), "results/s").targets():
            Path(f).parent.mkdir(parents=True, exist_ok=True)
            Path(f).touch()
    finally:
        os.chdir(cwd)
    p = snakemake("reproduce_paper", *config, cwd=work, force=True, extra=["--touch"])
    assert p.returncode == 0, p.stderr[-2000:]
    assert _dry_run_rules(work, config) == set()
    data["wrench"] = WRENCHES["down"]
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    rules = _dry_run_rules(work, config)
    assert SOLVING_RULES <= rules, sorted(SOLVING_RULES - rules)
    assert not rules & {"winch_table", "winch_figure"}, rules
