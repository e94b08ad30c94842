"""The checked inputs of the particle fit (:func:`contactres.analysis.fit_particles`): the
arrays of the shifts and their weights, and the overtones left out where the particle is
smaller than the liquid's penetration depth (module docstring of ``_particles``)."""

from __future__ import annotations

import numpy as np

from ..errors import ContactresInputError
from ..resonators import particle_model_validity
from ..validation import positive
from ._particle_linear import misfit, model_variance

__all__ = ["checked_sigma", "difference_noise", "drop_inside_delta", "noise_check", "prepare"]

#: The fewest time steps from which the noise is read off the step-to-step differences.
MIN_DIFFERENCE_STEPS = 5


def prepare(fundamental, overtones, df, dgamma, sigma_df, sigma_dgamma):
    """Checked arrays: f_F, n (n,), z = Δf + iΔΓ (T, n) and the weights 1/σ (T, n)."""
    f0 = positive("fundamental frequency", fundamental, "Hz")
    try:
        n = np.asarray(overtones, dtype=float)
    except (TypeError, ValueError):
        raise ContactresInputError(f"overtones must be integers >= 1, got {overtones!r}") from None
    if n.ndim != 1 or n.size < 2:
        raise ContactresInputError(
            f"fit_particles needs at least two overtones (a 1-D list), got {overtones!r}"
        )
    if np.any(~np.isfinite(n)) or np.any(n < 1) or np.any(n != np.round(n)):
        raise ContactresInputError(f"overtones must be integers >= 1, got {overtones!r}")
    d = np.atleast_2d(np.asarray(df, dtype=float))
    g = np.atleast_2d(np.asarray(dgamma, dtype=float))
    if d.shape != g.shape or d.shape[-1] != n.size or d.ndim != 2:
        raise ContactresInputError(
            f"df and dgamma must both have shape (T, {n.size}) or ({n.size},) for {n.size} "
            f"overtones, got {np.shape(df)} and {np.shape(dgamma)}"
        )
    if np.all(np.isnan(g)):
        raise ContactresInputError(
            "the bandwidth shifts dgamma are all missing: the particle fit needs Δf and ΔΓ"
        )
    estimate = sigma_df is None and sigma_dgamma is None
    if (sigma_df is None) != (sigma_dgamma is None):
        raise ContactresInputError("give both sigma_df and sigma_dgamma, or neither")
    wf = np.ones(d.shape) if estimate else 1.0 / checked_sigma("sigma_df", sigma_df, d.shape)
    wg = (
        np.ones(d.shape) if estimate else 1.0 / checked_sigma("sigma_dgamma", sigma_dgamma, d.shape)
    )
    # an overtone counts only with both of its shifts
    measured = np.isfinite(d) & np.isfinite(g)
    wf, wg = np.where(measured, wf, 0.0), np.where(measured, wg, 0.0)
    z = np.where(measured, d + 1j * g, 0.0)
    return f0, n, z, wf, wg, estimate


def checked_sigma(name, sigma, shape):
    s = np.asarray(sigma, dtype=float)
    if np.any(~np.isfinite(s)) or np.any(s <= 0):
        raise ContactresInputError(f"{name} must be finite and > 0 (Hz), got {sigma!r}")
    try:
        return np.broadcast_to(s, shape)
    except ValueError:
        raise ContactresInputError(f"{name} of shape {s.shape} does not fit data {shape}") from None


def drop_inside_delta(particle, freq, medium, wf, wg, estimate, fit_rocking, min_dof):
    """In a liquid, the overtones at which the particle is smaller than the penetration depth
    (:func:`~contactres.resonators.particle_model_validity`; δ ∝ 1/√f, so the lowest) are
    left out of the fit: their weights are set to 0 in place. Returns (reason, dropped): the
    reason of the lowest overtone when too few overtones remain (2, or ``min_dof`` degrees of
    freedom with the noise estimated) and nothing is dropped (every value is then flagged),
    else None and the indices of the dropped overtones."""
    none = np.array([], int)
    bad = np.array([particle_model_validity(particle, f, medium) is not None for f in freq])
    if not bad.any():
        return None, none
    left = int((~bad).sum())
    n_par = 4 if fit_rocking else 3
    if left < 2 or (estimate and 2 * left - n_par < min_dof):
        return particle_model_validity(particle, freq, medium), none
    wf[:, bad] = 0.0
    wg[:, bad] = 0.0
    return None, np.flatnonzero(bad)


def difference_noise(z, measured):
    """The noise variance of the shifts read off the time series alone, independently of any
    model: per overtone and per observable (Δf_n, ΔΓ_n), the robust spread of the first
    differences between consecutive steps, 1.4826 MAD/√2 (a difference of two independent
    draws has √2 times their spread; the MAD about the median difference ignores a steady
    drift and a few jumps), squared and averaged over the series that have at least
    :data:`MIN_DIFFERENCE_STEPS` - 1 differences.

    It assumes that the shifts change slowly from one step to the next compared with the
    noise: a fast change of the signal makes it larger (a fit is then less often called a
    misfit, never more often); noise correlated between neighbouring steps makes it smaller.

    Parameters
    ----------
    z : (T, n) complex, Δf_n + iΔΓ_n, Hz
    measured : (T, n) bool, the points that are fitted

    Returns
    -------
    (variance, count) : the mean noise variance, Hz², and the number of differences it rests
        on; (NaN, 0) for fewer than :data:`MIN_DIFFERENCE_STEPS` steps (a single time point
        has no such estimate)
    """
    if z.shape[0] < MIN_DIFFERENCE_STEPS:
        return np.nan, 0
    variances, count = [], 0
    for part in (z.real, z.imag):
        diff = np.diff(np.where(measured, part, np.nan), axis=0)
        for col in diff.T:
            col = col[np.isfinite(col)]
            if col.size < MIN_DIFFERENCE_STEPS - 1:
                continue
            mad = np.median(np.abs(col - np.median(col)))
            variances.append((1.4826 * mad) ** 2 / 2.0)
            count += col.size
    if not variances:
        return np.nan, 0
    return float(np.mean(variances)), count


def noise_check(chi2, dof, conv, z, measured):
    """(σ̂, σ_series, misfit): the noise (Hz) the fit's residuals imply
    (``_particle_linear.model_variance``), that of the series read off its step-to-step
    differences (:func:`difference_noise`; NaN with fewer than 5 steps) and whether the model
    misfits beyond the noise (``_particle_linear.misfit``)."""
    s2_fit = model_variance(chi2, dof, conv)
    s2_series, count = difference_noise(z, measured)
    bad = misfit(s2_fit, s2_series, dof, count)
    return float(np.sqrt(s2_fit)), float(np.sqrt(s2_series)), bad
