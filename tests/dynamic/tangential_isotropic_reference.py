"""Independent reference for the horizontal (tangential) rigid disk on an isotropic half-space.

Helper module for the tests (not part of the package). The massless rigid disk of radius a,
translated rigidly by U e^{iωt} in x without rotation, on a lossless isotropic half-space with
*relaxed* contact (zero normal traction under the disk, the normal displacement is free). We
want K_t(ω)/K_t0 = k_t(a₀) + i a₀ c_t(a₀), a₀ = k_s a, K_t0 = 8Ga/(2 − ν) (Mindlin 1949).

Method: the Galerkin fallback of issue 13 (not the Luco–Westmann Fredholm pair), written from
scratch: the surface Green's function of the half-space in Fourier space, a Mindlin-type
traction basis whose Hankel transforms are spherical Bessel functions, and the radial wave-number
integrals by Gauss–Legendre along a contour indented above the branch points and the Rayleigh
pole. Nothing is imported from :mod:`contactres`.

Derivation (units a = G = 1; k_s = ω/c_s, γ² = k_p²/k_s² = (1 − 2ν)/(2(1 − ν)))
-------------------------------------------------------------------------------
Green's function. With f̂(ξ) = ∫ f(x) e^{−iξ·x} d²x, a surface traction t(x) in the plane
(t_z = 0) gives the in-plane surface displacement

    û = A(ξ) t̂_L ξ̂ + B(ξ) t̂_T ê_ψ,   t̂_L = ξ̂·t̂,  t̂_T = ê_ψ·t̂,  ê_ψ = ẑ × ξ̂,
    A = −k_s² ν_s / F,   B = 1/ν_s,   F = (2ξ² − k_s²)² − 4ξ² ν_p ν_s,
    ν_s = √(ξ² − k_s²),  ν_p = √(ξ² − k_p²)   (Re ν ≥ 0),

the P-SV (Rayleigh-function) term A and the SH term B (Lamb 1904; e.g. Kausel 2006,
"Fundamental solutions in elastodynamics", surface loads of a half-space — signs not
re-checked there, but fixed here by the static limit: A -> (1 − ν)/ξ, B -> 1/ξ, Cerruti).
For e^{iωt} the lossless limit is taken from the damped side (G(1 + i0), so k_s slightly
below the real axis): the branch points k_p < k_s and the Rayleigh pole k_R = ζ_R k_s lie just
below the real ξ axis and the ξ integral passes above them. The principal square root of
ξ² − k² is then right for ξ in the first quadrant.

Traction basis. The response to U e_x has the symmetry t_r = F(r) cos θ, t_θ = −G(r) sin θ, i.e.
t_x = S(r) + D(r) cos 2θ, t_y = D(r) sin 2θ with S = (F + G)/2, D = (F − G)/2. Using
e^{−iξr cos(θ−ψ)} = Σ (−i)ⁿ Jₙ(ξr) e^{in(θ−ψ)},

    t̂_L = 2π cos ψ [Ŝ(ξ) − D̂(ξ)],   t̂_T = −2π sin ψ [Ŝ(ξ) + D̂(ξ)],
    Ŝ = ∫₀¹ S r J₀(ξr) dr,   D̂ = ∫₀¹ D r J₂(ξr) dr.

The Mindlin basis is r^m (1 − r²)^{−1/2} P_k^{(−1/2, m)}(1 − 2r²) (m = 0 for S, m = 2 for D),
whose order-m Hankel transform is, up to a constant, the spherical Bessel function j_{m+2k}(ξ)
(Gradshteyn & Ryzhik 6.567.1 with μ = −1/2, not re-checked; the k = 0 case ∫ r (1 − r²)^{−1/2}
J₀(ξr) dr = sin ξ/ξ is elementary). We normalise each basis function so that its transform is
exactly j_n: S-functions Ŝ = j_{2k}, D-functions D̂ = j_{2k+2}, k = 0 … N − 1.

Galerkin. The reaction ⟨t_i, u_j⟩ = ∫ t_i·u[t_j] d²x = (2π)⁻² ∫ t̂_i·û_j d²ξ (real t̂ here),
after the ψ integral

    M_ij = π ∫₀^∞ [A(ξ) P_i P_j + B(ξ) Q_i Q_j] ξ dξ,   P = Ŝ − D̂,   Q = Ŝ + D̂,

and rigid translation tested against every t_i gives M c = U b with b_i = ∫ t_{i,x} d²x =
2π Ŝ_i(0) = 2π δ_{i,0}; the force is F_x = bᵀc, so K_t = bᵀ M⁻¹ b = 4π² (M⁻¹)₀₀. Statically
M₀₀ = π (2 − ν) ∫ j₀² dξ = π²(2 − ν)/2 and K_t = 8/(2 − ν): Mindlin, with t = (1 − r²)^{−1/2}
exact (Johnson 1985, §3.8). M is complex symmetric (reciprocity).

Numerics (every resolution knob is doubled in the convergence test)
----------------------------------------------------------------------
* Static part: Aξ -> (1 − ν), Bξ -> 1 gives ∫₀^∞ j_m j_n dξ = π/(2(2m + 1)) δ_mn for even m, n
  (Weber–Schafheitlin, ∫ J_μ J_ν dt/t = 2 sin((μ − ν)π/2)/(π(μ² − ν²))), added in closed form.
* Dynamic remainder (Aξ − (1 − ν)) and (Bξ − 1) ~ a₀²/ξ²: Gauss–Legendre on a half-ellipse
  0 -> 2.5 a₀ of height a₀/2 in the upper half plane (j_n is entire), then real panels, geometric
  up to 8 and of width ~2 (the products j_m j_n oscillate like cos 2ξ) up to ξ_max. The tail
  beyond ξ_max is added from the leading asymptotics: Aξ − (1 − ν) ≈ (1 − ν)(c₁ − ½)a₀²/ξ²,
  c₁ = (1 + (1 − γ²)²/2)/(2(1 − γ²)), Bξ − 1 ≈ a₀²/(2ξ²), and the non-oscillating mean
  j_m j_n ≈ cos((m − n)π/2)/(2ξ²), so ∫_{ξ_max}^∞ ≈ (coefficient) cos(…)/(6 ξ_max³).
* On the real panels the Rayleigh function is evaluated in rationalised form (see
  :func:`_kernels`): the direct form cancels ~ξ²/a₀² digits, 1e-7 in K_t at a₀ = 1e-4.
* Measured: the basis converges spectrally (N = 4 is 1e-11 from N = 8 at a₀ = 2); doubling all
  knobs from the defaults (8, 32, 200) moves K_t/K_t0 by <= 1.3e-8 for a₀ <= 2, ν <= 0.45.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import integrate, optimize, special
from wavenumber_contour import wavenumber_rule

__all__ = [
    "low_frequency_damping",
    "rayleigh_root",
    "tangential_disk",
]


def _gamma2(nu):
    return (1 - 2 * nu) / (2 * (1 - nu))


def _kernels(eta, a0, nu):
    """(A ξ, B ξ) at ξ = η (complex allowed, first quadrant): the Green's function of the
    module docstring times ξ, so that both tend to constants (1 − ν, 1) at large ξ.

    F = (2ξ² − k_s²)² − 4ξ²ν_pν_s is a difference of two terms ~4ξ⁴ that leaves ~2(1 − γ²)k_s²ξ²:
    in that form it loses ξ²/a₀² of its digits (1e-7 absolute in K_t at a₀ = 1e-4). On the real
    axis beyond the singularities it is therefore rationalised,
    F = N/((2ξ² − k²)² + 4ξ²ν_pν_s), N = −16(1 − γ²)kX³ + (24 − 16γ²)k²X² − 8k³X + k⁴
    (X = ξ², k = k_s²), both terms of the new denominator being positive there.
    """
    z = np.asarray(eta, dtype=complex)
    z2, k = z * z, a0 * a0
    g2 = _gamma2(nu)
    s = np.sqrt(z2 - k)
    p = np.sqrt(z2 - g2 * k)
    poly = -16 * (1 - g2) * k * z2**3 + (24 - 16 * g2) * k * k * z2**2 - 8 * k**3 * z2 + k**4
    far = (z.imag == 0) & (z.real > 1.5 * a0)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(
            far,
            poly / ((2 * z2 - k) ** 2 + 4 * z2 * p * s),
            (2 * z2 - k) ** 2 - 4 * z2 * p * s,
        )
    return -k * s * z / f, z / s


def _tail_coefficients(nu):
    """c_A, c_B of Aξ ≈ (1 − ν) + c_A a₀²/ξ², Bξ ≈ 1 + c_B a₀²/ξ² (series in x = a₀²/ξ²)."""
    q = 1 - _gamma2(nu)
    c1 = (1 + q * q / 2) / (2 * q)
    return (1 - nu) * (c1 - 0.5), 0.5


def _wavenumber_rule(a0, n_wave, xi_max):
    """Nodes/weights of ∫₀^{ξ_max} (:mod:`wavenumber_contour`; panels of width 64/n_wave beyond
    ξ = 8)."""
    return wavenumber_rule(a0, n_wave, xi_max, 64.0 / n_wave, max(8, n_wave // 2))


def tangential_disk(a0, nu, n_basis=8, n_wave=32, xi_max=200.0):
    """K_t/K_t0 = k_t + i a₀ c_t of the relaxed rigid disk (module docstring).

    Parameters
    ----------
    a0 : float
        Dimensionless frequency k_s a (> 0).
    nu : float
        Poisson's ratio, 0 <= ν < 1/2.
    n_basis : int
        Basis functions per block (S and D), N.
    n_wave : int
        Gauss–Legendre nodes on the contour; real panels get n_wave/2 nodes and width 64/n_wave.
    xi_max : float
        End of the numerical ξ integral (the asymptotic tail beyond is added analytically).

    Returns
    -------
    complex
        K_t/K_t0, with K_t0 = 8Ga/(2 − ν).
    """
    k = np.arange(n_basis)
    orders = np.concatenate([2 * k, 2 * k + 2])  # S block, then D block
    sign = np.concatenate([np.ones(n_basis), -np.ones(n_basis)])  # P = Ŝ − D̂
    # static part: π [(1 − ν) ∫ P_i P_j + ∫ Q_i Q_j], ∫ j_m j_n dξ = π δ_mn / (2(2m + 1))
    same = orders[:, None] == orders[None, :]
    gram = np.where(same, np.pi / (2 * (2 * orders[:, None] + 1)), 0.0)
    ss = sign[:, None] * sign[None, :]
    m = np.pi * ((1 - nu) * ss + 1) * gram
    # dynamic remainder on the contour + real panels
    eta, deta = _wavenumber_rule(a0, n_wave, xi_max)
    ka, kb = _kernels(eta, a0, nu)
    # complex arithmetic only on the contour: the real-axis panels (most nodes) stay real
    jn = np.concatenate(
        [
            special.spherical_jn(orders[:, None], eta[None, :n_wave]),
            special.spherical_jn(orders[:, None], eta[None, n_wave:].real),
        ],
        axis=1,
    )
    wa = (ka - (1 - nu)) * deta
    wb = (kb - 1) * deta
    m = m + np.pi * (ss * ((jn * wa) @ jn.T) + (jn * wb) @ jn.T)
    # asymptotic tail beyond ξ_max (mean of j_m j_n only; the oscillating part is O(ξ_max⁻⁴))
    ca, cb = _tail_coefficients(nu)
    mean = np.cos((orders[:, None] - orders[None, :]) * np.pi / 2) / 2
    m = m + np.pi * a0 * a0 * (ca * ss + cb) * mean / (3 * xi_max**3)
    e0 = np.zeros(2 * n_basis)
    e0[0] = 1.0
    return complex(4 * np.pi**2 * np.linalg.solve(m, e0)[0] * (2 - nu) / 8)


def rayleigh_root(nu):
    """ζ_R = k_R/k_s > 1, the real root of (2ζ² − 1)² = 4ζ² √(ζ² − γ²) √(ζ² − 1)."""
    g2 = _gamma2(nu)

    def f(z):
        return (2 * z * z - 1) ** 2 - 4 * z * z * math.sqrt(z * z - g2) * math.sqrt(z * z - 1)

    return optimize.brentq(f, 1 + 1e-12, 2.0, xtol=1e-15)


def low_frequency_damping(nu):
    """c_t(0) by first-order perturbation of the static (Mindlin) solution.

    The static traction (1 − r²)^{−1/2} (Ŝ = j₀, D̂ = 0) is stationary for the Galerkin
    functional, so to first order δK/K = −δM₀₀/M₀₀ with M₀₀ = π²(2 − ν)/2. For a₀ -> 0 the
    imaginary part of A, B lives on ξ <= ζ_R a₀ where j₀ = 1 + O(a₀²); with ξ = a₀ζ,
    Aξ = Ã(ζ), Bξ = B̃(ζ) and ∫ (·) dξ = a₀ ∫ (·) dζ, so

        c_t(0) = −(2/(π(2 − ν))) Im ∫₀^∞ [Ã(ζ) + B̃(ζ)] dζ,
        Ã = −ζ√(ζ² − 1)/F̂,  F̂ = (2ζ² − 1)² − 4ζ²√(ζ² − γ²)√(ζ² − 1),  B̃ = ζ/√(ζ² − 1).

    Im ∫ B̃ = −∫₀¹ ζ/√(1 − ζ²) dζ = −1 (SH radiation, closed form); Im ∫ Ã = quad over the
    radiating band 0 < ζ < 1 plus −π × the residue at the Rayleigh pole (the path passes above).
    """
    g = math.sqrt(_gamma2(nu))

    def im_a(z):
        return float(_kernels(z, 1.0, nu)[0].imag)

    band = sum(
        integrate.quad(im_a, lo, hi, epsabs=1e-13, epsrel=1e-12, limit=200)[0]
        for lo, hi in ((0.0, g), (g, 1.0))
    )
    zr = rayleigh_root(nu)
    al, be = math.sqrt(zr * zr - g * g), math.sqrt(zr * zr - 1)
    d_f = 8 * zr * (2 * zr * zr - 1) - 8 * zr * al * be - 4 * zr**3 * (be / al + al / be)
    residue = -zr * be / d_f
    im_total = band - math.pi * residue - 1.0
    return -2 / (math.pi * (2 - nu)) * im_total
