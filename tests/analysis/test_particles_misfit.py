"""The particle fit with the noise estimated tells a model that does not fit from noisy data
(issue 28's second review, finding 1): the noise its residuals imply (σ̂) is compared with the
noise of the time series read off its step-to-step differences, independently of the model."""

from importlib.resources import files

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import PARTICLE_FLAGS, fit_particles
from contactres.analysis._particle_input import difference_noise
from contactres.resonators import WATER, Particle, coupled_resonance, particle_shifts

F0 = 5e6
N = np.arange(1, 14, 2)
NOISE = 0.1  # Hz
PS = Particle.sphere(1e-6, 1050.0)
VALUES = ("kappa", "xi", "coverage", "f_coupled", "coverage_kappa", "coverage_xi")


def _example():
    """The bundled example (silica spheres, R = 0.5 µm, 2200 kg/m³, adsorbing in water, free
    to roll; noise 0.1 Hz) as (T, n) arrays."""
    path = files("contactres.data").joinpath("example_particles.csv")
    table = pd.read_csv(str(path))
    df = table.pivot(index="time_s", columns="overtone", values="df_Hz")
    dg = table.pivot(index="time_s", columns="overtone", values="dgamma_Hz")
    return df.columns.to_numpy(int), df.to_numpy(float), dg.to_numpy(float)


def _kappa_for(particle, f_coupled, medium=None):
    """κ whose coupled resonance is f_coupled (bisection in ln κ on coupled_resonance)."""
    lo, hi = np.log(1e-6), np.log(1e9)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        f = np.min(coupled_resonance(particle, np.exp(mid), medium=medium))
        step = (mid, hi) if f < f_coupled else (lo, mid)
        if step == (lo, hi):  # the bracket no longer moves (~55 steps): it never will again
            break
        lo, hi = step
    return float(np.exp(0.5 * (lo + hi)))


def _all_misfit(fit):
    assert all("model-misfit" in f for f in fit.flags)
    for name in VALUES:
        assert np.all(np.isnan(getattr(fit, name))), name
    # σ̂ far above the series' own noise
    assert fit.noise_fit > 3 * fit.noise_series


@pytest.mark.parametrize(
    ("radius", "rocking"),
    [(5e-7, "locked"), (1.5e-7, "free")],  # the wrong rotation; the wrong radius
)
def test_the_wrong_model_of_the_bundled_example_is_a_misfit_and_prints_nothing(radius, rocking):
    n, df, dg = _example()
    particle = Particle.sphere(radius, 2200.0)
    fit = fit_particles(F0, n, df, dg, particle, rocking=rocking, medium=WATER)
    _all_misfit(fit)
    assert "model-misfit" in PARTICLE_FLAGS


def test_the_right_model_of_the_bundled_example_prints_its_values():
    n, df, dg = _example()
    fit = fit_particles(F0, n, df, dg, Particle.sphere(5e-7, 2200.0), medium=WATER)
    assert not any("model-misfit" in f for f in fit.flags)
    assert np.isfinite(fit.kappa).sum() >= 45
    # the example's noise is 0.1 Hz (its docs); the residuals say so
    assert fit.noise_fit == pytest.approx(NOISE, rel=0.15)


def test_in_comb_recovery_with_the_noise_estimated_is_no_misfit_and_stays_calibrated():
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    xi = 0.05 * kappa / (2 * np.pi * 30e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 2e10, medium=WATER)
    rng = np.random.default_rng(2813)
    d = df + NOISE * rng.standard_normal((300, N.size))
    g = dg + NOISE * rng.standard_normal((300, N.size))
    fit = fit_particles(F0, N, d, g, PS, medium=WATER)
    assert not any("model-misfit" in f for f in fit.flags)
    # both noise estimates find the 0.1 Hz drawn (the series' from 299 x 14 differences, the
    # MAD's standard error ~2.5 % there)
    assert fit.noise_fit == pytest.approx(NOISE, rel=0.1)
    assert fit.noise_series == pytest.approx(NOISE, rel=0.1)
    for name, true in (("kappa", kappa), ("xi", xi), ("coverage", 2e10)):
        value, err = getattr(fit, name), getattr(fit, f"{name}_err")
        assert np.max(np.abs(value / true - 1)) < 0.02, name
        ratio = np.std(value) / np.mean(err)
        assert 1 / 1.3 < ratio < 1.3, (name, ratio)


def test_a_model_that_misfits_by_a_few_noise_levels_is_caught():
    # locked rocking fitted to free-rolling particles in water: the residuals are systematic,
    # several times the 0.1 Hz noise, which the pooled σ̂ alone would take for noise
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    xi = 0.05 * kappa / (2 * np.pi * 30e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 2e10, medium=WATER)
    rng = np.random.default_rng(7)
    d = df + NOISE * rng.standard_normal((60, N.size))
    g = dg + NOISE * rng.standard_normal((60, N.size))
    _all_misfit(fit_particles(F0, N, d, g, PS, rocking="locked", medium=WATER))


def test_a_single_time_point_has_no_independent_noise_and_keeps_the_residual_rule():
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    df, dg = particle_shifts(F0, N, PS, kappa, 1e-8, 2e10, medium=WATER)
    fit = fit_particles(F0, N, df + 0.05, dg - 0.05, PS, medium=WATER)
    assert np.isnan(fit.noise_series) and np.isfinite(fit.noise_fit)
    assert not any("model-misfit" in f for f in fit.flags)
    assert np.isfinite(fit.kappa[0])


def test_with_a_stated_noise_neither_estimate_is_made():
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    df, dg = particle_shifts(F0, N, PS, kappa, 1e-8, 2e10, medium=WATER)
    fit = fit_particles(F0, N, df, dg, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    assert np.isnan(fit.noise_fit) and np.isnan(fit.noise_series)


def test_the_difference_noise_reads_the_spread_through_a_slow_drift_and_a_jump():
    rng = np.random.default_rng(3)
    t = np.arange(2000)[:, None]
    sigma = np.array([0.1, 0.3, 1.0])
    drift = 1e-3 * t + 5.0 * (t >= 1000)  # slow drift, one jump
    z = (drift + sigma * rng.standard_normal((2000, 3))) + 1j * (
        -drift + sigma * rng.standard_normal((2000, 3))
    )
    variance, count = difference_noise(z, np.ones(z.shape, bool))
    # the mean of the six series' variances (independent of the estimator: the σ drawn)
    assert variance == pytest.approx(np.mean(sigma**2), rel=0.1)
    assert count == 6 * 1999
    # a missing point breaks the two differences around it; one step has no estimate
    measured = np.ones(z.shape, bool)
    measured[10, 0] = False
    assert difference_noise(z, measured)[1] == 6 * 1999 - 4
    assert np.isnan(difference_noise(z[:1], measured[:1])[0])
