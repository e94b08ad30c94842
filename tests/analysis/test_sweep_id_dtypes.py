"""A hand-built :class:`~contactres.SweepTable` whose sweep ids are objects or categories (not
``str``, as :func:`~contactres.validate_sweeps` makes them) analyses as the validated one: the
step that puts the sweeps' labels beside their fits compares the ids by value (review R26c:
a dtype comparison raised an internal error there)."""

from __future__ import annotations

import pandas as pd
import pytest

from contactres.analysis import AnalysisSettings, analyze
from contactres.examples import example_path
from contactres.measurements import SweepTable, read_sweeps

SETTINGS = AnalysisSettings(bootstrap=0, workers=1)


@pytest.fixture(scope="module")
def one_group():
    """Two experiments of the example's first group, and their analysis."""
    t = read_sweeps(example_path("example_sweeps.csv"))
    d = t.data[t.data["configuration"] == t.data["configuration"].iat[0]]
    d = d[d["experiment"].isin(d["experiment"].unique()[:2])].reset_index(drop=True)
    table = SweepTable(data=d)
    return table, analyze(table, settings=SETTINGS).sweeps


@pytest.mark.parametrize("dtype", [object, "category"])
def test_sweep_ids_of_another_dtype_give_the_same_results(one_group, dtype):
    one_group, want = one_group
    other = SweepTable(data=one_group.data.assign(sweep=one_group.data["sweep"].astype(dtype)))
    got = analyze(other, settings=SETTINGS).sweeps
    pd.testing.assert_frame_equal(
        got.drop(columns="sweep"), want.drop(columns="sweep"), check_exact=True
    )
    assert list(got["sweep"].astype(str)) == list(want["sweep"])
