"""The command line's parser (cdpr.cli.parser.build_parser): every command runs a function that
exists, the job options are built only when asked for, one box option at a time, and every default a
help text states is the default the parser gives."""

import argparse
import importlib
import re

import pytest

from cdpr.cli.options import MAX_STEPS
from cdpr.cli.parser import build_parser

COMMANDS = {
    "inverse",
    "point",
    "compensate",
    "grid",
    "winch",
    "plane",
    "trajectory",
    "interference",
    "job",
    "compile",
    "calibrate",
    "import",
    "export",
    "view",
    "study",
}


def leaves(parser, path=()):
    """(command words, subparser) of every command that runs something."""
    nested = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not nested:
        yield path, parser
        return
    for name, sp in nested[0].choices.items():
        yield from leaves(sp, (*path, name))


def test_the_commands_are_the_documented_ones():
    found = {path for path, _ in leaves(build_parser())}
    assert {p[0] for p in found} == COMMANDS
    assert {p for p in found if p[0] == "calibrate"} == {
        ("calibrate", c) for c in ("fit", "check", "plan", "study", "cv")
    }
    assert ("import", "caspr") in found
    assert {p for p in found if p[0] in ("import", "export")} == {
        ("import", "caspr"),
        ("import", "rrf"),
        ("export", "rrf"),
        ("export", "klipper"),
    }
    assert ("study", "check") in found


def test_every_command_runs_a_function_that_exists():
    for path, sp in leaves(build_parser()):
        module, func = sp.get_default("run")
        assert callable(getattr(importlib.import_module(module), func, None)), (path, module, func)


def test_the_job_options_are_built_only_when_asked_for():
    def job_options(jobs):
        job = dict(leaves(build_parser(jobs=jobs)))[("job",)]
        return {s for a in job._actions for s in a.option_strings} - {"-h", "--help"}

    assert job_options(False) == set()
    assert {"--study", "--table", "--box-file", "--figure"} <= job_options(True)


def _parse(argv):
    return build_parser(jobs=False).parse_args(argv)


def test_grid_takes_one_box_only(capsys):
    base = ["grid", "--robot", "r.yaml", "--n", "3", "--out", "g.csv"]
    assert _parse([*base, "--frame"]).frame and _parse([*base, "--box-file", "b.json"]).box_file == "b.json"
    assert _parse([*base, "--box", "-1", "1", "-1e0", "1", "0", "2"]).box == [-1, 1, -1, 1, 0, 2]
    for extra in (["--frame", "--box-file", "b.json"], ["--box", "0", "1", "0", "1", "0", "1", "--frame"]):
        with pytest.raises(SystemExit) as exc:
            _parse([*base, *extra])
        err = capsys.readouterr().err
        assert exc.value.code == 2 and "not allowed with argument" in err and err.count("\n") == 1


def test_winch_steps_are_bounded(capsys):
    assert _parse(["winch", "--steps", str(MAX_STEPS)]).steps == MAX_STEPS
    for steps in ("1", str(MAX_STEPS + 1)):
        with pytest.raises(SystemExit):
            _parse(["winch", "--steps", steps])
        assert f"[2, {MAX_STEPS}]" in capsys.readouterr().err


def test_every_default_a_help_text_states_is_the_parser_s():
    """ "(default 100)" in a help text and the option's default agree (numbers compared as numbers)."""
    checked = 0
    for path, sp in leaves(build_parser()):
        for a in sp._actions:
            m = re.search(r"\(default:? ([^;,) ]+)[;,)]", a.help or "")
            if not m or a.default is None:
                continue
            stated = m.group(1).rstrip(":")
            if isinstance(a.default, (int, float)):
                assert float(stated) == a.default, (path, a.option_strings, stated, a.default)
            else:
                assert stated == a.default, (path, a.option_strings, stated, a.default)
            checked += 1
    assert checked >= 12, checked  # 14 today
