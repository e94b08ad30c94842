"""Write the maps of a contact-resonance map (``contactres afm map``, and the demo's CR map): the
report of the ``afm_map`` job's Result and its map Dataset, into one folder.

:func:`write_afm_map` writes ``afm_map.json`` (the conventions and the summary), the figures
registered for the Result (``afm_maps.png``, ``afm_histograms.png``:
:func:`contactres.report.figure_registry`) and the Dataset: NetCDF (``NAME.nc``, one file of
the folder's result set, written whole or not at all) or Zarr (``NAME.zarr``, a store written
beside the report with :func:`contactres.polycrystal.write_map`, replaced as a whole, and only
if contactres wrote it). :func:`check_afm_map_output` makes the checks before the long work.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ContactresInputError

if TYPE_CHECKING:
    import os

    from ..fileio import ResultSet
    from ..jobs.afm_map import Result

__all__ = ["MAP_SUFFIXES", "check_afm_map_output", "write_afm_map"]

#: The formats of the map Dataset, by suffix.
MAP_SUFFIXES = (".nc", ".zarr")


def _map_name(name: str) -> str:
    name = str(name)
    if Path(name).name != name or Path(name).suffix.lower() not in MAP_SUFFIXES:
        raise ContactresInputError(
            f"the map's file name must be a plain name ending in .nc (NetCDF) or .zarr (Zarr), "
            f"got {name!r}"
        )
    return name


def _result_set(folder: str | os.PathLike, name: str, formats, inputs) -> ResultSet:
    """The folder's result set: the report (``formats``: None for the report's default) and a
    NetCDF map Dataset (a Zarr store ``name`` is written beside it, not in the set)."""
    from ..fileio import ResultSet
    from ..jobs.afm_map import Result
    from ..report import FORMATS, report_names

    chosen = {} if formats is None else {"formats": tuple(formats)}  # else the report's default
    extra = (name,) if name.lower().endswith(".nc") else ()
    names = (*report_names(Result, **chosen), *extra)
    owned = (*report_names(Result, FORMATS), *extra)
    return ResultSet(folder, names=names, inputs=inputs, owned=owned, kind="afm_map")


def check_afm_map_output(
    folder: str | os.PathLike,
    *,
    map_name: str = "afm_map.nc",
    formats=None,
    inputs=(),
) -> None:
    """Check, writing nothing, that :func:`write_afm_map` may write into ``folder`` (before the
    long work): the folder's result set (:meth:`contactres.fileio.ResultSet.check`) and a Zarr
    map store ``map_name`` in it (:func:`contactres.polycrystal.check_map_output`).

    Parameters
    ----------
    folder : path
        The results folder.
    map_name, formats
        As for :func:`write_afm_map`.
    inputs : sequence of path
        The input files of the run (none of the outputs may be one of them).

    Raises
    ------
    contactres.fileio.OutputError
        One line naming the folder (or the store) and the reason; nothing was changed.
    """
    name = _map_name(map_name)
    _result_set(folder, name, formats, inputs).check()
    if name.lower().endswith(".zarr") and Path(folder).is_dir():  # else no store is there yet
        from ..polycrystal import check_map_output

        check_map_output(Path(folder) / name, inputs)


def write_afm_map(
    result: Result,
    folder: str | os.PathLike,
    *,
    map_name: str = "afm_map.nc",
    formats=None,
    progress=None,
) -> list[Path]:
    """Write the report and the map Dataset of ``result`` into ``folder``; return the paths.

    Parameters
    ----------
    result : contactres.jobs.afm_map.Result
    folder : path
        The results folder (created if missing).
    map_name : str
        The Dataset's file name: ``*.nc`` (NetCDF) or ``*.zarr`` (a Zarr store).
    formats : sequence of str, optional
        Of the report (default :data:`contactres.report.DEFAULT_FORMATS`).
    progress : callable, optional
        One line per figure drawn.

    Raises
    ------
    contactres.fileio.OutputError
        As :func:`check_afm_map_output`; a Zarr store that contactres may not replace is
        refused before the report moves in (issue 27).
    """
    from ..report import write_report

    name = _map_name(map_name)
    chosen = {} if formats is None else {"formats": tuple(formats)}  # else the report's default
    netcdf = name.lower().endswith(".nc")
    if not netcdf:  # a store contactres may not replace refuses the run before the report moves
        from ..polycrystal import check_map_output, write_map

        if Path(folder).is_dir():
            check_map_output(Path(folder) / name, result.input_files())
    with _result_set(folder, name, formats, result.input_files()) as rs:
        written = write_report(result, rs, progress=progress, **chosen)
        if netcdf:
            result.dataset.to_netcdf(rs.path(name))  # type: ignore[attr-defined]  # a Dataset
            written.append(rs.final(name))
    if not netcdf:
        written.append(write_map(Path(folder) / name, result.dataset))
    return written
