"""Synthetic polycrystals: Voronoi grains with random (uniform) orientations, seeded.

A test and benchmark map with a continuum of orientations (issue 16): ``n_grains`` seed points
uniform in the map, each pixel belongs to the grain of the nearest seed point (a Voronoi
tessellation, Euclidean distance between pixel centres in m, :class:`scipy.spatial.cKDTree`),
each grain has an orientation drawn uniformly on SO(3) (:func:`.random_orientations`). Everything
follows from ``seed``: the same seed gives the same map bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..errors import ContactresInputError
from ._maps import MAX_MAP_PIXELS, OrientationMap, check_map_size
from ._orientations import euler_from_surface_matrices, random_orientations

__all__ = ["SyntheticPolycrystal", "synthetic_polycrystal"]

#: Rows of pixels labelled per KD-tree query (bounds the memory of the pixel-centre array).
_ROWS_PER_QUERY = 256


@dataclass(frozen=True, eq=False, kw_only=True, repr=False)  # the compact repr of a map
class SyntheticPolycrystal(OrientationMap):
    """An :class:`~contactres.polycrystal.OrientationMap` with its grains.

    Adds ``grain_euler`` (G, 3), the Bunge angles of grain g in radians (φ1, φ2 in [0, 2π),
    Φ in [0, π]), and ``seed_points`` (G, 2), the Voronoi seeds (x, y) in m. ``labels[i, j]``
    is the grain of pixel (i, j) and ``euler[i, j] == grain_euler[labels[i, j]]``; ``phase`` is
    1 and ``confidence`` 1 everywhere.
    """

    grain_euler: np.ndarray
    seed_points: np.ndarray

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "grain_euler", np.asarray(self.grain_euler, dtype=float))
        object.__setattr__(self, "seed_points", np.asarray(self.seed_points, dtype=float))

    @property
    def n_grains(self) -> int:
        """Number of grains G."""
        return int(self.grain_euler.shape[0])


def synthetic_polycrystal(
    shape: tuple[int, int],
    n_grains: int,
    seed: int,
    pixel_size: float = 1e-6,
    *,
    max_pixels: int = MAX_MAP_PIXELS,
) -> SyntheticPolycrystal:
    """A seeded Voronoi polycrystal with uniformly random grain orientations.

    Parameters
    ----------
    shape : (int, int)
        (H, W): rows (y) and columns (x) of the map.
    n_grains : int
        Number of grains G (Voronoi seeds), 1 ≤ G ≤ H·W. A grain may end up with no pixel.
    seed : int
        Seed of :func:`numpy.random.default_rng`: seed points first, orientations second.
    pixel_size : float
        Square pixel pitch, m (default 1 µm).
    max_pixels : int
        Keyword only: the largest H·W accepted (default
        :data:`~contactres.polycrystal._maps.MAX_MAP_PIXELS`), checked before allocating.

    Returns
    -------
    SyntheticPolycrystal
        ``labels`` (H, W) int in [0, G), ``grain_euler`` (G, 3) Bunge radians, ``euler``
        (H, W, 3) = ``grain_euler[labels]``, ``step_x = step_y = pixel_size``.

    Examples
    --------
    >>> m = synthetic_polycrystal((40, 50), n_grains=6, seed=1)
    >>> m.euler.shape, m.grain_euler.shape, sorted(set(m.labels.ravel())) == list(range(6))
    ((40, 50, 3), (6, 3), True)
    """
    try:
        H, W = (int(n) for n in shape)
    except (TypeError, ValueError) as exc:
        raise ContactresInputError(
            f"shape must be two positive integers (H, W), got {shape!r}"
        ) from exc
    if H < 1 or W < 1:
        raise ContactresInputError(f"shape must be two positive integers (H, W), got {shape!r}")
    check_map_size((H, W), "synthetic map", max_pixels)
    if isinstance(n_grains, bool) or not isinstance(n_grains, int | np.integer):
        raise ContactresInputError(f"n_grains must be an integer, got {n_grains!r}")
    if not 1 <= n_grains <= H * W:
        raise ContactresInputError(f"n_grains must lie in [1, {H * W}] (pixels), got {n_grains}")
    pixel_size = float(pixel_size)
    if not (np.isfinite(pixel_size) and pixel_size > 0):
        raise ContactresInputError(f"pixel_size must be a positive length in m, got {pixel_size!r}")
    rng = np.random.default_rng(seed)
    seeds = rng.uniform(size=(int(n_grains), 2)) * np.array([W, H]) - 0.5  # pixel units (x, y)
    grain_R = random_orientations(int(n_grains), rng)
    grain_euler = euler_from_surface_matrices(grain_R, degrees=False)
    tree = cKDTree(seeds)
    labels = np.empty((H, W), dtype=np.int64)
    cols = np.arange(W, dtype=float)
    for r0 in range(0, H, _ROWS_PER_QUERY):  # a loop over blocks of rows, not over pixels
        rows = np.arange(r0, min(r0 + _ROWS_PER_QUERY, H), dtype=float)
        yy, xx = np.meshgrid(rows, cols, indexing="ij")
        _, idx = tree.query(np.stack([xx.ravel(), yy.ravel()], axis=-1))
        labels[r0 : r0 + rows.size] = idx.reshape(rows.size, W)
    return SyntheticPolycrystal(
        euler=grain_euler[labels],
        step_x=pixel_size,
        step_y=pixel_size,
        phase=np.ones((H, W), dtype=np.int64),
        confidence=np.ones((H, W)),
        confidence_name="none (synthetic)",
        labels=labels,
        source=f"synthetic Voronoi polycrystal, {n_grains} grains, seed {seed}",
        grain_euler=grain_euler,
        seed_points=seeds * pixel_size,
    )
