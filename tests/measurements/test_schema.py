"""The schema's rules are what the validator enforces: a bad value for every ruled column fails."""

import pandas as pd
import pytest

from contactres.measurements.schema import (
    GROUP_RESULTS,
    LOAD_RESULTS,
    SWEEP_RESULTS,
    SWEEP_TABLE,
)
from contactres.measurements.sweeps import validate_sweeps

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
