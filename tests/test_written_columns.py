"""A table contactres writes with a column name twice is a fault of contactres (the code that
built the table), not of the user's input: every writer (CSV, numpy archive, the report's
workbook and NetCDF file, the console's table) refuses it before writing anything, with a
plain ValueError that names the repeated name and its places, never a ContactresInputError
(which the command line shows as the user's error) and never an AttributeError from deep inside.
On the command line it is one "internal error" line, exit code 1.

A user's table with a name twice is refused where it is read: tests/cli/test_duplicate_columns.py.
"""

from dataclasses import dataclass
from types import MappingProxyType

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres import _csvcells
from contactres.cli import main
from contactres.errors import ContactresInputError
from contactres.fileio import neutralised, write_csv, write_npz
from contactres.jobs.contract import JobResult
from contactres.report import write_report

RULE = "every column of a table written needs its own name"
PLACES = "'x' (columns 1, 3)"


def _twice() -> pd.DataFrame:
    """Two float columns named x (with the first of them text that looks like a formula once,
    so that every step of the writing has work to do), a text column between."""
    frame = pd.DataFrame({"x": [1.5, 2.0], "label": ["=1+1", "b"], "y": [3.0, np.nan]})
    frame.columns = ["x", "label", "x"]
    return frame


def _internal(caught) -> str:
    assert type(caught.value) is ValueError  # not ContactresInputError, nor AttributeError
    assert not isinstance(caught.value, ContactresInputError)
    return str(caught.value)


@pytest.mark.parametrize(
    "options",
    [
        {"index": False},
        {"index": False, "float_format": "%.10g"},
        {"index": False, "na_rep": "NA", "float_format": "%.3e"},
        {"index": True},  # pandas' writer
        {"index": False, "sep": ";"},  # pandas' writer
    ],
)
def test_csv_to_refuses_a_name_twice_before_opening_the_file(tmp_path, options):
    target = tmp_path / "t.csv"
    with pytest.raises(ValueError) as caught:
        _csvcells.csv_to(target, _twice(), options)
    assert _internal(caught) == f"the table written: duplicate column name(s) {PLACES}; {RULE}"
    assert not target.exists()


def test_write_csv_and_write_npz_name_the_file_and_leave_nothing(tmp_path):
    for write, name in ((write_csv, "t.csv"), (write_npz, "t.npz")):
        target = tmp_path / name
        with pytest.raises(ValueError) as caught:
            write(target, _twice())
        assert _internal(caught) == f"{target}: duplicate column name(s) {PLACES}; {RULE}"
        assert list(tmp_path.iterdir()) == []


def test_the_other_writers_of_cells_refuse_it_too():
    for call in (
        lambda f: neutralised(f),  # the console's CSV (emit) and the workbook's cells
        lambda f: _csvcells.csv_text(f),
        lambda f: "".join(_csvcells.csv_chunks(f)),
        lambda f: _csvcells.floats_as_text(f),
    ):
        with pytest.raises(ValueError) as caught:
            call(_twice())
        assert PLACES in _internal(caught)


@pytest.mark.parametrize("fmt", ["csv", "json", "table"])
def test_the_console_table_refuses_it_in_every_format(fmt):
    import io

    from contactres.cli._common import emit

    stream = io.StringIO()
    with pytest.raises(ValueError) as caught:
        emit(_twice(), fmt, stream)
    assert _internal(caught) == f"the table written: duplicate column name(s) {PLACES}; {RULE}"
    assert stream.getvalue() == ""


def test_many_repeats_are_named_in_a_short_line():
    frame = pd.DataFrame(np.zeros((1, 3000)), columns=["a", "b", "c"] * 1000)
    with pytest.raises(ValueError) as caught:
        neutralised(frame)
    text = _internal(caught)
    assert text.startswith(
        "the table written: duplicate column name(s) 'a' (columns 1, 4, 7, 10, 13, ... 1000 in "
        "all); 'b' (columns 2, 5, 8, 11, 14, ... 1000 in all); 'c' (columns 3, 6, 9, 12, 15, "
        "... 1000 in all)"
    )
    assert len(text) < 300


def test_names_told_apart_by_type_alone_are_one_name_in_the_file(tmp_path):
    # 1 and "1" are two labels to pandas and the same header text in a CSV file
    frame = pd.DataFrame([[1.0, 2.0]], columns=[1, "1"])
    with pytest.raises(ValueError) as caught:
        write_csv(tmp_path / "t.csv", frame)
    assert "'1' (columns 1, 2)" in _internal(caught)


def test_distinct_names_are_written_as_before(tmp_path):
    frame = _twice()
    frame.columns = ["x", "label", "z"]
    _csvcells.csv_to(tmp_path / "a.csv", frame, {"index": False})
    frame.to_csv(tmp_path / "b.csv", index=False)  # pandas, for the bytes
    want = (tmp_path / "b.csv").read_bytes().replace(b"=1+1", b"'=1+1")  # neutralised
    assert (tmp_path / "a.csv").read_bytes() == want


@dataclass(frozen=True)
class Points(JobResult):
    SCHEMAS = MappingProxyType({"points": None})
    NAME = "points"

    points: pd.DataFrame
    conventions: dict


@pytest.mark.parametrize("fmt", ["csv", "xlsx", "netcdf"])
def test_the_report_writer_refuses_a_table_with_a_name_twice(tmp_path, monkeypatch, fmt):
    if fmt == "xlsx":
        pytest.importorskip("openpyxl")
    if fmt == "netcdf":
        pytest.importorskip("xarray")
    from contactres.report import _writer

    # The JSON file is written before the workbook and the NetCDF file: the check is up
    # front only if it is not written either.
    written = []
    monkeypatch.setattr(_writer, "write_text", lambda path, *a, **k: written.append(path))
    with pytest.raises(ValueError) as caught:
        write_report(Points(_twice(), {}), tmp_path / "r", (fmt, "json"))
    # Said up front for every format, naming the table: the writers' own checks further in
    # name a file (CSV), nothing (the workbook) or come after other files were written.
    assert _internal(caught) == (
        f"table 'points' of the points result: duplicate column name(s) {PLACES}; {RULE}"
    )
    assert written == []
    assert not (tmp_path / "r").exists()  # the set appears whole or not at all


def test_on_the_command_line_it_is_an_internal_error(tmp_path, monkeypatch):
    # A bug of ours stood in for: the RUM inversion hands back its k* column twice.
    import contactres.analysis

    real = contactres.analysis.invert_rum_table

    def twice(table, source="table", **options):
        out = real(table, source, **options)
        return pd.concat([out, out[["k_star_N_per_m"]]], axis=1)

    monkeypatch.setattr(contactres.analysis, "invert_rum_table", twice)
    source = contactres.example_path("example_rum.csv")
    r = CliRunner().invoke(main, ["rum", "invert", str(source), "--out", str(tmp_path / "o.csv")])
    assert r.exit_code == 1, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.output
    assert (
        lines[0]
        .split(": internal error: ", 1)[1]
        .startswith(
            f"ValueError: {tmp_path / 'o.csv'}: duplicate column "
            "name(s) 'k_star_N_per_m' (columns 6, 7); "
        )
    )
    assert "a fault of contactres, not of your input" in lines[0]
    assert not (tmp_path / "o.csv").exists()
