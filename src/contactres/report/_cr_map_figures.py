"""Figures of a contact-resonance map (the ``afm_map`` job): the maps of k*, M (or E*) and tan δ
with scale bars and colour bars in their units, and the histograms of the same quantities.

Each function takes a :class:`contactres.jobs.afm_map.Result` and returns a matplotlib Figure
(object API, Agg canvas, a fixed layout; matplotlib imported when drawn), or None when the
map has nothing to draw (no pixel with k*). A map is drawn with row index y downwards, as the
image was scanned; the scale bar is a round length (1, 2 or 5 × 10^n m) near a fifth of the
image's width, in nm or µm; without a pixel size the axes count pixels and no bar is drawn.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["cr_histograms_figure", "cr_maps_figure", "scale_bar_length"]

#: Quantity -> (panel title, axis label, factor to the unit shown).
_SHOWN = {
    "k_star_N_per_m": ("contact stiffness k*", "k* (N/m)", 1.0),
    "M_Pa": ("indentation modulus M", "M (GPa)", 1e-9),
    "E_star_Pa": ("reduced modulus E*", "E* (GPa)", 1e-9),
    "sigma_N_s_per_m": ("contact damping σ", "σ (µN s/m)", 1e6),
    "tan_delta": ("loss tangent tan δ = ωσ/k*", "tan δ", 1.0),
}


def scale_bar_length(width_m: float) -> float:
    """A round length (1, 2 or 5 × 10^n m) no longer than a fifth of ``width_m`` (m) — at least
    the smallest such length above a tenth of it."""
    target = width_m / 5.0
    exponent = math.floor(math.log10(target))
    for mantissa in (5.0, 2.0, 1.0):
        length = mantissa * 10.0**exponent
        if length <= target * (1 + 1e-12):
            return length
    return 10.0**exponent  # pragma: no cover - the loop always returns (mantissa 1)


def _length_text(length_m: float) -> str:
    if length_m >= 1e-6:
        return f"{length_m * 1e6:g} µm"
    return f"{length_m * 1e9:g} nm"


def _quantities(ds) -> list[str]:
    """k*, the modulus the map has (M, else E*, else σ) and tan δ, those with a finite value."""
    modulus = next(
        (n for n in ("M_Pa", "E_star_Pa", "sigma_N_s_per_m") if np.isfinite(ds[n].values).any()),
        None,
    )
    names = ["k_star_N_per_m", modulus, "tan_delta"]
    return [n for n in names if n is not None and np.isfinite(ds[n].values).any()]


def _title(ds, name: str) -> str:
    """The panel's title; σ standing in for a modulus that was asked for but is NaN on every
    pixel says so (the modulus flags tell why), rather than swapping the panel silently."""
    title = _SHOWN[name][0]
    if name == "sigma_N_s_per_m" and ds.attrs.get("modulus_method", "none") != "none":
        title += " (M is NaN: see modulus_flags)"
    return title


def _pixel_size(ds) -> tuple[float, float] | None:
    """(dx, dy) in m from the coordinates, or None (pixel indices, or a single row/column)."""
    x, y = ds["x"], ds["y"]
    if x.attrs.get("units") != "m" or x.size < 2 or y.size < 2:
        return None
    return float(x.values[1] - x.values[0]), float(y.values[1] - y.values[0])


def _robust_limits(values):
    """Colour range over the 1st-99th percentiles (a few wild pixels do not wash out the map)."""
    v = values[np.isfinite(values)]
    lo, hi = (float(x) for x in np.percentile(v, [1.0, 99.0]))
    # A uniform map (to round-off) is drawn as one colour, not as its rounding noise.
    mid, spread = 0.5 * (lo + hi), max(abs(lo), abs(hi), 1e-300)
    if hi - lo <= 1e-6 * spread:
        return mid - 0.01 * spread, mid + 0.01 * spread
    return lo, hi


def cr_maps_figure(result):
    """The maps of k*, M (or E*, or σ) and tan δ of an ``afm_map`` Result, side by side; None
    when no pixel has k*."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    ds = result.dataset
    names = _quantities(ds)
    if not names:
        return None
    # A fixed layout (constrained layout would double the time of drawing; the panels are alike).
    fig = Figure(figsize=(4.0 * len(names), 3.8))
    FigureCanvasAgg(fig)
    fig.subplots_adjust(left=0.02, right=0.94, bottom=0.04, top=0.88, wspace=0.3)
    step = _pixel_size(ds)
    h, w = ds["k_star_N_per_m"].shape
    for k, name in enumerate(names):
        _, label, factor = _SHOWN[name]
        title = _title(ds, name)
        ax = fig.add_subplot(1, len(names), k + 1)
        values = ds[name].values * factor
        lo, hi = _robust_limits(values)
        im = ax.imshow(
            np.ma.masked_invalid(values),
            cmap="viridis",
            vmin=lo,
            vmax=hi,
            interpolation="nearest",
            aspect=1.0 if step is None else step[1] / step[0],  # pixels to scale (dy/dx)
        )
        fig.colorbar(im, ax=ax, label=label, shrink=0.85)
        ax.set_title(f"({'abc'[k]}) {title}", fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
        if step is not None:
            _scale_bar(ax, step[0], w)
        else:
            ax.set_xlabel(f"{w} x {h} pixels", fontsize=8)
    fig.suptitle(f"Contact-resonance maps: {_source(result)}", fontsize=10)
    return fig


def _scale_bar(ax, step: float, width_px: int) -> None:
    """A white bar with its length, at the lower left, in data (pixel) coordinates."""
    # mpl_toolkits ships without type information (matplotlib's own package has it).
    from mpl_toolkits.axes_grid1.anchored_artists import (  # type: ignore[import-untyped]
        AnchoredSizeBar,
    )

    length = scale_bar_length(step * width_px)
    bar = AnchoredSizeBar(
        ax.transData,
        length / step,
        _length_text(length),
        "lower left",
        pad=0.4,
        color="white",
        frameon=False,
        size_vertical=max(width_px / 120.0, 0.5),
        fontproperties={"size": 8},
    )
    ax.add_artist(bar)


def cr_histograms_figure(result):
    """Histograms of k*, M (or E*, or σ) and tan δ of an ``afm_map`` Result (the finite pixels,
    with their median); None when no pixel has k*."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    ds = result.dataset
    names = _quantities(ds)
    if not names:
        return None
    fig = Figure(figsize=(4.0 * len(names), 3.0))  # a fixed layout, as the maps'
    FigureCanvasAgg(fig)
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.17, top=0.83, wspace=0.3)
    for k, name in enumerate(names):
        _, label, factor = _SHOWN[name]
        title = _title(ds, name)
        ax = fig.add_subplot(1, len(names), k + 1)
        v = ds[name].values * factor
        v = v[np.isfinite(v)]
        lo, hi = _robust_limits(v)
        counts, edges = np.histogram(v, bins=60, range=(lo, hi))
        ax.stairs(counts, edges, fill=True, color="0.35")  # one artist, not 60 bars
        med = float(np.median(v))
        ax.axvline(med, color="C1", lw=1.2, label=f"median {med:.4g}")
        ax.set_xlabel(label)
        ax.set_ylabel("pixels")
        ax.set_title(f"({'abc'[k]}) {title}", fontsize=9)
        ax.legend(fontsize=7, frameon=False)
    fig.suptitle(f"Histograms (1st-99th percentile): {_source(result)}", fontsize=10)
    return fig


def _source(result) -> str:
    from pathlib import Path

    from .figures import LABEL_CHARS

    name = Path(str(result.source)).name.replace("$", r"\$")
    return name if len(name) <= LABEL_CHARS else name[: LABEL_CHARS - 1] + "…"
