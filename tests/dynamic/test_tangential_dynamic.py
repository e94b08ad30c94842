"""The exact dynamic tangential stiffness (contactres.dynamic._tangential_galerkin and its API).

Independent checks: the isotropic reference written in the tests (tangential_isotropic_reference,
its own Fourier-space Lamb/Cerruti kernel, basis and contour; nothing from contactres), the
first-order low-frequency damping c_t(0) computed a third way (real-axis quad + Rayleigh
residue), the static solution of tangential_static (a different solver: eigen-decomposition,
its own harmonics and basis growth), reciprocity (K symmetric), passivity, the covariance of K
under a rotation of the in-plane axes, the 4-fold symmetry of a cubic (001) face, continuity
at A = 1 ± 1e-9, convergence when every discretisation is doubled, reciprocity of the
in-plane kernel at complex wavenumbers and the table against one fine θ grid evaluated directly.
"""

import math
import pickle

import numpy as np
import pytest
from tangential_isotropic_reference import low_frequency_damping, tangential_disk

import contactres as cr
from contactres.dynamic._table import Resolution
from contactres.dynamic._tangential_galerkin import (
    TangentialSize,
    prepare_tangential,
    tangential_per_a,
    tangential_size,
)
from contactres.dynamic._tangential_static import tangential_stiffness_static
from contactres.dynamic._tangential_stiffness import (
    tangential_contact_stiffness,
    tangential_dcsf,
    two_body_contact_stiffness,
)
from contactres.materials import Material


def _iso(nu, G=30e9, density=2500.0):
    return Material.isotropic(2 * G * (1 + nu), nu, density=density)


@pytest.fixture(scope="module")
def cu123():
    return Material.crystal("Cu").rotated((1, 2, 3))


@pytest.fixture(scope="module")
def quartz():
    return cr.at_cut_quartz()


# ------------------------------------------------------------------ isotropic, independent
@pytest.mark.parametrize("nu", [0.17, 0.25, 1 / 3])
def test_isotropic_against_independent_reference(nu):
    """K_t(a₀)/K_t0 against the independent Galerkin of the tests to 1e-6 (a₀ = 0.1-2)."""
    a0 = np.array([0.1, 0.5, 1.0, 2.0])
    got = tangential_dcsf(_iso(nu), a0)
    ref = np.array([tangential_disk(x, nu) for x in a0])
    assert np.max(np.abs(got - ref) / np.abs(ref)) < 1e-6


@pytest.mark.parametrize("nu", [0.17, 0.25])
def test_low_frequency_damping(nu):
    """Im K/(a₀ K₀) -> c_t(0) of the first-order perturbation (quad + Rayleigh residue); the
    correction is O(a₀²), removed by Richardson extrapolation from a₀ = 0.01 and 0.02."""
    a0 = np.array([0.01, 0.02])
    c = tangential_dcsf(_iso(nu), a0).imag / a0
    c0 = (4 * c[0] - c[1]) / 3
    assert c0 == pytest.approx(low_frequency_damping(nu), rel=1e-6)


@pytest.mark.parametrize("nu", [0.0, 0.25, 0.45])
def test_isotropic_static_is_mindlin(nu):
    """K_t0 = 8Ga/(2 − ν) (Mindlin 1949) to 1e-10, through the dynamic route at f = 0."""
    G, a = 30e9, 2e-6
    k = tangential_contact_stiffness(_iso(nu, G), a, 0.0)
    assert k.real == pytest.approx(8 * G * a / (2 - nu), rel=1e-10)
    assert k.imag == 0


# ------------------------------------------------------------------ anisotropic
@pytest.mark.parametrize("which", ["quartz"])
def test_static_limit_is_the_static_solver(which, request):
    """At k a = 0 the Galerkin gives the static tensor of tangential_static (another solver, to
    1e-10) to its rtol: < 1e-6 at the default (measured 7e-8 on Cu(123), from the
    harmonics |n| <= 6), < 1e-8 at rtol = 1e-9; at k a = 1e-4 Re K has moved by O((k a)²)."""
    m = request.getfixturevalue(which)
    # The fixed basis (12 harmonics, 4 radial terms): on AT-cut quartz within 1e-10 of the
    # static solver's result at rtol = 1e-10, and doubling its radial terms moves it by < 1e-10
    # (test_tangential_static.py::test_convergence_by_doubling; measured 7e-15 apart), at a
    # tenth of the CPU of the converged call (which grows the basis to 24 harmonics).
    ref = tangential_stiffness_static(m, 1.0, tensor=True, terms=(12, 4))
    scale = np.max(np.abs(ref))
    k = tangential_per_a(prepare_tangential(m), np.array([0.0, 1e-4]))
    assert np.max(np.abs(k[0] - ref)) / scale < 1e-6
    assert np.max(np.abs(k[1].real - k[0])) / scale < 1e-7
    fine = tangential_per_a(prepare_tangential(m, rtol=1e-9), np.array([0.0]))
    assert np.max(np.abs(fine[0] - ref)) / scale < 1e-8


@pytest.fixture(scope="module")
def na123_doubling():
    """Na(123), the most anisotropic built-in crystal (A = 7.6): the default table and K/a at
    k_s a = 0.5, 1, 2 in one call (the basis of k_s a = 2), and the table with every resolution
    doubled with the doubled basis (harmonics, radial, ln² and series terms) for the same k a."""
    m = Material.crystal("Na").rotated((1, 2, 3))
    ka = np.array([0.5, 1.0, 2.0])
    table = prepare_tangential(m)
    base = tangential_per_a(table, ka)
    size = tangential_size(2.0, 1e-6, table.n_harmonics).doubled()
    fine = prepare_tangential(m, resolution=Resolution().doubled(), max_order=2 * size.n_harmonics)
    big_size = TangentialSize(size.n_harmonics, size.n_radial, 2, 2, 24)
    return dict(zip(ka.tolist(), base, strict=True)), fine, big_size


# One k a per test (the doubled basis is the costly part, ~6 s and 1 GB each): K/a of a k a
# alone is that of the same k a in a call with smaller ones to round-off (the far grid of a call
# only adds panels below T₁ k_s a, where the far field is zero), so this is the check of all
# three at once. `make test` runs a file on one xdist worker (--dist loadfile): one fine table,
# never two of these at once.
@pytest.mark.parametrize("ka", [0.5, 1.0, 2.0])
def test_convergence_by_doubling(na123_doubling, ka):
    """Default basis (harmonics chosen from the kernel's tail) and resolution against both
    doubled: < 1e-6 up to k_s a = 2 (measured 4.7e-8 on Na(123), the most anisotropic
    built-in crystal (A = 7.6), with |n| <= 10; 4.5e-9 on Cu(123) with |n| <= 8: benchmark)."""
    base, fine, big_size = na123_doubling
    big = tangential_per_a(fine, np.array([ka]), big_size)[0]
    err = np.max(np.abs(base[ka] - big)) / np.max(np.abs(big))
    assert err < 1e-6


def test_reciprocity_and_passivity(cu123):
    """K_xy = K_yx at every frequency (reciprocity; the off-diagonal terms are ~3 % here), and
    (K − Kᴴ)/2i is positive semi-definite (a passive solid radiates, never gains energy)."""
    k = tangential_per_a(prepare_tangential(cu123), np.array([0.0, 0.3, 1.0, 2.0]))
    off = np.abs(k[:, 0, 1])
    assert np.all(off[1:] > 1e-3 * np.abs(k[1:, 0, 0]))
    assert np.max(np.abs(k[:, 0, 1] - k[:, 1, 0]) / off) < 1e-7
    diss = (k - np.conj(np.swapaxes(k, 1, 2))) / 2j
    assert np.all(np.linalg.eigvalsh(diss[1:]) > 0)


def test_rotating_inplane_axes_rotates_tensor(cu123):
    """The same face with the in-plane x axis turned by ψ: K' = Q K Qᵀ (rows of Q: the new
    axes in the old frame) at every frequency (tests the angular harmonics and the odd part
    of the kernel). At equal frequency, not equal k_s a: C44 of the surface frame, which sets
    k_s, changes with the in-plane axis on a face without a 4-fold axis."""
    psi = math.radians(37.0)
    c, s = math.cos(psi), math.sin(psi)
    turned = cu123.rotated((0, 0, 1), inplane=(c, s, 0))
    assert abs(turned.C[3, 3] / cu123.C[3, 3] - 1) > 1e-3
    Q = np.array([[c, s], [-s, c]])
    a, f = 1e-3, np.array([0.2e6, 0.6e6])
    k0 = tangential_contact_stiffness(cu123, a, f, tensor=True)
    k1 = tangential_contact_stiffness(turned, a, f, tensor=True)
    assert np.max(np.abs(k1 - Q @ k0 @ Q.T)) / np.max(np.abs(k0)) < 1e-6


def test_cubic_001_is_fourfold():
    """On Cu(001) K_xx = K_yy and K_xy = 0 dynamically too (4-fold axis)."""
    k = tangential_per_a(prepare_tangential(Material.crystal("Cu")), np.array([0.5, 2.0]))
    assert np.max(np.abs(k[:, 0, 0] - k[:, 1, 1]) / np.abs(k[:, 0, 0])) < 1e-9
    assert np.max(np.abs(k[:, 0, 1]) / np.abs(k[:, 0, 0])) < 1e-9


@pytest.mark.parametrize("zener", [1 - 1e-9, 1 + 1e-9])
def test_nearly_isotropic_is_continuous(zener):
    """A = 1 ± 1e-9 on a (111) face gives the isotropic answer to ~1e-9 (no branch or
    degeneracy switch), and the anisotropy is seen (not an isotropic shortcut)."""
    m = Material.cubic_from_ratios(zener, 0.25, c44=30e9).rotated((1, 1, 1))
    iso = Material.cubic_from_ratios(1.0, 0.25, c44=30e9)
    ka = np.array([0.5, 2.0])
    got = tangential_per_a(prepare_tangential(m), ka)
    ref = tangential_per_a(prepare_tangential(iso), ka)
    rel = np.max(np.abs(got - ref)) / np.max(np.abs(ref))
    assert 1e-12 < rel < 1e-8


# ------------------------------------------------------------------ API, two bodies
def test_two_identical_isotropic_bodies_halve(quartz):
    """Two identical isotropic bodies in series: K/2 at every frequency; a stiff sapphire
    sphere on quartz lies between the quartz plate alone and the quartz plate halved."""
    glass = Material.crystal("soda-lime-glass")
    a, f = 5e-6, 15e6
    one = tangential_contact_stiffness(glass, a, f)
    two = two_body_contact_stiffness(glass, glass, a, f)
    assert two == pytest.approx(one / 2, rel=1e-12)
    plate = tangential_contact_stiffness(quartz, a, f)
    k = two_body_contact_stiffness(Material.crystal("sapphire"), quartz, a, f)
    assert plate.real / 2 < k.real < plate.real


def test_frequency_and_wavenumber_conventions(quartz):
    """tangential_contact_stiffness at f equals K₀ × tangential_dcsf at k_s a = ω a √(ρ/C44);
    the "longitudinal" wave number scales k a by √(C33/C44)."""
    a, f = 4e-6, 15e6
    c44 = float(quartz.C[3, 3].real)
    ksa = 2 * math.pi * f * a * math.sqrt(quartz.density / c44)
    k0 = tangential_contact_stiffness(quartz, a, 0.0)
    k = tangential_contact_stiffness(quartz, a, f)
    # (the f = 0 call takes the smaller basis of k a = 0: the two static values agree to its
    # accuracy, ~1e-10, not to round-off)
    assert k == pytest.approx(k0 * tangential_dcsf(quartz, ksa), rel=1e-8)
    kl = ksa / math.sqrt(float(quartz.C[2, 2].real) / c44)
    assert tangential_dcsf(quartz, kl, wavenumber="longitudinal") == pytest.approx(
        tangential_dcsf(quartz, ksa), rel=1e-12
    )


def test_prepared_table_is_reused_and_checked(quartz):
    tab = prepare_tangential(quartz)
    again = pickle.loads(pickle.dumps(tab))
    a = tangential_dcsf(quartz, [0.2, 1.0], prepared=again)
    assert np.array_equal(a, tangential_dcsf(quartz, [0.2, 1.0]))
    with pytest.raises(ValueError, match="loss"):
        tangential_dcsf(quartz, 0.5, loss=0.01, prepared=tab)
    with pytest.raises(TypeError, match="TangentialTable"):
        tangential_dcsf(quartz, 0.5, prepared=object())


def test_bad_input(quartz):
    with pytest.raises(ValueError, match="radius"):
        tangential_contact_stiffness(quartz, -1e-6, 1e6)
    with pytest.raises(ValueError, match="frequency"):
        tangential_contact_stiffness(quartz, 1e-6, -1.0)
    with pytest.raises(ValueError, match="density"):
        tangential_contact_stiffness(Material.isotropic(1e9, 0.3), 1e-6, 1e6)
    with pytest.raises(ValueError, match="wavenumber"):
        tangential_dcsf(quartz, 0.5, wavenumber="bulk")
    with pytest.raises(ValueError, match="beyond"):
        tangential_dcsf(quartz, 1e3)
    with pytest.raises(ValueError, match="direction"):
        tangential_dcsf(quartz, 0.5, direction=float("nan"))


def test_two_body_frame_flip_with_an_anisotropic_sphere(quartz, cu123):
    """The sphere's frame is the plate's turned by π about x: its stiffness in the plate frame
    is that of the sphere material rotated so (x, −y, −z), computed directly here (another
    table), and the two bodies add in series in the plate frame."""
    a, f = 20e-6, 15e6
    turned = cu123.rotated((0, 0, -1), inplane=(1, 0, 0))
    k_turned = tangential_contact_stiffness(turned, a, f, tensor=True)
    k_plate = tangential_contact_stiffness(quartz, a, f, tensor=True)
    expected = np.linalg.inv(np.linalg.inv(k_plate) + np.linalg.inv(k_turned))
    got = two_body_contact_stiffness(cu123, quartz, a, f, tensor=True)
    assert abs(k_turned[0, 1]) > 1e-3 * abs(k_turned[0, 0])  # the flip matters here
    assert np.max(np.abs(got - expected)) / np.max(np.abs(expected)) < 1e-7


def test_lossy_solid_is_the_analytic_continuation():
    """A uniform loss C(1 + iq) is K_q(a₀) = (1 + iq) K(a₀/√(1 + iq)); to first order in q,
    (1 + iq)[K(a₀) − (iq/2) a₀ K'(a₀)], K' from the lossless curve by central differences:
    checks the lossy table (its κ rescaling and static part) against the lossless one."""
    m, q, a0, h = _iso(0.25), 1e-3, 1.0, 1e-3
    lossless = tangential_dcsf(m, [a0 - h, a0, a0 + h])
    slope = (lossless[2] - lossless[0]) / (2 * h)
    expected = (1 + 1j * q) * (lossless[1] - 0.5j * q * a0 * slope)
    got = tangential_dcsf(m, a0, loss=q)
    assert abs(got - expected) < 2e-6  # the O(q²) remainder is ~q² = 1e-6


def test_tiny_wavenumbers_tend_to_the_static_limit(quartz):
    """Down to k_s a = 1e-100: Re -> 1, Im/k_s a -> the low-frequency damping (as at 1e-4),
    never negative damping (the far grid stops at s = 1e-8; below 1e-6 the dynamic part is
    scaled linearly)."""
    ka = np.array([1e-4, 1e-7, 1e-12, 1e-20, 1e-100])
    d = tangential_dcsf(quartz, ka)
    assert np.max(np.abs(d.real - 1)) < 1e-8
    assert np.max(np.abs(d.imag / ka / (d[0].imag / ka[0]) - 1)) < 1e-6


def test_radial_gram_is_the_series_on_both_sides(cu123):
    # _to_radial (the far field's gram on the orders p, q mapped to the radial pairs, the row
    # index last): against S G Sᵀ by einsum, on the series of a default basis (polynomial and
    # enriched functions) and a seeded random G.
    from contactres.dynamic import _tangential_galerkin as galerkin

    table = prepare_tangential(cu123)
    basis = galerkin.basis_of(table, tangential_size(2.0, n_harmonics=4))
    series = basis.series[:, np.flatnonzero(np.any(basis.series != 0, axis=0))]
    assert 0 < np.sum(np.count_nonzero(series, axis=1) > 1) < series.shape[0]
    nl = series.shape[1]
    gram = np.random.default_rng(7).normal(size=(nl, nl, 5))
    ref = np.einsum("ap,bq,pqn->abn", series, series, gram)
    out = galerkin._to_radial(series, gram)
    assert np.max(np.abs(out - ref)) <= 1e-13 * np.max(np.abs(ref))


def test_shifted_chebyshev_rows_are_the_polynomials_t_f_of_2w_minus_1():
    # Row f, column k: the coefficient of w^k in T_f(2w − 1); against numpy's conversion of
    # the Chebyshev basis on the domain [0, 1] (exact integers) and against cos(f arccos(2w − 1)).
    from numpy.polynomial import Chebyshev, polynomial

    from contactres.dynamic import _tangential_galerkin as galerkin

    nf = 12
    rows = galerkin._shifted_chebyshev(nf)
    for f in range(nf):
        numpy_row = Chebyshev.basis(f, domain=[0.0, 1.0]).convert(kind=polynomial.Polynomial).coef
        assert np.array_equal(rows[f, : f + 1], numpy_row) and not np.any(rows[f, f + 1 :])
    w = np.linspace(0.0, 1.0, 41)
    values = rows @ w[None, :] ** np.arange(nf)[:, None]
    exact = np.cos(np.arange(nf)[:, None] * np.arccos(2.0 * w - 1.0))
    # the monomial form cancels: its rounding is ~1e-16 of the sum of |coefficients| (4e6 at f = 11)
    bound = 1e-15 * np.abs(rows).sum(axis=1)[:, None]
    assert np.all(np.abs(values - exact) < bound)


def test_direct_solve_check_is_the_eigenvalue_criterion(monkeypatch):
    # _keeps_every_direction (a shifted Cholesky first) against the criterion it replaces, the
    # eigenvalues of the scaled static matrix: λ_min > 1e-14 λ_max. Hermitian, unit diagonal,
    # spectra from well conditioned to numerically singular (seeded).
    from contactres.dynamic import _tangential_galerkin as galerkin

    rng = np.random.default_rng(31)
    n = 60
    q, _ = np.linalg.qr(rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n)))
    eigvalsh = np.linalg.eigvalsh
    # 1e-12: the Cholesky shift refuses it, the eigenvalues accept it (the fallback path)
    for ratio in (1e-2, 1e-6, 1e-9, 1e-12, 1e-17, 1e-20):
        a = (q * np.geomspace(ratio, 1.0, n)) @ q.conj().T
        d = 1.0 / np.sqrt(np.real(np.diagonal(a)))
        a = d[:, None] * a * d[None, :]
        a = 0.5 * (a + a.conj().T)
        w = eigvalsh(a)
        expected = bool(w[0] > 1e-14 * w[-1])
        assert expected == (ratio > 1e-14)
        if ratio >= 1e-6:
            # well conditioned: decided without the eigenvalues

            def refuse(*args, **kwargs):
                raise AssertionError("eigenvalues computed")

            monkeypatch.setattr(np.linalg, "eigvalsh", refuse)
        assert galerkin._keeps_every_direction(a) == expected
        monkeypatch.setattr(np.linalg, "eigvalsh", eigvalsh)


def test_inplane_kernel_half_turn_is_the_transpose_at_complex_wavenumbers(cu123):
    # Reciprocity, h(θ + π) = h(θ)ᵀ, evaluated directly (no half-turn shortcut) on lossy complex
    # κ of the contour, the real axis and the static limit: the table's half-turn evaluation and
    # the Galerkin's parity split (Ĝ_{αβ,m} = (−1)^m Ĝ_{βα,m}) rest on it.
    from contactres.dynamic import _tangential_table as tt
    from contactres.halfspace import scaled_tensor

    c = scaled_tensor(cu123).real.astype(complex)
    kappa = np.array([0.3 + 0.2j, 1.1 + 0.05j, 2.7, 40.0, np.inf]) * np.sqrt(1 + 0.03j)
    theta = np.linspace(0.0, np.pi, 13, endpoint=False) + 0.1
    h = tt._inplane(c, kappa, theta)
    h_turned = tt._inplane(c, kappa, theta + np.pi)
    assert np.max(np.abs(h_turned - np.swapaxes(h, -1, -2))) < 1e-13 * np.max(np.abs(h))
    # and a face without a mirror plane has an antisymmetric part well above round-off
    assert np.max(np.abs(h - np.swapaxes(h, -1, -2))) > 1e-3 * np.max(np.abs(h))


def _direct_harmonics(m, kappa, loss, max_order, n=256):
    """Harmonics m = −max_order..max_order of h − h∞ at ``kappa`` (units of k_s) of the solid
    with loss Q⁻¹ and of h∞ undamped, evaluated here on one grid of ``n`` nodes on the full turn
    (no half-turn shortcut, no doubling), the FFT written as a sum."""
    from contactres.dynamic import _tangential_table as tt
    from contactres.halfspace import scaled_tensor

    f = 1 + 1j * loss
    nodes = np.concatenate([np.asarray(kappa) * np.sqrt(f), [np.inf]])
    theta = 2 * np.pi * np.arange(n) / n
    values = tt._inplane(scaled_tensor(m).real.astype(complex), nodes, theta)
    orders = np.arange(-max_order, max_order + 1)
    phases = np.exp(1j * orders[:, None] * theta[None, :]) * (2 * np.pi / n)  # (nm, n)
    harm = np.einsum("mj,kjab->kmab", phases, values)
    return (harm[:-1] - harm[-1][None]) / f, harm[-1]


@pytest.mark.parametrize("name", ["Cu(001)", "Pb(123)"])
def test_table_harmonics_match_one_fine_theta_grid(name):
    # Each wavenumber node refines its own θ grid (_tangential_table._resolved): against the
    # harmonics of one grid of 256 nodes on the full turn for every node evaluated here, on
    # the contour (the hand-over segment holds the far field's series: the test below).
    m = {
        "Cu(001)": Material.crystal("Cu"),
        "Pb(123)": Material.crystal("Pb").rotated((1, 2, 3)),
    }[name]
    loss = 0.01
    table = prepare_tangential(m, loss=loss)
    nc = table.resolution.n_contour
    near, ginf0 = _direct_harmonics(m, table.near_kappa[:nc], loss, table.max_order)
    scale = np.max(np.abs(ginf0))
    assert np.max(np.abs(table.ginf0 - ginf0)) < 1e-12 * scale
    assert np.max(np.abs(table.near_values[:nc] - near)) < 1e-12 * scale


@pytest.mark.parametrize(
    ("m", "loss", "rtol"),
    [
        (Material.isotropic(60e9, 0.0, density=2500.0), 0.0, 1e-6),
        (Material.isotropic(60e9, 0.0, density=2500.0), 0.02, 1e-4),
        (Material.crystal("Cu").rotated((1, 2, 3)), 0.02, 1e-6),
        (cr.at_cut_quartz(), 0.0, 1e-4),
    ],
)
def test_hand_over_segment_from_the_series_within_its_bound(m, loss, rtol):
    """The table's hand-over segment [T₁, 2T₁] is the far field's Chebyshev series
    (_tangential_table.segment_from_series): against the kernel's harmonics there, evaluated
    directly, within its stated bound (2e-9 of the largest ``|h − h∞|`` at rtol 1e-6, 1e-7 at
    1e-4; measured at most 5.8e-10 and 2.9e-8, the isotropic ν = 0 solid the largest), and K
    from a table whose segment holds the direct values, integrated as the contour's are, within
    1e-5 rtol (measured <= 2.8e-6 rtol)."""
    from dataclasses import replace

    table = prepare_tangential(m, loss, rtol)
    nc = table.resolution.n_contour
    direct, _ = _direct_harmonics(m, table.near_kappa[nc:], loss, table.max_order)
    bound = 2e-9 if rtol < 1e-4 else 1e-7
    scale = np.max(np.abs(table.near_values))
    assert np.max(np.abs(table.near_values[nc:] - direct)) <= bound * scale
    # The segment's direct values as contour nodes (n_contour: where the series' nodes start).
    whole = replace(
        table,
        resolution=replace(table.resolution, n_contour=table.near_kappa.size),
        near_values=np.concatenate([table.near_values[:nc], direct]),
    )
    ka = np.linspace(0.0, 2.0, 11)
    ref = tangential_per_a(whole, ka)
    K = tangential_per_a(table, ka)
    assert np.max(np.abs(K - ref)) <= 1e-5 * rtol * np.max(np.abs(ref))
