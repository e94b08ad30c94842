"""Tests of contactres.resonators._cantilever: free and pinned limits, the closed form against the
4x4 determinant and an independent 8x8 one, and a finite-element beam (Hermite cubics)."""

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq

from contactres.resonators._cantilever import (
    FREE_ROOTS,
    PINNED_ROOTS,
    Cantilever,
    beta_from_frequency,
    characteristic_determinant,
    contact_frequencies,
    determinant_coefficients,
    normal_kappa,
    normal_log_slope,
    normal_trig,
    tip_coefficients,
)

LEVER = Cantilever((1.0e5, 6.3e5, 17.4e5), 10.0)


def test_free_and_pinned_roots():
    assert np.allclose(FREE_ROOTS[:3], [1.8751, 4.6941, 7.8548], atol=5e-5)
    assert np.allclose((FREE_ROOTS[1:3] / FREE_ROOTS[0]) ** 2, [6.267, 17.55], rtol=5e-4)
    assert np.allclose(PINNED_ROOTS[:2], [3.9266, 7.0686], atol=5e-5)
    assert np.allclose(np.tan(PINNED_ROOTS), np.tanh(PINNED_ROOTS), atol=1e-12)


def test_limits_of_the_forward_model():
    f0 = contact_frequencies(LEVER, 0.0, 0.8)
    assert np.allclose(f0, 1e5 * (FREE_ROOTS[:3] / FREE_ROOTS[0]) ** 2, rtol=1e-12)
    f_inf = contact_frequencies(LEVER, 1e12, 1.0)
    assert np.allclose(f_inf, 1e5 * (PINNED_ROOTS[:3] / FREE_ROOTS[0]) ** 2, rtol=1e-9)


def test_closed_form_equals_determinant_coefficient():
    # det M is linear in κ without lateral spring: κ = −det(0)/(det(1) − det(0)) at any β up to
    # the third pinned root (modes 1-3); beyond, rounding in the O(e^2β) terms of det M grows.
    beta = np.linspace(1.0, 10.1, 301)[:, None]
    r = np.linspace(0.6, 1.0, 41)[None, :]
    d0 = characteristic_determinant(beta, 0.0, r)
    d1 = characteristic_determinant(beta, 1.0, r)
    k_cf = normal_kappa(beta, r)
    rel = np.abs(-d0 / (d1 - d0) / k_cf - 1.0)
    _, b, c = determinant_coefficients(beta, r, tip_coefficients())
    assert np.abs(-c / b / k_cf - 1.0)[(k_cf >= 0.3) & (k_cf <= 3000)].max() < 1e-9
    # Over the physical range of κ (near the poles, det(1) − det(0) -> 0 and rounding grows).
    use = (k_cf >= 0.3) & (k_cf <= 3000)
    assert use.sum() > 3000
    assert rel[use].max() < 5e-9  # measured 2e-9 at β ≈ 10 (mode 3): rounding of det(1) − det(0)


def test_closed_form_reproduces_determinant_roots():
    kappa = np.geomspace(0.3, 3000.0, 25)[:, None]
    r = np.linspace(0.6, 1.0, 9)[None, :]
    f = contact_frequencies(LEVER, kappa, r)
    beta = beta_from_frequency(LEVER, f, np.array([1, 2, 3]))
    rr = r[..., None]
    k_cf = normal_kappa(beta, rr)
    # Compared in β (the closed form's root minus the determinant's, by one Newton step): in κ
    # the comparison is limited by the conditioning dκ/dβ, ~1e3 larger at κ = 3000 (saturation).
    slope = (normal_kappa(beta * (1 + 1e-7), rr) - normal_kappa(beta * (1 - 1e-7), rr)) / 2e-7
    assert np.max(np.abs((k_cf - kappa[..., None]) / slope)) < 1e-9
    assert np.max(np.abs(k_cf / kappa[..., None] - 1.0)) < 1e-8


def _kappa_plain(beta, r):
    """κ of the closed form written with numpy's own cos, sin, cosh, sinh (real or complex),
    independent of the module's exponential forms: the reference for the derivative below."""
    p, q = beta * r, beta * (1.0 - r)
    d = (np.sin(q) * np.cosh(q) - np.cos(q) * np.sinh(q)) * (1.0 - np.cos(p) * np.cosh(p)) - (
        np.sin(p) * np.cosh(p) - np.cos(p) * np.sinh(p)
    ) * (1.0 + np.cos(q) * np.cosh(q))
    return 2.0 * beta**3 * (1.0 + np.cos(beta) * np.cosh(beta)) / (3.0 * d)


def test_log_slope_is_the_derivative_of_the_closed_form():
    # Real β: the complex-step derivative of the plain formula, β Im κ(β + ih)/(h κ), free of
    # cancellation (exact to rounding); modes 1-3 and tips from mid-lever to the end.
    beta = np.linspace(1.0, 10.1, 401)[:, None]
    r = np.linspace(0.3, 1.0, 15)[None, :]
    k = _kappa_plain(beta, r)
    h = 1e-30
    reference = beta * np.imag(_kappa_plain(beta + 1j * h, r)) / (h * k)
    slope = normal_log_slope(beta, r)
    use = (np.abs(k) > 1e-3) & (np.abs(k) < 1e4)  # away from κ = 0 and the poles (L → ∞)
    assert use.sum() > 4000
    assert np.max(np.abs(slope[use] / reference[use] - 1.0)) < 1e-9
    # Complex β (a mode's Q of 50): a fourth-order central difference along β, step 1e-5 β.
    bq = beta * np.sqrt(1.0 + 1j / 50.0)
    e = 1e-5
    diff = (
        8.0 * (_kappa_plain(bq * (1 + e), r) - _kappa_plain(bq * (1 - e), r))
        - (_kappa_plain(bq * (1 + 2 * e), r) - _kappa_plain(bq * (1 - 2 * e), r))
    ) / (12.0 * e)
    kq = _kappa_plain(bq, r)
    use = (np.abs(kq) > 1e-1) & (np.abs(kq) < 1e3)
    assert use.sum() > 3000
    assert np.max(np.abs(normal_log_slope(bq, r)[use] / (diff[use] / kq[use]) - 1.0)) < 1e-6


def test_shared_functions_give_the_same_numbers():
    # The inversion evaluates the 12 functions of β and r once (normal_trig) for κ and for
    # its slope: both must be the numbers each computes alone, bit for bit, for a real β and
    # for a damped (complex) one; and κ is still the plain formula's.
    beta = np.linspace(1.0, 10.1, 401)[:, None]
    r = np.linspace(0.3, 1.0, 15)[None, :]
    for b in (beta, beta * np.sqrt(1.0 + 1j / 50.0)):
        trig = normal_trig(b, r)
        k = normal_kappa(b, r, trig)
        assert np.array_equal(k, normal_kappa(b, r), equal_nan=True)
        assert np.array_equal(normal_log_slope(b, r, trig), normal_log_slope(b, r), equal_nan=True)
        plain = _kappa_plain(b, r)
        use = np.abs(plain) < 1e4  # away from the poles
        assert np.allclose(k[use], plain[use], rtol=1e-9, atol=1e-9)


def det8(beta, kappa, r, g):
    """8x8 determinant with plain cos, sin, cosh, sinh of βξ on both segments (independent of
    the module's reduced 4x4): clamped at 0, free at 1, four jump rows at r written out."""
    g_yy, g_yt, g_tt = g

    def basis(x, k):  # k-th derivative / β^k of (cos, sin, cosh, sinh)(βx)
        c, s, ch, sh = np.cos(beta * x), np.sin(beta * x), np.cosh(beta * x), np.sinh(beta * x)
        return [[c, s, ch, sh], [-s, c, sh, ch], [-c, -s, ch, sh], [s, -c, sh, ch]][k]

    z = [0.0] * 4
    m = [basis(0, 0) + z, basis(0, 1) + z, z + basis(1, 2), z + basis(1, 3)]
    left = [np.array(basis(r, k)) for k in range(4)]
    right = [np.array(basis(r, k)) for k in range(4)]
    m.append(list(-left[0]) + list(right[0]))
    m.append(list(-left[1]) + list(right[1]))
    # y″(r⁺) − y″(r⁻) = 3κ(g_yθ y + g_θθ y′), y‴(r⁺) − y‴(r⁻) = −3κ(g_yy y + g_yθ y′)
    mom = -left[2] * beta**2 - 3 * kappa * (g_yt * left[0] + g_tt * beta * left[1])
    she = -left[3] * beta**3 + 3 * kappa * (g_yy * left[0] + g_yt * beta * left[1])
    m.append(list(mom) + list(right[2] * beta**2))
    m.append(list(she) + list(right[3] * beta**3))
    return np.linalg.det(np.array(m, dtype=float))


def roots8(kappa, r, g, n=3):
    grid = np.arange(0.5, 15.0, 0.01)
    d = np.array([det8(b, kappa, r, g) for b in grid])
    idx = np.nonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0][:n]
    return np.array([brentq(det8, grid[i], grid[i + 1], (kappa, r, g), xtol=1e-14) for i in idx])


CASES = [
    (3.0, 0.9, 0.0, 0.0, 0.0),
    (50.0, 0.75, 0.0, 0.0, 11.0),
    (20.0, 0.85, 0.8, 0.04, 12.0),
    (200.0, 1.0, 0.5, 0.03, 0.0),
]


@pytest.mark.parametrize("kappa, r, lat, eta, tilt", CASES)
def test_determinant_against_8x8(kappa, r, lat, eta, tilt):
    g = tip_coefficients(lat, eta, tilt)
    f = contact_frequencies(LEVER, kappa, r, lat, eta, tilt)
    beta = beta_from_frequency(LEVER, f, np.array([1, 2, 3]))
    assert np.allclose(beta, roots8(kappa, r, g), rtol=1e-10)


def fe_betas(kappa, r, g, n_el, n=3):
    """First β of a Hermite-cubic Euler-Bernoulli FE lever (EI = ρA = L = 1, so ω² = β⁴) with
    the tip stiffness 3κ[[g_yy, g_yθ], [g_yθ, g_θθ]] on the (w, θ) DOFs of the node at r.

    The rotations enter as hθ (element length h) so that both matrices are well scaled: with
    θ itself, M's rotational entries are O(h³) and eigh loses ~1e-5 at 640 elements."""
    h = 1.0 / n_el
    ke = np.array(
        [[12, 6, -12, 6], [6, 4, -6, 2], [-12, -6, 12, -6], [6, 2, -6, 4]]
    ) / h**3  # fmt: skip
    me = h / 420 * np.array(
        [[156, 22, 54, -13], [22, 4, 13, -3], [54, 13, 156, -22], [-13, -3, -22, 4]]
    )  # fmt: skip
    nd = 2 * (n_el + 1)
    k, m = np.zeros((nd, nd)), np.zeros((nd, nd))
    for e in range(n_el):
        s = slice(2 * e, 2 * e + 4)
        k[s, s] += ke
        m[s, s] += me
    node = round(r * n_el)
    assert abs(node - r * n_el) < 1e-9
    i = 2 * node
    g_yy, g_yt, g_tt = g
    k[i : i + 2, i : i + 2] += 3 * kappa * np.array([[g_yy, g_yt / h], [g_yt / h, g_tt / h**2]])
    lam = eigh(k[2:, 2:], m[2:, 2:], eigvals_only=True, subset_by_index=(0, n - 1))
    return lam**0.25


@pytest.mark.parametrize("kappa, r, lat, eta, tilt", CASES[1:])
def test_determinant_against_finite_elements(kappa, r, lat, eta, tilt):
    g = tip_coefficients(lat, eta, tilt)
    f = contact_frequencies(LEVER, kappa, r, lat, eta, tilt)
    beta = beta_from_frequency(LEVER, f, np.array([1, 2, 3]))
    # Measured: 20/40/80 elements -> ~8e-6 / 5e-7 / 3e-8 (16x per halving: error ~ h⁴); beyond
    # ~100 elements eigh's rounding (condition ~ n⁴) takes over, so more elements do not help.
    err = [np.max(np.abs(fe_betas(kappa, r, g, n) / beta - 1)) for n in (20, 40, 80)]
    assert err[2] < 1e-7
    assert err[1] < err[0] / 12 and err[2] < err[1] / 12


def test_complex_kappa_gives_complex_frequency():
    f = contact_frequencies(LEVER, 10.0 * (1 + 0.1j), 0.9)
    assert np.iscomplexobj(f)
    q = f.real / (2 * f.imag)
    assert np.all((q > 1) & (q < 1e4))
    assert np.allclose(f.real, contact_frequencies(LEVER, 10.0, 0.9), rtol=0.05)


def test_broadcasting_and_shapes():
    f = contact_frequencies(LEVER, np.ones((2, 1)), np.array([0.8, 0.9, 1.0]), modes=(1, 2))
    assert f.shape == (2, 3, 2)


def test_validation_names_parameter_and_unit():
    with pytest.raises(ValueError, match=r"tip_position.*L1/L"):
        contact_frequencies(LEVER, 1.0, 1.2)
    with pytest.raises(ValueError, match=r"spring_constant.*N/m"):
        Cantilever((1e5,), -1.0)
    with pytest.raises(ValueError, match="normalisation"):
        Cantilever((1e5,), 1.0, normalisation="bogus")
    with pytest.raises(ValueError, match="tilt"):
        tip_coefficients(0.0, 0.0, 95.0)


def test_roots_match_brentq_on_the_lu_determinant_pixel_by_pixel():
    # The bracketing scan evaluates det M by an expansion; the reference here is scipy's brentq
    # on characteristic_determinant (stacked matrices, LU), bracketed by the test's own scan of
    # step 0.002 (5x finer than BETA_STEP), pixel by pixel over κ from 1e-6 to 1e6 and tips
    # from 0.3 to 1 (nodes included) with normal-only and lateral/tilted springs.
    rng = np.random.default_rng(23)
    kappa = 10.0 ** rng.uniform(-6.0, 6.0, 24)
    r = rng.uniform(0.3, 1.0, 24)
    springs = [(0.0, 0.0, 0.0), (0.8, 0.03, 11.0), (2.0, 0.05, 80.0)] * 8
    scan = np.arange(0.5, FREE_ROOTS[4] + 0.5, 0.002)
    for k, rr, (lat, eta, tilt) in zip(kappa, r, springs, strict=True):
        f = contact_frequencies(LEVER, k, rr, lat, eta, tilt)
        beta = beta_from_frequency(LEVER, f, np.array([1, 2, 3]))

        def det(b, k=k, rr=rr, lat=lat, eta=eta, tilt=tilt):
            return characteristic_determinant(b, k, rr, lat, eta, tilt)

        d = det(scan)
        idx = np.flatnonzero(np.sign(d[:-1]) != np.sign(d[1:]))[:3]
        ref = [brentq(det, scan[i], scan[i + 1], xtol=1e-15, rtol=1e-15) for i in idx]
        assert np.allclose(beta, ref, rtol=1e-12, atol=0.0), (k, rr, lat, eta, tilt)


def test_a_root_on_a_grid_point_is_found_once_and_in_place():
    """Review R22b: springs whose mode-1 root lies exactly on (or a few ulps off) a point of the
    bracketing grid. The scan's expanded determinant and the bisection's LU may disagree on that
    point's sign, and an exact zero there used to count as two sign changes: β₁ landed a whole
    grid step (0.01) off, or mode 2 came back as a copy of mode 1. The roots are checked against
    the springs' own construction (normal_kappa(β, r) puts the root at β)."""
    lever = Cantilever((13e3,), 0.2)
    grid = np.arange(0.5, FREE_ROOTS[3] + 0.5, 0.01)  # contact_frequencies' grid for modes 1, 2
    beta = grid[(grid > 1.90) & (grid < 2.6)][:, None] + np.array([0, 1, 2])[None, :] * np.spacing(
        grid[(grid > 1.90) & (grid < 2.6)][:, None]
    )
    r = np.linspace(0.6, 1.0, 5)
    b, rr = np.broadcast_arrays(beta[..., None], r)
    kappa = normal_kappa(b, rr)
    ok = np.isfinite(kappa) & (kappa > 0)
    got = beta_from_frequency(
        lever, contact_frequencies(lever, kappa[ok], rr[ok], modes=(1, 2)), np.array([1, 2])
    )
    assert ok.sum() > 300
    np.testing.assert_allclose(got[:, 0], b[ok], rtol=0, atol=1e-9)
    assert np.all(got[:, 1] > got[:, 0] + 1.0)
    # The same pixels in one call and one at a time (chunks mixing finished and unfinished
    # pixels of the scan's blocks give each pixel its own brackets).
    some = np.flatnonzero(ok.ravel())[::9]
    one_by_one = [
        contact_frequencies(lever, kappa.ravel()[i], rr.ravel()[i], modes=(1, 2)) for i in some
    ]
    together = contact_frequencies(lever, kappa.ravel()[some], rr.ravel()[some], modes=(1, 2))
    assert np.array_equal(np.array(one_by_one), together)
