"""A class whose parameters the sweep does not identify has no criterion and no parameters;
a load whose Δf has the wrong sign is flagged ``negative-stiffness``.

Identification is counted here, independently of the analysis: Δf and ΔΓ give two residuals
at each *distinct* amplitude (copies of one amplitude add residuals but no information: a
line through points at one amplitude has no slope), and a class of k parameters needs
2·(distinct amplitudes) >= k. The k are those of the closed forms written out in
``analysis/_classify``'s table (Δf0 and ΔΓ0, plus a slope or a curvature of each channel, plus
the hinge's u_c), not read from the package.
"""

import warnings

import numpy as np
import pytest
from test_trust import CONST, study

from contactres.analysis import AnalysisSettings, analyze
from contactres.analysis._flags import Flag, has, negative_stiffness
from contactres.analysis._models import AMPLITUDE_MODELS
from contactres.measurements._sweeps import SweepWarning, validate_sweeps
from contactres.measurements._synthetic import synthetic_sweeps

#: The closed-form classes (``exact_loop=False``) and their parameters: Δf0, ΔΓ0 (elastic); a
#: slope of each channel (line in u0); a curvature of each (line in u0²); slopes and u_c (hinge).
CLOSED_FORM_K = {"elastic": 2, "cattaneo-mindlin": 4, "savkoor": 4, "plateau": 5}
RESIDUALS_PER_AMPLITUDE = 2  # Δf and ΔΓ
# Sweeps cut to their first points (ramps 1 and 4 are chosen alone, not in a block)...
CUT = {"glass/air/e1/F1/r4": 1, "glass/air/e1/F2/r1": 2, "glass/air/e1/F4/r1": 1}
# ... and one cut to 3 points all at one amplitude: three points, one distinct amplitude.
FLAT = "glass/air/e1/F3/r1"
# A load whose every ramp has Δf negated.
WRONG_SIGN = "glass/air/e2/F3/"


def _table():
    raw = synthetic_sweeps(study(n_experiments=2), 5, constants=False)
    names = raw["sweep"].astype(str).to_numpy().astype(str)
    cut = {**CUT, FLAT: 3}
    drop = np.concatenate([np.flatnonzero(names == s)[k:] for s, k in cut.items()])
    flat = np.flatnonzero(names == FLAT)[:3]
    raw.loc[flat, "amplitude_m"] = raw.loc[flat[0], "amplitude_m"]
    raw.loc[np.char.startswith(names, WRONG_SIGN), "df_Hz"] *= -1
    raw = raw.drop(raw.index[drop]).reset_index(drop=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SweepWarning)  # few points, one amplitude: as meant
        table = validate_sweeps(raw, constants=CONST)
    distinct = raw.groupby("sweep")["amplitude_m"].nunique()
    return table, {str(k): int(v) for k, v in distinct.items()}


@pytest.fixture(scope="module")
def closed_form():
    table, distinct = _table()
    settings = AnalysisSettings(bootstrap=0, workers=1, exact_loop=False)
    return analyze(table, settings=settings), distinct


def test_a_class_has_a_criterion_only_where_the_sweep_identifies_it(closed_form):
    results, distinct = closed_form
    sw = results.sweeps
    alone = sw[sw["decided_by"] == "sweep"]
    assert {*CUT, FLAT} <= set(alone["sweep"].astype(str))
    short = 0
    for _, row in alone.iterrows():
        d = distinct[str(row["sweep"])]
        for m, k in CLOSED_FORM_K.items():
            if RESIDUALS_PER_AMPLITUDE * d < k:
                short += 1
                assert row[f"bic_{m}"] == np.inf, (row["sweep"], m)
            elif m != "plateau":  # (a hinge may also find no u_c with enough points)
                assert np.isfinite(row[f"bic_{m}"]), (row["sweep"], m)
    assert short >= 3 * 3  # the two one-point sweeps and the flat one: three slip classes each
    # One distinct amplitude (one point, or three at one amplitude): elastic alone, no rival.
    for name in ("glass/air/e1/F1/r4", "glass/air/e1/F4/r1", FLAT):
        row = sw[sw["sweep"].astype(str) == name].iloc[0]
        assert distinct[name] == 1
        assert (row["model"], row["runner_up"], row["delta_bic"]) == ("elastic", "", np.inf)


def test_the_parameters_of_a_class_not_identified_are_not_given(closed_form):
    results, distinct = closed_form
    names = results.sweeps["sweep"].astype(str).to_numpy()
    one = np.array([distinct[s] == 1 for s in names])
    assert one.sum() == 3
    # The line in u0 and in u0² (k = 4 > 2): no limits, no slopes or curvatures, no errors.
    for model, second in (("cattaneo-mindlin", "slope"), ("savkoor", "curvature")):
        fit = results.fits[model]
        for c in ("df", "dgamma"):
            for col in (f"{c}0", f"{c}0_err", f"{c}_{second}", f"{c}_{second}_err", f"rss_{c}"):
                assert np.isnan(fit[col].to_numpy(float)[one]).all(), (model, col)
                assert np.isfinite(fit[col].to_numpy(float)[~one]).all(), (model, col)
    # The slopes and noise levels of the sweep table come from the line: none for them.
    sw = results.sweeps
    for col in ("df_slope_Hz_per_m", "sigma_df_Hz", "df_curvature_Hz_per_m2"):
        assert np.isnan(sw[col].to_numpy(float)[one]).all(), col
    # The elastic class (k = 2) is identified by one amplitude: its mean is the answer.
    assert np.isfinite(sw["df0_Hz"].to_numpy(float)[one]).all()


def test_every_classs_criterion_with_the_exact_loops_follows_the_same_count():
    table, distinct = _table()
    results = analyze(table, settings=AnalysisSettings(bootstrap=0, workers=1))
    sw = results.sweeps
    alone = sw[(sw["decided_by"] == "sweep").to_numpy()]
    # The loops: Δf0, ΔΓ0 and the slip scale (3); the plateau loop d_c too (4).
    k = {"elastic": 2, "cattaneo-mindlin": 3, "savkoor": 3, "plateau": 4}
    for _, row in alone.iterrows():
        d = distinct[str(row["sweep"])]
        for m in AMPLITUDE_MODELS:
            if RESIDUALS_PER_AMPLITUDE * d < k[m]:
                assert row[f"bic_{m}"] == np.inf, (row["sweep"], m)


def test_a_load_whose_shift_has_the_wrong_sign_is_flagged(closed_form):
    table, _ = _table()
    for results in (closed_form[0], analyze(table, settings=AnalysisSettings(bootstrap=0))):
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
