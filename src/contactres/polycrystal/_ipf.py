"""Inverse-pole-figure (IPF) colours of crystal directions and the standard triangle.

The IPF colour of a crystal direction (here usually the surface normal, IPF-Z = ND) is a colour
of its equivalent in the fundamental triangle of the Laue group
(:func:`~contactres.polycrystal.reduce_normals`), with the usual corner colours:

cubic (m-3m)
    [001] red, [101] green, [111] blue. The triangle of :func:`reduce_normals` is
    0 ≤ n_x ≤ n_y ≤ n_z, so its green corner is written [011] there: the same direction class
    <110>, shown as [101] as on the standard key.
hexagonal (6/mmm)
    [0001] red, [2-1-10] green, [10-10] blue. In the crystal frame of
    :meth:`Material.hexagonal` (a1 along x) [2-1-10] = 3 a1 is the azimuth φ = 0 of the triangle
    and [10-10] = 2 a1 + a2 the azimuth φ = 30°.

Construction: contactres' own *corner-weight key* (named so; it is not the "TSL" key of orix
and MTEX). For a direction p in the triangle with corners c_i and great-circle edges e_i (e_i
opposite c_i, unit inward normal m_i), the weight of corner i is the angular distance of p from
e_i over that of c_i, ``w_i = arcsin(p · m_i) / arcsin(c_i · m_i)``: 1 at c_i, 0 on the
opposite edge, continuous. The colour is ``w / max(w)``, so the largest channel is 1 (bright
colours, white where the three weights are equal).

Other keys: orix's ``IPFColorKeyTSL`` (after MTEX's TSL key; the polar coordinates about the
triangle's centre of Nolze and Hielscher 2016, section 2.4, mapped through HSL) and MTEX's
default key are different constructions. The corner colours agree (orix's corners lie within
0.01 of pure red, green and blue), the edges between them share their hue order, but inside the
triangle the channels differ by up to about 0.3 (cubic) and 0.5 (hexagonal) against orix 0.15
(tests/polycrystal/test_ebsd_orix.py measures it): an IPF map coloured here is read with the key
drawn here (:func:`ipf_triangle`), not with orix's or MTEX's key.

:func:`ipf_triangle` gives the triangle for plotting in the stereographic projection from the
south pole, ``(X, Y) = (u, v)/(1 + w)`` with (u, v, w) a direction in the plotting frame: for
cubic (u, v, w) = (n_y, n_x, n_z), so [001] is at the origin, [101] on the X axis and [111]
above; for hexagonal (n_x, n_y, n_z), [0001] at the origin, [2-1-10] on the X axis.

References
----------
G. Nolze and R. Hielscher, "Orientations - perfectly colored", J. Appl. Cryst. 49, 1786-1802
(2016), doi:10.1107/S1600576716012942 (a discussion of IPF keys and their corner colours).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._summary import Summarised, values
from ..errors import ContactresInputError
from ._normal_table import reduce_normals, zone_bounds

__all__ = [
    "IPF_CORNER_LABELS",
    "IPFTriangle",
    "TriangleModuli",
    "ipf_colors",
    "ipf_triangle",
    "triangle_geometry",
    "triangle_moduli",
]

#: Corner labels (red, green, blue) as matplotlib mathtext, per lattice.
IPF_CORNER_LABELS: dict[str, tuple[str, str, str]] = {
    "cubic": ("[001]", "[101]", "[111]"),
    "hexagonal": ("[0001]", r"$[2\bar{1}\bar{1}0]$", r"$[10\bar{1}0]$"),
}

_S3, _S2 = 1.0 / math.sqrt(3.0), 1.0 / math.sqrt(2.0)


def triangle_geometry(lattice: str) -> tuple[np.ndarray, np.ndarray]:
    """Corners (red, green, blue) and the inward unit normals of the opposite edges, (3, 3) each.

    In the crystal coordinates of :func:`reduce_normals`' triangle (rows = corners/edges).
    """
    zone_bounds(lattice)  # ValueError naming the known lattices
    if lattice == "cubic":
        # 0 ≤ x ≤ y ≤ z: edges y = z (opposite [001]), x = y (opposite [011]), x = 0 ([111]).
        corners = np.array([[0.0, 0.0, 1.0], [0.0, _S2, _S2], [_S3, _S3, _S3]])
        inward = np.array([[0.0, -_S2, _S2], [-_S2, _S2, 0.0], [1.0, 0.0, 0.0]])
    else:
        # z ≥ 0, azimuth in [0, 30°]: edges z = 0, azimuth 30° (opposite a1) and azimuth 0.
        c30, s30 = math.cos(math.pi / 6), math.sin(math.pi / 6)
        corners = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [c30, s30, 0.0]])
        inward = np.array([[0.0, 0.0, 1.0], [s30, -c30, 0.0], [0.0, 1.0, 0.0]])
    return corners, inward


def ipf_colors(normals, lattice: str) -> np.ndarray:
    """RGB inverse-pole-figure colours of crystal directions, in [0, 1].

    Parameters
    ----------
    normals : array_like, shape (..., 3)
        Crystal directions (e.g. the surface normal ``R[..., 2, :]`` for IPF-Z); any length,
        any symmetric equivalent.
    lattice : {"cubic", "hexagonal"}
        Laue group m-3m or 6/mmm.

    Returns
    -------
    ndarray, shape (..., 3)
        (r, g, b) of the corner-weight key (module docstring): largest channel 1; pure red,
        green, blue at the three corners; equal for all symmetric equivalents.

    Raises
    ------
    ValueError
        As :func:`reduce_normals`: wrong shape, non-finite or zero vectors, unknown lattice.

    Examples
    --------
    >>> import numpy as np
    >>> np.round(ipf_colors([[0, 0, -2], [1, 1, 0], [1, -1, 1]], "cubic"), 12) + 0.0
    array([[1., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]])
    """
    folded, _ = reduce_normals(normals, lattice)
    corners, inward = triangle_geometry(lattice)
    # Angular distance from each edge (clipped: round-off just outside the triangle).
    dist = np.arcsin(np.clip(folded @ inward.T, 0.0, 1.0))
    w = dist / np.arcsin(np.sum(corners * inward, axis=-1))
    return w / np.max(w, axis=-1, keepdims=True)


def _to_plane(n: np.ndarray, lattice: str) -> np.ndarray:
    """Stereographic (X, Y) of triangle directions (..., 3), plotting frame of the module."""
    u, v = (n[..., 1], n[..., 0]) if lattice == "cubic" else (n[..., 0], n[..., 1])
    return np.stack([u, v], axis=-1) / (1.0 + n[..., 2:3])


def _from_plane(X: np.ndarray, Y: np.ndarray, lattice: str) -> np.ndarray:
    """Unit crystal directions (..., 3) of stereographic points (inverse of :func:`_to_plane`)."""
    r2 = X**2 + Y**2
    u, v, w = 2.0 * X / (1.0 + r2), 2.0 * Y / (1.0 + r2), (1.0 - r2) / (1.0 + r2)
    return np.stack([v, u, w] if lattice == "cubic" else [u, v, w], axis=-1)


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the grid.
@dataclass(frozen=True, eq=False, repr=False)
class IPFTriangle(Summarised):
    """The standard triangle in the stereographic projection, for plotting (:func:`ipf_triangle`).

    Attributes
    ----------
    lattice : str
        "cubic" or "hexagonal".
    boundary : ndarray, shape (B, 2)
        Closed outline (X, Y) (first point repeated last), dimensionless projection coordinates.
    x, y : ndarray, shape (n, n)
        A regular grid over the triangle's bounding box (``x[i, j]`` varies along j).
    normals : ndarray, shape (n, n, 3)
        Unit crystal directions of all grid points (inverse projection); those outside the
        triangle are other directions, equivalent to some inside it (fold them with
        :func:`reduce_normals`: useful to fill the cells cut by the outline).
    inside : ndarray of bool, shape (n, n)
        Grid points in the (closed) triangle.
    corners : ndarray, shape (3, 3)
        The corner directions red, green, blue (crystal coordinates of :func:`reduce_normals`).
    corner_xy : ndarray, shape (3, 2)
        Their projections.
    corner_labels : tuple of str
        Their Miller(-Bravais) labels (:data:`IPF_CORNER_LABELS`, mathtext for hexagonal).
    """

    lattice: str
    boundary: np.ndarray
    x: np.ndarray
    y: np.ndarray
    normals: np.ndarray
    inside: np.ndarray
    corners: np.ndarray
    corner_xy: np.ndarray
    corner_labels: tuple[str, str, str]

    def _facts(self) -> list[tuple[str, str]]:
        """The lattice, the corners' labels and the grid."""
        n_in = int(np.count_nonzero(self.inside))
        return [
            ("", self.lattice),
            ("corners", ", ".join(self.corner_labels)),
            ("grid", f"{self.x.shape[0]} x {self.x.shape[1]} ({n_in} points inside)"),
        ]

    @property
    def points(self) -> np.ndarray:
        """(X, Y) of the grid points inside the triangle, shape (P, 2)."""
        return np.stack([self.x[self.inside], self.y[self.inside]], axis=-1)

    @property
    def inside_normals(self) -> np.ndarray:
        """Unit directions of the grid points inside the triangle, shape (P, 3)."""
        return self.normals[self.inside]


def ipf_triangle(lattice: str, n: int = 101, boundary_points: int = 60) -> IPFTriangle:
    """The fundamental triangle for plotting: outline and a grid, stereographic projection.

    Parameters
    ----------
    lattice : {"cubic", "hexagonal"}
        Laue group m-3m or 6/mmm.
    n : int
        Grid points per axis over the bounding box (≥ 2).
    boundary_points : int
        Points per edge of the outline (≥ 2); the edges are great-circle arcs.

    Returns
    -------
    IPFTriangle

    Examples
    --------
    >>> t = ipf_triangle("cubic", n=11)
    >>> t.corner_labels, t.x.shape, bool(t.inside.any())
    (('[001]', '[101]', '[111]'), (11, 11), True)
    """
    corners, inward = triangle_geometry(lattice)
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 2:
        raise ContactresInputError(f"n must be an integer >= 2 (grid points per axis), got {n!r}")
    if (
        isinstance(boundary_points, bool)
        or not isinstance(boundary_points, int | np.integer)
        or boundary_points < 2
    ):
        raise ContactresInputError(
            f"boundary_points must be an integer >= 2, got {boundary_points!r}"
        )
    # Edges red-green, green-blue, blue-red as slerps between the corners.
    t = np.linspace(0.0, 1.0, boundary_points)[:, None]
    arcs = []
    for a, b in ((0, 1), (1, 2), (2, 0)):  # three edges, not a loop over points
        omega = math.acos(float(np.clip(corners[a] @ corners[b], -1.0, 1.0)))
        arc = (np.sin((1 - t) * omega) * corners[a] + np.sin(t * omega) * corners[b]) / math.sin(
            omega
        )
        arcs.append(arc[:-1])
    outline = np.concatenate([*arcs, corners[:1]])
    boundary = _to_plane(outline, lattice)
    # The grid: inverse projection of a regular grid over the outline's bounding box.
    xs = np.linspace(0.0, float(boundary[:, 0].max()), int(n))
    ys = np.linspace(0.0, float(boundary[:, 1].max()), int(n))
    X, Y = np.meshgrid(xs, ys)
    d = _from_plane(X, Y, lattice)
    inside = np.all(d @ inward.T >= -1e-12, axis=-1)
    return IPFTriangle(
        lattice,
        boundary,
        X,
        Y,
        d,
        inside,
        corners,
        _to_plane(corners, lattice),
        IPF_CORNER_LABELS[lattice],
    )


def _dilated(mask: np.ndarray) -> np.ndarray:
    """``mask`` grown by one cell in the 8 directions (array shifts, no loop over cells)."""
    out = mask.copy()
    out[1:] |= mask[:-1]
    out[:-1] |= mask[1:]
    grown = out.copy()
    out[:, 1:] |= grown[:, :-1]
    out[:, :-1] |= grown[:, 1:]
    return out


# repr=False: the summary (Summarised, _facts) replaces the numpy reprs of the grid.
@dataclass(frozen=True, repr=False)
class TriangleModuli(Summarised):
    """A modulus over the grid of the standard triangle: the legend of a modulus map.

    Attributes
    ----------
    triangle : IPFTriangle
        The triangle and its grid (:func:`ipf_triangle`).
    cells : ndarray of bool, shape (n, n)
        The grid points where the modulus was evaluated: those inside the triangle and one
        cell beyond its outline (a figure draws the cells cut by the outline, then clips them).
    normals : ndarray, shape (P, 3)
        The unit crystal directions of the ``cells``, folded into the triangle
        (:func:`reduce_normals`; beyond the outline they are the equivalents inside it).
    moduli : ndarray, shape (n, n)
        The modulus at each grid point, Pa; NaN outside ``cells``.
    """

    triangle: IPFTriangle
    cells: np.ndarray
    normals: np.ndarray
    moduli: np.ndarray

    def _facts(self) -> list[tuple[str, str]]:
        """The lattice, the grid and the modulus over the triangle itself, GPa."""
        return [
            ("", self.triangle.lattice),
            ("grid", f"{self.moduli.shape[0]} x {self.moduli.shape[1]}"),
            ("M", values(self.moduli[self.triangle.inside], "GPa", 1e9)),
        ]

    @property
    def inside_range(self) -> tuple[float, float]:
        """(min, max) of the modulus over the triangle itself (not the cells beyond), Pa."""
        inner = self.moduli[self.triangle.inside]
        return float(inner.min()), float(inner.max())


def triangle_moduli(
    lattice: str, modulus_of_normals: Callable[[np.ndarray], np.ndarray], n: int = 81
) -> TriangleModuli:
    """Evaluate a modulus of the surface normal over the standard triangle's grid.

    Parameters
    ----------
    lattice : {"cubic", "hexagonal"}
        Laue group m-3m or 6/mmm.
    modulus_of_normals : callable
        ``f(normals) -> M`` in Pa for unit crystal directions of shape (P, 3), e.g.
        ``lambda v: indentation_moduli(material, surface_matrices_from_normals(v))``
        (:func:`indentation_moduli`, paper 1, Eqs. 1-4). Called once, on every cell at once.
    n : int
        Grid points per axis (≥ 2), as :func:`ipf_triangle`.

    Returns
    -------
    TriangleModuli

    Raises
    ------
    ContactresInputError
        For an unknown lattice, a bad ``n``, or a ``modulus_of_normals`` that does not return
        one finite value per direction.

    Examples
    --------
    The modulus of a direction-independent function is that constant everywhere:

    >>> import numpy as np
    >>> t = triangle_moduli("cubic", lambda v: np.full(len(v), 1e11), n=11)
    >>> t.inside_range
    (100000000000.0, 100000000000.0)
    """
    tri = ipf_triangle(lattice, n)
    cells = _dilated(tri.inside)
    folded, _ = reduce_normals(tri.normals[cells], lattice)
    values = np.asarray(modulus_of_normals(folded), dtype=float)
    if values.shape != (folded.shape[0],) or not np.all(np.isfinite(values)):
        raise ContactresInputError(
            f"modulus_of_normals must return one finite M (Pa) per direction: shape "
            f"({folded.shape[0]},), got {values.shape}"
        )
    grid = np.full(tri.inside.shape, np.nan)
    grid[cells] = values
    return TriangleModuli(triangle=tri, cells=cells, normals=folded, moduli=grid)
