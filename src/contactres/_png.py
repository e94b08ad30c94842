"""A matplotlib figure as PNG, drawn once (issue 31: the figures of a run cost more than its
analysis).

``Figure.savefig`` of a figure with a layout engine (ours use ``layout="constrained"``) draws
the figure twice: a first draw with the renderer's output switched off, only to run the layout
(and, with ``bbox_inches="tight"``, to measure the figure), then the real draw. Here the layout
runs on its own, on the same Agg canvas at the same resolution as ``savefig``'s first draw, the
tight box is measured after it, and the figure is printed with the layout engine set aside: one
draw. The pixels (and, at the default compression, the bytes) are those of ``savefig``.
:func:`print_figure` sends PNG here and any other format to ``savefig``; :func:`close_figure`
closes a figure for pyplot (both for :func:`contactres.fileio.save_figure`).
"""

from __future__ import annotations

import os
from typing import IO

import matplotlib as mpl
from matplotlib.backends.backend_agg import FigureCanvasAgg


def print_png(
    fig, target: str | os.PathLike | IO[bytes], dpi: float, *, tight: bool = False
) -> None:
    """Write ``fig`` as PNG to ``target`` (a path or a binary file) at ``dpi`` (dots per inch).

    ``tight``: crop to the figure's tight box padded by ``savefig.pad_inches`` (inches), as
    ``bbox_inches="tight"``. The figure is left with its canvas, resolution and layout engine.
    """
    engine = fig.get_layout_engine()
    forced = mpl.rcParams["figure.autolayout"] or mpl.rcParams["figure.constrained_layout.use"]
    if engine is None or forced:
        # One draw already (no layout), or an rcParam would put an engine back on the figure
        # (savefig then lays it out itself, as it always did).
        fig.savefig(target, format="png", dpi=dpi, bbox_inches="tight" if tight else None)
        return
    canvas, old_dpi = fig.canvas, fig.dpi
    try:
        # The canvas and resolution savefig's first draw would use: the text metrics (hinted,
        # not linear in dpi) and with them the layout depend on both.
        FigureCanvasAgg(fig)
        fig.dpi = dpi
        if fig.axes:  # as Figure.draw, which lays out axes only and lets a ValueError pass
            try:
                engine.execute(fig)
            except ValueError:
                pass
        box = None
        if tight:
            pad = mpl.rcParams["savefig.pad_inches"]
            box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(pad, pad)
        # No engine (not even the "none" placeholder): savefig then skips its first draw.
        fig.set_layout_engine(None)
        fig.savefig(target, format="png", dpi=dpi, bbox_inches=box)
    finally:
        fig.set_layout_engine(engine)
        fig.dpi = old_dpi
        fig.set_canvas(canvas)


def print_figure(fig, target: str | os.PathLike | IO[bytes], dpi: float, fmt: str) -> None:
    """Write ``fig`` to ``target`` in the format ``fmt`` (``png``, ``svg``, ``pdf``, ...) at
    ``dpi`` (dots per inch): PNG by :func:`print_png`, any other format by ``savefig``."""
    if fmt.lower() == "png":
        print_png(fig, target, dpi)
    else:
        fig.savefig(target, dpi=dpi, format=fmt)


def close_figure(fig) -> None:
    """Close ``fig`` for pyplot (no pyplot state leaks; a figure pyplot does not hold: no-op)."""
    import matplotlib.pyplot as plt

    plt.close(fig)
