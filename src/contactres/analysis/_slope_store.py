"""The store of the plateau loop's slopes that one call of the plateau's evidence reads again.

Why. :func:`contactres.analysis._plateau_evidence.plateau_log_evidence` evaluates the slopes
G′, G″ of the plateau loop at rows of nodes (θ, d_c/u_max and a block's amplitudes) that
blocks on one grid of amplitudes under one prior share; a row met again in a later chunk of the
call is read from here instead of being evaluated again, bit for bit, and held only while a
later chunk may read it (review R24a). Its own module since issue 31, point 3, eighth round
(the evidence's module had reached its length limit).
"""

from __future__ import annotations

import numpy as np

__all__ = ["SlopeStore"]


class SlopeStore:
    """The slopes of the rows of nodes that a call of
    :func:`contactres.analysis._plateau_evidence.plateau_log_evidence` reads again (its
    ``_slopes``), and only those.

    Why. A row's slopes are read again only by a row of another job (block, d_c/u_max) of the
    same d_c/u_max and amplitudes (its key holds both; a job's own rows are distinct): its
    *group*. Before a pass the evidence's ``_evaluate`` counts each group's rows over the pass
    and notes the last chunk of each group with two or more (:meth:`plan`); a row is kept only
    in such a group, and dropped after that group's last chunk (:meth:`done`). Blocks with
    amplitudes of their own (measured, not programmed) share no group, so nothing is kept: on
    10^4 sweeps with amplitudes jittered by 1e-6 the store held 2.3 GB when it kept every row
    of the call (review R24a). Where blocks share a grid and a prior, only groups open across
    a chunk's end, and the current chunk's shared rows, are held. Reuse across the two passes
    (a fine node in z bit for bit on another prior's coarse one) is not planned for: such a
    row is evaluated again, with the same bits (a row's arithmetic is its own)."""

    def __init__(self) -> None:
        self.rows: dict[tuple[int, bytes], tuple[np.ndarray, np.ndarray]] = {}
        self.groups: dict[bytes, list[tuple[int, bytes]]] = {}  # row keys held, by group
        self.last: dict[bytes, int] = {}  # a shared group's last chunk in the pass
        self.drops: dict[int, list[bytes]] = {}  # the groups that end at each chunk

    def __len__(self) -> int:
        return len(self.rows)

    def plan(self, groups: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]) -> None:
        """Note the groups of a pass: per number L of amplitudes, the distinct groups (the bytes
        of d_c/u_max and the amplitudes), each row of nodes' group and the numbers of rows of
        each (:func:`numpy.unique`'s inverse and counts), and the chunk that
        evaluates each row."""
        self.last, self.drops = {}, {}
        for group, inv, count, at in groups:
            last = np.zeros(count.size, dtype=int)
            np.maximum.at(last, inv, at)
            for i in np.flatnonzero(count >= 2).tolist():
                k, end = group[i].tobytes(), int(last[i])
                self.last[k] = end
                self.drops.setdefault(end, []).append(k)

    def keep(self, key: tuple[int, bytes], value: tuple[np.ndarray, np.ndarray]) -> None:
        """Hold a row's slopes (``key``: the evidence's ``_slopes``') if another row of its group
        is to come in the pass (its group: the key's bytes after its ``key[0]`` values of θ)."""
        group = key[1][8 * key[0] :]
        if group in self.last:
            # Copies: a view would keep its chunk's whole slope arrays alive (review R24b).
            self.rows[key] = (value[0].copy(), value[1].copy())
            self.groups.setdefault(group, []).append(key)

    def done(self, chunk: int) -> None:
        """Drop the rows of the groups whose last chunk in the pass was ``chunk``."""
        for group in self.drops.pop(chunk, []):
            del self.last[group]
            for key in self.groups.pop(group, []):
                del self.rows[key]
