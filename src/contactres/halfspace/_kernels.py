"""The normal surface kernels of an anisotropic half-space: static Ĝ(θ) and dynamic g(κ, θ).

Both are the normal-normal entry of the surface compliance (:mod:`._compliance`) of the solid in
its surface frame, under a unit normal point force pressing into the solid (σ_33 = −1):
Ĝ = −H_33/(C44 η) in statics (paper 1, Eqs. 1-4) and g = C44 η Ĝ_dyn = −H_33 at the
dimensionless wave number κ = η/k_s (paper 1, Eqs. 10-21).
"""

from __future__ import annotations

import numpy as np

from ..errors import ContactresInputError
from ..materials import Material
from ._compliance import normal_compliance, scaled_tensor, shear_reference

__all__ = ["dynamic_kernel", "static_kernel"]


def static_kernel(m: Material, theta) -> np.ndarray:
    """Static surface Green's function Ĝ(θ), 1/Pa (paper 1, Eqs. 1-4).

    The normal surface displacement under a unit normal point force (positive into the solid)
    is Ĝ(θ)/η in the wave-vector domain, ξ = η (cos θ, sin θ) in the surface frame x, y. ``m.C``
    is taken as the stiffness in the surface frame (z = inward normal; use
    :meth:`Material.rotated` for a face (hkl)). Isotropic: Ĝ = 2/E* = 2 (1 − ν²)/E.

    Parameters
    ----------
    m : Material
        Stiffness in the surface frame, Pa (complex for loss).
    theta : array_like
        Direction of the surface wave vector, rad.

    Returns
    -------
    ndarray
        Ĝ(θ), 1/Pa, shaped like ``theta``: real for a lossless material, complex for a lossy
        one.

    Examples
    --------
    Isotropic: Ĝ(θ) = 2 (1 − ν²)/E for every direction θ (Boussinesq):

    >>> import numpy as np
    >>> from contactres import Material, static_kernel
    >>> g = static_kernel(Material.isotropic(70e9, 0.22), np.array([0.0, np.pi / 4]))
    >>> bool(np.allclose(g, 2 * (1 - 0.22**2) / 70e9, rtol=1e-12, atol=0))
    True
    """
    c = scaled_tensor(m)
    g = -normal_compliance(c, theta, 0.0) / shear_reference(m)
    return g if m.is_lossy else g.real


def dynamic_kernel(m: Material, kappa, theta) -> np.ndarray:
    """Dimensionless dynamic kernel g(κ, θ) = C44 η Ĝ_dyn(η, θ; ω) (paper 1, Eqs. 10-21).

    Parameters
    ----------
    m : Material
        Stiffness in the surface frame (complex for loss); density is not needed: g depends on
        ``m.C / C44`` only, with C44 = :func:`shear_reference` (undamped).
    kappa : array_like
        κ = η/k_s, wave number over the shear wave number k_s = ω √(ρ/C44). Real κ > 0; for a
        lossless material also complex κ with Im κ > 0 (see Notes).
    theta : array_like
        Direction of the surface wave vector, rad; broadcasts against ``kappa``.

    Returns
    -------
    ndarray, complex
        g, with g -> C44 Ĝ(θ) as κ -> ∞ (statics).

    Notes
    -----
    Root selection: the partial waves decaying into the solid (Im p > 0); with loss this selects
    the outgoing waves. For a lossless material at real κ below a bulk-wave cutoff some vertical
    wave numbers are real; then the outgoing ones are kept (the limit Im κ -> 0+, limiting
    absorption), found by an eigen-decomposition that costs ~10x more per point. Exactly at a
    cutoff (a branch point) or at the Rayleigh pole of a lossless solid the value is not
    meaningful. For a lossless material, complex κ with Im κ > 0 is accepted: the decaying
    rule then gives the analytic continuation of g from large real κ (a real vertical wave
    number would need real 1/κ², i.e. real κ), so contours moved into the upper half plane are
    supported. Complex κ with a lossy material is refused (there the decaying rule is not the
    analytic continuation everywhere).

    Accuracy (tests): ~1e-13 against Lamb's closed form and a brute-force eigen-solution;
    see the docstring of :mod:`contactres.halfspace` for the corners that lose digits.
    """
    kappa = np.asarray(kappa)
    if np.iscomplexobj(kappa) and np.any(kappa.imag != 0):
        if m.is_lossy:
            raise ContactresInputError(
                "complex kappa is supported for lossless materials only; "
                "for a lossy material use real kappa > 0"
            )
        if np.any(kappa.imag < 0):
            raise ContactresInputError("complex kappa must have Im(kappa) >= 0 (upper half plane)")
        bad = (kappa.imag == 0) & ~(kappa.real > 0)
    else:
        kappa = kappa.real if np.iscomplexobj(kappa) else kappa.astype(float)
        bad = ~(kappa > 0)
    bad = bad | ~np.isfinite(kappa)
    if np.any(bad):
        first = kappa.ravel()[np.flatnonzero(bad.ravel())[0]]
        raise ContactresInputError(
            f"kappa (wave number / shear wave number) must be finite and > 0, got {first}"
        )
    c = scaled_tensor(m)
    s = 1.0 / np.asarray(kappa, dtype=complex) ** 2
    return -normal_compliance(c, theta, s)
