"""The batched fit of the exact plateau loop (paper 2, Eqs. 4-6) to the ``plateau`` sweeps.

The loop is :class:`contactres.PlateauLoop` around the Cattaneo-Mindlin loop (see
:mod:`contactres.analysis._loops`): the contact sticks up to the critical displacement d_c, then
slips as Cattaneo-Mindlin in the excess. The fit Δf = Pκ G′(θu0, θd_c), ΔΓ = P[ωξ + κ
G″(θu0, θd_c)] (θ = κ/(μF_N)) solves Pκ and Pωξ in closed form for given (θ, d_c) (variable
projection, :func:`contactres.analysis._loops.solve_projected`) and (ln θ, d_c) by a
Levenberg-Marquardt iteration run for all sweeps at once, on the shapes and their derivatives
in closed form (:func:`~contactres.analysis._plateau_slopes.plateau_loop_slopes`: power
series, elliptic integrals). It starts from
the hinge position and from the amplitude below it (the better of the two), θ from the
Cattaneo-Mindlin loop fitted to the amplitudes in excess of the hinge. Pass 1 weights the
points by the noise of the hinge fit, pass 2 by that of pass 1's own residuals. Errors come
from the Jacobian in (Pκ, Pωξ, ln θ, d_c), scaled by the residual variance. The low-amplitude
limits of such a sweep, and its ``plateau_amplitude_m``, then come from this fit
(``limits_from`` = ``plateau-loop``).

It replaces a :func:`scipy.optimize.least_squares` fit per sweep on the quadrature of
:func:`contactres.analysis._loops.plateau_loop_shape` (same starts, passes, bounds and
tolerances; tests/analysis/test_scale.py compares the two): on the bundled example the
parameters agree within 1e-3 of their standard errors, at ~1/100 of the cost per sweep. The
errors differ where d_c sits on its bound 0: there the d_c column of the Jacobian is (to
rounding) a combination of the others, which the finite differences of the old fit blurred
into errors of ~10⁴ Hz. A fit that ends there (within :data:`PLATEAU_D_C_BOUND`) is the
Cattaneo-Mindlin fit: refitted with d_c held at 0, its errors those of (Pκ, Pωξ, ln θ) alone,
d_c 0 with no error (NaN).

Two savings leave the iteration as it was. The Levenberg-Marquardt solver reads a step's
gradient and Hessian only where it accepts the step (its χ² not above the row's current one),
so they are formed there alone (a quarter of the steps are refused), and each row keeps the fit
of its last accepted step, the fit at the solution, with no evaluation again: both bit for bit.
The rows of a block fitted jointly repeat each amplitude once per ramp: their points are pooled
into one per amplitude (:func:`pool_repeats`, a third of the points of the three-ramp blocks of
issue 31), the same χ² to rounding. On the 10^4 sweeps of issue 31 (bench_scale.large_table
with COPIES = 8) that moves the pooled blocks' parameters by at most 4.5e-6 of their standard
errors (bound: 1e-3), their errors and covariances by 1.3e-4 relative, ΔBIC by 4.2e-6, no
model choice or flag; tests/analysis/test_plateau_fit.py checks the bound against the fit
point by point.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd

from .._levenberg_marquardt import solve_finite_stacked
from ..fitting import LMOptions, levenberg_marquardt
from ._amplitude import PLATEAU_MIN_SLOPE
from ._bad_rows import spread_rows, usable_rows
from ._loops import (
    X_MAX,
    LoopTable,
    fit_cm_loops,
    loop_fit_fields,
    pinv_finite,
    projection_data,
    solve_projected,
)
from ._plateau_slopes import slopes_ordered

__all__ = [
    "PLATEAU_LOOP_COLUMNS",
    "fit_plateau_loops",
    "pool_repeats",
]

#: The Levenberg-Marquardt iteration of the fit (:func:`contactres.fitting.levenberg_marquardt`
#: on the Gauss-Newton form of the projected χ², tolerances set per pass): Marquardt's scaling
#: and Nielsen's update of the damping from the ratio of the actual to the predicted decrease
#: of χ² (the residuals are not small: a Gauss-Newton step may overshoot along a narrow
#: valley), bounds by projection (a parameter on a bound that the gradient pushes outwards is
#: held there for the step), at most 60 steps per sweep. A sweep stops when a step moves p by
#: < tol (relative) or lowers χ² by < tol of it, when both the actual and the predicted
#: decrease of a step are below tol of χ² (MINPACK's ftol test), or when no step lowers χ² any
#: more. With tol = 1e-7 the parameters agree with scipy's least_squares at 1e-10 within 1e-3
#: of their standard errors (tests/analysis/test_scale.py); 1e-10 and 200 steps cost 2.3x the
#: time for nothing a model choice or an error bar can see.
PLATEAU_LM = LMOptions(damping="marquardt", update="nielsen", lam0=1e-3, lam_max=1e14, max_iter=60)

#: d_c/u_max below which a fit's d_c counts as on its bound 0 (the house rule: a fit at its
#: bound is flagged, an unidentified parameter not printed as a result). The fit is then a
#: Cattaneo-Mindlin fit: refitted with d_c held at 0, its errors those of that constrained fit,
#: d_c reported as 0 with a NaN error and NaN covariances. Why: as d_c -> 0 the d_c column of
#: the Jacobian becomes a combination of the others, so a fit ending on the bound or a rounding
#: error off it (4e-16 m) got errors of ln θ 0.05 or 5e3 (pinv dropping the degenerate
#: direction or keeping it), and μ flipped between resolved and not in the experiment's μ prior
#: and the model choice (delta_bic moved by 1e-3 relative for a 1e-15 change of the shapes).
#: Why 1e-3: far above the rounding, and a plateau too short to matter: at fixed θ, d_c = 1e-3
#: u_max moves G′ and G″ by 2e-3 of their range over the sweep where x_max <= 1 (3 % at the
#: gross-sliding end X_MAX), before Pκ and θ take up part of it. On the bundled example the
#: 34 fits it moves off d_c > 0 end at d_c/u_max <= 1.4e-4, d_c <= 1.2e-5 of its own error,
#: and the refit raises their RSS by <= 6e-6 relative.
PLATEAU_D_C_BOUND = 1e-3

# Bounds of ln θ(u_max - d_c), the fit's first parameter: from no slip resolved (x_max =
# 10^-2.5) to gross sliding (X_MAX).
_LY_BOUNDS = (np.log(10.0**-2.5), np.log(X_MAX))

#: Numeric columns of :func:`fit_plateau_loops` (besides ``edge``).
PLATEAU_LOOP_COLUMNS = (
    "df0_Hz",
    "df0_err_Hz",
    "dgamma0_Hz",
    "dgamma0_err_Hz",
    "theta_per_m",
    "lntheta_err",
    "cov_df0_lntheta",
    "x_max",
    "d_c_m",
    "d_c_err_m",
    "cov_df0_d_c",
    "cov_lntheta_d_c",
    "rss_df",
    "rss_dgamma",
)


def pool_repeats(u, df, dg, w) -> tuple[np.ndarray, ...] | None:
    """The points of padded sweeps that repeat an amplitude pooled into one point per amplitude.

    Why: the ramps of a block fitted jointly repeat each amplitude (amplitudes ascending, the
    copies side by side), and the loop is a function of the amplitude: Σ w (Δf - model)² over
    an amplitude's copies is W (mean Δf - model)² + Σ w (Δf - mean Δf)² (W = Σ w, the weighted
    mean), so the fit evaluates the loop once per amplitude. The χ², its gradient and Hessian
    (with √W the factor of the weighted residuals) and the errors are those of the points one
    by one to rounding; the iteration may then stop a step apart, within its tolerance (the
    bound and the measured change: module docstring).

    Parameters
    ----------
    u, df, dg, w : (S, M) amplitudes (m), shifts (Hz) and weights (0 for padding)

    Returns
    -------
    None if no amplitude repeats; else (u, Δf, ΔΓ, W, √W), (S, M′) with M′ the most distinct
    amplitudes of a row (the means of the shifts, the padding at the row's largest amplitude
    with weight 0), and the within-amplitude sums of squares Σ w (Δf - mean)², Σ w (ΔΓ -
    mean)² (S,), Hz².

    Notes
    -----
    M′ is the widest row's of this call, so a row's pooled points, and the fit on them, carry
    padding that depends on the other rows passed with it: a row pooled alone is fitted on
    arrays of another width, whose sums round otherwise, and its results differ by
    rounding from the same row pooled in a batch (120 rows of one call of the 9,409 sweeps
    of ``benchmarks/bench_scale.py``'s recipe refitted alone: θ, Δf0, ΔΓ0 and the RSS within
    1.3e-12 relative, d_c, the errors and covariances within 7e-10). The padding is kept as it
    is: padding each row to its own width would change the results. Each call of
    :func:`fit_plateau_loops` in the analysis is one block's sweeps, whichever process runs it,
    so its results do not depend on how the blocks are dealt out to worker processes.
    """
    data = w > 0
    same = np.pad((u[:, 1:] == u[:, :-1]) & data[:, 1:] & data[:, :-1], ((0, 0), (1, 0)))
    if not same.any():
        return None
    new = data & ~same  # the first copy of each amplitude
    width = int(new.sum(axis=1).max())
    # Each point's pooled position (row-major): its row's count of amplitudes up to it.
    at = np.arange(u.shape[0])[:, None] * width + np.cumsum(new, axis=1) - 1
    flat = at[data]

    def pooled(a):
        return np.bincount(flat, a[data], minlength=u.shape[0] * width).reshape(-1, width)

    weight = pooled(w)
    held = weight > 0
    safe = np.where(held, weight, 1.0)
    mean_f, mean_g = pooled(w * df) / safe, pooled(w * dg) / safe
    amp = np.repeat(np.max(np.where(data, u, 0.0), axis=1, keepdims=True), width, axis=1)
    amp[held] = u[new]
    at = np.where(data, at, 0)
    within = [
        np.where(data, w * (a - m.reshape(-1)[at]) ** 2, 0.0).sum(axis=1)
        for a, m in ((df, mean_f), (dg, mean_g))
    ]
    return amp, mean_f, mean_g, weight, np.sqrt(weight), *within


def _plateau_model(
    p, u, umax, df, dg, w, rw, wf, wg, within=None, current=None, sums=None, weighted=None
) -> dict:
    """Projected fit of the plateau loop at p = (ln θ(u_max - d_c), d_c/u_max), rows (R, 2):
    Pκ, Pωξ, χ², the RSS of the channels, the gradient of χ²/2 in p and its Gauss-Newton
    Hessian (Kaufman's variable projection: exact gradient, Jacobian projected off Pκ, Pωξ).
    ``rw``: the factor of the weighted residuals, w where w is 0 or 1, √w for the points of
    :func:`pool_repeats`, whose sums of squares within their amplitudes, ``within`` (Δf's,
    ΔΓ's), join the RSS. ``current``: (R,) the χ² of the rows' current points, or None. Given,
    the gradient and Hessian are formed only at the rows whose χ² does not exceed it
    (``"accepted"``, the rows :func:`~contactres.fitting.levenberg_marquardt` accepts: it
    reads those of the others nowhere; zero there), a quarter of the steps of the fit being
    refused. ``sums``: (Σw, the weighted mean of ΔΓ, ΔΓ - mean) of the rows
    (:func:`~contactres.analysis._loops.projection_data`), which depend on the data alone, or None:
    the same numbers formed here (:func:`~contactres.analysis._loops.solve_projected`).
    ``weighted``: (√wf·rw, √wg·rw) of the rows, the factors of the weighted residuals of Δf and
    ΔΓ, fixed for a pass of the fit (``run`` in :func:`fit_plateau_loops` forms them once a pass
    and gathers their rows), or None: formed here from ``wf``, ``wg`` and ``rw`` (the same
    products, the same bits)."""
    ly, dl = p[:, 0], p[:, 1]
    ey = np.exp(ly)
    theta = ey / (umax * (1.0 - dl))  # θ(u_max - d_c) = e^ly
    x = theta[:, None] * u
    # c at every point (each row's repeated: the values plateau_loop_slopes' broadcast takes,
    # without its Python-level broadcast and copy; and _descent's products with it contiguous)
    c = np.repeat(theta * dl * umax, u.shape[1]).reshape(u.shape)
    slopes = slopes_ordered(x, c)
    A, B, chi2, rss_f, rss_g = solve_projected(slopes[0], slopes[1], df, dg, w, wf, wg, sums)
    if within is not None:
        rss_f, rss_g = rss_f + within[0], rss_g + within[1]
        chi2 = wf * rss_f + wg * rss_g
    fit = {"A": A, "B": B, "chi2": chi2, "rss_f": rss_f, "rss_g": rss_g}
    fit.update(theta=theta, slopes=slopes)
    accepted: slice | np.ndarray = slice(None)
    if current is not None:
        # (χ² <= current: the solver's test gain = current - χ² >= 0, NaN failing both)
        better = np.flatnonzero(chi2 <= current)
        if better.size < chi2.size:
            accepted = better
    fit["accepted"] = accepted
    if weighted is None:
        weighted = (np.sqrt(wf)[:, None] * rw, np.sqrt(wg)[:, None] * rw)
    sf, sg = weighted
    if isinstance(accepted, slice):
        fit["grad"], fit["hess"] = _descent(ey, dl, x, c, A, B, slopes, sf, sg, df, dg)
        return fit
    fit["grad"], fit["hess"] = np.zeros((chi2.size, 2)), np.zeros((chi2.size, 2, 2))
    if accepted.size:
        k = accepted

        def at(a):  # the rows k of a (np.take: a copy of whole rows, ~1/4 of a[k]'s cost)
            return np.take(a, k, axis=0)

        grad, hess = _descent(
            ey[k], dl[k], at(x), at(c), A[k], B[k], [at(s) for s in slopes], at(sf), at(sg),
            at(df), at(dg),
        )  # fmt: skip
        fit["grad"][k], fit["hess"][k] = grad, hess
    return fit


def _descent(ey, dl, x, c, A, B, slopes, sf, sg, df, dg) -> tuple[np.ndarray, np.ndarray]:
    """The gradient of χ²/2 in p and its Gauss-Newton Hessian of :func:`_plateau_model`, from
    its shapes, Pκ (A) and Pωξ (B) at the rows' points (sf, sg: √(channel weight) times the
    rows' residual factors ``rw``: w, or √W of a pooled amplitude).

    The weighted columns are written into their places in the arrays the sums take (channels
    side by side), not formed apart and then joined: the same numbers, without the joins'
    copies."""
    g1, g2, g1x, g1c, g2x, g2c = slopes
    R, M = sf.shape
    dx = x / (1.0 - dl)[:, None]  # ∂x/∂(d_c/u_max); ∂x/∂ln(...) = x
    dc = (ey / (1.0 - dl) ** 2)[:, None]
    f, g = slice(0, M), slice(M, 2 * M)
    # The rows of one array: the weighted columns of the linear part (Pκ, Pωξ), those of
    # ∂(model)/∂p and the weighted residuals, channels side by side.
    Z = np.empty((R, 5, 2 * M))
    phi, D, r = Z[:, :2], Z[:, 2:4], Z[:, 4]
    np.multiply(sf, g1, out=phi[:, 0, f])
    np.multiply(sg, g2, out=phi[:, 0, g])
    phi[:, 1, f] = 0.0  # Pωξ's column is 0 in the Δf channel
    phi[:, 1, g] = sg
    # ∂(model)/∂p, weighted: A times the shapes' derivatives along ln(...) and d_c/u_max, i.e.
    # (s t) A with t = gx along + gc at, each column's product with A written into its place
    # (t and its addend in two buffers reused by the four columns: no new arrays; no pass of
    # D *= A over the strided (R, 2, 2M) view, ~4x the cost of a contiguous one).
    t, tc = np.empty((2, R, M))
    A_ = A[:, None]
    for j, along, at in ((0, x, c), (1, dx, dc)):
        for s, gx, gc, ch in ((sf, g1x, g1c, f), (sg, g2x, g2c, g)):
            np.multiply(gx, along, out=t)
            t += np.multiply(gc, at, out=tc)
            t *= s
            np.multiply(t, A_, out=D[:, j, ch])
    np.multiply(A_, g1, out=t)
    np.subtract(df, t, out=t)
    np.multiply(sf, t, out=r[:, f])
    np.subtract(dg, B[:, None], out=t)
    t -= np.multiply(A_, g2, out=tc)
    np.multiply(sg, t, out=r[:, g])
    # The sums of products of the rows: one einsum a column j, at a third of the cost of
    # einsum("rim,rjm->rij"), whose (r, i, j) iteration spent more than the sums (~0.4 ms of
    # 2,400 rows against ~0.13 ms). Those read: of the linear part's columns (j = 0, 1) with
    # each other, of the derivatives' (j = 2, 3) with every row. Each sum over a row's points
    # is taken whole, for one row or many: the same numbers as the old einsum up to 4,096
    # points a row, beyond which that one summed blocks of numpy's 8,192-element buffer when
    # it had two rows or more (a long sweep's fit then depended on its batch, by ~1e-14).
    G = np.empty((R, 5, 4))
    for j in range(4):
        np.einsum("rim,rm->ri", Z if j > 1 else phi, Z[:, j], out=G[:, : 5 if j > 1 else 2, j])
    gram, pd_ = G[:, :2, :2], G[:, :2, 2:]
    # pd_ᵀ gram⁻¹ pd_ as a₀b₀ + a₁b₁, two rounded products: einsum("rki,rkj->rij")'s numbers
    # (up to a NaN's sign) where its kernel does not fuse the multiply-add, as on numpy's
    # x86-64 wheels (on aarch64 it does, and the last bit may differ), without its iteration
    # over (r, i, j), which cost ~0.25 ms on 2,400 rows against ~0.1 ms. (A -0 sum, where the
    # einsum gave +0, leaves the Hessian G - proj unchanged: G's sums are never -0.)
    # Element by element of the 2 x 2 Hessian, on 1-d arrays of the rows: the broadcast
    # outer products (R, 2, 1) x (R, 1, 2) copied the rows one by one into numpy's buffers
    # (~33 µs against ~21 µs on 450 rows).
    sol = solve_finite_stacked(gram, pd_)  # (finite: the rows of finite sweeps)
    hess, t = np.empty((R, 2, 2)), np.empty(R)
    for i in range(2):
        for j in range(2):
            h = hess[:, i, j]
            np.multiply(pd_[:, 0, i], sol[:, 0, j], out=h)
            h += np.multiply(pd_[:, 1, i], sol[:, 1, j], out=t)
            np.subtract(G[:, 2 + i, 2 + j], h, out=h)
    return -G[:, 4, 2:], hess


def fit_plateau_loops(
    u, df, dg, w, sigma_df, sigma_dg, u_c, table: LoopTable | None = None, theta_start=None
) -> pd.DataFrame:
    """Fit the exact plateau loop (+ dashpot) to every row of padded sweeps (module docstring).

    Parameters
    ----------
    u, df, dg, w : (S, M) amplitudes (m, ascending in each row), shifts (Hz), weights (0 for
        padding); the padding must be finite too (e.g. the row's last amplitude and shifts of
        0): a NaN there, as in NaN padding, makes its row one with no fit
    sigma_df, sigma_dg : (S,) noise levels of the two channels, Hz
    u_c : (S,) start of the critical displacement (the hinge of the plateau model), m
    table : the Cattaneo-Mindlin loop table for the start of θ (built here if None)
    theta_start : (S,) start of θ = κ/(μF_N), 1/m (e.g. from the Cattaneo-Mindlin loop fitted
        to the whole sweep); if None, from that loop fitted to the amplitudes in excess of u_c

    Returns
    -------
    DataFrame with the columns of :func:`fit_cm_loops` (``theta_per_m`` = κ/(μF_N), ``x_max``
    = θ·max(u0); ``edge`` "high" if the excess beyond d_c reaches gross sliding beyond
    x = X_MAX, "low" if no slip is resolved) plus ``d_c_m``, ``d_c_err_m`` and the covariances
    of d_c with Δf0 and ln θ, ``cov_df0_d_c`` (Hz m) and ``cov_lntheta_d_c`` (m). A fit on the
    bound (d_c/u_max < :data:`PLATEAU_D_C_BOUND`): ``d_c_m`` 0, its error and covariances NaN,
    the other errors those of the fit with d_c held at 0. A row with a NaN or an inf among its
    values, noise levels, u_c or θ start, or fewer than 3 distinct amplitudes of weight > 0 (4
    parameters), has no fit: NaN, edge "" (:mod:`contactres.analysis._bad_rows`); the other
    rows' results are those of a batch without it, bit for bit. Where amplitudes repeat, the
    batch without it may be pooled narrower (:func:`pool_repeats`: the widest row sets the
    width), so they may differ by rounding from those of the same batch with that row clean.
    """
    starts = () if theta_start is None else (theta_start,)
    good = usable_rows((u, df, dg, w), (sigma_df, sigma_dg, u_c, *starts), 3)
    if good is not None:
        u, df, dg, w, sigma_df, sigma_dg, u_c = (
            np.asarray(a)[good] for a in (u, df, dg, w, sigma_df, sigma_dg, u_c)
        )
        start = None if theta_start is None else np.asarray(theta_start)[good]
        fit = fit_plateau_loops(u, df, dg, w, sigma_df, sigma_dg, u_c, table, start)
        return spread_rows(fit, good)
    u_c = np.asarray(u_c, dtype=float)
    S = u.shape[0]
    rows = np.arange(S)
    n = w.sum(axis=1)
    umax = np.max(np.where(w > 0, u, 0.0), axis=1)
    floor_f = 1e-6 * np.maximum(np.abs(df).max(axis=1), 1e-12)
    floor_g = 1e-6 * np.maximum(np.abs(dg).max(axis=1), 1e-12)
    lo = np.tile([_LY_BOUNDS[0], 0.0], (S, 1))
    # d_c/umax: from 0 (no plateau) to the amplitude that leaves PLATEAU_MIN_SLOPE - 1 distinct
    # amplitudes above it (a row may repeat amplitudes: the ramps of a block fitted jointly).
    data = w > 0
    distinct = data & np.concatenate([np.ones((S, 1), bool), np.diff(u, axis=1) > 0], axis=1)
    count = np.cumsum(distinct, axis=1)  # u ascending: distinct amplitudes <= u
    above = count[:, -1:] - count
    room = data & (above >= PLATEAU_MIN_SLOPE - 1)
    hi = np.column_stack([np.full(S, _LY_BOUNDS[1]), np.max(np.where(room, u, 0.0), axis=1) / umax])
    # Start of θ: the Cattaneo-Mindlin loop fitted to the amplitudes in excess of the hinge.
    if theta_start is None:
        excess = np.maximum(u - u_c[:, None], 0.0)
        y0 = fit_cm_loops(excess, df, dg, w, sigma_df, sigma_dg, table)["x_max"].to_numpy()
    else:
        y0 = np.asarray(theta_start, dtype=float) * np.maximum(umax - u_c, 0.0)

    # The points the fit sees: one per amplitude where amplitudes repeat (pool_repeats; the
    # weights 0 or 1, whose square roots are themselves).
    pooled = pool_repeats(u, df, dg, w) if np.all((w == 0) | (w == 1)) else None
    points = (u, df, dg, w, w, None, None) if pooled is None else pooled

    def run(starts, sig_f, sig_g, of, tol, top=hi, full=True):  # start i of the sweep of[i]
        wf = (1.0 / np.maximum(sig_f, floor_f) ** 2)[of]
        wg = (1.0 / np.maximum(sig_g, floor_g) ** 2)[of]
        data = [a[of] for a in points[:5]]
        within = None if points[5] is None else [a[of] for a in points[5:]]
        um = umax[of]
        # The parts of the projected χ² that depend on the data alone (Σw, the mean of ΔΓ and
        # ΔΓ - mean), formed once a pass rather than at every evaluation: row by row, so that
        # a row's are those solve_projected forms among any rows (_loops.projection_data).
        fixed = projection_data(data[2], data[3])
        # The factors of the weighted residuals, √wf·rw and √wg·rw, fixed for the pass: formed
        # once here and their rows gathered with the data's, rather than formed again at every
        # evaluation (_plateau_model's ``weighted``: the same products, element by element; the
        # plateau fits of the 10^4 sweeps of issue 31 0.3 % fewer instructions, the broadcast of
        # √w over each row's points at every evaluation gone).
        weighted = [np.sqrt(wf)[:, None] * data[4], np.sqrt(wg)[:, None] * data[4]]

        # The rows evaluated last and their data: the solver evaluates the same running rows
        # step after step until one of them stops, so they are gathered once for those steps
        # (_plateau_model changes none of its arguments).
        last = [None, None]

        def model(p, i, current=None):
            if last[0] is None or not np.array_equal(last[0], i):
                part = None if within is None else [a[i] for a in within]
                rows = [np.take(a, i, axis=0) for a in data]
                sums = [np.take(a, i, axis=0) for a in fixed]
                both = [np.take(a, i, axis=0) for a in weighted]
                last[:] = [i.copy(), (rows, um[i], wf[i], wg[i], part, sums, both)]
            (u_i, df_i, dg_i, w_i, rw_i), um_i, wf_i, wg_i, part, sums, both = last[1]
            return _plateau_model(
                p, u_i, um_i, df_i, dg_i, w_i, rw_i, wf_i, wg_i, part, current, sums=sums,
                weighted=both,
            )  # fmt: skip

        # Each row's fit at its latest accepted point (the solver's current one: χ² not above
        # the kept one) and where that is: the fit at the solution, with no evaluation again
        # (within this call a row's numbers do not depend on which of its rows are evaluated
        # with it: every evaluation has the call's width of points). Across calls they may:
        # pool_repeats pads each row to the widest row of the call, so a row fitted alone
        # differs from the same row in a batch by rounding (pool_repeats, Notes). Workers 1
        # and 2 agree because each call is one block's sweeps, whichever process runs it.
        # Only what the caller reads of it is kept: χ² and the RSS (pass 1), or also Pκ, Pωξ,
        # θ and the shapes (``full``; x and c follow from θ and p at the end).
        names = ("chi2", "rss_f", "rss_g") + (("A", "B", "theta", "slopes") if full else ())
        at = np.full(np.shape(starts), np.nan)
        kept: dict[str, np.ndarray] = {}

        def keep(fit, i, k=slice(None)):  # the rows i[k] of the evaluation fit
            rows_k = i[k]
            for key in names:
                v = fit[key]
                for j, a in enumerate(v) if key == "slopes" else [(None, v)]:
                    name = key if j is None else f"{key}{j}"
                    if name not in kept:
                        kept[name] = np.empty((len(at), *np.shape(a)[1:]), dtype=np.result_type(a))
                    kept[name][rows_k] = a[k] if isinstance(k, slice) else np.take(a, k, axis=0)

        def evaluate(p, i, jacobian):  # the Gauss-Newton form, complete where accepted
            fit = model(p, i, kept["chi2"][i] if kept else None)
            at[i[fit["accepted"]]] = p[fit["accepted"]]
            keep(fit, i, fit["accepted"])
            return {"chi2": fit["chi2"], "gradient": fit["grad"], "hessian": fit["hess"]}

        options = replace(PLATEAU_LM, xtol=tol, x_abs=1e-10 * tol, ftol=tol)
        p = levenberg_marquardt(evaluate, starts, lo[of], top[of], options)
        again = np.flatnonzero(np.any(at != p.x, axis=1))  # (none: a guard)
        if again.size:
            keep(model(p.x[again], again), again)
        fit = {key: v for key, v in kept.items() if not key.startswith("slopes")}
        if full:
            fit["slopes"] = tuple(kept[f"slopes{j}"] for j in range(6))
            # x and c as _plateau_model formed them from θ and p (the same numbers).
            fit["x"] = fit["theta"][:, None] * data[0]
            fit["c"] = (fit["theta"] * p.x[:, 1] * um)[:, None]
        return p.x, fit

    # Pass 1, weighted by the noise of the hinge fit; started at the hinge and at the amplitude
    # below it (the hinge sits at or above d_c), θ from the loop fitted to the excess; the
    # better of the two (the first on a tie).
    first = np.minimum(u_c / umax, hi[:, 1])
    below = np.max(np.where((w > 0) & (u < (u_c * (1.0 - 1e-9))[:, None]), u, -np.inf), axis=1)
    second = np.where(np.isfinite(below), below / umax, first)
    dl0 = np.concatenate([first, second])
    uc2 = np.tile(u_c / umax, 2)
    ly0 = np.log(np.tile(np.maximum(y0, 1e-300), 2) * (1.0 - dl0) / np.maximum(1.0 - uc2, 1e-12))
    p0 = np.column_stack([np.clip(ly0, *_LY_BOUNDS), dl0])
    # Pass 1 only chooses between the starts and brings pass 2 near the optimum: 1e-4 will do.
    # A second start that is the first (no amplitude below the hinge) is not run twice: a
    # row's iteration depends on its own start and data alone, so it would end where the first
    # does, and the first wins the tie.
    two = np.flatnonzero(second != first)
    p1, fit1 = run(
        p0[np.concatenate([rows, S + two])], sigma_df, sigma_dg, np.r_[rows, two], 1e-4, full=False
    )
    take = rows.copy()
    take[two] = np.where(fit1["chi2"][S:] < fit1["chi2"][two], S + np.arange(two.size), two)
    x1 = p1[take]
    # Pass 2, weighted by the noise of this fit's own residuals (the hinge misfits the onset).
    dof = np.maximum(n - 2, 1)
    sig = [np.sqrt(fit1[k][take] / dof) for k in ("rss_f", "rss_g")]
    p2, fit = run(x1, sig[0], sig[1], rows, 1e-7)
    # A d_c on its bound (PLATEAU_D_C_BOUND): the Cattaneo-Mindlin fit, d_c fixed at 0 (its upper
    # bound set to 0 too) and ln θ(u_max) fitted again from where pass 2 ended.
    bound = np.flatnonzero(p2[:, 1] < PLATEAU_D_C_BOUND)
    if bound.size:
        start = np.column_stack([p2[bound, 0], np.zeros(bound.size)])
        fixed = np.column_stack([hi[:, 0], np.zeros(S)])
        pb, fitb = run(start, sig[0], sig[1], bound, 1e-7, fixed)
        p2[bound] = pb
        for key, v in fitb.items():
            for a, b in zip(fit[key], v, strict=True) if key == "slopes" else [(fit[key], v)]:
                a[bound] = b
    ly, dl = p2[:, 0], p2[:, 1]
    at_zero = dl == 0.0  # the refitted rows, and any row pass 2 left exactly there
    A, theta, d_c = fit["A"], fit["theta"], dl * umax
    # Jacobian of the weighted residuals in (A, B, ln θ, d_c) at fixed d_c and θ respectively.
    g1, g2, g1x, g1c, g2x, g2c = fit["slopes"]
    x, c = fit["x"], fit["c"]
    wf = 1.0 / np.maximum(sig[0], floor_f) ** 2
    wg = 1.0 / np.maximum(sig[1], floor_g) ** 2
    sf, sg = np.sqrt(wf)[:, None] * points[4], np.sqrt(wg)[:, None] * points[4]
    a = -A[:, None]
    zero, one = np.zeros_like(g1), np.ones_like(g1)
    Jf = sf[..., None] * np.stack(
        [-g1, zero, a * (g1x * x + g1c * c), a * g1c * theta[:, None]], axis=-1
    )
    Jg = sg[..., None] * np.stack(
        [-g2, -one, a * (g2x * x + g2c * c), a * g2c * theta[:, None]], axis=-1
    )
    J = np.concatenate([Jf, Jg], axis=1)  # (S, 2M, 4)
    # d_c held at 0: no d_c column (pinv of the then block-diagonal JᵀJ is the inverse of the
    # (Pκ, Pωξ, ln θ) block, the constrained fit's covariance, and zero for d_c).
    J[at_zero, :, 3] = 0.0
    # Columns scaled to unit norm first: d_c in m makes JᵀJ too ill-scaled for pinv's cutoff.
    norm = np.linalg.norm(J, axis=1)
    norm = np.where(norm > 0, norm, 1.0)
    Js = J / norm[:, None, :]
    cov = pinv_finite(np.einsum("smi,smj->sij", Js, Js)) / (norm[:, :, None] * norm[:, None, :])
    cov *= (fit["chi2"] / np.maximum(2 * n - 4, 1))[:, None, None]
    edge = np.where(ly > hi[:, 0] - 1e-6, "high", np.where(ly < lo[:, 0] + 1e-6, "low", ""))
    return pd.DataFrame(
        {
            **loop_fit_fields(A, fit["B"], theta, cov, umax),
            "d_c_m": d_c,
            # d_c at its bound 0: no error the data give (NaN), nor covariances.
            "d_c_err_m": np.where(at_zero, np.nan, np.sqrt(cov[:, 3, 3])),
            # d_c's covariances with Δf0 and ln θ: the joint error of μ and d_c, which the fit
            # trades against each other (a later onset of slip: a larger μ or a wider plateau).
            "cov_df0_d_c": np.where(at_zero, np.nan, cov[:, 0, 3]),
            "cov_lntheta_d_c": np.where(at_zero, np.nan, cov[:, 2, 3]),
            "edge": edge,
            "rss_df": fit["rss_f"],
            "rss_dgamma": fit["rss_g"],
        }
    )
