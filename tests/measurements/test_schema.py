"""The schema's rules are what the validator enforces: a bad value for every ruled column fails."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from contactres.errors import ContactresInputError
from contactres.measurements._resonances import validate_resonance_table
from contactres.measurements._spectra_table import validate_spectra
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements.readers._delimited import load
from contactres.measurements.schema import (
    AFM_TABLE,
    GROUP_RESULTS,
    LOAD_RESULTS,
    RUM_TABLE,
    SPECTRA_TABLE,
    SWEEP_RESULTS,
    SWEEP_TABLE,
)

# One value that breaks each rule of the schema (column -> bad value). A new rule needs a line
# here, so that no rule is written in the schema without the validator enforcing it.
BREAKS = {
    "amplitude_m": [-1e-9, 2e-6],
    "normal_force_N": [0.0],
    "ramp": [0, 1.5],
    "fundamental_Hz": [0.0],
    "overtone": [4],
    "area_m2": [0.0],
    "n_contacts": [0, 2.5],
    "sphere_radius_m": [-1e-3],
    "poisson": [0.5, -1.0],
    "time_s": [float("inf"), float("nan")],
}


def good_frame() -> pd.DataFrame:
    rows = []
    for k in range(6):
        u = 2e-9 * (k + 1)
        rows.append(
            dict(
                sweep="s",
                ramp=2,
                normal_force_N=2e-3,
                amplitude_m=u,
                df_Hz=60.0 - 1e8 * u,
                dgamma_Hz=6.0 + 0.5e8 * u,
                fundamental_Hz=5e6,
                overtone=3,
                area_m2=2.5e-5,
                n_contacts=3,
                sphere_radius_m=1e-3,
                poisson=0.17,
                time_s=10.0 * k,
            )
        )
    return pd.DataFrame(rows)


def test_every_rule_is_covered_here():
    assert set(BREAKS) == {c.name for c in SWEEP_TABLE.columns if c.rule}


@pytest.mark.parametrize(("column", "bad"), [(c, v) for c, vs in BREAKS.items() for v in vs])
def test_a_value_breaking_the_rule_is_refused(column, bad):
    validate_sweeps(good_frame())  # the frame itself is fine
    frame = good_frame()
    frame[column] = frame[column].astype(object)
    frame.loc[3, column] = bad
    with pytest.raises(ValueError, match=column):
        validate_sweeps(frame)


@pytest.mark.parametrize("schema", [SWEEP_TABLE, SWEEP_RESULTS, LOAD_RESULTS, GROUP_RESULTS])
def test_markdown_rows_have_the_header_cells(schema):
    lines = schema.markdown(with_required=schema is SWEEP_TABLE).splitlines()
    cells = lines[0].count("|")
    assert all(line.count("|") == cells for line in lines), "a '|' inside a cell breaks the table"
    names = [c.name for c in schema.columns]
    assert len(names) == len(set(names))


# ---- every shown rule of the other input tables is run by their readers -----------------------

DATA = Path(__file__).resolve().parents[2] / "src" / "contactres" / "data"
# Values to break a rule with: the first that the rule refuses is written into one cell.
CANDIDATES = ("-1e30", "1e30", "0", "0.25", "2.5", "4", "inf")


def _breaking(rule) -> str:
    return next(c for c in CANDIDATES if not rule.accepts(np.array([float(c)]))[0])


def _shown_rules(table):
    return [(c.name, r) for c in table.columns for r in c.rules if r.shown]


@pytest.mark.parametrize(
    ("table", "example"),
    [(AFM_TABLE, "example_afm.csv"), (RUM_TABLE, "example_rum.csv")],
    ids=["afm", "rum"],
)
def test_every_resonance_table_rule_is_run_by_the_reader(table, example):
    pairs = _shown_rules(table)
    assert {name for name, _ in pairs} == set(table.names)  # every column has a rule
    for name, rule in pairs:
        raw = load(DATA / example)
        bad = _breaking(rule)
        raw[name] = raw[name] if name in raw else ""
        raw.loc[0, name] = bad
        with pytest.raises(ContactresInputError) as err:
            validate_resonance_table(raw, table, "x.csv")
        assert str(err.value).startswith(f"x.csv, line 2, column {name!r}: value {bad!r}: ")
        assert rule.text in str(err.value)


def test_every_spectra_label_rule_is_run_by_the_reader():
    pairs = [(n, r) for n, r in _shown_rules(SPECTRA_TABLE) if n != "frequency_Hz"]
    assert {n for n, _ in pairs} == {"overtone", "drive_voltage_V", "time_s", "ramp",
                                     "normal_force_N"}  # fmt: skip
    for name, rule in pairs:
        raw = load(DATA / "example_spectra.csv")
        raw[name] = raw[name] if name in raw else ""  # a reader gives blank cells, not NaN
        first = raw["spectrum"] == raw["spectrum"].iloc[0]
        raw.loc[first, name] = _breaking(rule)
        with pytest.raises(ContactresInputError) as err:
            validate_spectra(raw, "x.csv")
        assert str(err.value).startswith(f"x.csv, line 2, column {name!r}")
        assert str(err.value).endswith(rule.message)


def test_rules_in_words_match_their_checks():
    """A few rules against values decided here: the boundaries of the intervals."""
    q = AFM_TABLE.column("Q1").rules[0]  # Q > 1/2: below it no resonance peak
    assert list(q.accepts(np.array([0.5, 0.51, np.inf]))) == [False, True, True]
    r = AFM_TABLE.column("tip_position").rules[0]  # (0, 1]
    assert list(r.accepts(np.array([0.0, 1e-9, 1.0, 1.0 + 1e-9]))) == [False, True, True, False]
    odd = SPECTRA_TABLE.column("overtone").rules[0]
    assert list(odd.accepts(np.array([1.0, 2.0, 3.0, 3.5, -1.0]))) == [True, False, True, False,
                                                                          False]  # fmt: skip
    ramp = SWEEP_TABLE.column("ramp").rules[-1]
    assert list(ramp.accepts(np.array([0.0, 1.0, 1.5, 7.0]))) == [False, True, False, True]
