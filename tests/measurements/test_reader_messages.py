"""Messages of the readers that misled (issue 27, point 15), each reproduced here with the
input that showed it: a valid table after a long comment preamble, a CR inside a quoted label,
rows with more fields than the header, TOML constants that are dates or that make the shifts
look absolute, an empty output name."""

import os
from importlib import resources

import pytest

from contactres.fileio import OutputError, ResultSet, check_output_file
from contactres.measurements import read_sweeps
from contactres.measurements.readers import BUILT_IN


@pytest.fixture
def example(tmp_path):
    """The package's example sweep table, as lines (header first)."""
    source = resources.files("contactres") / "data" / "example_sweeps.csv"
    return source.read_text(encoding="utf-8").splitlines()


def _one_line(info, *words):
    text = str(info.value)
    assert len(text.splitlines()) == 1, text
    for w in words:
        assert w in text, text
    return text


def test_a_table_after_a_long_comment_preamble_is_recognised(tmp_path, example):
    preamble = [f"# run note {i}: " + "x" * 60 for i in range(100)]  # ~7.5 kB
    path = tmp_path / "noted.csv"
    path.write_text("\n".join([*preamble, *example[:200]]) + "\n")
    assert BUILT_IN.pick(path, "sweeps").name == "csv"
    assert len(read_sweeps(path).data) == 199


def test_no_reader_says_what_it_found(tmp_path):
    only = tmp_path / "only.csv"
    only.write_text("\n".join(f"# note {i} " + "y" * 70 for i in range(80)) + "\n")
    with pytest.raises(ValueError) as info:
        BUILT_IN.pick(only, "sweeps")
    _one_line(info, "only.csv", "only comment lines")
    junk = tmp_path / "junk.csv"
    junk.write_text("# a comment\nhello world\n")
    with pytest.raises(ValueError) as info:
        BUILT_IN.pick(junk, "sweeps")
    _one_line(info, "junk.csv", "'hello world'")


def test_a_line_break_inside_a_quoted_label_is_named(tmp_path, example):
    cells = example[1].split(",")
    cells[2] = '"SiO2\r2.2mm"'  # a CR inside the quotes of the configuration
    path = tmp_path / "cr.csv"
    path.write_bytes(("\n".join([example[0], ",".join(cells), *example[2:50]]) + "\n").encode())
    with pytest.raises(ValueError) as info:
        read_sweeps(path)
    _one_line(info, "cr.csv, line 2", "quoted cell runs over a line break")


def test_every_row_with_too_many_fields_is_named(tmp_path, example):
    lines = example[:40]
    for i in (3, 7, 9):
        lines[i] += ",x,y"
    path = tmp_path / "long.csv"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as info:
        read_sweeps(path)
    _one_line(
        info,
        "long.csv",
        "3 rows",
        "header's 15",
        "lines 4 (17 fields), 8 (17 fields), 10 (17 fields)",
    )


def _without_fundamental(tmp_path, example):
    header = example[0].split(",")
    i = header.index("fundamental_Hz")
    rows = [",".join(c for j, c in enumerate(ln.split(",")) if j != i) for ln in example[:80]]
    path = tmp_path / "t.csv"
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize(
    "toml, words",
    [
        ("fundamental_Hz = 1979-05-27", ["t.toml", "fundamental_Hz = 1979-05-27 is a date"]),
        ("fundamental_Hz = 07:32:00", ["t.toml", "07:32:00 is a date or time"]),
        ("fundamental_Hz = [5e6]", ["t.toml", "is an array"]),
        ("fundamental_Hz = 1000", ["column 'df_Hz'", "fundamental 1000 Hz",
                                   "t.toml, key 'fundamental_Hz'", "or a wrong fundamental"]),
    ],
)  # fmt: skip
def test_toml_constants_are_blamed_as_written(tmp_path, example, toml, words):
    path = _without_fundamental(tmp_path, example)
    path.with_suffix(".toml").write_text(toml + "\n")
    with pytest.raises(ValueError) as info:
        read_sweeps(path)
    text = _one_line(info, *words)
    assert "datetime" not in text


@pytest.mark.parametrize("name", ["", " "])
def test_an_empty_output_name_is_refused(tmp_path, name):
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        with pytest.raises(OutputError, match="is empty"):
            check_output_file(name)
        with pytest.raises(OutputError, match="is empty"), ResultSet(name, names=["a.csv"]) as rs:
            rs.path("a.csv").write_text("x")
    finally:
        os.chdir(cwd)
    assert list(tmp_path.iterdir()) == []
