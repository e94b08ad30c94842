"""Reader of numpy archives (``.npz``): a table of resonances as one array per column.

A binary table (issue 31: a 512² map read in milliseconds, where its CSV takes about a second
of parsing): each array of the archive (``numpy.savez``) is one column, named as in the CSV
(``fc1_Hz``, ``k_c_N_per_m``, ...), all one-dimensional and of one length. Numbers stay
numbers (NaN: not given, as a blank cell of the CSV); text columns (labels) are unicode
arrays. Rows are numbered from 1 in messages (``row``, there are no lines). Pickled objects are
refused (``allow_pickle=False``): an archive is data, never code. ``afm invert --out x.npz``
writes this layout.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

from ..._column_names import refuse_line_name, repeats_text
from ...errors import ContactresInputError
from .._array_table import ArrayTable

__all__ = ["detect", "load", "suffixes"]

suffixes = (".npz",)

#: An .npz is a zip archive of .npy files: its first bytes are a file's header, or the end of
#: the archive when it holds none.
_ZIP = (b"PK\x03\x04", b"PK\x05\x06")


def detect(path: Path, head: str) -> bool:
    """True for a file with suffix ``.npz`` that starts with the zip signature."""
    if path.suffix.lower() not in suffixes or not path.is_file():
        return False
    with path.open("rb") as fh:
        return fh.read(4) in _ZIP


def load(path: Path) -> ArrayTable:
    """The table of the archive: one column per array (numbers as floats or integers, text as
    Python strings), a ``line`` column numbering the rows from 1 (``attrs["line_word"]`` is
    ``row``), as numpy columns (:class:`~contactres.measurements.ArrayTable`: a binary table
    read and written again needs no pandas; its
    :meth:`~contactres.measurements.ArrayTable.to_frame` gives the DataFrame). One-line error
    for an archive that cannot be read, holds pickled objects, or whose arrays are not
    one-dimensional of one length."""
    try:
        with np.load(path, allow_pickle=False) as archive:
            # Two arrays of one name (a member written twice, or "x" beside "x.npy") are one
            # key to numpy, which reads one of them: refused, as a name twice in a CSV header.
            repeats = repeats_text(archive.files, word="arrays", tail=" of the archive")
            if repeats is not None:
                raise ContactresInputError(
                    f"{path}: duplicate array name(s) {repeats}; every column needs its own name"
                )
            columns = {name: archive[name] for name in archive.files}
    except ContactresInputError:
        raise
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise ContactresInputError(f"{path}: not a readable numpy archive (.npz): {exc}") from None
    if not columns:
        raise ContactresInputError(f"{path}: the archive holds no arrays (expected columns)")
    lengths = {name: a.shape for name, a in columns.items()}
    n = next(iter(columns.values())).shape
    if any(len(s) != 1 or s != n for s in lengths.values()):
        shown = ", ".join(f"{name} {s}" for name, s in lengths.items())
        raise ContactresInputError(
            f"{path}: every array of the archive is one column, one-dimensional and of one "
            f"length; got {shown}"
        )
    refuse_line_name(
        columns,
        str(path),
        lambda i: f"array 'line' (array {i} of the archive)",
        "row numbers of the table",
    )
    for name, a in columns.items():
        if a.dtype.kind not in "fiuU":
            raise ContactresInputError(
                f"{path}: column {name!r} holds {a.dtype} values; numbers or text expected"
            )
    # Text as Python strings (object), as the CSV reader gives it: a unicode array would be as
    # wide as its longest cell.
    table = ArrayTable(
        {name: (a.astype(object) if a.dtype.kind == "U" else a) for name, a in columns.items()}
    )
    table["line"] = np.arange(1, n[0] + 1)
    table.attrs["line_word"] = "row"
    table.attrs["decimal"] = "."
    return table
