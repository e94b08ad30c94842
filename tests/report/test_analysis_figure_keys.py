"""Keys, bars and titles of the sweep analysis figures (issue 30, "Figures"): the key fits a
narrow figure, says what the bars are for one experiment, the bars are drawn above the markers,
and each panel of Fig. 4 names its load in full."""

import dataclasses
from importlib.resources import as_file, files

import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure

import contactres
from contactres.analysis import AnalysisSettings
from contactres.report import figures


def _analyze(keep=None):
    with as_file(files("contactres") / "data" / "example_sweeps.csv") as path:
        table = contactres.read_sweeps(path)
    if keep is not None:
        data = table.data[keep(table.data)].reset_index(drop=True)
        table = dataclasses.replace(table, data=data)
    settings = AnalysisSettings(bootstrap=0, sphere_material="glass", plate_material="quartz-AT")
    return contactres.analyze(table, settings=settings)


@pytest.fixture(scope="module")
def results(example_analysis):
    return example_analysis(sphere_material="glass", plate_material="quartz-AT")  # _analyze()


@pytest.fixture(scope="module")
def one_config():
    return _analyze(lambda d: d["configuration"] == d["configuration"].iloc[0])


@pytest.fixture(scope="module")
def one_experiment():
    return _analyze(lambda d: d["experiment"] == "e1")


def _drawn(fig):
    renderer = fig.canvas.get_renderer()
    fig.draw(renderer)
    return renderer


@pytest.mark.parametrize("draw", [figures.figure_stiffness, figures.figure_dissipation])
def test_the_key_of_a_one_panel_figure_lies_inside_it(one_config, draw):
    fig = draw(one_config)
    renderer = _drawn(fig)
    (legend,) = fig.legends
    box, page = legend.get_window_extent(renderer), fig.bbox
    assert page.x0 <= box.x0 and box.x1 <= page.x1
    assert page.y0 <= box.y0 and box.y1 <= page.y1


def test_a_key_too_wide_for_one_column_widens_the_figure():
    fig = Figure(figsize=(1.0, 1.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1], label="a label far wider than a figure of one inch, " * 2)
    figures.key_below(fig, ncols=3)
    renderer = _drawn(fig)
    assert fig.get_figwidth() > 1.0
    assert fig.legends[0].get_window_extent(renderer).x1 <= fig.bbox.x1


@pytest.mark.parametrize(
    "draw", [figures.figure_stiffness, figures.figure_dissipation, figures.figure_friction]
)
def test_one_experiment_is_not_called_mean_and_sd(one_experiment, draw):
    fig = draw(one_experiment)
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    media = [label for label in labels if not label.startswith("JKR")]
    assert media and all("one experiment: no error bars" in label for label in media)
    assert not any("sd over experiments" in label for label in labels)
    suptitle = fig.get_suptitle()
    assert "sd over experiments" not in suptitle


def test_several_experiments_keep_mean_and_sd(results):
    fig = figures.figure_dissipation(results)
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert all("mean ± sd over experiments" in label for label in labels)


def test_error_bars_are_drawn_above_the_markers(results):
    fig = figures.figure_dissipation(results)
    for ax in fig.axes:
        # the data markers (the caps are lines of marker "_", drawn with the bars)
        markers = [line for line in ax.lines if line.get_marker() not in ("None", "_")]
        bars = [c for c in ax.collections if isinstance(c, LineCollection)]
        assert markers and bars
        assert min(b.get_zorder() for b in bars) > max(m.get_zorder() for m in markers)


def test_every_panel_of_fig4_names_medium_configuration_load_and_experiment(results):
    fig = figures.figure_sweeps(results)
    sw = results.sweeps
    for ax in fig.axes:
        title = ax.get_title()
        assert any(m in title for m in sw["medium"].unique())
        assert any(c in title for c in sw["configuration"].unique())
        assert "F_N = " in title and " mN" in title
        assert any(f"exp. {e}" in title for e in sw["experiment"].unique())
