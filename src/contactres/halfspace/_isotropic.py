"""Closed-form dynamic kernel of an isotropic half-space (Lamb 1904).

The isotropic special case of the kernels in :mod:`._kernels` (paper 1, Eqs. 10-20), written
with the Rayleigh function: an independent reference for the general algorithm.
"""

from __future__ import annotations

import numpy as np

from ..errors import ContactresInputError
from ..validation import nonnegative

__all__ = ["isotropic_dynamic_kernel"]


def isotropic_dynamic_kernel(kappa, c11_over_c44, loss: float = 0.0) -> np.ndarray:
    """Closed-form dynamic kernel of an isotropic half-space (Lamb 1904; paper 1, Eqs. 10-20).

    g(κ) = −Ω² v_p / (c̃44² F),  Ω = 1/κ,  c̃11 = (C11/C44)(1 + i loss),  c̃44 = 1 + i loss,
    v_p = √(1 − Ω²/c̃11),  v_s = √(1 − Ω²/c̃44)  (Re v >= 0),  F = (2 − Ω²/c̃44)² − 4 v_p v_s.

    F is the Rayleigh function (its zero is the Rayleigh pole). Lossless: g -> 1 − ν as κ -> ∞.
    The principal square root gives, at ``loss=0``, the outgoing limit on the real axis and the
    decaying branch for Im κ > 0. An independent reference for :func:`.kernels.dynamic_kernel`.

    Parameters
    ----------
    kappa : array_like
        κ = η/k_s, wave number over the shear wave number (real > 0, or Im κ > 0).
    c11_over_c44 : float
        C11/C44 of the solid, > 4/3 (positive bulk modulus).
    loss : float
        Loss factor Q⁻¹ >= 0 of both constants (:meth:`Material.with_loss`).

    Returns
    -------
    ndarray, complex
        g(κ), dimensionless, shaped like ``kappa``.
    """
    kappa = np.asarray(kappa, dtype=complex)
    ratio = float(c11_over_c44)
    if not ratio > 4.0 / 3.0:
        raise ContactresInputError(
            f"c11_over_c44 must exceed 4/3 (positive bulk modulus), got {ratio!r}"
        )
    q = nonnegative("loss (Q^-1)", loss)
    c44 = 1 + 1j * q
    c11 = ratio * c44
    om2 = 1.0 / kappa**2
    vp = np.sqrt(1 - om2 / c11)
    vs = np.sqrt(1 - om2 / c44)
    x = om2 / c44
    F = (2 - x) ** 2 - 4 * vp * vs
    # At small x, F ~ x is a difference of O(1) terms; its rationalised form has no cancellation
    # (the denominator (2 - x)^2 + 4 v_p v_s is ~8 there).
    a = c44 / c11
    small = np.abs(x) < 0.1
    F_rat = x * (-16 * (1 - a) + (24 - 16 * a) * x - 8 * x**2 + x**3) / ((2 - x) ** 2 + 4 * vp * vs)
    F = np.where(small, F_rat, F)
    return -om2 * vp / (c44**2 * F)
