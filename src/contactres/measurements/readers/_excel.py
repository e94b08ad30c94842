"""Reader plug-in for Excel workbooks (``.xlsx``): a tidy table on one sheet.

The tables the delimited-text reader takes (sweep tables, resonance tables, tidy spectra
tables) are taken from a workbook too. The sheet read is the one named after the kind of table
(``sweeps``, ``resonances``, ``spectra``) when the workbook has one, else the first sheet. Its
first row that is not empty is the header; empty rows are skipped. Every row keeps its Excel
number (the header of a sheet that starts at the top is row 1), so that an error names the
file, the sheet, the row and the column as Excel shows them, then the value and the rule, as
for a CSV file (``attrs["source"]``: ``book.xlsx, sheet 'sweeps'``; ``attrs["line_word"]``:
``row``).

Cells are read as the values Excel stored (``data_only``: a formula gives its last computed
value, none if the workbook was never opened in a spreadsheet) and turned into the text a CSV
would hold: a number by its shortest exact form (``1e-09``), a date in ISO form, an empty cell
as empty text. A workbook is recognised by its suffix and the zip signature it starts with
(``PK\\x03\\x04``). Reading needs openpyxl (the ``excel`` extra).
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from ..._column_names import empty_places, excel_letters, refuse_line_name, repeats_text
from ...errors import ContactresInputError, MissingExtraError

if TYPE_CHECKING:  # annotations: pandas is imported where a table is read (a numpy archive's
    import pandas as pd  # reader shares this package and needs none, issue 31)

__all__ = ["detect", "loader", "suffixes"]

suffixes = (".xlsx",)

_ZIP = b"PK\x03\x04"


def detect(path: Path, head: str) -> bool:
    """True for a file with suffix ``.xlsx`` that starts with the zip signature."""
    if path.suffix.lower() not in suffixes or not path.is_file():
        return False
    with path.open("rb") as fh:
        return fh.read(4) == _ZIP


def _text(value) -> str:
    """A cell as the text a CSV file would hold."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)  # the shortest text that reads back as the same float
    if isinstance(value, dt.datetime | dt.date | dt.time):
        return value.isoformat()
    return str(value)


def _workbook(path: Path):
    try:
        import openpyxl
    except ImportError as exc:
        raise MissingExtraError(
            f"{path}: openpyxl is needed to read an Excel workbook; install the optional "
            "extra: pip install 'contactres[excel]'"
        ) from exc
    try:
        return openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as exc:  # openpyxl raises zipfile, KeyError or its own errors alike
        raise ContactresInputError(
            f"{path}: not a readable Excel workbook ({type(exc).__name__}: {exc})"
        ) from None


def _check_header(where: str, number: int, names: list[str]) -> None:
    """A header with a name twice, an empty cell before a named column (every repeat and every
    empty cell named, by the columns' letters as Excel shows them, in the words of the CSV
    reader, which names them by number) or the name ``line`` (the reader's column of row
    numbers, which would replace the sheet's own) is an error. Unlike a CSV header, one empty
    cell is an error too: the cells right of the last name are no columns here, so an empty one
    stands among the names."""
    repeats = repeats_text(names, excel_letters, named_only=True)
    if repeats is not None:
        raise ContactresInputError(
            f"{where}, row {number}: duplicate column name(s) {repeats}; every column needs "
            "its own name"
        )
    empty = sum(not n for n in names)  # one count: whether to refuse, and "is" or "are"
    if empty:
        raise ContactresInputError(
            f"{where}, row {number}: {empty_places(names, excel_letters)} of the header "
            f"{'is' if empty == 1 else 'are'} empty; every column needs a name"
        )
    refuse_line_name(
        names,
        f"{where}, row {number}",
        lambda i: f"column 'line' (column {excel_letters(i)})",
        "row numbers of the sheet",
    )


def load_sheet(path: Path, kind: str) -> pd.DataFrame:
    """The table of a workbook's sheet as string cells with a ``line`` column (Excel's row
    numbers); the sheet named ``kind`` if there is one, else the first."""
    import pandas as pd

    book = _workbook(path)
    try:
        sheet = book[kind] if kind in book.sheetnames else book.worksheets[0]
        where = f"{path}, sheet {sheet.title!r}"
        rows = [
            (number, [_text(v) for v in values])
            for number, values in enumerate(sheet.iter_rows(values_only=True), start=1)
            if any(v is not None and str(v).strip() for v in values)
        ]
    finally:
        book.close()
    if not rows:
        raise ContactresInputError(
            f"{where}: the sheet is empty (expected a header row and data rows)"
        )
    header_row, header = rows[0]
    names = [n.strip() for n in header]
    while names and not names[-1]:  # empty cells right of the header are no columns
        names.pop()
    _check_header(where, header_row, names)
    width = len(names)
    for number, cells in rows[1:]:
        if any(c.strip() for c in cells[width:]):
            raise ContactresInputError(
                f"{where}, row {number}: a value right of the last named column (the header "
                f"has {width} columns); name its column or remove it"
            )
    raw = pd.DataFrame([cells[:width] + [""] * (width - len(cells)) for _, cells in rows[1:]])
    raw = raw.reindex(columns=range(width), fill_value="")
    raw.columns = names
    raw["line"] = [number for number, _ in rows[1:]]
    raw.attrs.update(
        decimal=".", comment_lines=(), source=where, line_word="row", column_letters=True
    )
    return raw


def loader(kind: str) -> Callable[..., pd.DataFrame]:
    """The ``load`` of a workbook reader of ``kind``: :func:`load_sheet` with that kind (the
    options a spectra reader is given concern folders of spectra only, as for a CSV table)."""

    def load(path: Path, **_options) -> pd.DataFrame:
        return load_sheet(Path(path), kind)

    return load
