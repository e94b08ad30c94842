"""``contactres demo``: the main job on bundled data, written into one folder.

Each part of the package contributes a step: a function ``step(out: Path) -> list[Path]`` that
writes its results into ``out`` (atomically, via :mod:`contactres.fileio`) and returns the
paths it wrote. Steps run in the order of :data:`DEMO_STEPS`.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from .fileio import ensure_dir, write_csv

__all__ = ["DEMO_STEPS", "run_demo"]


def _crystals_step(out: Path) -> list[Path]:
    from .crystals import crystal_table

    return [write_csv(out / "crystals.csv", crystal_table())]


#: (title, step) pairs run by :func:`run_demo`.
DEMO_STEPS: list[tuple[str, Callable[[Path], list[Path]]]] = [
    ("built-in crystals and their anisotropy", _crystals_step),
]


def run_demo(out: str | Path, progress: Callable[[str], None] | None = None) -> list[Path]:
    """Run every demo step into folder ``out``; return the files written."""
    folder = ensure_dir(out)
    written: list[Path] = []
    for title, step in DEMO_STEPS:
        if progress is not None:
            progress(title)
        written.extend(step(folder))
    return written
