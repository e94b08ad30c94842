"""Figures of the jobs' Results, registered by :func:`contactres.report.writer.figure_registry`.

Each function takes a Result and returns a matplotlib Figure (Agg canvas, no pyplot state).
"""

from __future__ import annotations

__all__ = ["prediction_figure", "stiffness_figure"]


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


def prediction_figure(result):
    """The map of M of a :class:`contactres.jobs.maps_predict.Result` with the IPF-coloured
    legend of the faces (:func:`contactres.report.map_figures.modulus_map_figure`)."""
    from ..polycrystal.grains import folded_normals
    from ..polycrystal.maps import map_from_dataset
    from ..polycrystal.moduli import indentation_moduli
    from ..polycrystal.normal_table import surface_matrices_from_normals
    from .map_figures import modulus_map_figure

    ds, material, lattice = result.dataset, result.material, result.lattice
    omap = map_from_dataset(ds)
    return modulus_map_figure(
        ds["M_Pa"].values,
        folded_normals(omap, lattice),
        lattice,
        lambda n: indentation_moduli(material, surface_matrices_from_normals(n)),
        pixel_size=omap.step_x,
        material_name=material.name or "",
    )
