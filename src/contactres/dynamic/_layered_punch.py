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
kernel table, contour and far field: ``contactres.dynamic._exact.galerkin_matrix``; as on the
homogeneous curve, the far grid beyond 2 T₁ × the largest k_s a is summed by its moments,
``contactres.dynamic._fartail``) and
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
film's Rayleigh pole, in both terms) and the branch points of the substrate, all at η <= T =
1.75 ω × (largest bulk slowness of any material). The path is the arc s(t) = t + i H sin(π t/S₁)
on 0 <= t <= S₁ = T a (Gauss-Legendre panels no wider than H), lifted by H = min(0.3 S₁, 1.5):
the products j_p j_q grow like e^{2 Im s}, so the lift stays O(1) in s (O(1/a) in η); up to S₁ =
5 (k_s a up to ~2.6 on PMMA over quartz) the arc is one arc in the slowness, whose layer
solutions every frequency shares. Beyond S₁, on the real axis, Δg has no singularity and varies
only on the scales 1/h and the wave numbers (not on the period π of j_p j_q): on geometric
panels of ratio 1.5 it is sampled at Chebyshev points (in ln s) and interpolated onto
Gauss-Legendre nodes dense enough for the oscillation of j_p j_q (below s = 32/3 each panel's
own; beyond, the panels of width L = 32/3 of one grid k L shared by every point, 16 nodes each,
whose Bessel functions are computed once per call; Gauss's error bound for e^{2is} on such a
panel is ~3e-12 of its largest value); the nodes stop at the first grid edge beyond η h = 5 and
s = 20 where ``|Δg|``/s (what the rest can add) falls below 1e-3 rtol of the film's ``|g|``:
``|Δg|`` is probed at the panel edges, and between the last edge above that level and the first
below it the crossing is placed where ln(``|Δg|``/s), taken linear in s between the two (exact
for the e^{−2ηh} decay under layers but for the slow 1/s), reaches it. The correction integrals
of all the points are formed together (one batched product on the points' own nodes, one real
product of every point's weights with the pairs' products j_p j_q on the shared grid). A lossy
stack is passed on the same path (its singularities lie below the real axis). In statics (f = 0)
the real axis from 0 is used. The layer solutions behind Δg depend on (η, ω) only through the
slowness η/ω: on the real axis they come from one table in the slowness per stack (interpolated
to round-off) and on the arc from one set of solutions, for every frequency
(``contactres.dynamic._layered_waves``); the nodes of all frequencies are solved together. On
the shared arc the stack's correction depends on the point only through T = p₁ω (the layers'
η h_j = T h_j z(τ)), so it is solved at 13 or 25 Chebyshev-Lobatto points in T and
interpolated to the curve's points when the last Chebyshev coefficients are below 1e-12 of
its largest value, else solved at every point (``contactres.dynamic._layered_arc``); and H_33
of an axisymmetric stack of isotropic layers comes from the recursion on the sagittal 2x2
block, where SH motion decouples (``contactres.dynamic._layered_sagittal``).
Caveat: a lossless stack with a backward-wave guided mode
(group and phase velocity opposite, possible for a stiff film on a soft substrate) would have
that pole's limiting-absorption side reversed; the passivity tests cover both stiff-on-soft and
soft-on-stiff stacks, but no backward-wave case was constructed.

A frequency-dependent material is evaluated at each frequency (a new film table at each one
if the film depends on frequency). The substrate and lower layers may have any constants.

Size of the pressure basis: the default of the exact model at the largest k_s a of any material
of the stack, grown until four more radial terms move N by less than rtol/10 (a thin film on a
much stiffer or softer substrate concentrates the pressure near the edge and needs more). A
grown basis reuses the integrals of the order pairs it had (the film's and the correction's:
an integral over a pair does not depend on the basis it belongs to), so each pair is
integrated once; the Bessel functions of the nodes (the correction's and the film's near and
far nodes) are computed for the orders of a basis grown further, not once per size: at first
two growths ahead if the layers are thinner than a/10 (where the basis usually grows twice),
else for the first basis; once it has grown, one growth ahead. Where the layers are thinner
than a/10 the matrix itself is formed at first for the basis two growths ahead, and the
checks of the three sizes solve its sub-blocks (the smaller bases' matrices, entry for entry).

Accuracy (tests/dynamic/test_layered_punch.py, measured): homogeneous isotropic against the
Fredholm disk 1e-8-2.6e-8 (k_s a = 0.3-2); a lossy stack (Q⁻¹ = 1e-3, PMMA h = 0.2a on quartz)
against an adaptive real-axis quadrature 4.4e-9, the viscoelastic PMMA film (unequal losses)
9.9e-9; doubling every node of the correction moves K by < 1e-10, rtol = 1e-9 (larger basis and
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
from dataclasses import replace

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..halfspace import shear_reference
from ..layered import LayeredMaterial
from ..materials import Material
from ..validation import nonnegative, positive
from ._exact import (
    GalerkinSize,
    galerkin_integrals,
    galerkin_plan,
    galerkin_size,
    kernel_harmonics,
    near_bessel,
)
from ._farfield import far_basis, far_grid
from ._fartail import far_tail, head_grid
from ._layered_nodes import (
    PunchResolution,
    grid_bessel,
    own_bessel,
    own_rows,
    punch_resolution,
    split_at,
    unit_rule,
)
from ._layered_path import correction_nodes, film_reference, stack_at, stack_of
from ._layered_tangential import tangential_punch
from ._normal_stiffness import normalised_wavenumber
from ._table import KernelTable, prepare
from ._tangential_table import prepare_tangential
from ._weights import spherical_bessel

__all__ = [
    "PunchResolution",
    "flat_punch_stiffness",
    "layered_dcsf",
    "layered_punch_stiffness",
    "punch_resolution",
]

# Largest number of radial terms per harmonic the adaptive basis may reach.
_MAX_RADIAL = 48


def _correction_integrals(bessel, values, orders, pairs, known=None) -> np.ndarray:
    """∫ Δg_m j_p j_q ds (n_pts, n_m, n_t) of every point with a correction, with the tail
    beyond each one's last node S: Δg ~ Δg(S) S²/s² (its 1/s² decay) and j_p j_q ->
    (−1)^{(p−q)/2}/(2s²) on average, so the tail is Δg_m(S) (−1)^{(p−q)/2}/(6S).

    ``bessel``: :func:`_nodes_bessel` (j_p on the points' own nodes and on the shared grid);
    ``values``: :func:`_point_values` (the weights times Δg_m on the same nodes, the tails);
    ``orders``: the plan's orders; ``pairs``: :func:`_new_pairs` of the plan; ``known``: what
    this call returned for the previous (smaller) basis, whose pairs' integrals are reused."""
    new, at, a, cols, pos, sign = pairs
    own_j, grid_jt = bessel
    own_v, grid_v, end, s_end = values
    n_pts, n_m = own_v.shape[:2]
    out = np.empty((n_pts, n_m, new.size), dtype=complex)
    if known is not None:
        out[..., ~new] = known[..., at]
    # The points' own nodes (the arc and the panels below s = 32/3): J diag(w Δg_m) J[cols]ᵀ, one
    # product per point batched over its harmonics, then the new pairs read from it (point by
    # point: no (points × harmonics × orders × nodes) temporary, fresh pages on every call).
    fresh = np.empty((n_pts, n_m, a.size), dtype=complex)
    at_rows = _order_rows(orders)
    # Each point's rows gathered from the parts of its complex and real nodes (a copy, where
    # a slice of one (orders x all own nodes) array was a view: that array was ~1/3 of the
    # peak of memory, faulted in afresh on every call).
    parts, runs = own_j
    for k, point_runs in enumerate(runs):
        rows = own_rows(parts, point_runs, at_rows)
        gram = (rows * own_v[k, :, None, : rows.shape[-1]]) @ rows[cols].T
        fresh[k] = gram[:, a, pos]
    # The shared grid's nodes, real J: Σ_n (w Δg_m)_n j_p j_q as one real product of every
    # point's and harmonic's values (real and imaginary parts) with the new pairs' products.
    products = grid_jt[:, orders[a]] * grid_jt[:, orders[cols[pos]]]
    both = (grid_v @ products).reshape(2, n_pts, n_m, -1)
    fresh += both[0] + 1j * both[1]
    fresh += end[:, :, None] * sign / (6 * s_end[:, None, None])
    out[..., new] = fresh
    return out


def _nodes_bessel(p_max: int, nodes: dict, res, rule) -> tuple:
    """(j_p, p = 0..``p_max``, on the points' own nodes (:func:`own_bessel`: the parts of the
    complex and the real nodes, each point's runs); j_p on the shared grid, transposed
    (n_grid, p_max + 1), real). ``rule``: :func:`unit_rule` of ``res.n_panel``."""
    grid = grid_bessel(p_max, nodes, res, rule)
    return own_bessel(p_max, nodes), np.ascontiguousarray(grid.T)


def _point_values(nodes: dict, harmonics: list, n_grid: int) -> tuple:
    """(w Δg_m on every point's own nodes (n_pts, n_m, most own nodes), complex; on the shared
    grid, real and imaginary parts stacked (2 n_pts n_m, n_grid); Δg_m(S) (n_pts, n_m); S
    (n_pts,)), zero beyond each point's nodes, from each point's harmonics (of the static
    shift, of Δg (n_m, len(s)), of Δg(S)), the points in the order of ``nodes``."""
    n_m = harmonics[0][1].shape[0]
    n_own = max(v.n_own for v in nodes.values())
    own = np.zeros((len(nodes), n_m, n_own), dtype=complex)
    grid = np.zeros((len(nodes), n_m, n_grid), dtype=complex)
    for k, (v, (_, harm, _)) in enumerate(zip(nodes.values(), harmonics, strict=True)):
        wg = v.weights[None, :] * harm
        own[k, :, : v.n_own] = wg[:, : v.n_own]
        grid[k, :, v.grid_from : v.grid_from + v.s.size - v.n_own] = wg[:, v.n_own :]
    flat = grid.reshape(-1, n_grid)
    end = np.array([h[2] for h in harmonics])
    s_end = np.array([v.s_end for v in nodes.values()])
    return own, np.concatenate([flat.real, flat.imag]), end, s_end


def _new_pairs(plan, previous):
    """Which order pairs of ``plan`` the basis ``previous`` (its plan, or None) lacked, and how
    to form them: (new (n_t,) bool, index in ``previous``'s pairs of the others, then for the
    new ones the row order index, the columns to form (indices into the plan's orders), each
    one's column among them, and the tail's sign (−1)^{(p−q)/2}). A pair's integral does not
    depend on the basis it belongs to; the Gram matrix is symmetric in p and q, so a new pair
    is read from the column of one of its new orders."""
    orders, (ti, tj) = plan.orders, plan.pairs
    keys = orders[ti] * _PAIR_KEY + orders[tj]
    new = np.ones(keys.size, dtype=bool)
    at = np.zeros(0, dtype=int)
    fresh = np.ones(orders.size, dtype=bool)
    if previous is not None and np.array_equal(previous.ms, plan.ms):
        po, (pi, pj) = previous.orders, previous.pairs
        old_keys = po[pi] * _PAIR_KEY + po[pj]
        by_key = np.argsort(old_keys)
        where = by_key[np.minimum(np.searchsorted(old_keys[by_key], keys), old_keys.size - 1)]
        new = old_keys[where] != keys
        at = where[~new]
        fresh = ~np.isin(orders, po)
    a, b = ti[new], tj[new]
    col = np.where(fresh[b], b, a)
    cols = np.unique(col)
    sign = np.where(((orders[a] - orders[b]) // 2) % 2 == 0, 1.0, -1.0)
    return new, at, a + b - col, cols, np.searchsorted(cols, col), sign


# Keys of order pairs (p, q): p × _PAIR_KEY + q (orders stay far below it).
_PAIR_KEY = 4096


def _order_rows(orders: np.ndarray):
    """Index of the rows p = ``orders`` of an array of rows p = 0, 1, ...: a slice (a view, no
    copy) where the orders are evenly spaced, as they are (0, 2, 4, ... on an axisymmetric
    stack; 0, 1, 2, ... otherwise), else the orders themselves."""
    step = int(orders[1] - orders[0]) if orders.size > 1 else 1
    if step > 0 and np.array_equal(orders, orders[0] + step * np.arange(orders.size)):
        return slice(int(orders[0]), int(orders[-1]) + 1, step)
    return orders


def _harmonics_of(values, plan, axisymmetric: bool) -> np.ndarray:
    """Ĝ_m = ∫₀^{2π} Δg e^{imθ} dθ (n_m, len(values)) of rows sampled on the table's θ nodes,
    or at one θ for an axisymmetric stack (then only m = 0)."""
    if axisymmetric:
        return np.where(plan.ms == 0, 2 * np.pi, 0.0)[:, None] * values[:, 0][None, :]
    return kernel_harmonics(values, plan.ms)


def _point_harmonics(nodes: dict, plan, axisymmetric: bool) -> list:
    """[(Ĝ_m of the static shift (n_m,), of Δg (n_m, len(s)), of Δg(S) (n_m,)), ...] of every
    point of ``nodes`` (:func:`_harmonics_of`), from one transform of all their rows (each row
    is transformed alone: the same values as point by point)."""
    points = list(nodes.values())
    sizes = np.array([v.delta_g.shape[0] for v in points])
    rows = [v.delta_g for v in points] + [np.stack([v.end for v in points])]
    h = _harmonics_of(
        np.concatenate([*rows, np.stack([v.shift for v in points])]), plan, axisymmetric
    )
    total, n = int(np.sum(sizes)), len(points)
    harm = split_at(h[:, :total], np.cumsum(sizes)[:-1], axis=1)
    return [(h[:, total + n + k], harm[k], h[:, total + k]) for k in range(n)]


def _assemble(integral, plan) -> np.ndarray:
    return plan.sign * integral[plan.m_index, plan.t_index]


def _film_matrices(
    table: KernelTable, ksa: np.ndarray, size: GalerkinSize, far, known=None, extra: int = 0
):
    """(M_film at k_s a values ``ksa`` (>= 0), (len(ksa), nb, nb); the Galerkin plan; the
    film's integrals by order pair for the next call), with ``far`` (the far-field basis of the
    positive ``ksa`` on the head of its grid, the whole grid's nodes, its tail or None; None if
    there is no positive k_s a; it does not depend on the basis size, so the growing basis of
    :func:`_punch` computes it once). ``known``: what the previous call of
    the growing basis returned last (its pairs' integrals are reused, not recomputed: a pair's
    integral does not depend on the basis it belongs to, and the harmonics stay the same; so
    are its Bessel functions at the near and far nodes where they reach the orders needed;
    None in their place where the caller let them go, :func:`_let_go_film_bessel`).
    ``extra``: where they must be computed, for ``extra`` radial terms more than ``size``
    (two orders each: the orders a grown basis may need, computed once, not once per size).
    The Bessel functions returned are None where no pair is new and none were held (nothing
    needed them)."""
    pos = ksa > 0
    # The plan without the far grid's products: those of the new pairs only are formed below.
    plan = galerkin_plan(table, size)
    nb = len(plan.basis)
    out = np.empty((ksa.size, nb, nb), dtype=complex)
    orders, (ti, tj) = plan.orders, plan.pairs
    # Static part of the exact model: Ĝ_m^∞ δ_pq π/(2(2p + 1)) (closed form).
    diag = np.where(ti == tj, np.pi / (2 * (2 * orders[ti] + 1)), 0.0)
    out[~pos] = _assemble(kernel_harmonics(table.ginf, plan.ms)[:, None] * diag[None, :], plan)
    if far is None:
        return out, plan, None
    # Each pair (p, q) by its orders, p <= q (the pairs of a smaller basis are among these).
    keys = orders[ti] * (2 * int(orders[-1]) + 2) + orders[tj]
    integral = np.empty((int(np.sum(pos)), plan.ms.size, keys.size), dtype=complex)
    new = np.ones(keys.size, dtype=bool)
    bessel = None
    if known is not None and np.array_equal(known[2], plan.ms):
        old_keys = known[0][0] * (2 * int(orders[-1]) + 2) + known[0][1]
        by_key = np.argsort(old_keys)
        at = by_key[np.minimum(np.searchsorted(old_keys[by_key], keys), old_keys.size - 1)]
        new = old_keys[at] != keys
        integral[..., ~new] = known[1][..., at[~new]]
        bessel = known[3]
    if np.any(new):
        # j_p at the far grid and the near nodes: those the previous call held where they
        # reach this basis's orders, else up to the orders a grown basis may need. (Computed
        # again they would differ in the last bits where their highest order differs: row p of
        # spherical_bessel(p_max, z) depends on p_max through the switch to the upward
        # recurrence for real z > p_max + 1 and the continued fraction's start.)
        if bessel is not None and bessel[0].shape[0] > orders[-1]:
            far_j, near_j = bessel
        else:
            p_max = int(orders[-1]) + 2 * extra
            far_j = spherical_bessel(p_max, np.asarray(far[1], dtype=float))
            near_j = None
        # Pair by pair into one array: indexing the rows by the pairs copied both factors
        # of every pair first (two (pairs x nodes) gathers, as the exact model's products).
        products = np.empty((int(np.sum(new)), far_j.shape[1]))
        for i, (p, q) in enumerate(np.stack([orders[ti[new]], orders[tj[new]]], 1).tolist()):
            np.multiply(far_j[p], far_j[q], out=products[i])
        basis, _, tail = far
        part = replace(plan, pairs=plan.pairs[:, new], far_products=products)
        if tail is not None:
            # The products on the head, their moments on the tail (as galerkin_plan's). The
            # head copied and the whole grid's products let go before the near field: held
            # through it (as a view's base), they (~2.5 MB for 250 nm PMMA on quartz, ~7x the
            # head) were on top of its Bessel functions and weighted copies, at the film's
            # peak of memory (fresh pages on every call: glibc gives the heap back at its
            # end); let go, their place is reused by those (which are therefore computed
            # after them).
            moments = tail.moments(products)
            head = products[:, : tail.split].copy()
            part = replace(part, far_products=head, far_tail=tail, far_moments=moments)
            del products
        if near_j is None:
            near_j = near_bessel(table, ksa[pos], far_j.shape[0] - 1)
        integral[..., new] = galerkin_integrals(table, ksa[pos], part, basis, near_j)
        bessel = (far_j, near_j)
    out[pos] = plan.sign * integral[:, plan.m_index, plan.t_index]
    return out, plan, (np.stack([orders[ti], orders[tj]]), integral, plan.ms, bessel)


def _far_field(table: KernelTable, ka: np.ndarray) -> tuple:
    """``far`` of :func:`_film_matrices` for the positive k_s a ``ka``: (the far-field basis on
    the head of its grid, the whole grid's nodes, its tail or None)."""
    # As the homogeneous curve: beyond 2 T₁ × the largest k_s a the far basis is summed by
    # its moments (contactres.dynamic._fartail), built on the head of the grid alone.
    grid = far_grid(table, float(np.min(ka)))
    tail = far_tail(table, grid, float(np.max(ka)))
    return far_basis(table, ka, head_grid(grid, tail)), grid.s, tail


def _let_go_film_bessel(known, p_basis: int):
    """``known`` of :func:`_film_matrices` with its Bessel functions let go (None) where they
    cannot serve a larger basis: where their highest order is at most ``p_basis``, the highest
    order of the basis they were made for (every first call, whose ``extra`` is 0, and so the
    whole 250 nm PMMA curve, which converges within the sizes its first matrix checks); held
    otherwise, for the grown basis they were computed for. A grown basis's highest order
    exceeds its predecessor's, so those let go would have been computed again in any case.

    Why: held to the end of the call, the film's ~2.3 MB (250 nm PMMA on quartz, 41 points)
    were part of the curve's peak of memory, whose heap glibc gives back to the system after
    each call, to be faulted in page by page on the next (~1500 faults per curve). Let go
    once the correction's own Bessel functions have been allocated (above them in the heap),
    they leave a hole that the correction's later arrays reuse, where let go at the end of
    the film's part they joined its freed temporaries at the top of the heap, past glibc's
    trim threshold: the heap was trimmed in mid-call and grown again (more faults)."""
    if known is None or known[3] is None or known[3][0].shape[0] - 1 > p_basis:
        return known
    return (*known[:3], None)


def _solve_c0(M: np.ndarray, n_radial: int, plan) -> np.ndarray:
    """c₀ of M c = e₀ on the sub-basis of the first ``n_radial`` radial terms per harmonic."""
    keep = np.array([k < n_radial for _, k in plan.basis])
    n_keep = int(np.sum(keep))
    # A prefix (one harmonic, as on an axisymmetric stack): a view, not two gathered copies.
    sub = M[:, :n_keep, :n_keep] if np.all(keep[:n_keep]) else M[:, keep][:, :, keep]
    e0 = np.zeros(sub.shape[-1])
    e0[0] = 1.0
    return np.linalg.solve(sub, np.broadcast_to(e0, sub.shape[:-1])[..., None])[..., 0, 0]


# One BLAS thread, as the homogeneous curve (dcsf_models): the correction's many small products
# (3x3 recursion, Gram products of ~20 functions) gain nothing from a second thread, which only
# spins (3-14x the CPU of one thread on a busy machine, benchmarks/bench_layered_dynamic.py).
@one_blas_thread()
def layered_punch_stiffness(
    material,
    radius,
    frequency=0.0,
    direction: str = "normal",
    rtol: float = 1e-6,
    *,
    resolution: PunchResolution | None = None,
    tensor: bool = False,
):
    """Normal or tangential stiffness K(ω) = F/δ of a rigid flat punch on a layered substrate,
    N/m (complex); ``tensor=True``: the 2x2 tangential tensor.

    The rigid disk of radius a, displaced uniformly (δ e^{iωt}: normal, frictionless; or along
    the surface x axis, bonded and relaxed), on a homogeneous, layered and/or viscoelastic
    substrate (module docstring for the method; for the tangential punch the module
    ``contactres.dynamic._layered_tangential``). On a
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
        "normal" (frictionless) or "tangential" (bonded and relaxed, along the surface x axis:
        K_xx; module ``contactres.dynamic._layered_tangential``, k_s a <= 5 in every material).
    rtol : float
        Target relative accuracy, in [1e-10, 1e-3] (default 1e-6).
    resolution : PunchResolution, optional
        Keyword only: the discretisation of the layered correction (default
        :func:`punch_resolution` of rtol; ``.doubled()`` for a convergence check).
    tensor : bool
        Keyword only, tangential only: return the tensor K_αβ (α, β = x, y of the surface
        frame: the force along α per unit rigid displacement along β) instead of K_xx. On a
        stack that is not unchanged by rotations about the normal (a crystal face without a
        three-, four- or sixfold axis, in any layer) K_yy ≠ K_xx and K_xy ≠ 0; K_xy = K_yx
        (reciprocity), and turning the stack about the normal turns the tensor. The basis then
        grows until the whole tensor converges (relative to its largest entry), so K_xx may
        differ from the default's by up to rtol/10.

    Returns
    -------
    complex or ndarray of complex
        K in N/m, shaped like broadcast(radius, frequency) (+ (2, 2) with ``tensor``);
        Im K >= 0 (Im K_xx, Im K_yy with ``tensor``).

    Examples
    --------
    The static punch on a homogeneous solid is 2 a E/(1 − ν²):

    >>> from contactres import Material
    >>> k = layered_punch_stiffness(Material.isotropic(70e9, 0.25), 1e-6)
    >>> bool(abs(k / (2e-6 * 70e9 / (1 - 0.25**2)) - 1) < 1e-9)
    True
    """
    if direction not in ("normal", "tangential"):
        raise ContactresInputError(f"direction must be 'normal' or 'tangential', got {direction!r}")
    inplane = direction == "tangential"
    if tensor and not inplane:
        raise ContactresInputError(
            "tensor=True is the 2x2 tangential stiffness: give direction='tangential'"
        )
    r = float(rtol)
    if not (math.isfinite(r) and 1e-10 <= r <= 1e-3):
        raise ContactresInputError(f"rtol must lie in [1e-10, 1e-3], got {rtol!r}")
    a = np.asarray(positive("radius", radius, "m"), dtype=float)
    f = np.asarray(nonnegative("frequency", frequency, "Hz"), dtype=float)
    a, f = np.broadcast_arrays(a, f)
    res = resolution or punch_resolution(r)
    out = np.empty(a.shape + ((2, 2) if tensor else ()), dtype=complex)
    flat_a, flat_f = a.ravel(), f.ravel()
    flat_out = out.reshape(-1, 2, 2) if tensor else out.reshape(-1)
    # Points grouped by film table (one for a film that does not depend on frequency): the film
    # matrices of a group come from one call, the correction is per point.
    groups: dict = {}
    known: dict = {}  # each material's slowness and symmetry, found once over the frequencies
    fixed = _fixed_stack(material)
    for freq in np.unique(flat_f):
        sel = np.flatnonzero(flat_f == freq)
        (mats, hs), (film, q) = fixed or _stack_and_film(material, float(freq))
        key = (np.asarray(film.C).tobytes(), q)
        if key not in groups:
            groups[key] = ((film, q), [])
        stack = stack_at(mats, hs, film, q, float(freq), inplane, known)
        groups[key][1].extend((i, stack, float(freq)) for i in sel)
    for (film, q), items in groups.values():
        index = np.array([i for i, _, _ in items])
        if inplane:
            table = prepare_tangential(film, q, r)
            k = tangential_punch(table, film, items, flat_a[index], r, res, tensor)
            flat_out[index] = k if tensor else k[:, 0, 0]
        else:
            flat_out[index] = _punch(prepare(film, q, r), film, items, flat_a[index], r, res)
    return complex(out) if out.ndim == 0 else out


def _stack_and_film(material, frequency: float):
    """((materials, thicknesses) of the stack at ``frequency``, (film reference, Q⁻¹))."""
    mats, hs = stack_of(material, frequency)
    return (mats, hs), film_reference(mats[0])


def _fixed_stack(material):
    """:func:`_stack_and_film` of a material or stack none of whose materials depends on the
    frequency (the same at every frequency: formed once), else None."""
    members = material.materials if isinstance(material, LayeredMaterial) else (material,)
    if all(isinstance(m, Material) for m in members):
        return _stack_and_film(material, 0.0)
    return None


def _storage(material):
    """The stack (or material) at f = 0 with the real parts of every material's constants:
    the undamped static solid that normalises the DCSF."""
    mats, hs = stack_of(material, 0.0)
    real = [Material(C=np.asarray(m.C).real, density=m.density, name=m.name) for m in mats]
    return LayeredMaterial(real[-1], list(zip(real[:-1], hs, strict=True)))


def flat_punch_stiffness(
    material,
    radius,
    frequency=0.0,
    direction: str = "normal",
    *,
    rtol: float = 1e-6,
    tensor: bool = False,
):
    """Stiffness of a rigid flat circular punch, static or time-harmonic, N/m (complex);
    ``tensor=True``: the 2x2 tangential stiffness tensor.

    The rigid disk of radius a on a homogeneous, layered and/or viscoelastic half-space:
    ``direction="normal"`` frictionless (K = F/δ), ``"tangential"`` bonded (no slip) and
    relaxed (no normal traction), along the surface x axis. e^{iωt}; a lossless material
    gives the limit Q⁻¹ -> 0⁺ (radiation only, Im K >= 0).

    At frequency 0 this is :func:`contactres.normal.static_punch_stiffness` (the axisymmetric
    Galerkin of the static layered solid, < 1e-9); above 0, for ``"normal"``,
    :func:`layered_punch_stiffness`, normal or tangential (the film's exact dynamic Galerkin
    plus the stack's correction on a lifted contour; on a layered or viscoelastic substrate
    K/K_static depends on the frequency and the radius separately, not on k a alone).

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
    tensor : bool
        Keyword only, with ``direction="tangential"``: the tensor K_αβ (α, β = x, y of the
        surface frame; the force along α per unit rigid displacement along β), at every
        frequency (0 included) from :func:`layered_punch_stiffness` (``tensor=True``): the
        exact Galerkin with the kernel's full dependence on the direction, where the static
        punch of ``tensor=False`` averages the compliance over directions (exact for
        axisymmetric stacks, an approximation for the others). K_xy = K_yx; on a stack
        unchanged by rotations about the normal K_yy = K_xx and K_xy = 0 (so a crystal face
        with a three-, four- or sixfold axis also has an isotropic tensor); turning the stack
        about the normal by ψ turns it: K' = Q K Qᵀ, Q = [[cos ψ, sin ψ], [−sin ψ, cos ψ]].

    Returns
    -------
    complex or ndarray of complex
        K, N/m (+ (2, 2) with ``tensor``). Homogeneous isotropic statics: 2aE* (Sneddon,
        normal), 8Ga/(2 − ν) (Mindlin, tangential).

    Examples
    --------
    Sneddon's 2aE/(1 − ν²) in statics:

    >>> from contactres import Material, flat_punch_stiffness
    >>> k = flat_punch_stiffness(Material.isotropic(70e9, 0.25), 1e-6)
    >>> bool(abs(k / (2e-6 * 70e9 / (1 - 0.25**2)) - 1) < 1e-9)
    True

    The tangential tensor of a Cu(110) face is not isotropic (its x axis along [001]):

    >>> cu = Material.crystal("Cu").rotated((1, 1, 0), (0, 0, 1))
    >>> k = flat_punch_stiffness(cu, 1e-6, direction="tangential", tensor=True)
    >>> bool(abs(k[0, 1]) < 1e-9 * abs(k[0, 0]) and abs(k[1, 1] / k[0, 0] - 1) > 0.05)
    True
    """
    from ..normal import static_punch_stiffness

    if tensor:
        return layered_punch_stiffness(material, radius, frequency, direction, rtol, tensor=True)
    f = np.asarray(nonnegative("frequency", frequency, "Hz"), dtype=float)
    if not np.any(f > 0):
        a = np.asarray(positive("radius", radius, "m"), dtype=float)
        shape = np.broadcast_shapes(a.shape, f.shape)
        k = static_punch_stiffness(material, np.broadcast_to(a, shape), direction)
        return complex(k) if np.ndim(k) == 0 else k
    return layered_punch_stiffness(material, radius, frequency, direction, rtol)


def layered_dcsf(
    material,
    radius,
    frequency,
    rtol: float = 1e-6,
    *,
    resolution: PunchResolution | None = None,
    direction: str = "normal",
):
    """Paper 1's dynamic-contact-stiffness factor (exact model) on a layered or viscoelastic
    substrate: K(f)/K_st of the rigid flat punch, complex (``direction="tangential"``: the
    tangential factor K_t(f)/K_t,st of the bonded, relaxed punch along x).

    K(f) is :func:`layered_punch_stiffness`; K_st the static (f = 0) stiffness of the same
    punch on the undamped stack: every material at f = 0 (its relaxed limit) with the real part
    of its constants, as paper 1's K_sa is the static stiffness of the undamped constants (so a
    homogeneous solid with constant loss Q⁻¹ gives DCSF(0) = 1 + iQ⁻¹, as
    :func:`contactres.dcsf`). On a layered or viscoelastic substrate the DCSF is a function of
    the frequency and the radius separately, not of k a alone: the film thickness and the
    frequency dependence of the moduli set their own scales.

    Parameters
    ----------
    material, radius, frequency, rtol, resolution, direction
        As in :func:`layered_punch_stiffness`; the materials need a static limit (a
        springpot, a power law without one, is refused at f = 0).

    Returns
    -------
    complex or ndarray of complex
        K/K_st, shaped like broadcast(radius, frequency).
    """
    k = layered_punch_stiffness(material, radius, frequency, direction, rtol, resolution=resolution)
    k_st = layered_punch_stiffness(_storage(material), radius, 0.0, direction, rtol)
    out = np.asarray(k) / np.asarray(k_st).real
    return complex(out) if out.ndim == 0 else out


def _punch(table, film, items, radii, rtol, res) -> np.ndarray:
    """K (N/m) at the points ``items`` [(index, Stack, frequency), ...] of one film table
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
    # One Gauss-Legendre rule for every use of it (roots_legendre costs ~0.2 ms a call).
    rule = unit_rule(res.n_panel)
    nodes = correction_nodes(stacks, radii, theta, res, gref, rule)
    pos = ksa > 0
    far = _far_field(table, ksa[pos]) if np.any(pos) else None
    known = None
    index = np.array(list(nodes), dtype=int)
    # The correction integrals of every point by order pair, reused by the grown basis; the
    # harmonics of Δg (the same for every size: the harmonics m do not change).
    reuse = None
    harmonics: list = []
    values = None
    previous = None
    bessel = None  # j_p at the nodes, p = 0..p_have (_nodes_bessel)
    p_have = -1
    thin = any(np.sum(stacks[i].thicknesses) < 0.1 * radii[i] for i in nodes)
    while True:
        # The Bessel functions of the nodes and of the film's integrals are computed for the
        # orders of a basis grown further (p = |n| + 2k: two more per radial term), not once
        # per size: two growths ahead at first where a layer thinner than a/10 is likely to
        # grow the basis twice (250 nm PMMA on quartz at a = 5 µm: 10 -> 13 -> 18 terms), one
        # once it has grown; a thicker stack, which rarely grows, pays for no extra order.
        # At first, where it is likely to grow twice, the matrix itself is formed for the
        # basis two growths ahead: the matrices of the smaller bases are its sub-blocks (an
        # entry depends on its pair of orders and harmonic alone), so each size's check reads
        # its sub-block and the per-call work of the film's and the correction's integrals
        # is done once instead of three times.
        # (Only the cost depends on this guess: the results do not, but for round-off.)
        growths = 0
        if nodes:
            growths = 1 if previous is not None else 2 if thin else 0
        ahead = n_radial
        checks = [n_radial]
        for _ in range(growths):
            ahead = min(_MAX_RADIAL - 4, math.ceil(1.5 * ahead))
            checks.append(ahead)
        if previous is not None or not thin:
            checks = checks[:1]
        grow = checks[-1] + 4 if nodes else n_radial
        size = GalerkinSize(grow, 0 if axisymmetric else n_harm)
        M, plan, known = _film_matrices(table, ksa, size, far, known, ahead - checks[-1])
        orders, (ti, tj) = plan.orders, plan.pairs
        diag = np.where(ti == tj, np.pi / (2 * (2 * orders[ti] + 1)), 0.0)
        if nodes:
            if p_have < orders[-1]:
                p_have = int(orders[-1]) + 2 * (ahead - checks[-1])
                bessel = _nodes_bessel(p_have, nodes, res, rule)
            known = _let_go_film_bessel(known, int(orders[-1]))
            assert bessel is not None  # computed at the first size
            reused = previous is not None and np.array_equal(previous.ms, plan.ms)
            if not reused:
                harmonics = _point_harmonics(nodes, plan, axisymmetric)
                values = _point_values(nodes, harmonics, bessel[1].shape[0])
            pairs = _new_pairs(plan, previous)
            reuse = _correction_integrals(bessel, values, orders, pairs, reuse if reused else None)
            # The static difference of film and reference: closed form, as in the exact model.
            shift = np.array([h[0] for h in harmonics])
            total = reuse + shift[:, :, None] * diag
            M[index] += plan.sign * total[:, plan.m_index, plan.t_index]
        if not nodes:
            c_big = _solve_c0(M, grow, plan)
            break
        done = False
        for n_radial in checks:
            # The check of the basis of n_radial + 4 terms against n_radial (a sub-block).
            c_big = _solve_c0(M, n_radial + 4, plan)
            c_small = _solve_c0(M, n_radial, plan)
            done = np.max(np.abs(c_big / c_small - 1)) < rtol / 10 or n_radial + 4 >= _MAX_RADIAL
            if done:
                break
        if done:
            break
        n_radial = min(_MAX_RADIAL - 4, math.ceil(1.5 * n_radial))
        previous = plan
    return 4 * np.pi**2 * radii * c44 * c_big
