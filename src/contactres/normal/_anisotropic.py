"""Hertz contact of a rigid sphere on an anisotropic half-space: an ellipse (paper 1, Eqs. 1-4;
Willis 1966; Vlassak et al. 2003).

The half-space enters only through its static surface Green's function Ĝ(θ)
(:func:`contactres.halfspace.static_kernel`: û_z = Ĝ(θ) p̂/η in the wave-vector domain,
ξ = η (cos θ, sin θ)) and its angular integrals

    I₀ = ∫₀^{2π} Ĝ(θ) dθ,     I₁ = ∫₀^{2π} Ĝ(θ) cos²θ dθ.

The indentation modulus M = 4π/I₀ is the E* of the isotropic solid on which a rigid sphere makes
nearly the same contact (Vlassak & Nix, J. Mech. Phys. Solids 42, 1223 (1994)); isotropic:
I₀ = 4π/E*. It does not depend on the in-plane axes of the surface frame.

The contact is an ellipse (J. R. Willis, J. Mech. Phys. Solids 14, 163 (1966); J. J. Vlassak,
M. Ciavarella, J. R. Barber, X. Wang, J. Mech. Phys. Solids 51, 1701 (2003)). Derivation used
here: the Hertz pressure p = p0 √(1 − xᵀA⁻¹x) on the ellipse xᵀA⁻¹x <= 1 (A symmetric positive,
semi-axes² its eigenvalues, ab = √det A) has the transform p̂(ξ) = ab p0 P(η s(θ)), with
s(θ)² = nᵀAn (n = (cos θ, sin θ), s the ellipse's support function) and P the transform of the
unit hemisphere, whose line integral ∫₀^∞ P(t) cos(tu) dt = π²(1 − u²)/2 for |u| <= 1 (the
projection-slice theorem). Inside the ellipse the displacement is therefore quadratic:

    u_z(x) = (ab p0/8) ∫₀^{2π} Ĝ(θ)/s(θ) [1 − (n·x)²/s(θ)²] dθ.

Matching it to the sphere's gap δ − |x|²/(2R) asks the matrix ∫ Ĝ n nᵀ/s³ dθ to be a multiple
of the identity. With A = λ Â, Â = I + ρ [[cos 2φ, sin 2φ], [sin 2φ, −cos 2φ]] (0 <= ρ < 1),
ŝ(θ)² = 1 + ρ cos 2(θ − φ) is linear in w = ρ (cos 2φ, sin 2φ), and these two conditions are the
stationarity of

    Φ(w) = ∫₀^{2π} Ĝ(θ)/ŝ(θ) dθ,

strictly convex in w (ŝ⁻¹ is a convex function of an affine one, Ĝ > 0) and infinite at ρ -> 1:
the shape (ρ, φ) is Φ's unique minimiser (found by Newton's method). Then, with
J = ½ ∫ Ĝ/ŝ³ dθ and Φ at the minimum (both I₀/2 = I₁ and I₀ on a circular face):

    a² = λ(1 + ρ),  b² = λ(1 − ρ),  λ^{3/2} = 3FRJ/(8π),
    p0 = 3F/(2πab),  δ = λ Φ/(2RJ),  K = dF/dδ = 3F/(2δ) = 8π√λ/Φ,

the semi-axes a >= b along φ and φ + π/2. On a face with a 3- or 4-fold axis ((001) and (111) of
a cubic crystal) Ĝ has no second angular harmonic, ρ = 0 and these are paper 1's circular
formulas a³ = 3FR I₁/(8π), δ = a² I₀/(2R I₁), K = 8πa/I₀.

Frame: turning the material about the normal only turns Ĝ(θ), so a, b, δ, p0, K stay and φ
follows the turn; I₁ (along the surface x axis) is the only frame-dependent number here.

Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", American Journal of Engineering and Applied Sciences 3(1), 56-63
(2010), doi:10.3844/ajeassp.2010.56.63.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._summary import Summarised, number
from ..errors import ContactresInputError
from ..halfspace import static_kernel
from ..materials import Material, require_material
from ..validation import nonnegative, positive
from ._isotropic import contact_facts

__all__ = [
    "AnisotropicContact",
    "ContactEllipse",
    "ContactIntegrals",
    "contact_ellipse",
    "contact_integrals",
    "contrast_poisson",
    "indentation_modulus",
    "isotropic_constants",
    "sphere_contact",
    "stiffness_contrast",
]

#: Default relative accuracy of I0, I1 (trapezoidal rule in θ, doubled until it moves less).
THETA_RTOL = 1e-12
# Doubling starts from this many points on [0, π) and stops with an error beyond the maximum.
_N_START = 16
_N_MAX = 2**15
# Below this relative second harmonic the contact is reported as circular (round-off level);
# the shape then differs from a circle by less than about this much (ρ is of the order of it).
_CIRCULAR_TOL = 1e-9
# Newton's method for the ellipse stops when its step in w (dimensionless) is below this, and
# gives up after _NEWTON_MAX steps (it converges quadratically: ~4 steps from a circle).
_NEWTON_STEP = 1e-14
_NEWTON_MAX = 60
# A stiffness is taken as isotropic when it equals the isotropic tensor of its own C12, C44 to
# this relative accuracy (round-off of a rotation is ~1e-16; a cubic crystal with A = 1 ± 1e-9
# is anisotropic for this purpose and takes the general rule, which is continuous through A = 1).
_ISOTROPIC_TOL = 1e-12
# Above this stiffness contrast a failed θ quadrature is blamed on round-off (near
# incompressibility) rather than on anisotropy: the general static kernel loses ~ε × contrast²
# (measured: 1.5e-7 pointwise at contrast 7500, isotropic ν = 0.4999).
_ROUNDOFF_CONTRAST = 1e3


def contrast_poisson(contrast: float) -> float:
    """ν of the isotropic solid with stiffness contrast 3K/(2G) = (1 + ν)/(1 − 2ν) =
    ``contrast`` (:func:`stiffness_contrast`), for messages; 0.5 for an infinite contrast."""
    return (contrast - 1) / (2 * contrast + 1) if np.isfinite(contrast) else 0.5


def stiffness_contrast(m: Material) -> float:
    """Largest over smallest eigenvalue of the Kelvin (Mandel) 6x6 form of the stiffness.

    Dimensionless and independent of the frame. Isotropic: 3K/(2G) = (1 + ν)/(1 − 2ν), which
    diverges at incompressibility; cubic: the ratio of the largest to the smallest of C11 + 2C12
    (bulk), C11 − C12 and 2C44 (shear). The conditioning of the half-space kernels
    (:mod:`contactres.halfspace`) degrades like its square.

    Parameters
    ----------
    m : Material
        Stiffness (real part used), Pa.

    Returns
    -------
    float
        λ_max/λ_min >= 1 (inf for a singular stiffness).
    """
    c = np.real(np.asarray(require_material(m).C, dtype=complex))
    # Mandel weights: √2 on the normal-shear blocks, 2 on the shear block, so that the
    # eigenvalues are those of the fourth-order tensor (Voigt's are not frame invariant).
    w = np.array([1.0, 1.0, 1.0, np.sqrt(2), np.sqrt(2), np.sqrt(2)])
    ev = np.linalg.eigvalsh(c * np.outer(w, w))
    return float(ev[-1] / ev[0]) if ev[0] > 0 else float("inf")


def isotropic_constants(m: Material):
    """(C11, C44) = (λ + 2μ, μ) if the stiffness of ``m`` is isotropic (in any frame), else None.

    Complex for a lossy material. The test: C equals the isotropic tensor built from its own
    C12 and C44 to a relative 1e-12 (the round-off of a rotated isotropic stiffness).
    """
    c = np.asarray(require_material(m).C)
    c11, c12, c44 = c[0, 0], c[0, 1], c[3, 3]
    iso = np.zeros((6, 6), dtype=c.dtype)
    iso[:3, :3] = c12
    iso[[0, 1, 2], [0, 1, 2]] = c12 + 2 * c44
    iso[[3, 4, 5], [3, 4, 5]] = c44
    if np.max(np.abs(c - iso)) > _ISOTROPIC_TOL * np.max(np.abs(c)):
        return None
    return c11, c44


@dataclass(frozen=True)
class ContactIntegrals:
    """The angular integrals of Ĝ(θ) (paper 1, Eqs. 1-4), 1/Pa (complex for a lossy solid).

    Attributes
    ----------
    I0 : ∫₀^{2π} Ĝ(θ) dθ
    I1 : ∫₀^{2π} Ĝ(θ) cos²θ dθ (θ from the surface-frame x axis)
    I2 : ∫₀^{2π} Ĝ(θ) e^{2iθ} dθ, the second harmonic (0 on a 3- or 4-fold face)
    n_theta : number of θ points on [0, π) of the trapezoidal rule that met the tolerance
    error : size of the last change when the points were doubled (an upper bound of the error
        of I0 in practice: the rule converges exponentially for the smooth periodic Ĝ)
    noncircularity, circular : properties: ``|I₂|``/``|I₀|``, and whether it is below 1e-9
        (the Hertz contact is then a circle)
    """

    I0: complex | float
    I1: complex | float
    I2: complex
    n_theta: int
    error: float

    @property
    def noncircularity(self) -> float:
        """``|I₂|``/``|I₀|``, the relative second harmonic of Ĝ."""
        return float(abs(self.I2) / abs(self.I0))

    @property
    def circular(self) -> bool:
        """Whether the Hertz contact is a circle: the second harmonic below 1e-9 of I₀ (round-off
        level; the ellipse then differs from a circle by about as little)."""
        return self.noncircularity <= _CIRCULAR_TOL


def _trapezoid(m: Material, n: int, prev=None):
    """Sums of Ĝ, Ĝ cos²θ, Ĝ e^{2iθ} over n equispaced θ in [0, π), reusing ``prev`` (n/2)."""
    if prev is None:
        theta = np.pi * np.arange(n) / n
    else:
        theta = np.pi * (np.arange(n // 2) + 0.5) / (n // 2)
    g = static_kernel(m, theta)
    sums = np.array([np.sum(g), np.sum(g * np.cos(theta) ** 2), np.sum(g * np.exp(2j * theta))])
    return sums if prev is None else prev + sums


def contact_integrals(m: Material, rtol: float = THETA_RTOL) -> ContactIntegrals:
    """I₀, I₁ (and the second harmonic I₂) of the static surface Green's function, 1/Pa.

    Ĝ(θ) is smooth and π-periodic (reciprocity), so the trapezoidal rule on [0, π) converges
    exponentially; the points are doubled (from 16) until I₀ and I₁ move by less than
    ``rtol`` relative to I₀. ``m.C`` must be given in the surface frame (use
    :meth:`Material.rotated`). An isotropic stiffness (in any frame) takes the closed form
    Ĝ = 2(1 − ν²)/E (``n_theta`` 1, ``error`` 0), exact up to incompressibility, where the
    general kernel loses digits to round-off.

    Raises
    ------
    ValueError
        For ``rtol`` outside [1e-15, 1e-2] or when 2^15 points do not reach it: for a nearly
        incompressible anisotropic solid (stiffness contrast > 1e3; the kernel's round-off,
        not the rule, limits the accuracy) or a very strongly anisotropic one; the message
        says which.
    """
    m = require_material(m)
    rtol = float(rtol)
    if not (1e-15 <= rtol <= 1e-2):
        raise ContactresInputError(f"rtol must lie in [1e-15, 1e-2], got {rtol!r}")
    iso = isotropic_constants(m)
    if iso is not None:
        # Closed form, Ĝ = 2(1 − ν²)/E = C11/(2 C44 (C11 − C44)): exact for every ν < 1/2,
        # where the general kernel loses digits near incompressibility (ν >= 0.4999).
        c11, c44 = iso
        g = c11 / (2 * c44 * (c11 - c44))
        I0, I1 = 2 * np.pi * g, np.pi * g
        if not m.is_lossy:
            I0, I1 = float(np.real(I0)), float(np.real(I1))
        return ContactIntegrals(I0=I0, I1=I1, I2=0j, n_theta=1, error=0.0)
    n = _N_START
    sums = _trapezoid(m, n)
    while True:
        n2 = 2 * n
        new = _trapezoid(m, n2, prev=sums)
        I_old = 2 * np.pi / n * sums
        I_new = 2 * np.pi / n2 * new
        err = float(np.max(np.abs(I_new[:2] - I_old[:2])) / abs(I_new[0]))
        n, sums = n2, new
        if err <= rtol:
            break
        if n >= _N_MAX:
            contrast = stiffness_contrast(m)
            if contrast > _ROUNDOFF_CONTRAST:
                nu = contrast_poisson(contrast)
                reason = (
                    f"the solid is nearly incompressible (stiffness contrast {contrast:.4g}, "
                    f"as an isotropic solid with nu = {nu:.6g}): the static kernel loses "
                    "digits to round-off; pass a larger rtol"
                )
            else:
                reason = "the solid is too anisotropic for it"
            raise ContactresInputError(
                f"contact_integrals: the theta quadrature did not reach rtol={rtol:g} with "
                f"{n} points (last change {err:.3g}); {reason}"
            )
    I0, I1, I2 = (2 * np.pi / n * sums).tolist()
    if not m.is_lossy:
        I0, I1 = float(np.real(I0)), float(np.real(I1))
    return ContactIntegrals(I0=I0, I1=I1, I2=complex(I2), n_theta=n, error=err * abs(I0))


def indentation_modulus(m: Material, rtol: float = THETA_RTOL) -> complex | float:
    """Indentation modulus M = 4π/I₀, Pa (paper 1, Eq. 4; Vlassak & Nix 1994).

    A rigid sphere on ``m`` (stiffness in the surface frame) behaves as on an isotropic solid
    with E* = M: K_sa = 2aM. Isotropic: M = E/(1 − ν²), in closed form for every ν < 1/2.
    Complex for a lossy material.

    Raises
    ------
    ValueError
        When the θ quadrature of an anisotropic solid does not reach ``rtol``; the message
        says whether round-off (a nearly incompressible solid, :func:`stiffness_contrast`)
        or strong anisotropy is the reason.

    Examples
    --------
    For an isotropic solid M is the plane-strain modulus E/(1 − ν²):

    >>> import math
    >>> from contactres import Material, indentation_modulus
    >>> math.isclose(indentation_modulus(Material.isotropic(70e9, 0.22)), 70e9 / (1 - 0.22**2))
    True

    Copper is stiffest along [111]:

    >>> cu = Material.crystal("Cu")
    >>> for hkl in [(0, 0, 1), (1, 1, 1)]:
    ...     print(hkl, f"{indentation_modulus(cu.rotated(hkl)) / 1e9:.1f} GPa")
    (0, 0, 1) 134.0 GPa
    (1, 1, 1) 151.6 GPa
    """
    I0 = contact_integrals(m, rtol).I0
    return 4 * np.pi / I0


@dataclass(frozen=True)
class ContactEllipse:
    """Shape of the Hertz contact of a sphere on an anisotropic half-space (module docstring).

    Independent of the load and of the sphere's radius; frame-invariant but for ``orientation``,
    which turns with the surface frame.

    Attributes
    ----------
    rho : ρ in [0, 1): the semi-axes are a = √(λ(1 + ρ)) >= b = √(λ(1 − ρ)) (0: a circle)
    orientation : φ, rad, in (−π/2, π/2]: the angle from the surface-frame x axis to the major
        axis, positive towards y (counter-clockwise seen from outside the solid, z the inward
        normal); 0 for a circle
    ellipticity : b/a = √((1 − ρ)/(1 + ρ)), 1 for a circle
    curvature_integral : J = ½ ∫₀^{2π} Ĝ/ŝ³ dθ, 1/Pa (I₁ = I₀/2 on a circular face)
    depth_integral : Φ = ∫₀^{2π} Ĝ/ŝ dθ at the minimum, 1/Pa (I₀ on a circular face; Φ <= I₀)
    n_theta : θ points on [0, π) of the trapezoidal rule that met the tolerance (1: closed form)
    error : the last change of w = ρ (cos 2φ, sin 2φ), J/J or Φ/Φ when the points were doubled
        (0: closed form)
    """

    rho: float
    orientation: float
    ellipticity: float
    curvature_integral: float
    depth_integral: float
    n_theta: int
    error: float


def _ellipse_newton(g, theta, w):
    """Minimise Φ(w) = Σ Ĝ/ŝ on one θ grid by Newton's method from ``w``; (w, J, Φ) as sums.

    Φ is strictly convex (module docstring): a step is halved while it leaves ρ < 1 or raises Φ
    beyond round-off, so the iteration cannot diverge.
    """
    c2, s2 = np.cos(2 * theta), np.sin(2 * theta)

    def phi_of(w):
        return np.sum(g / np.sqrt(1 + w[0] * c2 + w[1] * s2))

    phi = phi_of(w)
    for _ in range(_NEWTON_MAX):
        q = 1 + w[0] * c2 + w[1] * s2
        q3, q5 = g * q**-1.5, g * q**-2.5
        grad = -0.5 * np.array([np.sum(q3 * c2), np.sum(q3 * s2)])
        hess = 0.75 * np.array(
            [
                [np.sum(q5 * c2 * c2), np.sum(q5 * c2 * s2)],
                [np.sum(q5 * c2 * s2), np.sum(q5 * s2 * s2)],
            ]
        )
        step = -np.linalg.solve(hess, grad)
        t = 1.0
        while True:
            trial = w + t * step
            if np.hypot(*trial) < 1:
                new = phi_of(trial)
                if new <= phi * (1 + 1e-13):
                    break
            t /= 2
            if t < 1e-6:
                raise ContactresInputError("contact_ellipse: Newton's line search failed")
        w, phi = trial, new
        if t * np.max(np.abs(step)) <= _NEWTON_STEP:
            q = 1 + w[0] * c2 + w[1] * s2
            return w, 0.5 * np.sum(g * q**-1.5), np.sum(g / np.sqrt(q))
    raise ContactresInputError("contact_ellipse: Newton's method did not converge")


def _pair_kernel(m: Material, indenter: Material | None):
    """Ĝ(θ) of the plate ``m`` plus that of the sphere ``indenter`` in the plate's frame, 1/Pa.

    The sphere's frame is the plate's turned by π about x (x, −y, −z: z its own inward normal),
    so its kernel at the plate's θ is Ĝ_sphere(−θ); the two bodies take the same pressure and
    their normal displacements add to the approach. An isotropic sphere: its constant
    C11/(2 C44 (C11 − C44)) = 2/E*, exact up to incompressibility."""
    if indenter is None:
        return lambda theta: static_kernel(m, theta)
    iso = isotropic_constants(indenter)
    if iso is not None:
        c11, c44 = iso
        g_sphere = float(np.real(c11 / (2 * c44 * (c11 - c44))))
        return lambda theta: static_kernel(m, theta) + g_sphere
    return lambda theta: static_kernel(m, theta) + static_kernel(indenter, -theta)


def pair_integrals(m: Material, indenter: Material | None, rtol: float = THETA_RTOL):
    """:func:`contact_integrals` of the plate ``m`` and a sphere ``indenter`` together (or of
    ``m`` alone for None): I₀ and I₁ add, the sphere's I₂ enters conjugated (its Ĝ(−θ))."""
    ci = contact_integrals(m, rtol)
    if indenter is None:
        return ci
    cs = contact_integrals(require_material(indenter, lossless=True), rtol)
    return ContactIntegrals(
        I0=ci.I0 + cs.I0,
        I1=ci.I1 + cs.I1,
        I2=ci.I2 + np.conj(cs.I2),
        n_theta=max(ci.n_theta, cs.n_theta),
        error=ci.error + cs.error,
    )


def contact_ellipse(
    m: Material, rtol: float = THETA_RTOL, *, indenter: Material | None = None
) -> ContactEllipse:
    """Shape of the Hertz contact of a sphere on the anisotropic half-space ``m`` (an ellipse).

    Minimises Φ(w) = ∫ Ĝ(θ)/ŝ(θ) dθ over the shape w = ρ (cos 2φ, sin 2φ), ŝ² = 1 + w·(cos 2θ,
    sin 2θ) (the derivation from Willis 1966 is in the module docstring), on the trapezoidal rule
    in θ on [0, π) (the integrands are smooth and π-periodic), the points doubled from 16 until ρ
    (absolutely), J and Φ (relatively) move by less than ``rtol``. An isotropic stiffness takes
    the closed form (a circle, J = I₁, Φ = I₀ of :func:`contact_integrals`).

    Parameters
    ----------
    m : Material
        Lossless stiffness in the surface frame (z the inward normal), Pa.
    rtol : float
        Accuracy, in [1e-15, 1e-2].
    indenter : Material, optional
        The sphere's material (lossless, in its own frame: the plate's turned by π about x, z
        its inward normal); default rigid. Its Ĝ(−θ) adds to the plate's.

    Returns
    -------
    ContactEllipse
        ρ, orientation φ (rad, major axis from the surface x axis, towards y), ellipticity b/a,
        J and Φ (1/Pa).

    Raises
    ------
    ContactresInputError
        A lossy material, ``rtol`` out of range, or 2^15 points not reaching it.

    Examples
    --------
    On Cu (011) the contact is longer along [0 1 −1] (the surface y axis of
    ``rotated((0, 1, 1))``) than along [100]:

    >>> import numpy as np
    >>> from contactres import Material, contact_ellipse
    >>> e = contact_ellipse(Material.crystal("Cu").rotated((0, 1, 1)))
    >>> print(f"b/a = {e.ellipticity:.4f}, phi = {np.degrees(e.orientation):.1f} deg")
    b/a = 0.9287, phi = 90.0 deg
    """
    m = require_material(m)
    if m.is_lossy:
        raise ContactresInputError(
            "contact_ellipse needs real (undamped) constants: the static contact of a lossy "
            "material is that of its elastic part (drop with_loss; of a viscoelastic solid: "
            ".storage(f_Hz))"
        )
    rtol = float(rtol)
    if not (1e-15 <= rtol <= 1e-2):
        raise ContactresInputError(f"rtol must lie in [1e-15, 1e-2], got {rtol!r}")
    if indenter is not None:
        indenter = require_material(indenter, lossless=True)
    if isotropic_constants(m) is not None and (
        indenter is None or isotropic_constants(indenter) is not None
    ):
        ci = pair_integrals(m, indenter, rtol)
        return ContactEllipse(0.0, 0.0, 1.0, float(ci.I1), float(ci.I0), 1, 0.0)
    kernel = _pair_kernel(m, indenter)
    n = _N_START
    theta = np.pi * np.arange(n) / n
    g = kernel(theta)
    w, J, phi = _ellipse_newton(g, theta, np.zeros(2))
    while True:
        # Double the points: the old ones interleaved with the midpoints.
        mid = theta + np.pi / (2 * n)
        theta = np.stack([theta, mid], axis=1).ravel()
        g = np.stack([g, kernel(mid)], axis=1).ravel()
        n *= 2
        w_new, J_new, phi_new = _ellipse_newton(g, theta, w)
        scale = 2 * np.pi / n
        err = max(
            float(np.hypot(*(w_new - w))),
            abs(J_new * scale - J * 2 * scale) / (J_new * scale),
            abs(phi_new * scale - phi * 2 * scale) / (phi_new * scale),
        )
        w, J, phi = w_new, J_new, phi_new
        if err <= rtol:
            break
        if n >= _N_MAX:
            raise ContactresInputError(
                f"contact_ellipse: the theta quadrature did not reach rtol={rtol:g} with {n} "
                f"points (last change {err:.3g})"
            )
    rho = float(np.hypot(*w))
    # A component at round-off of ρ is zero: an axis along x or y is reported as exactly 0 or
    # 90 degrees, not 3e-14 (far below the quadrature's rtol, so nothing else moves).
    wx, wy = (0.0 if abs(float(c)) <= 1e-12 * rho else float(c) for c in w)
    orientation = 0.5 * float(np.arctan2(wy, wx)) if rho > 0 else 0.0
    # atan2 gives (−π, π]: keep φ in (−π/2, π/2], an axis at −π/2 up to round-off is at +π/2.
    if orientation <= -np.pi / 2 + 1e-12:
        orientation += np.pi
    return ContactEllipse(
        rho=rho,
        orientation=orientation,
        ellipticity=float(np.sqrt((1 - rho) / (1 + rho))),
        curvature_integral=float(2 * np.pi / n * J),
        depth_integral=float(2 * np.pi / n * phi),
        n_theta=n,
        error=float(err),
    )


# repr=False: the summary (Summarised, _facts) replaces numpy reprs of array fields.
@dataclass(frozen=True, repr=False)
class AnisotropicContact(Summarised):
    """Static Hertz contact of a rigid (or elastic) sphere on an anisotropic half-space: an
    ellipse (module docstring; paper 1, Eqs. 1-4, on a circular face).

    Every field but ``orientation`` and ``I1`` is independent of the in-plane axes of the surface
    frame.

    Attributes
    ----------
    contact_radius : equivalent radius √(ab) of the elliptic contact (its area is π a b), m; the
        Hertz radius a of Eq. 1 on a circular face
    semi_major, semi_minor : semi-axes a >= b of the contact ellipse, m
    orientation : φ, rad, in (−π/2, π/2]: angle from the surface-frame x axis to the major axis,
        positive towards y; 0 for a circular contact
    ellipticity : b/a (1 for a circular contact)
    depth : indentation depth δ (approach of the sphere to distant points), m (Eq. 3)
    mean_pressure : F/(π a b), Pa
    peak_pressure : pressure at the centre p0 = 3F/(2π a b), Pa (Eq. 2)
    stiffness : static normal contact stiffness dF/dδ = 8π√λ/Φ, N/m (Eq. 4: 8πa/I₀ on a circle)
    force : normal force F, N
    indentation_modulus : M = 4π/I₀, Pa
    I0, I1 : the angular integrals of Ĝ, 1/Pa (I₁ along the surface x axis: frame-dependent)
    circular : True when the contact is circular (second harmonic of Ĝ below 1e-9 of I₀, e.g. a
        3- or 4-fold face)
    noncircularity : ``|I₂|``/I₀, the relative second harmonic of Ĝ (0 for a circular contact)
    model : "anisotropic-hertz"
    """

    contact_radius: np.ndarray | float
    semi_major: np.ndarray | float
    semi_minor: np.ndarray | float
    orientation: float
    ellipticity: float
    depth: np.ndarray | float
    mean_pressure: np.ndarray | float
    peak_pressure: np.ndarray | float
    stiffness: np.ndarray | float
    force: np.ndarray | float
    indentation_modulus: complex | float  # complex for a lossy solid, as I0 and I1
    I0: complex | float
    I1: complex | float
    circular: bool
    noncircularity: float
    model: str = "anisotropic-hertz"

    def _facts(self) -> list[tuple[str, str]]:
        """As :class:`Contact`'s, with M (GPa) and b/a."""
        facts = contact_facts(self)
        facts += [("M", number(self.indentation_modulus, "GPa", 1e9))]
        return [*facts, ("b/a", "1 (circular)" if self.circular else number(self.ellipticity))]


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def sphere_contact(
    m: Material,
    radius,
    force,
    rtol: float = THETA_RTOL,
    *,
    indenter: Material | None = None,
) -> AnisotropicContact:
    """Hertz contact of a rigid (or elastic) sphere on the anisotropic half-space ``m``: an
    ellipse (module docstring; Willis 1966, Vlassak et al. 2003; paper 1, Eqs. 1-4, on a
    circular face).

    Parameters
    ----------
    m : Material
        Lossless stiffness in the surface frame (z = inward normal); for a crystal face (hkl)
        pass ``Material.crystal("Cu").rotated((h, k, l))``.
    radius : float or array
        Sphere radius R > 0, m.
    force : float or array
        Normal force F >= 0, N (broadcasts against ``radius``).
    rtol : float
        Relative accuracy of the θ integrals (see :func:`contact_integrals` and
        :func:`contact_ellipse`).
    indenter : Material, optional
        The sphere's material (lossless, homogeneous, in its own frame: the plate's turned by π
        about x, z its inward normal); default rigid. Its surface compliance adds to the
        plate's (Hertz's 1/E* = 1/E*_1 + 1/E*_2 in the isotropic case); ``indentation_modulus``,
        ``I0`` and ``I1`` are then those of the two bodies together.

    Returns
    -------
    AnisotropicContact
        Semi-axes a >= b, orientation φ of the major axis, ``contact_radius`` √(ab), depth δ,
        pressures, stiffness dF/dδ. On a circular face (``circular``: second harmonic of Ĝ
        below 1e-9 of I₀): a³ = 3FR I₁/(8π), p0 = 4a/(R I₁), δ = a² I₀/(2R I₁), K = 8πa/I₀;
        isotropic: the Hertz values with E* (a³ = 3FR/(4E*), δ = a²/R, K = 2aE*).

    Notes
    -----
    On a face without a 3- or 4-fold axis the Hertz contact with M (a circle, K = 2aM, the route
    of the maps) is an approximation of this one: within 0.3 % in K on the built-in crystals
    (Cu (011): 0.07 %, b/a = 0.93; Li (011): 0.27 %, b/a = 0.86).

    Examples
    --------
    On an isotropic half-space the contact is Hertz with E* = M (rigid sphere):

    >>> import numpy as np
    >>> from contactres import Material, hertz, indentation_modulus, sphere_contact
    >>> glass = Material.isotropic(70e9, 0.22)
    >>> c = sphere_contact(glass, 5e-6, 1e-3)  # radius m, force N
    >>> print(f"a = {float(c.contact_radius) * 1e9:.1f} nm")
    a = 370.8 nm
    >>> a_hertz = hertz(indentation_modulus(glass), 5e-6, 1e-3).contact_radius
    >>> bool(np.isclose(c.contact_radius, a_hertz, atol=0))
    True

    On Cu (011) the contact is an ellipse; turning the crystal about the normal turns it:

    >>> cu = Material.crystal("Cu").rotated((0, 1, 1))
    >>> c = sphere_contact(cu, 1e-3, 1.0)
    >>> print(f"a = {c.semi_major * 1e6:.3f} um, b = {c.semi_minor * 1e6:.3f} um, "
    ...       f"phi = {np.degrees(c.orientation):.1f} deg, K = {c.stiffness / 1e6:.4f} MN/m")
    a = 17.818 um, b = 16.547 um, phi = 90.0 deg, K = 5.0737 MN/m
    """
    m = require_material(m)
    if m.is_lossy:
        raise ContactresInputError(
            "sphere_contact needs real (undamped) constants: the static contact of a lossy "
            "material is that of its elastic part (drop with_loss; of a viscoelastic solid: "
            ".storage(f_Hz))"
        )
    R = np.asarray(positive("radius", radius, "m"))
    F = np.asarray(nonnegative("force", force, "N"))
    try:
        np.broadcast_shapes(R.shape, F.shape)
    except ValueError:
        raise ContactresInputError(
            f"radius (shape {R.shape}) and force (shape {F.shape}) do not broadcast together"
        ) from None
    ci = pair_integrals(m, indenter, rtol)
    I0, I1 = ci.I0, ci.I1
    ratio, circular = ci.noncircularity, ci.circular
    if circular:
        # Paper 1's circle: J = I₁, Φ = I₀ (the same formulas as the ellipse's with ρ = 0).
        rho, phi0, ell, J, Phi = 0.0, 0.0, 1.0, I1, I0
    else:
        e = contact_ellipse(m, rtol, indenter=indenter)
        rho, phi0, ell = e.rho, e.orientation, e.ellipticity
        J, Phi = e.curvature_integral, e.depth_integral
    # √λ, the geometric scale of the ellipse: λ^{3/2} = 3FRJ/(8π) (module docstring).
    s = np.cbrt(3 * F * R * J / (8 * np.pi))
    major, minor = s * np.sqrt(1 + rho), s * np.sqrt(1 - rho)
    area = major * minor  # a b: s² √(1 − ρ²)
    with np.errstate(divide="ignore", invalid="ignore"):
        mean_p = np.where(area > 0, F / (np.pi * area), 0.0)
    return AnisotropicContact(
        contact_radius=_out(np.sqrt(area) if rho else s),
        semi_major=_out(major),
        semi_minor=_out(minor),
        orientation=float(phi0),
        ellipticity=float(ell),
        depth=_out(s**2 * Phi / (2 * R * J)),
        mean_pressure=_out(mean_p),
        # p0 = 3F/(2πab) = 4√λ/(R J √(1 − ρ²)), finite at F = 0
        peak_pressure=_out(4 * s / (R * J * np.sqrt(1 - rho**2))),
        stiffness=_out(8 * np.pi * s / Phi),
        force=_out(F),
        indentation_modulus=4 * np.pi / I0,
        I0=I0,
        I1=I1,
        circular=circular,
        noncircularity=float(ratio),
    )
