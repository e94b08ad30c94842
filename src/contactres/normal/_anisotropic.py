"""Hertz contact of a rigid sphere on an anisotropic half-space (paper 1, Eqs. 1-4).

The half-space enters only through the angular integrals of its static surface Green's function
Ĝ(θ) (:func:`contactres.halfspace.static_kernel`):

    I₀ = ∫₀^{2π} Ĝ(θ) dθ,     I₁ = ∫₀^{2π} Ĝ(θ) cos²θ dθ,

    a³ = 3FR I₁/(8π),   p(r) = (4a/(R I₁)) √(1 − r²/a²),   w = a² I₀/(2R I₁),   K_sa = 8πa/I₀.

The indentation modulus M = 4π/I₀ is the E* of the isotropic solid on which a rigid sphere makes
the same contact (Vlassak & Nix, J. Mech. Phys. Solids 42, 1223 (1994)); isotropic: I₀ = 4π/E*.

Circular contact: the contact is exactly circular when the second angular harmonic of Ĝ vanishes,
∫ Ĝ(θ) e^{2iθ} dθ = 0, which 3- or 4-fold symmetry about the normal guarantees ((001) and (111)
of a cubic crystal). On other faces ((011) of a cubic crystal, low-symmetry cuts) the true contact
is slightly elliptic and the circular formulas above (with I₁ taken along the surface-frame x
axis, as in the paper) are an approximation; :class:`AnisotropicContact` reports
``circular`` and the relative size of that harmonic, ``noncircularity``.

Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", American Journal of Engineering and Applied Sciences 3(1), 56-63
(2010), doi:10.3844/ajeassp.2010.56.63.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ContactresInputError
from ..halfspace import static_kernel
from ..materials import Material, require_material
from ..validation import nonnegative, positive

__all__ = [
    "AnisotropicContact",
    "ContactIntegrals",
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
# Below this relative second harmonic the contact is reported as circular (round-off level).
_CIRCULAR_TOL = 1e-9
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
    """

    I0: complex | float
    I1: complex | float
    I2: complex
    n_theta: int
    error: float


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
class AnisotropicContact:
    """Static Hertz contact of a rigid sphere on an anisotropic half-space (paper 1, Eqs. 1-4).

    Attributes
    ----------
    contact_radius : a, m (Eq. 1)
    depth : indentation depth w (approach of the sphere to distant points), m (Eq. 3)
    mean_pressure : F/(π a²), Pa
    peak_pressure : pressure at the centre p0 = 4a/(R I₁), Pa (Eq. 2)
    stiffness : static contact stiffness K_sa = dF/dw = 8πa/I₀, N/m (Eq. 4)
    force : normal force F, N
    indentation_modulus : M = 4π/I₀, Pa
    I0, I1 : the angular integrals of Ĝ, 1/Pa
    circular : True when the contact is exactly circular (second harmonic of Ĝ vanishes, e.g. a
        3- or 4-fold face); False: the circular formulas are an approximation
    noncircularity : ``|I₂|``/I₀, the relative second harmonic of Ĝ (0 for a circular contact)
    model : "anisotropic-hertz"
    """

    contact_radius: np.ndarray | float
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


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def sphere_contact(m: Material, radius, force, rtol: float = THETA_RTOL) -> AnisotropicContact:
    """Hertz contact of a rigid sphere on the anisotropic half-space ``m`` (paper 1, Eqs. 1-4).

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
        Relative accuracy of the θ integrals I₀, I₁ (see :func:`contact_integrals`).

    Returns
    -------
    AnisotropicContact
        a³ = 3FR I₁/(8π), p0 = 4a/(R I₁), w = a² I₀/(2R I₁), K_sa = 8πa/I₀. Isotropic: the
        Hertz values with E* (a³ = 3FR/(4E*), w = a²/R, K_sa = 2aE*).

    Notes
    -----
    Exact for a face whose Ĝ has no second angular harmonic (3- or 4-fold symmetry about the
    normal). Elsewhere the true contact is elliptic; these circular formulas then use I₁ along
    the surface x axis (the paper's choice) and ``circular`` is False.

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
    """
    m = require_material(m)
    if m.is_lossy:
        raise ContactresInputError(
            "sphere_contact needs real (undamped) constants: the static contact of a lossy "
            "material is that of its elastic part (drop with_loss)"
        )
    R = np.asarray(positive("radius", radius, "m"))
    F = np.asarray(nonnegative("force", force, "N"))
    try:
        np.broadcast_shapes(R.shape, F.shape)
    except ValueError:
        raise ContactresInputError(
            f"radius (shape {R.shape}) and force (shape {F.shape}) do not broadcast together"
        ) from None
    ci = contact_integrals(m, rtol)
    I0, I1 = ci.I0, ci.I1
    a = np.cbrt(3 * F * R * I1 / (8 * np.pi))
    with np.errstate(divide="ignore", invalid="ignore"):
        mean_p = np.where(a > 0, F / (np.pi * a**2), 0.0)
    ratio = abs(ci.I2) / abs(I0)
    return AnisotropicContact(
        contact_radius=_out(a),
        depth=_out(a**2 * I0 / (2 * R * I1)),
        mean_pressure=_out(mean_p),
        peak_pressure=_out(4 * a / (R * I1)),
        stiffness=_out(8 * np.pi * a / I0),
        force=_out(F),
        indentation_modulus=4 * np.pi / I0,
        I0=I0,
        I1=I1,
        circular=bool(ratio <= _CIRCULAR_TOL),
        noncircularity=float(ratio),
    )
