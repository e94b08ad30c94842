"""The tables ``qcm analyze`` writes: the one source of their names, units and meanings.

* :data:`SWEEP_RESULTS`: ``sweeps.csv``, one row per sweep;
* :data:`LOAD_RESULTS`: ``loads.csv``, one row per (configuration, medium, normal force);
* :data:`GROUP_RESULTS`: the groups of ``summary.json``, one per (configuration, medium): the
  JKR + Mindlin fit (Table 1 of paper 2).

Conventions (recorded in every output, :data:`CONVENTIONS`): Δf is the frequency shift, not
Δf/n; ΔΓ the shift of the half-bandwidth at half height, not the dissipation D = 2Γ/f;
amplitudes in m; forces per contact in N. Paper 2: J. Vlachová, R. König, D. Johannsmann,
"Stiffness of sphere-plate contacts at MHz frequencies: dependence on normal load, oscillation
amplitude, and ambient medium", Beilstein J. Nanotechnol. 6, 845-856 (2015),
doi:10.3762/bjnano.6.87.
"""

from __future__ import annotations

from ._columns import Column, TableSchema

__all__ = [
    "COATING_CONVENTIONS",
    "CONVENTIONS",
    "GROUP_RESULTS",
    "LOAD_QUANTITIES",
    "LOAD_RESULTS",
    "SWEEP_RESULTS",
]

CONVENTIONS = {
    "df": "frequency shift Δf in Hz (not Δf/n)",
    "dgamma": "shift of the half-bandwidth at half height ΔΓ in Hz (dissipation D = 2Γ/f)",
    "amplitude": "oscillation amplitude u0 in m",
    "normal_force": "normal force per contact in N",
    "gamma": "paper 2's energy of adhesion γ in J/m² (work of adhesion w = 2γ)",
    "E": "Young's modulus of both bodies (E1 = E2), Pa, with ν fixed (settings/poisson)",
    "errors": "_err: standard error of a fit; _sd: standard deviation over experiments",
}

#: Added to :data:`CONVENTIONS` in summary.json when the plate is coated (``--coating``).
COATING_CONVENTIONS = {
    "E": "Young's modulus of the sphere and of the plate's substrate under the coating (the "
    "film's own constants fixed), Pa, with ν fixed (settings/poisson)",
    "coating": "groups/coating: the film(s), the uncoated (paper 2) fit, and per load the "
    "contact radius, κ on the coated and on the bare plate (same E, γ, load) and film_share = "
    "1 - κ/κ_bare, the share of the tangential contact stiffness the film takes",
}

# --------------------------------------------------------------------------------------------
# Outputs

_SWEEP_RESULT_COLUMNS = (
    Column("sweep", "text", "id of the sweep", level="sweep"),
    Column("experiment", "text", "experiment of the sweep", level="sweep"),
    Column("configuration", "text", "configuration of the sweep", level="sweep"),
    Column("medium", "text", "medium of the sweep", level="sweep"),
    Column("normal_force_N", "N", "normal force per contact", level="sweep"),
    Column("ramp", "-", "ramp number (0: the table had no ramp column)", level="sweep"),
    Column("used", "-", "true if the sweep enters the per-load statistics", level="sweep"),
    Column(
        "model",
        "text",
        "amplitude class: elastic, cattaneo-mindlin, savkoor or plateau (see decided_by)",
        level="sweep",
    ),
    Column(
        "plateau_amplitude_m",
        "m",
        "critical displacement d_c of a plateau sweep (exact plateau loop, else the hinge)",
        level="sweep",
    ),
    Column("df0_Hz", "Hz", "low-amplitude limit Δf0", level="sweep"),
    Column("df0_err_Hz", "Hz", "standard error of Δf0", level="sweep"),
    Column(
        "df_slope_Hz_per_m",
        "Hz/m",
        "slope of Δf(u0) (straight line; for a plateau the hinge slope, descriptive only)",
        level="sweep",
    ),
    Column("dgamma0_Hz", "Hz", "low-amplitude limit ΔΓ0", level="sweep"),
    Column(
        "dgamma_slope_Hz_per_m",
        "Hz/m",
        "slope of ΔΓ(u0) (straight line; for a plateau the hinge slope, descriptive only)",
        level="sweep",
    ),
    Column("mu_df", "-", "μ from the Δf slope (paper 2, Eq. 12; CM sweeps only)", level="sweep"),
    Column(
        "mu_dgamma", "-", "μ from the ΔΓ slope (paper 2, Eq. 12; CM sweeps only)", level="sweep"
    ),
    Column(
        "mu_fit",
        "-",
        "μ from this sweep's fit of the exact loop (Cattaneo-Mindlin, or behind a plateau)",
        level="sweep",
    ),
    Column("flags", "text", "';'-separated flags (README: flags)", level="sweep"),
    Column("n_points", "-", "points in the sweep", level="sweep"),
    Column(
        "direction", "text", "up, down or mixed: order of the amplitudes in the file", level="sweep"
    ),
    Column("dgamma0_err_Hz", "Hz", "standard error of ΔΓ0", level="sweep"),
    Column("df_slope_err_Hz_per_m", "Hz/m", "standard error of the Δf slope", level="sweep"),
    Column("dgamma_slope_err_Hz_per_m", "Hz/m", "standard error of the ΔΓ slope", level="sweep"),
    Column(
        "df_curvature_Hz_per_m2",
        "Hz/m^2",
        "half the second derivative of Δf(u0) (parabola, paper 2, Eq. 15)",
        level="sweep",
    ),
    Column(
        "dgamma_curvature_Hz_per_m2",
        "Hz/m^2",
        "half the second derivative of ΔΓ(u0) (parabola, paper 2, Eq. 15)",
        level="sweep",
    ),
    Column("kappa_N_per_m", "N/m", "contact stiffness κ = Δf0/P (paper 2, Eq. 2)", level="sweep"),
    Column(
        "omega_xi_N_per_m", "N/m", "dissipative part ωξ = ΔΓ0/P (paper 2, Eq. 2)", level="sweep"
    ),
    Column("loss_tangent", "-", "ΔΓ0/Δf0", level="sweep"),
    Column("mu_df_err", "-", "standard error of mu_df", level="sweep"),
    Column("mu_dgamma_err", "-", "standard error of mu_dgamma", level="sweep"),
    Column("mu_fit_err", "-", "standard error of mu_fit", level="sweep"),
    Column("plateau_amplitude_err_m", "m", "standard error of plateau_amplitude_m", level="sweep"),
    Column(
        "runner_up",
        "text",
        "the class with the next-best BIC (of the block where decided_by is block); empty where "
        "no other class has a BIC (e.g. a sweep of one amplitude: one point or copies of one; "
        "one of two points without the exact loops; with them, a load whose Δf has the wrong "
        "sign for every loop)",
        level="sweep",
    ),
    Column(
        "delta_bic",
        "-",
        "BIC of the runner-up minus that of the chosen class: the evidence for the choice; empty "
        "where there is no runner-up (in analyze()'s table inf where the chosen class has a BIC "
        "and no other has one, NaN where no class has one: a sweep of one point, whose mean "
        "leaves no residual for a BIC)",
        level="sweep",
    ),
    Column(
        "decided_by",
        "text",
        "block: the class was chosen for the used ramps of the load jointly; sweep: alone",
        level="sweep",
    ),
    Column("model_sweep", "text", "the class this sweep alone would get", level="sweep"),
    Column(
        "mu_block",
        "-",
        "μ of the joint fits of the load block (ramps sharing one contact), averaged over the "
        "Cattaneo-Mindlin and plateau loops with their BIC weights; used in loads.csv",
        level="sweep",
    ),
    Column(
        "mu_block_err",
        "-",
        "standard error of mu_block, including the spread between the two loops",
        level="sweep",
    ),
    Column(
        "sliding_force_N",
        "N",
        "Savkoor sweeps: sliding force πa²τ0 from the exact Savkoor loop (paper 2, Eqs. 13-14)",
        level="sweep",
    ),
    Column("sliding_force_err_N", "N", "standard error of sliding_force_N", level="sweep"),
    Column(
        "tau0_Pa",
        "Pa",
        "Savkoor sweeps: sliding traction τ0 = F_s/(πa²), a = κ/(2G*) with the group's E",
        level="sweep",
    ),
    Column("tau0_err_Pa", "Pa", "standard error of tau0_Pa (from F_s, κ and E)", level="sweep"),
)

SWEEP_RESULTS = TableSchema(
    "sweeps.csv", "one row per sweep: limits, slopes, class, friction, flags", _SWEEP_RESULT_COLUMNS
)

#: Quantities averaged per load: name, unit, meaning.
LOAD_QUANTITIES: tuple[tuple[str, str, str], ...] = (
    ("df0_Hz", "Hz", "low-amplitude Δf0"),
    ("dgamma0_Hz", "Hz", "low-amplitude ΔΓ0"),
    ("kappa_N_per_m", "N/m", "contact stiffness κ"),
    ("omega_xi_N_per_m", "N/m", "dissipative part ωξ"),
    ("loss_tangent", "-", "loss tangent ΔΓ0/Δf0"),
    ("mu_df", "-", "μ from the Δf slope"),
    ("mu_dgamma", "-", "μ from the ΔΓ slope"),
    ("mu_fit", "-", "μ from the exact-loop fit (of the load block where its ramps share one)"),
)

#: The Student-t factor of an error from a few repeats (loads.csv and the groups).
_T95 = Column(
    "t95",
    "-",
    "Student-t factor of the two-sided 95 % interval: value ± t95 x error",
    level="sweep",
)

LOAD_RESULTS = TableSchema(
    "loads.csv",
    "one row per (configuration, medium, normal force): statistics over experiments",
    (
        Column("configuration", "text", "configuration", level="sweep"),
        Column("medium", "text", "medium", level="sweep"),
        Column("normal_force_N", "N", "normal force per contact", level="sweep"),
        Column("n_experiments", "-", "experiments with used sweeps at this load", level="sweep"),
        Column("n_sweeps", "-", "used sweeps at this load", level="sweep"),
        Column(
            "errors_from",
            "text",
            "what _sem and _median_err come from: experiments, or sweeps of one experiment",
            level="sweep",
        ),
        Column(
            "dof",
            "-",
            "degrees of freedom of the _sem errors: experiments - 1 (sweeps - 1 for one "
            "experiment)",
            level="sweep",
        ),
        _T95,
        *(
            Column(f"{name}_{stat}", unit, f"{text}: {what}", level="sweep")
            for name, unit, text in LOAD_QUANTITIES
            for stat, what in (
                ("mean", "mean over experiments (each the mean of its used sweeps)"),
                ("sd", "standard deviation over experiments (ddof = 1)"),
                ("sem", "standard error of the mean (see errors_from)"),
                ("median", "median over experiments (over sweeps for one experiment)"),
                ("median_err", "1.2533 x the standard error: error of the median"),
            )
        ),
        # Last: the columns before it kept their places when it was added (issue 30).
        Column(
            "flags",
            "text",
            "mu-withheld: the μ columns are empty because the group's E and γ were withheld "
            "for an input μ scales with too (area_m2, n_contacts, normal_force_N)",
            level="sweep",
        ),
    ),
)

GROUP_RESULTS = TableSchema(
    "summary.json groups",
    "one group per (configuration, medium): JKR + Mindlin fit of κ(F_N) (Table 1 of paper 2)",
    (
        Column("configuration", "text", "configuration", level="sweep"),
        Column("medium", "text", "medium", level="sweep"),
        Column("E_Pa", "Pa", "Young's modulus E (E1 = E2, ν fixed)", level="sweep"),
        Column("E_err_Pa", "Pa", "standard error of E (see error_method)", level="sweep"),
        Column("gamma_J_m2", "J/m^2", "energy of adhesion γ (work of adhesion 2γ)", level="sweep"),
        Column("gamma_err_J_m2", "J/m^2", "standard error of γ (see error_method)", level="sweep"),
        Column("n_experiments", "-", "experiments in the group", level="sweep"),
        Column("n_sweeps_used", "-", "used sweeps in the group", level="sweep"),
        Column("models", "-", "number of used sweeps of each amplitude class", level="sweep"),
        Column(
            "error_method",
            "text",
            "how the errors of E and γ were found: bootstrap over the experiments (3 or more), "
            "the fits of 2 experiments, repeated sweeps of 1 experiment, or the fit's Jacobian",
            level="sweep",
        ),
        Column(
            "err_dof",
            "-",
            "degrees of freedom of the errors (experiments - 1; sweeps - loads for one "
            "experiment; points - 2 for the Jacobian)",
            level="sweep",
        ),
        _T95,
        Column(
            "checks",
            "text",
            "why E and γ are withheld: too-few-loads, fit-at-bound, E-out-of-range, "
            "gamma-out-of-range (empty: none)",
            level="sweep",
        ),
        Column(
            "note",
            "text",
            "why E and γ are withheld, or which points the fit left out (κ <= 0, or no κ), in "
            "words, with the input to check",
        ),
        Column("E_fit_err_Pa", "Pa", "standard error of E from the fit's Jacobian alone"),
        Column("gamma_fit_err_J_m2", "J/m^2", "standard error of γ from the fit's Jacobian alone"),
        Column(
            "E_gamma_fit_corr",
            "-",
            "correlation of E and γ in the fit's covariance (with E_fit_err_Pa and "
            "gamma_fit_err_J_m2 the whole covariance of the fit)",
        ),
        Column(
            "E_gamma_corr",
            "-",
            "correlation of E and γ that goes with E_err_Pa and gamma_err_J_m2: over the "
            "bootstrap's resamples where error_method is a bootstrap, else the fit's "
            "(E_gamma_fit_corr); the band of jkr_curves.csv propagates the three",
        ),
        Column("E_bootstrap_sd_Pa", "Pa", "sd of E over bootstrap resamples of the experiments"),
        Column(
            "gamma_bootstrap_sd_J_m2",
            "J/m^2",
            "sd of γ over bootstrap resamples of the experiments",
        ),
        Column("sphere_radius_m", "m", "sphere radius R"),
        Column("poisson", "-", "Poisson ratio ν (fixed)"),
        Column("n_points_fitted", "-", "(experiment, load) points in the fit"),
        Column("fit_rms_N_per_m", "N/m", "rms residual of the fit"),
        Column("P_Hz_per_N_per_m", "Hz/(N/m)", "sensitivity P of paper 2, Eq. 1"),
        Column("rejected_fit", "-", "E_Pa and gamma_J_m2 of a fit withheld by a check"),
        Column(
            "running_in",
            "-",
            "ratios ramp 1 / later ramps of κ, ωξ and μ_fit (mean and standard error over loads)",
        ),
        Column(
            "drift_removed",
            "-",
            "(experiment, normal force, drift of Δf and ΔΓ in Hz/s) of the loads corrected for "
            "a drift linear in time (--remove-drift)",
        ),
        Column(
            "drifting_loads",
            "-",
            "(experiment, normal force) of the loads left out because their ramps drift",
        ),
        Column(
            "coating",
            "-",
            "with --coating: the film(s), the uncoated fit, the table's ranges and per load the "
            "contact radius, κ coated and bare, and film_share = 1 - κ/κ_bare",
        ),
    ),
)
