"""What every amplitude model module of :mod:`contactres.analysis._models` declares.

A model module holds the model's metadata (:class:`contactres.fitting.Model`: parameters with
keys, units, bounds, fixed flags, and the model function) and, for a model that the analysis
fits to every sweep, a :class:`SweepFit`: its batched fitter and the fields of its fit table.
The shared parameters (the low-amplitude limits, the slopes and curvatures, those of the exact
loops) are defined here once.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from ...fitting import Model, Parameter

__all__ = [
    "ANY",
    "CURVATURES",
    "LIMITS",
    "LOOP_TABLE",
    "SLOPES",
    "LoopInputs",
    "SweepFit",
    "amplitude_model",
    "closed_form_fields",
    "closed_form_table",
    "loop_parameters",
]

#: Unbounded.
ANY = (-np.inf, np.inf)
#: The low-amplitude limits Δf0, ΔΓ0 (paper 2, Eq. 1-2).
LIMITS = (
    Parameter("df0", "low-amplitude Δf0", "Hz", "df0_Hz", ANY, scale=100.0),
    Parameter("dgamma0", "low-amplitude ΔΓ0", "Hz", "dgamma0_Hz", ANY, scale=10.0),
)
#: The slopes of a straight line in u0 (paper 2, Eq. 12).
SLOPES = (
    Parameter("df_slope", "dΔf/du0", "Hz/m", "df_slope_Hz_per_m", ANY, scale=1e9),
    Parameter("dgamma_slope", "dΔΓ/du0", "Hz/m", "dgamma_slope_Hz_per_m", ANY, scale=1e9),
)
#: The curvatures of a straight line in u0² (paper 2, Eq. 15).
CURVATURES = (
    Parameter("df_curvature", "d²Δf/du0² / 2", "Hz/m^2", "df_curvature_Hz_per_m2", ANY, scale=1e17),
    Parameter(
        "dgamma_curvature",
        "d²ΔΓ/du0² / 2",
        "Hz/m^2",
        "dgamma_curvature_Hz_per_m2",
        ANY,
        scale=1e17,
    ),
)


def amplitude_model(key, display, extra, source, function) -> Model:
    """A model of Δf(u0), ΔΓ(u0) in Hz with the limits and the ``extra`` parameters."""
    return Model(
        key, display, LIMITS + extra, "amplitude", "m", "df, dgamma", "Hz", source, function
    )


def loop_parameters(scale: str = "κ/(μF_N)") -> tuple[Parameter, ...]:
    """Pκ and Pωξ (the low-amplitude limits) and the loop's amplitude scale (κ/(μF_N), or 1/d_s
    for Savkoor's loop). Each is held in the loop's fit table (``Results.fits[key]``) under its
    own key, so the column a parameter names is its key (the named limits of the sweep
    results are the chosen model's, not the loop's)."""
    return (
        Parameter("df0", "Pκ (low-amplitude Δf0)", "Hz", "df0", (0.0, np.inf), scale=100.0),
        Parameter("dgamma0", "Pωξ (low-amplitude ΔΓ0)", "Hz", "dgamma0", ANY, scale=10.0),
        Parameter(
            "inverse_slip_scale",
            scale,
            "1/m",
            "inverse_slip_scale",
            (0.0, np.inf),
            scale=1e8,
        ),
    )


@dataclass(frozen=True)
class LoopInputs:
    """What the fitters of the exact loops need besides the points: the loop tables
    (:func:`contactres.analysis._loops.loop_tables`) and which sweeps get the plateau loop."""

    tables: object  # LoopTables
    plateau: np.ndarray  # (S,) bool


@dataclass(frozen=True)
class SweepFit:
    """The batched fit of one registered model to a block of sweeps.

    Attributes
    ----------
    model : key of the model in :data:`contactres.analysis.REGISTRY`
    source : the short name of the fit (``el``, ``line``, ... ``pl``): the key of its field
        table in the analysis (:data:`contactres.analysis._classify.FieldTables`), and its name
        in the model choice (:data:`contactres.analysis._classify.CLASS_SOURCES`)
    exact : fitted only with ``exact_loop`` (the exact loops)
    fit : ``fit(block, done, inputs) -> {field: (S,) array}``; ``done`` holds the fields of the
        fits before it, by source (a fit may start from or be weighted by an earlier one)
    table : field -> column of the model's fit table (``Results.fits[model]``): the
        parameters under their keys (``<key>``, its standard error ``<key>_err``), the other
        fields (residual sums, covariances, the loop's x at the largest amplitude ...) named
        alike
    """

    model: str
    source: str
    exact: bool
    fit: Callable
    table: Mapping[str, str]


def closed_form_fields(fit) -> dict[str, np.ndarray]:
    """The fields of a closed-form straight-line fit (both channels) in the order the analysis
    keeps them; ``fit`` is a :class:`contactres.analysis._amplitude.LineFit`."""
    out = {}
    for c, name in enumerate(("df", "dgamma")):
        out[f"{name}0_Hz"] = fit.a[c]
        out[f"{name}0_err_Hz"] = np.sqrt(fit.var_a[c])
        out[f"{name}_b"] = fit.b[c]
        out[f"{name}_b_err"] = np.sqrt(fit.var_b[c])
        out[f"{name}_cov_ab"] = fit.cov_ab[c]
        out[f"rss_{name}"] = fit.rss[c]
    return out


def closed_form_table(slope: str) -> dict[str, str]:
    """Fit-table columns of a closed-form fit whose second parameter is ``<channel>_<slope>``."""
    out = {}
    for name in ("df", "dgamma"):
        out[f"{name}0_Hz"] = f"{name}0"
        out[f"{name}0_err_Hz"] = f"{name}0_err"
        out[f"{name}_b"] = f"{name}_{slope}"
        out[f"{name}_b_err"] = f"{name}_{slope}_err"
        out[f"{name}_cov_ab"] = f"cov_{name}0_{name}_{slope}"
        out[f"rss_{name}"] = f"rss_{name}"
    return out


#: Fit-table columns of an exact-loop fit (:func:`contactres.analysis._loops.loop_fit_fields`):
#: θ is the parameter ``inverse_slip_scale``, its error that of ln θ.
LOOP_TABLE = {
    "df0_Hz": "df0",
    "df0_err_Hz": "df0_err",
    "dgamma0_Hz": "dgamma0",
    "dgamma0_err_Hz": "dgamma0_err",
    "theta_per_m": "inverse_slip_scale",
    "lntheta_err": "ln_inverse_slip_scale_err",
    "cov_df0_lntheta": "cov_df0_ln_inverse_slip_scale",
    "x_max": "x_max",
    "edge": "edge",
    "rss_df": "rss_df",
    "rss_dgamma": "rss_dgamma",
}
