"""Tests of contactres.resonators._rum: the lumped and rod models of the RUM oscillator."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from contactres.resonators._rum import RUMOscillator

F0 = 1.0e6  # Hz
MASS = 2.0e-4  # kg
ROD = RUMOscillator.rod(F0, MASS)
K_EFF = ROD.effective_stiffness
LUMPED = RUMOscillator.lumped(F0, K_EFF)


def test_rod_calibration_from_geometry():
    """A rod of given L, A, E, ρ: f0 = n c/(2L), K_eff = 2π² m f0² = (EA/L)(nπ)²/2."""
    L, A, E, rho = 4e-3, 1e-6, 170e9, 5700.0
    for n in (1, 2, 3):
        rod = RUMOscillator.rod_from_geometry(L, A, E, rho, mode=n)
        c = math.sqrt(E / rho)
        assert rod.free_frequency == pytest.approx(n * c / (2 * L), rel=1e-14)
        assert rod.axial_stiffness == pytest.approx(E * A / L, rel=1e-14)
        assert rod.effective_stiffness == pytest.approx(E * A / L * (n * math.pi) ** 2 / 2, 1e-14)
        assert rod.effective_mass == pytest.approx(rho * A * L / 2, rel=1e-14)


def test_rod_characteristic_equation_independently():
    """f from brentq on the untransformed equation k* = (EA/L) kL tan kL, kL in (π, 3π/2)."""
    EAL = ROD.axial_stiffness
    for s in (1e-3, 0.1, 1.0, 10.0, 300.0):
        k = s * K_EFF
        x = brentq(
            lambda x, k=k: EAL * x * math.tan(x) - k,
            math.pi,
            1.5 * math.pi - 1e-12,
            xtol=1e-15,
            rtol=1e-15,
        )
        assert ROD.frequency(k) == pytest.approx(F0 * x / math.pi, rel=1e-13)


@pytest.mark.parametrize(
    "osc", [LUMPED, ROD, RUMOscillator.rod(F0, MASS, mode=3)], ids=["lumped", "rod1", "rod3"]
)
def test_round_trips(osc):
    """f -> k* -> f and k* -> f -> k* to 1e-10 (k* from 1e-4 K_eff, where the shift f - f0 still
    carries its digits, to 1e3 K_eff)."""
    k = K_EFF * np.geomspace(1e-4, 1e3, 57)
    f = osc.frequency(k)
    np.testing.assert_allclose(osc.contact_stiffness(f), k, rtol=1e-10)
    f_top = min(osc.clamped_frequency, 3 * F0)
    f = F0 + (f_top - F0) * np.linspace(0, 1 - 1e-6, 41)
    np.testing.assert_allclose(osc.frequency(osc.contact_stiffness(f)), f, rtol=1e-13)
    assert osc.frequency(0.0) == F0 and osc.contact_stiffness(F0) == 0.0


def test_vectorised_shapes():
    k = K_EFF * np.array([[0.1, 1.0], [2.0, 5.0]])
    f = ROD.frequency(k)
    assert f.shape == (2, 2)
    for i in range(2):
        for j in range(2):
            assert f[i, j] == ROD.frequency(k[i, j])
    assert isinstance(ROD.frequency(1.0), float)


def test_small_stiffness_limit_is_the_lumped_model():
    """Rod f/f0 = 1 + s/2 - s²/4, lumped 1 + s/2 - s²/8 (s = k*/K_eff, K_eff = 2π² m f0²):
    the difference is -s²/8 (1 + O(s))."""
    for s in (1e-2, 1e-3, 1e-4):
        diff = (ROD.frequency(s * K_EFF) - LUMPED.frequency(s * K_EFF)) / F0
        assert diff == pytest.approx(-(s**2) / 8, rel=5 * s)
        # first order: both shifts s/2
        assert (ROD.frequency(s * K_EFF) / F0 - 1) == pytest.approx(s / 2, rel=s)


def test_stiff_limit_is_the_clamped_rod():
    """k* -> ∞: kL -> (n + 1/2)π, f -> (n + 1/2) f0/n; with β = k*L/(EA) large,
    f = f_c (1 - 1/β + O(β⁻²))."""
    for n in (1, 2):
        rod = RUMOscillator.rod(F0, MASS, mode=n)
        assert rod.clamped_frequency == pytest.approx((n + 0.5) / n * F0, rel=1e-15)
        for beta in (1e5, 1e7):
            f = rod.frequency(beta * rod.axial_stiffness)
            assert f / rod.clamped_frequency - 1 == pytest.approx(-1 / beta, rel=1e-4)
        assert rod.frequency(1e300) == pytest.approx(rod.clamped_frequency, rel=1e-15)
    assert LUMPED.clamped_frequency == math.inf


def test_invalid_input_names_parameter_unit_and_value():
    with pytest.raises(
        ValueError,
        match=r"f must be >= the free resonance f0 = 1000000 Hz.*"
        r"got 999999 Hz",
    ):
        LUMPED.contact_stiffness(999_999.0)
    with pytest.raises(ValueError, match=r"clamped limit 1500000 Hz.*got 1600000 Hz at index 1"):
        ROD.contact_stiffness([1.1e6, 1.6e6])
    with pytest.raises(ValueError, match=r"frequency f must be finite and > 0 \(Hz\), got -1"):
        ROD.contact_stiffness(-1.0)
    with pytest.raises(ValueError, match=r"contact stiffness k\* must be finite and >= 0 \(N/m\)"):
        ROD.frequency(-5.0)
    with pytest.raises(ValueError, match=r"f0 must be finite and > 0 \(Hz\), got 0"):
        RUMOscillator.lumped(0.0, 1e3)
    with pytest.raises(ValueError, match=r"mass m must be finite and > 0 \(kg\)"):
        RUMOscillator.rod(F0, -1.0)
    with pytest.raises(ValueError, match="model must be one of lumped, rod"):
        RUMOscillator(F0, 1e3, model="beam")
    with pytest.raises(ValueError, match="mode must be an integer >= 1"):
        RUMOscillator.rod(F0, MASS, mode=0)
