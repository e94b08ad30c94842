"""The one-draw PNG writer (contactres._png.print_png) against matplotlib's own savefig.

The reference is ``Figure.savefig`` (two draws: a hidden one for the layout, then the real one):
the decoded pixels must be equal, element for element, for figures that exercise what the
constrained layout and the tight box measure (titles, an offset text, a key outside the axes,
a shared axis, a suptitle), with and without ``bbox_inches="tight"``.
"""

from __future__ import annotations

import io

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from contactres._png import print_png


def _figure(layout: str | None) -> Figure:
    rng = np.random.default_rng(31)
    fig = Figure(figsize=(7.0, 3.5), layout=layout)
    axes = fig.subplots(1, 2, sharey=True)
    x = np.linspace(0.0, 1.0, 40)
    for i, ax in enumerate(axes):
        ax.plot(x, 1e-5 * (1 + x) + 1e-7 * rng.standard_normal(40), "o-", label=f"set {i}")
        ax.set_title(f"panel {i}: a title over an offset text")
        ax.set_xlabel("normal force F_N (mN)")
    axes[0].set_ylabel("Δf (Hz)")
    fig.suptitle("two panels")
    if layout is not None:
        fig.legend(loc="outside lower center", ncols=2)
    return fig


def _pixels(data: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(data)))


@pytest.mark.parametrize("layout", ["constrained", "compressed", None])
@pytest.mark.parametrize(("dpi", "tight"), [(150, False), (90, True), (100, True)])
def test_the_pixels_are_savefigs(layout, dpi, tight):
    reference = io.BytesIO()
    _figure(layout).savefig(
        reference, format="png", dpi=dpi, bbox_inches="tight" if tight else None
    )
    ours = io.BytesIO()
    fig = _figure(layout)
    engine, size = fig.get_layout_engine(), fig.get_size_inches().copy()
    print_png(fig, ours, dpi, tight=tight)
    a, b = _pixels(reference.getvalue()), _pixels(ours.getvalue())
    assert a.shape == b.shape
    assert np.array_equal(a, b)
    # The figure is left as it was: its engine (saved again later, e.g. as SVG), its size.
    assert fig.get_layout_engine() is engine
    assert np.array_equal(fig.get_size_inches(), size)


def test_a_figure_saved_twice_gives_the_same_pixels():
    fig = _figure("constrained")
    first, second = io.BytesIO(), io.BytesIO()
    print_png(fig, first, 100)
    print_png(fig, second, 100)
    assert np.array_equal(_pixels(first.getvalue()), _pixels(second.getvalue()))
