"""Static contact of rigid punches and spheres on coated (layered) substrates (issue 26, point 2).

The functions here take a homogeneous :class:`~contactres.Material` or a
:class:`~contactres.LayeredMaterial` (bonded layers on a half-space; every material in the
surface frame, z the inward normal) and solve the axisymmetric contact problem of
:mod:`contactres.normal._axisymmetric` with the θ-averaged radial compliance of the solid, taken
from its surface Green's function Ĝ(η, θ) (:func:`contactres.surface_green`, û_i = Ĝ_ij σ̂_j3,
σ_j3 = −t_j for a traction t applied to the solid) at frequency 0:

    normal:      g(η) = −η ⟨Ĝ_33⟩                    (isotropic homogeneous: 2(1 − ν²)/E),
    tangential:  g(η) = −η ⟨(Ĝ_11 + Ĝ_22)/2⟩,        (isotropic homogeneous: (2 − ν)/(2G)),
                 d(η) = −η ⟨(cos 2θ (Ĝ_11 − Ĝ_22) + sin 2θ (Ĝ_12 + Ĝ_21))/2⟩   (−ν/(2G)),

⟨⟩ = (1/2π) ∫₀^{2π} dθ, the tangential stiffness for a motion along the surface-frame x axis.
g∞ = g(η -> ∞) is the top layer's homogeneous value (η Ĝ of a homogeneous solid does not depend on
η), and Δg = g − g∞ decays like e^{−2ηh} (h the top layer's thickness).

Tangential (the relaxed, bonded punch: no normal traction, a rigid in-plane motion U e_x). For a
transversely isotropic stack (isotropic layers) the in-plane kernel is Ĝ = −(g I + d Q)/η with
Q = [[cos 2θ, sin 2θ], [sin 2θ, −cos 2θ]]: Q maps a traction along x, t_x = f(r), onto the pattern
g(r) (cos 2φ, sin 2φ) and back, so the exact traction is f(r) e_x + g(r) (cos 2φ, sin 2φ), which
:mod:`contactres.normal._axisymmetric` solves (Galerkin on both, coupled through d). For a
homogeneous solid d ∝ 1/η does not couple f's force-carrying term, and Mindlin's traction
t ∝ (1 − r̄²)^{-1/2} e_x is exact; on a coated solid the pattern carries ~0.1 % of the stiffness
(measured: PMMA on glass, a/h = 1-30).

Approximations, stated:

- Anisotropic layers: the θ averages are the axisymmetric approximation (exact when every layer is
  transversely isotropic about the normal, e.g. isotropic layers; on a homogeneous face without
  a 3- or 4-fold axis it is Hertz with the indentation modulus M, a circle, where
  :func:`contactres.sphere_contact` solves the ellipse). The
  tangential Galerkin then works on the two-function family above, a subspace of the true
  tractions: a lower bound of the stiffness (exact for a homogeneous face that is a mirror
  plane, e.g. cubic (001), where the x direction is also a symmetry direction).

The θ average is the trapezoidal rule on [0, π) (Ĝ_33 and the traces are π-periodic by
reciprocity), with the number of angles doubled until the average of every material's
homogeneous kernel moves by less than 1e-13; a stack whose materials are all isotropic needs one
angle (normal: Ĝ_33 does not depend on θ; tangential: the trace and the Q part of the in-plane
block do not either, see ``_angles``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .._summary import Summarised, values
from ..errors import ContactresInputError
from ..layered import LayeredMaterial, surface_green
from ..materials import Material, require_material
from ..numerics import illinois_step
from ..validation import nonnegative, positive
from ._anisotropic import THETA_RTOL, isotropic_constants, pair_integrals
from ._anisotropic import sphere_contact as homogeneous_sphere_contact
from ._axisymmetric import DEFAULT_TOL, RadialKernel, punch_and_sphere
from ._isotropic import contact_facts
from ._validity import checked

__all__ = [
    "LayeredContact",
    "indentation_modulus_at",
    "radial_kernel",
    "sphere_contact",
    "sphere_contact_at",
    "static_punch_stiffness",
]

# θ average: doubled from this many angles on [0, π) until it moves by less than _THETA_RTOL.
_THETA_START = 8
_THETA_MAX = 2**10
_THETA_RTOL = 1e-13
# Probe wavenumber for the homogeneous kernels (η Ĝ of a homogeneous solid is independent of η).
_PROBE = 1.0
_DIRECTIONS = {"normal": 2, "tangential": 0}


def _stack(material) -> LayeredMaterial:
    if isinstance(material, LayeredMaterial):
        stack = material.at(0.0)
    elif isinstance(material, Material) or callable(getattr(material, "at", None)):
        stack = LayeredMaterial(material).at(0.0)
    else:
        raise ContactresInputError(
            "material must be a contactres.Material or LayeredMaterial, got "
            f"{type(material).__name__}"
        )
    return stack


def _angles(stack: LayeredMaterial, comp: int) -> np.ndarray:
    """θ points on [0, π) that average the kernel of every material of the stack, each as a
    homogeneous half-space, to 1e-13 (module docstring)."""
    if all(isotropic_constants(m) is not None for m in stack.materials):
        # Transversely isotropic about z: Ĝ_33 does not depend on θ, and the in-plane block is
        # A ê ê + B (I − ê ê) (ê = (cos θ, sin θ)), so (Ĝ_11 + Ĝ_22)/2 = (A + B)/2 and
        # cos 2θ (Ĝ_11 − Ĝ_22) + sin 2θ (Ĝ_12 + Ĝ_21) = A − B at every θ: one angle is exact
        # (four cost four times the kernel, which is most of a tangential punch).
        return np.zeros(1)
    ends = [LayeredMaterial(m) for m in stack.materials]
    n, prev = _THETA_START, None
    while True:
        theta = np.pi * np.arange(n) / n
        vals = np.array(
            [np.mean(surface_green(m, _PROBE, theta)[:, comp, comp]) for m in ends], dtype=complex
        )
        if prev is not None and np.max(np.abs(vals - prev)) <= _THETA_RTOL * np.max(np.abs(vals)):
            return theta
        if n >= _THETA_MAX:
            raise ContactresInputError(
                f"the theta average of the surface response did not converge with {n} angles: "
                "the layers are too anisotropic for the axisymmetric solution"
            )
        prev, n = vals, 2 * n


def radial_kernel(material, direction: str = "normal") -> RadialKernel:
    """The θ-averaged static radial compliance g(η) of ``material`` (module docstring).

    Parameters
    ----------
    material : Material or LayeredMaterial
        In the surface frame (z the inward normal); static (frequency 0) constants.
    direction : {"normal", "tangential"}
        Normal: g = −η ⟨Ĝ_33⟩. Tangential: g = −η ⟨(Ĝ_11 + Ĝ_22)/2⟩ and the coupling
        d = −η ⟨(cos 2θ (Ĝ_11 − Ĝ_22) + sin 2θ (Ĝ_12 + Ĝ_21))/2⟩ (⟨⟩ the θ average).

    Returns
    -------
    RadialKernel
        g∞ (1/Pa) of the top material (and d∞ for tangential), the excess over it (None without
        layers) and the lengths of the stack.
    """
    if direction not in _DIRECTIONS:
        raise ContactresInputError(f"direction must be 'normal' or 'tangential', got {direction!r}")
    comp = _DIRECTIONS[direction]
    stack = _stack(material)
    theta = _angles(stack, comp)
    top = LayeredMaterial(stack.top)
    c2, s2 = np.cos(2 * theta), np.sin(2 * theta)

    def average(m, eta):
        eta = np.asarray(eta, dtype=float)
        G = surface_green(m, eta[..., None], theta)
        if comp == 2:
            return -eta * np.mean(G[..., 2, 2], axis=-1)
        g = 0.5 * (G[..., 0, 0] + G[..., 1, 1])
        d = 0.5 * (c2 * (G[..., 0, 0] - G[..., 1, 1]) + s2 * (G[..., 0, 1] + G[..., 1, 0]))
        return -eta * np.stack([np.mean(g, axis=-1), np.mean(d, axis=-1)])

    def real(x):
        return x if stack.is_lossy else np.real(x)

    inf = real(np.asarray(average(top, _PROBE), dtype=complex))
    g_inf = inf[()] if comp == 2 else inf[0][()]
    d_inf = None if comp == 2 else inf[1][()]
    if not stack.layers:
        return RadialKernel(g_inf=g_inf, coupling_inf=d_inf)
    h = stack.thicknesses

    def excess(eta):
        ref = g_inf if comp == 2 else inf.reshape(2, *[1] * np.ndim(eta))
        return real(average(stack, eta) - ref)

    return RadialKernel(
        g_inf=g_inf,
        excess=excess,
        lengths=(float(h.min()), float(h.sum())),
        coupling_inf=d_inf,
    )


def _radii(name: str, radius) -> np.ndarray:
    return np.asarray(positive(name, radius, "m"), dtype=float)


def _shaped(x, shape):
    x = np.asarray(x).reshape(shape)
    return x[()] if x.ndim == 0 else x


def static_punch_stiffness(
    material,
    radius,
    direction: str = "normal",
    *,
    tol: float = DEFAULT_TOL,
    indenter: Material | None = None,
    transforms: dict | None = None,
):
    """Static stiffness of a rigid flat circular punch on a homogeneous or layered half-space.

    :func:`contactres.flat_punch_stiffness` is the same at frequency 0 and adds the dynamic
    punch.

    Normal: frictionless, K = F/δ (uniform normal displacement δ, no shear traction).
    Tangential: bonded (no slip) and relaxed (no normal traction), K = F_x/U_x for a rigid motion
    U_x along the surface x axis (module docstring for the axisymmetric approximation).

    Parameters
    ----------
    material : Material or LayeredMaterial
        In the surface frame (z the inward normal), Pa; a lossy material gives a complex K
        (correspondence principle, static constants ``at(0)``).
    radius : float or array
        Punch radius a > 0, m.
    direction : {"normal", "tangential"}
        Which stiffness.
    tol : float
        Truncation of the kernel integral (:mod:`contactres.normal._axisymmetric`; the default
        leaves < 1e-9 relative).
    indenter : Material, optional
        A second, homogeneous body bonded to the punch face from above (default: none, a rigid
        punch): the stiffness of the two bodies' contact of radius a, both taking the same
        traction (equal and opposite), so their surface compliances add (normal g∞, and for
        tangential g∞ and d∞: module docstring) — not the two punch stiffnesses in series,
        which is an upper bound (two separately optimal tractions). Homogeneous pair:
        2a/(1/E*₁ + 1/E*₂) and 8a/((2 − ν₁)/G₁ + (2 − ν₂)/G₂) (Mindlin).
    transforms : dict, optional
        A store shared by calls at the same radii on solids with the same layer thicknesses
        (e.g. a table over the substrate's modulus, normal and tangential): the Galerkin's basis
        transforms at the quadrature nodes are kept there and reused where the nodes coincide.
        The same numbers as without it; start with an empty dict.

    Returns
    -------
    complex or ndarray of complex
        K, N/m, shaped like ``radius``. Homogeneous isotropic: 2aE* (Sneddon, normal) and
        8Ga/(2 − ν) (Mindlin, tangential).

    Raises
    ------
    ContactresInputError
        For a bad radius or direction.

    Examples
    --------
    A 1 µm punch on 250 nm of PMMA on fused quartz has 43 % of its stiffness on bare quartz:

    >>> from contactres import LayeredMaterial, Material
    >>> from contactres.normal import static_punch_stiffness
    >>> quartz = Material.isotropic(72e9, 0.17, name="quartz")
    >>> pmma = Material.isotropic(5e9, 0.35, name="PMMA")
    >>> coated = LayeredMaterial(quartz, [(pmma, 250e-9)])
    >>> ratio = static_punch_stiffness(coated, 1e-6) / static_punch_stiffness(quartz, 1e-6)
    >>> print(f"{ratio.real:.3f}")
    0.427
    """
    a = _radii("radius", radius)
    kernel = radial_kernel(material, direction)
    if indenter is not None:
        other = radial_kernel(require_material(indenter), direction)
        coupling = kernel.coupling_inf
        if coupling is not None and other.coupling_inf is not None:  # tangential
            coupling = coupling + other.coupling_inf
        kernel = replace(kernel, g_inf=kernel.g_inf + other.g_inf, coupling_inf=coupling)
    sol = punch_and_sphere(kernel, a, tol=tol, transforms=transforms)
    return _shaped(np.asarray(sol.punch_stiffness, dtype=complex), a.shape)


def indentation_modulus_at(material, contact_radius, *, tol: float = DEFAULT_TOL):
    """Indentation modulus as a function of contact radius, M(a) = K(a)/(2a), Pa.

    The E* of the homogeneous isotropic solid on which a rigid flat punch (or, by the
    frictionless-contact identity dF/dδ = K, a rigid sphere) of contact radius a has the same
    stiffness. Homogeneous: M = 4π/I₀ (:func:`contactres.indentation_modulus`) for every a; a
    film of thickness h on a substrate: M -> the film's value for a/h -> 0 and the substrate's
    for a/h -> ∞.

    Parameters
    ----------
    material : Material or LayeredMaterial
        Static constants in the surface frame; lossless.
    contact_radius : float or array
        a > 0, m (vectorised: the kernel is evaluated once per factor-of-2 range of a).
    tol : float
        Truncation of the kernel integral (:mod:`contactres.normal._axisymmetric`).

    Returns
    -------
    float or ndarray
        M(a), Pa, shaped like ``contact_radius``.

    Examples
    --------
    >>> import numpy as np
    >>> from contactres import LayeredMaterial, Material, indentation_modulus_at
    >>> si = Material.isotropic(165e9, 0.22, name="Si")
    >>> film = Material.isotropic(10e9, 0.3, name="low-k")
    >>> M = indentation_modulus_at(LayeredMaterial(si, [(film, 100e-9)]), [10e-9, 1e-6])
    >>> print(np.round(M / 1e9, 1))
    [12.  95.9]
    """
    stack = _stack(material)
    if stack.is_lossy:
        raise ContactresInputError(
            "indentation_modulus_at needs real (undamped) constants (drop with_loss; of a "
            "viscoelastic solid: .storage(f_Hz))"
        )
    a = _radii("contact_radius", contact_radius)
    sol = punch_and_sphere(radial_kernel(stack), a, tol=tol)
    return _shaped(np.real(sol.punch_stiffness) / (2 * a), a.shape)


# repr=False: the summary (Summarised, _facts) replaces numpy reprs of array fields.
@dataclass(frozen=True, repr=False)
class LayeredContact(Summarised):
    """Frictionless contact of a rigid sphere on a layered half-space (axisymmetric solution).

    Field names as :class:`~contactres.normal.AnisotropicContact` where they mean
    the same.

    Attributes
    ----------
    contact_radius : a, m
    depth : indentation depth δ (approach of the sphere to distant points), m
    mean_pressure : F/(π a²), Pa
    peak_pressure : pressure at the centre p(0), Pa (not Hertzian in general)
    stiffness : normal contact stiffness dF/dδ = the flat-punch stiffness at a, N/m
    force : normal force F, N
    indentation_modulus : M(a) = stiffness/(2a), Pa (shaped like ``force``)
    model : "layered-axisymmetric"
    """

    contact_radius: np.ndarray | float
    depth: np.ndarray | float
    mean_pressure: np.ndarray | float
    peak_pressure: np.ndarray | float
    stiffness: np.ndarray | float
    force: np.ndarray | float
    indentation_modulus: np.ndarray | float
    model: str = "layered-axisymmetric"

    def _facts(self) -> list[tuple[str, str]]:
        """As :class:`~contactres.normal.Contact`'s, with M(a) (GPa)."""
        return [*contact_facts(self), ("M", values(self.indentation_modulus, "GPa", 1e9))]


# Force solve: Illinois (modified regula falsi) on ln a, to this relative change of F.
_FORCE_RTOL = 1e-12
_MAX_ITER = 100


def _solve_radius(kernel, R, F, tol):
    """Contact radii of the sphere(s) R under forces F > 0 (1-D arrays of equal size)."""
    store: dict = {}

    def log_force(x):
        sol = punch_and_sphere(kernel, np.exp(x), tol=tol, nodes=store)
        return np.log(sol.force_factor * np.exp(3 * x) / R)

    # Bracket: Hertz with the extreme compliances of the kernel (g∞ and g at the smallest η).
    g_all = [kernel.g_inf]
    if kernel.excess is not None:
        probe = np.geomspace(1e-4 / kernel.lengths[1], 40 / kernel.lengths[0], 64)
        g_all = np.concatenate([[kernel.g_inf], kernel.g_inf + kernel.excess(probe)])
    g_lo, g_hi = float(np.min(g_all)), float(np.max(g_all))
    target = np.log(F)
    lo = np.log(np.cbrt(3 * F * R * g_lo / 8)) - 0.05
    hi = np.log(np.cbrt(3 * F * R * g_hi / 8)) + 0.05
    f_lo, f_hi = log_force(lo) - target, log_force(hi) - target
    # Widen any bracket that the kernel's extremes did not catch (a safeguard).
    for _ in range(60):
        bad_lo, bad_hi = f_lo > 0, f_hi < 0
        if not (bad_lo.any() or bad_hi.any()):
            break
        lo = np.where(bad_lo, lo - 0.5, lo)
        hi = np.where(bad_hi, hi + 0.5, hi)
        f_lo, f_hi = log_force(lo) - target, log_force(hi) - target
    side = np.zeros(F.shape, dtype=int)
    x = hi.copy()
    for _ in range(_MAX_ITER):
        x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        fx = log_force(x) - target
        if np.all(np.abs(fx) <= _FORCE_RTOL):
            return np.exp(x)
        lo, hi, f_lo, f_hi, side = illinois_step(x, fx, (lo, hi, f_lo, f_hi, side))
    raise ContactresInputError("sphere_contact: the contact radius did not converge")


def _pair_kernel(stack: LayeredMaterial, indenter) -> RadialKernel:
    """The normal kernel of the plate, plus the sphere's constant compliance if elastic."""
    kernel = radial_kernel(stack)
    if indenter is not None:
        sphere = radial_kernel(require_material(indenter, lossless=True))
        kernel = replace(kernel, g_inf=kernel.g_inf + sphere.g_inf)
    return kernel


def sphere_contact_at(
    material,
    radius,
    contact_radius,
    *,
    tol: float = DEFAULT_TOL,
    indenter: Material | None = None,
    transforms: dict | None = None,
) -> LayeredContact:
    """The frictionless sphere contact of :func:`sphere_contact` at given contact radii.

    The inverse of :func:`sphere_contact` (which solves for a at a given force): the force,
    depth, pressures and normal contact stiffness of the contact whose radius is a, from one
    solution of the axisymmetric problem per radius (no force iteration). This is the
    non-adhesive branch P'(a), δ'(a) that the compliance method of adhesive contact adds a
    flat punch to (K. R. Shull, Mater. Sci. Eng. R 36, 1 (2002)).

    Parameters
    ----------
    material : Material or LayeredMaterial
        Lossless static constants in the surface frame (z the inward normal).
    radius : float or array
        Sphere radius R > 0, m.
    contact_radius : float or array
        a > 0, m (broadcasts against ``radius``).
    tol : float
        Truncation of the kernel integral (:mod:`contactres.normal._axisymmetric`).
    indenter : Material, optional
        The sphere's own material (default rigid), as in :func:`sphere_contact`.
    transforms : dict, optional
        A store shared by calls at the same contact radii, as in
        :func:`static_punch_stiffness` (the same numbers as without it).

    Returns
    -------
    LayeredContact
        Shaped like the broadcast of ``radius`` and ``contact_radius``. Homogeneous: Hertz,
        F = 4E*a³/(3R), δ = a²/R, stiffness 2aE*.

    Examples
    --------
    It inverts :func:`sphere_contact`:

    >>> from contactres import LayeredMaterial, Material
    >>> from contactres.normal import sphere_contact, sphere_contact_at
    >>> glass = Material.isotropic(70e9, 0.22, name="glass")
    >>> pmma = Material.isotropic(5e9, 0.35, name="PMMA")
    >>> coated = LayeredMaterial(glass, [(pmma, 1e-6)])
    >>> c = sphere_contact_at(coated, 10e-6, 0.8e-6)
    >>> back = sphere_contact(coated, 10e-6, c.force)
    >>> print(f"F = {c.force * 1e3:.4f} mN, a = {back.contact_radius * 1e6:.6f} um")
    F = 0.4499 mN, a = 0.800000 um
    """
    stack = material.at(0.0) if isinstance(material, LayeredMaterial) else _stack(material)
    if stack.is_lossy:
        raise ContactresInputError(
            "sphere_contact_at needs real (undamped) constants (drop with_loss; of a "
            "viscoelastic solid: .storage(f_Hz))"
        )
    R = np.asarray(positive("radius", radius, "m"), dtype=float)
    a = _radii("contact_radius", contact_radius)
    try:
        shape = np.broadcast_shapes(R.shape, a.shape)
    except ValueError:
        raise ContactresInputError(
            f"radius (shape {R.shape}) and contact_radius (shape {a.shape}) do not broadcast"
        ) from None
    Rb, ab = np.broadcast_to(R, shape).ravel(), np.broadcast_to(a, shape).ravel()
    sol = punch_and_sphere(_pair_kernel(stack, indenter), ab, tol=tol, transforms=transforms)
    stiff = np.real(sol.punch_stiffness)
    force = sol.force_factor * ab**3 / Rb
    return LayeredContact(
        contact_radius=_shaped(ab, shape),
        depth=_shaped(sol.depth_factor * ab**2 / Rb, shape),
        mean_pressure=_shaped(force / (np.pi * ab**2), shape),
        peak_pressure=_shaped(sol.peak_factor * ab / Rb, shape),
        stiffness=_shaped(stiff, shape),
        force=_shaped(force, shape),
        indentation_modulus=_shaped(stiff / (2 * ab), shape),
    )


def sphere_contact(
    material,
    radius,
    force,
    rtol: float = THETA_RTOL,
    *,
    tol: float = DEFAULT_TOL,
    indenter: Material | None = None,
    check_validity: bool = True,
):
    """Frictionless contact of a rigid (or elastic) sphere on a homogeneous or layered half-space.

    A :class:`~contactres.Material` (or a stack without layers) is passed to the anisotropic
    Hertz solution (the ``sphere_contact`` of the private ``_anisotropic``: an ellipse on a face
    without a 3- or 4-fold axis, :class:`~contactres.normal.AnisotropicContact`). A
    :class:`~contactres.LayeredMaterial` is solved by the axisymmetric Galerkin of
    :mod:`contactres.normal._axisymmetric`: the contact radius a at which the pressure with no
    edge singularity carries the force (solved to 1e-12 relative in F; F(a) increases with a).

    Parameters
    ----------
    material : Material or LayeredMaterial
        Lossless static constants in the surface frame (z the inward normal).
    radius : float or array
        Sphere radius R > 0, m.
    force : float or array
        Normal force F >= 0, N (broadcasts against ``radius``).
    rtol : float
        Relative accuracy of the θ integrals of a homogeneous material
        (:func:`contactres.contact_integrals`).
    tol : float
        Truncation of the kernel integral (layered only).
    indenter : Material, optional
        The sphere's own material (homogeneous, static constants; default: rigid). Its surface
        compliance is added to the plate's (the two bodies take the same pressure: Hertz's
        1/E* = 1/E*_1 + 1/E*_2, here with the θ-averaged compliance of the sphere's face
        pointing at the plate, ``indenter`` in that frame). The result is then a
        :class:`LayeredContact`, its ``indentation_modulus`` the two bodies' E* together; but
        for two homogeneous bodies whose contact is not circular (a face without a 3- or 4-fold
        axis) the elliptic :class:`~contactres.normal.AnisotropicContact` with both compliances
        (the sphere's frame: the plate's turned by π about x).
    check_validity : bool
        Check Hertz's small-contact limit, as the command line's ``contact`` does (default):
        where a/R > 0.1 a :class:`contactres.errors.ContactresWarning` names a/R (values
        kept); where a/R > 0.5 the contact has no value: its radius, semi-axes, depth,
        pressures and stiffness (a layered contact's M(a) too) are NaN, with the same warning
        (most likely a radius or a force in the wrong unit). False: no check (a caller that
        flags a/R itself).

    Returns
    -------
    AnisotropicContact or LayeredContact
        The homogeneous result, or a :class:`LayeredContact` (contact radius, depth, pressures,
        normal contact stiffness dF/dδ, force and M(a)).

    Examples
    --------
    A sphere of 10 µm radius pressed with 0.5 mN on 1 µm of PMMA on glass: the film makes the
    contact softer than on bare glass, but stiffer than on bulk PMMA.

    >>> from contactres import LayeredMaterial, Material, sphere_contact
    >>> glass = Material.isotropic(70e9, 0.22, name="glass")
    >>> pmma = Material.isotropic(5e9, 0.35, name="PMMA")
    >>> c = sphere_contact(LayeredMaterial(glass, [(pmma, 1e-6)]), 10e-6, 0.5e-3)
    >>> print(f"a = {c.contact_radius * 1e6:.3f} um, K = {c.stiffness / 1e3:.1f} kN/m")
    a = 0.826 um, K = 19.4 kN/m
    """
    c = _sphere_contact(material, radius, force, rtol, tol, indenter)
    return checked(c, radius, "sphere_contact") if check_validity else c


def _sphere_contact(material, radius, force, rtol, tol, indenter):
    """:func:`sphere_contact` without the check of a/R."""
    if indenter is None and not isinstance(material, LayeredMaterial):
        return homogeneous_sphere_contact(material, radius, force, rtol)
    stack = material.at(0.0) if isinstance(material, LayeredMaterial) else _stack(material)
    if indenter is None and not stack.layers:
        return homogeneous_sphere_contact(require_material(stack.substrate), radius, force, rtol)
    if not stack.layers and isinstance(stack.substrate, Material) and not stack.is_lossy:
        # Two homogeneous bodies whose contact is not circular: the ellipse, of which the
        # axisymmetric solution below would be the circular approximation.
        pair = pair_integrals(stack.substrate, require_material(indenter, lossless=True), rtol)
        if not pair.circular:
            return homogeneous_sphere_contact(
                stack.substrate, radius, force, rtol, indenter=indenter
            )
    if stack.is_lossy:
        raise ContactresInputError(
            "sphere_contact needs real (undamped) constants: the static contact of a lossy "
            "material is that of its elastic part (drop with_loss; of a viscoelastic solid: "
            ".storage(f_Hz))"
        )
    R = np.asarray(positive("radius", radius, "m"), dtype=float)
    F = np.asarray(nonnegative("force", force, "N"), dtype=float)
    try:
        shape = np.broadcast_shapes(R.shape, F.shape)
    except ValueError:
        raise ContactresInputError(
            f"radius (shape {R.shape}) and force (shape {F.shape}) do not broadcast together"
        ) from None
    Rb, Fb = np.broadcast_to(R, shape).ravel(), np.broadcast_to(F, shape).ravel()
    kernel = _pair_kernel(stack, indenter)
    a = np.zeros(Fb.shape)
    pos = Fb > 0
    if pos.any():
        a[pos] = _solve_radius(kernel, Rb[pos], Fb[pos], tol)
    depth, stiff, peak, mod = (np.zeros(Fb.shape) for _ in range(4))
    if pos.any():
        sol = punch_and_sphere(kernel, a[pos], tol=tol)
        ap, Rp = a[pos], Rb[pos]
        depth[pos] = sol.depth_factor * ap**2 / Rp
        stiff[pos] = np.real(sol.punch_stiffness)
        peak[pos] = sol.peak_factor * ap / Rp
        mod[pos] = stiff[pos] / (2 * ap)
    mod[~pos] = 2 / kernel.g_inf.real if np.isrealobj(kernel.g_inf) else np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        mean_p = np.where(a > 0, Fb / (np.pi * a**2), 0.0)
    return LayeredContact(
        contact_radius=_shaped(a, shape),
        depth=_shaped(depth, shape),
        mean_pressure=_shaped(mean_p, shape),
        peak_pressure=_shaped(peak, shape),
        stiffness=_shaped(stiff, shape),
        force=_shaped(Fb, shape),
        indentation_modulus=_shaped(mod, shape),
    )
