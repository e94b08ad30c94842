"""The fast paths of hertz, jkr, dmt and jkr_contact_radius agree with the general path.

Python floats take a scalar path and float arrays of forces (with scalar E*, R, γ) an in-place
array path (issue 31). The array path repeats the general numpy path's operations and agrees
with it to the last bit. The scalar path evaluates the closed forms in Python floats with
``math.cbrt`` (numpy's cube root of an array and the C library's differ by up to a few ulp, and
numpy promises no bit-identity between the two either), so it agrees with the general path and
the array path within a few ulp (:data:`ULPS`) for the well-conditioned quantities; the JKR
quantities that are differences (depth, stiffness, centre pressure: each crosses zero) agree
within a few ulp of their terms (:func:`_jkr_terms`). Both fast paths raise the general path's
errors, with the same messages. The general path is reached by passing 0-d arrays (scalars),
which the fast paths do not take; the array path by a one-element array of forces.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from fractions import Fraction

import numpy as np
import pytest

import contactres as cr
from contactres.errors import ContactresInputError, ContactresWarning
from contactres.normal import _isotropic

EPS = np.finfo(float).eps
# Each path's a is a cube root within ~3 ulp of the true one (the C library's, numpy's) of an
# argument rounded in its own order: the two a's may be ~7 ulp apart, a² twice that. Observed
# over the cases below: <= 2 ulp for a, <= 5.5 ulp for the quantities derived from it.
ULPS = 16


def _cases(n: int = 400, seed: int = 3):
    """Random (E*, R, F, γ) over many decades, a quarter without adhesion, F >= the JKR
    pull-off force (and >= 0 without adhesion)."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        E = float(10 ** rng.uniform(4, 12))
        R = float(10 ** rng.uniform(-9, -2))
        gamma = 0.0 if rng.random() < 0.25 else float(10 ** rng.uniform(-4, 1))
        pull_off = 3 * np.pi * gamma * R
        F = float(-pull_off + (pull_off + 1e-9) * 10 ** rng.uniform(-3, 1))
        yield E, R, F, gamma


def _edge_cases():
    """Zero force, the JKR and DMT pull-off forces, a force just above them, a negative force
    between the two pull-off forces (DMT), and F = 0 at γ = 0 (the zero-area point)."""
    E, R, gamma = 62.65e9, 5e-6, 0.05
    jkr_off, dmt_off = -3 * np.pi * gamma * R, -4 * np.pi * gamma * R
    for F in [0.0, jkr_off, jkr_off * (1 - 1e-9), jkr_off / 2, 1e-12, 1e-3]:
        yield E, R, F, gamma
    yield E, R, 0.0, 0.0
    yield E, R, 1e-3, 0.0
    for F in [dmt_off, dmt_off * (1 - 1e-9), 0.5 * (jkr_off + dmt_off)]:
        yield E, R, F, -1.0  # DMT only (γ = -1 marks it; γ itself is 0.05)


def _close(fast, reference, scale=None) -> bool:
    """``fast`` within :data:`ULPS` ulp of ``reference`` (relative), or of ``scale`` where a
    quantity is a difference of terms of size ``scale``; NaN equal to NaN."""
    fast, reference = float(fast), float(reference)
    if math.isnan(reference):
        return math.isnan(fast)
    size = abs(reference) if scale is None else scale
    return abs(fast - reference) <= ULPS * EPS * size


def _jkr_terms(E, R, gamma, a) -> dict[str, float]:
    """The size of the terms of JKR's depth, stiffness and centre pressure (Johnson, Kendall &
    Roberts; the docstring of :func:`contactres.jkr`), by which their rounding is bounded.

    δ = a²/R − √(4πγa/E*), p(0) = 2E*a/(πR) − √(4γE*/(πa)) and k = (dF/da)/(dδ/da) with
    dF/da = 4E*a²/R − 6√(πγE*a) and dδ/da = 2a/R − √(πγ/(E*a)). Near zero depth, pressure or
    stiffness (pull-off) the terms cancel and a few ulp of the terms is what either path can
    promise; the denominator dδ/da stays >= 4a/(3R) on the branch of force control.
    """
    if a == 0.0:
        return {"depth": 0.0, "peak_pressure": 0.0, "stiffness": 0.0}
    dF_da = 4 * E * a**2 / R + 6 * math.sqrt(math.pi * gamma * E * a)
    dd_da = 2 * a / R - math.sqrt(math.pi * gamma / (E * a))
    return {
        "depth": a**2 / R + math.sqrt(4 * math.pi * gamma * a / E),
        "peak_pressure": 2 * E * a / (math.pi * R) + math.sqrt(4 * gamma * E / (math.pi * a)),
        "stiffness": dF_da / dd_da,
    }


def _agree(fast: cr.Contact, reference: cr.Contact, scales=None) -> bool:
    """The two contacts of the same model agree field by field (:func:`_close`)."""
    scales = scales or {}
    d1, d2 = dataclasses.asdict(fast), dataclasses.asdict(reference)
    if d1.pop("model") != d2.pop("model") or type(fast) is not type(reference):
        return False
    return all(type(d1[k]) is float and _close(d1[k], d2[k], scales.get(k)) for k in d1)


def _zero_d(*args):
    return [np.asarray(x) for x in args]


def _one_element(fn, E, R, F, *rest) -> cr.Contact:
    """``fn`` on the array path for the one force ``F``, as a contact of floats."""
    c = fn(E, R, np.array([F]), *rest)
    fields = {k: float(v[0]) for k, v in dataclasses.asdict(c).items() if k != "model"}
    return dataclasses.replace(c, **fields)


def _identical(c1: cr.Contact, c2: cr.Contact) -> bool:
    """The same to the last bit, field by field (NaN equal to NaN)."""
    return c1.model == c2.model and all(
        np.array_equal(x, y, equal_nan=True)
        for x, y in zip(dataclasses.astuple(c1)[:-1], dataclasses.astuple(c2)[:-1], strict=True)
    )


def _check(fn, args, scales=None):
    """``fn`` on Python floats agrees with the general path and, for an array of forces,
    with the array path."""
    fast = fn(*args)
    assert _agree(fast, fn(*_zero_d(*args)), scales), (fn.__name__, args)
    assert _agree(fast, _one_element(fn, *args), scales), (fn.__name__, args)


def test_scalar_path_agrees_with_the_general_and_the_array_path():
    for E, R, F, gamma in [*_cases(), *_edge_cases()]:
        if gamma < 0:  # a DMT edge case
            _check(cr.dmt, (E, R, F, 0.05))
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ContactresWarning)  # a/R > 0.1: both paths warn
            _check(cr.hertz, (E, R, abs(F)))
        c = cr.jkr(E, R, F, gamma)
        _check(cr.jkr, (E, R, F, gamma), _jkr_terms(E, R, gamma, c.contact_radius))
        _check(cr.dmt, (E, R, max(F, -4 * np.pi * gamma * R), gamma))
        a_fast = cr.jkr_contact_radius(E, R, F, gamma)
        assert type(a_fast) is float
        assert a_fast == c.contact_radius  # the same operations
        assert _close(a_fast, cr.jkr_contact_radius(*_zero_d(E, R, F, gamma)))


def test_scalar_path_takes_ints_and_numpy_floats():
    E, R, F, gamma = 62.65e9, 5e-6, 1e-3, 0.05
    floats = cr.jkr(E, R, F, gamma)
    assert cr.jkr(np.float64(E), R, np.float64(F), gamma) == floats
    assert cr.dmt(np.float64(E), R, F, np.float64(gamma)) == cr.dmt(E, R, F, gamma)
    assert _agree(cr.hertz(int(7e10), 1, 2), cr.hertz(7e10, 1.0, 2.0))


def test_scalar_result_is_a_frozen_contact():
    """The fast construction gives the dataclass's own instance: equal to one built by
    ``Contact(...)``, frozen, with ``replace`` and ``asdict``."""
    c = cr.hertz(62.65e9, 5e-6, 1e-3)
    assert type(c) is cr.Contact
    assert c == cr.Contact(**dataclasses.asdict(c))
    assert vars(c) == vars(cr.Contact(**dataclasses.asdict(c)))
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.depth = 0.0  # type: ignore[misc]
    assert dataclasses.replace(c, model="jkr").model == "jkr"
    assert hash(c) == hash(cr.Contact(**dataclasses.asdict(c)))


def test_zero_load_hertz_is_a_point():
    c = cr.hertz(62.65e9, 5e-6, 0.0)
    assert (c.contact_radius, c.stiffness, c.mean_pressure, c.peak_pressure) == (0.0,) * 4
    assert _agree(c, cr.hertz(*_zero_d(62.65e9, 5e-6, 0.0)))


def _within_ulps_of_the_cube_root(y: float, x: float, ulps: int) -> bool:
    """y within ``ulps`` ulp of the true cube root of x > 0: (y ∓ ulps·ulp(y))³ bracket x,
    in exact rational arithmetic."""
    step = ulps * Fraction(math.ulp(y))
    return (Fraction(y) - step) ** 3 <= Fraction(x) <= (Fraction(y) + step) ** 3


@pytest.mark.parametrize(
    ("cbrt", "ulps"),
    [(_isotropic._cbrt_pow, 1), (_isotropic._cbrt, 4)],
    ids=["pow-and-newton (Python 3.10)", "the fast paths' cube root"],
)
def test_cube_root_is_within_a_few_ulp(cbrt, ulps):
    """The cube root of the fast paths, and the fallback of Python 3.10 (``x ** (1/3)``, off by
    up to ~100 ulp for large ``|ln x|``, and one Newton step), over the whole range of floats,
    subnormals included."""
    rng = np.random.default_rng(31)
    for x in [*(10 ** rng.uniform(-320, 308, 2000)), 1.0, 8.0, 27e-300, 5e-324, 1.7e308]:
        x = float(x)
        y = cbrt(x)
        assert type(y) is float
        assert _within_ulps_of_the_cube_root(y, x, ulps), x
    assert _isotropic._cbrt_pow(0.0) == 0.0
    assert _isotropic._cbrt_pow(-8.0) == -2.0
    # x ** (1/3) alone is not enough: the Newton step is what the fallback needs.
    assert not all(_within_ulps_of_the_cube_root(x ** (1 / 3), x, 1) for x in [1e300, 1e-300])


@pytest.mark.parametrize("gamma", [0.0, 0.05])
def test_array_path_equals_the_general_path(gamma):
    E, R = 62.65e9, 5e-6
    pull_off = 3 * np.pi * gamma * R
    # From the pull-off force (the zero-area point without adhesion) to 1 mN, and a 2-d shape.
    F = np.concatenate([[-pull_off], np.geomspace(1e-12, 1e-3, 199)]).reshape(20, 10)
    for fn, force in [
        (lambda *a: cr.jkr(*a, gamma), F),
        (lambda *a: cr.dmt(*a, gamma), np.maximum(F, -4 * np.pi * gamma * R)),
    ]:
        assert _identical(fn(E, R, force), fn(np.array([E]), R, force))
    if gamma == 0.0:
        assert _identical(cr.hertz(E, R, F), cr.hertz(np.array([E]), R, F))


@pytest.mark.parametrize("gamma", [0.05, 0.0])
def test_array_path_in_chunks_equals_the_general_path(gamma):
    # Forces over three chunks of the array path and a part of one (CHUNK), in a 2-d shape and
    # as a strided view (copied before the chunks), the pull-off force among them: every field
    # is the general path's (whole rows at once) to the last bit.
    E, R = 62.65e9, 5e-6
    n = 3 * _isotropic.CHUNK + 17
    F = np.random.default_rng(2).uniform(-3 * np.pi * gamma * R, 1e-3, 2 * n)
    F[5] = -3 * np.pi * gamma * R
    for force in (F[:n], F.reshape(2, n), F[::2]):
        assert _identical(cr.jkr(E, R, force, gamma), cr.jkr(np.array([E]), R, force, gamma))


_BAD = [
    # (function, arguments as Python floats, which argument carries the array on the
    # general path: one whose value the message does not show)
    (cr.hertz, (-1.0, 5e-6, 1e-3), 1),
    (cr.hertz, (np.inf, 5e-6, 1e-3), 1),
    (cr.hertz, (np.nan, 5e-6, 1e-3), 1),
    (cr.hertz, (1e9, 0.0, 1e-3), 0),
    (cr.hertz, (1e9, -np.inf, 1e-3), 0),
    (cr.hertz, (1e9, 5e-6, -1e-3), 0),
    (cr.hertz, (1e9, 5e-6, np.nan), 0),
    (cr.hertz, (1e9, 5e-6, np.inf), 0),
    (cr.hertz, (-1e9, -5e-6, 1e-3), 2),
    (cr.jkr, (1e9, 5e-6, -1e-3, 0.05), 0),
    (cr.jkr, (1e9, 5e-6, -1e-3, 0.0), 0),
    (cr.jkr, (1e9, 5e-6, 1e-3, -0.05), 0),
    (cr.jkr, (1e9, 5e-6, 1e-3, np.inf), 0),
    (cr.jkr, (1e9, 5e-6, 1e-3, np.nan), 0),
    (cr.jkr, (1e9, 5e-6, -np.inf, 0.05), 0),
    (cr.jkr, (1e9, 5e-6, np.nan, 0.05), 0),
    (cr.jkr, (-1e9, 5e-6, 1e-3, 0.05), 2),
    (cr.jkr, (0.0, 5e-6, 1e-3, 0.05), 2),
    (cr.jkr, (1e9, np.inf, 1e-3, 0.05), 0),
    (cr.dmt, (1e9, 5e-6, -1e-3, 0.05), 0),
    (cr.dmt, (1e9, 5e-6, np.inf, 0.05), 0),
    (cr.dmt, (1e9, 5e-6, 1e-3, -0.05), 0),
    (cr.dmt, (1e9, 5e-6, 1e-3, np.inf), 0),
    (cr.dmt, (np.inf, 5e-6, 1e-3, 0.05), 2),
    (cr.dmt, (-1e9, -5e-6, -1e-3, 0.05), 3),
    (cr.jkr_contact_radius, (1e9, 5e-6, np.inf, 0.05), 0),
    (cr.jkr_contact_radius, (1e9, 5e-6, -1e-3, 0.05), 0),
]


@pytest.mark.parametrize(("fn", "args", "carrier"), _BAD)
def test_fast_paths_raise_the_general_errors(fn, args, carrier):
    """Python floats (the scalar path) raise the error of the general path, message and all:
    the same call with one valid argument as a one-element array (an array never takes the
    scalar path) gives the same message. A message shows the invalid value, so the invalid
    argument stays a Python float; the carrier is one that the message does not show."""
    with pytest.raises(ContactresInputError) as scalar:
        fn(*args)
    general = list(args)
    general[carrier] = np.array([args[carrier]])
    with pytest.raises(ContactresInputError) as array:
        fn(*general)
    assert str(scalar.value) == str(array.value)
    assert str(scalar.value)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: cr.jkr(1e9, 5e-6, np.array([1e-3, -1e-3]), 0.05), "below the pull-off force"),
        (lambda: cr.dmt(1e9, 5e-6, np.array([1e-3, np.nan]), 0.05), "must be finite"),
    ],
)
def test_array_path_raises_the_general_errors(call, message):
    with pytest.raises(ContactresInputError, match=message):
        call()


def _jkr_textbook(E, R, F, gamma):
    """JKR's fields in the textbook forms, four square roots (Johnson, Kendall & Roberts; the
    docstring of :func:`contactres.jkr`), evaluated with numpy from a of paper 2, Eq. 9."""
    b = 6 * np.pi * gamma * R
    disc = np.maximum(12 * np.pi * gamma * R * F + b**2, 0)  # rounding at the pull-off force
    a = np.cbrt(3 * R / (4 * E) * (F + b + np.sqrt(disc)))
    dF_da = 4 * E * a**2 / R - 6 * np.sqrt(np.pi * gamma * E * a)
    dd_da = 2 * a / R - np.sqrt(np.pi * gamma / (E * a))
    return {
        "contact_radius": a,
        "depth": a**2 / R - np.sqrt(4 * np.pi * gamma * a / E),
        "mean_pressure": F / (np.pi * a**2),
        "peak_pressure": 2 * E * a / (np.pi * R) - np.sqrt(4 * gamma * E / (np.pi * a)),
        "stiffness": dF_da / dd_da,
    }


@pytest.mark.parametrize("gamma", [0.0, 0.05, 3.0])
def test_array_path_agrees_with_the_textbook_forms(gamma):
    """The array path (one square root, in place) against the four-square-root forms written
    here, within a few ulp of the terms, from the pull-off force to 1 mN (without adhesion from
    1 pN: at F = 0 the textbook forms are 0/0, the API's zero-area point)."""
    E, R = 62.65e9, 5e-6
    pull_off = 3 * np.pi * gamma * R
    F = np.geomspace(1e-12, 1e-3, 300)
    if gamma:
        F = np.concatenate([[-pull_off, -pull_off / 2, 0.0], F])
    c = cr.jkr(E, R, F, gamma)
    expected = _jkr_textbook(E, R, F, gamma)
    for i, force in enumerate(F):
        a = float(c.contact_radius[i])
        scales = _jkr_terms(E, R, gamma, a)
        for name, values in expected.items():
            got = float(getattr(c, name)[i])
            assert _close(got, values[i], scales.get(name)), (name, force, got, values[i])


def test_no_forces_give_empty_fields_of_their_shape():
    # An empty array of forces is a valid array (numpy's elementwise rule): every field empty,
    # of the forces' shape, for each model (hertz and jkr raised numpy's reduction error).
    for shape in ((0,), (0, 3)):
        F = np.zeros(shape)
        for c in (
            cr.hertz(70e9, 1e-6, F),
            cr.jkr(70e9, 1e-6, F, 0.05),
            cr.dmt(70e9, 1e-6, F, 0.05),
        ):
            for field in (c.contact_radius, c.depth, c.mean_pressure, c.stiffness, c.force):
                assert np.shape(field) == shape
