"""The plateau loop's slip integral by its power series (issue 31, point 3).

Checked against QUADPACK's QAWS rule on the integral as written (in d, with the square-root
end point as its algebraic weight): a different variable, a different rule, no series.
"""

import numpy as np
import pytest
from scipy import integrate, special

from contactres.analysis import _plateau_slopes
from contactres.analysis._plateau_series import (
    SERIES_BLOCK,
    SERIES_MAX_M,
    SERIES_TIERS,
    slip_integral_series,
    slip_integrals_series,
)
from contactres.analysis._plateau_slopes import FIT_SERIES_GROUPS, plateau_loop_slopes


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


def _quadpack_derivatives(x, c):
    """∫_c^b d(e - d)/√Q dd and ∫_c^b d(x - d)/√Q dd, Q = d(x - d)(e - d): 1/√(b - d) as
    QAWS's weight."""
    e = c + 1.5
    b, far = min(x, e), max(x, e)
    out = []
    for top in (e, x):
        value, _ = integrate.quad(
            lambda d, top=top: d * (top - d) / np.sqrt(d * (far - d)),
            c,
            b,
            weight="alg",
            wvar=(0.0, -0.5),
            epsabs=0.0,
            epsrel=1e-13,
            limit=200,
        )
        out.append(value)
    return out


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


@pytest.mark.parametrize("seed", [0, 1])
def test_derivative_integrals_equal_adaptive_quadrature(seed):
    # J's series with its derivatives' integrals (the fit's path): J the same bits as alone,
    # the two others against QAWS on the integrals as written, on both sides of e, c = 0 and
    # c near x (Euler's relation gives one of them: checked here too).
    x, c = _points(seed)
    e = c + 1.5
    J, jx, jc = slip_integrals_series(x, c)
    np.testing.assert_array_equal(J, slip_integral_series(x, c))
    scale = np.minimum(x, e) * np.sqrt(np.maximum(x, e))  # their scale: r √A
    ref = np.array([_quadpack_derivatives(a, b) for a, b in zip(x, c, strict=True)])
    assert np.max(np.abs(jx - ref[:, 0]) / scale) < 1e-13
    assert np.max(np.abs(jc - ref[:, 1]) / scale) < 1e-13


@pytest.mark.parametrize("side", ["x <= e", "x > e"])
def test_derivative_integrals_of_points_all_on_one_side_of_e(side):
    # A call whose points all lie on one side of e takes Euler's relation without choosing
    # between the sides point by point: the two integrals against QAWS as above, on a call of
    # such points alone (the calls above mix both sides).
    x, c = _points(2)
    e = c + 1.5
    on = (x > e) if side == "x > e" else ~(x > e)
    x, c, e = x[on], c[on], e[on]
    assert x.size > 50
    _, jx, jc = slip_integrals_series(x, c)
    scale = np.minimum(x, e) * np.sqrt(np.maximum(x, e))
    ref = np.array([_quadpack_derivatives(a, b) for a, b in zip(x, c, strict=True)])
    assert np.max(np.abs(jx - ref[:, 0]) / scale) < 1e-13
    assert np.max(np.abs(jc - ref[:, 1]) / scale) < 1e-13


def test_derivative_series_in_groups_of_cells():
    # Only the cells of the groups are summed: m = 0.2 (cell 3) with groups ending at 4, not at
    # 3; a group sums its last cell's terms, within rounding of each cell alone.
    x, c = np.array([0.3, 0.3]), np.array([0.0, 0.0])
    assert all(np.isfinite(v).all() for v in slip_integrals_series(x, c, groups=(2, 4)))
    assert all(np.isnan(v).all() for v in slip_integrals_series(x, c, groups=(3,)))
    x, c = _points(4)
    e = c + 1.5
    inside = np.minimum(x, e) < 0.5 * np.maximum(x, e)
    r_a = np.minimum(x, e) * np.sqrt(np.maximum(x, e))  # r √A: the derivatives' scale, J's / r
    grouped, alone = slip_integrals_series(x, c, groups=(4, 8)), slip_integrals_series(x, c)
    for g, a, scale in zip(grouped, alone, (r_a * np.minimum(x, e), r_a, r_a), strict=True):
        assert np.all(np.isnan(g[~inside])) and inside.sum() > 50
        assert np.max(np.abs(g[inside] - a[inside]) / scale[inside]) < 1e-15


def test_each_tier_sums_enough_terms():
    # The rest after K terms, at most |b_{K+1}| B(3/2, (K + 2)/2) q^{K+1}/(1 - q) (module
    # docstring), at the tier's largest m; and the tiers cover (0, SERIES_MAX_M) in order.
    bounds = [m for m, _ in SERIES_TIERS]
    assert bounds == sorted(bounds) and bounds[-1] == SERIES_MAX_M
    for m, terms in SERIES_TIERS:
        q = m / (2.0 - m)
        most = abs(special.binom(0.5, terms + 1)) * special.beta(1.5, (terms + 2) / 2)
        assert most * q ** (terms + 1) / (1.0 - q) < 1e-17
        # The derivatives' series: |c_k| = (2k - 1)|b_k| (k >= 1), each term larger, the rest
        # at most 2K + 1 times J's (|c_k| B(...) falls with k as |b_k| B(...) does).
        most_c = abs(special.binom(-0.5, terms + 1)) * special.beta(1.5, (terms + 2) / 2)
        assert most_c == pytest.approx((2 * terms + 1) * most, rel=1e-12)
        assert most_c * q ** (terms + 1) / (1.0 - q) < 2.5e-15


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
    # The evidence's path (derivatives=False) against the fit's (the series with derivatives
    # in its groups of cells, the elliptic integrals beyond).
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
    # The series (SERIES_BLOCK points a call, with or without the derivatives' integrals)
    # works in blocks: over several blocks, each point's numbers are those it gets evaluated
    # alone (in calls of 1000 points), and points in the last block still equal the quadrature.
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
    slopes = plateau_loop_slopes(x, c)
    parts = [plateau_loop_slopes(x[i : i + 1000], c[i : i + 1000]) for i in range(0, n, 1000)]
    for j, a in enumerate(slopes):
        np.testing.assert_array_equal(a, np.concatenate([p[j] for p in parts]))


def _series_alone(x, c, terms):
    """J and the larger end's derivative integral (module docstring's recursion, V_k = b_k q^k
    T_k), each point summing exactly ``terms`` terms: the sum written out per term."""
    e = c + 1.5
    r, big = np.minimum(x, e), np.maximum(x, e)
    a = big - 0.5 * r
    rho, q = c / r, 0.5 * r / a
    sin, cos = 2.0 * np.sqrt(rho * (1.0 - rho)), 1.0 - 2.0 * rho
    phi = 2.0 * np.arcsin(np.sqrt(c / r))
    b = [1.0, 0.5]
    for k in range(2, terms + 1):
        b.append(b[-1] * (1.5 - k) / k)
    p = sin * sin * sin * q
    v = [0.5 * (np.pi - phi) + 0.5 * sin * cos, p * (-0.5 / 3.0)]
    total, other = v[0] + v[1], v[0] - v[1]
    for k in range(2, terms + 1):
        p = p * (q * cos)
        v.append(v[k - 2] * (q * q) * (b[k] / b[k - 2] * (k - 1) / (k + 2)) - p * (b[k] / (k + 2)))
        total = total + v[k]
        other = other - v[k] * (2 * k - 1)
    scale = 0.25 * r * r
    return scale * np.sqrt(a) * total, scale * other / np.sqrt(a)


@pytest.mark.parametrize(
    "groups",
    [(), (8, 4), (4, 4, 8), (0, 4), (-1, 4), (4, len(SERIES_TIERS) + 1), (4.0, 8), (4, 8.5)],
)
def test_groups_that_would_give_wrong_numbers_are_refused(groups):
    # Unsorted, repeated, empty groups, groups outside the cells or not integers: a
    # ValueError naming them, not silently wrong sums.
    x, c = np.array([0.3, 0.5]), np.array([0.0, 0.0])  # cells 3 and 5
    with pytest.raises(ValueError, match=r"^groups must be strictly ascending integers"):
        slip_integrals_series(x, c, groups=groups)
    # integers of numpy are integers
    assert all(np.isfinite(v).all() for v in slip_integrals_series(x, c, groups=np.array([4, 8])))


@pytest.mark.parametrize("groups", [(4, 8), (2, 5, 6), tuple(range(1, len(SERIES_TIERS) + 1))])
def test_one_loop_sums_each_group_its_own_terms(groups):
    # The groups' points share one loop over the terms (the points still summing a prefix of
    # them): each point's J and integrals are, bit for bit, those of its group's terms summed
    # for it alone, with points of every group mixed in one call and across blocks.
    rng = np.random.default_rng(11)
    n = SERIES_BLOCK + 3000
    c = rng.uniform(0.0, 2.0, n) * (rng.random(n) < 0.8)
    x = c + rng.uniform(1e-4, 4.0, n)
    got = slip_integrals_series(x, c, groups=groups)
    e = c + 1.5
    cell = np.floor(16.0 * np.minimum(x, e) / np.maximum(x, e))
    assert np.all(np.isnan(got[0][cell >= groups[-1]]))
    far = x > e
    for first, last in zip((0, *groups[:-1]), groups, strict=True):
        at = np.flatnonzero((cell >= first) & (cell < last))
        assert at.size > 100
        J, summed = _series_alone(x[at], c[at], SERIES_TIERS[last - 1][1])
        np.testing.assert_array_equal(got[0][at], J)
        # the summed integral is ∫d(x - d)/√Q where x <= e, ∫d(e - d)/√Q where x > e
        np.testing.assert_array_equal(np.where(far[at], got[1][at], got[2][at]), summed)


@pytest.mark.parametrize("derivatives", [True, False])
def test_slopes_of_slipping_points_do_not_depend_on_sticking_ones(derivatives):
    # Where every point slips the slopes skip the gather and scatter of the slipping points:
    # the same numbers, bit for bit, as those points among sticking ones (x <= c: G′ = 1 and
    # the rest 0, exactly), on both sides of e and in 2-d (rows sharing c).
    rng = np.random.default_rng(9)
    c = rng.uniform(0.0, 1.0, (40, 1))
    x = c + rng.uniform(1e-3, 3.0, (40, 12))
    alone = plateau_loop_slopes(x, c, derivatives)
    mixed = plateau_loop_slopes(np.concatenate([x, 0.5 * c], axis=1), c, derivatives)
    for a, b, stuck in zip(alone, mixed, (1.0, 0.0, 0.0, 0.0, 0.0, 0.0), strict=False):
        np.testing.assert_array_equal(a, b[:, :12])
        assert np.all(b[:, 12] == stuck)


def _slopes_plainly(x, c):
    """The six arrays of plateau_loop_slopes with derivatives at slipping points (1-d), as
    written before the fit took its points in one order: J by the series of the fit's groups
    (each point in its own tier), the elliptic form where that is NaN, then the formulas of
    G′, G″ and their derivatives with a choice (np.where) between y < 3/2 and beyond."""
    y = x - c
    half = 2.0 * np.arcsin(np.sqrt(c / x))
    J, Jx, Jc = slip_integrals_series(x, c, half, FIT_SERIES_GROUPS)
    far = np.isnan(J)
    J[far], Jx[far], Jc[far] = _plateau_slopes._elliptic_integrals(x[far], c[far])
    rcy = np.sqrt(c * y)
    H = x**2 / 8.0 * half - 0.25 * rcy * (y - c) + np.sqrt(2.0 / 3.0) * J
    inside = y < 1.5
    r = np.sqrt(np.maximum(1.0 - y / 1.5, 0.0))
    q = np.where(inside, (y / 1.5) / (1.0 + r), 1.0)
    s_y = np.where(inside, q * q * (0.5 + r), y - 1.0)
    W = np.where(inside, 0.3 * q**3 * (r * r + 3.0 * r + 1.0), y - 1.2)
    k1, k2 = 8.0 / (np.pi * x**2), 4.0 / (np.pi * x**2)
    g1, g2 = k1 * H, k2 * (c * s_y + W)
    Hx = 0.5 * (0.5 * x * half - rcy) + Jx / np.sqrt(6.0)
    dW = np.where(inside, 1.0 - r**3 - y * r, 1.0)
    return (
        g1,
        g2,
        k1 * Hx - 2.0 * g1 / x,
        k1 * (Jc / np.sqrt(6.0)),
        k2 * (c * q + dW) - 2.0 * g2 / x,
        k2 * (s_y - c * q - dW),
    )


def test_fit_slopes_in_one_order_are_those_of_the_plain_formulas():
    # With derivatives the slopes take the slipping points in one order (series groups, then
    # the elliptic form's points) and form everything in place: each point's six numbers are,
    # bit for bit, those of the plain formulas, at sticking points, every cell of m, x beyond
    # e, y beyond 3/2 and c = 0, in 2-d rows sharing c.
    rng = np.random.default_rng(21)
    c = rng.uniform(0.0, 2.0, (300, 1)) * (rng.random((300, 1)) < 0.8)
    x = c + rng.uniform(-0.5, 6.0, (300, 13))
    x = np.maximum(x, 1e-3)
    got = plateau_loop_slopes(x, c)
    cc = np.broadcast_to(c, x.shape)
    slip = x > cc
    e = cc + 1.5
    cell = np.floor(16.0 * np.minimum(x, e) / np.maximum(x, e))[slip]
    assert min(np.sum(cell == k) for k in range(16)) >= 10  # every cell of m, series or not
    assert np.sum(x > e) > 100 and np.sum(x - cc >= 1.5) > 100 and np.sum(~slip) > 100
    want = _slopes_plainly(x[slip], cc[slip])
    for j, (a, b) in enumerate(zip(got, want, strict=True)):
        np.testing.assert_array_equal(a[slip], b)
        assert np.all(a[~slip] == (1.0 if j == 0 else 0.0))
