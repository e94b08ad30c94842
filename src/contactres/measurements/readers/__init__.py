"""Readers: each turns one file format into what its kind of input needs.

A reader is an immutable recipe (:class:`~.recipe.Reader`: name, suffixes, ``detect``, ``load``,
``kind``); the built-in recipes form one immutable registry
(:data:`~.registry.BUILT_IN`, a :class:`~.recipe.Readers`), from which :func:`pick_reader` takes
the reader of a file: those whose suffix matches are tried first, then the others. To add a
reader, build a new registry (``BUILT_IN.with_reader(my_reader)``) and pass it to the function
that reads, or pass ``extra=(my_reader,)`` to :func:`pick_reader`: nothing shared changes.

The formats: delimited text (:mod:`.delimited`, sweep and resonance tables), spectra
(:mod:`.spectra`) and instrument exports (:mod:`.exports`).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

from .recipe import KINDS, Reader, Readers

if TYPE_CHECKING:
    from .registry import BUILT_IN, BUILT_IN_READERS, pick_reader

#: The names of :mod:`.registry`, loaded on first use (PEP 562): the registry imports every
#: reader and pandas, and a reader's package (the export readers, whose names the command
#: line's help shows) is imported with this one; the help starts without pandas.
_FROM_REGISTRY = ("BUILT_IN", "BUILT_IN_READERS", "pick_reader")

__all__ = [
    "BUILT_IN",
    "BUILT_IN_READERS",
    "KINDS",
    "Reader",
    "Readers",
    "SweepReader",
    "pick_reader",
]


def SweepReader(name, suffixes, detect, load) -> Reader:
    """A reader of sweep tables: ``Reader(name, suffixes, detect, load, "sweeps")``.

    .. deprecated:: 0.3
       Use :class:`~.recipe.Reader` with ``kind="sweeps"``.
    """
    warnings.warn(
        'SweepReader is deprecated: use Reader(name, suffixes, detect, load, "sweeps")',
        DeprecationWarning,
        stacklevel=2,
    )
    return Reader(name, tuple(suffixes), detect, load, "sweeps")


def __getattr__(name: str):
    if name in _FROM_REGISTRY:
        from . import registry

        return getattr(registry, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_FROM_REGISTRY})
