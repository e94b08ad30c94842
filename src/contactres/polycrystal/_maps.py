"""Orientation maps: the container, per-pixel evaluation chunk by chunk (numpy or dask), Zarr IO.

An :class:`OrientationMap` holds the Bunge Euler angles of a regular square grid (an EBSD scan,
:mod:`contactres.polycrystal._ebsd`, or a synthetic polycrystal,
:mod:`contactres.polycrystal._synthetic`). :func:`evaluate_map` applies a
per-pixel function ``f(R) -> values`` of the surface-frame matrices (shape (..., 3, 3) ->
(...), pure, numpy in and out; :class:`ExactModulus` is the exact indentation modulus) over
rectangular chunks of the map:

* default: the embedded single-machine path, a loop over the chunks in this process (numpy);
* ``client=`` a :class:`dask.distributed.Client`, or ``scheduler="tcp://host:port"``: a
  :mod:`dask.array` ``map_blocks`` over *the same chunks*, computed on the cluster.

Both paths call the same block function on the same blocks (same boundaries, same dtype), so
their results are identical bit for bit, whatever ``f`` does inside a block.

:func:`map_to_dataset` turns a map into an :mod:`xarray` Dataset (coordinates in m, the
conventions as attributes); :func:`write_map`/:func:`read_map` store it as a chunked Zarr store,
written atomically (a staging store beside the target, renamed onto it).

dask, xarray and zarr are the optional extra ``maps`` (``pip install 'contactres[maps]'``): they
are imported inside the functions that need them, never when :mod:`contactres.polycrystal` is
imported.

Conventions
-----------
Euler angles: Bunge (φ1, Φ, φ2), passive, radians (:mod:`.orientations`). Sample frame: x = RD
(the map's X, columns), y = TD (rows), z = ND, the inward surface normal. Array layout: row
index = y, column index = x, so ``euler[i, j]`` is the pixel at (x, y) = (j·step_x, i·step_y)
from the map origin.
"""

from __future__ import annotations

import os
import secrets
import shutil
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from .._ownership import STORE_MARKER, refusal, sign_store, unproven_store_entries
from ..errors import ContactresInputError, MissingExtraError
from ..fileio import OutputError, check_output_file, replace_folder
from ..materials import Material
from ._moduli import indentation_moduli
from ._orientations import surface_matrices_from_euler

__all__ = [
    "MAP_CONVENTIONS",
    "MAX_MAP_PIXELS",
    "ExactModulus",
    "OrientationMap",
    "check_map_output",
    "check_map_size",
    "evaluate_map",
    "map_from_dataset",
    "map_to_dataset",
    "read_map",
    "write_map",
]

#: Attributes written with every map (and checked on reading).
MAP_CONVENTIONS = {
    "euler_convention": "Bunge ZXZ, passive, radians",
    "sample_frame": "x=RD, y=TD, z=ND inward normal",
    "layout": "row index = y, column index = x",
}

_EXTRA = "pip install 'contactres[maps]'"

#: Largest map accepted, in pixels (rows x columns): 2^25 ≈ 3.4e7 (a 5793 x 5793 map). A map's
#: arrays take ~60 bytes a pixel (Euler angles, phase, confidence, labels and one value map):
#: 2 GB at the limit. The synthetic maps, the Zarr map stores (:func:`read_map`, checked from
#: the sizes a store declares, before any data is read) and the EBSD grids check it, so that a
#: 116 kB store declaring 10^10 pixels is refused at once instead of running out of memory after
#: minutes. From Python, ``max_pixels=`` of :func:`read_map` and
#: :func:`~contactres.polycrystal.synthetic_polycrystal` sets another limit.
MAX_MAP_PIXELS = 2**25
# The variables map_from_dataset needs from a store.
_MAP_VARIABLES = ("euler", "phase", "confidence")


def check_map_size(shape, what: str, max_pixels: int = MAX_MAP_PIXELS) -> None:
    """Refuse a map of ``shape`` = (rows, columns) beyond ``max_pixels`` pixels (a one-line
    ContactresInputError beginning with ``what``, the map's name), before it is allocated."""
    rows, cols = (int(n) for n in shape)
    if rows * cols > max_pixels:
        raise ContactresInputError(
            f"{what}: {rows} x {cols} = {rows * cols:.4g} pixels, more than the limit of "
            f"{max_pixels:.4g} ({max_pixels * 60 / 1e9:.3g} GB of arrays); from Python, "
            "max_pixels= of read_map or synthetic_polycrystal sets another limit"
        )


def require_maps_extra(module: str):
    """Import ``module`` (dask, distributed, xarray, zarr) or raise an ImportError naming the
    optional extra ``maps``."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:  # pragma: no cover - the test environment has the extra
        raise MissingExtraError(f"{module} is needed for polycrystal maps: {_EXTRA}") from exc


@dataclass(frozen=True, eq=False)
class OrientationMap:
    """Orientations of a regular square grid.

    Attributes
    ----------
    euler : ndarray, shape (H, W, 3)
        Bunge (φ1, Φ, φ2) in radians, per pixel (row = y, column = x).
    step_x, step_y : float
        Pixel pitch along x (columns) and y (rows), m.
    phase : ndarray of int, shape (H, W)
        Phase index per pixel (file convention; 0 is "not indexed" in .ctf files).
    confidence : ndarray of float, shape (H, W)
        A per-pixel quality value, named by ``confidence_name`` (CI of .ang, MAD of .ctf, 1 for
        a synthetic map).
    confidence_name : str
        What ``confidence`` is.
    labels : ndarray of int, shape (H, W), or None
        Grain label per pixel, when known (synthetic maps).
    source : str
        Where the map came from (a file name or "synthetic ...").
    """

    euler: np.ndarray
    step_x: float
    step_y: float
    phase: np.ndarray
    confidence: np.ndarray
    confidence_name: str = "confidence"
    labels: np.ndarray | None = None
    source: str = ""

    def __post_init__(self) -> None:
        e = np.asarray(self.euler, dtype=float)
        if e.ndim != 3 or e.shape[2] != 3:
            raise ContactresInputError(f"euler must have shape (H, W, 3), got {e.shape}")
        for name in ("step_x", "step_y"):
            step = float(getattr(self, name))
            if not (np.isfinite(step) and step > 0):
                raise ContactresInputError(f"{name} must be a positive length in m, got {step!r}")
            object.__setattr__(self, name, step)
        object.__setattr__(self, "euler", e)
        for name, dtype in (("phase", np.int64), ("confidence", float), ("labels", np.int64)):
            v = getattr(self, name)
            if v is None:
                continue
            v = np.asarray(v, dtype=dtype)
            if v.shape != e.shape[:2]:
                raise ContactresInputError(f"{name} must have shape {e.shape[:2]}, got {v.shape}")
            object.__setattr__(self, name, v)

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W): rows (y) and columns (x)."""
        return self.euler.shape[:2]

    def surface_matrices(self) -> np.ndarray:
        """Per-pixel surface-frame matrices, shape (H, W, 3, 3) (all in memory at once)."""
        e = self.euler
        return surface_matrices_from_euler(e[..., 0], e[..., 1], e[..., 2], degrees=False)

    def _facts(self) -> list[tuple[str, str]]:
        """(what, value) of the summary: the size, the phases, the grains and the quality; the
        arrays themselves are never printed (a map of 10^6 pixels would fill the screen)."""
        H, W = self.shape
        phases = ", ".join(str(p) for p in np.unique(self.phase))
        finite = self.confidence[np.isfinite(self.confidence)]
        quality = f"{finite.min():.3g} to {finite.max():.3g}" if finite.size else "none"
        grains = "not labelled" if self.labels is None else str(np.unique(self.labels).size)
        return [
            ("pixels", f"{H} x {W} of {self.step_x * 1e6:.4g} x {self.step_y * 1e6:.4g} µm"),
            ("phase ids", phases),
            ("grains", grains),
            (self.confidence_name, quality),
            ("source", self.source or "not given"),
        ]

    def __repr__(self) -> str:
        """One line: size, phases, grains, quality, source (the arrays are attributes)."""
        facts = "; ".join(f"{k}: {v}" for k, v in self._facts())
        return f"{type(self).__name__}({facts})"

    def _repr_html_(self) -> str:
        """The summary of :meth:`__repr__` as an HTML table, for notebooks (text escaped)."""
        import html

        rows = "".join(
            f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in self._facts()
        )
        return f"<p><b>{type(self).__name__}</b></p><table><tbody>{rows}</tbody></table>"


@dataclass(frozen=True, eq=False)
class ExactModulus:
    """Per-pixel function: the exact indentation modulus M of each surface matrix, Pa.

    ``ExactModulus(material)(R)`` with ``R`` of shape (..., 3, 3) returns M of shape (...)
    (:func:`~contactres.polycrystal.indentation_moduli`; real for a lossless material). A
    frozen dataclass of module level, so it pickles and can be shipped to dask workers.
    """

    material: Material
    rtol: float | None = None

    def __call__(self, R: np.ndarray) -> np.ndarray:
        R = np.asarray(R, dtype=float)
        flat = R.reshape(-1, 3, 3)
        if self.rtol is None:
            M = indentation_moduli(self.material, flat)
        else:
            M = indentation_moduli(self.material, flat, rtol=self.rtol)
        return M.reshape(R.shape[:-2])


def _euler_block(func: Callable, euler_block: np.ndarray, dtype) -> np.ndarray:
    """The per-chunk step shared by both paths: Euler (h, w, 3) -> R -> func -> (h, w)."""
    e = np.asarray(euler_block, dtype=float)
    R = surface_matrices_from_euler(e[..., 0], e[..., 1], e[..., 2], degrees=False)
    out = np.asarray(func(R))
    if out.shape != e.shape[:2]:
        raise ContactresInputError(
            f"the per-pixel function must map shape (..., 3, 3) to (...): got {out.shape} "
            f"for a chunk of {e.shape[:2]}"
        )
    return out.astype(dtype, copy=False)


def _dask_block(euler_block: np.ndarray, func: Callable, dtype) -> np.ndarray:
    return _euler_block(func, euler_block, dtype)


def _chunk_edges(n: int, size: int) -> list[tuple[int, int]]:
    return [(a, min(a + size, n)) for a in range(0, n, size)]


def _check_chunks(chunks) -> tuple[int, int]:
    try:
        cy, cx = (int(c) for c in chunks)
    except (TypeError, ValueError) as exc:
        raise ContactresInputError(
            f"chunks must be two positive integers (rows, columns), got {chunks!r}"
        ) from exc
    if cy < 1 or cx < 1:
        raise ContactresInputError(
            f"chunks must be two positive integers (rows, columns), got {chunks!r}"
        )
    return cy, cx


def evaluate_map(
    func: Callable[[np.ndarray], np.ndarray],
    euler,
    *,
    chunks: tuple[int, int] = (256, 256),
    client=None,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    dtype=float,
) -> np.ndarray:
    """Apply a per-pixel function of the surface matrices to a map, chunk by chunk.

    Parameters
    ----------
    func : callable
        ``func(R) -> values``: ``R`` of shape (h, w, 3, 3) (surface-frame matrices of a chunk,
        rows = sample axes in crystal coordinates) to values of shape (h, w). Pure (no state
        between calls). On a cluster it is pickled to the workers: use a module-level function,
        a :func:`functools.partial` of one, or a dataclass like :class:`ExactModulus`.
    euler : array_like, shape (H, W, 3)
        Bunge (φ1, Φ, φ2) in radians per pixel: a numpy array, an :class:`OrientationMap`, a
        :mod:`dask.array` (e.g. ``read_map(path)["euler"].data``, read by the workers chunk by
        chunk) or an xarray DataArray.
    chunks : (int, int)
        Chunk size (rows, columns); the last chunk of a row or column may be smaller. The
        chunking, not the path, fixes the result: the same ``chunks`` give identical values on
        both paths.
    client : dask.distributed.Client, optional
        Compute on this cluster (dask path).
    scheduler : str, optional
        Address of a dask scheduler (``"tcp://host:port"``); a client is opened for the call and
        closed after it. Not together with ``client``.
    progress : callable, optional
        ``progress(done, total)`` after each completed chunk (``total`` = number of chunks).
        Serial path: in chunk order. Dask path: as the chunks' futures complete
        (``distributed.as_completed``), in completion order; ``done`` still counts 1..total.
    dtype : numpy dtype
        dtype of the result (``complex`` for a lossy material's M).

    Returns
    -------
    ndarray, shape (H, W)
        ``func`` of every pixel (in memory on the caller).

    Raises
    ------
    ValueError
        For ``euler`` not of shape (H, W, 3), bad ``chunks``, both ``client`` and ``scheduler``,
        or a ``func`` that does not return one value per pixel.
    ImportError
        On the dask path when the extra ``maps`` is not installed.

    Notes
    -----
    Dask path: the map is cut into the same chunks as the serial loop (a numpy input as one
    dask source per chunk, so the blocks spread over the workers; a dask input, e.g. read
    from Zarr, rechunked, so each worker reads its own chunks), ``map_blocks`` applies the
    shared block function, and the blocks' futures are gathered as they complete. dask's
    worker processes run with ``MALLOC_TRIM_THRESHOLD_=65536`` by default, which makes
    :class:`ExactModulus` ~2.7x slower per pixel than the serial path (its large temporaries are
    mapped and unmapped at every call); start the workers with ``MALLOC_TRIM_THRESHOLD_`` and
    ``MALLOC_MMAP_THRESHOLD_`` both raised in ``distributed.nanny.pre-spawn-environ``, as the
    guide's "On a dask cluster" and ``benchmarks/bench_polycrystal_dask.py`` do.
    """
    cy, cx = _check_chunks(chunks)
    if client is not None and scheduler is not None:
        raise ContactresInputError("give either client or scheduler, not both")
    if isinstance(euler, OrientationMap):
        euler = euler.euler
    if hasattr(euler, "dims") and hasattr(euler, "data"):  # an xarray DataArray
        euler = euler.data
    if len(getattr(euler, "shape", ())) != 3 or euler.shape[2] != 3:
        raise ContactresInputError(
            f"euler must have shape (H, W, 3), got {getattr(euler, 'shape', None)}"
        )
    if client is None and scheduler is None:
        return _evaluate_serial(func, euler, (cy, cx), progress, dtype)
    if scheduler is not None:
        distributed = require_maps_extra("distributed")
        with distributed.Client(scheduler) as own:
            return _evaluate_dask(func, euler, (cy, cx), own, progress, dtype)
    return _evaluate_dask(func, euler, (cy, cx), client, progress, dtype)


def _evaluate_serial(func, euler, chunks, progress, dtype) -> np.ndarray:
    H, W = euler.shape[:2]
    out = np.empty((H, W), dtype=dtype)
    rows, cols = _chunk_edges(H, chunks[0]), _chunk_edges(W, chunks[1])
    total = len(rows) * len(cols)
    done = 0
    for r0, r1 in rows:
        for c0, c1 in cols:
            block = euler[r0:r1, c0:c1, :]  # a dask or zarr array reads this chunk only
            if hasattr(block, "compute"):  # in this process, even when a dask client exists
                block = block.compute(scheduler="synchronous")
            block = np.asarray(block)
            out[r0:r1, c0:c1] = _euler_block(func, block, dtype)
            done += 1
            if progress is not None:
                progress(done, total)
    return out


def _evaluate_dask(func, euler, chunks, client, progress, dtype) -> np.ndarray:
    da = require_maps_extra("dask.array")
    distributed = require_maps_extra("distributed")
    if isinstance(euler, da.Array):
        arr = euler.astype(float).rechunk((chunks[0], chunks[1], 3))
    else:
        # One source per chunk (not one for the whole array): a single source would be held
        # by one worker and draw every block task to it.
        e = np.asarray(euler, dtype=float)
        rows, cols = _chunk_edges(e.shape[0], chunks[0]), _chunk_edges(e.shape[1], chunks[1])
        blocks = [
            [[da.from_array(e[r0:r1, c0:c1], chunks=-1)] for c0, c1 in cols] for r0, r1 in rows
        ]
        arr = da.block(blocks)  # nested 3 deep: rows along y, columns along x, angles whole
    # A fresh name per call: a second call recomputes (never reuses results left on the cluster).
    name = f"contactres-evaluate-map-{secrets.token_hex(8)}"
    values = arr.map_blocks(_dask_block, func, dtype, dtype=np.dtype(dtype), drop_axis=2, name=name)
    blocks = values.to_delayed()  # (n_row_chunks, n_col_chunks) of delayed blocks
    keys = [(i, j) for i in range(blocks.shape[0]) for j in range(blocks.shape[1])]
    futures = client.compute([blocks[i, j] for i, j in keys])
    where = {f.key: k for f, k in zip(futures, keys, strict=True)}
    H, W = euler.shape[:2]
    out = np.empty((H, W), dtype=dtype)
    row0 = np.concatenate([[0], np.cumsum(values.chunks[0])])
    col0 = np.concatenate([[0], np.cumsum(values.chunks[1])])
    total = len(futures)
    for done, (fut, block) in enumerate(distributed.as_completed(futures, with_results=True), 1):
        i, j = where[fut.key]
        out[row0[i] : row0[i + 1], col0[j] : col0[j + 1]] = block
        if progress is not None:
            progress(done, total)
    return out


def map_to_dataset(m: OrientationMap):
    """The map as an :class:`xarray.Dataset` (numpy-backed; chunks are set on writing).

    Variables: ``euler`` (y, x, angle) rad, ``phase`` (y, x), ``confidence`` (y, x) and
    ``labels`` (y, x) when known; coordinates ``y``, ``x`` (pixel centres from 0, m); the
    ``angle`` dimension is (φ1, Φ, φ2) (attribute ``euler_angles``). Attributes:
    :data:`MAP_CONVENTIONS`, ``step_x_m``,
    ``step_y_m``, ``confidence_name``, ``source``.
    """
    xr = require_maps_extra("xarray")
    H, W = m.shape
    data = {
        "euler": (("y", "x", "angle"), m.euler, {"units": "rad", "long_name": "Bunge Euler"}),
        "phase": (("y", "x"), m.phase, {"units": "1"}),
        "confidence": (("y", "x"), m.confidence, {"long_name": m.confidence_name}),
    }
    if m.labels is not None:
        data["labels"] = (("y", "x"), m.labels, {"long_name": "grain label"})
    coords = {
        "y": ("y", np.arange(H) * m.step_y, {"units": "m"}),
        "x": ("x", np.arange(W) * m.step_x, {"units": "m"}),
    }
    attrs = dict(
        MAP_CONVENTIONS, euler_angles="phi1, Phi, phi2", step_x_m=m.step_x, step_y_m=m.step_y
    )
    attrs.update(confidence_name=m.confidence_name, source=m.source)
    return xr.Dataset(data, coords=coords, attrs=attrs)


def map_from_dataset(ds) -> OrientationMap:
    """The :class:`OrientationMap` of a Dataset written by :func:`map_to_dataset` (loads it).

    Raises ValueError when the Dataset's conventions are not those of :data:`MAP_CONVENTIONS`.
    """
    for key, value in MAP_CONVENTIONS.items():
        if ds.attrs.get(key) != value:
            raise ContactresInputError(
                f"map attribute {key!r} is {ds.attrs.get(key)!r}, expected {value!r}"
            )
    labels = _loaded(ds, "labels") if "labels" in ds else None
    return OrientationMap(
        euler=_loaded(ds, "euler"),
        step_x=float(ds.attrs["step_x_m"]),
        step_y=float(ds.attrs["step_y_m"]),
        phase=_loaded(ds, "phase"),
        confidence=_loaded(ds, "confidence"),
        confidence_name=str(ds.attrs.get("confidence_name", "confidence")),
        labels=labels,
        source=str(ds.attrs.get("source", "")),
    )


def _loaded(ds, name: str) -> np.ndarray:
    """The values of variable ``name`` of ``ds``; a one-line ContactresInputError naming the
    store (``ds.encoding["source"]``, set by :func:`read_map`) when a chunk cannot be read."""
    try:
        return ds[name].values
    except KeyError:
        raise ContactresInputError(
            f"map store {ds.encoding.get('source', '')!r}: variable {name!r} is missing"
        ) from None
    except (OSError, RuntimeError, ValueError, TypeError) as exc:
        # A truncated or foreign chunk (codec errors are RuntimeErrors or ValueErrors).
        raise ContactresInputError(
            f"map store {ds.encoding.get('source', '')!r}: variable {name!r} cannot be read "
            f"({type(exc).__name__}: {' '.join(str(exc).split())[:200]}): a half-written or "
            "damaged store; write it again"
        ) from None


def _is_zarr_store(path: Path) -> bool:
    return path.is_dir() and any((path / n).exists() for n in ("zarr.json", ".zgroup", ".zattrs"))


def _refuse_unproven(target: Path) -> None:
    """OutputError (one line, naming them) if the store at ``target`` holds anything contactres
    cannot show it wrote (:func:`contactres._ownership.unproven_store_entries`): only a store of
    contactres's own, with nothing added, is replaced."""
    if _is_zarr_store(target):
        foreign = unproven_store_entries(target)
        if foreign:
            raise OutputError(refusal("output store", target, foreign))


def check_map_output(path: str | os.PathLike, inputs=()) -> Path:
    """Check, writing nothing, that a map store may be written at ``path`` (before long work).

    Raises :class:`~contactres.fileio.OutputError` (one line) when the folder of ``path`` is
    missing or not writable, ``path`` is one of ``inputs``, or ``path`` exists and is not a
    Zarr store contactres wrote, with nothing added since (:func:`write_map` replaces only
    such a store: :mod:`contactres._ownership`); the refusal names what is not contactres's.
    """
    target = Path(path)
    if target.suffix and target.suffix.lower() != ".zarr":
        # A store named like another format's file (o.csv, o.nc) would be a folder under a
        # file's name: most likely the output meant for another command or option.
        raise OutputError(
            f"output {str(target)!r}: a map store is a Zarr folder, not a {target.suffix} file; "
            f"name it with .zarr (e.g. {target.with_suffix('.zarr').name!r})"
        )
    if target.exists() and not _is_zarr_store(target):
        raise OutputError(f"output {str(target)!r} exists and is not a Zarr store: not overwritten")
    if target.is_dir():  # an earlier store: check the folder above it and the inputs only
        for given in inputs:
            if Path(given).resolve() == target.resolve():
                raise OutputError(f"output {str(target)!r} is also an input")
        _refuse_unproven(target)
        check_output_file(target.parent / f".{target.name}.check", inputs)
        return target
    return check_output_file(target, inputs)


def write_map(path: str | os.PathLike, dataset, *, chunks: tuple[int, int] = (256, 256)) -> Path:
    """Write a map Dataset (or an :class:`OrientationMap`) as a chunked Zarr store, atomically.

    The store is written into a hidden staging folder beside ``path`` and renamed onto it; an
    earlier store at ``path`` is exchanged with it in one step where the system can, else moved
    aside first (:func:`contactres.fileio.replace_folder`), and removed after: a kill never
    leaves a half-written store at ``path``. Every
    (y, x) variable is chunked ``chunks`` = (rows, columns) (``euler`` with its 3 angles in one
    chunk). The complete store is signed before it moves in: its root attributes get
    contactres's marker (:data:`contactres._ownership.STORE_MARKER`, the digest of its keys),
    by which a rerun knows the store at ``path`` as its own (issue 27).

    Raises
    ------
    ValueError
        If ``path`` exists and is not a Zarr store, or is a store that contactres did not
        write or that holds files added since (an OutputError naming them, checked again just
        before the swap): nothing else is overwritten.
    """
    require_maps_extra("zarr")
    if isinstance(dataset, OrientationMap):
        dataset = map_to_dataset(dataset)
    cy, cx = _check_chunks(chunks)
    target = Path(path)
    if target.exists() and not _is_zarr_store(target):
        raise ContactresInputError(
            f"{str(target)!r} exists and is not a Zarr store: not overwritten"
        )
    _refuse_unproven(target)
    stage = target.parent / f".{target.name}.{secrets.token_hex(6)}.tmp"
    encoding = {}
    for name, var in dataset.data_vars.items():
        sizes = {"y": cy, "x": cx}
        encoding[name] = {"chunks": tuple(sizes.get(d, n) for d, n in var.sizes.items())}
    try:
        with warnings.catch_warnings():
            # Consolidated metadata (one read of the whole store's metadata) is what xarray's
            # open_zarr looks for first: without it xarray warns on every open (issue 30).
            # zarr 3 warns that it is not yet part of the format 3 specification; xarray
            # writes it by default all the same, and older readers ignore it.
            warnings.filterwarnings("ignore", message="Consolidated metadata is currently not")
            dataset.to_zarr(stage, mode="w-", encoding=encoding, consolidated=True)
        sign_store(stage)
        if target.exists():
            _refuse_unproven(target)  # again, just before the swap: written to meanwhile?
            aside = target.parent / f".{target.name}.{secrets.token_hex(6)}.old"
            shutil.rmtree(replace_folder(stage, target, aside), ignore_errors=True)
        else:
            os.replace(stage, target)
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    return target


def read_map(path: str | os.PathLike, *, max_pixels: int = MAX_MAP_PIXELS):
    """Open a map written by :func:`write_map` as a lazy, dask-chunked :class:`xarray.Dataset`.

    The variables are read chunk by chunk when used (``ds["euler"].data`` is a dask array that
    :func:`evaluate_map` or a cluster's workers read piecewise); :func:`map_from_dataset` loads
    it into an :class:`OrientationMap`. Only the metadata is read here, and checked: the store
    must hold the variables of a map (euler, phase, confidence) and declare at most
    ``max_pixels`` pixels (default :data:`MAX_MAP_PIXELS`).

    Raises
    ------
    FileNotFoundError
        If there is no store at ``path``.
    ValueError
        (ContactresInputError, one line naming the store) when its metadata cannot be read, a
        variable of the map is missing (a half-written store) or it declares more pixels than
        ``max_pixels``.
    """
    xr = require_maps_extra("xarray")
    target = Path(path)
    if not _is_zarr_store(target):
        raise FileNotFoundError(f"no Zarr map store at {str(target)!r}")
    # First without the x/y coordinates, whose default indexes xarray reads into memory chunk by
    # chunk: for a store declaring 10^10 pixels that is thousands of (absent) chunks and
    # seconds before its size could be refused. The sizes come from the arrays' metadata (no
    # dask arrays: nothing of the probe is read).
    probe = _open_store(xr, target, drop_variables=("x", "y"), chunks=None)
    missing = [name for name in _MAP_VARIABLES if name not in probe]
    if missing:
        raise ContactresInputError(
            f"map store {str(target)!r}: variable(s) {', '.join(map(repr, missing))} missing "
            "(a half-written store, or not a map): write it again"
        )
    check_map_size(
        (probe.sizes.get("y", 0), probe.sizes.get("x", 0)), f"map store {str(target)!r}", max_pixels
    )
    ds = _open_store(xr, target)
    ds.attrs.pop(STORE_MARKER, None)  # the store's, not the map's: never copied on
    ds.encoding["source"] = str(target)
    return ds


def _open_store(xr: ModuleType, target: Path, **options: object) -> Any:
    """``xarray.open_zarr(target, **options)`` (lazy, dask-chunked), or a one-line
    ContactresInputError naming the store when its metadata or coordinates cannot be read."""
    try:
        with warnings.catch_warnings():
            # A folder left without its metadata by a half-written store: the check of the
            # map's variables in read_map names it, in one line.
            warnings.filterwarnings("ignore", message=".*not recognized as a component")
            return xr.open_zarr(target, consolidated=False, **options)
    except (OSError, KeyError, RuntimeError, ValueError, TypeError) as exc:
        # Broken JSON metadata (ValueError), a group without its arrays (KeyError), a truncated
        # chunk of a coordinate read for its index (codec errors are RuntimeErrors), ...
        raise ContactresInputError(
            f"map store {str(target)!r}: not readable ({type(exc).__name__}: "
            f"{' '.join(str(exc).split())[:200]}): a half-written or damaged store"
        ) from None
