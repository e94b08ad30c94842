"""Contact stiffness, damping and coverage of attached particles from QCM-D shifts (issue 28).

The inverse of :func:`~contactres.resonators.particle_shifts`: from Δf_n and ΔΓ_n over the
measured overtones, per time step, the contact stiffness κ, its drag coefficient ξ and the
coverage N/A (and, with ``rocking="fit"``, a rotational stiffness κ_r), with errors,
correlations and the statement of what the data identify.

Model (theory page docs/theory/particles.md): Δf_n + iΔΓ_n = N K_L(ω_n)/(2nπ² Z_q) with
K_L = (1 - h)²/(c + 1/k) + g, k = κ + iωξ, where c, h and g describe the given particle
(:func:`~contactres.resonators.particle_compliance`).

Starts. Multiplied out by (ck + 1), the model is linear in (κ, ξ, Nκ, Nξ) once the small term
N g is known: z_n s_n c_n (κ + iω_n ξ) + (z_n s_n - N g_n) = ((1 - h_n)² + g_n c_n)(Nκ + iω_n Nξ),
with z_n = Δf_n + iΔΓ_n and s_n = 2nπ²Z_q; its weighted least squares, iterated with N g and
the weights of the propagated noise (Sanathanan-Koerner), is exact for noise-free data (the
"equation-error" start; ``_particle_linear``). Three more starts: the same with κ held where the
peak of nΔΓ_n puts the coupled resonance (Im K_L peaks at f_coupled); the Sauerbrey limit
(κ 10⁴ above the stiffness of a resonance at the top of the comb, the coverage fitted
linearly); and the heavy-particle limit of paper 2, Eq. 1 (κ 10⁴ below a resonance at the
bottom, with Nκ and Nξ from the linear fit of that limit). With rocking="fit" each start is the
best over a scan of κ_r. Without it, a fifth: the best point of a grid of resonances from 10x
below the lowest overtone up to it (loss tangents 0-0.3, the coverage fitted linearly at each;
``_particle_linear.scan_start``): below the comb the χ² has a second valley towards the
particles standing still, where the other starts stopped 10 noise variances above the minimum
near the truth (a third of the draws 2.5x below the comb in water, N·κ printed 8σ off).
Each is refined by the batched Levenberg-Marquardt of
:func:`contactres.fitting.levenberg_marquardt` in its Gauss-Newton form (all time steps at once:
no loop over steps) in ln κ, ξ, ln N (ln κ_r; a step changes a logarithm by at most 2 and ξ
by at most twice itself), within bounds 10⁸ beyond what the comb can see,
and the lowest χ² is kept. A start after the first is refined only where it begins below the
best fit so far, where that did not converge, where it fits poorly (χ² beyond dof + 2√(2 dof)
noise variances), or, for a limit start, where the best fit so far puts the coupled resonance
on the limit's side of the comb (the valley towards a limit can hold a second minimum);
refining every start everywhere costs several times more. Where the best fit then puts the
coupled resonance below the lowest overtone, the χ² is profiled along κ
(``_particle_profile.valley_profile``: κ held at 1/10 to 10 times the fit's, ξ and N fitted):
the valley of nearly constant N·κ and N·ξ has a second, shallower minimum on its stiff side,
where the search stopped in a quarter of the draws at f_F/10 in water with |Δf| up to 60 Hz
(N·κ printed 3-6σ off, its scatter twice its error). The profile's lowest point, refined with
κ free, replaces the fit where it fits better, and its points join the interval test (5.).

Errors. The covariance is (JᵀJ)⁻¹ with the residuals weighted by the stated noise
(``sigma_df``, ``sigma_dgamma``: errors from the noise model alone, χ² a test of it); without
a stated noise both observables get one noise level, estimated from the residuals and pooled
over the steps of the series (robustly: the median of χ²_i/med(ν_i), ν_i = 2M_i - p, M_i the
overtones measured at step i; ``_particle_linear.pooled_variance``), and the covariance is
scaled by it. A series of fewer than 20 steps estimates it per step (s² = χ²/ν), and the limit
tests below then use F thresholds of the same tail probability (``limit_threshold``): with the
per-step s² and the plain Δχ² < 9, 1 % of pure-noise steps printed a κ. That needs
``MIN_DOF_ESTIMATED`` (4) degrees of freedom: a step with fewer is flagged "too-few-overtones",
and data with fewer at every step are refused (state the noise).

Identifiability (the rule; names in :data:`PARTICLE_FLAGS`). Per time step:

1. The two limits of the model are fitted by linear least squares: a rigid contact (κ -> ∞,
   z = N[(1 - h)²/c + g]/s, N free) and particles standing still
   (z = [(1 - h)²(Nκ + iωNξ) + N g]/s, Nκ, Nξ and N free; g = 0 in vacuum). A limit whose
   χ² exceeds the fit's by less than :data:`LIMIT_CHI2` (9, in units of the noise variance;
   the F threshold of the same tail probability for a per-step variance) is not rejected:
   "sauerbrey-like" (κ and ξ unresolved: only the mass N·m) or "inertial" (κ, ξ and N
   unresolved: only N·κ and N·ξ, reported as ``coverage_kappa`` and ``coverage_xi``).
   The empty model (no particles, z = 0, χ²₀ = Σ w²|z|²) is the third limit, with a threshold
   of its own (``_particle_linear.no_signal_threshold``): the fit may put its resonance on any
   of the M overtones, so χ²₀ - χ² is not χ²(3) under pure noise; each overtone counts as a
   trial and the test lets pure noise through at most once in 10⁴ steps (25.2 for M = 7; the
   plain 9 let 4 % through and printed κ in 0.2-1 % of pure-noise steps). If it is not
   rejected the step is "no-signal" and every value (the products too) is left empty, so
   that noise before adsorption does not print a κ.
2. Any parameter whose relative standard error exceeds :data:`RELATIVE_ERROR_LIMIT` (0.3), or
   is not finite, is unresolved ("xi-unresolved" is the usual one: a loss at the noise level).
3. A fit that did not converge, or whose χ² is far beyond what the noise allows ("poor-fit";
   ``_particle_linear.poor_fit``: below the comb the fit can stop at 30 times the χ² of the
   truth), leaves every parameter unresolved, the products N·κ and N·ξ too. In a liquid, the
   overtones at which the particle is smaller than the penetration depth
   (:func:`~contactres.resonators.particle_model_validity`; δ is largest at the lowest) are
   left out of the fit and named in the flag "dropped-overtones-R<delta: 1,3"; where too few
   remain (fewer than 2, or than 4 degrees of freedom with the noise estimated) none is
   dropped and every parameter is unresolved ("particle-smaller-than-delta").
4. Outside the comb a parameter is printed only with a relative error up to 0.2 (κ, ξ) or 0.1
   (the coverage, κ_r; ``RELATIVE_ERROR_OUTSIDE``). Below the comb κ's relative error falls
   as the fitted κ rises (the term that sets κ grows with it), so a cut where the typical
   error lies prints the stiff draws only: at 10 % for κ and ξ (f_coupled = 3 MHz in vacuum,
   N = 1e9 m⁻²) κ was printed in 42 of 100 draws with a mean z of +1.0, ξ in 11 with +1.9;
   at 20 % in all, unbiased. Rule 5 now catches the curved valleys the 10 % was set for. The
   coverage keeps 10 %: above it, rule 5 printed it where its estimate came out low.
5. A value (κ, ξ, N, κ_r, N·κ, N·ξ) is unresolved ("wide-interval") where a point the search
   visited (starts, refined fits, the grid, the profile below the comb) with Δχ² = D below
   :data:`LIMIT_CHI2` lies farther from the fit in that value than ``PROFILE_FACTOR`` σ√max(D, 1)
   (``_particle_linear.wider_than_linear``): for a model linear in its parameters no point can
   lie beyond σ√D, so the profile-likelihood interval is wider than the printed error says
   (below the comb: a second minimum whose N·κ lies ~20 % from the first's). The products
   N·κ and N·ξ are not blanked by it but printed with their error widened to hold every such
   point (at least its distance over √max(D, 1); ``widened`` of
   ``_particle_linear.wide_values``): blanked, the draws printed were those whose second
   minimum lay farther out, i.e. whose estimate lay on one side (f_coupled = 2 MHz in water,
   N = 1e9 m⁻²: N·κ in 94 of 400 draws, mean z +1.3, 12 % beyond 3σ; now all 400, +0.6, 2 %).

Unresolved values are NaN, with their errors; f_coupled goes with κ (and with κ_r where that is
fitted: an unresolved κ_r leaves f_coupled empty and not flagged "outside-comb", since the
modes of an unidentified κ_r say nothing of where the data's resonance lies). "outside-comb"
says that the fitted coupled resonance lies outside [n_min f_F, n_max f_F] of the measured
overtones (information: a resonance just outside the comb can still be resolved);
"overdamped", a note that blanks nothing, that the loss tangent ωξ/κ at f_coupled exceeds 1
(quality factor below 1: ΔΓ_n shows no peak at the resonance, f_coupled is that of the
undamped contact). The
likelihood-ratio test of step 1 matters: far outside the comb the linearised error can look
small at a point that is many of its σ from the truth, while the limit fits the data as well.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..fitting import LMOptions, levenberg_marquardt
from ..resonators import Medium, Particle, coupled_resonance, particle_compliance
from ..validation import positive
from ._particle_flags import PARTICLE_FLAGS, dropped_named, noise_checked, outside_cut
from ._particle_input import drop_inside_delta, noise_check, prepare
from ._particle_linear import (
    equation_error,
    grid_coordinates,
    heavy_start,
    limit_chi2,
    limit_threshold,
    no_signal_threshold,
    pooled_variance,
    poor_fit,
    scan_start,
    series_variance,
    stacked_inverse,
    weighted_parts,
    wide_values,
)
from ._particle_profile import valley_profile
from ._particle_summary import FitSummary

__all__ = [
    "LIMIT_CHI2",
    "PARTICLE_FLAGS",
    "RELATIVE_ERROR_LIMIT",
    "ParticleFit",
    "fit_particles",
]

#: A fitted value whose relative standard error exceeds this is reported as unresolved (NaN).
RELATIVE_ERROR_LIMIT = 0.3

#: ... and outside the overtone comb, where the fit is far from linear at that scale, for κ,
#: ξ, the coverage and κ_r (module docstring, rule 4: a cut on a quantity that falls as κ̂
#: rises selects the stiff draws where the typical error lies near it).
RELATIVE_ERROR_OUTSIDE = (0.2, 0.2, 0.1, 0.1)

#: A limit of the model (rigid contact; particles standing still) whose best χ² exceeds the
#: fit's by less than this (in units of the noise variance) is not rejected by the data.
LIMIT_CHI2 = 9.0

#: With the noise estimated from the residuals, the fewest degrees of freedom (2M - p, M
#: overtones, p parameters) a step needs: with fewer, s² = χ²/dof scatters so much that the
#: errors are not calibrated (two overtones, 1 dof: 20 % of the draws beyond 3σ).
MIN_DOF_ESTIMATED = 4

#: A value is printed only where no point the fit visited within the limit test's Δχ² lies
#: farther from it than this factor times σ√max(Δχ², 1) (issue 28's factor between error
#: and scatter).
PROFILE_FACTOR = 1.3


# Scan of κ_r for rocking="fit", in units of I (2π f_F)² (a rocking mode at f_F √(value)).
_ROCKING_SCAN = np.logspace(-2.0, 4.0, 13)


# ξ (column 1) is no logarithm: its steps are capped at 2 max(|ξ|, 1) in units of its scale,
# the logarithms' at 2. Capped at 2 units, ξ crawled on pure noise (χ² still falling) and most
# rows ran to max_iter; a drift of ξ to 10⁴ of its scale now takes ~9 steps.
_LM = LMOptions(max_iter=300, xtol=1e-8, ftol=1e-10, max_step=2.0, relative_step=(1,))
# the scan start begins in the flat valley below the comb, where the steps are short
_LM_SCAN = replace(_LM, max_iter=2000)


# repr=False: the summary (FitSummary) replaces the numpy reprs of every series.
@dataclass(frozen=True, repr=False)
class ParticleFit(FitSummary):
    """Result of :func:`fit_particles`: arrays over the T time steps (NaN where unresolved).

    Attributes
    ----------
    kappa, kappa_err : contact stiffness κ and its standard error, N/m
    xi, xi_err : contact drag coefficient ξ, kg/s
    coverage, coverage_err : particles per m²
    f_coupled, f_coupled_err : coupled resonance, Hz
        (:func:`~contactres.resonators.coupled_resonance`; the lower mode where there are two)
    kappa_r, kappa_r_err : rotational stiffness, N m/rad (NaN unless rocking="fit")
    coverage_kappa, coverage_kappa_err : the product N·κ, N/m per m² (what an inertial
        response identifies: paper 2's Eq. 1 gives n_P κ/A_eff), NaN only where it is itself
        unresolved
    coverage_xi, coverage_xi_err : the product N·ξ, kg/s per m²
    parameters : names of the fitted parameters, in the order of ``correlation``
    correlation : (T, p, p) correlation matrix of the fitted parameters (ln κ, ξ, ln N, ln κ_r)
    chi2 : χ² of each step (weighted by the stated noise; in Hz² without one)
    dof : degrees of freedom, 2M - p
    df_model, dgamma_model : (T, n) the fitted model at every overtone of ``overtones``, Hz
        (also where a parameter is unresolved: the curve is identified when its parts are not)
    raw : (T, p) the fitted values before the identifiability rule (κ, ξ, N, κ_r)
    flags : per step, a tuple of names of :data:`PARTICLE_FLAGS`
    noise_fit : the noise σ̂ (Hz) the residuals imply, one for Δf and ΔΓ
        (``_particle_linear.model_variance``); NaN with a stated noise
    noise_series : the noise (Hz) read off the series' step-to-step differences, independently
        of the model (``_particle_input.difference_noise``); NaN for fewer than 5 steps or with a
        stated noise. Where σ̂ exceeds it beyond an F quantile every step is "model-misfit"
    """

    kappa: np.ndarray
    kappa_err: np.ndarray
    xi: np.ndarray
    xi_err: np.ndarray
    coverage: np.ndarray
    coverage_err: np.ndarray
    f_coupled: np.ndarray
    f_coupled_err: np.ndarray
    kappa_r: np.ndarray
    kappa_r_err: np.ndarray
    coverage_kappa: np.ndarray
    coverage_kappa_err: np.ndarray
    coverage_xi: np.ndarray
    coverage_xi_err: np.ndarray
    parameters: tuple[str, ...]
    correlation: np.ndarray
    chi2: np.ndarray
    dof: np.ndarray
    df_model: np.ndarray
    dgamma_model: np.ndarray
    raw: np.ndarray
    flags: tuple[tuple[str, ...], ...]
    noise_fit: float = np.nan
    noise_series: float = np.nan


@one_blas_thread()
def fit_particles(
    fundamental,
    overtones,
    df,
    dgamma,
    particle: Particle,
    *,
    rocking="free",
    medium: Medium | None = None,
    sigma_df=None,
    sigma_dgamma=None,
    zq=8.8e6,
) -> ParticleFit:
    """Fit κ, ξ and the coverage (and κ_r) to QCM-D shifts of attached particles, per time step.

    Parameters
    ----------
    fundamental : f_F, Hz
    overtones : (n,) overtone orders
    df, dgamma : (T, n) or (n,) Δf_n (not divided by n) and ΔΓ_n (half bandwidth), Hz, against
        the bare sensor in the same medium; NaN = not measured
    particle : :class:`~contactres.resonators.Particle` (mass, moment of inertia, radius known)
    rocking : "free", "locked", a rotational stiffness in N m/rad, or "fit"
    medium : None or a :class:`~contactres.resonators.Medium`
    sigma_df, sigma_dgamma : noise of Δf_n and ΔΓ_n, Hz (scalars or broadcasting against df);
        None: estimated from the residuals (module docstring)
    zq : shear-wave impedance of the quartz, kg m⁻² s⁻¹

    Returns
    -------
    :class:`ParticleFit`

    Examples
    --------
    >>> import numpy as np
    >>> from contactres.analysis import fit_particles
    >>> from contactres.resonators import Particle, particle_shifts
    >>> p = Particle.sphere(1e-6, 2000.0)
    >>> n = np.arange(1, 14, 2)
    >>> df, dg = particle_shifts(5e6, n, p, 100.0, 2e-7, 2e9)  # κ N/m, ξ kg/s, per m²
    >>> fit = fit_particles(5e6, n, df, dg, p, sigma_df=0.1, sigma_dgamma=0.1)
    >>> print(f"{fit.kappa[0]:.1f} N/m, {fit.coverage[0]:.4g} /m², {fit.f_coupled[0]/1e6:.1f} MHz")
    100.0 N/m, 2e+09 /m², 32.5 MHz
    >>> fit.flags[0]  # nothing unresolved: the resonance lies within the comb
    ()
    """
    f0, n, zf, wf, wg, estimate = prepare(
        fundamental, overtones, df, dgamma, sigma_df, sigma_dgamma
    )
    zq = positive("zq", zq, "kg m^-2 s^-1")
    fit_rocking = isinstance(rocking, str) and rocking.strip().lower() == "fit"
    freq = n * f0
    reason, dropped = drop_inside_delta(
        particle, freq, medium, wf, wg, estimate, fit_rocking, MIN_DOF_ESTIMATED
    )
    zf = np.where(wf > 0, zf, 0.0)
    sens = 2.0 * n * np.pi**2 * zq  # z_n s_n = N K_L
    prob = _Problem(f0, particle, freq, sens, medium, zf, wf, wg, rocking, fit_rocking)
    left = 2 * int(prob.count.max()) - prob.n_par  # degrees of freedom at the best step
    if estimate and left < MIN_DOF_ESTIMATED:
        raise ContactresInputError(
            f"{int(prob.count.max())} overtones leave {left} degree{'s' * (left != 1)} of "
            f"freedom for {prob.n_par} parameters, too few to estimate the noise from "
            f"the residuals (at least {MIN_DOF_ESTIMATED}): state the noise of Δf_n and ΔΓ_n "
            "(sigma_df and sigma_dgamma; --noise on the command line)"
        )
    t = zf.shape[0]
    p_best, chi2, conv = np.zeros((t, prob.n_par)), np.full(t, np.inf), np.zeros(t, bool)
    dof = 2 * prob.count - prob.n_par
    # every point the search visits (starts and refined fits), for the interval test of result
    visited = []
    for i, p0 in enumerate(prob.starts()):
        # A start is refined where it begins below the best fit so far, where that did not
        # converge, or where it fits poorly (χ² above dof + 2√(2 dof) noise variances; the
        # variance is the stated one, or the median of χ²/dof over the steps of a series).
        # Refining every start everywhere would cost several times more: the limit starts
        # crawl along their flat valleys for nothing where the data have a clear optimum.
        start_chi2 = prob.evaluate(p0, np.arange(t), False)["chi2"]
        visited.append((p0, start_chi2))
        poor = np.ones(t, bool)
        if i > 0:
            var = 1.0 if not estimate else series_variance(chi2, dof, conv)
            poor = chi2 > var * (dof + 2.0 * np.sqrt(2.0 * np.maximum(dof, 1)))
            # the limit starts also where the best fit so far lies on their side of the comb,
            # where the valley towards the limit can hold a second minimum
            with np.errstate(over="ignore", invalid="ignore"):
                f_c = prob._resonance(p_best)
            if i == 2:
                poor |= ~(f_c <= prob.freq.max())
            if i == 3:
                poor |= ~(f_c >= prob.freq.min())
            if i == 4:  # the grid below the comb: a poor fit there only (the rest costs 2.5x)
                poor &= ~(f_c >= prob.freq.min())
        sel = np.flatnonzero((start_chi2 < chi2) | ~conv | poor)
        if sel.size == 0:
            continue
        res = levenberg_marquardt(
            lambda q, rows, jac, sel=sel: prob.evaluate(q, sel[rows], jac),
            p0[sel],
            lo=prob.lo[sel],
            hi=prob.hi[sel],
            options=_LM if i < 4 else _LM_SCAN,
        )
        q_ref, chi2_ref = p0.copy(), np.full(t, np.inf)
        q_ref[sel], chi2_ref[sel] = res.x, res.chi2
        visited.append((q_ref, chi2_ref))
        better = res.chi2 < chi2[sel]
        take = sel[better]
        p_best[take], chi2[take] = res.x[better], res.chi2[better]
        conv[take] = res.converged[better]
    # below the comb: the χ² profile along κ, whose stiff side holds a second minimum; not
    # where no particles fit nearly as well (noise before adsorption: nothing to print there)
    var = 1.0 if not estimate else series_variance(chi2, dof, conv)
    chi2_empty = np.sum(wf**2 * zf.real**2 + wg**2 * zf.imag**2, axis=1)
    with np.errstate(over="ignore", invalid="ignore"):
        low = ~(prob._resonance(p_best) >= prob.freq.min())
        below = np.flatnonzero(low & (chi2_empty - chi2 >= LIMIT_CHI2 * var))
    p_best, chi2, conv, walked = valley_profile(
        prob.evaluate, p_best, chi2, conv, below, prob.lo, prob.hi, _LM
    )
    visited += walked
    if prob.grid is not None:  # the scan start's grid, in the fit's coordinates
        visited += zip(grid_coordinates(prob.grid[0], prob.xi_scale), prob.grid[1], strict=True)
    visited_q, visited_chi2 = (np.array(v) for v in zip(*visited, strict=True))
    fit = prob.result(p_best, chi2, conv, estimate, reason, (visited_q, visited_chi2))
    if estimate:
        # the model's noise against the series' own (read off its step-to-step differences):
        # the residuals absorb a systematic misfit, so only an independent noise exposes it
        noise_fit, noise_series, bad = noise_check(chi2, dof, conv, zf, wf > 0)
        fit = noise_checked(fit, noise_fit, noise_series, bad, prob.fit_rocking)
    return dropped_named(fit, n[dropped])


class _Problem:
    """The batched least-squares problem of :func:`fit_particles` (its evaluate, starts and
    result); an object only to keep the arrays of one call together (nothing is cached
    beyond the call)."""

    def __init__(self, f0, particle, freq, sens, medium, z, wf, wg, rocking, fit_rocking):
        self.f0, self.particle, self.freq, self.sens = f0, particle, freq, sens
        self.omega = 2.0 * np.pi * freq
        self.medium, self.z, self.wf, self.wg = medium, z, wf, wg
        self.fit_rocking = fit_rocking
        self.rocking = rocking
        self.n_par = 4 if fit_rocking else 3
        if not fit_rocking:
            c, h, g = particle_compliance(particle, freq, rocking=rocking, medium=medium)
            self.chg = (c[None, :], h[None, :], g[None, :])
        self.count = (wf > 0).sum(axis=1)
        t = z.shape[0]
        # Scales: the Sauerbrey coverage n0 (from the median |z_n| s_n/(m ω_n²)), the stiffness
        # of a resonance at the comb's ends and the rocking stiffness of a rocking mode at f_F.
        m = particle.mass
        with np.errstate(invalid="ignore", divide="ignore"):
            n0 = np.nanmedian(np.where(wf > 0, np.abs(z) * sens / (m * self.omega**2), np.nan), 1)
        self.n0 = np.where(np.isfinite(n0) & (n0 > 0), n0, 1.0)
        k_lo, k_hi = m * self.omega.min() ** 2, m * self.omega.max() ** 2
        self.kr0 = particle.moment_of_inertia * (2 * np.pi * f0) ** 2
        # Bounds far outside what the comb can see (a fit on a bound is flagged): 10⁴ in
        # frequency beyond the comb for κ (10⁸ in κ) and κ_r, 10⁸ around n0 for the coverage.
        lo = [np.log(k_lo * 1e-8), 0.0, np.log(self.n0 * 1e-8), np.log(self.kr0 * 1e-8)]
        hi = [np.log(k_hi * 1e8), np.inf, np.log(self.n0 * 1e8), np.log(self.kr0 * 1e10)]
        self.lo = np.stack(np.broadcast_arrays(*lo[: self.n_par]), axis=-1)
        self.hi = np.stack(np.broadcast_arrays(*hi[: self.n_par]), axis=-1)
        self.xi_scale = np.ones(t)
        self.grid = None  # the scan start's grid (starts; rocking="fit" has none)

    def _chg(self, p):
        """c, h, g of the particle (rows, n) at the κ_r of p (or the given rocking)."""
        if not self.fit_rocking:
            return self.chg
        return particle_compliance(
            self.particle, self.freq, rocking=np.exp(p[:, 3:4]), medium=self.medium
        )

    def model(self, p, chg):
        """z_n (Hz) for parameters p (rows, P), and dz/dk (the contact's k = κ + iωξ)."""
        c, h, g = chg
        kappa, xi, cov = np.exp(p[:, 0:1]), p[:, 1:2], np.exp(p[:, 2:3])
        k = kappa + 1j * self.omega * xi
        ck1 = c * k + 1.0
        one_h2 = (1.0 - h) ** 2
        kl = one_h2 * k / ck1 + g
        return cov * kl / self.sens, cov * one_h2 / (ck1 * ck1) / self.sens

    def evaluate(self, q, rows, jacobian):
        p = q.copy()
        p[:, 1] *= self.xi_scale[rows]
        zm, dk = self.model(p, self._chg(p))
        cols = [dk * np.exp(p[:, 0:1]), dk * 1j * self.omega * self.xi_scale[rows, None], zm]
        if self.fit_rocking:
            eps = 1e-6
            p2 = p.copy()
            p2[:, 3] += eps
            cols.append((self.model(p2, self._chg(p2))[0] - zm) / eps)
        wf, wg = self.wf[rows], self.wg[rows]
        diff = zm - self.z[rows]
        r = weighted_parts([diff], wf, wg)[:, :, 0]  # real parts, then imaginary
        jac = weighted_parts(cols, wf, wg)  # (rows, 2n, P): dr/dq
        chi2 = np.sum(r * r, axis=1)
        finite = np.isfinite(chi2)
        # (a finite χ² has finite residuals: the scrub is needed only where one is not)
        if not finite.all():
            chi2, r = np.where(finite, chi2, np.inf), np.nan_to_num(r)
        if not np.isfinite(jac).all():
            jac = np.nan_to_num(jac)
        jt = jac.transpose(0, 2, 1)
        return {"chi2": chi2, "gradient": (jt @ r[:, :, None])[:, :, 0], "hessian": jt @ jac}

    def starts(self):
        """Starting points (rows, P) in the fit's coordinates: the equation-error solution, and
        the same with κ put where the peak of nΔΓ_n puts the coupled resonance (module
        docstring). For rocking="fit" each is the best over a scan of κ_r."""
        t = self.z.shape[0]
        scan = [None]
        if self.fit_rocking:
            scan = list(
                _ROCKING_SCAN * self.particle.moment_of_inertia * (2 * np.pi * self.f0) ** 2
            )
        found = []
        kinds = ("equation", "peak", "sauerbrey", "heavy") + (() if self.fit_rocking else ("scan",))
        for kind in kinds:
            best, best_chi2 = np.full((t, self.n_par), np.nan), np.full(t, np.inf)
            for kr in scan:
                chg = self.chg if kr is None else self._chg(np.full((t, 4), np.log(kr)))
                kappa, xi, cov = self._start(kind, kr, chg)
                p = np.column_stack(
                    [np.log(kappa), xi, np.log(cov)]
                    + ([] if kr is None else [np.full(t, np.log(kr))])
                )
                p = np.clip(np.where(np.isfinite(p), p, self._fallback()), self.lo, self.hi)
                # a start exactly on an overtone's resonance (ξ = 0) divides by zero: χ² = inf
                with np.errstate(divide="ignore", invalid="ignore"):
                    chi2 = self.evaluate(p / self._unit(p), np.arange(t), False)["chi2"]
                take = chi2 < best_chi2
                best = np.where(take[:, None], p, best)
                best_chi2 = np.where(take, chi2, best_chi2)
            found.append(np.where(np.isfinite(best), best, self._fallback()))
        # ξ is fitted in units of its first start (Marquardt's damping is scale-free, but the
        # bounds and the covariance read better in those units)
        self.xi_scale = np.where(found[0][:, 1] > 0, found[0][:, 1], 1e-12)
        return [f / self._unit(f) for f in found]

    def _start(self, kind, kr, chg):
        """κ, ξ, N (T,) of one kind of start (module docstring)."""
        t = self.z.shape[0]
        if kind in ("equation", "peak"):
            fixed = self._peak_kappa(kr) if kind == "peak" else None
            return equation_error(self.z, self.wf, self.wg, self.sens, self.omega, chg, fixed)
        m = self.particle.mass
        if kind == "scan":
            f_grid = np.geomspace(self.freq.min() / 10, self.freq.min(), 40)
            kappas = self._peak_kappa(None, f_grid)
            xis = np.outer(kappas / (2 * np.pi * f_grid), [0.0, 0.02, 0.05, 0.1, 0.3])
            grid = np.column_stack([np.repeat(kappas, xis.shape[1]), xis.ravel(), 0 * xis.ravel()])
            # (a grid point exactly on a mode, ξ = 0, is infinite: scan_start skips it)
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                unit = self.model(np.column_stack([np.log(grid[:, 0]), grid[:, 1:]]), chg)[0]
            # the grid's points join those the search visited (fit_particles, result)
            best, self.grid = scan_start(unit, grid, self.z, self.wf, self.wg)
            return best[:, 0], best[:, 1], best[:, 2]
        if kind == "heavy":
            return self._heavy_start(chg, m * self.omega.min() ** 2 * 1e-4)
        # The rigid limit: κ 10⁴ above the stiffness of a resonance at the top of the comb, ξ
        # from the equation-error start (or 0) and the coverage that fits best with these
        # (linear least squares in N).
        _, xi, _ = equation_error(self.z, self.wf, self.wg, self.sens, self.omega, chg, None)
        xi = np.where(np.isfinite(xi), xi, 0.0)
        kappa = np.full(t, m * self.omega.max() ** 2 * 1e4)
        unit = np.zeros((t, self.n_par))
        unit[:, 0], unit[:, 1] = np.log(kappa), xi
        one = self.model(unit, chg)[0]  # the shifts of a unit coverage
        num = np.sum(self.wf**2 * one.real * self.z.real + self.wg**2 * one.imag * self.z.imag, 1)
        den = np.sum(self.wf**2 * one.real**2 + self.wg**2 * one.imag**2, 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            cov = num / den
        return kappa, xi, np.where(cov > 0, cov, np.nan)

    def _heavy_start(self, chg, kappa):
        """The particles standing still (paper 2, Eq. 1): κ as given (10⁴ below a resonance at
        the bottom of the comb), ξ and N from the products N·κ, N·ξ of the limit's fit."""
        return heavy_start(self.z, self.wf, self.wg, self.sens, self.omega, chg[1], kappa)

    def _unit(self, p):
        unit = np.ones_like(p)
        unit[:, 1] = self.xi_scale
        return unit

    def _fallback(self):
        """A start where the equation-error solution is not usable: κ of a resonance at the
        middle of the comb, ξ = 0, the Sauerbrey coverage."""
        mid = np.sqrt(self.freq.min() * self.freq.max())
        kappa = self.particle.mass * (2 * np.pi * mid) ** 2
        base = [np.log(kappa), 0.0, np.log(self.n0), np.log(self.kr0)][: self.n_par]
        return np.stack(np.broadcast_arrays(*base), axis=-1)

    def _peak_kappa(self, kr, f_peak=None):
        """κ that puts the coupled resonance (vacuum) at the largest nΔΓ_n of each step (or at
        the given frequencies)."""
        if f_peak is None:
            score = np.where(self.wf > 0, self.z.imag * self.freq, -np.inf)
            f_peak = self.freq[np.argmax(score, axis=1)]
        rocking = self.rocking if kr is None else kr
        f1 = coupled_resonance(self.particle, 1.0, rocking=rocking)
        f1 = f1 if isinstance(rocking, str) else f1[..., 0]
        return (f_peak / f1) ** 2  # f_coupled ∝ √κ in vacuum

    def _resonance(self, p):
        kap = np.exp(p[..., 0])
        rocking = self.rocking if not self.fit_rocking else np.exp(p[..., 3])
        f = coupled_resonance(self.particle, kap, rocking=rocking, medium=self.medium)
        # two modes with a rotational stiffness: the lower (the translation's continuation)
        return f if isinstance(rocking, str) else f[..., 0]

    def result(self, q, chi2, conv, estimate, reason, visited):
        """The :class:`ParticleFit` at the fitted q (rows, P): errors, the rule, flags."""
        t, npar = q.shape
        p = q.copy()
        p[:, 1] *= self.xi_scale
        rows = np.arange(t)
        hess = self.evaluate(q, rows, True)["hessian"]
        dof = 2 * self.count - npar
        # the noise variance: stated (1), pooled over the series, or (short series) per step
        pooled = pooled_variance(chi2, dof, conv) if estimate else 1.0
        per_step = estimate and not np.isfinite(pooled)
        with np.errstate(divide="ignore", invalid="ignore"):
            s2 = np.where(dof > 0, chi2 / dof, np.nan) if per_step else np.full(t, pooled)
            cov_q = stacked_inverse(hess) * s2[:, None, None]
            err_q = np.sqrt(np.diagonal(cov_q, axis1=1, axis2=2))
            corr = cov_q / (err_q[:, :, None] * err_q[:, None, :])
        kappa, xi, cov = np.exp(p[:, 0]), p[:, 1], np.exp(p[:, 2])
        kappa_err, xi_err, cov_err = (
            kappa * err_q[:, 0],
            self.xi_scale * err_q[:, 1],
            cov * err_q[:, 2],
        )
        if self.fit_rocking:
            kr, kr_err = np.exp(p[:, 3]), np.exp(p[:, 3]) * err_q[:, 3]
        else:
            kr = kr_err = np.full(t, np.nan)
        fc, fc_err = self._resonance_with_error(p, cov_q)
        chg = self._chg(p)
        zm = self.model(p, chg)[0]

        # The likelihood-ratio test against the two limits of the model (module docstring)
        # (the limits drop 2 parameters (rigid: κ, ξ), 1 (standing still: the κ -> 0 edge) and
        # all (empty); the q of the F thresholds where the noise is estimated per step)
        with np.errstate(invalid="ignore", divide="ignore"):
            lim_s, lim_h, lim_0 = limit_chi2(self.z, self.wf, self.wg, self.sens, self.omega, chg)
            sauerbrey = (lim_s - chi2) / s2 < limit_threshold(LIMIT_CHI2, dof, 2, per_step)
            inertial = (lim_h - chi2) / s2 < limit_threshold(LIMIT_CHI2, dof, 1, per_step)
            # no particles at all (z = 0) fits as well: the shifts are noise (or a drift of the
            # baseline), and the three parameters fitted to them are nonsense; the fit's
            # resonance may sit on any overtone, so the threshold grows with their number
            no_signal = (lim_0 - chi2) / s2 < no_signal_threshold(self.count, dof, npar, per_step)
        # the products N·κ and N·ξ: ln(Nκ) = q0 + q2, ln(Nξ) = ln q1 + q2 (+ const)
        with np.errstate(divide="ignore", invalid="ignore"):
            nk_rel = np.sqrt(cov_q[:, 0, 0] + cov_q[:, 2, 2] + 2 * cov_q[:, 0, 2])
            q1 = q[:, 1]
            nx_rel = np.sqrt(cov_q[:, 1, 1] / q1**2 + cov_q[:, 2, 2] + 2 * cov_q[:, 1, 2] / q1)
            nk, nx = cov * kappa, cov * xi
            nk_err, nx_err = nk * nk_rel, nx * nx_rel
        # too few overtones: fewer than two, or too few dof for the estimated noise's errors
        few = (self.count < 2) | (estimate & (dof < MIN_DOF_ESTIMATED))
        nk_ok = np.isfinite(nk_rel) & (nk_rel <= RELATIVE_ERROR_LIMIT) & ~few
        nx_ok = np.isfinite(nx_rel) & (nx_rel <= RELATIVE_ERROR_LIMIT) & ~few
        if reason is not None:
            nk_ok = nx_ok = np.zeros(t, bool)
        # a fit far beyond its χ² (or not converged) gives no value, the products neither
        poor = poor_fit(chi2, dof, s2, per_step)
        nk_ok, nx_ok = nk_ok & ~no_signal & conv & ~poor, nx_ok & ~no_signal & conv & ~poor
        # A point the search visited, within the Δχ² of the limit test, farther from the fit
        # than 1.3σ√Δχ²: the interval the data allow is wider than the linearised error says
        # (module docstring; below the comb the χ² valley has two minima)
        vq, vchi2 = visited
        with np.errstate(invalid="ignore", over="ignore"):
            dchi2 = (vchi2 - chi2) / s2
            near = dchi2 < limit_threshold(LIMIT_CHI2, dof, 1, per_step)
            wide, widened_err = wide_values(
                (kappa, xi, cov, kr, nk, nx),
                (kappa_err, xi_err, cov_err, kr_err, nk_err, nx_err),
                vq,
                self.xi_scale,
                dchi2,
                near,
                PROFILE_FACTOR,
            )
        # N·κ and N·ξ are printed with the error that holds those points (rule 5): blanked,
        # the draws printed were those whose estimate lay on one side (issue 28, fourth review)
        nk_err, nx_err = widened_err[4], widened_err[5]
        widened = np.zeros(t, bool)
        names = ("kappa", "xi", "coverage", "kappa_r")[:npar]
        flags, keep = [], np.ones((t, 4), bool)
        unresolved = ("kappa-unresolved", "xi-unresolved", "coverage-unresolved")
        if self.fit_rocking:
            unresolved += ("rocking-unresolved",)
        measured = self.wf > 0
        for i in range(t):
            f = []
            if few[i]:
                flags.append(("too-few-overtones",))
                keep[i] = False
                continue
            if no_signal[i]:
                flags.append(("no-signal", *unresolved))
                keep[i] = False
                continue
            rel = [
                kappa_err[i] / kappa[i],
                xi_err[i] / xi[i] if xi[i] > 0 else np.inf,
                cov_err[i] / cov[i],
                kr_err[i] / kr[i] if self.fit_rocking else 0.0,
            ]
            bad = [not (np.isfinite(r) and r <= RELATIVE_ERROR_LIMIT) for r in rel]
            comb = self.freq[measured[i]]
            if sauerbrey[i]:
                f.append("sauerbrey-like")
                bad[0] = bad[1] = True  # κ and ξ: a rigid contact fits as well
            if inertial[i]:
                f.append("inertial")
                # κ and N: only their product; ξ too, since ξ = Nξ/N inherits N's
                # unidentified scale (printed alone it was up to 6x off)
                bad[0] = bad[1] = bad[2] = True
            # with κ_r fitted but unresolved, fc is a mode of the unidentified κ_r (near rolling
            # for κ_r -> 0: Hz to kHz) and says nothing of where the data's resonance lies
            fc_known = not (self.fit_rocking and bad[3])
            if fc_known and not comb.min() <= fc[i] <= comb.max():
                f.append("outside-comb")
                # outside the comb a linearised error beyond 10 % is that of a curved valley
                # (2.5x below the comb: κ and N printed 2-4σ off with errors of 20-30 %)
                bad = outside_cut(bad, rel, RELATIVE_ERROR_OUTSIDE)
            if q[i, 1] <= 0.0:
                f.append("fit-at-bound")
            if not conv[i]:
                # a fit that stopped in a flat valley: its point is not an estimate
                f.append("not-converged")
                bad = [True] * 4
            if poor[i] and conv[i]:
                f.append("poor-fit")
                bad = [True] * 4
            if reason is not None:
                f.append("particle-smaller-than-delta")
                bad = [True] * 4
            # the interval test (above), named where it blanks a value the other rules print
            widened[i] |= any(not b and w[i] for b, w in zip(bad, wide, strict=False))
            bad = [b or w[i] for b, w in zip(bad, wide, strict=False)]
            if widened[i]:
                f.append("wide-interval")
            # a note, no value blanked: the loss tangent ωξ/κ at f_coupled above 1 (Q < 1)
            if fc_known and not (bad[0] or bad[1]) and 2 * np.pi * fc[i] * xi[i] > kappa[i]:
                f.append("overdamped")
            f += [name for name, b in zip(unresolved, bad, strict=False) if b]
            keep[i] = np.logical_not(bad)
            flags.append(tuple(f))

        def shown(value, col):
            return np.where(keep[:, col], value, np.nan)

        # f_coupled goes with κ, and with κ_r where that is fitted (it sets the modes)
        fc_keep = keep[:, 0] & (keep[:, 3] if self.fit_rocking else True)

        return ParticleFit(
            kappa=shown(kappa, 0),
            kappa_err=shown(kappa_err, 0),
            xi=shown(xi, 1),
            xi_err=shown(xi_err, 1),
            coverage=shown(cov, 2),
            coverage_err=shown(cov_err, 2),
            f_coupled=np.where(fc_keep, fc, np.nan),
            f_coupled_err=np.where(fc_keep, fc_err, np.nan),
            kappa_r=shown(kr, 3) if self.fit_rocking else kr,
            kappa_r_err=shown(kr_err, 3) if self.fit_rocking else kr_err,
            coverage_kappa=np.where(nk_ok, nk, np.nan),
            coverage_kappa_err=np.where(nk_ok, nk_err, np.nan),
            coverage_xi=np.where(nx_ok, nx, np.nan),
            coverage_xi_err=np.where(nx_ok, nx_err, np.nan),
            parameters=names,
            correlation=corr,
            chi2=chi2,
            dof=dof,
            df_model=zm.real,
            dgamma_model=zm.imag,
            raw=np.column_stack([kappa, xi, cov, kr][:npar]),
            flags=tuple(flags),
        )

    def _resonance_with_error(self, p, cov_q):
        """f_coupled (Hz) and its standard error from the covariance of (ln κ, ln κ_r)."""
        fc = self._resonance(p)
        idx = [0, 3] if self.fit_rocking else [0]
        grad = np.zeros((p.shape[0], p.shape[1]))
        eps = 1e-6
        for j in idx:
            p2 = p.copy()
            p2[:, j] += eps
            grad[:, j] = (np.log(self._resonance(p2)) - np.log(fc)) / eps
        var = np.einsum("ri,rij,rj->r", grad, cov_q, grad)
        return fc, fc * np.sqrt(np.maximum(var, 0.0))
