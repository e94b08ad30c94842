"""The layered correction on the shared arc, interpolated in the frequency instead of solved at
every point.

On the arc s = S₁ z(τ) shared by the frequencies of one stack (S₁ = T a, T = p₁ ω,
``contactres.dynamic._layered_path``) the layer waves depend on τ alone (their slowness is
1/(p₁ z)²: ``contactres.dynamic._layered_waves``) and each layer's exponent η h_j = (s/a) h_j
= T h_j z(τ): the radius cancels, and Δg at a node τ depends on the point only through T
(β = T h, h the total thickness: at most ~0.2 for 250 nm of PMMA on quartz at k_s a <= 2).
Δg is analytic in T there (the exponentials exp(η h_j A) are entire in it, and the poles of
the stack's response lie off the arc), so a polynomial through a few solutions at
Chebyshev–Lobatto points of the points' range [T_lo, T_hi] gives every point's values.

How many: the degree n is accepted when the last two Chebyshev coefficients of every entry,
which bound the interpolation error of a geometrically converging series up to a factor of
order one, are below :data:`ARC_TOL` of the largest ``|Δg|`` sampled (measured on PMMA over
quartz: at n = 12 the estimate is 4e-16 and the error 7e-16 for 250 nm; the 1 µm film needs
n = 24). First n = 12, then n = 24 (the same points and 12 new ones: Lobatto points nest) only
where the first estimate is small enough for the doubled degree to reach the bound (the
coefficients fall geometrically: doubling the degree about squares their ratio), and only if
the solutions stay fewer than the points; otherwise (thick films, a wide range of T, few
points) the points are solved directly.

References: L. N. Trefethen, *Approximation Theory and Approximation Practice* (SIAM, 2013),
Ch. 3 (Chebyshev coefficients) and Ch. 8 (their geometric decay for analytic functions);
J.-P. Berrut and L. N. Trefethen, SIAM Rev. 46, 501 (2004) (barycentric formula).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..numerics import lobatto_weights

__all__ = ["ARC_TOL", "ParameterFit", "chebyshev_coefficients", "fit_in_parameter"]

#: The interpolation error bound (the last two Chebyshev coefficients) relative to the largest
#: |Δg| sampled: 100 times below the smallest rtol the punch accepts (1e-10), so the curve moves
#: by round-off only.
ARC_TOL = 1e-12
#: The degrees tried (Lobatto points nest: the second reuses every solution of the first).
DEGREES = (12, 24)


def lobatto_points(n: int) -> np.ndarray:
    """The n + 1 Chebyshev–Lobatto points cos(π j/n), j = 0..n, on [−1, 1]."""
    return np.cos(np.pi * np.arange(n + 1) / n)


def chebyshev_coefficients(values: np.ndarray) -> np.ndarray:
    """c_k (n + 1, ...) of the polynomial Σ c_k T_k(x) through ``values`` (n + 1, ...) at the
    Lobatto points cos(π j/n): c_k = (2/n) Σ''_j f_j cos(π jk/n), the first and last halved
    (the discrete cosine transform of type I; Trefethen 2013, Ch. 3)."""
    n = values.shape[0] - 1
    k = np.arange(n + 1)
    half = np.where((k == 0) | (k == n), 0.5, 1.0)
    c = (2.0 / n) * np.tensordot(np.cos(np.pi * np.outer(k, k) / n) * half, values, axes=1)
    c[[0, n]] *= 0.5
    return c


class ParameterFit:
    """The polynomial through samples (n + 1, ...) at the Lobatto points of [lo, hi] of one
    real parameter; called at parameters t (m,) it gives (m, ...) (the barycentric formula of
    the second kind; a sample itself where t falls on its point)."""

    __slots__ = ("hi", "lo", "samples")

    def __init__(self, lo: float, hi: float, samples: np.ndarray):
        self.lo, self.hi, self.samples = lo, hi, samples

    def __call__(self, t: np.ndarray) -> np.ndarray:
        n = self.samples.shape[0] - 1
        x = (2 * np.asarray(t, dtype=float) - self.lo - self.hi) / (self.hi - self.lo)
        d = x[:, None] - lobatto_points(n)[None, :]
        with np.errstate(divide="ignore", invalid="ignore"):
            c = lobatto_weights(n + 1)[None, :] / d
            total = np.sum(c, axis=1)
            out = np.tensordot(c, self.samples, axes=1)
            out /= total.reshape(-1, *([1] * (out.ndim - 1)))
        hit = ~np.isfinite(total)
        if np.any(hit):
            out[hit] = self.samples[np.argmax(d[hit] == 0, axis=1)]
        return out


def fit_in_parameter(
    solve: Callable[[np.ndarray], np.ndarray],
    lo: float,
    hi: float,
    n_targets: int,
    tol: float = ARC_TOL,
    degrees: tuple[int, ...] = DEGREES,
) -> ParameterFit | None:
    """The :class:`ParameterFit` of ``solve`` (parameters (k,) -> values (k, ...)) on
    [``lo``, ``hi``] whose error estimate (the larger of the last two Chebyshev coefficients of
    every entry) is at most ``tol`` × the largest ``|value|`` sampled, trying the ``degrees``
    in turn (each one a multiple of the one before, so its Lobatto points hold the earlier
    ones); None where none meets it, or where its solutions would not be fewer than the
    ``n_targets`` values wanted (solving those directly is then cheaper)."""
    if not hi > lo:
        return None
    have: np.ndarray | None = None
    estimate = np.inf
    for k, n in enumerate(degrees):
        if n + 1 >= n_targets or (k > 0 and estimate**2 > tol):
            # Too many solutions, or the last estimate too large for this degree to reach
            # the bound (doubling the degree about squares the coefficients' ratio).
            return None
        x = lobatto_points(n)
        new = np.ones(n + 1, dtype=bool)
        if have is not None:
            new[:: n // (have.shape[0] - 1)] = False
        fresh = solve(lo + (hi - lo) * (x[new] + 1) / 2)
        values = np.empty((n + 1, *fresh.shape[1:]), dtype=fresh.dtype)
        values[new] = fresh
        if have is not None:
            values[~new] = have
        c = chebyshev_coefficients(values)
        scale = float(np.max(np.abs(values)))
        if not np.isfinite(scale):  # a NaN sample would pass every bound and spread to all
            return None
        estimate = float(np.max(np.abs(c[-2:]))) / scale if scale > 0 else 0.0
        if estimate <= tol:
            return ParameterFit(lo, hi, values)
        have = values
    return None
