"""The layered correction's path and nodes, shared by the normal and tangential layered punch.

A stack at one frequency in the units of its top film (:class:`Stack`), the difference of its
surface kernel and the film's (H_33 for the normal punch, the in-plane block H_αβ for the
tangential one), and the nodes on which that difference is integrated against the products of
the transforms of the Galerkin basis (:func:`correction_nodes`): the arc lifted above the poles
of the guided modes and the branch points, then geometric real-axis panels with Chebyshev
samples in ln s, until the difference has decayed. The method and its measured accuracy are
described in the modules ``contactres.dynamic._layered_punch`` (normal) and
``contactres.dynamic._layered_tangential`` (tangential).
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
from ._normal_stiffness import normalised_wavenumber
from ._table import max_slowness

__all__ = [
    "PunchResolution",
    "Stack",
    "bessel_on_nodes",
    "correction_nodes",
    "film_reference",
    "punch_resolution",
    "stack_at",
    "stack_of",
]

# T = _POLE_FACTOR × ω × (largest bulk slowness): beyond every pole and branch point (the same
# margin as the far-field start T₁ of the kernel table).
_POLE_FACTOR = 1.75
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
    n_start : nodes of the first real panel [0, s₀] (statics)
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


def film_reference(m: Material) -> tuple[Material, float]:
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
class Stack:
    """One frequency's stack in the film's units: tensors / C44_f, ρ_j ω²/C44_f, thicknesses,
    and the reference half-space of the film's kernel table (tensor / C44_f)."""

    tensors: list
    reference: np.ndarray
    inertia: list  # ρ_j ω²/C44_f, 1/m² (s_j = inertia_j/η²)
    thicknesses: np.ndarray
    pole: float  # T, 1/m: beyond every pole and branch point on the real η axis
    k_max: float  # largest shear wave number of any material, 1/m
    axisymmetric: bool
    inplane: bool = False  # the kernel: H_33 (normal punch) or the block H_αβ (tangential)

    def _block(self, tensors, eta, theta, inertia=None):
        e = eta[:, None] * np.ones_like(theta)[None, :]
        th = np.broadcast_to(theta[None, :], e.shape)
        s = [r / e**2 for r in (self.inertia if inertia is None else inertia)][: len(tensors)]
        hs = [e * h for h in self.thicknesses][: len(tensors) - 1]
        H = stack_compliance(tensors, s, hs, th)
        return H[..., :2, :2] if self.inplane else H[..., 2, 2]

    @property
    def needs_correction(self) -> bool:
        """True under layers, or for a film that is not its reference."""
        scale = 1e-14 * np.max(np.abs(self.reference))
        return len(self.tensors) > 1 or not np.allclose(
            self.tensors[0], self.reference, rtol=0, atol=scale
        )

    def static_shift(self, theta: np.ndarray) -> np.ndarray:
        """g∞_film − g∞_ref (θ): the static kernels of the film and of its reference."""
        one, zero = np.ones(1), [0.0]
        ref = self._block([self.reference], one, theta, zero)
        return (ref - self._block(self.tensors[:1], one, theta, zero))[0]

    def delta_g(self, eta: np.ndarray, theta: np.ndarray, shift: np.ndarray) -> np.ndarray:
        """Δg = g_stack − g_ref − (g∞_film − g∞_ref) at wavenumbers ``eta`` (1/m, complex) ×
        directions ``theta``, shape (len(eta), len(theta)) (+ (2, 2) for the in-plane block);
        -> 0 as η -> ∞."""
        ref = self._block([self.reference], eta, theta)
        return ref - self._block(self.tensors, eta, theta) - shift[None]


def stack_at(
    mats, thicknesses, film: Material, q: float, frequency: float, inplane: bool = False
) -> Stack:
    """The :class:`Stack` of the materials ``mats`` (top first) at ``frequency``, in the units
    of the film's reference ``film`` (undamped) with loss ``q``; ``inplane``: the in-plane
    block of the compliance (tangential punch) instead of H_33."""
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
    return Stack(
        tensors=[voigt_to_tensor(np.asarray(m.C, dtype=complex)) / c44 for m in mats],
        reference=voigt_to_tensor(np.asarray(film.C, dtype=complex)) * (1 + 1j * q) / c44,
        inertia=[(m.density or 0.0) * omega**2 / c44 for m in mats],
        thicknesses=np.asarray(thicknesses, dtype=float),
        pole=_POLE_FACTOR * max(slow),
        k_max=max(ks),
        axisymmetric=_axisymmetric(mats),
        inplane=inplane,
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


def correction_nodes(stack: Stack, a: float, theta: np.ndarray, res: PunchResolution, gref):
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
    # The geometric panels start at the end of the arc, where Δg varies on the scale S₁ (one
    # panel [S₁, s₀] would not resolve it at small k a); in statics after a first panel [0, s₀].
    start = s1 if s1 > 0 else s0
    if s1 == 0:
        t, wt = gauss_legendre(0.0, s0, res.n_start)
        nodes.append(t.astype(complex))
        weights.append(wt.astype(complex))
    # The real-axis panel edges e_k = start × ratio^k up to _S_MAX, probed in one call: the last
    # panel ends past every edge where what lies beyond (~|Δg(e)|/e, as j_p j_q <= 1/s²) is
    # still above 1e-3 rtol of |g|; Δg of layers decays like e^{−2ηh} (η h > 5 first), that of
    # a film with unequal losses like 1/s² (s > 20 first, for the tail formula).
    n_edges = math.ceil(math.log(_S_MAX / start) / math.log(res.ratio))
    edges = start * res.ratio ** np.arange(n_edges + 1, dtype=np.float64)
    probe = stack.delta_g(edges.astype(complex) / a, theta, shift)
    big = np.abs(probe).reshape(edges.size, -1).max(axis=1) / edges >= res.decay * gref
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
        g_all.append(_cheb_interp(xc, cheb[j], x).reshape(x.size, *values.shape[1:]))
    return (
        np.concatenate(s_all),
        np.concatenate(w_all),
        np.concatenate(g_all),
        float(edges[last]),
        probe[last],
        shift,
    )


def bessel_on_nodes(p_max: int, s: np.ndarray) -> np.ndarray:
    """j_p(s), p = 0..p_max, (p_max + 1, len(s)) complex, on the nodes ``s`` of the correction."""
    from ._weights import spherical_bessel

    out = np.empty((p_max + 1, s.size), dtype=complex)
    # Real nodes apart: their Bessel functions come from the cheap upward recurrence (the
    # continued fraction of complex arguments would start above 1.3 max|s| for every node).
    real = s.imag == 0
    out[:, real] = spherical_bessel(p_max, s[real].real)
    out[:, ~real] = spherical_bessel(p_max, s[~real])
    return out


def stack_of(material, frequency: float):
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
