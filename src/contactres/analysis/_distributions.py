"""Tail of the F distribution and quantile of Student's t, in numpy alone.

The sweep analysis needs two distribution functions: the p-value of the drift test (the upper
tail of Fisher's F, :func:`f_upper_tail`) and the factor of a two-sided 95 % interval (the
quantile of Student's t, :func:`student_t_quantile`). Both are the regularized incomplete beta
function I_x(a, b) (Abramowitz & Stegun 26.5.1; the F tail is A&S 26.6.2, the t distribution
A&S 26.7.1 with 26.5.27), written here so that a first analysis does not import
``scipy.special`` (0.2-0.4 s of CPU: its array-API layer brings ``numpy.testing``).

I_x(a, b) is evaluated by its continued fraction (A&S 26.5.8; DLMF 8.17.22) in the modified
Lentz form (W. J. Lentz, Appl. Opt. 15, 668 (1976); I. J. Thompson and A. R. Barnett,
J. Comput. Phys. 64, 490 (1986)) on the side of the mean where it converges fast, the other side
through I_x(a, b) = 1 - I_{1-x}(b, a) (A&S 26.5.2), so that each tail keeps its relative
accuracy. Its prefactor x^a (1-x)^b / B(a, b) takes log B from Stirling's series (A&S 6.1.40)
written as differences that do not cancel, after shifting small arguments up by the recurrence
of the gamma function (A&S 6.1.15). tests/analysis/test_distributions.py holds both functions
to scipy's (cephes) over the degrees of freedom the analysis uses and far beyond.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DOF_MAX", "T_MAX", "f_upper_tail", "incomplete_beta", "log_beta", "student_t_quantile"]

#: Below this argument log Γ is shifted up before Stirling's series (its truncation after the
#: z^-13 term is below 1e-17 relative from here on).
_STIRLING_FROM = 10.0
#: Coefficients B_2k / (2k (2k - 1)) of Stirling's series of log Γ(z) - (z - 1/2) log z + z
#: - log √(2π), k = 1 ... 7 (A&S 6.1.40; B_2k the Bernoulli numbers).
_STIRLING = (
    1.0 / 12.0,
    -1.0 / 360.0,
    1.0 / 1260.0,
    -1.0 / 1680.0,
    1.0 / 1188.0,
    -691.0 / 360360.0,
    1.0 / 156.0,
)
_HALF_LOG_2PI = 0.9189385332046727
_TINY = 1e-300  # the modified Lentz method's stand-in for a zero denominator
_EPS = np.finfo(float).eps
_STEP_TOL = 1e-14  # Newton's last step in log t (student_t_quantile) ...
_BRACKET_TOL = 1e-12  # ... or the width of its bracket about the root, for ν <= 1e4
#: The largest |t| and degrees of freedom :func:`student_t_quantile` answers (NaN beyond).
T_MAX = 1e150
DOF_MAX = 1e9


def _stirling_correction(z: np.ndarray) -> np.ndarray:
    """log Γ(z) - [(z - 1/2) log z - z + log √(2π)] for z >= 10 (A&S 6.1.40)."""
    w = 1.0 / (z * z)
    acc = np.zeros_like(z)
    for c in reversed(_STIRLING):
        acc = acc * w + c
    return acc / z


def log_beta(a, b) -> np.ndarray:
    """log B(a, b) = log Γ(a) + log Γ(b) - log Γ(a + b) for a, b > 0 (arrays, broadcast).

    Arguments below 10 are raised by B(a, b) = B(a, b + n) Π_{j<n} (a + b + j)/(b + j) (and the
    same in a; A&S 6.1.15), then Stirling's series (A&S 6.1.40) is written with the ratios
    a/(a + b) and b/(a + b), so that nothing of the size of a log a cancels: the error is a few
    ulps of the result's size plus ~1e-16 of b log(a/b).
    """
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    a, b = a.astype(float, copy=True), b.astype(float, copy=True)
    shifted = np.zeros_like(a)
    for _ in range(int(np.ceil(_STIRLING_FROM))):  # at most 10 steps each
        up = b < _STIRLING_FROM
        shifted += np.where(up, np.log((a + b) / np.where(up, b, 1.0)), 0.0)
        b = np.where(up, b + 1.0, b)
        up = a < _STIRLING_FROM
        shifted += np.where(up, np.log((a + b) / np.where(up, a, 1.0)), 0.0)
        a = np.where(up, a + 1.0, a)
    s = a + b
    # log(a/s) and log(b/s), the larger of the two through log1p of the smaller ratio.
    log_a = np.where(a < b, np.log(a / s), np.log1p(-b / s))
    log_b = np.where(b <= a, np.log(b / s), np.log1p(-a / s))
    # (a - 1/2) log a + (b - 1/2) log b - (s - 1/2) log s = (a - 1/2) log(a/s)
    # + (b - 1/2) log(b/s) - (1/2) log s; the -z terms cancel, one log √(2π) remains.
    stirling = (
        (a - 0.5) * log_a
        + (b - 0.5) * log_b
        - 0.5 * np.log(s)
        + _HALF_LOG_2PI
        + _stirling_correction(a)
        + _stirling_correction(b)
        - _stirling_correction(s)
    )
    return stirling + shifted


def _continued_fraction(a, b, x, y, max_iter: int) -> np.ndarray:
    """The continued fraction 1/(1 + d1/(1 + d2/(1 + ...))) of I_x(a, b) (A&S 26.5.8), by the
    modified Lentz method, to relative accuracy ~1e-16; NaN where ``max_iter`` pairs of terms
    did not converge (~√max(a, b) are needed near the mean)."""
    c = np.ones_like(x)
    # 1 - (a + b) x/(a + 1), written with y = 1 - x: no cancellation for x near 1, large a.
    d = (1.0 - b + (a + b) * y) / (a + 1.0)
    d = 1.0 / np.where(np.abs(d) < _TINY, _TINY, d)
    h = d.copy()
    done = np.zeros(x.shape, bool)
    for m in range(1, max_iter + 1):
        m2 = 2.0 * m
        for coef in (
            m * (b - m) * x / ((a + m2 - 1.0) * (a + m2)),
            -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0)),
        ):
            d = 1.0 + coef * d
            d = 1.0 / np.where(np.abs(d) < _TINY, _TINY, d)
            c = 1.0 + coef / c
            c = np.where(np.abs(c) < _TINY, _TINY, c)
            delta = c * d
            h = np.where(done, h, h * delta)
        done |= np.abs(delta - 1.0) <= _EPS
        if done.all():
            break
    return np.where(done, h, np.nan)


def incomplete_beta(a, b, x, y=None, max_iter: int = 20000) -> np.ndarray:
    """The regularized incomplete beta function I_x(a, b) (A&S 26.5.1), a, b > 0, 0 <= x <= 1.

    Parameters
    ----------
    a, b : shape parameters (arrays, broadcast)
    x : argument
    y : 1 - x when the caller has it more accurately than the subtraction (e.g. from the F
        statistic); default 1 - x
    max_iter : pairs of terms of the continued fraction allowed (NaN where they do not do)

    Returns
    -------
    ndarray
        I_x(a, b), each tail to a relative ~1e-14 + 1e-16 (a + b) (the rounding of the
        continued fraction near the mean grows with a + b: 5e-12 at a + b = 1e4, measured
        against scipy), down to ~1e-300. NaN for a NaN or out-of-range argument.
    """
    a, b, x = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, b, x)))
    y = 1.0 - x if y is None else np.broadcast_to(np.asarray(y, dtype=float), x.shape)
    bad = ~((a > 0) & (b > 0) & (x >= 0) & (y >= 0) & np.isfinite(a + b))
    # Past the mean the fraction converges slowly: there 1 - I_y(b, a) (A&S 26.5.2).
    swap = x * (a + b + 2.0) > a + 1.0
    p, q = np.where(swap, b, a), np.where(swap, a, b)
    u, v = np.where(swap, y, x), np.where(swap, x, y)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        # log u from the more accurate of u and 1 - u: for u near 1 the rounding of u itself,
        # times a large exponent, would dominate (ν ~ 1e7 in the t distribution).
        log_u = np.where(u > 0.5, np.log1p(-v), np.log(u))
        log_v = np.where(v > 0.5, np.log1p(-u), np.log(v))
        log_front = p * log_u + q * log_v - np.log(p) - log_beta(p, q)
        front = np.exp(log_front)
        # The fraction is needed only where its front does not underflow (nor on bad rows).
        need = (front > 0) & ~bad
        frac = np.zeros_like(front)
        if need.any():
            frac[need] = _continued_fraction(p[need], q[need], u[need], v[need], max_iter)
        part = np.where(front > 0, front * frac, 0.0)
        out = np.where(swap, 1.0 - part, part)
    return np.where(bad, np.nan, out)


def f_upper_tail(dfn, dfd, f) -> np.ndarray:
    """P(F > f) for Fisher's F distribution with ``dfn`` and ``dfd`` degrees of freedom (> 0,
    any real): I_{dfd/(dfd + dfn f)}(dfd/2, dfn/2) (A&S 26.6.2), what
    ``scipy.special.fdtrc(dfn, dfd, f)`` returns (to 5e-12 relative for dfn + dfd <= 1e4, see
    :func:`incomplete_beta`). f = +inf gives 0; NaN for f < 0 or NaN.

    Both sides of the incomplete beta function are formed from f (neither as 1 minus the
    other), so a p-value near 1 (f near 0) is as accurate as a small one.
    """
    dfn, dfd, f = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (dfn, dfd, f)))
    with np.errstate(invalid="ignore", over="ignore"):
        t = dfn * f
        x = np.where(np.isinf(f), 0.0, dfd / (dfd + t))
        y = np.where(np.isinf(f), 1.0, t / (dfd + t))
        out = incomplete_beta(0.5 * dfd, 0.5 * dfn, x, y)
    return np.where(f >= 0, out, np.nan)


def _t_upper_tail(t: np.ndarray, dof: np.ndarray) -> np.ndarray:
    """P(T > t) for t >= 0: I_{ν/(ν + t²)}(ν/2, 1/2) / 2 (A&S 26.7.1 with 26.5.27), with
    ν/(ν + t²) and t²/(ν + t²) formed from w² = t²/ν or its inverse (t² overflows beyond
    t ~ 1e154, which the tails of ν ~ 1 reach)."""
    w = t / np.sqrt(dof)
    big = w > 1.0
    r = np.where(big, 1.0 / np.where(big, w, 1.0), w) ** 2  # the smaller of w² and 1/w²
    small_side, large_side = r / (1.0 + r), 1.0 / (1.0 + r)
    x = np.where(big, small_side, large_side)
    y = np.where(big, large_side, small_side)
    return 0.5 * incomplete_beta(0.5 * dof, 0.5, x, y)


def _log1p_square(w: np.ndarray) -> np.ndarray:
    """log(1 + w²) without forming w² where it would overflow."""
    big = w > 1.0
    inv = 1.0 / np.where(big, w, 1.0)
    return np.where(big, 2.0 * np.log(np.where(big, w, 1.0)) + np.log1p(inv * inv), np.log1p(w * w))


def student_t_quantile(p, dof, max_iter: int = 100) -> np.ndarray:
    """The quantile t_p of Student's t distribution with ``dof`` degrees of freedom (> 0, any
    real), what ``scipy.special.stdtrit(dof, p)`` returns, to a relative 2e-12 for dof <=
    1e4 (2e-16 dof beyond: the rounding of the tail, see :func:`incomplete_beta`) and for
    |t| <= 1e150 (a tail down to 1e-150 at dof = 1, 1e-300 from dof = 2); NaN outside 0 < p < 1,
    above :data:`DOF_MAX` = 1e9 degrees of freedom or |t| > :data:`T_MAX` = 1e150 (where that
    accuracy no longer holds), or where the iteration did not converge in ``max_iter`` steps
    (<= 40 over that range). Within 1e-10 of p = 1/2 the relative error follows the problem's
    own conditioning (~1e-16/|p - 1/2|: t is ~|p - 1/2| there), as scipy's does.

    The upper tail q = min(p, 1 - p) is solved for t >= 0 by Newton's method on log P(T > t)
    in s = log t (the tail falls as a power of t, so the function is nearly straight there),
    kept inside a bracket that bisection shrinks whenever a step would leave it, until a step
    changes log t by at most 1e-14, from a start right of the root (below).
    """
    p, dof = np.broadcast_arrays(np.asarray(p, dtype=float), np.asarray(dof, dtype=float))
    shape = p.shape
    p, dof = p.ravel(), dof.ravel()
    ok = (p > 0) & (p < 1) & (dof > 0) & (dof <= DOF_MAX)
    q = np.where(ok, np.minimum(p, 1.0 - p), 0.25)
    nu = np.where(ok, dof, 1.0)
    log_b = log_beta(0.5 * nu, 0.5)
    log_q = np.log(q)
    # The start: the density is below ν^(ν/2) t^-(ν+1) / B, so the tail is below
    # ν^(ν/2 - 1) t^-ν / B, and the t where that bound equals q lies right of the root. log P is
    # concave in s (t f(t)/P(T > t) grows from 0 to ν), so Newton's steps from there fall
    # monotonically onto the root: none overshoots, and the bracket is a mere safeguard.
    s = ((0.5 * nu - 1.0) * np.log(nu) - log_b - log_q) / nu
    s = np.clip(s, -690.0, 705.0)
    # The bracket: log P(T > e^s) - log q is >= 0 at lo, < 0 at hi. The density is below f(0),
    # so the tail is above 1/2 - t f(0): lo where that equals q.
    log_f0 = -0.5 * np.log(nu) - log_b
    lo = np.clip(np.log(np.maximum(0.5 - q, 1e-300)) - log_f0, -700.0, s)
    hi = np.full_like(s, 706.0)
    done = q >= 0.5  # the median itself: t = 0
    # (a trial past the tail's underflow gives log 0 = -inf: bisection takes over)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        for _ in range(max_iter):
            t = np.exp(s)
            tail = _t_upper_tail(t, nu)
            g = np.log(tail) - log_q
            lo = np.where(g > 0, s, lo)
            hi = np.where(g <= 0, s, hi)
            # d log P(T > t) / ds = -t f(t) / P(T > t), f(t) = (ν/(ν + t²))^((ν+1)/2) / (√ν B).
            log_f = -0.5 * (nu + 1.0) * _log1p_square(t / np.sqrt(nu)) - 0.5 * np.log(nu) - log_b
            slope = -np.exp(s + log_f - np.log(tail))  # (in logs: t f(t) alone may underflow)
            step = -g / slope
            new = s + step
            newton = (new >= lo) & (new <= hi) & np.isfinite(new)
            new = np.where(newton, new, 0.5 * (lo + hi))
            # Newton's convergence is quadratic: after a step of 1e-14 the next would be ~1e-28,
            # below the rounding of the tail itself. That rounding (~1e-16 of ν relative, see
            # incomplete_beta) can make the last steps swing back and forth about the root; they
            # then close the bracket about it, and its middle ends the iteration.
            size = np.maximum(np.abs(s), 1.0)
            converged = np.abs(new - s) <= _STEP_TOL * size
            closed = (hi - lo) <= _BRACKET_TOL * np.maximum(1.0, 1e-4 * nu) * size
            new = np.where(closed & ~converged, 0.5 * (lo + hi), new)
            converged |= closed
            s = np.where(done, s, new)
            done |= converged
            if done.all():
                break
    t = np.where(q >= 0.5, 0.0, np.exp(s))
    # NaN rather than a wrong number outside the stated range: beyond |t| = 1e150 the tail's
    # continued fraction no longer resolves t (dof <= 2 at p ~ 1e-300 landed near 1e161 where
    # t is 3e299), and above DOF_MAX (in ``ok``) its rounding (2e-16 ν) would pass 2e-7
    # (ν = 1e20 gave 1e5 for 1.96).
    t = np.where(done & ok & (t <= T_MAX), t, np.nan)
    return np.where(p < 0.5, -t, t).reshape(shape)
