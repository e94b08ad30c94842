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
transforms on the far-field grid (:mod:`contactres.dynamic._farfield`), plus its closed-form tail;
the hand-over segment, where the table holds that series too, goes with it in real arithmetic
(its nodes as further rows of each Chebyshev term, :func:`_segment_rows`).
Those products are formed as H_a H_b = Σ S_ap S_bq j_p j_q from the products of the spherical
Bessel functions (fewer than the radial pairs), and beyond the hand-over of the largest k a
the Chebyshev terms are polynomials in w, integrated as moments shared by every k a
(:func:`_far_rows`).

The transforms of the λ-derivative functions are used in the dynamic remainder through their
expansion in the polynomial ones (Neumann series H^{(d)} = Σ_q A_q j_{``|n|+2q``}, with A_q from the
same closed-form integrals, orthogonality of the j_p), truncated at Q terms; the series converges
for ``|s|`` below about ``|n| + 2Q``, and the remainder's weight ~(k_s a/s)² makes the truncation
error fall like Q^{-3.5} × the small enrichment coefficients (measured in the tests against 2Q).

The phases are D M' D* with D = diag(i^{``|n|``}), and D B = B (only n = 0 carries force), so
Bᵀ M⁻¹ B = Bᵀ M'⁻¹ B: the solve needs no phases. The static matrix M0 (Hermitian, positive
definite up to the nearly dependent directions of the enriched basis, which carry no energy)
is scaled to a unit diagonal, diag(M0)^{-1/2} M0 diag(M0)^{-1/2}; when none of its eigenvalues is
below 1e-14 of the largest (every default basis: its condition number is ~3e5), M is solved
directly in that scaling. Otherwise (a doubled basis) the solve is done in the eigenbasis of
the static matrix without those directions, so that the dynamic matrix I + V'ᴴ ΔM V' is well
conditioned.

On a face that is a mirror plane of the crystal (cubic (001), isotropic) the kernel has no odd
angular harmonics (:func:`odd_free`): the functions of odd n then decouple from those of even
n, which carry the force, and only the latter are kept (:meth:`_Basis.even_part`).
On every face, reciprocity (h(θ + π) = h(θ)ᵀ) makes each kernel harmonic symmetric (even m) or
antisymmetric (odd m) in its two in-plane indices: the dynamic part integrates 3 or 1
components per harmonic instead of 4 (:func:`_by_parity`).

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

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ._farfield import FarGrid, far_basis, far_grid
from ._tangential_static import load_derivatives, radial_integrals
from ._tangential_table import KSA_MAX, TangentialTable, prepare_tangential
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
    ``|n|`` <= ``n_harmonics`` (the curve's, :func:`~.tangential_table.max_harmonics` of the
    same ksa_max; the radial terms below are measured with the harmonics converged).

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

    def even_part(self) -> _Basis:
        """The functions of even harmonic n (with their radial functions): those that carry
        force (n = 0) and, under a kernel without odd harmonics (:func:`odd_free`), all that
        couple to them: the others decouple exactly."""
        keep = self.n % 2 == 0
        live = self.rad_n % 2 == 0
        renumber = np.cumsum(live) - 1
        return _Basis(
            self.alpha[keep],
            self.n[keep],
            renumber[self.radial[keep]],
            self.rad_n[live],
            self.rad_p[live],
            self.rad_d[live],
            self.series[live],
            self.p_max,
            self.load[keep],
            self.form[np.ix_(keep, keep)],
            self.max_order,
            self.ginf0,
        )


# Odd kernel harmonics at most this fraction of the largest count as zero (odd_free): on a
# mirror-plane face they are round-off, ~1e-16 of it.
_ODD_TOL = 1e-13


def odd_free(table: TangentialTable) -> bool:
    """Whether the in-plane kernel of ``table`` has no odd angular harmonics (static part,
    near-field values and far-field coefficients alike). Ĝ(θ + π) = Ĝ(θ)ᵀ, so the odd
    harmonics are those of its antisymmetric part, which vanishes when the surface is a mirror
    plane of the crystal (cubic (001) and (011), isotropic) but not in general (cubic (111),
    AT-cut quartz: a few % of the symmetric part)."""
    order = np.arange(-table.max_order, table.max_order + 1)
    odd = order % 2 == 1
    far = table.far_coeffs.reshape(order.size, 4, -1)
    return all(
        np.max(np.abs(a[odd])) <= _ODD_TOL * np.max(np.abs(a))
        for a in (table.ginf0, table.near_values.swapaxes(0, 1), far)
    )


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
    # [d_a, d_b, p_a, p_b]: the static matrix's and (d_b = 0) the Neumann series' integrals.
    R = radial_integrals(max(p_max, int(rad_p.max())), nlog)
    series = np.zeros((len(rad), p_max + 1))
    poly = rad_d == 0
    series[np.flatnonzero(poly), rad_p[poly]] = 1.0
    enr = np.flatnonzero(~poly)
    pq = rad_n[enr][:, None] + 2 * np.arange(nq)[None, :]  # (n_enr, nq)
    # A_q = ∫ H^{(d)} j_{p_q} ds / ∫ j_{p_q}² ds (orthogonality of the j_p of one parity), the
    # numerator ∂^d_λ R(p, λ; p_q, 0) at λ = 0.
    deriv = R[rad_d[enr][:, None], 0, rad_p[enr][:, None], pq]  # (n_enr, nq)
    series[enr[:, None], pq] = 2 * (2 * pq + 1) / np.pi * deriv
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


# The largest block of far-field products j_p j_q formed at once (bytes): 1 MB. Small blocks
# keep memory bounded and are faster: a fresh array of many MB costs as much in page faults as
# the products in it (measured: the far-field integrals of Cu(123) in 7 ms instead of 14).
_FAR_BLOCK_BYTES = 2**20


def _shifted_chebyshev(nf: int) -> np.ndarray:
    """The coefficients of T_f(2w − 1) in powers of w, f < ``nf``: row f, column k the
    coefficient of w^k (the shifted Chebyshev polynomials, Abramowitz & Stegun 22.5.14).

    By the recurrence T*_{f+1} = 2(2w − 1) T*_f − T*_{f−1} on the coefficient rows: integers,
    exact in floating point, the same values as numpy's domain conversion of
    ``Chebyshev.basis(f, domain=[0, 1])`` (checked for ``nf`` <= 27) without its Python
    overhead (1.5 ms per call for ten terms).
    """
    out = np.zeros((nf, nf))
    out[0, 0] = 1.0
    if nf > 1:
        out[1, :2] = (-1.0, 2.0)
    for f in range(1, nf - 1):
        out[f + 1, 1:] = 4.0 * out[f, :-1]
        out[f + 1] -= 2.0 * out[f] + out[f - 1]
    return out


def _far_rows(table: TangentialTable, ka: np.ndarray, grid):
    """The far-field rows of a call, split where the kernel's w-polynomials take over.

    ∫ ds T_f(2w − 1) w (1 − χ(s/ka)) X(s), w = (T₁ ka/s)², for every (k a, Chebyshev term f) is
    needed for X = every product j_p j_q. Beyond S = 2T₁ max(ka) the hand-over χ is 0 for every
    k a of the call, and T_f(2w − 1) w = Σ_k A_fk w^k (k = 1..f + 1, the shifted Chebyshev
    polynomial's coefficients), w = λ v with λ = (T₁ ka/S)² <= 1/4 and v = (S/s)² <= 1: there
    the integral is Σ_k A_fk λ^k ∫ v^k X ds, nf moments of X over the grid instead of na nf
    rows. (The monomial form loses ~3 of the 16 digits in cancellation: the coefficients grow
    like 4^f, its terms are <= 4^f 4^{-k}.)

    Returns ``(low, cut, moments, mix)``: ``low`` (na nf, cut) the rows on the grid nodes below
    S, ``moments`` (nf, ns − cut) the weights v^k ds on the others, ``mix`` (na nf, nf) the
    A_fk λ^k that combine the moments.
    """
    top = 2 * table.t1 * float(np.max(ka))
    cut = int(np.searchsorted(grid.s, top))
    below = FarGrid(grid.s[:cut], grid.ds[:cut], grid.s_end)
    far = far_basis(table, ka, below).basis  # (na, cut, nf)
    na, nf = far.shape[0], far.shape[2]
    low = np.moveaxis(far, -1, 1).reshape(na * nf, cut)
    v = (top / grid.s[cut:]) ** 2
    k = np.arange(1, nf + 1)
    moments = v[None, :] ** k[:, None] * grid.ds[None, cut:]  # (nf, ns − cut)
    shifted = _shifted_chebyshev(nf)
    lam = (table.t1 * ka / top) ** 2
    mix = (shifted[None, :, :] * lam[:, None, None] ** k[None, None, :]).reshape(na * nf, nf)
    return low, cut, moments, mix


def _segment_rows(table: TangentialTable, ka: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The hand-over segment's nodes as rows of the far field's Chebyshev terms: s = k a κ
    (na, n_seg) at its real nodes κ in [T₁, 2T₁], and the weights k a dκ χ(κ) w T_f(2w − 1)
    (na, nf, n_seg), w = (T₁/κ)². The table's values there are the series
    (:func:`~._tangential_table.segment_from_series`), so the segment's integrals are the far
    field's coefficients times these rows' (real) integrals, as the far field's are."""
    nc = table.resolution.n_contour
    kappa = table.near_kappa[nc:].real
    w = (table.t1 / kappa) ** 2
    nf = table.far_coeffs.shape[1]
    weight = np.polynomial.chebyshev.chebvander(2 * w - 1, nf - 1).T * (
        w * table.near_weight[nc:].real
    )
    return ka[:, None] * kappa[None, :], ka[:, None, None] * weight[None]


def _far_gram(basis: _Basis, rows, grid, segment) -> np.ndarray:
    """∫ ds row(s) H_a(s) H_b(s) on the far grid for every row of ``rows`` (those of
    :func:`_far_rows`) and radial pair, plus the same sums over the hand-over segment's nodes
    of ``segment`` (:func:`_segment_rows`), (nrad, nrad, n_rows): the integrals of the products
    j_p j_q of the spherical Bessel functions, then H_a H_b = Σ S_ap S_bq j_p j_q (S =
    ``basis.series``, :func:`_to_radial`). There are fewer orders p than radial functions (30
    against 66 at ``|n|`` <= 8), so this forms a third of the products H_a H_b over the grid and
    multiplies a third as many by the rows."""
    low, cut, moments, mix = rows
    ns = grid.s.size
    # The orders some radial function uses (only the even ones in an even_part basis).
    live = np.flatnonzero(np.any(basis.series != 0, axis=0))
    jf = spherical_bessel(basis.p_max, grid.s)[live]  # (live orders, ns)
    nl = live.size
    gram = np.empty((low.shape[0], nl, nl))
    # By blocks of orders p, with every q >= p: the products of a doubled basis on a doubled
    # grid are 0.6 GB (issue 31: the convergence test once peaked at 6.6 GB).
    most = max(nl, _FAR_BLOCK_BYTES // (8 * ns))
    p0 = 0
    while p0 < nl:
        p1, count = p0, 0
        while p1 < nl and (p1 == p0 or count + nl - p1 <= most):
            count, p1 = count + nl - p1, p1 + 1
        prod = np.empty((count, ns))  # j_p j_q, p0 <= p < p1, q >= p
        at = 0
        for p in range(p0, p1):
            np.multiply(jf[p], jf[p:], out=prod[at : at + nl - p])
            at += nl - p
        part = low @ prod[:, :cut].T + mix @ (moments @ prod[:, cut:].T)
        at = 0
        for p in range(p0, p1):
            gram[:, p, p:] = part[:, at : at + nl - p]
            gram[:, p:, p] = part[:, at : at + nl - p]
            at += nl - p
        p0 = p1
    # The segment: per k a, its (nf, n_seg) rows against j_p j_q at its own nodes s = k a κ.
    s, weight = segment
    js = np.moveaxis(spherical_bessel(basis.p_max, s)[live], 0, 1)  # (na, nl, n_seg)
    part = (js[:, None, :, :] * weight[:, :, None, :]) @ np.swapaxes(js, 1, 2)[:, None]
    gram += part.reshape(gram.shape)
    return _to_radial(basis.series[:, live], np.moveaxis(gram, 0, -1))


def _to_radial(series: np.ndarray, gram: np.ndarray) -> np.ndarray:
    """Σ_pq S_ap S_bq G_pq (nrad, nrad, n) of ``gram`` G (nl, nl, n) on the orders and
    ``series`` S (nrad, nl): two products with S, each over every row at once (G's rows first,
    so that neither needs a transposed copy: a third of the time of S G Sᵀ per row and its
    transpose)."""
    nrad, nl, n = series.shape[0], series.shape[1], gram.shape[-1]
    half = series @ np.ascontiguousarray(gram).reshape(nl, nl * n)  # Σ_p S_ap G_pq
    return series @ half.reshape(nrad, nl, n)


def _layout(basis: _Basis) -> tuple[np.ndarray, int]:
    """The harmonics n of the basis (sorted) and the radial functions per harmonic, checking
    the order basis_of and even_part give: α, then n, then the radial functions of ``|n|``,
    numbered in the order of ``|n|``."""
    harmonics = np.unique(basis.n)
    per_n = basis.n.size // (2 * harmonics.size)
    magnitudes = np.unique(np.abs(harmonics))
    j = np.arange(per_n)
    alpha, n, radial = (
        np.repeat(np.arange(2), harmonics.size * per_n),
        np.tile(np.repeat(harmonics, per_n), 2),
        np.tile((np.searchsorted(magnitudes, np.abs(harmonics))[:, None] * per_n + j).ravel(), 2),
    )
    if not (
        np.array_equal(basis.alpha, alpha)
        and np.array_equal(basis.n, n)
        and np.array_equal(basis.radial, radial)
    ):
        raise RuntimeError("a basis not in the order of basis_of")
    return harmonics, per_n


def _by_parity(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The independent components of kernel harmonics ``g`` (..., 4: xx, xy, yx, yy) for even
    and odd m, ((..., 3), (..., 1)).

    h(θ + π) = h(θ)ᵀ (reciprocity, :mod:`~._tangential_table`) makes Ĝ_{αβ,m} =
    (−1)^m Ĝ_{βα,m}: symmetric for even m (xx, xy = yx, yy), antisymmetric for odd m (xx =
    yy = 0, yx = −xy). The table holds this to round-off (its FFT); the mean of the two
    off-diagonal entries keeps the part that is not round-off. A block of the Galerkin matrix
    then integrates 3 or 1 components per harmonic instead of 4 (half the near-field products
    of a basis without symmetry)."""
    even = np.stack((g[..., 0], 0.5 * (g[..., 1] + g[..., 2]), g[..., 3]), axis=-1)
    odd = 0.5 * (g[..., 1:2] - g[..., 2:3])
    return even, odd


# The 2x2 components (xx, xy, yx, yy) of a block from its independent ones (_by_parity): for
# even m the components taken and their signs, for odd m likewise (xx = yy = 0, yx = −xy).
_FULL = ((np.array([0, 1, 1, 2]), np.ones(4)), (np.zeros(4, dtype=int), np.array([0, 1, -1, 0])))


def _block_sizes(magnitudes: list[int], per_n: int) -> tuple[dict, dict, int]:
    """The harmonics m = ±``|n_a|`` ± ``|n_b|`` of every block (``|n_a|`` <= ``|n_b|``, indices
    into ``magnitudes``) and its offset in the packed entries (radial pair, m, α, β), and
    their total count."""
    ms, offset, total = {}, {}, 0
    for ia, n_a in enumerate(magnitudes):
        for ib in range(ia, len(magnitudes)):
            n_b = magnitudes[ib]
            ms[ia, ib] = sorted({n_a + n_b, n_a - n_b, n_b - n_a, -n_a - n_b})
            offset[ia, ib] = total
            total += per_n * per_n * len(ms[ia, ib]) * 4
    return ms, offset, total


def _placement(harmonics: np.ndarray, per_n: int, magnitudes: list[int], ms, offset):
    """Where each entry of the matrix (nb, nb) is in the packed entries of the blocks.

    Entry (α, n_r, j_r; β, n_c, j_c) is in the block of (``|n_r|``, ``|n_c|``) in increasing
    order, harmonic m = n_c − n_r, components (α, β), radial pair (j_r, j_c) in the same
    order as the magnitudes (the product H_a H_b is the same for both orders). Formed per pair
    of harmonics, then broadcast over the components and radial functions."""
    nn = harmonics.size
    order = int(max(magnitudes))
    # Per block (|n_a| <= |n_b|, indices into magnitudes): its offset, 4 × its count of m, and
    # the slot of each m.
    first = np.zeros((len(magnitudes),) * 2, dtype=np.intp)
    stride = np.zeros_like(first)
    slot = np.zeros((*first.shape, 4 * order + 1), dtype=np.intp)
    for (ia, ib), m_list in ms.items():
        first[ia, ib] = offset[ia, ib]
        stride[ia, ib] = 4 * len(m_list)
        slot[ia, ib, np.array(m_list) + 2 * order] = np.arange(len(m_list))
    mag = np.searchsorted(magnitudes, np.abs(harmonics))
    ia = np.minimum(mag[:, None], mag[None, :])
    ib = np.maximum(mag[:, None], mag[None, :])
    m = slot[ia, ib, harmonics[None, :] - harmonics[:, None] + 2 * order]
    base = first[ia, ib] + 4 * m  # (n_r, n_c)
    stride = stride[ia, ib]
    j = np.arange(per_n)
    swap = (mag[:, None] > mag[None, :])[:, None, :, None]  # (n_r, ., n_c, .)
    pair = np.where(
        swap,
        j[None, None, None, :] * per_n + j[None, :, None, None],
        j[None, :, None, None] * per_n + j[None, None, None, :],
    )
    where = base[:, None, :, None] + stride[:, None, :, None] * pair  # (n_r, j_r, n_c, j_c)
    comp = 2 * np.arange(2)[:, None] + np.arange(2)[None, :]  # 2α + β
    # (α, n_r j_r, β, n_c j_c)
    where = where.reshape(1, nn * per_n, 1, nn * per_n) + comp.reshape(2, 1, 2, 1)
    return where.reshape(2 * nn * per_n, 2 * nn * per_n)


def _dynamic_part(
    table: TangentialTable,
    basis: _Basis,
    ka: np.ndarray,
    grid,
    scale: np.ndarray | None = None,
) -> np.ndarray:
    """∫ ds (h − h∞)(s/ka) H_a H_b of every basis pair, (na, nb, nb), without the phase;
    ``grid`` is the far-field grid of the whole call (:func:`~.farfield.far_grid`). With
    ``scale`` (nb, real, the same for n and −n), entry (a, b) is multiplied by scale_a scale_b
    (block by block, before the entries are copied to every sign of n_a and n_b).

    An entry is the integral of the kernel harmonic m = n_b − n_a, component (α_a, β_b), against
    the product of two radial functions. They are computed by blocks of one (``|n_a|``,
    ``|n_b|``), ``|n_a|`` <= ``|n_b|``: every radial pair of the block with its harmonics
    m = ±``|n_a|`` ± ``|n_b|`` and the four components, each once, packed side by side; the
    matrix is then gathered from them in one step (every sign of n_a and n_b, and the pairs of
    (``|n_b|``, ``|n_a|``), transposed).

    The table's values past its contour nodes (the hand-over segment, ``near_values[n_contour:]``)
    are not read: that segment is integrated from the far field's series, which is what
    :func:`~contactres.dynamic._tangential_table.prepare_tangential` stores there
    (:func:`~contactres.dynamic._tangential_table.segment_from_series`, within its stated bound
    of the kernel). A table whose segment held other values would be integrated as if it held
    the series.
    """
    na = ka.size
    harmonics, per_n = _layout(basis)
    nn = harmonics.size
    # Near field: s = ka κ on the contour; the hand-over segment, where the table holds the
    # far field's series, goes with the far field (_far_gram).
    nk = table.resolution.n_contour
    s = ka[:, None] * table.near_kappa[None, :nk]  # (na, nk)
    jp = spherical_bessel(basis.p_max, s)  # (p, na, nk)
    h = np.tensordot(basis.series, jp, axes=(1, 0))  # (nrad, na, nk)
    wk = table.near_weight[None, :nk] * ka[:, None]
    nv = table.near_values[:nk].reshape(nk, -1, 4)  # (nk, nm, 4)
    # Real factors of complex products as complex numbers x + 0i, here and below (avg): numpy
    # would cast them through its iterator buffers, element by element of the broadcast, at
    # several times the cost of the products (which are the same, to the bit).
    hw = h * wk.astype(complex)[None, :, :]
    # Far field: Chebyshev series of each harmonic against the products on the far grid, one
    # product over the grid for every (k a, Chebyshev term).
    nf = table.far_coeffs.shape[1]
    # Real, radial pairs first: a block's (j_a, j_b, k a, f) is then a stack of matrices
    # (j_b, k a merged) that the real Chebyshev coefficients multiply without a copy.
    phi = _far_gram(basis, _far_rows(table, ka, grid), grid, _segment_rows(table, ka))
    nrad = basis.series.shape[0]
    phi = phi.reshape(nrad, nrad, na, nf)
    coef = table.far_coeffs.reshape(-1, 4, nf)  # (nm, 4, nf)
    # Beyond the grid: h − h∞ -> w C₁, H_a H_b -> (α_a α_b + β_a β_b)/(2 s²) on average.
    p = np.arange(basis.p_max + 1)
    amp_s = basis.series @ np.cos(p * np.pi / 2)
    amp_c = basis.series @ -np.sin(p * np.pi / 2)
    avg = (np.outer(amp_s, amp_s) + np.outer(amp_c, amp_c)).astype(complex)
    c1 = coef @ np.where(np.arange(nf) % 2 == 0, 1.0, -1.0)  # (nm, 4)
    # Each kernel quantity by the parity of m: (near values (nk, nm, c), far coefficients
    # (nm, c, nf), their tail sums (nm, c)) with c = 3 independent components for even m, 1 for
    # odd m (_by_parity); the four m of a block share the parity of |n_a| + |n_b|.
    near_e, near_o = _by_parity(nv)
    coef_e, coef_o = (np.moveaxis(g, -1, 1) for g in _by_parity(coef.swapaxes(1, 2)))
    c1_e, c1_o = _by_parity(c1)
    parity = ((near_e, coef_e, c1_e), (near_o, coef_o, c1_o))
    tail_scale = (table.t1 * ka) ** 2 / (6 * grid.s_end**3)
    magnitudes = np.unique(np.abs(harmonics)).tolist()
    index = {n: i for i, n in enumerate(harmonics.tolist())}  # harmonic -> its position
    # (α, |n|, radial function), as complex x + 0i (see hw above).
    by_mag = np.ones((2, len(magnitudes), per_n), dtype=complex)
    if scale is not None:
        by_mag = scale.reshape(2, nn, per_n)[:, [index[n] for n in magnitudes]].astype(complex)
    ms_of, offset, total = _block_sizes(magnitudes, per_n)
    packed = np.empty((na, total), dtype=complex)
    # Work arrays of the largest block, reused by every block: fresh arrays of ~1 MB per block
    # cost more in page faults than the products in them. Per radial pair and k a: the
    # products over the near nodes, the block's near and far parts (<= 4 m × 3 components
    # each) and its 2x2 components (<= 4 m × 4).
    pairs = per_n * per_n * na
    work = np.empty(pairs * (nk + 2 * 12 + 16), dtype=complex)
    prod = work[: pairs * nk].reshape(per_n, per_n, na, nk)
    spare = work[pairs * nk :]
    for (ia, ib), ms in ms_of.items():
        ra = slice(ia * per_n, (ia + 1) * per_n)
        rb = slice(ib * per_n, (ib + 1) * per_n)
        cols = np.array(ms) + table.max_order
        odd = (magnitudes[ia] + magnitudes[ib]) % 2
        near_p, coef_p, c1_p = parity[odd]
        nc = c1_p.shape[-1]
        width = len(ms) * nc
        # (j_a, j_b, k a, m, independent component)
        np.multiply(hw[ra, None], h[None, rb], out=prod)
        part = spare[: pairs * width].reshape(pairs, width)
        np.matmul(prod.reshape(pairs, nk), near_p[:, cols].reshape(nk, width), out=part)
        # The far field in real arithmetic, real and imaginary parts of the coefficients
        # side by side (a complex view of the result).
        real_coef = np.ascontiguousarray(coef_p[cols].reshape(width, nf).T).view(float)
        far = spare[pairs * width : 2 * pairs * width]
        far_real = far.view(float).reshape(per_n, per_n * na, 2 * width)
        np.matmul(phi[ra, rb].reshape(per_n, per_n * na, nf), real_coef, out=far_real)
        part += far.reshape(pairs, width)
        tail = tail_scale[:, None] * c1_p[cols].reshape(1, width)  # (na, m c)
        np.multiply(
            avg[ra, rb, None, None], tail[None, None], out=far.reshape(per_n, per_n, na, width)
        )
        part += far.reshape(pairs, width)
        # The 2x2 components, scaled, into the packed entries (k a, j_a, j_b, m, α, β).
        take, sign = _FULL[odd]
        factor = by_mag[:, ia, None, :, None] * by_mag[None, :, ib, None, :]  # (α, β, j_a, j_b)
        factor = factor.transpose(2, 3, 0, 1).reshape(per_n, per_n, 1, 1, 4) * sign
        size = per_n * per_n * len(ms) * 4
        dest = packed[:, offset[ia, ib] : offset[ia, ib] + size]
        dest = dest.reshape(na, per_n, per_n, len(ms), 4).transpose(1, 2, 0, 3, 4)
        full = spare[2 * pairs * width : 2 * pairs * width + pairs * len(ms) * 4]
        full = full.reshape(per_n, per_n, na, len(ms), 4)
        np.take(part.reshape(per_n, per_n, na, len(ms), nc), take, axis=-1, out=full)
        np.multiply(full, factor, out=dest)
    where = _placement(harmonics, per_n, magnitudes, ms_of, offset)
    return np.take(packed, where, axis=1)


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


def _keeps_every_direction(m0: np.ndarray) -> bool:
    """Whether the smallest eigenvalue of ``m0`` (Hermitian, unit diagonal) exceeds
    _EIG_CUTOFF times its largest: the test that the direct solve needs no eigenbasis.

    First without the eigenvalues: if the Cholesky factorisation of m0 − τI succeeds, with
    τ = c ‖m0‖_∞ >= c λ_max, then m0 − τI + ΔA is positive definite for a backward error
    ‖ΔA‖₂ <= n γ_{n+1} ‖m0 − τI‖₂/(1 − n γ_{n+1}) (N. J. Higham, *Accuracy and Stability of
    Numerical Algorithms*, 2nd ed., SIAM 2002, Thm 10.3, with ‖|Rᴴ||R|‖₂ <= n ‖Rᴴ R‖₂), so
    λ_min > (c − 2 n γ_{n+1}) λ_max; c = _EIG_CUTOFF + 8 n γ_{n+1} (a factor 4 more for the
    larger rounding constants of complex arithmetic, Higham §3.6) proves the test. A default
    basis (λ_min ~3e-6 λ_max, c ~4e-11 at n = 204) passes it at a fraction of the cost of the
    eigenvalues (a third of the instructions of the direct solve's setup went to them);
    otherwise the eigenvalues decide, as before.
    """
    n = m0.shape[0]
    unit = np.finfo(float).eps / 2
    gamma = (n + 1) * unit / (1 - (n + 1) * unit)
    tau = (_EIG_CUTOFF + 8 * n * gamma) * float(np.max(np.sum(np.abs(m0), axis=1)))
    try:
        np.linalg.cholesky(m0 - tau * np.eye(n))
        return True
    except np.linalg.LinAlgError:
        w = np.linalg.eigvalsh(m0)
        return bool(w[0] > _EIG_CUTOFF * w[-1])


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
        The basis; default :func:`tangential_size` of max(ksa) and the table's rtol, with the
        harmonics max(ksa) needs (``table.harmonics_for``: the table must be prepared with
        ``ksa_max`` >= max(ksa) when that exceeds 2).
    """
    ksa = np.asarray(ksa, dtype=float).ravel()
    top = float(np.max(ksa, initial=0.0))
    if not top <= KSA_MAX:
        raise ContactresInputError(
            f"k_s a = {top:.6g} is beyond the range where the dynamic tangential stiffness is "
            f"checked (k_s a <= {KSA_MAX:g}, k_s = ω√(ρ/C44)): check the frequency and the "
            "contact radius (units?)"
        )
    # The harmonic cut-off of this curve's largest k_s a (the same as the table's up to 2).
    size = size or tangential_size(top, table.rtol, table.harmonics_for(top))
    if 2 * size.n_harmonics > table.max_order:
        # A table prepared for fewer harmonics than this basis: a fault of the caller.
        raise RuntimeError("the basis needs more kernel harmonics than the table holds")
    out = np.empty((ksa.size, 2, 2), dtype=complex)
    b0 = basis_of(table, size)
    if odd_free(table):
        b0 = b0.even_part()
    # The static matrix without the phases (module docstring), Hermitian, scaled to a unit
    # diagonal; the loads in the same scaling.
    m0 = b0.static
    m0 = 0.5 * (m0 + m0.conj().T)
    d = 1.0 / np.sqrt(np.real(np.diagonal(m0)))
    m0 = d[:, None] * m0 * d[None, :]
    loads = d[:, None] * b0.load
    frame = None
    if _keeps_every_direction(m0):
        static = (loads.T @ np.linalg.solve(m0, loads)).real
    else:
        # Nearly dependent directions: the static eigenbasis without them.
        frame = eigen_frame(phase_of(b0.n) * b0.static, b0.load)
        static = frame.static
    f = 1 + 1j * table.loss
    k_static = 4 * np.pi**2 * table.c44 * 0.5 * (static + static.T)  # undamped, symmetric
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
            chunk = ka[lo : lo + _CHUNK]
            if frame is None:
                # Scaled by d as it is formed; the static part added in place (a fresh array
                # of this size costs as much in page faults as the arithmetic on it).
                dyn = _dynamic_part(table, b0, chunk, grid, d)
                dyn += m0 / f
                sol = np.linalg.solve(dyn, np.broadcast_to(loads, (chunk.size, *loads.shape)))
                res[lo : lo + _CHUNK] = loads.T @ sol
            else:
                dyn = film_dynamic(table, b0, chunk, grid)
                res[lo : lo + _CHUNK] = frame_solve(frame, table.loss, dyn)
        out[pos] = 4 * np.pi**2 * table.c44 * res
        if np.any(small):
            scale = (ksa[small] / KSA_SMALL)[:, None, None]
            out[small] = k_static * f + (out[small] - k_static * f) * scale
    return out
