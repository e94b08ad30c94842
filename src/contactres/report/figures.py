"""Figures of the sweep analysis (paper 2, Figs. 4, 5, 7, 8) as PNG, and the radiation loss.

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

from ..analysis.models import model_curves
from ..fileio import save_figure
from ..measurements.sweeps import SweepWarning
from ..tangential import kappa_jkr_mindlin

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "FIGURE_FILES",
    "LABEL_CHARS",
    "RADIATION_FIGURE",
    "figure_dissipation",
    "figure_friction",
    "figure_radiation",
    "figure_stiffness",
    "figure_sweeps",
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
#: Longest label from the data shown in a figure (longer ones end in an ellipsis).
LABEL_CHARS = 40

MARKERS = ("o", "s", "^", "D", "v", "P")
NM = 1e9


def _label(value) -> str:
    """A label from the data as plain text: shortened, and ``$`` escaped (no mathtext)."""
    text = " ".join(str(value).split())
    if len(text) > LABEL_CHARS:
        text = text[: LABEL_CHARS - 1] + "…"
    return text.replace("$", r"\$")


def _figure(nrows: int, ncols: int, width=3.2, height=2.6):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width * ncols, height * nrows), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def _media(results) -> list[str]:
    return sorted(results.sweeps["medium"].unique())


def _pick_examples(sw: pd.DataFrame, medium: str) -> list[pd.DataFrame]:
    """The used sweeps of one typical (Cattaneo-Mindlin) load and of one other-shaped load."""
    part = sw[(sw["medium"] == medium) & sw["used"]]
    keys = ["experiment", "configuration", "normal_force_N"]
    picks = []
    cm = part[part["model"] == "cattaneo-mindlin"]
    if len(cm):
        picks.append(part.merge(cm.iloc[[0]][keys], on=keys))
    other = part[part["model"].isin(["plateau", "savkoor"])]
    if len(other):
        picks.append(part.merge(other.iloc[[0]][keys], on=keys))
    return picks


def figure_sweeps(results) -> Figure:
    """Fig. 4: Δf and ΔΓ against u0 for a typical load and an unusual one, per medium.

    Points: the used ramps of one load of one experiment; lines: the model chosen for each sweep.
    """
    sw = results.sweeps
    p = results.padded
    index = {s: i for i, s in enumerate(p.sweeps)}
    media = _media(results)
    fig, axes = _figure(len(media), 4)
    for r, medium in enumerate(media):
        for c, sel in enumerate(_pick_examples(sw, medium)):
            ax_f, ax_g = axes[r, 2 * c], axes[r, 2 * c + 1]
            for k, (_, row) in enumerate(sel.iterrows()):
                i = index[row["sweep"]]
                u, df, dg = p.points(i)
                color = f"C{k % 10}"
                label = f"ramp {row['ramp']} ({row['direction']})"
                ax_f.plot(u * NM, df, MARKERS[k % 6], ms=3, color=color, label=label)
                ax_g.plot(u * NM, dg, MARKERS[k % 6], ms=3, color=color)
                uu = np.linspace(0.0, u.max(), 100)
                f, g = model_curves(row, uu)
                ax_f.plot(uu * NM, f, "-", lw=1, color=color)
                ax_g.plot(uu * NM, g, "-", lw=1, color=color)
            row = sel.iloc[0]
            title = (
                f"{_label(medium)}, {_label(row['configuration'])}, "
                f"F_N = {row['normal_force_N'] * 1e3:.3g} mN"
            )
            ax_f.set_title(f"{title}\n{row['model']}", fontsize=8)
            ax_g.set_title(f"exp. {_label(row['experiment'])}", fontsize=8)
            ax_f.legend(fontsize=6)
            for ax, lab in ((ax_f, "Δf (Hz)"), (ax_g, "ΔΓ (Hz)")):
                ax.set_xlabel("amplitude u0 (nm)")
                ax.set_ylabel(lab)
        for ax in axes[r]:
            if not ax.has_data():
                ax.set_axis_off()
    return fig


def _by_config(results):
    loads = results.loads
    return sorted(loads["configuration"].unique()), loads


def _errorbars(ax, loads, config, quantity, scale=1.0):
    for j, medium in enumerate(sorted(loads["medium"].unique())):
        part = loads[(loads["configuration"] == config) & (loads["medium"] == medium)]
        if part.empty:
            continue
        filled = j == 0
        ax.errorbar(
            part["normal_force_N"] * 1e3,
            part[f"{quantity}_mean"] * scale,
            yerr=np.nan_to_num(part[f"{quantity}_sd"].to_numpy() * scale),
            fmt=MARKERS[j % 6],
            color=f"C{j}",
            mfc=f"C{j}" if filled else "white",
            capsize=2,
            label=_label(medium),
        )


def figure_stiffness(results) -> Figure:
    """Fig. 5: low-amplitude Δf0 against F_N (mean ± sd over experiments) with the JKR fits."""
    configs, loads = _by_config(results)
    fig, axes = _figure(1, len(configs))
    for c, config in enumerate(configs):
        ax = axes[0, c]
        _errorbars(ax, loads, config, "df0_Hz")
        for g in sorted(results.groups, key=lambda g: g["medium"]):
            if g["configuration"] != config or not np.isfinite(g["E_Pa"]):
                continue
            part = loads[loads["configuration"] == config]
            F = np.linspace(0.0, part["normal_force_N"].max() * 1.05, 100)
            k = kappa_jkr_mindlin(F, g["E_Pa"], g["gamma_J_m2"], g["sphere_radius_m"], g["poisson"])
            ax.plot(
                F * 1e3,
                g["P_Hz_per_N_per_m"] * k,
                ":",
                color=f"C{sorted(loads['medium'].unique()).index(g['medium'])}",
                label=(
                    f"JKR {_label(g['medium'])}: E = {g['E_Pa'] / 1e9:.3g} GPa, "
                    f"γ = {g['gamma_J_m2'] * 1e3:.3g} mJ/m²"
                ),
            )
        ax.set_title(_label(config), fontsize=9)
        ax.set_xlabel("normal force per contact F_N (mN)")
        ax.set_ylabel("Δf0 (Hz)")
        ax.legend(fontsize=6)
    return fig


def figure_dissipation(results) -> Figure:
    """Fig. 7: ΔΓ0 (top) and the loss tangent ΔΓ0/Δf0 (bottom) against F_N."""
    configs, loads = _by_config(results)
    fig, axes = _figure(2, len(configs))
    for c, config in enumerate(configs):
        _errorbars(axes[0, c], loads, config, "dgamma0_Hz")
        _errorbars(axes[1, c], loads, config, "loss_tangent")
        axes[0, c].set_title(_label(config), fontsize=9)
        axes[0, c].set_ylabel("ΔΓ0 (Hz)")
        axes[1, c].set_ylabel("loss tangent ΔΓ0/Δf0")
        axes[1, c].set_xlabel("normal force per contact F_N (mN)")
        axes[0, c].legend(fontsize=6)
    return fig


def figure_friction(results) -> Figure:
    """Fig. 8: μ from the Δf slope, the ΔΓ slope and the exact-loop fit against F_N."""
    configs, loads = _by_config(results)
    kinds = (
        ("mu_df", "μ from Δf slope"),
        ("mu_dgamma", "μ from ΔΓ slope"),
        ("mu_fit", "μ, loop fit"),
    )
    fig, axes = _figure(len(configs), 3)
    for r, config in enumerate(configs):
        for c, (q, label) in enumerate(kinds):
            ax = axes[r, c]
            _errorbars(ax, loads, config, q)
            ax.set_title(f"{_label(config)}: {label}", fontsize=8)
            ax.set_xlabel("F_N (mN)")
            ax.set_ylabel("μ")
            if c == 0:
                ax.legend(fontsize=6)
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
            color, marker = f"C{j % 10}", MARKERS[j % 6]
            measured = ax.errorbar(
                F,
                part["tan_delta_measured"],
                yerr=np.nan_to_num(part["tan_delta_measured_sem"].to_numpy(float)),
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


def write_figures(results, folder: str | Path | Callable[[str], Path]) -> list[Path]:
    """Write Figs. 4, 5, 7, 8 (:data:`FIGURE_FILES`), and :data:`RADIATION_FIGURE` where the
    results have the radiation table; return the paths written.

    ``folder`` is a folder, or a function giving the path of each file name (such as
    :meth:`contactres.fileio.ResultSet.path`). With no used sweep (all are ramp 1, say) there is
    nothing to draw: no figure is written and a :class:`SweepWarning` says so.
    """
    where = folder if callable(folder) else (lambda name: Path(folder) / name)
    if not results.sweeps["used"].any():
        warnings.warn(
            "no sweep is used (all are ramp 1 or have too few points), so no figure is drawn; "
            "--keep-first-ramp (keep_first_ramp=True) uses ramp 1 too",
            SweepWarning,
            stacklevel=2,
        )
        return []
    makers = (figure_sweeps, figure_stiffness, figure_dissipation, figure_friction)
    written = [
        save_figure(where(name), make(results))
        for name, make in zip(FIGURE_FILES, makers, strict=True)
    ]
    if results.radiation is not None and len(results.radiation):
        written.append(save_figure(where(RADIATION_FIGURE), figure_radiation(results)))
    return written
