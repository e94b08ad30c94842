"""Surface compliance where partial waves propagate: the 6x6 Stroh eigen-decomposition.

A lossless solid at a real κ below a bulk-wave cutoff has real vertical wave numbers p: there is
no decaying/growing split and the doubling algorithm (:mod:`._doubling`) cannot converge. Those
points (only those) are diagonalised in the first-order (Stroh) form of the same equations
(paper 1, Eqs. 10-19), keeping the partial waves that carry energy into the solid: the limit
Im κ -> 0+ of the decaying choice (limiting absorption). About 40 µs per (κ, θ) point, ~10x the
doubling algorithm.
"""

from __future__ import annotations

import numpy as np

from ..errors import ContactresInputError

__all__ = ["outgoing_compliance"]

# Eigenvalues of the Stroh matrix closer than this (relative) to the imaginary axis are treated as
# real vertical wave numbers (propagating waves of a lossless solid).
_REAL_ROOT_TOL = 1e-9


def outgoing_compliance(Q, R, W, s3, th, sv) -> np.ndarray:
    """Dimensionless surface compliance H of a lossless solid with propagating partial waves.

    The limit Im κ -> 0+ of the decaying choice (limiting absorption): the 6x6 Stroh matrix
    N = [[−i W⁻¹Rᵀ, W⁻¹], [Q − S − R W⁻¹Rᵀ, −i R W⁻¹]] (S = diag(s); the first-order form of
    paper 1, Eqs. 10-19, for the displacement and the traction σ_i3) is
    diagonalised; eigenvalues λ = i p with Re λ < 0 are kept, and of the real p those whose
    eigenvalue moves into Re λ < 0 when κ gets a small positive imaginary part. By the
    J-symmetry of N that shift is δλ = i δκ κ⁻³ uᵀu/(uᵀt) for a mode [u; t], so, with u real and
    τ = −i t real (always possible for a real p), a real-p mode is kept when uᵀτ < 0 (its energy
    flows into the solid). Exactly repeated real roots (the isotropic shear pair) are fine: the
    test is made on the real form of each computed eigenvector, which lies in the same
    eigenspace. Costs ~10x the doubling algorithm per point.

    Parameters
    ----------
    Q, R, W : ndarray, real, shape (3, 3, N)
        Dimensionless (balanced) blocks of the Christoffel pencil, as for
        :func:`.doubling.decaying_solvent`.
    s3 : ndarray, real, shape (3, N)
        Diagonal of the balanced inertia term, ρω²/(C44 η²) per component.
    th : ndarray, shape (N,)
        Directions of the surface wave vector, rad (for error messages).
    sv : ndarray, shape (N,)
        1/κ² of every point, dimensionless (for error messages).

    Returns
    -------
    ndarray, complex, shape (3, 3, N)
        H (balanced), u(0) = H σ_i3/(C44 η) for the outgoing field (paper 1, Eqs. 12, 19).

    Raises
    ------
    ValueError
        Exactly at a bulk-wave cutoff (no split into three outgoing waves) or at the Rayleigh
        pole (infinite response).
    """
    n = th.size
    Qm, Rm, Wm = (np.moveaxis(a, -1, 0) for a in (Q, R, W))
    Wi = np.linalg.inv(Wm)
    Rt = np.swapaxes(Rm, -1, -2)
    N = np.empty((n, 6, 6), dtype=complex)
    N[:, :3, :3] = -1j * Wi @ Rt
    N[:, :3, 3:] = Wi
    N[:, 3:, :3] = Qm - Rm @ Wi @ Rt
    N[:, [3, 4, 5], [0, 1, 2]] -= s3.T
    N[:, 3:, 3:] = -1j * Rm @ Wi
    lam, V = np.linalg.eig(N)
    scale = np.max(np.abs(lam), axis=-1, keepdims=True)
    on_axis = np.abs(lam.real) <= _REAL_ROOT_TOL * scale
    u, t = V[:, :3, :], V[:, 3:, :]
    # Real form of each mode: x + x' with x' = [conj u; −conj t] (same eigenvalue when p is real).
    ur, tr = u + u.conj(), t - t.conj()
    ui, ti = (u - u.conj()) / 1j, (t + t.conj()) / 1j
    use_i = np.sum(np.abs(ur) ** 2, axis=1) < np.sum(np.abs(ui) ** 2, axis=1)
    ur = np.where(use_i[:, None, :], ui, ur).real
    tau = (-1j * np.where(use_i[:, None, :], ti, tr)).real
    flux_in = np.sum(ur * tau, axis=1) < 0
    keep = np.where(on_axis, flux_in, lam.real < 0)
    count = keep.sum(axis=-1)
    if np.any(count != 3):
        bad = np.flatnonzero(count != 3)[0]
        raise ContactresInputError(
            f"cannot split the partial waves at theta={th[bad]:.6g} rad, "
            f"1/kappa^2={sv[bad]:.6g}: a lossless solid exactly at a bulk-wave cutoff. Add loss "
            "(Material.with_loss) or move kappa off the real axis."
        )
    order = np.argsort(~keep, axis=-1, kind="stable")[:, None, :3]
    A = np.take_along_axis(u, order, axis=-1)
    B = np.take_along_axis(t, order, axis=-1)
    try:
        H = A @ np.linalg.inv(B)
    except np.linalg.LinAlgError:
        raise ContactresInputError(
            "a lossless solid exactly at its Rayleigh pole (infinite surface response); add loss "
            "or move kappa off the real axis"
        ) from None
    return np.moveaxis(H, 0, -1)
