"""Tests of contactres.normal._axisymmetric: the Galerkin on a wave-number-dependent compliance.

References used here, none of them the Galerkin itself:

- Sneddon's flat punch K = 2aE* and Hertz (δ = a²/R, F = 4E*a³/(3R), p(0) = 2aE*/(πR)) for a
  constant kernel g = 2/E* (Johnson, Contact Mechanics, 1985, §3.8 and §4.2);
- a second algorithm: the Fredholm integral equation of the second kind of the axisymmetric
  punch (Lebedev & Ufliand 1958; Cooke 1963), solved by Nyström in :mod:`fredholm_reference`
  (next to this file). For g = A + B e^{−2ηh} its cosine transform is closed form,
  c(x) = (B/A) 2h/(4h² + x²).
"""

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
