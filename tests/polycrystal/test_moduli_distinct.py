"""indentation_moduli evaluates each distinct orientation of a stack once (issue 31).

A map has many pixels per grain; the reduction must leave every value as it was: the M of an
orientation repeated in a large stack equals, to the bit, its M evaluated alone, and matrices
that differ in any bit are kept apart. Likewise several materials evaluated in one stack
(stacked_indentation_moduli, the central differences of the ratio fits) give, row by row, the
bits of each material evaluated alone.
"""

from __future__ import annotations

import numpy as np

from contactres import Material
from contactres.polycrystal import indentation_moduli, surface_matrices_from_euler
from contactres.polycrystal._moduli import stacked_indentation_moduli


def _orientations(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.uniform(0.0, 1.0, (n, 3)) * [2 * np.pi, np.pi, 2 * np.pi]
    return surface_matrices_from_euler(e[:, 0], e[:, 1], e[:, 2], degrees=False)


def test_repeated_orientations_equal_each_alone():
    cu = Material.crystal("Cu")
    R = _orientations(12, seed=5)
    pixels = np.random.default_rng(6).integers(0, 12, 3000)
    got = indentation_moduli(cu, R[pixels])
    alone = np.array([indentation_moduli(cu, R[i : i + 1])[0] for i in range(12)])
    assert np.array_equal(got, alone[pixels])


def test_matrices_one_ulp_apart_are_evaluated_apart():
    """A matrix nudged by one ulp is a different orientation to the reduction (its own M, which
    equals that of the nudged matrix evaluated alone)."""
    cu = Material.crystal("Cu")
    R = _orientations(1, seed=8)
    nudged = R.copy()
    nudged[0, 0, 0] = np.nextafter(nudged[0, 0, 0], 2.0)
    stack = np.concatenate([R, nudged, R])
    got = indentation_moduli(cu, stack)
    assert got[0] == got[2] == indentation_moduli(cu, R)[0]
    assert got[1] == indentation_moduli(cu, nudged)[0]


def test_lossy_and_empty_stacks():
    lossy = Material.crystal("Cu").with_loss(0.01)
    R = _orientations(3, seed=9)
    got = indentation_moduli(lossy, R[[0, 1, 0, 2, 1]])
    assert np.iscomplexobj(got)
    assert np.array_equal(got, indentation_moduli(lossy, R)[[0, 1, 0, 2, 1]])
    assert indentation_moduli(Material.crystal("Cu"), np.zeros((0, 3, 3))).shape == (0,)


def test_several_materials_in_one_stack_equal_each_alone():
    # Cubic (Cu, a unit crystal as the ratio fits build, and one 0.1 % away) and trigonal
    # (sapphire: 6 independent constants) materials, over repeated orientations.
    R = _orientations(30, seed=12)[np.random.default_rng(13).integers(0, 30, 120)]
    mats = [
        Material.crystal("Cu"),
        Material.cubic(1.0, 0.72, 0.5),
        Material.cubic(1.0, 0.72 * np.exp(1e-3), 0.5),
        Material.crystal("sapphire"),
    ]
    got = stacked_indentation_moduli(mats, R, rtol=1e-12)
    assert got.shape == (4, 120) and got.dtype == float
    for row, m in zip(got, mats, strict=True):
        assert np.array_equal(row, indentation_moduli(m, R, rtol=1e-12))
    assert stacked_indentation_moduli(mats, np.zeros((0, 3, 3))).shape == (4, 0)
    assert stacked_indentation_moduli([], R).shape == (0, 120)


def test_lossy_or_isotropic_materials_in_a_stack_equal_each_alone():
    cu = Material.crystal("Cu")
    R = _orientations(5, seed=14)
    for mats in (
        [cu.with_loss(0.01), cu.with_loss(0.02)],
        [cu, Material.isotropic(70e9, 0.22)],
        [cu],
    ):
        got = stacked_indentation_moduli(mats, R)
        assert got.shape == (len(mats), 5)
        for row, m in zip(got, mats, strict=True):
            assert np.array_equal(row, indentation_moduli(m, R))
