"""Reader plug-ins for the exports of commercial and open QCM-D instruments.

Each plug-in (:class:`ExportReader`: name, suffixes, ``detect``, ``load``, conventions,
source of the layout) turns one instrument's text export into an :class:`ExportTable`:
a tidy table ``time_s, overtone, df_Hz, dgamma_Hz`` (Δf not divided by n, ΔΓ the half-bandwidth
shift) and the conventions it was read with. The built-in readers, in the order they are tried:

* ``qsense``: Biolin Scientific QSense (QSoft, Dfind, QTools) text exports (``_qsense``);
* ``awsensors``: AWSensors exports (``_awsensors``);
* ``qcmi``: MicroVacuum QCM-I exports (``_qcmi``);
* ``openqcm``: openQCM Q-1 and Next data logs (``_openqcm``).

Beside them, :data:`TIDY_READER` (``tidy``, ``_shift_table``) reads the tidy table of shifts a
user writes from any instrument (``time_s, overtone, df_Hz, dgamma_Hz``,
:data:`contactres.measurements.schema.QCMD_SHIFTS_TABLE`); :data:`SHIFT_READERS` is it and the
four instrument readers, the readers of ``contactres qcm particles``.

The modules of the plug-ins, and ``_base`` (the recipe and the table) and ``_tidy`` (the
conversions) beside them, are private (scipy's rule): import from this package.

What a file does not say (Δf or Δf/n, the unit of D, the time unit, the baseline, the
fundamental, the channel, the overtone of a single-overtone log) is asked for: a keyword of
:func:`read_export` (:data:`CONVENTION_KEYS`), never a silent default. Nothing is dropped
without a word: a header naming a time, frequency or dissipation column twice is an error, and
an overtone without its frequency or dissipation column, rows without a value and comment
lines among the rows are named in an :class:`ExportWarning` (and in the table's
``conventions["left_out"]``).

:data:`EXPORT_READERS` is a tuple of recipes
(:class:`~contactres.measurements.readers.Reader` of kind ``export``, part of
:data:`contactres.measurements.readers.BUILT_IN`): pass your own tuple of readers to
:func:`pick_export_reader` and :func:`read_export` to add one.
"""

from __future__ import annotations

from pathlib import Path

from ....errors import ContactresInputError
from .._recipe import first_detected, read_head
from . import _awsensors, _openqcm, _qcmi, _qsense, _shift_table
from ._base import CONVENTION_KEYS, ExportReader, ExportTable, ExportWarning, parse_baseline

__all__ = [
    "CONVENTION_KEYS",
    "EXPORT_READERS",
    "SHIFT_READERS",
    "TIDY_READER",
    "ExportReader",
    "ExportTable",
    "ExportWarning",
    "export_reader",
    "parse_baseline",
    "pick_export_reader",
    "read_export",
]

#: The built-in export readers, in the order they are tried (after those whose suffix matches).
EXPORT_READERS: tuple[ExportReader, ...] = (
    _qsense.READER,
    _awsensors.READER,
    _qcmi.READER,
    _openqcm.READER,
)

#: The tidy table of QCM-D shifts (``time_s, overtone, df_Hz, dgamma_Hz``): its column names
#: state its conventions (:mod:`._shift_table`).
TIDY_READER: ExportReader = _shift_table.READER

#: The readers of a file of QCM-D shifts (``contactres qcm particles``): the tidy table first
#: (recognised by its column names, which no instrument writes), then :data:`EXPORT_READERS`.
SHIFT_READERS: tuple[ExportReader, ...] = (TIDY_READER, *EXPORT_READERS)

#: Binary files an instrument also writes, which no reader here reads.
_BINARY_SUFFIXES = (".xlsx", ".xls", ".xlsm", ".qsd", ".h5")


def export_reader(name: str, readers: tuple[ExportReader, ...] = EXPORT_READERS) -> ExportReader:
    """The reader called ``name`` (ValueError listing the known names)."""
    for reader in readers:
        if reader.name == str(name).strip().lower():
            return reader
    known = ", ".join(r.name for r in readers)
    raise ContactresInputError(f"no export reader is called {str(name)!r}; known: {known}")


def pick_export_reader(path, readers: tuple[ExportReader, ...] = EXPORT_READERS) -> ExportReader:
    """The reader that recognises ``path`` from its first 4 kB (those whose suffix matches are
    tried first). ValueError naming the file and the known formats if none does."""
    path = Path(path)
    binary = path.suffix.lower() in _BINARY_SUFFIXES
    # A binary file is tried only by the readers that take its suffix (the tidy shift table
    # on a sheet of an .xlsx workbook), never by the text readers.
    tried = tuple(r for r in readers if path.suffix.lower() in r.suffixes) if binary else readers
    found = first_detected(tried, path, read_head(path)) if tried else None
    if found is not None:
        return found
    if binary:
        sheet = (
            "; a workbook is read as the tidy table time_s, overtone, df_Hz, dgamma_Hz on its "
            "sheet 'shifts' (else its first)"
            if tried
            else ""
        )
        raise ContactresInputError(
            f"{path}: a {path.suffix} file is binary; export the data from the instrument "
            f"software as text (tab, semicolon or comma separated){sheet}"
        )
    names = ", ".join(r.name for r in readers)
    raise ContactresInputError(
        f"{path}: no export reader recognises its header (formats known: {names}); name one "
        "with reader=... (--reader), or see the layouts in contactres.measurements.readers.exports"
    )


def read_export(
    path,
    reader: str | None = None,
    *,
    readers: tuple[ExportReader, ...] = EXPORT_READERS,
    **conventions,
) -> ExportTable:
    """Read an instrument export into an :class:`ExportTable`.

    Parameters
    ----------
    path : str or Path
        The exported text file.
    reader : str, optional
        Name of the reader (default: recognised from the file's header).
    readers : tuple of ExportReader
        The readers to choose from (default :data:`EXPORT_READERS`).
    **conventions
        What the file does not say (:data:`CONVENTION_KEYS`): ``df_divided_by_n`` (bool),
        ``dissipation_scale`` (1e-6 for ppm), ``time_unit`` ("s", "min", "h"), ``baseline``
        ("first", "window:T0:T1" in s, "as-exported"), ``fundamental`` (Hz), ``channel``,
        ``overtone``. None means not given.

    Raises
    ------
    ValueError
        One line naming the file and, for a choice the file does not tell, the missing choice.

    Warns
    -----
    ExportWarning
        One per overtone, group of rows or comment lines left out, naming them.
    """
    path = Path(path)
    chosen = pick_export_reader(path, readers) if reader is None else export_reader(reader, readers)
    return chosen.load(path, **conventions)
