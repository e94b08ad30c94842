"""Tests of contactres.normal._axisymmetric: the Galerkin on a wave-number-dependent compliance.

References used here, none of them the Galerkin itself:

- Sneddon's flat punch K = 2aE* and Hertz (δ = a²/R, F = 4E*a³/(3R), p(0) = 2aE*/(πR)) for a
  constant kernel g = 2/E* (Johnson, Contact Mechanics, 1985, §3.8 and §4.2);
- a second algorithm: the Fredholm integral equation of the second kind of the axisymmetric
  punch (Lebedev & Ufliand 1958; Cooke 1963), solved by Nyström in :mod:`fredholm_reference`
  (next to this file). For g = A + B e^{−2ηh} its cosine transform is closed form,
  c(x) = (B/A) 2h/(4h² + x²).
"""

import math
import warnings
from fractions import Fraction

import numpy as np
import pytest
from fredholm_reference import fredholm
from scipy.special import spherical_jn

import contactres.normal._axisymmetric as axisymmetric
from contactres.errors import ContactresInputError
from contactres.normal._axisymmetric import (
    RadialKernel,
    even_spherical_bessel,
    punch_and_sphere,
)


def exp_kernel(A, B, h):
    return RadialKernel(g_inf=A, excess=lambda eta: B * np.exp(-2 * eta * h), lengths=(h, h))


def test_even_spherical_bessel_matches_scipy():
    s = np.concatenate([np.geomspace(1e-6, 3e3, 4000), np.pi * np.arange(1, 60)])
    for n in (1, 2, 7, 60):
        ref = spherical_jn(2 * np.arange(n)[:, None], s[None, :])
        np.testing.assert_allclose(even_spherical_bessel(n, s), ref, rtol=0, atol=3e-15)


def test_even_spherical_bessel_of_nan_arguments_is_nan():
    # A NaN gives NaN in its own column only; all NaN (the downward recurrence's start then
    # set by the highest order alone, not by a NaN argument): all NaN, no error.
    both = even_spherical_bessel(3, np.array([np.nan, 1.0]))
    assert np.isnan(both[:, 0]).all()
    np.testing.assert_allclose(both[:, 1], spherical_jn([0, 2, 4], 1.0), rtol=0, atol=3e-15)
    nans = even_spherical_bessel(3, np.array([np.nan, np.nan]))
    assert nans.shape == (3, 2) and np.isnan(nans).all()


@pytest.mark.parametrize("n", [2, 30, 88])
def test_even_spherical_bessel_of_ascending_nodes_is_scipys_and_the_shuffled_ones(n):
    # Ascending arguments (the quadrature's nodes) are worked on in place as slices; any other
    # order by masks: both scipy's values, and the same bits for the same argument.
    s = np.geomspace(1e-3, 600.0, 2900)
    got = even_spherical_bessel(n, s)
    ref = spherical_jn(2 * np.arange(n)[:, None], s[None, :])
    np.testing.assert_allclose(got, ref, rtol=0, atol=3e-15)
    shuffle = np.random.default_rng(n).permutation(s.size)
    np.testing.assert_array_equal(even_spherical_bessel(n, s[shuffle]), got[:, shuffle])


def series_even_spherical_bessel(n, s):
    """j_{2k}(s), k < n, by the power series s^{2k}/(4k + 1)!! (1 − s²/(2(4k + 3))) in exact
    rational arithmetic, rounded once: exact to double precision for s <= 1e-5 (the next term
    is below 1e-21 relative)."""
    out = np.empty((n, len(s)))
    for k in range(n):
        double_factorial = math.prod(range(1, 4 * k + 2, 2))
        for i, x in enumerate(s):
            x = Fraction(float(x))
            out[k, i] = float(x ** (2 * k) / double_factorial * (1 - x * x / (2 * (4 * k + 3))))
    return out


def test_even_spherical_bessel_at_tiny_arguments_is_the_power_series():
    # Down to the smallest subnormal (scipy's spherical_jn gives NaN there): j₀ = 1 and the
    # higher orders underflow to 0 as the series does.
    s = np.array([5e-324, 1e-300, 1e-150, 1e-20, 1e-8, 1e-5])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = even_spherical_bessel(60, s)
    np.testing.assert_allclose(got, series_even_spherical_bessel(60, s), rtol=2e-15, atol=1e-300)


def test_even_spherical_bessel_at_zero_is_its_limit_and_leaves_the_others():
    # j₀(0) = 1, j_{2k}(0) = 0: no 0/0 (a RuntimeWarning would be an error here).
    s = np.array([3.0, 0.0, 250.0, 0.0])
    got = even_spherical_bessel(30, s)
    np.testing.assert_array_equal(got[:, [1, 3]], np.eye(30)[:, [0, 0]])
    np.testing.assert_array_equal(got[:, [0, 2]], even_spherical_bessel(30, s[[0, 2]]))


def test_even_spherical_bessel_at_huge_arguments_is_scipys():
    # Far above every order (upward recurrence only); compared relative to the 1/s envelope.
    s = np.array([1e6, 3.3e9, 1e15, 1e300])
    for n in (1, 5, 400):
        ref = spherical_jn(2 * np.arange(n)[:, None], s[None, :])
        np.testing.assert_allclose(even_spherical_bessel(n, s) * s, ref * s, rtol=0, atol=3e-15)


@pytest.mark.parametrize("n", [0, 1, 2, 30, 400])
def test_even_spherical_bessel_of_any_order_of_arguments_is_scipys(n):
    # Unsorted, repeated, on both sides of s = 2n − 1 (the switch from the ratios run down to
    # the upward recurrence), for no order up to 400 of them (j_0 ... j_798).
    top = max(2 * n - 1, 2)
    s = np.array([top * 3, 0.5, top - 1e-9, top, top + 1e-9, 0.5, top * 3, 1e-3, top / 2])
    got = even_spherical_bessel(n, s)
    assert got.shape == (n, s.size)
    ref = spherical_jn(2 * np.arange(n)[:, None], s[None, :])
    np.testing.assert_allclose(got, ref, rtol=0, atol=3e-15)
    np.testing.assert_array_equal(got[:, 0], got[:, 6])  # repeats: the same bits
    np.testing.assert_array_equal(got[:, 1], got[:, 5])


@pytest.mark.parametrize("n", [0, 3])
def test_even_spherical_bessel_of_no_arguments_is_empty(n):
    assert even_spherical_bessel(n, np.zeros(0)).shape == (n, 0)


def test_even_spherical_bessel_is_even_in_its_argument():
    # j_{2k}(−s) = j_{2k}(s): negative arguments far beyond the highest order too (a start of
    # the ratios set by the signed largest argument would be far too low for them).
    s = np.array([-1000.0, -40.0, 5.0, -0.5, 1000.0])
    got = even_spherical_bessel(30, s)
    np.testing.assert_array_equal(got, even_spherical_bessel(30, np.abs(s)))
    ref = spherical_jn(2 * np.arange(30)[:, None], np.abs(s)[None, :])
    np.testing.assert_allclose(got, ref, rtol=0, atol=3e-15)


def test_even_spherical_bessel_of_a_nan_is_nan_in_its_column_alone():
    # 790 is below the highest order 798: its ratios start from the largest such argument,
    # which a NaN must not hide (a start at 828 instead of 1057 leaves ~2e-10 there).
    s = np.array([np.nan, 790.0, 2000.0, np.nan, 3.0])
    got = even_spherical_bessel(400, s)
    assert np.isnan(got[:, [0, 3]]).all()
    np.testing.assert_array_equal(got[:, [1, 2, 4]], even_spherical_bessel(400, s[[1, 2, 4]]))
    ref = spherical_jn(2 * np.arange(400)[:, None], s[None, [1, 2, 4]])
    np.testing.assert_allclose(got[:, [1, 2, 4]], ref, rtol=0, atol=3e-15)


@pytest.mark.parametrize("n_basis", [None, 2, 9])
def test_constant_kernel_is_sneddon_and_hertz(n_basis):
    E_star = 73.5e9
    g = 2 / E_star
    a = np.array([1e-9, 3e-6, 2e-3])
    sol = punch_and_sphere(RadialKernel(g_inf=g), a, n_basis=n_basis)
    np.testing.assert_allclose(sol.punch_stiffness, 2 * a * E_star, rtol=1e-14)
    np.testing.assert_allclose(sol.depth_factor, 1.0, rtol=1e-14)
    np.testing.assert_allclose(sol.force_factor, 4 * E_star / 3, rtol=1e-14)
    np.testing.assert_allclose(sol.peak_factor, 2 * E_star / np.pi, rtol=1e-14)


@pytest.mark.parametrize("ratio", [0.05, 0.5, 4.0, 50.0])
@pytest.mark.parametrize("a_over_h", [0.01, 0.3, 1.0, 5.0, 20.0])
def test_exponential_kernel_matches_fredholm(ratio, a_over_h):
    # g = A + B e^{−2ηh}: g(0) = A + B is the "substrate", A the "film"; ratio = g(0)/A.
    A, h = 2.0, 1.0
    B = A * (ratio - 1)
    a = a_over_h * h
    sol = punch_and_sphere(exp_kernel(A, B, h), a)
    ref = fredholm(A, lambda x: (B / A) * 2 * h / (4 * h * h + x * x), a)
    assert sol.punch_stiffness == pytest.approx(ref[0], rel=1e-10)
    assert sol.depth_factor == pytest.approx(ref[1], rel=1e-9)
    assert sol.force_factor == pytest.approx(ref[2], rel=1e-9)


@pytest.mark.parametrize("a_over_h", [0.1, 2.0, 30.0])
def test_default_tolerance_converges(a_over_h):
    """Twice the basis and tol/100 move K, δ and F by less than the stated 1e-9."""
    ker = exp_kernel(2.0, 2.0 * 30, 1.0)  # a compliant substrate under a film 30x stiffer
    a = a_over_h
    base = punch_and_sphere(ker, a)
    more = punch_and_sphere(ker, a, tol=1e-14, n_basis=2 * base.basis)
    assert more.nodes > base.nodes
    for name in ("punch_stiffness", "depth_factor", "force_factor", "peak_factor"):
        x, y = getattr(base, name), getattr(more, name)
        assert abs(x / y - 1) < 1e-9, name


def test_limits_of_the_kernel():
    """a << h sees the film (g∞), a >> h the substrate (g(0)): Sneddon with each."""
    A, B, h = 2.0, 6.0, 1.0
    ker = exp_kernel(A, B, h)
    small, large = punch_and_sphere(ker, [1e-5 * h, 200 * h]).punch_stiffness
    assert small / (4e-5 * h / A) - 1 == pytest.approx(0, abs=1e-4)
    # the film's correction at a >> h is O(h/a)
    assert large / (800 * h / (A + B)) - 1 == pytest.approx(0, abs=2e-2)


def test_bad_radius_and_too_thin_layer():
    ker = exp_kernel(2.0, 1.0, 1.0)
    with pytest.raises(ContactresInputError, match="contact radii"):
        punch_and_sphere(ker, [1.0, -1.0])
    with pytest.raises(ContactresInputError, match="times the thinnest layer"):
        punch_and_sphere(ker, 1e4)


def test_a_shared_store_of_transforms_changes_no_number(monkeypatch):
    # Kernels on the same nodes (same lengths and cut-off) share the transforms; a kernel with
    # other nodes (a smaller excess: fewer panels; another length) is recomputed, not served
    # the stored ones; the tangential problem (one order more) keeps its own. Every number as
    # without the store.
    h = 0.25e-6
    a = np.array([0.8e-6, 3e-6, 9e-6])
    coupled = RadialKernel(
        g_inf=2.0,
        excess=lambda eta: np.stack([0.5 * np.exp(-2 * eta * h), 0.1 * np.exp(-2 * eta * h)]),
        lengths=(h, h),
        coupling_inf=-0.3,
    )
    kernels = [exp_kernel(1.0, 0.5, h), exp_kernel(1.0, -0.3, h), exp_kernel(1.0, 1e-4, h)]
    kernels.append(exp_kernel(1.0, 0.5, 2 * h))
    store: dict = {}
    for kernel in [*kernels, coupled, kernels[0]]:
        alone = punch_and_sphere(kernel, a, tol=1e-6)
        shared = punch_and_sphere(kernel, a, tol=1e-6, transforms=store)
        for field in ("punch_stiffness", "depth_factor", "force_factor", "peak_factor"):
            assert np.array_equal(getattr(alone, field), getattr(shared, field), equal_nan=True)
    assert len(store) >= 2 * a.size  # normal and tangential orders at every radius
    # The store is used, not only filled: a kernel on stored nodes computes no transform again.
    calls = []
    monkeypatch.setattr(
        axisymmetric,
        "even_spherical_bessel",
        lambda *args, f=axisymmetric.even_spherical_bessel: calls.append(1) or f(*args),
    )
    punch_and_sphere(kernels[1], a, tol=1e-6, transforms=store)
    assert not calls
    punch_and_sphere(kernels[1], a, tol=1e-6)
    assert calls
