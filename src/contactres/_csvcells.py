"""How the cells of a table are written: to CSV (floats at 10 significant digits or as their
``repr``, text that a spreadsheet would run as a formula neutralised (CSV injection, OWASP), the
lines joined here where pandas' writer is not needed) and to a numpy archive (``.npz``).

Kept apart from :mod:`contactres.fileio` (which writes files whole or not at all: it hands
these a temporary path, or takes their bytes): this is what goes into the file, that is how the
file reaches the disk. The public names are re-exported by :mod:`contactres.fileio`, where
callers import them.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import numpy as np

from ._column_names import repeats_text
from ._decimal_text import copy_rows, g_precision, g_records, take_rows
from .numerics import object_pointers, repeat_runs, run_starts

__all__ = [
    "CHUNK_CELLS",
    "CSV_FLOAT_FORMAT",
    "csv_chunks",
    "csv_text",
    "csv_to",
    "floats_as_text",
    "neutralised",
    "npz_to",
    "unique_written",
]

CSV_FLOAT_FORMAT = "%.10g"  #: CSV floats: 10 digits, no noise (0.30000000000000004 -> 0.3)

#: First characters with which a spreadsheet reads a cell as a formula (CSV injection, OWASP):
#: a text cell starting with one of them is written with a leading apostrophe.
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")

#: A signed decimal number and nothing else ("-0.5", "+1e-3", "-inf"): text that a spreadsheet
#: reads as a number, never as a formula, though it starts with a sign.
_PLAIN_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?|[+-]?inf"


def unique_written(frame, what: str = "the table written") -> None:
    """Raise ValueError if ``frame`` (a table to write) holds a column name twice, as its
    file's header would (``1`` and ``"1"`` are one name there); ``what`` names the table or its
    file in the message. Anything without columns passes.

    Why a ValueError and not :class:`~contactres.errors.ContactresInputError`: a user's table
    with a name twice is refused by its reader, so a table of ours with one is a fault of the
    code that built it, which the command line reports as an internal error, never as the
    user's. Unchecked, pandas gives a frame for ``frame[name]`` where a column is meant (an
    AttributeError deep inside the writing), or writes a header no reader takes back; NetCDF
    and numpy archives would keep one of the two columns."""
    columns = getattr(frame, "columns", None)
    # (a pass over the names, not the cells: microseconds for the tables written)
    repeats = None if columns is None else repeats_text(str(c) for c in columns)
    if repeats is not None:
        raise ValueError(
            f"{what}: duplicate column name(s) {repeats}; every column of a table written "
            "needs its own name"
        )


def _risky(col) -> np.ndarray:
    """Boolean mask of the cells of the text column ``col`` (a pandas Series) that are strings
    starting with one of :data:`_FORMULA_START`.

    A column of strings (and gaps) is tested whole, on its first characters in numpy
    (``dtype="U1"`` keeps the first character of each string, in C): pandas' string methods
    would still make a Python call per cell. A column holding anything else (numbers, bytes) is
    tested cell by cell, with the same rule: a cell that is not a string is never risky."""
    import pandas as pd
    from pandas.api.types import infer_dtype

    if infer_dtype(col, skipna=True) == "string":
        # One test a run of the same object (a curve table's sweep id fills its 30 rows):
        # turning 3·10^6 cells to text was most of the writing's neutralising (issue 31).
        values = np.ascontiguousarray(col.to_numpy(dtype=object))
        starts = _run_starts(values)
        held = values[starts]
        first = np.asarray(held, dtype="U1")
        risky = np.isin(first, _FORMULA_START) & ~pd.isna(held)
        return repeat_runs(risky, starts, values.size)
    return col.map(lambda v: isinstance(v, str) and v.startswith(_FORMULA_START)).to_numpy(
        dtype=bool
    )


def _run_starts(values: np.ndarray) -> np.ndarray:
    """The first row of each run of one object (by identity) in the object array ``values``:
    the rows where the object differs from the row above. Compared as the object pointers the
    array holds (:func:`contactres.numerics.object_pointers`); every row is a run of its own where
    numpy keeps them to itself."""
    pointers = object_pointers(values)
    return np.arange(values.size) if pointers is None else run_starts(pointers)


def neutralised(frame, what: str = "the table written"):
    """``frame`` with every text cell that a spreadsheet would run as a formula (it starts with
    one of ``= + - @``, a tab or a carriage return) prefixed by an apostrophe, which spreadsheets
    show as text.
    Numbers are untouched (a negative number is a number, not a formula), and so is text that is
    a plain signed number ("-0.5"); only columns of text (object or string dtype) are looked at.
    Returns ``frame`` itself when nothing needs it."""
    columns = getattr(frame, "columns", None)
    if columns is None:  # not a table: written as the caller's to_csv writes it
        return frame
    unique_written(frame, what)
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
    unique_written(frame)
    floats = [i for i, dtype in enumerate(frame.dtypes) if dtype == np.float64]
    if not floats:
        return frame
    out = frame.copy()
    for i in floats:  # by position: column names need not be unique
        values = frame.iloc[:, i].to_numpy()
        text = np.array(_float_texts(values, None), dtype=object)
        text[np.isnan(values)] = na_rep
        out.isetitem(i, text)
    return out


#: Characters that make the csv module (QUOTE_MINIMAL, which pandas' ``to_csv`` uses) quote a
#: field: the separator and the quote (and line breaks, which :func:`csv_text` leaves to pandas).
_QUOTED = (",", '"', "\r", "\n")


class _NotJoined(Exception):
    """A table (or a chunk of it) that :func:`csv_chunks` does not cover: pandas writes it."""


#: Cells whose text :func:`csv_chunks` joins at a time (as many rows as hold this many): the
#: text of a chunk is held, never that of a whole table (a Python string per cell: 10^5
#: sweeps' curve table, 3·10^6 rows of five cells, held ~0.9 GB of text at once), and a wide
#: table's chunk is no larger than a narrow one's (~20 MB of text).
CHUNK_CELLS = 2**18


def _field_texts(col, na_rep: str, float_format: str | None = None) -> list[str]:
    """The cells of one column (a pandas Series) as the text ``to_csv`` writes for them, quoted
    where the csv module quotes. Raises _NotJoined for a column of another kind (dates,
    categories, mixed objects, a line break in a cell): the caller then leaves the table to
    pandas.

    A float64 cell is ``float_format % value`` where a format is given (what pandas'
    ``to_csv(float_format=...)`` writes for it, cell by cell), else its ``repr`` (the shortest
    text that reads back as the same double, pandas' text without a format); NaN is
    ``na_rep`` either way."""
    from pandas.api.types import infer_dtype

    values = col.to_numpy()
    if values.dtype == np.float64:
        text = _float_texts(values, float_format)
        if na_rep != "nan" or float_format is not None:
            for i in np.flatnonzero(np.isnan(values)).tolist():
                text[i] = na_rep
        return text
    if values.dtype.kind in "iu":
        return [str(v) for v in values.tolist()]
    if values.dtype.kind == "b":
        return ["True" if v else "False" for v in values.tolist()]
    if values.dtype.kind not in "OU" and str(col.dtype) != "str":
        raise _NotJoined
    kind = infer_dtype(col, skipna=True)
    if kind not in ("string", "empty"):
        raise _NotJoined
    gap = col.isna().to_numpy(dtype=bool)
    text = col.to_numpy(dtype=object).tolist()
    for i in np.flatnonzero(gap).tolist():
        text[i] = na_rep
    joined = "\x00".join(text)  # one scan in C for the characters that need quotes
    if "\r" in joined or "\n" in joined:
        raise _NotJoined  # a line break in a cell: pandas' writer keeps it as it is, to the byte
    if any(c in joined for c in _QUOTED):
        text = [
            '"' + v.replace('"', '""') + '"' if any(c in v for c in _QUOTED) else v for v in text
        ]
    return text


def _float_texts(values: np.ndarray, float_format: str | None) -> list[str]:
    """The text of every float64 in ``values``: ``float_format % v``, or ``repr(v)`` without a
    format (NaN as ``nan``; the caller puts its own gap text there).

    Why: the text of a float costs ~0.3 µs of Python a cell, and whole columns repeat a few
    values (a curve table's 30-point amplitude grid, a load, a gap written once per sweep):
    those are formatted once per distinct value and the texts picked out by a code per cell
    (issue 31: a third of the cells of ``qcm analyze``'s curve table). Values are told apart by
    their bits, not by ``==``: -0.0 and 0.0 have different texts. A column of mostly distinct
    values is formatted cell by cell, as before (the tally then costs ~10% more)."""
    import pandas as pd

    codes, distinct = pd.factorize(values.view(np.int64))
    cells = values if 2 * len(distinct) > len(values) else distinct.view(np.float64)
    if float_format is None:
        text = [repr(v) for v in cells.tolist()]
    else:
        text = [float_format % v for v in cells.tolist()]
    if cells is values:
        return text
    return np.array(text, dtype=object)[codes].tolist()


#: A float format of one conversion and nothing else ("%.10g", "%.3e"): the text of a double
#: is then the same formatted alone or within the format of a whole chunk.
#: A lone surrogate's bytes as ``surrogatepass`` writes them (U+D800..U+DFFF: ED A0..BF ..):
#: found exactly, so that text of U+D000..U+D7FF (Hangul) is not re-encoded for nothing.
_SURROGATE = re.compile(rb"\xed[\xa0-\xbf]")
_ONE_FLOAT = re.compile(r"%[-+ #0]*\d*(?:\.\d+)?[eEfFgG]")


def _few(values: np.ndarray) -> bool:
    """Whether a float column's first 1000 cells hold at most a tenth as many distinct values
    (a curve table's amplitude grid): then each is formatted once (:func:`_float_texts`)."""
    head = np.sort(values[:1000].view(np.int64))  # (a sort: a tenth of np.unique's time here)
    return (1 + np.count_nonzero(head[1:] != head[:-1])) * 10 <= head.size


def csv_chunks(
    frame,
    na_rep: str = "",
    lineterminator: str = "\n",
    float_format: str | None = None,
    rows: int | None = None,
) -> Iterator[str]:
    """The CSV text of ``frame`` as ``frame.to_csv(index=False, na_rep=na_rep,
    lineterminator=lineterminator, float_format=float_format)`` writes it, in pieces: the
    header line, then the lines of ``rows`` rows at a time (default: the rows of
    :data:`CHUNK_CELLS` cells; each line ended by ``lineterminator``). Raises _NotJoined,
    before or between pieces, for a table it does not cover (no rows, one column, column
    names that are not text, a column of dates or mixed objects, a line break in a cell):
    write those with pandas.

    Why: pandas 3 writes a column of text through its csv writer at ~0.3 µs a cell, and a
    formatted float at ~2 µs; joining the cells here costs a tenth of that (issue 31, point 5:
    ``afm invert`` of a 512² map writes 5.5 million cells; point 3: ``qcm analyze`` of 10^5
    sweeps writes ~15 million). In pieces, so that the text of a large table is never held
    whole. With a ``"%.Ng"`` format (the reports' :data:`CSV_FLOAT_FORMAT`) the lines are
    assembled as bytes in numpy (:func:`_lines_bytes`), the doubles' text made there too."""
    unique_written(frame)  # (csv_to's frame has passed neutralised's check)
    for piece in _pieces(frame, na_rep, lineterminator, float_format, rows):
        # (a lone surrogate in a text cell, "\udcff", is kept as pandas' to_csv() to a string
        # keeps it: _text_records encodes it as the three bytes surrogatepass decodes)
        yield piece if isinstance(piece, str) else piece.decode("utf-8", "surrogatepass")


def _pieces(
    frame, na_rep: str, lineterminator: str, float_format: str | None, rows: int | None
) -> Iterator[str | bytearray]:
    """:func:`csv_chunks`' pieces, those assembled in numpy (:func:`_lines_bytes`) as the
    UTF-8 bytes they are made as: :func:`csv_to` writes them without a decoding and encoding
    of each (~250 MB of text at 10^5 sweeps)."""
    columns = list(getattr(frame, "columns", ()))
    if len(columns) < 2 or len(frame) == 0 or not all(isinstance(c, str) for c in columns):
        raise _NotJoined  # (not a table; one column: the csv module quotes an empty field there)
    header = [
        '"' + c.replace('"', '""') + '"' if any(q in c for q in _QUOTED) else c for c in columns
    ]
    yield ",".join(header) + lineterminator
    step = max(1, CHUNK_CELLS // len(columns)) if rows is None else rows
    starts = range(0, len(frame), step)
    # "%.Ng": the lines assembled as bytes in numpy (NUL is their filler: not in the fixed texts)
    precision = g_precision(float_format) if "\0" not in na_rep + lineterminator else None
    if precision is None:
        assembled: Iterator[bytearray | None] = iter([None] * len(starts))
    else:
        assembled = _assembled(frame, starts, step, na_rep, lineterminator, precision)
    yield from _chunks(frame, starts, step, assembled, na_rep, lineterminator, float_format)


def _chunks(
    frame,
    starts: range,
    step: int,
    assembled: Iterator[bytearray | None],
    na_rep: str,
    lineterminator: str,
    float_format: str | None,
) -> Iterator[str | bytearray]:
    """The pieces of the chunks of :func:`_pieces`: each one ``assembled`` gives, or, where
    it gives None, the chunk's text joined here."""
    columns = list(frame.columns)
    one = _ONE_FLOAT.fullmatch(float_format or "") is not None
    # A NaN formats as "nan" (no sign, no width in the format): a column with gaps is
    # formatted with the others and its "nan" made ``na_rep`` in the chunk's text, where no
    # text cell holds "nan" (a float's text has none but NaN's).
    gaps_in_text = one and str(float_format) % float("nan") == "nan"
    for start, lines in zip(starts, assembled, strict=True):
        if lines is not None:
            yield lines
            continue
        part = frame.iloc[start : start + step]
        fields: list = []
        gaps = []  # positions of the doubles with a NaN
        for i in range(len(columns)):  # by position: column names need not be unique
            col = part.iloc[:, i]
            values = col.to_numpy()
            if one and values.dtype == np.float64 and not _few(values):
                # the doubles, formatted in _formatted_lines (infinities as the cells are)
                if not np.isnan(values).any():
                    fields.append(values)
                    continue
                if gaps_in_text:
                    fields.append(values)
                    gaps.append(i)
                    continue
            fields.append(_field_texts(col, na_rep, float_format))
        if na_rep == "nan":
            gaps = []  # the text NaN formats as already
        elif gaps and any("nan" in "\x00".join(f) for f in fields if isinstance(f, list)):
            for i in gaps:  # a text cell holds "nan": the gaps written cell by cell
                fields[i] = _field_texts(part.iloc[:, i], na_rep, float_format)
            gaps = []
        if any(isinstance(f, np.ndarray) for f in fields):
            text = _formatted_lines(fields, str(float_format), lineterminator)
            yield text.replace("nan", na_rep) if gaps else text
        else:
            yield lineterminator.join([*map(",".join, zip(*fields, strict=True)), ""])


def _assembled(
    frame, starts: range, step: int, na_rep: str, lineterminator: str, precision: int
) -> Iterator[bytearray | None]:
    """:func:`_lines_bytes` of each chunk of ``step`` rows from each of ``starts``, on the
    chunk's slices of the table's columns, taken once: numpy arrays for the doubles and
    booleans, pandas Series made of the slices of the others (``part.iloc[:, i]`` of each
    chunk's rows, and a Series of every column, cost ~10 % of the writing at 10^5 sweeps)."""
    import pandas as pd

    arrays = []
    for i in range(frame.shape[1]):  # by position: column names need not be unique
        col = frame.iloc[:, i]
        plain = col.dtype == np.float64 or col.dtype == np.bool_
        arrays.append(col.to_numpy() if plain else col.array)
    for start in starts:
        columns = [
            a if isinstance(a, np.ndarray) else pd.Series(a, copy=False)
            for a in (a[start : start + step] for a in arrays)
        ]
        yield _lines_bytes(columns, na_rep, lineterminator, precision)


def _lines_bytes(
    columns: list, na_rep: str, lineterminator: str, precision: int
) -> bytearray | None:
    """The CSV lines of the rows of ``columns`` (the columns of a chunk of a table, in order,
    of one length: numpy arrays of doubles or booleans, or pandas Series) with doubles as
    ``"%.{precision}g"``, as UTF-8 bytes: the text :func:`csv_chunks` joins, assembled in
    numpy. None where a text cell holds a NUL byte or is longer than :data:`_WIDEST_TEXT` bytes
    (then joined as text); raises _NotJoined as :func:`_field_texts`.

    Why: Python's ``%`` formats a double at ~0.2 µs and its text joined into lines costs
    another ~40 % (issue 31, point 3: ~12 million doubles in ``qcm analyze``'s tables at 10^5
    sweeps). Here each column is an array of records, fixed-width rows of bytes whose text is
    the row without its NUL bytes (:func:`contactres._decimal_text.g_records` for doubles, each
    distinct run of text encoded once); a chunk's lines are the records side by side with the
    separators, every NUL dropped at once."""
    records = []
    for col in columns:
        values = col if isinstance(col, np.ndarray) else col.to_numpy()
        if values.dtype == np.float64:
            records.append(_double_records(values, precision, na_rep.encode()))
            continue
        rec = _text_records(col, na_rep)
        if rec is None:
            return None
        records.append(rec)
    seps = [b","] * (len(records) - 1) + [lineterminator.encode()]
    width = sum(r.shape[1] + len(s) for r, s in zip(records, seps, strict=True))
    # In a bytearray, whose NULs are dropped by one pass in C (half the time of numpy's boolean
    # mask) without a copy to bytes first
    rows = len(columns[0])
    memory = bytearray(rows * width)
    lines = np.frombuffer(memory, dtype=np.uint8).reshape(rows, width)
    at = 0
    for rec, sep in zip(records, seps, strict=True):
        copy_rows(lines[:, at : at + rec.shape[1]], rec)
        at += rec.shape[1]
        lines[:, at : at + len(sep)] = np.frombuffer(sep, dtype=np.uint8)
        at += len(sep)
    del lines  # (the view)
    return memory.translate(None, b"\0")


def _double_records(values: np.ndarray, precision: int, na_rep: bytes) -> np.ndarray:
    """:func:`contactres._decimal_text.g_records` of a column of doubles; a column of few
    distinct values (:func:`_few`) has each value's record made once."""
    if not _few(values):
        return g_records(values, precision, na_rep)
    import pandas as pd

    codes, distinct = pd.factorize(values.view(np.int64))  # by bits: -0.0 is not 0.0
    return take_rows(g_records(distinct.view(np.float64), precision, na_rep), codes)


#: The widest text record (UTF-8 bytes) that :func:`_lines_bytes` assembles: every record of a
#: column is as wide as its longest text, and every line of the chunk as wide as its records,
#: so one long cell (a 4 kB note in a chunk of 87,381 rows) would make the chunk's buffer
#: 87,381 x 4 kB (680 MB, against 16 MB joined as text). Past it the chunk is joined as text.
_WIDEST_TEXT = 256


def _text_records(col, na_rep: str) -> np.ndarray | None:
    """The texts of a column that is not of doubles (:func:`_field_texts`: raises _NotJoined
    as it does) as NUL-padded UTF-8 records; None if a text holds a NUL byte or is wider than
    :data:`_WIDEST_TEXT` bytes. A run of one object (a curve table's sweep id over its 30
    rows) has its text made once, and so has each distinct text of a column that holds few."""
    from pandas.api.types import infer_dtype

    values = col if isinstance(col, np.ndarray) else col.to_numpy()
    codes = None
    if values.dtype.kind == "b":
        return (
            np.array([b"False", b"True"])[values.astype(np.intp)]
            .view(np.uint8)
            .reshape(values.size, -1)
        )
    if values.dtype.kind == "O" or str(col.dtype) == "str":
        if infer_dtype(col, skipna=True) not in ("string", "empty"):
            raise _NotJoined
        starts = _run_starts(np.ascontiguousarray(col.to_numpy(dtype=object)))
        if 2 * starts.size < values.size:
            codes = repeat_runs(np.arange(starts.size), starts, values.size)
            col = col.iloc[starts]
        else:  # a few texts, each object a row of its own (a sweep table's model names)
            import pandas as pd

            found, distinct = pd.factorize(col, use_na_sentinel=False)  # (gaps: one text)
            if 2 * len(distinct) < values.size:
                codes, col = found, pd.Series(distinct, dtype=col.dtype)
    texts = _field_texts(col, na_rep)
    joined = "".join(texts)
    if "\0" in joined:
        return None
    # (numpy encodes ASCII text itself, at a fraction of a Python call a cell). A lone
    # surrogate ("\udcff": a file name decoded with surrogateescape) is encoded as it is
    # (surrogatepass): csv_chunks' text keeps it, csv_to refuses it as the UTF-8 codec does.
    records = np.array(
        texts if joined.isascii() else [t.encode("utf-8", "surrogatepass") for t in texts],
        dtype="S",
    )
    records = records.view(np.uint8).reshape(records.size, -1)
    if records.shape[1] > _WIDEST_TEXT:
        return None
    return records if codes is None else take_rows(records, codes)


def _formatted_lines(fields: list, float_format: str, lineterminator: str) -> str:
    """The lines of a chunk whose fields are texts (lists) or doubles (arrays) to format with
    ``float_format``: one ``%`` of a format made for the whole chunk on its cells, in C.

    Why: Python's ``%`` formats a double at ~0.25 µs, and a call of its own per cell (and a
    join per row) cost another ~40 % on top (issue 31, point 3: ~10^7 doubles in ``qcm
    analyze``'s tables at 10^5 sweeps). The text is that of the cells formatted one by one:
    each conversion formats its one argument as ``float_format % value`` does."""
    rows = len(fields[0])
    cells = np.empty((rows, len(fields)), dtype=object)
    specs = []
    for i, f in enumerate(fields):
        cells[:, i] = f
        specs.append(float_format if isinstance(f, np.ndarray) else "%s")
    line = ",".join(specs) + lineterminator.replace("%", "%%")
    return (line * rows) % tuple(cells.ravel().tolist())


def csv_text(
    frame, na_rep: str = "", lineterminator: str = "\n", float_format: str | None = None
) -> str | None:
    """The CSV text of ``frame`` as ``frame.to_csv(index=False, na_rep=na_rep,
    lineterminator=lineterminator, float_format=float_format)`` writes it, whole
    (:func:`csv_chunks` joined), or None for a table that :func:`csv_chunks` does not cover:
    write those with pandas."""
    try:
        return "".join(csv_chunks(frame, na_rep, lineterminator, float_format))
    except _NotJoined:
        return None


def csv_to(path, frame, options: dict, what: str = "the table written") -> None:
    """Write ``frame`` to ``path`` as ``frame.to_csv(path, **options)`` would, with its
    formula-like text neutralised (:func:`neutralised`). With ``index=False`` and at most the
    options ``na_rep`` and ``float_format`` (a %-format string) the text is
    :func:`csv_chunks`', the same bytes as pandas' (lines ended by ``os.linesep``, its
    default), written chunk by chunk; a table it does not cover goes to ``to_csv`` (which then
    writes the file anew), its floats turned to text first when no option formats them
    (:func:`floats_as_text`: pandas 3 writes text faster than floats). A column name twice is
    a ValueError (:func:`unique_written`, ``what`` naming the table or its file) before the
    file is opened."""
    import os

    table = neutralised(frame, what)  # (its check of the names: before the file is opened)
    na_rep = options.get("na_rep", "")
    float_format = options.get("float_format")
    joined = options.keys() <= {"index", "na_rep", "float_format"} and not options.get(
        "index", True
    )
    if joined and (float_format is None or isinstance(float_format, str)):
        try:
            with open(path, "wb") as fh:  # (the text as the csv module writes it: UTF-8)
                for piece in _pieces(table, na_rep, os.linesep, float_format, None):
                    if isinstance(piece, str):
                        fh.write(piece.encode("utf-8"))
                    elif _SURROGATE.search(piece):  # (UTF-8 of U+D800..U+DFFF: ED A0..BF)
                        # a lone surrogate: the chunk's text encoded strictly raises the
                        # UnicodeEncodeError of pandas' writer
                        fh.write(piece.decode("utf-8", "surrogatepass").encode("utf-8"))
                    else:
                        fh.write(piece)
            return
        except _NotJoined:
            pass
    if not {"float_format", "decimal", "quoting"} & options.keys():  # pandas' default text
        table = floats_as_text(table, na_rep)
    table.to_csv(path, **options)


def _few_objects(values: np.ndarray, most: int) -> tuple[list[int], np.ndarray] | None:
    """(first row of each distinct object, the index of each row's object) of a contiguous
    object array holding at most ``most`` distinct objects (by identity), else None.

    The cells are compared as the object pointers the array holds
    (:func:`contactres.numerics.object_pointers`: the same pointer is the same object), a comparison
    of integers in C, where ``==`` of the cells calls the objects' own comparison a row (~100
    instructions each)."""
    pointers = object_pointers(values)
    if not values.size or pointers is None:
        return None
    firsts: list[int] = []
    codes = np.zeros(values.size, dtype=np.intp)
    left = np.ones(values.size, dtype=bool)
    while len(firsts) < most:
        firsts.append(int(left.argmax()))
        same = pointers == pointers[firsts[-1]]
        codes[same] = len(firsts) - 1
        left &= ~same
        if not left.any():
            return firsts, codes
    return None


def _few_texts(values: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(distinct texts as an object array, the index of each row's) of an object array whose
    cells are at most four distinct strings, else None. A map's flags, methods and
    normalisation are a few string objects repeated: their rows are grouped by object
    (:func:`_few_objects`) and objects of equal text merged. Otherwise one comparison of the
    whole column a text, in C (``==`` of equal strings: the same text whichever object holds
    it), instead of one Python call a row."""
    if (few := _few_objects(values, 8)) is not None:
        firsts, codes = few
        objects = [values[i] for i in firsts]
        if all(type(v) is str for v in objects):
            order = list(dict.fromkeys(objects))  # texts by their first row (dict: by value)
            if len(order) > 4:
                return None
            distinct = np.empty(len(order), dtype=object)
            distinct[:] = order
            if len(order) == len(objects):  # each object a text of its own: codes as they are
                return distinct, codes
            return distinct, np.array([order.index(v) for v in objects])[codes]
    texts: list[str] = []
    codes = np.zeros(values.size, dtype=np.intp)
    left = np.ones(values.size, dtype=bool)
    while values.size and len(texts) < 4 and type(text := values[int(left.argmax())]) is str:
        same = values == text
        codes[same] = len(texts)
        texts.append(text)
        left &= ~same
        if not left.any():
            distinct = np.empty(len(texts), dtype=object)
            distinct[:] = texts
            return distinct, codes
    return None


def _text_array(values: np.ndarray) -> np.ndarray:
    """Cells of an object array as a unicode array, a missing cell (None, NaN) as an empty
    string: what ``Series(values).fillna("").astype(str).to_numpy(dtype=str)`` gives, without
    pandas. Each distinct object is turned to text once: a map's flags and methods are a few
    objects repeated over 262,144 rows (a third of the time of the writing, cell by cell)."""
    values = np.asarray(values, dtype=object).reshape(-1)
    few = _few_texts(values)
    if few is not None:
        distinct, inverse = few
    else:
        ids = np.fromiter(map(id, values), dtype=np.intp, count=values.size)
        _, first, inverse = np.unique(ids, return_index=True, return_inverse=True)
        distinct = values[first]
    missing = np.array([v is None or v != v for v in distinct], dtype=bool)  # None, NaN
    # np.asarray(..., dtype=str) as pandas' to_numpy(dtype=str) (not astype: a column of only
    # empty cells is '<U2' there, '<U1' by astype)
    return np.asarray(np.where(missing, "", distinct), dtype=str)[inverse.reshape(-1)]


def npz_to(path, frame, what: str = "a numpy archive") -> None:
    """Write the numpy archive (``.npz``, the layout of ``numpy.savez``, uncompressed) of a
    pandas DataFrame, or of a :class:`~contactres.measurements.ArrayTable`, to the file
    ``path``: one array per column under its name; numbers as they are (float64: exact),
    anything else as unicode text (a gap an empty string). No pickles:
    ``numpy.load(..., allow_pickle=False)`` reads it.

    Written here rather than by ``numpy.savez``: its own keywords (``file``, ``allow_pickle``)
    would clash with columns of those names. Each array goes straight into the file, its
    ``.npy`` header (format 1.0, as ``numpy.lib.format.write_array`` writes it) then its
    memory as it is: a map's archive (70 MB for 512² pixels) is neither assembled in memory
    nor copied column by column to bytes. A column name twice is a ValueError
    (:func:`unique_written`, ``what`` naming the table or its file) before the file is opened."""
    import zipfile

    unique_written(frame, what)  # (two arrays of one name: numpy reads one)
    names = [str(c) for c in frame.columns]
    with open(path, "wb") as fh, zipfile.ZipFile(fh, "w", zipfile.ZIP_STORED) as zf:
        for i, name in enumerate(names):
            col = frame.iloc[:, i] if hasattr(frame, "iloc") else frame[name]
            if col.dtype.kind in "fiub":
                values = np.asarray(col)
            elif hasattr(col, "fillna"):  # text (labels, flags) of a DataFrame
                values = col.fillna("").astype(str).to_numpy(dtype=str)
            else:  # text of numpy columns
                values = _text_array(col)
            values = np.ascontiguousarray(values)  # one dimension: C order, as npy's header says
            with zf.open(f"{name}.npy", "w", force_zip64=True) as member:
                header = np.lib.format.header_data_from_array_1_0(values)
                np.lib.format.write_array_header_1_0(member, header)
                member.write(values.view(np.uint8).data)
