"""The normal kernel of an axisymmetric stack of isotropic layers on its sagittal plane.

For a stack every material of which is unchanged by rotations about the normal, at θ = 0 (the
wave vector along x) the plane y = 0 is a mirror plane of the whole problem: the SH
polarisation u_y decouples from the sagittal (P-SV) one, (u_x, u_z), and every 3x3 matrix of
the impedance recursion (the layers' half-space solutions D and exponents A, the substrate's
impedance Y, the factors P and Q of :func:`contactres.layered.compliance_factors`) is block
diagonal, {x, z} ⊕ {y}. The normal entry H_33 = (P Q⁻¹)_zz lies in the {x, z} block, so the
recursion runs there on stacks of 2x2 matrices: each product 8 complex multiplications per
node instead of 27, each inverse a 2x2 one. The same recursion, the same formulas
(Y_top = Q P⁻¹ layer by layer, H = P Q⁻¹ at the top; J. Tian, paper 1, and the module
``contactres.layered._recursion``), restricted to the block, so the results equal the 3x3 ones
to round-off (tested).

An isotropic layer's exponential exp(ηh A_d) takes the closed form of
:func:`contactres.layered._expm.expm_isotropic` (Sylvester's formula at the two roots −α_L,
−α_T) on the block: the block holds the P and SV waves, whose roots are λ_L and λ_T, and λ_T is
the decoupled SH entry A_yy (the SH wave decays like the SV one), so λ_L = tr(block) − λ_T.
A mirror-plane layer's upward solutions are sign changes of its downward ones (M X M with
M = diag(1, −1) on the block).
"""

from __future__ import annotations

import numpy as np

from ..layered import two_root_expm

__all__ = [
    "sagittal_h33",
    "sagittal_h33_blocks",
    "sagittal_reference",
    "sagittal_reference_block",
]


def _mm(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Products of stacked 2x2 matrices (2, 2, N), entry by entry on contiguous vectors (each
    entry's two products written in place: no temporary per entry)."""
    out = np.empty(a.shape[:2] + np.broadcast_shapes(a.shape[2:], b.shape[2:]), dtype=complex)
    tmp = np.empty(out.shape[2:], dtype=complex)
    for i in range(2):
        for j in range(2):
            np.multiply(a[i, 0], b[0, j], out=out[i, j])
            np.multiply(a[i, 1], b[1, j], out=tmp)
            out[i, j] += tmp
    return out


def _flipped_mm(x: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(M x M) b of stacked 2x2 matrices (2, 2, N), M = diag(1, −1): the products of
    :func:`_mm` with x's off-diagonal entries negated, as differences (the same numbers:
    (−p) q = −(p q) and r + (−s) = r − s exactly), without forming M x M."""
    out = np.empty(b.shape, dtype=complex)
    tmp = np.empty(b.shape[2:], dtype=complex)
    for j in range(2):
        np.multiply(x[0, 0], b[0, j], out=out[0, j])
        np.multiply(x[0, 1], b[1, j], out=tmp)
        out[0, j] -= tmp
        np.multiply(x[1, 1], b[1, j], out=out[1, j])
        np.multiply(x[1, 0], b[0, j], out=tmp)
        out[1, j] -= tmp
    return out


def _inv(a: np.ndarray) -> np.ndarray:
    """Inverses of stacked 2x2 matrices (2, 2, N) (adjugate over the determinant)."""
    r = np.multiply(a[0, 0], a[1, 1])
    r -= a[0, 1] * a[1, 0]
    np.divide(1.0, r, out=r)
    out = np.empty(a.shape, dtype=complex)
    np.multiply(a[1, 1], r, out=out[0, 0])
    np.multiply(a[0, 1], r, out=out[0, 1])
    np.negative(out[0, 1], out=out[0, 1])
    np.multiply(a[1, 0], r, out=out[1, 0])
    np.negative(out[1, 0], out=out[1, 0])
    np.multiply(a[0, 0], r, out=out[1, 1])
    return out


def _expm(a: np.ndarray, lam_t: np.ndarray, t: np.ndarray) -> np.ndarray:
    """exp(t a) of the sagittal block a (2, 2, N) of an isotropic layer's A_d with the SV (and
    SH) root ``lam_t``: e^{t b} [I + t φ₁((c − b) t) (a − b I)], b the root of the slower
    decay, φ₁(z) = (e^z − 1)/z (module docstring)."""
    return two_root_expm(a, a[0, 0] + a[1, 1] - lam_t, lam_t, t)


def _block(a: np.ndarray) -> np.ndarray:
    """The {x, z} block (2, 2, N) of stacked 3x3 matrices (3, 3, N) (a view)."""
    return a[0::2, 0::2]


def _factors(layer: tuple, eta_h: np.ndarray, Y: np.ndarray):
    """(I + T, D_d + D_u T) of one isotropic mirror-plane layer (``layer``: the {x, z} blocks
    (2, 2, N) of its D_d, D_u and A_d and its SH root A_yy (N,)) over the block impedance Y
    (2, 2, N): T = X_u ρ X_d, ρ = (D_u − Y)⁻¹ (Y − D_d)."""
    D_d, D_u, A_d, lam_t = layer
    X_d = _expm(A_d, lam_t, eta_h)
    rho = _mm(_inv(D_u - Y), Y - D_d)
    T = _flipped_mm(X_d, _mm(rho, X_d))
    Q = _mm(D_u, T)
    Q += D_d
    # P = I + T in place (T is not needed after Q).
    T[0, 0] += 1
    T[1, 1] += 1
    return T, Q


def sagittal_h33(layers: list, eta_h: list, substrate: np.ndarray) -> np.ndarray:
    """H_33 (N,) of isotropic mirror-plane layers (``layers``: their waves (4, 3, 3, N), top
    first; ``eta_h``: their η h, (N,) each) over ``substrate`` (its impedance Y (3, 3, N)),
    at θ = 0 of an axisymmetric stack, from the recursion on the {x, z} block (module
    docstring); non-finite where the stack is singular."""
    blocks = [(_block(w[0]), _block(w[1]), _block(w[2]), w[2, 1, 1]) for w in layers]
    return sagittal_h33_blocks(blocks, eta_h, _block(substrate))


def sagittal_h33_blocks(layers: list, eta_h: list, Y: np.ndarray) -> np.ndarray:
    """:func:`sagittal_h33` from the blocks alone: ``layers`` [(D_d, D_u, A_d, A_yy)], top
    first, the {x, z} blocks (2, 2, N) of each layer's impedances and exponent and its SH root
    (N,); ``Y`` (2, 2, N) the substrate's block (the same arithmetic, so the same numbers)."""
    with np.errstate(all="ignore"):
        for layer, eh in zip(layers[:0:-1], eta_h[:0:-1], strict=True):
            P, Q = _factors(layer, eh, Y)
            Y = _mm(Q, _inv(P))
        P, Q = _factors(layers[0], eta_h[0], Y)
        # (P Q⁻¹)_zz: row z of P times column z of Q⁻¹ = (−Q_xz, Q_xx)/det Q.
        det = Q[0, 0] * Q[1, 1] - Q[0, 1] * Q[1, 0]
        return (P[1, 1] * Q[0, 0] - P[1, 0] * Q[0, 1]) / det


def sagittal_reference(reference: np.ndarray) -> np.ndarray:
    """(R⁻¹)_zz (N,) of the reference half-space's impedance R (3, 3, N) at θ = 0 of an
    axisymmetric stack: its {x, z} block's R_xx/det."""
    return sagittal_reference_block(_block(reference))


def sagittal_reference_block(R: np.ndarray) -> np.ndarray:
    """:func:`sagittal_reference` from R's {x, z} block (2, 2, N) alone."""
    with np.errstate(all="ignore"):
        return R[0, 0] / (R[0, 0] * R[1, 1] - R[0, 1] * R[1, 0])
