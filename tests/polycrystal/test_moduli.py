"""Batched indentation modulus of many orientations (contactres.polycrystal._moduli).

Independent checks: the scalar path (indentation_modulus of Material.rotated, one orientation
at a time), the isotropic closed form, the cubic point group and rotations of the sample frame
about the surface normal (I₀ integrates Ĝ over every in-plane direction).
"""

from __future__ import annotations

import numpy as np
import pytest
from signed_permutations import cubic_group_by_hand

from contactres import Material
from contactres.halfspace._compliance import (
    normal_compliance,
    scaled_tensor,
    stacked_normal_compliance,
)
from contactres.materials import rotation_to_surface
from contactres.normal import indentation_modulus
from contactres.polycrystal._moduli import indentation_moduli

CU = Material.crystal("Cu")
FACES = [(0, 0, 1), (0, 1, 1), (1, 1, 1), (1, 2, 3)]


def random_rotations(n: int, seed: int) -> np.ndarray:
    """n random proper rotations (Haar measure: QR of Gaussian matrices, signs fixed)."""
    rng = np.random.default_rng(seed)
    q, r = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    q = q * np.sign(np.diagonal(r, axis1=1, axis2=2))[:, None, :]
    q[np.linalg.det(q) < 0] *= -1
    return q


def scalar_moduli(m: Material, R: np.ndarray) -> np.ndarray:
    """The reference: the existing one-orientation path, through Material.rotated."""
    return np.array([indentation_modulus(m.rotated(r[2], r[0])) for r in R])


def rz(alpha: float) -> np.ndarray:
    c, s = np.cos(alpha), np.sin(alpha)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_principal_and_random_faces_of_cu_match_the_scalar_path():
    R = np.concatenate(
        [np.stack([rotation_to_surface(f) for f in FACES]), random_rotations(20, seed=3)]
    )
    M = indentation_moduli(CU, R)
    ref = scalar_moduli(CU, R)
    assert M.shape == (24,) and M.dtype == float
    np.testing.assert_allclose(M, ref, rtol=1e-10, atol=0)
    # The known values of the doctest of indentation_modulus.
    assert M[0] == pytest.approx(134.0e9, rel=1e-3)
    assert M[2] == pytest.approx(151.6e9, rel=1e-3)


@pytest.mark.parametrize("name", ["sapphire", "quartz"])
def test_trigonal_crystals_match_the_scalar_path(name):
    # No hexagonal crystal is built in; the trigonal ones have the lowest symmetry available.
    m = Material.crystal(name)
    R = np.concatenate([np.stack([rotation_to_surface(f) for f in FACES]), random_rotations(8, 5)])
    np.testing.assert_allclose(indentation_moduli(m, R), scalar_moduli(m, R), rtol=1e-10, atol=0)


def test_lossy_crystal_gives_the_complex_scalar_result():
    m = CU.with_loss(0.02)
    R = random_rotations(6, seed=7)
    M = indentation_moduli(m, R)
    assert np.iscomplexobj(M)
    np.testing.assert_allclose(M, scalar_moduli(m, R), rtol=1e-10, atol=0)


def test_isotropic_solid_gives_the_plane_strain_modulus_in_every_orientation():
    E, nu = 70e9, 0.22
    M = indentation_moduli(Material.isotropic(E, nu), random_rotations(50, seed=11))
    np.testing.assert_allclose(M, E / (1 - nu**2), rtol=1e-12, atol=0)


def test_cubic_point_group_on_the_crystal_side_leaves_m_unchanged():
    G = cubic_group_by_hand()
    assert len(G) == 24
    R = random_rotations(5, seed=13)
    # Every orientation composed with every symmetry: (5, 24, 3, 3).
    RS = np.einsum("nij,gjk->ngik", R, G)
    M = indentation_moduli(CU, RS.reshape(-1, 3, 3)).reshape(5, 24)
    np.testing.assert_allclose(M, np.broadcast_to(M[:, :1], M.shape), rtol=1e-12, atol=0)


def test_rotation_of_the_sample_frame_about_the_normal_leaves_m_unchanged():
    R = random_rotations(4, seed=17)
    alphas = np.linspace(0.0, 2 * np.pi, 7, endpoint=False) + 0.3
    RR = np.einsum("aij,njk->naik", np.stack([rz(a) for a in alphas]), R)
    M = indentation_moduli(CU, RR.reshape(-1, 3, 3)).reshape(4, len(alphas))
    np.testing.assert_allclose(M, np.broadcast_to(M[:, :1], M.shape), rtol=1e-12, atol=0)
    # ... whereas tilting the normal does change it (the test would pass trivially otherwise).
    assert np.ptp(M[:, 0]) > 1e-3 * M[0, 0]


def test_default_rtol_is_converged():
    R = random_rotations(30, seed=19)
    M = indentation_moduli(CU, R)
    tight = indentation_moduli(CU, R, rtol=1e-15)
    np.testing.assert_allclose(M, tight, rtol=1e-12, atol=0)
    loose = indentation_moduli(CU, R, rtol=1e-4)
    np.testing.assert_allclose(loose, tight, rtol=1e-4, atol=0)


def test_improper_matrices_give_the_modulus_of_their_negative():
    R = random_rotations(3, seed=23)
    np.testing.assert_allclose(indentation_moduli(CU, -R), indentation_moduli(CU, R), rtol=1e-12)


def test_chunks_of_orientations_are_independent():
    R = random_rotations(9, seed=29)
    whole = indentation_moduli(CU, R)
    parts = np.concatenate([indentation_moduli(CU, R[:4]), indentation_moduli(CU, R[4:])])
    np.testing.assert_allclose(whole, parts, rtol=1e-14, atol=0)


def test_empty_stack():
    M = indentation_moduli(CU, np.empty((0, 3, 3)))
    assert M.shape == (0,)


@pytest.mark.parametrize(
    "mats, match",
    [
        (np.eye(3), "shape"),
        (np.ones((2, 3, 2)), "shape"),
        (np.full((1, 3, 3), np.nan), "finite"),
        (np.array([np.eye(3), 1.01 * np.eye(3)]), r"surface_matrices\[1\] is not orthogonal"),
    ],
)
def test_bad_matrices_are_rejected(mats, match):
    with pytest.raises(ValueError, match=match):
        indentation_moduli(CU, mats)


@pytest.mark.parametrize("rtol", [0.0, 1e-16, 0.1])
def test_bad_rtol_is_rejected(rtol):
    with pytest.raises(ValueError, match="rtol"):
        indentation_moduli(CU, np.eye(3)[None], rtol=rtol)


def test_stacked_normal_compliance_equals_the_one_solid_path():
    mats = [CU.rotated(f) for f in FACES] + [Material.crystal("quartz").rotated((1, 2, 3))]
    c = np.stack([scaled_tensor(m) for m in mats])
    theta = np.linspace(0.0, np.pi, 23)
    H = stacked_normal_compliance(c, theta)
    ref = np.stack([normal_compliance(ci, theta, 0.0) for ci in c])
    np.testing.assert_allclose(H, ref, rtol=1e-14, atol=0)
    # Dynamic, lossy and lossless (propagating points included), one θ row per solid.
    kappa = np.linspace(0.3, 3.0, 23)
    for m in (CU.with_loss(0.02), CU):
        c = np.stack([scaled_tensor(m.rotated(f)) for f in FACES])
        th = theta[None, :] + 0.1 * np.arange(len(FACES))[:, None]
        H = stacked_normal_compliance(c, th, 1 / kappa**2)
        ref = np.stack(
            [normal_compliance(ci, t, 1 / kappa**2) for ci, t in zip(c, th, strict=True)]
        )
        np.testing.assert_allclose(H, ref, rtol=1e-13, atol=0)
