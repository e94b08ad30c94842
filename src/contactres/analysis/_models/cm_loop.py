"""``cattaneo-mindlin-loop``: the exact Cattaneo-Mindlin loop with a dashpot (paper 2,
Eqs. 4-6, Masing loops, and Eq. 12).

Δf = Pκ g1(x), ΔΓ = Pωξ + Pκ g2(x) with x = θu0, θ = κ/(μF_N), g1 = K′/κ and g2 = (K″ - ωξ)/κ
of the loop (:func:`loop_shape`: closed form, the values of the quadrature
:func:`contactres.analysis._loops.cm_loop_shape` within ~1e-13). Fitted by variable projection
on the loop table (:func:`contactres.analysis._loops.fit_cm_loops`), each channel weighted by
the noise level of the straight line (``line``, fitted before it).
"""

from __future__ import annotations

import numpy as np

from ...errors import ContactresInputError
from ...fitting import Model
from .._loops import fit_cm_loops
from .._plateau import plateau_loop_slopes
from .base import LOOP_TABLE, SweepFit, loop_parameters

__all__ = ["FIT", "MODEL", "TINY_X", "line_noise", "loop_shape"]

#: Below this x = κu0/(μF_N), :func:`loop_shape` takes the limit x = 0 (K′/κ = 1, K″ = ωξ).
TINY_X = 1e-100


def loop_shape(x, c=0.0) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of the Cattaneo-Mindlin loop behind a stick plateau, in closed form.

    Paper 2, Eqs. 4-6 with Masing's rule, at x = κu0/(μF_N) and c = κd_c/(μF_N) (broadcast
    together; c = 0: the plain Cattaneo-Mindlin loop): the closed form of the plateau loop fit,
    :func:`contactres.analysis._plateau.plateau_loop_slopes` without derivatives (elliptic
    integrals, or their power series; K″ elementary). It gives the values of the quadratures
    :func:`contactres.analysis._loops.cm_loop_shape` and
    :func:`~contactres.analysis._loops.plateau_loop_shape` within ~1e-13 (tests/analysis/
    test_curves.py checks it against :func:`contactres.loop_stiffness` with twice its nodes,
    an independent algorithm), at ~1/25 of their cost: the model functions of the exact loops
    and so the fitted curves of :func:`contactres.analysis._curves.fitted_curves` use it.

    Raises
    ------
    ContactresInputError
        Where x or c is not finite and >= 0 (e.g. a NaN fitted value), as the quadratures do,
        so that :func:`~contactres.analysis._curves.fitted_curves` finds the sweep without a
        curve.
    """
    x, c = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(c, dtype=float))
    if not (np.isfinite(x).all() and np.isfinite(c).all() and (x >= 0).all() and (c >= 0).all()):
        raise ContactresInputError("the loop's shape needs finite x >= 0 and c >= 0")
    # Below x = 1e-100 the shapes are 1 and 0 to far below rounding (1 - K′/κ ~ x/6,
    # (K″ - ωξ)/κ ~ 2x/(9π)), and the closed form's x² would underflow: take the limit x = 0.
    x = np.where(x < TINY_X, 0.0, x)
    g1, g2 = plateau_loop_slopes(x, c, derivatives=False)
    return g1, g2


def cm_loop(u, df0, dgamma0, inverse_slip_scale):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m) of the loop with Pκ = df0, Pωξ = dgamma0."""
    # Δf0 = Pκ and ΔΓ0 = Pωξ; the loop's shape depends on u0 only through κu0/(μF_N).
    g1, g2 = loop_shape(np.asarray(inverse_slip_scale) * np.asarray(u))
    return df0 * g1, dgamma0 + df0 * g2


MODEL = Model(
    "cattaneo-mindlin-loop",
    "exact Cattaneo-Mindlin loop with a dashpot",
    loop_parameters(),
    "amplitude",
    "m",
    "df, dgamma",
    "Hz",
    "paper 2, Eqs. 4-6 (Masing loops) and Eq. 12 (dashpot)",
    cm_loop,
)


def line_noise(b, done) -> np.ndarray:
    """(2, S): the noise levels of Δf and ΔΓ of every sweep, from the residuals of its
    straight line (n - 2 degrees of freedom)."""
    rss = np.stack([done["line"]["rss_df"], done["line"]["rss_dgamma"]])
    return np.sqrt(rss / np.maximum(b.n.astype(float) - 2, 1))


def fit(b, done, inputs) -> dict[str, np.ndarray]:
    """The exact loop fitted to every sweep of the block ``b``."""
    sigma = line_noise(b, done)
    loop = fit_cm_loops(b.u, b.df, b.dg, b.w, sigma[0], sigma[1], inputs.tables.cm)
    return {col: loop[col].to_numpy() for col in loop.columns}


FIT = SweepFit("cattaneo-mindlin-loop", "cm", True, fit, LOOP_TABLE)
