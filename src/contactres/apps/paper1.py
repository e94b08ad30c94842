"""The figures of paper 1 (dynamic contact stiffness of a sphere on a cubic crystal, Figs. 2-5).

Abscissa: the longitudinal wave number k_l a = ω a √(ρ/C11) of the (001) face, as in the paper;
damping Q⁻¹ = 0.02. Every figure is written as PNG together with the CSV of the plotted numbers,
the folder as one result set (:func:`paper1_set`, with its ``manifest.json``: a rerun replaces
only what contactres wrote):

* Fig. 2: ``|u_z(r̄)|``/``|u_z(0)|`` across the contact (along [100]) for several k_l a,
  A = 0.5, ν = 0.25;
* Fig. 3: DCSF of the five displacement models at A = 0.5, ν = 0.25;
* Fig. 4: DCSF (WA) for A = 0.25, 0.5, 1, 2, 4 at ν = 0.25;
* Fig. 5: DCSF (WA) at A = 2 for ν = 0.1, 0.2, 0.25, 0.3, 0.4;
* the exact rigid-punch DCSF (:mod:`contactres.dynamic._exact`) on Figs. 3-5, and a ranking of
  the models by their largest relative error against it (k_l a <= 1 and <= 2).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure
from matplotlib.ticker import NullLocator

from ..fileio import ResultSet
from ..jobs import paper1 as job
from ..jobs.paper1 import KLA, LOSS, PAPER_MODELS
from ..materials import Material
from ..report.figures import key_below
from ._sets import figures_set, write_figures

__all__ = [
    "PAPER_MODELS",
    "crystal_dcsf_set",
    "crystals_figure",
    "dcsf_curves_figure",
    "displacement_figure",
    "fig3_models",
    "fig4_anisotropy",
    "fig5_poisson",
    "model_ranking",
    "paper1_set",
    "write_crystal_dcsf",
    "write_paper1_figures",
]

_cubic = job.cubic


def dcsf_curves_figure(
    curves: dict[str, np.ndarray],
    kla: np.ndarray,
    title: str,
    ylim=None,
    exact: dict[str, np.ndarray] | None = None,
):
    """Two panels, Re and Im of DCSF against k_l a, one line per labelled curve.

    ``exact`` (optional, same keys as ``curves`` or any subset) adds the exact rigid-punch curve
    of each case as a thin line of the same colour (label "... exact"). ``ylim`` clips both
    panels (the CSV keeps every value). Returns (figure, table): columns kla, curve, re, im.
    """
    fig = Figure(figsize=(8, 4.2), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2, sharex=True)
    rows = []
    exact = exact or {}
    beyond = []
    for i, (label, v) in enumerate(curves.items()):
        style = "-" if i == 0 else ("--", ":", "-.", (0, (5, 1, 1, 1)), (0, (1, 2)))[(i - 1) % 5]
        (line,) = ax1.plot(kla, v.real, linestyle=style, label=label)
        ax2.plot(kla, v.imag, linestyle=style, label=label)
        rows.append(pd.DataFrame({"kla": kla, "curve": label, "re": v.real, "im": v.imag}))
        if ylim is not None and np.any(
            (np.r_[v.real, v.imag] < ylim[0]) | (np.r_[v.real, v.imag] > ylim[1])
        ):
            beyond.append(label)
        if label in exact:
            e = exact[label]
            name = f"{label} exact" if len(curves) > 1 else "exact"
            for ax, part in ((ax1, e.real), (ax2, e.imag)):
                ax.plot(kla, part, color=line.get_color(), lw=0.8, alpha=0.7, label=name)
            rows.append(pd.DataFrame({"kla": kla, "curve": name, "re": e.real, "im": e.imag}))
    ax1.set_ylabel("Re DCSF (stiffness, -)")
    ax2.set_ylabel("Im DCSF (damping, -)")
    for ax, tag in ((ax1, "(a)"), (ax2, "(b)")):
        ax.set_xlabel("k_l a (-)")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.set_title(tag, fontsize=9, loc="left")
        if ylim is not None:
            ax.set_ylim(*ylim)
    if beyond:
        title += f"\ncut at the y-range: {', '.join(beyond)}"
    fig.suptitle(title, fontsize=9)
    key_below(fig, ncols=3 if len(curves) > 5 and not exact else min(len(curves), 5), fontsize=7)
    return fig, pd.concat(rows, ignore_index=True)


def fig3_models(kla=KLA, A: float = 0.5, nu: float = 0.25):
    """Fig. 3: the five displacement models at A = 0.5, ν = 0.25. Returns (figure, table)."""
    curves = job.fig3_curves(kla, A, nu)
    # SA has a pole where N(0) + N(1, 0) vanishes (k_l a ~ 1.88): clip as the paper does.
    title = f"Fig. 3: A = {A:g}, ν = {nu:g}, Q⁻¹ = {LOSS:g}"
    return dcsf_curves_figure(curves, kla, title, ylim=(-5, 6))


def _wa_with_exact(cases: dict[str, Material], kla, title: str):
    """WA curves of labelled materials, each with its exact rigid-punch curve (Figs. 4, 5)."""
    curves, exact = job.wa_with_exact(cases, kla)
    return dcsf_curves_figure(curves, kla, title, exact=exact)


def fig4_anisotropy(kla=KLA, zeners=(0.25, 0.5, 1.0, 2.0, 4.0), nu: float = 0.25):
    """Fig. 4: WA for several Zener ratios A at ν = 0.25. Returns (figure, table)."""
    cases = {f"A = {A:g}": _cubic(A, nu) for A in zeners}
    title = f"Fig. 4: WA model (thin: exact), ν = {nu:g}, Q⁻¹ = {LOSS:g}"
    return _wa_with_exact(cases, kla, title)


def fig5_poisson(kla=KLA, A: float = 2.0, nus=(0.1, 0.2, 0.25, 0.3, 0.4)):
    """Fig. 5: WA at A = 2 for several ν. Returns (figure, table)."""
    cases = {f"ν = {nu:g}": _cubic(A, nu) for nu in nus}
    title = f"Fig. 5: WA model (thin: exact), A = {A:g}, Q⁻¹ = {LOSS:g}"
    return _wa_with_exact(cases, kla, title)


def displacement_figure(kla=(0.3, 0.6, 0.9, 1.2, 1.7), A: float = 0.5, nu: float = 0.25):
    """Fig. 2: ``|u_z(r̄)|``/``|u_z(0)|`` along [100] under the oscillating flat-punch pressure.

    Returns (figure, table) with columns kla, rbar, re_N, im_N, abs_ratio.
    """
    return _draw_displacement(*job.displacement(kla, A, nu), A, nu)


def _draw_displacement(kla, rbar, N, ratio, A: float = 0.5, nu: float = 0.25):
    """Fig. 2 from :func:`contactres.jobs.paper1.displacement`: (figure, table)."""
    fig = Figure(figsize=(5.6, 3.6), layout="constrained")
    ax = fig.subplots()
    rows = []
    for i, k in enumerate(kla):
        ax.plot(rbar, ratio[i], label=f"k_l a = {k:g}")
        rows.append(
            pd.DataFrame(
                {
                    "kla": k,
                    "rbar": rbar,
                    "re_N": N[i].real,
                    "im_N": N[i].imag,
                    "abs_ratio": ratio[i],
                }
            )
        )
    ax.set_xlabel("r/a (-)")
    ax.set_ylabel("|u_z(r)| / |u_z(0)| (-)")
    ax.set_ylim(bottom=0)
    fig.legend(loc="outside right upper", fontsize=7)
    ax.set_title(f"Fig. 2: A = {A:g}, ν = {nu:g}, Q⁻¹ = {LOSS:g}, along [100]", fontsize=9)
    return fig, pd.concat(rows, ignore_index=True)


def crystals_figure(names=("RbI", "KCl", "W", "Cu", "Li"), kla=KLA, model: str = "WA"):
    """Fig. 4 for real crystals: DCSF of built-in crystals on their (001) faces (A from 0.25 to 9).

    Returns (figure, table) with columns kla, curve (crystal name with its A), re, im.
    """
    return _crystal_dcsf_figure(job.crystal_curves(names, kla, model), kla, model)


def _crystal_dcsf_figure(curves: dict, kla, model: str):
    """The crystals' DCSF curves drawn (figure, table)."""
    return dcsf_curves_figure(curves, kla, f"{model} model on (001) faces, Q⁻¹ = {LOSS:g}")


def model_ranking(kla=KLA, zeners=(0.25, 0.5, 1.0, 2.0, 4.0), nu: float = 0.25):
    """How far each approximate model is from the exact rigid punch (issue 7's question).

    For each A (ν = 0.25, Q⁻¹ = 0.02): the largest relative error ``|DCSF_model/DCSF_exact − 1|``
    over k_l a <= 1 and over k_l a <= 2. Returns (figure, table) with columns zener, model,
    max_rel_error_kla_le_1, max_rel_error_kla_le_2, rank_kla_le_1 (1 = closest to exact).
    """
    table = job.ranking_table(kla, zeners, nu)
    return _draw_ranking(table, zeners, nu), table


def _draw_ranking(table: pd.DataFrame, zeners, nu: float = 0.25):
    """The ranking figure from :func:`contactres.jobs.paper1.ranking_table`."""
    names = (*PAPER_MODELS, "WA2D")
    fig = Figure(figsize=(8, 4.0), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    labels = _coincident_labels(table, names)
    for ax, col, lim in zip(
        axes, ("max_rel_error_kla_le_1", "max_rel_error_kla_le_2"), ("1", "2"), strict=True
    ):
        for i, n in enumerate(names):
            t = table[table.model == n]
            twin = labels[n] != n  # drawn over an earlier model: open markers, dashed
            ax.semilogy(
                t.zener,
                t[col],
                marker=_RANK_MARKERS[i % len(_RANK_MARKERS)],
                ls="--" if twin else "-",
                mfc="none" if twin else None,
                ms=7 if twin else 5,
                label=labels[n],
            )
        ax.set_xscale("log")
        ax.xaxis.set_minor_locator(NullLocator())
        ax.set_xticks(list(zeners), [f"{A:g}" for A in zeners])
        ax.set_xlabel("Zener ratio A")
        ax.set_title(f"max |DCSF/exact − 1|, k_l a <= {lim}", fontsize=9)
    axes[0].set_ylabel("relative error (-)")
    fig.suptitle(
        f"Displacement models against the exact rigid punch, ν = {nu:g}, Q⁻¹ = {LOSS:g}",
        fontsize=9,
    )
    key_below(fig, ncols=3, fontsize=7)
    return fig


_RANK_MARKERS = ("o", "s", "^", "D", "v", "P", "X")


def _coincident_labels(table: pd.DataFrame, names) -> dict[str, str]:
    """Legend labels; a model whose errors are within 10 % of an earlier model's (the curves
    overlap on the log axis) says so, and is drawn dashed with open markers."""
    cols = ["max_rel_error_kla_le_1", "max_rel_error_kla_le_2"]
    values = {n: table.loc[table.model == n, cols].to_numpy(float) for n in names}
    labels = {}
    for i, n in enumerate(names):
        same = [m for m in names[:i] if np.allclose(values[n], values[m], rtol=0.1)]
        labels[n] = f"{n} (overlaps {same[0]}: within 10 %)" if same else n
    return labels


def crystal_dcsf_set(out, model: str = "exact") -> ResultSet:
    """The :class:`~contactres.fileio.ResultSet` of :func:`write_crystal_dcsf` in folder
    ``out``: ``crystals_dcsf_MODEL.csv`` and ``.png``, with the folder's ``manifest.json``."""
    return figures_set(out, [f"crystals_dcsf_{model}"], ("png",), kind="crystal_dcsf")


def write_crystal_dcsf(out, model: str = "exact", curves: dict | None = None) -> list[Path]:
    """The demo step of paper 1: :func:`crystals_figure` as PNG + CSV in folder ``out``.

    With the model the README recommends, the exact rigid punch (the paper's figure uses WA).
    ``out``: the folder (written as :func:`crystal_dcsf_set`; a file there under one of the
    names that contactres cannot show it wrote is refused, nothing is changed), or that set
    opened by the caller. ``curves``: :func:`contactres.jobs.paper1.crystal_curves` of that
    model, when computed already.
    """
    if not isinstance(out, ResultSet):
        with crystal_dcsf_set(out, model) as rs:
            return write_crystal_dcsf(rs, model, curves)
    if curves is None:
        fig, table = crystals_figure(model=model)
    else:
        # the grid the job computed the curves on, read when it runs (not the one imported)
        from ..jobs import paper1 as job

        fig, table = _crystal_dcsf_figure(curves, job.KLA, model)
    return write_figures(out, [(f"crystals_dcsf_{model}", fig, table)], ("png",))


def paper1_set(out, figure_formats=("png",)) -> ResultSet:
    """The :class:`~contactres.fileio.ResultSet` of :func:`write_paper1_figures` in folder
    ``out`` (``figure_formats`` as there): open it, or :meth:`~contactres.fileio.ResultSet.check`
    it, before the work, so that a file of the user's under one of the names is refused first
    (issue 27)."""
    return figures_set(out, job.STEMS, figure_formats, kind="paper1")


def write_paper1_figures(
    out,
    progress: Callable[[str], None] | None = None,
    result: job.Result | None = None,
    figure_formats=("png",),
) -> list[Path]:
    """Write Figs. 2-5 of paper 1 into folder ``out``; return the paths.

    ``out``: the folder (written as :func:`paper1_set`: with a ``manifest.json``; a file there
    under one of the names that contactres cannot show it wrote is refused,
    :class:`contactres.fileio.OutputError`, before the work, and nothing is changed), or that
    set opened by the caller. Each figure is written in every format of ``figure_formats``
    (PNG only by default; ``png``, ``svg``, ``pdf``: the CLI's ``--figure-format``), and its
    data as CSV beside it. ``result``: what :func:`contactres.jobs.paper1.run` returned (else it
    runs here, and ``progress``, optional, is called with the name of each figure before it is
    computed).
    """
    if not isinstance(out, ResultSet):
        with paper1_set(out, figure_formats) as rs:
            return write_paper1_figures(rs, progress, result, figure_formats)
    if result is None:
        result = job.run(None, job.Settings(), progress)
    kla = result.kla
    fig4_title = f"Fig. 4: WA model (thin: exact), ν = {0.25:g}, Q⁻¹ = {LOSS:g}"
    fig5_title = f"Fig. 5: WA model (thin: exact), A = {2.0:g}, Q⁻¹ = {LOSS:g}"
    drawn = (
        _draw_displacement(*result.fig2),
        dcsf_curves_figure(
            result.fig3, kla, f"Fig. 3: A = {0.5:g}, ν = {0.25:g}, Q⁻¹ = {LOSS:g}", ylim=(-5, 6)
        ),
        dcsf_curves_figure(result.fig4[0], kla, fig4_title, exact=result.fig4[1]),
        dcsf_curves_figure(result.fig5[0], kla, fig5_title, exact=result.fig5[1]),
        (_draw_ranking(result.ranking, result.zeners), result.ranking),
    )
    stems = zip(job.STEMS, drawn, strict=True)
    return write_figures(out, [(stem, fig, table) for stem, (fig, table) in stems], figure_formats)
