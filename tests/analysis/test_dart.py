"""DART reconstruction (contactres.dart_reconstruct): against the damped oscillator written here.

The data are made from the oscillator's amplitude and phase, A(ω) = A_d ω0²/√((ω0² − ω²)² +
(ω ω0/Q)²), tan φ = (ω ω0/Q)/(ω0² − ω²), computed in this file; the noise test compares the
scatter of many noisy draws with the first-order lines stated in the module's docstring.
"""

from __future__ import annotations

import numpy as np
import pytest

import contactres as cr
from contactres.analysis import dart_flag_names, dart_reconstruction


def oscillator(f, f0, q, a_drive):
    """Amplitude and lag (rad, in (0, π)) of the damped harmonic oscillator at f (Hz)."""
    w, w0 = 2 * np.pi * np.asarray(f, float), 2 * np.pi * np.asarray(f0, float)
    amp = a_drive * w0**2 / np.sqrt((w0**2 - w**2) ** 2 + (w * w0 / q) ** 2)
    return amp, np.arctan2(w * w0 / q, w0**2 - w**2)


def test_exact_oscillator_data_give_f0_q_and_drive_to_1e_10():
    rng = np.random.default_rng(3)
    f0 = rng.uniform(50e3, 2e6, 500)
    q = rng.uniform(5.0, 500.0, 500)
    a_d = rng.uniform(1e-12, 1e-9, 500)
    # Drives within a few half-widths either side, not necessarily symmetric.
    f1 = f0 * (1 - rng.uniform(0.1, 3.0, 500) / (2 * q))
    f2 = f0 * (1 + rng.uniform(0.1, 3.0, 500) / (2 * q))
    a1, p1 = oscillator(f1, f0, q, a_d)
    a2, p2 = oscillator(f2, f0, q, a_d)
    g0, gq, ga = cr.dart_reconstruct(f1, f2, a1, a2, p1, p2)
    np.testing.assert_allclose(g0, f0, rtol=1e-10, atol=0)
    np.testing.assert_allclose(gq, q, rtol=1e-10, atol=0)
    np.testing.assert_allclose(ga, a_d, rtol=1e-10, atol=0)
    assert not dart_reconstruction(f1, f2, a1, a2, p1, p2).flags.any()


def test_a_common_phase_offset_and_the_drive_order_do_not_matter():
    f = np.array([297e3, 303.5e3])
    a, p = oscillator(f, 300e3, 60.0, 2e-10)
    r = dart_reconstruction(f[1], f[0], a[1], a[0], p[1] + 0.7, p[0] + 0.7)  # f1 > f2
    np.testing.assert_allclose([r.f0, r.Q, r.A_drive], [300e3, 60.0, 2e-10], rtol=1e-10)
    np.testing.assert_allclose(r.phase_offset, 0.7, rtol=1e-10)


def test_broadcasting_a_map_against_scalar_frequencies():
    f0 = np.linspace(290e3, 310e3, 12).reshape(3, 4)
    a1, p1 = oscillator(295e3, f0, 40.0, 1.0)
    a2, p2 = oscillator(305e3, f0, 40.0, 1.0)
    g0, gq, _ = cr.dart_reconstruct(295e3, 305e3, a1, a2, p1, p2)
    assert g0.shape == (3, 4)
    np.testing.assert_allclose(g0, f0, rtol=1e-10)
    np.testing.assert_allclose(gq, 40.0, rtol=1e-10)


def test_scatter_under_noise_follows_the_first_order_propagation():
    f0, q = 300e3, 50.0
    # Symmetric drives (f0² = f1 f2) with Δ = π/2: cot φ1 = 1, i.e. f0²/f1 − f1 = f0/Q.
    f1 = 0.5 * (-f0 / q + np.sqrt(f0**2 / q**2 + 4 * f0**2))
    f2 = f0**2 / f1
    a1, p1 = oscillator(f1, f0, q, 1.0)
    a2, p2 = oscillator(f2, f0, q, 1.0)
    assert p2 - p1 == pytest.approx(np.pi / 2, rel=1e-12)
    n, sa, sp = 40_000, 1e-4, 1e-4
    rng = np.random.default_rng(7)
    amp = lambda a: a * (1 + sa * rng.standard_normal(n))  # noqa: E731 - a relative noise
    g0, gq, _ = cr.dart_reconstruct(f1, f2, amp(a1), amp(a2), p1, p2)
    expected_f0 = np.sqrt(2) * sa * f0 / (q * (f1 + f2))  # sin Δ = 1
    assert np.std(g0 / f0) == pytest.approx(expected_f0, rel=0.03)
    assert np.std(gq / q) < 0.05 * np.sqrt(2) * sp  # amplitude noise: Q unmoved to first order
    ph = lambda p: p + sp * rng.standard_normal(n)  # noqa: E731
    g0, gq, _ = cr.dart_reconstruct(f1, f2, a1, a2, ph(p1), ph(p2))
    assert np.std(gq / q) == pytest.approx(np.sqrt(2) * sp, rel=0.03)
    assert np.std(g0 / f0) < 0.05 * expected_f0  # phase noise: f0 unmoved to first order


def test_drives_on_one_side_are_solved_and_flagged():
    f = np.array([310e3, 316e3])  # both above f0
    a, p = oscillator(f, 300e3, 80.0, 1.0)
    r = dart_reconstruction(f[0], f[1], a[0], a[1], p[0], p[1])
    assert dart_flag_names(r.flags) == ["not_straddling"]
    np.testing.assert_allclose([r.f0, r.Q], [300e3, 80.0], rtol=1e-9)


@pytest.mark.parametrize("delta", [0.0, 1e-5, np.pi, -np.pi])
def test_degenerate_phase_difference_gives_nan_and_its_flag(delta):
    r = dart_reconstruction(295e3, 305e3, 1.0, 1.0, 1.0, 1.0 + delta)
    assert dart_flag_names(r.flags) == ["degenerate_phase"]
    assert np.isnan(r.f0) and np.isnan(r.Q) and np.isnan(r.A_drive)


def test_lag_falling_with_frequency_is_not_physical():
    # Above the resonance with f2 > f1 the lag must grow: swapping the phases reverses it.
    f = np.array([295e3, 305e3])
    a, p = oscillator(f, 300e3, 30.0, 1.0)
    r = dart_reconstruction(f[0], f[1], a[0], a[1], p[1], p[0])
    assert dart_flag_names(r.flags) == ["not_physical"]
    assert np.isnan(r.Q)


@pytest.mark.parametrize(
    "args",
    [
        (295e3, 305e3, np.nan, 1.0, 1.0, 2.0),
        (295e3, 305e3, 0.0, 1.0, 1.0, 2.0),
        (295e3, 295e3, 1.0, 1.0, 1.0, 2.0),
        (295e3, 305e3, 1.0, 1.0, np.nan, 2.0),
    ],
)
def test_missing_or_impossible_inputs_are_not_measured(args):
    r = dart_reconstruction(*args)
    assert dart_flag_names(r.flags) == ["not_measured"]
    assert np.isnan(r.f0)
