"""Linear-algebra helpers of the particle fit (:mod:`contactres.analysis._particles`).

The closed-form pieces of :func:`~contactres.analysis.fit_particles`, batched over the time
steps: the equation-error start (the model multiplied out, linear in κ, ξ, Nκ, Nξ), the start
in the limit of particles standing still, the χ² of the model's two limits (a rigid contact;
particles standing still) and of no particles at all, the inverse of the stacked normal
matrices that marks an unidentified direction, and the noise variance of a series.
Notation as there: z = Δf + iΔΓ (Hz), s = 2nπ²Z_q, c, h, g of
:func:`~contactres.resonators.particle_compliance`, weights wf = 1/σ_Δf and wg = 1/σ_ΔΓ (0 where
an overtone is not measured).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "equation_error",
    "grid_coordinates",
    "heavy_start",
    "limit_chi2",
    "limit_threshold",
    "misfit",
    "model_variance",
    "no_signal_threshold",
    "pooled_variance",
    "poor_fit",
    "scan_start",
    "series_variance",
    "stacked_inverse",
    "weighted_parts",
    "wide_values",
    "wider_than_linear",
]

#: The fewest converged steps a series needs for its pooled noise variance.
MIN_POOLED_STEPS = 20


def weighted_parts(parts: list[np.ndarray], wf: np.ndarray, wg: np.ndarray) -> np.ndarray:
    """The weighted real and imaginary parts of K arrays z_k (rows, n) side by side, as the
    fit's residuals (K = 1) or Jacobian: (rows, 2n, K) with Re z_k wf in [:, :n, k] and
    Im z_k wg in [:, n:, k], each product written into its place (no stacked and concatenated
    copies: the fit evaluates this once per Levenberg-Marquardt step, hundreds of times for a
    series of pure noise)."""
    m, n = parts[0].shape
    out = np.empty((m, 2 * n, len(parts)))
    for k, z in enumerate(parts):  # (the K parameters, not the data)
        np.multiply(z.real, wf, out=out[:, :n, k])
        np.multiply(z.imag, wg, out=out[:, n:, k])
    return out


def series_variance(chi2, dof, conv):
    """The noise variance of a time series: the median χ²/dof of its converged steps, or 0
    (every step counts as a poor fit) for fewer than 20 of them."""
    ok = conv & (dof > 0) & np.isfinite(chi2)
    if ok.sum() < 20:
        return 0.0
    return float(np.median(chi2[ok] / dof[ok]))


def pooled_variance(chi2, dof, conv):
    """The noise variance of a time series pooled over its steps, robustly: the median over
    the converged steps of χ²_i/med(ν_i), med(ν) the median of a χ² variable of ν degrees of
    freedom (so that it estimates σ² without bias for Gaussian noise, and a minority of steps
    that the model does not fit, e.g. a jump, does not move it). NaN for fewer than
    :data:`MIN_POOLED_STEPS` such steps (a single step's χ²/ν then has to do, with the F
    thresholds of :func:`limit_threshold`)."""
    from scipy.stats import chi2 as chi2_dist

    ok = conv & (dof > 0) & np.isfinite(chi2)
    if ok.sum() < MIN_POOLED_STEPS:
        return np.nan
    return float(np.median(chi2[ok] / chi2_dist.median(dof[ok])))


def limit_threshold(limit, dof, q, per_step):
    """Δχ² (in noise variances) below which a limit of the model is not rejected.

    With the noise known (stated, or pooled over a series: :func:`pooled_variance`) that is
    ``limit``, read as a χ²-test of q parameters. With the noise of each step estimated from
    its own residuals (s² = χ²/ν, ν = ``dof``), Δχ²/(q s²) is F(q, ν)-distributed: the
    threshold has the same tail probability as ``limit`` for χ²(q), q F⁻¹(P; q, ν) (larger:
    an estimated s² scatters, and Δχ²/s² < 9 let 8 % of pure-noise steps past the
    no-signal test at ν = 11 instead of 3 %)."""
    from scipy.stats import chi2 as chi2_dist
    from scipy.stats import f as f_dist

    if not per_step:
        return np.full(np.shape(dof), float(limit))
    nu = np.maximum(np.asarray(dof, float), 1.0)
    return q * f_dist.isf(chi2_dist.sf(limit, q), q, nu)


#: The largest share of pure-noise steps (shifts at the noise level alone) that may pass the
#: no-signal test and print a κ: at most one step in 10⁴ (:func:`no_signal_threshold`).
NO_SIGNAL_RATE = 1e-4


def no_signal_threshold(count, dof, q, per_step, rate=NO_SIGNAL_RATE):
    """(T,) Δχ² (in noise variances) the fit must gain over the empty model (no particles,
    z = 0) for the step to count as a signal, from the number of overtones ``count`` (M).

    The Δχ² of the fit against the empty model is not χ²(q) under pure noise: the fit's
    resonance can be placed on any of the M overtones, and it takes the best of them (a
    look-elsewhere effect; with the plain χ²(3) threshold of 9, 4 % of pure-noise steps passed
    and 0.5-1 % printed a κ, issue 28). The rule counts each overtone as a trial of its own
    and splits the ``rate`` between them (Bonferroni): the χ²(q) quantile at tail probability
    rate/M, or with the noise estimated per step (s² = χ²/ν, ν = ``dof``) q F⁻¹(rate/M; q, ν),
    as :func:`limit_threshold` does. For rate = 1e-4, q = 3: 25.2 at M = 7, 23.4 at M = 3,
    26.4 at M = 13. In seeded simulations of pure noise (3000-5000 steps;
    n = 1, 3, ..., 13 in vacuum and water, and M = 3 and 13 in vacuum) the tail of the Δχ²
    at 9-20 was 0.3-3 times that of χ²(3), far below M times it: the rule is conservative
    and the rate it states an upper bound (no step of 16 000 passed at these thresholds).

    Parameters
    ----------
    count : (T,) array of int
        Overtones measured at each step (M).
    dof : (T,) array of int
        Degrees of freedom of the fit, 2M - q (used with ``per_step``).
    q : int
        Parameters of the fit (3, or 4 with a fitted rocking stiffness).
    per_step : bool
        True where the noise is estimated from each step's own residuals.
    rate : float
        Tail probability of the whole test per step (default :data:`NO_SIGNAL_RATE`)."""
    from scipy.stats import chi2 as chi2_dist
    from scipy.stats import f as f_dist

    tail = rate / np.maximum(np.asarray(count, float), 1.0)
    if not per_step:
        return chi2_dist.isf(tail, q)
    nu = np.maximum(np.asarray(dof, float), 1.0)
    return q * f_dist.isf(tail, q, nu)


#: A step whose χ² (in noise variances) exceeds its χ²(ν) quantile at 1 - this fits badly.
POOR_FIT_P = 1e-4


def poor_fit(chi2, dof, s2, per_step):
    """(T,) True where the fit's χ²/s² lies beyond the χ²(ν) quantile at 1 - :data:`POOR_FIT_P`:
    with the noise known (stated, or pooled over a series) a test of the fit. Below the comb
    the fit can stop far from its minimum (at 30 times the χ² of the truth), where its
    linearised errors are meaningless: such a step is reported as no value. With the noise
    estimated per step from the same χ² there is no test (all False)."""
    from scipy.stats import chi2 as chi2_dist

    if per_step:
        return np.zeros(np.shape(chi2), bool)
    nu = np.maximum(np.asarray(dof, float), 1.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return ~(chi2 / s2 <= chi2_dist.isf(POOR_FIT_P, nu))


#: The model misfits where its noise variance exceeds the series' own by the F quantile at 1 -
#: this (:func:`misfit`).
MISFIT_P = 1e-4

#: The efficiency of the MAD as an estimate of a Gaussian spread: its variance is that of a
#: standard deviation from this fraction of the values (Huber, Robust Statistics, 1981, §5.5).
MAD_EFFICIENCY = 0.37


def model_variance(chi2, dof, conv):
    """The noise variance the fit's residuals imply: pooled over the series
    (:func:`pooled_variance`), or for a short series the median over its converged steps of
    χ²/ν; NaN where no step has a degree of freedom."""
    pooled = pooled_variance(chi2, dof, conv)
    if np.isfinite(pooled):
        return pooled
    ok = conv & (dof > 0) & np.isfinite(chi2)
    return float(np.median(chi2[ok] / dof[ok])) if ok.any() else np.nan


def misfit(s2_model, s2_series, dof, count):
    """True where the model does not fit the data: the noise variance of its residuals,
    ``s2_model`` (:func:`model_variance`; ν₁ the median degrees of freedom of a step, fewer
    than the pooled series has, so the test is cautious), exceeds that of the series read off
    its step-to-step differences, ``s2_series`` (``_particle_input.difference_noise``, from
    ``count`` differences; ν₂ = count × :data:`MAD_EFFICIENCY`), beyond the quantile of F(ν₁,
    ν₂) at 1 - :data:`MISFIT_P`. With the noise estimated, the residuals absorb a systematic
    misfit into s², and the errors grow with it while the values are those of a wrong model:
    only a noise known independently of the model tells the two apart. False where there is
    no independent estimate (fewer than 5 steps, or a series of identical values)."""
    from scipy.stats import f as f_dist

    if not (np.isfinite(s2_model) and np.isfinite(s2_series) and s2_series > 0 and count > 0):
        return False
    nu = np.asarray(dof, float)
    nu1 = max(float(np.median(nu[nu > 0])) if np.any(nu > 0) else 1.0, 1.0)
    nu2 = max(MAD_EFFICIENCY * count, 1.0)
    return bool(s2_model / s2_series > f_dist.isf(MISFIT_P, nu1, nu2))


def stacked_inverse(h):
    """(JᵀJ)⁻¹ of a stack, inf on the diagonal where it is singular (an unidentified
    direction) instead of the finite nonsense of a pseudo-inverse."""
    d = np.sqrt(np.maximum(np.diagonal(h, axis1=1, axis2=2), 1e-300))
    hn = h / (d[:, :, None] * d[:, None, :])
    ev = np.linalg.eigvalsh(hn)
    singular = ~(ev[:, 0] > 1e-14 * ev[:, -1])
    safe = np.where(singular[:, None, None], np.eye(h.shape[-1]), hn)
    inv = np.linalg.inv(safe) / (d[:, :, None] * d[:, None, :])
    return np.where(singular[:, None, None], np.inf, inv)


def equation_error(z, wf, wg, sens, omega, chg, kappa_fixed=None, sweeps=4):
    """κ, ξ, N (T,) from the model multiplied out, linear in (κ, ξ, Nκ, Nξ) once N g is known:

        z s c (κ + iωξ) + (z s - N g) = ((1 - h)² + g c)(Nκ + iω Nξ)
        (from z s = N[(1 - h)²/(c + 1/k) + g], times (c k + 1))

    solved by weighted least squares ``sweeps`` times, each with N g from the sweep before (0
    at first; g = 0 in vacuum) and reweighted with the noise of each equation, |s(ck + 1)| σ
    (Sanathanan-Koerner). N = Nκ/κ. With ``kappa_fixed`` (T,) κ is held. Exact for noise-free
    data in vacuum, and in a liquid at convergence; a start, not the fit."""
    c, h, g = chg
    zs = z * sens
    # the variance of one complex equation's noise, the mean of the two observables'
    sf, sg = 1.0 / np.where(wf > 0, wf, 1.0), 1.0 / np.where(wg > 0, wg, 1.0)
    sig2 = np.where(wf > 0, 0.5 * (sf**2 + sg**2), 0.0)
    lin = (1.0 - h) ** 2 + g * c + 0 * zs
    cols = [zs * c, 1j * omega * zs * c, -lin, -1j * omega * lin]
    if kappa_fixed is not None:
        cols = cols[1:]
    a = np.concatenate(
        [np.stack([col.real for col in cols], -1), np.stack([col.imag for col in cols], -1)], 1
    )
    w = np.where(wf > 0, 1.0 / np.where(sig2 > 0, sig2, 1.0), 0.0)
    n_g = np.zeros(z.shape[0])
    x = None
    for _ in range(sweeps):
        rhs = -(zs - n_g[:, None] * g)
        if kappa_fixed is not None:
            rhs = rhs - zs * c * kappa_fixed[:, None]
        b = np.concatenate([rhs.real, rhs.imag], 1)
        ww = np.concatenate([w, w], 1)
        aw = a * np.sqrt(ww)[:, :, None]
        bw = b * np.sqrt(ww)
        d = np.sqrt(np.maximum(np.einsum("rgp,rgp->rp", aw, aw), 1e-300))
        an = aw / d[:, None, :]
        m = np.einsum("rgp,rgq->rpq", an, an) + 1e-12 * np.eye(a.shape[-1])
        rhs_n = np.einsum("rgp,rg->rp", an, bw)[:, :, None]
        good = np.all(np.isfinite(m), axis=(1, 2)) & np.all(np.isfinite(rhs_n), axis=(1, 2))
        m = np.where(good[:, None, None], m, np.eye(a.shape[-1]))
        x = np.linalg.solve(m, np.where(good[:, None, None], rhs_n, np.nan))[:, :, 0] / d
        kap = kappa_fixed if kappa_fixed is not None else x[:, 0]
        k = kap[:, None] + 1j * omega * x[:, 1 if kappa_fixed is None else 0, None]
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            # the next weights and N g; a start that overflows here keeps the last ones
            var = sig2 * np.abs(sens * (c * k + 1.0)) ** 2
            w_new = np.where(wf > 0, 1.0 / np.where(var > 0, var, 1.0), 0.0)
            n_new = x[:, -2] / kap
        w = np.where(np.isfinite(w_new), w_new, w)
        n_g = np.where(np.isfinite(n_new) & (n_new > 0), n_new, n_g)
    if kappa_fixed is not None:
        x = np.column_stack([kappa_fixed, x])
    kappa, xi, a_nk = x[:, 0], x[:, 1], x[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        cov = a_nk / kappa
    ok = (kappa > 0) & (cov > 0)
    return np.where(ok, kappa, np.nan), np.maximum(xi, 0.0), np.where(ok, cov, np.nan)


def heavy_start(z, wf, wg, sens, omega, h, kappa):
    """A start in the limit of particles standing still (paper 2, Eq. 1): N·κ and N·ξ from
    z s = (1 - h)² (Nκ + iω Nξ) by weighted linear least squares (2 × 2 normal equations per
    step), then κ as given (a scalar, N/m), N = Nκ/κ and ξ = Nξ/N.

    Returns
    -------
    kappa, xi, cov : (T,) κ (N/m), ξ (kg/s, 0 where not finite or negative), N (per m², NaN
        where not positive)
    """
    u = (1.0 - h) ** 2 / sens + 0 * z
    cols = [u, 1j * omega * u]
    a = [np.concatenate([col.real * wf, col.imag * wg], 1) for col in cols]
    y = np.concatenate([z.real * wf, z.imag * wg], 1)
    m = np.array([[np.sum(ai * aj, 1) for aj in a] for ai in a])  # (2, 2, T)
    r = np.array([np.sum(ai * y, 1) for ai in a])
    det = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        nk = (m[1, 1] * r[0] - m[0, 1] * r[1]) / det
        nx = (m[0, 0] * r[1] - m[1, 0] * r[0]) / det
        cov = nk / kappa
        xi = np.maximum(nx / cov, 0.0)
    t = z.shape[0]
    return np.full(t, kappa), np.where(np.isfinite(xi), xi, 0.0), np.where(cov > 0, cov, np.nan)


def limit_chi2(z, wf, wg, sens, omega, chg):
    """χ² (T,) of the best fits of the model's two limits, both linear least squares:
    a rigid contact, z = N[(1 - h)²/c + g]/s (N free), and particles standing still,
    z = [(1 - h)²(Nκ + iω Nξ) + N g]/s (Nκ, Nξ, N free; g = 0 in vacuum); and of the empty
    model (no particles, z = 0): χ²₀ = Σ wf² (Re z)² + wg² (Im z)².

    Returns
    -------
    rigid, still, empty : (T,) χ² of the three, in the units of the weights"""
    c, h, g = chg
    zr, zi = z.real * wf, z.imag * wg

    def chi2_of(basis):
        a = np.stack([np.concatenate([b.real * wf, b.imag * wg], 1) for b in basis], -1)
        y = np.concatenate([zr, zi], 1)
        d = np.sqrt(np.maximum(np.einsum("rgp,rgp->rp", a, a), 1e-300))
        an = a / d[:, None, :]
        m = np.einsum("rgp,rgq->rpq", an, an) + 1e-12 * np.eye(len(basis))
        good = np.all(np.isfinite(m), axis=(1, 2))
        m = np.where(good[:, None, None], m, np.eye(len(basis)))
        x = np.linalg.solve(m, np.einsum("rgp,rg->rp", an, y)[:, :, None])
        r = y - (an @ x)[:, :, 0]
        return np.where(good, np.sum(r * r, axis=1), np.inf)

    c_b, h_b, g_b = np.broadcast_arrays(c, h, g, z)[:3]
    one_h2 = (1.0 - h_b) ** 2
    rigid = chi2_of([(one_h2 / c_b + g_b) / sens])
    still = chi2_of([one_h2 / sens, 1j * omega * one_h2 / sens, g_b / sens])
    empty = np.sum(zr * zr + zi * zi, axis=1)
    return rigid, still, empty


def scan_start(unit, grid, z, wf, wg):
    """The best of a grid of contacts (κ, ξ), the coverage fitted linearly at each (z = N u is
    linear in N: N = Σ w² Re(ū z)/Σ w²|u|² over both observables, and the χ² of that optimum
    Σ w²|z|² - (Σ w² Re(ū z))²/Σ w²|u|²), as matrix products over the grid.

    Parameters
    ----------
    unit : (G, n) complex shifts of a unit coverage at each grid point, Hz (the same at every
        time step: the contact is given)
    grid : (G, 2+) κ (N/m) and ξ (kg/s) of the grid points (columns beyond are ignored)
    z, wf, wg : (T, n) shifts (Hz) and weights (module docstring)

    Returns
    -------
    best : (T, 3) κ, ξ, N of the lowest χ² (NaN where no grid point has N > 0)
    (points, chi2) : (G, T, 3) and (G, T) every grid point and its χ² (inf where N <= 0)
    """
    a, b = wf**2, wg**2
    u = np.where(np.isfinite(unit), unit, np.nan)
    ur, ui = np.nan_to_num(u.real), np.nan_to_num(u.imag)
    num = (a * z.real) @ ur.T + (b * z.imag) @ ui.T
    den = a @ (ur**2).T + b @ (ui**2).T
    with np.errstate(divide="ignore", invalid="ignore"):
        cov = (num / den).T  # (G, T)
        chi2 = np.sum(a * z.real**2 + b * z.imag**2, 1) - (num * num / den).T
    ok = (cov > 0) & np.all(np.isfinite(unit), axis=1)[:, None]
    chi2 = np.where(ok, np.maximum(chi2, 0.0), np.inf)
    g, t = chi2.shape
    points = np.empty((g, t, 3))
    points[..., 0], points[..., 1], points[..., 2] = grid[:, 0:1], grid[:, 1:2], cov
    best = np.take_along_axis(points, np.argmin(chi2, axis=0)[None, :, None], 0)[0]
    return np.where(np.isfinite(chi2.min(axis=0))[:, None], best, np.nan), (points, chi2)


def wider_than_linear(value, error, others, dchi2, near, factor):
    """(T,) True where a point near the fit lies farther from it in this value than the
    linearised error allows at that point's Δχ² (by more than ``factor``).

    For a model linear in its parameters the profile of one value is the parabola
    Δχ² = ((u - û)/σ)², σ the linearised error: a point with Δχ² = D lies at most σ√D from
    û in that value. A point the fit's search visited (``others`` (S, T), with its ``dchi2``
    (S, T) in noise variances, considered where ``near`` (S, T)) farther out than
    ``factor`` × σ √max(D, 1) shows the profile interval (the likelihood-ratio interval; e.g.
    Press et al., Numerical Recipes, 3rd ed., §15.6.5) wider than ±σ by more than ``factor``
    at that level: the printed error would understate the scatter. ``value``, ``error`` (T,).
    """
    with np.errstate(invalid="ignore"):
        allowed = factor * error * np.sqrt(np.maximum(dchi2, 1.0))
        far = np.abs(others - value) > allowed
    return np.any(near & far & np.isfinite(others), axis=0)


def grid_coordinates(points, xi_scale):
    """(S, T, 3) grid points (κ, ξ, N) in the fit's coordinates (ln κ, ξ/scale, ln N)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.stack(
            [np.log(points[..., 0]), points[..., 1] / xi_scale, np.log(points[..., 2])], -1
        )


def wide_values(values, errors, visited, xi_scale, dchi2, near, factor):
    """:func:`wider_than_linear` for κ, ξ, N, κ_r, N·κ and N·ξ (six (T,) arrays each of
    ``values`` and ``errors``) over the ``visited`` points (S, T, P) in the fit's
    coordinates (ln κ, ξ/``xi_scale``, ln N, ln κ_r); κ_r only with P = 4.

    Returns
    -------
    wide : list of six (T,) bool
    widened : tuple of six (T,) errors, each at least the distance of every near point
        from the fit in that value over √max(D, 1): the half-width of the profile interval at
        Δχ² = 1 that a model linear in its parameters would need to hold those points (N·κ and
        N·ξ are printed with it: blanking them by rule 5 selected the draws)
    """
    with np.errstate(invalid="ignore", over="ignore"):
        kap, xi, cov = np.exp(visited[..., 0]), visited[..., 1] * xi_scale, np.exp(visited[..., 2])
        kr = np.exp(visited[..., 3]) if visited.shape[-1] > 3 else np.full_like(kap, np.nan)
        others = (kap, xi, cov, kr, kap * cov, xi * cov)
        scale = np.sqrt(np.maximum(dchi2, 1.0))
        use = near & np.isfinite(dchi2)
        widened = tuple(
            np.fmax(e, np.max(np.where(use & np.isfinite(o), np.abs(o - v) / scale, 0.0), axis=0))
            for v, e, o in zip(values, errors, others, strict=True)
        )
    wide = [
        wider_than_linear(v, e, o, dchi2, near, factor)
        for v, e, o in zip(values, errors, others, strict=True)
    ]
    return wide, widened
