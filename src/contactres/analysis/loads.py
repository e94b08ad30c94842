"""Statistics per load: the used sweeps of each experiment averaged, then over experiments.

Paper 2 reports, per configuration, medium and normal force, the mean and the spread of the
quantities over repeated experiments (its Figs. 5, 7, 8); a NaN value (e.g. the slope μ of a
plateau sweep) is skipped, and a load without any value gets NaN.
"""

from __future__ import annotations

import pandas as pd

from ..measurements.schema import LOAD_QUANTITIES

__all__ = ["GROUP_KEYS", "LOAD_KEYS", "QUANTITIES", "per_experiment", "per_load"]

#: The quantities averaged per load (columns of the sweep results).
QUANTITIES = tuple(name for name, _, _ in LOAD_QUANTITIES)
#: One group of the JKR fit, one load of a group.
GROUP_KEYS = ["configuration", "medium"]
LOAD_KEYS = ["configuration", "medium", "normal_force_N"]


def per_experiment(sw: pd.DataFrame) -> pd.DataFrame:
    """One row per (load, experiment): the means of its used sweeps and their number."""
    used = sw[sw["used"]]
    g = used.groupby([*LOAD_KEYS, "experiment"], sort=True)
    exp = g[list(QUANTITIES)].mean()
    exp["n_sweeps"] = g.size()
    for c in ("sphere_radius_m", "poisson", "P_Hz_per_N_per_m"):
        exp[c] = g[c].first()
    return exp.reset_index()


def per_load(exp: pd.DataFrame) -> pd.DataFrame:
    """One row per load: mean and standard deviation (ddof = 1) over experiments."""
    g = exp.groupby(LOAD_KEYS, sort=True)
    out = g.size().rename("n_experiments").to_frame()
    out["n_sweeps"] = g["n_sweeps"].sum()
    for q in QUANTITIES:
        out[f"{q}_mean"] = g[q].mean()
        out[f"{q}_sd"] = g[q].std(ddof=1)
    return out.reset_index()
