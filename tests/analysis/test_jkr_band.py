"""The 95 % band of the fitted JKR + Mindlin curve κ(F_N) (``jkr_curves.csv``, issue 30): the
linear propagation of the fit's covariance, against a Monte Carlo of the public κ function,
against the exact variance of a linear curve, and the groups that get no band."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from contactres.analysis._curves import band_half_width, jkr_curves
from contactres.analysis._jkr import fit_correlation, fit_jkr_mindlin
from contactres.tangential import kappa_jkr_mindlin

R, NU = 1.2e-3, 0.17
E, GAMMA = 70e9, 0.05


def _group(**changes) -> dict:
    """A group record as the analysis makes it (the fields jkr_curves reads)."""
    g = {
        "configuration": "c",
        "medium": "air",
        "E_Pa": E,
        "gamma_J_m2": GAMMA,
        "sphere_radius_m": R,
        "poisson": NU,
        "P_Hz_per_N_per_m": 2.3e-4,
        "E_fit_err_Pa": 0.004 * E,
        "gamma_fit_err_J_m2": 0.02 * GAMMA,
        "E_gamma_fit_corr": -0.9,
        "n_points_fitted": 32,
    }
    g.update(changes)
    return g


LOADS = pd.DataFrame({"configuration": ["c", "c"], "normal_force_N": [1e-4, 2e-3]})


def test_the_band_is_the_monte_carlo_spread_of_the_public_kappa():
    """Small errors (linearisation holds): the half-width over t(0.975; N - 2) is the sd of κ,
    and 1.96 of it is half the 2.5-97.5 % range of κ over draws of (E, γ) from the covariance,
    each evaluated with the public kappa_jkr_mindlin (not the band's code)."""
    g = _group()
    curve = jkr_curves([g], LOADS)
    half = (curve["kappa_hi_N_per_m"] - curve["kappa_lo_N_per_m"]).to_numpy() / 2
    sigma = half / stats.t.ppf(0.975, g["n_points_fitted"] - 2)
    sd = np.array([g["E_fit_err_Pa"], g["gamma_fit_err_J_m2"]])
    rho = g["E_gamma_fit_corr"]
    cov = np.outer(sd, sd) * np.array([[1, rho], [rho, 1]])
    draws = np.random.default_rng(7).multivariate_normal([E, GAMMA], cov, size=40_000)
    F = curve["normal_force_N"].to_numpy()
    kappa = kappa_jkr_mindlin(F[None, :], draws[:, :1], draws[:, 1:], R, NU)
    lo, hi = np.percentile(kappa, [2.5, 97.5], axis=0)
    np.testing.assert_allclose(stats.norm.ppf(0.975) * sigma, (hi - lo) / 2, rtol=0.03)
    # and the band is centred on the curve of the fitted values
    np.testing.assert_allclose(
        curve["kappa_N_per_m"], kappa_jkr_mindlin(F, E, GAMMA, R, NU), rtol=1e-12
    )


def test_the_band_contains_the_curve_and_scales_to_df0():
    curve = jkr_curves([_group()], LOADS)
    k, lo, hi = (curve[c].to_numpy() for c in ("kappa_N_per_m", "kappa_lo_N_per_m",
                                               "kappa_hi_N_per_m"))  # fmt: skip
    assert np.all(lo < k) and np.all(k < hi)
    P = _group()["P_Hz_per_N_per_m"]
    np.testing.assert_allclose(curve["df0_model_lo_Hz"], P * lo, rtol=1e-12)
    np.testing.assert_allclose(curve["df0_model_hi_Hz"], P * hi, rtol=1e-12)


def test_the_band_of_a_straight_line_is_its_exact_variance():
    """y = a + b x: var y = σa² + 2 x ρ σa σb + x² σb² exactly (the delta method is exact)."""
    x = np.linspace(-2.0, 3.0, 11)
    sa, sb, rho = 0.3, 0.05, 0.6
    cov = np.array([[sa**2, rho * sa * sb], [rho * sa * sb, sb**2]])
    half = band_half_width(lambda a, b: a + b * x, (1.0, 2.0), cov, 2.0)
    np.testing.assert_allclose(half, 2.0 * np.sqrt(sa**2 + 2 * x * rho * sa * sb + x**2 * sb**2))


def test_a_parameter_at_its_lower_bound_is_differenced_one_sided():
    """γ = 0 (JKR is not defined below): the band is finite and has the width of the
    derivative from above (κ is smooth in γ there, so a small step from above is it)."""
    g = _group(gamma_J_m2=0.0)
    curve = jkr_curves([g], LOADS)
    assert np.isfinite(curve["kappa_lo_N_per_m"]).all()
    assert np.all(curve["kappa_hi_N_per_m"] > curve["kappa_N_per_m"])


def test_a_fit_without_covariance_has_a_curve_and_no_band():
    """Not identified (NaN errors or correlation): the curve, with empty band cells."""
    for change in ({"E_gamma_fit_corr": np.nan}, {"gamma_fit_err_J_m2": np.nan},
                   {"n_points_fitted": 2}):  # fmt: skip
        curve = jkr_curves([_group(**change)], LOADS)
        assert np.isfinite(curve["kappa_N_per_m"]).all()
        assert curve["kappa_lo_N_per_m"].isna().all() and curve["kappa_hi_N_per_m"].isna().all()
        assert curve["df0_model_lo_Hz"].isna().all()


def test_a_withheld_fit_has_no_rows():
    curve = jkr_curves([_group(E_Pa=np.nan, checks=["fit-at-bound"])], LOADS)
    assert curve.empty


def test_the_fit_correlation_is_that_of_the_jacobian_of_the_public_kappa():
    """The correlation of E and γ is -(JᵀJ)⁻¹'s off-diagonal normalised, J the Jacobian of
    kappa_jkr_mindlin at the fitted values (central differences here)."""
    F = np.linspace(1e-4, 2e-3, 8)
    noise = np.random.default_rng(3).normal(0.0, 0.01, F.size)
    kappa = kappa_jkr_mindlin(F, E, GAMMA, R, NU) * (1 + noise)
    res = fit_jkr_mindlin(F, kappa, R, NU)
    e, gam = res.values["E"], res.values["gamma"]
    dE, dg = 1e-5 * e, 1e-5 * gam
    J = np.stack(
        [
            (kappa_jkr_mindlin(F, e + dE, gam, R, NU) - kappa_jkr_mindlin(F, e - dE, gam, R, NU))
            / (2 * dE),
            (kappa_jkr_mindlin(F, e, gam + dg, R, NU) - kappa_jkr_mindlin(F, e, gam - dg, R, NU))
            / (2 * dg),
        ],
        axis=1,
    )
    inv = np.linalg.inv(J.T @ J)
    assert fit_correlation(res) == pytest.approx(
        inv[0, 1] / np.sqrt(inv[0, 0] * inv[1, 1]), abs=1e-4
    )
