"""Fitted models with metadata, and the least-squares fit behind them.

A :class:`Model` carries everything needed to fit it and to report it: its parameters
(:class:`Parameter`: key, display name, unit, output column, default bounds, fixed or free), the
observable it predicts and its unit, and the source of its formula. A :class:`ModelRegistry` is an
immutable mapping of models by key, built explicitly by the package that defines the models (the
sweep analysis: :data:`contactres.analysis.models.REGISTRY`); a test walks it and holds every
parameter to a closed table of names, units and columns.

:func:`fit` wraps :func:`scipy.optimize.least_squares`: a pure function of (model, data,
settings). Standard errors come from the Jacobian, ``cov = inv(JᵀJ) · RSS/(N - p)`` (residual
variance from the fit itself), so they hold when the points scatter more than their nominal
errors. The result holds the fitted values and their errors, never the starting values.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import least_squares

from .errors import ContactresInputError

__all__ = ["FitResult", "Model", "ModelRegistry", "Parameter", "fit"]


@dataclass(frozen=True)
class Parameter:
    """One parameter of a fitted model.

    Attributes
    ----------
    key : name used in code (a keyword argument of the model's function), read as physics
    display : name for figures and tables
    unit : SI unit ("-" for dimensionless)
    column : the column of the results that holds the fitted value
    bounds : default (lower, upper) bounds in that unit
    fixed : True if the parameter is held at its given value (not fitted)
    scale : typical magnitude (the optimiser works in units of ``scale``)
    """

    key: str
    display: str
    unit: str
    column: str
    bounds: tuple[float, float] = (-np.inf, np.inf)
    fixed: bool = False
    scale: float = 1.0


@dataclass(frozen=True)
class Model:
    """A fitted model: ``function(x, **params) -> prediction`` plus its metadata."""

    key: str
    display: str
    parameters: tuple[Parameter, ...]
    x: str
    x_unit: str
    observable: str
    unit: str
    source: str
    function: Callable[..., Any]


class ModelRegistry(Mapping[str, Model]):
    """An immutable mapping key -> :class:`Model`, built once from a sequence of models.

    Keys are unique (a duplicate is a ValueError); nothing can be added later, so what a package
    registers is exactly what its module defines.
    """

    def __init__(self, models: Iterable[Model]) -> None:
        self._models: dict[str, Model] = {}
        for m in models:
            if m.key in self._models:
                raise ContactresInputError(f"model {m.key!r} is registered twice")
            self._models[m.key] = m

    def __getitem__(self, key: str) -> Model:
        try:
            return self._models[key]
        except KeyError:
            raise KeyError(f"no model {key!r}; registered: {', '.join(self._models)}") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._models)

    def __len__(self) -> int:
        return len(self._models)


@dataclass(frozen=True)
class FitResult:
    """Fitted values, standard errors and covariance (free parameters only), and fit quality."""

    model: str
    values: Mapping[str, float]
    errors: Mapping[str, float]
    covariance: np.ndarray
    free: tuple[str, ...]
    rss: float
    n_points: int
    success: bool
    message: str = ""
    residuals: np.ndarray = field(default_factory=lambda: np.zeros(0))


def fit(
    model: Model,
    x,
    y,
    start: Mapping[str, float],
    fixed: Mapping[str, float] | None = None,
    sigma=None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
) -> FitResult:
    """Least-squares fit of ``model`` to points (x, y).

    Parameters
    ----------
    model : the :class:`Model`; its fixed parameters must be given in ``fixed``
    x, y : data, in the model's ``x_unit`` and ``unit``; for a model of k observables (its
        function returns k arrays) ``y`` has shape (k, len(x))
    start : starting values of the free parameters (not reported)
    fixed : values of the fixed parameters (and of any free ones to hold here)
    sigma : optional per-point errors (weights 1/σ, broadcast against ``y``); default equal
    bounds : optional overrides of the default bounds

    Returns
    -------
    FitResult
        ``errors`` are standard errors from ``inv(JᵀJ)·RSS/(N - p)``; NaN when N <= p or the
        Jacobian is singular.
    """
    fixed = dict(fixed or {})
    bounds = dict(bounds or {})
    free = [p for p in model.parameters if p.key not in fixed]
    missing = [p.key for p in model.parameters if p.fixed and p.key not in fixed]
    if missing:
        raise ContactresInputError(
            f"model {model.key!r}: fixed parameter(s) {missing} need a value"
        )
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    w = np.ones_like(y) if sigma is None else 1.0 / np.asarray(sigma, dtype=float)
    scale = np.array([p.scale for p in free])
    lo = np.array([bounds.get(p.key, p.bounds)[0] for p in free]) / scale
    hi = np.array([bounds.get(p.key, p.bounds)[1] for p in free]) / scale
    # least_squares (trf) moves a start on a bound strictly inside by itself.
    x0 = np.clip(np.array([start[p.key] for p in free]) / scale, lo, hi)

    def params(z):
        d = dict(fixed)
        d.update({p.key: v * s for p, v, s in zip(free, z, scale, strict=True)})
        return d

    def residuals(z):
        # ravel: a model of several observables (e.g. Δf and ΔΓ) returns one row per observable
        return np.ravel((np.asarray(model.function(x, **params(z))) - y) * w)

    sol = least_squares(
        residuals, x0, bounds=(lo, hi), method="trf", x_scale="jac", ftol=1e-12, xtol=1e-12
    )
    r = sol.fun
    rss = float(r @ r)
    n, p = y.size, len(free)
    cov = np.full((p, p), np.nan)
    if n > p:
        jac = np.asarray(sol.jac)  # dense: neither jac_sparsity nor tr_solver="lsmr" is used
        jtj = jac.T @ jac
        if np.linalg.matrix_rank(jtj) == p:
            cov = np.linalg.inv(jtj) * (rss / (n - p)) * np.outer(scale, scale)
    values = params(sol.x)
    errors = {k: np.nan for k in fixed}
    errors.update({q.key: float(np.sqrt(cov[i, i])) for i, q in enumerate(free)})
    return FitResult(
        model=model.key,
        values={k: float(v) for k, v in values.items()},
        errors=errors,
        covariance=cov,
        free=tuple(q.key for q in free),
        rss=rss,
        n_points=n,
        success=bool(sol.success),
        message=str(sol.message),
        residuals=r,
    )
