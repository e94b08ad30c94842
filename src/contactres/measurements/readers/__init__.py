"""Reader plug-ins: each turns one file format into a table of raw string columns.

A reader (:class:`SweepReader`) knows its suffixes, how to recognise its format from the first
few kB of a file and how to load it; :func:`pick_reader` tries the readers whose suffix matches
first, then the others. The built-in readers are registered here; :func:`register_reader` adds
one (tried before the built-in ones).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from ...errors import ContactresInputError
from . import delimited

__all__ = ["READERS", "SweepReader", "pick_reader", "register_reader"]


@dataclass(frozen=True)
class SweepReader:
    """A reader plug-in: turns one file format into a table of raw string columns.

    Attributes
    ----------
    name : str
        Short name of the format.
    suffixes : tuple of str
        File suffixes (lower case, with dot) this reader is tried for first.
    detect : callable(path, head: str) -> bool
        True if the file (whose first few kB are ``head``) is in this format.
    load : callable(path) -> DataFrame
        Raw table: string cells, header names stripped, plus an integer ``line`` column giving
        the line number of each row in the file (header = line 1).
    """

    name: str
    suffixes: tuple[str, ...]
    detect: Callable[[Path, str], bool]
    load: Callable[[Path], pd.DataFrame]


#: The readers, in the order they are tried (after those whose suffix matches).
READERS: list[SweepReader] = [
    SweepReader("csv", delimited.suffixes, delimited.detect, delimited.load)
]


def register_reader(reader: SweepReader) -> SweepReader:
    """Add a reader plug-in (tried before the built-in ones); its name must be new."""
    if any(r.name == reader.name for r in READERS):
        raise ContactresInputError(f"a reader named {reader.name!r} is already registered")
    READERS.insert(0, reader)
    return reader


def pick_reader(path: Path) -> SweepReader:
    """The reader for ``path`` (ValueError naming the known formats if none recognises it)."""
    with path.open(encoding="utf-8-sig", errors="replace") as fh:
        head = fh.read(4096)
    if not head.strip():
        raise ContactresInputError(
            f"{path}: the file is empty (expected a header line and data rows)"
        )
    by_suffix = [r for r in READERS if path.suffix.lower() in r.suffixes]
    others = [r for r in READERS if r not in by_suffix]
    for reader in by_suffix + others:
        if reader.detect(path, head):
            return reader
    names = ", ".join(f"{r.name} ({'/'.join(r.suffixes)})" for r in READERS)
    raise ContactresInputError(f"{path}: no reader recognises this file; formats known: {names}")
