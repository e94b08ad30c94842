"""Results print as a short summary (counts and Table 1) and render in notebooks, escaped."""

from __future__ import annotations

import math

import pandas as pd

from contactres.analysis import Results


def _group(configuration, medium, E, gamma, checks=(), note=""):
    return {
        "configuration": configuration,
        "medium": medium,
        "E_Pa": E,
        "E_err_Pa": 1.25e9,
        "gamma_J_m2": gamma,
        "gamma_err_J_m2": 0.004,
        "n_experiments": 3,
        "n_sweeps_used": 40,
        "checks": list(checks),
        "note": note,
    }


def _results(groups, n_sweeps=100, n_used=70):
    sweeps = pd.DataFrame({"sweep": range(n_sweeps), "used": [i < n_used for i in range(n_sweeps)]})
    loads = pd.DataFrame({"normal_force_N": [1e-3, 2e-3, 4e-3]})
    return Results(sweeps, loads, pd.DataFrame(), groups, {}, "9.9.9")


def test_repr_is_a_summary_with_counts_and_table_1():
    withheld = _group("PMMA", "water", math.nan, math.nan, ("E-at-bound",), "check sphere_radius_m")
    res = _results([_group("SiO2_2.2mm", "air", 71.23e9, 0.0567), withheld])
    text = repr(res)
    lines = text.splitlines()
    assert lines[0] == (
        "Results (contactres 9.9.9): 100 sweeps (70 used), 3 loads, 2 configuration/medium groups"
    )
    assert (
        "SiO2_2.2mm, air: E = 71.2 ± 1.2 GPa, γ = 56.7 ± 4 mJ/m² (3 experiments, 40 sweeps)"
        in (lines[1])
    )
    assert "PMMA, water: E and γ withheld (E-at-bound): check sphere_radius_m" in lines[2]
    assert "nan" not in text.lower() and len(text) < 600
    # the dataclass' own repr (every table in full) is not used
    assert "DataFrame" not in text and "u_max_m" not in text


def test_repr_html_escapes_labels():
    res = _results([_group("<b>x</b>", "a&b", 70e9, 0.05)])
    page = res._repr_html_()
    assert "&lt;b&gt;x&lt;/b&gt;" in page and "a&amp;b" in page and "<b>x</b>" not in page
    assert "100 sweeps (70 used)" in page and "E = 70 ± 1.2 GPa" in page


def test_a_coated_analysis_says_so_in_its_summary():
    res = _results([_group("SiO2_2.2mm", "air", 71.23e9, 0.0567)])
    coated = Results(
        res.sweeps,
        res.loads,
        res.experiments,
        res.groups,
        {"coating": {"label": "PMMA 250 nm"}},
        "9.9.9",
    )
    assert "fitted on the coated plate (PMMA 250 nm)" in repr(coated).splitlines()[0]
    assert "PMMA 250 nm" in coated._repr_html_() and "coated" not in repr(res)


# ``print(res.table1())`` shows E and γ at pandas' default width (issue 30, review M3).
def test_table1_printed_at_width_80_shows_e_and_gamma(monkeypatch):
    # pandas' defaults in a terminal 80 characters wide: columns fitted to the width
    monkeypatch.setenv("COLUMNS", "80")
    # the longest errors text, and t95 of a few repeats, as a group of the analysis has them
    errors = "fit residuals (Jacobian), bootstrap off (--bootstrap 0)"
    wide = {"error_method": errors, "t95": 2.0738}
    groups = [
        {**_group("SiO2_2.2mm", "air", 71.25e9, 0.0567), **wide},
        {**_group("SiO2_1.2mm", "water", 6e10, 0.017), **wide},
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
