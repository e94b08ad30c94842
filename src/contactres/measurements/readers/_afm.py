"""The recipes of contact-resonance AFM map files (kind ``afm_map``): an Asylum Research image
(``.ibw``), a band-excitation SHO fit of BGlib (``.h5``) and a plain grid of frequency and Q
(NetCDF ``.nc`` or a Zarr store ``.zarr``).

Each is recognised by its first bytes (its magic number) as well as its suffix, so a file
renamed is still read by the right recipe: an Igor binary wave begins with its version, 5, as a
2-byte integer in either byte order; HDF5 with the 8-byte signature ``\\x89HDF\\r\\n\\x1a\\n``
(NetCDF 4 is HDF5 too); NetCDF 3 with ``CDF\\x01`` or ``CDF\\x02``; a Zarr store is a folder
holding ``.zgroup`` (Zarr 2) or ``zarr.json`` (Zarr 3). The readers themselves live in
:mod:`contactres.measurements` (:func:`~contactres.measurements.read_ibw`,
:func:`~contactres.measurements.read_be_sho`,
:func:`~contactres.measurements.read_resonance_grid`).
"""

from __future__ import annotations

from pathlib import Path

from .._afm_maps import read_be_sho, read_resonance_grid
from .._ibw import read_ibw
from ._recipe import Reader

__all__ = ["AFM_MAP_READERS"]

_HDF5 = b"\x89HDF\r\n\x1a\n"


def _first_bytes(path: Path, count: int = 8) -> bytes:
    if not path.is_file():
        return b""
    with path.open("rb") as fh:
        return fh.read(count)


def _is_ibw(path: Path, head: str) -> bool:
    """An Igor binary wave of version 5 (Asylum's), little- or big-endian."""
    return _first_bytes(path, 2) in (b"\x05\x00", b"\x00\x05")


def _is_be_sho(path: Path, head: str) -> bool:
    """An HDF5 file that is not NetCDF (those go to the grid recipe by their suffix)."""
    return path.suffix.lower() != ".nc" and _first_bytes(path) == _HDF5


def _is_grid(path: Path, head: str) -> bool:
    """A NetCDF file (3, or 4: HDF5 with the .nc suffix) or a Zarr store (a folder)."""
    if path.is_dir():
        return (path / ".zgroup").is_file() or (path / "zarr.json").is_file()
    first = _first_bytes(path)
    return first[:4] in (b"CDF\x01", b"CDF\x02") or (
        first == _HDF5 and path.suffix.lower() == ".nc"
    )


#: The recipes of kind ``afm_map``, in the order they are tried (after those whose suffix
#: matches).
AFM_MAP_READERS = (
    Reader("ibw", (".ibw",), _is_ibw, read_ibw, "afm_map"),
    Reader("be-sho", (".h5", ".hdf5"), _is_be_sho, read_be_sho, "afm_map"),
    Reader("grid", (".nc", ".zarr"), _is_grid, read_resonance_grid, "afm_map"),
)
