"""Exact dynamic tangential stiffness of a rigid disk on an anisotropic half-space (Galerkin).

The tangential counterpart of :mod:`contactres.dynamic._exact`. Relaxed contact: under the disk
r̄ = r/a <= 1 the normal traction is zero and the disk translates rigidly, u_α = U_α e^{iωt}
(α = x, y). The in-plane surface response of the half-space to a traction t_β,
û_α(ξ) = Ĝ_αβ(κ, θ)/``|ξ|`` t̂_β(ξ) with κ = ``|ξ|``/k_s (k_s = ω√(ρ/C44), C44 of the surface frame),
is the in-plane block of the surface compliance, Ĝ = −H(θ, 1/κ²)/C44
(:func:`contactres.halfspace.surface_compliance`); as κ -> ∞ it tends to the static kernel of
:mod:`contactres.dynamic._tangential_static`.

Galerkin on the disk, with the traction basis of the static solution (angular harmonics
e^{inφ}, ``|n|`` <= N_h, for each component; Jacobi radial functions whose order-``|n|`` Hankel
transforms are the spherical Bessel functions j_p(s), p = ``|n|`` + 2k, k < N_r; and the
λ-derivatives d = 1, 2 of the first N_e of them, the ln(1 − r̄²) and ln²(1 − r̄²) factors of the
oscillatory edge singularity that the odd imaginary part of the static kernel creates)::

    M_ab = i^{|n_a| − |n_b|} ∫₀^∞ ds Ĝ_{α_a β_b, n_b − n_a}(s/k_s a) H_a(s) H_b(s),
    Ĝ_{αβ, m}(κ) = ∫₀^{2π} Ĝ_αβ(κ, θ) e^{imθ} dθ,

and K = 4π² a Bᵀ M⁻¹ B (B: the force carried by each basis function; only n = 0, k = 0 and its
λ-derivatives carry force), as in the static module. Split Ĝ = Ĝ∞ + (Ĝ − Ĝ∞): the static part
is the closed form of the static module (Weber-Schafheitlin with its λ-derivatives), exact for
every basis function; only the dynamic remainder (~κ⁻²) is integrated, on the nodes of the
normal problem (:mod:`contactres.dynamic._table`): a complex contour above the branch points
and the Rayleigh pole (so loss -> 0⁺ is exact), the hand-over segment, and the far field as a
Chebyshev series in w = (T₁/κ)² per angular harmonic, integrated against products of the
transforms on the far-field grid (:mod:`contactres.dynamic._farfield`), plus its closed-form tail.

The transforms of the λ-derivative functions are used in the dynamic remainder through their
expansion in the polynomial ones (Neumann series H^{(d)} = Σ_q A_q j_{``|n|+2q``}, with A_q from the
same closed-form integrals, orthogonality of the j_p), truncated at Q terms; the series converges
for ``|s|`` below about ``|n| + 2Q``, and the remainder's weight ~(k_s a/s)² makes the truncation
error fall like Q^{-3.5} × the small enrichment coefficients (measured in the tests against 2Q).

The solve is done in the eigenbasis of the static matrix (Hermitian, positive definite up to
the nearly dependent directions of the enriched basis, which carry no energy and are dropped
below 1e-14 of the largest eigenvalue), so that the dynamic matrix I + V'ᴴ ΔM V' is well
conditioned.

Accuracy (rtol = 1e-6 default, k_s a <= 2; tests): against the independent isotropic reference
(tests/dynamic/tangential_isotropic_reference.py) and against every discretisation doubled.

References: R. D. Mindlin, J. Appl. Mech. 16, 259-268 (1949) (static); J. Tian, Am. J. Eng.
Appl. Sci. 3(1), 56-63 (2010) (paper 1: the kernel table and contour of the normal problem
reused here); J. E. Luco and R. A. Westmann, "Dynamic response of a rigid footing bonded to an
elastic half space", J. Appl. Mech. 39, 527-534 (1972) (the isotropic horizontal problem,
welded contact; not reproduced here, whose contact is relaxed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ._farfield import far_basis, far_grid
from ._tangential_static import CAUCHY_POINTS, CAUCHY_RADIUS, load_derivatives, radial_integrals
from ._tangential_table import TangentialTable, prepare_tangential
from ._weights import spherical_bessel

__all__ = [
    "KSA_MAX",
    "KSA_SMALL",
    "Frame",
    "TangentialSize",
    "TangentialTable",
    "basis_of",
    "eigen_frame",
    "film_dynamic",
    "frame_solve",
    "phase_of",
    "prepare_tangential",
    "tangential_per_a",
    "tangential_size",
]

# Eigenvalues of the scaled static matrix below this fraction of the largest are dropped.
_EIG_CUTOFF = 1e-14
# k a values evaluated together (memory ~1 MB per value at the default basis).
_CHUNK = 32
#: Largest k_s a accepted: the range of the convergence tests (at 5: 1.5e-8 from the radial
#: terms); beyond it the default basis is not checked.
KSA_MAX = 5.0
#: Below this k_s a the dynamic part is taken as linear in k_s a (see tangential_per_a).
KSA_SMALL = 1e-6


@dataclass(frozen=True)
class TangentialSize:
    """Galerkin basis: harmonics ``|n|`` <= n_harmonics, n_radial polynomial terms per harmonic,
    n_enriched of them with their λ-derivatives d = 1..n_log, and n_series terms of the
    Neumann series of the enriched transforms."""

    n_harmonics: int
    n_radial: int
    n_enriched: int = 2
    n_log: int = 2
    n_series: int = 24

    def doubled(self) -> TangentialSize:
        """Twice the harmonics, radial terms and series terms (convergence check)."""
        return TangentialSize(
            2 * self.n_harmonics,
            2 * self.n_radial,
            self.n_enriched,
            self.n_log,
            2 * self.n_series,
        )


def tangential_size(ksa_max: float, rtol: float = 1e-6, n_harmonics: int = 6) -> TangentialSize:
    """Default basis reaching ``rtol`` up to k_s a = ksa_max with traction harmonics
    ``|n|`` <= ``n_harmonics`` (the table's, :func:`~.tangential_table.max_harmonics`).

    Measured against ``|n|`` <= 16, 10 radial terms, ln and ln² enrichment and 32 series terms
    (AT-cut quartz, Cu(111), Cu(123), isotropic ν = 0.3; k_s a <= 5): ceil(0.6 k_s a) + 2
    radial terms leave < 3e-9 for k_s a <= 3 and 1.5e-8 at 5; the ln² terms move K by <= 1.2e-8
    (Cu(111), k_s a = 5), 12 series terms instead of 24 by <= 5.5e-10. rtol <= 1e-8 takes two
    radial terms more, the ln² terms and 16 series terms.
    """
    fine = rtol <= 1e-8
    return TangentialSize(
        n_harmonics=int(n_harmonics),
        n_radial=max(2, math.ceil(0.6 * ksa_max) + (4 if fine else 2)),
        n_log=2 if fine else 1,
        n_series=16 if fine else 12,
    )


@dataclass(frozen=True, eq=False)
class _Basis:
    """Index bookkeeping of one basis: per function its component, harmonic, radial id; per
    radial id its ``|n|``, k, d and its transform as coefficients on the orders p."""

    alpha: np.ndarray
    n: np.ndarray
    radial: np.ndarray
    rad_n: np.ndarray
    rad_p: np.ndarray
    rad_d: np.ndarray
    series: np.ndarray  # (n_rad, p_max + 1): H_r = Σ_p series[r, p] j_p
    p_max: int
    load: np.ndarray  # (nb, 2)
    form: np.ndarray  # (nb, nb) R of every pair (the static matrix of a unit kernel harmonic)
    max_order: int  # the kernel harmonics are held for m = −max_order..max_order
    ginf0: np.ndarray  # (2 max_order + 1, 2, 2) the undamped static harmonics

    def static_of(self, harmonics: np.ndarray) -> np.ndarray:
        """The static matrix (phases not included) of a kernel whose harmonics ``harmonics``
        ((2 max_order + 1, 2, 2), as the table's ginf) are independent of κ: Ĝ_{αβ, n_b − n_a}
        R(p_a, λ_a; p_b, λ_b) in closed form."""
        m = self.max_order + self.n[None, :] - self.n[:, None]
        return harmonics[m, self.alpha[:, None], self.alpha[None, :]] * self.form

    @property
    def static(self) -> np.ndarray:
        """The static matrix of the undamped kernel, in the normalisation of M."""
        return self.static_of(self.ginf0)


def _series_integrals(pa: np.ndarray, pb: np.ndarray, n_log: int) -> np.ndarray:
    """∂^d_λ R(p_a, λ; p_b, 0) at λ = 0, d = 0..n_log (R of
    :func:`contactres.dynamic._tangential_static.radial_integrals`, its second function at
    λ = 0), shape (n_log + 1, *broadcast(pa, pb).shape); Cauchy's formula in λ on the same
    circle as there."""
    nc, rho = CAUCHY_POINTS, CAUCHY_RADIUS
    z = rho * np.exp(2j * np.pi * np.arange(nc) / nc)
    pa = np.asarray(pa, dtype=float)[None]
    pb = np.asarray(pb, dtype=float)[None]
    lam = z.reshape((nc,) + (1,) * (pa.ndim - 1))
    L = 1 + lam
    ratio = np.exp(special.gammaln((pa + pb + 1) / 2) - special.loggamma((pa + pb + 3) / 2 + lam))
    values = (
        (np.pi / 2)
        * special.gamma(L)
        * 2.0 ** (-L)
        * ratio
        * special.rgamma((pb - pa) / 2 + 1)
        * special.rgamma((pa - pb) / 2 + 1 + lam)
    )
    d = np.arange(n_log + 1)
    w = np.exp(-2j * np.pi * np.outer(d, np.arange(nc)) / nc) / nc  # (n_log + 1, nc)
    coef = np.tensordot(w, values, axes=(1, 0))
    scale = special.factorial(d) / rho**d
    return (coef * scale.reshape((-1,) + (1,) * (coef.ndim - 1))).real


def basis_of(table: TangentialTable, size: TangentialSize) -> _Basis:
    """The Galerkin basis ``size`` on the harmonics of ``table`` (index bookkeeping, transforms
    as series of j_p, loads and the radial integrals of the static matrix)."""
    nh, nr, ne, nlog, nq = (
        size.n_harmonics,
        size.n_radial,
        size.n_enriched,
        size.n_log,
        max(size.n_series, size.n_radial),
    )
    # Radial functions per |n|: (k, d) polynomial d = 0 for k < nr, enriched d >= 1 for k < ne.
    kd = [(k, 0) for k in range(nr)] + [(k, d) for d in range(1, nlog + 1) for k in range(ne)]
    rad = [(na, k, d) for na in range(nh + 1) for k, d in kd]
    rad_n = np.array([r[0] for r in rad])
    rad_k = np.array([r[1] for r in rad])
    rad_d = np.array([r[2] for r in rad])
    rad_p = rad_n + 2 * rad_k
    p_max = nh + 2 * (nq - 1)
    R = radial_integrals(int(rad_p.max()), nlog)  # [d_a, d_b, p_a, p_b]
    series = np.zeros((len(rad), p_max + 1))
    poly = rad_d == 0
    series[np.flatnonzero(poly), rad_p[poly]] = 1.0
    enr = np.flatnonzero(~poly)
    pq = rad_n[enr][:, None] + 2 * np.arange(nq)[None, :]  # (n_enr, nq)
    # A_q = ∫ H^{(d)} j_{p_q} ds / ∫ j_{p_q}² ds (orthogonality of the j_p of one parity).
    deriv = _series_integrals(rad_p[enr][:, None], pq, nlog)  # (nlog + 1, n_enr, nq)
    series[enr[:, None], pq] = 2 * (2 * pq + 1) / np.pi * deriv[rad_d[enr], np.arange(enr.size)]
    # The basis: component α, harmonic n, radial id of (|n|, k, d).
    per_n = len(kd)
    alphas, harmonics, radials = [], [], []
    for a in range(2):
        for nn in range(-nh, nh + 1):
            for j in range(per_n):
                alphas.append(a)
                harmonics.append(nn)
                radials.append(abs(nn) * per_n + j)
    alpha, n, radial = np.array(alphas), np.array(harmonics), np.array(radials)
    form = R[
        rad_d[radial][:, None],
        rad_d[radial][None, :],
        rad_p[radial][:, None],
        rad_p[radial][None, :],
    ]
    loads = load_derivatives(nlog)
    load = np.zeros((n.size, 2))
    carry = (n == 0) & (rad_k[radial] == 0)
    load[carry, alpha[carry]] = loads[rad_d[radial][carry]]
    return _Basis(
        alpha,
        n,
        radial,
        rad_n,
        rad_p,
        rad_d,
        series,
        p_max,
        load,
        form,
        table.max_order,
        table.ginf0,
    )


def phase_of(n: np.ndarray) -> np.ndarray:
    """i^{(|n_a| − |n_b|) mod 4} of every pair of harmonics ``n``: the phases of the matrix."""
    return 1j ** ((np.abs(n)[:, None] - np.abs(n)[None, :]) % 4)


# The largest block of far-field products H_a H_b formed at once (bytes): 256 MB.
_FAR_BLOCK_BYTES = 2**28


def _dynamic_part(table: TangentialTable, basis: _Basis, ka: np.ndarray, grid) -> np.ndarray:
    """∫ ds (h − h∞)(s/ka) H_a H_b of every basis pair, (na, nb, nb), without the phase;
    ``grid`` is the far-field grid of the whole call (:func:`~.farfield.far_grid`)."""
    na = ka.size
    nrad = basis.series.shape[0]
    iu, ju = np.triu_indices(nrad)
    # Per distinct (radial pair, harmonic m): which entries read it.
    nb = basis.n.size
    pair_of = np.empty((nrad, nrad), dtype=int)
    pair_of[iu, ju] = np.arange(iu.size)
    pair_of[ju, iu] = np.arange(iu.size)
    ra, rb = basis.radial[:, None], basis.radial[None, :]
    entry_pair = np.broadcast_to(pair_of[ra, rb], (nb, nb))
    entry_m = basis.n[None, :] - basis.n[:, None] + table.max_order
    entry_c = 2 * basis.alpha[:, None] + basis.alpha[None, :]
    key = (entry_pair * (2 * table.max_order + 1) + entry_m).ravel()
    uniq, inverse = np.unique(key, return_inverse=True)
    u_pair, u_m = uniq // (2 * table.max_order + 1), uniq % (2 * table.max_order + 1)
    out = np.zeros((na, uniq.size, 4), dtype=complex)
    # Near field: s = ka κ on the contour and the hand-over segment.
    s = ka[:, None] * table.near_kappa[None, :]  # (na, nk)
    jp = spherical_bessel(basis.p_max, s)  # (p, na, nk)
    h = np.tensordot(basis.series, jp, axes=(1, 0))  # (nrad, na, nk)
    wk = table.near_weight[None, :] * ka[:, None]
    nv = table.near_values.reshape(table.near_kappa.size, -1, 4)  # (nk, nm, 4)
    hw = h * wk[None]
    nk = wk.shape[1]
    for m in np.unique(u_m):
        sel = np.flatnonzero(u_m == m)
        pr = u_pair[sel]
        prod = hw[iu[pr]] * h[ju[pr]]  # (n_sel, na, nk)
        part = (prod.reshape(-1, nk) @ nv[:, m]).reshape(sel.size, na, 4)
        out[:, sel] += part.transpose(1, 0, 2)
    # Far field: Chebyshev series of each harmonic against the products on the far grid.
    far = far_basis(table, ka, grid)  # basis (na, ns, nf)
    jf = spherical_bessel(basis.p_max, grid.s)  # (p, ns)
    hf = basis.series @ jf  # (nrad, ns)
    nf = far.basis.shape[-1]
    ns = grid.s.size
    # (na nf, ns) @ (ns, npairs): one product over the grid for every (k a, Chebyshev term),
    # by blocks of pairs: the products H_a H_b of a doubled basis on the far grid are 3 GB
    # (32,000 pairs x 13,000 points), and their gathering held two such arrays at once (issue
    # 31: the convergence test peaked at 6.6 GB). A basis whose products fit one block (every
    # default size) takes one product, as before, so its results are unchanged to the bit.
    far_rows = np.moveaxis(far.basis, -1, 1).reshape(na * nf, ns)
    phi = np.empty((na * nf, iu.size))
    step = max(1, _FAR_BLOCK_BYTES // (8 * ns))
    for i0 in range(0, iu.size, step):
        block = slice(i0, i0 + step)
        prod_f = hf[iu[block]] * hf[ju[block]]  # (pairs of the block, ns)
        phi[:, block] = far_rows @ prod_f.T
    phi = phi.reshape(na, nf, -1)
    coef = table.far_coeffs.reshape(-1, 4, nf)  # (nm, 4, nf)
    for m in np.unique(u_m):
        sel = np.flatnonzero(u_m == m)
        out[:, sel] += np.matmul(coef[m], phi[:, :, u_pair[sel]]).transpose(0, 2, 1)
    # Beyond the grid: h − h∞ -> w C₁, H_a H_b -> (α_a α_b + β_a β_b)/(2 s²) on average.
    p = np.arange(basis.p_max + 1)
    amp_s = basis.series @ np.cos(p * np.pi / 2)
    amp_c = basis.series @ -np.sin(p * np.pi / 2)
    avg = amp_s[iu] * amp_s[ju] + amp_c[iu] * amp_c[ju]  # (npairs,)
    c1 = coef @ np.where(np.arange(nf) % 2 == 0, 1.0, -1.0)  # (nm, 4)
    scale = (table.t1 * ka) ** 2 / (6 * grid.s_end**3)
    out += scale[:, None, None] * (avg[u_pair][:, None] * c1[u_m])[None]
    full = out[:, inverse, entry_c.ravel()]  # (na, nb*nb)
    return full.reshape(na, nb, nb)


@dataclass(frozen=True, eq=False)
class Frame:
    """Coordinates in which the dynamic matrix is well conditioned: T with Tᴴ M0 T = I (M0 the
    undamped static matrix, phases included, Hermitian; its nearly dependent directions, which
    carry no energy, dropped below 1e-14 of the largest eigenvalue) and the loads Tᴴ B."""

    T: np.ndarray  # (nb, n_keep)
    load: np.ndarray  # (n_keep, 2)

    @property
    def static(self) -> np.ndarray:
        """Bᵀ M0⁻¹ B (2x2, real): the undamped static K/(4π² a C44)."""
        return (self.load.conj().T @ self.load).real


def eigen_frame(m0: np.ndarray, load: np.ndarray) -> Frame:
    """The :class:`Frame` of the static matrix ``m0`` (nb, nb, phases included) and the loads
    ``load`` (nb, 2)."""
    m0 = 0.5 * (m0 + m0.conj().T)
    d = 1.0 / np.sqrt(np.real(np.diagonal(m0)))
    w, V = np.linalg.eigh(d[:, None] * m0 * d[None, :])
    keep = w > _EIG_CUTOFF * w[-1]
    T = d[:, None] * V[:, keep] / np.sqrt(w[keep])[None, :]
    return Frame(T, T.conj().T @ load)


def frame_solve(frame: Frame, loss: float, dynamic: np.ndarray) -> np.ndarray:
    """Bᵀ M⁻¹ B (n, 2, 2) of M = M0/(1 + iQ⁻¹) + ``dynamic`` ((n, nb, nb), phases included):
    the lossy static matrix plus the dynamic remainder, solved in the frame's coordinates."""
    Th = frame.T.conj().T
    A = np.eye(frame.T.shape[1]) / (1 + 1j * loss) + Th @ dynamic @ frame.T
    sol = np.linalg.solve(A, np.broadcast_to(frame.load, (A.shape[0], *frame.load.shape)))
    return frame.load.conj().T @ sol


def film_dynamic(table: TangentialTable, basis: _Basis, ka: np.ndarray, grid) -> np.ndarray:
    """The dynamic remainder of the table's half-space, phases included, (len(ka), nb, nb) at
    k_s a values ``ka`` (> 0); ``grid``: :func:`~.farfield.far_grid` of the whole call."""
    return phase_of(basis.n)[None] * _dynamic_part(table, basis, ka, grid)


# Galerkin matrices of a few dozen unknowns, their solves: one BLAS thread (contactres._threads)
@one_blas_thread()
def tangential_per_a(
    table: TangentialTable, ksa: np.ndarray, size: TangentialSize | None = None
) -> np.ndarray:
    """K/a (Pa, complex, (len(ksa), 2, 2)) at k_s a values ``ksa`` (1-D, >= 0).

    Parameters
    ----------
    table : TangentialTable
        From :func:`prepare_tangential`.
    ksa : ndarray
        k_s a values (dimensionless, >= 0).
    size : TangentialSize, optional
        The basis; default :func:`tangential_size` of max(ksa) and the table's rtol.
    """
    ksa = np.asarray(ksa, dtype=float).ravel()
    top = float(np.max(ksa, initial=0.0))
    if not top <= KSA_MAX:
        raise ContactresInputError(
            f"k_s a = {top:.6g} is beyond the range where the dynamic tangential stiffness is "
            f"checked (k_s a <= {KSA_MAX:g}, k_s = ω√(ρ/C44)): check the frequency and the "
            "contact radius (units?)"
        )
    size = size or tangential_size(top, table.rtol, table.n_harmonics)
    if 2 * size.n_harmonics > table.max_order:
        # A table prepared for fewer harmonics than this basis: a fault of the caller.
        raise RuntimeError("the basis needs more kernel harmonics than the table holds")
    out = np.empty((ksa.size, 2, 2), dtype=complex)
    # Static eigenbasis (undamped, Hermitian): well-conditioned coordinates for every k a.
    b0 = basis_of(table, size)
    frame = eigen_frame(phase_of(b0.n) * b0.static, b0.load)
    f = 1 + 1j * table.loss
    k_static = 4 * np.pi**2 * table.c44 * frame.static  # undamped, symmetric
    zero = ksa == 0
    out[zero] = k_static * f
    pos = ~zero
    # Below KSA_SMALL the far-field grid (which starts at s = T₁ k_s a, floored at 1e-8) would
    # miss the band that radiates: there K - K(0) is linear in k_s a to ~KSA_SMALL relative,
    # so it is scaled from its value at KSA_SMALL.
    small = pos & (ksa < KSA_SMALL)
    if np.any(pos):
        # Lossy static part: M0/(1 + iQ⁻¹); dynamic remainder in the same coordinates.
        ka = np.where(small, KSA_SMALL, ksa)[pos]
        grid = far_grid(table, float(np.min(ka)))
        res = np.empty((ka.size, 2, 2), dtype=complex)
        # Chunks of k a values: memory stays bounded (~30 MB) whatever the call's size.
        for lo in range(0, ka.size, _CHUNK):
            dyn = film_dynamic(table, b0, ka[lo : lo + _CHUNK], grid)
            res[lo : lo + _CHUNK] = frame_solve(frame, table.loss, dyn)
        out[pos] = 4 * np.pi**2 * table.c44 * res
        if np.any(small):
            scale = (ksa[small] / KSA_SMALL)[:, None, None]
            out[small] = k_static * f + (out[small] - k_static * f) * scale
    return out
