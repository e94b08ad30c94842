"""Exact small-oscillation stiffness of the contact: the rigid flat punch (Galerkin).

With the contact radius fixed and frictionless contact, the exact dynamic problem behind paper 1's
displacement conditions is the rigid flat punch on the lossy anisotropic half-space: the pressure
on the disk whose displacement is uniform (Luco & Westmann 1971 for the isotropic solid).

Galerkin (Rayleigh-Ritz) on the disk r̄ = r/a <= 1. The pressure is expanded as

    p(r̄, φ) = Σ_{n, k} c_{nk} f_{nk}(r̄) e^{inφ},
    f_{nk}(r̄) = √π Γ(|n|+k+1)/(Γ(k+½) |n|!) r̄^{|n|} ₂F₁(|n|+k+1, ½−k; |n|+1; r̄²)
              = r̄^{|n|} (1 − r̄²)^{-1/2} × (polynomial of degree k in r̄²),

whose order-|n| Hankel transforms are spherical Bessel functions, ∫₀¹ r̄ f_{nk} J_|n|(s r̄) dr̄ =
j_{|n|+2k}(s) (Weber-Schafheitlin): the flat punch f₀₀ = 1/√(1 − r̄²) has sin s/s. Only the angular
harmonics that the face couples to n = 0 enter (n ≡ 0 mod 4 on a 4-fold face, even n otherwise).
The Galerkin matrix of the displacement, in the normalisation of N (paper 1, Eq. 22),

    M_ab = (−1)^{(n_a+n_b)/2} ∫₀^∞ ds Ĝ_{n_a+n_b}(s/ka) j_{p_a}(s) j_{p_b}(s),
    Ĝ_m(κ) = ∫₀^{2π} g(κ, θ) e^{imθ} dθ,   p = |n| + 2k,

uses the same kernel table as the other models: its static part is closed form (∫ j_p j_q ds =
π/(2(2p+1)) δ_pq, so the static solution is the flat punch itself), the rest is the near-field
contour and the Chebyshev far field. Uniform displacement gives M c = e₀ (only f₀₀ carries force),
N_exact = 1/c₀ and DCSF = N_st/N_exact. With one term, N_exact = M₀₀ = N_WA2D: the whole-contact
weighted average is the one-term Galerkin (variational) estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special

from .farfield import FarBasis, far_basis
from .table import KernelTable

__all__ = ["GalerkinSize", "exact_n", "galerkin_size", "pressure_basis"]


@dataclass(frozen=True)
class GalerkinSize:
    """Number of radial terms per harmonic and of angular harmonics (|n| <= step × n_harmonics)."""

    n_radial: int
    n_harmonics: int

    def doubled(self) -> GalerkinSize:
        """Twice the radial terms and twice the harmonics (the convergence check of the tests)."""
        return GalerkinSize(2 * self.n_radial, 2 * self.n_harmonics)


def galerkin_size(ksa_max: float, rtol: float = 1e-6) -> GalerkinSize:
    """Default basis size reaching ``rtol`` up to k_s a = ksa_max (from the convergence tests:
    the radial series converges like a Neumann series in (k a/2p)², the angular one like the
    harmonics of g)."""
    extra = 0 if rtol < 1e-4 else -2
    return GalerkinSize(n_radial=max(2, math.ceil(0.6 * ksa_max) + 6 + extra), n_harmonics=3)


def _basis(table: KernelTable, size: GalerkinSize) -> list[tuple[int, int]]:
    step = 4 if table.fourfold else 2
    ns = [0] + [s * step * j for j in range(1, size.n_harmonics + 1) for s in (1, -1)]
    return [(n, k) for n in ns for k in range(size.n_radial)]


def pressure_basis(n: int, k: int, rbar) -> np.ndarray:
    """f_nk(r̄) of the module docstring (its order-|n| Hankel transform is j_{|n|+2k}(s))."""
    n = abs(int(n))
    r = np.asarray(rbar, dtype=float)
    norm = math.sqrt(math.pi) * math.exp(special.gammaln(n + k + 1) - special.gammaln(k + 0.5))
    norm /= math.factorial(n)
    with np.errstate(divide="ignore"):
        return norm * r**n * special.hyp2f1(n + k + 1, 0.5 - k, n + 1, r * r)


def _harmonics(values: np.ndarray, ms) -> dict:
    """Ĝ_m = ∫₀^{2π} g e^{imθ} dθ of rows sampled on [0, π) (period π; m even)."""
    n = values.shape[-1]
    h = np.fft.fft(values, axis=-1) / n  # a_j of e^{2ijθ}
    out = {}
    for m in ms:
        j = (-m // 2) % n
        out[m] = 2 * np.pi * h[..., j]
    return out


def exact_n(
    table: KernelTable,
    ksa: np.ndarray,
    size: GalerkinSize,
    return_coeffs: bool = False,
    far: FarBasis | None = None,
):
    """N_exact of the rigid flat punch at k_s a values ``ksa`` (module docstring).

    Parameters
    ----------
    table : KernelTable
        The prepared kernel table of the material and loss.
    ksa : ndarray
        k_s a values (1-D, >= 0; dimensionless).
    size : GalerkinSize
        Number of radial terms and angular harmonics of the pressure basis.
    return_coeffs : bool
        Also return the Galerkin coefficients c (per ksa) and the basis [(n, k), ...].
    far : FarBasis, optional
        The far-field basis of the positive ``ksa``, when the caller shares it with the other
        models of the same call; built here otherwise.

    Returns
    -------
    ndarray or tuple
        Complex N_exact shaped like ``ksa`` (DCSF = N_st/N_exact, paper 1, Eq. 29); with
        ``return_coeffs`` also c (ksa.shape + (n_basis,)) and the basis list.
    """
    basis = _basis(table, size)
    nb = len(basis)
    n_of = np.array([b[0] for b in basis])
    p_of = np.array([abs(b[0]) + 2 * b[1] for b in basis])
    orders = np.unique(p_of)
    pidx = {int(p): i for i, p in enumerate(orders)}
    ms = sorted({int(a + b) for a in set(n_of) for b in set(n_of)})
    sign = np.where(((n_of[:, None] + n_of[None, :]) // 2) % 2 == 0, 1.0, -1.0)

    # Static part: Ĝ_m^∞ δ_pq π/(2(2p + 1)).
    ginf_h = _harmonics(table.ginf, ms)
    out_n = np.empty(ksa.shape, dtype=complex)
    coeffs = np.empty((*ksa.shape, nb), dtype=complex)
    pos = ksa > 0
    ka = ksa[pos]
    na = ka.size
    I = {m: np.zeros((na, orders.size, orders.size), dtype=complex) for m in ms}  # noqa: E741
    if na:
        # Near field: contour + hand-over segment, harmonics of the tabulated g − g∞.
        near_h = _harmonics(table.near_values, ms)  # m -> (nk,)
        s = ka[:, None] * table.near_kappa[None, :]  # (na, nk)
        jp = np.stack([special.spherical_jn(int(p), s) for p in orders])  # (np, na, nk)
        wk = table.near_weight[None, :] * ka[:, None]
        for m in ms:
            I[m] += np.einsum("ak,pak,qak->apq", wk * near_h[m][None, :], jp, jp, optimize=True)
        # Far field: Chebyshev series in w = (T1 ka/s)² of each harmonic.
        if far is None:
            far = far_basis(table, ka)
        elif not np.array_equal(far.ka, ka):
            raise ValueError("the far-field basis was built for other k a values")
        sg, s_end, cheb = far.s, far.s_end, far.basis  # cheb: (na, ns, nf)
        nf = cheb.shape[2]
        js = np.stack([special.spherical_jn(int(p), sg) for p in orders])  # (np, ns)
        iu = np.triu_indices(orders.size)
        prod = js[iu[0]] * js[iu[1]]  # (npairs, ns)
        phi = np.einsum("asf,ts->aft", cheb, prod, optimize=True)  # (na, nf, npairs)
        harm = {int(j): i for i, j in enumerate(table.far_harmonics)}
        alt = np.where(np.arange(nf) % 2 == 0, 1.0, -1.0)
        diff = orders[iu[0]] - orders[iu[1]]
        tail_sign = np.where((diff // 2) % 2 == 0, 1.0, -1.0)
        for m in ms:
            j = -m // 2
            if j not in harm:
                continue
            c = 2 * np.pi * table.far_coeffs[harm[j]]  # (nf,)
            far = np.einsum("aft,f->at", phi, c)
            # Beyond the grid: j_p j_q -> (−1)^{(p−q)/2}/(2 s²) on average, g − g∞ -> w C₁.
            far += np.outer((table.t1 * ka) ** 2 * (c @ alt) / (6 * s_end**3), tail_sign)
            full = np.zeros((na, orders.size, orders.size), dtype=complex)
            full[:, iu[0], iu[1]] = far
            full[:, iu[1], iu[0]] = far
            I[m] += full
    diag = np.pi / (2 * (2 * orders + 1))
    for m in ms:
        I_st = ginf_h[m] * np.diag(diag)
        if na:
            I[m] = I[m] + I_st[None]
    # Assemble and solve M c = e0 for every ka.
    idx_p = np.array([pidx[int(p)] for p in p_of])
    M = np.empty((na, nb, nb), dtype=complex)
    for a in range(nb):
        for b in range(nb):
            M[:, a, b] = sign[a, b] * I[int(n_of[a] + n_of[b])][:, idx_p[a], idx_p[b]]
    e0 = np.zeros(nb)
    e0[0] = 1.0
    if na:
        c = np.linalg.solve(M, np.broadcast_to(e0, (na, nb))[..., None])[..., 0]
        out_n[pos] = 1 / c[:, 0]
        coeffs[pos] = c
    static = np.pi**2 * np.mean(table.ginf)
    out_n[~pos] = static
    coeffs[~pos] = e0 / static
    if return_coeffs:
        return out_n, coeffs, basis
    return out_n
