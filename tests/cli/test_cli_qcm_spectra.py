"""Tests of ``contactres qcm spectra`` and of ``qcm analyze`` on spectra (issue 14)."""

from importlib.resources import files

import pandas as pd
import pytest
from cli_checks import invoke, one_line_error, option_names, run

SPECTRA = str(files("contactres") / "data" / "example_spectra.csv")


def test_bundled_spectra_to_sweeps_and_fits(tmp_path):
    """The bundled example: every measured spectrum gives a row with Δf, ΔΓ, their errors and
    u0; the conventions are printed; the input is not modified."""
    before = (files("contactres") / "data" / "example_spectra.csv").read_bytes()
    out, fits = tmp_path / "sweeps.csv", tmp_path / "fits.csv"
    r = run("qcm", "spectra", SPECTRA, "--out", out, "--fits", fits)
    assert r.exit_code == 0, r.output
    rows, fitted = pd.read_csv(out), pd.read_csv(fits)
    assert len(fitted) == 158 and len(rows) == 156
    for col in ("sweep", "amplitude_m", "df_Hz", "dgamma_Hz", "df_err_Hz", "dgamma_err_Hz"):
        assert rows[col].notna().all(), col
    assert (rows["df_err_Hz"] > 0).all() and (rows["amplitude_m"] <= 1.1e-8).all()
    assert "not divided by n" in r.stdout and "4 d26 Q U" in r.stdout
    assert (files("contactres") / "data" / "example_spectra.csv").read_bytes() == before


def test_analyze_reads_spectra_directly(tmp_path):
    r = run("qcm", "analyze", SPECTRA, "--out", tmp_path / "o", "--no-figures", "--bootstrap", 0)
    assert r.exit_code == 0, r.output
    loads = pd.read_csv(tmp_path / "o" / "loads.csv")
    assert len(loads) == 6 and (loads["kappa_N_per_m_mean"] > 0).all()


def test_calibration_replaces_the_formula(tmp_path):
    out = tmp_path / "s.csv"
    r = run("qcm", "spectra", SPECTRA, "--out", out, "--calibration", 2e-9)
    assert r.exit_code == 0, r.output
    rows = pd.read_csv(out)
    assert rows["amplitude_m"].to_numpy() == pytest.approx(
        2e-9 * rows["drive_voltage_V"].to_numpy(), rel=1e-9
    )


BASE = {"--out": "OUT"}
BAD = [
    ("--out", "/nonexistent/folder/s.csv"),
    ("--fits", SPECTRA),
    ("--reference", "nope"),
    ("--layout", "XY"),
    ("--reference-impedance", "-5"),
    ("--voltage", "peak"),
    ("--d26", "3.3"),
    ("--calibration", "0"),
    ("--format", "xml"),
]


def test_every_option_has_a_bad_input_case():
    from contactres.cli.qcm_spectra import spectra_command

    assert option_names(spectra_command) - {"spectra"} == {o for o, _ in BAD}


@pytest.mark.parametrize("option, value", BAD, ids=[o for o, _ in BAD])
def test_each_option_refuses_bad_input_in_one_line(tmp_path, option, value):
    base = {"--out": str(tmp_path / "s.csv")}
    r = invoke(["qcm", "spectra", SPECTRA], base, option, value)
    one_line_error(r)


def test_bad_spectra_files_in_one_line(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("spectrum,frequency_Hz,G_S\ns,1e6,nan\n")
    one_line_error(run("qcm", "spectra", bad, "--out", tmp_path / "s.csv"), "G_S", "finite")
    one_line_error(run("qcm", "spectra", tmp_path / "missing.csv", "--out", tmp_path / "s.csv"))
