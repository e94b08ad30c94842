"""Static tangential stiffness of a rigid circular contact on an anisotropic half-space.

Relaxed contact (Johnson 1985, §7.2): under the disk r < a the normal traction is zero (the
normal displacement is free), the tangential tractions t_α (α = x, y) are unknown and the disk
translates rigidly, u_α = U_α (no rotation). The total tangential force is F_α = K_αβ U_β with
K the 2x2 tangential stiffness tensor, N/m. Isotropic: K = 8Ga/(2 − ν) I, carried by the traction
t ∝ (a² − r²)^(-1/2) (Mindlin 1949).

Kernel. With ``m`` in its surface frame (z = inward normal, :meth:`Material.rotated`), a traction
t_β applied to the surface (positive along +x, +y on the solid) gives û_α(ξ) = Ĝ_αβ(θ)/``|ξ|``
t̂_β(ξ), ξ = ``|ξ|`` (cos θ, sin θ), f̂(ξ) = ∫ f(x) e^{-iξ·x} d²x. Since t_i = −σ_i3 on the face z =
0, Ĝ = −H/C44 with H the dimensionless surface compliance at s = 0
(:func:`contactres.halfspace.surface_compliance`); the normal-normal entry is the
:func:`~contactres.halfspace.static_kernel` Ĝ(θ). Isotropic: Ĝ_αβ = (δ_αβ − ν n_α n_β)/G (Cerruti).
Ĝ_αβ(θ) is Hermitian (reciprocity) with Ĝ(θ + π) = conj Ĝ(θ) (a real field): its real part is
symmetric and π-periodic, its imaginary part antisymmetric and odd under θ -> θ + π. The imaginary
part vanishes when the surface is a mirror plane (cubic (001), (011)) but not in general (cubic
(111): ~4 % of the real part, AT-cut quartz similar).

Galerkin (Rayleigh-Ritz for tractions). Each component of the traction is expanded, on r̄ = r/a, in
angular harmonics e^{inφ} times radial functions whose order-``|n|`` Hankel transforms are √(π/2)
J_{p+½+λ}(s)/s^{½+λ}, p = ``|n|`` + 2k (Jacobi polynomials ``P_k^{(λ−½, |n|)}(1 − 2r̄²)`` times
r̄^{``|n|``} (1 − r̄²)^{λ−½}); at λ = 0 these are the flat-punch functions of
:mod:`contactres.dynamic._exact` (transform j_p(s)). The matrix of the displacement functional is::

    M_ab = i^{|n_a|−|n_b|} Ĝ_{αβ, n_b − n_a} R(p_a, λ_a; p_b, λ_b),
    Ĝ_{αβ, m} = ∫₀^{2π} Ĝ_αβ(θ) e^{imθ} dθ,
    R = (π/2) ∫₀^∞ J_{p_a+½+λ_a} J_{p_b+½+λ_b} s^{−1−λ_a−λ_b} ds       (Weber-Schafheitlin),

which at λ = 0 is π/(2(2p+1)) for p_a = p_b, 0 for even p_a − p_b ≠ 0 and
(−1)^{(p_a−p_b−1)/2}/((p_a − p_b)(p_a + p_b + 1)) for odd p_a − p_b. With the real (even)
part of Ĝ only, the n = 0, k = 0 pair decouples and Mindlin's traction is exact for any
anisotropy (as the flat punch is for the normal problem); the odd imaginary part couples it to
all the others. The edge singularity is then r̄-oscillatory, (1 − r̄)^{-1/2 ± iε(φ)} with a small
ε varying round the edge (as at an interface crack), and polynomials converge only like N⁻² in
K. The basis is therefore enriched with the λ-derivatives (d = 1, 2) of the functions at λ = 0,
i.e. the factors ln(1 − r̄²) and ln²(1 − r̄²): the expansion of (1 − r̄²)^{±iε} to O(ε²). K then
converges to round-off with a few radial terms per harmonic (AT-cut quartz: 1e-14 with 2-4).
The λ-derivatives of R are taken from the closed form, a product of Γ factors of one variable
each, by Cauchy's formula (trapezoidal rule on a circle, spectrally accurate). The harmonics
Ĝ_m come from the FFT of Ĝ(θ) on an equispaced θ grid, doubled until they converge
(exponentially: Ĝ is analytic and periodic).

Only n = 0, k = 0 carries force. With the load vector b_a = H_a(0) (δ_{n_a 0} δ_{k_a 0}), the
Galerkin equations a³ M c = 2π a² b U give F = 4π² a (bᴴ M⁻¹ b) U, so K = 4π² a Re(bᴴ M⁻¹ b).
One term (Mindlin's traction shape, the analogue of Vlassak & Nix's indentation modulus for the
normal problem): K₁ = 8π a [∫₀^{2π} Re Ĝ(θ) dθ]⁻¹. Variational bound: the exact traction
minimises ½⟨t, Ĝt⟩ − U·F (complementary energy), so every Galerkin subspace overestimates the
compliance: K₁ <= K_N <= K (in the sense of quadratic forms), K_N growing with the basis.

References: R. D. Mindlin, "Compliance of elastic bodies in contact", J. Appl. Mech. 16,
259-268 (1949); K. L. Johnson, *Contact Mechanics*, Cambridge 1985, §7.2; D. M. Barnett and
J. Lothe, "Line force loadings on anisotropic half-spaces and wedges", Phys. Norv. 8, 13-22
(1975) for the anisotropic surface Green's function (not re-checked); J. J. Vlassak and
W. D. Nix, J. Mech. Phys. Solids 42, 1223 (1994); the Weber-Schafheitlin integral and the
Hankel transform of the Jacobi functions: Gradshteyn & Ryzhik 6.574.2 and 6.575 (not
re-checked; the λ = 0 values are verified against the closed form above in the tests).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from ..errors import ContactresInputError
from ..halfspace import scaled_tensor, shear_reference, surface_compliance
from ..materials import Material, require_material
from ..validation import positive

__all__ = [
    "CAUCHY_POINTS",
    "CAUCHY_RADIUS",
    "inplane_kernel",
    "inplane_kernel_harmonics",
    "load_derivatives",
    "radial_integrals",
    "tangential_stiffness_static",
]

# Orders of the logarithmic enrichment (λ-derivatives d = 0..N_LOG): ln and ln² of (1 − r̄²).
N_LOG = 2
# Cauchy's formula for the λ-derivatives of the load (load_derivatives): circle radius and
# points (1/Γ(3/2 + λ) is entire).
CAUCHY_RADIUS = 0.2
CAUCHY_POINTS = 32
# The same for the one-variable factors of R (_weber_taylor): a wider circle (round-off in the
# coefficient of σ^k ~ε/ρ^k: 16ε at the fourth, for the ln² x ln² pairs) with more points
# (aliasing from the pole at σ = −1 ~ρ^nc = 5e-20).
TAYLOR_RADIUS = 0.5
TAYLOR_POINTS = 64
# θ grid of the kernel harmonics: first size, largest size.
_N_THETA_START = 64
_N_THETA_MAX = 2**14
# First basis (harmonics |n| <= 6, 2 radial terms per harmonic and log order); the harmonics
# are doubled until K moves by less than rtol, then the radial terms, up to these limits.
_START_TERMS = (6, 2)
_MAX_HARMONICS = 96
_MAX_RADIAL = 16
# Eigenvalues of the scaled Galerkin matrix below this fraction of the largest are dropped:
# the enriched basis is nearly dependent at larger sizes, and a Galerkin on the remaining
# subspace is still variational (it only drops directions that carry no energy).
_EIG_CUTOFF = 1e-14


def inplane_kernel(m: Material, theta) -> np.ndarray:
    """In-plane block Ĝ_αβ(θ) of the static surface Green's function, 1/Pa.

    Parameters
    ----------
    m : Material
        Stiffness in the surface frame (z = inward normal), Pa; lossless.
    theta : array_like
        Direction of the surface wave vector from the surface x axis, rad.

    Returns
    -------
    ndarray, complex, shape ``theta.shape + (2, 2)``
        Ĝ_αβ(θ): û_α(ξ) = Ĝ_αβ(θ)/``|ξ|`` t̂_β(ξ) for a tangential surface traction t applied to
        the solid (module docstring). Hermitian; isotropic (δ_αβ − ν n_α n_β)/G.
    """
    m = require_material(m, lossless=True)
    H = surface_compliance(scaled_tensor(m), np.asarray(theta, dtype=float), 0.0)
    # t_i = −σ_i3 on the face whose outward normal is −z, hence the sign.
    return -H[..., :2, :2] / shear_reference(m)


def inplane_kernel_harmonics(m: Material, max_order: int, rtol: float = 1e-13) -> np.ndarray:
    """Ĝ_{αβ,m} = ∫₀^{2π} Ĝ_αβ(θ) e^{imθ} dθ for m = −max_order..max_order, 1/Pa.

    The trapezoidal rule (an FFT) on an equispaced θ grid, doubled from 64 points until the
    harmonics move by less than ``rtol`` relative to the largest (exponential convergence).

    Returns
    -------
    ndarray, complex, shape (2 max_order + 1, 2, 2)
        Row j holds the harmonic m = j − max_order.
    """
    orders = np.arange(-int(max_order), int(max_order) + 1)
    n = _N_THETA_START
    while n < 4 * orders[-1] + 8:
        n *= 2
    prev = None
    while True:
        g = inplane_kernel(m, 2 * np.pi * np.arange(n) / n)
        # e^{imθ_j} = e^{2πi m j/n}: the FFT bin −m.
        h = (2 * np.pi / n) * np.fft.fft(g, axis=0)[(-orders) % n]
        if prev is not None:
            change = np.max(np.abs(h - prev)) / np.max(np.abs(h))
            if change <= rtol:
                return h
        if n >= _N_THETA_MAX:
            raise ContactresInputError(
                f"kernel harmonics did not converge to rtol={rtol:g} with {n} theta points"
            )
        prev, n = h, 2 * n


def radial_integrals(p_max: int, n_log: int) -> np.ndarray:
    """∂^{d_a}_{λ_a} ∂^{d_b}_{λ_b} R(p_a, λ_a; p_b, λ_b) at λ = 0 (module docstring).

    Returns an array (n_log + 1, n_log + 1, p_max + 1, p_max + 1), real. Weber-Schafheitlin with
    μ = p_a + ½ + λ_a, ν = p_b + ½ + λ_b, exponent L = 1 + λ_a + λ_b:
    R = (π/2) Γ(L) Γ((p_a+p_b+1)/2) / (2^L Γ((p_b−p_a)/2 + 1 + λ_b) Γ((p_a+p_b+3)/2 + λ_a + λ_b)
    Γ((p_a−p_b)/2 + 1 + λ_a)).

    R is a product A_{p_a+p_b}(λ_a + λ_b) B_{p_a−p_b}(λ_a) B_{p_b−p_a}(λ_b) of functions of one
    variable each (:func:`_weber_taylor`), so its Taylor coefficient of λ_a^u λ_b^v is
    Σ_{r<=u, s<=v} C(r+s, r) a_{r+s} b_{u−r} b'_{v−s} (the binomial expansion of (λ_a + λ_b)^k):
    the Γ factors are evaluated on one circle in one variable (nc (2 p_max + 1) values each)
    instead of on every (λ_a, λ_b) pair of a two-variable Cauchy rule (nc² (2 p_max + 1): 16x
    more at nc = 32); against a rule of 160 points on ``|σ|`` = 0.6 the entries (relative to
    the largest of each (d_a, d_b)) agree to <= 7e-15, as the two-variable rule's did (<= 1e-14).
    """
    a, b = _weber_taylor(p_max, 2 * n_log)
    p = np.arange(p_max + 1)
    total = p[:, None] + p[None, :]  # p_a + p_b
    diff = p[:, None] - p[None, :] + p_max  # index of p_a − p_b (its transpose: p_b − p_a)
    a = a[:, total]
    ba, bb = b[:, diff], b[:, diff.T]
    out = np.zeros((n_log + 1, n_log + 1, p_max + 1, p_max + 1))
    # Loops over the derivative orders only (<= 3 x 3 x 3 x 3 terms of (p_max + 1)² values).
    for u in range(n_log + 1):
        for v in range(n_log + 1):
            for r in range(u + 1):
                for s in range(v + 1):
                    out[u, v] += math.comb(r + s, r) * a[r + s] * ba[u - r] * bb[v - s]
            out[u, v] *= math.factorial(u) * math.factorial(v)
    return out


def _weber_taylor(p_max: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Taylor coefficients at 0, up to ``order``, of the factors of R (:func:`radial_integrals`).

    Returns ``(a, b)``: a[k, t] the coefficient of σ^k of
    A_t(σ) = (π/2) Γ(1 + σ) 2^{−1−σ} Γ((t+1)/2)/Γ((t+3)/2 + σ), t = p_a + p_b = 0..2 p_max, and
    b[k, p_max + e] that of B_e(λ) = 1/Γ(e/2 + 1 + λ), e = p_a − p_b = −p_max..p_max.
    Cauchy's formula on the circle ``|σ|`` = TAYLOR_RADIUS (trapezoidal rule, TAYLOR_POINTS
    points): spectrally accurate, the nearest singularity being the pole of Γ(1 + σ) at σ = −1
    (B is entire)."""
    nc, rho = TAYLOR_POINTS, TAYLOR_RADIUS
    z = rho * np.exp(2j * np.pi * np.arange(nc) / nc)[:, None]
    total = np.arange(2 * p_max + 1, dtype=float)
    # Γ((t+1)/2)/Γ((t+3)/2 + σ) as one log-gamma difference: no overflow at large t.
    ratio = np.exp(special.gammaln((total + 1) / 2) - special.loggamma((total + 3) / 2 + z))
    by_sum = (np.pi / 2) * special.gamma(1 + z) * 2.0 ** (-1 - z) * ratio  # (nc, 2 p_max + 1)
    diff = np.arange(-p_max, p_max + 1, dtype=float)
    by_diff = special.rgamma(diff / 2 + 1 + z)  # (nc, 2 p_max + 1)
    k = np.arange(order + 1)
    # Coefficient of z^k: the mean of f z^{−k} over the circle.
    w = np.exp(-2j * np.pi * np.outer(k, np.arange(nc)) / nc) / (nc * rho ** k[:, None])
    return (w @ by_sum).real, (w @ by_diff).real


def load_derivatives(n_log: int) -> np.ndarray:
    """∂^d_λ H(0; λ) at λ = 0, d = 0..n_log: the force carried by the n = 0, k = 0 functions.

    H(0; λ) = √(π/2) 2^{−½−λ}/Γ(3/2 + λ) is the transform at s = 0 (1 at λ = 0).
    """
    nc, rho = CAUCHY_POINTS, CAUCHY_RADIUS
    z = rho * np.exp(2j * np.pi * np.arange(nc) / nc)
    h = math.sqrt(np.pi / 2) * 2.0 ** (-0.5 - z) * special.rgamma(1.5 + z)
    d = np.arange(n_log + 1)
    coef = np.mean(h[None, :] * z[None, :] ** (-d[:, None]), axis=1)
    return (coef * special.factorial(d)).real


def _basis(n_harmonics: int, n_radial: int, n_log: int):
    """Flat index arrays (α, n, k, d) of the basis."""
    grids = np.meshgrid(
        np.arange(2),
        np.arange(-n_harmonics, n_harmonics + 1),
        np.arange(n_radial),
        np.arange(n_log + 1),
        indexing="ij",
    )
    return tuple(g.ravel() for g in grids)


def _compliance_form(harm: np.ndarray, n_harmonics: int, n_radial: int, n_log: int) -> np.ndarray:
    """bᴴ M⁻¹ b (2x2, Pa) for the kernel harmonics ``harm`` (orders −2N..2N, N >= n_harmonics)."""
    alpha, n, k, d = _basis(n_harmonics, n_radial, n_log)
    p = np.abs(n) + 2 * k
    radial = radial_integrals(int(p.max()), n_log)
    mid = harm.shape[0] // 2
    dn = n[None, :] - n[:, None]
    G = harm[mid + dn, alpha[:, None], alpha[None, :]]
    phase = 1j ** ((np.abs(n)[:, None] - np.abs(n)[None, :]) % 4)
    M = phase * G * radial[d[:, None], d[None, :], p[:, None], p[None, :]]
    M = 0.5 * (M + M.conj().T)  # Hermitian up to round-off
    b = np.zeros((alpha.size, 2))
    first = (n == 0) & (k == 0)
    load = load_derivatives(n_log)
    for a in range(2):
        sel = first & (alpha == a)
        b[sel, a] = load[d[sel]]
    # Diagonal scaling, then the eigen-decomposition with near-null directions dropped.
    s = 1.0 / np.sqrt(np.real(np.diagonal(M)))
    w, V = np.linalg.eigh(s[:, None] * M * s[None, :])
    keep = w > _EIG_CUTOFF * w[-1]
    Vb = V[:, keep].conj().T @ (s[:, None] * b)
    return np.real(Vb.conj().T @ (Vb / w[keep, None]))


def _tensor(m: Material, terms, rtol: float, one_term: bool) -> tuple[np.ndarray, tuple]:
    """K/a (2x2, Pa) and the basis size (n_harmonics, n_radial) used."""
    if one_term:
        g0 = inplane_kernel_harmonics(m, 0, rtol=min(rtol, 1e-13))[0].real
        g0 = 0.5 * (g0 + g0.T)
        return 8 * np.pi * np.linalg.inv(g0), (0, 1)
    if terms is not None:
        nh, nr = (int(v) for v in terms)
        if nh < 0 or nr < 1:
            raise ContactresInputError(
                f"terms must be (n_harmonics >= 0, n_radial >= 1), got {terms!r}"
            )
        harm = inplane_kernel_harmonics(m, 2 * nh)
        return 4 * np.pi**2 * _compliance_form(harm, nh, nr, N_LOG), (nh, nr)
    # Angular harmonics first (they converge slowest: e.g. cubic (111) couples n = 0 to
    # n = ±6, ±12, ... with contributions falling ~50x per step of 6), then the radial terms.
    nh, nr = _START_TERMS
    harm = inplane_kernel_harmonics(m, 2 * _MAX_HARMONICS)
    mid = harm.shape[0] // 2

    def solve(nh: int, nr: int) -> np.ndarray:
        h = harm[mid - 2 * nh : mid + 2 * nh + 1]
        return 4 * np.pi**2 * _compliance_form(h, nh, nr, N_LOG)

    K = solve(nh, nr)
    change = float("inf")
    for grow_radial in (False, True):
        while True:
            nh2, nr2 = (nh, 2 * nr) if grow_radial else (2 * nh, nr)
            if nh2 > _MAX_HARMONICS or nr2 > _MAX_RADIAL:
                raise ContactresInputError(
                    f"tangential Galerkin did not converge to rtol={rtol:g} with {nh} "
                    f"harmonics and {nr} radial terms (last change {change:.3g} relative)"
                )
            K2 = solve(nh2, nr2)
            change = float(np.max(np.abs(K2 - K)) / np.max(np.abs(K2)))
            K, nh, nr = K2, nh2, nr2
            if change <= rtol:
                break
    return K, (nh, nr)


def tangential_stiffness_static(
    material: Material,
    radius,
    *,
    tensor: bool = False,
    direction: float = 0.0,
    rtol: float = 1e-10,
    terms: tuple[int, int] | None = None,
    one_term: bool = False,
):
    """Static tangential stiffness of a rigid circular contact, relaxed (no normal traction).

    Parameters
    ----------
    material : Material
        Lossless stiffness in the surface frame (z = inward normal, x and y in the surface; use
        :meth:`Material.rotated` for a face (hkl)), Pa.
    radius : float or array
        Contact radius a > 0, m.
    tensor : bool
        Return the 2x2 tensor K_αβ (F_α = K_αβ U_β, surface-frame x, y) instead of K_ψ.
    direction : float
        ψ, degrees from the surface x axis towards y (right-handed about the inward normal z):
        K_ψ = e_ψ·K·e_ψ with e_ψ = (cos ψ, sin ψ), the force component along a motion e_ψ.
    rtol : float
        Relative accuracy of K: harmonics ``|n|`` <= 6 and 2 radial terms per harmonic and log order
        to start; the harmonics are doubled until K moves by less than ``rtol`` (max-norm,
        relative to the largest entry), then the radial terms, until that doubling also moves
        it by less; in [1e-13, 1e-2]. Ignored with ``terms`` or ``one_term``.
    terms : (int, int), optional
        Fixed basis: angular harmonics ``|n|`` <= terms[0] and terms[1] radial terms per harmonic
        and log order (no convergence check).
    one_term : bool
        Mindlin's traction shape only: K₁ = 8π a [∫₀^{2π} Re Ĝ(θ) dθ]⁻¹, a lower bound of K
        (module docstring); exact when the surface is a mirror plane of the solid.

    Returns
    -------
    float or ndarray
        K_ψ in N/m (shaped like ``radius``), or with ``tensor`` the tensor, N/m, shaped
        ``radius.shape + (2, 2)``: symmetric, positive definite.

    Notes
    -----
    Isotropic: K = 8Ga/(2 − ν) (Mindlin 1949; Johnson 1985, §7.2), reproduced by the Galerkin to
    round-off. K is linear in a, so the Galerkin runs once per call.

    Examples
    --------
    Isotropic glass, contact radius 1 µm: Mindlin's K = 8Ga/(2 − ν) (one basis term is exact here):

    >>> import numpy as np
    >>> from contactres import Material, tangential_stiffness_static
    >>> glass = Material.isotropic(70e9, 0.22)
    >>> K = tangential_stiffness_static(glass, 1e-6, one_term=True)  # N/m
    >>> print(f"{K:.5g} N/m")
    1.2894e+05 N/m
    >>> G = 70e9 / (2 * (1 + 0.22))
    >>> bool(np.isclose(K, 8 * G * 1e-6 / (2 - 0.22), atol=0))
    True
    """
    m = require_material(material, lossless=True)
    a = np.asarray(positive("radius", radius, "m"), dtype=float)
    rtol = float(rtol)
    if not (1e-13 <= rtol <= 1e-2):
        raise ContactresInputError(f"rtol must lie in [1e-13, 1e-2], got {rtol!r}")
    k_per_a, _ = _tensor(m, terms, rtol, one_term)
    k_per_a = 0.5 * (k_per_a + k_per_a.T)  # reciprocity; removes the round-off asymmetry
    if tensor:
        out = a[..., None, None] * k_per_a
        return out
    psi = math.radians(float(direction))
    e = np.array([math.cos(psi), math.sin(psi)])
    k = a * float(e @ k_per_a @ e)
    return float(k) if k.ndim == 0 else k
