"""Tests of contactres.tangential: virgin curves, Masing loops, loop areas, dashpot, plateau."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

import contactres as cr
from contactres.tangential import PlateauLoop, kappa_jkr_mindlin

# scipy.quad at epsrel ~1e-13 warns about round-off it cannot beat; the tests compare values.
pytestmark = pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")

OMEGA = 2 * np.pi * 15e6
CM = cr.CattaneoMindlinLoop(kappa=4e5, mu=0.8, normal_force=5e-3)  # d* = 15 nm
SV = cr.SavkoorLoop(kappa=4e5, tau=20e6, a=5e-6)  # d_s = 5 nm
PL = PlateauLoop(CM, critical_displacement=3e-9)
LOOPS = [CM, SV, PL, cr.VoigtLoop(4e5, 1e-3, OMEGA), cr.with_dashpot(CM, 2e-3, OMEGA)]


def quad_area(loop, u0):
    """Loop area by adaptive quadrature of F₊ - F₋ (independent of the closed forms)."""
    pts = [x for x in np.ravel(loop.kinks(u0)) if np.isfinite(x)]
    f = lambda u: np.subtract(*loop.branches(u, u0))  # noqa: E731
    tol = 1e-15 * loop.kappa * u0**2
    val, _ = quad(
        f, -u0, u0, points=[p * u0 for p in pts] or None, epsabs=tol, epsrel=1e-13, limit=200
    )
    return val


def test_mindlin_stiffness():
    assert cr.mindlin_stiffness(2e-6, 1e10) == pytest.approx(4e4)
    with pytest.raises(ValueError):
        cr.mindlin_stiffness(1e-6, -1.0)


def test_cattaneo_mindlin_virgin_curve():
    d = CM.slip_displacement
    assert d == pytest.approx(1.5 * 0.8 * 5e-3 / 4e5)
    assert CM.virgin(d) == pytest.approx(CM.sliding_force, rel=1e-15)
    assert CM.virgin(3 * d) == pytest.approx(CM.sliding_force, rel=1e-15)
    h = 1e-6 * d
    assert (CM.virgin(h) - CM.virgin(-h)) / (2 * h) == pytest.approx(CM.kappa, rel=1e-6)
    assert CM.virgin(-0.3 * d) == -CM.virgin(0.3 * d)


def test_savkoor_virgin_curve_from_eqs_13_14():
    a, tau, kappa = SV.a, SV.tau, SV.kappa
    u = np.linspace(0, SV.slip_displacement, 7)[1:-1]
    # Eq. 14 for the stick radius c, then Eq. 13, written with arccos as printed.
    c = np.sqrt(a**2 - (kappa * u / (4 * a * tau)) ** 2)
    F = 2 * tau * (a**2 * np.arccos(c / a) + c * np.sqrt(a**2 - c**2))
    np.testing.assert_allclose(SV.virgin(u), F, rtol=1e-13)
    assert SV.slip_displacement == pytest.approx(4 * a**2 * tau / kappa)
    assert SV.virgin(SV.slip_displacement) == pytest.approx(np.pi * a**2 * tau, rel=1e-15)
    # Small-u expansion of Eqs. 13-14 (arcsin z + z√(1 - z²) = 2z - z³/3 + ..., z = u/d_s):
    # F ≈ κu - κ³u³/(96 a⁴ τ0²).
    u = 1e-3 * SV.slip_displacement
    series = kappa * u - kappa**3 * u**3 / (96 * a**4 * tau**2)
    assert SV.virgin(u) == pytest.approx(series, rel=1e-11)


@pytest.mark.parametrize("loop", [CM, SV, PL])
def test_slope_and_slope_loss_match_numerical_derivative(loop):
    d = np.array([0.1, 0.5, 0.9, 1.2]) * max(loop.breaks)
    h = 1e-6 * max(loop.breaks)
    num = (loop.virgin(d + h) - loop.virgin(d - h)) / (2 * h)
    np.testing.assert_allclose(loop.slope(d), num, rtol=1e-7, atol=1e-9 * loop.kappa)
    np.testing.assert_allclose(loop.slope(d) + loop.slope_loss(d), loop.kappa, rtol=1e-14)
    both = loop.slopes(d)
    np.testing.assert_allclose(both[0], loop.slope(d), rtol=1e-15)
    np.testing.assert_allclose(both[1], loop.slope_loss(d), rtol=1e-15)


@pytest.mark.parametrize("loop", LOOPS)
@given(x=st.floats(-1, 1), frac=st.floats(0.01, 5.0))
def test_masing_symmetry(loop, x, frac):
    u0 = frac * 10e-9
    up, down = loop.branches(x * u0, u0)
    up_m, _ = loop.branches(-x * u0, u0)
    assert down == pytest.approx(-up_m, rel=1e-12, abs=1e-15 * loop.kappa * u0)
    # the loop closes at the turning points and is traversed anticlockwise (dissipative)
    assert up >= down - 1e-12 * loop.kappa * u0


@pytest.mark.parametrize("loop", LOOPS)
@pytest.mark.parametrize("frac", [0.05, 0.3, 0.999, 1.5, 4.0])
def test_area_closed_form_matches_quadrature(loop, frac):
    u0 = frac * 10e-9
    ref = quad_area(loop, u0)
    assert loop.area(u0) == pytest.approx(ref, rel=1e-10, abs=1e-14 * loop.kappa * u0**2)


@pytest.mark.parametrize("loop", [CM, SV])
def test_area_series_and_closed_form_agree_at_the_switch(loop):
    d = loop.slip_displacement
    below, above = loop.area(0.1 * d * (1 - 1e-12)), loop.area(0.1 * d)
    assert below == pytest.approx(above, rel=1e-9)


@pytest.mark.parametrize("loop", [CM, SV])
def test_slack_series_matches_closed_form_and_quadrature(loop):
    d = loop.slip_displacement
    assert loop.slack(0.1 * d * (1 - 1e-12)) == pytest.approx(loop.slack(0.1 * d), rel=1e-9)
    for v in (1e-3 * d, 0.05 * d, 0.5 * d):
        ref, _ = quad(loop.slope_loss, 0, v, epsabs=0, epsrel=1e-13)
        assert loop.slack(v) == pytest.approx(ref, rel=1e-12)


def test_area_at_tiny_amplitude_has_cubic_law():
    # Mindlin & Deresiewicz to leading order in q = Q*/(μF_N): W ≈ 2Q*³/(9κμF_N), Q* ≈ κu0
    # (the bracket of their energy is 5q³/162 + O(q⁴)).
    u0 = 1e-6 * CM.slip_displacement
    W = 2 * (CM.kappa * u0) ** 3 / (9 * CM.kappa * CM.sliding_force)
    assert CM.area(u0) == pytest.approx(W, rel=1e-5)


@pytest.mark.parametrize("frac", [0.01, 0.2, 0.7, 0.99, 1.0])
def test_cattaneo_mindlin_area_is_mindlin_deresiewicz_energy(frac):
    u0 = frac * CM.slip_displacement
    Q = CM.virgin(u0)
    W = cr.mindlin_deresiewicz_energy(Q, CM.kappa, CM.mu, CM.normal_force)
    assert quad_area(CM, u0) == pytest.approx(W, rel=1e-9)


def test_beyond_full_sliding_the_loop_is_a_parallelogram_of_height_2_mu_fn():
    d = CM.slip_displacement
    u0 = 10 * d
    u = np.linspace(-u0 + 2 * d, u0 - 2 * d, 11)
    up, down = CM.branches(u, u0)
    np.testing.assert_allclose(up, CM.sliding_force, rtol=1e-15)
    np.testing.assert_allclose(down, -CM.sliding_force, rtol=1e-15)
    # area -> 2μF_N · 2u0 as u0 -> ∞ (rectangle); the deficit is the two rounded corners.
    for k in (10, 1000):
        u0 = k * d
        assert CM.area(u0) / (4 * CM.sliding_force * u0) == pytest.approx(1 - 0.8 / k, rel=1e-12)


def test_plateau_loop_is_linear_below_critical_displacement():
    u = np.linspace(-2e-9, 2e-9, 5)
    up, down = PL.branches(u, 2e-9)
    np.testing.assert_allclose(up, PL.kappa * u, rtol=1e-15)
    np.testing.assert_allclose(down, PL.kappa * u, rtol=1e-15)
    assert abs(PL.area(2e-9)) < 1e-14 * PL.kappa * 4e-18
    # above d_c: the inner loop with shifted virgin curve
    d = 10e-9
    assert PL.virgin(d) == pytest.approx(CM.kappa * 3e-9 + CM.virgin(d - 3e-9), rel=1e-15)


def test_voigt_and_dashpot():
    v = cr.VoigtLoop(4e5, 1e-3, OMEGA)
    assert v.area(2e-9) == pytest.approx(np.pi * OMEGA * 1e-3 * 4e-18)
    dp = cr.with_dashpot(CM, 1e-3, OMEGA)
    assert dp.area(7e-9) - CM.area(7e-9) == pytest.approx(v.area(7e-9), rel=1e-12)


# ------------------------------------------------- κ(F_N) of a sphere on a flat: JKR + Mindlin
# Glass on glass, roughly paper 2's setting: E (Pa), ν, sphere radius R (m).
E_GL, NU_GL, R_GL = 70e9, 0.17, 1.2e-3


def _kappa_by_hand(F, E, gamma, R, nu):
    """κ = 2G*a written out from paper 2 for two bodies of the same material (E, ν)."""
    E_star = 1.0 / (2.0 * (1.0 - nu**2) / E)  # Eq. 10 with E1 = E2 = E, ν1 = ν2 = ν
    G = E / (2.0 * (1.0 + nu))  # Eq. 8
    G_star = 1.0 / (2.0 * (2.0 - nu) / (4.0 * G))  # Eq. 7 with G1 = G2 = G
    b = 6.0 * np.pi * gamma * R
    root = np.sqrt(12.0 * np.pi * gamma * R * F + b**2)
    a = np.cbrt(3.0 * R / (4.0 * E_star) * (F + b + root))  # Eq. 9 (JKR)
    return 2.0 * G_star * a, E_star, G_star


@pytest.mark.parametrize("gamma", [0.05, 0.3])
def test_kappa_jkr_mindlin_by_hand(gamma):
    F = np.array([-0.9, -0.5, 0.0, 0.3, 1.0, 5.0, 40.0]) * 3 * np.pi * gamma * R_GL
    kappa = kappa_jkr_mindlin(F, E_GL, gamma, R_GL, NU_GL)
    ref, E_star, G_star = _kappa_by_hand(F, E_GL, gamma, R_GL, NU_GL)
    np.testing.assert_allclose(kappa, ref, rtol=1e-13)
    # An identity independent of the closed form of Eq. 9: the JKR energy balance
    # F = 4E*a³/(3R) - √(8πwE*a³) with the work of adhesion w = 2γ, for a = κ/(2G*).
    a = kappa / (2.0 * G_star)
    F_back = 4 * E_star * a**3 / (3 * R_GL) - np.sqrt(8 * np.pi * (2 * gamma) * E_star * a**3)
    np.testing.assert_allclose(F_back, F, rtol=1e-9, atol=1e-12 * np.pi * gamma * R_GL)


@pytest.mark.parametrize("gamma", [0.05, 0.3])
def test_kappa_jkr_mindlin_at_pull_off_and_at_zero_load(gamma):
    # From the energy balance F(a) = 4E*a³/(3R) - 4√(πγE*a³) alone (not from Eq. 9):
    # dF/da = 0 gives a_c³ = 9πγR²/(4E*) and F(a_c) = -3πγR (the pull-off force), and F = 0
    # gives a_0³ = 9πγR²/E* = 4a_c³. With γ doubled inside the function κ(-3πγR) would be 1.80
    # times larger; with γ halved, -3πγR would lie below its pull-off force (ValueError).
    _, E_star, G_star = _kappa_by_hand(0.0, E_GL, gamma, R_GL, NU_GL)
    a_c = np.cbrt(9 * np.pi * gamma * R_GL**2 / (4 * E_star))
    pull_off = -3 * np.pi * gamma * R_GL
    assert kappa_jkr_mindlin(pull_off, E_GL, gamma, R_GL, NU_GL) == pytest.approx(
        2 * G_star * a_c, rel=1e-12
    )
    assert kappa_jkr_mindlin(0.0, E_GL, gamma, R_GL, NU_GL) == pytest.approx(
        2 * G_star * np.cbrt(4.0) * a_c, rel=1e-13
    )
    # G* of two equal bodies is 2G/(2 - ν) and E* = E/(2(1 - ν²)): κ(F = 0) in closed form.
    G = E_GL / (2 * (1 + NU_GL))
    a0 = np.cbrt(9 * np.pi * gamma * R_GL**2 * 2 * (1 - NU_GL**2) / E_GL)
    assert kappa_jkr_mindlin(0.0, E_GL, gamma, R_GL, NU_GL) == pytest.approx(
        2 * (2 * G / (2 - NU_GL)) * a0, rel=1e-13
    )
    with pytest.raises(ValueError, match="pull-off"):
        kappa_jkr_mindlin(1.01 * pull_off, E_GL, gamma, R_GL, NU_GL)


@pytest.mark.parametrize(
    "call",
    [
        lambda: cr.CattaneoMindlinLoop(0.0, 0.5, 1e-3),
        lambda: cr.CattaneoMindlinLoop(1e5, -0.5, 1e-3),
        lambda: cr.SavkoorLoop(1e5, 1e6, 0.0),
        lambda: cr.VoigtLoop(1e5, -1.0, OMEGA),
        lambda: CM.branches(2e-9, 1e-9),
        lambda: CM.area(-1e-9),
        lambda: PlateauLoop(cr.VoigtLoop(1e5, 0, OMEGA), 1e-9),
        lambda: cr.mindlin_deresiewicz_energy(2 * CM.sliding_force, CM.kappa, 0.8, 5e-3),
    ],
)
def test_bad_input_raises(call):
    with pytest.raises(ValueError):
        call()


def test_the_series_coefficients_of_one_minus_a_square_root_are_exact():
    """c_k of 1 - √(1 - z) = Σ c_k z^k are -(-1)^k binom(1/2, k) (the binomial series): each
    of the module's 24 (a product recurrence, no scipy.special) is the double nearest the exact
    fraction; their sum at z = 1/2 is 1 - √(1/2) up to the tail, < c_24 z^24 / (1 - z)."""
    from fractions import Fraction

    import contactres.tangential as tangential

    exact, c = [], Fraction(1, 2)
    for k in range(1, 25):
        exact.append(c)
        c *= Fraction(2 * k - 1, 2 * (k + 1))  # binom(1/2, k+1)/binom(1/2, k) = (1/2 - k)/(k+1)
    assert [float(e) for e in exact] == list(tangential._C)
    z = 0.5
    tail = float(exact[-1]) * z**24 / (1 - z)
    assert 0 <= (1 - np.sqrt(1 - z)) - np.sum(tangential._C * z ** np.arange(1, 25)) < tail
