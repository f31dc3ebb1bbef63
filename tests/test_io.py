"""Atomic output, output checks, JSON and number spellings (cdpr.io): a file appears complete or not
at all, an output path is refused before any work with one line naming it, NaN becomes null, and a
points table's numbers are plain decimal or exponent notation."""

import json
import math
import os
import stat

import pytest

from cdpr import io
from cdpr.errors import CdprError


def _listing(folder):
    return sorted(p.name for p in folder.iterdir())


def test_atomic_writes_the_whole_file_with_the_mode_open_would_give(tmp_path):
    target = tmp_path / "sub" / "out.txt"  # the folder is created
    io.atomic(target, lambda tmp: open(tmp, "w").write("done\n"))
    assert target.read_text() == "done\n" and _listing(target.parent) == ["out.txt"]
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(target.stat().st_mode) == 0o666 & ~mask  # not mkstemp's 0600


def test_an_interrupted_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old\n")

    def half(tmp):
        open(tmp, "w").write("ne")
        raise KeyboardInterrupt  # a BaseException, as Ctrl-C

    with pytest.raises(KeyboardInterrupt):
        io.atomic(target, half)
    assert target.read_text() == "old\n" and _listing(tmp_path) == ["out.txt"]


def test_write_json_writes_standard_json_with_nan_and_inf_as_null(tmp_path):
    obj = {"a": [1.0, math.nan, (math.inf, -math.inf)], "b": {"c": 2, "d": "x"}}
    io.write_json(obj, tmp_path / "o.json")
    text = (tmp_path / "o.json").read_text()
    assert "NaN" not in text and "Infinity" not in text and text.endswith("}\n")
    assert json.loads(text) == {"a": [1.0, None, [None, None]], "b": {"c": 2, "d": "x"}}
    io.write_text("é\n", tmp_path / "t.md")
    assert (tmp_path / "t.md").read_bytes() == "é\n".encode()


@pytest.mark.parametrize(
    "name,suffixes",
    [
        ("t.csv", None),
        ("t.parquet", None),
        ("f.png", None),
        ("r.json", None),
        ("s.md", None),
        ("r.yaml", (".yaml",)),
    ],
)
def test_check_output_accepts_the_formats_of_its_kind(tmp_path, name, suffixes):
    path = tmp_path / "new" / name
    assert io.check_output(path, suffixes) == path and path.parent.is_dir() and not path.exists()


def test_check_output_refuses_in_one_line_naming_the_path(tmp_path):
    cases = [
        (tmp_path / "t.txt", None, "unknown output format '.txt'; allowed: .parquet, .csv"),
        (tmp_path / "f.pdf", (".png",), "unknown output format '.pdf'; allowed: .png"),
        (tmp_path / "dir.csv", None, "is a folder, not a file name"),
    ]
    (tmp_path / "dir.csv").mkdir()
    blocker = tmp_path / "file"
    blocker.write_text("")
    cases.append((blocker / "t.csv", None, "cannot create its folder"))
    for path, suffixes, words in cases:
        with pytest.raises(CdprError) as exc:
            io.check_output(path, suffixes)
        msg = str(exc.value)
        assert msg.startswith(f"{path}: ") and words in msg and "\n" not in msg, msg


@pytest.mark.parametrize("text", ["2.5", "-1e-3", ".5", "5.", "+3E+2", " 7 ", "nan", "-inf", "Infinity"])
def test_plain_numbers_are_numbers(text):
    assert io.is_plain_number(text)


@pytest.mark.parametrize("text", ["1_0", "0x10", "0,5", "1e", "e3", "", "2.5 m", "--1", "1.2.3"])
def test_other_spellings_are_not(text):
    assert not io.is_plain_number(text)


def test_check_csv_rows_names_file_row_and_column(tmp_path):
    p = tmp_path / "points.csv"
    p.write_text("x,y,z,label\n0,1,2,a\n\n1.5,2e-1,3,b\n")
    io.check_csv_rows(p, ["x", "y", "z"])  # a blank line is skipped; the label column is not a number
    for text, words in [
        ("x,y,z\n0,1,2\n0,1\n", "row 2 has 2 fields, the header has 3 (x, y, z)"),
        ("x,y,z\n0,1,2\n0,1,2,3\n", "row 2 has 4 fields"),
        ('x,y,z\n"0,5",1,2\n', "row 1, column x: '0,5' is not a number (use a decimal point, not a comma)"),
        ("x,y,z\n0,1_0,2\n", "row 1, column y: '1_0' is not a number; allowed: plain decimal"),
        ("", "the table is empty; it needs a header row (x, y, z)"),
    ]:
        p.write_text(text)
        with pytest.raises(CdprError) as exc:
            io.check_csv_rows(p, ["x", "y", "z"])
        assert str(exc.value).startswith(f"{p}: ") and words in str(exc.value), str(exc.value)
