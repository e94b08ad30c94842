"""The points and fitted curves the analysis hands to the report (``Results.points``,
``Results.curves``), against the input table and the registered model of each sweep."""

import numpy as np
import pandas as pd
import pytest

from contactres.analysis._amplitude import Padded
from contactres.analysis._curves import (
    CURVE_GRIDS,
    FIGURE_POINTS,
    PAGE_POINTS,
    model_keys,
    sweep_points,
    sweep_rows,
)
from contactres.analysis._models import REGISTRY, exact_model, model_curves
from contactres.errors import ContactresInputError

LOOPS = {
    "cm-loop": "cattaneo-mindlin-loop",
    "savkoor-loop": "savkoor-loop",
    "plateau-loop": "plateau-loop",
}


@pytest.fixture(scope="module")
def results(example_analysis):
    return example_analysis()


def test_the_points_are_the_input_points_of_each_sweep(results):
    # No drift removed: the points fitted are the file's, amplitudes ascending in each sweep.
    data = results.table.data
    points = results.points
    assert len(points) == len(data)
    rows = sweep_rows(points)
    assert list(rows) == list(data["sweep"].drop_duplicates())
    for sweep, part in data.groupby("sweep", sort=False):
        part = part.sort_values("amplitude_m", kind="stable")
        got = points.iloc[rows[sweep]]
        for mine, given in (("amplitude_m", "amplitude_m"), ("df_Hz", "df_Hz"),
                            ("dgamma_Hz", "dgamma_Hz")):  # fmt: skip
            np.testing.assert_array_equal(got[mine].to_numpy(), part[given].to_numpy())


def test_points_of_sweeps_not_back_to_back_are_gathered_in_sweep_order():
    # A Padded whose sweeps do not lie back to back in its flat arrays (sweep b's points stored
    # before a's): the points are each sweep's own, in the order of its sweeps, not the arrays
    # as stored (written out here by hand).
    u = np.array([4.0, 5.0, 1.0, 2.0, 3.0])
    p = Padded(
        sweeps=np.array(["a", "b"], dtype=object),
        n=np.array([3, 2]),
        direction=np.array(["up", "up"]),
        start=np.array([2, 0]),
        points_u=u,
        points_df=10.0 * u,
        points_dg=100.0 * u,
    )
    points = sweep_points(p)
    assert list(points["sweep"]) == ["a", "a", "a", "b", "b"]
    np.testing.assert_array_equal(points["amplitude_m"], [1.0, 2.0, 3.0, 4.0, 5.0])
    np.testing.assert_array_equal(points["df_Hz"], [10.0, 20.0, 30.0, 40.0, 50.0])
    np.testing.assert_array_equal(points["dgamma_Hz"], [100.0, 200.0, 300.0, 400.0, 500.0])


@pytest.mark.parametrize("ids", [["a", "b"], [7, 3]])
def test_the_sweep_labels_are_the_column_pandas_makes_of_them(ids):
    # The points' sweep column is given its dtype from the distinct ids (not inferred from the
    # long column): the column pandas infers from the object array of the ids written out row
    # by row (str for text, object for other ids).
    u = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    p = Padded(
        sweeps=np.array(ids, dtype=object),
        n=np.array([3, 2]),
        direction=np.array(["up", "up"]),
        start=np.array([0, 3]),
        points_u=u,
        points_df=u,
        points_dg=u,
    )
    written = pd.DataFrame({"sweep": np.array([ids[0]] * 3 + [ids[1]] * 2, dtype=object)})
    pd.testing.assert_series_equal(sweep_points(p)["sweep"], written["sweep"])


def _drawn(sw: pd.DataFrame) -> list:
    """The sweeps Fig. 4 draws, read off figure_examples' loads, in the order of ``sw``."""
    from contactres.analysis import figure_examples

    drawn = {s for _, sel in figure_examples(sw) for s in sel["sweep"]}
    return [s for s in sw["sweep"] if s in drawn]


def test_the_curves_sweep_labels_are_each_sweep_once_per_grid_point(results):
    # Labels filled grid by grid in one array: the column pandas makes of them written out;
    # by default Fig. 4's grid first, for the sweeps it draws, then the page's for every sweep.
    ids = results.sweeps["sweep"].to_numpy(dtype=object)
    drawn = np.asarray(_drawn(results.sweeps), dtype=object)
    assert 0 < len(drawn) < len(ids)
    labels = np.concatenate([np.repeat(drawn, FIGURE_POINTS), np.repeat(ids, PAGE_POINTS)])
    written = pd.DataFrame({"sweep": labels})
    pd.testing.assert_series_equal(results.curves["sweep"], written["sweep"])
    grids = np.repeat(
        [FIGURE_POINTS, PAGE_POINTS], [len(drawn) * FIGURE_POINTS, len(ids) * PAGE_POINTS]
    )
    np.testing.assert_array_equal(results.curves["grid_points"], grids)


def test_every_sweep_has_its_model_on_each_grid(results):
    # Each curve is the registered function of the sweep's exact loop (every sweep of the
    # example takes its limits from one), evaluated sweep by sweep with the values of that
    # model's fit table (keyed by the parameters' keys); the analysis batches the sweeps.
    # Every sweep on the page's grid, the sweeps Fig. 4 draws on its grid.
    sw, curves = results.sweeps, results.curves
    assert sorted(curves["grid_points"].unique()) == sorted(CURVE_GRIDS)
    assert set(sw["limits_from"]) <= set(LOOPS)
    u_max = results.table.data.groupby("sweep")["amplitude_m"].max()
    for n in CURVE_GRIDS:
        part = curves[curves["grid_points"] == n]
        rows = sweep_rows(part)
        assert list(rows) == (_drawn(sw) if n == FIGURE_POINTS else list(sw["sweep"]))
        # Every sweep Fig. 4 draws, every ninth sweep on the page's grid.
        held = [i for i in range(len(sw)) if sw["sweep"].iloc[i] in rows]
        for i in held if n == FIGURE_POINTS else held[::9]:
            sweep, key = sw["sweep"].iloc[i], LOOPS[sw["limits_from"].iloc[i]]
            got = part.iloc[rows[sweep]]
            grid = np.linspace(0.0, u_max[sweep], n)
            np.testing.assert_array_equal(got["amplitude_m"].to_numpy(), grid)
            table = results.fits[key]
            assert table["sweep"].iloc[i] == sweep
            model = REGISTRY[key]
            f, g = model.function(grid, **{p.key: table[p.key].iloc[i] for p in model.parameters})
            np.testing.assert_allclose(got["df_model_Hz"], f, rtol=1e-12, atol=0)
            np.testing.assert_allclose(got["dgamma_model_Hz"], g, rtol=1e-12, atol=1e-12)


def test_by_default_figure_rows_are_those_of_an_analysis_with_every_sweep_on_both_grids(results):
    # The default (curve_grids=None) against an analysis that evaluates every sweep on both
    # grids (an explicit tuple): the page's rows the same, and Fig. 4's rows exactly the
    # explicit run's rows of the sweeps that figure draws (their curves do not depend on the
    # other sweeps evaluated with them).
    from contactres import AnalysisSettings, analyze

    both = analyze(
        results.table,
        settings=AnalysisSettings(bootstrap=0),
        curve_grids=(FIGURE_POINTS, PAGE_POINTS),
    ).curves
    ids = set(both["sweep"])
    assert list(sweep_rows(both[both["grid_points"] == FIGURE_POINTS])) == list(
        results.sweeps["sweep"]
    )
    mine = results.curves
    for n in (FIGURE_POINTS, PAGE_POINTS):
        want = both[both["grid_points"] == n]
        if n == FIGURE_POINTS:
            drawn = _drawn(results.sweeps)
            assert 0 < len(drawn) < len(ids)
            want = want[want["sweep"].isin(drawn)]
        got = mine[mine["grid_points"] == n]
        pd.testing.assert_frame_equal(
            got.reset_index(drop=True), want.reset_index(drop=True), check_exact=True
        )


def test_a_grid_of_some_sweeps_holds_their_curves_whatever_the_chunks(results, monkeypatch):
    # Each curve depends on its own sweep only: a grid that holds a random third of the sweeps
    # (seeded), evaluated in chunks of a few sweeps, holds exactly the rows of those sweeps in
    # a run of every sweep in the default chunks; a grid not named in held keeps every sweep;
    # a grid that holds none has no rows.
    from contactres.analysis import _curves
    from contactres.analysis._amplitude import pad_sweeps

    sw, fits = results.sweeps, results.fits
    padded = pad_sweeps(results.table.data)  # the example has no drift removed
    every = _curves.fitted_curves(sw, padded, fits, grids=(7, 11))
    some = np.random.default_rng(31).random(len(sw)) < 1 / 3
    assert 3 < some.sum() < len(sw) - 3
    monkeypatch.setattr(_curves, "CHUNK_POINTS", 40)  # chunks of 5 sweeps on the 7-point grid
    held = {7: some, 3: np.zeros(len(sw), bool)}
    part = _curves.fitted_curves(sw, padded, fits, grids=(7, 3, 11), held=held)
    chosen = set(sw["sweep"][some])
    want = pd.concat(
        [every[(every["grid_points"] == 7) & every["sweep"].isin(chosen)],
         every[every["grid_points"] == 11]]
    )  # fmt: skip
    pd.testing.assert_frame_equal(
        part.reset_index(drop=True), want.reset_index(drop=True), check_exact=True
    )
    with pytest.raises(ValueError, match="one boolean per sweep"):
        _curves.fitted_curves(sw, padded, fits, grids=(7,), held={7: some[1:]})


def test_a_sweep_without_a_usable_fit_gets_no_curve_and_the_others_keep_theirs(results):
    from contactres.analysis._amplitude import pad_sweeps
    from contactres.analysis._classify import fit_sweeps
    from contactres.analysis._curves import fitted_curves
    from contactres.analysis._models import fit_tables

    padded = pad_sweeps(results.table.data)
    sw, fields = fit_sweeps(padded)  # the named table and every fit's fields
    fits = fit_tables(sw["sweep"], fields)
    plateaus = sw.index[sw["limits_from"] == "plateau-loop"][:3]
    assert len(plateaus) == 3
    loop = fits["plateau-loop"]
    loop.loc[plateaus[0], "critical_displacement"] = np.nan  # the quadrature refuses it
    with pytest.raises(ValueError):
        model_curves(sw.loc[plateaus[0]], np.linspace(0.0, 1e-9, 5), loop.loc[plateaus[0]])
    curves = fitted_curves(sw.loc[plateaus], padded, fits, grids=(5,))
    broken = (curves["sweep"] == sw.loc[plateaus[0], "sweep"]).to_numpy()
    assert broken.sum() == 5
    assert curves.loc[broken, ["df_model_Hz", "dgamma_model_Hz"]].isna().all().all()
    assert np.isfinite(curves.loc[~broken, ["df_model_Hz", "dgamma_model_Hz"]]).all().all()


@pytest.mark.parametrize("c", [0.0, 1e-6, 0.3, 2.0, 10.0, 30.0])
def test_the_closed_form_loop_shape_is_the_quadrature_of_the_loop(c):
    # The curves' loop shapes (closed form: elliptic integrals or their series) against the
    # Masing quadrature of the public loop, an independent algorithm, with twice its default
    # nodes (~1e-14): x from 0 to 30 past the stick length c, dense around full sliding
    # (x - c = 3/2), at small x (c = 0) and small excess x - c down to 1e-8 of x, and below c.
    from contactres import CattaneoMindlinLoop, PlateauLoop, loop_stiffness
    from contactres.analysis._models.cm_loop import cm_shape, loop_shape

    side = np.geomspace(1e-9, 0.5, 41)
    y = np.unique(np.concatenate([[0.0, 1e-12, 1e-5, 1e-3], np.linspace(0.0, 30.0, 601),
                                  1.5 + side, 1.5 - side]))  # fmt: skip
    y = y[(y == 0.0) | (y >= 1e-8 * c)]  # the excess that is resolved to 1e-12 (see below)
    onset = c * np.geomspace(1e-8, 1e-2, 13)
    x = np.concatenate([c * np.array([0.0, 0.5, 1.0 - 1e-9]), c + y, c + onset])
    inner = CattaneoMindlinLoop(kappa=1.0, mu=1.0, normal_force=1.0)
    loop = inner if c == 0.0 else PlateauLoop(inner, c)
    reference = loop_stiffness(loop, x, nodes=48)
    g1, g2 = loop_shape(x, c)
    np.testing.assert_allclose(g1, reference.real, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g2, reference.imag, rtol=0, atol=1e-12)
    if c == 0.0:  # the plain loop's own series, and both sides of its bounds m = 7/8
        bounds = np.array([1.3125, 1.5 * 8.0 / 7.0])[:, None] + np.linspace(-1e-3, 1e-3, 21)
        x = np.concatenate([x, bounds.ravel()])
        reference = loop_stiffness(loop, x, nodes=48)
        g1, g2 = cm_shape(x)
        np.testing.assert_allclose(g1, reference.real, rtol=0, atol=1e-12)
        np.testing.assert_allclose(g2, reference.imag, rtol=0, atol=1e-12)
    # Closer to the onset of slip, 2 arcsin √(c/x) near π (the closed form's) loses digits:
    # K′/κ is then 1 within ~1e-9 (1 - K′/κ ~ (x - c)^{5/2}), still held to 1e-9.
    x = c * (1.0 + np.array([1e-15, 1e-12, 1e-10]))
    np.testing.assert_allclose(loop_shape(x, c)[0], 1.0, rtol=0, atol=1e-9)


def test_the_closed_form_loop_shape_has_the_small_amplitude_limits():
    # Mindlin's limits at small x: 1 - K′/κ = x/6 and (K″ - ωξ)/κ = 2x/(9π) to first order
    # (paper 2, Eqs. 4-6 with F = 1 - (1 - 2d/3)^{3/2}); x = 0 and below 1e-100: exactly 1, 0.
    from contactres.analysis._models.cm_loop import cm_shape, loop_shape

    x = np.array([1e-300, 1e-30, 1e-12, 1e-8])
    for shape in (loop_shape, cm_shape):
        g1, g2 = shape(x)
        np.testing.assert_allclose(1.0 - g1, x / 6.0, rtol=1e-6, atol=3e-16)
        np.testing.assert_allclose(g2[1:], 2.0 * x[1:] / (9.0 * np.pi), rtol=1e-7)
        assert shape(0.0) == (1.0, 0.0) and shape(1e-300)[1] == 0.0
        for bad in (np.nan, -1e-9, np.inf):
            with pytest.raises(ContactresInputError):
                shape(np.array([0.1, bad]))
    g1, g2 = cm_shape(np.array([[0.0, 0.1], [2.0, 1e-200]]))  # the shape of x
    assert g1.shape == g2.shape == (2, 2) and g1[0, 0] == g1[1, 1] == 1.0


def test_savkoor_closed_form_shape_is_the_quadrature_of_the_loop():
    # The curves' Savkoor shapes (power series, the loop's area; the quadrature in a band
    # around full sliding) against the Masing quadrature of the public loop with four times
    # its default nodes: x from 0 to 30, dense around full sliding at x = 1 (both sides of the
    # series' bounds 0.933 and 1.071) and at small x.
    from contactres import SavkoorLoop, loop_stiffness
    from contactres.analysis._models.savkoor_loop import savkoor_shape

    side = np.geomspace(1e-10, 0.5, 61)
    bounds = np.array([14.0 / 15.0, 15.0 / 14.0])[:, None] + np.linspace(-1e-3, 1e-3, 21)
    x = np.unique(np.concatenate([[0.0, 1e-30, 1e-12, 1e-8, 1e-5, 1e-3],
                                  np.linspace(0.0, 30.0, 1201), 1.0 + side, 1.0 - side,
                                  bounds.ravel()]))  # fmt: skip
    reference = loop_stiffness(SavkoorLoop(kappa=1.0, tau=1.0, a=0.5), x, nodes=96)
    g1, g2 = savkoor_shape(x)
    np.testing.assert_allclose(g1, reference.real, rtol=0, atol=1e-12)
    np.testing.assert_allclose(g2, reference.imag, rtol=0, atol=1e-12)
    # Small x: K′/κ = 1 - (5/32)x², (K″ - ωξ)/κ = x²/(3π) (paper 2, Eq. 15); the shape of x.
    g1, g2 = savkoor_shape(np.array([[1e-300, 1e-4], [1e-3, 0.0]]))
    assert g1.shape == (2, 2) and g1[0, 0] == g1[1, 1] == 1.0 and g2[0, 0] == g2[1, 1] == 0.0
    np.testing.assert_allclose(1.0 - g1[0, 1], 5e-8 / 32, rtol=1e-6)
    np.testing.assert_allclose(g2[1, 0], 1e-6 / (3 * np.pi), rtol=1e-5)
    for bad in (np.nan, -1e-9, np.inf):
        with pytest.raises(ContactresInputError):
            savkoor_shape(np.array([0.1, bad]))


def test_savkoor_series_terms_bound_the_rest_of_the_series():
    # Each cell's last index K: the rest Σ_{k>K} M_k T_k < 1e-17 at the cell's largest ρ, M_k the
    # coefficients of (2 - √(1 - ρt))² (|binom(1/2, i)| ρ^i convolved with itself) and
    # T_k = ∫₀^π sin²φ cosᵏφ dφ (0 for odd k), here by Euler's beta function.
    from scipy.special import beta, binom

    from contactres.analysis._models.savkoor_loop import SAVKOOR_CELLS, SAVKOOR_TERMS

    k = np.arange(4000)
    t = np.where(k % 2 == 0, beta(1.5, (k + 1) / 2.0), 0.0)
    for cell, last in enumerate(SAVKOOR_TERMS, start=1):
        a = np.abs(binom(0.5, k)) * (cell / SAVKOOR_CELLS) ** k
        m = np.convolve(a, a)[: k.size]
        assert (m * t)[last + 1 :].sum() < 1e-17
        assert (m * t)[last - 1 :].sum() >= 1e-17  # the fewest (K even: K - 1 adds nothing)


@pytest.mark.parametrize("dtype", [object, "str"])
def test_model_keys_are_exact_model_of_each_sweep(dtype):
    # Once per distinct (model, limits_from) pair, then spread over the sweeps: the same key as
    # exact_model sweep by sweep, gaps (None, NaN) and unknown names included.
    rng = np.random.default_rng(7)
    models = np.array(
        ["elastic", "cattaneo-mindlin", "savkoor", "plateau", None, np.nan, "bogus"], dtype=object
    )
    sources = np.array(
        ["mean", "cm-loop", "savkoor-loop", "plateau-loop", "line", None, np.nan], dtype=object
    )
    model = pd.Series(models[rng.integers(0, len(models), 3000)], dtype=object).astype(dtype)
    limits = pd.Series(sources[rng.integers(0, len(sources), 3000)], dtype=object).astype(dtype)
    want = [exact_model(m, lf) for m, lf in zip(model, limits, strict=True)]
    got = model_keys(model, limits)
    assert got.dtype == object
    assert got.tolist() == want
    assert len(set(want) - {None}) >= 4  # every kind of key was met
    assert model_keys(model.iloc[:0], limits.iloc[:0]).tolist() == []
