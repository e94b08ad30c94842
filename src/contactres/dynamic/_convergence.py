"""The DCSF with its accuracy checked at run time: each value against a refined evaluation.

The resolution that :func:`~contactres.dynamic._table.resolution_for` picks for an rtol and the
Galerkin basis of :func:`~contactres.dynamic._exact.galerkin_size` were measured for k_l a <= 2,
A = 0.2-10 and ν <= 0.45 (paper 1's range and a margin), less the corner A < 0.25, ν > 0.44
(:data:`VALIDATED_CORNER`: TP misses there). Outside it they can miss the target by far: on
Cu(001) at k_l a = 10 with rtol = 1e-4 the coarse grid gives 3.82 + 15.9i where the converged
DCSF is 0.666 + 19.78i, and at A = 0.05, ν = 0.45, k_l a = 2 the default grid is 1.4 % off.
A promise of accuracy is therefore checked where it is used:

* level 0 is the ordinary evaluation (the value :func:`~contactres.dynamic.dcsf_models` gives);
* level L evaluates again on a kernel table whose every resolution is doubled L times
  (:meth:`~contactres.dynamic._table.Resolution.doubled`) with 4 L more radial terms and 3 L more
  angular harmonics in the exact model's Galerkin basis;
* a value of level L is accepted when level L + 1 differs from it by at most rtol (relative):
  the estimated error of the accepted value is that difference, measured, not assumed. Values
  that miss go up one level (only those k a are evaluated again), at most ``max_refine`` times;
  a value still missing then is the finest one, marked not converged, with the last difference
  as its estimated error (an over-estimate: the finer value is the better one).

Where level 0 meets rtol (in the validated range, away from poles) the value is exactly the one of
:func:`~contactres.dynamic.dcsf_models`; the check costs one refined evaluation (a table of
twice the resolution: 5-20 times the ordinary evaluation). Nothing is cached.

The public :func:`~contactres.dynamic.dcsf`, :func:`~contactres.dynamic.dcsf_models` and
:func:`~contactres.dynamic.dynamic_contact_stiffness` therefore check only outside the validated
range (:func:`in_validated_range`: a cubic or isotropic solid, judged in its crystal frame, with
A = 0.2-10 and ν <= 0.45 but not A < 0.25 with ν > 0.44, at k_l a <= 2), where nothing promises
that level 0 meets rtol: there they return the checked values (:func:`checked_values`) and an
:class:`~contactres.errors.AccuracyWarning` for values that still miss rtol after
:data:`MAX_REFINE` refinements, naming the material, the k a and the accuracy reached. Inside
the range they are unchanged (no check, no cost) but near a pole of a model's DCSF: values
beyond ``|DCSF|`` = :data:`POLE_DCSF`, whose relative error grows like ``|DCSF|``, are checked
there too (the AccuracyWarning then says so).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from .._summary import Summarised, values
from ..errors import AccuracyWarning, ContactresInputError
from ._models import ALL_MODELS
from ._normal_stiffness import (
    CHUNK,
    check_model,
    evaluate_models,
    shear_ka,
    shear_wavenumber_ratio,
    table_for,
)
from ._table import kernel_table, resolution_for

if TYPE_CHECKING:
    from collections.abc import Mapping

    from ..materials import Material
    from ._table import KernelTable

__all__ = [
    "MAX_REFINE",
    "POLE_DCSF",
    "VALIDATED_CORNER",
    "VALIDATED_KLA",
    "VALIDATED_POISSON",
    "VALIDATED_ZENER",
    "CheckedDCSF",
    "checked_dcsf_models",
    "checked_values",
    "in_validated_range",
]

#: Default number of refinements tried (each doubles every resolution of the kernel table):
#: two reach the converged value on Cu(001) at k_l a = 10 from rtol = 1e-4, and at A = 0.05,
#: ν = 0.45 from the default; a third would cost ~8 times the second.
MAX_REFINE = 2

#: The range where the resolutions were measured to meet rtol (the convergence tests of
#: tests/dynamic/test_dynamic_exact.py): k_l a at most VALIDATED_KLA, a cubic (or isotropic)
#: solid with Zener ratio A within VALIDATED_ZENER and cubic ν = C12/(C11 + C12) at most
#: VALIDATED_POISSON, less the corner of VALIDATED_CORNER. Outside it the public functions
#: check each value (module docstring).
VALIDATED_KLA = 2.0
VALIDATED_ZENER = (0.2, 10.0)
VALIDATED_POISSON = 0.45
#: (A, ν): below this A the range ends at this ν. In that corner TP has a narrow feature near
#: k_l a = 1.95-2 (at A = 0.2-0.21, ν = 0.45) that the resolutions miss: against every
#: resolution doubled it is 2.3e-4 off at rtol = 1e-4 (1.5e-3 at A = 0.21, Q⁻¹ = 0.02) and
#: 5.7e-6 at rtol = 1e-6; at A = 0.22 or ν = 0.445 it is within 1.6e-5 and 1.3e-7, at A = 0.25
#: or ν = 0.44 within 1.0e-5 and 3e-8 (the limits keep that margin). There the run-time check
#: (checked_values) meets rtol.
VALIDATED_CORNER = (0.25, 0.44)
#: Inside the validated range, values of a model's DCSF beyond this modulus (near a pole of SA
#: or R1, where N -> 0) are checked at run time as those outside it: there the relative error
#: grows like |DCSF| (measured: ~5e-8 |DCSF| on the coarse grid of rtol >= 1e-4, ~1.5e-10
#: |DCSF| on the default one), so that no resolution meets rtol at every k a next to a pole.
POLE_DCSF = 500.0


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of every model.
@dataclass(frozen=True, repr=False)
class CheckedDCSF(Summarised):
    """DCSF values with their accuracy estimated at run time (module docstring).

    Attributes
    ----------
    values : mapping model -> complex array shaped like ``ka``: DCSF = K_da/K_sa, dimensionless
    error : mapping model -> float array: estimated relative error of the value,
        ``|DCSF' − DCSF| / |DCSF'|`` with DCSF' the value at the next refinement
    converged : mapping model -> bool array: the estimated error is at most rtol
    level : mapping model -> int array: the refinement level of the value (0: ordinary)
    rtol : the target relative accuracy
    """

    values: Mapping[str, np.ndarray]
    error: Mapping[str, np.ndarray]
    converged: Mapping[str, np.ndarray]
    level: Mapping[str, np.ndarray]
    rtol: float

    def _facts(self) -> list[tuple[str, str]]:
        """Per model (the first six) the range of Re DCSF, then how many values converged."""
        names = list(self.values)
        facts = [(k, values(self.values[k])) for k in names[:6]]
        if len(names) > 6:
            facts.append(("more models", ", ".join(names[6:])))
        done = sum(int(np.count_nonzero(v)) for v in self.converged.values())
        total = sum(np.size(v) for v in self.converged.values())
        return [*facts, ("converged", f"{done} of {total} (rtol {self.rtol:g})")]


def checked_dcsf_models(
    m: Material,
    ka,
    models=ALL_MODELS,
    loss: float = 0.0,
    wavenumber: str = "longitudinal",
    rtol: float = 1e-6,
    prepared: KernelTable | None = None,
    *,
    max_refine: int = MAX_REFINE,
) -> CheckedDCSF:
    """The DCSF of several models at ``ka``, each value checked against a refined evaluation.

    Parameters
    ----------
    m, ka, models, loss, wavenumber, rtol, prepared
        As in :func:`contactres.dynamic.dcsf_models` (``prepared``: the level-0 table).
    max_refine : int
        Keyword only: refinements tried at most (>= 1; default :data:`MAX_REFINE`).

    Returns
    -------
    CheckedDCSF
        The values (where level 0 meets rtol, those of ``dcsf_models`` to the bit), their
        estimated relative errors and whether they meet ``rtol``.
    """
    names = [check_model(x) for x in ([models] if isinstance(models, str) else models)]
    if not (isinstance(max_refine, int | np.integer) and max_refine >= 1):
        raise ContactresInputError(f"max_refine must be a positive integer, got {max_refine!r}")
    ksa = shear_ka(m, ka, wavenumber)
    table = table_for(m, ksa, loss, rtol, prepared)
    return checked_values(m, table, ksa, names, loss, rtol, max_refine=max_refine)


def checked_values(
    m: Material,
    table: KernelTable,
    ksa: np.ndarray,
    names: list[str],
    loss: float,
    rtol: float,
    *,
    max_refine: int = MAX_REFINE,
    chunk: int = CHUNK,
    interpolate: bool | None = None,
) -> CheckedDCSF:
    """The work of :func:`checked_dcsf_models` after its checks: the checked model names
    ``names`` at the k_s a values ``ksa`` (array), level 0 on ``table`` (the kernel table of
    ``m``, ``loss``, ``rtol``); ``chunk`` and ``interpolate`` as in
    :func:`contactres.dynamic.dcsf` (for every level)."""
    uniq, inverse = np.unique(ksa.ravel(), return_inverse=True)
    current = evaluate_models(table, uniq, names, rtol, chunk=chunk, interpolate=interpolate)
    values = {k: v.copy() for k, v in current.items()}
    error = {k: np.full(uniq.shape, np.inf) for k in names}
    level = {k: np.zeros(uniq.shape, dtype=int) for k in names}
    pending = {k: np.ones(uniq.shape, dtype=bool) for k in names}
    resolution = resolution_for(rtol)
    for refine in range(1, max_refine + 1):
        todo = np.logical_or.reduce([pending[k] for k in names])
        if not todo.any():
            break
        resolution = resolution.doubled()
        fine_table = kernel_table(m, loss, resolution)
        fine = evaluate_models(
            fine_table, uniq[todo], names, rtol, chunk=chunk, interpolate=interpolate, refine=refine
        )
        for k in names:
            idx = np.flatnonzero(todo)
            coarse = current[k][idx]
            diff = _relative(fine[k], coarse)
            ok = diff <= rtol
            left = pending[k][idx]
            # Accepted at the coarser level: the value stays the coarser one (level 0: the
            # ordinary value, unchanged), its error estimate is the difference measured.
            accept = idx[left & ok]
            error[k][accept] = diff[left & ok]
            # Still missing: the finer value is the better one; it waits for the next level.
            miss = idx[left & ~ok]
            values[k][miss] = fine[k][left & ~ok]
            error[k][miss] = diff[left & ~ok]
            level[k][miss] = refine
            pending[k][accept] = False
            current[k][idx] = fine[k]

    def shaped(d):
        return MappingProxyType({k: v[inverse].reshape(ksa.shape) for k, v in d.items()})

    return CheckedDCSF(
        values=shaped(values),
        error=shaped(error),
        converged=shaped({k: ~pending[k] for k in names}),
        level=shaped(level),
        rtol=float(rtol),
    )


def _relative(fine: np.ndarray, coarse: np.ndarray) -> np.ndarray:
    """|fine − coarse| / |fine|, 0 where both are equal (k a = 0: DCSF = 1 + iQ⁻¹ exactly)."""
    diff = np.abs(fine - coarse)
    scale = np.abs(fine)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(diff == 0, 0.0, diff / scale)


def in_validated_range(m: Material, ksa: np.ndarray) -> bool:
    """Whether every k_s a of ``ksa`` on ``m`` lies where the resolutions were measured to meet
    rtol (:data:`VALIDATED_KLA`, :data:`VALIDATED_ZENER`, :data:`VALIDATED_POISSON`, less
    :data:`VALIDATED_CORNER`).

    The solid is judged in its crystal frame (``m.frame`` undone), so every face of a cubic
    crystal counts as that crystal; a solid that is neither cubic nor isotropic there (trigonal
    quartz, a stiffness given in a rotated frame) is outside: nothing was measured for it.
    """
    if ksa.size and float(np.max(ksa)) > VALIDATED_KLA * shear_wavenumber_ratio(m) * (1 + 1e-12):
        return False
    ratios = _cubic_ratios(m)
    if ratios is None:
        return False
    zener, poisson = ratios
    lo, hi = VALIDATED_ZENER
    corner = zener < VALIDATED_CORNER[0] and poisson > VALIDATED_CORNER[1]
    return lo <= zener <= hi and poisson <= VALIDATED_POISSON and not corner


def _cubic_ratios(m: Material) -> tuple[float, float] | None:
    """(A, ν) of ``m`` turned back to its crystal frame, or None if it is not cubic there."""
    # The rows of m.frame are the current axes in crystal coordinates: the crystal axes in the
    # current frame are its columns, and turning to them undoes every rotation made so far.
    axes = np.asarray(m.frame, dtype=float)
    # A solid never rotated is in its crystal frame already: the rotation by the identity
    # (~1.5 ms, a tenth of a five-model curve, issue 31) would give its constants back.
    unturned = np.array_equal(axes, np.eye(3))
    crystal = m if unturned else m.rotated(normal=axes[:, 2], inplane=axes[:, 0])
    try:
        return crystal.zener_ratio, crystal.cubic_poisson
    except ContactresInputError:  # not cubic in its crystal frame
        return None


def warn_unconverged(
    m: Material, checked: CheckedDCSF, ka: np.ndarray, wavenumber: str, why: str = ""
) -> None:
    """An :class:`~contactres.errors.AccuracyWarning` if some values of ``checked`` (at the
    k a values ``ka``, in the convention ``wavenumber``) still miss their rtol; ``why`` says why
    they were checked (default: outside the validated range)."""
    ka = np.asarray(ka, dtype=float)
    for name, ok in checked.converged.items():
        if np.all(ok):
            continue
        bad = ~np.broadcast_to(ok, ka.shape)
        err = np.broadcast_to(checked.error[name], ka.shape)[bad]
        where = ka[bad]
        lo, hi = float(np.min(where)), float(np.max(where))
        span = f"{lo:.4g}" if lo == hi else f"{lo:.4g}-{hi:.4g}"
        label = "k_l a" if wavenumber == "longitudinal" else "k_s a"
        warnings.warn(
            f"DCSF ({name} model) of {_describe(m)} at {label} = {span} misses rtol = "
            f"{checked.rtol:g} after {MAX_REFINE} refinements: estimated relative error up to "
            f"{float(np.max(err)):.2g} ({why or _OUTSIDE})",
            AccuracyWarning,
            stacklevel=4,
        )


_OUTSIDE = (
    f"outside the validated range k_l a <= {VALIDATED_KLA:g}, A = {VALIDATED_ZENER[0]:g}-"
    f"{VALIDATED_ZENER[1]:g}, nu <= {VALIDATED_POISSON:g}, nu <= {VALIDATED_CORNER[1]:g} below "
    f"A = {VALIDATED_CORNER[0]:g}"
)


def _describe(m: Material) -> str:
    """The material of a message: its name, else its cubic ratios, else 'the material'."""
    ratios = _cubic_ratios(m)
    text = f"A = {ratios[0]:.4g}, nu = {ratios[1]:.4g}" if ratios else ""
    if m.name:
        return f"{m.name} ({text})" if text else str(m.name)
    return f"the cubic solid {text}" if text else "the material (not cubic)"
