"""``elastic``: no amplitude dependence, Δf = Δf0, ΔΓ = ΔΓ0 (a Voigt element; paper 2, Eq. 1).

Fitted by the weighted mean of each channel; the standard errors are those of the means.
"""

from __future__ import annotations

import numpy as np

from .base import SweepFit, amplitude_model

__all__ = ["FIT", "MODEL"]


def elastic(u, df0, dgamma0):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m): the limits, independent of u."""
    return df0 + 0.0 * u, dgamma0 + 0.0 * u


MODEL = amplitude_model(
    "elastic", "no amplitude dependence", (), "paper 2, Eq. 1 (Voigt element)", elastic
)


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """The weighted means of Δf and ΔΓ of every sweep of the block ``b``, their standard errors
    (residual variance / (n - 1) / n) and residual sums."""
    Y = np.stack([b.df, b.dg])
    n = b.n.astype(float)
    mean = (b.w * Y).sum(-1) / n
    rss = (b.w * (Y - mean[..., None]) ** 2).sum(-1)
    var_mean = rss / np.maximum(n - 1, 1) / n
    out = {}
    for c, name in enumerate(("df", "dgamma")):
        out[f"{name}0_Hz"] = mean[c]
        out[f"{name}0_err_Hz"] = np.sqrt(var_mean[c])
        out[f"rss_{name}"] = rss[c]
    return out


FIT = SweepFit(
    "elastic",
    "el",
    False,
    fit,
    {
        "df0_Hz": "df0",
        "df0_err_Hz": "df0_err",
        "rss_df": "rss_df",
        "dgamma0_Hz": "dgamma0",
        "dgamma0_err_Hz": "dgamma0_err",
        "rss_dgamma": "rss_dgamma",
    },
)
