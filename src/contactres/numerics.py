"""Numerical building blocks shared by the forward models (ground layer: numpy and scipy).

Pure functions without state: a caller that needs a rule many times computes it once and keeps
it (as a constant of its module or an argument it passes on); nothing here remembers a result.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .errors import ContactresInputError

if TYPE_CHECKING:  # annotations only: the numerics import no pandas
    import pandas as pd

__all__ = [
    "IllinoisBracket",
    "column_run_starts",
    "factorize_at_runs",
    "factorize_runs",
    "gauss_legendre",
    "gauss_legendre_unit",
    "illinois_step",
    "lobatto_weights",
    "object_pointers",
    "repeat_runs",
    "run_starts",
]


def lobatto_weights(n_points: int) -> np.ndarray:
    """Barycentric weights of the ``n_points`` Chebyshev–Lobatto points cos(πj/(n_points − 1)).

    (−1)^j, halved at both ends (Berrut and Trefethen 2004, SIAM Rev. 46, 501, Eq. 5.4): exact,
    where weights formed as products over the nodes carry round-off (and scipy's
    ``BarycentricInterpolator`` forms them in a random order). A common factor of the weights
    (e.g. the sign of nodes taken in ascending order) cancels in the barycentric formula of the
    second kind.

    Parameters
    ----------
    n_points : int
        How many Lobatto points, >= 2.

    Returns
    -------
    ndarray of shape (n_points,)
        1, −1, 1, ... with the first and last halved.
    """
    w = np.where(np.arange(n_points) % 2 == 0, 1.0, -1.0)
    w[[0, -1]] *= 0.5
    return w


def gauss_legendre_unit(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights of the n-point Gauss-Legendre rule on [0, 1].

    The rule of :func:`numpy.polynomial.legendre.leggauss` on [-1, 1], mapped by x -> (x + 1)/2
    (weights halved), so ``np.sum(w * f(x))`` integrates a polynomial f of degree <= 2n - 1 over
    [0, 1] exactly (to rounding). Both arrays are read-only.

    Parameters
    ----------
    n : number of nodes, >= 1

    Returns
    -------
    (x, w) : two ndarrays of shape (n,), nodes ascending in (0, 1) and positive weights summing
        to 1.

    Notes
    -----
    numpy's construction (eigenvalues of the companion matrix and one Newton step) costs about
    35 µs per node (0.8 ms for n = 24): compute the rule once per call of a vectorised routine,
    not once per sub-interval.
    """
    n_int = int(n)
    if n_int != n or n_int < 1:
        raise ContactresInputError(
            f"n (number of Gauss-Legendre nodes) must be an integer >= 1, got {n!r}"
        )
    x, w = np.polynomial.legendre.leggauss(n_int)
    x01, w01 = 0.5 * (x + 1.0), 0.5 * w
    x01.setflags(write=False)
    w01.setflags(write=False)
    return x01, w01


def gauss_legendre(a, b, n: int, *, rule: tuple | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights of the n-point Gauss-Legendre rule on [a, b] (or on many panels).

    ``a`` and ``b`` broadcast against each other and against the node axis, which comes last:
    panels given as arrays of shape (P, 1) give nodes and weights of shape (P, n). The map is
    x -> (b - a)/2 x + (b + a)/2 of the rule on [-1, 1] of :func:`scipy.special.roots_legendre`
    (the same rule as numpy's ``leggauss`` to ~5e-15, ~5x cheaper: ~0.3 ms at n = 40, and the
    kernel tables and far-field grids of :mod:`contactres.dynamic` need several per call).

    Parameters
    ----------
    a, b : float or array_like, the ends of the interval(s) (any unit; the weights carry it)
    n : number of nodes, >= 1
    rule : (x, w), optional
        The n-point rule on [-1, 1] (``gauss_legendre(-1.0, 1.0, n)``), computed once by a
        caller that maps it onto many intervals: mapped by the same arithmetic, so the same
        numbers as without it, without the root finding each call costs.

    Returns
    -------
    (x, w) : nodes and weights, of the broadcast shape of a, b with the node axis (n,) last;
        ``np.sum(w * f(x), axis=-1)`` integrates a polynomial f of degree <= 2n - 1 over each
        [a, b] exactly (to rounding).

    Notes
    -----
    :func:`gauss_legendre_unit` keeps numpy's construction: the QCM model was validated on
    those nodes, which differ from scipy's in the last bits (<= ~5e-15).
    """
    n_int = int(n)
    if n_int != n or n_int < 1:
        raise ContactresInputError(
            f"n (number of Gauss-Legendre nodes) must be an integer >= 1, got {n!r}"
        )
    if rule is None:
        # Imported here: the root finder and gauss_legendre_unit of this module need no scipy,
        # and a command that uses only those (a static contact) need not import scipy.special.
        from scipy import special

        rule = special.roots_legendre(n_int)
    x, w = rule
    a = np.asarray(a)
    b = np.asarray(b)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


#: (lo, hi, f_lo, f_hi, side): a bracket of roots, the function's values at its ends, and which
#: end the last step kept (-1: the lower, 1: the upper, 0: none yet); arrays of one shape.
IllinoisBracket = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def illinois_step(x, fx, bracket: IllinoisBracket) -> IllinoisBracket:
    """One step of the Illinois method (modified regula falsi), elementwise on arrays.

    The false-position point ``x`` with the function's value ``fx`` there replaces the end of
    the bracket whose value has its sign; when the same end is kept twice, the value at the
    kept end is halved, so the method converges superlinearly (order ~1.44) where plain regula
    falsi stalls on a convex function. The caller forms x = (lo f_hi − hi f_lo)/(f_hi − f_lo),
    evaluates fx and decides when to stop.

    Parameters
    ----------
    x, fx : ndarray
        The new point and the function's value there (f increases through the root: f(lo) < 0
        < f(hi)).
    bracket : IllinoisBracket
        (lo, hi, f_lo, f_hi, side) before the step.

    Returns
    -------
    IllinoisBracket
        The bracket after the step.

    References
    ----------
    M. Dowell and P. Jarratt, "A modified regula falsi method for computing the root of an
    equation", BIT 11, 168-174 (1971).

    Examples
    --------
    The cube root of 2, in a few steps:

    >>> import numpy as np
    >>> lo, hi = np.array([1.0]), np.array([2.0])
    >>> bracket = (lo, hi, lo**3 - 2, hi**3 - 2, np.zeros(1, dtype=int))
    >>> for _ in range(12):
    ...     lo, hi, f_lo, f_hi, _ = bracket
    ...     x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
    ...     bracket = illinois_step(x, x**3 - 2, bracket)
    >>> print(f"{x[0]:.12f}")
    1.259921049895
    """
    lo, hi, f_lo, f_hi, side = bracket
    left = fx < 0
    # Illinois: halve the kept end's value when the same end is kept twice.
    f_hi = np.where(left & (side == -1), f_hi / 2, f_hi)
    f_lo = np.where(~left & (side == 1), f_lo / 2, f_lo)
    lo, f_lo = np.where(left, x, lo), np.where(left, fx, f_lo)
    hi, f_hi = np.where(left, hi, x), np.where(left, f_hi, fx)
    return lo, hi, f_lo, f_hi, np.where(left, -1, 1)


def run_starts(*columns) -> np.ndarray:
    """The index of the first row of each run of rows equal in every one of ``columns``.

    A table whose equal cells follow one another (the points of a sweep, the sweeps of a
    configuration) holds every distinct cell, and every distinct combination, in the runs' first
    rows: counting or factorising those alone gives what all rows give, first appearances in the
    same order, where hashing every cell of 10^6 rows cost ~0.1 s a column (issue 31). Cells are
    compared with ``!=`` (a missing cell, NaN, is a run of its own).

    Parameters
    ----------
    *columns : array_like
        Columns of one length (object arrays for text).

    Returns
    -------
    numpy.ndarray
        Increasing row indices, 0 first (empty for no rows).

    Examples
    --------
    >>> run_starts(np.array(["a", "a", "b", "a"], dtype=object)).tolist()
    [0, 2, 3]
    """
    n = len(columns[0])
    change = np.zeros(n, dtype=bool)
    change[:1] = True
    for cells in columns:
        cells = np.asarray(cells)
        change[1:] |= cells[1:] != cells[:-1]
    return np.flatnonzero(change)


def column_run_starts(cells) -> np.ndarray | None:
    """:func:`run_starts` of one column, whatever its dtype, or None where hashing every cell
    in pandas is the cheaper way (an Arrow-backed column).

    A column backed by Arrow (pandas 3 with pyarrow installed keeps text so) would first be
    made into Python strings to be compared: 0.11-0.15 s for 1.2 M cells, where
    ``pandas.factorize`` hashes them in Arrow for 0.025-0.056 s (review R28a). A column of a
    numpy numeric, boolean or time dtype is compared as it is (int64 codes of 1.2 M rows:
    0.008 s, 0.036 s as objects). Any other is compared as objects, first by identity, then
    by ``!=`` where the object changes (:func:`_object_run_starts`: a NaN or NaT is a run of
    its own unless the same object fills the rows above, a run of None one run).
    ``pandas.NA`` has no truth value (``!=`` on it raises): in a column where it is compared,
    every missing cell is compared as NaN, a run of its own. Splitting runs further is
    always safe: every distinct cell still starts some run.

    Parameters
    ----------
    cells : pandas.Series or array_like
        One column.

    Returns
    -------
    numpy.ndarray or None
        The run starts (increasing row indices, 0 first; empty for no rows), or None for an
        Arrow-backed Series.

    Examples
    --------
    >>> column_run_starts(np.array([3, 3, 1, 3])).tolist()
    [0, 2, 3]
    """
    import pandas as pd  # here: the package's numerics need no pandas until a table is met

    if isinstance(cells, pd.Series):
        dtype = cells.dtype
        if getattr(dtype, "storage", None) == "pyarrow":
            return None
        if isinstance(dtype, np.dtype) and dtype.kind in "biufcmM":
            values = cells.to_numpy()
        elif getattr(dtype, "na_value", None) is pd.NA:  # masked and "string" columns
            values = cells.to_numpy(dtype=object, na_value=np.nan)
        else:  # objects, "str", categories: NaN or None where missing, pandas.NA rarely
            values = cells.to_numpy(dtype=object)
    else:
        values = np.asarray(cells)
    try:
        return _object_run_starts(values) if values.dtype == object else run_starts(values)
    except TypeError:
        # pandas.NA among objects: NaN for every missing cell (a pass over every cell in C,
        # which a column without pandas.NA is spared).
        return run_starts(np.where(pd.isna(values), np.nan, values))


def object_pointers(values: np.ndarray) -> np.ndarray | None:
    """The object pointers a one-dimensional, contiguous object array holds, as a read-only
    ``intp`` view of its memory (the same pointer: the same object), or None where numpy does
    not give them (not contiguous, not one-dimensional, a numpy that keeps them to itself).

    Why: cells compared by identity are integers compared in C, where ``==`` or ``!=`` of the
    cells calls the objects' own comparison a row (~100 instructions each). Read-only: a write
    through the view would corrupt the objects' reference counts."""
    if values.ndim != 1 or not values.flags.c_contiguous:
        return None
    try:
        pointers = np.frombuffer(values, dtype=np.intp)
    except (TypeError, ValueError, BufferError):
        return None
    pointers.flags.writeable = False
    return pointers


def _object_run_starts(values: np.ndarray) -> np.ndarray:
    """:func:`run_starts` of one object array, the cells compared by ``!=`` only where the
    object changes from the row above; rows holding the same object as the row above (one
    pointer: an integer compare in C) are in its run.

    pandas' parser gives equal cells of a column one string object (within each block of rows
    it parses): a sweep id's rows, a constant's column. ``!=`` on 1.2 M such cells called the
    strings' comparison a row, ~9 ms a column where the pointers take ~1 ms (issue 31, point
    3: some 25 columns compared while reading and setting up 10^5 sweeps). A NaN object
    repeated is one run here, where ``!=`` made each NaN a run of its own: splitting runs
    further was always allowed, and every missing cell is still in a run of missing cells.
    Where numpy does not give an array's pointers (not contiguous), every cell is compared."""
    pointers = object_pointers(values)
    if pointers is None:
        return run_starts(values)
    change = np.zeros(len(values), dtype=bool)
    change[:1] = True
    np.not_equal(pointers[1:], pointers[:-1], out=change[1:])
    other = np.flatnonzero(change[1:]) + 1  # another object: compared as cells
    if 4 * other.size > len(values):
        # Equal cells mostly in objects of their own (ids built a row at a time, numbers made
        # text by astype(str)): every cell compared in one pass, as gathers of the changed rows
        # cost 2-5 times that (review R29b), and a row holding the object above still in its run.
        change[1:] &= values[1:] != values[:-1]
        return np.flatnonzero(change)
    change[other] = values[other] != values[other - 1]
    return np.flatnonzero(change)


def factorize_runs(cells, use_na_sentinel: bool = True) -> tuple[np.ndarray, pd.Index | np.ndarray]:
    """``pandas.factorize(cells, sort=False, use_na_sentinel=use_na_sentinel)``, hashing only
    the first cell of each run of equal cells (:func:`column_run_starts`).

    Every distinct cell starts some run and first appearances keep their order, so the codes
    and the distinct cells are those of hashing every cell: a sweep id fills its sweep's rows
    and a constant a whole column, and hashing 10^6 cells of text cost ~0.1 s a column (issue
    31, point 3), ~2-4x what the runs' first cells cost. An Arrow-backed column is hashed
    whole by pandas, which is cheaper there (:func:`column_run_starts`).

    Parameters
    ----------
    cells : pandas.Series or numpy.ndarray
        One column (an object array for text). Anything else (a list, a ``pandas.Index``, a
        ``pandas.Categorical``) is taken as ``numpy.asarray(cells)``: the distinct cells are
        then an ndarray, where ``pandas.factorize`` would give an Index or a Categorical.
    use_na_sentinel : bool
        As pandas has it: True, a missing cell gets code -1 and is not among the distinct
        cells; False, missing cells are one distinct cell.

    Returns
    -------
    codes : numpy.ndarray
        The code of each cell (intp), numbering the distinct cells in order of appearance.
    uniques : pandas.Index or numpy.ndarray
        The distinct cells, as ``pandas.factorize`` gives them for a Series (an Index, of the
        Series' dtype) or an ndarray (an ndarray).

    Examples
    --------
    >>> codes, uniques = factorize_runs(np.array(["b", "b", "a", "b"], dtype=object))
    >>> codes.tolist(), list(uniques)
    ([0, 0, 1, 0], ['b', 'a'])
    """
    import pandas as pd  # here: the package's numerics need no pandas until a table is met

    cells = cells if isinstance(cells, pd.Series) else np.asarray(cells)
    return factorize_at_runs(cells, column_run_starts(cells), use_na_sentinel)


def factorize_at_runs(
    cells, starts: np.ndarray | None, use_na_sentinel: bool = True
) -> tuple[np.ndarray, pd.Index | np.ndarray]:
    """:func:`factorize_runs` of a column whose runs the caller has found already: ``starts``
    is :func:`column_run_starts` of ``cells`` (None: every cell is hashed).

    Why: a caller that needs the run starts itself (to choose how to treat a column) would
    otherwise have them found twice, a pass over every cell each time.

    Parameters
    ----------
    cells : pandas.Series or numpy.ndarray
        One column (an object array for text); anything else is taken as
        ``numpy.asarray(cells)``, as :func:`factorize_runs` takes it.
    starts : numpy.ndarray or None
        The first row of each run of equal cells, increasing, 0 first; any finer split of the
        runs is as good (every distinct cell still starts some run). None where
        :func:`column_run_starts` gives None.
    use_na_sentinel : bool
        As for :func:`factorize_runs`.

    Returns
    -------
    codes : numpy.ndarray
        The code of each cell (intp), numbering the distinct cells in order of appearance.
    uniques : pandas.Index or numpy.ndarray
        The distinct cells, as :func:`factorize_runs` gives them.

    Examples
    --------
    >>> cells = np.array(["b", "b", "a", "b"], dtype=object)
    >>> codes, uniques = factorize_at_runs(cells, np.array([0, 2, 3]))
    >>> codes.tolist(), list(uniques)
    ([0, 0, 1, 0], ['b', 'a'])
    """
    import pandas as pd  # here: the package's numerics need no pandas until a table is met

    cells = cells if isinstance(cells, pd.Series) else np.asarray(cells)
    if starts is None:
        return pd.factorize(cells, sort=False, use_na_sentinel=use_na_sentinel)
    firsts = cells.iloc[starts] if isinstance(cells, pd.Series) else cells[starts]
    codes, uniques = pd.factorize(firsts, sort=False, use_na_sentinel=use_na_sentinel)
    return repeat_runs(codes, starts, len(cells)), uniques


def repeat_runs(values, starts: np.ndarray, n_rows: int) -> np.ndarray:
    """Each of ``values`` (one per run) repeated over the rows of its run: the column of
    ``n_rows`` rows whose runs start at the rows ``starts``.

    What a column's runs give back to its rows: a value found on the first cell of each run of
    equal cells (:func:`run_starts`, :func:`column_run_starts`) is every cell's of that run.

    Parameters
    ----------
    values : array_like
        One value per run, in the order of the runs (its length is that of ``starts``); taken
        as ``numpy.asarray(values)``.
    starts : array_like of int
        The first row of each run: increasing integers, 0 first (empty for no rows).
    n_rows : int
        The number of rows; the last run ends there.

    Returns
    -------
    numpy.ndarray
        ``n_rows`` values, of the dtype of ``values``.

    Examples
    --------
    >>> repeat_runs(np.array([7, 8, 9]), np.array([0, 2, 3]), 5).tolist()
    [7, 7, 8, 9, 9]
    """
    # (an empty list or float array of starts is no rows: cast, or np.repeat refuses floats)
    counts = np.diff(np.append(np.asarray(starts, dtype=np.intp), n_rows))
    return np.repeat(np.asarray(values), counts)
