"""Running-in: how much the first ramp of a load differs from the later ramps of the same load.

Paper 2 sets the first amplitude ramp of every load aside because the contact is still settling
("running-in"). The size of the effect is reported instead of hidden: for every load of every
experiment that has a ramp 1 and later used ramps, the ratios of ramp 1's κ, ωξ and μ (exact-loop
fit) to the mean of the later ramps, then per configuration and medium the mean ratio and its
standard error over those loads.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ._drift import LOAD_OF_EXPERIMENT

__all__ = ["QUANTITIES", "running_in"]

#: Quantity of the sweep results -> name of its ratio in the report.
QUANTITIES = {"kappa_N_per_m": "kappa", "omega_xi_N_per_m": "omega_xi", "mu_fit": "mu_fit"}


def running_in(sw: pd.DataFrame, first: np.ndarray, later: np.ndarray) -> dict:
    """Ratios ramp 1 / later ramps for the sweeps ``sw`` of one configuration and medium.

    ``first``: the running-in sweep of each load; ``later``: which sweeps count as the later
    ramps (enough points, not the first, not drifting). Returns
    ``{"n_loads": n, "<q>_ratio": mean, "<q>_ratio_err": standard error, ...}`` for the
    quantities of :data:`QUANTITIES` (NaN where fewer than one or two loads give a ratio), or
    ``{"n_loads": 0}`` when the table has no ramp 1.
    """
    if not first.any():
        return {"n_loads": 0}
    keys = LOAD_OF_EXPERIMENT
    cols = list(QUANTITIES)
    ramp1 = sw[first].groupby(keys, sort=True)[cols].mean()
    rest = sw[later].groupby(keys, sort=True)[cols].mean()
    both = ramp1.merge(rest, left_index=True, right_index=True, suffixes=("_1", "_later"))
    out: dict = {"n_loads": len(both)}
    for col, name in QUANTITIES.items():
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = (both[f"{col}_1"] / both[f"{col}_later"]).to_numpy(float)
        ratio = ratio[np.isfinite(ratio)]
        out[f"{name}_ratio"] = float(ratio.mean()) if ratio.size else np.nan
        out[f"{name}_ratio_err"] = (
            float(ratio.std(ddof=1) / np.sqrt(ratio.size)) if ratio.size >= 2 else np.nan
        )
    return out
