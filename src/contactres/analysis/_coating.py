"""E and γ from κ(F_N) on a coated plate (issue 26, point 4): JKR + Mindlin on a layered plate.

Paper 2 fits κ(F_N) with JKR (Eq. 9) and Mindlin (κ = 2G*a, Eqs. 7-8) as if sphere and plate
were one homogeneous solid. On a plate coated with a film (thickness h, a fixed material) the
contact radius and the tangential stiffness change; here they come from the layered solution,
and E keeps its meaning: the common Young's modulus of the sphere and of the plate's substrate
under the film (ν fixed, from the ``poisson`` column).

**Normal contact, adhesive (compliance method).** For the pair (elastic sphere on the coated
plate; both see the same pressure, so their surface compliances add: the kernel of
:func:`contactres.normal.sphere_contact` with ``indenter=``) let P'(a) be the force of the
frictionless, non-adhesive contact of radius a and C(a) = 1/K(a) the compliance of the flat
punch of radius a (:func:`contactres.normal.sphere_contact_at`). The adhesive contact of radius
a is the non-adhesive one plus a flat punch carrying P − P' (the sum is the solution with
the same contact area: Shull, Mater. Sci. Eng. R 36, 1 (2002), Sect. 3; Johnson & Sridhar,
J. Phys. D 27, 429 (1994)). The punch's elastic energy at fixed load is U = ½ C (P − P')²,
and the energy released per unit of contact area lost, −∂U/∂A at fixed P with A = πa², is

    G = (P − P')² (−dC/da) / (4π a),

which Griffith's condition sets equal to the work of adhesion w = 2γ (paper 2's γ):

    P(a) = P'(a) − √(8π γ a / (−dC/da)).

Check, homogeneous pair (C = 1/(2aE*), −dC/da = 1/(2a²E*), P' = 4E*a³/(3R)):
P = 4E*a³/(3R) − √(16πγE*a³), i.e. a³ = (3R/4E*)[P + 6πγR + √(12πγRP + (6πγR)²)], paper 2's
Eq. 9 (tests/analysis/test_coating.py checks it against :func:`contactres.jkr` to 1e-8). The
contact is force controlled: a is the root on the stable branch (dP/da > 0).

**Tangential stiffness.** κ is the stiffness of the sticking contact of radius a: the sphere
(homogeneous, E and ν) and the coated plate take the same, equal and opposite, traction, so
their in-plane surface compliances add, and κ is the bonded, relaxed tangential punch on the
summed compliance (:func:`contactres.normal.static_punch_stiffness` with ``indenter=``), real
part (κ is the storage part: Δf0/P). Homogeneous: κ = 4Ga/(2 − ν) = 2G*a, paper 2's κ with G*
of Eqs. 7-8. The sphere's punch and the coated plate's punch in series (each with its own
traction) is an upper bound: measured 0.3 % (a/h = 5) to 1 % (a/h = 20-40) above it for
250 nm of PMMA on E = 70 GPa (the gallery's estimate, docs/gallery/scripts/paper2_coating.py,
uses the series).

**The film's constants.** A frequency-dependent film (:func:`contactres.pmma`) enters the
normal (static) contact with its storage constants at 1 Hz
(:func:`contactres.viscoelastic.static_solid`) and the tangential stiffness with its
complex constants at the overtone frequency (correspondence principle; the plate's inertia at
k a ~ 0.1 is left out, as in paper 2). Approximations, stated: isotropic sphere and substrate
(the film any material the layered solver takes, θ-averaged: :mod:`contactres.normal._layered`),
frictionless normal contact (the normal-tangential coupling of dissimilar bodies is left out, as
in Hertz and JKR), the axisymmetric solution, the radiation of the plate not included.

The table of the film corrections, its interpolation and the contact-radius solve:
:mod:`contactres.analysis._coating_law`. The E range of the table is the fit's bound (a
fit there is flagged ``fit-at-bound``); a contact radius outside the table is clamped to it
while the fit searches. The table's radii are first those of the uncoated fit widened (an
elastic film keeps the coated radii near them); a fit that needs a radius outside at a load
it used is refitted once on a table of the radii the film can give there, within a reach of
the thinnest layer (a film soft in the static contact and stiff at the overtone:
:func:`_wider_law`), and withheld
(``fit-at-bound``, with a note) only if it still needs one. A load the fit left out (κ <= 0, or
no κ) withholds nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..fitting import fit
from ..layered import checked_thickness
from ..materials import Material
from ..normal import indentation_modulus, jkr_contact_radius
from ..tangential import kappa_jkr_mindlin
from ..viscoelastic import static_solid
from ._coating_bootstrap import resampled_coated
from ._coating_law import CoatedLaw, Coating, build_law
from ._jkr import LoadLaw, fit_group, fitted_points

__all__ = [
    "CoatedLaw",
    "Coating",
    "apply_coating",
    "as_coating",
    "build_law",
    "fit_coated",
    "load_law",
]

# The E range of the table around the uncoated fits' E (a soft film lowers the apparent E, a
# stiff one raises it) and the contact radii around theirs (both models fit the same κ, so the
# coated radii stay near the uncoated ones for an elastic film: 0.9-1.1 times them on the
# bundled example with 250 nm of PMMA; a film soft statically and stiff at the overtone needs
# more, and gets a wider table, _wider_law); five nodes in E, seven under a film stiffer than
# the substrate (build_law). A fit outside is flagged, not extrapolated.
_E_WINDOW = (0.6, 2.5)
_A_WINDOW = (0.7, 1.5)
# The largest contact radius of a widened table (_wider_law), in thicknesses of the thinnest
# layer. Why: the bound by the softest layer is loose for a thin soft film (up to ~850 h for
# 20 MPa / 150 nm, beyond the layered solver's ~525 h, where it raised and lost the whole
# analysis), and a table's cost grows like (a/h)²-³: measured for that film, 0.27 s up to
# 50 h, 0.74 s to 100 h, 1.7 s to 150 h, 38 s to 500 h (review R31f). A fit that needs radii
# beyond it is withheld, as it was before the widening.
_WIDE_REACH = 100.0
# γ bound of the coated fit, J/m² (as paper 2's model: the checks flag γ above 10 J/m²).
_GAMMA_MAX = 1e3


def as_coating(value, option: str = "coating") -> Coating | None:
    """The :class:`Coating` of ``value``: None, a Coating, one (material, thickness_m) pair or
    a sequence of them (top first).

    Parameters
    ----------
    value : None, Coating, pair or sequence of pairs
        The film(s), thicknesses in m.
    option : str
        The option or argument the value came from, named by the error line (e.g.
        ``"--coating"`` for a command's, ``"AnalysisSettings(coating=...)"``).

    Raises
    ------
    ContactresInputError
        One line naming ``option``: a text (names are read by the command line,
        :func:`contactres.jobs.contact.parse_coating`), something not a material, or a
        thickness outside (0, :data:`contactres.layered.MAX_THICKNESS_M`] (the one rule of
        every layered input, :func:`contactres.layered.checked_thickness`).
    """
    if value is None or isinstance(value, Coating):
        return value
    if isinstance(value, str):
        raise ContactresInputError(
            f"coating ({option}) {value!r}: give (material, thickness_m) pairs, e.g. "
            "(contactres.pmma(), 250e-9); contactres.jobs.contact.parse_coating('pmma:250e-9') "
            "makes them from text"
        )
    pairs = [value] if _is_pair(value) else list(value) if isinstance(value, Sequence) else None
    if not pairs or not all(_is_pair(p) for p in pairs):
        raise ContactresInputError(
            f"coating ({option}) must be a (material, thickness_m) pair or a sequence of them, "
            f"got {value!r}"
        )
    layers = []
    for j, (m, h) in enumerate(pairs, start=1):
        layers.append((m, checked_thickness(h, f"coating thickness ({option}, layer {j})")))
    return Coating(tuple(layers))


def _is_pair(p) -> bool:
    return (
        isinstance(p, (tuple, list))
        and len(p) == 2
        and (isinstance(p[0], Material) or callable(getattr(p[0], "at", None)))
        and isinstance(p[1], (int, float, np.floating, np.integer))
    )


def fit_coated(law: CoatedLaw, force, kappa, radius: float, start: dict, gamma_max: float):
    """Fit κ(F_N) with the coated law (E and γ free); a :class:`~contactres.fitting.FitResult`."""
    return fit(
        law.model(gamma_max),
        np.asarray(force, dtype=float),
        np.asarray(kappa, dtype=float),
        start={"E": float(np.clip(start["E"], *law.bounds)), "gamma": float(start["gamma"])},
        fixed={"radius": float(radius), "poisson": law.poisson},
    )


def load_law(law: CoatedLaw, start: dict) -> LoadLaw:
    """The :class:`~contactres.analysis._jkr.LoadLaw` of ``law`` (fits started at ``start``)."""

    def fit_(F, kappa, R, nu):
        return fit_coated(law, F, kappa, R, start, _GAMMA_MAX)

    def resampled(F, kappa, W, R, nu, res):
        return resampled_coated(law, F, kappa, W, R, res, _GAMMA_MAX)

    return LoadLaw(law.model(_GAMMA_MAX), fit_, resampled)


def _frequency(sweeps) -> float:
    """The one overtone frequency of a group's used sweeps, Hz."""
    f = np.unique(sweeps["fundamental_Hz"].to_numpy(float) * sweeps["overtone"].to_numpy(float))
    if f.size != 1:
        raise ContactresInputError(
            "a coated plate (coating) needs one overtone frequency per configuration and "
            f"medium (the film's modulus depends on it), found {sorted(f.tolist())} Hz"
        )
    return float(f[0])


# The layered solutions of the table (3x3 recursions, Galerkin matrices of a few dozen unknowns)
# and the fits' small products: one BLAS thread (contactres._threads; several spun on a busy
# machine: 15 s of CPU instead of 4.5 s for the bundled example)
@one_blas_thread()
def apply_coating(groups, exp, sweeps, coating: Coating, bootstrap: int, seed: int, say=None):
    """Refit every group's κ(F_N) on the coated plate, in place; returns {key: CoatedLaw}.

    ``groups``: the records of :func:`~contactres.analysis._jkr.fit_group` with paper 2's law
    (their E, γ start the coated fits and set the table's ranges); ``exp``: the per-experiment
    points; ``sweeps``: the used sweeps. Each record's fit fields are replaced by the coated
    fit's, and ``coating`` records the film, the uncoated E and γ, the table and, at each load,
    the contact radius, κ on the coated plate and on the bare one (same E, γ and load) and
    ``film_share`` = 1 − κ/κ_bare (the share of the tangential contact stiffness the film
    takes, as ``contactres contact`` reports it for the normal stiffness; every measured load,
    :func:`_film_share`). A group whose uncoated fit is withheld is not refitted (its E stays
    withheld). A fit that needs contact radii outside the table at loads it used is refitted
    once on a wider table (:func:`_wider_law`; the group's law and ``table_*`` are then that
    table's) and withheld if it still needs them (:func:`_outside_the_table`).
    """
    say = say or (lambda step: None)
    fitted = [g for g in groups if np.isfinite(g["E_Pa"])]
    todo: dict = {}
    for g in fitted:
        key = (g["configuration"], g["medium"])
        part = exp[(exp["configuration"] == key[0]) & (exp["medium"] == key[1])]
        mine = sweeps[(sweeps["configuration"] == key[0]) & (sweeps["medium"] == key[1])]
        F = part["normal_force_N"].to_numpy(float)
        R, nu = g["sphere_radius_m"], g["poisson"]
        e_star = g["E_Pa"] / (2 * (1 - nu**2))
        a = jkr_contact_radius(e_star, R, F[F > 0], g["gamma_J_m2"])
        todo[key] = (g, part, mine, (nu, _frequency(mine)), (np.min(a), np.max(a)))
    laws: dict = {}
    for spec in dict.fromkeys(v[3] for v in todo.values()):
        members = [v for v in todo.values() if v[3] == spec]
        E0 = [v[0]["E_Pa"] for v in members]
        E_range = (min(E0) * _E_WINDOW[0], max(E0) * _E_WINDOW[1])
        a_range = (
            min(v[4][0] for v in members) * _A_WINDOW[0],
            max(v[4][1] for v in members) * _A_WINDOW[1],
        )
        say(f"coated plate: tabulating {coating.label} (ν = {spec[0]:g}, {spec[1]:.4g} Hz)")
        laws[spec] = build_law(coating, spec[0], spec[1], E_range, a_range)
    out = {}
    for key, (g, part, mine, spec, _) in todo.items():
        say(f"JKR fit on the coated plate: {key[0]}, {key[1]}")
        law = laws[spec]
        uncoated = {k: g[k] for k in ("E_Pa", "E_err_Pa", "gamma_J_m2", "gamma_err_J_m2")}
        start = {"E": g["E_Pa"], "gamma": g["gamma_J_m2"]}
        new = fit_group(part, key, bootstrap, seed, mine, law=load_law(law, start))
        # The contact radii at the measured loads: the test of the table's range and the
        # per-load record below (one solve for both).
        radii = _radii(law, new, part)
        wide = (
            _wider_law(law, new, uncoated, radii) if radii and (radii[2] & radii[3]).any() else None
        )
        if wide is not None:
            # The window assumed coated radii near the uncoated ones (an elastic film); a film
            # soft in the static contact and stiff at the overtone needs larger ones: once,
            # on the table of the radii the film can give, within its reach (_wider_law).
            say(f"coated plate: re-tabulating {coating.label} for a wider range of contact radii")
            law = wide
            new = fit_group(part, key, bootstrap, seed, mine, law=load_law(law, start))
            radii = _radii(law, new, part)
        if radii:
            _outside_the_table(law, new, radii)
        g.update(new)
        g["coating"] = {
            **coating.record(),
            "frequency_Hz": law.frequency,
            "uncoated": uncoated,
            "table_E_range_Pa": list(law.bounds),
            "table_contact_radius_range_m": list(law.radius_range),
            "loads": _film_share(law, g, radii) if radii and np.isfinite(g["E_Pa"]) else [],
        }
        out[key] = law
    return out


def _radii(law: CoatedLaw, out: dict, part) -> tuple | None:
    """(the distinct measured loads F, N; a(F), m, at the fit's E, γ and R; the mask of the
    radii clamped to the table; the mask of the loads the fit used), or None
    for a withheld fit. A load whose every point has κ <= 0 (or not finite) was left out of
    the fit (:func:`~contactres.analysis._jkr.fit_group`): where its radius lies says nothing
    of the fit."""
    if not np.isfinite(out["E_Pa"]):
        return None
    F = np.unique(part["normal_force_N"].to_numpy(float))
    a, clamped = law.contact_radius(F, out["E_Pa"], out["gamma_J_m2"], out["sphere_radius_m"])
    used = part["normal_force_N"].to_numpy(float)[
        fitted_points(part["kappa_N_per_m"].to_numpy(float))
    ]
    return F, a, clamped, np.isin(F, used)


def _wider_law(law: CoatedLaw, out: dict, uncoated: dict, radii: tuple) -> CoatedLaw | None:
    """The table rebuilt over the contact radii the film can give at the loads the fit used
    (up to :data:`_WIDE_REACH` thicknesses of its thinnest layer), or None if that is no
    wider than ``law``'s (the fit is then withheld as it is).

    The bound: the layered plate is no softer than a half-space of its softest static layer
    (substrate or film) and no stiffer than one of its stiffest, and the softer of two
    homogeneous pairs has the larger radius at a load (paper 2's Eq. 9: a³ ∝ 1/E* at fixed γ,
    and a grows with γ). So the radii lie between the Hertz radius (γ = 0) of the stiffest
    pair at the smallest used load and the JKR radius of the softest pair at the largest, E
    over the table's range (the fit's bound: the sphere and the substrate share E) and γ the
    larger of the uncoated and the clamped fit's (the refit's γ may exceed both: a test
    measured 0.212 J/m² against 0.200, inside the bound only because it is loose). The
    layered plate between the two half-spaces is the argument, not a proof (a reviewer's
    probe of seven films, loads 10 µN-30 mN, γ 0.1-10 J/m², found both ends held), and the
    refit's γ is not known before it: a radius still outside after the refit withholds the
    fit. Bounded by the softest layer,
    the table stays small: the study of tests/analysis/test_coating.py (loads 2-30 mN, E
    70 GPa) with 2 µm of a film of 2 GPa (static) and 8 GPa (overtone) needs 1.54x the
    uncoated radius at 30 mN, beyond the first table (1.5x); the bound gives 2.5x, a table of
    11 radii (a/h 1.4-13) after the first's 8 (a/h 1.9-7.7) (measured: 0.13-0.15 s more CPU
    for the group, the table and the refit: 0.40 s against 0.26 s withheld on the first
    table, three alternated pairs). A table's cost grows with its number of radii (15 a
    decade below 4 thicknesses, 5 above, build_law) and steeply with its largest radius over
    the thickness (:data:`_WIDE_REACH`)."""
    F = radii[0][radii[3] & (radii[0] > 0)]
    if not F.size:
        return None
    nu, R = law.poisson, out["sphere_radius_m"]
    films = [float(np.real(indentation_modulus(static_solid(m)))) for m, _ in law.coating.layers]
    E_lo, E_hi = (E / (1 - nu**2) for E in law.bounds)  # plane-strain moduli of the substrate
    soft = 1 / (1 / E_lo + 1 / min(E_lo, *films))
    stiff = 1 / (1 / E_hi + 1 / max(E_hi, *films))
    gamma = max(uncoated["gamma_J_m2"], out["gamma_J_m2"])
    lo = float(jkr_contact_radius(stiff, R, F.min(), 0.0))
    hi = float(jkr_contact_radius(soft, R, F.max(), gamma))
    a_lo, a_hi = law.radius_range
    reach = _WIDE_REACH * min(float(h) for _, h in law.coating.layers)
    hi = min(hi, max(reach, a_hi))  # (never below the first table's top)
    # (1e-9: the table's ends are exp(ln a), a rounding away from the radii they were made of)
    if lo >= a_lo * (1 - 1e-9) and hi <= a_hi * (1 + 1e-9):
        return None
    return build_law(
        law.coating,
        nu,
        law.frequency,
        law.bounds,
        (min(lo, a_lo), max(hi, a_hi)),
        n_E=law.E_nodes.size,
    )


def _outside_the_table(law: CoatedLaw, out: dict, radii: tuple) -> None:
    """Withhold a coated fit (in place, check ``fit-at-bound``) whose contact radius at a
    load it used lies outside the table's radii: the model was clamped there, not solved
    (``radii``: :func:`_radii`)."""
    clamped = radii[2] & radii[3]
    if not clamped.any():
        return
    lo, hi = law.radius_range
    out["rejected_fit"] = {"E_Pa": out["E_Pa"], "gamma_J_m2": out["gamma_J_m2"]}
    out["checks"] = [*out["checks"], "fit-at-bound"]
    text = (
        f"the coated fit needs contact radii outside its table ({lo:.3g}-{hi:.3g} m) at "
        f"{int(clamped.sum())} load(s): E and γ withheld"
    )
    out["note"] = "; ".join(t for t in (out["note"], text) if t)
    for key in ("E_Pa", "E_err_Pa", "gamma_J_m2", "gamma_err_J_m2"):
        out[key] = math.nan


def _film_share(law: CoatedLaw, g: dict, radii: tuple) -> list[dict]:
    """Per load: a, κ on the coated and the bare plate and the film's share (apply_coating);
    ``radii``: :func:`_radii` at the group's E, γ and R. Every measured load is listed, also
    one the fit left out (κ <= 0: its κ on the bare plate, and a, κ and the share where its
    radius is inside the table); a radius outside the table (at such a load only: one at a
    load the fit used withholds the fit) has NaN a, κ and share, not the clamped values."""
    F, a, clamped, _ = radii
    E, gamma, R, nu = g["E_Pa"], g["gamma_J_m2"], g["sphere_radius_m"], g["poisson"]
    kappa = law.tangential(E, a)
    bare = np.asarray(kappa_jkr_mindlin(F, E, gamma, R, nu), dtype=float)
    return [
        {
            "normal_force_N": float(f),
            "contact_radius_m": float(r) if not c else math.nan,
            "kappa_N_per_m": float(k) if not c else math.nan,
            "kappa_bare_N_per_m": float(b),
            "film_share": float(1 - k / b) if not c else math.nan,
        }
        for f, r, k, b, c in zip(F, a, kappa, bare, clamped, strict=True)
    ]
