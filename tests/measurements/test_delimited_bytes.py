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


@pytest.mark.parametrize("code", range(128))
def test_ascii_bytes_are_taken_as_they_are_where_their_text_would_be(monkeypatch, code):
    # An ASCII file is not decoded: its bytes are tested for blank lines, comments and CRs
    # (_ascii_lines). Against the text's own tests (_data_lines): every ASCII character at the
    # start of the file, of a line, of the last line and at the end, with and without the
    # last LF. Where the text is taken as it is, so are the bytes, with the same line numbers.
    split = _delimited._LINE_BREAK.split
    sorted_lines = []

    class Spy:  # _data_lines splits the text into lines only where it sorts them one by one
        def split(self, text):
            sorted_lines.append(text)
            return split(text)

    monkeypatch.setattr(_delimited, "_LINE_BREAK", Spy())
    c = chr(code)
    for text in (f"{c}h,a\n1,2\n", f"h,a\n{c}1,2\n3,4\n", f"h,a\n1,2\n{c}", f"h,a\n1,2{c}"):
        for whole in (text, text + "\n"):
            sorted_lines.clear()
            body, numbers, comments = _delimited._data_lines(whole)
            got = _delimited._ascii_lines(whole.encode("ascii"))
            assert (got is None) == bool(sorted_lines), repr(whole)
            if got is not None:
                assert (body, comments) == (whole.removesuffix("\n"), [])
                assert got.tolist() == numbers.tolist()


def test_a_nul_byte_of_an_ascii_table_is_named_by_its_line(tmp_path):
    path = tmp_path / "nul.csv"
    path.write_bytes(b"sweep,amplitude_m\ns1,1e-9\ns1,2\x00e-9\n")
    with pytest.raises(ValueError, match=r"nul\.csv: line 3: a NUL character"):
        _delimited.load(path, ("amplitude_m",))
