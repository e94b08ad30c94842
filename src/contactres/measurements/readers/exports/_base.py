"""Shared pieces of the QCM-D export readers: the plug-in, the tidy table and the conventions.

An instrument export holds, per overtone n, the resonance frequency f_n or its shift (Δf_n, or
Δf_n/n), and the dissipation D_n (often in units of 1e-6) or the half-bandwidth Γ_n. Every
reader turns its file into an :class:`ExportTable`: one row per point and overtone with the
time (s), Δf (Hz, *not* divided by n) and ΔΓ (Hz, the half-bandwidth at half height), and a
``conventions`` mapping that records what the file held and what was done to it.

What a reader cannot tell from the file it asks for (keyword arguments of ``load``, the options
of ``contactres qcm stiffness``); a missing choice is a one-line ValueError naming the file and
the choice, never a silent default:

``df_divided_by_n`` (bool)
    The file's shifts are Δf_n/n (True) or Δf_n (False). Absolute frequencies are f_n itself.
``dissipation_scale`` (float)
    What one unit of the D column is: 1e-6 for D in ppm ("1e-6"), 1 for D as a plain number.
``time_unit`` ("s", "min", "h")
    The unit of the time column.
``baseline`` ("first", "window:T0:T1", "as-exported")
    The reference of the shifts: the first point (earliest time) of each overtone, the mean
    over T0 <= t <= T1 (seconds), or the instrument software's own reference (files of shifts
    only). Files of absolute frequencies need "first" or a window.
``fundamental`` (Hz)
    The fundamental f_F: needed to turn a D shift into ΔΓ = ΔD n f_F / 2 when the file holds no
    absolute frequency (with absolute f_n it is read from the file: the median of f_n/n at the
    baseline; a value given is then checked against the file, 5 % tolerance).
``channel`` (str)
    The sensor or channel of a multi-sensor export (QSense 1-4, QCM-I A-D).
``overtone`` (int)
    The overtone of a file that does not name it (a single-overtone openQCM log), or the one to
    keep of a file that holds several.

The conversions to Δf and ΔΓ are in :mod:`._tidy` (:func:`~._tidy.convert`). Errors name the
file, the line, the column, the value and the rule in one line.
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from ....errors import ContactresInputError
from ....units import ABSOLUTE_FREQUENCY_FRACTION
from ..._messages import shown_value
from .._recipe import Reader

if TYPE_CHECKING:  # pandas is imported where a file is read: the command line's help imports
    import pandas as pd  # this package for the names of the readers, and starts without pandas

__all__ = [
    "ABSOLUTE_FREQUENCY_HZ",
    "COLUMNS",
    "CONVENTION_KEYS",
    "DECIMAL_COMMA",
    "LINE_BREAK",
    "TIME_UNITS",
    "ExportReader",
    "ExportTable",
    "ExportWarning",
    "Layout",
    "check_duplicates",
    "check_keys",
    "fail_at",
    "header_names",
    "missing",
    "numbers",
    "parse_baseline",
    "pick_channel",
    "read_rows",
    "rows_left_out",
    "unpaired",
]

#: Columns of :attr:`ExportTable.data`.
COLUMNS = ("time_s", "overtone", "df_Hz", "dgamma_Hz")

#: The line breaks of a text file (str.splitlines would also split at form feeds, U+2028, ...).
LINE_BREAK = re.compile(r"\r\n|\r|\n")

#: A number written with a decimal comma.
DECIMAL_COMMA = re.compile(r"^[+-]?\d+,\d+([eE][+-]?\d+)?$")

#: Seconds per unit of the time column.
TIME_UNITS = MappingProxyType({"s": 1.0, "min": 60.0, "h": 3600.0})

#: A frequency cell above this is a resonance frequency f_n, below it a shift: a tenth of the
#: lowest QCM fundamental (1 MHz), the rule of :data:`contactres.units.ABSOLUTE_FREQUENCY_FRACTION`.
ABSOLUTE_FREQUENCY_HZ = ABSOLUTE_FREQUENCY_FRACTION * 1e6

#: A column name that :func:`read_rows` made unique: the header's name repeated, with `` #k``.
_REPEATED = re.compile(r"^(.*) #(\d+)$")


class ExportWarning(UserWarning):
    """Something of an export that was not read (an overtone without its frequency or
    dissipation column, rows without a value, comment lines among the rows), or rows out of time
    order (the baseline "first" is then the earliest point), named in the message; the same
    lines are in the table's ``conventions["left_out"]``."""


#: The conventions a reader's ``load`` takes, with the command-line options that give them.
CONVENTION_KEYS = MappingProxyType(
    {
        "df_divided_by_n": "--df-divided-by-n or --df-per-overtone",
        "dissipation_scale": "--dissipation-scale",
        "time_unit": "--time-unit",
        "baseline": "--baseline",
        "fundamental": "--fundamental",
        "channel": "--channel",
        "overtone": "--overtone",
    }
)


@dataclass(frozen=True)
class ExportTable:
    """A QCM-D export in tidy form.

    Attributes
    ----------
    data : DataFrame
        One row per point and overtone: ``time_s`` (s), ``overtone`` (odd n), ``df_Hz``
        (Δf_n in Hz, not divided by n) and ``dgamma_Hz`` (ΔΓ_n in Hz, half-bandwidth).
    conventions : mapping
        What the file held and what was done (JSON-ready values): source file, reader, layout,
        channel, overtones, time unit, frequency and Δf form as read, D or Γ as read, D scale,
        baseline and reference values, fundamental and its source, the Γ rule, empty cells
        skipped and the keys the caller gave.
    """

    data: pd.DataFrame
    conventions: Mapping[str, object]

    def __post_init__(self):
        if tuple(self.data.columns) != COLUMNS:
            raise ContactresInputError(
                f"ExportTable needs the columns {COLUMNS}, got {tuple(self.data)}"
            )
        object.__setattr__(self, "conventions", MappingProxyType(dict(self.conventions)))


@dataclass(frozen=True)
class ExportReader(Reader):
    """The recipe of one instrument's export (a :class:`~contactres.measurements.readers.Reader`
    of kind ``export``).

    Attributes
    ----------
    name : str
        Short name (``--reader``).
    suffixes : tuple of str
        File suffixes (lower case, with dot) this reader is tried for first.
    detect : callable(path, head: str) -> bool
        True if the file (whose first few kB are ``head``) is in this format.
    load : callable
        ``load(path, **conventions) -> ExportTable`` reads the file; the conventions are those
        of :data:`CONVENTION_KEYS`.
    kind : str
        ``export``.
    conventions : mapping of str to str
        What the file holds, in words: time, frequency, dissipation, overtones, channels, and
        which choices the reader asks for.
    source : str
        Where the layout is documented.
    """

    kind: str = "export"
    conventions: Mapping[str, str] = field(default_factory=dict)
    source: str = ""

    def __post_init__(self):
        super().__post_init__()
        if self.kind != "export":
            raise ContactresInputError(f"export reader {self.name!r}: kind must be 'export'")
        object.__setattr__(self, "conventions", MappingProxyType(dict(self.conventions)))


@dataclass(frozen=True)
class Layout:
    """What a reader found in the header of one file (input of :func:`convert`).

    Attributes
    ----------
    description : str
        The layout in words, with its column names.
    time_column : str
        Column of the time.
    traces : tuple of (int, str, str)
        (overtone n, frequency column, dissipation column) per overtone.
    channel : str
        The sensor or channel read ("" if the file has one).
    time_unit : str or None
        Unit of the time column if the header says it, else None (asked for).
    frequency : "absolute", "shift" or None
        What the frequency columns hold if the header says it, else None (told from the values:
        above :data:`ABSOLUTE_FREQUENCY_HZ` a resonance frequency, below it a shift).
    divided_by_n : bool or None
        Shifts divided by n, if the header says it, else None (asked for when shifts).
    dissipation : "D" or "gamma"
        The dissipation factor D or the half-bandwidth Γ (Hz).
    dissipation_scale : float or None
        The unit of D if the header says it (1e-6 for ppm), else None (asked for).
    overtone_in_file : bool
        False when the file does not name its overtone (then ``overtone`` is asked for).
    left_out : tuple of (int, str)
        (overtone n, why) of the overtones of the header that are not read: a frequency
        column without its dissipation column or the reverse (:func:`unpaired`).
    dissipation_scale_default : float or None
        The unit of D the header implies without stating it as a number (an AWSensors ``()``:
        dimensionless, 1), used when the caller gives none; a ``dissipation_scale`` given
        replaces it.
    """

    description: str
    time_column: str
    traces: tuple[tuple[int, str, str], ...]
    channel: str = ""
    time_unit: str | None = None
    frequency: str | None = None
    divided_by_n: bool | None = None
    dissipation: str = "D"
    dissipation_scale: float | None = None
    overtone_in_file: bool = True
    left_out: tuple[tuple[int, str], ...] = ()
    dissipation_scale_default: float | None = None


def check_duplicates(path: Path, reader: str, names: list[str], patterns) -> None:
    """One-line error for a header that names a time, frequency or dissipation column twice
    (``patterns``: the reader's regular expressions of those names). The two columns cannot
    be told apart, and taking either would drop or misplace an overtone (issue 27)."""
    for i, name in enumerate(names):
        m = _REPEATED.match(name)
        if m and m.group(1) in names and any(p.match(m.group(1)) for p in patterns):
            first = names.index(m.group(1)) + 1
            raise ContactresInputError(
                f"{path}: the header names the column {m.group(1)!r} twice (columns {first} "
                f"and {i + 1}): which one holds the data is not known; rename the wrong one "
                f"({reader} export)"
            )


def unpaired(freqs: Mapping[int, str], diss: Mapping[int, str]) -> tuple[tuple[int, str], ...]:
    """(n, why) of the overtones with a frequency column and no dissipation column, or the
    reverse (``freqs``, ``diss``: column by overtone, of the channel read): they are left out
    of the table, and said (:attr:`Layout.left_out`)."""
    lines = []
    for n in sorted(freqs.keys() ^ diss.keys()):
        if n in freqs:
            why = f"frequency column {freqs[n]!r} has no dissipation column"
        else:
            why = f"dissipation column {diss[n]!r} has no frequency column"
        lines.append((n, f"overtone {n} not read: its {why}"))
    return tuple(lines)


def missing(path: Path, reader: str, choices: list[tuple[str, str]]) -> ValueError:
    """The one-line error of the conventions the file does not tell: the file, why each is
    needed, and the keyword and option that give it. ``choices``: (key, why) pairs."""
    whys = "; ".join(why for _, why in choices)
    keys = ", ".join(f"{key}=..." for key, _ in choices)
    options = "; ".join(CONVENTION_KEYS[key] for key, _ in choices)
    return ContactresInputError(
        f"{path}: {whys} ({reader} export); give {keys} ({options} on the command line)"
    )


def check_keys(path: Path, reader: str, conventions: Mapping[str, object]) -> None:
    """ValueError for a convention no reader knows (a typo must not be ignored)."""
    unknown = sorted(set(conventions) - set(CONVENTION_KEYS))
    if unknown:
        raise ContactresInputError(
            f"{path}: unknown convention(s) {', '.join(map(repr, unknown))} for the {reader} "
            f"reader; known: {', '.join(CONVENTION_KEYS)}"
        )


def header_names(head: str) -> list[str]:
    """Column names of the first line of ``head`` that is neither blank nor a comment."""
    first = next((ln for ln in head.splitlines() if ln.strip() and ln.lstrip()[0] != "#"), "")
    first = first.lstrip("\ufeff")
    sep = "\t" if "\t" in first else ";" if ";" in first else ","
    try:
        cells = next(csv.reader([first], delimiter=sep), [])
    except csv.Error:
        # A field over the csv module's limit (128 kB): split plainly, for recognising the
        # layout only; reading the file (read_rows) names the line in its error.
        cells = first.split(sep)
    return [" ".join(n.split()) for n in cells]


def read_rows(path: Path) -> pd.DataFrame:
    """The file as a table of string cells; the line of each row in ``attrs["lines"]``.

    Comma, semicolon or tab separated (from the header line); a decimal comma is recognised with
    semicolon or tab separators. Blank lines and lines starting with ``#`` are skipped (those
    below the header are recorded in ``attrs["comment_lines"]``, which the conversion names).
    Column names get runs of blanks made one blank; a repeated name (QCM-I repeats its flow and
    temperature columns per overtone) gets `` #2``, `` #3``, ... (a number the file's own names
    do not hold: every column keeps a name of its own). Text is UTF-8 (a byte order mark is
    skipped), else read as Windows-1252, as instrument software on Windows writes it.
    Short rows are padded with empty cells; empty cells past the header's width are dropped.
    """
    path = Path(path)
    data = path.read_bytes()
    try:
        text, encoding = data.decode("utf-8-sig"), "utf-8"
    except UnicodeDecodeError:
        text, encoding = data.decode("cp1252", errors="replace"), "cp1252"
    lines = LINE_BREAK.split(text)
    kept = [(i + 1, ln) for i, ln in enumerate(lines) if ln.strip() and not _comment(ln)]
    if not kept:
        raise ContactresInputError(
            f"{path}: the file is empty (expected a header line and data rows)"
        )
    header = kept[0][1]
    sep = "\t" if "\t" in header else ";" if ";" in header else ","
    reader = csv.reader((ln for _, ln in kept), delimiter=sep)
    try:
        rows = list(reader)
    except csv.Error as exc:
        # A field over the csv module's limit (128 kB) or a broken quote: name the file's line.
        number = kept[max(1, min(reader.line_num, len(kept))) - 1][0]
        raise ContactresInputError(
            f"{path}, line {number}: not a readable {sep!r}-separated row ({exc})"
        ) from None
    if len(rows) != len(kept):  # csv joined lines: a quoted cell holds a line break (CR, LF)
        number = next((n for n, ln in kept if ln.count('"') % 2), kept[0][0])
        raise ContactresInputError(
            f"{path}, line {number}: a quoted cell runs over a line break (a CR or LF inside "
            "quotes); write every cell on one line"
        )
    names: list[str] = []
    header = [" ".join(c.split()) for c in rows[0]]
    taken = set(header)  # a repeat's number skips a name the file itself holds ("Flow #2")
    seen: dict[str, int] = {}
    for name in header:
        seen[name] = seen.get(name, 0) + 1
        if seen[name] == 1:
            names.append(name)
            continue
        while f"{name} #{seen[name]}" in taken:
            seen[name] += 1
        names.append(f"{name} #{seen[name]}")
        taken.add(names[-1])
    width, cells, long = len(names), [], []
    for (number, _), row in zip(kept[1:], rows[1:], strict=True):
        if len(row) > width and any(c.strip() for c in row[width:]):
            long.append((number, len(row)))
        cells.append(row[:width] + [""] * (width - len(row)))
    if long:  # every such row is named (the first few), not only the first
        shown = ", ".join(f"{n} ({k} fields)" for n, k in long[:5])
        more = f", ... ({len(long)} rows in all)" if len(long) > 5 else ""
        raise ContactresInputError(
            f"{path}: line(s) {shown}{more} have more fields than the header (line "
            f"{kept[0][0]}, {width} fields): not one table"
        )
    import pandas as pd

    raw = pd.DataFrame(cells, columns=names, dtype=str)
    decimal = "."
    if sep != ",":
        sample = (c.strip() for row in cells[:50] for c in row)
        decimal = "," if any(DECIMAL_COMMA.match(c) for c in sample) else "."
    # Comment lines below the header are rows the user may have commented out: named by the
    # conversion (a preamble above the header is not a row).
    comments = tuple(i + 1 for i, ln in enumerate(lines) if i + 1 > kept[0][0] and _comment(ln))
    raw.attrs.update(
        lines=[n for n, _ in kept[1:]], decimal=decimal, encoding=encoding, comment_lines=comments
    )
    return raw


def _comment(line: str) -> bool:
    return line.lstrip().startswith("#")


def rows_left_out(raw: pd.DataFrame, n: int, keep: np.ndarray) -> str | None:
    """The line naming the rows of overtone ``n`` left out (``keep`` False: an empty time,
    frequency or dissipation cell), or None."""
    if keep.all():
        return None
    from .._delimited import line_ranges  # imports pandas: not at start-up (the CLI's help)

    numbers = np.asarray(raw.attrs["lines"])[~keep]
    return (
        f"overtone {n}: {numbers.size} row(s) without a time, frequency or dissipation value "
        f"left out (line(s) {line_ranges(numbers)})"
    )


def pick_channel(path: Path, reader: str, available: Iterable[str], wanted) -> str:
    """The channel to read: the one given, or the only one in the file."""
    found = sorted(dict.fromkeys(available))
    if not found:
        raise ContactresInputError(f"{path}: no channel found in the header ({reader} export)")
    if wanted is None:
        if len(found) > 1:
            why = f"the file holds the channels {', '.join(found)}"
            raise missing(path, reader, [("channel", why)])
        return found[0]
    if str(wanted).strip() not in found:
        raise ContactresInputError(
            f"{path}: channel {str(wanted)!r} (--channel) is not in the file; it holds "
            f"{', '.join(found)} ({reader} export)"
        )
    return str(wanted).strip()


def parse_baseline(text: str) -> tuple[str, float, float]:
    """``"first"``, ``"as-exported"`` or ``"window:T0:T1"`` (seconds, T0 < T1) as (kind, T0, T1)."""
    s = str(text).strip().lower()
    if s in ("first", "as-exported"):
        return s, math.nan, math.nan
    parts = s.split(":")
    try:
        if len(parts) != 3 or parts[0] != "window":
            raise ValueError
        t0, t1 = float(parts[1]), float(parts[2])
    except ValueError:
        raise ContactresInputError(
            f"baseline {str(text)!r} is not one of first, as-exported or window:T0:T1 (seconds)"
        ) from None
    if not (math.isfinite(t0) and math.isfinite(t1) and t0 < t1):
        raise ContactresInputError(
            f"baseline {str(text)!r}: the window needs finite T0 < T1 (seconds)"
        )
    return "window", t0, t1


def numbers(raw: pd.DataFrame, column: str, path: Path) -> np.ndarray:
    """A column as floats, NaN for an empty cell; a cell that is no finite number is an error."""
    import pandas as pd

    cells = raw[column].astype(str).str.strip()
    text = cells.str.replace(",", ".", regex=False) if raw.attrs.get("decimal") == "," else cells
    values = pd.to_numeric(text.where(text != "", "nan"), errors="coerce").to_numpy(float)
    bad = (cells != "").to_numpy() & ~np.isfinite(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ContactresInputError(
            f"{path}, line {raw.attrs['lines'][i]}, column {column!r}: value "
            f"{shown_value(cells.iloc[i])} is not a finite number"
        )
    return values


def fail_at(raw: pd.DataFrame, path: Path, column: str, rows: np.ndarray, rule: str) -> None:
    """Raise for the first row of ``rows`` (a boolean mask): file, line, column, value, rule."""
    i = int(np.flatnonzero(rows)[0])
    value = shown_value(raw[column].iloc[i])
    raise ContactresInputError(
        f"{path}, line {raw.attrs['lines'][i]}, column {column!r}: value {value} {rule}"
    )
