"""Tests of contactres.materials: symmetry, rotation, energy invariance, constructors, errors."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from contactres import Material
from contactres.materials import (
    rotation_to_surface,
    tensor_to_voigt,
    voigt_to_tensor,
)

CU = Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0)


def _rotate(m: Material, R: np.ndarray) -> np.ndarray:
    """Brute-force rotation of C by an explicit 4-fold loop (independent of Material.rotated)."""
    c = voigt_to_tensor(m.C)
    out = np.zeros_like(c)
    for i, j, k, m_ in np.ndindex(3, 3, 3, 3):
        out[i, j, k, m_] = np.sum(
            R[i, :, None, None, None]
            * R[j, None, :, None, None]
            * R[k, None, None, :, None]
            * R[m_, None, None, None, :]
            * c
        )
    return tensor_to_voigt(out)


def test_voigt_tensor_round_trip_and_minor_symmetry():
    c = voigt_to_tensor(CU.C)
    assert np.array_equal(tensor_to_voigt(c), CU.C)
    assert np.array_equal(c, c.transpose(1, 0, 2, 3))
    assert np.array_equal(c, c.transpose(2, 3, 0, 1))


def test_rotation_by_90_degrees_about_001_leaves_cubic_unchanged():
    m = CU.rotated(normal=(0, 0, 1), inplane=(0, 1, 0))
    np.testing.assert_allclose(m.C, CU.C, atol=1e-6 * 168.4e9)


def test_rotated_matches_brute_force_rotation():
    R = rotation_to_surface((1, 1, 1))
    np.testing.assert_allclose(CU.rotated((1, 1, 1)).C, _rotate(CU, R), rtol=0, atol=1e-3)


def test_default_inplane_axes():
    np.testing.assert_allclose(rotation_to_surface((0, 0, 1)), np.eye(3))
    R = rotation_to_surface((1, 1, 1))
    np.testing.assert_allclose(R[2], np.ones(3) / np.sqrt(3))
    np.testing.assert_allclose(R[0], np.array([2, -1, -1]) / np.sqrt(6))
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(R) == pytest.approx(1.0)
    R = rotation_to_surface((1, 0, 0))
    np.testing.assert_allclose(R[0], [0, 1, 0])


def test_c11_along_111_is_known_combination():
    # Longitudinal modulus along [111] of a cubic crystal: (C11 + 2 C12 + 4 C44)/3.
    c11, c12, c44 = 168.4e9, 121.4e9, 75.4e9
    C = CU.rotated((1, 1, 1)).C
    assert C[2, 2] == pytest.approx((c11 + 2 * c12 + 4 * c44) / 3, rel=1e-12)


@st.composite
def rotations(draw):
    q = draw(
        st.lists(st.floats(-1, 1), min_size=4, max_size=4).filter(lambda v: np.linalg.norm(v) > 0.1)
    )
    return Rotation.from_quat(q).as_matrix()


@given(rotations(), st.floats(1e9, 500e9), st.floats(-0.95, 0.49))
def test_isotropic_is_invariant_under_any_rotation(R, E, nu):
    m = Material.isotropic(E, nu)
    rotated = m.rotated(normal=R[2], inplane=R[0])
    np.testing.assert_allclose(rotated.C, m.C, rtol=0, atol=1e-9 * np.max(np.abs(m.C)))


@given(rotations())
def test_rotate_and_rotate_back(R):
    m = CU.rotated(normal=R[2], inplane=R[0])
    # The crystal axes seen from the rotated frame are the columns of R.
    back = m.rotated(normal=R.T[2], inplane=R.T[0])
    np.testing.assert_allclose(back.C, CU.C, rtol=0, atol=1e-6 * 168.4e9)
    np.testing.assert_allclose(back.frame, np.eye(3), atol=1e-12)


@given(rotations(), st.lists(st.floats(-1e-3, 1e-3), min_size=6, max_size=6))
def test_elastic_energy_is_frame_independent(R, e):
    eps = np.array([[e[0], e[5], e[4]], [e[5], e[1], e[3]], [e[4], e[3], e[2]]])
    voigt = lambda t: np.array([t[0, 0], t[1, 1], t[2, 2], 2 * t[1, 2], 2 * t[0, 2], 2 * t[0, 1]])  # noqa: E731
    m = CU.rotated(normal=R[2], inplane=R[0])
    w0 = CU.energy_density(voigt(eps))
    w1 = m.energy_density(voigt(R @ eps @ R.T))
    assert w1 == pytest.approx(w0, rel=1e-9, abs=1e-12 * 168.4e9 * 1e-6)


@given(st.floats(0.05, 20), st.floats(-0.9, 0.45), st.floats(1e6, 1e12))
def test_cubic_from_ratios_round_trip(A, nu, c44):
    m = Material.cubic_from_ratios(A, nu, c44)
    assert m.zener_ratio == pytest.approx(A, rel=1e-12)
    assert m.cubic_poisson == pytest.approx(nu, rel=1e-10, abs=1e-14)
    assert m.C[3, 3] == c44


@given(st.floats(1e6, 1e12), st.floats(-0.95, 0.49))
def test_isotropic_gives_back_E_and_nu(E, nu):
    m = Material.isotropic(E, nu)
    E2, nu2 = m.isotropic_constants
    assert E2 == pytest.approx(E, rel=1e-12)
    assert nu2 == pytest.approx(nu, rel=1e-10, abs=1e-14)
    assert m.zener_ratio == pytest.approx(1.0, rel=1e-12)


def test_hexagonal_is_transversely_isotropic():
    # Zn-like constants (GPa); a rotation about the c axis must not change C.
    m = Material.hexagonal(163.7e9, 36.4e9, 53.0e9, 63.5e9, 38.8e9)
    ang = 0.37
    np.testing.assert_allclose(
        m.rotated((0, 0, 1), inplane=(np.cos(ang), np.sin(ang), 0)).C, m.C, atol=1e-3
    )
    assert m.C[5, 5] == pytest.approx((163.7e9 - 36.4e9) / 2)


def test_with_loss_scales_constants_and_keeps_density():
    m = CU.with_loss(0.02)
    np.testing.assert_allclose(m.C, CU.C * (1 + 0.02j))
    assert m.is_lossy and not CU.is_lossy
    assert m.density == CU.density
    assert m.zener_ratio == pytest.approx(CU.zener_ratio)


def test_material_is_frozen_and_C_read_only():
    with pytest.raises(AttributeError):
        CU.density = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        CU.C[0, 0] = 1.0


def test_zener_ratio_of_rotated_crystal_is_an_error():
    with pytest.raises(ValueError, match="cubic symmetry"):
        _ = CU.rotated((1, 1, 1)).zener_ratio
    with pytest.raises(ValueError, match="not isotropic"):
        _ = CU.isotropic_constants


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Material.isotropic(-1e9, 0.3), "E must be finite and > 0"),
        (lambda: Material.isotropic(1e9, 0.5), "nu .*Poisson"),
        (lambda: Material.isotropic(1e9, -1.0), "nu .*Poisson"),
        (lambda: Material.isotropic(float("nan"), 0.3), "E must be finite and > 0"),
        (lambda: Material.isotropic(1e9, 0.3, density=0), "density must be finite and > 0"),
        (lambda: Material.isotropic(1e9, 0.3, density=-5), "density must be finite and > 0"),
        (lambda: Material.cubic(100e9, 120e9, 50e9), "unstable"),
        (lambda: Material.cubic(100e9, -60e9, 50e9), "unstable"),
        (lambda: Material.cubic(100e9, 50e9, -1), "c44 must be finite and > 0"),
        (lambda: Material.cubic_from_ratios(-1, 0.3), "zener must be finite and > 0"),
        (lambda: Material.cubic_from_ratios(1, 0.7), "poisson .*Poisson"),
        (lambda: Material.from_voigt(np.eye(5)), "6x6"),
        (lambda: Material.from_voigt(np.triu(np.ones((6, 6))) + 6 * np.eye(6)), "symmetric"),
        (lambda: Material.from_voigt(-np.eye(6)), "positive-definite"),
        (lambda: Material.from_voigt(np.full((6, 6), np.nan)), "finite"),
        (lambda: Material.from_voigt(np.eye(6) * (1 - 0.1j)), "loss part"),
        (lambda: CU.with_loss(-0.1), "q_inv"),
        (lambda: CU.rotated((0, 0, 0)), "normal must not be the zero vector"),
        (lambda: CU.rotated((0, 0, 1), inplane=(0, 0, 2)), "parallel"),
    ],
)
def test_bad_input_is_rejected_with_a_message_naming_it(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_crystal_builds_the_cubic_solid_of_the_table():
    # Kittel's Al row: C11, C12, C44 = 108.2, 61.3, 28.5 GPa, ρ = 2700 kg/m³.
    m = Material.crystal("al")
    np.testing.assert_array_equal(m.C, Material.cubic(108.2e9, 61.3e9, 28.5e9).C)
    assert (m.density, m.name) == (2700.0, "Al")
    with pytest.raises(ValueError, match="unknown crystal 'steel'"):
        Material.crystal("steel")
