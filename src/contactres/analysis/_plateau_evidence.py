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
the plateau has positive evidence (2 ln B > 2 on the scale of Kass & Raftery, J. Am. Stat.
Assoc. 90, 773 (1995), Sec. 3.2). Amplitudes whose plateau leaves fewer than
:data:`~contactres.analysis._amplitude.PLATEAU_MIN_SLOPE` distinct amplitudes above it carry
no likelihood (the prior mass there counts against the plateau: a plateau the sweep cannot
show is no evidence for one). The same nodes give the plateau loop's μ with d_c integrated out
(the posterior of ln μ under the likelihood and the amplitude prior alone): its error includes
what the plateau's width leaves open, which the fit's error at its optimum does not; the
model-averaged μ of the block (:func:`contactres.analysis._friction.model_averaged_mu`) uses it.

Accuracy. The nodes (:data:`EVIDENCE_NODES`) are refined around the peaks of the integrands in
z and in y, and a block whose posterior in z or in y spans fewer than :data:`MIN_SPAN_NODES`
nodes keeps the criterion with the priors at the fit's optimum (NaN here). On the water blocks
of the seeded study 2 ln B is within 0.33 of its value on a far finer grid, μ within 1.6 % and
its error within 6 % (``tests/analysis/test_plateau_evidence.py``).

Limits. The marginal μ's weights over d_c are the pooled amplitude prior's times the block's
likelihood: where the likelihood is flat in d_c (the case this module is for) they are the
prior's, so a block whose plateau differs from the analysis's other plateaus gets a μ centred
where the prior puts d_c, with an error that does not cover its own (a plateau at 0.15 u_max
under a prior at 0.4: none of 20 blocks covered); and a plateau much narrower than the
others' (0.10 u_max) is voted down by the same prior. The prior is the best knowledge of d_c
the analysis has, but only as good as the assumption that a study's plateaus are alike
(docs/validation.md).

Where. Only blocks whose criterion with the priors at the optimum leaves the plateau within
``PLATEAU_UNDECIDED`` of the best other candidate, either way
(:mod:`contactres.analysis._blocks`): a decisive choice is not changed by the integration, and
a clear plateau (the likelihood far narrower in d_c than the prior) is better served by the
fit's own optimum than by nodes spread over the prior.

Result. Validation study, ten seeds: water plateau sweeps right 78.5 % → 94.6 % (per seed 91,
100, 92, 83, 100, 100, 88, 100, 100, 100 %), water Cattaneo-Mindlin 97.5 % → 98.0 %, air
plateau 97.1 % → 98.0 %, air Cattaneo-Mindlin 98.5 % → 99.1 %; μ of the true water plateau
blocks inside ±1.96 printed errors 92.9 % → 94.6 %. With the refined nodes and the stricter
use of the marginal μ (sd of ln μ at most 0.5; issue 27, point 11, review): water plateau 94.6 %,
water Cattaneo-Mindlin 97.8 %, air as before; μ of the water plateau blocks inside ±1.96 errors
92.4 % (2 of 92 blocks fewer: where the marginal μ is not resolved the fit's own μ stands, whose
error at its optimum is too small). With a loop whose μ is not resolved (error above μ) left
out of the model average and of the μ prior (:mod:`contactres.analysis._friction`): water
plateau 96.8 %, water Cattaneo-Mindlin 97.7 %, air plateau 99.0 %; μ of the water plateau
blocks inside ±1.96 errors 93.3 % of 90.

Cost. The nodes of all undecided blocks are evaluated together, in chunks of blocks with one
number of distinct amplitudes (numpy on large arrays), the slopes and the projected solve at
each block's distinct amplitudes only, weighted by their numbers of points (its three ramps
repeat them; :func:`_integrand_in_sets`), the slopes without their derivatives and with G′'s
integral by its power series (:mod:`contactres.analysis._plateau_series`) instead of a Gauss rule or
elliptic integrals: on the analysis of the 1,344-sweep study of
:func:`contactres.measurements.example_study` (14 experiments, 244 undecided blocks) 5.1 × 10⁹
instructions against 14.3 × 10⁹ with the slopes at every point by the fit's own forms (CPU,
side by side on the loaded reference machine: 1.3 s against 3.1 s; on eight copies of that
study with fresh noise, 10,752 sweeps, 6.0 s against 16.6 s), with the same numbers to
rounding (2 ln B within 1.4e-10, μ and its error within 3e-12 relative, on both tables).
Before the nodes were evaluated together, block by block, it cost about twice the former.
Since (issue 31, point 3, second round) G′ and G″ are formed in place, 2 arcsin √(c/x) once
for G′ and the series, the series' terms counted in cells of m 1/16 wide found by truncation
rather than a binary search, and each block's distinct amplitudes found once: on the evidence
of the bundled ``example_sweeps.csv`` (384 sweeps, 69 undecided blocks, 52 with a finite
2 ln B) 0.23-0.25 s of CPU against 0.26-0.28 s, on the seeded study's of
``tests/analysis/test_plateau_evidence.py`` (seeds 0-2, 168 blocks) 0.52-0.59 s against
0.60-0.68 s (best of three, side by side, loaded machine); 2 ln B, μ and its error within
6e-15 relative on the example, 4e-14 on the study.
Since (issue 31, point 3, third round) no node of the rule is evaluated twice (:func:`_over_y`:
a fine node in y on a coarse one, L's fine span where it repeats L π's; a fine node in z
clipped onto an end of the coarse ones, whose row is that node's), 12 % of the evaluations in y
and 11 % of the rows in z of the 10,752 sweeps of issue 31 (eight copies of the study above),
and the projected solve sums over a block's amplitudes as products with the vector of the
weights (:func:`~contactres.analysis._evidence_solve._solve_levels`): there, side by side on the
loaded reference machine, one thread, best of three, 3.2 s of CPU against 4.2 s (3.6 × 10⁹
instructions against 4.5 × 10⁹ on an eighth of its undecided blocks); ``delta_bic`` within 6e-13
relative, μ and its error within 1.2e-14, every class the same, and the bundled example's files the
same byte for byte.
Since (issue 31, point 3, fourth round) rows of nodes of the same bits are evaluated once
(:func:`_slopes`: blocks on one grid of amplitudes under one prior share their nodes), the
blocks of one grid and nodes in z in one chunk (:data:`EVIDENCE_CHUNK_CELLS`): on those 10,752
sweeps, one thread, the evidence 2.7 s of CPU against 7.8 s (best of three, side by side,
loaded machine), every result the same bit for bit.
Since (issue 31, point 3, fifth round) the projected solve sums over the amplitudes only G′,
G″ and their squares against each row's weights and weighted data, the residual sums by the
expanded square (:func:`~contactres.analysis._evidence_solve._solve_levels`), the squares formed on
the distinct rows of :func:`_slopes`: on those 10,752 sweeps, one thread, the evidence 1.4-1.9 s of
CPU against 2.1-2.7 s (best of two, side by side, heavily loaded machine); 2 ln B within 4e-9, μ and
its error within 1.2e-10 relative, every class the same.
Since (issue 31, point 3, sixth round) the call keeps one store of slopes for all its chunks
and passes (:func:`_slopes`: 861 distinct rows of nodes evaluated instead of 2,987), the
projected solve multiplies all rows on one distinct row of slopes in one product (no copy of
the slopes per row; :func:`~contactres.analysis._evidence_solve._solve_levels`), a fine node in z on
a coarse one takes that row, the per-block steps (distinct amplitudes, nodes in z, the combination
over z) run on all blocks at once, and chunks are four times larger (:data:`EVIDENCE_CHUNK_CELLS`):
on the 10,752 sweeps, one thread, the evidence 0.89-1.04 s of CPU against 1.55-1.61 s (best of two,
four times alternated, machine at a load of ~15 on two cores; in instructions, callgrind, on a
sixteenth of its undecided blocks, where fewer rows are shared, 0.64 × 10^9 against 0.77 × 10^9),
every output of ``analyze`` the same bit for bit (354 columns of 21 tables) and the bundled
example's files the same byte for byte.
Since review R24a the store keeps a row only while a later row of its pass may read it
(:class:`SlopeStore`: it kept every row of the call, 2.3 GB on 10^4 sweeps whose amplitudes
differ by 1e-6 from sweep to sweep, where no row is shared) and a chunk's new rows are bounded
(:data:`EVIDENCE_FRESH_CELLS`): there peak RSS of the evidence 152 MB against 2.6 GB, the
shared case's chunks and store reads unchanged, every result the same bit for bit.
Since (issue 31, point 3, seventh round) the node-by-node steps (the projected solve's ratios,
the logarithms, the sort and sums over y) run in blocks of rows that stay in the cache
(:data:`NODE_BLOCK_CELLS`) with fewer temporaries, the rows of nodes are told apart by an
integer of their bits rather than by a sort of their bytes (:func:`_distinct_rows`), no key is
looked up where no group of the pass is shared (:func:`_slopes`), the per-block outputs are
gathered once and not sliced block by block (:func:`_evaluate`, :func:`_levels`): on the 10^4
sweeps of issue 31, one thread, best of three in three rounds alternated with main on a
machine at a load of 12-15 on two cores, the evidence 0.69-0.77 s of CPU against 0.82-0.89 s
(instructions, callgrind, a quarter of its blocks: 1.33 × 10^9 against 1.44 × 10^9; most of
the gain is in memory traffic, which callgrind does not count), with amplitudes jittered by
1e-6 per sweep 14.9-16.3 s against 16.0-17.2 s (two rounds alternated; there the slopes of
:mod:`contactres.analysis._plateau` take most of it; 3.31 × 10^9 instructions against
3.37 × 10^9 on a sixteenth of the blocks); every output the same bit for bit on both tables
and on the bundled example, the evidence's peak RSS on the jittered table 152 MB (151 MB).
(The sums over the amplitudes that the rounds above credit to
:func:`~contactres.analysis._evidence_solve._solve_levels` are formed by
:func:`~contactres.analysis._evidence_solve.level_sums` since this round.)
Since (issue 31, point 3, eighth round) a row's nodes in y are ordered, and their spacings and
edge cells found, once for each pair of peaks (:func:`_y_patterns`; they follow from the peaks
alone) instead of by a sort of every row, the node values are written in place, without the
copies of a tuple into an array (:func:`~contactres.analysis._evidence_solve.node_values`), the
trapezoid's halving is applied to the spacings (:func:`_cells`) and a chunk's points are gathered
without a loop over its blocks (:func:`_rows`); the store of slopes has its own module
(:mod:`contactres.analysis._slope_store`). On the 10^4 sweeps of issue 31, one thread, best of
six, twice alternated with main on a machine at a load of ~15 on two cores, the evidence's user
CPU 0.54-0.57 s against 0.61-0.63 s (system CPU 0.007 s against 0.000: 3,100 page faults a
call; arrays of their own for the five sums the solve uses, so that its loops ran over whole
blocks, took 20,000 more and were left out); every output the same bit for bit on the 10^4
sweeps with shared and with jittered amplitudes, on the 10^5 sweeps, on the bundled example
and on the studies of ``benchmarks/bench_scale.py``.
Since (issue 31, point 3, ninth round) the sums of a block's own points (its weights, C_f, C_Γ,
n) are formed once a block, each row of nodes reading its block's by index
(:func:`_integrand_in_sets`'s ``own``) instead of copies of the points for each of its 13 to 25
rows; the products, the projected solve and the logarithms run segment by segment over whole sets of
rows on one distinct row of slopes (:func:`~contactres.analysis._evidence_solve.segments`), a
segment's sums in arrays of its own rather than scattered into arrays of all rows and read back
strided; the three parts of the values in y are written into one array and read by one flat take
each (a take over two dimensions at once was 7 times slower), θ at the coarse nodes comes from one
row of exponentials, the spans' nodes on coarse nodes from one take a density, and a pass's groups
are found by the integer of their bits (:func:`_distinct_rows`) rather than by a sort of their
bytes. On the 10^5 sweeps of issue 31 (18,351 undecided blocks), one thread, CPU of the
evidence alone (second call of a process) alternated with main on a machine at a load of 7-13
on two cores, three pairs: 2.77-3.00 s against 3.31-3.43 s (12-16 % less; 11,500-12,400 page
faults against 9,000-11,700); every output of ``analyze`` the same bit for bit on those sweeps
(workers 1 and 2), on the 10^4 sweeps (workers 1; workers 2 with 200 bootstrap draws) and, for
the evidence, on the 10^4 sweeps' blocks with amplitudes jittered by 1e-6 (no row shared).
Since (issue 31, point 3, tenth round) the values at the nodes stay where the integrand forms
them, in the order of its sets of rows on one distinct row of slopes (:func:`_integrand_in_sets`),
and each row's nodes are read from there in their order of y by one take (:func:`_sources`),
instead of each segment being scattered back to its rows and L π's values copied to the nodes
of L they stand for; the sums of the squared slopes are formed once for a set whose blocks have
the same numbers of points at each amplitude
(:func:`~contactres.analysis._evidence_solve.same_weights`; on the 10^5 sweeps of issue 31 every
set: 6,838 products instead of 791,909); the node values are written straight into their place and
the masked writes of nodes without a likelihood made only where there is one (none of the 19.2
million nodes there); the trapezoid's terms are formed on the rows laid end to end (:func:`_cells`)
and the spans counted as bytes (:func:`_span`); the sums over y run in the order in which the rows'
coarse values lie in memory. On those 10^5 sweeps (18,351 undecided blocks, one call, 19.2 million
nodes), one thread, CPU of the evidence alone alternated with main on a machine at a load of 5-6 on
two cores, three pairs of two calls each: 2.29-2.55 s against 2.91-3.34 s (~22 % less); instructions
(callgrind) of the 10^4 sweeps' call 2.53 × 10^9 against 2.88 × 10^9; every output of ``analyze``
the same bit for bit on the 10^5 sweeps (workers 2) and on the 10^4 sweeps (workers 1; workers 2
with 200 bootstrap draws). A block's result depends on its own row alone, so the caller deals the
undecided blocks out to the analysis's worker processes where they are many
(``contactres.analysis._blocks``, ``_evidence``: 1,975 blocks of the 10,752 sweeps in two halves of
~2.3 s of CPU each).
Since session 31 the sums of a chunk's points that the projected solve takes (their weights,
C_f, C_Γ, n, the floors of the RSS; the numbers of the blocks' rows of weights among the distinct
ones) are formed once for the chunk (:func:`_block_sums`) and handed to its three to five
evaluations (:func:`_over_y`), each of which formed them again from the same points: on the
undecided blocks of the 10^4 sweeps of issue 31 (one call, one thread) 2.487 × 10^9 instructions
against 2.517 × 10^9 (callgrind, 1.2 % less), on the 10^5 sweeps' call 24.47 × 10^9 against
24.77 × 10^9 (1.2 % less); every output of ``analyze`` the same bit for bit on those sweeps
(workers 1; workers 2 with 200 bootstrap draws) and on the 10^5 sweeps (workers 2).
"""

from __future__ import annotations

import itertools

import numpy as np

from ._amplitude import PLATEAU_MIN_SLOPE
from ._evidence_solve import level_sums, level_weights, node_values, same_weights, segments
from ._loops import CHUNK_CELLS, X_MAX
from ._plateau_slopes import plateau_loop_slopes
from ._slope_store import SlopeStore

__all__ = ["EVIDENCE_NODES", "plateau_log_evidence"]

#: Nodes of the rules: in z = ln(d_c/u_max), 12 uniform over [m - 4s, min(m + 4s, hi)] (m, s: the
#: prior's mean and width; hi: the widest plateau the sweep can show), then 5 more (a third of a
#: step apart) across the two coarse steps around the largest integrand of 2 ln B and, where it lies
#: more than a step away, around that of μ's posterior; in y = ln θ(u_max - d_c), 32 uniform from
#: 10^-2.5 to :data:`~contactres.analysis._loops.X_MAX` (the fitter's bounds; 0.3 apart) and 25
#: across the two coarse steps around the largest integrand L π (0.025 apart), 25 more around that
#: of L alone where it lies elsewhere (μ's moments use L alone); all summed by the trapezoidal rule.
#: Accuracy on the water blocks of the seeded study (seeds 0-2, 169 undecided blocks) against 81
#: uniform nodes in z and 256 + 201 in y: 2 ln B within 0.33, μ within 1.6 %, its error within 6 %;
#: the 12 uniform nodes in z alone, which sum the prior to ~1e-4, left 2 ln B off by up to 2.1 (a
#: likelihood narrower than the prior).
EVIDENCE_NODES = (12, 5, 32, 25)

#: A posterior counts as resolved by the nodes where at least this many of them carry a tenth
#: of its largest value or more (±2.15 widths of a normal density: a node spacing of at most
#: 2.15 widths, at which the trapezoidal rule integrates a normal density to 3 %, 0.06 in
#: 2 ln B); else the block keeps the criterion with the priors at the fit's optimum.
MIN_SPAN_NODES = 3

#: The marginal μ stands for the plateau loop's only where the posterior standard deviation
#: of ln μ is at most this (a relative error of about 50 %; beyond it the moments depend on
#: where the y grid ends) and at most this share of the posterior lies in the first or last
#: coarse y cell (two cells of 31 hold 6.5 % of a flat posterior: more is a posterior piled up
#: against the fitter's bounds).
MU_MARGINAL_MAX_SD = 0.5
MU_MARGINAL_MAX_EDGE = 0.1

#: Nodes x amplitudes of one chunk of :func:`_evaluate`: sixteen times the loop fits' chunk.
#: The per-chunk costs (the sort of its rows, a product per distinct row) are paid for ~800
#: blocks at once where blocks share their rows of nodes (one grid of amplitudes, one prior):
#: on the 10^4 sweeps of issue 31 ~20 % less CPU than with four times (noisy machine, best of
#: two, 0.8-1.2 s against 1.1-1.4 s), the same numbers bit for bit (a row's arithmetic is its
#: own). The largest arrays are the slopes (nodes x amplitudes, a dozen in
#: :func:`~contactres.analysis._plateau_slopes.plateau_loop_slopes`), formed only for the rows
#: not read from the store (:func:`_slopes`, :class:`SlopeStore`) and bounded by
#: :data:`EVIDENCE_FRESH_CELLS`: peak RSS of a process running the evidence of those sweeps,
#: ~120 MB above what it holds before (~195 MB in all), the same as with the store unbounded.
EVIDENCE_CHUNK_CELLS = 16 * CHUNK_CELLS

#: Nodes x amplitudes of the rows of one chunk whose groups (d_c/u_max and amplitudes,
#: :class:`SlopeStore`) the pass has not met before: their slopes are evaluated there. Where
#: blocks share no row (each sweep's amplitudes its own) this, not :data:`EVIDENCE_CHUNK_CELLS`,
#: cuts the chunks: on the 10^4 sweeps of issue 31 with amplitudes jittered by 1e-6 per sweep,
#: peak RSS of the evidence 152 MB (the process held 76 MB before the call), 218 MB at four
#: times the loop fits' chunk (chunks of a041d07's size: 207 MB there), 2.6 GB with the store
#: keeping every row.
EVIDENCE_FRESH_CELLS = 2 * CHUNK_CELLS

#: Nodes (rows x nodes in y) of one block of the node-by-node steps of :func:`_integrand_in_sets`
#: (the projected solve's ratios, the logarithms): 128 kB arrays, a dozen of which stay in the cache
#: where the chunk's (a few MB each) did not: on the 10^4 sweeps of issue 31 those steps
#: ~40 % less CPU, the same numbers bit for bit (each node's arithmetic its own).
NODE_BLOCK_CELLS = 1 << 14


def _integrand(pts, dl, y, own=None):
    """ln L + ln π (as :func:`plateau_log_evidence`, up to a common constant), ln L alone and
    ln μ at the nodes (R, Y) of d_c/u_max ``dl`` (R, 1) and ``y`` (R, Y; (1, Y): the same for
    every row), each row R one block's (``pts``: :func:`_rows`, one row a block; ``own`` (R,):
    each row's block there, by default row r block r): (3, R, Y).

    :func:`_integrand_in_sets`' values (what the evidence evaluates) put back in the order of
    the rows: for the tests, which read a row's values by its place; the evidence itself reads
    them where they are formed."""
    vals = np.empty((3, dl.shape[0], y.shape[1]))
    order = _integrand_in_sets(pts, dl, y, None, vals, own)
    out = np.empty_like(vals)
    for k in range(3):
        out[k][order] = vals[k]
    return out


def _integrand_in_sets(pts, dl, y, store, out, own=None, sums=None):
    """:func:`_integrand_in_sets`'s values of its rows (ln L + ln π, ln L, ln μ) written into
    ``out`` (3, R, Y) in the order in which they are formed, the rows of one distinct row of slopes
    together (:func:`_slopes`): returns that order (R,), ``out[:, i]`` being row ``order[i]``'s.
    ``sums``: :func:`_block_sums` of ``pts``, or None: formed here.

    The model depends on a point only through its amplitude, and a block's sweeps repeat the
    same amplitudes (three ramps: a third of its points distinct), so the slopes and the
    projected solve work on the block's distinct amplitudes: each weighted by its number of
    points, with the means of Δf and ΔΓ there, and the scatter of the points about those means
    added to the residual sums (Σ (v - a)² over a level = Σ (v - v̄)² + n (v̄ - a)², the
    scatter free of cancellation; the sums over the levels by
    :func:`~contactres.analysis._evidence_solve._solve_levels`). The same numbers to rounding at a
    third of the cost of the points.

    Why in that order. Written where they are formed, a segment's values go to one contiguous
    slice of ``out``; the callers read them through the order (:func:`_over_y`) instead of
    having them scattered back to the rows' places first (on the 10^5 sweeps of issue 31 those
    scatters, three arrays of ~19 million nodes, were ~7 % of the evidence's CPU)."""
    if own is None:
        own = np.arange(dl.shape[0])
    lev, umax = pts[0][own], pts[6][own]
    theta = np.exp(y) / (umax * (1.0 - dl))
    slopes = _slopes(
        theta, np.broadcast_to(dl, umax.shape), lev, SlopeStore() if store is None else store
    )
    slopes, squares, inv = slopes
    W, w, per, ids = _block_sums(pts) if sums is None else sums
    # The rows in sets of one distinct row of slopes, the sets one after the other, and each
    # row's block in that order.
    order = np.argsort(inv, kind="stable")
    cut = np.searchsorted(inv[order], np.arange(slopes.shape[0] + 1))
    block = own[order]
    # Sets of rows whose blocks have the same numbers of points at each amplitude (the blocks'
    # distinct rows of w by their bits): their sums of the squares are formed once (level_sums).
    same = same_weights(ids[block], cut)
    # The sums over the amplitudes and the rest node by node in segments of whole sets of
    # ~NODE_BLOCK_CELLS nodes (arrays of their own that stay in the cache; the same bits, each
    # node's arithmetic its own, each set's products of one shape).
    for d0, d1 in segments(cut, max(1, NODE_BLOCK_CELLS // max(theta.shape[1], 1))):
        a, b = cut[d0], cut[d1]
        lin, sq = level_sums(slopes, squares, W, w, block, cut, d0, d1, same)
        node_values(lin, sq, per[block[a:b]], theta[order[a:b]], out[:, a:b])
    return order


def _block_sums(pts):
    """The sums of each block's points that :func:`_integrand_in_sets` takes (``pts``:
    :func:`_rows`): :func:`~contactres.analysis._evidence_solve.level_weights`' three arrays and
    the number of each block's row of weights among the distinct ones (:func:`_distinct_rows`).

    Why apart. They depend on the blocks' points alone, not on the nodes: :func:`_over_y` forms
    them once for a chunk and hands them to each of its three to five evaluations, which formed
    them again each (the same function of the same arrays: the same bits)."""
    W, w, per = level_weights(pts, pts[0].shape[2])
    return W, w, per, _distinct_rows(w)[1]


def _slopes(theta, dl, lev, store):
    """G′ and G″ (R, Y, L) at x = θ·u and c = θ·d_c (d_c = ``dl`` · u_max) of each row's
    ``theta`` (R, Y), ``dl`` (R, 1) and amplitudes ``lev`` (R, 1, L), each distinct row once.

    Why. x and c follow from θ, d_c/u_max and the amplitudes alone, not from the data: blocks
    measured on one grid of amplitudes under one prior on d_c/u_max share their nodes, and
    so their slopes, bit for bit (a point's slopes depend on its own x and c alone). Rows of
    the same bytes (θ, d_c/u_max and the amplitudes: x and c follow from them by the same
    arithmetic) are found by sorting them and evaluated once: on the 10^4 sweeps of issue 31
    (two grids of amplitudes, five priors) 3,019 rows of 87,738: the slopes there 0.6 s of CPU
    instead of 7.1 s (under cProfile, sort included). Where every block has a grid of its own
    the sort and the copies cost ~5 % of the evidence.
    A row's G′, G″ and their squares are kept in ``store`` (a :class:`SlopeStore` made by
    :func:`plateau_log_evidence` for its call, keyed by the row's number of nodes and bytes)
    and taken from there in any later chunk that has the same row: on those sweeps 861
    distinct rows in all instead of 2,987 evaluated chunk by chunk (issue 31, point 3, sixth
    round; every result the same bit for bit). Kept only where a later row of the pass may
    read it, until its group's last chunk (review R24a)."""
    a = np.concatenate([theta, dl, lev[:, 0]], axis=1)
    first, inv = _distinct_rows(a)
    if not (store.rows or store.last):
        # Nothing to read nor to keep (no group of the pass shared, as where each block's
        # amplitudes are its own): no keys looked up (~85,000 on 10^4 such sweeps).
        return (*_new_slopes(theta, dl, lev, first), inv)
    # Keyed by the row's shape too: rows of other numbers of nodes and amplitudes may have
    # the same length.
    keys = [(theta.shape[1], k.tobytes()) for k in _void_rows(a[first])]
    got = [store.rows.get(k) for k in keys]
    new = np.array([g is None for g in got], dtype=bool)
    if new.any():
        both, sq = _new_slopes(theta, dl, lev, first[new])
        at = np.flatnonzero(new).tolist()
        for i, b, q in zip(at, both, sq, strict=True):
            got[i] = (b, q)
            store.keep(keys[i], got[i])
        if new.all():  # in the order of ``keys``: no copy
            return both, sq, inv
    return np.stack([g[0] for g in got]), np.stack([g[1] for g in got]), inv


def _distinct_rows(a):
    """The first of each set of rows of ``a`` (R, C) with the same bytes and each row's set
    (:func:`numpy.unique`'s ``return_index`` and ``return_inverse`` of the rows as bytes).

    Why. A sort of the rows as bytes (memory compares of C doubles) cost ~6 % of the evidence
    of issue 31's 10^4 sweeps; the rows are sorted instead by one integer of their bits
    (rows of the same bytes get the same one; rows that differ in the last bit of one double
    other ones, where sums of the doubles could round to the same), and the sets checked to
    be of rows of the same bytes: where two rows of other bytes share it, the sort of the
    bytes decides."""
    if not a.shape[0]:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    bits = a.view(np.int64)
    # A sum of the bits times odd numbers, modulo 2^64 (numpy's integers wrap): rows of other
    # bytes share it only by chance (~2^-64 a pair).
    odd = (np.arange(a.shape[1], dtype=np.int64) * 0x5851F42D4C957F2D) | 1
    _, first, inv = np.unique((bits * odd).sum(axis=1), return_index=True, return_inverse=True)
    if (bits[first][inv] == bits).all():
        return first, inv
    _, first, inv = np.unique(_void_rows(a), return_index=True, return_inverse=True)
    return first, inv


def _new_slopes(theta, dl, lev, f):
    """G′ and G″ side by side in y, (F, 2Y, L), and their squares, of the rows ``f`` (F,) of
    :func:`_slopes`' arrays."""
    t = theta[f]
    x = t[..., None] * lev[f]
    c = np.broadcast_to((t * dl[f] * lev[f, 0, -1:])[..., None], x.shape)
    g1, g2 = plateau_loop_slopes(x, c, derivatives=False)
    both = np.concatenate([g1, g2], axis=1)
    return both, both * both


def _void_rows(a):
    """The rows of a 2-d array as single items of its bytes (to sort, count and key them)."""
    a = np.ascontiguousarray(a)
    return a.view(np.dtype((np.void, a.itemsize * a.shape[1])))[:, 0]


def _span(e):
    """How many nodes of each row of ``e`` (a density over its nodes, its largest 1) carry a
    tenth of the largest or more (:data:`MIN_SPAN_NODES`).

    Rows of fewer than 256 nodes (all of the rule's) are counted as bytes: the sum of a boolean
    array casts every node to a 64-bit integer first, ~twice the time."""
    hit = e >= 0.1
    if hit.shape[-1] < 256:
        return np.add.reduce(hit.view(np.uint8), axis=-1, dtype=np.uint8).astype(np.intp)
    return hit.sum(axis=-1)


def _cells(f, dx):
    """The terms of the trapezoidal rule along the rows of ``f`` (R, N) with half the node
    spacings ``dx`` (R, N; its last column 0): (R, N), the terms in the first N - 1 columns
    (the last column is none: the rule's sums are over ``[:, :-1]``). :func:`numpy.trapezoid`'s
    arithmetic (halving the spacings, exact, once for all the integrands on one set of nodes,
    rather than each product: the same bits but where a product falls below 2^-1021, then by
    its last subnormal bit, ~5e-324 absolute; none on issue 31's tables).

    Why the last column. Each term is formed on the rows laid end to end, one contiguous pass
    for the sums of neighbours and one for the products, instead of passes over the views
    ``f[:, 1:]`` and ``f[:, :-1]`` (rows of N - 1 at a stride of N, which numpy copies into its
    buffers first: ~4 times the time of the contiguous pass); the pairs across the end of a row
    fall in the last column, times 0."""
    t = np.empty(f.shape)  # C order whatever f's: line is a view of t, not a copy
    line = t.reshape(-1)
    np.add(f.reshape(-1)[1:], f.reshape(-1)[:-1], out=line[:-1])
    line[-1:] = 0.0
    with np.errstate(invalid="ignore"):  # an infinite pair across rows, times 0
        t *= dx
    return t


def _over_y(pts, own, dl, store):
    """ln ∫ L π dy, ln ∫ L dy, the first two moments of ln μ under L, the share of L's mass in
    the first and last coarse cells and the nodes both posteriors span (:func:`_span`), at each
    d_c/u_max ``dl`` (R,) of its row's block ``own`` (R,) (``pts``: :func:`_rows`).

    A node of the rule (:data:`EVIDENCE_NODES`) that another node stands for is not evaluated
    again: the middle and the ends of a fine span (they fall on coarse nodes), all of L's fine
    span where its peak is L π's, and its half towards L π's peak where the two are one coarse
    step apart (it falls on L π's other half). A pair differs by rounding in y at most (the
    trapezoid gives it a cell of zero or rounding width), and :func:`_span` still counts each
    node the rule places, so that the same nodes resolve a posterior: the same numbers to
    rounding for 12 % fewer evaluations (on the 10,752 sweeps of issue 31's study).

    A row's nodes in y follow from the coarse nodes of its two peaks alone, so their order,
    spacings and edge cells are found once for each pair of peaks met (:func:`_y_patterns`), not
    row by row. Each evaluation's values stay where :func:`_integrand_in_sets` writes them, in
    one flat array for all of them, and each row's nodes are read from there in their order of
    y by one take (:func:`_sources`): no values are scattered back to their rows, nor copied
    from L π's nodes to the nodes of L that they stand for."""
    _, _, ny, nf = EVIDENCE_NODES
    K = len(dl)
    dl = dl[:, None]
    coarse = np.linspace(np.log(10.0**-2.5), np.log(X_MAX), ny)
    h = coarse[1] - coarse[0]
    # The fine offsets -h to h: those at multiples of h (``on``: -1, 0, 1 coarse steps) fall on
    # coarse nodes; ``lower`` and ``upper``: the others below and above the middle (odd nf).
    j = np.arange(nf)
    on = (2 * j) % max(nf - 1, 1) == 0
    mid = (nf - 1) // 2 if nf % 2 else -1  # an even nf has no middle node (nor shared halves)
    lower, upper = np.flatnonzero(j[~on] < mid), np.flatnonzero(j[~on] > mid)
    step = np.linspace(-h, h, nf)[~on]
    nfine = step.size
    # ln L π, ln L and ln μ at all nodes evaluated, one flat array each (read by one take each
    # in :func:`_over_y_rows`): the coarse nodes', then the fine ones' around L π's peak, then
    # those of L's evaluated, each part as its :func:`_integrand_in_sets` wrote it; ``base``:
    # where each row's values of each part start. θ of the coarse nodes from one row of y: the
    # exponentials of the same 32 numbers, not of each row's.
    flat = np.empty((3, K * (ny + 2 * nfine)))
    base = np.zeros((K, 3), dtype=np.intp)
    end = 0
    into = (pts, own, dl, store, flat, base, _block_sums(pts))
    everyone = np.arange(K)
    end, first, at_c = _into(into, end, everyone, coarse[None], 0)
    # Fine nodes around the peak of L π (the evidence) and, where it lies elsewhere, around
    # that of L (μ's moments): else μ would follow its prior through the nodes.
    at_p, at_l = np.argmax(first[0], axis=1)[at_c], np.argmax(first[1], axis=1)[at_c]
    fine_p = np.clip(coarse[at_p][:, None] + step, coarse[0], coarse[-1])
    end = _into(into, end, everyone, fine_p, 1)[0]
    fine_l = np.clip(coarse[at_l][:, None] + step, coarse[0], coarse[-1])
    side = at_l - at_p
    # L's nodes that L π's stand for (their values are read from L π's: :func:`_sources`).
    shared = [(side == 0, slice(None), slice(None))]
    if mid > 0:  # one step up: L's lower half is L π's upper half; one step down the reverse
        shared += [(side == 1, lower, upper), (side == -1, upper, lower)]
    for rows, mine, theirs in shared:
        r = np.flatnonzero(rows)[:, None]
        fine_l[r, mine] = fine_p[r, theirs]
    # The rest of L's nodes: all of them two steps apart or more, the other half one apart
    # (an even nf shares no half: all of them one step apart or more).
    far = np.flatnonzero(np.abs(side) >= (2 if mid > 0 else 1))
    end = _into(into, end, far, fine_l[far], 2)[0]
    if mid > 0:
        for sign, mine in ((1, upper), (-1, lower)):
            r = np.flatnonzero(side == sign)
            end = _into(into, end, r, fine_l[r[:, None], mine[None, :]], 2)[0]
    pattern, order, dy, edge = _y_patterns(at_p, at_l, fine_p, fine_l, coarse)
    src, col = _sources(pattern, order, side, lower, upper, mid)
    # The sums over y row by row, in blocks of rows of ~NODE_BLOCK_CELLS nodes (arrays that
    # stay in the cache; the same bits, each row's sums its own), the rows in the order in
    # which their values at the coarse nodes lie in ``flat``: those are read in order, not
    # from all over the chunk's values (on the 10^5 sweeps of issue 31, six pairs alternated
    # on a loaded machine, the evidence ~4 % less CPU in all, 9 of 12 calls less).
    out = [np.empty(K), np.empty(K), np.empty(K), np.empty(K), np.empty(K), np.empty(K, int)]
    rows = max(1, NODE_BLOCK_CELLS // order.shape[1])
    seq = np.argsort(base[:, 0], kind="stable")
    for start in range(0, K, rows):
        b = seq[start : start + rows]
        # Each row's pattern's arrays by whole rows (numpy.take along the first axis: copies
        # of rows, where an index array copies item by item), then where each node's values
        # are: its part's start in the row's ``base`` plus its column.
        p = pattern[b]
        part = np.take(src, p, axis=0)
        part += np.arange(0, 3 * p.size, 3)[:, None]
        at = np.take(base[b].reshape(-1), part)
        at += np.take(col, p, axis=0)
        dy_b, edge_b = np.take(dy, p, axis=0), np.take(edge, p, axis=0)
        got_b = _over_y_rows(flat, at, dy_b, edge_b, at_p[b], at_l[b], base[b, 0])
        for o, v in zip(out, got_b, strict=True):
            o[b] = v
    return tuple(out)


def _into(into, end, rows, y, k):
    """Evaluate :func:`_over_y`'s rows ``rows`` (R,) at their nodes ``y`` (R or 1, Y) into its
    flat arrays from ``end`` on, in :func:`_integrand_in_sets`' order, and note where each row's
    values start in column ``k`` of its ``base`` (``into``: its points, the rows' blocks and
    d_c/u_max, the store of slopes, the flat arrays, ``base`` and the sums of the blocks' points,
    :func:`_block_sums`, formed once for all the chunk's evaluations): the end of what is written,
    the values (3, R, Y) and each row's place among them."""
    pts, own, dl, store, flat, base, sums = into
    R, Y = rows.size, y.shape[1]
    vals = flat[:, end : end + R * Y].reshape(3, R, Y)
    at = np.arange(R)
    if R and Y:
        at[_integrand_in_sets(pts, dl[rows], y, store, vals, own[rows], sums)] = np.arange(R)
    base[rows, k] = end + at * Y
    return end + R * Y, vals, at


def _sources(pattern, order, side, lower, upper, mid):
    """For each pattern of nodes in y (:func:`_y_patterns`: ``pattern`` (R,) each row's, ``order``
    (P, N) its nodes' order), where :func:`_over_y` holds each node's values, in the nodes'
    order of y: which part's values (0 the coarse nodes', 1 the fine ones' around L π's peak,
    2 those evaluated for L) and which column of that part (P, N) each. ``side`` (R,): the
    coarse steps from L π's peak to L's; ``lower``, ``upper``, ``mid``: :func:`_over_y`'s.

    Where L's peak is L π's all of L's fine nodes are L π's; one step up (down), L's lower
    (upper) half is L π's upper (lower) half and its other half was evaluated alone, its
    columns in the order of that half; elsewhere L's nodes were evaluated, all in order."""
    P, N = order.shape
    nfine = lower.size + upper.size  # the fine nodes off the coarse ones: both halves
    ny = N - 2 * nfine
    sides = np.zeros(P, dtype=side.dtype)
    sides[pattern] = side  # one side a pattern: it follows from the two peaks
    src = np.repeat(np.array([0, 1, 2]), [ny, nfine, nfine])[None].repeat(P, axis=0)
    col = np.concatenate([np.arange(ny), np.arange(nfine), np.arange(nfine)])[None]
    col = col.repeat(P, axis=0)
    src[sides == 0, ny + nfine :] = 1
    if mid > 0:
        for sign, mine, theirs in ((1, lower, upper), (-1, upper, lower)):
            r = np.flatnonzero(sides == sign)[:, None]
            src[r, ny + nfine + mine] = 1
            col[r, ny + nfine + mine] = theirs
            other = upper if sign == 1 else lower
            col[r, ny + nfine + other] = np.arange(other.size)
    return np.take_along_axis(src, order, axis=1), np.take_along_axis(col, order, axis=1)


def _y_patterns(at_p, at_l, fine_p, fine_l, coarse):
    """Each row's pattern of nodes in y (R,) and, per pattern, the order of its nodes (the
    coarse ones, those around L π's peak, L's: ascending, stable), their spacings and which
    spacings lie in the first or last coarse cell, 1 or 0, each with a last column 0
    (:func:`_cells`) (:func:`_over_y`'s ``fine_p``, ``fine_l``: the fine nodes around the peaks at
    the coarse nodes ``at_p``, ``at_l`` (R,)).

    Why. The nodes of a row follow from its peaks alone (a few hundred pairs among 10^4-10^5
    rows): sorted once a pair, the same order as row by row, bit for bit."""
    _, first, pattern = np.unique(at_p * coarse.size + at_l, return_index=True, return_inverse=True)
    y = np.concatenate(
        [np.broadcast_to(coarse, (first.size, coarse.size)), fine_p[first], fine_l[first]], axis=1
    )
    order = np.argsort(y, axis=1, kind="stable")
    y = np.take_along_axis(y, order, axis=1)
    # Spacings and edge cells (R, N), the last column 0: :func:`_cells`' layout.
    dy, edge = np.zeros(y.shape), np.zeros(y.shape)
    dy[:, :-1] = np.diff(y, axis=1) / 2.0
    edge[:, :-1] = (y[:, 1:] <= coarse[1]) | (y[:, :-1] >= coarse[-2])
    return pattern.ravel(), order, dy, edge


def _over_y_rows(flat, at, dy, edge, at_p, at_l, at_c):
    """:func:`_over_y`'s outputs of its rows from :func:`_integrand_in_sets`'s values at all nodes
    evaluated (``flat`` (3, T): :func:`_over_y`'s), where each row's nodes are there in their
    order of y (``at`` (R, N): :func:`_sources`), half their spacings and which spacings lie in
    the first or last coarse cell, 1 or 0 (R, N, the last column 0: :func:`_y_patterns`); ``at_p``,
    ``at_l``: the coarse nodes of the peaks of L π and L; ``at_c``: where each row's values at
    the coarse nodes start in ``flat``."""
    _, _, ny, nf = EVIDENCE_NODES
    j = np.arange(nf)
    on = (2 * j) % max(nf - 1, 1) == 0
    # Each row in its order of y (one take each).
    lp, ll, mu = (np.take(v, at) for v in flat)
    top_p = lp.max(axis=1, keepdims=True)
    top_l = ll.max(axis=1, keepdims=True)
    with np.errstate(invalid="ignore"):
        lp -= top_p
        ll -= top_l
        ep, el = np.exp(lp, out=lp), np.exp(ll, out=ll)
    # A row without a finite node (its top -inf) is NaN throughout: no mass. Elsewhere every
    # value is in [0, 1].
    ep[~np.isfinite(top_p[:, 0])] = 0.0
    el[~np.isfinite(top_l[:, 0])] = 0.0
    # L's cells: the terms of its trapezoidal sum, also its mass in the edge cells (the same
    # numbers as 0.5 (el_i + el_i+1) dy, halving being exact, but for the last bit in the
    # subnormal range, ~1e-308 of zl).
    cell = _cells(el, dy)
    with np.errstate(invalid="ignore", divide="ignore"):
        log_p = np.log(_cells(ep, dy)[:, :-1].sum(axis=1)) + top_p[:, 0]
        zl = cell[:, :-1].sum(axis=1)
        log_l = np.log(zl) + top_l[:, 0]
        m1 = _cells(el * mu, dy)[:, :-1].sum(axis=1) / zl
        m2 = _cells(el * mu**2, dy)[:, :-1].sum(axis=1) / zl
        cell *= edge
        share = cell[:, :-1].sum(axis=1) / zl
    # The nodes on coarse nodes count as the rule places them: -1, 0, 1 steps from each peak
    # (only there their densities are needed: each an exponential of its own), of both
    # densities and both peaks in one take.
    steps = (2 * j[on]) // max(nf - 1, 1) - 1
    at_on = np.concatenate([at_p[:, None] + steps, at_l[:, None] + steps], axis=1)
    at_on = np.clip(at_on, 0, ny - 1, out=at_on) + at_c[:, None]
    span = []
    for v, e_all, top in ((flat[0], ep, top_p), (flat[1], el, top_l)):
        with np.errstate(invalid="ignore"):
            # NaN (a row without a finite node) counts as no node
            e = np.exp(np.take(v, at_on) - top)
        span.append(_span(e_all) + _span(e))
    return log_p, log_l, m1, m2, share, np.minimum(*span)


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
    (3, B): 2 ln B (positive: the data favour the plateau), and μ under the plateau loop with
    d_c marginalised, exp of the posterior mean of ln μ, with its error μ times the posterior
    standard deviation of ln μ. That posterior is the likelihood's in y times the pooled
    amplitude prior in z (not the prior on μ): its weights over d_c are the prior's, not the
    block's own points' alone, so a block whose plateau lies far from the others' gets a μ and
    an error from where the prior puts d_c (module docstring, Limits). NaN where there is no
    amplitude prior, where the prior puts no plateau the sweep can show (the fit's criterion
    stays) and where the nodes do not resolve a posterior (:data:`MIN_SPAN_NODES`); μ also
    where it is not resolved (:data:`MU_MARGINAL_MAX_SD`, :data:`MU_MARGINAL_MAX_EDGE`)
    """
    u, df, dg, w = (np.asarray(a, dtype=float) for a in (u, df, dg, w))
    B = u.shape[0]
    out = np.full((3, B), np.nan)
    m2, v2 = (np.asarray(a, dtype=float) for a in ratio_prior)
    sig = np.asarray(sigma, dtype=float)
    nz, nzf = EVIDENCE_NODES[:2]
    todo = np.isfinite(m2) & np.isfinite(v2) & (v2 > 0)
    todo &= np.ones(B, bool) if rows is None else np.asarray(rows, bool)
    todo &= (sig > 0).all(axis=0)
    # Each block's distinct amplitudes and its points there (:func:`_levels`).
    jb = np.flatnonzero(todo)
    per_block = _levels(u, df, dg, w, jb)
    jb = jb[np.array([per_block[b][0].size > PLATEAU_MIN_SLOPE for b in jb], dtype=bool)]
    # The widest plateau that leaves PLATEAU_MIN_SLOPE distinct amplitudes above it: the nodes
    # end there (beyond it the prior's mass counts against the plateau). Where the prior puts
    # (almost) no plateau below it there is nothing to integrate: NaN.
    hi = np.array([np.log(per_block[b][0][-PLATEAU_MIN_SLOPE] / per_block[b][0][-1]) for b in jb])
    s = np.sqrt(v2[jb])
    lo = m2[jb] - 4 * s
    keep = hi > lo
    jb, hi, s, lo = jb[keep], hi[keep], s[keep], lo[keep]
    J = jb.size
    Z = np.linspace(lo, np.minimum(m2[jb] + 4 * s, hi), nz, axis=1).reshape(J, nz)
    args = (per_block, sig, mu_prior, to_mu)
    store = SlopeStore()  # the slopes of rows of nodes read again, for both passes
    coarse = [
        v.reshape(J, nz + 1)
        for v in _evaluate(args, list(zip(jb.tolist(), Z, strict=True)), True, store)
    ] or [np.empty((0, nz + 1))] * 5 + [np.empty((0, nz + 1), dtype=int)]
    # Fine nodes in z across the two coarse steps around the peak of the integrand of 2 ln B
    # and around that of μ's posterior (where it lies elsewhere): 12 nodes over the prior
    # resolve the prior, not a likelihood narrower than it.
    prior = -0.5 * (Z - m2[jb, None]) ** 2 / v2[jb, None]
    peaks = [np.argmax(v[:, :-1] + prior, axis=1) for v in coarse[:2]]
    two = np.abs(peaks[1] - peaks[0]) > 1  # μ's peak outside the fine span of the evidence's
    dz = Z[:, 1] - Z[:, 0]
    step = np.linspace(-dz, dz, nzf + 2, axis=1).reshape(J, nzf + 2)[:, 1:-1]
    at = np.arange(J)
    zf = np.clip(
        np.concatenate([Z[at, p][:, None] + step for p in peaks], axis=1), Z[:, :1], Z[:, -1:]
    )
    # A fine node on a coarse node (the middle of a fine span, where its offset comes out 0;
    # one clipped onto an end of the coarse nodes, a peak there) is that coarse node, whose row
    # is evaluated already (a block's row depends on its d_c alone): taken from there, bit for
    # bit (on issue 31's 10^4 sweeps 6,146 fine rows evaluated instead of 7,197 with the ends
    # alone, 3 % of all rows).
    used = np.arange(2 * nzf) < np.where(two, 2 * nzf, nzf)[:, None]
    same = zf[:, :, None] == Z[:, None, :]
    on = same.any(axis=2) & used
    new = used & ~on
    fine_jobs = [(b, zz[k]) for b, zz, k in zip(jb.tolist(), zf, new, strict=True)]
    fine = _evaluate(args, fine_jobs, False, store) if nzf and J else []
    f = []
    for k, c in enumerate(coarse):
        v = np.zeros((J, 2 * nzf), dtype=c.dtype)
        if fine:
            v[new] = fine[k]
        v[on] = np.take_along_axis(c, np.argmax(same, axis=2), axis=1)[on]
        f.append(v)
    # Blocks of one number of fine nodes together: each row as the block's alone.
    for n_f in sorted({nzf, 2 * nzf}):
        g = np.flatnonzero(used.sum(axis=1) == n_f)
        if not g.size:
            continue
        zz = np.concatenate([Z[g], zf[g, :n_f]], axis=1)
        order = np.argsort(zz, axis=1, kind="stable")
        vals = [
            np.take_along_axis(np.concatenate([c[g, :-1], v[g, :n_f]], axis=1), order, axis=1)
            for c, v in zip(coarse, f, strict=True)
        ]
        zz = np.take_along_axis(zz, order, axis=1)
        out[:, jb[g]] = _combine(zz, coarse[0][g, -1], vals, m2[jb[g]], v2[jb[g]])
    return out


def _evaluate(args, jobs, zero, store):
    """:func:`_over_y` at the nodes ``z`` of every job (block, z), and at d_c = 0 after them if
    ``zero``: each of :func:`_over_y`'s outputs for the rows of all jobs, one array each, the
    jobs in their order and each job's rows in its order of z ([] without jobs).

    All blocks' nodes in a few calls (numpy on large arrays), in chunks of them
    (:data:`EVIDENCE_CHUNK_CELLS`, :data:`EVIDENCE_FRESH_CELLS`). Blocks of one number of distinct
    amplitudes go together: no slopes at padding; within those, blocks of one grid of
    amplitudes and one set of nodes in z follow each other, so that they share a chunk and
    with it their slopes (:func:`_slopes`)."""
    per_block, sig, mu_prior, to_mu = args
    if not jobs:
        return []
    same: dict[int, list] = {}
    for k, job in enumerate(jobs):
        same.setdefault(per_block[job[0]][0].size, []).append((k, *job))
    nrow = max(1, max(z.size for _, z in jobs) + zero)
    step = max(1, EVIDENCE_CHUNK_CELLS // (nrow * EVIDENCE_NODES[2] * max(same)))
    cap = EVIDENCE_FRESH_CELLS // (EVIDENCE_NODES[2] * max(same))
    chunks, ends, plan = [], [], []
    for group in same.values():
        # Blocks of one grid of amplitudes and one set of nodes in z next to each other: in one
        # chunk their rows share their slopes (:func:`_slopes`).
        group.sort(key=lambda job: (per_block[job[1]][0].tobytes(), job[2].tobytes()))
        # d_c/u_max of each job's rows, all jobs' in one array (0 after each job's if ``zero``).
        sizes = [z.size + zero for _, _, z in group]
        ends_g = np.cumsum(sizes)
        dl = np.zeros(ends_g[-1])
        at_z = np.ones(dl.size, dtype=bool)
        if zero:
            at_z[ends_g - 1] = False
        dl[at_z] = np.exp(np.concatenate([z for _, _, z in group]))
        # Each row's group (d_c/u_max, amplitudes; :class:`SlopeStore`) and whether it is the
        # first of its group in the pass: its slopes are evaluated, the others' may be read.
        # (The groups found as the slopes' rows are, by an integer of their bits: a sort of
        # their bytes cost ~4 % of the evidence of the 10^5 sweeps of issue 31.)
        lev = np.repeat(np.stack([per_block[b][0] for _, b, _ in group]), sizes, axis=0)
        lev = np.c_[dl, lev]
        first, inv = _distinct_rows(lev)
        count = np.bincount(inv, minlength=first.size)
        key = _void_rows(lev[first])
        fresh = np.zeros(lev.shape[0], dtype=int)
        fresh[first] = 1
        fresh = np.add.reduceat(fresh, np.cumsum([0, *sizes[:-1]])).tolist()
        # At most ``step`` blocks a chunk, and at most ``cap`` rows of groups met first
        # (:data:`EVIDENCE_CHUNK_CELLS`, :data:`EVIDENCE_FRESH_CELLS`).
        cuts, blocks, new = [0], 0, 0
        for j, n in enumerate(fresh):
            if blocks and (blocks == step or new + n > cap):
                cuts.append(j)
                blocks, new = 0, 0
            blocks, new = blocks + 1, new + n
        cuts.append(len(group))
        at = len(chunks) + np.repeat(np.arange(len(cuts) - 1), np.diff(cuts))
        plan.append((key, inv, count, np.repeat(at, sizes)))
        for a, b in itertools.pairwise(cuts):
            chunks.append(group[a:b])
            ends.append((dl[ends_g[a] - sizes[a] : ends_g[b - 1]], sizes[a:b]))
    # The store keeps what a later row of the pass reads again (:class:`SlopeStore`).
    store.plan(plan)
    del plan, key, lev, inv  # the keys of the whole pass: not held through it
    outs, done = [], []
    for i, (chunk, (dl, sizes)) in enumerate(zip(chunks, ends, strict=True)):
        own = np.repeat(np.arange(len(chunk)), sizes)
        pts = _rows(per_block, sig, mu_prior, to_mu, [b for _, b, _ in chunk])
        outs.append(_over_y(pts, own, dl, store))
        store.done(i)
        done.extend(k for k, _, _ in chunk)
    # The rows in the order of the jobs, each job's in its order of z: a stable sort of the
    # rows' jobs (one gather per output instead of a slice per job and output).
    per_job = np.array([z.size + zero for _, z in jobs])[done]
    back = np.argsort(np.repeat(done, per_job), kind="stable")
    return [np.concatenate(v)[back] for v in zip(*outs, strict=True)]


def _levels(u, df, dg, w, blocks):
    """Each block's distinct amplitudes of its points (``u``, ``w`` > 0; ``blocks``: which rows),
    the number of points at each, the means of Δf ``df`` and ΔΓ ``dg`` there and the scatter
    Σ (v - v̄)² of each channel's points about them: a dict of tuples by block, once per call.

    All blocks at once, with each block's numbers as from its points alone, bit for bit: the
    sums at each amplitude by one :func:`numpy.bincount` over all blocks' points in their
    order (each bin summed in the order of its points, as for a block alone), the scatter
    summed row by row over blocks of one number of points (a row's sum as its own)."""
    data = w[blocks] > 0
    n = data.sum(axis=1)
    uu = np.where(data, u[blocks], np.inf)  # padding last
    order = np.argsort(uu, axis=1, kind="stable")
    su = np.take_along_axis(uu, order, axis=1)
    first = np.arange(u.shape[1]) < n[:, None]
    first[:, 1:] &= su[:, 1:] != su[:, :-1]
    n_lev = first.sum(axis=1)
    # Each point's amplitude, numbered across all blocks.
    index = np.empty(data.shape, dtype=np.intp)
    shift = np.concatenate([[0], np.cumsum(n_lev)[:-1]])[:, None]
    np.put_along_axis(index, order, np.cumsum(first, axis=1) - 1 + shift, axis=1)
    index = index[data]
    count = np.bincount(index, minlength=n_lev.sum())
    means, scatter = [], []
    for v in (df, dg):
        vv = v[blocks][data]
        mean = np.bincount(index, weights=vv, minlength=count.size) / count
        means.append(mean)
        sq = (vv - mean[index]) ** 2
        total = np.empty(blocks.size)
        ends = np.cumsum(n)
        for m in np.unique(n):
            rows = np.flatnonzero(n == m)
            at = (ends[rows] - m)[:, None] + np.arange(m)
            total[rows] = sq[at].sum(axis=1)
        scatter.append(total)
    # Each block's slices of the flat arrays (views, as numpy.split's, without its per-piece
    # overhead: ~0.1 s of CPU on 10^4 sweeps).
    ends = np.cumsum(n_lev).tolist()
    flat = (su[first], count, *means)
    return {
        b: (*(a[e - m : e] for a in flat), sf, sg)
        for b, e, m, sf, sg in zip(
            blocks.tolist(), ends, n_lev.tolist(), *(v.tolist() for v in scatter), strict=True
        )
    }


def _rows(per_block, sig, mu_prior, to_mu, blocks):
    """The points of ``blocks`` as :func:`_integrand_in_sets` takes them, one row (1, ...) a block:
    its distinct amplitudes (padded with u_max), the number of points at each (padding 0), the
    means of Δf and ΔΓ there, the scatter Σ (v - v̄)² of each channel's points about them
    (``per_block``: :func:`_levels` of each block), u_max, the weights 1/σ² of Δf and ΔΓ, the prior
    on ln μ and to_mu."""
    # All blocks' numbers in one flat array each, gathered into rows (no loop over blocks).
    got = [per_block[b] for b in blocks]
    size = np.array([g[0].size for g in got])
    L = int(size.max())
    at = np.minimum(np.arange(L), size[:, None] - 1) + (np.cumsum(size) - size)[:, None]
    levs = np.concatenate([g[0] for g in got])[at][:, None]  # padded with u_max
    per = np.stack([np.concatenate([g[j] for g in got])[at] for j in (1, 2, 3)])
    per[:, np.arange(L) >= size[:, None]] = 0.0  # points, mean Δf, mean ΔΓ at each amplitude
    per = per[:, :, None]
    scatter = np.array([[g[4] for g in got], [g[5] for g in got]])[..., None]
    col = [levs[:, 0, -1:], 1.0 / sig[0, blocks, None] ** 2, 1.0 / sig[1, blocks, None] ** 2]
    col += [np.asarray(a, dtype=float)[blocks, None] for a in (*mu_prior, to_mu)]
    return levs, *per, *scatter, *col


def _combine(z, l0, rows, mean, var):
    """2 ln B and μ (3, J) of J blocks from their ``rows`` of :func:`_over_y` (J, N) each at
    the nodes ``z`` (J, N) of ln(d_c/u_max), ascending in each row, and ``l0`` (J,),
    ln ∫ L π dy at d_c = 0; ``mean``, ``var`` (J,): the prior on z. Left NaN where a posterior
    spans fewer than :data:`MIN_SPAN_NODES` nodes in z or, where it carries weight, in y: then
    the nodes do not resolve it. Each row as the block's alone (the sums along rows)."""
    out = np.full((3, z.shape[0]), np.nan)
    lp, ll, mu1, mu2, share, span = rows
    mean, var = mean[:, None], var[:, None]
    prior = -0.5 * (z - mean) ** 2 / var - 0.5 * np.log(2 * np.pi * var)
    t, q = lp + prior, ll + prior
    top, topq = t.max(axis=1, keepdims=True), q.max(axis=1, keepdims=True)
    ok = (np.isfinite(top) & np.isfinite(l0[:, None]) & np.isfinite(topq))[:, 0]
    with np.errstate(invalid="ignore"):
        wt, wq = np.exp(t - top), np.exp(q - topq)
    carry = (wt >= 0.1) | (wq >= 0.1)
    resolved = np.minimum(_span(wt), _span(wq))
    resolved = np.minimum(resolved, np.where(carry, span, np.iinfo(span.dtype).max).min(axis=1))
    ok &= resolved >= MIN_SPAN_NODES
    with np.errstate(invalid="ignore", divide="ignore"):
        two_ln_b = 2.0 * (np.log(np.trapezoid(wt, z, axis=1)) + top[:, 0] - l0)
        norm = np.trapezoid(wq, z, axis=1)
        m = np.trapezoid(wq * mu1, z, axis=1) / norm
        sd = np.sqrt(np.maximum(np.trapezoid(wq * mu2, z, axis=1) / norm - m**2, 0.0))
        edge = np.trapezoid(wq * share, z, axis=1) / norm
    out[0] = np.where(ok, two_ln_b, np.nan)
    # Else the fit's own μ stays.
    mu_ok = ok & (sd <= MU_MARGINAL_MAX_SD) & (edge <= MU_MARGINAL_MAX_EDGE)
    out[1] = np.where(mu_ok, np.exp(m), np.nan)
    out[2] = np.where(mu_ok, np.exp(m) * sd, np.nan)
    return out
