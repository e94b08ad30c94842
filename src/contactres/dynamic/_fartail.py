"""The tail of the far-field grid, summed by moments instead of node by node (paper 1, Eq. 22).

On the far-field s grid of a call (:mod:`contactres.dynamic._farfield`), the Chebyshev basis
of the kernel table at k_s a is T_f(2w − 1) w (1 − χ(s/ka)) ds with w = (T₁ ka/s)². From
S >= 2 T₁ × (the largest k_s a of the call) on, the hand-over χ is zero (to 1e-17, exactly 0
in :func:`~contactres.dynamic._farfield.far_basis`) and w = β u with β = (T₁ ka/S)² <= 1/4 and
u = (S/s)² in (0, 1]: the basis is a polynomial of degree f + 1 <= n_fit in u, the same
polynomial space for every k a. Interpolated exactly at n_fit + 1 Chebyshev nodes of u, each
integral over the tail, Σ_s basis × (weights of the models), becomes a sum of the Chebyshev
coefficients against the moments Σ_s T_j(2u − 1) ds (weights), computed once per call. On a
curve up to k_l a = 2 the tail is ~85 % of the grid (issue 31): the basis is then built and
summed on the head alone. The same integrals as node by node (to round-off: the interpolation
of a polynomial is exact).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._farfield import FarGrid
from ._table import KernelTable

__all__ = ["FarTail", "far_tail", "head_grid", "tail_coefficients"]


@dataclass(frozen=True, eq=False)
class FarTail:
    """The tail of a far-field grid: the nodes from index ``split`` on.

    Attributes
    ----------
    split : index of the first node of the tail in the grid
    s_first : S, that node (dimensionless s)
    chebyshev : (n_tail, n_fit + 1) T_j(2u − 1) ds at the tail's nodes, u = (S/s)²
    """

    split: int
    s_first: float
    chebyshev: np.ndarray

    def moments(self, values: np.ndarray) -> np.ndarray:
        """Σ_s T_j(2u − 1) ds values[..., s] over the tail, ``values`` given on the whole grid
        (last axis): shape (n_fit + 1, *values.shape[:-1])."""
        tail = values[..., self.split :]
        flat = tail.reshape(-1, tail.shape[-1]) @ self.chebyshev  # (rows, n_fit + 1)
        return flat.T.reshape(self.chebyshev.shape[1], *values.shape[:-1])


def far_tail(table: KernelTable, grid: FarGrid, ka_max: float) -> FarTail | None:
    """The tail of ``grid`` for a call whose largest k_s a is ``ka_max``: its nodes
    s >= 2 T₁ ka_max (module docstring); None if the grid ends before."""
    split = int(np.searchsorted(grid.s, 2 * table.t1 * float(ka_max), side="left"))
    if split >= grid.s.size:
        return None
    first = float(grid.s[split])
    u = (first / grid.s[split:]) ** 2
    cheb = np.polynomial.chebyshev.chebvander(2 * u - 1, table.far_coeffs.shape[1])
    return FarTail(split=split, s_first=first, chebyshev=cheb * grid.ds[split:, None])


def head_grid(grid: FarGrid, tail: FarTail | None) -> FarGrid:
    """The nodes of ``grid`` before its tail (all of them without a tail)."""
    if tail is None:
        return grid
    return FarGrid(grid.s[: tail.split], grid.ds[: tail.split], grid.s_end)


def tail_coefficients(table: KernelTable, ka: np.ndarray, tail: FarTail) -> np.ndarray:
    """The Chebyshev coefficients in u of the basis T_f(2w − 1) w on the tail at the k_s a
    values ``ka``: (na, n_fit, n_fit + 1), so that basis[a, s, f] = Σ_j coef[a, f, j]
    T_j(2u_s − 1) ds_s there. ``ka`` must not exceed the call's largest (a ValueError)."""
    if ka.size and 2 * table.t1 * float(np.max(ka)) > tail.s_first:
        raise ValueError("the far tail was built for smaller k a values")  # internal misuse
    nf = table.far_coeffs.shape[1]
    n = nf + 1
    x = np.cos(np.pi * (np.arange(n) + 0.5) / n)  # Chebyshev nodes of 2u − 1
    w = (table.t1 * ka[:, None] / tail.s_first) ** 2 * (0.5 * (x + 1))[None, :]  # (na, n)
    values = np.polynomial.chebyshev.chebvander(2 * w - 1, nf - 1) * w[..., None]  # (na, n, nf)
    to_coeffs = (2.0 / n) * np.polynomial.chebyshev.chebvander(x, nf)  # (n, nf + 1)
    to_coeffs[:, 0] *= 0.5
    return np.swapaxes(values, 1, 2) @ to_coeffs
