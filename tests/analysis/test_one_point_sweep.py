"""A sweep of one point among others in analyze(): no class has a criterion, none an error.

One point gives two residuals (Δf and ΔΓ at its amplitude). The elastic model has two
parameters (Δf0, ΔΓ0): it is determined exactly, the mean is the point, but no residual is left
over: its residual sums are 0 and the BIC of such a fit would sit on the floor for a perfect
fit (-136.8 for any one-point sweep, whatever its data), and its errors would be 0. So it keeps
its values (Δf0 and ΔΓ0 are the point's shifts) without errors or a criterion. The
Cattaneo-Mindlin and Savkoor loops have three (Δf0, ΔΓ0 and the inverse slip scale θ): fewer
residuals than parameters, no BIC (inf, never chosen); the base fitted the three to the two
residuals and gave them a BIC the data could not support. With no class of criterion, the
sweep keeps the simplest, elastic, and the evidence for it, delta_bic, is NaN (none).
"""

import numpy as np
import pytest
from test_trust import CONST, study

from contactres.analysis import AnalysisSettings, analyze
from contactres.measurements._sweeps import SweepWarning, validate_sweeps
from contactres.measurements._synthetic import synthetic_sweeps

RESIDUALS_PER_POINT = 2  # Δf and ΔΓ
PARAMETERS = {"elastic": 2, "cattaneo-mindlin": 3, "savkoor": 3}  # (the loops: Δf0, ΔΓ0, θ)


def test_a_one_point_sweep_has_no_bic_and_no_errors_but_keeps_its_values():
    raw = synthetic_sweeps(study(n_experiments=2), 5, constants=False)
    target = raw["sweep"].unique()[7]
    rows = np.flatnonzero(raw["sweep"].to_numpy() == target)
    cut = raw.drop(raw.index[rows[1:]]).reset_index(drop=True)
    with (
        pytest.warns(SweepWarning, match="fewer than 4 points"),
        pytest.warns(SweepWarning, match="all amplitudes equal"),
    ):
        table = validate_sweeps(cut, constants=CONST)
    sweeps = analyze(table, settings=AnalysisSettings(bootstrap=0, workers=1)).sweeps
    row = sweeps[sweeps["sweep"].astype(str) == str(target)].iloc[0]
    assert row["n_points"] == 1
    residuals = RESIDUALS_PER_POINT * row["n_points"]
    for model, k in PARAMETERS.items():
        # a criterion only with a residual left over
        assert np.isfinite(row[f"bic_{model}"]) == (residuals > k), model
    assert row["model"] == row["model_sweep"] == "elastic"
    assert row["runner_up"] == "" and np.isnan(row["delta_bic"])
    # The elastic class's values are the point's own shifts; their errors are not known.
    point = cut[cut["sweep"] == target].iloc[0]
    assert (row["df0_Hz"], row["dgamma0_Hz"]) == (point["df_Hz"], point["dgamma_Hz"])
    assert np.isnan(row["df0_err_Hz"]) and np.isnan(row["dgamma0_err_Hz"])
    # The sweeps of more points keep a criterion for each loop.
    others = sweeps[sweeps["n_points"] > 1]
    assert np.isfinite(others[["bic_cattaneo-mindlin", "bic_savkoor"]].to_numpy()).all()
