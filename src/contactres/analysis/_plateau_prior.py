"""The plateau amplitudes of the analysis's clear plateaus as prior knowledge of each block's.

Why. The BIC charges the stick plateau's critical displacement d_c ln N, the Laplace
approximation of a unit-information prior (Kass & Raftery, J. Am. Stat. Assoc. 90, 773 (1995),
Sec. 4.1.3): as if d_c could lie anywhere over a range as wide as one point's worth of data
constrains it. In noisy data (water: σ = 0.6 Hz, three ramps of 11 amplitudes, N = 66
residuals) that is ln 66 = 4.2 units on top of the ``delta_bic`` a nesting model needs, and a
plateau block whose loop bends only over the last half of its amplitudes rarely pays it: on the
validation study (``benchmarks/study_qcm_trust.py``, ten seeds) 25 of 93 plateau blocks in water
were read as Cattaneo-Mindlin (a larger μ) or as elastic, at a BIC difference of a few units.
A Bayes oracle that knows the generator's distribution of d_c
(``benchmarks/study_plateau_oracle.py``) decides far better than one that does not, and the
analysis can learn that distribution from the data themselves: the blocks whose plateau is
clear (the plateau beats every other candidate by :data:`PLATEAU_PRIOR_EVIDENCE`) show where
plateaus of this sample lie. The plateau amplitude is compared as a fraction of the block's
largest amplitude, ln(d_c/u_max): the drive range is the experimenter's scale of the sweep, and
the fraction is what decides how much of the loop the plateau hides.

How (empirical Bayes, :func:`plateau_prior`). For every load block, ln(d_c/u_max) of the
joint plateau fits of the *other* clear plateaus of the analysis (at least
:data:`PLATEAU_PRIOR_MIN_BLOCKS` of them) give a normal prior N(m, v): their mean, and their
sample variance (which includes their own fit errors: a broader prior, never a narrower one)
widened by the error of that mean, v = s²(1 + 1/K) (:func:`reference_plateau`). Leaving the
block out keeps the prior independent of the block's own points. The criterion of the block's
shared plateau fit then replaces ln N of d_c by the prior's Occam factor and misfit, the same
Laplace approximation as for μ (:func:`contactres.analysis._mu_prior.prior_penalty`), and
where μ has its prior too (from the experiment's other loads), both at once with the fit's
joint covariance of μ and d_c (:func:`joint_prior_penalty`): the fit trades one against the
other, and two separate terms would waive the same freedom twice.

What it does not do. A Cattaneo-Mindlin block's plateau fit puts d_c near 0: a few per cent of
u_max, several prior widths below the clear plateaus' (a misfit larger than the ln N it
replaces), or on its bound 0 (with no error); or it leaves d_c unresolved (relative error above
1). On the bound or unresolved, the prior of d_c does not apply and its ln N stays in the
criterion; only μ's prior, where μ has one (and is resolved), replaces μ's ln N
(:func:`joint_prior_penalty` falls back to the μ-only term), as it does in the block's Coulomb
loops' criteria. So the prior rarely turns such a block into a plateau (on the validation study
12 of 557 Cattaneo-Mindlin blocks in water, 6 before). Where fewer than
:data:`PLATEAU_PRIOR_MIN_BLOCKS` other plateaus are clear (a sample without plateaus, or with
one or two), nothing changes. Only the class choice and the weights of the model-averaged μ
use the prior; d_c and μ of every block are still those its own points give.

Where the criterion with this penalty leaves a block's plateau undecided (within
``PLATEAU_UNDECIDED`` of its best other candidate, :mod:`contactres.analysis._blocks`), the
same prior enters the plateau's evidence integrated over d_c instead
(:mod:`contactres.analysis._plateau_evidence`): the fit of such a block often ends on a bound of
d_c, where nothing expands about it.
"""

from __future__ import annotations

import numpy as np

from ._mu_prior import MU_PRIOR_MAX_REL, prior_penalty

__all__ = [
    "PLATEAU_PRIOR_EVIDENCE",
    "PLATEAU_PRIOR_MIN_BLOCKS",
    "joint_prior_penalty",
    "plateau_prior",
    "reference_plateau",
]

#: How much lower than every other candidate a block's shared plateau criterion must be for the
#: block to inform the prior: 6, "strong" evidence on the Kass-Raftery scale (2 ln B > 6).
PLATEAU_PRIOR_EVIDENCE = 6.0

#: Other clear plateaus the prior needs: a mean and a variance, and one more that shows the
#: variance is not a chance agreement of two.
PLATEAU_PRIOR_MIN_BLOCKS = 3


def reference_plateau(ratio: np.ndarray, clear: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The prior of ln(d_c/u_max) of every block from the other clear plateaus.

    Parameters
    ----------
    ratio : (B,) d_c/u_max of each block's plateau fit (NaN: none)
    clear : (B,) which blocks' plateau is clear (they inform the prior)

    Returns
    -------
    mean, var : (B,) the mean of ln(d_c/u_max) over the other clear blocks and its sample
        variance (ddof 1) times (1 + 1/K), K of them; NaN where K <
        :data:`PLATEAU_PRIOR_MIN_BLOCKS`
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.log(np.asarray(ratio, dtype=float))
    use = np.asarray(clear, bool) & np.isfinite(y)
    # Leave-one-out sums: the block's own term removed where it is one of them.
    own = np.where(use, y, 0.0)
    K = use.sum() - use.astype(int)
    s1 = own.sum() - own
    s2 = (own**2).sum() - own**2
    mean = np.full(y.shape, np.nan)
    var = np.full(y.shape, np.nan)
    ok = K >= PLATEAU_PRIOR_MIN_BLOCKS
    mean[ok] = s1[ok] / K[ok]
    sample = np.maximum(s2[ok] - K[ok] * mean[ok] ** 2, 0.0) / (K[ok] - 1)
    var[ok] = sample * (1.0 + 1.0 / K[ok])
    return mean, var


def plateau_prior(
    d_c: np.ndarray, d_c_err: np.ndarray, u_max: np.ndarray, evidence: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The prior of ln(d_c/u_max) of every block from the other blocks' clear plateaus.

    Parameters
    ----------
    d_c, d_c_err : (B,) the critical displacement of each block's joint plateau fit and its
        standard error, m
    u_max : (B,) the block's largest amplitude, m
    evidence : (B,) the best criterion of the block's other candidates minus its shared
        plateau's (positive: the plateau is better); resolved fits (relative error of d_c below
        1) above :data:`PLATEAU_PRIOR_EVIDENCE` inform the prior

    Returns
    -------
    mean, var : (B,) as :func:`reference_plateau`
    """
    d_c, d_c_err, u_max = (np.asarray(a, dtype=float) for a in (d_c, d_c_err, u_max))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = d_c / u_max
    resolved = np.isfinite(ratio) & (ratio > 0) & (d_c_err > 0) & (d_c_err < d_c)
    clear = resolved & (np.asarray(evidence, dtype=float) > PLATEAU_PRIOR_EVIDENCE)
    return reference_plateau(ratio, clear)


def _with_prior(value, err, mean, var) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ln of a fitted value, its relative variance, and where a prior N(mean, var) of that ln
    applies (a prior exists and the value is resolved: relative error in (0,
    :data:`~contactres.analysis._mu_prior.MU_PRIOR_MAX_REL`])."""
    value, err = np.asarray(value, dtype=float), np.asarray(err, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.log(value)
        s2 = (err / value) ** 2
    ok = np.isfinite(y) & (s2 > 0) & (s2 <= MU_PRIOR_MAX_REL**2)
    ok &= np.isfinite(np.asarray(mean, dtype=float)) & np.isfinite(np.asarray(var, dtype=float))
    return y, s2, ok


def joint_prior_penalty(mu, mu_err, mu_prior, ratio, ratio_err, ratio_prior, cov, n_points):
    """What the priors on μ and on the plateau amplitude together change in the criterion of a
    plateau loop's fit.

    The plateau fit trades μ against d_c (a later onset of slip: a larger μ or a wider
    plateau), so its errors of ln μ and ln(d_c/u_max) are strongly correlated, and each alone
    is large. Two one-parameter Laplace terms (:func:`~contactres.analysis._mu_prior.
    prior_penalty` each) would count that freedom twice: each prior would waive its
    parameter's ln N as if the other parameter were fixed. With the fit's joint covariance C of
    (ln μ, ln(d_c/u_max)) and the independent priors N(m, V), V diagonal, the Laplace
    approximation of the evidence replaces 2 ln N by

        ln det(C + V) - ln det C + (y - m)ᵀ (C + V)⁻¹ (y - m)

    (the two-parameter form of the one in :mod:`contactres.analysis._mu_prior`). Where only one
    prior applies, its one-parameter term (a d_c on its bound 0 or whose relative error is above
    :data:`~contactres.analysis._mu_prior.MU_PRIOR_MAX_REL` has no prior term: μ's alone);
    neither: 0.

    Parameters
    ----------
    mu, mu_err : (B,) μ of the plateau fit and its standard error
    mu_prior : (mean, var) of ln μ, (B,) each (NaN: none)
    ratio, ratio_err : (B,) d_c/u_max of the fit and its standard error
    ratio_prior : (mean, var) of ln(d_c/u_max) (:func:`plateau_prior`)
    cov : (B,) the fit's covariance of ln μ and ln(d_c/u_max)
    n_points : (B,) points of each block (N = 2n residuals)
    """
    y1, c11, ok1 = _with_prior(mu, mu_err, *mu_prior)
    y2, c22, ok2 = _with_prior(ratio, ratio_err, *ratio_prior)
    one = np.where(ok1, prior_penalty(mu, mu_err, *mu_prior, n_points), 0.0)
    one += np.where(ok2, prior_penalty(ratio, ratio_err, *ratio_prior, n_points), 0.0)
    (m1, v1), (m2, v2) = (
        (np.asarray(a, dtype=float) for a in mu_prior),
        (np.asarray(a, dtype=float) for a in ratio_prior),
    )
    c12 = np.asarray(cov, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        det_c = c11 * c22 - c12**2
        s11, s22 = c11 + v1, c22 + v2
        det_s = s11 * s22 - c12**2
        d1, d2 = y1 - m1, y2 - m2
        misfit = (s22 * d1**2 - 2.0 * c12 * d1 * d2 + s11 * d2**2) / det_s
        two = np.log(det_s / det_c) + misfit - 2.0 * np.log(2 * np.asarray(n_points, float))
    both = ok1 & ok2 & (det_c > 0) & np.isfinite(two)
    return np.where(both, two, one)
