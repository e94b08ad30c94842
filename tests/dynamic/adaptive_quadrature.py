"""A vectorised adaptive quadrature for the real-axis references of the layered tests.

scipy's ``quad_vec`` calls the integrand at one point at a time; the references of
tests/dynamic/test_layered_punch.py and test_layered_tangential.py evaluate the public
``surface_green`` there, whose cost is mostly per call (~2 ms for one wavenumber, ~13 µs a
wavenumber for an array of them), so those references spent ~10 s each in that overhead. The
rule here asks the integrand for every node of every panel it refines at once.

Rule (global error control, as quad_vec's): each panel [a, b] holds its n-point Gauss-Legendre
value Q and the sum Q₂ of the values of its two halves; the largest entry of ``|Q − Q₂|``
estimates the error of Q, an upper bound for that of the Q₂ kept (~2⁻²ⁿ of it for a smooth
integrand). While the sum of the estimates exceeds max(epsabs, epsrel·``|I|``) (``|I|``: the
largest entry of the total, quad_vec's max norm), every panel whose estimate exceeds the mean
share of that tolerance is bisected. A jump or a near-singular point of the integrand (a branch
point of the layered Green's function just off the real axis) is resolved by panels that shrink
around it, since only the sum of the estimates is bounded.
"""

from __future__ import annotations

import numpy as np

__all__ = ["adaptive_gauss"]


def _gauss_values(f, a, b, x, w):
    """n-point Gauss-Legendre values of f on the panels [a_i, b_i]: shape (panels, ...)."""
    half = 0.5 * (b - a)
    nodes = (0.5 * (a + b))[:, None] + half[:, None] * x[None, :]  # (panels, n)
    values = np.asarray(f(nodes.ravel()))  # (..., panels * n): the integrand's last axis
    values = values.reshape(*values.shape[:-1], a.size, x.size)
    return np.moveaxis(np.tensordot(values, w, axes=([-1], [0])) * half, -1, 0)


def _halves(f, lo, hi, whole, x, w):
    """Midpoints, the values of the two halves, their sum and the error estimates of panels."""
    mid = 0.5 * (lo + hi)
    values = _gauss_values(f, np.concatenate([lo, mid]), np.concatenate([mid, hi]), x, w)
    left, right = values[: lo.size], values[lo.size :]
    pair = left + right
    return mid, left, right, pair, np.abs(whole - pair).reshape(lo.size, -1).max(axis=1)


def adaptive_gauss(f, a, b, points=(), *, epsabs=1e-12, epsrel=1e-11, n=10, max_panels=200_000):
    """∫_a^b f(s) ds of a vector-valued ``f`` (module notes).

    Parameters
    ----------
    f : callable
        ``f(s)`` for a 1-D array s returns shape (..., s.size).
    a, b : float
        The interval (a < b).
    points : sequence of float
        Breakpoints inside (a, b) (peaks of the integrand): the first panels end there.
    epsabs, epsrel : float
        Absolute and relative tolerance of the result (max norm over its entries).
    n : int
        Gauss-Legendre points per half panel.
    max_panels : int
        Refusal bound: a RuntimeError beyond it (the tolerance cannot be met).

    Returns
    -------
    (value, error) : the integral (shape ``f(s).shape[:-1]``) and the sum of the error
        estimates of its panels.
    """
    x, w = np.polynomial.legendre.leggauss(n)
    edges = np.unique(np.concatenate([[a], np.asarray(points, dtype=float), [b]]))
    lo, hi = edges[:-1][edges[:-1] >= a], edges[1:][edges[:-1] >= a]
    mid, left, right, pair, err = _halves(f, lo, hi, _gauss_values(f, lo, hi, x, w), x, w)
    while True:
        total = pair.sum(axis=0)
        tol = max(epsabs, epsrel * float(np.abs(total).max()))
        if err.sum() <= tol:
            return total, float(err.sum())
        split = err > tol / lo.size
        split[np.argmax(err)] = True
        if lo.size + split.sum() > max_panels:
            raise RuntimeError(f"adaptive_gauss: more than {max_panels} panels needed")
        new_lo = np.concatenate([lo[split], mid[split]])
        new_hi = np.concatenate([mid[split], hi[split]])
        new = _halves(f, new_lo, new_hi, np.concatenate([left[split], right[split]]), x, w)
        keep = ~split
        lo, hi = np.concatenate([lo[keep], new_lo]), np.concatenate([hi[keep], new_hi])
        mid, left, right, pair, err = (
            np.concatenate([old[keep], fresh])
            for old, fresh in zip((mid, left, right, pair, err), new, strict=True)
        )
