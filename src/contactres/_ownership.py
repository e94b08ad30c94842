"""What a rerun may replace: only what contactres can show it wrote (issue 27).

An output that already exists is replaced, or has files removed, only where an earlier run of
contactres can be shown to have written it; anything else there is refused in one line
(:func:`refusal`), before the work starts, and nothing is changed:

* in a results folder (:class:`contactres.fileio.ResultSet`) a file is contactres's when the
  folder's ``manifest.json``, written by contactres, lists it with its current size and SHA-256;
  a file the set would write whose name exists there without such a record (a ``stiffness.csv``
  of the user's, a results file edited since) is named by :func:`unvouched`;
* a Zarr map store (:func:`contactres.polycrystal.write_map`, replaced as a whole) is
  contactres's when its root attributes hold :data:`STORE_MARKER`, which contactres adds once
  the store is complete (:func:`sign_store`): the writer and the SHA-256 of the sorted list of
  the store's keys (every file and folder in it, by its path inside the store). A file or
  group added since (``notes.txt``, another program's array) changes the keys;
  :func:`unproven_store_entries` names it. A store without the marker (another program's, or
  one an older contactres wrote) is never replaced.

The keys, not the chunks' contents, are digested: proving the store's own files would mean
reading the whole store before every rerun, and a chunk contactres wrote is contactres's to
replace. The marker is a JSON string (a NetCDF export of the attributes takes strings).
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

__all__ = [
    "STORE_MARKER",
    "refusal",
    "sign_store",
    "store_keys",
    "store_marker",
    "unproven_store_entries",
    "unvouched",
    "writer_version",
]

#: The root attribute of a map store that contactres wrote (a JSON string: see the module).
STORE_MARKER = "contactres_store"

_GENERATOR = "contactres"
_SHOWN = 3  # foreign names a refusal lists before "…"


def writer_version() -> str:
    """The installed version of contactres, for the records the writers keep (read at the
    first record: importlib.metadata costs ~40 ms of start-up, which a command that keeps no
    record, ``afm invert`` say, need not pay)."""
    from ._version import __version__

    return __version__


def refusal(what: str, given: str | os.PathLike, foreign: Sequence[str]) -> str:
    """The one-line refusal of an output ``given`` (``what``: "output folder", "output store")
    that holds the files ``foreign``, which contactres cannot show it wrote."""
    shown = ", ".join(foreign[:_SHOWN]) + (", …" if len(foreign) > _SHOWN else "")
    return (
        f"{what} {os.fspath(given)!r} holds files contactres did not write ({shown}); "
        "choose another path (nothing was changed)"
    )


def unvouched(folder: Path, names: Iterable[str], vouched: Iterable[str]) -> list[str]:
    """The ``names`` that exist in ``folder`` (as a file, a folder or a link, even a broken
    one) and are not in ``vouched`` (the names a manifest proves contactres wrote): the files
    a set of ``names`` must not overwrite."""
    proven = set(vouched)
    return sorted(n for n in set(names) - proven if os.path.lexists(folder / n))


def store_keys(store: Path) -> list[str]:
    """Every file and folder inside ``store``, as its path relative to it ('/'-separated;
    folders end in '/'), sorted. Links are listed, not followed."""
    keys = []
    for root, dirs, files in os.walk(store):
        rel = Path(root).relative_to(store).as_posix()
        prefix = "" if rel == "." else f"{rel}/"
        keys += [f"{prefix}{d}/" for d in dirs]
        keys += [f"{prefix}{f}" for f in files]
    return sorted(keys)


def _keys_digest(keys: Sequence[str]) -> str:
    return hashlib.sha256("\n".join(keys).encode("utf-8")).hexdigest()


def _root_metadata(store: Path) -> tuple[Path, list[str]]:
    """The file of a store's root attributes and the path to them in it: ``zarr.json``'s
    ``attributes`` (Zarr 3), else ``.zattrs`` (Zarr 2)."""
    if (store / "zarr.json").is_file():
        return store / "zarr.json", ["attributes"]
    return store / ".zattrs", []


def _read_json(path: Path) -> dict:
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return record if isinstance(record, dict) else {}


def store_marker(store: Path) -> dict:
    """The marker contactres left in the root attributes of ``store`` ({} if there is none or
    it is not one contactres wrote)."""
    path, inside = _root_metadata(store)
    attrs = _read_json(path)
    for key in inside:
        inner = attrs.get(key)
        attrs = inner if isinstance(inner, dict) else {}
    try:
        record = json.loads(str(attrs.get(STORE_MARKER, "")))
    except ValueError:
        return {}
    if not isinstance(record, dict) or record.get("generator") != _GENERATOR:
        return {}
    return record


def sign_store(store: Path) -> None:
    """Add contactres's marker (:data:`STORE_MARKER`: writer, version, the digest of the keys
    and the store's top-level names) to the root attributes of the complete ``store``.

    Rewrites only the root metadata file, whose name stays (the keys are unchanged); in Zarr 2
    the copy of the root attributes in the consolidated ``.zmetadata`` too. Called on the
    staging copy, before it is moved into place.
    """
    keys = store_keys(store)

    record = {
        "generator": _GENERATOR,
        "version": writer_version(),
        "keys": len(keys),
        "keys_sha256": _keys_digest(keys),
        "entries": sorted({k.split("/")[0] for k in keys}),
    }
    marker = json.dumps(record, separators=(",", ":"))
    path, inside = _root_metadata(store)
    meta = _read_json(path)
    attrs = meta
    for key in inside:
        attrs = attrs.setdefault(key, {})
    attrs[STORE_MARKER] = marker
    path.write_text(json.dumps(meta, indent=2, allow_nan=True), encoding="utf-8")
    consolidated = store / ".zmetadata"
    if not inside and consolidated.is_file():  # Zarr 2 keeps a second copy of .zattrs there
        meta = _read_json(consolidated)
        meta.setdefault("metadata", {}).setdefault(".zattrs", {})[STORE_MARKER] = marker
        consolidated.write_text(json.dumps(meta, indent=4, allow_nan=True), encoding="utf-8")


def unproven_store_entries(store: Path) -> list[str]:
    """What in the existing ``store`` contactres cannot show it wrote ([] if it may replace the
    store): every top-level entry of a store without contactres's marker; else the entries
    added since it was written (top-level names first, then files inside its arrays that are
    not metadata or chunks); a store whose keys differ otherwise gives one generic entry."""
    keys = store_keys(store)
    record = store_marker(store)
    if not record:
        return sorted({k.split("/")[0] for k in keys}) or ["(no marker)"]
    if record.get("keys_sha256") == _keys_digest(keys):
        return []
    known = set(map(str, record.get("entries", [])))
    added = sorted({k.split("/")[0] for k in keys} - known)
    if not added:  # inside an array: neither its metadata nor its chunks (the folder c/)
        added = [
            k.rstrip("/")
            for k in keys
            if "/" in k.rstrip("/")
            and k.split("/")[1] not in ("zarr.json", ".zarray", ".zattrs", "c")
            and not k.split("/")[1][:1].isdigit()
        ]
    return added or ["files added or removed since contactres wrote it"]
