"""``cattaneo-mindlin`` (closed form): a straight line in u0, the small-amplitude form of the
Cattaneo-Mindlin loop (paper 2, Eq. 12).

Fitted in closed form to both channels (:func:`contactres.analysis._amplitude.fit_line`); its
residuals also give the noise levels that weight the exact loops, and its slopes μ by Eq. 12.
"""

from __future__ import annotations

import numpy as np

from .._amplitude import fit_line
from .base import SLOPES, SweepFit, amplitude_model, closed_form_fields, closed_form_table

__all__ = ["FIT", "MODEL"]


def line(u, df0, dgamma0, df_slope, dgamma_slope):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m): straight lines from the limits."""
    return df0 + df_slope * u, dgamma0 + dgamma_slope * u


MODEL = amplitude_model(
    "cattaneo-mindlin", "linear in u0 (Cattaneo-Mindlin)", SLOPES, "paper 2, Eq. 12", line
)


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """The weighted straight line of every sweep of the block ``b``, both channels."""
    return closed_form_fields(fit_line(b.u, np.stack([b.df, b.dg]), b.w))


FIT = SweepFit("cattaneo-mindlin", "line", False, fit, closed_form_table("slope"))
