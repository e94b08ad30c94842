"""Normal surface response of an anisotropic elastic half-space, static and time-harmonic.

Paper 1, Eqs. 10-20, in the robust form of ``physics.md``: for a surface wave vector
ξ = η (cos θ, sin θ) the displacement field decaying into the solid z > 0 is
``u(z) = exp(i η Z z) u(0)``, where the 3x3 matrix Z (wave numbers p/η of the partial waves)
is the *solvent* of the quadratic eigenproblem of the Christoffel matrix

    W Z² + (R + Rᵀ) Z + Q − s I = 0,     Q_ik = c_iakb n_a n_b,  R_ik = c_iak3 n_a,  W_ik = c_i3k3,

with all its eigenvalues in the upper half plane (Im p > 0: decaying; with loss this is also the
outgoing choice), c = C/C44 and s = ρω²/(C44 η²) = 1/κ². The surface traction of that field is
σ_i3 = i η C44 (Rᵀ + W Z) u(0), so the surface compliance is H = −i (Rᵀ + W Z)⁻¹ and the normal
displacement under a unit normal point force (pressing into the solid, σ_33 = −1) is
Ĝ = −H_33/(C44 η). This is the 6x6 Stroh formulation with the projector on the decaying subspace,
reduced to 3x3 blocks.

The solvent is computed by cyclic reduction (a quadratically convergent doubling algorithm) after
the Möbius map w = (p − iβ)/(p + iβ), which sends the decaying half plane to the unit disk. It
never forms eigenvectors, so it is exact and continuous at degenerate points: the isotropic solid
(a triple root p = i in statics, a double shear root in dynamics) is not a special case, and a
slightly anisotropic solid (A = 1 ± 1e-9) gives the isotropic answer to ~1e-9 (a test).

Accuracy: the doubling stops when its last update is below 1e-10 (relative); what remains is
then ~1e-16 (convergence is quadratic), and the kernels agree with closed forms and with a
brute-force eigen-solution to ~1e-13 or better (tests). Two corners lose digits: nearly
incompressible solids (relative error ~1e-16 (C11/C44)³: 2e-14 at ν = 0.49, 2e-11 at ν = 0.499)
and real κ ≪ 1 with a tiny loss (2e-9 at κ = 1e-4, Q⁻¹ = 1e-8: partial waves within 1e-8 of
propagating). Cost: ~5 µs per (κ, θ) point (``benchmarks/bench_halfspace.py``).

Sign conventions: time factor e^{iωt}; the solid fills z >= 0 with z the inward normal; loss
enters as complex constants C (1 + i Q⁻¹) (:meth:`Material.with_loss`). The normal-normal
response is even in ξ (reciprocity), so the sign of the Fourier exponent does not matter here.
"""

from __future__ import annotations

import numpy as np

from .materials import Material, voigt_to_tensor

__all__ = [
    "dynamic_kernel",
    "isotropic_dynamic_kernel",
    "shear_reference",
    "static_kernel",
    "surface_compliance",
]

# Cyclic reduction stops after an update of its accumulated matrix below this (relative): the
# convergence is quadratic, so what is left is ~1e-20.
_CR_TOL = 1e-10
# Maximum number of doubling steps; 2**60 halvings resolve roots within 1e-16 of |w| = 1.
_CR_MAXITER = 60
# Relative residual of the solvent above which another Möbius parameter β is tried, and the
# factors tried (irrational ratios, so that no two give the same angles of the images).
_RESID_TOL = 1e-12
_BETA_RETRY = (0.7, 1.618, 0.45, 2.3)
# Points per chunk: small enough for the working set (~20 stacks of 3x3 complex) to stay in cache.
_CHUNK = 2048


def shear_reference(m: Material) -> float:
    """Re C44 of the surface frame (Voigt ``C[3, 3].real``), Pa.

    The stiffness that normalises the dimensionless kernel g and the shear wave number
    k_s = ω √(ρ/C44) (paper 1, Eq. 21). For a cubic (001) face it is the crystal's C44.
    """
    c44 = float(np.real(np.asarray(m.C)[3, 3]))
    if not c44 > 0:
        raise ValueError(f"surface-frame C44 must be positive, got {c44!r} Pa")
    return c44


def _scaled_tensor(m: Material) -> np.ndarray:
    """c_ijkl / Re C44 as a complex 3x3x3x3 array."""
    return voigt_to_tensor(np.asarray(m.C, dtype=complex)) / shear_reference(m)


def _blocks(c: np.ndarray, theta: np.ndarray):
    """Q, R, W of the directions n = (cos θ, sin θ), stacked as (3, 3, N) for flat ``theta``."""
    n1 = np.cos(theta)
    n2 = np.sin(theta)
    c11, c12, c21, c22 = c[:, 0, :, 0], c[:, 0, :, 1], c[:, 1, :, 0], c[:, 1, :, 1]
    Q = c11[..., None] * n1**2 + (c12 + c21)[..., None] * (n1 * n2) + c22[..., None] * n2**2
    R = c[:, 0, :, 2, None] * n1 + c[:, 1, :, 2, None] * n2
    W = np.broadcast_to(c[:, 2, :, 2, None], Q.shape)
    return Q, R, W


# Stacks of 3x3 matrices are stored as (3, 3, N): every entry is a contiguous vector, so the
# elementwise formulas below run at memory speed (a batched LAPACK call per 3x3 is much slower).
def _mm(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Product of stacked 3x3 matrices, (3, 3, N) @ (3, 3, N)."""
    return np.einsum("ijn,jkn->ikn", a, b)


def _tr(a: np.ndarray) -> np.ndarray:
    return a.transpose(1, 0, 2)


def _inv3(a: np.ndarray) -> np.ndarray:
    """Inverse of stacked 3x3 matrices (3, 3, N) by the adjugate formula."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    c00 = a11 * a22 - a12 * a21
    c01 = a12 * a20 - a10 * a22
    c02 = a10 * a21 - a11 * a20
    r = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02)
    out = np.empty_like(a)
    out[0, 0] = c00 * r
    out[1, 0] = c01 * r
    out[2, 0] = c02 * r
    out[0, 1] = (a02 * a21 - a01 * a22) * r
    out[1, 1] = (a00 * a22 - a02 * a20) * r
    out[2, 1] = (a01 * a20 - a00 * a21) * r
    out[0, 2] = (a01 * a12 - a02 * a11) * r
    out[1, 2] = (a02 * a10 - a00 * a12) * r
    out[2, 2] = (a00 * a11 - a01 * a10) * r
    return out


def _decaying_solvent(Q, R, W, s, beta):
    """The Möbius image G (3, 3, N) of the decaying solvent, a boolean array (converged), and
    the relative residual of G.

    With p = iβ (1 + w)/(1 − w), the quadratic pencil W p² + (R + Rᵀ) p + Q − diag(s) becomes
    A0 + A1 w + A2 w² and the decaying roots lie inside the unit disk; cyclic reduction (Bini &
    Meini) returns the minimal solvent G of A0 + A1 G + A2 G² = 0. ``s`` (3, N) is the diagonal
    of the (balanced) inertia term. Also returns the relative residual (backward error).
    """
    Qs = Q.astype(complex)
    Qs[[0, 1, 2], [0, 1, 2]] -= s
    bW = beta**2 * W
    ibK = 1j * beta * (R + _tr(R))
    A0 = Qs - bW + ibK
    a1 = -2.0 * (bW + Qs)
    a2 = Qs - bW - ibK
    A1h = a1.copy()
    a0, a1h = A0, A1h
    a1_0, a2_0 = a1, a2
    n = A0.shape[-1]
    done = np.zeros(n, dtype=bool)
    active = np.arange(n)
    for _ in range(_CR_MAXITER):
        k = _inv3(a1)
        ka0 = _mm(k, a0)
        ka2 = _mm(k, a2)
        a2ka0 = _mm(a2, ka0)
        a0ka2 = _mm(a0, ka2)
        a1h = a1h - a2ka0
        a1 = a1 - a0ka2 - a2ka0
        a0 = -_mm(a0, ka0)
        a2 = -_mm(a2, ka2)
        # Quadratic convergence: after an update of relative size τ the rest is ~τ².
        upd = np.max(np.abs(a2ka0), axis=(0, 1))
        scale = np.max(np.abs(a1h), axis=(0, 1))
        conv = (upd <= _CR_TOL * scale) & np.isfinite(scale)  # NaN: not converged
        if np.any(conv):
            A1h[:, :, active[conv]] = a1h[:, :, conv]
            done[active[conv]] = True
            keep = ~conv
            active = active[keep]
            a0, a1, a2, a1h = a0[:, :, keep], a1[:, :, keep], a2[:, :, keep], a1h[:, :, keep]
        if active.size == 0:
            break
    G = -_mm(_inv3(A1h), A0)
    # Backward error of the solvent: the relative residual of A0 + A1 G + A2 G² = 0.
    res = A0 + _mm(a1_0, G) + _mm(a2_0, _mm(G, G))
    g = _maxabs(G)
    resid = _maxabs(res) / (_maxabs(A0) + _maxabs(a1_0) * g + _maxabs(a2_0) * g**2)
    resid[~np.isfinite(resid)] = np.inf
    return G, done, resid


def _maxabs(a: np.ndarray) -> np.ndarray:
    return np.max(np.abs(a), axis=(0, 1))


def surface_compliance(c: np.ndarray, theta, s) -> np.ndarray:
    """Dimensionless surface compliance H (shape ``broadcast(theta, s).shape + (3, 3)``).

    Parameters
    ----------
    c : ndarray, shape (3, 3, 3, 3)
        Stiffness tensor in the surface frame divided by the reference C44 (complex allowed).
    theta : array_like
        Direction of the surface wave vector, rad.
    s : array_like
        ρω²/(C44 η²) = 1/κ² (0 in statics; complex allowed).

    Returns
    -------
    ndarray
        H with u(0) = H σ_i3/(C44 η) for the decaying field (paper 1, Eqs. 12, 19).
    """
    theta, s = np.broadcast_arrays(np.asarray(theta, dtype=float), np.asarray(s, dtype=complex))
    shape = theta.shape
    th = theta.ravel()
    sv = s.ravel()
    H = np.empty((3, 3, th.size), dtype=complex)
    # Work in cache-sized chunks: the algorithm is elementwise and memory-bound.
    for i in range(0, th.size, _CHUNK):
        H[:, :, i : i + _CHUNK] = _compliance_chunk(c, th[i : i + _CHUNK], sv[i : i + _CHUNK])
    return np.moveaxis(H, -1, 0).reshape((*shape, 3, 3))


def _compliance_chunk(c: np.ndarray, th: np.ndarray, sv: np.ndarray) -> np.ndarray:
    """H (3, 3, N) for flat arrays of directions ``th`` and inertia terms ``sv``."""
    Q, R, W = _blocks(c, th)
    # Balance the pencil by the congruence D (.) D, D = diag(W)^(-1/2): W gets a unit diagonal.
    # Then Z = D Z~ D^-1, the identity in Q − sI becomes D², and H = D H~ D.
    d = 1.0 / np.sqrt(np.real(np.diagonal(c[:, 2, :, 2])))
    DD = (d[:, None] * d[None, :])[..., None]
    Q, R, W = Q * DD, R * DD, W * DD
    # Scale of the vertical wave numbers: |p| ~ 1 in statics, ~ sqrt(|s|) at high frequency.
    beta = np.sqrt(1.0 + np.abs(sv))
    s3 = d[:, None] ** 2 * sv
    G, ok, resid = _decaying_solvent(Q, R, W, s3, beta)
    # Cyclic reduction loses accuracy (or breaks down) where the squared Möbius images of a
    # decaying and a growing root nearly coincide; another β moves those points elsewhere.
    for factor in _BETA_RETRY:
        idx = np.flatnonzero(~ok | (resid > _RESID_TOL))
        if idx.size == 0:
            break
        G2, ok2, res2 = _decaying_solvent(
            Q[..., idx], R[..., idx], W[..., idx], s3[:, idx], factor * beta[idx]
        )
        better = ok2 & (~ok[idx] | (res2 < resid[idx]))
        j = idx[better]
        G[..., j] = G2[..., better]
        beta[j] *= factor
        ok[j] = True
        resid[j] = res2[better]
    if not np.all(ok):
        bad = np.flatnonzero(~ok)[0]
        raise ValueError(
            "no decaying/outgoing split of the partial waves at theta="
            f"{th[bad]:.6g} rad, 1/kappa^2={sv[bad]:.6g}: a lossless solid at a real wave number "
            "below a bulk-wave cutoff (propagating waves). Add loss (Material.with_loss) or pass "
            "kappa with a positive imaginary part."
        )
    eye = np.eye(3)[..., None]
    # Z = iβ (I + G)(I − G)⁻¹, so Rᵀ + W Z = [Rᵀ (I − G) + iβ W (I + G)] (I − G)⁻¹.
    M = _mm(_tr(R), eye - G) + 1j * beta * _mm(W, eye + G)
    return -1j * _mm(eye - G, _inv3(M)) * DD


def static_kernel(m: Material, theta) -> np.ndarray:
    """Static surface Green's function Ĝ(θ), 1/Pa (paper 1, Eqs. 1-4).

    The normal surface displacement under a unit normal point force (positive into the solid)
    is Ĝ(θ)/η in the wave-vector domain, ξ = η (cos θ, sin θ) in the surface frame x, y. ``m.C``
    is taken as the stiffness in the surface frame (z = inward normal; use
    :meth:`Material.rotated` for a face (hkl)). Isotropic: Ĝ = 2/E* = 2 (1 − ν²)/E.

    Returns a real array for a lossless material, complex for a lossy one.
    """
    c = _scaled_tensor(m)
    H = surface_compliance(c, theta, 0.0)
    g = -H[..., 2, 2] / shear_reference(m)
    return g if m.is_lossy else g.real


def dynamic_kernel(m: Material, kappa, theta) -> np.ndarray:
    """Dimensionless dynamic kernel g(κ, θ) = C44 η Ĝ_dyn(η, θ; ω) (paper 1, Eqs. 10-21).

    Parameters
    ----------
    m : Material
        Stiffness in the surface frame (complex for loss); density is not needed: g depends on
        ``m.C / C44`` only, with C44 = :func:`shear_reference` (undamped).
    kappa : array_like
        κ = η/k_s, wave number over the shear wave number k_s = ω √(ρ/C44). Real κ > 0; for a
        lossless material also complex κ with Im κ > 0 (see Notes).
    theta : array_like
        Direction of the surface wave vector, rad; broadcasts against ``kappa``.

    Returns
    -------
    ndarray, complex
        g, with g -> C44 Ĝ(θ) as κ -> ∞ (statics).

    Notes
    -----
    Root selection: the partial waves decaying into the solid (Im p > 0); with loss this selects
    the outgoing waves. For a lossless material and complex κ in the upper half plane the same
    rule gives the analytic continuation of g from large real κ (a real vertical wave number
    would need real 1/κ², i.e. real κ), so contours moved into Im κ > 0 are supported; its limit
    Im κ -> 0+ is the outgoing (limiting-absorption) kernel. A lossless material at a real κ
    below a bulk-wave cutoff (propagating partial waves) raises ValueError: add loss or move κ
    off the axis. Complex κ with a lossy material is refused (there the decaying rule is not
    the analytic continuation everywhere).
    """
    kappa = np.asarray(kappa)
    if np.iscomplexobj(kappa) and np.any(kappa.imag != 0):
        if m.is_lossy:
            raise ValueError(
                "complex kappa is supported for lossless materials only; "
                "for a lossy material use real kappa > 0"
            )
        if np.any(kappa.imag < 0):
            raise ValueError("complex kappa must have Im(kappa) >= 0 (upper half plane)")
        bad = (kappa.imag == 0) & ~(kappa.real > 0)
    else:
        kappa = kappa.real if np.iscomplexobj(kappa) else kappa.astype(float)
        bad = ~(kappa > 0)
    if np.any(bad) or not np.all(np.isfinite(kappa)):
        raise ValueError("kappa (wave number / shear wave number) must be finite and > 0")
    c = _scaled_tensor(m)
    s = 1.0 / np.asarray(kappa, dtype=complex) ** 2
    H = surface_compliance(c, theta, s)
    return -H[..., 2, 2]


def isotropic_dynamic_kernel(kappa, c11_over_c44, loss: float = 0.0) -> np.ndarray:
    """Closed-form dynamic kernel of an isotropic half-space (Lamb; physics.md, paper 1).

    g(κ) = −Ω² v_p / (c̃44² F),  Ω = 1/κ,  c̃11 = (C11/C44)(1 + i loss),  c̃44 = 1 + i loss,
    v_p = √(1 − Ω²/c̃11),  v_s = √(1 − Ω²/c̃44)  (Re v >= 0),  F = (2 − Ω²/c̃44)² − 4 v_p v_s.

    F is the Rayleigh function (its zero is the Rayleigh pole). Lossless: g -> 1 − ν as κ -> ∞.
    The principal square root gives, at ``loss=0``, the outgoing limit on the real axis and the
    decaying branch for Im κ > 0. An independent reference for :func:`dynamic_kernel`.
    """
    kappa = np.asarray(kappa, dtype=complex)
    ratio = float(c11_over_c44)
    if not ratio > 4.0 / 3.0:
        raise ValueError(f"c11_over_c44 must exceed 4/3 (positive bulk modulus), got {ratio!r}")
    q = float(loss)
    if not (np.isfinite(q) and q >= 0):
        raise ValueError(f"loss (Q^-1) must be finite and >= 0, got {loss!r}")
    c44 = 1 + 1j * q
    c11 = ratio * c44
    om2 = 1.0 / kappa**2
    vp = np.sqrt(1 - om2 / c11)
    vs = np.sqrt(1 - om2 / c44)
    x = om2 / c44
    F = (2 - x) ** 2 - 4 * vp * vs
    # At small x, F ~ x is a difference of O(1) terms; its rationalised form has no cancellation
    # (the denominator (2 - x)^2 + 4 v_p v_s is ~8 there).
    a = c44 / c11
    small = np.abs(x) < 0.1
    F_rat = x * (-16 * (1 - a) + (24 - 16 * a) * x - 8 * x**2 + x**3) / ((2 - x) ** 2 + 4 * vp * vs)
    F = np.where(small, F_rat, F)
    return -om2 * vp / (c44**2 * F)
