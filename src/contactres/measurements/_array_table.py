"""A table held as numpy columns, for the binary path of the resonance tables.

A numpy archive (``.npz``) read, checked, inverted and written again by ``afm invert`` needs no
pandas: its columns are arrays from the file to the file, and pandas' import alone was a third
of the CPU time of a 512² map (issue 31, point 5). :class:`ArrayTable` holds such a table with
the few operations of a :class:`pandas.DataFrame` that the reading, checking and inversion of
a resonance table use (a column by name, columns by a list of names, a new column, the number
of rows, the column names, ``attrs``, ``copy``), so that one code serves both kinds of table.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ContactresInputError

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["ArrayTable"]


class ArrayTable:
    """Named one-dimensional numpy arrays of one length, in order: the columns of a table.

    ``table[name]`` is a column (the array itself, not a copy), ``table[[a, b]]`` a new table
    of those columns, ``table[name] = values`` sets a column (a scalar fills every row: text
    as an object array, as pandas keeps it), ``len(table)`` is the number of rows and
    ``table.columns`` the names. ``attrs`` holds what a reader says of the table (as
    :attr:`pandas.DataFrame.attrs`: ``line_word``, ``decimal``, ``given``).

    Parameters
    ----------
    columns : mapping of str to array-like, optional
        The columns, in order; each one-dimensional, all of one length.
    attrs : mapping, optional
        Copied into :attr:`attrs`.

    Examples
    --------
    >>> t = ArrayTable({"fc1_Hz": [2.5e5, 2.6e5]})
    >>> t["normalisation"] = "global"
    >>> len(t), t.columns
    (2, ['fc1_Hz', 'normalisation'])
    """

    def __init__(self, columns: Mapping[str, Any] | None = None, attrs: Mapping | None = None):
        self._data: dict[str, np.ndarray] = {}
        self._rows: int | None = None
        self.attrs: dict[str, Any] = dict(attrs or {})
        for name, values in (columns or {}).items():
            self[name] = values

    @classmethod
    def from_frame(cls, frame: pd.DataFrame) -> ArrayTable:
        """The columns of a DataFrame (with unique column names) as arrays, and its attrs."""
        return cls({str(c): frame[c].to_numpy() for c in frame.columns}, frame.attrs)

    def to_frame(self) -> pd.DataFrame:
        """A :class:`pandas.DataFrame` of the columns (copied), with :attr:`attrs`."""
        import pandas as pd

        frame = pd.DataFrame(self._data)
        frame.attrs.update(self.attrs)
        return frame

    @property
    def columns(self) -> list[str]:
        """The column names, in order."""
        return list(self._data)

    def __len__(self) -> int:
        return self._rows or 0

    def __contains__(self, name: object) -> bool:
        return name in self._data

    def __iter__(self):
        return iter(self._data)

    def __getitem__(self, key):
        if isinstance(key, str):
            return self._data[key]
        return ArrayTable({name: self._data[name] for name in key}, self.attrs)

    def __setitem__(self, name: str, values) -> None:
        if np.ndim(values) == 0:  # one value for every row
            if self._rows is None:
                raise ContactresInputError(f"column {name!r}: one value needs a table with rows")
            if isinstance(values, str):  # one text object in every row, as pandas keeps it
                text = np.empty(self._rows, dtype=object)
                text.fill(values)  # (np.full would make a new str object per row)
                values = text
            else:
                values = np.full(self._rows, values)
        array = np.asarray(values)
        if array.ndim != 1 or (self._rows is not None and len(array) != self._rows):
            raise ContactresInputError(
                f"column {name!r}: expected one dimension of {self._rows} rows, got shape "
                f"{array.shape}"
            )
        self._rows = len(array)
        self._data[name] = array

    def copy(self, deep: bool = True) -> ArrayTable:
        """A new table of copies of the columns (``deep=False``: of the same arrays; setting a
        column of either table then leaves the other as it is) and of :attr:`attrs`."""
        return ArrayTable(
            {name: a.copy() if deep else a for name, a in self._data.items()}, self.attrs
        )

    def items(self) -> Iterable[tuple[str, np.ndarray]]:
        """(name, column) pairs, in order."""
        return self._data.items()
