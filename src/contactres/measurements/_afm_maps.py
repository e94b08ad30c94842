"""Maps of contact-resonance frequency and Q from instrument files: band-excitation SHO fits
(BGlib, HDF5), plain grids (xarray NetCDF/Zarr), the frequency layer of a DART image, and the
check every frequency map passes before it is inverted.

Band excitation (BE) records the response over a band of frequencies at every pixel; BGlib
(ORNL, formerly pycroscopy) fits a simple harmonic oscillator (SHO) to each spectrum and stores
the parameters as an HDF5 compound dataset in the Universal Spectroscopy and Imaging Data
(USID) layout: a group ``<main>-SHO_Fit_<nnn>`` beside the raw data holds ``Guess`` and ``Fit``,
of shape (positions, steps), with the fields ``Amplitude [V]``, ``Frequency [Hz]``,
``Quality Factor``, ``Phase [rad]`` and ``R2 Criterion``; the ancillary dataset
``Position_Indices`` (positions × dimensions, its ``labels`` attribute naming them ``X``, ``Y``)
places each row on the grid; the measurement group's attributes ``grid_scan_width_[m]``,
``grid_scan_height_[m]``, ``grid_num_cols`` and ``grid_num_rows`` give the scan's size.
:func:`read_be_sho` reads them with ``h5py`` alone (no sidpy/pyUSID).

A plain grid (:func:`read_resonance_grid`) is an xarray Dataset of variables ``frequency_Hz``
and ``q_factor`` (or ``Q``) over dimensions ``y``, ``x``, in NetCDF or Zarr (the optional
extra ``maps``).

Conventions
-----------
Every map here is (rows, columns) = (y, x): ``frequency_Hz[i, j]`` is the pixel at
(x, y) = (j·dx, i·dy), as the polycrystal maps are laid out (an Igor image, whose first index
runs along x, is transposed by :func:`dart_frequency_Hz`). A pixel not measured is NaN.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._summary import Summarised, values
from ..errors import ContactresInputError, MissingExtraError
from ._ibw import IgorWave

__all__ = [
    "SHO_FIELDS",
    "ResonanceMaps",
    "check_frequency_map",
    "dart_frequency_Hz",
    "read_be_sho",
    "read_resonance_grid",
]

#: The fields of BGlib's SHO compound dtype -> the attribute of :class:`ResonanceMaps`.
SHO_FIELDS = {
    "Frequency [Hz]": "frequency_Hz",
    "Quality Factor": "q_factor",
    "Amplitude [V]": "amplitude",
    "Phase [rad]": "phase_rad",
    "R2 Criterion": "r2",
}

# Lengths as the position units of USID files and grid coordinates spell them, in m.
_LENGTHS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "μm": 1e-6, "nm": 1e-9}


# repr=False: the summary (Summarised, _facts) replaces the numpy repr of the maps.
@dataclass(frozen=True, eq=False, repr=False)
class ResonanceMaps(Summarised):
    """Contact-resonance frequency and Q per pixel, with what else the file gives.

    Attributes
    ----------
    frequency_Hz : ndarray (y, x)
        Resonance frequency, Hz (NaN: not measured).
    q_factor : ndarray (y, x)
        Quality factor, dimensionless.
    pixel_size : tuple of float or None
        (dx, dy), m; None when the file does not give it.
    source : str
        The file read, and the dataset inside it (``file.h5:/Measurement_000/...``).
    amplitude : ndarray (y, x) or None
        The SHO amplitude (BGlib: ``Amplitude [V]``, V), where the file has it.
    phase_rad : ndarray (y, x) or None
        The SHO phase, rad, where the file has it.
    r2 : ndarray (y, x) or None
        The fit's coefficient of determination, where the file has it.
    steps : int
        How many spectroscopic steps the file holds (one map each: the DC bias steps of a
        BEPS experiment); 1 for a BE-line map or a grid.
    """

    frequency_Hz: np.ndarray
    q_factor: np.ndarray
    pixel_size: tuple[float, float] | None
    source: str
    amplitude: np.ndarray | None = None
    phase_rad: np.ndarray | None = None
    r2: np.ndarray | None = None
    steps: int = 1

    def _facts(self) -> list[tuple[str, str]]:
        """The maps' shape, the ranges of f (kHz) and Q, the pixel size, steps and source."""
        facts = [("f", values(self.frequency_Hz, "kHz", 1e3)), ("Q", values(self.q_factor))]
        if self.pixel_size is not None:
            dx, dy = self.pixel_size
            facts.append(("pixel", f"{dx * 1e9:.4g} x {dy * 1e9:.4g} nm"))
        extra = [n for n in ("amplitude", "phase_rad", "r2") if getattr(self, n) is not None]
        facts += [("also", ", ".join(extra))] if extra else []
        facts += [("steps", str(self.steps))] if self.steps != 1 else []
        facts.append(("source", self.source))
        return facts


def check_frequency_map(frequency, source: str) -> np.ndarray:
    """A frequency map checked before it is inverted: float, 2-D, read-only, NaN where not
    measured.

    Parameters
    ----------
    frequency : array_like (y, x)
        Resonance frequencies, Hz; NaN, or exactly 0 (what an instrument writes where its
        tracking or fit did not run), is a pixel not measured.
    source : str
        What the map is (a file and its layer), for the messages.

    Returns
    -------
    ndarray
        A float copy with the zeros as NaN.

    Raises
    ------
    ContactresInputError
        One line naming ``source`` and the rule: not 2-D; no pixel measured (a map of zeros:
        the tracking was off, or the layer is not a frequency); a negative, infinite frequency
        (a negative one is what a map of offsets from the drive frequency holds).
    """
    values = np.array(frequency, dtype=float)
    if values.ndim != 2:
        raise ContactresInputError(
            f"{source}: a frequency map must be 2-D (y, x), got shape {values.shape}"
        )
    values[values == 0] = np.nan
    if np.isinf(values).any():
        raise ContactresInputError(f"{source}: infinite frequencies in the map")
    if (values < 0).any():
        i, j = np.argwhere(values < 0)[0]
        raise ContactresInputError(
            f"{source}: negative frequency {values[i, j]:.6g} Hz at row {i}, column {j}: "
            "frequencies must be > 0 Hz (a map of offsets from the drive frequency needs the "
            "drive frequency added)"
        )
    if not np.isfinite(values).any():
        raise ContactresInputError(
            f"{source}: no frequency measured (every pixel is 0 or NaN: was the resonance "
            "tracking off, or is this layer not a frequency?)"
        )
    values.flags.writeable = False
    return values


def dart_frequency_Hz(wave: IgorWave, layer: str = "Frequency") -> np.ndarray:
    """The contact-resonance frequency map of an Asylum DART image, Hz, (y, x), checked.

    Asylum's note maps the ``Frequency`` channel to ``$DDSFrequencyOffset0``: the layer holds
    the tracked frequency's offset from the drive frequency set (``DriveFrequency`` of the
    note). A layer whose values are below half the drive frequency in magnitude is read as
    such an offset and the drive frequency is added; larger values are taken as frequencies
    already (a DART tracking offset is a few kHz at a few hundred kHz, so the two cases do not
    meet). Without ``DriveFrequency`` in the note the layer is taken as it is.

    Parameters
    ----------
    wave : IgorWave
        The image (:func:`~contactres.measurements.read_ibw`).
    layer : str
        The frequency layer's name (``Frequency``: ``FrequencyRetrace``, else
        ``FrequencyTrace``).

    Returns
    -------
    ndarray
        :func:`check_frequency_map` of the frequencies, transposed to (y, x).
    """
    values = np.asarray(wave.layer(layer), dtype=float)
    if values.ndim != 2:
        raise ContactresInputError(
            f"{wave.source}: layer {layer!r} is not an image (shape {values.shape})"
        )
    drive = wave.note.get("DriveFrequency")
    measured = values[np.isfinite(values) & (values != 0)]
    if (
        isinstance(drive, float)
        and drive > 0
        and measured.size
        and np.median(np.abs(measured)) < 0.5 * drive
    ):
        values = np.where(values == 0, np.nan, values + drive)
    name = wave.labels[wave.layer_index(layer)]
    return check_frequency_map(values.T, f"{wave.source} (layer {name})")


def _h5py():
    try:
        import h5py
    except ImportError as exc:
        raise MissingExtraError(
            "reading band-excitation .h5 files needs h5py: pip install 'contactres[afm]'"
        ) from exc
    return h5py


def _sho_datasets(h5file, h5py) -> list:
    """Every compound dataset with a ``Frequency [Hz]`` field whose name is ``Fit`` or
    ``Guess``, Fits first, each kind in the order of their paths."""
    found: list = []

    def visit(name, obj):
        if (
            isinstance(obj, h5py.Dataset)
            and obj.dtype.names
            and "Frequency [Hz]" in obj.dtype.names
            and name.rsplit("/", 1)[-1] in ("Fit", "Guess")
        ):
            found.append(obj)

    h5file.visititems(visit)
    return sorted(found, key=lambda d: (d.name.rsplit("/", 1)[-1] != "Fit", d.name))


def _ancillary(dataset, name: str, h5py):
    """The USID ancillary dataset ``name`` of ``dataset``: its object-reference attribute, else
    a dataset of that name in its group or the groups above."""
    ref = dataset.attrs.get(name)
    if isinstance(ref, h5py.Reference) and ref:
        return dataset.file[ref]
    group = dataset.parent
    while True:
        if name in group and isinstance(group[name], h5py.Dataset):
            return group[name]
        if group.name == "/":
            return None
        group = group.parent


def _texts(values) -> list[str]:
    """An attribute of names (bytes or str, scalar or array) as a list of str."""
    items = np.atleast_1d(values).tolist() if values is not None else []
    return [v.decode() if isinstance(v, bytes) else str(v) for v in items]


def _grid_positions(dataset, where: str, h5py) -> tuple[np.ndarray, np.ndarray]:
    """(row, column) of each position of an SHO dataset: the Y and X columns of its
    ``Position_Indices`` (by their labels; the first column is X and the second Y without
    labels, USID's order: X varies fastest)."""
    n_positions = dataset.shape[0]
    indices = _ancillary(dataset, "Position_Indices", h5py)
    if indices is None:
        raise ContactresInputError(f"{where}: no Position_Indices dataset for the SHO fit")
    table = np.asarray(indices[()]).reshape(n_positions, -1).astype(np.int64)
    labels = [s.strip().lower() for s in _texts(indices.attrs.get("labels"))]
    if table.shape[1] == 1:
        return np.zeros(n_positions, np.int64), table[:, 0]  # a single line
    x = labels.index("x") if "x" in labels else 0
    y = labels.index("y") if "y" in labels else 1
    if table.shape[1] != 2 or x == y:
        raise ContactresInputError(
            f"{where}: Position_Indices has {table.shape[1]} columns {labels}: need X and Y"
        )
    rows, cols = table[:, y], table[:, x]
    if (rows < 0).any() or (cols < 0).any():
        raise ContactresInputError(f"{where}: negative position indices")
    if len(set(zip(rows.tolist(), cols.tolist(), strict=True))) != n_positions:
        raise ContactresInputError(f"{where}: two positions share the same X and Y indices")
    return rows, cols


def _be_pixel_size(dataset, shape) -> tuple[float, float] | None:
    """(dx, dy) in m from the scan size that BGlib's translators copy into the attributes of the
    measurement group (the nearest group above the dataset that has them)."""
    group = dataset.parent
    while True:
        attrs = group.attrs
        if "grid_scan_width_[m]" in attrs and "grid_scan_height_[m]" in attrs:
            width = float(np.ravel(attrs["grid_scan_width_[m]"])[0])
            height = float(np.ravel(attrs["grid_scan_height_[m]"])[0])
            rows, cols = shape
            if width > 0 and height > 0:
                return width / cols, height / rows
            return None
        if group.name == "/":
            return None
        group = group.parent


def read_be_sho(path: str | os.PathLike, *, dataset: str | None = None, step: int = 0):
    """Read the SHO fit of a band-excitation map from a BGlib (USID) HDF5 file.

    Parameters
    ----------
    path : str or path-like
        The ``.h5`` file.
    dataset : str, optional
        The compound dataset's path in the file; by default the first ``Fit`` of the file's
        ``*-SHO_Fit_*`` groups (the ``Guess`` if no fit was run).
    step : int
        The spectroscopic step (a column of the dataset: one per DC bias step of a BEPS
        experiment, a single one for BE-line maps); 0 by default.

    Returns
    -------
    ResonanceMaps
        frequency_Hz, q_factor, amplitude (V), phase_rad and r2 as (y, x) maps (NaN at a grid
        position no row fills), the pixel size from the measurement's
        ``grid_scan_width_[m]``/``grid_scan_height_[m]`` (None without them: BGlib's position
        values are indices, not lengths), and the source ``file:dataset``.

    Raises
    ------
    ContactresInputError
        One line naming the file: not HDF5, no SHO dataset, no positions, a step out of range.
    MissingExtraError
        h5py is not installed (the optional extra ``afm``).
    """
    h5py = _h5py()
    p = Path(path)
    if not p.is_file():
        raise ContactresInputError(f"{p}: no such file")
    try:
        h5file = h5py.File(p, "r")
    except OSError:
        raise ContactresInputError(f"{p}: not an HDF5 file (or truncated)") from None
    with h5file:
        if dataset is not None:
            if dataset not in h5file:
                raise ContactresInputError(f"{p}: no dataset {dataset!r} in the file")
            sho = h5file[dataset]
            if not (isinstance(sho, h5py.Dataset) and sho.dtype.names):
                raise ContactresInputError(f"{p}: {dataset!r} is not a compound dataset")
        else:
            candidates = _sho_datasets(h5file, h5py)
            if not candidates:
                raise ContactresInputError(
                    f"{p}: no SHO fit in the file (a compound dataset 'Fit' or 'Guess' with "
                    "the field 'Frequency [Hz]', as BGlib writes into a '*-SHO_Fit_*' group)"
                )
            sho = candidates[0]
        where = f"{p}:{sho.name}"
        missing = [f for f in ("Frequency [Hz]", "Quality Factor") if f not in sho.dtype.names]
        if missing:
            raise ContactresInputError(
                f"{where}: no field {missing[0]!r}; fields: {', '.join(sho.dtype.names)}"
            )
        table = np.asarray(sho[()]).reshape(sho.shape[0], -1)
        if not 0 <= step < table.shape[1]:
            raise ContactresInputError(
                f"{where}: step {step} is out of range (the dataset has {table.shape[1]})"
            )
        rows, cols = _grid_positions(sho, where, h5py)
        shape = (int(rows.max()) + 1, int(cols.max()) + 1)
        maps = {}
        for field_name, attribute in SHO_FIELDS.items():
            if field_name in sho.dtype.names:
                grid = np.full(shape, np.nan)
                grid[rows, cols] = table[field_name][:, step]
                grid.flags.writeable = False
                maps[attribute] = grid
        pixel_size = _be_pixel_size(sho, shape)
    return ResonanceMaps(pixel_size=pixel_size, source=where, steps=table.shape[1], **maps)


def _units(variable) -> str:
    return str(variable.attrs.get("units", "")).strip()


def read_resonance_grid(path: str | os.PathLike) -> ResonanceMaps:
    """Read a grid of resonance frequencies and Q: an xarray Dataset in NetCDF or Zarr.

    Parameters
    ----------
    path : str or path-like
        A NetCDF file (``.nc``) or a Zarr store (``.zarr``, a folder) with the variables
        ``frequency_Hz`` (units ``Hz`` if the attribute is given) and ``q_factor`` or ``Q``
        (no units, ``1`` or ``dimensionless``), both over the dimensions ``y`` and ``x``
        (either order); coordinates ``x`` and ``y`` in m (or ``mm``, ``um``, ``nm`` as their
        ``units`` say) give the pixel size.

    Returns
    -------
    ResonanceMaps
        frequency_Hz and q_factor as (y, x) maps, the pixel size (None without regular
        coordinates) and the source.

    Raises
    ------
    ContactresInputError
        One line naming the file and the rule (a missing variable, other dimensions, units
        that are not Hz).
    MissingExtraError
        xarray is not installed (the optional extra ``maps``).
    """
    try:
        import xarray as xr
    except ImportError as exc:
        raise MissingExtraError(
            "reading a resonance grid needs xarray: pip install 'contactres[maps]'"
        ) from exc
    p = Path(path)
    if not p.exists():
        raise ContactresInputError(f"{p}: no such file")
    try:
        zarr = p.is_dir() or p.suffix.lower() == ".zarr"
        # Consolidated metadata is not part of Zarr 3: asking for it only adds a warning.
        ds = xr.open_zarr(p, consolidated=False) if zarr else xr.open_dataset(p)
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ContactresInputError(
            f"{p}: not a NetCDF file or Zarr store that xarray can open ({type(exc).__name__})"
        ) from None
    with ds:
        q_name = next((n for n in ("q_factor", "Q") if n in ds.data_vars), None)
        if "frequency_Hz" not in ds.data_vars or q_name is None:
            need = "frequency_Hz" if "frequency_Hz" not in ds.data_vars else "q_factor (or Q)"
            raise ContactresInputError(
                f"{p}: no variable {need}; variables: {', '.join(map(str, ds.data_vars))}"
            )
        maps = {}
        for name, attribute in (("frequency_Hz", "frequency_Hz"), (q_name, "q_factor")):
            variable = ds[name]
            if set(variable.dims) != {"y", "x"}:
                raise ContactresInputError(
                    f"{p}: variable {name} has dimensions {variable.dims}, need ('y', 'x')"
                )
            maps[attribute] = variable.transpose("y", "x").to_numpy().astype(float)
        f_units, q_units = _units(ds["frequency_Hz"]), _units(ds[q_name])
        if f_units not in ("", "Hz"):
            raise ContactresInputError(f"{p}: frequency_Hz has units {f_units!r}; it must be in Hz")
        if q_units not in ("", "1", "dimensionless"):
            raise ContactresInputError(f"{p}: {q_name} has units {q_units!r}; Q has none")
        pixel_size = _grid_pixel_size(ds, p)
    for grid in maps.values():
        grid.flags.writeable = False
    return ResonanceMaps(pixel_size=pixel_size, source=str(p), **maps)


def _grid_pixel_size(ds, p: Path) -> tuple[float, float] | None:
    """(dx, dy) in m from the ``x`` and ``y`` coordinates when both are regular."""
    steps = []
    for axis in ("x", "y"):
        if axis not in ds.coords or ds.sizes[axis] < 2:
            return None
        units = _units(ds.coords[axis]) or "m"
        if units not in _LENGTHS:
            raise ContactresInputError(
                f"{p}: coordinate {axis} has units {units!r}; expected one of {list(_LENGTHS)}"
            )
        diffs = np.diff(ds.coords[axis].to_numpy().astype(float))
        if not np.allclose(diffs, diffs[0], rtol=1e-6, atol=0) or diffs[0] == 0:
            return None
        steps.append(abs(float(diffs[0])) * _LENGTHS[units])
    return steps[0], steps[1]
