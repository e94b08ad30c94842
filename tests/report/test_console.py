"""What qcm analyze prints: values with errors, a dash (never nan) where a value is withheld."""

import math

import pytest
from click.testing import CliRunner

from contactres.cli import main
from contactres.report._console import DASH, plus_minus


@pytest.mark.parametrize(
    ("value", "err", "text"),
    [
        (59.7163, 0.5463, "59.72 ± 0.55"),
        (228.745, 5.72, "228.7 ± 5.7"),
        (1.0437, 0.0401, "1.044 ± 0.040"),
        (77.0, 12.3, "77 ± 12"),
        (1.5, math.nan, "1.5"),
        (math.nan, 0.1, DASH),
    ],
)
def test_value_with_error(value, err, text):
    assert plus_minus(value, err) == text


def test_area_in_mm2_prints_dashes_and_says_which_input(tmp_path):
    import pandas as pd

    from contactres.measurements._studies import example_study
    from contactres.measurements._synthetic import synthetic_sweeps

    raw = synthetic_sweeps(example_study(2), 1, constants=True)
    raw["area_m2"] = 25.0  # mm² typed into a m² column: refused when read (issue 27)
    path = tmp_path / "sweeps.csv"
    raw.to_csv(path, index=False)
    args = ["qcm", "analyze", str(path), "--out", str(tmp_path / "out"), "--no-figures"]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 2 and "looks like square millimetres" in r.stderr
    # A wrong area inside the plausible range (100 times too large) is found by the fit.
    raw["area_m2"] = 100 * 2.5e-5
    raw.to_csv(path, index=False)
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0
    assert "nan" not in r.stdout.lower() and DASH in r.stdout
    assert "E and γ withheld" in r.stderr and "check area_m2" in r.stderr
    summary = pd.read_json(tmp_path / "out" / "summary.json", typ="series")
    assert all(g["E_Pa"] is None for g in summary["groups"])
