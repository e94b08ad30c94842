"""Tests of contactres.normal._isotropic: Hertz, JKR, DMT, effective moduli, Tabor parameter."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import contactres as cr
from contactres.normal import (
    jkr_contact_radius,
    jkr_from_depth,
    jkr_pull_off_force,
    tabor_parameter,
    which_adhesion_model,
)

E, NU = 70e9, 0.17
ESTAR = E / (2 * (1 - NU**2))
R = 1.1e-3


def test_hertz_hand_numbers():
    # a³ = 3FR/(4E*): E* = 1e9 Pa, R = 1 m, F = 4/3 N -> a = 1 mm, δ = 1 µm, k = 2E*a = 2e6 N/m.
    c = cr.hertz(1e9, 1.0, 4.0 / 3.0)
    assert c.contact_radius == pytest.approx(1e-3, rel=1e-14)
    assert c.depth == pytest.approx(1e-6, rel=1e-14)
    assert c.stiffness == pytest.approx(2e6, rel=1e-13)
    assert c.peak_pressure == pytest.approx(1.5 * c.mean_pressure, rel=1e-14)
    assert c.model == "hertz"


def test_hertz_stiffness_is_slope_of_force_versus_depth():
    F = np.array([1e-3, 1e-2])
    h = 1e-6
    lo, hi = cr.hertz(ESTAR, R, F * (1 - h)), cr.hertz(ESTAR, R, F * (1 + h))
    slope = (hi.force - lo.force) / (hi.depth - lo.depth)
    np.testing.assert_allclose(cr.hertz(ESTAR, R, F).stiffness, slope, rtol=1e-9)


def test_jkr_tends_to_hertz_as_gamma_vanishes():
    F = 5e-3
    h = cr.hertz(ESTAR, R, F)
    errs = []
    for gamma in (1e-8, 1e-10, 1e-12):
        j = cr.jkr(ESTAR, R, F, gamma)
        errs.append(j.contact_radius / h.contact_radius - 1)
    # The leading correction is the √(12πγRF) term of Eq. 9: a/a_H - 1 ≈ √(12πγR/F)/3.
    expected = [np.sqrt(12 * np.pi * g * R / F) / 3 for g in (1e-8, 1e-10, 1e-12)]
    np.testing.assert_allclose(errs, expected, rtol=1e-3)
    assert j.depth == pytest.approx(h.depth, rel=1e-3)
    assert j.stiffness == pytest.approx(h.stiffness, rel=1e-4)


def test_jkr_at_pull_off_force():
    gamma = 0.05
    Fc = jkr_pull_off_force(R, gamma)
    assert Fc == pytest.approx(-3 * np.pi * gamma * R, rel=1e-15)
    c = cr.jkr(ESTAR, R, Fc, gamma)
    # At pull-off dF/da = 0: a³ = 9πγR²/(4E*) (Johnson Eq. 5.138 with w = 2γ) and zero stiffness.
    assert c.contact_radius**3 == pytest.approx(9 * np.pi * gamma * R**2 / (4 * ESTAR), rel=1e-10)
    assert abs(c.stiffness) < 1e-6 * cr.jkr(ESTAR, R, 0.0, gamma).stiffness
    with pytest.raises(ValueError, match="pull-off"):
        cr.jkr(ESTAR, R, 1.01 * Fc, gamma)


def test_jkr_zero_load_radius():
    gamma = 0.05
    a = jkr_contact_radius(ESTAR, R, 0.0, gamma)
    assert a**3 == pytest.approx(3 * R / (4 * ESTAR) * 12 * np.pi * gamma * R, rel=1e-13)


@given(st.floats(-0.9, 50.0), st.floats(1e-3, 1.0))
def test_jkr_force_and_depth_round_trip(f_rel, gamma):
    F = f_rel * 3 * np.pi * gamma * R
    c = cr.jkr(ESTAR, R, F, gamma)
    # Energy balance form of JKR: F = 4E*a³/(3R) - √(8πwE*a³), w = 2γ (independent of Eq. 9).
    a = c.contact_radius
    w = 2 * gamma
    assert F == pytest.approx(
        4 * ESTAR * a**3 / (3 * R) - np.sqrt(8 * np.pi * w * ESTAR * a**3),
        abs=1e-9 * 3 * np.pi * gamma * R,
    )
    back = jkr_from_depth(ESTAR, R, c.depth, gamma)
    assert back.contact_radius == pytest.approx(a, rel=1e-9)
    assert back.force == pytest.approx(F, abs=1e-9 * 3 * np.pi * gamma * R)


def test_jkr_stiffness_is_slope_of_force_versus_depth():
    gamma, F = 0.05, 2e-3
    c = cr.jkr(ESTAR, R, F, gamma)
    h = 1e-7 * c.depth
    lo, hi = (
        jkr_from_depth(ESTAR, R, c.depth - h, gamma),
        jkr_from_depth(ESTAR, R, c.depth + h, gamma),
    )
    assert c.stiffness == pytest.approx((hi.force - lo.force) / (2 * h), rel=1e-6)


def test_jkr_from_depth_rejects_detached():
    with pytest.raises(ValueError, match="depth"):
        jkr_from_depth(ESTAR, R, -1.0, 0.05)


def test_jkr_vectorised_over_force():
    F = np.linspace(0, 1e-2, 5)
    c = cr.jkr(ESTAR, R, F, 0.05)
    assert c.contact_radius.shape == (5,)
    assert np.all(np.diff(c.contact_radius) > 0)


def test_dmt():
    gamma = 0.05
    c = cr.dmt(ESTAR, R, -4 * np.pi * gamma * R, gamma)
    assert c.contact_radius == 0.0
    c = cr.dmt(ESTAR, R, 1e-3, gamma)
    h = cr.hertz(ESTAR, R, 1e-3 + 4 * np.pi * gamma * R)
    assert c.contact_radius == pytest.approx(h.contact_radius, rel=1e-14)
    assert c.stiffness == pytest.approx(h.stiffness, rel=1e-14)
    with pytest.raises(ValueError, match="pull-off"):
        cr.dmt(ESTAR, R, -1.0, gamma)


def test_effective_moduli_and_conventions():
    assert cr.effective_modulus(E, NU) == pytest.approx(E / (2 * (1 - NU**2)), rel=1e-15)
    assert cr.effective_modulus(E, NU, np.inf, 0.3) == pytest.approx(E / (1 - NU**2), rel=1e-15)
    G = cr.shear_modulus(E, NU)
    assert G == pytest.approx(E / 2.34, rel=1e-15)
    Gs = cr.effective_shear_modulus(G, NU)
    # Johnson's G*: 1/G*_J = (2 - ν1)/G1 + (2 - ν2)/G2; the paper's is four times it.
    G_johnson = 1 / (2 * (2 - NU) / G)
    assert Gs == pytest.approx(4 * G_johnson, rel=1e-15)
    # Same Mindlin stiffness: κ = 2 G* a = 8 G*_J a.
    a = 1e-6
    assert cr.mindlin_stiffness(a, Gs) == pytest.approx(8 * G_johnson * a, rel=1e-15)


@pytest.mark.parametrize(
    "call",
    [
        lambda: cr.hertz(ESTAR, 0.0, 1.0),
        lambda: cr.hertz(-1.0, R, 1.0),
        lambda: cr.hertz(ESTAR, R, -1.0),
        lambda: cr.effective_modulus(E, 0.5),
        lambda: cr.effective_modulus(E, -1.0),
        lambda: cr.shear_modulus(0.0, 0.2),
        lambda: cr.jkr(ESTAR, R, 1.0, -0.1),
        lambda: cr.effective_shear_modulus(1e9, 0.7),
    ],
)
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()


def test_tabor_parameter_and_model_choice():
    # Tabor parameter by hand: R = 1 µm, w = 0.1 J/m², E* = 1 GPa, z0 = 0.3 nm.
    mu = tabor_parameter(1e9, 1e-6, 0.05)
    assert mu == pytest.approx((1e-6 * 0.01 / (1e18 * 0.027e-27)) ** (1 / 3), rel=1e-12)
    assert which_adhesion_model(1e9, 1e-6, 0.05) == "jkr"  # μ_T ≈ 7.2
    assert which_adhesion_model(200e9, 10e-9, 0.01) == "dmt"
    assert which_adhesion_model(70e9, 1e-6, 0.01) == "maugis"
