"""Time-harmonic tangential stiffness of a rigid flat punch on a layered or viscoelastic substrate.

The rigid disk of radius a, bonded to the surface and relaxed (no normal traction under it, the
normal displacement free), translated along the surface x axis by U e^{iωt}, on bonded layers
over a half-space (:class:`contactres.layered.LayeredMaterial`), every material evaluated at the
frequency. The tangential Galerkin of the module ``contactres.dynamic._tangential_galerkin``
(traction harmonics e^{inφ}, ``|n|`` <= N_h, of each in-plane component, Jacobi radial functions
whose transforms H_a(s) are series of j_p(s), s = η a) applies unchanged to any in-plane surface
kernel. With the top film's shear reference C44_f (real part) and the dimensionless in-plane
kernel of the stack

    h_αβ(η, θ) = −H_αβ(η, θ)     (α, β = x, y; H: :func:`contactres.layered.stack_compliance`
                                  in C44_f units; = −C44_f η Ĝ_αβ, Ĝ of ``surface_green``),

the Galerkin matrix is split as for the normal punch (``contactres.dynamic._layered_punch``;
the path, nodes and tail of the module ``contactres.dynamic._layered_path`` are shared):

    M = M_film + ΔM,   ΔM_ab = i^{|n_a|−|n_b|} ∫₀^∞ ds Δh_{α_a β_b, n_b − n_a}(s/a) H_a(s) H_b(s),
    Δh_{αβ, m}(η) = ∫₀^{2π} (h_stack − h_film)_αβ(η, θ) e^{imθ} dθ,

M_film the matrix of the film as a homogeneous half-space at its k_s a (the tangential kernel
table, contour and far field). Δh decays like e^{−2ηh} (h the total thickness), so the integral
has a finite end; it runs on the lifted arc above the guided-mode poles and branch points (the
limit loss -> 0⁺) and on the real axis beyond (Chebyshev samples of Δh per geometric panel),
exactly as the normal correction. A film whose channels have unequal loss tangents gets the
table of a reference (Re C with the shear loss); the difference film − reference joins Δh, its
static part in closed form (the static Galerkin form R(p_a, λ_a; p_b, λ_b) of the harmonics of
h∞_film − h∞_ref) and the rest with its 1/s² tail Δh(S) ⟨H_a H_b⟩ s²/(6S) beyond the last node S.

Angular harmonics. On a stack of materials unchanged by rotations about the normal (isotropic,
transversely isotropic about z) h(θ) = R(θ) h(0) R(θ)ᵀ holds only the harmonics m = 0, ±2, taken
from h(0) (one direction per node); otherwise Δh is sampled on 128 directions in [0, 2π) and
transformed by FFT (harmonics up to 2 N_h).

Basis. On an axisymmetric stack the kernel couples t_± = t_x ± i t_y of harmonic n only to
harmonics n and n ± 2 of the other, so the sectors of one total angular number decouple; the
x-translation lives in two of them (t_+ of harmonics 0 and −2, t_− of 0 and 2), and the traction
harmonics are kept to n = 0, ±2 (the others, n = ±1 among them, decouple exactly; the solution
is t = A(r) e_x + B(r) (cos 2φ, sin 2φ)). Every radial function is then one j_p, so the Gram
products of the correction run on the distinct orders p, and a grown basis reuses those of the
orders it had. Its film's static in-plane kernel has no odd imaginary part:
the edge singularity is the square root of the polynomial basis, and the logarithmic enrichment
of the homogeneous module (needed for the oscillatory singularity of faces that are not mirror
planes) is left out. On a stack that is not axisymmetric all the harmonics are kept; the
enrichment is left out too when the top film is unchanged by rotations about the normal (an
isotropic film on an anisotropic substrate, e.g. PMMA on quartz-AT): the edge singularity is
the top film's own (the field at distances from the edge small against h sees the film as a
half-space), the square root of the polynomial basis (measured: PMMA at a/h = 5 and 10 on
quartz-AT, f = 0 and 15 MHz, the same K with and without the enrichment to 8e-12). Otherwise
(an anisotropic top film) it is kept, its transforms as Neumann series of j_p with enough
terms to reach the last node (2Q >= 1.5 S + 16, at most _MAX_SERIES terms: a film so thin that
the correction reaches beyond η a ≈ 150 is refused: the correction's end scales like 13 a/h,
so anisotropic top films thinner than about a tenth of a are (measured on PMMA over quartz-AT
and Cu(111))). The radial terms start at the homogeneous default of the
largest k_s a of the stack and grow until four more move K by less than rtol/10 (a thin film
concentrates the traction at the edge), up to _MAX_RADIAL per harmonic.

Accuracy (tests/dynamic/test_layered_tangential.py, measured at the default rtol = 1e-6): a
film of the substrate's own material gives the homogeneous exact punch
(:func:`contactres.tangential_contact_stiffness`) to 1e-11 (k_s a = 0.3-2); f = 0 gives the
static layered tangential punch (``contactres.normal.static_punch_stiffness``) to 1.5e-12, and
as f -> 0 Im K grows linearly and Re K − K₀ quadratically; a lossy stack (Q⁻¹ = 1e-3, PMMA
h = 0.2a on quartz, k_s a = 1.5 in the film) agrees with a Galerkin of the x-translation
integrated on the real axis by adaptive quadrature to 2.0e-9 (that reference reproduces the
homogeneous exact punch to 1.1e-9), the viscoelastic built-in PMMA film (unequal losses,
h = 0.05a, 15 MHz) to 8.9e-10; doubling every node of the correction moves K by < 5e-10 and
rtol = 1e-9 by < 5e-10 (h = 0.05a and 0.2a); a cubic (111) film with A = 1 + 1e-7 (the
non-axisymmetric path, with the enriched basis) equals the isotropic film to < 1e-6. The 2x2 tensor
(tests/dynamic/test_punch_tensor.py): on Cu(111) (threefold) isotropic to 5e-16; K_yy equals
K_xx of the stack turned by 90° to 4e-13 (Cu(110), bare and as a 0.3 a film on quartz);
turning the stack about the normal turns the tensor (Q K Qᵀ) to 3e-15; K_xy = K_yx.

Result: K = 4π² a C44_f Bᵀ M⁻¹ B, the 2x2 tensor K_αβ (the force along α per unit
displacement along β; B the loads of the x and y translations), complex N/m, e^{iωt}; Im K_xx,
Im K_yy >= 0; K_xy = K_yx (M is symmetric: reciprocity). On an axisymmetric stack K_yy = K_xx
and K_xy = 0 (the y translation is the x one turned by 90°, in the same harmonics |n| <= 2); on
any other the basis of every harmonic is kept, so the y translation is as resolved as the x one.
Static limit on a homogeneous isotropic solid: 8Ga/(2 − ν) (Mindlin).

References: R. D. Mindlin, J. Appl. Mech. 16, 259-268 (1949) (static); J. Tian, paper 1 (the
kernel table and contour); J. E. Luco and R. A. Westmann, J. Appl. Mech. 39, 527-534 (1972) (the
homogeneous isotropic horizontal footing, welded; not reproduced here, whose contact is relaxed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ContactresInputError
from ._farfield import far_grid
from ._layered_nodes import PunchResolution, bessel_on_nodes, weighted_gram
from ._layered_path import correction_nodes, is_axisymmetric
from ._normal_stiffness import normalised_wavenumber
from ._tangential_galerkin import (
    KSA_MAX,
    KSA_SMALL,
    TangentialTable,
    basis_of,
    eigen_frame,
    film_dynamic,
    frame_solve,
    phase_of,
    tangential_size,
)
from ._tangential_table import angular_harmonics

__all__ = ["tangential_punch"]

# Largest number of radial terms per harmonic the adaptive basis may reach.
_MAX_RADIAL = 32
# Largest number of Neumann-series terms of the enriched transforms (their coefficients need
# Γ of arguments up to this; beyond ~150 they over- and underflow).
_MAX_SERIES = 120
# Directions sampled for the harmonics of a stack that is not axisymmetric.
_N_THETA = 128


def _rotation_harmonics(values: np.ndarray, max_order: int) -> np.ndarray:
    """The harmonics (n, 2 max_order + 1, 2, 2) of h(θ) = R(θ) h(0) R(θ)ᵀ (an axisymmetric
    stack) from h(0) = [[a, b], [e, d]] = ``values[:, 0]``, in closed form: with
    R = [[cos θ, −sin θ], [sin θ, cos θ]],

        h_xx, h_yy = (a + d)/2 ± ((a − d)/2 cos 2θ − (b + e)/2 sin 2θ),
        h_xy, h_yx = ±(b − e)/2 + (b + e)/2 cos 2θ + (a − d)/2 sin 2θ,

    and ∫₀^{2π} e^{imθ} dθ = 2π δ_m0, ∫ cos 2θ e^{imθ} dθ = π, ∫ sin 2θ e^{imθ} dθ = ±iπ at
    m = ±2: only m = 0, ±2 (what sampling 8 rotated directions and their FFT gave, to
    round-off)."""
    h0 = values[:, 0]
    a, b, e, d = h0[:, 0, 0], h0[:, 0, 1], h0[:, 1, 0], h0[:, 1, 1]
    harm = np.zeros((h0.shape[0], 2 * max_order + 1, 2, 2), dtype=complex)
    mid = max_order
    harm[:, mid, 0, 0] = harm[:, mid, 1, 1] = np.pi * (a + d)
    harm[:, mid, 0, 1] = np.pi * (b - e)
    harm[:, mid, 1, 0] = np.pi * (e - b)
    if max_order >= 2:
        diff, mixed = 0.5 * np.pi * (a - d), 0.5 * np.pi * (b + e)
        for sign in (1, -1):
            m = mid + 2 * sign
            harm[:, m, 0, 0] = diff - sign * 1j * mixed
            harm[:, m, 1, 1] = -harm[:, m, 0, 0]
            harm[:, m, 0, 1] = harm[:, m, 1, 0] = mixed + sign * 1j * diff
    return harm


def _kernel_harmonics(values: np.ndarray, max_order: int, axisymmetric: bool) -> np.ndarray:
    """Δh_{αβ, m} (n, 2 max_order + 1, 2, 2) of samples ``values`` (n, nθ, 2, 2): on the
    _N_THETA directions, or at θ = 0 only for an axisymmetric stack (then m = 0, ±2:
    :func:`_rotation_harmonics`)."""
    if not axisymmetric:
        return angular_harmonics(values, max_order)
    return _rotation_harmonics(values, max_order)


def _point_harmonics(nodes, big_m: int, axisymmetric: bool):
    """The harmonics of Δh at one point's nodes, at its end and of the static shift
    (:func:`_kernel_harmonics` up to ``big_m``)."""
    harm = _kernel_harmonics(nodes.delta_g, big_m, axisymmetric)
    end_h = _kernel_harmonics(nodes.end[None], big_m, axisymmetric)
    shift_h = _kernel_harmonics(nodes.shift[None], big_m, axisymmetric)[0]
    return harm.reshape(nodes.weights.size, -1, 4), end_h.reshape(-1, 4), shift_h


@dataclass(frozen=True, eq=False)
class _Plan:
    """What the correction of every point needs of one basis (:func:`_plan`).

    Attributes
    ----------
    orders : the orders p of the rows of the Gram products (None: the rows are the radial
        functions' transforms ``series @ J``, enriched ones among them)
    series : (n_rows, p_max + 1) each row's transform as coefficients on the j_p
    row_a, row_b : (nb, nb) the rows of the pair (a, b)'s radial functions
    entry_m, entry_c : (nb, nb) the kernel harmonic (offset by max_order) and the component
        (2 α_a + β_b) of every entry
    phase : (nb, nb) i^{|n_a| − |n_b|}
    m_values : the distinct kernel harmonics (offset by max_order) that the entries use
    gathers : the index arrays that scatter the products of a set of live harmonics onto the
        entries, made on first use for that set and kept here (with the plan, which lives as
        long as its basis: not a module-level cache)
    """

    orders: np.ndarray | None
    series: np.ndarray
    row_a: np.ndarray
    row_b: np.ndarray
    entry_m: np.ndarray
    entry_c: np.ndarray
    phase: np.ndarray
    m_values: np.ndarray
    gathers: dict

    def gather(self, ms: list) -> tuple:
        """(entries, index into the (harmonic, component, row, row) integrals) of the entries
        whose harmonic is among ``ms``; formed once per set of harmonics (every point of an
        axisymmetric stack has the same)."""
        key = tuple(int(m) for m in ms)
        if key not in self.gathers:
            which = np.full(int(self.m_values.max()) + 1, -1)
            which[list(key)] = np.arange(len(key))
            k = which[self.entry_m]
            at = np.flatnonzero(k >= 0)
            a, b = np.divmod(at, self.entry_m.shape[1])
            index = (k[a, b], self.entry_c[a, b], self.row_a[a, b], self.row_b[a, b])
            self.gathers[key] = ((a, b), index)
        return self.gathers[key]

    def rows(self, J: np.ndarray) -> np.ndarray:
        """The rows of the Gram products from J = j_p(s), p = 0..p_max, column by column."""
        return self.series @ J if self.orders is None else J[self.orders]


def _plan(basis) -> _Plan:
    """The :class:`_Plan` of ``basis``. A basis without enriched functions (every radial
    function one j_p: an axisymmetric stack's) has its Gram products formed on its distinct
    orders (n_rad + 1 of them for the harmonics 0 and ±2 instead of 2 n_rad functions, which
    share all but two orders: the products cost a quarter)."""
    if np.all(basis.rad_d == 0):
        orders, row = np.unique(basis.rad_p, return_inverse=True)
        series = np.eye(basis.p_max + 1)[orders]
    else:
        orders, row, series = None, np.arange(basis.series.shape[0]), basis.series
    r = row[basis.radial]
    row_a, row_b = np.broadcast_arrays(r[:, None], r[None, :])
    return _Plan(
        orders=orders,
        series=series,
        row_a=row_a,
        row_b=row_b,
        entry_m=basis.max_order + basis.n[None, :] - basis.n[:, None],
        entry_c=2 * basis.alpha[:, None] + basis.alpha[None, :],
        phase=phase_of(basis.n),
        m_values=np.unique(basis.max_order + basis.n[None, :] - basis.n[:, None]),
        gathers={},
    )


def _correction(
    basis, plan: _Plan, nodes, jp, harmonics, known=None
) -> tuple[np.ndarray, tuple | None]:
    """(ΔM (nb, nb), phases included; the Gram integrals for the next call) from one point's
    nodes (``_layered_nodes.CorrectionNodes``: s, ds, Δh, the end S with Δh(S), and the static
    shift h∞_film − h∞_ref) and the transforms H_a there (``jp``: own and grid parts of
    ``_layered_nodes.bessel_on_nodes`` of the plan's rows, :meth:`_Plan.rows`), with the
    harmonics of :func:`_point_harmonics` up to ``basis.max_order``. ``known``: what this
    returned for the point's previous (smaller) basis: the integrals of the order pairs it had
    are taken from it (an integral over a pair of orders does not depend on the basis), only
    the new orders' columns are formed."""
    w, s_end = nodes.weights, nodes.s_end
    harm, end_h, shift_h = harmonics
    H = jp  # the rows: H_a(s) = Σ_p series_ap j_p(s), own and grid parts
    # Beyond S: H_a H_b -> (α_a α_b + β_a β_b)/(2 s²) on average (j_p ~ sin(s − pπ/2)/s).
    p = np.arange(basis.p_max + 1)
    amp_s, amp_c = plan.series @ np.cos(p * np.pi / 2), plan.series @ -np.sin(p * np.pi / 2)
    avg = (np.outer(amp_s, amp_s) + np.outer(amp_c, amp_c)) / (6 * s_end)
    # A film that is its own reference has no static shift (zero: no static matrix to form).
    out = (
        basis.static_of(shift_h).astype(complex)
        if np.any(shift_h)
        else np.zeros(plan.phase.shape, dtype=complex)
    )
    ms = [m for m in plan.m_values if np.any(harm[:, m]) or np.any(end_h[m])]
    if not ms:
        return plan.phase * out, None
    # ∫ Δh_{m,c} H_a H_b ds for every harmonic, component and pair of rows (one batched matrix
    # product, or the new orders' columns of it) and the tail.
    weights = w[None, :] * harm[:, ms].reshape(w.size, -1).T  # (len(ms) × 4, len(s))
    gram = _grown_gram(plan, H, weights, ms, known)
    parts = gram.reshape(len(ms), 4, *avg.shape) + end_h[ms][:, :, None, None] * avg
    # Every entry takes its harmonic's and component's integral over its rows (one gather).
    at, index = plan.gather(ms)
    out[at] += parts[index]
    return plan.phase * out, (plan.orders, ms, gram)


def _grown_gram(plan: _Plan, H, weights: np.ndarray, ms: list, known) -> np.ndarray:
    """Σ_n H_a w_kn H_b (K, R, R) of the plan's rows (:func:`_layered_nodes.weighted_gram`),
    with the pairs of orders that ``known`` (orders, harmonics, Gram of the previous basis)
    had taken from it: only the columns of the new orders are formed, and their rows by
    symmetry (the products are symmetric in a and b)."""
    if known is None or plan.orders is None or known[0] is None or list(known[1]) != list(ms):
        return weighted_gram(H, weights)
    old_orders, _, old = known
    pos = np.minimum(np.searchsorted(old_orders, plan.orders), old_orders.size - 1)
    had = old_orders[pos] == plan.orders
    if not np.any(had):
        return weighted_gram(H, weights)
    new = np.flatnonzero(~had)
    rows = np.flatnonzero(had)
    out = np.empty((weights.shape[0], plan.orders.size, plan.orders.size), dtype=complex)
    out[:, rows[:, None], rows[None, :]] = old[:, pos[had][:, None], pos[had][None, :]]
    if new.size:
        cols = weighted_gram(H, weights, new)  # (K, R, len(new))
        out[:, :, new] = cols
        out[:, new, :] = np.swapaxes(cols, 1, 2)
    return out


def _sub_basis(basis, n_radial: int) -> np.ndarray:
    """Mask of the functions with fewer than ``n_radial`` polynomial radial terms (all the
    enriched ones kept)."""
    k = (basis.rad_p - basis.rad_n) // 2
    return (basis.rad_d[basis.radial] > 0) | (k[basis.radial] < n_radial)


def _solve(basis, loss: float, matrices: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """Bᵀ M⁻¹ B (n, 2, 2) on the sub-basis ``keep`` (film static matrix + ``matrices``)."""
    m0 = (phase_of(basis.n) * basis.static)[np.ix_(keep, keep)]
    frame = eigen_frame(m0, basis.load[keep])
    return frame_solve(frame, loss, matrices[:, keep][:, :, keep])


def tangential_punch(
    table: TangentialTable,
    film,
    items,
    radii,
    rtol: float,
    res: PunchResolution,
    tensor: bool = False,
) -> np.ndarray:
    """The in-plane stiffness tensor K_αβ (N/m, (n, 2, 2)) at the points ``items`` [(index,
    stack, frequency), ...] (stacks of the in-plane block from ``_layered_path.stack_at``) of
    one film table (``film``: its undamped reference material) with radii ``radii`` (m). The
    basis grows until K_xx converges, or with ``tensor`` the whole tensor (relative to its
    largest entry)."""
    c44 = table.c44
    stacks = [st for _, st, _ in items]
    freqs = np.array([f for _, _, f in items])
    ksa = normalised_wavenumber(freqs, radii, film.density or 0.0, c44)
    ka_top = float(np.max(np.array([st.k_max for st in stacks]) * radii))
    if not ka_top <= KSA_MAX:
        raise ContactresInputError(
            f"k_s a = {ka_top:.4g} in a material of the stack is beyond the range where the "
            f"dynamic tangential stiffness is checked (k_s a <= {KSA_MAX:g}, k_s = ω√(ρ/C44)): "
            "check the frequency and the contact radius (units?)"
        )
    axisymmetric = all(st.axisymmetric for st in stacks)
    theta = np.zeros(1) if axisymmetric else 2 * np.pi * np.arange(_N_THETA) / _N_THETA
    gref = float(np.max(np.abs(table.ginf)))
    nodes = correction_nodes(stacks, radii, theta, res, gref)
    size = tangential_size(ka_top, rtol, table.n_harmonics)
    if axisymmetric:
        # The x-translation of an axisymmetric stack lives in the harmonics |n| <= 2 (module
        # docstring); the others decouple exactly.
        size = replace(size, n_harmonics=2, n_enriched=0, n_log=0)
    elif is_axisymmetric([film]):
        # The edge singularity is the top film's (the substrate is a distance h away): a film
        # unchanged by rotations about the normal has none of the oscillatory part that the
        # enrichment resolves, so every harmonic is kept and the enrichment is not (module
        # docstring).
        size = replace(size, n_enriched=0, n_log=0)
    elif nodes:
        s_top = max(float(np.max(np.abs(v.s))) for v in nodes.values())
        n_series = max(size.n_series, math.ceil(0.75 * s_top) + 8)
        if n_series > _MAX_SERIES:
            s_max = (_MAX_SERIES - 8) / 0.75
            raise ContactresInputError(
                "the tangential punch on an anisotropic top film (not unchanged by rotations "
                "about the normal) needs a thicker film for this contact radius: the layered "
                f"correction reaches η a = "
                f"{s_top:.3g}, beyond {s_max:.3g} (a top film about "
                f"{math.ceil(100 * (s_top / s_max - 1)) + 1} % thicker, or a contact that much "
                "smaller, would do)"
            )
        size = replace(size, n_series=n_series)
    pos = ksa > 0
    # Below KSA_SMALL the film's remainder is scaled linearly from its value there (as in the
    # homogeneous module: the far-field grid would miss the band that radiates).
    ka = np.maximum(ksa[pos], KSA_SMALL)
    grid = far_grid(table, float(np.min(ka))) if np.any(pos) else None
    n_radial = size.n_radial
    harmonics: dict = {}
    grams: dict = {}
    while True:
        grow = n_radial + 4 if nodes else n_radial
        basis = basis_of(table, replace(size, n_radial=grow, n_series=max(size.n_series, grow)))
        if axisymmetric:
            # The kernel of an axisymmetric stack has only the harmonics m = 0, ±2 (and its
            # film's table none that is odd): the functions of odd n decouple exactly from
            # those of even n, which carry the force (two fifths of the basis, a third of the
            # radial functions fewer).
            basis = basis.even_part()
        nb = basis.n.size
        M = np.zeros((ksa.size, nb, nb), dtype=complex)
        if np.any(pos):
            scale = (ksa[pos] / ka)[:, None, None]
            M[pos] = film_dynamic(table, basis, ka, grid) * scale
        plan = _plan(basis)
        jps = bessel_on_nodes(basis.p_max, nodes, res, plan.rows)
        for i, values in nodes.items():
            # The harmonics of Δh depend on the basis only through its largest order.
            key = (i, basis.max_order)
            if key not in harmonics:
                harmonics[key] = _point_harmonics(values, basis.max_order, axisymmetric)
            delta, grams[i] = _correction(basis, plan, values, jps[i], harmonics[key], grams.get(i))
            M[i] += delta
        k_big = _solve(basis, table.loss, M, np.ones(nb, dtype=bool))
        if not nodes:
            break
        k_small = _solve(basis, table.loss, M, _sub_basis(basis, n_radial))
        if tensor:
            size_k = np.max(np.abs(k_big), axis=(1, 2))
            change = np.max(np.max(np.abs(k_big - k_small), axis=(1, 2)) / size_k)
        else:
            change = np.max(np.abs(k_big[:, 0, 0] / k_small[:, 0, 0] - 1))
        if change < rtol / 10 or grow >= _MAX_RADIAL:
            break
        n_radial = min(_MAX_RADIAL - 4, math.ceil(1.5 * n_radial))
    return 4 * np.pi**2 * (radii * c44)[:, None, None] * k_big
