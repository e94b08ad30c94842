"""The evidence of a block's stick plateau against its Cattaneo-Mindlin loop, integrated.

Why. The criterion of the plateau loop used to be its fit's BIC with the priors on μ and on
the plateau amplitude d_c/u_max applied at the fit's optimum (Laplace,
:func:`contactres.analysis._plateau_prior.joint_prior_penalty`). In noisy water data the
likelihood of a block's points is nearly flat in d_c (three ramps of 11 amplitudes at
σ = 0.6 Hz cannot tell a plateau over the first third of the loop from a larger μ), so the fit
ends wherever the noise puts it: on its bound d_c = 0 (then the plateau is Cattaneo-Mindlin
and pays one ln N more) or at a plateau beyond any the sample shows. At a bound the Laplace
approximation has nothing to expand about, and the priors, which are what decide such a
block, were not applied at all. On the validation study (``benchmarks/study_qcm_trust.py``,
ten seeds) 12 of the 20 water plateau blocks read as another class ended so.

How (:func:`plateau_log_evidence`). The Bayes factor of the plateau loop against the
Cattaneo-Mindlin loop it nests is the integral over the plateau amplitude and the slip scale,
done on a grid rather than about an optimum:

    B = ∫∫ L(y, z) π(μ(y, z)) p(z) dy dz / ∫ L(y, 0) π(μ(y, 0)) dy,

with y = ln θ(u_max - d_c) (θ = κ/(μF_N), the fitter's own parameter), z = ln(d_c/u_max)
with the prior p = N(m, v) of the analysis's clear plateaus
(:func:`contactres.analysis._plateau_prior.plateau_prior`), π the prior on ln μ from the
experiment's other loads (:mod:`contactres.analysis._mu_prior`; flat in y where there is none,
over the same range in both models, so that its normalisation cancels) and L the likelihood
with the noise levels of Δf and ΔΓ maximised, L ∝ RSS_f^(-n/2) RSS_Γ^(-n/2), the amplitudes Pκ
and Pωξ solved in closed form at every node (:func:`contactres.analysis._loops.
solve_projected`): the same parameters in both models, whose Occam factors cancel to the
order kept. The plateau's criterion is then the Cattaneo-Mindlin loop's minus 2 ln B, on the
scale of the BIC, so that the nesting margin ``delta_bic`` still keeps Cattaneo-Mindlin unless
the plateau has positive evidence. Amplitudes whose plateau leaves fewer than
:data:`~contactres.analysis._amplitude.PLATEAU_MIN_SLOPE` distinct amplitudes above it carry
no likelihood (the prior mass there counts against the plateau: a plateau the sweep cannot
show is no evidence for one). The same nodes give the plateau loop's μ with d_c integrated out
(the posterior of ln μ under the likelihood and the amplitude prior alone): its error includes
what the plateau's width leaves open, which the fit's error at its optimum does not; the
model-averaged μ of the block (:func:`contactres.analysis._friction.model_averaged_mu`) uses it.

Where. Only blocks whose criterion with the priors at the optimum leaves the plateau within
``PLATEAU_UNDECIDED`` of the best other candidate, either way
(:mod:`contactres.analysis._blocks`): a decisive choice is not changed by the integration, and
a clear plateau (the likelihood far narrower in d_c than the prior) is better served by the
fit's own optimum than by nodes spread over the prior.

Result. Validation study, ten seeds: water plateau sweeps right 78.5 % → 94.6 % (per seed 91,
100, 92, 83, 100, 100, 88, 100, 100, 100 %), water Cattaneo-Mindlin 97.5 % → 98.0 %, air
plateau 97.1 % → 98.0 %, air Cattaneo-Mindlin 98.5 % → 99.1 %; μ of the true water plateau
blocks inside ±1.96 printed errors 92.9 % → 94.6 %.

Cost. The nodes of all undecided blocks are evaluated together, in chunks of blocks with one
number of points (numpy on large arrays, no padding weights in the projected solve), the
slopes at each block's distinct amplitudes only (its three ramps repeat them) and without
their derivatives: about 5.7 ms of CPU per block on a full validation study (97 blocks),
against 11 ms block by block, with the same numbers bit for bit.
"""

from __future__ import annotations

import numpy as np

from ..numerics import gauss_legendre_unit
from ._amplitude import PLATEAU_MIN_SLOPE
from ._loops import CHUNK_CELLS, X_MAX, solve_projected
from ._mu_prior import MU_PRIOR_MAX_REL
from ._plateau import SMALL_X_NODES, plateau_loop_slopes

__all__ = ["EVIDENCE_NODES", "plateau_log_evidence"]

#: Nodes of the rules: in z = ln(d_c/u_max), 12 uniform over ±4 prior widths (0.73 of a width
#: apart; a normal density summed so is exact to ~1e-4); in y = ln θ(u_max - d_c), 32 uniform
#: from 10^-2.5 to :data:`~contactres.analysis._loops.X_MAX` (the fitter's bounds; 0.3 apart)
#: and 25 across the two coarse steps around the largest integrand (0.025 apart), summed
#: together by the trapezoidal rule: the fine nodes resolve a μ known to 2 %, the coarse ones
#: the tails of a μ known to 20 % or worse.
EVIDENCE_NODES = (12, 32, 25)


def _integrand(pts, dl, y, rule):
    """ln L + ln π (as :func:`plateau_log_evidence`, up to a common constant), ln L alone and
    ln μ at the nodes (R, Y) of d_c/u_max ``dl`` (R, 1) and ``y`` (R, Y), each row R one block's
    (``pts``: :func:`_rows`).

    The slopes depend on a point only through its amplitude, and a block's sweeps repeat the
    same amplitudes (three ramps: a third of its points distinct), so they are evaluated at the
    block's distinct amplitudes and gathered to its points: the same numbers at a third of the
    cost, which is that of the slopes."""
    lev, idx, df, dg, w, umax, wf, wg, mean, var, to_mu = pts
    theta = np.exp(y) / (umax * (1.0 - dl))
    x = theta[..., None] * lev
    c = np.broadcast_to((theta * dl * umax)[..., None], x.shape)
    g1, g2 = (
        np.take_along_axis(g, idx, axis=-1)
        for g in plateau_loop_slopes(x, c, rule, derivatives=False)
    )
    A, _, _, rss_f, rss_g = solve_projected(g1, g2, df, dg, w, wf, wg)
    n = w.sum(-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        lnL = -0.5 * n * (np.log(rss_f) + np.log(rss_g))
        mu = A * to_mu / theta
        # A block without a prior on μ: flat in y, the same in both models.
        has = np.isfinite(mean) & np.isfinite(var) & (var > 0)
        lnpi = np.where(
            has, -0.5 * (np.log(mu) - mean) ** 2 / var - 0.5 * np.log(2 * np.pi * var), 0.0
        )
        ok = np.isfinite(lnL) & (A > 0) & np.isfinite(lnpi)
        ln_mu = np.where(ok, np.log(np.where(ok, mu, 1.0)), 0.0)
    return np.where(ok, lnL + lnpi, -np.inf), np.where(ok, lnL, -np.inf), ln_mu


def _over_y(pts, dl, rule):
    """ln ∫ L π dy, ln ∫ L dy and the first two moments of ln μ under L, at each d_c/u_max ``dl``
    (R,) of its row's block (``pts``: :func:`_rows`)."""
    _, ny, nf = EVIDENCE_NODES
    K = len(dl)
    dl = dl[:, None]
    coarse = np.linspace(np.log(10.0**-2.5), np.log(X_MAX), ny)
    h = coarse[1] - coarse[0]
    first = _integrand(pts, dl, np.broadcast_to(coarse, (K, ny)), rule)
    peak = coarse[np.argmax(first[0], axis=1)]
    fine = peak[:, None] + np.linspace(-h, h, nf)[None, :]
    fine = np.clip(fine, coarse[0], coarse[-1])
    parts = [(np.broadcast_to(coarse, (K, ny)), first)]
    parts.append((fine, _integrand(pts, dl, fine, rule)))
    y = np.concatenate([yy for yy, _ in parts], axis=1)
    order = np.argsort(y, axis=1, kind="stable")
    y = np.take_along_axis(y, order, axis=1)
    lp, ll, mu = (
        np.take_along_axis(np.concatenate([v[k] for _, v in parts], axis=1), order, axis=1)
        for k in range(3)
    )
    top_p = lp.max(axis=1, keepdims=True)
    top_l = ll.max(axis=1, keepdims=True)
    with np.errstate(invalid="ignore"):
        ep, el = np.exp(lp - top_p), np.exp(ll - top_l)
    ep, el = np.nan_to_num(ep), np.nan_to_num(el)
    with np.errstate(divide="ignore"):
        log_p = np.log(np.trapezoid(ep, y, axis=1)) + top_p[:, 0]
        zl = np.trapezoid(el, y, axis=1)
        log_l = np.log(zl) + top_l[:, 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        m1 = np.trapezoid(el * mu, y, axis=1) / zl
        m2 = np.trapezoid(el * mu**2, y, axis=1) / zl
    return log_p, log_l, m1, m2


def plateau_log_evidence(
    u, df, dg, w, sigma, mu_prior, ratio_prior, to_mu, rows=None
) -> np.ndarray:
    """2 ln B of the plateau loop against the Cattaneo-Mindlin loop of every row (module
    docstring).

    Parameters
    ----------
    u, df, dg, w : (B, M) the points of each block, amplitudes ascending (m, Hz, Hz; w 0 for
        padding)
    sigma : (2, B) noise levels of Δf and ΔΓ, Hz (weights of the projected Pκ, Pωξ)
    mu_prior : (mean, var) of ln μ, (B,) each (NaN: none, a flat prior in y)
    ratio_prior : (mean, var) of ln(d_c/u_max), (B,) each (NaN: none; then NaN out)
    to_mu : (B,) 1/(P F_N), μ = Pκ · to_mu / θ (P in Hz per N/m, F_N in N)
    rows : (B,) which blocks to evaluate (default all; the others get NaN)

    Returns
    -------
    (3, B): 2 ln B (positive: the data favour the plateau; -inf where the prior puts no
    plateau the sweep can show), and μ under the plateau loop with d_c marginalised over its
    prior, exp of the posterior mean of ln μ, with its error μ times the posterior standard
    deviation of ln μ (without the prior on μ: the block's μ stays its own points'); NaN where
    there is no amplitude prior, μ also where that deviation exceeds
    :data:`~contactres.analysis._mu_prior.MU_PRIOR_MAX_REL` (μ not resolved)
    """
    u, df, dg, w = (np.asarray(a, dtype=float) for a in (u, df, dg, w))
    B = u.shape[0]
    out = np.full((3, B), np.nan)
    m2, v2 = (np.asarray(a, dtype=float) for a in ratio_prior)
    sig = np.asarray(sigma, dtype=float)
    nz = EVIDENCE_NODES[0]
    todo = np.isfinite(m2) & np.isfinite(v2) & (v2 > 0)
    todo &= np.ones(B, bool) if rows is None else np.asarray(rows, bool)
    jobs = []  # (block, its nodes in z)
    for b in np.flatnonzero(todo):
        data = w[b] > 0
        umax = u[b][data].max()
        levels = np.unique(u[b][data])
        if levels.size < PLATEAU_MIN_SLOPE + 1 or not (sig[:, b] > 0).all():
            continue
        # The widest plateau that leaves PLATEAU_MIN_SLOPE distinct amplitudes above it.
        hi = np.log(levels[-PLATEAU_MIN_SLOPE] / umax)
        s = np.sqrt(v2[b])
        z = np.linspace(m2[b] - 4 * s, m2[b] + 4 * s, nz)
        z = z[z <= hi]
        if z.size < 2:
            out[0, b] = -np.inf
            continue
        jobs.append((b, z))
    # All blocks' nodes in a few calls (numpy on large arrays), chunks of them keeping those
    # arrays at a few MB; each block's rows: its nodes in z, then d_c = 0. Blocks of one number
    # of points go together: without padding the projected solve skips its weights.
    step = max(1, CHUNK_CELLS // ((nz + 1) * EVIDENCE_NODES[1] * max(u.shape[1], 1)))
    rule = gauss_legendre_unit(SMALL_X_NODES)
    same: dict[int, list] = {}
    for job in jobs:
        same.setdefault(int((w[job[0]] > 0).sum()), []).append(job)
    for group in same.values():
        for i in range(0, len(group), step):
            chunk = group[i : i + step]
            own = np.concatenate([np.full(z.size + 1, k) for k, (_, z) in enumerate(chunk)])
            dl = np.concatenate([np.append(np.exp(z), 0.0) for _, z in chunk])
            pts = _rows(u, df, dg, w, sig, mu_prior, to_mu, [b for b, _ in chunk])
            lp, ll, mu1, mu2 = _over_y(tuple(a[own] for a in pts), dl, rule)
            for k, (b, z) in enumerate(chunk):
                at = np.flatnonzero(own == k)
                _combine(out[:, b], z, lp[at], ll[at], mu1[at], mu2[at], m2[b], v2[b])
    return out


def _rows(u, df, dg, w, sig, mu_prior, to_mu, blocks):
    """The points of ``blocks`` as :func:`_integrand` takes them, one row (1, ...) a block:
    its distinct amplitudes (padded with u_max), each point's index among them, Δf, ΔΓ and
    weights (padding 0), u_max, the weights 1/σ² of Δf and ΔΓ, the prior on ln μ and to_mu."""
    lev, idx = [], []
    for b in blocks:
        levels, inv = np.unique(u[b][w[b] > 0], return_inverse=True)
        lev.append(levels)
        idx.append(inv)
    L, M = max(v.size for v in lev), max(v.size for v in idx)
    nb = len(blocks)
    levs, ids = np.empty((nb, 1, L)), np.zeros((nb, 1, M), int)
    pts = np.zeros((3, nb, 1, M))
    for k, b in enumerate(blocks):
        data = w[b] > 0
        levs[k, 0] = np.pad(lev[k], (0, L - lev[k].size), mode="edge")
        ids[k, 0, : idx[k].size] = idx[k]
        for row, v in zip(pts[:, k, 0], (df[b][data], dg[b][data], 1.0), strict=True):
            row[: idx[k].size] = v
    col = [levs[:, 0, -1:], 1.0 / sig[0, blocks, None] ** 2, 1.0 / sig[1, blocks, None] ** 2]
    col += [np.asarray(a, dtype=float)[blocks, None] for a in (*mu_prior, to_mu)]
    return levs, ids, *pts, *col


def _combine(out, z, lp, ll, mu1, mu2, mean, var):
    """2 ln B and μ of one block (``out``, (3,)) from its rows of :func:`_over_y`: those at the
    nodes ``z`` of ln(d_c/u_max), then d_c = 0; ``mean``, ``var``: the prior on z."""
    l0 = lp[-1]
    lp, ll, mu1, mu2 = lp[:-1], ll[:-1], mu1[:-1], mu2[:-1]
    prior = -0.5 * (z - mean) ** 2 / var - 0.5 * np.log(2 * np.pi * var)
    t, q = lp + prior, ll + prior
    top, topq = t.max(), q.max()
    if not (np.isfinite(top) and np.isfinite(l0) and np.isfinite(topq)):
        return
    dz = z[1] - z[0]
    out[0] = 2.0 * (np.log(np.exp(t - top).sum() * dz) + top - l0)
    wq = np.exp(q - topq)
    m = (wq * mu1).sum() / wq.sum()
    sd = np.sqrt(max((wq * mu2).sum() / wq.sum() - m**2, 0.0))
    if sd <= MU_PRIOR_MAX_REL:  # else μ is not resolved: the fit's own stays
        out[1], out[2] = np.exp(m), np.exp(m) * sd
