"""The text cells of a table, each distinct text handled once: a sweep table of 10^6 rows holds
10^5 sweep ids and a few labels, and Python's strip per cell was 16 % of ``qcm analyze``
(issue 31); factorising the cells is a hash table in C.

Shared by :func:`contactres.measurements.schema.stripped` (every cell) and the sweep reader's
labels (their rules checked on the distinct texts only).
"""

from __future__ import annotations

import numpy as np

from ..numerics import factorize_runs

__all__ = ["stripped_codes", "stripped_distinct"]


def stripped_distinct(cells) -> tuple[np.ndarray, np.ndarray]:
    """The cells as text without the white space around them, as ``(codes, distinct)``:
    ``distinct[codes]`` is what ``Series(cells).astype(str).str.strip().to_numpy()`` gives (an
    object array, NaN where a cell is missing); ``distinct`` holds each distinct cell once,
    stripped, in the order of its first appearance (a rule that holds for them holds for every
    cell)."""
    codes, distinct, _ = stripped_codes(cells)
    return codes, distinct


def stripped_codes(cells) -> tuple[np.ndarray, np.ndarray, bool]:
    """:func:`stripped_distinct`'s ``(codes, distinct)``, and whether the codes are already
    ``pandas.factorize(distinct)[0][codes]``: True where no cell is missing and the stripping
    changed no distinct cell (the stripped texts are then as distinct as the cells were), so
    that a caller need not hash the distinct texts again (10^5 sweep ids: ~0.02 s, issue 31)."""
    import pandas as pd  # here: the numeric rules of a binary table need no pandas

    text = (cells if isinstance(cells, pd.Series) else pd.Series(cells, dtype=object)).astype(str)
    # Hashed on the first cell of each run of equal cells only (a sweep's id fills its rows,
    # a label its sweeps'): the codes of every cell hashed, 2-3x faster at 10^6 rows.
    codes, uniques = factorize_runs(text, use_na_sentinel=False)
    cells_once = np.asarray(uniques, dtype=object)
    distinct = pd.Series(uniques).str.strip().to_numpy(dtype=object)
    # (NaN is not equal to itself: a missing cell makes this False)
    return codes, distinct, bool((distinct == cells_once).all())
