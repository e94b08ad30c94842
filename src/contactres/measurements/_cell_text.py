"""The text cells of a table, each distinct text handled once: a sweep table of 10^6 rows holds
10^5 sweep ids and a few labels, and Python's strip per cell was 16 % of ``qcm analyze``
(issue 31); factorising the cells is a hash table in C.

Shared by :func:`contactres.measurements.schema.stripped` (every cell) and the sweep reader's
labels (their rules checked on the distinct texts only).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..numerics import column_run_starts, factorize_at_runs

if TYPE_CHECKING:  # annotations only: pandas is imported where a table is read
    import pandas as pd

__all__ = ["stripped_codes", "stripped_text_codes", "text_cells"]


def text_cells(cells) -> pd.Series:
    """The cells as text: ``Series(cells).astype(str)`` (a Series taken as it is, anything
    else as a Series of objects)."""
    import pandas as pd  # here: the numeric rules of a binary table need no pandas

    return (cells if isinstance(cells, pd.Series) else pd.Series(cells, dtype=object)).astype(str)


def stripped_codes(cells) -> tuple[np.ndarray, np.ndarray, bool]:
    """The cells as text without the white space around them, as ``(codes, distinct)``:
    ``distinct[codes]`` is what ``Series(cells).astype(str).str.strip().to_numpy()`` gives (an
    object array, NaN where a cell is missing); ``distinct`` holds each distinct cell once,
    stripped, in the order of its first appearance (a rule that holds for them holds for every
    cell). Also whether the codes are already
    ``pandas.factorize(distinct)[0][codes]``: True where no cell is missing and the stripping
    changed no distinct cell (the stripped texts are then as distinct as the cells were), so
    that a caller need not hash the distinct texts again (10^5 sweep ids: ~0.02 s, issue 31)."""
    text = text_cells(cells)
    return stripped_text_codes(text, column_run_starts(text))


def stripped_text_codes(
    text: pd.Series, starts: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray, bool]:
    """:func:`stripped_codes` of cells already made text (:func:`text_cells`), whose runs of
    equal cells the caller has found (``starts``: :func:`contactres.numerics.column_run_starts`
    of ``text``): a caller that looks at the runs itself need not have them found again."""
    import pandas as pd

    # Hashed on the first cell of each run of equal cells only (a sweep's id fills its rows,
    # a label its sweeps'): the codes of every cell hashed, 2-3x faster at 10^6 rows.
    codes, uniques = factorize_at_runs(text, starts, use_na_sentinel=False)
    cells_once = np.asarray(uniques, dtype=object)
    distinct = pd.Series(uniques).str.strip().to_numpy(dtype=object)
    # (NaN is not equal to itself: a missing cell makes this False)
    return codes, distinct, bool((distinct == cells_once).all())
