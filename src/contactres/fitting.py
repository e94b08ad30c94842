"""Fitted models with metadata, the least-squares fit behind them, and the batched
Levenberg-Marquardt solver of the package's own fits.

A :class:`Model` carries everything needed to fit it and to report it: its parameters
(:class:`Parameter`: key, display name, unit, output column, default bounds, fixed or free), the
observable it predicts and its unit, and the source of its formula. A :class:`ModelRegistry` is an
immutable mapping of models by key, built explicitly by the package that defines the models (the
sweep analysis: :data:`contactres.analysis.REGISTRY`); a test walks it and holds every
parameter to a closed table of names, units and columns.

:func:`fit` is a pure function of (model, data, settings), solved by the package's own
:func:`levenberg_marquardt` (Marquardt's damping, bounds by projection, forward-difference
Jacobian; until issue 31 it wrapped :func:`scipy.optimize.least_squares`, whose import was
most of a first analysis's). Standard errors come from the Jacobian, ``cov = inv(JᵀJ) ·
RSS/(N - p)`` (residual variance from the fit itself), so they hold when the points scatter
more than their nominal errors. The result holds the fitted values and their errors, never the
starting values.

:func:`levenberg_marquardt` (written in :mod:`contactres._levenberg_marquardt`, a module of
its own) minimises χ² of many independent problems at once (a leading batch axis; one problem
is a batch of one), each with its own damping and stopping, with box bounds
(projection), an admissible region (a step outside it fails like one that raises χ²) and
optional geodesic acceleration; :class:`LMOptions` chooses among the classic variants (damping
matrix, update of the damping, tolerances). It serves the plateau-loop fit of the sweeps
(:mod:`contactres.analysis`, thousands of two-parameter problems in the Gauss-Newton form
of variable projection) and the ratio fit of polycrystal maps
(:mod:`contactres.polycrystal._ratio_fit`, one ill-conditioned problem in the Jacobian form).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._levenberg_marquardt import LeastSquaresResult, LMOptions, levenberg_marquardt, solve_stacked
from ._summary import Summarised, clipped, number, plus_minus
from .errors import ContactresInputError

__all__ = [
    "FitResult",
    "LMOptions",
    "LeastSquaresResult",
    "Model",
    "ModelRegistry",
    "Parameter",
    "fit",
    "levenberg_marquardt",
    "solve_stacked",
]


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


# repr=False: the summary (Summarised, _facts) names the parameters instead of printing each
# Parameter in full.
@dataclass(frozen=True, repr=False)
class Model(Summarised):
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

    def _facts(self) -> list[tuple[str, str]]:
        """Key and meaning, the parameters with their units, the axes and the source."""
        names = ", ".join(f"{p.key} ({p.unit or '1'})" for p in self.parameters)
        return [
            ("", repr(self.key)),
            ("", self.display),
            ("parameters", names),
            ("fits", f"{self.observable} ({self.unit}) against {self.x} ({self.x_unit})"),
            ("source", clipped(self.source, 60)),
        ]


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


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the covariance and
# the residuals.
@dataclass(frozen=True, repr=False)
class FitResult(Summarised):
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

    def _facts(self) -> list[tuple[str, str]]:
        """The model, each value (± its error when free; the first eight), the residual sum."""
        shown = list(self.values)[:8]
        facts = [("", self.model)]
        facts += [(k, plus_minus(self.values[k], self.errors.get(k, np.nan))) for k in shown]
        facts += [("rss", number(self.rss)), ("points", str(self.n_points))]
        return [*facts, ("success", "yes" if self.success else f"no ({self.message})")]


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
    model : the :class:`Model`; its fixed parameters must be given in ``fixed``. Its function
        must be a deterministic function of its arguments: the fit evaluates it once per set
        of parameters, its last few results kept for the points it asks for again
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
        Jacobian is singular or not finite.
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
    x0 = np.clip(np.array([start[p.key] for p in free]) / scale, lo, hi)

    def params(z):
        d = dict(fixed)
        d.update({p.key: v * s for p, v, s in zip(free, z, scale, strict=True)})
        return d

    # The residuals of this fit's last evaluations by their parameters (bytes of z): the
    # solver evaluates the point it accepts again with its Jacobian, the start is checked here
    # before the solver evaluates it, and the result and its Jacobian below were mostly
    # evaluated by the solver already. A model can be costly (the coated law solves a contact
    # radius per force: 27 of its ~120 evaluations in the bundled example's four fits were
    # repeats); a repeat is the same function of the same numbers, hence the same residuals.
    # Read-only, so that no caller changes a kept array (the result gets a copy of its own).
    seen: dict[bytes, np.ndarray] = {}

    def residuals(z):
        key = np.asarray(z, dtype=float).tobytes()
        r = seen.get(key)
        if r is None:
            # ravel: a model of several observables (e.g. Δf and ΔΓ) returns one row each
            r = np.ravel((np.asarray(model.function(x, **params(z))) - y) * w)
            r.setflags(write=False)
            seen[key] = r
            if len(seen) > _FIT_REPEATS:
                del seen[next(iter(seen))]  # the oldest
        return r

    if not np.all(np.isfinite(residuals(x0))):
        # As least_squares refused it: a NaN or inf would otherwise surface as a failed SVD.
        raise ContactresInputError(
            f"model {model.key!r}: the residuals at the start are not finite "
            "(check x, y and sigma for NaN or inf, and the start values)"
        )
    # The package's own Levenberg-Marquardt (below), not scipy.optimize.least_squares: the
    # import of scipy.optimize (with scipy.linalg, sparse and spatial, ~0.3 s of CPU) would be
    # most of what a first analysis pays. Marquardt's damping λ diag(JᵀJ) is invariant to the
    # units of the parameters, as least_squares' x_scale="jac" is; bounds by projection.
    sol = levenberg_marquardt(
        lambda z, rows, jacobian: _fit_evaluation(residuals, z, jacobian, (lo, hi)),
        x0,
        lo,
        hi,
        _FIT_OPTIONS,
    )
    z_hat = sol.x[0]
    r = residuals(z_hat)
    rss = float(r @ r)
    n, p = y.size, len(free)
    cov = np.full((p, p), np.nan)
    if n > p:
        jac = _forward_jacobian(residuals, z_hat, r, (lo, hi))
        jtj = jac.T @ jac
        # (not finite: a Jacobian step into a region where the model is NaN; the SVD of
        # matrix_rank would raise)
        if np.isfinite(jtj).all() and np.linalg.matrix_rank(jtj) == p:
            cov = np.linalg.inv(jtj) * (rss / (n - p)) * np.outer(scale, scale)
    values = params(z_hat)
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
        success=bool(sol.converged[0]),
        message=sol.message(0),
        residuals=np.array(r),  # (writable, as before: the kept array is read-only)
    )


def _forward_jacobian(residuals, z, r, bounds) -> np.ndarray:
    """The Jacobian dr/dz (G, P) of ``residuals`` at ``z`` by forward differences, r = the
    residuals there: steps h = √ε max(1, |z|) (ε the double precision), turned backwards where
    a forward step would leave the ``bounds`` (lo, hi), the rule of scipy's least_squares for
    its default ("2-point") Jacobian, so that the standard errors of :func:`fit` stay those it
    gave."""
    lo, hi = bounds
    h = np.sqrt(np.finfo(float).eps) * np.where(z >= 0, 1.0, -1.0) * np.maximum(1.0, np.abs(z))
    h = np.where((z + h > hi) | (z + h < lo), -h, h)
    cols = []
    for i in range(z.size):  # one evaluation per parameter (two or three)
        zi = z.copy()
        zi[i] = z[i] + h[i]
        cols.append((residuals(zi) - r) / (zi[i] - z[i]))  # the step as rounded
    return np.stack(cols, axis=-1)


def _fit_evaluation(residuals, z, jacobian: bool, bounds) -> dict[str, np.ndarray]:
    """One evaluation of :func:`fit`'s problem for :func:`levenberg_marquardt` (a batch of
    one): the residuals at z (1, P) and, when asked, their forward-difference Jacobian."""
    r = residuals(z[0])
    out = {"residuals": r[None]}
    if jacobian:
        out["jacobian"] = _forward_jacobian(residuals, z[0], r, bounds)[None]
    return out


#: The settings of :func:`fit`: the tolerances of its former scipy least_squares call
#: (ftol = xtol = 1e-12) and room for the steps they take.
_FIT_OPTIONS = LMOptions(xtol=1e-12, ftol=1e-12, max_iter=500)
#: Evaluations :func:`fit` keeps for repeats (its solver's last trials, the Jacobian's points):
#: 4 caught all 27 repeats of the coated bundled example's fits, as 16 did (2: 21), at a
#: quarter of 16's memory on a large fit (each kept array has the residuals' length: 8 MB at
#: 10^6 points; review R30b).
_FIT_REPEATS = 4
