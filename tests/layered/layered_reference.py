"""Test-only reference: the layered surface compliance by a global boundary-value solve.

Independent of contactres.layered and contactres.halfspace: the first-order (Stroh) system
d/dz [u; t] = η N [u; t] with t = σ_i3/(η C44_ref), written out here from the equations of
motion; each layer's transfer matrix is scipy.linalg.expm(η h N) (fine at moderate η h, where a
transfer matrix is still accurate), and the substrate's decaying subspace is spanned by the
ordered Schur vectors of N (eigenvalues with Re < 0), which also works where N is defective
(the static isotropic solid).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from contactres.materials import voigt_to_tensor


def stroh_matrix(c: np.ndarray, theta: float, s: complex) -> np.ndarray:
    """N of d/dz [u; t] = η N [u; t] for the tensor c = C/C44_ref and s = ρω²/(C44_ref η²)."""
    n = np.array([np.cos(theta), np.sin(theta)])
    Q = np.einsum("iakb,a,b->ik", c[:, :2, :, :2], n, n)
    R = np.einsum("iak,a->ik", c[:, :2, :, 2], n)
    W = c[:, 2, :, 2]
    Wi = np.linalg.inv(W)
    N = np.empty((6, 6), dtype=complex)
    N[:3, :3] = -1j * Wi @ R.T
    N[:3, 3:] = Wi
    N[3:, :3] = Q - s * np.eye(3) - R @ Wi @ R.T
    N[3:, 3:] = -1j * R @ Wi
    return N


def reference_compliance(materials, thicknesses, eta: float, theta: float, frequency: float):
    """H (3x3) with u(0) = H σ(0)/(C44_ref η), C44_ref = Re C44 of the substrate (last)."""
    c44 = float(np.real(materials[-1].C[3, 3]))
    omega2 = (2 * np.pi * frequency) ** 2
    Ns = []
    for m in materials:
        c = voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44
        s = (m.density or 0.0) * omega2 / (c44 * eta**2)
        Ns.append(stroh_matrix(c, theta, s))
    P = np.eye(6, dtype=complex)
    for N, h in zip(Ns[:-1], thicknesses, strict=True):
        P = scipy.linalg.expm(eta * h * N) @ P
    _, V, _ = scipy.linalg.schur(Ns[-1], output="complex", sort="lhp")
    V = V[:, :3]
    # P [u0; t0] = V a: unknowns u0 and a, for t0 = each unit vector.
    A = np.hstack([P[:, :3], -V])
    X = np.linalg.solve(A, -P[:, 3:])
    return X[:3]
