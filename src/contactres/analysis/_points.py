"""Operations over arrays laid out points first, (M, ...), with the numbers of numpy's own
forms on the points-last layout (the loop fits' exact χ², :mod:`contactres.analysis._loops`).

Why: numpy's sum over a last axis of ~10 points pays its cost per row (a call of its pairwise
summation for every sweep and trial), and an operand broadcast along an axis runs through
numpy's buffers (numpy 2.x) at several times the cost of a plain pass; with the points on the
first axis each addition of the sum is one pass over whole rows, and a per-sweep number is
applied to a row of points at a time.
"""

from __future__ import annotations

import numpy as np

__all__ = ["BY_POINT_MIN", "PAIRWISE_BLOCK", "by_point", "point_sum"]


#: :func:`by_point` runs its operation point by point where a point's part holds at least this
#: many numbers (there a call per point costs less than numpy's buffers; below, one call).
BY_POINT_MIN = 1024


def by_point(op, a, v, out=None) -> np.ndarray:
    """``op(a, v)`` (a ufunc) of ``a`` (M, ...) laid out points first and ``v`` shaped as its
    trailing axes (one number per sweep and trial), the same numbers, into ``out`` (None: a new
    array): a call per point of ``a``, where ``v`` is then not broadcast along the first axis,
    which numpy (2.x) runs through buffers at several times the cost of a plain pass."""
    shape = (a.shape[0], *np.broadcast_shapes(a.shape[1:], np.shape(v)))
    out = np.empty(shape) if out is None else out
    if a[:1].size < BY_POINT_MIN:
        return op(a, v, out=out)
    for m in range(a.shape[0]):
        op(a[m], v, out=out[m])
    return out


#: numpy sums at most this many terms as one block of eight running sums (longer rows are split
#: in halves first: numpy's PW_BLOCKSIZE); :func:`point_sum` copies its order up to here.
PAIRWISE_BLOCK = 128


def point_sum(a: np.ndarray) -> np.ndarray:
    """Σ over the first axis of ``a`` (M, ...), bit for bit the number that numpy's
    ``a.sum(-1)`` gives with the points on the last axis (its pairwise summation), without its
    cost per row: numpy adds the M terms of each row into 0 as eight running sums (terms j,
    j + 8, j + 16, ... for j < 8), joined as ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7)),
    then the last M mod 8 terms one by one (fewer than 8 terms: one by one); here each of those
    additions is one pass over whole rows of points. Beyond :data:`PAIRWISE_BLOCK` terms numpy
    splits a row first: such rows are summed by numpy itself, on a copy with the points last
    (tests/analysis/test_loop_search.py checks both against numpy for every M up to 300)."""
    m = a.shape[0]
    if m == 0 or m > PAIRWISE_BLOCK:
        return np.ascontiguousarray(np.moveaxis(a, 0, -1)).sum(-1)
    if m < 8:
        total = a[0] + 0.0  # 0 + a0: numpy's start (-0.0 becomes 0.0)
        for i in range(1, m):
            total += a[i]
        return total
    tail = m - m % 8
    runs = a[:8] if tail == 8 else a[:8] + a[8:16]
    for i in range(16, tail, 8):
        runs += a[i : i + 8]
    pairs = runs[0::2] + runs[1::2]
    quads = pairs[0::2] + pairs[1::2]
    total = quads[0] + quads[1]
    for i in range(tail, m):
        total += a[i]
    total += 0.0  # numpy adds the row's sum to 0: -0.0 (every term -0.0) becomes 0.0
    return total
