"""Oxford Instruments' HDF5 EBSD files (``.h5oina``, AZtec 4.2 and later) as orientation maps.

The layout, as the public specification states it (Oxford Instruments NanoAnalysis, "HDF5
File Specification", github.com/oinanoanalysis/h5oina, ``H5OINAFile.md``): an acquisition is
the group ``/<slice>`` (``1`` for a single map) with the technique group ``EBSD``, which holds
``Data`` and ``Header``:

- ``1/EBSD/Data/Euler`` (size, 3): Bunge angles in **radians** (every angle of the format is in
  radians), the orientation of the crystal (CS2) to the sample surface (CS1);
- ``1/EBSD/Data/Phase`` (size,): the phase index, **0 = not indexed**;
- ``1/EBSD/Data/X``, ``Y`` (size,), optional: pixel positions in µm (origin top left);
- ``1/EBSD/Data/Mean Angular Deviation`` (size,), optional: MAD in **radians**;
- ``1/EBSD/Header/X Cells``, ``Y Cells`` (pixels), ``X Step``, ``Y Step`` (µm);
- ``1/EBSD/Header/Phases/<n>/Phase Name``, ``Lattice Dimensions`` (Å), ``Lattice Angles``
  (radians), ``Laue Group``, ``Space Group`` (phase indices from 1).

Pixels outside an irregular acquisition area hold NaN; they are read as not indexed (phase 0,
angles 0). Without X and Y the rows are taken in the order the specification implies for a map
(x fastest, row by row); with them, the points are placed on the square grid by position, as
the text exports (:mod:`._ebsd`). MAD is converted to degrees, so that the map is a MAD map
like a ``.ctf`` one (``confidence_name = "MAD (degrees)"``) and
:func:`~contactres.polycrystal.indexed_pixels` applies the same rules (phase 0 out;
``max_mad`` in degrees). Without MAD the confidence is 0 ("no deviation recorded").

h5py comes with the optional extras ``maps`` and ``afm`` (``pip install 'contactres[maps]'``);
it is imported when a file is read. Not read: several slices (particle analyses), line scans,
patterns; the Euler angles are taken in the map's sample frame as :mod:`._ebsd` states it for
the .ctf (the specimen orientation CS1 -> CS0 is not applied).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import ContactresInputError, MissingExtraError
from ._maps import OrientationMap, check_map_size

__all__ = ["read_h5oina"]


def _h5py():
    try:
        import h5py
    except ImportError as exc:  # pragma: no cover - the test environment has the extra
        raise MissingExtraError(
            "reading .h5oina files needs h5py: pip install 'contactres[maps]'"
        ) from exc
    return h5py


def _dataset(path: Path, group, name: str, *, required: bool = True):
    """The dataset ``name`` of ``group`` as a numpy array (None when optional and absent)."""
    if name not in group:
        if not required:
            return None
        raise ContactresInputError(
            f"{path.name}: no dataset {group.name}/{name}: not an .h5oina EBSD map (see the "
            "Oxford Instruments H5OINA specification)"
        )
    return np.asarray(group[name][()])


def _scalar(path: Path, header, name: str) -> float:
    v = np.asarray(_dataset(path, header, name), dtype=float).ravel()
    if v.size != 1 or not (np.isfinite(v[0]) and v[0] > 0):
        raise ContactresInputError(
            f"{path.name}: {header.name}/{name} = {v.tolist()} must be one positive number"
        )
    return float(v[0])


def read_h5oina(path: str | os.PathLike, slice_name: str = "1") -> OrientationMap:
    """Read the EBSD map of an Oxford ``.h5oina`` file as an :class:`OrientationMap`.

    Parameters
    ----------
    path : str or PathLike
        The ``.h5oina`` file.
    slice_name : str
        The acquisition (slice) group, ``"1"`` for a single map.

    Returns
    -------
    OrientationMap
        Euler angles in radians as stored, steps in m (header X Step, Y Step in µm),
        ``phase`` = the Phase dataset (0 = not indexed), ``confidence`` = MAD in degrees
        (``confidence_name`` "MAD (degrees)"); ``source`` the file name.

    Raises
    ------
    ContactresInputError
        Not an HDF5 file; a missing group or dataset; datasets of the wrong size; steps that
        are not positive; points not filling the square grid.
    MissingExtraError
        h5py is not installed (the extras ``maps`` and ``afm``).
    """
    h5py = _h5py()
    path = Path(path)
    if not path.is_file():
        raise ContactresInputError(f"{path}: no such file")
    if not h5py.is_hdf5(path):
        raise ContactresInputError(f"{path.name}: not an HDF5 file (an .h5oina file is HDF5)")
    with h5py.File(path, "r") as f:
        where = f"{slice_name}/EBSD"
        if where not in f or "Data" not in f[where] or "Header" not in f[where]:
            raise ContactresInputError(
                f"{path.name}: no group /{where}/Data and /{where}/Header: not an .h5oina EBSD map"
            )
        data, header = f[where]["Data"], f[where]["Header"]
        W = int(_scalar(path, header, "X Cells"))
        H = int(_scalar(path, header, "Y Cells"))
        steps = (_scalar(path, header, "X Step"), _scalar(path, header, "Y Step"))
        check_map_size((H, W), f"{path.name}: the header declares a grid of")
        euler = np.asarray(_dataset(path, data, "Euler"), dtype=float).reshape(-1, 3)
        phase = np.asarray(_dataset(path, data, "Phase"), dtype=float).ravel()
        x, y = (_dataset(path, data, k, required=False) for k in ("X", "Y"))
        mad = _dataset(path, data, "Mean Angular Deviation", required=False)
    n = H * W
    columns = {"Euler": euler, "Phase": phase, "X": x, "Y": y, "Mean Angular Deviation": mad}
    for name, v in columns.items():
        if v is not None and np.asarray(v).shape[0] != n:
            raise ContactresInputError(
                f"{path.name}: {slice_name}/EBSD/Data/{name} holds {np.asarray(v).shape[0]} rows, "
                f"the header declares {H} x {W} = {n} pixels"
            )
    outside = ~np.isfinite(euler).all(axis=1) | ~np.isfinite(phase)
    euler[outside] = 0.0
    phase = np.where(outside, 0, phase).astype(np.int64)
    conf = np.zeros(n) if mad is None else np.degrees(np.asarray(mad, dtype=float).ravel())
    conf[~np.isfinite(conf)] = 0.0
    if x is None or y is None:
        i, j = np.divmod(np.arange(n), W)
    else:
        i, j = _place(path, np.asarray(x, float).ravel(), np.asarray(y, float).ravel(), steps)
        if i.max() >= H or j.max() >= W:
            raise ContactresInputError(
                f"{path.name}: the X/Y positions span {i.max() + 1} x {j.max() + 1} pixels, the "
                f"header declares {H} x {W}"
            )
    grid = np.zeros((H, W, 3))
    grid[i, j] = euler
    ph = np.zeros((H, W), dtype=np.int64)
    ph[i, j] = phase
    cf = np.zeros((H, W))
    cf[i, j] = conf
    return OrientationMap(
        euler=grid, step_x=steps[0] * 1e-6, step_y=steps[1] * 1e-6, phase=ph, confidence=cf,
        confidence_name="MAD (degrees)", source=path.name,
    )  # fmt: skip


def _place(path: Path, x: np.ndarray, y: np.ndarray, steps) -> tuple[np.ndarray, np.ndarray]:
    """Row and column of each point from its position (µm), each grid position exactly once."""
    ok = np.isfinite(x) & np.isfinite(y)
    if not ok.all():
        raise ContactresInputError(
            f"{path.name}: X/Y of {int((~ok).sum())} points are not finite; the positions must "
            "span the grid"
        )
    fx, fy = (x - x.min()) / steps[0], (y - y.min()) / steps[1]
    j, i = np.rint(fx).astype(np.int64), np.rint(fy).astype(np.int64)
    # float32 positions: a few 1e-7 µm of round-off; a point off the grid is a wrong step.
    if np.max(np.maximum(np.abs(fx - j), np.abs(fy - i)), initial=0.0) > 1e-2:
        raise ContactresInputError(
            f"{path.name}: points not on the square grid of step ({steps[0]:g}, {steps[1]:g}) µm"
        )
    if np.unique(i * (int(j.max()) + 1) + j).size != len(i):
        raise ContactresInputError(f"{path.name}: a grid position is given twice in X/Y")
    return i, j
