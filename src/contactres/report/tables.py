"""Results of the sweep analysis and the results folder they are written to.

``Results.write(folder)`` writes, each file atomically (:mod:`contactres.fileio`):

``sweeps.csv``
    one row per sweep: :data:`SWEEP_COLUMNS` in this order, then the uncertainties and derived
    quantities of :data:`SWEEP_EXTRA_COLUMNS`. ``model``: the amplitude class (elastic,
    cattaneo-mindlin, savkoor, plateau). ``plateau_amplitude_m`` (± ``plateau_amplitude_err_m``):
    the critical displacement d_c of a plateau sweep, from the fit of the exact plateau loop
    (the hinge of the plateau model if that fit is off or unresolved; then no error). ``df0_Hz``,
    ``dgamma0_Hz``: low-amplitude limits. ``df_slope_Hz_per_m``, ``dgamma_slope_Hz_per_m``: the
    straight line, or for a plateau the hinge slope above the plateau (descriptive only).
    ``mu_df``, ``mu_dgamma``: μ from those slopes (physics.md Eq. 11-12), Cattaneo-Mindlin
    sweeps only; empty for a plateau sweep (flag ``plateau-slope``: the shifts leave a plateau
    with no linear term, so no slope formula holds). ``mu_fit``: μ from the fit of the exact
    loop (Cattaneo-Mindlin, or Cattaneo-Mindlin behind the plateau). ``flags``: ';'-separated
    (see :mod:`contactres.analysis`).
``loads.csv``
    one row per (configuration, medium, normal force): ``n_experiments``, ``n_sweeps`` and
    ``<quantity>_mean``, ``<quantity>_sd`` (standard deviation over experiments, ddof = 1) of
    Δf0, ΔΓ0 (Hz), κ, ωξ (N/m), the loss tangent ΔΓ0/Δf0 and μ (from Δf, from ΔΓ, from the fit).
``summary.json``
    ``{"groups": [...], "settings": {...}, "version": ..., "conventions": {...}}``; one group per
    (configuration, medium) with the JKR + Mindlin fit (Table 1 of paper 2).
``fig4_sweeps.png``, ``fig5_df0_vs_load.png``, ``fig7_dissipation_vs_load.png``,
``fig8_friction_vs_load.png``
    the figures of paper 2 for these data (:mod:`contactres.plots`).

Conventions: Δf is the frequency shift (not Δf/n); ΔΓ the half-bandwidth at half height (not D);
amplitudes in m; forces per contact in N; NaN (CSV: empty; JSON: null) where not applicable.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd

from ..fileio import ensure_dir, write_csv, write_text

__all__ = ["SUMMARY_GROUP_KEYS", "SWEEP_COLUMNS", "SWEEP_EXTRA_COLUMNS", "Results"]

SWEEP_COLUMNS = (
    "sweep",
    "experiment",
    "configuration",
    "medium",
    "normal_force_N",
    "ramp",
    "used",
    "model",
    "plateau_amplitude_m",
    "df0_Hz",
    "df0_err_Hz",
    "df_slope_Hz_per_m",
    "dgamma0_Hz",
    "dgamma_slope_Hz_per_m",
    "mu_df",
    "mu_dgamma",
    "mu_fit",
    "flags",
)
SWEEP_EXTRA_COLUMNS = (
    "n_points",
    "direction",
    "dgamma0_err_Hz",
    "df_slope_err_Hz_per_m",
    "dgamma_slope_err_Hz_per_m",
    "df_curvature_Hz_per_m2",
    "dgamma_curvature_Hz_per_m2",
    "kappa_N_per_m",
    "omega_xi_N_per_m",
    "loss_tangent",
    "mu_df_err",
    "mu_dgamma_err",
    "mu_fit_err",
    "plateau_amplitude_err_m",
)
SUMMARY_GROUP_KEYS = (
    "configuration",
    "medium",
    "E_Pa",
    "E_err_Pa",
    "gamma_J_m2",
    "gamma_err_J_m2",
    "n_experiments",
    "n_sweeps_used",
    "models",
)
CONVENTIONS = {
    "df": "frequency shift Δf in Hz (not Δf/n)",
    "dgamma": "shift of the half-bandwidth at half height ΔΓ in Hz (dissipation D = 2Γ/f)",
    "amplitude": "oscillation amplitude u0 in m",
    "normal_force": "normal force per contact in N",
    "gamma": "paper 2's energy of adhesion γ in J/m² (work of adhesion w = 2γ)",
    "E": "Young's modulus of both bodies (E1 = E2), Pa, with ν fixed (settings/poisson)",
    "errors": "_err: standard error of a fit; _sd: standard deviation over experiments",
}


def _clean(value):
    """JSON-safe: NaN/inf -> None, numpy scalars -> Python."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


@dataclass
class Results:
    """Everything :func:`contactres.analyze` found.

    Attributes
    ----------
    sweeps : one row per sweep (all columns, including internal ones)
    loads : one row per (configuration, medium, normal force)
    experiments : one row per (configuration, medium, normal force, experiment): the means of
        its used sweeps (the points of the JKR fit)
    groups : one dict per (configuration, medium): JKR + Mindlin fit and counts
    settings : the settings used
    version : contactres version
    table : the input sweep table
    padded : the sweeps as padded arrays (for the figures)
    """

    sweeps: pd.DataFrame
    loads: pd.DataFrame
    experiments: pd.DataFrame
    groups: list[dict]
    settings: dict
    version: str
    table: pd.DataFrame | None = None
    padded: Any = field(default=None, repr=False)

    @property
    def sweeps_table(self) -> pd.DataFrame:
        """The ``sweeps.csv`` table."""
        cols = [*SWEEP_COLUMNS, *SWEEP_EXTRA_COLUMNS]
        return self.sweeps[cols].copy()

    @property
    def summary(self) -> dict:
        """The ``summary.json`` record."""
        groups = []
        for g in self.groups:
            ordered = {k: g.get(k) for k in SUMMARY_GROUP_KEYS}
            ordered.update({k: v for k, v in g.items() if k not in ordered})
            groups.append(ordered)
        source = None if self.table is None else self.table.attrs.get("source")
        return _clean(
            {
                "groups": groups,
                "settings": self.settings,
                "version": self.version,
                "source": source,
                "conventions": CONVENTIONS,
            }
        )

    def table1(self) -> pd.DataFrame:
        """Table 1 of paper 2 for these data: E (GPa) and γ (mJ/m²) per configuration/medium."""
        rows = []
        for g in self.groups:
            rows.append(
                {
                    "configuration": g["configuration"],
                    "medium": g["medium"],
                    "E_GPa": g["E_Pa"] / 1e9,
                    "E_err_GPa": g["E_err_Pa"] / 1e9,
                    "gamma_mJ_m2": g["gamma_J_m2"] * 1e3,
                    "gamma_err_mJ_m2": g["gamma_err_J_m2"] * 1e3,
                    "n_exp": g["n_experiments"],
                    "n_sweeps": g["n_sweeps_used"],
                }
            )
        return pd.DataFrame(rows)

    def write(self, folder, figures: bool = True) -> list[Path]:
        """Write the results folder (see the module docstring); return the paths written."""
        out = ensure_dir(folder)
        written = [
            write_csv(out / "sweeps.csv", self.sweeps_table),
            write_csv(out / "loads.csv", self.loads),
            write_text(
                out / "summary.json", json.dumps(self.summary, indent=1, ensure_ascii=False) + "\n"
            ),
        ]
        if figures:
            from .figures import write_figures

            written.extend(write_figures(self, out))
        return written
