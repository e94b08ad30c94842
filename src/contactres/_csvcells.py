"""How the cells of a table are written to CSV: floats at 10 significant digits, and text that a
spreadsheet would run as a formula neutralised (CSV injection, OWASP).

Kept apart from :mod:`contactres.fileio` (which writes files whole or not at all): this is what
goes into the cells, that is how the file reaches the disk. The public names are re-exported
by :mod:`contactres.fileio`, where callers import them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

__all__ = ["CSV_FLOAT_FORMAT", "neutralised"]

CSV_FLOAT_FORMAT = "%.10g"  #: CSV floats: 10 digits, no noise (0.30000000000000004 -> 0.3)

#: First characters with which a spreadsheet reads a cell as a formula (CSV injection, OWASP):
#: a text cell starting with one of them is written with a leading apostrophe.
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def _risky(col) -> np.ndarray:
    """Boolean mask of the cells of the text column ``col`` (a pandas Series) that are strings
    starting with one of :data:`_FORMULA_START`.

    The whole column at once (pandas' string methods: no Python call per cell); a column those
    methods refuse (bytes, or no strings at all) is tested cell by cell, with the same answer:
    a cell that is not a string is never risky."""
    try:
        found = col.str.startswith(_FORMULA_START, na=False)
        return found.to_numpy(dtype=bool, na_value=False)
    except (AttributeError, TypeError, ValueError):
        return col.map(lambda v: isinstance(v, str) and v.startswith(_FORMULA_START)).to_numpy(
            dtype=bool
        )


def neutralised(frame):
    """``frame`` with every text cell that a spreadsheet would run as a formula (it starts with
    one of ``= + - @``, a tab or a carriage return) prefixed by an apostrophe, which spreadsheets
    show as text.
    Numbers are untouched (a negative number is a number, not a formula); only columns of text
    (object or string dtype) are looked at. Returns ``frame`` itself when nothing needs it."""
    columns = getattr(frame, "columns", None)
    if columns is None:  # not a table: written as the caller's to_csv writes it
        return frame
    text = [c for c in columns if frame[c].dtype.kind == "O" or str(frame[c].dtype) == "str"]
    if not text:
        return frame
    out = None
    for c in text:
        col = frame[c]
        risky = _risky(col)
        if risky.any():
            out = frame.copy() if out is None else out
            out[c] = col.where(~risky, "'" + col.astype(str))
    return frame if out is None else out
