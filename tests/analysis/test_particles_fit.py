"""The fit of attached particles (contactres.analysis.fit_particles): recovery of synthetic
data, error calibration over repeated noise, the identifiability flags, bad input."""

import numpy as np
import pytest

from contactres.analysis import PARTICLE_FLAGS, fit_particles
from contactres.errors import ContactresInputError
from contactres.resonators import WATER, Particle, coupled_resonance, particle_shifts

F0 = 5e6
N = np.arange(1, 14, 2)
NOISE = 0.1  # Hz, on Δf_n and ΔΓ_n (issue 28's studies)
# polystyrene-like colloids of 1 µm radius in water, silica-like ones of 0.5 µm in air
PS = Particle.sphere(1e-6, 1050.0)
SILICA = Particle.sphere(0.5e-6, 2000.0)


def _kappa_for(particle, f_coupled, rocking="free", medium=None):
    """κ whose coupled resonance is f_coupled (bisection in ln κ on coupled_resonance)."""
    lo, hi = np.log(1e-6), np.log(1e9)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        f = np.min(coupled_resonance(particle, np.exp(mid), rocking=rocking, medium=medium))
        step = (mid, hi) if f < f_coupled else (lo, mid)
        if step == (lo, hi):  # the bracket no longer moves (~55 steps): it never will again
            break
        lo, hi = step
    return float(np.exp(0.5 * (lo + hi)))


def _noisy(df, dg, draws, seed):
    rng = np.random.default_rng(seed)
    shape = (draws, np.size(df))
    return df + NOISE * rng.standard_normal(shape), dg + NOISE * rng.standard_normal(shape)


@pytest.mark.parametrize("rocking", ["free", "locked", 2e-9])
@pytest.mark.parametrize("medium", [None, WATER])
def test_noise_free_shifts_give_back_the_parameters(rocking, medium):
    kappa = _kappa_for(PS, 30e6, rocking, medium)
    xi = 0.02 * kappa / (2 * np.pi * 30e6)  # loss tangent 0.02 at the resonance
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 3e10, rocking=rocking, medium=medium)
    fit = fit_particles(
        F0, N, df, dg, PS, rocking=rocking, medium=medium, sigma_df=NOISE, sigma_dgamma=NOISE
    )
    np.testing.assert_allclose(
        [fit.kappa[0], fit.xi[0], fit.coverage[0]], [kappa, xi, 3e10], rtol=1e-6
    )
    # the fit's f_coupled is the lower mode where there are two
    assert fit.f_coupled[0] == pytest.approx(30e6, rel=1e-6)
    assert fit.flags == ((),)
    np.testing.assert_allclose(fit.df_model[0], df, atol=1e-6)


def test_the_rotational_stiffness_is_fitted_where_the_rocking_mode_is_in_the_comb():
    kappa, kr = 100.0, 1e-9
    df, dg = particle_shifts(F0, N, SILICA, kappa, 2e-7, 2e10, rocking=kr)
    fit = fit_particles(F0, N, df, dg, SILICA, rocking="fit", sigma_df=NOISE, sigma_dgamma=NOISE)
    np.testing.assert_allclose(
        [fit.kappa[0], fit.xi[0], fit.coverage[0], fit.kappa_r[0]],
        [kappa, 2e-7, 2e10, kr],
        rtol=1e-6,
    )
    assert fit.parameters == ("kappa", "xi", "coverage", "kappa_r")


def test_an_unresolved_rotational_stiffness_leaves_f_coupled_empty():
    # spheres free to roll (κ_r = 0) fitted with rocking="fit": κ_r is not identified, and the
    # lower mode of the fitted κ_r (near rolling: Hz to kHz) is not the data's 30 MHz resonance
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    xi = 0.05 * kappa / (2 * np.pi * 30e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 2e10, medium=WATER)
    d, g = _noisy(df, dg, 20, seed=9)
    fit = fit_particles(
        F0, N, d, g, PS, medium=WATER, rocking="fit", sigma_df=NOISE, sigma_dgamma=NOISE
    )
    unresolved = np.array(["rocking-unresolved" in f for f in fit.flags])
    assert unresolved.sum() >= 15
    assert np.all(np.isnan(fit.f_coupled[unresolved]))
    assert np.all(np.isnan(fit.f_coupled_err[unresolved]))
    assert not any("outside-comb" in f for f, u in zip(fit.flags, unresolved, strict=True) if u)
    # κ and the coverage are still identified (the translation sets the comb's response)
    np.testing.assert_allclose(fit.kappa[unresolved], kappa, rtol=0.02)


@pytest.mark.parametrize(
    ("particle", "medium", "f_coupled", "coverage"),
    [
        (PS, WATER, 8e6, 2e10),
        (PS, WATER, 30e6, 2e10),
        (PS, WATER, 60e6, 2e10),
        (PS, WATER, 30e6, 2e9),  # ten times fewer particles: |Δf| up to 240 Hz
        (SILICA, None, 12e6, 5e10),
        (SILICA, None, 45e6, 5e10),
    ],
)
def test_recovery_within_two_percent_and_errors_calibrated(particle, medium, f_coupled, coverage):
    """Issue 28's study: n = 1..13, 0.1 Hz noise on Δf_n and ΔΓ_n, resonance in the comb."""
    kappa = _kappa_for(particle, f_coupled, medium=medium)
    xi = 0.05 * kappa / (2 * np.pi * f_coupled)
    df, dg = particle_shifts(F0, N, particle, kappa, xi, coverage, medium=medium)
    draws = 300
    d, g = _noisy(df, dg, draws, seed=28)
    fit = fit_particles(F0, N, d, g, particle, medium=medium, sigma_df=NOISE, sigma_dgamma=NOISE)
    assert all(f == () for f in fit.flags)
    for name, true in (("kappa", kappa), ("xi", xi), ("coverage", coverage)):
        value, err = getattr(fit, name), getattr(fit, f"{name}_err")
        assert np.max(np.abs(value / true - 1)) < 0.02, name
        # the printed errors against the scatter over 300 draws: the ratio of a standard
        # deviation estimated from 300 normal draws has a relative spread of ~4 %, so 1.3 is
        # far outside chance
        ratio = np.std(value) / np.mean(err)
        assert 1 / 1.3 < ratio < 1.3, (name, ratio)


def test_errors_from_the_residuals_without_a_stated_noise_are_calibrated():
    kappa = _kappa_for(PS, 25e6, medium=WATER)
    xi = 0.05 * kappa / (2 * np.pi * 25e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 2e10, medium=WATER)
    d, g = _noisy(df, dg, 300, seed=5)
    fit = fit_particles(F0, N, d, g, PS, medium=WATER)
    for name in ("kappa", "xi", "coverage"):
        ratio = np.std(getattr(fit, name)) / np.mean(getattr(fit, f"{name}_err"))
        assert 1 / 1.3 < ratio < 1.3, (name, ratio)
    # the noise estimate: χ²/dof in Hz² is the noise variance
    assert np.mean(fit.chi2 / fit.dof) == pytest.approx(NOISE**2, rel=0.1)


def test_a_resonance_far_above_the_comb_identifies_only_the_mass():
    # f_coupled = 2 GHz, shifts of 24-234 Hz against 0.1 Hz of noise
    kappa = _kappa_for(PS, 2e9, medium=WATER)
    df, dg = particle_shifts(F0, N, PS, kappa, 1e-6, 2e9, medium=WATER)
    d, g = _noisy(df, dg, 50, seed=3)
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    for flags in fit.flags:
        assert {"outside-comb", "kappa-unresolved"} <= set(flags)
    # the rigid contact is not rejected (a few draws may reject it at Δχ² = 9 and still leave
    # κ unresolved by its error)
    assert sum("sauerbrey-like" in f for f in fit.flags) >= 40
    assert np.all(np.isnan(fit.kappa)) and np.all(np.isnan(fit.f_coupled))
    assert np.all(np.isnan(fit.kappa_err))
    # the mass, and so the coverage of particles of known mass, is identified (where the fit
    # converged)
    assert np.sum(np.isfinite(fit.coverage)) >= 40
    assert np.nanmax(np.abs(fit.coverage / 2e9 - 1)) < 0.02


def test_a_resonance_far_below_the_comb_identifies_only_the_products():
    # particles that stand still on soft contacts (paper 2's regime): Δf > 0 on every overtone,
    # 1.5-20 Hz against 0.1 Hz of noise
    kappa = _kappa_for(PS, 0.5e6, medium=WATER)
    xi = 0.1 * kappa / (2 * np.pi * 15e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 1e11, medium=WATER)
    assert np.all(df > 0)
    d, g = _noisy(df, dg, 50, seed=4)
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    for flags in fit.flags:
        assert {"inertial", "kappa-unresolved", "xi-unresolved", "coverage-unresolved"} <= set(
            flags
        )
    # ξ = Nξ/N carries the unidentified N: it is blanked with κ and N
    assert np.all(np.isnan(fit.kappa)) and np.all(np.isnan(fit.coverage))
    assert np.all(np.isnan(fit.xi))
    # N·κ is what the data give (paper 2, Eq. 1), within its stated error; where the search
    # found a second minimum that fits nearly as well farther out than the error allows (one
    # of the 50 here: Δχ² = 7.5 at 6σ) its error is widened to hold it (before: left empty)
    true = 1e11 * kappa
    shown = np.isfinite(fit.coverage_kappa)
    assert shown.sum() >= 45
    assert all("wide-interval" in f for f, s in zip(fit.flags, shown, strict=True) if not s)
    assert np.all(np.abs(fit.coverage_kappa[shown] - true) < 5 * fit.coverage_kappa_err[shown])
    assert np.mean(fit.coverage_kappa[shown]) == pytest.approx(true, rel=0.02)


def test_a_product_with_a_second_minimum_below_the_comb_is_not_printed():
    # Issue 28's open case: f_coupled 2.5x below the comb in water. The χ² has a second valley
    # towards the particles standing still (κ 25x lower, N 30x higher) whose N·κ lies ~20 %
    # (8σ) from the truth's; before, fits stopped there and printed N·κ with 35 % of the draws
    # beyond 3σ. Now the fit finds the lower minimum (a grid start below the comb), and N·κ's
    # error holds every point of nearly the same χ² (rule 5; before, such steps were blank).
    kappa = _kappa_for(PS, 2e6, medium=WATER)
    xi = 0.05 * kappa / (2 * np.pi * 2e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 2e9, medium=WATER)
    d, g = _noisy(df, dg, 60, seed=11)
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    shown = np.isfinite(fit.coverage_kappa)
    z = (fit.coverage_kappa[shown] - 2e9 * kappa) / fit.coverage_kappa_err[shown]
    assert shown.sum() >= 20
    # 3σ: 0.3 % of normal draws; 10 % allows for the 60 draws (before: 35 %)
    assert np.mean(np.abs(z) > 3) < 0.1, (shown.sum(), np.round(z, 1))


@pytest.mark.parametrize("stated", [True, False], ids=["noise stated", "noise estimated"])
def test_far_below_the_comb_with_a_large_signal_the_fit_finds_the_lowest_minimum(stated):
    # Issue 28's remaining case: f_coupled = f_F/10 in water, loss tangent 0.1, |Δf| up to 61
    # Hz. The χ² along the valley of constant N·κ has a second minimum at 2.2 times κ (Δχ² ≈
    # 19 above the first without noise); the search stopped there in a quarter of the draws,
    # with χ² 5-25 above that of the true parameters and N·κ printed 3-6σ off (200 draws:
    # scatter twice the printed error, mean +0.9 to +1.4σ, 20-30 % beyond 3σ). The profile
    # along κ finds the lower minimum.
    kappa = _kappa_for(PS, 0.5e6, medium=WATER)
    xi = 0.1 * kappa / (2 * np.pi * 0.5e6)
    coverage = 3e11
    df, dg = particle_shifts(F0, N, PS, kappa, xi, coverage, medium=WATER)
    d, g = _noisy(df, dg, 60, seed=7)
    sigma = NOISE if stated else None
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=sigma, sigma_dgamma=sigma)
    # the least-squares minimum lies at or below the χ² of the truth, one point of the
    # parameter space (independent of where the search went; in Hz² without a stated noise)
    chi2_truth = np.sum((d - df) ** 2 + (g - dg) ** 2, axis=1) / (NOISE**2 if stated else 1.0)
    assert np.all(fit.chi2 <= chi2_truth + 1e-6), np.round(fit.chi2 - chi2_truth, 1)
    shown = np.isfinite(fit.coverage_kappa)
    z = (fit.coverage_kappa[shown] - coverage * kappa) / fit.coverage_kappa_err[shown]
    assert shown.sum() >= 40
    # a standard deviation from 40-60 normal draws has a relative spread of 9-11 %: 1.3 is ~3
    # of it above 1, and the mean's spread is 0.13-0.16 (0.5: ~3.5 of it)
    assert np.std(z) < 1.3, (shown.sum(), np.round(z, 1))
    assert abs(np.mean(z)) < 0.5, np.mean(z)
    # beyond 3σ: 0.3 % of normal draws, ~0.2 of 60 expected (before: 14-17 of these 60)
    assert np.sum(np.abs(z) > 3) <= 2, np.round(z, 1)


@pytest.mark.parametrize(
    "f_coupled, medium", [(2e6, None), (3e6, WATER)], ids=["2 MHz, vacuum", "3 MHz, water"]
)
def test_below_the_comb_a_printed_value_has_an_error_that_matches_its_scatter(f_coupled, medium):
    # The review's case: a resonance below the lowest overtone (5 MHz) at a coverage that shifts
    # Δf_1 by ~10 Hz. Before, some steps printed κ and the coverage 4σ from the truth (2 MHz),
    # and N·κ from fits stuck at 30 times the χ² of the truth (3 MHz, water: the scatter 4x
    # the printed error). Now a value is printed only with an error that matches the scatter
    # over 300 draws within the factor 1.3 (and its mean within 0.5σ of the truth).
    kappa = _kappa_for(PS, f_coupled, medium=medium)
    xi = 0.05 * kappa / (2 * np.pi * f_coupled)
    coverage = 2e9
    df, dg = particle_shifts(F0, N, PS, kappa, xi, coverage, medium=medium)
    d, g = _noisy(df, dg, 300, seed=5)
    fit = fit_particles(F0, N, d, g, PS, medium=medium, sigma_df=NOISE, sigma_dgamma=NOISE)
    truth = {"kappa": kappa, "xi": xi, "coverage": coverage, "coverage_kappa": coverage * kappa}
    for name, true in truth.items():
        value, err = getattr(fit, name), getattr(fit, f"{name}_err")
        shown = np.isfinite(value)
        if shown.sum() < 20:  # (flagged at nearly every step: nothing to calibrate)
            continue
        z = (value[shown] - true) / err[shown]
        assert 1 / 1.3 < np.std(z) < 1.3, (name, shown.sum(), np.std(z))
        assert abs(np.mean(z)) < 0.5, (name, np.mean(z))


@pytest.mark.parametrize(("loss", "overdamped"), [(0.5, False), (2.0, True)])
def test_a_contact_damped_beyond_its_stiffness_is_noted_overdamped(loss, overdamped):
    # loss tangent ωξ/κ at f_coupled = 20 MHz (in the comb)
    kappa = _kappa_for(PS, 20e6, medium=WATER)
    xi = loss * kappa / (2 * np.pi * 20e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 2e10, medium=WATER)
    # what the note says: above 1 the bandwidth shift has no peak within the comb (it rises
    # to the last overtone), below it peaks inside
    assert (np.argmax(dg) == N.size - 1) == overdamped
    d, g = _noisy(df, dg, 20, seed=9)
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    assert all(("overdamped" in f) == overdamped for f in fit.flags)
    # a note, not a verdict: κ, ξ, the coverage and f_coupled are printed
    for name in ("kappa", "xi", "coverage", "f_coupled"):
        assert np.all(np.isfinite(getattr(fit, name))), name


@pytest.mark.parametrize("medium", [None, WATER])
@pytest.mark.parametrize("stated", [True, False])
def test_pure_noise_is_no_signal_and_prints_kappa_at_most_at_the_stated_rate(medium, stated):
    # Issue 28's review: with the threshold 9 (χ²(3)) 11-23 of 2000 pure-noise steps printed
    # κ in vacuum, 4 in water (the fit's resonance sits on the best of the 7 overtones). The
    # no-signal threshold now allows at most NO_SIGNAL_RATE (1e-4) per step: at most 0.3
    # expected in 3000 steps (the bound; the simulated rate is lower), so none or one.
    # The noise estimated in water is also the review's case of each step's own s² = χ²/11 in
    # the no-signal test: 8-15 of 1000 pure-noise steps printed a κ (an F test at 8 % instead of
    # 3 %); with the variance pooled over the series the rate is that of a stated noise.
    # Power (Poisson, "none or one" passes): in vacuum the old rate (>= 11 of 2000) gives 11
    # expected in 2000 steps, passing with P = 2e-4 (with 1000 steps, 2.7 %); in water (4 of
    # 2000) 3000 steps are needed (6 expected, P = 1.7 %; with 1000 it would pass in 41 %).
    from contactres.analysis._particle_linear import NO_SIGNAL_RATE

    draws = 2000 if medium is None else 3000
    rng = np.random.default_rng(2828 + 2 * stated + (medium is None))
    d, g = NOISE * rng.standard_normal((2, draws, N.size))
    sigma = NOISE if stated else None
    fit = fit_particles(F0, N, d, g, PS, medium=medium, sigma_df=sigma, sigma_dgamma=sigma)
    assert draws * NO_SIGNAL_RATE < 1
    for name in ("kappa", "f_coupled", "coverage_kappa"):
        assert np.isfinite(getattr(fit, name)).sum() <= 1, name
    # Shifts that are noise alone (a sensor before adsorption) are no-signal steps: the empty
    # model fits as well wherever Δχ² is below the threshold. At the rate above nearly every
    # step (even at the old threshold 9, with P(χ²(3) > 9) = 3 % and P(F(3, 11) > 3) = 8 %,
    # 85 % of 2000 steps was > 10σ of the binomial below either expectation).
    empty = np.array(["no-signal" in f for f in fit.flags])
    assert empty.mean() > 0.85
    # a no-signal step prints nothing (no κ, ξ, coverage, f_coupled or product) and names it
    for flags in (f for f in fit.flags if "no-signal" in f):
        assert {"kappa-unresolved", "xi-unresolved", "coverage-unresolved"} <= set(flags)
    for name in ("kappa", "xi", "coverage", "f_coupled", "coverage_kappa", "coverage_xi"):
        assert np.all(np.isnan(getattr(fit, name)[empty])), name


def test_the_no_signal_threshold_grows_with_the_overtones_and_keeps_its_rate():
    # Each overtone a trial (look-elsewhere): M trials of χ²(q) at rate/M each; checked
    # against draws of χ²(3) (stated noise) and of 3F(3, ν) (noise per step) themselves
    from contactres.analysis._particle_linear import no_signal_threshold

    rng = np.random.default_rng(47)
    count = np.array([3, 7, 13])
    stated = no_signal_threshold(count, 2 * count - 3, 3, per_step=False, rate=0.05)
    per_step = no_signal_threshold(count, 2 * count - 3, 3, per_step=True, rate=0.05)
    assert np.all(np.diff(stated) > 0) and np.all(per_step > stated)
    draws = rng.chisquare(3, 400_000)
    for m, t in zip(count, stated, strict=True):
        assert np.mean(draws > t) == pytest.approx(0.05 / m, rel=0.05)
    for m, t in zip(count, per_step, strict=True):
        nu = 2 * m - 3
        ratio = rng.chisquare(3, 400_000) / (rng.chisquare(nu, 400_000) / nu)
        assert np.mean(ratio > t) == pytest.approx(0.05 / m, rel=0.05)
    # the default rate (1e-4) at the seven overtones n = 1...13: above the old 9 by far
    assert no_signal_threshold(np.array([7]), np.array([11]), 3, per_step=False)[0] > 20


def test_the_per_step_threshold_has_the_tail_probability_of_the_stated_one():
    # A short series (too few steps to pool) estimates s² per step: Δχ²/s² is then
    # q F(q, ν)-distributed, checked here against draws of χ²(q)/(χ²(ν)/ν) themselves
    from contactres.analysis._particle_linear import limit_threshold

    rng = np.random.default_rng(31)
    for q, nu in ((3, 11), (2, 4), (1, 9)):
        ratio = rng.chisquare(q, 400_000) / (rng.chisquare(nu, 400_000) / nu)
        threshold = limit_threshold(9.0, np.array([nu]), q, per_step=True)[0]
        expected = np.mean(rng.chisquare(q, 400_000) > 9.0)
        assert np.mean(ratio > threshold) == pytest.approx(expected, rel=0.05)
    assert limit_threshold(9.0, np.array([11]), 3, per_step=False)[0] == 9.0


def test_a_signal_well_above_the_noise_is_not_no_signal():
    # the same rule does not blank a real (if small) response: 1 µm spheres in the comb at a
    # coverage that shifts Δf by a few hertz
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    df, dg = particle_shifts(F0, N, PS, kappa, 1e-7, 2e8, medium=WATER)
    d, g = _noisy(df, dg, 50, seed=7)
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    assert not any("no-signal" in f for f in fit.flags)


def test_two_overtones_with_the_noise_estimated_are_refused_in_one_line():
    # 2 overtones, 3 parameters: one degree of freedom (singular), too few for the noise
    df, dg = particle_shifts(F0, N[:2], PS, 1e7, 0.0, 1e10)
    with pytest.raises(ContactresInputError, match="2 overtones leave 1 degree of freedom for 3"):
        fit_particles(F0, N[:2], df, dg, PS)


def test_flags_are_named_in_the_flag_table():
    df, dg = particle_shifts(F0, N, PS, 1e7, 0.0, 1e10)
    fit = fit_particles(F0, N, df, dg, PS, sigma_df=NOISE, sigma_dgamma=NOISE)
    assert fit.flags[0] and all(f in PARTICLE_FLAGS for f in fit.flags[0])


def test_time_series_with_missing_overtones():
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    df, dg = particle_shifts(F0, N, PS, kappa, 1e-7, 2e10, medium=WATER)
    d, g = np.tile(df, (3, 1)), np.tile(dg, (3, 1))
    d[1, 2] = np.nan  # 5th overtone missing at step 1
    d[2, 1:] = np.nan  # step 2: only the fundamental
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    np.testing.assert_allclose(fit.kappa[:2], kappa, rtol=1e-6)
    assert fit.flags[2] == ("too-few-overtones",) and np.isnan(fit.kappa[2])
    assert fit.kappa.shape == fit.correlation.shape[:1] == (3,)
    assert fit.correlation.shape == (3, 3, 3)


def test_particles_smaller_than_the_penetration_depth_in_water_give_a_flag_not_a_number():
    # 50 nm: smaller than δ = 70 nm in water even at 65 MHz, the top of the comb
    small = Particle.sphere(50e-9, 1050.0)
    df, dg = particle_shifts(F0, N, small, 1.0, 1e-9, 1e12, medium=WATER)
    fit = fit_particles(F0, N, df, dg, small, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    assert "particle-smaller-than-delta" in fit.flags[0]
    assert np.isnan(fit.kappa[0]) and np.isnan(fit.coverage[0]) and np.isnan(fit.xi[0])


def test_the_overtones_inside_the_penetration_depth_are_dropped_and_the_rest_fitted():
    # R = 120 nm in water: δ = √(2η/(ρω)) = 238, 138, 107 nm at n = 1, 3, 5 (f_F = 5 MHz),
    # below R from n = 5 on: n = 1 and 3 are dropped and 5..13 fitted. The shifts at n = 1, 3
    # are spoilt on purpose (+50 Hz): a fit that used them would miss.
    particle = Particle.sphere(0.12e-6, 1050.0)
    delta = np.sqrt(2 * WATER.viscosity / (WATER.density * 2 * np.pi * F0 * N))
    assert list(N[delta > 0.12e-6]) == [1, 3]
    kappa = _kappa_for(particle, 35e6, medium=WATER)
    xi = 0.02 * kappa / (2 * np.pi * 35e6)
    df, dg = particle_shifts(F0, N, particle, kappa, xi, 5e10, medium=WATER)
    df, dg = df + 50.0 * (N < 5), dg + 50.0 * (N < 5)
    fit = fit_particles(F0, N, df, dg, particle, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    assert fit.flags[0] == ("dropped-overtones-R<delta: 1,3",)
    assert fit.flags[0][0].split(":")[0] in PARTICLE_FLAGS
    assert fit.kappa[0] == pytest.approx(kappa, rel=1e-6)
    assert fit.coverage[0] == pytest.approx(5e10, rel=1e-6)
    assert fit.dof[0] == 2 * 5 - 3


def test_too_few_overtones_to_estimate_the_noise_are_refused_or_flagged():
    kappa = _kappa_for(PS, 30e6, medium=WATER)
    df, dg = particle_shifts(F0, N, PS, kappa, 1e-7, 2e10, medium=WATER)
    # two or three overtones leave 1 or 3 dof for 3 parameters: refused without a stated noise
    for m in (2, 3):
        with pytest.raises(ContactresInputError, match="state the noise"):
            fit_particles(F0, N[:m], df[:m], dg[:m], PS, medium=WATER)
    # ... and fitted with one (the noise-free shifts come back)
    fit = fit_particles(F0, N[:3], df[:3], dg[:3], PS, medium=WATER, sigma_df=0.1, sigma_dgamma=0.1)
    assert fit.kappa[0] == pytest.approx(kappa, rel=1e-6)
    # in a series, a step with three overtones is flagged, the others are fitted
    d, g = _noisy(df, dg, 25, seed=11)
    d[0, 3:] = np.nan
    fit = fit_particles(F0, N, d, g, PS, medium=WATER)
    assert fit.flags[0] == ("too-few-overtones",) and np.isnan(fit.kappa[0])
    assert np.all(np.isfinite(fit.kappa[1:]))


def test_two_overtones_with_a_stated_noise_have_calibrated_errors():
    # The review's case (20 % of the draws beyond 3σ with residual-based errors from 1 dof):
    # with the noise stated the errors come from it alone and match the scatter over 300 draws
    n = np.array([3, 5])
    kappa = _kappa_for(PS, 20e6, medium=WATER)
    xi = 0.05 * kappa / (2 * np.pi * 20e6)
    df, dg = particle_shifts(F0, n, PS, kappa, xi, 2e10, medium=WATER)
    d, g = _noisy(df, dg, 300, seed=23)
    fit = fit_particles(F0, n, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    for name, true in (("kappa", kappa), ("xi", xi), ("coverage", 2e10)):
        z = (getattr(fit, name) - true) / getattr(fit, f"{name}_err")
        assert np.all(np.isfinite(z)), name
        assert 1 / 1.3 < np.std(z) < 1.3, (name, np.std(z))
        assert np.mean(np.abs(z) > 3) < 0.02, name


def test_bad_input_is_one_line():
    df, dg = particle_shifts(F0, N, PS, 100.0, 1e-7, 1e10)
    with pytest.raises(ContactresInputError, match="at least two overtones"):
        fit_particles(F0, [3], df[:1], dg[:1], PS)
    with pytest.raises(ContactresInputError, match="bandwidth"):
        fit_particles(F0, N, df, np.full(N.size, np.nan), PS)
    with pytest.raises(ContactresInputError, match="shape"):
        fit_particles(F0, N, df[:3], dg[:3], PS)
    with pytest.raises(ContactresInputError, match="sigma_df"):
        fit_particles(F0, N, df, dg, PS, sigma_df=-1.0, sigma_dgamma=0.1)
    with pytest.raises(ContactresInputError, match="both"):
        fit_particles(F0, N, df, dg, PS, sigma_df=0.1)


def test_the_valley_profile_moves_a_fit_from_the_shallower_to_the_deeper_minimum():
    # A toy problem in the fit's coordinates (q0 = ln κ, q1 = ξ, q2 = ln N) with residuals
    # q0² - 1, 0.3 (q0 - 1), q1 - 2, q2 - 3: along q0 a minimum at q0 = 1 with χ² = 0 and a
    # shallower one near q0 = -1 (χ² ≈ 0.36). From the shallower, the profile (q0 held at
    # q0 + ln s, q1, q2 fitted) reaches the basin of the deeper, and the refined fit is its
    # exact minimum (1, 2, 3).
    from contactres.analysis._particle_profile import valley_profile
    from contactres.fitting import LMOptions

    def evaluate(q, rows, jacobian):
        r = np.stack([q[:, 0] ** 2 - 1, 0.3 * (q[:, 0] - 1), q[:, 1] - 2, q[:, 2] - 3], 1)
        jac = np.zeros((q.shape[0], 4, 3))
        jac[:, 0, 0], jac[:, 1, 0], jac[:, 2, 1], jac[:, 3, 2] = 2 * q[:, 0], 0.3, 1.0, 1.0
        jt = jac.transpose(0, 2, 1)
        return {
            "chi2": np.sum(r * r, 1),
            "gradient": (jt @ r[:, :, None])[..., 0],
            "hessian": jt @ jac,
        }

    # two steps: one in the shallower minimum's basin (profiled), one at the deeper (not)
    q = np.array([[-1.0, 2.0, 3.0], [1.0, 2.0, 3.0]])
    chi2 = evaluate(q, None, False)["chi2"]
    lo, hi = np.full((2, 3), -10.0), np.full((2, 3), 10.0)
    options = LMOptions(max_iter=300, xtol=1e-12, ftol=1e-14)
    q2, chi2_2, conv, visited = valley_profile(
        evaluate, q, chi2, np.ones(2, bool), np.array([0]), lo, hi, options
    )
    np.testing.assert_allclose(q2[0], [1.0, 2.0, 3.0], atol=1e-6)
    assert chi2_2[0] < 1e-10 and conv[0]
    # the step not profiled is left alone, and only the profiled step has visited points
    np.testing.assert_array_equal(q2[1], q[1])
    assert all(np.isinf(c[1]) and np.isfinite(c[0]) for _, c in visited)


def test_below_the_comb_the_decision_to_print_does_not_pick_the_stiff_draws():
    # Issue 28's review (M2): a resonance at 3 MHz in vacuum at a coverage of 1e9 m⁻², where
    # κ's relative error is about 10 % in every draw. It falls as the fitted κ rises, so a cut
    # at 10 % printed κ in 32 of these 60 draws (ξ in 6), the stiff ones: mean z +0.93 (ξ
    # +1.90). The raw fit is unbiased; printed in every draw (now: mean z +0.31 and +0.08)
    # its errors match its scatter.
    kappa = _kappa_for(PS, 3e6)
    xi = 0.1 * kappa / (2 * np.pi * 3e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 1e9)
    d, g = _noisy(df, dg, 60, seed=28)
    fit = fit_particles(F0, N, d, g, PS, sigma_df=NOISE, sigma_dgamma=NOISE)
    for name, true in {"kappa": kappa, "xi": xi}.items():
        value, err = getattr(fit, name), getattr(fit, f"{name}_err")
        shown = np.isfinite(value)
        assert shown.sum() >= 54, (name, shown.sum())
        z = (value[shown] - true) / err[shown]
        # the mean of 54+ standard normals: within 0.5 at 3.7 of its σ
        assert abs(np.mean(z)) < 0.5, (name, np.mean(z))
        assert 1 / 1.3 < np.std(z) < 1.3, (name, np.std(z))


def test_below_the_comb_a_product_with_a_wide_interval_is_printed_with_a_wider_error():
    # Issue 28's review (M1): 2 MHz in water at a coverage of 1e9 m⁻² (|Δf| up to 2.6 Hz). The
    # valley's far side fits nearly as well in most draws; N·κ was left empty there and printed
    # in the 14 of these 60 draws where the search saw no such point, those whose estimate lay
    # high (mean z +1.5; 94 of 400 draws in the review, 12 % beyond 3σ). Printed in every draw
    # with its error widened to hold those points, it keeps a lean of about +0.7σ (the visited
    # points do not always reach the far side) that the bound below allows.
    kappa = _kappa_for(PS, 2e6, medium=WATER)
    xi = 0.1 * kappa / (2 * np.pi * 2e6)
    df, dg = particle_shifts(F0, N, PS, kappa, xi, 1e9, medium=WATER)
    d, g = _noisy(df, dg, 60, seed=28)
    fit = fit_particles(F0, N, d, g, PS, medium=WATER, sigma_df=NOISE, sigma_dgamma=NOISE)
    shown = np.isfinite(fit.coverage_kappa)
    assert shown.sum() >= 54, shown.sum()
    z = (fit.coverage_kappa[shown] - 1e9 * kappa) / fit.coverage_kappa_err[shown]
    assert np.mean(z) < 1.1 and np.std(z) < 1.3, (np.mean(z), np.std(z))
    # beyond 3σ: 0.3 % of normal draws (0.2 of 60 expected)
    assert np.sum(np.abs(z) > 3) <= 2, np.round(z, 1)
