"""Sweeps as flat point arrays with padded blocks, and the closed-form amplitude fits.

Three of the four amplitude descriptions of Δf(u0), ΔΓ(u0) (paper 2, Figs. 1D and 4) are linear
least squares: a constant (``elastic``), a straight line in u0 (``cattaneo-mindlin``, paper 2,
Eq. 12) and a straight line in u0² (``savkoor``, paper 2, Eq. 15). The fourth, a hinge (flat
below u_c, linear above: the ``plateau`` of Fig. 4C, D), is linear once u_c is fixed, and u_c is
searched on a grid. All of them are solved in closed form for many sweeps at once.

**Layout.** :class:`Padded` keeps the points flat, sweep after sweep, so that memory grows with
the number of points. The fits run on blocks (:meth:`Padded.blocks`): sweeps of similar length,
padded to the longest of the block with weight 0, a bounded number of points per block. One long
sweep among short ones therefore pads only its own block.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.lib.mixins import NDArrayOperatorsMixin

from ..numerics import factorize_runs, repeat_runs, run_starts

__all__ = [
    "BLOCK_POINTS",
    "PLATEAU_MIN_FLAT",
    "PLATEAU_MIN_SLOPE",
    "PLATEAU_SUBSTEPS",
    "Block",
    "HingeFit",
    "LineFit",
    "Padded",
    "PaddedRows",
    "bic",
    "fit_hinge",
    "fit_line",
    "pad_sweeps",
    "row_sets",
]

# Plateau search: points on the plateau / on the slope, and the sub-steps between amplitudes.
PLATEAU_MIN_FLAT = 2
PLATEAU_MIN_SLOPE = 3
PLATEAU_SUBSTEPS = (0.0, 0.25, 0.5, 0.75)

#: Padded points (rows x longest sweep) of one block: its arrays stay at a few MB.
BLOCK_POINTS = 1 << 16

# Sweeps of up to EXACT_LENGTH points are blocked by their exact length (no padding, same sums
# as one common padding for the usual 10-20-point sweeps); longer ones in classes of
# LENGTH_RATIO, so that padding adds at most 25 % and the number of blocks stays small.
EXACT_LENGTH = 16
LENGTH_RATIO = 1.25

# Hinge candidates re-ranked with the direct residual sums (the suffix sums only rank them).
HINGE_RECHECK = 4


@dataclass(frozen=True)
class Block:
    """Some sweeps as padded 2-D arrays (one row per sweep, amplitudes ascending, padding weight
    0 and amplitude equal to the sweep's largest): what the fits take."""

    rows: np.ndarray  # (S,) rows of these sweeps in the Padded
    u: np.ndarray  # (S, M) amplitude, m
    df: np.ndarray  # (S, M) Hz
    dg: np.ndarray  # (S, M) Hz
    w: np.ndarray  # (S, M) 1 for data, 0 for padding
    n: np.ndarray  # (S,) points per sweep


@dataclass(frozen=True)
class Padded:
    """The points of every sweep, flat: sweep after sweep, amplitudes ascending within a sweep.

    Memory is linear in the number of points. :meth:`block` pads some sweeps to a common
    length, :meth:`blocks` groups the sweeps into such blocks of similar length, and
    :meth:`points` returns the points of some sweeps, concatenated. ``u``, ``df``, ``dg`` and
    ``w`` (:class:`PaddedRows`) pad the sweeps that they are indexed with, on request.
    """

    sweeps: np.ndarray  # (S,) sweep ids, order of first appearance
    n: np.ndarray  # (S,) points per sweep
    direction: np.ndarray  # (S,) "up", "down" or "mixed" (order of amplitudes in the file)
    start: np.ndarray  # (S,) index of each sweep's first point in the flat arrays
    points_u: np.ndarray  # (N,) amplitude, m
    points_df: np.ndarray  # (N,) Hz
    points_dg: np.ndarray  # (N,) Hz

    def points(self, rows) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Amplitudes (m), Δf and ΔΓ (Hz) of the sweeps ``rows``, concatenated in that order."""
        rows = np.atleast_1d(np.asarray(rows, dtype=np.intp))
        counts = self.n[rows]
        first = np.repeat(self.start[rows] - (np.cumsum(counts) - counts), counts)
        idx = first + np.arange(counts.sum())
        return self.points_u[idx], self.points_df[idx], self.points_dg[idx]

    def block(self, rows) -> Block:
        """The sweeps ``rows`` padded to the longest of them."""
        rows = np.atleast_1d(np.asarray(rows, dtype=np.intp))
        n = self.n[rows]
        pos = np.arange(int(n.max()))
        data = pos < n[:, None]
        # Padding repeats the largest amplitude, so that max() and grids stay meaningful.
        idx = self.start[rows][:, None] + np.minimum(pos, n[:, None] - 1)
        df = np.where(data, self.points_df[idx], 0.0)
        dg = np.where(data, self.points_dg[idx], 0.0)
        return Block(rows, self.points_u[idx], df, dg, data.astype(float), n)

    def blocks(self, rows=None, max_points: int = BLOCK_POINTS) -> list[np.ndarray]:
        """The sweeps ``rows`` (default all) in groups of similar length, ascending row order
        within a group, each of at most ``max_points`` padded points (or one sweep)."""
        rows = np.arange(len(self.n)) if rows is None else np.asarray(rows, dtype=np.intp)
        n = self.n[rows]
        longer = np.log(np.maximum(n, 1) / EXACT_LENGTH) / np.log(LENGTH_RATIO)
        key = np.where(n <= EXACT_LENGTH, n, EXACT_LENGTH + np.ceil(longer).astype(np.int64))
        order = np.lexsort((rows, key))
        cuts = np.flatnonzero(np.diff(key[order])) + 1
        out = []
        for group in np.split(rows[order], cuts):  # a few length classes, not the sweeps
            per_block = max(1, max_points // int(self.n[group].max()))
            out.extend(np.split(group, np.arange(per_block, group.size, per_block)))
        return out

    @property
    def u_min(self) -> np.ndarray:
        """Smallest amplitude of every sweep (S,), m."""
        return self.points_u[self.start]

    @property
    def u_max(self) -> np.ndarray:
        """Largest amplitude of every sweep (S,), m."""
        return self.points_u[self.start + self.n - 1]

    @property
    def u(self) -> PaddedRows:
        """Amplitudes, m, padded per request: ``p.u[rows]`` (padding: the largest amplitude)."""
        return PaddedRows(self, "u")

    @property
    def df(self) -> PaddedRows:
        """Δf, Hz, padded per request: ``p.df[rows]`` (padding 0)."""
        return PaddedRows(self, "df")

    @property
    def dg(self) -> PaddedRows:
        """ΔΓ, Hz, padded per request: ``p.dg[rows]`` (padding 0)."""
        return PaddedRows(self, "dg")

    @property
    def w(self) -> PaddedRows:
        """1 for data, 0 for padding, per request: ``p.w[rows]``."""
        return PaddedRows(self, "w")


class PaddedRows(NDArrayOperatorsMixin):
    """One array of :class:`Block` for any rows of a :class:`Padded`, built when indexed.

    ``view[i]`` is sweep i padded to its own length, ``view[rows]`` those sweeps padded to the
    longest of them (so ``p.u[rows][p.w[rows] > 0]`` are their amplitudes). Used whole (``np.
    asarray(view)``, arithmetic, comparisons), it is every sweep padded to the longest one:
    sweeps x longest sweep, for small tables only. Nothing is kept: the memory of a
    :class:`Padded` stays linear in the number of points.
    """

    def __init__(self, padded: Padded, name: str):
        self.padded, self.name = padded, name

    def __len__(self) -> int:
        return len(self.padded.n)

    @property
    def shape(self) -> tuple[int, int]:
        return (len(self), int(self.padded.n.max()))

    def __getitem__(self, key) -> np.ndarray:
        rows = np.arange(len(self))[key]
        out = getattr(self.padded.block(np.atleast_1d(rows)), self.name)
        return out[0] if np.ndim(rows) == 0 else out

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        out = self[:]
        return out if dtype is None else out.astype(dtype)

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        args = [np.asarray(a) if isinstance(a, PaddedRows) else a for a in inputs]
        return getattr(ufunc, method)(*args, **kwargs)


def pad_sweeps(
    table: pd.DataFrame, sweeps: tuple[np.ndarray, pd.Index | np.ndarray] | None = None
) -> Padded:
    """Arrange the points of a sweep table (a DataFrame of its columns) sweep by sweep.

    ``sweeps``: the code of every row's sweep and the sweep ids, numbered by first appearance
    (:func:`contactres.numerics.factorize_runs` of ``table["sweep"]`` with
    ``use_na_sentinel=False``: no code -1), where the caller has
    them already (the analysis factorises its table's ids once for every step); None: they are
    found here.
    """
    # (hashing the first row of each run of a sweep's rows: 10^6 ids cost ~0.1 s, issue 31)
    codes, names = factorize_runs(table["sweep"]) if sweeps is None else sweeps
    u = table["amplitude_m"].to_numpy(float)
    order = np.lexsort((u, codes))
    counts = np.bincount(codes, minlength=len(names))
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    # Direction from the order of the amplitudes in time (where every point has a time), else
    # in the file: up, down, or mixed.
    time = table["time_s"].to_numpy(float) if "time_s" in table else np.full(u.shape, np.nan)
    timed = np.isfinite(time).all()
    seq = np.lexsort((time, codes)) if timed else np.argsort(codes, kind="stable")
    same = codes[seq][1:] == codes[seq][:-1]
    step = np.diff(u[seq])
    rises = np.bincount(codes[seq][1:][same & (step > 0)], minlength=len(names)) > 0
    falls = np.bincount(codes[seq][1:][same & (step < 0)], minlength=len(names)) > 0
    direction = np.where(rises & falls, "mixed", np.where(falls, "down", "up"))
    df = table["df_Hz"].to_numpy(float)[order]
    dg = table["dgamma_Hz"].to_numpy(float)[order]
    return Padded(np.asarray(names), counts, direction, start, u[order], df, dg)


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

    X, W: (..., M); Y: (2, ..., M) (Δf and ΔΓ), broadcast together (W and Y may be given with
    a length-1 axis where X has rows that share them: their sums are then formed once).

    The sums are those of the plain formulas (Σ w x, Σ w x x, Σ w x y ... multiplied left to
    right), bit for bit: w x is formed once and reused, and the products with w are skipped
    where every weight is 1 (1.0 * a is a), as in sweeps of one length (the usual blocks).
    """
    ones = bool(np.all(W == 1.0))

    def weighted(a):  # W * a, the same numbers
        return a if ones else W * a

    S0 = W.sum(-1)
    WX = weighted(X)
    Sx = WX.sum(-1)
    Sxx = (WX * X).sum(-1)
    Sy = weighted(Y).sum(-1)
    Sxy = (WX * Y).sum(-1)
    D = S0 * Sxx - Sx**2
    ok = D > 1e-300 * np.maximum(Sxx * S0, 1e-300)
    Dsafe = np.where(ok, D, 1.0)
    b = np.where(ok, (S0 * Sxy - Sx * Sy) / Dsafe, 0.0)
    a = (Sy - b * Sx) / S0
    rss = weighted((Y - a[..., None] - b[..., None] * X) ** 2).sum(-1)
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


def row_sets(key) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The sets of rows of ``key`` (S, C) (integers) that agree in every column: the first row
    of each set, the set of each row, the rows sorted by set and where each set ends in them."""
    order = np.lexsort(key.T[::-1])
    # A row starts a set where any column differs from the row before: the runs of the sorted
    # rows, found column after column (a pass over the rows each), not by any() along rows of a
    # few columns (its cost per row).
    starts = run_starts(*key.take(order, axis=0).T)
    group = np.empty(order.size, dtype=np.intp)
    group[order] = repeat_runs(np.arange(starts.size), starts, order.size)
    return order[starts], group, order, np.append(starts, order.size)


def _suffix(a: np.ndarray) -> np.ndarray:
    """Σ_{i >= k} a_i along the last axis for k = 0 ... M (the last one 0)."""
    s = np.cumsum(a[..., ::-1], axis=-1)[..., ::-1]
    return np.concatenate([s, np.zeros((*a.shape[:-1], 1))], axis=-1)


def _suffix_at(a: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Σ_{i >= k} a_i along the last axis of ``a`` (..., S, M) at the positions ``k`` (S, C)
    (0 <= k <= M) of each row: ``take_along_axis(_suffix(a), k)`` for every leading index, the
    same numbers, gathered by flat indices formed once for all of them."""
    S, M = a.shape[-2:]
    suffix = _suffix(a).reshape(*a.shape[:-2], S * (M + 1))
    flat = k + (M + 1) * np.arange(S)[:, None]
    return suffix.take(flat, axis=-1)


def _hinge_crit(rss) -> np.ndarray:
    return np.log(np.maximum(rss[0], 1e-30)) + np.log(np.maximum(rss[1], 1e-30))


def _hinge_candidates(u, w, n) -> tuple[np.ndarray, ...]:
    """The candidate u_c of every sweep (S, M·T) and what of their fits depends on the
    amplitudes alone (:func:`fit_hinge`): the first point above each, whether it leaves enough
    points on both sides, u_c - max u0, and the determinant D of the line's normal equations
    and whether it is safely positive."""
    S, M = u.shape
    t = np.asarray(PLATEAU_SUBSTEPS)
    u_next = np.concatenate([u[:, 1:], u[:, -1:]], axis=1)
    uc = u[:, :, None] + t[None, None, :] * (u_next - u)[:, :, None]  # (S, M, T)
    # Points <= u_c: u_c lies in [u_j, u_j+1], so they end where the run of equal amplitudes
    # after u_j (or, if u_c reaches u_j+1, after u_j+1) ends.
    rise = np.where(u[:, 1:] > u[:, :-1], np.arange(1, M), M)
    run_end = np.minimum.accumulate(rise[:, ::-1], axis=1)[:, ::-1]  # first i > j, u_i > u_j
    nxt = np.concatenate([run_end, np.full((S, 1), M)], axis=1)
    nxt_next = np.concatenate([nxt[:, 1:], np.full((S, 1), M)], axis=1)
    k = np.where(uc >= u_next[:, :, None], nxt_next[:, :, None], nxt[:, :, None])
    n_flat = np.minimum(k, n[:, None, None])  # padding (= the largest amplitude) is never data
    gap = (u_next - u)[:, :, None] > 0
    valid = (n_flat >= PLATEAU_MIN_FLAT) & (n[:, None, None] - n_flat >= PLATEAU_MIN_SLOPE)
    valid &= gap | (t[None, None, :] == 0)

    # Suffix sums at k (above u_c), with v = u - max(u).
    top = u[np.arange(S), n - 1][:, None]
    v = (u - top) * w
    kk = k.reshape(S, -1)
    A0, A1, A2 = _suffix_at(np.stack([w, v, v * (u - top)]), kk)
    ucv = uc.reshape(S, -1) - top
    Sx = A1 - ucv * A0
    Sxx = A2 - 2.0 * ucv * A1 + ucv * ucv * A0
    S0 = n[:, None].astype(float)
    D = S0 * Sxx - Sx**2
    ok = D > 1e-300 * np.maximum(Sxx * S0, 1e-300)
    return uc.reshape(S, -1), kk, valid.reshape(S, -1), ucv, D, ok


def fit_hinge(b: Block) -> HingeFit:
    """Hinge Δf = Δf0 + s_f max(u0 - u_c, 0) (likewise ΔΓ) of every sweep, u_c on a grid.

    u_c is searched at the data amplitudes and at :data:`PLATEAU_SUBSTEPS` between them, with at
    least :data:`PLATEAU_MIN_FLAT` points on the plateau and :data:`PLATEAU_MIN_SLOPE` on the
    slope; the best u_c minimises ln RSS_f + ln RSS_Γ. (For a contact that sticks below a
    critical displacement d_c, the shifts leave the plateau smoothly, so the hinge lies at or up
    to ~2 amplitude steps above d_c.)

    Cost O(points x substeps): the sums over the points above every candidate (Σw, Σwv, Σwv²,
    Σw(y - ȳ), Σwv(y - ȳ), v = u0 - max u0 to keep them well conditioned) are suffix sums over
    the sorted amplitudes, and give every candidate's RSS in closed form. These only rank the
    candidates: the best :data:`HINGE_RECHECK` of each sweep are refitted with the direct sums
    of :func:`fit_line` (the same arithmetic as a fit of every candidate), which pick the hinge.
    What depends on the amplitudes alone (the candidates, the sums of w, v, v², the normal
    equations' determinant) is formed once per set of sweeps measured at the same amplitudes
    (bit for bit, :func:`row_sets`): the same numbers.
    """
    u, w, n = b.u, b.w, b.n
    Y = np.stack([b.df, b.dg])
    S = u.shape[0]
    # What depends on the amplitudes alone, once per set of sweeps measured at the same ones.
    first, group, _, _ = row_sets(np.concatenate([u, w, n[:, None]], axis=1).view(np.int64))
    if 2 * first.size > S:  # mostly distinct amplitudes
        uc, kk, valid, ucv, D, ok = _hinge_candidates(u, w, n)
    else:
        sets = _hinge_candidates(u[first], w[first], n[first])
        uc, kk, valid, ucv, D, ok = (a[group] for a in sets)
    top = u[np.arange(S), n - 1][:, None]
    yc = (Y - ((w * Y).sum(-1) / n)[..., None]) * w
    B0, B1 = _suffix_at(np.stack([yc, yc * (u - top)]), kk)
    S0 = n[:, None].astype(float)
    Syy = (yc * yc).sum(-1)[..., None]
    # rss = Syy - Sxy² S0/D (Sxy = B1 - ucv B0) where D is safely positive, else Syy: the
    # numbers of that expression, formed in place in B1.
    rss = np.subtract(B1, np.multiply(B0, ucv, out=B0), out=B1)
    rss *= rss
    rss *= S0
    rss /= np.where(ok, D, 1.0)
    rss = np.subtract(Syy, rss, out=rss)
    np.copyto(rss, Syy, where=~ok)
    crit = _hinge_crit(rss)
    np.copyto(crit, np.inf, where=~valid.reshape(S, -1))

    # Re-rank the best few candidates with the direct sums; ties go to the first candidate.
    K = min(HINGE_RECHECK, crit.shape[1])
    pick = np.sort(np.argpartition(crit, K - 1, axis=1)[:, :K], axis=1)
    none = ~np.isfinite(crit.min(axis=1))
    pick[none, 0] = 0  # no valid candidate: report the first, as a full search would
    uc_k = np.take_along_axis(uc.reshape(S, -1), pick, axis=1)  # (S, K)
    Xh = np.maximum(u[:, None, :] - uc_k[..., None], 0.0)  # (S, K, M)
    # The weights and shifts of a sweep are those of each of its candidates: given once.
    lines = fit_line(Xh, Y[:, :, None, :], w[:, None, :])
    valid_k = np.take_along_axis(valid.reshape(S, -1), pick, axis=1)
    crit_k = np.where(valid_k, _hinge_crit(lines.rss), np.inf)
    best = np.argmin(crit_k, axis=1)
    rows = np.arange(S)
    picked = LineFit(*(f[:, rows, best] for f in lines.fields()))
    return HingeFit(picked, uc_k[rows, best], np.isfinite(crit_k[rows, best]))
