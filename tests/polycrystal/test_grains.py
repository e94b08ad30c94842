"""Grains of unlabelled maps (contactres.polycrystal._grains).

Independent checks: the true Voronoi grains of synthetic maps, the angle modulo symmetry by
brute force over the 48 (24) operations of the Laue group, symmetric-equivalent pixels, the
cube group written out by hand.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_array
from scipy.sparse.csgraph import connected_components
from signed_permutations import cubic_group_by_hand

from contactres.polycrystal import OrientationMap, synthetic_polycrystal
from contactres.polycrystal._grains import folded_normals, grain_orientations, segment_grains
from contactres.polycrystal._normal_table import reduce_normals
from contactres.polycrystal._orientations import (
    euler_from_surface_matrices,
    surface_matrices_from_euler,
    symmetry_operators,
)

TOL = 2.0


def laue_group(lattice: str) -> np.ndarray:
    """The proper rotations and their products with the inversion: 48 (cubic) or 24."""
    S = symmetry_operators(lattice)
    return np.concatenate([S, -S])


def brute_angle(a: np.ndarray, b: np.ndarray, lattice: str) -> np.ndarray:
    """Smallest angle (deg) between a (..., 3) and every symmetric equivalent of b (..., 3)."""
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    images = np.einsum("kij,...j->...ki", laue_group(lattice), b)
    cos = np.einsum("...i,...ki->...k", a, images).max(axis=-1)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def expected_partition(m, lattice: str, tol: float = TOL) -> np.ndarray:
    """The true grains, split where not 4-connected on the pixel grid (a thin Voronoi cell can
    touch itself only diagonally) and joined where touching grains have normals within
    ``tol`` (brute force over the Laue group)."""
    lab, G = m.labels, m.n_grains
    n = surface_matrices_from_euler(*m.grain_euler.T, degrees=False)[:, 2]
    gi, gj = np.meshgrid(np.arange(G), np.arange(G), indexing="ij")
    close = brute_angle(n[gi], n[gj], lattice) < tol  # (G, G), the diagonal True
    idx = np.arange(lab.size).reshape(lab.shape)
    src = np.concatenate([idx[:, :-1].ravel(), idx[:-1].ravel()])
    dst = np.concatenate([idx[:, 1:].ravel(), idx[1:].ravel()])
    keep = close[lab.ravel()[src], lab.ravel()[dst]]
    graph = coo_array((np.ones(keep.sum()), (src[keep], dst[keep])), shape=(lab.size,) * 2)
    return connected_components(graph, directed=False)[1].reshape(lab.shape)


def same_partition(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal up to relabelling: the label pairs are a bijection."""
    pairs = np.unique(np.stack([a.ravel(), b.ravel()], -1), axis=0)
    return len(pairs) == len(np.unique(a)) == len(np.unique(b))


def coarsens(found: np.ndarray, true: np.ndarray) -> bool:
    """Every true region lies in one found region (found regions are unions of true ones)."""
    pairs = np.unique(np.stack([found.ravel(), true.ravel()], -1), axis=0)
    return len(np.unique(pairs[:, 1])) == len(pairs)


def test_folding_gives_the_smallest_angle_over_the_laue_group():
    rng = np.random.default_rng(11)
    for lattice in ("cubic", "hexagonal"):
        a, b = rng.normal(size=(2, 2000, 3))
        fa, fb = reduce_normals(a, lattice)[0], reduce_normals(b, lattice)[0]
        folded = np.degrees(np.arccos(np.clip(np.sum(fa * fb, -1), -1, 1)))
        assert np.allclose(folded, brute_angle(a, b, lattice), rtol=0, atol=1e-6)
        # also close pairs (the regime of a tolerance of a few degrees)
        c = b + 0.02 * rng.normal(size=b.shape)
        fc = reduce_normals(c, lattice)[0]
        folded = np.degrees(np.arccos(np.clip(np.sum(fb * fc, -1), -1, 1)))
        assert np.allclose(folded, brute_angle(b, c, lattice), rtol=0, atol=1e-5)


def test_the_laue_group_of_the_test_is_the_cube_group_with_inversion():
    hand = cubic_group_by_hand()
    group = laue_group("cubic")
    assert len(group) == 48
    assert {tuple(s.ravel()) for s in np.concatenate([hand, -hand])} == {
        tuple(s.ravel()) for s in group
    }


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_segmentation_reproduces_the_voronoi_grains(seed):
    m = synthetic_polycrystal((50, 70), 14, seed=seed)
    labels = segment_grains(m, "cubic", TOL)
    assert labels.min() == 0 and labels.max() == len(np.unique(labels)) - 1
    assert coarsens(labels, expected_partition(m, "cubic", tol=1e-9))
    assert same_partition(labels, expected_partition(m, "cubic"))
    # From the matrices as from the map: the same labels.
    assert np.array_equal(segment_grains(m.surface_matrices(), "cubic", TOL), labels)


def test_segmentation_equals_true_partition_when_neighbours_differ():
    # Seed 1: every pair of touching grains differs by more than the tolerance (checked).
    m = synthetic_polycrystal((50, 70), 14, seed=1)
    assert touching_angles(m, "cubic").min() > TOL
    assert same_partition(expected_partition(m, "cubic"), m.labels)
    assert same_partition(segment_grains(m, "cubic"), m.labels)


def touching_angles(m, lattice: str) -> np.ndarray:
    """Angle modulo symmetry (deg, brute force) of the normals of every touching grain pair."""
    lab = m.labels
    pairs = np.concatenate(
        [
            np.stack([lab[:, :-1].ravel(), lab[:, 1:].ravel()], -1),
            np.stack([lab[:-1].ravel(), lab[1:].ravel()], -1),
        ]
    )
    pairs = np.unique(pairs[pairs[:, 0] != pairs[:, 1]], axis=0)
    n = surface_matrices_from_euler(*m.grain_euler.T, degrees=False)[:, 2]
    return brute_angle(n[pairs[:, 0]], n[pairs[:, 1]], lattice)


def test_segmentation_is_robust_to_orientation_noise():
    # Seed 4: touching grains differ by > 5° (checked), well clear of the 2° tolerance plus
    # the noise of a neighbour difference (0.3° per Euler angle -> ~0.4° per component).
    m = synthetic_polycrystal((60, 60), 12, seed=4)
    assert touching_angles(m, "cubic").min() > 5.0
    rng = np.random.default_rng(5)
    noisy_euler = m.euler + np.radians(0.3) * rng.normal(size=m.euler.shape)
    R = surface_matrices_from_euler(*np.moveaxis(noisy_euler, -1, 0), degrees=False)
    labels = segment_grains(R, "cubic", TOL)
    assert same_partition(labels, expected_partition(m, "cubic"))
    spread = grain_orientations(labels, R, "cubic")
    assert np.all(spread.max_spread_deg < 3.0) and np.all(spread.rms_spread_deg < 1.0)
    assert np.all(spread.rms_spread_deg > 0.05)  # the noise is seen


def test_symmetric_equivalent_pixels_do_not_split_a_grain():
    m = synthetic_polycrystal((40, 50), 6, seed=3)
    R = m.surface_matrices()
    S = cubic_group_by_hand()
    grain = m.labels == np.bincount(m.labels.ravel()).argmax()
    half = grain & (np.arange(50)[None, :] % 2 == 0)  # every other column: interleaved
    R[half] = R[half] @ S[5]
    assert not np.allclose(R[half][:, 2], m.surface_matrices()[half][:, 2])  # normals changed
    labels = segment_grains(R, "cubic", 0.1)
    assert len(np.unique(labels[grain])) == 1
    assert same_partition(labels, segment_grains(m, "cubic", 0.1))


def test_hexagonal_segmentation_and_symmetry():
    m = synthetic_polycrystal((40, 60), 10, seed=2)
    labels = segment_grains(m, "hexagonal")
    assert coarsens(labels, expected_partition(m, "hexagonal", tol=1e-9))
    assert same_partition(labels, expected_partition(m, "hexagonal"))
    R = m.surface_matrices()
    ops = laue_group("hexagonal")
    # A different equivalent per pixel (including improper ones acting on the normal only).
    k = np.random.default_rng(0).integers(0, len(ops), size=m.shape)
    normals = np.einsum("hwij,hwj->hwi", ops[k], R[..., 2, :])
    R2 = R.copy()
    R2[..., 2, :] = normals  # only the normal row matters for the segmentation
    assert np.array_equal(segment_grains(R2, "hexagonal"), labels)


def test_grain_orientations_of_exact_grains():
    m = synthetic_polycrystal((30, 40), 5, seed=2)
    go = grain_orientations(m.labels, m, "cubic")
    true_n = surface_matrices_from_euler(*m.grain_euler.T, degrees=False)[:, 2]
    # The representative normal is the folded true normal; spread zero; matrices proper.
    assert np.allclose(go.normals, reduce_normals(true_n, "cubic")[0], rtol=0, atol=1e-12)
    assert np.allclose(go.matrices[:, 2], go.normals, rtol=0, atol=1e-12)
    assert np.allclose(np.linalg.det(go.matrices), 1.0, rtol=0, atol=1e-12)
    assert np.allclose(go.max_spread_deg, 0.0, rtol=0, atol=1e-5)
    assert np.array_equal(go.pixels, np.bincount(m.labels.ravel(), minlength=5))


def test_grain_spread_is_the_angle_modulo_symmetry():
    # Two pixels 3° apart within the mirror x = y, one inverted (-n): 1.5° each from the mean.
    n0 = np.array([1.0, 1.0, 2.5]) / np.linalg.norm([1.0, 1.0, 2.5])
    axis = np.cross(n0, [1.0, -1.0, 0.0]) / np.linalg.norm(np.cross(n0, [1.0, -1.0, 0.0]))
    t = np.radians(1.5)
    normals = [n0 * np.cos(t) + axis * np.sin(t), -(n0 * np.cos(t) - axis * np.sin(t))]
    R = np.zeros((1, 2, 3, 3))
    R[0, :, 2] = normals
    go = grain_orientations(np.zeros((1, 2), dtype=int), R, "cubic")
    assert np.allclose(go.max_spread_deg, 1.5, rtol=0, atol=1e-9)
    assert np.allclose(go.normals[0], n0, rtol=0, atol=1e-12)


def test_nonfinite_pixels_and_small_regions_get_minus_one():
    m = synthetic_polycrystal((30, 30), 4, seed=1)
    R = m.surface_matrices()
    R[3, 4] = np.nan
    R[10, 10, 2] = [0.0, 0.0, 0.0]  # a zero normal is not a direction
    labels = segment_grains(R, "cubic")
    assert labels[3, 4] == -1 and labels[10, 10] == -1
    assert (labels >= 0).sum() == 900 - 2
    e = m.euler.copy()
    e[5, 5] = np.nan
    omap = OrientationMap(e, 1e-6, 1e-6, m.phase, m.confidence)
    assert segment_grains(omap, "cubic")[5, 5] == -1
    # An isolated pixel of another orientation: its own region, dropped by min_pixels = 2.
    R = m.surface_matrices()
    R[15, 15] = surface_matrices_from_euler(0.1, 0.7, 0.3, degrees=False)
    assert segment_grains(R, "cubic")[15, 15] >= 0
    small = segment_grains(R, "cubic", min_pixels=2)
    assert small[15, 15] == -1 and same_partition(small[small >= 0], m.labels[small >= 0])
    go = grain_orientations(labels, R, "cubic", n_grains=int(labels.max()) + 2)
    assert go.pixels[-1] == 0 and np.isnan(go.normals[-1]).all()


def test_labels_are_in_raster_order():
    m = synthetic_polycrystal((30, 30), 6, seed=4)
    labels = segment_grains(m, "cubic").ravel()
    first = [int(np.flatnonzero(labels == g)[0]) for g in range(labels.max() + 1)]
    assert first == sorted(first)


def test_folded_normals_of_map_and_matrices_agree():
    m = synthetic_polycrystal((10, 12), 3, seed=1)
    e = euler_from_surface_matrices(m.surface_matrices(), degrees=False)
    R = surface_matrices_from_euler(*np.moveaxis(e, -1, 0), degrees=False)
    assert np.allclose(folded_normals(m, "cubic"), folded_normals(R, "cubic"), atol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"orientations": np.zeros((4, 4, 3))}, "shape"),
        ({"orientations": np.zeros((4, 3, 3))}, "shape"),
        ({"tolerance_deg": 0.0}, "tolerance_deg"),
        ({"tolerance_deg": -1.0}, "tolerance_deg"),
        ({"tolerance_deg": np.nan}, "tolerance_deg"),
        ({"lattice": "tetragonal"}, "lattice must be one of"),
        ({"min_pixels": 0}, "min_pixels"),
        ({"min_pixels": 2.5}, "min_pixels"),
    ],
)
def test_bad_input_raises(kwargs, message):
    args = {"orientations": np.tile(np.eye(3), (4, 4, 1, 1)), "lattice": "cubic"} | kwargs
    with pytest.raises(ValueError, match=message):
        segment_grains(**args)


def test_grain_orientations_bad_input():
    R = np.tile(np.eye(3), (4, 4, 1, 1))
    with pytest.raises(ValueError, match="shape"):
        grain_orientations(np.zeros((3, 4), dtype=int), R, "cubic")
    with pytest.raises(ValueError, match="integers"):
        grain_orientations(np.zeros((4, 4)), R, "cubic")
    with pytest.raises(ValueError, match="lattice"):
        grain_orientations(np.zeros((4, 4), dtype=int), R, "trigonal")
