"""The checked inputs of the particle fit (:func:`contactres.analysis.fit_particles`): the
arrays of the shifts and their weights, and the overtones left out where the particle is
smaller than the liquid's penetration depth (module docstring of ``_particles``)."""

from __future__ import annotations

import numpy as np

from ..errors import ContactresInputError
from ..resonators import particle_model_validity
from ..validation import positive

__all__ = ["checked_sigma", "drop_inside_delta", "prepare"]


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
