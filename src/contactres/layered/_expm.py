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

An isotropic layer needs none of this: its exponent has two roots (P, and SV with SH), so
:func:`expm_isotropic` forms the exponential from them in closed form (Sylvester's formula,
Hermite's in the static limit where the roots meet), with ``expm1`` where they are close.
"""

from __future__ import annotations

import math

import numpy as np

from ..halfspace import mm

__all__ = ["expm3", "expm_isotropic", "two_root_expm"]

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


def expm_isotropic(a: np.ndarray, t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """exp(t a) of every stacked exponent matrix a of an isotropic layer, in closed form.

    The exponent A_d of an isotropic solid (:func:`contactres.layered.layer_waves`) has two
    eigenvalues: −α_L (the P wave) and −α_T twice (the SV and SH waves, two independent
    polarisations), so its minimal polynomial is (x − λ_L)(x − λ_T), and in the static limit,
    where the two meet, (x − λ)² (the defective triple root of the module docstring: Jordan
    blocks of sizes 2 and 1). For such a matrix every function is its interpolation at the
    two roots (Sylvester's formula; Hermite's where they meet):

        exp(t A) = e^{t b} [I + t φ₁((c − b) t) (A − b I)],   φ₁(z) = (e^z − 1)/z,

    with b the root of the slower decay (larger Re t λ) and c the other, so that Re z <= 0
    and nothing overflows, and φ₁ from ``expm1`` (no cancellation as the roots meet). The
    roots are read from A itself: the SH polarisation, the surface direction
    (−sin θ, cos θ, 0) normal to the wave vector, decouples, so λ_T = tᵀ A t, and
    λ_L = tr A − 2 λ_T. One product-free evaluation instead of the scaled Taylor polynomial
    and its squarings of :func:`expm3`; the two agree to ~1e-15 relative (tested, static to
    lossy and complex η h), and the result is exact for any A of this structure.

    Parameters
    ----------
    a : ndarray, complex, shape (3, 3, N)
        A_d of an isotropic layer (dimensionless); for any other matrix the result is wrong.
    t : ndarray, shape (N,)
        η h (complex on a lifted path).
    theta : ndarray, shape (N,)
        Direction of the wave vector in the surface, rad.

    Returns
    -------
    ndarray, complex, shape (3, 3, N)
        exp(t a).
    """
    if not np.all(np.isfinite(a)):
        raise FloatingPointError("expm_isotropic: non-finite matrix entries")
    c, s = np.cos(theta), np.sin(theta)
    lam_t = s * s * a[0, 0] - s * c * (a[0, 1] + a[1, 0]) + c * c * a[1, 1]
    lam_l = a[0, 0] + a[1, 1] + a[2, 2] - 2 * lam_t
    return two_root_expm(a, lam_l, lam_t, t)


def two_root_expm(a: np.ndarray, lam_l: np.ndarray, lam_t: np.ndarray, t: np.ndarray) -> np.ndarray:
    """exp(t a) of stacked square matrices a (n, n, N) whose minimal polynomial is
    (x − λ_L)(x − λ_T) (or (x − λ)² where the roots meet), from the two roots alone:
    e^{t b} [I + t φ₁((c − b) t) (a − b I)], b the root of the slower decay (larger Re t λ),
    c the other, φ₁(z) = (e^z − 1)/z by ``expm1`` (Sylvester's formula, Hermite's where the
    roots meet; :func:`expm_isotropic` and the module docstring).

    Parameters
    ----------
    a : ndarray, complex, shape (n, n, N)
        The exponent matrices (dimensionless): an isotropic layer's A_d (n = 3), or its
        sagittal block (n = 2: P and SV); for any matrix of another structure the result is
        wrong.
    lam_l, lam_t : ndarray, shape (N,)
        The two roots of each matrix.
    t : ndarray, shape (N,)
        The factor of the exponent (η h, complex on a lifted path).

    Returns
    -------
    ndarray, complex, shape (n, n, N)
        exp(t a).
    """
    slow_l = (t * lam_l).real > (t * lam_t).real
    base = np.where(slow_l, lam_l, lam_t)
    z = (lam_l + lam_t - 2 * base) * t
    zero = z == 0
    with np.errstate(all="ignore"):
        phi = np.where(zero, 1.0, np.expm1(z) / np.where(zero, 1.0, z))
    scale = np.exp(t * base)
    out = (scale * t * phi) * a
    # exp(t b) (1 − t φ₁ b) on the diagonal.
    diag = scale * (1 - t * phi * base)
    for i in range(a.shape[0]):
        out[i, i] += diag
    return out
