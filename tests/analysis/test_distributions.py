"""The F tail and the Student-t quantile of contactres.analysis._distributions against scipy.

scipy stays a dependency and is the peer here (cephes/Boost): the analysis's own functions
exist only so that a first analysis need not import scipy.special. Tolerances (relative):

* log B(a, b): 1e-13 of max(1, |log B|) for 0.05 <= a, b <= 100 (beyond, scipy's betaln
  loses ~1e-16 a log a; large a is held to the asymptotic ratio of gamma functions instead);
* I_x(a, b): 1e-11 for a, b <= 1e3 and values above 1e-250 (below that scipy's betainc itself
  loses digits: a case is held to the power series A&S 26.5.4 instead, written here);
* the F tail: 5e-12 for dfn + dfd <= 1e4 (the drift test: dfn = ramps - 1, dfd = points - ramps
  - 2, a few hundred to a few thousand), 5e-16 (dfn + dfd) beyond, up to 1e5, for F >= 1e-3
  (below, scipy's 1 - w loses digits: closed forms of dfn = 2 and dfn = dfd = 1 instead);
* the t quantile: 2e-12 for dof <= 1e4 (t95: experiments - 1), 2e-16 dof beyond, up to 1e9;
  tails down to 1e-150 through scipy's distribution function (its quantile, stdtrit, misses
  there for non-integer dof) and the closed forms of dof = 1 and 2.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import special

from contactres.analysis._distributions import (
    DOF_MAX,
    T_MAX,
    f_upper_tail,
    incomplete_beta,
    log_beta,
    student_t_quantile,
)


def _rel(a, b):
    return np.abs(np.asarray(a) / np.asarray(b) - 1.0)


def test_log_beta_is_scipys():
    rng = np.random.default_rng(31)
    a, b = 10 ** rng.uniform(np.log10(0.05), 2, (2, 20000))
    ref = special.betaln(a, b)
    assert np.max(np.abs(log_beta(a, b) - ref) / np.maximum(1.0, np.abs(ref))) < 1e-13


def test_log_beta_of_a_large_and_a_small_argument_is_the_asymptotic_ratio():
    """log B(a, b) = log Γ(b) - log[Γ(a + b)/Γ(a)], the ratio b log a + b(b - 1)/(2a) +
    O(a^-2) for large a (A&S 6.1.47): where scipy's betaln keeps only ~1e-9."""
    from math import lgamma, log

    for a, b in [(682050.79, 0.1175), (3.1e6, 0.5), (2.0e7, 7.5)]:
        ref = lgamma(b) - (b * log(a) + b * (b - 1) / (2 * a))
        assert abs(float(log_beta(a, b)) - ref) < 1e-13 * max(1.0, abs(ref))


def test_incomplete_beta_is_scipys():
    rng = np.random.default_rng(7)
    a, b = 10 ** rng.uniform(-1, 3, (2, 20000))
    x = rng.uniform(0, 1, 20000)
    got, ref = incomplete_beta(a, b, x), special.betainc(a, b, x)
    shown = ref > 1e-250
    assert np.max(_rel(got[shown], ref[shown])) < 1e-11
    assert np.max(np.abs(got - ref)) < 1e-13  # (also where both are tiny)


def test_incomplete_beta_deep_in_the_tail_is_its_power_series():
    """I_x(a, b) = x^a (1-x)^b / (a B(a, b)) [1 + Σ_n B(a+1, n+1)/B(a+b, n+1) x^(n+1)] (A&S
    26.5.4), positive terms summed here, at values ~1e-264 where scipy's betainc is off by 40 %
    (its complement betaincc agrees)."""
    from math import exp, lgamma, log, log1p

    a, b, x = 3967.313001952528, 36.643367580773024, 0.8286794264673325
    front = a * log(x) + b * log1p(-x) - log(a) - (lgamma(a) + lgamma(b) - lgamma(a + b))
    term = total = 1.0
    n = 0
    while term > 1e-18 * total:
        term *= (a + b + n) / (a + 1 + n) * x
        total += term
        n += 1
    series = exp(front) * total  # lgamma's ~1e-12 abs. error at a ~ 4e3 bounds the check
    assert _rel(incomplete_beta(a, b, x), series) < 1e-11
    assert _rel(incomplete_beta(a, b, x), special.betaincc(b, a, 1 - x)) < 1e-11


def test_the_f_tail_is_scipys_fdtrc_over_the_drift_tests_range_and_beyond():
    dfn = np.arange(1.0, 60.0)[:, None, None]
    dfd = np.unique(np.round(10 ** np.linspace(0, 5, 120)))[None, :, None]
    f = np.array([0.0, 1e-3, 0.1, 0.5, 1, 2, 5, 30, 1e3, 1e6, 1e12])
    got, ref = f_upper_tail(dfn, dfd, f), special.fdtrc(dfn, dfd, f)
    shown = ref > 1e-250
    assert np.array_equal(shown, got > 1e-250)
    tol = np.maximum(5e-12, 5e-16 * (dfn + dfd)) + 0 * f
    assert np.all(_rel(got[shown], ref[shown]) < tol[shown])
    assert np.all(got[~shown] < 1e-249)
    assert np.all(f_upper_tail(dfn, dfd, 0.0) == 1.0)
    assert np.all(f_upper_tail(dfn, dfd, np.inf) == 0.0)
    assert np.isnan(f_upper_tail(2.0, 10.0, [-1.0, np.nan])).all()


def test_the_f_tail_is_closed_form_for_two_and_for_one_and_one_degrees_of_freedom():
    """For dfn = 2: P(F > f) = (1 + 2f/dfd)^(-dfd/2) exactly (A&S 26.6.4 with one term); for
    dfn = dfd = 1: (2/π) arctan(1/√f) (A&S 26.6.8). Near f = 0 the tail is 1 - O(f^(dfn/2)),
    kept to full relative accuracy."""
    f = 10 ** np.linspace(-15, 3, 50)
    for dfd in (3.0, 40.0, 2500.0):
        exact = np.exp(-0.5 * dfd * np.log1p(2 * f / dfd))
        shown = exact > 1e-300
        got = f_upper_tail(2.0, dfd, f)
        assert np.max(_rel(got[shown], exact[shown])) < 1e-13 * max(1.0, dfd / 100)
    exact = 2 / np.pi * np.arctan(1 / np.sqrt(f))
    assert np.max(_rel(f_upper_tail(1.0, 1.0, f), exact)) < 1e-14


@pytest.mark.parametrize("p", [0.025, 0.6, 0.9, 0.975, 0.995, 1 - 1e-10, 1e-6])
def test_the_t_quantile_is_scipys_stdtrit(p):
    dof = np.concatenate([np.arange(1.0, 10001.0, 7.0), np.linspace(1.0, 40.0, 157)])
    assert np.max(_rel(student_t_quantile(p, dof), special.stdtrit(dof, p))) < 2e-12
    large = 10 ** np.linspace(4, 9, 40)
    tol = np.maximum(2e-12, 2e-16 * large)
    assert np.all(_rel(student_t_quantile(p, large), special.stdtrit(large, p)) < tol)


def test_t95_is_the_tables():
    """Student's table (two-sided 95 %): 12.706, 4.303, 3.182, ..., 1.960 at infinity."""
    t = student_t_quantile(0.975, [1, 2, 3, 10, 30, DOF_MAX])
    assert np.allclose(t, [12.7062047, 4.3026527, 3.1824463, 2.2281389, 2.0422725, 1.9599640])


def test_the_t_quantile_in_the_tails_inverts_scipys_distribution_function():
    rng = np.random.default_rng(3)
    dof = np.concatenate([rng.uniform(1, 50, 1500), np.round(10 ** rng.uniform(0, 4, 1500))])
    q = 10 ** rng.uniform(-150, np.log10(0.49), dof.size)
    t = student_t_quantile(q, dof)
    assert np.all(t < 0)
    assert np.max(_rel(special.stdtr(dof, t), q)) < 1e-11
    # The upper tail is the same solve: p = 1 - q' with q' = 1 - (1 - q) (exact in floats).
    p = 1 - q[q > 1e-15]
    upper = student_t_quantile(p, dof[q > 1e-15])
    assert np.max(_rel(upper, -student_t_quantile(1 - p, dof[q > 1e-15]))) < 1e-15


def test_the_t_quantile_of_one_and_two_degrees_of_freedom_is_closed_form():
    """dof = 1 (Cauchy): t = -cot(π q); dof = 2: t = -(1 - 2q)/√(2q(1 - q)) (A&S 26.7.3-4)."""
    q = 10 ** np.linspace(-150, np.log10(0.499), 400)
    assert np.max(_rel(student_t_quantile(q, 1.0), -1 / np.tan(np.pi * q))) < 1e-13
    assert np.max(_rel(student_t_quantile(q, 2.0), -(1 - 2 * q) / np.sqrt(2 * q * (1 - q)))) < (
        1e-13
    )
    assert student_t_quantile(0.5, 7.0) == 0.0
    assert np.isnan(student_t_quantile([0.0, 1.0, np.nan, 0.3], [3.0, 3.0, 3.0, 0.0])).all()


def test_the_t_quantile_converges_in_a_few_newton_steps():
    """Newton's steps from the right of the root (the tail's power-law bound) reach it in at
    most 40 steps over dof 1 ... 1e5 and tails down to 1e-150; with 3 steps most are still
    running (NaN), so the limit is live."""
    rng = np.random.default_rng(5)
    dof = np.concatenate([rng.uniform(1, 50, 2000), np.round(10 ** rng.uniform(0, 5, 6000))])
    q = 10 ** rng.uniform(-150, np.log10(0.4999), dof.size)
    assert not np.isnan(student_t_quantile(q, dof, max_iter=40)).any()
    assert np.isnan(student_t_quantile(q, dof, max_iter=3)).mean() > 0.3


def test_the_t_quantile_is_nan_outside_its_stated_range():
    """Beyond DOF_MAX degrees of freedom or |t| = T_MAX the tail's rounding or its continued
    fraction no longer give the stated accuracy: NaN, not a wrong number (review R24a: 1e20
    degrees of freedom gave 1.1e5 for 1.96; dof = 1 at p = 1e-300 gave 6e161 for 3e299)."""
    assert np.isnan(student_t_quantile(0.975, [1.01 * DOF_MAX, 1e20, 1e100, np.inf])).all()
    assert _rel(student_t_quantile(0.975, DOF_MAX), special.stdtrit(DOF_MAX, 0.975)) < 2e-16 * (
        DOF_MAX
    )
    # dof = 1 and 2 down to p = 1e-300: the closed forms where |t| <= T_MAX, NaN beyond.
    q = 10 ** np.linspace(-300, -100, 300)
    for dof, exact in ((1.0, -1 / np.tan(np.pi * q)), (2.0, -1 / np.sqrt(2 * q * (1 - q)))):
        got = student_t_quantile(q, dof)
        inside = np.abs(exact) <= T_MAX
        assert inside.any() and (dof == 2.0 or (~inside).any())  # dof 2: |t| <= 7.1e149
        assert np.max(_rel(got[inside], exact[inside])) < 1e-13
        assert np.isnan(got[~inside]).all()
