"""The results folder (cdpr.pipeline.results): the layout against the Snakemake DAG, the summary's
refusal of a missing or incomplete folder, and the study sizes load_study refuses before any job."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from cdpr.errors import CdprError, ConfigError
from cdpr.pipeline import results
from cdpr.pipeline.results import (
    CALIBRATION_FOLDERS,
    CALIBRATION_LOGS,
    CALIBRATION_OUTPUTS,
    STUDY_LOGS,
    STUDY_OUTPUTS,
    ComparisonLayout,
    Layout,
    calibration_outputs,
    rel_path,
)
from cdpr.pipeline.study import MAX_SHARDS, load_study
from tests.conftest import ROOT
from tests.quick_runs import make_workdir, rule_jobs

QUICK = ROOT / "config" / "studies" / "quick.yaml"


@pytest.fixture
def at_root(monkeypatch):
    monkeypatch.chdir(ROOT)  # robot paths of the study files are relative to the repository


@pytest.fixture
def work(tmp_path):
    """Snakemake's working folder: outside the tree (Snakemake writes .snakemake/ there, even for a dry
    run), with ``config/`` linked to the repository's, so that config/studies/... and the study files'
    robot paths resolve as from the repository (``make_workdir``)."""
    return make_workdir(tmp_path / "work", studies=())


def _snakemake(work, *args):
    """Run the repository's Snakefile in the working folder ``work`` with ``args``."""
    exe = Path(sys.executable).with_name("snakemake")
    return subprocess.run(
        [str(exe), "--snakefile", str(ROOT / "Snakefile"), *args], cwd=work, capture_output=True, text=True
    )


def _study(tmp_path, old, new):
    text = QUICK.read_text()
    assert old in text, old
    path = tmp_path / "study.yaml"
    path.write_text(text.replace(old, new))
    return path


def _dry_run_jobs(work, *config, target="reproduce_paper"):
    """Jobs per rule of a Snakemake dry run (``-n --quiet rules``) on an empty results folder, in the
    working folder ``work``."""
    p = _snakemake(work, target, "-n", "--quiet", "rules", "--cores", "1", "--config", *config)
    return rule_jobs(p)


def test_every_rule_has_its_outputs_and_log():
    assert set(STUDY_LOGS) == set(STUDY_OUTPUTS)
    assert set(CALIBRATION_LOGS) == set(CALIBRATION_FOLDERS) == set(CALIBRATION_OUTPUTS)
    assert not set(CALIBRATION_OUTPUTS) & set(STUDY_OUTPUTS)  # rel_path finds a rule in either
    for rule, outs in {**STUDY_OUTPUTS, **CALIBRATION_OUTPUTS}.items():
        for name, pattern in outs.items():
            if pattern.endswith(".png"):  # every figure has its PDF beside it, also an output
                assert pattern[:-4] + ".pdf" in outs.values(), (rule, name)


def _dag_outputs(work, *config, targets=("reproduce_paper",)):
    """Rule -> the set of its outputs over every job of the DAG of ``targets``, as Snakemake lists
    them (``--summary``: one row per output file, with its rule), in the working folder ``work``."""
    p = _snakemake(work, *targets, "--summary", "--cores", "1", "--config", *config)
    assert p.returncode == 0, p.stderr[-2000:]
    rows = [line.split("\t") for line in p.stdout.splitlines()]
    assert rows[0][:3] == ["output_file", "date", "rule"], rows[0]
    out = {}
    for row in rows[1:]:
        out.setdefault(row[2], set()).add(row[0])
    return out


@pytest.mark.parametrize("name", ["quick", "quick_spatial"])
def test_every_output_of_the_dag_is_a_file_of_the_layout(at_root, tmp_path, work, name):
    """Every output of every job of the DAG (a study's rules and the two calibration studies) is a
    path of cdpr.pipeline.results under its rule, and every path it lists there is an output:
    no rule spells a results file of its own."""
    st = load_study(ROOT / "config" / "studies" / f"{name}.yaml")
    res = tmp_path / "r"
    layout = Layout(st, res)
    dag = _dag_outputs(
        work,
        f"study=config/studies/{name}.yaml",
        f"results={res}",
        targets=("reproduce_paper", *CALIBRATION_OUTPUTS),
    )
    expected = {rule: set(layout.rule_outputs(rule)) for rule in layout.rules()}
    expected.update({rule: set(calibration_outputs(rule).values()) for rule in CALIBRATION_OUTPUTS})
    assert dag == expected
    assert "results/calibration/exact/samples.csv" in dag["calibration_study"]
    assert "results/calibration/cogiro/validation_errors.pdf" in dag["calibration_cogiro"]


def test_the_calibration_files_are_named_once():
    """The calibration studies' folders nest (CoGiRo's inside CDPR4's) without sharing a file, and
    rel_path spells their files as it spells a study's."""
    files = [
        f"{CALIBRATION_FOLDERS[rule]}/{rel}"
        for rule, outs in CALIBRATION_OUTPUTS.items()
        for rel in outs.values()
    ]
    assert len(files) == len(set(files))
    assert rel_path("calibration_study", "curve") == "learning_curve.csv"
    assert rel_path("calibration_cogiro", "figure") == "validation_errors.png"
    assert rel_path("doe", "effects") == "doe/effects.csv"
    assert calibration_outputs("calibration_cogiro", "out")["samples"] == "out/exact/samples.csv"


def test_layout_is_the_dag(at_root, tmp_path, work):
    """A dry run on an empty folder schedules, per rule, as many jobs as the layout has wildcard
    values, and the layout's targets are distinct files: the rules and the layout agree."""
    st = load_study(QUICK)
    layout = Layout(st, tmp_path / "r")
    jobs = _dry_run_jobs(work, "study=config/studies/quick.yaml", f"results={tmp_path / 'r'}")
    expected = {rule: len(layout.wildcards(rule)) for rule in layout.rules()}
    assert jobs == {**expected, "reproduce_paper": 1}
    targets = layout.targets()
    assert len(targets) == len(set(targets)) and all(t.startswith(str(tmp_path / "r") + "/") for t in targets)
    assert f"{tmp_path}/r/doe/rw_c.json" in targets and f"{tmp_path}/r/plane/CDPR4_SR.csv" in targets
    assert f"{tmp_path}/r/shards/volume/CDPR4_DR_1.parquet" in targets  # intermediates too


def test_a_study_without_uncertainty_has_no_uncertainty_outputs(at_root, tmp_path):
    st = load_study(ROOT / "config" / "studies" / "example.yaml")
    layout = Layout(st, "r")
    assert "uncertainty" not in st
    assert not [t for t in layout.targets() if "uncertainty" in t]
    assert layout.summary_inputs()["uncertainty"] == []


def test_comparison_layout_names_the_page_the_folder_and_both_runs(at_root):
    from cdpr.pipeline.comparison import load_comparison

    lay = ComparisonLayout(load_comparison(ROOT / "config" / "comparisons" / "quick.yaml"))
    t = lay.targets()
    assert "results/quick_comparison.md" in t and "results/quick_comparison/difference_stats.csv" in t
    assert "results/quick_comparison/budget/CDPR4_SRopt.csv" in t
    inputs = lay.inputs()
    assert "results/quick/plane/CDPR3_DR.csv" in inputs and "results/quick_physical/summary.csv" in inputs


def _summary(res, tmp_path):
    return subprocess.run(
        [sys.executable, "-m", "cdpr", "job", "summary", "--study", str(QUICK), "--results", str(res)]
        + ["--markdown", str(tmp_path / "s.md"), "--table", str(tmp_path / "s.csv")],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )


def test_summary_of_a_folder_that_does_not_exist_is_an_error(tmp_path):
    p = _summary(tmp_path / "nothing", tmp_path)
    assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr
    assert "nothing: the results folder does not exist" in p.stderr
    assert not (tmp_path / "s.md").exists()


def test_summary_of_an_incomplete_folder_names_what_is_missing(at_root, tmp_path):
    res = tmp_path / "res"
    layout = Layout(load_study(QUICK), res)
    have = results._flat(layout.summary_inputs().values())
    for f in have:  # every table the summary reads but one plane table
        Path(f).parent.mkdir(parents=True, exist_ok=True)
        Path(f).write_text("x\n1\n")
    os.unlink(layout.path("plane_table", "table", robot="CDPR4", pulley="SR"))
    p = _summary(res, tmp_path)
    assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr
    assert "incomplete results folder" in p.stderr and "1 missing file(s): plane/CDPR4_SR.csv" in p.stderr
    with pytest.raises(CdprError, match="needs 2 missing file.*doe/rw_c.json"):
        os.unlink(layout.path("regular_workspace", "json"))
        results.check_complete(res, layout.summary_inputs(), "the summary")


@pytest.mark.parametrize(
    "old,new,key,fragment",
    [
        ("  n: 12\n  shards: 2\n", "  n: 2\n  shards: 9\n", "volumes.shards", "9 shards for 8 points"),
        (
            "  n: 12\n  shards: 2\n",
            f"  n: 40\n  shards: {MAX_SHARDS + 1}\n",
            "volumes.shards",
            "at most 1000",
        ),
        ("  index_n: 8                  # N", "  index_n: 100000  # N", "doe.index_n", "GiB of memory"),
        ("h_m: [0.100, 0.150]", "h_m: [0.1, 0.1]", "doe.levels.h_m", "the two levels must differ"),
        ("joint: [SR, DR]", "joint: [DR, DR]", "doe.levels.joint", "got [DR, DR]"),
        (
            "  index_n: 8\n  shards: 2 ",
            "  index_n: 8\n  shards: 4 ",
            "elasticity.shards",
            "4 shards for 3 moduli",
        ),
    ],
)
def test_sizes_that_cannot_run_are_refused_before_any_job(at_root, tmp_path, old, new, key, fragment):
    path = _study(tmp_path, old, new)
    with pytest.raises(ConfigError, match=rf"study.yaml: key '{key}'") as exc:
        load_study(path)
    assert fragment in str(exc.value)


def test_a_huge_index_grid_is_refused_with_its_memory_and_time(at_root, tmp_path):
    path = _study(tmp_path, "  index_n: 8                  # N", "  index_n: 100000  # N")
    with pytest.raises(ConfigError) as exc:
        load_study(path)
    msg = str(exc.value)
    # 1e15 points per job (a job solves whole grids; doe.shards splits the tests) at 600 bytes each:
    # 5.6e8 GiB per job; 8 tests at 250,000 points/s
    assert "100000^3 = 1,000,000,000,000,000 points" in msg and "558,793,544.8 GiB" in msg
    assert f"{8e15 / 250_000 / 86400:,.1f} days of solver time" in msg


def test_bad_size_stops_the_pipeline_before_any_job(tmp_path, work):
    bad = _study(tmp_path, "h_m: [0.100, 0.150]", "h_m: [0.1, 0.1]")
    p = _snakemake(work, "-n", "--cores", "1", "--config", f"study={bad}", f"results={tmp_path / 'r'}")
    assert p.returncode != 0 and "key 'doe.levels.h_m': the two levels must differ" in p.stdout + p.stderr
    assert not (tmp_path / "r").exists()


def test_the_spatial_study_layout_is_the_dag_and_names_its_paths(at_root, tmp_path, work):
    """quick_spatial.yaml (CoGiRo, issue 19): the rules and the layout agree; its two paths of one
    robot are named by their labels; every solver job gets the study's orientation and the workspace
    grids the wrench-feasible flag."""
    path = ROOT / "config" / "studies" / "quick_spatial.yaml"
    st = load_study(path)
    layout = Layout(st, tmp_path / "r")
    jobs = _dry_run_jobs(work, f"study={path.relative_to(ROOT)}", f"results={tmp_path / 'r'}")
    expected = {rule: len(layout.wildcards(rule)) for rule in layout.rules()}
    assert jobs == {**expected, "reproduce_paper": 1}
    targets = layout.targets()
    for rel in ("trajectories/diagonal_SR.csv", "trajectories/vertical_DR.csv", "plane/CoGiRo_subsets.png"):
        assert f"{tmp_path}/r/{rel}" in targets
    assert not [t for t in targets if t.endswith("parity.png")]
    for rel in ("uncertainty/sobol.png", "uncertainty/SRopt_compensated_map.csv"):  # issue 19: both cases
        assert f"{tmp_path}/r/{rel}" in targets
    p = _snakemake(
        work,
        "reproduce_paper",
        "-n",
        "-p",
        "--cores",
        "1",
        "--config",
        f"study={path}",
        f"results={tmp_path / 'r'}",
    )
    assert p.returncode == 0, p.stderr[-2000:]
    # the solver jobs read the study's options (physical mode, the fixed orientation) as values
    kinds = ("plane-table", "volume-shard", "workspace-grid", "trajectory-table", "elasticity-path")
    solves = [ln for ln in p.stdout.splitlines() if any(f" -m cdpr job {k} " in ln for k in kinds)]
    assert solves and all(f"--study {path}" in ln and "--redundancy" not in ln for ln in solves)
    assert st.options.redundancy == "physical" and st.options.rotvec == (0.0, 0.0, 0.0)
    # the 8 DOE workspace grids: the job adds the wrench-feasible test itself on a spatial study
    assert sum(" -m cdpr job workspace-grid " in ln for ln in solves) == 8


def test_every_robot_has_its_view_and_only_spatial_studies_have_dphi_volumes(at_root):
    spatial = Layout(load_study(ROOT / "config" / "studies" / "quick_spatial.yaml"), "r")
    assert spatial.wildcards("robot_view") == [{"robot": "CoGiRo"}]
    assert {
        "r/robot/CoGiRo.png",
        "r/robot/CoGiRo.pdf",
        "r/volumes/volumes_dphi.csv",
        "r/volumes/R_V_dphi.png",
    } <= set(spatial.targets())
    point = Layout(load_study(QUICK), "r")
    robots = list(point.st["robots"])
    assert len(robots) >= 2 and point.wildcards("robot_view") == [{"robot": r} for r in robots]
    assert {f"r/robot/{r}.png" for r in robots} <= set(point.targets())
    assert point.wildcards("volumes_dphi") == [] and not [t for t in point.targets() if "dphi" in t]


def test_the_summary_reads_the_dphi_volumes_only_where_the_study_sets_their_limits():
    spatial = Layout(load_study(ROOT / "config" / "studies" / "quick_spatial.yaml"), "r").summary_inputs()
    assert spatial["volumes_dphi"] == "r/volumes/volumes_dphi.csv"
    point = Layout(load_study(ROOT / "config" / "studies" / "quick.yaml"), "r").summary_inputs()
    assert "volumes_dphi" not in point
