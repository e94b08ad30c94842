"""Carlson's R_F and R_D on arrays, and the Legendre tails the plateau loop takes from them.

Checked against scipy's ``elliprf``/``elliprd`` (an independent implementation of the same
functions) and against adaptive quadrature of the Legendre integrands as written (a different
variable, no symmetric form).
"""

import numpy as np
from scipy import integrate, special

from contactres.analysis._carlson import BLOCK, carlson_rf_rd, legendre_tails


def _arguments(seed, n=2000):
    """(x, y, z) over many orders of magnitude, with x = 0 and nearly equal arguments too."""
    rng = np.random.default_rng(seed)
    x, y, z = (10.0 ** rng.uniform(-12.0, 4.0, n) for _ in range(3))
    x[: n // 10] = 0.0
    near = slice(n // 10, 2 * (n // 10))
    y[near] = x[near] * (1.0 + 1e-3 * rng.standard_normal(n // 10))
    z[near] = x[near] * (1.0 + 1e-3 * rng.standard_normal(n // 10))
    return x, y, z


def test_rf_rd_equal_scipys():
    for seed in (0, 1):
        x, y, z = _arguments(seed)
        rf, rd = carlson_rf_rd(x, y, z)
        np.testing.assert_allclose(rf, special.elliprf(x, y, z), rtol=2e-15, atol=0.0)
        np.testing.assert_allclose(rd, special.elliprd(x, y, z), rtol=4e-15, atol=0.0)


def test_known_values():
    # Carlson (1995), section 3: R_F(1, 2, 0) = 1.3110287771461, R_D(0, 2, 1) = 1.7972103521034;
    # and R_F(x, x, x) = x^(-1/2), R_D(x, x, x) = x^(-3/2) with no step.
    rf, rd = carlson_rf_rd(np.array([1.0, 0.0, 4.0]), np.array([2.0, 2.0, 4.0]), [1.0, 1.0, 4.0])
    assert abs(special.elliprf(1.0, 2.0, 0.0) - 1.3110287771461) < 1e-12
    rf0, _ = carlson_rf_rd(np.array([1.0]), np.array([2.0]), np.array([1e-300]))
    assert abs(rf0[0] - 1.3110287771461) < 1e-12
    assert abs(rd[1] - 1.7972103521034) < 1e-12
    assert rf[2] == 0.5 and rd[2] == 0.125


def test_each_point_its_own_numbers():
    # A point stops after its own steps: over several blocks, and with points that need many
    # steps (arguments 1e-12 apart in scale), each equals its value computed alone.
    x, y, z = _arguments(2, n=2 * BLOCK + 333)
    rf, rd = carlson_rf_rd(x, y, z)
    for i in np.random.default_rng(3).choice(x.size, 40, replace=False):
        a, b = carlson_rf_rd(x[i : i + 1], y[i : i + 1], z[i : i + 1])
        assert a[0] == rf[i] and b[0] == rd[i]


def _tails_by_quadrature(delta, m):
    """The tails as integrals over ψ = π/2 - θ from 0 to δ = π/2 - φ, of (m' + m sin²ψ)^∓½
    (1 - m sin²θ written without cancellation), split where the integrand's peak at ψ = 0
    (width ~√m') ends."""
    m1 = 1.0 - m
    cuts = [p for p in np.sqrt(m1) * np.array([1.0, 10.0, 100.0]) if p < delta]

    def tail(power):
        return integrate.quad(
            lambda t: (m1 + m * np.sin(t) ** 2) ** power,
            0.0,
            delta,
            points=cuts or None,
            epsabs=0.0,
            epsrel=2e-14,
            limit=200,
        )[0]

    return tail(-0.5), tail(0.5)


def test_legendre_tails_equal_quadrature():
    rng = np.random.default_rng(4)
    m = np.concatenate([rng.uniform(0.0, 1.0, 60), 1.0 - 10.0 ** rng.uniform(-8.0, -1.0, 20)])
    delta = rng.uniform(0.0, np.pi / 2, m.size)  # π/2 - φ
    delta[:10] = 10.0 ** rng.uniform(-9.0, -3.0, 10)  # short tails: K - F(φ|m) with φ near π/2
    phi = np.pi / 2 - delta
    kf, ef = legendre_tails(np.cos(delta) ** 2, np.sin(delta) ** 2, m, 1.0 - m)
    ref = np.array([_tails_by_quadrature(d, q) for d, q in zip(delta, m, strict=True)])
    np.testing.assert_allclose(kf, ref[:, 0], rtol=1e-13, atol=0.0)
    np.testing.assert_allclose(ef, ref[:, 1], rtol=1e-13, atol=0.0)
    # And scipy's complete minus incomplete integrals, where that difference keeps its digits.
    wide = delta > 0.5
    k_sp = special.ellipk(m) - special.ellipkinc(phi, m)
    e_sp = special.ellipe(m) - special.ellipeinc(phi, m)
    np.testing.assert_allclose(kf[wide], k_sp[wide], rtol=1e-13)
    np.testing.assert_allclose(ef[wide], e_sp[wide], rtol=1e-13)


def test_outside_the_domain_is_nan_and_the_rest_unchanged():
    """A NaN or infinite argument, a negative one, x = y = 0 or z <= 0 gives NaN (as scipy
    does) and returns: without the check the duplication never converges there (NaN never
    passes its test) and the call did not end. The valid points keep their own numbers."""
    x = np.array([1.0, np.nan, np.inf, 1.0, 0.0, -1.0, 1.0, 2.0])
    y = np.array([2.0, 1.0, 1.0, 1.0, 0.0, 1.0, 1.0, 3.0])
    z = np.array([3.0, 1.0, 1.0, np.inf, 1.0, 1.0, 0.0, 4.0])
    rf, rd = carlson_rf_rd(x, y, z)
    bad = np.array([False, True, True, True, True, True, True, False])
    assert np.isnan(rf[bad]).all() and np.isnan(rd[bad]).all()
    alone_f, alone_d = carlson_rf_rd(x[~bad], y[~bad], z[~bad])
    assert np.array_equal(rf[~bad], alone_f) and np.array_equal(rd[~bad], alone_d)
    np.testing.assert_allclose(rf[~bad], special.elliprf(x[~bad], y[~bad], z[~bad]), rtol=2e-15)
    # Through the plateau loop's closed form: an infinite x gives NaN, as before the tails
    # came from this module (scipy's integrals), not a call that never ends.
    from contactres.analysis._plateau_slopes import plateau_loop_slopes

    with np.errstate(invalid="ignore"):  # inf/inf on the way, as before
        slopes = plateau_loop_slopes(np.array([np.inf]), np.array([1.0]))
    assert all(np.isnan(v).all() for v in slopes)


def _one_point(x, y, z):
    """Carlson's duplication for one point, step by step in Python floats (the module's
    schedule: the first check after MIN_STEPS steps, then every CHECK_EVERY), its series by the
    module's own; R_F and R_D."""
    from math import sqrt

    from contactres.analysis import _carlson

    tail, scale = 0.0, 1.0
    for steps in range(1, _carlson.MAX_STEPS + 1):
        sx, sy, sz = sqrt(x), sqrt(y), sqrt(z)
        lam = sx * sy + (sx + sy) * sz
        tail += scale / ((z + lam) * sz)
        scale *= 0.25
        x, y, z = (x + lam) * 0.25, (y + lam) * 0.25, (z + lam) * 0.25
        if steps < _carlson.MIN_STEPS or (steps - _carlson.MIN_STEPS) % _carlson.CHECK_EVERY:
            continue
        mean = (x + y + z) / 3.0
        if max(x, y, z) - min(x, y, z) < _carlson.DEVIATION * mean:
            f, d = _carlson._series(*(np.array([v]) for v in (x, y, z, mean)))
            return f[0], d[0] * scale + 3.0 * tail
    return np.nan, np.nan


def test_points_stopping_at_different_checks_are_their_own_duplication():
    # Points whose arguments spread from 1 to 1e12 stop at different checks (6 to ~26 steps);
    # those stopping at one check are gathered, and the series runs once on all of them: each
    # point's numbers must be those of its own duplication, bit for bit (review R30a: a wrong
    # 4⁻ⁿ of the points stopping early was caught by no test).
    rng = np.random.default_rng(30)
    n = 400
    x = 10.0 ** rng.uniform(-12, 0, n)
    y = 10.0 ** rng.uniform(-12, 0, n)
    z = 10.0 ** rng.uniform(-1, 0, n)
    x[:20], y[:20], z[:20] = 0.7, 0.7 * (1 + 1e-4), 0.7 * (1 - 1e-4)  # (stop at the first check)
    for part in (slice(None), slice(0, 20)):  # (the first 20 alone: all stop at one check)
        rf, rd = carlson_rf_rd(x[part], y[part], z[part])
        ref = np.array([_one_point(*p) for p in zip(x[part], y[part], z[part], strict=True)])
        np.testing.assert_array_equal(rf, ref[:, 0])
        np.testing.assert_array_equal(rd, ref[:, 1])
