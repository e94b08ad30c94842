"""The partial waves of a stack as functions of the slowness, shared by every frequency.

The layered correction of the punch (``contactres.dynamic._layered_path``) needs the kernel
difference Δg of the stack at a few hundred wavenumbers η per frequency. The layer solutions
behind it — each material's downward and upward impedances D and exponents A
(:func:`contactres.layered.layer_waves`), the substrate's impedance Y and the film reference's
(:func:`contactres.layered.substrate_impedance`) — depend on (η, ω) only through
s_j = ρ_j ω²/(C44_f η²) = σ_j x, x = ω²/η² (the squared slowness's inverse), not on η h;
only the layer exponentials exp(η h A) and the recursion over them do. So:

- on the real axis beyond the last pole and branch point, η >= T = p₁ ω (p₁ = 1.75 × the
  largest bulk slowness, the same at every frequency), the waves are tabulated once in
  y = x p₁² ∈ [0, 1] at Chebyshev points and interpolated (barycentric formula) onto every
  node of every frequency: each is analytic in y there, its nearest singularity (a branch
  point or the Rayleigh pole of one material) beyond y = 1.75²/1.1² ≈ 2.5, so
  :data:`_N_TABLE` points give round-off (checked at construction against direct solutions at
  points between the nodes; a stack where they differ by more than :data:`_TABLE_TOL` is
  solved directly, as without a table). The interpolation is one real matrix product for
  every entry of every array, and it forms only what the others do not fix (a mirror-plane
  layer's D_u and A_u are sign changes of D_d and A_d; a film with one loss tangent is its
  own reference);
- on the lifted arc s = S₁ (τ + 0.3 i sin πτ), S₁ = T a, x = 1/(p₁ (τ + 0.3 i sin πτ))²
  does not depend on the frequency either (wherever the lift is 0.3 S₁, i.e. S₁ <= 5), so
  one set of arc solutions serves all those frequencies;
- in statics (ω = 0) x = 0 at every η: one solution per direction.

The recursion (:func:`contactres.layered.compliance_factors`) then runs once over the nodes of
all frequencies together (on the shared arc only at the Chebyshev points in T = p₁ω of
``contactres.dynamic._layered_arc`` where its fit is accepted; for the normal kernel of an
axisymmetric stack of isotropic layers on the sagittal 2x2 block of
``contactres.dynamic._layered_sagittal``), and only H_33 (or the in-plane block) of the
stack's and the reference's compliance is formed from it; the exponentials of isotropic
layers take their closed form there (two roots: the same to ~1e-15, at a fraction of the
general one's cost).
Results equal the direct solution of every node to the table's accuracy (measured: < 1e-13
relative on PMMA over quartz, isotropic and cubic (111) films).
"""

from __future__ import annotations

import numpy as np

from ..halfspace import inv3, mm
from ..layered import compliance_factors, isotropic_moduli, layer_waves, substrate_impedance
from ._layered_sagittal import (
    sagittal_h33,
    sagittal_h33_blocks,
    sagittal_reference,
    sagittal_reference_block,
)

__all__ = [
    "StackWaves",
    "arc_fraction",
    "chebyshev_matrix",
    "chebyshev_values",
    "is_isotropic",
    "waves_at",
]

# Chebyshev points of the slowness table on y ∈ [0, 1], and the largest relative difference
# between table and direct solutions (at points between the nodes) that lets the table serve.
_N_TABLE = 28
_TABLE_TOL = 1e-12
# The arc's lift over its length S₁ (where the lift is below its cap: _layered_path) and its
# panels.
ARC_LIFT = 0.3
ARC_PANELS = 4


def arc_fraction(tau: np.ndarray) -> np.ndarray:
    """z(τ) = τ + 0.3 i sin πτ: the lifted arc s = S₁ z(τ), 0 <= τ <= 1."""
    return tau + 1j * ARC_LIFT * np.sin(np.pi * tau)


def _barycentric(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The n Chebyshev points of the first kind cos(π (j + 1/2)/n) and their barycentric
    weights (−1)^j sin(π (2j + 1)/(2n)) (Berrut and Trefethen, SIAM Rev. 46, 501 (2004))."""
    j = np.arange(n)
    return np.cos(np.pi * (j + 0.5) / n), (-1.0) ** j * np.sin((2 * j + 1) * np.pi / (2 * n))


def chebyshev_matrix(n: int, x: np.ndarray) -> np.ndarray:
    """B (len(x), n): values at ``x`` (in [−1, 1]) of the polynomial through n samples at the
    Chebyshev points of the first kind cos(π (j + 1/2)/n), j = 0..n−1 (barycentric formula,
    exact at the points)."""
    xc, w = _barycentric(n)
    d = x[:, None] - xc[None, :]
    # A node on a sample point makes its row's sum infinite: only those rows (rare) are
    # replaced by the sample's unit row, not every entry tested. In place, and one division
    # per row (the table's matrix has ~10000 rows of 28 per call).
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.divide(w[None, :], d)
        total = np.sum(out, axis=1)
        out *= (1 / total)[:, None]
    hit = ~np.isfinite(total)
    if np.any(hit):
        out[hit] = (d[hit] == 0).astype(float)
    return out


def chebyshev_values(
    x: np.ndarray, samples: np.ndarray, rows: np.ndarray | None = None
) -> np.ndarray:
    """Values at ``x`` (m,) (in [−1, 1]) of the polynomials through the rows of ``samples``
    (P, n, ...), node k's own row ``rows[k]`` (None: row k, P = m): each row's n samples at
    the Chebyshev points of the first kind cos(π (j + 1/2)/n).

    Each row's Chebyshev coefficients a_i = (2/n) Σ_j f_j cos(π i (j + 1/2)/n) (a_0 halved;
    the discrete cosine transform of type II, L. N. Trefethen, *Approximation Theory and
    Approximation Practice*, SIAM 2013, Ch. 3) are formed once per row, and every node sums
    Σ_i a_i T_i(x) with T_i(x) from the three-term recurrence: n products per node where the
    barycentric formula divides n times (the same polynomial, to round-off; |T_i| <= 1 on
    [−1, 1], so the sum is as well conditioned as the coefficients)."""
    n = samples.shape[1]
    i = np.arange(n)
    dct = (2.0 / n) * np.cos(np.pi * np.outer(i, i + 0.5) / n)
    dct[0] *= 0.5
    coef = np.moveaxis(np.einsum("ij,pj...->pi...", dct, samples), 1, 0)
    coef = coef[:, rows] if rows is not None else np.ascontiguousarray(coef)
    # The sum over i term by term on vectors of all the nodes (i outermost, a_i gathered as
    # (n, m, ...)): the same products added in the same order as a contraction over i node by
    # node (an einsum, whose inner loop ran over n ~ 12 terms per node: ~0.8 M instructions
    # per call more on the 250 nm curve's groups of ~4000 nodes). Each node's value is its own
    # alone, whatever the batch; the einsum's was not for real samples at one node (another
    # order of the sum: ~1e-14 apart, review R28e). With wide trailing axes (32 in a test,
    # 1-4 on the curves) the two passes over out and term per term leave the cache and cost
    # ~12 % more CPU than the einsum; the curves' shapes gain.
    tail = (slice(None),) + (None,) * (coef.ndim - 2)
    out = np.zeros(coef.shape[1:], dtype=np.result_type(coef, x))
    term = np.empty_like(out)
    t_prev, t_cur = np.ones_like(x), x
    two_x = 2 * x
    for k in range(n):
        if k >= 2:
            t_prev, t_cur = t_cur, two_x * t_cur - t_prev
        np.multiply((t_prev if k == 0 else t_cur)[tail], coef[k], out=term)
        out += term
    return out


# The rows of a layer's waves in the sagittal form (StackWaves.sagittal_form): the {x, z}
# blocks of D_d (0-3), D_u (4-7) and A_d (8-11), row-major, and A_d's SH entry A_yy (12). An
# interpolation forms D_d, A_d and A_yy (D_u is a sign change of D_d in a mirror-plane layer).
_SAGITTAL_ROWS = 13


def _block(a: np.ndarray) -> np.ndarray:
    """The {x, z} block (2, 2, ...) of stacked 3x3 matrices (3, 3, ...) (a view)."""
    return a[0::2, 0::2]


class StackWaves:
    """The layer waves, substrate and reference impedances of one stack on a set of nodes ×
    directions: ``layers`` [(waves (4, 3, 3, n, nθ), mirror)], ``substrate`` and ``reference``
    (3, 3, n, nθ). Built by :func:`waves_at` or by interpolation (:meth:`combined`).
    ``own_reference``: the reference is the top layer's D_d (a film with one loss tangent).
    ``sagittal``: the sagittal form (:meth:`sagittal_form`): only what the normal kernel of an
    axisymmetric stack of isotropic mirror-plane layers at θ = 0 reads, each layer's
    (13, n, 1) rows and the substrate's and reference's {x, z} blocks (2, 2, n, 1)."""

    __slots__ = ("layers", "own_reference", "reference", "sagittal", "substrate")

    def __init__(
        self, layers, substrate, reference, own_reference: bool = False, sagittal: bool = False
    ):
        self.layers = layers
        self.substrate = substrate
        self.reference = reference
        self.own_reference = own_reference
        self.sagittal = sagittal

    @property
    def size(self) -> int:
        return self.substrate.shape[2]

    def arrays(self) -> list:
        """The arrays that hold the waves (a reference that is the top layer's D_d is not one
        of them: it is rebuilt as a view, not copied with them)."""
        out = [w for w, _ in self.layers] + [self.substrate]
        return out if self.own_reference else [*out, self.reference]

    def _with(self, arrays) -> StackWaves:
        n = len(self.layers)
        layers = [(a, m) for a, (_, m) in zip(arrays[:n], self.layers, strict=True)]
        reference = _top_d(layers, self.sagittal) if self.own_reference else arrays[n + 1]
        return StackWaves(layers, arrays[n], reference, self.own_reference, self.sagittal)

    def sagittal_form(self) -> StackWaves:
        """These waves in the sagittal form (class docstring): the rows the recursion of
        ``contactres.dynamic._layered_sagittal`` reads, copied out of the 3x3 arrays (the same
        numbers), so that interpolating, joining and slicing them moves ~17 rows per node
        instead of ~54."""
        layers = []
        for w, mirror in self.layers:
            red = np.empty((_SAGITTAL_ROWS, *w.shape[-2:]), dtype=complex)
            for k in range(3):
                red[4 * k : 4 * k + 4] = _block(w[k]).reshape(4, *w.shape[-2:])
            red[12] = w[2, 1, 1]
            layers.append((red, mirror))
        substrate = np.ascontiguousarray(_block(self.substrate))
        reference = (
            _top_d(layers, True)
            if self.own_reference
            else np.ascontiguousarray(_block(self.reference))
        )
        return StackWaves(layers, substrate, reference, self.own_reference, True)

    def interpolated(self, B: np.ndarray) -> StackWaves:
        """The waves at the nodes whose Chebyshev row vectors are ``B`` (m, n)."""
        m, n = B.shape
        # Only what the others do not fix: D_d and A_d of a mirror-plane layer (D_u = −M D_d M,
        # A_u = M A_d M, M = diag(1, 1, −1): the interpolation commutes with these sign
        # changes, so they are exact), and no reference that is the top layer's D_d.
        if self.sagittal:
            arrays = [np.concatenate([w[0:4], w[8:13]]) for w, _ in self.layers]
        else:
            arrays = [w[0::2] if mirror else w for w, mirror in self.layers]
        arrays = [*arrays, *self.arrays()[len(self.layers) :]]
        # Every entry of every array as one row of a (K, n) complex matrix, its real and
        # imaginary parts stacked: one real (2K, n) @ (n, m) product for all of them (a batched
        # complex product per array is ~50 matrix-vector products of B), each entry's values
        # at the nodes contiguous, as the recursion reads them.
        rows = [np.swapaxes(a, -1, -2).reshape(-1, n) for a in arrays]
        both = np.concatenate([r.real for r in rows] + [r.imag for r in rows])
        prod = both @ B.T
        k = prod.shape[0] // 2
        out, start = [], 0
        for a, r in zip(arrays, rows, strict=True):
            # The result's parts written in place (no complex temporary, no copy).
            part = np.empty((*a.shape[:-2], a.shape[-1], m), dtype=complex)
            flat = part.reshape(r.shape[0], m)
            flat.real = prod[start : start + r.shape[0]]
            flat.imag = prod[k + start : k + start + r.shape[0]]
            out.append(np.swapaxes(part, -1, -2))
            start += r.shape[0]
        layers = []
        for (_, mirror), w in zip(self.layers, out, strict=False):
            if self.sagittal:
                w = _sagittal_mirror(w)
            elif mirror:
                full = np.empty((4, *w.shape[1:]), dtype=complex)
                full[0::2] = w
                full[3] = w[1]
                np.negative(w[0], out=full[1])
                full[1, :2, 2] *= -1
                full[1, 2, :2] *= -1
                full[3, :2, 2] *= -1
                full[3, 2, :2] *= -1
                w = full
            layers.append((w, mirror))
        n_l = len(self.layers)
        reference = _top_d(layers, self.sagittal) if self.own_reference else out[n_l + 1]
        return StackWaves(layers, out[n_l], reference, self.own_reference, self.sagittal)

    def repeated(self, counts) -> StackWaves:
        """Node j taken ``counts[j]`` times (a single static node broadcast to many)."""
        return self._with([np.repeat(a, counts, axis=-2) for a in self.arrays()])

    @staticmethod
    def combined(parts) -> StackWaves:
        """The nodes of ``parts`` one after the other."""
        arrays = [
            np.concatenate(group, axis=-2)
            for group in zip(*(p.arrays() for p in parts), strict=True)
        ]
        return parts[0]._with(arrays)

    def delta_g(self, stack, eta_h, shift, theta=None, isotropic=None) -> np.ndarray:
        """Δg = g_ref − g_stack − shift (n, nθ) (+ (2, 2) in-plane) at these nodes, with
        ``eta_h`` (n_layers, n) the layers' η h_j (complex on the arc); ``theta`` (nθ,), the
        directions, lets an isotropic layer's exponential take its closed form (without it,
        the general one: the same to ~1e-15); ``isotropic``: which layers are isotropic (one
        bool per layer, found by the caller once for many calls; None: tested here)."""
        n, nth = self.substrate.shape[2:]

        def flat(a):
            return a.reshape((*a.shape[:-2], n * nth))

        layers = [(flat(w), m) for w, m in self.layers]
        eh = [np.repeat(np.asarray(e, dtype=complex), nth) for e in eta_h]
        if self.sagittal:
            # The sagittal form: the recursion on the blocks it holds (as below).
            blocks = [
                (
                    w[0:4].reshape(2, 2, -1),
                    w[4:8].reshape(2, 2, -1),
                    w[8:12].reshape(2, 2, -1),
                    w[12],
                )
                for w, _ in layers
            ]
            h33 = sagittal_h33_blocks(blocks, eh, flat(self.substrate))
            out = sagittal_reference_block(flat(self.reference)) - h33
            return out.reshape(n, nth) - shift[None]
        # An isotropic layer's exponential in closed form (its two roots; the direction of
        # every point tells its SH wave apart): the same to ~1e-15 at a fraction of the cost.
        closed: list[np.ndarray | None] = [None] * len(layers)
        if theta is not None:
            th = np.tile(np.asarray(theta, dtype=float), n)
            if isotropic is None:
                isotropic = [is_isotropic(c) for c in stack.tensors[: len(layers)]]
            closed = [th if iso else None for iso in isotropic]
        if (
            closed
            and all(c is not None for c in closed)
            and all(m for _, m in layers)
            and not stack.inplane
            and stack.axisymmetric
            and nth == 1
            and theta is not None
            and theta[0] == 0
        ):
            # Isotropic mirror-plane layers of an axisymmetric stack at θ = 0: H_33 from the
            # recursion on the sagittal {x, z} block (2x2 instead of 3x3; the same to
            # round-off).
            h33 = sagittal_h33([w for w, _ in layers], eh, flat(self.substrate))
            out = sagittal_reference(flat(self.reference)) - h33
            return out.reshape(n, nth) - shift[None]
        # H = P Q⁻¹ (compliance_factors; P = I without layers) and H_ref = reference⁻¹: only
        # the entries the kernel needs (H_33, or the in-plane block).
        with np.errstate(all="ignore"):
            if layers:
                P, Q = compliance_factors(layers, eh, flat(self.substrate), closed)
            else:
                P, Q = None, flat(self.substrate)
            ref = flat(self.reference)
            if stack.inplane:
                Qi = inv3(Q)
                H = Qi if P is None else mm(P, Qi)
                out = inv3(ref)[:2, :2] - H[:2, :2]
                return np.moveaxis(out, (0, 1), (-2, -1)).reshape(n, nth, 2, 2) - shift[None]
            col = _inverse_column(Q)
            h33 = col[2] if P is None else P[2, 0] * col[0] + P[2, 1] * col[1] + P[2, 2] * col[2]
            out = _inverse_column(ref)[2] - h33
        return out.reshape(n, nth) - shift[None]


def _top_d(layers: list, sagittal: bool) -> np.ndarray:
    """The top layer's D_d (a view): (3, 3, n, nθ), or its {x, z} block (2, 2, n, 1) in the
    sagittal form."""
    w = layers[0][0]
    return w[0:4].reshape(2, 2, *w.shape[1:]) if sagittal else w[0]


def _sagittal_mirror(w: np.ndarray) -> np.ndarray:
    """A mirror-plane layer's sagittal rows (13, m, 1) from the interpolated D_d, A_d and A_yy
    (9, m, 1): D_u's block by the sign changes that form a mirror layer's D_u = −M D_d M in
    :meth:`StackWaves.interpolated` (the same operations on the same entries, so the same
    numbers: the diagonal negated, the off-diagonal negated twice)."""
    red = np.empty((_SAGITTAL_ROWS, *w.shape[1:]), dtype=complex)
    red[0:4] = w[0:4]
    red[8:13] = w[4:9]
    np.negative(w[0:4], out=red[4:8])
    red[5:7] *= -1
    return red


def is_isotropic(c: np.ndarray) -> bool:
    """True if the tensor c (3, 3, 3, 3) is isotropic, c_ijkl = λ δ_ij δ_kl + μ (δ_ik δ_jl +
    δ_il δ_jk) to the round-off of a rotated tensor (complex moduli allowed;
    :func:`contactres.layered.isotropic_moduli`)."""
    return isotropic_moduli(c) is not None


def _inverse_column(a: np.ndarray) -> list:
    """The third column of the inverse of every stacked 3x3 matrix a (3, 3, N), by the
    adjugate formula of :func:`contactres.halfspace.inv3` (the same arithmetic)."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    r = 1.0 / (
        a00 * (a11 * a22 - a12 * a21)
        + a01 * (a12 * a20 - a10 * a22)
        + a02 * (a10 * a21 - a11 * a20)
    )
    return [(a01 * a12 - a02 * a11) * r, (a02 * a10 - a00 * a12) * r, (a00 * a11 - a01 * a10) * r]


def waves_at(stack, theta: np.ndarray, x) -> StackWaves:
    """The waves of ``stack`` (``_layered_path.Stack``) solved directly at x = ω²/η² (s_j =
    σ_j x, complex allowed) × directions ``theta``."""
    x = np.asarray(x, dtype=complex)
    n, nth = x.size, theta.size
    th = np.broadcast_to(theta[None, :], (n, nth)).ravel()
    sv = [np.repeat(sig * x, nth) for sig in stack.sigma]

    def shaped(a):
        return a.reshape((*a.shape[:-1], n, nth))

    layers = [
        (shaped(w), m)
        for w, m in (
            layer_waves(c, th, v) for c, v in zip(stack.tensors[:-1], sv[:-1], strict=True)
        )
    ]
    substrate = shaped(substrate_impedance(stack.tensors[-1], th, sv[-1]))
    if layers and np.array_equal(stack.reference, stack.tensors[0]):
        # A film with one loss tangent is its own reference: its D_d is the reference's Y.
        reference = layers[0][0][0]
    else:
        reference = shaped(substrate_impedance(stack.reference, th, sv[0]))
    own = bool(layers) and np.array_equal(stack.reference, stack.tensors[0])
    return StackWaves(layers, substrate, reference, own)


def slowness_table(stack, theta: np.ndarray) -> StackWaves | None:
    """The waves at the Chebyshev points of y = x p₁² ∈ [0, 1] (module docstring), or None
    where interpolating them would not reach :data:`_TABLE_TOL` (then solve directly)."""
    p1 = stack.pole_slowness
    yc = 0.5 * (1 + np.cos(np.pi * (np.arange(_N_TABLE) + 0.5) / _N_TABLE))
    # Points between the nodes where the interpolant is checked against direct solutions.
    y_check = np.array([0.013, 0.31, 0.62, 0.97, 1.0])
    both = waves_at(stack, theta, np.concatenate([yc, y_check]) / p1**2)
    table = both._with([a[..., :_N_TABLE, :] for a in both.arrays()])
    direct = [a[..., _N_TABLE:, :] for a in both.arrays()]
    approx = table.interpolated(chebyshev_matrix(_N_TABLE, 2 * y_check - 1)).arrays()
    for d, t in zip(direct, approx, strict=True):
        scale = np.max(np.abs(d), axis=tuple(range(d.ndim - 2)))
        if not np.all(np.max(np.abs(d - t), axis=tuple(range(d.ndim - 2))) <= _TABLE_TOL * scale):
            return None
    return table
