"""Tests of contactres.analysis._inversion: contact stiffness -> reduced and sample modulus."""

import math

import numpy as np
import pytest

from contactres.analysis._inversion import (
    FLAG_DESCRIPTIONS,
    ModulusFlag,
    dcsf_values,
    longitudinal_velocity,
    modulus_from_contact_stiffness,
    modulus_of,
)
from contactres.dynamic import dcsf, prepare
from contactres.materials import Material
from contactres.normal import effective_modulus, indentation_modulus
from contactres.normal import hertz as api_hertz


def hertz(E_star, radius, force):
    """The forward Hertz contact as the inversion reads it, without the API's a/R check: the
    CR-AFM contacts here reach a/R > 0.5 on the soft samples, where the API gives NaN (issue
    30); the inversion flags a contact wider than the tip itself."""
    return api_hertz(E_star, radius, force, check_validity=False)


R, P = 50e-9, 1e-6  # m, N
SI = Material.crystal("Si")
SI001 = SI.rotated((0, 0, 1))


def series(a, b):
    return 1.0 / (1.0 / a + 1.0 / b)


def test_hertz_inversion_of_the_forward_hertz_contact():
    """k* = 2aE* from contactres.normal.hertz, inverted to 1e-12 (also a and p0)."""
    E = np.array([[1e9, 10e9], [80e9, 300e9]])
    c = hertz(E, R, P)
    res = modulus_from_contact_stiffness(c.stiffness, tip_radius=R, load=P)
    np.testing.assert_allclose(res.E_star, E, rtol=1e-12)
    np.testing.assert_allclose(res.M_sample, E, rtol=1e-12)  # rigid tip
    np.testing.assert_allclose(res.contact_radius, c.contact_radius, rtol=1e-12)
    np.testing.assert_allclose(res.peak_pressure, c.peak_pressure, rtol=1e-12)
    assert res.method == "hertz" and res.exponent == 1.5 and res.tip_modulus == math.inf
    assert np.all(res.flags == 0) and np.all(res.dcsf == 1) and np.all(np.isnan(res.k_a))
    # array tip radius and load broadcast against k*
    res2 = modulus_from_contact_stiffness(
        hertz(70e9, np.array([20e-9, 50e-9]), np.array([[1e-7], [1e-6]])).stiffness,
        tip_radius=np.array([20e-9, 50e-9]),
        load=np.array([[1e-7], [1e-6]]),
    )
    assert res2.E_star.shape == (2, 2)
    np.testing.assert_allclose(res2.E_star, 70e9, rtol=1e-12)


def test_reference_method_equals_hertz_for_a_hertzian_reference():
    """Reference (m = 3/2) with k*_ref from the forward Hertz contact = the Hertz method."""
    M_tip, M_ref = 169e9, 72e9
    E_s = series(M_tip, np.array([5e9, 50e9, 130e9]))
    k_s = hertz(E_s, R, P).stiffness
    k_ref = hertz(series(M_tip, M_ref), R, P).stiffness
    ref = modulus_from_contact_stiffness(
        k_s, reference_k_star=k_ref, reference_modulus=M_ref, tip_modulus=M_tip
    )
    hz = modulus_from_contact_stiffness(k_s, tip_radius=R, load=P, tip_modulus=M_tip)
    np.testing.assert_allclose(ref.E_star, hz.E_star, rtol=1e-12)
    np.testing.assert_allclose(ref.E_star, E_s, rtol=1e-12)
    np.testing.assert_allclose(ref.M_sample, [5e9, 50e9, 130e9], rtol=1e-11)
    np.testing.assert_allclose(ref.contact_radius, hz.contact_radius, rtol=1e-12)
    assert ref.method == "reference (given m = 1.5)"


def test_two_references_fit_flat_punch_exponent():
    """Flat punch k* = 2 a0 E* (a0 fixed): the fitted m is 1 and E* of the sample is exact."""
    a0, M_tip = 20e-9, 160e9
    Ms = np.array([3e9, 40e9])
    M1, M2 = 10e9, 120e9
    k = 2 * a0 * series(M_tip, Ms)
    res = modulus_from_contact_stiffness(
        k,
        reference_k_star=2 * a0 * series(M_tip, M1),
        reference_modulus=M1,
        reference2_k_star=2 * a0 * series(M_tip, M2),
        reference2_modulus=M2,
        tip_modulus=M_tip,
    )
    assert res.exponent == pytest.approx(1.0, abs=1e-13)
    np.testing.assert_allclose(res.M_sample, Ms, rtol=1e-12)
    np.testing.assert_allclose(res.contact_radius, a0, rtol=1e-12)
    assert res.method.startswith("reference (fitted m = 1")
    # given m = 1 instead of fitted: the same
    res1 = modulus_from_contact_stiffness(
        k, reference_k_star=2 * a0 * series(M_tip, M1), reference_modulus=M1, exponent=1.0,
        tip_modulus=M_tip,
    )  # fmt: skip
    np.testing.assert_allclose(res1.M_sample, Ms, rtol=1e-12)


def test_tip_compliance_series_law_and_tip_limit_flag():
    M_tip = 130e9
    Ms = np.array([10e9, 100e9, 1000e9])
    E = series(M_tip, Ms)
    k = hertz(E, R, P).stiffness
    res = modulus_from_contact_stiffness(k, tip_radius=R, load=P, tip_modulus=M_tip)
    np.testing.assert_allclose(1 / res.E_star, 1 / M_tip + 1 / res.M_sample, rtol=1e-12)
    np.testing.assert_allclose(res.M_sample, Ms, rtol=1e-10)
    # the same k* read with a softer tip than E*: sample "stiffer than the tip allows"
    bad = modulus_from_contact_stiffness(
        k, tip_radius=R, load=P, tip_modulus=110e9
    )  # E* = 118 GPa in pixel 2
    assert list(bad.flags) == [0, 0, int(ModulusFlag.TIP_LIMIT)]
    assert np.isnan(bad.M_sample[2]) and np.all(np.isfinite(bad.M_sample[:2]))
    assert "tip modulus" in FLAG_DESCRIPTIONS[ModulusFlag.TIP_LIMIT]


def test_moduli_of_materials():
    """Si(100) from indentation_modulus; an isotropic material gives E/(1 - ν²)."""
    m100 = modulus_of((SI, (1, 0, 0)))
    assert m100 == pytest.approx(float(np.real(indentation_modulus(SI.rotated((1, 0, 0))))), 1e-15)
    assert modulus_of(SI001) == pytest.approx(m100, rel=1e-12)  # (100) and (001) are equivalent
    assert modulus_of((SI, (1, 1, 1))) > m100  # Si is stiffer along <111>
    E, nu = 70e9, 0.17
    iso = modulus_of(Material.isotropic(E, nu))
    assert iso == pytest.approx(E / (1 - nu**2), rel=1e-10)
    assert iso == pytest.approx(effective_modulus(E, nu, np.inf, 0.0), rel=1e-10)
    # tip=(material, face) is the same as tip_modulus=M
    k = hertz(60e9, R, P).stiffness
    a = modulus_from_contact_stiffness(k, tip_radius=R, load=P, tip=(SI, (1, 0, 0)))
    b = modulus_from_contact_stiffness(k, tip_radius=R, load=P, tip_modulus=m100)
    assert a.tip_modulus == m100 and a.M_sample == pytest.approx(b.M_sample, rel=1e-15)
    with pytest.raises(ValueError, match="tip must be a number"):
        modulus_of("Si", "tip")


def test_hardness_flag():
    E = np.array([1e9, 100e9])
    c = hertz(E, R, P)
    H = float(np.mean(c.peak_pressure))  # between the two peak pressures
    res = modulus_from_contact_stiffness(c.stiffness, tip_radius=R, load=P, hardness=H)
    assert list(res.flags) == [0, int(ModulusFlag.NOT_ELASTIC)]
    assert res.peak_pressure[1] > H > res.peak_pressure[0]
    assert "not elastic" in FLAG_DESCRIPTIONS[ModulusFlag.NOT_ELASTIC]
    with pytest.raises(ValueError, match="hardness needs load"):
        modulus_from_contact_stiffness(
            c.stiffness, reference_k_star=1e3, reference_modulus=1e11, hardness=H
        )


def test_dynamic_correction_vanishes_as_ka_goes_to_zero():
    """50 nm Si[001] tip on Si(001), 1 µN, 1 MHz: k_l a ~ 6e-6, correction ~1e-11."""
    M = modulus_of(SI001)
    k = hertz(M / 2, R, P).stiffness
    res = modulus_from_contact_stiffness(
        k, tip_radius=R, load=P, tip=SI001, sample=SI001, frequency=1e6, dynamic=True
    )
    assert res.k_a == pytest.approx(5.73e-6, rel=1e-3)
    assert abs(res.dcsf - 1) == pytest.approx(7.03e-6, rel=1e-3)  # radiation: 1.228 k_l a
    assert res.k_static / k - 1 == pytest.approx(0.298 * res.k_a**2, rel=1e-2)
    assert res.M_sample == pytest.approx(M, rel=1e-10)
    assert res.method == "hertz + dynamic"
    # static values with the wave number reported
    st = modulus_from_contact_stiffness(k, tip_radius=R, load=P, sample=SI001, frequency=1e6)
    assert st.dcsf == 1 and st.k_a == pytest.approx(res.k_a, rel=1e-10)


def test_dynamic_correction_size_and_fixed_point():
    """At k_l a ~ 0.01-0.2 (µm contacts, tens of MHz): K_static/k* - 1 = 1/Re DCSF - 1, and
    the iteration has converged: k_l a = k_l K_static/(2E*(K_static)) with DCSF(k_l a)."""
    table = prepare(SI001, 0.0)
    E = modulus_of(SI001)  # rigid tip
    Rb, Pb = 20e-6, np.array([1e-3, 1e-2, 1e-1])
    k = hertz(E, Rb, Pb).stiffness
    f = 100e6
    res = modulus_from_contact_stiffness(
        k, tip_radius=Rb, load=Pb, sample=SI001, frequency=f, dynamic=True, prepared=table
    )
    kl = 2 * np.pi * f / longitudinal_velocity(SI001)
    D = np.asarray(dcsf(SI001, res.k_a, model="exact", loss=0.0, prepared=table))
    np.testing.assert_allclose(res.dcsf, D, rtol=1e-9)
    np.testing.assert_allclose(res.k_static, k / D.real, rtol=1e-9)
    np.testing.assert_allclose(res.k_a, kl * res.k_static / (2 * res.E_star), rtol=1e-12)
    assert np.all(res.k_a > 0.03) and np.all(res.k_a < 0.2)
    np.testing.assert_allclose(res.k_static / k - 1, 1 / D.real - 1, rtol=1e-9)
    assert np.all(res.E_star > E)  # the dynamic contact is softer: the static modulus is higher
    # the grid + spline path agrees with the direct one
    kk = np.linspace(k[0], k[-1], 60)
    Pk = np.interp(kk, k, Pb)
    kw = dict(tip_radius=Rb, load=Pk, sample=SI001, frequency=f, dynamic=True, prepared=table)
    grid = modulus_from_contact_stiffness(kk, dcsf_grid=16, **kw)
    direct = modulus_from_contact_stiffness(kk, dcsf_grid=100, **kw)
    np.testing.assert_allclose(grid.k_static, direct.k_static, rtol=1e-7)


def test_si001_thresholds_of_the_dynamic_correction():
    """|DCSF - 1| = 1e-3 at k_l a = 8.14e-4; |1/Re DCSF - 1| = 1e-3 at k_l a = 0.0579."""
    d = dcsf_values(SI001, np.array([8.1447e-4, 0.05790]))
    assert abs(d[0] - 1) == pytest.approx(1e-3, rel=1e-4)
    assert 1 / d[1].real - 1 == pytest.approx(1e-3, rel=1e-3)


def test_invalid_inputs():
    with pytest.raises(ValueError, match=r"k_star \(contact stiffness k\*\) must be finite and > 0"
                       r" \(N/m\), got -1"):  # fmt: skip
        modulus_from_contact_stiffness(-1.0, tip_radius=R, load=P)
    with pytest.raises(ValueError, match=r"tip_radius must be finite and > 0 \(m\), got 0"):
        modulus_from_contact_stiffness(1e3, tip_radius=0.0, load=P)
    with pytest.raises(ValueError, match="give tip_radius and load"):
        modulus_from_contact_stiffness(1e3, tip_radius=R)
    with pytest.raises(ValueError, match="dynamic=True needs frequency"):
        modulus_from_contact_stiffness(1e3, tip_radius=R, load=P, dynamic=True)
    with pytest.raises(ValueError, match="not both"):
        modulus_from_contact_stiffness(1e3, tip_radius=R, load=P, tip_modulus=1e11, tip=SI001)
    with pytest.raises(ValueError, match="different contact stiffness"):
        modulus_from_contact_stiffness(
            1e3, reference_k_star=1e3, reference_modulus=1e11, reference2_k_star=1e3,
            reference2_modulus=2e11,
        )  # fmt: skip
    with pytest.raises(ValueError, match="do not broadcast"):
        modulus_from_contact_stiffness(np.ones(3) * 1e3, tip_radius=R, load=np.ones(2) * P)
    with pytest.raises(ValueError, match="density"):
        modulus_from_contact_stiffness(
            1e3, tip_radius=R, load=P, sample=Material.isotropic(1e11, 0.2), frequency=1e6
        )


def test_hardness_of_some_pixels_only():
    E = np.array([1e9, 100e9, 100e9])
    c = hertz(E, R, P)
    H = np.array([np.nan, 1.0, np.nan])  # only pixel 1 has a hardness, far below its p0
    res = modulus_from_contact_stiffness(c.stiffness, tip_radius=R, load=P, hardness=H)
    assert list(res.flags) == [0, int(ModulusFlag.NOT_ELASTIC), 0]
