"""Tests of the chunked evaluation of many k a values and of the special functions behind it.

Chunking must change nothing but the memory: a call cut into tiny chunks gives the numbers of
one unchunked call (same grids, same Galerkin size), for every model. The spherical Bessel
recurrence is checked against scipy's Bessel function of half-integer order, and the truncated
Struve series of the WA weight against the full 60-term series written out here.
"""

import numpy as np
import pytest
from scipy import special

from contactres import Material
from contactres.dynamic import ALL_MODELS, dcsf, dcsf_models, prepare
from contactres.dynamic._weights import spherical_bessel, wa_line_weight


@pytest.fixture(scope="module")
def cu111_table():
    m = Material.crystal("Cu").rotated((1, 1, 1))
    return m, prepare(m, 0.02, 1e-6)


def test_chunked_call_equals_the_unchunked_one(cu111_table):
    m, table = cu111_table
    # Unsorted, repeated and zero k a, so that no chunk sees the extremes of the whole call.
    ka = np.concatenate([np.linspace(0.0, 1.9, 23), [0.0, 0.4, 0.4], np.linspace(1.95, 0.05, 9)])
    # R0's and SA's negative damping at high k a is not this test's matter (its warning:
    # test_negative_damping_warning.py)
    kw = {"loss": 0.02, "prepared": table, "warn_negative": False}
    whole = dcsf_models(m, ka, ALL_MODELS, chunk=ka.size, **kw)
    for chunk in (1, 3, 7):
        parts = dcsf_models(m, ka, ALL_MODELS, chunk=chunk, **kw)
        for name in ALL_MODELS:
            np.testing.assert_allclose(parts[name], whole[name], rtol=1e-14, atol=0, err_msg=name)


def test_chunked_dcsf_keeps_the_shape_of_ka(cu111_table):
    m, table = cu111_table
    ka = np.linspace(0.1, 1.5, 12).reshape(3, 4)
    a = dcsf(m, ka, model="exact", loss=0.02, prepared=table, chunk=5)
    b = dcsf(m, ka.ravel(), model="exact", loss=0.02, prepared=table, chunk=12)
    assert a.shape == (3, 4)
    np.testing.assert_allclose(a.ravel(), b, rtol=1e-14, atol=0)


@pytest.mark.parametrize("chunk", [0, -2, 1.5, "8"])
def test_bad_chunk_is_refused(cu111_table, chunk):
    m, table = cu111_table
    with pytest.raises(ValueError, match="chunk"):
        dcsf_models(m, [0.5], ("WA",), loss=0.02, prepared=table, chunk=chunk)


@pytest.mark.parametrize(
    "z",
    [
        np.linspace(1e-3, 60.0, 1500),  # real, through many zeros of every order
        np.linspace(0.01, 30.0, 400) * (1 + 0.3j),  # the near-field contour's complex values
        np.array([np.pi, 2 * np.pi, 4.493409457909064, 7.725251836937707, 1e-5]),  # zeros of j0, j1
    ],
)
def test_spherical_bessel_recurrence_matches_scipy_half_integer_bessel(z):
    p_max = 40
    got = spherical_bessel(p_max, z)
    for p in range(p_max + 1):
        # √(π/2z) J_{p+1/2}(z) (AMOS): scipy's spherical_jn itself drifts by ~2e-12 at
        # high order for z > p (its upward recurrence).
        ref = np.sqrt(np.pi / (2 * z)) * special.jv(p + 0.5, z)
        # Relative 1e-12, or 1e-14 of the largest |j_p| of the set near its zeros.
        bound = 1e-12 * np.abs(ref) + 1e-14 * np.max(np.abs(ref))
        assert np.all(np.abs(got[p] - ref) <= bound), p


@pytest.mark.parametrize("p_max", [3, 12, 34, 46])
@pytest.mark.parametrize("imag", [0.0, 0.5, 3.0])
def test_spherical_bessel_short_start_below_the_turning_point_matches_scipy(p_max, imag):
    """Every argument below p_max − 1 (the own nodes and arc of the layered punch, the near
    field of the exact model): the continued fraction then starts a few orders above p_max
    (its truncation bound, not max(p_max, 1.3|z|) + 30); the highest orders, the first its
    truncation would spoil, and arguments up to the bound's edge, against √(π/2z) J_{p+1/2}."""
    x = np.linspace(0.05, 1.0, 97) * (p_max - 1.01)
    z = x + 1j * imag * np.linspace(-1.0, 1.0, x.size) if imag else x
    got = spherical_bessel(p_max, z)
    for p in range(p_max + 1):
        ref = np.sqrt(np.pi / (2 * z)) * special.jv(p + 0.5, z)
        bound = 1e-13 * np.abs(ref) + 1e-14 * np.max(np.abs(ref))
        assert np.all(np.abs(got[p] - ref) <= bound), p


def test_truncated_struve_series_equals_the_full_series():
    """The series is cut where its terms fall below 1e-17 of the largest: the full 60 terms,
    summed here directly, agree to their round-off (~1e-16 x the largest term, ~1e2 at
    |z| = 8), for real and complex arguments below |z| = 8."""
    k = np.arange(60)
    coef = (-1.0) ** k * 0.5 ** (2 * k + 2) / (special.gamma(k + 1.5) * special.gamma(k + 2.5))
    for z in (np.linspace(0.0, 7.99, 300), np.linspace(0.01, 7.5, 200) * np.exp(0.25j)):
        z2 = z * z
        full = 1 - 0.5 * np.pi * z2 * np.sum(coef[:, None] * z2[None, :] ** k[:, None], axis=0)
        for lo in (0, 100):  # the cut depends on the largest |z| of a call
            np.testing.assert_allclose(wa_line_weight(z[lo:]), full[lo:], rtol=0, atol=1e-13)
