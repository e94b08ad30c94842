"""Statistics per load: the used sweeps of each experiment averaged, then over experiments.

Paper 2 reports, per configuration, medium and normal force, the mean and the spread of the
quantities over repeated experiments (its Figs. 5, 7, 8); a NaN value (e.g. the slope μ of a
plateau sweep) is skipped, and a load without any value gets NaN.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..measurements.schema import LOAD_QUANTITIES
from ._jkr import t95_factor

__all__ = [
    "GROUP_KEYS",
    "LOAD_KEYS",
    "MU_WITHHELD",
    "QUANTITIES",
    "per_experiment",
    "per_load",
    "withhold_mu",
]

#: The quantities averaged per load (columns of the sweep results).
QUANTITIES = tuple(name for name, _, _ in LOAD_QUANTITIES)
#: One group of the JKR fit, one load of a group.
GROUP_KEYS = ["configuration", "medium"]
LOAD_KEYS = ["configuration", "medium", "normal_force_N"]
#: The flag of a load whose μ is withheld with its group's E and γ (:func:`withhold_mu`).
MU_WITHHELD = "mu-withheld"
# The checks of a group's JKR fit that name an input μ scales with as well: κ, and with it μ,
# is proportional to area_m2 and n_contacts (paper 2, Eqs. 3 and 12), and μ is a force ratio
# (normal_force_N). A fit at a bound or too few loads say nothing about those inputs.
_MU_CHECKS = ("E-out-of-range", "gamma-out-of-range")


def _used(sw: pd.DataFrame, columns) -> pd.DataFrame:
    """The used sweeps, their ``columns`` (and ``mu_block`` where ``sw`` has it), with
    ``mu_fit`` the joint fit of their load block where there is one (``mu_block``): one μ for
    ramps that share a contact, better conditioned than the mean of their separate nonlinear
    fits. Both statistics below take μ from here.

    Only the columns the statistics read: the used rows of every column (~80) were copied
    twice, a fifth of this stage at 10^5 sweeps (issue 31, point 3)."""
    names = list(dict.fromkeys([*columns, *(["mu_block"] if "mu_block" in sw else [])]))
    used = sw.loc[sw["used"], names]
    if "mu_block" in used:
        block = used["mu_block"].to_numpy(float)
        used = used.assign(mu_fit=np.where(np.isfinite(block), block, used["mu_fit"]))
    return used


def per_experiment(sw: pd.DataFrame) -> pd.DataFrame:
    """One row per (load, experiment): the means of its used sweeps and their number (``mu_fit``:
    the joint fit of the load block, ``mu_block``, where there is one)."""
    firsts = ("sphere_radius_m", "poisson", "P_Hz_per_N_per_m")
    used = _used(sw, [*LOAD_KEYS, "experiment", *QUANTITIES, *firsts])
    g = used.groupby([*LOAD_KEYS, "experiment"], sort=True)
    exp = g[list(QUANTITIES)].mean()
    exp["n_sweeps"] = g.size()
    for c in firsts:
        exp[c] = g[c].first()
    return exp.reset_index()


def per_load(exp: pd.DataFrame, sw: pd.DataFrame) -> pd.DataFrame:
    """One row per load: mean, sd (ddof = 1), standard error and median over experiments.

    ``exp``: :func:`per_experiment`; ``sw``: the sweep results (``used`` marks the sweeps behind
    the means). The standard error ``_sem`` is sd/√n over the experiments; a load measured in
    one experiment only gets it from its repeated sweeps instead (sd over the used sweeps/√n,
    which does not include what remounting the sample changes); ``errors_from`` says which.
    ``_median`` is the median over the experiments (over the sweeps for one experiment), a
    location robust to one odd experiment, with ``_median_err`` = 1.2533 × ``_sem`` (the median's
    large-sample error for normal scatter). ``dof`` (experiments - 1, or sweeps - 1 for one
    experiment) and ``t95`` (the Student-t factor of a two-sided 95 % interval) say how far to
    trust an error estimated from a few repeats.
    """
    g = exp.groupby(LOAD_KEYS, sort=True)
    out = g.size().rename("n_experiments").to_frame()
    out["n_sweeps"] = g["n_sweeps"].sum()
    used = _used(sw, [*LOAD_KEYS, *QUANTITIES]).groupby(LOAD_KEYS, sort=True)
    single = (out["n_experiments"] == 1).to_numpy()
    out["errors_from"] = np.where(single, "sweeps of one experiment", "experiments")
    out.loc[single & (out["n_sweeps"] < 2).to_numpy(), "errors_from"] = ""
    # A standard error from a few repeats has their number minus one degrees of freedom.
    dof = np.where(single, out["n_sweeps"] - 1, out["n_experiments"] - 1).astype(float)
    out["dof"] = np.where(dof >= 1, dof, np.nan)
    out["t95"] = t95_factor(out["dof"])
    for q in QUANTITIES:
        sweep_sd = used[q].std(ddof=1).reindex(out.index)
        sweep_n = used[q].count().reindex(out.index)
        out[f"{q}_mean"] = g[q].mean()
        out[f"{q}_sd"] = g[q].std(ddof=1)
        sem = out[f"{q}_sd"] / np.sqrt(g[q].count())
        out[f"{q}_sem"] = np.where(single, sweep_sd / np.sqrt(sweep_n), sem)
        out[f"{q}_median"] = np.where(single, used[q].median().reindex(out.index), g[q].median())
        out[f"{q}_median_err"] = 1.2533 * out[f"{q}_sem"]
    return out.reset_index()


def withhold_mu(loads: pd.DataFrame, groups: list[dict]) -> pd.DataFrame:
    """``loads`` with the μ of every load of a group whose E and γ were withheld for a unit
    slip (its checks ``E-out-of-range`` or ``gamma-out-of-range``) set to NaN, and a ``flags``
    column: :data:`MU_WITHHELD` on those loads, empty on the others.

    The inputs those checks name (area_m2, n_contacts, normal_force_N) scale μ too: an area in
    mm² typed as m² gave E = 1e4 GPa, withheld, and μ = 44 per load, printed (issue 30).
    """
    out = loads.copy()
    flags = np.full(len(out), "", dtype=object)
    mu = [c for c in out.columns if c.startswith("mu_")]
    for g in groups:
        if not any(c in _MU_CHECKS for c in g.get("checks", ())):
            continue
        rows = (out["configuration"] == g["configuration"]).to_numpy() & (
            out["medium"] == g["medium"]
        ).to_numpy()
        out.loc[rows, mu] = np.nan
        flags[rows] = MU_WITHHELD
    out["flags"] = flags
    return out
