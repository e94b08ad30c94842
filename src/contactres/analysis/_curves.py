"""The points of every sweep as analysed and its fitted model on the grids the report draws.

The figures (paper 2, Fig. 4) and the HTML page draw each sweep's points with the curve of the
model chosen for it. Both are computed here, once, by the analysis, and carried by the results
(:attr:`contactres.analysis.Results.points`, :attr:`~contactres.analysis._results.
Results.curves`), so that the report draws numbers and never evaluates a model or reads the
analysis' internal arrays.

The curve of a sweep is the registered model function (:mod:`contactres.analysis._models`) of
its class, evaluated with its fitted values; a sweep whose limits come from an exact loop (the
Cattaneo-Mindlin, Savkoor or plateau loop, paper 2, Eqs. 4-6 and 13-14) is drawn as that loop
(:func:`~contactres.analysis._models.model_curves`, the same function per sweep), with the
values of that loop's fit table (``Results.fits``); a closed form with the named columns of
the sweep results. The exact loops are evaluated in closed form or by power series
(:func:`contactres.analysis._models.cm_loop.cm_shape`, :func:`~contactres.analysis._models.
cm_loop.loop_shape`, :func:`~contactres.analysis._models.savkoor_loop.savkoor_shape`, within
~1e-12 of the quadrature of :func:`contactres.loop_stiffness`): ~0.1-0.2 µs per curve point,
not ~2 µs. The grid
runs from u0 = 0 to the sweep's largest amplitude in :data:`FIGURE_POINTS` (Fig. 4) and
:data:`PAGE_POINTS` (the inline SVG of the page and ``curves.csv``) equal steps. A grid may
hold a subset of the sweeps: by default (:func:`contactres.analyze`'s ``curve_grids=None``)
Fig. 4's holds only the sweeps that figure draws (:mod:`contactres.analysis._examples`), the
page's every sweep.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ._amplitude import Padded
from ._models import EXACT_LOOPS, REGISTRY, exact_model, model_curves
from ._workers import WorkerPool, lent_pool

__all__ = [
    "CURVE_GRIDS",
    "FIGURE_POINTS",
    "PAGE_POINTS",
    "band_half_width",
    "fitted_curves",
    "jkr_curves",
    "model_keys",
    "sweep_points",
    "sweep_rows",
]

#: Points of the model curve of a sweep in the PNG figures (Fig. 4).
FIGURE_POINTS = 100
#: Points of the model curve of a sweep in the inline SVG plots of the HTML page.
PAGE_POINTS = 30
#: The grids of :func:`fitted_curves`, by number of points.
CURVE_GRIDS = (FIGURE_POINTS, PAGE_POINTS)
#: Curve points (sweeps x grid points) per call of a model function. The exact loops' closed
#: forms hold some ten arrays of the chunk's size (a few MB at this size; the quadrature of
#: Savkoor's loop near full sliding, ~48 nodes per point and sub-interval, goes by smaller
#: chunks of its own, :data:`~contactres.analysis._models.savkoor_loop.BAND_CHUNK`). Chunks
#: 4x smaller cost a third more CPU time in calls on smaller arrays (10^4 sweeps).
CHUNK_POINTS = 2**16
#: Points of the JKR + Mindlin curve of a group (Fig. 5), from F_N = 0 to 1.05 times the
#: configuration's largest load.
JKR_POINTS = 100

# The fit table of each model, by key (``Results.fits``).
Fits = Mapping[str, pd.DataFrame]


def _label_column(ids: np.ndarray, labels: np.ndarray) -> pd.Series:
    """``labels`` (an object array of values of ``ids``, each id repeated) as a column of the
    dtype that pandas infers for ``ids``: the column pandas would make of ``labels``, made
    without a copy.

    Why: a frame made of an object array infers its dtype (pandas' ``str`` for sweep ids) by
    converting the whole array, which at 10^5 sweeps held ~0.6 GB of temporaries for the
    13 million labels of :func:`fitted_curves` (issue 31, point 3); inferred from the distinct
    ids and given, the labels are only checked and wrapped."""
    return pd.Series(labels, dtype=pd.Series(ids).dtype, copy=False)


def sweep_points(p: Padded) -> pd.DataFrame:
    """The points of every sweep as the analysis fitted them (after any drift correction).

    Returns
    -------
    DataFrame
        ``sweep``, ``amplitude_m`` (m), ``df_Hz``, ``dgamma_Hz`` (Hz): sweep after sweep in the
        order of ``p``, amplitudes ascending within a sweep.
    """
    # Every sweep in order is the flat arrays themselves where the sweeps lie back to back (as
    # pad_sweeps lays them): taken as they are, not gathered into copies (and copy=False, as
    # pandas copies the columns of a dict by default), which at 10^5 sweeps kept ~60 MB of
    # duplicates alive to the end of the analysis (issue 31, point 3).
    if np.array_equal(p.start, np.cumsum(p.n) - p.n) and p.n.sum() == p.points_u.size:
        u, df, dg = p.points_u, p.points_df, p.points_dg
    else:
        u, df, dg = p.points(np.arange(len(p.n)))
    ids = np.asarray(p.sweeps, dtype=object)
    return pd.DataFrame(
        {
            "sweep": _label_column(ids, np.repeat(ids, p.n)),
            "amplitude_m": u,
            "df_Hz": df,
            "dgamma_Hz": dg,
        },
        copy=False,
    )


def _lookup(sw: pd.DataFrame, fits: Fits, key: str) -> tuple[pd.DataFrame, np.ndarray]:
    """The table that holds the fitted values of the model ``key`` (the sweep results for a
    closed form; for an exact loop its fit table ``fits[key]``) and the position in it of every
    sweep of ``sw`` (-1: none). Found once per model: looking the sweeps up chunk by chunk hashed
    the whole fit table for every chunk (quadratic in the number of sweeps)."""
    if key not in EXACT_LOOPS:
        return sw, np.arange(len(sw))
    table = fits[key]
    return table, pd.Index(table["sweep"]).get_indexer(sw["sweep"].to_numpy())


def _values_of(found: tuple[pd.DataFrame, np.ndarray], rows: np.ndarray, key: str) -> tuple:
    """The table of :func:`_lookup` (``found``) and the positions in it of the sweeps
    ``rows``."""
    table, at = found
    at = at[rows]
    if (at < 0).any():  # the analysis fits every loop to every sweep: a caller's mistake
        raise KeyError(f"sweeps without a row in the {key} fit table")
    return table, at


def _parameters(found: tuple[pd.DataFrame, np.ndarray], rows: np.ndarray, key: str) -> dict:
    """The fitted values of the model ``key`` for the sweeps ``rows`` (``found``: its
    :func:`_lookup`), (rows, 1) each."""
    table, at = _values_of(found, rows, key)
    return {q.key: table[q.column].to_numpy(float)[at][:, None] for q in REGISTRY[key].parameters}


def _model_on(key: str, values: dict[str, np.ndarray], grid: np.ndarray) -> tuple | None:
    """Δf, ΔΓ (Hz) of the model ``key`` with ``values`` ((rows, 1) each) on ``grid`` (rows, N),
    or None where the model function refuses some sweep of the batch (a picklable call for
    :func:`fitted_curves`)."""
    try:
        f, g = REGISTRY[key].function(grid, **values)
    except ContactresInputError:
        return None
    return np.broadcast_to(f, grid.shape), np.broadcast_to(g, grid.shape)


def _one_by_one(sw: pd.DataFrame, found, rows: np.ndarray, key: str, grid: np.ndarray):
    """Δf, ΔΓ (Hz) of the model ``key`` for the sweeps ``rows`` on ``grid`` (rows, N), sweep
    by sweep (``found``: its :func:`_lookup`): NaN for a sweep that fails alone (where the batch
    of :func:`_model_on` failed)."""
    table, at = _values_of(found, rows, key)
    f, g = np.full(grid.shape, np.nan), np.full(grid.shape, np.nan)
    for j, (i, k) in enumerate(zip(rows, at, strict=True)):
        loop = table.iloc[k] if table is not sw else None
        try:
            f[j], g[j] = model_curves(sw.iloc[i], grid[j], loop)
        except ContactresInputError:  # no curve for this sweep: its points are drawn alone
            continue
    return f, g


def model_keys(model: pd.Series, limits_from: pd.Series) -> np.ndarray:
    """:func:`~contactres.analysis._models.exact_model` of every sweep (object array, None
    where a sweep has none), called once per distinct (``model``, ``limits_from``) pair.

    Why: a sweep table holds a handful of pairs over 10^5 sweeps, and a Python call per sweep
    cost ~1 s of ``qcm analyze`` there (issue 31, point 3). Gaps (None, NaN) are one value
    to the factorisation, as they are to exact_model (no model: None; no source: the class)."""
    m_codes, m_values = pd.factorize(model, use_na_sentinel=False)
    l_codes, l_values = pd.factorize(limits_from, use_na_sentinel=False)
    width = max(1, len(l_values))
    distinct, inverse = np.unique(m_codes.astype(np.int64) * width + l_codes, return_inverse=True)
    keys = np.empty(len(distinct), dtype=object)
    keys[:] = [exact_model(m_values[c // width], l_values[c % width]) for c in distinct.tolist()]
    return keys[inverse.reshape(-1)]


def fitted_curves(
    sw: pd.DataFrame,
    p: Padded,
    fits: Fits,
    grids=CURVE_GRIDS,
    workers: int | WorkerPool = 1,
    held: Mapping[int, np.ndarray] | None = None,
) -> pd.DataFrame:
    """The chosen model of the sweeps of ``sw`` on each grid of ``grids`` (see the module
    docstring): every sweep, or on a grid named in ``held`` the sweeps it holds.

    The model function of each class is called once per chunk of sweeps (at most
    :data:`CHUNK_POINTS` curve points, its parameters broadcast along the sweeps); where a
    chunk fails (a sweep without a usable fit, e.g. NaN parameters that a loop's shape
    refuses) its sweeps are evaluated one by one, NaN for a sweep that fails alone. Each curve
    depends on its own sweep's values only, so chunks, processes and the other sweeps a grid
    holds do not change it.

    Parameters
    ----------
    sw : the per-sweep results (``sweep``, ``model``, ``limits_from`` and the fitted values of
        the closed forms in the columns that the registered parameters name)
    p : the sweeps' points (:func:`contactres.analysis._amplitude.pad_sweeps`), for the
        largest amplitude of each
    fits : the fit table of each model (:func:`contactres.analysis._models.fit_tables`,
        ``Results.fits``): the exact loops' values, by sweep
    grids : numbers of grid points (each a grid from 0 to the largest amplitude)
    workers : processes for the chunks (1: none, in this process), or the analysis's
        :class:`~contactres.analysis._workers.WorkerPool`
    held : by number of grid points, which sweeps of ``sw`` that grid holds (a boolean per
        row of ``sw``, e.g. those Fig. 4 draws,
        :func:`contactres.analysis._examples.drawn_in_figure`); a grid not named holds every
        sweep (None: each grid every sweep)

    Returns
    -------
    DataFrame
        ``sweep``, ``grid_points`` (the grid's number of points), ``amplitude_m`` (m),
        ``df_model_Hz``, ``dgamma_model_Hz`` (Hz; NaN where the sweep has no usable fit):
        per grid (in the order of ``grids``), sweep after sweep in the order of ``sw``.
    """
    S = len(sw)
    held = held or {}
    if any(np.shape(mask) != (S,) for mask in held.values()):
        raise ValueError(f"held: one boolean per sweep ({S}) for each grid named")
    # The positions in sw of each grid's sweeps (ascending: the order of sw).
    where = {n: np.flatnonzero(held[n]) if n in held else np.arange(S) for n in grids}
    rows_p = pd.Index(p.sweeps).get_indexer(sw["sweep"].to_numpy())
    u_max = p.u_max[rows_p]  # the points of a sweep are in ascending amplitude
    key = model_keys(sw["model"], sw["limits_from"])
    # The columns of the result, each grid's rows a (sweeps, n) view: filled in place, no copies.
    sizes = [where[n].size * n for n in grids]
    amplitude, shifts = np.empty(sum(sizes)), np.full((2, sum(sizes)), np.nan)  # Δf, ΔΓ
    ends = np.cumsum(sizes)
    grid, curves = {}, {}
    for n, end, size in zip(grids, ends, sizes, strict=True):
        at, shape = slice(end - size, end), (where[n].size, n)
        grid[n] = amplitude[at].reshape(shape)
        grid[n][:] = np.linspace(0.0, u_max[where[n]], n, axis=-1)  # row i: 0 to its u_max
        curves[n] = (shifts[0, at].reshape(shape), shifts[1, at].reshape(shape))
    # Every (grid, model, chunk of sweeps) is one call of the model function: its sweeps by
    # position in sw (for their values) and in the grid's rows (for their grid and curves).
    tasks: list[tuple[int, str, np.ndarray, np.ndarray]] = []
    for n in grids:
        mine = key[where[n]]
        for k in sorted({k for k in set(mine.tolist()) if k is not None}):
            local = np.flatnonzero(mine == k)
            size = max(1, CHUNK_POINTS // n)
            for chunk in np.split(local, range(size, local.size, size)):
                tasks.append((n, k, where[n][chunk], chunk))
    keys = [k for _, k, _, _ in tasks]
    found = {k: _lookup(sw, fits, k) for k in set(keys)}
    # Generators: each chunk's parameters and grid are made when its call comes (serial) or
    # sent (a pool), and each result is put in place as it arrives.
    values = (_parameters(found[k], rows, k) for _, k, rows, _ in tasks)
    grids_of = (grid[n][local] for n, _, _, local in tasks)
    with lent_pool(workers) as pool:
        done = pool.imap(_model_on, len(tasks), keys, values, grids_of, chunksize=4)
        for (n, k, rows, local), fg in zip(tasks, done, strict=True):
            if fg is None:  # some sweep of the chunk has no curve: find which, one by one
                fg = _one_by_one(sw, found[k], rows, k, grid[n][local])
            curves[n][0][local], curves[n][1][local] = fg
    # Each grid's labels a (sweeps, n) view of one array, filled in place (no per-grid copies).
    ids = sw["sweep"].to_numpy(dtype=object)
    labels = np.empty(sum(sizes), dtype=object)
    for n, end, size in zip(grids, ends, sizes, strict=True):
        labels[end - size : end].reshape(where[n].size, n)[:] = ids[where[n], None]
    columns = {
        "sweep": _label_column(ids, labels),
        "grid_points": np.repeat(np.asarray(grids, dtype=np.int64), sizes),
        "amplitude_m": amplitude,
        "df_model_Hz": shifts[0],
        "dgamma_model_Hz": shifts[1],
    }
    return pd.DataFrame(columns, copy=False)


def sweep_rows(table: pd.DataFrame) -> dict:
    """Positions of the rows of each sweep in a long table with a ``sweep`` column (such as
    :func:`sweep_points` or :func:`fitted_curves`), in table order: sweep id -> int array."""
    return table.groupby("sweep", sort=False).indices


def band_half_width(kappa_of, values, covariance, factor: float, lower=None) -> np.ndarray:
    """Half-width of the pointwise band of a fitted curve, by linear propagation of the
    covariance of its parameters (the delta method): ``factor`` x sqrt(diag(J Σ Jᵀ)).

    J is the Jacobian of the curve with respect to the parameters, by central differences
    (one-sided where a parameter sits within a step of its lower bound, e.g. γ = 0), a step of
    10⁻³ standard errors: far below the scale on which the curve bends over the parameters'
    spread (the linearisation's own error), far above the rounding of the curve.

    Parameters
    ----------
    kappa_of : (values...) -> array, the curve at the parameters ``values`` (every point of
        the curve at once)
    values : the fitted parameters, length p
    covariance : (p, p), their covariance (units of the parameters squared)
    factor : the multiple of the standard deviation the band spans on each side (1.96 for 95 %
        of a normal law; the group's Student-t factor ``t95`` for errors from few repeats)
    lower : lower bounds of the parameters (default: none)

    Returns
    -------
    ndarray
        The half-width at every point of the curve (its units; NaN where the curve is NaN).
    """
    theta = np.asarray(values, dtype=float)
    cov = np.asarray(covariance, dtype=float)
    low = np.full(theta.size, -np.inf) if lower is None else np.asarray(lower, dtype=float)
    h = 1e-3 * np.sqrt(np.diag(cov))
    centre = None  # the curve at the values: only a one-sided difference needs it
    columns = []
    for i in range(theta.size):
        up, down = theta.copy(), theta.copy()
        up[i] += h[i]
        if theta[i] - h[i] >= low[i]:
            down[i] -= h[i]
            columns.append((np.asarray(kappa_of(*up)) - np.asarray(kappa_of(*down))) / (2 * h[i]))
        else:  # within a step of the bound: the curve is not defined below it
            if centre is None:
                # (a coated plate's curve costs a contact-radius solve per call)
                centre = np.asarray(kappa_of(*theta), dtype=float)
            columns.append((np.asarray(kappa_of(*up)) - centre) / h[i])
    J = np.stack(columns, axis=-1)  # (points, p)
    variance = np.einsum("ni,ij,nj->n", J, cov, J)
    return factor * np.sqrt(np.maximum(variance, 0.0))


def _table_covariance(g) -> np.ndarray | None:
    """The covariance of (E, γ) that Table 1's errors give for a group record (Pa², Pa J/m²,
    (J/m²)²): diag(E_err, γ_err) · C · diag(E_err, γ_err) with ``E_err_Pa``,
    ``gamma_err_J_m2`` and C the correlation ``E_gamma_corr`` that goes with them (the
    bootstrap's where a bootstrap gives the errors, else the fit's); None where one is missing
    or an error is not positive (no covariance to propagate)."""
    sd = np.array([g.get("E_err_Pa", np.nan), g.get("gamma_err_J_m2", np.nan)], float)
    rho = float(g.get("E_gamma_corr", np.nan))
    if not (np.isfinite(sd).all() and np.isfinite(rho) and (sd > 0).all()):
        return None
    return np.outer(sd, sd) * np.array([[1.0, rho], [rho, 1.0]])


def jkr_curves(groups, loads: pd.DataFrame, n: int = JKR_POINTS, laws=None) -> pd.DataFrame:
    """The fitted JKR + Mindlin curve κ(F_N) of every group with an E, on the grid Fig. 5 draws,
    with its 95 % pointwise band.

    The band is the linear propagation (:func:`band_half_width`) of the covariance of E and γ
    that Table 1 prints: its errors ``E_err_Pa``, ``gamma_err_J_m2`` (the spread between
    experiments where a bootstrap over them gives the errors, ``error_method``) with their
    correlation ``E_gamma_corr`` (over the same bootstrap's resamples, else the fit's,
    ``inv(JᵀJ)·RSS/(N - 2)`` of :func:`contactres.fitting.fit`), ``t95`` standard deviations
    on each side: the Student-t factor of Table 1's 95 % interval (t(0.975; experiments - 1)
    for a bootstrap over experiments, t(0.975; N - 2) for the fit's errors, N the points
    fitted). So the band at a load holds the curves that Table 1's E ± t95 err, γ ± t95 err
    allow, correlated as they are; empty (NaN) where there is no such covariance or factor.

    Parameters
    ----------
    groups : the group records of the analysis (``configuration``, ``medium``, ``E_Pa``,
        ``gamma_J_m2``, ``sphere_radius_m``, ``poisson``, ``P_Hz_per_N_per_m``; for the band
        ``E_err_Pa``, ``gamma_err_J_m2``, ``E_gamma_corr``, ``t95``)
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
        Eqs. 6-10 with the fitted E and γ), ``kappa_lo_N_per_m``, ``kappa_hi_N_per_m`` (N/m,
        the band), ``df0_model_Hz`` (= P κ, Hz, paper 2, Eq. 1), ``df0_model_lo_Hz``,
        ``df0_model_hi_Hz`` (Hz, the band times P); no rows for a group whose E is withheld.
    """
    from ..tangential import kappa_jkr_mindlin

    frames = []
    for g in groups:
        if not np.isfinite(g["E_Pa"]):
            continue
        part = loads[loads["configuration"] == g["configuration"]]
        F = np.linspace(0.0, part["normal_force_N"].max() * 1.05, n)
        law = (laws or {}).get((g["configuration"], g["medium"]))
        R, nu = g["sphere_radius_m"], g["poisson"]

        def kappa_of(E, gamma, F=F, law=law, R=R, nu=nu):
            if law is None:
                return kappa_jkr_mindlin(F, E, gamma, R, nu)
            a, out = law.contact_radius(F, E, gamma, R)
            return np.where(out, np.nan, law.tangential(E, a))

        k = kappa_of(g["E_Pa"], g["gamma_J_m2"])
        half = np.full(F.shape, np.nan)  # no band where Table 1's errors give no covariance
        cov = _table_covariance(g)
        t = float(g.get("t95", np.nan))
        if cov is not None and np.isfinite(t):
            values = (g["E_Pa"], g["gamma_J_m2"])
            half = band_half_width(kappa_of, values, cov, t, lower=(0.0, 0.0))
        P = g["P_Hz_per_N_per_m"]
        frames.append(
            pd.DataFrame(
                {
                    "configuration": g["configuration"],
                    "medium": g["medium"],
                    "normal_force_N": F,
                    "kappa_N_per_m": k,
                    "kappa_lo_N_per_m": k - half,
                    "kappa_hi_N_per_m": k + half,
                    "df0_model_Hz": P * k,
                    # |P|: the band's ends in order whatever the sign convention of P
                    "df0_model_lo_Hz": P * k - abs(P) * half,
                    "df0_model_hi_Hz": P * k + abs(P) * half,
                }
            )
        )
    columns = [
        "configuration", "medium", "normal_force_N", "kappa_N_per_m", "kappa_lo_N_per_m",
        "kappa_hi_N_per_m", "df0_model_Hz", "df0_model_lo_Hz", "df0_model_hi_Hz",
    ]  # fmt: skip
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=columns)
