"""Atomic file output: results appear whole or not at all, and inputs are never touched."""

from __future__ import annotations

import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "ensure_dir", "save_figure", "write_csv", "write_text"]


def ensure_dir(folder: str | os.PathLike) -> Path:
    """Create ``folder`` (and parents) if needed; error if it exists and is not a directory."""
    p = Path(folder)
    if p.exists() and not p.is_dir():
        raise ValueError(f"output folder {str(p)!r} exists and is not a directory")
    p.mkdir(parents=True, exist_ok=True)
    return p


def _create_beside(target: Path) -> Path:
    """Create an empty, uniquely named hidden file beside ``target`` and return its path.

    Created with mode 0o666 so that the kernel applies the umask, as for a plain write (the
    owner-only mode of ``tempfile.mkstemp`` would leak into the result).
    """
    for _ in range(100):
        tmp = target.parent / f".{target.name}.{secrets.token_hex(6)}.tmp"
        try:
            fd = os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"no free temporary name beside {str(target)!r}")


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
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
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_csv(path: str | os.PathLike, frame, **kwargs) -> Path:
    """Write a pandas DataFrame as CSV atomically (no index unless asked)."""
    kwargs.setdefault("index", False)
    with atomic_path(path) as tmp:
        frame.to_csv(tmp, **kwargs)
    return Path(path)


def save_figure(path: str | os.PathLike, fig, dpi: int = 150) -> Path:
    """Save a matplotlib figure atomically and close it (no pyplot state leaks)."""
    import matplotlib.pyplot as plt

    target = Path(path)
    try:
        with atomic_path(target) as tmp:
            fig.savefig(tmp, dpi=dpi, format=target.suffix.lstrip(".") or "png")
    finally:
        plt.close(fig)
    return target
