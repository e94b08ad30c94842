"""The built-in readers of resonance tables (kind ``resonances``), in a registry of their own.

The same recipes as those of :data:`~contactres.measurements.readers.BUILT_IN` of this kind,
in the same order (delimited text, an Excel workbook's sheet, a numpy archive):
:func:`contactres.measurements.read_resonance_table` picks its reader from them, so that
reading a CR-AFM or RUM table does not import every other reader of the registry (the
instrument exports, the AFM maps of ``.ibw``, BGlib and NetCDF files, the spectra): ~2 % of the
CPU time of ``afm invert`` of a 512² map from ``.npz`` to ``.npz`` (issue 31, point 5).
:data:`~contactres.measurements.readers.BUILT_IN` holds these very objects.
"""

from __future__ import annotations

from . import _delimited, _excel, _npz
from ._recipe import Reader, Readers

__all__ = ["RESONANCE_READERS"]

#: The built-in readers of kind ``resonances``, in the order they are tried.
RESONANCE_READERS = Readers(
    (
        Reader("csv", _delimited.suffixes, _delimited.detect, _delimited.load, "resonances"),
        Reader("xlsx", _excel.suffixes, _excel.detect, _excel.loader("resonances"), "resonances"),
        Reader("npz", _npz.suffixes, _npz.detect, _npz.load, "resonances"),
    )
)
