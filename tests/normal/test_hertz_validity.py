"""The Python API guards Hertz's small-contact limit as the command line does (issue 30,
second review M4): a/R > 0.1 warns naming a/R, a/R > 0.5 gives NaN and the warning.

The reference a/R comes from Hertz's closed form, a³ = 3FR/(4E*) (Johnson 1985, Eq. 4.22),
computed here, not from the functions under test.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from contactres import LayeredMaterial, Material, effective_modulus, hertz, sphere_contact
from contactres.errors import ContactresWarning

E_STAR = effective_modulus(70e9, 0.22)  # glass on glass, Pa


def _ratio(R, F, E=E_STAR):
    return (3 * F * R / (4 * E)) ** (1 / 3) / R


def test_a_small_contact_is_returned_without_a_word():
    assert _ratio(5e-6, 1e-3) < 0.1
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = hertz(E_STAR, 5e-6, 1e-3)
        sphere_contact(Material.isotropic(70e9, 0.22), 5e-6, 1e-3)
    assert c.contact_radius == pytest.approx(_ratio(5e-6, 1e-3) * 5e-6, rel=1e-12)


def test_an_approximate_contact_warns_and_keeps_its_values():
    R, F = 1e-6, 1e-3
    ratio = _ratio(R, F)
    assert 0.1 < ratio <= 0.5
    with pytest.warns(ContactresWarning, match=f"a/R = {ratio:.3g} > 0.1: Hertz approximate"):
        c = hertz(E_STAR, R, F)
    assert c.contact_radius == pytest.approx(ratio * R, rel=1e-12)


@pytest.mark.parametrize("vector", [False, True])
def test_a_contact_beyond_hertz_is_nan_with_a_warning(vector):
    """Issue 30's case: R = 20 nm, F = 1 N (a/R = 24 on Cu, 37 on glass)."""
    R, F = 2e-8, 1.0
    ratio = _ratio(R, F)
    forces = np.array([1e-12, F]) if vector else F
    with pytest.warns(ContactresWarning, match=rf"a/R = {ratio:.3g} > 0.5.*: beyond Hertz"):
        c = hertz(E_STAR, R, forces)
    values = np.atleast_1d(c.contact_radius)
    assert np.isnan(values[-1]) and np.isnan(np.atleast_1d(c.peak_pressure)[-1])
    assert np.isnan(np.atleast_1d(c.stiffness)[-1]) and np.atleast_1d(c.force)[-1] == F
    if vector:  # the small contact of the pair keeps its value
        assert values[0] == pytest.approx(_ratio(R, 1e-12) * R, rel=1e-12)


def test_sphere_contact_on_a_crystal_and_a_stack_is_guarded_too():
    cu = Material.crystal("Cu")
    with pytest.warns(ContactresWarning, match=r"sphere_contact: a/R = \S+ > 0.5"):
        c = sphere_contact(cu, radius=2e-8, force=1.0)
    assert np.isnan(c.contact_radius) and np.isnan(c.peak_pressure) and c.force == 1.0
    assert np.isnan(c.semi_major) and np.isnan(c.stiffness)
    glass = Material.isotropic(70e9, 0.22)
    film = Material.isotropic(5e9, 0.35)
    with pytest.warns(ContactresWarning, match="Hertz approximate"):
        sphere_contact(LayeredMaterial(glass, [(film, 1e-6)]), 10e-6, 5e-2)


def test_check_validity_false_leaves_the_check_out():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = hertz(E_STAR, 2e-8, 1.0, check_validity=False)
        d = sphere_contact(Material.crystal("Cu"), 2e-8, 1.0, check_validity=False)
    assert c.contact_radius == pytest.approx(_ratio(2e-8, 1.0) * 2e-8, rel=1e-12)
    assert np.isfinite(d.contact_radius)
