"""μ per load is withheld with its group's E and γ when they were withheld for an input μ
scales with too (issue 30, second review M1: an area in mm² typed as m² gave E = 1e4 GPa,
withheld, and μ ≈ 44 per load, printed)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from contactres import AnalysisSettings, analyze, read_sweeps
from contactres.analysis._loads import MU_WITHHELD, withhold_mu
from contactres.examples import example_path
from contactres.report._console import friction_table


def _loads():
    return pd.DataFrame(
        {
            "configuration": ["A", "A", "B"],
            "medium": ["air", "air", "air"],
            "normal_force_N": [1e-3, 2e-3, 1e-3],
            "kappa_N_per_m_mean": [1e5, 2e5, 1e5],
            "mu_fit_median": [0.4, 0.5, 0.6],
            "mu_df_mean": [0.4, 0.5, 0.6],
        }
    )


@pytest.mark.parametrize(
    ("checks", "withheld"),
    [
        (["fit-at-bound", "E-out-of-range"], True),
        (["gamma-out-of-range"], True),
        (["fit-at-bound"], False),  # a bound says nothing of the area or the force
        (["too-few-loads"], False),
        ([], False),
    ],
)
def test_only_the_checks_naming_mus_inputs_withhold_it(checks, withheld):
    groups = [
        {"configuration": "A", "medium": "air", "checks": checks},
        {"configuration": "B", "medium": "air", "checks": []},
    ]
    out = withhold_mu(_loads(), groups)
    a = (out["configuration"] == "A").to_numpy()
    assert np.isnan(out.loc[a, ["mu_fit_median", "mu_df_mean"]].to_numpy()).all() == withheld
    assert (out.loc[a, "flags"] == (MU_WITHHELD if withheld else "")).all()
    # the other group and every other quantity are untouched
    assert out.loc[~a, "mu_fit_median"].tolist() == [0.6] and (out.loc[~a, "flags"] == "").all()
    assert out["kappa_N_per_m_mean"].tolist() == [1e5, 2e5, 1e5]


def test_an_area_in_mm2_typed_as_m2_withholds_mu_on_every_route(tmp_path):
    frame = pd.read_csv(example_path("example_sweeps.csv"), comment="#")
    frame = frame[frame["configuration"] == "SiO2_2.2mm"].drop(columns=["area_m2"])
    path = tmp_path / "noarea.csv"
    frame.to_csv(path, index=False)
    res = analyze(read_sweeps(path, area_m2=1e-3), settings=AnalysisSettings(bootstrap=0))
    assert all("E-out-of-range" in g["checks"] for g in res.groups)
    mu = [c for c in res.loads.columns if c.startswith("mu_")]
    assert np.isnan(res.loads[mu].to_numpy(float)).all()
    assert (res.loads["flags"] == MU_WITHHELD).all()
    assert (friction_table(res)["μ (loop fit)"] == "withheld (see E, γ)").all()
    # the same file with its own area: μ is printed and no load is flagged
    frame.assign(area_m2=2.5e-5).to_csv(path, index=False)
    res = analyze(read_sweeps(path), settings=AnalysisSettings(bootstrap=0))
    assert not any(g["checks"] for g in res.groups) and (res.loads["flags"] == "").all()
    assert np.isfinite(res.loads["mu_fit_median"]).any()
