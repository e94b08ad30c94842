"""Predicted maps of a polycrystal: contact stiffness and dynamic factor per pixel.

From the indentation modulus M of each pixel (interpolated, :class:`NormalTable.modulus
<contactres.polycrystal.NormalTable>`, or exact) and a spherical tip of radius R
pressed with a force F:

* :func:`contact_stiffness_map`: the static Hertz contact (Johnson 1985, Ch. 4) with the tip's
  compliance in series, 1/E* = 1/M + 1/M_tip, a = (3FR/(4E*))^{1/3}, k* = 2aE*
  (paper 1, Eq. 4: K_sa = 2aM for a rigid sphere, Vlassak & Nix 1994). This is the circular
  approximation of the contact: on a face without a 3- or 4-fold axis the contact is an ellipse
  (:func:`contactres.sphere_contact`, Willis 1966), whose stiffness it matches to 0.3 % on the
  built-in crystals (Cu (011): 0.07 %, Li (011): 0.27 %); exact on (001) and (111) of a cubic
  crystal.
* :func:`map_wavenumbers`: k_l a of each pixel at a frequency (k_l = ω √(ρ/C33'), C33' the
  stiffness along the pixel's normal: the default convention of :func:`contactres.dcsf`).
* :func:`dynamic_factor_map`: the DCSF (paper 1, Eq. 29) of the sample at each pixel's k_l a,
  from the tabulated DCSF, and the dynamic contact stiffness with the tip in series.

Segmented maps: when the map is segmented into grains (an integer ``labels`` array, one
orientation per grain), evaluate exactly per grain and index, no interpolation needed::

    from contactres.polycrystal import indentation_moduli
    M_grain = indentation_moduli(material, R_grains)  # (n_grains,), Pa, exact (paper 1, Eq. 4)
    M_map = M_grain[labels]                           # (rows, cols)
    k_map = contact_stiffness_map(M_map, tip, radius, force).stiffness

The DCSF of a few grains is exact with :func:`contactres.dcsf` of ``material.rotated(n)`` per
grain (``n = R_grains[g, 2]``) at that grain's k_l a.

References
----------
K. L. Johnson, *Contact Mechanics*, Cambridge University Press (1985), Ch. 4.
Paper 1: J. Tian, Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010), Eqs. 1-4 (M) and 23-29 (DCSF).
J. J. Vlassak and W. D. Nix, J. Mech. Phys. Solids 42, 1223 (1994).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._summary import Summarised, values
from ..errors import ContactresInputError
from ..materials import Material, voigt_to_tensor
from ._normal_table import NormalTable

__all__ = [
    "ContactMap",
    "DynamicMap",
    "contact_stiffness_map",
    "dynamic_factor_map",
    "map_wavenumbers",
    "tip_modulus",
]


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the maps.
@dataclass(frozen=True, eq=False, repr=False)
class ContactMap(Summarised):
    """Static Hertz contact per pixel: E* (Pa), contact radius a (m), stiffness k* (N/m)."""

    effective_modulus: np.ndarray
    contact_radius: np.ndarray
    stiffness: np.ndarray

    def _facts(self) -> list[tuple[str, str]]:
        """E* (GPa), a (nm) and k* (N/m) over the map."""
        return [
            ("E*", values(self.effective_modulus, "GPa", 1e9)),
            ("a", values(self.contact_radius, "nm", 1e-9)),
            ("k*", values(self.stiffness, "N/m")),
        ]


@dataclass(frozen=True, eq=False)
class DynamicMap:
    """Dynamic contact per pixel.

    Attributes
    ----------
    contact : ContactMap
        The static contact (a from the combined E* of sample and tip).
    ka : ndarray
        k_l a of each pixel (:func:`map_wavenumbers`).
    dcsf : ndarray
        DCSF = K_da/K_sa of the sample, complex (paper 1, Eq. 29).
    stiffness : ndarray
        Dynamic contact stiffness, N/m, complex: the sample's 2aM·DCSF in series with the
        tip's static 2aM_tip (the tip is taken as quasi-static).
    """

    contact: ContactMap
    ka: np.ndarray
    dcsf: np.ndarray
    stiffness: np.ndarray


def tip_modulus(tip) -> float:
    """Plane-strain modulus M_tip = E/(1 − ν²) of an isotropic tip, Pa.

    Parameters
    ----------
    tip : Material, (E, ν) or None
        An isotropic :class:`~contactres.materials.Material`, a pair (E in Pa, ν), with
        E = ``np.inf`` for a rigid tip, or None (rigid: returns inf).
    """
    if tip is None:
        return math.inf
    if isinstance(tip, Material):
        E, nu = tip.isotropic_constants  # ValueError for an anisotropic tip
    else:
        try:
            E, nu = (float(x) for x in tip)
        except (TypeError, ValueError):
            raise ContactresInputError(
                f"tip must be a Material, (E, nu) or None, got {tip!r}"
            ) from None
    if not (E > 0) or math.isnan(E):
        raise ContactresInputError(f"tip Young's modulus must be > 0 (inf for rigid), got {E!r} Pa")
    if not -1.0 < nu < 0.5:
        raise ContactresInputError(f"tip Poisson's ratio must lie in (-1, 0.5), got {nu!r}")
    return E / (1.0 - nu * nu)


def contact_stiffness_map(moduli, tip, radius: float, force: float) -> ContactMap:
    """Static Hertz contact stiffness of a spherical tip on every pixel, N/m.

    1/E* = 1/M + 1/M_tip, a = (3FR/(4E*))^{1/3}, k* = 2aE* (Johnson 1985, Eqs. 4.22-4.23;
    paper 1, Eq. 4 for M).

    Parameters
    ----------
    moduli : array_like
        Indentation modulus M of each pixel, Pa (real, > 0): :meth:`NormalTable.modulus` or
        exact :func:`~contactres.polycrystal.indentation_moduli`.
    tip : Material, (E, ν) or None
        The isotropic tip (:func:`tip_modulus`); None or E = inf: rigid.
    radius : float
        Tip radius R, m.
    force : float
        Static normal force F ≥ 0, N. ``radius`` and ``force`` broadcast with ``moduli``.

    Returns
    -------
    ContactMap
        E* (Pa), a (m) and k* (N/m), shaped like ``moduli``.
    """
    M = np.asarray(moduli)
    if np.iscomplexobj(M) or not np.all(np.asarray(M, float) > 0):
        raise ContactresInputError("moduli must be real and > 0 (Pa)")
    R, F = np.asarray(radius, float), np.asarray(force, float)
    if not np.all(R > 0) or not np.all(np.isfinite(R)):
        raise ContactresInputError(f"radius must be finite and > 0 (m), got {radius!r}")
    if not np.all(F >= 0) or not np.all(np.isfinite(F)):
        raise ContactresInputError(f"force must be finite and >= 0 (N), got {force!r}")
    E_star = 1.0 / (1.0 / M + 1.0 / tip_modulus(tip))
    a = np.cbrt(3.0 * F * R / (4.0 * E_star))
    return ContactMap(E_star, a, 2.0 * a * E_star)


def map_wavenumbers(material: Material, normals, contact_radius, frequency: float):
    """k_l a = ω a √(ρ/C33') of each pixel, C33' = n_i n_j n_k n_l C_ijkl (real part), Pa.

    The wave-number convention of :func:`contactres.dcsf` (``wavenumber="longitudinal"``) for
    each pixel's face; C33' depends on the normal ``n`` only. ``normals`` (..., 3) in crystal
    coordinates (e.g. ``R[..., 2, :]``), ``contact_radius`` in m, ``frequency`` in Hz;
    ``material`` needs its density (kg/m^3).
    """
    if material.density is None:
        raise ContactresInputError("map_wavenumbers needs the material density (kg/m^3)")
    f = float(frequency)
    if not (f >= 0 and math.isfinite(f)):
        raise ContactresInputError(f"frequency must be finite and >= 0 (Hz), got {frequency!r}")
    n = np.asarray(normals, float)
    n = n / np.linalg.norm(n, axis=-1, keepdims=True)
    c = voigt_to_tensor(np.real(np.asarray(material.C)))
    c33 = np.einsum("...i,...j,...k,...l,ijkl->...", n, n, n, n, c, optimize=True)
    from ..dynamic import normalised_wavenumber  # the lazy package: no scipy until here

    return normalised_wavenumber(f, contact_radius, material.density, c33)


def dynamic_factor_map(
    table: NormalTable,
    orientations,
    tip,
    radius: float,
    force: float,
    frequency: float,
    moduli=None,
) -> DynamicMap:
    """DCSF and dynamic contact stiffness of every pixel at one frequency.

    Per pixel: M (``moduli`` if given, else interpolated by ``table``), the static contact
    radius a with the tip in series (:func:`contact_stiffness_map`), k_l a
    (:func:`map_wavenumbers`), the DCSF of the sample interpolated by ``table`` in the normal
    and in k_l a (the table's ``ka`` nodes must cover the map's range), and
    K = [1/(2aM·DCSF) + 1/(2aM_tip)]⁻¹.

    Parameters
    ----------
    table : NormalTable
        From :func:`~contactres.polycrystal.prepare_normal_table` with ``ka``; its
        material needs a density.
    orientations : array_like, shape (..., 3, 3)
        Surface matrices of the pixels.
    tip, radius, force
        As :func:`contact_stiffness_map` (m, N).
    frequency : float
        Oscillation frequency f, Hz (ω = 2πf).
    moduli : array_like, optional
        M per pixel, Pa (e.g. exact per grain); default: ``table.modulus(orientations)``.

    Returns
    -------
    DynamicMap
    """
    R = np.asarray(orientations, float)
    M = table.modulus(R) if moduli is None else np.asarray(moduli)
    contact = contact_stiffness_map(M, tip, radius, force)
    ka = map_wavenumbers(table.material, R[..., 2, :], contact.contact_radius, frequency)
    d = table.dcsf(ka, R)
    a = contact.contact_radius
    with np.errstate(divide="ignore"):
        k = 1.0 / (1.0 / (2 * a * M * d) + 1.0 / (2 * a * tip_modulus(tip)))
    return DynamicMap(contact, ka, d, k)
