"""Reader plug-in for delimited text tables (CSV, semicolon- or tab-separated).

The separator and the decimal mark are recognised from the header and the first data lines:
comma, semicolon or tab; a decimal comma with semicolon or tab separators. The file must be
UTF-8 text (a byte order mark is skipped). Comments: a line whose first non-blank character is
``#`` is a comment, as a whole; a ``#`` anywhere else is data (``SiO2 #A`` is a label, not
``SiO2`` plus a comment). Blank lines are skipped. Column names must be unique (names that
differ by outer blanks only are one: ``' df_Hz'`` is ``df_Hz``, while ``a b`` and ``a  b`` are
two), at most one header cell may be empty, and no name may be ``line``: the reader's column of
line numbers.
"""

from __future__ import annotations

import csv
import hashlib
import io
import re
import threading
import warnings
from collections.abc import Callable, Collection
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..._column_names import empty_places, refuse_line_name, repeats_text, shown_names
from ...errors import ContactresInputError
from ...numerics import column_run_starts, repeat_runs

if TYPE_CHECKING:  # annotations: pandas is imported where a table is read (a numpy archive's
    import pandas as pd  # reader shares this package and needs none, issue 31)

__all__ = ["detect", "load", "suffixes"]

suffixes = (".csv", ".txt", ".tsv")

_DECIMAL_COMMA = re.compile(r"^[+-]?\d+,\d+([eE][+-]?\d+)?$")
# The line breaks of a CSV file (str.splitlines would also split at form feeds, U+2028, ...).
_LINE_BREAK = re.compile(r"\r\n|\r|\n")
_FIELD_COUNT = re.compile(r"Expected (\d+) fields in line (\d+), saw (\d+)")
# A line break before a line that may be blank or a comment (it starts with white space, as
# str.strip has it, or with #): such a table's lines are sorted one by one.
_DROPPED_LINE = re.compile(r"\n[\s#]")
# The same in ASCII bytes: the white space of str.isspace there is \t-\r and \x1c-\x20.
_DROPPED_LINE_ASCII = re.compile(rb"\n[\t-\r\x1c-\x20#]")
_SPACE_OR_HASH = frozenset(b"\t\n\x0b\x0c\r\x1c\x1d\x1e\x1f #")
#: Files of at least this many bytes are hashed in a thread beside their parsing (:func:`_hashing`).
_HASHED_BESIDE = 1 << 20


def _dialect(text: str) -> tuple[str, str]:
    """Separator and decimal mark of a table from its header and first data lines."""
    lines = [ln for ln in text.splitlines() if ln.strip()]
    header = lines[0]
    if "\t" in header:
        sep = "\t"
    elif header.count(";") > 0:
        sep = ";"
    else:
        sep = ","
    decimal = "."
    if sep != ",":
        cells = [c.strip() for ln in lines[1:50] for c in ln.split(sep)]
        if any(_DECIMAL_COMMA.match(c) for c in cells):
            decimal = ","
    return sep, decimal


def _hashing(data: bytes) -> Callable[[], str]:
    """A function giving the SHA-256 (hex) of ``data``, which a thread of its own computes
    meanwhile where ``data`` is large.

    Why: hashlib lets go of the GIL while it hashes, so the hash of a large table costs its
    reading no wall time: it runs on the other core while the table is checked and parsed
    (issue 31, point 3: 0.08 s of CPU for the 148 MB table of 10^5 sweeps, which preceded
    the parsing). A failure of the thread is raised where the digest is asked for; where no
    thread can be started (a limit on threads), the hash is taken here. A reading that fails
    before the digest is asked for leaves the thread to finish its hash (~0.1 s for 148 MB)."""
    if len(data) < _HASHED_BESIDE:  # a thread costs more than the hash
        digest = hashlib.sha256(data).hexdigest()
        return lambda: digest
    done: list = []

    def work() -> None:
        try:
            done.append(hashlib.sha256(data).hexdigest())
        except BaseException as exc:  # handed to the caller, raised there
            done.append(exc)

    worker = threading.Thread(target=work, name="contactres-sha256", daemon=True)
    started = True
    try:
        worker.start()
    except RuntimeError:  # ("can't start new thread": the hash is this thread's to take)
        started = False
        work()

    def result() -> str:
        if started:
            worker.join()
        if isinstance(done[0], BaseException):
            raise done[0]
        return done[0]

    return result


def _decode(path: Path) -> tuple[str | None, Callable[[], str], bytes]:
    """Three things from one reading of the file: its text (UTF-8, a byte order mark skipped;
    a one-line error names the first byte that is not UTF-8), the SHA-256 (hex) of all its
    bytes (a function that gives it: :func:`_hashing`), and the bytes of the text (those after
    the byte order mark: the text's UTF-8, a decoding undone). The text is None where those
    bytes are ASCII: each byte is then its character, and a caller that needs the text
    decodes them (``encoded.decode("ascii")``); the usual table is parsed as its bytes and
    never needs it (issue 31, point 3: decoding 148 MB cost ~0.1 s and a copy of the file)."""
    data = path.read_bytes()
    bom = len(b"\xef\xbb\xbf") if data.startswith(b"\xef\xbb\xbf") else 0
    body = data[bom:] if bom else data
    digest = _hashing(data)
    if body.isascii():  # ASCII is UTF-8 as it is (one scan in C, no copy)
        return None, digest, body
    try:
        return body.decode("utf-8"), digest, body
    except UnicodeDecodeError as exc:
        at = bom + exc.start
        line = data.count(b"\n", 0, at) + 1
        raise ContactresInputError(
            f"{path}: not UTF-8 text (byte 0x{data[at]:02x} at offset {at}, line {line}); save "
            "the table as UTF-8"
        ) from None


def _no_nul(path: Path, body: str | bytes, numbers) -> None:
    """A one-line error if a line of the table (``body``, the lines parsed, as text or as their
    ASCII bytes; ``numbers`` their line numbers in the file) holds a NUL character.

    NUL is valid UTF-8 but no character of a text table: it is what a UTF-16 file without a
    byte order mark holds between its ASCII characters, which would otherwise read as columns
    of odd names, blamed as missing. Comment lines and a preamble are not parsed and may hold
    anything (review R28e: an instrument's preamble with NULs was read before, and still is).
    """
    # one scan in C; the line breaks before it counted
    at = body.find("\x00") if isinstance(body, str) else body.find(b"\x00")
    if at >= 0:
        breaks = body.count("\n", 0, at) if isinstance(body, str) else body.count(b"\n", 0, at)
        line = int(numbers[breaks])
        raise ContactresInputError(
            f"{path}: line {line}: a NUL character (0x00) is no text of a table (UTF-16 text "
            "saved without a byte order mark, or a binary file); save the table as UTF-8 text"
        )


def _check_header(path: Path, number: int, header: str, sep: str) -> list[str]:
    """The column names of the header (stripped of outer blanks). Duplicate column names are
    an error (pandas would rename them, ``df_Hz.1``, in quadratic time, and a reader would take
    the first column without a word), names that differ by outer blanks only included (``a b``
    and ``a  b`` are two names); so are two or more empty cells (one is a column pandas names
    ``Unnamed: i``), the name ``line``, the column of line numbers the reader adds (the
    file's own column would be replaced, its values lost), and a header the csv module cannot
    split (a field over its limit of 128 kB: no column name)."""
    try:
        names = [n.strip() for n in next(csv.reader([header], delimiter=sep))]
    except csv.Error as exc:
        raise ContactresInputError(
            f"{path}, line {number}: the header is not a readable {sep!r}-separated line "
            f"({exc}); a header holds the column names"
        ) from None
    repeats = repeats_text(names, named_only=True)
    if repeats is not None:
        raise ContactresInputError(
            f"{path}, line {number}: duplicate column name(s) {repeats}; every column needs "
            "its own name"
        )
    # One empty cell reads as a column pandas names ("Unnamed: 4", kept as before); two or
    # more are no repeat of a name but columns without one. Trailing ones are not dropped as
    # the workbook reader drops them: a single one is a column read today (its values kept in
    # an inversion's output, bytes that stay), and dropping only two or more would give one
    # empty cell and two different rules.
    if sum(not n for n in names) > 1:
        raise ContactresInputError(
            f"{path}, line {number}: {empty_places(names)} of the header are empty; every "
            "column needs a name"
        )
    refuse_line_name(
        names,
        f"{path}, line {number}",
        lambda i: f"column 'line' (column {i})",
        "line numbers of the file",
    )
    return names


def load(path: Path, number_columns: Collection[str] = ()) -> pd.DataFrame:
    """Raw string table with a ``line`` column (line number in the file, header = line 1).

    ``number_columns``: columns that may come as float64 instead, each cell the number its
    text gives (:func:`_parsed`; a table with a decimal point), named in
    ``attrs["number_columns"]``; the others are text.

    ``attrs["sha256"]`` is the SHA-256 (hex) of the bytes parsed, read once with them (the
    sweep reader's checksum of its input, :func:`contactres.measurements.read_sweeps`).
    ``attrs["decimal"]`` records the decimal mark for the validator. Comment lines and blank
    lines are dropped here, before parsing, so that ``#`` inside a cell stays data and every
    row keeps the number of its line in the file; ``attrs["comment_lines"]`` holds the numbers
    of the comment lines below the header, which the validator reports (a commented-out row is
    data the user may not mean to drop). A row with more fields than the header, the first data
    row included, is an error naming it; so is a short row whose cells hold another separator
    (a line of ``;`` in a comma file), which would otherwise read as a row of empty cells.
    """
    import pandas as pd

    text, digest, encoded = _decode(path)
    # A table taken as it is (no line dropped) is its file's bytes: those are parsed, not the
    # text encoded again (UTF-8 decoding is undone exactly; ~0.1 s and a copy of the 148 MB
    # table of 10^5 sweeps, issue 31). The usual file ends in a line break, which ``body``
    # lacks: the bytes keep it (pandas makes no row of it) and only ``kept`` drops it, since
    # slicing it off would copy the whole file while the text is still held (+138 MB at the
    # peak of reading those 10^5 sweeps, review R28a). A file ending in a bare CR is rare:
    # its ``body`` is encoded again below. An ASCII table taken as it is is never decoded
    # (:func:`_ascii_lines`): its bytes stand for its text until a bad line is named.
    data = None
    tail = b""
    numbers = None if text is not None else _ascii_lines(encoded)
    body: str | bytes
    comments: list[int]
    if numbers is not None:
        body, comments, data = encoded, [], encoded
        tail = b"\n" if encoded.endswith(b"\n") else b""
    else:
        text = encoded.decode("ascii") if text is None else text
        body, numbers, comments = _data_lines(text)
        if body is text:
            data = encoded
        elif len(body) == len(text) - 1 and text.startswith(body) and text.endswith("\n"):
            data, tail = encoded, b"\n"
    del text, encoded
    if not len(numbers):
        raise ContactresInputError(
            f"{path}: the file is empty (expected a header line and data rows)"
        )
    _no_nul(path, body, numbers)
    head = _first_lines(body, 51)
    sep, decimal = _dialect("\n".join(head))
    names = _check_header(path, int(numbers[0]), head[0], sep)
    width = len(names)
    # Parsed as UTF-8 bytes: a StringIO holds its text at 4 bytes a character (issue 31,
    # point 3: 0.6 GB for the 148 MB table of 10^5 sweeps, most of the reading's peak); the
    # text itself is let go, and made again from the bytes only to name a bad line.
    if data is None:
        data = body.encode("utf-8") if isinstance(body, str) else body
    del body

    def kept() -> list[tuple[int, str]]:  # every line parsed, with its number (for errors)
        lines = data[: len(data) - len(tail)].decode("utf-8").split("\n")
        return list(zip(numbers.tolist(), lines, strict=True))

    def unreadable(exc: Exception | None) -> ContactresInputError:
        return ContactresInputError(
            f"{path}: not a readable {sep!r}-separated table ({_bad_rows(kept(), sep, exc)})"
        )

    # A first data row longer than the header would make pandas take its first field for an
    # index and shift every column one to the left (issue 27: an extra field blamed the wrong
    # column); later rows longer than the header are pandas' own error, named as this one.
    if len(head) > 1 and _width(head[1], sep) > width:
        raise unreadable(None)
    try:
        raw = _parsed(data, sep, names, number_columns if decimal == "." else ())
    except pd.errors.ParserError as exc:
        raise unreadable(exc) from None
    raw.columns = [str(c).strip() for c in raw.columns]
    # pandas names an empty header cell (kept so: the tables and messages of such a file are
    # as before), "Unnamed: i" or, where the header also holds that name written out (a table
    # saved twice by pandas: ",Unnamed: 0,pixel"), "Unnamed: 0.1": any name, so only the
    # named cells are compared. Any other difference from the csv module's names (a column
    # renamed, df_Hz.1, or two joined) is a fault of the reader, never to pass as a table
    # read right.
    read = list(raw.columns)
    if len(read) != width or any(n and c != n for c, n in zip(read, names, strict=True)):
        raise RuntimeError(
            f"{path}: pandas read the header as {shown_names(read)}, the csv module as "
            f"{shown_names(names)}"
        )
    # A short row may leave NaN in its missing cells (pandas 3 gives empty ones): make them
    # empty cells, as written. Its last cell is one of them, so that column alone is looked
    # at first (one column, not every cell of 10^6 rows: issue 31), on the first cell of each
    # run of equal cells (a constant's column is a few runs; _other_separator reads the runs).
    last = raw.iloc[:, -1]
    starts = column_run_starts(last)
    if (last if starts is None else last.iloc[starts]).isna().any():
        raw = raw.fillna("")
    if len(numbers) - 1 != len(raw):
        # pandas joined lines: a quoted cell ran over a line break (a CR or LF inside quotes).
        # Every row would be named by a wrong line, and the label would not be the one written.
        _quoted_break(path, kept())
    raw["line"] = numbers[1:]
    _other_separator(path, raw, starts, kept, sep, decimal, width)
    raw.attrs["decimal"] = decimal
    # Dropped lines among the data are said, never silent: the validator reports them
    # (line_ranges). Comments above the header are a preamble (an instrument's, or the
    # conventions qcm spectra writes), not rows.
    raw.attrs["comment_lines"] = tuple(n for n in comments if n > numbers[0])
    raw.attrs["sha256"] = digest()
    return raw


def _parsed(data: bytes, sep: str, names: list[str], numbers: Collection[str]) -> pd.DataFrame:
    """The table of the UTF-8 bytes ``data`` (header ``names``, separator ``sep``, decimal
    point): text cells, the columns of ``numbers`` as float64 where each reads as the same
    doubles as its text does (``attrs["number_columns"]`` names them), else all as text.

    Why: 10^6 rows of text cells are 10^6 Python strings a column, each parsed to a number
    again by the validator; pandas' parser reads a number column in C (issue 31: reading was
    the largest part of ``qcm analyze`` beyond the fits). Its converter is the one
    ``pandas.to_numeric`` applies to the text, with three exceptions, which send the table to
    the text path: a number with a leading ``+`` (to_numeric rounds those differently: 5.4e32
    from "+5.4E+32" one unit in the last place off; the file's bytes then hold a ``+`` not
    after ``e``/``E``), ``-0`` in a column of whole numbers (to_numeric makes it the integer 0,
    +0.0) and whole numbers from 2**53 on (converted from a 64-bit integer); NaN and infinities
    (the validator names their cells, from the text) and any cell that is no number (pandas'
    ValueError) too. tests/measurements/test_delimited_numbers.py compares both on 10^5 cells
    of many forms."""
    import pandas as pd

    options = {"encoding": "utf-8", "sep": sep, "keep_default_na": False,
               "skip_blank_lines": False, "index_col": False}  # fmt: skip
    typed = [i for i, name in enumerate(names) if name in numbers]
    signs = b"+" in data and data.count(b"+") != data.count(b"e+") + data.count(b"E+")
    if typed and not signs:
        dtype = {i: (np.float64 if i in typed else str) for i in range(len(names))}
        try:
            with warnings.catch_warnings():
                # A warning of the parser (a row it shortens) is the text path's to give.
                warnings.simplefilter("error")
                raw = pd.read_csv(io.BytesIO(data), dtype=dtype, **options)  # type: ignore[call-overload]
        except Exception:  # a cell that is no number, a table pandas refuses: the text path's
            raw = None
        if (
            raw is not None
            and raw.shape[1] == len(names)
            and all(_as_written(raw.iloc[:, i].to_numpy()) for i in typed)
        ):
            raw.attrs["number_columns"] = tuple(names[i] for i in typed)
            return raw
    return pd.read_csv(io.BytesIO(data), dtype=str, **options)  # type: ignore[call-overload]


def _as_written(values: np.ndarray) -> bool:
    """Whether a column that pandas' parser read as float64 holds what the validator reads
    from its text (:func:`_parsed`): finite, no -0.0, no whole number from 2**53 on."""
    if values.dtype != np.float64:
        return False
    if values.size and not np.abs(values).max() < 2.0**53:  # NaN, infinite or too large
        return False
    zero = values == 0
    return not (zero.any() and np.signbit(values[zero]).any())


def _data_lines(text: str) -> tuple[str, np.ndarray, list[int]]:
    """The lines of ``text`` to parse (neither blank nor a comment) joined by LF, the number of
    each in the file (the header's first) and the numbers of the comment lines.

    A table without blank lines, comments or CRs (the usual one: a file ending in a line break
    has an empty last line, which is no line) is taken as it is, found by two scans in C: no
    work per line in Python (issue 31: 10^6 lines)."""
    body = text[:-1] if text.endswith("\n") else text
    plain = body[:1] not in ("", "#") and not body[:1].isspace() and not body.endswith("\n")
    if plain and "\r" not in body and _DROPPED_LINE.search(body) is None:
        return body, np.arange(1, body.count("\n") + 2), []
    lines = _LINE_BREAK.split(text)
    kept = [(i + 1, ln) for i, ln in enumerate(lines) if ln.strip() and not _is_comment(ln)]
    comments = [i + 1 for i, ln in enumerate(lines) if _is_comment(ln)]
    numbers = np.array([n for n, _ in kept], dtype=np.int64)
    return "\n".join(ln for _, ln in kept), numbers, comments


def _ascii_lines(encoded: bytes) -> np.ndarray | None:
    """The line numbers (1, 2, ...: the header's first) of the ASCII bytes ``encoded`` where
    :func:`_data_lines` would take their text as it is (no blank line, comment or CR), else
    None: the same tests, made on the bytes (a decoded copy of the 148 MB table of 10^5
    sweeps cost ~0.1 s, and its slice less the last LF as much, issue 31, point 3)."""
    end = len(encoded) - 1 if encoded.endswith(b"\n") else len(encoded)
    if not end or encoded[0] in _SPACE_OR_HASH or encoded[end - 1 : end] == b"\n":
        return None
    if b"\r" in encoded or _DROPPED_LINE_ASCII.search(encoded) is not None:
        return None
    return np.arange(1, encoded.count(b"\n", 0, end) + 2)


def _first_lines(body: str | bytes, count: int) -> list[str]:
    """The first ``count`` lines of ``body`` (text, or ASCII bytes), as ``body.split("\\n",
    count)[:count]`` gives them, as text; the rest of the table is not copied (a split of
    the whole 148 MB table would copy it)."""
    lf = "\n" if isinstance(body, str) else b"\n"
    at = -1
    for _ in range(count):
        at = body.find(lf, at + 1)  # type: ignore[arg-type]
        if at < 0:
            break
    part = body if at < 0 else body[:at]
    text = part if isinstance(part, str) else part.decode("ascii")
    return text.split("\n")


def _width(line: str, sep: str) -> int:
    """The number of fields of one line, as the csv module splits it (0 if it cannot: a field
    over its limit of 128 kB, which pandas reads or names)."""
    try:
        return len(next(csv.reader([line], delimiter=sep), []))
    except csv.Error:
        return 0


def _other_separator(
    path: Path,
    raw: pd.DataFrame,
    starts: np.ndarray | None,
    kept: Callable[[], list[tuple[int, str]]],
    sep: str,
    decimal: str,
    width: int,
) -> None:
    """One-line error for a short row whose fields hold another separator (a line of ``;`` in
    a comma file): its cells would read as empty ones and be blamed as such (issue 27).

    Only rows whose cells past the first are all empty are looked at (a vectorised test), and
    only those are split again, by the csv module, to count their fields. ``starts``: the runs
    of equal cells of the last column (:func:`contactres.numerics.column_run_starts`), as the
    caller found them (before a short row's missing cells were made empty: equal cells stay
    equal, so they are still runs)."""
    others = [c for c in (",", ";", "\t") if c != sep and not (c == "," and decimal == ",")]
    if width < 2 or not others or raw.empty:
        return
    # The last cell first (one column: cheap on 10^6 rows, and compared on the first cell of
    # each run of equal cells only: a constant's column is a few runs), then the few rows left.
    last = raw.iloc[:, width - 1]
    if starts is None:  # Arrow text, compared whole
        empty = (last == "").to_numpy(dtype=bool)
    else:
        empty = repeat_runs((last.iloc[starts] == "").to_numpy(dtype=bool), starts, len(last))
    rows = raw.loc[empty]
    first = rows.iloc[:, 0].astype(str)
    held = np.zeros(len(rows), dtype=bool)
    for c in others:
        held |= first.str.contains(c, regex=False).to_numpy()
    suspect = held & (rows.iloc[:, 1:width] == "").all(axis=1).to_numpy()
    if not suspect.any():
        return
    lines = dict(kept())
    for number in rows["line"].to_numpy()[suspect]:
        text = lines[int(number)]
        fields = _width(text, sep)
        if not 0 < fields < width:
            continue
        used = next(c for c in others if c in text)
        raise ContactresInputError(
            f"{path}, line {number}: the row has {fields} field{'s' if fields > 1 else ''} "
            f"where the {sep!r}-separated header has {width}, and it holds {used!r}: the file "
            f"may use {used!r} as separator here; separate every row as the header is"
        )


def _bad_rows(kept: list[tuple[int, str]], sep: str, exc: Exception | None) -> str:
    """What pandas could not read, in the lines of the file: every row with more fields than
    the header (the first five and the count), else pandas' own words (``exc``; None when the
    first data row was found longer than the header before pandas read the table)."""
    widths = [len(row) for row in csv.reader((ln for _, ln in kept), delimiter=sep)]
    if len(widths) == len(kept):
        long = [(kept[i][0], w) for i, w in enumerate(widths) if i and w > widths[0]]
        if len(long) == 1:
            extra = long[0][1] - widths[0]
            return (
                f"line {long[0][0]} has {long[0][1]} fields, the header {widths[0]}: "
                f"{extra} field{'s' if extra > 1 else ''} more than the header; every row has "
                "one field per column"
            )
        if long:
            shown = ", ".join(f"{n} ({w} fields)" for n, w in long[:5])
            more = ", ..." if len(long) > 5 else ""
            head = f"{len(long)} rows have more fields than the header's {widths[0]}"
            return f"{head}: lines {shown}{more}"
    if exc is None:
        return f"line {kept[1][0]} has more fields than the header"
    found = _FIELD_COUNT.search(str(exc))
    if found and int(found.group(2)) <= len(kept):
        number = kept[int(found.group(2)) - 1][0]
        return f"line {number} has {found.group(3)} fields, the header {found.group(1)}"
    return " ".join(str(exc).split())[:200]


def _quoted_break(path: Path, kept: list[tuple[int, str]]) -> None:
    """One-line error naming the first line whose quotes do not close on it (a quoted cell
    holding a line break)."""
    number = next((n for n, ln in kept if ln.count('"') % 2), kept[0][0])
    raise ContactresInputError(
        f"{path}, line {number}: a quoted cell runs over a line break (a CR or LF inside "
        "quotes); write every label on one line"
    )


def _is_comment(line: str) -> bool:
    return line.lstrip().startswith("#")


def line_ranges(numbers) -> str:
    """Line numbers as ranges, e.g. ``2–14, 20, 31–32`` (at most five ranges, then "...")."""
    spans: list[list[int]] = []
    for n in sorted(int(x) for x in numbers):
        if spans and n == spans[-1][1] + 1:
            spans[-1][1] = n
        else:
            spans.append([n, n])
    shown = [f"{a}" if a == b else f"{a}–{b}" for a, b in spans[:5]]
    return ", ".join(shown) + (", ..." if len(spans) > 5 else "")


def detect(path: Path, head: str) -> bool:
    """True if the first line of ``head`` that is neither blank nor a comment has a comma, a
    semicolon or a tab."""
    first = next((ln for ln in head.splitlines() if ln.strip() and ln.lstrip()[0] != "#"), "")
    return any(s in first for s in (",", ";", "\t"))
