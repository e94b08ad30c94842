"""Sweeps as padded arrays, and the closed-form amplitude fits solved for every sweep at once.

Three of the four amplitude descriptions of Δf(u0), ΔΓ(u0) (paper 2, Figs. 1D and 4) are linear
least squares: a constant (``elastic``), a straight line in u0 (``cattaneo-mindlin``, paper 2,
Eq. 12) and a straight line in u0² (``savkoor``, paper 2, Eq. 15). The fourth, a hinge (flat
below u_c, linear above: the ``plateau`` of Fig. 4C, D), is linear once u_c is fixed, and u_c is
searched on a grid. All of them are solved in closed form for every sweep at once: the sweeps are
padded to a common length and the padding is weighted 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = [
    "PLATEAU_MIN_FLAT",
    "PLATEAU_MIN_SLOPE",
    "PLATEAU_SUBSTEPS",
    "HingeFit",
    "LineFit",
    "Padded",
    "bic",
    "fit_hinge",
    "fit_line",
    "pad_sweeps",
]

# Plateau search: points on the plateau / on the slope, and the sub-steps between amplitudes.
PLATEAU_MIN_FLAT = 2
PLATEAU_MIN_SLOPE = 3
PLATEAU_SUBSTEPS = (0.0, 0.25, 0.5, 0.75)


@dataclass(frozen=True)
class Padded:
    """Sweeps as padded 2-D arrays (one row per sweep, amplitudes ascending, padding weight 0)."""

    sweeps: np.ndarray  # sweep ids, order of first appearance
    u: np.ndarray  # amplitude, m
    df: np.ndarray  # Hz
    dg: np.ndarray  # Hz
    w: np.ndarray  # 1 for data, 0 for padding
    n: np.ndarray  # points per sweep
    direction: np.ndarray  # "up", "down" or "mixed" (order of amplitudes in the file)


def pad_sweeps(table: pd.DataFrame) -> Padded:
    """Arrange the points of a sweep table (a DataFrame of its columns) into padded arrays."""
    codes, names = pd.factorize(table["sweep"], sort=False)
    u = table["amplitude_m"].to_numpy(float)
    order = np.lexsort((u, codes))
    codes_s = codes[order]
    counts = np.bincount(codes, minlength=len(names))
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    pos = np.arange(len(order)) - starts[codes_s]
    m = int(counts.max())
    shape = (len(names), m)
    U, DF, DG, W = (np.zeros(shape) for _ in range(4))
    U[codes_s, pos] = u[order]
    DF[codes_s, pos] = table["df_Hz"].to_numpy(float)[order]
    DG[codes_s, pos] = table["dgamma_Hz"].to_numpy(float)[order]
    W[codes_s, pos] = 1.0
    # Padding repeats the largest amplitude so that max() and grids stay meaningful.
    last = U[np.arange(len(names)), counts - 1]
    U = np.where(W > 0, U, last[:, None])
    # Direction from the file order of the amplitudes: up, down, or mixed.
    same = codes[1:] == codes[:-1]
    step = np.diff(u)
    rises = np.bincount(codes[1:][same & (step > 0)], minlength=len(names)) > 0
    falls = np.bincount(codes[1:][same & (step < 0)], minlength=len(names)) > 0
    direction = np.where(rises & falls, "mixed", np.where(falls, "down", "up"))
    return Padded(np.asarray(names), U, DF, DG, W, counts, direction)


@dataclass(frozen=True)
class LineFit:
    """Weighted straight lines y = a + b x, one per row and channel (arrays of shape (2, ...)).

    ``var_a``, ``var_b``, ``cov_ab``: covariance from the residual variance rss/(Σw - 2);
    ``rss``: weighted residual sum of squares.
    """

    a: np.ndarray
    b: np.ndarray
    var_a: np.ndarray
    var_b: np.ndarray
    cov_ab: np.ndarray
    rss: np.ndarray

    def fields(self) -> tuple[np.ndarray, ...]:
        """The six arrays, in the order of the attributes."""
        return (self.a, self.b, self.var_a, self.var_b, self.cov_ab, self.rss)


def fit_line(X, Y, W) -> LineFit:
    """Weighted straight line y = a + b x per row (closed form), both channels at once.

    X, W: (..., M); Y: (2, ..., M) (Δf and ΔΓ).
    """
    S0 = W.sum(-1)
    Sx = (W * X).sum(-1)
    Sxx = (W * X * X).sum(-1)
    Sy = (W * Y).sum(-1)
    Sxy = (W * X * Y).sum(-1)
    D = S0 * Sxx - Sx**2
    ok = D > 1e-300 * np.maximum(Sxx * S0, 1e-300)
    Dsafe = np.where(ok, D, 1.0)
    b = np.where(ok, (S0 * Sxy - Sx * Sy) / Dsafe, 0.0)
    a = (Sy - b * Sx) / S0
    rss = (W * (Y - a[..., None] - b[..., None] * X) ** 2).sum(-1)
    s2 = rss / np.maximum(S0 - 2, 1)
    var_a = np.where(ok, s2 * Sxx / Dsafe, np.inf)
    var_b = np.where(ok, s2 * S0 / Dsafe, np.inf)
    cov_ab = np.where(ok, -s2 * Sx / Dsafe, 0.0)
    return LineFit(a, b, var_a, var_b, cov_ab, rss)


def bic(rss, n, k):
    """BIC of a two-channel fit with separate unknown noise levels; rss: (2, S), n: (S,).

    ``BIC = n ln(RSS_f/n) + n ln(RSS_Γ/n) + k ln(2n)`` for k parameters.
    """
    # Floor: a perfect fit (rss = 0, e.g. noiseless synthetic data) must not give -inf.
    floor = 1e-30
    return (
        n * np.log(np.maximum(rss[0], floor) / n)
        + n * np.log(np.maximum(rss[1], floor) / n)
        + k * np.log(2 * n)
    )


@dataclass(frozen=True)
class HingeFit:
    """The best hinge of every sweep: its lines (above u_c), u_c, and whether one was found."""

    line: LineFit  # arrays (2, S)
    u_c: np.ndarray  # (S,), m
    found: np.ndarray  # (S,) bool: False if no u_c leaves enough points on both sides


def fit_hinge(p: Padded) -> HingeFit:
    """Hinge Δf = Δf0 + s_f max(u0 - u_c, 0) (likewise ΔΓ) of every sweep, u_c on a grid.

    u_c is searched at the data amplitudes and at :data:`PLATEAU_SUBSTEPS` between them, with at
    least :data:`PLATEAU_MIN_FLAT` points on the plateau and :data:`PLATEAU_MIN_SLOPE` on the
    slope; the best u_c minimises ln RSS_f + ln RSS_Γ. (For a contact that sticks below a
    critical displacement d_c, the shifts leave the plateau smoothly, so the hinge lies at or up
    to ~2 amplitude steps above d_c.)
    """
    Y = np.stack([p.df, p.dg])
    S = p.u.shape[0]
    t = np.asarray(PLATEAU_SUBSTEPS)
    u_next = np.concatenate([p.u[:, 1:], p.u[:, -1:]], axis=1)
    uc = p.u[:, :, None] + t[None, None, :] * (u_next - p.u)[:, :, None]  # (S, M, T)
    Xh = np.maximum(p.u[:, None, None, :] - uc[..., None], 0.0)  # (S, M, T, M)
    Wh = np.broadcast_to(p.w[:, None, None, :], Xh.shape)
    n_flat = (Wh * (Xh == 0.0)).sum(-1)  # points with u0 <= u_c
    gap = (u_next - p.u)[:, :, None] > 0
    valid = (n_flat >= PLATEAU_MIN_FLAT) & (p.n[:, None, None] - n_flat >= PLATEAU_MIN_SLOPE)
    valid &= gap | (t[None, None, :] == 0)
    lines = fit_line(Xh, Y[:, :, None, None, :], Wh)
    crit = np.where(
        valid,
        np.log(np.maximum(lines.rss[0], 1e-30)) + np.log(np.maximum(lines.rss[1], 1e-30)),
        np.inf,
    )
    flat = crit.reshape(S, -1)
    best = np.argmin(flat, axis=1)
    rows = np.arange(S)
    picked = LineFit(*(f.reshape(2, S, -1)[:, rows, best] for f in lines.fields()))
    return HingeFit(picked, uc.reshape(S, -1)[rows, best], np.isfinite(flat[rows, best]))
