"""``savkoor-loop``: the exact Savkoor loop (constant sliding traction τ0) with a dashpot
(paper 2, Eqs. 13-14 with Masing's rule, and Eq. 12).

Δf = Pκ g1(x), ΔΓ = Pωξ + Pκ g2(x) with x = u0/d_s, d_s = 4a²τ0/κ the amplitude of full
sliding (:func:`contactres.analysis._loops.savkoor_loop_shape`). Fitted like the
Cattaneo-Mindlin loop, on Savkoor's table.
"""

from __future__ import annotations

import numpy as np

from ...fitting import Model
from .._loops import fit_cm_loops, savkoor_loop_shape
from .base import LOOP_TABLE, SweepFit, loop_parameters
from .cm_loop import line_noise

__all__ = ["FIT", "MODEL"]


def savkoor_loop(u, df0, dgamma0, inverse_slip_scale):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m) of the loop with Pκ = df0, Pωξ = dgamma0."""
    # Savkoor's loop is self-similar in u0/d_s (d_s = 4a²τ0/κ: full sliding).
    g1, g2 = savkoor_loop_shape(np.asarray(inverse_slip_scale) * np.asarray(u))
    return df0 * g1, dgamma0 + df0 * g2


MODEL = Model(
    "savkoor-loop",
    "exact Savkoor loop (constant sliding traction) with a dashpot",
    loop_parameters("1/d_s = κ/(4a²τ0)"),
    "amplitude",
    "m",
    "df, dgamma",
    "Hz",
    "paper 2, Eqs. 13-14 (Masing loops) and Eq. 12 (dashpot)",
    savkoor_loop,
)


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """Savkoor's exact loop fitted to every sweep of the block ``b``."""
    sigma = line_noise(b, done)
    loop = fit_cm_loops(b.u, b.df, b.dg, b.w, sigma[0], sigma[1], inputs.tables.savkoor)
    return {col: loop[col].to_numpy() for col in loop.columns}


FIT = SweepFit("savkoor-loop", "sv", True, fit, LOOP_TABLE)
