"""Inverse problem of a hexagonal polycrystal map (contactres.polycrystal._inverse_hexagonal).

Synthetic data built here: random grain orientations and the exact forward model
(indentation_moduli) of Zn, C11, C12, C13, C33, C44 = 165, 31.1, 50.0, 61.8, 39.6 GPa (room
temperature handbook values, e.g. Simmons & Wang 1971), as a modulus map with 1e-4 relative
errors per grain.
"""

from __future__ import annotations

import numpy as np
import pytest

from contactres import Material
from contactres.polycrystal._inverse import fit_map
from contactres.polycrystal._inverse_hexagonal import HEXAGONAL, fit_hexagonal_constants
from contactres.polycrystal._moduli import indentation_moduli
from contactres.polycrystal._orientations import random_orientations

ZN_C = np.array([165.0, 31.1, 50.0, 61.8, 39.6]) * 1e9
ZN = Material.hexagonal(*ZN_C)
TRUE = ZN_C[1:] / ZN_C[0]
# 10 % off the truth, alternating signs: a start the fit has to walk from.
GUESS = dict(zip(HEXAGONAL.names, TRUE * np.array([1.1, 0.9, 1.1, 0.9]), strict=True))
REL = 1e-4


def rotation_about_z(phi: np.ndarray) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    Rz = np.zeros((phi.size, 3, 3))
    Rz[:, 0, 0], Rz[:, 0, 1], Rz[:, 1, 0], Rz[:, 1, 1], Rz[:, 2, 2] = c, -s, s, c, 1.0
    return Rz


@pytest.fixture(scope="module")
def grains():
    R = random_orientations(60, seed=1)
    return R, indentation_moduli(ZN, R)


@pytest.fixture(scope="module")
def noise_free(grains):
    R, M = grains
    return fit_hexagonal_constants(R, M, REL * M, quantity="modulus", guess=GUESS)


def test_noise_free_zn_reproduces_the_determined_combinations(noise_free):
    res = noise_free
    assert res.success and res.chi2_dof < 1e-6
    lr = res.parameters[-4:]
    assert res.parameter_names[-4:] == tuple(f"ln_{n}" for n in HEXAGONAL.names)
    assert 1 <= res.n_identified < 4
    for i in range(res.n_identified):
        # Noise-free and converged to χ² ~ 0: the fitted combination is the true one to a small
        # fraction of its (1e-4-level) standard error.
        d = float(res.directions[i] @ (lr - np.log(TRUE)))
        assert abs(d) < 0.01 * res.combination_errors[i], (i, d)
        assert res.combinations[i] == pytest.approx(np.exp(res.directions[i] @ np.log(TRUE)))
    # Directions: orthonormal rows, strong to weak, each a combination over all four ratios.
    np.testing.assert_allclose(res.directions @ res.directions.T, np.eye(4), atol=1e-12)
    assert np.all(np.diff(res.ratio_singular_values) < 0)
    assert np.all(np.diff(res.combination_errors) > 0)


def test_undetermined_combination_gives_nan_ratios_and_a_warning(noise_free):
    res = noise_free
    n = res.n_identified
    assert not res.identified[-1] and res.combination_errors[-1] > 0.1
    assert np.all(np.isnan(res.ratios)) and np.isnan(res.c13)
    assert np.all(np.isnan(res.combinations[n:])) and np.all(np.isfinite(res.combinations[:n]))
    assert any(f"{n} of 4 combinations" in w for w in res.warnings)
    text = res.summary()
    assert "not determined" in text and "nan" not in text
    assert text.count("combination ") >= 4
    assert max(len(line) for line in text.splitlines()) <= 100  # wrapped for a terminal


def test_singular_directions_do_not_depend_on_the_noise_draw(grains, noise_free):
    R, M = grains
    for seed in (3, 4, 5):
        y = M * (1 + REL * np.random.default_rng(seed).normal(size=M.size))
        res = fit_hexagonal_constants(R, y, REL * M, quantity="modulus", guess=GUESS)
        assert res.success and 0.3 < res.chi2_dof < 2.5
        # The directions are those of the Jacobian at the fitted point, which differs from the
        # truth by the noise, mostly along the undetermined combination (~0.2 in log): that
        # turns them by a few degrees at most.
        dots = np.abs(np.sum(res.directions * noise_free.directions, axis=1))
        assert np.all(dots > 0.99), dots
        assert res.n_identified == noise_free.n_identified


def test_rotating_every_grain_about_the_c_axis_changes_nothing():
    # M depends only on the angle between the surface normal and the c axis: R -> R Rz(φ)
    # (each grain turned by its own φ about the crystal z = c axis) keeps R[2, 2].
    R = random_orientations(20, seed=7)
    M = indentation_moduli(ZN, R)
    # 1e-5 per grain: the fits converge in half the evaluations of 1e-3 (58 against 120) and
    # agree to 5e-10; a crystal that is not transversely isotropic (C66 1 % off (C11 − C12)/2
    # in the unit crystal of the fit) moves them apart by 0.05 at 1e-5 as at 1e-3 (measured).
    y = M * (1 + 1e-5 * np.random.default_rng(8).normal(size=M.size))
    phi = np.random.default_rng(9).uniform(0, 2 * np.pi, size=20)
    R2 = R @ rotation_about_z(phi)
    np.testing.assert_allclose(R2[:, 2, 2], R[:, 2, 2], rtol=0, atol=1e-14)
    np.testing.assert_allclose(indentation_moduli(ZN, R2), M, rtol=1e-12, atol=0)
    a, b = (
        fit_hexagonal_constants(r, y, 1e-5 * M, quantity="modulus", guess=GUESS) for r in (R, R2)
    )
    np.testing.assert_allclose(b.parameters, a.parameters, rtol=0, atol=1e-8)
    np.testing.assert_allclose(b.ratio_singular_values, a.ratio_singular_values, rtol=1e-6)
    assert b.chi2 == pytest.approx(a.chi2, rel=1e-6, abs=1e-12)


def test_isotropic_constants_written_as_hexagonal_see_only_the_anisotropy():
    # C11 = C33, C12 = C13, C44 = (C11 − C12)/2: M is the same in every orientation. To first
    # order about isotropy δM(θ) lies in span{1, cos²θ, cos⁴θ} (δC contracted with n n and
    # n n n n, n·c = cos θ); the constant goes into the scale, so at most two anisotropic
    # combinations are seen; the other two only at second order.
    r12, r44 = 0.4, 0.3
    iso = Material.hexagonal(1.0, r12, r12, 1.0, r44)
    R = random_orientations(30, seed=2)
    m = indentation_moduli(iso, R)
    assert np.ptp(m) < 1e-12 * m.mean()
    start = {"c12_c11": 0.41, "c13_c11": 0.39, "c33_c11": 1.02, "c44_c11": 0.295}
    res = fit_hexagonal_constants(R, m, 1e-4 * m, quantity="modulus", guess=start)
    s = res.ratio_singular_values
    assert s[2] < 1e-5 * s[0] and res.n_identified <= 2
    assert not res.identified[2] and not res.identified[3]
    assert np.all(np.isnan(res.ratios))
    # Along the isotropic family (ν changes, C11 = C33, C12 = C13, C44 = (C11 − C12)/2) M
    # changes uniformly: invisible with a free scale, so it is the weakest direction, and the
    # determined ones are pure anisotropy (orthogonal to it).
    t = np.array([1.0, 1.0, 0.0, -r12 / (1 - r12)])
    t /= np.linalg.norm(t)
    assert abs(float(res.directions[-1] @ t)) > 0.999
    assert np.all(np.abs(res.directions[: res.n_identified] @ t) < 0.05)


def test_stability_region_and_unstable_guess():
    assert HEXAGONAL.admissible(TRUE)
    # (C11 + C12) C33 > 2 C13² fails: 1.3 · 0.5 < 2 · 0.81.
    assert not HEXAGONAL.admissible(np.array([0.3, 0.9, 0.5, 0.3]))
    R = random_orientations(5, seed=3)
    M = indentation_moduli(ZN, R)
    bad = {"c12_c11": 0.3, "c13_c11": 0.9, "c33_c11": 0.5, "c44_c11": 0.3}
    with pytest.raises(ValueError, match="stable"):
        fit_hexagonal_constants(R, M, 1e-3 * M, quantity="modulus", guess=bad)


def test_fit_map_dispatches_on_the_lattice_and_rejects_bad_input():
    rng = np.random.default_rng(11)
    G = 12
    R = random_orientations(G, seed=12)
    labels = np.repeat(np.arange(G), 50).reshape(G * 5, 10)
    M = indentation_moduli(ZN, R)
    # 1e-5 pixel noise: a fit that converges in about half the evaluations of one at 1e-3 (which
    # walks its 30 steps along the undetermined combinations); the dispatch is the same.
    values = M[labels] * (1 + 1e-5 * rng.normal(size=labels.shape))
    res = fit_map(labels, values, R, lattice="hexagonal", quantity="modulus", guess=GUESS)
    assert res.n_grains == G and res.ratio_names == HEXAGONAL.names
    assert res.directions.shape == (4, 4)
    with pytest.raises(ValueError, match="lattice"):
        fit_map(labels, values, R, lattice="tetragonal", quantity="modulus")
    with pytest.raises(ValueError, match="shape"):
        fit_map(labels, values, R[:, :2], lattice="hexagonal")
    with pytest.raises(ValueError, match="need orientations"):
        fit_hexagonal_constants(R[:5], M, 1e-3 * M)
    with pytest.raises(ValueError, match="need orientations"):
        fit_hexagonal_constants(R, M, 1e-3 * M[:5])
    with pytest.raises(ValueError, match="unknown guess"):
        fit_hexagonal_constants(R, M, 1e-3 * M, guess={"c66_c11": 0.4})
    with pytest.raises(ValueError, match="quantity"):
        fit_hexagonal_constants(R, M, 1e-3 * M, quantity="hardness")
