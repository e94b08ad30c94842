"""Exact small-oscillation stiffness of the contact: the rigid flat punch (Galerkin).

With the contact radius fixed and frictionless contact, the exact dynamic problem behind paper 1's
displacement conditions is the rigid flat punch on the lossy anisotropic half-space: the pressure
on the disk whose displacement is uniform (Luco & Westmann 1971 for the isotropic solid).

Galerkin (Rayleigh-Ritz) on the disk r̄ = r/a <= 1. The pressure is expanded as::

    p(r̄, φ) = Σ_{n, k} c_{nk} f_{nk}(r̄) e^{inφ},
    f_{nk}(r̄) = √π Γ(|n|+k+1)/(Γ(k+½) |n|!) r̄^{|n|} ₂F₁(|n|+k+1, ½−k; |n|+1; r̄²)
              = r̄^{|n|} (1 − r̄²)^{-1/2} × (polynomial of degree k in r̄²),

whose order-``|n|`` Hankel transforms are spherical Bessel functions,
∫₀¹ r̄ f_{nk} J_{``|n|``}(s r̄) dr̄ = j_{``|n|+2k``}(s) (Weber-Schafheitlin): the flat punch
f₀₀ = 1/√(1 − r̄²) has sin s/s. Only the angular harmonics that the face couples to n = 0
enter (n ≡ 0 mod 4 on a 4-fold face, even n otherwise).
The Galerkin matrix of the displacement, in the normalisation of N (paper 1, Eq. 22)::

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
from dataclasses import dataclass, replace

import numpy as np
from scipy import special

from ..errors import ContactresInputError
from ._farfield import FarBasis, far_basis, low_rank
from ._fartail import FarTail, tail_coefficients
from ._table import KernelTable
from ._weights import real_columns, spherical_bessel

__all__ = [
    "GalerkinPlan",
    "GalerkinSize",
    "exact_n",
    "galerkin_integrals",
    "galerkin_matrix",
    "galerkin_plan",
    "galerkin_size",
    "kernel_harmonics",
    "model_size",
    "near_bessel",
    "pressure_basis",
]


@dataclass(frozen=True)
class GalerkinSize:
    """Radial terms per harmonic and angular harmonics (``|n| <= step × n_harmonics``)."""

    n_radial: int
    n_harmonics: int

    def doubled(self) -> GalerkinSize:
        """Twice the radial terms and twice the harmonics (the convergence check of the tests)."""
        return GalerkinSize(2 * self.n_radial, 2 * self.n_harmonics)


def galerkin_size(
    ksa_max: float, rtol: float = 1e-6, *, pressure: bool = False, refine: int = 0
) -> GalerkinSize:
    """Default basis size reaching ``rtol`` up to k_s a = ksa_max (from the convergence tests:
    the radial series converges like a Neumann series in (k a/2p)², the angular one like the
    harmonics of g).

    N_exact is variational (its error is quadratic in that of the pressure). Measured against
    twice the terms and harmonics on the same table (k_l a <= 2, each basis also at the largest
    k_s a of its size, where 0.6 k_s a is an integer; A = 0.2-10, ν = −0.3-0.45 less the corner
    A < 0.25, ν > 0.44, and ν = −0.9 at A = 0.2, 1, 4, 10; Cu(001), (110), (111) and (123);
    Q⁻¹ = 0 and 0.02, the lossless solid the worse), ceil(0.6 k_s a) + 4 radial terms and
    harmonics ``|n|`` <= 3 × step (the default, 1e-8 < rtol < 1e-4) leave at most 1.1e-9 on
    (001) faces (A = 0.2, ν = 0.44, k_l a = 2), 3.9e-11 on Cu(111), and 6.5e-8 on Cu(123) and
    2.6e-7 on Cu(110), set by the harmonics. Two radial terms fewer (rtol >= 1e-4) leave at
    most 6.8e-6 (A = 10, ν = 0.416, three terms at k_s a = 5/3, k_l a = 2; below 1e-6 for
    A <= 5.5), 1.9e-6 on Cu(110) and 8.7e-8 on Cu(001) and Cu(111)
    (tests/dynamic/test_dynamic_exact.py). The harmonics must reach
    the face's first coupled one: a (111) face is six-fold, so with step 2 it couples n = ±6,
    and ``|n|`` <= 2 × step missed it (3e-4 off on Cu(111), found by review). rtol <= 1e-8 takes two
    terms and one harmonic more.
    ``pressure=True`` sizes the basis for the pressure field itself (:func:`contact_pressure
    <contactres.dynamic.contact_pressure>`), which converges only linearly:
    two radial terms and one harmonic more.
    ``refine`` = L > 0 adds 4 L radial terms and 3 L harmonics: the refined evaluations of the
    run-time convergence check (:mod:`contactres.dynamic._convergence`). Three, not two: the
    check must add a harmonic the face couples, and on a six-fold (111) face (step 2) those are
    the multiples of 6; with 2 L the first refinement went from ``|n|`` <= 6 to 10, coupled
    nothing new, agreed with the default to 1e-9 and passed a value 3.7e-5 off at k_l a = 5
    (issue 27). With 3 L every level adds one coupled harmonic on (001), (111) and the two-fold
    faces alike.
    """
    extra = 2 if rtol <= 1e-8 else (0 if rtol < 1e-4 else -2)
    extra += 4 * refine
    more = 2 if pressure else 0
    harmonics = (4 if rtol <= 1e-8 else 3) + 3 * refine
    return GalerkinSize(
        n_radial=max(2, math.ceil(0.6 * ksa_max) + 4 + extra + more), n_harmonics=harmonics
    )


def model_size(ksa_max: float, rtol: float = 1e-6, *, refine: int = 0) -> GalerkinSize:
    """The Galerkin basis of the exact model of the DCSF curves
    (:func:`~contactres.dynamic.dcsf_models`): that of :func:`galerkin_size` with one radial term
    fewer at rtol in (1e-8, 1e-4) on the ordinary evaluation (``refine`` = 0; the refined ones
    of the run-time check, ``refine`` > 0, keep :func:`galerkin_size`'s).

    N_exact is variational, so the basis of :func:`galerkin_size` at those rtol leaves far less
    than rtol. Measured against twice the terms and harmonics (k_l a up to 0.5, 1 and 2, A =
    0.2-10, ν = −0.3-0.45 less the corner A < 0.25, ν > 0.44, isotropic, Cu(111), Cu(123) and
    Cu(110), Q⁻¹ = 0 and 0.02; tests/dynamic/test_dynamic_exact.py), one radial term fewer
    leaves at most 3.7e-9 where the radial series sets the error (A = 4, ν = 0.45; <= 2.1e-10
    for ν <= 0.25 and on Cu(111)), and the 6.5e-8 and 2.6e-7 of Cu(123) and Cu(110), set by the
    harmonics, as they were. One term fewer is 2.7 % of the instructions of the seven-model
    curve (issue 31).
    :func:`galerkin_size` itself stays as it was: the layered punch starts its adaptive basis
    from it (:mod:`contactres.dynamic._layered_punch`).
    """
    size = galerkin_size(ksa_max, rtol, refine=refine)
    if refine == 0 and 1e-8 < rtol < 1e-4:
        return replace(size, n_radial=max(2, size.n_radial - 1))
    return size


def _basis(table: KernelTable, size: GalerkinSize) -> list[tuple[int, int]]:
    step = 4 if table.fourfold else 2
    ns = [0] + [s * step * j for j in range(1, size.n_harmonics + 1) for s in (1, -1)]
    return [(n, k) for n in ns for k in range(size.n_radial)]


def pressure_basis(n: int, k: int, rbar) -> np.ndarray:
    """f_nk(r̄) of the module docstring (its order-``|n|`` Hankel transform is j_{``|n|+2k``}(s))."""
    n = abs(int(n))
    r = np.asarray(rbar, dtype=float)
    norm = math.sqrt(math.pi) * math.exp(special.gammaln(n + k + 1) - special.gammaln(k + 0.5))
    norm /= math.factorial(n)
    with np.errstate(divide="ignore"):
        return norm * r**n * special.hyp2f1(n + k + 1, 0.5 - k, n + 1, r * r)


def kernel_harmonics(values: np.ndarray, ms) -> np.ndarray:
    """Ĝ_m = ∫₀^{2π} g e^{imθ} dθ of rows sampled on [0, π) (period π; m even), stacked as
    (len(ms), *values.shape[:-1])."""
    n = values.shape[-1]
    h = np.fft.fft(values, axis=-1) / n  # a_j of e^{2ijθ}
    j = (-np.asarray(ms, dtype=int) // 2) % n
    return 2 * np.pi * np.moveaxis(h[..., j], -1, 0)


@dataclass(frozen=True, eq=False)
class GalerkinPlan:
    """The index bookkeeping of one Galerkin basis, built once per call and shared by its chunks.

    Attributes
    ----------
    basis : [(n, k), ...] the pressure basis (angular order n, radial index k)
    orders : (n_p,) the distinct Hankel orders p = ``|n|`` + 2k
    pairs : (2, n_t) order indices (i <= j) of the products j_p j_q the matrix needs
    ms : (n_m,) the angular orders n_a + n_b of the kernel harmonics Ĝ_m
    m_index, t_index : (nb, nb) where M_ab reads its harmonic (into ``ms``) and its pair
    sign : (nb, nb) (−1)^{(n_a + n_b)/2}
    far_products : (n_t, n_s) j_p(s) j_q(s) on the far-field grid (None without a grid); with a
        ``far_tail``, on the nodes before it alone (n_s = its ``split``: the tail is read by
        moments)
    far_tail : the tail of the far-field grid (:mod:`contactres.dynamic._fartail`), summed by
        its moments (None: the whole grid is summed node by node)
    far_moments : (n_fit + 1, n_t) the tail's moments of the products j_p j_q (or None)
    mirror : the Galerkin system reduced by the mirror symmetry of the face (None: the face
        has none, or the plan was made without its table's values)
    """

    basis: list
    orders: np.ndarray
    pairs: np.ndarray
    ms: np.ndarray
    m_index: np.ndarray
    t_index: np.ndarray
    sign: np.ndarray
    far_products: np.ndarray | None
    far_tail: FarTail | None = None
    far_moments: np.ndarray | None = None
    mirror: MirrorPlan | None = None


@dataclass(frozen=True, eq=False)
class MirrorPlan:
    """The Galerkin system on a face with a mirror plane y -> −y (g(−θ) = g(θ), so that
    Ĝ_{−m} = Ĝ_m): M is then invariant under n -> −n, and so is the solution of M c = e₀,
    c_{−n,k} = c_{n,k}. The unknowns c_{n,k}, n >= 0, solve the reduced system
    Σ_{n' >= 0, k'} (M_{(n,k),(n',k')} + [n' > 0] M_{(n,k),(−n',k')}) c_{n',k'} = δ_{(n,k),(0,0)}
    (the rows n < 0 repeat those of −n): 28 unknowns instead of 49 at rtol 1e-6 on a cubic
    (001) face, and only the harmonics m >= 0 of the kernel (issue 31). The same N_exact as the
    full system to round-off.

    Attributes
    ----------
    ms : (n_h,) the harmonics ``|n_a ± n_b|`` >= 0 the reduced matrix reads
    m_index : (2, nr, nr) where its two terms read their harmonic (into ``ms``)
    t_index : (nr, nr) where both read their pair (into the plan's pairs)
    sign : (2, nr, nr) (−1)^{(n_a + n_b)/2} of each term, 0 for the second where n' = 0
    expand : (nb,) the reduced unknown of each basis function (n, k): that of (``|n|``, k)
    """

    ms: np.ndarray
    m_index: np.ndarray
    t_index: np.ndarray
    sign: np.ndarray
    expand: np.ndarray


def _mirror_plan(table: KernelTable, basis: list, t_index: np.ndarray) -> MirrorPlan | None:
    """The :class:`MirrorPlan` of ``basis`` when ``table`` has the mirror symmetry g(−θ) = g(θ)
    (its θ nodes πj/nθ: columns j and nθ − j equal, as the table builds them, to the bit);
    None otherwise."""
    v = table.near_values
    if not (
        np.array_equal(v[:, 1:], v[:, :0:-1]) and np.array_equal(table.ginf[1:], table.ginf[:0:-1])
    ):
        return None
    n_of = np.array([b[0] for b in basis])
    k_of = np.array([b[1] for b in basis])
    rows = np.flatnonzero(n_of >= 0)
    n, nt = n_of[rows], n_of[rows][None, :]
    plus, minus = n[:, None] + nt, np.abs(n[:, None] - nt)
    ms = np.unique(np.concatenate([plus.ravel(), minus.ravel()]))
    sign = np.where((plus // 2) % 2 == 0, 1.0, -1.0)
    where = {(int(a), int(b)): i for i, (a, b) in enumerate(zip(n, k_of[rows], strict=True))}
    return MirrorPlan(
        ms=ms,
        m_index=np.stack([np.searchsorted(ms, plus), np.searchsorted(ms, minus)]),
        t_index=t_index[np.ix_(rows, rows)],
        sign=np.stack([sign, np.where(nt > 0, sign, 0.0)]),
        expand=np.array([where[(abs(int(a)), int(b))] for a, b in zip(n_of, k_of, strict=True)]),
    )


# Elements (8 bytes each) of the products j_p j_q formed at once on the far-field grid: ~32 MB.
# All pairs at once on the finest grids of the run-time convergence check (1176 pairs x 102400
# nodes) made a 0.96 GB temporary, the largest allocation of the test suite (issue 31).
_PRODUCT_BLOCK = 1 << 22


def _far_products(js: np.ndarray, pairs: np.ndarray, tail: FarTail | None):
    """The products j_p j_q of the order ``pairs`` on the far-field grid (``js``: j_p of the
    plan's orders there, (n_p, n_s)) and, with its ``tail``, their moments on the tail: the
    (n_t, n_s) products without a tail, those of the head alone and the (n_fit + 1, n_t)
    moments with one (:func:`galerkin_integrals` reads no more). Formed a few pairs at a time,
    without the (n_t, n_s) temporary (issue 31): each pair's row and its moments depend on that
    pair alone, so the products are those of all pairs at once to the bit, and the moments to
    round-off (the BLAS product of a block may group its sums otherwise than that of all pairs:
    a few units in the last place)."""
    n_t, n_s = pairs.shape[1], js.shape[1]
    head = n_s if tail is None else tail.split
    products = np.empty((n_t, head))
    moments = None if tail is None else np.empty((tail.chebyshev.shape[1], n_t))
    step = max(1, _PRODUCT_BLOCK // max(n_s, 1))
    work = np.empty((min(step, n_t), n_s))
    for lo in range(0, n_t, step):
        block = work[: min(step, n_t - lo)]
        # Pair by pair into the work array: indexing js by the pairs copied both factors of
        # every pair first (two (pairs x nodes) gathers, the exact model's largest copies).
        for i, (p, q) in enumerate(pairs[:, lo : lo + step].T.tolist()):
            np.multiply(js[p], js[q], out=block[i])
        products[lo : lo + step] = block[:, :head]
        if moments is not None and tail is not None:
            moments[:, lo : lo + step] = tail.moments(block)
    return products, moments


def galerkin_plan(
    table: KernelTable, size: GalerkinSize, far_s=None, *, tail: FarTail | None = None
) -> GalerkinPlan:
    """The :class:`GalerkinPlan` of ``size`` on ``table``; with the far-field nodes ``far_s``
    (those of :func:`contactres.dynamic._farfield.far_grid`) also the Bessel products there,
    and with the tail of that grid (:func:`contactres.dynamic._fartail.far_tail`) also their
    moments on it, the products then on the nodes before it alone (:func:`galerkin_integrals`
    reads the tail by its moments)."""
    basis = _basis(table, size)
    n_of = np.array([b[0] for b in basis])
    p_of = np.array([abs(b[0]) + 2 * b[1] for b in basis])
    orders = np.unique(p_of)
    pidx = np.searchsorted(orders, p_of)
    ms = np.unique(n_of[:, None] + n_of[None, :])
    # Only the (p, q) pairs some matrix entry reads, upper triangle (the products are symmetric).
    lo = np.minimum(pidx[:, None], pidx[None, :])
    hi = np.maximum(pidx[:, None], pidx[None, :])
    key = lo * orders.size + hi
    used, t_index = np.unique(key, return_inverse=True)
    pairs = np.stack([used // orders.size, used % orders.size])
    products = moments = None
    if far_s is not None:
        js = spherical_bessel(int(orders[-1]), np.asarray(far_s, dtype=float))[orders]
        products, moments = _far_products(js, pairs, tail)
    t_index = t_index.reshape(len(basis), len(basis))
    return GalerkinPlan(
        basis=basis,
        orders=orders,
        pairs=pairs,
        ms=ms,
        m_index=np.searchsorted(ms, n_of[:, None] + n_of[None, :]),
        t_index=t_index,
        sign=np.where(((n_of[:, None] + n_of[None, :]) // 2) % 2 == 0, 1.0, -1.0),
        far_products=products,
        far_tail=tail if moments is not None else None,
        far_moments=moments,
        mirror=_mirror_plan(table, basis, t_index),
    )


def exact_n(
    table: KernelTable,
    ksa: np.ndarray,
    size: GalerkinSize,
    return_coeffs: bool = False,
    far: FarBasis | None = None,
    *,
    plan: GalerkinPlan | None = None,
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
    plan : GalerkinPlan, optional
        :func:`galerkin_plan` of ``size`` on the grid of ``far`` (shared by the chunks of one
        call); built here otherwise.

    Returns
    -------
    ndarray or tuple
        Complex N_exact shaped like ``ksa`` (DCSF = N_st/N_exact, paper 1, Eq. 29); with
        ``return_coeffs`` also c (ksa.shape + (n_basis,)) and the basis list.
    """
    pos = ksa > 0
    ka = ksa[pos]
    na = ka.size
    if na:
        if far is None:
            far = far_basis(table, ka)
        elif not np.array_equal(far.ka, ka):
            raise ContactresInputError("the far-field basis was built for other k a values")
    if plan is None:
        plan = galerkin_plan(table, size, far.s if na and far is not None else None)
    nb = len(plan.basis)
    out_n = np.empty(ksa.shape, dtype=complex)
    coeffs = np.empty((*ksa.shape, nb), dtype=complex)
    e0 = np.zeros(nb)
    e0[0] = 1.0
    if na:
        # far: built above for these k a; its grid is the plan's (the caller's contract)
        assert far is not None
        mirror = plan.mirror
        if mirror is None:
            M = galerkin_matrix(table, ka, plan, far)
        else:  # the reduced system of the mirror symmetry (MirrorPlan), expanded after
            half = galerkin_integrals(table, ka, replace(plan, ms=mirror.ms), far)
            # The signs ±1 and 0 by reading from [half, −half, 0] (exact, as the products
            # were; a broadcast real x complex product is buffered and cast, issue 31).
            n_h = mirror.ms.size
            signed = np.concatenate([half, -half, np.zeros_like(half[:, :1])], axis=1)
            at = np.where(mirror.sign > 0, mirror.m_index, mirror.m_index + n_h)
            at[mirror.sign == 0] = 2 * n_h
            # Both terms by one flat index each into the rows of ``signed`` (np.take: the
            # same gather as signed[:, at[i], t_index], without the two-array indexing).
            flat = signed.reshape(ka.size, -1)
            where = at * half.shape[-1] + mirror.t_index
            M = np.take(flat, where[0], axis=1)
            M += np.take(flat, where[1], axis=1)
        rhs = np.zeros(M.shape[-1])
        rhs[0] = 1.0
        c = np.linalg.solve(M, np.broadcast_to(rhs, M.shape[:-1])[..., None])[..., 0]
        if mirror is not None:
            c = c[:, mirror.expand]
        out_n[pos] = 1 / c[:, 0]
        coeffs[pos] = c
    static = np.pi**2 * np.mean(table.ginf)
    out_n[~pos] = static
    coeffs[~pos] = e0 / static
    if return_coeffs:
        return out_n, coeffs, plan.basis
    return out_n


def galerkin_matrix(
    table: KernelTable, ka: np.ndarray, plan: GalerkinPlan, far: FarBasis
) -> np.ndarray:
    """The Galerkin matrix M_ab of the module docstring at k_s a values ``ka``.

    Parameters
    ----------
    table : KernelTable
        The prepared kernel table of the material and loss.
    ka : ndarray
        k_s a values (1-D, > 0; dimensionless), those ``far`` was built for.
    plan : GalerkinPlan
        :func:`galerkin_plan` on the grid of ``far`` (with its far-field products).
    far : FarBasis
        The far-field basis of ``ka`` (:func:`contactres.dynamic.farfield.far_basis`).

    Returns
    -------
    ndarray, complex, shape (len(ka), n_basis, n_basis)
        M in the normalisation of N (dimensionless): M c = e₀ gives N_exact = 1/c₀.
    """
    # Assemble M_ab = sign_ab I[n_a + n_b][p_a, p_b].
    return plan.sign * galerkin_integrals(table, ka, plan, far)[:, plan.m_index, plan.t_index]


def near_bessel(table: KernelTable, ka: np.ndarray, p_max: int) -> np.ndarray:
    """j_p(s), p = 0..p_max, at the near-field nodes s = ka × ``table.near_kappa`` of the k_s a
    values ``ka``, shape (p_max + 1, len(ka), nk), complex: the ``near_j`` of
    :func:`galerkin_integrals`. The nodes of the real hand-over segment in real arithmetic
    (:func:`~contactres.dynamic._weights.real_columns`; the same values to round-off)."""
    s = ka[:, None] * table.near_kappa[None, :]
    split = real_columns(s)
    if split in (0, s.shape[-1]):
        return spherical_bessel(int(p_max), s)
    out = np.empty((int(p_max) + 1, *s.shape), dtype=complex)
    out[..., :split] = spherical_bessel(int(p_max), s[:, :split])
    out[..., split:] = spherical_bessel(int(p_max), np.ascontiguousarray(s[:, split:].real))
    return out


def galerkin_integrals(
    table: KernelTable, ka: np.ndarray, plan: GalerkinPlan, far: FarBasis, near_j=None
) -> np.ndarray:
    """I[a, m, t] = ∫₀^∞ ds Ĝ_m(s/k_s a) j_p(s) j_q(s) (dimensionless) at k_s a values ``ka``
    for the harmonics ``plan.ms`` and the order pairs t = (p, q) of ``plan.pairs``: the
    entries :func:`galerkin_matrix` assembles M from, shape (len(ka), n_m, n_t), complex.
    Each pair's column depends on that pair alone (and on ``plan.ms``), so a plan whose
    ``pairs`` and ``far_products`` are restricted to some pairs gives their columns only.
    Arguments as in :func:`galerkin_matrix`; ``near_j``, optional: j_p at the near nodes
    s = ka × ``table.near_kappa`` for p = 0 to at least the plan's highest order, shape
    (p_max + 1, len(ka), nk) (:func:`near_bessel`), for a caller that grows its basis and
    computes them once."""
    assert plan.far_products is not None
    na = ka.size
    orders, (ti, tj) = plan.orders, plan.pairs
    # I[a, m, t]: ∫ ds Ĝ_m(s/ka) j_p j_q for the harmonics m and pairs t = (p, q).
    # Static part: Ĝ_m^∞ δ_pq π/(2(2p + 1)).
    diag = np.where(ti == tj, np.pi / (2 * (2 * orders[ti] + 1)), 0.0)
    static = kernel_harmonics(table.ginf, plan.ms)[:, None] * diag[None, :]  # (n_m, n_t)
    # Near field: contour + hand-over segment, harmonics of the tabulated g − g∞.
    near_h = kernel_harmonics(table.near_values, plan.ms)  # (n_m, nk)
    if near_j is None:
        near_j = near_bessel(table, ka, int(orders[-1]))
    jp = _rows(near_j, orders)  # (n_p, na, nk)
    wk = table.near_weight[None, :] * ka[:, None]
    one = plan.ms.size == 1
    if one:
        # One harmonic (an axisymmetric kernel, as the layered punch's film, or any plan of
        # the harmonic n = 0 alone): it joins the weights, and the pairs' sums are Gram
        # products (_gram_pair_sums). A plan of several harmonics (dcsf's default sizes of the
        # homogeneous curve: 7) keeps the product per pair, bit for bit as before.
        wk = wk * near_h[0]
    # Order by order, not jp * wk[None]: numpy copies the operands of a broadcast product
    # into buffers, which cost 3x the product itself (issue 31).
    weighted = np.empty_like(jp, dtype=np.result_type(jp, wk))
    for i in range(orders.size):
        np.multiply(jp[i], wk, out=weighted[i])
    if one:
        near = _gram_pair_sums(weighted, jp, ti, tj)[..., None]  # (n_t, na, 1)
    else:
        near = _near_pair_sums(weighted, jp, ti, tj, near_h.T)  # (n_t, na, n_m)
    # The static part plus the near field, made in one pass (the same sums as a copy of the
    # static part and the near field added to it).
    integral = np.add(static[None], near.transpose(1, 2, 0))  # (na, n_m, n_t)
    # Far field: Chebyshev series in w = (T1 ka/s)² of each harmonic, against j_p j_q.
    nf = far.basis.shape[-1]
    harm = {int(j): i for i, j in enumerate(table.far_harmonics)}
    coef = np.zeros((plan.ms.size, nf), dtype=complex)
    for i, m in enumerate(plan.ms):
        if -int(m) // 2 in harm:
            coef[i] = 2 * np.pi * table.far_coeffs[harm[-int(m) // 2]]
    # The large product runs over the s grid for every row (direction, ka). The real
    # coefficient matrix [Re; Im] (2 n_m x nf) has rapidly falling singular values (the
    # series of all harmonics decay alike): only its directions above 1e-15 of the largest
    # can move the sum beyond round-off, so the basis is projected on those first (about
    # half of the nf rows).
    left, right = low_rank(np.concatenate([coef.real, coef.imag]))  # (2 n_m, k), (k, nf)
    k = right.shape[0]
    cheb = np.moveaxis(far.basis, -1, 0)  # (nf, na, ns), contiguous (see far_basis)
    # Beyond 2 T₁ k_s a (the plan's tail) the basis is a polynomial in w = (T₁ ka/s)²: summed
    # against the tail's moments, not node by node (contactres.dynamic._fartail). A basis
    # built on the head of the grid alone needs them.
    tail = plan.far_tail
    head = cheb.shape[-1] if tail is None else tail.split
    if cheb.shape[-1] not in (head, plan.far_products.shape[-1]):
        raise ValueError("the far-field basis was built on another grid")  # internal misuse
    proj = np.tensordot(right, cheb[..., :head], axes=(1, 0)).reshape(k * na, head)
    phi = (proj @ plan.far_products[:, :head].T).reshape(k, na, -1)
    if tail is not None and plan.far_moments is not None:
        coeffs = right @ tail_coefficients(table, ka, tail)  # (na, k, n_fit + 1)
        phi += np.swapaxes(coeffs @ plan.far_moments, 0, 1)  # (k, na, n_t)
    mixed = np.tensordot(left, phi, axes=(1, 0))  # (2 n_m, na, n_t)
    # Its real and imaginary parts added to those of the integral (a complex sum is the sums
    # of its parts: the same values as adding mixed[:n_m] + 1j mixed[n_m:], without forming it).
    integral.real += mixed[: plan.ms.size].transpose(1, 0, 2)
    integral.imag += mixed[plan.ms.size :].transpose(1, 0, 2)
    # Beyond the grid: j_p j_q -> (−1)^{(p−q)/2}/(2 s²) on average, g − g∞ -> w C₁.
    alt = np.where(np.arange(nf) % 2 == 0, 1.0, -1.0)
    tail_sign = np.where(((orders[ti] - orders[tj]) // 2) % 2 == 0, 1.0, -1.0)
    scale = (table.t1 * ka) ** 2 / (6 * far.s_end**3)
    integral += scale[:, None, None] * (coef @ alt)[None, :, None] * tail_sign[None, None, :]
    return integral


def _rows(a: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``a[index]`` of sorted row indices: a view when they are evenly spaced (the Hankel
    orders p = ``|n|`` + 2k of a basis are 0, 2, 4, ... or 0, 1, 2, ...), so that the rows are
    not copied (~0.8 MB of near-field Bessel functions per curve at rtol 1e-6); a copy
    otherwise. The same values either way."""
    if index.size > 1:
        step = int(index[1] - index[0])
        if step > 0 and np.array_equal(index, index[0] + step * np.arange(index.size)):
            return a[int(index[0]) : int(index[-1]) + 1 : step]
    return a[index]


def _near_pair_sums(
    left: np.ndarray, right: np.ndarray, ti: np.ndarray, tj: np.ndarray, h: np.ndarray
) -> np.ndarray:
    """Σ_k ``left[ti, :, k] * right[tj, :, k] * h[k, :]``, (n_t, na, n_m): the near-field sums
    of the pair products against the kernel harmonics, one first order at a time (``left``
    and ``right`` indexed (order, k a, node), as the Bessel functions come).

    The pairs of a plan come sorted by their first order, each first order with a run of
    second orders: per first order p, the products of its row of ``left`` with the run of
    ``right`` (run, na, nk) and their product with ``h``, one BLAS call each, straight into
    the result. The whole (n_t, na, nk) array of products is never made: it was the largest
    array of the exact model (4.7 MB at 40 k a values, rtol 1e-6; issue 31). The products
    of every first order go to one work array, in the order of the Bessel functions (a run
    of second orders is a contiguous block of ``right``, its products contiguous rows for
    the BLAS call, with no copy; one product per pair, since numpy buffers the operands of a
    broadcast product, at 3x the cost), and the sums go straight into the result: a fresh
    (na, run, nk) product and its reordered copy per first order made the heap's top grow
    and shrink, ~400 fresh pages of memory per curve. The same sums as the product of the
    whole array with ``h`` (to round-off: the BLAS call is split by first order).
    """
    n_p, na, nk = left.shape
    out = np.empty((ti.size, na, h.shape[-1]), dtype=np.result_type(left, right, h))
    order = np.argsort(ti, kind="stable")
    ti_s, tj_s = ti[order], tj[order]
    starts = np.searchsorted(ti_s, np.arange(n_p + 1))
    longest = int(np.max(np.diff(starts), initial=0))
    work = np.empty(longest * na * nk, dtype=np.result_type(left, right))
    for p in range(n_p):
        lo, hi = int(starts[p]), int(starts[p + 1])
        if hi == lo:
            continue
        q = tj_s[lo:hi]
        run = q[-1] - q[0] == hi - lo - 1 and bool(np.all(np.diff(q) == 1))
        cols = right[int(q[0]) : int(q[-1]) + 1] if run else right[q]
        prod = work[: (hi - lo) * na * nk].reshape(hi - lo, na, nk)
        for i in range(hi - lo):  # one product per pair: a broadcast one is buffered, 3x slower
            np.multiply(left[p], cols[i], out=prod[i])
        rows = prod.reshape(-1, nk)
        if np.array_equal(order[lo:hi], np.arange(lo, hi)):
            np.matmul(rows, h, out=out[lo:hi].reshape(-1, h.shape[-1]))
        else:
            out[order[lo:hi]] = (rows @ h).reshape(hi - lo, na, -1)
    return out


def _gram_pair_sums(
    left: np.ndarray, right: np.ndarray, ti: np.ndarray, tj: np.ndarray
) -> np.ndarray:
    """Σ_k ``left[ti, :, k] * right[tj, :, k]``, (n_t, na): the near-field sums of one
    harmonic (an axisymmetric kernel, as the layered punch's film, whose harmonic the caller
    has folded into ``left``) of the pair products, as :func:`_near_pair_sums` forms them for
    several: each k a's sums of every pair of orders are one Gram product (n_p, nk) x
    (nk, n_p), batched over the k a values: one numpy call (one zgemm per k a) instead of a
    product per pair and a matrix-vector call per first order. It forms every pair of orders,
    n_p², where ``ti``, ``tj`` ask for about half (one triangle) of a basis made at once, and
    for fewer where a grown basis asks for its new pairs only (~4x at 100 nm and 50 nm films:
    154 of 625, 341 of 1296; those curves are no slower, review R31e). The same sums to
    round-off (another order of the products and the additions: <= 1e-14 on the layered
    curves)."""
    gram = np.matmul(left.transpose(1, 0, 2), right.transpose(1, 2, 0))  # (na, n_p, n_p)
    return gram[:, ti, tj].T
