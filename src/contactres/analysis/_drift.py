"""Drift between the ramps of one load: a model-free F test on the points themselves.

Up and down ramps of a history-free (Masing) contact must give the same shifts (paper 2, Eqs.
4-5), so ramps of one load of one experiment that are offset from each other beyond the noise
mean that the baseline moved between them. Where the table gives the time of each point, a
drift linear in time can be removed instead of the load being left out
(:func:`remove_linear_drift`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ._amplitude import Padded
from ._distributions import f_upper_tail

__all__ = ["LOAD_OF_EXPERIMENT", "drifting_sweeps", "remove_linear_drift"]

#: Columns that identify one load of one experiment.
LOAD_OF_EXPERIMENT = ["experiment", "configuration", "medium", "normal_force_N"]


def _grouped(values: np.ndarray, group: np.ndarray, size: int) -> np.ndarray:
    return np.bincount(group, weights=values, minlength=size)


def _within(values: np.ndarray, group: np.ndarray, size: int, count: np.ndarray) -> np.ndarray:
    """``values`` minus their mean within each group."""
    return values - (_grouped(values, group, size) / np.maximum(count, 1))[group]


def _solve(M_inv: np.ndarray, v: np.ndarray) -> np.ndarray:
    """vᵀ M⁻¹ v for stacks of small symmetric matrices, given M's pseudo-inverses ``M_inv``
    (degenerate loads: ``np.linalg.pinv``, taken once for both channels)."""
    return np.einsum("li,lij,lj->l", v, M_inv, v)


def drifting_sweeps(sw: pd.DataFrame, padded: Padded, used: np.ndarray, p: float) -> np.ndarray:
    """True for the used sweeps of a load (experiment, configuration, medium, F_N) that drifts.

    All used ramps of the load are fitted with one common quadratic in u0, with and without an
    offset per ramp; the offsets are significant if the F statistic exceeds its ``1 - p/2``
    quantile in Δf or in ΔΓ (two channels, Bonferroni). All loads at once, from grouped sums:
    the common quadratic by its 3 x 3 normal equations on values centred per load, the model
    with offsets by the same on values centred per ramp (the offsets drop out).
    """
    flag = np.zeros(len(sw), bool)
    idx = np.flatnonzero(used)
    if idx.size == 0:
        return flag
    names = sw["sweep"].to_numpy(dtype=object)
    if len(names) == len(padded.sweeps) and (names == padded.sweeps).all():
        rows = idx  # the usual case: both in the order of the table (no hashing of 10^5 ids)
    else:
        row_of = pd.Series(np.arange(len(padded.sweeps)), index=padded.sweeps)
        rows = row_of.reindex(names[idx]).to_numpy()
    load = sw.iloc[idx].groupby(LOAD_OF_EXPERIMENT, sort=False).ngroup().to_numpy()
    L = load.max() + 1
    k = np.bincount(load, minlength=L)  # ramps per load
    u, df, dg = padded.points(rows)
    pt_load = np.repeat(load, padded.n[rows])
    pt_ramp = np.repeat(np.arange(idx.size), padded.n[rows])  # one group per sweep
    n = np.bincount(pt_load, minlength=L)
    n_ramp = np.bincount(pt_ramp, minlength=idx.size)
    scale = np.zeros(L)
    np.maximum.at(scale, pt_load, u)
    v = u / np.where(scale > 0, scale, 1.0)[pt_load]
    X = np.stack([v, v * v])  # the quadratic's columns besides the constant
    # Common quadratic (intercept per load): centre per load, then 2 x 2 normal equations.
    Xc = np.stack([_within(x, pt_load, L, n) for x in X])
    Xr = np.stack([_within(x, pt_ramp, idx.size, n_ramp) for x in X])
    M0 = np.stack([[_grouped(Xc[i] * Xc[j], pt_load, L) for j in range(2)] for i in range(2)])
    M1 = np.stack([[_grouped(Xr[i] * Xr[j], pt_load, L) for j in range(2)] for i in range(2)])
    # The pseudo-inverses depend on u0 alone: one SVD per load for Δf and ΔΓ both.
    M0_inv = np.linalg.pinv(M0.transpose(2, 0, 1))
    M1_inv = np.linalg.pinv(M1.transpose(2, 0, 1))
    d1 = k - 1
    d2 = n - 3 - d1
    testable = (k >= 2) & (d2 >= 2)
    drifting = np.zeros(L, bool)
    for y in (df, dg):
        yc, yr = _within(y, pt_load, L, n), _within(y, pt_ramp, idx.size, n_ramp)
        b0 = np.stack([_grouped(Xc[i] * yc, pt_load, L) for i in range(2)], axis=1)
        b1 = np.stack([_grouped(Xr[i] * yr, pt_load, L) for i in range(2)], axis=1)
        total = _grouped(yc * yc, pt_load, L)
        rss0 = np.maximum(total - _solve(M0_inv, b0), 0.0)
        rss1 = np.maximum(_grouped(yr * yr, pt_load, L) - _solve(M1_inv, b1), 0.0)
        tiny = 1e-12 * total + 1e-300  # rounding of the sums: a perfect fit
        with np.errstate(divide="ignore", invalid="ignore"):
            fstat = ((rss0 - rss1) / np.maximum(d1, 1)) / (rss1 / np.maximum(d2, 1))
            pval = f_upper_tail(np.maximum(d1, 1), np.maximum(d2, 1), fstat)
        pval = np.where(rss1 <= tiny, np.where(rss0 > tiny, 0.0, 1.0), pval)
        drifting |= testable & (pval < p / 2)
    flag[idx] = drifting[load]
    return flag


def remove_linear_drift(
    data: pd.DataFrame, loads: pd.DataFrame
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Remove a drift linear in time from the points of some loads of some experiments.

    For each load of ``loads`` (rows with the columns of :data:`LOAD_OF_EXPERIMENT` and
    ``sweeps``, the list of the sweeps that estimate the drift: its ramps after the first), Δf
    and ΔΓ of those sweeps' points are fitted with a common quadratic in u0 plus β t (t: the
    ``time_s`` column; linear least squares, per channel), and β (t - t_0) is subtracted from
    every point of the load (its first ramp too; t_0 its first time), so that the shifts read
    as at the start of the load. Returns the corrected copy of ``data`` and one row per load
    with ``drift_df_Hz_per_s`` and ``drift_dgamma_Hz_per_s`` (β of each channel).
    """
    data = data.copy()
    out = []
    where = data.groupby(LOAD_OF_EXPERIMENT, sort=False).indices if len(loads) else {}
    time = data["time_s"].to_numpy(float)
    for _, load in loads.iterrows():  # the drifting loads: a few
        this = where[tuple(load[c] for c in LOAD_OF_EXPERIMENT)]
        fit = this[np.isin(data["sweep"].to_numpy()[this], list(load["sweeps"]))]
        u = data["amplitude_m"].to_numpy(float)[fit]
        scale = u.max() if u.size and u.max() > 0 else 1.0
        t0 = float(time[this].min())
        X = np.column_stack([np.ones(u.size), u / scale, (u / scale) ** 2, time[fit] - t0])
        betas = {}
        for col in ("df_Hz", "dgamma_Hz"):
            values = data[col].to_numpy(float, copy=True)
            beta = float(np.linalg.lstsq(X, values[fit], rcond=None)[0][3])
            values[this] -= beta * (time[this] - t0)
            data[col] = values
            betas[f"drift_{col.removesuffix('_Hz')}_Hz_per_s"] = beta
        out.append({**{c: load[c] for c in LOAD_OF_EXPERIMENT}, **betas})
    return data, pd.DataFrame(out)
