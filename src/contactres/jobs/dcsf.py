"""Job ``dcsf``: the dynamic contact stiffness factor DCSF = K_da/K_sa of a rigid sphere on a
crystal face, against k a or for physical contacts (paper 1, Eq. 29).

Inputs: the solid in the frame of its face (a :class:`~contactres.materials.Material`; its
constants may be ratios only, C44 = 1, when ``Settings.constants_in_pa`` is False: the DCSF
depends on ratios only). Settings: the displacement models, either the values of k a or the
contacts (sphere radius, force and frequency, which give k a through the static Hertz contact
radius a: :func:`contactres.dynamic.normalised_wavenumber`), the loss factor, the wave-number
convention and the accuracy. One kernel table of the face serves every model
(:func:`contactres.dynamic.prepare`, :func:`contactres.dynamic.dcsf_models`). Every value is
checked against a refined evaluation, and refined where it misses the accuracy
(:func:`contactres.dynamic.checked_dcsf_models`): the table gives the estimated error of each
row and flags the rows that still miss it, and those with negative damping.

On a coated face (``coating``: films ``"MATERIAL:THICKNESS"`` as the ``contact`` job's) the DCSF
is a function of the frequency and the contact radius separately, not of k a alone (the films'
thickness and their frequency-dependent moduli set their own scales): only physical contacts
(radius, force, frequency) are taken, the model is "exact", and the static contact (contact
radius a, K_sa) is the ``contact`` job's on the coated face. DCSF = K(f)/K_sa with K(f) the
layered rigid flat punch at a (:func:`contactres.flat_punch_stiffness`): for elastic films
:func:`contactres.dynamic.layered_dcsf` (K_sa the static punch of the undamped stack); a film
without a static limit (the built-in PMMA's power laws) is referred to its storage constants at
:data:`contactres.viscoelastic.STATIC_FREQUENCY_HZ` (1 Hz), as the ``contact`` job's static
columns are. The ``ka`` column is then the substrate's k a, for orientation only. A lossy face
(a Material with complex constants, e.g. C (1 + i Q⁻¹) from
:meth:`~contactres.Material.with_loss`: from Python, the command line makes none) is taken
under a coating as the ``contact`` job takes it: the static contact (contact radius, K_sa, k a)
of its elastic part, K(f) of its complex constants, so its loss adds to ``im``.

A bare face takes an undamped Material only: a lossy one is refused, before any contact or
kernel table (the static contact, :func:`contactres.sphere_contact`, needs real constants, and
so does the kernel table, :func:`contactres.dynamic.prepare`), in one line that names the
remedies. The bare kernels take the loss as one factor, ``loss`` (Q⁻¹ of C (1 + i Q⁻¹)): give
the undamped Material and its loss there (the elastic part alone would lose the damping), or
put the face under a coating. (A lossy Material's loss need not be one factor, so it is not
split into the two; the message names the factor where it is one.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..measurements.schema import DCSF_TABLE
from ..validation import nonnegative
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import pandas as pd

    from ..materials import Material

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """The DCSF curve to compute.

    Parameters
    ----------
    models : tuple of str
        Displacement conditions (``contactres.dynamic.ALL_MODELS``: "exact", "R0", ...).
    ka : array or None
        Normalised wave numbers k a, dimensionless; None when the contacts give them.
    radius, force, frequency : array or None
        Sphere radius R (m), static force F (N) and frequency f (Hz) of physical contacts
        (all three, broadcast; the face needs its density), or None.
    loss : float
        Loss factor Q⁻¹ of the constants, dimensionless (0: lossless).
    wavenumber : str
        "longitudinal" (k_l a, the paper's figures) or "shear" (k_s a).
    rtol : float
        Target relative accuracy of the DCSF, checked at run time (each value against a
        refined evaluation: the table's rel_error and flags).
    constants_in_pa : bool
        False when the face's constants are ratios only (C44 = 1): no C33, C44 in Pa and no
        wave speeds are reported, and physical contacts are refused.
    coating : tuple
        Films on the face, top first (``"MATERIAL:THICKNESS"``, thickness in m, as the
        ``contact`` job's): the DCSF of the coated face (module docstring); physical contacts,
        model "exact" and no ``loss`` only. Empty: the bare face.
    """

    models: tuple[str, ...] = ("exact",)
    ka: np.ndarray | None = None
    radius: np.ndarray | None = None
    force: np.ndarray | None = None
    frequency: np.ndarray | None = None
    loss: float = 0.0
    wavenumber: str = "longitudinal"
    rtol: float = 1e-6
    constants_in_pa: bool = True
    coating: tuple = ()


@dataclass(frozen=True)
class Result(JobResult):
    """``table``: one row per (model, k a): ka, model, re, im (DCSF relative to K_sa), rel_error
    (its relative error, estimated against a refined evaluation) and flags, and for
    physical contacts radius_m, force_N, frequency_Hz, contact_radius_m, stiffness_N_per_m and
    K = K_sa DCSF (K_re_N_per_m, K_im_N_per_m): :data:`contactres.measurements.schema.DCSF_TABLE`.
    ``face``: C33/C44, C33 and C44 (Pa) of the face and its wave speeds v_l = √(C33/ρ),
    v_s = √(C44/ρ) (m/s); NaN where unknown (on a coated face: the substrate's).
    ``warnings``: one line per kind of flag in the table (rows that miss rtol, negative
    damping), and with a coating how the static constants of its viscoelastic films or of a
    lossy face were taken. With a coating the table adds ``coating``; its rel_error is not
    estimated (NaN: the layered punch meets its rtol by construction,
    :func:`contactres.dynamic.layered_dcsf`)."""

    SCHEMAS = MappingProxyType({"table": DCSF_TABLE})

    table: pd.DataFrame
    face: dict
    warnings: tuple[str, ...] = ()


@one_blas_thread()
def run(inputs: Material, settings: Settings, progress: Progress | None = None) -> Result:
    """The DCSF of ``settings`` on the face ``inputs`` (see the module docstring)."""
    import pandas as pd

    from ..dynamic import checked_dcsf_models, prepare
    from ..materials import require_material

    m, s = inputs, settings
    contacts = [v is not None for v in (s.radius, s.force, s.frequency)]
    if any(contacts) and not all(contacts):
        raise ContactresInputError("radius, force and frequency go together: give all three")
    physical = all(contacts)
    if s.coating:
        if not physical or s.ka is not None:
            raise ContactresInputError(
                "on a coating (--coating) the DCSF depends on the frequency and the contact "
                "radius separately, not on k a alone: give --radius, --force and --frequency "
                "(not --ka)"
            )
        return _run_coated(m, s, progress)
    if physical == (s.ka is not None):
        raise ContactresInputError("give either ka or radius/force/frequency (which give k a)")
    m = require_material(m)
    if m.is_lossy:
        # Said here, not by sphere_contact or the kernel table deep inside: their "drop the
        # loss" alone would lose the damping this job can take as loss=.
        raise ContactresInputError(_lossy_bare_face(m))
    c33, c44 = float(np.real(m.C[2, 2])), float(np.real(m.C[3, 3]))
    # At least one row: a single k a from Python (a float) makes a table of one row per model.
    ka = None if s.ka is None else np.atleast_1d(np.asarray(s.ka, dtype=float))
    if physical:
        if not s.constants_in_pa or m.density is None:
            raise ContactresInputError(
                "physical contacts need the elastic constants in Pa and the density"
            )
        ka, extra = _contact_points(m, s)
    assert ka is not None  # given, or computed from the contacts (checked above: one of them)
    # One kernel table serves every model (several models share it, and the far-field basis).
    say(progress, "kernel table of the face")
    table = prepare(m, s.loss, s.rtol)
    # One model name given as a string (from Python) is one model, not its letters.
    models = [s.models] if isinstance(s.models, str) else list(s.models)
    say(progress, f"DCSF of {len(models)} model(s) at {np.size(ka)} values of k a, checked")
    out = checked_dcsf_models(
        m, ka, models, loss=s.loss, wavenumber=s.wavenumber, rtol=s.rtol, prepared=table
    )
    frames = []
    for name, v in out.values.items():
        flags = _flags(v, out.error[name], out.converged[name])
        cols = {"ka": ka, "model": name, "re": v.real, "im": v.imag}
        cols.update(rel_error=out.error[name], flags=flags)
        if physical:
            k = extra["stiffness_N_per_m"] * v
            cols.update(extra, K_re_N_per_m=k.real, K_im_N_per_m=k.imag)
        frames.append(pd.DataFrame(cols))
    frame = pd.concat(frames, ignore_index=True)
    density = m.density if s.constants_in_pa else None
    return Result(
        table=frame,
        face=_face_constants(c33, c44, density, not s.constants_in_pa),
        warnings=_warnings(frame, s.rtol),
    )


def _lossy_bare_face(m: Material) -> str:
    """The one line that refuses a lossy Material as a bare face, with the two ways to take its
    damping (module docstring); the loss factor named where every constant carries the same
    one, C (1 + i Q⁻¹) (:meth:`~contactres.Material.with_loss`)."""
    C = np.asarray(m.C)
    given = C.real != 0
    ratio = C.imag[given] / C.real[given]
    same = ratio.size and np.all(C.imag[~given] == 0) and np.ptp(ratio) <= 1e-12 * abs(ratio[0])
    factor = f" (here C (1 + i {ratio[0]:.6g}): loss={ratio[0]:.6g})" if same else ""
    return (
        "the dcsf job's bare face takes the undamped Material and its loss as the setting "
        "loss=Q⁻¹ (constants C (1 + i Q⁻¹)); the Material given is lossy (complex constants), "
        "and its elastic part alone would lose the damping: give its elastic part "
        f"(contactres.viscoelastic.static_solid(m)) and loss=Q⁻¹{factor}, or put the face "
        "under a coating (coating=), which takes its complex constants as they are"
    )


def _flags(values: np.ndarray, error: np.ndarray, converged: np.ndarray) -> np.ndarray:
    """The flags of one model's rows: "not-converged" (the estimated relative error exceeds
    rtol after every refinement) and "negative-damping" (Im DCSF < 0 beyond that error: no
    passive contact has it; R0, SA and WA reach it at high k a, paper 1's approximations)."""
    negative = values.imag < -np.maximum(error, 1e-12) * np.abs(values)
    out = np.full(values.shape, "", dtype=object)
    out[~converged] = "not-converged"
    both = negative & ~converged
    out[negative] = "negative-damping"
    out[both] = "not-converged;negative-damping"
    return out


def _warnings(frame: pd.DataFrame, rtol: float) -> tuple[str, ...]:
    """One line per kind of flag in the listing (the rows of the flags column)."""
    lines = []
    flags = frame["flags"].astype(str)
    bad = frame[flags.str.contains("not-converged")]
    if len(bad):
        lines.append(
            f"{len(bad)} row(s) miss rtol = {rtol:g} after every refinement (flag not-converged;"
            f" estimated relative error up to {bad['rel_error'].max():.2g}, k a "
            f"{_span(bad['ka'])}): outside the validated range of the kernels (k_l a <= 2, "
            "A = 0.2-10, nu <= 0.45, less A < 0.25 with nu > 0.44) or next to a pole of the "
            "model (|DCSF| > 500)"
        )
    neg = frame[flags.str.contains("negative-damping")]
    if len(neg):
        names = ", ".join(sorted(set(neg["model"])))
        lines.append(
            f"{len(neg)} row(s) of model(s) {names} have negative damping, Im DCSF < 0 (flag "
            f"negative-damping; k a {_span(neg['ka'])}): no passive contact has it, the "
            "displacement condition fails there; use the exact model"
        )
    return tuple(lines)


def _span(ka) -> str:
    """'X' or 'X-Y': the k a values of some rows."""
    lo, hi = float(np.min(ka)), float(np.max(ka))
    return f"{lo:.4g}" if lo == hi else f"{lo:.4g}-{hi:.4g}"


def _broadcast_contacts(s: Settings) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sphere radii (m), forces (N) and frequencies (Hz, checked >= 0) broadcast to one shape,
    at least 1-D (a one-line error for lengths that do not broadcast)."""
    # the callers check that all three are given
    assert s.radius is not None and s.force is not None and s.frequency is not None
    try:
        R, F, f = (np.atleast_1d(x) for x in np.broadcast_arrays(s.radius, s.force, s.frequency))
    except ValueError:
        raise ContactresInputError(
            f"radius ({np.size(s.radius)}), force ({np.size(s.force)}) and frequency "
            f"({np.size(s.frequency)}) must have the same number of values, or a single value"
        ) from None
    return R, F, np.asarray(nonnegative("frequency", f, "Hz"), dtype=float)


def _contact_points(m, s: Settings):
    """k a (in the ``wavenumber`` convention) and the contact columns of R, F, f broadcast."""
    from ..dynamic import normalised_wavenumber, wave_modulus
    from ..materials import require_material
    from ..normal import sphere_contact

    # run calls this only when all three are given
    assert s.radius is not None and s.force is not None and s.frequency is not None
    R, F, f = _broadcast_contacts(s)
    # The job flags a/R itself, as contact does: no warning from the library.
    c = sphere_contact(require_material(m), R, F, check_validity=False)  # homogeneous only
    a = np.asarray(c.contact_radius, dtype=float)
    ka = normalised_wavenumber(f, a, m.density, wave_modulus(m, s.wavenumber))
    extra = {
        "radius_m": R,
        "force_N": F,
        "frequency_Hz": f,
        "contact_radius_m": a,
        "stiffness_N_per_m": np.asarray(c.stiffness, dtype=float),
    }
    return ka, extra


def _run_coated(m, s: Settings, progress) -> Result:
    """The DCSF of physical contacts on the coated face (module docstring)."""
    import pandas as pd

    from ..dynamic import flat_punch_stiffness, layered_dcsf, normalised_wavenumber, wave_modulus
    from ..layered import LayeredMaterial
    from ..materials import Material
    from . import contact

    models = [s.models] if isinstance(s.models, str) else list(s.models)
    if models != ["exact"]:
        raise ContactresInputError(
            "on a coating (--coating) the DCSF is the exact model's (the layered rigid punch): "
            "leave out --model"
        )
    if s.loss != 0:
        raise ContactresInputError(
            "on a coating (--coating) the materials carry their own loss (a viscoelastic film; "
            "from Python also a lossy face, a Material with complex constants): leave out --loss"
        )
    if not s.constants_in_pa or m.density is None:
        raise ContactresInputError(
            "physical contacts need the elastic constants in Pa and the density"
        )
    assert s.radius is not None and s.force is not None and s.frequency is not None
    R, F, f = _broadcast_contacts(s)
    say(progress, "static contact on the coated face")
    static = contact.run(m, contact.Settings(R, F, coating=tuple(s.coating)))
    t = static.table
    a = t["contact_radius_m"].to_numpy(dtype=float)
    k_sa = t["stiffness_N_per_m"].to_numpy(dtype=float)
    stack = LayeredMaterial(m, contact.parse_coating(s.coating))
    touching = a > 0
    say(progress, f"layered punch at {int(touching.sum())} contacts")
    dcsf = np.full(a.shape, np.nan, dtype=complex)
    if touching.any():
        if all(isinstance(x, Material) for x in stack.materials):
            dcsf[touching] = layered_dcsf(stack, a[touching], f[touching], s.rtol)
        else:  # no static limit: K_sa of the storage constants at 1 Hz (the contact job's)
            k = flat_punch_stiffness(stack, a[touching], f[touching], rtol=s.rtol)
            dcsf[touching] = np.asarray(k) / k_sa[touching]
    ka = normalised_wavenumber(f, a, m.density, wave_modulus(m, s.wavenumber))
    table = pd.DataFrame(
        {
            "ka": ka,
            "model": "exact",
            "re": dcsf.real,
            "im": dcsf.imag,
            "radius_m": t["radius_m"],
            "force_N": t["force_N"],
            "frequency_Hz": f,
            "contact_radius_m": a,
            "stiffness_N_per_m": k_sa,
            "K_re_N_per_m": (k_sa * dcsf).real,
            "K_im_N_per_m": (k_sa * dcsf).imag,
            "rel_error": np.nan,
            "flags": "",
            "coating": t["coating"],
        }
    )
    table = table[[c for c in DCSF_TABLE.names if c in table.columns]]  # the schema's order
    c33, c44 = float(np.real(m.C[2, 2])), float(np.real(m.C[3, 3]))
    return Result(
        table=table,
        face=_face_constants(c33, c44, m.density, False),
        warnings=tuple(static.warnings),
    )


def _face_constants(c33: float, c44: float, density, ratios_only: bool) -> dict:
    """C33, C44 (Pa; NaN when the constants were given as ratios) and the wave speeds (m/s;
    NaN without a density) of the rotated material."""
    nan = float("nan")
    if ratios_only:
        return {"C33_over_C44": c33 / c44, "C33_Pa": nan, "C44_Pa": nan, "v_l_m_per_s": nan,
                "v_s_m_per_s": nan}  # fmt: skip
    v_l = math.sqrt(c33 / density) if density else nan
    v_s = math.sqrt(c44 / density) if density else nan
    return {"C33_over_C44": c33 / c44, "C33_Pa": c33, "C44_Pa": c44, "v_l_m_per_s": v_l,
            "v_s_m_per_s": v_s}  # fmt: skip
