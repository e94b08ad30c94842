"""The far field κ > T₁ of the N(r̄, φ) integrals (paper 1, Eqs. 22 and 27).

There the kernel table holds g − g∞ as a Chebyshev series in w = (T₁/κ)² per angular harmonic
e^{2imθ}. With s = κ k_s a, every harmonic is integrated against the analytic Bessel weights of
the pressure shapes on a fixed grid in s: geometric panels from s_low = T₁ × (smallest k_s a of
the call) up to s = 8, uniform panels of width 2 up to ``Resolution.s_coarse`` (there the
hand-over of the larger k a, of width ~ s/18, is resolved), then wider panels of 2.5 nodes per
unit of s (the weights oscillate with frequency <= 2) up to ``Resolution.s_far``; beyond it the
leading asymptotic term is added in closed form. The grid, the Chebyshev basis on it and the
weights are built once per call (:func:`far_basis`, :func:`far_weights`) and passed to every
model and point of that call; nothing is kept between calls.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special

from ..numerics import gauss_legendre
from ._table import KernelTable, Resolution, handover
from ._weights import bessel_even, j1_over_s, sinc, wa_harmonic_weights

TYPE_CHECKING = False
if TYPE_CHECKING:
    from ._tangential_table import TangentialTable

__all__ = [
    "FarBasis",
    "FarGrid",
    "far_basis",
    "far_grid",
    "far_limit",
    "far_remainder",
    "far_weights",
    "low_rank",
    "tail_sine",
]

# The non-axisymmetric harmonics of the WA weight are integrated up to this s (see far_weights).
_WA_HARMONIC_CUT = 120.0
# Singular values kept by low_rank, relative to the largest.
_RANK_TOL = 1e-15


@dataclass(frozen=True, eq=False)
class FarBasis:
    """The far-field s grid of one call and the Chebyshev basis of the kernel table on it.

    Attributes
    ----------
    ka : (na,) the k_s a values (> 0) the basis was built for
    s : (ns,) Gauss-Legendre nodes of the s grid (dimensionless, s = η a)
    s_end : end S of the grid
    basis : (na, ns, nf) T_f(2w − 1) × w × (1 − χ(s/ka)) × ds with w = (T₁ ka/s)² (zero where
        w > 1), so that ``basis @ far_coeffs[m]`` is harmonic m of g − g∞ at κ = s/ka times the
        hand-over and the quadrature weight ds
    """

    ka: np.ndarray
    s: np.ndarray
    s_end: float
    basis: np.ndarray


def _far_grid(res: Resolution, s_low: float):
    """Nodes and weights of the far-field s integral on [s_low, s_far]: geometric panels up to
    s = 8, uniform ones of width ``s_panel`` up to ``s_coarse``, then wide ones."""
    top = 8.0
    edges = [top]
    while edges[-1] > s_low:
        edges.append(edges[-1] / res.s_ratio)
    edges = edges[::-1]
    mid = max(top, min(res.s_coarse, res.s_far))
    n_uni = max(1, math.ceil((mid - top) / res.s_panel))
    edges.extend(top + res.s_panel * np.arange(1, n_uni + 1))
    bounds = np.asarray(edges)
    s, ws = gauss_legendre(bounds[:-1, None], bounds[1:, None], res.n_gauss)
    s, ws = s.ravel(), ws.ravel()
    n_wide = math.ceil((res.s_far - bounds[-1]) / res.s_panel_coarse)
    if n_wide <= 0:
        return s, ws, float(bounds[-1])
    wide = bounds[-1] + res.s_panel_coarse * np.arange(n_wide + 1)
    s2, ws2 = gauss_legendre(wide[:-1, None], wide[1:, None], res.n_gauss_coarse)
    return np.concatenate([s, s2.ravel()]), np.concatenate([ws, ws2.ravel()]), float(wide[-1])


@dataclass(frozen=True, eq=False)
class FarGrid:
    """The far-field s grid of one call: Gauss-Legendre nodes ``s``, weights ``ds`` (both (ns,),
    dimensionless) on [s_low, ``s_end``]; s_low depends only on the smallest k_s a of the call."""

    s: np.ndarray
    ds: np.ndarray
    s_end: float


def far_grid(table: KernelTable | TangentialTable, ka_min: float) -> FarGrid:
    """The far-field grid of a call whose smallest positive k_s a is ``ka_min``.

    It starts at a power of ``Resolution.s_ratio`` just below T₁ × ka_min, so every chunk of a
    call (and every call with the same smallest k_s a) gets the same grid.
    """
    res = table.resolution
    s_low = table.t1 * float(ka_min)
    level = math.floor(math.log(max(s_low, 1e-8)) / math.log(res.s_ratio))
    return FarGrid(*_far_grid(res, res.s_ratio**level))


def far_basis(
    table: KernelTable | TangentialTable, ka: np.ndarray, grid: FarGrid | None = None
) -> FarBasis:
    """The far-field s grid for the k_s a values ``ka`` (1-D, > 0) and the Chebyshev basis on it.

    ``grid`` (from :func:`far_grid`) is the grid of the whole call when ``ka`` is one chunk of
    it; by default the grid of min(ka), so it depends on the smallest k_s a (and nothing else).
    Memory: ns × n_fit × 8 bytes per k a value (~0.6 MB at the default resolution).
    """
    if grid is None:
        grid = far_grid(table, float(np.min(ka)))
    sg, ds, s_end = grid.s, grid.ds, grid.s_end
    w = (table.t1 * ka[:, None] / sg[None, :]) ** 2  # (na, ns)
    inside = w <= 1
    x = np.where(inside, 2 * w - 1, 1.0)
    nf = table.far_coeffs.shape[1]
    kappa = sg[None, :] / ka[:, None]
    # χ(κ) <= 1e-17 from κ = 2T₁ on, where 1 − χ rounds to 1: erfc only below.
    blend = kappa < 2 * table.t1
    far_share = np.ones(kappa.shape)
    far_share[blend] = 1 - handover(kappa[blend], table.t1)
    hand = far_share * inside * w * ds[None, :]
    # hand × T_f(x) by the three-term recurrence (linear, so it carries the factor), stored
    # (nf, na, ns): chebvander(x) * hand[..., None] without its two full-size temporaries and
    # without a pass over the whole basis to scale it.
    v = np.empty((nf, *x.shape))
    v[0] = hand
    if nf > 1:
        np.multiply(x, hand, out=v[1])
        x2 = 2 * x
        for f in range(2, nf):
            np.multiply(v[f - 1], x2, out=v[f])
            v[f] -= v[f - 2]
    return FarBasis(ka=ka, s=sg, s_end=s_end, basis=np.moveaxis(v, 0, -1))


def low_rank(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``left`` (m, k) and ``right`` (k, n, orthonormal rows) with left @ right = ``matrix``
    (real, (m, n)) to 1e-15 of its largest singular value: the truncated SVD."""
    u, sv, vt = np.linalg.svd(matrix, full_matrices=False)
    rank = max(1, int(np.count_nonzero(sv > _RANK_TOL * sv[0])))
    return u[:, :rank] * sv[:rank], vt[:rank]


def far_weights(table: KernelTable, s: np.ndarray, orders=None) -> np.ndarray:
    """Analytic weights of the far field on the nodes ``s`` (of :func:`far_basis`).

    Returns a (6, n_o, n_s) array: for the functionals F0, F1, FW, F2D, H0, H1 (see
    :func:`contactres.dynamic._quadrature.functionals`) and the harmonic e^{inθ} of order n in
    ``orders`` (default: n = 2|m| for the m of ``table.far_harmonics``, one row per distinct
    n: the weights of e^{±inθ} are the same), the factor 2π iⁿ × (Hankel transform of the
    pressure shape: sin s/s or j₁(s)/s) × (J_n(s r̄) at the point, or its weighted average W_n,
    paper 1, Eq. 27).
    """
    res = table.resolution
    flat = sinc(s)
    hertz = j1_over_s(s)
    if orders is None:
        orders = np.unique(2 * np.abs(table.far_harmonics))
    nabs = [int(n) for n in orders]
    jtab = bessel_even(nabs, s)
    # WA weights of the non-axisymmetric harmonics: their share of N is ~1e-3, so stopping
    # them at s = _WA_HARMONIC_CUT costs < 1e-8 relative (their tail ~ s^-2.5). W_0 is sinc(s).
    cut = s <= min(_WA_HARMONIC_CUT, res.s_far)
    if max(nabs) > 0:
        wtab = wa_harmonic_weights(s[cut], max(nabs))
    # All orders at once, rows (n_o, ns), not order by order (issue 31: the per-order loop was
    # ~10 small numpy calls per order): the same products, 2π × the shape first, then × J_n or
    # W_n, and iⁿ = −1 (n = 2 mod 4) applied last, exactly (a product by ±1).
    two_pi = 2 * np.pi
    pf, ph = two_pi * flat, two_pi * hertz
    order = np.asarray(nabs)
    zero = order == 0
    jn = np.array([jtab[n] for n in nabs])  # (n_o, ns)
    wn = np.zeros((order.size, s.size))
    if max(nabs) > 0:
        wn[:, cut] = wtab[order // 2]
    wn[zero] = flat  # W₀ is sinc(s) on the whole grid
    out = np.zeros((6, order.size, s.size))
    np.multiply(pf, jn, out=out[1])
    np.multiply(pf, wn, out=out[2])
    np.multiply(ph, jn, out=out[5])
    sign = np.where(order % 4 == 0, 1.0, -1.0)[:, None]  # iⁿ of the even orders n
    out[1:3] *= sign
    out[5] *= sign
    out[0, zero] = pf
    out[3, zero] = two_pi * flat**2
    out[4, zero] = ph
    return out


def far_limit(table: KernelTable) -> np.ndarray:
    """C₁ per far-field harmonic: the limit of (g − g∞)/w as w = (T₁/κ)² -> 0, Σ_k c_k T_k(−1)."""
    nf = table.far_coeffs.shape[1]
    return table.far_coeffs @ np.where(np.arange(nf) % 2 == 0, 1.0, -1.0)


def far_remainder(table: KernelTable, ka: np.ndarray, s_end: float) -> np.ndarray:
    """Leading asymptotics of the far field beyond the end S of the s grid, (na, 6).

    There g − g∞ -> w C₁(θ), w = (T₁ ka/s)², C₁ = Σ_k c_k T_k(−1). Averaged over their
    oscillation, the weights of the edge point tend to 2π iⁿ sinc(s) J_n(s) -> √π s^-3/2 and
    2π iⁿ (j₁(s)/s) J_n(s) -> −√π s^-5/2 for every even n, and sinc² -> 1/(2s²); the centre
    weight 2π sinc(s) leaves 2π cos(S)/S³ (by parts). What is left (the oscillating parts, the WA
    weight, whose r = 1 endpoint is softened by the average) is below (T₁ ka)² S^-3.5.
    Columns in the order F0, F1, FW, F2D, H0, H1.
    """
    c1 = far_limit(table)
    scale = (table.t1 * ka) ** 2
    out = np.zeros((ka.size, 6), dtype=complex)
    edge = np.sum(c1)  # Σ_m C₁_m: the direction φ = 0
    axis = np.sum(c1[table.far_harmonics == 0])
    out[:, 1] = scale * edge * math.sqrt(math.pi) * 0.4 * s_end**-2.5
    out[:, 5] = -scale * edge * math.sqrt(math.pi) * (2 / 7) * s_end**-3.5
    out[:, 3] = scale * axis * 2 * math.pi / 6 * s_end**-3
    out[:, 2] = out[:, 3]  # the axisymmetric WA weight is sinc², the others are ~1e-3 of it
    out[:, 0] = scale * axis * 2 * math.pi * math.cos(s_end) * s_end**-3
    return out


def tail_sine(beta: np.ndarray, s_end: float) -> np.ndarray:
    """∫_S^∞ s^-7/2 sin(β s + π/4) ds (β >= 0), the slow tail of the flat-punch weight.

    With u = β s it is β^{5/2} Im[e^{iπ/4} F_{7/2}(βS)], F_ν(x) = ∫_x^∞ u^-ν e^{iu} du, from the
    Fresnel integrals F_{1/2} and F_{ν+1} = (i F_ν + x^-ν e^{ix})/ν (integration by parts).
    """
    beta = np.asarray(beta, dtype=float)
    out = np.full(beta.shape, math.sin(math.pi / 4) * 0.4 * s_end**-2.5)
    pos = beta > 1e-9
    if np.any(pos):
        b = beta[pos]
        x = b * s_end
        fs, fc = special.fresnel(np.sqrt(2 * x / np.pi))
        f = math.sqrt(np.pi / 2) * ((1 - 2 * fc) + 1j * (1 - 2 * fs))  # F_{1/2}(x)
        e = np.exp(1j * x)
        for nu in (0.5, 1.5, 2.5):
            f = (1j * f + x**-nu * e) / nu
        out[pos] = b**2.5 * np.imag(np.exp(1j * np.pi / 4) * f)
    return out
