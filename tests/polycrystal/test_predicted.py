"""Predicted per-pixel maps (contactres.polycrystal._predicted).

Independent checks: contactres.hertz and effective_modulus (isotropic closed forms), springs in
series, exact per-grain moduli, contactres.dcsf of the rotated crystal.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contactres import Material, dcsf, effective_modulus, hertz
from contactres.polycrystal._moduli import indentation_moduli
from contactres.polycrystal._normal_table import prepare_normal_table
from contactres.polycrystal._orientations import random_orientations
from contactres.polycrystal._predicted import (
    contact_stiffness_map,
    dynamic_factor_map,
    map_wavenumbers,
    tip_modulus,
)

CU = Material.crystal("Cu")
DIAMOND = (1141e9, 0.07)


def test_isotropic_rigid_tip_is_hertz():
    E, nu = 70e9, 0.22
    M = indentation_moduli(Material.isotropic(E, nu), random_orientations(6, 1)).reshape(2, 3)
    got = contact_stiffness_map(M, (1e300, 0.0), 50e-9, 0.2e-6)  # a/R = 0.09: Hertz holds
    ref = hertz(effective_modulus(E, nu, np.inf), 50e-9, 0.2e-6)
    assert np.allclose(got.stiffness, ref.stiffness, rtol=1e-12, atol=0)
    assert np.allclose(got.contact_radius, ref.contact_radius, rtol=1e-12, atol=0)
    assert np.array_equal(contact_stiffness_map(M, None, 50e-9, 0.2e-6).stiffness.shape, (2, 3))


def test_tip_compliance_in_series():
    E, nu, R, F = 70e9, 0.22, 1e-6, 1e-5
    M = E / (1 - nu**2)
    got = contact_stiffness_map(np.array([M]), DIAMOND, R, F)
    ref = hertz(effective_modulus(E, nu, *DIAMOND), R, F)  # Johnson's two-body E*
    assert got.stiffness[0] == pytest.approx(float(ref.stiffness), rel=1e-12)
    # Closed form: E* = (1/M + (1 - ν_t²)/E_t)⁻¹, k = 2 E* a, a³ = 3FR/(4E*).
    e_star = 1 / (1 / M + (1 - DIAMOND[1] ** 2) / DIAMOND[0])
    assert got.stiffness[0] == pytest.approx(2 * e_star * (3 * F * R / (4 * e_star)) ** (1 / 3))
    tip = Material.isotropic(*DIAMOND)
    assert tip_modulus(tip) == pytest.approx(DIAMOND[0] / (1 - DIAMOND[1] ** 2), rel=1e-12)
    with pytest.raises(ValueError):
        tip_modulus(CU)  # anisotropic tip


def test_segmented_map_uses_exact_grain_moduli():
    R_grains = random_orientations(5, 7)
    labels = np.array([[0, 0, 1], [2, 3, 4]])
    M = indentation_moduli(CU, R_grains)[labels]
    k = contact_stiffness_map(M, DIAMOND, 100e-9, 1e-6).stiffness
    assert k[0, 0] == k[0, 1] and k.shape == (2, 3)


def test_wavenumbers_match_dcsf_convention():
    # (001): C33' = C11, so k_l a = ω a √(ρ/C11).
    ka = map_wavenumbers(CU, [(0, 0, 1), (1, 1, 1)], 1e-6, 1e8)
    assert ka[0] == pytest.approx(2 * math.pi * 1e8 * 1e-6 * math.sqrt(CU.density / CU.C[0, 0]))
    c33 = float(CU.rotated((1, 1, 1)).C[2, 2])
    assert ka[1] == pytest.approx(2 * math.pi * 1e8 * 1e-6 * math.sqrt(CU.density / c33))


def test_dynamic_factor_map():
    table = prepare_normal_table(CU, "cubic", rtol=1e-3, ka=[0.1, 0.5], dcsf_rtol=4e-2)
    R = random_orientations(4, 9).reshape(2, 2, 3, 3)
    radius, force = 1e-6, 1e-3
    a = contact_stiffness_map(table.modulus(R), DIAMOND, radius, force).contact_radius
    f = 0.3 / (2 * math.pi * float(a.mean()) * math.sqrt(CU.density / 200e9))  # k_l a ~ 0.3
    out = dynamic_factor_map(table, R, DIAMOND, radius, force, f)
    assert out.dcsf.shape == (2, 2) and np.all((out.ka > 0.1) & (out.ka < 0.5))
    i = (1, 0)
    exact = dcsf(CU.rotated(R[i][2], R[i][0]), out.ka[i], rtol=1e-4)
    assert abs(out.dcsf[i] / exact - 1) <= table.dcsf_error
    M, Mt = table.modulus(R)[i], tip_modulus(DIAMOND)
    k = 1 / (1 / (2 * a[i] * M * out.dcsf[i]) + 1 / (2 * a[i] * Mt))
    assert out.stiffness[i] == pytest.approx(k, rel=1e-12)
    with pytest.raises(ValueError, match="within"):  # k a outside the table's nodes
        dynamic_factor_map(table, R, DIAMOND, radius, force, f * 1e-3)
