"""Job ``maps_synthetic``: a seeded synthetic polycrystal and its noisy 'measured' contact
stiffness map (the test input of ``maps_fit``).

Inputs: none (pass None). Settings: the crystal, the tip and load, the map's size, grains,
seed, noise and pixel size. The map is :func:`contactres.jobs.maps.synthetic_map` (Voronoi
grains, k* per grain from the exact indentation modulus M, paper 1, Eq. 4, and Hertz). Its tip
and load pass the check of ``maps predict`` first: a Hertz contact wider than half the tip
radius on the softest orientation is refused (most likely a unit slip), one wider than a tenth
is made with a warning (``warnings``, and the store's ``hertz_flag`` attribute).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    from ..materials import Material
    from .maps import TipLoad

__all__ = ["Result", "Settings", "run"]


@dataclass(frozen=True)
class Settings:
    """The synthetic map.

    Parameters
    ----------
    material : Material
        The crystal, cube (or crystal) axes.
    lattice : str
        "cubic" or "hexagonal".
    tipload : TipLoad
        Tip radius (m), force (N) and tip modulus (Pa; inf: rigid).
    shape : (int, int)
        Rows and columns of pixels.
    n_grains, seed : int
        Grains, and the seed of the grains and the noise.
    noise : float
        Relative standard deviation of the noise on k*, in [0, 0.5).
    pixel_size : float
        Pixel size, m.
    """

    material: Material
    lattice: str
    tipload: TipLoad
    shape: tuple[int, int] = (64, 64)
    n_grains: int = 20
    seed: int = 0
    noise: float = 0.02
    pixel_size: float = 1e-6


@dataclass(frozen=True)
class Result(JobResult):
    """``dataset``: the map (Bunge angles, grain labels, k_star_N_per_m; the truth as
    attributes), an :mod:`xarray` Dataset written as a Zarr store; ``warnings``: the Hertz
    flag, if any."""

    NOT_VALUES = ("dataset", "warnings")

    dataset: object
    warnings: tuple[str, ...] = ()


@one_blas_thread()
def run(inputs: None, settings: Settings, progress: Progress | None = None) -> Result:
    """The synthetic map of ``settings`` (see the module docstring)."""
    from .maps import check_tip_load, synthetic_map

    s = settings
    # The map's k* are Hertz's: a contact Hertz does not describe is refused before any work,
    # as maps predict refuses it (issue 27's closing campaign: 1 N on a 20 nm tip, a/R = 24,
    # gave k* of 1.3e5 N/m without a word).
    hertz_flag = check_tip_load(s.material, s.tipload)
    say(progress, f"{s.shape[0]}x{s.shape[1]} pixels, {s.n_grains} grains")
    ds = synthetic_map(
        s.material,
        s.lattice,
        s.tipload,
        shape=s.shape,
        n_grains=s.n_grains,
        seed=s.seed,
        noise=s.noise,
        pixel_size=s.pixel_size,
    )
    if hertz_flag:  # recorded with the map, as maps predict records it
        ds.attrs["hertz_flag"] = hertz_flag
    return Result(dataset=ds, warnings=(hertz_flag,) if hertz_flag else ())
