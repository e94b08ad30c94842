"""Tests of contactres.dynamic._exact: the rigid flat punch (Galerkin) on an anisotropic solid.

Independent checks: the basis transforms against scipy quadrature, the one-term Galerkin against
the whole-contact weighted average (a different code path), the isotropic lossless rigid-disk
impedance of Luco & Westmann (1971), the static limit, convergence in the number of terms and of
every resolution, continuity through A = 1, the loss -> 0 limit, and the force balance of the
converged pressure.
"""

import math

import numpy as np
import pytest
from scipy import integrate, special

from contactres import Material, contact_pressure, dcsf, dcsf_models
from contactres.dynamic import ALL_MODELS, prepare, shear_wavenumber_ratio
from contactres.dynamic._exact import (
    GalerkinSize,
    exact_n,
    galerkin_size,
    model_size,
    pressure_basis,
)
from contactres.dynamic._quadrature import functionals
from contactres.dynamic._table import kernel_table, resolution_for

Q = 0.02


def _cubic(A, nu=0.25):
    return Material.cubic_from_ratios(zener=A, poisson=nu)


@pytest.mark.parametrize(("n", "k"), [(0, 0), (0, 3), (4, 0), (-4, 2), (8, 1)])
def test_pressure_basis_hankel_transform_is_spherical_bessel(n, k):
    def integrand(t, s):
        # r = sin t removes the 1/√(1 − r²) edge singularity: r dr = sin t cos t dt
        r = math.sin(t)
        return r * math.cos(t) * pressure_basis(n, k, r) * special.jv(abs(n), s * r)

    for s in (0.6, 4.0):
        val = integrate.quad(integrand, 0, math.pi / 2, args=(s,), limit=200, epsabs=1e-13)[0]
        assert val == pytest.approx(special.spherical_jn(abs(n) + 2 * k, s), abs=1e-11)


def test_one_term_galerkin_is_the_whole_contact_weighted_average():
    for A in (0.4, 1.0, 3.0):
        m = _cubic(A)
        table = kernel_table(m, Q)
        ksa = np.array([0.5, 2.0, 4.5])
        one = exact_n(table, ksa, GalerkinSize(n_radial=1, n_harmonics=0))
        np.testing.assert_allclose(one, functionals(table, ksa)["F2D"], rtol=1e-12)


def test_luco_westmann_rigid_disk_isotropic_lossless():
    """Rigid disk on a lossless half-space, ν = 1/3: K/K0 = k(a0) + i a0 c(a0), a0 = k_s a,
    K0 = 2aE*. Four-digit values attributed to Luco & Westmann 1971 (see docs/validation.md):
    (k, c) = (0.9689, 0.7931) at a0 = 0.5 and (0.8826, 0.8239) at a0 = 1, four digits.
    At a0 = 0.5 we agree to their rounding (c = 0.793045: −5.5e-5, a five-digit 0.79305 rounded
    again). At a0 = 1 we are 1.2e-4 (k) and 1.6e-4 (c) below them, beyond rounding; that error is
    in the quoted digits, not here: tests/dynamic/test_rigid_disk_isotropic.py solves the disk by an
    independent Fredholm integral equation and agrees with this Galerkin to 1e-11 (converged),
    giving (0.882477, 0.823743). The 1e-6 isotropic check lives there."""
    m = Material.isotropic(E=1.0, nu=1 / 3)
    a0 = np.array([0.5, 1.0])
    d = dcsf(m, a0, model="exact", loss=0.0, wavenumber="shear")
    k, c = d.real, d.imag / a0
    assert k[0] == pytest.approx(0.9689, abs=5e-5) and c[0] == pytest.approx(0.7931, abs=6e-5)
    assert k[1] == pytest.approx(0.8826, abs=2e-4) and c[1] == pytest.approx(0.8239, abs=2e-4)


def test_exact_static_limit():
    for A in (0.5, 2.0):
        v = dcsf(_cubic(A), [0.0, 1e-4, 1e-3], model="exact", loss=Q)
        assert v[0] == pytest.approx(1 + 1j * Q, abs=1e-14)
        d1, d2 = abs(v[1] - (1 + 1j * Q)), abs(v[2] - (1 + 1j * Q))
        assert d2 < 1e-2 and 7 < d2 / d1 < 13


@pytest.mark.parametrize(
    ("A", "nu", "loss"), [(4.0, 0.45, 0.0), (4.0, 0.45, Q), (10.0, 0.25, Q), (0.25, 0.0, Q)]
)
def test_basis_of_the_curves_against_twice_the_terms_and_harmonics(A, nu, loss):
    # The DCSF's exact model takes one radial term fewer than galerkin_size at rtol 1e-6
    # (model_size): against twice galerkin_size's terms and harmonics on the same table, k_l a up
    # to 2, at the solids where one term fewer left the most (A = 4, nu = 0.45: 3.7e-9
    # measured), still far inside rtol; and the curve is made with that basis.
    m = _cubic(A, nu)
    table = prepare(m, loss)
    ksa = np.linspace(0.05, 2.0, 12) * shear_wavenumber_ratio(m)
    size = model_size(float(ksa.max()))
    assert size.n_radial == galerkin_size(float(ksa.max())).n_radial - 1
    got = exact_n(table, ksa, size)
    fine = exact_n(table, ksa, galerkin_size(float(ksa.max())).doubled())
    assert np.max(np.abs(got / fine - 1)) < 1e-8
    curve = dcsf(m, ksa / shear_wavenumber_ratio(m), loss=loss, prepared=table)
    np.testing.assert_allclose(curve, table.n_static / got, rtol=1e-13)


@pytest.mark.parametrize(
    ("face", "A", "nu", "loss", "ksa_top", "stated"),
    [
        (None, 10.0, 0.416, 0.0, 5 / 3, 6.8e-6),
        (None, 10.0, 0.416, Q, 5 / 3, 6.8e-6),
        ((1, 1, 0), None, None, 0.0, 10 / 3, 1.9e-6),
    ],
)
def test_rtol_1e4_basis_against_twice_the_terms_and_harmonics(face, A, nu, loss, ksa_top, stated):
    # galerkin_size at rtol >= 1e-4 (two radial terms fewer) against twice the default's terms and
    # harmonics on the same table, at the worst places measured on k_l a <= 2, A = 0.2-10,
    # nu = -0.3-0.45, Cu(001), (110), (111), (123): the largest k_s a of a basis size (0.6 k_s a an
    # integer), at A = 10, nu = 0.416 (three terms, k_l a = 2) and on Cu(110). Within rtol, and
    # within twice the figures galerkin_size's docstring states (its measured worst cases: a
    # factor 2, not 5 %, so that a change of the table or quadrature well inside rtol does not
    # fail here, while a docstring off by more than that does).
    m = Material.crystal("Cu").rotated(face) if face else _cubic(A, nu)
    assert ksa_top <= 2.0 * shear_wavenumber_ratio(m)
    ksa = np.linspace(0.05, 1.0, 8) * ksa_top
    size = galerkin_size(ksa_top, 1e-4)
    assert size.n_radial == galerkin_size(ksa_top).n_radial - 2
    table = prepare(m, loss, 1e-4)
    fine = exact_n(table, ksa, galerkin_size(ksa_top).doubled())
    err = np.max(np.abs(exact_n(table, ksa, size) / fine - 1))
    assert err < min(1e-4, 2.0 * stated)


def test_default_basis_on_cu110_is_set_by_the_harmonics():
    # Cu(110), in no other test: the default basis (rtol 1e-6) against twice its terms and
    # harmonics, k_l a up to 2, is 2.6e-7 off (galerkin_size's docstring), and twice the radial
    # terms alone do not help: the harmonics set it.
    m = Material.crystal("Cu").rotated((1, 1, 0))
    ksa = np.linspace(0.05, 2.0, 8) * shear_wavenumber_ratio(m)
    size = galerkin_size(float(ksa.max()))
    table = prepare(m, 0.0)
    fine = exact_n(table, ksa, size.doubled())
    err = np.max(np.abs(exact_n(table, ksa, size) / fine - 1))
    more_terms = exact_n(table, ksa, GalerkinSize(2 * size.n_radial, size.n_harmonics))
    assert err < 2.0 * 2.6e-7  # twice the docstring's figure (as above)
    assert np.max(np.abs(more_terms / fine - 1)) > 0.5 * err


@pytest.mark.parametrize(("A", "nu"), [(0.25, 0.25), (1.0, 0.25), (4.0, 0.3)])
def test_convergence_in_terms_and_resolution(A, nu):
    m = _cubic(A, nu)
    kl = np.linspace(0.0, 2.0, 9)
    ksa = kl * math.sqrt(m.C[2, 2] / m.C[3, 3])
    size = galerkin_size(float(ksa.max()))
    res = resolution_for(1e-6)
    base = kernel_table(m, Q, res)
    fine = kernel_table(m, Q, res.doubled())
    a = base.n_static / exact_n(base, ksa, size)
    b = fine.n_static / exact_n(fine, ksa, size.doubled())
    assert np.max(np.abs(a / b - 1)) < 1e-6


def test_exact_continuity_through_isotropy_and_isotropic_harmonics_vanish():
    kl = np.array([0.6, 1.5])
    iso = dcsf(_cubic(1.0), kl, model="exact", loss=Q)
    for eps in (1e-7, -1e-7):
        np.testing.assert_allclose(
            dcsf(_cubic(1.0 + eps), kl, model="exact", loss=Q), iso, rtol=1e-5
        )
    # isotropic: the angular harmonics decouple, one harmonic is as good as many
    table = kernel_table(_cubic(1.0), Q)
    ksa = kl * math.sqrt(_cubic(1.0).C[0, 0] / _cubic(1.0).C[3, 3])
    np.testing.assert_allclose(
        exact_n(table, ksa, GalerkinSize(10, 0)),
        exact_n(table, ksa, GalerkinSize(10, 3)),
        rtol=1e-9,
    )


def test_lossless_limit_of_every_model_including_exact():
    m = _cubic(0.5)
    kl = np.array([0.8, 1.7])
    # R0's negative damping at k_l a = 1.7 is not this test's matter (test_negative_damping_warning)
    d0 = dcsf_models(m, kl, ALL_MODELS, loss=0.0, warn_negative=False)
    dq = dcsf_models(m, kl, ALL_MODELS, loss=1e-5, warn_negative=False)
    for name in ALL_MODELS:
        assert np.all(np.isfinite(d0[name])), name
        np.testing.assert_allclose(dq[name], d0[name], rtol=3e-4, err_msg=name)
    # lossless: no material damping, DCSF(0) = 1 exactly
    assert dcsf(m, 0.0, model="exact", loss=0.0) == 1.0


def test_contact_pressure_static_shape_force_balance_and_symmetry():
    m = _cubic(0.5)
    r = np.array([0.0, 0.5, 0.9])
    p0 = contact_pressure(m, 0.0, r, loss=Q)
    np.testing.assert_allclose(p0, 0.5 / np.sqrt(1 - r * r), rtol=1e-12)
    # mean pressure = 1: ∫ p dA/(π a²) with r = sin t and the trapezoidal rule in φ
    t, w = np.polynomial.legendre.leggauss(40)
    t = 0.25 * np.pi * (t + 1)
    w = 0.25 * np.pi * w
    phi = np.linspace(0, 2 * np.pi, 16, endpoint=False)
    p = contact_pressure(m, 1.4, np.sin(t)[:, None], phi[None, :], loss=Q)
    # p ~ 1/√(1 − r²) = 1/cos t: r dr = sin t cos t dt cancels it
    mean = np.sum(w[:, None] * np.sin(t)[:, None] * np.cos(t)[:, None] * p) * (2 * np.pi / 16)
    assert mean / np.pi == pytest.approx(1.0, abs=1e-10)
    # cubic symmetry of the pressure
    q = contact_pressure(m, 1.4, 0.6, np.array([0.2, 0.2 + np.pi / 2, -0.2]), loss=Q)
    np.testing.assert_allclose(q, q[0], rtol=1e-10)
    # and it is not axisymmetric
    p0, p4 = (contact_pressure(m, 1.4, 0.8, phi, loss=Q) for phi in (0.0, 0.4))
    assert abs(p0 / p4 - 1) > 1e-5


def test_exact_model_errors():
    with pytest.raises(ValueError, match="rbar"):
        contact_pressure(_cubic(0.5), 1.0, 1.0)
    with pytest.raises(ValueError, match="one ka"):
        contact_pressure(_cubic(0.5), [1.0, 2.0], 0.5)


@pytest.mark.parametrize("face", [(1, 1, 1), (1, 2, 3)])
def test_default_basis_reaches_the_coupled_harmonics_of_low_symmetry_faces(face):
    # A (111) face is six-fold: with step 2 it couples the harmonics n = ±6, which a basis with
    # |n| <= 4 missed (3e-4 off on Cu(111), found by review). The default basis against twice
    # the terms and harmonics, k_l a up to 2.
    m = Material.crystal("Cu").rotated(face)
    table = prepare(m, 0.0)
    ksa = np.linspace(0.1, 2.0, 8) * shear_wavenumber_ratio(m)
    size = galerkin_size(float(ksa.max()))
    default = exact_n(table, ksa, size)
    fine = exact_n(table, ksa, size.doubled())
    assert np.max(np.abs(default / fine - 1)) < 1e-7
    np.testing.assert_allclose(dcsf(m, ksa / shear_wavenumber_ratio(m)), table.n_static / default)
