"""Figures of the sweep analysis (paper 2, Figs. 4, 5, 7, 8) as PNG, the radiation loss, and
the classification of the used sweeps (the HTML report's).

Object API only (:class:`matplotlib.figure.Figure`, Agg canvas): nothing touches pyplot's state,
and every figure is saved atomically and closed by :func:`contactres.fileio.save_figure`.
matplotlib is imported when a figure is drawn, not with this module (the report writes its
tables without it).

Labels from the data (configuration, medium, experiment) are shown as plain text, shortened to
:data:`LABEL_CHARS` characters: a ``$`` in a label is a dollar sign, not the start of mathtext,
and a label of 100 kB does not make the layout engine work for minutes.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from ..analysis import FIGURE_POINTS, figure_examples, sweep_rows
from ..errors import ContactresInputError
from ..fileio import save_figure
from ..measurements import SweepWarning

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "FIGURE_FILES",
    "LABEL_CHARS",
    "NO_SWEEP_USED",
    "RADIATION_FIGURE",
    "figure_classification",
    "figure_dissipation",
    "figure_friction",
    "figure_radiation",
    "figure_stiffness",
    "figure_sweeps",
    "key_below",
    "write_figures",
]

#: The files :func:`write_figures` writes (paper 2, Figs. 4, 5, 7, 8).
FIGURE_FILES = (
    "fig4_sweeps.png",
    "fig5_df0_vs_load.png",
    "fig7_dissipation_vs_load.png",
    "fig8_friction_vs_load.png",
)
#: The figure of the radiation table (written only when the results have one).
RADIATION_FIGURE = "radiation_loss.png"
#: What a report says when no sweep is used (all are ramp 1, say): there is nothing to draw.
NO_SWEEP_USED = (
    "no sweep is used (all are ramp 1 or have too few points), so no figure is drawn; "
    "--keep-first-ramp (keep_first_ramp=True) uses ramp 1 too"
)
#: Longest label from the data shown in a figure (longer ones end in an ellipsis).
LABEL_CHARS = 40

#: The columns of :attr:`~contactres.analysis.Results.curves` drawn: u0, Δf, ΔΓ.
_CURVE_COLUMNS = ("amplitude_m", "df_model_Hz", "dgamma_model_Hz")
_MARKERS = ("o", "s", "^", "D", "v", "P")
_NM = 1e9


def _label(value) -> str:
    """A label from the data as plain text: shortened, and ``$`` escaped (no mathtext)."""
    text = " ".join(str(value).split())
    if len(text) > LABEL_CHARS:
        text = text[: LABEL_CHARS - 1] + "…"
    return text.replace("$", r"\$")


def _figure(nrows: int, ncols: int, width=3.2, height=2.6, **share):
    fig = _blank(width * ncols, height * nrows)
    axes = fig.subplots(nrows, ncols, squeeze=False, **share)
    return fig, axes


def _blank(width: float, height: float) -> Figure:
    """An empty figure with the constrained layout (room for a key outside the panels)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def key_below(fig, extra=(), ncols: int = 3, fontsize=7) -> None:
    """One key for the whole figure, below the panels, so that it never covers data.

    The key holds the labelled artists of every axes, each label once (first wins), then the
    ``extra`` (handle, label) pairs (e.g. a proxy line saying what the lines are). Needs the
    constrained layout (``loc="outside ..."``).

    The key must fit the figure's width (a narrow figure, one panel say, would clip it on both
    sides): it takes fewer columns, down to one, until it fits, and a key of one column still
    wider than the figure widens the figure to hold it.
    """
    seen: dict[str, object] = {}
    for ax in fig.axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            seen.setdefault(label, handle)
    for handle, label in extra:
        seen.setdefault(label, handle)
    if not seen:
        return
    for n in range(min(ncols, len(seen)), 0, -1):
        legend = fig.legend(
            list(seen.values()),
            list(seen),
            loc="outside lower center",
            ncols=n,
            fontsize=fontsize,
        )
        width = _width_inches(fig, legend)
        if width is None or width <= 0.98 * fig.get_figwidth():
            return
        if n > 1:
            legend.remove()
        else:  # one column is still too wide: the figure grows to the key's width (a margin)
            fig.set_figwidth(width / 0.95)


def _width_inches(fig, artist) -> float | None:
    """The drawn width of ``artist`` in inches (None for a figure without an Agg renderer)."""
    get_renderer = getattr(fig.canvas, "get_renderer", None)
    if get_renderer is None:
        return None
    return float(artist.get_window_extent(get_renderer()).width / fig.dpi)


def figure_sweeps(results) -> Figure:
    """Fig. 4: Δf and ΔΓ against u0 for a typical load and an unusual one, per medium.

    Points: the used ramps of one load of one experiment (one marker and colour per ramp);
    lines: the model chosen for each sweep, in the colour of its ramp. Only the loads that
    exist are drawn (two pairs of panels per row, no empty panel); the key is below the panels.
    The loads are :func:`contactres.analysis.figure_examples`' (the analysis computes the
    curves on Fig. 4's grid for their sweeps); results whose curves lack that grid for a
    sweep drawn raise :class:`~contactres.errors.ContactresInputError`.
    """
    from matplotlib.lines import Line2D

    sw = results.sweeps
    points = sweep_rows(results.points)
    curves = results.curves[results.curves["grid_points"] == FIGURE_POINTS]
    curve = sweep_rows(curves)
    picks = figure_examples(sw)
    drawn = [s for _, sel in picks for s in sel["sweep"]]
    if not all(s in curve for s in drawn):
        # analyze(curve_grids=...) left out the figure's grid (or these sweeps on it).
        raise ContactresInputError(
            f"these results hold the fitted curves without Fig. 4's {FIGURE_POINTS}-point grid "
            "for the sweeps it draws: analyse with curve_grids=None (the default) or including "
            "it to draw the figures"
        )
    ramps = sorted(sw.loc[sw["used"], "ramp"].unique())
    per_row = 2 if len(picks) > 1 else 1
    nrows = -(-len(picks) // per_row)
    fig = _blank(3.2 * 2 * per_row, 2.6 * nrows + 0.5)
    grid = fig.add_gridspec(nrows, 2 * per_row)
    for n, (medium, sel) in enumerate(picks):
        r, c = divmod(n, per_row)
        ax_f, ax_g = fig.add_subplot(grid[r, 2 * c]), fig.add_subplot(grid[r, 2 * c + 1])
        for _, row in sel.iterrows():
            k = ramps.index(row["ramp"])
            pts = results.points.iloc[points[row["sweep"]]]
            u, df, dg = (pts[c].to_numpy() for c in ("amplitude_m", "df_Hz", "dgamma_Hz"))
            color, marker = f"C{k % 10}", _MARKERS[k % len(_MARKERS)]
            label = f"ramp {row['ramp']} ({row['direction']})"
            ax_f.plot(u * _NM, df, marker, ms=3, color=color, ls="none", label=label)
            ax_g.plot(u * _NM, dg, marker, ms=3, color=color, ls="none", label=label)
            fit = curves.iloc[curve[row["sweep"]]]  # computed by the analysis, not here
            uu, f, g = (
                fit[c].to_numpy() for c in ("amplitude_m", "df_model_Hz", "dgamma_model_Hz")
            )
            ax_f.plot(uu * _NM, f, "-", lw=1, color=color)
            ax_g.plot(uu * _NM, g, "-", lw=1, color=color)
        row = sel.iloc[0]
        title = (
            f"{_label(medium)}, {_label(row['configuration'])}, "
            f"F_N = {row['normal_force_N'] * 1e3:.3g} mN"
        )
        # Each panel names its load in full: a ΔΓ panel is read on its own too.
        title += f"\nexp. {_label(row['experiment'])}"
        ax_f.set_title(f"{title}, model: {row['model']}", fontsize=8)
        ax_g.set_title(title, fontsize=8)
        for ax, lab in ((ax_f, "Δf (Hz)"), (ax_g, "ΔΓ (Hz)")):
            ax.set_xlabel("amplitude u0 (nm)")
            ax.set_ylabel(lab)
    fit = Line2D([], [], color="0.3", lw=1)
    key_below(fig, [(fit, "line: model fitted to the ramp of its colour")], ncols=4)
    return fig


def _by_config(results):
    loads = results.loads
    return sorted(loads["configuration"].unique()), loads


def _top(mean, sd) -> float:
    """Top of a y-range from zero: every mean, the bars up to twice the 90th percentile."""
    mean, sd = np.asarray(mean, float), np.nan_to_num(np.asarray(sd, float))
    if not np.isfinite(mean).any():
        return 1.0
    reach = min(np.nanmax(mean + sd), 2.0 * np.nanpercentile(mean, 90))
    return 1.05 * max(np.nanmax(mean), reach)


def _from_zero(fig) -> None:
    """Every y-axis from zero, once all data are drawn (shared axes see all their data) —
    unless some data lie below zero (a negative mean must stay visible, not be cut off)."""
    for ax in fig.axes:
        lows = [
            np.nanmin(np.asarray(line.get_ydata(), dtype=float))
            for line in ax.get_lines()
            if np.size(line.get_ydata()) and np.isfinite(np.asarray(line.get_ydata(), float)).any()
        ]
        if not lows or min(lows) >= 0:
            ax.set_ylim(0.0, ax.get_ylim()[1])


def _has_data(loads, config, quantity) -> bool:
    part = loads[loads["configuration"] == config]
    return bool(np.isfinite(part[f"{quantity}_mean"].to_numpy(float)).any())


def _spread(n_experiments) -> str:
    """What the error bars of loads measured in ``n_experiments`` experiments (one count per
    load) are: a single experiment has no spread, so no bar, and the key must not promise one."""
    n = np.asarray(n_experiments, float)
    if not np.any(n > 1):
        return "one experiment: no error bars"
    if np.all(n > 1):
        return "mean ± sd over experiments"
    return "mean ± sd over experiments; no bar where one"


def _errorbars(ax, loads, config, quantity, scale=1.0):
    """Mean ± sd per medium; the lower bar stops at zero (every quantity drawn is >= 0).

    The bars are drawn above the markers (a filled marker would hide a short bar)."""
    for j, medium in enumerate(sorted(loads["medium"].unique())):
        part = loads[(loads["configuration"] == config) & (loads["medium"] == medium)]
        if part.empty:
            continue
        mean = part[f"{quantity}_mean"].to_numpy(float) * scale
        sd = np.abs(np.nan_to_num(part[f"{quantity}_sd"].to_numpy(float) * scale))
        lower = np.where(mean > 0, np.minimum(sd, np.abs(mean)), sd)
        markers, caps, bars = ax.errorbar(
            part["normal_force_N"] * 1e3,
            mean,
            yerr=np.vstack([lower, sd]),
            fmt=_MARKERS[j % 6],
            color=f"C{j}",
            mfc=f"C{j}" if j == 0 else "white",
            capsize=2,
            label=f"{_label(medium)} ({_spread(part['n_experiments'])})",
        )
        for artist in (*caps, *bars):
            artist.set_zorder(markers.get_zorder() + 0.5)


def figure_stiffness(results) -> Figure:
    """Fig. 5: low-amplitude Δf0 against F_N (mean ± sd over experiments, where more than one)
    with the JKR fits and their 95 % bands (shaded; ``Results.jkr``).

    A group whose fit is withheld, or whose fit has no band (Table 1's errors of E and γ give
    no covariance), is named in the key with the reason."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    configs, loads = _by_config(results)
    configs = [c for c in configs if _has_data(loads, c, "df0_Hz")] or configs
    media = sorted(loads["medium"].unique())
    fig, axes = _figure(1, len(configs), height=3.2, sharey=True)
    banded, notes = False, []
    for c, config in enumerate(configs):
        ax = axes[0, c]
        _errorbars(ax, loads, config, "df0_Hz")
        for g in sorted(results.groups, key=lambda g: g["medium"]):
            if g["configuration"] != config:
                continue
            where = f"{_label(config)}, {_label(g['medium'])}"
            if not np.isfinite(g["E_Pa"]):
                notes.append(f"{where}: no JKR fit ({', '.join(g.get('checks') or ['withheld'])})")
                continue
            # The curve the analysis computed with the fit (Results.jkr): drawn, not evaluated.
            curve = results.jkr[
                (results.jkr["configuration"] == config) & (results.jkr["medium"] == g["medium"])
            ]
            colour = f"C{media.index(g['medium'])}"
            F = curve["normal_force_N"].to_numpy() * 1e3
            ax.plot(
                F,
                curve["df0_model_Hz"].to_numpy(),
                ":",
                color=colour,
                label=(
                    f"JKR-Mindlin fit, {where}: "
                    f"E = {g['E_Pa'] / 1e9:.3g} GPa, γ = {g['gamma_J_m2'] * 1e3:.3g} mJ/m²"
                ),
            )
            lo, hi = (
                curve[col].to_numpy(float) if col in curve else np.full(len(curve), np.nan)
                for col in ("df0_model_lo_Hz", "df0_model_hi_Hz")
            )
            if np.isfinite(lo).any():
                ax.fill_between(F, lo, hi, color=colour, alpha=0.2, lw=0)
                banded = True
            else:
                notes.append(f"{where}: JKR fit without a band (its errors give no covariance)")
        ax.set_title(_label(config), fontsize=9)
        ax.set_xlabel("normal force per contact F_N (mN)")
        ax.set_ylabel("Δf0 (Hz)")
    _from_zero(fig)
    extra: list[tuple[object, str]] = [(Line2D([], [], ls="none"), note) for note in notes]
    if banded:
        extra.insert(0, (Patch(color="0.5", alpha=0.3, lw=0), "JKR fit, 95 % band"))
    key_below(fig, extra, ncols=2, fontsize=6)
    return fig


def figure_dissipation(results) -> Figure:
    """Fig. 7: ΔΓ0 (top) and the loss tangent ΔΓ0/Δf0 (bottom) against F_N.

    One column per configuration with data; each row shares its y-range, from zero."""
    configs, loads = _by_config(results)
    rows = [
        (q, lab)
        for q, lab in (("dgamma0_Hz", "ΔΓ0 (Hz)"), ("loss_tangent", "loss tangent ΔΓ0/Δf0 (-)"))
        if any(_has_data(loads, c, q) for c in configs)
    ] or [("dgamma0_Hz", "ΔΓ0 (Hz)")]
    configs = [c for c in configs if any(_has_data(loads, c, q) for q, _ in rows)] or configs
    fig, axes = _figure(len(rows), len(configs), height=2.4, sharey="row", sharex=True)
    for c, config in enumerate(configs):
        axes[0, c].set_title(_label(config), fontsize=9)
        axes[-1, c].set_xlabel("normal force per contact F_N (mN)")
        for r, (q, lab) in enumerate(rows):
            _errorbars(axes[r, c], loads, config, q)
            axes[r, c].set_ylabel(lab)
    _from_zero(fig)
    key_below(fig, ncols=2)
    return fig


def figure_friction(results) -> Figure:
    """Fig. 8: μ from the Δf slope, the ΔΓ slope and the exact-loop fit against F_N.

    Only the estimates with data get a column; each column (estimate) shares one y-range from
    zero that shows every mean (bars much longer than the spread of the means are cut at the
    top, which the title says)."""
    configs, loads = _by_config(results)
    kinds = [
        (q, label)
        for q, label in (
            ("mu_df", "μ from Δf slope"),
            ("mu_dgamma", "μ from ΔΓ slope"),
            ("mu_fit", "μ, loop fit"),
        )
        if any(_has_data(loads, c, q) for c in configs)
    ] or [("mu_df", "μ from Δf slope")]
    configs = [c for c in configs if any(_has_data(loads, c, q) for q, _ in kinds)] or configs
    fig, axes = _figure(len(configs), len(kinds), height=2.4, sharey="col", sharex=True)
    for c, (q, label) in enumerate(kinds):
        for r, config in enumerate(configs):
            ax = axes[r, c]
            _errorbars(ax, loads, config, q)
            ax.set_title(f"{_label(config)}: {label}", fontsize=8)
            ax.set_ylabel("friction coefficient μ (-)")
        axes[-1, c].set_xlabel("normal force per contact F_N (mN)")
        axes[0, c].set_ylim(0.0, _top(loads[f"{q}_mean"], loads[f"{q}_sd"]))
    spread = _spread(loads["n_experiments"])
    if spread.startswith("one"):
        fig.suptitle(spread, fontsize=8)
    else:
        fig.suptitle(f"error bars: {spread}, cut at 0 and at the top", fontsize=8)
    key_below(fig, ncols=2)
    return fig


def figure_radiation(results) -> Figure:
    """Measured loss tangent ΔΓ0/Δf0 (mean ± standard error, filled markers) and that of the
    sound radiated by the contact, Im K/Re K (open markers, dashed), against F_N; one panel per
    configuration, one colour per medium, the key below the panels (not over the data)."""
    table = results.radiation
    configs = sorted(table["configuration"].unique())
    media = sorted(table["medium"].unique())
    fig, axes = _figure(1, len(configs), width=3.4, height=2.8)
    key: dict[str, object] = {}  # label -> handle, measured then radiation per medium
    for c, config in enumerate(configs):
        ax = axes[0, c]
        for j, medium in enumerate(media):
            part = table[(table["configuration"] == config) & (table["medium"] == medium)]
            if part.empty:
                continue
            F = part["normal_force_N"].to_numpy(float) * 1e3
            color, marker = f"C{j % 10}", _MARKERS[j % 6]
            measured = ax.errorbar(
                F,
                part["tan_delta_measured"],
                yerr=_clipped(part["tan_delta_measured"], part["tan_delta_measured_sem"]),
                fmt=marker,
                color=color,
                capsize=2,
            )
            (radiated,) = ax.plot(
                F, part["tan_delta_rad"], marker + "--", color=color, mfc="white", lw=1
            )
            key.setdefault(f"{_label(medium)}: measured ΔΓ0/Δf0", measured)
            key.setdefault(f"{_label(medium)}: radiation Im K/Re K", radiated)
        ax.set_title(_label(config), fontsize=9)
        ax.set_xlabel("F_N per contact (mN)")
        ax.set_ylabel("loss tangent (-)")
        ax.set_ylim(bottom=0.0)
    first = table.iloc[0]
    fig.suptitle(
        f"sound radiated into sphere ({_label(first['sphere_material'])}) and plate "
        f"({_label(first['plate_material'])})",
        fontsize=9,
    )
    fig.legend(list(key.values()), list(key), loc="outside lower center", ncols=2, fontsize=7)
    return fig


#: Panels in a row of :func:`figure_classification`, and the size of each (inches).
_PANELS_PER_ROW = 3
_PANEL_INCHES = (2.6, 1.9)
#: The class of a used sweep without a model in :func:`figure_classification`.
_NO_MODEL = "no model"


def _classes(results, present) -> list[str]:
    """The model classes to draw: those the analysis counts per group (its order), then any
    other present in the data (sorted), then :data:`_NO_MODEL` where it occurs."""
    counted = [m for g in results.groups for m in g.get("models", {})]
    order = list(dict.fromkeys(counted))
    order += sorted(set(present) - set(order) - {_NO_MODEL})
    return order + ([_NO_MODEL] if _NO_MODEL in present else [])


def figure_classification(results) -> Figure | None:
    """The classification of the used sweeps (the HTML report, issue 30): per group
    (configuration, medium) one panel, per load one bar stacked by the model class chosen for
    its used sweeps; None when no sweep is used (nothing classified).

    The classes are in the order the analysis counts them (a group's ``models`` record), a
    used sweep without a model (too few points to fit, say) as "no model" (grey), each class in
    the same colour in every panel: the default cycle of the other figures from its third
    colour on (its first two mark the media there; a model class is not a medium). At most
    three panels a row, 2.6 x 1.9 inches each, so that the figure fits the page's content
    column (~8 inches at the page's 90 dpi) without shrinking.
    """
    sw = results.sweeps
    if not len(sw) or not sw["used"].any():
        return None
    used = sw[sw["used"].to_numpy(dtype=bool)]
    model = used["model"].where(used["model"].astype(str).str.len() > 0).fillna(_NO_MODEL)
    counts = pd.crosstab(
        [used["configuration"], used["medium"], used["normal_force_N"]], model.rename("model")
    )
    classes = _classes(results, counts.columns)
    counts = counts.reindex(columns=classes, fill_value=0)
    groups = list(dict.fromkeys((c, m) for c, m, _ in counts.index))
    ncols = min(_PANELS_PER_ROW, len(groups))
    nrows = -(-len(groups) // ncols)
    w, h = _PANEL_INCHES
    fig = _blank(w * ncols, h * nrows + 0.6)
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False, sharey=True)).ravel()
    colour = {m: ("0.6" if m == _NO_MODEL else f"C{(j + 2) % 10}") for j, m in enumerate(classes)}
    for ax, (config, medium) in zip(axes, groups, strict=False):
        part = counts.xs((config, medium), level=(0, 1))
        x = np.arange(len(part))
        bottom = np.zeros(len(part))
        for m in classes:
            n = part[m].to_numpy(float)
            if n.any():
                ax.bar(x, n, bottom=bottom, width=0.8, color=colour[m], label=m)
            bottom += n
        ax.set_xticks(x, [f"{f * 1e3:.3g}" for f in part.index], fontsize=7)
        ax.tick_params(axis="y", labelsize=7)
        ax.set_title(f"{_label(config)}, {_label(medium)}", fontsize=8)
        ax.set_xlabel("F_N (mN)", fontsize=7)
    for ax in axes[len(groups) :]:  # the empty places of the last row
        ax.set_visible(False)
    for r in range(nrows):
        axes[r * ncols].set_ylabel("used sweeps", fontsize=7)
    key_below(fig, ncols=len(classes), fontsize=7)
    return fig


def _clipped(mean, err) -> np.ndarray:
    """Asymmetric (2, n) error bars whose lower bar stops at zero."""
    mean, err = np.asarray(mean, float), np.abs(np.nan_to_num(np.asarray(err, float)))
    return np.vstack([np.where(mean > 0, np.minimum(err, np.abs(mean)), err), err])


def write_figures(results, folder: str | Path | Callable[[str], Path]) -> list[Path]:
    """Write Figs. 4, 5, 7, 8 (:data:`FIGURE_FILES`), and :data:`RADIATION_FIGURE` where the
    results have the radiation table; return the paths written.

    ``folder`` is a folder, or a function giving the path of each file name (such as
    :meth:`contactres.fileio.ResultSet.path`). With no used sweep (all are ramp 1, say) there is
    nothing to draw: no figure is written and a :class:`SweepWarning` says so.
    """
    where = folder if callable(folder) else (lambda name: Path(folder) / name)
    if not results.sweeps["used"].any():
        warnings.warn(NO_SWEEP_USED, SweepWarning, stacklevel=2)
        return []
    makers = (figure_sweeps, figure_stiffness, figure_dissipation, figure_friction)
    written = [
        save_figure(where(name), make(results))
        for name, make in zip(FIGURE_FILES, makers, strict=True)
    ]
    if results.radiation is not None and len(results.radiation):
        written.append(save_figure(where(RADIATION_FIGURE), figure_radiation(results)))
    return written
