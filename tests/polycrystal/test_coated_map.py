"""The indentation modulus map of a coated polycrystal (contactres.polycrystal.coated_moduli).

Anchors, independent of the code under test: the bare map (a film of an isotropic crystal's
own material changes nothing); the film's own modulus E/(1 − ν²) under a thick film; the
cubic Voigt-Reuss-Hill formulas in closed form; the axisymmetric layered solution of the
anisotropic substrate itself (the approximation's size); and the equivalent-substrate solution
recomputed here at the pixels' own moduli (the interpolation's size).
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres import LayeredMaterial, Material, indentation_modulus_at
from contactres.errors import ContactresInputError
from contactres.materials import rotate_tensor, tensor_to_voigt, voigt_to_tensor
from contactres.polycrystal import (
    coated_moduli,
    contact_stiffness_map,
    hill_poisson_ratio,
    indentation_moduli,
    random_orientations,
    surface_matrices_from_normals,
)

CU = Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0, name="Cu")
SILICA = Material.isotropic(72e9, 0.17, name="silica")
TIP = dict(tip=None, radius=20e-9, force=1e-6)  # rigid tip; a ≈ 4.8 nm on Cu
SILICA_M = 72e9 / (1 - 0.17**2)  # its indentation modulus E/(1 − ν²), Pa


def _cu_map(n=40):
    return indentation_moduli(CU, random_orientations(n, seed=3))


def test_hill_poisson_ratio_is_the_cubic_closed_form_and_nu_of_an_isotropic_solid():
    c11, c12, c44 = 168.4e9, 121.4e9, 75.4e9
    k = (c11 + 2 * c12) / 3
    g_v = (c11 - c12 + 3 * c44) / 5
    g_r = 5 * (c11 - c12) * c44 / (4 * c44 + 3 * (c11 - c12))
    g = (g_v + g_r) / 2
    assert hill_poisson_ratio(CU) == pytest.approx((3 * k - 2 * g) / (2 * (3 * k + g)), rel=1e-12)
    assert hill_poisson_ratio(SILICA) == pytest.approx(0.17, rel=1e-12)


def test_a_film_of_the_isotropic_crystals_own_material_gives_the_bare_map():
    M = np.array([[SILICA_M, np.nan], [SILICA_M, SILICA_M]])
    got = coated_moduli(SILICA, [(SILICA, 15e-9)], M, **TIP)
    np.testing.assert_allclose(got.moduli, M, rtol=1e-9)
    bare = contact_stiffness_map(np.full(3, SILICA_M), **TIP)
    np.testing.assert_allclose(got.stiffness[np.isfinite(M)], bare.stiffness, rtol=1e-9)
    assert np.isnan(got.moduli[0, 1]) and np.isnan(got.stiffness[0, 1])


def test_a_thick_film_gives_the_films_modulus_everywhere():
    """h = 2e5 a: the substrate shows through at O(a/h) (measured: 4e-6; 4e-4 at h = 2e3 a)."""
    film = Material.isotropic(5e9, 0.35)
    got = coated_moduli(CU, [(film, 1e-3)], _cu_map(), **TIP)
    np.testing.assert_allclose(got.moduli, 5e9 / (1 - 0.35**2), rtol=2e-5)


def test_interpolation_in_m_reaches_its_stated_error():
    """The interpolated M_c at every pixel against the equivalent-substrate solution computed
    here at the pixel's own M (measured: 1.5e-9 with rtol 1e-6, 9 layered solutions)."""
    film = Material.isotropic(10e9, 0.3)
    M = _cu_map(12)
    got = coated_moduli(CU, [(film, 20e-9)], M, rtol=1e-6, **TIP)
    assert got.error <= 1e-6
    nu = hill_poisson_ratio(CU)
    a = contact_stiffness_map(M, **TIP).contact_radius
    want = [
        indentation_modulus_at(
            LayeredMaterial(Material.isotropic(m * (1 - nu**2), nu), [(film, 20e-9)]), ai
        )
        for m, ai in zip(M, a, strict=True)
    ]
    np.testing.assert_allclose(got.moduli, want, rtol=1e-6)
    # The film lowers M well beyond the interpolation error: the test can fail.
    assert np.all(got.moduli < 0.5 * M)


@pytest.mark.parametrize("normal", [(0, 0, 1), (1, 1, 1)])
def test_equivalent_substrate_is_close_to_the_anisotropic_substrate(normal):
    """The stated approximation against the axisymmetric layered solution on the rotated
    crystal itself (measured: 1.7e-4 on (001), 3.5e-4 on (111) under 20 nm of silica)."""
    R = surface_matrices_from_normals(np.array([normal], dtype=float) / np.linalg.norm(normal))
    M = indentation_moduli(CU, R)
    got = coated_moduli(CU, [(SILICA, 20e-9)], M, **TIP)
    turned = Material(C=tensor_to_voigt(rotate_tensor(voigt_to_tensor(np.asarray(CU.C)), R[0])))
    a = contact_stiffness_map(M, **TIP).contact_radius[0]
    exact = indentation_modulus_at(LayeredMaterial(turned, [(SILICA, 20e-9)]), a)
    assert got.moduli[0] == pytest.approx(exact, rel=2e-3)
    assert abs(got.moduli[0] / M[0] - 1) > 0.1  # the film matters here


def test_bad_input():
    with pytest.raises(ContactresInputError, match="layer"):
        coated_moduli(CU, [], _cu_map(3), **TIP)
    with pytest.raises(ContactresInputError, match="no pixel"):
        coated_moduli(CU, [(SILICA, 1e-8)], np.full(3, np.nan), **TIP)
    with pytest.raises(ContactresInputError, match="rtol"):
        coated_moduli(CU, [(SILICA, 1e-8)], _cu_map(3), rtol=0.5, **TIP)
