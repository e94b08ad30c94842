"""Write any job's Result into a folder: :func:`write_report`.

A :class:`contactres.jobs.contract.JobResult` carries its tables (each with its schema) and its
values; this module writes them the same way for every job, as one
:class:`contactres.fileio.ResultSet` (whole or not at all), in the formats asked for:

* ``csv``: each table as ``<table>.csv`` (15 significant digits,
  :data:`contactres.fileio.CSV_FLOAT_FORMAT`);
* ``json``: the values as ``<NAME>.json`` (``Result.NAME``; UTF-8, one space of indent);
* ``png``, ``svg``, ``pdf``: the figures registered for the Result's type
  (:func:`figure_registry`), each drawn once and saved in every figure format asked for (the
  registered ``<figure>.png`` with its suffix changed; :data:`FIGURE_FORMATS`);
* ``html``: the page registered for the Result's type (:func:`html_registry`), one
  self-contained HTML file (its figures are embedded as PNG, whatever the figure formats);
* ``xlsx``: the tables and the conventions as one Excel workbook ``results.xlsx``;
  ``netcdf``: the tables as one NetCDF 3 file ``results.nc``
  (:mod:`contactres.report._workbook`; extras ``excel`` and ``maps``).

Unless told otherwise a report holds :data:`DEFAULT_FORMATS` (a page is written when asked for).

The QCM sweep analysis is reported as every job is: the ``qcm_sweeps`` job's Result
(:class:`contactres.jobs.qcm_sweeps.Result`) gives the tables and the summary record of its
results folder, and registers the figures of paper 2 and ``report.html`` here. The analysis
Results that :func:`contactres.analyze` returns are written as the job's Result that carries
them, so ``contactres.write_report(results, folder)`` writes the folder described in
:mod:`contactres.report._tables`.

Map stores are not written here: ``maps synthetic|predict`` write a Zarr store with
:func:`contactres.polycrystal.write_map`. A store is itself the output the user names (not
a file inside a results folder), a tree of chunk files whose chunking is a choice of the writing
(``--chunks``), replaced as a whole (in one step where the system can); a report is a folder
of named files, each digested in its ``manifest.json``, that a
:class:`~contactres.fileio.ResultSet` moves in.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from .._csvcells import unique_written
from ..errors import ContactresInputError
from ..fileio import (
    CSV_FLOAT_FORMAT,
    ResultSet,
    save_figure,
    write_bytes,
    write_csv,
    write_text,
)
from ..jobs.contract import JobResult
from ._workbook import EXPORT_FILES, netcdf_bytes, require, workbook_bytes

if TYPE_CHECKING:
    import os

    from ..jobs.contract import Progress

__all__ = [
    "DEFAULT_FORMATS",
    "FIGURE_FORMATS",
    "FORMATS",
    "figure_registry",
    "html_registry",
    "report_names",
    "report_set",
    "write_report",
]

#: What a report can hold: the tables (CSV), the values (JSON), the figures (PNG, SVG, PDF),
#: the page, and the tables as one workbook (xlsx) or one NetCDF file.
FORMATS = ("csv", "json", "png", "svg", "pdf", "html", "xlsx", "netcdf")
#: The formats of :data:`FORMATS` that are figure formats (matplotlib's names and suffixes).
FIGURE_FORMATS = ("png", "svg", "pdf")
#: What a report holds unless told otherwise.
DEFAULT_FORMATS = ("csv", "json", "png")

#: A drawing function: the Result -> a matplotlib Figure, or None (nothing to draw: no file).
Drawing = Callable[[Any], object]
#: A page function: the Result -> the text of one self-contained HTML page.
Page = Callable[[Any], str]


def figure_registry() -> Mapping[type, tuple[tuple[str, Drawing], ...]]:
    """Result type -> its figures, as (file name, drawing function) pairs, in order.

    Built on each call (an immutable mapping; nothing is kept between calls). A job whose
    Result has figures adds its line here; the drawing functions live in the report package
    (they need matplotlib, which the jobs never import).
    """
    from ..jobs import afm_map, maps_predict, qcm_particles, qcm_stiffness, qcm_sweeps
    from . import _job_figures as draw
    from . import _particle_figures as particles
    from ._cr_map_figures import cr_histograms_figure, cr_maps_figure
    from .figures import FIGURE_FILES, RADIATION_FIGURE

    paper2 = (draw.sweeps_figure, draw.load_figure, draw.dissipation_figure, draw.friction_figure)
    return MappingProxyType(
        {
            afm_map.Result: (
                ("afm_maps.png", cr_maps_figure),
                ("afm_histograms.png", cr_histograms_figure),
            ),
            maps_predict.Result: (("M_map.png", draw.prediction_if_legend),),
            qcm_particles.Result: (
                ("particles_overtones.png", particles.overtones_figure),
                ("particles_plane.png", particles.plane_figure),
                ("particles_time.png", particles.time_figure),
            ),
            qcm_stiffness.Result: (("stiffness.png", draw.stiffness_figure),),
            qcm_sweeps.Result: (
                *zip(FIGURE_FILES, paper2, strict=True),
                (RADIATION_FIGURE, draw.radiation_figure),
            ),
        }
    )


def html_registry() -> Mapping[type, tuple[str, Page]]:
    """Result type -> its page, as (file name, page function); written for the format ``html``.

    Built on each call, as :func:`figure_registry`. A job without a page of its own registers
    the generic one (:func:`contactres.report._job_page.job_page`: values, flags, the tables'
    first rows, the figures).
    """
    from ..jobs import afm_map, qcm_particles, qcm_sweeps
    from ._job_page import JOB_PAGE_FILE, job_page

    def generic(result) -> str:
        # The generic page embeds the figures registered for the Result's type.
        return job_page(result, figure_registry().get(type(result), ()))

    def sweeps(result) -> str:
        # Imported when a page is written: the sweep page's tables import the analysis (and
        # scipy.stats), which every report's list of names (report_names) need not pay.
        from ._html import sweeps_page

        return sweeps_page(result)

    return MappingProxyType(
        {
            afm_map.Result: (JOB_PAGE_FILE, generic),
            qcm_sweeps.Result: (JOB_PAGE_FILE, sweeps),  # report.html, as _html.HTML_FILE
            qcm_particles.Result: (JOB_PAGE_FILE, generic),
        }
    )


def _formats(formats) -> tuple[str, ...]:
    chosen = (formats,) if isinstance(formats, str) else tuple(formats)
    unknown = [f for f in chosen if f not in FORMATS]
    if unknown:
        raise ContactresInputError(f"unknown report format(s) {unknown}: choose from {FORMATS}")
    return chosen


def _figure_name(name: str, fmt: str) -> str:
    """The registered figure ``name`` (``x.png``) as the file of figure format ``fmt``."""
    return f"{Path(name).stem}.{fmt}"


def _job_result(result) -> JobResult:
    """``result`` as a job's Result: the analysis Results of :func:`contactres.analyze` as the
    ``qcm_sweeps`` job's Result that carries them
    (:meth:`~contactres.jobs.qcm_sweeps.Result.of`)."""
    from ..analysis import Results
    from ..jobs import qcm_sweeps

    if isinstance(result, Results):
        return qcm_sweeps.Result.of(result)
    if not isinstance(result, JobResult):
        raise TypeError(
            f"write_report writes a job's Result or analysis Results, got {type(result).__name__}"
        )
    return result


def report_names(kind: type[JobResult], formats=DEFAULT_FORMATS) -> tuple[str, ...]:
    """The files a report of a Result of type ``kind`` can hold (to declare a ResultSet before
    the job runs): ``<table>.csv`` for each of its tables, ``<NAME>.json``, the registered
    figures and page. A Result may write fewer (a table or a figure it does not have)."""
    formats = _formats(formats)
    names: list[str] = []
    if "csv" in formats:
        names += [f"{name}.csv" for name in kind.table_names()]
    if "json" in formats:
        names.append(f"{kind.NAME}.json")
    for fmt in (f for f in FIGURE_FORMATS if f in formats):
        names += [_figure_name(name, fmt) for name, _ in figure_registry().get(kind, ())]
    if "html" in formats:
        page = html_registry().get(kind)
        names += [] if page is None else [page[0]]
    names += [EXPORT_FILES[f] for f in EXPORT_FILES if f in formats]
    return tuple(names)


def report_set(
    kind: type[JobResult],
    folder: str | os.PathLike,
    formats=DEFAULT_FORMATS,
    *,
    inputs=(),
) -> ResultSet:
    """The :class:`~contactres.fileio.ResultSet` of a report of a Result of type ``kind`` in
    ``folder``: declared with :func:`report_names` for ``formats``; it owns every file such a
    report can hold in any format, so those an earlier report wrote and this one does not are
    removed when it is moved into place. ``inputs``: files it must not overwrite.
    MissingExtraError, before anything is written, when a format needs an extra that is not
    installed (``xlsx``: ``excel``; ``netcdf``: ``maps``)."""
    names = report_names(kind, formats)
    require(_formats(formats))
    # The kind of set is the job's name (its module's): a folder of another job's results is
    # refused, never mixed with or removed by this one.
    job = kind.__module__.rsplit(".", 1)[-1]
    return ResultSet(
        folder, names=names, inputs=inputs, owned=report_names(kind, FORMATS), kind=job
    )


def write_report(
    result,
    folder: str | os.PathLike | ResultSet,
    formats=DEFAULT_FORMATS,
    *,
    inputs=None,
    progress: Progress | None = None,
) -> list[Path]:
    """Write ``result`` into ``folder``; return the paths written (where they are once in place).

    Parameters
    ----------
    result : JobResult or contactres.analysis.Results
        A job's Result, or the QCM sweep analysis (what :func:`contactres.analyze` returns,
        written as the ``qcm_sweeps`` job's Result).
    folder : path or ResultSet
        The results folder (created if missing), or a :class:`~contactres.fileio.ResultSet`
        the caller opened (:func:`report_set`), which moves the files into place when its
        block ends.
    formats : str or sequence of str
        Among :data:`FORMATS` (default :data:`DEFAULT_FORMATS`).
    inputs : sequence of paths, optional
        Files that must not be overwritten (default: the Result's
        :meth:`~contactres.jobs.contract.JobResult.input_files`); ignored when ``folder`` is a
        ResultSet (it was given its inputs).
    progress : callable, optional
        Gets one line per figure drawn.

    Raises
    ------
    contactres.fileio.OutputError
        Before anything is written: the folder cannot be written, a file of the set is one of
        ``inputs``, or another run is writing into the folder.
    """
    result = _job_result(result)
    formats = _formats(formats)
    require(formats)
    if isinstance(folder, ResultSet):
        return _write_into(result, folder, formats, progress)
    inputs = result.input_files() if inputs is None else inputs
    with report_set(type(result), folder, formats, inputs=inputs) as rs:
        return _write_into(result, rs, formats, progress)


def _write_into(result: JobResult, rs: ResultSet, formats, progress) -> list[Path]:
    # A table of the Result with a column name twice is a fault of the job that built it
    # (a user's table with one is refused where it is read): said for every format before
    # anything is written, naming the table.
    # (the summary tables of the workbook and the NetCDF file are checked where they are made)
    for name, (frame, _schema) in result.tables().items():
        unique_written(frame, f"table {name!r} of the {result.NAME} result")
    names: list[str] = []
    if "csv" in formats:
        for name, (frame, _schema) in result.tables().items():
            write_csv(rs.path(f"{name}.csv"), frame, float_format=CSV_FLOAT_FORMAT)
            names.append(f"{name}.csv")
    if "json" in formats:
        text = json.dumps(result.values(), indent=1, ensure_ascii=False, allow_nan=False)
        write_text(rs.path(f"{result.NAME}.json"), text + "\n")
        names.append(f"{result.NAME}.json")
    figure_formats = [f for f in FIGURE_FORMATS if f in formats]
    for name, draw in figure_registry().get(type(result), ()) if figure_formats else ():
        if progress is not None:
            progress(f"figure {name}")
        figure = draw(result)
        if figure is None:  # None: this Result has nothing to draw there
            continue
        for i, fmt in enumerate(figure_formats):  # drawn once, saved in each format
            file = _figure_name(name, fmt)
            save_figure(rs.path(file), figure, close=i == len(figure_formats) - 1)
            names.append(file)
    if "html" in formats and (page := html_registry().get(type(result))) is not None:
        name, make = page
        write_text(rs.path(name), make(result))
        names.append(name)
    for fmt, make_bytes in (("xlsx", workbook_bytes), ("netcdf", netcdf_bytes)):
        if fmt in formats:
            write_bytes(rs.path(EXPORT_FILES[fmt]), make_bytes(result))
            names.append(EXPORT_FILES[fmt])
    return [rs.final(name) for name in names]
