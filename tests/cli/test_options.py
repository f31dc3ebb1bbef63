"""Argument types and shared option groups of the command line (cdpr.cli.options): numbers in plain
decimal or exponent notation only, ranges named in the refusal, one-line usage errors, negative
numbers read as numbers, and the choices spelled here equal to their owners' (which this module may
not import: ``cdpr --help`` loads no numpy)."""

import argparse
import os

import pytest

from cdpr.cli import options


def test_choices_agree_with_their_owners():
    from cdpr.robot import PULLEY_KINDS
    from cdpr.solve import ENGINES, REDUNDANCY

    assert options.PULLEY_KINDS == PULLEY_KINDS
    assert options.ENGINES == tuple(ENGINES)
    assert set(options.METHODS) == {m for ms in ENGINES.values() for m in ms}
    assert options.REDUNDANCY == REDUNDANCY
    from cdpr.analyses import calibration

    assert options.CALIBRATION_MODELS == calibration.MODELS
    assert options.CALIBRATION_SIGMA == calibration.SIGMA_DEFAULT


@pytest.mark.parametrize(
    "text,value", [("2.5", 2.5), ("-1e-3", -1e-3), (".5", 0.5), ("3", 3.0), ("+4E2", 400.0)]
)
def test_finite_reads_plain_decimal_and_exponent_notation(text, value):
    assert options.finite(text) == value


@pytest.mark.parametrize(
    "text,words",
    [
        ("1_0", "'1_0' is not a number; allowed: plain decimal or exponent notation"),
        ("0x1p3", "'0x1p3' is not a number"),
        ("0,5", "'0,5' is not a number (use a decimal point, not a comma)"),
        ("nan", "'nan' is not a finite number"),
        ("-inf", "'-inf' is not a finite number"),
        ("1e999", "'1e999' is not a finite number"),
        ("abc", "'abc' is not a number"),
    ],
)
def test_finite_refuses_other_spellings_and_non_finite_values(text, words):
    with pytest.raises(argparse.ArgumentTypeError, match="^" + words.replace("(", r"\(").replace(")", r"\)")):
        options.finite(text)


def test_positive_and_non_negative_bounds():
    assert options.positive("1e-9") == 1e-9 and options.non_negative("0") == 0.0
    for f, text, words in [
        (options.positive, "0", "'0' must be > 0"),
        (options.positive, "-2", "'-2' must be > 0"),
        (options.non_negative, "-1e-12", "'-1e-12' must be >= 0"),
        (options.positive, "1,5", "not a number"),
    ]:
        with pytest.raises(argparse.ArgumentTypeError, match=words):
            f(text)


def test_count_accepts_its_closed_range_only():
    steps = options.count(2, 5)
    assert [steps(t) for t in ("2", "5")] == [2, 5]
    for text, words in [
        ("1", r"1 is outside the allowed range \[2, 5\]"),
        ("6", "6 is outside"),
        ("2.0", "not an integer"),
    ]:
        with pytest.raises(argparse.ArgumentTypeError, match=words):
            steps(text)
    assert options.count(1)("1000000") == 1_000_000
    with pytest.raises(argparse.ArgumentTypeError, match=r"\[1, inf\]"):
        options.count(1)("0")


def test_threads_is_one_to_the_number_of_cores():
    cores = os.cpu_count() or 1
    assert options.threads("1") == 1 and options.threads(str(cores)) == cores
    with pytest.raises(argparse.ArgumentTypeError, match=rf"\[1, {cores}\]"):
        options.threads(str(cores + 1))


def test_groups_split_on_commas_and_drop_blanks():
    assert options.groups("anchors, dead_lengths,,moduli ") == ["anchors", "dead_lengths", "moduli"]
    assert options.groups(" , ") == []


def _parser():
    ap = options.Parser(prog="cdpr test")
    options.robot_options(ap)
    options.solver_options(ap)
    options.points_options(ap, "desired position")
    options.physics_options(ap)
    return ap


def test_negative_numbers_in_exponent_notation_are_values_not_options():
    args = _parser().parse_args(
        ["--robot", "r.yaml", "--at", "-1e-1", "-.5", "2", "--rotvec", "-1E-3", "0", "-0.2"]
    )
    assert args.at == [-0.1, -0.5, 2.0] and args.rotvec == [-1e-3, 0.0, -0.2]
    assert (args.method, args.engine, args.redundancy, args.json) == (
        "newton",
        None,
        None,
        False,
    )  # None: the robot's default (paper mode for a point mass)


@pytest.mark.parametrize(
    "argv,words",
    [
        (["--robot", "r.yaml"], "one of the arguments --at --points is required"),
        (["--robot", "r.yaml", "--at", "0", "0", "1", "--points", "p.csv"], "not allowed with argument"),
        (["--robot", "r.yaml", "--at", "0", "0", "1", "--pulley", "XR"], "invalid choice: 'XR'"),
        (["--robot", "r.yaml", "--at", "0", "0", "1", "--E", "-5"], "'-5' must be > 0"),
        (["--robot", "r.yaml", "--at", "0", "0,5", "1"], "use a decimal point"),
    ],
)
def test_a_usage_error_is_one_line_naming_the_command_and_exit_2(capsys, argv, words):
    with pytest.raises(SystemExit) as exc:
        _parser().parse_args(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2 and err.startswith("cdpr: error: test: ") and err.count("\n") == 1
    assert words in err, err
