"""The jobs that read a table (afm invert, rum invert, qcm spectra) through their Python API."""

import numpy as np
import pandas as pd
import pytest

from contactres.jobs import afm_invert, qcm_spectra, rum_invert

DATA = "src/contactres/data/"


def test_rum_job_lumped_rows_follow_the_oscillator_law():
    result = rum_invert.run(DATA + "example_rum.csv")
    given = pd.read_csv(DATA + "example_rum.csv")
    assert set(given.columns) <= set(result.input_columns)  # read: every column known
    lumped = result.table["rum_model"] == "lumped"
    rows = given[lumped.to_numpy()]
    # (fc/f0)² = 1 + k*/K_eff, solved for k* here.
    expected = rows["K_eff_N_per_m"] * ((rows["fc_Hz"] / rows["f0_Hz"]) ** 2 - 1)
    assert result.table.loc[lumped, "k_star_N_per_m"].to_numpy() == pytest.approx(expected, 1e-9)


def test_afm_job_reports_progress_and_keeps_the_input_columns():
    lines = []
    result = afm_invert.run(DATA + "example_afm.csv", afm_invert.Settings(), lines.append)
    assert lines[0] == "reading example_afm.csv" and lines[1].startswith("inverting")
    given = pd.read_csv(DATA + "example_afm.csv")
    assert set(given.columns) <= set(result.input_columns)  # read: every column known
    assert set(given.columns) <= set(result.table.columns)  # copied to the output
    assert np.isfinite(result.table["k_star_N_per_m"]).any()


def test_spectra_job_gives_the_sweep_table_bound_to_its_schema():
    from contactres.measurements.schema import SPECTRA_SWEEPS, SWEEP_TABLE

    result = qcm_spectra.run(DATA + "example_spectra.csv")
    frame, schema = result.tables()["sweeps"]
    assert schema is SPECTRA_SWEEPS
    assert set(SWEEP_TABLE.required) <= set(frame.columns)
    assert "quality" not in frame.columns
    assert len(result.fits) == pd.read_csv(DATA + "example_spectra.csv")["spectrum"].nunique()
