"""The plateau loop's slip integral by its power series (issue 31, point 3).

Checked against QUADPACK's QAWS rule on the integral as written (in d, with the square-root
end point as its algebraic weight): a different variable, a different rule, no series.
"""

import numpy as np
import pytest
from scipy import integrate, special

from contactres.analysis._plateau import SMALL_X_BLOCK, plateau_loop_slopes
from contactres.analysis._plateau_series import (
    SERIES_BLOCK,
    SERIES_MAX_M,
    SERIES_TIERS,
    slip_integral_series,
)


def _quadpack(x, c):
    """∫_c^b √(d(x - d)(e - d)) dd, e = c + 3/2, b = min(x, e): √(b - d) as QAWS's weight."""
    e = c + 1.5
    b, far = min(x, e), max(x, e)
    value, _ = integrate.quad(
        lambda d: np.sqrt(d * (far - d)),
        c,
        b,
        weight="alg",
        wvar=(0.0, 0.5),
        epsabs=0.0,
        epsrel=1e-13,
        limit=200,
    )
    return value


def _points(seed, n=300):
    """(x, c) across the series' domain on both sides of e = c + 3/2, c = 0 and c near x."""
    rng = np.random.default_rng(seed)
    c = rng.uniform(0.0, 3.0, n) * rng.choice([1.0, 1e-3, 0.0], n)
    e = c + 1.5
    m = rng.uniform(0.0, SERIES_MAX_M, n)
    below = rng.random(n) < 0.5
    x = np.where(below, np.maximum(m * e, c * (1.0 + 1e-3 * rng.random(n))), e / m)
    keep = (x > c) & (np.minimum(x, e) < SERIES_MAX_M * np.maximum(x, e))
    return x[keep], c[keep]


@pytest.mark.parametrize("seed", [0, 1])
def test_series_equals_adaptive_quadrature(seed):
    x, c = _points(seed)
    e = c + 1.5
    r = np.minimum(x, e)
    scale = r * r * np.sqrt(np.maximum(x, e) - 0.5 * r)  # J's own scale (module docstring)
    ref = np.array([_quadpack(a, b) for a, b in zip(x, c, strict=True)])
    assert np.max(np.abs(slip_integral_series(x, c) - ref) / scale) < 1e-14


def test_each_tier_sums_enough_terms():
    # The rest after K terms, at most |b_{K+1}| B(3/2, (K + 2)/2) q^{K+1}/(1 - q) (module
    # docstring), at the tier's largest m; and the tiers cover (0, SERIES_MAX_M) in order.
    bounds = [m for m, _ in SERIES_TIERS]
    assert bounds == sorted(bounds) and bounds[-1] == SERIES_MAX_M
    for m, terms in SERIES_TIERS:
        q = m / (2.0 - m)
        most = abs(special.binom(0.5, terms + 1)) * special.beta(1.5, (terms + 2) / 2)
        assert most * q ** (terms + 1) / (1.0 - q) < 1e-17


def test_the_bound_of_each_term():
    # |T_k| <= B(3/2, (k + 1)/2), the integral over all of (0, π), by quadrature at φ_c = 0
    # (where it is reached for even k) and φ_c = 1.
    for k in (0, 1, 2, 7, 30):
        for lo in (0.0, 1.0):
            t, _ = integrate.quad(lambda p, k=k: np.sin(p) ** 2 * np.cos(p) ** k, lo, np.pi)
            assert abs(t) <= special.beta(1.5, (k + 1) / 2) * (1 + 1e-12)


def test_outside_the_domain_is_nan():
    got = slip_integral_series(np.array([1.5, 0.3]), np.array([0.0, 0.0]))  # m = 1 and 0.2
    assert np.isnan(got[0]) and np.isfinite(got[1])


def test_slopes_without_derivatives_agree_with_the_fits():
    # The evidence's path (derivatives=False) against the fit's (Gauss rule and elliptic
    # integrals) and against the quadrature of the loop shape's integral in d.
    x, c = _points(2)
    h1, h2 = plateau_loop_slopes(x, c, derivatives=False)
    g1, g2, *_ = plateau_loop_slopes(x, c)
    assert np.max(np.abs(h1 - g1)) < 1e-12 and np.array_equal(h2, g2)


def test_the_callers_angle_gives_the_same_numbers():
    # The slopes pass their 2 arcsin √(c/x) as the series' φ_c (used where x <= e, recomputed
    # where x > e): the same J, bit for bit, as the series' own angle on both sides of e.
    x, c = _points(3)
    assert (x > c + 1.5).any() and (x < c + 1.5).any()
    phi = 2.0 * np.arcsin(np.sqrt(c / x))
    np.testing.assert_array_equal(slip_integral_series(x, c, phi), slip_integral_series(x, c))


def test_blocks_do_not_mix_points():
    # The series (SERIES_BLOCK points a call) and the small-x Gauss rule (SMALL_X_BLOCK) work
    # in blocks: over several blocks, each point's numbers are those it gets evaluated alone
    # (in calls of 1000 points), and points in the last block still equal the quadrature.
    rng = np.random.default_rng(5)
    n = 2 * SERIES_BLOCK + 777
    c = rng.uniform(0.0, 1.0, n)
    x = c + rng.uniform(1e-3, 1.0, n)  # m < 1/2 (a few tiers, each over several blocks)
    got = slip_integral_series(x, c)
    alone = np.concatenate(
        [slip_integral_series(x[i : i + 1000], c[i : i + 1000]) for i in range(0, n, 1000)]
    )
    np.testing.assert_array_equal(got, alone)
    for i in range(n - 5, n):
        assert abs(got[i] - _quadpack(x[i], c[i])) < 1e-14 * x[i] ** 2
    k = 3 * SMALL_X_BLOCK + 5
    cs = rng.uniform(0.0, 0.05, k)
    xs = cs + rng.uniform(1e-3, 0.09, k)  # x < (c + 3/2)/10: the Gauss rule
    slopes = plateau_loop_slopes(xs, cs)
    parts = [plateau_loop_slopes(xs[i : i + 100], cs[i : i + 100]) for i in range(0, k, 100)]
    for j, a in enumerate(slopes):
        np.testing.assert_array_equal(a, np.concatenate([p[j] for p in parts]))
