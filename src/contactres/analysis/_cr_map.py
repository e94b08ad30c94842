"""Maps of physics from a contact-resonance map: k*, contact damping σ, E*, M and tan δ per pixel.

Input: the contact resonance of mode 1 per pixel — frequency f (Hz) and quality factor Q, from
DART (:func:`contactres.analysis.dart_reconstruction`), band excitation's SHO fit or a grid —
and the free lever (:class:`contactres.Cantilever`: free frequency, spring constant k_c, free
Q). Per pixel:

1. κ = k*/k_c and the contact damping σ (N s/m) by :func:`contactres.invert_contact_resonance`
   (mode 1, the tip position r = L1/L given; optional lateral spring ratio, tip height and tilt).
   The contact is a spring k* in parallel with a dashpot σ (Kelvin-Voigt; Yuya, Hurley &
   Turner, J. Appl. Phys. 104, 074916 (2008)). It enters the lever's characteristic equation at
   the complex eigenfrequency ω_c = ω(1 + i/(2Q)), ω = 2πf, as k_c κ_c = k* + iω_c σ, so
   σ = k_c Im κ_c/ω and k* = k_c (Re κ_c + Im κ_c/(2Q)) (the reading of
   :func:`~contactres.invert_contact_resonance`).
2. The reduced modulus E* and the sample's indentation modulus M, one of

   * Hertz, tip radius R and load P: E* = √(k*³/(6RP)) (Johnson, Contact Mechanics, Eqs.
     4.22-4.23; :func:`contactres.modulus_from_contact_stiffness`);
   * a flat punch of radius a: E* = k*/(2a);
   * a reference region of the map of known modulus M_ref (the same tip and load): k*_ref is
     the median of k* over the region, E* = E*_ref (k*/k*_ref)^m with E*_ref = 1/(1/M_tip +
     1/M_ref), m = 3/2 (Hertz) unless given (1 for a flat punch). Done per map, this also
     follows the wear of the tip across a series of maps (J. P. Killgore, R. H. Geiss and
     D. C. Hurley, "Continuous measurement of atomic force microscope tip wear by contact
     resonance force microscopy", Small 7, 1018 (2011): the tip's radius changes from map to
     map, a reference in every map calibrates each).

   then M = 1/(1/E* − 1/M_tip) (tip compliance in series; NaN, flagged ``tip_limit``, where
   1/E* ≤ 1/M_tip).
3. The loss tangent (Yuya et al. 2008; D. C. Hurley et al., Macromolecules 46, 9396 (2013)):

       tan δ = ω σ / k*.

   Its assumptions: the storage and the loss of the contact share one contact geometry, so that
   k* = 2a E*′ and ωσ = 2a E*″ with the same contact radius a (Hertz or flat punch, a set by the
   storage part), and the contact's damping is the sample's loss (the lever's own damping is
   removed through the free Q, the air's is not modelled). Then a cancels: tan δ needs no tip
   shape or load, and it is the loss tangent of the reduced modulus, tan δ = E*″/E*′. With a
   compliant elastic tip (M_tip finite, real) the sample's loss tangent is that of
   M = 1/(1/E* − 1/M_tip) with E* = E*′(1 + i tan δ): ``tan_delta_sample`` (larger than tan δ
   by about the factor M′/E*′; equal to it for a rigid tip), where E*′ is known.

Negative damping. σ < 0 (tan δ < 0) is no contact's loss: the measured Q exceeds what the
lever's own damping (its free Q, removed from σ) allows, a free Q too low or a wrong drive
separation of DART. Such pixels keep k* but σ, tan δ and ``tan_delta_sample`` are NaN, flagged
``negative_damping`` (:data:`FLAG_NEGATIVE_DAMPING`, a bit of the map's own above the
inversion's).

The result is an :mod:`xarray` Dataset (dims y, x; coordinates in m from the pixel size, else
pixel indices; every variable with a ``units`` attribute; the conventions as attributes and as
one JSON text, ``conventions``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError, MissingExtraError
from ..units import QUANTITIES
from ..validation import positive
from ._inversion import FLAG_DESCRIPTIONS, ModulusFlag, modulus_from_contact_stiffness

__all__ = ["CR_MAP_FLAGS", "CR_MAP_UNITS", "ModulusModel", "invert_cr_map", "reference_region"]

#: σ < 0 (module notes: negative damping): σ and tan δ are NaN. A bit of ``flags`` of the map
#: above those of :func:`contactres.invert_contact_resonance` (which end at 2^8), so both live
#: in one mask.
FLAG_NEGATIVE_DAMPING = 1 << 16

#: The map's own bits of ``flags``: bit -> (name, what it means).
CR_MAP_FLAGS = MappingProxyType(
    {
        FLAG_NEGATIVE_DAMPING: (
            "negative_damping",
            "contact damping < 0 (σ and tan δ NaN): the contact's Q exceeds what the lever's "
            "free Q allows; check --free-q / --frequency-width",
        ),
    }
)

#: Variables of the Dataset and their units.
CR_MAP_UNITS = {
    "frequency_Hz": "Hz",
    "q_factor": "1",
    "kappa": "1",
    "k_star_N_per_m": "N/m",
    "sigma_N_s_per_m": "N s/m",
    "tan_delta": "1",
    "tan_delta_sample": "1",
    "E_star_Pa": "Pa",
    "M_Pa": "Pa",
    "contact_radius_m": "m",
    "flags": "1",
    "modulus_flags": "1",
}


@dataclass(frozen=True)
class ModulusModel:
    """How k* becomes a modulus: Hertz (``tip_radius`` and ``load``), a flat punch
    (``punch_radius``) or a reference region of the map (``reference`` and
    ``reference_modulus``); exactly one. None of them: no modulus (k*, σ and tan δ only).

    Parameters
    ----------
    tip_radius, load : float, optional
        Tip radius R, m, and static load P, N (Hertz).
    punch_radius : float, optional
        Radius of a flat punch, m.
    reference : (y0, y1, x0, x1), optional
        Rows y0 ≤ y < y1 and columns x0 ≤ x < x1 (pixel indices) of a region of known modulus.
    reference_modulus : float, optional
        Indentation modulus of the reference region, Pa.
    exponent : float, optional
        m of E* = E*_ref (k*/k*_ref)^m; default 3/2 (Hertz).
    tip_modulus : float, optional
        Indentation modulus of the tip, Pa (None: rigid).
    """

    tip_radius: float | None = None
    load: float | None = None
    punch_radius: float | None = None
    reference: tuple[int, int, int, int] | None = None
    reference_modulus: float | None = None
    exponent: float | None = None
    tip_modulus: float | None = None

    def __post_init__(self):
        self.method  # noqa: B018 - a contradictory model is refused when it is made

    @property
    def method(self) -> str | None:
        """ "hertz", "punch", "reference" or None (no modulus); checked."""
        given = {
            "hertz": self.tip_radius is not None or self.load is not None,
            "punch": self.punch_radius is not None,
            "reference": self.reference is not None or self.reference_modulus is not None,
        }
        chosen = [k for k, v in given.items() if v]
        if len(chosen) > 1:
            raise ContactresInputError(
                "give one way to the modulus: tip radius and load (Hertz), a punch radius, or "
                f"a reference region and its modulus; got {' and '.join(chosen)}"
            )
        if not chosen:
            return None
        if chosen == ["hertz"] and (self.tip_radius is None or self.load is None):
            raise ContactresInputError("Hertz needs both the tip radius (m) and the load (N)")
        if chosen == ["reference"] and (self.reference is None or self.reference_modulus is None):
            raise ContactresInputError(
                "a reference region needs its modulus (Pa), and a modulus its region"
            )
        return chosen[0]


def reference_region(region, shape) -> tuple[slice, slice]:
    """Slices of a reference region (y0, y1, x0, x1), checked to be non-empty and to lie inside
    a map of ``shape``."""
    try:
        y0, y1, x0, x1 = (int(v) for v in region)
    except (TypeError, ValueError):
        raise ContactresInputError(
            f"the reference region must be (y0, y1, x0, x1) pixel indices, got {region!r}"
        ) from None
    h, w = shape
    if y1 <= y0 or x1 <= x0:  # the ends are excluded: y0:y0 holds no row
        raise ContactresInputError(
            f"the reference region rows {y0}:{y1}, columns {x0}:{x1} is empty: the ends are "
            "excluded, give Y0 < Y1 and X0 < X1"
        )
    if not (0 <= y0 < y1 <= h and 0 <= x0 < x1 <= w):
        raise ContactresInputError(
            f"the reference region rows {y0}:{y1}, columns {x0}:{x1} is not inside the "
            f"{h} x {w} image (rows 0:{h}, columns 0:{w})"
        )
    return slice(y0, y1), slice(x0, x1)


def _punch(k, radius, tip_modulus):
    """E*, M, flags of a flat punch of ``radius`` (m): E* = k*/(2a)."""
    e = k / (2.0 * positive("punch radius", radius, "m"))
    excess = 1.0 / e - 1.0 / tip_modulus
    flags = np.where(excess <= 0, int(ModulusFlag.TIP_LIMIT), 0)
    with np.errstate(divide="ignore"):
        m = np.where(excess > 0, 1.0 / np.where(excess > 0, excess, 1.0), np.nan)
    absurd = np.isfinite(m) & ~QUANTITIES["sample_modulus"].accepts(m)
    flags = flags | np.where(absurd, int(ModulusFlag.MODULUS_OUT_OF_RANGE), 0)
    return np.where(absurd, np.nan, e), np.where(absurd, np.nan, m), flags


def _moduli(k_star, model: ModulusModel, shape):
    """(E*, M, contact radius, flags, record) for the pixels of ``k_star`` (NaN: none)."""
    method = model.method
    nan = np.full(shape, np.nan)
    e_star, m_s, radius = nan.copy(), nan.copy(), nan.copy()
    flags = np.zeros(shape, dtype=int)
    record: dict = {"method": method or "none"}
    if method is None:
        return e_star, m_s, radius, flags, record
    m_tip = np.inf if model.tip_modulus is None else positive("tip modulus", model.tip_modulus)
    ok = np.isfinite(k_star) & (k_star > 0)
    k = k_star[ok]
    if method == "punch":
        radius_m = model.punch_radius
        assert radius_m is not None  # the method says which fields are given (ModulusModel)
        e, m, f = _punch(k, radius_m, m_tip)
        a = np.full(k.shape, float(radius_m))
        record.update(punch_radius_m=float(radius_m), equation="E* = k*/(2a)")
    else:
        kwargs: dict[str, Any] = {}
        if method == "hertz":
            tip_radius, load = model.tip_radius, model.load
            assert tip_radius is not None and load is not None  # method "hertz" has both
            kwargs = {"tip_radius": tip_radius, "load": load}
            record.update(tip_radius_m=float(tip_radius), load_N=float(load))
        else:
            region_given, reference_modulus = model.reference, model.reference_modulus
            assert region_given is not None and reference_modulus is not None  # "reference"
            rows, cols = reference_region(region_given, shape)
            region = k_star[rows, cols]
            good = region[np.isfinite(region) & (region > 0)]
            if good.size == 0:
                raise ContactresInputError(
                    "the reference region holds no pixel with a contact stiffness (k*): choose "
                    "a region of the map where the contact resonance was measured"
                )
            k_ref = float(np.median(good))
            kwargs = {
                "reference_k_star": k_ref,
                "reference_modulus": reference_modulus,
                "exponent": model.exponent,
            }
            record.update(
                reference_region=[int(v) for v in region_given],
                reference_modulus_Pa=float(reference_modulus),
                reference_k_star_N_per_m=k_ref,
                reference_pixels=int(good.size),
            )
        if k.size:
            r = modulus_from_contact_stiffness(k, tip_modulus=model.tip_modulus, **kwargs)
            e, m, a, f = r.E_star, r.M_sample, r.contact_radius, r.flags
            record["equation"] = (
                "E* = sqrt(k*^3/(6 R P)) (Hertz)"
                if method == "hertz"
                else f"E* = E*_ref (k*/k*_ref)^m, {r.method}"
            )
            record["exponent"] = float(r.exponent)
        else:
            e = m = a = np.array([])
            f = np.array([], dtype=int)
    e_star[ok], m_s[ok], radius[ok], flags[ok] = e, m, a, f
    record["tip_modulus_Pa"] = None if np.isinf(m_tip) else float(m_tip)
    return e_star, m_s, radius, flags, record


def _sample_loss_tangent(e_star, tan_delta, tip_modulus):
    """tan δ of M = 1/(1/E* − 1/M_tip) with E* = E*′(1 + i tan δ) (module notes)."""
    if tip_modulus is None:
        return tan_delta.copy()
    with np.errstate(all="ignore"):
        m = 1.0 / (1.0 / (e_star * (1.0 + 1j * tan_delta)) - 1.0 / float(tip_modulus))
        return np.where(m.real > 0, m.imag / m.real, np.nan)


def _map_flag_names(flags: int) -> list[str]:
    """Short names of the bits set in one ``flags`` value of a map: the inversion's
    (:func:`contactres.resonators.flag_names`) and the map's own (:data:`CR_MAP_FLAGS`)."""
    from ..resonators import flag_names

    own = [name for bit, (name, _) in CR_MAP_FLAGS.items() if int(flags) & bit]
    return flag_names(int(flags)) + own


def _flag_bits(flag_names) -> dict:
    """What each bit of ``flags`` and ``modulus_flags`` means (JSON: bit value as text)."""
    bits = {str(1 << i): flag_names(1 << i) for i in range(31)}
    return {
        "flags": {k: v[0] for k, v in bits.items() if v},
        "modulus_flags": {str(int(f)): text for f, text in FLAG_DESCRIPTIONS.items()},
    }


@one_blas_thread()
def invert_cr_map(
    frequency,
    q_factor,
    cantilever,
    *,
    tip_position: float = 1.0,
    lateral_ratio: float = 0.0,
    tip_height: float = 0.0,
    tilt: float = 0.0,
    modulus: ModulusModel | None = None,
    pixel_size: float | tuple[float, float] | None = None,
    conventions: dict | None = None,
):
    """k*, σ, tan δ, E* and M per pixel of a contact-resonance map (module notes).

    Parameters
    ----------
    frequency : array_like, shape (H, W)
        Contact-resonance frequency of mode 1, Hz (NaN, or ≤ 0: not measured).
    q_factor : array_like, shape (H, W), or None
        Its quality factor, dimensionless (NaN or ≤ 0: unknown; None: no σ, no tan δ).
    cantilever : contactres.Cantilever
        The free lever (k_c = 3EI/L³ at the free end, free frequency and Q).
    tip_position, lateral_ratio, tip_height, tilt
        r = L1/L, α = k_lat/k*, η = h/L and the tilt, degrees
        (:func:`contactres.invert_contact_resonance`).
    modulus : ModulusModel, optional
        How k* becomes E* and M; None: no modulus.
    pixel_size : float or (float, float), optional
        Pixel pitch, m, square or (dx, dy): the coordinates x, y in m (else pixel indices).
    conventions : dict, optional
        More conventions to record (the instrument's constants, the source); JSON-able.

    Returns
    -------
    xarray.Dataset
        Variables :data:`CR_MAP_UNITS` on (y, x), each with ``units``; attributes: the method,
        the equations and the flags' meanings, and ``conventions`` (one JSON text of them all).

    Raises
    ------
    ContactresInputError
        A map that is not 2-D, shapes that differ, a map with no positive frequency, a
        reference region outside the image or without k*, or bad lever constants.
    """
    from ..resonators import invert_contact_resonance

    f = np.array(frequency, dtype=float)
    if f.ndim != 2:
        raise ContactresInputError(f"the frequency map must be 2-D (rows, columns), got {f.shape}")
    with np.errstate(invalid="ignore"):
        measured = np.isfinite(f) & (f > 0)
    if not measured.any():
        raise ContactresInputError(
            "the frequency map holds no positive frequency (all zero or missing): no contact "
            "resonance was tracked"
        )
    f = np.where(measured, f, np.nan)
    q = None
    if q_factor is not None:
        q = np.array(q_factor, dtype=float)
        if q.shape != f.shape:
            raise ContactresInputError(
                f"the Q map has shape {q.shape}, the frequency map {f.shape}: they must agree"
            )
        with np.errstate(invalid="ignore"):
            q = np.where(np.isfinite(q) & (q > 0), q, np.nan)
    model = ModulusModel() if modulus is None else modulus
    if model.reference is not None:
        reference_region(model.reference, f.shape)
    res = invert_contact_resonance(
        cantilever,
        f[..., None],
        tip_position=tip_position,
        q_factors=None if q is None else q[..., None],
        lateral_ratio=lateral_ratio,
        tip_height=tip_height,
        tilt=tilt,
        modes=(1,),
    )
    k_star = np.where(np.isfinite(res.k_star), res.k_star, np.nan)
    # σ < 0 is no loss of a contact (module notes: negative damping): flagged, σ NaN.
    negative = res.sigma < 0
    sigma = np.where(negative, np.nan, res.sigma)
    flags = res.flags | np.where(negative, FLAG_NEGATIVE_DAMPING, 0)
    with np.errstate(all="ignore"):
        # No loss tangent without a contact spring (κ = 0: flagged no_contact by the inversion).
        tan_delta = np.where(k_star > 0, 2.0 * np.pi * f * sigma / k_star, np.nan)
    e_star, m_s, radius, m_flags, record = _moduli(k_star, model, f.shape)
    tan_sample = _sample_loss_tangent(e_star, tan_delta, model.tip_modulus)
    if record["method"] == "none":
        tan_sample = np.where(np.isfinite(tan_delta), tan_delta, np.nan)
    values = {
        "frequency_Hz": f,
        "q_factor": np.full(f.shape, np.nan) if q is None else q,
        "kappa": res.kappa,
        "k_star_N_per_m": k_star,
        "sigma_N_s_per_m": sigma,
        "tan_delta": tan_delta,
        "tan_delta_sample": tan_sample,
        "E_star_Pa": e_star,
        "M_Pa": m_s,
        "contact_radius_m": radius,
        "flags": flags.astype(np.int32),
        "modulus_flags": m_flags.astype(np.int32),
    }
    inv_bits = sorted({b for v in np.unique(flags) for b in _map_flag_names(v)})
    # The modulus's flags too (by the names of ModulusFlag): a modulus that fails is said.
    inv_bits += sorted(
        {str(f.name).lower() for v in np.unique(m_flags) for f in ModulusFlag if int(v) & f}
    )
    record_all = {
        "model": "Kelvin-Voigt contact: k* + i ω_c σ = k_c κ_c at ω_c = 2πf (1 + i/(2Q))",
        "inversion": res.method,
        "mode": 1,
        "tip_position": float(tip_position),
        "lateral_ratio": float(lateral_ratio),
        "tip_height": float(tip_height),
        "tilt_deg": float(tilt),
        "spring_constant_N_per_m": float(cantilever.spring_constant),
        "free_frequency_Hz": float(cantilever.free_frequencies[0]),
        "free_q": None if cantilever.free_q_factors is None else cantilever.free_q_factors[0],
        "tan_delta": "tan δ = ω σ / k*, ω = 2πf (Yuya, Hurley & Turner 2008; Hurley et al. "
        "2013): one contact geometry for storage and loss, the lever's damping removed via "
        "its free Q; tan_delta_sample: of M = 1/(1/E* − 1/M_tip)",
        "modulus": record,
        "flags_present": inv_bits,
        "flag_bits": _flag_bits(_map_flag_names),
        "units": dict(CR_MAP_UNITS),
        "pixel_size_m": None if pixel_size is None else np.ravel(pixel_size).tolist(),
        **(conventions or {}),
    }
    return _dataset(values, pixel_size, record_all)


def _dataset(values: dict, pixel_size, conventions: dict):
    try:
        import xarray as xr
    except ImportError as exc:  # pragma: no cover - the test environment has the extra
        raise MissingExtraError(
            "xarray is needed for CR-AFM maps: pip install 'contactres[maps]'"
        ) from exc
    h, w = next(iter(values.values())).shape
    if pixel_size is None:
        coords = {"y": np.arange(h), "x": np.arange(w)}
        unit = "pixel"
    else:
        dx, dy = np.broadcast_to(positive("pixel size", pixel_size, "m"), (2,))
        coords = {"y": np.arange(h) * dy, "x": np.arange(w) * dx}
        unit = "m"
    ds = xr.Dataset(
        {k: (("y", "x"), v, {"units": CR_MAP_UNITS.get(k, "1")}) for k, v in values.items()},
        coords=coords,
    )
    ds["y"].attrs["units"] = unit
    ds["x"].attrs["units"] = unit
    ds.attrs["conventions"] = json.dumps(conventions, ensure_ascii=False, default=str)
    ds.attrs["modulus_method"] = conventions["modulus"]["method"]
    ds.attrs["tan_delta"] = conventions["tan_delta"]
    return ds
