"""The slip integral of the plateau loop's in-phase slope by its power series (no quadrature).

Why. The evidence of the plateau (:mod:`contactres.analysis._plateau_evidence`) evaluates the
loop's slopes G′, G″ (:func:`contactres.analysis._plateau_slopes.plateau_loop_slopes`) at some 10⁴
nodes per block, and the plateau fit (:func:`contactres.analysis._plateau.fit_plateau_loops`)
evaluates them with their derivatives at every Levenberg-Marquardt step, whose integrals of
J's derivatives :func:`slip_integrals_series` sums from the same series.
Their cost was that of the integral J below: a 16-point Gauss-Legendre
rule (16 cosines, sines and square roots per point, ~530 ns) where m = x/e < 0.1, Legendre's
incomplete elliptic integrals (~350 ns, scipy's, when this series was written) elsewhere. The
series here costs ~70 ns per point wherever m = min(x, e)/max(x, e) < 1/2 (80 % of the
evidence's slipping points) and is as accurate as the rule, more so than the elliptic form,
which loses ~1e-13 of x² to cancellation at 0.1 < m < 1/2 and more at x >> e
(``tests/analysis/test_plateau_series.py`` checks all three against adaptive quadrature).
The elliptic form now takes its two tails from Carlson's R_F and R_D
(:mod:`contactres.analysis._carlson`: the tails themselves without cancellation, ~1200
instructions a point with the rest of the closed form against ~2400 through scipy's
integrals; the closed form's combination of the tails still loses the digits above), so the
cut-off between the two below was chosen against the older, dearer form and may no longer be
the cheapest.

How. J = ∫_c^b √(d(x - d)(e - d)) dd, b = min(x, e), e = c + 3/2 (paper 2, Eqs. 4-6: the
integral of :func:`~contactres.analysis._plateau_slopes.plateau_loop_slopes`), is symmetric in x and
e: let r = min(x, e) (= b) and A = max(x, e) - r/2. With d = r(1 - cos φ)/2 (φ from
φ_c = 2 arcsin √ρ, ρ = c/r, to π; √(d(r - d)) dd = r² sin²φ dφ/4)

    J = (r²/4) √A ∫_φ_c^π sin²φ √(1 + q cos φ) dφ,    q = r/(2A) = m/(2 - m) < 1.

The binomial series √(1 + q cos φ) = Σ b_k q^k cosᵏφ, b_k = binom(1/2, k), then gives
J = (r²/4) √A Σ b_k q^k T_k with T_k = ∫_φ_c^π sin²φ cosᵏφ dφ: T_0 = (π - φ_c)/2 +
sin φ_c cos φ_c/2, T_1 = -sin³φ_c/3 and, from d/dφ (sin³φ cosᵏ⁻¹φ) = (k + 2) sin²φ cosᵏφ -
(k - 1) sin²φ cosᵏ⁻²φ,

    T_k = [(k - 1) T_{k-2} - sin³φ_c cosᵏ⁻¹φ_c]/(k + 2),

a recursion whose factor (k - 1)/(k + 2) < 1 damps rounding errors (forward-stable). Here
sin φ_c = 2√(ρ(1 - ρ)) and cos φ_c = 1 - 2ρ: no trigonometric function per point. As
|T_k| <= ∫_0^π sin²φ |cos φ|ᵏ dφ = B(3/2, (k + 1)/2) (Euler's beta function) and both it and
|b_k| fall with k, the terms beyond the K-th sum to at most
|b_{K+1}| B(3/2, (K + 2)/2) q^{K+1}/(1 - q) of (r²/4)√A.
"""

from __future__ import annotations

from numbers import Integral

import numpy as np

from ..errors import ContactresInputError

__all__ = [
    "ALL_CELLS",
    "SERIES_CELLS",
    "SERIES_MAX_M",
    "SERIES_TERMS",
    "SERIES_TIERS",
    "slip_integral_series",
    "slip_integrals_ordered",
    "slip_integrals_series",
]

#: The series' tiers: m = min(x, e)/max(x, e) in cells 1/16 wide, a point's tier the cell
#: floor(16 m) (exact: 16 m is m with another exponent, so that no point near a bound goes
#: to its neighbour's; a binary search of the bounds cost 10-15 ns per point, the
#: truncation ~1). The cells stop at 7/8 (the series' domain): the next would
#: sum 200 terms. Cells 1/32 wide would sum fewer terms a point; measured when each group of
#: cells had its own loop over its terms, their extra numpy calls cost more than that saved on
#: the bundled example. Since the groups share one loop (:func:`_series`) they cost no calls of
#: their own: finer cells may now pay, at a change of the sums' last bits (not measured).
SERIES_CELLS = 16

#: The terms (k = 0..K) summed in each cell of m (:data:`SERIES_CELLS`): the fewest for which
#: the rest of the series (module docstring) stays below 1e-17 of (r²/4)√A (the scale of J and
#: of the loop's G′ alike) at the cell's largest q = m/(2 - m)
#: (tests/analysis/test_plateau_series.py checks the bound): under the rounding of the sum. A
#: point's terms follow from its own m alone, so that its J does not depend on the points
#: evaluated with it. Each term costs ~8 instructions per point against ~2400-3000 for the
#: elliptic form through scipy's incomplete integrals, which the series thus beat up to
#: K ~ 300 (m ~ 0.95); against the ~1200 of the Carlson form used since, the break-even is
#: nearer K ~ 150. Four
#: tiers (m below 0.1, 0.5, 0.8, 0.9: 10, 26, 67, 129 terms) summed more terms at most
#: points, with the same numbers to rounding (the series over uniform m in (0, 7/8) costs a
#: third less CPU in these cells).
SERIES_TERMS = (9, 11, 13, 15, 17, 20, 23, 26, 30, 36, 43, 54, 71, 104)

#: Points per call of the series' loop over its terms: its ~7 arrays of that many doubles stay
#: in the core's 2 MB cache, and the calls' own cost stays small (~20 µs a block at 20 terms,
#: against ~1 ms of arithmetic). The same numbers as one call over all of the points (each
#: point's terms are its own), at half the CPU of the 10⁵-point calls of the evidence. Since
#: one loop serves all tiers (a block's points sorted by terms, each term's passes over the
#: prefix still summing), J alone (every cell a group of its own) takes 61 % fewer
#: instructions on the points of the plateau fits of issue 31's 10⁴ sweeps (every 8th call),
#: J with the derivatives' integrals in the fit's two groups 3 % fewer on its largest call
#: (35,435 points) and 12 % on one of 156 (callgrind): the numbers bit for bit the same.
SERIES_BLOCK = 32768

#: (largest m, terms) of each cell, m ascending.
SERIES_TIERS = tuple(((j + 1) / SERIES_CELLS, k) for j, k in enumerate(SERIES_TERMS))

#: The series' domain: m below this.
SERIES_MAX_M = SERIES_TIERS[-1][0]

#: Each cell of :data:`SERIES_TIERS` a group of its own (:func:`slip_integrals_series`).
ALL_CELLS = tuple(range(1, len(SERIES_TIERS) + 1))


def slip_integral_series(x, c, phi=None) -> np.ndarray:
    """J = ∫_c^b √(d(x - d)(e - d)) dd, e = c + 3/2, b = min(x, e), by its power series
    (module docstring).

    Parameters
    ----------
    x, c : 1-d arrays, the loop's dimensionless amplitude κu0/(μF_N) and plateau κd_c/(μF_N),
        with c < b and min(x, e) < :data:`SERIES_MAX_M` · max(x, e) (the series' domain)
    phi : 2 arcsin √(c/x) at each point, if the caller has it (the plateau's slopes need it
        too): the angle φ_c of the points with x <= e (computed here if None, and where x > e)

    Returns
    -------
    J, dimensionless (the integral of
    :func:`contactres.analysis._plateau_slopes.plateau_loop_slopes`; NaN outside the domain)
    """
    return _by_tiers(x, c, phi, ALL_CELLS, False)[0]


def slip_integrals_series(x, c, phi=None, groups=ALL_CELLS) -> tuple[np.ndarray, ...]:
    """J of :func:`slip_integral_series` (the same numbers, bit for bit) with the two integrals
    of its derivatives, ∫ d(e - d)/√Q dd and ∫ d(x - d)/√Q dd (Q = d(x - d)(e - d), from c to
    b), by the same series.

    Why. The plateau fit needs G′'s derivatives in x and c at every point of every
    Levenberg-Marquardt step (:func:`contactres.analysis._plateau_slopes.plateau_loop_slopes`): by a
    16-point Gauss-Legendre rule (m < 0.1) and Carlson's R_F, R_D, ~400-900 ns a point; this
    costs two more passes a term than J alone.

    How. With d = r(1 - cos φ)/2 as for J, the integral with √ of the larger end (max(x, e) - d
    = A(1 + q cos φ)) in the denominator is (r²/4)/√A ∫ sin²φ (1 + q cos φ)^(-1/2) dφ =
    (r²/4)/√A Σ c_k q^k T_k, c_k = binom(-1/2, k) = -(2k - 1) b_k (k >= 1): the terms of J's
    series times -(2k - 1), summed alongside (the rest after K terms is at most 2K + 1 times
    J's, below ~2e-15 of its scale in the last tier). That is ∫ d(x - d)/√Q where x <= e and
    ∫ d(e - d)/√Q where x > e; the other follows from Euler's relation for J(x, c, e),
    homogeneous of degree 5/2 in the three, whose partial derivatives are half the two
    integrals (in x and e) and -√Q(c) (in c, the lower end): x ∫d(e - d)/√Q + e ∫d(x - d)/√Q
    = 5J + 2c√Q(c), √Q(c) = √(3c(x - c)/2). The terms on the right are positive and the
    subtraction loses no more than a few units of rounding of 5J (x ∫d(e - d)/√Q and
    e ∫d(x - d)/√Q are each at least ~J).

    Parameters
    ----------
    x, c, phi : as :func:`slip_integral_series`
    groups : ascending ends (exclusive) of groups of cells of :data:`SERIES_TIERS`: the points
        of each group sum the terms of its last cell (the most it needs); NaN beyond the last
        group's end (m below ``groups[-1]``/:data:`SERIES_CELLS` only). Default: each cell
        alone, as :func:`slip_integral_series`, whose J this then is bit for bit. All groups
        share one loop over the terms (the points sorted by their group's terms, those still
        summing at a term a prefix of them): a group costs no numpy calls of its own, and each
        point's numbers are those of its own terms alone (tests/analysis/test_plateau_series.py)

    Returns
    -------
    J, ∫ d(e - d)/√Q dd and ∫ d(x - d)/√Q dd, dimensionless (NaN outside the domain)

    Raises
    ------
    ContactresInputError
        (a ValueError) Unless ``groups`` are integers, strictly ascending, within
        1..len(:data:`SERIES_TIERS`): other groups would give wrong numbers silently.
    """
    groups = tuple(groups)
    # ~2 µs a call (a fit calls it once a step, on all its points): cheap against the series.
    if not (
        groups
        and all(isinstance(g, Integral) for g in groups)
        and all(lo < hi for lo, hi in zip((0, *groups), groups, strict=False))
        and groups[-1] <= len(SERIES_TIERS)
    ):
        raise ContactresInputError(
            f"groups must be strictly ascending integers in 1..{len(SERIES_TIERS)}, got {groups!r}"
        )
    return _by_tiers(x, c, phi, groups, True)


def _by_tiers(x, c, phi, groups: tuple[int, ...], derivatives: bool) -> tuple[np.ndarray, ...]:
    """The series of :func:`slip_integral_series` (with the integrals of
    :func:`slip_integrals_series` if ``derivatives``) in the ``groups`` of cells."""
    x, c = np.asarray(x, dtype=float), np.asarray(c, dtype=float)
    e = c + 1.5
    # The integrand is symmetric in x and e (module docstring): r = min(x, e), A.
    m = np.minimum(x, e) / np.maximum(x, e)
    # Each point's tier (len(SERIES_TIERS): outside), the points sorted by tier (a radix sort
    # of small integers) and taken in reverse, the most terms first: a group's cells a range of
    # tiers, the points still summing at any term are then a prefix of them (one loop over the
    # terms for all groups: _series). Only the points inside the domain are gathered, and only
    # x, c and φ_c of them (r and A are cheaper formed again than gathered).
    # (fmin: a NaN m goes outside, as m >= SERIES_MAX_M does)
    tier = np.fmin(m * SERIES_CELLS, len(SERIES_TIERS)).astype(np.int8)
    order = np.argsort(tier, kind="stable")
    ends = np.cumsum(np.bincount(tier, minlength=len(SERIES_TIERS) + 1))
    inside = int(ends[groups[-1] - 1])
    order = order[:inside][::-1]
    x, c = x[order], c[order]
    if phi is not None:
        phi = np.asarray(phi, dtype=float)[order]
    # (terms, end of the prefix of the points that sum them), the group summing the most first.
    reach = [
        (SERIES_TIERS[last - 1][1], inside - int((0, *ends)[first]))
        for first, last in zip((0, *groups[:-1]), groups, strict=True)
    ][::-1]
    got = slip_integrals_ordered(x, c, phi, reach, derivatives)
    out = np.full((1 + 2 * derivatives, m.size), np.nan)
    for o, v in zip(out, got, strict=True):
        o[order] = v
    return tuple(out)


def slip_integrals_ordered(x, c, phi, reach, derivatives: bool = True) -> tuple[np.ndarray, ...]:
    """J of :func:`slip_integral_series` (with the integrals of :func:`slip_integrals_series`
    if ``derivatives``) at points already ordered by the terms they sum, the most first: the
    same numbers, bit for bit, as those functions give at each point with the same terms.

    Why. The plateau fit (:func:`contactres.analysis._plateau_slopes.plateau_loop_slopes`)
    orders its points once an evaluation (series groups, then the elliptic form's points) and
    keeps that order for all of its arithmetic: one gather and one scatter instead of this
    module's own sort and those of its callers.

    Parameters
    ----------
    x, c : 1-d arrays inside the series' domain (as :func:`slip_integral_series`), ordered
    phi : 2 arcsin √(c/x) at each point, or None; overwritten where x > e (with φ_c there)
    reach : (K, n) pairs, K descending, n ascending, the last n the points' count: the first
        n points sum the terms k = 0..K (at least; a point's K that of the last pair it falls
        under; K at most that of :data:`SERIES_TIERS`' last cell)
    derivatives : with the two integrals of :func:`slip_integrals_series`

    Returns
    -------
    J (and ∫ d(e - d)/√Q dd, ∫ d(x - d)/√Q dd), dimensionless, at each point
    """
    e = c + 1.5
    r, a = np.minimum(x, e), np.maximum(x, e)
    a -= 0.5 * r
    # φ_c = 2 arcsin √(c/r): the caller's 2 arcsin √(c/x) where r = x, the same numbers.
    far = x > e
    if phi is None or far.all():
        phi = 2.0 * np.arcsin(np.sqrt(c / r))
    elif far.any():
        phi[far] = 2.0 * np.arcsin(np.sqrt(c[far] / r[far]))
    got = np.empty((1 + derivatives, x.size))
    # In blocks of SERIES_BLOCK points (the last one shorter): each term's passes then stay in
    # the core's cache.
    for start in range(0, x.size, SERIES_BLOCK):
        block = slice(start, min(start + SERIES_BLOCK, x.size))
        size = block.stop - start
        here = [(t, min(max(end - start, 0), size)) for t, end in reach]
        got[:, block] = _series(r[block], a[block], c[block], phi[block], here, derivatives)
    if not derivatives:
        return (got[0],)
    # Euler's relation (slip_integrals_series): the summed one is that of the larger end.
    J, summed = got
    rest = 5.0 * J + 2.0 * c * np.sqrt(1.5 * c * (x - c))
    # (where no point, or every point, lies beyond e, the choices below are one side whole:
    # the same numbers without a selection's pass over the points)
    if not far.any():
        rest -= e * summed
        rest /= x
        return J, rest, summed
    if far.all():
        rest -= x * summed
        rest /= e
        return J, summed, rest
    rest -= np.where(far, x, e) * summed
    rest /= np.where(far, e, x)
    return J, np.where(far, summed, rest), np.where(far, rest, summed)


def _series(r, a, c, phi, reach, derivatives=False):
    """(r²/4) √A Σ_{k <= K} b_k q^k T_k (module docstring) at r, A = ``a``, c and φ_c =
    ``phi`` (and, if ``derivatives``, (r²/4)/√A Σ c_k q^k T_k of
    :func:`slip_integrals_series`). ``reach``: (K, n) pairs, K descending, n ascending: the
    first n points sum K terms (at least; a point's K that of the last pair it falls under),
    the points beyond the last n none (their numbers undefined)."""
    rho = c / r
    q = 0.5 * r / a
    sin = 2.0 * np.sqrt(rho * (1.0 - rho))
    cos = 1.0 - 2.0 * rho
    # V_k = b_k q^k T_k, summed as it goes; p = q^k sin³φ_c cosᵏ⁻¹φ_c.
    p = sin * sin * sin * q  # not sin**3: a call of pow per point
    older, old = 0.5 * (np.pi - phi) + 0.5 * sin * cos, p * (-0.5 / 3.0)
    total = older + old
    # c_k/b_k = -(2k - 1) for k >= 1 (slip_integrals_series): V_0 - V_1 so far.
    other = older - old if derivatives else None
    qq, qc = q * q, q * cos
    tmp = np.empty_like(p)
    # Points still summing at term k: the first n of the pairs with K >= k (a prefix).
    most = reach[0][0]
    n = np.zeros(most + 1, dtype=np.intp)
    for terms, end in reach:
        n[: terms + 1] = np.maximum(n[: terms + 1], end)
    # In place (V_k in the buffer of V_{k-2}, which it no longer needs: V_k of even k in
    # ``older``'s, of odd k in ``old``'s): the same arithmetic without a new array per
    # operation, on the prefix of the points still summing. The prefixes' views are taken once
    # a prefix (it changes at a group's end only) and updated in place, not written back
    # through a slice (total[s] += v copies the sum onto itself: a pass more a term).
    views: tuple[np.ndarray, ...] = ()
    for k, (to_older, to_p) in enumerate(_FACTORS[: most - 1], start=2):
        if not n[k]:
            break
        if not views or views[0].size != n[k]:
            s = slice(0, n[k])
            views = (p[s], qc[s], qq[s], tmp[s], total[s], older[s], old[s])
            oth = other[s] if other is not None else None
        pk, qck, qqk, tk, tot, even, odd = views
        ok = odd if k & 1 else even
        pk *= qck
        ok *= qqk
        ok *= to_older
        ok -= np.multiply(pk, to_p, out=tk)
        tot += ok
        if other is not None:
            oth -= np.multiply(ok, 2 * k - 1, out=tk)
    scale = 0.25 * r * r
    if other is None:
        return scale * np.sqrt(a) * total
    root = np.sqrt(a)
    return scale * root * total, scale * other / root


def _factors(terms: int) -> tuple[tuple[float, float], ...]:
    """(b_k (k - 1)/(b_{k-2} (k + 2)), b_k/(k + 2)) for k = 2..``terms``: the constant factors
    of the recursion V_k = b_k q^k T_k (module docstring), b_k = binom(1/2, k)."""
    b = [1.0, 0.5]
    for k in range(2, terms + 1):
        b.append(b[-1] * (1.5 - k) / k)
    return tuple((b[k] / b[k - 2] * (k - 1) / (k + 2), b[k] / (k + 2)) for k in range(2, terms + 1))


#: The factors of :func:`_series` up to the most terms a tier sums (constants of the series).
_FACTORS = _factors(max(SERIES_TERMS))
