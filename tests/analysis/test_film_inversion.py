"""Tests of contactres.analysis._film_inversion: k* -> the modulus of a film on a substrate.

The forward contacts are built here, independently of the inversion's scaled film: each film is
a fresh ``Material.isotropic(E, ν)`` in a ``LayeredMaterial`` passed to ``sphere_contact``; the
inversion starts from a film of the same ν at another modulus.
"""

import numpy as np
import pytest

from contactres import LayeredMaterial, Material, sphere_contact
from contactres.analysis import film_modulus_from_contact_stiffness
from contactres.errors import ContactresInputError

SILICA = Material.isotropic(72e9, 0.17, name="silica")
NU = 0.35
GUESS = Material.isotropic(3e9, NU, name="film")  # the film's material: ν kept, E unknown


def _film(M):
    """An isotropic film of indentation modulus M (Pa), Poisson's ratio NU."""
    return Material.isotropic(M * (1 - NU**2), NU, name="film")


def _k(M, h, R, P, tip=None):
    stack = LayeredMaterial(SILICA, [(_film(M), h)])
    # The forward model as the inversion evaluates it: without the API's a/R check (a
    # compliant film's contact reaches a/R ~ 1 here; issue 30 made the API give NaN there).
    c = sphere_contact(stack, R, P, indenter=tip, check_validity=False)
    return np.asarray(c.stiffness, dtype=float)


def _numerics(k, h, R, P, **options):
    """The inversion of k* (N/m) under a film of thickness ``h`` (m) on SILICA, from GUESS, tip
    radius R (m) and load P (N), without Hertz's a/R check: these tests check the inversion's
    numerics at the forward model's contacts, up to a/R ~ 1 (:func:`_k`); the a/R limit has
    its own test (test_hertz_limit_at_the_solution_flags_and_empties)."""
    return film_modulus_from_contact_stiffness(
        k,
        substrate=SILICA,
        film=GUESS,
        thickness=h,
        tip_radius=R,
        load=P,
        check_validity=False,
        **options,
    )


def test_round_trip_through_the_forward_layered_contact():
    """Film moduli 0.5-25 GPa under 20 nm, two tips and loads in one map: M_film back to 1e-6."""
    M = np.array([0.5e9, 2e9, 6e9, 25e9])
    R = np.array([20e-9, 50e-9])[:, None]
    P = np.array([1e-6, 5e-6])[:, None]
    k = np.stack([_k(m, 20e-9, R[i, 0], P[i, 0]) for i in range(2) for m in M]).reshape(2, 4)
    r = _numerics(k, 20e-9, R, P)
    np.testing.assert_allclose(r.M_film, np.broadcast_to(M, (2, 4)), rtol=1e-6)
    assert set(r.verdict.ravel()) == {"film"}
    assert np.all((r.film_weight > 0.1) & (r.film_weight < 1.0))
    assert r.interpolation_error < 1e-9
    # The contact radius at the solution is the forward contact's.
    stack = LayeredMaterial(SILICA, [(_film(6e9), 20e-9)])
    a = sphere_contact(stack, 50e-9, 5e-6, check_validity=False)  # as _k
    assert r.contact_radius[1, 2] == pytest.approx(float(a.contact_radius), rel=1e-6)


def test_round_trip_with_an_elastic_tip():
    tip_M = 165e9
    tip = Material.isotropic(tip_M, 0.0, name="tip")  # M = E for ν = 0
    k = _k(8e9, 30e-9, 30e-9, 2e-6, tip=tip)
    r = _numerics(k, 30e-9, 30e-9, 2e-6, tip_modulus=tip_M)
    assert float(r.M_film) == pytest.approx(8e9, rel=1e-6)


def test_weight_is_the_films_share_of_the_sensitivity():
    """w = (3/2) ∂ln k*/∂ln M_f (rigid tip), checked by a central difference of the forward."""
    M, h, R, P = 5e9, 20e-9, 20e-9, 1e-6
    r = _numerics(_k(M, h, R, P), h, R, P)
    step = 1e-3
    slope = (np.log(_k(M * (1 + step), h, R, P)) - np.log(_k(M / (1 + step), h, R, P))) / (
        2 * np.log1p(step)
    )
    assert float(r.film_weight) == pytest.approx(1.5 * slope, rel=1e-5)


def test_thick_film_is_the_homogeneous_hertz_inversion():
    """A film 10⁴ times the contact radius: the verdict too-thick, M_film = Hertz on the film
    alone (E* = √(k*³/(6RP)), Johnson Eqs. 4.22-4.23) and = the film's modulus."""
    M, R, P = 4e9, 20e-9, 1e-6
    k = _k(M, 1e-4, R, P)
    r = _numerics(k, 1e-4, R, P)
    assert r.verdict[()] == "too-thick"
    hertz = np.sqrt(k**3 / (6 * R * P))
    # The substrate still shows at O(a/h) (a/h = 1.6e-4): M_film is the film's to 1e-6, Hertz's
    # to 1e-3.
    assert float(r.M_film) == pytest.approx(M, rel=1e-6)
    assert float(r.M_film) == pytest.approx(hertz, rel=1e-3)
    assert float(r.M_homogeneous) == pytest.approx(hertz, rel=1e-12)
    assert float(r.film_weight) == pytest.approx(1.0, abs=1e-3)


def test_thin_film_is_flagged_and_not_given():
    """2 nm of a 60 GPa film under a 14 nm contact: the substrate takes the contact (w ~ 0.05),
    no film modulus. (A soft film shows at much smaller h/a: its weight grows with
    M_substrate/M_f.)"""
    M, h, R, P = 60e9, 2e-9, 50e-9, 5e-6
    r = _numerics(_k(M, h, R, P), h, R, P, film_range=(20e9, 100e9))
    assert r.verdict[()] == "too-thin"
    assert float(r.film_weight) < 0.1
    assert np.isnan(r.M_film)


def test_a_range_beyond_the_layered_solver_is_one_line():
    """A film 2000 times thinner than the contact at the range's soft end: the solver's limit,
    said with the film modulus where it was met."""
    with pytest.raises(ContactresInputError, match=r"film modulus .* of the search range") as err:
        film_modulus_from_contact_stiffness(
            1e4, substrate=SILICA, film=GUESS, thickness=0.05e-9, tip_radius=200e-9, load=20e-6
        )
    assert "\n" not in str(err.value)


def test_outside_the_search_range_is_flagged():
    M, h, R, P = 4e9, 20e-9, 20e-9, 1e-6
    k = np.array([_k(0.5e9, h, R, P), _k(M, h, R, P), _k(60e9, h, R, P)])
    r = _numerics(k, h, R, P, film_range=(1e9, 30e9))
    assert list(r.verdict) == ["below-range", "film", "above-range"]
    assert np.isnan(r.M_film[[0, 2]]).all()
    assert r.M_film[1] == pytest.approx(M, rel=1e-6)
    assert r.film_range == (1e9, 30e9)


@pytest.mark.parametrize(
    "change, words",
    [
        (dict(thickness=-1e-9), "thickness"),
        (dict(k_star=-1.0), "k_star"),
        (dict(film_range=(3e9, 1e9)), "film_range"),
        (dict(min_film_weight=1.5), "min_film_weight"),
        (dict(tip_modulus=0.0), "tip_modulus"),
        (dict(film=Material.isotropic(3e9, NU).with_loss(0.1)), "undamped"),
    ],
)
def test_bad_input_is_one_line(change, words):
    kwargs = dict(
        k_star=100.0, substrate=SILICA, film=GUESS, thickness=20e-9, tip_radius=20e-9, load=1e-6
    )
    kwargs.update(change)
    with pytest.raises(ContactresInputError, match=words) as err:
        film_modulus_from_contact_stiffness(**kwargs)
    assert "\n" not in str(err.value)


def test_a_map_costs_one_curve_per_distinct_contact(monkeypatch):
    """2000 pixels with one tip and load: ``nodes`` layered contacts in all (no loop over the
    pixels), each pixel's M_film back to 1e-6."""
    import contactres.normal as normal

    calls = []
    forward = normal.sphere_contact

    def counted(*args, **kwargs):
        calls.append(np.size(args[1]))
        return forward(*args, **kwargs)

    h, R, P = 20e-9, 20e-9, 1e-6
    M = np.array([1e9, 4e9, 12e9])
    k = np.stack([_k(m, h, R, P) for m in M])
    pixels = np.resize(k, 2000)
    monkeypatch.setattr(normal, "sphere_contact", counted)
    r = _numerics(pixels, h, R, P, nodes=17)
    assert calls == [1] * 17
    np.testing.assert_allclose(r.M_film, np.resize(M, 2000), rtol=1e-6)


def test_hertz_limit_at_the_solution_flags_and_empties():
    """The inversion checks a/R at its own solution, as sphere_contact does (a/R = a from the
    forward layered contact here, independent of the inversion): beyond 0.5 no modulus
    (verdict beyond-hertz, NaN) after a warning naming a/R; between 0.1 and 0.5 the modulus
    with a warning; below 0.1 no warning; check_validity=False gives every modulus."""
    import warnings

    from contactres.errors import ContactresWarning

    h, M = 20e-9, 6e9
    cases = [(20e-9, 1e-6), (50e-9, 1e-6), (100e-9, 50e-9)]  # wide, approximate, small
    stack = LayeredMaterial(SILICA, [(_film(M), h)])
    ratio = [
        float(sphere_contact(stack, R, P, check_validity=False).contact_radius) / R
        for R, P in cases
    ]
    assert ratio[0] > 0.5 and 0.1 < ratio[1] < 0.5 and ratio[2] < 0.1
    R = np.array([c[0] for c in cases])
    P = np.array([c[1] for c in cases])
    k = np.array([_k(M, h, r, p) for r, p in cases])
    kwargs = dict(substrate=SILICA, film=GUESS, thickness=h, tip_radius=R, load=P)
    with pytest.warns(ContactresWarning, match=r"a/R = 0\.6\d* > 0\.5 \(1 of 3 pixels\): beyond"):
        r = film_modulus_from_contact_stiffness(k, **kwargs)
    assert list(r.verdict) == ["beyond-hertz", "film", "film"]
    assert np.isnan(r.M_film[0])
    np.testing.assert_allclose(r.M_film[1:], M, rtol=1e-6)
    np.testing.assert_allclose(r.contact_radius / R, ratio, rtol=1e-5)
    with pytest.warns(
        ContactresWarning, match=r"a/R = 0\.\d+ > 0\.1 \(1 of 2 pixels\): Hertz approx"
    ):
        film_modulus_from_contact_stiffness(k[1:], **{**kwargs, "tip_radius": R[1:], "load": P[1:]})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        small = film_modulus_from_contact_stiffness(
            k[2], **{**kwargs, "tip_radius": R[2], "load": P[2]}
        )
        every = film_modulus_from_contact_stiffness(k, **kwargs, check_validity=False)
    assert small.verdict[()] == "film"
    np.testing.assert_allclose(every.M_film, M, rtol=1e-6)
