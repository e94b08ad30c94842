"""The SHA-256 checksum of an input file, of the very bytes that were parsed: the analysis
reports its input under it (``SweepTable.source_sha256``, the HTML report's checksum).

The built-in delimited-text reader hashes the bytes it reads (``attrs["sha256"]``): its file
is read once (issue 31, point 3: the 148 MB table of 10^5 sweeps was read three times, hashed
before and after its reading). Any other reader's file is hashed before and after it is read,
and one that changed in between is refused rather than reported under a hash it no longer has.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from ..errors import ContactresInputError

__all__ = ["file_sha256", "hashed_load"]


def file_sha256(path) -> str | None:
    """SHA-256 (hex) of the bytes of the file ``path``, read in blocks of 1 MiB; None for a
    folder (an input read from several files has no one checksum)."""
    p = Path(path)
    if not p.is_file():
        return None
    h = hashlib.sha256()
    with p.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def hashed_load(reader, path: Path, built_in) -> tuple:
    """``(reader.load(path), SHA-256 hex of the bytes it parsed)``.

    Parameters
    ----------
    reader : Reader
        The recipe picked for ``path`` (:class:`contactres.measurements.readers.Reader`).
    path : Path
        The input file.
    built_in : Readers
        The built-in registry (:data:`contactres.measurements.readers.BUILT_IN`): its ``csv``
        recipes record the hash of what they parse; any other recipe is bracketed by two.

    Raises
    ------
    ContactresInputError
        The file changed while a reader that does not hash it read it.
    """
    if reader.name == "csv" and reader in built_in.readers:
        raw = reader.load(path)
        return raw, raw.attrs["sha256"]
    digest = file_sha256(path)
    raw = reader.load(path)
    if file_sha256(path) != digest:
        raise ContactresInputError(
            f"{path}: the file changed while it was read; read it again once it is complete"
        )
    return raw, digest
