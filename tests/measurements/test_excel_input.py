"""Tables on a sheet of an Excel workbook, read through the reader registry as the same table
in CSV is: equal values, and errors that name the file, the sheet, the Excel row, the column,
the value and the rule. The workbooks are written here with openpyxl."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

import contactres
from contactres.cli import main
from contactres.errors import ContactresInputError, MissingExtraError
from contactres.measurements import read_resonance_table, read_sweeps
from contactres.measurements.readers import BUILT_IN
from contactres.measurements.schema import AFM_TABLE

openpyxl = pytest.importorskip("openpyxl")

DATA = Path(contactres.__file__).parent / "data"


@pytest.fixture(scope="module")
def sweeps_csv(tmp_path_factory) -> Path:
    """The first 8 sweeps of the example table, as CSV (the reference)."""
    table = pd.read_csv(DATA / "example_sweeps.csv")
    path = tmp_path_factory.mktemp("csv") / "sweeps.csv"
    table[table["sweep"].isin(table["sweep"].unique()[:8])].to_csv(path, index=False)
    return path


def _book(path: Path, sheets: dict[str, list[list]]) -> Path:
    """A workbook with ``sheets`` (name -> rows, the first written at row 1)."""
    book = openpyxl.Workbook()
    book.remove(book.active)
    for name, rows in sheets.items():
        sheet = book.create_sheet(name)
        for row in rows:
            sheet.append(row)
    book.save(path)
    return path


def _rows(csv: Path) -> list[list]:
    table = pd.read_csv(csv)
    values = table.astype(object).where(table.notna(), None).to_numpy().tolist()
    return [list(table.columns), *values]


def test_a_sweep_table_on_a_sheet_reads_as_its_csv(sweeps_csv, tmp_path):
    rows = _rows(sweeps_csv)
    # The sheet named 'sweeps' is read, not the first one.
    book = _book(tmp_path / "s.xlsx", {"notes": [["measured on Monday"]], "sweeps": rows})
    assert BUILT_IN.pick(book, "sweeps").name == "xlsx"
    from_csv, from_book = read_sweeps(sweeps_csv), read_sweeps(book)
    pd.testing.assert_frame_equal(from_book.data, from_csv.data)
    assert from_book.source == f"{book}, sheet 'sweeps'"


def test_without_a_sheet_of_its_kind_the_first_sheet_is_read(sweeps_csv, tmp_path):
    book = _book(tmp_path / "s.xlsx", {"Sheet A": _rows(sweeps_csv), "other": [["x"]]})
    assert len(read_sweeps(book).data) == len(pd.read_csv(sweeps_csv))


def test_a_bad_cell_is_named_by_file_sheet_excel_row_column_value_and_rule(sweeps_csv, tmp_path):
    rows = _rows(sweeps_csv)
    column = rows[0].index("df_Hz")
    rows[4][column] = "12,5 Hz"  # Excel row 5 (the header is row 1)
    book = _book(tmp_path / "bad.xlsx", {"sweeps": rows})
    with pytest.raises(ContactresInputError) as caught:
        read_sweeps(book)
    assert str(caught.value) == (
        f"{book}, sheet 'sweeps', row 5, column 'df_Hz': value '12,5 Hz' is not a number"
    )
    rows[4][column] = 10.0
    amplitude = rows[0].index("amplitude_m")
    rows[7][amplitude] = rows[9][amplitude] = -1e-9  # rows 8 and 10 break a rule
    book = _book(tmp_path / "bad2.xlsx", {"sweeps": rows})
    with pytest.raises(ContactresInputError) as caught:
        read_sweeps(book)
    message = str(caught.value)
    assert message.startswith(f"{book}, sheet 'sweeps', row 8, column 'amplitude_m'")
    assert "rows 8, 10" in message and "-1e-09" in message and ">= 0" in message


def test_a_header_named_twice_or_a_value_without_a_column_is_refused(tmp_path):
    book = _book(tmp_path / "d.xlsx", {"sweeps": [[], ["sweep", "df_Hz", "df_Hz"], ["a", 1, 2]]})
    with pytest.raises(ContactresInputError, match=r"sheet 'sweeps', row 2: duplicate column"):
        read_sweeps(book)
    book = _book(tmp_path / "w.xlsx", {"sweeps": [["sweep", "df_Hz"], ["a", 1, "stray"]]})
    with pytest.raises(ContactresInputError, match=r"row 2: a value right of the last named"):
        read_sweeps(book)
    book = _book(tmp_path / "e.xlsx", {"sweeps": [[None, None]]})
    with pytest.raises(ContactresInputError, match=r"sheet 'sweeps': the sheet is empty"):
        read_sweeps(book)


def test_a_resonance_table_on_a_sheet_reads_as_its_csv(tmp_path):
    csv = DATA / "example_afm.csv"
    book = _book(tmp_path / "afm.xlsx", {"resonances": _rows(csv)})
    from_csv, from_book = (
        read_resonance_table(csv, AFM_TABLE),
        read_resonance_table(book, AFM_TABLE),
    )
    for column in AFM_TABLE.names:
        np.testing.assert_array_equal(from_book[column], from_csv[column])


def test_qcm_analyze_names_the_sheet_and_row_in_one_line(sweeps_csv, tmp_path):
    rows = _rows(sweeps_csv)
    rows[2][rows[0].index("normal_force_N")] = -0.001
    book = _book(tmp_path / "q.xlsx", {"sweeps": rows})
    run = CliRunner().invoke(main, ["qcm", "analyze", str(book), "--out", str(tmp_path / "o")])
    assert run.exit_code == 2
    lines = run.output.strip().splitlines()
    assert len(lines) == 1 and "sheet 'sweeps', row 3, column 'normal_force_N'" in lines[0]


def test_without_openpyxl_a_workbook_is_one_line_naming_the_extra(tmp_path, monkeypatch):
    book = _book(tmp_path / "s.xlsx", {"sweeps": [["sweep"], ["a"]]})
    monkeypatch.setattr("builtins.__import__", _refusing("openpyxl"))
    with pytest.raises(MissingExtraError, match=r"contactres\[excel\]"):
        read_sweeps(book)


def _refusing(module: str):
    """An ``__import__`` that refuses ``module`` (as if it were not installed)."""
    import builtins

    real = builtins.__import__

    def importer(name, *args, **kwargs):
        if name == module or name.startswith(module + "."):
            raise ImportError(f"No module named {module!r}")
        return real(name, *args, **kwargs)

    return importer


def test_a_tidy_spectra_table_on_a_sheet_reads_as_its_csv(tmp_path):
    from contactres.measurements._spectra_table import read_spectra

    table = pd.read_csv(DATA / "example_spectra.csv")
    first = table[table["spectrum"].isin(table["spectrum"].unique()[:6])]
    csv = tmp_path / "spectra.csv"
    first.to_csv(csv, index=False)
    book = _book(tmp_path / "spectra.xlsx", {"spectra": _rows(csv)})
    from_csv, from_book = read_spectra(csv), read_spectra(book)
    pd.testing.assert_frame_equal(from_book.points, from_csv.points)
    pd.testing.assert_frame_equal(from_book.spectra, from_csv.spectra)
    assert from_book.source == f"{book}, sheet 'spectra'"


def test_a_tidy_shift_table_on_a_sheet_reads_as_its_csv(tmp_path):
    from contactres.measurements.readers.exports import SHIFT_READERS, read_export

    csv = DATA / "example_particles.csv"
    book = _book(tmp_path / "shifts.xlsx", {"notes": [["x"]], "shifts": _rows(csv)})
    from_csv = read_export(csv, readers=SHIFT_READERS, fundamental=5e6)
    from_book = read_export(book, readers=SHIFT_READERS, fundamental=5e6)
    pd.testing.assert_frame_equal(from_book.data, from_csv.data)
    assert from_book.conventions["reader"] == "tidy"
    rows = _rows(csv)
    rows[3][rows[0].index("overtone")] = 4  # Excel row 4: an even overtone
    bad = _book(tmp_path / "bad.xlsx", {"shifts": rows})
    with pytest.raises(ContactresInputError, match=r"bad.xlsx, sheet 'shifts', row 4, column "):
        read_export(bad, readers=SHIFT_READERS, fundamental=5e6)


def test_qcm_analyze_tells_a_spectra_workbook_from_a_sweeps_workbook(sweeps_csv, tmp_path):
    from contactres.measurements import is_spectra_input

    spectra = pd.read_csv(DATA / "example_spectra.csv").head(40)
    csv = tmp_path / "spectra.csv"
    spectra.to_csv(csv, index=False)
    assert is_spectra_input(_book(tmp_path / "sp.xlsx", {"spectra": _rows(csv)}))
    assert not is_spectra_input(_book(tmp_path / "sw.xlsx", {"sweeps": _rows(sweeps_csv)}))
    assert not is_spectra_input(_book(tmp_path / "empty.xlsx", {"sweeps": [[None]]}))
