"""Atomic output: a file appears complete or not at all, so an interrupted run resumes cleanly."""

from __future__ import annotations

import csv
import json
import math
import os
import re
import tempfile
from pathlib import Path

from cdpr.errors import CdprError


def _umask():
    """The process's umask (read without changing it for longer than this call)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic(path, write):
    """Run write(tmp) on a temporary file beside ``path``, then rename it onto ``path``.

    The file gets the mode a plain ``open()`` would give it (0666 minus the umask), not the 0600 of
    the temporary file, so that results are readable by others under the usual umask 022."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        write(tmp)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


#: Significant digits of the floats written to CSV: the tracked tables are byte-identical on another
#: machine (the last bits of a float differ between CPUs' maths libraries), and 12 digits keep
#: far more than any number we compare (1e-9 m on metres).
CSV_DIGITS = 12
TABLE_SUFFIXES = (".parquet", ".csv")


def check_output(path, suffixes=None):
    """Refuse an output path before any work: unknown extension, or a folder that cannot be created
    or written. ``suffixes`` defaults to the table formats; a figure takes .png."""
    path = Path(path)
    if suffixes is None:
        suffixes = {".png": (".png",), ".json": (".json",), ".md": (".md",)}.get(path.suffix, TABLE_SUFFIXES)
    if path.suffix not in suffixes:
        raise CdprError(f"{path}: unknown output format '{path.suffix}'; allowed: {', '.join(suffixes)}")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CdprError(f"{path}: cannot create its folder ({exc.strerror})") from None
    if not os.access(path.parent, os.W_OK | os.X_OK):
        raise CdprError(f"{path}: cannot write there ({path.parent} is not a writable folder)")
    if path.is_dir():
        raise CdprError(f"{path}: is a folder, not a file name")
    return path


def clean_json(obj):
    """Replace NaN/inf floats by None so the JSON is standard."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: clean_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [clean_json(v) for v in obj]
    return obj


def write_json(obj, path):
    atomic(
        path, lambda tmp: Path(tmp).write_text(json.dumps(clean_json(obj), indent=2) + "\n", encoding="utf-8")
    )


def write_text(text, path):
    atomic(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))


#: A number as a points table may spell it: plain decimal or exponent notation (no digit separators
#: such as ``1_0``, no decimal comma), or nan/inf (refused later as non-finite, with the row).
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|[+-]?(?:nan|inf|infinity)", re.IGNORECASE)


def is_plain_number(text):
    """True for plain decimal or exponent notation ('2.5', '-1e-3', '.5'), and for nan/inf."""
    return _NUMBER.fullmatch(text.strip()) is not None


def check_csv_rows(path, columns):
    """Refuse a CSV table whose rows do not all have the header's number of fields, or whose
    ``columns`` hold something other than a plain number (a decimal comma, a digit separator, a
    word), or that names one of ``columns`` twice in its header, with one line naming the file, the
    row (1 = the first row after the header) and the column."""
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header is None:
            raise CdprError(f"{path}: the table is empty; it needs a header row ({', '.join(columns)})")
        twice = [c for c in columns if header.count(c) > 1]
        if twice:
            raise CdprError(
                f"{path}: column {twice[0]} appears {header.count(twice[0])} times in the header; give it once"
            )
        where = {c: header.index(c) for c in columns if c in header}
        for row_no, row in enumerate(reader, start=1):
            if not row:
                continue
            if len(row) != len(header):
                raise CdprError(
                    f"{path}: row {row_no} has {len(row)} fields, the header has {len(header)} "
                    f"({', '.join(header)}); every row needs one value per column"
                )
            for c, k in where.items():
                if not is_plain_number(row[k]):
                    hint = " (use a decimal point, not a comma)" if "," in row[k] else ""
                    raise CdprError(
                        f"{path}: row {row_no}, column {c}: {row[k]!r} is not a number{hint}; "
                        "allowed: plain decimal or exponent notation, e.g. 2.5 or 2.5e-3"
                    )


def md_cell(value):
    """One cell of a Markdown table as text: a ``|`` inside it escaped (``\\|``, e.g. ``||dp||``), a
    line break made a space, so that the row keeps its header's column count."""
    return str(value).replace("\r", " ").replace("\n", " ").replace("|", "\\|")


def md_row(cells):
    """A Markdown table row ``| a | b |`` of ``cells`` (each through ``md_cell``)."""
    return "| " + " | ".join(md_cell(c) for c in cells) + " |"
