"""Figures of the jobs' Results, registered by :func:`contactres.report._writer.figure_registry`.

Each function takes a Result and returns a matplotlib Figure (Agg canvas, no pyplot state), or
None when the Result has nothing to draw in that figure (no file is written then).

The QCM sweep analysis (a :class:`contactres.jobs.qcm_sweeps.Result`) has the figures of
paper 2 (Figs. 4, 5, 7, 8: :mod:`contactres.report.figures`), none when no sweep is used (Fig.
4's function says so once, a :class:`~contactres.measurements.SweepWarning`), and the
radiation loss where the analysis has it.
"""

from __future__ import annotations

import warnings

from ..errors import ContactresInputError

__all__ = [
    "dissipation_figure",
    "friction_figure",
    "load_figure",
    "prediction_figure",
    "radiation_figure",
    "stiffness_figure",
    "sweeps_figure",
]


def _drawn(result):
    """The analysis of a qcm_sweeps Result, or None when no sweep is used (nothing to draw)."""
    analysis = result.analysis
    return analysis if analysis.sweeps["used"].any() else None


def sweeps_figure(result):
    """Fig. 4 of paper 2: Δf and ΔΓ against u0 for a typical load and an unusual one, per
    medium, with the chosen models (a qcm_sweeps Result); with no sweep used, None and a
    SweepWarning that no figure is drawn."""
    from ..measurements import SweepWarning
    from .figures import NO_SWEEP_USED, figure_sweeps

    analysis = _drawn(result)
    if analysis is None:
        warnings.warn(NO_SWEEP_USED, SweepWarning, stacklevel=2)
        return None
    return figure_sweeps(analysis)


def load_figure(result):
    """Fig. 5 of paper 2: the low-amplitude Δf0 against F_N with the JKR fits."""
    from .figures import figure_stiffness

    analysis = _drawn(result)
    return None if analysis is None else figure_stiffness(analysis)


def dissipation_figure(result):
    """Fig. 7 of paper 2: ΔΓ0 and the loss tangent ΔΓ0/Δf0 against F_N."""
    from .figures import figure_dissipation

    analysis = _drawn(result)
    return None if analysis is None else figure_dissipation(analysis)


def friction_figure(result):
    """Fig. 8 of paper 2: the friction coefficient μ (from the slopes, from the exact-loop fit)
    against F_N."""
    from .figures import figure_friction

    analysis = _drawn(result)
    return None if analysis is None else figure_friction(analysis)


def radiation_figure(result):
    """Measured and radiation loss tangent per load, where the analysis has the radiation
    table (with rows) and a sweep is used."""
    from .figures import figure_radiation

    analysis = _drawn(result)
    radiation = None if analysis is None else analysis.radiation
    return None if radiation is None or not len(radiation) else figure_radiation(analysis)


def stiffness_figure(result):
    """κ and ωξ against time, one colour per overtone, the key right of the panels, titled by
    the export's name (a :class:`contactres.jobs.qcm_stiffness.Result`)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    title, result = result.source, result.stiffness
    fig = Figure(figsize=(7.5, 5.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax_k, ax_x = fig.subplots(2, 1, sharex=True)
    handles = []
    for j, (n, part) in enumerate(result.groupby("overtone")):
        style = {"color": f"C{j % 10}", "marker": ".", "ms": 2, "lw": 0.8}
        (line,) = ax_k.plot(part["time_s"], part["kappa_N_per_m"], **style)
        ax_x.plot(part["time_s"], part["omega_xi_N_per_m"], **style)
        handles.append((line, f"n = {n}"))
    ax_k.set_ylabel("κ per contact (N/m)")
    ax_x.set_ylabel("ωξ per contact (N/m)")
    ax_x.set_xlabel("time (s)")
    label = " ".join(str(title).split())
    label = (label if len(label) <= 60 else label[:59] + "…").replace("$", r"\$")
    fig.suptitle(f"{label}: contact stiffness (paper 2, Eq. 2)", fontsize=9)
    fig.legend(
        [h for h, _ in handles],
        [t for _, t in handles],
        loc="outside right upper",
        title="overtone",
        fontsize=8,
    )
    return fig


def prediction_if_legend(result):
    """:func:`prediction_figure`, or None (no file) for a result computed without its legend:
    the figure of a maps-predict result in a report."""
    return None if result.triangle is None else prediction_figure(result)


def prediction_figure(result):
    """The map of M of a :class:`contactres.jobs.maps_predict.Result` with the IPF-coloured
    legend of the faces (:func:`contactres.report.modulus_map_figure`): M over the standard
    triangle as the job computed it (``result.triangle``; a result without it, from
    ``Settings(legend=False)``, raises ContactresInputError)."""
    from ..polycrystal import folded_normals, map_from_dataset
    from ._map_figures import modulus_map_figure

    if result.triangle is None:
        raise ContactresInputError(
            "this maps-predict result has no legend (M over the standard triangle): run the "
            "job with Settings(legend=True) to draw its figure"
        )
    ds, material, lattice = result.dataset, result.material, result.lattice
    omap = map_from_dataset(ds)
    return modulus_map_figure(
        ds["M_Pa"].values,
        folded_normals(omap, lattice),
        lattice,
        result.triangle,
        pixel_size=omap.step_x,
        material_name=material.name or "",
    )
