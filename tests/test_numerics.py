"""Tests of contactres.numerics: the Gauss-Legendre rules on [0, 1] and on panels [a, b], the
Chebyshev-Lobatto barycentric weights."""

import math

import numpy as np
import pytest
from scipy.special import eval_legendre

from contactres.numerics import gauss_legendre, gauss_legendre_unit, lobatto_weights


@pytest.mark.parametrize("n", [1, 2, 5, 24, 48])
def test_rule_integrates_monomials_exactly_up_to_degree_2n_minus_1(n):
    x, w = gauss_legendre_unit(n)
    assert x.shape == w.shape == (n,)
    k = np.arange(2 * n)
    exact = 1.0 / (k + 1)  # ∫₀¹ x^k dx
    # (rounding of the high powers reaches ~2e-13 at n = 48)
    np.testing.assert_allclose(
        (w[:, None] * x[:, None] ** k[None, :]).sum(axis=0), exact, rtol=1e-12
    )


@pytest.mark.parametrize("n", [1, 2, 3, 5])
def test_error_of_degree_2n_is_the_textbook_remainder(n):
    # The n-point Gauss-Legendre remainder on [0, 1] is (n!)⁴ f^(2n)(ξ) / ((2n + 1) ((2n)!)³);
    # for f = x^(2n) the derivative is the constant (2n)!, so the error is exactly known.
    x, w = gauss_legendre_unit(n)
    err = 1.0 / (2 * n + 1) - np.sum(w * x ** (2 * n))
    expected = math.factorial(n) ** 4 / ((2 * n + 1) * math.factorial(2 * n) ** 2)
    assert err == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("n", [3, 24])
def test_nodes_are_the_legendre_roots_and_symmetric(n):
    x, w = gauss_legendre_unit(n)
    # Roots of P_n(2x - 1) (scipy's recurrence, a second implementation), inside (0, 1).
    assert np.max(np.abs(eval_legendre(n, 2 * x - 1))) < 1e-13
    assert np.all(np.diff(x) > 0) and 0 < x[0] and x[-1] < 1
    np.testing.assert_allclose(x + x[::-1], 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(w, w[::-1], rtol=1e-14)
    assert np.all(w > 0)


def test_arrays_are_read_only_and_bad_n_is_refused():
    x, w = gauss_legendre_unit(4)
    with pytest.raises(ValueError):
        x[0] = 0.0
    with pytest.raises(ValueError):
        w[0] = 0.0
    for bad in (0, -3, 2.5):
        with pytest.raises(ValueError, match="Gauss-Legendre"):
            gauss_legendre_unit(bad)


@pytest.mark.parametrize("n", [1, 3, 12, 20, 32, 48])
def test_panel_rule_integrates_polynomials_of_degree_2n_minus_1_on_every_panel(n):
    # Panels of shape (P, 1), as the far-field grid passes them; powers of t - mid (mid the
    # centre of the panel) keep the rounding small and have integrals known in closed form.
    a = np.array([-1.5, 0.0, 0.25, 3.0])[:, None]
    b = np.array([-0.5, 2.0, 0.3, 7.0])[:, None]
    x, w = gauss_legendre(a, b, n)
    assert x.shape == w.shape == (4, n)
    assert np.all((x > a) & (x < b)) and np.all(w > 0)
    np.testing.assert_allclose(w.sum(axis=-1), (b - a)[:, 0], rtol=1e-14)
    mid, half = 0.5 * (a + b)[:, 0], 0.5 * (b - a)[:, 0]
    for k in range(2 * n):
        # ∫ (t - mid)^k dt over [a, b]: 0 for odd k, 2 half^(k+1)/(k + 1) for even k; errors
        # are measured against ∫ |t - mid|^k, the size of the terms that are summed.
        size = 2.0 * half ** (k + 1) / (k + 1)
        exact = size if k % 2 == 0 else 0.0 * size
        got = np.sum(w * (x - mid[:, None]) ** k, axis=-1)
        assert np.max(np.abs(got - exact) / size) < 1e-12, k  # rounding of high powers ~3e-13


@pytest.mark.parametrize("n", [4, 24])
def test_panel_rule_on_the_unit_interval_matches_numpy_leggauss(n):
    # scipy's roots_legendre against numpy's leggauss (gauss_legendre_unit): two independent
    # constructions of the same rule.
    x, w = gauss_legendre(0.0, 1.0, n)
    xu, wu = gauss_legendre_unit(n)
    np.testing.assert_allclose(x, xu, rtol=0, atol=1e-15)
    np.testing.assert_allclose(w, wu, rtol=1e-13)
    with pytest.raises(ValueError, match="Gauss-Legendre"):
        gauss_legendre(0.0, 1.0, 0)


def test_illinois_step_finds_cube_roots_elementwise_where_regula_falsi_stalls():
    """Vectorised Illinois against numpy's cbrt: every element to 1e-14 within 14 steps, where
    plain regula falsi (one end kept for ever on this convex function) is still far off."""
    from contactres.numerics import illinois_step

    c = np.array([2.0, 5.0, 30.0, 99.0])
    lo, hi = np.zeros(4), np.full(4, 5.0)

    def run(steps, halve):
        b = (lo, hi, lo**3 - c, hi**3 - c, np.zeros(4, dtype=int))
        for _ in range(steps):
            lo_, hi_, f_lo, f_hi, _side = b
            x = (lo_ * f_hi - hi_ * f_lo) / (f_hi - f_lo)
            b = illinois_step(x, x**3 - c, b) if halve else _plain(x, x**3 - c, b)
        return x

    def _plain(x, fx, b):
        lo_, hi_, f_lo, f_hi, side = b
        left = fx < 0
        return (
            np.where(left, x, lo_),
            np.where(left, hi_, x),
            np.where(left, fx, f_lo),
            np.where(left, f_hi, fx),
            side,
        )

    np.testing.assert_allclose(run(14, True), np.cbrt(c), rtol=1e-14)
    assert np.max(np.abs(run(14, False) / np.cbrt(c) - 1)) > 1e-3


@pytest.mark.parametrize("n_points", [2, 3, 8, 17])
def test_lobatto_weights_are_the_product_weights_up_to_a_common_factor(n_points):
    # The barycentric weights by their definition, 1/∏_{k≠j}(x_j − x_k) at the Lobatto points
    # (Berrut and Trefethen 2004, Eq. 3.2), scaled to the first: the closed form's ratios.
    x = np.cos(np.pi * np.arange(n_points) / (n_points - 1))
    diff = x[:, None] - x[None, :]
    np.fill_diagonal(diff, 1.0)
    direct = 1.0 / np.prod(diff, axis=1)
    w = lobatto_weights(n_points)
    np.testing.assert_allclose(w / w[0], direct / direct[0], rtol=1e-12, atol=0)


def test_run_starts_against_a_loop_over_the_rows():
    # Two columns with runs, a missing cell (NaN: a run of its own) and a value that comes back.
    from contactres.numerics import run_starts

    a = np.array(["x", "x", "y", "y", "x", np.nan, np.nan, "y"], dtype=object)
    b = np.array([1, 1, 1, 2, 2, 2, 2, 2], dtype=object)
    want = [i for i in range(a.size) if i == 0 or a[i] != a[i - 1] or b[i] != b[i - 1]]
    assert run_starts(a, b).tolist() == want == [0, 2, 3, 4, 5, 6, 7]
    assert run_starts(a).tolist() == [0, 2, 4, 5, 6, 7]
    assert run_starts(np.array([], dtype=object)).tolist() == []


def _columns():
    """Columns with runs of random length of a few cells that come back later, missing cells
    among them (NaN, None, pandas.NA, NaT: each a run of its own), of every kind of dtype the
    tables hold or a user may pass."""
    import importlib.util

    import pandas as pd

    rng = np.random.default_rng(7)
    words = np.array(["b", "a", "c c", " a", "", None], dtype=object)
    cells = np.repeat(words[rng.integers(0, words.size, 400)], rng.integers(1, 5, 400))
    ints = np.repeat(rng.integers(0, 5, 300), rng.integers(1, 4, 300))
    columns = {
        "object": pd.Series(cells, dtype=object),
        "object with pandas.NA": pd.Series(np.where(cells == "", pd.NA, cells), dtype=object),
        "astype(str)": pd.Series(cells, dtype=object).astype(str),
        "str": pd.Series(cells, dtype="str"),
        "string (python)": pd.Series(cells, dtype=pd.StringDtype("python")),
        "category": pd.Series(cells, dtype="category"),
        "category, unused": pd.Series(
            pd.Categorical(cells[:9], categories=["z", "", "c c", " a", "a", "b"])
        ),
        "int64": pd.Series(ints),
        "Int64 with NA": pd.Series(ints).astype("Int64").mask(lambda c: c == 3),
        "float with NaN": pd.Series(ints.astype(float)).mask(lambda c: c == 3),
        "boolean with NA": pd.Series(ints > 1, dtype="boolean").mask(lambda c: c.index % 7 == 0),
        "datetime with NaT": pd.Series(pd.to_datetime(ints, unit="D")).mask(
            lambda c: c.dt.day == 2
        ),
        "empty object": pd.Series([], dtype=object),
        "ndarray object": cells,
        # Equal texts in objects of their own (as pandas' parser gives a column from one block
        # of rows to the next), every other run, or every cell: compared as texts.
        "ndarray object, equal texts in other objects": np.array(
            [c if c is None or i % 7 < 3 else "".join([c, ""]) + " " for i, c in enumerate(cells)],
            dtype=object,
        ),
        "object, every cell its own object": pd.Series(
            [None if c is None else "".join([c, "x"]) for c in cells], dtype=object
        ),
        "object, one NaN object repeated": pd.Series(
            np.where(cells == "a", np.nan, cells), dtype=object
        ),
        "ndarray object with pandas.NA": np.where(cells == "", pd.NA, cells),
        "ndarray float with NaN": np.where(ints == 3, np.nan, ints.astype(float)),
        "ndarray int": ints,
        "ndarray empty": np.array([]),
    }
    if importlib.util.find_spec("pyarrow") is not None:  # not in the project's environment
        columns["string (pyarrow)"] = pd.Series(cells, dtype=pd.StringDtype("pyarrow"))
    return columns


@pytest.mark.parametrize("use_na_sentinel", [True, False])
@pytest.mark.parametrize("name", list(_columns()))
def test_factorize_runs_as_pandas_hashing_every_cell(name, use_na_sentinel):
    # The reference is pandas' factorize of every cell: the same codes, and the same distinct
    # cells of the same type (an Index of the Series' dtype; an ndarray for an ndarray).
    import pandas as pd

    from contactres.numerics import factorize_runs

    column = _columns()[name]
    codes, uniques = factorize_runs(column, use_na_sentinel=use_na_sentinel)
    want_codes, want_uniques = pd.factorize(column, use_na_sentinel=use_na_sentinel)
    assert codes.dtype == want_codes.dtype and codes.tolist() == want_codes.tolist()
    assert type(uniques) is type(want_uniques) and uniques.dtype == want_uniques.dtype
    if isinstance(want_uniques, pd.Index):
        assert uniques.equals(want_uniques)
    else:
        assert pd.Series(uniques).equals(pd.Series(want_uniques))  # NaN equal to NaN


@pytest.mark.parametrize("name", list(_columns()))
def test_column_run_starts_against_a_loop_over_the_rows(name):
    # A run starts where a cell is not the one before it by Python's ``!=`` (a NaN or NaT is a
    # run of its own; None equals None), cells held as objects first by identity (the same
    # object as above: the same run); in a column holding pandas.NA, which has no truth
    # value, every missing cell is taken as NaN. An Arrow-backed column is left to pandas'
    # hashing (None).
    import pandas as pd

    from contactres.numerics import column_run_starts

    column = _columns()[name]
    starts = column_run_starts(column)
    if getattr(column.dtype, "storage", None) == "pyarrow":  # "str" too, where pyarrow is
        assert starts is None
        return
    cells = list(column)
    # Cells held as objects: a row holding the object above it is in its run (a NaN object
    # repeated too; a masked or "string" column's missing cells are the one object NaN),
    # unless pandas.NA met another cell (every missing cell NaN, compared).
    dtype = column.dtype
    as_objects = not (isinstance(dtype, np.dtype) and dtype.kind in "biufcmM")
    if getattr(dtype, "na_value", None) is pd.NA:
        cells = list(column.to_numpy(dtype=object, na_value=np.nan))
    elif any(c is pd.NA for c in cells):
        cells, as_objects = [np.nan if pd.isna(c) else c for c in cells], False
    elif as_objects:
        cells = list(column.to_numpy(dtype=object) if isinstance(column, pd.Series) else column)
    want = [
        i
        for i in range(len(cells))
        if i == 0
        or (not (as_objects and cells[i] is cells[i - 1]) and bool(cells[i] != cells[i - 1]))
    ]
    assert starts.tolist() == want


@pytest.mark.parametrize("name", list(_columns()))
def test_factorize_at_finer_runs_is_pandas_hashing_every_cell(name):
    # Starts given by the caller: any split of the runs finer than column_run_starts' (here:
    # some runs cut again at random rows) gives pandas' factorisation of every cell; None
    # hashes every cell.
    import pandas as pd

    from contactres.numerics import column_run_starts, factorize_at_runs

    column = _columns()[name]
    want_codes, want_uniques = pd.factorize(column, use_na_sentinel=False)
    starts = column_run_starts(column)
    choices = [None]
    if starts is not None:
        rng = np.random.default_rng(len(column))
        cut = np.flatnonzero(rng.random(len(column)) < 0.1)
        choices += [starts, np.union1d(starts, cut).astype(np.intp)]
    for given in choices:
        codes, uniques = factorize_at_runs(column, given, use_na_sentinel=False)
        assert codes.tolist() == want_codes.tolist()
        assert pd.Series(uniques).equals(pd.Series(want_uniques))


def test_repeat_runs_against_a_loop_over_the_rows():
    # Each run's value on each of its rows, as a loop over the rows sets it: runs of one row,
    # of many, the last run ending at the last row; no rows.
    from contactres.numerics import repeat_runs

    rng = np.random.default_rng(11)
    for trial in range(50):
        n_rows = int(rng.integers(1, 60))
        starts = np.flatnonzero(np.r_[True, rng.random(n_rows - 1) < 0.3])
        values = rng.normal(size=starts.size) if trial % 2 else np.arange(starts.size) * 3
        want = []
        for row in range(n_rows):
            run = max(i for i, s in enumerate(starts) if s <= row)
            want.append(values[run])
        got = repeat_runs(values, starts, n_rows)
        assert got.dtype == values.dtype and got.tolist() == want
    empty = repeat_runs(np.array([], dtype=bool), np.array([], dtype=np.intp), 0)
    assert empty.dtype == bool and empty.size == 0
    # No rows given as a plain empty list (numpy makes it float) or a list of values; a Series
    # of values gives an ndarray, not a Series with repeated labels (review R31b).
    assert repeat_runs(np.array([]), [], 0).size == 0
    import pandas as pd

    got = repeat_runs(pd.Series([4, 5], index=[10, 20]), [0, 2], 3)
    assert type(got) is np.ndarray and got.tolist() == [4, 4, 5]


def test_factorize_at_runs_takes_a_list_as_factorize_runs_does():
    from contactres.numerics import factorize_at_runs, factorize_runs

    cells = ["b", "b", "a", "b"]
    codes, uniques = factorize_at_runs(cells, np.array([0, 2, 3]))
    want_codes, want_uniques = factorize_runs(cells)
    assert codes.tolist() == want_codes.tolist() == [0, 0, 1, 0]
    assert type(uniques) is type(want_uniques) is np.ndarray and list(uniques) == ["b", "a"]


def test_object_pointers_are_the_objects_identities():
    # The same pointer is the same object: id() of each cell (CPython's id is the address),
    # read-only; None where numpy gives no flat view of the pointers.
    from contactres.numerics import object_pointers

    a, b = "alpha", ["beta"]
    cells = np.array([a, b, a, None, b], dtype=object)
    pointers = object_pointers(cells)
    assert pointers is not None and not pointers.flags.writeable
    np.testing.assert_array_equal(pointers, [id(c) for c in cells])
    assert object_pointers(cells[::2]) is None  # not contiguous
    assert object_pointers(cells.reshape(1, 5)) is None  # not one-dimensional
