"""Atomic output: a file appears complete or not at all, so an interrupted run resumes cleanly."""
from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path

from .errors import CdprError


def atomic(path, write):
    """Run write(tmp) on a temporary file beside ``path``, then rename it onto ``path``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_table(df, path):
    """Write a DataFrame as parquet (.parquet) or CSV (.csv), atomically."""
    import pandas as pd

    suffix = Path(path).suffix
    if suffix == ".parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        # uncompressed (float columns barely compress; snappy triples the write time) and dictionary
        # encoding only for the categorical columns (trying it on every float column costs 5x)
        table = pa.Table.from_pandas(df, preserve_index=False)
        cats = [c for c in df.columns if isinstance(df[c].dtype, pd.CategoricalDtype)]
        atomic(path, lambda tmp: pq.write_table(table, tmp, compression=None, use_dictionary=cats or False))
    elif suffix == ".csv":
        atomic(path, lambda tmp: df.to_csv(tmp, index=False))
    else:
        raise CdprError(f"{path}: unknown table format '{suffix}'; allowed: .parquet, .csv")


def read_table(path):
    import pandas as pd

    suffix = Path(path).suffix
    if suffix == ".parquet":
        return pd.read_parquet(path)
    if suffix == ".csv":
        return pd.read_csv(path)
    raise CdprError(f"{path}: unknown table format '{suffix}'; allowed: .parquet, .csv")


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
    atomic(path, lambda tmp: Path(tmp).write_text(json.dumps(clean_json(obj), indent=2) + "\n"))


def write_text(text, path):
    atomic(path, lambda tmp: Path(tmp).write_text(text))
