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
        (general step only; a point then stops when both have converged).

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


def _cyclic_reduction(A0, a1, a2, may_stall, dual=False):
    """Cyclic reduction for the general pencil: the limit Â1 (3, 3, N) and a converged flag;
    with ``dual`` also the limit Â1' of the reversed pencil A2 + A1 w + A0 w² (its iterates
    are those of A0, A1, A2 with A0 and A2 swapped: Â1' accumulates A0 K A2 where Â1 takes
    A2 K A0), a point then stopping when both updates are small."""
    A1h = a1.copy()
    A1h2 = a1.copy() if dual else None
    n = A0.shape[-1]
    # Slots hold A0, A1, A2, Â1 (and Â1') and one free stack; ``at`` says which is which
    # (the free one takes each new A0, A2 and each gathered stack, and the old one is freed).
    start = (A0, a1, a2, a1, a1) if dual else (A0, a1, a2, a1)
    pool = _Slots(len(start) + 1, (3, 3), n)
    for i, x in enumerate(start):
        pool.view(i, n)[...] = x
    at = list(range(len(start)))
    free = len(start)
    work = _Slots(5, (3, 3), n)
    mag = _Slots(1, (3, 3), n, dtype=float)
    pts = _Finish(n, may_stall)
    for it in range(_CR_MAXITER):
        m = pts.active.size
        a0, a1, a2, a1h, *rest = (pool.view(i, m) for i in at)
        k, ka0, ka2, a0ka2, tmp = (work.view(i, m) for i in range(5))
        re = mag.view(0, m)
        inv3(a1, out=k)
        mm(k, a0, out=ka0, tmp=tmp)
        mm(k, a2, out=ka2, tmp=tmp)
        # A0, A1, A2 are complex symmetric (major symmetry of C) and cyclic reduction keeps
        # them so: A2 K A0 = (A0 K A2)ᵀ saves one product.
        mm(a0, ka2, out=a0ka2, tmp=tmp)
        a2ka0 = transpose(a0ka2)
        a1h -= a2ka0
        a1 -= a0ka2
        a1 -= a2ka0
        # (−A0 K A0 and −A2 K A2 by the recursion; both signs are dropped, as they cancel in
        # every later update: A0 and A2 enter them in pairs.)
        mm(a0, ka0, out=pool.view(free, m), tmp=tmp)
        at[0], free = free, at[0]
        mm(a2, ka2, out=pool.view(free, m), tmp=tmp)
        at[2], free = free, at[2]
        # Quadratic convergence: after an update of relative size τ the rest is ~τ².
        upd = np.abs(a0ka2, out=re).max(axis=(0, 1))
        scale = np.abs(a1h, out=re).max(axis=(0, 1))
        if A1h2 is not None:
            rest[0] -= a0ka2
            np.minimum(scale, np.abs(rest[0], out=re).max(axis=(0, 1)), out=scale)
        new = pts.newly_converged(it, upd, scale)
        if np.any(new):
            A1h[:, :, pts.active[new]] = a1h[:, :, new]
            if A1h2 is not None:
                A1h2[:, :, pts.active[new]] = rest[0][:, :, new]
        keep = pts.keep(it)
        if keep is not None:
            for j, i in enumerate(at):
                np.take(pool.view(i, m), keep, axis=-1, out=pool.view(free, keep.size), mode="clip")
                at[j], free = free, i
        if pts.active.size == 0:
            break
    return A1h, A1h2, pts.done


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
