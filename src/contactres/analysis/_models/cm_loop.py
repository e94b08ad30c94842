"""``cattaneo-mindlin-loop``: the exact Cattaneo-Mindlin loop with a dashpot (paper 2,
Eqs. 4-6, Masing loops, and Eq. 12).

Δf = Pκ g1(x), ΔΓ = Pωξ + Pκ g2(x) with x = θu0, θ = κ/(μF_N), g1 = K′/κ and g2 = (K″ - ωξ)/κ
of the loop (:func:`cm_shape`: closed form, the values of the quadrature
:func:`contactres.analysis._loops.cm_loop_shape` within ~1e-13). Fitted by variable projection
on the loop table (:func:`contactres.analysis._loops.fit_cm_loops`), each channel weighted by
the noise level of the straight line (``line``, fitted before it).
"""

from __future__ import annotations

import numpy as np

from ...errors import ContactresInputError
from ...fitting import Model
from .._loops import fit_cm_loops
from .._plateau_series import SERIES_CELLS, SERIES_TIERS
from .._plateau_slopes import plateau_loop_slopes
from .base import LOOP_TABLE, SweepFit, loop_parameters

__all__ = ["FIT", "MODEL", "TINY_X", "cm_shape", "line_noise", "loop_shape"]

#: Below this x = κu0/(μF_N), :func:`loop_shape` takes the limit x = 0 (K′/κ = 1, K″ = ωξ).
TINY_X = 1e-100


def _even_coefficients(n: int) -> np.ndarray:
    """b_{2j} T_{2j}, j = 0..n: b_k = binom(1/2, k), T_k = ∫₀^π sin²φ cosᵏφ dφ (the series
    of :mod:`contactres.analysis._plateau_series` at c = 0, where T_k = 0 for odd k)."""
    b, t, out = 1.0, 0.5 * np.pi, [0.5 * np.pi]
    for k in range(1, 2 * n + 1):
        b *= (1.5 - k) / k
        if k % 2 == 0:
            t *= (k - 1) / (k + 2)
            out.append(b * t)
    return np.array(out)


#: The coefficients of :func:`cm_shape`'s series in q², enough for its last tier.
EVEN_COEFFICIENTS = _even_coefficients(SERIES_TIERS[-1][1] // 2)


def loop_shape(x, c=0.0) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of the Cattaneo-Mindlin loop behind a stick plateau, in closed form.

    Paper 2, Eqs. 4-6 with Masing's rule, at x = κu0/(μF_N) and c = κd_c/(μF_N) (broadcast
    together; c = 0: the plain Cattaneo-Mindlin loop): the closed form of the plateau loop fit,
    :func:`contactres.analysis._plateau_slopes.plateau_loop_slopes` without derivatives (elliptic
    integrals, or their power series; K″ elementary). It gives the values of the quadratures
    :func:`contactres.analysis._loops.cm_loop_shape` and
    :func:`~contactres.analysis._loops.plateau_loop_shape` within ~1e-13 (tests/analysis/
    test_curves.py checks it against :func:`contactres.loop_stiffness` with twice its nodes,
    an independent algorithm), at ~1/25 of their cost: the model function of the plateau loop
    (and so its fitted curves, :func:`contactres.analysis._curves.fitted_curves`) uses it; the
    plain loop's, :func:`cm_shape` (its series at c = 0, cheaper still).

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


def cm_shape(x) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of the Cattaneo-Mindlin loop at x = κu0/(μF_N): :func:`loop_shape`
    at c = 0, at about half its cost.

    At c = 0 the series of the slip integral J (:mod:`contactres.analysis._plateau_series`,
    m = min(x, 3/2)/max(x, 3/2) < 7/8, the same terms per tier of m) has no odd terms and its
    coefficients are numbers: J = (r²/4) √A Σ_j b_{2j} T_{2j} q^{2j}, summed by Horner's rule
    (2 operations per term, not ~14); K′/κ = 8/(πx²) √(2/3) J. Points with m >= 7/8 (around full
    sliding) take :func:`loop_shape`. The loss part is that of
    :func:`~contactres.analysis._plateau_slopes.plateau_loop_slopes` at c = 0: 4W(x)/(πx²), W(y) =
    ∫₀^min(y, 3/2) √(1 - 2t/3)(y - 2t) dt, a polynomial in √(1 - 2y/3) below full sliding.
    Same accuracy as :func:`loop_shape` (tests/analysis/test_curves.py).

    Raises
    ------
    ContactresInputError
        Where x is not finite and >= 0.
    """
    x = np.asarray(x, dtype=float)
    if not (np.isfinite(x).all() and (x >= 0).all()):
        raise ContactresInputError("the loop's shape needs finite x >= 0")
    shape, x = x.shape, x.ravel()
    # Every point through the same arithmetic, elementwise (the numbers of each point its own),
    # and those below TINY_X set to the limit x = 0 at the end, as in loop_shape: no gather of
    # the others and no scatter back (a curve's grid starts at x = 0).
    r, big = np.minimum(x, 1.5), np.maximum(x, 1.5)
    a = big - 0.5 * r
    qq = 0.5 * r / a
    qq *= qq
    tier = np.fmin(r / big * SERIES_CELLS, len(SERIES_TIERS)).astype(np.int8)
    total = np.empty(x.shape)
    # The points by tier: one stable sort of the small integers (numpy's radix sort), so that
    # each tier is a slice of it, not a pass over every point.
    order = np.argsort(tier, kind="stable")
    starts = np.concatenate([[0], np.cumsum(np.bincount(tier, minlength=len(SERIES_TIERS)))])
    for j, (_, terms) in enumerate(SERIES_TIERS):
        at = order[starts[j] : starts[j + 1]]
        if at.size:
            q2, coefficients = qq[at], EVEN_COEFFICIENTS[: terms // 2 + 1]
            part = np.full(at.shape, coefficients[-1])
            for value in coefficients[-2::-1]:  # Horner's rule in q²
                part *= q2
                part += value
            total[at] = part
    x2 = x * x
    with np.errstate(divide="ignore", invalid="ignore"):  # x below TINY_X: replaced below
        g1 = (2.0 * np.sqrt(2.0 / 3.0) / np.pi) * r * r * np.sqrt(a) * total / x2
    near = order[starts[len(SERIES_TIERS)] :]  # m >= 7/8: beyond the series' cells
    if near.size:
        g1[near] = loop_shape(x[near])[0]
    # W(x) as in plateau_loop_slopes (c = 0): 1 - √(1 - 2x/3) = (2x/3)/(1 + √(1 - 2x/3));
    # beyond full sliding (x >= 3/2) W = x - 6/5.
    root = np.sqrt(np.maximum(1.0 - x / 1.5, 0.0))
    v = (x / 1.5) / (1.0 + root)
    w = 0.3 * v**3 * (root * root + 3.0 * root + 1.0)
    np.copyto(w, x - 1.2, where=x >= 1.5)
    with np.errstate(divide="ignore", invalid="ignore"):
        g2 = 4.0 * w / (np.pi * x2)
    tiny = x < TINY_X
    np.copyto(g1, 1.0, where=tiny)
    np.copyto(g2, 0.0, where=tiny)
    return g1.reshape(shape), g2.reshape(shape)


def cm_loop(u, df0, dgamma0, inverse_slip_scale):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m) of the loop with Pκ = df0, Pωξ = dgamma0."""
    # Δf0 = Pκ and ΔΓ0 = Pωξ; the loop's shape depends on u0 only through κu0/(μF_N).
    g1, g2 = cm_shape(np.asarray(inverse_slip_scale) * np.asarray(u))
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
