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

A lossless solid at a real κ below a bulk-wave cutoff has real vertical wave numbers: there is
no decaying/growing split and the doubling cannot converge. Those points (only those) take the
6x6 Stroh eigen-decomposition of physics.md, keeping the partial waves that carry energy into
the solid (the limit Im κ -> 0+, limiting absorption; see :func:`_outgoing_compliance`).

Accuracy: the doubling stops when its last update is below 1e-10 (relative); what remains is
then ~1e-16 (convergence is quadratic), and the kernels agree with closed forms and with a
brute-force eigen-solution to ~1e-13 or better (tests). Two corners lose digits: nearly
incompressible solids (relative error ~1e-16 (C11/C44)³: 2e-14 at ν = 0.49, 2e-11 at ν = 0.499)
and real κ ≪ 1 with a tiny loss (2e-9 at κ = 1e-4, Q⁻¹ = 1e-8: partial waves within 1e-8 of
propagating).

Cost (``benchmarks/bench_halfspace.py``): the number of doubling steps is set by how close the
mapped roots come to the unit circle (~5 in the evanescent range, ~10 for barely damped
propagating waves), not by β. When the surface is a mirror plane of the solid (cubic (001),
(011), hexagonal basal and prism faces, orthotropic principal cuts) the pencil has the block
structure of :func:`_cyclic_reduction_mirror` and a step costs a third of a general one:
~1.5-2 µs per (κ, θ) point, against ~4 µs on other faces (e.g. cubic (111)); ~40 µs on the
eigen-decomposition path.

Sign conventions: time factor e^{iωt}; the solid fills z >= 0 with z the inward normal; loss
enters as complex constants C (1 + i Q⁻¹) (:meth:`Material.with_loss`). The normal-normal
response is even in ξ (reciprocity), so the sign of the Fourier exponent does not matter here.
"""

from __future__ import annotations

import numpy as np

from .materials import Material, voigt_to_tensor
from .validation import nonnegative

__all__ = [
    "dynamic_kernel",
    "isotropic_dynamic_kernel",
    "shear_reference",
    "static_kernel",
    "surface_compliance",
]

# Cyclic reduction stops after an update of its accumulated matrix below this (relative); the
# convergence is quadratic, so what is left is far smaller (stopping at 1e-15 instead moves g
# by < 1e-13: a test).
_CR_TOL = 1e-10
# Maximum number of doubling steps: 2**40 squarings resolve roots within ~1e-11 of |w| = 1.
_CR_MAXITER = 40
# A lossless point at real κ whose update is still above _STALL_TOL after _STALL_ITER steps has
# (nearly) real vertical wave numbers; it goes to the eigen-decomposition instead.
_STALL_ITER = 12
_STALL_TOL = 1e-3
# Relative residual of the solvent above which another Möbius parameter β is tried, and the
# factors tried (irrational ratios, so that no two give the same angles of the images).
_RESID_TOL = 1e-12
_BETA_RETRY = (0.7, 1.618, 0.45, 2.3)
# Eigenvalues of the Stroh matrix closer than this (relative) to the imaginary axis are treated as
# real vertical wave numbers (propagating waves of a lossless solid).
_REAL_ROOT_TOL = 1e-9
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
def _mm(a: np.ndarray, b: np.ndarray, out=None, tmp=None) -> np.ndarray:
    """Product of stacked 3x3 matrices, (3, 3, N) @ (3, 3, N), optionally into ``out`` (with a
    work array ``tmp`` of the same shape; neither may overlap ``a`` or ``b``)."""
    if out is None:
        return a[:, 0, None] * b[0] + a[:, 1, None] * b[1] + a[:, 2, None] * b[2]
    np.multiply(a[:, 0, None], b[0], out=out)
    out += np.multiply(a[:, 1, None], b[1], out=tmp)
    out += np.multiply(a[:, 2, None], b[2], out=tmp)
    return out


def _tr(a: np.ndarray) -> np.ndarray:
    return a.transpose(1, 0, 2)


def _inv3(a: np.ndarray, out=None) -> np.ndarray:
    """Inverse of stacked 3x3 matrices (3, 3, N) by the adjugate formula (into ``out``)."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    c00 = a11 * a22 - a12 * a21
    c01 = a12 * a20 - a10 * a22
    c02 = a10 * a21 - a11 * a20
    r = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02)
    if out is None:
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


def _decaying_solvent(Q, R, W, s, beta, may_stall=None, mirror=False):
    """The Möbius image G (3, 3, N) of the decaying solvent, a boolean array (converged), and
    the relative residual of G.

    With p = iβ (1 + w)/(1 − w), the quadratic pencil W p² + (R + Rᵀ) p + Q − diag(s) becomes
    A0 + A1 w + A2 w² and the decaying roots lie inside the unit disk; cyclic reduction (Bini &
    Meini) returns the minimal solvent G of A0 + A1 G + A2 G² = 0. ``s`` (3, N) is the diagonal
    of the (balanced) inertia term. Also returns the relative residual (backward error).
    Points flagged in ``may_stall`` (lossless, real κ) that have not come near convergence after
    ``_STALL_ITER`` steps are given up (not converged): their roots sit on the unit circle.
    """
    Qs = Q.astype(complex)
    Qs[[0, 1, 2], [0, 1, 2]] -= s
    bW = beta**2 * W
    ibK = 1j * beta * (R + _tr(R))
    A0 = Qs - bW + ibK
    a1 = -2.0 * (bW + Qs)
    a2 = Qs - bW - ibK
    if mirror:
        A1h, done = _cyclic_reduction_mirror(A0, a1, may_stall)
    else:
        A1h, done = _cyclic_reduction(A0, a1, a2, may_stall)
    G = -_mm(_inv3(A1h), A0)
    # Backward error of the solvent: the relative residual of A0 + A1 G + A2 G² = 0.
    res = A0 + _mm(a1, G) + _mm(a2, _mm(G, G))
    g = _maxabs(G)
    resid = _maxabs(res) / (_maxabs(A0) + _maxabs(a1) * g + _maxabs(a2) * g**2)
    resid[~np.isfinite(resid)] = np.inf
    return G, done, resid


def _cyclic_reduction(A0, a1, a2, may_stall):
    """Cyclic reduction for the general pencil: the limit Â1 (3, 3, N) and a converged flag."""
    A1h = a1.copy()
    n = A0.shape[-1]
    # Work arrays, reused in place: fresh (3, 3, N) temporaries in every step cost more than
    # the arithmetic (allocation and cache misses).
    a0, a1, a2, a1h = A0.copy(), a1.copy(), a2.copy(), A1h.copy()
    k, ka0, ka2, a0ka2, nxt, tmp = (np.empty_like(A0) for _ in range(6))
    re = np.empty(A0.shape, dtype=float)
    done = np.zeros(n, dtype=bool)
    active = np.arange(n)
    for it in range(_CR_MAXITER):
        _inv3(a1, out=k)
        _mm(k, a0, out=ka0, tmp=tmp)
        _mm(k, a2, out=ka2, tmp=tmp)
        # A0, A1, A2 are complex symmetric (major symmetry of C) and cyclic reduction keeps
        # them so: A2 K A0 = (A0 K A2)ᵀ saves one product.
        _mm(a0, ka2, out=a0ka2, tmp=tmp)
        a2ka0 = _tr(a0ka2)
        a1h -= a2ka0
        a1 -= a0ka2
        a1 -= a2ka0
        # (−A0 K A0 and −A2 K A2 by the recursion; both signs are dropped, as they cancel in
        # every later update: A0 and A2 enter them in pairs.)
        a0, nxt = _mm(a0, ka0, out=nxt, tmp=tmp), a0
        a2, nxt = _mm(a2, ka2, out=nxt, tmp=tmp), a2
        # Quadratic convergence: after an update of relative size τ the rest is ~τ².
        upd = np.abs(a0ka2, out=re).max(axis=(0, 1))
        scale = np.abs(a1h, out=re).max(axis=(0, 1))
        conv = (upd <= _CR_TOL * scale) & np.isfinite(scale)  # NaN: not converged
        drop = conv.copy()
        if may_stall is not None and it + 1 == _STALL_ITER:
            drop |= may_stall[active] & ~(upd <= _STALL_TOL * scale)
        if np.any(drop):
            A1h[:, :, active[conv]] = a1h[:, :, conv]
            done[active[conv]] = True
            keep = ~drop
            active = active[keep]
            a0, a1, a2, a1h = a0[:, :, keep], a1[:, :, keep], a2[:, :, keep], a1h[:, :, keep]
            k, ka0, ka2, a0ka2, nxt, tmp = (np.empty_like(a0) for _ in range(6))
            re = np.empty(a0.shape, dtype=float)
        if active.size == 0:
            break
    return A1h, done


def _cyclic_reduction_mirror(A0, a1, may_stall):
    """Cyclic reduction for a solid with a mirror plane z -> -z (see :func:`_has_mirror`).

    Then A2 = D A0 D with D = diag(1, 1, −1), A1 is block diagonal (2x2 ⊕ 1x1), and cyclic
    reduction keeps both properties, so each step needs only the blocks P (2x2), q (2), r of
    A0 = [[P, q], [qᵀ, r]], the blocks S, t of A1 and a 2x2 inverse: a third of the work of
    the general step, with the same iterates (in exact arithmetic) and the same stopping rule.
    The sign of A0 is dropped (it enters every update squared).
    """
    n = A0.shape[-1]
    # Rows: p11 p12 p22 q1 q2 r | s11 s12 s22 t | h11 h12 h22 h33 h13 h23 (Â1, upper triangle;
    # its (3, α) entries are −(α, 3)).
    st = np.empty((16, n), dtype=complex)
    st[0], st[1], st[2] = A0[0, 0], A0[0, 1], A0[1, 1]
    st[3], st[4], st[5] = A0[0, 2], A0[1, 2], A0[2, 2]
    st[6], st[7], st[8], st[9] = a1[0, 0], a1[0, 1], a1[1, 1], a1[2, 2]
    st[10:14] = st[6:10]
    st[14:16] = 0.0
    out = np.empty((16, n), dtype=complex)
    h = st[10:16].copy()
    done = np.zeros(n, dtype=bool)
    active = np.arange(n)
    for it in range(_CR_MAXITER):
        p11, p12, p22, q1, q2, r, s11, s12, s22, t = st[:10]
        ide = 1.0 / (s11 * s22 - s12 * s12)
        t11, t12, t22 = s22 * ide, -s12 * ide, s11 * ide
        u = 1.0 / t
        pt11 = p11 * t11 + p12 * t12
        pt12 = p11 * t12 + p12 * t22
        pt21 = p12 * t11 + p22 * t12
        pt22 = p12 * t12 + p22 * t22
        tq1 = t11 * q1 + t12 * q2
        tq2 = t12 * q1 + t22 * q2
        uq1, uq2, ur = u * q1, u * q2, u * r
        # P T P, u q qᵀ, P T q, u r q, qᵀ T q, u r²: the blocks of A0 K A0 and A0 K A2.
        e11, e12, e22 = pt11 * p11 + pt12 * p12, pt11 * p12 + pt12 * p22, pt21 * p12 + pt22 * p22
        f11, f12, f22 = uq1 * q1, uq1 * q2, uq2 * q2
        v11, v12 = pt11 * q1 + pt12 * q2, pt21 * q1 + pt22 * q2
        v21, v22 = ur * q1, ur * q2
        w1, w2 = q1 * tq1 + q2 * tq2, ur * r
        upd = np.empty((6, active.size), dtype=complex)
        # A2 K A0 = (A0 K A2)ᵀ: blocks P T P − u q qᵀ, ±(P T q − u r q), u r² − qᵀ T q.
        np.subtract(e11, f11, out=upd[0])
        np.subtract(e12, f12, out=upd[1])
        np.subtract(e22, f22, out=upd[2])
        np.subtract(w2, w1, out=upd[3])
        np.subtract(v11, v21, out=upd[4])
        np.subtract(v12, v22, out=upd[5])
        nxt = out[:, : active.size]
        np.add(e11, f11, out=nxt[0])
        np.add(e12, f12, out=nxt[1])
        np.add(e22, f22, out=nxt[2])
        np.add(v11, v21, out=nxt[3])
        np.add(v12, v22, out=nxt[4])
        np.add(w1, w2, out=nxt[5])
        nxt[6:10] = st[6:10] - 2.0 * upd[:4]
        nxt[10:16] = st[10:16] - upd
        st, out = nxt, st
        # Quadratic convergence: after an update of relative size τ the rest is ~τ².
        ma = np.abs(upd).max(axis=0)
        scale = np.abs(st[10:16]).max(axis=0)
        conv = (ma <= _CR_TOL * scale) & np.isfinite(scale)  # NaN: not converged
        drop = conv.copy()
        if may_stall is not None and it + 1 == _STALL_ITER:
            drop |= may_stall[active] & ~(ma <= _STALL_TOL * scale)
        if np.any(drop):
            fin = active[conv]
            h[:, fin] = st[10:16, conv]
            done[fin] = True
            keep = ~drop
            active = active[keep]
            st = np.ascontiguousarray(st[:, keep])
            out = np.empty_like(st)
        if active.size == 0:
            break
    h11, h12, h22, h33, h13, h23 = h
    A1h = np.array([[h11, h12, h13], [h12, h22, h23], [-h13, -h23, h33]])
    return A1h, done


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
    H = _compliance(c, theta, s, normal_only=False)
    return np.ascontiguousarray(np.moveaxis(H, (0, 1), (-2, -1)))


def _compliance(c: np.ndarray, theta, s, normal_only: bool) -> np.ndarray:
    """H as (3, 3, *shape), or only H_33 (shape) if ``normal_only``."""
    theta, s = np.broadcast_arrays(np.asarray(theta, dtype=float), np.asarray(s, dtype=complex))
    shape = theta.shape
    th = theta.ravel()
    sv = s.ravel()
    mirror = _has_mirror(c)
    H = np.empty((th.size,) if normal_only else (3, 3, th.size), dtype=complex)
    # Work in cache-sized chunks: the algorithm is elementwise and memory-bound.
    for i in range(0, th.size, _CHUNK):
        sl = slice(i, i + _CHUNK)
        H[..., sl] = _compliance_chunk(c, th[sl], sv[sl], mirror, normal_only)
    return H.reshape(H.shape[:-1] + shape)


def _has_mirror(c: np.ndarray) -> bool:
    """True if the surface plane is a mirror plane of the solid (z -> −z symmetry).

    Then every c_ijkl with an odd number of indices equal to z vanishes (cubic (001) and
    (011), hexagonal basal and prism faces, orthotropic principal cuts, ...). Entries at the
    round-off level of a rotated tensor count as zero.
    """
    odd = (np.sum(np.indices(c.shape) == 2, axis=0) % 2).astype(bool)
    return bool(np.max(np.abs(c[odd]), initial=0.0) <= 1e-14 * np.max(np.abs(c)))


def _compliance_chunk(c, th, sv, mirror: bool, normal_only: bool) -> np.ndarray:
    """H (3, 3, N), or H_33 (N), for flat arrays of directions ``th`` and inertia terms ``sv``;
    ``mirror``: the solid has the mirror plane z -> −z (:func:`_has_mirror`)."""
    Q, R, W = _blocks(c, th)
    # Balance the pencil by the congruence D (.) D, D = diag(W)^(-1/2): W gets a unit diagonal.
    # Then Z = D Z~ D^-1, the identity in Q − sI becomes D², and H = D H~ D.
    d = 1.0 / np.sqrt(np.real(np.diagonal(c[:, 2, :, 2])))
    DD = (d[:, None] * d[None, :])[..., None]
    Q, R, W = Q * DD, R * DD, W * DD
    # Scale of the vertical wave numbers: |p| ~ 1 in statics, ~ sqrt(|s|) at high frequency.
    beta = np.sqrt(1.0 + np.abs(sv))
    s3 = d[:, None] ** 2 * sv
    # A lossless solid at a real wave number below a bulk cutoff has real vertical wave numbers
    # (propagating partial waves): no decaying/growing split, so the doubling cannot converge.
    # Those points take the eigen-decomposition with the limiting-absorption choice below.
    lossless = not np.iscomplexobj(c) or not np.any(c.imag)
    real_s = (sv.imag == 0) if lossless else np.zeros(sv.shape, dtype=bool)
    G, ok, resid = _decaying_solvent(Q, R, W, s3, beta, may_stall=real_s, mirror=mirror)
    propagating = ~ok & real_s
    # Cyclic reduction loses accuracy (or breaks down) where the squared Möbius images of a
    # decaying and a growing root nearly coincide; another β moves those points elsewhere.
    for factor in _BETA_RETRY:
        idx = np.flatnonzero((~ok | (resid > _RESID_TOL)) & ~propagating)
        if idx.size == 0:
            break
        G2, ok2, res2 = _decaying_solvent(
            Q[..., idx], R[..., idx], W[..., idx], s3[:, idx], factor * beta[idx], mirror=mirror
        )
        better = ok2 & (~ok[idx] | (res2 < resid[idx]))
        j = idx[better]
        G[..., j] = G2[..., better]
        beta[j] *= factor
        ok[j] = True
        resid[j] = res2[better]
    if not np.all(ok | propagating):
        bad = np.flatnonzero(~(ok | propagating))[0]
        raise ValueError(
            "no decaying/growing split of the partial waves at theta="
            f"{th[bad]:.6g} rad, 1/kappa^2={sv[bad]:.6g} (cyclic reduction did not converge)"
        )
    G[..., propagating] = 0.0
    eye = np.eye(3)[..., None]
    # Z = iβ (I + G)(I − G)⁻¹, so Rᵀ + W Z = [Rᵀ (I − G) + iβ W (I + G)] (I − G)⁻¹.
    M = _mm(_tr(R), eye - G) + 1j * beta * _mm(W, eye + G)
    if normal_only:
        H = -1j * np.sum((eye - G)[2] * _inv3(M)[:, 2], axis=0)
    else:
        H = -1j * _mm(eye - G, _inv3(M))
    if np.any(propagating):
        i = np.flatnonzero(propagating)
        Hp = _outgoing_compliance(
            Q[..., i].real, R[..., i].real, W[..., i].real, s3[:, i].real, th[i], sv[i]
        )
        H[..., i] = Hp[2, 2] if normal_only else Hp
    return H * DD[2, 2] if normal_only else H * DD


def _outgoing_compliance(Q, R, W, s3, th, sv) -> np.ndarray:
    """H (3, 3, N) of a lossless solid with propagating partial waves (real blocks, real s).

    The limit Im κ -> 0+ of the decaying choice (limiting absorption): the 6x6 Stroh matrix
    N = [[−i W⁻¹Rᵀ, W⁻¹], [Q − S − R W⁻¹Rᵀ, −i R W⁻¹]] (physics.md; S = diag(s)) is
    diagonalised; eigenvalues λ = i p with Re λ < 0 are kept, and of the real p those whose
    eigenvalue moves into Re λ < 0 when κ gets a small positive imaginary part. By the
    J-symmetry of N that shift is δλ = i δκ κ⁻³ uᵀu/(uᵀt) for a mode [u; t], so, with u real and
    τ = −i t real (always possible for a real p), a real-p mode is kept when uᵀτ < 0 (its energy
    flows into the solid). Exactly repeated real roots (the isotropic shear pair) are fine: the
    test is made on the real form of each computed eigenvector, which lies in the same
    eigenspace. Costs ~10x the doubling algorithm per point.
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
        raise ValueError(
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
        raise ValueError(
            "a lossless solid exactly at its Rayleigh pole (infinite surface response); add loss "
            "or move kappa off the real axis"
        ) from None
    return np.moveaxis(H, 0, -1)


def static_kernel(m: Material, theta) -> np.ndarray:
    """Static surface Green's function Ĝ(θ), 1/Pa (paper 1, Eqs. 1-4).

    The normal surface displacement under a unit normal point force (positive into the solid)
    is Ĝ(θ)/η in the wave-vector domain, ξ = η (cos θ, sin θ) in the surface frame x, y. ``m.C``
    is taken as the stiffness in the surface frame (z = inward normal; use
    :meth:`Material.rotated` for a face (hkl)). Isotropic: Ĝ = 2/E* = 2 (1 − ν²)/E.

    Returns a real array for a lossless material, complex for a lossy one.
    """
    c = _scaled_tensor(m)
    g = -_compliance(c, theta, 0.0, normal_only=True) / shear_reference(m)
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
    the outgoing waves. For a lossless material at real κ below a bulk-wave cutoff some vertical
    wave numbers are real; then the outgoing ones are kept (the limit Im κ -> 0+, limiting
    absorption), found by an eigen-decomposition that costs ~10x more per point. Exactly at a
    cutoff (a branch point) or at the Rayleigh pole of a lossless solid the value is not
    meaningful. For a lossless material, complex κ with Im κ > 0 is accepted: the decaying
    rule then gives the analytic continuation of g from large real κ (a real vertical wave
    number would need real 1/κ², i.e. real κ), so contours moved into the upper half plane are
    supported. Complex κ with a lossy material is refused (there the decaying rule is not the
    analytic continuation everywhere).

    Accuracy (tests): ~1e-13 against Lamb's closed form and a brute-force eigen-solution;
    see the module docstring for the corners that lose digits.
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
    bad = bad | ~np.isfinite(kappa)
    if np.any(bad):
        first = kappa.ravel()[np.flatnonzero(bad.ravel())[0]]
        raise ValueError(
            f"kappa (wave number / shear wave number) must be finite and > 0, got {first}"
        )
    c = _scaled_tensor(m)
    s = 1.0 / np.asarray(kappa, dtype=complex) ** 2
    return -_compliance(c, theta, s, normal_only=True)


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
    q = nonnegative("loss (Q^-1)", loss)
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
