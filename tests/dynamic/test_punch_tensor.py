"""The 2x2 tangential stiffness tensor of the rigid flat punch (flat_punch_stiffness and
layered_punch_stiffness with tensor=True).

Anchors, each independent of the tensor's own components: symmetry (a stack unchanged by
rotations about the normal, or a face with a threefold axis, has an isotropic second-rank
tensor); the x-translation of the stack turned by 90° about the normal (K_yy, from the default
K_xx path); the rotation law K' = Q K Qᵀ of a tensor; reciprocity K_xy = K_yx; Mindlin's static
8Ga/(2 − ν); and passivity of the dynamic tensor.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contactres import LayeredMaterial, Material, flat_punch_stiffness
from contactres.dynamic._layered_punch import layered_punch_stiffness
from contactres.errors import ContactresInputError

QUARTZ = Material.isotropic(72e9, 0.17, density=2650.0, name="quartz")
PMMA = Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA")
CU = Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0, name="Cu")
CU110 = CU.rotated((1, 1, 0), (0, 0, 1))  # x along [001], y along [1-10]: a twofold face
A = 1e-6
F = 3e8  # Hz: k_s a ≈ 0.65 in Cu, 1.0 in quartz
FILM = LayeredMaterial(QUARTZ, [(CU110, 0.3 * A)])  # a twofold film: K_xy far from zero turned


def _kt(material, f, **kw):
    return flat_punch_stiffness(material, A, f, direction="tangential", tensor=True, **kw)


def _turned(material, psi):
    """The stack turned about the normal: its new x axis at angle psi in the old frame."""
    return material.rotated((0, 0, 1), (math.cos(psi), math.sin(psi), 0))


@pytest.fixture(scope="module")
def film_tensor():
    """The tensor of FILM, static and at F (read by three tests)."""
    return _kt(FILM, np.array([0.0, F]))


def test_axisymmetric_stack_has_an_isotropic_tensor_equal_to_k_xx():
    """Isotropic layers: K_xy = 0, K_yy = K_xx, and K_xx is the default tangential punch."""
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.2 * A)])
    f = np.array([0.0, 1e8])
    k = layered_punch_stiffness(stack, A, f, direction="tangential", tensor=True)
    scale = np.abs(k[:, 0, 0])
    assert np.all(np.abs(k[:, 0, 1]) < 1e-12 * scale)
    assert np.all(np.abs(k[:, 1, 0]) < 1e-12 * scale)
    assert np.all(np.abs(k[:, 1, 1] - k[:, 0, 0]) < 1e-12 * scale)
    k_xx = layered_punch_stiffness(stack, A, f, direction="tangential")
    np.testing.assert_allclose(k[:, 0, 0], k_xx, rtol=1e-13)


def test_static_isotropic_tensor_is_mindlin():
    e, nu = 70e9, 0.25
    g = e / (2 * (1 + nu))
    k = _kt(Material.isotropic(e, nu), 0.0)
    mindlin = 8 * g * A / (2 - nu)
    np.testing.assert_allclose(k, mindlin * np.eye(2), rtol=1e-9, atol=1e-12 * mindlin)


def test_threefold_face_has_an_isotropic_tensor():
    """Cu(111) is threefold about its normal (not axisymmetric: the full-θ path), and a
    second-rank tensor invariant under 120° turns is isotropic (measured: < 5e-16)."""
    k = _kt(CU.rotated((1, 1, 1)), np.array([0.0, F]))
    scale = np.abs(k[:, 0, 0])
    assert np.all(np.abs(k[:, 0, 1]) < 1e-7 * scale)
    assert np.all(np.abs(k[:, 1, 1] / k[:, 0, 0] - 1) < 1e-7)


@pytest.mark.parametrize("material", [CU110, FILM], ids=["Cu(110)", "Cu(110)-on-quartz"])
def test_k_yy_is_k_xx_of_the_stack_turned_by_90_degrees(material, request):
    """The y translation is the x translation of the stack turned by 90°: its K_xx on the
    default (x only) path (measured: < 4e-13). The (110) face is far from isotropic
    (|K_yy/K_xx| = 0.77 bare; a 0.3 a film of it on quartz: 0.96 static, 0.997 at F)."""
    f = np.array([0.0, F])
    k = request.getfixturevalue("film_tensor") if material is FILM else _kt(material, f)
    k_yy = layered_punch_stiffness(_turned(material, math.pi / 2), A, f, direction="tangential")
    np.testing.assert_allclose(k[:, 1, 1], k_yy, rtol=1e-8)
    assert np.all(np.abs(k[:, 1, 1] / k[:, 0, 0] - 1) > 1e-3)


@pytest.fixture(scope="module")
def turned_film_tensor():
    """The tensor of FILM turned by 0.4 rad, at 0, 1e8 Hz and F (read by two tests): one call
    for the three frequencies costs ~60 % of two calls for two each."""
    return _kt(_turned(FILM, 0.4), np.array([0.0, 1e8, F]))


@pytest.mark.parametrize("psi", [0.4, 1.1])
def test_turning_the_stack_turns_the_tensor(psi, film_tensor, request):
    """K' = Q K Qᵀ, Q = [[cos ψ, sin ψ], [−sin ψ, cos ψ]] (the rows: the turned axes in the old
    frame), static and dynamic (measured: < 3e-15); and reciprocity K_xy = K_yx where K_xy is
    far from zero."""
    k = film_tensor
    if psi == 0.4:  # at 0 and F
        turned = request.getfixturevalue("turned_film_tensor")[[0, 2]]
    else:
        turned = _kt(_turned(FILM, psi), np.array([0.0, F]))
    c, s = math.cos(psi), math.sin(psi)
    Q = np.array([[c, s], [-s, c]])
    want = Q @ k @ Q.T
    scale = np.max(np.abs(k), axis=(1, 2))
    assert np.all(np.max(np.abs(turned - want), axis=(1, 2)) < 1e-8 * scale)
    assert np.all(np.abs(turned[:, 0, 1]) > 1e-3 * scale)
    assert np.all(np.abs(turned[:, 0, 1] - turned[:, 1, 0]) < 1e-10 * scale)


def test_dynamic_tensor_is_passive(turned_film_tensor):
    """The power into the solid under any rigid in-plane motion U is (ω/2) Im(Uᴴ K U) >= 0:
    the anti-Hermitian part of K is positive semi-definite (and positive: waves radiate)."""
    k = turned_film_tensor[1:]  # FILM turned by 0.4 rad, at 1e8 Hz and F
    loss = (k - np.conj(np.swapaxes(k, -1, -2))) / 2j
    assert np.all(np.linalg.eigvalsh(loss) > 0)


def test_tensor_needs_the_tangential_direction():
    with pytest.raises(ContactresInputError, match="tangential"):
        flat_punch_stiffness(QUARTZ, A, 1e6, direction="normal", tensor=True)
