"""The models the sweep analysis fits, with their metadata: :data:`REGISTRY`.

Amplitude models of one sweep, Δf(u0) and ΔΓ(u0) (paper 2, Figs. 1D and 4), each fitted to both
channels at once:

``elastic``                 Δf = Δf0, ΔΓ = ΔΓ0 (a Voigt element, paper 2, Eq. 1)
``cattaneo-mindlin``        straight line in u0 (paper 2, Eq. 12)
``savkoor``                 straight line in u0² (paper 2, Eq. 15)
``plateau``                 flat below u_c, straight line above (paper 2, Fig. 4C, D)
``cattaneo-mindlin-loop``   the exact Cattaneo-Mindlin loop with a dashpot (paper 2, Eqs. 4-6)
``savkoor-loop``            the exact Savkoor loop with a dashpot (paper 2, Eqs. 13-14)
``plateau-loop``            the Cattaneo-Mindlin loop behind a stick plateau of width d_c

and the model of the load dependence, ``jkr-mindlin``: κ(F_N) = 2G*a with the JKR contact
radius (paper 2, Eqs. 7-10). Each parameter names the column of the results that holds its
fitted value. The closed-form and variable-projection fitters of
:mod:`contactres.analysis.amplitude`, :mod:`contactres.analysis.loops` and
:mod:`contactres.analysis.jkr` solve these models; the tests check each against
:func:`contactres.fitting.fit` on the registered function (a second algorithm).
"""

from __future__ import annotations

import numpy as np

from ..fitting import Model, ModelRegistry, Parameter
from ..tangential import kappa_jkr_mindlin
from ..units import POISSON_OPEN_RANGE
from .loops import cm_loop_shape, plateau_loop_shape, savkoor_loop_shape

__all__ = ["AMPLITUDE_MODELS", "N_PARAMETERS", "REGISTRY", "exact_model", "model_curves"]

#: The amplitude classes, simplest and most common first (the order of the model choice).
AMPLITUDE_MODELS = ("elastic", "cattaneo-mindlin", "savkoor", "plateau")

_ANY = (-np.inf, np.inf)
_LIMITS = (
    Parameter("df0", "low-amplitude Δf0", "Hz", "df0_Hz", _ANY, scale=100.0),
    Parameter("dgamma0", "low-amplitude ΔΓ0", "Hz", "dgamma0_Hz", _ANY, scale=10.0),
)
_SLOPES = (
    Parameter("df_slope", "dΔf/du0", "Hz/m", "df_slope_Hz_per_m", _ANY, scale=1e9),
    Parameter("dgamma_slope", "dΔΓ/du0", "Hz/m", "dgamma_slope_Hz_per_m", _ANY, scale=1e9),
)
_CURVATURES = (
    Parameter(
        "df_curvature", "d²Δf/du0² / 2", "Hz/m^2", "df_curvature_Hz_per_m2", _ANY, scale=1e17
    ),
    Parameter(
        "dgamma_curvature",
        "d²ΔΓ/du0² / 2",
        "Hz/m^2",
        "dgamma_curvature_Hz_per_m2",
        _ANY,
        scale=1e17,
    ),
)


def _amplitude_model(key, display, extra, source, function) -> Model:
    return Model(
        key, display, _LIMITS + extra, "amplitude", "m", "df, dgamma", "Hz", source, function
    )


def _elastic(u, df0, dgamma0):
    return df0 + 0.0 * u, dgamma0 + 0.0 * u


def _line(u, df0, dgamma0, df_slope, dgamma_slope):
    return df0 + df_slope * u, dgamma0 + dgamma_slope * u


def _parabola(u, df0, dgamma0, df_curvature, dgamma_curvature):
    return df0 + df_curvature * u**2, dgamma0 + dgamma_curvature * u**2


def _hinge(u, df0, dgamma0, df_slope, dgamma_slope, critical_amplitude):
    excess = np.maximum(u - critical_amplitude, 0.0)
    return df0 + df_slope * excess, dgamma0 + dgamma_slope * excess


def _cm_loop(u, df0, dgamma0, inverse_slip_scale):
    # Δf0 = Pκ and ΔΓ0 = Pωξ; the loop's shape depends on u0 only through κu0/(μF_N).
    g1, g2 = cm_loop_shape(np.asarray(inverse_slip_scale) * np.asarray(u))
    return df0 * g1, dgamma0 + df0 * g2


def _savkoor_loop(u, df0, dgamma0, inverse_slip_scale):
    # Savkoor's loop is self-similar in u0/d_s (d_s = 4a²τ0/κ: full sliding).
    g1, g2 = savkoor_loop_shape(np.asarray(inverse_slip_scale) * np.asarray(u))
    return df0 * g1, dgamma0 + df0 * g2


def _plateau_loop(u, df0, dgamma0, inverse_slip_scale, critical_displacement):
    theta = np.asarray(inverse_slip_scale)
    g1, g2 = plateau_loop_shape(theta * np.asarray(u), theta * critical_displacement)
    return df0 * g1, dgamma0 + df0 * g2


def _loop_parameters(prefix: str, scale: str = "κ/(μF_N)") -> tuple[Parameter, ...]:
    """Pκ and Pωξ (the low-amplitude limits) and the loop's amplitude scale (κ/(μF_N), or 1/d_s
    for Savkoor's loop), held in the columns ``<prefix>df0_Hz``, ``<prefix>dgamma0_Hz``,
    ``<prefix>theta_per_m`` of the per-sweep results (``cm_`` for the Cattaneo-Mindlin loop fit,
    ``sv_`` for Savkoor's loop, ``pl_`` for the plateau loop)."""
    return (
        Parameter(
            "df0", "Pκ (low-amplitude Δf0)", "Hz", f"{prefix}df0_Hz", (0.0, np.inf), scale=100.0
        ),
        Parameter(
            "dgamma0", "Pωξ (low-amplitude ΔΓ0)", "Hz", f"{prefix}dgamma0_Hz", _ANY, scale=10.0
        ),
        Parameter(
            "inverse_slip_scale",
            scale,
            "1/m",
            f"{prefix}theta_per_m",
            (0.0, np.inf),
            scale=1e8,
        ),
    )


#: Every model the sweep analysis fits, by key.
REGISTRY = ModelRegistry(
    (
        _amplitude_model(
            "elastic", "no amplitude dependence", (), "paper 2, Eq. 1 (Voigt element)", _elastic
        ),
        _amplitude_model(
            "cattaneo-mindlin", "linear in u0 (Cattaneo-Mindlin)", _SLOPES, "paper 2, Eq. 12", _line
        ),
        _amplitude_model(
            "savkoor", "parabolic in u0 (Savkoor)", _CURVATURES, "paper 2, Eq. 15", _parabola
        ),
        _amplitude_model(
            "plateau",
            "flat below u_c, linear above",
            (
                *_SLOPES,
                Parameter(
                    "critical_amplitude",
                    "critical amplitude u_c",
                    "m",
                    "plateau_amplitude_m",
                    (0.0, 1e-6),
                    scale=1e-9,
                ),
            ),
            "paper 2, Fig. 4C, D (stick plateau)",
            _hinge,
        ),
        Model(
            "cattaneo-mindlin-loop",
            "exact Cattaneo-Mindlin loop with a dashpot",
            _loop_parameters("cm_"),
            "amplitude",
            "m",
            "df, dgamma",
            "Hz",
            "paper 2, Eqs. 4-6 (Masing loops) and Eq. 12 (dashpot)",
            _cm_loop,
        ),
        Model(
            "savkoor-loop",
            "exact Savkoor loop (constant sliding traction) with a dashpot",
            _loop_parameters("sv_", "1/d_s = κ/(4a²τ0)"),
            "amplitude",
            "m",
            "df, dgamma",
            "Hz",
            "paper 2, Eqs. 13-14 (Masing loops) and Eq. 12 (dashpot)",
            _savkoor_loop,
        ),
        Model(
            "plateau-loop",
            "exact Cattaneo-Mindlin loop behind a stick plateau, with a dashpot",
            (
                *_loop_parameters("pl_"),
                Parameter(
                    "critical_displacement",
                    "critical displacement d_c",
                    "m",
                    "pl_d_c_m",
                    (0.0, 1e-6),
                    scale=1e-9,
                ),
            ),
            "amplitude",
            "m",
            "df, dgamma",
            "Hz",
            "paper 2, Eqs. 4-6 (Masing loops), Fig. 4C, D (stick plateau), Eq. 12 (dashpot)",
            _plateau_loop,
        ),
        Model(
            "jkr-mindlin",
            "JKR + Mindlin tangential stiffness",
            (
                Parameter("E", "Young's modulus E", "Pa", "E_Pa", (1e6, 1e13), scale=1e10),
                Parameter(
                    "gamma", "energy of adhesion γ", "J/m^2", "gamma_J_m2", (0.0, 1e3), scale=0.1
                ),
                Parameter(
                    "radius", "sphere radius R", "m", "sphere_radius_m", (1e-9, 1.0), True, 1e-3
                ),
                Parameter("poisson", "Poisson ratio ν", "-", "poisson", POISSON_OPEN_RANGE, True),
            ),
            "normal_force",
            "N",
            "kappa",
            "N/m",
            "paper 2, Eqs. 7-10 and κ = 2G*a",
            kappa_jkr_mindlin,
        ),
    )
)

#: Number of fitted parameters of each amplitude model (the k of its BIC).
N_PARAMETERS = {key: len(model.parameters) for key, model in REGISTRY.items()}

# The exact loop that stands behind a sweep whose limits come from it.
_EXACT = {
    "cm-loop": "cattaneo-mindlin-loop",
    "savkoor-loop": "savkoor-loop",
    "plateau-loop": "plateau-loop",
}


def exact_model(model, limits_from) -> str | None:
    """The registered model that draws a sweep of class ``model`` whose limits come from
    ``limits_from`` (its exact loop where they come from one); None where there is none (a
    sweep without a class)."""
    key = _EXACT.get(limits_from, model)
    return key if isinstance(key, str) and key in REGISTRY else None


def model_curves(row, u) -> tuple[np.ndarray, np.ndarray]:
    """Δf(u0), ΔΓ(u0) in Hz of the model chosen for one sweep (a row of the sweep results).

    Evaluates the registered model function with the sweep's fitted values, read from the
    columns its parameters name; a sweep whose limits come from an exact loop (Cattaneo-Mindlin,
    Savkoor or plateau, column ``limits_from``) is drawn as that loop.
    """
    u = np.asarray(u, dtype=float)
    model = REGISTRY[_EXACT.get(row.get("limits_from"), row["model"])]
    values = {p.key: row[p.column] for p in model.parameters}
    df, dg = model.function(u, **values)
    return np.broadcast_to(df, u.shape).astype(float), np.broadcast_to(dg, u.shape).astype(float)
