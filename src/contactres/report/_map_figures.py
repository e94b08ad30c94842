"""The figure of an indentation-modulus map: M, the IPF-Z colours, and M over the triangle.

:func:`modulus_map_figure` draws three panels side by side:

(a) the map of the indentation modulus M, GPa, with its colour bar;
(b) the inverse-pole-figure colours of the surface normal (IPF-Z,
    :func:`contactres.polycrystal.ipf_colors`);
(c) the legend that links them: the standard triangle of surface normals coloured by M (same
    colour map), and below it the IPF colour key. A colour of (b) is found in the key; the same
    place of the triangle above gives M. With M a function of the normal alone (paper 1,
    Eqs. 1-4; :mod:`contactres.polycrystal._normal_table`) this reads every pixel.

Object API only (:class:`matplotlib.figure.Figure` with an Agg canvas, constrained layout),
matplotlib imported when the figure is drawn; save it with
:func:`contactres.fileio.save_figure` (atomic, closes the figure).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ContactresInputError
from .figures import LABEL_CHARS

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from matplotlib.image import AxesImage

    from ..polycrystal import TriangleModuli

__all__ = ["modulus_map_figure"]

GPA = 1e-9
UM = 1e6
# Corner label placement (red, green, blue): offset in points and alignment.
CORNER_TEXT = (((-3, -3), "right", "top"), ((3, -3), "left", "top"), ((0, 4), "center", "bottom"))


def _plain(text: str) -> str:
    """A name from the caller as plain text: shortened, ``$`` escaped (no mathtext)."""
    text = " ".join(str(text).split())
    if len(text) > LABEL_CHARS:
        text = text[: LABEL_CHARS - 1] + "…"
    return text.replace("$", r"\$")


def _triangle_panel(ax, tri, image, fontsize: float, **imshow) -> AxesImage:
    """Draw ``image`` (n, n[, 4]) over the triangle's grid, clipped to its outline; label it."""
    from matplotlib.patches import Polygon

    dx = tri.x[0, 1] - tri.x[0, 0]
    dy = tri.y[1, 0] - tri.y[0, 0]
    extent = (-dx / 2, tri.x[0, -1] + dx / 2, -dy / 2, tri.y[-1, 0] + dy / 2)
    art = ax.imshow(image, origin="lower", extent=extent, interpolation="nearest", **imshow)
    outline = Polygon(tri.boundary, closed=True, facecolor="none", edgecolor="k", lw=0.8)
    ax.add_patch(outline)
    art.set_clip_path(outline)
    for (xy, label), (offset, ha, va) in zip(
        zip(tri.corner_xy, tri.corner_labels, strict=True), CORNER_TEXT, strict=True
    ):
        ax.annotate(
            label, xy, xytext=offset, textcoords="offset points", ha=ha, va=va, fontsize=fontsize
        )
    # Room for the corner labels inside the axes (projection coordinates, dimensionless).
    xmax, ymax = tri.boundary.max(axis=0)
    ax.set_xlim(-0.22 * xmax, 1.22 * xmax)
    ax.set_ylim(-0.2 * ymax, 1.2 * ymax)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return art


def modulus_map_figure(
    moduli,
    normals,
    lattice: str,
    modulus_of_normals: Callable[[np.ndarray], np.ndarray] | TriangleModuli,
    *,
    pixel_size: float | None = None,
    material_name: str = "",
    grid_points: int = 81,
    cmap: str = "viridis",
) -> Figure:
    """Three panels: the M map, the IPF-Z colours of the normals, M over the standard triangle.

    Parameters
    ----------
    moduli : array_like, shape (H, W)
        Indentation modulus M per pixel, Pa (NaN: not shown). Row index = y, column = x.
    normals : array_like, shape (H, W, 3)
        The surface normal of each pixel in crystal coordinates (``R[..., 2, :]`` of the surface
        matrices); non-finite or zero rows are not shown.
    lattice : {"cubic", "hexagonal"}
        Laue group m-3m or 6/mmm (the triangle and the IPF key).
    modulus_of_normals : TriangleModuli or callable
        M over the triangle as a job computed it (a
        :class:`~contactres.polycrystal.TriangleModuli`, drawn as it is: ``grid_points`` is then
        its grid), or ``f(n) -> M`` in Pa for unit crystal directions n of shape (P, 3), e.g.
        ``lambda n: indentation_moduli(material, surface_matrices_from_normals(n))`` (exact) or
        ``lambda n: table.modulus(normals=n)`` (a :class:`~contactres.polycrystal.NormalTable`),
        evaluated once on the triangle's grid (:func:`~contactres.polycrystal.triangle_moduli`).
    pixel_size : float, optional
        Square pixel pitch, m: the map axes in µm. Without it they count pixels.
    material_name : str
        Shown in the figure title (plain text).
    grid_points : int
        Grid points per axis of the triangle panels (≥ 2), when ``modulus_of_normals`` is a
        callable.
    cmap : str
        Colour map of M, shared by panels (a) and (c).

    Returns
    -------
    matplotlib.figure.Figure
        Axes in order: (a) map, (b) IPF map, (c) triangle coloured by M, (c) IPF key, then the
        two colour bars (of (a) and (c)), each labelled "M (GPa)". The triangle's colour range
        is the min and max of M over its grid; panel (a) uses the same range, widened to the
        map's values if they fall outside it, so equal colours mean equal M.

    Raises
    ------
    ValueError
        For mismatched shapes, a map without a finite M, an unknown lattice, a bad pixel size,
        or a ``modulus_of_normals`` that does not return one finite value per direction.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    from ..polycrystal import TriangleModuli, ipf_colors, triangle_moduli

    M = np.asarray(moduli, dtype=float)
    n = np.asarray(normals, dtype=float)
    if M.ndim != 2:
        raise ContactresInputError(f"moduli must be a map of shape (H, W), got {M.shape}")
    if n.shape != (*M.shape, 3):
        raise ContactresInputError(
            f"normals must have shape {(*M.shape, 3)} (the map's), got {n.shape}"
        )
    if not np.isfinite(M).any():
        raise ContactresInputError("moduli has no finite value: nothing to draw")
    if isinstance(modulus_of_normals, TriangleModuli):
        legend = modulus_of_normals
        if legend.triangle.lattice != lattice:
            raise ContactresInputError(
                f"the triangle's moduli are of the {legend.triangle.lattice} lattice, the map's "
                f"of {lattice}"
            )
    else:
        legend = triangle_moduli(lattice, modulus_of_normals, grid_points)
    tri, cells, folded = legend.triangle, legend.cells, legend.normals
    if pixel_size is not None:
        pixel_size = float(pixel_size)
        if not (np.isfinite(pixel_size) and pixel_size > 0):
            raise ContactresInputError(
                f"pixel_size must be a positive length in m, got {pixel_size!r}"
            )
    grid = legend.moduli * GPA
    lo, hi = (v * GPA for v in legend.inside_range)  # the colour range: M over the triangle
    tri_norm = Normalize(lo, hi)
    map_norm = Normalize(min(lo, float(np.nanmin(M)) * GPA), max(hi, float(np.nanmax(M)) * GPA))
    # IPF colours of the valid pixels; the others stay transparent.
    ok = np.all(np.isfinite(n), axis=-1) & (np.linalg.norm(np.nan_to_num(n), axis=-1) > 0)
    rgba = np.zeros((*M.shape, 4))
    rgba[ok, :3] = ipf_colors(n[ok], lattice)
    rgba[ok, 3] = 1.0

    fig = Figure(figsize=(11.0, 4.0), layout="constrained")
    FigureCanvasAgg(fig)
    gs = fig.add_gridspec(2, 3, width_ratios=(1.0, 1.0, 0.85), height_ratios=(1.6, 1.0))
    ax_m, ax_ipf = fig.add_subplot(gs[:, 0]), fig.add_subplot(gs[:, 1])
    ax_tri, ax_key = fig.add_subplot(gs[0, 2]), fig.add_subplot(gs[1, 2])

    H, W = M.shape
    if pixel_size is None:
        extent, unit = (-0.5, W - 0.5, H - 0.5, -0.5), "pixel"
    else:
        size = pixel_size * UM
        extent, unit = (0.0, W * size, H * size, 0.0), "µm"
    im = ax_m.imshow(M * GPA, cmap=cmap, norm=map_norm, extent=extent, interpolation="nearest")
    fig.colorbar(im, ax=ax_m, label="M (GPa)", shrink=0.8)
    ax_m.set_title("(a) indentation modulus M", fontsize=9)
    ax_ipf.imshow(rgba, extent=extent, interpolation="nearest")
    ax_ipf.set_title("(b) IPF-Z: crystal direction of the normal", fontsize=9)
    for ax in (ax_m, ax_ipf):
        ax.set_xlabel(f"x ({unit})")
        ax.set_ylabel(f"y ({unit})")

    art = _triangle_panel(ax_tri, tri, np.ma.masked_invalid(grid), 7, cmap=cmap, norm=tri_norm)
    fig.colorbar(art, ax=ax_tri, label="M (GPa)", shrink=0.9)
    ax_tri.set_title("(c) M over the standard triangle", fontsize=9)
    key = np.zeros((*tri.inside.shape, 4))
    key[cells, :3] = ipf_colors(folded, lattice)
    key[cells, 3] = 1.0
    _triangle_panel(ax_key, tri, key, 6)
    # The key is contactres' corner-weight key, not the TSL key of OIM or orix: the figure says so.
    ax_key.set_title("IPF key of (b): corner weights, not TSL", fontsize=8)

    name = f" of {_plain(material_name)}" if str(material_name).strip() else ""
    fig.suptitle(f"Indentation modulus map{name} ({lattice})", fontsize=10)
    return fig
