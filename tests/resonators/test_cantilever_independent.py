"""The CR-AFM inversion against models written here, apart from the package (issue 29).

* A finite-element lever (Hermite cubics, consistent mass) whose tip springs are built from the
  geometry in the laboratory frame: the lever's axis and normal as vectors, the tip apex a
  height h below the axis, the sample's normal and tangent; the 2 x 2 tip stiffness on
  (w, θ) is Bᵀ diag(k_lat, k*) B with B the apex displacement per (w, θ). Nothing of
  ``tip_coefficients`` or the module notes is used.
* A characteristic determinant in the exponential basis e^{±βξ}, e^{±iβξ} on both segments
  (8 x 8, jump conditions written from the same tip stiffness), whose complex root in β gives
  the damped lever with a Kelvin-Voigt contact k* + iω_c σ at its complex frequency ω_c.
* The free lever's roots, 1 + cos β cosh β = 0, by brentq.
"""

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq

from contactres.resonators._cantilever import Cantilever, contact_frequencies
from contactres.resonators._cantilever_inversion import (
    FLAG_BELOW_FREE,
    FLAG_NO_CONTACT,
    FLAG_SEVERAL_CROSSINGS,
    FREE_TOLERANCE,
    invert_contact_resonance,
)

F1 = 1.0e5  # Hz, the free lever's first resonance
K_C = 10.0  # N/m, k_c = 3EI/L³
#: β of the free lever's first three modes, found here (not the package's FREE_ROOTS).
FREE = [
    brentq(lambda b: 1.0 + np.cos(b) * np.cosh(b), a, a + 1.0, xtol=1e-15) for a in (1.5, 4.2, 7.4)
]
#: An ideal beam: free frequencies in the ratios of the roots, so global = modewise.
LEVER = Cantilever(tuple(F1 * (b / FREE[0]) ** 2 for b in FREE), K_C)


def tip_stiffness(alpha, eta, tilt_deg):
    """2 x 2 stiffness per unit k* on (w, dw/dξ) of the lever (L = 1), from the geometry.

    Laboratory frame: the sample's surface is the x axis, its normal n = (0, 1). The lever's
    axis points from the clamp to the free end, e_x = (cos φ, −sin φ): tilted by φ with its
    free end nearer the sample. Its normal e_y = (sin φ, cos φ) points away from the sample
    (deflection w > 0: away); the tip hangs below the axis, apex at −h e_y. A rotation θ of the
    cross-section turns −h e_y into −h e_y + θ h e_x, so the apex moves by w e_y + θ h e_x.
    """
    phi = np.radians(tilt_deg)
    e_x = np.array([np.cos(phi), -np.sin(phi)])
    e_y = np.array([np.sin(phi), np.cos(phi)])
    b = np.column_stack([e_y, eta * e_x])  # apex displacement per (w, θ), h = η L
    springs = np.diag([alpha, 1.0])  # k_lat along the surface (x), k* along its normal (y)
    return b.T @ springs @ b


def fe_betas(kappa, r, stiffness, n_el=200, n=3):
    """β of the first n modes of a Hermite-cubic FE lever (EI = ρA = L = 1, ω² = β⁴), tip
    stiffness 3κ ``stiffness`` on the (w, θ) DOFs of the node at r.

    The rotational DOFs are h θ (element length h) and the eigenproblem is solved as
    M v = μ K v for the largest μ = 1/β⁴ (K is definite: the lever is clamped), which keeps
    eigh's rounding below 1e-8 in β at 200 elements (measured; eigh(K, M) loses ~1e-6 there).
    """
    h = 1.0 / n_el
    ke = np.array([[12, 6, -12, 6], [6, 4, -6, 2], [-12, -6, 12, -6], [6, 2, -6, 4]]) / h**3
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
    scale = np.diag([1.0, 1.0 / h])  # (w, θ) = scale @ (w, hθ)
    i = 2 * node
    k[i : i + 2, i : i + 2] += 3.0 * kappa * scale @ stiffness @ scale
    mu = eigh(m[2:, 2:], k[2:, 2:], eigvals_only=True, subset_by_index=(nd - 2 - n, nd - 3))
    return mu[::-1] ** -0.25


def fe_frequencies(kappa, r, stiffness, n=3):
    return F1 * (fe_betas(kappa, r, stiffness, n=n) / FREE[0]) ** 2


def exp_frequencies(kappa, r, stiffness, n=3):
    """The first n frequencies (Hz) from the real roots of :func:`det_exp` (any r, not only
    FE nodes). For real β the determinant is real: the exponential basis is the trigonometric
    and hyperbolic one times a constant matrix of real determinant."""
    grid = np.arange(0.5, 12.0, 0.01)
    d = det_exp(grid, kappa, r, stiffness).real  # the whole grid in one stacked det
    idx = np.nonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0][:n]
    fun = lambda b: det_exp(b, kappa, r, stiffness).real  # noqa: E731
    beta = np.array([brentq(fun, grid[i], grid[i + 1], xtol=1e-14) for i in idx])
    return F1 * (beta / FREE[0]) ** 2


def det_exp(beta, kappa, r, stiffness):
    """det of the 8 x 8 system in the basis e^{λξ}, λ = ±β, ±iβ, on [0, r] and [r, 1]:
    clamped at 0, free at 1, y and y′ continuous at r, and the jumps of the moment and shear
    from the tip springs: y″(r⁺) − y″(r⁻) = 3κ (G_wθ y + G_θθ y′) and
    y‴(r⁺) − y‴(r⁻) = −3κ (G_ww y + G_wθ y′) (ξ-derivatives, L = 1, k_c = 3EI).
    ``beta`` may be an array: one determinant per β (the scan of a grid in one call)."""
    beta = np.asarray(beta)[..., None]
    lam = np.array([1.0, -1.0, 1j, -1j]) * beta
    zero = np.zeros_like(lam)

    def d(x, k, side):  # k-th ξ-derivative of the basis at x, divided by β^k
        v = (lam / beta) ** k * np.exp(lam * x)
        return np.concatenate([v, zero] if side == 0 else [zero, v], axis=-1)

    (g_ww, g_wt), (_, g_tt) = stiffness
    y, slope = d(r, 0, 0), beta * d(r, 1, 0)
    rows = [d(0, 0, 0), d(0, 1, 0), d(1, 2, 1), d(1, 3, 1), d(r, 0, 1) - y, d(r, 1, 1) - d(r, 1, 0)]
    rows.append(d(r, 2, 1) - d(r, 2, 0) - 3 * kappa * (g_wt * y + g_tt * slope) / beta**2)
    rows.append(d(r, 3, 1) - d(r, 3, 0) + 3 * kappa * (g_ww * y + g_wt * slope) / beta**3)
    return np.linalg.det(np.stack(rows, axis=-2))


def damped(k_star, sigma, r, stiffness, mode, free_q=None):
    """(f, Q) of ``mode`` of the lever with a Kelvin-Voigt contact (k* N/m, σ N s/m): the
    complex root ω_c of det(β(ω_c), (k* + iω_c σ)/k_c) = 0, continued by Newton from the
    undamped root. The lever's own loss (``free_q``): its bending stiffness complex, so that
    β⁴ ∝ ω² with the first free mode at 2πF1 (1 + i/(2Q_free))."""
    w_ref = 2 * np.pi * F1 * (1 + (0.5j / free_q if free_q else 0.0))
    kappa0 = k_star / K_C
    grid = np.arange(0.5, 12.0, 0.01)
    d = det_exp(grid, kappa0, r, stiffness).real
    i = np.nonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0][mode - 1]
    b0 = brentq(lambda b: det_exp(b, kappa0, r, stiffness).real, grid[i], grid[i + 1])

    def fun(b):
        w = w_ref * (b / FREE[0]) ** 2
        return det_exp(b, (k_star + 1j * w * sigma) / K_C, r, stiffness)

    b = complex(b0)
    for _ in range(40):
        h = 1e-7 * abs(b)
        step = fun(b) / ((fun(b + h) - fun(b - h)) / (2 * h))
        b -= step
        if abs(step) < 1e-14 * abs(b):
            break
    w = w_ref * (b / FREE[0]) ** 2
    return w.real / (2 * np.pi), w.real / (2 * w.imag)


# --- 1. The free limit -------------------------------------------------------------------


def test_free_frequency_gives_zero_stiffness_flagged_no_contact():
    # The free resonances from brentq's roots: exactly no contact, with and without a Q.
    f_free = F1 * (np.array(FREE) / FREE[0]) ** 2
    res = invert_contact_resonance(LEVER, f_free[None, :], 0.95)
    assert np.array_equal(res.kappa, [0.0]) and np.array_equal(res.k_star, [0.0])
    assert np.array_equal(res.flags_modes, [[FLAG_NO_CONTACT] * 3])
    assert res.flags[0] == FLAG_NO_CONTACT
    damped_lever = Cantilever(LEVER.free_frequencies, K_C, free_q_factors=(300, 400, 500))
    res = invert_contact_resonance(
        damped_lever, f_free[None, :1], 0.95, q_factors=[[300.0]], modes=(1,)
    )
    assert res.kappa[0] == 0.0 and res.sigma[0] == 0.0 and res.flags[0] == FLAG_NO_CONTACT
    # the lever's Q known, the contact's not: still the free frequency, still no contact
    res = invert_contact_resonance(damped_lever, f_free[None, :], 0.95)
    assert res.kappa[0] == 0.0 and np.array_equal(res.flags_modes, [[FLAG_NO_CONTACT] * 3])


def test_a_hair_below_the_free_frequency_is_no_contact_further_below_is_below_free():
    f_free = F1 * (FREE[1] / FREE[0]) ** 2  # mode 2
    f = f_free * (1 - np.array([0.01, 0.99, 3.0]) * FREE_TOLERANCE)
    res = invert_contact_resonance(LEVER, f[:, None], 0.9, modes=(2,))
    assert np.array_equal(res.kappa[:2], [0.0, 0.0])
    assert np.array_equal(res.flags[:2], [FLAG_NO_CONTACT] * 2)
    assert res.flags[2] & FLAG_BELOW_FREE and not res.flags[2] & FLAG_NO_CONTACT
    assert not res.kappa[2] >= 0  # negative or NaN: no κ >= 0 explains it
    # Above the free frequency by less than the tolerance: no contact too (the band is
    # symmetric); beyond it the contact is tiny but real: no flag "no contact".
    f_above = f_free * (1 + np.array([0.99, 3.0]) * FREE_TOLERANCE)
    above = invert_contact_resonance(LEVER, f_above[:, None], 0.9, modes=(2,))
    assert above.kappa[0] == 0.0 and above.flags[0] == FLAG_NO_CONTACT
    assert 0 < above.kappa_modes[1, 0] < 1e-3 and not above.flags[1] & FLAG_NO_CONTACT


def test_a_free_frequency_is_no_contact_whatever_its_rounding():
    # f equal to the free one gives f/f_free = 1 ± 2e-16 as the rounding of the model's free
    # frequency falls (88 kHz gave 1 + 2e-16, and κ NaN before the band was made symmetric):
    # every whole-Hz free frequency from 10 to 500 kHz, 88 kHz among them, and each moved by
    # ±1e-12 (relative), far inside the 1e-6 band, is no contact, κ = 0 (with a Q: σ = 0, on
    # every tenth of them).
    base = np.append(np.unique(np.round(np.geomspace(1e4, 5e5, 2000))), 88e3)
    shifts = np.array([[0.0], [-1e-12], [1e-12]])
    for q, every in ((None, 1), (200.0, 10)):
        for f_free in base[::every]:
            lever = Cantilever((f_free,), 3.0, free_q_factors=None if q is None else (q,))
            qs = None if q is None else np.full((3, 1), q)
            res = invert_contact_resonance(lever, f_free * (1.0 + shifts), 0.95, q_factors=qs)
            assert np.all(res.kappa == 0.0) and np.all(res.flags == FLAG_NO_CONTACT), f_free
            assert q is None or np.all(res.sigma == 0.0)


# --- 3. The tilted lever with a lateral spring ---------------------------------------------

TILTED = [
    (alpha, tilt, r) for alpha in (0.5, 0.75, 1.0) for tilt in (1e-6, 11.0) for r in (0.9, 1.0)
]


@pytest.mark.parametrize("alpha, tilt, r", TILTED)
def test_tilted_lever_with_lateral_spring_matches_the_fe_beam(alpha, tilt, r):
    eta = 0.05
    stiffness = tip_stiffness(alpha, eta, tilt)
    springs = dict(lateral_ratio=alpha, tip_height=eta, tilt=tilt)
    kappa = np.array([3.0, 30.0, 300.0])
    fe = np.array([fe_frequencies(k, r, stiffness) for k in kappa])
    f = contact_frequencies(LEVER, kappa, r, **springs)
    assert np.max(np.abs(f / fe - 1)) < 3e-8  # measured <= 6e-9 (the FE's own error)
    res = invert_contact_resonance(LEVER, fe, r, **springs)
    # κ from the FE's frequencies: their 6e-9 error grows by 1/s (s = d ln f/d ln κ) in κ,
    # to <= 1e-6 for the modes the inversion does not flag (measured 2e-7)
    good = res.flags_modes == 0
    assert good.sum() >= 7
    assert np.max(np.abs(res.kappa_modes / kappa[:, None] - 1)[good]) < 1e-6


def test_the_tilt_sign_convention_matters_and_is_the_documented_one():
    # φ > 0 is the free end nearer the sample (tip_stiffness above). The other sign, a mirrored
    # mounting, changes κ by per cent where the lateral spring differs from the normal one:
    # reading one convention for the other is an error of that size.
    alpha, eta, r, kappa = 0.5, 0.05, 1.0, 100.0
    springs = dict(lateral_ratio=alpha, tip_height=eta, tilt=11.0)
    right = fe_frequencies(kappa, r, tip_stiffness(alpha, eta, 11.0))
    mirrored = fe_frequencies(kappa, r, tip_stiffness(alpha, eta, -11.0))
    k_right = invert_contact_resonance(LEVER, right[:1], r, modes=(1,), **springs).kappa
    k_mirror = invert_contact_resonance(LEVER, mirrored[:1], r, modes=(1,), **springs).kappa
    assert abs(k_right / kappa - 1) < 1e-6
    assert abs(k_mirror / kappa - 1) > 0.05  # measured 19 %


# --- 2. Several crossings, and the tip at the very end ---------------------------------------


@pytest.mark.parametrize("r", [0.9, 0.95, 1.0])
def test_two_modes_give_the_physical_crossing_and_the_other_beside_it(r):
    # The FE lever's modes 1-2 with the tip at r: κ_a(r) = κ_b(r) has a second root near
    # r ≈ 0.64-0.69 (its partner). Judged by the FE's third mode, the crossing near the end is
    # the lever (f3 reproduced), the other is not: the largest r is the physical one.
    kappa = np.array([3.0, 30.0, 100.0])
    stiffness = tip_stiffness(0.0, 0.0, 0.0)
    fe = np.array([fe_frequencies(k, r, stiffness) for k in kappa])
    res = invert_contact_resonance(LEVER, fe[:, :2])
    assert np.max(np.abs(res.tip_position - r)) < 1e-6
    assert np.max(np.abs(res.kappa / kappa - 1)) < 1e-5
    assert np.all(res.flags == FLAG_SEVERAL_CROSSINGS)  # information, with values
    other, k_other = res.tip_position_other, res.kappa_other
    assert np.all((other > 0.6) & (other < 0.7)) and np.all(k_other > 0)
    for i in range(kappa.size):
        f3_taken = exp_frequencies(res.kappa[i], res.tip_position[i], stiffness)[2]
        assert abs(f3_taken / fe[i, 2] - 1) < 1e-8  # measured 2e-9: the FE's own error
        # measured 1.6e-3 (κ = 3, where the contact moves f3 by 0.02-0.5 % at all) to 0.31
        f3_other = exp_frequencies(k_other[i], other[i], stiffness)[2]
        assert abs(f3_other / fe[i, 2] - 1) > 1e-3


@pytest.mark.parametrize(
    "springs, kappa",
    [
        ({}, 30.0),
        (dict(lateral_ratio=1.0, tip_height=0.05, tilt=11.0), 300.0),
        (dict(lateral_ratio=0.5, tip_height=0.05, tilt=11.0), 30.0),
    ],
)
@pytest.mark.parametrize("error", [1e-7, -1e-7, 1e-6, -1e-6])
def test_tip_at_the_end_survives_a_small_frequency_error(springs, kappa, error):
    # A tip at r = 1 and a relative error of ±1e-7 or ±1e-6 in f2: the crossing moves to
    # either side of r = 1. Both sides must give r = 1 and κ (one side found none but the
    # far crossing near r = 0.62, κ off by a factor 2.6 to 4).
    f = contact_frequencies(LEVER, kappa, 1.0, modes=(1, 2), **springs)
    f = f * np.array([1.0, 1.0 + error])
    res = invert_contact_resonance(LEVER, f, **springs)
    assert abs(res.tip_position - 1.0) < 1e-5
    assert abs(res.kappa / kappa - 1) < 100 * abs(error)  # κ moves by error/s, s >= 0.01


def test_a_crossing_truly_past_the_end_is_not_taken_for_the_end():
    # Lateral spring, κ = 300 at r = 0.95: the saturated modes also meet at r ≈ 1.0049, where
    # κ_a and κ_b differ by 5 % at r = 1: not the tip at the end (END_TOLERANCE).
    springs = dict(lateral_ratio=0.5, tip_height=0.05, tilt=11.0)
    f = contact_frequencies(LEVER, 300.0, 0.95, modes=(1, 2), **springs)
    res = invert_contact_resonance(LEVER, f, **springs)
    assert abs(res.tip_position - 0.95) < 1e-9 and abs(res.kappa / 300.0 - 1) < 1e-8


# --- 4. The damped inversion -------------------------------------------------------------

DAMPED = [  # κ, tan δ = ωσ/k* at the undamped mode 1, lateral spring (α, η, φ), free Q
    (3.0, 0.04, (0.0, 0.0, 0.0), None),
    (30.0, 0.05, (0.0, 0.0, 0.0), None),
    (30.0, 0.05, (0.0, 0.0, 0.0), 300.0),
    (30.0, 0.05, (0.5, 0.05, 11.0), None),
]


@pytest.mark.parametrize("kappa, tan_delta, springs, free_q", DAMPED)
def test_damped_inversion_is_the_exact_complex_root(kappa, tan_delta, springs, free_q):
    alpha, eta, tilt = springs
    stiffness = tip_stiffness(alpha, eta, tilt)
    r, k_star = 0.95, kappa * K_C
    omega = 2 * np.pi * fe_frequencies(kappa, r, stiffness, n=1)[0]
    sigma = tan_delta * k_star / omega  # N s/m
    f, q = damped(k_star, sigma, r, stiffness, 1, free_q)
    assert 35 < q < 66  # the checks' range
    lever = LEVER if free_q is None else Cantilever((F1,), K_C, free_q_factors=(free_q,))
    res = invert_contact_resonance(
        lever, [[f]], r, q_factors=[[q]], modes=(1,), lateral_ratio=alpha, tip_height=eta,
        tilt=tilt,
    )  # fmt: skip
    # k* + iω_c σ at ω_c = ω(1 + i/(2Q)): k* = k_c(κ′ + κ″/(2Q)), σ = k_c κ″/ω; taking k_c κ′
    # for k* was off by κ″/(2Qκ′), 5e-4 to 8e-4 here
    assert abs(res.k_star[0] / k_star - 1) < 1e-9
    assert abs(res.sigma[0] / sigma - 1) < 1e-8
