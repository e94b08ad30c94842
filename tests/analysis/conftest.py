"""Shared helpers of the analysis tests."""

from __future__ import annotations

from dataclasses import replace

import pytest


def _water_study(seed: int, plateau: float = 0.3):
    """Paper 2's water configurations (validation_study) with a share ``plateau`` of loads with
    a stick plateau, no drift and no Savkoor experiment: the analysis, and its sweeps with the
    truth."""
    from contactres.analysis import AnalysisSettings, analyze
    from contactres.measurements import synthetic_sweeps, validate_sweeps, validation_study

    base = validation_study(4)
    study = replace(
        base,
        groups=tuple(g for g in base.groups if g.medium == "water"),
        random_plateau=plateau,
        drifts=(),
        savkoor_experiments=(),
    )
    raw = synthetic_sweeps(study, seed, truth=True)
    truth_cols = [c for c in raw.columns if c.startswith("true_")]
    table = validate_sweeps(
        raw.drop(columns=truth_cols), constants=dict(overtone=3, area_m2=2.5e-5, n_contacts=3)
    )
    res = analyze(table, settings=AnalysisSettings(bootstrap=0))
    truth = raw.drop_duplicates("sweep")[["sweep", *truth_cols]]
    return res, res.sweeps.merge(truth, on="sweep", validate="one_to_one")


@pytest.fixture(scope="session")
def water_study():
    """``water_study(seed, plateau=0.3) -> (results, sweeps with the truth)``: paper 2's water
    configurations with a share ``plateau`` of plateau loads (issue 27, point 11)."""
    return _water_study
