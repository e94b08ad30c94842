"""Job ``qcm_particles``: attached particles against time from QCM-D shifts over the overtones
(issue 28).

Inputs: the path of a QCM-D file, an instrument's text export (QSense, AWSensors, QCM-I,
openQCM) or the tidy table ``time_s, overtone, df_Hz, dgamma_Hz``
(:data:`contactres.measurements.schema.QCMD_SHIFTS_TABLE`), read by the plug-ins of
:data:`contactres.measurements.readers.exports.SHIFT_READERS`. Settings: the particle (radius and
density of a sphere, or its mass and moment of inertia), the rocking of the particle about its
contact, the medium, the fundamental, how to read the file and the noise of the shifts.

Per time step the shifts of all overtones are fitted together
(:func:`contactres.analysis.fit_particles`) with the load of N particles per area A on their
contacts in paper 2's small-load relation, Δf_n + iΔΓ_n = (N/A) K_L(ω_n)/(2nπ² Z_q), ω_n = 2π n f_F
(:func:`contactres.resonators.particle_shifts`): the contact stiffness κ, its damping ξ, the
coverage N/A and the coupled-resonance frequency, with standard errors. A value the data do not
identify is NaN (an empty cell of ``particles.csv``) and named in the step's ``flags``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING

from .._threads import one_blas_thread
from ..errors import ContactresInputError
from ..measurements.schema import PARTICLE_SHIFTS_CSV, PARTICLES_CSV
from ..units import check_magnitude
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    import numpy as np
    import pandas as pd

__all__ = [
    "COLUMN_UNITS",
    "CONVENTIONS",
    "EQUATION",
    "ROCKING",
    "Result",
    "Settings",
    "run",
]

#: The choices of the particle's rotation about its contact (``--rocking``).
ROCKING = MappingProxyType(
    {
        "free": "no rocking stiffness at the contact: the sphere may roll about its contact "
        "point (rigidly attached, it loads the sensor with I/(I + mR²) of its mass, 2/7 for a "
        "homogeneous sphere)",
        "locked": "no rotation of the particle (rigidly attached, it loads the sensor with its "
        "whole mass)",
        "fit": "a rocking stiffness κ_r (N m/rad) at the contact, fitted per time step",
    }
)

#: What the shifts are, recorded with every result.
CONVENTIONS = MappingProxyType(
    {
        "df": "Δf_n, Hz, not divided by n",
        "dgamma": "ΔΓ_n, Hz, the shift of the half bandwidth at half height (Γ = D f_n/2)",
        "reference": "the bare sensor in the same medium (the medium's own load, e.g. "
        "Kanazawa-Gordon in a liquid, is in the reference, not in the shifts)",
        "coverage": "dilute: no hydrodynamic or mechanical interaction between particles",
    }
)

EQUATION = (
    "Δf_n + iΔΓ_n = (N/A) K_L(ω_n)/(2nπ² Z_q), ω_n = 2π n f_F; K_L the load of one particle "
    "on its contact κ + iωξ (contactres.resonators.particle_stiffness; paper 2, Eqs. 1-2 "
    "with n_P/A_eff -> N/A)"
)

#: Units of the columns of both tables (recorded with the result).
COLUMN_UNITS = MappingProxyType(
    {
        "time_s": "s",
        "overtone": "1",
        "df_Hz": "Hz (Δf, not divided by n)",
        "dgamma_Hz": "Hz (ΔΓ, half bandwidth)",
        "df_model_Hz": "Hz (Δf of the fitted model)",
        "dgamma_model_Hz": "Hz (ΔΓ of the fitted model)",
        "kappa_N_per_m": "N/m (per particle)",
        "kappa_err_N_per_m": "N/m (standard error)",
        "xi_kg_per_s": "kg/s (per particle)",
        "xi_err_kg_per_s": "kg/s (standard error)",
        "coverage_per_m2": "1/m^2 (particles per area)",
        "coverage_err_per_m2": "1/m^2 (standard error)",
        "f_coupled_Hz": "Hz",
        "flags": "text (';'-separated)",
        # the per-step values of particles.json (``steps``), beside particles.csv's columns
        "coverage_kappa_N_per_m3": "N/m^3 (coverage × κ: what an inertial step identifies)",
        "coverage_kappa_err_N_per_m3": "N/m^3 (standard error)",
        "coverage_xi_kg_per_s_m2": "kg/(s m^2) (coverage × ξ)",
        "coverage_xi_err_kg_per_s_m2": "kg/(s m^2) (standard error)",
        "chi2_per_dof": "1 with the noise stated (a test of it); Hz^2 without (the noise "
        "variance estimated from the residuals)",
        "kappa_r_N_m_per_rad": "N m/rad (the fitted rocking stiffness; --rocking fit only)",
        "kappa_r_err_N_m_per_rad": "N m/rad (standard error)",
        "f_coupled_err_Hz": "Hz (standard error of f_coupled)",
        # the correlations of the fitted parameters (ln κ, ξ, ln N, ln κ_r), per step
        **{
            f"corr_{a}_{b}": f"1 (correlation of the fitted {a} and {b}; also where a value "
            "is unresolved: near ±1 it names the direction the data do not fix)"
            for a, b in (
                ("kappa", "xi"),
                ("kappa", "coverage"),
                ("xi", "coverage"),
                ("kappa", "kappa_r"),
                ("xi", "kappa_r"),
                ("coverage", "kappa_r"),
            )
        },
    }
)

#: The per-step values of ``particles.json`` (``steps``, after ``time_s``: name -> the fit's
#: field): what the contract's particles.csv leaves out; units in COLUMN_UNITS.
_STEP_FIELDS = MappingProxyType(
    {
        "coverage_kappa_N_per_m3": "coverage_kappa",
        "coverage_kappa_err_N_per_m3": "coverage_kappa_err",
        "coverage_xi_kg_per_s_m2": "coverage_xi",
        "coverage_xi_err_kg_per_s_m2": "coverage_xi_err",
        "kappa_r_N_m_per_rad": "kappa_r",
        "kappa_r_err_N_m_per_rad": "kappa_r_err",
        "f_coupled_err_Hz": "f_coupled_err",
    }
)


@dataclass(frozen=True)
class Settings:
    """The particle, its contact's rotation, the medium and how to read the file.

    Parameters
    ----------
    particle_radius : float
        Radius R of the particle, m (a sphere's; the lever arm of rocking about the contact).
    particle_density : float or None
        Density of the sphere, kg/m³ (None: give ``particle_mass`` and ``moment_of_inertia``).
    particle_mass, moment_of_inertia : float or None
        Mass m (kg) and moment of inertia I about the centre (kg m²) of a particle that is no
        homogeneous sphere (both, instead of the density).
    fundamental : float or None
        Fundamental frequency f_F of the crystal, Hz (None: from the export's absolute
        frequencies; a tidy table needs it).
    rocking : str
        ``free``, ``locked`` or ``fit`` (:data:`ROCKING`).
    medium : str or None
        ``air``, ``water`` (:func:`contactres.resonators.medium_named`) or None (no load of a
        medium on the particles).
    reader : str or None
        The reader's name (None: recognised from the header; ``tidy`` or an export reader).
    conventions : dict or None
        What an export does not say, as :func:`contactres.measurements.readers.exports.read_export`
        takes it (``df_divided_by_n``, ``dissipation_scale``, ``baseline``, ``time_unit``,
        ``channel``, ``overtone``; ``fundamental`` is the field above).
    zq : float
        Acoustic impedance Z_q of AT-cut quartz, kg m^-2 s^-1.
    sigma_df, sigma_dgamma : float or None
        Standard deviation of the noise of Δf_n and ΔΓ_n, Hz (None: estimated by the fit from
        its residuals).
    """

    particle_radius: float
    particle_density: float | None = None
    particle_mass: float | None = None
    moment_of_inertia: float | None = None
    fundamental: float | None = None
    rocking: str = "free"
    medium: str | None = None
    reader: str | None = None
    conventions: dict | None = None
    zq: float = 8.8e6
    sigma_df: float | None = None
    sigma_dgamma: float | None = None


@dataclass(frozen=True)
class Result(JobResult):
    """``particles``: one row per time step (:data:`contactres.measurements.schema.PARTICLES_CSV`:
    κ, ξ, coverage, f_coupled, their errors and the flags; NaN where not identified);
    ``shifts``: the shifts read and the fitted model's per time and overtone
    (:data:`~contactres.measurements.schema.PARTICLE_SHIFTS_CSV`). The conventions the file was
    read with and those of the shifts, the constants (particle, medium, quartz, noise), the
    equation, the units of the columns, how many steps carry each flag and what each flag means
    (:data:`contactres.analysis.PARTICLE_FLAGS`); ``steps``, per time step, what particles.csv
    leaves out (the products coverage × κ and coverage × ξ with their errors, κ_r, the
    correlations of the fitted parameters and χ²/dof: lists over the steps, null where not
    identified; units in ``columns``); ``model_curves`` the fitted model on a fine grid of
    continuous n at a few steps (:func:`_model_curves`, for the figure); ``source`` the
    file's name and ``warnings`` what the reader left out and what the user should know."""

    SCHEMAS = MappingProxyType({"particles": PARTICLES_CSV, "shifts": PARTICLE_SHIFTS_CSV})
    NOT_VALUES = ("source", "warnings")
    NAME = "particles"
    #: Values the HTML page leaves to particles.json (lists over the steps, the model's curves)
    JSON_ONLY = ("steps", "model_curves")

    particles: pd.DataFrame
    shifts: pd.DataFrame
    conventions: dict
    constants: dict
    equation: str
    columns: dict
    flag_counts: dict
    flag_meanings: dict
    steps: dict
    model_curves: dict
    source: str = ""
    warnings: tuple[str, ...] = ()

    def summary(self) -> pd.DataFrame:
        """One row per quantity (κ, ξ, coverage, f_coupled): its unit, how many steps
        identify it, the median and the range of the identified values (NaN where none is);
        what the command prints and the report shows first."""
        import numpy as np
        import pandas as pd

        rows = []
        for column, quantity, unit in (
            ("kappa_N_per_m", "κ", "N/m"),
            ("xi_kg_per_s", "ξ", "kg/s"),
            ("coverage_per_m2", "coverage", "1/m^2"),
            ("f_coupled_Hz", "f_coupled", "Hz"),
        ):
            values = self.particles[column].to_numpy(float)
            ok = values[np.isfinite(values)]
            empty = ok.size == 0
            rows.append(
                {
                    "quantity": quantity,
                    "unit": unit,
                    "identified": f"{ok.size} of {values.size}",
                    "median": np.nan if empty else float(np.median(ok)),
                    "min": np.nan if empty else float(ok.min()),
                    "max": np.nan if empty else float(ok.max()),
                }
            )
        return pd.DataFrame(rows)


@one_blas_thread()
def run(inputs: str | os.PathLike, settings: Settings, progress: Progress | None = None) -> Result:
    """Fit the particles of the file ``inputs`` (see the module docstring)."""
    import numpy as np

    from ..analysis import PARTICLE_FLAGS, fit_particles

    source, s = Path(inputs), settings
    if s.rocking not in ROCKING:
        raise ContactresInputError(
            f"rocking {s.rocking!r} is not one of {', '.join(ROCKING)} (--rocking)"
        )
    particle = _particle(s)
    medium = _medium(s.medium)
    say(progress, f"reading {source.name}")
    table, left_out = _read(source, s)
    fundamental = table.conventions["fundamental_Hz"]
    if fundamental is None or not math.isfinite(fundamental):
        raise ContactresInputError(
            f"{source}: the fundamental frequency is not in the file: give it "
            "(fundamental=..., --fundamental, Hz)"
        )
    times, overtones, df, dgamma = _grid(table.data, source)
    lines = [*left_out, *_depth_check(particle, medium, fundamental, overtones, source)]
    say(progress, f"fitting {len(times)} time steps x {len(overtones)} overtones")
    fit = fit_particles(
        fundamental,
        overtones,
        df,
        dgamma,
        particle,
        rocking=s.rocking,
        medium=medium,
        sigma_df=s.sigma_df,
        sigma_dgamma=s.sigma_dgamma,
        zq=s.zq,
    )
    particles = _particles_table(times, fit)
    shifts = _shifts_table(times, overtones, df, dgamma, fit)
    counts = _flag_counts(particles["flags"])
    lines += _noise_lines(fit, counts)
    if counts:
        shown = ", ".join(f"{name} {k}" for name, k in counts.items())
        lines.append(
            f"flagged time steps (of {len(times)}): {shown}; what each flag means is in "
            "particles.json (flag_meanings)"
        )
    return Result(
        particles=particles,
        shifts=shifts,
        conventions={**dict(table.conventions), **CONVENTIONS, "rocking": ROCKING[s.rocking]},
        constants={
            **_constants(particle, medium, s, fundamental, np.asarray(overtones)),
            "noise_fit_Hz": _finite(getattr(fit, "noise_fit", math.nan)),
            "noise_series_Hz": _finite(getattr(fit, "noise_series", math.nan)),
        },
        equation=EQUATION,
        columns=dict(COLUMN_UNITS),
        flag_counts=counts,
        # a flag with details after a colon ("dropped-overtones-R<delta: 1,3") means its name's
        flag_meanings={name: PARTICLE_FLAGS.get(name.split(":")[0], "") for name in counts},
        steps=_steps(times, fit),
        model_curves=_model_curves(times, overtones, fit, particle, medium, s, fundamental),
        source=source.name,
        warnings=tuple(lines),
    )


def _finite(value: float) -> float | None:
    """A float, or None (JSON null) where it is NaN."""
    return float(value) if math.isfinite(value) else None


def _noise_lines(fit, counts: dict) -> list[str]:
    """The warning where the model misfits (the noise its residuals imply against the series'
    own, :func:`contactres.analysis.fit_particles`)."""
    lines = []
    if counts.get("model-misfit"):
        lines.append(
            f"the model does not fit: its residuals imply a noise σ̂ = {fit.noise_fit:.3g} Hz "
            f"where the shifts scatter by {fit.noise_series:.3g} Hz from step to step (assuming "
            "a slow drift between steps); no value is reported. Likely causes: the rocking "
            "choice (--rocking), the particle's radius or density, the medium (--medium)"
        )
    return lines


def _particle(s: Settings):
    """The :class:`contactres.resonators.Particle` of the settings (one-line errors)."""
    from ..resonators import Particle

    r = s.particle_radius
    if not (isinstance(r, int | float) and math.isfinite(r) and r > 0):
        raise ContactresInputError(f"particle radius {r!r} m must be a finite number > 0")
    # The same plausible range as --particle-radius, for a caller of the API (issue 30: a
    # radius in µm typed as m ran and ended in model-misfit flags).
    check_magnitude("particle_radius", r, "particle radius")
    if s.particle_mass is not None or s.moment_of_inertia is not None:
        if s.particle_density is not None:
            raise ContactresInputError(
                "give the particle's density, or its mass and moment of inertia, not both"
            )
        if s.particle_mass is None or s.moment_of_inertia is None:
            raise ContactresInputError(
                "a particle given by its mass needs its moment of inertia too (kg m² about "
                "its centre), and the reverse"
            )
        return Particle(s.particle_mass, s.moment_of_inertia, r)
    rho = s.particle_density
    if rho is None:
        raise ContactresInputError(
            "the particle needs its density (kg/m³), or its mass and moment of inertia"
        )
    if not (isinstance(rho, int | float) and math.isfinite(rho) and rho > 0):
        raise ContactresInputError(f"particle density {rho!r} kg/m³ must be a finite number > 0")
    return Particle.sphere(r, rho)


def _medium(name: str | None):
    if name is None:
        return None
    from ..resonators import medium_named

    return medium_named(name)


def _read(source: Path, s: Settings):
    """The file as an ExportTable, and the lines of what the reader left out."""
    from ..measurements.readers.exports import SHIFT_READERS, ExportWarning, read_export

    conventions = dict(s.conventions or {})
    if "fundamental" in conventions and conventions["fundamental"] is not None:
        raise ContactresInputError(
            "give the fundamental as Settings.fundamental, not among the conventions"
        )
    conventions["fundamental"] = s.fundamental
    # What the reader left out (overtones without a column, rows without a value) is said
    # with the other warnings (the CLI prints them), never only in the JSON.
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always", ExportWarning)
        table = read_export(source, s.reader, readers=SHIFT_READERS, **conventions)
    for w in seen:
        if w.category is not ExportWarning:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    left = [" ".join(str(w.message).split()) for w in seen if w.category is ExportWarning]
    return table, left


def _grid(data: pd.DataFrame, source: Path):
    """The tidy rows as arrays over (time, overtone): times (T,), overtones (N,), Δf and ΔΓ
    (T, N), NaN where a point was not measured. One-line errors for what no fit can use."""
    import numpy as np

    measured = data[np.isfinite(data["df_Hz"]) & np.isfinite(data["dgamma_Hz"])]
    if measured.empty:
        raise ContactresInputError(
            f"{source}: no point has both Δf and ΔΓ: the bandwidth shifts ΔΓ_n are needed "
            "beside Δf_n to tell the particles' contact from their mass"
        )
    overtones = np.sort(measured["overtone"].unique()).astype(int)
    if overtones.size < 2:
        raise ContactresInputError(
            f"{source}: only overtone {int(overtones[0])} has Δf and ΔΓ: the coupled resonance "
            "is read from how the shifts change over the overtones, so at least two are "
            "needed (QCM-D instruments record n = 3, 5, ..., 13)"
        )
    times = np.sort(data["time_s"].unique())
    n = data["overtone"].to_numpy()
    i = np.searchsorted(times, data["time_s"].to_numpy())
    j = np.searchsorted(overtones, n)
    # An overtone with no point of both shifts is not among the columns: its rows are dropped.
    keep = (j < overtones.size) & (overtones[np.minimum(j, overtones.size - 1)] == n)
    df = np.full((times.size, overtones.size), np.nan)
    dgamma = np.full_like(df, np.nan)
    df[i[keep], j[keep]] = data["df_Hz"].to_numpy(float)[keep]
    dgamma[i[keep], j[keep]] = data["dgamma_Hz"].to_numpy(float)[keep]
    return times, overtones, df, dgamma


def _depth_check(particle, medium, fundamental: float, overtones, source: Path) -> list[str]:
    """In a liquid the model holds for particles larger than the penetration depth δ of the
    shear wave (:func:`contactres.resonators.particle_model_validity`: a smaller particle sits
    inside the liquid's boundary layer, where a lattice-Boltzmann treatment is the tool): a
    one-line error when the model fails at every overtone measured (δ is smallest at the
    highest), a warning line naming the overtones where it fails (the fit leaves them out:
    :func:`contactres.analysis.fit_particles`)."""
    if medium is None:
        return []
    from ..resonators import particle_model_validity, penetration_depth

    reasons = [particle_model_validity(particle, fundamental * n, medium) for n in overtones]
    failed = [int(n) for n, why in zip(overtones, reasons, strict=True) if why is not None]
    if len(failed) == len(reasons):
        # one clause: the numbers at the highest overtone (the smallest δ), not the reason's
        # own sentence, which repeats "smaller than the penetration depth"
        f = fundamental * failed[-1]
        raise ContactresInputError(
            f"{source}: particles of radius R = {particle.radius * 1e9:.3g} nm are smaller than "
            f"the penetration depth of {medium.name} at every overtone measured, even at n = "
            f"{failed[-1]} (δ = {penetration_depth(medium, f) * 1e9:.3g} nm at "
            f"{f / 1e6:.3g} MHz): the hydrodynamic model needs R > δ (lattice Boltzmann is the "
            "tool there)"
        )
    if failed:
        return [
            # δ is largest at the lowest overtone: its reason names the widest gap
            f"overtone(s) {', '.join(map(str, failed))}: the particles are inside the penetration "
            f"depth of {medium.name} ({reasons[0]}); left out of the fit where enough overtones "
            "remain (flag dropped-overtones-R<delta), else nothing is fitted"
        ]
    return []


def _column(fit, name: str, size: int):
    """A field of the fit as a float array over the time steps (NaN where it has none)."""
    import numpy as np

    value = getattr(fit, name, None)
    if value is None:
        return np.full(size, np.nan)
    return np.broadcast_to(np.asarray(value, float), (size,)).copy()


def _flag_text(flags, size: int) -> list[str]:
    """The fit's flags per step as ``;``-separated text (names, or sequences of names)."""
    import numpy as np

    # one object per step (np.asarray would make a 2-D array of flag tuples of one length)
    steps = list(flags) if isinstance(flags, list | tuple) else [flags]
    items = np.empty(len(steps), dtype=object)
    for i, step in enumerate(steps):
        items[i] = step
    texts = []
    for item in np.broadcast_to(items, (size,)):
        if item is None or (isinstance(item, float) and math.isnan(item)):
            texts.append("")
        elif isinstance(item, str):
            texts.append(item)
        else:
            texts.append(";".join(str(v) for v in item))
    return texts


def _particles_table(times, fit) -> pd.DataFrame:
    """``particles.csv``: one row per step; an error is NaN where its value is (an empty cell
    is never beside a number it would seem to qualify)."""
    import numpy as np
    import pandas as pd

    size = times.size
    columns = {"time_s": times}
    for value, error, field in (
        ("kappa_N_per_m", "kappa_err_N_per_m", "kappa"),
        ("xi_kg_per_s", "xi_err_kg_per_s", "xi"),
        ("coverage_per_m2", "coverage_err_per_m2", "coverage"),
    ):
        v, e = _column(fit, field, size), _column(fit, f"{field}_err", size)
        columns[value], columns[error] = v, np.where(np.isfinite(v), e, np.nan)
    columns["f_coupled_Hz"] = _column(fit, "f_coupled", size)
    columns["flags"] = _flag_text(fit.flags, size)
    return pd.DataFrame(columns)[list(PARTICLES_CSV.names)]


def _steps(times, fit) -> dict:
    """``steps`` of particles.json: lists over the time steps (NaN where not identified;
    JSON null), with the correlations of the fitted parameters (``corr_a_b``)."""
    import numpy as np

    size = times.size
    steps = {"time_s": times}
    steps.update({name: _column(fit, field, size) for name, field in _STEP_FIELDS.items()})
    names = tuple(getattr(fit, "parameters", ()))
    correlation = getattr(fit, "correlation", None)
    for i, a in enumerate(names):
        for j, b in enumerate(names[i + 1 :], start=i + 1):
            steps[f"corr_{a}_{b}"] = np.asarray(correlation, float)[:, i, j]
    chi2, dof = _column(fit, "chi2", size), _column(fit, "dof", size)
    with np.errstate(divide="ignore", invalid="ignore"):
        steps["chi2_per_dof"] = np.where(dof > 0, chi2 / dof, np.nan)
    return steps


#: How many time steps carry a model curve (evenly spread over those fitted) and on how many
#: points of continuous n between the lowest and highest overtone.
CURVE_STEPS, CURVE_POINTS = 4, 121


def _model_curves(times, overtones, fit, particle, medium, s: Settings, fundamental) -> dict:
    """``model_curves`` of particles.json: the fitted model on a fine grid of continuous n
    (n f_F the frequency; K_L(ω)/(2nπ² Z_q) is smooth between the odd overtones, where a
    coupled resonance between two overtones peaks), at up to :data:`CURVE_STEPS` steps spread
    over the run, for the figure of Δf_n/n and ΔΓ_n/n against n. Drawn from the fitted values
    also where one is unresolved (the curve is identified when its parts are not)."""
    import numpy as np

    from ..resonators import particle_stiffness

    raw = np.asarray(getattr(fit, "raw", np.empty((0, 0))), float)
    fitted = np.flatnonzero(np.all(np.isfinite(raw), axis=1)) if raw.size else np.array([], int)
    if fitted.size == 0:
        return {"time_s": [], "overtone": [], "df_model_Hz": [], "dgamma_model_Hz": []}
    pick = fitted[np.unique(np.round(np.linspace(0, fitted.size - 1, CURVE_STEPS)).astype(int))]
    n = np.linspace(float(np.min(overtones)), float(np.max(overtones)), CURVE_POINTS)
    p = raw[pick]
    rocking = p[:, 3:4] if p.shape[1] > 3 else s.rocking
    # paper 2's Eq. 1 at continuous n (particle_shifts takes the overtones' integers only)
    k_l = particle_stiffness(
        particle, n * fundamental, p[:, 0:1], p[:, 1:2], rocking=rocking, medium=medium
    )
    z = p[:, 2:3] * k_l / (2.0 * n * np.pi**2 * s.zq)
    return {"time_s": times[pick], "overtone": n, "df_model_Hz": z.real, "dgamma_model_Hz": z.imag}


def _shifts_table(times, overtones, df, dgamma, fit):
    """``shifts.csv``: the shifts read and those of the fitted model (the fit's ``df_model``
    and ``dgamma_model``, drawn also where a parameter is unresolved: the curve is identified
    when its parts are not), per time and overtone."""
    import numpy as np
    import pandas as pd

    n_t, n_o = df.shape
    model_f = np.broadcast_to(np.asarray(fit.df_model, float), (n_t, n_o))
    model_g = np.broadcast_to(np.asarray(fit.dgamma_model, float), (n_t, n_o))
    return pd.DataFrame(
        {
            "time_s": np.repeat(times, n_o),
            "overtone": np.tile(overtones, n_t),
            "df_Hz": df.ravel(),
            "dgamma_Hz": dgamma.ravel(),
            "df_model_Hz": model_f.ravel(),
            "dgamma_model_Hz": model_g.ravel(),
        }
    )[list(PARTICLE_SHIFTS_CSV.names)]


def _flag_counts(flags: pd.Series) -> dict[str, int]:
    """Each flag's name -> the number of steps that carry it, in order of first appearance."""
    counts: dict[str, int] = {}
    for text in flags:
        for name in (t for t in str(text).split(";") if t):
            counts[name] = counts.get(name, 0) + 1
    return counts


def _constants(particle, medium, s: Settings, fundamental: float, overtones: np.ndarray) -> dict:
    """The constants of the fit, SI units in the names."""
    return {
        "fundamental_Hz": fundamental,
        "overtones": [int(n) for n in overtones],
        "zq_kg_per_m2_s": s.zq,
        "particle_radius_m": particle.radius,
        "particle_density_kg_per_m3": s.particle_density,
        "particle_mass_kg": particle.mass,
        "particle_moment_of_inertia_kg_m2": particle.moment_of_inertia,
        "rocking": s.rocking,
        "medium": None if medium is None else medium.name,
        "medium_density_kg_per_m3": None if medium is None else medium.density,
        "medium_viscosity_Pa_s": None if medium is None else medium.viscosity,
        "sigma_df_Hz": s.sigma_df,
        "sigma_dgamma_Hz": s.sigma_dgamma,
        "noise": "given" if s.sigma_df is not None else "estimated by the fit from its residuals",
    }
