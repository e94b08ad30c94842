"""The 95 % band of the fitted JKR + Mindlin curve κ(F_N) (``jkr_curves.csv``, issue 30): the
linear propagation of the covariance of Table 1's errors (the bootstrap's correlation where a
bootstrap gives them), against a Monte Carlo of the public κ function, against the exact
variance of a linear curve, and the groups that get no band."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from contactres.analysis._curves import band_half_width, jkr_curves
from contactres.analysis._jkr import (
    bootstrap_jkr,
    fit_correlation,
    fit_group,
    fit_jkr_mindlin,
)
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
        "E_err_Pa": 0.004 * E,
        "gamma_err_J_m2": 0.02 * GAMMA,
        "E_gamma_corr": -0.9,
        "t95": 3.18,
    }
    g.update(changes)
    return g


LOADS = pd.DataFrame({"configuration": ["c", "c"], "normal_force_N": [1e-4, 2e-3]})


def test_the_band_is_the_monte_carlo_spread_of_the_public_kappa():
    """Small errors (linearisation holds): the half-width over the group's t95 is the sd of κ,
    and 1.96 of it is half the 2.5-97.5 % range of κ over draws of (E, γ) from Table 1's errors
    with their correlation, each evaluated with the public kappa_jkr_mindlin (not the band's
    code)."""
    g = _group()
    curve = jkr_curves([g], LOADS)
    half = (curve["kappa_hi_N_per_m"] - curve["kappa_lo_N_per_m"]).to_numpy() / 2
    sigma = half / g["t95"]
    sd = np.array([g["E_err_Pa"], g["gamma_err_J_m2"]])
    rho = g["E_gamma_corr"]
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


def test_the_band_evaluates_the_curve_only_where_its_differences_need_it():
    """Central differences need the curve at values ± a step only: two calls per parameter
    (a coated plate's curve costs a contact-radius solve per call); the curve at the values
    themselves once, for a one-sided difference at a bound, with the same band as a straight
    line's exact variance there."""
    x = np.linspace(-2.0, 3.0, 11)
    cov = np.diag([0.3, 0.05]) ** 2
    calls = []

    def line(a, b):
        calls.append((a, b))
        return a + b * x

    band_half_width(line, (1.0, 2.0), cov, 2.0)
    assert len(calls) == 4 and (1.0, 2.0) not in calls
    calls.clear()
    half = band_half_width(line, (1.0, 0.0), cov, 2.0, lower=(-np.inf, 0.0))
    assert len(calls) == 4 and calls.count((1.0, 0.0)) == 1
    np.testing.assert_allclose(half, 2.0 * np.sqrt(0.3**2 + x**2 * 0.05**2), rtol=1e-9)


def test_a_parameter_at_its_lower_bound_is_differenced_one_sided():
    """γ = 0 (JKR is not defined below): the band is finite and has the width of the
    derivative from above (κ is smooth in γ there, so a small step from above is it)."""
    g = _group(gamma_J_m2=0.0)
    curve = jkr_curves([g], LOADS)
    assert np.isfinite(curve["kappa_lo_N_per_m"]).all()
    assert np.all(curve["kappa_hi_N_per_m"] > curve["kappa_N_per_m"])


def test_a_fit_without_covariance_has_a_curve_and_no_band():
    """Not identified (NaN errors, correlation or t95): the curve, with empty band cells."""
    for change in ({"E_gamma_corr": np.nan}, {"gamma_err_J_m2": np.nan}, {"t95": np.nan},
                   {"E_err_Pa": 0.0}):  # fmt: skip
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


# ---- the band of a group whose errors come from a bootstrap ------------------------------------

LOADS_5 = np.array([1e-3, 2e-3, 4e-3, 6e-3, 8e-3])


def _experiments(n_exp: int, seed: int = 11) -> pd.DataFrame:
    """Per-(experiment, load) κ of remounted samples: E and γ drawn per experiment (the spread
    between experiments the bootstrap sees) and 0.3 % noise per point, from the public κ."""
    rng = np.random.default_rng(seed)
    rows = []
    for i in range(n_exp):
        e, gam = E * (1 + 0.02 * rng.normal()), GAMMA * (1 + 0.1 * rng.normal())
        kappa = kappa_jkr_mindlin(LOADS_5, e, gam, R, NU) * (1 + 0.003 * rng.normal(size=5))
        rows += [(f"x{i}", F, k) for F, k in zip(LOADS_5, kappa, strict=True)]
    table = pd.DataFrame(rows, columns=["experiment", "normal_force_N", "kappa_N_per_m"])
    return table.assign(sphere_radius_m=R, poisson=NU)


def test_the_recorded_correlation_is_that_of_the_bootstrap():
    """E_gamma_corr of a group with a bootstrap over its experiments is the correlation over
    the resamples of bootstrap_jkr (itself checked against refitting every resample in
    test_analysis.py), not the fit's, which stays recorded as E_gamma_fit_corr."""
    pts = _experiments(6)
    B, seed = 60, 5
    g = fit_group(pts, ("c", "air"), B, seed)
    assert g["error_method"].startswith("bootstrap over the 6 experiments")
    res = fit_jkr_mindlin(pts["normal_force_N"], pts["kappa_N_per_m"], R, NU)
    assert g["E_gamma_corr"] == bootstrap_jkr(pts, R, NU, res, B, seed)[2]
    assert g["E_gamma_fit_corr"] == pytest.approx(fit_correlation(res), rel=1e-12)
    assert abs(g["E_gamma_corr"] - g["E_gamma_fit_corr"]) > 0.5  # spread vs fit: unlike here


def test_the_band_of_a_bootstrapped_group_holds_table_1s_errors():
    """With a bootstrap over experiments: the band is t95 x the sd of κ over draws of (E, γ)
    from a 2-D normal with Table 1's errors (E_err_Pa, gamma_err_J_m2) and the recorded
    correlation, κ from the public kappa_jkr_mindlin; it is not the fit's band."""
    g = fit_group(_experiments(6), ("c", "air"), 200, 2) | {"P_Hz_per_N_per_m": 2.3e-4}
    curve = jkr_curves([g], LOADS)
    half = (curve["kappa_hi_N_per_m"] - curve["kappa_lo_N_per_m"]).to_numpy() / 2
    assert g["t95"] == pytest.approx(stats.t.ppf(0.975, 5), rel=1e-9)  # 6 experiments
    sd = np.array([g["E_err_Pa"], g["gamma_err_J_m2"]])
    rho = g["E_gamma_corr"]
    cov = np.outer(sd, sd) * np.array([[1, rho], [rho, 1]])
    draws = np.random.default_rng(8).multivariate_normal([g["E_Pa"], g["gamma_J_m2"]], cov,
                                                         size=40_000)  # fmt: skip
    F = curve["normal_force_N"].to_numpy()
    kappa = kappa_jkr_mindlin(F[None, :], draws[:, :1], np.maximum(draws[:, 1:], 0), R, NU)
    lo, hi = np.percentile(kappa, [2.5, 97.5], axis=0)
    expected = g["t95"] / stats.norm.ppf(0.975) * (hi - lo) / 2
    np.testing.assert_allclose(half, expected, rtol=0.03)
    # The fit's own covariance would draw another band (here: errors from the points alone).
    fit_only = g | {"E_err_Pa": g["E_fit_err_Pa"], "gamma_err_J_m2": g["gamma_fit_err_J_m2"],
                    "E_gamma_corr": g["E_gamma_fit_corr"]}  # fmt: skip
    other = jkr_curves([fit_only], LOADS)
    other_half = (other["kappa_hi_N_per_m"] - other["kappa_lo_N_per_m"]).to_numpy() / 2
    assert not np.allclose(other_half, half, rtol=0.1)


def test_without_a_bootstrap_the_correlation_is_the_fits():
    """--bootstrap 0: Table 1 prints the fit's errors, and the correlation with them is the
    fit's."""
    g = fit_group(_experiments(4), ("c", "air"), 0, 1)
    assert g["error_method"].startswith("fit residuals")
    assert g["E_gamma_corr"] == g["E_gamma_fit_corr"]
    assert g["E_err_Pa"] == g["E_fit_err_Pa"]


def test_one_experiment_records_the_correlation_of_its_resampled_sweeps():
    """One experiment with repeated sweeps: E_gamma_corr is np.corrcoef over resamples of the
    sweeps within each load (the same seeded draws, load after load in order of appearance),
    each fitted here to its per-load means with the public least-squares fit."""
    rng = np.random.default_rng(4)
    F = np.repeat(LOADS_5, 4)  # 4 sweeps per load
    kappa = kappa_jkr_mindlin(F, E, GAMMA, R, NU) * (1 + 0.01 * rng.normal(size=F.size))
    sweeps = pd.DataFrame({"normal_force_N": F, "kappa_N_per_m": kappa})
    exp = sweeps.groupby("normal_force_N", as_index=False)["kappa_N_per_m"].mean()
    exp = exp.assign(experiment="x0", sphere_radius_m=R, poisson=NU)
    B, seed = 60, 9
    g = fit_group(exp, ("c", "air"), B, seed, sweeps=sweeps)
    assert g["error_method"].startswith("within one experiment")
    draws = np.random.default_rng(seed)
    picks = [draws.integers(0, 4, size=(B, 4)) for _ in LOADS_5]  # members of each load
    reps = []
    for b in range(B):
        means = [kappa[F == load][p[b]].mean() for load, p in zip(LOADS_5, picks, strict=True)]
        f = fit_jkr_mindlin(LOADS_5, np.array(means), R, NU)
        reps.append((f.values["E"], f.values["gamma"]))
    expected = np.corrcoef(np.array(reps).T)[0, 1]
    # (the fit's own correlation is -0.953 here: 0.005 tells the two apart)
    assert g["E_gamma_corr"] == pytest.approx(expected, abs=0.005)
