"""The layered correction on the shared arc fitted in T = p₁ω (module ``_layered_arc``): the
Chebyshev machinery against numpy, the fit against direct layer recursions at every point of a
curve, its refusal where too few points cannot meet the bound, and the punch with and without
it."""

from __future__ import annotations

import numpy as np
import pytest

from contactres import LayeredMaterial, Material
from contactres.dynamic import _layered_path
from contactres.dynamic._layered_arc import (
    ARC_TOL,
    chebyshev_coefficients,
    fit_in_parameter,
    lobatto_points,
)
from contactres.dynamic._layered_nodes import punch_resolution
from contactres.dynamic._layered_path import film_reference, stack_at, stack_of
from contactres.dynamic._layered_punch import layered_punch_stiffness
from contactres.layered import stack_compliance

QUARTZ = Material.isotropic(72e9, 0.17, density=2650.0, name="quartz")
PMMA = Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA")
A = 5e-6
# The benchmark's curve: k_s a = 0 .. 2 in the film (41 points).
KSA = np.linspace(0.0, 2.0, 41)
FREQ = KSA * np.sqrt(np.real(PMMA.C[3, 3]) / PMMA.density) / (2 * np.pi * A)


def test_chebyshev_coefficients_are_numpys_interpolant():
    """The DCT of the Lobatto samples gives the coefficients numpy's least-squares Chebyshev
    fit of full degree finds (the interpolant through the same points)."""
    rng = np.random.default_rng(11)
    for n in (4, 9, 12):
        values = rng.standard_normal((n + 1, 3))
        want = np.polynomial.chebyshev.chebfit(lobatto_points(n), values, n)
        np.testing.assert_allclose(chebyshev_coefficients(values), want, rtol=0, atol=1e-12)


def test_fit_reproduces_a_polynomial_and_refuses_what_it_cannot_resolve():
    """A polynomial of degree 10 is met at the first degree (to round-off, also between the
    points); e^{60 t} on [0, 1] is not met by degree 24, and too few targets are not fitted."""
    coef = np.random.default_rng(3).standard_normal(11)

    def poly(t):
        return np.polynomial.polynomial.polyval(t, coef)[:, None] * np.array([1.0, 1j])

    fit = fit_in_parameter(poly, 2.0, 5.0, 40)
    assert fit is not None and fit.samples.shape[0] == 13
    t = np.linspace(2.0, 5.0, 57)
    assert np.max(np.abs(fit(t) - poly(t))) < 1e-12 * np.max(np.abs(poly(t)))
    assert fit_in_parameter(lambda t: np.exp(60 * t)[:, None], 0.0, 1.0, 100) is None
    assert fit_in_parameter(poly, 2.0, 5.0, 13) is None


def _arc_setup(thickness: float):
    """The shared waves of PMMA (``thickness``, m) on quartz over the benchmark's frequencies,
    and T = p₁ω of its dynamic points."""
    material = LayeredMaterial(QUARTZ, [(PMMA, thickness)])
    mats, hs = stack_of(material, 0.0)
    film, q = film_reference(mats[0])
    stacks = [stack_at(mats, hs, film, q, float(f)) for f in FREQ]
    shared = _layered_path._SharedWaves(stacks[1], np.zeros(1), punch_resolution(1e-6), stacks)
    return stacks[1:], shared, np.array([st.pole for st in stacks[1:]])


def _direct(st, poles: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Δg (len(poles), len(z)) at η = T z by the layer recursion of stack_compliance at each
    node (no shared waves, no closed-form exponentials)."""
    eta = poles[:, None] * z[None, :]
    omega = poles[:, None] / st.pole_slowness
    s = [sig * omega**2 / eta**2 for sig in st.sigma]
    th = np.zeros(eta.shape)
    H = stack_compliance(st.tensors, s, [eta * h for h in st.thicknesses], th)
    H_ref = stack_compliance([st.reference], s[:1], [], th)
    return H_ref[..., 2, 2] - H[..., 2, 2]


@pytest.mark.parametrize("thickness", [250e-9, 1e-6], ids=["250nm", "1um"])
def test_arc_fit_meets_its_bound_against_direct_recursions(thickness):
    """At every point of the curve the fitted Δg on the arc equals the direct recursion within
    ARC_TOL of its largest value (the estimate's bound; measured ~1e-15); a fit of degree 4,
    accepted without the bound, misses it: the estimate is what keeps the error small."""
    stacks, shared, poles = _arc_setup(thickness)
    lo, hi = float(np.min(poles)), float(np.max(poles))
    fit = fit_in_parameter(shared._arc_delta_g, lo, hi, poles.size)
    assert fit is not None
    want = _direct(stacks[0], poles, shared.z)
    scale = np.max(np.abs(want))
    assert np.max(np.abs(fit(poles)[..., 0] - want)) <= ARC_TOL * scale
    # Too few points: refused under the bound, and too far off where accepted anyway.
    assert fit_in_parameter(shared._arc_delta_g, lo, hi, poles.size, degrees=(4,)) is None
    coarse = fit_in_parameter(shared._arc_delta_g, lo, hi, poles.size, tol=1.0, degrees=(4,))
    assert coarse is not None
    assert np.max(np.abs(coarse(poles)[..., 0] - want)) > ARC_TOL * scale


def test_a_thick_film_is_solved_directly():
    """5 µm of PMMA (T h up to 3.5): no degree meets the bound with fewer solutions than the
    40 points, so every point is solved directly; the 250 nm film is fitted."""
    stacks, shared, poles = _arc_setup(5e-6)
    lo, hi = float(np.min(poles)), float(np.max(poles))
    assert fit_in_parameter(shared._arc_delta_g, lo, hi, poles.size) is None
    shared.fit_arc(stacks, [A] * len(stacks))
    assert shared.arc_fit is None
    # The 250 nm film's points are fitted (the same call).
    stacks, shared, _ = _arc_setup(250e-9)
    shared.fit_arc(stacks, [A] * len(stacks))
    assert shared.arc_fit is not None


def test_the_punch_with_the_fit_equals_the_punch_without(monkeypatch):
    """The 250 nm curve with the arc fitted in T and with every point solved directly agree to
    1e-12 of its largest value (measured: 2e-15)."""
    material = LayeredMaterial(QUARTZ, [(PMMA, 250e-9)])
    fitted = layered_punch_stiffness(material, A, FREQ)
    monkeypatch.setattr(_layered_path, "fit_in_parameter", lambda *args, **kw: None)
    direct = layered_punch_stiffness(material, A, FREQ)
    assert np.max(np.abs(fitted - direct)) < 1e-12 * np.max(np.abs(direct))
    assert not np.array_equal(fitted, direct)  # the fit did serve


def test_a_nan_sample_is_refused_not_spread():
    """A solution that is NaN at one Lobatto point must refuse the fit (the points are then
    solved directly), not pass the bound: NaN compares false with it, and the interpolant
    would put NaN at every point, where the direct solutions are finite."""
    lo, hi = 1.0, 2.0
    bad = lo + (hi - lo) * (lobatto_points(12)[5] + 1) / 2

    def solve(t):
        v = np.exp(t)[:, None] * np.array([1.0, 1j])
        v[t == bad] = np.nan
        return v

    assert fit_in_parameter(solve, lo, hi, 100) is None
    assert fit_in_parameter(lambda t: np.exp(t)[:, None] + 0j, lo, hi, 100) is not None
