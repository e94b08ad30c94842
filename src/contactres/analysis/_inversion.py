"""Contact stiffness k* -> elastic modulus of the sample (contact-resonance / RUM inversion).

Three steps, all vectorised over the pixels of a map (arrays broadcast together):

1. (optional, ``dynamic=True``) Paper 1's dynamic correction. The resonance sees the dynamic
   contact stiffness K_da = K_sa × DCSF(k_l a) (paper 1, Eqs. 28-29); its real part is the
   stiffness that shifts the resonance (the imaginary part is radiation damping, which widens
   it), so the static stiffness is K_static = k*/Re DCSF. k_l = 2πf/c_l is the longitudinal wave
   number of the sample's face, c_l = √(Re C33/ρ) in the surface frame (the convention
   ``wavenumber="longitudinal"`` of :func:`contactres.dynamic.dcsf`), and a the contact radius.
   DCSF is evaluated with ``model="exact"`` (rigid flat punch), lossless (``loss=0``) unless
   told otherwise. The DCSF belongs to a rigid sphere on the sample: with a compliant tip,
   correcting the whole series stiffness overstates the (small) correction by at most the factor
   M_sample/E* (exact for a rigid tip).
2. Reduced modulus E* from the static stiffness, either

   * Hertz with known tip radius R and load P (K. L. Johnson, Contact Mechanics, Cambridge
     University Press 1985, Eqs. 4.22-4.23): K = 2aE*, a³ = 3PR/(4E*), so
     E* = √(K³/(6RP)); or
   * reference samples measured with the same tip and load (D. C. Hurley, "Contact resonance
     force microscopy techniques for nanomechanical measurements", in B. Bhushan, H. Fuchs
     (eds.), Applied Scanning Probe Methods XI, Springer 2009, pp. 97-138):
     E*_s = E*_ref (K_s/K_ref)^m, m = 3/2 (Hertz, default) or 1 (flat punch), or m fitted to two
     references, m = ln(E*_ref2/E*_ref1)/ln(K_ref2/K_ref1), then E*_s from reference 1. The
     reference's E*_ref = 1/(1/M_tip + 1/M_ref).

3. Tip compliance (series law): 1/E* = 1/M_tip + 1/M_sample, M_sample = 1/(1/E* − 1/M_tip);
   where 1/E* − 1/M_tip <= 0 the sample looks stiffer than the tip allows (check M_tip):
   M_sample is NaN and :attr:`ModulusFlag.TIP_LIMIT` is set.

Moduli of tip, sample and references are indentation moduli M (Pa): a number, or a
:class:`~contactres.materials.Material` already in its surface frame (z along the contact
normal), or a pair ``(material, (h, k, l))`` which is rotated here. M of a material is
:func:`contactres.normal.indentation_modulus` (paper 1, Eq. 4; isotropic:
M = E/(1 − ν²)). A silicon tip along [001]: ``tip=(Material.crystal("Si"), (0, 0, 1))``.

Contact radius a = K_static/(2E*) (for Hertz identical to (3PR/(4E*))^(1/3)); Hertz peak pressure
p0 = 3P/(2πa²) (Johnson Eq. 4.23) when the load P is known. p0 above ``hardness`` sets
:attr:`ModulusFlag.NOT_ELASTIC` (a flag, not a warning): the contact yields, k* is not elastic.

Size of the dynamic correction, Si(001), exact model, lossless (tests/analysis/test_inversion.py):
DCSF ≈ 1 − 0.298 (k_l a)² + 1.228i k_l a for small k_l a. ``|DCSF − 1|`` (dominated by the radiation
term) reaches 1e-3 at k_l a ≈ 8.1e-4, but the correction applied, ``|1/Re DCSF − 1|``, reaches 1e-3
only at k_l a ≈ 0.058. A 50 nm Si[001] tip on Si(001) (E* = M/2, M = 164.8 GPa, c_l = 8435 m/s) at 1
µN and 1 MHz has a ≈ 7.7 nm, k_l a ≈ 5.7e-6, ``|DCSF − 1|`` ≈ 7e-6 and ``|1/Re DCSF − 1|`` ≈ 1e-11:
negligible. It matters for µm-size contacts at MHz (paper 1's RUM: k_l a up to ~0.2).

Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", American Journal of Engineering and Applied Sciences 3(1), 56-63
(2010), doi:10.3844/ajeassp.2010.56.63.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from .._summary import Summarised, flagged, number, values
from ..errors import ContactresInputError
from ..units import QUANTITIES
from ..validation import nonnegative, positive

if TYPE_CHECKING:
    from ..materials import Material

__all__ = [
    "FLAG_DESCRIPTIONS",
    "ModulusFlag",
    "ModulusResult",
    "dcsf_values",
    "longitudinal_velocity",
    "modulus_from_contact_stiffness",
    "modulus_of",
    "surface_material",
]


class ModulusFlag(enum.IntFlag):
    """Bits of :attr:`ModulusResult.flags` (0: nothing to report)."""

    TIP_LIMIT = enum.auto()
    NOT_ELASTIC = enum.auto()
    NOT_HERTZIAN = enum.auto()
    MODULUS_OUT_OF_RANGE = enum.auto()
    NO_SPRING_CONSTANT = enum.auto()


#: What each flag means.
FLAG_DESCRIPTIONS = MappingProxyType(
    {
        ModulusFlag.TIP_LIMIT: (
            "1/E* - 1/M_tip <= 0: the sample looks stiffer than the tip allows (check the tip "
            "modulus); M_sample is NaN"
        ),
        ModulusFlag.NOT_ELASTIC: (
            "the Hertz peak pressure exceeds the hardness: the contact yields, k* is not elastic"
        ),
        ModulusFlag.NOT_HERTZIAN: (
            "the contact radius a = k*/(2E*) exceeds the tip radius: no sphere contact (Hertz "
            "needs a << R), most likely an input in the wrong unit (load_N in µN, tip_radius_m "
            "in nm, k_c); E* and M_sample are NaN"
        ),
        ModulusFlag.MODULUS_OUT_OF_RANGE: (
            "M_sample outside the plausible range of contactres.units (0.1 MPa to 1.5 TPa): "
            "an input in the wrong unit, not a result; E* and M_sample are NaN"
        ),
        ModulusFlag.NO_SPRING_CONSTANT: (
            "k_c_N_per_m is blank or its column is missing: only κ = k*/k_c is known; k* and "
            "the Hertz modulus need the lever's spring constant (a reference sample does not)"
        ),
    }
)

#: Largest number of fixed-point steps of the dynamic correction (a depends on E*, E* on the
#: corrected stiffness). A step shrinks the error of K_static by ~0.3 (k_l a)² (Hertz: a ∝ K^-1/2,
#: Re DCSF − 1 ≈ −0.3 (k_l a)² on Si(001)); the loop stops once K_static changes by less than
#: :data:`DYNAMIC_RTOL` (two steps at k_l a ~ 1e-5, four at 0.2).
DYNAMIC_ITERATIONS = 8

#: Relative change of K_static at which the dynamic fixed point is taken as converged.
DYNAMIC_RTOL = 1e-13

#: Default largest number of distinct k a values evaluated directly per step (above it: the
#: Chebyshev interpolation of :func:`contactres.dynamic.dcsf`).
DCSF_GRID = 48


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the maps.
@dataclass(frozen=True, repr=False)
class ModulusResult(Summarised):
    """Moduli from contact stiffness, per pixel (arrays of the broadcast input shape).

    Attributes
    ----------
    E_star : reduced modulus E*, Pa
    M_sample : indentation modulus of the sample, Pa (NaN where flagged TIP_LIMIT)
    contact_radius : a = K_static/(2E*), m
    peak_pressure : Hertz p0 = 3P/(2πa²), Pa (NaN without a load)
    k_a : k_l a, longitudinal wave number of the sample face times a (NaN without frequency
        and sample)
    dcsf : the DCSF applied (complex; 1 where no dynamic correction was made)
    k_static : the static contact stiffness K_static = k*/Re DCSF, N/m
    flags : bit mask of :class:`ModulusFlag` (int array)
    method : "hertz" or "reference (m = ...)", with "+ dynamic" when corrected
    exponent : the exponent m of the reference method (1.5 for Hertz)
    tip_modulus : M_tip used, Pa (inf: rigid tip)
    """

    E_star: np.ndarray
    M_sample: np.ndarray
    contact_radius: np.ndarray
    peak_pressure: np.ndarray
    k_a: np.ndarray
    dcsf: np.ndarray
    k_static: np.ndarray
    flags: np.ndarray
    method: str
    exponent: float | np.ndarray
    tip_modulus: float

    def _facts(self) -> list[tuple[str, str]]:
        """The method, E* and M (GPa), a (nm), the flagged pixels and the tip modulus."""
        return [
            ("", self.method),
            ("E*", values(self.E_star, "GPa", 1e9)),
            ("M", values(self.M_sample, "GPa", 1e9)),
            ("a", values(self.contact_radius, "nm", 1e-9)),
            ("flagged", flagged(self.flags)),
            ("M_tip", number(self.tip_modulus, "GPa", 1e9)),
        ]


def surface_material(spec, name: str) -> Material:
    """A Material in its surface frame from a Material or a (Material, (h, k, l)) pair."""
    # Imported here, as in modulus_of and longitudinal_velocity: a table of numbers (a CR-AFM
    # map, moduli in Pa) is inverted without the materials, crystals and half-space kernels
    # (~1 % of an afm invert of a 512² map).
    from ..materials import Material

    if isinstance(spec, tuple) and len(spec) == 2 and isinstance(spec[0], Material):
        return spec[0].rotated(spec[1])
    if isinstance(spec, Material):
        return spec
    raise ContactresInputError(
        f"{name} must be a number (Pa), a contactres.Material in its surface frame or a "
        f"(Material, (h, k, l)) pair, got {type(spec).__name__}"
    )


def modulus_of(spec, name: str = "modulus"):
    """Indentation modulus M (Pa) of a number or array (taken as M, Pa; one per pixel), a
    Material in its surface frame, or a (Material, (h, k, l)) pair:
    :func:`~contactres.normal.indentation_modulus` (paper 1, Eq. 4; E/(1 − ν²) for
    an isotropic material)."""
    if isinstance(spec, (int, float, np.floating, np.integer, np.ndarray)):
        return positive(name, spec, "Pa")
    from ..materials import require_material
    from ..normal import indentation_modulus

    m = require_material(surface_material(spec, name), lossless=True)
    return float(np.real(indentation_modulus(m)))


def longitudinal_velocity(m: Material) -> float:
    """c_l = √(Re C33/ρ) of a material in its surface frame, m/s (needs the density)."""
    from ..materials import require_material

    m = require_material(m)
    if m.density is None:
        raise ContactresInputError(
            "the sample material needs its density (kg/m^3) for the wave number"
        )
    return math.sqrt(float(np.real(m.C[2, 2])) / m.density)


def dcsf_values(m: Material, ka, *, loss: float = 0.0, grid: int = DCSF_GRID, prepared=None):
    """DCSF (model "exact", ``wavenumber="longitudinal"``) of ``m`` at the k_l a values ``ka``.

    At most ``grid`` distinct values are evaluated directly; more are interpolated between
    Chebyshev points with a measured error below 1e-7 of the largest ``|1/DCSF|`` on the range
    (``interpolate=True`` of :func:`contactres.dynamic.dcsf`). ``prepared``: the kernel table
    of ``m`` and ``loss`` (rtol 1e-6), built here when not given.
    """
    from ..dynamic import dcsf, prepare  # here, not at the top: see modulus_from_contact_stiffness

    ka = np.asarray(nonnegative("ka (normalised wave number k_l a)", ka), dtype=float)
    table = prepare(m, loss) if prepared is None else prepared
    many = np.unique(ka).size > grid
    vals = dcsf(m, ka.ravel(), model="exact", loss=loss, prepared=table, interpolate=many)
    return np.asarray(vals).reshape(ka.shape)


def _exponent(reference_k_star, E_ref, reference2_k_star, E_ref2, exponent):
    if reference2_k_star is None:
        return 1.5 if exponent is None else positive("exponent", exponent, "dimensionless")
    if exponent is not None:
        raise ContactresInputError(
            "give either exponent or a second reference (which fits it), not both"
        )
    k1, k2 = np.asarray(reference_k_star), np.asarray(reference2_k_star)
    ratio = np.log(k2 / k1)
    if np.any(np.abs(ratio) < 1e-12):
        raise ContactresInputError(
            f"the two references need different contact stiffness, got {reference_k_star!r} "
            f"and {reference2_k_star!r} N/m"
        )
    m = np.log(E_ref2 / E_ref) / ratio
    return float(m) if np.ndim(m) == 0 else m


def modulus_from_contact_stiffness(
    k_star,
    *,
    tip_radius=None,
    load=None,
    reference_k_star=None,
    reference_modulus=None,
    reference2_k_star=None,
    reference2_modulus=None,
    exponent: float | None = None,
    tip_modulus: float | None = None,
    tip=None,
    sample=None,
    hardness: float | None = None,
    frequency=None,
    dynamic: bool = False,
    loss: float = 0.0,
    iterations: int = DYNAMIC_ITERATIONS,
    dcsf_grid: int = DCSF_GRID,
    prepared=None,
) -> ModulusResult:
    """Reduced modulus E* and sample modulus M_sample from the contact stiffness k*.

    Parameters
    ----------
    k_star : float or array
        Measured contact stiffness k*, N/m (e.g. from
        :meth:`contactres.resonators.RUMOscillator.contact_stiffness`).
    tip_radius, load : float or array, optional
        Tip radius R (m) and static load P (N): the Hertz method (Johnson Eq. 4.22-4.23).
        ``load`` also gives the peak pressure with the reference method.
    reference_k_star, reference_modulus : optional
        k*_ref (N/m) of a reference sample measured with the same tip and load, and its
        indentation modulus M_ref (Pa, a Material or a (Material, (h, k, l)) pair): the
        reference method (Hurley 2009), used instead of Hertz when given.
    reference2_k_star, reference2_modulus : optional
        A second reference: the exponent m is then fitted (do not give ``exponent``).
    exponent : float, optional
        m of E*_s = E*_ref (k*_s/k*_ref)^m; default 3/2 (Hertz), 1 for a flat punch.
    tip_modulus : float, optional
        Indentation modulus of the tip M_tip, Pa. Or ``tip``: a Material in its surface frame or
        a (Material, (h, k, l)) pair. Neither: a rigid tip (M_tip = inf).
    sample : Material or (Material, (h, k, l)), optional
        The sample (with density), for the wave number k_l of the dynamic correction.
    hardness : float or array, optional
        Hardness (Pa): p0 above it sets ModulusFlag.NOT_ELASTIC (needs ``load``); NaN: no
        hardness known for that pixel.
    frequency : float or array, optional
        Contact-resonance frequency f, Hz (for k_l = 2πf/c_l).
    dynamic : bool
        Apply paper 1's correction K_static = k*/Re DCSF(k_l a) (needs ``frequency`` and
        ``sample``), iterated (a depends on E*) until K_static changes by less than 1e-13
        relative, at most ``iterations`` times.
    loss : float
        Q⁻¹ of the sample's constants for the DCSF (default 0: lossless).
    dcsf_grid, prepared
        As in :func:`dcsf_values` (``prepared``: the kernel table of the sample and ``loss``).

    Returns
    -------
    ModulusResult
        Arrays of the broadcast shape of the array inputs.

    Examples
    --------
    Hertz with a known tip radius (m) and load (N): E* = √(k*³/(6RP)), a = k*/(2E*):

    >>> import numpy as np
    >>> from contactres import modulus_from_contact_stiffness
    >>> r = modulus_from_contact_stiffness(1262.8, tip_radius=50e-9, load=1e-6)  # k* in N/m
    >>> print(f"E* = {float(r.E_star) / 1e9:.2f} GPa, a = {float(r.contact_radius) * 1e9:.2f} nm")
    E* = 81.93 GPa, a = 7.71 nm
    >>> bool(np.isclose(r.E_star, np.sqrt(1262.8**3 / (6 * 50e-9 * 1e-6)), atol=0))
    True
    """
    k = np.asarray(positive("k_star (contact stiffness k*)", k_star, "N/m"), dtype=float)
    if tip_modulus is not None and tip is not None:
        raise ContactresInputError("give tip_modulus or tip, not both")
    if tip_modulus is not None:
        M_tip = positive("tip_modulus (M_tip)", tip_modulus, "Pa")
    elif tip is not None:
        M_tip = modulus_of(tip, "tip")
    else:
        M_tip = math.inf
    P = None if load is None else np.asarray(positive("load", load, "N"))
    arrays = [k] if P is None else [k, P]
    hertz_radius = None  # the tip radius where Hertz gives E*

    if reference_k_star is not None:
        if reference_modulus is None:
            raise ContactresInputError(
                "reference_k_star needs reference_modulus (Pa or a Material)"
            )
        k_ref = np.asarray(positive("reference_k_star", reference_k_star, "N/m"))
        E_ref = 1.0 / (1.0 / M_tip + 1.0 / modulus_of(reference_modulus, "reference_modulus"))
        E_ref2 = None
        if reference2_k_star is not None:
            if reference2_modulus is None:
                raise ContactresInputError(
                    "reference2_k_star needs reference2_modulus (Pa or a Material)"
                )
            positive("reference2_k_star", reference2_k_star, "N/m")
            M2 = modulus_of(reference2_modulus, "reference2_modulus")
            E_ref2 = 1.0 / (1.0 / M_tip + 1.0 / M2)
        m_exp = _exponent(k_ref, E_ref, reference2_k_star, E_ref2, exponent)
        arrays.append(k_ref)
        method = "reference"

        def e_star(K):
            return E_ref * (K / k_ref) ** m_exp
    elif tip_radius is not None and load is not None:
        R = hertz_radius = np.asarray(positive("tip_radius", tip_radius, "m"))
        arrays.append(R)
        m_exp = 1.5
        method = "hertz"

        def e_star(K):
            return np.sqrt(K**3 / (6.0 * R * P))
    else:
        raise ContactresInputError(
            "give tip_radius and load (Hertz) or reference_k_star and reference_modulus "
            "(reference sample)"
        )

    k_l = None
    if frequency is not None and sample is not None:
        # The dynamic package is imported where the dynamic correction is made: its kernel
        # tables load scipy.special (~0.15 s of CPU), which a static inversion (afm invert of a
        # map without --crystal) never needs (issue 31, point 5).
        from ..dynamic import normalised_wavenumber, wave_modulus

        surface = surface_material(sample, "sample")
        f = np.asarray(positive("frequency", frequency, "Hz"))
        arrays.append(f)
        longitudinal_velocity(surface)  # a clear error without the density
        # The one wave-number function of the package (k per metre: a = 1 m).
        k_l = normalised_wavenumber(f, 1.0, surface.density, wave_modulus(surface, "longitudinal"))
    elif dynamic:
        raise ContactresInputError(
            "dynamic=True needs frequency (Hz) and sample (Material, with density)"
        )
    try:
        shape = np.broadcast_shapes(*(np.shape(x) for x in arrays))
    except ValueError:
        shapes = ", ".join(str(np.shape(x)) for x in arrays)
        raise ContactresInputError(
            f"the array inputs do not broadcast together: {shapes}"
        ) from None
    k = np.broadcast_to(k, shape)

    K = k
    D = np.ones(shape, dtype=complex)
    if dynamic:
        n_it = int(iterations)
        if n_it < 1:
            raise ContactresInputError(f"iterations must be >= 1, got {iterations!r}")
        from ..dynamic import prepare

        table = prepare(surface, loss) if prepared is None else prepared
        for _ in range(n_it):
            ka = k_l * K / (2.0 * e_star(K))
            D = dcsf_values(surface, ka, loss=loss, grid=dcsf_grid, prepared=table)
            K, K_old = k / D.real, K
            if np.max(np.abs(K / K_old - 1.0)) <= DYNAMIC_RTOL:
                break
        method += " + dynamic"
    E = np.broadcast_to(e_star(K), shape).astype(float)
    a = K / (2.0 * E)
    ka = np.full(shape, np.nan) if k_l is None else np.broadcast_to(k_l * a, shape).astype(float)
    p0 = np.full(shape, np.nan) if P is None else 3.0 * P / (2.0 * np.pi * a**2)

    flags = np.zeros(shape, dtype=int)
    excess = 1.0 / E - 1.0 / M_tip
    tip_limit = excess <= 0
    flags[tip_limit] |= int(ModulusFlag.TIP_LIMIT)
    with np.errstate(divide="ignore"):
        M_s = np.where(tip_limit, np.nan, 1.0 / np.where(tip_limit, 1.0, excess))
    if hertz_radius is not None:
        # A contact wider than the tip is no sphere contact at all (Hertz needs a << R; a/R of
        # order 1 still happens on soft samples and is left to the user): a unit slip.
        wide = a > hertz_radius
        flags[wide] |= int(ModulusFlag.NOT_HERTZIAN)
        E = np.where(wide, np.nan, E)
        M_s = np.where(wide, np.nan, M_s)
    absurd = np.isfinite(M_s) & ~QUANTITIES["sample_modulus"].accepts(M_s)
    flags[absurd] |= int(ModulusFlag.MODULUS_OUT_OF_RANGE)
    E, M_s = np.where(absurd, np.nan, E), np.where(absurd, np.nan, M_s)
    if hardness is not None:
        H = np.asarray(hardness, dtype=float)  # NaN: no hardness for that pixel, no check
        positive("hardness", H[~np.isnan(H)], "Pa")
        if P is None:
            raise ContactresInputError("hardness needs load (N) for the peak pressure")
        flags[p0 > H] |= int(ModulusFlag.NOT_ELASTIC)
    if method.startswith("reference"):
        how = "fitted" if reference2_k_star is not None else "given"
        value = f" = {m_exp:.6g}" if np.ndim(m_exp) == 0 else ""
        method = method.replace("reference", f"reference ({how} m{value})")
    return ModulusResult(
        E_star=E,
        M_sample=M_s,
        contact_radius=np.asarray(a, dtype=float),
        peak_pressure=np.asarray(p0, dtype=float),
        k_a=ka,
        dcsf=np.asarray(D, dtype=complex),
        k_static=np.asarray(K, dtype=float),
        flags=flags,
        method=method,
        exponent=m_exp if np.ndim(m_exp) else float(m_exp),  # an array for per-pixel refs
        tip_modulus=M_tip,
    )
