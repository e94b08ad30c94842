"""The points and fitted curves the analysis hands to the report (``Results.points``,
``Results.curves``), against the input table and the registered model of each sweep."""

import warnings
from importlib.resources import files

import numpy as np
import pytest

import contactres
from contactres.analysis.curves import CURVE_GRIDS, sweep_rows
from contactres.analysis.models import model_curves


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
    sw, curves = results.sweeps, results.curves
    assert sorted(curves["grid_points"].unique()) == sorted(CURVE_GRIDS)
    u_max = results.table.data.groupby("sweep")["amplitude_m"].max()
    for n in CURVE_GRIDS:
        rows = sweep_rows(curves[curves["grid_points"] == n])
        part = curves[curves["grid_points"] == n]
        assert list(rows) == list(sw["sweep"])
        for _, row in sw.iloc[:: max(1, len(sw) // 40)].iterrows():  # every 9th or so sweep
            got = part.iloc[rows[row["sweep"]]]
            grid = np.linspace(0.0, u_max[row["sweep"]], n)
            np.testing.assert_array_equal(got["amplitude_m"].to_numpy(), grid)
            # the curves are computed for all sweeps of a model at once; one sweep alone:
            f, g = model_curves(row, grid)
            np.testing.assert_allclose(got["df_model_Hz"], f, rtol=1e-12, atol=0)
            np.testing.assert_allclose(got["dgamma_model_Hz"], g, rtol=1e-12, atol=1e-12)


def test_a_sweep_without_a_usable_fit_gets_no_curve_and_the_others_keep_theirs(results):
    from contactres.analysis.amplitude import pad_sweeps
    from contactres.analysis.curves import fitted_curves

    sw = results.sweeps.copy()
    plateaus = sw.index[sw["limits_from"] == "plateau-loop"][:3]
    assert len(plateaus) == 3
    sw.loc[plateaus[0], "pl_d_c_m"] = np.nan  # the plateau loop's quadrature refuses it
    with pytest.raises(ValueError):
        model_curves(sw.loc[plateaus[0]], np.linspace(0.0, 1e-9, 5))
    curves = fitted_curves(sw.loc[plateaus], pad_sweeps(results.table.data), grids=(5,))
    broken = (curves["sweep"] == sw.loc[plateaus[0], "sweep"]).to_numpy()
    assert broken.sum() == 5
    assert curves.loc[broken, ["df_model_Hz", "dgamma_model_Hz"]].isna().all().all()
    assert np.isfinite(curves.loc[~broken, ["df_model_Hz", "dgamma_model_Hz"]]).all().all()
