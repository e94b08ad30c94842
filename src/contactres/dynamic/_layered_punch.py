"""Time-harmonic normal stiffness of a rigid flat punch on a layered (or viscoelastic) substrate.

The rigid, frictionless flat punch of radius a, moved normally by a uniform displacement
δ e^{iωt}, on bonded layers over a half-space (:class:`contactres.layered.LayeredMaterial`),
every material evaluated at the frequency (:func:`contactres.layered.material_at`). The
Galerkin method of the module ``contactres.dynamic._exact`` (pressure basis f_nk, Hankel transforms
j_p(s), s = η a) applies unchanged to any surface kernel; only the kernel changes. With the
top film's shear reference C44_f (real part) and the dimensionless kernel of the stack

    g(η, θ) = −C44_f η Ĝ_33(η, θ)      (Ĝ: :func:`contactres.layered.surface_green`, m/Pa),

the Galerkin matrix is split as

    M = M_film + ΔM,   ΔM_ab = (−1)^{(n_a+n_b)/2} ∫₀^∞ ds Δg_{n_a+n_b}(s/a) j_{p_a}(s) j_{p_b}(s),

where M_film is the matrix of the film as a homogeneous half-space at k_s a (its prepared
kernel table, contour and far field: ``contactres.dynamic._exact.galerkin_matrix``) and
Δg = g_stack − g_film. The difference is the response of what lies under the film: it decays
like e^{−2ηh} once η h ≫ 1 (h the total thickness of the layers), so its integral has a finite
end and needs neither the far field nor a static split.

The kernel table takes constants C (1 + iQ⁻¹) with real C. A film whose channels have unequal
loss tangents (a viscoelastic film with its own bulk law, such as the built-in PMMA) is given
the table of a reference half-space, Re C with the shear loss Q⁻¹ = Im C44/Re C44, and the
difference film − reference joins Δg: its static part (g∞_film − g∞_ref) δ_pq π/(2(2p + 1)) in
closed form, the rest (~1/η²) on the same path, closed by its tail Δg(S)(−1)^{(p−q)/2}/(6S)
beyond the last node S (j_p j_q -> (−1)^{(p−q)/2}/(2s²) on average).

The path of the ΔM integral (lossless: the limit of loss -> 0⁺). Δg is analytic in the upper
half η plane; on the real axis of a lossless stack it has the poles of the guided modes (and the
film's Rayleigh pole, in both terms) and the branch points of the substrate, all at
η <= T = 1.75 ω × (largest bulk slowness of any material). The path is the arc
s(t) = t + i H sin(π t/S₁) on 0 <= t <= S₁ = T a (Gauss-Legendre panels no wider than H),
lifted by H = min(0.3 S₁, 1): the products j_p j_q grow like e^{2 Im s}, so the lift stays O(1)
in s (O(1/a) in η). Beyond S₁, on the real axis, Δg has no singularity and varies only on the
scales 1/h and the wave numbers (not on the period π of j_p j_q): on geometric panels of ratio
1.5 it is sampled at Chebyshev points (in ln s) and interpolated onto Gauss-Legendre nodes dense
enough for the oscillation of j_p j_q; the panels stop beyond η h = 5 and s = 20 once
``|Δg|``/s (what the rest can add) falls below 1e-3 rtol of the film's ``|g|``. A lossy
stack is passed on the same path (its singularities lie below the real axis). In statics
(f = 0) the real axis from 0 is used. Caveat: a lossless stack with a backward-wave guided mode
(group and phase velocity opposite, possible for a stiff film on a soft substrate) would have
that pole's limiting-absorption side reversed; the passivity tests cover both stiff-on-soft and
soft-on-stiff stacks, but no backward-wave case was constructed.

A frequency-dependent material is evaluated at each frequency (a new film table at each one
if the film depends on frequency). The substrate and lower layers may have any constants.

Size of the pressure basis: the default of the exact model at the largest k_s a of any material
of the stack, grown until four more radial terms move N by less than rtol/10 (a thin film on a
much stiffer or softer substrate concentrates the pressure near the edge and needs more).

Accuracy (tests/dynamic/test_layered_punch.py, measured): homogeneous isotropic against the
Fredholm disk 1e-8-2.6e-8 (k_s a = 0.3-2); a lossy stack (Q⁻¹ = 1e-3, PMMA h = 0.2a on quartz)
against an adaptive real-axis quadrature 4.4e-9, the viscoelastic PMMA film (unequal losses)
9.9e-9; doubling every node of the correction moves K by < 3e-11, rtol = 1e-9 (larger basis and
table) by < 3e-9. Films thinner than ~a/100 need many radial terms (the pressure's edge layer
of width h): the basis grows to at most 48 terms per harmonic, checked as above at h = 0.01 a.

Result: K = 4π² a C44_f c₀ (c = M⁻¹ e₀, paper 1, Eq. 28 with N = 1/c₀), complex N/m,
e^{iωt}; Im K >= 0 (radiation and material loss). Static limit: 2 a E* on a homogeneous
isotropic solid.

References: J. E. Luco and R. A. Westmann, "Dynamic response of circular footings",
J. Eng. Mech. Div. ASCE 97, 1381-1395 (1971) (the homogeneous isotropic punch, relaxed);
J. Tian, paper 1 (the Galerkin kernel table of the module ``contactres.dynamic._exact``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ContactresInputError
from ..halfspace import shear_reference
from ..layered import LayeredMaterial, material_at, stack_compliance
from ..materials import Material, voigt_to_tensor
from ..numerics import gauss_legendre
from ..validation import nonnegative, positive
from ._exact import (
    GalerkinSize,
    galerkin_matrix,
    galerkin_plan,
    galerkin_size,
    kernel_harmonics,
)
from ._farfield import far_basis
from ._normal_stiffness import normalised_wavenumber
from ._table import KernelTable, max_slowness, prepare

__all__ = [
    "PunchResolution",
    "flat_punch_stiffness",
    "layered_dcsf",
    "layered_punch_stiffness",
    "punch_resolution",
]

# T = _POLE_FACTOR × ω × (largest bulk slowness): beyond every pole and branch point (the same
# margin as the far-field start T₁ of the kernel table).
_POLE_FACTOR = 1.75
# Largest number of radial terms per harmonic the adaptive basis may reach.
_MAX_RADIAL = 48
# Largest η a of the correction's nodes: a film thinner than ~a/1e5 is out of reach (the nodes
# resolve the oscillation of j_p j_q, ~3 per unit of s).
_S_MAX = 1e6


@dataclass(frozen=True)
class PunchResolution:
    """Discretisation of the ΔM integral; :meth:`doubled` refines every part.

    Attributes
    ----------
    n_panel : Gauss-Legendre nodes per panel of the lifted arc (panels no wider than the lift)
    n_cheb : Chebyshev samples of Δg per real-axis panel (in ln s)
    ratio : ratio of the geometric real-axis panels
    per_unit : Gauss-Legendre nodes per unit of s on the real axis (j_p j_q has period π)
    n_start : nodes of the first real panel [0, s₀] (statics) or [S₁, s₀]
    decay : the panels stop when ``|Δg|`` falls below decay × ``|g_film|`` (and η h > 5)
    """

    n_panel: int = 16
    n_cheb: int = 12
    ratio: float = 1.5
    per_unit: float = 3.0
    n_start: int = 16
    decay: float = 1e-9

    def doubled(self) -> PunchResolution:
        """Twice the nodes everywhere, panels of the square-root ratio, decay 1e-2 lower."""
        return replace(
            self,
            n_panel=2 * self.n_panel,
            n_cheb=2 * self.n_cheb,
            ratio=math.sqrt(self.ratio),
            per_unit=2 * self.per_unit,
            n_start=2 * self.n_start,
            decay=self.decay * 1e-2,
        )


def punch_resolution(rtol: float) -> PunchResolution:
    """The :class:`PunchResolution` for relative accuracy ``rtol`` (checked in the tests against
    :meth:`PunchResolution.doubled`)."""
    base = PunchResolution(decay=1e-3 * rtol)
    if rtol <= 1e-8:
        return replace(base, n_panel=24, n_cheb=16, per_unit=4.0)
    return base


def _reference(m: Material) -> tuple[Material, float]:
    """(undamped material, Q⁻¹) of the reference half-space whose kernel table serves the film
    ``m``: Re C with the loss of C44 (surface frame), C (1 + iQ⁻¹) exactly when ``m`` has one
    loss tangent."""
    C = np.asarray(m.C)
    if not m.is_lossy:
        return m, 0.0
    q = float(C[3, 3].imag / C[3, 3].real)
    if not 0 <= q < 1:
        raise ContactresInputError(
            f"the top film ({m.name or 'unnamed'}) has a shear loss tangent {q:.4g} outside "
            "[0, 1) (a passive film with a moderate loss is needed)"
        )
    return Material(C=C.real, density=m.density, name=m.name), q


def _axisymmetric(mats) -> bool:
    """True if every material is unchanged by a rotation about the normal (transversely
    isotropic about z): then g does not depend on θ."""
    for m in mats:
        c = np.asarray(m.C)
        turned = m.rotated((0, 0, 1), (math.cos(0.7), math.sin(0.7), 0)).C
        if not np.allclose(turned, c, rtol=0, atol=1e-12 * np.max(np.abs(c))):
            return False
    return True


@dataclass(frozen=True, eq=False)
class _Stack:
    """One frequency's stack in the film's units: tensors / C44_f, ρ_j ω²/C44_f, thicknesses,
    and the reference half-space of the film's kernel table (tensor / C44_f)."""

    tensors: list
    reference: np.ndarray
    inertia: list  # ρ_j ω²/C44_f, 1/m² (s_j = inertia_j/η²)
    thicknesses: np.ndarray
    pole: float  # T, 1/m: beyond every pole and branch point on the real η axis
    k_max: float  # largest shear wave number of any material, 1/m
    axisymmetric: bool

    def _h33(self, tensors, eta, theta, inertia=None):
        e = eta[:, None] * np.ones_like(theta)[None, :]
        th = np.broadcast_to(theta[None, :], e.shape)
        s = [r / e**2 for r in (self.inertia if inertia is None else inertia)][: len(tensors)]
        hs = [e * h for h in self.thicknesses][: len(tensors) - 1]
        return stack_compliance(tensors, s, hs, th)[..., 2, 2]

    def static_shift(self, theta: np.ndarray) -> np.ndarray:
        """g∞_film − g∞_ref (θ): the static kernels of the film and of its reference."""
        one, zero = np.ones(1), [0.0]
        ref = self._h33([self.reference], one, theta, zero)
        return (ref - self._h33(self.tensors[:1], one, theta, zero))[0]

    def delta_g(self, eta: np.ndarray, theta: np.ndarray, shift: np.ndarray) -> np.ndarray:
        """Δg = g_stack − g_ref − (g∞_film − g∞_ref) at wavenumbers ``eta`` (1/m, complex) ×
        directions ``theta``, shape (len(eta), len(theta)); -> 0 as η -> ∞."""
        ref = self._h33([self.reference], eta, theta)
        return ref - self._h33(self.tensors, eta, theta) - shift[None, :]


def _stack_at(mats, thicknesses, film: Material, q: float, frequency: float) -> _Stack:
    """The :class:`_Stack` of the materials ``mats`` (top first) at ``frequency``, in the units
    of the film's reference ``film`` (undamped) with loss ``q``."""
    c44 = shear_reference(film)
    omega = 2 * math.pi * frequency
    if omega > 0:
        missing = [j for j, m in enumerate(mats) if m.density is None]
        if missing:
            j = missing[0]
            which = "the substrate" if j == len(mats) - 1 else f"layer {j + 1}"
            raise ContactresInputError(
                f"the dynamic punch stiffness (frequency > 0) needs densities: {which} "
                f"({mats[j].name or 'unnamed'}) has none"
            )
    # The shear wave number of every material, per metre (the one wave-number function).
    ks = [
        float(normalised_wavenumber(frequency, 1.0, m.density or 0.0, shear_reference(m)))
        for m in mats
    ]
    slow = [k * max_slowness(m) for k, m in zip(ks, mats, strict=True)]
    return _Stack(
        tensors=[voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44 for m in mats],
        reference=voigt_to_tensor(np.asarray(film.C, dtype=complex)) * (1 + 1j * q) / c44,
        inertia=[(m.density or 0.0) * omega**2 / c44 for m in mats],
        thicknesses=np.asarray(thicknesses, dtype=float),
        pole=_POLE_FACTOR * max(slow),
        k_max=max(ks),
        axisymmetric=_axisymmetric(mats),
    )


def _cheb_interp(x_nodes, values, x):
    """Barycentric interpolation from the Chebyshev points of the first kind ``x_nodes`` (on
    [−1, 1], n of them) to ``x``; ``values`` (n, ...) -> (len(x), ...)."""
    n = x_nodes.size
    j = np.arange(n)
    w = (-1.0) ** j * np.sin((2 * j + 1) * np.pi / (2 * n))
    d = x[:, None] - x_nodes[None, :]
    exact = d == 0
    d[exact] = 1.0
    c = w[None, :] / d
    out = (c @ values.reshape(n, -1)) / np.sum(c, axis=1)[:, None]
    hit = np.any(exact, axis=1)
    if np.any(hit):
        out[hit] = values.reshape(n, -1)[np.argmax(exact[hit], axis=1)]
    return out.reshape((x.size, *values.shape[1:]))


def _correction_nodes(stack: _Stack, a: float, theta: np.ndarray, res: PunchResolution, gref):
    """Nodes s (complex), weights ds and Δg(s/a, θ) (len(s), len(theta)) of the ΔM integral,
    the end S of the nodes with Δg(S/a, θ) there (for the tail beyond S), and the static
    shift g∞_film − g∞_ref (θ)."""
    shift = stack.static_shift(theta)
    nodes, weights = [], []
    s1 = stack.pole * a
    h_tot = float(np.sum(stack.thicknesses))
    s0 = 0.1 * min(1.0, a / h_tot) if h_tot > 0 else 0.1
    if s1 > 0:
        lift = min(0.3 * s1, 1.0)
        n_pan = max(4, math.ceil(s1 / lift))
        edges = np.linspace(0.0, s1, n_pan + 1, dtype=np.float64)
        t, wt = gauss_legendre(edges[:-1, None], edges[1:, None], res.n_panel)
        t, wt = t.ravel(), wt.ravel()
        arg = np.pi * t / s1
        nodes.append(t + 1j * lift * np.sin(arg))
        weights.append(wt * (1 + 1j * lift * np.pi / s1 * np.cos(arg)))
    start = max(s1, s0)
    if start > s1:
        t, wt = gauss_legendre(s1, start, res.n_start)
        nodes.append(t.astype(complex))
        weights.append(wt.astype(complex))
    # The real-axis panel edges e_k = start × ratio^k up to _S_MAX, probed in one call: the last
    # panel ends past every edge where what lies beyond (~|Δg(e)|/e, as j_p j_q <= 1/s²) is
    # still above 1e-3 rtol of |g|; Δg of layers decays like e^{−2ηh} (η h > 5 first), that of
    # a film with unequal losses like 1/s² (s > 20 first, for the tail formula).
    n_edges = math.ceil(math.log(_S_MAX / start) / math.log(res.ratio))
    edges = start * res.ratio ** np.arange(n_edges + 1, dtype=np.float64)
    probe = stack.delta_g(edges.astype(complex) / a, theta, shift)
    big = np.max(np.abs(probe), axis=1) / edges >= res.decay * gref
    big |= (edges <= 20) | ((h_tot > 0) & (edges * h_tot / a <= 5))
    last = int(np.flatnonzero(big)[-1]) + 1 if np.any(big) else 1
    if last > n_edges:
        raise ContactresInputError(
            f"the layered correction did not decay by η a = {_S_MAX:.3g}: a film {h_tot:.3g} m "
            f"thin under a punch of radius {a:.3g} m (h/a = {h_tot / a:.2g}) is out of reach"
        )
    # Δg at Chebyshev points in ln s per panel, interpolated onto nodes that resolve j_p j_q.
    xc = np.cos(np.pi * (np.arange(res.n_cheb) + 0.5) / res.n_cheb)
    u = np.log(edges[: last + 1])
    uc = 0.5 * (u[:-1, None] + u[1:, None]) + 0.5 * (u[1:, None] - u[:-1, None]) * xc[None, :]
    n_head = sum(x.size for x in nodes)
    sample = np.concatenate([*nodes, np.exp(uc).ravel().astype(complex)])
    values = stack.delta_g(sample / a, theta, shift)
    s_all, w_all, g_all = [*nodes], [*weights], [values[:n_head]]
    cheb = values[n_head:].reshape(last, res.n_cheb, -1)
    for j in range(last):
        lo, hi = edges[j], edges[j + 1]
        # Sub-panels of n_panel nodes each, per_unit nodes per unit of s on average.
        n_sub = max(1, math.ceil(res.per_unit * (hi - lo) / res.n_panel))
        sub = np.linspace(lo, hi, n_sub + 1)
        t, wt = gauss_legendre(sub[:-1, None], sub[1:, None], res.n_panel)
        t, wt = t.ravel(), wt.ravel()
        x = (2 * np.log(t) - u[j] - u[j + 1]) / (u[j + 1] - u[j])
        s_all.append(t.astype(complex))
        w_all.append(wt.astype(complex))
        g_all.append(_cheb_interp(xc, cheb[j], x))
    return (
        np.concatenate(s_all),
        np.concatenate(w_all),
        np.concatenate(g_all),
        float(edges[last]),
        probe[last],
        shift,
    )


def _correction_integrals(s, w, dg_harm, plan, s_end, end_harm) -> np.ndarray:
    """∫ Δg_m j_p j_q ds, (n_m, n_t), from the nodes and the harmonics Δg_m (n_m, len(s)),
    with the tail beyond ``s_end``: Δg ~ Δg(S) S²/s² (its 1/s² decay) and j_p j_q ->
    (−1)^{(p−q)/2}/(2s²) on average, so the tail is Δg_m(S) (−1)^{(p−q)/2}/(6S)."""
    from ._weights import spherical_bessel

    orders, (ti, tj) = plan.orders, plan.pairs
    jp = np.empty((orders.size, s.size), dtype=complex)
    # Real nodes apart: their Bessel functions come from the cheap upward recurrence (the
    # continued fraction of complex arguments would start above 1.3 max|s| for every node).
    real = s.imag == 0
    jp[:, real] = spherical_bessel(int(orders[-1]), s[real].real)[orders]
    jp[:, ~real] = spherical_bessel(int(orders[-1]), s[~real])[orders]
    sign = np.where(((orders[ti] - orders[tj]) // 2) % 2 == 0, 1.0, -1.0)
    out = end_harm[:, None] * sign[None, :] / (6 * s_end)
    # Per harmonic, all order pairs at once: J diag(w Δg_m) Jᵀ (one matrix product).
    for m in range(dg_harm.shape[0]):
        out[m] += ((jp * (w * dg_harm[m])[None, :]) @ jp.T)[ti, tj]
    return out


def _harmonics_of(values, plan, axisymmetric: bool) -> np.ndarray:
    """Ĝ_m = ∫₀^{2π} Δg e^{imθ} dθ (n_m, len(values)) of rows sampled on the table's θ nodes,
    or at one θ for an axisymmetric stack (then only m = 0)."""
    if axisymmetric:
        return np.where(plan.ms == 0, 2 * np.pi, 0.0)[:, None] * values[:, 0][None, :]
    return kernel_harmonics(values, plan.ms)


def _assemble(integral, plan) -> np.ndarray:
    return plan.sign * integral[plan.m_index, plan.t_index]


def _film_matrices(table: KernelTable, ksa: np.ndarray, size: GalerkinSize):
    """(M_film at k_s a values ``ksa`` (>= 0), (len(ksa), nb, nb); the Galerkin plan)."""
    pos = ksa > 0
    far = far_basis(table, ksa[pos]) if np.any(pos) else None
    plan = galerkin_plan(table, size, None if far is None else far.s)
    nb = len(plan.basis)
    out = np.empty((ksa.size, nb, nb), dtype=complex)
    orders, (ti, tj) = plan.orders, plan.pairs
    # Static part of the exact model: Ĝ_m^∞ δ_pq π/(2(2p + 1)) (closed form).
    diag = np.where(ti == tj, np.pi / (2 * (2 * orders[ti] + 1)), 0.0)
    out[~pos] = _assemble(kernel_harmonics(table.ginf, plan.ms)[:, None] * diag[None, :], plan)
    if far is not None:
        out[pos] = galerkin_matrix(table, ksa[pos], plan, far)
    return out, plan


def _solve_c0(M: np.ndarray, n_radial: int, plan) -> np.ndarray:
    """c₀ of M c = e₀ on the sub-basis of the first ``n_radial`` radial terms per harmonic."""
    keep = np.array([k < n_radial for _, k in plan.basis])
    sub = M[:, keep][:, :, keep]
    e0 = np.zeros(sub.shape[-1])
    e0[0] = 1.0
    return np.linalg.solve(sub, np.broadcast_to(e0, sub.shape[:-1])[..., None])[..., 0, 0]


def _stack_of(material, frequency: float):
    if isinstance(material, LayeredMaterial):
        stack = material.at(frequency)
    elif isinstance(material, Material) or callable(getattr(material, "at", None)):
        stack = LayeredMaterial(material_at(material, frequency))
    else:
        raise ContactresInputError(
            "material must be a contactres.Material or LayeredMaterial, got "
            f"{type(material).__name__}"
        )
    return [material_at(m, frequency) for m in stack.materials], stack.thicknesses


def layered_punch_stiffness(
    material,
    radius,
    frequency=0.0,
    direction: str = "normal",
    rtol: float = 1e-6,
    *,
    resolution: PunchResolution | None = None,
):
    """Normal stiffness K(ω) = F/δ of a rigid flat punch on a layered substrate, N/m (complex).

    The rigid, frictionless disk of radius a, displaced uniformly (normal, δ e^{iωt}), on a
    homogeneous, layered and/or viscoelastic substrate (module docstring for the method). On a
    layered or viscoelastic substrate K/K_static depends on the frequency and the radius
    separately, not on k a alone.

    Parameters
    ----------
    material : Material, LayeredMaterial or frequency-dependent material
        In the surface frame (z the inward normal); every material is evaluated at each
        frequency (``at(f)``); densities are needed for f > 0. Lossless materials give the
        limit Q⁻¹ -> 0⁺.
    radius : float or array
        Punch radius a > 0, m.
    frequency : float or array
        f >= 0, Hz (ω = 2πf); broadcasts against ``radius``. 0: the static stiffness.
    direction : str
        "normal" (the only one so far).
    rtol : float
        Target relative accuracy, in [1e-10, 1e-3] (default 1e-6).
    resolution : PunchResolution, optional
        Keyword only: the discretisation of the layered correction (default
        :func:`punch_resolution` of rtol; ``.doubled()`` for a convergence check).

    Returns
    -------
    complex or ndarray of complex
        K in N/m, shaped like broadcast(radius, frequency); Im K >= 0.

    Examples
    --------
    The static punch on a homogeneous solid is 2 a E/(1 − ν²):

    >>> from contactres import Material
    >>> k = layered_punch_stiffness(Material.isotropic(70e9, 0.25), 1e-6)
    >>> bool(abs(k / (2e-6 * 70e9 / (1 - 0.25**2)) - 1) < 1e-9)
    True
    """
    if direction != "normal":
        raise ContactresInputError(
            f"direction must be 'normal' (the tangential layered punch is not available yet), "
            f"got {direction!r}"
        )
    r = float(rtol)
    if not (math.isfinite(r) and 1e-10 <= r <= 1e-3):
        raise ContactresInputError(f"rtol must lie in [1e-10, 1e-3], got {rtol!r}")
    a = np.asarray(positive("radius", radius, "m"), dtype=float)
    f = np.asarray(nonnegative("frequency", frequency, "Hz"), dtype=float)
    a, f = np.broadcast_arrays(a, f)
    res = resolution or punch_resolution(r)
    out = np.empty(a.shape, dtype=complex)
    flat_a, flat_f, flat_out = a.ravel(), f.ravel(), out.reshape(-1)
    # Points grouped by film table (one for a film that does not depend on frequency): the film
    # matrices of a group come from one call, the correction is per point.
    groups: dict = {}
    for freq in np.unique(flat_f):
        sel = np.flatnonzero(flat_f == freq)
        mats, hs = _stack_of(material, float(freq))
        film, q = _reference(mats[0])
        key = (np.asarray(film.C).tobytes(), q)
        if key not in groups:
            groups[key] = ((film, q), [])
        stack = _stack_at(mats, hs, film, q, float(freq))
        groups[key][1].extend((i, stack, float(freq)) for i in sel)
    for (film, q), items in groups.values():
        index = np.array([i for i, _, _ in items])
        flat_out[index] = _punch(prepare(film, q, r), film, items, flat_a[index], r, res)
    return complex(out) if out.ndim == 0 else out


def _storage(material):
    """The stack (or material) at f = 0 with the real parts of every material's constants:
    the undamped static solid that normalises the DCSF."""
    mats, hs = _stack_of(material, 0.0)
    real = [Material(C=np.asarray(m.C).real, density=m.density, name=m.name) for m in mats]
    return LayeredMaterial(real[-1], list(zip(real[:-1], hs, strict=True)))


def flat_punch_stiffness(
    material,
    radius,
    frequency=0.0,
    direction: str = "normal",
    *,
    rtol: float = 1e-6,
):
    """Stiffness of a rigid flat circular punch, static or time-harmonic, N/m (complex).

    The rigid disk of radius a on a homogeneous, layered and/or viscoelastic half-space:
    ``direction="normal"`` frictionless (K = F/δ), ``"tangential"`` bonded (no slip) and
    relaxed (no normal traction), along the surface x axis. e^{iωt}; a lossless material
    gives the limit Q⁻¹ -> 0⁺ (radiation only, Im K >= 0).

    At frequency 0 this is :func:`contactres.normal.static_punch_stiffness` (the axisymmetric
    Galerkin of the static layered solid, < 1e-9); above 0, for ``"normal"``,
    :func:`layered_punch_stiffness` (the film's exact dynamic Galerkin plus the stack's
    correction on a lifted contour; on a layered or viscoelastic substrate K/K_static depends
    on the frequency and the radius separately, not on k a alone). The tangential punch at a
    frequency is not available for a layered substrate yet (for a homogeneous solid:
    :func:`contactres.tangential_contact_stiffness`).

    Parameters
    ----------
    material : Material, LayeredMaterial or frequency-dependent material
        In the surface frame (z the inward normal); every material is evaluated at the
        frequency (``at(f)``; densities needed for f > 0).
    radius : float or array
        Punch radius a > 0, m.
    frequency : float or array
        f >= 0, Hz; broadcasts against ``radius``.
    direction : {"normal", "tangential"}
        Which stiffness.
    rtol : float
        Target relative accuracy of the dynamic punch (static: < 1e-9 always).

    Returns
    -------
    complex or ndarray of complex
        K, N/m. Homogeneous isotropic statics: 2aE* (Sneddon, normal), 8Ga/(2 − ν) (Mindlin,
        tangential).

    Examples
    --------
    Sneddon's 2aE/(1 − ν²) in statics:

    >>> from contactres import Material, flat_punch_stiffness
    >>> k = flat_punch_stiffness(Material.isotropic(70e9, 0.25), 1e-6)
    >>> bool(abs(k / (2e-6 * 70e9 / (1 - 0.25**2)) - 1) < 1e-9)
    True
    """
    from ..normal import static_punch_stiffness

    f = np.asarray(nonnegative("frequency", frequency, "Hz"), dtype=float)
    if not np.any(f > 0):
        a = np.asarray(positive("radius", radius, "m"), dtype=float)
        shape = np.broadcast_shapes(a.shape, f.shape)
        k = static_punch_stiffness(material, np.broadcast_to(a, shape), direction)
        return complex(k) if np.ndim(k) == 0 else k
    if direction == "tangential":
        raise ContactresInputError(
            "the tangential punch at a frequency > 0 on a layered substrate is not available yet "
            "(frequency 0 is); for a homogeneous solid use tangential_contact_stiffness"
        )
    return layered_punch_stiffness(material, radius, frequency, direction, rtol)


def layered_dcsf(
    material,
    radius,
    frequency,
    rtol: float = 1e-6,
    *,
    resolution: PunchResolution | None = None,
):
    """Paper 1's dynamic-contact-stiffness factor (exact model) on a layered or viscoelastic
    substrate: K(f)/K_st of the rigid flat punch, complex.

    K(f) is :func:`layered_punch_stiffness`; K_st the static (f = 0) stiffness of the same
    punch on the undamped stack: every material at f = 0 (its relaxed limit) with the real part
    of its constants, as paper 1's K_sa is the static stiffness of the undamped constants (so a
    homogeneous solid with constant loss Q⁻¹ gives DCSF(0) = 1 + iQ⁻¹, as
    :func:`contactres.dcsf`). On a layered or viscoelastic substrate the DCSF is a function of
    the frequency and the radius separately, not of k a alone: the film thickness and the
    frequency dependence of the moduli set their own scales.

    Parameters
    ----------
    material, radius, frequency, rtol, resolution
        As in :func:`layered_punch_stiffness` (normal direction); the materials need a static
        limit (a springpot, a power law without one, is refused at f = 0).

    Returns
    -------
    complex or ndarray of complex
        K/K_st, shaped like broadcast(radius, frequency).
    """
    k = layered_punch_stiffness(material, radius, frequency, rtol=rtol, resolution=resolution)
    k_st = layered_punch_stiffness(_storage(material), radius, 0.0, rtol=rtol)
    out = np.asarray(k) / np.asarray(k_st).real
    return complex(out) if out.ndim == 0 else out


def _punch(table, film, items, radii, rtol, res) -> np.ndarray:
    """K (N/m) at the points ``items`` [(index, _Stack, frequency), ...] of one film table
    (``film``: its undamped reference material) with radii ``radii``."""
    c44 = shear_reference(film)
    stacks = [st for _, st, _ in items]
    freqs = np.array([f for _, _, f in items])
    ksa = normalised_wavenumber(freqs, radii, film.density or 0.0, c44)
    k_max = np.array([st.k_max for st in stacks]) * radii
    n_radial = galerkin_size(float(np.max(k_max)), rtol).n_radial
    n_harm = galerkin_size(0.0, rtol).n_harmonics
    axisymmetric = all(st.axisymmetric for st in stacks)
    theta = np.zeros(1) if axisymmetric else np.asarray(table.theta)
    gref = float(np.max(np.abs(table.ginf)))
    # A correction is needed under layers, or for a film that is not its reference.
    needs = [
        len(st.tensors) > 1
        or not np.allclose(
            st.tensors[0], st.reference, rtol=0, atol=1e-14 * np.max(np.abs(st.reference))
        )
        for st in stacks
    ]
    nodes = {
        i: _correction_nodes(st, float(radii[i]), theta, res, gref)
        for i, st in enumerate(stacks)
        if needs[i]
    }
    while True:
        grow = n_radial + 4 if nodes else n_radial
        size = GalerkinSize(grow, 0 if axisymmetric else n_harm)
        M, plan = _film_matrices(table, ksa, size)
        orders, (ti, tj) = plan.orders, plan.pairs
        diag = np.where(ti == tj, np.pi / (2 * (2 * orders[ti] + 1)), 0.0)
        for i, (s, w, dg, s_end, end, static) in nodes.items():
            shift = _harmonics_of(static[None, :], plan, axisymmetric)
            harm = _harmonics_of(dg, plan, axisymmetric)
            end_h = _harmonics_of(end[None, :], plan, axisymmetric)[:, 0]
            integral = _correction_integrals(s, w, harm, plan, s_end, end_h)
            # The static difference of film and reference: closed form, as in the exact model.
            M[i] += _assemble(integral + shift[:, 0][:, None] * diag[None, :], plan)
        c_big = _solve_c0(M, grow, plan)
        if not nodes:
            break
        c_small = _solve_c0(M, n_radial, plan)
        if np.max(np.abs(c_big / c_small - 1)) < rtol / 10 or grow >= _MAX_RADIAL:
            break
        n_radial = min(_MAX_RADIAL - 4, math.ceil(1.5 * n_radial))
    return 4 * np.pi**2 * radii * c44 * c_big
