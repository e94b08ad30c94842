"""contactres.fitting.fit, solved by the package's own Levenberg-Marquardt, against scipy's
least_squares (trf, x_scale="jac", ftol = xtol = 1e-12: the solver fit wrapped until issue 31),
run here on the same residuals in the same scaled parameters.

The two solvers stop at different points of the same minimum; each value and its standard error
must agree to 1e-3 of that standard error (the bound of issue 31; the measured differences are
~1e-7), on the JKR + Mindlin fit of the sweep analysis with noise of 0.3-3 %, a fit whose γ ends
on its lower bound (γ = 0: least_squares stays a hair inside, the projection sits on it), and
a linear model whose least-squares answer numpy's lstsq gives.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.optimize import least_squares

from contactres.analysis import REGISTRY
from contactres.errors import ContactresInputError
from contactres.fitting import Model, Parameter, fit
from contactres.tangential import kappa_jkr_mindlin

R, NU = 1.1e-3, 0.2
LOADS = np.repeat(np.linspace(0.05, 1.2, 8), 3)


def _scipy_fit(model: Model, x, y, start, fixed):
    """What fit returned before issue 31: least_squares on the residuals in units of each
    parameter's scale, and errors from its Jacobian."""
    free = [p for p in model.parameters if p.key not in fixed]
    scale = np.array([p.scale for p in free])
    lo = np.array([p.bounds[0] for p in free]) / scale
    hi = np.array([p.bounds[1] for p in free]) / scale

    def residuals(z):
        params = dict(fixed) | {p.key: v * s for p, v, s in zip(free, z, scale, strict=True)}
        return np.ravel(np.asarray(model.function(x, **params)) - y)

    z0 = np.clip(np.array([start[p.key] for p in free]) / scale, lo, hi)
    sol = least_squares(
        residuals, z0, bounds=(lo, hi), method="trf", x_scale="jac", ftol=1e-12, xtol=1e-12
    )
    rss = float(sol.fun @ sol.fun)
    cov = np.linalg.inv(sol.jac.T @ sol.jac) * rss / (y.size - len(free)) * np.outer(scale, scale)
    values = {p.key: v * s for p, v, s in zip(free, sol.x, scale, strict=True)}
    errors = {p.key: float(np.sqrt(cov[i, i])) for i, p in enumerate(free)}
    return values, errors


def _assert_same_fit(model, x, y, start, fixed):
    ours = fit(model, x, y, start=start, fixed=fixed)
    values, errors = _scipy_fit(model, x, y, start, fixed)
    assert ours.success, ours.message
    for key, value in values.items():
        se = errors[key]
        assert abs(ours.values[key] - value) <= 1e-3 * se, key
        assert abs(ours.errors[key] - se) <= 1e-3 * se, key
    return ours


@pytest.mark.parametrize(
    ("gamma", "noise", "seed"), [(0.05, 0.003, 1), (0.2, 0.01, 2), (0.02, 0.03, 3)]
)
def test_the_jkr_fit_is_least_squares(gamma, noise, seed):
    model = REGISTRY["jkr-mindlin"]
    rng = np.random.default_rng(seed)
    kappa = kappa_jkr_mindlin(LOADS, 70e9, gamma, R, NU) * (1 + noise * rng.standard_normal(24))
    start = {"E": 50e9, "gamma": 0.05}
    _assert_same_fit(model, LOADS, kappa, start, {"radius": R, "poisson": NU})


def test_a_fit_on_its_lower_bound_is_least_squares():
    """No adhesion and a stiffness rising faster than JKR allows: γ wants to be negative and
    ends on its bound 0; E is then the one-parameter fit of both solvers."""
    model = REGISTRY["jkr-mindlin"]
    rng = np.random.default_rng(4)
    kappa = kappa_jkr_mindlin(LOADS, 70e9, 0.0, R, NU) * LOADS**0.05
    kappa *= 1 + 0.002 * rng.standard_normal(24)
    ours = fit(
        model, LOADS, kappa, start={"E": 50e9, "gamma": 0.05}, fixed={"radius": R, "poisson": NU}
    )
    values, errors = _scipy_fit(
        model, LOADS, kappa, {"E": 50e9, "gamma": 0.05}, {"radius": R, "poisson": NU}
    )
    assert ours.values["gamma"] == 0.0 and values["gamma"] < 1e-6 * errors["gamma"]
    assert abs(ours.values["E"] - values["E"]) <= 1e-3 * errors["E"]
    assert abs(ours.errors["E"] - errors["E"]) <= 1e-3 * errors["E"]


def _line() -> Model:
    return Model(
        "line",
        "a line",
        (
            Parameter("slope", "slope", "-", "slope"),
            Parameter("offset", "offset", "-", "offset", scale=10.0),
        ),
        "x",
        "-",
        "y",
        "-",
        "test",
        lambda x, slope, offset: slope * x + offset,
    )


def test_a_linear_fit_is_lstsq():
    line = _line()
    rng = np.random.default_rng(5)
    x = np.linspace(0, 3, 40)
    y = 2.5 * x - 7 + 0.1 * rng.standard_normal(40)
    A = np.column_stack([x, np.ones_like(x)])
    coef, rss = np.linalg.lstsq(A, y, rcond=None)[:2]
    cov = np.linalg.inv(A.T @ A) * rss[0] / 38
    ours = _assert_same_fit(line, x, y, {"slope": 1.0, "offset": 0.0}, {})
    assert np.allclose([ours.values["slope"], ours.values["offset"]], coef, rtol=0, atol=1e-9)
    assert np.allclose(
        [ours.errors["slope"], ours.errors["offset"]], np.sqrt(np.diag(cov)), rtol=1e-6
    )


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_a_point_that_is_not_finite_is_refused_in_one_line(bad):
    # least_squares refused residuals that are not finite at the start; without that check the
    # own solver's SVD failed with numpy's LinAlgError (review R24a).
    x = np.linspace(0, 3, 10)
    y = 2.0 * x
    y[4] = bad
    with pytest.raises(ContactresInputError, match="not finite") as err:
        fit(_line(), x, y, start={"slope": 1.0, "offset": 0.0})
    assert "\n" not in str(err.value)


def test_a_fit_evaluates_each_parameter_set_once_with_the_same_result(monkeypatch):
    # The solver re-evaluates the point it accepts with its Jacobian, and fit the start and the
    # result: fit keeps its last evaluations (_FIT_REPEATS), so that a costly model (the coated
    # law's contact-radius solve) runs once per parameter set; kept or not, the same numbers.
    import contactres.fitting as fitting

    model = REGISTRY["jkr-mindlin"]
    rng = np.random.default_rng(3)
    y = kappa_jkr_mindlin(LOADS, 70e9, 0.05, R, NU) * (1 + 0.01 * rng.standard_normal(LOADS.size))
    calls: list[tuple] = []

    def counted(x, **p):
        calls.append(tuple(sorted(p.items())))
        return model.function(x, **p)

    spy = dataclasses.replace(model, function=counted)
    start, fixed = {"E": 50e9, "gamma": 0.1}, {"radius": R, "poisson": NU}
    kept = fit(spy, LOADS, y, start=start, fixed=fixed)
    assert len(calls) == len(set(calls))
    monkeypatch.setattr(fitting, "_FIT_REPEATS", 0)  # none kept: every repeat evaluated
    n_kept = len(calls)
    again = fit(spy, LOADS, y, start=start, fixed=fixed)
    assert len(calls) - n_kept > n_kept
    assert again.values == kept.values and again.errors == kept.errors
    np.testing.assert_array_equal(again.covariance, kept.covariance)
    np.testing.assert_array_equal(again.residuals, kept.residuals)
    kept.residuals[0] = 0.0  # the result's own copy, writable as before (review R30b)
