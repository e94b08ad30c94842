"""The resonance-curve fit of QCM admittance spectra against the Butterworth–van Dyke circuit.

The truth always comes from the generator (contactres.measurements._synthetic_spectra), which
evaluates the circuit R + iωL + 1/(iωC) in parallel with C0 through its impedance, never the
fit's own resonance curve; the parameters are the ones the spectra were generated with.
"""

import numpy as np
import pandas as pd
import pytest
from scipy.optimize import brentq

from contactres.measurements._spectra import COLUMNS, FLAGS, fit_resonances, resonance_curve
from contactres.measurements._synthetic_spectra import (
    bvd_admittance,
    bvd_circuit,
    bvd_parameters,
    synthetic_spectra,
)

N_SEEDS = 200  # repeated noise realisations (one spectrum each)


def fit(df: pd.DataFrame, with_b: bool = True, **kw) -> pd.DataFrame:
    return fit_resonances(
        df["spectrum"], df["frequency_Hz"], df["G_S"], df["B_S"] if with_b else None, **kw
    )


def assert_unbiased_and_calibrated(out: pd.DataFrame, f_r: float, gamma: float) -> None:
    """Mean within 3 standard errors of the truth; stated errors = observed scatter within 1.3."""
    assert (out["flags"] == "").all() and out["converged"].all()
    n = len(out)
    for col, err, truth in (("f_r_Hz", "f_r_err_Hz", f_r), ("gamma_Hz", "gamma_err_Hz", gamma)):
        scatter = out[col].std()
        assert abs(out[col].mean() - truth) < 3 * scatter / np.sqrt(n), col
        assert 1 / 1.3 < out[err].mean() / scatter < 1.3, col


# --- the circuit and the generator -------------------------------------------------------------


def test_circuit_round_trip_and_resonance_values():
    R, L, C = bvd_circuit(15e6, 450.0, 2e-3)
    assert R == pytest.approx(500.0)
    np.testing.assert_allclose(bvd_parameters(R, L, C), (15e6, 450.0, 2e-3), rtol=1e-12)
    y = bvd_admittance(15e6, 15e6, 450.0, 2e-3, c0=4e-12)
    assert y.real == pytest.approx(2e-3, rel=1e-9)  # G = 1/R at series resonance
    assert y.imag == pytest.approx(2 * np.pi * 15e6 * 4e-12, rel=1e-6)  # only ωC0 left


def test_generator_is_seeded_and_its_noise_has_the_stated_sd():
    kw = dict(f_r=np.full(50, 5e6), gamma=300.0, g_max=1e-3, noise=0.01, seed=3)
    a, b = synthetic_spectra(**kw), synthetic_spectra(**kw)
    pd.testing.assert_frame_equal(a, b)
    assert list(a.columns) == ["spectrum", "frequency_Hz", "G_S", "B_S"]
    assert a["spectrum"].nunique() == 50 and len(a) == 50 * 200
    clean = synthetic_spectra(**{**kw, "noise": 0.0})
    for col in ("G_S", "B_S"):
        assert np.std(a[col] - clean[col]) == pytest.approx(0.01 * 1e-3, rel=0.03)


# --- (a) accuracy at peak SNR 1000 --------------------------------------------------------------


def test_snr_1000_recovers_gamma_to_1e3_and_f_r_within_its_error():
    f_r = np.array([5e6, 5e6, 15e6, 15e6, 25e6, 35e6])
    q = np.array([1e4, 1e6, 3e4, 3e5, 1e5, 1e4])  # Q = f_r/(2Γ)
    gamma = f_r / (2 * q)
    g_max = np.array([1e-3, 5e-2, 2e-3, 1e-2, 3e-3, 1e-3])
    out = fit(synthetic_spectra(f_r, gamma, g_max, noise=1e-3, seed=1))
    assert (out["flags"] == "").all() and out["converged"].all()
    # 200 points over f_r ± 5Γ at SNR 1000: 1e-3 Γ is over two standard errors of Γ ...
    assert (out["gamma_err_Hz"] / gamma < 1e-3 / 2).all()
    # ... and the fitted Γ is within 1e-3 of the truth, f_r within 3 standard errors
    assert (np.abs(out["gamma_Hz"] / gamma - 1) < 1e-3).all()
    assert (np.abs(out["f_r_Hz"] - f_r) < 3 * out["f_r_err_Hz"]).all()
    np.testing.assert_allclose(out["g_max_S"], g_max, rtol=3e-3)


# --- (b) bias and error calibration over repeated noise -----------------------------------------


@pytest.mark.parametrize("q", [1e4, 1e6])
def test_unbiased_and_errors_match_scatter_over_200_noise_seeds(q):
    f_r, g_max = 15e6, 2e-3
    gamma = f_r / (2 * q)
    out = fit(synthetic_spectra(np.full(N_SEEDS, f_r), gamma, g_max, noise=1e-3, seed=7))
    assert_unbiased_and_calibrated(out, f_r, gamma)
    assert out["reduced_chi2"].mean() == pytest.approx(1.0, abs=0.05)


def test_noise_level_given_weights_and_reduced_chi2():
    f_r, gamma, g_max, sd = 5e6, 300.0, 1e-3, 1e-6
    out = fit(
        synthetic_spectra(np.full(N_SEEDS, f_r), gamma, g_max, noise=sd / g_max, seed=8), noise_S=sd
    )
    assert_unbiased_and_calibrated(out, f_r, gamma)
    assert out["reduced_chi2"].mean() == pytest.approx(1.0, abs=0.02)


# --- (c) phase, offset, slope, C0 and its drift -------------------------------------------------


def test_phase_offset_slope_and_c0_drift_do_not_bias():
    f_r, gamma, g_max = 5e6, 400.0, 1e-3
    df = synthetic_spectra(
        np.full(N_SEEDS, f_r),
        gamma,
        g_max,
        noise=1e-3,
        phase=1.2,
        offset=(3 + 2j) * 1e-4,
        baseline_slope=(1 - 0.3j) * 0.5 * g_max / (10 * gamma),  # 0.5 G_max across the span
        c0=5e-12,  # ωC0 = 0.16 G_max
        c0_drift=5e-14,  # 1 % of C0 during each sweep
        seed=9,
    )
    out = fit(df)
    assert_unbiased_and_calibrated(out, f_r, gamma)
    assert out["phase_rad"].mean() == pytest.approx(1.2, abs=3 * out["phase_rad"].std())
    assert out["g_max_S"].mean() == pytest.approx(g_max, rel=1e-3)


def test_large_phase_and_an_off_centre_narrow_span():
    f_r, gamma = 5e6, 400.0
    df = synthetic_spectra(
        np.full(N_SEEDS, f_r), gamma, 1e-3, phase=0.9 * np.pi, span=6.0, centre=1.0, seed=10
    )  # f_r − 2Γ ... f_r + 4Γ
    assert_unbiased_and_calibrated(fit(df), f_r, gamma)


# --- (d) G alone ----------------------------------------------------------------------------------


def test_g_alone_is_unbiased_and_calibrated():
    f_r, gamma = 25e6, 1250.0
    df = synthetic_spectra(np.full(N_SEEDS, f_r), gamma, 3e-3, noise=1e-3, seed=11)
    out = fit(df, with_b=False)
    assert_unbiased_and_calibrated(out, f_r, gamma)
    assert out["phase_rad"].isna().all()  # φ is not fitted from G alone


def test_g_alone_and_g_with_b_in_one_call():
    df = synthetic_spectra([5e6, 6e6, 7e6], [300.0, 350.0, 400.0], 1e-3, seed=12)
    df.loc[df["spectrum"] == "s1", "B_S"] = np.nan  # s1 recorded G only
    out = fit(df)
    assert (out["flags"] == "").all()
    assert out["phase_rad"].isna().tolist() == [False, True, False]
    alone = fit(df[df["spectrum"] == "s1"], with_b=False)
    assert out.loc[1, "gamma_Hz"] == pytest.approx(alone.loc[0, "gamma_Hz"], rel=1e-6)
    assert (np.abs(out["gamma_Hz"] - [300.0, 350.0, 400.0]) < 4 * out["gamma_err_Hz"]).all()


# --- (e) bad spectra ----------------------------------------------------------------------------


def tagged(name: str, df: pd.DataFrame) -> pd.DataFrame:
    return df.assign(spectrum=name + "-" + df["spectrum"])


def test_each_bad_spectrum_gets_its_flag_and_nan_and_leaves_the_others_alone():
    good = synthetic_spectra([5e6, 5.1e6], [300.0, 500.0], [1e-3, 2e-3], seed=1)
    one_spectrum = dict(f_r=5e6, gamma=300.0, g_max=1e-3)
    noisy = synthetic_spectra(**one_spectrum, seed=2)
    noisy["G_S"], noisy["B_S"] = np.random.default_rng(2).normal(1e-4, 1e-6, (2, 200))
    nan = synthetic_spectra(**one_spectrum, seed=3)
    nan.loc[50, "G_S"] = np.nan
    dup = synthetic_spectra(**one_spectrum, seed=4)
    dup.loc[100, "frequency_Hz"] = dup.loc[99, "frequency_Hz"]
    inf = synthetic_spectra(**one_spectrum, seed=10)
    inf.loc[120, "B_S"] = np.inf
    bad = {
        "no-peak": noisy,
        "peak-not-covered": synthetic_spectra(**one_spectrum, centre=5.0, seed=5),  # at the edge
        "peak-outside": synthetic_spectra(**one_spectrum, centre=20.0, seed=6),
        "half-span": synthetic_spectra(**one_spectrum, span=1.0, seed=7),  # f_r ± Γ/2 only
        "bad-values": nan,
        "too-few-points": synthetic_spectra(**one_spectrum, n_points=1, seed=8),
        "sparse": synthetic_spectra(**one_spectrum, span=200.0, seed=9),  # 1 point per Γ
        "frequencies-not-increasing": dup,
        "inf": inf,
    }
    parts = [tagged("good", good)] + [tagged(k, v) for k, v in bad.items()]
    out = fit(pd.concat(parts, ignore_index=True)).set_index("spectrum")
    flags = out["flags"].str.split(";")
    expected = {
        "no-peak": "no-peak",
        "peak-not-covered": "peak-not-covered",
        "peak-outside": "peak-not-covered",
        "half-span": "peak-not-covered",
        "bad-values": "bad-values",
        "too-few-points": "too-few-points",
        "sparse": "too-few-points",
        "frequencies-not-increasing": "frequencies-not-increasing",
        "inf": "bad-values",
    }
    for name, flag in expected.items():
        row = f"{name}-s0"
        assert flag in flags[row], (name, out.loc[row, "flags"])
        assert out.loc[row, ["f_r_Hz", "gamma_Hz", "f_r_err_Hz", "gamma_err_Hz"]].isna().all()
    assert set(f for fl in flags for f in fl if f) <= set(FLAGS)
    alone = fit(good).set_index("spectrum")
    for s in ("s0", "s1"):
        row = out.loc[f"good-{s}"]
        assert row["flags"] == "" and row["converged"]
        for col in ("f_r_Hz", "gamma_Hz"):  # the same fit, whatever shares the call
            assert (
                abs(row[col] - alone.loc[s, col])
                < 0.1 * alone.loc[s, col.replace("_Hz", "_err_Hz")]
            )


def test_pure_noise_is_never_reported_as_a_resonance():
    rng = np.random.default_rng(4)
    n, m = 300, 200
    f = np.tile(5e6 + np.linspace(-2500.0, 2500.0, m), n)
    g, b = rng.normal(0.0, 1e-6, (2, n * m)) + np.array([[3e-4], [2e-4]])
    out = fit_resonances(np.repeat(np.arange(n), m), f, g, b)
    assert out["f_r_Hz"].isna().all() and (out["flags"] != "").all()


# --- (f) the BVD half width and the Lorentzian --------------------------------------------------


@pytest.mark.parametrize("q", [1e4, 1e5, 1e6])
def test_bvd_half_width_is_gamma_and_the_lorentzian_is_close(q):
    f_r, g_max = 5e6, 1e-3
    gamma = f_r / (2 * q)

    def half(f):
        return bvd_admittance(f, f_r, gamma, g_max).real - g_max / 2

    lo = brentq(half, f_r - 3 * gamma, f_r, xtol=1e-12, rtol=1e-15)
    hi = brentq(half, f_r, f_r + 3 * gamma, xtol=1e-12, rtol=1e-15)
    # The circuit's G: full width at half height exactly 2Γ, midpoint at √(f_r² + Γ²).
    assert (hi - lo) / 2 == pytest.approx(gamma, rel=1e-9)
    assert (hi + lo) / 2 - f_r == pytest.approx(np.sqrt(f_r**2 + gamma**2) - f_r, abs=1e-7 * gamma)
    df = synthetic_spectra(f_r, gamma, g_max, noise=0.0)
    eps = 1 / (4 * q)  # = Γ/(2 f_r)
    for with_b in (True, False):
        exact = fit(df, with_b).iloc[0]
        assert exact["gamma_Hz"] == pytest.approx(gamma, rel=1e-9)
        assert exact["f_r_Hz"] == pytest.approx(f_r, abs=1e-9 * gamma + 1e-8)
        lor = fit(df, with_b, model="lorentzian").iloc[0]
        assert lor["flags"] == "" and lor["converged"]
        # Γ to second order in ε (~ε² = 1/(16 Q²)), f_r within εΓ = Γ/(4Q); the last terms
        # are the rounding floors (the circuit loses log10 Q digits; 1e-9 Hz is 2e-16 f_r).
        assert abs(lor["gamma_Hz"] / gamma - 1) < 1 / q**2 + 1e-9
        assert abs(lor["f_r_Hz"] - f_r) <= eps * gamma + 1e-8
        if with_b:  # G and B: the real part of the complex pole, √(f_r² − Γ²) ≈ f_r − εΓ
            pole = np.sqrt(f_r**2 - gamma**2)
            assert lor["f_r_Hz"] == pytest.approx(pole, abs=1e-2 * eps * gamma + 1e-8)
    curve = resonance_curve(df["frequency_Hz"], f_r, gamma, g_max)
    np.testing.assert_allclose(curve, df["G_S"] + 1j * df["B_S"], rtol=0, atol=1e-9 * g_max)


# --- the call ------------------------------------------------------------------------------------


def test_columns_order_of_first_appearance_and_mixed_grids():
    a = synthetic_spectra([5e6, 5e6], 300.0, 1e-3, n_points=120, seed=1)
    b = synthetic_spectra(15e6, 900.0, 2e-3, n_points=301, span=14.0, seed=2).assign(spectrum="x")
    df = pd.concat([b, a], ignore_index=True).sample(frac=1.0, random_state=0)
    df = df.sort_values("frequency_Hz", kind="stable")  # the spectra's rows interleave
    out = fit(df)
    assert list(out.columns) == list(COLUMNS)
    assert out["spectrum"].tolist() == list(df["spectrum"].drop_duplicates())
    assert out["n_points"].tolist() == [120, 120, 301]
    assert (out["flags"] == "").all()
    assert out["converged"].dtype == bool and out["n_points"].dtype.kind == "i"
    assert len(fit_resonances([], [], [])) == 0


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (dict(frequency_Hz=np.ones(3)), "lengths must agree"),
        (dict(G_S=["a"] * 4), "real numbers"),
        (dict(G_S=np.ones(4) + 1j), "real numbers"),
        (dict(B_S=np.ones((4, 1))), "1-D"),
        (dict(spectrum=["a", None, "a", "a"]), "missing ids"),
        (dict(noise_S=0.0), "noise_S"),
        (dict(model="gauss"), "model"),
    ],
)
def test_bad_arguments_raise_one_line_value_errors(change, message):
    kw = dict(spectrum=["a"] * 4, frequency_Hz=[1.0, 2.0, 3.0, 4.0], G_S=np.ones(4), B_S=None)
    kw.update(change)
    with pytest.raises(ValueError, match=message) as err:
        fit_resonances(**kw)
    assert "\n" not in str(err.value)
