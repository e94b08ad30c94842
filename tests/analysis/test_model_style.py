"""The model registry: a closed table of parameter names, units and columns, and each fitted model
checked against a second algorithm (the generic least-squares fit of its registered function)."""

import inspect

import numpy as np
import pytest

from contactres.analysis._amplitude import pad_sweeps
from contactres.analysis._classify import fit_sweeps
from contactres.analysis._loops import loop_tables
from contactres.analysis._models import AMPLITUDE_MODELS, REGISTRY, fit_tables
from contactres.fitting import fit
from contactres.measurements._sweeps import validate_sweeps
from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.measurements.schema import GROUP_RESULTS, SWEEP_RESULTS
from contactres.resonators._qcm import QCM

# Every parameter any fitted model may have: unit and the result columns that may hold it.
# A new parameter must be added here with its unit, or this test fails.
KNOWN = {
    "df0": ("Hz", {"df0_Hz", "df0"}),
    "dgamma0": ("Hz", {"dgamma0_Hz", "dgamma0"}),
    "df_slope": ("Hz/m", {"df_slope_Hz_per_m"}),
    "dgamma_slope": ("Hz/m", {"dgamma_slope_Hz_per_m"}),
    "df_curvature": ("Hz/m^2", {"df_curvature_Hz_per_m2"}),
    "dgamma_curvature": ("Hz/m^2", {"dgamma_curvature_Hz_per_m2"}),
    "critical_amplitude": ("m", {"plateau_amplitude_m"}),
    "critical_displacement": ("m", {"critical_displacement"}),
    "inverse_slip_scale": ("1/m", {"inverse_slip_scale"}),
    "E": ("Pa", {"E_Pa"}),
    "gamma": ("J/m^2", {"gamma_J_m2"}),
    "radius": ("m", {"sphere_radius_m"}),
    "poisson": ("-", {"poisson"}),
}
KNOWN_MODELS = {
    *AMPLITUDE_MODELS,
    "cattaneo-mindlin-loop",
    "savkoor-loop",
    "plateau-loop",
    "jkr-mindlin",
}
Q = QCM(5e6, 3, 2.5e-5)
CONST = dict(overtone=3, area_m2=2.5e-5, n_contacts=3, sphere_radius_m=1e-3)


def test_registry_is_the_closed_set_of_models():
    assert set(REGISTRY) == KNOWN_MODELS
    with pytest.raises(KeyError, match="registered"):
        REGISTRY["no-such-model"]
    with pytest.raises(TypeError):
        REGISTRY["x"] = REGISTRY["elastic"]  # immutable


@pytest.mark.parametrize("key", sorted(KNOWN_MODELS))
def test_parameters_have_known_names_units_and_columns(key):
    model = REGISTRY[key]
    assert model.key == key and model.display and model.source and model.unit and model.x_unit
    names = [p.key for p in model.parameters]
    # The parameters are exactly the keyword arguments of the model function, in order.
    assert list(inspect.signature(model.function).parameters)[1:] == names
    for p in model.parameters:
        assert p.key in KNOWN, f"{key}: parameter {p.key!r} missing from the closed table"
        unit, columns = KNOWN[p.key]
        assert p.unit == unit, f"{key}.{p.key}: unit {p.unit!r}, expected {unit!r}"
        assert p.column in columns, f"{key}.{p.key}: column {p.column!r} not in {columns}"
        assert p.display and p.scale > 0 and p.bounds[0] < p.bounds[1]
        # Where the column is an output of the schema, its unit agrees.
        for schema in (SWEEP_RESULTS, GROUP_RESULTS):
            if p.column in schema.names:
                assert schema.column(p.column).unit == p.unit


@pytest.fixture(scope="module")
def fitted():
    """A small noisy study and the per-sweep fits of the analysis (with the exact loops)."""
    study = SweepStudy(
        groups=(
            SweepGroup(
                "glass", "air", 1e-3, 70e9, 0.05, tuple(np.linspace(0.5e-9, 8e-9, 12)), 1e4, 0.05
            ),
        ),
        normal_forces=(2e-3, 6e-3),
        n_experiments=2,
        ramps=(2, 3),
        alternate=False,
        qcm=Q,
    )
    table = validate_sweeps(synthetic_sweeps(study, 5), constants=CONST)
    padded = pad_sweeps(table.data)
    sw, fields = fit_sweeps(padded, tables=loop_tables())
    return padded, sw, fit_tables(sw["sweep"], fields)


def test_every_parameter_column_is_produced_by_the_analysis(fitted):
    _, sw, fits = fitted
    named = set(sw.columns) | set(GROUP_RESULTS.names)
    for model in REGISTRY.values():
        # A class of the model choice (and the JKR fit) fills named columns; a model fitted to
        # every sweep that is not a class (the exact loops) only its own fit table.
        own = model.key in fits and model.key not in AMPLITUDE_MODELS
        produced = set(fits[model.key].columns) if own else named
        for p in model.parameters:
            assert p.column in produced, f"{model.key}.{p.key} -> {p.column!r} is never written"


def _closed_form_values(row, model):
    return {p.key: float(row[p.column]) for p in model.parameters}


@pytest.mark.parametrize("key", ["elastic", "cattaneo-mindlin", "savkoor"])
def test_closed_form_fits_equal_the_generic_least_squares_fit(fitted, key):
    # fit_sweeps solves these linear models in closed form for all sweeps at once; the generic
    # fit of the registered function (scipy least_squares) must find the same values.
    padded, sw, _ = fitted
    model = REGISTRY[key]
    i = 0
    m = padded.w[i] > 0
    u, y = padded.u[i][m], np.stack([padded.df[i][m], padded.dg[i][m]])
    res = fit(model, u, y, start={p.key: 0.0 for p in model.parameters})
    if key == "elastic":
        expected = {"df0": y[0].mean(), "dgamma0": y[1].mean()}
    else:
        power = 1 if key == "cattaneo-mindlin" else 2
        sf, f0 = np.polyfit(u**power, y[0], 1)
        sg, g0 = np.polyfit(u**power, y[1], 1)
        slope = "slope" if power == 1 else "curvature"
        expected = {"df0": f0, "dgamma0": g0, f"df_{slope}": sf, f"dgamma_{slope}": sg}
        # fit_sweeps' own straight line and parabola agree with both.
        for name in ("df", "dgamma"):
            col = f"{name}_{slope}_Hz_per_m" + ("2" if power == 2 else "")
            assert sw[col].iloc[i] == pytest.approx(expected[f"{name}_{slope}"], rel=1e-9)
    for k, v in expected.items():
        assert res.values[k] == pytest.approx(v, rel=1e-7, abs=1e-9)


def test_exact_loop_fit_equals_the_generic_fit_of_the_registered_loop(fitted):
    # Variable projection on the tabulated loop (fit_sweeps) vs scipy least_squares on the
    # registered function, which evaluates the loop exactly (no table): same minimum.
    padded, sw, fits = fitted
    model = REGISTRY["cattaneo-mindlin-loop"]
    loop = fits[model.key]
    for i in range(len(sw)):
        m = padded.w[i] > 0
        u, y = padded.u[i][m], np.stack([padded.df[i][m], padded.dg[i][m]])
        row = loop.iloc[i]
        assert row["sweep"] == sw["sweep"].iloc[i]
        sigma = np.array([[sw["sigma_df_Hz"].iloc[i]], [sw["sigma_dgamma_Hz"].iloc[i]]])
        start = {
            "df0": row["df0"] * 1.02,
            "dgamma0": row["dgamma0"],
            "inverse_slip_scale": row["inverse_slip_scale"] * 0.9,
        }
        res = fit(model, u, y, start=start, sigma=sigma)
        assert res.values["df0"] == pytest.approx(row["df0"], rel=1e-5)
        assert res.values["inverse_slip_scale"] == pytest.approx(
            row["inverse_slip_scale"], rel=1e-3
        )
        assert res.values["dgamma0"] == pytest.approx(row["dgamma0"], abs=1e-4 * abs(row["df0"]))
