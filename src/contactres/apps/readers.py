"""Every reader recipe of contactres in one immutable registry (:data:`ALL_READERS`).

The recipes live in the layer that owns each format and are composed here, the lowest layer
that sees them all: the measurements' built-in ones
(:data:`contactres.measurements.readers.registry.BUILT_IN`: sweep tables, spectra, instrument
exports, resonance tables), the EBSD maps of :data:`contactres.polycrystal.ebsd.EBSD_READERS`
and the measured value grids of :func:`contactres.apps.maps.read_value_grid`
(:data:`GRID_READER`). So a recipe never imports a layer above its own.

>>> from contactres.apps.readers import ALL_READERS
>>> [r.name for r in ALL_READERS.of_kind("ebsd")]
['ang', 'ctf']
"""

from __future__ import annotations

import re
from pathlib import Path

from ..measurements.readers.recipe import Reader, Readers
from ..measurements.readers.registry import BUILT_IN
from ..polycrystal.ebsd import EBSD_READERS
from .maps import read_value_grid

__all__ = ["ALL_READERS", "GRID_READER"]

# One cell of a text grid: a number, NaN or blank (a pixel not measured).
_CELL = re.compile(r"^\s*([+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|nan|NaN|NAN)?\s*$")


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
