"""The loads Fig. 4 draws (paper 2): picked by the analysis (``figure_examples``), which
computes the curves on Fig. 4's grid for their sweeps only, and drawn by the report from them."""

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from contactres.analysis import FIGURE_POINTS, PAGE_POINTS, figure_examples
from contactres.analysis._examples import FIGURE_COLUMNS, drawn_in_figure
from contactres.errors import ContactresInputError
from contactres.report.figures import figure_sweeps

CM, PLATEAU, SAVKOOR, ELASTIC = "cattaneo-mindlin", "plateau", "savkoor", "elastic"


@pytest.fixture(scope="module")
def results(example_analysis):
    return example_analysis()


def _study() -> pd.DataFrame:
    """A small study whose picks are known by hand (see the test)."""
    rows = [  # sweep, medium, experiment, normal force (mN), used, model
        ("w1", "water", "A", 1.0, True, ELASTIC),
        ("w2", "water", "A", 2.0, True, ELASTIC),
        ("a1", "air", "A", 1.0, False, CM),
        ("a2", "air", "A", 2.0, True, ELASTIC),
        ("a3", "air", "A", 2.0, True, CM),
        ("a4", "air", "A", 2.0, False, PLATEAU),
        ("a5", "air", "B", 2.0, True, SAVKOOR),
        ("a6", "air", "B", 2.0, True, ELASTIC),
        ("a7", "air", "B", 3.0, True, PLATEAU),
        ("o1", "oil", "A", 1.0, False, CM),
        ("n1", "argon", "A", 1.0, True, CM),
        ("n2", "argon", "A", 1.0, True, PLATEAU),
        ("n3", "argon", "A", 4.0, True, CM),
        ("a8", "air", "A", 2.0, True, CM),  # the load of a2, a3 but on the single sphere
    ]
    sweep, medium, experiment, force, used, model = zip(*rows, strict=True)
    return pd.DataFrame(
        {
            "sweep": sweep,
            "medium": medium,
            "experiment": experiment,
            "configuration": ["single" if s == "a8" else "tripod" for s in sweep],
            "normal_force_N": np.array(force) * 1e-3,
            "used": used,
            "model": model,
        }
    )


def test_figure_examples_are_the_loads_picked_by_hand():
    # Media in sorted order. air: the first used Cattaneo-Mindlin sweep is a3 (a1 is not
    # used), its load (A, tripod, 2 mN) holds the used a2, a3 (a4 is not used; a8 is of the
    # same experiment and force but of the other configuration); the first used plateau
    # or Savkoor sweep is a5, load (B, 2 mN): a5, a6 (a7 is another load). argon: both kinds
    # first in load (A, 1 mN): drawn twice. oil: nothing used, nothing drawn. water: neither
    # kind, its first used load (A, 1 mN): w1.
    sw = _study()
    got = [(m, list(sel["sweep"])) for m, sel in figure_examples(sw)]
    assert got == [
        ("air", ["a2", "a3"]),
        ("air", ["a5", "a6"]),
        ("argon", ["n1", "n2"]),
        ("argon", ["n1", "n2"]),
        ("water", ["w1"]),
    ]
    for _, sel in figure_examples(sw):  # the sweeps' rows, every column
        want = sw[sw["sweep"].isin(sel["sweep"])].reset_index(drop=True)
        pd.testing.assert_frame_equal(sel, want)
    drawn = {"a2", "a3", "a5", "a6", "n1", "n2", "w1"}
    np.testing.assert_array_equal(drawn_in_figure(sw), sw["sweep"].isin(drawn).to_numpy())
    # The analysis passes FIGURE_COLUMNS alone: the same choice (a column the choice reads
    # and the list lacks would raise KeyError here).
    np.testing.assert_array_equal(drawn_in_figure(sw[FIGURE_COLUMNS]), drawn_in_figure(sw))
    assert not drawn_in_figure(sw.assign(used=False)).any()
    assert figure_examples(sw.assign(used=False)) == []


def _drawn_sweeps(fig, results) -> set:
    """The sweeps whose points a figure draws, read off its marker lines (u0 in nm, Δf or ΔΓ)
    by matching them to each sweep's points in ``Results.points``."""
    points = results.points
    by_data = {}
    for sweep, part in points.groupby("sweep", sort=False):
        u = tuple(part["amplitude_m"].to_numpy() * 1e9)
        by_data[(u, tuple(part["df_Hz"]))] = sweep
        by_data[(u, tuple(part["dgamma_Hz"]))] = sweep
    found = set()
    for ax in fig.axes:
        for line in ax.lines:
            if line.get_linestyle() == "None":  # the points; the curves are solid lines
                key = (tuple(line.get_xdata()), tuple(line.get_ydata()))
                found.add(by_data[key])
    return found


def test_the_figure_grid_holds_the_sweeps_fig4_draws(results):
    # By default the curves hold Fig. 4's grid for exactly the sweeps the drawn figure shows
    # (read off its points), and every curve line it draws has that grid's points.
    fig = figure_sweeps(results)
    drawn = _drawn_sweeps(fig, results)
    curves = results.curves
    held = set(curves.loc[curves["grid_points"] == FIGURE_POINTS, "sweep"])
    assert drawn == held
    assert 0 < len(held) < len(results.sweeps)
    solid = [line for ax in fig.axes for line in ax.lines if line.get_linestyle() == "-"]
    assert len(solid) == 2 * sum(len(sel) for _, sel in figure_examples(results.sweeps))
    assert {len(line.get_xdata()) for line in solid} == {FIGURE_POINTS}


def test_fig4_without_its_grid_for_a_sweep_it_draws_says_so(results):
    # Results whose curves lack Fig. 4's grid (curve_grids=(PAGE_POINTS,)), or lack it for
    # one sweep the figure draws: a one-line input error, not a KeyError.
    curves = results.curves
    figure = (curves["grid_points"] == FIGURE_POINTS).to_numpy()
    one = figure_examples(results.sweeps)[0][1]["sweep"].iloc[0]
    for drop in (figure, figure & (curves["sweep"] == one).to_numpy()):
        lacking = replace(results, curves=curves[~drop])
        with pytest.raises(ContactresInputError, match="curve_grids") as error:
            figure_sweeps(lacking)
        assert f"{FIGURE_POINTS}-point grid" in str(error.value)
        assert "\n" not in str(error.value)
    assert set(curves.loc[~figure, "grid_points"]) == {PAGE_POINTS}
