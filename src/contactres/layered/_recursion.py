"""Surface response of a layered substrate by a stable impedance (reflection-matrix) recursion.

Conventions (those of :mod:`contactres.halfspace`): time factor e^{iωt}; fields vary along the
surface as e^{iξ·x} with ξ = η (cos θ, sin θ), i.e. the Fourier transform
f̂(ξ) = ∫ f(x) e^{−iξ·x} dx; z is the inward normal; c = C/C44_ref with one reference C44 for
the whole stack (that of the substrate) and s_j = ρ_j ω²/(C44_ref η²) for every material. In
a homogeneous solid the field decaying into z > 0 is u(z) = exp(iηzZ) u(0) with Z the decaying
solvent of the Christoffel pencil W Z² + (R + Rᵀ) Z + Q − sI = 0, and the traction on the
planes z = const is σ_i3 = iηC44_ref (Rᵀ + WZ) u =: ηC44_ref D u. The half-space compliance is
H = −i (Rᵀ + WZ)⁻¹ = D⁻¹ (:func:`contactres.halfspace.surface_compliance`).

Derivation. In a layer 0 <= z <= h, u(z) = E_d(z) a + E_u(z − h) b, with E_d(z) = exp(iηzZ_d)
(decaying downward) and E_u(z − h) = exp(iη(z − h)Z_u) (decaying upward, from the bottom of the
layer); both are bounded on the layer. The growing solvent needs no new algorithm: the pencil at
θ + π has the same Q and W and R -> −R, so Z_u(θ) = −Z_d(θ + π), and
D_u = i(Rᵀ + WZ_u) = −H(θ + π)⁻¹, D_d = H(θ)⁻¹ (H of the layer's material as a half-space).
For a lossless layer with propagating partial waves, the outgoing (limiting-absorption) choice of
the half-space at θ + π is, by point inversion, the set of waves carrying energy upward at θ, the
complement of the downward set: together they span all solutions, which is what the layer needs.
With X_d = exp(iηhZ_d), X_u = exp(−iηhZ_u) = exp(iηhZ_d(θ + π)) (both decaying) and the impedance
Y of what lies below (σ(h) = ηC44_ref Y u(h)), continuity of u and σ_i3 at z = h gives
b = ρ X_d a with the reflection matrix ρ = (D_u − Y)⁻¹ (Y − D_d), and at the top
u(0) = (I + X_u ρ X_d) a, σ(0) = (D_d + D_u X_u ρ X_d) a, so

    Y_top = (D_d + D_u X_u ρ X_d) (I + X_u ρ X_d)⁻¹,

recursed upward from Y = H_substrate⁻¹; H_stack = Y_top⁻¹. Only decaying exponentials appear, so
nothing overflows at any ηh (a transfer matrix carries e^{+ηh} terms and loses every digit beyond
ηh ~ 35). A layer of the substrate's own material gives ρ = 0 exactly. This is the surface
impedance (Riccati) form of the stiffness-matrix recursion of S. I. Rokhlin and L. Wang,
"Stable recursive algorithm for elastic wave propagation in layered anisotropic media: Stiffness
matrix method", J. Acoust. Soc. Am. 112(3), 822-834 (2002), doi:10.1121/1.1497365 (after
L. Wang and S. I. Rokhlin, Ultrasonics 39, 413-424 (2001)), with the partial waves of each layer
from Stroh's formalism (A. N. Stroh, "Steady state problems in anisotropic elasticity",
J. Math. Phys. 41, 77 (1962)) as the half-space code computes them.

Interfaces: welded (u and σ_i3 continuous). Bottom: the substrate half-space with decaying
(lossless: outgoing) waves only. Top: the applied traction.

Guided modes: a lossless stack has poles of H on the real wavenumber axis (Rayleigh and the
layer's guided modes, e.g. Love and Lamb-type waves) where the response is infinite; there the
value is not meaningful (use loss, or a complex wavenumber with Im > 0), and a non-finite result
raises :class:`~contactres.errors.ContactresInputError`.

Accuracy (tests/layered, measured): a stack of films of the substrate's own material
reproduces the homogeneous compliance to 8e-16 (relative, static and dynamic, isotropic and
cubic (111), lossless with propagating partial waves and lossy); a global boundary-value solve
of two- and three-material stacks (isotropic and Si (111), static, 15 and 300 MHz, η h up to 4;
tests/layered/layered_reference.py, scipy's expm and Schur) agrees to 3e-14; a cubic film with
A = 1 equals the isotropic film to 1e-15 and A = 1 ± 1e-6 moves it by 7.6e-7; a film of
η h = 1e-9 changes the substrate's response by 1.7e-9 (first order in η h), and for η h >= 30 the
stack is the film's half-space to 7e-16 (no overflow at η h = 1e3). The exponentials add
< 1e-19 of truncation (:mod:`._expm`).

Cost (``benchmarks/bench_layered.py``): per layer and point, an isotropic film (and an
isotropic substrate) costs no half-space evaluation (its impedance D_d and exponent A_d in
closed form from the P and S decay rates, :func:`_isotropic_impedance`: the same as the general
Stroh solution to ~1e-15, tested), another mirror-plane film (cubic (001), ...) one half-space
evaluation and one 3x3 exponential, any other film two of each, plus a few 3x3 products and
inverses; one film on a substrate takes ~1.0-1.8x the time
of the two homogeneous half-spaces together (~10-17 µs per (η, θ) point on an unloaded core).
A caller that knows a layer to be isotropic (and the directions θ) may have its exponential
formed in closed form (``isotropic`` of :func:`impedance_recursion` and
:func:`compliance_factors`; :mod:`._expm`): a few elementwise operations instead of the Taylor
polynomial and its squarings, the same to ~1e-15 (the layered punch and
:func:`stack_compliance` do so).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ContactresInputError
from ..halfspace import (
    inv3,
    mm,
    shear_reference,
    surface_compliance,
    surface_compliance_pair,
    transpose,
)
from ..materials import Material, voigt_to_tensor
from ._expm import expm3, expm_isotropic
from ._stack import LayeredMaterial, material_at

__all__ = [
    "compliance_factors",
    "impedance_recursion",
    "isotropic_moduli",
    "layer_waves",
    "stack_compliance",
    "substrate_impedance",
    "surface_green",
]


def _rw_blocks(c: np.ndarray, theta: np.ndarray):
    """R (3, 3, N) and W (3, 3, 1) of the pencil (R_ik = c_iak3 n_a, W_ik = c_i3k3)."""
    R = c[:, 0, :, 2, None] * np.cos(theta) + c[:, 1, :, 2, None] * np.sin(theta)
    return R, c[:, 2, :, 2, None]


def _halfspace(c, th, s) -> np.ndarray:
    """H of the half-space of tensor c as a (3, 3, N) stack."""
    return np.moveaxis(surface_compliance(c, th, s), (-2, -1), (0, 1))


def _impedance(c, th, s) -> np.ndarray:
    """D = H⁻¹ (3, 3, N) of the half-space of tensor c: in closed form for an isotropic solid
    (:func:`_isotropic_impedance`), else the inverse of the general compliance."""
    moduli = isotropic_moduli(c)
    if moduli is None:
        return inv3(_halfspace(c, th, s))
    return _isotropic_impedance(moduli[0], moduli[1], np.asarray(th, dtype=float), s)


def isotropic_moduli(c: np.ndarray) -> tuple[complex, complex] | None:
    """(c11, c44) of the tensor c if it is isotropic, c_ijkl = λ δ_ij δ_kl + μ (δ_ik δ_jl +
    δ_il δ_jk) to the round-off of a rotated tensor (complex moduli allowed); else None.

    Parameters
    ----------
    c : (3, 3, 3, 3) elastic tensor (any unit; Pa for a material's), real or complex

    Returns
    -------
    tuple of two complex or None
        c11 = λ + 2μ and c44 = μ in the unit of ``c`` where every component of ``c`` is
        within 1e-14 of its largest of the isotropic tensor with λ = c_1122, μ = c_1212 (the
        closed-form paths for isotropic layers and substrates use them); None otherwise.
    """
    d = np.eye(3)
    lam, mu = c[0, 0, 1, 1], c[0, 1, 0, 1]
    iso = lam * np.einsum("ij,kl->ijkl", d, d) + mu * (
        np.einsum("ik,jl->ijkl", d, d) + np.einsum("il,jk->ijkl", d, d)
    )
    if np.max(np.abs(c - iso)) > 1e-14 * np.max(np.abs(c)):
        return None
    return complex(lam + 2 * mu), complex(mu)


def _isotropic_impedance(c11, c44, th: np.ndarray, s, exponent: bool = False):
    """D = H⁻¹ (3, 3, N) of an isotropic half-space (moduli c11 = λ + 2μ, c44 = μ over the
    reference C44; inertia s = ρω²/(C44_ref η²)) at the directions ``th``, in closed form;
    ``exponent``: (D, A_d), with A_d the exponent of its decaying field, u(z) = exp(ηz A_d) u(0)
    (:func:`layer_waves`).

    With the decay rates α = √(1 − s/c11) (P) and β = √(1 − s/c44) (S) (Re >= 0; a lossless
    solid beyond a cutoff, s real above c11 or c44: the outgoing root, i√(s/c − 1)), the
    potentials of the decaying P-SV field, u = M diag(e^{−αηz}, e^{−βηz}) (amplitudes) with
    M = [[i, β], [−α, i]] in the frame (ξ/η, its normal in the surface, z), give the sagittal
    blocks D = N M⁻¹ (N the tractions of the two waves) and A_d = M diag(−α, −β) M⁻¹:

        D_xx = −α K,  D_zz = −β K,  D_xz = −D_zx = i (2 c44 − K),
        A_xx = −α K/c44,  A_zz = −β K/c11,  A_xz, A_zx = −i (β, α) (c11 − c44) K/(c11 c44 (α + β)),
        K = (1 + αβ) c11 c44 / (c11 + c44 − s)

    (the rationalised forms of s α/(αβ − 1) and their kin: no 0/0 in statics), and the SH
    entries D_yy = −β c44, A_yy = −β; turned to the surface axes by θ. The general Stroh
    solution (:func:`contactres.halfspace.surface_compliance`) gives the same D to round-off
    (tests)."""
    s = np.broadcast_to(np.asarray(s, dtype=complex), th.shape)
    alpha = _decay_root(1 - s / c11, s, c11)
    beta = _decay_root(1 - s / c44, s, c44)
    k = (1 + alpha * beta) * c11 * c44 / (c11 + c44 - s)
    d = _turned(th, -alpha * k, -beta * c44, -beta * k, 1j * (2 * c44 - k), -1j * (2 * c44 - k))
    if not exponent:
        return d
    off = (c11 - c44) * k / (c11 * c44 * (alpha + beta))
    a = _turned(th, -alpha * k / c44, -beta, -beta * k / c11, -1j * beta * off, -1j * alpha * off)
    return d, a


def _turned(th, xx, yy, zz, xz, zx) -> np.ndarray:
    """The (3, 3, N) matrix with the entries ``xx`` ... in the frame (wave vector, its normal
    in the surface, z) turned to the surface axes by the direction θ (no xy, yz coupling)."""
    cos, sin = np.cos(th), np.sin(th)
    out = np.empty((3, 3, th.size), dtype=complex)
    out[0, 0] = cos**2 * xx + sin**2 * yy
    out[1, 1] = sin**2 * xx + cos**2 * yy
    out[0, 1] = out[1, 0] = cos * sin * (xx - yy)
    out[0, 2], out[1, 2] = cos * xz, sin * xz
    out[2, 0], out[2, 1] = cos * zx, sin * zx
    out[2, 2] = zz
    return out


def _decay_root(v: np.ndarray, s: np.ndarray, c: complex) -> np.ndarray:
    """√v with Re >= 0 (decaying); where v is real and negative (a lossless solid beyond its
    cutoff, s real above c) the outgoing root +i√(−v) (limiting absorption, e^{iωt})."""
    root = np.sqrt(v)
    beyond = (s.imag == 0) & (c.imag == 0) & (v.real < 0)
    return np.where(beyond, 1j * np.sqrt(np.maximum(-v.real, 0.0)), root)


def _is_mirror(c: np.ndarray) -> bool:
    """True if z -> −z is a symmetry of the solid: every c_ijkl with an odd number of z indices
    vanishes (to the round-off of a rotated tensor), as in the half-space code."""
    odd = (np.sum(np.indices(c.shape) == 2, axis=0) % 2).astype(bool)
    return bool(np.max(np.abs(c[odd]), initial=0.0) <= 1e-14 * np.max(np.abs(c)))


def _flip(a: np.ndarray) -> np.ndarray:
    """M a M with M = diag(1, 1, −1), for a (3, 3, N) stack."""
    out = a.copy()
    out[:2, 2] *= -1
    out[2, :2] *= -1
    return out


def layer_waves(c, th, s) -> tuple[np.ndarray, bool]:
    """The partial waves of one layer (tensor c, inertia s) at the directions ``th``: the
    impedances and exponents of its downward- and upward-decaying solutions.

    Parameters
    ----------
    c : ndarray, shape (3, 3, 3, 3)
        The layer's tensor over the stack's reference C44 (complex allowed).
    th, s : ndarray, shape (N,)
        Directions, rad, and ρω²/(C44_ref η²) (complex allowed).

    Returns
    -------
    (waves, mirror) : (ndarray, shape (4, 3, 3, N), complex; bool)
        D_d, D_u (module docstring) and A_d, A_u with X_d = exp(ηh A_d), X_u = exp(ηh A_u);
        ``mirror`` if z -> −z is a symmetry of the layer (then A_u = M A_d M and X_u = M X_d M,
        M = diag(1, 1, −1)). Each depends on (η, ω) only through s, so a table in s serves
        every frequency (``contactres.dynamic._layered_path``). An isotropic layer's come in
        closed form (:func:`_isotropic_impedance`), any other's from the Stroh solution.
    """
    parts, mirror = _wave_parts(c, th, s)
    return np.stack(parts), mirror


def _wave_parts(c, th, s) -> tuple[tuple[np.ndarray, ...], bool]:
    """:func:`layer_waves` as its four (3, 3, N) parts (D_d, D_u, A_d, A_u), not stacked: the
    recursion takes them apart again (:func:`stack_compliance`: the stack was a copy of ~3 MB
    per call at the coated table's ~5500 nodes)."""
    moduli = isotropic_moduli(c)
    if moduli is not None:
        # An isotropic solid (mirror-plane): D_d and A_d in closed form, no eigen-solution.
        th = np.asarray(th, dtype=float)
        D_d, A_d = _isotropic_impedance(moduli[0], moduli[1], th, s, exponent=True)
        return (D_d, -_flip(D_d), A_d, _flip(A_d)), True
    R, W = _rw_blocks(c, th)
    Wi = inv3(np.broadcast_to(W, R.shape).copy())
    Rt = transpose(R)
    mirror = _is_mirror(c)
    if mirror:
        # A mirror-plane solid (isotropic, cubic (001), ...): the pencil at θ + π is the one at θ
        # conjugated by M = diag(1, 1, −1), so H(θ + π) = M H(θ) M and X_u = M X_d M; one
        # half-space evaluation and one exponential instead of two.
        D_d = inv3(_halfspace(c, th, s))
        H_pi_inv = _flip(D_d)
        A_d = 1j * mm(Wi, -1j * D_d - Rt)
        A_u = _flip(A_d)
    else:
        # Both directions from one cyclic reduction (the pencil at θ + π is the reversed one).
        H, H_pi = surface_compliance_pair(c, th, s)
        D_d = inv3(np.ascontiguousarray(np.moveaxis(H, (-2, -1), (0, 1))))
        H_pi_inv = inv3(np.ascontiguousarray(np.moveaxis(H_pi, (-2, -1), (0, 1))))
        # Z = W⁻¹(−i D − Rᵀ) at θ, and at θ + π (where R -> −R): the decaying solvents.
        A_d = 1j * mm(Wi, -1j * D_d - Rt)
        A_u = 1j * mm(Wi, -1j * H_pi_inv + Rt)
    return (D_d, -H_pi_inv, A_d, A_u), mirror


def substrate_impedance(c, th, s) -> np.ndarray:
    """Y = H⁻¹ (3, 3, N) of the substrate half-space (tensor c, inertia s) at ``th``: what
    :func:`impedance_recursion` starts from (depends on (η, ω) only through s; in closed form
    for an isotropic substrate, :func:`_isotropic_impedance`)."""
    return _impedance(c, th, s)


def _layer_factors(waves, mirror: bool, eta_h, Y, theta=None):
    """(I + T, D_d + D_u T) of one layer (its :func:`layer_waves`, thickness ηh) over Y: the
    impedance at its top is their quotient (module docstring). ``theta``: the directions of an
    isotropic layer (its exponential then in closed form, :func:`._expm.expm_isotropic`)."""
    D_d, D_u, A_d, A_u = waves
    X_d = expm3(eta_h * A_d) if theta is None else expm_isotropic(A_d, eta_h, theta)
    X_u = _flip(X_d) if mirror else expm3(eta_h * A_u)
    rho = mm(inv3(D_u - Y), Y - D_d)
    T = mm(X_u, mm(rho, X_d))
    eye = np.eye(3)[..., None]
    return eye + T, D_d + mm(D_u, T)


def _layer_impedance(waves, mirror: bool, eta_h, Y, theta=None):
    """Impedance at the top of one layer (its :func:`layer_waves`, thickness ηh) over Y."""
    P, Q = _layer_factors(waves, mirror, eta_h, Y, theta)
    return mm(Q, inv3(P))


def impedance_recursion(layers, eta_h, Y, isotropic=None) -> np.ndarray:
    """Surface impedance Y_top (3, 3, N) of layers over a substrate of impedance Y.

    Parameters
    ----------
    layers : sequence of (ndarray, bool)
        :func:`layer_waves` of every layer, top first, each (4, 3, 3, N) (or its four parts)
        with its mirror flag.
    eta_h : sequence of ndarray, shape (N,)
        η h_j of every layer (complex on a lifted path).
    Y : ndarray, shape (3, 3, N)
        :func:`substrate_impedance`.
    isotropic : sequence of (None or ndarray, shape (N,)), optional
        Per layer, for a layer the caller knows to be isotropic, the direction θ (rad) of
        every point: its exponential exp(ηh A_d) is then formed in closed form (two roots,
        :func:`._expm.expm_isotropic`: a few elementwise operations instead of a scaled Taylor
        polynomial and its squarings; equal to ~1e-15); None (default) for the general one.

    Returns
    -------
    ndarray, complex, shape (3, 3, N)
        Y_top (module docstring); the stack's compliance is H = Y_top⁻¹. Non-finite where the
        stack is singular (no error here: :func:`stack_compliance` raises).
    """
    closed = [None] * len(layers) if isotropic is None else list(isotropic)
    with np.errstate(all="ignore"):
        for (waves, mirror), eh, th in zip(
            reversed(layers), reversed(eta_h), reversed(closed), strict=True
        ):
            Y = _layer_impedance(waves, mirror, eh, Y, th)
    return Y


def compliance_factors(layers, eta_h, Y, isotropic=None):
    """The stack's surface compliance as a quotient H = Y_top⁻¹ = P Q⁻¹ of two factors.

    With the top layer's I + T and D_d + D_u T (module docstring), Y_top = Q P⁻¹, so
    H = P Q⁻¹: one 3x3 inverse fewer than inverting :func:`impedance_recursion`, and a caller
    that needs a few entries of H (the normal entry H_33: row 3 of P and column 3 of Q⁻¹)
    forms only those.

    Parameters
    ----------
    layers, eta_h, Y, isotropic
        As in :func:`impedance_recursion` (at least one layer).

    Returns
    -------
    (P, Q) : (ndarray, ndarray), complex, each shape (3, 3, N)
        H = P Q⁻¹ (dimensionless); non-finite where the stack is singular.
    """
    if not layers:
        raise ContactresInputError("compliance_factors needs at least one layer")
    with np.errstate(all="ignore"):
        closed = [None] * len(layers) if isotropic is None else list(isotropic)
        below = impedance_recursion(layers[1:], eta_h[1:], Y, closed[1:])
        return _layer_factors(*layers[0], eta_h[0], below, closed[0])


def stack_compliance(tensors, s, eta_h, theta) -> np.ndarray:
    """Dimensionless surface compliance H of a layered half-space (impedance recursion).

    Parameters
    ----------
    tensors : sequence of ndarray, shape (3, 3, 3, 3)
        Stiffness tensors in the surface frame divided by one common reference C44, top layer
        first, the substrate last (complex allowed).
    s : sequence of array_like
        ρ_j ω²/(C44_ref η²) of every material (same order; 0 in statics; complex allowed).
    eta_h : sequence of array_like
        η h_j of every layer (one fewer than ``tensors``), dimensionless.
    theta : array_like
        Direction of the surface wave vector, rad.

    Returns
    -------
    ndarray, complex, shape ``broadcast(theta, s, eta_h).shape + (3, 3)``
        H with u(0) = H σ_i3(0)/(C44_ref η) (module docstring); for one tensor, exactly
        :func:`contactres.halfspace.surface_compliance`.
    """
    tensors = [np.asarray(c) for c in tensors]
    if len(s) != len(tensors) or len(eta_h) != len(tensors) - 1:
        raise ContactresInputError(
            "stack_compliance needs one s per material and one eta_h per layer"
        )
    arrays = np.broadcast_arrays(
        np.asarray(theta, dtype=float),
        *(np.asarray(v, dtype=complex) for v in s),
        *(np.asarray(v, dtype=complex) for v in eta_h),
    )
    shape = arrays[0].shape
    th = arrays[0].ravel()
    sv = [a.ravel() for a in arrays[1 : 1 + len(tensors)]]
    hv = [a.ravel() for a in arrays[1 + len(tensors) :]]
    if len(tensors) > 1:
        with np.errstate(all="ignore"):
            layers = [_wave_parts(c, th, v) for c, v in zip(tensors[:-1], sv[:-1], strict=True)]
            # An isotropic substrate's impedance and an isotropic layer's exponential in closed
            # form (the same as the general Stroh solution and Taylor exponential to ~1e-15,
            # without their cost: most of a static layered contact's kernel).
            closed = [th if isotropic_moduli(c) is not None else None for c in tensors[:-1]]
            Y = substrate_impedance(tensors[-1], th, sv[-1])
            H = inv3(impedance_recursion(layers, hv, Y, closed))
    else:
        H = _halfspace(tensors[-1], th, sv[-1])
    bad = ~np.all(np.isfinite(H), axis=(0, 1))
    if np.any(bad):
        i = np.flatnonzero(bad)[0]
        raise ContactresInputError(
            f"the surface response of the stack is singular at theta={th[i]:.6g} rad "
            "(a guided mode of a lossless stack on the real wavenumber axis): add loss "
            "(with_loss) or give the wavenumber a positive imaginary part"
        )
    return np.ascontiguousarray(np.moveaxis(H, (0, 1), (-2, -1))).reshape((*shape, 3, 3))


def _check_wavenumber(eta, lossy: bool) -> np.ndarray:
    eta = np.asarray(eta)
    if np.iscomplexobj(eta) and np.any(eta.imag != 0):
        if lossy:
            raise ContactresInputError(
                "complex wavenumber is supported for lossless materials only; "
                "for a lossy material use real wavenumber > 0"
            )
        bad = (eta.imag < 0) | ((eta.imag == 0) & ~(eta.real > 0))
    else:
        eta = eta.real if np.iscomplexobj(eta) else eta.astype(float)
        bad = ~(eta > 0)
    bad = bad | ~np.isfinite(eta)
    if np.any(bad):
        first = eta.ravel()[np.flatnonzero(bad.ravel())[0]]
        raise ContactresInputError(
            f"wavenumber must be finite and > 0 1/m (complex: Im >= 0, lossless only), got {first}"
        )
    return eta


def surface_green(material, wavenumber, theta, frequency: float = 0.0) -> np.ndarray:
    """Surface Green's function Ĝ(ξ) of a homogeneous or layered half-space, m/Pa.

    û_i(ξ) = Ĝ_ij(ξ) σ̂_j3(ξ) at the surface z = 0, in the surface frame (z the inward normal),
    with ξ = η (cos θ, sin θ), fields ∝ e^{i(ξ·x + ωt)} (Fourier transform
    f̂(ξ) = ∫ f(x) e^{−iξ·x} dx) and σ_j3 the stress in the solid at the surface; a traction t
    applied on the surface is σ_j3 = −t_j (so a force pressing into the solid is σ_33 < 0).
    Ĝ = H/(C44_ref η) with H the dimensionless compliance (:func:`stack_compliance`); for a
    homogeneous solid H = :func:`contactres.halfspace.surface_compliance`, and
    :func:`contactres.static_kernel` is Ĝ(θ) = −η Ĝ_33 at frequency 0.

    Layers are welded to each other and to the substrate (u and σ_i3 continuous); the
    substrate carries only decaying (lossless: outgoing) waves. The recursion is the stable
    surface-impedance form of the stiffness-matrix method (Rokhlin & Wang, J. Acoust. Soc. Am.
    112, 822 (2002)); see the docstring of the private module ``contactres.layered._recursion``
    for its derivation and accuracy.

    Parameters
    ----------
    material : Material, LayeredMaterial or frequency-dependent material
        In the surface frame (:meth:`LayeredMaterial.rotated` turns the whole stack).
    wavenumber : array_like
        η = ``|ξ|``, 1/m: real > 0; for a lossless material also complex with Im η > 0 (the
        analytic continuation, as for :func:`contactres.dynamic_kernel`).
    theta : array_like
        Direction of ξ, rad; broadcasts against ``wavenumber``.
    frequency : float, optional
        Frequency, Hz (0: statics, and the relaxed limit of a frequency-dependent material).
        Above 0 every material needs a density.

    Returns
    -------
    ndarray, complex, shape ``broadcast(wavenumber, theta).shape + (3, 3)``
        Ĝ_ij, m/Pa.

    Notes
    -----
    Reciprocity: Ĝ(θ + π) = Ĝ(θ)ᵀ; in statics of a lossless solid Ĝ is Hermitian. Passivity
    (e^{iωt}): the power into the solid per unit area under σ̂ is (ω/2) Im(σ̂ᴴ Ĝ σ̂) >= 0, so the
    anti-Hermitian part (Ĝ − Ĝᴴ)/(2i) is positive semi-definite. A lossless stack has guided-mode
    poles on the real η axis (see the private module ``contactres.layered._recursion``): there an
    error is raised.

    Examples
    --------
    The homogeneous isotropic static limit, −η Ĝ_33 = 2 (1 − ν²)/E (Boussinesq):

    >>> import numpy as np
    >>> from contactres import Material, surface_green
    >>> g = surface_green(Material.isotropic(70e9, 0.22), 1e6, 0.3)
    >>> bool(np.isclose(-1e6 * g[2, 2].real, 2 * (1 - 0.22**2) / 70e9, rtol=1e-12, atol=0))
    True
    """
    f = float(frequency)
    if not (math.isfinite(f) and f >= 0):
        raise ContactresInputError(f"frequency must be finite and >= 0 Hz, got {frequency!r}")
    if isinstance(material, LayeredMaterial):
        stack = material.at(f)
    elif isinstance(material, Material) or callable(getattr(material, "at", None)):
        stack = LayeredMaterial(material_at(material, f))
    else:
        raise ContactresInputError(
            "material must be a contactres.Material or LayeredMaterial, got "
            f"{type(material).__name__}"
        )
    mats = [material_at(m, f) for m in stack.materials]
    eta = _check_wavenumber(wavenumber, stack.is_lossy)
    c44 = shear_reference(mats[-1])
    for m in mats:
        shear_reference(m)
    omega2 = (2 * np.pi * f) ** 2
    missing = [j for j, m in enumerate(mats) if m.density is None]
    if omega2 > 0 and missing:
        j = missing[0]
        which = "the substrate" if j == len(mats) - 1 else f"layer {j + 1}"
        raise ContactresInputError(
            f"a dynamic surface response (frequency > 0) needs densities: {which} "
            f"({mats[j].name or 'unnamed'}) has none"
        )
    eta = np.asarray(eta, dtype=complex if np.iscomplexobj(eta) else float)
    tensors = [voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44 for m in mats]
    s = [(m.density or 0.0) * omega2 / (c44 * eta**2) for m in mats]
    H = stack_compliance(tensors, s, [eta * h for h in stack.thicknesses], theta)
    eta_b = np.broadcast_to(eta, H.shape[:-2])
    return H / (c44 * eta_b[..., None, None])
