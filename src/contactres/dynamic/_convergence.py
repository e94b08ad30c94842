"""The DCSF with its accuracy checked at run time: each value against a refined evaluation.

The resolution that :func:`~contactres.dynamic._table.resolution_for` picks for an rtol and the
Galerkin basis of :func:`~contactres.dynamic._exact.galerkin_size` were measured for k_l a <= 2,
A = 0.2-10 and ν <= 0.45 (paper 1's range and a margin). Outside it they can miss the target by
far: on Cu(001) at k_l a = 10 with rtol = 1e-4 the coarse grid gives 3.82 + 15.9i where the
converged DCSF is 0.666 + 19.78i, and at A = 0.05, ν = 0.45, k_l a = 2 the default grid is
1.4 % off. A promise of accuracy is therefore checked where it is used:

* level 0 is the ordinary evaluation (the value :func:`~contactres.dynamic.dcsf_models` gives);
* level L evaluates again on a kernel table whose every resolution is doubled L times
  (:meth:`~contactres.dynamic._table.Resolution.doubled`) with 4 L more radial terms and 2 L more
  angular harmonics in the exact model's Galerkin basis;
* a value of level L is accepted when level L + 1 differs from it by at most rtol (relative):
  the estimated error of the accepted value is that difference, measured, not assumed. Values
  that miss go up one level (only those k a are evaluated again), at most ``max_refine`` times;
  a value still missing then is the finest one, marked not converged, with the last difference
  as its estimated error (an over-estimate: the finer value is the better one).

Where level 0 meets rtol (everywhere in the validated range) the value is exactly the one of
:func:`~contactres.dynamic.dcsf_models`; the check costs one refined evaluation (a table of
twice the resolution). Nothing is cached.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from .._summary import Summarised, values
from ..errors import ContactresInputError
from ._models import ALL_MODELS
from ._normal_stiffness import check_model, evaluate_models, shear_ka, table_for
from ._table import kernel_table, resolution_for

if TYPE_CHECKING:
    from collections.abc import Mapping

    from ..materials import Material
    from ._table import KernelTable

__all__ = ["MAX_REFINE", "CheckedDCSF", "checked_dcsf_models"]

#: Default number of refinements tried (each doubles every resolution of the kernel table):
#: two reach the converged value on Cu(001) at k_l a = 10 from rtol = 1e-4, and at A = 0.05,
#: ν = 0.45 from the default; a third would cost ~8 times the second.
MAX_REFINE = 2


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
    uniq, inverse = np.unique(ksa.ravel(), return_inverse=True)
    current = evaluate_models(table, uniq, names, rtol)
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
        fine = evaluate_models(fine_table, uniq[todo], names, rtol, refine=refine)
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
