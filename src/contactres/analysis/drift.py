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
from scipy.special import fdtrc

from .amplitude import Padded

__all__ = ["LOAD_OF_EXPERIMENT", "drifting_sweeps", "remove_linear_drift"]

#: Columns that identify one load of one experiment.
LOAD_OF_EXPERIMENT = ["experiment", "configuration", "medium", "normal_force_N"]


def _offset_p_value(base: np.ndarray, full: np.ndarray, y: np.ndarray, k: int) -> float:
    """False-alarm probability of per-ramp offsets (``full``) over a common curve (``base``)."""
    r0 = y - base @ np.linalg.lstsq(base, y, rcond=None)[0]
    r1 = y - full @ np.linalg.lstsq(full, y, rcond=None)[0]
    rss0, rss1 = r0 @ r0, r1 @ r1
    d1, d2 = k - 1, y.size - full.shape[1]
    if rss1 <= 0:
        return 0.0 if rss0 > 0 else 1.0
    fstat = ((rss0 - rss1) / d1) / (rss1 / d2)
    return float(fdtrc(d1, d2, fstat))  # survival function of the F distribution


def drifting_sweeps(sw: pd.DataFrame, padded: Padded, used: np.ndarray, p: float) -> np.ndarray:
    """True for the used sweeps of a load (experiment, configuration, medium, F_N) that drifts.

    All used ramps of the load are fitted with one common quadratic in u0, with and without an
    offset per ramp; the offsets are significant if the F statistic exceeds its ``1 - p/2``
    quantile in Δf or in ΔΓ (two channels, Bonferroni).
    """
    flag = np.zeros(len(sw), bool)
    used_idx = np.flatnonzero(used)
    row_of = {s: i for i, s in enumerate(padded.sweeps)}
    padded_row = np.array([row_of[s] for s in sw["sweep"]], dtype=int)
    for pos in sw.iloc[used_idx].groupby(LOAD_OF_EXPERIMENT, sort=False).indices.values():
        idx = used_idx[pos]  # positions in sw
        k = len(idx)
        if k < 2:
            continue
        rows = padded_row[idx]
        u, df, dg = padded.points(rows)
        ramp = np.repeat(np.arange(k), padded.n[rows])
        n = u.size
        if n - 3 - (k - 1) < 2:
            continue
        scale = u.max() if u.max() > 0 else 1.0
        base = np.column_stack([np.ones(n), u / scale, (u / scale) ** 2])
        dummies = (ramp[:, None] == np.arange(1, k)[None, :]).astype(float)
        full = np.column_stack([base, dummies])
        pvals = [_offset_p_value(base, full, y, k) for y in (df, dg)]
        if min(pvals) < p / 2:
            flag[idx] = True
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
