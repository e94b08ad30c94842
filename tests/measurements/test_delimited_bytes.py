"""The delimited reader parses a table taken as it is from the file's own bytes (issue 31: the
text was encoded again): the same raw table as the path that joins and encodes the kept lines,
whatever the byte order mark, the last line break and the characters of the last cell."""

import pandas as pd
import pytest

from contactres.measurements.readers import _delimited

ROWS = "sweep,amplitude_m,df_Hz,label\ns1,1e-9,2.5,Glas\ns1,2e-9,2.4,Øl\ns2,1e-9,2.6,{last}"


@pytest.mark.parametrize("bom", [b"", b"\xef\xbb\xbf"])
@pytest.mark.parametrize("end", ["", "\n"])
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
