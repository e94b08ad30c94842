"""Tests of contactres.resonators._qcm: paper 2, Eqs. 1-2, the loop quadrature (Eqs. 4-5), the
expansions (Eqs. 11-12, 15) and the friction coefficient."""

import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import array_shapes
from scipy.integrate import quad

import contactres as cr
from contactres.resonators._qcm import loop_stiffness
from contactres.tangential import PlateauLoop

# scipy.quad at epsrel ~1e-13 warns about round-off it cannot beat; the tests compare values.
pytestmark = pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")

Q = cr.QCM(fundamental=5e6, overtone=3, area=1e-5)
OMEGA = Q.omega
CM = cr.CattaneoMindlinLoop(kappa=4e5, mu=0.8, normal_force=5e-3)  # d* = 15 nm
SV = cr.SavkoorLoop(kappa=4e5, tau=20e6, a=5e-6)  # d_s = 5 nm
PL = PlateauLoop(CM, critical_displacement=3e-9)
PLS = PlateauLoop(SV, critical_displacement=1e-9)
MASING = [CM, SV, PL, PLS]


class BranchesOnly:
    """A loop seen only through ``branches`` and ``kinks``: it is not a Masing loop nor a dashpot,
    so :func:`loop_stiffness` integrates Eq. 4 straight from its branches (the generic path)."""

    def __init__(self, loop):
        self._loop = loop

    def branches(self, u, u0):
        return self._loop.branches(u, u0)

    def kinks(self, u0):
        return self._loop.kinks(u0)


def quad_stiffness(loop, u0):
    """Eqs. 4-5 by adaptive quadrature straight from the branches (x = sin t), split at kinks."""
    kinks = sorted(np.arcsin(x) for x in np.ravel(loop.kinks(u0)) if np.isfinite(x))

    def g(t, part):
        up, down = loop.branches(u0 * np.sin(t), u0)
        return (up + down) * np.sin(t) if part == 0 else (up - down) * np.cos(t)

    out = []
    for part in (0, 1):
        val, _ = quad(
            g,
            -np.pi / 2,
            np.pi / 2,
            args=(part,),
            points=kinks or None,
            epsabs=1e-16 * loop.kappa * u0,
            epsrel=1e-14,
            limit=500,
        )
        out.append(val / (np.pi * u0))
    return complex(out[0], out[1])


def fft_stiffness(loop, u0, n=2**15):
    """Eq. 3 (time domain): (2/u0)<F(t) e^{-iωt}> with u = u0 cos ωt, over one period."""
    theta = 2 * np.pi * np.arange(n) / n
    u = u0 * np.cos(theta)
    up, down = loop.branches(u, u0)
    F = np.where(theta < np.pi, down, up)  # moving down for 0 < ωt < π
    return 2.0 / u0 * np.fft.fft(F)[1] / n


# --- Eqs. 1-2 ---------------------------------------------------------------------------------


def test_qcm_sensitivity_by_hand():
    # P = n_P/(2nπ²AZq) = 3/(2·3·π²·1e-5·8.8e6)
    assert Q.sensitivity(3) == pytest.approx(3 / (6 * np.pi**2 * 1e-5 * 8.8e6), rel=1e-15)
    assert Q.omega == pytest.approx(2 * np.pi * 15e6)
    df, dg = cr.shifts_from_stiffness(Q, 1e5, 1e-3, 3)
    assert df == pytest.approx(1e5 * Q.sensitivity(3)) and df > 0
    assert dg == pytest.approx(Q.omega * 1e-3 * Q.sensitivity(3))


@given(
    kappa=st.floats(0, 1e7),
    xi=st.floats(0, 1e-1),
    n=st.integers(1, 5),
    overtone=st.sampled_from([1, 3, 5, 7, 11]),
)
def test_stiffness_shift_round_trip(kappa, xi, n, overtone):
    q = cr.QCM(5e6, overtone, 2e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        df, dg = cr.shifts_from_stiffness(q, kappa, xi, n)
        k, x = cr.stiffness_from_shifts(q, df, dg, n)
    assert k == pytest.approx(kappa, rel=1e-14, abs=1e-300)
    assert x == pytest.approx(xi, rel=1e-14, abs=1e-300)


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(overtone=2),
        dict(overtone=0),
        dict(overtone=3.5),
        dict(overtone=np.inf),
        dict(overtone=np.nan),
        dict(fundamental=-5e6),
        dict(area=0.0),
        dict(zq=np.nan),
    ],
)
def test_qcm_validation(kwargs):
    with pytest.raises(ValueError):
        cr.QCM(**kwargs)


def test_warning_when_shift_is_not_small():
    with pytest.warns(RuntimeWarning, match="small-load"):
        cr.shifts_from_stiffness(Q, 1e12, 0.0, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cr.shifts_from_stiffness(Q, 1e5, 0.0, 1)


# --- Eqs. 4-5 ---------------------------------------------------------------------------------


def test_voigt_identity():
    loop = cr.VoigtLoop(3.3e5, 2.2e-3, OMEGA)
    u0 = np.array([0.0, 1e-12, 1e-9, 7e-9, 1e-6])
    k = loop_stiffness(loop, u0)
    np.testing.assert_allclose(k.real, 3.3e5, rtol=1e-12)
    np.testing.assert_allclose(k.imag, OMEGA * 2.2e-3, rtol=1e-12)
    df, dg = cr.shifts_from_loop(Q, loop, u0, 3)
    np.testing.assert_allclose(df, cr.shifts_from_stiffness(Q, 3.3e5, 2.2e-3, 3)[0], rtol=1e-12)
    np.testing.assert_allclose(dg, cr.shifts_from_stiffness(Q, 3.3e5, 2.2e-3, 3)[1], rtol=1e-12)


@pytest.mark.parametrize("loop", [*MASING, cr.with_dashpot(CM, 1e-3, OMEGA)])
@pytest.mark.parametrize("frac", [0.3, 0.9, 1.7, 6.0])
def test_time_domain_eq3_equals_eqs_4_5(loop, frac):
    u0 = frac * max(getattr(loop, "breaks", CM.breaks))
    k = loop_stiffness(loop, u0)
    kf = fft_stiffness(loop, u0)
    assert abs(kf - k) < 1e-8 * abs(k)


@pytest.mark.parametrize("loop", MASING)
@pytest.mark.parametrize("rel", [-0.5, -1e-3, -1e-6, -1e-12, 0.0, 1e-12, 1e-6, 1e-3, 0.5, 9.0, 1e3])
def test_quadrature_against_adaptive_reference_at_and_near_kinks(loop, rel):
    # amplitudes around the last break (full sliding) and, for the plateau, the first one
    for b in loop.breaks:
        u0 = b * (1 + rel)
        k = loop_stiffness(loop, u0)
        ref = quad_stiffness(loop, u0)
        assert k.real == pytest.approx(ref.real, rel=1e-9)
        assert k.imag == pytest.approx(ref.imag, rel=1e-9, abs=1e-12 * loop.kappa)


@pytest.mark.parametrize("loop", MASING)
def test_quadrature_converges_doubling_nodes(loop):
    b = max(loop.breaks)
    u0 = b * np.concatenate(
        [1 + np.logspace(-14, 0, 15), 1 - np.logspace(-14, -0.1, 15), np.logspace(-4, 3, 30)]
    )
    k = loop_stiffness(loop, u0)
    k2 = loop_stiffness(loop, u0, nodes=2 * 24)
    assert np.max(np.abs(k.real / k2.real - 1)) < 1e-10
    nz = k2.imag > 1e-12 * loop.kappa
    assert np.max(np.abs(k.imag[nz] / k2.imag[nz] - 1)) < 1e-10


@pytest.mark.parametrize("loop", MASING)
def test_loop_area_closed_form_gives_k2(loop):
    u0 = max(loop.breaks) * np.array([0.01, 0.2, 0.8, 1.0, 1.3, 10.0])
    u0 = np.concatenate([u0, min(loop.breaks) * (1 + np.array([1e-4, 1e-3, 0.3]))])
    k = loop_stiffness(loop, u0)
    np.testing.assert_allclose(
        k.imag, loop.area(u0) / (np.pi * u0**2), rtol=1e-10, atol=1e-14 * loop.kappa
    )


@pytest.mark.parametrize("loop", [CM, SV])
def test_generic_branch_quadrature_agrees_with_masing_form(loop):
    # a second algorithm: Eq. 4 from the branches (cos-mapped pieces split at the kinks)
    u0 = loop.slip_displacement * np.array([0.2, 0.5, 1.5, 3.0, 20.0])
    g = loop_stiffness(BranchesOnly(loop), u0, nodes=200)
    k = loop_stiffness(loop, u0)
    np.testing.assert_allclose(g.real, k.real, rtol=1e-10)
    np.testing.assert_allclose(g.imag, k.imag, rtol=1e-10)


def test_dashpot_adds_exactly_omega_xi():
    u0 = np.array([0.0, 1e-9, 20e-9, 100e-9])
    k0 = loop_stiffness(CM, u0)
    k1 = loop_stiffness(cr.with_dashpot(CM, 1.5e-3, OMEGA), u0)
    np.testing.assert_allclose(k1 - k0, 1j * OMEGA * 1.5e-3, rtol=1e-15)
    # ... and so does the branch quadrature of the wrapped loop (not special-cased)
    g = loop_stiffness(BranchesOnly(cr.with_dashpot(CM, 1.5e-3, OMEGA)), u0[1:], nodes=200)
    gi = loop_stiffness(BranchesOnly(CM), u0[1:], nodes=200)
    np.testing.assert_allclose(g.imag - gi.imag, OMEGA * 1.5e-3, rtol=1e-10)


def test_zero_amplitude_limit():
    k = loop_stiffness(CM, np.array([0.0, 1e-20]))
    np.testing.assert_allclose(k.real, CM.kappa, rtol=1e-12)
    assert k.imag[0] == 0 and k.imag[1] < 1e-10 * CM.kappa


def test_plateau_keeps_low_amplitude_values():
    u0 = np.linspace(0, 3e-9, 5)
    k = loop_stiffness(PL, u0)
    np.testing.assert_allclose(k.real, PL.kappa, rtol=1e-14)
    np.testing.assert_allclose(k.imag, 0, atol=1e-14 * PL.kappa)
    assert loop_stiffness(PL, 4e-9).real < PL.kappa


def test_full_sliding_rectangle_limit():
    # u0 ≫ d*: the loop is a rectangle of height 2μF_N: K″ -> 4μF_N/(π u0), K′ -> 0.
    d = CM.slip_displacement
    for k in (1e3, 1e5):
        K = loop_stiffness(CM, k * d)
        assert K.imag * np.pi * k * d / (4 * CM.sliding_force) == pytest.approx(1, rel=2 / k)
        assert K.real < 2 * CM.kappa / np.sqrt(k) ** 1


# --- expansions (Eqs. 11-12, 15) -----------------------------------------------------------------


def _richardson(f, h):
    return 2 * f(h) - f(2 * h)


def test_cattaneo_mindlin_coefficients_from_quadrature():
    k, muF = CM.kappa, CM.sliding_force

    def K(e):
        return loop_stiffness(CM, e * muF / k) / k

    c1 = _richardson(lambda e: (K(e).real - 1) / e, 1e-4)
    c2 = _richardson(lambda e: (K(e).real - 1 + e / 6) / e**2, 1e-3)
    d1 = _richardson(lambda e: K(e).imag / e, 1e-4)
    d2 = _richardson(lambda e: (K(e).imag - 2 * e / (9 * np.pi)) / e**2, 1e-3)
    assert c1 == pytest.approx(-1 / 6, rel=1e-7)
    assert c2 == pytest.approx(-5 / 288, rel=1e-5)
    assert d1 == pytest.approx(2 / (9 * np.pi), rel=1e-7)
    assert d2 == pytest.approx(1 / (27 * np.pi), rel=1e-5)
    # The OCR of the paper's Eq. 11 (1/3 and 4/(9π)) is twice these: rejected.
    assert abs(c1 / (-1 / 3) - 1) > 0.4 and abs(d1 / (4 / (9 * np.pi)) - 1) > 0.4


def test_savkoor_coefficients_from_quadrature():
    k, a2t = SV.kappa, SV.a**2 * SV.tau

    def K(e):
        return loop_stiffness(SV, e * a2t / k) / k

    c2 = _richardson(lambda e: (K(e).real - 1) / e**2, 1e-3)
    d2 = _richardson(lambda e: K(e).imag / e**2, 1e-3)
    assert c2 == pytest.approx(-5 / 512, rel=1e-5)
    assert d2 == pytest.approx(1 / (48 * np.pi), rel=1e-5)


def test_expansions_match_quadrature_to_their_order():
    # the remainder is of third (CM) or fourth (Savkoor, even in u0) order
    for loop, expand, unit, order in (
        (CM, cr.cattaneo_mindlin_expansion, CM.sliding_force / CM.kappa, 3),
        (SV, cr.savkoor_expansion, SV.a**2 * SV.tau / SV.kappa, 4),
    ):
        errs = []
        for e in (5e-3, 1e-2):
            diff = expand(loop, e * unit, 7.0) - 7j - loop_stiffness(loop, e * unit)
            assert abs(diff) < 0.02 * e**3 * loop.kappa
            errs.append(abs(diff))
        assert errs[1] / errs[0] == pytest.approx(2**order, rel=0.1)


def test_friction_from_slopes_recovers_mu():
    u0 = np.array([1e-12, 2e-12])
    df, dg = cr.shifts_from_loop(Q, cr.with_dashpot(CM, 1e-3, OMEGA), u0, 3)
    s_df = (df[1] - df[0]) / (u0[1] - u0[0])
    s_dg = (dg[1] - dg[0]) / (u0[1] - u0[0])
    mu1, mu2 = cr.friction_from_slopes(Q, CM.kappa, CM.normal_force, s_df, s_dg, 3)
    assert mu1 == pytest.approx(CM.mu, rel=1e-3)
    assert mu2 == pytest.approx(CM.mu, rel=1e-3)
    m1, m2 = cr.friction_from_slopes(Q, CM.kappa, CM.normal_force, -s_df, None, 3)
    assert np.isnan(m1) and np.isnan(m2)


# --- vectorisation (hypothesis) ------------------------------------------------------------


@given(
    shape=array_shapes(min_dims=0, max_dims=3, max_side=4),
    scale=st.floats(1e-11, 1e-7),
    n=st.integers(1, 4),
)
def test_shifts_from_loop_shapes_and_signs(shape, scale, n):
    rng = np.random.default_rng(0)
    u0 = scale * rng.random(shape)
    for loop in (CM, SV, PL):
        df, dg = cr.shifts_from_loop(Q, loop, u0, n)
        assert np.shape(df) == shape and np.shape(dg) == shape
        assert np.all(np.asarray(dg) >= -1e-12 * Q.sensitivity(n) * loop.kappa)
        assert np.all(np.asarray(df) <= Q.sensitivity(n) * loop.kappa * (1 + 1e-12))


@given(st.lists(st.floats(0, 1e-7), min_size=2, max_size=20, unique=True))
def test_cattaneo_mindlin_df_falls_and_dgamma_positive(u0):
    u0 = np.sort(u0)
    df, dg = cr.shifts_from_loop(Q, CM, u0, 3)
    assert np.all(np.diff(df) <= 1e-12 * abs(df[0]))
    assert np.all(dg[u0 > 0] > 0)


def test_bad_input():
    with pytest.raises(ValueError, match="u0"):
        cr.shifts_from_loop(Q, CM, [-1e-9])
    with pytest.raises(ValueError, match="not a loop"):
        cr.shifts_from_loop(Q, object(), [1e-9])
    with pytest.raises(ValueError, match="n_contacts"):
        cr.shifts_from_loop(Q, CM, [1e-9], 0)
    # a negative amplitude is named with its value and position, also by the expansions
    with pytest.raises(ValueError, match=r"u0 .*>= 0 \(m\), got -2e-09 at index 1"):
        cr.shifts_from_loop(Q, CM, [1e-9, -2e-9])
    with pytest.raises(ValueError, match="u0"):
        cr.cattaneo_mindlin_expansion(CM, -1e-9)
    with pytest.raises(ValueError, match="u0"):
        cr.savkoor_expansion(SV, -1e-9)
    with pytest.raises(ValueError, match=r"kappa > 0 .*got kappa=-1"):
        cr.friction_from_slopes(Q, -1.0, 1e-3, -1.0, 1.0)
