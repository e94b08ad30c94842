"""Folders of figures and their tables written as result sets (issue 27).

``contactres figures paper1|paper2`` and the parts of ``contactres demo`` write each of their
folders as one :class:`contactres.fileio.ResultSet`: the folder gets a ``manifest.json``, a rerun
replaces only the files a manifest shows contactres wrote, and a file of the user's under one of
the output names is refused (one line, before the work) instead of overwritten.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path

from ..fileio import CSV_FLOAT_FORMAT, ResultSet, save_figure, write_csv

# Every format a figure can be saved in (``--figure-format``): a set owns its figures in all of
# them, so a rerun in PNG removes the SVG an earlier run wrote (only if the manifest vouches).
_FIGURE_SUFFIXES = ("png", "svg", "pdf")


def figure_names(stems: Iterable[str], figure_formats: Sequence[str]) -> tuple[str, ...]:
    """The files of figures ``stems``: ``STEM.csv`` (the plotted numbers), then ``STEM.FMT``
    for each of ``figure_formats``."""
    return tuple(f"{stem}.{suffix}" for stem in stems for suffix in ("csv", *figure_formats))


def figures_set(
    folder, stems: Sequence[str], figure_formats: Sequence[str], kind: str
) -> ResultSet:
    """The result set of the figures ``stems`` (with their tables) in ``folder``; ``kind``
    names the set in its manifest (a folder of another kind is refused)."""
    return ResultSet(
        folder,
        names=figure_names(stems, figure_formats),
        owned=figure_names(stems, _FIGURE_SUFFIXES),
        kind=kind,
    )


def write_figures(rs: ResultSet, drawn, figure_formats: Sequence[str]) -> list[Path]:
    """Write ``drawn`` (``(stem, figure, table)`` each) into the open set ``rs``: the table as
    CSV, the figure in each of ``figure_formats``. Returns where the files are once in place."""
    names = []
    for stem, fig, table in drawn:
        write_csv(rs.path(f"{stem}.csv"), table, float_format=CSV_FLOAT_FORMAT)
        names.append(f"{stem}.csv")
        for i, fmt in enumerate(figure_formats):  # drawn once; the last save closes it
            save_figure(rs.path(f"{stem}.{fmt}"), fig, close=i == len(figure_formats) - 1)
            names.append(f"{stem}.{fmt}")
    return [rs.final(name) for name in names]
