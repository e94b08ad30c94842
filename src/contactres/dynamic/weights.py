"""Special functions of the N(r̄, φ) quadrature (paper 1, Eqs. 22 and 27): the Hankel transforms
of the pressure shapes, the WA line average, and Bessel functions of many orders by recurrence.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special


def _sinc(s):
    """sin s / s (Hankel transform of the flat-punch shape 1/√(1 − ρ²)); complex s allowed."""
    return np.sinc(np.asarray(s) / np.pi)


def _j1s(s):
    """j₁(s)/s = (sin s − s cos s)/s³ (Hankel transform of the Hertz shape √(1 − ρ²))."""
    s = np.asarray(s)
    small = np.abs(s) < 0.3
    z = np.where(small, 1.0, s)
    full = (np.sin(z) - z * np.cos(z)) / z**3
    s2 = s * s
    series = 1 / 3 - s2 / 30 + s2**2 / 840 - s2**3 / 45360 + s2**4 / 3991680
    return np.where(small, series, full)


# Gauss-Laguerre rule for ∫₀^∞ e^{-u} √(1 + u²/z²) du = (π/2)(H₁ − Y₁)(z) (|z| >= 8).
_LAG_X, _LAG_W = np.polynomial.laguerre.laggauss(24)
# Power-series coefficients of W(z) = 1 − (π/2) H₁(z) in z² (|z| < 8).
_W_SERIES = np.array(
    [
        (-1) ** k * (0.5) ** (2 * k + 2) / (special.gamma(k + 1.5) * special.gamma(k + 2.5))
        for k in range(60)
    ]
)


def _wa_line_weight(z):
    """W(z) = ∫₀¹ r cos(z r)/√(1 − r²) dr = 1 − (π/2) H₁(z), even in z, complex z allowed.

    The WA average (Eq. 27) of cos(s r̄ cos θ). Power series for |z| < 8; for larger |z|,
    W = 1 − (π/2) Y₁(z) − ∫₀^∞ e^{-u} √(1 + u²/z²) du (Re z > 0; Gauss-Laguerre, error < 1e-14).
    Real input gives a real result (and runs in real arithmetic).
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
        for c in _W_SERIES[::-1]:
            acc = acc * z2 + c
        out[small] = 1 - 0.5 * np.pi * acc * z2
    zl = z[~small]
    if zl.size:
        lag = np.sqrt(1 + (_LAG_X[:, None] / zl[None, :]) ** 2).T @ _LAG_W
        y1 = special.y1(zl) if real else special.yv(1, zl)
        out[~small] = 1 - 0.5 * np.pi * y1 - lag
    return out


def _bessel_even(orders, s: np.ndarray) -> dict:
    """{n: J_n(s)} for the even ``orders``, real s > 0: recurrences instead of one jv per order.

    Where s > the highest order the upward recurrence from J₀, J₁ is stable; below it the
    downward one from scipy's two highest orders (J is its minimal solution). scipy's jv of a
    high order is slow at large s, which is exactly where it is not needed.
    """
    orders = sorted({int(n) for n in orders})
    top = orders[-1]
    want = set(orders)
    s = np.asarray(s, dtype=float)
    out = {n: np.empty(s.shape) for n in orders}
    up = s > top + 1
    if np.any(up):
        x = s[up]
        j_prev, j_cur = special.j0(x), special.j1(x)
        if 0 in want:
            out[0][up] = j_prev
        for n in range(1, top):
            j_prev, j_cur = j_cur, (2 * n / x) * j_cur - j_prev
            if n + 1 in want:
                out[n + 1][up] = j_cur
    down = ~up
    if np.any(down):
        x = s[down]
        j_next = special.jv(top + 1, x)
        j_top = j_cur = special.jv(top, x)
        for n in range(top, -1, -1):
            if n in want:
                out[n][down] = j_cur
            if n == 0:
                break
            j_next, j_cur = j_cur, (2 * n / x) * j_cur - j_next
        # Where the starting values underflow (s << top) the recurrence has nothing to carry.
        low = np.abs(j_top) < 1e-280
        if np.any(low):
            idx = np.flatnonzero(down)[low]
            for n in orders:
                out[n].flat[idx] = special.jv(n, x[low])
    return out


def _wa_harmonic_weights(s: np.ndarray, n_max: int) -> np.ndarray:
    """W_n(s) = ∫₀¹ J_n(s r) r/√(1 − r²) dr for even n = 0, 2, ..., n_max; shape (n_max/2 + 1, ns).

    By Jacobi-Anger, W(s cos θ) = Σ_n iⁿ W_n(s) e^{inθ}: the W_n are the Fourier coefficients of
    the line weight :func:`_wa_line_weight` over θ (FFT, exact once the grid resolves them).
    """
    s = np.asarray(s, dtype=float)
    smax = float(np.max(s, initial=0.0))
    n_t = 8 * math.ceil(max(n_max + 2, n_max / 2 + 0.3 * smax + 24) / 8)
    theta = np.pi * np.arange(n_t) / n_t
    vals = _wa_line_weight(np.multiply.outer(s, np.cos(theta)))
    coef = np.fft.rfft(vals, axis=-1).real / n_t  # harmonic j of e^{2ijθ}
    j = np.arange(n_max // 2 + 1)
    return (coef[:, j] * np.where(j % 2 == 0, 1.0, -1.0)).T
