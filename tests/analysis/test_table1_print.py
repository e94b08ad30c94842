"""``print(res.table1())`` shows E and γ at pandas' default width (issue 30, review M3)."""

from __future__ import annotations

import pandas as pd

from contactres.analysis import Results

ERRORS = "fit residuals (Jacobian), bootstrap off (--bootstrap 0)"  # the longest text


def _group(configuration, medium, E, gamma):
    return {
        "configuration": configuration,
        "medium": medium,
        "E_Pa": E,
        "E_err_Pa": 1.25e9,
        "gamma_J_m2": gamma,
        "gamma_err_J_m2": 0.004,
        "n_experiments": 3,
        "n_sweeps_used": 40,
        "error_method": ERRORS,
        "t95": 2.0738,
        "checks": [],
        "note": "",
    }


def test_table1_printed_at_width_80_shows_e_and_gamma(monkeypatch):
    # pandas' defaults in a terminal 80 characters wide: columns fitted to the width
    monkeypatch.setenv("COLUMNS", "80")
    groups = [
        _group("SiO2_2.2mm", "air", 71.25e9, 0.0567),
        _group("SiO2_1.2mm", "water", 6e10, 0.017),
    ]
    table = Results(pd.DataFrame(), pd.DataFrame(), pd.DataFrame(), groups, {}, "9").table1()
    with pd.option_context("display.width", 80, "display.max_columns", 0):
        text = str(table)
    assert max(len(line) for line in text.splitlines()) <= 80
    for column in ("E_GPa", "E_err_GPa", "gamma_mJ_m2", "gamma_err_mJ_m2", "note", "errors"):
        assert column in text
    assert "71.25" in text and "56.7" in text and "..." not in text.splitlines()[0]
    # the numbers come first, the long text last; the table is still a plain DataFrame
    assert list(table.columns[:6]) == [
        "configuration", "medium", "E_GPa", "E_err_GPa", "gamma_mJ_m2", "gamma_err_mJ_m2"
    ]  # fmt: skip
    assert table.columns[-1] == "errors" and isinstance(table, pd.DataFrame)
    assert type(table[["E_GPa"]]) is pd.DataFrame
