"""File output: results appear whole or not at all, and inputs are never touched.

Single files are written atomically (``_atomic_path``, :func:`write_text`, :func:`write_csv`,
:func:`save_figure`): a temporary file beside the target is renamed onto it. A folder of results
that belong together is written as one :class:`ResultSet`:

* :func:`check_output` (:func:`check_output_file` for one file) first makes sure, writing
  nothing, that the folder can be written and that no output is an input (links resolved);
* a lock file beside the folder (``.<name>.contactres.lock``, ``O_EXCL``, holding process id and
  host) refuses a second run into it; the lock of a process that is gone is taken over;
* the files are written into a hidden staging folder beside the target, then moved into place as
  a whole: a folder holding nothing but an earlier set (or no folder) is swapped with the staging
  folder (``renameat2(RENAME_EXCHANGE)`` on Linux; else two renames, undone by the next run if a
  kill falls between them); a folder holding other files too (the data, say) gets the files one
  by one, its manifest removed first;
* ``manifest.json`` (:data:`MANIFEST`), written last, lists the files with sizes and SHA-256
  sums, the writer (``contactres`` and its version) and the kind of set (the job that wrote
  it); files of an earlier set that the new one lacks (its figures, say) are removed.

A set owns only the files it can show it wrote: those its kind's earlier manifest lists *and*
whose size and SHA-256 still match the record. A file someone else wrote or changed since is
never removed nor overwritten: a folder where a file of the set's names exists without such a
record (the user's ``stiffness.csv``, say), whose manifest contactres did not write, or that
holds another kind of set (``qcm stiffness`` results when ``qcm analyze`` writes, say), is
refused before anything is computed, in one line naming what is not contactres's
(:mod:`contactres._ownership`, the rule map stores follow too), and checked again under the
lock just before the move.

So a kill leaves the earlier set or the new one (plus hidden leftovers the next run removes).
Where the files go in one by one, the staging folder is first renamed to a committed folder
(``.commit``, with the list of the earlier set's files to remove): a kill before that rename
leaves the earlier set whole, a kill after it a folder without a manifest, whose move the next
run into the folder finishes before anything else, so that it holds the new set whole.
"""

from __future__ import annotations

import ctypes
import errno
import hashlib
import json
import os
import shutil
import sys
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from ._csvcells import CSV_FLOAT_FORMAT, csv_to, neutralised, npz_to
from ._csvcells import unique_written as unique_written  # (for the command line: its check)
from ._ownership import refusal, unvouched, writer_version
from .errors import ContactresInputError

__all__ = [
    "CSV_FLOAT_FORMAT",
    "MANIFEST",
    "OutputError",
    "ResultSet",
    "check_output",
    "check_output_file",
    "ensure_dir",
    "neutralised",
    "replace_folder",
    "save_figure",
    "write_bytes",
    "write_csv",
    "write_npz",
    "write_text",
]

#: The file of a result set written last: its files, sizes and SHA-256 sums.
MANIFEST = "manifest.json"


class OutputError(ContactresInputError):
    """An output folder that cannot (or must not) be written; the message says why."""


def ensure_dir(folder: str | os.PathLike) -> Path:
    """Create ``folder`` (and parents) if needed; error if it exists and is not a directory."""
    p = Path(folder)
    if p.exists() and not p.is_dir():
        raise ContactresInputError(f"output folder {str(p)!r} exists and is not a directory")
    p.mkdir(parents=True, exist_ok=True)
    return p


def _create_beside(target: Path) -> Path:
    """Create an empty, uniquely named hidden file beside ``target`` and return its path.

    Created with mode 0o666 so that the kernel applies the umask, as for a plain write (the
    owner-only mode of ``tempfile.mkstemp`` would leak into the result).
    """
    for _ in range(100):
        # os.urandom(6).hex() is secrets.token_hex(6) without importing secrets (random,
        # base64, hmac: ~10 ms of a one-file command such as afm invert to .npz)
        tmp = target.parent / f".{target.name}.{os.urandom(6).hex()}.tmp"
        try:
            fd = os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"no free temporary name beside {str(target)!r}")


@contextmanager
def _atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success rename it onto ``path`` atomically.

    On an exception the temporary file is removed and ``path`` is left as it was. The result
    gets the permissions a plain write would give it (those of the file it replaces, else the
    umask default), not the owner-only mode of the temporary file.
    """
    target = Path(path)
    tmp_path = _create_beside(target)
    try:
        yield tmp_path
        try:
            os.chmod(tmp_path, target.stat().st_mode & 0o7777)  # keep the replaced file's mode
        except FileNotFoundError:
            pass  # a new file keeps the umask default it was created with
        os.replace(tmp_path, target)
    except BaseException:
        tmp_path.unlink(missing_ok=True)
        raise


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (UTF-8)."""
    with _atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically."""
    with _atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def write_csv(path: str | os.PathLike, frame, **kwargs) -> Path:
    """Write a pandas DataFrame as CSV atomically (no index unless asked); text cells that a
    spreadsheet would run as formulas are neutralised (:func:`neutralised`). With pandas'
    default options the text is joined without pandas' writer: the same bytes, ~10x faster
    (``contactres._csvcells.csv_to``). A column name twice is a ValueError naming ``path``
    (``contactres._csvcells.unique_written``: a fault of the caller), and nothing is written."""
    with _atomic_path(path) as tmp:
        csv_to(tmp, frame, {"index": False, **kwargs}, str(path))
    return Path(path)


def write_npz(path: str | os.PathLike, frame) -> Path:
    """Write a pandas DataFrame atomically as a numpy archive (``.npz``, uncompressed): one
    array per column under its name, numbers as they are (float64 doubles: exact), text as
    unicode arrays (a gap is an empty string). Read back by the ``npz`` reader of
    :mod:`contactres.measurements.readers`, or by ``numpy.load(path, allow_pickle=False)``.
    A column name twice is a ValueError naming ``path``, and nothing is written."""
    with _atomic_path(path) as tmp:
        npz_to(tmp, frame, str(path))
    return Path(path)


def save_figure(path: str | os.PathLike, fig, dpi: int = 150, *, close: bool = True) -> Path:
    """Save a matplotlib figure atomically, in the format its suffix names (``.png``, ``.svg``,
    ``.pdf``; PNG without one), and close it (no pyplot state leaks); ``close=False`` keeps it
    open to be saved again in another format (the caller's last save closes it; a failed save
    closes it always)."""
    from ._png import close_figure, print_figure  # PNG drawn once, not twice as by savefig

    try:
        with _atomic_path(path) as tmp:
            print_figure(fig, tmp, dpi, Path(path).suffix.lstrip(".") or "png")
    finally:
        if close or sys.exc_info()[0] is not None:
            close_figure(fig)
    return Path(path)


# --------------------------------------------------------------------------------------------
# Result sets


def _writable(folder: Path) -> bool:
    return os.access(folder, os.W_OK | os.X_OK)


def _same_file(a: Path, b: Path) -> bool:
    """True if ``a`` and ``b`` name one file (symbolic links resolved; hard links by inode)."""
    if a.resolve() == b.resolve():
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:  # either does not exist: different files
        return False


def _named(path: str | os.PathLike, what: str) -> None:
    """OutputError for an empty name: Path("") is the current folder, where an empty --out
    wrote its files without a word (issue 27); "." says that on purpose."""
    if not os.fspath(path).strip():
        raise OutputError(
            f'{what} {os.fspath(path)!r} is empty: name one ("." for the current folder)'
        )


def check_output_file(path: str | os.PathLike, inputs: Iterable[str | os.PathLike] = ()) -> Path:
    """:func:`check_output` for one output file: OutputError (one line) when ``path`` is empty,
    a directory or one of ``inputs``, or its folder is missing or not writable."""
    _named(path, "output file")
    given, folder = Path(path), Path(path).resolve().parent
    if not folder.is_dir():
        raise OutputError(f"output {str(given)!r}: folder {str(given.parent)!r} does not exist")
    if not _writable(folder):
        raise OutputError(f"output {str(given)!r}: folder {str(given.parent)!r} is not writable")
    _check_names(folder, given.parent, [given.name], inputs)
    return folder / given.name


#: The writer recorded in a manifest (a manifest without it is refused unless it is an older
#: contactres one: file records with sizes and SHA-256 sums, names all of this kind of set).
_GENERATOR = "contactres"


def _read_manifest(folder: Path, name: str = MANIFEST) -> dict | None:
    """The manifest of ``folder`` (or its file ``name`` of the same layout) as a dict; None if
    there is none; {} if it cannot be read as a contactres manifest (not JSON, no ``files``
    table)."""
    path = folder / name
    if not path.is_file():
        return None
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    if not isinstance(record, dict) or not isinstance(record.get("files"), dict):
        return {}
    return record


def _plain_name(n: str) -> bool:
    # Never trust a path from a file: only names of files directly inside the folder.
    return Path(n).name == n and not n.startswith(".") and n != MANIFEST


def _manifest_owner(folder: Path, given: Path, kind: str, owned: frozenset[str]) -> dict:
    """The manifest of ``folder`` if this kind of set may take the folder over ({} if there is
    none); OutputError naming the folder if it holds a manifest contactres did not write or
    another kind of set (whose files would otherwise be removed or left without a record)."""
    record = _read_manifest(folder)
    if record is None:
        return {}
    names = [str(n) for n in record.get("files", {})]
    if record.get("generator") == _GENERATOR:
        if record.get("kind", "") != kind:
            raise OutputError(
                f"output folder {str(given)!r} holds the results of another command "
                f"({record.get('kind') or 'unnamed'!r} results, {MANIFEST}); choose another folder"
            )
    elif not record or not all(
        isinstance(r, dict) and "sha256" in r for r in record["files"].values()
    ):
        raise OutputError(
            f"output folder {str(given)!r} holds a {MANIFEST} that contactres did not write; "
            "choose another folder (its files are not touched)"
        )
    elif not set(names) <= owned:  # an older contactres manifest: its names tell its kind
        raise OutputError(
            f"output folder {str(given)!r} holds the results of another command ({MANIFEST} "
            f"lists {sorted(set(names) - owned)[0]!r}); choose another folder"
        )
    return record


def _verified_names(folder: Path, record: dict) -> set[str]:
    """The names of ``record`` (a manifest :func:`_manifest_owner` accepted) whose files in
    ``folder`` still have the recorded size and SHA-256: the files the earlier set wrote and
    nobody changed since. Only those may be removed."""
    out = set()
    for name, rec in record.get("files", {}).items():
        name = str(name)
        path = folder / name
        if not (_plain_name(name) and isinstance(rec, dict)):
            continue
        if path.is_file() and not path.is_symlink():
            try:
                same = _digest(path) == {"bytes": rec.get("bytes"), "sha256": rec.get("sha256")}
            except OSError:
                same = False
            if same:
                out.add(name)
    return out


def _leftover_temporary(name: str, owned: Iterable[str]) -> bool:
    """True for the hidden temporary of ``_atomic_path`` for one of ``owned``, left by a kill."""
    return (
        name.startswith(".")
        and name.endswith(".tmp")
        and any(name.startswith(f".{n}.") and len(name) == len(n) + 18 for n in owned)
    )


def check_output(
    folder: str | os.PathLike,
    names: Iterable[str] = (),
    inputs: Iterable[str | os.PathLike] = (),
) -> Path:
    """Check, without writing anything, that a result set may be written into ``folder``.

    ``folder``: the output folder (created later if missing); ``names``: every file name the
    set may write or remove in it; ``inputs``: the input files of the run (those that do not
    exist are ignored). Returns ``folder`` with symbolic links resolved. Raises
    :class:`OutputError`, one line naming the folder and the reason: an empty name, a path
    through a file, an existing file, a folder that cannot be created or written, a file of the
    set that is an input or a directory.
    """
    _named(folder, "output folder")
    given, target = Path(folder), Path(folder).resolve()
    nearest = target  # the folder, or the nearest of its parents that exists
    while not nearest.exists():
        nearest = nearest.parent
    if nearest == target:
        if not target.is_dir():
            raise OutputError(f"output folder {str(given)!r} exists and is not a directory")
        if not _writable(target):
            raise OutputError(f"output folder {str(given)!r} is not writable")
    elif not nearest.is_dir() or not _writable(nearest):
        why = "is not writable" if nearest.is_dir() else "is not a directory"
        raise OutputError(f"output folder {str(given)!r} cannot be created: {str(nearest)!r} {why}")
    _check_names(target, given, {*names, MANIFEST}, inputs)
    return target


def _check_names(target: Path, given: Path, names, inputs) -> None:
    """OutputError if a file ``name`` in ``target`` is a directory or one of ``inputs``."""
    present = [Path(p) for p in inputs if Path(p).exists()]
    for name in sorted(names):
        out = target / name
        if out.is_dir():
            raise OutputError(f"output {str(given / name)!r} is a directory, not a file")
        for src in present:
            if _same_file(out, src):
                raise OutputError(
                    f"output {str(given / name)!r} would overwrite the input {str(src)!r}; "
                    "choose another output"
                )


def _pid_alive(pid: int) -> bool:
    if os.name == "nt":  # no portable liveness check there: treat the lock as held
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # a process of another user
        pass
    return True


def _lock_holder(lock: Path) -> tuple[int, str] | None:
    """(pid, host) written in ``lock``; None if it cannot be read."""
    try:
        pid, host = lock.read_text(encoding="utf-8").split("\n")[:2]
        return int(pid), host
    except (OSError, ValueError):
        return None


def _exchange(a: Path, b: Path) -> bool:
    """Swap the paths ``a`` and ``b`` in one step (Linux ``renameat2(RENAME_EXCHANGE)``).

    Returns False where the system or the file system cannot (the caller then renames twice).
    """
    if not sys.platform.startswith("linux"):
        return False
    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError):  # a C library without renameat2 (glibc < 2.28, musl)
        return False
    fd, name = ctypes.c_int, ctypes.c_char_p
    renameat2.argtypes = [fd, name, fd, name, ctypes.c_uint]
    at_fdcwd, rename_exchange = -100, 2  # <fcntl.h>, <linux/fs.h>
    if renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(code, os.strerror(code), str(b))


def replace_folder(new: Path, target: Path, aside: Path) -> Path:
    """Put the folder ``new`` at the existing ``target``; return where the earlier one now lies:
    at ``new`` after a one-step exchange, else at ``aside`` after two renames."""
    if _exchange(new, target):
        return new
    os.rename(target, aside)
    os.rename(new, target)
    return aside


def _digest(path: Path) -> dict:
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return {"bytes": path.stat().st_size, "sha256": h.hexdigest()}


# Suffix of a staging folder whose set is complete and on its way into the folder, and the file
# in it that lists the earlier set's files to remove (hidden: never one of the set's files).
_COMMITTED, _JOURNAL = ".commit", ".stale.json"


def _roll_forward(committed: Path, folder: Path, owned: Iterable[str] = ()) -> None:
    """Move the files of a committed staging folder into ``folder``, remove the earlier set's
    files its journal lists (only those still as recorded: :func:`_verified_names`) and the
    leftover temporaries of ``owned``, the manifest last, then ``committed`` itself. Done again
    after a kill, it picks up where it stopped (moved files are gone from ``committed``; a
    manifest already moved in means the move was complete: the caller checks that
    ``committed`` still holds it)."""
    (folder / MANIFEST).unlink(missing_ok=True)  # no manifest while the set is mixed
    for p in sorted(p for p in committed.iterdir() if _plain_name(p.name)):
        _move_in(p, folder / p.name)
    stale = _verified_names(folder, _read_manifest(committed, _JOURNAL) or {})
    for p in folder.iterdir():
        if p.name in stale or _leftover_temporary(p.name, owned):
            if p.is_file() and not p.is_symlink():
                p.unlink()
    _move_in(committed / MANIFEST, folder / MANIFEST)
    shutil.rmtree(committed, ignore_errors=True)


def _move_in(src: Path, dst: Path) -> None:
    """Move ``src`` onto ``dst`` atomically, copying if they lie on different file systems."""
    try:
        os.replace(src, dst)
    except OSError as exc:
        if exc.errno != errno.EXDEV:
            raise
        with _atomic_path(dst) as tmp:
            shutil.copyfile(src, tmp)


class ResultSet:
    """A folder of result files written as a whole (see the module docstring).

    Use as a context manager; write each file at :meth:`path`; on a normal exit the set is moved
    into place, on an exception (or a kill) the folder is left as it was::

        with ResultSet("out", names=["a.csv", "b.png"], inputs=["data.csv"]) as rs:
            frame.to_csv(rs.path("a.csv"))

    ``folder`` is the output folder (created if missing; symbolic links are followed); ``names``
    the files this run may write (:meth:`path` refuses others); ``inputs`` the input files of the
    run (no file of the set may be one of them); ``owned`` every name a set of this kind can
    hold; ``kind`` the name of that kind (the job's), recorded in the manifest. Files of an
    earlier set of the same kind that the new set lacks are removed if the earlier manifest lists
    them with their current size and SHA-256 (nothing else is ever removed), and a folder
    holding only such files (and its manifest) is replaced as a whole.

    Raises :class:`OutputError` on entering: see :func:`check_output`; the folder holds a
    manifest contactres did not write or one of another kind of set, or a file of ``names``
    that its manifest does not prove contactres wrote; or another run holds the lock. Where
    the folder's parent cannot be written but the folder itself can, the lock file and the
    staging folder live inside the folder (hidden) and the files are moved in one by one.
    """

    def __init__(
        self,
        folder: str | os.PathLike[str],
        *,
        names: Iterable[str] = (),
        inputs: Iterable[str | os.PathLike[str]] = (),
        owned: Iterable[str] = (),
        kind: str = "",
    ) -> None:
        self._name = os.fspath(folder)  # as given: Path("") would be the current folder
        self.given = Path(folder)
        self.kind = str(kind)
        self.names = tuple(names)
        self.inputs = tuple(inputs)
        self.owned = frozenset(owned) | frozenset(self.names)
        self.folder = self.given.resolve()
        self._workspace: Path | None = None
        self._staging: Path | None = None
        self._lock: Path | None = None
        self._created: list[Path] = []
        self._earlier: set[str] = set()

    # -- set-up ---------------------------------------------------------------------------

    def __enter__(self) -> ResultSet:
        _named(self._name, "output folder")
        self.folder = check_output(self.given, self.owned, self.inputs)
        _manifest_owner(self.folder, self.given, self.kind, self.owned)
        parent = self.folder.parent
        missing = [p for p in (parent, *parent.parents) if not p.exists()]
        try:
            for p in reversed(missing):
                p.mkdir()
                self._created.append(p)
            inside = not _writable(parent) and self.folder.is_dir()
            self._workspace = self.folder if inside else parent
            self._take_lock()
            self._clean_leftovers()
            self._refuse_unvouched(self._vouched())
            self._staging = self._new_dir("tmp")
        except BaseException:
            self._release(aborted=True)
            raise
        return self

    def check(self) -> None:
        """Make the checks of entering the with-block and leave, writing nothing: for a caller
        that opens the set only once its long work is done (OutputError as on entering)."""
        self.__enter__()
        self._release(aborted=True)

    @property
    def _work(self) -> Path:
        """The folder of the lock and the staging folders (chosen on entering the with-block)."""
        if self._workspace is None:
            raise RuntimeError("a ResultSet writes only inside its with-block")
        return self._workspace

    def _prefix(self) -> str:
        """Name prefix of the lock and the staging folders (hidden)."""
        if self._workspace == self.folder:
            return ".contactres"
        return f".{self.folder.name}.contactres"

    def _take_lock(self) -> None:
        import socket  # here: most commands never need it

        lock = self._work / f"{self._prefix()}.lock"
        for _ in range(2):
            try:
                fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                holder = _lock_holder(lock)
                if holder and holder[1] == socket.gethostname() and not _pid_alive(holder[0]):
                    lock.unlink(missing_ok=True)  # a killed run's lock: take it over
                    continue
                who = f"process {holder[0]} on {holder[1]}" if holder else "another process"
                raise OutputError(
                    f"output folder {str(self.given)!r} is being written by another contactres "
                    f"run ({who}; lock file {str(lock)!r}); wait for it to finish, or remove the "
                    "lock file if no such run exists"
                ) from None
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(f"{os.getpid()}\n{socket.gethostname()}\n")
            self._lock = lock
            return
        raise OutputError(f"could not take the lock file {str(lock)!r}")

    def _new_dir(self, kind: str) -> Path:
        for _ in range(100):
            p = self._work / f"{self._prefix()}-{os.urandom(6).hex()}.{kind}"
            try:
                p.mkdir()  # umask default, as a plain mkdir of the target would give
            except FileExistsError:
                continue
            return p
        raise OutputError(f"no free temporary folder name in {str(self._workspace)!r}")

    def _ours(self, p: Path) -> bool:
        """True for the lock and the staging folders of runs into this folder."""
        prefix = self._prefix()
        return p.name == f"{prefix}.lock" or (
            p.name.startswith(f"{prefix}-") and p.suffix in (".tmp", ".old", _COMMITTED)
        )

    def _clean_leftovers(self) -> None:
        """Finish or remove what killed runs into this folder left (we hold the lock: none is
        live): a committed set (complete, its move into the folder cut short) is moved in, a
        staging folder not yet committed is removed (the earlier set is still whole)."""
        left = [p for p in self._work.iterdir() if self._ours(p) and p.is_dir()]
        old = [p for p in left if p.suffix == ".old"]
        if not self.folder.exists() and len(old) == 1:
            os.rename(old[0], self.folder)  # a kill fell between the two renames of a swap
            left.remove(old[0])
        for p in left:
            if p.suffix == _COMMITTED and (p / MANIFEST).is_file() and self.folder.is_dir():
                _roll_forward(p, self.folder)
            shutil.rmtree(p, ignore_errors=True)

    def _vouched(self) -> set[str]:
        """The files of the folder the earlier set's manifest proves contactres wrote."""
        earlier = _manifest_owner(self.folder, self.given, self.kind, self.owned)
        return _verified_names(self.folder, earlier) if self.folder.exists() else set()

    def _refuse_unvouched(self, vouched: set[str]) -> None:
        """OutputError naming the files of the set that exist in the folder and that no
        manifest proves contactres wrote: they are never overwritten (issue 27)."""
        foreign = unvouched(self.folder, self.names, vouched)
        if foreign:
            raise OutputError(refusal("output folder", self.given, foreign))

    # -- writing --------------------------------------------------------------------------

    def path(self, name: str) -> Path:
        """Where to write the file ``name`` of the set (inside the staging folder)."""
        if self._staging is None:
            raise RuntimeError("ResultSet.path is only valid inside its with-block")
        if name not in self.names or Path(name).name != name or name == MANIFEST:
            # The caller's fault (a file it did not declare), never the user's input.
            raise KeyError(f"{name!r} is not one of the files declared for this result set")
        return self._staging / name

    def final(self, name: str) -> Path:
        """Where the file ``name`` is once the set is in place."""
        return self.given / name

    # -- commit or abort ------------------------------------------------------------------

    def __exit__(self, kind, value, tb) -> None:
        try:
            if kind is None:
                self._commit()
        finally:
            self._release(aborted=kind is not None)

    def _replaceable(self) -> bool:
        """True if the folder can be swapped as a whole: it holds nothing but an earlier result
        set and is not (nor holds) this process's working directory."""
        if self._workspace == self.folder:
            return False
        if not self.folder.exists():
            return True
        cwd = Path.cwd().resolve()
        if cwd == self.folder or self.folder in cwd.parents:
            return False
        # Swapping the folder drops every file of it that the new set does not write again:
        # only the earlier set's own (verified) files and the manifest may go that way.
        ours = self._earlier | set(self.names) | {MANIFEST}
        return all(
            (p.name in ours and p.is_file() and not p.is_symlink())
            or _leftover_temporary(p.name, self.owned)
            for p in self.folder.iterdir()
        )

    def _commit(self) -> None:
        staging = self._staging
        assert staging is not None, "made on entering, kept until the commit"
        staged = sorted(p.name for p in staging.iterdir() if not p.name.startswith("."))

        record = {
            "generator": _GENERATOR,
            "version": writer_version(),
            "kind": self.kind,
            "files": {name: _digest(staging / name) for name in staged},
        }
        write_text(staging / MANIFEST, json.dumps(record, indent=1) + "\n")
        # Checked again under the lock, just before the move: what the earlier set wrote now.
        earlier = _manifest_owner(self.folder, self.given, self.kind, self.owned)
        self._earlier = _verified_names(self.folder, earlier) if self.folder.exists() else set()
        self._refuse_unvouched(self._earlier)  # a file of the set's names put there meanwhile
        if self._replaceable():
            if not self.folder.exists():
                try:
                    os.rename(staging, self.folder)
                except OSError:
                    pass  # made meanwhile and not empty: move the files in one by one
                else:
                    self._staging = None
                    return
            else:
                os.chmod(staging, self.folder.stat().st_mode & 0o7777)
                old = self._work / f"{self._prefix()}-{os.urandom(6).hex()}.old"
                # self._staging now holds the earlier set: removed on release
                self._staging = replace_folder(staging, self.folder, old)
                return
        self._commit_in_place(staging, staged, earlier)

    def _commit_in_place(self, staging: Path, staged: list[str], earlier: dict) -> None:
        """Move the files in one by one (the folder holds other files that must stay).

        The staging folder, complete with its manifest and the record of the earlier set's
        files to remove (:data:`_JOURNAL`, their verified sizes and SHA-256), is first renamed
        to a committed folder in one step: from then on the new set is what the folder will
        hold. If the move is cut short (a kill), the next run into the folder finishes it
        (:meth:`_clean_leftovers`), so the folder ends with the earlier set whole (a kill
        before the rename) or the new one (after it), never a mixture; in between it has no
        manifest.
        """
        stale = {n: earlier["files"][n] for n in sorted(self._earlier - set(staged))}
        write_text(staging / _JOURNAL, json.dumps({"files": stale}, indent=1) + "\n")
        committed = staging.rename(staging.with_name(staging.stem + _COMMITTED))
        # Kept if the move fails half-way: the next run finishes it, nothing removes it before.
        self._staging = None
        _roll_forward(committed, self.folder, self.owned)

    def _release(self, aborted: bool) -> None:
        if self._staging is not None:
            shutil.rmtree(self._staging, ignore_errors=True)
            self._staging = None
        if self._lock is not None:
            self._lock.unlink(missing_ok=True)
            self._lock = None
        if aborted:  # remove the parent folders made for a set that was never written
            for p in reversed(self._created):
                try:
                    p.rmdir()
                except OSError:
                    break
        self._created = []
