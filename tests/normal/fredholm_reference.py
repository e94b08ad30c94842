"""A second algorithm for the axisymmetric punch and sphere: the Fredholm equation (tests only).

With P(η) = ∫₀^a φ(t) cos(ηt) dt the Hankel transform of the pressure (Copson's representation)
and u(r) = ∫₀^∞ g(η) P(η) J₀(ηr) dη the surface displacement (g = η Ḡ, 1/Pa), Abel's inversion
of u = w on r < a (∫₀^∞ cos(ηt) J₀(ηr) dη = 1/√(r² − t²) for t < r, 0 beyond) gives the
Fredholm equation of the second kind (Lebedev & Ufliand, J. Appl. Math. Mech. 22, 442 (1958);
Cooke, Q. J. Mech. Appl. Math. 16, 193 (1963)):

    φ(t) + ∫₀^a K(t, u) φ(u) du = (2/(π g∞)) W(t),
    K(t, u) = (1/π) [c(t − u) + c(t + u)],   c(x) = ∫₀^∞ (g(η)/g∞ − 1) cos(ηx) dη,

with W = δ for the flat punch and W = δ − t²/R for the sphere (the Abel transform of r²/(2R)).
The force is F = 2π P(0) = 2π ∫₀^a φ dt; the sphere's pressure is bounded at the edge when
φ(a) = 0, which fixes δ. Solved here by Nyström on Gauss–Legendre nodes (spectrally accurate
for a smooth c), independently of the Galerkin of :mod:`contactres.normal._axisymmetric`.
"""

import numpy as np


def fredholm(A, c, a, n=400):
    """(K, δR/a², FR/a³) of the punch and the sphere (R = 1) by Nyström (module docstring)."""
    x, w = np.polynomial.legendre.leggauss(n)
    t, w = 0.5 * a * (x + 1), 0.5 * a * w
    kern = (c(t[:, None] - t[None, :]) + c(t[:, None] + t[None, :])) / np.pi
    mat = np.eye(n) + kern * w[None, :]
    f_punch = np.full(n, 2 / (np.pi * A))  # δ = 1
    f_curv = -2 / (np.pi * A) * t**2  # the −t²/R part, R = 1
    phi_p = np.linalg.solve(mat, f_punch)
    phi_c = np.linalg.solve(mat, f_curv)
    k_edge = (c(a - t) + c(a + t)) / np.pi * w  # φ(a) from the equation itself (Nyström)
    end_p = 2 / (np.pi * A) - k_edge @ phi_p
    end_c = -2 / (np.pi * A) * a * a - k_edge @ phi_c
    delta = -end_c / end_p
    force = 2 * np.pi * w @ (delta * phi_p + phi_c)
    return 2 * np.pi * w @ phi_p, delta / a**2, force / a**3
