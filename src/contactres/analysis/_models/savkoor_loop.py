"""``savkoor-loop``: the exact Savkoor loop (constant sliding traction τ0) with a dashpot
(paper 2, Eqs. 13-14 with Masing's rule, and Eq. 12).

Δf = Pκ g1(x), ΔΓ = Pωξ + Pκ g2(x) with x = u0/d_s, d_s = 4a²τ0/κ the amplitude of full
sliding, g1 = K′/κ and g2 = (K″ - ωξ)/κ of the loop (:func:`savkoor_shape`: the values of the
quadrature :func:`contactres.analysis._loops.savkoor_loop_shape` to its accuracy, at ~1/10 of
its cost). Fitted like the Cattaneo-Mindlin loop, on Savkoor's table.

The in-phase part by its power series. In units κ = d_s = 1 the virgin slope is
F′(d) = √(1 - d²) below full sliding (d < 1), 0 beyond, and the Masing form of
:func:`contactres.resonators.masing_stiffness` gives

    g1 = 8/(πx²) ∫₀^r √(d(x - d)(1 - d)(1 + d)) dd,    r = min(x, 1), R = max(x, 1).

With d = r(1 - cos φ)/2 (√(d(r - d)) dd = r² sin²φ dφ/4; {x, 1} = {r, R}), R - d = A(1 + q cos φ)
and 1 + d = B(1 - p cos φ), A = R - r/2, q = r/(2A) = m/(2 - m), m = r/R, B = 1 + r/2,
p = r/(2B) <= 1/3:

    g1 = (2r²/(πx²)) √(AB) Σ_k γ_k T_k,    T_k = ∫₀^π sin²φ cosᵏφ dφ,

γ_k the Taylor coefficients of f(t) = √((1 + qt)(1 - pt)). T_k = 0 for odd k, T_0 = π/2,
T_k = T_{k-2}(k - 1)/(k + 2). From (1 + qt)(1 - pt) f′ = [(q - p)/2 - pqt] f,

    γ_{k+1} = [(q - p)(1/2 - k) γ_k + pq(k - 2) γ_{k-1}]/(k + 1),   γ_0 = 1, γ_1 = (q - p)/2,

a recursion whose wanted solution is its dominant one (f's nearest singularity, at t = -1/q or
1/p, sets both its growth and that of the recursion), so forward-stable. The loss part is
elementary: (K″ - ωξ)/κ = area/(πx²), the loop area of :meth:`contactres.SavkoorLoop.area`
(paper 2, Eq. 5; its series at small x, where the closed form cancels).
"""

from __future__ import annotations

import numpy as np

from ...errors import ContactresInputError
from ...fitting import Model
from ...resonators import DEFAULT_NODES, loop_stiffness
from ...tangential import SavkoorLoop
from .._loops import fit_cm_loops
from .base import LOOP_TABLE, SweepFit, loop_parameters
from .cm_loop import TINY_X, line_noise

__all__ = ["BAND_CHUNK", "FIT", "MODEL", "SAVKOOR_CELLS", "SAVKOOR_TERMS", "savkoor_shape"]

#: The series' tiers: ρ = max(q, p) in cells 1/SAVKOOR_CELLS wide, a point's tier
#: floor(SAVKOOR_CELLS ρ) (exact: a power of two). Beyond the last cell (q >= 7/8, i.e.
#: 0.933 < x < 1.071, around full sliding) the series would sum hundreds of terms: those points
#: take the quadrature of :func:`contactres.loop_stiffness`.
SAVKOOR_CELLS = 16

#: The last index k summed in each cell of ρ: the fewest for which the rest of the series stays
#: below 1e-17 (Σ_{k>K} M_k T_k, M_k the coefficients of (2 - √(1 - ρt))², which bound |γ_k|,
#: at the cell's largest ρ; tests/analysis/test_curves.py checks the bound).
SAVKOOR_TERMS = (10, 14, 18, 22, 26, 30, 34, 42, 48, 60, 74, 94, 128, 192)

#: Points per call of the quadrature near full sliding: its temporaries (~48 nodes per point
#: and sub-interval) stay at a few MB.
BAND_CHUNK = 2**13


def _savkoor_series(q, p, terms):
    """Σ_{k <= terms} γ_k T_k (module docstring) at q, p (1-d arrays)."""
    a, b = q - p, p * q
    older, old = np.ones_like(q), 0.5 * a  # γ_0, γ_1
    total = 0.5 * np.pi * older
    t = 0.5 * np.pi  # T_0
    for k in range(1, terms):
        new = a * old
        new *= (0.5 - k) / (k + 1)
        new += b * older * ((k - 2) / (k + 1))
        older, old = old, new  # γ_k, γ_{k+1}
        if k % 2:  # k + 1 even: T_{k+1} = T_{k-1} k/(k + 3)
            t *= k / (k + 3)
            total += t * new
    return total


def savkoor_shape(x) -> tuple[np.ndarray, np.ndarray]:
    """K′/κ and (K″ - ωξ)/κ of Savkoor's loop at x = u0/d_s (d_s = 4a²τ0/κ), in closed form.

    Paper 2, Eqs. 13-14 with Masing's rule (module docstring): the in-phase part by its power
    series, the loss part from the loop's area; points too close to full sliding for the series
    (0.933 < x < 1.071) by the quadrature of :func:`contactres.loop_stiffness` with twice its
    default nodes. Within ~1e-13 of that quadrature with four times its nodes
    (tests/analysis/test_curves.py), at ~1/10 of the cost of
    :func:`contactres.analysis._loops.savkoor_loop_shape` on a curve from 0 to a few d_s.

    Raises
    ------
    ContactresInputError
        Where x is not finite and >= 0, as the quadrature does.
    """
    x = np.asarray(x, dtype=float)
    if not (np.isfinite(x).all() and (x >= 0).all()):
        raise ContactresInputError("the loop's shape needs finite x >= 0")
    shape, x = x.shape, x.ravel()
    loop = SavkoorLoop(kappa=1.0, tau=1.0, a=0.5)  # d_s = 4a²τ0/κ = 1
    g1, g2 = np.ones(x.shape), np.zeros(x.shape)
    slip = x >= TINY_X  # below: the limit x = 0 (1 - K′/κ ~ 5x²/32, K″ - ωξ ~ x²/(3π))
    xs = x[slip]
    r, big = np.minimum(xs, 1.0), np.maximum(xs, 1.0)
    a, b = big - 0.5 * r, 1.0 + 0.5 * r
    q, p = 0.5 * r / a, 0.5 * r / b
    tier = np.fmin(np.maximum(q, p) * SAVKOOR_CELLS, len(SAVKOOR_TERMS)).astype(np.int8)
    total = np.empty(xs.shape)
    for j, terms in enumerate(SAVKOOR_TERMS):
        at = np.flatnonzero(tier == j)
        if at.size:
            total[at] = _savkoor_series(q[at], p[at], terms)
    first = 2.0 * r * r / (np.pi * xs * xs) * np.sqrt(a * b) * total
    # Twice the quadrature's default nodes (its 1e-9 is ~1e-11 there, this ~1e-14), by chunks.
    near = np.flatnonzero(tier >= len(SAVKOOR_TERMS))
    for at in np.split(near, range(BAND_CHUNK, near.size, BAND_CHUNK)):
        if at.size:
            first[at] = loop_stiffness(loop, xs[at], 2 * DEFAULT_NODES).real
    g1[slip] = first
    area = loop.area(xs)
    g2[slip] = np.asarray(area, dtype=float) / (np.pi * xs * xs)
    return g1.reshape(shape), g2.reshape(shape)


def savkoor_loop(u, df0, dgamma0, inverse_slip_scale):
    """Δf, ΔΓ (Hz) at the amplitudes ``u`` (m) of the loop with Pκ = df0, Pωξ = dgamma0."""
    # Savkoor's loop is self-similar in u0/d_s (d_s = 4a²τ0/κ: full sliding).
    g1, g2 = savkoor_shape(np.asarray(inverse_slip_scale) * np.asarray(u))
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
