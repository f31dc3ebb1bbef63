"""config/studies/template_spatial.yaml runs on a fresh clone (issue 41: cogiro.yaml's `conclusions:`
needs another study's results): copied onto another shipped spatial robot, with its positions moved
into that robot's frame, it passes `cdpr study check` and Snakemake plans its whole DAG (dry run)."""

import subprocess
import sys
from pathlib import Path

import yaml

from cdpr.cli.main import main
from tests.conftest import ROOT
from tests.quick_runs import make_workdir


def _on_ipanema(tmp_path):
    """The template with IPAnema-like (8 cables, pulleys at z = 0 and 3 m, a rigid platform) instead of
    CoGiRo: every CoGiRo position moved into IPAnema's 4 x 3 x 3 m frame."""
    st = yaml.safe_load((ROOT / "config/studies/template_spatial.yaml").read_text())
    assert "conclusions" not in st
    st["name"] = "template_test"
    st["robots"] = {"IPAnema": str(ROOT / "config/robots/ipanema_like.yaml")}
    st["trajectories"]["paths"] = {
        "diagonal": {"robot": "IPAnema", "start_m": [-1.5, -1.0, 0.5], "end_m": [1.5, 1.0, 2.5]},
        "vertical": {"robot": "IPAnema", "start_m": [0.0, 0.0, 0.3], "end_m": [0.0, 0.0, 2.7]},
    }
    st["plane"]["z_m"] = 1.5
    st["doe"]["robot"] = "IPAnema"
    st["doe"]["paper_rw_c_m"] = [-1.0, 1.0, -0.8, 0.8, 0.5, 2.5]
    st["elasticity"]["path"] = {"start_m": [-1.5, 0.0, 0.5], "end_m": [1.5, 0.0, 2.5], "points": 21}
    if "uncertainty" in st:
        st["uncertainty"]["sobol"]["points_m"] = [[0.0, 0.0, 1.5], [-1.0, 0.8, 2.0]]
    path = tmp_path / "study.yaml"
    path.write_text(yaml.safe_dump(st, sort_keys=False))
    return path


def test_the_template_passes_the_study_check_on_another_robot(tmp_path, capsys):
    assert main(["study", "check", str(_on_ipanema(tmp_path))]) == 0
    assert capsys.readouterr().out.strip().endswith("ok")


def test_snakemake_plans_the_templates_dag_on_another_robot(tmp_path):
    study = _on_ipanema(tmp_path)
    work = make_workdir(tmp_path / "w", studies=[])  # Snakemake's own files stay out of the tree
    exe = Path(sys.executable).with_name("snakemake")
    p = subprocess.run(
        [str(exe), "--snakefile", str(ROOT / "Snakefile"), "-n", "--cores", "1"]
        + ["--config", f"study={study}", f"results={tmp_path / 'results'}"],
        cwd=work,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert p.returncode == 0, p.stderr[-2000:]
    assert "plane_table" in p.stdout and "Job stats" in p.stdout


def test_a_spatial_study_that_names_no_mode_is_physical(tmp_path, capsys):
    """Issue 41 'Defaults': a rigid platform has only physical mode, so a study of one that names no
    redundancy mode (nor uncertainty.redundancy) runs in physical mode instead of being refused;
    paper mode asked for explicitly is still refused with the sentence naming ``redundancy:
    physical``; a point-mass study that names none keeps paper mode."""
    from cdpr.errors import ConfigError
    from cdpr.pipeline import study

    path = _on_ipanema(tmp_path)
    st = yaml.safe_load(path.read_text())
    del st["redundancy"], st["uncertainty"]["redundancy"]
    path.write_text(yaml.safe_dump(st, sort_keys=False))
    got = study.load_study(path)
    assert (study.redundancy(got), study.uq_redundancy(got)) == ("physical", "physical")
    assert got["redundancy"] == "physical"  # in the mapping too: the rules' params see the mode
    st["redundancy"] = "paper"
    path.write_text(yaml.safe_dump(st, sort_keys=False))
    try:
        study.load_study(path)
    except ConfigError as exc:
        assert "key 'redundancy'" in str(exc) and "use redundancy: physical, got 'paper'" in str(exc)
    else:
        raise AssertionError("paper mode asked for on a rigid platform was accepted")
    quick = yaml.safe_load((ROOT / "config/studies/quick.yaml").read_text())
    del quick["redundancy"], quick["uncertainty"]["redundancy"]
    quick["robots"] = {k: str(ROOT / v) for k, v in quick["robots"].items()}
    if quick.get("conclusions"):
        del quick["conclusions"]
    (tmp_path / "quick.yaml").write_text(yaml.safe_dump(quick, sort_keys=False))
    q = study.load_study(tmp_path / "quick.yaml")
    assert (study.redundancy(q), study.uq_redundancy(q)) == ("paper", "paper")
