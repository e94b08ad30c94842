"""The layout of every figure the package draws (issue 15, "figures fixed").

Each figure is drawn (Agg) and checked in display coordinates: no legend box holds a visible data
point or a point of a visible line (segments sampled densely), every labelled artist appears in
a legend, no axes is empty, and no error bar of a positive quantity goes below zero. An axes that
holds a table drawn as a figure (the gallery's ranking table and Table 1) has no data points: it
is checked instead for a table that lies wholly inside the figure.

The figures of the documentation (docs/gallery/scripts, docs/validation) are checked by running
each script as the plot directive does (:data:`SLOW_SCRIPTS` excepted).
"""

import runpy
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import Collection, LineCollection
from matplotlib.lines import Line2D

from contactres.apps import paper1, paper2
from contactres.report import figures

KLA = np.linspace(0.0, 2.0, 11)


@pytest.fixture(scope="module")
def results(example_analysis):
    return example_analysis(sphere_material="glass", plate_material="quartz-AT")


def _line_points(line: Line2D) -> np.ndarray:
    """Display coordinates of a line's markers, and of its segments sampled 20 times each."""
    xy = np.asarray(line.get_xydata(), float)
    xy = xy[np.isfinite(xy).all(axis=1)]
    pts = line.get_transform().transform(xy) if len(xy) else np.empty((0, 2))
    if line.get_linestyle() not in ("None", "none", "", " ") and len(pts) > 1:
        t = np.linspace(0.0, 1.0, 20)[:, None, None]
        pts = (pts[:-1] + t * (pts[1:] - pts[:-1])).reshape(-1, 2)
    return pts


def _collection_points(coll: Collection) -> np.ndarray:
    parts = [p.vertices for p in coll.get_paths() if len(p.vertices)]
    if not parts:
        return np.empty((0, 2))
    xy = np.concatenate(parts)
    return coll.get_transform().transform(xy[np.isfinite(xy).all(axis=1)])


def _inside(box, pts: np.ndarray) -> np.ndarray:
    """Which display points lie in a bounding box (edges included)."""
    x, y = pts[:, 0], pts[:, 1]
    return (x >= box.x0) & (x <= box.x1) & (y >= box.y0) & (y <= box.y1)


def _visible_points(ax) -> np.ndarray:
    """Every data point of the axes that is drawn inside it (clipped ones are not shown)."""
    pts = [_line_points(line) for line in ax.lines]
    pts += [_collection_points(c) for c in ax.collections]
    pts = np.concatenate([np.empty((0, 2)), *pts])
    return pts[_inside(ax.get_window_extent(), pts)] if len(pts) else pts


def _has_data(ax) -> bool:
    lines = any(np.isfinite(np.asarray(line.get_xydata(), float)).all(1).any() for line in ax.lines)
    return lines or any(len(c.get_paths()) for c in ax.collections)


def check_layout(fig) -> None:
    FigureCanvasAgg(fig)  # a Figure made without pyplot has a base canvas that draws nothing
    fig.canvas.draw()
    legends = [*fig.legends, *(ax.get_legend() for ax in fig.axes if ax.get_legend())]
    keyed = {t.get_text() for leg in legends for t in leg.get_texts()}
    for ax in fig.axes:
        if ax.tables and not ax.axison:  # a table drawn as a figure: no points, no legend
            box, inner = fig.bbox, ax.tables[0].get_window_extent(fig.canvas.get_renderer())
            assert box.x0 <= inner.x0 and inner.x1 <= box.x1, "table cut at the figure's sides"
            assert box.y0 <= inner.y0 and inner.y1 <= box.y1, "table cut at the figure's top"
            continue
        assert _has_data(ax), f"empty axes: {ax.get_title()!r}"
        pts = _visible_points(ax)
        for leg in legends:
            box = leg.get_window_extent()
            inside = _inside(box, pts)
            assert not inside.any(), f"legend over {inside.sum()} points of {ax.get_title()!r}"
        labels = {lab for lab in ax.get_legend_handles_labels()[1] if not lab.startswith("_")}
        assert labels <= keyed, f"not keyed: {labels - keyed}"


def _lower_error_ends(fig) -> np.ndarray:
    ends = [
        np.concatenate([seg[:, 1] for seg in coll.get_segments()])
        for ax in fig.axes
        for coll in ax.collections
        if isinstance(coll, LineCollection) and coll.get_segments()
    ]
    return np.concatenate(ends) if ends else np.empty(0)


MAKERS = {
    "fig4_sweeps": figures.figure_sweeps,
    "fig5_df0": figures.figure_stiffness,
    "fig7_dissipation": figures.figure_dissipation,
    "fig8_friction": figures.figure_friction,
    "radiation": figures.figure_radiation,
}


@pytest.mark.parametrize("name", MAKERS)
def test_analysis_figures(results, name):
    fig = MAKERS[name](results)
    check_layout(fig)
    if name != "fig4_sweeps":
        # every quantity with error bars (Δf0, ΔΓ0, loss tangents, μ) is >= 0
        assert _lower_error_ends(fig).size and (_lower_error_ends(fig) >= 0).all()
    assert fig.legends, "the key is below the panels"


PAPER_FIGURES = {
    "paper1_fig2": lambda f=paper1.displacement_figure: f(kla=(0.5, 1.5)),
    "paper1_fig3": lambda f=paper1.fig3_models: f(kla=KLA),
    "paper1_fig4": lambda f=paper1.fig4_anisotropy: f(kla=KLA, zeners=(0.5, 2.0)),
    "paper1_fig5": lambda f=paper1.fig5_poisson: f(kla=KLA, nus=(0.2, 0.3)),
    "paper1_ranking": lambda f=paper1.model_ranking: f(kla=KLA, zeners=(0.5, 2.0)),
    "paper1_crystals": lambda: paper1.crystals_figure(names=("KCl", "Cu"), kla=KLA),
    # the demo's figure (paper1-dcsf/): the exact punch on real crystals
    "demo_crystals_exact": lambda: paper1.crystals_figure(
        names=("KCl", "Cu"), kla=np.linspace(0.0, 2.0, 6), model="exact"
    ),
    "paper2_loops": paper2.loops_figure,
    "paper2_shifts": paper2.shifts_figure,
}


@pytest.mark.parametrize("name", PAPER_FIGURES)
def test_paper_figures(name):
    fig, table = PAPER_FIGURES[name]()
    check_layout(fig)
    assert len(table) and fig.legends


def test_the_check_catches_a_legend_over_the_data():
    """The control: a legend placed on the curves fails the check."""
    fig, _ = paper2.shifts_figure()
    for leg in fig.legends:
        leg.remove()
    fig.legends.clear()
    ax = fig.axes[0]
    ax.legend(loc="upper left")  # both curves start there, at u0 = 0
    with pytest.raises(AssertionError, match="legend over"):
        check_layout(fig)


def test_coinciding_models_are_both_visible_and_say_so():
    fig, _ = paper1.model_ranking(kla=np.linspace(0.0, 2.0, 21))
    lines = {line.get_label(): line for line in fig.axes[0].lines}
    (wa2d,) = [lab for lab in lines if lab.startswith("WA2D")]
    assert "overlaps WA" in wa2d
    assert lines[wa2d].get_linestyle() == "--" and lines["WA"].get_linestyle() == "-"


def test_clipped_curves_are_named_in_the_title():
    fig, _ = paper1.fig3_models(kla=np.linspace(0.0, 2.0, 21))
    assert "cut at the y-range: SA model" in fig._suptitle.get_text()


def test_write_paper1_figures_reports_progress(tmp_path, monkeypatch):
    # The job reads its grids when it runs: the coarse ones of PAPER_FIGURES (what is tested is
    # the progress and the files, not the curves; the paper's grids take 3 times the CPU).
    from contactres.jobs import paper1 as job

    monkeypatch.setattr(job, "KLA", KLA)
    monkeypatch.setattr(job, "DISPLACEMENT_KLA", (0.5, 1.5))
    monkeypatch.setattr(job, "ZENERS", (0.5, 2.0))
    monkeypatch.setattr(job, "POISSONS", (0.2, 0.3))
    steps = []
    written = paper1.write_paper1_figures(tmp_path, progress=steps.append)
    assert len(written) == 10
    assert steps[0] == "[1/5] paper1_fig2_displacement" and steps[-1].startswith("[5/5]")


DOCS = Path(__file__).resolve().parents[2] / "docs"
#: Documentation scripts left out for their run time (seconds, measured), each with the
#: package function whose figure the tests above check at a coarse resolution.
SLOW_SCRIPTS = {
    "convergence.py": "22 s; the convergence is tested in tests/dynamic/test_dynamic_exact.py",
    "tangential_disk.py": "26 s",
    "rigid_disk.py": "14 s",
    "paper1_crystals.py": "11 s; paper1.crystals_figure above",
    "paper1_fig2_displacement.py": "9 s; paper1.displacement_figure above",
    "paper1_fig4_anisotropy.py": "5 s; paper1.fig4_anisotropy above",
    "paper1_fig5_poisson.py": "5 s; paper1.fig5_poisson above",
    "paper1_model_ranking.py": "6 s; paper1.model_ranking above",
    "paper2_coating.py": "30 s; its contacts are tested in tests/normal/test_layered_contact.py",
}
DOC_SCRIPTS = sorted(
    p
    for p in [*(DOCS / "gallery" / "scripts").glob("*.py"), *(DOCS / "validation").glob("*.py")]
    if not p.name.startswith("_") and p.name not in SLOW_SCRIPTS
)


@pytest.mark.parametrize("path", DOC_SCRIPTS, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_documentation_figures(path, monkeypatch):
    """Each script run as the plot directive runs it: argv, working directory and sys.path."""
    monkeypatch.chdir(path.parent)
    monkeypatch.setattr(sys, "argv", [str(path)])
    monkeypatch.setattr(sys, "path", [str(path.parent), *sys.path])
    plt.close("all")
    try:
        runpy.run_path(str(path), run_name="__main__")
        assert plt.get_fignums(), "the script hands no figure to pyplot"
        for num in plt.get_fignums():
            check_layout(plt.figure(num))
    finally:
        plt.close("all")


@pytest.fixture(scope="module")
def particles():
    """``qcm particles`` on the bundled example (5e-7 m spheres of 2200 kg/m³ in water): the
    job's Result, computed once for the two tests that draw it."""
    from contactres.examples import example_path
    from contactres.jobs import qcm_particles

    settings = qcm_particles.Settings(5e-7, 2200.0, fundamental=5e6, medium="water")
    return qcm_particles.run(example_path("example_particles.csv"), settings)


def test_particle_figures(particles):
    """The figures of ``qcm particles`` on the bundled example (its first step identifies
    nothing: drawn without it)."""
    from contactres.report import _particle_figures as draw

    result = particles
    for make in (draw.overtones_figure, draw.plane_figure, draw.time_figure):
        fig = make(result)
        check_layout(fig)
    # κ, ξ and the coverage are positive: no error bar goes below zero
    assert _lower_error_ends(fig).size and (_lower_error_ends(fig) >= 0).all()


def test_the_particle_model_line_is_drawn_on_a_fine_grid_of_n(particles):
    """The model line of Δf_n/n against n runs through continuous n, not only the odd
    overtones, and is the forward model there (a coupled resonance between two overtones
    peaks between them)."""
    from contactres.report import _particle_figures as draw
    from contactres.resonators import WATER, Particle, particle_stiffness

    result = particles  # its settings: spheres of radius 5e-7 m, 2200 kg/m³, 5 MHz, in water
    fig = draw.overtones_figure(result)
    ax_f = fig.axes[0]
    lines = [ln for ln in ax_f.get_lines() if ln.get_linestyle() == "-" and len(ln.get_xdata()) > 2]
    assert lines
    checked = 0
    for line, t in zip(lines, result.model_curves["time_s"], strict=True):
        n = np.asarray(line.get_xdata(), float)
        assert n.size > 50 and np.any(np.abs(n - np.round(n)) > 0.2)
        # at the odd overtones the line goes through the fitted model of shifts.csv
        part = result.shifts[result.shifts["time_s"] == t]
        for order, model in zip(part["overtone"], part["df_model_Hz"], strict=True):
            np.testing.assert_allclose(np.interp(order, n, line.get_ydata()), model / order,
                                       rtol=1e-3, atol=1e-3)  # fmt: skip
        # ... and between them it is the particle load (paper 2, Eq. 1) at the fitted values
        row = result.particles.set_index("time_s").loc[t]
        if np.isnan(row["kappa_N_per_m"]):
            continue  # a step that identifies nothing (step 0, no particles)
        checked += 1
        k_l = particle_stiffness(Particle.sphere(5e-7, 2200.0), 5e6 * n, row["kappa_N_per_m"],
                                 row["xi_kg_per_s"], medium=WATER)  # fmt: skip
        df = (row["coverage_per_m2"] * k_l / (2 * n * np.pi**2 * 8.8e6)).real
        np.testing.assert_allclose(line.get_ydata(), df / n, rtol=1e-9, atol=1e-9)
    assert checked >= 3
