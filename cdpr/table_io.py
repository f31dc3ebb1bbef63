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

#: Rows of one parquet row group: pyarrow's default for ``pq.write_table`` (the smaller of the
#: table's length and 1024 * 1024). ``write_table_chunks`` cuts its row groups at the same rows so
#: that a table written in chunks has the bytes of the same table written at once.
ROW_GROUP_ROWS = 1024 * 1024


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


def write_table_chunks(frames, path, float_format=None):
    """Write the DataFrames ``frames`` (an iterable, e.g. a generator that solves one chunk of points
    per item) one after the other as one table, atomically, holding only part of it in memory.

    The bytes are those of ``write_table(pd.concat(frames), path)`` when every frame has the same
    columns, dtypes and categories (tests/cli/test_long_work.py): a CSV is written row by row, a
    parquet file gets the same row groups (``ROW_GROUP_ROWS``), each written from one contiguous
    table. Memory: one frame for a CSV; up to one row group of the table, in Arrow form (about 8 bytes
    per number, twice while the group is written), for a parquet file. An exception (also
    KeyboardInterrupt) leaves no file behind.

    Parameters
    ----------
    frames : iterable of DataFrame
        The table's rows, in order; at least one frame.
    path : str or Path
        A .parquet or .csv file.
    float_format : str, optional
        As ``write_table``.

    Returns
    -------
    int
        The number of rows written.
    """
    suffix = Path(path).suffix
    if suffix not in TABLE_SUFFIXES:
        raise CdprError(f"{path}: unknown table format '{suffix}'; allowed: .parquet, .csv")
    rows = [0]

    def write_csv(tmp):
        fmt = float_format or f"%.{CSV_DIGITS}g"
        with open(tmp, "w", encoding="utf-8", newline="") as f:
            for k, df in enumerate(frames):
                _rounded_objects(df).to_csv(f, index=False, header=k == 0, float_format=fmt)
                rows[0] += len(df)

    def write_parquet(tmp):
        writer, buffered, n_buffered = None, [], 0
        try:
            for df in frames:
                table = pa.Table.from_pandas(df, preserve_index=False)
                if writer is None:
                    cats = [c for c in df.columns if isinstance(df[c].dtype, pd.CategoricalDtype)]
                    writer = pq.ParquetWriter(
                        tmp, table.schema, compression=None, use_dictionary=cats or False
                    )
                buffered.append(table)
                n_buffered += len(table)
                rows[0] += len(table)
                while n_buffered >= ROW_GROUP_ROWS:
                    whole = pa.concat_tables(buffered).combine_chunks()
                    writer.write_table(whole.slice(0, ROW_GROUP_ROWS))
                    rest = whole.slice(ROW_GROUP_ROWS)
                    buffered, n_buffered = ([rest] if len(rest) else []), len(rest)
                    del whole
            if buffered:
                writer.write_table(pa.concat_tables(buffered).combine_chunks())
        finally:
            if writer is not None:
                writer.close()

    atomic(path, write_parquet if suffix == ".parquet" else write_csv)
    return rows[0]


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


def _check_readable(path):
    """``path`` as a Path, refused unless it names an existing .parquet or .csv file (a folder is
    named as such; a missing file raises FileNotFoundError)."""
    path = Path(path)
    suffix = path.suffix
    if suffix not in TABLE_SUFFIXES:
        raise CdprError(f"{path}: unknown table format '{suffix}'; allowed: .parquet, .csv")
    if path.is_dir():
        raise CdprError(f"{path}: is a folder, not a {suffix[1:]} table; remove it and run again")
    if not path.exists():
        raise FileNotFoundError(path)
    return path


def _unreadable(path, exc):
    """The CdprError of a table file that pandas or pyarrow cannot read (``read_table``)."""
    return CdprError(
        f"{path}: cannot read this table ({type(exc).__name__}: {' '.join(str(exc).split())[:200]}); "
        f"{_found(path, path.suffix)}"
    )


def table_columns(path):
    """The column names of a .parquet or .csv table, read from its schema or header only.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    list of str
        As ``read_table(path).columns`` would give them (a CSV's repeated names get pandas' suffixes).
    """
    path = _check_readable(path)
    try:
        if path.suffix == ".parquet":
            return list(pq.ParquetFile(path).schema_arrow.names)
        return list(pd.read_csv(path, nrows=0).columns)
    except Exception as exc:  # pyarrow.ArrowInvalid, pandas' EmptyDataError/ParserError, ...
        raise _unreadable(path, exc) from None


def iter_table(path, columns, chunk_rows):
    """The columns ``columns`` of a .parquet or .csv table, ``chunk_rows`` rows at a time, so that a
    large table is read with bounded memory (pyarrow's batches of a parquet file, pandas' chunks of
    a CSV); the values are those of ``read_table(path)[columns]``.

    Parameters
    ----------
    path : str or Path
    columns : list of str
        Columns that the table has (``table_columns``).
    chunk_rows : int
        Rows per chunk (the last one may be shorter).

    Yields
    ------
    DataFrame
        The next ``chunk_rows`` rows of those columns; nothing for a table without rows.
    """
    path = _check_readable(path)
    try:
        if path.suffix == ".parquet":
            reader = pq.ParquetFile(path)
            chunks = (
                batch.to_pandas()
                for batch in reader.iter_batches(batch_size=chunk_rows, columns=list(columns))
            )
        else:
            reader = chunks = pd.read_csv(path, usecols=list(columns), chunksize=chunk_rows)
        with reader:  # closed when the reading stops early too (a generator closed after one chunk)
            for df in chunks:
                if len(df):  # a header-only CSV reads as one empty chunk of text columns
                    yield df
    except Exception as exc:  # pyarrow.ArrowInvalid, pandas' EmptyDataError/ParserError, ...
        raise _unreadable(path, exc) from None


def read_table(path):
    """Read a .parquet or .csv table; an unreadable file is named, with what was found and what to
    do (a folder, binary data where CSV text belongs, a truncated table, ...)."""
    path = _check_readable(path)
    try:
        return pd.read_parquet(path) if path.suffix == ".parquet" else pd.read_csv(path)
    except FileNotFoundError:
        raise
    except Exception as exc:  # pyarrow.ArrowInvalid, pandas' EmptyDataError/ParserError, ...
        raise _unreadable(path, exc) from None
