"""drifting_sweeps takes the sweeps of its table in the padded points' order without hashing
their ids where both are in that order (the analysis's case, issue 31, point 3): the flags are
those it gives a table of the same sweeps in another order, whose ids it looks up."""

import numpy as np

from contactres.analysis._amplitude import pad_sweeps
from contactres.analysis._drift import drifting_sweeps
from contactres.measurements import validate_sweeps
from contactres.measurements._studies import EXAMPLE_SEED, example_study
from contactres.measurements._synthetic import synthetic_sweeps


def test_drift_flags_do_not_depend_on_the_order_of_the_sweeps():
    raw = synthetic_sweeps(example_study(2), EXAMPLE_SEED, constants=True)
    # One ramp of some loads offset by far more than the noise: those loads drift.
    sweeps = raw["sweep"].drop_duplicates().to_numpy()
    moved = raw["sweep"].isin(sweeps[::7]) & (raw["ramp"] == 2)
    raw.loc[moved, "df_Hz"] += 5.0
    data = validate_sweeps(raw).data
    padded = pad_sweeps(data)
    info = data.drop_duplicates("sweep").reset_index(drop=True)
    assert (info["sweep"].to_numpy() == padded.sweeps).all()
    used = info["ramp"].to_numpy() > 1
    flags = drifting_sweeps(info, padded, used, 0.01)
    assert 0 < flags.sum() < flags.size  # some loads drift, some do not
    # The same sweeps in another order: found by their ids, the same flag each.
    order = np.random.default_rng(4).permutation(len(info))
    shuffled = drifting_sweeps(info.iloc[order].reset_index(drop=True), padded, used[order], 0.01)
    np.testing.assert_array_equal(shuffled, flags[order])
