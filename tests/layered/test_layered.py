"""The layered substrate and its surface response (contactres.layered, issue 26 part 1).

Anchors independent of the code under test: the homogeneous half-space compliance
(contactres.halfspace) for a film of the substrate's own material, the thin and thick limits, a
global boundary-value solve with scipy's expm and Schur (tests/layered/layered_reference.py),
the isotropic solid written as a cubic one, reciprocity and passivity of the response, and
scipy.linalg.expm for the 3x3 exponential.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
from layered_reference import reference_compliance

import contactres as cr
from contactres.errors import ContactresInputError
from contactres.halfspace import surface_compliance
from contactres.layered import LayeredMaterial, stack_compliance, surface_green
from contactres.layered._expm import expm3, expm_isotropic
from contactres.materials import voigt_to_tensor

QUARTZ = cr.Material.isotropic(72e9, 0.17, density=2650.0, name="quartz")
PMMA = cr.Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA")
SI111 = cr.Material.crystal("Si").rotated((1, 1, 1))
CU111 = cr.Material.crystal("Cu").rotated((1, 1, 1))
THETA = np.array([0.0, 0.4, 1.3, 2.9, 4.4])


def halfspace_green(m, eta, theta, frequency):
    """Ĝ of the homogeneous half-space straight from contactres.halfspace (m/Pa)."""
    c44 = float(np.real(m.C[3, 3]))
    c = voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44
    eta, theta = np.broadcast_arrays(np.asarray(eta, dtype=float), np.asarray(theta, float))
    s = (m.density or 0.0) * (2 * np.pi * frequency) ** 2 / (c44 * eta**2)
    return surface_compliance(c, theta, s) / (c44 * eta[..., None, None])


def rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


# --- film = substrate -------------------------------------------------------------------------


@pytest.mark.parametrize("m", [QUARTZ, SI111, QUARTZ.with_loss(0.02), CU111.with_loss(0.01)])
@pytest.mark.parametrize("frequency", [0.0, 20e6, 400e6])
def test_film_of_the_substrate_is_the_homogeneous_half_space(m, frequency):
    # 400 MHz: η = 1e6 1/m is below the shear wave number of quartz and Cu (propagating
    # partial waves: the outgoing split of the half-space code in every layer).
    eta = np.array([1e6, 7e6, 3e7])[:, None]
    stack = LayeredMaterial(m, [(m, 120e-9), (m, 1e-6), (m, 35e-9)])
    G = surface_green(stack, eta, THETA, frequency)
    assert G.shape == (3, 5, 3, 3)
    assert rel(G, halfspace_green(m, eta, THETA, frequency)) < 1e-10


def test_no_layers_is_the_substrate():
    G = surface_green(LayeredMaterial(SI111), 2e6, THETA, 30e6)
    assert np.array_equal(G, surface_green(SI111, 2e6, THETA, 30e6))
    assert rel(G, halfspace_green(SI111, 2e6, THETA, 30e6)) < 1e-14


# --- limits -----------------------------------------------------------------------------------


@pytest.mark.parametrize("frequency", [0.0, 50e6])
def test_vanishing_film_gives_the_substrate(frequency):
    # The film changes H by O(η h x contrast): η h = 1e-9 leaves ~2e-9 of it.
    eta = np.array([1e6, 1e7])[:, None]
    stack = LayeredMaterial(QUARTZ, [(PMMA, 1e-9 / 1e7)])
    G = surface_green(stack, eta, THETA, frequency)
    assert rel(G, halfspace_green(QUARTZ, eta, THETA, frequency)) < 1e-8


@pytest.mark.parametrize("frequency", [0.0, 50e6])
@pytest.mark.parametrize("eta_h", [60.0, 1e3])
def test_thick_film_gives_the_film(frequency, eta_h):
    # The substrate shows through as e^{−η h Im p}, Im p >= ~0.9 here: below round-off at
    # η h = 60; η h = 1e3 would overflow a transfer matrix (e^{+1000}).
    eta = 1e7
    stack = LayeredMaterial(QUARTZ, [(SI111, eta_h / eta)])
    G = surface_green(stack, eta, THETA, frequency)
    assert np.all(np.isfinite(G))
    assert rel(G, halfspace_green(SI111, eta, THETA, frequency)) < 1e-12


def test_transfer_matrix_would_overflow_where_the_recursion_does_not():
    # The point of the recursion: the reference's transfer matrix at η h = 1e3 is not finite.
    c = voigt_to_tensor(np.asarray(PMMA.C, dtype=complex)) / float(PMMA.C[3, 3])
    from layered_reference import stroh_matrix

    with np.errstate(all="ignore"):
        P = scipy.linalg.expm(1e3 * stroh_matrix(c, 0.3, 0.0))
    assert not np.all(np.isfinite(P)) or np.max(np.abs(P)) > 1e300
    G = surface_green(LayeredMaterial(QUARTZ, [(PMMA, 1e-4)]), 1e7, 0.3)
    assert np.all(np.isfinite(G))


# --- second route: global boundary-value solve ------------------------------------------------

CASES = [
    ([PMMA, QUARTZ], [250e-9]),
    ([QUARTZ, PMMA], [300e-9]),
    ([PMMA.with_loss(0.05), QUARTZ.with_loss(0.01)], [400e-9]),
    ([PMMA, QUARTZ, PMMA.with_loss(0.02)], [200e-9, 150e-9]),
    ([PMMA.with_loss(0.05), SI111.with_loss(0.01), QUARTZ.with_loss(0.02)], [250e-9, 400e-9]),
]


@pytest.mark.parametrize("case", range(len(CASES)))
@pytest.mark.parametrize("frequency", [0.0, 15e6, 300e6])
def test_against_a_global_boundary_value_solution(case, frequency):
    mats, hs = CASES[case]
    substrate = mats[-1]
    stack = LayeredMaterial(substrate, list(zip(mats[:-1], hs, strict=True)))
    c44 = float(np.real(substrate.C[3, 3]))
    for eta in (1e6, 4e6, 1e7):
        if frequency > 0 and not substrate.is_lossy:
            k_s = 2 * np.pi * frequency * np.sqrt(substrate.density / float(substrate.C[3, 3]))
            if eta < 1.05 * k_s:
                continue  # propagating waves in a lossless substrate: no Re λ < 0 split
        for theta in (0.0, 0.7, 2.2):
            H = surface_green(stack, eta, theta, frequency) * c44 * eta
            assert rel(H, reference_compliance(mats, hs, eta, theta, frequency)) < 1e-9


@pytest.mark.parametrize("case", [0, 3, 4])
def test_compliance_factors_against_the_boundary_value_solution(case):
    """H = P Q⁻¹ of compliance_factors (the top layer's step without its two inverses) equals
    the global boundary-value solution (one, two layers; isotropic and Si (111); lossy)."""
    from contactres.layered import compliance_factors, layer_waves, substrate_impedance

    mats, hs = CASES[case]
    c44 = float(np.real(mats[-1].C[3, 3]))
    frequency, theta = 15e6, np.array([0.0, 0.7, 2.2])
    for eta in (4e6, 1e7):
        s = [(m.density or 0.0) * (2 * np.pi * frequency) ** 2 / (c44 * eta**2) for m in mats]
        sv = [np.full(theta.size, v, dtype=complex) for v in s]
        tensors = [voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44 for m in mats]
        layers = [layer_waves(c, theta, v) for c, v in zip(tensors[:-1], sv, strict=False)]
        eta_h = [np.full(theta.size, eta * h, dtype=complex) for h in hs]
        Y = substrate_impedance(tensors[-1], theta, sv[-1])
        P, Q = compliance_factors(layers, eta_h, Y)
        # The isotropic layers' exponentials in closed form (Si (111) keeps the general one).
        iso = [theta if m.name in ("PMMA", "quartz") else None for m in mats[:-1]]
        P_iso, Q_iso = compliance_factors(layers, eta_h, Y, iso)
        for k, th in enumerate(theta):
            want = reference_compliance(mats, hs, eta, th, frequency)
            assert rel(P[..., k] @ np.linalg.inv(Q[..., k]), want) < 1e-9
            assert rel(P_iso[..., k] @ np.linalg.inv(Q_iso[..., k]), want) < 1e-9


@pytest.mark.parametrize("frequency", [15e6, 300e6])
def test_complex_wavenumber_of_a_lossless_stack_against_the_boundary_value_solution(frequency):
    # Im η > 0: the decaying rule of the substrate (Re λ < 0 of N, i.e. Im p > 0) in both codes,
    # the analytic continuation from large real η (as for contactres.dynamic_kernel).
    mats, hs = [PMMA, SI111, QUARTZ], [250e-9, 300e-9]
    stack = LayeredMaterial(QUARTZ, [(PMMA, 250e-9), (SI111, 300e-9)])
    c44 = float(QUARTZ.C[3, 3])
    for eta in (3e5 * (1 + 0.2j), 1e6 * (1 + 0.05j), 4e6 * (1 + 0.3j), 1e7 * (1 + 0.01j)):
        H = surface_green(stack, eta, 0.7, frequency) * c44 * eta
        assert rel(H, reference_compliance(mats, hs, eta, 0.7, frequency)) < 1e-9


# --- cubic written isotropic ------------------------------------------------------------------


def cubic_pmma(a_ratio: float) -> cr.Material:
    """PMMA's constants as a cubic solid with Zener ratio A = 2 c44/(c11 − c12)."""
    C = np.asarray(PMMA.C)
    c11, c12 = float(C[0, 0]), float(C[0, 1])
    return cr.Material.cubic(c11, c12, a_ratio * (c11 - c12) / 2, density=1190.0)


@pytest.mark.parametrize(
    "mats",
    [
        [PMMA, QUARTZ],
        [QUARTZ, SI111],
        [SI111.with_loss(0.01), QUARTZ],
        [PMMA.with_loss(0.05), SI111.with_loss(0.01), QUARTZ.with_loss(0.02)],
    ],
    ids=["PMMA/quartz", "quartz/Si", "lossy Si/quartz", "lossy PMMA/Si/quartz"],
)
@pytest.mark.parametrize("inertia", [0.0, 0.5])
def test_stack_compliance_has_the_half_spaces_as_its_limits(mats, inertia):
    """The layer recursion's limits, each a homogeneous half-space (contactres.halfspace, the
    Stroh solution with no layer): layers of zero thickness leave the substrate's compliance,
    layers of the substrate's own material too (at any thickness), and a top layer far thicker
    than 1/η (ηh = 60) is a half-space of its own material. ``inertia``: ρω²/η² as a fraction
    of the slowest C44/ρ of the stack (every partial wave evanescent; statics at 0); isotropic
    and Si (111), lossy or not."""
    c44 = float(np.real(mats[-1].C[3, 3]))
    tensors = [voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44 for m in mats]
    slowest = min(float(np.real(m.C[3, 3])) / m.density for m in mats)
    s = [inertia * m.density * slowest / c44 for m in mats]
    layers = len(mats) - 1
    substrate = surface_compliance(tensors[-1], THETA, s[-1])
    top = surface_compliance(tensors[0], THETA, s[0])
    thin = stack_compliance(tensors, s, [0.0] * layers, THETA)
    assert rel(thin, substrate) < 1e-13
    same = stack_compliance(
        [tensors[-1]] * len(mats), [s[-1]] * len(mats), [0.7, 2.0][:layers], THETA
    )
    assert rel(same, substrate) < 1e-13
    thick = stack_compliance(tensors, s, [60.0] + [0.5] * (layers - 1), THETA)
    assert rel(thick, top) < 1e-13


@pytest.mark.parametrize("frequency", [0.0, 40e6])
def test_cubic_film_with_unit_anisotropy_is_the_isotropic_film(frequency):
    eta = np.array([2e6, 8e6])[:, None]
    iso = surface_green(LayeredMaterial(SI111, [(PMMA, 300e-9)]), eta, THETA, frequency)
    cub = cubic_pmma(1.0).rotated((1, 1, 1))
    G = surface_green(LayeredMaterial(SI111, [(cub, 300e-9)]), eta, THETA, frequency)
    assert rel(G, iso) < 1e-12
    for a in (1 - 1e-6, 1 + 1e-6):
        near = cubic_pmma(a).rotated((1, 2, 3))
        Gn = surface_green(LayeredMaterial(SI111, [(near, 300e-9)]), eta, THETA, frequency)
        assert rel(Gn, iso) < 1.5e-6


# --- reciprocity and passivity ----------------------------------------------------------------


def test_reciprocity_homogeneous_then_layered():
    # Ĝ_ij(ξ) = Ĝ_ji(−ξ): the reciprocal theorem for two surface loads, in Fourier space.
    for m, f in ((SI111, 0.0), (SI111.with_loss(0.02), 60e6)):
        hom = halfspace_green(m, 3e6, THETA, f)
        assert rel(halfspace_green(m, 3e6, THETA + np.pi, f), np.swapaxes(hom, -1, -2)) < 1e-12
    stack = LayeredMaterial(QUARTZ.with_loss(0.01), [(SI111.with_loss(0.02), 300e-9)])
    for f in (0.0, 60e6, 400e6):
        G = surface_green(stack, 3e6, THETA, f)
        Gpi = surface_green(stack, 3e6, THETA + np.pi, f)
        assert rel(Gpi, np.swapaxes(G, -1, -2)) < 1e-12


def test_static_lossless_stack_is_hermitian():
    # A real load gives a real displacement: Ĝ(−ξ) = conj Ĝ(ξ), with reciprocity Hermitian.
    G = surface_green(LayeredMaterial(QUARTZ, [(CU111, 200e-9), (PMMA, 1e-6)]), 3e6, THETA)
    assert rel(G, np.conj(np.swapaxes(G, -1, -2))) < 1e-12


def dissipation(G):
    """Eigenvalues of the anti-Hermitian part (Ĝ − Ĝᴴ)/(2i), scaled by the largest |Ĝ|."""
    A = (G - np.conj(np.swapaxes(G, -1, -2))) / 2j
    return np.linalg.eigvalsh(A) / np.max(np.abs(G))


def test_passivity_homogeneous_then_layered():
    eta = np.geomspace(2e5, 3e7, 9)[:, None]
    # The lossy half-space first: power into the solid (ω/2) Im(σᴴ Ĝ σ) >= 0.
    ev = dissipation(halfspace_green(QUARTZ.with_loss(0.02), eta, THETA, 50e6))
    assert ev.min() > -1e-12 and ev.max() > 1e-3
    stack = LayeredMaterial(
        SI111.with_loss(0.01), [(PMMA.with_loss(0.05), 250e-9), (CU111.with_loss(0.02), 1e-6)]
    )
    for f in (0.0, 50e6, 300e6):
        ev = dissipation(surface_green(stack, eta, THETA, f))
        assert ev.min() > -1e-12 and ev.max() > 1e-3
    # Lossless and static: no dissipation at all.
    lossless = LayeredMaterial(SI111, [(PMMA, 250e-9)])
    assert np.max(np.abs(dissipation(surface_green(lossless, eta, THETA)))) < 1e-12


# --- the exponential --------------------------------------------------------------------------


def test_expm3_against_scipy():
    rng = np.random.default_rng(7)
    mats = []
    for scale in (1e-3, 0.3, 1.0, 5.0, 40.0, 300.0):
        for _ in range(6):
            a = rng.normal(size=(3, 3)) + 1j * rng.normal(size=(3, 3))
            # Stable: shift the spectrum into Re < 0 (a decaying exponential, as in the layers).
            a = a - (np.max(np.linalg.eigvals(a).real) + 0.5) * np.eye(3)
            mats.append(scale * a / np.linalg.norm(a, 2))
    got = expm3(np.stack(mats, axis=-1))
    for j, a in enumerate(mats):
        ref = scipy.linalg.expm(a)
        assert np.max(np.abs(got[..., j] - ref)) <= 1e-13 * max(1.0, np.max(np.abs(ref)))


def test_expm3_of_a_defective_matrix():
    # A 3x3 Jordan block (the static isotropic layer's triple root): exp = e^λ (I + N + N²/2).
    lam, t = -0.8 + 0.3j, 7.0
    J = t * (lam * np.eye(3) + np.eye(3, k=1))
    N = t * np.eye(3, k=1)
    ref = np.exp(t * lam) * (np.eye(3) + N + N @ N / 2)
    assert np.max(np.abs(expm3(J[..., None])[..., 0] - ref)) < 1e-14 * np.max(np.abs(ref))


@pytest.mark.parametrize("m", [PMMA, QUARTZ.with_loss(0.02)])
def test_isotropic_waves_against_stroh(m):
    """An isotropic layer's impedance D_d and exponent A_d (closed form) equal the general
    Stroh solution: D_d = H⁻¹ of :func:`contactres.halfspace.surface_compliance` (its
    eigen-solution; outgoing waves of a lossless solid beyond its cutoffs) and
    A_d = i W⁻¹(−i D_d − Rᵀ) (the decaying solvent Z of the pencil, A_d = iZ), to 1e-13:
    statics, evanescent and propagating partial waves, complex slowness, any direction."""
    from contactres.layered import layer_waves, substrate_impedance

    c44 = float(np.real(m.C[3, 3]))
    c = voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44
    s = np.array([0.0, 1e-9, 0.4, 0.9, 1.7, 6.0, 0.2 - 0.3j, 3.0 - 1.0j, 2.0 + 0.5j])
    theta = np.array([0.0, 0.3, 1.2, 2.5, 0.0, 0.7, 0.1, 4.0, 5.5])
    waves, mirror = layer_waves(c, theta, s)
    assert mirror
    H = np.moveaxis(surface_compliance(c, theta, s), (-2, -1), (0, 1))
    for k in range(s.size):
        d = np.linalg.inv(H[..., k])
        n = np.array([np.cos(theta[k]), np.sin(theta[k]), 0.0])
        R = np.einsum("iak,a->ik", c[:, :, :, 2], n)
        W = c[:, 2, :, 2]
        a = 1j * np.linalg.solve(W, -1j * d - R.T)
        scale = np.max(np.abs(d))
        assert np.max(np.abs(waves[0][..., k] - d)) < 1e-13 * scale
        assert np.max(np.abs(waves[1][..., k] + np.diag([1, 1, -1]) @ d @ np.diag([1, 1, -1]))) < (
            1e-13 * scale
        )
        assert np.max(np.abs(waves[2][..., k] - a)) < 1e-13 * np.max(np.abs(a))
        y = substrate_impedance(c, theta[k : k + 1], s[k : k + 1])[..., 0]
        assert np.max(np.abs(y - d)) < 1e-13 * scale


@pytest.mark.parametrize("m", [PMMA, QUARTZ.with_loss(0.02)])
def test_expm_isotropic_against_scipy(m):
    """The closed form of an isotropic layer's exponential (two roots: P and the SV/SH pair)
    equals scipy's expm of the same exponent matrix: static (the defective double root),
    propagating-free and lossy, complex slowness and η h, small and large η h, any direction."""
    from contactres.layered import layer_waves

    c44 = float(np.real(m.C[3, 3]))
    c = voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44
    s = np.array([0.0, 1e-9, 0.1, 0.5, 0.2 - 0.3j, 3.0 - 1.0j, 0.97, 0.5, 0.1])
    theta = np.array([0.0, 0.3, 1.2, 2.5, 0.0, 0.7, 0.1, 4.0, 5.5])
    t = np.array([0.3, 2.0, 5.0, 1.0 + 0.5j, 50.0, 0.1 + 0.02j, 3.0, 1e-8, 0.7 - 0.2j])
    waves, mirror = layer_waves(c, theta, s.astype(complex))
    assert mirror
    A = waves[2]
    got = expm_isotropic(A, t, theta)
    for k in range(t.size):
        # scipy's expm of exp(t A / m) (|t A|/m <= 1: no scaling and squaring, whose error at
        # η h = 50 reaches 3e-13 for a decaying A) raised to the m-th power: 4e-14 of a
        # long-double Taylor series there, where the closed form is within 1.4e-14.
        m = max(1, math.ceil(abs(t[k]) * np.max(np.abs(A[..., k]))))
        ref = np.linalg.matrix_power(scipy.linalg.expm(t[k] * A[..., k] / m), m)
        assert np.max(np.abs(got[..., k] - ref)) < 1e-13 * np.max(np.abs(ref))


# --- the stack object -------------------------------------------------------------------------


class Relaxing:
    """A stand-in frequency-dependent material: lossy PMMA when relaxed (f = 0), a stiffer
    lossy solid (quartz's constants) at any f > 0; only the dispatch on ``at`` is tested."""

    name = "relaxing"
    is_lossy = True

    def at(self, frequency):
        return PMMA.with_loss(0.05) if frequency == 0 else QUARTZ.with_loss(0.03)

    def rotated(self, normal=(0, 0, 1), inplane=None):
        return self


def test_stack_properties():
    unnamed = cr.Material.isotropic(100e9, 0.3)
    stack = LayeredMaterial(QUARTZ, [(PMMA, 250e-9), (unnamed, 1.5e-6)])
    assert stack.name == "PMMA 250 nm on film 1.5 µm on quartz"
    assert LayeredMaterial(SI111, [(PMMA, 2e-3)]).name == "PMMA 2 mm on Si"
    assert stack.materials == (PMMA, unnamed, QUARTZ)
    assert np.array_equal(stack.thicknesses, [250e-9, 1.5e-6])
    assert stack.density == PMMA.density
    assert not stack.is_lossy and stack.with_loss(0.01).is_lossy
    assert LayeredMaterial(QUARTZ).thicknesses.shape == (0,)
    assert LayeredMaterial(QUARTZ).density == QUARTZ.density


def test_rotated_turns_every_material():
    cu = cr.Material.crystal("Cu")
    si = cr.Material.crystal("Si")
    stack = LayeredMaterial(si, [(cu, 300e-9)]).rotated((1, 1, 0), (0, 0, 1))
    by_hand = LayeredMaterial(
        si.rotated((1, 1, 0), (0, 0, 1)), [(cu.rotated((1, 1, 0), (0, 0, 1)), 300e-9)]
    )
    assert np.array_equal(surface_green(stack, 3e6, THETA), surface_green(by_hand, 3e6, THETA))


def test_frequency_dependent_layer_is_evaluated_at_the_frequency():
    stack = LayeredMaterial(SI111, [(Relaxing(), 250e-9)])
    assert stack.is_frequency_dependent and stack.is_lossy
    for f, m in ((0.0, PMMA.with_loss(0.05)), (30e6, QUARTZ.with_loss(0.03))):
        expect = surface_green(LayeredMaterial(SI111, [(m, 250e-9)]), 3e6, THETA, f)
        assert np.array_equal(surface_green(stack, 3e6, THETA, f), expect)
    assert stack.at(30e6).layers[0][0] is not None
    assert surface_green(Relaxing(), 3e6, 0.0).shape == (3, 3)


def test_stack_compliance_of_one_solid_is_the_half_space():
    c = voigt_to_tensor(np.asarray(SI111.C, dtype=complex)) / float(SI111.C[3, 3])
    H = stack_compliance([c], [0.3], [], THETA)
    assert np.array_equal(H, surface_compliance(c, THETA, 0.3))


def test_surface_green_matches_the_normal_kernels():
    # Ĝ(θ) of static_kernel is −η Ĝ_33; g of dynamic_kernel is −C44 η Ĝ_33 at κ = η/k_s.
    m = SI111.with_loss(0.01)
    eta, f = 4e6, 80e6
    G = surface_green(m, eta, THETA)
    assert rel(-eta * G[..., 2, 2], cr.static_kernel(m, THETA)) < 1e-14
    c44 = float(np.real(m.C[3, 3]))
    kappa = eta / (2 * np.pi * f * np.sqrt(m.density / c44))
    g = -c44 * eta * surface_green(m, eta, THETA, f)[..., 2, 2]
    assert rel(g, cr.dynamic_kernel(m, kappa, THETA)) < 1e-14


# --- bad input --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("layers", "match"),
    [
        ([(PMMA, 0.0)], r"layer 1 thickness must be finite and > 0 m, got 0.0 m"),
        ([(PMMA, -1e-7)], r"layer 1 thickness must be finite and > 0 m"),
        ([(PMMA, np.inf)], r"finite and > 0 m"),
        ([(PMMA, np.nan)], r"finite and > 0 m"),
        ([(PMMA, 1e-7), (PMMA, 2.0)], r"layer 2 thickness 2.0 m is above 1 m.*as the substrate"),
        ([(PMMA, "thin")], r"layer 1 thickness must be a number in m"),
        ([(PMMA,)], r"layer 1 must be a \(material, thickness_m\) pair"),
        ([("PMMA", 1e-7)], r"layer 1 material must be a contactres.Material"),
        (5, r"layers must be a sequence"),
    ],
)
def test_bad_layers_one_clear_line(layers, match):
    with pytest.raises(ContactresInputError, match=match) as err:
        LayeredMaterial(QUARTZ, layers)
    assert "\n" not in str(err.value)


def test_thickness_text_picks_the_unit():
    from contactres.layered import thickness_text

    cases = [(2.5e-7, "250 nm"), (1e-6, "1 µm"), (1.5e-6, "1.5 µm"), (1e-3, "1 mm"), (1.0, "1 m")]
    for h, want in [*cases, (5e-10, "0.5 nm")]:
        assert thickness_text(h) == want
    assert LayeredMaterial(cr.Material.isotropic(70e9, 0.2, name="Si"), [(PMMA, 1.0)]).name == (
        f"{PMMA.name or 'film'} 1 m on Si"
    )


def test_one_thickness_rule_for_every_layered_input():
    """LayeredMaterial, ``--coating`` (jobs.contact.parse_coating) and the analysis's coating
    take the same thicknesses: up to MAX_THICKNESS_M (1 m) inclusive, nothing above."""
    from contactres.analysis._coating import as_coating
    from contactres.jobs.contact import parse_coating
    from contactres.layered import MAX_THICKNESS_M, checked_thickness

    assert MAX_THICKNESS_M == 1.0
    sub = cr.Material.isotropic(70e9, 0.2)
    ok, bad = MAX_THICKNESS_M, MAX_THICKNESS_M * (1 + 1e-9)
    assert checked_thickness(ok, "x") == ok
    assert LayeredMaterial(sub, [(PMMA, ok)]).thicknesses[0] == ok
    assert parse_coating([f"pmma:{ok!r}"])[0][1] == ok
    assert as_coating((PMMA, ok)).thickness == ok
    for make in (
        lambda: checked_thickness(bad, "x thickness"),
        lambda: LayeredMaterial(sub, [(PMMA, bad)]),
        lambda: parse_coating([f"pmma:{bad!r}"]),
        lambda: as_coating((PMMA, bad), "--coating"),
    ):
        with pytest.raises(ContactresInputError, match=r"is above 1 m") as err:
            make()
        assert "\n" not in str(err.value)
    with pytest.raises(ContactresInputError, match=r"^coating thickness \(--coating, layer 1\)"):
        as_coating((PMMA, bad), "--coating")


def test_bad_materials_and_arguments():
    with pytest.raises(ContactresInputError, match=r"substrate must be a contactres\.Material"):
        LayeredMaterial("quartz", [])
    inner = LayeredMaterial(QUARTZ, [(PMMA, 1e-7)])
    with pytest.raises(ContactresInputError, match="not a LayeredMaterial"):
        LayeredMaterial(QUARTZ, [(inner, 1e-7)])
    with pytest.raises(ContactresInputError, match="material must be"):
        surface_green(3.0, 1e6, 0.0)
    with pytest.raises(ContactresInputError, match="wavenumber must be finite and > 0"):
        surface_green(inner, [1e6, 0.0], 0.0)
    with pytest.raises(ContactresInputError, match="lossless materials only"):
        surface_green(inner.with_loss(0.01), 1e6 + 1e3j, 0.0, 1e6)
    with pytest.raises(ContactresInputError, match="frequency must be finite and >= 0 Hz"):
        surface_green(inner, 1e6, 0.0, -1.0)
    with pytest.raises(
        ContactresInputError, match="needs densities: layer 1 \\(unnamed\\) has none"
    ):
        surface_green(
            LayeredMaterial(QUARTZ, [(cr.Material.isotropic(5e9, 0.3), 1e-7)]), 1e6, 0, 1e6
        )


def test_two_root_expm_is_scipys_expm_for_matrices_of_two_roots():
    """exp(t a) from the two roots equals scipy's scaling-and-squaring expm (an independent
    algorithm) for 2x2 and 3x3 stacks with two distinct roots (one of them double, as an
    isotropic layer's P and SV/SH), complex t included, and Hermite's form where the roots
    meet: a Jordan block [[λ, 1], [0, λ]] gives e^{tλ} [[1, t], [0, 1]]."""
    from scipy.linalg import expm

    from contactres.layered import two_root_expm

    rng = np.random.default_rng(20)
    N = 12
    for n in (2, 3):
        v = rng.standard_normal((N, n, n)) + 1j * rng.standard_normal((N, n, n))
        lam_l = -rng.uniform(0.5, 3.0, N) + 0.3j * rng.standard_normal(N)
        lam_t = -rng.uniform(0.5, 3.0, N) + 0.3j * rng.standard_normal(N)
        roots = np.stack([lam_l] + [lam_t] * (n - 1), axis=1)
        mats = v @ (roots[:, :, None] * np.linalg.inv(v))  # (N, n, n), eigenvalues roots
        t = rng.uniform(0.1, 2.0, N) * np.exp(0.4j * rng.standard_normal(N))
        got = two_root_expm(np.moveaxis(mats, 0, -1), lam_l, lam_t, t)
        want = np.stack([expm(t[k] * mats[k]) for k in range(N)], axis=-1)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-10 * np.abs(want).max())
    lam = np.array([-1.0 + 0.5j, -2.0])
    t = np.array([0.7, 1.3 - 0.2j])
    jordan = np.zeros((2, 2, 2), complex)
    jordan[0, 0] = jordan[1, 1] = lam
    jordan[0, 1] = 1.0
    got = two_root_expm(jordan, lam, lam, t)
    want = np.exp(t * lam) * np.array([[np.ones(2), t], [np.zeros(2), np.ones(2)]])
    np.testing.assert_allclose(got, want, rtol=1e-14, atol=0)
