"""Reader plug-in for delimited text tables (CSV, semicolon- or tab-separated).

The separator and the decimal mark are recognised from the header and the first data lines:
comma, semicolon or tab; a decimal comma with semicolon or tab separators. A UTF-8 byte order
mark is skipped; lines starting with ``#`` are comments.
"""

from __future__ import annotations

import io
import re
from pathlib import Path

import pandas as pd

__all__ = ["detect", "load", "suffixes"]

suffixes = (".csv", ".txt", ".tsv")

_DECIMAL_COMMA = re.compile(r"^[+-]?\d+,\d+([eE][+-]?\d+)?$")


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


def load(path: Path) -> pd.DataFrame:
    """Raw string table with a ``line`` column (line number in the file, header = line 1).

    ``attrs["decimal"]`` records the decimal mark for the validator.
    """
    text = path.read_text(encoding="utf-8-sig")
    if not text.strip():
        raise ValueError(f"{path}: the file is empty (expected a header line and data rows)")
    sep, decimal = _dialect(text)
    try:
        raw = pd.read_csv(
            io.StringIO(text),  # parse the text already read (and decoded) once
            sep=sep,
            dtype=str,
            keep_default_na=False,
            skip_blank_lines=True,
            comment="#",
        )
    except pd.errors.ParserError as exc:
        raise ValueError(f"{path}: not a readable {sep!r}-separated table ({exc})") from None
    raw.columns = [str(c).strip() for c in raw.columns]
    # Line numbers for messages: count non-blank, non-comment lines as pandas does.
    numbers = [
        i + 1
        for i, ln in enumerate(text.splitlines())
        if ln.strip() and not ln.lstrip().startswith("#")
    ]
    raw["line"] = numbers[1 : len(raw) + 1] if len(numbers) > len(raw) else range(2, len(raw) + 2)
    raw.attrs["decimal"] = decimal
    return raw


def detect(path: Path, head: str) -> bool:
    """True if the first non-blank line of ``head`` has a comma, semicolon or tab."""
    first = next((ln for ln in head.splitlines() if ln.strip()), "")
    return any(s in first for s in (",", ";", "\t"))
