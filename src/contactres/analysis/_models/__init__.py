"""The models the sweep analysis fits: :data:`REGISTRY`, one module each.

Amplitude models of one sweep, Δf(u0) and ΔΓ(u0) (paper 2, Figs. 1D and 4), each fitted to both
channels at once:

=========================  ==========================================================  ============
key                        model                                                       module
=========================  ==========================================================  ============
``elastic``                Δf = Δf0, ΔΓ = ΔΓ0 (a Voigt element, paper 2, Eq. 1)        elastic
``cattaneo-mindlin``       straight line in u0 (paper 2, Eq. 12)                       line
``savkoor``                straight line in u0² (paper 2, Eq. 15)                      parabola
``plateau``                flat below u_c, straight line above (Fig. 4C, D)            hinge
``cattaneo-mindlin-loop``  the exact Cattaneo-Mindlin loop with a dashpot (Eqs. 4-6)   cm_loop
``savkoor-loop``           the exact Savkoor loop with a dashpot (Eqs. 13-14)          savkoor_loop
``plateau-loop``           the Cattaneo-Mindlin loop behind a stick plateau d_c        plateau_loop
=========================  ==========================================================  ============

and the model of the load dependence, ``jkr-mindlin``: κ(F_N) = 2G*a with the JKR contact
radius (paper 2, Eqs. 7-10; module jkr_mindlin). Each module holds the model's metadata
(``MODEL``, a :class:`contactres.fitting.Model`: parameters with keys, units, bounds, fixed
flags, and the model function) and, for a model fitted to every sweep, its batched fitter
(``FIT``, a :class:`~contactres.analysis._models.base.SweepFit`). The analysis fits every
registered sweep model through :data:`SWEEP_FITS`
(:func:`contactres.analysis._classify.fit_sweeps`) and keeps one fit table per model
(:func:`fit_tables`, ``Results.fits``). A new model is one new module and one line in
:data:`MODULES`. The tests check each fitter against
:func:`contactres.fitting.fit` on the registered function (a second algorithm).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from ...fitting import ModelRegistry
from . import cm_loop, elastic, hinge, jkr_mindlin, line, parabola, plateau_loop, savkoor_loop
from .base import SweepFit

__all__ = [
    "AMPLITUDE_MODELS",
    "EXACT_LOOPS",
    "MODULES",
    "N_PARAMETERS",
    "REGISTRY",
    "SWEEP_FITS",
    "exact_model",
    "fit_tables",
    "model_curves",
]

#: The model modules, in the order their sweep fits run (a fit may use those before it).
MODULES = (elastic, line, parabola, hinge, cm_loop, savkoor_loop, plateau_loop, jkr_mindlin)

#: Every model the sweep analysis fits, by key.
REGISTRY = ModelRegistry(module.MODEL for module in MODULES)

#: The per-sweep fits, in the order they run.
SWEEP_FITS: tuple[SweepFit, ...] = tuple(m.FIT for m in MODULES if hasattr(m, "FIT"))

#: The amplitude classes, simplest and most common first (the order of the model choice).
AMPLITUDE_MODELS = ("elastic", "cattaneo-mindlin", "savkoor", "plateau")

#: Number of fitted parameters of each amplitude model (the k of its BIC).
N_PARAMETERS = {key: len(model.parameters) for key, model in REGISTRY.items()}

# The exact loop that stands behind a sweep whose limits come from it.
_EXACT = {
    "cm-loop": "cattaneo-mindlin-loop",
    "savkoor-loop": "savkoor-loop",
    "plateau-loop": "plateau-loop",
}
#: The exact loops: their parameters' columns are those of their fit tables (``Results.fits``).
EXACT_LOOPS = frozenset(_EXACT.values())


def exact_model(model, limits_from) -> str | None:
    """The registered model that draws a sweep of class ``model`` whose limits come from
    ``limits_from`` (its exact loop where they come from one); None where there is none (a
    sweep without a class)."""
    key = _EXACT.get(limits_from, model)
    return key if isinstance(key, str) and key in REGISTRY else None


def model_curves(row, u, loop=None) -> tuple[np.ndarray, np.ndarray]:
    """Δf(u0), ΔΓ(u0) in Hz of the model chosen for one sweep.

    Evaluates the registered model function with the sweep's fitted values, read from the
    columns its parameters name: those of ``row`` (a row of the sweep results: ``model``,
    ``limits_from`` and the named limits, slopes, curvatures, plateau) for a closed form; a
    sweep whose limits come from an exact loop (Cattaneo-Mindlin, Savkoor or plateau, column
    ``limits_from``) is drawn as that loop, with the values of ``loop``, the sweep's row of
    that loop's fit table (``Results.fits[key]``, :func:`fit_tables`).
    """
    u = np.asarray(u, dtype=float)
    key = _EXACT.get(row.get("limits_from"), row["model"])
    model = REGISTRY[key]
    if key in EXACT_LOOPS:
        if loop is None:
            raise TypeError(f"the curve of a sweep drawn as the {key} needs its fit's row")
        row = loop
    values = {p.key: row[p.column] for p in model.parameters}
    df, dg = model.function(u, **values)
    return np.broadcast_to(df, u.shape).astype(float), np.broadcast_to(dg, u.shape).astype(float)


def fit_tables(sweep, fields: Mapping[str, pd.DataFrame]) -> dict[str, pd.DataFrame]:
    """One table per registered sweep model fitted in ``fields`` (the fields of each fit by
    source, :data:`contactres.analysis._classify.FieldTables`): ``sweep`` (the ids of the rows)
    and the fields under the names of :attr:`SweepFit.table` (the parameters under their
    keys), one row per sweep.

    Fields a fitter adds beyond its ``table`` keep their own names."""
    out = {}
    for fit in SWEEP_FITS:
        if fit.source not in fields:
            continue  # not fitted (the exact loops without exact_loop)
        table = {"sweep": np.asarray(sweep)}
        for field, values in fields[fit.source].items():
            table[fit.table.get(str(field), str(field))] = values.to_numpy()
        out[fit.model] = pd.DataFrame(table)
    return out
