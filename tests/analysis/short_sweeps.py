"""Test-only builder shared by test_runner_up and test_identified: the synthetic study of
test_trust (two experiments, 5 points a ramp) with a few sweeps cut short and a load whose Δf
has the wrong sign, as a validated table, for the cases where a class has no criterion."""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping

import numpy as np
from test_trust import CONST, study

from contactres.measurements._sweeps import SweepWarning, validate_sweeps
from contactres.measurements._synthetic import synthetic_sweeps

# Sweeps cut to their first points (ramps 1 and 4 are not used, so chosen alone, not in a
# block): two of one point, one of two.
CUT = {"glass/air/e1/F1/r4": 1, "glass/air/e1/F2/r1": 2, "glass/air/e1/F4/r1": 1}
# A load whose every ramp has Δf negated (its used ramps 2-4 are a block).
WRONG_SIGN = "glass/air/e2/F3/"


def short_sweeps(
    edit: Callable | None = None, cut: Mapping[str, int] = CUT
) -> tuple[object, object]:
    """(validated table, raw rows): the study's rows with every sweep of ``cut`` kept to its
    first ``cut[sweep]`` points and Δf of the load :data:`WRONG_SIGN` negated; ``edit(raw,
    names)`` (names: the rows' sweep names as str) may change the rows first, in place."""
    raw = synthetic_sweeps(study(n_experiments=2), 5, constants=False)
    names = raw["sweep"].astype(str).to_numpy().astype(str)
    drop = np.concatenate([np.flatnonzero(names == s)[k:] for s, k in cut.items()])
    if edit is not None:
        edit(raw, names)
    raw.loc[np.char.startswith(names, WRONG_SIGN), "df_Hz"] *= -1
    raw = raw.drop(raw.index[drop]).reset_index(drop=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SweepWarning)  # few points, one amplitude: as meant
        table = validate_sweeps(raw, constants=CONST)
    return table, raw
