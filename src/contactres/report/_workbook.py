"""A job's Result as one file: an Excel workbook (``xlsx``) or a NetCDF file (``netcdf``).

The CSV files of a report are the reference; these two hold the same tables for the tools that
prefer one file:

* :func:`workbook_bytes`: an Office Open XML workbook (written by pandas with openpyxl, the
  ``excel`` extra), one sheet per table under the table's name, the cells as the CSV has them
  (text cells a spreadsheet would run as formulas prefixed by an apostrophe, as
  :func:`contactres.fileio.neutralised` does for the CSV, so that they stay text), then one
  sheet per summary table of the Result (``summary_tables``: a QCM analysis' ``table1``, E and
  γ with their errors per fitted group), and a last sheet ``conventions``: the Result's
  conventions and settings as (name, value) rows;
* :func:`netcdf_bytes`: a NetCDF 3 file (64-bit offset format, written by xarray with scipy's
  NetCDF writer: no netCDF4 library is needed; the ``maps`` extra brings xarray), one variable
  ``<table>.<column>`` per column along the dimension ``<table>_row`` (Table 1's along
  ``group``: ``table1.E_Pa``, ...), with the column's unit (``units``) and meaning
  (``long_name``) from its schema, and the Result's values as JSON text in the global attribute
  ``values_json`` (``conventions_json``: its conventions alone).

Both return the bytes of the file, which the caller writes atomically into its result set.
A missing extra raises :class:`contactres.errors.MissingExtraError` (:func:`require`), checked
before a job runs.
"""

from __future__ import annotations

import io
import json
from typing import TYPE_CHECKING, Any

from .._csvcells import unique_written
from ..errors import MissingExtraError
from ..fileio import neutralised

if TYPE_CHECKING:
    from ..jobs.contract import JobResult

__all__ = ["EXPORT_FILES", "netcdf_bytes", "require", "workbook_bytes"]

#: Report format -> the file it writes into a results folder.
EXPORT_FILES = {"xlsx": "results.xlsx", "netcdf": "results.nc"}

#: Report format -> (module it needs, the extra that brings it).
_NEEDS = {"xlsx": ("openpyxl", "excel"), "netcdf": ("xarray", "maps")}

#: The name of the workbook's sheet of conventions (a table of that name would be renamed).
CONVENTIONS_SHEET = "conventions"

#: Longest sheet name Excel accepts.
_SHEET_CHARS = 31


def require(formats) -> None:
    """MissingExtraError (one line, naming the extra) if a format of ``formats`` needs a package
    that is not installed: ``xlsx`` openpyxl (extra ``excel``), ``netcdf`` xarray (``maps``)."""
    import importlib.util

    for fmt in formats:
        if fmt in _NEEDS:
            module, extra = _NEEDS[fmt]
            if importlib.util.find_spec(module) is None:
                raise MissingExtraError(
                    f"{module} is needed to write {EXPORT_FILES[fmt]}; install the optional "
                    f"extra: pip install 'contactres[{extra}]'"
                )


def _flat(record: Any, prefix: str = "") -> list[tuple[str, Any]]:
    """(dotted name, value) rows of a nested record; a list is one row of JSON text."""
    if isinstance(record, dict):
        rows: list[tuple[str, Any]] = []
        for key, value in record.items():
            rows += _flat(value, f"{prefix}.{key}" if prefix else str(key))
        return rows
    if isinstance(record, list):
        return [(prefix, json.dumps(record, ensure_ascii=False))]
    return [(prefix, record)]


def conventions_table(result: JobResult):
    """The workbook's ``conventions`` sheet: (name, value) rows of the Result's ``conventions``
    and ``settings`` values (those it has), then the contactres version."""
    import pandas as pd

    from .._version import __version__

    values = result.values()
    rows = []
    for key in ("conventions", "settings"):
        if isinstance(values.get(key), dict):
            rows += _flat(values[key], key)
    rows.append(("contactres_version", __version__))
    # Values of mixed types as text, as the CSV would show them (one column, one type).
    frame = pd.DataFrame(rows, columns=["name", "value"])
    frame["value"] = ["" if v is None else str(v) for v in frame["value"]]
    return frame


def _sheet_names(names) -> dict[str, str]:
    """Table name -> its sheet name: at most 31 characters, unique, never ``conventions``."""
    out: dict[str, str] = {}
    for name in names:
        sheet, n = name[:_SHEET_CHARS], 1
        while sheet in out.values() or sheet == CONVENTIONS_SHEET:
            n += 1
            sheet = f"{name[: _SHEET_CHARS - len(str(n)) - 1]}_{n}"
        out[name] = sheet
    return out


def workbook_bytes(result: JobResult) -> bytes:
    """The Result's tables and conventions as the bytes of an ``.xlsx`` workbook.

    One sheet per table (header row, no index), text cells neutralised as in the CSV
    (:func:`contactres.fileio.neutralised`: a label starting with ``= + - @`` is written with a
    leading apostrophe, so no spreadsheet runs it), infinities as ``inf``/``-inf`` text as the
    CSV writes them, missing values as empty cells; then the sheet ``conventions``
    (:func:`conventions_table`).
    """
    import pandas as pd

    require(("xlsx",))
    tables = result.tables()
    sheets = _sheet_names(tables)
    buffer = io.BytesIO()
    with pd.ExcelWriter(buffer, engine="openpyxl") as writer:
        for name, (frame, _schema) in tables.items():
            _cells(frame).to_excel(writer, sheet_name=sheets[name], index=False)
        # The summary tables (a QCM analysis' Table 1) before the conventions: the numbers a
        # reader opens the workbook for (issue 30: the sheets held no E or γ).
        summary = _summary_tables(result)
        names = _sheet_names([*tables, *summary])
        for name, (frame, _schema) in summary.items():
            _cells(frame).to_excel(writer, sheet_name=names[name], index=False)
        _cells(conventions_table(result)).to_excel(
            writer, sheet_name=CONVENTIONS_SHEET, index=False
        )
    return buffer.getvalue()


def _summary_tables(result: JobResult):
    """The Result's summary tables (``summary_tables``; none for a Result without them)."""
    method = getattr(result, "summary_tables", None)
    return {} if method is None else dict(method())


def _cells(frame):
    """``frame`` as the workbook's cells: text neutralised as in the CSV, and the control
    characters an xlsx file cannot hold (all below U+0020 but tab, line feed and carriage
    return) shown as U+FFFD, the replacement character (openpyxl refuses them). The caller's
    frame is never changed."""
    from openpyxl.cell.cell import ILLEGAL_CHARACTERS_RE

    def legal(v):
        return ILLEGAL_CHARACTERS_RE.sub("\ufffd", v) if isinstance(v, str) else v

    out = neutralised(frame)
    text = [c for c in out.columns if out[c].dtype.kind == "O" or str(out[c].dtype) == "str"]
    changed = {c: col for c in text if not (col := out[c].map(legal)).equals(out[c])}
    return out.assign(**changed) if changed else out


def _column_values(series):
    """A column as an array NetCDF 3 can hold: text as str (missing: empty), numbers as they
    are (bool is encoded by xarray as int8 and decoded back)."""
    import numpy as np

    if series.dtype.kind == "O" or str(series.dtype) in ("str", "string"):
        return np.array(["" if v is None or v != v else str(v) for v in series], dtype=str)
    # Integers: xarray stores them as NetCDF 3's 32-bit integers (refusing any that do not fit).
    return series.to_numpy()


def results_dataset(result: JobResult):
    """The Result as an :class:`xarray.Dataset`: one variable ``<table>.<column>`` per column
    along the dimension ``<table>_row``; units and meanings from the tables' schemas; the
    values as JSON text in the attributes ``values_json`` and ``conventions_json``."""
    import xarray as xr

    from .._version import __version__

    variables = {}
    summary = _summary_tables(result)
    for name, (frame, schema) in {**result.tables(), **summary}.items():
        # (a column twice would be one variable: the other column lost without a word)
        unique_written(frame, f"table {name!r} of the {result.NAME} result")
        known = {} if schema is None else {c.name: c for c in schema.columns}
        # A summary table's rows are the fitted groups (Table 1): the dimension ``group``.
        dim = "group" if name == "table1" else f"{name}_row"
        for column in frame.columns:
            attrs = {}
            if column in known:
                unit = known[column].unit
                attrs["long_name"] = known[column].meaning
                if unit not in ("text", ""):
                    attrs["units"] = "1" if unit == "-" else unit
            variables[f"{name}.{column}"] = xr.Variable(
                (dim,), _column_values(frame[column]), attrs
            )
    values = result.values()
    attrs = {
        "title": f"contactres {type(result).__module__.rsplit('.', 1)[-1]} results",
        "source": f"contactres {__version__}",
        "values_json": json.dumps(values, ensure_ascii=False, allow_nan=False),
        "conventions_json": json.dumps(values.get("conventions"), ensure_ascii=False),
    }
    return xr.Dataset(variables, attrs=attrs)


def netcdf_bytes(result: JobResult) -> bytes:
    """The Result as the bytes of a NetCDF 3 file (:func:`results_dataset`, written by xarray's
    ``scipy`` engine, which needs no netCDF4 library)."""
    require(("netcdf",))
    data = results_dataset(result).to_netcdf(engine="scipy")
    return bytes(data)  # xarray returns a memoryview or bytes, by version
