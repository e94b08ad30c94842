"""Matrix exponential of stacks of 3x3 matrices, (3, 3, N), by scaling and squaring.

The layer recursion (:mod:`.recursion`) needs exp(i η h Z) for the solvents Z of every layer at
every (η, θ) point. An eigen-decomposition will not do: the static isotropic solid has a triple,
defective vertical wave number (Z is not diagonalisable), and near-degenerate points would lose
digits. Scaling and squaring with a Taylor polynomial works for any matrix (Higham, "The scaling
and squaring method for the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26, 1179
(2005), section 1; here with a plain Taylor polynomial instead of Padé, which needs no solve).

Truncation error: each matrix is scaled by 2^-k so that its infinity norm is at most
θ = 1/2; the Taylor polynomial of degree 14 then leaves a remainder of at most
θ^15/15! · e^θ ≈ 4e-17 relative to exp of the scaled matrix (below double-precision round-off).
The k squarings that follow can amplify the round-off of the scaled exponential by up to ~2^k
in the worst (strongly non-normal) case; for the decaying layer exponentials the absolute error
stays at the round-off level of the largest intermediate power. Large arguments (η h = 1e3)
cost only log2 extra squarings, and a decaying exponential underflows to zero without overflow.
"""

from __future__ import annotations

import numpy as np

from ..halfspace.stacked import mm

__all__ = ["expm3"]

# Infinity-norm bound of the scaled matrix and the Taylor degree that reaches round-off there.
_THETA = 0.5
_DEGREE = 14


def expm3(a: np.ndarray) -> np.ndarray:
    """exp(a) of every stacked 3x3 matrix.

    Parameters
    ----------
    a : ndarray, complex, shape (3, 3, N)
        The matrices (dimensionless).

    Returns
    -------
    ndarray, complex, shape (3, 3, N)
        exp(a) for every stacked matrix, by scaling and squaring with a degree-14 Taylor
        polynomial (truncation ≤ 4e-17 relative to the scaled exponential; see the module
        docstring).
    """
    a = np.asarray(a, dtype=complex)
    norm = np.max(np.sum(np.abs(a), axis=1), axis=0)
    if not np.all(np.isfinite(norm)):
        raise FloatingPointError("expm3: non-finite matrix entries")
    # Number of squarings of every point: ||a / 2^k|| <= θ.
    k = np.maximum(0, np.ceil(np.log2(np.maximum(norm, 1e-300) / _THETA))).astype(int)
    b = a * np.exp2(-k)
    eye = np.broadcast_to(np.eye(3)[..., None], a.shape)
    # Horner: I + b (I + b/2 (I + b/3 (... (I + b/m)))).
    e = eye + b / _DEGREE
    for j in range(_DEGREE - 1, 0, -1):
        e = eye + mm(b, e) / j
    # Square each point as many times as it was scaled; points with fewer squarings drop out.
    for step in range(int(k.max(initial=0))):
        idx = np.flatnonzero(k > step)
        sub = e[..., idx]
        e[..., idx] = mm(sub, sub)
    return e
