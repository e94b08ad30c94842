"""The tables contactres writes besides those of ``qcm analyze``
(:mod:`contactres.measurements.schema._results`).

* :data:`SPECTRA_SWEEPS`: the sweep table ``qcm spectra`` writes (``--out``), one row per
  measured spectrum: the sweep table's columns with the errors and the spectrum's own;
* :data:`SPECTRA_FITS`: ``fits.csv`` of ``qcm spectra --fits``, one row per spectrum;
* :data:`STIFFNESS_CSV`: ``stiffness.csv`` of ``qcm stiffness``, one row per time and overtone;
* :data:`AFM_INVERT_RESULTS`, :data:`RUM_INVERT_RESULTS`: the columns ``afm invert`` and
  ``rum invert`` append to the input's;
* :data:`RADIATION_RESULTS`: ``radiation.csv`` of ``qcm analyze --radiation``, one row per
  (configuration, medium, normal force).

The code that writes each table is checked against these names by the tests
(``tests/report/test_dictionary.py``, ``tests/analysis``).
"""

from __future__ import annotations

from dataclasses import replace

from ._columns import Column, TableSchema
from ._inputs import SPECTRA_TABLE, SWEEP_TABLE

__all__ = [
    "AFM_INVERT_RESULTS",
    "CURVE_RESULTS",
    "JKR_CURVE_RESULTS",
    "RADIATION_RESULTS",
    "RUM_INVERT_RESULTS",
    "SPECTRA_FITS",
    "SPECTRA_SWEEPS",
    "STIFFNESS_CSV",
]


def _written(schema: TableSchema, name: str, meaning: str | None = None) -> Column:
    """Column ``name`` of the input table ``schema`` as an output column: its unit, level and
    meaning (or ``meaning``), without the rules, the default or the "required" of a reader."""
    c = schema.column(name)
    return replace(c, meaning=meaning or c.meaning, required=False, rules=(), default=None)


#: The sweep table of ``contactres qcm spectra`` (``--out``; ``qcm-spectra/sweeps.csv`` of
#: ``contactres demo``): what :func:`contactres.measurements._shifts.sweeps_from_spectra`
#: returns, one row per measured spectrum, in its order. ``qcm analyze`` reads it as a sweep table
#: (:data:`~.inputs.SWEEP_TABLE`), whose columns it repeats, and ignores the others.
SPECTRA_SWEEPS = TableSchema(
    "sweeps.csv of qcm spectra",
    "the sweep table from the spectra, one row per measured spectrum (references left out)",
    (
        _written(SWEEP_TABLE, "sweep"),
        _written(
            SWEEP_TABLE,
            "amplitude_m",
            "oscillation amplitude u0 = 4 d26 Q U/(nπ)², "
            "Q = f_r/(2Γ) (or the calibration u0/U times U)",
        ),
        _written(
            SWEEP_TABLE,
            "df_Hz",
            "frequency shift Δf = f_r − (mean f_r of the references of its overtone)",
        ),
        _written(
            SWEEP_TABLE,
            "dgamma_Hz",
            "half-bandwidth shift ΔΓ = Γ − (mean Γ of the references of its overtone)",
        ),
        Column(
            "df_err_Hz",
            "Hz",
            "standard error of Δf: the fit's and the references' mean's, in quadrature",
        ),
        Column(
            "dgamma_err_Hz",
            "Hz",
            "standard error of ΔΓ: the fit's and the references' mean's, in quadrature",
        ),
        _written(SWEEP_TABLE, "normal_force_N"),
        _written(SWEEP_TABLE, "experiment"),
        _written(SWEEP_TABLE, "configuration"),
        _written(SWEEP_TABLE, "medium"),
        _written(SWEEP_TABLE, "ramp", "ramp number of the sweep (absent: no spectrum gave one)"),
        _written(SWEEP_TABLE, "overtone"),
        _written(SWEEP_TABLE, "time_s", "time of the spectrum (absent: no spectrum gave one)"),
        _written(SPECTRA_TABLE, "spectrum"),
        Column("f_r_Hz", "Hz", "fitted resonance frequency f_r of the spectrum"),
        Column("gamma_Hz", "Hz", "fitted half width at half height Γ of the spectrum"),
        Column(
            "quality",
            "-",
            "quality factor Q = f_r/(2Γ) (in the sweep table of `contactres demo` only)",
        ),
        _written(SPECTRA_TABLE, "drive_voltage_V"),
        *(
            _written(
                SWEEP_TABLE,
                name,
                f"{SWEEP_TABLE.column(name).meaning} (where the spectra carried it)",
            )
            for name in ("fundamental_Hz", "area_m2", "n_contacts", "sphere_radius_m", "poisson")
        ),
    ),
)

#: ``fits.csv`` of ``contactres qcm spectra --fits``: the columns of
#: :func:`contactres.measurements.fit_resonances`, in its order.
SPECTRA_FITS = TableSchema(
    "fits.csv",
    "the resonance fit of every spectrum, one row per spectrum",
    (
        Column("spectrum", "text", "the spectrum id (the spectra table's `spectrum` column)"),
        Column("f_r_Hz", "Hz", "resonance frequency f_r (NaN where a flag says so)"),
        Column("f_r_err_Hz", "Hz", "standard error of f_r"),
        Column("gamma_Hz", "Hz", "half width at half height Γ of the conductance G"),
        Column("gamma_err_Hz", "Hz", "standard error of Γ"),
        Column("g_max_S", "S", "conductance at the peak G_max"),
        Column("phase_rad", "rad", "phase φ of the resonance (NaN: G alone, not fitted)"),
        Column("reduced_chi2", "-", "reduced χ² of the fit (against the given noise, if any)"),
        Column("n_points", "-", "points of the spectrum"),
        Column("converged", "-", "true: a fit ran and its remaining step is negligible"),
        Column("flags", "text", "';'-separated names of the fit flags (empty: none)"),
    ),
)

#: ``stiffness.csv`` of ``contactres qcm stiffness`` (units as in its ``stiffness.json``).
STIFFNESS_CSV = TableSchema(
    "stiffness.csv",
    "κ + iωξ of one contact against time, one row per time and overtone",
    (
        Column("time_s", "s", "time of the export's row"),
        Column("overtone", "-", "overtone order n (odd)"),
        Column("df_Hz", "Hz", "frequency shift Δf (not divided by n)"),
        Column("dgamma_Hz", "Hz", "shift of the half-bandwidth ΔΓ"),
        Column("kappa_N_per_m", "N/m", "contact stiffness κ of one contact (paper 2, Eq. 2)"),
        Column("omega_xi_N_per_m", "N/m", "ωξ of one contact (damping times angular frequency)"),
    ),
)

#: The film columns ``afm invert`` and ``rum invert`` add with ``--coating`` (the modulus of a
#: film on a known substrate: :func:`contactres.analysis.film_modulus_from_contact_stiffness`).
_FILM_COLUMNS = (
    Column("coating", "text", "the film on the substrate, e.g. `PMMA 250 nm` (with `--coating`)"),
    Column(
        "M_film_Pa",
        "Pa",
        "indentation modulus of the film from k* on the coated substrate (with `--coating`; "
        "empty where film_verdict is too-thin, below-range, above-range or beyond-hertz)",
    ),
    Column(
        "film_contact_radius_m",
        "m",
        "contact radius of the coated contact at M_film (with `--coating`)",
    ),
    Column(
        "film_weight",
        "-",
        "the film's share of the sensitivity of k*, (∂ln k*/∂ln M_film)/((2/3) "
        "E*_film/M_film): 0 substrate only, 1 film only (with `--coating`)",
    ),
    Column(
        "film_verdict",
        "text",
        "film (resolved), too-thick (= the homogeneous inversion of the film within 1 %), "
        "too-thin (film_weight below the threshold: not identified), below-range or "
        "above-range (outside the search range), beyond-hertz (contact radius above half the "
        "tip radius: no modulus); empty: no k*, tip radius or load (with `--coating`)",
    ),
)

#: The columns ``contactres afm invert`` appends to the input's (which it copies).
AFM_INVERT_RESULTS = TableSchema(
    "afm invert output",
    "the input columns, then these",
    (
        Column("kappa", "-", "normalised contact stiffness κ = Re k*/k_c"),
        Column("k_star_N_per_m", "N/m", "contact stiffness k* = κ k_c (NaN without k_c)"),
        Column("tip_position_used", "-", "tip position r = L1/L (given, or the chosen crossing)"),
        Column("sigma_N_s_per_m", "N s/m", "contact damping σ (NaN without Q or k_c)"),
        Column("mode_spread", "-", "(max − min)/κ of the per-mode κ (inf: a mode contradicts r)"),
        Column(
            "tip_position_other",
            "-",
            "r solved from two modes: the crossing in [0.5, 1] not taken (several-crossings)",
        ),
        Column("kappa_other", "-", "κ at tip_position_other (the alternative's stiffness/k_c)"),
        Column("E_star_Pa", "Pa", "reduced modulus E* (Hertz or reference method)"),
        Column("M_sample_Pa", "Pa", "indentation modulus of the sample (tip compliance removed)"),
        Column("contact_radius_m", "m", "contact radius a (Hertz rows)"),
        Column(
            "modulus_method",
            "text",
            '"hertz", "reference (given m …)" or "reference (fitted m …)", with " + dynamic" '
            "where the dynamic correction was applied; empty: no modulus",
        ),
        Column("k_static_N_per_m", "N/m", "static stiffness k*/Re DCSF (with `--crystal` only)"),
        Column("k_a", "-", "k_l a of the first corrected mode (with `--crystal` only)"),
        Column("dcsf_real", "-", "Re DCSF of that mode (with `--crystal` only)"),
        Column("dcsf_imag", "-", "Im DCSF of that mode (with `--crystal` only)"),
        Column("flags", "text", "';'-separated resonance and modulus flags (empty: none)"),
        Column("normalisation", "text", "the `--normalisation` used: global or modewise"),
        *_FILM_COLUMNS,
    ),
)

#: The columns ``contactres rum invert`` appends to the input's (which it copies).
RUM_INVERT_RESULTS = TableSchema(
    "rum invert output",
    "the input columns, then these",
    (
        Column("rum_model", "text", "lumped (K_eff_N_per_m given) or rod (mass_kg given)"),
        Column("k_star_N_per_m", "N/m", "contact stiffness k* from the contact resonance"),
        *_FILM_COLUMNS,
    ),
)

#: ``radiation.csv``: the radiation loss of each load against the measured loss.
RADIATION_RESULTS = TableSchema(
    "radiation.csv",
    "one row per (configuration, medium, normal force): radiation loss of the contact vs measured",
    tuple(
        Column(name, unit, meaning, level="sweep")
        for name, unit, meaning in (
            ("configuration", "text", "configuration"),
            ("medium", "text", "medium"),
            ("normal_force_N", "N", "normal force per contact"),
            ("sphere_material", "text", "material of the sphere (--sphere-material)"),
            ("plate_material", "text", "material of the plate (--plate-material)"),
            ("frequency_Hz", "Hz", "frequency of the overtone, fundamental_Hz x overtone"),
            (
                "contact_radius_m",
                "m",
                "contact radius a from the group's JKR fit (paper 2, Eq. 9) at this load",
            ),
            ("stiffness_static_N_per_m", "N/m", "tangential stiffness K₀ of the contact at f = 0"),
            ("stiffness_real_N_per_m", "N/m", "Re K at the frequency (sphere and plate in series)"),
            ("stiffness_imag_N_per_m", "N/m", "Im K at the frequency: waves radiated"),
            ("tan_delta_rad", "-", "radiation loss tangent Im K/Re K"),
            ("tan_delta_measured", "-", "measured loss tangent ΔΓ0/Δf0 (loss_tangent_mean)"),
            ("tan_delta_measured_sem", "-", "standard error of tan_delta_measured"),
            (
                "radiation_share",
                "-",
                "tan_delta_rad/tan_delta_measured: the fraction of ΔΓ0 the radiation explains",
            ),
            ("dynamic_softening", "-", "Re K/K₀ - 1: change of the elastic part with frequency"),
            ("E_Pa", "Pa", "E of the group's JKR fit (κ taken as static)"),
            (
                "E_static_corrected_Pa",
                "Pa",
                "E refitted with κ/(Re K/K₀) per point (the group's, repeated per load)",
            ),
            ("E_relative_change", "-", "E_static_corrected_Pa/E_Pa - 1"),
            (
                "note",
                "text",
                "why the row has no radiation values, or why they exceed the measured loss "
                "(empty: computed and below the measured)",
            ),
        )
    ),
)


#: ``curves.csv`` of ``qcm analyze``: the model chosen for each sweep with one, evaluated on a
#: grid of amplitudes (the grid the HTML report draws), so that the fitted curves can be plotted
#: from the file without contactres.
CURVE_RESULTS = TableSchema(
    "curves.csv",
    "the model chosen for each sweep with one, on 30 amplitudes from 0 to the sweep's largest",
    tuple(
        Column(name, unit, meaning, level="point")
        for name, unit, meaning in (
            ("sweep", "text", "the sweep (as in sweeps.csv)"),
            ("amplitude_m", "m", "oscillation amplitude u0 of the grid"),
            ("df_model_Hz", "Hz", "Δf of the chosen model at u0 (empty: no usable fit)"),
            ("dgamma_model_Hz", "Hz", "ΔΓ of the chosen model at u0 (empty: no usable fit)"),
        )
    ),
)

#: ``jkr_curves.csv`` of ``qcm analyze``: the fitted JKR + Mindlin κ(F_N) of every
#: (configuration, medium) with an E (Fig. 5's lines).
JKR_CURVE_RESULTS = TableSchema(
    "jkr_curves.csv",
    "the fitted JKR + Mindlin curve κ(F_N) of every configuration and medium with an E",
    tuple(
        Column(name, unit, meaning, level="sweep")
        for name, unit, meaning in (
            ("configuration", "text", "configuration"),
            ("medium", "text", "medium"),
            ("normal_force_N", "N", "normal force per contact, 0 to 1.05 times the largest load"),
            (
                "kappa_N_per_m",
                "N/m",
                "κ of the fitted E and γ (paper 2, Eqs. 6-10; coated plate: the coated law)",
            ),
            (
                "kappa_lo_N_per_m",
                "N/m",
                "lower end of κ's 95 % pointwise band: linear propagation of the covariance of "
                "Table 1's errors of E and γ (E_err_Pa, gamma_err_J_m2 with E_gamma_corr: the "
                "bootstrap's correlation where a bootstrap gives the errors, else the fit's), "
                "t95 wide (empty: no covariance)",
            ),
            ("kappa_hi_N_per_m", "N/m", "upper end of κ's 95 % pointwise band (as kappa_lo)"),
            ("df0_model_Hz", "Hz", "Δf0 = P κ (paper 2, Eq. 1)"),
            ("df0_model_lo_Hz", "Hz", "lower end of Δf0's 95 % band: P times κ's band"),
            ("df0_model_hi_Hz", "Hz", "upper end of Δf0's 95 % band: P times κ's band"),
        )
    ),
)
