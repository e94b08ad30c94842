"""The nodes of the layered correction's ΔM integral and the Bessel functions on them.

The discretisation of the integral (:class:`PunchResolution`); the real-axis nodes of each
point (:func:`assemble_nodes`): the geometric panels' own Gauss-Legendre nodes below s = 32/3,
then the panels of one grid k L shared by every point (:func:`grid_width`), Δg interpolated onto
them from its Chebyshev samples in ln s, every panel on one Gauss-Legendre rule made once per
call (:func:`unit_rule`, mapped by :func:`rule_on`); and j_p(s) on those nodes: the shared
grid's once per call (:func:`grid_bessel` for the normal punch, :func:`bessel_on_grid` and
:func:`bessel_on_nodes` for the tangential one), the points' own nodes as their real and complex
parts with each point's rows gathered from them (:func:`own_bessel`, :func:`own_rows`), and the
weighted Gram products of the tangential punch (:func:`weighted_gram`). The path that leads to
these nodes (the lifted arc, the panels' edges and where they stop) is the module
``contactres.dynamic._layered_path``; the method and its measured accuracy are described in
``contactres.dynamic._layered_punch``.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace

import numpy as np

from ..numerics import gauss_legendre
from ._layered_waves import chebyshev_values

__all__ = [
    "CorrectionNodes",
    "PunchResolution",
    "assemble_nodes",
    "bessel_on_grid",
    "bessel_on_nodes",
    "concatenated_ranges",
    "grid_bessel",
    "grid_width",
    "own_bessel",
    "own_rows",
    "panel_search",
    "punch_resolution",
    "rule_on",
    "split_at",
    "unit_rule",
    "weighted_gram",
]

# s below which the geometric real panels keep their own nodes (Δg varies on the scale of the
# arc's end S₁ <= 5 there), beyond which the shared grid's panels serve.
_OWN_END = 32 / 3


@dataclass(frozen=True)
class PunchResolution:
    """Discretisation of the ΔM integral; :meth:`doubled` refines every part.

    Attributes
    ----------
    n_panel : Gauss-Legendre nodes per panel of the lifted arc (panels no wider than the lift)
    n_cheb : Chebyshev samples of Δg per real-axis panel (in ln s)
    ratio : ratio of the geometric real-axis panels
    per_unit : Gauss-Legendre nodes per unit of s on the shared real grid (j_p j_q has period
        π; n_panel nodes on a panel of width n_panel/per_unit, :func:`grid_width`)
    n_start : nodes of the first real panel [0, s₀] (statics)
    decay : the panels stop when ``|Δg|`` falls below decay × ``|g_film|`` (and η h > 5)
    """

    n_panel: int = 16
    n_cheb: int = 12
    ratio: float = 1.5
    per_unit: float = 1.5
    n_start: int = 16
    decay: float = 1e-9

    def doubled(self) -> PunchResolution:
        """Twice the nodes everywhere, panels of the square-root ratio, decay 1e-2 lower."""
        return replace(
            self,
            n_panel=2 * self.n_panel,
            n_cheb=2 * self.n_cheb,
            ratio=math.sqrt(self.ratio),
            per_unit=2 * self.per_unit,
            n_start=2 * self.n_start,
            decay=self.decay * 1e-2,
        )


def punch_resolution(rtol: float) -> PunchResolution:
    """The :class:`PunchResolution` for relative accuracy ``rtol`` (checked in the tests against
    :meth:`PunchResolution.doubled`)."""
    base = PunchResolution(decay=1e-3 * rtol)
    if rtol <= 1e-8:
        return replace(base, n_panel=24, n_cheb=16, per_unit=2.0)
    return base


def grid_width(res: PunchResolution) -> float:
    """L: the width of the real-axis panels of n_panel nodes (per_unit nodes per unit of s)
    on the grid k L shared by every point (their Bessel functions are computed once).

    Gauss's error on such a panel of half-width w = L/2 for the oscillation e^{2is} of
    j_p j_q is at most (64/15) w e^{w(ρ − 1/ρ)} ρ^{−2n}/(ρ² − 1) for any ρ > 1 (the
    integrand's bound on the Bernstein ellipse ρ): with n = 16 nodes and w = 16/3 (1.5 per
    unit of s, the default) ~3e-12 of the panel's largest ``|Δg j_p j_q|`` at ρ = 5.8; with
    n = 24 and 2 per unit (rtol <= 1e-8) ~1e-22. Δg varies more slowly there (its scales
    are h and the wave numbers: :data:`_OWN_END`)."""
    return res.n_panel / res.per_unit


def unit_rule(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The n-point Gauss-Legendre rule on [−1, 1] (nodes, weights) of
    :func:`contactres.numerics.gauss_legendre`, for :func:`rule_on` to map: the nodes of the
    correction take it once per call instead of once per use (each costs a few hundred µs)."""
    return gauss_legendre(-1.0, 1.0, n)


def rule_on(rule: tuple, a, b) -> tuple[np.ndarray, np.ndarray]:
    """The :func:`unit_rule` ``rule`` on [a, b] (broadcast as in
    :func:`contactres.numerics.gauss_legendre`, by the same arithmetic: the same numbers)."""
    return gauss_legendre(a, b, len(rule[0]), rule=rule)


def _on_panels(rule, lo: np.ndarray, hi: np.ndarray):
    """Nodes and weights (flat) of the unit Gauss-Legendre ``rule`` (x, w on [0, 1]) mapped
    onto the panels [lo_k, hi_k]."""
    x, w = rule
    d = (hi - lo)[:, None]
    return (lo[:, None] + d * x[None, :]).ravel(), (d * w[None, :]).ravel()


def assemble_nodes(res: PunchResolution, rule, points, shift) -> list:
    """The nodes of every point of ``points`` [(edges, last, stop, head, values), ...]
    (:class:`CorrectionNodes`): the head's; the geometric panels' own below
    :data:`_OWN_END`; a panel to the next edge of the shared grid k L (:func:`grid_width`); the
    grid's panels up to the first grid edge S at or beyond ``stop`` (<= ``edges[last]``). Δg at
    the real nodes is interpolated from the Chebyshev samples (in ln s) of the geometric panel
    holding them.

    The points are assembled in groups of at most ~:data:`_GROUP_NODES` nodes (one mapping of
    the Gauss rule, one panel search and one interpolation per group instead of per point:
    the same values node by node); a group's arrays stay small enough to be reused from the
    heap (those of the ~16000 nodes of 41 points at once were fresh pages on every call)."""
    out: list = []
    group: list = []
    size = 0
    for point, panels in zip(points, _real_panels(res, points), strict=True):
        group.append((point, panels))
        size += panels[0].size * res.n_panel
        if size >= _GROUP_NODES:
            out += _assemble_group(res, rule, group, shift)
            group, size = [], 0
    if group:
        out += _assemble_group(res, rule, group, shift)
    return out


# Real nodes of the points assembled together (see assemble_nodes).
_GROUP_NODES = 4096


def _real_panels(res: PunchResolution, points) -> list:
    """[(lo, hi, k0, k1), ...] of every point (edges, last, stop, ...) of ``points``: the real
    panels [lo_k, hi_k] of its nodes, its first and last edges k0 L, k1 L of the shared grid;
    formed for all the points at once (a few hundred panels)."""
    width = grid_width(res)
    n_pts = len(points)
    lasts = np.array([p[1] for p in points])
    # The points' edges e_0..e_last one after the other; point i's from row first[i].
    edges = np.concatenate([p[0][: p[1] + 2] for p in points])
    first = np.cumsum(lasts + 2) - (lasts + 2)
    # Below _OWN_END the geometric panels are narrower than the grid's (Δg varies on the scale
    # of the arc's end S₁ there): each gets its own sub-panels, per_unit nodes per unit of s on
    # average; from the first edge beyond _OWN_END one panel to the next grid edge, then the
    # grid. own: the number of edges e_0..e_last below _OWN_END (np.searchsorted).
    below = edges < _OWN_END
    below[first + lasts + 1] = False
    own = np.bincount(np.repeat(np.arange(n_pts), lasts + 2), weights=below, minlength=n_pts)
    own = own.astype(int)
    j = np.repeat(first, own) + concatenated_ranges(own)
    width_j = edges[j + 1] - edges[j]
    n_sub = np.maximum(1, np.ceil(res.per_unit * width_j / res.n_panel)).astype(int)
    subs = np.bincount(np.repeat(np.arange(n_pts), own), weights=n_sub, minlength=n_pts)
    subs = subs.astype(int)
    k = concatenated_ranges(n_sub)
    wj, nj, ej = np.repeat(width_j, n_sub), np.repeat(n_sub, n_sub), edges[np.repeat(j, n_sub)]
    bridge = edges[first + own]
    k0 = np.ceil(bridge / width).astype(int)
    k1 = np.maximum(k0, np.ceil(np.array([p[2] for p in points]) / width).astype(int))
    n_pan = subs + 1 + k1 - k0
    start = np.cumsum(n_pan) - n_pan
    lo, hi = np.empty(int(np.sum(n_pan))), np.empty(int(np.sum(n_pan)))
    at = np.repeat(start, subs) + concatenated_ranges(subs)
    lo[at], hi[at] = ej + wj * k / nj, ej + wj * (k + 1) / nj
    lo[start + subs], hi[start + subs] = bridge, width * k0
    grid = concatenated_ranges(k1 - k0)
    at = np.repeat(start + subs + 1, k1 - k0) + grid
    kk = np.repeat(k0, k1 - k0) + grid
    lo[at], hi[at] = width * kk, width * (kk + 1)
    cut = np.cumsum(n_pan)[:-1]
    return list(zip(split_at(lo, cut), split_at(hi, cut), k0.tolist(), k1.tolist(), strict=True))


def split_at(a: np.ndarray, cuts, axis: int = 0) -> list[np.ndarray]:
    """``np.split(a, cuts, axis)``: the views of ``a`` between the indices ``cuts`` along
    ``axis``, by slicing: np.split swaps the axes once per piece and once per call (~400
    pieces per layered curve for its 41 points), the same views."""
    bounds = [0, *np.asarray(cuts, dtype=int).tolist(), a.shape[axis]]
    before = (slice(None),) * (axis % a.ndim)
    index = [(*before, slice(lo, hi)) for lo, hi in itertools.pairwise(bounds)]
    return [a[i] for i in index]


def concatenated_ranges(counts: np.ndarray) -> np.ndarray:
    """0, 1, ..., c_0 − 1, 0, 1, ..., c_1 − 1, ... for the counts c_i (>= 0)."""
    return np.arange(int(np.sum(counts))) - np.repeat(np.cumsum(counts) - counts, counts)


def _assemble_group(res: PunchResolution, rule, group, shift) -> list:
    """:func:`assemble_nodes` of the points of ``group`` [(point, :func:`_real_panels`), ...]."""
    width = grid_width(res)
    n_pts = len(group)
    t, wt = _on_panels(
        rule,
        np.concatenate([p[1][0] for p in group]),
        np.concatenate([p[1][1] for p in group]),
    )
    counts = np.array([p[1][0].size * res.n_panel for p in group])
    ends = width * np.array([float(p[1][3]) for p in group])
    # Every point's real nodes, then every point's end S (Δg(S) for its tail).
    where = np.concatenate([t, ends])
    pid = np.concatenate([np.repeat(np.arange(n_pts), counts), np.arange(n_pts)])
    # The points' edges and Chebyshev samples one after the other: point i's edge e and panel
    # k are rows first[i] + e and first_panel[i] + k.
    lasts = np.array([p[0][1] for p in group])
    n_edges = lasts + 2
    first = np.cumsum(n_edges) - n_edges
    first_panel = first - np.arange(n_pts)
    edges = np.concatenate([p[0][0][: p[0][1] + 2] for p in group])
    u = np.log(edges)
    log_where = np.log(where)
    lo, hi = first[pid], (first + lasts)[pid]
    panel = panel_search(where, log_where, edges, u, lo, hi)
    x = (2 * log_where - u[panel] - u[panel + 1]) / (u[panel + 1] - u[panel])
    cheb = np.concatenate(
        [p[0][4][p[0][3][0].size :].reshape(p[0][1] + 1, res.n_cheb, -1) for p in group]
    )
    tail = group[0][0][4].shape[1:]
    g = chebyshev_values(x, cheb, panel - first[pid] + first_panel[pid])
    g = g.reshape(where.size, *tail)
    n_real = t.size
    # Each point's head and real nodes, one after the other, in one array per field (views).
    heads = [p[0][3] for p in group]
    n_head = np.array([h[0].size for h in heads])
    ends_real = np.cumsum(counts)
    bounds = np.stack([ends_real - counts, ends_real], axis=1)
    tc, wc = t.astype(complex), wt.astype(complex)

    def joined(head_parts, real):
        parts = []
        for h, (lo_k, hi_k) in zip(head_parts, bounds, strict=True):
            parts += [h, real[lo_k:hi_k]]
        return split_at(np.concatenate(parts), np.cumsum(n_head + counts)[:-1])

    s = joined([h[0] for h in heads], tc)
    weights = joined([h[1] for h in heads], wc)
    delta_g = joined([p[0][4][: h[0].size] for p, h in zip(group, heads, strict=True)], g)
    out = []
    for i, (_, (lo_i, _, k0, k1)) in enumerate(group):
        out.append(
            CorrectionNodes(
                s=s[i],
                weights=weights[i],
                delta_g=delta_g[i],
                s_end=float(width * k1),
                end=g[n_real + i],
                shift=shift,
                n_own=int(n_head[i]) + (lo_i.size - (k1 - k0)) * res.n_panel,
                grid_from=k0 * res.n_panel,
            )
        )
    return out


def panel_search(v, log_v, edges, u, lo, hi) -> np.ndarray:
    """For each value v (> 0) the row p in [lo, hi] of the concatenated ascending runs
    ``edges`` (``u`` their logarithms) with edges[p] < v <= edges[p + 1] (clipped to the run:
    ``np.searchsorted(run, v) − 1`` clipped to [0, last], for every run at once). Started from
    the geometric estimate ln(v/e₀)/ln(e₁/e₀) and moved until it holds (one step for geometric
    edges)."""
    guess = np.floor((log_v - u[lo]) / (u[lo + 1] - u[lo]))
    p = lo + np.clip(guess, 0, hi - lo).astype(int)
    while True:
        down = (p > lo) & (v <= edges[p])
        up = (p < hi) & (v > edges[p + 1])
        if not (np.any(down) or np.any(up)):
            return p
        p = p - down + up


@dataclass(frozen=True, eq=False)
class CorrectionNodes:
    """The nodes of one point's ΔM integral (:func:`correction_nodes`).

    Attributes
    ----------
    s, weights : complex nodes s = η a and weights ds
    delta_g : Δg(s/a, θ), (len(s), nθ) (+ (2, 2) in-plane)
    s_end : S, the end of the nodes (the tail beyond it is in closed form)
    end : Δg(S/a, θ)
    shift : g∞_film − g∞_ref (θ), the static difference of film and reference
    n_own : the first ``n_own`` nodes are this point's own; the rest are the nodes
        ``grid_from`` onwards of the shared real grid (:func:`bessel_on_nodes`)
    grid_from : index of the first shared grid node
    """

    s: np.ndarray
    weights: np.ndarray
    delta_g: np.ndarray
    s_end: float
    end: np.ndarray
    shift: np.ndarray
    n_own: int
    grid_from: int


def bessel_on_nodes(p_max: int, nodes: dict, res: PunchResolution, transform) -> dict:
    """T(J) of J = j_p(s), p = 0..p_max ((p_max + 1, n) complex), on the nodes of every point
    of ``nodes`` (index -> :class:`CorrectionNodes`): index -> (T(J) on the point's own nodes,
    T(J) on its shared grid nodes (a view)). J of the shared grid is computed once; ``transform``
    T maps J (p_max + 1, n) to the rows the caller needs (R, n), column by column."""
    if not nodes:
        return {}
    grid, own = bessel_on_grid(p_max, nodes, res, transform)
    return {
        i: (o, grid[:, v.grid_from : v.grid_from + v.s.size - v.n_own])
        for (i, v), o in zip(nodes.items(), own, strict=True)
    }


def bessel_on_grid(p_max: int, nodes: dict, res: PunchResolution, transform=None):
    """(T(J) on the whole shared grid (R, n_grid), real; [T(J) on each point's own nodes, in
    the order of ``nodes``]), J = j_p(s), p = 0..p_max (:func:`bessel_on_nodes`, whose grid
    parts are the columns ``grid_from`` onwards of the first; ``transform`` None: J itself)."""
    T = transform or (lambda J: J)
    grid = T(grid_bessel(p_max, nodes, res))
    # Every point's own nodes in one call (the recurrences run over orders: one pass for all).
    own = T(_bessel(p_max, np.concatenate([v.s[: v.n_own] for v in nodes.values()])))
    cut = np.cumsum([v.n_own for v in nodes.values()])[:-1]
    return grid, split_at(own, cut, axis=1)


def grid_bessel(p_max: int, nodes: dict, res: PunchResolution, rule=None) -> np.ndarray:
    """J = j_p(s), p = 0..p_max, on the whole shared grid of the points ``nodes`` (index ->
    :class:`CorrectionNodes`), (p_max + 1, n_grid), real (:func:`bessel_on_grid`'s grid);
    ``rule``: :func:`unit_rule` of ``res.n_panel`` where the caller has it."""
    top = max(v.grid_from + v.s.size - v.n_own for v in nodes.values())
    n_pan = math.ceil(top / res.n_panel)
    edges = grid_width(res) * np.arange(n_pan + 1, dtype=np.float64)
    unit = rule_on(rule, 0.0, 1.0) if rule is not None else gauss_legendre(0.0, 1.0, res.n_panel)
    t, _ = _on_panels(unit, edges[:-1], edges[1:])
    # Real nodes, real j_p: the grid's part of every Gram product runs in real arithmetic.
    from ._weights import spherical_bessel

    return spherical_bessel(p_max, t)


def weighted_gram(parts, v: np.ndarray, cols=None) -> np.ndarray:
    """Σ_n J_an v_kn J_bn (K, R, R) over a point's nodes, from its two parts (own, grid) of J
    (:func:`bessel_on_nodes`) and K rows of weights ``v`` (K, n) on all its nodes (own
    first): one batched matrix product per part. ``cols``: only the columns b in ``cols``
    (K, R, len(cols)) (the rows of a basis grown by a few orders: the others are known)."""
    own, grid = parts
    right_own = own if cols is None else own[cols]
    right_grid = grid if cols is None else grid[cols]
    n, k = own.shape[1], v.shape[0]
    out = (own[None] * v[:, None, :n]) @ right_own.T
    # The grid's J is real: the real and imaginary parts of v as 2K real products (half the
    # arithmetic of complex ones).
    both = np.concatenate([v.real[:, n:], v.imag[:, n:]])
    g = (grid[None] * both[:, None, :]) @ right_grid.T
    return out + (g[:k] + 1j * g[k:])


def own_bessel(p_max: int, nodes: dict) -> tuple:
    """J = j_p(s), p = 0..p_max, on every point's own nodes (``nodes``: index ->
    :class:`CorrectionNodes`), kept as computed: ((J of the complex nodes (p_max + 1, n_c),
    complex; J of the real nodes (p_max + 1, n_r), real), [each point's runs (kind, first and
    end column in its part, first and end column on its own nodes), in the order of
    ``nodes``]). The rows of a point are :func:`own_rows`.

    The same values as :func:`bessel_on_grid`'s own J, without its complex (p_max + 1, all
    own nodes) copy of both parts: with the parts, that copy was held at the normal punch's
    peak of memory (3.7 MB of 11.6 MB for 250 nm PMMA on quartz, 41 points), whose heap glibc
    returns to the system after each call (fresh pages, faulted in again, on every call)."""
    from ._weights import spherical_bessel

    s = np.concatenate([v.s[: v.n_own] for v in nodes.values()])
    real = s.imag == 0
    parts = (spherical_bessel(p_max, s[~real]), spherical_bessel(p_max, s[real].real))
    # Runs of one kind (the complex arc, then the real panels), cut at the points' ends.
    ends = np.cumsum([v.n_own for v in nodes.values()])
    cuts = np.union1d(np.flatnonzero(real[1:] != real[:-1]) + 1, ends)
    taken = np.cumsum(real)  # real nodes up to and including each node
    runs: list[list] = [[] for _ in nodes]
    lo, point = 0, 0
    for hi in cuts.tolist():
        if hi > lo:
            kind = int(real[lo])
            # The run's first column in its part: the nodes of its kind before it.
            first = int(taken[lo]) - 1 if kind else lo - int(taken[lo])
            start = int(ends[point - 1]) if point else 0
            runs[point].append((kind, first, first + hi - lo, lo - start, hi - start))
        while point < ends.size and hi == ends[point]:
            point += 1
        lo = hi
    return parts, runs


def own_rows(parts: tuple, runs: list, rows) -> np.ndarray:
    """The rows ``rows`` (a slice or index array of orders) of J on one point's own nodes,
    (len(rows), its own nodes), complex, from :func:`own_bessel`'s ``parts`` and the point's
    ``runs``."""
    n_rows = np.arange(parts[0].shape[0])[rows].size
    out = np.empty((n_rows, runs[-1][4] if runs else 0), dtype=complex)
    for kind, first, end, lo, hi in runs:
        out[:, lo:hi] = parts[kind][rows, first:end]
    return out


def _bessel(p_max: int, s: np.ndarray) -> np.ndarray:
    """j_p(s), p = 0..p_max, (p_max + 1, len(s)) complex, on nodes ``s``."""
    from ._weights import spherical_bessel

    out = np.empty((p_max + 1, s.size), dtype=complex)
    if s.size == 0:
        return out
    # Real nodes apart: their Bessel functions come from the cheap upward recurrence (the
    # continued fraction of complex arguments would start above 1.3 max|s| for every node).
    real = s.imag == 0
    parts = (spherical_bessel(p_max, s[~real]), spherical_bessel(p_max, s[real].real))
    # Put back run by run (each point's nodes are a run of complex arc nodes, then one of
    # real ones): a slice per run, where a column mask over (p_max + 1) rows cost as much as
    # the functions of the real nodes.
    ends = np.append(np.flatnonzero(real[1:] != real[:-1]) + 1, s.size)
    starts = np.append(0, ends[:-1])
    taken = [0, 0]
    for lo, hi in zip(starts.tolist(), ends.tolist(), strict=True):
        kind = int(real[lo])
        out[:, lo:hi] = parts[kind][:, taken[kind] : taken[kind] + hi - lo]
        taken[kind] += hi - lo
    return out
