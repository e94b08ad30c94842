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
