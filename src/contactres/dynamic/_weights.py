"""Special functions of the N(r̄, φ) quadrature (paper 1, Eqs. 22 and 27): the Hankel transforms
of the pressure shapes, the WA line average, and Bessel functions of many orders by recurrence.

All arguments and results are dimensionless (s = η a, the surface wave number times the contact
radius).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

__all__ = [
    "bessel_even",
    "bessel_even_sum",
    "bessel_orders",
    "by_real_columns",
    "j1_over_s",
    "real_columns",
    "sinc",
    "spherical_bessel",
    "wa_harmonic_sum",
    "wa_harmonic_weights",
    "wa_harmonic_weights_complex",
    "wa_line_weight",
]


def sinc(s):
    """sin s / s: the Hankel transform of the flat-punch pressure 1/√(1 − ρ²) (paper 1, Eq. 22).

    Parameters
    ----------
    s : array_like, real or complex
        Dimensionless wave number s = η a.

    Returns
    -------
    ndarray
        sin s / s (1 at s = 0).
    """
    return np.sinc(np.asarray(s) / np.pi)


def j1_over_s(s):
    """j₁(s)/s = (sin s − s cos s)/s³: the Hankel transform of the Hertz shape √(1 − ρ²).

    The second pressure of the two-parameter (TP) model (Tian et al. 2004; paper 1, Fig. 3).
    Below ``|s|`` = 0.3 the Taylor series is used: the closed form loses digits to cancellation.

    Parameters
    ----------
    s : array_like, real or complex
        Dimensionless wave number s = η a.

    Returns
    -------
    ndarray
        j₁(s)/s (1/3 at s = 0).
    """
    s = np.asarray(s)
    small = np.abs(s) < 0.3
    z = np.where(small, 1.0, s)
    out = np.asarray((np.sin(z) - z * np.cos(z)) / z**3)
    if np.any(small):  # the series only where it is used (its powers cost more than the rest)
        s2 = s[small] * s[small]
        out[small] = 1 / 3 - s2 / 30 + s2**2 / 840 - s2**3 / 45360 + s2**4 / 3991680
    return out


# Gauss-Laguerre rule for ∫₀^∞ e^{-u} √(1 + u²/z²) du = (π/2)(H₁ − Y₁)(z) (|z| >= 8).
_LAG_X, _LAG_W = np.polynomial.laguerre.laggauss(24)
# Power-series coefficients of W(z) = 1 − (π/2) H₁(z) in z² (|z| < 8).
_W_SERIES = np.array(
    [
        (-1) ** k * (0.5) ** (2 * k + 2) / (special.gamma(k + 1.5) * special.gamma(k + 2.5))
        for k in range(60)
    ]
)
for _constant in (_LAG_X, _LAG_W, _W_SERIES):
    _constant.setflags(write=False)
del _constant


def _series_terms(zmax: float) -> int:
    """Terms of the W series that reach its round-off for ``|z|`` <= zmax (< 8).

    Term k is bounded by ``|c_k|`` zmax^{2k}; the sum stops at the first k beyond the largest term
    where that bound is below 1e-17 × the largest (the series alternates, the terms fall faster
    than geometrically from there, so the dropped rest is below 2e-17 of the largest term,
    i.e. below the round-off of the sum itself, ~1e-16 × the largest term).
    """
    mags = np.abs(_W_SERIES) * zmax ** (2 * np.arange(_W_SERIES.size))
    peak = int(np.argmax(mags))
    below = np.flatnonzero(mags[peak:] < 1e-17 * mags[peak])
    return _W_SERIES.size if below.size == 0 else peak + int(below[0]) + 1


def real_columns(z: np.ndarray) -> int:
    """Where the trailing columns (last axis) of ``z`` whose imaginary parts are all exactly 0
    begin: ``z.shape[-1]`` if the last column has a nonzero one, 0 if all are real.

    The near field's nodes are the complex contour followed by the real hand-over segment
    [T₁, 2T₁] (:func:`~contactres.dynamic._table.wavenumber_nodes`), 32 of the 80 at the
    default resolution: the Bessel sums there run in real arithmetic (a real division costs a
    fraction of numpy's complex one, which is most of a continued fraction's work; issue 31).
    """
    z = np.asarray(z)
    if not np.iscomplexobj(z):
        return 0
    rows = tuple(range(z.ndim - 1))
    complex_columns = np.flatnonzero(np.any(z.imag != 0, axis=rows))
    return int(complex_columns[-1]) + 1 if complex_columns.size else 0


def by_real_columns(fn, z: np.ndarray, *per_column: np.ndarray) -> np.ndarray:
    """``fn(z, *per_column)`` of a function of ``z`` (..., n) column by column (elementwise, as
    :func:`sinc`, or a per-column sum over orders, as :func:`bessel_even_sum` and
    :func:`wa_harmonic_sum` with their coefficients (K + 1, n) in ``per_column``), with the
    trailing real columns of ``z`` (:func:`real_columns`) passed as real arguments: the same
    values there, in real arithmetic (to round-off; a continued fraction of each part starts
    from its own largest ``|z|``, with the margin the caller gives: at the defaults the
    truncation stays below 1e-20; at the near field's 20/10, within ~3e-14 of Σ|c|). Complex,
    shaped like ``z``."""
    split = real_columns(z)
    if split in (0, z.shape[-1]):
        return fn(z, *per_column)
    out = np.empty(z.shape, dtype=np.result_type(z, *per_column))
    out[..., :split] = fn(z[..., :split], *(c[..., :split] for c in per_column))
    real = np.ascontiguousarray(z[..., split:].real)
    out[..., split:] = fn(real, *(c[..., split:] for c in per_column))
    return out


def wa_line_weight(z):
    """W(z) = ∫₀¹ r cos(z r)/√(1 − r²) dr = 1 − (π/2) H₁(z), even in z (H₁: Struve function).

    The weighted average of paper 1, Eq. 27, applied to the plane wave cos(s r̄ cos θ) of Eq. 22.
    Power series for ``|z|`` < 8; for larger ``|z|``,
    W = 1 − (π/2) Y₁(z) − ∫₀^∞ e^{-u} √(1 + u²/z²) du (Re z > 0;
    24-node Gauss-Laguerre, error < 1e-14).

    Parameters
    ----------
    z : array_like, real or complex
        Dimensionless argument s cos θ.

    Returns
    -------
    ndarray
        W(z); real for real input (computed in real arithmetic), complex otherwise.
    """
    z = np.asarray(z)
    real = not np.iscomplexobj(z)
    z = np.abs(z) if real else np.where(z.real < 0, -z, z)
    out = np.empty(z.shape, dtype=float if real else complex)
    small = np.abs(z) < 8
    zs = z[small]
    if zs.size:
        z2 = zs * zs
        acc = np.zeros_like(z2)
        for c in _W_SERIES[: _series_terms(float(np.max(np.abs(zs))))][::-1]:
            acc = acc * z2 + c
        out[small] = 1 - 0.5 * np.pi * acc * z2
    zl = z[~small]
    if zl.size:
        lag = np.sqrt(1 + (_LAG_X[:, None] / zl[None, :]) ** 2).T @ _LAG_W
        y1 = special.y1(zl) if real else special.yv(1, zl)
        out[~small] = 1 - 0.5 * np.pi * y1 - lag
    return out


def bessel_even(orders, s: np.ndarray) -> dict:
    """Bessel functions J_n(s) of many even orders, by recurrence instead of one jv per order.

    Where s > the highest order the upward recurrence from J₀, J₁ is stable; below it the
    downward one (J is its minimal solution), from the ratio J_{top+1}/J_top of the continued
    fraction r_n = s/(2n − s r_{n+1}) started 20 orders above 1.3 max s (Miller's method, as
    :func:`bessel_orders`), normalised on the larger of J₀ and J₁ (scipy's j0 and j1), so that
    no zero of either costs digits. scipy's jv of the two highest orders, the start before,
    cost three times that recurrence (issue 31); the values agree with jv within 6e-15 absolute
    (orders up to 60, s = 1e-9-150; tests/dynamic/test_dynamic.py). The result at each s
    depends only on that s, on the highest order asked for and on the largest of the given s
    below that order (which sets the start).

    Parameters
    ----------
    orders : iterable of int
        Non-negative even orders n.
    s : ndarray
        Real arguments s > 0 (dimensionless).

    Returns
    -------
    dict
        {n: J_n(s)} for every requested order, arrays shaped like ``s``.
    """
    orders = sorted({int(n) for n in orders})
    top = orders[-1]
    row = {n: i for i, n in enumerate(orders)}
    s = np.asarray(s, dtype=float)
    # Every order in one array, each part written by one masked assignment (one per order
    # cost as much as the recurrence on the far-field grid).
    out = np.empty((len(orders), *s.shape))
    up = s > top + 1
    if np.any(up):
        x = s[up]
        block = np.empty((len(orders), x.size))
        j_prev, j_cur = special.j0(x), special.j1(x)
        if 0 in row:
            block[row[0]] = j_prev
        for n in range(1, top):
            j_prev, j_cur = j_cur, (2 * n / x) * j_cur - j_prev
            if n + 1 in row:
                block[row[n + 1]] = j_cur
        out[:, up] = block
    down = ~up
    if np.any(down):
        x = s[down]
        block, ok = _bessel_down(orders, x)
        # Where the unnormalised values overflow (s << top) the recurrence has nothing to carry.
        if not np.all(ok):
            block[:, ~ok] = [special.jv(n, x[~ok]) for n in orders]
        out[:, down] = block
    return {n: out[i] for i, n in enumerate(orders)}


def _bessel_down(orders: list, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """J_n(x), n in the sorted even ``orders``, of real 0 < x <= the highest order + 1, as a
    (len(orders), x.size) block, by the downward recurrence of :func:`bessel_even`; and where
    it is finite (False: the unnormalised values overflowed, x far below the highest order)."""
    top = orders[-1]
    # Truncation of the continued fraction falls like (x/2N)^(2(N − n)) above 1.3 x: 20 orders
    # leave it below round-off (as the near field's margin of bessel_even_sum); no denominator
    # vanishes, J_{n−1}(x) > 0 for n − 1 >= x.
    start = max(top + 12, math.ceil(1.3 * float(np.max(x))) + 20)
    ratio = np.zeros_like(x)
    den = np.empty_like(x)
    for n in range(start, top, -1):
        np.multiply(x, ratio, out=den)
        np.subtract(2 * n, den, out=den)
        np.divide(x, den, out=ratio)  # r_n = J_n/J_{n−1}, down to r_{top+1}
    row = {n: i for i, n in enumerate(orders)}
    block = np.empty((len(orders), x.size))
    # J_top -> 1, J_{top+1} -> r_{top+1}; scaled at the end.
    j_next, j_cur = ratio, np.ones_like(x)
    j_one = j_cur
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        for n in range(top, 0, -1):
            if n in row:
                block[row[n]] = j_cur
            if n == 1:
                j_one = j_cur
            j_next, j_cur = j_cur, (2 * n / x) * j_cur - j_next
        if 0 in row:
            block[row[0]] = j_cur
        j0, j1 = special.j0(x), special.j1(x)
        scale = np.where(np.abs(j0) >= np.abs(j1), j0 / j_cur, j1 / j_one)
        ok = np.isfinite(j_cur) & np.isfinite(j_one) & np.isfinite(scale)
        block *= scale
    return block, ok


def wa_harmonic_weights(s: np.ndarray, n_max: int) -> np.ndarray:
    """W_n(s) = ∫₀¹ J_n(s r) r/√(1 − r²) dr for even n = 0, 2, ..., n_max (paper 1, Eq. 27).

    The weighted average of Eq. 27 of the angular harmonic e^{inθ} of the displacement. By
    Jacobi-Anger, W(s cos θ) = Σ_n iⁿ W_n(s) e^{inθ}: the W_n are the Fourier coefficients of the
    line weight :func:`wa_line_weight` over θ. They are summed from spherical Bessel functions,

        W_{2k}(s) = Σ_{p >= k} (−1)^{p−k} (2p + 1) j_p(s/2)²,

    from J_{n−1} + J_{n+1} = (2n/x) J_n and ∫₀¹ J_{2k−1}(s r)/√(1 − r²) dr = (π/2) J_{k−½}(s/2)²
    (W_{2k} + W_{2k−2} = (2k − 1) j_{k−1}(s/2)², with W₀ = Σ (−1)^p (2p + 1) j_p(s/2)² = sin s/s).
    For these real s they are summed upwards from W₀ = sin s/s by that relation
    (:func:`_wa_upward`: the orders below n_max/2 alone; accurate to round-off of the largest
    W, absolutely); the complex ones of :func:`wa_harmonic_weights_complex`, from the top.
    Unlike an FFT of the line weight over θ, no θ grid has to resolve W(s cos θ), and no
    harmonic aliases onto another.

    Parameters
    ----------
    s : ndarray
        Real arguments s >= 0 (dimensionless), 1-D.
    n_max : int
        Highest even order.

    Returns
    -------
    ndarray
        Shape (n_max/2 + 1, s.size): row j holds W_{2j}(s).
    """
    s = np.asarray(s, dtype=float)
    k_max = n_max // 2
    if s.size == 0:
        return np.zeros((k_max + 1, 0))
    # j_p(0) = δ_p0: the sum then gives W₀(0) = 1 and W_n(0) = 0 without dividing by s.
    x = np.where(s > 0, 0.5 * s, 1.0)
    out = _wa_upward(k_max, x)
    out[:, s <= 0] = 0.0
    out[0, s <= 0] = 1.0
    return out


def _wa_upward(k_max: int, x: np.ndarray) -> np.ndarray:
    """W_{2k}(2x), k = 0..k_max, of real x > 0, upwards from W₀(2x) = sin 2x/2x by
    W_{2k} = (2k − 1) j_{k−1}(x)² − W_{2k−2} (:func:`wa_harmonic_weights`), i.e.
    W_{2k} = (−1)^k [W₀ + Σ_{i <= k} (−1)^i (2i − 1) j_{i−1}²].

    It needs the orders p < k_max alone, where the sum from the top (:func:`_wa_from_spherical`)
    needs them up to 1.3 x + 20 and a continued fraction from 30 above (~110 orders at s = 120,
    where the far field stops it; issue 31). The sum only adds, so no error is amplified: it is
    accurate to round-off of the largest term, ~5e-16 absolute against the sum from the top for
    k_max = 4-46, x = 1e-4-62 (measured), where the W are at most 1. A W_{2k} far below that,
    at x << k, has that absolute error, not a relative one: the far field, its only user, sums
    the weights against the kernel's coefficients, where only absolute errors count.
    """
    j = spherical_bessel(max(k_max - 1, 0), x)[:k_max]  # j_0 .. j_{k_max − 1}
    i = np.arange(1, k_max + 1)[:, None]
    out = np.empty((k_max + 1, x.size))
    out[0] = np.sin(2 * x) / (2 * x)
    np.cumsum(np.where(i % 2 == 0, 1.0, -1.0) * (2 * i - 1) * (j * j), axis=0, out=out[1:])
    out[1:] += out[0]
    out *= np.where(np.arange(k_max + 1) % 2 == 0, 1.0, -1.0)[:, None]
    return out


def wa_harmonic_weights_complex(z: np.ndarray, k_max: int) -> np.ndarray:
    """W_{2k}(z), k = 0..k_max, of :func:`wa_harmonic_weights` for complex z (``|z|`` > 0).

    Parameters
    ----------
    z : ndarray
        Nonzero complex (or real) arguments of any shape; ``|Im z|`` moderate (<~10).
    k_max : int
        Highest index k (order 2 k_max).

    Returns
    -------
    ndarray
        Shape ``(k_max + 1, *z.shape)``.
    """
    return _wa_from_spherical(k_max, 0.5 * np.asarray(z))


def wa_harmonic_sum(z: np.ndarray, coeffs: np.ndarray, *, margin: int = 20) -> np.ndarray:
    """Σ_k W_{2k}(z) c_k, the WA weights of :func:`wa_harmonic_weights_complex` summed against
    coefficients c_k, without the weights themselves (paper 1, Eq. 27; the near field of
    :func:`contactres.dynamic._quadrature.near_theta_integrals`).

    With W_{2k}(2x) = Σ_{p >= k} (−1)^{p−k} (2p + 1) j_p(x)², the order of the sums turns:
    Σ_k W_{2k} c_k = Σ_p (2p + 1) j_p(x)² F_p, F_p = Σ_{k <= min(p, K)} (−1)^{p−k} c_k. The
    F_p are partial sums of the coefficients alone (no z), so the work per argument is one
    product and sum over the orders p, not the suffix sums of every W_{2k} (issue 31: a third
    of the near field of the five-model curve). The sum over p is taken by Horner's rule during
    the downward pass of the continued fraction of :func:`spherical_bessel` (the same ratios
    r_p = j_p/j_{p−1}, from the same start): with f_p = (2p + 1) F_p,
    Σ_{p >= 1} f_p j_p² = j₁² U₁, U_p = f_p + r_{p+1}² U_{p+1}, so the sum is j₀² (f₀ + r₁² U₁)
    anchored on j₀, or j₀² f₀ + j₁² U₁ on j₁ (the larger of the two, as
    :func:`spherical_bessel` anchors). No array over the orders is made (issue 31: those
    arrays, fresh memory on every call, cost more than the arithmetic). Absolute round-off
    ~1e-16 × Σ_k ``|c_k|``, as for the weights summed one by one.

    Parameters
    ----------
    z : ndarray
        Nonzero complex (or real) arguments, shape (..., n); ``|Im z|`` moderate (<~10).
    coeffs : ndarray
        c_k, k = 0..K, shape (K + 1, n) (one set per last index of ``z``) or (K + 1,).
    margin : int
        Keyword only: the orders summed reach ``margin`` beyond 1.3 max ``|z/2|`` (default 20,
        with a wide margin; 10, as the near field of
        :func:`~contactres.dynamic._quadrature.near_theta_integrals` takes, leaves the same
        round-off, tests/dynamic/test_near_harmonics.py).

    Returns
    -------
    ndarray
        Σ_k W_{2k}(z) c_k, shaped like ``z``.
    """
    x = 0.5 * np.asarray(z)
    c = np.asarray(coeffs)
    k_max = c.shape[0] - 1
    # The orders whose terms reach round-off (_wa_orders) and no more: unlike the weights
    # one by one, the sum needs no order p above them for its rows k <= K (F_p stops at p).
    p_max = _wa_orders(0, x, margin)
    # f_p = (2p + 1) F_p = (2p + 1) (−1)^p G_min(p, K), G_k = Σ_{i <= k} (−1)^i c_i.
    p = np.arange(p_max + 1)
    sign = np.where(p % 2 == 0, 1.0, -1.0)
    k_max = min(k_max, p_max)  # W_{2k}, k > p_max, are below round-off: no order p reaches k
    g = np.cumsum(sign[: k_max + 1].reshape(-1, *([1] * (c.ndim - 1))) * c[: k_max + 1], axis=0)
    f = g[np.minimum(p, k_max)] * (sign * (2 * p + 1)).reshape(-1, *([1] * (c.ndim - 1)))
    # Start of the continued fraction at N = p_max + 5: its truncation error falls like
    # (|x|/2N)^(2(N − p)), and the orders that carry the sum, p <= 1.3|x| + 5, lie 20 below
    # p_max: below (1/2.6)^50 ~ 1e-21 there. (Starting 25 orders higher, at spherical_bessel's
    # N, changes no bit of the sum for |z| <= 120.)
    return _finite_pass(_wa_sum_pass, x, f, p_max + 5)


def _next_ratio(z, above, out, den, order: int, guard: bool) -> None:
    """``out`` = z/(order − z ``above``): one step down the continued fraction of the ratios of
    Bessel functions (order 2n for J_n/J_{n−1}, 2p + 1 for j_p/j_{p−1}), in place (``den``: a
    work array); ``guard``: a denominator that rounds to zero becomes its rounding error, as in
    :func:`bessel_orders`, so that the ratio stays finite."""
    np.multiply(z, above, out=den)
    np.subtract(order, den, out=den)
    if guard:
        den[den == 0] = order * np.finfo(float).eps
    np.divide(z, den, out=out)


def _finite_pass(run, *args):
    """``run(*args, guard=False)``, a downward pass of a continued fraction; a denominator that
    rounds to zero (the function below it is 0 to the last bit) makes it non-finite: only then
    is it run again with ``guard=True``, which keeps that ratio finite (the guard costs a
    quarter of the pass on every order)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = run(*args, guard=False)
    if np.all(np.isfinite(out)):
        return out
    return run(*args, guard=True)


def _wa_sum_pass(x: np.ndarray, f: np.ndarray, top: int, guard: bool) -> np.ndarray:
    """Σ_p f_p j_p(x)², p = 0..len(f) − 1, by Horner's rule in the downward pass of the ratios
    r_p = j_p/j_{p−1} from the order ``top`` (:func:`wa_harmonic_sum`; ``guard``: keep a
    denominator that rounds to zero finite)."""
    p_max = f.shape[0] - 1
    # r_{p+1} then r_p, r_{p+1} while r_p is made, and two work arrays.
    ratio, above, den, square = np.zeros((4, *x.shape), dtype=np.result_type(x, float))
    acc = np.zeros(x.shape, dtype=np.result_type(x, float, f))  # U_{p+1}, then U_p
    for p in range(top, 0, -1):
        ratio, above = above, ratio
        _next_ratio(x, above, ratio, den, 2 * p + 1, guard)  # r_p = x/(2p + 1 − x r_{p+1})
        if p <= p_max:  # U_p = f_p + r_{p+1}² U_{p+1} (U_{p_max} = f_{p_max})
            np.multiply(above, above, out=square)
            acc *= square
            acc += f[p]
    j0 = np.sin(x) / x
    j1 = (j0 - np.cos(x)) / x
    # Anchor on j₀ where it is the larger of the two, on j₁ elsewhere (ratio = r₁).
    use0 = np.abs(j0) >= np.abs(j1)
    j1 = np.where(use0, j0 * ratio, j1)
    return j0 * j0 * f[0] + j1 * j1 * acc


def _wa_orders(k_max: int, x: np.ndarray, margin: int = 20) -> int:
    """Highest order p of the spherical Bessel sums of the W_{2k}(2x), k <= k_max, ``margin``
    orders beyond 1.3 max ``|x|``."""
    xmax = float(np.max(np.abs(x), initial=0.0))
    # Beyond p ~ 1.3|x| the terms fall by (|x|/2p)² < 0.15 per order: 20 more leave < 1e-16.
    return int(max(k_max, math.ceil(1.3 * xmax)) + margin)


def _wa_from_spherical(k_max: int, x: np.ndarray) -> np.ndarray:
    """W_{2k}(2x) = Σ_{p >= k} (−1)^{p−k} (2p + 1) j_p(x)², k = 0..k_max (x nonzero)."""
    p_max = _wa_orders(k_max, x)
    j = spherical_bessel(p_max, x)
    p = np.arange(p_max + 1).reshape(-1, *([1] * x.ndim))
    signed = j * j
    signed *= np.where(p % 2 == 0, 1.0, -1.0) * (2 * p + 1)
    # Suffix sums from the highest order down (the small terms first).
    tail = np.cumsum(signed[::-1], axis=0)[::-1][: k_max + 1]
    tail *= np.where(p[: k_max + 1] % 2 == 0, 1.0, -1.0)
    return tail


def bessel_orders(n_max: int, z: np.ndarray) -> np.ndarray:
    """Bessel functions J_n(z), n = 0..n_max, of real or complex nonzero z (Miller's method).

    The ratios r_n = J_n/J_{n−1} from the continued fraction r_n = z/(2n − z r_{n+1}), run
    downwards from r = 0 at an order well above n_max and ``|z|`` (J is the minimal solution of the
    recurrence, so the ratios are stable), normalised by 1 = J₀ + 2 Σ_k J_{2k}. Written with
    d = 2 − z r₂ (r₁ = z/d) as J₀ = d/D, J_n = z Q_n/D, Q_n = r₂ ⋯ r_n, D = d + 2z Σ_k Q_{2k},
    nothing is divided by J₀ (which vanishes on the real axis) and nothing overflows. The
    normalisation loses ~ max_n ``|J_n|`` ~ e^{``|Im z|``} digits' worth, harmless for the moderate
    imaginary parts of the near-field contour. For complex z, where scipy's jv (AMOS) costs
    a call per order and point; real z > 0 is cheaper with :func:`bessel_even`.

    Parameters
    ----------
    n_max : int
        Highest order (>= 0).
    z : ndarray
        Nonzero arguments (dimensionless), real or complex, of any shape.

    Returns
    -------
    ndarray
        Shape ``(n_max + 1, *z.shape)``: row n holds J_n(z).
    """
    z = np.asarray(z)
    zmax = float(np.max(np.abs(z), initial=0.0))
    # Truncation of the continued fraction falls like (|z|/2N)^(2(N − n)): 30 orders above
    # 1.3|z| for the orders that carry the sum, 12 above n_max for the smallest (where
    # |z|/2N < 0.4 bounds the error by 1e-10 of a J_n itself < 1e-8 of the largest). Even.
    top = 2 * math.ceil(max(n_max + 12, 1.3 * zmax + 30) / 2)
    ratios = np.empty((top + 2, *z.shape), dtype=np.result_type(z, float))
    ratios[top + 1] = 0.0
    den = np.empty(z.shape, dtype=ratios.dtype)
    for n in range(top, 1, -1):
        # In place: this loop over ~100 orders is most of the cost.
        np.multiply(z, ratios[n + 1], out=den)
        np.subtract(2 * n, den, out=den)
        # Zero only where J_{n−1}(z) rounds to 0: a denominator of its rounding error instead
        # keeps r_n finite (r_{n−1} ~ 1/r_n then returns J_{n−1} ~ 1e-16, as it should).
        den[den == 0] = 2 * n * np.finfo(float).eps
        np.divide(z, den, out=ratios[n])
    d = 2 - z * ratios[2]
    q = np.empty_like(ratios)
    q[1] = 1.0
    for n in range(2, top + 1):
        np.multiply(q[n - 1], ratios[n], out=q[n])
    denom = d + 2 * z * np.sum(q[2::2], axis=0)
    out = np.empty((n_max + 1, *z.shape), dtype=ratios.dtype)
    out[0] = d / denom
    if n_max:
        out[1:] = q[1 : n_max + 1] * (z / denom)
    return out


def bessel_even_sum(z: np.ndarray, coeffs: np.ndarray, *, margin: int = 30) -> np.ndarray:
    """Σ_m J_{2m}(z) c_m, m = 0..K, of nonzero real or complex z, without the J_{2m} themselves
    (the near field of :func:`contactres.dynamic._quadrature.near_theta_integrals`).

    Miller's method as in :func:`bessel_orders` (the same continued fraction, started at the
    same order, so the same ratios r_n = J_n/J_{n−1}), with the sums that need the products
    Q_n = r₂ ⋯ r_n taken by Horner's rule during the downward pass, from the small terms up:
    Σ_{k >= 1} Q_{2k} = r₂ A₂, A_{2k} = 1 + r_{2k+1} r_{2k+2} A_{2k+2}, and likewise
    Σ_{m >= 1} c_m Q_{2m} = r₂ V₂, V_{2m} = c_m + r_{2m+1} r_{2m+2} V_{2m+2}. Then
    J₀ = d/D, J_n = z Q_n/D (d = 2 − z r₂, D = d + 2z r₂ A₂), so the sum is
    (c₀ d + z r₂ V₂)/D. No array over the orders is kept (issue 31: half the cost of the
    orders of :func:`bessel_orders` and of the product with c).

    Parameters
    ----------
    z : ndarray
        Nonzero arguments (dimensionless), real or complex, shape (..., n).
    coeffs : ndarray
        c_m, m = 0..K, shape (K + 1, n) (one set per last index of ``z``) or (K + 1,).
    margin : int
        Keyword only: the continued fraction starts ``margin`` orders above 1.3 max ``|z|``,
        (default 30: truncation ~1e-20; 20, as the near field of
        :func:`~contactres.dynamic._quadrature.near_theta_integrals` takes, leaves the same
        round-off, tests/dynamic/test_near_harmonics.py); the c_m of orders 2m at or above that
        start are left out: each costs at most max_{n >= start} ``|J_n(z)|`` times ``|c_m|``,
        for ``|Re z|`` <= 60, ``|Im z|`` <= 3 below 1e-18 at margin 30, 4e-13 at 20 and 2.3e-7
        at 10 (the largest at ``|z|`` ~ 14-28).

    Returns
    -------
    ndarray
        Σ_m J_{2m}(z) c_m, shaped like ``z`` (complex if z or c is).
    """
    z = np.asarray(z)
    c = np.asarray(coeffs)
    zmax = float(np.max(np.abs(z), initial=0.0))
    # The start of bessel_orders (its truncation error, even), not raised to 2K + 12 (that
    # bound is for J_2K itself to relative accuracy, which a sum does not need): the terms of
    # the orders 2k >= top are dropped, each at most max_{n >= top} |J_n(z)| per |c_k| (scipy's
    # jv, |Re z| <= 60, |Im z| <= 3: 3.7e-13 at margin 20, 2.3e-7 at margin 10, the coarse
    # margin of rtol >= 1e-4; tests/dynamic/test_near_harmonics.py). The
    # number of steps, not their size, is the cost of these passes (arrays of a few thousand
    # values; issue 31): on the near-field contour at rtol 1e-6, 32 orders instead of 58.
    top = 2 * math.ceil((1.3 * zmax + margin) / 2)
    # Rerun with the guard of bessel_orders only where J_{n−1}(z) rounds to 0 (_finite_pass).
    return _finite_pass(_even_sum_pass, z, c, top)


def _even_sum_pass(z: np.ndarray, c: np.ndarray, top: int, guard: bool) -> np.ndarray:
    """The downward pass of :func:`bessel_even_sum` from the order ``top`` (``guard``: keep a
    denominator that rounds to zero finite, as :func:`bessel_orders` does)."""
    k_max = c.shape[0] - 1
    dtype = np.result_type(z, float)
    ratio = np.zeros(z.shape, dtype=dtype)  # r_{n+1}, then r_n
    above = np.zeros(z.shape, dtype=dtype)  # r_{n+1} while r_n is made
    den = np.empty(z.shape, dtype=dtype)
    pair = np.empty(z.shape, dtype=dtype)
    acc_a = np.ones(z.shape, dtype=np.result_type(dtype))  # A_top = 1
    acc_v = np.zeros(z.shape, dtype=np.result_type(dtype, c))  # V beyond K: 0
    for n in range(top, 1, -1):
        ratio, above = above, ratio
        _next_ratio(z, above, ratio, den, 2 * n, guard)  # r_n = z/(2n − z r_{n+1})
        if n % 2 == 1:  # n = 2k + 1: A_{2k} and V_{2k} from r_{2k+1} r_{2k+2}
            np.multiply(ratio, above, out=pair)
            acc_a *= pair
            acc_a += 1
            k = n // 2
            if k <= k_max:
                acc_v *= pair
                acc_v += c[k]
    d = 2 - z * ratio  # ratio = r₂
    total = d + 2 * z * ratio * acc_a
    return (c[0] * d + z * ratio * acc_v) / total


# ln of the relative truncation error the continued fraction of spherical_bessel is started
# for, at its highest order: e^−46 ~ 1e-20, 1e-4 of a unit in the last place.
_LOG_TRUNCATION = -46.0


def _fraction_start(p_max: int, zmax: float) -> int:
    """The order N at which the continued fraction r_p = z/(2p + 1 − z r_{p+1}) of
    :func:`spherical_bessel` starts (r_{N+1} = 0) for orders up to ``p_max`` and ``|z|`` <=
    ``zmax``.

    Setting r_{N+1} = 0 errs in r_p by the relative amount Π_{k=p+1}^{N+1} ρ_k, ρ_k the ratio
    of the steps j_k/j_{k−1} and y_k/y_{k−1} of the minimal and dominant solutions of the
    recurrence; above the turning point (k > ``|z|``) j_k/j_{k−1} <= ``|z|``/2k and y_k/y_{k−1}
    >= (2k − 1)/``|z|`` − ``|z|``/(2k − 3), so ρ_k <= (``|z|``/2k)/((2k − 1)/``|z|`` −
    ``|z|``/(2k − 3)) (~``|z|``²/4k²). Where every argument is below p_max − 1 the start is
    the first N at which that product, from p_max + 1, falls below e^−46 (~1e-20): a few to
    ~20 orders above p_max (N = 42 at p_max = 34, ``|z|`` <= 3.5) instead of the classical
    max(p_max, 1.3 ``|z|``) + 30 (64), which stays the start for larger arguments (and caps the
    other). The error at lower orders is smaller still (each step below p_max multiplies it by
    another ρ_k < 1 until the turning point). Miller's algorithm: F. W. J. Olver, "Error
    analysis of Miller's recurrence algorithm", Math. Comp. 18, 65-74 (1964)."""
    classic = int(max(p_max, 1.3 * zmax) + 30)
    if not zmax < p_max - 1:  # near or past the turning point (or NaN): the classic start
        return classic
    z = max(zmax, 1e-300)
    log_err, k = 0.0, p_max
    while log_err > _LOG_TRUNCATION and k < classic:
        k += 1
        log_err += math.log(z / (2 * k)) - math.log((2 * k - 1) / z - z / (2 * k - 3))
    return k


def spherical_bessel(p_max: int, z: np.ndarray) -> np.ndarray:
    """Spherical Bessel functions j_p(z), p = 0..p_max, of real or complex z (``|z|`` > 0).

    j₀ = sin z/z and j₁ = (sin z/z − cos z)/z in closed form; above them the ratios
    r_p = j_p/j_{p−1} from the continued fraction r_p = z/(2p + 1 − z r_{p+1}), run downwards
    from r = 0 at an order well above p_max and ``|z|`` (j is the minimal solution of the
    recurrence, so the ratios are stable and nothing overflows; high orders at small z
    underflow gracefully to 0). Every j_p is anchored on the larger of ``|j₀|`` and ``|j₁|``, so
    that no zero of either costs digits. Relative accuracy ~1e-15 (tested against scipy's
    half-integer order jv), one pass over the orders instead of one scipy call per order.

    Parameters
    ----------
    p_max : int
        Highest order (>= 0).
    z : ndarray
        Arguments (dimensionless), real or complex, nonzero; ``|Im z|`` is moderate (the
        near-field contour keeps it below ~10).

    Returns
    -------
    ndarray
        Shape ``(p_max + 1, *z.shape)``: row p holds j_p(z).
    """
    z = np.asarray(z)
    out = np.empty((p_max + 1, *z.shape), dtype=z.dtype if np.iscomplexobj(z) else float)
    sin, cos = np.sin(z), np.cos(z)
    out[0] = sin / z
    if p_max == 0:
        return out
    out[1] = (out[0] - cos) / z
    flat = out.reshape(p_max + 1, -1)
    zf = z.ravel()
    # Real z beyond every order: the upward recurrence is stable there (j oscillates and no
    # order is small), and cheaper than a continued fraction started above 1.3 z (the far-field
    # grid reaches z ~ 600 for orders <= ~40).
    up = np.zeros(zf.shape, dtype=bool) if np.iscomplexobj(z) else zf > p_max + 1
    if np.any(up):
        zu = zf[up]
        j_prev, j_cur = flat[0, up], flat[1, up]
        block = np.empty((p_max + 1, zu.size))
        block[0], block[1] = j_prev, j_cur
        for p in range(1, p_max):
            np.multiply((2 * p + 1) / zu, block[p], out=block[p + 1])
            block[p + 1] -= block[p - 1]
        flat[:, up] = block
    low = ~up
    if not np.any(low):
        return out
    # Every argument below (complex z, the near field): work on ``out`` itself, without
    # gathering the columns into a copy and scattering them back (~2 ms at 40 x 80 x 48).
    every = bool(np.all(low))
    zl = zf if every else zf[low]
    sub = flat if every else flat[:, low]
    top = _fraction_start(p_max, float(np.max(np.abs(zl), initial=0.0)))
    ratio = np.zeros_like(sub[0])
    den = np.empty_like(ratio)
    # The ratios j_p / j_{p-1} kept in the rows p >= 2 of the result itself (each row then
    # turned into j_p in place, upwards), j_1 / j_0 apart: no second array of the result's
    # size, fresh pages on every call.
    ratio1 = np.empty_like(ratio)
    for p in range(top, 0, -1):
        # In place: this loop over ~100 orders is most of the cost for complex z.
        np.multiply(zl, ratio, out=den)
        np.subtract(2 * p + 1, den, out=den)
        if p <= p_max:
            ratio = sub[p] if p >= 2 else ratio1
        np.divide(zl, den, out=ratio)
    # Anchor on j₀ where it is the larger of the two, on j₁ elsewhere.
    use0 = np.abs(sub[0]) >= np.abs(sub[1])
    sub[1] = np.where(use0, sub[0] * ratio1, sub[1])
    for p in range(2, p_max + 1):
        np.multiply(sub[p - 1], sub[p], out=sub[p])
    if not every:
        flat[:, low] = sub
    return out
