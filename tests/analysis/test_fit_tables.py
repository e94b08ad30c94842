"""The registry is the engine: every registered sweep model is fitted through it and has its own
fit table in the results (``Results.fits``), keyed by its parameters' keys; the sweep table keeps
the named columns only."""

import numpy as np
import pytest

from contactres.analysis._models import MODULES, REGISTRY, SWEEP_FITS
from contactres.measurements.schema import SWEEP_RESULTS

PREFIXES = ("el_", "line_", "parabola_", "hinge_", "cm_", "sv_", "pl_")


@pytest.fixture(scope="module", params=[True, False], ids=["exact-loops", "closed-forms"])
def results(request, example_analysis):
    return example_analysis(exact_loop=request.param)


def test_one_module_per_model_and_one_registry_line_each():
    assert [m.MODEL.key for m in MODULES] == list(REGISTRY)
    assert [f.model for f in SWEEP_FITS] == [m.MODEL.key for m in MODULES if hasattr(m, "FIT")]
    assert len({f.source for f in SWEEP_FITS}) == len(SWEEP_FITS)


def test_every_fitted_model_has_a_table_keyed_by_its_parameters(results):
    exact = results.settings["exact_loop"]
    expected = {f.model for f in SWEEP_FITS if exact or not f.exact}
    assert set(results.fits) == expected
    for key, table in results.fits.items():
        assert list(table["sweep"]) == list(results.sweeps["sweep"])
        for p in REGISTRY[key].parameters:
            assert p.key in table.columns, f"{key}: no column {p.key!r}"
        assert {"rss_df", "rss_dgamma", "df0_err", "dgamma0_err"} <= set(table.columns)


def test_the_sweep_table_keeps_its_named_columns_only(results):
    columns = set(results.sweeps.columns)
    assert set(SWEEP_RESULTS.names) <= columns
    assert not [c for c in columns if c.startswith(PREFIXES)]


def test_the_elastic_table_holds_the_mean_of_each_sweep(results):
    # Against pandas' own means of the input points (no drift removed by default).
    means = results.table.data.groupby("sweep", sort=False)[["df_Hz", "dgamma_Hz"]].mean()
    table = results.fits["elastic"].set_index("sweep").loc[means.index]
    np.testing.assert_allclose(table["df0"], means["df_Hz"], rtol=1e-12)
    np.testing.assert_allclose(table["dgamma0"], means["dgamma_Hz"], rtol=1e-12, atol=1e-12)


def test_the_line_table_holds_the_least_squares_slope(results):
    # Against numpy's polynomial fit of degree 1 (another algorithm), on a few sweeps.
    table = results.fits["cattaneo-mindlin"].set_index("sweep")
    data = results.table.data
    for sweep in results.sweeps["sweep"].iloc[::50]:
        part = data[data["sweep"] == sweep]
        for channel, key in (("df_Hz", "df"), ("dgamma_Hz", "dgamma")):
            slope, offset = np.polyfit(part["amplitude_m"], part[channel], 1)
            assert table.loc[sweep, f"{key}_slope"] == pytest.approx(slope, rel=1e-8)
            assert table.loc[sweep, f"{key}0"] == pytest.approx(offset, rel=1e-8, abs=1e-9)


def test_a_sweep_takes_its_limits_from_the_fit_of_its_class(results):
    sw = results.sweeps
    sources = {
        "mean": "elastic",
        "line": "cattaneo-mindlin",
        "parabola": "savkoor",
        "plateau": "plateau",
        "cm-loop": "cattaneo-mindlin-loop",
        "savkoor-loop": "savkoor-loop",
        "plateau-loop": "plateau-loop",
    }
    for limits_from, model in sources.items():
        rows = (sw["limits_from"] == limits_from).to_numpy()
        if not rows.any():
            continue
        table = results.fits[model]
        for name in ("df0", "dgamma0"):
            np.testing.assert_array_equal(sw.loc[rows, f"{name}_Hz"], table.loc[rows, name])
