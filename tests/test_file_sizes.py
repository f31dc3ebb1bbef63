"""The house rule: no Python file in the package cdpr/ is over ``MAX_LINES`` lines (split it by
concept instead, docs/code.md)."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: The most lines a .py file under cdpr/ may have.
MAX_LINES = 1000


def _lines(path):
    with open(path, encoding="utf-8") as fh:
        return sum(1 for _ in fh)


def test_no_package_file_is_over_the_limit():
    files = sorted((ROOT / "cdpr").rglob("*.py"))
    assert files, "no .py file found under cdpr/"
    over = [(p.relative_to(ROOT).as_posix(), n) for p in files if (n := _lines(p)) > MAX_LINES]
    assert not over, "over %d lines: %s" % (
        MAX_LINES,
        ", ".join(f"{name} ({n} lines)" for name, n in over),
    )


def test_the_limit_names_a_long_file(tmp_path):
    """The count the rule uses: a file of MAX_LINES + 1 lines is over, one of MAX_LINES is not."""
    long, ok = tmp_path / "long.py", tmp_path / "ok.py"
    long.write_text("x = 1\n" * (MAX_LINES + 1))
    ok.write_text("x = 1\n" * MAX_LINES)
    assert _lines(long) == MAX_LINES + 1 > MAX_LINES >= _lines(ok)
