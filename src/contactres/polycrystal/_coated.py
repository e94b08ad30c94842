"""The indentation modulus map of a coated polycrystal (issue 26, point 4: ``maps predict
--coating``).

Every grain of the map is the substrate of the same films (top first, each isotropic or as
given in the sample frame). The coated modulus of a pixel is M_c = K(a)/(2a), the static
punch of :func:`contactres.indentation_modulus_at` on the stack, at the contact radius a of
the pixel's bare Hertz contact (:func:`contact_stiffness_map`, the map's own contact: the
contact radius is not solved again on the coated surface).

Approximation, stated. Under the films, each grain's crystal is replaced by the isotropic solid
with the same indentation modulus M(n) (paper 1, Eq. 4; Vlassak and Nix) and the Poisson ratio
ν_H of the crystal's Voigt-Reuss-Hill average (one value for the whole map). M_c then depends on
the grain only through M(n) (and a, itself a function of M(n) and the tip), so it is one
smooth function of M over the map's range, tabulated on Chebyshev-Lobatto points in M and
interpolated (barycentric): the points are doubled (5, 9, 17, 33) until the interpolant at
the next level's new points differs from the exact values by less than ``rtol`` (relative;
stated in the result). Its limits are exact: a film of thickness -> 0 gives the bare map (the
equivalent solid has the grain's M), a thick one the film's modulus everywhere, and for an
isotropic crystal with a film of its own material the bare map. Measured against the
axisymmetric layered solution with the anisotropic substrate itself (tests/polycrystal/
test_coated_map.py, and a survey: Cu, 20 nm films, a = 5-30 nm, normals [001], [011], [111]
and a general one): 2e-6-9e-4 for fused silica and a 10 GPa film, up to 5e-3 for a 400 GPa
film (stiffer than the grains, which then carry the load with their full anisotropy).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._summary import Summarised, number, values
from ..errors import ContactresInputError
from ..layered import LayeredMaterial
from ..materials import Material
from ..normal import indentation_modulus_at
from ..numerics import lobatto_weights
from ._predicted import contact_stiffness_map

__all__ = ["CoatedModuli", "coated_moduli", "hill_poisson_ratio"]

# Chebyshev-Lobatto points per level (nested: each level's points are the previous level's plus
# the midpoints in angle).
_LEVELS = (5, 9, 17, 33)


def hill_poisson_ratio(material: Material) -> float:
    """ν of the Voigt-Reuss-Hill average of a crystal (any symmetry), dimensionless.

    K_V = (C11 + C22 + C33 + 2 (C12 + C23 + C31))/9, G_V = (C11 + C22 + C33 − C12 − C23 − C31
    + 3 (C44 + C55 + C66))/15, K_R = 1/(S11 + S22 + S33 + 2 (S12 + S23 + S31)), G_R = 15/(4
    (S11 + S22 + S33) − 4 (S12 + S23 + S31) + 3 (S44 + S55 + S66)) (S = C⁻¹, Voigt), K and G
    the means of the two bounds (R. Hill, Proc. Phys. Soc. A 65, 349 (1952)), and
    ν = (3K − 2G)/(2 (3K + G)).
    """
    C = np.real(np.asarray(material.C, dtype=complex))
    S = np.linalg.inv(C)
    d, o, s = slice(0, 3), [(0, 1), (1, 2), (2, 0)], slice(3, 6)

    def parts(M):
        return np.trace(M[d, d]), sum(M[i, j] for i, j in o), np.trace(M[s, s])

    a, b, c = parts(C)
    k_v, g_v = (a + 2 * b) / 9, (a - b + 3 * c) / 15
    a, b, c = parts(S)
    k_r, g_r = 1 / (a + 2 * b), 15 / (4 * a - 4 * b + 3 * c)
    k, g = (k_v + k_r) / 2, (g_v + g_r) / 2
    return float((3 * k - 2 * g) / (2 * (3 * k + g)))


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the maps.
@dataclass(frozen=True, repr=False)
class CoatedModuli(Summarised):
    """The coated moduli of a map (:func:`coated_moduli`).

    Attributes
    ----------
    moduli : M_c of every pixel at its bare Hertz contact radius, Pa (NaN where M is NaN)
    contact_radius : that radius, m
    stiffness : k*_c = 2 a E*_c, 1/E*_c = 1/M_c + 1/M_tip, N/m (at the bare contact radius)
    poisson : ν_H of the equivalent isotropic substrates (:func:`hill_poisson_ratio`)
    error : largest relative difference of the interpolated and exact M_c at the check points
    evaluations : layered solutions made (nodes and checks)
    """

    moduli: np.ndarray
    contact_radius: np.ndarray
    stiffness: np.ndarray
    poisson: float
    error: float
    evaluations: int

    def _facts(self) -> list[tuple[str, str]]:
        """M_c (GPa), a (nm), k* (N/m), ν_H and the interpolation error."""
        return [
            ("M_c", values(self.moduli, "GPa", 1e9)),
            ("a", values(self.contact_radius, "nm", 1e-9)),
            ("k*", values(self.stiffness, "N/m")),
            ("ν_H", number(self.poisson)),
            ("error", f"{self.error:.2g}"),
        ]


def _lobatto(n: int) -> np.ndarray:
    return np.cos(np.pi * np.arange(n) / (n - 1))


def _barycentric(x_nodes: np.ndarray, values: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The polynomial through ``values`` at the Lobatto points ``x_nodes`` (on [−1, 1]), at x."""
    n = x_nodes.size
    w = lobatto_weights(n)
    d = x[:, None] - x_nodes[None, :]
    exact = d == 0
    d[exact] = 1.0
    c = w[None, :] / d
    out = (c @ values) / np.sum(c, axis=1)
    hit = np.any(exact, axis=1)
    out[hit] = values[np.argmax(exact[hit], axis=1)]
    return out


def coated_moduli(
    material: Material, layers, moduli, tip, radius: float, force: float, rtol: float = 1e-6
) -> CoatedModuli:
    """The indentation modulus map of a coated polycrystal (module docstring).

    Parameters
    ----------
    material : Material
        The crystal, in its crystal frame, Pa (static, lossless).
    layers : sequence of (Material, float)
        The films, top first: static lossless materials in the sample frame (z the inward
        normal) and thicknesses in m, as :class:`contactres.LayeredMaterial` takes them.
    moduli : array_like
        The bare M of every pixel, Pa (NaN: no pixel).
    tip, radius, force
        The tip (isotropic Material, (E, ν) or None: rigid), its radius (m) and the force (N),
        of the map's Hertz contact (:func:`contact_stiffness_map`).
    rtol : float
        Target relative accuracy of the interpolation in M, in [1e-9, 1e-2].

    Returns
    -------
    CoatedModuli
        Shaped like ``moduli``.
    """
    r = float(rtol)
    if not 1e-9 <= r <= 1e-2:
        raise ContactresInputError(f"rtol must lie in [1e-9, 1e-2], got {rtol!r}")
    if not layers:
        raise ContactresInputError("coated_moduli needs at least one layer (the films)")
    M = np.asarray(moduli, dtype=float)
    ok = np.isfinite(M)
    if not np.any(ok):
        raise ContactresInputError("the map has no pixel with a modulus")
    nu = hill_poisson_ratio(material)
    layers = tuple(layers)

    def exact(m_values: np.ndarray) -> np.ndarray:
        a = contact_stiffness_map(m_values, tip, radius, force).contact_radius
        out = np.empty(m_values.size)
        for i, (m, ai) in enumerate(zip(m_values, a, strict=True)):
            # The grain's equivalent isotropic substrate: its M with the map's Hill ν.
            sub = Material.isotropic(m * (1 - nu**2), nu)
            out[i] = indentation_modulus_at(LayeredMaterial(sub, layers), ai)
        return out

    lo, hi = float(np.min(M[ok])), float(np.max(M[ok]))
    coated = np.full(M.shape, np.nan)
    if hi - lo <= 1e-12 * hi:
        # One modulus on the whole map (an isotropic crystal): one layered solution.
        coated[ok] = exact(np.array([hi]))[0]
        error, count = 0.0, 1
    else:
        mid, half = (hi + lo) / 2, (hi - lo) / 2
        x = _lobatto(_LEVELS[0])
        values = exact(mid + half * x)
        count, error = x.size, np.inf
        for n in _LEVELS[1:]:
            finer = _lobatto(n)
            new = finer[1::2]
            exact_new = exact(mid + half * new)
            count += new.size
            error = float(np.max(np.abs(_barycentric(x, values, new) / exact_new - 1)))
            merged = np.empty(n)
            merged[0::2], merged[1::2] = values, exact_new
            x, values = finer, merged
            if error <= r:
                break
        coated[ok] = _barycentric(x, values, (M[ok] - mid) / half)
    bare = contact_stiffness_map(M[ok], tip, radius, force)
    a = np.full(M.shape, np.nan)
    a[ok] = bare.contact_radius
    # The tip's compliance 1/M_tip = 1/E* − 1/M of the bare contact, added to the coated M.
    tip_compliance = 1 / bare.effective_modulus - 1 / M[ok]
    k = np.full(M.shape, np.nan)
    k[ok] = 2 * a[ok] / (1 / coated[ok] + tip_compliance)
    return CoatedModuli(coated, a, k, nu, error, count)
