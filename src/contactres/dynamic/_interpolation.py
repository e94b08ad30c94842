"""Curves of many k a values: Chebyshev interpolation with an a-posteriori error check.

A DCSF curve is an analytic function of k a on any finite interval (the low-frequency expansion
of the half-space's Green's function, e^{ikr}/r = 1/r + ik − k²r/2 + ..., has no logarithms in
three dimensions, and the lossless limit is taken on a contour that keeps the integrands away
from their branch points). Polynomial interpolation at Chebyshev points then converges
geometrically in the number of nodes (L. N. Trefethen, *Approximation Theory and Approximation
Practice*, SIAM 2013, Ch. 8), so a map of 10⁵ pixels needs the direct evaluation at a few dozen
k a values only.

The nodes are Chebyshev–Lobatto points x_j = cos(πj/n) mapped onto [min, max] of the requested
values; going from n to 2n intervals keeps every old node, so each refinement costs only the new
points. The error of the n-interval interpolant is measured at the n new points (the midpoints
in angle, where it is largest) against the direct values there; the refinement stops once it is
below ``tol`` × ``max|f|`` (then the 2n-interval interpolant, which is used, is far more accurate
still). The values are evaluated by the barycentric formula (scipy's
:class:`~scipy.interpolate.BarycentricInterpolator`, stable for these nodes) with the closed-form
weights of the Chebyshev–Lobatto points, w_j = (−1)^j, halved at both ends (J.-P. Berrut and
L. N. Trefethen, SIAM Rev. 46, 501 (2004), Eq. 5.4). They are given, not left to scipy: scipy
computes the weights as products in a random order (its ``rng``, unseeded by default), so the
interpolated values differed in the last bits from run to run; the same k a values now give the
same bits every run.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..numerics import lobatto_weights

__all__ = ["FIRST_INTERVALS", "MAX_INTERVALS", "chebyshev_values"]

#: Intervals of the first Chebyshev–Lobatto grid (17 nodes). Measured on Cu(001), k_l a in
#: [0, 2], error at the new nodes: exact 6e-8 (16 intervals), 2e-12 (32); WA, whose wiggles
#: need the most, 2e-3 (16), 1.3e-6 (32), 6e-12 (64).
FIRST_INTERVALS = 16
#: Largest number of intervals tried (257 nodes); beyond it the caller evaluates directly.
MAX_INTERVALS = 256


def _nodes(lo: float, hi: float, n: int) -> np.ndarray:
    """The n + 1 Chebyshev–Lobatto points on [lo, hi], ascending."""
    t = -np.cos(np.pi * np.arange(n + 1) / n)
    return 0.5 * (lo + hi) + 0.5 * (hi - lo) * t


def chebyshev_values(
    evaluate: Callable[[np.ndarray], dict[str, np.ndarray]],
    x: np.ndarray,
    tol: float,
    *,
    first: int = FIRST_INTERVALS,
    largest: int = MAX_INTERVALS,
) -> tuple[dict[str, np.ndarray], float] | None:
    """Values of every curve of ``evaluate`` at ``x`` by Chebyshev interpolation.

    Parameters
    ----------
    evaluate : function of a 1-D array of abscissae returning ``{name: complex array}``
        The direct evaluation (called on the nodes only).
    x : 1-D array
        Where the curves are wanted (any order, repeats allowed).
    tol : float
        Largest interpolation error accepted, relative to the largest ``|value|`` of each curve
        on the nodes, as measured at the next refinement's new nodes.
    first, largest : int
        Intervals of the first grid and the largest grid tried.

    Returns
    -------
    ({name: values at x}, measured error) or None when ``largest`` intervals do not reach
    ``tol``, or when [min, max] is too narrow for distinct nodes (relative width <= 1e-9): the
    caller then evaluates directly.
    """
    # Imported here: scipy.interpolate pulls in scipy.optimize and scipy.linalg (~0.3 s), which
    # every importer of contactres.dynamic (afm invert's Hertz rows) paid without a curve.
    from scipy.interpolate import BarycentricInterpolator

    lo, hi = float(np.min(x)), float(np.max(x))
    if not hi - lo > 1e-9 * max(abs(lo), abs(hi)):  # nodes would coincide to round-off
        return None
    n = first
    nodes = _nodes(lo, hi, n)
    values = evaluate(nodes)
    while 2 * n <= largest:
        fine = _nodes(lo, hi, 2 * n)
        new = fine[1::2]  # the nodes the coarse grid lacks (fine[::2] are the old ones)
        new_values = evaluate(new)
        error = 0.0
        for name, v in values.items():
            guess = BarycentricInterpolator(nodes, v, wi=lobatto_weights(n + 1))(new)
            scale = max(np.max(np.abs(v)), np.max(np.abs(new_values[name])))
            error = max(error, float(np.max(np.abs(guess - new_values[name]))) / scale)
        merged = {}
        for name, v in values.items():
            both = np.empty(fine.size, dtype=complex)
            both[::2], both[1::2] = v, new_values[name]
            merged[name] = both
        nodes, values, n = fine, merged, 2 * n
        if error <= tol:
            w = lobatto_weights(n + 1)
            out = {name: BarycentricInterpolator(nodes, v, wi=w)(x) for name, v in values.items()}
            return out, error
    return None
