"""Matrix exponential of stacks of 3x3 matrices, (3, 3, N), by scaling and squaring.

The layer recursion (:mod:`._recursion`) needs exp(i η h Z) for the solvents Z of every layer at
every (η, θ) point. An eigen-decomposition will not do: the static isotropic solid has a triple,
defective vertical wave number (Z is not diagonalisable), and near-degenerate points would lose
digits. Scaling and squaring with a Taylor polynomial works for any matrix (Higham, "The scaling
and squaring method for the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26, 1179
(2005), section 1; here with a plain Taylor polynomial instead of Padé, which needs no solve).

Truncation error: each matrix is scaled by 2^-k so that its infinity norm is at most
θ = 1/2; the Taylor polynomial of degree 16 then leaves a remainder of at most
θ^17/17! · e^θ ≈ 4e-20 relative to exp of the scaled matrix (far below double-precision
round-off). The polynomial is evaluated by the Paterson-Stockmeyer scheme (powers up to b⁴, then
Horner in b⁴): six 3x3 products instead of sixteen.
The k squarings that follow can amplify the round-off of the scaled exponential by up to ~2^k
in the worst (strongly non-normal) case; for the decaying layer exponentials the absolute error
stays at the round-off level of the largest intermediate power. Large arguments (η h = 1e3)
cost only log2 extra squarings, and a decaying exponential underflows to zero without overflow.
"""

from __future__ import annotations

import math

import numpy as np

from ..halfspace import mm

__all__ = ["expm3"]

# Infinity-norm bound of the scaled matrix; the Taylor coefficients 1/j!, j = 0..16, of the
# degree that reaches round-off there.
_THETA = 0.5
_COEF = tuple(1.0 / math.factorial(j) for j in range(17))


def expm3(a: np.ndarray) -> np.ndarray:
    """exp(a) of every stacked 3x3 matrix.

    Parameters
    ----------
    a : ndarray, complex, shape (3, 3, N)
        The matrices (dimensionless).

    Returns
    -------
    ndarray, complex, shape (3, 3, N)
        exp(a) for every stacked matrix, by scaling and squaring with a degree-16 Taylor
        polynomial (truncation ≤ 4e-20 relative to the scaled exponential; see the module
        docstring).
    """
    a = np.asarray(a, dtype=complex)
    norm = np.max(np.sum(np.abs(a), axis=1), axis=0)
    if not np.all(np.isfinite(norm)):
        raise FloatingPointError("expm3: non-finite matrix entries")
    # Number of squarings of every point: ||a / 2^k|| <= θ.
    k = np.maximum(0, np.ceil(np.log2(np.maximum(norm, 1e-300) / _THETA))).astype(int)
    b = a * np.exp2(-k)
    eye = np.eye(3)[..., None]
    b2 = mm(b, b)
    b3 = mm(b2, b)
    b4 = mm(b2, b2)
    c = _COEF

    def block(j):
        return c[j] * eye + c[j + 1] * b + c[j + 2] * b2 + c[j + 3] * b3

    # Σ c_j b^j = B0 + b⁴ (B1 + b⁴ (B2 + b⁴ (B3 + b⁴ c16))), B_i of degree 3 in b.
    e = block(12) + c[16] * b4
    for j in (8, 4, 0):
        e = block(j) + mm(b4, e)
    # Square each point as many times as it was scaled; points with fewer squarings drop out.
    for step in range(int(k.max(initial=0))):
        idx = np.flatnonzero(k > step)
        sub = e[..., idx]
        e[..., idx] = mm(sub, sub)
    return e
