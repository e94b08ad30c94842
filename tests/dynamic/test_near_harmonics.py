"""Tests of the harmonic (Jacobi-Anger) paths of the N(r̄, φ) quadrature and their special
functions.

The near-field θ integrals are summed over the harmonics of g with J_2m(s) and W_2m(s) weights;
here they are checked against the θ-direct trapezoidal rule they replaced (written out below:
g resampled by FFT onto nt nodes, cos(s cos θ) and the line weight W(s cos θ) at every node).
The Bessel functions of complex argument (Miller's method) are checked against scipy's AMOS,
the WA harmonics W_n (a sum of squared spherical Bessel functions) against scipy quadrature and
the FFT of the line weight on a fine θ grid, and the reduced far-field basis against the full
one.
"""

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy import integrate, special

from contactres import Material
from contactres.dynamic import prepare
from contactres.dynamic._exact import exact_n, galerkin_plan, galerkin_size, near_bessel
from contactres.dynamic._farfield import far_basis, far_grid, low_rank
from contactres.dynamic._fartail import far_tail, head_grid
from contactres.dynamic._quadrature import (
    _COARSE_MARGINS,
    _n_theta_near,
    _near_margins,
    far_operator,
    far_operator_and_moments,
    functionals,
    near_theta_integrals,
)
from contactres.dynamic._weights import (
    bessel_even_sum,
    bessel_orders,
    by_real_columns,
    real_columns,
    spherical_bessel,
    wa_harmonic_sum,
    wa_harmonic_weights,
    wa_harmonic_weights_complex,
    wa_line_weight,
)


@pytest.fixture(scope="module", params=["A0.25", "Cu111"])
def table(request):
    if request.param == "A0.25":  # strongly anisotropic (001) face: 256 θ nodes, 4-fold
        m = Material.cubic_from_ratios(0.25, 0.25)
    else:  # (111) face: no 4-fold axis, harmonics 3j
        m = Material.crystal("Cu").rotated((1, 1, 1))
    return prepare(m, 0.02)


def _theta_direct(table, s, smax):
    """The former near field: θ-direct trapezoidal rule on nt nodes of [0, π), g resampled."""
    nt = _n_theta_near(smax)
    values = table.near_values
    n = values.shape[-1]
    h = np.fft.fft(values, axis=-1)
    out = np.zeros((values.shape[0], nt), dtype=complex)
    half = min(n, nt) // 2
    out[:, :half] = h[:, :half]
    out[:, nt - half + 1 :] = h[:, n - half + 1 :]
    vals = np.fft.ifft(out, axis=-1) * (nt / n)
    z = s[:, :, None] * np.cos(np.pi * np.arange(nt) / nt)[None, None, :]
    dth = 2 * np.pi / nt
    c1 = np.einsum("akt,kt->ak", np.cos(z), vals) * dth
    cw = np.einsum("akt,kt->ak", wa_line_weight(z), vals) * dth
    return c1, cw, np.mean(vals, axis=1) * 2 * np.pi


def test_near_harmonic_sums_equal_the_theta_direct_rule(table):
    ka = np.array([0.05, 0.7, 2.0, 4.0, 6.9])
    s = ka[:, None] * table.near_kappa[None, :]
    smax = float(ka.max() * np.max(np.abs(table.near_kappa)))
    c1, cw, mean0 = near_theta_integrals(table, s, smax)
    r1, rw, r0 = _theta_direct(table, s, smax)
    scale = np.max(np.abs(r0))  # ∫ |g − g∞| dθ sets the size of every integral at a node
    np.testing.assert_allclose(mean0, r0, rtol=0, atol=1e-14 * scale)
    np.testing.assert_allclose(c1, r1, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(cw, rw, rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize(
    "z",
    [
        np.linspace(0.01, 30.0, 300) * (1 + 0.1j),  # the near-field contour
        np.linspace(0.01, 25.0, 200) + 2j,
        np.linspace(1e-3, 25.0, 400),  # the real hand-over segment
        # zeros of J0, J1, J2 and tiny arguments: no division by a vanishing J
        np.array([2.404825557695773, 3.8317059702075125, 5.135622301840683, 1e-6, 1e-6 + 1e-7j]),
    ],
)
def test_bessel_orders_match_scipy(z):
    got = bessel_orders(60, z)
    ref = special.jv(np.arange(61)[:, None], z[None, :])
    bound = 1e-12 * np.abs(ref) + 1e-15 * np.max(np.abs(ref), axis=0)
    assert np.all(np.abs(got - ref) <= bound)


def test_wa_harmonics_against_quad_up_to_high_order():
    """Up to s = 120 and n = 92 (the far field's largest), where an FFT of the line weight on a
    θ grid too coarse for W(s cos θ) had aliased by ~2e-4."""
    s = np.array([0.0, 1e-3, 7.0, 60.0, 120.0])
    W = wa_harmonic_weights(s, 92)
    for n in (0, 10, 40, 80, 92):
        ref = [
            integrate.quad(
                lambda r, n=n, ss=ss: special.jv(n, ss * r) * r / math.sqrt(1 - r * r),
                0,
                1,
                limit=2000,
                epsabs=1e-14,
            )[0]
            for ss in s
        ]
        np.testing.assert_allclose(W[n // 2], ref, rtol=0, atol=1e-11)


def test_complex_wa_harmonics_are_the_fourier_coefficients_of_the_line_weight():
    z = np.array([3 + 0.4j, 9 + 1.5j, 24 - 2j, 12 + 0.5j, 0.01 + 1e-3j, 17.0 + 0j])
    n_t = 512
    theta = np.pi * np.arange(n_t) / n_t
    coef = np.fft.fft(wa_line_weight(np.multiply.outer(z, np.cos(theta))), axis=-1) / n_t
    k = np.arange(31)
    ref = (coef[:, k] * np.where(k % 2 == 0, 1.0, -1.0)).T
    np.testing.assert_allclose(wa_harmonic_weights_complex(z, 30), ref, rtol=0, atol=1e-13)


def test_bessel_even_sum_against_amos():
    """Σ_m J_2m(z) c_m summed during Miller's pass against scipy's jv (AMOS) order by order,
    on the near-field contour's kind of arguments (complex, small to ~20, and real)."""
    rng = np.random.default_rng(7)
    z = np.concatenate(
        [
            rng.uniform(1e-3, 20, (3, 40)) + 1j * rng.uniform(0, 3, (3, 40)),
            rng.uniform(1e-3, 20, (1, 40)) + 0j,
        ]
    )
    c = rng.normal(size=(24, 40)) + 1j * rng.normal(size=(24, 40))
    ref = sum(special.jv(2 * m, z) * c[m] for m in range(24))
    scale = np.sum(np.abs(c), axis=0)
    assert np.all(np.abs(bessel_even_sum(z, c) - ref) <= 1e-14 * scale)
    real = z[-1].real
    got = bessel_even_sum(real, c[:, 0].real)
    ref = sum(special.jv(2 * m, real) * c[m, 0].real for m in range(24))
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-14 * np.sum(np.abs(c[:, 0].real)))


def test_wa_harmonic_sum_against_the_fourier_coefficients_of_the_line_weight():
    """Σ_k W_2k(z) c_k with the sums turned (one pass over the orders) against the W_2k as the
    Fourier coefficients of the line weight W(z cos θ) (an FFT on a fine θ grid)."""
    z = np.array([3 + 0.4j, 9 + 1.5j, 12 + 0.5j, 0.01 + 1e-3j, 17.0 + 0j])
    n_t = 512
    theta = np.pi * np.arange(n_t) / n_t
    coef = np.fft.fft(wa_line_weight(np.multiply.outer(z, np.cos(theta))), axis=-1) / n_t
    k = np.arange(25)
    weights = (coef[:, k] * np.where(k % 2 == 0, 1.0, -1.0)).T  # (25, n_z)
    c = np.random.default_rng(3).normal(size=(25, z.size)) * (0.7 ** k[:, None])
    ref = np.sum(weights * c, axis=0)
    np.testing.assert_allclose(wa_harmonic_sum(z, c), ref, rtol=0, atol=1e-13)


def _wa_reference(z, zmax):
    """Twelve arguments of ``z``, the line weight's Fourier coefficients at them (an FFT of
    :func:`wa_line_weight` over θ, the reference of :func:`wa_harmonic_sum`) and seeded
    decaying coefficients to sum them with."""
    n_c = int(0.6 * zmax) + 10
    w = np.concatenate([z[0, :6], z[3, :6]])
    n_t = 1024
    theta = np.pi * np.arange(n_t) / n_t
    coef = np.fft.fft(wa_line_weight(np.multiply.outer(w, np.cos(theta))), axis=-1) / n_t
    k = np.arange(n_c)
    weights = (coef[:, k] * np.where(k % 2 == 0, 1.0, -1.0)).T
    cw = np.random.default_rng(5).normal(size=(n_c, w.size)) * (0.9 ** k[:, None])
    return w, weights, cw


@pytest.mark.parametrize("zmax", [21.0, 60.0])
def test_near_sums_with_the_margins_of_the_near_field(zmax):
    """The continued fractions started 20 and 10 orders above the arguments, as the near field
    does (:mod:`contactres.dynamic._quadrature`), against scipy's jv (AMOS) and the Fourier
    coefficients of the line weight, on the near field's kind of arguments: complex with
    Im <= 3 (the contour) and real (the hand-over segment), up to 21 (k_l a = 2) and 60 (the
    checked range beyond it); independent references, so that a margin too short shows (15
    and 7 orders fail these bounds)."""
    rng = np.random.default_rng(11)
    z = np.concatenate(
        [
            rng.uniform(1e-3, zmax / 2, (2, 30)) + 1j * rng.uniform(0, 3, (2, 30)),
            rng.uniform(1e-3, zmax, (2, 30)) + 0j,
        ]
    )
    # Few coefficients, so that the even sum's start is set by the margin (1.3 |z| + margin),
    # not by its floor 2K + 12 (review R24b: with 0.6 zmax + 10 of them no margin showed).
    n_e = 8
    c = rng.normal(size=(n_e, 30)) + 1j * rng.normal(size=(n_e, 30))
    ref = sum(special.jv(2 * m, z) * c[m] for m in range(n_e))
    scale = np.sum(np.abs(c), axis=0)
    assert np.all(np.abs(bessel_even_sum(z, c, margin=20) - ref) <= 1e-14 * scale)
    real = z[2:].real
    ref = sum(special.jv(2 * m, real) * c[m].real for m in range(n_e))
    got = bessel_even_sum(real, c.real, margin=20)
    assert np.all(np.abs(got - ref) <= 1e-14 * np.sum(np.abs(c.real), axis=0))
    w, weights, cw = _wa_reference(z, zmax)
    np.testing.assert_allclose(
        wa_harmonic_sum(w, cw, margin=10), np.sum(weights * cw, axis=0), rtol=0, atol=3e-14
    )


def test_spherical_bessel_upward_recurrence_at_large_real_arguments():
    """Real z beyond every order take the upward recurrence: against AMOS up to z = 700 (which
    itself scatters by ~2e-14 of the largest |j_p| there, hence the absolute bound)."""
    z = np.concatenate([np.linspace(30.0, 700.0, 3000), [33.0, 33.0001]])
    got = spherical_bessel(32, z)
    for p in range(33):
        ref = np.sqrt(np.pi / (2 * z)) * special.jv(p + 0.5, z)
        assert np.all(np.abs(got[p] - ref) <= 1e-12 * np.abs(ref) + 1e-13 * np.max(np.abs(ref)))


def test_low_rank_reproduces_the_far_coefficients(table):
    c = table.far_coeffs
    matrix = np.concatenate([c.real, c.imag])
    left, right = low_rank(matrix)
    assert right.shape[0] <= matrix.shape[1]
    np.testing.assert_allclose(right @ right.T, np.eye(right.shape[0]), atol=1e-14)
    assert np.max(np.abs(left @ right - matrix)) <= 1e-14 * np.max(np.abs(matrix))


def test_exact_far_field_on_the_reduced_basis_equals_the_full_one(table, monkeypatch):
    """exact_n with the far-field basis projected on the leading directions of the
    coefficients against exact_n on the full Chebyshev basis (no truncation, identity as
    directions): the same N to round-off."""
    import contactres.dynamic._exact as exact

    ka = np.array([0.4, 1.5, 3.0])
    size = galerkin_size(float(ka.max()))
    fb = far_basis(table, ka)
    plan = galerkin_plan(table, size, fb.s)
    reduced = exact_n(table, ka, size, far=fb, plan=plan)
    monkeypatch.setattr(exact, "low_rank", lambda m: (m, np.eye(m.shape[1])))
    full = exact_n(table, ka, size, far=fb, plan=plan)
    np.testing.assert_allclose(reduced, full, rtol=1e-13)


def test_far_tail_by_moments_equals_the_node_by_node_sum(table):
    """The far field beyond 2 T₁ × the largest k a summed by the moments of its polynomial
    basis (contactres.dynamic._fartail), with the basis built on the head of the grid alone
    (and the operator of the functionals too, with the moments of its weights), against the
    same integrals summed node by node on the whole grid: the six functionals and N_exact agree
    to round-off."""
    ka = np.array([0.05, 0.4, 1.5, 3.0])
    grid = far_grid(table, float(ka.min()))
    tail = far_tail(table, grid, float(ka.max()))
    assert tail is not None and 0 < tail.split < grid.s.size // 2  # most of the grid
    op = far_operator(table, grid)
    full = functionals(table, ka, far=far_basis(table, ka, grid), far_op=op)
    head = far_basis(table, ka, head_grid(grid, tail))
    by_moments = functionals(table, ka, far=head, far_op=op, tail=tail)
    # The operator on the head alone with the moments of the weights over the tail.
    op_head, moments = far_operator_and_moments(table, grid, tail)
    split = functionals(table, ka, far=head, far_op=op_head, tail=tail, far_moments=moments)
    for name in full:
        np.testing.assert_allclose(by_moments[name], full[name], rtol=1e-13)
        np.testing.assert_allclose(split[name], full[name], rtol=1e-13)
    size = galerkin_size(float(ka.max()))
    node_by_node = exact_n(table, ka, size, far=far_basis(table, ka, grid))
    plan = galerkin_plan(table, size, grid.s, tail=tail)
    np.testing.assert_allclose(
        exact_n(table, ka, size, far=head, plan=plan), node_by_node, rtol=1e-13
    )


def test_far_products_formed_by_blocks_of_pairs_are_those_of_all_pairs_at_once(table, monkeypatch):
    """galerkin_plan forms the far-field products j_p j_q and their tail moments a few pairs at
    a time (issue 31: all at once was a 0.96 GB temporary). Against the products of every pair
    written out here from spherical_bessel and the tail's moments of all of them in one call,
    with blocks of 7 pairs (many blocks, a short last one) and with one block: the products the
    same to the bit (those of the head, the tail being read by its moments), the moments to
    round-off of their sums (a BLAS product of 7 rows may group a sum otherwise)."""
    import contactres.dynamic._exact as exact

    ka = np.array([0.4, 3.0])
    grid = far_grid(table, float(ka.min()))
    tail = far_tail(table, grid, float(ka.max()))
    assert tail is not None
    size = galerkin_size(float(ka.max()))
    monkeypatch.setattr(exact, "_PRODUCT_BLOCK", 7 * grid.s.size)
    blocks = galerkin_plan(table, size, grid.s, tail=tail)
    assert blocks.pairs.shape[1] % 7 != 0 and blocks.pairs.shape[1] > 14
    monkeypatch.setattr(exact, "_PRODUCT_BLOCK", blocks.pairs.shape[1] * grid.s.size)
    whole = galerkin_plan(table, size, grid.s, tail=tail)
    js = spherical_bessel(int(blocks.orders[-1]), grid.s)[blocks.orders]
    products = js[blocks.pairs[0]] * js[blocks.pairs[1]]
    moments = tail.moments(products)
    # The round-off scale of each moment: the sum of its terms' magnitudes.
    terms = (np.abs(products[:, tail.split :]) @ np.abs(tail.chebyshev)).T
    for plan in (blocks, whole):
        assert np.array_equal(plan.far_products, products[:, : tail.split])
        assert plan.far_moments is not None
        assert np.all(np.abs(plan.far_moments - moments) <= 1e-14 * terms)
    no_tail = galerkin_plan(table, size, grid.s)
    assert no_tail.far_moments is None and np.array_equal(no_tail.far_products, products)


def test_real_columns_finds_the_trailing_real_segment():
    z = np.array([[1 + 1j, 2 + 0j, 3 + 0j], [4 + 0j, 5 + 0j, 6 + 0j]])
    assert real_columns(z) == 1  # column 0 has a nonzero imaginary part, 1 and 2 do not
    assert real_columns(z.real) == 0
    assert real_columns(np.array([1.0 + 0j, 2 + 1e-300j])) == 2


def test_sums_split_at_the_real_columns_against_amos(table):
    """The near field's sums with its real hand-over segment in real arithmetic: against
    scipy's jv (AMOS) term by term, and against the same sums with every column complex."""
    ka = np.array([0.05, 0.9, 4.0])
    s = ka[:, None] * table.near_kappa[None, :]
    assert 0 < real_columns(s) < s.shape[1]  # the contour, then the real segment
    c = np.random.default_rng(11).normal(size=(20, s.shape[1])) * (1 + 0.5j)
    ref = sum(special.jv(2 * m, s) * c[m] for m in range(20))
    scale = np.sum(np.abs(c), axis=0)
    got = by_real_columns(bessel_even_sum, s, c)
    assert np.all(np.abs(got - ref) <= 1e-14 * scale)
    split = by_real_columns(wa_harmonic_sum, s, c)
    assert np.all(np.abs(split - wa_harmonic_sum(s, c)) <= 1e-14 * scale)


def test_near_bessel_against_scipy_spherical_jn(table):
    """j_p at the near nodes, the real segment in real arithmetic, against scipy's spherical_jn
    (AMOS; the bound of the test of spherical_bessel: AMOS itself scatters near the zeros)."""
    ka = np.array([0.05, 1.3, 4.9])
    got = near_bessel(table, ka, 24)
    s = ka[:, None] * table.near_kappa[None, :]
    for p in (0, 1, 7, 24):
        ref = special.spherical_jn(p, s)
        assert np.all(np.abs(got[p] - ref) <= 1e-12 * np.abs(ref) + 1e-13 * np.max(np.abs(ref)))


@pytest.mark.parametrize("margin", [20, 30])
@pytest.mark.parametrize("zmax", [1.0, 8.0, 21.0, 60.0])
def test_bessel_even_sum_leaves_out_only_terms_below_round_off(zmax, margin):
    """More coefficients c_m than the continued fraction's start reaches (2m up to ~40 orders
    beyond 1.3 |z| + margin, every c_m of order one, none decaying): the terms of the orders
    left out are below round-off. Against scipy's jv (AMOS) term by term, on complex arguments
    with Im <= 3 (the contour) and real ones (the hand-over segment); measured <= 2.2e-15 of
    Σ|c| (margin 20, |z| <= 21)."""
    rng = np.random.default_rng(3)
    z = np.concatenate(
        [
            rng.uniform(1e-3, zmax, (2, 40)) + 1j * rng.uniform(0, 3, (2, 40)),
            rng.uniform(1e-3, zmax, (2, 40)) + 0j,
        ]
    )
    n_c = int(0.65 * zmax + margin / 2) + 20
    assert 2 * (n_c - 1) > 1.3 * zmax + margin + 30  # orders beyond the start, to be left out
    c = rng.normal(size=(n_c, 40)) + 1j * rng.normal(size=(n_c, 40))
    ref = sum(special.jv(2 * m, z) * c[m] for m in range(n_c))
    got = bessel_even_sum(z, c, margin=margin)
    assert np.all(np.abs(got - ref) <= 1e-14 * np.sum(np.abs(c), axis=0))
    real = z[2:].real
    ref = sum(special.jv(2 * m, real) * c[m].real for m in range(n_c))
    got = bessel_even_sum(real, c.real, margin=margin)
    assert np.all(np.abs(got - ref) <= 1e-14 * np.sum(np.abs(c.real), axis=0))


@pytest.mark.parametrize("zmax", [21.0, 60.0])
def test_near_sums_with_the_coarse_margins_of_rtol_1e_4(zmax):
    """The near field's continued fractions on a table prepared for rtol >= 1e-4 start 10 and
    5 orders above the arguments (_quadrature._COARSE_MARGINS): against scipy's jv (AMOS) and
    the Fourier coefficients of the line weight, within 1e-8 of Σ|c| (1e-4 of that rtol;
    measured 5e-10 and 9e-10; 6 and 3 orders fail it)."""
    even, wa = _COARSE_MARGINS
    rng = np.random.default_rng(11)
    z = np.concatenate(
        [
            rng.uniform(1e-3, zmax / 2, (2, 30)) + 1j * rng.uniform(0, 3, (2, 30)),
            rng.uniform(1e-3, zmax, (2, 30)) + 0j,
        ]
    )
    c = rng.normal(size=(8, 30)) + 1j * rng.normal(size=(8, 30))
    ref = sum(special.jv(2 * m, z) * c[m] for m in range(8))
    assert np.all(np.abs(bessel_even_sum(z, c, margin=even) - ref) <= 1e-8 * np.sum(abs(c), 0))
    w, weights, cw = _wa_reference(z, zmax)
    got = wa_harmonic_sum(w, cw, margin=wa)
    assert np.all(np.abs(got - np.sum(weights * cw, axis=0)) <= 1e-8 * np.sum(np.abs(cw), 0))


def test_near_field_of_a_rtol_1e_4_table_against_the_round_off_margins():
    """The near-field θ integrals of a table prepared for rtol 1e-4 (coarse margins) against
    those of the same table taken as one of an explicit resolution (round-off margins), and
    both against the θ-direct rule: within 1e-8 of ∫|g − g∞| dθ."""
    t = prepare(Material.cubic_from_ratios(0.5, 0.25), 0.02, 1e-4)
    assert _near_margins(t) == _COARSE_MARGINS
    fine = replace(t, rtol=None)
    assert _near_margins(fine) != _COARSE_MARGINS
    ka = np.array([0.05, 0.7, 2.0, 4.9])
    s = ka[:, None] * t.near_kappa[None, :]
    smax = float(ka.max() * np.max(np.abs(t.near_kappa)))
    c1, cw, mean0 = near_theta_integrals(t, s, smax)
    f1, fw, _ = near_theta_integrals(fine, s, smax)
    r1, rw, _ = _theta_direct(t, s, smax)
    scale = np.max(np.abs(mean0))
    for got in (c1, f1):
        np.testing.assert_allclose(got, r1, rtol=0, atol=1e-8 * scale)
    for got in (cw, fw):
        np.testing.assert_allclose(got, rw, rtol=0, atol=1e-8 * scale)
    assert np.max(np.abs(c1 - f1)) > 0  # the margins differ, so do the sums (in the last bits)


@pytest.mark.parametrize(("margin", "bound"), [(10, 3e-7), (20, 5e-13)])
@pytest.mark.parametrize("zmax", [14.0, 20.0, 40.0])
def test_even_sum_drops_a_coefficient_at_the_start_within_the_largest_jn_beyond(
    margin, bound, zmax
):
    """One coefficient c_K = 1 at the order 2K = top where the continued fraction starts (top
    = 2 ceil((1.3 max|z| + margin)/2), the first order bessel_even_sum leaves out): the sum
    against scipy's jv misses by at most max_{n >= top} |J_n(z)| (per |c_K| = Σ|c|), which is
    below 3e-7 at the coarse margin 10 and 5e-13 at margin 20 (|z| up to 40, |Im z| <= 3).
    The 8 smooth coefficients of the test above never reach that order."""
    rng = np.random.default_rng(29)
    z = np.concatenate(
        [
            rng.uniform(1e-3, zmax, 40) + 0j,
            np.linspace(zmax / 2, zmax, 9) + 0j,
            rng.uniform(1e-3, zmax - 3, 20) + 1j * rng.uniform(0, 3, 20),
        ]
    )
    top = 2 * math.ceil((1.3 * np.max(np.abs(z)) + margin) / 2)
    c = np.zeros(top // 2 + 1)
    c[top // 2] = 1.0
    ref = special.jv(top, z)
    beyond = np.max(np.abs(special.jv(np.arange(top, top + 60)[:, None], z)), axis=0)
    assert np.max(beyond) <= bound
    # The dropping is exercised: the left-out term is far above round-off at the largest |z|.
    assert np.max(np.abs(ref)) > 1e-6 * bound
    err = np.abs(bessel_even_sum(z, c, margin=margin) - ref)
    assert np.all(err <= 1.01 * beyond + 1e-15)


@pytest.mark.parametrize("n_m", [1, 3])
def test_near_pair_sums_against_the_sum_written_out(n_m):
    """The near-field pair sums Σ_k left[p, a, k] right[q, a, k] h[k, m] of a plan's pairs
    (p <= q, sorted by p, with a gap in the run of one first order): for several harmonics
    (one product per pair) and for one, folded into ``left`` (the layered punch's film: a
    batched Gram product of all the orders), both against the triple product summed by
    einsum."""
    from contactres.dynamic._exact import _gram_pair_sums, _near_pair_sums

    rng = np.random.default_rng(7)
    n_p, na, nk = 6, 3, 40
    left = rng.normal(size=(n_p, na, nk)) + 1j * rng.normal(size=(n_p, na, nk))
    right = rng.normal(size=(n_p, na, nk)) + 1j * rng.normal(size=(n_p, na, nk))
    h = rng.normal(size=(nk, n_m)) + 1j * rng.normal(size=(nk, n_m))
    pairs = [(p, q) for p in range(n_p) for q in range(p, n_p) if (p, q) != (1, 3)]
    ti, tj = (np.array(x) for x in zip(*pairs, strict=True))
    want = np.einsum("tak,tak,km->tam", left[ti], right[tj], h)
    if n_m == 1:
        got = _gram_pair_sums(left * h[:, 0], right, ti, tj)[..., None]
    else:
        got = _near_pair_sums(left, right, ti, tj, h)
    assert got.shape == (ti.size, na, n_m)
    np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-13 * np.max(np.abs(want)))
