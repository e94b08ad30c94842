"""Orientations (issue 16, point 1): conventions against hand-worked cases, groups, reduction.

The expected matrices are worked out by hand from the Bunge definition g = Z(φ2) X(Φ) Z(φ1)
(sample -> crystal) and R = gᵀ (rows = sample axes in crystal coordinates), or taken from the
texture literature (Goss (011)[100] = (0°, 45°, 0°), Brass (011)[2-11] = (35.26°, 45°, 0°)).
"""

import itertools

import numpy as np
import pytest
from signed_permutations import cubic_group_by_hand

from contactres import Material, indentation_modulus
from contactres.materials import (
    rotate_tensor,
    rotation_to_surface,
    tensor_to_voigt,
    voigt_to_tensor,
)
from contactres.polycrystal._orientations import (
    euler_from_surface_matrices,
    quaternions_from_surface_matrices,
    random_orientations,
    reduce_to_fundamental_zone,
    surface_matrices_from_euler,
    surface_matrices_from_quaternions,
    surface_matrix_from_miller,
    symmetry_operators,
)

EXACT = {"rtol": 0, "atol": 1e-12}
PHI_111 = np.degrees(np.arccos(1 / np.sqrt(3)))  # 54.7356°: angle between [001] and [111]


def frame_Z(w):
    """Bunge's passive rotation Z(ω) (degrees), written out by hand."""
    c, s = np.cos(np.radians(w)), np.sin(np.radians(w))
    return np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])


def frame_X(w):
    c, s = np.cos(np.radians(w)), np.sin(np.radians(w))
    return np.array([[1, 0, 0], [0, c, s], [0, -s, c]])


def bunge_g(phi1, Phi, phi2):
    """g = Z(φ2) X(Φ) Z(φ1), degrees: sample -> crystal coordinates."""
    return frame_Z(phi2) @ frame_X(Phi) @ frame_Z(phi1)


def bunge_quaternion(phi1, Phi, phi2):
    """Rowenhorst et al. (2015) eu2qu with P = -1, written out by hand (degrees in)."""
    p1, P, p2 = np.radians([phi1, Phi, phi2])
    sigma, delta = (p1 + p2) / 2, (p1 - p2) / 2
    c, s = np.cos(P / 2), np.sin(P / 2)
    q = np.array([c * np.cos(sigma), s * np.cos(delta), s * np.sin(delta), c * np.sin(sigma)])
    return q if q[0] >= 0 else -q


def in_sample_frame(m: Material, R) -> Material:
    """The crystal ``m`` seen in the frame of the surface-frame matrix ``R``."""
    C = tensor_to_voigt(rotate_tensor(voigt_to_tensor(m.C), R))
    return Material(C=C, density=m.density, name=m.name, frame=R)


def contains(group, S, atol=1e-12):
    return bool(np.any(np.all(np.abs(group - S) <= atol, axis=(1, 2))))


# --- hand-worked Euler cases ------------------------------------------------------------------


def test_zero_angles_are_the_identity():
    R = surface_matrices_from_euler(0, 0, 0, degrees=True)
    np.testing.assert_allclose(R, np.eye(3), **EXACT)


def test_Phi_90_puts_the_normal_along_010():
    """g = X(90°) = [[1,0,0],[0,0,1],[0,-1,0]]: sample z -> g e_z = [010], y -> [00-1]."""
    R = surface_matrices_from_euler(0, np.pi / 2, 0, degrees=False)
    expected = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    np.testing.assert_allclose(R, expected, **EXACT)
    np.testing.assert_allclose(R, bunge_g(0, 90, 0).T, **EXACT)


def test_phi1_alone_rotates_about_the_normal():
    """g = Z(90°): sample x = g e_x = [0-10], y = [100]; the surface stays (001)."""
    R = surface_matrices_from_euler(90, 0, 0, degrees=True)
    np.testing.assert_allclose(R, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], **EXACT)


def test_normal_along_111():
    """g e_z = (sin Φ sin φ2, sin Φ cos φ2, cos Φ) = (1, 1, 1)/√3 for Φ = 54.74°, φ2 = 45°."""
    for phi1 in (0.0, 30.0, 200.0):
        R = surface_matrices_from_euler(phi1, PHI_111, 45, degrees=True)
        np.testing.assert_allclose(R[2], np.ones(3) / np.sqrt(3), **EXACT)


def test_matches_the_written_out_bunge_matrix():
    rng = np.random.default_rng(1)
    angles = rng.uniform([0, 0, 0], [360, 180, 360], size=(20, 3))
    R = surface_matrices_from_euler(*angles.T, degrees=True)
    expected = np.array([bunge_g(*a).T for a in angles])
    np.testing.assert_allclose(R, expected, **EXACT)
    assert R.shape == (20, 3, 3)
    np.testing.assert_allclose(np.linalg.det(R), 1, **EXACT)


def test_degrees_and_radians_agree_and_broadcast():
    grid = np.zeros((2, 3))
    R_deg = surface_matrices_from_euler(grid + 10, 20, grid + 30, degrees=True)
    R_rad = surface_matrices_from_euler(*np.radians([10, 20, 30]), degrees=False)
    assert R_deg.shape == (2, 3, 3, 3)
    np.testing.assert_allclose(R_deg, np.broadcast_to(R_rad, R_deg.shape), **EXACT)


def test_unit_is_required_and_implausible_angles_are_refused():
    with pytest.raises(TypeError):
        surface_matrices_from_euler(0, 0, 0)  # degrees is a required keyword
    with pytest.raises(ValueError, match="were the angles given in degrees"):
        surface_matrices_from_euler(180.0, 90.0, 45.0, degrees=False)
    with pytest.raises(ValueError, match="720"):
        surface_matrices_from_euler(800.0, 0.0, 0.0, degrees=True)
    with pytest.raises(ValueError, match="finite"):
        surface_matrices_from_euler(np.nan, 0.0, 0.0, degrees=True)
    surface_matrices_from_euler(-4 * np.pi, 2 * np.pi, 4 * np.pi, degrees=False)  # at the rule


# --- Euler round trip, quaternions ----------------------------------------------------------


def test_euler_round_trip_and_bunge_ranges():
    R = random_orientations(200, seed=2)
    for degrees in (True, False):
        e = euler_from_surface_matrices(R, degrees=degrees)
        turn = 360.0 if degrees else 2 * np.pi
        assert np.all((e[:, [0, 2]] >= 0) & (e[:, [0, 2]] < turn))
        assert np.all((e[:, 1] >= 0) & (e[:, 1] <= turn / 2))
        np.testing.assert_allclose(
            surface_matrices_from_euler(*e.T, degrees=degrees), R, rtol=0, atol=1e-10
        )


def test_euler_of_hand_worked_matrices_including_phi_zero():
    e = euler_from_surface_matrices(
        surface_matrices_from_euler(90, 0, 0, degrees=True), degrees=True
    )
    np.testing.assert_allclose(e, [90, 0, 0], rtol=0, atol=1e-10)  # Φ = 0: φ2 = 0 by convention
    e = euler_from_surface_matrices(np.eye(3), degrees=True)
    np.testing.assert_allclose(e, [0, 0, 0], rtol=0, atol=1e-10)
    e = euler_from_surface_matrices(bunge_g(35.26, 45, 0).T, degrees=True)
    np.testing.assert_allclose(e, [35.26, 45, 0], rtol=0, atol=1e-10)


def test_quaternions_agree_with_euler():
    """Rowenhorst eu2qu (P = -1, by hand) -> the same matrix as the Euler path."""
    rng = np.random.default_rng(3)
    angles = rng.uniform([0, 0, 0], [360, 180, 360], size=(30, 3))
    q = np.array([bunge_quaternion(*a) for a in angles])
    R_q = surface_matrices_from_quaternions(q)
    R_e = surface_matrices_from_euler(*angles.T, degrees=True)
    np.testing.assert_allclose(R_q, R_e, **EXACT)
    np.testing.assert_allclose(surface_matrices_from_quaternions(-q), R_e, **EXACT)
    np.testing.assert_allclose(
        surface_matrices_from_quaternions(np.roll(q, -1, axis=1), scalar_first=False), R_e, **EXACT
    )
    np.testing.assert_allclose(quaternions_from_surface_matrices(R_e), q, **EXACT)


def test_quaternion_of_phi1_90():
    """eu2qu(90°, 0, 0) = (cos 45°, 0, 0, sin 45°) -> x = [0-10], y = [100]."""
    q = [np.sqrt(0.5), 0, 0, np.sqrt(0.5)]
    R = surface_matrices_from_quaternions(q)
    np.testing.assert_allclose(R, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], **EXACT)


def test_bad_quaternions_and_matrices_are_refused():
    with pytest.raises(ValueError, match="unit norm"):
        surface_matrices_from_quaternions([1, 1, 0, 0])
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 4\)"):
        surface_matrices_from_quaternions([1, 0, 0])
    with pytest.raises(ValueError, match="orthogonal"):
        euler_from_surface_matrices(2 * np.eye(3), degrees=True)
    with pytest.raises(ValueError, match="proper rotation"):
        euler_from_surface_matrices(-np.eye(3), degrees=True)


# --- Miller indices ----------------------------------------------------------------------------


def test_miller_agrees_with_rotation_to_surface():
    cases = [((0, 0, 1), (1, 0, 0)), ((1, 1, 1), (1, -1, 0)), ((1, 2, 3), (3, 0, -1))]
    cases += [((0, 1, 1), (2, -1, 1)), ((1, 1, 0), (0, 0, 1)), ((1, 1, 2), (1, 1, -1))]
    for hkl, uvw in cases:
        R = surface_matrix_from_miller(hkl, uvw)
        np.testing.assert_allclose(R, rotation_to_surface(hkl, uvw), **EXACT)
    stacked = surface_matrix_from_miller([c[0] for c in cases], [c[1] for c in cases])
    assert stacked.shape == (len(cases), 3, 3)


def test_miller_cube_goss_and_brass_have_their_textbook_euler_angles():
    np.testing.assert_allclose(surface_matrix_from_miller((0, 0, 1), (1, 0, 0)), np.eye(3), **EXACT)
    goss = surface_matrix_from_miller((0, 1, 1), (1, 0, 0))
    np.testing.assert_allclose(goss, surface_matrices_from_euler(0, 45, 0, degrees=True), **EXACT)
    brass = surface_matrix_from_miller((0, 1, 1), (2, -1, 1))
    phi1 = np.degrees(np.arccos(2 / np.sqrt(6)))  # 35.26°
    np.testing.assert_allclose(
        brass, surface_matrices_from_euler(phi1, 45, 0, degrees=True), **EXACT
    )


def test_miller_direction_must_lie_in_the_plane():
    with pytest.raises(ValueError, match="does not lie in the plane"):
        surface_matrix_from_miller((1, 1, 1), (1, 0, 0))
    with pytest.raises(ValueError, match="zero vector"):
        surface_matrix_from_miller((0, 0, 0), (1, 0, 0))


def test_miller_orientation_rotates_the_stiffness_like_material_rotated():
    cu = Material.crystal("Cu")
    R = surface_matrix_from_miller((1, 1, 0), (0, 0, 1))
    np.testing.assert_allclose(
        in_sample_frame(cu, R).C, cu.rotated((1, 1, 0), (0, 0, 1)).C, rtol=0, atol=1e-3
    )


# --- symmetry groups ---------------------------------------------------------------------------


@pytest.mark.parametrize(("lattice", "K"), [("cubic", 24), ("hexagonal", 12)])
def test_groups_are_groups_of_proper_rotations(lattice, K):
    S = symmetry_operators(lattice)
    assert S.shape == (K, 3, 3)
    np.testing.assert_allclose(S[0], np.eye(3), **EXACT)
    np.testing.assert_allclose(
        S @ np.swapaxes(S, 1, 2), np.broadcast_to(np.eye(3), S.shape), **EXACT
    )
    np.testing.assert_allclose(np.linalg.det(S), 1, **EXACT)
    for A, B in itertools.product(S, S):  # closure
        assert contains(S, A @ B)
    for i, j in itertools.combinations(range(K), 2):  # distinct
        assert not np.allclose(S[i], S[j], rtol=0, atol=1e-9)


def test_cubic_group_is_the_signed_permutations():
    S = symmetry_operators("cubic")
    hand = cubic_group_by_hand()
    assert len(hand) == 24
    assert all(contains(S, H, atol=0) for H in hand)  # exact entries


def test_hexagonal_group_axes():
    """Six-fold about z = c, two-folds about x = a1 and at every 30° in the basal plane."""
    S = symmetry_operators("hexagonal")
    c, s = np.cos(np.pi / 3), np.sin(np.pi / 3)
    assert contains(S, np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]))
    assert contains(S, np.diag([1.0, -1.0, -1.0]))  # 180° about x = a1
    assert contains(S, np.diag([-1.0, 1.0, -1.0]))  # 180° about y
    for k in range(6):
        t = np.radians(30 * k)
        n = np.array([np.cos(t), np.sin(t), 0])
        assert contains(S, 2 * np.outer(n, n) - np.eye(3))  # 180° about n
    assert not contains(S, np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]))  # no four-fold
    with pytest.raises(ValueError, match="lattice"):
        symmetry_operators("tetragonal")


def test_symmetry_leaves_the_stiffness_unchanged():
    cu = Material.crystal("Cu")
    hexa = Material.hexagonal(162e9, 92e9, 69e9, 181e9, 46.7e9)  # Ti-like constants, Pa
    for m, lattice in ((cu, "cubic"), (hexa, "hexagonal")):
        for S in symmetry_operators(lattice):
            np.testing.assert_allclose(in_sample_frame(m, S).C, m.C, rtol=0, atol=1e-3)


# --- fundamental zone --------------------------------------------------------------------------


def test_reduction_of_hand_worked_rotations_about_the_normal():
    """A turn of 100° about z is 10° after a cubic four-fold; 50° is -10° after a six-fold."""
    for lattice, angle, expected in (("cubic", 100, 10), ("hexagonal", 50, -10)):
        R = surface_matrices_from_euler(angle, 0, 0, degrees=True)
        reduced = reduce_to_fundamental_zone(R, lattice)
        np.testing.assert_allclose(
            reduced, surface_matrices_from_euler(expected % 360, 0, 0, degrees=True), **EXACT
        )


def test_goss_variants_reduce_to_one_matrix():
    a = surface_matrix_from_miller((1, 1, 0), (0, 0, 1))
    b = surface_matrices_from_euler(0, 45, 0, degrees=True)  # (011)[100]
    np.testing.assert_allclose(
        reduce_to_fundamental_zone(a, "cubic"), reduce_to_fundamental_zone(b, "cubic"), **EXACT
    )


@pytest.mark.parametrize("lattice", ["cubic", "hexagonal"])
def test_every_equivalent_reduces_to_the_same_matrix(lattice):
    S = symmetry_operators(lattice)
    R = random_orientations(25, seed=4)
    equivalents = R[:, None] @ S[None]  # (N, K, 3, 3)
    reduced = reduce_to_fundamental_zone(equivalents, lattice)
    np.testing.assert_allclose(reduced, np.broadcast_to(reduced[:, :1], reduced.shape), **EXACT)
    # each reduced matrix is R @ S for some S, and its angle is the smallest of the orbit
    first = reduced[:, 0]
    for Ri, Rr, orbit in zip(R, first, equivalents, strict=True):
        assert contains(S, Ri.T @ Rr, atol=1e-12)
        assert np.trace(Rr) >= np.max(np.trace(orbit, axis1=1, axis2=2)) - 1e-12


def test_ties_are_broken_deterministically():
    """The identity of a cube has no tie; a 45° turn about z ties with -45°: both orders agree."""
    plus = surface_matrices_from_euler(45, 0, 0, degrees=True)
    minus = surface_matrices_from_euler(315, 0, 0, degrees=True)
    a = reduce_to_fundamental_zone(plus, "cubic")
    b = reduce_to_fundamental_zone(minus, "cubic")
    np.testing.assert_allclose(a, b, **EXACT)
    np.testing.assert_allclose(np.trace(a), 1 + 2 * np.cos(np.pi / 4), **EXACT)
    np.testing.assert_allclose(reduce_to_fundamental_zone(np.eye(3), "cubic"), np.eye(3), **EXACT)


def test_reduction_keeps_the_indentation_modulus():
    cu = Material.crystal("Cu")
    R = random_orientations(3, seed=5)
    reduced = reduce_to_fundamental_zone(R, "cubic")
    for Ri, Rr in zip(R, reduced, strict=True):
        M = indentation_modulus(in_sample_frame(cu, Ri))
        M_red = indentation_modulus(in_sample_frame(cu, Rr))
        assert abs(M - M_red) <= 1e-10 * abs(M)


def test_euler_111_gives_the_111_indentation_modulus():
    cu = Material.crystal("Cu")
    R = surface_matrices_from_euler(0, PHI_111, 45, degrees=True)
    M = indentation_modulus(in_sample_frame(cu, R))
    M_111 = indentation_modulus(cu.rotated((1, 1, 1)))
    assert abs(M - M_111) <= 1e-10 * M_111


# --- random orientations -----------------------------------------------------------------------


def test_random_orientations_are_seeded_rotations_uniform_in_trace():
    R = random_orientations(4000, seed=6)
    assert R.shape == (4000, 3, 3)
    np.testing.assert_allclose(random_orientations(4000, seed=6), R, **EXACT)
    np.testing.assert_allclose(np.linalg.det(R), 1, rtol=0, atol=1e-12)
    # Haar measure: E[tr R] = 0 and E[R_ij] = 0; the normal R[2] is uniform on the sphere
    assert abs(np.trace(R, axis1=1, axis2=2).mean()) < 0.05
    assert np.all(np.abs(R.mean(axis=0)) < 0.05)
    assert abs(np.mean(np.abs(R[:, 2, 2])) - 0.5) < 0.02  # |cos θ| uniform on [0, 1]
    assert random_orientations(0).shape == (0, 3, 3)
    with pytest.raises(ValueError):
        random_orientations(-1)
