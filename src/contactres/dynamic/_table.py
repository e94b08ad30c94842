"""The prepared kernel table of a material: g(κ, θ) − g∞(θ) on the nodes every frequency reuses.

The displacement function N(r̄, φ) of paper 1, Eq. 22 integrates the dimensionless kernel
g(s/(k_s a), θ) over s. With s = κ·(k_s a) one table of g in κ serves every frequency and every
displacement model of one material and loss; :func:`prepare` builds it, and the caller holds it
and passes it on (``prepared=``) to evaluate many curves without rebuilding it. The table is an
immutable object of numpy arrays; it pickles, so a process pool or a dask worker can receive it.

Nodes (all exact rearrangements; their number is set by :class:`Resolution`):

* Near field 0 < κ < T₁ (T₁ beyond every bulk and Rayleigh slowness): a Gauss-Legendre contour in
  the upper half κ plane, where g is analytic (the branch points and the Rayleigh near-pole lie
  on or below the real axis), so ``loss=0`` (Q⁻¹ -> 0⁺) works as well as Q⁻¹ = 0.02. A uniform
  loss C(1 + iQ⁻¹) is exactly a rescaling of the wave number: g_lossy(κ) = g_elastic(κ √(1 +
  iQ⁻¹))/(1 + iQ⁻¹), so only the elastic kernel is evaluated.
* A smooth partition of unity χ(κ) (:func:`handover`) hands the real axis over from the near field
  (Gauss-Legendre in κ on [T₁, 2T₁]) to the far field κ > T₁, where g − g∞ is tabulated as a
  Chebyshev series in w = (T₁/κ)², split into the angular harmonics e^{2imθ} (only cos 4mθ on a
  cubic (001) face). The near field's values on [T₁, 2T₁] are that series' (the segment lies
  in its range): the kernel is evaluated on the contour and the series' nodes alone.
* θ on [0, π) (g has period π) with an adaptive number of nodes: doubled until the angular
  harmonics of g have decayed (strong anisotropy needs more: A = 0.2 takes 128 nodes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np
from scipy import special

from .._summary import Summarised, number
from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..halfspace import (
    scaled_tensor,
    shear_reference,
    stacked_normal_compliance,
)
from ..materials import Material, require_material, voigt_to_tensor
from ..numerics import gauss_legendre

__all__ = [
    "COARSE_RTOL",
    "MAX_ISOTROPIC_POISSON",
    "MAX_STIFFNESS_CONTRAST",
    "KernelTable",
    "Resolution",
    "check_contrast",
    "check_loss",
    "handover",
    "kernel_table",
    "max_slowness",
    "prepare",
    "resolution_for",
    "wavenumber_nodes",
]

# T1 = _T1_FACTOR x the largest in-plane bulk slowness (units of 1/c_s); the Rayleigh slowness
# is below 1/0.69 of it for any isotropic Poisson ratio, so T1 clears every singularity.
_T1_FACTOR = 1.75
# Height of the near-field contour over the real κ axis, relative to the largest slowness.
_CONTOUR_HEIGHT = 0.3
# Width parameter of the erfc hand-over on [T1, 2 T1]: χ(T1) = 1 - 1e-17, χ(2 T1) = 1e-17.
_CHI_STEPS = 12.0
# Far-field harmonics kept: those whose Chebyshev coefficients reach this fraction of the
# largest (|J_n| <= 1, so a dropped one moves N by less than ~1e-11 relative).
_FAR_HARMONIC_TOL = 1e-11
# Upper bound of the adaptive number of θ nodes on [0, π).
_N_THETA_MAX = 1024
# _look_ahead: a table is expected to need more than n_theta nodes where the in-plane spread of
# a bulk slowness exceeds this times theta_tol^(1/4). A heuristic, for speed only: measured on
# 100 cubic (001) solids (A = 0.2-10, ν = −0.3-0.42, Q⁻¹ = 0.02), the spread separates the tables
# that stop at n_theta from the others only roughly (ν matters too); a needless look-ahead costs
# ~1.2 ms (rtol 1e-6) or ~0.6 ms (1e-4), a right one saves ~0.4 or ~0.7 ms, and the threshold
# (0.30 at rtol 1e-6, 0.40 at 1e-4) comes within 16 % of the best net saving over those solids at
# both (47 of 60 and 25 of 43 tables that go on are looked ahead, 5 and 6 of 40 and 57 needlessly)
# and is right on the six solids of benchmarks/bench_dcsf.py.
_LOOK_AHEAD_SPREAD = 4.0

#: Largest stiffness contrast (λ_max/λ_min of the Kelvin stiffness,
#: :func:`contactres.normal.stiffness_contrast`; isotropic (1 + ν)/(1 − 2ν) = 3K/2G)
#: accepted by the DCSF. Near incompressibility the general kernels of
#: :mod:`contactres.halfspace` lose digits to round-off (~ε × contrast²). Measured for the
#: isotropic exact model, lossless, k_s a = 0.01-2, against the independent Fredholm solution of
#: tests/dynamic/test_rigid_disk_isotropic.py: max. error 5e-8 up to ν = 0.49998 (as at
#: ν = 0.45), 8.4e-7 at ν = 0.499984 (contrast 4.7e4), 1.4e-6 at 0.499986, 3e-6 at 0.49999,
#: 7e-4 at 0.499999 and garbage (negative damping) at 0.4999999. The limit keeps a factor 6 in
#: contrast from the first failure (the error there jumps with round-off). A candidate for
#: :mod:`contactres.units`.
MAX_STIFFNESS_CONTRAST = 7500.0
#: The isotropic Poisson ratio at that contrast: (1 + ν)/(1 − 2ν) = 7499.5 at ν = 0.4999.
MAX_ISOTROPIC_POISSON = 0.4999
#: The rtol from which :func:`resolution_for` takes its coarse grid (and the near field its
#: coarse continued-fraction margins, :func:`~contactres.dynamic._quadrature.near_theta_integrals`).
COARSE_RTOL = 1e-4


# ----------------------------------------------------------------------------------- resolution
@dataclass(frozen=True)
class Resolution:
    """Discretisation of the N(r̄, φ) integrals; :meth:`doubled` refines every one of them.

    Attributes
    ----------
    n_theta : θ nodes of the kernel table on [0, π) (period of g), before adaptive doubling
    n_contour : Gauss-Legendre nodes on the complex near-field contour 0 -> T₁
    n_segment : Gauss-Legendre nodes on the real hand-over segment [T₁, 2T₁]
    n_fit : Chebyshev nodes of the far field in w = (T₁/κ)²
    s_ratio : ratio of the geometric far-field s panels (below s = 8)
    s_panel : width of the uniform far-field s panels on [8, s_coarse]
    s_far : end of the far-field s grid; beyond it the leading asymptotic term (~ s_far^-2.5) is
        added in closed form and the rest (~ s_far^-3.5) neglected
    n_gauss : Gauss-Legendre nodes per far-field s panel below s_coarse
    s_coarse : start of the wide far-field s panels (there only the oscillation, whose frequency
        is <= 2 in s, and the hand-over of the larger k a, of width >= s_coarse/18, are resolved)
    s_panel_coarse : width of the far-field s panels above s_coarse
    n_gauss_coarse : Gauss-Legendre nodes per far-field s panel above s_coarse
    theta_tol : n_theta is doubled until the angular harmonics of g in the upper half of the
        resolved band are below theta_tol times the axisymmetric part (the functionals use only
        the low harmonics; measured for k_l a <= 2: 64 nodes with a tail of 5e-5 (A = 0.2) move
        the DCSF by 2e-12, 32 nodes with 5e-4 (A = 0.25) by 3e-7, with 1.2e-3 (A = 0.2) by 5e-6)

    The wide panels start at s_coarse and have edges at s_coarse + j s_panel_coarse; s = 120,
    where the WA weights of the non-axisymmetric harmonics stop
    (:func:`~contactres.dynamic._farfield.far_weights`), is one of them (also when doubled).

    The defaults are the accuracy rtol = 1e-6 with a margin of 10 or more: against every
    resolution doubled (tests and benchmarks/bench_dcsf.py, k_l a <= 2, A = 0.25-10, ν =
    0.25-0.42, Q⁻¹ = 0 and 0.02) the largest relative deviation of the seven models is 4e-8
    (SA near its zero at A = 0.25; the far-field end s_far), most are 1e-9-1e-11; at A = 0.2,
    ν = 0.45 TP reaches 9e-7 (no margin left; found by review: that corner is left out of the
    validated range, and :func:`resolution_for` states the whole range). Measured one
    at a time, n_contour = 36, n_segment = 24, s_panel = 4 or s_ratio = 1.5 move it to 1e-7-4e-7;
    n_fit = 8, 64 θ nodes, wide panels from s = 16 or with 2 nodes per unit of s do not move it
    beyond 1e-8.
    """

    n_theta: int = 32
    n_contour: int = 48
    n_segment: int = 32
    n_fit: int = 10
    s_ratio: float = 1.25
    s_panel: float = 2.0
    s_far: float = 600.0
    n_gauss: int = 12
    theta_tol: float = 3e-5
    s_coarse: float = 32.0
    s_panel_coarse: float = 8.0
    n_gauss_coarse: int = 20

    def doubled(self) -> Resolution:
        """Every resolution doubled (the convergence check of the tests)."""
        return replace(
            self,
            n_theta=2 * self.n_theta,
            n_contour=2 * self.n_contour,
            n_segment=2 * self.n_segment,
            n_fit=2 * self.n_fit,
            s_ratio=math.sqrt(self.s_ratio),
            s_panel=self.s_panel / 2,
            s_far=2 * self.s_far,
            n_gauss=2 * self.n_gauss,
            theta_tol=self.theta_tol * 1e-2,
            s_coarse=2 * self.s_coarse,
            s_panel_coarse=self.s_panel_coarse / 2,
            n_gauss_coarse=2 * self.n_gauss_coarse,
        )


def resolution_for(rtol: float) -> Resolution:
    """The :class:`Resolution` that reaches relative accuracy ``rtol`` of the DCSF.

    rtol in (1e-8, COARSE_RTOL) takes the default grid, rtol >= :data:`COARSE_RTOL` a coarser
    one, rtol <= 1e-8 doubles everything. Measured against every resolution doubled, models R0,
    R1, SA, WA, TP, WA2D, 991 k_l a in [0.02, 2], Q⁻¹ = 0-0.05, 45 cubic solids over the
    validated range's corners and edges (A = 0.2-10, ν = −0.3-0.45, less A < 0.25 with
    ν > 0.44; :data:`~contactres.dynamic._convergence.VALIDATED_CORNER`):

    * default grid: at most 4.7e-8 (7.9e-8 at Q⁻¹ = 0.05) where ``|DCSF|`` <= 100, 7.1e-8
      (1.4e-7) up to ``|DCSF|`` = 500; the exact model ~5e-8 (README);
    * coarse grid: at most 1.03e-5 (1.9e-5 at Q⁻¹ = 0.05) where ``|DCSF|`` <= 100, 2.4e-5
      (2.6e-5) up to 500;
    * near a pole of SA or R1 (N -> 0) the relative error grows like ``|DCSF|``: ~1.5e-10
      ``|DCSF|`` on the default grid, ~5e-8 ``|DCSF|`` on the coarse one (7.6e-10 and 7e-8 at
      Q⁻¹ = 0.05; 7.9e-7 and 1.8e-4 at ``|SA|`` = 6100, A = 0.3, ν = 0, Q⁻¹ = 0.01). The public
      functions check values beyond ``|DCSF|`` =
      :data:`~contactres.dynamic._convergence.POLE_DCSF` at run time;
    * in the corner left out, TP has a narrow feature near k_l a = 1.95-2 that both grids miss
      (up to 5.7e-6 and 1.5e-3 at A = 0.21, ν = 0.45, Q⁻¹ = 0.02); there every value is checked.

    Parameters
    ----------
    rtol : float
        Target relative accuracy of the DCSF, in [1e-10, 1).
    """
    r = float(rtol)
    if not (np.isfinite(r) and 1e-10 <= r < 1):
        raise ContactresInputError(f"rtol must lie in [1e-10, 1), got {rtol!r}")
    if r >= COARSE_RTOL:
        return Resolution(
            n_contour=32,
            n_segment=24,
            n_fit=8,
            s_far=150.0,
            n_gauss=10,
            theta_tol=1e-4,
            n_gauss_coarse=16,
        )
    if r <= 1e-8:
        return Resolution().doubled()
    return Resolution()


def check_contrast(m: Material) -> float:
    """The stiffness contrast of ``m``, after refusing one beyond :data:`MAX_STIFFNESS_CONTRAST`
    (a nearly incompressible solid, where the DCSF would miss its stated accuracy 1e-6)."""
    from ..normal import contrast_poisson, stiffness_contrast

    contrast = stiffness_contrast(m)
    if not contrast <= MAX_STIFFNESS_CONTRAST:
        nu = contrast_poisson(contrast)
        raise ContactresInputError(
            f"the solid is too nearly incompressible for the dynamic kernels: stiffness "
            f"contrast (bulk/shear) {contrast:.4g}, as an isotropic solid with nu = {nu:.7g}; "
            f"the DCSF keeps its accuracy 1e-6 up to {MAX_STIFFNESS_CONTRAST:g} "
            f"(isotropic nu <= {MAX_ISOTROPIC_POISSON}) and is not computed beyond"
        )
    return contrast


def check_loss(loss) -> float:
    """Q⁻¹ as a float after checking that it lies in [0, 1) (0: the lossless limit)."""
    q = float(loss)
    if not (np.isfinite(q) and 0 <= q < 1):
        raise ContactresInputError(f"loss (Q^-1) must lie in [0, 1), got {loss!r}")
    return q


def handover(kappa, t1: float):
    """Smooth hand-over χ(κ) from the near to the far field: 1 below T₁, 0 above 2T₁ (to 1e-17),
    erfc-shaped between (of Re κ). ``kappa`` and ``t1`` are dimensionless (units of 1/k_s)."""
    width = t1 / _CHI_STEPS
    return 0.5 * special.erfc((np.real(kappa) - 1.5 * t1) / width)


# ----------------------------------------------------------------------------------- the table
class ReadOnlyArrays(Summarised):
    """Base of the prepared tables (frozen dataclasses of arrays): their arrays are made
    read-only, and stay so through pickling (a table goes to dask workers); they print as a
    summary (declare them with ``repr=False``: a numpy repr of every node is no use)."""

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]
            value = getattr(self, f.name)
            if isinstance(value, np.ndarray):
                value.setflags(write=False)

    def __reduce__(self):
        # Unpickling goes through __init__, so the arrays come back read-only.
        return (type(self), tuple(getattr(self, f.name) for f in fields(self)))

    def _facts(self) -> list[tuple[str, str]]:
        """What the table was prepared for (C11, C33, C44 in GPa, Q⁻¹, rtol) and its size."""
        t: Any = self  # a KernelTable or a TangentialTable: both have these fields
        C = np.real(t.constants)
        facts = [(f"C{i}{i}", number(C[i - 1, i - 1], "GPa", 1e9)) for i in (1, 3, 4)]
        facts += [("Q⁻¹", number(t.loss)), ("rtol", str(t.rtol))]
        return [*facts, ("near-field nodes", str(np.size(t.near_kappa)))]


@dataclass(frozen=True, eq=False, repr=False)
class KernelTable(ReadOnlyArrays):
    """g(κ, θ) − g∞(θ) of one material and loss on the nodes every frequency and model reuse.

    Made by :func:`prepare` (or :func:`kernel_table` for an explicit :class:`Resolution`);
    immutable (its arrays are read-only, also after unpickling). Dimensionless: κ in units of
    the shear wave number k_s, g = C44 η Ĝ_dyn (paper 1, Eq. 21); θ on [0, π) (g has period π).

    Attributes
    ----------
    constants : (6, 6) Voigt stiffness (Pa, surface frame) the table was prepared for
    loss : Q⁻¹ it was prepared for
    rtol : the accuracy it was prepared for (None when built for an explicit Resolution)
    resolution : the discretisation
    t1 : T₁, start of the far field (and end of the near-field contour)
    theta : (nθ,) θ nodes on [0, π)
    ginf : (nθ,) lossy static kernel g∞(θ) = C44 Ĝ(θ)/(1 + iQ⁻¹)
    n_static : N_st of the undamped constants, (π/2) ∫₀^{2π} g∞ dθ (paper 1, Eq. 29)
    near_kappa : (nk,) complex near-field nodes (contour, then the real segment [T₁, 2T₁])
    near_weight : (nk,) quadrature weights dκ × χ(κ)
    near_values : (nk, nθ) g − g∞ at the near nodes (on the real segment, from the far field's
        Chebyshev series: :func:`_segment_from_series`)
    far_harmonics : (n_m,) indices m of the harmonics e^{2imθ} kept in the far field
    far_coeffs : (n_m, n_fit) Chebyshev coefficients of (g − g∞)/w per harmonic
    fourfold : g(θ + π/2) = g(θ) (only harmonics e^{4ijθ})
    """

    constants: np.ndarray
    loss: float
    rtol: float | None
    resolution: Resolution
    t1: float
    theta: np.ndarray
    ginf: np.ndarray
    n_static: float
    near_kappa: np.ndarray
    near_weight: np.ndarray
    near_values: np.ndarray
    far_harmonics: np.ndarray
    far_coeffs: np.ndarray
    fourfold: bool

    def check_for(self, m: Material, loss: float, rtol: float) -> KernelTable:
        """``self`` if it was prepared for the constants of ``m``, ``loss`` and ``rtol``; a
        ValueError saying what differs otherwise."""
        wrong = []
        if not np.array_equal(self.constants, np.asarray(m.C)):
            wrong.append("another material (elastic constants)")
        if self.loss != check_loss(loss):
            wrong.append(f"loss={self.loss!r}, not {loss!r}")
        if self.rtol is None:
            wrong.append(f"an explicit Resolution, not rtol={rtol!r}")
        elif self.rtol != float(rtol):
            wrong.append(f"rtol={self.rtol!r}, not {rtol!r}")
        if wrong:
            raise ContactresInputError(
                "the prepared kernel table was made for "
                + "; ".join(wrong)
                + ": pass the same material, loss and rtol, or prepare(m, loss, rtol) again"
            )
        return self


def prepare(m: Material, loss: float = 0.0, rtol: float = 1e-6) -> KernelTable:
    """The kernel table of ``m`` with loss Q⁻¹ at accuracy ``rtol``, to pass on as ``prepared=``.

    Building it is most of the cost of a DCSF curve. Every function of
    :mod:`contactres.dynamic` (``dcsf``, ``dcsf_models``, ``dynamic_contact_stiffness``,
    ``contact_displacement``, ``contact_pressure``) takes it as ``prepared=`` for the same
    material, loss and rtol (and checks that they are the same). Nothing is cached: the caller
    holds the table.

    Parameters
    ----------
    m : Material
        Undamped elastic constants in the surface frame (z = inward normal), Pa.
    loss : float
        Q⁻¹ of the constants C (1 + i Q⁻¹), in [0, 1) (default 0: the lossless solid; 0.02
        in paper 1's figures).
    rtol : float
        Target relative accuracy of the DCSF (as in :func:`~contactres.dynamic.dcsf`).

    Returns
    -------
    KernelTable
        Immutable, picklable, safe to share between threads.

    Raises
    ------
    ValueError
        For a nearly incompressible solid (stiffness contrast beyond
        :data:`MAX_STIFFNESS_CONTRAST`, isotropic ν > 0.4999), where the kernels lose the
        stated accuracy to round-off.
    """
    table = kernel_table(m, loss, resolution_for(rtol))
    return replace(table, rtol=float(rtol))


# Batched 3x3 eigenproblems and solves: one BLAS thread (contactres._threads).
@one_blas_thread()
def kernel_table(m: Material, loss: float = 0.0, resolution: Resolution | None = None):
    """The :class:`KernelTable` of the undamped material ``m`` (surface frame) with loss Q⁻¹
    for an explicit :class:`Resolution` (default: ``Resolution()``). Not cached."""
    m = require_material(m, lossless=True)
    q = check_loss(loss)
    check_contrast(m)
    return _build_table(m, q, resolution or Resolution())


def _elastic_and_static(m: Material, kappa: np.ndarray, theta: np.ndarray, loss: float, static):
    """g of the lossy solid C(1 + iQ⁻¹) on κ × θ (``kappa`` (nk,), ``theta`` (nθ,)), from the
    elastic one, g(κ√(1 + iQ⁻¹))/(1 + iQ⁻¹), and the undamped static kernel g∞₀ = C44 Ĝ at the
    directions ``static``, in one evaluation of the surface compliance (the static kernel is its
    limit 1/κ² = 0): one pass of the batched doubling instead of two, whose fixed cost is that
    of a few hundred points (issue 31). Every point is evaluated on its own, so a value does
    not depend on the others of the call. The same values as
    :func:`~contactres.halfspace.dynamic_kernel` (the same operations) and
    :func:`~contactres.halfspace.static_kernel` (to the last bit or two: C44 Ĝ is not divided by
    C44 and multiplied back)."""
    f = 1 + 1j * loss
    inverse_square = 1.0 / (np.asarray(kappa, dtype=complex) * np.sqrt(f)) ** 2
    shape = (kappa.size, theta.size)
    th = np.concatenate([np.broadcast_to(theta[None, :], shape).ravel(), static])
    s = np.concatenate([np.broadcast_to(inverse_square[:, None], shape).ravel(), 0 * static])
    h = stacked_normal_compliance(scaled_tensor(m)[None], th[None], s[None])[0]
    return -h[: th.size - static.size].reshape(shape) / f, -h[th.size - static.size :].real


def max_slowness(m: Material) -> float:
    """Largest slowness of bulk waves travelling along the surface, in units of 1/c_s."""
    return float(np.max(_slowness(m)[:, 0]))


def _slowness(m: Material) -> np.ndarray:
    """Slownesses (units of 1/c_s) of the three bulk waves along the in-plane directions θ =
    0°, 1°, ..., 180°, shape (181, 3), slowest first."""
    c = voigt_to_tensor(np.asarray(m.C).real) / shear_reference(m)
    th = np.linspace(0.0, np.pi, 181)
    # The Christoffel matrices Γ_ik = Σ_j n_j Σ_l c_ijkl n_l of the in-plane directions
    # n = (cos θ, sin θ, 0), from the four in-plane (j, l) blocks: an einsum over all of j, l
    # cost half the slowness (~0.1 ms, ~1 % of a seven-model curve; issue 31). The same sums
    # in the same order as numpy 2.4's einsum took them (each j's sum over l first; checked),
    # so the same bits as before.
    n = (np.cos(th)[:, None, None], np.sin(th)[:, None, None])
    gamma = [
        (c[None, :, j, :, 0] * n[j]) * n[0] + (c[None, :, j, :, 1] * n[j]) * n[1] for j in (0, 1)
    ]
    return 1.0 / np.sqrt(np.linalg.eigvalsh(gamma[0] + gamma[1]))


def _symmetry(m: Material) -> tuple[bool, bool]:
    """(mirror, fourfold): g(−θ) = g(θ) (mirror plane y -> −y) and g(θ + π/2) = g(θ) (4-fold
    axis along z) of the surface-frame stiffness; a cubic (001) face has both."""
    c = voigt_to_tensor(np.asarray(m.C).real)
    scale = np.max(np.abs(c))

    def same(perm, sign):
        # The rotation R with rows sign_i e_perm(i) (a signed permutation): c'_ijkl =
        # sign_i sign_j sign_k sign_l c_{perm(i) perm(j) perm(k) perm(l)}, exactly what
        # rotate_tensor gives, without its einsum (whose path search costs ~0.7 ms).
        p = np.asarray(perm)
        sg = np.asarray(sign, dtype=float)
        # The product of four signs ±1 (exact), by broadcasting: an einsum cost ~30 µs.
        signs = sg[:, None, None, None] * sg[None, :, None, None] * sg[:, None] * sg
        cr = c[np.ix_(p, p, p, p)] * signs
        return bool(np.max(np.abs(cr - c)) <= 1e-12 * scale)

    # Mirror y -> −y: R = diag(1, −1, 1); 4-fold about z: R = [[0, −1, 0], [1, 0, 0], [0, 0, 1]].
    return same((0, 1, 2), (1, -1, 1)), same((1, 0, 2), (-1, 1, 1))


def _theta_base(nth: int, symmetry) -> np.ndarray:
    """For each θ_j = πj/nth the index of the node with the same g by ``symmetry``."""
    mirror, fourfold = symmetry
    j = np.arange(nth)
    base = j % (nth // 2) if fourfold else j
    if mirror:
        period = nth // 2 if fourfold else nth
        base = np.minimum(base, period - base)
    return base


def _theta_values(m, kappa, q, nth, symmetry, old=None):
    """(g − g∞ on κ × (θ_j = πj/nth), the undamped static kernel g∞₀ on the θ_j): reuses ``old``
    (the pair at nth/2) and the symmetry. g∞ = g∞₀/(1 + iQ⁻¹). The nodes not in ``old`` (the
    distinct θ_j of the symmetry) get both kernels from one evaluation
    (:func:`_elastic_and_static`): the static kernel only where the table needs it, so a table
    that stops at its first θ grid evaluates no static kernel on the grids it never reaches."""
    base = _theta_base(nth, symmetry)
    need = np.unique(base)
    values = np.empty((kappa.size, nth), dtype=complex)
    static = np.empty(nth)
    if old is not None:
        have = need[need % 2 == 0]
        values[:, have] = old[0][:, have // 2]
        static[have] = old[1][have // 2]
        need = need[need % 2 == 1]
    theta = np.pi * need / nth
    elastic, static[need] = _elastic_and_static(m, kappa, theta, q, theta)
    values[:, need] = elastic - static[need] / (1 + 1j * q)
    return values[:, base], static[base]


def wavenumber_nodes(m: Material, res: Resolution, kb: float | None = None):
    """The κ nodes every kernel table of ``m`` uses (units of k_s): T₁, the near-field nodes
    κ(t) = t + i h sin(π t/T₁) on [0, T₁] then the real segment [T₁, 2T₁] with their weights
    dκ χ(κ), and the Chebyshev nodes x of the far field in w = (T₁/κ)², x = 2w − 1. ``kb``:
    :func:`max_slowness` of ``m`` if the caller has it."""
    if kb is None:
        kb = max_slowness(m)
    t1 = _T1_FACTOR * kb
    height = _CONTOUR_HEIGHT * kb
    t, wt = gauss_legendre(0.0, t1, res.n_contour)
    kc = t + 1j * height * np.sin(np.pi * t / t1)
    wc = wt * (1 + 1j * height * np.pi / t1 * np.cos(np.pi * t / t1))
    ks, ws = gauss_legendre(t1, 2 * t1, res.n_segment)
    near_kappa = np.concatenate([kc, ks.astype(complex)])
    near_weight = np.concatenate([wc, ws * handover(ks, t1)])
    x = np.cos(np.pi * (np.arange(res.n_fit) + 0.5) / res.n_fit)
    return t1, near_kappa, near_weight, x


def _segment_from_series(res: Resolution, t1: float, near_kappa: np.ndarray, x: np.ndarray):
    """The (n_segment, n_fit) matrix that maps (g − g∞)/w at the far field's Chebyshev nodes
    ``x`` (x = 2w − 1, w = (T₁/κ)²) to g − g∞ at the real hand-over nodes κ in [T₁, 2T₁] (the
    last n_segment of ``near_kappa``): the far field's Chebyshev series, evaluated there.

    The segment lies inside the far field's range (w in [1/4, 1]), where g is smooth and the
    series converges as fast as it does for the far field (its n_fit terms are what the far
    field is accurate with). Measured (A = 0.2-10, ν up to 0.49, Cu(111) and (123), Q⁻¹ = 0
    and 0.02): its values are within 1.1e-10 (rtol 1e-6) and 8.1e-9 (rtol 1e-4; the largest
    both at ν = 0.49, Q⁻¹ = 0, found in review) of the largest
    ``|g − g∞|`` of the kernel's, and the DCSF of every model moves by at most 7e-11 and 3e-9,
    far below the 1e-10-9e-7 and 1e-7-2e-4 it moves when every resolution is doubled
    (tests/dynamic/test_prepared.py; issue 31). The half-space kernel, the table's largest
    cost, is then evaluated on the contour and the series' nodes alone: 58 wave numbers
    instead of 90 at rtol 1e-6 (40 instead of 64 at 1e-4)."""
    nf = res.n_fit
    to_coeffs = (2.0 / nf) * np.polynomial.chebyshev.chebvander(x, nf - 1).T  # (nf, nf)
    to_coeffs[0] *= 0.5
    ws = (t1 / near_kappa[res.n_contour :].real) ** 2  # w of the segment's nodes
    at = np.polynomial.chebyshev.chebvander(2 * ws - 1, nf - 1)  # (n_segment, nf)
    return (at @ to_coeffs) * ws[:, None]


def _look_ahead(slowness: np.ndarray, res: Resolution) -> bool:
    """Whether the table's θ grid is expected to need more than ``res.n_theta`` nodes, from the
    in-plane anisotropy of the bulk slownesses (:func:`_slowness`): the largest relative spread
    ``ptp/mean`` of a branch over θ above :data:`_LOOK_AHEAD_SPREAD` theta_tol^(1/4).

    Only the order of the work depends on it, never a value (:func:`_build_table`)."""
    spread = (slowness.max(axis=0) - slowness.min(axis=0)) / slowness.mean(axis=0)
    return bool(spread.max() > _LOOK_AHEAD_SPREAD * res.theta_tol**0.25)


def _build_table(m: Material, q: float, res: Resolution) -> KernelTable:
    slowness = _slowness(m)
    t1, near_kappa, near_weight, x = wavenumber_nodes(m, res, float(np.max(slowness[:, 0])))
    # Far field: (g − g∞)/w as a Chebyshev series in x = 2w − 1, w = (T1/κ)² in (0, 1).
    nf = res.n_fit
    w = 0.5 * (x + 1)
    # The kernel on the contour and at the far field's nodes; on the real hand-over segment
    # from the far field's series (_segment_from_series).
    nc = res.n_contour
    kappa = np.concatenate([near_kappa[:nc], t1 / np.sqrt(w)])
    segment = _segment_from_series(res, t1, near_kappa, x)

    symmetry = _symmetry(m)
    nth = res.n_theta
    # A solid expected to need 2 nth nodes gets them in the first pass of the half-space kernel
    # (its fixed cost is that of a few hundred points, ~0.6 ms; issue 31), and the test at nth
    # reads every other of them: each value is evaluated on its own at the same θ (πj/nth =
    # π(2j)/(2 nth) exactly), so the table is the same to the last bit whatever _look_ahead says.
    ahead = _theta_values(m, kappa, q, 2 * nth, symmetry) if _look_ahead(slowness, res) else None
    both = None
    while True:
        if ahead is not None and ahead[0].shape[1] >= nth:
            step = ahead[0].shape[1] // nth
            both = (ahead[0][:, ::step].copy(), ahead[1][::step].copy())
        else:
            both = _theta_values(m, kappa, q, nth, symmetry, both)
        evaluated = both[0]
        # Every node's values, in the order of near_kappa then the far field's nodes.
        values = np.concatenate(
            [evaluated[:nc], segment @ (evaluated[nc:] / w[:, None]), evaluated[nc:]]
        )
        harm = np.abs(np.fft.fft(values, axis=1))
        tail = np.max(harm[:, nth // 4 : nth - nth // 4 + 1])
        if tail <= res.theta_tol * np.max(harm[:, 0]) or nth >= _N_THETA_MAX:
            break
        nth *= 2
    theta = np.pi * np.arange(nth) / nth
    ginf0 = both[1]  # undamped
    ginf = ginf0 / (1 + 1j * q)
    n_static = 0.5 * np.pi * (2 * np.pi) * float(np.mean(ginf0))
    near_values = values[: near_kappa.size]
    vals = values[near_kappa.size :] / w[:, None]
    tk = np.polynomial.chebyshev.chebvander(x, nf - 1)  # (nf, nf)
    coeffs = (2.0 / nf) * (tk.T @ vals)  # (nf, nθ)
    coeffs[0] *= 0.5
    harm = np.fft.fft(coeffs, axis=1) / nth  # (nf, nθ) harmonic m at index m mod nθ
    mm = np.fft.fftfreq(nth, 1.0 / nth).astype(int)
    keep = np.max(np.abs(harm), axis=0) > _FAR_HARMONIC_TOL * np.max(np.abs(harm))
    keep &= np.abs(mm) < nth // 2
    return KernelTable(
        constants=np.array(m.C),
        loss=q,
        rtol=None,
        resolution=res,
        t1=t1,
        theta=theta,
        ginf=ginf,
        n_static=n_static,
        near_kappa=near_kappa,
        near_weight=near_weight,
        near_values=near_values,
        far_harmonics=mm[keep],
        far_coeffs=harm[:, keep].T,
        fourfold=symmetry[1],
    )
