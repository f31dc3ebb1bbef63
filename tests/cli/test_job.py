"""``cdpr job NAME`` (cdpr.cli.job): the registry read from the tasks' signatures (every public task a
job, the known names kept, options following the parameters), and ``run``: the study is validated,
a missing option or an output that cannot be written is refused before the task runs, and the task
gets the study and the options by name."""

import inspect
import re

import pytest

from cdpr.cli import job
from cdpr.cli.main import main
from cdpr.pipeline import tasks
from tests.cli.test_house import subparser
from tests.conftest import ROOT

STUDY = str(ROOT / "config" / "studies" / "quick.yaml")


#: The job names users and the rules know (issue 16: every one kept exactly).
KNOWN_JOBS = [
    "winch-figure",
    "plane-figure",
    "subsets-figure",
    "trajectories",
    "volumes",
    "volume-view",
    "volumes-dphi",
    "rw",
    "robot-view",
    "doe",
    "map",
    "maps",
    "elasticity",
    "dead-length-point",
    "dead-length",
    "summary",
    "budget-design",
    "budget",
    "comparison",
    "uq-shard",
    "uq-design",
    "uncertainty",
]


def test_every_public_task_has_a_job_and_every_known_name_stays():
    public = {
        n
        for module in job.TASK_MODULES
        for n, f in vars(module).items()
        if inspect.isfunction(f) and f.__module__ == module.__name__ and not n.startswith("_")
    }
    assert tasks in job.TASK_MODULES
    assert public - set(job.HELPERS) == set(job.task_functions())
    assert {job.JOBS[j].func.__name__ for j in job.JOBS} == public - set(job.HELPERS)
    # every known name stays, in its order (the order of tasks.py, shown by --help); new jobs may join
    assert [j for j in job.JOBS if j in KNOWN_JOBS] == KNOWN_JOBS
    assert set(job.HELPERS) <= public  # a helper that disappears from tasks.py is dropped from HELPERS too


def test_job_options_follow_the_signatures():
    for name, j in job.JOBS.items():
        sig = inspect.signature(j.func).parameters
        assert list(sig)[0] == "st" and j.params == tuple(list(sig)[1:]), name
        assert j.required == tuple(p for p in j.params if sig[p].default is inspect.Parameter.empty), name
    assert job.JOBS["map"].required == ("kind", "box_file", "table")  # threads has a default
    ap = subparser("job")
    helps = {a.option_strings[0]: a.help for a in ap._actions if a.option_strings}
    for n in {n for j in job.JOBS.values() for n in j.params}:
        assert helps[job.option(n)] == job.OPTIONS[n].help, n
    assert set(job.OPTIONS) == {n for j in job.JOBS.values() for n in j.params}  # no stale entry


def test_a_task_parameter_without_an_option_entry_is_refused(monkeypatch):
    def new_task(st, table, colour):
        """A task with a parameter OPTIONS does not know."""

    monkeypatch.setattr(tasks, "new_task", new_task, raising=False)
    new_task.__module__ = tasks.__name__
    with pytest.raises(TypeError, match="new_task: parameter.*colour"):
        job.registry()


def test_job_missing_options_and_outputs_are_named(tmp_path, capsys):
    study = str(ROOT / "config" / "studies" / "quick.yaml")
    assert main(["job", "maps", "--study", study, "--tables", "a.csv", "--box-file", "b.json"]) == 2
    assert capsys.readouterr().err == "cdpr: error: job maps needs --map, --lines, --figure\n"
    code = main(
        ["job", "dead-length", "--study", study, "--tables", "a.csv", "--table", str(tmp_path / "t.txt")]
        + ["--figure", str(tmp_path / "f.png")]
    )
    err = capsys.readouterr().err
    assert code == 2 and "t.txt" in err and err.count("\n") == 1


def test_job_help_lists_every_job_and_option(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["job", "--help"])
    out = capsys.readouterr().out
    assert exc.value.code == 0
    assert all(j in out for j in KNOWN_JOBS)
    assert all(job.option(n) in out for n in job.OPTIONS)


def test_job_names_and_options_are_distinct_dashed_words():
    """Two tasks never share a job name (an alias could shadow a task), and every name and option is
    lowercase words joined by dashes, as the rules write them."""
    names = [job.job_name(n) for n in job.task_functions()]
    assert len(set(names)) == len(names) == len(job.JOBS)
    dashed = re.compile(r"[a-z][a-z0-9]*(-[a-z0-9]+)*")
    assert all(dashed.fullmatch(n) for n in names), names
    assert all(dashed.fullmatch(job.option(p)[2:]) for p in job.OPTIONS)
    assert job.option("box_file") == "--box-file" and job.job_name("regular_workspace") == "rw"
    assert set(job.ALIASES) <= set(job.task_functions())  # no alias of a task that is gone


@pytest.fixture
def recorded(monkeypatch):
    """``cdpr job summary`` replaced by a task that records its call (the registry's Job kept)."""
    calls = []

    def summary(st, results, table, markdown):
        calls.append((st, results, table, markdown))

    real = job.JOBS["summary"]
    monkeypatch.setitem(job.JOBS, "summary", job.Job(summary, real.params, real.required))
    return calls


def test_run_gives_the_task_the_validated_study_and_its_options(recorded, tmp_path):
    from cdpr.pipeline.study import load_study

    table, md = str(tmp_path / "out" / "s.csv"), str(tmp_path / "out" / "s.md")
    argv = ["job", "summary", "--study", STUDY, "--results", "res", "--table", table, "--markdown", md]
    assert main(argv) == 0
    ((st, results, t, m),) = recorded
    assert st == load_study(STUDY) and (results, t, m) == ("res", table, md)
    assert (tmp_path / "out").is_dir()  # the outputs' folder exists before the task runs


@pytest.mark.parametrize(
    "extra,words",
    [
        (["--table", "s.txt", "--markdown", "s.md"], "s.txt: unknown output format '.txt'"),
        (["--table", "s.csv"], "job summary needs --markdown"),
    ],
)
def test_run_refuses_before_the_task_runs(recorded, capsys, tmp_path, extra, words):
    extra = [str(tmp_path / e) if e.startswith("s.") else e for e in extra]
    assert main(["job", "summary", "--study", STUDY, "--results", "res", *extra]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and recorded == []


def test_a_bad_study_is_refused_naming_it_before_the_task_runs(recorded, capsys, tmp_path):
    bad = tmp_path / "study.yaml"
    bad.write_text("solver: newton\n")
    argv = ["job", "summary", "--study", str(bad), "--results", "r", "--table", "t.csv", "--markdown", "s.md"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"cdpr: error: {bad}") and err.count("\n") == 1 and recorded == []
