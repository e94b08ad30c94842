"""The chain spectra -> resonance fits -> shifts and amplitudes -> analysis (issue 14).

The truth is a synthetic sweep study (the package's forward model of paper 2); its spectra are
generated from it (BVD resonator, SNR 1000 at the reference); the chain must give back the
shifts within their stated errors, the amplitudes, and E, γ and μ as the analysis of the exact
shifts does.
"""

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import analyze
from contactres.measurements._shifts import read_spectra_sweeps, sweeps_from_spectra
from contactres.measurements._spectra import fit_resonances
from contactres.measurements._spectra_table import read_spectra
from contactres.measurements._studies import EXAMPLE_SEED, example_study
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import synthetic_sweeps
from contactres.measurements._synthetic_spectra import spectra_from_sweeps


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    sw = synthetic_sweeps(example_study(2), EXAMPLE_SEED, constants=True)
    sw = sw[(sw.configuration == "SiO2_1.2mm") & (sw.medium == "air")].reset_index(drop=True)
    path = tmp_path_factory.mktemp("chain") / "spectra.csv"
    spectra_from_sweeps(sw, n_references=4, seed=3).to_csv(path, index=False, float_format="%.12g")
    return sw, path


@pytest.fixture(scope="module")
def chain(study):
    return read_spectra_sweeps(study[1])


def test_shifts_within_their_stated_errors(study, chain):
    """(Δf_chain − Δf_true)/σ: mean ~0 and standard deviation ~1 over the 624 spectra (the
    reference's error is shared by all, so the mean is tested against it, not against 0)."""
    sw, (_, rows, _, left_out) = study[0], chain
    assert not left_out
    for col, err in (("df_Hz", "df_err_Hz"), ("dgamma_Hz", "dgamma_err_Hz")):
        z = (rows[col].to_numpy() - sw[col].to_numpy()) / rows[err].to_numpy()
        assert 0.7 < np.std(z) < 1.3, (col, np.std(z))
        assert abs(np.mean(z)) < 3


def test_amplitudes_follow_the_drive_voltage(study, chain):
    """u0 back from U through Q of each fitted spectrum: to the relative error of Γ (< 1 %)."""
    sw, rows = study[0], chain[1]
    assert np.max(np.abs(rows["amplitude_m"].to_numpy() / sw["amplitude_m"].to_numpy() - 1)) < 0.01


def test_analysis_from_spectra_matches_analysis_from_exact_shifts(study, chain):
    """E and γ within a fifth of their standard errors of the exact-shift analysis, the
    per-load friction coefficients (loop fit) within 5 %."""
    exact = analyze(validate_sweeps(study[0], constants={}))
    from_spectra = analyze(chain[0])
    a, b = exact.table1().iloc[0], from_spectra.table1().iloc[0]
    assert abs(b["E_GPa"] - a["E_GPa"]) < 0.2 * a["E_err_GPa"]
    assert abs(b["gamma_mJ_m2"] - a["gamma_mJ_m2"]) < 0.2 * a["gamma_err_mJ_m2"]
    mu_a = exact.loads["mu_fit_median"].to_numpy()
    mu_b = from_spectra.loads["mu_fit_median"].to_numpy()
    assert np.nanmax(np.abs(mu_b / mu_a - 1)) < 0.05


def _first_sweep(path) -> pd.DataFrame:
    """The study's first sweep and the reference spectra of its experiment, as text: the errors
    below concern the references and the drive, so they need not fit all 632 spectra."""
    frame = pd.read_csv(path, keep_default_na=False, dtype=str)
    measured = frame[frame["reference"] == "False"]
    experiment, sweep = measured[["experiment", "sweep"]].iloc[0]
    keep = (frame["experiment"] == experiment) & (frame["reference"] == "True")
    return frame[keep | (frame["sweep"] == sweep)]


def _table(path, **change):
    frame = _first_sweep(path)
    for col, (mask_col, value) in change.items():
        frame.loc[frame[mask_col] == "True", col] = value
    return frame


@pytest.mark.parametrize(
    "edit, words",
    [
        ({"reference": ("reference", "False")}, ["no reference spectrum"]),
        ({"overtone": ("reference", "5")}, ["no usable reference", "overtone 3"]),
    ],
)
def test_missing_references_are_named(study, tmp_path, edit, words):
    path = tmp_path / "bad.csv"
    _table(study[1], **edit).to_csv(path, index=False)
    with pytest.raises(ValueError) as info:
        read_spectra_sweeps(path)
    for w in words:
        assert w in str(info.value)


def test_missing_drive_voltage_and_unknown_reference_ids(study, tmp_path):
    frame = _first_sweep(study[1])
    frame.loc[frame["spectrum"] == frame["spectrum"].iloc[-1], "drive_voltage_V"] = ""
    path = tmp_path / "nov.csv"
    frame.to_csv(path, index=False)
    table = read_spectra(path)
    p = table.points
    fits = fit_resonances(p["spectrum"], p["frequency_Hz"], p["G_S"], p["B_S"])
    with pytest.raises(ValueError, match="drive voltage"):
        sweeps_from_spectra(table, fits)
    # a calibration factor replaces the formula: then no voltage is needed... for the others
    with pytest.raises(ValueError, match="no spectrum with id"):
        sweeps_from_spectra(table, fits, reference=["nope"])
