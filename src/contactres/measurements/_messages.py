"""How the cells of a user's table are named in one-line error messages: file, line, column,
value (shortened, never a numpy repr)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._column_names import SHOWN_CHARS, column_place

if TYPE_CHECKING:  # annotations only: the messages need no pandas (the export readers, which
    import pandas as pd  # use them, are imported by the command line's help: no pandas there)

    from ._array_table import ArrayTable

__all__ = [
    "SHOWN_CHARS",
    "at_cell",
    "column_named",
    "column_names",
    "column_place",
    "line_word",
    "shown_value",
    "where_rows",
]

# SHOWN_CHARS: the longest value shown in a message (a 50 MB label is shown by its first
# characters), one figure for the column names' messages and these.


def shown_value(value) -> str:
    """A cell as the user wrote it: plain Python repr, never a numpy scalar's repr, and at most
    :data:`SHOWN_CHARS` characters of it."""
    value = value.item() if isinstance(value, np.generic) else value
    if isinstance(value, str) and len(value) > SHOWN_CHARS:
        return repr(value[: SHOWN_CHARS - 1]) + "…"
    text = repr(value)
    return text if len(text) <= SHOWN_CHARS else text[: SHOWN_CHARS - 1] + "…"


def column_names(names) -> str:
    """A list of column names for a message: the first ten, each shortened."""
    names = list(names)
    shown = ", ".join(shown_value(n) for n in names[:10])
    return f"[{shown}{f', ... ({len(names)} in all)' if len(names) > 10 else ''}]"


def where_rows(table: pd.DataFrame | ArrayTable, source: str, mask: np.ndarray, col: str) -> str:
    """'file, line 6, column 'x'' and, for several bad rows, how many and the first five lines."""
    lines = np.asarray(table["line"])[mask]
    word = line_word(table)
    where = f"{source}, {word} {lines[0]}, column {column_named(table, col)}"
    if len(lines) < 2:
        return where
    shown = ", ".join(str(v) for v in lines[:5]) + (", ..." if len(lines) > 5 else "")
    return f"{where} ({len(lines)} such rows: {word}s {shown})"


def column_named(table, col: str) -> str:
    """Column ``col`` of ``table`` for a message, as the user's file names it: ``'col'``; or,
    for a column the reader converted to SI from the unit of its name (``attrs["written_as"]``
    maps the SI name to the file's: ``amplitude_nm`` read as ``amplitude_m``),
    ``'amplitude_nm' (read in SI as amplitude_m)``: the file's name, and word that the numbers
    of the message are the SI ones (a number the user wrote is shown converted)."""
    written = getattr(table, "attrs", {}).get("written_as", {}).get(col)
    return repr(col) if written is None else f"{written!r} (read in SI as {col})"


def line_word(table) -> str:
    """What the numbers of a table's ``line`` column are called: ``line`` (of a text file), or
    what its reader says in ``attrs["line_word"]`` (``row`` for a sheet of a workbook)."""
    return str(getattr(table, "attrs", {}).get("line_word", "line"))


def at_cell(table: pd.DataFrame | ArrayTable, source: str, mask: np.ndarray, col: str) -> str:
    """:func:`where_rows` and the first bad value as the user wrote it."""
    i = int(np.flatnonzero(mask)[0])
    cells = table[col]  # a DataFrame's column, or an ArrayTable's array
    value = cells.iloc[i] if hasattr(cells, "iloc") else cells[i]
    return f"{where_rows(table, source, mask, col)}: value {shown_value(value)}"
