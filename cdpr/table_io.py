"""Table files: parquet and CSV tables written atomically and read back with what went wrong named.

Beside ``cdpr.io`` (atomic files, JSON, text) because it needs pandas and pyarrow, which the command
line loads only for the commands that read or write a table.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from cdpr.errors import CdprError
from cdpr.io import CSV_DIGITS, TABLE_SUFFIXES, atomic


def write_table(df, path, float_format=None):
    """Write a DataFrame as parquet (.parquet) or CSV (.csv, floats with CSV_DIGITS significant
    digits, or ``float_format`` such as ``"%.4f"`` where fewer digits are what the computation
    determines), atomically."""
    suffix = Path(path).suffix
    if suffix == ".parquet":
        # uncompressed (float columns barely compress; snappy triples the write time) and dictionary
        # encoding only for the categorical columns (trying it on every float column costs 5x)
        table = pa.Table.from_pandas(df, preserve_index=False)
        cats = [c for c in df.columns if isinstance(df[c].dtype, pd.CategoricalDtype)]
        atomic(path, lambda tmp: pq.write_table(table, tmp, compression=None, use_dictionary=cats or False))
    elif suffix == ".csv":
        df = _rounded_objects(df)
        fmt = float_format or f"%.{CSV_DIGITS}g"
        atomic(path, lambda tmp: df.to_csv(tmp, index=False, float_format=fmt))
    else:
        raise CdprError(f"{path}: unknown table format '{suffix}'; allowed: .parquet, .csv")


def _rounded_objects(df):
    """``df`` with the floats of its object columns (a column mixing numbers and text, such as a
    conclusions table's values) rounded to CSV_DIGITS significant digits, as ``float_format`` rounds
    the float columns: the digits written do not depend on the last bits of a computation."""
    cols = [c for c in df.columns if df[c].dtype == object]
    if not cols:
        return df
    out = df.copy()
    for c in cols:
        out[c] = out[c].map(lambda v: float(f"{v:.{CSV_DIGITS}g}") if isinstance(v, float) else v)
    return out


#: The magic bytes at both ends of a parquet file.
_PARQUET_MAGIC = b"PAR1"


def _found(path, suffix):
    """What an unreadable table file holds, and what to do: a truncated table (the only case for the
    hint about an interrupted run), or something else that is named (binary data in a .csv, a file
    that is not parquet, ...)."""
    size = path.stat().st_size
    with open(path, "rb") as f:
        head = f.read(4096)
        f.seek(max(size - 4, 0))
        tail = f.read(4)
    truncated = "it is probably truncated by an interrupted run: delete it and run again"
    if size == 0:
        return f"it is empty (0 bytes); {truncated}"
    if suffix == ".parquet":
        if head[:4] == _PARQUET_MAGIC and tail != _PARQUET_MAGIC:
            return f"a parquet file without its footer; {truncated}"
        if head[:4] != _PARQUET_MAGIC:
            return f"it is not a parquet file (it starts with {head[:16]!r}); write it again with cdpr"
        return "a complete parquet file that pyarrow cannot read; write it again with cdpr"
    if head[:4] == _PARQUET_MAGIC:
        return "it is a parquet file, not CSV text; give it a .parquet name or write it again as CSV"
    try:
        text = head.decode("utf-8")
    except UnicodeDecodeError as exc:
        if exc.start < len(head) - 4:  # not a multi-byte letter cut by the 4 KiB read
            return (
                f"it holds binary data, not CSV text (it starts with {head[:16]!r}); write it again with cdpr"
            )
        text = head[: exc.start].decode("utf-8")
    if "\0" in text:
        return f"it holds binary data, not CSV text (it starts with {head[:16]!r}); write it again with cdpr"
    if not text.strip():
        return f"it holds only blank lines; {truncated}"
    return truncated


def read_table(path):
    """Read a .parquet or .csv table; an unreadable file is named, with what was found and what to
    do (a folder, binary data where CSV text belongs, a truncated table, ...)."""
    path = Path(path)
    suffix = path.suffix
    if suffix not in TABLE_SUFFIXES:
        raise CdprError(f"{path}: unknown table format '{suffix}'; allowed: .parquet, .csv")
    if path.is_dir():
        raise CdprError(f"{path}: is a folder, not a {suffix[1:]} table; remove it and run again")
    if not path.exists():
        raise FileNotFoundError(path)
    try:
        return pd.read_parquet(path) if suffix == ".parquet" else pd.read_csv(path)
    except FileNotFoundError:
        raise
    except Exception as exc:  # pyarrow.ArrowInvalid, pandas' EmptyDataError/ParserError, ...
        raise CdprError(
            f"{path}: cannot read this table ({type(exc).__name__}: {' '.join(str(exc).split())[:200]}); "
            f"{_found(path, suffix)}"
        ) from None
