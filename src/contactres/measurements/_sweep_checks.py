"""The rules a validated sweep table obeys beyond one cell: no duplicated rows, one value per
sweep (or per configuration) of the columns that describe it, the sign of ΔΓ, enough points
with more than one amplitude per sweep — each broken rule is one error line or one
:class:`SweepWarning` naming the rows (paper 2's analysis takes the table as these rules
leave it)."""

from __future__ import annotations

import warnings
from collections.abc import Mapping

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ..units import MIN_SWEEP_POINTS
from ._messages import column_named, line_word, shown_value

__all__ = [
    "SweepWarning",
    "check_dissipation_sign",
    "check_per_sweep",
    "conflict",
    "drop_duplicates",
    "point_keys",
    "warn_sweeps",
]


class SweepWarning(UserWarning):
    """The data are usable but something is odd (the message says what and where)."""


def drop_duplicates(
    out: pd.DataFrame, source: str, sweep_codes: np.ndarray | None = None
) -> pd.DataFrame:
    """The table without rows that repeat another row (all but the line number), named in one
    warning. ``sweep_codes``: a code per row, equal where the sweep ids are (the reader's,
    as :func:`pandas.factorize` gives them), which then stand for the ids in the first test."""
    data_only = [c for c in out.columns if c != "line"]
    # A repeated row repeats its point (sweep, amplitude and shifts): where no point repeats,
    # no row does, found without hashing the other dozen columns (10^6 rows, issue 31), nor
    # the sweep ids where their codes are given (integers hash in a fraction of the time).
    point = [c for c in ("sweep", "amplitude_m", "df_Hz", "dgamma_Hz") if c in data_only]
    if sweep_codes is not None and len(point) == 4:
        numbers = [out[c].to_numpy() for c in point[1:]]
        if not pd.Series(point_keys(sweep_codes, numbers)).duplicated().any():
            return out
    if point and not out.duplicated(subset=point).any():
        return out
    dup = out.duplicated(subset=data_only, keep="first").to_numpy()
    if not dup.any():
        return out
    lines = out["line"].to_numpy()[dup]
    shown = ", ".join(str(n) for n in lines[:5]) + (" ..." if len(lines) > 5 else "")
    warnings.warn(
        f"{source}: {int(dup.sum())} duplicated row(s) dropped (at {line_word(out)}(s) {shown})",
        SweepWarning,
        stacklevel=4,
    )
    return out.loc[~dup].reset_index(drop=True)


#: Odd multipliers that spread a point's four 64-bit words over its key (:func:`point_keys`).
_SPREAD = (0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9, 0x27D4EB2F165667C5)


def point_keys(codes: np.ndarray, numbers: list[np.ndarray]) -> np.ndarray:
    """One 64-bit key per row from its code (an integer) and its doubles: rows equal in all of
    them (as ``==`` has it: 0.0 and -0.0 one value) have equal keys; rows with equal keys are
    most likely, not surely, equal. Where no two keys are equal, no two rows are: one hash
    table of integers instead of pandas' ``duplicated`` over the columns (which factorises
    each: ~0.8 s for 10^6 rows of a sweep and three doubles, issue 31). Where some are, the
    caller compares the rows themselves. A NaN (not equal to itself: pandas' ``duplicated``
    pairs them), or numbers that are no doubles, make every key 0: the caller compares the rows."""
    key = codes.astype(np.uint64) * np.uint64(_SPREAD[0])
    for spread, values in zip(_SPREAD[1:], numbers, strict=False):
        if values.dtype != np.float64 or np.isnan(values).any():
            return np.zeros(len(codes), dtype=np.uint64)
        bits = (values + 0.0).view(np.uint64)  # + 0.0: -0.0 becomes 0.0, as == has it
        key ^= (bits ^ (bits >> np.uint64(29))) * np.uint64(spread)
        key = (key << np.uint64(23)) | (key >> np.uint64(41))  # the next column elsewhere
    return key


def conflict(table: pd.DataFrame, source: str, by: str, col: str, rule: str) -> None:
    """Error naming two rows if ``col`` takes more than one value within a group of ``by``."""
    counts = table.groupby(by, sort=False)[col].nunique()
    if (counts > 1).any():
        name = counts.index[counts.to_numpy() > 1][0]
        rows = table[table[by] == name]
        a, b = rows.iloc[0], rows.loc[rows[col] != rows[col].iloc[0]].iloc[0]
        raise ContactresInputError(
            f"{source}, {by} {shown_value(name)}: conflicting values in column "
            f"{column_named(table, col)}: "
            f"{shown_value(a[col])} ({line_word(table)} {a['line']}) and {shown_value(b[col])} "
            f"({line_word(table)} {b['line']}); {rule}"
        )


def check_per_sweep(
    table: pd.DataFrame,
    source: str,
    per_sweep: tuple[str, ...],
    codes: Mapping[str, np.ndarray] | None = None,
) -> None:
    """Columns that describe a whole sweep take one value within it; the sphere and the
    material (``sphere_radius_m``, ``poisson``) one value within a configuration, whose sweeps
    the JKR fit (paper 2, Eqs. 7-10) takes together. ``codes``: for columns of text, a code
    per row of ``table``, equal where the texts are (the reader's, as
    :func:`pandas.factorize` gives them); the other columns are factorised here."""
    checks = [("sweep", col, f"one sweep has one {col}") for col in per_sweep]
    checks += [("configuration", col, "one configuration has one sphere") for col in _SPHERE]
    # Each grouping factorised once, each column tested in numpy: pandas' nunique per column
    # factorised the sweep ids again for every column (13 hashings of 10^6 strings); the
    # reader's codes spare the rest. A column that varies within a group is named by
    # :func:`conflict`, as before.
    given = dict(codes or {})
    groups = {
        by: given[by] if by in given else pd.factorize(table[by])[0]
        for by in ("sweep", "configuration")
    }
    inner = {by: _within_runs(group) for by, group in groups.items()}
    for by, col, rule in checks:
        if _varies(groups[by], table[col], given.get(col), inner[by]):
            conflict(table, source, by, col, rule)


def _within_runs(group: np.ndarray) -> np.ndarray | None:
    """Where each row is in the group of the row above (``group[1:] == group[:-1]``), if every
    group is one run of rows and every row in one (a sweep's points follow one another), else
    None."""
    if not group.size or group.min() < 0:
        return None
    inner = group[1:] == group[:-1]
    runs = group.size - np.count_nonzero(inner)
    return inner if runs == int(group.max()) + 1 else None


#: The columns of the sphere and its material, one value per configuration.
_SPHERE = ("sphere_radius_m", "poisson")


def _varies(
    group: np.ndarray,
    cells: pd.Series,
    codes: np.ndarray | None = None,
    inner: np.ndarray | None = None,
) -> bool:
    """Whether ``cells`` take more than one value (missing cells aside, as ``nunique`` counts)
    within some group, ``group`` the group code of each row (-1: in none). ``codes``: the
    cells' codes as :func:`pandas.factorize` gives them, where known already. ``inner``: where
    each row is in the group of the row above, where every group is one run of rows
    (:func:`_within_runs`), else None.

    In groups that are runs, with no cell missing, a group varies where a cell differs from
    the one above it in the same group: two passes over the rows (issue 31, point 3: 13
    columns of 10^6 rows). Otherwise one value of each group is kept (whichever a repeated
    index assigns last: any of them will do), and a group varies where some cell differs
    from it: O(n), no sort, no hashing of floats. Integers are compared as they are, other
    cells that are no floats by their codes."""
    if codes is not None:  # equal cells share a code (-1: missing)
        values, present = codes, codes >= 0
    else:
        values = cells.to_numpy()
        if values.dtype.kind in "iu":  # whole numbers: none missing
            present = None
        elif values.dtype.kind == "f":
            present = ~np.isnan(values)
        else:  # text and the rest: factorised as the codes are
            values = pd.factorize(cells)[0]
            present = values >= 0
    if inner is not None and (present is None or present.all()):
        return bool((inner & (values[1:] != values[:-1])).any())
    present = group >= 0 if present is None else present & (group >= 0)
    g, v = group[present], values[present]
    if not g.size:
        return False
    kept = np.empty(int(g.max()) + 1, dtype=v.dtype)
    kept[g] = v
    return bool((v != kept[g]).any())


def _sweep_ids(table: pd.DataFrame, groups: pd.Index, codes: np.ndarray | None) -> list:
    """The sweep ids of ``groups``, the index of a grouping of ``table`` by :func:`_by_sweep`
    (the ids themselves, or their codes)."""
    if codes is None:
        return list(groups)
    _, first = np.unique(codes, return_index=True)  # (only for a message: once, if ever)
    return list(table["sweep"].to_numpy()[first[np.asarray(groups, dtype=np.intp)]])


def _by_sweep(table: pd.DataFrame, col: str, codes: np.ndarray | None):
    """``table[col]`` grouped by sweep, the groups in the order of their first rows: by the
    sweep ids, or by ``codes`` (one per row, equal where the ids are: integers, which pandas
    groups in a fraction of the time of 10^6 texts, issue 31)."""
    return table[col].groupby(table["sweep"] if codes is None else codes, sort=False)


def check_dissipation_sign(
    table: pd.DataFrame, source: str, sweep_codes: np.ndarray | None = None
) -> None:
    """A contact adds dissipation: ΔΓ (the half-bandwidth shift) of a sweep is positive. Most
    sweeps with a negative median ΔΓ is a sign slip (an export giving −ΔΓ; it moved E by 25 %,
    issue 27): an error. A few such sweeps are named in a warning (noise on a tiny ΔΓ, or a
    reference taken in contact). ``sweep_codes``: as for :func:`drop_duplicates`."""
    median = _by_sweep(table, "dgamma_Hz", sweep_codes).median()
    negative = median < 0
    if not negative.any():
        return
    flagged = median.index[negative.to_numpy()]
    names = [shown_value(n) for n in _sweep_ids(table, flagged, sweep_codes)]
    shown = ", ".join(names[:5]) + (f" ... ({len(names)} in all)" if len(names) > 5 else "")
    if negative.sum() * 2 > len(median):
        raise ContactresInputError(
            f"{source}: dgamma_Hz is negative in {int(negative.sum())} of {len(median)} sweeps "
            f"(median {median.median():.4g} Hz); ΔΓ, the shift of the half-bandwidth, grows "
            "with the contact's dissipation: check its sign (an export may give −ΔΓ)"
        )
    warnings.warn(
        f"{source}: sweep(s) {shown} have a negative median dgamma_Hz (a contact adds "
        "dissipation: check the reference of ΔΓ)",
        SweepWarning,
        stacklevel=3,
    )


def warn_sweeps(table: pd.DataFrame, source: str, sweep_codes: np.ndarray | None = None) -> None:
    """Warn by name of sweeps with too few points, and of sweeps whose amplitudes are all equal
    (all zero, say): a line through a single amplitude has no slope. ``sweep_codes``: as for
    :func:`drop_duplicates`."""
    amp = _by_sweep(table, "amplitude_m", sweep_codes)
    few = f"have fewer than {MIN_SWEEP_POINTS} points and will not be used"
    flat = "have all amplitudes equal: no slope and no friction coefficient can come from them"
    for bad, what in ((amp.size() < MIN_SWEEP_POINTS, few), (amp.max() == amp.min(), flat)):
        flagged = bad.index[bad.to_numpy()]
        names = [shown_value(n) for n in _sweep_ids(table, flagged, sweep_codes)]
        if names:
            more = f" ... ({len(names)} in all)" if len(names) > 5 else ""
            message = f"{source}: sweep(s) {', '.join(names[:5])}{more} {what}"
            warnings.warn(message, SweepWarning, stacklevel=3)
