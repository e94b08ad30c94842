"""Isotropic normal contact of a sphere on a flat: Hertz, JKR, DMT and effective moduli.

All functions take SI quantities (Pa, m, N, J/m^2) and broadcast over numpy arrays.

Adhesion follows paper 2 (Eq. 9): ``gamma`` is the paper's "energy of adhesion" γ, and the work of
adhesion (Johnson's w, Dupré) is w = 2γ. With that convention the JKR pull-off force is
F = -3πγR and the DMT pull-off force is F = -4πγR.

Two effective moduli are used and they are easy to mix up:

* :func:`effective_modulus` is the usual E* of Hertz theory, 1/E* = Σ (1 - ν_i²)/E_i
  (paper 2, Eq. 10);
* :func:`effective_shear_modulus` is the G* of paper 2, Eq. 7, G* = [Σ (2 - ν_i)/(4 G_i)]⁻¹,
  which is **four times** the G* of Johnson's *Contact Mechanics* (G*_J = [Σ (2 - ν_i)/G_i]⁻¹).
  The tangential (Mindlin) stiffness is κ = 2 G* a with the paper's G* (= 8 G*_J a).

Paper 2: J. Vlachová, R. König, D. Johannsmann, "Stiffness of sphere-plate contacts at MHz
frequencies: dependence on normal load, oscillation amplitude, and ambient medium", Beilstein
J. Nanotechnol. 6, 845-856 (2015), doi:10.3762/bjnano.6.87.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._summary import Summarised, values
from ..errors import ContactresInputError
from ..units import HERTZ_APPROXIMATE_RATIO
from ..validation import nonnegative as _nonnegative
from ..validation import positive as _positive
from ._validity import checked

__all__ = [
    "Contact",
    "dmt",
    "effective_modulus",
    "effective_shear_modulus",
    "hertz",
    "jkr",
    "jkr_contact_radius",
    "jkr_from_depth",
    "jkr_pull_off_force",
    "shear_modulus",
    "tabor_parameter",
    "which_adhesion_model",
]


# repr=False: the summary (Summarised, _facts) replaces numpy reprs of array fields.
@dataclass(frozen=True, repr=False)
class Contact(Summarised):
    """State of a normal sphere-on-flat contact (SI units; fields may be numpy arrays).

    Attributes
    ----------
    contact_radius : contact radius a, m
    depth : penetration (approach of distant points) δ, m
    mean_pressure : F/(π a²), Pa (the applied force over the contact area)
    peak_pressure : pressure at the centre of the contact, Pa (the maximum for Hertz and DMT;
        JKR has an integrable tensile singularity at the edge, so the centre value is given)
    stiffness : normal contact stiffness dF/dδ, N/m
    force : applied normal force F, N (negative = tensile)
    model : "hertz", "jkr" or "dmt"
    """

    contact_radius: np.ndarray | float
    depth: np.ndarray | float
    mean_pressure: np.ndarray | float
    peak_pressure: np.ndarray | float
    stiffness: np.ndarray | float
    force: np.ndarray | float
    model: str = "hertz"

    def _facts(self) -> list[tuple[str, str]]:
        return contact_facts(self)


def contact_facts(c) -> list[tuple[str, str]]:
    """The summary of a contact (this module's, the anisotropic and the layered one): the
    model, F (µN), a and δ (nm), p0 (GPa) and k (N/m), each a value or a range."""
    return [
        ("", c.model),
        ("F", values(c.force, "µN", 1e-6)),
        ("a", values(c.contact_radius, "nm", 1e-9)),
        ("δ", values(c.depth, "nm", 1e-9)),
        ("p0", values(c.peak_pressure, "GPa", 1e9)),
        ("k", values(c.stiffness, "N/m")),
    ]


# The fast paths below (issue 31: a scalar call cost ~100 µs of numpy overhead, 100x the peers';
# an array call made a dozen temporaries). Scalars: plain Python floats (ints and numpy floats are
# converted first), in the closed forms of the functions' docstrings, each input checked by a
# float comparison; their results agree with the general path's to a few ulp (to a few ulp of
# the larger term where a JKR quantity is a difference), not to the last bit: the cube root is
# math.cbrt, not numpy's (tests/normal/test_isotropic_fast.py). Arrays: a float array of forces
# with scalar E*, R and γ, in place in one block; its fields are the general path's to the last
# bit (both call _jkr_fields, in the scalar path's forms). Anything else, and any input that
# fails a check, takes the general path, which raises the usual error.
_PLAIN = frozenset((float, int, np.float64))
_INF = math.inf
_PI = math.pi
_sqrt = math.sqrt


def _cbrt_pow(x: float) -> float:
    """Cube root of a float for Python 3.10, which has no :func:`math.cbrt`.

    ``x ** (1/3)`` is off by up to a few ulp (1/3 is not a float: the error grows with
    ``|ln x|``); one Newton step y − (y − x/y²)/3 brings it within about one ulp of the true
    root (tests/normal/test_isotropic_fast.py checks both against a 40-digit reference). The
    fast paths call it with 0 < x < inf only; other values take numpy's cube root.
    """
    if not 0.0 < x < _INF:
        return float(np.cbrt(x))
    y = x ** (1.0 / 3.0)
    return y - (y - x / (y * y)) / 3.0


# math.cbrt (Python >= 3.11) costs a third of numpy's cube root of a Python float.
_cbrt = getattr(math, "cbrt", _cbrt_pow)


class _Draft(Summarised):
    """A mutable twin of :class:`Contact` (the same instance layout), for :func:`_new_contact`
    (a draft is typed ``Any`` there: its fields are Contact's)."""


def _new_contact(a, depth, mean_p, centre, stiffness, force, model) -> Contact:
    """A :class:`Contact`, built without the frozen dataclass's ``__init__``.

    That ``__init__`` sets the seven fields one by one through ``object.__setattr__`` and costs
    more than the arithmetic of a scalar contact. Here the fields are set on a :class:`_Draft`
    (plain attribute stores, the interpreter's fastest) whose class is then made
    :class:`Contact` (allowed between classes of the same layout): the same instance as
    ``Contact(...)`` builds (equal, frozen, same fields, same ``__dict__``), in a third of the
    time. :func:`hertz` repeats these lines in place: a call is a fifth of its time.
    """
    c: Any = _Draft()
    c.contact_radius = a
    c.depth = depth
    c.mean_pressure = mean_p
    c.peak_pressure = centre
    c.stiffness = stiffness
    c.force = force
    c.model = model
    c.__class__ = Contact
    return c


def _floats(*xs) -> tuple[float, ...] | None:
    """``xs`` as Python floats when each is an int, a float or a numpy float (and one is not a
    Python float), else None."""
    if all(type(x) is float for x in xs) or not all(type(x) in _PLAIN for x in xs):
        return None
    try:
        return tuple(float(x) for x in xs)
    except OverflowError:  # an int beyond the floats: the general path says so
        return None


def _zero_where_no_area(a: np.ndarray, *fields: np.ndarray) -> None:
    """Set ``fields`` to 0 where a > 0 fails (the general path's ``np.where(a > 0, x, 0)``)."""
    if not a.min(initial=np.inf) > 0.0:  # no forces (an empty array): nothing to zero
        none = ~(a > 0.0)
        for x in fields:
            x[none] = 0.0


def _fields(F: np.ndarray) -> np.ndarray:
    """One block for the five computed fields of a :class:`Contact` of forces ``F``.

    One allocation instead of five: a block of >= 4 MiB is mapped (and madvised for huge pages)
    by numpy and reused by malloc from call to call, where five arrays of 0.8 MB (10^5 loads) are
    mapped and faulted in page by page on every call: 1.8 ms against 0.1 ms on the reference
    machine. Each field is a contiguous row of the block.
    """
    return np.empty((5, *F.shape))


#: Forces per chunk of the array path: its six rows of 256 KiB (five fields and the forces) stay
#: in a core's L2 cache (2 MiB on the reference machine) through the ~25 elementwise passes,
#: where the rows of 10^5 loads (4.8 MB) stream from L3 on every pass: 1.66 -> 1.40 ms a call
#: (issue 31: jkr on 10^5 loads was 1.16x the peer's). Smaller chunks pay more of the ~35 µs
#: of Python a chunk costs.
CHUNK = 32768


def _array_jkr(E_star: float, R: float, F: np.ndarray, gamma: float, model) -> Contact | None:
    """:func:`jkr` for an array of forces F (float, ndim >= 1) and float E*, R, γ (checked), or
    None when F fails a check. The contact radius by the general path's operations (the same
    bits as :func:`jkr_contact_radius`), in place; the other fields by :func:`_jkr_fields`;
    both chunk by chunk (:data:`CHUNK`), elementwise: the same bits as on whole rows."""
    lo, hi = F.min(), F.max()
    if not (-_INF < lo and hi < _INF) or (gamma == 0.0 and lo < 0.0):
        return None
    b = 6.0 * _PI * gamma * R
    clip = False
    if gamma != 0.0:
        # The least discriminant 12πγR F + b² is the least force's: both roundings are
        # monotonic in F (12πγR > 0), so it is checked before any row is computed.
        lowest = (12.0 * _PI * gamma * R) * float(lo) + b**2
        if lowest < -1e-12 * max(b**2, 1e-300):
            return None
        clip = lowest < 0.0  # rounding at the pull-off force (a no-op elsewhere: skipped)
    block = _fields(F)
    rows, forces = block.reshape(5, -1), F.reshape(-1)
    for start in range(0, forces.size, CHUNK):
        a, depth, mean_p, centre, stiffness = rows[:, start : start + CHUNK]
        f = forces[start : start + CHUNK]
        np.add(f, b, out=a)
        if gamma != 0.0:
            disc = np.multiply(12.0 * _PI * gamma * R, f, out=depth)  # depth's row as scratch
            disc += b**2
            if clip:
                np.maximum(disc, 0.0, out=disc)
            a += np.sqrt(disc, out=disc)
        else:
            a += 0.0  # sqrt(disc) = 0 (kept: it turns -0.0 into 0.0, as the general path does)
        a *= 3.0 * R / (4.0 * E_star)
        np.cbrt(a, out=a)
        _jkr_fields(E_star, R, gamma, a, f, (depth, mean_p, centre, stiffness), gamma != 0.0)
    a, depth, mean_p, centre, stiffness = block
    return _new_contact(a, depth, mean_p, centre, stiffness, np.broadcast_to(F, a.shape), model)


def _jkr_fields(E, R, gamma, a: np.ndarray, F, rows, adhesive: bool) -> None:
    """Fill ``rows`` = (depth, mean pressure, centre pressure, stiffness) of JKR contacts of
    radius ``a`` under forces ``F`` (E*, R, γ floats or arrays of a's shape), in place.

    The closed forms of :func:`jkr` with one square root, q = √(πγa/E*), as its scalar path
    writes them: δ = u − 2q with u = a²/R, k = dF/dδ = 2E*a (2u − 3q)/(2u − q) (the ratio of
    dF/da = 2E*(2u − 3q) and dδ/da = (2u − q)/a), p(0) = (2E*/π)(a/R − q/a) and F/(πa²); the
    four square roots of the textbook forms are q times E*, 1/a and 2. Without adhesion (q = 0)
    the terms in q are left out. Where a = 0 (no area) the pressures and the stiffness are 0.
    The array path and the general path both call it: their fields agree to the last bit.
    """
    depth, mean_p, centre, stiffness = rows
    inv_r = 1.0 / R
    # In place where it can be (x op= y reads two rows and writes one it has just read: a
    # third less memory traffic than np.op(y, z, out=x), which bounds these loops).
    with np.errstate(divide="ignore", invalid="ignore"):  # a = 0: zeroed below
        np.square(a, out=depth)
        depth *= inv_r  # u = a²/R
        if adhesive:
            q = np.multiply(a, _PI * gamma / E, out=mean_p)  # mean_p's row holds q a while
            np.sqrt(q, out=q)
            w = np.multiply(depth, 2.0, out=centre)  # centre's row holds 2u − q a while
            w -= q
            np.multiply(q, -2.0, out=stiffness)
            depth += stiffness  # u − 2q
            stiffness += w  # 2u − 3q
            stiffness /= w
            stiffness *= a
            stiffness *= 2.0 * E
            q /= a
            np.multiply(a, inv_r, out=centre)
            centre -= q  # a/R − q/a
            centre *= 2.0 * E / _PI
        else:
            np.multiply(a, 2.0 * E, out=stiffness)
            np.multiply(stiffness, inv_r / _PI, out=centre)
        np.square(a, out=mean_p)
        mean_p *= _PI
        np.divide(F, mean_p, out=mean_p)
    _zero_where_no_area(a, stiffness, mean_p, centre)


def _array_dmt(E_star: float, R: float, F: np.ndarray, gamma: float) -> Contact | None:
    """:func:`dmt` for an array of forces (as :func:`_array_jkr`), or None."""
    load = F + 4.0 * _PI * gamma * R
    if not (-_INF < F.min() and F.max() < _INF and load.min() >= 0.0):
        return None
    a, depth, mean_p, centre, stiffness = _fields(F)
    np.multiply(load, 3.0 * R, out=a)
    a /= 4.0 * E_star
    np.cbrt(a, out=a)
    a2 = np.square(a, out=depth)  # depth = a²/R below
    with np.errstate(divide="ignore", invalid="ignore"):
        np.multiply(_PI, a2, out=mean_p)
        np.divide(F, mean_p, out=mean_p)
        np.multiply(2.0 * _PI, a2, out=centre)
        load *= 3.0
        np.divide(load, centre, out=centre)
    _zero_where_no_area(a, mean_p, centre)
    depth /= R
    np.multiply(2.0 * E_star, a, out=stiffness)
    return _new_contact(a, depth, mean_p, centre, stiffness, np.broadcast_to(F, a.shape), "dmt")


def _poisson(name: str, value) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(v)) or np.any(v <= -1) or np.any(v >= 0.5):
        raise ContactresInputError(f"{name} must lie in (-1, 0.5), got {value!r}")
    return v


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def shear_modulus(E, nu):
    """Shear modulus G = E / (2(1 + ν)) of an isotropic solid (paper 2, Eq. 8), Pa.

    Examples
    --------
    >>> from contactres import shear_modulus
    >>> print(f"{float(shear_modulus(70e9, 0.22)) / 1e9:.3f} GPa")
    28.689 GPa
    """
    return _out(_positive("E", E) / (2.0 * (1.0 + _poisson("nu", nu))))


def effective_modulus(E1, nu1, E2=None, nu2=None):
    """Hertz effective modulus E* (paper 2, Eq. 10), Pa.

    1/E* = (1 - ν₁²)/E₁ + (1 - ν₂²)/E₂. Without ``E2``/``nu2`` the second body is the same
    material as the first (the paper's assumption); ``E2=np.inf`` makes it rigid.

    Examples
    --------
    Glass (E = 70 GPa, ν = 0.22) on sapphire-like alumina (E = 400 GPa, ν = 0.23):

    >>> from contactres import effective_modulus
    >>> print(f"{float(effective_modulus(70e9, 0.22, 400e9, 0.23)) / 1e9:.2f} GPa")
    62.65 GPa

    On a rigid flat, E* is the plane-strain modulus E/(1 − ν²) of the sphere:

    >>> import numpy as np
    >>> bool(np.isclose(effective_modulus(70e9, 0.22, np.inf), 70e9 / (1 - 0.22**2), atol=0))
    True
    """
    E1, nu1 = _positive("E1", E1), _poisson("nu1", nu1)
    E2 = E1 if E2 is None else np.asarray(E2, dtype=float)
    if not np.all(E2 > 0):
        raise ContactresInputError(f"E2 must be > 0 (np.inf for a rigid body), got {E2!r}")
    nu2 = nu1 if nu2 is None else _poisson("nu2", nu2)
    return _out(1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2))


def effective_shear_modulus(G1, nu1, G2=None, nu2=None):
    """Tangential effective modulus G* of paper 2, Eq. 7, Pa (= 4 x Johnson's G*).

    G* = [(2 - ν₁)/(4G₁) + (2 - ν₂)/(4G₂)]⁻¹, so that the Mindlin stiffness is κ = 2 G* a
    (:func:`contactres.mindlin_stiffness`). Johnson's book defines G*_J = [Σ(2 - ν_i)/G_i]⁻¹ with
    κ = 8 G*_J a: the same stiffness. Without ``G2``/``nu2`` both bodies are the same material;
    ``G2=np.inf`` makes the second rigid.

    Examples
    --------
    With the paper's G*, κ = 2 G* a is Mindlin's 8Ga/(2 − ν) for a rigid partner:

    >>> import numpy as np
    >>> from contactres import effective_shear_modulus, mindlin_stiffness, shear_modulus
    >>> G = shear_modulus(70e9, 0.22)
    >>> G_star = effective_shear_modulus(G, 0.22, np.inf)
    >>> bool(np.isclose(mindlin_stiffness(1e-6, G_star), 8 * G * 1e-6 / (2 - 0.22), atol=0))
    True
    """
    G1, nu1 = _positive("G1", G1), _poisson("nu1", nu1)
    G2 = G1 if G2 is None else np.asarray(G2, dtype=float)
    if not np.all(G2 > 0):
        raise ContactresInputError(f"G2 must be > 0, got {G2!r}")
    nu2 = nu1 if nu2 is None else _poisson("nu2", nu2)
    return _out(1.0 / ((2.0 - nu1) / (4.0 * G1) + (2.0 - nu2) / (4.0 * G2)))


def hertz(E_star, radius, force, *, check_validity: bool = True) -> Contact:
    """Hertz contact of a sphere (radius R) on a flat under normal force F >= 0.

    a³ = 3FR/(4E*), δ = a²/R, p_centre = 3F/(2πa²), k = dF/dδ = 2E*a (Johnson, Ch. 4; paper 2,
    Eq. 9 with γ = 0). ``E_star`` in Pa (:func:`effective_modulus`), ``radius`` m, ``force`` N.

    Hertz's theory holds for a contact small against its sphere (a/R ≲ 0.1, Johnson §4.2), as
    the command line's ``contact`` checks: where a/R > 0.1 a
    :class:`contactres.errors.ContactresWarning` names a/R (values kept, "Hertz approximate");
    where a/R > 0.5 the contact has no value: contact radius, depth, pressures and stiffness
    are NaN (the force is kept), with the same warning ("beyond Hertz", most likely a radius or
    force in the wrong unit). ``check_validity=False`` leaves the check out (a caller that flags
    a/R itself).

    Examples
    --------
    A glass sphere of radius 5 µm pressed with 1 mN on glass:

    >>> import numpy as np
    >>> from contactres import effective_modulus, hertz
    >>> E_star = effective_modulus(70e9, 0.22)  # Pa, two identical bodies
    >>> c = hertz(E_star, 5e-6, 1e-3)
    >>> print(f"a = {float(c.contact_radius) * 1e9:.1f} nm, k = {float(c.stiffness):.4g} N/m")
    a = 467.2 nm, k = 3.436e+04 N/m
    >>> bool(np.isclose(c.contact_radius, (3e-3 * 5e-6 / (4 * E_star)) ** (1 / 3), atol=0))
    True
    >>> bool(np.isclose(c.depth, c.contact_radius**2 / 5e-6, atol=0))
    True
    """
    if type(E_star) is float and type(radius) is float and type(force) is float:
        # The fast path (see above), inline: a call costs a fifth of it. x in (0, inf) with R,
        # F > 0 holds only for finite inputs and E* > 0 (an infinite E* gives x = 0 or NaN, an
        # infinite R or F x = inf or NaN; NaN fails every comparison); F = 0, x out of range
        # (an overflow or underflow of valid inputs) and a/R > 0.1 take the general path.
        x = 0.75 * force * radius / E_star
        if 0.0 < force and 0.0 < radius and 0.0 < x < _INF:
            a = _cbrt(x)
            if a <= HERTZ_APPROXIMATE_RATIO * radius or not check_validity:
                a2 = a * a
                k = 2.0 * E_star * a
                new: Any = _Draft()  # as _new_contact
                new.contact_radius = a
                new.depth = a2 / radius
                new.mean_pressure = force / (_PI * a2)
                new.peak_pressure = k / (_PI * radius)  # = 3F/(2πa²)
                new.stiffness = k
                new.force = force
                new.model = "hertz"
                new.__class__ = Contact
                return new
    else:
        floats = _floats(E_star, radius, force)
        if floats is not None:  # ints, numpy floats: jkr's fast path below
            E_star, radius, force = floats
    c = jkr(E_star, radius, force, 0.0, _model="hertz")
    return checked(c, radius, "hertz") if check_validity else c


def jkr_pull_off_force(radius, gamma):
    """JKR pull-off force (force control) F = -3πγR, N (paper 2's γ; w = 2γ).

    Examples
    --------
    >>> import math
    >>> from contactres import jkr_pull_off_force
    >>> print(f"{float(jkr_pull_off_force(5e-6, 0.05)) * 1e6:.3f} µN")
    -2.356 µN
    >>> math.isclose(float(jkr_pull_off_force(5e-6, 0.05)), -3 * math.pi * 0.05 * 5e-6)
    True
    """
    return _out(-3.0 * np.pi * _nonnegative("gamma", gamma) * _positive("radius", radius))


def jkr_contact_radius(E_star, radius, force, gamma):
    """JKR contact radius a, m (paper 2, Eq. 9).

    a³ = (3R / 4E*) [F + 6πγR + √(12πγR F + (6πγR)²)]. ``gamma`` is the paper's energy of
    adhesion (J/m², work of adhesion w = 2γ); γ = 0 gives Hertz. Raises ValueError for a force
    below the pull-off force -3πγR.
    """
    plain = type(E_star) in _PLAIN and type(radius) in _PLAIN and type(force) in _PLAIN
    if (
        plain
        and type(gamma) in _PLAIN
        and (0.0 < E_star < _INF and 0.0 < radius < _INF)
        and (0.0 <= gamma < _INF and -_INF < force < _INF)
    ):
        # Python numbers: jkr's fast path's operations (see above), the same contact radius.
        E, R, F, g = float(E_star), float(radius), float(force), float(gamma)
        b = 6.0 * _PI * g * R
        disc = b * b + 2.0 * b * F
        if disc >= 0.0 and not (g == 0.0 and F < 0.0):
            return _cbrt(0.75 * R / E * (F + b + _sqrt(disc)))
    E_star = _positive("E_star", E_star)
    R = _positive("radius", radius)
    gamma = _nonnegative("gamma", gamma)
    F = np.asarray(force, dtype=float)
    if not np.all(np.isfinite(F)):
        raise ContactresInputError(f"force must be finite, got {force!r}")
    b = 6.0 * np.pi * gamma * R
    disc = 12.0 * np.pi * gamma * R * F + b**2
    # disc >= 0 exactly when F >= -3πγR (the pull-off force); allow rounding at the limit.
    if np.any(disc < -1e-12 * np.maximum(b**2, 1e-300)) or np.any((gamma == 0) & (F < 0)):
        raise ContactresInputError(
            f"force {force!r} N is below the pull-off force -3πγR = "
            f"{float(np.min(-3 * np.pi * gamma * R))!r} N (γ={gamma!r}, R={radius!r}); "
            "without adhesion (γ = 0) the force must be >= 0"
        )
    return _out(np.cbrt(3.0 * R / (4.0 * E_star) * (F + b + np.sqrt(np.maximum(disc, 0.0)))))


def _jkr_state(E_star, R, gamma, a, model, force=None) -> Contact:
    """The :class:`Contact` of JKR contacts of radius ``a`` (E*, R, γ and a broadcast arrays)
    under ``force``, or, without it, the force F = 4E*a³/(3R) − 4√(πγE*a³) of that radius."""
    if force is None:
        force = 4.0 * E_star * a**3 / (3.0 * R) - 4.0 * np.sqrt(np.pi * gamma * E_star * a**3)
    F = np.broadcast_to(np.asarray(force, dtype=float), a.shape)
    block = np.empty((4, *a.shape))
    rows = tuple(block[i, ...] for i in range(4))  # views, 0-d arrays for a 0-d a
    _jkr_fields(E_star, R, gamma, a, F, rows, bool(np.any(gamma != 0.0)))
    depth, mean_p, centre, stiffness = (_out(x) for x in rows)
    return Contact(_out(a), depth, mean_p, centre, stiffness, _out(F), model)


def jkr(E_star, radius, force, gamma, *, _model: str = "jkr") -> Contact:
    """JKR contact of a sphere on a flat (paper 2, Eq. 9; Johnson, Kendall & Roberts 1971).

    Parameters
    ----------
    E_star : effective modulus E*, Pa
    radius : sphere radius R, m
    force : normal force F, N (>= pull-off force -3πγR)
    gamma : paper 2's energy of adhesion γ, J/m² (work of adhesion w = 2γ)

    Returns
    -------
    Contact with a from Eq. 9, δ = a²/R - √(4πγa/E*) = a²/R - √(2πwa/E*), the normal stiffness
    dF/dδ (zero slope at the pull-off point, where dδ/da = 0 is not reached: dF/da = 0 there), and
    the pressure at the centre 2E*a/(πR) - √(2wE*/(πa)).

    Examples
    --------
    Adhesion keeps a finite contact at zero load; the pull-off force is −3πγR:

    >>> import numpy as np
    >>> from contactres import effective_modulus, hertz, jkr
    >>> E_star = effective_modulus(70e9, 0.22)
    >>> c = jkr(E_star, 5e-6, 0.0, 0.05)  # γ = 0.05 J/m²
    >>> print(f"a(F = 0) = {float(c.contact_radius) * 1e9:.1f} nm")
    a(F = 0) = 98.7 nm
    >>> bool(np.isclose(c.contact_radius, (9 * np.pi * 0.05 * 5e-6**2 / E_star) ** (1 / 3), atol=0))
    True
    >>> bool(np.isclose(jkr(E_star, 5e-6, 1e-3, 0.0).contact_radius,
    ...                 hertz(E_star, 5e-6, 1e-3).contact_radius, atol=0))
    True
    """
    E, R, F = E_star, radius, force
    if type(E) is float and type(R) is float and type(F) is float and type(gamma) is float:
        # The fast path (see above). Checks as in hertz (an infinite γ gives b = inf); the
        # discriminant b² + 2bF = 12πγRF + (6πγR)² >= 0 is F >= -3πγR (F = NaN fails), and
        # a > 0 rules out F <= 0 without adhesion, an error or the zero-area point.
        b = 6.0 * _PI * gamma * R
        disc = b * b + 2.0 * b * F
        if 0.0 < E and 0.0 < R and 0.0 <= gamma and disc >= 0.0:
            x = 0.75 * R / E * (F + b + _sqrt(disc))
            if 0.0 < x < _INF:
                a = _cbrt(x)
                # One square root: q = √(πγa/E*) gives √(4πγa/E*) = 2q, √(πγE*a) = E*q,
                # √(πγ/(E*a)) = q/a and √(4γE*/(πa)) = 2E*q/(πa); u = a²/R.
                u = a * a / R
                q = _sqrt(_PI * gamma * a / E)
                try:
                    # dF/dδ = (dF/da)/(dδ/da) = 2E*(2u - 3q) / ((2u - q)/a)
                    k = 2.0 * E * a * (2.0 * u - 3.0 * q) / (2.0 * u - q)
                    return _new_contact(
                        a, u - 2.0 * q, F / (_PI * a * a), 2.0 * E / _PI * (a / R - q / a),
                        k, F, _model,
                    )  # fmt: skip
                except ZeroDivisionError:  # u = q = 0 (a²/R underflowed, γ = 0): numpy's nan
                    pass
    else:
        floats = _floats(E_star, radius, force, gamma)
        if floats is not None:
            return jkr(*floats, _model=_model)
    E_star = _positive("E_star", E_star)
    R = _positive("radius", radius)
    gamma = _nonnegative("gamma", gamma)
    F = np.asarray(force, dtype=float)
    if type(E_star) is float and type(R) is float and type(gamma) is float and F.ndim and F.size:
        c = _array_jkr(E_star, R, F, gamma, _model)
        if c is not None:
            return c
    a = np.asarray(jkr_contact_radius(E_star, R, force, gamma), dtype=float)
    E_star, R, gamma, a = np.broadcast_arrays(E_star, R, gamma, a)
    # The requested force itself, not its round trip through a.
    return _jkr_state(E_star, R, gamma, a, _model, force)


def jkr_from_depth(E_star, radius, depth, gamma) -> Contact:
    """JKR contact at a given penetration δ (displacement control), m.

    Solves δ = a²/R - √(4πγa/E*) for the contact radius (the stable branch, a above the
    displacement-controlled pull-off radius) and returns the :class:`Contact`, including the force
    F = 4E*a³/(3R) - 4√(πγE*a³). Raises ValueError for δ below the smallest δ of a connected
    contact (the displacement-controlled pull-off point).
    """
    E_star = _positive("E_star", E_star)
    R = _positive("radius", radius)
    gamma = _nonnegative("gamma", gamma)
    d = np.asarray(depth, dtype=float)
    E_star, R, gamma, d = np.broadcast_arrays(E_star, R, gamma, d)
    if not np.all(np.isfinite(d)):
        raise ContactresInputError(f"depth must be finite, got {depth!r}")
    # f(a) = a²/R - c√a - δ, c = √(4πγ/E*), is convex with its minimum d_min at
    # a_min = (cR/4)^(2/3); the stable branch is the root above a_min. Convexity with f'' >= 2/R
    # bounds that root by a_min + √(R(δ - d_min)), so Newton from there converges monotonically.
    c = np.sqrt(4.0 * np.pi * gamma / E_star)
    a_min = np.cbrt(c * R / 4.0) ** 2
    d_min = a_min**2 / R - c * np.sqrt(a_min)
    if np.any(d < d_min * (1 + 1e-12)) or np.any((gamma == 0) & (d < 0)):
        raise ContactresInputError(
            f"depth {depth!r} m is below the smallest penetration of a JKR contact "
            f"({np.min(d_min)!r} m, reached at displacement-controlled pull-off)"
        )
    a = a_min + np.sqrt(R * np.maximum(d - d_min, 0.0))
    for _ in range(100):
        f = a**2 / R - c * np.sqrt(a) - d
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(a > 0, f / (2.0 * a / R - 0.5 * c / np.sqrt(a)), 0.0)
        step = np.where(np.isfinite(step), step, 0.0)
        a = np.maximum(a - step, a_min)
        if np.all(np.abs(step) <= 1e-15 * np.maximum(a, 1e-300)):
            break
    return _jkr_state(E_star, R, gamma, a, "jkr")


def dmt(E_star, radius, force, gamma) -> Contact:
    """DMT contact (Derjaguin, Muller & Toporov 1975): Hertz under the load F + 4πγR.

    a³ = 3R(F + 4πγR)/(4E*), δ = a²/R, stiffness 2E*a, pull-off force -4πγR (= -2πwR with the
    paper's γ, w = 2γ). Valid for stiff, small, weakly adhesive contacts (Tabor parameter < 0.1).

    Examples
    --------
    >>> import numpy as np
    >>> from contactres import dmt, effective_modulus, hertz
    >>> E_star = effective_modulus(70e9, 0.22)
    >>> c = dmt(E_star, 5e-6, 0.0, 0.05)

    DMT is Hertz under the applied load plus the adhesive load 4πγR:

    >>> a_hertz = hertz(E_star, 5e-6, 4 * np.pi * 0.05 * 5e-6).contact_radius
    >>> bool(np.isclose(c.contact_radius, a_hertz, atol=0))
    True
    """
    E, R, F = E_star, radius, force
    if type(E) is float and type(R) is float and type(F) is float and type(gamma) is float:
        # The fast path (see above): x in (0, inf) with E*, R > 0 and γ >= 0 holds only for
        # finite inputs (as in hertz) and a load above the pull-off force.
        load = F + 4.0 * _PI * gamma * R
        x = 0.75 * load * R / E
        if 0.0 < E and 0.0 < R and 0.0 <= gamma and 0.0 < x < _INF:
            a = _cbrt(x)
            a2 = a * a
            return _new_contact(
                a, a2 / R, F / (_PI * a2), 1.5 * load / (_PI * a2), 2.0 * E * a, F, "dmt"
            )
    else:
        floats = _floats(E_star, radius, force, gamma)
        if floats is not None:
            return dmt(*floats)
    E_star = _positive("E_star", E_star)
    R = _positive("radius", radius)
    gamma = _nonnegative("gamma", gamma)
    F = np.asarray(force, dtype=float)
    if type(E_star) is float and type(R) is float and type(gamma) is float and F.ndim and F.size:
        c = _array_dmt(E_star, R, F, gamma)
        if c is not None:
            return c
    load = F + 4.0 * np.pi * gamma * R
    if not np.all(np.isfinite(F)) or np.any(load < 0):
        raise ContactresInputError(
            f"force {force!r} N must be finite and >= the DMT pull-off force -4πγR = "
            f"{float(np.min(-4 * np.pi * gamma * R))!r} N (γ={gamma!r}, R={radius!r})"
        )
    a = np.cbrt(3.0 * R * load / (4.0 * E_star))
    with np.errstate(divide="ignore", invalid="ignore"):
        mean_p = np.where(a > 0, F / (np.pi * a**2), 0.0)
        centre = np.where(a > 0, 3.0 * load / (2.0 * np.pi * a**2), 0.0)
    return Contact(
        contact_radius=_out(a),
        depth=_out(a**2 / R),
        mean_pressure=_out(mean_p),
        peak_pressure=_out(centre),
        stiffness=_out(2.0 * E_star * a),
        force=_out(np.broadcast_to(F, a.shape)),
        model="dmt",
    )


def tabor_parameter(E_star, radius, gamma, z0=0.3e-9):
    """Tabor parameter μ_T = (R w² / (E*² z0³))^(1/3), dimensionless (w = 2γ, z0 in m).

    ``z0`` is the equilibrium separation of the surface potential (default 0.3 nm). See
    :func:`which_adhesion_model`.

    Examples
    --------
    >>> from contactres import effective_modulus, tabor_parameter
    >>> E_star = effective_modulus(70e9, 0.22)
    >>> round(float(tabor_parameter(E_star, 5e-6, 0.05)), 3)
    1.11
    """
    E_star = _positive("E_star", E_star)
    R = _positive("radius", radius)
    w = 2.0 * _nonnegative("gamma", gamma)
    z0 = _positive("z0", z0)
    return _out(np.cbrt(R * w**2 / (E_star**2 * z0**3)))


def which_adhesion_model(E_star, radius, gamma, z0=0.3e-9) -> str:
    """Which adhesive contact model applies: "jkr" (μ_T > 5), "dmt" (μ_T < 0.1), else
    "maugis" (the transition, Maugis-Dugdale; JKR and DMT both approximate), Johnson & Greenwood
    1997 adhesion map. Scalars only.

    Examples
    --------
    A stiff small glass sphere sits between DMT and JKR; a soft large one is JKR:

    >>> from contactres import effective_modulus, which_adhesion_model
    >>> which_adhesion_model(effective_modulus(70e9, 0.22), 5e-6, 0.05)
    'maugis'
    >>> which_adhesion_model(1e6, 1e-3, 0.05)
    'jkr'
    """
    mu = float(np.asarray(tabor_parameter(E_star, radius, gamma, z0)))
    if mu > 5.0:
        return "jkr"
    if mu < 0.1:
        return "dmt"
    return "maugis"
