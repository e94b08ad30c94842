"""The runner-up of a model choice is another class with a criterion, or none ("").

A class is no rival of itself. Where no other class has a criterion — a load whose Δf has the
wrong sign for every exact loop (they need Δf0 > 0), or a sweep of one point (two residuals, Δf
and ΔΓ: a loop's three parameters are not determined, and the elastic class's two are
determined exactly, with no residual left over for a criterion either) — the base named the
first class of an argmin over nothing but inf: ``elastic``, the winner itself ("elastic beat
elastic"). The expected runner-ups here are found again from the rows' own ``bic_<class>``
columns by a plain minimum over the other classes, and from the counts of residuals and
parameters.
"""

import numpy as np
import pytest
from short_sweeps import CUT, WRONG_SIGN, short_sweeps

from contactres.analysis import AnalysisSettings, analyze
from contactres.analysis._classify import choose, runner_up
from contactres.analysis._models import AMPLITUDE_MODELS

RESIDUALS_PER_POINT = 2  # Δf and ΔΓ
LOOP_PARAMETERS = 3  # the Cattaneo-Mindlin and Savkoor loops: Δf0, ΔΓ0, θ
ELASTIC_PARAMETERS = 2  # Δf0, ΔΓ0


@pytest.fixture(scope="module")
def results():
    table, _ = short_sweeps()
    return analyze(table, settings=AnalysisSettings(bootstrap=0, workers=1))


def _lowest_other(row) -> str:
    """The class other than the row's model with the lowest finite BIC, "" if none."""
    bics = {m: row[f"bic_{m}"] for m in AMPLITUDE_MODELS if m != row["model"]}
    finite = {m: b for m, b in bics.items() if np.isfinite(b)}
    return min(finite, key=finite.__getitem__) if finite else ""


def test_sweeps_chosen_alone_name_the_lowest_other_class_or_none(results):
    sw = results.sweeps
    alone = sw[sw["decided_by"] == "sweep"]
    assert set(CUT) <= set(alone["sweep"].astype(str))
    for _, row in alone.iterrows():
        expected = _lowest_other(row)
        assert row["runner_up"] == expected, row["sweep"]
        if expected:
            assert row["delta_bic"] == row[f"bic_{expected}"] - row[f"bic_{row['model']}"]
        elif np.isfinite(row[f"bic_{row['model']}"]):
            assert row["delta_bic"] == np.inf  # no rival
        else:
            assert np.isnan(row["delta_bic"])  # no criterion at all: no evidence
    # By the counts alone (a criterion needs a residual left over, 2 n > k): one point has no
    # class with a criterion, the elastic one neither; two points have the loops as rivals.
    for name, points in CUT.items():
        row = sw[sw["sweep"].astype(str) == name].iloc[0]
        assert row["n_points"] == points
        rivals = RESIDUALS_PER_POINT * points > LOOP_PARAMETERS
        winner = RESIDUALS_PER_POINT * points > ELASTIC_PARAMETERS
        assert (row["runner_up"] != "") == rivals, name
        assert np.isfinite(row["delta_bic"]) == rivals, name
        assert np.isnan(row["delta_bic"]) == (not winner), name


def test_a_block_with_no_other_class_has_no_runner_up(results):
    sw, blocks = results.sweeps, results.blocks
    wrong = sw["sweep"].astype(str).str.startswith(WRONG_SIGN).to_numpy()
    block = sw[wrong & (sw["decided_by"] == "block").to_numpy()]
    assert len(block) == 3  # ramps 2-4
    # No loop has a criterion with Δf of the wrong sign: elastic alone, no rival.
    assert np.isinf(block[[f"bic_{m}" for m in AMPLITUDE_MODELS[1:]]].to_numpy()).all()
    assert (block["model"] == "elastic").all()
    assert (block["runner_up"] == "").all()
    assert (block["delta_bic"] == np.inf).all()
    row = blocks[blocks["block"] == block["block"].iloc[0]].iloc[0]
    assert (row["model"], row["runner_up"], row["delta_bic"]) == ("elastic", "", np.inf)
    # The other blocks have rivals: named, another class, finite evidence.
    rest = blocks[blocks["block"] != row["block"]]
    assert len(rest) > 0
    assert (rest["runner_up"] != "").all() and np.isfinite(rest["delta_bic"]).all()


def test_no_class_is_its_own_runner_up(results):
    for table in (results.sweeps, results.blocks):
        assert (table["runner_up"] != table["model"]).all()
        assert table["runner_up"].isin(["", *AMPLITUDE_MODELS]).all()


def test_no_criterion_at_all_keeps_the_simplest_class_without_evidence():
    # As for a sweep of one point, whose mean has no residual left for a criterion either:
    # elastic kept, no runner-up, no evidence (NaN, not inf).
    crit = np.array([[np.inf, 1.0], [np.inf, 0.0], [np.inf, 5.0], [np.inf, np.inf]])
    choice, runner, evidence = choose(crit, 2.0)
    assert [AMPLITUDE_MODELS[i] for i in choice] == ["elastic", "elastic"]  # nested, within 2
    assert list(runner) == ["", "cattaneo-mindlin"]
    assert np.isnan(evidence[0]) and evidence[1] == -1.0


def test_ties_go_to_the_first_class_and_only_plus_inf_means_no_rival():
    """Equal rival criteria name the first class in the order given; a NaN or -inf rival is
    not "no criterion" (only +inf is), so the other column names argmin's class as before."""
    names = np.array(["elastic", "cattaneo-mindlin", "savkoor", "plateau"])
    inf, nan = np.inf, np.nan
    # Columns: a tie between savkoor and plateau; a NaN beside a finite rival; -inf; all +inf.
    others = np.array(
        [[inf, inf, inf, inf], [9.0, nan, 2.0, inf], [4.0, 5.0, 1.0, inf], [4.0, 5.0, -inf, inf]]
    )
    runner, evidence = runner_up(others, names, np.array([1.0, 1.0, 1.0, 1.0]))
    assert list(runner) == ["savkoor", "cattaneo-mindlin", "plateau", ""]
    assert evidence[0] == 3.0 and np.isnan(evidence[1]) and evidence[2] == -inf
    assert evidence[3] == inf
