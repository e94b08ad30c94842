"""The tables of ``contactres qcm particles`` (issue 28): the tidy table of QCM-D shifts it reads,
and the two tables it writes.

* :data:`QCMD_SHIFTS_TABLE`: the tidy input, one row per time and overtone (``time_s, overtone,
  df_Hz, dgamma_Hz``), read by the ``tidy`` export reader
  (:data:`contactres.measurements.readers.exports.TIDY_READER`) with these rules;
* :data:`PARTICLES_CSV`: ``particles.csv``, one row per time step: the contact stiffness κ, its
  damping ξ, the coverage and the coupled-resonance frequency with their standard errors (a
  value the data do not identify is left empty and named in ``flags``);
* :data:`PARTICLE_SHIFTS_CSV`: ``shifts.csv``, one row per time and overtone: the shifts read and
  those of the fitted model (what the figures draw).

Conventions of every shift (as :data:`contactres.measurements.readers.exports.COLUMNS`): Δf_n is
not divided by n, Γ is the half bandwidth at half height, both against the bare sensor in the
same medium.
"""

from __future__ import annotations

import numpy as np

from ._columns import Column, TableSchema, rule
from ._inputs import A_NUMBER, FINITE, LARGEST_COUNT

__all__ = ["PARTICLES_CSV", "PARTICLE_SHIFTS_CSV", "QCMD_SHIFTS_TABLE"]


def _odd(v: np.ndarray) -> np.ndarray:
    return (np.abs(v) <= LARGEST_COUNT) & (v >= 1) & (v % 2 == 1)


#: The tidy table of QCM-D shifts (``contactres qcm particles DATA`` where DATA is no instrument
#: export): one row per time and overtone. A blank ``dgamma_Hz`` cell is a bandwidth not
#: measured at that point (left out of the fit); a table without one is refused.
QCMD_SHIFTS_TABLE = TableSchema(
    "QCM-D shift table",
    "one row per time and overtone: the shifts against the bare sensor in the same medium "
    "(CSV: comma, semicolon or tab separated)",
    (
        Column("time_s", "s", "time of the point (any origin)", required=True, rules=(FINITE,)),
        Column(
            "overtone",
            "-",
            "overtone order n",
            required=True,
            rules=(
                A_NUMBER,
                rule(
                    "odd",
                    _odd,
                    "odd integer >= 1",
                    " is not allowed; a thickness-shear resonator has odd overtones only "
                    "(1, 3, 5, ...)",
                ),
            ),
        ),
        Column(
            "df_Hz",
            "Hz",
            "frequency shift Δf_n (not divided by n)",
            required=True,
            rules=(A_NUMBER,),
        ),
        Column(
            "dgamma_Hz",
            "Hz",
            "shift of the half bandwidth ΔΓ_n (half width at half height; Γ = D f_n/2); blank: "
            "not measured at that point",
            required=True,
            rules=(A_NUMBER,),
        ),
    ),
)

_ERROR = "standard error of {} (empty where the value is)"

#: ``particles.csv`` of ``contactres qcm particles``: one row per time step (issue 28's
#: contract, names exact).
PARTICLES_CSV = TableSchema(
    "particles.csv",
    "the attached particles against time, one row per time step (empty cell: not identified "
    "by the data, named in flags)",
    (
        Column("time_s", "s", "time of the step"),
        Column("kappa_N_per_m", "N/m", "tangential contact stiffness κ of one particle"),
        Column("kappa_err_N_per_m", "N/m", _ERROR.format("κ")),
        Column("xi_kg_per_s", "kg/s", "contact damping ξ of one particle (force/velocity)"),
        Column("xi_err_kg_per_s", "kg/s", _ERROR.format("ξ")),
        Column("coverage_per_m2", "1/m^2", "number of attached particles per area N/A"),
        Column("coverage_err_per_m2", "1/m^2", _ERROR.format("the coverage")),
        Column(
            "f_coupled_Hz",
            "Hz",
            "frequency of the particle's resonance on its contact (the coupled resonance)",
        ),
        Column(
            "flags",
            "text",
            "';'-separated names (contactres.analysis.PARTICLE_FLAGS): what the step's data do "
            "not identify and why, and the fit's own notes (at a bound, not converged); empty: "
            "all identified",
        ),
    ),
)

#: ``shifts.csv`` of ``contactres qcm particles``: the shifts read and the fitted model's, one
#: row per time and overtone (the figures draw them).
PARTICLE_SHIFTS_CSV = TableSchema(
    "shifts.csv",
    "the shifts read and the fitted model's, one row per time and overtone",
    (
        Column("time_s", "s", "time of the step"),
        Column("overtone", "-", "overtone order n"),
        Column("df_Hz", "Hz", "frequency shift Δf_n read (not divided by n)"),
        Column("dgamma_Hz", "Hz", "half-bandwidth shift ΔΓ_n read (empty: not measured)"),
        Column(
            "df_model_Hz",
            "Hz",
            "Δf_n of the fitted model (also where a parameter is not identified: the curve is "
            "when its parts are not)",
        ),
        Column("dgamma_model_Hz", "Hz", "ΔΓ_n of the fitted model"),
    ),
)
