"""Atomic file output: results appear whole or not at all, and inputs are never touched."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from functools import cache
from pathlib import Path

__all__ = ["atomic_path", "ensure_dir", "save_figure", "write_csv", "write_text"]


def ensure_dir(folder: str | os.PathLike) -> Path:
    """Create ``folder`` (and parents) if needed; error if it exists and is not a directory."""
    p = Path(folder)
    if p.exists() and not p.is_dir():
        raise ValueError(f"output folder {str(p)!r} exists and is not a directory")
    p.mkdir(parents=True, exist_ok=True)
    return p


@cache
def _new_file_mode() -> int:
    """The permissions open() gives a new file: 0o666 less the umask (read once per process,
    as os.umask can only be read by setting it)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success rename it onto ``path`` atomically.

    On an exception the temporary file is removed and ``path`` is left as it was. The result
    gets the permissions a plain write would give it (those of the file it replaces, else the
    umask default), not the owner-only mode of the temporary file.
    """
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        try:
            mode = target.stat().st_mode & 0o7777
        except FileNotFoundError:
            mode = _new_file_mode()
        os.chmod(tmp_path, mode)
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
