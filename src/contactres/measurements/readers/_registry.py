"""The built-in reader recipes of the measurements layer, in one immutable registry.

:data:`BUILT_IN` holds, by kind (:data:`KINDS`): the delimited-text reader of sweep
tables and of resonance tables (``csv``) and that of the same tables, and of a tidy spectra
table, on a sheet of an Excel workbook (``xlsx``), the spectra readers (a folder of spectrum
files, a tidy table: ``SPECTRA_READERS`` of ``_spectra``) and the instrument exports
(:data:`~.exports.EXPORT_READERS`, and the tidy table of shifts,
:data:`~.exports.TIDY_READER`), and the contact-resonance AFM maps (kind ``afm_map``: an
Asylum ``.ibw`` image, a BGlib SHO fit ``.h5``, a NetCDF/Zarr grid; ``AFM_MAP_READERS`` of
``_afm``). EBSD maps and value grids are read by recipes of the layers
that own their formats (:data:`contactres.polycrystal.EBSD_READERS`,
``contactres.jobs.readers``), which compose the full registry above this layer; a recipe here
never imports a higher layer, not even when it is called.

To add a reader, build a new registry (``BUILT_IN.with_reader(my_reader)``) and pass it to the
function that reads (``read_sweeps(path, readers=...)``), or pass ``extra=(my_reader,)`` to
:func:`pick_reader`; nothing shared changes.
"""

from __future__ import annotations

from collections.abc import Iterable
from functools import partial
from pathlib import Path

from . import _delimited, _excel
from ._afm import AFM_MAP_READERS
from ._recipe import Reader, Readers
from ._resonance_readers import RESONANCE_READERS
from ._spectra import SPECTRA_READERS
from .exports import EXPORT_READERS, TIDY_READER

__all__ = ["BUILT_IN", "BUILT_IN_READERS", "pick_reader"]

#: The measured columns of a sweep table, which the delimited reader gives as numbers where
#: they read as the validator reads their text (10^6 rows each: issue 31); the constants and
#: the ramp stay text, each distinct text read (and, if wrong, named as written) once.
SWEEP_NUMBERS = ("amplitude_m", "df_Hz", "dgamma_Hz", "normal_force_N", "time_s")

#: The built-in recipes, in the order they are tried within each kind (after those whose
#: suffix matches).
BUILT_IN_READERS: tuple[Reader, ...] = (
    Reader(
        "csv",
        _delimited.suffixes,
        _delimited.detect,
        partial(_delimited.load, number_columns=SWEEP_NUMBERS),
        "sweeps",
    ),
    RESONANCE_READERS.named("csv", "resonances"),
    Reader("xlsx", _excel.suffixes, _excel.detect, _excel.loader("sweeps"), "sweeps"),
    *RESONANCE_READERS.of_kind("resonances")[1:],  # xlsx, npz: the tables of resonances
    *SPECTRA_READERS,
    # A workbook of spectra rows: tried first for .xlsx, by its suffix, before the tidy table.
    Reader("xlsx", _excel.suffixes, _excel.detect, _excel.loader("spectra"), "spectra"),
    *EXPORT_READERS,
    *AFM_MAP_READERS,
    TIDY_READER,
)
#: The built-in registry.
BUILT_IN = Readers(BUILT_IN_READERS)


def pick_reader(path, kind: str = "sweeps", extra: Iterable[Reader] = ()) -> Reader:
    """The reader of ``kind`` for ``path``: ``extra`` readers first, then the built-in ones
    (within each, those whose suffix matches first). One-line error naming the file and the
    formats known if none recognises it, or if the file is empty."""
    extra = tuple(extra)
    registry = BUILT_IN.with_reader(*extra) if extra else BUILT_IN
    return registry.pick(Path(path), kind)
