"""The fast paths of hertz, jkr, dmt and jkr_contact_radius give the general path's results.

Python floats take a scalar path and float arrays of forces (with scalar E*, R, γ) an in-place
array path (issue 31). Both must agree with the general numpy path to the last bit, and raise
the same errors. The general path is reached by passing a 0-d array (scalars) or a one-element
array of E* (arrays), which the fast paths do not take.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import contactres as cr
from contactres.errors import ContactresInputError


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


def _same(x, y) -> bool:
    """Equal to the last bit (NaN equal to NaN), and of the same type."""
    if type(x) is not type(y):
        return False
    if isinstance(x, str):
        return x == y
    return bool(np.array_equal(x, y, equal_nan=True))


def _same_contact(c1: cr.Contact, c2: cr.Contact) -> bool:
    d1, d2 = dataclasses.asdict(c1), dataclasses.asdict(c2)
    return all(_same(d1[k], d2[k]) for k in d1)


def _zero_d(*args):
    return [np.asarray(x) for x in args]


def test_scalar_path_equals_the_general_path():
    for E, R, F, gamma in _cases():
        hertz_force = abs(F)
        dmt_force = max(F, -4 * np.pi * gamma * R)
        assert _same_contact(cr.hertz(E, R, hertz_force), cr.hertz(*_zero_d(E, R, hertz_force)))
        assert _same_contact(cr.jkr(E, R, F, gamma), cr.jkr(*_zero_d(E, R, F, gamma)))
        assert _same_contact(
            cr.dmt(E, R, dmt_force, gamma), cr.dmt(*_zero_d(E, R, dmt_force, gamma))
        )
        a_fast = cr.jkr_contact_radius(E, R, F, gamma)
        assert _same(a_fast, cr.jkr_contact_radius(*_zero_d(E, R, F, gamma)))


def test_scalar_path_takes_ints_and_numpy_floats():
    E, R, F, gamma = 62.65e9, 5e-6, 1e-3, 0.05
    general = cr.jkr(*_zero_d(E, R, F, gamma))
    assert _same_contact(cr.jkr(np.float64(E), R, np.float64(F), gamma), general)
    assert _same_contact(cr.hertz(int(7e10), 1, 2), cr.hertz(*_zero_d(7e10, 1.0, 2.0)))


def test_zero_load_hertz_is_a_point():
    c = cr.hertz(62.65e9, 5e-6, 0.0)
    assert (c.contact_radius, c.stiffness, c.mean_pressure, c.peak_pressure) == (0.0,) * 4
    assert _same_contact(c, cr.hertz(*_zero_d(62.65e9, 5e-6, 0.0)))


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
        fast, general = fn(E, R, force), fn(np.array([E]), R, force)
        assert _same_contact(fast, general)
    if gamma == 0.0:
        assert _same_contact(cr.hertz(E, R, F), cr.hertz(np.array([E]), R, F))


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: cr.hertz(-1.0, 5e-6, 1e-3), "E_star must be finite and > 0"),
        (lambda: cr.hertz(1e9, 0.0, 1e-3), "radius must be finite and > 0"),
        (lambda: cr.hertz(1e9, 5e-6, -1e-3), "without adhesion"),
        (lambda: cr.hertz(1e9, 5e-6, np.nan), "force must be finite"),
        (lambda: cr.jkr(1e9, 5e-6, -1e-3, 0.05), "below the pull-off force"),
        (lambda: cr.jkr(1e9, 5e-6, 1e-3, -0.05), "gamma must be finite and >= 0"),
        (lambda: cr.dmt(1e9, 5e-6, -1e-3, 0.05), "DMT pull-off force"),
        (lambda: cr.jkr_contact_radius(1e9, 5e-6, np.inf, 0.05), "force must be finite"),
        (lambda: cr.jkr(1e9, 5e-6, np.array([1e-3, -1e-3]), 0.05), "below the pull-off force"),
        (lambda: cr.dmt(1e9, 5e-6, np.array([1e-3, np.nan]), 0.05), "must be finite"),
    ],
)
def test_fast_paths_raise_the_general_errors(call, message):
    with pytest.raises(ContactresInputError, match=message):
        call()
