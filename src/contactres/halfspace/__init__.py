"""Normal surface response of an anisotropic elastic half-space, static and time-harmonic.

Paper 1, Eqs. 10-20, rewritten in a form that holds for any anisotropy, the degenerate isotropic
solid included: for a surface wave vector ξ = η (cos θ, sin θ) the displacement field decaying
into the solid z > 0 is ``u(z) = exp(i η Z z) u(0)``, where the 3x3 matrix Z (wave numbers p/η
of the partial waves) is the *solvent* of the quadratic eigenproblem of the Christoffel matrix
with all its eigenvalues in the upper half plane (Im p > 0: decaying; with loss this is also the
outgoing choice). The surface compliance H = −i (Rᵀ + W Z)⁻¹ follows, and the normal
displacement under a unit normal point force (pressing into the solid, σ_33 = −1) is
Ĝ = −H_33/(C44 η).

The modules that implement it are private (scipy's rule: import from ``contactres.halfspace``),
bottom up:

- ``_stacked``: arithmetic on stacks of 3x3 matrices (:func:`mm` products, :func:`inv3` adjugate
  inverse, :func:`transpose`).
- ``_doubling``: the decaying solvent by cyclic reduction after a Möbius map (a quadratically
  convergent doubling algorithm, exact and continuous at degenerate points), with a
  block-structured step, a third of the cost, when the surface is a mirror plane of the solid.
- ``_outgoing``: the 6x6 Stroh eigen-decomposition for the points where a lossless solid has
  propagating partial waves (limiting absorption, Im κ -> 0+).
- ``_compliance``: the surface compliance H of the dimensionless tensor c = C/C44
  (:func:`surface_compliance`, :func:`shear_reference`, :func:`has_mirror_plane`), the tensor
  c itself (:func:`scaled_tensor`) and the static normal compliance of many tensors at once
  (:func:`stacked_normal_compliance`, one per orientation of a polycrystal).
- ``_kernels``: the normal kernels of a :class:`~contactres.materials.Material`, static
  Ĝ(θ) (:func:`static_kernel`) and dynamic g(κ, θ) (:func:`dynamic_kernel`).
- ``_isotropic``: Lamb's closed form :func:`isotropic_dynamic_kernel`, an independent check.

Accuracy: the doubling stops when its last update is below 1e-10 (relative); what remains is
then ~1e-16 (convergence is quadratic), and the kernels agree with closed forms and with a
brute-force eigen-solution to ~1e-13 or better (tests). A slightly anisotropic solid
(A = 1 ± 1e-9) gives the isotropic answer to ~1e-9. Two corners lose digits: nearly
incompressible solids (relative error ~1e-16 (C11/C44)³: 2e-14 at ν = 0.49, 2e-11 at ν = 0.499)
and real κ ≪ 1 with a tiny loss (2e-9 at κ = 1e-4, Q⁻¹ = 1e-8: partial waves within 1e-8 of
propagating).

Cost (``benchmarks/bench_halfspace.py``): ~1.5-2 µs per (κ, θ) point on a mirror-plane face
(cubic (001), (011), hexagonal basal and prism faces, orthotropic principal cuts), ~4 µs on
other faces (e.g. cubic (111)), ~40 µs on the eigen-decomposition path.

Sign conventions: time factor e^{iωt}; the solid fills z >= 0 with z the inward normal; loss
enters as complex constants C (1 + i Q⁻¹) (:meth:`Material.with_loss`). The normal-normal
response is even in ξ (reciprocity), so the sign of the Fourier exponent does not matter here.

Paper 1: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness for
a Vibrating Rigid Indenter", American Journal of Engineering and Applied Sciences 3(1), 56-63
(2010), doi:10.3844/ajeassp.2010.56.63. Other references: docs/references.md.
"""

from __future__ import annotations

from ._compliance import (
    has_mirror_plane,
    scaled_tensor,
    shear_reference,
    stacked_normal_compliance,
    surface_compliance,
    surface_compliance_pair,
)
from ._isotropic import isotropic_dynamic_kernel
from ._kernels import dynamic_kernel, static_kernel
from ._stacked import inv3, mm, transpose

# The kernels, and beside them the lower-level pieces the layers above build on (the layered
# recursion, the tangential tables, the polycrystal moduli): the dimensionless tensor, the
# batched normal compliance and the 3x3 stack arithmetic.
__all__ = [
    "dynamic_kernel",
    "has_mirror_plane",
    "inv3",
    "isotropic_dynamic_kernel",
    "mm",
    "scaled_tensor",
    "shear_reference",
    "stacked_normal_compliance",
    "static_kernel",
    "surface_compliance",
    "surface_compliance_pair",
    "transpose",
]
