"""The in-plane dynamic surface kernel of one material on the nodes every k a reuses.

The table behind :mod:`contactres.dynamic._tangential_galerkin`: the angular harmonics
Ĝ_{αβ,m}(κ) = ∫₀^{2π} Ĝ_αβ(κ, θ) e^{imθ} dθ of the in-plane block (α, β = x, y) of the dynamic
surface Green's function, Ĝ = −H(θ, 1/κ²)/C44 (:func:`contactres.halfspace.surface_compliance`;
κ = ``|ξ|``/k_s, k_s = ω√(ρ/C44), C44 = Re C[3, 3] of the surface frame), minus its static limit,
on the nodes of the normal problem's table (:mod:`contactres.dynamic._table`, paper 1): a
complex contour above the branch points and the Rayleigh pole (loss -> 0⁺ exact), the real
hand-over segment (there the far field's series, :func:`segment_from_series`), and Chebyshev
nodes in w = (T₁/κ)² for the far field. A uniform loss enters as g_lossy(κ) =
g(κ√(1 + iQ⁻¹))/(1 + iQ⁻¹). The θ grid covers [0, 2π) (the in-plane kernel has an odd
imaginary part on faces that are not mirror planes); only its first half is evaluated
(h(θ + π) = h(θ)ᵀ), and it is doubled per wavenumber node, reusing the values it has, until
the aliases of that node's harmonics are below 1e-11 of the static one.

Reference: J. Tian, "Anisotropy Influence of Cubic Solid on Dynamic Hertzian Contact Stiffness
for a Vibrating Rigid Indenter", Am. J. Eng. Appl. Sci. 3(1), 56-63 (2010) (paper 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..halfspace import scaled_tensor, shear_reference, surface_compliance
from ..materials import Material, require_material
from ._table import (
    ReadOnlyArrays,
    Resolution,
    check_contrast,
    check_loss,
    resolution_for,
    wavenumber_nodes,
)

__all__ = [
    "HARMONIC_STEPS",
    "KSA_MAX",
    "TangentialTable",
    "angular_harmonics",
    "harmonic_cutoff",
    "kernel_tail",
    "max_harmonics",
    "prepare_tangential",
    "segment_from_series",
    "tail_factor",
]

# θ grid on [0, 2π): first size, largest size, and the accuracy of the harmonics (relative to the
# static ones; see _resolved).
_N_THETA_START = 64
_N_THETA_MAX = 1024
_THETA_TOL = 1e-11


#: Candidate largest traction harmonics ``|n|`` of the Galerkin basis, smallest first.
HARMONIC_STEPS = (6, 8, 10, 12, 16, 20, 24)
# 0.02 tail² (tail: the largest static kernel harmonic beyond |n| relative to the axisymmetric
# one) is a fit, not a bound: against |n| <= 20 (k_s a <= 2; 194 cases: every built-in cubic
# crystal on (001), (011), (111), (123), AT-cut quartz, sapphire, 40 random cubic solids, with
# and without loss, rtol 1e-4 to 1e-8) the truncation error is 0.38x-3.7e5x of it (median 10x),
# below 1x at |n| <= 10 on (111)-like faces (up to 0.053 tail²). The cut-off it picks has still
# left <= 0.71 of rtol/3 on each (the steps are coarse; tests/dynamic/test_tangential_harmonics).
# No kernel-only estimate bounding it with a 1.5x margin lets Cu(123) keep |n| <= 6 at rtol 1e-6
# (its error 1.3e-7; such estimates >= 2.3e-6).
_TAIL_FACTOR = 0.02
# Beyond k_s a = 2 the error grows steeply with k_s a (the disk then samples the dynamic kernel
# near κ ~ 1, whose angular structure is sharper than the static one's), so the factor grows:
# F(x) = 0.02 × 10^(1.7 x − 0.18 x²), x = k_s a − 2 (F = 0.66, 9.6, 60 at k_s a = 3, 4, 5).
# Measured ratio error/tail² (the 92 (111), (123) and random-face cases of the survey, |n| 6-20
# against 24, errors above 3e-11): at most 0.051, 0.32, 1.5, 5.4, 13, 29 at k_s a = 2.5, 3,
# 3.5, 4, 4.5, 5 (the cubic solids A = 7.58, ν = 0.11 and A = 8.97, ν = 0.17 on random faces);
# F is 1.8x-2.5x these (0.046 at k_s a = 2, where 0.02 stays: the steps are coarse).
_GROWTH = (1.7, -0.18)
_KSA_STATIC = 2.0
#: Largest k_s a accepted: the range of the convergence tests (at 5: 1.5e-8 from the radial
#: terms; the harmonic cut-off grows with the curve's k_s a, tests/dynamic/
#: test_tangential_harmonics at 2 and 5); beyond it the default basis is not checked.
KSA_MAX = 5.0


def tail_factor(ksa_max: float) -> float:
    """F(k_s a) of the harmonic cut-off's estimate F tail² (see _GROWTH): 0.02 up to k_s a = 2,
    growing to 60 at k_s a = 5 (measured truncation error / tail² at most 29 there)."""
    x = float(ksa_max) - _KSA_STATIC
    if not x > 0:
        return _TAIL_FACTOR
    return _TAIL_FACTOR * 10.0 ** (_GROWTH[0] * x + _GROWTH[1] * x * x)


def kernel_tail(m: Material) -> np.ndarray:
    """t_k (k = 0..25): the largest static in-plane kernel harmonic of order ``|m|`` = k of
    ``m``, relative to the axisymmetric one (dimensionless)."""
    from ._tangential_static import inplane_kernel_harmonics

    top = HARMONIC_STEPS[-1] + 1
    h = np.abs(inplane_kernel_harmonics(m, top)).max(axis=(1, 2))
    mid = h.size // 2
    return np.maximum(h[mid:], h[mid::-1]) / h[mid]


def harmonic_cutoff(tail: np.ndarray, rtol: float, ksa_max: float = _KSA_STATIC) -> int:
    """The first of :data:`HARMONIC_STEPS` whose kernel tail t (largest of ``tail`` beyond it,
    :func:`kernel_tail`) has F t² <= rtol/3, F = :func:`tail_factor` of ``ksa_max`` (the
    largest k_s a of the curve); nondecreasing in ``ksa_max``."""
    factor = tail_factor(ksa_max)
    for n in HARMONIC_STEPS:
        if factor * np.max(tail[n + 1 :]) ** 2 <= rtol / 3:
            return n
    return HARMONIC_STEPS[-1]


def max_harmonics(m: Material, rtol: float, ksa_max: float = _KSA_STATIC) -> int:
    """Largest traction harmonic ``|n|`` of the Galerkin basis for ``m`` at accuracy ``rtol`` up
    to k_s a = ``ksa_max``: the first of :data:`HARMONIC_STEPS` whose kernel tail t (the largest
    static in-plane kernel harmonic beyond it, relative to the axisymmetric one) has
    F t² <= rtol/3, F = 0.02 up to k_s a = 2, growing to 60 at k_s a = 5 (:func:`tail_factor`).
    Measured error at ``|n|`` <= 6 / 8 / 10, k_s a = 2: Cu(123) 1.3e-7 / 3.9e-9 / 7.6e-10,
    Na(123) 1.3e-6 / 6.8e-8 / 2.8e-8, Li(111) 6.2e-7 / 6.2e-7 / 4.2e-8 (t = 5.4e-3, 1.6e-2,
    8.0e-3 at ``|n|`` <= 6); at k_s a = 5, rtol 1e-6 (the cut-off at 2 in brackets): KCl(123)
    [6] 2.6e-6, Pb(111) [6] 2.2e-6, a cubic solid A = 7.58, ν = 0.11 [8] 8.2e-5 /
    ``|n|`` <= 12: 4.6e-7 / 16: 6.0e-10."""
    return harmonic_cutoff(kernel_tail(m), rtol, ksa_max)


@dataclass(frozen=True, eq=False, repr=False)
class TangentialTable(ReadOnlyArrays):
    """The in-plane dynamic kernel of one material and loss on the nodes every k a reuses.

    Dimensionless: h = C44 Ĝ (C44 = Re C[3, 3] of the surface frame), κ in units of k_s.

    Attributes
    ----------
    constants : (6, 6) Voigt stiffness (Pa) it was prepared for
    loss : Q⁻¹
    rtol : the accuracy it was prepared for
    resolution : the discretisation (that of the normal kernel table at this rtol)
    c44 : the reference stiffness C44, Pa
    t1 : start of the far field, units of k_s
    ksa_max : the largest k_s a its harmonics serve (:meth:`harmonics_for`)
    tail : (26,) the static kernel harmonics relative to the axisymmetric one (:func:`kernel_tail`)
    n_harmonics : largest traction harmonic ``|n|`` of the Galerkin basis up to k_s a = ksa_max
        (:func:`max_harmonics`)
    max_order : kernel harmonics m = −max_order..max_order are held (>= 2 n_harmonics)
    ginf : (2M+1, 2, 2) harmonics of the lossy static kernel h∞ = C44 Ĝ∞/(1 + iQ⁻¹)
    ginf0 : (2M+1, 2, 2) the same of the undamped constants
    near_kappa, near_weight : (nk,) near-field nodes and weights dκ χ(κ) (as the normal table)
    near_values : (nk, 2M+1, 2, 2) harmonics of h − h∞ at the near nodes (on the hand-over
        segment, the last nk − resolution.n_contour, the far field's series:
        :func:`segment_from_series`)
    far_coeffs : ((2M+1)·4, n_fit) Chebyshev coefficients in x = 2w − 1 of (h − h∞)/w
    """

    constants: np.ndarray
    loss: float
    rtol: float
    resolution: Resolution
    c44: float
    t1: float
    ksa_max: float
    tail: np.ndarray
    n_harmonics: int
    max_order: int
    ginf: np.ndarray
    ginf0: np.ndarray
    near_kappa: np.ndarray
    near_weight: np.ndarray
    near_values: np.ndarray
    far_coeffs: np.ndarray

    def check_for(self, m: Material, loss: float, rtol: float) -> TangentialTable:
        """``self`` if prepared for the constants of ``m``, ``loss`` and ``rtol``; else a
        ValueError naming what differs."""
        wrong = []
        if not np.array_equal(self.constants, np.asarray(m.C)):
            wrong.append("another material (elastic constants)")
        if self.loss != check_loss(loss):
            wrong.append(f"loss={self.loss!r}, not {loss!r}")
        if self.rtol != float(rtol):
            wrong.append(f"rtol={self.rtol!r}, not {rtol!r}")
        if wrong:
            raise ContactresInputError(
                "the prepared tangential table was made for "
                + "; ".join(wrong)
                + ": pass the same material, loss and rtol, or prepare_tangential again"
            )
        return self

    def harmonics_for(self, ksa_max: float) -> int:
        """The basis's largest harmonic ``|n|`` for a curve up to k_s a = ``ksa_max``
        (:func:`harmonic_cutoff`); a ContactresInputError beyond the table's ksa_max, whose
        kernel harmonics would not suffice."""
        if ksa_max > self.ksa_max:
            raise ContactresInputError(
                f"the prepared tangential table serves k_s a <= {self.ksa_max:g}, not "
                f"{ksa_max:.6g}: prepare_tangential(..., ksa_max={ksa_max:.6g}) (the harmonic "
                "cut-off grows with k_s a)"
            )
        return min(harmonic_cutoff(self.tail, self.rtol, ksa_max), self.n_harmonics)


def _inplane(c: np.ndarray, kappa: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """h = −H_in of the dimensionless tensor c at (κ, θ) (κ = ∞: static), (nκ, nθ, 2, 2)."""
    kappa = np.asarray(kappa, dtype=complex)
    finite = np.isfinite(kappa)
    s = np.zeros(kappa.shape, dtype=complex)
    s[finite] = 1.0 / kappa[finite] ** 2
    H = surface_compliance(c, theta[None, :], s[:, None])
    return -H[..., :2, :2]


def _full_turn(c: np.ndarray, kappa: np.ndarray, n: int, coarse: np.ndarray | None) -> np.ndarray:
    """h on θ_j = 2πj/n, j < n, (nκ, n, 2, 2): only the half-turn θ < π is evaluated, the rest
    is h(θ + π) = h(θ)ᵀ (reciprocity, Ĝ(−ξ) = Ĝ(ξ)ᵀ, at every complex κ as at the real ones);
    ``coarse`` (the values at n/2 nodes, or None) gives every other node of the half-turn, so a
    doubling evaluates only the new nodes (together 1/3.5 of the evaluations of three full
    grids)."""
    half = n // 2
    values = np.empty((kappa.size, n, 2, 2), dtype=complex)
    if coarse is None:
        values[:, :half] = _inplane(c, kappa, 2 * np.pi * np.arange(half) / n)
    else:
        values[:, 0:half:2] = coarse[:, : half // 2]
        values[:, 1:half:2] = _inplane(c, kappa, 2 * np.pi * np.arange(1, half, 2) / n)
    values[:, half:] = np.swapaxes(values[:, :half], -1, -2)
    return values


def _resolved(values: np.ndarray, max_order: int, static: float) -> np.ndarray:
    """Which rows of ``values`` (axis 1: n nodes θ on [0, 2π)) have their harmonics ``|m|`` <=
    ``max_order`` to 1e-11 of ``static`` (the largest static harmonic, as angular_harmonics
    gives it), a boolean per row.

    The FFT's harmonic m holds the aliases m ± n, ``|m ± n|`` >= 3n/4 when n >= 4 max_order. h is
    analytic in θ, so its harmonics decay geometrically: from the largest harmonic t₁ of
    n/4 <= ``|m|`` < 3n/8 and t₂ of 3n/8 <= ``|m|`` <= n/2 (an upper bound: it holds aliases too),
    those at 3n/4 are about t₂ (t₂/t₁)². Measured (AT-cut quartz, Cu(123), Cu(111), Cu(001),
    Na(123), Li(111), Pb(123), the harmonics of rtol 1e-6 and 1e-9): the harmonics change by
    <= 2e-14 of the static ones from the grid accepted to the next. (The check it replaces, a
    change below 1e-11 from the previous grid, evaluated that next grid every time.) Each row
    (wavenumber node) is judged by its own harmonics, so a row whose kernel is smoother in θ
    stops at a coarser grid than the rest (rtol 1e-6: 16 of the 91 nodes of Cu(123), 80 of those
    of Cu(001), one doubling earlier); measured on the same materials at rtol 1e-6 and 1e-9,
    the table then differs from that of one grid for every node by <= 1.7e-13 of the static
    harmonics.
    """
    n = values.shape[1]
    freq = np.abs(np.fft.fftfreq(n, 1.0 / n))
    # Scaled as angular_harmonics: the same units on every grid.
    spectrum = (2 * np.pi / n) * np.abs(np.fft.fft(values, axis=1))
    t1 = np.max(spectrum[:, (freq >= n // 4) & (freq < 3 * n // 8)], axis=(1, 2, 3))
    t2 = np.max(spectrum[:, freq >= 3 * n // 8], axis=(1, 2, 3))
    decay = np.minimum(1.0, np.divide(t2, t1, out=np.ones_like(t2), where=t1 > 0))
    return (n >= 4 * max_order) & (t2 * decay**2 <= _THETA_TOL * static)


def angular_harmonics(values: np.ndarray, max_order: int) -> np.ndarray:
    """∫₀^{2π} v(θ) e^{imθ} dθ, m = −M..M, of rows sampled at θ_j = 2πj/n (axis 1)."""
    n = values.shape[1]
    orders = np.arange(-max_order, max_order + 1)
    return (2 * np.pi / n) * np.fft.fft(values, axis=1)[:, (-orders) % n]


def segment_from_series(t1: float, kappa: np.ndarray, coeffs: np.ndarray) -> np.ndarray:
    """h − h∞ (any trailing shape of ``coeffs``, flattened) at real wave numbers ``kappa`` in
    [T₁, 2T₁] (units of k_s) from the far field's Chebyshev series (``coeffs`` (n_fit, ...) of
    (h − h∞)/w in x = 2w − 1, w = (T₁/κ)²): w Σ_f c_f T_f(2w − 1), (len(kappa), ...).

    The hand-over segment lies inside the series' range (w in [1/4, 1]), where h is smooth and
    the series converges as fast as for the far field, so the kernel is evaluated on the
    contour and the series' nodes alone (58 wave numbers instead of 90 at rtol 1e-6; the
    normal table does the same, :mod:`contactres.dynamic._table`). Bound (tests/dynamic/
    test_tangential_dynamic): within 2e-9 (rtol 1e-6) and 1e-7 (rtol 1e-4) of the table's
    largest ``|h − h∞|`` harmonic of the kernel's own, evaluated directly; measured at most
    5.8e-10 and 2.9e-8 (isotropic ν = 0, the largest of a survey of every built-in crystal on
    (001), (011), (111), (123), AT-cut quartz, ν = 0 and 0.49 and 10 random cubic solids on
    random faces, Q⁻¹ = 0 and 0.02; Cu(123) 2e-12 and 1.9e-10), ~1e-15 at rtol <= 1e-8. K moves
    by at most 2.8e-12 and 1.5e-10 of its largest value (k_s a <= 2), far below rtol.
    """
    w = (t1 / kappa) ** 2
    at = np.polynomial.chebyshev.chebvander(2 * w - 1, coeffs.shape[0] - 1)
    return (at * w[:, None]) @ coeffs.reshape(coeffs.shape[0], -1)


def _checked_ksa_max(ksa_max: float) -> float:
    """``ksa_max`` of :func:`prepare_tangential` as a float in [0, :data:`KSA_MAX`], or a
    one-line :class:`~contactres.errors.ContactresInputError`: a NaN or a value beyond the
    checked range used to pass silently (a NaN then compared false everywhere, and a table for
    k_s a = 50 claimed harmonics no convergence test covers)."""
    try:
        value = float(ksa_max)
    except (TypeError, ValueError):
        raise ContactresInputError(
            f"ksa_max must be a number (the largest k_s a of the curves), got {ksa_max!r}"
        ) from None
    if not 0.0 <= value <= KSA_MAX:
        raise ContactresInputError(
            f"ksa_max = {value!r} is outside [0, {KSA_MAX:g}], the range where the dynamic "
            "tangential stiffness is checked (k_s = ω√(ρ/C44)): check the frequency and the "
            "contact radius (units?)"
        )
    return value


# 3x3 solves of the in-plane kernel, its Chebyshev fit: one BLAS thread (contactres._threads).
@one_blas_thread()
def prepare_tangential(
    m: Material,
    loss: float = 0.0,
    rtol: float = 1e-6,
    *,
    ksa_max: float = 2.0,
    resolution: Resolution | None = None,
    max_order: int | None = None,
) -> TangentialTable:
    """The in-plane kernel table of ``m`` (surface frame, undamped constants, Pa) with loss Q⁻¹
    at accuracy ``rtol`` (in [1e-10, 1)) for curves up to k_s a = ``ksa_max`` (default 2; the
    harmonic cut-off grows beyond it, :func:`max_harmonics`; at most
    :data:`~contactres.dynamic.KSA_MAX`), to pass as ``prepared=``; ``resolution`` overrides
    the discretisation and ``max_order`` the highest kernel harmonic held (default
    2 × :func:`max_harmonics`, the basis's own need; convergence tests). Immutable,
    picklable; nothing is cached."""
    m = require_material(m, lossless=True)
    q = check_loss(loss)
    check_contrast(m)
    res = resolution or resolution_for(rtol)
    ksa_top = max(_checked_ksa_max(ksa_max), _KSA_STATIC)
    tail = kernel_tail(m)
    n_harmonics = harmonic_cutoff(tail, rtol, ksa_top)
    max_order = int(max_order or 2 * n_harmonics)
    c44 = shear_reference(m)
    c = scaled_tensor(m).real.astype(complex)
    t1, near_kappa, near_weight, x = wavenumber_nodes(m, res)
    nf = res.n_fit
    w = 0.5 * (x + 1)
    # The lossy solid C(1 + iQ⁻¹) from the elastic one: h(κ√(1 + iQ⁻¹))/(1 + iQ⁻¹).
    f = 1 + 1j * q
    # The kernel on the contour and at the far field's nodes; on the real hand-over segment
    # from the far field's series (segment_from_series).
    nc = res.n_contour
    kappa = np.concatenate([near_kappa[:nc], t1 / np.sqrt(w)]) * np.sqrt(f)
    nodes = np.concatenate([kappa, [np.inf]])
    # The θ grid doubled per node until its harmonics are resolved (_resolved), relative to
    # the static ones (the last node) on the first grid: accurate far beyond the 1e-11 asked.
    n = _N_THETA_START
    harm = np.empty((nodes.size, 2 * max_order + 1, 2, 2), dtype=complex)
    rows = np.arange(nodes.size)
    values = _full_turn(c, nodes, n, None)
    static = float(np.max(np.abs(angular_harmonics(values[-1:], max_order))))
    while True:
        done = _resolved(values, max_order, static) | (n >= _N_THETA_MAX)
        harm[rows[done]] = angular_harmonics(values[done], max_order)
        rows, values = rows[~done], values[~done]
        if rows.size == 0:
            break
        n *= 2
        values = _full_turn(c, nodes[rows], n, values)
    ginf0 = harm[-1]
    dyn = (harm[:-1] - ginf0[None]) / f  # harmonics of h − h∞ (lossy)
    vals = dyn[nc:].reshape(nf, -1) / w[:, None]
    tk = np.polynomial.chebyshev.chebvander(x, nf - 1)
    coeffs = (2.0 / nf) * (tk.T @ vals)
    coeffs[0] *= 0.5
    segment = segment_from_series(t1, near_kappa[nc:].real, coeffs)
    near_values = np.concatenate([dyn[:nc], segment.reshape(-1, *dyn.shape[1:])])
    return TangentialTable(
        constants=np.array(m.C),
        loss=q,
        rtol=float(rtol),
        resolution=res,
        c44=c44,
        t1=t1,
        ksa_max=ksa_top,
        tail=tail,
        n_harmonics=n_harmonics,
        max_order=max_order,
        ginf=ginf0 / f,
        ginf0=ginf0,
        near_kappa=near_kappa,
        near_weight=near_weight,
        near_values=near_values,
        far_coeffs=coeffs.T.copy(),
    )
