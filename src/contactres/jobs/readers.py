"""Every reader recipe of contactres in one immutable registry (:data:`ALL_READERS`), and the
readers of the map jobs' files through it.

The recipes live in the layer that owns each format and are composed here, the lowest layer
that sees them all: the measurements' built-in ones
(:data:`contactres.measurements.readers.BUILT_IN`: sweep tables, spectra, instrument
exports, resonance tables), the EBSD maps of :data:`contactres.polycrystal.EBSD_READERS`
and the measured value grids of :func:`read_value_grid` (:data:`GRID_READER`). So a recipe
never imports a layer above its own.

Contact-resonance AFM map files (kind ``afm_map``: an Asylum ``.ibw`` image, a BGlib SHO fit,
a NetCDF/Zarr grid) are recognised by their first bytes, the recipe of their suffix tried first
(:func:`read_afm_map_file`). EBSD exports and value grids are told apart by their suffix alone
(:meth:`~contactres.measurements.readers.Readers.for_suffix`): the reader of the
suffix reads the file and gives its own precise error for a file that is not right.
:func:`read_ebsd_file` and :func:`read_grid_file` take the registry to use (``readers=``), so a
caller adds a format with ``ALL_READERS.with_reader(...)`` and changes nothing shared.

>>> from contactres.jobs.readers import ALL_READERS
>>> [r.name for r in ALL_READERS.of_kind("ebsd")]
['ang', 'ctf', 'h5oina']
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import cast

import numpy as np

from ..errors import ContactresInputError
from ..measurements.readers import BUILT_IN, Reader, Readers
from ..polycrystal import EBSD_READERS

__all__ = [
    "ALL_READERS",
    "GRID_READER",
    "read_afm_map_file",
    "read_ebsd_file",
    "read_grid_file",
    "read_value_grid",
]

# One cell of a text grid: a number, NaN or blank (a pixel not measured).
_CELL = re.compile(r"^\s*([+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|nan|NaN|NAN)?\s*$")


def read_value_grid(path: str | os.PathLike) -> np.ndarray:
    """A measured map: ``.npy`` (2-D float array) or a CSV/text grid (one line per row y, one
    number per column x, comma- or whitespace-separated, no header; an empty cell or NaN is a
    pixel not measured). Values must be finite and > 0 where given.

    Raises ValueError naming the file, row, column and value of the first bad cell.
    """
    import pandas as pd

    p = Path(path)
    if p.suffix.lower() == ".npy":
        grid = np.load(p, allow_pickle=False)
        if grid.ndim != 2 or grid.dtype.kind not in "iuf":
            raise ContactresInputError(
                f"{p.name}: need a 2-D array of numbers, got {grid.dtype} {grid.shape}"
            )
        grid = grid.astype(float)
        cells = None
    else:
        sep = "," if "," in p.read_text(encoding="utf-8", errors="replace")[:4096] else r"\s+"
        try:
            cells = pd.read_csv(
                p, header=None, sep=sep, dtype=str, keep_default_na=False, skip_blank_lines=True
            )
        except pd.errors.ParserError as exc:
            raise ContactresInputError(f"{p.name}: rows of unequal length ({exc})") from None
        except pd.errors.EmptyDataError:
            raise ContactresInputError(f"{p.name}: no data") from None
        text = cells.to_numpy()
        blank = np.char.strip(text.astype(str)) == ""
        grid = (
            pd.DataFrame(np.where(blank, "nan", text))
            .apply(pd.to_numeric, errors="coerce")
            .to_numpy(float)
        )
        bad_text = (
            np.isnan(grid) & ~blank & (np.char.lower(np.char.strip(text.astype(str))) != "nan")
        )
        if bad_text.any():
            i, j = np.argwhere(bad_text)[0]
            raise ContactresInputError(
                f"{p.name}: row {i + 1}, column {j + 1}: {text[i, j]!r} is not a number"
            )
    bad = ~(np.isnan(grid) | (np.isfinite(grid) & (grid > 0)))
    if bad.any():
        i, j = np.argwhere(bad)[0]
        shown: object = grid[i, j] if cells is None else cells.iat[i, j]
        raise ContactresInputError(
            f"{p.name}: row {i + 1}, column {j + 1}: {shown} must be finite and > 0 "
            "(a stiffness in N/m or a modulus in Pa)"
        )
    if not np.isfinite(grid).any():
        raise ContactresInputError(f"{p.name}: no measured value")
    return grid


def _looks_like_grid(path: Path, head: str) -> bool:
    """A ``.npy`` array (its magic string), or a text grid whose first line holds numbers only,
    comma- or whitespace-separated (no header)."""
    if head[1:6] == "NUMPY":
        return True
    first = next((line for line in head.splitlines() if line.strip()), "")
    cells = first.split(",") if "," in first else first.split()
    return bool(cells) and all(_CELL.match(c) for c in cells)


#: The measured value grid of ``contactres maps fit`` (kind ``grid``).
GRID_READER = Reader("grid", (".npy", ".csv", ".txt"), _looks_like_grid, read_value_grid, "grid")

#: Every recipe: the measurements' built-in ones, the EBSD maps, the value grids.
ALL_READERS = Readers((*BUILT_IN, *EBSD_READERS, GRID_READER))


def read_ebsd_file(path: str | os.PathLike, readers: Readers = ALL_READERS):
    """An EBSD export read by the ``ebsd`` recipe of ``readers`` for its suffix.

    Returns the :class:`~contactres.polycrystal.OrientationMap`; a suffix no recipe
    claims is a one-line error naming the file and the suffixes known.
    """
    reader = readers.for_suffix(path, "ebsd")
    if reader is None:
        p = Path(path)
        known = " or ".join(s for r in readers.of_kind("ebsd") for s in r.suffixes)
        raise ContactresInputError(
            f"{p.name}: unknown EBSD export {p.suffix.lower()!r} (expected {known})"
        )
    return reader.load(path)


def read_grid_file(path: str | os.PathLike, readers: Readers = ALL_READERS) -> np.ndarray:
    """A measured value grid read by the ``grid`` recipe of ``readers`` for its suffix, or by
    the first ``grid`` recipe for another suffix (a text grid may be called anything)."""
    reader = readers.for_suffix(path, "grid") or readers.of_kind("grid")[0]
    return cast(np.ndarray, reader.load(path))  # what a grid recipe returns (KINDS["grid"])


def read_afm_map_file(path: str | os.PathLike, readers: Readers = ALL_READERS):
    """A contact-resonance AFM map file read by the ``afm_map`` recipe of ``readers`` that
    recognises it (by its first bytes; the recipe of its suffix is tried first).

    Returns what that recipe's ``load`` returns
    (:data:`~contactres.measurements.readers.KINDS`): an
    :class:`~contactres.measurements.IgorWave` for an Asylum image, a
    :class:`~contactres.measurements.ResonanceMaps` for a BGlib SHO fit or a grid. A missing or
    empty file, or one that no recipe recognises, is a one-line error naming the file and the
    formats known.
    """
    p = Path(path)
    if not p.exists():
        raise ContactresInputError(f"{p}: no such file")
    if p.is_file() and p.stat().st_size == 0:
        raise ContactresInputError(f"{p}: the file is empty")
    try:
        reader = readers.pick(p, "afm_map")
    except ContactresInputError:
        # pick's message quotes the first line of a text file; these formats are binary.
        known = ", ".join(f"{r.name} ({'/'.join(r.suffixes)})" for r in readers.of_kind("afm_map"))
        raise ContactresInputError(
            f"{p}: not a contact-resonance map file contactres reads; formats known: {known}"
        ) from None
    return reader.load(p)
