"""Checks of the independent isotropic reference for the horizontal (tangential) rigid disk.

The reference (:mod:`tangential_isotropic_reference`, next to this file) is a Galerkin with the
isotropic dynamic surface Green's function in Fourier space and a Mindlin traction basis, the
ξ integrals along a contour above the branch points and the Rayleigh pole; nothing comes from
:mod:`contactres`. These tests check it against what is known without it:

* a₀ -> 0: Mindlin's K_t0 = 8Ga/(2 − ν) and the first-order radiation damping c_t(0), computed
  a second way (real-axis ``quad`` over the radiating band + Rayleigh residue, a perturbation of
  the static traction (1 − r²)^{−1/2}), not along the Galerkin's contour;
* convergence when every resolution knob (basis size, contour and panel nodes, ξ_max) is doubled.

Published numbers: none compared. Searches (stored pages and docs) for the tables of Luco &
Westmann (1971, J. Eng. Mech. Div. ASCE 97, 1381–1395), Veletsos & Wei (1971, J. Soil Mech.
Found. Div. ASCE 97, 1227–1248) and Wong & Luco found only abstracts and citations, no
tabulated horizontal impedances; none are quoted here rather than recalled digits.
"""

import itertools

import numpy as np
import pytest
from tangential_isotropic_reference import (
    _kernels,
    _tail_coefficients,
    low_frequency_damping,
    rayleigh_root,
    tangential_disk,
)


# ------------------------------------------------------------------ the Green's function
@pytest.mark.parametrize("nu", [0.0, 0.25, 1 / 3, 0.45])
def test_kernel_static_limit_tail_and_rayleigh_pole(nu):
    """Aξ -> 1 − ν, Bξ -> 1 (Cerruti), with the a₀²/ξ² coefficients of the tail correction; the
    rationalised Rayleigh function (used on the real axis) equals the direct one where both are
    accurate; F vanishes at ζ_R (the pole the contour avoids)."""
    a0 = 1.0
    ca, cb = _tail_coefficients(nu)
    for xi in (300.0, 600.0):
        ka, kb = _kernels(np.array([xi]), a0, nu)
        assert (ka[0].real - (1 - nu)) * xi**2 == pytest.approx(ca, rel=1e-4)
        assert (kb[0].real - 1) * xi**2 == pytest.approx(cb, rel=1e-4)
    # direct form at ξ = 3 + 0j·(contour branch) vs rationalised form at ξ = 3 (real)
    direct = _kernels(np.array([3.0 + 1e-300j]), a0, nu)[0]
    rational = _kernels(np.array([3.0]), a0, nu)[0]
    assert abs(direct[0] - rational[0]) < 1e-13
    zr = rayleigh_root(nu)
    near = _kernels(np.array([zr * (1 + 1e-9)]), a0, nu)[0]
    assert abs(near[0]) > 1e6  # the pole sits on the real axis at ζ_R


# ------------------------------------------------------------------ low frequency
@pytest.mark.parametrize("nu", [0.0, 0.25, 0.45])
def test_static_limit_is_mindlin(nu):
    """K_t/K_t0 = 1 + i a₀ c_t(0) + O(a₀²). |K/K0 − 1| itself cannot be 1e-8 at a₀ = 1e-4 (the
    imaginary part is c_t(0) a₀ ≈ 6e-5), so the real part and the difference from the first-order
    form are checked to 1e-8. Measured: Re − 1 = −6.6e-10, −4.8e-10, −3.5e-10 (ν = 0, ¼, 0.45),
    and Re − 1 scales by 4.00 from a₀ = 1e-3 to 2e-3 (a genuine O(a₀²) term, not noise)."""
    a0 = 1e-4
    c0 = low_frequency_damping(nu)
    v = tangential_disk(a0, nu)
    assert abs(v.real - 1) < 1e-8
    assert abs(v - (1 + 1j * a0 * c0)) < 1e-8
    d1, d2 = (tangential_disk(x, nu).real - 1 for x in (1e-3, 2e-3))
    assert d1 < 0 and 3.9 < d2 / d1 < 4.1


@pytest.mark.parametrize("nu", [0.0, 0.17, 0.25, 1 / 3, 0.45])
def test_low_frequency_damping_from_first_order_perturbation(nu):
    """Im(K/K0)/a₀ at a₀ = 1e-3 against c_t(0) of the perturbation formula (real-axis quad +
    residue + the closed-form SH part): measured relative differences 3.5e-8 … 6.4e-8 (the O(a₀²)
    correction, 3.5e-2 a₀²), required 1e-4."""
    a0 = 1e-3
    c0 = low_frequency_damping(nu)
    c = tangential_disk(a0, nu).imag / a0
    assert c == pytest.approx(c0, rel=1e-4)


# ------------------------------------------------------------------ convergence
@pytest.mark.parametrize("nu", [0.17, 1 / 3, 0.45])
def test_converges_when_every_resolution_is_doubled(nu):
    """Doubling basis size (8 -> 16 per block), contour/panel nodes (32 -> 64) and ξ_max
    (200 -> 400) moves K/K0 by < 1e-7 for a₀ <= 2. Measured: <= 8e-9 (ν = 0.17, a₀ = 2), and the
    doubled rule moves by < 5e-11 when doubled again (24, 128, 800)."""
    for a0 in (0.1, 0.5, 1.0, 2.0):
        base = tangential_disk(a0, nu, 8, 32, 200.0)
        fine = tangential_disk(a0, nu, 16, 64, 400.0)
        assert abs(base - fine) < 1e-7


def test_basis_converges_spectrally():
    """The Mindlin basis needs few terms: at a₀ = 2, N = 1, 2, 3, 4 differ from N = 8 by
    ~7e-2, 5e-5, 3e-8, 1e-11 (measured)."""
    ref = tangential_disk(2.0, 1 / 3, 8)
    errs = [abs(tangential_disk(2.0, 1 / 3, n) - ref) for n in (1, 2, 3, 4)]
    assert errs[0] > 1e-2
    assert all(e2 < 1e-2 * e1 for e1, e2 in itertools.pairwise(errs))
    assert errs[-1] < 1e-9


# ------------------------------------------------------------------ values and the QCM estimate
def test_loss_tangent_is_about_0p6_a0_at_low_frequency():
    """The QCM estimate tan δ = Im/Re ≈ 0.6 a₀ per body for a₀ ≈ 0.1 … 0.2 holds to within 4 %
    for ν = 0.17 … ⅓: measured tan δ/a₀ = 0.6180 … 0.6197 (ν = 0.17, fused silica), 0.5984 …
    0.5999 (ν = ¼), 0.5806 … 0.5820 (ν = ⅓)."""
    for nu in (0.17, 0.25, 1 / 3):
        for a0 in (0.1, 0.2):
            v = tangential_disk(a0, nu)
            ratio = v.imag / v.real / a0
            assert 0.575 < ratio < 0.625
            # and it is the low-frequency damping plus a small positive drift
            assert 0 < ratio - low_frequency_damping(nu) < 3e-3
