"""Static tangential stiffness of a rigid disk on an anisotropic half-space (relaxed contact)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import special

from contactres.dynamic._tangential_static import (
    inplane_kernel,
    radial_integrals,
    tangential_stiffness_static,
)
from contactres.materials import Material, at_cut_quartz

A = 2.5e-6  # contact radius, m


def _mindlin(G: float, nu: float, a: float = A) -> float:
    """Mindlin's K = 8Ga/(2 − ν), N/m."""
    return 8 * G * a / (2 - nu)


@pytest.fixture(scope="module")
def quartz_at():
    """AT-cut quartz: no mirror plane, so the odd (imaginary) in-plane kernel couples terms."""
    m = at_cut_quartz()
    return m, tangential_stiffness_static(m, A, tensor=True, rtol=1e-10)


@pytest.mark.parametrize("nu", [0.0, 0.25, 0.45])
def test_isotropic_mindlin(nu):
    E = 1.3e11
    G = E / (2 * (1 + nu))
    m = Material.isotropic(E, nu)
    K = tangential_stiffness_static(m, A, tensor=True)
    assert np.allclose(K, _mindlin(G, nu) * np.eye(2), rtol=0, atol=1e-10 * _mindlin(G, nu))
    for kw in ({"one_term": True}, {"direction": 37.0}, {"terms": (3, 3)}):
        assert tangential_stiffness_static(m, A, **kw) == pytest.approx(_mindlin(G, nu), rel=1e-10)


def test_isotropic_kernel_is_cerruti():
    """Ĝ_αβ = (δ_αβ − ν n_α n_β)/G, real (the convention the module derives from H)."""
    E, nu = 2.0e11, 0.3
    G = E / (2 * (1 + nu))
    th = np.linspace(0, 2 * np.pi, 11)
    n = np.stack([np.cos(th), np.sin(th)], axis=-1)
    ref = (np.eye(2) - nu * n[:, :, None] * n[:, None, :]) / G
    got = inplane_kernel(Material.isotropic(E, nu), th)
    assert np.max(np.abs(got - ref)) < 1e-14 / G


@pytest.mark.parametrize("zener", [1 - 1e-9, 1 + 1e-9])
def test_nearly_isotropic_is_continuous(zener):
    nu = 0.3  # cubic ν = C12/(C11 + C12) = Poisson's ratio at A = 1
    m = Material.cubic_from_ratios(zener, nu, c44=5e10)
    iso = _mindlin(5e10, nu)
    K = tangential_stiffness_static(m.rotated((1, 1, 1)), A, tensor=True)
    rel = np.abs(K - iso * np.eye(2)) / iso
    assert np.max(rel) < 1e-8  # ~1e-9 anisotropy -> ~1e-9 change, no jump
    assert np.max(rel) > 1e-11  # and the anisotropy is seen (not the isotropic shortcut)


def test_kernel_hermitian_and_odd_part():
    """Reciprocity: Ĝ(θ) Hermitian, Ĝ(θ + π) = conj Ĝ(θ); the odd imaginary part is absent on a
    mirror face (Cu(011)) and present on AT-cut quartz (why the Galerkin needs more terms)."""
    th = np.linspace(0, np.pi, 9, endpoint=False)
    for m, has_odd in ((Material.crystal("Cu").rotated((0, 1, 1)), False), (at_cut_quartz(), True)):
        g = inplane_kernel(m, th)
        scale = np.max(np.abs(g))
        assert np.max(np.abs(g - np.conj(np.swapaxes(g, -1, -2)))) < 1e-14 * scale
        assert np.max(np.abs(inplane_kernel(m, th + np.pi) - np.conj(g))) < 1e-14 * scale
        assert (np.max(np.abs(g.imag)) > 1e-3 * scale) == has_odd


def _kernel_harmonics(m: Material, nh: int) -> np.ndarray:
    """Ĝ_m (m = -2 nh..2 nh, 2 x 2 each) by composite Gauss-Legendre in θ (not the module's
    FFT): 24 nodes on each of 32 equal panels, every node in one call of the kernel, checked
    against 16 panels to 1e-14 (the kernel is smooth in θ: 16 panels already agree with
    scipy's adaptive quad_vec at epsrel 1e-14 to 8e-16, measured on AT-cut quartz, nh = 8)."""
    orders = np.arange(-2 * nh, 2 * nh + 1)
    x, w = np.polynomial.legendre.leggauss(24)

    def rule(panels: int) -> np.ndarray:
        edges = np.linspace(0.0, 2 * np.pi, panels + 1)
        half = np.diff(edges)[:, None] / 2
        t = (edges[:-1, None] + half * (x + 1)).ravel()
        weight = (half * w).ravel()[:, None] * np.exp(1j * t[:, None] * orders)
        return np.einsum("jm,jab->mab", weight, inplane_kernel(m, t))

    coarse, fine = rule(16), rule(32)
    assert np.max(np.abs(fine - coarse)) < 1e-14 * np.max(np.abs(fine))
    return fine


def _plain_galerkin(harm: np.ndarray, nh: int, nr: int) -> np.ndarray:
    """Independent Galerkin, K/a (Pa), without the log enrichment: harmonics ``harm`` of
    :func:`_kernel_harmonics`, radial integrals ∫ j_p j_q ds in closed form, dense solve."""
    al, n, k = (x.ravel() for x in np.meshgrid([0, 1], np.arange(-nh, nh + 1), np.arange(nr)))
    p = np.abs(n) + 2 * k
    d = p[:, None] - p[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        odd = np.sin(d * np.pi / 2) / (d * (p[:, None] + p[None, :] + 1))
    R = np.where(d == 0, np.pi / (2 * (2 * p[:, None] + 1)), np.where(d % 2 == 0, 0.0, odd))
    G = harm[2 * nh + n[None, :] - n[:, None], al[:, None], al[None, :]]
    M = 1j ** ((np.abs(n)[:, None] - np.abs(n)[None, :]) % 4) * G * R
    b = np.zeros((al.size, 2))
    for a in range(2):
        b[(n == 0) & (k == 0) & (al == a), a] = 1.0
    return 4 * np.pi**2 * np.real(b.T @ np.linalg.solve(M, b))


def test_anisotropic_second_way_and_bounds(quartz_at):
    """AT-cut quartz against a plain polynomial Galerkin written here: every Galerkin subspace
    underestimates K (complementary energy: the traction trial overestimates the compliance),
    the plain one converges like N⁻² from below, and its Richardson extrapolation meets the
    log-enriched value."""
    m, K = quartz_at
    nh = 8
    K_same_angles = tangential_stiffness_static(m, 1.0, tensor=True, terms=(nh, 4))
    assert np.max(np.abs(K_same_angles * A - K)) < 1e-10 * np.max(K)
    harm = _kernel_harmonics(m, nh)  # the same for both radial bases
    K16, K32 = (_plain_galerkin(harm, nh, nr) for nr in (16, 32))
    d = np.diag(K_same_angles)
    assert np.all(np.diag(K16) < np.diag(K32)) and np.all(np.diag(K32) < d)
    assert np.all(d - np.diag(K32) < 1e-7 * d)
    richardson = np.diag(K32) + (np.diag(K32) - np.diag(K16)) / 3
    assert np.allclose(richardson, d, rtol=1e-9, atol=0)
    # One term (Mindlin's traction shape): a lower bound, by quadrature of Re Ĝ here.
    G0 = harm[2 * nh].real  # the harmonic m = 0: ∫₀^{2π} Ĝ(θ) dθ
    K1 = 8 * np.pi * A * np.linalg.inv(G0)
    assert np.allclose(
        tangential_stiffness_static(m, A, tensor=True, one_term=True), K1, rtol=1e-11
    )
    gap = np.linalg.eigvalsh(K - K1)
    assert np.all(gap > 0) and np.max(gap) < 1e-3 * np.max(np.diag(K))


@pytest.mark.parametrize("face", [(0, 0, 1), (1, 1, 1)])
def test_three_and_four_fold_faces_isotropic(face):
    # A fixed basis whose span is invariant under in-plane rotation (as in
    # test_rotating_inplane_axis_rotates_tensor) keeps the face's symmetry to round-off, so 12
    # harmonics test it as sharply as the default's adaptive basis (the same solve on larger
    # bases, checked against fixed ones in test_convergence_by_doubling) at about a tenth of
    # the CPU: a wrongly turned kernel or an asymmetric harmonic set breaks the isotropy at
    # every basis size (measured: K_xx/K_yy − 1 <= 4e-15 at (12, 4), as with the default).
    m = Material.crystal("Cu").rotated(face)
    K = tangential_stiffness_static(m, A, tensor=True, terms=(12, 4))
    assert K[0, 0] == pytest.approx(K[1, 1], rel=1e-10)
    assert abs(K[0, 1]) < 1e-12 * K[0, 0]
    assert np.array_equal(K, K.T)


def test_cu011_anisotropic_principal_axes():
    """Cu(011) in the default frame of ``rotated``: x = [100], y = z × x = [01-1]/√2."""
    m = Material.crystal("Cu").rotated((0, 1, 1))
    assert np.allclose(m.frame[0], [1, 0, 0]) and np.allclose(m.frame[1], [0, 1, -1] / np.sqrt(2))
    K = tangential_stiffness_static(m, A, tensor=True)
    assert np.array_equal(K, K.T)
    assert abs(K[0, 1]) < 1e-12 * K[0, 0]  # principal axes [100] and [01-1]
    assert K[0, 0] > 1.2 * K[1, 1] > 0  # stiffer along [100]
    assert np.all(np.linalg.eigvalsh(K) > 0)
    # Mirror face: Mindlin's traction is exact, one term gives the converged value.
    K1 = tangential_stiffness_static(m, A, tensor=True, one_term=True)
    assert np.allclose(K1, K, rtol=1e-12, atol=1e-12 * K[0, 0])


@pytest.mark.parametrize("which", ["Cu011", "quartz"])
def test_rotating_inplane_axis_rotates_tensor(which):
    base = Material.crystal("Cu").rotated((0, 1, 1)) if which == "Cu011" else at_cut_quartz()
    terms = (8, 2)  # a fixed basis: its span is invariant under in-plane rotation
    K = tangential_stiffness_static(base, A, tensor=True, terms=terms)
    psi = 27.0
    c, s = np.cos(np.radians(psi)), np.sin(np.radians(psi))
    turned = base.rotated((0, 0, 1), inplane=(c, s, 0))  # new x along e_ψ of the old frame
    Q = np.array([[c, s], [-s, c]])  # rows: the new axes in the old frame
    K2 = tangential_stiffness_static(turned, A, tensor=True, terms=terms)
    assert np.allclose(K2, Q @ K @ Q.T, rtol=0, atol=1e-11 * np.max(K))
    K_psi = tangential_stiffness_static(base, A, direction=psi, terms=terms)
    assert K_psi == pytest.approx(K2[0, 0], rel=1e-11)


def test_convergence_by_doubling(quartz_at):
    """The default rtol = 1e-10 stops at (24 harmonics, 4 radial terms) on AT-cut quartz: the
    doubling from (12, 4) moves K by < 1e-10, geometrically less than the one from (6, 4), and
    doubling the radial terms ((12, 4) -> (12, 8)) moves it by < 1e-10 too."""
    m, K = quartz_at
    K6, K12, K12r = (
        tangential_stiffness_static(m, A, tensor=True, terms=t) for t in ((6, 4), (12, 4), (12, 8))
    )
    scale = np.max(K)
    assert np.max(np.abs(K - K12)) < 1e-10 * scale
    assert np.max(np.abs(K - K12)) < 0.1 * np.max(np.abs(K12 - K6))
    assert np.max(np.abs(K12r - K12)) < 1e-10 * scale


def test_symmetric_axis_and_linear_in_radius(quartz_at):
    m, K = quartz_at
    assert abs(K[0, 1]) < 1e-12 * K[0, 0]  # x = crystal X, a two-fold axis in the surface
    radii = np.array([1e-6, 2e-6])
    assert np.allclose(
        tangential_stiffness_static(m, radii, terms=(8, 2)),
        radii * tangential_stiffness_static(m, 1.0, terms=(8, 2)),
        rtol=1e-14,
    )


def test_bad_input():
    m = Material.isotropic(1e11, 0.3)
    with pytest.raises(ValueError, match="radius"):
        tangential_stiffness_static(m, -1.0)
    with pytest.raises(ValueError, match="rtol"):
        tangential_stiffness_static(m, 1.0, rtol=1e-16)
    with pytest.raises(ValueError, match="terms"):
        tangential_stiffness_static(m, 1.0, terms=(2, 0))
    with pytest.raises(ValueError, match="undamped"):
        tangential_stiffness_static(m.with_loss(0.01), 1.0)


def test_radial_integrals_closed_form_and_two_variable_rule():
    # R(p_a, λ_a; p_b, λ_b) and its λ-derivatives: at λ = 0 the closed form of the module
    # docstring; the derivatives against Cauchy's formula in both variables at once, written
    # here from Weber-Schafheitlin (radial_integrals multiplies one-variable Taylor series).
    p_max, n_log = 20, 2
    R = radial_integrals(p_max, n_log)
    p = np.arange(p_max + 1)
    pa, pb = p[:, None], p[None, :]
    diff = pa - pb
    with np.errstate(divide="ignore", invalid="ignore"):
        odd = (-1.0) ** ((diff - 1) // 2) / (diff * (pa + pb + 1))
    closed = np.where(diff == 0, np.pi / (2 * (2 * pa + 1)), np.where(diff % 2 == 1, odd, 0.0))
    assert np.max(np.abs(R[0, 0] - closed)) < 1e-14
    nc, rho = 32, 0.2
    z = rho * np.exp(2j * np.pi * np.arange(nc) / nc)
    la, lb = z[:, None, None, None], z[None, :, None, None]
    L = 1 + la + lb
    F = (
        (np.pi / 2)
        * special.gamma(L)
        * special.gamma((pa + pb + 1) / 2)
        * 2.0 ** (-L)
        * special.rgamma((pb - pa) / 2 + 1 + lb)
        * special.rgamma((pa + pb + 3) / 2 + la + lb)
        * special.rgamma((pa - pb) / 2 + 1 + la)
    )
    for u in range(n_log + 1):
        for v in range(n_log + 1):
            weight = np.exp(-2j * np.pi * (u * np.arange(nc)[:, None] + v * np.arange(nc)) / nc)
            coef = np.tensordot(weight, F, axes=([0, 1], [0, 1])) / (nc * nc * rho ** (u + v))
            expected = (math.factorial(u) * math.factorial(v) * coef).real
            assert np.max(np.abs(R[u, v] - expected)) < 5e-14 * np.max(np.abs(expected))
