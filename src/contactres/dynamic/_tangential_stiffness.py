"""Tangential contact stiffness of a rigid circular contact, static and dynamic (public API).

The tangential counterpart of paper 1: a rigid disk of radius a bonded to the surface of an
anisotropic half-space (relaxed contact: no normal traction under it, the normal displacement
free) translates tangentially, u = U (cos ψ, sin ψ) e^{iωt}, without rotating. The force is
F_α = K_αβ(ω) U_β with K the complex 2x2 tangential stiffness tensor, N/m (Im K > 0: energy
carried away by shear, longitudinal and Rayleigh waves, and material loss).

* Static: :mod:`contactres.dynamic._tangential_static` (isotropic K = 8Ga/(2 − ν), Mindlin 1949).
* Dynamic: :mod:`contactres.dynamic._tangential_galerkin`, the Galerkin solution on the disk with
  the in-plane block of the dynamic surface Green's function of
  :mod:`contactres.halfspace`; K(ω)/K₀ = k_t(a₀) + i a₀ c_t(a₀), a₀ = k_s a (isotropic
  c_t(0) = 0.617, 0.598, 0.580 at ν = 0.17, 0.25, 1/3); accuracy 1e-6 up to k_s a = 2
  (k_s a <= 5 accepted: there the harmonic cut-off, which grows with the curve's largest
  k_s a, and the radial terms are checked).
* Two bodies (a sphere on a plate, the QCM contact of paper 2): the compliances add,
  K⁻¹ = K_sphere⁻¹ + K_plate⁻¹ (:func:`two_body_contact_stiffness`).

Conventions: time factor e^{iωt}; k_s = ω √(ρ/C44) with C44 = Re C[3, 3] of the surface frame
(the shear wave number of an isotropic solid); loss as constants C (1 + i Q⁻¹); directions in
degrees from the surface x axis towards y (right-handed about the inward normal z).

References: R. D. Mindlin, J. Appl. Mech. 16, 259-268 (1949); J. Tian, Am. J. Eng. Appl. Sci.
3(1), 56-63 (2010) (paper 1, the normal problem this one mirrors); J. Vlachová, R. König,
D. Johannsmann, "Stiffness of sphere-plate contacts at MHz frequencies: dependence on normal
load, oscillation amplitude, and ambient medium", Beilstein J. Nanotechnol. 6, 845-856 (2015),
doi:10.3762/bjnano.6.87 (paper 2: the QCM at 15 MHz whose contacts motivate it).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ContactresInputError
from ..halfspace import shear_reference
from ..materials import Material, require_material
from ..validation import nonnegative, positive
from ._normal_stiffness import normalised_wavenumber, shear_ka
from ._table import check_loss
from ._tangential_galerkin import KSA_MAX, TangentialTable, prepare_tangential, tangential_per_a

__all__ = [
    "tangential_contact_stiffness",
    "tangential_dcsf",
    "two_body_contact_stiffness",
]


def _unit(direction) -> np.ndarray:
    try:
        psi = math.radians(float(direction))
    except (TypeError, ValueError):
        raise ContactresInputError(
            f"direction must be an angle in degrees, got {direction!r}"
        ) from None
    if not math.isfinite(psi):
        raise ContactresInputError(
            f"direction must be a finite angle in degrees, got {direction!r}"
        )
    return np.array([math.cos(psi), math.sin(psi)])


def _per_a(m: Material, ksa: np.ndarray, loss: float, rtol: float, prepared) -> np.ndarray:
    """K/a (Pa, complex, ksa.shape + (2, 2)) of the lossy material at k_s a values ``ksa``."""
    if prepared is None:
        # A table for this curve's k_s a (KSA_MAX at most: beyond it tangential_per_a refuses).
        top = float(np.max(ksa, initial=0.0))
        table = prepare_tangential(m, loss, rtol, ksa_max=min(top, KSA_MAX))
    elif isinstance(prepared, TangentialTable):
        table = prepared.check_for(m, loss, rtol)
    else:
        raise TypeError(
            f"prepared must be a TangentialTable from prepare_tangential, got "
            f"{type(prepared).__name__}"
        )
    flat = ksa.ravel()
    uniq, inverse = np.unique(flat, return_inverse=True)
    out = tangential_per_a(table, uniq)
    return out[inverse].reshape(*ksa.shape, 2, 2)


def tangential_dcsf(
    material: Material,
    ka,
    direction: float = 0.0,
    wavenumber: str = "shear",
    *,
    loss: float = 0.0,
    tensor: bool = False,
    rtol: float = 1e-6,
    prepared: TangentialTable | None = None,
):
    """Tangential dynamic-contact-stiffness factor K_t(ω)/K_t0 of a rigid disk, complex.

    Parameters
    ----------
    material : Material
        Undamped constants in the surface frame (z = inward normal), Pa; density not needed.
        A layered or viscoelastic solid: :func:`contactres.dynamic.layered_dcsf` with
        ``direction="tangential"``, a function of the radius and the frequency, not of k a
        alone.
    ka : float or array
        Normalised wave number k a >= 0 (a: contact radius) in the convention ``wavenumber``.
    direction : float
        ψ, degrees from the surface x axis: the direction of the motion and of the force
        component reported (K_ψ = e_ψ·K·e_ψ).
    wavenumber : str
        "shear" (default): k_s = ω√(ρ/C44), the a₀ = k_s a of the tangential literature; or
        "longitudinal": k_l = ω√(ρ/C33) (C44, C33 of the surface frame), as for :func:`dcsf`.
    loss : float
        Q⁻¹ of the constants C (1 + i Q⁻¹), in [0, 1) (default 0: radiation damping only).
    tensor : bool
        Return the 2x2 matrix K(ka) K₀⁻¹ (K₀ the static tensor of the undamped constants)
        instead of K_ψ(ka)/K_ψ0.
    rtol : float
        Target relative accuracy (default 1e-6; see
        :mod:`contactres.dynamic._tangential_galerkin`).
    prepared : TangentialTable, optional
        :func:`~contactres.dynamic.prepare_tangential` of this material,
        ``loss`` and ``rtol`` (most of the cost of a curve), with ``ksa_max`` >= the largest
        k_s a asked when that exceeds 2; built for this call otherwise.

    Returns
    -------
    complex or ndarray of complex
        1 + i Q⁻¹ at ka = 0; real part: stiffness, imaginary part: radiation + material loss.
    """
    m = require_material(material, lossless=True)
    ksa = shear_ka(m, ka, wavenumber)
    e = _unit(direction)
    K = _per_a(m, np.concatenate([[0.0], ksa.ravel()]), loss, rtol, prepared)
    # The static tensor of the undamped constants (ka = 0 gives it times 1 + iQ⁻¹).
    k0 = (K[0] / (1 + 1j * check_loss(loss))).real
    k = K[1:].reshape(*ksa.shape, 2, 2)
    if tensor:
        return k @ np.linalg.inv(k0)
    out = np.einsum("i,...ij,j->...", e, k, e) / float(e @ k0 @ e)
    return complex(out) if out.ndim == 0 else out


def tangential_contact_stiffness(
    material: Material,
    radius,
    frequency=0.0,
    direction: float = 0.0,
    loss: float = 0.0,
    *,
    tensor: bool = False,
    rtol: float = 1e-6,
    prepared: TangentialTable | None = None,
):
    """Tangential stiffness K_t(ω) = F/U of a rigid disk of radius a on ``material``, N/m.

    Parameters
    ----------
    material : Material
        Undamped constants in the surface frame (z = inward normal), Pa, with ``density``
        (kg/m^3) when ``frequency`` > 0.
    radius : float or array
        Contact radius a > 0, m.
    frequency : float or array
        f >= 0, Hz (ω = 2πf); broadcasts against ``radius``. 0: the static stiffness.
    direction : float
        ψ, degrees from the surface x axis (motion e_ψ, force component along it).
    loss : float
        Q⁻¹ of the constants, in [0, 1) (default 0).
    tensor : bool
        Return the 2x2 tensor K_αβ (surface frame) instead of K_ψ.
    rtol, prepared
        As in :func:`tangential_dcsf`.

    Returns
    -------
    complex or ndarray of complex
        K_ψ in N/m (shaped like the broadcast of ``radius`` and ``frequency``), or with
        ``tensor`` the tensors (shape + (2, 2)).

    Examples
    --------
    Glass (density needed), contact radius 1 µm, at 100 MHz: the real part stays close to the static
    K = 1.289e5 N/m, the imaginary part is the radiation damping ω c:

    >>> from contactres import Material, tangential_contact_stiffness
    >>> glass = Material.isotropic(70e9, 0.22, density=2500.0)
    >>> K = tangential_contact_stiffness(glass, 1e-6, 1e8, rtol=1e-3)  # a in m, f in Hz
    >>> K0 = 8 * (70e9 / 2.44) * 1e-6 / (2 - 0.22)  # Mindlin 8Ga/(2 − ν), static
    >>> bool(-0.01 < K.real / K0 - 1 < 0), bool(K.imag > 0)  # k_s a ≈ 0.19: softer, lossy
    (True, True)
    """
    m = require_material(material, lossless=True)
    a = np.asarray(positive("radius", radius, "m"), dtype=float)
    f = np.asarray(nonnegative("frequency", frequency, "Hz"), dtype=float)
    a, f = np.broadcast_arrays(a, f)
    if np.any(f > 0) and m.density is None:
        raise ContactresInputError(
            "a dynamic tangential stiffness needs the material density (kg/m^3)"
        )
    # No density is needed (nor read) for a static contact, f = 0 everywhere.
    ksa = normalised_wavenumber(f, a, m.density, shear_reference(m)) if np.any(f > 0) else 0 * f
    K = a[..., None, None] * _per_a(m, ksa, loss, rtol, prepared)
    if tensor:
        return K
    e = _unit(direction)
    out = np.einsum("i,...ij,j->...", e, K, e)
    return complex(out) if out.ndim == 0 else out


def two_body_contact_stiffness(
    sphere: Material,
    plate: Material,
    radius,
    frequency=0.0,
    direction: float = 0.0,
    *,
    sphere_loss: float = 0.0,
    plate_loss: float = 0.0,
    tensor: bool = False,
    rtol: float = 1e-6,
):
    """Tangential stiffness of a contact of radius a between two bodies, N/m (complex).

    The relative tangential motion is shared by the two half-spaces in series: the
    compliances add, K⁻¹ = K_sphere⁻¹(ω) + K_plate⁻¹(ω), each with its own material,
    orientation, loss and dynamic factor (Mindlin 1949 for the static sum; the bodies are
    treated as half-spaces, a ≪ R). The sum is exact when both bodies carry the same traction
    shape (two isotropic bodies in statics: Mindlin's); dynamically, and between different
    anisotropic bodies, the common traction of the bonded disk is that of the summed kernels,
    and the sum of the two stiffnesses is an approximation: measured for glass against an
    isotropic body of G = 58 GPa, ν = 0.08 at 15 MHz, 9e-9 at a = 3 µm, 4.5e-7 at 8 µm,
    8e-5 at 30 µm (``rtol`` covers each body, not this).

    Parameters
    ----------
    sphere, plate : Material
        Undamped constants of each body in its own surface frame (z = inward normal of that
        body), with density. The frames share the x axis: the sphere's (x, y, z) is the plate's
        (x, −y, −z) (a rotation by π about x), so for an isotropic sphere only the plate's frame
        matters. For the QCM of paper 2: :func:`~contactres.materials.at_cut_quartz` (x = the
        crystal's X axis, the shear direction of the plate).
    radius : float or array
        Contact radius a > 0, m.
    frequency : float or array
        f >= 0, Hz.
    direction : float
        ψ, degrees from the plate's x axis: the direction of the relative motion.
    sphere_loss, plate_loss : float
        Q⁻¹ of each body's constants, in [0, 1) (default 0: radiation only).
    tensor : bool
        Return the 2x2 tensor in the plate frame instead of K_ψ.
    rtol : float
        Relative accuracy of each body's stiffness (default 1e-6).

    Returns
    -------
    complex or ndarray of complex
        K_ψ (or the tensors) in N/m; tan δ_rad = Im K/Re K is the loss tangent of the contact.
    """
    kp = tangential_contact_stiffness(
        plate, radius, frequency, loss=plate_loss, tensor=True, rtol=rtol
    )
    ks = tangential_contact_stiffness(
        sphere, radius, frequency, loss=sphere_loss, tensor=True, rtol=rtol
    )
    flip = np.diag([1.0, -1.0])
    ks = flip @ ks @ flip
    K = np.linalg.inv(np.linalg.inv(kp) + np.linalg.inv(ks))
    if tensor:
        return K
    e = _unit(direction)
    out = np.einsum("i,...ij,j->...", e, K, e)
    return complex(out) if out.ndim == 0 else out
