"""Readers: each turns one file format into what its kind of input needs.

A reader is an immutable recipe (:class:`Reader`: name, suffixes, ``detect``, ``load``,
``kind``); the built-in recipes form one immutable registry
(:data:`BUILT_IN`, a :class:`Readers`), from which :func:`pick_reader` takes
the reader of a file: those whose suffix matches are tried first, then the others. To add a
reader, build a new registry (``BUILT_IN.with_reader(my_reader)``) and pass it to the function
that reads, or pass ``extra=(my_reader,)`` to :func:`pick_reader`: nothing shared changes.
:data:`RESONANCE_READERS` holds the built-in readers of resonance tables alone (the same
objects), for a reading that needs no other reader imported.

The formats: delimited text (``_delimited``, sweep and resonance tables), spectra
(``_spectra``), instrument exports (:mod:`.exports`) and contact-resonance AFM maps (``_afm``:
Asylum ``.ibw`` images, BGlib SHO fits, NetCDF/Zarr grids). The modules are private (scipy's rule:
import from this package and from :mod:`.exports`). Beside the recipes, this package exports
what the tables of :mod:`contactres.measurements` take from the readers: the spectra tables'
layouts, two-port parameters, labels and constant columns (:data:`SPECTRUM_LAYOUTS`,
:data:`TWO_PORT_PARAMETERS`, :data:`LABELS`,
:data:`NUMERIC_LABELS`, :data:`CONSTANT_COLUMNS`), their cells as numbers
(:func:`cells_as_numbers`) and line numbers as ranges for messages (:func:`line_ranges`).
"""

from __future__ import annotations

import importlib
import warnings
from typing import TYPE_CHECKING

from ._recipe import KINDS, Reader, Readers

if TYPE_CHECKING:
    from ._delimited import line_ranges
    from ._registry import BUILT_IN, BUILT_IN_READERS, pick_reader
    from ._resonance_readers import RESONANCE_READERS
    from ._spectra import (
        CONSTANT_COLUMNS,
        LABELS,
        NUMERIC_LABELS,
        SPECTRUM_LAYOUTS,
        TWO_PORT_PARAMETERS,
        cells_as_numbers,
    )

#: The names loaded on first use (PEP 562) -> their private module: the registry imports every
#: reader and pandas, and a reader's package (the export readers, whose names the command
#: line's help shows) is imported with this one; the help starts without pandas.
_LAZY = {
    "BUILT_IN": "_registry",
    "BUILT_IN_READERS": "_registry",
    "pick_reader": "_registry",
    "RESONANCE_READERS": "_resonance_readers",
    "CONSTANT_COLUMNS": "_spectra",
    "LABELS": "_spectra",
    "NUMERIC_LABELS": "_spectra",
    "SPECTRUM_LAYOUTS": "_spectra",
    "TWO_PORT_PARAMETERS": "_spectra",
    "cells_as_numbers": "_spectra",
    "line_ranges": "_delimited",
}

__all__ = [
    "BUILT_IN",
    "BUILT_IN_READERS",
    "CONSTANT_COLUMNS",
    "KINDS",
    "LABELS",
    "NUMERIC_LABELS",
    "RESONANCE_READERS",
    "SPECTRUM_LAYOUTS",
    "TWO_PORT_PARAMETERS",
    "Reader",
    "Readers",
    "SweepReader",
    "cells_as_numbers",
    "line_ranges",
    "pick_reader",
]


def SweepReader(name, suffixes, detect, load) -> Reader:
    """A reader of sweep tables: ``Reader(name, suffixes, detect, load, "sweeps")``.

    .. deprecated:: 0.3
       Use :class:`Reader` with ``kind="sweeps"``.
    """
    warnings.warn(
        'SweepReader is deprecated: use Reader(name, suffixes, detect, load, "sweeps")',
        DeprecationWarning,
        stacklevel=2,
    )
    return Reader(name, tuple(suffixes), detect, load, "sweeps")


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})
