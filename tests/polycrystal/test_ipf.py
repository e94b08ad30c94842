"""IPF colours and the standard triangle (contactres.polycrystal._ipf).

Independent facts: the corner directions and their conventional colours, the Laue group (48 or
24 operations), the stereographic projection of known directions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contactres.polycrystal._ipf import ipf_colors, ipf_triangle
from contactres.polycrystal._orientations import symmetry_operators

RED, GREEN, BLUE = np.eye(3)
C30, S30 = math.cos(math.pi / 6), math.sin(math.pi / 6)
# Hexagonal: a1 along x (Material.hexagonal), a2 at 120°; [uvtw] -> u a1 + v a2 + t a3.
A1, A2 = np.array([1.0, 0.0, 0.0]), np.array([-0.5, C30, 0.0])
A3 = -A1 - A2


def bravais(u, v, t, w):
    return u * A1 + v * A2 + t * A3 + w * np.array([0.0, 0.0, 1.0])


def laue_group(lattice: str) -> np.ndarray:
    S = symmetry_operators(lattice)
    return np.concatenate([S, -S])


def test_cubic_corners_are_pure_colours():
    # [001], [101], [111] and equivalents in other octants.
    dirs = np.array([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, -3, 0], [0, 1, -1], [-1, 1, -1]], float)
    expected = np.array([RED, GREEN, BLUE, RED, GREEN, BLUE])
    assert np.allclose(ipf_colors(dirs, "cubic"), expected, rtol=0, atol=1e-12)


def test_hexagonal_corners_are_pure_colours():
    dirs = np.array([bravais(0, 0, 0, 1), bravais(2, -1, -1, 0), bravais(1, 0, -1, 0)])
    assert np.allclose(ipf_colors(dirs, "hexagonal"), np.eye(3), rtol=0, atol=1e-12)
    # [10-10] lies at 30° from a1, [2-1-10] along it.
    assert np.allclose(dirs[1] / np.linalg.norm(dirs[1]), A1, rtol=0, atol=1e-12)
    assert np.isclose(math.atan2(dirs[2][1], dirs[2][0]), math.pi / 6, rtol=0, atol=1e-12)


@pytest.mark.parametrize("lattice", ["cubic", "hexagonal"])
def test_equivalent_directions_have_equal_colours(lattice):
    ops = laue_group(lattice)
    assert len(ops) == (48 if lattice == "cubic" else 24)
    v = np.random.default_rng(1).normal(size=(200, 3))
    base = ipf_colors(v, lattice)
    images = np.einsum("kij,nj->kni", ops, v)
    assert np.allclose(ipf_colors(images, lattice), base[None], rtol=0, atol=1e-12)


@pytest.mark.parametrize("lattice", ["cubic", "hexagonal"])
def test_colours_in_unit_range_with_max_one(lattice):
    rgb = ipf_colors(np.random.default_rng(2).normal(size=(5000, 3)), lattice)
    assert rgb.min() >= 0.0 and rgb.max() <= 1.0
    assert np.allclose(rgb.max(axis=-1), 1.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("lattice", ["cubic", "hexagonal"])
def test_nearby_directions_have_nearby_colours(lattice):
    rng = np.random.default_rng(3)
    v = rng.normal(size=(5000, 3))
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    eps = 1e-4
    w = v + eps * rng.normal(size=v.shape)
    diff = np.abs(ipf_colors(v, lattice) - ipf_colors(w, lattice)).max()
    # Lipschitz: a few times the step (the weights' slope is ~1/arcsin(c·m) <= 1/0.52 rad),
    # also across the triangle's edges (folding is continuous).
    assert diff < 50 * eps


def test_edges_mix_only_their_two_corners():
    # The edge [001]-[101] (x = 0 after folding) has no blue; [001]-[111] no green.
    t = np.linspace(0.01, 0.99, 50)[:, None]
    e1 = (1 - t) * np.array([0, 0, 1.0]) + t * np.array([1, 0, 1.0])
    e2 = (1 - t) * np.array([0, 0, 1.0]) + t * np.array([1, 1, 1.0])
    assert np.allclose(ipf_colors(e1, "cubic")[:, 2], 0.0, rtol=0, atol=1e-12)
    assert np.allclose(ipf_colors(e2, "cubic")[:, 1], 0.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("lattice", ["cubic", "hexagonal"])
def test_triangle_grid_and_outline(lattice):
    tri = ipf_triangle(lattice, n=41, boundary_points=30)
    assert tri.x.shape == tri.y.shape == tri.inside.shape == (41, 41)
    assert np.allclose(tri.boundary[0], tri.boundary[-1], rtol=0, atol=1e-15)
    # Corners project as the stereographic formula says, and get their pure colours.
    assert np.allclose(ipf_colors(tri.corners, lattice), np.eye(3), rtol=0, atol=1e-12)
    if lattice == "cubic":
        expected = [(0, 0), (math.tan(math.pi / 8), 0), (1 / (math.sqrt(3) + 1),) * 2]
    else:
        expected = [(0, 0), (1, 0), (C30, S30)]
    assert np.allclose(tri.corner_xy, expected, rtol=0, atol=1e-12)
    # Grid normals are unit, their projection is the grid; inside points are in the triangle.
    assert np.allclose(np.linalg.norm(tri.normals, axis=-1), 1.0, rtol=0, atol=1e-12)
    n = tri.inside_normals
    assert n.shape == (tri.inside.sum(), 3) and tri.points.shape == (tri.inside.sum(), 2)
    if lattice == "cubic":
        assert np.all((n[:, 0] <= n[:, 1] + 1e-12) & (n[:, 1] <= n[:, 2] + 1e-12))
        assert np.all(n[:, 0] >= -1e-12)
        xy = np.stack([n[:, 1], n[:, 0]], -1) / (1 + n[:, 2:])
    else:
        az = np.degrees(np.arctan2(n[:, 1], n[:, 0]))
        assert np.all((az >= -1e-9) & (az <= 30 + 1e-9) & (n[:, 2] >= -1e-12))
        xy = n[:, :2] / (1 + n[:, 2:])
    assert np.allclose(xy, tri.points, rtol=0, atol=1e-12)
    # About half of the bounding box of a triangle lies inside it.
    assert 0.3 < tri.inside.mean() < 0.7


def test_bad_input():
    with pytest.raises(ValueError, match="lattice"):
        ipf_colors([0, 0, 1], "orthorhombic")
    with pytest.raises(ValueError, match="shape"):
        ipf_colors([0, 1], "cubic")
    with pytest.raises(ValueError, match="finite"):
        ipf_colors([np.nan, 0, 1], "cubic")
    with pytest.raises(ValueError, match="n must be"):
        ipf_triangle("cubic", n=1)
    with pytest.raises(ValueError, match="lattice"):
        ipf_triangle("trigonal")
