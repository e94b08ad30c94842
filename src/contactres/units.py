"""Ranges and magnitudes that decide whether a number is physical: every such rule lives here once.

The reader, the validator and the analysis all take their limits from this module, so that a rule
(for example the small-load limit of paper 2, Eq. 1) cannot disagree between two places.

The second half holds the plausible magnitude of every physical quantity a user types
(:data:`QUANTITIES`) and :func:`check_magnitude`, the one check behind every command-line option
that takes a length, force, modulus, area, ...: a value outside its range is refused in one line
that names the option, the value as typed and the range, and says which unit slip it looks like
("20" typed for an amplitude in metres looks like nanometres).

This module needs only the standard library (no numpy): the command line imports it while it
parses its options.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType

from .errors import ContactresInputError

__all__ = [
    "ABSOLUTE_FREQUENCY_FRACTION",
    "HERTZ_APPROXIMATE_RATIO",
    "HERTZ_MAX_RATIO",
    "JUNCTION_SIGMAS",
    "LINEAR_ONSET_X",
    "MAX_AMPLITUDE_M",
    "MAX_MU",
    "MIN_AMPLITUDE_M",
    "MIN_SWEEP_POINTS",
    "POISSON_OPEN_RANGE",
    "QUANTITIES",
    "SMALL_LOAD_LIMIT",
    "Plausible",
    "check_magnitude",
    "format_number",
    "unit_slip",
]

#: ``|Δf|``/f above which the small-load approximation (paper 2, Eq. 1) is questioned.
SMALL_LOAD_LIMIT = 1e-3

#: Largest plausible QCM oscillation amplitude, m. Contact-resonance ramps reach tens of nm; 1 µm
#: would wreck the resonator, so a larger value means the column holds nanometres, not metres.
MAX_AMPLITUDE_M = 1e-6

#: Smallest plausible non-zero QCM oscillation amplitude, m: 0.1 pm lies below what any QCM
#: resolves (amplitude ramps start at tens of pm), so a smaller value means metres typed in a
#: column of nanometres (5e-10 "nm" is 5e-19 m), not a measurement.
MIN_AMPLITUDE_M = 1e-13

#: Contact radius over sphere radius, a/R, above which a contact is flagged as approximate:
#: Hertz's theory (and the anisotropic and layered contacts built on it) takes the sphere as a
#: paraboloid on a half-space in small strain, good for a ≪ R (K. L. Johnson, *Contact
#: Mechanics*, Cambridge University Press (1985), §4.2: a/R ≲ 0.1). Its values are kept (at
#: a/R = 0.24, a CR-AFM tip's usual contact, the paraboloid's gap at the contact edge is 1.5 %
#: below the sphere's) and flagged.
HERTZ_APPROXIMATE_RATIO = 0.1

#: a/R above which a contact gets no values: the paraboloid's gap at the edge is 7 % below the
#: sphere's at a/R = 0.5 (and the depth a²/R a quarter of the radius), no longer a small-contact
#: answer; most likely a radius or a force typed in the wrong unit (issue 30: R = 20 nm and F =
#: 1 N gave a/R = 24 and p0 = 2 TPa).
HERTZ_MAX_RATIO = 0.5

#: A shift above this fraction of the fundamental is an absolute frequency, not a shift.
ABSOLUTE_FREQUENCY_FRACTION = 0.1

#: Open interval of the Poisson ratio of an isotropic solid (positive definite stiffness).
POISSON_OPEN_RANGE = (-1.0, 0.5)

#: Fewest points a sweep needs to take part in the analysis (a straight line with two
#: parameters per channel and an estimate of the noise needs at least four).
MIN_SWEEP_POINTS = 4

#: A Δf slope more than this many standard errors above zero means that Δf rises with the
#: amplitude (the junction grows), which no partial-slip loop does.
JUNCTION_SIGMAS = 2.0

#: The largest κu0/(μF_N) of a Cattaneo-Mindlin sweep up to which the slopes of paper 2's
#: Eq. 12 give μ within ~10 %: a straight line fitted to the exact loop on 13 amplitudes from
#: 5 % to 100 % of the largest reads μ 6 % low from the Δf slope and 9 % low from the ΔΓ slope
#: at 0.5 (tests/analysis/test_blocks.py recomputes it from the forward model).
LINEAR_ONSET_X = 0.5

#: The largest friction coefficient reported as one. Clean metals in vacuum, where adhesion
#: dominates, reach μ of a few to ~10; above that the number is a wrong input (a normal force
#: per resonator for one per contact, an area in mm²), not a coefficient (issue 27: μ above 50
#: was printed).
MAX_MU = 10.0


def _poisson_in_range(nu: float) -> bool:
    """True if ``nu`` lies strictly inside :data:`POISSON_OPEN_RANGE`."""
    lo, hi = POISSON_OPEN_RANGE
    return lo < nu < hi


#: Largest normalised wave number k a taken from a user: 30 times paper 1's range (k_l a <= 2).
#: The DCSF kernels end near it too (k_s a x T1 < 60, dynamic/_normal_stiffness.py), at a
#: material-dependent point that the library checks itself.
_MAX_KA = 60.0

# Unit slips: (factor to SI, unit symbol, unit in words). A value outside its range whose product
# with a factor falls inside looks typed in that unit. Lengths and forces are typed too large
# (in nm, µm, mm, µN, ...), moduli, frequencies and stiffnesses too small (in GPa, MHz, N/nm).
# Each quantity lists only the slips that can be the suggestion (tests/test_units.py checks it):
# e.g. a force typed in mN is either inside the range or nearer the typical force read as µN.
_MM = (1e-3, "mm", "millimetres")
_UM = (1e-6, "µm", "micrometres")
_NM = (1e-9, "nm", "nanometres")
_MPA = (1e6, "MPa", "megapascals")
_GPA = (1e9, "GPa", "gigapascals")


def format_number(x: float) -> str:
    """``x`` to 6 significant digits, powers of ten as a bare exponent.

    ``2e-8``, ``1.657e11``, ``1e5``, ``20``, ``0.005``: plain between 1e-3 and 1e4, where a
    number reads best without an exponent.
    """
    v = float(x)
    if v == 0 or not math.isfinite(v) or 1e-3 <= abs(v) < 1e4:
        return f"{v:.6g}"
    mantissa, _, exponent = f"{v:.5e}".partition("e")
    mantissa = mantissa.rstrip("0").rstrip(".")
    return f"{mantissa}e{int(exponent)}"


@dataclass(frozen=True)
class Plausible:
    """The plausible magnitudes of one physical quantity, in SI units.

    Attributes
    ----------
    name : str
        What the quantity is, for messages ("sphere radius").
    unit : str
        SI unit ("" for a dimensionless number).
    lo, hi : float
        The plausible range; ``lo_open``/``hi_open`` exclude the bound itself.
    typical : float
        A common value (> 0, in ``unit``): when several unit slips land inside the range, the
        suggestion is the one nearest to it (on a log scale).
    slips : tuple of (float, str, str)
        The unit slips to look for: (factor to SI, unit symbol, unit in words).
    """

    name: str
    unit: str
    lo: float
    hi: float
    typical: float
    slips: tuple[tuple[float, str, str], ...] = ()
    lo_open: bool = False
    hi_open: bool = False

    def accepts(self, value, *, allow_zero: bool = False, signed: bool = False):
        """True where ``value`` lies in the range (NaN never does).

        Works element-wise on numpy arrays too (only comparisons, ``abs``, ``&`` and ``|``).
        ``allow_zero`` also accepts exactly 0 (an unloaded contact, a zero amplitude);
        ``signed`` checks the magnitude and accepts either sign (the cubic constant C12).
        """
        v = abs(value) if signed else value
        above = (v > self.lo) if self.lo_open else (v >= self.lo)
        below = (v < self.hi) if self.hi_open else (v <= self.hi)
        inside = above & below
        return (inside | (value == 0)) if allow_zero else inside

    def describe(self, *, allow_zero: bool = False, signed: bool = False) -> str:
        """The rule in words: ``the sphere radius lies in [1e-9, 1] m``."""
        bounds = (
            f"{'(' if self.lo_open else '['}{format_number(self.lo)}, "
            f"{format_number(self.hi)}{')' if self.hi_open else ']'}"
        )
        text = f"the {self.name} lies in {'±' if signed else ''}{bounds}"
        text = f"{text} {self.unit}" if self.unit else text
        return f"{text} or is 0" if allow_zero and not self.accepts(0.0) else text


# Each range spans the quantity in every experiment the package models, with a margin of about
# ten on either side: wide enough never to refuse a real value, narrow enough that a value typed
# in the wrong unit (a factor 1e3 or more) falls outside. The comment gives each range's reason.
QUANTITIES = MappingProxyType(
    {
        # u0 = 0 is the low-amplitude limit; MAX_AMPLITUDE_M above says why 1 µm is the top.
        "amplitude": Plausible(
            "oscillation amplitude", "m", 0.0, MAX_AMPLITUDE_M, 1e-8, (_MM, _UM, _NM)
        ),
        # A tangential displacement of a loop (e.g. the critical displacement d_c of paper 2's
        # plateau) is compared with u0, so it shares the amplitude's range.
        "displacement": Plausible(
            "tangential displacement", "m", 0.0, MAX_AMPLITUDE_M, 1e-9, (_MM, _UM, _NM)
        ),
        # A sphere pressed on a sample in a forward model (contact, dcsf, rum invert): from the
        # sharpest AFM tips (a few nm; below 1 nm there is no continuum sphere) to a 1 m sphere,
        # beyond any indenter.
        "sphere_radius": Plausible("sphere radius", "m", 1e-9, 1.0, 1e-4, (_MM, _UM, _NM)),
        # The sphere of a QCM contact experiment (paper 2: R = 1.1 mm): a sphere wider than a
        # few cm cannot sit on a 14-25 mm crystal, so 5 cm is the top (issue 30: R = 0.6, a
        # radius in mm typed as m, passed and gave E = 1.9 GPa for glass).
        "qcm_sphere_radius": Plausible(
            "sphere radius on the resonator", "m", 1e-9, 5e-2, 1e-3, (_MM, _UM, _NM)
        ),
        # A particle on a QCM-D crystal: colloids, vesicles, cells, ~10 nm to ~100 µm, with a
        # margin of ten below and fifty above (5 mm); mm spheres are `qcm analyze`'s route.
        # A radius in mm typed as m would already lie inside for any particle below 5 mm,
        # so only µm and nm are slips.
        "particle_radius": Plausible("particle radius", "m", 1e-9, 5e-3, 1e-6, (_UM, _NM)),
        # An AFM tip: sharp tips of a few nm to colloidal probes of ~50 µm, with a margin of
        # twenty (1 mm). As for particles, a tip in mm typed as m is never the nearest slip.
        "tip_radius": Plausible("tip radius", "m", 1e-9, 1e-3, 3e-8, (_UM, _NM)),
        # From one interatomic spacing (0.1 nm) to the largest sphere radius: a contact cannot
        # be wider than its sphere.
        "contact_radius": Plausible("contact radius", "m", 1e-10, 1.0, 1e-6, (_UM, _NM)),
        # The step of an orientation map: ~1 nm (transmission Kikuchi diffraction) to 1 mm
        # (a coarse overview scan), with a margin of ten: a step typed in µm as a plain number
        # (0.5 for 0.5 µm) is read as 0.5 m and refused.
        "pixel_size": Plausible("pixel size", "m", 1e-10, 1e-2, 1e-6, (_MM, _UM, _NM)),
        # 1 pN (an AFM single-asperity contact) to 1 kN (a 100 kg load on one sphere).
        "force": Plausible(
            "normal force per contact",
            "N",
            1e-12,
            1e3,
            1e-3,
            ((1e-6, "µN", "micronewtons"), (1e-9, "nN", "nanonewtons")),
        ),
        # Elastic constants and moduli of solids: soft rubbers and gels (~1 MPa, /10) to diamond
        # (C11 = 1.08 TPa, x10). Crystal constants are quoted in GPa: the typical slip.
        "modulus": Plausible("elastic modulus", "Pa", 1e5, 1e13, 1e11, (_MPA, _GPA)),
        # The indentation modulus of a sample found from a contact stiffness: soft gels (~1e5
        # Pa) to a little beyond diamond (M ~ 1.2e12 Pa); beyond that the stiffness or the
        # Hertz inputs (load, tip radius) were given in the wrong unit.
        "sample_modulus": Plausible("indentation modulus of the sample", "Pa", 1e5, 1.5e12, 1e10),
        # Interfacial shear strength τ0 (paper 2, Eq. 13): from soft gels (~kPa, /10) to the
        # ideal shear strength of diamond (~1e11 Pa, about G/5).
        "stress": Plausible("interfacial shear stress", "Pa", 1e2, 1e11, 1e7, (_MPA, _GPA)),
        # Contact stiffness κ: a soft AFM cantilever's 0.01 N/m (/10) to ~8 G a of a cm-wide
        # diamond contact (~1e11 N/m, x10). Only N/nm is a detectable slip: a value in N/µm
        # or N/mm read as N/m mostly stays inside this wide range.
        "stiffness": Plausible(
            "contact stiffness",
            "N/m",
            1e-3,
            1e12,
            1e5,
            ((1e9, "N/nm", "N/nm"),),
        ),
        # A cantilever's spring constant k_c (at the free end, 3EI/L³): contact-mode levers of
        # ~0.01 N/m and CR-AFM levers of 1-50 N/m, with a margin of ten (1e-3 to 1e3 N/m). It
        # is not a contact stiffness: a value of 1e5 N/m is a contact's k*, not any lever's.
        "lever_stiffness": Plausible("cantilever spring constant", "N/m", 1e-3, 1e3, 1.0),
        # μ = 0 has no loop (no sliding force); clean metals in vacuum reach μ ~ 5-10, so 50 is
        # beyond any measured friction.
        "friction": Plausible("friction coefficient", "", 0.0, 50.0, 0.5, lo_open=True),
        # ξ = 0 is no dashpot. The top keeps the loss stiffness ωξ at 1 MHz below the stiffest
        # contact (2π 1e6 s^-1 x 1e5 kg/s ~ 6e11 N/m).
        "drag": Plausible("dashpot drag coefficient", "kg/s", 0.0, 1e5, 1e-3),
        # Aerogels and foams (~100 kg/m³) to osmium (22 590 kg/m³) with a margin; a density
        # typed in g/cm³ is a thousand times too small.
        "density": Plausible(
            "density", "kg/m^3", 1e2, 3e4, 5e3, ((1e3, "g/cm^3", "grams per cm^3"),)
        ),
        # Resonance frequencies: AFM cantilevers (kHz) to thin-film bulk acoustic resonators
        # (~10 GHz). QCM fundamentals (5-10 MHz) are typed in MHz: the typical slip.
        "frequency": Plausible(
            "resonance frequency",
            "Hz",
            1e3,
            1e10,
            5e6,
            ((1e3, "kHz", "kilohertz"), (1e6, "MHz", "megahertz"), (1e9, "GHz", "gigahertz")),
        ),
        # QCM electrode areas: 0.1 mm x 0.1 mm (resonator arrays) to 10 cm x 10 cm; areas are
        # quoted in cm² or mm², typed as m² they are 1e4 or 1e6 times too large.
        "area": Plausible(
            "electrode area",
            "m^2",
            1e-8,
            1e-2,
            1e-5,
            (
                (1e-4, "cm^2", "square centimetres"),
                (1e-6, "mm^2", "square millimetres"),
                (1e-12, "µm^2", "square micrometres"),
            ),
        ),
        # The piezoelectric strain constant d26 of AT-cut quartz, 3.1 pm/V (Johannsmann et al.
        # 2021), with a margin of thirty either side; it is quoted in pm/V: the typical slip.
        "piezo_constant": Plausible(
            "piezoelectric constant d26", "m/V", 1e-13, 1e-10, 3.1e-12, ((1e-12, "pm/V", "pm/V"),)
        ),
        # An amplitude per drive volt measured on a QCM: from d26-like 0.1 pm/V to 10 µm/V, far
        # beyond any crystal's (u0 = 4 d26 Q U/(nπ)² reaches ~10 nm/V at Q = 1e5).
        "amplitude_calibration": Plausible("amplitude calibration u0/U", "m/V", 1e-13, 1e-5, 1e-9),
        # The reference impedance Z0 of an S11 measurement: 50 Ω (or 75 Ω), with a wide margin.
        "reference_impedance": Plausible("reference impedance Z0", "ohm", 1e-3, 1e6, 50.0),
        # Acoustic impedance of a resonator's material: soft polymers (~1e6, /10) to tungsten
        # (~1e8, x10); AT-cut quartz has 8.8e6 kg m^-2 s^-1 = 8.8 MRayl.
        "impedance": Plausible(
            "acoustic impedance",
            "kg m^-2 s^-1",
            1e5,
            1e9,
            8.8e6,
            ((1e3, "kRayl", "kilorayl"), (1e6, "MRayl", "megarayl")),
        ),
        # Zener ratio A = 2 C44/(C11 - C12): known cubic crystals lie within ~0.2..10 (1 is
        # isotropic); two decades either side of 1 covers them with room.
        "zener": Plausible("Zener ratio", "", 1e-2, 1e2, 1.0),
        # ν = C12/(C11 + C12): positive definite stiffness (see POISSON_OPEN_RANGE).
        "poisson": Plausible(
            "Poisson ratio", "", *POISSON_OPEN_RANGE, 0.3, lo_open=True, hi_open=True
        ),
        # Loss factor Q^-1 of C (1 + i Q^-1): 0 is the lossless limit; the DCSF kernels assume
        # a loss below 1 (the lossiest rubbers have tan δ ~ 1).
        "loss": Plausible("loss factor Q^-1", "", 0.0, 1.0, 0.02, hi_open=True),
        # k a >= 0; _MAX_KA above says why it ends there.
        "ka": Plausible("normalised wave number k a", "", 0.0, _MAX_KA, 1.0),
        # Target relative accuracy of a quadrature: below 1e-10 round-off wins, at 1 it means
        # nothing.
        "rtol": Plausible("relative tolerance", "", 1e-10, 1.0, 1e-6, hi_open=True),
        # Relative disagreement of κ between cantilever modes tolerated before a flag: below
        # 1e-4 no lever model holds, above 1 (100 %) the check means nothing.
        "mode_tolerance": Plausible("mode tolerance", "", 1e-4, 1.0, 0.05),
        # QCM overtone order n: measured up to ~13; 999 keeps n f_F inside the frequency range.
        "overtone": Plausible("overtone order", "", 1.0, 999.0, 3.0),
        # Number of equal contacts under the electrode: 1 to a dense layer of 10 nm particles on
        # 1 cm² (~1e12).
        "contacts": Plausible("number of contacts", "", 1.0, 1e12, 1.0),
    }
)
"""Plausible magnitude of every physical quantity a user types, by name (read-only)."""


def _quantity(quantity: str) -> Plausible:
    try:
        return QUANTITIES[quantity]
    except KeyError:
        raise ContactresInputError(
            f"unknown quantity {quantity!r}: use one of {', '.join(QUANTITIES)}"
        ) from None


def unit_slip(quantity: str, value: float, *, signed: bool = False) -> str | None:
    """The unit slip ``value`` looks like, in words, or None.

    A slip is a unit of :attr:`Plausible.slips` in which ``value``, itself outside the range,
    lands inside; of several, the one nearest to the typical value (on a log scale). Example:
    ``unit_slip("amplitude", 20)`` gives ``"nanometres (20 nm = 2e-8 m)"``.

    Parameters
    ----------
    quantity : str
        A key of :data:`QUANTITIES`.
    value : float
        The value as given, read as SI.
    signed : bool
        Judge the magnitude (either sign is plausible).
    """
    q = _quantity(quantity)
    v = float(value)
    if not math.isfinite(v) or v == 0 or q.accepts(v, signed=signed):
        return None  # a plausible value is taken as typed
    best = None
    for factor, symbol, words in q.slips:
        si = v * factor
        if q.accepts(si, signed=signed):
            distance = abs(math.log10(abs(si) / q.typical))
            if best is None or distance < best[0]:
                best = (
                    distance,
                    f"{words} ({format_number(v)} {symbol} = {format_number(si)} {q.unit})",
                )
    return None if best is None else best[1]


def check_magnitude(
    quantity: str,
    value: float | str,
    option: str,
    *,
    text: str | None = None,
    allow_zero: bool = False,
    signed: bool = False,
) -> float:
    """``value`` as a float, after checking that it is a plausible ``quantity`` in SI units.

    Parameters
    ----------
    quantity : str
        A key of :data:`QUANTITIES` ("sphere_radius", "force", "modulus", ...).
    value : float or str
        The value in SI units; a string is parsed (and is the value as typed): a plain number
        is SI, a number with its unit (``"1.1 mm"``) is converted to the quantity's SI unit
        (:func:`contactres.typed_units.to_si`, which refuses a unit of another kind).
    option : str
        Who gave the value, for the message (``"--radius"``).
    text : str, optional
        The value as the user typed it (default: ``value`` itself, or its number).
    allow_zero : bool
        Also accept exactly 0 where the range starts above it (an unloaded contact).
    signed : bool
        Check the magnitude and accept either sign (the cubic constant C12 may be negative).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        One line naming ``option``, the value as typed and the range with its unit: for a
        value that is not a number, not finite, negative where only >= 0 is physical, or outside
        the range; then also the unit slip it looks like (:func:`unit_slip`), if any.
    """
    q = _quantity(quantity)
    rule = q.describe(allow_zero=allow_zero, signed=signed)
    with_unit = False
    if isinstance(value, str):
        typed = value.strip() if text is None else text
        try:
            v = float(value)
        except ValueError:
            from .typed_units import has_unit, to_si

            if not has_unit(value):
                raise ContactresInputError(
                    f"{option} {value.strip()!r} is not a number: {rule}"
                ) from None
            v, with_unit = to_si(value, q.unit, option), True
            typed = f"{typed} (= {format_number(v)} {q.unit})".replace(" )", ")")
    else:
        v = float(value)
        typed = format_number(v) if text is None else text
    if q.accepts(v, allow_zero=allow_zero, signed=signed):
        return v
    if not math.isfinite(v):
        raise ContactresInputError(f"{option} {typed} is not a finite number: {rule}")
    if v < 0 and not signed and q.lo >= 0:
        raise ContactresInputError(f"{option} {typed} is negative: {rule}")
    message = f"{option} {typed} is outside the plausible range: {rule}"
    # A value typed with its unit has no unit slip to suggest: its unit was said.
    slip = None if with_unit else unit_slip(quantity, v, signed=signed)
    if slip is not None:
        message += f"; it looks like {slip}: check the unit of {option}"
    raise ContactresInputError(message)
