"""``plateau`` (closed form): flat below the critical amplitude u_c, a straight line above
(the stick plateau of paper 2, Fig. 4C, D).

Fitted by :func:`contactres.analysis._amplitude.fit_hinge` (u_c on a grid of the amplitudes,
both channels in closed form for each); ``found`` is False where no u_c leaves enough points on
both sides.
"""

from __future__ import annotations

import numpy as np

from ...fitting import Parameter
from .._amplitude import fit_hinge
from .base import SLOPES, SweepFit, amplitude_model, closed_form_fields, closed_form_table

__all__ = ["FIT", "MODEL"]


def hinge(u, df0, dgamma0, df_slope, dgamma_slope, critical_amplitude):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m): the limits up to u_c, straight lines above."""
    excess = np.maximum(u - critical_amplitude, 0.0)
    return df0 + df_slope * excess, dgamma0 + dgamma_slope * excess


MODEL = amplitude_model(
    "plateau",
    "flat below u_c, linear above",
    (
        *SLOPES,
        Parameter(
            "critical_amplitude",
            "critical amplitude u_c",
            "m",
            "plateau_amplitude_m",
            (0.0, 1e-6),
            scale=1e-9,
        ),
    ),
    "paper 2, Fig. 4C, D (stick plateau)",
    hinge,
)


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """The best hinge of every sweep of the block ``b``: its lines, u_c and whether found."""
    found = fit_hinge(b)
    out = closed_form_fields(found.line)
    out["u_c_m"], out["found"] = found.u_c, found.found
    return out


FIT = SweepFit(
    "plateau",
    "hinge",
    False,
    fit,
    {**closed_form_table("slope"), "u_c_m": "critical_amplitude", "found": "found"},
)
