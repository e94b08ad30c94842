"""Curves of many k a values: Chebyshev interpolation against direct evaluation."""

import numpy as np
import pytest

from contactres.dynamic import ALL_MODELS, dcsf, dcsf_models, prepare
from contactres.dynamic import _normal_stiffness as normal_stiffness
from contactres.dynamic._interpolation import chebyshev_values
from contactres.materials import Material


def test_chebyshev_values_meets_its_tolerance_on_an_analytic_function():
    x = np.random.default_rng(3).uniform(0.0, 2.0, 500)

    def f(t):
        return {"g": np.exp(3j * t) / (1.0 + t**2), "h": np.cosh(t) + 0j}

    found = chebyshev_values(f, x, 1e-10)
    assert found is not None
    values, error = found
    assert error <= 1e-10
    for name in ("g", "h"):
        assert np.max(np.abs(values[name] - f(x)[name])) < 1e-11


def test_chebyshev_values_gives_up_on_a_kink():
    # |t - 0.3| is not analytic: the error falls only like 1/n, so 64 intervals cannot reach
    # 1e-8 and the caller is told to evaluate directly.
    x = np.linspace(0, 1, 50)
    assert chebyshev_values(lambda t: {"k": np.abs(t - 0.3) + 0j}, x, 1e-8, largest=64) is None


def test_chebyshev_weights_are_exact_for_a_polynomial_of_the_grid_degree():
    # The barycentric formula with the closed-form Lobatto weights reproduces any polynomial of
    # degree n on n + 1 nodes to round-off (Berrut and Trefethen 2004, Sec. 5); a wrong weight
    # (sign or the halved ends) breaks it at every point between the nodes.
    poly = np.polynomial.Polynomial(np.random.default_rng(5).standard_normal(17))
    x = np.linspace(-0.4, 1.3, 301)
    found = chebyshev_values(lambda t: {"p": poly(t) + 0j}, x, 1e-8, first=16, largest=32)
    assert found is not None
    assert np.allclose(found[0]["p"], poly(x), rtol=0, atol=1e-11 * np.max(np.abs(poly(x))))


def test_chebyshev_values_are_the_same_bits_every_call():
    # scipy's BarycentricInterpolator forms its weights as products in a random order (its rng:
    # numpy's global random state by default, seeded from the OS and moved on by every draw), so
    # afm invert --crystal of a map differed in the last bits from run to run. The same
    # abscissae must give the same bits every time.
    x = np.random.default_rng(11).uniform(0.0, 2.0, 5000)

    def f(t):
        return {"g": np.exp(3j * t) / (1.0 + t**2)}

    runs = [chebyshev_values(f, x, 1e-12)[0]["g"] for _ in range(3)]
    assert all(np.array_equal(runs[0], run) for run in runs[1:])


@pytest.fixture(scope="module")
def cu001():
    m = Material.crystal("Cu").rotated((0, 0, 1))
    return m, prepare(m, 0.0)


def test_interpolated_curves_agree_with_direct_evaluation(cu001):
    m, table = cu001
    ka = np.random.default_rng(7).uniform(0.0, 2.0, 150)
    # R0's negative damping near k_l a = 2 is not this test's matter (test_negative_damping_warning)
    fast = dcsf_models(m, ka, prepared=table, interpolate=True, warn_negative=False)
    slow = dcsf_models(m, ka, prepared=table, interpolate=False, warn_negative=False)
    for name in ALL_MODELS:
        scale = np.max(np.abs(1 / slow[name]))
        # the stated bound: a tenth of rtol (1e-6) of the largest |1/DCSF| on the curve
        assert np.max(np.abs(1 / fast[name] - 1 / slow[name])) <= 1e-7 * scale, name


def test_a_pole_of_the_sa_model_does_not_stop_the_interpolation(monkeypatch):
    # A = 0.5, ν = 0.25, Q⁻¹ = 0.02: N of SA passes near zero for k_l a < 2, so DCSF_SA has a
    # near-pole that no polynomial follows; 1/DCSF is smooth and is what is interpolated.
    m = Material.cubic_from_ratios(0.5, 0.25)
    table = prepare(m, 0.02)
    ka = np.linspace(0.0, 2.0, 2001)
    evaluated = []
    direct = normal_stiffness._direct

    def spy(table, flat, *args):
        evaluated.append(flat.size)
        return direct(table, flat, *args)

    monkeypatch.setattr(normal_stiffness, "_direct", spy)
    # SA's negative damping beyond the near-pole is not this test's matter
    kw = {"loss": 0.02, "prepared": table, "warn_negative": False}
    fast = dcsf_models(m, ka, ("SA", "exact"), **kw)
    assert 33 <= sum(evaluated) <= 257  # interpolated: a few dozen direct values, not 2001
    monkeypatch.undo()
    slow = dcsf_models(m, ka[::40], ("SA", "exact"), interpolate=False, **kw)
    assert np.max(np.abs(slow["SA"])) > 20  # the near-pole is there
    for name in ("SA", "exact"):
        scale = np.max(np.abs(1 / slow[name]))
        assert np.max(np.abs(1 / fast[name][::40] - 1 / slow[name])) <= 1e-7 * scale


def test_small_calls_are_direct_and_bad_options_refused(cu001):
    m, table = cu001
    # 200 distinct values within a few ulps (found by review: coinciding nodes crashed scipy)
    narrow = 0.3 * (1 + np.finfo(float).eps * np.arange(200))
    values = dcsf(m, narrow, prepared=table)
    assert np.allclose(values, dcsf(m, 0.3, prepared=table), rtol=1e-12, atol=0)
    ka = np.linspace(0.1, 1.5, 60)
    auto = dcsf(m, ka, prepared=table)
    direct = dcsf(m, ka, prepared=table, interpolate=False)
    assert np.array_equal(auto, direct)  # below INTERPOLATE_ABOVE distinct values
    grid = dcsf(m, np.repeat(ka, 5), prepared=table)  # repeats are not distinct values
    assert np.array_equal(grid, np.repeat(direct, 5))
    with pytest.raises(ValueError, match="interpolate"):
        dcsf(m, ka, prepared=table, interpolate="yes")


def test_an_interpolated_curve_is_the_same_bits_every_run(cu001):
    # The path of afm invert --crystal on a map (many distinct k a: interpolated 1/DCSF).
    m, table = cu001
    ka = np.random.default_rng(13).uniform(0.0, 1e-3, 2000)
    runs = [
        dcsf_models(m, ka, ("exact",), prepared=table, interpolate=True)["exact"] for _ in range(3)
    ]
    assert all(np.array_equal(runs[0], run) for run in runs[1:])
