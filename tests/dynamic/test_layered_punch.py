"""The dynamic rigid flat punch on a layered substrate (contactres.dynamic._layered_punch).

Anchors, each independent of the code under test: the homogeneous isotropic disk of the
Fredholm solution (test_rigid_disk_isotropic.py, Luco & Westmann's equation solved afresh);
Boussinesq's static punch 2aE*; the limits h -> 0 (substrate) and h -> ∞ (film); passivity;
and a second route for a lossy layered case: the Galerkin matrix integrated here on the real
wavenumber axis by an adaptive Gauss-Legendre rule (adaptive_quadrature.py) from the public
surface_green.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from adaptive_quadrature import adaptive_gauss
from scipy import special
from test_rigid_disk_isotropic import fredholm_disk

from contactres import LayeredMaterial, Material, dcsf, surface_green, viscoelastic
from contactres.dynamic._layered_nodes import own_bessel, own_rows
from contactres.dynamic._layered_punch import (
    layered_dcsf,
    layered_punch_stiffness,
    punch_resolution,
)
from contactres.errors import ContactresInputError

QUARTZ = Material.isotropic(72e9, 0.17, density=2650.0, name="quartz")
PMMA = Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA")
A = 5e-6


def _e_star(m):
    c11, c12 = np.real(m.C[0, 0]), np.real(m.C[0, 1])
    g = np.real(m.C[3, 3])
    nu = c12 / (c11 + c12)
    return 2 * g * (1 + nu) / (1 - nu**2), nu


def _freq(m, ksa, a=A):
    """Frequency (Hz) of the shear wave number k_s a in material m."""
    return ksa * np.sqrt(np.real(m.C[3, 3]) / m.density) / (2 * np.pi * a)


def test_static_homogeneous_is_boussinesq():
    for m in (QUARTZ, PMMA):
        e, _ = _e_star(m)
        k = layered_punch_stiffness(m, [1e-6, 3e-6])
        np.testing.assert_allclose(k, 2 * np.array([1e-6, 3e-6]) * e, rtol=1e-12)


@pytest.mark.parametrize("ksa", [0.3, 1.0, 2.0])
def test_homogeneous_and_film_equal_to_substrate_match_the_fredholm_disk(ksa):
    """Fredholm solution of Luco & Westmann's equation (accurate to < 1e-7, its own tests;
    measured here: < 1e-7); and a film of the substrate's own material reproduces the
    homogeneous punch to 1e-10 (issue 26, point 5; measured: 0 at every rtol tried, 1e-6 to
    1e-10: the film's reflection is zero and its correction vanishes)."""
    e, nu = _e_star(QUARTZ)
    f = _freq(QUARTZ, ksa)
    ref = fredholm_disk(ksa, nu) * 2 * A * e
    same = LayeredMaterial(QUARTZ, [(QUARTZ, 0.4 * A)])
    for m in (QUARTZ, same):
        assert abs(layered_punch_stiffness(m, A, f) / ref - 1) < 1e-6
    k_hom = layered_punch_stiffness(QUARTZ, A, f, rtol=1e-10)
    assert abs(layered_punch_stiffness(same, A, f, rtol=1e-10) / k_hom - 1) < 1e-10


def test_frequency_to_zero_reaches_the_static_punch():
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.1 * A)])
    k0 = layered_punch_stiffness(stack, A)
    ks = layered_punch_stiffness(stack, A, _freq(PMMA, np.array([1e-3, 2e-3])))
    dev = np.abs(ks / k0 - 1)
    # K − K₀ = i a₀ c + O(a₀²): first order in the frequency, through the damping
    assert dev[0] < 1e-2 and 1.8 < dev[1] / dev[0] < 2.2
    assert np.all(ks.imag > 0)


def test_thin_film_reaches_the_substrate_and_thick_film_the_film():
    k_sub = layered_punch_stiffness(QUARTZ, A, 20e6)
    dev_thin = [
        abs(layered_punch_stiffness(LayeredMaterial(QUARTZ, [(PMMA, t * A)]), A, 20e6) / k_sub - 1)
        for t in (0.04, 0.02, 0.01)
    ]
    # The film's share falls with its thickness, about in proportion (first order in h/a).
    assert dev_thin[2] < dev_thin[1] < dev_thin[0] and dev_thin[2] < 0.5 * dev_thin[0]
    # Thick lossy film: the waves reflected by the substrate die out, and the static share of
    # the substrate falls like a/h.
    lossy = PMMA.with_loss(0.1)
    f = _freq(PMMA, 2.0)
    k_film = layered_punch_stiffness(lossy, A, f)
    dev_thick = [
        abs(layered_punch_stiffness(LayeredMaterial(QUARTZ, [(lossy, t * A)]), A, f) / k_film - 1)
        for t in (4.0, 16.0)
    ]
    assert dev_thick[1] < dev_thick[0] / 3 and dev_thick[1] < 0.02


@pytest.mark.parametrize(
    "stack",
    [
        LayeredMaterial(QUARTZ, [(PMMA, 0.2 * A)]),
        LayeredMaterial(PMMA, [(QUARTZ, 0.2 * A)]),
        LayeredMaterial(QUARTZ, [(PMMA, 0.1 * A), (QUARTZ.with_loss(0.01), 0.3 * A)]),
    ],
    ids=["soft-on-stiff", "stiff-on-soft", "two-layers"],
)
def test_passive(stack):
    f = _freq(PMMA, np.linspace(0.1, 2.0, 6))
    k = layered_punch_stiffness(stack, A, f)
    assert np.all(k.imag > 0)


@pytest.mark.parametrize("film_over_a", [0.02, 0.2])
def test_default_resolution_converges(film_over_a):
    """Twice the nodes of the correction (measured: < 1e-10) and rtol = 1e-9 (a larger basis
    and a finer film table; measured: < 3e-9) move the default result less than its rtol."""
    stack = LayeredMaterial(QUARTZ, [(PMMA, film_over_a * A)])
    f = _freq(PMMA, np.array([0.5, 1.5]))
    res = punch_resolution(1e-6)
    base = layered_punch_stiffness(stack, A, f, resolution=res)
    fine = layered_punch_stiffness(stack, A, f, resolution=res.doubled())
    assert np.max(np.abs(base / fine - 1)) < 1e-8
    tight = layered_punch_stiffness(stack, A, f, rtol=1e-9)
    assert np.max(np.abs(base / tight - 1)) < 1e-6


def _real_axis_reference(stack, film, a, f, n_radial):
    """K by the Galerkin of the n = 0 pressure basis, its matrix integrated on the real axis.

    M_pq = 2π ∫₀^∞ g(s) j_p(s) j_q(s) ds (p, q = 0, 2, 4, ...), g = −C44_f η Ĝ_33(η), η = s/a,
    C44_f = Re C44 of the isotropic film (constants at f, complex allowed); split as
    g∞ + (g − g∞) with g∞ = C44_f (1 − ν*)/G* (Boussinesq, ν* = C12/(C11 + C12), G* = C44
    complex) and ∫ j_p² = π/(2(2p+1));
    the rest by adaptive_gauss (every panel's nodes in one call of surface_green) on [0, S_c]
    (breakpoints at the peaks of ``|g|`` found on a fine grid) and on [S_c, 400] (the tail
    beyond ~ (k a)²/S³ < 1e-7). K = 4π² a C44_f (M⁻¹)₀₀.
    """
    c44 = np.real(film.C[3, 3])
    nu = film.C[0, 1] / (film.C[0, 0] + film.C[0, 1])
    g_inf = c44 * (1 - nu) / film.C[3, 3]
    p = 2 * np.arange(n_radial)
    iu, ju = np.triu_indices(n_radial)

    def integrand(s):  # s: 1-D; shape (upper entries, s.size)
        g = -c44 * (s / a) * surface_green(stack, s / a, 0.0, f)[..., 2, 2]
        j = special.spherical_jn(p[:, None], s)
        return (g - g_inf) * (j[iu] * j[ju])

    s_c = 2.5 * 2 * np.pi * f * np.sqrt(film.density / c44) * a  # beyond the slowest wave
    grid = np.linspace(1e-6, s_c, 20001)
    mag = np.abs(-c44 * (grid / a) * surface_green(stack, grid / a, 0.0, f)[..., 2, 2])
    peaks = grid[1:-1][(mag[1:-1] > mag[:-2]) & (mag[1:-1] > mag[2:])]
    opts = dict(epsabs=1e-12, epsrel=1e-11)
    part1, _ = adaptive_gauss(integrand, 0.0, s_c, points=peaks, **opts)
    part2, _ = adaptive_gauss(integrand, s_c, 400.0, **opts)
    upper = part1 + part2 + np.where(iu == ju, g_inf * np.pi / (2 * (2 * p[iu] + 1)), 0)
    M = np.zeros((n_radial, n_radial), dtype=complex)
    M[iu, ju] = upper
    M[ju, iu] = upper
    return 4 * np.pi**2 * a * c44 * np.linalg.inv(2 * np.pi * M)[0, 0]


def test_lossy_stack_matches_a_real_axis_quadrature():
    """Light loss (Q⁻¹ = 1e-3) leaves sharp guided-mode peaks on the real axis; the reference
    resolves them adaptively, the code passes above them on its contour. Measured: 4.4e-9
    (the reference moves by 1e-13 with 16 radial terms instead of 12)."""
    q = 1e-3
    stack = LayeredMaterial(QUARTZ, [(PMMA, 0.2 * A)]).with_loss(q)
    f = _freq(PMMA, 1.5)
    ref = _real_axis_reference(stack, PMMA.with_loss(q), A, f, 12)
    k = layered_punch_stiffness(stack, A, f)
    assert abs(k / ref - 1) < 1e-7


def test_viscoelastic_film_with_unequal_losses_matches_a_real_axis_quadrature():
    """The built-in PMMA has unequal loss tangents in its channels (bulk and shear), so its
    kernel table is that of a reference (Re C, the shear loss) and the difference, static in
    closed form and dynamic on the path with its 1/s² tail, is added. Measured at 15 MHz: 9.2e-9
    on quartz (9.9e-9 at 1 MHz), 1.5e-10 for the homogeneous film."""
    pmma = viscoelastic.pmma()
    stack = LayeredMaterial(QUARTZ, [(pmma, 0.05 * A)])
    ref = _real_axis_reference(stack, pmma.at(15e6), A, 15e6, 12)
    k = layered_punch_stiffness(stack, A, 15e6)
    assert abs(k / ref - 1) < 1e-7 and k.imag > 0
    homogeneous = _real_axis_reference(pmma, pmma.at(15e6), A, 15e6, 12)
    assert abs(layered_punch_stiffness(pmma, A, 15e6) / homogeneous - 1) < 1e-7


def test_cubic_film_near_isotropy_equals_the_isotropic_film():
    """A cubic (111) film with A = 1 + 1e-7 (six-fold face: the angular harmonics path) against
    the isotropic film of the same C11, C12 (the axisymmetric path): they differ by O(A − 1)."""
    c11, c12, c44 = (np.real(PMMA.C[i, j]) for i, j in ((0, 0), (0, 1), (3, 3)))
    cubic = Material.cubic(c11, c12, c44 * (1 + 1e-7), density=PMMA.density).rotated((1, 1, 1))
    f = np.array([0.0, _freq(PMMA, 1.5)])
    iso = layered_punch_stiffness(LayeredMaterial(QUARTZ, [(PMMA, 0.2 * A)]), A, f)
    cub = layered_punch_stiffness(LayeredMaterial(QUARTZ, [(cubic, 0.2 * A)]), A, f)
    assert np.max(np.abs(cub / iso - 1)) < 1e-6


def test_layered_dcsf_is_paper_1s_exact_dcsf_on_a_homogeneous_solid():
    """Against contactres.dcsf (model "exact"), lossless and with Q⁻¹ = 0.02 (then DCSF(0) =
    1 + iQ⁻¹: K_st of the undamped constants), on the homogeneous solid and on a film of its
    own material."""
    ksa = np.array([0.0, 0.5, 1.5])
    for q in (0.0, 0.02):
        m = QUARTZ.with_loss(q) if q else QUARTZ
        got = layered_dcsf(m, A, _freq(QUARTZ, ksa))
        ref = dcsf(QUARTZ, ksa, model="exact", loss=q, wavenumber="shear")
        np.testing.assert_allclose(got, ref, rtol=1e-6, atol=0)
        # Film = substrate (issue 26, point 5): 1e-10 of the largest |DCSF|, both routes at
        # rtol 1e-10 (measured: 1.3e-15).
        tight = dcsf(QUARTZ, ksa, model="exact", loss=q, wavenumber="shear", rtol=1e-10)
        same = LayeredMaterial(m, [(m, 0.4 * A)])
        film = layered_dcsf(same, A, _freq(QUARTZ, ksa), rtol=1e-10)
        assert np.max(np.abs(film - tight)) < 1e-10 * np.max(np.abs(tight))
    stack = LayeredMaterial(QUARTZ, [(viscoelastic.pmma(), 0.05 * A)])
    with pytest.raises(ContactresInputError, match="static limit"):
        layered_dcsf(stack, A, 15e6)


def test_the_curves_of_k_a_alone_refuse_a_layered_or_viscoelastic_solid_naming_the_route():
    """Issue 26, point 3: a DCSF of a viscoelastic or layered solid is a function of the
    frequency, not of k a alone; the k a functions say so and name the functions that take it."""
    from contactres import dcsf, tangential_dcsf

    for m in (viscoelastic.pmma(), LayeredMaterial(QUARTZ, [(PMMA, 0.2 * A)])):
        for curve in (dcsf, tangential_dcsf):
            with pytest.raises(ContactresInputError, match="not on k a alone") as info:
                curve(m, 0.5)
            assert "layered_dcsf" in str(info.value) and "\n" not in str(info.value)


def test_bad_input():
    with pytest.raises(ContactresInputError, match="direction"):
        layered_punch_stiffness(QUARTZ, A, 1e6, direction="sideways")
    with pytest.raises(ContactresInputError, match="densities"):
        layered_punch_stiffness(LayeredMaterial(Material.isotropic(1e9, 0.3), [(PMMA, A)]), A, 1e6)
    with pytest.raises(ContactresInputError):
        layered_punch_stiffness(QUARTZ, -1.0)


@pytest.mark.parametrize("rows", [slice(0, 13, 2), np.array([3, 1, 12, 4])])
def test_own_bessel_rows_are_scipys_on_each_points_nodes(rows):
    # Points whose own nodes mix complex and real runs in every order (and one of a single
    # node), each followed by a grid node that is not its own: the rows gathered from the two
    # parts must be j_p at that point's own nodes, in order (a misplaced run is off by O(1),
    # far above round-off).
    rng = np.random.default_rng(7)

    def run(n, real):
        x = rng.uniform(0.05, 20.0, n)
        return x if real else x + 1j * rng.uniform(-1.0, 1.0, n)

    points = [
        np.concatenate([run(9, False), run(5, True)]),
        run(6, True),
        run(7, False),
        np.concatenate([run(3, True), run(4, False), run(2, True)]),
        run(1, False),
    ]
    nodes = {i: SimpleNamespace(s=np.append(s, 99.0), n_own=s.size) for i, s in enumerate(points)}
    parts, runs = own_bessel(12, nodes)
    orders = np.arange(13)[rows]
    for s, point_runs in zip(points, runs, strict=True):
        expected = special.spherical_jn(orders[:, None], s.astype(complex)[None, :])
        got = own_rows(parts, point_runs, rows)
        assert got.shape == expected.shape
        # |j_p(z)| <= e^{|Im z|} <= e: round-off relative to that bound.
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-13 * np.e)


def test_film_bessel_functions_held_for_a_grown_basis_and_let_go_where_none_can_use_them():
    """The layered punch lets the film's Bessel functions go once the correction's own are
    made (a smaller peak of memory, fewer page faults) where they cannot serve a larger basis
    (their highest order that of the basis they were made for: a first call, extra 0), and
    holds them where they were computed for a grown basis (extra > 0, as _punch's later
    calls). Held: the grown basis uses them as they are (the same arrays, not computed
    again), and its matrix agrees with that size formed from scratch (no pair reused, its
    own highest order) to round-off. Let go: the grown basis's orders pass theirs, so it
    computes its own in either case, and its matrix is the same, bit for bit, whether they
    were let go or held."""
    from contactres.dynamic._exact import GalerkinSize
    from contactres.dynamic._layered_punch import (
        _far_field,
        _film_matrices,
        _let_go_film_bessel,
    )
    from contactres.dynamic._table import prepare

    table = prepare(PMMA)
    ksa = np.linspace(0.0, 2.0, 9)
    far = _far_field(table, ksa[ksa > 0])
    fresh, _, _ = _film_matrices(table, ksa, GalerkinSize(14, 0), far)
    scale = np.max(np.abs(fresh))
    # Computed for a basis grown by 8 radial terms (16 orders): held, and used as they are.
    _, plan, known = _film_matrices(table, ksa, GalerkinSize(10, 0), far, None, 8)
    assert known[3][0].shape[0] - 1 == plan.orders[-1] + 16
    assert _let_go_film_bessel(known, int(plan.orders[-1])) is known
    held, grown_plan, grown = _film_matrices(table, ksa, GalerkinSize(14, 0), far, known, 3)
    assert grown_plan.orders[-1] > plan.orders[-1]
    assert grown[3][0] is known[3][0] and grown[3][1] is known[3][1]
    np.testing.assert_allclose(held, fresh, rtol=1e-13, atol=1e-13 * scale)
    # Computed for this basis alone (extra 0): let go, and not needed by the grown basis.
    _, plan, known = _film_matrices(table, ksa, GalerkinSize(10, 0), far)
    assert known[3][0].shape[0] - 1 == plan.orders[-1]
    let_go = _let_go_film_bessel(known, int(plan.orders[-1]))
    assert let_go[3] is None and all(x is y for x, y in zip(let_go[:3], known[:3], strict=True))
    kept, _, _ = _film_matrices(table, ksa, GalerkinSize(14, 0), far, known, 3)
    again, _, grown = _film_matrices(table, ksa, GalerkinSize(14, 0), far, let_go, 3)
    assert grown[3][0].shape[0] - 1 == grown_plan.orders[-1] + 6
    assert np.array_equal(again, kept)
    np.testing.assert_allclose(again, fresh, rtol=1e-13, atol=1e-13 * scale)
