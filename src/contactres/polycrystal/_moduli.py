"""Indentation modulus of many crystal orientations in one vectorised evaluation.

A polycrystal map gives one orientation per pixel; the indentation modulus of a rigid sphere on
that grain is M = 4π/I₀ with I₀ = ∫₀^{2π} Ĝ(θ) dθ (paper 1, Eq. 4; Vlassak & Nix 1994), Ĝ the
static surface Green's function of the crystal in the sample (surface) frame
(:func:`contactres.halfspace.static_kernel`). :func:`indentation_moduli` rotates the stiffness
of all orientations at once, evaluates Ĝ on an (orientation x θ) grid in stacked calls of the
doubling algorithm (:func:`contactres.halfspace.stacked_normal_compliance`) and
applies the same trapezoidal rule and stopping test as
:func:`contactres.normal.contact_integrals`, orientation by orientation.

Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", American Journal of Engineering and Applied Sciences 3(1), 56-63
(2010), doi:10.3844/ajeassp.2010.56.63. J. J. Vlassak and W. D. Nix, J. Mech. Phys. Solids 42,
1223 (1994).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import ContactresInputError
from ..halfspace import stacked_normal_compliance
from ..materials import Material, require_material, voigt_to_tensor
from ..normal import (
    THETA_RTOL,
    contrast_poisson,
    isotropic_constants,
    stiffness_contrast,
)

__all__ = ["indentation_moduli", "moduli_and_points", "stacked_indentation_moduli"]

# The θ rule of contact_integrals: 16 points on [0, π) to start, doubled up to 2^15.
_N_START = 16
_N_MAX = 2**15
# Orientations per vectorised evaluation: bounds the memory (81 complex entries of the rotated
# tensor and ~64 θ points each) for maps of millions of pixels.
_ORIENTATION_CHUNK = 4096
# Largest deviation of R Rᵀ from the identity accepted for a surface matrix.
_ORTHO_TOL = 1e-10


def indentation_moduli(
    material: Material, surface_matrices, rtol: float = THETA_RTOL
) -> np.ndarray:
    """Indentation modulus M = 4π/I₀ of N crystal orientations, Pa (paper 1, Eq. 4).

    For orientation n the stiffness in the sample frame is
    C'_ijkl = R_ia R_jb R_kc R_ld C_abcd (R = ``surface_matrices[n]``), and

        I₀ = ∫₀^{2π} Ĝ(θ) dθ = 2 ∫₀^π Ĝ(θ) dθ,   I₁ = ∫₀^{2π} Ĝ(θ) cos²θ dθ,   M = 4π/I₀,

    with Ĝ(θ) the static surface Green's function of C' (1/Pa; Ĝ is π-periodic by
    reciprocity). M is the E* of the isotropic solid on which a rigid sphere makes the same
    contact stiffness, K_sa = 2aM (Vlassak & Nix 1994); isotropic: M = E/(1 − ν²).

    All orientations are evaluated together: four contractions rotate the stiffness (numpy's
    loops, no BLAS: the same bits in every process, whatever its threads), Ĝ is computed
    on the (orientation x θ) grid by the stacked doubling algorithm, and the trapezoidal rule
    on [0, π) starts at 16 points and adds the midpoints for the orientations whose I₀ or I₁
    still moved by more than ``rtol`` relative to I₀ (the rule of
    :func:`contactres.normal.contact_integrals`, applied orientation by
    orientation; Cu converges at 64 points). An isotropic solid takes the closed form
    M = 4 C44 (C11 − C44)/C11 for every orientation.

    Parameters
    ----------
    material : Material
        The crystal in its crystal frame (stiffness in Pa; complex for a lossy solid).
    surface_matrices : array_like, shape (N, 3, 3)
        Orthogonal matrices R whose rows are the sample axes x, y, z in crystal coordinates,
        z the inward surface normal (the convention of
        :func:`contactres.materials.rotation_to_surface`; ``v_sample = R @ v_crystal``).
        Improper R (det −1) give the same M as −R (the stiffness is centrosymmetric).
    rtol : float
        Relative accuracy of I₀ and I₁, in [1e-15, 1e-2].

    Returns
    -------
    ndarray, shape (N,)
        M, Pa: real for a lossless material, complex for a lossy one.

    Raises
    ------
    ValueError
        For matrices that are not (N, 3, 3), finite and orthogonal (to 1e-10), for ``rtol``
        outside [1e-15, 1e-2], or when 2^15 θ points do not reach ``rtol`` for some
        orientation (its index and the reason are given, as in ``contact_integrals``).

    Notes
    -----
    Accuracy: the trapezoidal rule converges exponentially for the smooth periodic Ĝ, so the
    last change (<= ``rtol`` relative) bounds the quadrature error; the kernel itself is
    accurate to ~1e-13 (see :mod:`contactres.halfspace`). Tests: agreement with
    :func:`contactres.normal.indentation_modulus` of the rotated material to 1e-12
    (Cu principal faces and random orientations, trigonal sapphire and quartz, lossy Cu),
    the isotropic closed form to 1e-12, invariance under the cubic point group and under
    rotations of the sample frame about the normal to 1e-12. Cost: ~0.5 ms per Cu
    orientation (64 θ points), 17x the loop over ``indentation_modulus`` of the rotated
    material (``benchmarks/bench_polycrystal_moduli.py``).

    Examples
    --------
    >>> import numpy as np
    >>> from contactres import Material
    >>> from contactres.materials import rotation_to_surface
    >>> from contactres.polycrystal._moduli import indentation_moduli
    >>> R = np.stack([rotation_to_surface(n) for n in [(0, 0, 1), (1, 1, 1)]])
    >>> print(np.round(indentation_moduli(Material.crystal("Cu"), R) / 1e9, 1))
    [134.  151.6]
    """
    m = require_material(material)
    rtol, R = _checked(rtol, surface_matrices)
    dtype = complex if m.is_lossy else float
    iso = isotropic_constants(m)
    if iso is not None:
        # Ĝ = C11/(2 C44 (C11 − C44)) in every direction: M = 4π/(2π Ĝ).
        c11, c44 = iso
        M = 4 * c44 * (c11 - c44) / c11
        return np.full(R.shape[0], M if m.is_lossy else np.real(M), dtype=dtype)
    # A map has many pixels per grain, all of one orientation: each distinct matrix (to the
    # bit) is evaluated once (issue 31: a 512² map of grains took 34 s). An orientation's M
    # does not depend on the others evaluated with it (every step is per orientation), so the
    # values are those of the full stack to the bit. The distinct matrices keep the order of
    # their first pixel, so an error names the first pixel at fault, as without the reduction.
    first, inverse = _distinct(R)
    unique = R[first]
    out = np.empty(unique.shape[0], dtype=dtype)
    for i in range(0, unique.shape[0], _ORIENTATION_CHUNK):
        sl = slice(i, i + _ORIENTATION_CHUNK)
        out[sl] = _moduli([m], unique[sl], rtol, index=first[sl])[0]
    return out[inverse]


def stacked_indentation_moduli(
    materials: Sequence[Material], surface_matrices, rtol: float = THETA_RTOL
) -> np.ndarray:
    """M (Pa) of several materials for the same orientations: shape (len(materials), N).

    Row j equals :func:`indentation_moduli` of ``materials[j]`` to the bit: every
    (material, orientation) pair is its own row of one stacked evaluation, and no step mixes
    rows. One evaluation instead of one per material: the cost of a small stack is mostly
    per call (the θ doublings), so the 2k + 1 materials of a central-difference Jacobian
    (:mod:`contactres.polycrystal._ratio_fit`) cost about one call. Lossy or isotropic
    materials (closed form) are evaluated one by one; one lossy material among them makes
    every row complex, as its own M is. Parameters and errors as :func:`indentation_moduli`;
    no materials give an empty (0, N) array.
    """
    return moduli_and_points(materials, surface_matrices, rtol)[0]


def moduli_and_points(
    materials: Sequence[Material],
    surface_matrices,
    rtol: float = THETA_RTOL,
    first_points: int | None = None,
) -> tuple[np.ndarray, int | None]:
    """:func:`stacked_indentation_moduli` and the fewest θ points a row needed.

    The rows are those of :func:`stacked_indentation_moduli` to the bit, whatever
    ``first_points``: it sets only how the same points of the same nested rule are batched.

    Parameters
    ----------
    materials, surface_matrices, rtol
        As :func:`stacked_indentation_moduli`.
    first_points : int, optional
        θ points on [0, π) of every row evaluated in the first stacked call: 16 2^j, at most
        2^15; None: 16. The rule then compares its levels 16, 32, ... as before; rows that
        meet ``rtol`` before ``first_points`` leave the surplus unused, the others go on
        doubling call by call. A fit passes the points its last rows needed (materials a
        small step away need about as many): one call instead of one per doubling (Cu: 64
        points, three calls), whose fixed cost dominates for tens of grains.

    Returns
    -------
    M : ndarray, shape (len(materials), N)
        Pa, as :func:`stacked_indentation_moduli`.
    points : int or None
        The fewest θ points on [0, π) with which a row met ``rtol`` (16 2^j); None when no
        row took the rule (no orientations, or lossy or isotropic materials, evaluated one
        by one).
    """
    ms = [require_material(m) for m in materials]
    first_points = _N_START if first_points is None else int(first_points)
    if first_points < _N_START or first_points > _N_MAX or first_points & (first_points - 1):
        raise ContactresInputError(f"first_points must be 16 2^j <= {_N_MAX}, got {first_points!r}")
    if not ms:
        return np.empty((0, _checked(rtol, surface_matrices)[1].shape[0])), None
    if any(m.is_lossy or isotropic_constants(m) is not None for m in ms):
        return np.stack([indentation_moduli(m, surface_matrices, rtol) for m in ms]), None
    rtol, R = _checked(rtol, surface_matrices)
    first, inverse = _distinct(R)
    unique = R[first]
    out = np.empty((len(ms), unique.shape[0]))
    step = max(1, _ORIENTATION_CHUNK // len(ms))
    fewest = None
    for i in range(0, unique.shape[0], step):
        sl = slice(i, i + step)
        m, n = _moduli(ms, unique[sl], rtol, index=first[sl], first_points=first_points)
        out[:, sl] = m.reshape(len(ms), -1)
        fewest = n if fewest is None else min(fewest, n)
    return out[:, inverse], fewest


def _checked(rtol, surface_matrices) -> tuple[float, np.ndarray]:
    """``rtol`` as a float and the surface matrices as an (N, 3, 3) array, checked as
    :func:`indentation_moduli` documents."""
    rtol = float(rtol)
    if not (1e-15 <= rtol <= 1e-2):
        raise ContactresInputError(f"rtol must lie in [1e-15, 1e-2], got {rtol!r}")
    R = np.asarray(surface_matrices, dtype=float)
    if R.ndim != 3 or R.shape[1:] != (3, 3):
        raise ContactresInputError(f"surface_matrices must have shape (N, 3, 3), got {R.shape}")
    if not np.all(np.isfinite(R)):
        raise ContactresInputError("surface_matrices must be finite")
    dev = np.abs(R @ R.transpose(0, 2, 1) - np.eye(3)).max(axis=(1, 2), initial=0.0)
    if np.any(dev > _ORTHO_TOL):
        bad = int(np.flatnonzero(dev > _ORTHO_TOL)[0])
        raise ContactresInputError(
            f"surface_matrices[{bad}] is not orthogonal (|R R^T - I| = {dev[bad]:.3g})"
        )
    return rtol, R


def _distinct(R: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(first, inverse)``: the index of the first of each distinct matrix of ``R`` (N, 3, 3),
    in order of appearance, and for every matrix the position of its own in ``first``.

    Matrices are compared bit by bit (as 9 integers), so 0.0 and -0.0 differ and no two
    matrices with different bits share a value.
    """
    bits = np.ascontiguousarray(R).view(np.uint64).reshape(R.shape[0], 9)
    _, first, inverse = np.unique(bits, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return first[order], rank[inverse.reshape(-1)]


def _rotated(R: np.ndarray, c: np.ndarray) -> np.ndarray:
    """c'_nijkl = R_nia R_njb R_nkc R_nld c_abcd for the stack of rotations ``R`` (n, 3, 3).

    One index at a time, each a two-operand einsum without ``optimize``: numpy's own loops,
    never BLAS. With ``optimize=True`` the path ran through BLAS, whose rounding depends on its
    threads: a dask worker (one BLAS thread) gave 1 ulp off the serial result in 1 pixel of
    10^4 (issue 27, point 10). This order of the sums is the same in every process.
    """
    t = np.einsum("nld,abcd->nlabc", R, c)
    t = np.einsum("nkc,nlabc->nklab", R, t)
    t = np.einsum("njb,nklab->njkla", R, t)
    return np.einsum("nia,njkla->nijkl", R, t)


def _theta_levels(points: int) -> list[np.ndarray]:
    """The nested θ rule on [0, π) up to ``points`` points, level by level: the 16 starting
    points, then the midpoints added at 16, 32, ..., ``points``/2 (rad; each array formed
    by the expression the doubling loop of :func:`_moduli` uses, so the same bits)."""
    levels = [np.pi * np.arange(_N_START) / _N_START]
    n = _N_START
    while 2 * n <= points:
        levels.append(np.pi * (np.arange(n) + 0.5) / n)
        n *= 2
    return levels


def _moduli(
    ms: list[Material], R: np.ndarray, rtol: float, index: np.ndarray, first_points: int = _N_START
) -> tuple[np.ndarray, int]:
    """M of one chunk of orientations ``R`` (n, 3, 3) for each material of ``ms`` (all lossy
    or all lossless, none isotropic), material-major: shape (len(ms) n,), and the fewest θ
    points a row needed; ``index``: the index of each orientation in the caller's stack
    (named in an error); ``first_points``: see :func:`moduli_and_points`."""
    lossy = ms[0].is_lossy
    dtype = complex if lossy else float
    # Each material rotated as alone (the same einsum calls, the same bits), then stacked.
    cs = np.concatenate([_rotated(R, voigt_to_tensor(np.asarray(m.C, dtype=dtype))) for m in ms])
    index = np.tile(index, len(ms))
    # Reference C44 of each sample frame (Voigt C'44 = c'_yzyz), as in shear_reference.
    c44 = np.real(cs[:, 1, 2, 1, 2])
    if not np.all(c44 > 0):
        bad = int(np.flatnonzero(~(c44 > 0))[0])
        raise ContactresInputError(f"surface-frame C44 must be positive, got {c44[bad]!r} Pa")
    cs = cs / c44[:, None, None, None, None]

    def kernel(idx, theta):
        return -stacked_normal_compliance(cs[idx], theta) / c44[idx, None]

    def sums(g, theta):
        if not lossy:
            g = g.real
        return np.stack([g.sum(axis=1), (g * np.cos(theta) ** 2).sum(axis=1)], axis=1)

    active = np.arange(cs.shape[0])
    # The first levels of every row in one call: Ĝ at a point is the same bits in any stack
    # (the kernel works point by point), and each level's columns are copied out, so its
    # sums add the values of a call of its own in its order.
    levels = _theta_levels(first_points)
    g = kernel(active, np.concatenate(levels))
    edges = np.cumsum([0] + [th.size for th in levels])
    ready = [
        sums(np.ascontiguousarray(g[:, a:b]), th)
        for a, b, th in zip(edges[:-1], edges[1:], levels, strict=True)
    ]
    n, level = _N_START, 1
    total = ready[0]
    I0 = np.empty(cs.shape[0], dtype=total.dtype)
    fewest = 0
    while active.size:
        if level < len(ready):
            added = ready[level][active]
        else:
            theta = np.pi * (np.arange(n) + 0.5) / n
            added = sums(kernel(active, theta), theta)
        new = total + added
        level += 1
        I_old = 2 * np.pi / n * total
        I_new = np.pi / n * new
        err = np.max(np.abs(I_new - I_old), axis=1) / np.abs(I_new[:, 0])
        n *= 2
        conv = err <= rtol
        I0[active[conv]] = I_new[conv, 0]
        if not fewest and conv.any():
            fewest = n
        if n >= _N_MAX and not np.all(conv):
            j = int(np.flatnonzero(~conv)[0])
            contrast = stiffness_contrast(ms[active[j] // R.shape[0]])
            if contrast > 1e3:
                reason = (
                    f"the solid is nearly incompressible (stiffness contrast {contrast:.4g}, "
                    f"as an isotropic solid with nu = {contrast_poisson(contrast):.6g}): the "
                    "static kernel loses digits to round-off; pass a larger rtol"
                )
            else:
                reason = "the solid is too anisotropic for it"
            raise ContactresInputError(
                f"indentation_moduli: the theta quadrature of orientation {index[active[j]]} "
                f"did not reach rtol={rtol:g} with {n} points (last change {err[j]:.3g}); "
                f"{reason}"
            )
        active, total = active[~conv], new[~conv]
    return 4 * np.pi / I0, fewest
