"""Job ``contact``: Hertz contact of a rigid sphere on a crystal face (paper 1, Eqs. 1-4; an
ellipse on a face without 3- or 4-fold symmetry), and its normal and tangential stiffness,
static or at a frequency; on a bare or a coated face.

Inputs: the solid in the frame of its face (a :class:`~contactres.materials.Material`, z the
inward normal), or a coated one (a :class:`~contactres.LayeredMaterial`). Settings: sphere
radius, force and frequency (broadcast), the tangential stiffness on or off, the direction of
the tangential motion, and a coating of built-in films put on the face (``coating``, parsed by
:func:`parse_coating`). The static contact is :func:`contactres.sphere_contact`; on a bare face
the dynamic normal stiffness is :func:`contactres.dynamic_contact_stiffness` (exact model,
lossless solid) and the tangential one :func:`contactres.tangential_contact_stiffness` (relaxed
contact, rigid disk of radius a); on a coated face both are :func:`contactres.flat_punch_stiffness`
of the stack at the contact radius (normal: frictionless; tangential: bonded and relaxed, the
stack turned so that its x axis is the direction of the motion), static or at the frequency.

On a bare face the contact is the ellipse of the anisotropic Hertz contact (Willis 1966; a
circle on a face with 3- or 4-fold symmetry): the table gives its semi-axes, ellipticity b/a and
orientation (the major axis, degrees from the surface x axis towards y), and ``contact_radius_m``
is the equivalent radius √(ab), which the dynamic and tangential stiffness (rigid disks) take.
The static normal columns but the orientation do not depend on the in-plane axis
(``--inplane``).

On a coated face the contact is solved with the θ-averaged (axisymmetric) compliance of the
stack (:func:`contactres.sphere_contact` on a :class:`~contactres.LayeredMaterial`): exact for
isotropic layers on a face with 3- or 4-fold symmetry, an approximation elsewhere (there the
coated tangential stiffness is the θ average, the same for every ``direction``, and a film of
the substrate's own material gives back the circle of Hertz with the face's M, not the bare
face's ellipse); the ellipse columns are then left out.

Frequency-dependent (viscoelastic) materials of a stack, e.g. the built-in PMMA, whose power laws
have no relaxed (0 Hz) limit: the static columns use their storage constants at
:data:`STATIC_FREQUENCY_HZ` (1 Hz, the quasi-static modulus their anchors are quoted at), the
dynamic columns their complex constants at the frequency (the correspondence principle). A lossy
Material of a stack (:meth:`~contactres.Material.with_loss`) likewise: its elastic part in the
static columns, its complex constants in the dynamic ones
(:func:`contactres.viscoelastic.static_solid`). The ``warnings`` say which materials' static
columns were taken so.

A bare face takes an undamped Material only: a lossy one is refused, in one line that names
the remedies (the static contact, :func:`contactres.sphere_contact`, needs real constants).
The bare dynamic solvers take the same undamped constants with the loss as one separate
factor Q⁻¹ (``loss=`` of :func:`contactres.dynamic_contact_stiffness` and
:func:`contactres.tangential_contact_stiffness`, which refuse a lossy Material too; this job
sets no loss: its bare dynamic columns are the lossless solid's, radiation only). A Material's
loss need not be one factor (any Im C >= 0), so the bare face does not split a lossy Material
into the two; the layered punch of a coated face takes each material's complex constants as
they are. For the bare face of a lossy solid give its elastic part (``static_solid(m)``); its
damping then appears in no column (the ``dcsf`` job and those solvers take it as ``loss=``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..layered import LayeredMaterial, checked_thickness, thickness_text
from ..materials import Material, require_material
from ..measurements.schema import CONTACT_TABLE
from ..units import HERTZ_APPROXIMATE_RATIO, HERTZ_MAX_RATIO
from ..validation import nonnegative
from ..viscoelastic import STATIC_FREQUENCY_HZ, static_solid
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import pandas as pd

    from ..layered import FrequencyDependentMaterial
    from ..materials import Material

__all__ = [
    "HERTZ_APPROXIMATE_RATIO",
    "HERTZ_MAX_RATIO",
    "MAX_COATING_LAYERS",
    "STATIC_FREQUENCY_HZ",
    "Result",
    "Settings",
    "coating_materials",
    "parse_coating",
    "run",
]

# STATIC_FREQUENCY_HZ (the frequency whose storage constants a viscoelastic layer's static
# columns take) is contactres.viscoelastic's, with static_solid: re-exported here, where the
# job's users have found it.
# More layers than this is a typing slip, not a coating anyone measures.
MAX_COATING_LAYERS = 10
# The a/R rule of Hertz's validity (HERTZ_APPROXIMATE_RATIO, HERTZ_MAX_RATIO) is
# contactres.units': the library's sphere_contact and hertz apply the same one.


@dataclass(frozen=True)
class Settings:
    """The contact to compute.

    Parameters
    ----------
    radius, force : array
        Sphere radius R (m) and normal force F (N); they broadcast with ``frequency``.
    frequency : array or None
        Oscillation frequency f, Hz: adds the dynamic normal (and, with ``tangential``,
        tangential) stiffness; None: static only.
    tangential : bool
        Add the tangential stiffness K_t (N/m).
    direction : float
        Direction of the tangential motion, degrees from the surface x axis.
    coating : tuple
        Films put on the face, top first: each ``"MATERIAL:THICKNESS"`` (thickness in m, e.g.
        ``"pmma:250e-9"``) or a ``(material_name, thickness_m)`` pair, the materials named as in
        :func:`coating_materials` (see :func:`parse_coating`). Empty: the bare face (or the
        stack given as ``inputs``). A lossy Material (:meth:`~contactres.Material.with_loss`)
        is taken in a stack, as its substrate or a layer, and refused as a bare face (module
        docstring).
    """

    radius: np.ndarray
    force: np.ndarray
    frequency: np.ndarray | None = None
    tangential: bool = False
    direction: float = 0.0
    coating: tuple = ()


@dataclass(frozen=True)
class Result(JobResult):
    """One row per (R, F, f): ``table`` (columns in SI units but the orientation in degrees,
    named with them: :data:`contactres.measurements.schema.CONTACT_TABLE`), and whether the
    contact is circular (the face has 3- or 4-fold symmetry) with the relative 2nd harmonic of
    its compliance, ``noncircularity`` (on a coated face: those of the substrate's face).
    ``warnings``: notes for the user (with a viscoelastic material in the stack: its static
    columns use its storage constants at :data:`STATIC_FREQUENCY_HZ`; with a lossy Material:
    they use its elastic part, its loss is in the dynamic columns only). A lossy Material as a
    bare face is refused (module docstring)."""

    SCHEMAS = MappingProxyType({"table": CONTACT_TABLE})

    table: pd.DataFrame
    circular: bool
    noncircularity: float
    warnings: tuple[str, ...] = ()


@one_blas_thread()
def run(
    inputs: Material | LayeredMaterial, settings: Settings, progress: Progress | None = None
) -> Result:
    """The contact of ``settings`` on the face ``inputs``, bare or coated (module docstring)."""
    import pandas as pd

    from ..materials import require_material
    from ..normal import sphere_contact

    m, s = inputs, settings
    stack = _coated(m, s.coating)
    freq = np.zeros(1) if s.frequency is None else s.frequency
    try:
        # At least one row: single values from Python (floats) make a table of one row.
        R, F, f = (np.atleast_1d(x) for x in np.broadcast_arrays(s.radius, s.force, freq))
    except ValueError:
        raise ContactresInputError(
            "radius, force and frequency must have the same number of values, or single values"
        ) from None
    if s.frequency is not None:
        f = np.asarray(nonnegative("frequency", f, "Hz"), dtype=float)
    if s.frequency is not None and not _has_densities(m if stack is None else stack):
        raise ContactresInputError(
            "a dynamic stiffness (frequency) needs the density of the solid (a --crystal on the "
            "command line)"
        )
    if not math.isfinite(s.direction):
        raise ContactresInputError(
            f"direction (--direction) must be a finite angle in degrees, got {s.direction!r}"
        )
    if s.direction != 0.0 and not s.tangential:
        raise ContactresInputError(
            "direction (--direction) is the direction of the tangential motion: set tangential "
            "(--tangential)"
        )
    if stack is not None:
        return _run_coated(stack, R, F, f, s, progress)
    if require_material(m).is_lossy:
        # Said here, not by sphere_contact deep inside ("drop with_loss"): dropping the loss
        # also drops the damping, which this job's bare columns cannot take (module docstring).
        raise ContactresInputError(
            "the contact job's bare face takes an undamped Material (real constants); the "
            "Material given is lossy (complex constants): give its elastic part "
            "(contactres.viscoelastic.static_solid(m)), whose bare dynamic columns are the "
            "lossless solid's (its damping as loss=Q⁻¹ in contactres.dynamic_contact_stiffness "
            "or the dcsf job), or put the face under a coating (coating=), whose dynamic "
            "columns take its complex constants"
        )
    say(progress, "static contact")
    # The job flags a/R itself (flags column, empty rows): no warning from the library.
    c = sphere_contact(require_material(m), R, F, check_validity=False)  # homogeneous only
    wide = _too_wide(c.contact_radius, R)
    # A contact beyond Hertz's validity gets no dynamic stiffness either (its k_s a may lie
    # far outside every solver's range): it is computed as no contact, then left empty.
    F_valid = np.where(wide, 0.0, F)
    table = pd.DataFrame(
        {
            "radius_m": R,
            "force_N": F,
            "contact_radius_m": c.contact_radius,
            "semi_major_m": c.semi_major,
            "semi_minor_m": c.semi_minor,
            "ellipticity": c.ellipticity,
            "orientation_deg": math.degrees(c.orientation),
            "peak_pressure_Pa": c.peak_pressure,
            "depth_m": c.depth,
            "stiffness_N_per_m": c.stiffness,
            "indentation_modulus_Pa": c.indentation_modulus,
        }
    )
    if s.frequency is not None:
        say(progress, "dynamic stiffness")
        _add_dynamic(table, m, R, F_valid, f, s.tangential, s.direction)
    elif s.tangential:
        table["tangential_stiffness_N_per_m"] = _tangential(
            m, np.where(wide, 0.0, c.contact_radius), 0.0, s.direction
        ).real
    return Result(
        table=_flag_wide(table, wide),
        circular=bool(c.circular),
        noncircularity=float(c.noncircularity),
        warnings=_wide_warnings(table),
    )


def _too_wide(contact_radius, radius) -> np.ndarray:
    """Where a/R exceeds :data:`HERTZ_MAX_RATIO` (a boolean array of the rows)."""
    a = np.atleast_1d(np.asarray(contact_radius, dtype=float))
    return np.asarray(a > HERTZ_MAX_RATIO * np.atleast_1d(radius), dtype=bool)


# Columns a contact beyond Hertz's validity keeps: what the user gave, not what was computed.
_GIVEN = ("radius_m", "force_N", "frequency_Hz", "coating")


def _ratio(table) -> np.ndarray:
    """a/R of every row (NaN without contact radius)."""
    return table["contact_radius_m"].to_numpy(dtype=float) / table["radius_m"].to_numpy(float)


def _flag_wide(table, wide: np.ndarray):
    """``table`` with a ``flags`` column where a/R > :data:`HERTZ_APPROXIMATE_RATIO` (only then:
    a table of small contacts is unchanged), and the computed values of the rows ``wide`` left
    empty (NaN)."""
    ratio = _ratio(table)
    approximate = ratio > HERTZ_APPROXIMATE_RATIO
    if not approximate.any():
        return table
    table = table.copy()
    for col in table.columns:
        if col not in _GIVEN:
            table[col] = table[col].where(~wide, np.nan)
    table["flags"] = [
        f"a/R = {r:.3g} > {HERTZ_MAX_RATIO:g}: beyond Hertz, no value"
        if w
        else (f"a/R = {r:.3g} > {HERTZ_APPROXIMATE_RATIO:g}: Hertz approximate" if x else "")
        for r, w, x in zip(ratio, wide, approximate, strict=True)
    ]
    return table


def _wide_warnings(table) -> tuple[str, ...]:
    """A line on the rows beyond :data:`HERTZ_MAX_RATIO` (left empty) and one on those beyond
    :data:`HERTZ_APPROXIMATE_RATIO` (kept); none when every contact is small."""
    ratio = _ratio(table)
    lines = []
    for low, high, what, advice in (
        (
            HERTZ_MAX_RATIO,
            np.inf,
            "beyond Hertz's validity are left empty",
            "check the sphere radius (m) and the force (N)",
        ),
        (
            HERTZ_APPROXIMATE_RATIO,
            HERTZ_MAX_RATIO,
            "where Hertz is approximate are flagged",
            "their values are kept: Hertz takes the sphere as a paraboloid, for a ≪ R",
        ),
    ):
        rows = (ratio > low) & (ratio <= high)
        if rows.any():
            worst = int(np.nanargmax(np.where(rows, ratio, -np.inf)))
            lines.append(
                f"{int(rows.sum())} of {rows.size} rows {what} (a/R up to {ratio[worst]:.3g} > "
                f"{low:g} at R = {table['radius_m'].iat[worst]:.3g} m, F = "
                f"{table['force_N'].iat[worst]:.3g} N); {advice}"
            )
    return tuple(lines)


def _add_dynamic(table, m, R, F, f, tangential: bool, direction: float) -> None:
    """The dynamic normal (and tangential) stiffness columns at the frequencies ``f``."""
    from ..dynamic import dynamic_contact_stiffness, normalised_wavenumber, wave_modulus

    # F = 0 stands for no contact (also a contact beyond Hertz's validity: run).
    a = np.where(np.asarray(F) > 0, table["contact_radius_m"].to_numpy(dtype=float), 0.0)
    table["frequency_Hz"] = f
    table["ks_a"] = normalised_wavenumber(f, a, m.density, wave_modulus(m, "shear"))
    kn = dynamic_contact_stiffness(m, R, F, f)
    table["dynamic_stiffness_real_N_per_m"] = np.real(kn)
    table["dynamic_stiffness_imag_N_per_m"] = np.imag(kn)
    if tangential:
        kt = _tangential(m, a, f, direction)
        table["tangential_stiffness_real_N_per_m"] = kt.real
        table["tangential_stiffness_imag_N_per_m"] = kt.imag
        # No contact (F = 0): no loss tangent (NaN, printed empty), not a division warning.
        loss = np.full(kt.shape, np.nan)
        np.divide(kt.imag, kt.real, out=loss, where=kt.real > 0)
        table["tangential_loss_tangent"] = loss


def _tangential(m, a, f, direction: float):
    """K_t at contact radii ``a`` and frequencies ``f`` (broadcast); 0 where a = 0 (F = 0)."""
    from ..dynamic import tangential_contact_stiffness

    a, f = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(f, dtype=float))
    out = np.zeros(a.shape, dtype=complex)
    touching = a > 0
    if touching.any():
        out[touching] = tangential_contact_stiffness(m, a[touching], f[touching], direction)
    return out


# ------------------------------------------------------------------------------ coated faces
def coating_materials() -> tuple[str, ...]:
    """The built-in names a coating layer may take: ``pmma`` (the viscoelastic
    :func:`contactres.pmma`) and the isotropic solids of :func:`contactres.crystal_names`
    (amorphous or polycrystalline films, the same in every frame)."""
    from ..crystals import crystal_names, crystal_record

    return ("pmma", *(n for n in crystal_names() if crystal_record(n).symmetry == "isotropic"))


def _coating_material(name: str):
    """The material of the coating name ``name`` (case-insensitive)."""
    from ..viscoelastic import pmma

    key = name.strip().lower()
    known = coating_materials()
    if key == "pmma":
        return pmma()
    for n in known[1:]:
        if n.lower() == key:
            return Material.crystal(n)
    raise ContactresInputError(
        f"unknown coating material {name!r} (--coating); known: {', '.join(known)}"
    )


def _thickness(text, spec) -> float:
    """A layer's thickness in m from ``text`` (a number, its text, or a number with its unit,
    ``250nm``, converted with pint as every option's), checked by the one rule of contactres
    (:func:`contactres.layered.checked_thickness`)."""
    try:
        h = float(text)
    except (TypeError, ValueError):
        h = math.nan
        from ..typed_units import has_unit, to_si

        if isinstance(text, str) and has_unit(text):
            h = to_si(text, "m", f"coating thickness (--coating {spec})")
    if not (math.isfinite(h) and h > 0):
        raise ContactresInputError(
            f"coating thickness (--coating {spec}) must be a positive finite number in m (or "
            f"with its unit, e.g. 250nm), got {text!r}"
        )
    return checked_thickness(h, f"coating thickness (--coating {spec})")


def parse_coating(
    coating, *, static: bool = False
) -> tuple[tuple[Material | FrequencyDependentMaterial, float], ...]:
    """The layers of a coating, top first, as (material, thickness_m) pairs for
    :class:`~contactres.LayeredMaterial`.

    Parameters
    ----------
    coating : sequence
        Each item ``"MATERIAL:THICKNESS"`` (the command line's ``--coating``; thickness in m)
        or a ``(material_name, thickness_m)`` pair (one string alone: one layer); at most
        :data:`MAX_COATING_LAYERS` items. Material names: :func:`coating_materials`
        (case-insensitive).
    static : bool
        Keyword only: every material with its static constants instead
        (:func:`contactres.viscoelastic.static_solid`: a frequency-dependent one its storage
        constants at :data:`STATIC_FREQUENCY_HZ`, real: the undamped solid of a static
        contact).

    Returns
    -------
    tuple of (Material or ViscoelasticMaterial, float)
        ``pmma`` is :func:`contactres.pmma` (frequency dependent); the others
        ``Material.crystal(name)``.

    Raises
    ------
    ContactresInputError
        One line naming ``--coating``: an unknown material (the known ones listed), a missing
        colon, a thickness that is not a positive finite number of metres or is above
        :data:`contactres.layered.MAX_THICKNESS_M` (1 m), too many layers.

    Examples
    --------
    >>> from contactres.jobs.contact import parse_coating
    >>> [(m.name, h) for m, h in parse_coating(["pmma:250e-9", "fused-silica:1e-7"])]
    [('PMMA', 2.5e-07), ('fused-silica', 1e-07)]
    """
    # One layer given as a bare string (Python API) is one item, not its characters.
    items = (coating,) if isinstance(coating, str) else tuple(coating)
    if len(items) > MAX_COATING_LAYERS:
        raise ContactresInputError(
            f"at most {MAX_COATING_LAYERS} coating layers (--coating), got {len(items)}"
        )
    layers = []
    for item in items:
        if isinstance(item, str):
            name, colon, thickness = item.partition(":")
            if not colon:
                raise ContactresInputError(
                    f"coating (--coating {item}) must be MATERIAL:THICKNESS with the thickness "
                    "in m, e.g. pmma:250e-9"
                )
            spec = item
        elif isinstance(item, (tuple, list)) and len(item) == 2 and isinstance(item[0], str):
            name, thickness = item
            spec = f"{name}:{thickness}"
        else:
            raise ContactresInputError(
                "each coating layer (--coating) must be 'MATERIAL:THICKNESS' or a "
                f"(material_name, thickness_m) pair, got {item!r}"
            )
        m = _coating_material(name)
        layers.append((static_solid(m) if static else m, _thickness(thickness, spec)))
    return tuple(layers)


def _coated(inputs, coating) -> LayeredMaterial | None:
    """The coated solid: ``inputs`` under the layers of ``coating``, or ``inputs`` if it is a
    stack already; None for a bare face."""
    if isinstance(inputs, LayeredMaterial):
        if coating:
            raise ContactresInputError(
                "give the coating either as the layers of the LayeredMaterial or as the "
                "coating setting (--coating), not both"
            )
        return inputs if inputs.layers else None
    if not coating:
        return None
    return LayeredMaterial(inputs, parse_coating(coating))


def _has_densities(m) -> bool:
    """Whether every material of ``m`` (a solid or a stack) has a density."""
    materials = m.materials if isinstance(m, LayeredMaterial) else (m,)
    return all(getattr(x, "density", None) is not None for x in materials)


def _coating_label(stack: LayeredMaterial) -> str:
    """E.g. ``"PMMA 250 nm"``, ``"PMMA 1.5 µm on fused-silica 2 mm"``; layers top first,
    joined by "on" (each thickness in the unit that reads best: nm, µm, mm or m)."""
    return " on ".join(
        f"{getattr(m, 'name', None) or 'film'} {thickness_text(h)}" for m, h in stack.layers
    )


def _run_coated(stack: LayeredMaterial, R, F, f, s: Settings, progress) -> Result:
    """The rows of ``run`` on a coated face (module docstring)."""
    import pandas as pd

    from ..dynamic import flat_punch_stiffness
    from ..normal import sphere_contact

    dynamic = s.frequency is not None
    static = LayeredMaterial(
        static_solid(stack.substrate), tuple((static_solid(m), h) for m, h in stack.layers)
    )
    say(progress, "static contact, bare and coated")
    bare = sphere_contact(static.substrate, R, F, check_validity=False)  # a/R: flagged by run
    c = sphere_contact(static, R, F, check_validity=False)
    k, k_bare = np.asarray(c.stiffness, dtype=float), np.asarray(bare.stiffness, dtype=float)
    # No contact (F = 0): no share (NaN, printed empty), not a division warning.
    share = np.full(k.shape, np.nan)
    np.divide(k_bare - k, k_bare, out=share, where=k_bare > 0)
    a = np.asarray(c.contact_radius, dtype=float)
    table = pd.DataFrame(
        {
            "radius_m": R,
            "force_N": F,
            "contact_radius_m": a,
            "peak_pressure_Pa": c.peak_pressure,
            "depth_m": c.depth,
            "stiffness_N_per_m": k,
            "indentation_modulus_Pa": c.indentation_modulus,
            "coating": _coating_label(stack),
            "film_share": share,
        }
    )
    wide = _too_wide(a, R)
    # A contact beyond Hertz's validity is computed as no contact, then left empty (run).
    touching = (a > 0) & ~wide
    kt = np.zeros(a.shape, dtype=complex)
    # The layered punch moves along the surface x axis: turn the stack so x is the direction.
    turn = math.radians(s.direction)
    inplane = (math.cos(turn), math.sin(turn), 0)
    if s.tangential and touching.any():
        solid = static.rotated((0, 0, 1), inplane)
        kt[touching] = flat_punch_stiffness(solid, a[touching], 0.0, "tangential")
    if dynamic:
        from ..dynamic import normalised_wavenumber, wave_modulus

        say(progress, "dynamic stiffness")
        sub = require_material(static.substrate)  # evaluated: a Material
        table["frequency_Hz"] = f
        table["ks_a"] = normalised_wavenumber(f, a, sub.density, wave_modulus(sub, "shear"))
        kn = k.astype(complex)  # f = 0: the static stiffness; a = 0: no contact, 0
        moving = touching & (f > 0)
        # The tangential punch first: its range (k_s a <= 5) is checked before the longer
        # normal one. f = 0: the static K_t; a = 0: no contact, 0.
        if s.tangential and moving.any():
            turned = stack.rotated((0, 0, 1), inplane)
            kt[moving] = flat_punch_stiffness(turned, a[moving], f[moving], "tangential")
        if moving.any():
            kn[moving] = flat_punch_stiffness(stack, a[moving], f[moving])
        table["dynamic_stiffness_real_N_per_m"] = kn.real
        table["dynamic_stiffness_imag_N_per_m"] = kn.imag
        if s.tangential:
            table["tangential_stiffness_real_N_per_m"] = kt.real
            table["tangential_stiffness_imag_N_per_m"] = kt.imag
            # No contact (F = 0): no loss tangent (NaN, printed empty), as on a bare face.
            loss = np.full(kt.shape, np.nan)
            np.divide(kt.imag, kt.real, out=loss, where=kt.real > 0)
            table["tangential_loss_tangent"] = loss
    elif s.tangential:
        table["tangential_stiffness_N_per_m"] = kt.real
    return Result(
        table=_flag_wide(table, wide),
        circular=bool(getattr(bare, "circular", True)),
        noncircularity=float(getattr(bare, "noncircularity", 0.0)),
        warnings=_static_notes(stack, dynamic) + _wide_warnings(table),
    )


def _static_notes(stack: LayeredMaterial, dynamic: bool) -> tuple[str, ...]:
    """A line naming the viscoelastic materials of ``stack`` (static columns: their storage
    constants at :data:`STATIC_FREQUENCY_HZ`) and one naming its lossy Materials (static
    columns: their elastic part); none for an undamped stack."""
    # Unnamed: a layer is "film" (as in the coating column), the substrate "substrate".
    named = [(m, getattr(m, "name", None) or "film") for m, _ in stack.layers]
    named.append((stack.substrate, getattr(stack.substrate, "name", None) or "substrate"))
    viscous = [name for m, name in named if not isinstance(m, Material)]
    lossy = [name for m, name in named if isinstance(m, Material) and m.is_lossy]
    notes = []
    if viscous:
        notes.append(
            f"the static columns use the storage modulus at {STATIC_FREQUENCY_HZ:g} Hz of "
            f"{', '.join(viscous)} (viscoelastic)"
            + ("; the dynamic ones its modulus at the frequency" if dynamic else "")
        )
    if lossy:
        # The loss a static column leaves out, said as the viscoelastic one's is.
        notes.append(
            f"the static columns use the elastic part (real constants) of {', '.join(lossy)} "
            "(lossy), without its loss"
            + ("; the dynamic ones its complex constants" if dynamic else "")
        )
    return tuple(notes)
