"""Contact stiffness k* -> the modulus of a film on a known substrate (CR-AFM / RUM on a coating;
issue 26, point 4).

On a coated sample the contact of a sphere (tip radius R, load P) is no longer Hertzian: its
radius and its stiffness k*(M_f) depend on the film's modulus M_f, the film's thickness h and the
substrate, and there is no closed form to invert. Here the film is a known material whose
constants are scaled by one unknown factor s (its anisotropy and Poisson's ratio kept), so that
its indentation modulus is M_f = s M_ref, and

1. the forward curve ln k*(ln s) of every distinct contact (R, P, tip modulus) is computed on
   ``nodes`` Chebyshev points (first kind) of ln s over the search range with the exact layered
   contact, :func:`contactres.sphere_contact` on a :class:`~contactres.LayeredMaterial`
   (axisymmetric solution; an elastic tip as its ``indenter``), and interpolated by the
   Chebyshev polynomial through them. The curve is smooth (analytic) in ln s, so the
   interpolation converges geometrically. Measured on 20 nm of a ν = 0.35 film on silica, a
   20 nm tip at 1 µN: over a range of 100 in M_f (the default's width) the round trip of M_f
   is off by 4e-9 with 13 points, 2e-11 with 17 (the default) and 4e-14 with 25; over a range
   of 10⁴ the largest error of ln k* is 3e-7 with 17 points, 1.5e-9 with 25 and 2e-12 with 33.
   The error is estimated on every run from the last two Chebyshev coefficients
   (``interpolation_error``);
2. every pixel's k* is then found on its contact's curve by a vectorised root find (Illinois,
   modified regula falsi, on ln s, to 1e-14 in ln k*): no Python loop over the pixels, and the
   cost is ``nodes`` layered contacts per distinct contact, whatever the number of pixels.
   The layered contact's cost grows like (a/h)³ (a the contact radius) and its solver refuses
   a/h > ~525: the soft end of a wide range under a thin film is the costly one (narrow the
   range there).

k*(M_f) increases with M_f (a stiffer film, a stiffer contact). A k* outside the curve's range
has no film modulus in the search range: verdict ``below-range`` or ``above-range``, M_f NaN.

How well the film is resolved: the film's weight w = (∂ln k*/∂ln M_f) / ((2/3) E*_f/M_f), the
sensitivity of k* to the film's modulus relative to that of a contact on the film alone
(Hertz at fixed load: k* ∝ E*^(2/3), E*_f = (1/M_f + 1/M_tip)⁻¹). With a rigid tip, k* scaled
with every modulus of the stack scales as their 2/3 power, so ∂ln k*/∂ln M_f + ∂ln k*/∂ln M_s
= 2/3 (Euler): w is the film's share of the stiffness's sensitivity and 1 − w the substrate's.
w -> 0 for a film much thinner than the contact (the substrate dominates: the film's modulus is
not identified; an error ε in k* becomes an error 3ε/(2w) in M_f), and w -> 1 for a film much
thicker than it. Verdicts:

* ``too-thin``: w < ``min_film_weight`` (default 0.1: a 1 % error of k* would move M_f by
  more than 15 %); M_f is not given (NaN);
* ``too-thick``: M_f within ``thick_tolerance`` (default 1 %) of the homogeneous inversion of
  the same k* (Hertz on the film alone, ``M_homogeneous``: K. L. Johnson, Contact Mechanics,
  Cambridge University Press 1985, Eqs. 4.22-4.23, E* = √(k*³/(6RP)), tip compliance removed):
  the coating made no difference, M_f is given and equals that;
* ``film``: M_f identified with the layered contact;
* ``beyond-hertz``: the contact radius at the solution exceeds half the tip radius
  (a/R > :data:`~contactres.units.HERTZ_MAX_RATIO`): the layered contact, like Hertz's, takes
  the tip as a paraboloid in small strain (Johnson 1985, §4.2: a/R ≲ 0.1), so M_f is not
  given (NaN), as :func:`contactres.sphere_contact` gives no value there. Between
  a/R = 0.1 and 0.5 M_f is given with one :class:`~contactres.errors.ContactresWarning`
  ("Hertz approximate"); ``check_validity=False`` skips both.

Moduli are indentation moduli (Pa): isotropic M = E/(1 − ν²). Static contact: k* is the static
contact stiffness (a dynamic correction, if any, applied before).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .._summary import Summarised, number, values
from ..errors import ContactresInputError, ContactresWarning
from ..layered import LayeredMaterial
from ..materials import Material, require_material
from ..numerics import illinois_step
from ..units import HERTZ_APPROXIMATE_RATIO, HERTZ_MAX_RATIO
from ..validation import positive

__all__ = [
    "FILM_COLUMNS",
    "FILM_VERDICTS",
    "RANGE_FACTOR",
    "FilmModulusResult",
    "film_columns",
    "film_modulus_from_contact_stiffness",
]

#: The columns :func:`film_columns` gives, in its order.
FILM_COLUMNS = ("M_film_Pa", "film_contact_radius_m", "film_weight", "film_verdict")
#: The verdicts of :func:`film_modulus_from_contact_stiffness`, one per pixel.
FILM_VERDICTS = ("film", "too-thick", "too-thin", "below-range", "above-range", "beyond-hertz")
#: Default search range of the film's modulus, as factors of the named film's own modulus.
RANGE_FACTOR = 10.0
# Root find on the Chebyshev curve: Illinois on x in [-1, 1], to this residual of ln k*.
_ROOT_TOL = 1e-14
_ROOT_ITERATIONS = 100


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the maps.
@dataclass(frozen=True, repr=False)
class FilmModulusResult(Summarised):
    """The film's modulus from contact stiffness, per pixel (arrays of the broadcast shape).

    Attributes
    ----------
    M_film : the film's indentation modulus, Pa (NaN for ``too-thin`` and out-of-range pixels)
    M_homogeneous : the Hertz inversion of k* as if the film filled the half-space, Pa (tip
        compliance removed; NaN where the tip is the stiffer limit)
    contact_radius : the contact radius of the coated contact at M_film, m (NaN where no
        solution in the range)
    film_weight : w, the film's share of the sensitivity of k* (module docstring; NaN where no
        solution in the range)
    verdict : one of :data:`FILM_VERDICTS` (object array)
    film_range : the search range of M_film, (low, high), Pa
    reference_modulus : the indentation modulus of the film material as given, Pa
    interpolation_error : estimated largest error of the interpolated ln k*, dimensionless
    """

    M_film: np.ndarray
    M_homogeneous: np.ndarray
    contact_radius: np.ndarray
    film_weight: np.ndarray
    verdict: np.ndarray
    film_range: tuple[float, float]
    reference_modulus: float
    interpolation_error: float

    def _facts(self) -> list[tuple[str, str]]:
        """M_film and M_homogeneous (GPa), the verdicts counted, the search range (GPa)."""
        kinds, counts = np.unique(np.asarray(self.verdict, dtype=str), return_counts=True)
        lo, hi = self.film_range
        return [
            ("M_film", values(self.M_film, "GPa", 1e9)),
            ("M_homogeneous", values(self.M_homogeneous, "GPa", 1e9)),
            ("verdicts", ", ".join(f"{k} {n}" for k, n in zip(kinds, counts, strict=True))),
            ("range", f"{number(lo, '', 1e9)} to {number(hi, 'GPa', 1e9)}"),
        ]


def _range(film_range, reference: float) -> tuple[float, float]:
    """The search range of M_film (Pa), checked."""
    if film_range is None:
        return reference / RANGE_FACTOR, reference * RANGE_FACTOR
    try:
        lo, hi = (float(v) for v in film_range)
    except (TypeError, ValueError):
        raise ContactresInputError(
            f"film_range must be two moduli (low, high) in Pa, got {film_range!r}"
        ) from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise ContactresInputError(
            f"film_range must be two finite moduli 0 < low < high in Pa, got {film_range!r}"
        )
    return lo, hi


def _scaled(film: Material, s: float) -> Material:
    """The film with every constant times ``s`` (its indentation modulus times ``s``)."""
    return Material(C=film.C * s, density=film.density, name=film.name, frame=film.frame)


def _curves(substrate, film, film_modulus, thickness, log_s, R, P, M_tip):
    """ln k* and ln a of the coated contact at the films ``exp(log_s)`` (rows) for the distinct
    contacts (R, P, M_tip) (columns)."""
    from ..normal import sphere_contact

    ln_k = np.empty((log_s.size, R.size))
    ln_a = np.empty_like(ln_k)
    tips = np.unique(M_tip)
    for j, ls in enumerate(log_s):
        stack = LayeredMaterial(substrate, [(_scaled(film, math.exp(ls)), thickness)])
        for m in tips:  # one indenter per tip modulus (a few at most)
            cols = M_tip == m
            tip = None if math.isinf(m) else Material.isotropic(m, 0.0, name="tip")
            try:
                c = sphere_contact(stack, R[cols], P[cols], indenter=tip, check_validity=False)
            except ContactresInputError as err:  # a/h beyond the layered solver
                raise ContactresInputError(
                    f"film modulus {math.exp(ls) * film_modulus:.3g} Pa of the search range: "
                    f"{err} (narrow the film's range)"
                ) from None
            ln_k[j, cols] = np.log(np.asarray(c.stiffness, dtype=float))
            ln_a[j, cols] = np.log(np.asarray(c.contact_radius, dtype=float))
    return ln_k, ln_a


def _roots(coef, target):
    """x in [-1, 1] with chebval(x, coef[:, i]) = target[i] for each column i (the curves
    increase; every target lies between the curve's values at -1 and 1)."""
    from numpy.polynomial import chebyshev

    def g(x):
        return chebyshev.chebval(x, coef, tensor=False) - target

    lo, hi = -np.ones(target.shape), np.ones(target.shape)
    g_lo, g_hi = g(lo), g(hi)
    x = np.zeros(target.shape)
    side = np.zeros(target.shape, dtype=int)
    for _ in range(_ROOT_ITERATIONS):
        span = g_hi - g_lo
        x = np.where(span > 0, (lo * g_hi - hi * g_lo) / np.where(span > 0, span, 1.0), lo)
        gx = g(x)
        if np.all(np.abs(gx) <= _ROOT_TOL):
            return x
        lo, hi, g_lo, g_hi, side = illinois_step(x, gx, (lo, hi, g_lo, g_hi, side))
    return x  # residuals of a few 1e-14 after the cap: far below the interpolation error


def film_modulus_from_contact_stiffness(
    k_star,
    *,
    substrate: Material,
    film: Material,
    thickness: float,
    tip_radius,
    load,
    tip_modulus=None,
    film_range: tuple[float, float] | None = None,
    min_film_weight: float = 0.1,
    thick_tolerance: float = 0.01,
    nodes: int = 17,
    check_validity: bool = True,
) -> FilmModulusResult:
    """The indentation modulus of a film on a known substrate from the contact stiffness k*.

    Parameters
    ----------
    k_star : float or array
        Static contact stiffness k* of each pixel, N/m (> 0).
    substrate : Material
        The substrate in its surface frame (static constants, lossless).
    film : Material
        The film's material (static constants, lossless): its anisotropy and Poisson's ratio
        are kept, its modulus is the unknown (every constant scaled by one factor).
    thickness : float
        The film's thickness h, m.
    tip_radius, load : float or array
        Tip radius R (m) and static load P (N) of each pixel (broadcast with ``k_star``).
    tip_modulus : float or array, optional
        The tip's indentation modulus M_tip, Pa (inf or None: a rigid tip).
    film_range : (float, float), optional
        The search range of M_film, Pa; default the film's own modulus divided and multiplied
        by :data:`RANGE_FACTOR` (10).
    min_film_weight : float
        Below this film weight the verdict is ``too-thin`` (module docstring), dimensionless.
    thick_tolerance : float
        Relative distance of M_film from the homogeneous inversion within which the verdict is
        ``too-thick``, dimensionless.
    nodes : int
        Chebyshev points of the forward curve (module docstring for its accuracy).
    check_validity : bool
        Check Hertz's small-contact limit at the solution (module docstring: verdict
        ``beyond-hertz`` and no M_f beyond a/R = 0.5, a warning above 0.1); False skips it.

    Returns
    -------
    FilmModulusResult
        Arrays of the broadcast shape of ``k_star``, ``tip_radius``, ``load``, ``tip_modulus``.

    Raises
    ------
    ContactresInputError
        For a bad stiffness, radius, load, tip modulus, thickness, range or threshold.

    Examples
    --------
    A 20 nm film on fused silica measured with a 100 nm tip at 50 nN: the forward contact at
    M_f = 6 GPa, inverted with a film of the same Poisson's ratio at another modulus.

    >>> from contactres import LayeredMaterial, Material, sphere_contact
    >>> from contactres.analysis import film_modulus_from_contact_stiffness
    >>> silica = Material.isotropic(72e9, 0.17, name="silica")
    >>> film = Material.isotropic(6e9 * (1 - 0.35**2), 0.35, name="film")  # M = 6 GPa
    >>> stack = LayeredMaterial(silica, [(film, 20e-9)])
    >>> k = sphere_contact(stack, 100e-9, 50e-9).stiffness  # a/R = 0.085: Hertz's range
    >>> guess = Material.isotropic(3e9, 0.35, name="film")
    >>> r = film_modulus_from_contact_stiffness(
    ...     k, substrate=silica, film=guess, thickness=20e-9, tip_radius=100e-9, load=50e-9)
    >>> print(f"M_film = {float(r.M_film) / 1e9:.6f} GPa ({r.verdict[()]})")
    M_film = 6.000000 GPa (film)
    """
    from numpy.polynomial import chebyshev

    substrate = require_material(substrate, lossless=True)
    film = require_material(film, lossless=True)
    h = float(positive("thickness (film thickness h)", thickness, "m"))
    k = np.asarray(positive("k_star (contact stiffness k*)", k_star, "N/m"), dtype=float)
    R = np.asarray(positive("tip_radius", tip_radius, "m"), dtype=float)
    P = np.asarray(positive("load", load, "N"), dtype=float)
    M_tip = np.asarray(math.inf if tip_modulus is None else tip_modulus, dtype=float)
    if np.any(np.isnan(M_tip) | (M_tip <= 0)):
        raise ContactresInputError("tip_modulus must be > 0 Pa (inf: a rigid tip)")
    for name, value in (("min_film_weight", min_film_weight), ("thick_tolerance", thick_tolerance)):
        if not (math.isfinite(value) and 0 <= value < 1):
            raise ContactresInputError(f"{name} must be in [0, 1), got {value!r}")
    n = int(nodes)
    if n < 4:
        raise ContactresInputError(f"nodes must be >= 4, got {nodes!r}")
    try:
        shape = np.broadcast_shapes(k.shape, R.shape, P.shape, M_tip.shape)
    except ValueError:
        raise ContactresInputError(
            "k_star, tip_radius, load and tip_modulus do not broadcast together: "
            f"{k.shape}, {R.shape}, {P.shape}, {M_tip.shape}"
        ) from None
    k, R, P, M_tip = (np.broadcast_to(x, shape).ravel() for x in (k, R, P, M_tip))
    from ..normal import indentation_modulus

    M_ref = float(np.real(indentation_modulus(film)))
    lo, hi = _range(film_range, M_ref)
    # The distinct contacts: every pixel of a map with one tip and one load shares one curve.
    keys, which = np.unique(np.stack([R, P, M_tip]), axis=1, return_inverse=True)
    which = which.reshape(-1)
    # Chebyshev points (first kind) of ln s, s = M_f/M_ref, over the range.
    x_nodes = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    mid, half = 0.5 * math.log(hi * lo) - math.log(M_ref), 0.5 * math.log(hi / lo)
    ln_k, ln_a = _curves(substrate, film, M_ref, h, mid + half * x_nodes, *keys)
    order = np.argsort(x_nodes)
    if np.any(np.diff(ln_k[order], axis=0) <= 0):
        raise ContactresInputError(
            "the coated contact's stiffness does not increase with the film's modulus over "
            f"{lo:.3g}-{hi:.3g} Pa: narrow the film's range"
        )
    c_k = chebyshev.chebfit(x_nodes, ln_k, n - 1)
    c_a = chebyshev.chebfit(x_nodes, ln_a, n - 1)
    error = float(np.max(np.abs(c_k[-2:])))
    target = np.log(k)
    ck = c_k[:, which]
    y_lo, y_hi = chebyshev.chebval(-1.0, ck), chebyshev.chebval(1.0, ck)
    below, above = target < y_lo, target > y_hi
    inside = ~(below | above)
    x = np.full(k.shape, np.nan)
    x[inside] = _roots(ck[:, inside], target[inside])
    M_f = M_ref * np.exp(mid + half * x)
    slope = chebyshev.chebval(x, chebyshev.chebder(ck), tensor=False) / half  # ∂ln k*/∂ln M_f
    weight = 1.5 * slope * (1.0 + M_f / M_tip)
    a = np.exp(chebyshev.chebval(x, c_a[:, which], tensor=False))
    # Hertz on the film alone (Johnson, Eqs. 4.22-4.23), the tip's compliance removed.
    excess = 1.0 / np.sqrt(k**3 / (6.0 * R * P)) - 1.0 / M_tip
    with np.errstate(divide="ignore"):
        M_hom = np.where(excess > 0, 1.0 / np.where(excess > 0, excess, 1.0), np.nan)
    verdict = np.full(k.shape, "film", dtype=object)
    thick = np.abs(M_f / M_hom - 1.0) <= thick_tolerance
    verdict[inside & thick] = "too-thick"
    thin = inside & (weight < min_film_weight)
    verdict[thin] = "too-thin"
    verdict[below], verdict[above] = "below-range", "above-range"
    M_f = np.where(inside & ~thin, M_f, np.nan)
    if check_validity:
        M_f = _hertz_limit(a / R, inside, verdict, M_f)

    def out(v):
        return np.asarray(v).reshape(shape)

    return FilmModulusResult(
        M_film=out(M_f),
        M_homogeneous=out(M_hom),
        contact_radius=out(a),
        film_weight=out(weight),
        verdict=out(verdict),
        film_range=(lo, hi),
        reference_modulus=M_ref,
        interpolation_error=error,
    )


def _hertz_limit(ratio, inside, verdict, M_f) -> np.ndarray:
    """M_f without the pixels whose contact is beyond Hertz (a/R > HERTZ_MAX_RATIO: verdict
    ``beyond-hertz``, set in ``verdict`` in place), after one ContactresWarning where some
    a/R > HERTZ_APPROXIMATE_RATIO (the rule of :mod:`contactres.normal._validity`)."""
    over = inside & (ratio > HERTZ_APPROXIMATE_RATIO)
    if not over.any():
        return M_f
    beyond = inside & (ratio > HERTZ_MAX_RATIO)

    def count(mask):
        return f" ({int(mask.sum())} of {ratio.size} pixels)" if ratio.size > 1 else ""

    if beyond.any():
        verdict[beyond] = "beyond-hertz"
        message = (
            f"film_modulus_from_contact_stiffness: a/R = {float(np.max(ratio[beyond])):.3g} > "
            f"{HERTZ_MAX_RATIO:g}{count(beyond)}: beyond Hertz, no film modulus (verdict "
            "beyond-hertz); check the tip radius (m) and the load (N)"
        )
    else:
        message = (
            f"film_modulus_from_contact_stiffness: a/R = {float(np.max(ratio[over])):.3g} > "
            f"{HERTZ_APPROXIMATE_RATIO:g}{count(over)}: Hertz approximate (the contact takes "
            "the tip as a paraboloid, for a ≪ R); values kept"
        )
    warnings.warn(message, ContactresWarning, stacklevel=3)
    return np.where(beyond, np.nan, M_f)


def film_columns(
    k_star, tip_radius, load, tip_modulus, **film
) -> tuple[dict, FilmModulusResult | None]:
    """The film columns of a table of pixels (``afm invert``/``rum invert --coating``).

    Parameters
    ----------
    k_star, tip_radius, load, tip_modulus : 1-D arrays
        Per row: k* (N/m), R (m), P (N) and M_tip (Pa; NaN or inf: a rigid tip). Rows without
        a positive finite k*, R and P are left out (empty verdict, NaN columns).
    **film
        ``substrate``, ``film``, ``thickness`` and the options of
        :func:`film_modulus_from_contact_stiffness`.

    Returns
    -------
    (dict, FilmModulusResult or None)
        Columns M_film_Pa, film_contact_radius_m, film_weight (floats) and film_verdict (text)
        (:data:`FILM_COLUMNS`), and the result on the rows used (None without any).
    """
    k, R, P, tip = (np.asarray(x, dtype=float).ravel() for x in (k_star, tip_radius, load,
                                                                  tip_modulus))  # fmt: skip
    used = np.ones(k.size, dtype=bool)
    for x in (k, R, P):
        used &= np.isfinite(x) & (x > 0)
    *numbers, verdict = FILM_COLUMNS
    cols = {c: np.full(k.size, np.nan) for c in numbers}
    cols[verdict] = np.full(k.size, "", dtype=object)
    if not used.any():
        return cols, None
    res = film_modulus_from_contact_stiffness(
        k[used],
        tip_radius=R[used],
        load=P[used],
        tip_modulus=np.where(np.isnan(tip[used]), np.inf, tip[used]),
        **film,
    )
    cols["M_film_Pa"][used] = res.M_film
    cols["film_contact_radius_m"][used] = res.contact_radius
    cols["film_weight"][used] = res.film_weight
    cols["film_verdict"][used] = res.verdict
    return cols, res
