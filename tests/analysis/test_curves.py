"""The points and fitted curves the analysis hands to the report (``Results.points``,
``Results.curves``), against the input table and the registered model of each sweep."""

import warnings
from importlib.resources import files

import numpy as np
import pytest

import contactres
from contactres.analysis._curves import CURVE_GRIDS, sweep_rows
from contactres.analysis._models import REGISTRY, model_curves

LOOPS = {
    "cm-loop": "cattaneo-mindlin-loop",
    "savkoor-loop": "savkoor-loop",
    "plateau-loop": "plateau-loop",
}


@pytest.fixture(scope="module")
def results():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        table = contactres.read_sweeps(files("contactres") / "data" / "example_sweeps.csv")
        return contactres.analyze(table, settings=contactres.AnalysisSettings(bootstrap=0))


def test_the_points_are_the_input_points_of_each_sweep(results):
    # No drift removed: the points fitted are the file's, amplitudes ascending in each sweep.
    data = results.table.data
    points = results.points
    assert len(points) == len(data)
    rows = sweep_rows(points)
    assert list(rows) == list(data["sweep"].drop_duplicates())
    for sweep, part in data.groupby("sweep", sort=False):
        part = part.sort_values("amplitude_m", kind="stable")
        got = points.iloc[rows[sweep]]
        for mine, given in (("amplitude_m", "amplitude_m"), ("df_Hz", "df_Hz"),
                            ("dgamma_Hz", "dgamma_Hz")):  # fmt: skip
            np.testing.assert_array_equal(got[mine].to_numpy(), part[given].to_numpy())


def test_every_sweep_has_its_model_on_each_grid(results):
    # Each curve is the registered function of the sweep's exact loop (every sweep of the
    # example takes its limits from one), evaluated sweep by sweep with the values of that
    # model's fit table (keyed by the parameters' keys); the analysis batches the sweeps.
    sw, curves = results.sweeps, results.curves
    assert sorted(curves["grid_points"].unique()) == sorted(CURVE_GRIDS)
    assert set(sw["limits_from"]) <= set(LOOPS)
    u_max = results.table.data.groupby("sweep")["amplitude_m"].max()
    for n in CURVE_GRIDS:
        part = curves[curves["grid_points"] == n]
        rows = sweep_rows(part)
        assert list(rows) == list(sw["sweep"])
        for i in range(0, len(sw), 9):
            sweep, key = sw["sweep"].iloc[i], LOOPS[sw["limits_from"].iloc[i]]
            got = part.iloc[rows[sweep]]
            grid = np.linspace(0.0, u_max[sweep], n)
            np.testing.assert_array_equal(got["amplitude_m"].to_numpy(), grid)
            table = results.fits[key]
            assert table["sweep"].iloc[i] == sweep
            model = REGISTRY[key]
            f, g = model.function(grid, **{p.key: table[p.key].iloc[i] for p in model.parameters})
            np.testing.assert_allclose(got["df_model_Hz"], f, rtol=1e-12, atol=0)
            np.testing.assert_allclose(got["dgamma_model_Hz"], g, rtol=1e-12, atol=1e-12)


def test_a_sweep_without_a_usable_fit_gets_no_curve_and_the_others_keep_theirs(results):
    from contactres.analysis._amplitude import pad_sweeps
    from contactres.analysis._classify import fit_sweeps
    from contactres.analysis._curves import fitted_curves
    from contactres.analysis._models import fit_tables

    padded = pad_sweeps(results.table.data)
    sw, fields = fit_sweeps(padded)  # the named table and every fit's fields
    fits = fit_tables(sw["sweep"], fields)
    plateaus = sw.index[sw["limits_from"] == "plateau-loop"][:3]
    assert len(plateaus) == 3
    loop = fits["plateau-loop"]
    loop.loc[plateaus[0], "critical_displacement"] = np.nan  # the quadrature refuses it
    with pytest.raises(ValueError):
        model_curves(sw.loc[plateaus[0]], np.linspace(0.0, 1e-9, 5), loop.loc[plateaus[0]])
    curves = fitted_curves(sw.loc[plateaus], padded, fits, grids=(5,))
    broken = (curves["sweep"] == sw.loc[plateaus[0], "sweep"]).to_numpy()
    assert broken.sum() == 5
    assert curves.loc[broken, ["df_model_Hz", "dgamma_model_Hz"]].isna().all().all()
    assert np.isfinite(curves.loc[~broken, ["df_model_Hz", "dgamma_model_Hz"]]).all().all()
