"""The decaying solvent of the Christoffel pencil by cyclic reduction (a doubling algorithm).

For a surface wave vector ξ = η (cos θ, sin θ) the partial waves of the half-space have vertical
wave numbers p η, the roots of det(W p² + (R + Rᵀ) p + Q − S) = 0 (the Christoffel equation of
paper 1, Eqs. 10-12, with the dimensionless blocks of :mod:`._compliance`; S is the diagonal
inertia term, ρω²/(C44 η²) per component after balancing). The field decaying into the solid
z > 0 is built from the three roots with Im p > 0; they are the eigenvalues of the *decaying
solvent* Z of W Z² + (R + Rᵀ) Z + Q − S = 0.

The Möbius map p = iβ (1 + w)/(1 − w) sends the decaying half plane Im p > 0 to the unit disk
``|w|`` < 1 and turns the pencil into A0 + A1 w + A2 w²; cyclic reduction (Bini & Meini) then
returns the minimal solvent G of A0 + A1 G + A2 G² = 0, whose eigenvalues are the images of the
decaying roots. It never forms eigenvectors, so it is exact and continuous at degenerate points
(the triple static root p = i of an isotropic solid, the double shear root in dynamics).

Convergence is quadratic: the number of steps is set by how close the mapped roots come to the
unit circle (~5 in the evanescent range, ~10 for barely damped propagating waves), not by β.
A lossless solid at a real κ below a bulk-wave cutoff has roots on the circle (real p): those
points stall and are handed back as not converged (:mod:`._outgoing` takes them).

When the surface is a mirror plane of the solid (:func:`.compliance.has_mirror_plane`) the
pencil has the block structure used by :func:`_cyclic_reduction_mirror` and a step costs a
third of a general one: ~1.5-2 µs per (κ, θ) point against ~4 µs for a general face
(``benchmarks/bench_halfspace.py``).
"""

from __future__ import annotations

import numpy as np

from ._stacked import inv3, maxabs, mm, transpose

__all__ = ["decaying_solvent"]

# Cyclic reduction stops after an update of its accumulated matrix below this (relative); the
# convergence is quadratic, so what is left is far smaller (stopping at 1e-15 instead moves g
# by < 1e-13: a test).
_CR_TOL = 1e-10
# Maximum number of doubling steps: 2**40 squarings resolve roots within ~1e-11 of |w| = 1.
_CR_MAXITER = 40
# A lossless point at real κ whose update is still above _STALL_TOL after _STALL_ITER steps has
# (nearly) real vertical wave numbers; it goes to the eigen-decomposition instead.
_STALL_ITER = 12
_STALL_TOL = 1e-3
# Recorded (converged or given-up) points leave the work arrays once the oldest of them has
# waited this many steps, or once they are this fraction of the active points.
_RETIRE_WAIT = 2
_RETIRE_SHARE = 0.25


def _retire(waited: int, finished: int, active: int) -> bool:
    """Whether to drop the recorded points from the work arrays now: all of them are finished,
    the oldest has iterated ``_RETIRE_WAIT`` steps past its result (its iterates only shrink,
    towards underflow), or they are ``_RETIRE_SHARE`` of the ``active`` points."""
    return finished == active or waited >= _RETIRE_WAIT or finished >= _RETIRE_SHARE * active


class _Finish:
    """Which points of a doubling loop are still iterated, and when finished ones leave.

    Converged points are recorded at once but, if ``batched``, dropped from the work arrays
    only in batches (:func:`_retire`): a few points converge in every step, and gathering the
    general step's four stacks each time cost about a fifth of a step. A recorded point
    iterates on unused for a step or two; its arithmetic is elementwise, so the others' values
    do not change.
    """

    def __init__(self, n: int, may_stall, batched: bool = True) -> None:
        self.batched = batched  # else finished points leave in the step they finish
        self.active = np.arange(n)  # original index of every work column
        self.done = np.zeros(n, dtype=bool)  # converged (by original index)
        self.may_stall = may_stall
        self.fin = np.zeros(n, dtype=bool)  # recorded (by work column)
        self.since = -1  # step of the oldest recorded point still in the work arrays

    def newly_converged(self, it: int, upd, scale) -> np.ndarray:
        """Work columns that converge in step ``it`` (update ``upd`` against ``scale``)."""
        new = (upd <= _CR_TOL * scale) & np.isfinite(scale) & ~self.fin  # NaN: not converged
        if np.any(new):
            self.done[self.active[new]] = True
            self.fin |= new
            self.since = it if self.since < 0 else self.since
        if self.may_stall is not None and it + 1 == _STALL_ITER:
            stall = self.may_stall[self.active] & ~(upd <= _STALL_TOL * scale) & ~self.fin
            if np.any(stall):  # given up: they leave now
                self.fin |= stall
                self.since = it - _RETIRE_WAIT
        return new

    def keep(self, it: int) -> np.ndarray | None:
        """Work columns to keep if the recorded ones leave now (then they are gone), else
        None."""
        m = self.active.size
        if self.since < 0:
            return None
        if self.batched and not _retire(it - self.since, int(np.count_nonzero(self.fin)), m):
            return None
        keep = np.flatnonzero(~self.fin)
        self.active = self.active[keep]
        self.fin = np.zeros(keep.size, dtype=bool)
        self.since = -1
        return keep


def decaying_solvent(Q, R, W, s, beta, may_stall=None, mirror=False, dual=False):
    """Möbius image of the decaying solvent of the balanced Christoffel pencil (paper 1,
    Eqs. 10-12).

    Parameters
    ----------
    Q, R, W : ndarray, shape (3, 3, N)
        Dimensionless blocks of the pencil W p² + (R + Rᵀ) p + Q − diag(s) (stiffness over the
        reference C44, balanced so that W has a unit diagonal).
    s : ndarray, shape (3, N)
        Diagonal of the balanced inertia term, ρω²/(C44 η²) per component (0 in statics;
        complex allowed).
    beta : ndarray, shape (N,)
        Möbius parameter β > 0 of p = iβ (1 + w)/(1 − w), of the order of ``|p|``.
    may_stall : ndarray of bool, shape (N,), optional
        Points (lossless, real κ) that may have real roots p: if they have not come near
        convergence after ``_STALL_ITER`` steps they are given up (roots on the unit circle).
    mirror : bool
        The surface is a mirror plane of the solid: take the block-structured step.
    dual : bool
        Also return the solvent of the direction θ + π (R -> −R), from the same iterates
        (general step only; its limit is Â1ᵀ, see :func:`_cyclic_reduction`, so the points
        stop as without ``dual``).

    Returns
    -------
    G : ndarray, complex, shape (3, 3, N)
        The minimal solvent of A0 + A1 G + A2 G² = 0; Z = iβ (I + G)(I − G)⁻¹.
    done : ndarray of bool, shape (N,)
        Converged points (G is meaningless elsewhere).
    resid : ndarray, shape (N,)
        Relative residual (backward error) of G; inf where it is not finite.
    G2, resid2 : ndarray
        With ``dual`` (not ``mirror``): the same for θ + π, the pencil with A0 and A2
        swapped (converged where ``done``).
    """
    Qs = Q.astype(complex)
    Qs[[0, 1, 2], [0, 1, 2]] -= s
    bW = beta**2 * W
    ibK = 1j * beta * (R + transpose(R))
    A0 = Qs - bW + ibK
    a1 = -2.0 * (bW + Qs)
    a2 = Qs - bW - ibK
    if mirror:
        A1h, done = _cyclic_reduction_mirror(A0, a1, may_stall)
        A1h2 = None
    else:
        A1h, A1h2, done = _cyclic_reduction(A0, a1, a2, may_stall, dual)
    G, resid = _solvent(A1h, A0, a1, a2)
    if A1h2 is None:
        return G, done, resid
    # The reversed pencil is that of the direction θ + π (R -> −R swaps A0 and A2).
    G2, resid2 = _solvent(A1h2, a2, a1, A0)
    return G, done, resid, G2, resid2


def _solvent(A1h, A0, a1, a2):
    """The minimal solvent G = −Â1⁻¹ A0 of A0 + A1 G + A2 G² = 0 and its relative residual
    (backward error; inf where it is not finite)."""
    G = -mm(inv3(A1h), A0)
    res = A0 + mm(a1, G) + mm(a2, mm(G, G))
    g = maxabs(G)
    resid = maxabs(res) / (maxabs(A0) + maxabs(a1) * g + maxabs(a2) * g**2)
    resid[~np.isfinite(resid)] = np.inf
    return G, resid


class _Slots:
    """Work buffers for the doubling loops, each holding ``rows`` values for up to n points.

    :meth:`view` gives slot i's first m points as a C-contiguous (*shape, m) array, so that
    dropping finished points (m shrinks) needs no fresh arrays: a new (3, 3, N) stack in every
    step cost more than its arithmetic (the heap grew and shrank, and every new page faulted).
    """

    def __init__(self, slots: int, shape: tuple[int, ...], n: int, dtype=complex) -> None:
        self.shape = shape
        self.rows = int(np.prod(shape))
        self.buf = np.empty((slots, self.rows * n), dtype=dtype)

    def view(self, i: int, m: int) -> np.ndarray:
        return self.buf[i, : self.rows * m].reshape(*self.shape, m)


# Upper-triangle entries (i, j), i <= j, of a symmetric 3x3 matrix in the packed order of the
# general step, and the packed index of every entry (i, j).
_UPPER = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
_PACKED = ((0, 3, 4), (3, 1, 5), (4, 5, 2))


def _cyclic_reduction(A0, a1, a2, may_stall, dual=False):
    """Cyclic reduction for the general pencil: the limit Â1 (3, 3, N), with ``dual`` also the
    limit Â1' of the reversed pencil A2 + A1 w + A0 w², and a converged flag.

    A0, A1, A2 are complex symmetric (major symmetry of C: Q, W and R + Rᵀ are symmetric) and
    one step keeps them so, with K = A1⁻¹ symmetric:

        A0 <- A0 K A0,   A2 <- A2 K A2,   P = A0 K A2,   A1 <- A1 − P − Pᵀ,   Â1 <- Â1 − Pᵀ

    (the signs of A0 and A2 are dropped: they enter every later update in pairs). So K, A0
    and A2 are kept as their six upper-triangle entries, and A0, A2 side by side, entry by
    entry, so that X = K A0 and Y = K A2 come from the same calls on twice the length, as do
    A0 X and A2 Y: 138 complex products per point and step against 165 for five full 3x3
    products and an inverse, in about 60 % of the numpy calls (a call's overhead is about the
    arithmetic of a thousand points). The reversed pencil's iterates are those of A0, A2
    swapped: the same A1 and, as A1 is symmetric, Â1' = A1 − Σ P = Â1ᵀ, so ``dual`` costs
    nothing and stops with Â1 (same iterates, same scale).
    """
    A1h = a1.copy()
    n = A0.shape[-1]
    # Rows of the iterate: A0 and A2 paired per packed entry (6, 2), A1 packed (6), Â1 (3, 3);
    # two slots, the iterate and the next one (see _Slots).
    pool = _Slots(2, (27,), n)
    cur = 0
    st = pool.view(cur, n)
    for e, (i, j) in enumerate(_UPPER):
        st[2 * e], st[2 * e + 1], st[12 + e] = A0[i, j], a2[i, j], a1[i, j]
    st[18:27] = a1.reshape(9, n)
    # K paired like A0, A2 (6, 2); [X, Y] (3, 3, 2); Pᵀ; the cofactors; a temporary of two
    # rows. (Every operand below is a contiguous row or block: numpy takes about four times as
    # long on a transposed or strided (3, 3, m) view as on a contiguous one.)
    work = _Slots(1, (12 + 18 + 9 + 6 + 2,), n)
    mag = _Slots(1, (9,), n, dtype=float)
    pts = _Finish(n, may_stall)
    for it in range(_CR_MAXITER):
        m = pts.active.size
        st, w, re = pool.view(cur, m), work.view(0, m), mag.view(0, m).reshape(3, 3, m)
        S = st[:12].reshape(6, 2, m)
        a1, a1h = st[12:18], st[18:27].reshape(3, 3, m)
        K, XY = w[:12].reshape(6, 2, m), w[12:30].reshape(3, 3, 2, m)
        PT, cof, t2 = w[30:39].reshape(3, 3, m), w[39:45], w[45:47]
        _symmetric_inverse(a1, cof, t2[0], t2[1], K)
        # [X, Y] = K [A0, A2] (full), then [A0 X, A2 Y] (upper triangles: the next A0, A2).
        for i in range(3):
            for j in range(3):
                _dot3(K, _PACKED[i], S, [_PACKED[k][j] for k in range(3)], XY[i, j], t2)
        cur = 1 - cur
        nxt = pool.view(cur, m)
        Sn = nxt[:12].reshape(6, 2, m)
        for e, (i, j) in enumerate(_UPPER):
            _dot3(S, _PACKED[i], XY[:, j], (0, 1, 2), Sn[e], t2)
        # P = A0 Y, stored transposed (Â1 takes Pᵀ).
        A0p, Y = S[:, 0], XY[:, :, 1]
        for i in range(3):
            for j in range(3):
                _dot3(A0p, _PACKED[i], Y[:, j], (0, 1, 2), PT[j, i], t2[0])
        a1n, a1hn = nxt[12:18], nxt[18:27].reshape(3, 3, m)
        for e, (i, j) in enumerate(_UPPER):
            np.subtract(a1[e], np.add(PT[i, j], PT[j, i], out=t2[0]), out=a1n[e])
        np.subtract(a1h, PT, out=a1hn)
        # Quadratic convergence: after an update of relative size τ the rest is ~τ².
        upd = np.abs(PT, out=re).max(axis=(0, 1))
        scale = np.abs(a1hn, out=re).max(axis=(0, 1))
        new = pts.newly_converged(it, upd, scale)
        if np.any(new):
            A1h[:, :, pts.active[new]] = a1hn[:, :, new]
        keep = pts.keep(it)
        if keep is not None:
            np.take(nxt, keep, axis=-1, out=pool.view(1 - cur, keep.size), mode="clip")
            cur = 1 - cur
        if pts.active.size == 0:
            break
    return A1h, (transpose(A1h) if dual else None), pts.done


def _dot3(a, ai, b, bi, out, tmp) -> None:
    """out = a[ai[0]] b[bi[0]] + a[ai[1]] b[bi[1]] + a[ai[2]] b[bi[2]] (elementwise, in this
    order), with a work array ``tmp`` shaped like ``out``."""
    np.multiply(a[ai[0]], b[bi[0]], out=out)
    out += np.multiply(a[ai[1]], b[bi[1]], out=tmp)
    out += np.multiply(a[ai[2]], b[bi[2]], out=tmp)


def _symmetric_inverse(a, cof, t, r, out) -> None:
    """Inverse of stacked complex symmetric 3x3 matrices (packed upper triangles ``a``, (6, m))
    by the adjugate formula, into ``out`` (6, 2, m): each packed entry twice (see
    :func:`_cyclic_reduction`). ``cof`` (6, m), ``t`` and ``r`` (m) are work arrays."""
    a00, a11, a22, a01, a02, a12 = a
    # Cofactors in packed order: the six distinct entries of the adjugate.
    for c, (x, y, u, v) in zip(
        cof,
        [
            (a11, a22, a12, a12),
            (a00, a22, a02, a02),
            (a00, a11, a01, a01),
            (a02, a12, a01, a22),
            (a01, a12, a02, a11),
            (a01, a02, a00, a12),
        ],
        strict=True,
    ):
        np.multiply(x, y, out=c)
        c -= np.multiply(u, v, out=t)
    np.multiply(a00, cof[0], out=r)
    r += np.multiply(a01, cof[3], out=t)
    r += np.multiply(a02, cof[4], out=t)
    np.divide(1.0, r, out=r)
    for e in range(6):
        np.multiply(cof[e], r, out=out[e, 0])
    out[:, 1] = out[:, 0]


def _cyclic_reduction_mirror(A0, a1, may_stall):
    """Cyclic reduction for a solid with a mirror plane z -> −z (the surface plane; see
    :func:`.compliance.has_mirror_plane`).

    Then A2 = D A0 D with D = diag(1, 1, −1), A1 is block diagonal (2x2 ⊕ 1x1), and cyclic
    reduction keeps both properties, so each step needs only the blocks P (2x2), q (2), r of
    A0 = [[P, q], [qᵀ, r]], the blocks S, t of A1 and a 2x2 inverse: a third of the work of
    the general step, with the same iterates (in exact arithmetic) and the same stopping rule.
    The sign of A0 is dropped (it enters every update squared).
    """
    n = A0.shape[-1]
    # Rows: p11 p12 p22 q1 q2 r | s11 s12 s22 t | h11 h12 h22 h33 h13 h23 (Â1, upper triangle;
    # its (3, α) entries are −(α, 3)).
    pool = _Slots(2, (16,), n)  # the iterate and the next one (see _cyclic_reduction)
    cur = 0
    st = pool.view(cur, n)
    st[0], st[1], st[2] = A0[0, 0], A0[0, 1], A0[1, 1]
    st[3], st[4], st[5] = A0[0, 2], A0[1, 2], A0[2, 2]
    st[6], st[7], st[8], st[9] = a1[0, 0], a1[0, 1], a1[1, 1], a1[2, 2]
    st[10:14] = st[6:10]
    st[14:16] = 0.0
    h = st[10:16].copy()
    # Its 16 rows are gathered in one call, cheaper than the steps a finished point would
    # iterate on: no batching.
    pts = _Finish(n, may_stall, batched=False)
    for it in range(_CR_MAXITER):
        m = pts.active.size
        st = pool.view(cur, m)
        p11, p12, p22, q1, q2, r, s11, s12, s22, t = st[:10]
        ide = 1.0 / (s11 * s22 - s12 * s12)
        t11, t12, t22 = s22 * ide, -s12 * ide, s11 * ide
        u = 1.0 / t
        pt11 = p11 * t11 + p12 * t12
        pt12 = p11 * t12 + p12 * t22
        pt21 = p12 * t11 + p22 * t12
        pt22 = p12 * t12 + p22 * t22
        tq1 = t11 * q1 + t12 * q2
        tq2 = t12 * q1 + t22 * q2
        uq1, uq2, ur = u * q1, u * q2, u * r
        # P T P, u q qᵀ, P T q, u r q, qᵀ T q, u r²: the blocks of A0 K A0 and A0 K A2.
        e11, e12, e22 = pt11 * p11 + pt12 * p12, pt11 * p12 + pt12 * p22, pt21 * p12 + pt22 * p22
        f11, f12, f22 = uq1 * q1, uq1 * q2, uq2 * q2
        v11, v12 = pt11 * q1 + pt12 * q2, pt21 * q1 + pt22 * q2
        v21, v22 = ur * q1, ur * q2
        w1, w2 = q1 * tq1 + q2 * tq2, ur * r
        upd = np.empty((6, m), dtype=complex)
        # A2 K A0 = (A0 K A2)ᵀ: blocks P T P − u q qᵀ, ±(P T q − u r q), u r² − qᵀ T q.
        np.subtract(e11, f11, out=upd[0])
        np.subtract(e12, f12, out=upd[1])
        np.subtract(e22, f22, out=upd[2])
        np.subtract(w2, w1, out=upd[3])
        np.subtract(v11, v21, out=upd[4])
        np.subtract(v12, v22, out=upd[5])
        cur = 1 - cur
        nxt = pool.view(cur, m)
        np.add(e11, f11, out=nxt[0])
        np.add(e12, f12, out=nxt[1])
        np.add(e22, f22, out=nxt[2])
        np.add(v11, v21, out=nxt[3])
        np.add(v12, v22, out=nxt[4])
        np.add(w1, w2, out=nxt[5])
        np.subtract(st[6:10], 2.0 * upd[:4], out=nxt[6:10])
        np.subtract(st[10:16], upd, out=nxt[10:16])
        st = nxt
        # Quadratic convergence: after an update of relative size τ the rest is ~τ².
        ma = np.abs(upd).max(axis=0)
        scale = np.abs(st[10:16]).max(axis=0)
        new = pts.newly_converged(it, ma, scale)
        if np.any(new):
            h[:, pts.active[new]] = st[10:16, new]
        keep = pts.keep(it)
        if keep is not None:
            np.take(st, keep, axis=-1, out=pool.view(1 - cur, keep.size), mode="clip")
            cur = 1 - cur
        if pts.active.size == 0:
            break
    h11, h12, h22, h33, h13, h23 = h
    A1h = np.array([[h11, h12, h13], [h12, h22, h23], [-h13, -h23, h33]])
    return A1h, pts.done
