"""The delimited reader parses a table taken as it is from the file's own bytes (issue 31: the
text was encoded again): the same raw table as the path that joins and encodes the kept lines,
whatever the byte order mark, the last line break and the characters of the last cell. The
usual file's last LF stays in the bytes parsed (no copy of the file): it adds no row, and a
bad row is still named by its own line."""

import pandas as pd
import pytest

from contactres.measurements.readers import _delimited

ROWS = "sweep,amplitude_m,df_Hz,label\ns1,1e-9,2.5,Glas\ns1,2e-9,2.4,Øl\ns2,1e-9,2.6,{last}"


@pytest.mark.parametrize("bom", [b"", b"\xef\xbb\xbf"])
@pytest.mark.parametrize("end", ["", "\n", "\r", "\r\n"])  # "\r": a bare CR ends the file
@pytest.mark.parametrize("last", ["quartz", "Øl", "ℏ€"])
def test_plain_table_as_the_table_with_a_dropped_line(tmp_path, bom, end, last):
    text = ROWS.format(last=last)
    plain = tmp_path / "plain.csv"
    plain.write_bytes(bom + (text + end).encode("utf-8"))
    # A comment below the data: its lines are joined and encoded (the other path), the data
    # rows keep their line numbers.
    dropped = tmp_path / "dropped.csv"
    dropped.write_bytes(bom + (text + "\n# end\n").encode("utf-8"))
    numbers = ("amplitude_m", "df_Hz")
    got = _delimited.load(plain, numbers)
    want = _delimited.load(dropped, numbers)
    pd.testing.assert_frame_equal(got, want)
    assert list(got.columns) == ["sweep", "amplitude_m", "df_Hz", "label", "line"]
    assert got["label"].tolist() == ["Glas", "Øl", last]
    assert got["line"].tolist() == [2, 3, 4]


@pytest.mark.parametrize("end", ["\n", "\r", "\n# end\n"])
def test_a_bad_row_is_named_by_its_line_whatever_the_last_line_break(tmp_path, end):
    # The lines of the error's search are the bytes parsed less the last LF kept in them: one
    # line too many (or a lost last line) would not match the line numbers.
    path = tmp_path / "bad.csv"
    path.write_bytes((ROWS.format(last="quartz,extra") + end).encode("utf-8"))
    with pytest.raises(ValueError) as err:
        _delimited.load(path, ("amplitude_m", "df_Hz"))
    assert str(err.value) == (
        f"{path}: not a readable ','-separated table (line 4 has 5 fields, the header 4: 1 "
        "field more than the header; every row has one field per column)"
    )
