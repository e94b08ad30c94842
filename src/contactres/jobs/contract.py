"""The contract every job keeps: a ``Settings``, a typed ``Result`` and ``run``.

A job is one workflow of contactres (a QCM sweep analysis, a DCSF curve, a CR-AFM inversion,
...), one module of :mod:`contactres.jobs`. Each module defines

* ``Settings``: a frozen dataclass of the choices of the workflow (SI units, as the library's
  functions take them); its defaults are those of the command line;
* ``Result``: a frozen dataclass deriving from :class:`JobResult`, whose fields are its tables
  (:class:`pandas.DataFrame`, each bound in :attr:`JobResult.SCHEMAS` to the
  :class:`~contactres.measurements.schema.TableSchema` that documents its columns: every table
  has one, ``tests/jobs/test_job_schemas.py`` checks it) and its values (numbers, text, small
  dicts);
* ``run(inputs, settings, progress=None) -> Result``: the computation, a pure function of its
  arguments apart from reading the input files it is given. ``progress`` (a :data:`Progress`)
  receives one short line per stage ("reading x.csv", "inverting 12 rows").

A job never writes a file nor prints: the command line prints a Result and
:func:`contactres.report.write_report` writes one (its tables as CSV, its values as JSON,
the figures and the HTML page registered for its type). A job imports the library below it
(analysis, polycrystal, ...), never :mod:`contactres.report`, :mod:`contactres.apps` or the
command line.
User errors raise :class:`contactres.errors.ContactresInputError`, as in the rest of the library.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar

if TYPE_CHECKING:  # annotations only: a job module imports pandas when it runs
    import pandas as pd

    from ..measurements.schema import TableSchema

__all__ = ["JobResult", "Progress", "json_value", "say"]

#: A progress callback: takes one short line of text (a stage of the job), returns nothing.
Progress = Callable[[str], None]


def say(progress: Progress | None, text: str) -> None:
    """Pass ``text`` to ``progress`` when there is one (a job's stages, for a progress line)."""
    if progress is not None:
        progress(text)


def json_value(value: Any) -> Any:
    """``value`` as plain JSON data: numpy scalars and arrays become Python numbers and lists,
    non-finite floats ``None`` (JSON has no NaN), mappings and sequences recursively."""
    if hasattr(value, "tolist"):  # numpy scalar or array
        value = value.tolist()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {str(k): json_value(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_value(v) for v in value]
    if value is None or isinstance(value, bool | int | str):
        return value
    return str(value)


class JobResult:
    """Base of the ``Result`` dataclasses of the jobs: their tables and values, separated.

    A subclass is a frozen dataclass; :attr:`SCHEMAS` names its fields that are tables (a
    :class:`pandas.DataFrame` each) with their schema. Every other field is a value.
    """

    #: Table field -> its schema (None only while a schema is being written: the tests refuse it).
    SCHEMAS: ClassVar[Mapping[str, TableSchema | None]] = MappingProxyType({})
    #: Fields that are not values of the result: messages for the user (``warnings``, a tuple
    #: of lines, printed) and labels (the input's name, for a figure's title).
    NOT_VALUES: ClassVar[tuple[str, ...]] = ("warnings",)
    #: The stem of the file of the values (``<NAME>.json``) when a report writes the result.
    NAME: ClassVar[str] = "result"

    @classmethod
    def table_names(cls) -> tuple[str, ...]:
        """Every table a result of this type can hold (known before the job runs, so that a
        report can declare its files): the keys of :attr:`SCHEMAS`."""
        return tuple(cls.SCHEMAS)

    def tables(self) -> Mapping[str, tuple[pd.DataFrame, TableSchema | None]]:
        """The tables of the result: field name -> (DataFrame, schema), in declaration order."""
        return MappingProxyType(
            {name: (getattr(self, name), schema) for name, schema in self.SCHEMAS.items()}
        )

    def summary_tables(self) -> Mapping[str, tuple[pd.DataFrame, TableSchema | None]]:
        """Tables that summarise :meth:`values` (Table 1 of a QCM analysis), for the formats
        that hold a whole result in one file (``xlsx``, ``netcdf``); a results folder has them
        in its JSON record. None by default."""
        return MappingProxyType({})

    def values(self) -> dict[str, Any]:
        """The fields that are neither tables nor :attr:`NOT_VALUES`, as JSON-able data
        (:func:`json_value`), in declaration order."""
        return {
            f.name: json_value(getattr(self, f.name))
            for f in dataclasses.fields(self)  # type: ignore[arg-type]
            if f.name not in self.SCHEMAS and f.name not in self.NOT_VALUES
        }

    def input_files(self) -> tuple[str, ...]:
        """The files the result was computed from, which a report of it must never overwrite
        (none known here: a job whose Result knows its input says it)."""
        return ()
