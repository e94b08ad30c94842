"""Surface compliance of an anisotropic elastic half-space, static and time-harmonic.

Paper 1, Eqs. 10-20, in a form that holds for any anisotropy, the degenerate isotropic solid
included. For a surface wave vector ξ = η (cos θ, sin θ) the displacement field decaying into
the solid z > 0 is ``u(z) = exp(i η Z z) u(0)``, where Z is the decaying solvent
(:mod:`._doubling`) of the Christoffel pencil

    W Z² + (R + Rᵀ) Z + Q − s I = 0,     Q_ik = c_iakb n_a n_b,  R_ik = c_iak3 n_a,  W_ik = c_i3k3,

with c = C/C44 (:func:`scaled_tensor`), n = (cos θ, sin θ) and s = ρω²/(C44 η²) = 1/κ². The
surface traction of that field is σ_i3 = i η C44 (Rᵀ + W Z) u(0), so the dimensionless surface
compliance is H = −i (Rᵀ + W Z)⁻¹ (paper 1, Eqs. 12, 19): the 6x6 Stroh formulation with the
projector on the decaying subspace, reduced to 3x3 blocks.

This module assembles the blocks, balances the pencil, picks the doubling step (general, or
block-structured when the surface is a mirror plane), retries another Möbius parameter where
the doubling loses accuracy, and sends the points with propagating partial waves of a lossless
solid to the eigen-decomposition of :mod:`._outgoing`.
"""

from __future__ import annotations

import numpy as np

from ..errors import ContactresInputError
from ..materials import Material, voigt_to_tensor
from ._doubling import decaying_solvent
from ._outgoing import outgoing_compliance
from ._stacked import inv3, mm, transpose

__all__ = [
    "has_mirror_plane",
    "normal_compliance",
    "scaled_tensor",
    "shear_reference",
    "stacked_normal_compliance",
    "surface_compliance",
    "surface_compliance_pair",
]

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

    Parameters
    ----------
    m : Material
        Stiffness in the surface frame, Pa (complex with loss: only the real part is used).

    Returns
    -------
    float
        Re C44 of the surface frame, Pa.

    Raises
    ------
    ValueError
        If it is not positive.
    """
    c44 = float(np.real(np.asarray(m.C)[3, 3]))
    if not c44 > 0:
        raise ContactresInputError(f"surface-frame C44 must be positive, got {c44!r} Pa")
    return c44


def scaled_tensor(m: Material) -> np.ndarray:
    """Dimensionless stiffness tensor c = C/C44 of the surface frame.

    Parameters
    ----------
    m : Material
        Stiffness in the surface frame, Pa (complex with loss).

    Returns
    -------
    ndarray, complex, shape (3, 3, 3, 3)
        c_ijkl / Re C44, with C44 = :func:`shear_reference` (paper 1, Eq. 21).
    """
    return voigt_to_tensor(np.asarray(m.C, dtype=complex)) / shear_reference(m)


def has_mirror_plane(m: Material) -> bool:
    """True if the surface plane of ``m``'s current frame is a mirror plane of the solid.

    The kernels then take the block-structured doubling step (about a third of the cost of a
    general one): cubic (001) and (011), hexagonal basal and prism faces, orthotropic principal
    cuts; not cubic (111) nor a general cut.

    Parameters
    ----------
    m : Material
        Stiffness in the surface frame, Pa.

    Returns
    -------
    bool
        Whether z -> −z is a symmetry of the solid.
    """
    return _has_mirror(scaled_tensor(m))


def _has_mirror(c: np.ndarray) -> bool:
    """True if the surface plane is a mirror plane of the solid (z -> −z symmetry).

    Then every c_ijkl with an odd number of indices equal to z vanishes (cubic (001) and
    (011), hexagonal basal and prism faces, orthotropic principal cuts, ...). Entries at the
    round-off level of a rotated tensor count as zero.
    """
    odd = (np.sum(np.indices(c.shape) == 2, axis=0) % 2).astype(bool)
    return bool(np.max(np.abs(c[odd]), initial=0.0) <= 1e-14 * np.max(np.abs(c)))


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


def surface_compliance_pair(c: np.ndarray, theta, s) -> tuple[np.ndarray, np.ndarray]:
    """:func:`surface_compliance` at the directions θ and θ + π from one cyclic reduction.

    The pencil at θ + π is that at θ with R -> −R, i.e. with the outer coefficients of the
    doubling swapped; its decaying solvent is the reversed pencil's minimal solvent, built from
    the same iterates (:func:`._doubling.decaying_solvent` with ``dual``): a layer's downward
    and upward waves (:func:`contactres.layered.layer_waves`) at about the cost of one
    direction. H(θ + π) equals ``surface_compliance(c, theta + pi, s)`` to round-off (tested),
    though not bit for bit (θ + π is not rounded, and the products are formed in the other
    order).

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
    (H, H_pi) : tuple of ndarray
        H at θ and at θ + π, each shaped ``broadcast(theta, s).shape + (3, 3)`` (paper 1,
        Eqs. 12, 19).
    """
    H, H_pi = (
        np.ascontiguousarray(np.moveaxis(h, (0, 1), (-2, -1)))
        for h in _compliance(c, theta, s, normal_only=False, pair=True)
    )
    return H, H_pi


def normal_compliance(c: np.ndarray, theta, s) -> np.ndarray:
    """Normal-normal entry H_33 of the dimensionless surface compliance.

    Parameters
    ----------
    c : ndarray, shape (3, 3, 3, 3)
        Stiffness tensor in the surface frame divided by the reference C44 (complex allowed).
    theta : array_like
        Direction of the surface wave vector, rad.
    s : array_like
        ρω²/(C44 η²) = 1/κ² (0 in statics; complex allowed); broadcasts against ``theta``.

    Returns
    -------
    ndarray, complex, shape ``broadcast(theta, s).shape``
        H_33: the normal displacement u_3(0) = H_33 σ_33/(C44 η) (paper 1, Eqs. 12, 19).
    """
    return _compliance(c, theta, s, normal_only=True)


def stacked_normal_compliance(c: np.ndarray, theta, s=0.0) -> np.ndarray:
    """H_33 of a stack of M solids in one vectorised evaluation (same algorithm and accuracy
    as :func:`normal_compliance`, which it equals solid by solid).

    Parameters
    ----------
    c : ndarray, shape (M, 3, 3, 3, 3)
        Stiffness tensors in their surface frames, each divided by its reference C44 (complex
        allowed).
    theta : array_like, shape (K,) or (M, K)
        Directions of the surface wave vector, rad: shared by the solids, or one row each.
    s : array_like
        ρω²/(C44 η²) = 1/κ² (0 in statics); broadcasts against ``theta`` as (M, K).

    Returns
    -------
    ndarray, complex, shape (M, K)
        H_33 of every (solid, direction) pair (paper 1, Eqs. 12, 19).
    """
    c = np.asarray(c)
    m = c.shape[0]
    theta, s = np.broadcast_arrays(np.asarray(theta, dtype=float), np.asarray(s, dtype=complex))
    k = theta.shape[-1]
    th = np.broadcast_to(theta, (m, k)).ravel()
    sv = np.broadcast_to(s, (m, k)).ravel()
    # The 3x3 pieces of every solid that the blocks Q, R, W combine (see _blocks).
    pieces = np.stack(
        [
            c[:, :, 0, :, 0],
            c[:, :, 0, :, 1] + c[:, :, 1, :, 0],
            c[:, :, 1, :, 1],
            c[:, :, 0, :, 2],
            c[:, :, 1, :, 2],
            c[:, :, 2, :, 2],
        ],
        axis=1,
    )
    odd = (np.sum(np.indices((3, 3, 3, 3)) == 2, axis=0) % 2).astype(bool)
    mirror = np.max(np.abs(c[:, odd]), axis=1) <= 1e-14 * np.max(np.abs(c), axis=(1, 2, 3, 4))
    lossless = not np.iscomplexobj(c) or not np.any(c.imag)
    H = np.empty(m * k, dtype=complex)
    # Mirror-plane solids take the cheaper doubling step; chunks keep the working set in cache.
    for group in (True, False):
        pts = np.flatnonzero(np.repeat(mirror == group, k))
        for i in range(0, pts.size, _CHUNK):
            p = pts[i : i + _CHUNK]
            n1, n2 = np.cos(th[p]), np.sin(th[p])
            solid = p // k  # ascending
            if solid[0] == solid[-1]:
                # One solid (a kernel table's whole chunk): its pieces broadcast against the
                # directions instead of being gathered and transposed point by point (two
                # copies of 54 values per point); the same products.
                a = pieces[solid[0]][..., None]
            else:
                a = np.ascontiguousarray(np.moveaxis(pieces[solid], 0, -1))
            Q = a[0] * n1**2 + a[1] * (n1 * n2) + a[2] * n2**2
            R = a[3] * n1 + a[4] * n2
            W = np.broadcast_to(a[5], Q.shape)
            H[p] = _pencil_compliance(Q, R, W, th[p], sv[p], group, True, lossless)
    return H.reshape(m, k)


def _compliance(c: np.ndarray, theta, s, normal_only: bool, pair: bool = False):
    """H as (3, 3, *shape), or only H_33 (shape) if ``normal_only``; with ``pair`` a (2, ...)
    array: H at θ and at θ + π."""
    theta, s = np.broadcast_arrays(np.asarray(theta, dtype=float), np.asarray(s, dtype=complex))
    shape = theta.shape
    th = theta.ravel()
    sv = s.ravel()
    mirror = _has_mirror(c)
    H = np.empty(
        ((2,) if pair else ()) + ((th.size,) if normal_only else (3, 3, th.size)), dtype=complex
    )
    # Work in cache-sized chunks: the algorithm is elementwise and memory-bound.
    for i in range(0, th.size, _CHUNK):
        sl = slice(i, i + _CHUNK)
        H[..., sl] = _compliance_chunk(c, th[sl], sv[sl], mirror, normal_only, pair)
    return H.reshape(H.shape[:-1] + shape)


def _compliance_chunk(c, th, sv, mirror: bool, normal_only: bool, pair: bool = False):
    """H (3, 3, N), or H_33 (N), for flat arrays of directions ``th`` and inertia terms ``sv``;
    ``mirror``: the solid has the mirror plane z -> −z (:func:`has_mirror_plane`); ``pair``:
    H at θ and θ + π stacked (2, ...)."""
    Q, R, W = _blocks(c, th)
    lossless = not np.iscomplexobj(c) or not np.any(c.imag)
    if not pair:
        return _pencil_compliance(Q, R, W, th, sv, mirror, normal_only, lossless)
    if mirror:
        # z -> −z maps the pencil at θ + π onto that at θ: H(θ + π) = M H(θ) M, M = diag(1, 1, −1).
        H = _pencil_compliance(Q, R, W, th, sv, mirror, normal_only, lossless)
        Hpi = H.copy()
        if not normal_only:
            Hpi[:2, 2] *= -1
            Hpi[2, :2] *= -1
        return np.stack([H, Hpi])
    return np.stack(_pencil_compliance(Q, R, W, th, sv, mirror, normal_only, lossless, True))


def _pencil_compliance(Q, R, W, th, sv, mirror, normal_only, lossless, pair=False):
    """H (3, 3, N), or H_33 (N), of the pencil blocks Q, R, W (3, 3, N) of flat points; with
    ``pair`` (not ``mirror``) the tuple (H, H at θ + π), the pencil with R -> −R."""
    # Balance the pencil by the congruence D (.) D, D = diag(W)^(-1/2): W gets a unit diagonal.
    # Then Z = D Z~ D^-1, the identity in Q − sI becomes D², and H = D H~ D.
    d = 1.0 / np.sqrt(np.real(np.diagonal(W, axis1=0, axis2=1).T))
    DD = d[:, None] * d[None, :]
    given = Q, R, W
    Q, R, W = Q * DD, R * DD, W * DD
    # Scale of the vertical wave numbers: |p| ~ 1 in statics, ~ sqrt(|s|) at high frequency.
    beta = np.sqrt(1.0 + np.abs(sv))
    s3 = d**2 * sv
    # A lossless solid at a real wave number below a bulk cutoff has real vertical wave numbers
    # (propagating partial waves): no decaying/growing split, so the doubling cannot converge.
    # Those points take the eigen-decomposition with the limiting-absorption choice below.
    real_s = (sv.imag == 0) if lossless else np.zeros(sv.shape, dtype=bool)
    if pair:
        G, ok, resid, Gpi, resid_pi = decaying_solvent(
            Q, R, W, s3, beta, may_stall=real_s, dual=True
        )
        ok_pi, beta_pi = ok & (resid_pi <= _RESID_TOL), beta.copy()
    else:
        G, ok, resid = decaying_solvent(Q, R, W, s3, beta, may_stall=real_s, mirror=mirror)
    propagating = ~ok & real_s
    # Cyclic reduction loses accuracy (or breaks down) where the squared Möbius images of a
    # decaying and a growing root nearly coincide; another β moves those points elsewhere.
    for factor in _BETA_RETRY:
        idx = np.flatnonzero((~ok | (resid > _RESID_TOL)) & ~propagating)
        if idx.size == 0:
            break
        G2, ok2, res2 = decaying_solvent(
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
        raise ContactresInputError(
            "no decaying/growing split of the partial waves at theta="
            f"{th[bad]:.6g} rad, 1/kappa^2={sv[bad]:.6g} (cyclic reduction did not converge)"
        )
    H = _solvent_compliance(G, Q, R, W, s3, beta, th, sv, propagating, normal_only)
    if not pair:
        return H * DD[2, 2] if normal_only else H * DD
    Hpi = _solvent_compliance(Gpi, Q, -R, W, s3, beta_pi, th, sv, propagating, normal_only)
    H, Hpi = (H * DD[2, 2], Hpi * DD[2, 2]) if normal_only else (H * DD, Hpi * DD)
    # Points whose θ + π solvent is not accurate enough take the separate evaluation (with its
    # own retries of β): rare.
    j = np.flatnonzero(~ok_pi & ~propagating)
    if j.size:
        Qj, Rj, Wj = (x[..., j] for x in given)
        Hpi[..., j] = _pencil_compliance(
            Qj, -Rj, Wj, th[j] + np.pi, sv[j], False, normal_only, lossless
        )
    return H, Hpi


def _solvent_compliance(G, Q, R, W, s3, beta, th, sv, propagating, normal_only):
    """H (balanced) from the Möbius image G of the decaying solvent; the eigen-decomposition
    of :mod:`._outgoing` at the ``propagating`` points."""
    G[..., propagating] = 0.0
    eye = np.eye(3)[..., None]
    # Z = iβ (I + G)(I − G)⁻¹, so Rᵀ + W Z = [Rᵀ (I − G) + iβ W (I + G)] (I − G)⁻¹.
    M = mm(transpose(R), eye - G) + 1j * beta * mm(W, eye + G)
    if normal_only:
        H = -1j * np.sum((eye - G)[2] * _inverse_last_column(M), axis=0)
    else:
        H = -1j * mm(eye - G, inv3(M))
    if np.any(propagating):
        i = np.flatnonzero(propagating)
        Hp = outgoing_compliance(
            Q[..., i].real, R[..., i].real, W[..., i].real, s3[:, i].real, th[i], sv[i]
        )
        H[..., i] = Hp[2, 2] if normal_only else Hp
    return H


def _inverse_last_column(a: np.ndarray) -> np.ndarray:
    """Last column (3, N) of the inverse of stacked 3x3 matrices (3, 3, N): the entries of
    :func:`.stacked.inv3` (the same formulas, so the same values) without the other six."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    r = 1.0 / (
        a00 * (a11 * a22 - a12 * a21)
        + a01 * (a12 * a20 - a10 * a22)
        + a02 * (a10 * a21 - a11 * a20)
    )
    return np.array(
        [(a01 * a12 - a02 * a11) * r, (a02 * a10 - a00 * a12) * r, (a00 * a11 - a01 * a10) * r]
    )


def _blocks(c: np.ndarray, theta: np.ndarray):
    """Q, R, W of the directions n = (cos θ, sin θ), stacked as (3, 3, N) for flat ``theta``."""
    n1 = np.cos(theta)
    n2 = np.sin(theta)
    c11, c12, c21, c22 = c[:, 0, :, 0], c[:, 0, :, 1], c[:, 1, :, 0], c[:, 1, :, 1]
    Q = c11[..., None] * n1**2 + (c12 + c21)[..., None] * (n1 * n2) + c22[..., None] * n2**2
    R = c[:, 0, :, 2, None] * n1 + c[:, 1, :, 2, None] * n2
    W = np.broadcast_to(c[:, 2, :, 2, None], Q.shape)
    return Q, R, W
