"""Tables of measured resonances: contact-resonance AFM and the resonance ultrasound microscope.

One row per point or map pixel; SI units, the unit in every column name; a blank cell means "not
given" (a mode that was not measured, a tip position to be solved from two modes). The schemas
(:data:`AFM_TABLE`, :data:`RUM_TABLE`, defined in :mod:`contactres.measurements.schema` and
re-exported here) are the one source of the names, units and rules: the reader runs their rules
and the README's column tables are generated from them. Columns that
are not in the schema are carried through to the output unchanged (point labels, pixel
coordinates), except a name that looks like a misspelling of a schema column the table lacks
(``fc1_hz``, ``tip_radius``: :meth:`~contactres.measurements.schema.TableSchema.check_names`):
that is taken for a typo and refused.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ContactresInputError
from ._array_table import ArrayTable
from ._messages import at_cell, where_rows
from .readers import RESONANCE_READERS
from .schema import AFM_TABLE, RUM_TABLE, Rule, TableSchema

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["AFM_TABLE", "RUM_TABLE", "Rule", "read_resonance_table", "validate_resonance_table"]


def _numbers(raw: pd.DataFrame | ArrayTable, col: str, source: str, decimal: str) -> np.ndarray:
    """The cells of ``col`` as floats; blank cells are NaN (not given), text is an error.

    The column is parsed whole by pandas' ``to_numeric``, which skips ASCII white space around
    a number itself; only the cells it leaves unread (blank with spaces, other white space,
    text) are stripped and read again: no Python call per cell for a column of numbers (issue
    31: stripping every cell first cost ~40 % of the reading). A column of numbers (a binary
    table's) is taken as it is."""
    if raw[col].dtype.kind in "fiu":  # a binary table's numbers (.npz): NaN is not given
        # An archive's arrays are this reading's own: taken as they are, where a DataFrame's
        # column is copied (a 512² map's copies were a tenth of its reading).
        values = (
            np.asarray(raw[col], dtype=float)
            if isinstance(raw, ArrayTable)
            else np.array(raw[col], dtype=float)
        )
        if np.isinf(values).any():
            bad = np.isinf(values)
            raise ContactresInputError(f"{at_cell(raw, source, bad, col)} is not a finite number")
        return values
    import pandas as pd  # text to read (a CSV's cells, an archive's text column)

    cells = raw[col]
    if isinstance(raw, ArrayTable):  # an archive's text column, where numbers are expected
        cells = pd.Series(cells, dtype=object)
    s = cells.astype(str)
    if decimal == ",":
        s = s.str.replace(",", ".", regex=False)
    values = pd.to_numeric(s, errors="coerce").to_numpy(dtype=float, copy=True)
    given = (s != "").to_numpy(dtype=bool, copy=True)
    again = np.flatnonzero(np.isnan(values) & given)
    if again.size:
        text = s.iloc[again].str.strip()
        values[again] = pd.to_numeric(text, errors="coerce").to_numpy(dtype=float)
        given[again] = (text != "").to_numpy()
    bad = (np.isnan(values) & given) | np.isinf(values)
    if bad.any():
        raise ContactresInputError(f"{at_cell(raw, source, bad, col)} is not a finite number")
    return values


def validate_resonance_table(raw, schema: TableSchema, source: str):
    """Check a raw table (string cells, a ``line`` column) against ``schema``.

    Returns the table with the schema's columns as floats (NaN where blank or absent), the other
    columns unchanged, and ``line``, of the raw table's type (a DataFrame, or the
    :class:`~contactres.measurements.ArrayTable` of a numpy archive). Raises ValueError naming
    file, line, column, value and rule.
    """
    schema.check_names(raw.columns, source)
    missing = [c for c in schema.required if c not in raw.columns]
    if missing:
        raise ContactresInputError(f"{source}: required column(s) missing: {', '.join(missing)}")
    if len(raw) == 0:
        raise ContactresInputError(f"{source}: no data rows after the header")
    decimal = raw.attrs.get("decimal", ".")
    out = raw.copy(deep=not isinstance(raw, ArrayTable))  # the archive's arrays: not copied
    # The columns as given (the output keeps these, not the schema's absent ones).
    out.attrs["given"] = [c for c in raw.columns if c != "line"]
    for c in schema.columns:
        if c.name not in raw.columns:
            # One value: each table makes it a writable column of its own (ArrayTable too).
            out[c.name] = np.nan
            continue
        v = _numbers(raw, c.name, source, decimal)
        given = ~np.isnan(v)
        if c.required and not given.all():
            raise ContactresInputError(
                f"{where_rows(raw, source, ~given, c.name)}: is empty (required)"
            )
        schema.check_cells(raw, source, c.name, v, given)
        out[c.name] = v
    return out


def read_resonance_table(path, schema: TableSchema, *, readers=None, arrays: bool = False):
    """Read and check a table of resonances (:data:`AFM_TABLE` or :data:`RUM_TABLE`).

    The file (CSV: comma, semicolon or tab separated; a numpy archive, ``.npz``) is never
    modified; ``readers`` is the registry its reader is picked from (kind ``resonances``;
    default :data:`~contactres.measurements.readers.RESONANCE_READERS`, the readers of this
    kind of :data:`~contactres.measurements.readers.BUILT_IN`, without importing the others). See
    :func:`validate_resonance_table` for what is returned and checked: a
    :class:`pandas.DataFrame`, or with ``arrays`` an
    :class:`~contactres.measurements.ArrayTable` (numpy columns: a numpy archive is then read
    and checked without pandas, issue 31).
    """
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{p}: no such file")
    if p.is_dir():
        raise ContactresInputError(f"{p}: is a directory, expected a table file")
    raw = (RESONANCE_READERS if readers is None else readers).pick(p, "resonances").load(p)
    # A workbook's reader names its sheet too ("book.xlsx, sheet 'resonances'").
    if arrays and not isinstance(raw, ArrayTable):
        raw = ArrayTable.from_frame(raw)
    elif not arrays and isinstance(raw, ArrayTable):  # a reader's numpy columns, as a DataFrame
        raw = raw.to_frame()
    return validate_resonance_table(raw, schema, str(raw.attrs.get("source", p)))
