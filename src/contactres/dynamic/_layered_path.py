"""The layered correction's path and nodes, shared by the normal and tangential layered punch.

A stack at one frequency in the units of its top film (:class:`Stack`), the difference of its
surface kernel and the film's (H_33 for the normal punch, the in-plane block H_αβ for the
tangential one), and the nodes on which that difference is integrated against the products of
the transforms of the Galerkin basis (:func:`correction_nodes`): the arc lifted above the poles
of the guided modes and the branch points, then geometric real-axis panels with Chebyshev
samples in ln s, until the difference has decayed (the Gauss nodes on those panels and the
interpolation of Δg onto them: ``contactres.dynamic._layered_nodes``). The method and its
measured accuracy are described in the modules ``contactres.dynamic._layered_punch`` (normal)
and ``contactres.dynamic._layered_tangential`` (tangential).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ContactresInputError
from ..halfspace import shear_reference
from ..layered import LayeredMaterial, material_at, stack_compliance
from ..materials import Material, voigt_to_tensor
from ..numerics import gauss_legendre
from ._layered_arc import ParameterFit, fit_in_parameter
from ._layered_nodes import (
    PunchResolution,
    assemble_nodes,
    concatenated_ranges,
    rule_on,
    split_at,
    unit_rule,
)
from ._layered_waves import (
    ARC_LIFT,
    ARC_PANELS,
    StackWaves,
    arc_fraction,
    chebyshev_matrix,
    is_isotropic,
    slowness_table,
    waves_at,
)
from ._table import max_slowness

__all__ = [
    "Stack",
    "correction_nodes",
    "film_reference",
    "is_axisymmetric",
    "stack_at",
    "stack_of",
]

# T = _POLE_FACTOR × ω × (largest bulk slowness): beyond every pole and branch point (the same
# margin as the far-field start T₁ of the kernel table).
_POLE_FACTOR = 1.75
# η h₁ (top film) beyond which the edges of a film that is its own reference are probed only
# where Δg has not decayed yet (:func:`_probes`).
_PROBE_ETA_H = 50.0
# Largest η a of the correction's nodes: a film thinner than ~a/1e5 is out of reach (the nodes
# resolve the oscillation of j_p j_q, ~3 per unit of s).
_S_MAX = 1e6
# Largest lift of the arc (in s = η a): j_p j_q grow like e^{2 Im s} on it.
_MAX_LIFT = 1.5
# Real samples of Δg solved together (see _chunk_nodes: small groups reuse the heap's pages).
_GROUP_NODES = 2048


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


def is_axisymmetric(mats) -> bool:
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
    sigma: list  # ρ_j/C44_f, s²/m² (s_j = σ_j ω²/η²)
    omega: float  # ω, rad/s
    thicknesses: np.ndarray
    pole_slowness: float  # p₁ = T/ω, s/m: beyond every pole and branch point (T = p₁ ω)
    k_max: float  # largest shear wave number of any material, 1/m
    axisymmetric: bool
    inplane: bool = False  # the kernel: H_33 (normal punch) or the block H_αβ (tangential)
    # Equal for the stacks of one material set at any frequency (the waves of one slowness
    # are then the same: ``contactres.dynamic._layered_waves``): :func:`_set_key`.
    key: bytes = field(init=False, repr=False)
    # True under layers, or for a film that is not its reference: :func:`_needs_correction`.
    # Both are the same at every frequency, so formed once per material set (a few numpy
    # calls per point otherwise: ~0.5 ms of the 41-point curves) and carried to the stack of
    # each frequency by :meth:`at_frequency`. Not arguments: a stack made or replaced with
    # other materials forms its own (a key given or kept from another material set grouped
    # it with that set's waves, 3 % off in Δg: review R31e).
    needs_correction: bool = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "key", _set_key(self))
        object.__setattr__(self, "needs_correction", _needs_correction(self))

    def at_frequency(self, omega: float, k_max: float) -> Stack:
        """This stack at the angular frequency ``omega`` (rad/s) with its largest shear wave
        number ``k_max`` (1/m): a copy with those two fields set, its key and
        ``needs_correction`` kept (neither depends on ω: :func:`_set_key`)."""
        out = copy.copy(self)
        object.__setattr__(out, "omega", omega)
        object.__setattr__(out, "k_max", k_max)
        return out

    @property
    def pole(self) -> float:
        """T = p₁ ω, 1/m: beyond every pole and branch point on the real η axis."""
        return self.pole_slowness * self.omega

    def _block(self, tensors, theta):
        """The static kernel block of a half-space of the tensor ``tensors[0]``."""
        H = stack_compliance(tensors, [0.0], [], theta)
        return H[..., :2, :2] if self.inplane else H[..., 2, 2]

    def static_shift(self, theta: np.ndarray) -> np.ndarray:
        """g∞_film − g∞_ref (θ): the static kernels of the film and of its reference."""
        if np.array_equal(self.reference, self.tensors[0]):
            # A film that is its own reference: zero (the two ~1 ms static solutions skipped).
            return np.zeros(theta.shape + ((2, 2) if self.inplane else ()), dtype=complex)
        return self._block([self.reference], theta) - self._block(self.tensors[:1], theta)


def stack_at(
    mats,
    thicknesses,
    film: Material,
    q: float,
    frequency: float,
    inplane: bool = False,
    known: dict | None = None,
) -> Stack:
    """The :class:`Stack` of the materials ``mats`` (top first) at ``frequency``, in the units
    of the film's reference ``film`` (undamped) with loss ``q``; ``inplane``: the in-plane
    block of the compliance (tangential punch) instead of H_33. ``known``: a dict the caller
    keeps over its frequencies, where each material's symmetry and slowness are kept once
    found (the same materials at every frequency need them once)."""
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
    known = {} if known is None else known
    # What does not depend on the frequency, found once for the materials (by their constants).
    members = tuple((np.asarray(m.C).tobytes(), m.density) for m in mats)
    film_c, hs = np.asarray(film.C).tobytes(), np.asarray(thicknesses).tobytes()
    key = ("stack", inplane, q, film_c, hs, members)
    if key not in known:
        known[key] = _frequency_free(mats, thicknesses, film, q, inplane, known)
    fixed, slow_max = known[key]
    return fixed.at_frequency(omega, omega * slow_max)


def _frequency_free(mats, thicknesses, film: Material, q: float, inplane: bool, known: dict):
    """(the :class:`Stack` of :func:`stack_at` at ω = 0, the largest shear slowness √(ρ/C44)
    of its materials (k_max = ω × it), s/m)."""
    c44 = shear_reference(film)
    props = []
    for m in mats:
        key = (np.asarray(m.C).tobytes(), m.density)
        if key not in known:
            # The shear slowness √(ρ/C44) (k_s = ω × it), the largest bulk slowness along the
            # surface and the symmetry about the normal of one material, s/m.
            slow = math.sqrt((m.density or 0.0) / shear_reference(m))
            C = np.asarray(m.C)
            if is_isotropic(voigt_to_tensor(C.real)) and C[0, 0].real >= C[3, 3].real:
                # Isotropic: the shear wave is the slowest bulk wave in every direction and
                # the material is axisymmetric (the general search and test cost ~0.6 ms).
                known[key] = (slow, slow, True)
            else:
                known[key] = (slow, slow * max_slowness(m), is_axisymmetric([m]))
        props.append(known[key])

    def tensor(m, factor=1.0):
        # The tensor / C44_f of one material, formed once over the frequencies.
        key = ("tensor", np.asarray(m.C).tobytes(), factor, c44)
        if key not in known:
            known[key] = voigt_to_tensor(np.asarray(m.C, dtype=complex)) * factor / c44
        return known[key]

    stack = Stack(
        tensors=[tensor(m) for m in mats],
        reference=tensor(film, 1 + 1j * q),
        sigma=[(m.density or 0.0) / c44 for m in mats],
        omega=0.0,
        thicknesses=np.asarray(thicknesses, dtype=float),
        pole_slowness=_POLE_FACTOR * max(p[1] for p in props),
        k_max=0.0,
        axisymmetric=all(p[2] for p in props),
        inplane=inplane,
    )
    return stack, max(p[0] for p in props)


def _set_key(st: Stack) -> bytes:
    """:attr:`Stack.key`: the bytes of what the stacks of one material set share (all but ω)."""
    parts = [*st.tensors, st.reference, np.asarray(st.sigma), st.thicknesses]
    flags = np.array([st.inplane, st.axisymmetric, st.pole_slowness])
    return b"".join(np.ascontiguousarray(x).tobytes() for x in (*parts, flags))


def _needs_correction(st: Stack) -> bool:
    """:attr:`Stack.needs_correction`: layers under the film, or a film unequal to its
    reference (beyond 1e-14 of the largest constant)."""
    scale = 1e-14 * np.max(np.abs(st.reference))
    return len(st.tensors) > 1 or not np.allclose(st.tensors[0], st.reference, rtol=0, atol=scale)


def correction_nodes(
    stacks, radii, theta: np.ndarray, res: PunchResolution, gref, rule=None
) -> dict:
    """The ΔM integral's nodes of every stack that needs a correction: index i of ``stacks``
    (with radius ``radii[i]``) -> (s (complex), ds, Δg(s/a, θ) (len(s), len(theta)) (+ (2, 2)
    in-plane), the end S of the nodes, Δg(S/a, θ) there (for the tail beyond S), the static
    shift g∞_film − g∞_ref (θ)).

    The stacks of one material set (one per frequency) share their layer waves on the
    slowness (``contactres.dynamic._layered_waves``) and are solved together, in chunks of
    at most ~_NODE_BUDGET nodes × directions. ``rule``: the caller's
    :func:`~contactres.dynamic._layered_nodes.unit_rule` of ``res.n_panel`` (None: made here)."""
    rule = rule if rule is not None else unit_rule(res.n_panel)
    groups: dict = {}
    for i, st in enumerate(stacks):
        if st.needs_correction:
            groups.setdefault(st.key, []).append(i)
    out: dict = {}
    per_chunk = max(1, _NODE_BUDGET // (_NODES_PER_POINT * theta.size))
    for members in groups.values():
        shared = _SharedWaves(stacks[members[0]], theta, res, [stacks[i] for i in members], rule)
        shared.fit_arc([stacks[i] for i in members], [float(radii[i]) for i in members])
        for k in range(0, len(members), per_chunk):
            chunk = members[k : k + per_chunk]
            out.update(_chunk_nodes(shared, [stacks[i] for i in chunk], radii, chunk, res, gref))
    return out


# Nodes × directions solved together (memory: a few kB each), and a typical count of nodes per
# point (sets the number of points per chunk).
_NODE_BUDGET = 40000
_NODES_PER_POINT = 250


class _SharedWaves:
    """What the stacks of one material set share: the static shift, the slowness table of the
    real axis, the waves on the arc of lift 0.3 S₁ and the static waves."""

    def __init__(self, st: Stack, theta, res: PunchResolution, stacks, rule=None):
        self.theta = theta
        # The Gauss-Legendre rule of res.n_panel on [−1, 1], mapped onto every panel.
        self.rule = rule if rule is not None else unit_rule(res.n_panel)
        self.shift = st.static_shift(theta)
        self.stack = st
        # Which layers are isotropic (their exponentials in closed form), tested once.
        self.isotropic = [is_isotropic(c) for c in st.tensors[:-1]]
        dynamic = [x for x in stacks if x.omega > 0]
        # The normal kernel of an axisymmetric stack of isotropic layers at θ = 0 reads the
        # sagittal blocks alone (StackWaves.delta_g): every set of waves below is kept in the
        # sagittal form, so that its interpolations and copies move those rows only.
        self.sagittal = (
            bool(self.isotropic)
            and all(self.isotropic)
            and not st.inplane
            and st.axisymmetric
            and theta.size == 1
            and theta[0] == 0
        )
        table = slowness_table(st, theta) if dynamic else None
        self.table = self._form(table) if table is not None else None
        self.static = self.solved(st, [0.0]) if len(dynamic) < len(stacks) else None
        edges = np.linspace(0.0, 1.0, ARC_PANELS + 1)
        tau, wt = rule_on(self.rule, edges[:-1, None], edges[1:, None])
        # The shared arc's nodes z(τ) and weights z'(τ) dτ (s = S₁ z, ds = S₁ z' dτ).
        self.z = arc_fraction(tau.ravel())
        self.dz = (wt * (1 + 1j * ARC_LIFT * np.pi * np.cos(np.pi * tau))).ravel()
        self.arc = None
        if dynamic:
            # x = ω²/η² on the arc s = S₁ z(τ): 1/(p₁ z)², the same at every frequency.
            self.arc = self.solved(st, 1 / (st.pole_slowness * self.z) ** 2)
        self._panels: StackWaves | None = None  # panel_waves' samples (grown on demand)
        self.arc_fit: ParameterFit | None = None  # Δg on the shared arc in T (fit_arc)

    def _form(self, waves: StackWaves) -> StackWaves:
        """``waves`` in the set's form: the sagittal one (``self.sagittal``; isotropic layers
        are mirror planes), else as they are."""
        return waves.sagittal_form() if self.sagittal else waves

    def solved(self, st: Stack, x) -> StackWaves:
        """The waves of ``st`` solved directly at x = ω²/η² (:func:`waves_at`), in the set's
        form (:meth:`_form`)."""
        return self._form(waves_at(st, self.theta, x))

    def fit_arc(self, stacks, radii) -> None:
        """Δg on the shared arc as a polynomial in T = p₁ ω over the points of ``stacks``
        (radii ``radii``, m) whose head is that arc (``contactres.dynamic._layered_arc``:
        none where it would not meet its bound with fewer solutions than points)."""
        poles = np.array([st.pole for st, a in zip(stacks, radii, strict=True) if _shared(st, a)])
        if self.arc is not None and poles.size > 1:
            lo, hi = float(np.min(poles)), float(np.max(poles))
            self.arc_fit = fit_in_parameter(self._arc_delta_g, lo, hi, poles.size)

    def _arc_delta_g(self, poles: np.ndarray) -> np.ndarray:
        """Δg (len(poles), arc nodes, nθ) on the shared arc at T = ``poles``: η h_j = (s/a) h_j
        = T h_j z, so a radius of 1 with s = T z gives it."""
        assert self.arc is not None  # fit_arc checks it
        parts = [(self.stack, 1.0, t * self.z) for t in poles]
        return np.array(_delta_g(self, parts, StackWaves.combined([self.arc] * poles.size)))

    def panel_waves(self, counts, ratio: float, n_cheb: int) -> StackWaves:
        """The waves at the real samples of dynamic points whose geometric panels start at
        their arc's end S₁ (ratio ``ratio``, ``n_cheb`` Chebyshev samples in ln s per panel),
        point k's first ``counts[k]`` samples one after the other. There y = (S₁/s)² =
        e^{−2 (u − ln S₁)} is the same at every point (the panels are one geometric sequence in
        s/S₁), so the waves are interpolated from the table once, at the samples of the
        longest, and each point's are its first ones (equal to their own interpolation to
        round-off: y differs only by the rounding of s)."""
        assert self.table is not None  # the caller checks that the table serves
        n = int(np.max(counts))
        if self._panels is None or self._panels.size < n:
            n_pan = -(-n // n_cheb)
            xc = np.cos(np.pi * (np.arange(n_cheb) + 0.5) / n_cheb)
            u = np.arange(n_pan + 1) * np.log(ratio)
            uc = 0.5 * (u[:-1, None] + u[1:, None]) + 0.5 * (u[1:, None] - u[:-1, None]) * xc
            y = np.exp(-2 * uc).ravel()
            self._panels = self.table.interpolated(chebyshev_matrix(self.table.size, 2 * y - 1))
        return _rows_of(self._panels, [(0, int(c)) for c in counts])

    def edge_waves(self, items: list, ranges: list[tuple[int, int]], ratio: float) -> StackWaves:
        """:meth:`real_all` of the panel edges of ``items`` [(stack, a, edges[lo:hi]), ...],
        ``ranges`` [(lo, hi), ...]. A dynamic point's edges e_i = S₁ ratio^i have y = (S₁/e_i)²
        = ratio^(−2i), the same at every point (as :meth:`panel_waves`' samples): the waves
        are interpolated once, at the i of the longest, and each point takes its own rows
        (equal to their own interpolation to round-off: y differs by the rounding of e_i); a
        static point takes the static waves."""
        dynamic = [st.omega > 0 for st, _, _ in items]
        if self.table is None or not any(dynamic):
            return self.real_all(items)
        n = max(hi for (_, hi), d in zip(ranges, dynamic, strict=True) if d)
        y = ratio ** (-2.0 * np.arange(n))
        waves = self.table.interpolated(chebyshev_matrix(self.table.size, 2 * y - 1))
        if all(dynamic):
            return _rows_of(waves, ranges)
        assert self.static is not None  # built whenever a stack of the set is static
        # The static waves at row n, repeated for each static point.
        waves = StackWaves.combined([waves, self.static])
        rows = [
            (lo, hi) if d else (n, lo - hi) for (lo, hi), d in zip(ranges, dynamic, strict=True)
        ]
        return _rows_of(waves, rows)

    def static_at(self, n: int) -> StackWaves:
        """The static waves (x = 0) on ``n`` nodes (statics: the same at every η)."""
        assert self.static is not None  # built whenever a stack of the set is static
        return self.static.repeated(np.full(1, n))

    def real(self, st: Stack, a: float, s: np.ndarray) -> StackWaves:
        """The waves at real nodes s >= S₁ (η = s/a) of the stack ``st``."""
        if st.omega == 0:
            return self.static_at(s.size)
        if self.table is None:
            return self.solved(st, (st.omega * a / s) ** 2)
        y = (st.pole * a / s) ** 2
        return self.table.interpolated(chebyshev_matrix(self.table.size, 2 * y - 1))

    def real_all(self, items) -> StackWaves:
        """:meth:`real` of every (stack, a, s) of ``items``, one after the other: where every
        stack is dynamic and the table serves, one interpolation for all of them (one
        barycentric matrix and one batched product per array instead of one per point)."""
        dynamic = [(st, a, s) for st, a, s in items if st.omega > 0]
        if self.table is None or not dynamic:
            return StackWaves.combined([self.real(st, a, s) for st, a, s in items])
        y = np.concatenate([(st.pole * a / s) ** 2 for st, a, s in dynamic])
        waves = self.table.interpolated(chebyshev_matrix(self.table.size, 2 * y - 1))
        if len(dynamic) == len(items):
            return waves
        # Static points (f = 0) among them: their waves in their places.
        ends = np.cumsum([s.size for _, _, s in dynamic])
        parts, k = [], 0
        for st, _, s in items:
            if st.omega == 0:
                parts.append(self.static_at(s.size))
            else:
                lo = ends[k] - s.size
                parts.append(waves._with([x[..., lo : ends[k], :] for x in waves.arrays()]))
                k += 1
        return StackWaves.combined(parts)


def _rows_of(waves: StackWaves, ranges: list[tuple[int, int]]) -> StackWaves:
    """The rows lo..hi − 1 of ``waves`` for each (lo, hi) of ``ranges``, one after the other
    ((lo, −k): row lo k times), joined slice by slice: each entry's values at the nodes stay
    contiguous, as the recursion reads them (a gather by an index array along the node axis
    put the nodes outermost: the recursion's ~100 products then ran over strided vectors)."""

    def piece(w: np.ndarray, lo: int, hi: int) -> np.ndarray:
        if hi >= 0:
            return w[..., lo:hi, :]
        return np.broadcast_to(w[..., lo : lo + 1, :], (*w.shape[:-2], -hi, w.shape[-1]))

    return waves._with(
        [np.concatenate([piece(w, lo, hi) for lo, hi in ranges], axis=-2) for w in waves.arrays()]
    )


def _head(shared: _SharedWaves, st: Stack, a: float, res: PunchResolution, s0: float):
    """Nodes, weights and waves of the part before the real panels: the lifted arc (dynamic)
    or the first real panel [0, s₀] (statics)."""
    s1 = st.pole * a
    if s1 == 0:
        if res.n_start == res.n_panel:
            t, wt = rule_on(shared.rule, 0.0, s0)
        else:
            t, wt = gauss_legendre(0.0, s0, res.n_start)
        return t.astype(complex), wt.astype(complex), shared.static_at(t.size)
    if _shared(st, a):
        # The arc of every frequency with this lift is one arc in the slowness (shared waves).
        nodes, weights = s1 * shared.z, s1 * shared.dz
        return nodes, weights, shared.arc
    lift = _MAX_LIFT
    n_pan = max(ARC_PANELS, math.ceil(s1 / lift))
    edges = np.linspace(0.0, s1, n_pan + 1, dtype=np.float64)
    t, wt = rule_on(shared.rule, edges[:-1, None], edges[1:, None])
    t, wt = t.ravel(), wt.ravel()
    arg = np.pi * t / s1
    lifted = t + 1j * lift * np.sin(arg)
    along = wt * (1 + 1j * lift * np.pi / s1 * np.cos(arg))
    return lifted, along, shared.solved(st, (st.omega * a / lifted) ** 2)


def _shared(st: Stack, a: float) -> bool:
    """True if the dynamic point (``st``, radius ``a``) has the shared arc as its head: its lift
    0.3 S₁ is below the cap (S₁ = T a <= 5)."""
    s1 = st.pole * a
    return s1 > 0 and min(ARC_LIFT * s1, _MAX_LIFT) == ARC_LIFT * s1


def _head_delta_g(shared: _SharedWaves, heads) -> list:
    """Δg at the head nodes of every (stack, a, (s, ds, waves)) of ``heads``: on the shared arc
    from its fit in T where there is one, the others solved together."""
    fit = shared.arc_fit
    on = [fit is not None and head[2] is shared.arc for _, _, head in heads]
    out: list = [None] * len(heads)
    rest = [k for k, o in enumerate(on) if not o]
    if rest:
        parts = [(heads[k][0], heads[k][1], heads[k][2][0]) for k in rest]
        waves = StackWaves.combined([heads[k][2][2] for k in rest])
        for k, v in zip(rest, _delta_g(shared, parts, waves), strict=True):
            out[k] = v
    fitted = [k for k, o in enumerate(on) if o]
    if fit is not None and fitted:
        for k, v in zip(fitted, fit(np.array([heads[k][0].pole for k in fitted])), strict=True):
            out[k] = v
    return out


def _delta_g(shared: _SharedWaves, parts, waves: StackWaves) -> list:
    """Δg at the nodes of every (stack, a, s) of ``parts``, solved together, with ``waves``
    the waves of all their nodes one after the other."""
    n_layers = len(shared.stack.tensors) - 1
    eta_h = [
        np.concatenate([s / a * st.thicknesses[j] for st, a, s in parts]) for j in range(n_layers)
    ]
    values = waves.delta_g(shared.stack, eta_h, shared.shift, shared.theta, shared.isotropic)
    return split_at(values, np.cumsum([s.size for _, _, s in parts])[:-1])


def _chunk_nodes(shared: _SharedWaves, stacks, radii, index, res: PunchResolution, gref) -> dict:
    """:func:`correction_nodes` of the points ``index`` (stacks ``stacks``) of one set."""
    plan = []
    for st, i in zip(stacks, index, strict=True):
        a = float(radii[i])
        s1 = st.pole * a
        h_tot = float(np.sum(st.thicknesses))
        s0 = 0.1 * min(1.0, a / h_tot) if h_tot > 0 else 0.1
        # The geometric panels start at the end of the arc, where Δg varies on the scale S₁
        # (one panel [S₁, s₀] would not resolve it at small k a); in statics after a first
        # panel [0, s₀]. Their edges e_k = start × ratio^k up to _S_MAX are probed together
        # (past η h₁ = 50 only where Δg has not decayed, :func:`_probes`):
        # the last panel ends past every edge where what lies beyond (~|Δg(e)|/e, as
        # j_p j_q <= 1/s²) is still above 1e-3 rtol of |g|; Δg of layers decays like e^{−2ηh}
        # (η h > 5 first), that of a film with unequal losses like 1/s² (s > 20 first, for the
        # tail formula).
        start = s1 if s1 > 0 else s0
        n_edges = math.ceil(math.log(_S_MAX / start) / math.log(res.ratio)) + 1
        edges = start * res.ratio ** np.arange(n_edges + 1, dtype=np.float64)
        plan.append((st, a, h_tot, s0, edges))
    probes = _probes(shared, plan, res.decay * gref, res.ratio)
    threshold = res.decay * gref
    # Every point's edges (and what lies beyond each, rest = |Δg|/e) one after the other, point
    # k's from row first[k]: where the panels stop, for all the points at once.
    sizes = np.array([p[4].size for p in plan])
    first = np.cumsum(sizes) - sizes
    edges = np.concatenate([p[4] for p in plan])
    probe = np.concatenate(probes)
    rest = np.abs(probe).reshape(edges.size, -1).max(axis=1) / edges
    thick, radius = (np.repeat([p[i] for p in plan], sizes) for i in (2, 1))
    forced = _forced(edges, thick, radius)
    big = forced | (rest >= threshold)
    # last: one past the last edge kept (at or above the threshold, or forced), 1 if none.
    kept = np.where(big, concatenated_ranges(sizes) + 1, 0)
    lasts = np.maximum(np.maximum.reduceat(kept, first), 1)
    for (_, a, h, _, e), last in zip(plan, lasts, strict=True):
        if last > e.size - 2:
            raise ContactresInputError(
                f"the layered correction did not decay by η a = {_S_MAX:.3g}: a film "
                f"{h:.3g} m thin under a punch of radius {a:.3g} m (h/a = {h / a:.2g}) "
                "is out of reach"
            )
    stops = [
        _stop(edges[k : k + n], rest[k : k + n], forced[k : k + n], int(last), threshold)
        for k, n, last in zip(first, sizes, lasts, strict=True)
    ]
    # Δg at Chebyshev points in ln s per panel, after the arc (or first panel), one panel
    # beyond edges[last] (the nodes end at the next grid edge, < 1.5 edges[last]).
    xc = np.cos(np.pi * (np.arange(res.n_cheb) + 0.5) / res.n_cheb)
    lo = np.repeat(first, lasts + 1) + concatenated_ranges(lasts + 1)
    u0, u1 = np.log(edges[lo])[:, None], np.log(edges[lo + 1])[:, None]
    sc = np.exp(0.5 * (u0 + u1) + 0.5 * (u1 - u0) * xc[None, :]).ravel()
    parts = [
        (st, a, _head(shared, st, a, res, s0), s)
        for (st, a, _, s0, _), s in zip(
            plan, split_at(sc, np.cumsum((lasts + 1) * res.n_cheb)[:-1]), strict=True
        )
    ]
    # Every head first, then every point's real samples, in groups of points of at most
    # ~_GROUP_NODES nodes (one interpolation per group): a group's interpolated waves and the
    # recursion's temporaries stay small enough to be reused from the heap, where those of all
    # ~10000 samples at once were fresh pages on every call (their page faults cost about a
    # tenth of the 250 nm curve); the values are the same node by node. A static point
    # (f = 0) is a group apart: a group of dynamic points alone takes its waves from the
    # shared panels' (one slice), where one static point among them made the whole group's
    # waves interpolated afresh (~4 % of the 250 nm curve).
    reals = [(st, a, sc) for st, a, _, sc in parts]
    pieces = _head_delta_g(shared, [(st, a, head) for st, a, head, _ in parts])
    group: list = []
    for k, item in enumerate(reals):
        group.append(item)
        size = sum(s.size for _, _, s in group)
        if (
            k + 1 == len(reals)
            or size + reals[k + 1][2].size > _GROUP_NODES
            or (item[0].omega > 0) != (reals[k + 1][0].omega > 0)
        ):
            if shared.table is not None and all(st.omega > 0 for st, _, _ in group):
                waves = shared.panel_waves([s.size for _, _, s in group], res.ratio, res.n_cheb)
            else:
                waves = shared.real_all(group)
            pieces += _delta_g(shared, group, waves)
            group = []
    n = len(parts)
    samples = [np.concatenate(hr) for hr in zip(pieces[:n], pieces[n:], strict=True)]
    rule = rule_on(shared.rule, 0.0, 1.0)
    points = [(plan[k][4], int(lasts[k]), stops[k], parts[k][2], samples[k]) for k in range(n)]
    return dict(zip(index, assemble_nodes(res, rule, points, shared.shift), strict=True))


def _stop(edges, rest, forced, last: int, threshold: float) -> float:
    """Where the nodes may end, between ``edges[last − 1]`` (the last edge where what lies
    beyond, ``rest`` = ``|Δg|``/s, is at or above ``threshold``) and ``edges[last]`` (the first
    below it): where ln ``rest``, interpolated linearly in s between the two (exact for the
    e^{−2ηh} decay of Δg under layers, up to the slowly varying 1/s), reaches the threshold;
    ``edges[last]`` where the last edge above it was only kept by ``forced`` (s <= 20,
    η h <= 5), or where the decay is not resolved (``rest`` zero at ``edges[last]``)."""
    if last < 1 or forced[last - 1]:
        return float(edges[last])
    r0, r1 = float(rest[last - 1]), float(rest[last])
    if not (r0 >= threshold > r1 > 0):
        return float(edges[last])
    return float(
        edges[last - 1]
        + (edges[last] - edges[last - 1]) * math.log(r0 / threshold) / math.log(r0 / r1)
    )


def _probes(shared: _SharedWaves, plan, threshold: float, ratio: float) -> list:
    """Δg at the edges of every point of ``plan`` [(stack, a, h_tot, s₀, edges), ...].

    Under a film that is its own reference, Δg decays like e^{−2 α η h₁} (h₁ the film's
    thickness, α the slowest decay rate of its partial waves) once past the poles: the edges
    beyond η h₁ = :data:`_PROBE_ETA_H` are probed only for the points whose last edge before
    it is not yet 1e-12 below the decay threshold (``threshold`` = decay × ``|g|``, what
    ``|Δg|``/s is compared with); the others' are zero (far below round-off of the result).
    ``ratio``: that of the edges (e_i = S₁ ratio^i for a dynamic point)."""
    stack = shared.stack
    own = len(stack.tensors) > 1 and np.array_equal(stack.reference, stack.tensors[0])
    n_probe = [
        max(1, int(np.sum(e * st.thicknesses[0] / a <= _PROBE_ETA_H))) if own else e.size
        for st, a, _, _, e in plan
    ]
    # The leading edges kept by _forced are not probed (their values decide nothing), but
    # for the last one probed.
    skip = [
        min(int(np.sum(_forced(e, h, a))), n - 1)
        for (_, a, h, _, e), n in zip(plan, n_probe, strict=True)
    ]
    first = [(st, a, e[k:n]) for (st, a, _, _, e), k, n in zip(plan, skip, n_probe, strict=True)]
    ranges = list(zip(skip, n_probe, strict=True))
    out = _delta_g(shared, first, shared.edge_waves(first, ranges, ratio))
    rest = [
        k
        for k, ((*_, e), n, value) in enumerate(zip(plan, n_probe, out, strict=True))
        if n < e.size and not np.max(np.abs(value[-1])) / e[n - 1] < 1e-12 * threshold
    ]
    if rest:
        more = [(plan[k][0], plan[k][1], plan[k][4][n_probe[k] :]) for k in rest]
        ranges = [(n_probe[k], plan[k][4].size) for k in rest]
        waves = shared.edge_waves(more, ranges, ratio)
        for k, value in zip(rest, _delta_g(shared, more, waves), strict=True):
            out[k] = np.concatenate([out[k], value])
    probes = []
    for (*_, e), k, value in zip(plan, skip, out, strict=True):
        full = np.zeros((e.size, *value.shape[1:]), dtype=value.dtype)
        full[k : k + value.shape[0]] = value
        probes.append(full)
    return probes


def _forced(edges: np.ndarray, h_tot, a) -> np.ndarray:
    """The edges the nodes reach whatever ``|Δg|``: s <= 20 (the tail formula's start) and
    η h <= 5 (the e^{−2ηh} decay of Δg under layers has not begun); a prefix of ``edges``
    (``h_tot``, ``a``: the total thickness and the radius, m, floats or one per edge)."""
    return (edges <= 20) | ((h_tot > 0) & (edges * h_tot / a <= 5))


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
