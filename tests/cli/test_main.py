"""``cdpr.cli.main.main``: parse, run the command, and turn what goes wrong into one line: a refused
input (CdprError) exit 2, a write that fails (a full disk) exit 1, a reader that left (a closed pipe)
exit 0 in silence; a programming error is not hidden. The commands are replaced here by stand-ins
that raise, so each exit path is tested without solving anything; one test runs the real commands
in a process of their own."""

import errno
import io
import subprocess
import sys

import pytest

from cdpr.cli import main as main_module
from cdpr.cli import winch as commands  # the module of cmd_winch
from cdpr.cli.main import main
from cdpr.errors import CdprError, ConfigError
from tests.conftest import ROBOTS, ROOT

R4 = str(ROBOTS / "cdpr4.yaml")
#: A command line that reaches ``cdpr.cli.winch.cmd_winch`` (replaced by a stand-in in these tests).
WINCH = ["winch", "--steps", "3"]


def _raising(exc):
    def command(args):
        print("partial output")
        raise exc

    return command


@pytest.mark.parametrize(
    "exc,line",
    [
        (CdprError("robot.yaml: cable 2 has no anchor"), "cdpr: error: robot.yaml: cable 2 has no anchor\n"),
        (
            ConfigError("s.yaml", "n_train", "must be > 0"),
            "cdpr: error: s.yaml: key 'n_train': must be > 0\n",
        ),
    ],
)
def test_a_refused_input_is_one_line_and_exit_2(monkeypatch, capsys, exc, line):
    monkeypatch.setattr(commands, "cmd_winch", _raising(exc))
    assert main(WINCH) == 2
    out, err = capsys.readouterr()
    assert err == line and out == "partial output\n"


@pytest.mark.parametrize(
    "exc,words",
    [
        (
            OSError(errno.ENOSPC, "No space left on device", "/data/t.csv"),
            "cannot write /data/t.csv (No space left on device)",
        ),
        (
            OSError(errno.ENOSPC, "No space left on device"),
            "cannot write the output (No space left on device)",
        ),
    ],
)
def test_a_failed_write_is_one_line_and_exit_1(monkeypatch, capsys, exc, words):
    monkeypatch.setattr(commands, "cmd_winch", _raising(exc))
    assert main(WINCH) == 1
    assert capsys.readouterr().err == f"cdpr: error: {words}\n"


def test_a_missing_input_file_is_one_line_naming_it_and_exit_2(tmp_path, capsys):
    """A job run by hand on input tables that are not there (Snakemake would have made them): one
    line naming the missing file, exit 2 (a refused input), not "cannot write"."""
    missing = tmp_path / "none" / "CDPR4_SR.csv"
    argv = [
        "job",
        "plane-figure",
        "--study",
        str(ROOT / "config" / "studies" / "paper.yaml"),
        "--robot-key",
        "CDPR4",
    ]
    argv += [
        "--tables",
        str(missing),
        str(tmp_path / "none" / "CDPR4_DR.csv"),
        "--figure",
        str(tmp_path / "f.png"),
    ]
    assert main(argv) == 2
    assert capsys.readouterr().err == f"cdpr: error: {missing}: no such file or folder\n"
    assert not (tmp_path / "f.png").exists()


def test_output_that_cannot_be_flushed_is_one_line_and_exit_1(monkeypatch, capsys, tmp_path):
    """A command that succeeded but whose buffered output cannot reach a full disk: ``main`` flushes
    standard output itself, so the failure is its one line and exit 1, not an error at interpreter
    exit after a 0 was returned."""

    class FullDisk(io.StringIO):
        def __init__(self, fd):
            super().__init__()
            self.fd = fd

        def flush(self):
            if self.getvalue():
                raise OSError(errno.ENOSPC, "No space left on device")

        def fileno(self):
            return self.fd

    monkeypatch.setattr(commands, "cmd_winch", lambda args: print("all of the output"))
    with open(tmp_path / "stdout", "w") as real:
        monkeypatch.setattr(sys, "stdout", FullDisk(real.fileno()))
        assert main(WINCH) == 1
    assert capsys.readouterr().err == "cdpr: error: cannot write the output (No space left on device)\n"


def test_a_closed_pipe_ends_quietly_and_sends_what_is_left_nowhere(monkeypatch, capsys, tmp_path):
    """The reader left (``cdpr ... | head``): exit 0, nothing on stderr, and standard output now goes
    to /dev/null, so the interpreter's last flush raises nothing more."""
    monkeypatch.setattr(commands, "cmd_winch", _raising(BrokenPipeError(errno.EPIPE, "Broken pipe")))
    with open(tmp_path / "stdout", "w") as stdout:
        monkeypatch.setattr(sys, "stdout", stdout)
        assert main(WINCH) == 0
        stdout.write("after the reader left\n")
        stdout.flush()
    assert (tmp_path / "stdout").read_text() == ""
    assert capsys.readouterr().err == ""


def test_a_programming_error_is_not_turned_into_a_user_error(monkeypatch):
    monkeypatch.setattr(commands, "cmd_winch", _raising(ZeroDivisionError("a bug")))
    with pytest.raises(ZeroDivisionError, match="a bug"):
        main(WINCH)


def test_the_command_named_by_the_parser_runs_with_the_parsed_arguments(monkeypatch):
    seen = []
    monkeypatch.setattr(commands, "cmd_winch", seen.append)
    assert main(["winch", "--steps", "7", "--json"]) == 0
    ((args,),) = [seen]
    assert args.command == "winch" and args.steps == 7 and args.json


def test_argv_defaults_to_the_process_arguments(monkeypatch):
    seen = []
    monkeypatch.setattr(commands, "cmd_winch", seen.append)
    monkeypatch.setattr(sys, "argv", ["cdpr", "winch", "--steps", "5"])
    assert main() == 0 and seen[0].steps == 5


def test_only_the_job_command_builds_the_job_options(monkeypatch):
    """The job registry imports the pipeline (pandas, the analyses): built for ``cdpr job`` only."""
    built = []
    real = main_module.build_parser
    monkeypatch.setattr(main_module, "build_parser", lambda jobs=True: built.append(jobs) or real(jobs=jobs))
    monkeypatch.setattr(commands, "cmd_winch", lambda args: None)
    main(["winch"])
    with pytest.raises(SystemExit):
        main(["job", "--help"])
    assert built == [False, True]


def test_a_usage_error_exits_2_with_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["winch", "--steps", "0"])
    err = capsys.readouterr().err
    assert (
        exc.value.code == 2
        and err.count("\n") == 1
        and err.startswith("cdpr: error: winch: argument --steps")
    )


def test_errors_are_one_sentence_without_traceback(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text((ROBOTS / "cdpr4.yaml").read_text().replace("r_p_m: 0.0665", "r_p_m: -0.0665"))
    for args in (
        ["point", "--robot", str(bad), "--at", "0", "0", "1"],
        ["point", "--robot", R4, "--pulley", "DR", "--h", "0.05", "--at", "0", "0", "1"],
        [
            "grid",
            "--robot",
            R4,
            "--box",
            "1",
            "0",
            "0",
            "1",
            "0",
            "1",
            "--n",
            "2",
            "--out",
            str(tmp_path / "x.csv"),
        ],
    ):
        p = subprocess.run([sys.executable, "-m", "cdpr", *args], capture_output=True, text=True)
        assert p.returncode == 2
        assert "Traceback" not in p.stderr and p.stderr.startswith("cdpr: error:")
        assert len(p.stderr.strip().splitlines()) == 1
