"""Quadrature of the oscillating-pressure displacement N(r̄, φ) (paper 1, Eqs. 21-22).

The six linear functionals of N that the displacement conditions of paper 1 (Eqs. 24-28) need,
and N itself at given points, from a prepared kernel table (:mod:`contactres.dynamic._table`).

Numerical method (all exact rearrangements; the accuracy is set by the table's Resolution):

* s = κ·(k_s a) turns ∫ds g(s/ka) F(s) into ka ∫dκ g(κ) F(κ ka): one table of g per material
  serves every frequency and every model.
* The static part g∞(θ) is integrated in closed form: the flat-punch pressure displaces the contact
  uniformly, N_st = (π/2) ∫ g∞ dθ; the Hertz shape gives (π/4)(1 − r̄²/2) per unit ĝ₀ plus a
  second-harmonic term ∝ r̄² (Weber-Schafheitlin integrals). Only g − g∞ (~1/κ²) is integrated.
* Near field (the complex contour and the hand-over segment of the table): the θ integrals of
  the six functionals are sums over the angular harmonics ĝ_m of g − g∞ (Jacobi-Anger) with the
  weights J_2m(s) (the point values) and W_2m(s) (the WA line average), the same harmonics a
  trapezoidal rule in θ would resolve (:func:`near_theta_integrals`); at general points
  (:func:`point_values`) the θ integral is the trapezoidal rule (spectrally accurate for the
  smooth periodic integrand), with g upsampled by FFT so the rule also resolves cos(s r̄ cos θ).
* Far field: the Chebyshev series of the table against the analytic Bessel weights of each
  angular harmonic (:mod:`contactres.dynamic._farfield`).
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from ..errors import ContactresInputError
from ._farfield import (
    FarBasis,
    FarGrid,
    far_basis,
    far_limit,
    far_remainder,
    far_weights,
    tail_sine,
)
from ._fartail import FarTail, tail_coefficients
from ._table import COARSE_RTOL, KernelTable
from ._weights import (
    bessel_even,
    bessel_even_sum,
    by_real_columns,
    j1_over_s,
    sinc,
    wa_harmonic_sum,
)

__all__ = [
    "FUNCTIONALS",
    "far_operator",
    "far_operator_and_moments",
    "functionals",
    "near_theta_integrals",
    "point_values",
]


# ----------------------------------------------------------------------------------- functionals
def _resampled(values: np.ndarray, n_out: int) -> np.ndarray:
    """Rows sampled on n equispaced θ in [0, π), trigonometrically resampled to n_out points
    (harmonics ``|m|`` < min(n, n_out)/2 kept: the weights they multiply vanish beyond)."""
    n = values.shape[-1]
    if n_out == n:
        return values
    h = np.fft.fft(values, axis=-1)
    out = np.zeros((*values.shape[:-1], n_out), dtype=complex)
    half = min(n, n_out) // 2
    out[..., :half] = h[..., :half]
    out[..., n_out - half + 1 :] = h[..., n - half + 1 :]
    return np.fft.ifft(out, axis=-1) * (n_out / n)


def _n_theta_near(smax: float) -> int:
    """θ nodes on [0, π) that resolve cos(s cos θ), ``|s|`` <= smax: its harmonics e^{2imθ} are
    J_2m(s), negligible beyond ``2|m| ~ |s| + 12``."""
    return int(8 * math.ceil((1.1 * smax + 24) / 8))


def _static_values(table: KernelTable) -> dict:
    """Closed-form static parts (lossy g∞) of the six functionals (see module docstring)."""
    g0 = np.mean(table.ginf)
    g2 = 2 * np.mean(table.ginf * np.cos(2 * table.theta))  # ĝ₂ + ĝ₋₂
    flat = np.pi**2 * g0
    return {
        "F0": flat,
        "F1": flat,
        "FW": flat,
        "F2D": flat,
        "H0": 2 * np.pi * (np.pi / 4) * g0,
        "H1": 2 * np.pi * ((np.pi / 8) * g0 - (np.pi / 16) * g2),
    }


# How far above 1.3 max |s| (and 1.3 max |s/2|) the continued fractions of bessel_even_sum (and
# wa_harmonic_sum) start: 20 (and 10) orders, not their defaults 30 (and 20), which put the
# truncation near 1e-20, far below round-off. Measured against scipy's jv and the Fourier
# coefficients of the line weight (tests/dynamic/test_near_harmonics.py, arguments complex up to
# ~30 and real up to 60): the same error as with the defaults, ~5e-16 and ~5e-15 of Σ|c| (15 and
# 8 orders reach 3e-12 and 2e-13 at real arguments ~20); coefficients of orders at or above the
# start are dropped, each costing at most 3.7e-13 |c_m| (bessel_even_sum). Against the defaults
# the DCSF of every model kept every bit on 16 solids at rtol 1e-6 (k_l a <= 3, Q⁻¹ = 0 and
# 0.02; one 300-point interpolated curve moved by 4e-16); so it did at rtol 1e-4 until the coarse
# margins below took over there. 18 % fewer steps of these passes, ~2-3 % of the CPU of the
# five-model curve at rtol 1e-4, ~1.5 % of the seven-model one at 1e-6 (issue 31).
_EVEN_SUM_MARGIN = 20
_WA_SUM_MARGIN = 10
# A table prepared for rtol >= COARSE_RTOL (resolution_for's coarse grid): the sums not to
# round-off but to ~1e-7 of the coefficients: 10 and 5 orders (measured against the same
# references, arguments up to 21 and 60, smooth coefficients: <= 5e-10 and <= 9e-10 of Σ|c|; a
# single coefficient at the first dropped order costs up to max_{n >= start} |J_n(z)| ~ 2.3e-7
# of itself, bessel_even_sum; both well below that rtol; tests/dynamic/test_near_harmonics.py).
# The DCSF at rtol 1e-4 moved by <= 1.2e-10. 30 % fewer steps of these passes, whose cost is
# their number of steps (issue 31, lead 1).
_COARSE_MARGINS = (10, 5)


def _near_margins(table: KernelTable) -> tuple[int, int]:
    """The margins (even sum, WA sum) of the near field's continued fractions for ``table``:
    :data:`_COARSE_MARGINS` if it was prepared for rtol >= :data:`COARSE_RTOL` (the coarse
    grid of :func:`~contactres.dynamic._table.resolution_for`), the round-off ones otherwise
    (also for a table of an explicit Resolution, ``rtol`` None)."""
    if table.rtol is not None and table.rtol >= COARSE_RTOL:
        return _COARSE_MARGINS
    return _EVEN_SUM_MARGIN, _WA_SUM_MARGIN


def near_theta_integrals(table: KernelTable, s: np.ndarray, smax: float):
    """The θ integrals of the near field at s = k_s a κ (near nodes κ of ``table``).

    ∫₀^{2π} cos(s cos θ) (g − g∞) dθ = 2π Σ_m (−1)^m J_{``2|m|``}(s) ĝ_m and
    ∫₀^{2π} W(s cos θ) (g − g∞) dθ = 2π Σ_m (−1)^m W_{``2|m|``}(s) ĝ_m (Jacobi-Anger; W the WA line
    weight, W_n its harmonics), ĝ_m the harmonics e^{2imθ} of the tabulated g − g∞. The same
    harmonics ``|m|`` < min(n_θ, nt)/2 as the trapezoidal rule on the nt = :func:`_n_theta_near`
    nodes of θ (the weights of the others are negligible, J_{2m}(s) ~ (e s/4m)^{2m}), at a cost
    of O(harmonics) per (s, κ) instead of O(nt) evaluations of cos and W. The sums are
    accurate to round-off, or to ~1e-9 on a table prepared for rtol >= 1e-4
    (:func:`_near_margins`).

    Parameters
    ----------
    table : KernelTable
        The prepared kernel table.
    s : ndarray
        (na, nk) complex s = k_s a κ (nonzero).
    smax : float
        Bound of ``|s|`` of the whole call (sets the harmonics kept, the same for every chunk).

    Returns
    -------
    tuple of ndarray
        The cos and W integrals, (na, nk) complex, and ∫₀^{2π} (g − g∞) dθ, (nk,) complex.
    """
    n = table.theta.size
    keep = min(n, _n_theta_near(smax)) // 2 - 1  # highest |m| kept
    h = np.fft.fft(table.near_values, axis=1) / n  # (nk, n): ĝ_m at index m mod n
    m = np.arange(keep + 1)
    # The weights depend on |m| only: fold ĝ_m + ĝ_−m, with 2π (−1)^m.
    folded = h[:, m].T.copy()  # (keep + 1, nk)
    folded[1:] += h[:, n - m[1:]].T
    folded *= (2 * np.pi) * np.where(m % 2 == 0, 1.0, -1.0)[:, None]
    # Summed against the folded harmonics as the weights are made (no (keep, na, nk) arrays).
    even, wa = _near_margins(table)
    c1 = by_real_columns(partial(bessel_even_sum, margin=even), s, folded)
    cw = by_real_columns(partial(wa_harmonic_sum, margin=wa), s, folded)
    return c1, cw, 2 * np.pi * h[:, 0]


#: The six functionals of N the displacement models need, in the order of the far-field weights.
FUNCTIONALS = ("F0", "F1", "FW", "F2D", "H0", "H1")


def far_operator(table: KernelTable, grid: FarGrid) -> np.ndarray:
    """The far-field weights of the six functionals on ``grid``, contracted with the table's
    Chebyshev coefficients: (n_fit, ns, 12) real, [..., :6] the real and [..., 6:] the imaginary
    part of Σ_m c_{mf} weight_j[m, s] (built once per call, shared by its chunks)."""
    return _contracted(table, _far_weights_by_order(table, grid))


def far_operator_and_moments(
    table: KernelTable, grid: FarGrid, tail: FarTail
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`far_operator` on the head of ``grid`` (the nodes before ``tail``), (n_fit,
    tail.split, 12), and the moments of the rest over the tail, Σ_s T_j(2u − 1) ds × the
    operator at s, (n_fit, n_fit + 1, 12) (:mod:`contactres.dynamic._fartail`): the moments of
    the weights are taken first, so that the contraction with the coefficients runs over the
    head's nodes and the n_fit + 1 moments instead of the whole grid (~85 % of it the tail on a
    curve up to k_l a = 2; issue 31). The same sums as :func:`far_operator` followed by the
    moments, to round-off."""
    weights = _far_weights_by_order(table, grid)  # (6, n_o, ns)
    split = tail.split
    moments = weights[..., split:] @ tail.chebyshev  # (6, n_o, n_fit + 1)
    both = _contracted(table, np.concatenate([weights[..., :split], moments], axis=-1))
    return both[:, :split], both[:, split:]


def _far_weights_by_order(table: KernelTable, grid: FarGrid) -> np.ndarray:
    """:func:`~contactres.dynamic._farfield.far_weights` on ``grid`` for the distinct orders
    ``2|m|`` of the table's far harmonics (the weights of e^{±2imθ} are the same): (6, n_o, ns)."""
    return far_weights(table, grid.s, np.unique(2 * np.abs(table.far_harmonics)))


def _contracted(table: KernelTable, weights: np.ndarray) -> np.ndarray:
    """Σ_m c_{mf} weight_j[m, ...] of the weights by order (6, n_o, n), as (n_fit, n, 12) real:
    [..., :6] its real and [..., 6:] its imaginary part."""
    # The coefficients of ±m added first (half the weights to build and half the product).
    orders, which = np.unique(2 * np.abs(table.far_harmonics), return_inverse=True)
    fold = (which[:, None] == np.arange(orders.size)[None, :]).astype(float)  # (n_m, n_o)
    c = table.far_coeffs.T @ fold  # (nf, n_o) complex
    # Real products (the weights are real): [Re c @ w_j, Im c @ w_j] for the six functionals j.
    v = np.matmul(np.concatenate([c.real, c.imag])[None], weights)  # (6, 2 nf, n)
    nf = c.shape[0]
    return np.concatenate([v[:, :nf], v[:, nf:]]).transpose(1, 2, 0)  # (nf, n, 12)


def functionals(
    table: KernelTable,
    ksa: np.ndarray,
    far: FarBasis | None = None,
    *,
    smax: float | None = None,
    far_op: np.ndarray | None = None,
    tail: FarTail | None = None,
    far_moments: np.ndarray | None = None,
) -> dict:
    """N of the six functionals of the displacement at k_s a values ``ksa`` (paper 1, Eq. 22).

    F0 = N_F(0), F1 = N_F(1, 0), FW = weighted average of N_F along φ = 0 (Eq. 27), F2D = the
    weighted average over the whole contact, H0 = N_H(0), H1 = N_H(1, 0) (N_F: flat-punch
    pressure, Eq. 22; N_H: Hertz-shaped pressure, the second pressure of the TP model).

    Parameters
    ----------
    table : KernelTable
        The prepared kernel table of the material and loss.
    ksa : ndarray
        k_s a values (1-D, >= 0; dimensionless).
    far : FarBasis, optional
        The far-field basis of the positive ``ksa`` (from
        :func:`contactres.dynamic._farfield.far_basis`), when the caller shares it with other
        models of the same call; built here otherwise.
    smax : float, optional
        The largest k_s a of the whole call when ``ksa`` is one chunk of it (it sets the θ
        grid of the near field, so that every chunk uses the same); default max(ksa).
    far_op : ndarray, optional
        :func:`far_operator` on the grid of ``far`` (shared by the chunks of one call).
    tail : FarTail, optional
        With ``far_op``: the tail of its grid (:func:`contactres.dynamic._fartail.far_tail`),
        summed by its moments; ``far`` is then built on the head of the grid alone.
    far_moments : ndarray, optional
        With ``tail``: the moments of the operator over it, when ``far_op`` covers the head of
        the grid alone (both from :func:`far_operator_and_moments`); taken from the whole
        grid's ``far_op`` otherwise.

    Returns
    -------
    dict
        {name: complex ndarray shaped like ``ksa``} for the names of :data:`FUNCTIONALS`.
    """
    static = _static_values(table)
    out = {k: np.full(ksa.shape, v, dtype=complex) for k, v in static.items()}
    pos = ksa > 0
    if not np.any(pos):
        return out
    ka = ksa[pos]

    # Near field: the θ integrals by Jacobi-Anger in the harmonics of g (module docstring).
    s = ka[:, None] * table.near_kappa[None, :]  # (na, nk)
    top = float(np.max(ka)) if smax is None else float(smax)
    c1, cw, mean0 = near_theta_integrals(table, s, top * float(np.max(np.abs(table.near_kappa))))
    wk = table.near_weight[None, :] * ka[:, None]  # ka dκ χ
    flat = by_real_columns(sinc, s)  # the real segment in real arithmetic (round-off)
    hertz = by_real_columns(j1_over_s, s)
    wf, wh = wk * flat, wk * hertz  # each product once (the same bits as formed in each sum)
    near = [
        wf @ mean0,
        np.sum(wf * c1, axis=1),
        np.sum(wf * cw, axis=1),
        (wk * flat**2) @ mean0,
        wh @ mean0,
        np.sum(wh * c1, axis=1),
    ]

    # Far field: Chebyshev series in w = (T1 ka/s)² against the harmonic weights on the grid.
    if far is None:
        far = far_basis(table, ka)
    elif not np.array_equal(far.ka, ka):
        raise ContactresInputError("the far-field basis was built for other k a values")
    if far_op is None:
        far_op = far_operator(table, FarGrid(far.s, np.empty(0), far.s_end))
    # Σ_f Σ_s T_f(...)[a, s] v[f, s, j]: one batched product over f on the basis as stored,
    # (nf, na, ns) contiguous, then the sum over f. A product over (f, s) at once (tensordot)
    # first copies the whole basis into (na, nf, ns) order, which cost 4x the product itself
    # (1.9 against 0.4 ms at rtol 1e-6, 40 k a values; issue 31).
    head = far.basis.shape[1]
    parts = np.matmul(np.moveaxis(far.basis, -1, 0), far_op[:, :head]).sum(axis=0)  # (na, 12)
    if tail is not None:
        # The tail by its moments (contactres.dynamic._fartail): Σ_{f, j} coef[a, f, j] ×
        # Σ_s T_j(2u − 1) ds v[f, s, c].
        if head != tail.split:
            raise ValueError("the far-field basis was built on another grid")  # internal misuse
        moments = far_moments
        if moments is None:
            moments = np.matmul(tail.chebyshev.T, far_op[:, tail.split :])  # (nf, n_fit + 1, 12)
        coef = tail_coefficients(table, ka, tail)  # (na, nf, n_fit + 1)
        parts += coef.reshape(ka.size, -1) @ moments.reshape(-1, 12)
    elif head != far_op.shape[1]:
        raise ValueError("the far-field basis was built on another grid")  # internal misuse
    total = parts[:, :6] + 1j * parts[:, 6:]
    total += far_remainder(table, ka, far.s_end)
    for j, name in enumerate(FUNCTIONALS):
        out[name][pos] += near[j] + total[:, j]
    return out


def point_values(table: KernelTable, ksa: float, rbar: np.ndarray, phi: np.ndarray, shape: str):
    """N(r̄, φ) at one k_s a at the points (r̄, φ) of the contact (paper 1, Eq. 22).

    Parameters
    ----------
    table : KernelTable
        The prepared kernel table of the material and loss.
    ksa : float
        k_s a >= 0 (dimensionless).
    rbar, phi : ndarray
        Points r/a in [0, 1] and their polar angles from the surface x axis (rad), same size.
    shape : str
        "flat": the flat-punch pressure 1/√(1 − r̄²) (N_F); "hertz": √(1 − r̄²) (N_H, the second
        pressure of the TP model).

    Returns
    -------
    ndarray
        Complex N at the points (1-D).
    """
    rbar = np.asarray(rbar, dtype=float).ravel()
    phi = np.asarray(phi, dtype=float).ravel()
    shape_fn = sinc if shape == "flat" else j1_over_s
    # Static part (closed form).
    g0 = np.mean(table.ginf)
    if shape == "flat":
        out = np.full(rbar.shape, np.pi**2 * g0, dtype=complex)
    else:
        g2 = 2 * np.mean(table.ginf[None, :] * np.cos(2 * (table.theta[None, :] - phi[:, None])), 1)
        out = 2 * np.pi * ((np.pi / 4) * (1 - rbar**2 / 2) * g0 - (np.pi / 16) * rbar**2 * g2)
    if ksa <= 0:
        return out
    # Near field: θ-direct on the full period.
    s = ksa * table.near_kappa  # (nk,)
    nt = _n_theta_near(float(np.max(np.abs(s))))
    vals = _resampled(table.near_values, nt)  # (nk, nt)
    theta = np.pi * np.arange(nt) / nt
    arg = rbar[:, None] * np.cos(theta[None, :] - phi[:, None])  # (np, nt)
    cosw = np.cos(s[None, :, None] * arg[:, None, :])  # (np, nk, nt)
    inner = np.einsum("pkt,kt->pk", cosw, vals) * (2 * np.pi / nt)
    out += np.sum(inner * (table.near_weight * ksa * shape_fn(s))[None, :], axis=1)
    # Far field: harmonics with J_n(s r̄) weights; the grid and Chebyshev basis as in dcsf.
    far = far_basis(table, np.array([ksa]))
    sg, s_end = far.s, far.s_end
    basis = far.basis[0]  # (ns, nf)
    dhat = table.far_coeffs @ basis.T  # (n_m, ns): harmonic m of g − g∞ at s/ksa
    nabs = 2 * np.abs(table.far_harmonics)
    sign = np.where(nabs % 4 == 0, 1.0, -1.0)
    coef = 2 * np.pi * sign[:, None] * dhat * shape_fn(sg)[None, :]  # (n_m, ns)
    ph = np.exp(2j * np.outer(phi, table.far_harmonics))  # (np, n_m)
    orders = {int(n) for n in nabs}
    for lo in range(0, rbar.size, 16):
        r = rbar[lo : lo + 16]
        x = np.outer(r, sg)  # (nr, ns)
        jn = bessel_even(orders, np.where(x > 0, x, 1.0))
        for i, n in enumerate(nabs):
            j = np.where(x > 0, jn[int(n)], 1.0 if n == 0 else 0.0)
            out[lo : lo + 16] += ph[lo : lo + 16, i] * (j @ coef[i])
    if shape == "flat":
        # Slowly oscillating tail of sinc(s) J_n(s r̄) beyond the grid (see far_remainder).
        c1 = far_limit(table)
        edge = ph @ c1
        inside = rbar > 0
        r = np.where(inside, rbar, 1.0)
        tail = (table.t1 * ksa) ** 2 * np.pi * np.sqrt(2 / (np.pi * r)) * tail_sine(1 - r, s_end)
        centre = far_remainder(table, np.array([ksa]), s_end)[0, 0]  # F0's tail, r̄ = 0
        out += np.where(inside, edge * tail, centre)
    return out
