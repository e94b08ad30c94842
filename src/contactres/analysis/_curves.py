"""The points of every sweep as analysed and its fitted model on the grids the report draws.

The figures (paper 2, Fig. 4) and the HTML page draw each sweep's points with the curve of the
model chosen for it. Both are computed here, once, by the analysis, and carried by the results
(:attr:`contactres.analysis.Results.points`, :attr:`~contactres.analysis._results.
Results.curves`), so that the report draws numbers and never evaluates a model (the exact loops
are quadratures) or reads the analysis' internal arrays.

The curve of a sweep is the registered model function (:mod:`contactres.analysis._models`) of
its class, evaluated with its fitted values; a sweep whose limits come from an exact loop (the
Cattaneo-Mindlin, Savkoor or plateau loop, paper 2, Eqs. 4-6 and 13-14) is drawn as that loop
(:func:`~contactres.analysis._models.model_curves`, the same function per sweep), with the
values of that loop's fit table (``Results.fits``); a closed form with the named columns of
the sweep results. The grid runs from u0 = 0 to the sweep's largest amplitude in
:data:`FIGURE_POINTS` (Fig. 4) and :data:`PAGE_POINTS` (the inline SVG of the page) equal
steps.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ._amplitude import Padded
from ._models import EXACT_LOOPS, REGISTRY, exact_model, model_curves

__all__ = [
    "CURVE_GRIDS",
    "FIGURE_POINTS",
    "PAGE_POINTS",
    "fitted_curves",
    "jkr_curves",
    "sweep_points",
    "sweep_rows",
]

#: Points of the model curve of a sweep in the PNG figures (Fig. 4).
FIGURE_POINTS = 100
#: Points of the model curve of a sweep in the inline SVG plots of the HTML page.
PAGE_POINTS = 30
#: The grids of :func:`fitted_curves`, by number of points.
CURVE_GRIDS = (FIGURE_POINTS, PAGE_POINTS)
#: Points of the JKR + Mindlin curve of a group (Fig. 5), from F_N = 0 to 1.05 times the
#: configuration's largest load.
JKR_POINTS = 100

# The fit table of each model, by key (``Results.fits``).
Fits = Mapping[str, pd.DataFrame]


def sweep_points(p: Padded) -> pd.DataFrame:
    """The points of every sweep as the analysis fitted them (after any drift correction).

    Returns
    -------
    DataFrame
        ``sweep``, ``amplitude_m`` (m), ``df_Hz``, ``dgamma_Hz`` (Hz): sweep after sweep in the
        order of ``p``, amplitudes ascending within a sweep.
    """
    u, df, dg = p.points(np.arange(len(p.n)))
    return pd.DataFrame(
        {
            "sweep": np.repeat(np.asarray(p.sweeps, dtype=object), p.n),
            "amplitude_m": u,
            "df_Hz": df,
            "dgamma_Hz": dg,
        }
    )


def _values_of(sw: pd.DataFrame, fits: Fits, rows: np.ndarray, key: str) -> tuple:
    """The table that holds the fitted values of the model ``key`` for the sweeps ``rows`` of
    ``sw`` (the sweep results for a closed form; for an exact loop its fit table ``fits[key]``)
    and the positions of those sweeps in it."""
    if key not in EXACT_LOOPS:
        return sw, rows
    table = fits[key]
    at = pd.Index(table["sweep"]).get_indexer(sw["sweep"].to_numpy()[rows])
    if (at < 0).any():  # the analysis fits every loop to every sweep: a caller's mistake
        raise KeyError(f"sweeps without a row in the {key} fit table")
    return table, at


def _curves_of(sw: pd.DataFrame, fits: Fits, rows: np.ndarray, key: str, grid: np.ndarray) -> tuple:
    """Δf, ΔΓ (Hz) of the model ``key`` for the sweeps ``rows`` on ``grid`` (rows, N).

    One call of the model function for all of them (its parameters broadcast along the
    sweeps); where that fails (a sweep without a usable fit, e.g. NaN parameters that a loop's
    quadrature refuses) sweep by sweep, NaN for a sweep that fails alone."""
    model = REGISTRY[key]
    table, at = _values_of(sw, fits, rows, key)
    values = {q.key: table[q.column].to_numpy(float)[at][:, None] for q in model.parameters}
    try:
        f, g = model.function(grid, **values)
        return np.broadcast_to(f, grid.shape), np.broadcast_to(g, grid.shape)
    except ContactresInputError:  # some sweep of the batch has no curve: find which, one by one
        f, g = np.full(grid.shape, np.nan), np.full(grid.shape, np.nan)
        for j, (i, k) in enumerate(zip(rows, at, strict=True)):
            loop = table.iloc[k] if table is not sw else None
            try:
                f[j], g[j] = model_curves(sw.iloc[i], grid[j], loop)
            except ContactresInputError:  # no curve for this sweep: its points are drawn alone
                continue
        return f, g


def fitted_curves(sw: pd.DataFrame, p: Padded, fits: Fits, grids=CURVE_GRIDS) -> pd.DataFrame:
    """The chosen model of every sweep of ``sw`` on each grid of ``grids`` (see the module
    docstring).

    Parameters
    ----------
    sw : the per-sweep results (``sweep``, ``model``, ``limits_from`` and the fitted values of
        the closed forms in the columns that the registered parameters name)
    p : the sweeps' points (:func:`contactres.analysis._amplitude.pad_sweeps`), for the
        largest amplitude of each
    fits : the fit table of each model (:func:`contactres.analysis._models.fit_tables`,
        ``Results.fits``): the exact loops' values, by sweep
    grids : numbers of grid points (each a grid from 0 to the largest amplitude)

    Returns
    -------
    DataFrame
        ``sweep``, ``grid_points`` (the grid's number of points), ``amplitude_m`` (m),
        ``df_model_Hz``, ``dgamma_model_Hz`` (Hz; NaN where the sweep has no usable fit):
        per grid, sweep after sweep in the order of ``sw``.
    """
    S = len(sw)
    index = {s: i for i, s in enumerate(p.sweeps)}
    rows_p = np.array([index[s] for s in sw["sweep"]], dtype=np.intp)
    u_max = np.array([p.points(i)[0].max() for i in rows_p]) if S else np.zeros(0)
    key = np.array(
        [exact_model(m, lf) for m, lf in zip(sw["model"], sw["limits_from"], strict=True)],
        dtype=object,
    )
    parts = []
    for n in grids:
        grid = np.linspace(0.0, u_max, n, axis=-1)  # (S, n): row i is linspace(0, u_max[i], n)
        f, g = np.full(grid.shape, np.nan), np.full(grid.shape, np.nan)
        for k in sorted({k for k in key if k is not None}):
            rows = np.flatnonzero(key == k)
            f[rows], g[rows] = _curves_of(sw, fits, rows, k, grid[rows])
        parts.append(
            pd.DataFrame(
                {
                    "sweep": np.repeat(sw["sweep"].to_numpy(dtype=object), n),
                    "grid_points": np.full(S * n, n, dtype=np.int64),
                    "amplitude_m": grid.ravel(),
                    "df_model_Hz": f.ravel(),
                    "dgamma_model_Hz": g.ravel(),
                }
            )
        )
    return pd.concat(parts, ignore_index=True)


def sweep_rows(table: pd.DataFrame) -> dict:
    """Positions of the rows of each sweep in a long table with a ``sweep`` column (such as
    :func:`sweep_points` or :func:`fitted_curves`), in table order: sweep id -> int array."""
    return table.groupby("sweep", sort=False).indices


def jkr_curves(groups, loads: pd.DataFrame, n: int = JKR_POINTS, laws=None) -> pd.DataFrame:
    """The fitted JKR + Mindlin curve κ(F_N) of every group with an E, on the grid Fig. 5 draws.

    Parameters
    ----------
    groups : the group records of the analysis (``configuration``, ``medium``, ``E_Pa``,
        ``gamma_J_m2``, ``sphere_radius_m``, ``poisson``, ``P_Hz_per_N_per_m``)
    loads : the per-load table (``configuration``, ``normal_force_N``): the grid of a group
        runs from 0 to 1.05 times the largest load of its configuration (every medium)
    n : points per curve
    laws : {(configuration, medium): CoatedLaw} of a coated plate, or None
        With a coated plate the curve is that law's κ(F_N) (:mod:`contactres.analysis._coating`;
        NaN where the contact radius is outside its table).

    Returns
    -------
    DataFrame
        ``configuration``, ``medium``, ``normal_force_N`` (N), ``kappa_N_per_m`` (N/m, paper 2,
        Eqs. 6-10 with the fitted E and γ) and ``df0_model_Hz`` (= P κ, Hz, paper 2, Eq. 1);
        no rows for a group whose E is withheld.
    """
    from ..tangential import kappa_jkr_mindlin

    frames = []
    for g in groups:
        if not np.isfinite(g["E_Pa"]):
            continue
        part = loads[loads["configuration"] == g["configuration"]]
        F = np.linspace(0.0, part["normal_force_N"].max() * 1.05, n)
        law = (laws or {}).get((g["configuration"], g["medium"]))
        if law is None:
            k = kappa_jkr_mindlin(F, g["E_Pa"], g["gamma_J_m2"], g["sphere_radius_m"], g["poisson"])
        else:
            a, out = law.contact_radius(F, g["E_Pa"], g["gamma_J_m2"], g["sphere_radius_m"])
            k = np.where(out, np.nan, law.tangential(g["E_Pa"], a))
        frames.append(
            pd.DataFrame(
                {
                    "configuration": g["configuration"],
                    "medium": g["medium"],
                    "normal_force_N": F,
                    "kappa_N_per_m": k,
                    "df0_model_Hz": g["P_Hz_per_N_per_m"] * k,
                }
            )
        )
    columns = ["configuration", "medium", "normal_force_N", "kappa_N_per_m", "df0_model_Hz"]
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=columns)
