"""The elastodynamic share of the measured contact damping: sound radiated from the contact.

A contact shaken tangentially at the QCM's frequency (15 MHz at the 3rd overtone of a 5 MHz
crystal) radiates shear, longitudinal and Rayleigh waves into the sphere and into the plate
(issue 13). Its complex tangential stiffness K(ω) = Re K (1 + i tan δ_rad) has a loss tangent
tan δ_rad ≈ 0.6 k_s a per body (k_s the shear wave number, a the contact radius) even for a
contact that neither slips nor loses energy in its materials.
:func:`contactres.dynamic.two_body_contact_stiffness` gives K of a rigid
disk of radius a between two half-spaces (compliances in series; a ≪ R). For every load of an
analysed study, :func:`radiation_loss` evaluates it at

* the contact radius of the group's JKR fit (paper 2, Eq. 9 with E* from Eq. 10, E1 = E2 = E
  and ν of the fit, paper 2's γ: work of adhesion w = 2γ),
  a³ = (3R/4E*) [F + 6πγR + √(12πγRF + (6πγR)²)]
  (:func:`contactres.normal.jkr_contact_radius`), and
* the frequency of the overtone, f = ``fundamental_Hz`` x ``overtone`` of the load's sweeps,

and compares it with the measured loss tangent ΔΓ0/Δf0 = ωξ/κ (``loss_tangent_mean`` of
``loads.csv``: the mean over experiments of each experiment's mean of its used sweeps).

**Why a ratio of loss tangents is a fraction of ΔΓ0.** Paper 2, Eq. 2 maps the complex contact
stiffness linearly, with one real factor P, to the shifts: Δf0 + iΔΓ0 = P (κ + iωξ). Losses
that act in parallel in the contact add in ωξ. The radiation adds ωξ_rad = Im K = κ tan δ_rad at
the measured (fixed) κ, hence ΔΓ_rad = P κ tan δ_rad, and

    ΔΓ_rad / ΔΓ0 = κ tan δ_rad / ωξ = tan δ_rad / tan δ_measured   (``radiation_share``).

Only the loss tangent comes from the model: the share does not depend on whether the model's
absolute stiffness (from the tabulated constants of the two bodies) equals the measured κ.

**Dynamic softening.** Re K(ω)/K₀ − 1 (K₀ = K at f = 0, the static stiffness of the same model)
is the change of the elastic part with frequency. The JKR + Mindlin fit treats κ as the static
stiffness; with κ = E^(2/3) h(F_N, γ) (E enters paper 2, Eqs. 7-10 only as this power) a factor
s = Re K/K₀ common to all loads biases E by s^(3/2) (relative change of the static E ≈ −(3/2)
(s − 1) to first order) and leaves γ alone. Since s depends on a, i.e. on the load, E is refitted
instead: κ / s per point with :func:`contactres.analysis.fit_jkr_mindlin`, the group's own
fit (``E_static_corrected_Pa``, ``E_relative_change``). The radius stays that of the uncorrected
fit (a second-order effect).

**Coated plate** (``coating``, issue 26). With a film on the plate the contact radius of each
load is the coated fit's (``contact_radius_m`` of the group's ``coating`` record,
:func:`contactres.analysis._coating.apply_coating`), and the plate's tangential stiffness is the
dynamic punch on the stack, K_p = :func:`contactres.flat_punch_stiffness` (plate under the
film(s), radius a, f, "tangential"; K_xx, along the shear direction), each film at the overtone
frequency. The sphere's is the same half-space stiffness as without a film
(:func:`contactres.dynamic.tangential_contact_stiffness`, the body stiffness of
:func:`~contactres.dynamic.two_body_contact_stiffness`), and K⁻¹ = K_p⁻¹ + K_sphere⁻¹.
Approximation, stated: the compliances of the two bodies in series at the same radius a (each
body with the traction of its own bonded punch, not the common traction of the pair; for a
bare plate two_body_contact_stiffness measured < 1e-6 at a <= 8 µm; a soft film makes the two
tractions differ more: in statics the series is 0.3-1 % stiffer than the shared traction for
250 nm of PMMA at a/h = 5-40, :mod:`contactres.analysis._coating`), and only
the x component of the plate's stiffness (its xy coupling, ~1e-16 relative for the AT-cut
quartz, is left out). K₀ is the static punch (f = 0) on the same stack with each film's storage
constants at the overtone frequency, so that the softening is the inertia's alone, not the
film's viscoelastic dispersion. A lossy film (e.g. :func:`contactres.pmma`) adds its own
material loss to Im K: tan δ_rad is then the loss tangent of radiation and film together. The E
refit is not done on a coated plate (the refit would need the coated law of the fit:
``E_static_corrected_Pa`` NaN, said in ``note``), and ``plate_material`` names the film, e.g.
"quartz-AT coated with PMMA 250 nm".

Limits: both bodies are half-spaces (no curvature of the sphere, no finite thickness of the
plate, whose thickness is about one shear wavelength at 15 MHz), the contact is a bonded rigid
disk (no slip, no normal traction), and the bodies' constants are the tabulated ones (not the
fitted E). Paper 2: J. Vlachová, R. König, D. Johannsmann, Beilstein J. Nanotechnol. 6, 845-856
(2015), doi:10.3762/bjnano.6.87.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from ..crystals import crystal_names
from ..errors import ContactresInputError
from ..materials import Material, at_cut_quartz
from ..measurements.schema import RADIATION_RESULTS
from ..normal import effective_modulus, jkr_contact_radius
from ._jkr import fit_jkr_mindlin
from ._loads import LOAD_KEYS

__all__ = [
    "AT_CUT_PLATE",
    "MATERIAL_ALIASES",
    "RADIATION_RESULTS",
    "known_materials",
    "load_frequencies",
    "material_by_name",
    "radiation_for",
    "radiation_loss",
    "radiation_summary",
]

#: The plate name that means :func:`contactres.materials.at_cut_quartz` (x = the shear direction).
AT_CUT_PLATE = "quartz-AT"
#: Short names of built-in solids.
MATERIAL_ALIASES = {"glass": "soda-lime-glass"}
# Relative accuracy of the stiffness on a coated plate: a share needs far less than the bare
# plate's 1e-6.
_COATED_RTOL = 1e-4


def known_materials(role: str = "sphere") -> list[str]:
    """The names :func:`material_by_name` accepts for ``role`` ("sphere" or "plate")."""
    if role not in ("sphere", "plate"):
        raise ContactresInputError(f"role must be 'sphere' or 'plate', got {role!r}")
    first = [AT_CUT_PLATE] if role == "plate" else []
    return [*first, *MATERIAL_ALIASES, *crystal_names()]


def material_by_name(name: str, role: str = "sphere") -> Material:
    """The solid called ``name`` (case-insensitive), its ``name`` attribute the canonical label.

    ``role="plate"`` also accepts ``quartz-AT``: :func:`contactres.materials.at_cut_quartz`, the
    QCM plate in its surface frame (x = the crystal's X axis, the thickness-shear direction).
    Other names are the built-in solids (``contactres crystals``) in their crystal frame, and
    ``glass`` (soda-lime glass). Raises ValueError naming the known ones.
    """
    known = known_materials(role)
    key = str(name).strip().lower()
    if role == "plate" and key == AT_CUT_PLATE.lower():
        return dataclasses.replace(at_cut_quartz(), name=AT_CUT_PLATE)
    key = MATERIAL_ALIASES.get(key, key)
    for candidate in crystal_names():
        if candidate.lower() == key:
            return Material.crystal(candidate)
    raise ContactresInputError(f"unknown {role} material {name!r}; known: {', '.join(known)}")


def _material(m: Material | str, role: str) -> Material:
    return material_by_name(m, role) if isinstance(m, str) else m


def load_frequencies(sweeps: pd.DataFrame, loads: pd.DataFrame) -> np.ndarray:
    """f = ``fundamental_Hz`` x ``overtone`` of the used sweeps of each load, Hz (rows of
    ``loads``); NaN where a load has no used sweep or its sweeps were measured at several
    frequencies."""
    used = sweeps[sweeps["used"]]
    f = used["fundamental_Hz"].to_numpy(float) * used["overtone"].to_numpy(float)
    span = used[LOAD_KEYS].assign(f=f).groupby(LOAD_KEYS, sort=False)["f"].agg(["min", "max"])
    one = span["min"].where(span["min"] == span["max"]).rename("f").reset_index()
    merged = loads[LOAD_KEYS].merge(one, on=LOAD_KEYS, how="left", validate="many_to_one")
    return merged["f"].to_numpy(float)


def _radii(loads: pd.DataFrame, groups: Sequence[Mapping]) -> tuple[np.ndarray, np.ndarray]:
    """JKR contact radius of every load from its group's fit (m), and why it is missing."""
    n = len(loads)
    a = np.full(n, np.nan)
    note = np.full(n, "no JKR fit of this configuration and medium", dtype=object)
    config, medium = loads["configuration"].to_numpy(), loads["medium"].to_numpy()
    force = loads["normal_force_N"].to_numpy(float)
    for g in groups:
        member = (config == g["configuration"]) & (medium == g["medium"])
        E, gamma = float(g["E_Pa"]), float(g["gamma_J_m2"])
        if not (np.isfinite(E) and np.isfinite(gamma)):
            why = ", ".join(g.get("checks") or []) or "E not given"
            note[member] = f"no JKR fit ({why})"
            continue
        E_star = effective_modulus(E, float(g["poisson"]))
        R = float(g["sphere_radius_m"])
        note[member] = ""
        try:
            a[member] = jkr_contact_radius(E_star, R, force[member], gamma)
        except ContactresInputError:
            # Some load below the JKR pull-off force: those rows only (a handful of loads).
            for i in np.flatnonzero(member):
                try:
                    a[i] = jkr_contact_radius(E_star, R, force[i], gamma)
                except ContactresInputError:
                    note[i] = "normal force below the JKR pull-off of the fit: no contact radius"
    none = np.isfinite(a) & ~(a > 0)
    note[none] = "contact radius 0 (no contact at this load): no radiation"
    return a, note


def _coated_radii(loads: pd.DataFrame, groups: Sequence[Mapping]):
    """The contact radius of every load from its group's coated fit (m; the ``contact_radius_m``
    per load of the group's ``coating`` record), and why it is missing."""
    n = len(loads)
    a = np.full(n, np.nan)
    note = np.full(n, "no JKR fit of this configuration and medium", dtype=object)
    config, medium = loads["configuration"].to_numpy(), loads["medium"].to_numpy()
    force = loads["normal_force_N"].to_numpy(float)
    for g in groups:
        member = (config == g["configuration"]) & (medium == g["medium"])
        record = g.get("coating") or {}
        radius = {r["normal_force_N"]: r["contact_radius_m"] for r in record.get("loads", [])}
        if not radius:
            why = ", ".join(g.get("checks") or []) or "E not given"
            note[member] = f"no coated JKR fit ({why})"
            continue
        for i in np.flatnonzero(member):
            a[i] = radius.get(force[i], np.nan)
            note[i] = (
                "" if np.isfinite(a[i]) else "no contact radius of the coated fit at this load"
            )
    none = np.isfinite(a) & ~(a > 0)
    note[none] = "contact radius 0 (no contact at this load): no radiation"
    return a, note


def _coated_stiffness(
    sphere: Material, plate: Material, coating, a, f, static: bool = False
) -> np.ndarray:
    """K of the sphere (half-space) and the coated plate in series, N/m, complex (module
    docstring), at the radii ``a`` (m) and overtone frequencies ``f`` (Hz); ``static``: K₀, the
    same at f = 0 with each film's storage constants at ``f``
    (:func:`contactres.viscoelastic.static_solid`)."""
    from ..dynamic import (
        flat_punch_stiffness,
        layered_punch_stiffness,
        tangential_contact_stiffness,
    )
    from ..layered import LayeredMaterial, material_at
    from ..viscoelastic import static_solid

    a, f = np.asarray(a, dtype=float), np.asarray(f, dtype=float)
    out = np.empty(a.shape, dtype=complex)
    # One stack per frequency: a frequency-dependent film is evaluated there.
    film_at = static_solid if static else material_at
    for value in np.unique(f):
        rows = f == value
        stack = LayeredMaterial(plate, [(film_at(m, float(value)), h) for m, h in coating.layers])
        if static:
            # The layered Galerkin at f = 0, not flat_punch_stiffness: that takes the static
            # axisymmetric solver there, whose θ-averaged kernel is 3 % off the exact static
            # punch of an anisotropic plate (quartz-AT) that the bare plate's K₀ is.
            k_plate = layered_punch_stiffness(stack, a[rows], 0.0, "tangential", _COATED_RTOL)
        else:
            k_plate = flat_punch_stiffness(stack, a[rows], value, "tangential", rtol=_COATED_RTOL)
        at = 0.0 if static else float(value)
        k_sphere = tangential_contact_stiffness(sphere, a[rows], at, rtol=_COATED_RTOL)
        out[rows] = 1.0 / (1.0 / np.asarray(k_plate) + 1.0 / np.asarray(k_sphere))
    return out


def _coated_rows(sphere, plate, coating, a, f, valid, note):
    """(K, K₀) of the rows ``valid`` on the coated plate (:func:`_coated_stiffness`), NaN and a
    ``note`` (in place) where the layered solver refuses a row."""
    rows = np.flatnonzero(valid)
    K = np.full(rows.size, np.nan + 0j)
    K0 = np.full(rows.size, np.nan)
    try:
        # All rows at once: the solver prepares each film table once per call.
        K[:] = _coated_stiffness(sphere, plate, coating, a[rows], f[rows])
        K0[:] = _coated_stiffness(sphere, plate, coating, a[rows], f[rows], static=True).real
    except ContactresInputError:
        # Some row beyond the solver's range (e.g. an anisotropic film thin against a on an
        # anisotropic plate): row by row, each refusal said in its note.
        for j, i in enumerate(rows):
            try:
                K[j] = _coated_stiffness(sphere, plate, coating, a[i : i + 1], f[i : i + 1])[0]
                K0[j] = _coated_stiffness(
                    sphere, plate, coating, a[i : i + 1], f[i : i + 1], static=True
                )[0].real
            except ContactresInputError as exc:
                K[j], K0[j] = np.nan, np.nan
                note[i] = f"stiffness not computed: {' '.join(str(exc).split())}"
    return K, K0


def _plate_label(plate: Material, coating) -> str:
    """The plate's name, with the film(s) when coated (e.g. "quartz-AT coated with PMMA
    250 nm")."""
    name = plate.name or "custom"
    return name if coating is None else f"{name} coated with {coating.label}"


def _corrected_modulus(
    points: pd.DataFrame, factor: pd.DataFrame, g: Mapping
) -> tuple[float, float]:
    """E of the group refitted with κ/s per point (s = Re K/K₀ of its load), and the relative
    change against the same fit of the uncorrected κ."""
    ok = np.isfinite(points["kappa_N_per_m"].to_numpy(float))
    ok &= points["kappa_N_per_m"].to_numpy(float) > 0
    pts = points[ok].merge(factor, on="normal_force_N", how="left", validate="many_to_one")
    # Loads without a radiation value (notes say why) are left out of the refit.
    pts = pts[np.isfinite(pts["s"].to_numpy(float))]
    s = pts["s"].to_numpy(float)
    if len(pts) < 3 or pts["normal_force_N"].nunique() < 2:
        return np.nan, np.nan
    F, kappa = pts["normal_force_N"], pts["kappa_N_per_m"].to_numpy(float)
    R, nu = float(g["sphere_radius_m"]), float(g["poisson"])
    base = fit_jkr_mindlin(F, kappa, R, nu).values["E"]
    static = fit_jkr_mindlin(F, kappa / s, R, nu).values["E"]
    change = static / base - 1.0
    return float(g["E_Pa"]) * (1.0 + change), float(change)


def radiation_loss(
    loads: pd.DataFrame,
    groups: Sequence[Mapping],
    sphere: Material | str,
    plate: Material | str,
    *,
    frequency_Hz,
    experiments: pd.DataFrame | None = None,
    coating=None,
) -> pd.DataFrame:
    """The radiation loss of every load next to the measured one (see the module docstring).

    Parameters
    ----------
    loads : one row per (configuration, medium, normal force) with ``loss_tangent_mean`` and
        ``loss_tangent_sem`` (:attr:`contactres.analysis.Results.loads`)
    groups : the JKR fits, one dict per (configuration, medium) with ``E_Pa`` (Pa),
        ``gamma_J_m2`` (J/m²), ``sphere_radius_m`` (m), ``poisson`` and ``checks``
        (:attr:`~contactres.analysis.Results.groups`); NaN E: no radius, NaN row
    sphere, plate : the two bodies (:class:`contactres.Material` with density, each in its own
        surface frame) or names for :func:`material_by_name` (e.g. "soda-lime-glass",
        "quartz-AT")
    frequency_Hz : the overtone frequency f, Hz: one number or one per row of ``loads``
        (:func:`load_frequencies`)
    experiments : the points of the JKR fits, one row per experiment and load, with
        ``kappa_N_per_m`` (:attr:`~contactres.analysis.Results.experiments`); None:
        the loads' ``kappa_N_per_m_mean`` (E is then refitted on the means)
    coating : the film(s) on the plate (:class:`contactres.analysis._coating.Coating`, or what
        :func:`~contactres.analysis._coating.as_coating` takes), or None (bare plate). With
        a coating the groups are the coated fits (their ``coating`` record gives the contact
        radius of each load) and the plate's stiffness is the punch on the stack (module
        docstring)

    Returns
    -------
    pandas.DataFrame
        The columns of :data:`RADIATION_RESULTS`, one row per row of ``loads`` (materials
        labelled by their ``name``). A row without a radius or a frequency, or whose stiffness
        the solver refuses (its ValueError, e.g. k_s a out of range), has NaN values and says
        why in ``note``.
    """
    # The dynamic contact solver and the half-space are imported here, where they are used: an
    # analysis without materials (and the report, which reads this module's schema) loads
    # neither contactres.dynamic nor contactres.halfspace.
    from ..dynamic import KSA_MAX, normalised_wavenumber, two_body_contact_stiffness
    from ..halfspace import shear_reference

    sphere, plate = _material(sphere, "sphere"), _material(plate, "plate")
    if coating is not None:
        from ._coating import as_coating

        coating = as_coating(coating, "radiation_loss(coating=...)")
    n = len(loads)
    f = np.broadcast_to(np.asarray(frequency_Hz, dtype=float), (n,)).copy()
    a, note = _radii(loads, groups) if coating is None else _coated_radii(loads, groups)
    no_f = ~(np.isfinite(f) & (f > 0))
    note[no_f & (note == "")] = "no single overtone frequency (several, or no used sweep)"
    valid = np.isfinite(a) & (a > 0) & ~no_f
    # Rows beyond the solver's range of k_s a (in either body) are left out one by one.
    f_valid, a_valid = np.where(valid, f, 0.0), np.where(valid, a, 0.0)
    for body in (sphere, plate):
        if body.density is None:
            continue
        ksa = normalised_wavenumber(f_valid, a_valid, body.density, shear_reference(body))
        far = valid & (ksa > KSA_MAX)
        note[far] = f"k_s a beyond {KSA_MAX:g} (contact radius or frequency too large)"
        valid &= ~far
    K = np.full(n, np.nan + 0j)
    K0 = np.full(n, np.nan)
    if valid.any() and coating is not None:
        K[valid], K0[valid] = _coated_rows(sphere, plate, coating, a, f, valid, note)
        valid &= np.isfinite(K0)
    elif valid.any():
        # One call for every load, the static K₀ (f = 0) with them: the solver prepares each
        # material once per call.
        m = int(valid.sum())
        try:
            both = two_body_contact_stiffness(
                sphere,
                plate,
                np.concatenate([a[valid], a[valid]]),
                np.concatenate([f[valid], np.zeros(m)]),
            )
        except ContactresInputError as exc:  # e.g. k_s a beyond the solver's range: per row
            note[valid] = f"stiffness not computed: {' '.join(str(exc).split())}"
            valid[:] = False
        else:
            both = np.atleast_1d(both)
            K[valid], K0[valid] = both[:m], both[m:].real
    measured = loads["loss_tangent_mean"].to_numpy(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        tan_rad = K.imag / K.real
        share = np.where(measured > 0, tan_rad / measured, np.nan)
        soft = K.real / K0 - 1.0
    no_measure = valid & ~(measured > 0)
    note[no_measure] = "measured loss tangent missing or <= 0: no share"
    # A share above 1 is no answer: the radiation cannot exceed the whole measured damping.
    over = valid & np.isfinite(share) & (share > 1)
    note[over] = (
        "radiation loss above the measured one: the model's assumptions (half-space plate, "
        "bonded rigid contact, tabulated constants, JKR radius) do not hold here"
    )
    out = (
        loads[LOAD_KEYS]
        .reset_index(drop=True)
        .assign(
            sphere_material=sphere.name or "custom",
            plate_material=_plate_label(plate, coating),
            frequency_Hz=f,
            contact_radius_m=a,
            stiffness_static_N_per_m=K0,
            stiffness_real_N_per_m=K.real,
            stiffness_imag_N_per_m=K.imag,
            tan_delta_rad=tan_rad,
            tan_delta_measured=measured,
            tan_delta_measured_sem=loads["loss_tangent_sem"].to_numpy(float),
            radiation_share=np.where(np.isfinite(share), share, np.nan),
            dynamic_softening=soft,
            E_Pa=np.nan,
            E_static_corrected_Pa=np.nan,
            E_relative_change=np.nan,
            note=note,
        )
    )
    points = loads.rename(columns={"kappa_N_per_m_mean": "kappa_N_per_m"})
    points = points if experiments is None else experiments
    for g in groups:
        rows = (out["configuration"] == g["configuration"]) & (out["medium"] == g["medium"])
        rows = rows.to_numpy()
        out.loc[rows, "E_Pa"] = float(g["E_Pa"])
        if not (rows & valid).any():
            continue
        if coating is not None:
            # The refit needs the coated law of the fit (module docstring): not done.
            out.loc[rows & valid, "note"] = out.loc[rows & valid, "note"].map(
                lambda t: "; ".join(x for x in (t, "E not refitted on a coated plate") if x)
            )
            continue
        mine = (points["configuration"] == g["configuration"]) & (points["medium"] == g["medium"])
        factor = pd.DataFrame(
            {"normal_force_N": out.loc[rows, "normal_force_N"], "s": 1.0 + soft[rows]}
        )
        E_static, change = _corrected_modulus(points[mine.to_numpy()], factor, g)
        out.loc[rows, "E_static_corrected_Pa"] = E_static
        out.loc[rows, "E_relative_change"] = change
    return out[list(RADIATION_RESULTS.names)]


def radiation_for(
    results, sphere: Material | str, plate: Material | str, coating=None
) -> pd.DataFrame:
    """:func:`radiation_loss` of an analysed study (:class:`~.results.Results`), with the
    frequency of each load from its sweeps and the E refit on the points of the JKR fit
    (``coating``: the film(s) of a study analysed with that coating, as :func:`radiation_loss`).

    For a study analysed without materials:
    ``dataclasses.replace(res, radiation=radiation_for(res, "glass", "quartz-AT"))`` adds the
    table that :func:`contactres.write_report` writes as ``radiation.csv``.
    """
    return radiation_loss(
        results.loads,
        results.groups,
        sphere,
        plate,
        frequency_Hz=load_frequencies(results.sweeps, results.loads),
        experiments=results.experiments,
        coating=coating,
    )


def _range(values) -> list[float] | None:
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return [float(v.min()), float(v.max())] if v.size else None


def _median(values) -> float:
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(np.median(v)) if v.size else np.nan


def radiation_summary(table: pd.DataFrame) -> list[dict]:
    """Per (configuration, medium) of a :func:`radiation_loss` table: the materials, the ranges
    of a (m) and tan δ_rad, the medians of tan δ_rad, of the share and of the softening, and the
    corrected E (NaN where nothing was computed, ``note`` says why)."""
    out = []
    for (config, medium), part in table.groupby(["configuration", "medium"], sort=True):
        notes = sorted({str(x) for x in part["note"] if str(x)})
        out.append(
            {
                "configuration": config,
                "medium": medium,
                "sphere_material": str(part["sphere_material"].iloc[0]),
                "plate_material": str(part["plate_material"].iloc[0]),
                "n_loads": int(np.isfinite(part["tan_delta_rad"].to_numpy(float)).sum()),
                "contact_radius_range_m": _range(part["contact_radius_m"]),
                "tan_delta_rad_range": _range(part["tan_delta_rad"]),
                "tan_delta_rad_median": _median(part["tan_delta_rad"]),
                "radiation_share_range": _range(part["radiation_share"]),
                "radiation_share_median": _median(part["radiation_share"]),
                "dynamic_softening_median": _median(part["dynamic_softening"]),
                "E_Pa": float(part["E_Pa"].iloc[0]),
                "E_static_corrected_Pa": float(part["E_static_corrected_Pa"].iloc[0]),
                "E_relative_change": float(part["E_relative_change"].iloc[0]),
                "note": "; ".join(notes),
            }
        )
    return out
