"""A class whose parameters the sweep does not identify has no criterion and no parameters;
one with no residual left over keeps its parameters but has no criterion and no errors; a load
whose Δf has the wrong sign is flagged ``negative-stiffness``.

Identification is counted here, independently of the analysis: Δf and ΔΓ give two residuals
at each *distinct* amplitude (copies of one amplitude add residuals but no information: a
line through points at one amplitude has no slope), and a class of k parameters needs
2·(distinct amplitudes) >= k. A fit also needs a residual left over: 2·(points) > k, every
point counted (a copy of an amplitude does add a residual), or it passes through every point
and its residual sums (~0) and errors (0) mean nothing. The k are those of the closed forms
written out in ``analysis/_classify``'s table (Δf0 and ΔΓ0, plus a slope or a curvature of each
channel, plus the hinge's u_c), not read from the package.
"""

import numpy as np
import pytest
from short_sweeps import CUT, WRONG_SIGN, short_sweeps

from contactres.analysis import AnalysisSettings, analyze
from contactres.analysis._bad_rows import blank_errors, blank_unidentified, points_of
from contactres.analysis._flags import Flag, has, negative_stiffness
from contactres.analysis._models import AMPLITUDE_MODELS

#: The closed-form classes (``exact_loop=False``) and their parameters: Δf0, ΔΓ0 (elastic); a
#: slope of each channel (line in u0); a curvature of each (line in u0²); slopes and u_c (hinge).
CLOSED_FORM_K = {"elastic": 2, "cattaneo-mindlin": 4, "savkoor": 4, "plateau": 5}
RESIDUALS_PER_AMPLITUDE = 2  # Δf and ΔΓ
RESIDUALS_PER_POINT = 2  # the same two, at every point
# short_sweeps' table (its load WRONG_SIGN has Δf negated); of its sweeps cut to their first
# points (CUT: ramps chosen alone, not in a block) ...
ONE_POINT = ("glass/air/e1/F1/r4", "glass/air/e1/F4/r1")
TWO_POINTS = "glass/air/e1/F2/r1"
# ... and one cut to 3 points all at one amplitude: three points, one distinct amplitude.
FLAT = "glass/air/e1/F3/r1"
# A load whose every point sits at one amplitude (its used ramps 2-4 are a block: one distinct
# amplitude among their 30 points together) ...
FLAT_LOAD = "glass/air/e2/F5/"
# ... and one whose used ramps each sit at one amplitude, another for each ramp (three distinct
# amplitudes together, one each alone).
FLAT_RAMPS = {"glass/air/e2/F4/r2": 0, "glass/air/e2/F4/r3": 4, "glass/air/e2/F4/r4": 9}


def _flatten(raw, rows, at, rng):
    """Every point of ``rows`` moved to the amplitude of row ``at``, its shifts those of ``at``
    with a little noise (0.1 Hz: the fits have residuals)."""
    raw.loc[rows, "amplitude_m"] = raw.loc[at, "amplitude_m"]
    for c in ("df_Hz", "dgamma_Hz"):
        raw.loc[rows, c] = raw.loc[at, c] + 0.1 * rng.standard_normal(len(rows))


def _table():
    rng = np.random.default_rng(1)

    def edit(raw, names):
        flat = np.flatnonzero(names == FLAT)[:3]
        raw.loc[flat, "amplitude_m"] = raw.loc[flat[0], "amplitude_m"]
        load = np.flatnonzero(np.char.startswith(names, FLAT_LOAD))
        _flatten(raw, load, np.flatnonzero(names == FLAT_LOAD + "r2")[0], rng)
        for sweep, j in FLAT_RAMPS.items():
            rows = np.flatnonzero(names == sweep)
            _flatten(raw, rows, rows[j], rng)

    table, raw = short_sweeps(edit, {**CUT, FLAT: 3})
    distinct = raw.groupby("sweep")["amplitude_m"].nunique()
    return table, {str(k): int(v) for k, v in distinct.items()}, raw


def _points(raw) -> dict[str, int]:
    return {str(k): int(v) for k, v in raw.groupby("sweep").size().items()}


@pytest.fixture(scope="module")
def closed_form():
    table, distinct, raw = _table()
    settings = AnalysisSettings(bootstrap=0, workers=1, exact_loop=False)
    return analyze(table, settings=settings), distinct, raw


@pytest.fixture(scope="module")
def default():
    table, distinct, raw = _table()
    return analyze(table, settings=AnalysisSettings(bootstrap=0, workers=1)), distinct, raw


def test_a_class_has_a_criterion_only_where_the_sweep_identifies_it(closed_form):
    results, distinct, raw = closed_form
    points = _points(raw)
    sw = results.sweeps
    alone = sw[sw["decided_by"] == "sweep"]
    assert {*CUT, FLAT} <= set(alone["sweep"].astype(str))
    short = 0
    for _, row in alone.iterrows():
        d, n = distinct[str(row["sweep"])], points[str(row["sweep"])]
        for m, k in CLOSED_FORM_K.items():
            if RESIDUALS_PER_AMPLITUDE * d < k or RESIDUALS_PER_POINT * n <= k:
                short += 1
                assert row[f"bic_{m}"] == np.inf, (row["sweep"], m)
            elif m != "plateau":  # (a hinge may also find no u_c with enough points)
                assert np.isfinite(row[f"bic_{m}"]), (row["sweep"], m)
    # The two one-point sweeps: every class; the two-point sweep and the flat one: three each.
    assert short >= 2 * 4 + 2 * 3
    # One distinct amplitude in three points: elastic alone, no rival.
    row = sw[sw["sweep"].astype(str) == FLAT].iloc[0]
    assert (distinct[FLAT], points[FLAT]) == (1, 3)
    assert (row["model"], row["runner_up"], row["delta_bic"]) == ("elastic", "", np.inf)
    # Two points at two amplitudes: the lines pass through both (4 residuals, 4 parameters),
    # the mean does not: elastic alone, no rival.
    row = sw[sw["sweep"].astype(str) == TWO_POINTS].iloc[0]
    assert (distinct[TWO_POINTS], points[TWO_POINTS]) == (2, 2)
    assert (row["model"], row["runner_up"], row["delta_bic"]) == ("elastic", "", np.inf)
    # One point: no class has a criterion (the mean passes through it too); elastic, the
    # simplest, is kept without evidence (NaN: no winner's criterion to compare with).
    for name in ONE_POINT:
        row = sw[sw["sweep"].astype(str) == name].iloc[0]
        assert points[name] == 1
        assert (row["model"], row["runner_up"]) == ("elastic", "")
        assert np.isnan(row["delta_bic"])


def test_the_parameters_of_a_class_not_identified_are_not_given(closed_form):
    results, distinct, raw = closed_form
    points = _points(raw)
    names = results.sweeps["sweep"].astype(str).to_numpy()
    one = np.array([distinct[s] == 1 for s in names])
    # Two one-point sweeps, the flat one, the flat load's four ramps and the three flat ramps.
    assert one.sum() == 2 + 1 + 4 + len(FLAT_RAMPS)
    # (the lines' errors and residual sums also need a residual left over: 2 n > 4)
    spare = np.array([RESIDUALS_PER_POINT * points[s] > 4 for s in names])
    # The line in u0 and in u0² (k = 4 > 2): no limits, no slopes or curvatures, no errors.
    for model, second in (("cattaneo-mindlin", "slope"), ("savkoor", "curvature")):
        fit = results.fits[model]
        for c in ("df", "dgamma"):
            for col in (f"{c}0", f"{c}0_err", f"{c}_{second}", f"{c}_{second}_err", f"rss_{c}"):
                assert np.isnan(fit[col].to_numpy(float)[one]).all(), (model, col)
                there = ~one & (spare | (col in (f"{c}0", f"{c}_{second}")))
                assert np.isfinite(fit[col].to_numpy(float)[there]).all(), (model, col)
    # The slopes and noise levels of the sweep table come from the line: none for them.
    sw = results.sweeps
    for col in ("df_slope_Hz_per_m", "sigma_df_Hz", "df_curvature_Hz_per_m2"):
        assert np.isnan(sw[col].to_numpy(float)[one]).all(), col
    # The elastic class (k = 2) is identified by one amplitude: its mean is the answer, and
    # that of the sweeps chosen elastic (the flat ramps take their block's slip class).
    assert np.isfinite(results.fits["elastic"]["df0"].to_numpy(float)[one]).all()
    elastic = (sw["model"] == "elastic").to_numpy()
    assert one.sum() - elastic[one].sum() == len(FLAT_RAMPS)
    assert np.isfinite(sw["df0_Hz"].to_numpy(float)[one & elastic]).all()


def test_every_classs_criterion_with_the_exact_loops_follows_the_same_count(default):
    """A regression guard, not a test of the rule's code: the exact loops refuse the sweeps
    of too few distinct amplitudes themselves (_bad_rows.usable_rows, as before the rule of
    _classify._fit_block), so this passes with that rule switched off; it fails if the loops'
    own count is lost or falls below the count here."""
    results, distinct, _ = default
    sw = results.sweeps
    alone = sw[(sw["decided_by"] == "sweep").to_numpy()]
    # The loops: Δf0, ΔΓ0 and the slip scale (3); the plateau loop d_c too (4).
    k = {"elastic": 2, "cattaneo-mindlin": 3, "savkoor": 3, "plateau": 4}
    for _, row in alone.iterrows():
        d = distinct[str(row["sweep"])]
        for m in AMPLITUDE_MODELS:
            if RESIDUALS_PER_AMPLITUDE * d < k[m]:
                assert row[f"bic_{m}"] == np.inf, (row["sweep"], m)


def test_a_load_whose_shift_has_the_wrong_sign_is_flagged(closed_form, default):
    for results in (closed_form[0], default[0]):
        sw = results.sweeps
        wrong = sw["sweep"].astype(str).str.startswith(WRONG_SIGN).to_numpy()
        assert wrong.sum() == 4  # ramps 1-4
        flagged = has(sw["flags"].to_numpy(), Flag.NEGATIVE_STIFFNESS)
        # Exactly the negated load: every other shift of the synthetic study is positive.
        assert (flagged == wrong).all()
        assert (sw["kappa_N_per_m"].to_numpy(float)[wrong] < 0).all()


def test_negative_stiffness_is_below_zero_by_more_than_two_errors():
    df0 = np.array([-1.0, -1.0, -1.0, -1.0, 0.0, 1.0, -1e-3])
    err = np.array([0.4, 0.5, 0.6, np.nan, 0.0, 0.0, 0.0])
    # -1 + 2·0.4 < 0; -1 + 2·0.5 = 0 is not below; -1 + 1.2 > 0; a missing error counts as 0.
    expected = [True, False, False, True, False, False, True]
    assert negative_stiffness(df0, err).tolist() == expected


def test_a_load_block_whose_points_sit_at_one_amplitude_has_no_slip_class(closed_form):
    """The rule for the joint fit of a load block's ramps, counted over their points together:
    the flat load's 30 points have one distinct amplitude (2 residuals that carry information
    against the lines' 4 and the hinge's 5), so only the mean has a criterion, shared or per
    ramp; the flat ramps' load has three together (6 >= 5), so its shared fits have one."""
    results, _, raw = closed_form
    load = raw[raw["sweep"].astype(str).str.startswith(FLAT_LOAD)]
    used = load[~load["sweep"].astype(str).str.endswith("/r1")]  # ramp 1: running-in
    assert used["amplitude_m"].nunique() == 1 and len(used) == 30
    sw, blocks = results.sweeps, results.blocks
    mine = sw[sw["sweep"].astype(str).str.startswith(FLAT_LOAD).to_numpy()]
    mine = mine[(mine["decided_by"] == "block").to_numpy()]
    assert len(mine) == 3
    row = blocks[blocks["block"] == mine["block"].iloc[0]].iloc[0]
    assert row["n_points"] == 30
    assert (row["model"], row["runner_up"], row["delta_bic"]) == ("elastic", "", np.inf)
    assert (mine["model"] == "elastic").all() and (mine["runner_up"] == "").all()
    assert (mine["delta_bic"] == np.inf).all()
    # The flat ramps together: three distinct amplitudes, every class has a shared criterion.
    ramps = sw[sw["sweep"].astype(str).isin(FLAT_RAMPS).to_numpy()]
    together = raw[raw["sweep"].astype(str).isin(FLAT_RAMPS)]["amplitude_m"].nunique()
    assert together == 3 and RESIDUALS_PER_AMPLITUDE * together >= max(CLOSED_FORM_K.values())
    row = blocks[blocks["block"] == ramps["block"].iloc[0]].iloc[0]
    assert (ramps["decided_by"] == "block").all()
    assert row["runner_up"] != "" and np.isfinite(row["delta_bic"])


def test_a_fit_with_no_residual_left_keeps_its_values_but_has_no_errors(closed_form, default):
    """Two points at two amplitudes: the straight line passes through both (4 residuals, 4
    parameters). Its slope and limit are still those of the two points (found here from the
    points themselves), but it has no residual sums, no errors and no criterion, and the sweep
    no noise level. One point: the mean is the point, without an error or a criterion."""
    for results, distinct, raw in (closed_form, default):
        sw, line = results.sweeps, results.fits["cattaneo-mindlin"]
        two = raw[raw["sweep"].astype(str) == TWO_POINTS].sort_values("amplitude_m")
        u = two["amplitude_m"].to_numpy(float)
        assert len(two) == distinct[TWO_POINTS] == 2
        at = np.flatnonzero(line["sweep"].astype(str).to_numpy() == TWO_POINTS)[0]
        i_two = np.flatnonzero(sw["sweep"].astype(str).to_numpy() == TWO_POINTS)[0]
        for c, column in (("df", "df_Hz"), ("dgamma", "dgamma_Hz")):
            y = two[column].to_numpy(float)
            slope = (y[1] - y[0]) / (u[1] - u[0])
            assert line[f"{c}_slope"].iloc[at] == pytest.approx(slope, rel=1e-9)
            assert line[f"{c}0"].iloc[at] == pytest.approx(y[0] - slope * u[0], rel=1e-9)
            for col in (f"{c}0_err", f"{c}_slope_err", f"cov_{c}0_{c}_slope", f"rss_{c}"):
                assert np.isnan(line[col].iloc[at]), col
            assert np.isnan(sw[f"sigma_{c}_Hz"].to_numpy(float)[i_two])
        if results is closed_form[0]:  # (with the exact loops the class is the loop's, k = 3)
            assert sw["bic_cattaneo-mindlin"].iloc[i_two] == np.inf
        elastic = results.fits["elastic"]
        for name in ONE_POINT:
            point = raw[raw["sweep"].astype(str) == name]
            i = np.flatnonzero(sw["sweep"].astype(str).to_numpy() == name)[0]
            assert sw["bic_elastic"].iloc[i] == np.inf
            for c, column in (("df", "df_Hz"), ("dgamma", "dgamma_Hz")):
                assert sw[f"{c}0_Hz"].iloc[i] == point[column].iloc[0]
                assert np.isnan(sw[f"{c}0_err_Hz"].iloc[i])
                j = np.flatnonzero(elastic["sweep"].astype(str).to_numpy() == name)[0]
                assert np.isnan(elastic[f"rss_{c}"].iloc[j])


def test_emptying_a_fit_keeps_its_values_where_only_the_errors_go_and_refuses_integers():
    """The emptying itself on a small batch of three sweeps, the second not ``ok``: written
    out here, field by field, not from the analysis."""
    fields = {
        "df0_Hz": np.array([1.0, 2.0, 3.0]),
        "df0_err_Hz": np.array([0.1, 0.0, 0.3]),
        "df_cov_ab": np.array([0.01, 0.0, 0.03]),
        "rss_df": np.array([1.0, 0.0, 3.0]),
        "found": np.array([True, True, True]),
        "edge": np.array(["low", "high", ""], dtype=object),
    }
    ok = np.array([True, False, True])
    out = blank_errors(fields, ok)
    assert out["df0_Hz"].tolist() == [1.0, 2.0, 3.0]  # a value: kept
    for key in ("df0_err_Hz", "df_cov_ab", "rss_df"):  # an error, a covariance, a residual sum
        assert np.isnan(out[key][1]) and out[key][[0, 2]].tolist() == fields[key][[0, 2]].tolist()
    assert out["found"].tolist() == [True, True, True] and out["edge"][1] == "high"
    gone = blank_unidentified(fields, ok)
    assert np.isnan(gone["df0_Hz"][1]) and gone["found"].tolist() == [True, False, True]
    assert gone["edge"].tolist() == ["low", "", ""]
    assert fields["df0_Hz"][1] == 2.0  # the input is not changed
    assert blank_errors(fields, np.ones(3, bool)) is fields  # every sweep ok: the same arrays
    # An integer field has no empty value: refused, naming it (where a sweep is not ok only).
    counted = {**fields, "n_iterations": np.array([3, 4, 5])}
    with pytest.raises(TypeError, match="'n_iterations' is an integer array"):
        blank_unidentified(counted, ok)
    assert blank_unidentified(counted, np.ones(3, bool)) is counted
    assert blank_errors(counted, ok)["n_iterations"].tolist() == [3, 4, 5]  # not an error


def test_points_are_the_weights_above_zero():
    """Padding (weight 0) and a NaN weight are no points; copies of one amplitude each count."""
    w = np.array([[1.0, np.nan, 0.0, 1.0], [1.0, 1.0, 1.0, 1.0], [0.0, 0.0, np.nan, 0.0]])
    assert list(points_of(w)) == [2, 4, 0]
