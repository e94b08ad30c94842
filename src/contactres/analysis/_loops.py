"""Fits of the exact Cattaneo-Mindlin loop, and the loop behind a stick plateau (paper 2, Eqs. 4-6).

**Exact Cattaneo-Mindlin loop.** The loop is self-similar: K′/κ and (K″ - ωξ)/κ depend on u0 only
through x = κu0/(μF_N) (paper 2, Eq. 4-6). Both functions are tabulated once from the package's
forward model (:func:`contactres.shifts_from_loop` on a :class:`contactres.CattaneoMindlinLoop`)
and the fit Δf = Pκ g′(θu0), ΔΓ = P[ωξ + κ g″(θu0)] with θ = κ/(μF_N) is solved by variable
projection: for fixed θ, Pκ and Pωξ follow in closed form; θ is found by a zooming grid search
(relative resolution < 1e-3), independently for every sweep. The search's rounds take χ² in its
residual-free form C - num²/den, exact χ² only where a trial can be the least of the round
(:func:`_least_chi2`: the trial and value of χ² at every trial, but where solve_projected's own
rounding exceeds the short cut's tolerance). Sweeps measured at the same amplitudes
(one amplitude programme: bit for bit the same u) look the table up once for the trials that
they share, the grid and a round's trials where they share its centre, and sum over their
points by matrix products (:func:`_shared_chi2`: the same numbers). Errors come from the Jacobian in
(Pκ, Pωξ, ln θ), scaled by the residual variance. Points are weighted by the noise level of
each channel taken from the straight-line fit.

**Plateau loop.** A sweep classified ``plateau`` is refitted (:mod:`contactres.analysis._plateau`)
with the loop of :class:`contactres.PlateauLoop` around the Cattaneo-Mindlin loop: the contact
sticks up to the critical displacement d_c, then slips as Cattaneo-Mindlin in the excess
d - d_c. In units of μF_N/κ (x = κu0/(μF_N), c = κd_c/(μF_N), y = x - c) its shapes depend on
two arguments, not one, so the table above cannot be reused for both. From the virgin-curve
form of Eq. 4-5 (slope deficit L(d) = L_CM(d - d_c) above d_c, zero below):

    K″ - ωξ = κ [ (y/x)² g″(y) + 4c s(y)/(πx²) ],   s(y) = y - F_CM(y)  (κ = μF_N = 1)
    K′/κ    = 1 - (8/(πx²)) ∫₀^y L_CM(e) √((e + c)(y - e)) de

The loss part is the table at the shifted argument y plus a closed-form term (verified against
:func:`contactres.shifts_from_loop` in tests/test_analysis.py); the storage part is not, since
√((e + c)(y - e)) is not the weight of any single Cattaneo-Mindlin amplitude.
:func:`plateau_loop_shape` integrates both with the package's Masing-loop quadrature (relative
accuracy 1e-9, vectorised over amplitudes): the reference that the closed form of
:func:`contactres.analysis._plateau_slopes.plateau_loop_slopes`, which the fit uses, is checked
against.

Near d_c the shifts leave the plateau as K″ - ωξ ≈ (2/(3π)) κ²v²/(μF_N d_c) and
K′ - κ ≈ -(32/(45π)) κ²v^{5/2}/(μF_N d_c^{3/2}) in the excess v = u0 - d_c ≪ d_c, μF_N/κ
(checked numerically in tests/test_analysis.py): there is no linear onset, and the slope of the
hinge depends on how far the sweep reaches beyond d_c. No slope formula gives μ for a plateau
sweep; :func:`contactres.analyze` reports none (flag ``plateau-slope``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ..resonators import (
    DEFAULT_NODES,
    QCM,
    loop_stiffness,
    masing_stiffness,
    shifts_from_loop,
    shifts_from_stiffness,
)
from ..tangential import CattaneoMindlinLoop, MasingLoop, SavkoorLoop
from ._amplitude import row_sets
from ._bad_rows import spread_rows, usable_rows
from ._points import by_point, point_sum

__all__ = [
    "N_TABLE",
    "X_MAX",
    "LoopTable",
    "LoopTables",
    "TableInterpolant",
    "cm_loop_shape",
    "cm_loop_table",
    "fit_cm_loops",
    "interpolate_table",
    "loop_fit_fields",
    "loop_tables",
    "pinv_finite",
    "plateau_loop_shape",
    "projection_data",
    "savkoor_loop_shape",
    "savkoor_loop_table",
    "solve_projected",
    "table_interpolant",
]

# Table of the exact CM loop in x = κu0/(μF_N): full sliding starts at x = 3/2; beyond X_MAX the
# contact slides grossly over almost all the cycle and the fit says so instead of extrapolating.
X_MAX = 30.0
N_TABLE = 12001

#: Trial points (sweeps x trial values x points) of one chunk of the loop fits (~2 MB arrays).
CHUNK_CELLS = 1 << 18


@dataclass(frozen=True)
class LoopTable:
    """K′/κ (``g1``) and (K″ - ωξ)/κ (``g2``) of the Cattaneo-Mindlin loop, and their slopes
    ``d1``, ``d2``, against x = κu0/(μF_N) on 0 <= x <= :data:`X_MAX` (:func:`cm_loop_table`)."""

    x: np.ndarray
    g1: np.ndarray
    g2: np.ndarray
    d1: np.ndarray
    d2: np.ndarray


def _loop_table(loop, slip_x: float) -> LoopTable:
    """K′/κ and (K″ - ωξ)/κ of a self-similar ``loop`` with κ = 1, tabulated against x = u0.

    Uniform grid on 0 <= x <= X_MAX, refined around full sliding at ``slip_x``, where K′ and K″
    have a square-root singularity in their derivatives: linear interpolation then stays within
    1e-6 of κ (tests/analysis/test_analysis.py checks both tables against the quadrature).
    """
    q = QCM(fundamental=5e6, overtone=3, area=1e-5)
    P = float(np.asarray(shifts_from_stiffness(q, 1.0, 0.0, 1)[0]))
    side = np.geomspace(1e-7, 0.4 * slip_x, 800)
    near = slip_x + np.concatenate([-side, side])
    fine = np.linspace(0.0, 4.0 * slip_x, 4001)  # where the curvature of K′, K″ is largest
    x = np.unique(np.concatenate([np.linspace(0.0, X_MAX, N_TABLE), fine, [slip_x], near]))
    # The two grids meet at points one rounding apart (x = 0.9 in the Cattaneo-Mindlin table,
    # 1.4 in Savkoor's): np.gradient across a step of 1e-16 gave a slope of 0 (-1) there
    # instead of -0.21 (-0.48), and so the errors of sweeps with points beside them. One of
    # each such pair is kept.
    x = x[np.concatenate([[True], np.diff(x) > 1e-12 * np.maximum(x[1:], 1.0)])]
    df, dg = shifts_from_loop(q, loop, x[1:], 1)
    g1 = np.concatenate([[1.0], np.asarray(df, float) / P])
    g2 = np.concatenate([[0.0], np.asarray(dg, float) / P])
    return LoopTable(x, g1, g2, np.gradient(g1, x), np.gradient(g2, x))


def cm_loop_table() -> LoopTable:
    """Tabulate the Cattaneo-Mindlin loop's K′/κ and (K″ - ωξ)/κ against x = κu0/(μF_N).

    Made from the forward model (paper 2, Eqs. 4-6 with Masing's rule) with κ = μF_N = 1, so
    x = u0, on a grid 0 <= x <= X_MAX (uniform, refined near full sliding at x = 3/2); linear
    interpolation in it is accurate to 1e-6 (a test checks). Costs ~0.1 s: build it once and
    pass it to :func:`fit_cm_loops` (and :func:`contactres.analysis._classify.fit_sweeps`).
    """
    return _loop_table(CattaneoMindlinLoop(kappa=1.0, mu=1.0, normal_force=1.0), 1.5)


def savkoor_loop_table() -> LoopTable:
    """Tabulate Savkoor's loop (constant sliding traction τ0) against x = u0/d_s.

    d_s = 4a²τ0/κ is the amplitude of full sliding (paper 2, Eqs. 13-14), reached at x = 1; the
    loop is self-similar in x as the Cattaneo-Mindlin loop is in κu0/(μF_N), so
    :func:`fit_cm_loops` fits it with this table: its ``theta_per_m`` is then 1/d_s and the
    sliding force πa²τ0 = πκd_s/4 (no contact radius needed). Small x: K′/κ = 1 - (5/32)x²,
    (K″ - ωξ)/κ = x²/(3π) (paper 2, Eq. 15). Same grid and accuracy as :func:`cm_loop_table`.
    """
    return _loop_table(SavkoorLoop(kappa=1.0, tau=1.0, a=0.5), 1.0)


@dataclass(frozen=True)
class LoopTables:
    """The tables of the self-similar loops the sweep analysis fits (:func:`loop_tables`)."""

    cm: LoopTable
    savkoor: LoopTable


def loop_tables() -> LoopTables:
    """The Cattaneo-Mindlin and Savkoor loop tables (~0.2 s: build once, pass them on)."""
    return LoopTables(cm_loop_table(), savkoor_loop_table())


def cm_loop_shape(x) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of the Cattaneo-Mindlin loop at x = κu0/(μF_N), by quadrature.

    The exact values behind :func:`cm_loop_table` (paper 2, Eqs. 4-6, relative accuracy 1e-9),
    for any x >= 0 (no table limit), vectorised. The model function, and so the fitted curves,
    use the closed form :func:`contactres.analysis._models.cm_loop.cm_shape` (the same values
    within ~1e-12, at a small fraction of the cost); this quadrature is its independent
    reference.
    """
    x = np.asarray(x, dtype=float)
    k = loop_stiffness(CattaneoMindlinLoop(kappa=1.0, mu=1.0, normal_force=1.0), x)
    return np.real(k), np.imag(k)


def savkoor_loop_shape(x) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of Savkoor's loop at x = u0/d_s (d_s = 4a²τ0/κ), by quadrature.

    The exact values behind :func:`savkoor_loop_table` (paper 2, Eqs. 13-14 with Masing's rule,
    relative accuracy 1e-9), for any x >= 0, vectorised. The model function, and so the fitted
    curves, use :func:`contactres.analysis._models.savkoor_loop.savkoor_shape` (a power series;
    the same values within ~1e-12, at ~1/10 of the cost).
    """
    x = np.asarray(x, dtype=float)
    k = loop_stiffness(SavkoorLoop(kappa=1.0, tau=1.0, a=0.5), x)
    return np.real(k), np.imag(k)


#: The table lookup of the loop fits (:func:`table_interpolant`) sorts amplitudes into buckets
#: 2**-LOOKUP_BITS wide in x (a power of two: the bucket of x is exact) and steps through at most
#: LOOKUP_STEPS table points in each; the few buckets crowded around full sliding (~0.4 %) are
#: searched. Narrower buckets cost nothing more (61,441 of them for the tables' 0 <= x <= 30).
LOOKUP_BITS = 11
LOOKUP_STEPS = 1
_CROWDED = -(2**30)


@dataclass(frozen=True)
class TableInterpolant:
    """A loop table (:class:`LoopTable`) prepared for :func:`interpolate_table`: the bucket index of
    its abscissae and the slopes of its columns between table points, each column's slope
    formed as :func:`numpy.interp` forms it (so that the values agree bit for bit)."""

    table: LoopTable
    first: np.ndarray  # last table point <= the start of each bucket; < 0: a crowded bucket
    ahead: tuple[np.ndarray, ...]  # the next LOOKUP_STEPS points of each bucket (inf: none)
    slopes: dict[str, np.ndarray]  # slopes of g1, g2, d1, d2, and of g1, g2 as a pair ("c1", "c2")
    pair: np.ndarray  # (5, N): x, slope "c1", g1, slope "c2", g2 of the points (one gather)


def table_interpolant(table: LoopTable) -> TableInterpolant:
    """Prepare ``table`` for :func:`interpolate_table` (~1 ms: once per block of sweeps)."""
    x = table.x
    n_edges = int(np.ceil(x[-1] * 2.0**LOOKUP_BITS)) + 2  # edges e·2^-LOOKUP_BITS, e < n_edges
    # The last table point <= each edge e·2^-LOOKUP_BITS, as searchsorted(x, edges, "right") - 1
    # finds it, counted instead of searched: x_i <= e·2^-LOOKUP_BITS exactly where
    # ceil(x_i·2^LOOKUP_BITS) <= e (a power of two: the product is exact), so the number of
    # points <= each edge is a running count of those ceilings (a tenth of the cost).
    up = np.ceil(np.maximum(x, 0.0) * 2.0**LOOKUP_BITS).astype(np.intp)
    first = np.cumsum(np.bincount(up, minlength=n_edges)[:n_edges]) - 1
    count = np.diff(first)
    beyond = np.append(x, np.inf)
    ahead = []
    for k in range(1, LOOKUP_STEPS + 1):
        nxt = beyond.take(np.minimum(first[:-1] + k, x.size))
        np.putmask(nxt, count < k, np.inf)  # no k-th point in the bucket
        ahead.append(nxt)
    dx = x[1:] - x[:-1]
    inv = 1.0 / dx  # numpy.interp of complex values: differences times 1/dx; of real ones: / dx
    slopes = {k: np.diff(getattr(table, k)) / dx for k in ("g1", "g2", "d1", "d2")}
    slopes |= {"c1": np.diff(table.g1) * inv, "c2": np.diff(table.g2) * inv}
    # The last point has slope 0: x at or beyond it takes the last value, as numpy.interp's.
    slopes = {k: np.append(v, 0.0) for k, v in slopes.items()}
    pair = np.stack([x, slopes["c1"], table.g1, slopes["c2"], table.g2])
    # Buckets of more table points than LOOKUP_STEPS are marked by a negative first point, far
    # enough below 0 that the steps cannot lift it: one gather tells both.
    first = first[:-1].astype(np.intp)  # a copy
    np.putmask(first, count > LOOKUP_STEPS, _CROWDED)
    return TableInterpolant(table, first, tuple(ahead), slopes, pair)


def interpolate_table(ip: TableInterpolant, x, columns) -> list[np.ndarray]:
    """Columns of a loop table interpolated linearly, the same numbers as :func:`numpy.interp`.

    numpy.interp bisects the table for every point; this takes the bucket of each point (a
    multiplication by a power of two) and steps through the table point in it, or searches the
    few crowded buckets: a third of the cost, and the slope of each interval formed as numpy
    (2.x) forms it, so that the values agree bit for bit (tests/analysis/test_scale.py).

    Parameters
    ----------
    ip : the table prepared by :func:`table_interpolant`
    x : array of abscissae (x = κu0/(μF_N) for the Cattaneo-Mindlin table), >= 0; below 0
        the first value, beyond the table's end the last (numpy.interp's ends)
    columns : names of the columns: ``"g1"``, ``"g2"``, ``"d1"``, ``"d2"`` of
        :class:`LoopTable`, or ``"c1"``, ``"c2"`` for g1 and g2 as one complex numpy.interp of
        ``g1 + 1j g2`` gives them (its slopes are differences times 1/Δx, not over Δx)

    Returns
    -------
    list of arrays shaped as ``x``, one per column
    """
    x, j = _table_index(ip, x)
    # 0 <= j < table size: take's "wrap" gathers what indexing does, without its checks.
    d = x - ip.table.x.take(j, mode="wrap")
    values = {"c1": "g1", "c2": "g2"}
    return [
        ip.slopes[c].take(j, mode="wrap") * d
        + getattr(ip.table, values.get(c, c)).take(j, mode="wrap")
        for c in columns
    ]


def _table_index(ip: TableInterpolant, x) -> tuple[np.ndarray, np.ndarray]:
    """``x`` clipped to the table and the index of the last table point <= it (for
    :func:`interpolate_table`)."""
    x_tab = ip.table.x
    x = np.clip(x, x_tab[0], x_tab[-1])  # the ends: the first and the last value
    b = x * 2.0**LOOKUP_BITS
    # fmax: a NaN amplitude (no NaN in validated sweeps) takes bucket 0 and gives NaN below.
    b = np.fmax(b, 0.0, out=b).astype(np.intp)
    j = ip.first.take(b)  # take: the same gather as indexing, without its checks of b's kind
    for nxt in ip.ahead:
        j += nxt.take(b) <= x
    if j.size and j.min() < 0:  # crowded buckets (~1 % of the lookups): searched
        search = np.flatnonzero(j < 0)
        j.flat[search] = np.searchsorted(x_tab, x.flat[search], side="right") - 1
    return x, j


def _interpolate_pair(ip: TableInterpolant, x) -> tuple[np.ndarray, np.ndarray]:
    """``interpolate_table(ip, x, ("c1", "c2"))``, the same numbers, from the table's five
    columns gathered at one index (the θ search's lookups), with fewer temporaries."""
    x, j = _table_index(ip, x)
    return _pair_at(ip, x, j)


def _pair_at(ip: TableInterpolant, x: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """g1, g2 (as the complex numpy.interp forms them) at ``x`` in the interval ``j`` of the
    table; ``x`` is overwritten. Where j is the last point, x may lie beyond it: its slope 0
    then gives the last value, as the clipped x would (0·d = 0 for any finite d)."""
    x_j, s1, g1, s2, g2 = ip.pair  # rows of a C-ordered array: each contiguous
    # 0 <= j < table size, so take's "wrap" gathers what its default "raise" does, without
    # the bounds check of every index (~1/4 of the gather's instructions).
    d = np.subtract(x, x_j.take(j, mode="wrap"), out=x)
    v1 = s1.take(j, mode="wrap")
    v1 *= d  # in place: the same numbers as s1 * d + g1
    v1 += g1.take(j, mode="wrap")
    v2 = s2.take(j, mode="wrap")
    v2 *= d
    v2 += g2.take(j, mode="wrap")
    return v1, v2


def _search_pair(ip: TableInterpolant, u: np.ndarray, theta: np.ndarray):
    """:func:`_interpolate_pair` at x = θu of the points ``u`` (S, M) >= 0 at the trials
    ``theta`` (S, K): the same numbers, as (M, S, K) arrays (points first, in that order in
    memory, as :func:`_least_chi2` sums them), with fewer passes over the trials.

    x is finite and >= 0 here, so neither x nor its bucket needs the clip to the table: a
    bucket beyond the last is taken as the last (``take(mode="clip")``), whose table point
    is the table's end, and x beyond the end gives the last value there (:func:`_pair_at`).
    The bucket is truncated to an integer in one pass, where x·2^LOOKUP_BITS < 2^52 (bounded
    by max u · max θ; otherwise the general lookup).
    """
    x = np.multiply(u.T[:, :, None], theta, out=np.empty((u.shape[1], *theta.shape)))
    bound = np.max(u, initial=0.0) * np.max(theta, initial=0.0)
    if not (bound < 2.0 ** (50 - LOOKUP_BITS) and np.min(u, initial=0.0) >= 0.0):
        return _interpolate_pair(ip, x)
    # The product in floating point, then truncated: the same integers as one multiplication
    # cast on output, which numpy runs through buffers (a copy of the factor per element).
    b = (x * 2.0**LOOKUP_BITS).astype(np.intp)
    # b >= 0: clipped once to the last bucket, then gathered without bounds checks ("wrap"
    # of an index in range), the same numbers as take(b, mode="clip") per lookup.
    b = np.minimum(b, ip.first.size - 1, out=b)
    j = ip.first.take(b, mode="wrap")
    for nxt in ip.ahead:
        j += nxt.take(b, mode="wrap") <= x
    if j.size and j.min() < 0:  # crowded buckets (~1 % of the lookups): searched
        search = np.flatnonzero(j < 0)
        j.flat[search] = np.searchsorted(ip.table.x, x.flat[search], side="right") - 1
    return _pair_at(ip, x, j)


def projection_data(dg, w) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Σw, the weighted mean of ΔΓ and ΔΓ - mean of each row of ``dg``, ``w`` (..., M): the
    parts of :func:`solve_projected` that depend on the data alone, the numbers it forms
    (row by row: those of a row do not depend on the rows formed with it), for a caller that
    solves the same rows at many θ (the plateau loop's iteration: once a pass, not at every
    evaluation)."""
    n = w.sum(-1)
    dgm = (w * dg).sum(-1) / n  # (w * dg where every weight is 1: dg, the same numbers)
    return n, dgm, dg - dgm[..., None]


def solve_projected(g1, g2, df, dg, w, wf, wg, data=None):
    """Closed-form Pκ (A) and Pωξ (B) for fixed θ, and χ². Arrays (..., M); wf, wg (...);
    ``data``: :func:`projection_data` of ``dg``, ``w`` (None: formed here; the same numbers).

    The weighted sums are those of the plain formulas, bit for bit: each product with ``w`` is
    formed once and reused, and skipped where every weight is 1 (a block of sweeps of one
    length, the usual case: 1.0 * a is a), which saves a third of the arithmetic of the
    θ-grid search and of every step of the plateau loop's iteration.
    """
    ones = bool(np.all(w == 1.0))

    def weighted(a):  # w * a, the same numbers
        return a if ones else w * a

    n, dgm, dgc = projection_data(dg, w) if data is None else data
    g2m = weighted(g2).sum(-1) / n
    g2c = g2 - g2m[..., None]
    wg1, wg2c = weighted(g1), weighted(g2c)
    num = wf * (wg1 * df).sum(-1) + wg * (wg2c * dgc).sum(-1)
    den = wf * (wg1 * g1).sum(-1) + wg * (wg2c * g2c).sum(-1)
    A = num / den
    B = dgm - A * g2m
    rf = df - A[..., None] * g1
    rg = dg - B[..., None] - A[..., None] * g2
    rss_f = weighted(rf * rf).sum(-1)
    rss_g = weighted(rg * rg).sum(-1)
    return A, B, wf * rss_f + wg * rss_g, rss_f, rss_g


def _least_chi2(g1, g2, df, dg, w, wf, wg, sums=None) -> np.ndarray:
    """:func:`solve_projected`'s χ², bit for bit, at the trials that can hold the least χ² of
    their sweep; +inf at the others.

    The θ search needs of each round only the position of the least χ² and its value. With A
    and B projected out, χ² = C - num²/den (C = wf Σw Δf² + wg Σw (ΔΓ - mean)², num and den as
    in :func:`solve_projected`), without the residuals; the points on the first axis, its sums
    over points weighted by data are a matrix-vector product per sweep (BLAS), those of
    squares a sum along the first axis (where a sum along the last axis pays numpy's per-row
    overhead on rows of ~10 points): about a fifth of solve_projected's cost. The two forms
    differ by rounding only. The short cut's own is a few (M + 3)·ε·C at most (Higham's bound
    for sums of M terms in any order; every term is at most ~C, since num² <= den·C); a trial
    more than (M + 4)·2^-40·C (~10³ times that bound) above the least short-cut value is not
    taken as a candidate, so only the trials within it, one or two a sweep, are evaluated as
    :func:`solve_projected` evaluates them (:func:`_exact_near`), and numpy.argmin over the
    result finds the trial that it finds over solve_projected's χ² at every trial (ties: the
    first) wherever solve_projected's rounding is within that tolerance too. It need not be:
    where A and B are large and cancel (nearly equal amplitudes, a Δf channel of almost no
    weight), solve_projected's χ² carries up to ~10⁵ ε·C (review R28d, with exact rational
    arithmetic), and the trial found can differ from its argmin at every trial; the two χ²
    then differ by rounding alone.

    Parameters
    ----------
    g1, g2 : (M, S, K) K′/κ and (K″ - ωξ)/κ of the loop at the M points of S sweeps, each at
        K trial θ (points first)
    df, dg : (S, M) the shifts, Hz
    w : (S, M) weights (0 for padding)
    wf, wg : (S,) weights of the two channels, Hz⁻²
    sums : :func:`_data_sums` of these sweeps (None: formed here; the same numbers)

    Returns
    -------
    (S, K) χ² (dimensionless): solve_projected's where it can be its row's least, +inf
    elsewhere
    """
    ones = bool(np.all(w == 1.0))
    sums = _data_sums(df, dg, w, wf, wg) if sums is None else sums
    n, c, wdf, wdg = sums[:4]
    # The sums over the points weighted by a vector of each sweep: matrix-vector products,
    # one per sweep (BLAS); the sums of squares row of points after row (no per-row overhead).

    g2c = g2 - (_dot(w, g2) / n[:, None])[None]
    if ones:
        # Squares, then their sum over the points (the first axis: added row after row, the
        # order einsum("msk,msk->sk") adds them in): the same numbers at ~1/2 of its instructions.
        ss1, ss2 = (g1 * g1).sum(axis=0), (g2c * g2c).sum(axis=0)
    else:
        ss1, ss2 = _dot(w, g1 * g1), _dot(w, g2c * g2c)
    short = _short_chi2(c, _dot(wdf, g1), _dot(wdg, g2c), ss1, ss2, wf, wg)
    return _exact_near(short, sums, g1, g2, None, wf, wg)


def _dot(v, g) -> np.ndarray:
    """Σ_m v[s, m] g[m, s, k]: (S, K), a matrix-vector product per sweep (BLAS)."""
    return np.matmul(v[:, None, :], g.transpose(1, 0, 2))[:, 0]


def _short_chi2(c, n1, n2, s1, s2, wf, wg) -> np.ndarray:
    """The short cut's χ² = C - num²/den (:func:`_least_chi2`) from its sums (S, K): num =
    wf·n1 + wg·n2, den = wf·s1 + wg·s2; in place (``n1``, ``n2``, ``s1``, ``s2`` are
    overwritten), the numbers of the plain expression with three temporaries fewer. The
    weights are spread over the trials once each, for their two products: numpy (2.x) runs an
    operand broadcast along the last axis through buffers at ~5x the cost of one that is not."""
    S, K = n1.shape
    wf2, wg2 = (np.repeat(v, K).reshape(S, K) for v in (wf, wg))
    num = np.multiply(n1, wf2, out=n1)
    num += np.multiply(n2, wg2, out=n2)
    den = np.multiply(s1, wf2, out=s1)
    den += np.multiply(s2, wg2, out=s2)
    num *= num
    num /= den
    return np.subtract(c[:, None], num, out=num)


def _dot_gathered(v, g, group) -> np.ndarray:
    """:func:`_dot` of ``v`` (S, M) with the shapes ``g[:, group]`` (g: (M, sets, K)), the same
    numbers: the sets' shapes laid out set by set first (a copy of the sets' points, fewer than
    the sweeps'), so that each sweep's (M, K) block is one contiguous run that ``take`` copies
    whole, where indexing the middle axis copies K numbers at a time (half the cost)."""
    by_set = np.ascontiguousarray(g.transpose(1, 0, 2))
    # 0 <= group < sets: "wrap" gathers what the default "raise" does, without its checks.
    return np.matmul(v[:, None, :], by_set.take(group, axis=0, mode="wrap"))[:, 0]


def _data_sums(df, dg, w, wf, wg) -> tuple[np.ndarray, ...]:
    """Σw, C = wf Σw Δf² + wg Σw (ΔΓ - mean)² (mean: the weighted mean of ΔΓ), wΔf,
    w(ΔΓ - mean), the mean, and ΔΓ - mean, Δf, ΔΓ and w laid out points first ((M, S), as
    :func:`_projected` takes them) of every sweep: the parts of :func:`_least_chi2`'s short
    cut and of :func:`solve_projected` that do not depend on θ, formed once per chunk of sweeps
    for all the rounds of its search (row by row: a slice of rows has the numbers of the same
    rows of the whole; the mean and ΔΓ - mean those that solve_projected forms)."""
    n, dgm, dgc = projection_data(dg, w)
    c = wf * (w * df * df).sum(-1) + wg * (w * dgc * dgc).sum(-1)
    points = tuple(np.ascontiguousarray(a.T) for a in (dgc, df, dg, w))
    return n, c, w * df, w * dgc, dgm, *points


def _exact_near(short, sums, g1, g2, column, wf, wg) -> np.ndarray:
    """(S, K): :func:`solve_projected`'s χ² at the trials whose short-cut χ² ``short`` lies
    within (M + 4)·2^-40·C of their row's least (every trial of a row with a non-finite one),
    +inf elsewhere (:func:`_least_chi2`). The shapes of sweep s are ``g1[:, column[s]]``
    (``column`` None: ``g1[:, s]``); ``sums``: :func:`_data_sums` of the sweeps.

    Each row's least trial is among them: those are evaluated for every row at once, on the
    data as it lies (no gather), and the few others apart (a second trial in up to ~6 % of the
    rows, in the last rounds on the 10^5-sweep benchmark), on their rows' data gathered; each
    χ² is its own row's alone, so that the split does not change it.
    """
    c = sums[1]
    S, K = short.shape
    M, C, _ = g1.shape
    tol = (M + 4) * 2.0**-40 * c
    rows = np.arange(S)
    first = np.argmin(short, axis=1)  # the least: np.min's value (NaN: the first NaN)
    least = short.ravel().take(rows * K + first)
    # Every trial of a row finite: its least and its largest finite (NaN propagates to both).
    sure = np.isfinite(least) & np.isfinite(np.max(short, axis=1)) & np.isfinite(c)
    near = short <= (least + tol)[:, None]
    if not sure.all():
        near[~sure] = True
    near.ravel()[rows * K + first] = False  # the others
    chi = np.full(short.shape, np.inf)
    r, k = np.nonzero(near)
    col = rows if column is None else column
    span = np.arange(M)[:, None] * (C * K)  # the points of the (M, C, K) shapes, first
    batches = [(rows, first, _sweep_data(sums, wf, wg))]
    if r.size:
        batches.append((r, k, _sweep_data(sums, wf, wg, r)))
    for at_rows, at_k, data in batches:
        # g[:, col, k] gathered by flat indices, points first: rows of points, contiguous.
        at = (col.take(at_rows) * K + at_k) + span
        a1, a2 = (np.take(g, at, mode="wrap") for g in (g1, g2))  # 0 <= at < g.size
        chi.ravel()[at_rows * K + at_k] = _projected(a1, a2, data)[2]
    return chi


def _sweep_data(sums, wf, wg, r=None, trials=False) -> tuple[np.ndarray, ...]:
    """What :func:`_projected` takes of the sweeps: Σw, the mean of ΔΓ (S,), ΔΓ - mean, Δf, ΔΓ,
    w (points first, (M, S), from :func:`_data_sums`, ``sums``), wf, wg (S,); of the sweeps
    ``r`` (gathered), or of every one (None), with an axis of trials (length 1, broadcast)
    before the sweeps' if ``trials`` (shapes (M, K, S))."""
    data = (sums[0], sums[4], *sums[5:9], wf, wg)  # Σw, mean, ΔΓ - mean, Δf, ΔΓ, w, wf, wg
    if r is not None:
        data = tuple(a.take(r, axis=a.ndim - 1) for a in data)
    if trials:  # (M, S) -> (M, 1, S); (S,) broadcasts against (K, S) as it is
        data = tuple(a[:, None] if a.ndim == 2 else a for a in data)
    return data


def _projected(g1, g2, data) -> tuple[np.ndarray, ...]:
    """:func:`solve_projected` (A, B, χ², rss_f, rss_g) at the shapes ``g1``, ``g2`` laid out
    points first, (M, ...), bit for bit: its arithmetic, in its order (its sums over the points
    by :func:`~contactres.analysis._points.point_sum`), with the parts of the data alone (Σw,
    the mean of ΔΓ and ΔΓ - mean) formed once (``data``: :func:`_sweep_data`, aligned with the
    shapes), and in place where solve_projected makes temporaries (``g1``, ``g2`` are left as
    they are). Not solve_projected itself: that one takes shapes that broadcast against the
    data (a shared (M,) or (K, M) set of shapes), where this one writes into temporaries of the
    shapes' own size, which must then be the result's; and its points come last, where a sum
    over them pays numpy's overhead per row of ~10 points (here: a few passes over whole
    rows)."""
    n, dgm, dgc, df, dg, w, wf, wg = data
    ones = bool(np.all(w == 1.0))

    def weighted(a):  # w * a, the same numbers (as in solve_projected)
        return a if ones else w * a

    g2m = point_sum(weighted(g2)) / n
    g2c = by_point(np.subtract, g2, g2m)
    wg1, wg2c = weighted(g1), weighted(g2c)
    num = wf * point_sum(wg1 * df) + wg * point_sum(wg2c * dgc)
    den = wf * point_sum(wg1 * g1) + wg * point_sum(wg2c * g2c)
    A = num / den
    B = dgm - A * g2m
    rf = by_point(np.multiply, g1, A)  # A g1 (a product: either order, the same number)
    rf = np.subtract(df, rf, out=rf)  # df - A g1
    rg = by_point(np.subtract, dg, B)
    rg -= by_point(np.multiply, g2, A, out=g2c)  # dg - B - A g2 (g2c is not needed again)
    rf *= rf
    rg *= rg
    rss_f, rss_g = point_sum(weighted(rf)), point_sum(weighted(rg))
    return A, B, wf * rss_f + wg * rss_g, rss_f, rss_g


#: The short cut's sums run trial set by trial set (two matrix products each) for at most this
#: many distinct sets of trials in a chunk; beyond it on their shapes gathered per sweep (the
#: loop would cost more than it saves).
GROUP_LOOP = 8


def _shared_chi2(ip, u, df, dg, w, wf, wg, umax, lx, key, sums=None) -> np.ndarray:
    """:func:`_least_chi2` at the trials x_max = 10^lx (``lx`` (S, K)): the same numbers, the
    table looked up once per set of sweeps with the same amplitudes and trials, the sweeps
    whose rows of ``key`` (S, C) (integers) agree (:func:`_fit_cm_chunk`: the amplitudes'
    set and the trials' centre, bit for bit).

    Sweeps of one amplitude programme (loads, ramps, repeats) have the same u (and u_max): on
    the θ grid, and in the zoom rounds where they share their best trial so far, they have the
    same θ = 10^lx/u_max and x = θu at every trial, so the same shapes g1, g2: one lookup. For
    few such sets the short cut's sums over the points are matrix products of a set's shapes
    (M, K) with the data of its sweeps (BLAS; any order of the sums is within the short cut's
    tolerance), otherwise those of :func:`_least_chi2` on the shapes gathered per sweep.
    ``sums``: :func:`_data_sums` of the sweeps (None: formed here; the same numbers).
    """
    sums = _data_sums(df, dg, w, wf, wg) if sums is None else sums
    first, group, order, ends = row_sets(key)
    S, M = u.shape
    if 2 * first.size > S:  # mostly distinct: a lookup per sweep
        # By parts of CHUNK_CELLS trial points (a chunk sized for a round's trials may hold
        # mostly distinct sweeps on the grid): each sweep's numbers are its own alone.
        step = max(1, CHUNK_CELLS // (lx.shape[1] * max(M, 1)))
        parts = []
        for s in (slice(i, i + step) for i in range(0, S, step)):
            g1, g2 = _search_pair(ip, u[s], 10.0 ** lx[s] / umax[s, None])
            part = (*(a[s] for a in sums[:5]), *(a[:, s] for a in sums[5:]))  # (M, S): [:, s]
            parts.append(_least_chi2(g1, g2, df[s], dg[s], w[s], wf[s], wg[s], part))
        return np.concatenate(parts) if parts else np.empty(lx.shape)
    # θ of the set's first sweep: that of every sweep of the set, bit for bit.
    g1, g2 = _search_pair(ip, u[first], 10.0 ** lx[first] / umax[first][:, None])
    n, c, wdf, wdg = sums[:4]
    # The sums over the points of each set's shapes alone: once per set.
    g2c = g2 - (_dot(w[first], g2) / n[first][:, None])[None]
    ss = _dot(w[first], g1 * g1), _dot(w[first], g2c * g2c)
    if first.size > GROUP_LOOP:  # the sums with the data: per sweep, on gathered shapes
        n1, n2 = _dot_gathered(wdf, g1, group), _dot_gathered(wdg, g2c, group)
    else:  # per set: two matrix products
        n1, n2 = np.empty((2, *lx.shape))
        # fit_cm_loops sorts the sweeps by amplitude set: on its grid each set is a run of
        # rows, taken as a slice (no gather of the data, no scatter of the products).
        runs = np.array_equal(order, np.arange(S))
        for i in range(first.size):
            rows = slice(ends[i], ends[i + 1]) if runs else order[ends[i] : ends[i + 1]]
            n1[rows], n2[rows] = wdf[rows] @ g1[:, i], wdg[rows] @ g2c[:, i]
    short = _short_chi2(c, n1, n2, ss[0][group], ss[1][group], wf, wg)
    return _exact_near(short, sums, g1, g2, group, wf, wg)


def fit_cm_loops(
    u, df, dg, w, sigma_df, sigma_dg, table: LoopTable | None = None, rounds: int = 4
) -> pd.DataFrame:
    """Fit the exact Cattaneo-Mindlin loop (+ dashpot) to every row of padded sweeps.

    Parameters
    ----------
    u, df, dg, w : (S, M) amplitudes (m), shifts (Hz), weights (0 for padding); the padding
        must be finite too (e.g. the row's last amplitude and shifts of 0): a NaN there, as
        in NaN padding, makes its row one with no fit
    sigma_df, sigma_dg : (S,) noise levels of the two channels, Hz
    table : the loop table (:func:`cm_loop_table`; built here if None)
    rounds : zoom rounds of the grid search in θ (each refines the step 4x; then a parabola)

    Returns
    -------
    DataFrame with ``df0_Hz`` = Pκ, ``dgamma0_Hz`` = Pωξ, ``theta_per_m`` = κ/(μF_N), their standard
    errors (``*_err``), ``cov_df0_lntheta``, ``x_max`` = θ·max(u0) and ``edge`` ("low" if no slip
    is resolved, "high" if the best fit is gross sliding beyond the table, "" otherwise). A row
    with a NaN or an inf among its values or noise levels, or fewer than 2 distinct amplitudes
    of weight > 0 (3 parameters), has no fit: NaN, edge ""
    (:mod:`contactres.analysis._bad_rows`); the other rows' results are those of a batch
    without it.
    """
    good = usable_rows((u, df, dg, w), (sigma_df, sigma_dg), 2)
    if good is not None:
        u, df, dg, w, sigma_df, sigma_dg = (
            np.asarray(a)[good] for a in (u, df, dg, w, sigma_df, sigma_dg)
        )
        return spread_rows(fit_cm_loops(u, df, dg, w, sigma_df, sigma_dg, table, rounds), good)
    table = table if table is not None else cm_loop_table()
    S = u.shape[0]
    # Sweeps measured at the same amplitudes (bit for bit) share the lookups of the trials that
    # they share (_shared_chi2): sorted by amplitude set, so that a set shares its chunk.
    _, amplitudes, order, _ = row_sets(np.concatenate([u, w], axis=1).view(np.int64))
    # 49 trial θ per sweep on the grid, 8 in a round: chunks of sweeps keep those arrays at a
    # few MB. Where amplitudes are shared, the grid is looked up per set: rounds are the most.
    trials = 9 if 2 * (amplitudes.max(initial=-1) + 1) <= S else 49
    step = max(1, CHUNK_CELLS // (trials * max(u.shape[1], 1)))
    ip = table_interpolant(table)
    parts = []
    for i in range(0, max(S, 1), step):
        s = order[i : i + step]
        data = (u[s], df[s], dg[s], w[s], sigma_df[s], sigma_dg[s])
        parts.append(_fit_cm_chunk(*data, ip, rounds, amplitudes[s]))
    back = np.empty_like(order)
    back[order] = np.arange(S)
    return pd.DataFrame({c: np.concatenate([q[c] for q in parts])[back] for c in parts[0]})


def _fit_cm_chunk(
    u, df, dg, w, sigma_df, sigma_dg, ip, rounds, amplitudes
) -> dict[str, np.ndarray]:
    """:func:`fit_cm_loops` on one chunk of sweeps (a dict of its columns; ``ip`` the loop
    table prepared by :func:`table_interpolant`, ``amplitudes`` (S,) the set of each sweep:
    equal where u and w are equal bit for bit)."""
    S = u.shape[0]
    umax = np.maximum(np.max(np.where(w > 0, u, 0.0), axis=1), 1e-300)
    floor_f = 1e-6 * np.maximum(np.abs(df).max(axis=1), 1e-12)
    floor_g = 1e-6 * np.maximum(np.abs(dg).max(axis=1), 1e-12)
    wf = 1.0 / np.maximum(sigma_df, floor_f) ** 2
    wg = 1.0 / np.maximum(sigma_dg, floor_g) ** 2

    sums = _data_sums(df, dg, w, wf, wg)  # of the data alone: once for every round

    # Sweeps of one amplitude set share their lookups where they share their trials: on the
    # grid, and in a round where they share its centre.
    def chi2_at(lx, least=False, centre=None):  # lx: (S, K) log10 of x_max
        if least:  # only the least χ² of each row matters (its position, its value)
            key = amplitudes[:, None] if centre is None else np.stack([amplitudes, centre], 1)
            return _shared_chi2(ip, u, df, dg, w, wf, wg, umax, lx, key, sums)
        # x = θu points first and sweeps last, (M, K, S): the numbers of θ[s, k]·u[s, m].
        theta = (10.0**lx / umax[:, None]).T
        xu = np.multiply(theta, u.T[:, None, :], out=np.empty((u.shape[1], *theta.shape)))
        # Both shapes from one lookup, as one complex numpy.interp of the table made them.
        g1, g2 = _interpolate_pair(ip, xu)
        return _projected(g1, g2, _sweep_data(sums, wf, wg, trials=True))[2].T

    lo, hi = -2.5, np.log10(X_MAX)
    line = np.linspace(lo, hi, 49)
    grid = np.broadcast_to(line, (S, 49))
    chi = chi2_at(grid, least=True)
    k = np.argmin(chi, axis=1)
    edge = np.where(k == 0, "low", np.where(k == grid.shape[1] - 1, "high", ""))
    step = line[1] - line[0]  # (of the line: a batch may be empty)
    rows = np.arange(S)
    centre, best = grid[rows, k], chi[rows, k]
    # Each round's middle trial is the best point so far (centre + 0): its χ², known, is put
    # in its place instead of evaluated again (the same number: the sums run row by row).
    for _ in range(rounds):
        around = np.delete(np.linspace(-step, step, 9), 4)  # the middle one is 0 exactly
        local = np.clip(centre[:, None] + around[None, :], lo, hi)
        # (Trials were once spared against the best so far: its tolerance did not cover
        # solve_projected's rounding where A and B cancel, and results moved; review R28d.)
        chi = _with_middle(chi2_at(local, True, centre.view(np.int64)), best)
        j = np.argmin(chi, axis=1)
        centre = _with_middle(local, centre)[rows, j]
        best = chi[rows, j]
        step = step / 4.0
    # The vertex of the parabola through the best point and its neighbours (χ² is smooth in
    # log θ near its minimum): the resolution of 4 rounds (step/256) improved to ~1e-6.
    h = step
    c0, c2 = chi2_at(np.clip(centre[:, None] + np.array([-h, h])[None, :], lo, hi)).T
    c1 = best
    curv = c0 - 2.0 * c1 + c2
    shift = np.where(curv > 0, 0.5 * (c0 - c2) / np.where(curv > 0, curv, 1.0), 0.0)
    centre = np.clip(centre + np.clip(shift, -1.0, 1.0) * h, lo, hi)

    theta = 10.0**centre / umax
    xu = np.multiply(u.T, theta, out=np.empty(u.shape[::-1]))  # points first: θ[s]·u[s, m]
    g1, g2, d1, d2 = interpolate_table(ip, xu, ("g1", "g2", "d1", "d2"))
    A, B, chi2, rss_f, rss_g = _projected(g1, g2, _sweep_data(sums, wf, wg))
    e1, e2 = d1 * xu, d2 * xu
    jtj = _normal_matrix(g1.T, g2.T, e1.T, e2.T, A, w, wf, wg)
    n_res = 2 * w.sum(axis=1)
    cov = _inverse_3x3(jtj) * (chi2 / np.maximum(n_res - 3, 1))[:, None, None]
    return {
        **loop_fit_fields(A, B, theta, cov, umax),
        "edge": edge,
        "rss_df": rss_f,
        "rss_dgamma": rss_g,
    }


def _normal_matrix(g1, g2, e1, e2, A, w, wf, wg) -> np.ndarray:
    """JᵀJ (S, 3, 3) of the weighted residuals of the loop fit in (A, B, ln θ).

    The residuals' derivatives are -(g1, 0, A e1) in Δf and -(g2, 1, A e2) in ΔΓ (e = x dg/dx,
    x = θu0), weighted by w√wf and w√wg: JᵀJ = wf Σw²(g1, 0, Ae1)ᵀ(…) + wg Σw²(g2, 1, Ae2)ᵀ(…),
    all its sums from one product of the five weighted columns per sweep (BLAS).
    """
    S, M = w.shape
    Y = np.empty((S, 5, M))
    a = A[:, None]
    np.multiply(g1, w, out=Y[:, 0])
    np.multiply(a * e1, w, out=Y[:, 1])
    np.multiply(g2, w, out=Y[:, 2])
    Y[:, 3] = w
    np.multiply(a * e2, w, out=Y[:, 4])
    G = np.matmul(Y, Y.transpose(0, 2, 1))
    jtj = np.empty((S, 3, 3))
    jtj[:, 0, 0] = wf * G[:, 0, 0] + wg * G[:, 2, 2]
    jtj[:, 0, 1] = wg * G[:, 2, 3]
    jtj[:, 0, 2] = wf * G[:, 0, 1] + wg * G[:, 2, 4]
    jtj[:, 1, 1] = wg * G[:, 3, 3]
    jtj[:, 1, 2] = wg * G[:, 3, 4]
    jtj[:, 2, 2] = wf * G[:, 1, 1] + wg * G[:, 4, 4]
    jtj[:, 1, 0], jtj[:, 2, 0], jtj[:, 2, 1] = jtj[:, 0, 1], jtj[:, 0, 2], jtj[:, 1, 2]
    return jtj


#: :func:`_inverse_3x3` inverts in closed form where the determinant of JᵀJ scaled to a unit
#: diagonal is at least this (condition number <= 6.75/det: ~7e6), by numpy.linalg.pinv elsewhere.
INVERSE_MIN_DET = 1e-6


def _inverse_3x3(m: np.ndarray) -> np.ndarray:
    """The inverses of symmetric positive semi-definite 3x3 matrices ``m`` (S, 3, 3): as
    numpy.linalg.pinv gives them (its SVD per matrix cost ~10x this), to rounding, where pinv
    is accurate; the true inverse where pinv's cut of small singular values, made on the
    unscaled matrix, would act (a diagonal spanning ~1e15 or more: pinv is then wrong by O(1),
    the scaled closed form is not).

    Each matrix is scaled to a unit diagonal, D⁻¹mD⁻¹ with D = √diag(m), and inverted by its
    adjugate over its determinant det, then scaled back. The scaled matrix's eigenvalues sum
    to 3, so that its condition number is at most 3·(3/2)²/det = 6.75/det (a safe bound: the
    largest eigenvalue squared times the middle one is at most 4, so 4/det holds), and the closed
    form's error, of order ε times that, is bounded by 20ε·6.75/det of the scaled inverse's
    largest entry where det >= :data:`INVERSE_MIN_DET` (tests/analysis/test_loop_search.py
    checks it against exact rational arithmetic). The loop fits' JᵀJ have det >= 0.24 on the
    10^4-sweep benchmark: there the errors agree with pinv's to 8e-14 relative, pinv of the
    unscaled matrix (condition number up to ~1e6) being the less accurate of the two. The
    other matrices (near-singular, a zero diagonal) take pinv itself, as before: its cut of
    tiny singular values is kept where it matters. A matrix that is not finite (of a sweep
    whose fit failed) gets NaN: pinv's SVD would raise for every matrix passed with it.
    """
    d = np.sqrt(np.diagonal(m, axis1=1, axis2=2))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = m / (d[:, :, None] * d[:, None, :])
    a, b, e = c[:, 0, 1], c[:, 0, 2], c[:, 1, 2]
    # Cofactors of [[1, a, b], [a, 1, e], [b, e, 1]] (the diagonal is 1 up to rounding: kept).
    # A non-finite matrix gives NaN here without a warning: it takes pinv below, as before.
    with np.errstate(invalid="ignore", over="ignore"):
        c00 = c[:, 1, 1] * c[:, 2, 2] - e * e
        c01 = b * e - a * c[:, 2, 2]
        c02 = a * e - b * c[:, 1, 1]
        c11 = c[:, 0, 0] * c[:, 2, 2] - b * b
        c12 = a * b - c[:, 0, 0] * e
        c22 = c[:, 0, 0] * c[:, 1, 1] - a * a
        det = c[:, 0, 0] * c00 + a * c01 + b * c02
    good = det >= INVERSE_MIN_DET  # False for NaN
    adj = np.stack([c00, c01, c02, c01, c11, c12, c02, c12, c22], axis=1).reshape(-1, 3, 3)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = adj / (det[:, None, None] * d[:, :, None] * d[:, None, :])
    if not good.all():
        out[~good] = pinv_finite(m[~good])
    return out


def pinv_finite(m: np.ndarray) -> np.ndarray:
    """numpy.linalg.pinv of a stack, NaN for a matrix that is not finite (a fit that failed,
    e.g. on a hinge beyond its sweep's amplitudes), whose SVD would raise for the whole stack.
    Each matrix's SVD is its own: the others' pseudo-inverses are pinv's of the stack."""
    if np.isfinite(m).all():  # (the usual case: one test)
        return np.linalg.pinv(m)
    finite = np.isfinite(m).all(axis=(1, 2))
    out = np.full(m.shape, np.nan)
    out[finite] = np.linalg.pinv(m[finite])
    return out


def _with_middle(a, m):
    """(S, 8) ``a`` with the column ``m`` (S,) put in the middle: (S, 9) (as numpy.insert at 4,
    without its overhead per call)."""
    return np.concatenate([a[:, :4], m[:, None], a[:, 4:]], axis=1)


def loop_fit_fields(A, B, theta, cov, umax) -> dict:
    """The fields every exact-loop fit reports, from its parameters (A = Δf0, B = ΔΓ0, θ) and
    their covariance ``cov`` (S, k, k), k >= 3 with (A, B, ln θ) first; ``umax`` the largest
    amplitude of each sweep (x_max = θ u_max)."""
    return {
        "df0_Hz": A,
        "df0_err_Hz": np.sqrt(cov[:, 0, 0]),
        "dgamma0_Hz": B,
        "dgamma0_err_Hz": np.sqrt(cov[:, 1, 1]),
        "theta_per_m": theta,
        "lntheta_err": np.sqrt(cov[:, 2, 2]),
        "cov_df0_lntheta": cov[:, 0, 2],
        "x_max": theta * umax,
    }


# --------------------------------------------------------------------------------------------
# Plateau loop (the quadrature reference; the fit is in contactres.analysis._plateau)


class _UnitPlateauLoops(MasingLoop):
    """:class:`contactres.PlateauLoop` around ``CattaneoMindlinLoop(1, 1, 1)`` for an array of
    critical displacements ``c`` (one per amplitude), in the form that the Masing quadrature of
    :mod:`contactres.resonators` integrates (breaks and singular points per amplitude, last
    axis)."""

    def __init__(self, c):
        self.inner = CattaneoMindlinLoop(kappa=1.0, mu=1.0, normal_force=1.0)
        self.kappa = 1.0
        self.c = np.asarray(c, dtype=float)[..., None]

    @property
    def breaks(self):
        return np.concatenate([self.c, self.c + self.inner.slip_displacement], axis=-1)

    @property
    def singular_points(self):
        return self.c + self.inner.slip_displacement

    def slopes(self, d):
        return self.inner.slopes(np.maximum(d - self.c, 0.0))


def plateau_loop_shape(x, c) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of a Cattaneo-Mindlin loop behind a stick plateau.

    The loop is :class:`contactres.PlateauLoop` (critical displacement d_c) around
    :class:`contactres.CattaneoMindlinLoop`; ``x`` = κu0/(μF_N) and ``c`` = κd_c/(μF_N)
    (broadcast together). Paper 2, Eqs. 4-6 with Masing's rule, integrated with the quadrature
    of :func:`contactres.loop_stiffness` (relative accuracy 1e-9), vectorised.
    """
    x, c = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(c, dtype=float))
    if np.any(~(x >= 0)) or np.any(~(c >= 0)):
        raise ContactresInputError("plateau_loop_shape needs x >= 0 and c >= 0")
    k1, k2 = masing_stiffness(_UnitPlateauLoops(c.ravel()), x.ravel(), DEFAULT_NODES)
    return k1.reshape(x.shape), k2.reshape(x.shape)
