"""The θ points a fit asks for up front (contactres.polycrystal._moduli.moduli_and_points).

A fit's next rows need about as many points of the θ rule as its last ones, so it evaluates
them in one stacked call instead of one call per doubling (issue 31, point 6). Only the
batching may change: every row must be the bits of its own indentation_moduli call whatever
the points asked for (fewer than a row needs, as many, or more), and the points reported must
be those of the rule, recomputed here from the static kernel by the trapezoidal rule.
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres import Material, static_kernel
from contactres.errors import ContactresInputError
from contactres.materials import rotation_to_surface
from contactres.polycrystal import indentation_moduli, surface_matrices_from_euler
from contactres.polycrystal._moduli import moduli_and_points

CU = Material.crystal("Cu")


def _orientations(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.uniform(0.0, 1.0, (n, 3)) * [2 * np.pi, np.pi, 2 * np.pi]
    return surface_matrices_from_euler(e[:, 0], e[:, 1], e[:, 2], degrees=False)


def _points_of_the_rule(m: Material, normal, rtol: float) -> int:
    """θ points on [0, π) with which the trapezoidal rule of I₀ = ∫Ĝ and I₁ = ∫Ĝ cos²θ first
    changes by <= ``rtol`` relative to I₀ on doubling (Ĝ of the face from static_kernel)."""
    face = m.rotated(normal)
    n = 16
    while True:
        theta = np.pi * np.arange(2 * n) / (2 * n)
        g = static_kernel(face, theta)
        coarse = np.array([g[::2].sum(), (g[::2] * np.cos(theta[::2]) ** 2).sum()]) * np.pi / n
        fine = np.array([g.sum(), (g * np.cos(theta) ** 2).sum()]) * np.pi / (2 * n)
        if np.max(np.abs(fine - coarse)) <= rtol * abs(fine[0]):
            return 2 * n
        n *= 2


@pytest.mark.parametrize(
    ("first", "rtol"), [(None, 1e-12), (32, 1e-12), (64, 1e-12), (256, 1e-12), (64, 1e-8)]
)
def test_rows_are_each_materials_own_bits_whatever_the_first_points(first, rtol):
    # Cu and two unit crystals as a fit builds them, strongly anisotropic cubic (A = 6: more
    # points than the others), hexagonal Zn and trigonal sapphire (no mirror faces).
    R = _orientations(12, seed=21)
    mats = [
        CU,
        Material.cubic(1.0, 0.72, 0.46),
        Material.cubic(1.0, 0.72 * np.exp(1e-3), 0.46),
        Material.cubic(1.0, 0.5, 1.5),
        Material.hexagonal(165e9, 31.1e9, 50.0e9, 61.8e9, 39.6e9),
        Material.crystal("sapphire"),
    ]
    got, points = moduli_and_points(mats, R, rtol=rtol, first_points=first)
    assert got.shape == (len(mats), 12) and points is not None
    for row, m in zip(got, mats, strict=True):
        assert np.array_equal(row, indentation_moduli(m, R, rtol=rtol))
    alone, _ = moduli_and_points(mats[:1], R, rtol=rtol, first_points=first)
    assert np.array_equal(alone[0], got[0])


def test_points_are_those_of_the_trapezoidal_rule():
    normals = [(0, 0, 1), (1, 1, 1), (1, 1, 0), (1, 2, 3)]
    R = np.stack([rotation_to_surface(n) for n in normals])
    for m, rtol in ((CU, 1e-12), (Material.cubic(1.0, 0.5, 1.5), 1e-12), (CU, 1e-6)):
        want = min(_points_of_the_rule(m, n, rtol) for n in normals)
        for first in (None, 16, want, 4 * want):
            assert moduli_and_points([m], R, rtol=rtol, first_points=first)[1] == want
    # Cu meets 1e-12 with 64 points (indentation_moduli's documentation).
    assert moduli_and_points([CU], R, rtol=1e-12)[1] == 64


def test_no_rule_and_bad_first_points():
    R = _orientations(3, seed=22)
    assert moduli_and_points([CU.with_loss(0.01)], R)[1] is None
    assert moduli_and_points([Material.isotropic(70e9, 0.22)], R)[1] is None
    assert moduli_and_points([CU], np.zeros((0, 3, 3)))[1] is None
    for bad in (8, 48, 2**16):
        with pytest.raises(ContactresInputError, match="first_points"):
            moduli_and_points([CU], R, first_points=bad)
