"""Table files (cdpr.table_io): written and read back (formats, categories, digits); an unreadable table
is named (read_table): the message says what was found, and the hint about an
interrupted run is given only for a truncated table."""

import numpy as np
import pandas as pd
import pytest

from cdpr import table_io
from cdpr.errors import CdprError

TRUNCATED = "probably truncated by an interrupted run"


def _message(path):
    with pytest.raises(CdprError) as exc:
        table_io.read_table(path)
    msg = str(exc.value)
    assert msg.startswith(str(path)) and "\n" not in msg
    return msg


def test_a_folder_is_named_a_folder(tmp_path):
    (tmp_path / "plane.csv").mkdir()
    msg = _message(tmp_path / "plane.csv")
    assert "is a folder, not a csv table" in msg and TRUNCATED not in msg


def test_binary_data_in_a_csv_is_named(tmp_path):
    p = tmp_path / "t.csv"
    p.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)))
    msg = _message(p)
    assert "holds binary data, not CSV text" in msg and TRUNCATED not in msg


def test_a_parquet_file_named_csv_is_named(tmp_path):
    pq = tmp_path / "t.parquet"
    table_io.write_table(pd.DataFrame({"x": [1.0, 2.0]}), pq)
    p = tmp_path / "t.csv"
    p.write_bytes(pq.read_bytes())
    msg = _message(p)
    assert "it is a parquet file, not CSV text" in msg and TRUNCATED not in msg


def test_a_text_file_named_parquet_is_not_called_truncated(tmp_path):
    p = tmp_path / "t.parquet"
    p.write_text("x,y\n1,2\n")
    msg = _message(p)
    assert "it is not a parquet file (it starts with b'x,y" in msg and TRUNCATED not in msg


def test_a_cut_parquet_file_is_called_truncated(tmp_path):
    full = tmp_path / "full.parquet"
    table_io.write_table(pd.DataFrame({"x": range(100)}), full)
    p = tmp_path / "cut.parquet"
    p.write_bytes(full.read_bytes()[: full.stat().st_size // 2])
    assert "without its footer" in (msg := _message(p)) and TRUNCATED in msg


@pytest.mark.parametrize("content", [b"", b"x,y\n1,2\n3,4,5,6\n"], ids=["empty", "ragged"])
def test_an_empty_or_cut_csv_is_called_truncated(tmp_path, content):
    p = tmp_path / "t.csv"
    p.write_bytes(content)
    assert TRUNCATED in _message(p)


def test_a_good_table_reads_back(tmp_path):
    df = pd.DataFrame({"x": [0.1, 0.2], "s": ["ok", "é"]})
    for name in ("t.csv", "t.parquet"):
        table_io.write_table(df, tmp_path / name)
        pd.testing.assert_frame_equal(table_io.read_table(tmp_path / name), df)


def test_numbers_in_a_text_column_are_written_to_the_same_digits_as_a_float_column(tmp_path):
    # 0.1 + 0.2 is 0.30000000000000004: the last bits of a sum must not reach the file
    df = pd.DataFrame({"value": ["best 1", 0.1 + 0.2, 206.44006573099998, float("nan")], "x": 0.1 + 0.2})
    path = tmp_path / "t.csv"
    table_io.write_table(df, path)
    lines = path.read_text().splitlines()
    assert lines[1:] == ["best 1,0.3", "0.3,0.3", "206.440065731,0.3", ",0.3"]


def test_an_unknown_table_format_is_refused_naming_the_allowed_ones(tmp_path):
    df = pd.DataFrame({"x": [1.0]})
    for call in (lambda p: table_io.write_table(df, p), table_io.read_table):
        with pytest.raises(CdprError) as exc:
            call(tmp_path / "t.xlsx")
        msg = str(exc.value)
        assert msg == f"{tmp_path / 't.xlsx'}: unknown table format '.xlsx'; allowed: .parquet, .csv"
    assert not (tmp_path / "t.xlsx").exists()


def test_a_missing_table_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        table_io.read_table(tmp_path / "absent.parquet")


def test_parquet_keeps_categories_and_bits_and_csv_takes_a_float_format(tmp_path):
    x = np.array([0.1 + 0.2, np.pi, -1e-300])
    df = pd.DataFrame(
        {"x": x, "status": pd.Categorical(["ok", "slack", "ok"], categories=["ok", "slack", "x"])}
    )
    table_io.write_table(df, tmp_path / "t.parquet")
    back = table_io.read_table(tmp_path / "t.parquet")
    assert back["x"].to_numpy().tobytes() == x.tobytes()  # every bit
    assert list(back["status"].cat.categories) == ["ok", "slack", "x"]
    table_io.write_table(df[["x"]], tmp_path / "t.csv", float_format="%.4f")
    assert (tmp_path / "t.csv").read_text().splitlines() == ["x", "0.3000", "3.1416", "-0.0000"]
