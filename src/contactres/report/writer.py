"""Write any job's Result into a folder: :func:`write_report`.

A :class:`contactres.jobs.contract.JobResult` carries its tables (each with its schema) and its
values; this module writes them the same way for every job, as one
:class:`contactres.fileio.ResultSet` (whole or not at all):

* each table as ``<table>.csv`` (15 significant digits, :data:`contactres.fileio.CSV_FLOAT_FORMAT`);
* the values as ``<NAME>.json`` (``Result.NAME``; UTF-8, one space of indent);
* the figures registered for the Result's type (:func:`figure_registry`) as PNG.

The QCM sweep analysis (:class:`contactres.analysis.Results`, what :func:`contactres.analyze`
returns) keeps its own folder layout (tables, summary, the paper's figures): its Results go to
:func:`contactres.report.tables.write_report`, so ``contactres.write_report(results, folder)``
works as it always has.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from ..errors import ContactresInputError
from ..fileio import CSV_FLOAT_FORMAT, ResultSet, save_figure, write_csv, write_text
from ..jobs.contract import JobResult
from . import tables as qcm_tables

if TYPE_CHECKING:
    import os

    from ..jobs.contract import Progress

__all__ = ["FORMATS", "figure_registry", "report_names", "write_report"]

#: What a report can hold: the tables (CSV), the values (JSON) and the figures (PNG).
FORMATS = ("csv", "json", "png")

#: A drawing function: the Result -> a matplotlib Figure.
Drawing = Callable[[JobResult], object]


def figure_registry() -> Mapping[type, tuple[tuple[str, Drawing], ...]]:
    """Result type -> its figures, as (file name, drawing function) pairs, in order.

    Built on each call (an immutable mapping; nothing is kept between calls). A job whose
    Result has figures adds its line here; the drawing functions live in the report package
    (they need matplotlib, which the jobs never import).
    """
    from ..jobs import qcm_stiffness
    from .job_figures import stiffness_figure

    return MappingProxyType({qcm_stiffness.Result: (("stiffness.png", stiffness_figure),)})


def _formats(formats) -> tuple[str, ...]:
    chosen = (formats,) if isinstance(formats, str) else tuple(formats)
    unknown = [f for f in chosen if f not in FORMATS]
    if unknown:
        raise ContactresInputError(f"unknown report format(s) {unknown}: choose from {FORMATS}")
    return chosen


def report_names(kind: type[JobResult], formats=FORMATS) -> tuple[str, ...]:
    """The files a report of a Result of type ``kind`` holds (to declare a ResultSet before the
    job runs): ``<table>.csv`` each, ``<NAME>.json``, the registered figures."""
    formats = _formats(formats)
    names: list[str] = []
    if "csv" in formats:
        names += [f"{name}.csv" for name in kind.SCHEMAS]
    if "json" in formats:
        names.append(f"{kind.NAME}.json")
    if "png" in formats:
        names += [name for name, _ in figure_registry().get(kind, ())]
    return tuple(names)


def write_report(
    result,
    folder: str | os.PathLike | ResultSet,
    formats=FORMATS,
    *,
    inputs=None,
    progress: Progress | None = None,
) -> list[Path]:
    """Write ``result`` into ``folder``; return the paths written (where they are once in place).

    Parameters
    ----------
    result : JobResult or contactres.analysis.Results
        A job's Result, or the QCM sweep analysis (:class:`contactres.analysis.Results` or the
        ``qcm_sweeps`` job's Result: written by :func:`contactres.report.tables.write_report`,
        its own layout).
    folder : path or ResultSet
        The results folder (created if missing), or a :class:`~contactres.fileio.ResultSet`
        the caller opened (declared with :func:`report_names`), which moves the files into
        place when its block ends.
    formats : str or sequence of str
        Among :data:`FORMATS`.
    inputs : sequence of paths, optional
        Files that must not be overwritten (ignored when ``folder`` is a ResultSet).
    progress : callable, optional
        Gets one line per figure drawn.

    Raises
    ------
    contactres.fileio.OutputError
        Before anything is written: the folder cannot be written, a file of the set is one of
        ``inputs``, or another run is writing into the folder.
    """
    from ..analysis import Results
    from ..jobs.qcm_sweeps import Result as SweepsResult

    if isinstance(result, SweepsResult):  # the job's Result carries the analysis's
        result = result.analysis
    if isinstance(result, Results):
        return qcm_tables.write_report(result, folder, formats, inputs=inputs)
    if not isinstance(result, JobResult):
        raise ContactresInputError(
            f"write_report writes a job's Result or analysis Results, got {type(result).__name__}"
        )
    formats = _formats(formats)
    if isinstance(folder, ResultSet):
        return _write_into(result, folder, formats, progress)
    names = report_names(type(result), formats)
    with ResultSet(folder, names=names, inputs=inputs or ()) as rs:
        return _write_into(result, rs, formats, progress)


def _write_into(result: JobResult, rs: ResultSet, formats, progress) -> list[Path]:
    names: list[str] = []
    if "csv" in formats:
        for name, (frame, _schema) in result.tables().items():
            write_csv(rs.path(f"{name}.csv"), frame, float_format=CSV_FLOAT_FORMAT)
            names.append(f"{name}.csv")
    if "json" in formats:
        text = json.dumps(result.values(), indent=1, ensure_ascii=False, allow_nan=False)
        write_text(rs.path(f"{result.NAME}.json"), text + "\n")
        names.append(f"{result.NAME}.json")
    if "png" in formats:
        for name, draw in figure_registry().get(type(result), ()):
            if progress is not None:
                progress(f"figure {name}")
            save_figure(rs.path(name), draw(result))
            names.append(name)
    return [rs.final(name) for name in names]
