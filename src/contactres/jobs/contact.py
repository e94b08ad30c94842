"""Job ``contact``: Hertz contact of a rigid sphere on a crystal face (paper 1, Eqs. 1-4), and
its normal and tangential stiffness, static or at a frequency.

Inputs: the solid in the frame of its face (a :class:`~contactres.materials.Material`, z the
inward normal). Settings: sphere radius, force and frequency (broadcast), the tangential
stiffness on or off and the direction of the tangential motion. The static contact is
:func:`contactres.sphere_contact`; the dynamic normal stiffness
:func:`contactres.dynamic_contact_stiffness` (exact model, lossless solid); the tangential one
:func:`contactres.tangential_contact_stiffness` (relaxed contact, rigid disk of radius a).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ContactresInputError
from ..measurements.schema import CONTACT_TABLE
from ..validation import nonnegative
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import pandas as pd

    from ..materials import Material

__all__ = ["Result", "Settings", "run"]


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
    """

    radius: np.ndarray
    force: np.ndarray
    frequency: np.ndarray | None = None
    tangential: bool = False
    direction: float = 0.0


@dataclass(frozen=True)
class Result(JobResult):
    """One row per (R, F, f): ``table`` (columns in SI units, named with them:
    :data:`contactres.measurements.schema.CONTACT_TABLE`), and whether the
    contact is circular (the face has 3- or 4-fold symmetry) with the relative 2nd harmonic of
    its compliance, ``noncircularity``."""

    SCHEMAS = MappingProxyType({"table": CONTACT_TABLE})

    table: pd.DataFrame
    circular: bool
    noncircularity: float


def run(inputs: Material, settings: Settings, progress: Progress | None = None) -> Result:
    """The contact of ``settings`` on the face ``inputs`` (see the module docstring)."""
    import pandas as pd

    from ..materials import require_material
    from ..normal import sphere_contact

    m, s = inputs, settings
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
    if s.frequency is not None and m.density is None:
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
    say(progress, "static contact")
    c = sphere_contact(require_material(m), R, F)  # homogeneous only: no layered stack here
    table = pd.DataFrame(
        {
            "radius_m": R,
            "force_N": F,
            "contact_radius_m": c.contact_radius,
            "peak_pressure_Pa": c.peak_pressure,
            "depth_m": c.depth,
            "stiffness_N_per_m": c.stiffness,
            "indentation_modulus_Pa": c.indentation_modulus,
        }
    )
    if s.frequency is not None:
        say(progress, "dynamic stiffness")
        _add_dynamic(table, m, R, F, f, s.tangential, s.direction)
    elif s.tangential:
        table["tangential_stiffness_N_per_m"] = _tangential(
            m, c.contact_radius, 0.0, s.direction
        ).real
    return Result(table=table, circular=bool(c.circular), noncircularity=float(c.noncircularity))


def _add_dynamic(table, m, R, F, f, tangential: bool, direction: float) -> None:
    """The dynamic normal (and tangential) stiffness columns at the frequencies ``f``."""
    from ..dynamic import dynamic_contact_stiffness, normalised_wavenumber, wave_modulus

    a = table["contact_radius_m"].to_numpy(dtype=float)
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
