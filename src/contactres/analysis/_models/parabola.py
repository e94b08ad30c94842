"""``savkoor`` (closed form): a straight line in u0², the small-amplitude form of Savkoor's
loop (constant sliding traction; paper 2, Eq. 15).

Fitted in closed form to both channels as a straight line in u0²
(:func:`contactres.analysis._amplitude.fit_line`); its slopes are the reported curvatures.
"""

from __future__ import annotations

import numpy as np

from .._amplitude import fit_line
from .base import CURVATURES, SweepFit, amplitude_model, closed_form_fields, closed_form_table

__all__ = ["FIT", "MODEL"]


def parabola(u, df0, dgamma0, df_curvature, dgamma_curvature):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m): parabolas in u from the limits."""
    return df0 + df_curvature * u**2, dgamma0 + dgamma_curvature * u**2


MODEL = amplitude_model(
    "savkoor", "parabolic in u0 (Savkoor)", CURVATURES, "paper 2, Eq. 15", parabola
)


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """The weighted straight line in u0² of every sweep of the block ``b``, both channels."""
    return closed_form_fields(fit_line(b.u**2, np.stack([b.df, b.dg]), b.w))


FIT = SweepFit("savkoor", "parabola", False, fit, closed_form_table("curvature"))
