"""Arithmetic on stacks of 3x3 matrices stored as (3, 3, N).

Every entry of such a stack is a contiguous vector of N values, so the elementwise formulas
below run at memory speed; a batched LAPACK call per 3x3 matrix is much slower. The doubling
algorithm (:mod:`._doubling`) and the surface compliance (:mod:`._compliance`) work on these
stacks; the matrices are the dimensionless blocks of the Christoffel pencil of paper 1,
Eqs. 10-20, so the entries carry no unit.
"""

from __future__ import annotations

import numpy as np

__all__ = ["inv3", "maxabs", "mm", "transpose"]


def mm(a: np.ndarray, b: np.ndarray, out=None, tmp=None) -> np.ndarray:
    """Product of stacked 3x3 matrices, (3, 3, N) @ (3, 3, N).

    Parameters
    ----------
    a, b : ndarray, shape (3, 3, N)
        The factors (dimensionless, complex allowed).
    out, tmp : ndarray, shape (3, 3, N), optional
        Result and work array; given together, the product is written into ``out`` without
        temporaries. Neither may overlap ``a`` or ``b``.

    Returns
    -------
    ndarray, shape (3, 3, N)
        ``a @ b`` for every stacked pair (``out`` when given).
    """
    # Entry by entry on contiguous (N,) vectors: a broadcast operand (a[:, 0, None] against
    # b[0]) sends numpy 2's ufuncs through buffered copies, about twice the instructions of
    # these nine sums. The sum order a_i0 b_0j + a_i1 b_1j + a_i2 b_2j is that of the broadcast
    # form, so the results are bit-identical to it.
    if out is None:
        out = np.empty(
            a.shape[:2] + np.broadcast_shapes(a.shape[2:], b.shape[2:]), dtype=np.result_type(a, b)
        )
        # Each sum formed in its row of ``out`` (the same operations in the same order), not
        # in a temporary copied there afterwards.
        for i in range(3):
            for j in range(3):
                o = out[i, j]
                np.multiply(a[i, 0], b[0, j], out=o)
                o += a[i, 1] * b[1, j]
                o += a[i, 2] * b[2, j]
        return out
    for i in range(3):
        for j in range(3):
            o, t = out[i, j], tmp[i, j]
            np.multiply(a[i, 0], b[0, j], out=o)
            o += np.multiply(a[i, 1], b[1, j], out=t)
            o += np.multiply(a[i, 2], b[2, j], out=t)
    return out


def transpose(a: np.ndarray) -> np.ndarray:
    """Transpose of every stacked 3x3 matrix (a view), shape (3, 3, N)."""
    return a.transpose(1, 0, 2)


def inv3(a: np.ndarray, out=None) -> np.ndarray:
    """Inverse of stacked 3x3 matrices by the adjugate formula.

    Parameters
    ----------
    a : ndarray, shape (3, 3, N)
        The matrices (dimensionless, complex allowed).
    out : ndarray, shape (3, 3, N), optional
        Where to write the result; must not overlap ``a``.

    Returns
    -------
    ndarray, shape (3, 3, N)
        ``inv(a)`` for every stacked matrix; a singular one gives inf/NaN entries, no error.
    """
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    c00 = a11 * a22 - a12 * a21
    c01 = a12 * a20 - a10 * a22
    c02 = a10 * a21 - a11 * a20
    r = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02)
    if out is None:
        out = np.empty_like(a)
    # Products written straight into ``out`` (no temporary copied there afterwards).
    np.multiply(c00, r, out=out[0, 0])
    np.multiply(c01, r, out=out[1, 0])
    np.multiply(c02, r, out=out[2, 0])
    np.multiply(a02 * a21 - a01 * a22, r, out=out[0, 1])
    np.multiply(a00 * a22 - a02 * a20, r, out=out[1, 1])
    np.multiply(a01 * a20 - a00 * a21, r, out=out[2, 1])
    np.multiply(a01 * a12 - a02 * a11, r, out=out[0, 2])
    np.multiply(a02 * a10 - a00 * a12, r, out=out[1, 2])
    np.multiply(a00 * a11 - a01 * a10, r, out=out[2, 2])
    return out


def maxabs(a: np.ndarray) -> np.ndarray:
    """Largest entry modulus of every stacked matrix: shape (N,) for a (3, 3, N) stack."""
    return np.max(np.abs(a), axis=(0, 1))
