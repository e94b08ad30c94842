"""The computations of the map jobs: synthetic maps, predicted maps and the fit of measured maps.

Each function takes an :class:`~contactres.polycrystal.OrientationMap` (read from a Zarr
map store or an EBSD export by :func:`open_map`) and returns an :mod:`xarray` Dataset or a fit
result; the jobs :mod:`~contactres.jobs.maps_synthetic`, :mod:`~contactres.jobs.maps_predict` and
:mod:`~contactres.jobs.maps_fit` run them, and the command line writes what they return (Zarr
stores atomically, JSON/CSV atomically).

Physics: the indentation modulus M of each pixel (paper 1, Eq. 4; Vlassak & Nix 1994), the
Hertz contact of a spherical tip with its compliance in series (Johnson 1985, Ch. 4), paper 1's
DCSF (Eq. 29) and the inverse of :mod:`contactres.polycrystal._inverse`.

References
----------
Paper 1: J. Tian, Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010). J. J. Vlassak and W. D. Nix,
J. Mech. Phys. Solids 42, 1223 (1994). K. L. Johnson, *Contact Mechanics*, Cambridge
University Press (1985).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ContactresInputError
from ..materials import Material
from ..polycrystal import (
    ContactMap,
    ExactModulus,
    IndexedPixels,
    OrientationMap,
    contact_stiffness_map,
    dynamic_factor_map,
    evaluate_map,
    fit_map,
    folded_normals,
    grain_orientations,
    indentation_moduli,
    indexed_pixels,
    map_from_dataset,
    map_to_dataset,
    prepare_normal_table,
    read_map,
    segment_grains,
    surface_matrices_from_euler,
    synthetic_polycrystal,
)
from .readers import ALL_READERS, read_ebsd_file, read_value_grid

if TYPE_CHECKING:
    from ..measurements.readers import Readers

__all__ = [
    "METHODS",
    "TipLoad",
    "check_tip_load",
    "fit_measured_map",
    "fit_record",
    "open_map",
    "predict_map",
    "read_value_grid",
    "synthetic_map",
]

#: How ``predict_map`` evaluates M: tabulated and interpolated, exact per pixel, exact per grain.
METHODS = ("auto", "interpolated", "exact", "grains")
# Largest angle (rad) between two pixels' normals for a labelled grain to count as uniform.
_UNIFORM_RAD = 1e-9


@dataclass(frozen=True)
class TipLoad:
    """The spherical tip and its load.

    Attributes
    ----------
    radius : float
        Tip radius R, m.
    force : float
        Static normal force F, N.
    tip_modulus : float
        Plane-strain modulus of the tip E/(1 − ν²), Pa; ``math.inf`` for a rigid tip.
    """

    radius: float
    force: float
    tip_modulus: float = math.inf

    @property
    def tip(self) -> tuple[float, float] | None:
        """The tip as :func:`~contactres.polycrystal.contact_stiffness_map` takes it
        (a plane-strain modulus is (E, ν = 0))."""
        return None if math.isinf(self.tip_modulus) else (self.tip_modulus, 0.0)


def open_map(path: str | os.PathLike, readers: Readers = ALL_READERS):
    """Read a map: a Zarr map store (:func:`~contactres.polycrystal.write_map`) or an EBSD
    export (.ang, .ctf, .h5oina: the ``ebsd`` recipes of ``readers``, :func:`read_ebsd_file`).
    Returns (OrientationMap, Dataset or None): the store's Dataset keeps its other variables (a
    measured map, a prediction)."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{str(p)!r}: no such file or map store")
    if p.is_dir():
        ds = read_map(p)
        return map_from_dataset(ds), ds
    return read_ebsd_file(p, readers), None


def _first_pixels(labels: np.ndarray) -> np.ndarray:
    """Flat index of the first pixel of each grain 0 .. G-1 (-1 for a grain without pixels);
    unlabelled pixels (-1) belong to no grain."""
    lab = labels.ravel()
    first = np.full(int(lab.max(initial=-1)) + 1, -1)
    valid = np.flatnonzero(lab >= 0)
    first[lab[valid][::-1]] = valid[::-1]  # reversed: the earliest pixel is written last
    return first


def _uniform_grains(omap: OrientationMap, normals: np.ndarray) -> bool:
    """True when every labelled grain has one orientation (a synthetic or cleaned map)."""
    if omap.labels is None:  # no grains at all
        return False
    lab = omap.labels.ravel()
    keep = lab >= 0
    n = normals.reshape(-1, 3)
    ref = n[_first_pixels(lab)[lab[keep]]]
    return bool(np.all(np.linalg.norm(n[keep] - ref, axis=1) <= _UNIFORM_RAD))


def predict_map(
    omap: OrientationMap,
    material: Material,
    lattice: str,
    tipload: TipLoad,
    *,
    method: str = "auto",
    rtol: float = 1e-4,
    frequency: float | None = None,
    model: str = "exact",
    dcsf_rtol: float = 1e-3,
    chunks: tuple[int, int] = (256, 256),
    scheduler: str | None = None,
    client=None,
    progress: Callable[[int, int], None] | None = None,
    pixels: IndexedPixels | None = None,
):
    """Predicted M, static (and dynamic) contact stiffness of every pixel, as a Dataset.

    Parameters
    ----------
    omap : OrientationMap
    material : Material
        The crystal in its crystal frame, Pa (density in kg/m^3 for ``frequency``).
    lattice : {"cubic", "hexagonal"}
    tipload : TipLoad
    method : {"auto", "interpolated", "exact", "grains"}
        "interpolated": M tabulated over the fundamental triangle until the interpolation
        error at the cell centres is below ``rtol``
        (:func:`~contactres.polycrystal.prepare_normal_table`); "exact": M of
        every pixel (slow; worth a cluster); "grains": exact per labelled grain (needs labels
        and one orientation per grain); "auto": "grains" when that holds, else "interpolated".
    rtol : float
        Interpolation tolerance of M (relative).
    frequency : float, optional
        Hz: add paper 1's DCSF of every pixel (``model``, tabulated to ``dcsf_rtol``) and the
        dynamic contact stiffness.
    chunks, scheduler, client, progress
        Of :func:`~contactres.polycrystal.evaluate_map` (the M evaluation).
    pixels : IndexedPixels, optional
        The pixels to predict (:func:`~contactres.polycrystal.indexed_pixels`; default: its
        rules with their defaults): the others (not indexed, low confidence, another phase)
        get NaN, not the modulus of a placeholder orientation.

    Returns
    -------
    (xarray.Dataset, dict)
        The map's variables plus ``M_Pa``, ``E_star_Pa``, ``contact_radius_m``,
        ``k_star_N_per_m`` (and ``ka_l``, ``dcsf_real``, ``dcsf_imag``,
        ``k_dynamic_real_N_per_m``, ``k_dynamic_imag_N_per_m``); a dict describing how M was
        evaluated (method, stated error, exact evaluations).
    """
    if method not in METHODS:
        raise ContactresInputError(f"method must be one of {METHODS}, got {method!r}")
    pixels = indexed_pixels(omap) if pixels is None else pixels
    normals = folded_normals(omap, lattice)  # M depends on the folded normal only
    uniform = omap.labels is not None and _uniform_grains(omap, normals)
    if method == "auto":
        method = "grains" if uniform else "interpolated"
    if method == "grains" and not uniform:
        raise ContactresInputError(
            "method 'grains' needs grain labels with one orientation per grain; use "
            "'interpolated' for a map whose orientations vary within grains"
        )
    table = None
    info: dict[str, str | int] = {"method": method}
    if method == "grains":
        lab = omap.labels
        assert lab is not None  # uniform grains are labelled
        idx = _first_pixels(lab)
        G = idx.size
        present = idx >= 0
        e = omap.euler.reshape(-1, 3)[idx[present]]
        R = surface_matrices_from_euler(e[:, 0], e[:, 1], e[:, 2], degrees=False)
        Mg = np.full(G, np.nan)
        Mg[present] = indentation_moduli(material, R)
        M = np.where(lab >= 0, Mg[np.maximum(lab, 0)], np.nan)
        info.update(exact_evaluations=int(present.sum()), stated_error="exact (rtol 1e-10)")
    elif method == "exact":
        M = evaluate_map(
            ExactModulus(material),
            omap,
            chunks=chunks,
            scheduler=scheduler,
            client=client,
            progress=progress,
        )
        info.update(exact_evaluations=int(M.size), stated_error="exact (rtol 1e-10)")
    else:
        table = prepare_normal_table(material, lattice, rtol)
        M = evaluate_map(
            table.modulus,
            omap,
            chunks=chunks,
            scheduler=scheduler,
            client=client,
            progress=progress,
        )
        info.update(exact_evaluations=table.evaluations, stated_error=f"{table.error:.2g}")
    M = np.where(pixels.mask, M, np.nan)
    info.update(pixels=pixels.summary(), pixels_left_out=pixels.left_out)
    contact = _contact_where_finite(M, tipload)
    ds = map_to_dataset(omap)
    dims = ("y", "x")
    ds["M_Pa"] = (dims, M, {"units": "Pa", "long_name": "indentation modulus M"})
    ds["E_star_Pa"] = (dims, contact.effective_modulus, {"units": "Pa"})
    ds["contact_radius_m"] = (dims, contact.contact_radius, {"units": "m"})
    ds["k_star_N_per_m"] = (dims, contact.stiffness, {"units": "N/m"})
    if frequency is not None:
        _add_dynamic(
            ds, material, lattice, tipload, normals, M, contact, frequency, model, dcsf_rtol, info
        )
    ds.attrs.update(_prediction_attrs(material, lattice, tipload, frequency, info))
    return ds, info


def _contact_where_finite(M: np.ndarray, tipload: TipLoad) -> ContactMap:
    """Hertz contact of every pixel with an M; NaN where M is NaN (unlabelled pixels)."""
    ok = np.isfinite(M)
    c = contact_stiffness_map(M[ok], tipload.tip, tipload.radius, tipload.force)
    out = [np.full(M.shape, np.nan) for _ in range(3)]
    for full, part in zip(out, (c.effective_modulus, c.contact_radius, c.stiffness), strict=True):
        full[ok] = part
    return ContactMap(*out)


def _add_dynamic(
    ds, material, lattice, tipload, normals, M, contact, frequency, model, dcsf_rtol, info
) -> None:
    """The DCSF per pixel from a table over the map's k_l a range (3 nodes, spline)."""
    from ..polycrystal import map_wavenumbers, surface_matrices_from_normals

    ka = map_wavenumbers(material, normals, contact.contact_radius, frequency)
    lo, hi = float(np.nanmin(ka)), float(np.nanmax(ka))
    nodes = np.array([lo]) if hi - lo <= 1e-9 * hi else np.linspace(lo, hi, 3)
    table = prepare_normal_table(material, lattice, ka=nodes, model=model, dcsf_rtol=dcsf_rtol)
    dyn = dynamic_factor_map(
        table,
        surface_matrices_from_normals(normals),
        tipload.tip,
        tipload.radius,
        tipload.force,
        frequency,
        moduli=M,
    )
    dims = ("y", "x")
    ds["ka_l"] = (dims, dyn.ka, {"units": "1", "long_name": "k_l a"})
    ds["dcsf_real"] = (dims, dyn.dcsf.real, {"units": "1"})
    ds["dcsf_imag"] = (dims, dyn.dcsf.imag, {"units": "1"})
    ds["k_dynamic_real_N_per_m"] = (dims, dyn.stiffness.real, {"units": "N/m"})
    ds["k_dynamic_imag_N_per_m"] = (dims, dyn.stiffness.imag, {"units": "N/m"})
    info.update(
        dcsf_model=model,
        dcsf_stated_error=f"{table.dcsf_error:.2g}",
        dcsf_orientations=table.dcsf_evaluations,
    )


def _prediction_attrs(material, lattice, tipload, frequency, info) -> dict:
    attrs = {
        "lattice": lattice,
        "stiffness_voigt_Pa": np.real(np.asarray(material.C)).ravel().tolist(),
        "tip_radius_m": tipload.radius,
        "force_N": tipload.force,
        "tip_modulus_Pa": "rigid" if math.isinf(tipload.tip_modulus) else tipload.tip_modulus,
        "k_star_convention": "Hertz, k* = 2 a E*, 1/E* = 1/M + 1/M_tip (static)",
    }
    if frequency is not None:
        attrs["frequency_Hz"] = float(frequency)
        attrs["dcsf_convention"] = "K_da/K_sa of the sample (paper 1, Eq. 29), k_l a"
    attrs.update({f"M_{k}": v for k, v in info.items()})
    return attrs


def synthetic_map(
    material: Material,
    lattice: str,
    tipload: TipLoad,
    *,
    shape: tuple[int, int],
    n_grains: int,
    seed: int,
    noise: float,
    pixel_size: float = 1e-6,
):
    """A seeded Voronoi polycrystal with a noisy 'measured' contact-stiffness map.

    k* per grain from the exact M (rigid or given tip, Hertz), times (1 + noise·N(0, 1)) per
    pixel (``numpy.random.default_rng(seed + 1)``). Returns the Dataset of the map with
    ``k_star_N_per_m`` (measured) and the truth as attributes (``truth_*``).
    """
    if not (0 <= noise < 0.5 and math.isfinite(noise)):
        raise ContactresInputError(
            f"noise must be a relative standard deviation in [0, 0.5), got {noise!r}"
        )
    sp = synthetic_polycrystal(shape, n_grains, seed, pixel_size)
    R = surface_matrices_from_euler(*sp.grain_euler.T, degrees=False)
    Mg = indentation_moduli(material, R)
    kg = contact_stiffness_map(Mg, tipload.tip, tipload.radius, tipload.force).stiffness
    rng = np.random.default_rng(seed + 1)
    assert sp.labels is not None  # a synthetic polycrystal is labelled
    k = kg[sp.labels] * (1.0 + noise * rng.standard_normal(sp.labels.shape))
    ds = map_to_dataset(sp)
    ds["k_star_N_per_m"] = (
        ("y", "x"),
        k,
        {"units": "N/m", "long_name": "contact stiffness (synthetic, noisy)"},
    )
    ds.attrs.update(_prediction_attrs(material, lattice, tipload, None, {}))
    ds.attrs.update(truth_noise_relative=float(noise), truth_seed=int(seed))
    return ds


def fit_measured_map(
    omap: OrientationMap,
    values: np.ndarray,
    *,
    quantity: str,
    lattice: str = "cubic",
    tipload: TipLoad | None = None,
    tip_modulus: float | None = None,
    tolerance_deg: float = 2.0,
    min_pixels: int = 10,
    pixels: IndexedPixels | None = None,
):
    """Fit the single-crystal constants to a measured map of k* (N/m) or M (Pa).

    Grains: the map's labels, else :func:`~contactres.polycrystal.segment_grains`
    (regions of equal surface normal within ``tolerance_deg``). Per grain: the mean and its
    standard error, and the orientation of the mean normal. With ``tipload`` (force and tip
    radius known) the calibration of a stiffness map is c = (6 F R)^{1/3}; else it is free.
    ``pixels`` (:func:`~contactres.polycrystal.indexed_pixels`, default: its rules with their
    defaults): only these pixels enter the fit (a not-indexed pixel's orientation is a
    placeholder).

    Returns
    -------
    (result, labels, n_pixels_used)
    """
    vals = np.asarray(values, dtype=float)
    if vals.shape != omap.shape:
        raise ContactresInputError(
            f"the measured map has shape {vals.shape}, the orientation map {omap.shape}: they "
            "must be on the same grid"
        )
    pixels = indexed_pixels(omap) if pixels is None else pixels
    vals = np.where(pixels.mask, vals, np.nan)
    # A pixel left out has no orientation either: NaN angles keep it out of the grains.
    omap = replace(omap, euler=np.where(pixels.mask[..., None], omap.euler, np.nan))
    labels = omap.labels
    if labels is None:
        labels = segment_grains(omap, lattice, tolerance_deg=tolerance_deg, min_pixels=min_pixels)
    grains = grain_orientations(labels, omap, lattice)
    calibration = None
    if tipload is not None:
        calibration = (
            (6 * tipload.force * tipload.radius) ** (1 / 3) if quantity == "stiffness" else 1.0
        )
    kwargs: dict[str, Any] = {
        "quantity": quantity,
        "tip_modulus": tip_modulus,
        "calibration": calibration,
    }
    if lattice != "cubic":
        kwargs["lattice"] = lattice
    result = fit_map(labels, vals, grains.matrices, **kwargs)
    used = int(np.sum((labels >= 0) & np.isfinite(vals)))
    return result, labels, used


def fit_record(result, **context) -> dict:
    """The fit as JSON text (``"json"``: every field, arrays as lists, undetermined values as
    null, with the conventions) and a flat record of its scalars (``"flat"``)."""
    import dataclasses
    import json

    def clean(v):
        if isinstance(v, np.ndarray):
            return [clean(x) for x in v.tolist()]
        if isinstance(v, (list, tuple)):
            return [clean(x) for x in v]
        if isinstance(v, (float, np.floating)):
            v = float(v)
            return v if math.isfinite(v) else None
        if isinstance(v, np.integer | np.bool_):
            return v.item()
        return v

    fields = {f.name: clean(getattr(result, f.name)) for f in dataclasses.fields(result)}
    conventions = {
        "ratios": "C_ij/C11, dimensionless; C11 in Pa",
        "errors": "one standard error (covariance inflated by chi2/dof when > 1)",
        "null": "not determined (see warnings): never reported as a value",
        "values": "per grain: mean of the pixels and its standard error",
    }
    doc = {"conventions": conventions, **{k: clean(v) for k, v in context.items()}, **fields}
    flat = {k: v for k, v in doc.items() if not isinstance(v, (dict, list))}
    # The warnings (a list) are kept in the flat record as one text: a fit that did not
    # converge or is at a bound says so in every format (issue 27).
    flat["warnings"] = "; ".join(doc.get("warnings") or ())
    return {"json": json.dumps(doc, indent=1, allow_nan=False) + "\n", "flat": flat}


# Surface normals whose M bounds a crystal's from below: the cube axes, face and body diagonals
# (the extremes of a cubic crystal's M) and the c axis and basal directions of a hexagonal one.
_BOUNDING_NORMALS = (
    (0, 0, 1), (1, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 1), (0, 1, 1), (1, 1, 1),
)  # fmt: skip


def check_tip_load(material: Material, tip: TipLoad) -> str:
    """Refuse, before any work, a tip and load whose Hertz contact on the map's softest
    orientation is wider than :data:`contactres.jobs.contact.HERTZ_MAX_RATIO` of the tip
    radius (issue 30: such a map printed moduli of a contact Hertz does not describe; most
    likely a radius or force in the wrong unit). a is :func:`contactres.hertz`'s with E* of the
    smallest M over the cube axes, face and body diagonals in series with the tip. The jobs
    ``maps_predict`` and ``maps_synthetic`` call it before their work (issue 27's closing
    campaign: ``maps synthetic`` made a map of 1 N on a 20 nm tip, a/R = 24, without a word).

    Parameters
    ----------
    material : Material
        The crystal, in its cube (or crystal) axes.
    tip : TipLoad
        Tip radius (m), force (N) and tip modulus (Pa; inf: rigid).

    Returns
    -------
    str
        The flag of a contact wider than
        :data:`~contactres.jobs.contact.HERTZ_APPROXIMATE_RATIO` of the tip radius (Hertz
        approximate, values kept, as ``contact`` flags its rows), else "".
    """
    from ..normal import hertz
    from ..polycrystal import surface_matrices_from_normals
    from .contact import HERTZ_APPROXIMATE_RATIO, HERTZ_MAX_RATIO

    normals = np.asarray(_BOUNDING_NORMALS, dtype=float)
    m_min = float(np.min(indentation_moduli(material, surface_matrices_from_normals(normals))))
    e_star = 1.0 / (1.0 / m_min + (0.0 if math.isinf(tip.tip_modulus) else 1.0 / tip.tip_modulus))
    ratio = hertz(e_star, tip.radius, tip.force, check_validity=False).contact_radius / tip.radius
    if ratio > HERTZ_MAX_RATIO:
        raise ContactresInputError(
            f"--tip-radius {tip.radius:g} m and --force {tip.force:g} N give a Hertz contact "
            f"radius of {ratio:.3g} times the tip radius on the softest orientation (M = "
            f"{m_min:.3g} Pa): beyond Hertz (a/R > {HERTZ_MAX_RATIO:g}); check their units"
        )
    if ratio > HERTZ_APPROXIMATE_RATIO:
        return (
            f"a/R = {ratio:.3g} > {HERTZ_APPROXIMATE_RATIO:g} on the softest orientation (M = "
            f"{m_min:.3g} Pa): Hertz approximate; the map's values are kept (Hertz takes the "
            "tip as a paraboloid, for a ≪ R)"
        )
    return ""
