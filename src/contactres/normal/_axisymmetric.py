"""Axisymmetric contact on a half-space whose surface compliance depends on the wave number.

A solid whose surface response is not self-similar (a coated substrate: the film near the surface,
the substrate below) has, after the average over the direction θ of the surface wave vector, the
radial compliance

    g(η) = η Ḡ(η),   Ḡ(η) = (1/2π) ∫₀^{2π} G(η, θ) dθ,   1/Pa,

with û(ξ) = G(``|ξ|``, θ) t̂(ξ) the surface displacement of a traction t on the disk (η = ``|ξ|``,
1/m; f̂(ξ) = ∫ f e^{−iξ·x} d²x). A homogeneous solid has a constant g (isotropic normal: 2/E*,
E* = E/(1 − ν²); tangential: (2 − ν)/(2G)). For an axisymmetric traction p(r) with Hankel transform
P(η) = ∫₀^∞ p(r) J₀(ηr) r dr the surface displacement is u(r) = ∫₀^∞ g(η) P(η) J₀(ηr) dη.
Anisotropic solids: the θ average is the axisymmetric approximation (exact for a solid that is
transversely isotropic about the normal; the same approximation as the circular-contact formulas
of :mod:`contactres.normal`, which use I₀ = 2π g on a non-circular face).

Galerkin on the disk r̄ = r/a <= 1. The traction is expanded in the functions f_k(r̄) whose Hankel
transforms are spherical Bessel functions, ∫₀¹ r̄ f_k(r̄) J₀(s r̄) dr̄ = j_{2k}(s) (those of
:mod:`contactres.dynamic._exact` with n = 0): f₀ = 1/√(1 − r̄²), each f_k = (1 − r̄²)^{-1/2} times a
polynomial of degree k in r̄², edge value f_k √(1 − r̄²) -> (−1)^k (Chu–Vandermonde), centre
value f_k(0) = √π k!/Γ(k + ½). With p = Σ c_k f_k the Galerkin equations are

    a³ Σ_k M_jk c_k = ∫₀^a f_j(r/a) u(r) r dr,   M_jk = ∫₀^∞ g(s/a) j_{2j}(s) j_{2k}(s) ds.

The matrix is split as g = g∞ + Δg, g∞ = lim_{η->∞} g (the top film's homogeneous value): the g∞
part is closed form, g∞ π/(2(4k + 1)) δ_jk (∫ j_p j_q ds, Weber–Schafheitlin), and the rest,
Δg -> 0 (like e^{−2ηh} for a film of thickness h), is integrated by Gauss–Legendre panels in η up
to where ``|Δg|`` < ``tol`` g∞ (:func:`graded_breakpoints`, :func:`quadrature_nodes`). Only the
first terms interact with Δg (j_{2k}(s) is negligible for s < 2k − O(k^{1/3})); the basis grows
like a/h, h the thinnest layer (:func:`basis_size`), so the cost grows like (a/h)² to (a/h)³
and a/h is limited to ~500.

Flat punch (uniform u = δ on the disk, only f₀ carries force, ∫₀¹ r̄ f_j dr̄ = δ_j0): K = F/δ =
2π a (M⁻¹)₀₀. Homogeneous: K = 4a/g = 2aE* (Sneddon).

Rigid sphere, radius R, given contact radius a: u = δ − r²/(2R) on the disk. With the moments
∫₀¹ r̄³ f_j dr̄ = m_j (m₀ = 2/3, m₁ = −4/15, then 0: the s² terms of j_{2k}) the solution is
c = M⁻¹(δ e₀/a − (a/2R) m); the pressure has no edge singularity (the frictionless contact
separates smoothly) when Σ (−1)^k c_k = 0, which fixes δ(a); then F = 2π a² c₀. For a frictionless
contact dF/dδ at fixed shape equals the flat-punch stiffness at the same a (the change of the
contact radius does no work at first order: the pressure vanishes at the edge). Homogeneous:
Hertz, δ = a²/R, F = 4E*a³/(3R), exactly (two terms).

Tangential punch (bonded, relaxed, a rigid motion U e_x; :mod:`contactres.normal._layered`
derives the kernels). The in-plane compliance has an isotropic part g(η) and a part d(η) along
Q = [[cos 2θ, sin 2θ], [sin 2θ, −cos 2θ]], which couples the traction along the motion, f(r) e_x,
to the pattern h(r) (cos 2φ, sin 2φ) (and only to it: Q² = I). With f = Σ c_k f_k (order-0
transforms j_{2k}) and h = Σ b_l h_l (order-2 transforms j_{2l+2}, the n = 2 functions of
:mod:`contactres.dynamic._exact`), the work ⟨t, u⟩ = 2π a³ ∫ [g (Σ c j_{2k})² + g (Σ b j_{2l+2})²
− 2 d (Σ c j_{2k})(Σ b j_{2l+2})] ds (the θ integrals of the cross terms), so the Galerkin matrix
has the blocks ∫ g j_{2k} j_{2k'}, ∫ g j_{2l+2} j_{2l'+2} and −∫ d j_{2k} j_{2l+2} (closed form for
g∞, d∞: f_{l+1} and h_l share the order 2l + 2), and K = 2π a (M⁻¹)₀₀ as for the normal punch.
Homogeneous: f₀ couples to nothing, K = 4a/g = 8Ga/(2 − ν) (Mindlin).

Accuracy (measured in tests/normal/test_axisymmetric.py): with ``tol`` = 1e-12 (the default) the
quadrature and the basis leave below 1e-9 relative in K, δ, F and p(0) for a/h from 0.01 to 30
(twice the basis and a hundredth of ``tol`` move them by less); a second algorithm (the
Fredholm equation of the second kind of Cooke and Lebedev–Ufliand, solved by Nyström) agrees to
1e-10 or better (measured ~1e-14) on g = A + B e^{−2ηh} with g(0)/g∞ from 0.05 to 50.

References: I. N. Sneddon, Int. J. Eng. Sci. 3, 47 (1965) (axisymmetric punches); H. Hertz (1882);
N. N. Lebedev and Ya. S. Ufliand, J. Appl. Math. Mech. 22, 442 (1958) and J. C. Cooke, Q. J. Mech.
Appl. Math. 16, 193 (1963) for the Fredholm form (used only in the tests).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import ContactresInputError
from ..numerics import gauss_legendre

__all__ = [
    "DEFAULT_TOL",
    "AxisymmetricSolution",
    "RadialKernel",
    "basis_size",
    "even_spherical_bessel",
    "graded_breakpoints",
    "punch_and_sphere",
    "quadrature_nodes",
]

# Default truncation of the Δg integral: panels are added until |Δg| < DEFAULT_TOL · |g∞|.
DEFAULT_TOL = 1e-12
# Gauss–Legendre nodes per panel. A panel is at most _WIDTH long in s = η a (two periods of the
# Bessel products' oscillation, e^{2is}) and at most a ratio _GRADING long in η (the kernel's own
# scale): 16 nodes integrate e^{2is} over 2π to ~1e-18 ((e ω/4n)^{2n}, ω = 2π, n = 16).
_GL_NODES = 16
_WIDTH = 2 * math.pi
_GRADING = 1.5
# The graded panels start at η = _ETA_START / (the kernel's largest length): below it Δg is flat.
_ETA_START = 1e-3
# Basis size: _BASIS_SLOPE a/h + _BASIS_MARGIN terms (h the thinnest length of the kernel).
# j_{2k}(s) reaches the Δg part only for 2k <~ η_cut a (η_cut h ≈ 14-30), but the pressure
# converges much faster than that bound: measured on Δg = B e^{−2ηh} (a/h = 3-30, tol 1e-12),
# 1.3 a/h + 10 terms already leave < 1e-11 in δ and F (K converges quadratically, to round-off).
_BASIS_SLOPE = 1.5
_BASIS_MARGIN = 12
_MAX_BASIS = 800


@dataclass(frozen=True)
class RadialKernel:
    """The θ-averaged radial compliance g(η) = η Ḡ(η) of a half-space (module docstring).

    Attributes
    ----------
    g_inf : float or complex
        lim_{η->∞} g(η), 1/Pa (real part > 0): the top material's homogeneous value (complex for
        a lossy solid, by the correspondence principle).
    excess : callable or None
        Δg(η) = g(η) − g∞ for an array of η (1/m), vectorised, 1/Pa, tending to 0 as η -> ∞;
        None for a homogeneous solid (Δg = 0).
    lengths : (float, float)
        The smallest and largest length of the solid (m; the thinnest layer and the total
        thickness): Δg varies on η ~ 1/lengths[1] and decays on η ~ 1/lengths[0].
    coupling_inf : float, complex or None
        Tangential problems only (module docstring, "Tangential punch"): d∞ = lim d(η), 1/Pa,
        of the Q part of the in-plane kernel, which couples the traction along the motion to
        the traction pattern (cos 2φ, sin 2φ). With it, ``excess`` returns the pair
        [Δg, Δd] stacked on a first axis of length 2. None: a normal problem (no coupling).
    """

    g_inf: float | complex
    excess: Callable[[np.ndarray], np.ndarray] | None = None
    lengths: tuple[float, float] = (1.0, 1.0)
    coupling_inf: float | complex | None = None


@dataclass(frozen=True)
class AxisymmetricSolution:
    """Flat punch and frictionless sphere at contact radii a (shapes of ``a``).

    Attributes
    ----------
    contact_radius : a, m
    punch_stiffness : K = F/δ of the rigid flat punch of radius a, N/m; also dF/dδ of the
        frictionless sphere contact of radius a
    depth_factor : δ R/a² of the sphere (1 for a homogeneous solid)
    force_factor : F R/a³ of the sphere, Pa (4E*/3 for a homogeneous solid)
    peak_factor : p(0) R/a of the sphere, Pa (2E*/π for a homogeneous solid)
    basis : the largest number of basis functions used
    nodes : the largest number of quadrature nodes in η used (one set per group of radii)
    """

    contact_radius: np.ndarray
    punch_stiffness: np.ndarray
    depth_factor: np.ndarray
    force_factor: np.ndarray
    peak_factor: np.ndarray
    basis: int
    nodes: int


def graded_breakpoints(kernel: RadialKernel, tol: float = DEFAULT_TOL) -> np.ndarray:
    """Breakpoints in η (1/m) of the kernel's own panels (independent of the contact radius):
    0, then geometric (ratio 1.5) from 1e-3 over the largest length up to two panels beyond the
    last breakpoint where ``|Δg|`` >= tol g∞."""
    if kernel.excess is None:  # a homogeneous solid: no panels of its own
        return np.zeros(1)
    h_min, h_max = kernel.lengths
    eta0 = _ETA_START / h_max
    # Geometric breakpoints up to where even the thinnest layer's e^{−2ηh} is below 1e-300.
    n_geo = math.ceil(math.log(400.0 / h_min / eta0) / math.log(_GRADING)) + 1
    geo = eta0 * _GRADING ** np.arange(n_geo)
    d = np.abs(np.asarray(kernel.excess(geo)))
    d = d.max(axis=0) if d.ndim == 2 else d  # [Δg, Δd] of a tangential kernel: the larger
    big = np.flatnonzero(d >= tol * abs(kernel.g_inf))
    # Two panels beyond the last breakpoint where Δg still matters (a margin for a wiggle).
    last = min(n_geo - 1, (int(big[-1]) if big.size else 0) + 2)
    return np.concatenate([[0.0], geo[: last + 1]])


def quadrature_nodes(cuts: np.ndarray, a_max: float) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights in η (1/m) for the Δg part of M at radii <= ``a_max``:
    the panels of ``cuts`` (:func:`graded_breakpoints`) cut to at most 2π/a_max long (two
    periods of the oscillation of j_p(ηa) j_q(ηa)), 16 nodes each."""
    width = _WIDTH / a_max
    pieces = [
        np.linspace(lo, hi, max(1, math.ceil((hi - lo) / width)) + 1)[:-1]
        for lo, hi in itertools.pairwise(cuts)
    ]
    edges = np.concatenate([*pieces, cuts[-1:]])
    # The package's one Gauss-Legendre rule, on every panel at once.
    eta, weight = gauss_legendre(edges[:-1, None], edges[1:, None], _GL_NODES)
    return eta.ravel(), weight.ravel()


def basis_size(kernel: RadialKernel, a: float) -> int:
    """Basis functions used at contact radius ``a`` (m): 1.5 a/h + 12, h the kernel's thinnest
    length (2 for a homogeneous kernel: Hertz is exact with two).

    Raises
    ------
    ContactresInputError
        Above 800 terms (a/h > ~525): the layer is too thin against the contact for this
        solver (the contact then sees the substrate under a thin film; the cost grows like
        (a/h)³).
    """
    if kernel.excess is None:
        return 2
    n = math.ceil(_BASIS_SLOPE * a / kernel.lengths[0]) + _BASIS_MARGIN
    if n > _MAX_BASIS:
        raise ContactresInputError(
            f"contact radius {a:.4g} m is {a / kernel.lengths[0]:.4g} times the thinnest layer: "
            f"above {(_MAX_BASIS - _BASIS_MARGIN) / _BASIS_SLOPE:.0f} the axisymmetric solver "
            f"would need more than {_MAX_BASIS} terms (treat such a thin film as absent)"
        )
    return n


def even_spherical_bessel(n: int, s: np.ndarray) -> np.ndarray:
    """j_{2k}(s) for k = 0..n−1 at finite real s, shape (n, s.size) (the basis transforms).

    The even orders are even functions of s: computed at ``|s|``. At s = 0 the limits j₀ = 1 and
    j_{2k} = 0 (k >= 1); a NaN gives NaN in its own column and leaves the others as they are
    without it. Above the highest order (s > 2n − 1) the upward recurrence j_{p+1} = (2p + 1)/s
    j_p − j_{p−1} is stable (no order is small there); below it the ratios j_p/j_{p−1} = s/(2p + 1
    − s j_{p+1}/j_p) are run down from zero at an order 30 above max(2n, 1.3 s) (the minimal
    solution: its truncation error falls like (s/2N)^{2(N − p)}), and anchored on j₀ = sin s/s or
    j₁ = (sin s/s − cos s)/s, whichever is larger (no zero costs digits). ~1e-15 absolute (and
    2e-15 relative at s <= 1e-5, where the higher orders fall to the underflow), checked in the
    tests against scipy's spherical_jn and the power series; one pass over the orders.
    """
    s = np.abs(np.asarray(s, dtype=float).ravel())
    p_max = max(2 * n - 2, 1)
    j = np.empty((p_max + 1, s.size))
    # j₀ and j₁; at s = 0 their limits 1 and 0 (the recurrence below then gives 0 above).
    j[0], j[1] = 1.0, 0.0
    nonzero = s != 0
    np.divide(np.sin(s), s, out=j[0], where=nonzero)
    np.divide(j[0] - np.cos(s), s, out=j[1], where=nonzero)
    up = s > p_max + 1
    n_up = int(np.count_nonzero(up))
    # Ascending s (the quadrature's nodes): the arguments above every order are the last ones,
    # worked on in place as slices of j; otherwise gathered and put back by the masks
    # (:func:`_on_columns`): the same operations, hence the same values, either way.
    first = s.size - n_up
    tail = bool(np.all(up[first:]))
    if n_up:
        _on_columns(j, slice(first, None) if tail else up, s, _upward)
    if n_up < s.size:
        _on_columns(j, slice(0, first) if tail else ~up, s, _downward)
    return j[0 : 2 * n : 2]


def _on_columns(
    j: np.ndarray,
    cols: slice | np.ndarray,
    s: np.ndarray,
    fill: Callable[[np.ndarray, np.ndarray], None],
) -> None:
    """``fill(block, s[cols])`` on the columns ``cols`` of ``j`` (rows 0 and 1 set): a slice is
    worked on in j's own memory, a mask on a gathered copy of its rows 0 and 1, put back."""
    if isinstance(cols, slice):
        fill(j[:, cols], s[cols])
        return
    blk = np.empty((j.shape[0], int(np.count_nonzero(cols))))
    blk[:2] = j[:2, cols]
    fill(blk, s[cols])
    j[:, cols] = blk


def _upward(blk: np.ndarray, s: np.ndarray) -> None:
    """Rows 2.. of ``blk`` from j₀ and j₁ in its rows 0 and 1 by the upward recurrence, at
    arguments ``s`` above every order. Every step writes into its row (no temporaries: ~1/3 of
    the cost at the coated table's ~90 orders x ~3000 nodes)."""
    for p in range(1, blk.shape[0] - 1):
        np.multiply((2 * p + 1) / s, blk[p], out=blk[p + 1])
        blk[p + 1] -= blk[p - 1]


def _downward(blk: np.ndarray, s: np.ndarray) -> None:
    """Rows 1.. of ``blk`` from j₀ and j₁ in its rows 0 and 1 by the ratios run down (in place,
    as :func:`_upward`), at arguments ``s`` at most one above the highest order."""
    p_max = blk.shape[0] - 1
    # The largest argument sets the start; fmax passes a NaN over (its column is NaN anyway, and
    # max would make it start too low for all the others). All NaN: s_max is NaN, and max,
    # which keeps its first argument unless a later one is larger, keeps p_max (tested).
    s_max = float(np.fmax.reduce(s))
    top = int(max(p_max, 1.3 * s_max)) + 30
    ratio = np.zeros(s.size)
    ratios = np.empty_like(blk)
    den = np.empty(s.size)
    for p in range(top, 0, -1):
        np.multiply(s, ratio, out=den)
        np.subtract(2 * p + 1, den, out=den)
        if p <= p_max:
            ratio = ratios[p]  # kept: the row p of the ratios
        np.divide(s, den, out=ratio)
    j0, j1 = blk[0], blk[1]
    blk[1] = np.where(np.abs(j0) >= np.abs(j1), j0 * ratios[1], j1)
    for p in range(2, p_max + 1):
        np.multiply(blk[p - 1], ratios[p], out=blk[p])


def _centre_values(n: int) -> np.ndarray:
    # Imported here: contactres.normal.sphere_contact imports this module also for a bare face,
    # which needs no scipy; only the coated solve reaches these values.
    from scipy import special

    k = np.arange(n)
    return math.sqrt(math.pi) * np.exp(special.gammaln(k + 1) - special.gammaln(k + 0.5))


def _transforms(store: dict | None, n: int, a: float, eta: np.ndarray) -> np.ndarray:
    """j_{2k}(ηa), k < n (:func:`even_spherical_bessel`), from ``store`` if it holds them for
    these n, a and η (another kernel on the same nodes), else computed (and kept there)."""
    if store is None:
        return even_spherical_bessel(n, a * eta)
    kept = store.get((n, a))
    if kept is not None and np.array_equal(kept[0], eta):
        return kept[1]
    jb = even_spherical_bessel(n, a * eta)
    store[(n, a)] = (eta, jb)
    return jb


def _solve_one(
    g_inf, a, eta, weight, dg, n: int, store: dict | None = None
) -> tuple[complex, complex, complex, complex]:
    """(K, δR/a², FR/a³, p(0)R/a) at one radius ``a`` with ``n`` basis functions (``store``:
    :func:`_transforms`)."""
    k = np.arange(n)
    # Dimensionless matrix M/g∞: diagonal (closed form) + a ∫ (Δg/g∞) j_{2j}(ηa) j_{2k}(ηa) dη.
    mat = np.diag(np.pi / (2 * (4 * k + 1))).astype(np.result_type(dg, float))
    if eta.size:
        jb = _transforms(store, n, a, eta)
        mat += (jb * (a * weight * dg / g_inf)) @ jb.T
    rhs = np.zeros((n, 2), dtype=mat.dtype)
    rhs[0, 0] = 1.0  # uniform displacement: ∫₀¹ r̄ f_j dr̄ = δ_j0
    rhs[0, 1] = 2 / 3  # the moments m_j = ∫₀¹ r̄³ f_j dr̄ of the sphere's r²
    if n > 1:
        rhs[1, 1] = -4 / 15
    sol = np.linalg.solve(mat, rhs) / g_inf  # A = M⁻¹e₀, B = M⁻¹m with M in 1/Pa
    A, B = sol[:, 0], sol[:, 1]
    edge = np.where(k % 2 == 0, 1.0, -1.0)  # f_k √(1 − r̄²) at the edge
    depth = 0.5 * (edge @ B) / (edge @ A)  # δ R/a²: no edge singularity
    c = depth * A - 0.5 * B  # the sphere's pressure coefficients times R/a
    return (2 * np.pi * a * A[0], depth, 2 * np.pi * c[0], _centre_values(n) @ c)


def _real_gram(left: np.ndarray, w: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Σ_i left_pi w_i right_qi for real ``left`` and ``right``: real products only (a complex
    ``w`` as its real and imaginary parts)."""
    if not np.iscomplexobj(w):
        return (left * w) @ right.T
    return (left * w.real) @ right.T + 1j * ((left * w.imag) @ right.T)


def _solve_tangential(
    kernel, a, eta, weight, dgd, n: int, store: dict | None = None
) -> tuple[complex, float, float, float]:
    """(K, nan, nan, nan): the tangential punch with the coupled traction (module docstring;
    ``store``: :func:`_transforms`)."""
    k = np.arange(n)
    g_inf, d_inf = kernel.g_inf, kernel.coupling_inf
    dtype = np.result_type(dgd, g_inf, d_inf, float)
    mat = np.zeros((2 * n, 2 * n), dtype=dtype)
    # Closed-form parts: ∫ j_p j_q ds = π/(2(2p + 1)) δ_pq (p − q even); f_k has p = 2k, the
    # pattern's g_l has p = 2l + 2, so f_{l+1} and g_l share an order.
    mat[:n, :n] = np.diag(np.pi / (2 * (4 * k + 1)))
    mat[n:, n:] = np.diag(np.pi / (2 * (4 * k + 5)))
    cross = np.zeros((n, n))
    cross[k[1:], k[:-1]] = np.pi / (2 * (4 * k[1:] + 1))
    mat[:n, n:] = -(d_inf / g_inf) * cross
    if eta.size:
        jb = _transforms(store, n + 1, a, eta)  # j_0, j_2, ..., j_{2n}
        jf, jg = jb[:n], jb[1:]
        wg = a * weight * dgd[0] / g_inf
        wd = a * weight * dgd[1] / g_inf
        # f_k and g_l run on j_0..j_2n with one order shifted: both g blocks are parts of one
        # Gram product of all n + 1 orders. A complex weight (a lossy film) as two real
        # products (the j_p are real): a third of the arithmetic of three complex products.
        gram = _real_gram(jb, wg, jb)
        mat[:n, :n] += gram[:n, :n]
        mat[n:, n:] += gram[1:, 1:]
        mat[:n, n:] -= _real_gram(jf, wd, jg)
    mat[n:, :n] = mat[:n, n:].T
    e0 = np.zeros(2 * n, dtype=dtype)
    e0[0] = 1.0
    A0 = np.linalg.solve(mat, e0)[0] / g_inf
    return (2 * np.pi * a * A0, np.nan, np.nan, np.nan)


def punch_and_sphere(
    kernel: RadialKernel,
    a,
    tol: float = DEFAULT_TOL,
    n_basis: int | None = None,
    nodes: dict | None = None,
    transforms: dict | None = None,
) -> AxisymmetricSolution:
    """Flat-punch stiffness and the frictionless sphere at contact radii ``a`` (module docstring).

    Parameters
    ----------
    kernel : RadialKernel
        The θ-averaged radial compliance.
    a : float or array
        Contact radii, m (> 0).
    tol : float
        Δg is integrated up to where ``|Δg|`` < tol g∞ (module docstring for the accuracy).
    n_basis : int, optional
        Fixed number of basis functions (the convergence tests); default from
        :func:`basis_size` at each radius.
    nodes : dict, optional
        The caller's store of quadrature nodes between calls on the same kernel and ``tol``
        (the force solve of a sphere calls this repeatedly): radii in (2^(b−1), 2^b] m share the
        nodes built for 2^b (:func:`quadrature_nodes`) and the kernel values there, kept under
        the key b, and the kernel's breakpoints under "cuts"; filled here.
    transforms : dict, optional
        The caller's store of the basis transforms j_{2k}(ηa) at the quadrature nodes, for
        calls on other kernels at the same radii (a table of several moduli, normal and
        tangential: their nodes coincide where their breakpoints do); used where the nodes
        are the same (compared), filled here: the same numbers as without it.

    Returns
    -------
    AxisymmetricSolution
        Shaped like ``a``. The sphere's δ, F and p(0) at radius R follow by scaling:
        δ = depth_factor a²/R, F = force_factor a³/R, p(0) = peak_factor a/R.
        ``punch_stiffness`` is complex for a lossy kernel (the others are then meaningless).
    """
    a = np.asarray(a, dtype=float)
    flat = a.ravel()
    if flat.size == 0 or not np.all(np.isfinite(flat) & (flat > 0)):
        raise ContactresInputError("contact radii must be finite and > 0 m")
    if n_basis is None:
        basis_size(kernel, float(flat.max()))  # a layer too thin for the solver: say so first
    store = {} if nodes is None else nodes
    out = np.empty((4, flat.size), dtype=complex)
    buckets = np.ceil(np.log2(flat)).astype(int)
    wanted = [int(b) for b in np.unique(buckets)]
    if kernel.excess is not None:
        # One kernel evaluation for the nodes of every new bucket (a layered kernel costs
        # ~10 ms per call whatever the number of points).
        if "cuts" not in store:
            store["cuts"] = graded_breakpoints(kernel, tol)
        new = [b for b in wanted if b not in store]
        if new:
            grids = [quadrature_nodes(store["cuts"], 2.0**b) for b in new]
            dg_all = np.asarray(kernel.excess(np.concatenate([g[0] for g in grids])))
            ends = np.cumsum([0] + [g[0].size for g in grids])
            for b, (eta, weight), lo, hi in zip(new, grids, ends[:-1], ends[1:], strict=True):
                store[b] = (eta, weight, dg_all[..., lo:hi])
    used_basis = used_nodes = 0
    coupled = kernel.coupling_inf is not None
    empty = (np.zeros(0), np.zeros(0), np.zeros((2, 0) if coupled else 0))
    for b in wanted:
        eta, weight, dg = empty if kernel.excess is None else store[b]
        for i in np.flatnonzero(buckets == b):
            n = basis_size(kernel, float(flat[i])) if n_basis is None else int(n_basis)
            ai = float(flat[i])
            if not coupled:
                out[:, i] = _solve_one(kernel.g_inf, ai, eta, weight, dg, n, transforms)
            else:
                out[:, i] = _solve_tangential(kernel, ai, eta, weight, dg, n, transforms)
            used_basis = max(used_basis, n)
        used_nodes = max(used_nodes, int(eta.size))
    shape = a.shape
    lossy = np.iscomplexobj(kernel.g_inf) or bool(np.any(out[0].imag != 0))
    k_out = out[0] if lossy else out[0].real
    return AxisymmetricSolution(
        contact_radius=a,
        punch_stiffness=k_out.reshape(shape),
        depth_factor=out[1].real.reshape(shape),
        force_factor=out[2].real.reshape(shape),
        peak_factor=out[3].real.reshape(shape),
        basis=used_basis,
        nodes=used_nodes,
    )
