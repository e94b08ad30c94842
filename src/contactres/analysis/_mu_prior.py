"""The friction of an experiment's other loads as prior knowledge of each load block's μ.

Why. In noisy data (water: σ = 0.6 Hz on shifts of 15-100 Hz, 11 amplitudes, x = κu0/(μF_N)
< 1) a stick plateau of width d_c and a Cattaneo-Mindlin loop with a larger μ describe a load
block almost equally well: on the validation study (``benchmarks/study_qcm_trust.py``) the best
Cattaneo-Mindlin fit of a true plateau block comes within Δχ² = 2 of the *true* model in about
half of the blocks, so the block's own points cannot tell them apart, whatever the criterion.
What tells them apart is μ: the Cattaneo-Mindlin reading of a plateau puts the late onset of
slip down to a larger friction force, a μ tens of per cent above that of the experiment's other
loads, while the plateau loop finds their μ. The same contact (one mounting of the sample) at
the other loads is therefore a prior on μ of this load, as paper 2 reads its data (Fig. 7: one
friction law per experiment, μ falling slowly with load).

How. For every load block of an experiment (:func:`reference_mu`), the model-averaged μ of the
experiment's *other* load blocks (:func:`contactres.analysis._friction.model_averaged_mu`, each
from its own points) are fitted by weighted least squares with a power law ln μ = a + b ln F_N
(at least :data:`MU_PRIOR_MIN_LOADS` of them, weights 1/(relative error)²); the prior of this
block is its prediction, with the variance of the prediction (scaled by the reduced χ² of the
fit where that exceeds 1: a law that scatters more than its errors says is a broader prior).
Leaving the block out keeps the prior independent of the block's own data. The exponent b is a
property of the interface (configuration and medium), the level a of the mounting: so the
experiments of one configuration in one medium share b (``group``; each keeps its own a), and
their other loads all inform the block's prior. In water, where a block's μ has an error of
10-30 %, a slope from the 3-5 other loads of one experiment is loose; shared over the 4
experiments of the validation study it no longer adds much to the prior's variance.

The class criterion then uses that prior (:func:`prior_penalty`). The BIC charges each parameter
ln N, the Laplace approximation of a unit-information prior (Kass & Raftery, J. Am. Stat. Assoc.
90, 773 (1995), Sec. 4.1.3). For ln μ of a Coulomb loop (Cattaneo-Mindlin or plateau) the prior
N(m, v) is known instead, and the Laplace approximation of the evidence with a Gaussian prior on
one linear combination of the parameters (ln μ = ln Pκ - ln θ - ln PF_N) whose posterior
variance is s² replaces ln N by

    ln(1 + v/s²) + (ln μ̂ - m)²/(s² + v),

the Occam factor of the prior plus the misfit of the fitted μ̂ to it (exact for a Gaussian
likelihood in ln μ; the prior variance v includes the error of the prediction). A loop whose μ
agrees with the other loads thus costs less than ln N, one that needs another μ more. Only the
class choice and the weights of the model average use the prior: μ of every block is still
the one its own points give.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from ._friction import COULOMB_LOOPS, MU_PRIOR_MAX_REL, loop_table_force, model_averaged_mu

__all__ = [
    "MU_PRIOR_MAX_REL",
    "MU_PRIOR_MIN_LOADS",
    "mu_prior_penalties",
    "mu_prior_reference",
    "prior_penalty",
    "reference_mu",
]

#: Other load blocks of the experiment with a resolved μ that a prior needs: the power law has
#: two parameters, and a third point is the least that shows its scatter.
MU_PRIOR_MIN_LOADS = 3


def reference_mu(
    experiment: np.ndarray,
    force: np.ndarray,
    mu: np.ndarray,
    mu_err: np.ndarray,
    group: np.ndarray | None = None,
):
    """The prior of ln μ of every load block from the other blocks of its experiment.

    Parameters
    ----------
    experiment : (B,) a code of each block's experiment (configuration, medium, mounting)
    force : (B,) normal force F_N of each block, N
    mu, mu_err : (B,) μ of each block and its standard error (NaN: none)
    group : (B,) a code of each block's configuration and medium, or None. Given, the
        experiments of one group share the exponent b of the power law, each with its own level
        a (ln μ = a_e + b ln F_N, weighted least squares over all other blocks of the group);
        None: every experiment has its own a and b

    Returns
    -------
    mean, var : (B,) the prior mean and variance of ln μ (module docstring: the weighted power
        law of the other blocks, its prediction at this F_N and the variance of that
        prediction, scaled by the reduced χ² where it exceeds 1); NaN where fewer than
        :data:`MU_PRIOR_MIN_LOADS` other blocks of the block's experiment have a μ or their
        loads do not span two values

    Notes
    -----
    The least-squares fit with one level per experiment and a shared exponent is solved in
    closed form rather than by inverting its normal matrix (one inversion per block, of the size
    of the group's experiments, made this step cubic in the size of the table). Given b, each
    level is its experiment's weighted mean, a_e = ȳ_e - b x̄_e (x = ln F_N, y = ln μ); so
    b = Σ_e p_e / Σ_e q_e with q_e = Σ w (x - x̄_e)² and p_e = Σ w (x - x̄_e)(y - ȳ_e) over the
    experiment's blocks, and the prediction at x of experiment e has the variance
    1/Σ_e w + (x - x̄_e)²/Σ_e q_e (the inverse of the normal matrix, written out). Leaving a
    block out changes the sums of its own experiment only: those are taken afresh over the
    others (a few loads), those of the group's other experiments once.
    """
    experiment = np.asarray(experiment)
    group = np.asarray(experiment if group is None else group)
    lnF = np.log(np.asarray(force, dtype=float))
    mu = np.asarray(mu, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.log(mu)
        rel = np.asarray(mu_err, dtype=float) / mu
    good = np.isfinite(y) & np.isfinite(rel) & (rel > 0) & np.isfinite(lnF)
    mean = np.full(len(mu), np.nan)
    var = np.full(len(mu), np.nan)
    if not good.any():
        return mean, var
    # Every experiment of every group (the same experiment code in two groups is two).
    g_code = np.unique(group, return_inverse=True)[1].ravel()
    e_code = np.unique(experiment, return_inverse=True)[1].ravel()
    pair, exp = np.unique(np.stack([g_code, e_code]), axis=1, return_inverse=True)
    exp = exp.ravel()
    w = np.where(good, 1.0 / np.where(good, rel, 1.0) ** 2, 0.0)
    x = np.where(good, lnF, 0.0)
    yv = np.where(good, y, 0.0)
    # Each experiment's sums over all its blocks with a μ, then those of the others of its group.
    E = pair.shape[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        S = np.bincount(exp, w, E)
        xbar = np.bincount(exp, w * x, E) / S
        ybar = np.bincount(exp, w * yv, E) / S
    dx = np.where(good, x - xbar[exp], 0.0)
    dy = np.where(good, yv - ybar[exp], 0.0)
    q_others = _others_in_group(np.bincount(exp, w * dx * dx, E), pair[0])
    p_others = _others_in_group(np.bincount(exp, w * dx * dy, E), pair[0])
    n_others = _others_in_group(np.bincount(exp, good, E).astype(float), pair[0])
    # The blocks of the experiments with n blocks, as a (k, n) table of block indices.
    order = np.argsort(exp, kind="stable")
    count = np.bincount(exp, minlength=E)
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    for n in np.unique(count):
        exps = np.flatnonzero(count == n)
        idx = order[start[exps][:, None] + np.arange(n)]  # (k, n)
        # (k, n, n): for block j of each experiment, the others of its experiment with a μ.
        mask = ~np.eye(n, dtype=bool) & good[idx][:, None, :]
        ww = np.where(mask, w[idx][:, None, :], 0.0)
        xx = np.broadcast_to(lnF[idx][:, None, :], mask.shape)
        yy = np.broadcast_to(y[idx][:, None, :], mask.shape)
        own = mask.sum(axis=2)
        span = np.where(mask, xx, -np.inf).max(axis=2) - np.where(mask, xx, np.inf).min(axis=2)
        ok = (own >= MU_PRIOR_MIN_LOADS) & (span > 0)
        if not ok.any():
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            Sj = ww.sum(axis=2)
            xj = (ww * np.where(mask, xx, 0.0)).sum(axis=2) / Sj
            yj = (ww * np.where(mask, yy, 0.0)).sum(axis=2) / Sj
            ddx = np.where(mask, xx - xj[..., None], 0.0)
            ddy = np.where(mask, yy - yj[..., None], 0.0)
            Q = q_others[exps][:, None] + (ww * ddx * ddx).sum(axis=2)
            b = (p_others[exps][:, None] + (ww * ddx * ddy).sum(axis=2)) / Q
            # The scatter that widens the prior is the block's own experiment's about the law
            # (its level a and the shared b): a mounting whose other loads scatter (a plateau
            # among them read with a high μ) must not borrow confidence from the others.
            dof = own - np.where(n_others[exps][:, None] > 0, 1, 2)
            chi2 = (ww * (ddy - b[..., None] * ddx) ** 2).sum(axis=2) / dof
            at = lnF[idx] - xj
            m = yj + b * at
            v = (1.0 / Sj + at**2 / Q) * np.maximum(chi2, 1.0)
        mean[idx[ok]] = m[ok]
        var[idx[ok]] = v[ok]
    return mean, var


def _others_in_group(values: np.ndarray, group: np.ndarray) -> np.ndarray:
    """The sum of ``values`` over the other experiments of each one's group (summed ahead and
    behind it, not as the group's total less its own: no cancellation when one dominates)."""
    out = np.zeros_like(values)
    for g in np.unique(group):
        at = np.flatnonzero(group == g)
        v = values[at]
        ahead = np.concatenate([[0.0], np.cumsum(v)[:-1]])
        behind = np.concatenate([np.cumsum(v[::-1])[:-1][::-1], [0.0]])
        out[at] = ahead + behind
    return out


def prior_penalty(mu, mu_err, mean, var, n_points) -> np.ndarray:
    """What the prior N(mean, var) of ln μ changes in the criterion of a Coulomb loop's fit.

    ``ln(1 + var/s²) + (ln μ - mean)²/(s² + var) - ln(2n)`` with s = ``mu_err``/``mu`` (the
    module docstring: the prior's Occam factor and misfit in place of the BIC's ln N for one
    parameter; ``n_points`` n per block, N = 2n residuals); 0 where there is no prior, no μ, or a
    μ not resolved (relative error above :data:`MU_PRIOR_MAX_REL`).
    """
    mu, mu_err, mean, var = (np.asarray(a, dtype=float) for a in (mu, mu_err, mean, var))
    with np.errstate(divide="ignore", invalid="ignore"):
        s2 = (mu_err / mu) ** 2
        d = np.log(mu) - mean
        pen = np.log1p(var / s2) + d**2 / (s2 + var) - np.log(2 * np.asarray(n_points, float))
    ok = np.isfinite(pen) & (s2 > 0) & (s2 <= MU_PRIOR_MAX_REL**2)
    return np.where(ok, pen, 0.0)


def mu_prior_reference(
    blocks: pd.DataFrame, joint: Mapping[str, pd.DataFrame], P: np.ndarray, usable: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The prior of ln μ of every load block (:func:`reference_mu`) from the model-averaged μ
    of the other blocks.

    Parameters
    ----------
    blocks : one row per block, with ``configuration``, ``medium``, ``experiment``,
        ``normal_force_N``
    joint : the joint fit table of each loop of :data:`~contactres.analysis._friction.
        COULOMB_LOOPS` (one row per block) with ``bic_shared``, its shared criterion without
        the prior (the weights of the model-averaged μ of the other blocks)
    P : (B,) the sensitivity of each block, Hz per N/m (paper 2, Eq. 1)
    usable : (B,) blocks that may serve as (and receive) a prior: those whose experiment's
        friction law is not Savkoor's

    Returns
    -------
    mean, var : (B,) of ln μ (NaN where there is none, and for the blocks not ``usable``)
    """
    F = blocks["normal_force_N"].to_numpy(float)
    mu, err, _ = model_averaged_mu(blocks, joint, P)
    mu = np.where(usable, mu, np.nan)
    experiment = blocks.groupby(["configuration", "medium", "experiment"], sort=False).ngroup()
    group = blocks.groupby(["configuration", "medium"], sort=False).ngroup()
    mean, var = reference_mu(experiment.to_numpy(), F, mu, err, group.to_numpy())
    return np.where(usable, mean, np.nan), np.where(usable, var, np.nan)


def mu_prior_penalties(
    blocks: pd.DataFrame, joint: Mapping[str, pd.DataFrame], P: np.ndarray, mean, var
) -> dict[str, np.ndarray]:
    """:func:`prior_penalty` of the joint fit of each Coulomb loop of every load block.

    ``blocks``, ``joint`` and ``P`` as for :func:`mu_prior_reference` (``blocks`` with
    ``n_points`` too), ``mean``, ``var`` its prior of ln μ. Returns the penalty of each loop of
    COULOMB_LOOPS (key -> (B,) array; 0 where there is no prior).
    """
    F = blocks["normal_force_N"].to_numpy(float)
    n = blocks["n_points"].to_numpy(float)
    out = {}
    for key in COULOMB_LOOPS:
        force, ferr, ok = loop_table_force(joint[key], P)
        pen = prior_penalty(force / F, ferr / F, mean, var, n)
        out[key] = np.where(ok, pen, 0.0)
    return out
