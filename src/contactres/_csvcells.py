"""How the cells of a table are written to CSV: floats at 10 significant digits, and text that a
spreadsheet would run as a formula neutralised (CSV injection, OWASP).

Kept apart from :mod:`contactres.fileio` (which writes files whole or not at all): this is what
goes into the cells, that is how the file reaches the disk. The public names are re-exported
by :mod:`contactres.fileio`, where callers import them.
"""

from __future__ import annotations

import numpy as np

__all__ = ["CSV_FLOAT_FORMAT", "floats_as_text", "neutralised"]

CSV_FLOAT_FORMAT = "%.10g"  #: CSV floats: 10 digits, no noise (0.30000000000000004 -> 0.3)

#: First characters with which a spreadsheet reads a cell as a formula (CSV injection, OWASP):
#: a text cell starting with one of them is written with a leading apostrophe.
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")

#: A signed decimal number and nothing else ("-0.5", "+1e-3", "-inf"): text that a spreadsheet
#: reads as a number, never as a formula, though it starts with a sign.
_PLAIN_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?|[+-]?inf"


def _risky(col) -> np.ndarray:
    """Boolean mask of the cells of the text column ``col`` (a pandas Series) that are strings
    starting with one of :data:`_FORMULA_START`.

    A column of strings (and gaps) is tested whole, on its first characters in numpy
    (``dtype="U1"`` keeps the first character of each string, in C): pandas' string methods
    would still make a Python call per cell. A column holding anything else (numbers, bytes) is
    tested cell by cell, with the same rule: a cell that is not a string is never risky."""
    from pandas.api.types import infer_dtype

    if infer_dtype(col, skipna=True) == "string":
        first = np.asarray(col.to_numpy(dtype=object), dtype="U1")
        return np.isin(first, _FORMULA_START) & ~col.isna().to_numpy(dtype=bool)
    return col.map(lambda v: isinstance(v, str) and v.startswith(_FORMULA_START)).to_numpy(
        dtype=bool
    )


def neutralised(frame):
    """``frame`` with every text cell that a spreadsheet would run as a formula (it starts with
    one of ``= + - @``, a tab or a carriage return) prefixed by an apostrophe, which spreadsheets
    show as text.
    Numbers are untouched (a negative number is a number, not a formula), and so is text that is
    a plain signed number ("-0.5"); only columns of text (object or string dtype) are looked at.
    Returns ``frame`` itself when nothing needs it."""
    columns = getattr(frame, "columns", None)
    if columns is None:  # not a table: written as the caller's to_csv writes it
        return frame
    text = [c for c in columns if frame[c].dtype.kind == "O" or str(frame[c].dtype) == "str"]
    if not text:
        return frame
    out = None
    for c in text:
        col = frame[c]
        risky = _risky(col).copy()  # (a view of pandas memory may be read-only)
        if risky.any():
            # A plain number written as text ("-0.5": afm invert rounds its computed columns to
            # 10 digits as text) is a number to a spreadsheet, not a formula: left as it is.
            at = np.flatnonzero(risky)
            plain = col.iloc[at].astype(str).str.fullmatch(_PLAIN_NUMBER).to_numpy(dtype=bool)
            risky[at[plain]] = False
        if risky.any():
            out = frame.copy() if out is None else out
            out[c] = col.where(~risky, "'" + col.astype(str))
    return frame if out is None else out


def floats_as_text(frame, na_rep: str = ""):
    """``frame`` with its float64 columns turned into the very text that pandas' ``to_csv``
    writes for them (no ``float_format``): the shortest repr that reads back as the same double
    (``repr``, which is what numpy's ``astype(str)`` gives, the call pandas makes), ``na_rep``
    for NaN. Other columns are untouched; returns ``frame`` itself when it has no float64 column.

    Why: pandas 3 writes a float column about 5x slower than the same column as text (4.8 s
    against 0.9 s for ten columns of 262,144 rows), and ``afm invert`` of a 512² map writes
    eleven of them (issue 31, point 5). Neutralise first (:func:`neutralised`): the text of a
    negative number starts with "-"."""
    columns = getattr(frame, "columns", None)
    if columns is None:
        return frame
    floats = [i for i, dtype in enumerate(frame.dtypes) if dtype == np.float64]
    if not floats:
        return frame
    out = frame.copy()
    for i in floats:  # by position: column names need not be unique
        values = frame.iloc[:, i].to_numpy()
        text = np.array([repr(v) for v in values.tolist()], dtype=object)
        text[np.isnan(values)] = na_rep
        out.isetitem(i, text)
    return out
