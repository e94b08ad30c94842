"""The χ² profile along κ of the particle fit below the overtone comb (issue 28).

Below the comb the data fix the products N·κ and N·ξ (paper 2, Eq. 1) to a fraction of a
percent, while κ and N apart rest on the small terms of the expansion in (f_coupled/f_n)² and
on the particle's hydrodynamic load N g. Along the valley of constant N·κ and N·ξ the χ²
(profiled over ξ and N) is far from a parabola: a narrow minimum, and on its stiff side a
shoulder with a second, shallower minimum (2.2 times the stiffness for a 1 µm sphere in water
with f_coupled at f_F/10: Δχ² ≈ 19 above the first without noise, a few to 30 with a noise of
0.1 Hz). A local search from the starts of :func:`~contactres.analysis.fit_particles` stopped
there in a quarter of the draws at a coverage of 3e11 m⁻², with N·κ printed 3-6σ off.

:func:`valley_profile` walks the valley: at each of :data:`PROFILE_STEPS` stiffnesses
κ̂·s (s from 1/10 to 10) it holds κ and fits ξ and N (and κ_r) by Levenberg-Marquardt from
(ξ̂ s, N̂/s), which keeps N·κ and N·ξ. That is the profile likelihood in κ (Press et al.,
Numerical Recipes, 3rd ed., §15.6.5): its lowest point, refined with κ free, replaces the fit
where it fits better, and all its points join those the interval test of the fit's ``result``
reads (a point of Δχ² = D farther than 1.3σ√max(D, 1) from the fit in a value blanks that
value).
"""

from __future__ import annotations

import numpy as np

from ..fitting import levenberg_marquardt

__all__ = ["PROFILE_STEPS", "valley_profile"]

#: The factors s of κ at which the profile is taken (κ held at κ̂ s, ξ and N fitted): 1/10 to
#: 10 in steps of 10^(1/12) (21 %), the fit itself (s = 1) left out. The second minimum lies
#: at s ≈ 2.2 from the first (module docstring); the χ² rises by 10³-10⁴ at the ends.
PROFILE_STEPS = np.delete(np.logspace(-1.0, 1.0, 25), 12)


def valley_profile(evaluate, q, chi2, conv, rows, lo, hi, options):
    """The profile of χ² along κ (ln κ in column 0 of the fit's coordinates) at ``rows``.

    Parameters
    ----------
    evaluate : ``evaluate(q, rows, jacobian)`` of the fit (the Gauss-Newton form of
        :func:`contactres.fitting.levenberg_marquardt`; ``rows`` index the T steps)
    q : (T, P) the fitted parameters (ln κ, ξ in units of its scale, ln N, [ln κ_r])
    chi2, conv : (T,) their χ² and whether they converged
    rows : (R,) the steps to profile (those whose fit lies below the comb)
    lo, hi : (T, P) the bounds of the fit
    options : :class:`~contactres.fitting.LMOptions`

    Returns
    -------
    q, chi2, conv : the fit, improved at the steps where the profile's lowest point, refined
        with κ free, fits better (copies)
    visited : list of ((T, P) points, (T,) χ²) pairs, χ² = inf at the steps not profiled: the
        profile's points and the refined fits, for the interval test
    """
    q, chi2, conv = q.copy(), chi2.copy(), conv.copy()
    t, npar = q.shape
    if rows.size == 0:
        return q, chi2, conv, []
    n_s = PROFILE_STEPS.size
    at = np.tile(rows, n_s)  # (S R,) the step of each profile point, and its factor s
    s = np.repeat(PROFILE_STEPS, rows.size)
    p0 = q[at].copy()
    # along the valley: κ s, ξ s and N/s keep N·κ and N·ξ
    p0[:, 0] += np.log(s)
    p0[:, 1] *= s
    p0[:, 2] -= np.log(s)
    p0 = np.clip(p0, lo[at], hi[at])
    # κ held (lo = hi: the bound holds it), the rest free
    lo_h, hi_h = lo[at].copy(), hi[at].copy()
    lo_h[:, 0] = hi_h[:, 0] = p0[:, 0]
    res = levenberg_marquardt(
        lambda x, r, jac: evaluate(x, at[r], jac),
        p0,
        lo=lo_h,
        hi=hi_h,
        options=options,
    )
    visited = []
    for j in range(n_s):
        part = slice(j * rows.size, (j + 1) * rows.size)
        pts, c2 = q.copy(), np.full(t, np.inf)
        pts[rows], c2[rows] = res.x[part], res.chi2[part]
        visited.append((pts, c2))
    # the lowest point of each step's profile, refined with κ free where it beats the fit
    prof_chi2 = res.chi2.reshape(n_s, rows.size)
    low = np.argmin(np.where(np.isfinite(prof_chi2), prof_chi2, np.inf), axis=0)
    start = res.x.reshape(n_s, rows.size, npar)[low, np.arange(rows.size)]
    sel = np.flatnonzero(prof_chi2[low, np.arange(rows.size)] < chi2[rows])
    if sel.size == 0:
        return q, chi2, conv, visited
    steps = rows[sel]
    ref = levenberg_marquardt(
        lambda x, r, jac: evaluate(x, steps[r], jac),
        start[sel],
        lo=lo[steps],
        hi=hi[steps],
        options=options,
    )
    pts, c2 = q.copy(), np.full(t, np.inf)
    pts[steps], c2[steps] = ref.x, ref.chi2
    visited.append((pts, c2))
    better = ref.chi2 < chi2[steps]
    take = steps[better]
    q[take], chi2[take], conv[take] = ref.x[better], ref.chi2[better], ref.converged[better]
    return q, chi2, conv, visited
