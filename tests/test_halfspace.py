"""Tests of contactres.halfspace: static and dynamic surface response of an anisotropic solid.

Independent references: Boussinesq (isotropic statics), the exact axial indentation modulus of a
transversely isotropic solid (Delafargue & Ulm 2004), Lamb's closed-form isotropic kernel, the
published secular equation of Rayleigh waves on an orthotropic face (cubic (001) Rayleigh pole),
a brute-force 6x6 Stroh eigen-decomposition (np.linalg.eig), the general doubling step
against the mirror-plane one, symmetry and reciprocity.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

from contactres import Material
from contactres.halfspace import (
    dynamic_kernel,
    has_mirror_plane,
    isotropic_dynamic_kernel,
    mm,
    shear_reference,
    static_kernel,
)
from contactres.materials import tensor_to_voigt, voigt_to_tensor

CU = Material.cubic(168.4e9, 121.4e9, 75.4e9, density=8960.0)
THETA = np.linspace(0.0, 2 * np.pi, 13)


def _rel(a, b):
    return np.max(np.abs(np.asarray(a) - np.asarray(b)) / np.abs(np.asarray(b)))


def _rotate_C(C, R):
    c = voigt_to_tensor(C)
    return tensor_to_voigt(np.einsum("ia,jb,kc,ld,abcd->ijkl", R, R, R, R, c))


def _triclinic(seed=3, loss=0.0):
    """A generic anisotropic solid: a rotated hexagonal crystal plus a small random perturbation."""
    rng = np.random.default_rng(seed)
    base = Material.hexagonal(160e9, 90e9, 66e9, 181e9, 46e9).C
    R = Rotation.from_rotvec(rng.normal(size=3)).as_matrix()
    C = _rotate_C(base, R)
    P = rng.normal(size=(6, 6)) * 4e9
    C = C + 0.5 * (P + P.T)
    return Material.from_voigt(C * (1 + 1j * loss) if loss else C)


# --------------------------------------------------------------------------------- statics
@pytest.mark.parametrize("nu", [-0.5, 0.0, 0.17, 0.25, 0.45, 0.49])
def test_isotropic_static_kernel_is_boussinesq(nu):
    E = 70e9
    m = Material.isotropic(E, nu)
    G = static_kernel(m, THETA)
    assert G.dtype == float
    assert _rel(G, 2 * (1 - nu**2) / E) < 1e-12


def test_isotropic_static_kernel_any_orientation():
    m = Material.isotropic(200e9, 0.3)
    r = m.rotated(normal=(0.3, -1.2, 0.7), inplane=(1, 1, 0))
    assert _rel(static_kernel(r, THETA), 2 * (1 - 0.09) / 200e9) < 1e-12


def test_transversely_isotropic_axis_normal_matches_delafargue_ulm():
    # Exact indentation modulus along the symmetry axis of a transversely isotropic solid:
    # M = 2 sqrt((C11 C33 - C13^2)/C11 / (1/C44 + 2/(sqrt(C11 C33) + C13)))
    # (Delafargue & Ulm, Int. J. Solids Struct. 41 (2004) 7351, Eq. 23). Ĝ = 2/M for every θ.
    c11, c12, c13, c33, c44 = 163.0e9, 92.0e9, 69.0e9, 181.0e9, 46.7e9  # Ti-like, Pa
    m = Material.hexagonal(c11, c12, c13, c33, c44)
    M = 2 * np.sqrt((c11 * c33 - c13**2) / c11 / (1 / c44 + 2 / (np.sqrt(c11 * c33) + c13)))
    assert _rel(static_kernel(m, THETA), 2 / M) < 1e-12


def test_static_kernel_lossy_is_complex_and_scales():
    m = CU.with_loss(0.02)
    G = static_kernel(m, THETA)
    assert np.iscomplexobj(G)
    # Uniform loss C(1 + iq) scales the compliance by 1/(1 + iq) exactly.
    assert _rel(G, static_kernel(CU, THETA) / (1 + 0.02j)) < 1e-12


def test_shear_reference_is_surface_frame_c44():
    assert shear_reference(CU) == 75.4e9
    assert shear_reference(CU.with_loss(0.1)) == 75.4e9
    c111 = CU.rotated((1, 1, 1))
    assert shear_reference(c111) == pytest.approx(np.real(c111.C[3, 3]))
    # independent: the shear modulus on planes normal to [111] is (C11 − C12 + C44)/3
    assert shear_reference(c111) == pytest.approx((168.4e9 - 121.4e9 + 75.4e9) / 3, rel=1e-12)


# --------------------------------------------------------------------------------- dynamics
def _rayleigh_kappa(ratio):
    """Root of the lossless Rayleigh function (κ_R = c_s/c_R > 1), by bracketing."""

    def F(k):
        om2 = 1 / k**2
        return (2 - om2) ** 2 - 4 * np.sqrt(1 - om2 / ratio) * np.sqrt(1 - om2)

    return brentq(F, 1.0 + 1e-12, 2.0, xtol=1e-15)


@pytest.mark.parametrize("nu", [0.0, 0.25, 0.4])
def test_isotropic_dynamic_kernel_matches_lamb_closed_form_with_loss(nu):
    m = Material.isotropic(1.0, nu)
    ratio = m.C[0, 0] / m.C[3, 3]
    kr = _rayleigh_kappa(ratio)
    kappa = np.concatenate(
        [np.geomspace(0.02, 50, 60), kr * (1 + np.linspace(-0.03, 0.03, 41)), [0.999, 1.0, 1.001]]
    )
    for q in (0.02, 1e-3):
        g = dynamic_kernel(m.with_loss(q), kappa, 0.7)
        ref = isotropic_dynamic_kernel(kappa, ratio, loss=q)
        assert _rel(g, ref) < 1e-10
    # Near the Rayleigh pole the kernel is large: the check bites where it matters.
    assert np.max(np.abs(ref)) > 100


def test_isotropic_dynamic_kernel_lossless_above_cutoff_and_complex_kappa():
    m = Material.isotropic(1.0, 0.3)
    ratio = m.C[0, 0] / m.C[3, 3]
    kr = _rayleigh_kappa(ratio)
    k_real = np.array([1.0 + 1e-6, 1.01, 1.2, kr * 1.01, 3.0, 1e3])
    assert _rel(dynamic_kernel(m, k_real, 0.0), isotropic_dynamic_kernel(k_real, ratio)) < 1e-10
    # Contour in the upper half plane, through the propagating range and past the pole.
    s = np.linspace(0.01, 3.0, 50)
    kc = s + 0.05j * np.sin(np.pi * s / 3.0) + 1e-3j
    assert _rel(dynamic_kernel(m, kc, 1.1), isotropic_dynamic_kernel(kc, ratio)) < 1e-10


def test_closed_form_lossless_static_limit():
    m = Material.isotropic(1.0, 0.3)
    ratio = m.C[0, 0] / m.C[3, 3]
    assert isotropic_dynamic_kernel(1e8, ratio).real == pytest.approx(0.7, rel=1e-12)


def _orthotropic_rayleigh_x(c11, c12, c66):
    """ρ c_R²/c66 on a principal face of an orthotropic solid, wave along a principal axis.

    The classical secular equation (Chadwick, J. Sound Vib. 47 (1976) 39; in the form of Vinh &
    Ogden, "Formulas for the Rayleigh wave speed in orthotropic elastic solids", Arch. Mech. 56
    (2004), no. 3), with c11 along the wave, c22 = c11 normal to the face (cubic), X = ρ c²:
        c22 c66 (c11 − X) X² = (c66 − X) (c11 c22 − c12² − c22 X)².
    It is squared, so it can have spurious roots: the largest root below c66 is the surface wave.
    """

    def sec(x):
        X = x * c66
        return c11 * c66 * (c11 - X) * X**2 - (c66 - X) * (c11 * c11 - c12**2 - c11 * X) ** 2

    xs = np.linspace(1e-4, 1.0, 4001)[:-1]
    v = sec(xs)
    i = np.flatnonzero(np.sign(v[:-1]) != np.sign(v[1:]))[-1]
    return brentq(sec, xs[i], xs[i + 1], xtol=1e-16)


@pytest.mark.parametrize(
    "c11, c12, c44",
    [
        (168.4e9, 121.4e9, 75.4e9),  # Cu, A = 3.2
        (246.5e9, 147.3e9, 124.7e9),  # Ni, A = 2.5
        (3.0, 1.5, 0.375),  # A = 0.5
    ],
)
def test_cubic_001_rayleigh_pole_matches_orthotropic_secular_equation(c11, c12, c44):
    # Lossless cubic (001), wave along [100]: g has its Rayleigh pole at κ_R = c_s/c_R with
    # c_R from the published orthotropic secular equation (an algebraic equation, independent of
    # the Stroh/doubling machinery). The pole is located as the sign change of 1/g on the real
    # axis above the limiting speed (where g is real).
    m = Material.cubic(c11, c12, c44, density=5000.0)
    k = np.linspace(1.0005, 4.0, 600)
    g = dynamic_kernel(m, k, 0.0)
    inv = (1 / g).real
    real = g.imag == 0
    j = np.flatnonzero(real[:-1] & real[1:] & (np.sign(inv[:-1]) != np.sign(inv[1:])))
    assert j.size == 1
    k_pole = brentq(
        lambda q: (1 / dynamic_kernel(m, q, 0.0)).real, k[j[0]], k[j[0] + 1], xtol=1e-14
    )
    k_R = 1 / np.sqrt(_orthotropic_rayleigh_x(c11, c12, c44))
    assert abs(k_pole / k_R - 1) < 1e-10


def test_orthotropic_secular_equation_reduces_to_rayleigh():
    # The formula above, checked on the isotropic solid against the Rayleigh function.
    for nu in (0.1, 0.25, 0.4):
        iso = Material.isotropic(1.0, nu)
        c11, c12, c44 = iso.C[0, 0], iso.C[0, 1], iso.C[3, 3]
        x = _orthotropic_rayleigh_x(c11, c12, c44)
        assert 1 / np.sqrt(x) == pytest.approx(_rayleigh_kappa(c11 / c44), rel=1e-12)


def _stroh_eig_kernel(C, kappa, theta):
    """Brute force: the 6x6 Stroh matrix (state vector: displacement and scaled traction σ_i3),
    np.linalg.eig, keep the three eigenvalues with Re λ < 0 (decaying), H = A B⁻¹."""
    c = voigt_to_tensor(np.asarray(C, dtype=complex)) / np.real(C[3, 3])
    n = np.array([np.cos(theta), np.sin(theta)])
    Q = np.einsum("iakb,a,b->ik", c[:, :2, :, :2], n, n)
    R = np.einsum("iak,a->ik", c[:, :2, :, 2], n)
    W = c[:, 2, :, 2]
    Wi = np.linalg.inv(W)
    s = 1 / kappa**2
    M = np.block([[-1j * Wi @ R.T, Wi], [Q - s * np.eye(3) - R @ Wi @ R.T, -1j * R @ Wi]])
    lam, V = np.linalg.eig(M)
    keep = np.argsort(lam.real)[:3]
    assert np.all(lam.real[keep] < 0) and np.sort(lam.real)[3] > 0
    A, B = V[:3, keep], V[3:, keep]
    return -(A @ np.linalg.inv(B))[2, 2]


@pytest.mark.parametrize("kappa", [0.3, 0.9, 1.05, 2.0, 7.0])
def test_anisotropic_dynamic_kernel_matches_brute_force_eigen_solution(kappa):
    m = _triclinic(loss=0.02)
    for th in (0.0, 0.4, 2.5):
        ref = _stroh_eig_kernel(m.C, kappa, th)
        assert abs(dynamic_kernel(m, kappa, th) - ref) < 1e-10 * abs(ref)


def test_dynamic_tends_to_static_at_large_kappa():
    for m in (CU.rotated((0, 1, 1)), _triclinic(), _triclinic(loss=0.02)):
        g_inf = shear_reference(m) * static_kernel(m, THETA)
        d1 = np.abs(dynamic_kernel(m, 1e3, THETA) - g_inf)
        d2 = np.abs(dynamic_kernel(m, 2e3, THETA) - g_inf)
        assert np.max(d1 / np.abs(g_inf)) < 1e-5
        # The approach is ~1/κ²: doubling κ cuts the gap by ~4.
        np.testing.assert_allclose(d1 / d2, 4.0, rtol=1e-3)


def test_kernel_depends_only_on_c_over_c44_not_density():
    m1 = Material.from_voigt(CU.C.copy(), density=8960.0).with_loss(0.02)
    m2 = Material.from_voigt(7.0 * CU.C, density=1.0).with_loss(0.02)
    k = np.array([0.5, 1.3, 4.0])
    np.testing.assert_allclose(dynamic_kernel(m1, k, 0.3), dynamic_kernel(m2, k, 0.3), rtol=1e-13)


def test_broadcasting_shapes():
    m = CU.with_loss(0.02)
    g = dynamic_kernel(m, np.linspace(0.5, 2, 4)[:, None], np.linspace(0, 1, 3)[None, :])
    assert g.shape == (4, 3)
    assert static_kernel(CU, 0.3).shape == ()
    assert static_kernel(CU, np.zeros((2, 5))).shape == (2, 5)


def test_doubling_tolerance_is_converged(monkeypatch):
    # The cyclic reduction stops at an update of 1e-10; stopping at 1e-15 moves g by < 1e-13.
    from contactres.halfspace import _doubling as doubling

    m = Material.crystal("Cu").rotated((0, 1, 1)).with_loss(0.02)
    k = np.geomspace(0.05, 50, 40)[:, None]
    th = np.linspace(0, np.pi, 9)[None, :]
    g = dynamic_kernel(m, k, th)
    # The patch reaches the doubling loop: a loose tolerance visibly changes g.
    monkeypatch.setattr(doubling, "_CR_TOL", 1e-2)
    assert np.max(np.abs(dynamic_kernel(m, k, th) - g) / np.abs(g)) > 1e-4
    monkeypatch.setattr(doubling, "_CR_TOL", 1e-15)
    g_tight = dynamic_kernel(m, k, th)
    assert np.max(np.abs(g - g_tight) / np.abs(g_tight)) < 1e-13


def test_mirror_plane_fast_path_equals_general_cyclic_reduction(monkeypatch):
    # Faces that are mirror planes of the solid take the block-structured doubling step; the
    # general 3x3 step (forced here) is a second algorithm for the same solvent.
    from contactres.halfspace import _compliance as compliance
    from contactres.halfspace import _doubling as doubling

    calls = {"general": 0, "mirror": 0}

    def counted(name, fn):
        def wrapper(*args, **kwargs):
            calls[name] += 1
            return fn(*args, **kwargs)

        return wrapper

    monkeypatch.setattr(
        doubling, "_cyclic_reduction", counted("general", doubling._cyclic_reduction)
    )
    monkeypatch.setattr(
        doubling,
        "_cyclic_reduction_mirror",
        counted("mirror", doubling._cyclic_reduction_mirror),
    )
    m001, m011 = CU, CU.rotated((0, 1, 1))
    hexa = Material.hexagonal(160e9, 90e9, 66e9, 181e9, 46e9).rotated((1, 0, 0))
    k = np.concatenate([np.geomspace(0.05, 50, 12), [0.999, 1.0001, 1.3]])[:, None]
    th = np.linspace(0, np.pi, 7)[None, :] + 0.1
    cases = [(m.with_loss(0.02), k) for m in (m001, m011, hexa)]
    cases += [(m001, np.array([[1.2], [2.0], [9.0]])), (m011, k + 0.05j)]  # lossless
    for m, _ in cases:
        assert has_mirror_plane(m)
    fast = [dynamic_kernel(m, kk, th) for m, kk in cases]
    assert calls["mirror"] >= len(cases) and calls["general"] == 0
    monkeypatch.setattr(compliance, "_has_mirror", lambda c: False)
    calls.update(general=0, mirror=0)
    for (m, kk), g in zip(cases, fast, strict=True):
        ref = dynamic_kernel(m, kk, th)
        assert np.max(np.abs(g - ref) / np.abs(ref)) < 1e-12
    # The forced path really ran: only the general step, and it rounds differently.
    assert calls["general"] >= len(cases) and calls["mirror"] == 0
    assert not np.array_equal(fast[0], dynamic_kernel(cases[0][0], cases[0][1], th))
    # No mirror plane: (111) of a cubic crystal, a generic solid.
    assert not has_mirror_plane(CU.rotated((1, 1, 1)))
    assert not has_mirror_plane(_triclinic())


# --------------------------------------------------------------------------------- symmetry
def test_cubic_001_four_fold_and_mirror():
    m = CU.with_loss(0.02)
    k = np.array([0.4, 1.1, 1.3, 5.0])[:, None]
    th = np.linspace(0, 2 * np.pi, 17)[None, :] + 0.123
    g = dynamic_kernel(m, k, th)
    np.testing.assert_allclose(dynamic_kernel(m, k, th + np.pi / 2), g, rtol=1e-11)
    np.testing.assert_allclose(dynamic_kernel(m, k, -th), g, rtol=1e-11)
    # ...and the anisotropy is really there (the checks would pass trivially if g were constant).
    assert np.ptp(static_kernel(CU, th)) > 0.05 * np.mean(static_kernel(CU, th))


def test_cubic_111_six_fold():
    m = CU.rotated((1, 1, 1)).with_loss(0.02)
    k = np.array([0.4, 1.1, 1.3, 5.0])[:, None]
    th = np.linspace(0, 2 * np.pi, 17)[None, :] + 0.2
    g = dynamic_kernel(m, k, th)
    np.testing.assert_allclose(dynamic_kernel(m, k, th + np.pi / 3), g, rtol=1e-11)
    assert np.max(np.abs(dynamic_kernel(m, k, th + np.pi / 6) - g)) > 1e-4 * np.max(np.abs(g))


def test_reciprocity_even_in_wave_vector():
    m = _triclinic(loss=0.02)
    k = np.array([0.4, 1.1, 3.0])[:, None]
    th = np.linspace(0, np.pi, 7)[None, :]
    np.testing.assert_allclose(dynamic_kernel(m, k, th + np.pi), dynamic_kernel(m, k, th), 1e-11)


def test_rotating_the_solid_in_plane_shifts_theta():
    # The (111) face rotated by 40° about the normal: g(θ) of the new frame = g(θ + 40°) of the old.
    m0 = CU.rotated((1, 1, 1))
    alpha = np.deg2rad(40.0)
    R = m0.frame  # rows: surface axes in crystal coordinates
    x_new = np.cos(alpha) * R[0] + np.sin(alpha) * R[1]
    m1 = CU.rotated((1, 1, 1), inplane=x_new)
    k = np.array([0.7, 2.0])[:, None]
    th = np.linspace(0, 2 * np.pi, 9)[None, :]
    np.testing.assert_allclose(
        dynamic_kernel(m1.with_loss(0.02), k, th),
        dynamic_kernel(m0.with_loss(0.02), k, th + alpha),
        rtol=1e-10,
    )


@pytest.mark.parametrize("nu", [0.1, 0.25, 0.45])
def test_continuity_through_isotropy(nu):
    # A = 1 has a triple static root and a double shear root: no special case may be needed.
    k = np.concatenate([np.geomspace(0.05, 1e6, 25), [0.999, 1.0001]])[:, None]
    k_prop = np.linspace(0.0213, 0.99, 9)[:, None]
    th = np.linspace(0, np.pi / 2, 5)[None, :]
    iso = Material.cubic_from_ratios(1.0, nu)
    ratio = iso.C[0, 0] / iso.C[3, 3]
    ref_static = (1 - nu) * np.ones(th.shape)
    for A in (1 - 1e-9, 1.0, 1 + 1e-9):
        m = Material.cubic_from_ratios(A, nu)
        assert np.max(np.abs(shear_reference(m) * static_kernel(m, th) - ref_static)) < 1e-9
        g = dynamic_kernel(m.with_loss(0.02), k, th)
        ref = isotropic_dynamic_kernel(k, ratio, loss=0.02)
        assert np.max(np.abs(g - ref) / np.abs(ref)) < 1e-8
        # lossless, propagating range (eigen-decomposition with the repeated shear root)
        g = dynamic_kernel(m, k_prop, th)
        ref = isotropic_dynamic_kernel(k_prop, ratio)
        assert np.max(np.abs(g - ref) / np.abs(ref)) < 1e-7


@given(seed=st.integers(0, 2**31), loss=st.floats(1e-3, 0.2))
def test_random_solids_are_passive_and_reciprocal(seed, loss):
    # Any positive-definite stiffness: Ĝ > 0 (the surface yields to a push), Ĝ(θ + π) = Ĝ(θ),
    # and with loss Im g <= 0 (e^{iωt}: the half-space absorbs energy, it never supplies it).
    rng = np.random.default_rng(seed)
    L = rng.normal(size=(6, 6))
    m = Material.from_voigt((L @ L.T + 0.5 * np.eye(6)) * 1e10)
    th = np.linspace(0, np.pi, 5)
    G = static_kernel(m, th)
    assert np.all(G > 0)
    np.testing.assert_allclose(static_kernel(m, th + np.pi), G, rtol=1e-10)
    g = dynamic_kernel(m.with_loss(loss), np.array([0.3, 0.9, 1.7, 6.0])[:, None], th)
    assert np.all(g.imag <= 1e-12 * np.abs(g))


# --------------------------------------------------------------------------------- errors
def test_lossless_propagating_range_is_the_outgoing_limit_isotropic():
    # Real κ < 1: real vertical wave numbers, including the repeated shear root (SH = SV).
    for nu in (0.1, 0.25, 0.4):
        m = Material.isotropic(1.0, nu)
        ratio = m.C[0, 0] / m.C[3, 3]
        # (the grid avoids the P-wave branch point κ = (C44/C11)^½, where g = 0)
        k = np.concatenate([np.linspace(0.0213, 0.99, 40), [1.0 + 1e-9]])
        g = dynamic_kernel(m, k[:, None], np.array([0.0, 1.1])[None, :])
        ref = isotropic_dynamic_kernel(k, ratio)[:, None]  # principal root = the 0+ limit
        assert np.max(np.abs(g / ref - 1)) < 1e-10


@pytest.mark.parametrize("normal", [(0, 0, 1), (0, 1, 1), (1, 2, 3)])
def test_lossless_propagating_range_is_the_outgoing_limit_anisotropic(normal):
    # g(κ) must be the limit of g(κ(1 + iε)) as ε -> 0+: Richardson from ε and 2ε leaves O(ε²).
    m = CU.rotated(normal)
    k = np.array([0.2, 0.45, 0.7])[:, None]
    th = np.array([0.0, 0.5, 1.3])[None, :]
    g0 = dynamic_kernel(m, k, th)
    eps = 1e-6
    g1 = dynamic_kernel(m, k * (1 + 1j * eps), th)
    g2 = dynamic_kernel(m, k * (1 + 2j * eps), th)
    assert np.max(np.abs(g0 - g1) / np.abs(g0)) > 1e-8  # the check is not trivially met
    assert np.max(np.abs(g0 - (2 * g1 - g2)) / np.abs(g0)) < 1e-7


@pytest.mark.parametrize("kappa", [0.0, -1.0, np.nan, np.inf])
def test_bad_kappa(kappa):
    with pytest.raises(ValueError, match="kappa"):
        dynamic_kernel(CU.with_loss(0.02), kappa, 0.0)


def test_complex_kappa_rules():
    with pytest.raises(ValueError, match="lossless"):
        dynamic_kernel(CU.with_loss(0.02), 1 + 0.1j, 0.0)
    with pytest.raises(ValueError, match="upper half"):
        dynamic_kernel(CU, 1 - 0.1j, 0.0)


def test_closed_form_rejects_bad_input():
    with pytest.raises(ValueError, match="c11_over_c44"):
        isotropic_dynamic_kernel(1.0, 1.0)
    with pytest.raises(ValueError, match="loss"):
        isotropic_dynamic_kernel(1.0, 3.0, loss=-0.1)


def test_stacked_product_matches_einsum_for_views_and_mixed_types():
    """mm of (3, 3, N) stacks, with and without out/tmp, equals np.einsum's matrix product,
    also for a real factor times a complex one, a transposed view and a broadcast stack (the
    operand layouts the compliance code passes it)."""
    rng = np.random.default_rng(31)
    n = 37
    a = rng.standard_normal((3, 3, n)) + 1j * rng.standard_normal((3, 3, n))
    b = rng.standard_normal((3, 3, n)) + 1j * rng.standard_normal((3, 3, n))
    w = np.broadcast_to(rng.standard_normal((3, 3, 1)), (3, 3, n))
    pairs = [(a, b), (a.transpose(1, 0, 2), b), (w, b), (b.real, a)]
    for x, y in pairs:
        ref = np.einsum("ikn,kjn->ijn", x, y)
        np.testing.assert_allclose(mm(x, y), ref, rtol=1e-14, atol=1e-14)
        out, tmp = np.empty_like(a), np.empty_like(a)
        assert mm(x, y, out=out, tmp=tmp) is out
        np.testing.assert_allclose(out, ref, rtol=1e-14, atol=1e-14)


@pytest.mark.parametrize("face", [(0, 0, 1), (1, 1, 1)])
def test_doubling_batched_retirement_changes_no_bit(monkeypatch, face):
    # The doubling loops drop finished points from their work arrays in batches (a finished
    # point may iterate on unused for a step or two); dropping every point in the step it
    # finishes (the plain algorithm, forced here) must give the same kernel bit for bit: lossy,
    # and lossless with propagating points that are given up after _STALL_ITER steps.
    from contactres.halfspace import _doubling as doubling

    m = CU.rotated(face)
    k = np.geomspace(0.05, 20, 25)[:, None]
    th = np.linspace(0, np.pi, 11)[None, :] + 0.05
    cases = [(m.with_loss(0.02), k), (m, k), (m, k * (1 + 0.1j))]
    batched = [dynamic_kernel(mm_, kk, th) for mm_, kk in cases]
    waited = []
    plain = doubling._retire

    def spy(waited_steps, finished, active):
        waited.append(waited_steps)
        return plain(waited_steps, finished, active)

    monkeypatch.setattr(doubling, "_retire", spy)
    for (mm_, kk), g in zip(cases, batched, strict=True):
        assert np.array_equal(dynamic_kernel(mm_, kk, th), g)
    # The general step batches (exercised here); the mirror-plane step drops at once.
    assert max(waited, default=0) >= 1 if face == (1, 1, 1) else not waited
    monkeypatch.setattr(doubling, "_retire", lambda waited_steps, finished, active: True)
    for (mm_, kk), g in zip(cases, batched, strict=True):
        assert np.array_equal(dynamic_kernel(mm_, kk, th), g)


def test_surface_compliance_pair_gives_both_directions():
    # θ + π from the reversed pencil of the same cyclic reduction: the 6x6 Stroh eigen-solution
    # at θ + π (brute force) and the separate evaluation there agree with it; θ itself is the
    # plain evaluation bit for bit; a mirror-plane face gives M H M, M = diag(1, 1, −1).
    from contactres.halfspace import scaled_tensor, surface_compliance, surface_compliance_pair

    th = np.linspace(0.0, 2 * np.pi, 9)[None, :] + 0.05
    kappa = np.array([0.3, 0.8, 1.05, 2.0, 7.0])
    si111 = Material.crystal("Si").rotated((1, 1, 1))
    cases = [(_triclinic(loss=0.02), kappa), (si111.with_loss(0.01), kappa)]
    cases += [
        (si111, np.array([0.5, 0.9, 3.0]) * (1 + 0.05j)),
        (si111, np.array([0.5, 0.9, 1.5, 3.0])),
    ]
    for m, k in cases:
        assert not has_mirror_plane(m)
        c, s = scaled_tensor(m), 1.0 / k[:, None] ** 2
        H, H_pi = surface_compliance_pair(c, th, s)
        assert np.array_equal(H, surface_compliance(c, th, s))
        sep = surface_compliance(c, th + np.pi, s)
        scale = np.max(np.abs(sep), axis=(-2, -1), keepdims=True)
        assert np.max(np.abs(H_pi - sep) / scale) < 1e-10
        if m.is_lossy:
            for i, j in [(0, 0), (1, 3), (2, 5), (4, 8)]:
                ref = -_stroh_eig_kernel(m.C, k[i], th[0, j] + np.pi)
                assert abs(H_pi[i, j, 2, 2] - ref) < 1e-10 * abs(ref)
    c = scaled_tensor(CU.rotated((0, 1, 1)).with_loss(0.02))
    H, H_pi = surface_compliance_pair(c, th, 1.0 / kappa[:, None] ** 2)
    flip = np.array([1.0, 1.0, -1.0])
    np.testing.assert_array_equal(H_pi, H * flip[:, None] * flip[None, :])


def test_inverse_last_column_is_that_of_inv3():
    # The normal compliance needs one column of (Rᵀ(I − G) + iβW(I + G))⁻¹; the shortcut uses
    # inv3's formulas, so the same values bit for bit (and the inverse's, to round-off).
    from contactres.halfspace import _compliance as compliance
    from contactres.halfspace import inv3

    rng = np.random.default_rng(7)
    a = rng.normal(size=(3, 3, 50)) + 1j * rng.normal(size=(3, 3, 50))
    col = compliance._inverse_last_column(a)
    assert np.array_equal(col, inv3(a)[:, 2])
    ref = np.linalg.inv(np.moveaxis(a, -1, 0))[:, :, 2].T
    assert np.max(np.abs(col - ref)) < 1e-12 * np.max(np.abs(ref))


def test_general_step_symmetric_inverse_and_one_step_match_dense_algebra(monkeypatch):
    # The general doubling step keeps A0, A1, A2 as packed upper triangles (A0, A2 paired) and
    # K = A1⁻¹ from six cofactors; checked here against numpy's dense inverse and one step of
    # cyclic reduction written out with full matrices.
    from contactres.halfspace import _doubling as doubling

    rng = np.random.default_rng(11)
    n = 40

    def sym():
        a = rng.normal(size=(n, 3, 3)) + 1j * rng.normal(size=(n, 3, 3))
        return a + np.swapaxes(a, -1, -2)

    a0, a1, a2 = sym(), sym() + 6 * np.eye(3), sym()
    packed = np.array([a1[:, i, j] for i, j in doubling._UPPER])
    cof, t, r = np.empty((6, n), complex), np.empty(n, complex), np.empty(n, complex)
    K = np.empty((6, 2, n), complex)
    doubling._symmetric_inverse(packed, cof, t, r, K)
    ref = np.linalg.inv(a1)
    for e, (i, j) in enumerate(doubling._UPPER):
        assert np.array_equal(K[e, 0], K[e, 1])
        assert np.max(np.abs(K[e, 0] - ref[:, i, j])) < 1e-13 * np.max(np.abs(ref))
    # One step (the loop stops after it with the tolerance raised so that every point is done):
    # Â1 = A1 − A2 K A0.
    stack = [np.moveaxis(x, 0, -1) for x in (a0, a1, a2)]
    monkeypatch.setattr(doubling, "_CR_TOL", np.inf)
    A1h, A1h_dual, done = doubling._cyclic_reduction(*stack, None, dual=True)
    assert done.all()
    want = a1 - a2 @ ref @ a0
    got = np.moveaxis(A1h, -1, 0)
    assert np.max(np.abs(got - want)) < 1e-12 * np.max(np.abs(want))
    # The reversed pencil's Â1' = A1 − A0 K A2 is the transpose.
    want_dual = a1 - a0 @ ref @ a2
    assert np.max(np.abs(np.moveaxis(A1h_dual, -1, 0) - want_dual)) < 1e-12 * np.max(np.abs(want))


def test_surface_compliance_pair_falls_back_where_the_reversed_solvent_is_not_accurate(
    monkeypatch,
):
    # With the residual bound at 0 no θ + π solvent of the shared iterates is accepted: every
    # such point must take the separate evaluation, and give what it gives.
    from contactres.halfspace import (
        _compliance,
        scaled_tensor,
        surface_compliance,
        surface_compliance_pair,
    )

    c = scaled_tensor(Material.crystal("Si").rotated((1, 1, 1)).with_loss(0.01))
    th = np.linspace(0.0, 2 * np.pi, 7)[None, :] + 0.05
    s = 1.0 / np.array([0.3, 0.8, 2.0])[:, None] ** 2
    calls = []
    separate = _compliance._pencil_compliance

    def spy(*args, **kwargs):
        calls.append(len(args) > 8 and args[8])
        return separate(*args, **kwargs)

    monkeypatch.setattr(_compliance, "_RESID_TOL", 0.0)
    monkeypatch.setattr(_compliance, "_pencil_compliance", spy)
    _, H_pi = surface_compliance_pair(c, th, s)
    assert calls.count(False) >= 1  # the separate evaluation ran
    monkeypatch.undo()
    sep = surface_compliance(c, th + np.pi, s)
    scale = np.max(np.abs(sep), axis=(-2, -1), keepdims=True)
    assert np.max(np.abs(H_pi - sep) / scale) < 1e-12
