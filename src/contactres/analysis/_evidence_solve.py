"""The projected solve of the plateau's evidence at its nodes: the sums over a block's amplitudes
and, from them, ln L, ln π and ln μ node by node.

Why. :func:`contactres.analysis._plateau_evidence._integrand_in_sets` evaluates the plateau loop's
likelihood at ~10^7 nodes (the 10^5 sweeps of issue 31); at each, the amplitudes Pκ and Pωξ
are solved in closed form on the block's distinct amplitudes (:func:`level_sums`,
:func:`_solve_levels`) and the node's logarithms formed (:func:`node_values`). Its own module
since issue 31, point 3, ninth round (the evidence's module had passed its length limit): the
node construction and the sums over the nodes stay there, the arithmetic at one node here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["level_sums", "level_weights", "node_values", "same_weights", "segments"]


def segments(cut, rows):
    """Runs (d0, d1) of the sets of rows that share their slopes (set d: the rows
    ``cut[d]:cut[d + 1]`` in the order of
    :func:`~contactres.analysis._plateau_evidence._integrand_in_sets`), each of ``rows`` rows
    or more (the last: what is left), no set split: each set's products stay of one shape."""
    out, d0, D = [], 0, cut.size - 1
    while d0 < D:
        d1 = min(max(d0 + 1, int(np.searchsorted(cut, cut[d0] + rows))), D)
        out.append((d0, d1))
        d0 = d1
    return out


def node_values(lin, sq, per, theta, out):
    """ln L + ln π, ln L and ln μ of
    :func:`~contactres.analysis._plateau_evidence._integrand_in_sets` at its nodes ``theta``
    (R, Y), into ``out`` (3, R, Y), from the sums over the amplitudes (``lin``, ``sq``:
    :func:`level_sums`) and the rows' numbers ``per`` (R, 13; :func:`level_weights`): C_f, C_Γ,
    Σ w ΔΓc, n, the floors of the RSS, the scatters, the prior on ln μ, to_mu and the weights
    of Δf, ΔΓ."""
    C_f, C_g, g_sum, n, lo_f, lo_g, scatter_f, scatter_g, mean, var, to_mu, wf, wg = (
        per[:, k : k + 1] for k in range(13)
    )
    A, rss_f, rss_g = _solve_levels(lin, sq, C_f, C_g, g_sum, n, lo_f, lo_g, wf, wg)
    # ln L = -n/2 (ln RSS_f + ln RSS_Γ), ln μ = ln(A to_mu / θ) and ln π: in place, each
    # operation's operands and order as written out here (the same bits, fewer temporaries),
    # straight into ``out`` (its callers give a contiguous block of rows: numpy's loops run
    # over it at once, not row by row as over a strided view).
    with np.errstate(divide="ignore", invalid="ignore"):
        rss_f += scatter_f
        rss_g += scatter_g
        lnL = np.log(rss_f, out=out[1])
        lnL += np.log(rss_g, out=rss_g)
        lnL *= -0.5 * n
        ln_mu = np.multiply(A, to_mu, out=out[2])
        ln_mu /= theta
        np.log(ln_mu, out=ln_mu)
        # A block without a prior on μ: flat in y, the same in both models.
        has = np.isfinite(mean) & np.isfinite(var) & (var > 0)
        lnpi = np.subtract(ln_mu, mean, out=out[0])  # -(ln μ - mean)²/(2 var) - ln(2π var)/2
        np.square(lnpi, out=lnpi)
        lnpi *= -0.5
        lnpi /= var
        lnpi -= 0.5 * np.log(2 * np.pi * var)
        if not has.all():
            lnpi[~has[:, 0]] = 0.0
        ok = np.isfinite(lnL)
        ok &= A > 0
        ok &= np.isfinite(lnpi)
        # A node without a likelihood (A <= 0, an RSS not positive) or a prior is none: its
        # values set where there is one (on the 10^5 sweeps of issue 31 none of 19 million
        # nodes: the three masked passes skipped).
        bad = None if ok.all() else ~ok
        if bad is not None:
            np.copyto(ln_mu, 0.0, where=bad)
        lnpi += lnL
        if bad is not None:
            np.copyto(lnpi, -np.inf, where=bad)
            np.copyto(lnL, -np.inf, where=bad)


def level_weights(pts, L):
    """The weights of the sums of :func:`level_sums` of each block (``pts``:
    :func:`~contactres.analysis._plateau_evidence._rows`; L amplitudes): (w, w Δf, w ΔΓc) (B, 3, L),
    w = the numbers of points (B, L), and (B, 13) the numbers :func:`node_values` takes: C_f, C_Γ,
    Σ w ΔΓc, n and the floors of the RSS of :func:`_solve_levels`, the scatters, the prior on ln μ,
    to_mu and the weights of Δf, ΔΓ."""
    _, n_lev, df, dg = pts[:4]
    w = n_lev[:, 0]  # (B, L)
    n = w.sum(-1, keepdims=True)  # (B, 1)
    dgm = (w * dg[:, 0]).sum(-1, keepdims=True) / n
    dgc = dg[:, 0] - dgm
    wdf, wdgc = w * df[:, 0], w * dgc
    C_f = (wdf * df[:, 0]).sum(-1, keepdims=True)
    C_g = (wdgc * dgc).sum(-1, keepdims=True)
    # Below its rounding, (L + 3)·ε·C, the expanded square says nothing; a fit exact to that
    # level would come out negative (ln L -inf, the node lost): such an RSS is held at the
    # floor, its best estimate (review R22b; :func:`_solve_levels`).
    floor = (L + 3) * np.finfo(float).eps
    per = (C_f, C_g, wdgc.sum(-1, keepdims=True), n, floor * C_f, floor * C_g)
    per += (*pts[4:6], *pts[9:12], *pts[7:9])
    return np.stack([w, wdf, wdgc], axis=1), w, np.concatenate(per, axis=1)


def level_sums(slopes, squares, W, w, block, cut, d0, d1, same=None):
    """The sums over the amplitudes of the projected solve at the nodes (R, Y) of each row
    (:func:`_solve_levels`): that of :func:`~contactres.analysis._loops.solve_projected` on a
    block's distinct amplitudes weighted by their numbers of points, from the sums over the
    amplitudes of G′, G″ (``slopes``, (D, 2Y, L), of the distinct rows) and of their squares
    (``squares``) times the weights and weighted data of the row's block (``W``, ``w``:
    :func:`level_weights`), for the rows of the sets ``d0`` to ``d1`` of rows on one distinct
    row of slopes (set d: the rows ``cut[d]:cut[d + 1]`` in the order of
    :func:`~contactres.analysis._plateau_evidence._integrand_in_sets`, whose blocks are
    ``block``), in that order: (n, 3, 2Y) and (n, 2Y). ``same`` (D,): whether all rows of set d
    have the same ``w`` (its bits; :func:`same_weights`; by default none is taken to).

    Why. The sums are the only work at each node and amplitude: matrix products of the rows
    of G′, G″ and of their squares against the weight vectors, instead of the residuals formed
    at every amplitude (~20 passes over (R, Y, L) arrays against ~8); the weight vectors of all
    rows on one distinct row of slopes against it in one product (no copy of the slopes for
    each row; on the 10^4 sweeps of issue 31 the same numbers bit for bit), the squares against
    each row's w one by one (matrix times vector: taken together, as a matrix product, they
    differed by rounding, 2 ln B by up to 9e-10), once for a set whose rows have one w (the
    same call with the same vector: the same bits; on the 10^5 sweeps of issue 31 every set's
    rows have one w, 6,838 products instead of 791,909). With
    S_ff = Σ n G′², S_f = Σ n Δf G′ and the like, A = (w_f S_f + w_g S_g)/(w_f S_ff + w_g S_gg)
    and RSS_f = C_f - 2A S_f + A² S_ff, RSS_Γ = C_Γ - 2A S_g + A² S_gg (C: the weighted sums of
    squares of the data, ΔΓ about its mean): the same minimum in exact arithmetic, by the
    expanded square. Its rounding is a few (L + 3)·ε·C_f at most (Higham's bound for sums of
    L terms), relative to the RSS C_f/RSS times that, and ln L's error n/2 of that relative
    error: ~1e-6 for RSS/C at 1e-8 (noise 1e-4 of the shifts), far below the rule's own error
    (:data:`~contactres.analysis._plateau_evidence.EVIDENCE_NODES`: 0.33 in 2 ln B). On the 10^4
    sweeps of issue 31 (1,975 undecided blocks, 1,402 with a finite 2 ln B) 2 ln B moved by <= 4e-9
    against the residuals squared at every amplitude, μ and its error by <= 1.2e-10 relative. Each
    row's products have one shape, so its numbers do not depend on the rows evaluated with it; where
    no row shares its slopes (each sweep's amplitudes its own) the same products are taken for all
    of a segment's rows in one stacked call (not a Python loop over ~10^5 rows; on 10^4 such
    sweeps the same bits)."""
    _, Y2, L = slopes.shape
    a, b = int(cut[d0]), int(cut[d1])
    lin, sq = np.empty((b - a, 3, Y2)), np.empty((b - a, Y2))
    # Per row: (w, w Δf, w ΔΓc) against [G′; G″] (2Y, L), w against [G′²; G″²]: for all rows
    # of one distinct row of slopes in one product each, written in place. (Not the three
    # products used alone, w Δf against G′ and (w, w ΔΓc) against G″: BLAS sums the last
    # columns of a product of Y columns in another order than those of 2Y, other bits in
    # 2 ln B at ~1e-12.)
    if slopes.shape[0] == block.size:
        # No row shares its slopes: the products of all the segment's rows in one call each.
        mine = block[a:b]
        np.matmul(W[mine], slopes[d0:d1].transpose(0, 2, 1), out=lin)
        sq[...] = (squares[d0:d1] @ w[mine][..., None])[..., 0]
        return lin, sq
    for d in range(d0, d1):
        i, j = int(cut[d]) - a, int(cut[d + 1]) - a
        mine = block[a + i : a + j]
        np.matmul(W[mine].reshape(-1, L), slopes[d].T, out=lin[i:j].reshape(-1, Y2))
        # A set whose rows have one w: the product of its first row (the same call as for each
        # row, a matrix times one vector) given to all.
        k = 1 if same is not None and same[d] else j - i
        sq[i:j] = (squares[d] @ w[mine[:k], :, None])[..., 0]
    return lin, sq


def same_weights(ids, cut):
    """Whether all rows of each set of :func:`level_sums` (set d: the rows ``cut[d]:cut[d + 1]``)
    have the same weights, from the number of each row's weights among the distinct ones
    (``ids``, (R,) in that order): (D,), a set's least and largest number equal."""
    if not ids.size:
        return np.zeros(cut.size - 1, dtype=bool)
    return np.minimum.reduceat(ids, cut[:-1]) == np.maximum.reduceat(ids, cut[:-1])


def _solve_levels(lin, sq, C_f, C_g, g_sum, n, lo_f, lo_g, wf, wg):
    """Pκ (A) and the residual sums of Δf and ΔΓ at the nodes (R, Y) of each row from the sums
    of :func:`level_sums` (``lin``: Σ w G, Σ w Δf G, Σ w ΔΓc G, G = G′ and G″ side by side
    (R, 3, 2Y); ``sq``: Σ w G′², Σ w G″² side by side (R, 2Y); ``C_f``, ``C_g``,
    ``g_sum`` = Σ w ΔΓc, ``n`` and the floors ``lo_f``, ``lo_g`` of the RSS (R, 1)) and the
    weights ``wf``, ``wg`` (R, 1) of Δf and ΔΓ (:func:`level_sums`' docstring)."""
    Y = lin.shape[2] // 2
    s_f, s_ff = lin[:, 1, :Y], sq[:, :Y]
    g2m = lin[:, 0, Y:] / n
    # Σ n ΔΓc (G″ - mean) and Σ n (G″ - mean)²: the mean's terms taken out (Σ n ΔΓc is 0 but
    # for rounding; kept, it costs one product).
    s_g = lin[:, 2, Y:] - g2m * g_sum
    s_gg = sq[:, Y:] - g2m * lin[:, 0, Y:]
    # A = (wf s_f + wg s_g)/(wf s_ff + wg s_gg), RSS = C - A (2 s - A s_sq): in place, each
    # operation's operands and order as written (the same bits, fewer temporaries).
    A = wf * s_f
    A += wg * s_g
    den = wf * s_ff
    den += wg * s_gg
    A /= den
    # An RSS below its rounding held at its floor (:func:`level_sums`); rows with noise above
    # rounding are untouched.
    rss = []
    for C, s, ss, lo in ((C_f, s_f, s_ff, lo_f), (C_g, s_g, s_gg, lo_g)):
        r = A * ss
        np.subtract(2.0 * s, r, out=r)
        r *= A
        np.subtract(C, r, out=r)
        rss.append(np.maximum(r, lo, out=r))
    return A, rss[0], rss[1]
