"""Issue 41: ``cdpr study check FILE`` is the pipeline's validation of a study without Snakemake (one
line per problem and exit 2, or ``ok`` and exit 0), and a results folder that is an existing file
stops the pipeline in one line before any job (``cdpr.pipeline.study.check_results_folder``)."""

import pytest

from cdpr.cli.main import main
from cdpr.errors import ConfigError
from cdpr.pipeline.study import check_file, check_results_folder
from tests.conftest import ROOT
from tests.quick_runs import make_workdir, snakemake

QUICK = ROOT / "config" / "studies" / "quick.yaml"


def run(argv, capsys):
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def test_a_valid_study_is_ok(capsys):
    assert run(["study", "check", QUICK], capsys) == (0, "ok\n", "")


def test_each_problem_is_one_line_and_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    text = QUICK.read_text()
    assert "solver: newton" in text
    bad.write_text(text.replace("solver: newton", "solver: magic") + "\nbogus_key: 1\n")
    code, out, err = run(["study", "check", bad], capsys)
    lines = err.splitlines()
    assert code == 2 and out == "" and len(lines) == len(check_file(bad)) >= 2
    assert all(line.startswith(f"cdpr: error: {bad}: key '") for line in lines)
    assert any("key 'solver'" in line for line in lines) and any("bogus_key" in line for line in lines)
    assert run(["study", "check", tmp_path / "none.yaml"], capsys)[0] == 2


def test_results_path_that_is_a_file_is_one_line(tmp_path, capsys):
    f = tmp_path / "results"
    f.write_text("not a folder")
    with pytest.raises(ConfigError, match="the results folder .* is an existing file"):
        check_results_folder(f)
    with pytest.raises(ConfigError, match="lies below .*, an existing file"):
        check_results_folder(f / "quick")
    check_results_folder(tmp_path / "new" / "quick")  # a folder still to be made is fine
    code, out, err = run(["study", "check", QUICK, "--results", f], capsys)
    assert code == 2 and err.count("\n") == 1 and "is an existing file" in err


def test_snakemake_stops_before_any_job_on_a_results_file(tmp_path):
    work = make_workdir(tmp_path / "w", studies=("quick",))
    (work / "results").write_text("a file where the results folder should be")
    p = snakemake(
        "reproduce_paper", "study=studies/quick.yaml", "results=results", quiet=False, cwd=work, extra=["-n"]
    )
    text = p.stdout + p.stderr
    assert p.returncode != 0 and "invalid study configuration" in text and "is an existing file" in text
    assert "NotADirectoryError" not in text and "Traceback" not in text
