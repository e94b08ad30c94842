"""The exact plateau loop's slopes G′, G″ and their derivatives in closed form (paper 2, Eqs. 4-6).

:func:`plateau_loop_slopes` gives, at x = κu0/(μF_N) and c = κd_c/(μF_N), the shapes of the
plateau loop (:class:`contactres.PlateauLoop`: the contact sticks up to the critical
displacement d_c, then slips as Cattaneo-Mindlin in the excess) that the plateau fit
(:func:`contactres.analysis._plateau.fit_plateau_loops`) and the plateau's evidence
(:mod:`contactres.analysis._plateau_evidence`) evaluate at some 10⁶ points of a large table:
by power series (:mod:`contactres.analysis._plateau_series`) where the parameter m of the
elliptic integrals is small, by Carlson's elliptic integrals (:mod:`contactres.analysis.
_carlson`) beyond. :func:`slopes_ordered` is the fit's form, with derivatives, at points it
orders once an evaluation.
"""

from __future__ import annotations

import numpy as np

from ._carlson import legendre_tails
from ._plateau_series import (
    SERIES_CELLS,
    SERIES_TIERS,
    slip_integral_series,
    slip_integrals_ordered,
)

__all__ = ["FIT_SERIES_GROUPS", "VALUES_BLOCK", "plateau_loop_slopes", "slopes_ordered"]

#: Groups of cells of m = min(x, e)/max(x, e) (1/16 wide, :data:`~contactres.analysis.
#: _plateau_series.SERIES_TIERS`) in which :func:`plateau_loop_slopes` with derivatives sums
#: the series of J and of its derivatives' integrals (:func:`~contactres.analysis.
#: _plateau_series.slip_integrals_series`): m < 1/4 with 15 terms, m < 1/2 with 26 (89 % of
#: the fit's points on the 10^4 sweeps of issue 31); the elliptic form beyond. Why, when
#: measured (each group of cells then summed its terms in a loop of its own): the fit
#: evaluates a few thousand points a call, so that numpy's per-call cost of a cell's terms
#: outweighed the terms a coarser group sums in vain: on the slopes of those fits' calls
#: (6.4·10⁵ points) one cell a group up to 11/16 took 0.28 s of CPU, these two groups
#: 0.20 s, the 16-point Gauss-Legendre rule (m < 0.1) and the elliptic form they replace
#: 0.38 s (best of seven, loaded machine). Since the groups share one loop over the terms
#: (:func:`~contactres.analysis._plateau_series.slip_integrals_series`) a group costs no
#: calls of its own, so that finer groups may now pay (a review's quick timing: one cell a
#: group up to 8/16 cost 0.396 ms against 0.388 ms at 3,000 points and 4.49 ms against
#: 4.71 ms at 35,000; J within 3.4e-16): not changed, as it moves the sums' last bits.
FIT_SERIES_GROUPS = (4, 8)

#: Points per block of the arithmetic of G′ and G″ from J without derivatives: its ~6 arrays
#: stay in the core's cache (the evidence's calls hold up to ~2·10⁵ points); elementwise, so
#: the same numbers in any block.
VALUES_BLOCK = 8192


def plateau_loop_slopes(x, c, derivatives: bool = True) -> tuple[np.ndarray, ...]:
    """:func:`contactres.analysis._loops.plateau_loop_shape` in closed form, with derivatives.

    Returns G′ = K′/κ, G″ = (K″ - ωξ)/κ and ∂G′/∂x, ∂G′/∂c, ∂G″/∂x, ∂G″/∂c at x = κu0/(μF_N),
    c = κd_c/(μF_N) (broadcast together, x, c >= 0). Paper 2, Eqs. 4-6 with Masing's rule in
    the virgin-curve form of :func:`contactres.resonators.masing_stiffness`, for the slope
    F′(d) = 1 (d < c), √(1 - 2(d - c)/3) (c < d < e = c + 3/2), 0 beyond:

    * G″ = 4/(πx²) [c s(y) + W(y)], y = x - c, with s(y) = y - F_CM(y) and
      W(y) = ∫₀^min(y, 3/2) √(1 - 2t/3)(y - 2t) dt, both polynomials in r = √(1 - 2y/3);
    * G′ = 8/(πx²) [∫₀^c √(d(x - d)) dd + √(2/3) ∫_c^b √(d(x - d)(e - d)) dd], b = min(x, e):
      the second integral and those of the derivatives reduce to ∫ dᵏ/√(d(x - d)(e - d)),
      k = 0, 1, 2, i.e. to Legendre's incomplete elliptic integrals F and E of parameter
      m = b/max(x, e). Where m < 1/2 (:data:`FIT_SERIES_GROUPS`; small x, where the elliptic
      combination cancels, among them) the three integrals are instead summed as power series
      (:func:`contactres.analysis._plateau_series.slip_integrals_series`'s sums, at the
      points ordered once an evaluation: :func:`~contactres.analysis._plateau_series.
      slip_integrals_ordered`).

    Agrees with the quadrature of :func:`~contactres.analysis._loops.plateau_loop_shape` to
    ~2e-11 (that quadrature's own accuracy; tests/analysis/test_scale.py), at ~0.3-0.5 µs per
    point for all six arrays, several times less than the quadrature of G′, G″ alone.
    ``derivatives=False``: G′ and G″ alone (the nodes of
    :mod:`contactres.analysis._plateau_evidence`, which need no gradient), at a fraction of the
    cost: the second integral by its power series wherever m < 7/8
    (:func:`contactres.analysis._plateau_series.slip_integral_series`), the same numbers to
    rounding (within ~1e-13 of G′ with derivatives, whose elliptic form, at m >= 1/2, loses
    that much to cancellation; the series is the more accurate).
    """
    x, c = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(c, dtype=float))
    if derivatives:
        return slopes_ordered(x, c)
    slip = x > c  # below d_c the contact sticks: G′ = 1, G″ = 0, and so do their derivatives
    if slip.all():  # (no gather and scatter: the same numbers, each point's its own)
        return tuple(v.reshape(x.shape) for v in _slipping_values(x.ravel(), c.ravel()))
    out = [np.ones(x.shape), np.zeros(x.shape)]
    at = np.flatnonzero(slip)  # (found once for the 2 gathers and 2 scatters)
    if at.size:
        flat = [o.reshape(-1) for o in out]
        got = _slipping_values(x.reshape(-1)[at], c.reshape(-1)[at])
        for o, v in zip(flat, got, strict=True):
            o[at] = v
    return tuple(out)


def slopes_ordered(x, c) -> tuple[np.ndarray, ...]:
    """:func:`plateau_loop_slopes` with derivatives at x, c (broadcast, same shape).

    The slipping points (x > c) are gathered once, ordered as J's forms take them: the series'
    groups of :data:`FIT_SERIES_GROUPS`, the most terms first (a prefix of them still summing
    at each term, :func:`contactres.analysis._plateau_series.slip_integrals_ordered`), then
    the elliptic form's points; all of :func:`_slipping` runs in that order, its six arrays
    scattered back once. Each point's numbers are its own (elementwise arithmetic), so that
    they are those of the points taken one by one, bit for bit: one gather and one scatter
    instead of a sort, five gathers and a dozen scatters (those of the slipping points, the
    series' tiers and the elliptic points each on its own)."""
    xf, cf = x.reshape(-1), c.reshape(-1)
    slip = xf > cf  # below d_c the contact sticks: G′ = 1, G″ = 0, and so do their derivatives
    # m = min(x, e)/max(x, e) in cells 1/16 wide, as _plateau_series takes it (a NaN m goes to
    # the elliptic form, as the series' NaN sent it there).
    e = cf + 1.5
    cells = np.minimum(xf, e)
    cells /= np.maximum(xf, e)
    cells *= SERIES_CELLS
    below = [cells < g for g in FIT_SERIES_GROUPS]
    parts, reach = [], []
    for j in range(len(below) - 1, -1, -1):  # the group summing the most terms first
        group = below[j] & slip
        if j:
            group &= ~below[j - 1]
        parts.append(np.flatnonzero(group))
        ns = sum(p.size for p in parts)
        reach.append((SERIES_TIERS[FIT_SERIES_GROUPS[j] - 1][1], ns))
    slip &= ~below[-1]
    parts.append(np.flatnonzero(slip))
    order = np.concatenate(parts)
    got = _slipping(xf[order], cf[order], reach)
    if order.size == xf.size:  # every point slips: each is written below
        out = [np.empty(x.shape) for _ in range(6)]
    else:
        out = [np.ones(x.shape)] + [np.zeros(x.shape) for _ in range(5)]
    for o, v in zip(out, got, strict=True):
        o.reshape(-1)[order] = v
    return tuple(out)


def _slipping(x, c, reach) -> tuple[np.ndarray, ...]:
    """:func:`plateau_loop_slopes` with derivatives where x > c (1-d arrays ordered by
    :func:`slopes_ordered`: ``reach`` the series' (terms, end) pairs, the points beyond the
    last end by the elliptic form)."""
    y = x - c
    half = 2.0 * np.arcsin(np.sqrt(c / x))  # d = c at φ = half
    # J and its derivatives' integrals by their series where it is the cheaper (m below
    # FIT_SERIES_GROUPS[-1]/16), by the elliptic integrals beyond.
    ns = reach[-1][1]
    # (φ_c: a copy, which the series overwrites where x > e)
    if ns == x.size:  # every point by the series: its arrays are J's, not copied into others
        J, Jx, Jc = slip_integrals_ordered(x, c, half.copy(), reach)
    else:
        J, Jx, Jc = np.empty(x.size), np.empty(x.size), np.empty(x.size)
        if ns:
            J[:ns], Jx[:ns], Jc[:ns] = slip_integrals_ordered(
                x[:ns], c[:ns], half[:ns].copy(), reach
            )
        J[ns:], Jx[ns:], Jc[ns:] = _elliptic_integrals(x[ns:], c[ns:])
    bad = np.flatnonzero(np.isnan(J[:ns]))  # (none inside the domain: a guard)
    if bad.size:
        J[bad], Jx[bad], Jc[bad] = _elliptic_integrals(x[bad], c[bad])
    rcy = c * y
    np.sqrt(rcy, out=rcy)
    x2 = x**2
    # H = x²/8 · half - (1/4)√(cy)(y - c) + √(2/3) J, in that order of operations.
    H = x2 / 8.0
    H *= half
    t = 0.25 * rcy
    t *= y - c
    H -= t
    H += np.sqrt(2.0 / 3.0) * J
    # Loss part: s(y) = ∫₀^y (1 - √(1 - 2t/3)) dt and W(y), with 1 - r = (2y/3)/(1 + r): the
    # inside formulas (y < 3/2) at every point (finite beyond, where r = 0), the points beyond
    # then set to y - 1, y - 1.2 (and q = 1, W′ = 1): the numbers of a choice between the two.
    q = y / 1.5
    r = 1.0 - q
    np.maximum(r, 0.0, out=r)
    np.sqrt(r, out=r)
    q /= 1.0 + r
    s_y = q * q
    s_y *= 0.5 + r
    W = 0.3 * q**3
    t = r * r
    t += 3.0 * r
    t += 1.0
    W *= t
    dW = 1.0 - r**3
    dW -= y * r
    beyond = np.flatnonzero(~(y < 1.5))  # (a NaN y beyond, as np.where took it)
    if beyond.size:
        yb = y[beyond]
        q[beyond], s_y[beyond], W[beyond], dW[beyond] = 1.0, yb - 1.0, yb - 1.2, 1.0
    k1 = np.pi * x2
    k2 = 4.0 / k1
    np.divide(8.0, k1, out=k1)
    g1 = k1 * H
    g2 = c * s_y
    g2 += W
    g2 *= k2
    Hx = 0.5 * x
    Hx *= half
    Hx -= rcy
    Hx *= 0.5
    Hx += Jx / np.sqrt(6.0)
    Jc /= np.sqrt(6.0)  # Hc
    Jc *= k1  # ∂G′/∂c
    cq = c * q
    Hx *= k1  # ∂G′/∂x below
    t = 2.0 * g1
    t /= x
    Hx -= t
    dg2x = cq + dW
    dg2x *= k2
    t = 2.0 * g2
    t /= x
    dg2x -= t
    s_y -= cq
    s_y -= dW
    s_y *= k2  # ∂G″/∂c
    return g1, g2, Hx, Jc, dg2x, s_y


def _slipping_values(x, c) -> tuple[np.ndarray, np.ndarray]:
    """G′ and G″ of :func:`_slipping` alone (``derivatives=False``): the same formulas, J by
    its series where it converges fast (the elliptic form elsewhere), each intermediate formed
    once and updated in place (a third fewer passes over the points), in blocks of
    :data:`VALUES_BLOCK` points once J is known."""
    half = np.sqrt(c / x)
    np.arcsin(half, out=half)
    half *= 2.0  # d = c at φ = half, the series' φ_c where x <= e (one arcsin for both)
    J = slip_integral_series(x, c, half)
    far = np.isnan(J)
    if far.any():
        J[far] = _elliptic_integrals(x[far], c[far], derivatives=False)[0]
    if x.size <= VALUES_BLOCK:
        return _values_from(x, c, half, J)
    g1, g2 = np.empty_like(x), np.empty_like(x)
    for start in range(0, x.size, VALUES_BLOCK):
        block = slice(start, start + VALUES_BLOCK)
        g1[block], g2[block] = _values_from(x[block], c[block], half[block], J[block])
    return g1, g2


def _values_from(x, c, half, J) -> tuple[np.ndarray, np.ndarray]:
    """G′ and G″ of :func:`_slipping_values` from 2 arcsin √(c/x) (``half``) and J at the
    points (both overwritten)."""
    y = x - c
    x2 = x * x
    # H = x²/8 · 2 arcsin √(c/x) - (1/4) √(cy) (y - c) + √(2/3) J, as in _slipping.
    H = half
    H *= x2
    H /= 8.0
    t = c * y
    np.sqrt(t, out=t)
    t *= 0.25
    t *= y - c
    H -= t
    J *= np.sqrt(2.0 / 3.0)
    H += J
    k2 = np.pi * x2
    np.divide(4.0, k2, out=k2)
    # Loss part as in _slipping: s(y) and W(y) inside y < 3/2, y - 1 and y - 1.2 beyond.
    # The inside formulas at min(y, 3/2) everywhere (no NaN beyond), then one choice: a third
    # of the selections (~3.5 ns a point each) with the same numbers on both sides.
    inside = y < 1.5
    q = np.minimum(y, 1.5)
    q /= 1.5
    r = 1.0 - q
    np.sqrt(r, out=r)
    q /= 1.0 + r
    g2 = q * q
    g2 *= 0.5 + r
    g2 *= c
    w = q**3  # not qq * q: G″ is the fit's bit for bit
    w *= 0.3
    w *= r * r + 3.0 * r + 1.0
    g2 += w
    beyond = y - 1.0
    beyond *= c
    beyond += y - 1.2
    g2 = np.where(inside, g2, beyond)
    g2 *= k2
    H *= 2.0 * k2
    return H, g2


def _elliptic_integrals(x, c, derivatives: bool = True) -> tuple[np.ndarray, ...]:
    """J = ∫_c^b √Q, ∫d(e - d)/√Q and ∫d(x - d)/√Q (Q = d(x - d)(e - d), b = min(x, e)) of
    :func:`plateau_loop_slopes`, from Legendre's incomplete elliptic integrals F and E (J
    alone if not ``derivatives``)."""
    e = c + 1.5
    r2, r3 = np.minimum(x, e), np.maximum(x, e)
    m = r2 / r3
    # I_k = ∫_c^r2 dᵏ dd/√Q with d = r2 sin²θ, from θ = φ (sin²φ = c/r2) to π/2: the tails
    # K - F(φ|m) and E - E(φ|m) by Carlson's R_F and R_D (:mod:`._carlson`), with no
    # difference of the complete and incomplete integrals (which lost their digits as φ nears
    # π/2). m' = 1 - m, held above 1e-150 where x = e (m = 1, a log singularity: the tails'
    # weights vanish there; above 1e-150 the arguments' products stay normal numbers).
    rho = np.minimum(c / r2, 1.0)
    m1 = np.maximum((r3 - r2) / r3, 1e-150)
    # cos²φ = (r2 - c)/r2 without the cancellation of 1 - sin²φ as c nears r2.
    kf, ef = legendre_tails(rho, (r2 - c) / r2, m, m1)
    sq3 = np.sqrt(r3)
    S, P = x + e, x * e
    qc = np.sqrt(1.5 * c * (x - c))  # √Q at d = c
    # ∫√Q = [(2d/5 - 2S/15)√Q] + ∫(SP/15 + (2P/5 - 2S²/15) d)/√Q: d/dd of the bracket is √Q.
    a1 = 0.4 * P - 2.0 * S**2 / 15.0
    J = (2.0 * S / 15.0 - 0.4 * c) * qc + (2.0 / 15.0) * sq3 * kf * (r3 - r2) * (r2 - 2 * r3)
    J = J - 2.0 * a1 * sq3 * ef
    if not derivatives:
        return (J,)
    I1 = 2.0 * sq3 * (kf - ef)
    I2 = (2.0 * S * I1 - P * (2.0 / sq3) * kf - 2.0 * qc) / 3.0
    return J, e * I1 - I2, x * I1 - I2
