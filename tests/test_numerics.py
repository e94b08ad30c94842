"""Tests of contactres.numerics: the Gauss-Legendre rule on [0, 1]."""

import math

import numpy as np
import pytest
from scipy.special import eval_legendre

from contactres.numerics import gauss_legendre_unit


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
